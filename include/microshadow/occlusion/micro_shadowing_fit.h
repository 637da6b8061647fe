// ALU-only approximation (no texture) of the azimuth-mean generic VNDF micro-shadowing term for isotropic
// Smith-GGX: the value a LUT texel stores, i.e. generic_vndf_exact_azimuth_mean (micro_shadowing.h), the mean
// over the relative azimuth φ ∈ [0, π] of P[n·m > c ∧ m·l > c] / P[n·m > 0 ∧ m·l > 0], m ~ VNDF(v, α = r²),
// c = sqrt(1 − V). Form, fit and measured error: docs/micro-shadowing.md, "ALU-only approximation".
//
// Form (θc = acos c is the visibility cone's half-angle, θl = acos N·L):
//   f = Pcap · (1 + S(tan(θc − θl) / a)) / (1 + S(cot θl / a)),   S(z) = z / sqrt(1 + z²),
//   Pcap = V / (V + (1 − V) q).
// S is the cumulative distribution of the GGX slope along one axis (Walter et al. 2007, "Microfacet Models
// for Refraction through Rough Surfaces"): 1D slopes are distributed as 1/(2a(1 + x²/a²)^{3/2}), whose CDF is
// (1 + S(x/a))/2. For small roughness a microfacet passes m·l > c when its slope toward l exceeds
// tan(θl − θc), and the conditioning on m·l > 0 is the same CDF at tan(θl − π/2); their ratio gives the
// numerator/denominator pair above (exact for the denominator at N·V = 1). Pcap is the probability of the
// n-cone: for v = n it is exactly tan²θc / (tan²θc + α²), i.e. q = α². The effective width a and q are
// fitted: a = α (p0 + p1 r + p2 V + p3 k), q = a² (p4 + p5 r + p6 V + p7 k), k = N·V / (N·V + α), by
// scripts/fit_micro_shadowing.py on the exact term (training data: `plot micro-shadowing-fit`).
// Exact properties: α → 0 gives the reference step N·L > cos θc; V = 0 gives 0; V = 1 gives 1 (S terms equal,
// Pcap = 1); 2V + N·L < 1 gives 0 (exact_zero); the value is in [0, 1].
#pragma once

#include <microshadow/occlusion/micro_shadowing.h>

#include <array>
#include <cmath>

namespace msh::ms {

// Coefficients p0..p7 of generic_vndf_alu (fitted over V ∈ [0,1], N·L ∈ (0,1], N·V ∈ (0,1], r ∈ [0.1, 1];
// scripts/fit_micro_shadowing.py). Both linear forms stay positive over the whole input cube (checked there).
inline constexpr std::array<double, 8> kGenericVndfAluCoeffs = {1.16147, -0.735958, 0.39027,    -0.260151,
                                                                12.5356, -3.04389,  -0.0466582, -10.5623};

// ALU-only approximation of generic_vndf_exact_azimuth_mean(V, r², N·L, N·V) (39 arithmetic operations in
// the shaders, counted in docs/micro-shadowing.md). Domain: V, N·L, N·V ∈ [0,1] and perceptual roughness
// r ∈ [0,1] (fitted on [0.1, 1]; below 0.1 it tends to the reference step, its α → 0 limit). Inputs are
// clamped to [0,1] and NaN maps to 0 (saturate semantics, as every term in micro_shadowing.h), so the
// result is finite and in [0,1] for any input. Measured error vs the exact term: docs/micro-shadowing.md.
template <class T>
T generic_vndf_alu(T V, T n_dot_l, T n_dot_v, T roughness) {
  const T vis = saturate(V), nl = saturate(n_dot_l), nv = saturate(n_dot_v), r = saturate(roughness);
  if (exact_zero(vis, nl)) return T(0);
  const auto& p = kGenericVndfAluCoeffs;
  const T one_minus_v = T(1) - vis;
  const T c = std::sqrt(one_minus_v), s = std::sqrt(vis);  // cos θc, sin θc
  const T nl2 = nl * nl, sl = std::sqrt(T(1) - nl2);       // cos²θl, sin θl
  const T d = s * nl - c * sl;                             // sin(θc − θl); cos²(θc − θl) = 1 − d²
  const T alpha = std::max(r * r, T(1e-4));                // GGX<T>::kMinAlpha
  const T k = nv / (nv + alpha);
  const T a = alpha * (T(p[0]) + T(p[1]) * r + T(p[2]) * vis + T(p[3]) * k);
  const T a2 = a * a, one_minus_a2 = T(1) - a2;
  const T q = a2 * (T(p[4]) + T(p[5]) * r + T(p[6]) * vis + T(p[7]) * k);
  // S(tan x / a) = sin x / sqrt(sin²x + a² cos²x) = sin x / sqrt(a² + (1 − a²) sin²x), for |x| < π/2.
  const T p1 = T(1) + d / std::sqrt(a2 + one_minus_a2 * (d * d));  // 1 + S(tan(θc − θl) / a)
  const T p2 = T(1) + nl / std::sqrt(a2 + one_minus_a2 * nl2);     // 1 + S(cot θl / a), ≥ 1
  const T f = vis * p1 / ((vis + one_minus_v * q) * p2);
  return std::min(T(1), std::max(T(0), f));  // [0, 1] up to rounding already
}

}  // namespace msh::ms
