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
//     Part 1, the azimuth mean of the generic term through its LUT or ALU fit) by Gauss–Legendre in N·L with
//     the cap's exact width, split at the term's kinks: a fast form with a light-size "axis" for free.
//
// Inputs: V ∈ [0, 1] (saturated), N·L of the centre ∈ [−1, 1] (clamped), ρ ∈ [0, π/2] (clamped). ρ = 0
// returns the point value. A light entirely below the horizon returns 0. Every function is finite for any
// input (NaN → 0 as in occlusion/micro_shadowing.h).
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/occlusion/micro_shadowing.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace msh::ms {

namespace area_detail {
template <class T>
T clamp_acos(T x) {
  return std::acos(clamp(x, T(-1), T(1)));
}
template <class T>
T clean(T x, T lo, T hi) {
  return std::isnan(x) ? lo : clamp(x, lo, hi);
}
}  // namespace area_detail

// Solid angle of the intersection of two spherical caps of angular radii r1, r2 ∈ [0, π/2] whose axes are
// `gamma` ∈ [0, π] apart (Mazonka 2012, eq. for two intersecting caps; equivalently Gauss–Bonnet on the lens
// bounded by two small-circle arcs):
//   Ω = 2(π − ψ) − 2 w1 cos r1 − 2 w2 cos r2,
//   cos ψ = (cos γ − cos r1 cos r2)/(sin r1 sin r2)   (the lens corner's interior angle is π − ψ),
//   cos w1 = (cos r2 − cos r1 cos γ)/(sin r1 sin γ),  cos w2 = (cos r1 − cos r2 cos γ)/(sin r2 sin γ)
//   (w_i: half of the angle, about axis i, of circle i's arc inside the other cap).
// Nested caps: 2π(1 − cos min(r1, r2)); disjoint: 0.
template <class T>
T cap_intersection_solid_angle(T r1, T r2, T gamma) {
  using namespace area_detail;
  r1 = clean(r1, T(0), kPi<T> / 2), r2 = clean(r2, T(0), kPi<T> / 2), gamma = clean(gamma, T(0), kPi<T>);
  if (gamma >= r1 + r2) return T(0);
  if (gamma <= std::abs(r1 - r2)) return T(2) * kPi<T> * (T(1) - std::cos(std::min(r1, r2)));
  const T c1 = std::cos(r1), s1 = std::sin(r1), c2 = std::cos(r2), s2 = std::sin(r2);
  const T cg = std::cos(gamma), sg = std::sin(gamma);
  const T psi = clamp_acos((cg - c1 * c2) / (s1 * s2));
  const T w1 = clamp_acos((c2 - c1 * cg) / (s1 * sg)), w2 = clamp_acos((c1 - c2 * cg) / (s2 * sg));
  return std::max(T(0), T(2) * (kPi<T> - psi) - T(2) * w1 * c1 - T(2) * w2 * c2);
}

// Oat & Sander 2007 ("Ambient Aperture Lighting", SphericalCapIntersectionAreaFast): the smaller cap's area
// times smoothstep(0, 1, 1 − (γ − |r1 − r2|)/(r1 + r2 − |r1 − r2|)) between the nested and disjoint cases.
// An approximation of cap_intersection_solid_angle; its error: docs/area-lights.md §4.
template <class T>
T cap_intersection_solid_angle_oat_sander(T r1, T r2, T gamma) {
  using namespace area_detail;
  r1 = clean(r1, T(0), kPi<T> / 2), r2 = clean(r2, T(0), kPi<T> / 2), gamma = clean(gamma, T(0), kPi<T>);
  const T full = T(2) * kPi<T> * (T(1) - std::cos(std::min(r1, r2)));
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
//   E = cos θc w1 sin²ρ − sin θc sin w1 sinρ cosρ + w2 sin²t,
// w1, w2 the half-arcs of cap_intersection_solid_angle (γ = θc). Nested: π sin²ρ cos θc (cap in cone) or
// π sin²t (cone in cap); disjoint: 0.
template <class T>
T cap_cone_projected_solid_angle(T rho, T theta_c, T t) {
  using namespace area_detail;
  rho = clean(rho, T(0), kPi<T> / 2), t = clean(t, T(0), kPi<T> / 2), theta_c = clean(theta_c, T(0), kPi<T>);
  const T sr = std::sin(rho), cr = std::cos(rho), st = std::sin(t), ct = std::cos(t);
  const T cc = std::cos(theta_c), sc = std::sin(theta_c);
  if (theta_c >= rho + t) return T(0);
  if (theta_c <= t - rho) return kPi<T> * sr * sr * cc;
  if (theta_c <= rho - t) return kPi<T> * st * st;
  const T w1 = clamp_acos((ct - cr * cc) / (sr * sc)), w2 = clamp_acos((cr - ct * cc) / (st * sc));
  return std::max(T(0), cc * w1 * sr * sr - sc * std::sin(w1) * sr * cr + w2 * st * st);
}

// Angle of the cap centre from n for the inputs N·L ∈ [−1, 1].
template <class T>
T cap_theta(T n_dot_l) {
  return area_detail::clamp_acos(area_detail::clean(n_dot_l, T(-1), T(1)));
}

// The reference step (lit iff N·L > cos_t) over a cap light, Lambertian receiver, exact:
// E(cap ∩ cone) / E(cap ∩ hemisphere). ρ = 0: the point value reference_step(V, N·L).
template <class T>
T reference_step_area_cap(T V, T n_dot_l, T rho) {
  using namespace area_detail;
  rho = clean(rho, T(0), kPi<T> / 2);
  if (!(rho > T(0))) return reference_step(V, n_dot_l);
  const T th = cap_theta(n_dot_l), t = clamp_acos(cone_cos_from_visibility(V));
  const T den = cap_cone_projected_solid_angle(rho, th, kPi<T> / 2);
  return den > T(0) ? saturate(cap_cone_projected_solid_angle(rho, th, t) / den) : T(0);
}

// The same ratio with plain solid angles, Ω(cap ∩ cone) / Ω(cap ∩ hemisphere) (Mazonka 2012): the (n·l)
// weight inside the light is dropped. Its cost against reference_step_area_cap: docs/area-lights.md §4.
template <class T>
T reference_step_area_cap_solid_angle(T V, T n_dot_l, T rho) {
  using namespace area_detail;
  rho = clean(rho, T(0), kPi<T> / 2);
  if (!(rho > T(0))) return reference_step(V, n_dot_l);
  const T th = cap_theta(n_dot_l), t = clamp_acos(cone_cos_from_visibility(V));
  const T den = cap_intersection_solid_angle(rho, kPi<T> / 2, th);
  return den > T(0) ? saturate(cap_intersection_solid_angle(rho, t, th) / den) : T(0);
}

// The same with Oat & Sander 2007's approximation for both solid angles.
template <class T>
T reference_step_area_cap_oat_sander(T V, T n_dot_l, T rho) {
  using namespace area_detail;
  rho = clean(rho, T(0), kPi<T> / 2);
  if (!(rho > T(0))) return reference_step(V, n_dot_l);
  const T th = cap_theta(n_dot_l), t = clamp_acos(cone_cos_from_visibility(V));
  const T den = cap_intersection_solid_angle_oat_sander(rho, kPi<T> / 2, th);
  return den > T(0) ? saturate(cap_intersection_solid_angle_oat_sander(rho, t, th) / den) : T(0);
}

// Width in azimuth about n, 2·acos((cos ρ − z cos θc)/(sin θc sqrt(1 − z²))), of the cap on the circle
// n·l = z: dl = dz dφ, so ∫_cap g(n·l) dl = ∫ g(z) width(z) dz.
template <class T>
T cap_azimuth_width(T z, T cos_rho, T cos_tc, T sin_tc) {
  const T s = std::sqrt(std::max(T(0), T(1) - z * z));
  const T d = sin_tc * s;
  if (!(d > T(0))) return z * cos_tc > cos_rho ? T(2) * kPi<T> : T(0);
  return T(2) * area_detail::clamp_acos((cos_rho - z * cos_tc) / d);
}

// Kinks (in N·L) of the point terms, the panel edges of area_cap_lambert.
template <class T>
std::array<T, 2> brinck_maximov_2016_kinks(T V) {
  const T v = saturate(V);
  return {T(1) - T(2) * v * v, T(2) - T(2) * v * v};
}
template <class T>
std::array<T, 2> chan_2018_kinks(T V) {
  return {cone_cos_from_visibility(V), T(-1)};
}
template <class T>
std::array<T, 2> part1_analytic_kinks(T V) {
  const T v = saturate(V);
  return {std::sqrt(std::max(T(0), T(1) - v * v * v * v * v)), T(-1)};
}
// Generic term: exactly 0 below N·L = 1 − 2V (the early-out), smooth above for the azimuth mean.
template <class T>
std::array<T, 2> generic_vndf_kinks(T V) {
  return {T(1) - T(2) * saturate(V), T(-1)};
}

// Gauss–Legendre nodes on [0, 1] for n = 1..4 (ascending) and their weights.
template <class T>
struct GaussLegendreSmall {
  static void get(int n, T* x, T* w) {
    switch (n) {
      case 1:
        x[0] = T(0.5), w[0] = T(1);
        break;
      case 2:
        x[0] = T(0.21132486540518711775), x[1] = T(0.78867513459481288225);
        w[0] = w[1] = T(0.5);
        break;
      case 3:
        x[0] = T(0.11270166537925831148), x[1] = T(0.5), x[2] = T(0.88729833462074168852);
        w[0] = w[2] = T(0.27777777777777777778), w[1] = T(0.44444444444444444444);
        break;
      default:
        x[0] = T(0.06943184420297371239), x[1] = T(0.33000947820757186760);
        x[2] = T(0.66999052179242813240), x[3] = T(0.93056815579702628761);
        w[0] = w[3] = T(0.17392742256872692869), w[1] = w[2] = T(0.32607257743127307131);
        break;
    }
  }
};

// M_area over a cap light, Lambertian receiver, of a point term M(N·L) that depends on N·L only: the
// z-integral ∫ M(z) z width(z) dz / ∫ z width(z) dz over [max(0, cos(θc + ρ)), cos(max(0, θc − ρ))], split at
// the two kinks (values outside the range are ignored) and at cos(ρ − θc), each panel by n-point
// Gauss–Legendre (n ∈ [1, 4]) after z = z0 + (z1 − z0)(3s² − 2s³), which removes the square-root ends of
// width(z). The denominator is the exact projected solid angle (cap_cone_projected_solid_angle). 4·n
// evaluations of M at most. Measured error against the exact reference: docs/area-lights.md §5. ρ = 0:
// M(N·L).
template <class T, class F>
T area_cap_lambert(F&& M, T n_dot_l, T rho, std::array<T, 2> kinks, int n = 3) {
  using namespace area_detail;
  rho = clean(rho, T(0), kPi<T> / 2);
  const T nl = clean(n_dot_l, T(-1), T(1));
  if (!(rho > T(0))) return M(nl);
  const T th = cap_theta(nl);
  const T den = cap_cone_projected_solid_angle(rho, th, kPi<T> / 2);
  if (!(den > T(0))) return T(0);
  // z range of the cap above the horizon; above cos(ρ − θc) a cap that contains n is a full circle.
  const T z_lo = std::max(T(0), std::cos(std::min(kPi<T>, th + rho)));
  const T z_hi = th < rho ? T(1) : std::cos(th - rho);
  if (!(z_hi > z_lo)) return T(0);
  T pts[5] = {z_lo, kinks[0], kinks[1], std::cos(std::abs(th - rho)), z_hi};
  for (int i = 1; i < 4; ++i)  // sort the interior points
    for (int j = i; j > 1 && pts[j - 1] > pts[j]; --j) std::swap(pts[j - 1], pts[j]);
  const T cos_rho = std::cos(rho), cos_tc = std::cos(th), sin_tc = std::sin(th);
  T x[4], w[4];
  n = std::clamp(n, 1, 4);
  GaussLegendreSmall<T>::get(n, x, w);
  T num = T(0), a = z_lo;
  for (int p = 1; p < 5; ++p) {
    const T b = pts[p] > z_lo ? std::min(pts[p], z_hi) : z_lo;
    if (!(b > a)) continue;
    const T h = b - a;
    for (int i = 0; i < n; ++i) {
      const T s = x[i];
      const T z = a + h * s * s * (T(3) - T(2) * s);
      num += w[i] * T(6) * h * s * (T(1) - s) * z * cap_azimuth_width(z, cos_rho, cos_tc, sin_tc) * M(z);
    }
    a = b;
  }
  return saturate(num / den);
}

// The area forms of the closed-form terms of occlusion/micro_shadowing.h (Lambertian receiver, cap light).
template <class T>
T brinck_maximov_2016_area_cap(T V, T n_dot_l, T rho, int n = 3) {
  return area_cap_lambert([V](T z) { return brinck_maximov_2016(V, z); }, n_dot_l, rho,
                          brinck_maximov_2016_kinks(V), n);
}
template <class T>
T chan_2018_area_cap(T V, T n_dot_l, T rho, int n = 3) {
  return area_cap_lambert([V](T z) { return chan_2018(V, z); }, n_dot_l, rho, chan_2018_kinks(V), n);
}
template <class T>
T part1_analytic_area_cap(T V, T n_dot_l, T rho, int n = 3) {
  return area_cap_lambert([V](T z) { return part1_analytic(V, z); }, n_dot_l, rho, part1_analytic_kinks(V),
                          n);
}

}  // namespace msh::ms
