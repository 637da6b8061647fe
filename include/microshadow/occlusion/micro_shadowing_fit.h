// ALU-only approximations (no texture) of the azimuth-mean generic VNDF micro-shadowing term for isotropic
// Smith-GGX: the value a LUT texel stores, generic_vndf_exact_azimuth_mean
// (reference/micro_shadowing_exact.h), i.e. the mean over the relative azimuth φ ∈ [0, π] of P[n·m > c ∧ m·l
// > c] / P[n·m > 0 ∧ m·l > 0], m ~ VNDF(v, α = r²), c = cos θc = sqrt(1 − V). Fit, operation counts and
// measured error: docs/micro-shadowing.md, "ALU-only approximation".
//
// Both share one form (θl = acos N·L; a and q are fitted functions of roughness, V and N·V):
//   f = Pcap · P1 · L / P2,   Pcap = V / (V + (1 − V) q),   L = 1 + g (1 − V) (N·L − 1) / V,
//   P1 = 1 + S(tan(θc − θl) / a),   P2 = 1 + S(cot θl / a),   S(z) = z / sqrt(1 + z²).
// (1 + S(x/a))/2 is the cumulative distribution of one component of the GGX slope (its marginal density is
// 1/(2a(1 + x²/a²)^{3/2}); Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces").
// For a small slope spread a microfacet lies in the light's cone m·l > c when its slope toward l exceeds
// tan(θl − θc), and it faces l (the conditioning m·l > 0) when that slope exceeds tan(θl − π/2) = −cot θl:
// P1/P2 is their ratio. Pcap is the probability of the normal's cone n·m > c, which for v = n is exactly
// tan²θc / (tan²θc + α²) (q = α²). L is a linear correction in N·L for the overlap of the two cones at large
// roughness (the exact term is 0 at θl = 2θc). Exact properties of both: α → 0 is the reference step
// N·L > cos θc; V = 0 gives 0; V = 1 gives 1; 2V + N·L < 1 gives exactly 0 (exact_zero); the value is in [0,
// 1].
//
// * generic_vndf_alu (one call, 40 operations): a = α (p0 + p1 r + p2 V + p3 k), q = a² (p4 + p5 V + p6 k),
//   g = p7 + p8 r, k = N·V / (N·V + α).
// * generic_vndf_alu_pixel + generic_vndf_alu_light (more accurate, two stages): everything that does not
//   depend on N·L is computed once per pixel; each light then costs 23 operations. a = α 2^{Q_a}, q = a²
//   2^{Q_q}, g = Q_g, with Q cubic forms in (r, cos θc, w_z), w_z = N·V / sqrt(N·V² + α²(1 − N·V²)) (the
//   z of the stretched view direction, Heitz 2018, "Sampling the GGX Distribution of Visible Normals"), and
//   the light's cone term pinned to 0 at θl = 2θc: P1 = 1 + S(tan(θc − θl)/a) / S(tan θc / a).
// Coefficients: tools/research/fit_micro_shadowing.py on the exact term (data: `microshadow plot
// micro-shadowing-fit`).
#pragma once

#include <microshadow/occlusion/micro_shadowing.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace msh::micro_shadowing {

// Fitted over V ∈ [0,1], N·L ∈ (0,1], N·V ∈ (0,1], r ∈ [0.1, 1] (tools/research/fit_micro_shadowing.py).
inline constexpr std::array<double, 9> kGenericVndfAluFast = {
    1.39397, -0.796604, 0.332797, -0.467188, 6.28222, 0.384725, -6.03135, -0.00902245, 0.555965};
