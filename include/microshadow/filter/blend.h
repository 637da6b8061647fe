// Material blending (RTR4 §9.13): BRDF parameters blend linearly (exact for parameters linear in the shaded
// colour, F0 and ρ; an approximation for roughness, done better on α² = the slope variance); normal maps
// blend as the height maps they come from (slope / partial-derivative blending), and a detail normal map is
// applied on top of a base with Reoriented Normal Mapping (Barré-Brisebois & Hill 2012, "Blending in Detail",
// RTR4 ref. [106]). Tangent-space unit normals, n = +z flat. Header-only, templated on the scalar, no I/O.
#pragma once

#include <microshadow/math/color.h>
#include <microshadow/math/vec.h>

namespace msh::filter {

// Linear parameter blend (RTR4 §9.13): a + t (b − a), t in [0,1] (clamped). Works for scalars and Rgb.
template <class T, class P>
P blend_linear(T t, const P& a, const P& b) {
  const T u = saturate(t);
  return a * (T(1) - u) + b * u;
}

// Roughness blended in variance space: α² = lerp(α_a², α_b²) (slope variances add linearly under a mask, as
// LEAN/CLEAN filtering assumes), r = α^½. Inputs: perceptual roughness in [0,1] (clamped).
template <class T>
T blend_roughness(T t, T r_a, T r_b) {
  const T a2 = sqr(sqr(saturate(r_a))), b2 = sqr(sqr(saturate(r_b)));
  return std::sqrt(std::sqrt(blend_linear(t, a2, b2)));
}

// Height-map (slope) blend of two normals: slopes b = (−n_x/n_z, −n_y/n_z) blend linearly, like the heights
// they differentiate. n_z clamped to ≥ 1e-4 (so backfacing or zero inputs still give a unit, upward result).
template <class T>
Vec3<T> blend_normals_slopes(T t, const Vec3<T>& n_a, const Vec3<T>& n_b) {
  const Vec3<T> a = normalize(n_a), b = normalize(n_b);
  const T za = std::max(a.z, T(1e-4)), zb = std::max(b.z, T(1e-4));
  const T u = saturate(t);
  const T bx = (T(1) - u) * (-a.x / za) + u * (-b.x / zb);
  const T by = (T(1) - u) * (-a.y / za) + u * (-b.y / zb);
  return normalize(Vec3<T>(-bx, -by, T(1)));
}

// Reoriented Normal Mapping (Barré-Brisebois & Hill 2012): rotates the detail normal by the rotation that
// takes +z to the base normal. Base with n_z ≤ −1 + ε (pointing straight down) has no unique rotation:
// returns the base.
template <class T>
Vec3<T> detail_normal_rnm(const Vec3<T>& base, const Vec3<T>& detail) {
  const Vec3<T> b = normalize(base), d = normalize(detail);
  const Vec3<T> t(b.x, b.y, b.z + T(1));
  if (!(t.z > T(1e-6))) return b;
  const Vec3<T> u(-d.x, -d.y, d.z);
  return normalize(t * (dot(t, u) / t.z) - u, b);
}

}  // namespace msh::filter
