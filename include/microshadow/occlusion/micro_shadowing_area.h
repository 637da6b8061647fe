// Area-light micro-shadowing, engine-facing fast forms (header-only, templated on the scalar). A
// spherical-cap light (a sphere light, or a disk facing the point) of angular radius ρ whose centre is at N·L
// = cos θc, and a Lambertian receiver:
//
//   M_area = ∫_cap M(l) (n·l)⁺ dl / ∫_cap (n·l)⁺ dl.
//
// The exact quadrature reference for any shape, receiver and term: reference/micro_shadowing_area_exact.h;
// definitions, derivations and measured errors: docs/area-lights.md.
//
// Contents:
//   * cap_intersection_solid_angle: the solid angle of the intersection of two spherical caps (Mazonka
//     2012, "Solid Angle of Conical Surfaces, Polyhedral Cones, and Intersecting Spherical Caps"), exact;
//   * cap_intersection_solid_angle_oat_sander: the approximation of Oat & Sander 2007 ("Ambient Aperture
//     Lighting", smoothstep in the axis distance);
//   * cap_cone_projected_solid_angle: the COSINE-WEIGHTED (projected) solid angle ∫ (n·l) dl of the
//     intersection of a cap with a cone about n, exact (our derivation from the boundary formula
//     ∫_A l dl = ½ ∮_∂A l × dl, Arvo 1995 "Applications of Irradiance Tensors", docs/area-lights.md §3);
//   * reference_step_area_cap: the reference step's M_area, exact (projected solid angles);
//     reference_step_area_cap_solid_angle / _oat_sander: the same ratio with plain solid angles (what an
//     ambient-aperture style engine computes: the (n·l) weight is dropped inside the light);
//   * area_cap_lambert: M_area of ANY point term that depends on N·L only (Brinck–Maximov 2016, Chan 2018,
//     Part 1, the azimuth mean of the generic term through its LUT or ALU fit): a product rule in N·L whose
//     weights come from the cap's closed-form CDF, split at the term's kinks; no table, any light size.
//
// Inputs: V ∈ [0, 1] (saturated), N·L of the centre ∈ [−1, 1] (clamped), ρ ∈ [0, π/2] (clamped). ρ = 0
// returns the point value. A light entirely below the horizon returns 0. Every function is finite for any
// input (NaN → 0 as in occlusion/micro_shadowing.h).
#pragma once

#include <microshadow/math/quadrature.h>
#include <microshadow/math/vec.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace msh::micro_shadowing {

namespace spherical_geometry {
template <class T>
T clamp_acos(T x) {
  return std::acos(clamp(x, T(-1), T(1)));
}
template <class T>
T clean(T x, T lo, T hi) {
  return std::isnan(x) ? lo : clamp(x, lo, hi);
}

// The spherical triangle with sides a, b, c (angles between three unit vectors), in the forms that stay
// accurate in float when the triangle is thin (a small light): with σ = (a + b + c)/2 and
// A = sin σ, B = sin(σ − a), C = sin(σ − b), D = sin(σ − c),
//   G = 1 − cos²a − cos²b − cos²c + 2 cos a cos b cos c = 4ABCD  (the Gram determinant),
//   cos a − cos b cos c = AB − CD  (and cyclically),
// so the angle opposite side a is atan2(√G, AB − CD) (law of cosines without acos near ±1). Requires the
// triangle inequalities (the crossing case of two circles).
template <class T>
struct ThinTriangle {
  T sqrt_g, a_num, b_num, c_num;  // √G; cos a − cos b cos c; cos b − cos a cos c; cos c − cos a cos b
  ThinTriangle(T a, T b, T c) {
    const T s = T(0.5) * (a + b + c);
    const T A = std::sin(s), B = std::sin(s - a), C = std::sin(s - b), D = std::sin(s - c);
    sqrt_g = T(2) * std::sqrt(std::max(T(0), A * B * C * D));
    a_num = A * B - C * D, b_num = A * C - B * D, c_num = A * D - B * C;
  }
  // Spherical excess by L'Huilier's theorem: tan(E/4) = sqrt(tan(σ/2) tan((σ−a)/2) tan((σ−b)/2)
  // tan((σ−c)/2)).
  static T excess(T a, T b, T c) {
    const T s = T(0.5) * (a + b + c);
    const T p = std::tan(T(0.5) * s) * std::tan(T(0.5) * (s - a)) * std::tan(T(0.5) * (s - b)) *
                std::tan(T(0.5) * (s - c));
    return T(4) * std::atan(std::sqrt(std::max(T(0), p)));
  }
};
}  // namespace spherical_geometry