// Three cubic forms (a, q, g) in (x, y, z) = (r, cos θc, w_z), 20 coefficients each, in the order
// 1, x, y, z, x², y², z², xy, xz, yz, x³, y³, z³, x²y, x²z, y²x, y²z, z²x, z²y, xyz.
inline constexpr std::array<double, 60> kGenericVndfAluTwoStage = {
    1.0217,    -2.9439,  2.9061,    -0.670065, 0.471315,  -3.2708,  -0.396618,  1.08175,  1.66018,  -2.8354,
    0.396493,  0.342605, 0.0423424, -0.427877, -0.437596, 0.634181, 2.39379,    1.05468,  0.407305, -1.61536,
    11.644,    -9.6416,  -26.1472,  -0.739559, 7.56448,   26.5267,  -4.27069,   6.01259,  0.966796, 8.15792,
    -2.27743,  -9.77157, -1.07619,  -0.05405,  -2.87783,  -1.88619, -6.78087,   2.61554,  3.37417,  -1.3212,
    -0.9204,   3.81808,  2.24386,   0.55774,   1.04404,   -2.27448, 0.640291,   -5.48228, -3.36957, -0.812951,
    -0.682536, 1.15732,  -0.665058, -0.962631, 0.460372,  2.19737,  -0.0851906, 0.488589, 0.139112, 2.98356};

namespace fit_basis {
// Roughness clamped to [0.01, 1], so α = r² ≥ 1e-4 (GGX<T>::kMinAlpha); NaN → 0.01.
template <class T>
T fit_roughness(T r) {
  return std::isnan(r) ? T(0.01) : std::clamp(r, T(0.01), T(1));
}
// The cubic above, grouped as the shaders evaluate it (19 fma).
template <class T>
T fit_cubic(const double* p, T x, T y, T z) {
  const T px = T(p[1]) + x * (T(p[4]) + T(p[10]) * x + T(p[13]) * y + T(p[14]) * z) +
               y * (T(p[7]) + T(p[15]) * y + T(p[19]) * z) + z * (T(p[8]) + T(p[17]) * z);
  const T py = T(p[2]) + y * (T(p[5]) + T(p[11]) * y + T(p[16]) * z) + z * (T(p[9]) + T(p[18]) * z);
  const T pz = T(p[3]) + z * (T(p[6]) + T(p[12]) * z);
  return T(p[0]) + x * px + y * py + z * pz;
}
}  // namespace fit_basis

// One-call approximation of generic_vndf_exact_azimuth_mean(V, r², N·L, N·V) (40 arithmetic operations in
// the shaders; docs/micro-shadowing.md). Domain: V, N·L, N·V ∈ [0,1], perceptual roughness r ∈ [0,1] (fitted
// on [0.1, 1]; r < 0.01 is evaluated at 0.01, already the reference step to < 1e-3 away from it). Inputs are
// clamped to [0,1] and NaN maps to 0 (roughness: 0.01), as every term in micro_shadowing.h, so the result is
// finite and in [0,1] for any input. Measured error vs the exact term: docs/micro-shadowing.md.
template <class T>
T generic_vndf_alu(T V, T n_dot_l, T n_dot_v, T roughness) {
  const T vis = saturate(V), nl = saturate(n_dot_l), nv = saturate(n_dot_v);
  const T r = fit_basis::fit_roughness(roughness);
  if (exact_zero(vis, nl)) return T(0);
  const auto& p = kGenericVndfAluFast;
  const T one_minus_v = T(1) - vis;
  const T c = std::sqrt(one_minus_v), s = std::sqrt(vis);  // cos θc, sin θc
  const T nl2 = nl * nl, sl = std::sqrt(T(1) - nl2);       // cos²θl, sin θl
  const T d = s * nl - c * sl;                             // sin(θc − θl); cos²(θc − θl) = 1 − d²
  const T alpha = r * r;
  const T k = nv / (nv + alpha);
  const T a = alpha * (T(p[0]) + T(p[1]) * r + T(p[2]) * vis + T(p[3]) * k);
  const T a2 = a * a, one_minus_a2 = T(1) - a2;
  const T q = a2 * (T(p[4]) + T(p[5]) * vis + T(p[6]) * k);
  const T g = (T(p[7]) + T(p[8]) * r) * one_minus_v;
  // S(tan x / a) = sin x / sqrt(sin²x + a² cos²x) = sin x / sqrt(a² + (1 − a²) sin²x), |x| < π/2.
  const T p1 = T(1) + d / std::sqrt(a2 + one_minus_a2 * (d * d));  // 1 + S(tan(θc − θl) / a)
  const T p2 = T(1) + nl / std::sqrt(a2 + one_minus_a2 * nl2);     // 1 + S(cot θl / a); equals p1 at V = 1
  const T f = p1 * (vis + g * (nl - T(1))) / ((vis + one_minus_v * q) * p2);  // V·L = V + g(1 − V)(N·L − 1)
  return std::clamp(f, T(0), T(1));
}

