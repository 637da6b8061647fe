// Engine-side area-light shading with linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016) and the
// micro-shadowing hook: the bilinear table fetch a shader does, GGX specular and Lambert diffuse for sphere
// and rectangle lights, and the combination with a micro-shadowing factor for the light (docs/ltc.md):
//   L_o,spec = L · (F0 · magnitude + (1 − F0) · fresnel) · ∫_light D_ltc · ms_area
//   L_o,diff = L · ρ · ∫_light (n·l)/π dl · ms_area_diffuse
// ms_area is the light-averaged micro-shadowing M_area (docs/area-lights.md §1). Its fast form here is the
// cone-clipped LTC (LtcLightCone, below: the light's polygon clipped by the visibility cone); the point term
// at ltc_representative_direction (ltc_ms_at_representative) is the cheap stand-in, measured far worse
// (docs/area-lights.md §5). Header-only; no I/O.
#pragma once

#include <microshadow/bsdf/ltc.h>
#include <microshadow/math/quadrature.h>

namespace msh::bsdf {

// The table's texture coordinates (the layout of Heitz et al.'s tables): x = perceptual roughness r ∈ [0, 1],
// y = sqrt(1 − cos θ_v) ∈ [0, 1]; texel i of n holds i/(n − 1) (GPU: uv · (n − 1)/n + 0.5/n).
template <class T>
Vec2<T> ltc_table_coords(T roughness, T cos_theta_v) {
  return {saturate(roughness), std::sqrt(T(1) - saturate(cos_theta_v))};
}

// Bilinear fetch, as a shader's linear filter does, of the two tables: mat = n×n RGBA (a, b, c, d of M⁻¹),
// amp = n×n RG (magnitude, fresnel), texel (i, j) at [(j·n + i)·channels], i along roughness. n ≥ 2.
template <class T>
LtcCoeffs<T> ltc_fetch(const float* mat, const float* amp, int n, T roughness, T cos_theta_v) {
  const Vec2<T> uv = ltc_table_coords(roughness, cos_theta_v);
  const T x = uv.x * T(n - 1), y = uv.y * T(n - 1);
  const int i0 = std::min(int(x), n - 2), j0 = std::min(int(y), n - 2);
  const T fx = x - T(i0), fy = y - T(j0);
  auto lerp4 = [&](const float* t, int ch, int c) {
    auto at = [&](int i, int j) {
      return T(t[(size_t(j) * size_t(n) + size_t(i)) * size_t(ch) + size_t(c)]);
    };
    const T a = at(i0, j0) + fx * (at(i0 + 1, j0) - at(i0, j0));
    const T b = at(i0, j0 + 1) + fx * (at(i0 + 1, j0 + 1) - at(i0, j0 + 1));
    return a + fy * (b - a);
  };
  LtcCoeffs<T> k;
  k.a = lerp4(mat, 4, 0), k.b = lerp4(mat, 4, 1), k.c = lerp4(mat, 4, 2), k.d = lerp4(mat, 4, 3);
  k.magnitude = lerp4(amp, 2, 0), k.fresnel = lerp4(amp, 2, 1);
  return k;
}

// One light shaded with one LTC.
template <class T>
struct LtcLightResult {
  T integral = T(0);           // ∫_light D (the normalized lobe's share of the light), in [0, 1]
  T magnitude = T(1);          // ∫ f (n·l) dl, F = 1 (1 for the diffuse LTC)
  T fresnel = T(0);            // ∫ f (n·l) (1 − v·h)⁵ dl (0 for the diffuse LTC)
  Vec3<T> direction{0, 0, 1};  // representative direction, in the caller's (world) frame
  T n_dot_l = T(1);            // n · direction
  // The shaded value per unit radiance for Schlick's F0, times the micro-shadowing factor of the light.
  T value(T f0, T ms_area = T(1)) const {
    return (f0 * magnitude + (T(1) - f0) * fresnel) * integral * ms_area;
  }
};

namespace ltc_result {
template <class T>
LtcLightResult<T> ltc_finish(const LtcCoeffs<T>& k, const Frame<T>& f, const Mat3<T>& minv,
                             const LtcPolygonResult<T>& r) {
  LtcLightResult<T> o;
  o.integral = clamp(r.integral, T(0), T(1));
  o.magnitude = k.magnitude, o.fresnel = k.fresnel;
  o.direction = f.to_world(ltc_representative_direction(minv.inverse(), r));
  o.n_dot_l = dot(o.direction, f.n);
  return o;
}
}  // namespace ltc_result

// A sphere light seen from the shading point (all vectors in one frame, n and v unit, v above the surface):
// centre direction `to_light` (unit), angular radius σ given as sin σ = radius / distance ∈ [0, 1).
// The LTC `k` (fetched for the receiver's roughness and n·v), or LtcCoeffs<T>{} for Lambert diffuse (identity
// M⁻¹, magnitude 1, fresnel 0). polygon_sides: the N of the cap's polygon (3..16). clip_surface: clip the
// light to the surface's horizon too (ltc_integrate_polygon; the default, measured better in docs/ltc.md).
template <class T>
LtcLightResult<T> ltc_shade_sphere(const LtcCoeffs<T>& k, const Vec3<T>& n, const Vec3<T>& v,
                                   const Vec3<T>& to_light, T sin_sigma, int polygon_sides = 16,
                                   bool clip_surface = true) {
  const Frame<T> f = ltc_view_frame(n, v);
  const Mat3<T> minv = k.inv_m();
  return ltc_result::ltc_finish(
      k, f, minv, ltc_integrate_sphere(minv, f.to_local(to_light), sin_sigma, polygon_sides, clip_surface));
}

// A rectangle light: corners p[0..3] relative to the shading point (any winding), same frame as n, v.
template <class T>
LtcLightResult<T> ltc_shade_polygon(const LtcCoeffs<T>& k, const Vec3<T>& n, const Vec3<T>& v,
                                    const Vec3<T>* p, int count, bool clip_surface = true) {
  const Frame<T> f = ltc_view_frame(n, v);
  const Mat3<T> minv = k.inv_m();
  std::array<Vec3<T>, 16> q;
  count = std::clamp(count, 0, 16);
  for (int i = 0; i < count; ++i) q[size_t(i)] = f.to_local(p[i]);
  return ltc_result::ltc_finish(k, f, minv, ltc_integrate_polygon(minv, q.data(), count, clip_surface));
}

// The cheap stand-in for M_area: the point micro-shadowing term (any callable
// ms_point(n_dot_l) → factor, e.g. [&](double nl) { return micro_shadowing::reference_step(V, nl); })
// evaluated at the LTC's representative direction (the "most representative point" of the light for this
// lobe).
template <class T, class Fn>
T ltc_ms_at_representative(const LtcLightResult<T>& r, Fn&& ms_point) {
  return ms_point(clamp(r.n_dot_l, T(0), T(1)));
}

// ---- micro-shadowing of an LTC-shaded light without the representative point ---------------------------
//
// For a point term that depends on N·L only, M_area = ∫_Ω M(n·l) w(l) dl / ∫_Ω w(l) dl (docs/area-lights.md
// §1) depends on the light only through the distribution of z = n·l under the weight w over the light. With
// w = f(v, l)(n·l) ≈ magnitude · D_ltc(l) (GGX receiver) or w = (n·l)/π (Lambertian receiver: the identity
// LTC, exact) its complementary CDF is a ratio of two LTC polygon integrals,
//   S(z) = ∫_{Ω ∩ {n·l > z}} w / ∫_Ω w,  w = D_ltc + tail · (n·l)/π (the tail: see ltc_tail_weight),
// and the cap {n·l > z} is a cone about n, which we replace by the regular K-gon of the same gnomonic area
// (as ltc_sphere_polygon does for a sphere light) and clip the light's polygon by (Sutherland–Hodgman against
// the K planes through the shading point). So the reference step is S(cos_t) (one clipped polygon integral),
// and any smooth term is ∫ M dP by integrate_by_ccdf (math/quadrature.h). Measured against the exact
// GGX-weighted quadrature: docs/area-lights.md §5.

// Keeps the part of the polygon in[0..n−1] (any planar polygon in 3D, vertices relative to the shading point)
// with dot(d, p) ≥ 0, d the normal of a plane through the shading point; writes at most n + 1 vertices to out
// and returns their count (0: nothing left).
template <class T>
int ltc_clip_polygon(const Vec3<T>* in, int n, const Vec3<T>& d, Vec3<T>* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3<T>& a = in[i];
    const Vec3<T>& b = in[(i + 1) % n];
    const T da = dot(d, a), db = dot(d, b);
    if (da >= T(0)) out[m++] = a;
    if ((da >= T(0)) != (db >= T(0))) out[m++] = a + (b - a) * (da / (da - db));
  }
  return m < 3 ? 0 : m;
}

