// Engine-side area-light shading with linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016) and the
// micro-shadowing hook: the bilinear table fetch a shader does, GGX specular and Lambert diffuse for sphere
// and rectangle lights, and the combination with a micro-shadowing factor for the light (docs/ltc.md):
//   L_o,spec = L · (F0 · magnitude + (1 − F0) · fresnel) · ∫_light D_ltc · ms_area
//   L_o,diff = L · ρ · ∫_light (n·l)/π dl · ms_area_diffuse
// ms_area is the light-averaged micro-shadowing M_area (issue 12, item 1); until its fast forms exist, the
// point term at ltc_representative_direction is the stand-in (ltc_ms_at_representative). Header-only; no I/O.
#pragma once

#include <microshadow/bsdf/ltc.h>

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

// The stand-in for M_area until the fast forms exist: the point micro-shadowing term (any callable
// ms_point(n_dot_l) → factor, e.g. [&](double nl) { return micro_shadowing::reference_step(V, nl); })
// evaluated at the LTC's representative direction (the "most representative point" of the light for this
// lobe).
template <class T, class Fn>
T ltc_ms_at_representative(const LtcLightResult<T>& r, Fn&& ms_point) {
  return ms_point(clamp(r.n_dot_l, T(0), T(1)));
}

}  // namespace msh::bsdf