// Solid angle of the intersection of two spherical caps of angular radii r1, r2 ∈ [0, π/2] whose axes are
// `gamma` ∈ [0, π] apart (Mazonka 2012, the result for two intersecting caps; equivalently Gauss–Bonnet on
// the lens bounded by two small-circle arcs):
//   Ω = 2(π − ψ) − 2 w1 cos r1 − 2 w2 cos r2,
//   cos ψ = (cos γ − cos r1 cos r2)/(sin r1 sin r2)   (the lens corner's interior angle is π − ψ),
//   cos w1 = (cos r2 − cos r1 cos γ)/(sin r1 sin γ),  cos w2 = (cos r1 − cos r2 cos γ)/(sin r2 sin γ)
//   (w_i: half of the angle, about axis i, of circle i's arc inside the other cap).
// Evaluated as Ω = 4 w1 sin²(r1/2) + 4 w2 sin²(r2/2) − 2 E, E = w1 + w2 + ψ − π the excess of the triangle
// (axis 1, axis 2, corner) by L'Huilier, and the angles by ThinTriangle: the direct form loses everything
// to cancellation in float for a light of a few degrees. Nested caps: 4π sin²(min(r1, r2)/2); disjoint: 0.
template <class T>
T cap_intersection_solid_angle(T r1, T r2, T gamma) {
  using namespace spherical_geometry;
  r1 = clean(r1, T(0), kPi<T> / 2), r2 = clean(r2, T(0), kPi<T> / 2), gamma = clean(gamma, T(0), kPi<T>);
  if (gamma >= r1 + r2) return T(0);
  const T rm = std::min(r1, r2);
  if (gamma <= std::abs(r1 - r2)) return T(4) * kPi<T> * sqr(std::sin(T(0.5) * rm));
  const ThinTriangle<T> tri(r1, r2, gamma);  // sides: r1 (axis 1–corner), r2 (axis 2–corner), γ
  const T w1 = std::atan2(tri.sqrt_g, tri.b_num), w2 = std::atan2(tri.sqrt_g, tri.a_num);
  const T ex = ThinTriangle<T>::excess(r1, r2, gamma);
  const T om = T(4) * w1 * sqr(std::sin(T(0.5) * r1)) + T(4) * w2 * sqr(std::sin(T(0.5) * r2)) - T(2) * ex;
  return clamp(om, T(0), T(4) * kPi<T> * sqr(std::sin(T(0.5) * rm)));
}

// Oat & Sander 2007 ("Ambient Aperture Lighting", SphericalCapIntersectionAreaFast): the smaller cap's area
// times smoothstep(0, 1, 1 − (γ − |r1 − r2|)/(r1 + r2 − |r1 − r2|)) between the nested and disjoint cases.
// An approximation of cap_intersection_solid_angle; its error: docs/area-lights.md §4.
template <class T>
T cap_intersection_solid_angle_oat_sander(T r1, T r2, T gamma) {
  using namespace spherical_geometry;
  r1 = clean(r1, T(0), kPi<T> / 2), r2 = clean(r2, T(0), kPi<T> / 2), gamma = clean(gamma, T(0), kPi<T>);
  const T full = T(4) * kPi<T> * sqr(std::sin(T(0.5) * std::min(r1, r2)));
  const T diff = std::abs(r1 - r2);
  if (gamma <= diff) return full;
  if (gamma >= r1 + r2) return T(0);
  const T x = saturate(T(1) - (gamma - diff) / (r1 + r2 - diff));
  return full * x * x * (T(3) - T(2) * x);
}