// The weight of the cosine "tail" beside the LTC in LtcLightCone for a GGX receiver of α = roughness²:
// 1.5 α^1.5. The LTC lobe has a hard edge (the transformed horizon) where GGX has a long tail, so a light off
// the highlight gets almost no LTC mass and its distribution of n·l is the tail's. Chosen on 300 Sobol points
// of verify area-lights' domain, measured on 2048 others (docs/area-lights.md §5).
template <class T>
T ltc_tail_weight(T alpha) {
  const T a = clamp(alpha, T(0), T(1));
  return T(1.5) * a * std::sqrt(a);
}

// A light's polygon in the LTC's frame (ltc_view_frame), clipped to the surface's horizon, prepared once per
// light, then S(z) per cone. The weight is w = D_ltc + tail · (n·l)/π (both normalized lobes): tail = 0 with
// the identity LTC for a Lambertian receiver (exact up to the polygons), ltc_tail_weight(α) for GGX.
template <class T>
struct LtcLightCone {
  static constexpr int kMaxSides = 16;    // light polygon: at most 16 vertices (ltc_integrate_polygon)
  static constexpr int kMaxCone = 16;     // cone polygon: 4..16 sides
  static constexpr int kMaxClipped = 40;  // 16 + 1 (horizon) + 16 (cone) + margin
  std::array<Vec3<T>, kMaxClipped> p{};
  int n = 0;
  Mat3<T> minv;
  int cone_sides = 16;
  T tail = T(0);
  T den = T(0);  // ∫ w over the horizon-clipped light
  T z_lo = T(0), z_hi = T(0);

