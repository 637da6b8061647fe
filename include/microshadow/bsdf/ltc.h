// Linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016, "Real-Time Polygonal-Light Shading with
// Linearly Transformed Cosines"): D(ω) is the clamped cosine D_o(ω_o) = max(0, ω_o.z)/π carried by the
// direction transform ω = M ω_o / |M ω_o|. Everything here works with M⁻¹, which is what the table stores:
//   D(ω) = D_o(ω_o) |det M⁻¹| / |M⁻¹ω|³,  ω_o = M⁻¹ω / |M⁻¹ω|          (Heitz et al. 2016, eq. 2–3)
//   ∫_P D(ω) dω = ∫_{M⁻¹P} D_o(ω_o) dω_o = form factor of the transformed polygon, horizon-clipped
//   (Lambert 1760 / Baum et al. 1989 edge integral: (1/2π) Σ_edges θ_e n̂_e · z).
// Shading frame (docs/ltc.md): n = +z and the view in the xz-plane with v.x ≥ 0 (the LTC is fitted for
// v = (sin θ_v, 0, cos θ_v)); the isotropic table's M⁻¹ is [[a, 0, b], [0, 1, 0], [c, 0, d]] (scaled so
// that the middle entry is 1: the polygon integral does not depend on the scale of M⁻¹).
// Sphere lights (a spherical cap of angular radius σ): an LTC over a cap has no closed form; we integrate the
// area-matched regular N-gon in the plane perpendicular to the cap axis exactly (polygonal approximation;
// docs/ltc.md measures its error against quadrature of the LTC over the cap).
// Header-only, no I/O, no threads; templated on the scalar type.
#pragma once

#include <microshadow/math/vec.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace msh::bsdf {

// A row-major 3×3 matrix (just what LTCs need).
template <class T>
struct Mat3 {
  std::array<T, 9> m{T(1), T(0), T(0), T(0), T(1), T(0), T(0), T(0), T(1)};

  constexpr T operator()(int r, int c) const { return m[size_t(r * 3 + c)]; }
  constexpr T& operator()(int r, int c) { return m[size_t(r * 3 + c)]; }
  constexpr Vec3<T> operator*(const Vec3<T>& v) const {
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
            m[6] * v.x + m[7] * v.y + m[8] * v.z};
  }
  constexpr Mat3 operator*(const Mat3& b) const {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r(i, j) = (*this)(i, 0) * b(0, j) + (*this)(i, 1) * b(1, j) + (*this)(i, 2) * b(2, j);
    return r;
  }
  constexpr T det() const {
    return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
           m[2] * (m[3] * m[7] - m[4] * m[6]);
  }
  // The inverse by cofactors; a singular matrix returns the identity (callers keep M⁻¹ well conditioned:
  // the fitter bounds its parameters away from 0).
  Mat3 inverse() const {
    const T d = det();
    Mat3 r;
    if (!(std::abs(d) > T(0)) || !std::isfinite(d)) return r;
    const T id = T(1) / d;
    r(0, 0) = (m[4] * m[8] - m[5] * m[7]) * id;
    r(0, 1) = (m[2] * m[7] - m[1] * m[8]) * id;
    r(0, 2) = (m[1] * m[5] - m[2] * m[4]) * id;
    r(1, 0) = (m[5] * m[6] - m[3] * m[8]) * id;
    r(1, 1) = (m[0] * m[8] - m[2] * m[6]) * id;
    r(1, 2) = (m[2] * m[3] - m[0] * m[5]) * id;
    r(2, 0) = (m[3] * m[7] - m[4] * m[6]) * id;
    r(2, 1) = (m[1] * m[6] - m[0] * m[7]) * id;
    r(2, 2) = (m[0] * m[4] - m[1] * m[3]) * id;
    return r;
  }
  static constexpr Mat3 from_columns(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c) {
    Mat3 r;
    r.m = {a.x, b.x, c.x, a.y, b.y, c.y, a.z, b.z, c.z};
    return r;
  }
};

// The isotropic LTC of one table texel: M⁻¹ = [[a, 0, b], [0, 1, 0], [c, 0, d]] (texture RGBA = a, b, c, d),
// and the BRDF's moments (texture RG): magnitude = ∫ f (n·l) dl with F = 1 (the directional albedo E) and
// fresnel = ∫ f (n·l) (1 − v·h)⁵ dl (E_Fc), so that with Schlick's Fresnel the shaded value is
// (F0 · magnitude + (1 − F0) · fresnel) · ∫_light D (Heitz et al. 2016 §4; Hill & Heitz 2016 course notes).
template <class T>
struct LtcCoeffs {
  T a = T(1), b = T(0), c = T(0), d = T(1);
  T magnitude = T(1), fresnel = T(0);

  Mat3<T> inv_m() const {
    Mat3<T> r;
    r.m = {a, T(0), b, T(0), T(1), T(0), c, T(0), d};
    return r;
  }
};