// ∫ (n·l) dl over {l in the cap of radius rho ∈ [0, π/2] about c} ∩ {n·l > cos t}, t ∈ [0, π/2] (t = π/2:
// the horizon), with θc ∈ [0, π] the angle between c and n. From ∫_A l dl = ½ ∮_∂A l × dl (Arvo 1995): an
// arc of the small circle of radius r about axis a, spanning |τ| < w about the direction e toward the other
// circle's axis, contributes ½ n·∫ l × dl = (n·a) w sin²r − (n·e) sin w sin r cos r. For the cap (a = c,
// n·e = sin θc) and the cone (a = n, n·e = 0):
//   E = cos θc w1 sin²ρ − cos ρ √G + w2 sin²t     (sin θc sin w1 sin ρ = √G),
// w1 (at c), w2 (at n) the angles of the triangle (n, c, corner) with sides t, ρ, θc, by ThinTriangle.
// Nested: π sin²ρ cos θc (cap in cone) or π sin²t (cone in cap); disjoint: 0.
template <class T>
T cap_cone_projected_solid_angle(T rho, T theta_c, T t) {
  using namespace spherical_geometry;
  rho = clean(rho, T(0), kPi<T> / 2), t = clean(t, T(0), kPi<T> / 2), theta_c = clean(theta_c, T(0), kPi<T>);
  const T sr = std::sin(rho), st = std::sin(t), cc = std::cos(theta_c);
  if (theta_c >= rho + t) return T(0);
  if (theta_c <= t - rho) return kPi<T> * sr * sr * cc;
  if (theta_c <= rho - t) return kPi<T> * st * st;
  const ThinTriangle<T> tri(t, rho, theta_c);      // sides: t (n–corner), ρ (c–corner), θc (n–c)
  const T w1 = std::atan2(tri.sqrt_g, tri.a_num);  // at c, opposite t
  const T w2 = std::atan2(tri.sqrt_g, tri.b_num);  // at n, opposite ρ
  return std::max(T(0), cc * w1 * sr * sr - std::cos(rho) * tri.sqrt_g + w2 * st * st);
}

// Half-angle of the visibility cone, atan2(√V, √(1 − V)) (accurate at both ends, unlike acos √(1 − V)).
template <class T>
T cone_angle(T V) {
  const T v = saturate(V);
  return std::atan2(std::sqrt(v), std::sqrt(T(1) - v));
}

// Angle of the cap centre from n for the inputs N·L ∈ [−1, 1].
template <class T>
T cap_theta(T n_dot_l) {
  return spherical_geometry::clamp_acos(spherical_geometry::clean(n_dot_l, T(-1), T(1)));
}

namespace cap_ratio {
// The frame the reference_step_area_cap* forms share: ρ = 0 is the point value reference_step(V, N·L);
// otherwise measure(ρ, θc, t) / measure(ρ, θc, π/2) for the cone half-angle t, in [0, 1] (0 if the light
// is below the horizon). measure(ρ, θc, t) is a measure of the cap ∩ the cone of half-angle t about n.
template <class T, class Measure>
T cone_over_hemisphere(T V, T n_dot_l, T rho, Measure measure) {
  using namespace spherical_geometry;
  rho = clean(rho, T(0), kPi<T> / 2);
  if (!(rho > T(0))) return reference_step(V, n_dot_l);
  const T th = cap_theta(n_dot_l), t = cone_angle(V);
  const T den = measure(rho, th, kPi<T> / 2);
  return den > T(0) ? saturate(measure(rho, th, t) / den) : T(0);
}
}  // namespace cap_ratio

// The reference step (lit iff N·L > cos_t) over a cap light, Lambertian receiver, exact:
// E(cap ∩ cone) / E(cap ∩ hemisphere). ρ = 0: the point value reference_step(V, N·L).
template <class T>
T reference_step_area_cap(T V, T n_dot_l, T rho) {
  return cap_ratio::cone_over_hemisphere(
      V, n_dot_l, rho, [](T r, T th, T t) { return cap_cone_projected_solid_angle(r, th, t); });
}

// The same ratio with plain solid angles, Ω(cap ∩ cone) / Ω(cap ∩ hemisphere) (Mazonka 2012): the (n·l)
// weight inside the light is dropped. Its cost against reference_step_area_cap: docs/area-lights.md §4.
template <class T>
T reference_step_area_cap_solid_angle(T V, T n_dot_l, T rho) {
  return cap_ratio::cone_over_hemisphere(
      V, n_dot_l, rho, [](T r, T th, T t) { return cap_intersection_solid_angle(r, t, th); });
}

// The same with Oat & Sander 2007's approximation for both solid angles.
template <class T>
T reference_step_area_cap_oat_sander(T V, T n_dot_l, T rho) {
  return cap_ratio::cone_over_hemisphere(
      V, n_dot_l, rho, [](T r, T th, T t) { return cap_intersection_solid_angle_oat_sander(r, t, th); });
}