  // poly[0..count−1]: the light's corners relative to the shading point in the LTC frame (n = +z); minv the
  // LTC's inverse matrix (identity: Lambertian receiver); tail ≥ 0 the cosine's weight; cone_sides K ∈ [4,
  // 16].
  static LtcLightCone make(const Mat3<T>& minv, const Vec3<T>* poly, int count, T tail = T(0),
                           int cone_sides = 16) {
    LtcLightCone c;
    c.minv = minv;
    c.tail = std::isfinite(tail) ? std::max(tail, T(0)) : T(0);
    c.cone_sides = std::clamp(cone_sides, 4, kMaxCone);
    count = std::clamp(count, 0, kMaxSides);
    c.n = ltc_clip_polygon(poly, count, Vec3<T>(T(0), T(0), T(1)), c.p.data());
    if (c.n == 0) return c;
    c.den = c.weight(c.p.data(), c.n);
    if (!(c.den > T(0))) {  // the LTC lobe misses the light: its n·l distribution is the tail's
      c.tail = T(1), c.minv = Mat3<T>{};
      c.den = c.weight(c.p.data(), c.n);
    }
    // z = n·l over the clipped spherical polygon: the minimum is at a corner (an arc above the horizon has
    // no interior minimum); the maximum is 1 if the polygon holds n, else the highest point of an arc.
    c.z_lo = T(1), c.z_hi = T(0);
    bool pos = true, neg = true;
    for (int i = 0; i < c.n; ++i) {
      const Vec3<T> a = normalize(c.p[size_t(i)]), b = normalize(c.p[size_t((i + 1) % c.n)]);
      c.z_lo = std::min(c.z_lo, a.z);
      T zmax = std::max(a.z, b.z);
      const T ab = clamp(dot(a, b), T(-1), T(1));
      const Vec3<T> e = b - a * ab;  // toward b, orthogonal to a
      const T le = length(e);
      if (le > T(0)) {
        const T ang = std::atan2(le, ab), t = std::atan2(e.z / le, a.z);
        if (t > T(0) && t < ang) zmax = std::max(zmax, std::hypot(a.z, e.z / le));
      }
      c.z_hi = std::max(c.z_hi, zmax);
      const T side = cross(a, b).z;
      pos = pos && side >= T(0), neg = neg && side <= T(0);
    }
    if (pos || neg) c.z_hi = T(1);
    c.z_lo = saturate(c.z_lo), c.z_hi = saturate(c.z_hi);
    return c;
  }

  // ∫ w over a polygon (shading frame, above the horizon): the LTC's integral in the cosine's space plus
  // tail times the polygon's own form factor.
  T weight(const Vec3<T>* q, int m) const {
    std::array<Vec3<T>, kMaxClipped> o;
    for (int i = 0; i < m; ++i) o[size_t(i)] = minv * q[i];
    T w = ltc_integrate_polygon_o<T>(o.data(), m).integral;
    if (tail > T(0)) w += tail * ltc_integrate_polygon_o<T>(q, m).integral;
    return w;
  }

  // S(z): the share of the light's weight with n·l > z, the cone {n·l > z} as its K-gon of equal gnomonic
  // area. 1 for z ≤ z_lo, 0 for z ≥ z_hi (and for a light below the horizon).
  T ccdf(T z) const {
    if (!(den > T(0))) return T(0);
    if (!(z > z_lo)) return T(1);
    if (!(z < z_hi)) return T(0);
    const int k = cone_sides;
    // Circumradius in the plane z = 1: the circle's radius tan t times the regular K-gon's area factor.
    const T tan_t = std::sqrt(std::max(T(0), T(1) - z * z)) / z;
    const T rc = tan_t * std::sqrt(T(2) * kPi<T> / (T(k) * std::sin(T(2) * kPi<T> / T(k))));
    std::array<Vec3<T>, kMaxClipped> a = p, b;
    int m = n;
    const Vec3<T> u0(rc, T(0), T(1));
    Vec3<T> u = u0;
    for (int i = 0; i < k && m > 0; ++i) {
      const T ph = T(2) * kPi<T> * T(i + 1) / T(k);
      const Vec3<T> v = i + 1 == k ? u0 : Vec3<T>(rc * std::cos(ph), rc * std::sin(ph), T(1));
      m = ltc_clip_polygon(a.data(), m, cross(u, v), b.data());
      std::swap(a, b);
      u = v;
    }
    return m > 0 ? saturate(weight(a.data(), m) / den) : T(0);
  }
};