// D(ω) of the LTC with inverse matrix minv (any scale), ω a unit vector (Heitz et al. 2016, eq. 3). 0 below
// the transformed horizon; finite for any finite minv (a singular one gives 0).
template <class T>
T ltc_eval(const Mat3<T>& minv, const Vec3<T>& w) {
  const Vec3<T> lo = minv * w;
  const T l2 = dot(lo, lo);
  if (!(l2 > T(0)) || !std::isfinite(l2)) return T(0);
  const T l = std::sqrt(l2);
  const T cz = lo.z / l;
  if (!(cz > T(0))) return T(0);
  const T jac = std::abs(minv.det()) / (l2 * l);  // |∂ω_o/∂ω|
  const T r = cz * kInvPi<T> * jac;
  return std::isfinite(r) ? r : T(0);
}

// Samples ω ~ D: ω_o ~ cosine (Malley), ω = M ω_o / |M ω_o| with m = M (the inverse of the table's M⁻¹).
// The pdf is ltc_eval(minv, ω). u ∈ [0,1)².
template <class T>
Vec3<T> ltc_sample(const Mat3<T>& m, Vec2<T> u) {
  const T r = std::sqrt(u.x), phi = T(2) * kPi<T> * u.y;
  const Vec3<T> wo(r * std::cos(phi), r * std::sin(phi), safe_sqrt(T(1) - u.x));
  return normalize(m * wo);
}

// The contribution of the great-circle arc a→b (unit vectors) to the vector form factor:
// θ n̂ = acos(a·b) (a×b)/|a×b| (Baum, Rushmeier, Winget 1989, eq. 4; times 1/2π by the caller). θ from atan2
// so that nearly parallel or antiparallel vertices stay exact; a × (b − a) = a × b, but without the
// cancellation of two nearly equal products when a ≈ b (in float, a × b of two unit vectors 1e-5 apart has
// an error larger than a tiny light's whole integral; the shaders do the same).
template <class T>
Vec3<T> ltc_edge_vector(const Vec3<T>& a, const Vec3<T>& b) {
  const Vec3<T> c = cross(a, b - a);
  const T s = length(c);
  const T th = std::atan2(s, dot(a, b));
  const T k = s > T(1e-30) ? th / s : T(1);
  return c * k;
}

// Result of integrating a clamped cosine over a polygon.
template <class T>
struct LtcPolygonResult {
  T integral = T(0);    // ∫ over the horizon-clipped polygon of D_o = max(0, z)/π (the form factor)
  Vec3<T> vector_ff{};  // vector form factor of the clipped polygon (its z is ±integral)
};

// ∫ D_o over the polygon p[0..n−1] (any vertices, not normalized, in the cosine's frame), clipped to z ≥ 0
// (Sutherland–Hodgman on the planar 3D polygon, streamed: no vertex list), then the edge sum (Heitz et al.
// 2016, §5.2, "Polygon integration"; Lambert's formula). Two-sided: |Σ| (winding-independent; whether the
// light faces the receiver is the caller's test). n ≤ 0 gives 0.
template <class T, class P>
LtcPolygonResult<T> ltc_integrate_polygon_o(const P* p, int n) {
  LtcPolygonResult<T> r;
  if (n < 3) return r;
  Vec3<T> first{}, last{};
  int emitted = 0;
  Vec3<T> sum{};
  auto emit = [&](const Vec3<T>& q) {
    const Vec3<T> u = normalize(q);
    if (emitted == 0)
      first = u;
    else
      sum += ltc_edge_vector(last, u);
    last = u;
    ++emitted;
  };
  for (int i = 0; i < n; ++i) {
    const Vec3<T> a = Vec3<T>(p[i]), b = Vec3<T>(p[(i + 1) % n]);
    const bool ia = a.z >= T(0), ib = b.z >= T(0);
    if (ia) emit(a);
    if (ia != ib) {
      const T t = a.z / (a.z - b.z);
      Vec3<T> q = a + (b - a) * t;
      q.z = T(0);  // exactly on the horizon
      emit(q);
    }
  }
  if (emitted < 3) return r;
  sum += ltc_edge_vector(last, first);
  r.vector_ff = sum * (T(1) / (T(2) * kPi<T>));
  r.integral = std::abs(r.vector_ff.z);
  if (!std::isfinite(r.integral)) r = LtcPolygonResult<T>{};
  return r;
}