// A cap light of angular radius ρ centred at N·L = cos θc with a Lambertian receiver, prepared once per
// light: the z = n·l range it covers above the horizon and its complementary CDF in z,
//   S(z) = ∫_{cap, n·l > z} (n·l) dl / ∫_{cap, n·l > 0} (n·l) dl
// (= reference_step_area_cap at cos_t = z), in closed form (cap_cone_projected_solid_angle).
template <class T>
struct CapLightLambert {
  T rho = 0, theta_c = 0, den = 0;
  T z_lo = 0;  // lowest n·l of the cap above the horizon
  T z_hi = 0;  // highest n·l (1 when the cap contains n)
  T z_b = 0;   // cos|θc − ρ|: the top of the cap, or where its circles of constant n·l become full

  static CapLightLambert make(T n_dot_l, T rho) {
    using namespace spherical_geometry;
    CapLightLambert c;
    c.rho = clean(rho, T(0), kPi<T> / 2);
    c.theta_c = cap_theta(n_dot_l);
    c.den = cap_cone_projected_solid_angle(c.rho, c.theta_c, kPi<T> / 2);
    c.z_lo = std::max(T(0), std::cos(std::min(kPi<T>, c.theta_c + c.rho)));
    c.z_b = std::cos(std::abs(c.theta_c - c.rho));
    c.z_hi = c.theta_c < c.rho ? T(1) : c.z_b;
    return c;
  }
  T ccdf(T z) const {
    if (!(z > z_lo)) return T(1);
    if (!(z < z_hi) || !(den > T(0))) return T(0);
    return saturate(cap_cone_projected_solid_angle(rho, theta_c, spherical_geometry::clamp_acos(z)) / den);
  }
};

// Kinks (in N·L) of the point terms: the panel edges of area_cap_lambert (−1: none).
template <class T>
std::array<T, 2> brinck_maximov_2016_kinks(T V) {
  const T v = saturate(V);
  return {T(1) - T(2) * v * v, T(2) - T(2) * v * v};
}
template <class T>
std::array<T, 2> chan_2018_kinks(T V) {
  return {cone_cos_from_visibility(V), T(-1)};
}
// Part 1: the kink at sqrt(1 − V⁵), and where the term reaches 0.03: for small V its exponent 0.75/V makes it
// a near-step just below the kink, which a panel edge there resolves (max error 6.7/255 → 0.2/255).
template <class T>
std::array<T, 2> part1_analytic_kinks(T V) {
  const T v = saturate(V);
  const T cp = std::sqrt(std::max(T(0), T(1) - v * v * v * v * v));
  return {cp, cp * std::pow(T(0.03), v / T(0.75))};
}
// Generic term: exactly 0 below N·L = 1 − 2V (the early-out); its azimuth mean is a smoothed step at the cone
// N·L = cos_t of width ~ w = max(α, 0.02) sin t at low roughness, so cos_t and cos_t ± 4w are panel edges
// too (max quadrature error 1.8/255 → 0.08/255 at 40 Sobol points).
template <class T>
std::array<T, 4> generic_vndf_kinks(T V, T roughness) {
  const T v = saturate(V), c = cone_cos_from_visibility(v);
  const T r = clamp(roughness, T(0), T(1));
  const T w = std::max(r * r, T(0.02)) * std::sqrt(v);
  return {T(1) - T(2) * v, c, c - T(4) * w, c + T(4) * w};
}

// The micro-BRDF-aware terms' azimuth means (docs/micro-shadowing-aware.md): the specular-aware mean kinks
// where its closed form's interval ends reach φ = 0 or π, θl = |2t − θv| and θl = θv + 2t (t the cone's
// half-angle, θv = acos N·V), and is 0 below the early-out 1 − 2V; the diffuse-aware mean is continuous
// apart from the early-out and the cone (−1: none).
template <class T>
std::array<T, 3> specular_aware_kinks(T V, T n_dot_v) {
  const T v = saturate(V), c = cone_cos_from_visibility(v);
  const T t = std::acos(clamp(c, T(0), T(1))), tv = std::acos(saturate(n_dot_v));
  return {std::cos(std::abs(T(2) * t - tv)), T(1) - T(2) * v,
          T(2) * t + tv < T(0.5) * kPi<T> ? std::cos(T(2) * t + tv) : T(-1)};
}
template <class T>
std::array<T, 2> diffuse_aware_kinks(T V) {
  const T v = saturate(V);
  return {T(1) - T(2) * v, cone_cos_from_visibility(v)};
}