// M_area of the reference step (lit iff N·L > cos_t) over an LTC-shaded light: S(cos_t).
template <class T>
T ltc_reference_step_area(const LtcLightCone<T>& light, T cos_t) {
  return light.ccdf(cos_t);
}

// M_area of any point term M(N·L) over an LTC-shaded light: ∫ M dP by integrate_by_ccdf, panels split at the
// light's n·l range and the term's kinks (occlusion/micro_shadowing_area.h: brinck_maximov_2016_kinks, …;
// values outside [0, 1] are ignored). n ∈ [1, 4] nodes per panel.
template <class T, class F, size_t K>
T ltc_micro_shadowing_area(F&& M, const LtcLightCone<T>& light, const std::array<T, K>& kinks, int n = 4) {
  if (!(light.den > T(0))) return T(0);
  if (!(light.z_hi > light.z_lo)) return M(light.z_lo);
  constexpr int kPts = int(K) + 2;
  T pts[kPts];
  pts[0] = light.z_lo, pts[kPts - 1] = light.z_hi;
  for (size_t i = 0; i < K; ++i) pts[i + 1] = kinks[i];
  sort_interior(pts, kPts);
  return saturate(integrate_by_ccdf(
      M, [&light](T z) { return light.ccdf(z); }, pts, kPts, light.z_hi, n));
}

// The light polygons of ltc_shade_sphere / ltc_shade_polygon, in the LTC frame of (n, v): a sphere light as
// its area-matched N-gon, a disk of centre c, unit normal nd and radius R as its area-matched N-gon in its
// plane, a polygon as given. tail: 0 for a Lambertian receiver (with the identity minv), ltc_tail_weight(α)
// for GGX.
template <class T>
LtcLightCone<T> ltc_light_cone_sphere(const Mat3<T>& minv, const Vec3<T>& n, const Vec3<T>& v,
                                      const Vec3<T>& to_light, T sin_sigma, T tail = T(0),
                                      int polygon_sides = 16, int cone_sides = 16) {
  const Frame<T> f = ltc_view_frame(n, v);
  std::array<Vec3<T>, 16> p;
  polygon_sides = std::clamp(polygon_sides, 3, 16);
  ltc_sphere_polygon(f.to_local(to_light), sin_sigma, polygon_sides, p.data());
  return LtcLightCone<T>::make(minv, p.data(), polygon_sides, tail, cone_sides);
}
template <class T>
LtcLightCone<T> ltc_light_cone_disk(const Mat3<T>& minv, const Vec3<T>& n, const Vec3<T>& v, const Vec3<T>& c,
                                    const Vec3<T>& nd, T R, T tail = T(0), int polygon_sides = 16,
                                    int cone_sides = 16) {
  const Frame<T> f = ltc_view_frame(n, v);
  polygon_sides = std::clamp(polygon_sides, 3, 16);
  const Frame<T> d = Frame<T>::from_z(normalize(nd));
  const T rc = R * std::sqrt(T(2) * kPi<T> / (T(polygon_sides) * std::sin(T(2) * kPi<T> / T(polygon_sides))));
  std::array<Vec3<T>, 16> p;
  for (int k = 0; k < polygon_sides; ++k) {
    const T ph = T(2) * kPi<T> * T(k) / T(polygon_sides);
    p[size_t(k)] = f.to_local(c + (d.s * std::cos(ph) + d.t * std::sin(ph)) * rc);
  }
  return LtcLightCone<T>::make(minv, p.data(), polygon_sides, tail, cone_sides);
}
template <class T>
LtcLightCone<T> ltc_light_cone_polygon(const Mat3<T>& minv, const Vec3<T>& n, const Vec3<T>& v,
                                       const Vec3<T>* corners, int count, T tail = T(0),
                                       int cone_sides = 16) {
  const Frame<T> f = ltc_view_frame(n, v);
  std::array<Vec3<T>, 16> p;
  count = std::clamp(count, 0, 16);
  for (int i = 0; i < count; ++i) p[size_t(i)] = f.to_local(corners[i]);
  return LtcLightCone<T>::make(minv, p.data(), count, tail, cone_sides);
}

}  // namespace msh::bsdf