// Per-pixel state of the two-stage approximation (everything that does not depend on N·L).
template <class T>
struct GenericVndfAluPixel {
  T vis, c, s;  // V, cos θc, sin θc
  T a2, one_minus_a2;
  T inv_st;  // 1 / S(tan θc / a): pins the light's cone term to 0 at θl = 2θc
  T g;       // g (1 − V)
  T den;     // V + (1 − V) q
};

// Stage 1, once per pixel. Domain and input handling as generic_vndf_alu.
template <class T>
GenericVndfAluPixel<T> generic_vndf_alu_pixel(T V, T n_dot_v, T roughness) {
  const T vis = saturate(V), nv = saturate(n_dot_v), r = fit_basis::fit_roughness(roughness);
  const double* p = kGenericVndfAluTwoStage.data();
  const T one_minus_v = T(1) - vis;
  const T c = std::sqrt(one_minus_v), s = std::sqrt(vis);
  const T alpha = r * r, nv2 = nv * nv;
  const T wz = nv / std::sqrt(nv2 + alpha * alpha * (T(1) - nv2));  // > 0 denominator: α ≥ 1e-4
  const T a = alpha * std::exp2(fit_basis::fit_cubic(p, r, c, wz));
  const T a2 = a * a, one_minus_a2 = T(1) - a2;
  const T q = a2 * std::exp2(fit_basis::fit_cubic(p + 20, r, c, wz));
  const T g = fit_basis::fit_cubic(p + 40, r, c, wz) * one_minus_v;
  const T inv_st = std::sqrt(a2 + one_minus_a2 * vis) / std::max(s, T(1e-6));  // V = 0: finite (d = 0 there)
  return {vis, c, s, a2, one_minus_a2, inv_st, g, vis + one_minus_v * q};
}

// Stage 2, per light: the approximation of generic_vndf_exact_azimuth_mean(V, r², N·L, N·V). N·L is clamped
// to [0,1] (NaN → 0); finite and in [0,1] for any input.
template <class T>
T generic_vndf_alu_light(const GenericVndfAluPixel<T>& px, T n_dot_l) {
  const T nl = saturate(n_dot_l);
  if (exact_zero(px.vis, nl)) return T(0);
  if (!(px.vis < T(1))) return T(1);
  const T nl2 = nl * nl, sl = std::sqrt(T(1) - nl2);
  const T d = px.s * nl - px.c * sl;
  const T p1 = T(1) + d / std::sqrt(px.a2 + px.one_minus_a2 * (d * d)) * px.inv_st;
  const T p2 = T(1) + nl / std::sqrt(px.a2 + px.one_minus_a2 * nl2);
  const T f = p1 * (px.vis + px.g * (nl - T(1))) / (px.den * p2);
  return std::clamp(f, T(0), T(1));
}

// Both stages in one call (convenience; an engine calls generic_vndf_alu_pixel once per pixel).
template <class T>
T generic_vndf_alu_two_stage(T V, T n_dot_l, T n_dot_v, T roughness) {
  return generic_vndf_alu_light(generic_vndf_alu_pixel(V, n_dot_v, roughness), n_dot_l);
}

}  // namespace msh::micro_shadowing