// M_area over a cap light, Lambertian receiver, of any point term M(N·L) that depends on N·L only (the
// closed-form terms; the azimuth mean of the generic term through its LUT or ALU fit: for a Lambertian
// receiver the azimuth mean of M_area is exactly M_area of the azimuth-mean term, docs/area-lights.md §5).
// M_area = ∫ M dP, P the distribution of n·l over the cosine-weighted cap. The z range is split at the
// kinks and at z_b; on each panel [a, b] M is replaced by its interpolating polynomial Σ M(z_i) L_i(z) at
// the n Gauss–Legendre nodes z_i (n ∈ [1, 4]) and integrated against dP exactly by parts:
//   ∫_a^b L_i dP = L_i(a) S(a) − L_i(b) S(b) + ∫_a^b L_i'(z) S(z) dz,
// the last integral by the same n-point rule. So the square-root ends of the cap's density are never
// sampled: they are inside S, in closed form. Cost per panel: n evaluations of M and n + 1 of S (3 acos).
// Measured error: docs/area-lights.md §5. ρ = 0: M(N·L).
template <class T, class F, size_t K>
T area_cap_lambert(F&& M, T n_dot_l, T rho, const std::array<T, K>& kinks, int n = 4) {
  using namespace spherical_geometry;
  rho = clean(rho, T(0), kPi<T> / 2);
  const T nl = clean(n_dot_l, T(-1), T(1));
  if (!(rho > T(0))) return M(nl);
  const CapLightLambert<T> c = CapLightLambert<T>::make(nl, rho);
  if (!(c.den > T(0)) || !(c.z_hi > c.z_lo)) return T(0);
  constexpr int kPts = int(K) + 3;
  T pts[kPts];
  pts[0] = c.z_lo, pts[kPts - 2] = c.z_b, pts[kPts - 1] = c.z_hi;
  for (size_t i = 0; i < K; ++i) pts[i + 1] = kinks[i];
  sort_interior(pts, kPts);
  return saturate(integrate_by_ccdf(
      M, [&c](T z) { return c.ccdf(z); }, pts, kPts, c.z_hi, n));
}

// The area forms of the closed-form terms of occlusion/micro_shadowing.h (Lambertian receiver, cap light).
template <class T>
T brinck_maximov_2016_area_cap(T V, T n_dot_l, T rho, int n = 4) {
  return area_cap_lambert([V](T z) { return brinck_maximov_2016(V, z); }, n_dot_l, rho,
                          brinck_maximov_2016_kinks(V), n);
}
template <class T>
T chan_2018_area_cap(T V, T n_dot_l, T rho, int n = 4) {
  return area_cap_lambert([V](T z) { return chan_2018(V, z); }, n_dot_l, rho, chan_2018_kinks(V), n);
}
template <class T>
T part1_analytic_area_cap(T V, T n_dot_l, T rho, int n = 4) {
  return area_cap_lambert([V](T z) { return part1_analytic(V, z); }, n_dot_l, rho, part1_analytic_kinks(V),
                          n);
}

// The generic term's azimuth mean through its ALU fit (occlusion/micro_shadowing_fit.h, generic_vndf_alu)
// over a cap light, Lambertian receiver: n evaluations of the fit per panel (two panels at most: the
// early-out, the cone and z_b). Its error against the exact reference: docs/area-lights.md §5.
template <class T>
T generic_vndf_alu_area_cap(T V, T n_dot_l, T n_dot_v, T roughness, T rho, int n = 4) {
  return area_cap_lambert([&](T z) { return generic_vndf_alu(V, z, n_dot_v, roughness); }, n_dot_l, rho,
                          generic_vndf_kinks(V, roughness), n);
}

// ---- disk and rectangle lights, Lambertian receiver: the equivalent cap
// ------------------------------------
//
// For a term that depends on N·L only and a Lambertian receiver, M_area depends on the light only through the
// distribution of n·l over its cosine-weighted solid angle. The fast form replaces a disk or a polygon (a
// rectangle light) by the spherical cap with the same vector form factor F = ∫_Ω l dl (unclipped): axis
// F/|F|, sin²ρ = |F|/π (a cap of radius ρ about c has F = π sin²ρ c). So the cap has the light's
// cosine-weighted form factor toward every receiver normal whose horizon does not cut it, is centred on the
// light's centroid direction, and reuses every cap form above (reference_step_area_cap, area_cap_lambert and
// the terms built on it); the horizon clipping is then the cap's. The same sphere approximates the horizon-
// clipped irradiance of a polygon light in Heitz 2017, "Geometric Derivation of the Irradiance of Polygonal
// Lights". Its error against the exact reference: docs/area-lights.md §5.