// ∫_P D(ω) dω for the LTC with inverse matrix minv, P given by vertices relative to the shading point in the
// shading frame: the polygon is carried to the cosine's space by M⁻¹ and integrated there (Heitz et al.
// 2016, eq. 6: ∫_P D = ∫_{M⁻¹P} D_o). At most 16 vertices. The vector form factor is in the cosine's space.
// clip_surface: also clip P to the surface's horizon z ≥ 0 first, i.e. ∫_P D(ω) [ω.z ≥ 0] dω. The LTC puts a
// little mass below the surface (its support is the tilted half-space (M⁻¹ω).z > 0) where f·cos is 0;
// dropping it lowers the error for lights crossing the horizon (docs/ltc.md). The paper clips in the cosine's
// space only.
template <class T>
LtcPolygonResult<T> ltc_integrate_polygon(const Mat3<T>& minv, const Vec3<T>* p, int n,
                                          bool clip_surface = false) {
  std::array<Vec3<T>, 17> q;
  n = std::min(n, 16);
  int m = 0;
  if (clip_surface) {
    // Also clip to the surface's horizon z ≥ 0 first (the BRDF × cosine vanishes below it, the LTC need not).
    for (int i = 0; i < n; ++i) {
      const Vec3<T>& a = p[i];
      const Vec3<T>& b = p[(i + 1) % n];
      if (a.z >= T(0)) q[size_t(m++)] = minv * a;
      if ((a.z >= T(0)) != (b.z >= T(0))) {
        Vec3<T> c = a + (b - a) * (a.z / (a.z - b.z));
        c.z = T(0);
        q[size_t(m++)] = minv * c;
      }
    }
  } else {
    for (int i = 0; i < n; ++i) q[size_t(i)] = minv * p[i];
    m = n;
  }
  return ltc_integrate_polygon_o<T>(q.data(), m);
}

// The regular N-gon (N ≤ 16) standing in for a spherical cap of axis `axis` (unit) and angular radius σ
// (sin_sigma = sin σ, the sphere light's r/d): in the plane at distance 1 along the axis, circumradius chosen
// so that its area equals the disk of radius tan σ that subtends the cap. Counter-clockwise about the axis.
template <class T>
void ltc_sphere_polygon(const Vec3<T>& axis, T sin_sigma, int n, Vec3<T>* out) {
  n = std::clamp(n, 3, 16);
  sin_sigma = clamp(sin_sigma, T(0), T(0.9999));
  const T tan_s = sin_sigma / std::sqrt(T(1) - sin_sigma * sin_sigma);
  const T rc = tan_s * std::sqrt(T(2) * kPi<T> / (T(n) * std::sin(T(2) * kPi<T> / T(n))));
  const Frame<T> f = Frame<T>::from_z(axis);
  for (int k = 0; k < n; ++k) {
    const T ph = T(2) * kPi<T> * T(k) / T(n);
    out[k] = axis + (f.s * std::cos(ph) + f.t * std::sin(ph)) * rc;
  }
}

// ∫ D over a spherical cap (sphere light) by its N-gon (ltc_sphere_polygon), horizon-clipped.
template <class T>
LtcPolygonResult<T> ltc_integrate_sphere(const Mat3<T>& minv, const Vec3<T>& axis, T sin_sigma, int n = 16,
                                         bool clip_surface = false) {
  std::array<Vec3<T>, 16> p;
  n = std::clamp(n, 3, 16);
  ltc_sphere_polygon(axis, sin_sigma, n, p.data());
  return ltc_integrate_polygon(minv, p.data(), n, clip_surface);
}

// The four corners of a rectangle light of centre c, unit half-axes ex, ey and half-sizes hx, hy.
template <class T>
std::array<Vec3<T>, 4> ltc_rect_polygon(const Vec3<T>& c, const Vec3<T>& ex, const Vec3<T>& ey, T hx, T hy) {
  return {c - ex * hx - ey * hy, c + ex * hx - ey * hy, c + ex * hx + ey * hy, c - ex * hx + ey * hy};
}

// The rotation to the LTC's frame: local x = tangent toward the view, z = n. For a view along n any tangent
// works (the fit at θ_v = 0 is rotationally symmetric).
template <class T>
Frame<T> ltc_view_frame(const Vec3<T>& n, const Vec3<T>& v) {
  return Frame<T>::from_zx(n, v);
}

// The representative light direction of an LTC-shaded light: the clipped light's vector form factor in the
// cosine's space (∝ its mean direction there, Lambert's formula) mapped back, normalize(M F_o) (the direction
// Hill & Heitz 2016 use to fetch a light's texture). For a tiny light it is the light's direction; for a
// light larger than the lobe it follows the lobe. In the LTC frame; +z when the light is below the horizon.
// m = M (the inverse of the table's M⁻¹).
template <class T>
Vec3<T> ltc_representative_direction(const Mat3<T>& m, const LtcPolygonResult<T>& r) {
  if (!(r.integral > T(0))) return {T(0), T(0), T(1)};
  Vec3<T> f = r.vector_ff;
  if (f.z < T(0)) f = -f;  // two-sided: the clipped polygon's normal points toward +z in the cosine's space
  return normalize(m * f);
}

}  // namespace msh::bsdf