template <class T>
struct EquivalentCap {
  T n_dot_l = T(1);  // N·L of the cap's axis
  T rho = T(0);      // its angular radius ∈ [0, π/2]
};

// The cap of the vector form factor F. A light of zero size (F = 0, or not finite) gives the zero-size cap at
// `center` (its direction), so the cap forms return the point value there.
template <class T>
EquivalentCap<T> equivalent_cap(const Vec3<T>& F, const Vec3<T>& center = Vec3<T>(T(0), T(0), T(1))) {
  const T len = length(F);
  EquivalentCap<T> c;
  if (!(len > T(0)) || !std::isfinite(len)) {
    const T lc = length(center);
    c.n_dot_l = lc > T(0) ? clamp(center.z / lc, T(-1), T(1)) : T(1);
    return c;
  }
  c.n_dot_l = clamp(F.z / len, T(-1), T(1));
  const T q = saturate(len / kPi<T>);
  c.rho = std::atan2(std::sqrt(q), std::sqrt(T(1) - q));
  return c;
}

// F = ∫_Ω l dl of a convex spherical polygon with corners (unit directions, either winding, n ≤ 8): Lambert's
// formula ½ Σ θ_i n̂_i (θ_i the arc between corners i and i + 1, n̂_i the normal of its great circle; Arvo
// 1995, "Applications of Irradiance Tensors"), oriented toward the corners' mean.
template <class T>
Vec3<T> polygon_vector_form_factor(const Vec3<T>* corners, int n) {
  Vec3<T> F(T(0), T(0), T(0)), mean(T(0), T(0), T(0));
  for (int i = 0; i < n; ++i) {
    const Vec3<T> a = normalize(corners[i]), b = normalize(corners[(i + 1) % n]);
    const Vec3<T> x = cross(a, b);
    const T sx = length(x);
    if (sx > T(0)) F += x * (std::atan2(sx, dot(a, b)) / sx);
    mean += a;
  }
  F = F * T(0.5);
  return dot(F, mean) < T(0) ? -F : F;
}

// F = ∫_Ω l dl of a planar disk: centre c (relative to the shading point, any distance > 0), unit normal nd
// (either sign), radius R. From ∫_Ω l dl = ½ ∮ l × dl (Arvo 1995) on the rim p(a) = c + R(cos a e1 + sin a
// e2): l × dl = p × p′ / |p|² da with |p|² = A + B cos a + C sin a (A = |c|² + R², B = 2R c·e1, C = 2R c·e2)
// and p × p′ = R (cos a c × e2 − sin a c × e1) + R² nd, whose integrals are ∫ da/|p|² = 2π/D and ∫ (cos a,
// sin a) da/|p|² = −2π (B, C)/(D (D + A)), D = √(A² − B² − C²). Oriented toward c.
template <class T>
Vec3<T> disk_vector_form_factor(const Vec3<T>& c, const Vec3<T>& nd, T R) {
  const Vec3<T> n = normalize(nd);
  const Frame<T> f = Frame<T>::from_z(n);
  const T r = std::max(R, T(0));
  const T A = dot(c, c) + r * r, B = T(2) * r * dot(c, f.s), C = T(2) * r * dot(c, f.t);
  const T hb = std::hypot(B, C);
  // The point on the rim of a disk seen edge-on (A = |(B, C)|): zero solid angle, the integrals singular.
  if (!(A - hb > T(8) * std::numeric_limits<T>::epsilon() * A)) return Vec3<T>(T(0), T(0), T(0));
  const T D = std::sqrt((A - hb) * (A + hb));
  const T I0 = T(2) * kPi<T> / D, k = -T(2) * kPi<T> / (D * (D + A));
  const Vec3<T> F = (cross(c, f.t) * (r * k * B) - cross(c, f.s) * (r * k * C) + n * (r * r * I0)) * T(0.5);
  return dot(F, c) < T(0) ? -F : F;
}

// The reference step over a disk or polygon light through its equivalent cap (Lambertian receiver).
template <class T>
T reference_step_area_equivalent_cap(T V, const Vec3<T>& F,
                                     const Vec3<T>& center = Vec3<T>(T(0), T(0), T(1))) {
  const EquivalentCap<T> e = equivalent_cap(F, center);
  return reference_step_area_cap(V, e.n_dot_l, e.rho);
}

}  // namespace msh::micro_shadowing
