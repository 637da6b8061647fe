// ALU-only approximation (no texture, no samples) of the azimuth-mean diffuse micro-BRDF-aware
// micro-shadowing term for isotropic Smith-GGX: diffuse_aware_exact_azimuth_mean
// (reference/micro_shadowing_aware_exact.h), the run-time form of the diffuse-aware term of
// docs/micro-shadowing-aware.md (§3, Lambertian facets, the visibility-cone model of Zurita 2026, "Improving
// Direct Lighting Material Occlusion – Part 2"). Fit and measured error: docs/micro-shadowing-aware.md,
// "Run-time form of the diffuse-aware term".
//
// The form is the generic term's two-stage ALU fit (occlusion/micro_shadowing_fit.h) with one cone factor per
// direction the facet exchanges (θx = acos N·X, θc = acos c, c = sqrt(1 − V), S(z) = z / sqrt(1 + z²)):
//   f = Pcap · T_l · L_l · T_v · L_v,   Pcap = V / (V + (1 − V) q),   L_x = 1 + g_x (1 − V)(N·X − 1) / V,
//   T_x = (1 + S(tan(θc − θx)/a_x) / S(tan θc / a_x)) / (1 + S(cot θx / a_x)),
// one factor T_x L_x per direction because the reciprocal form's integrand is symmetric in l and v (the
// facet's cone must hold both). T_x is the generic fit's light factor: the probability that a facet with
// GGX-like slope spread a_x lies in the cone around x (the cumulative slope distribution, Walter et al. 2007,
// "Microfacet Models for Refraction through Rough Surfaces"), pinned to 0 at θx = 2θc. a_x, q, g_x are cubic
// forms in (r, cos θc, w) through exp2 for a and q, with w_x = N·X / sqrt(N·X² + α²(1 − N·X²)) (the z of the
// stretched direction, Heitz 2018, "Sampling the GGX Distribution of Visible Normals"): a_l and g_l take
// w_v (the facets are drawn from the VNDF of v), a_v and g_v take w_l (the same coefficients: reciprocity),
// q takes w_l w_v. Only the Reciprocal form (the one the renderer's `aware` and `aware-alu` use) has a fit;
// the Flux form has none yet (its run-time form is the estimator).
// Exact properties: V = 1 gives 1; V = 0 gives 0; 2V + N·L < 1 and 2V + N·V < 1 give exactly 0 (exact_zero;
// the cone region is a subset of the generic term's, for l and, by reciprocity, for v); the value is in
// [0, 1]; symmetric in N·L and N·V. Coefficients: tools/research/fit_micro_shadowing_aware.py on the exact
// term (data: `microshadow plot micro-shadowing-fit --term diffuse-aware`), started from the generic term's
// two-stage coefficients.
#pragma once

#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace msh::micro_shadowing {

// Three cubic forms (a, q, g) in (r, cos θc, w), 20 coefficients each, in fit_basis::fit_cubic's order.
// Fitted over V ∈ [0,1], N·L, N·V ∈ (0,1], r ∈ [0.1, 1] (tools/research/fit_micro_shadowing_aware.py).
inline constexpr std::array<double, 60> kDiffuseAwareAluReciprocal = {
    4.7413,   -9.98672, 5.60447,  2.29771,  10.7242,   14.5875,  -7.79898, -27.395,  4.65937,   -5.50467,
    1.63791,  -6.25831, 1.13435,  8.15713,  -19.3248,  2.49487,  -3.68374, 13.559,   -5.30555,  15.5449,
    13.9158,  -21.439,  -1.45917, 7.31156,  16.3105,   -56.2036, -6.02686, 14.636,   -20.0127,  20.4968,
    -3.89923, 47.3793,  -6.68909, -11.7598, 4.66624,   19.3493,  -37.9807, 9.45357,  18.7872,   -4.47527,
    -5.54821, -3.8796,  22.6404,  3.55435,  -0.856421, -33.7625, -4.80667, 25.9747,  -21.5183,  4.97385,
    3.87288,  25.9899,  2.75697,  -10.9443, 4.71002,   -28.2844, -15.3595, -1.21187, -0.210605, 32.2277};

namespace aware_fit_terms {
// T_x · L_x of one direction (both in one factor; 0 at θx ≥ 2θc).
template <class T>
T cone_factor(T vis, T c, T s, T n_dot_x, T a, T g) {
  const T a2 = a * a, one_minus_a2 = T(1) - a2;
  const T nx2 = n_dot_x * n_dot_x, sx = std::sqrt(T(1) - nx2);
  const T d = s * n_dot_x - c * sx;  // sin(θc − θx)
  // S(tan x / a) = sin x / sqrt(a² + (1 − a²) sin²x), |x| < π/2; 1 / S(tan θc / a) finite at V = 0.
  const T inv_st = std::sqrt(a2 + one_minus_a2 * vis) / std::max(s, T(1e-6));
  const T p1 = T(1) + d / std::sqrt(a2 + one_minus_a2 * (d * d)) * inv_st;
  const T p2 = T(1) + n_dot_x / std::sqrt(a2 + one_minus_a2 * nx2);
  return p1 * (vis + g * (T(1) - vis) * (n_dot_x - T(1))) / (vis * p2);
}
template <class T>
T stretched_z(T n_dot_x, T alpha) {
  const T n2 = n_dot_x * n_dot_x;
  return n_dot_x / std::sqrt(n2 + alpha * alpha * (T(1) - n2));  // > 0 denominator: α ≥ 1e-4
}
}  // namespace aware_fit_terms

// ALU approximation of diffuse_aware_exact_azimuth_mean(V, r², N·L, N·V, DiffuseAwareForm::Reciprocal)
// (six cubic forms of 19 fma, 3 exp2, 12 sqrt, 11 divisions). Domain: V, N·L, N·V ∈ [0,1], perceptual
// roughness r ∈ [0,1] (fitted on [0.1, 1], extrapolated below; r < 0.01 is evaluated at 0.01). Inputs are
// clamped to [0,1] and NaN maps to 0 (roughness: 0.01), as every term in micro_shadowing.h, so the result is
// finite and in [0,1] for any input; N·L = 0 gives 0. Measured error: docs/micro-shadowing-aware.md,
// "Run-time form of the diffuse-aware term".
template <class T>
T diffuse_aware_alu(T V, T n_dot_l, T n_dot_v, T roughness) {
  const T vis = saturate(V), nl = saturate(n_dot_l), nv = saturate(n_dot_v);
  const T r = fit_basis::fit_roughness(roughness);
  // N·L = 0 (and NaN): 0 as the exact term (no light); N·V = 0 is finite (the exact term's N·V → 0 limit).
  if (!(nl > T(0)) || exact_zero(vis, nl) || exact_zero(vis, nv) || !(vis > T(0))) return T(0);
  if (!(vis < T(1))) return T(1);
  const double* p = kDiffuseAwareAluReciprocal.data();
  const T one_minus_v = T(1) - vis;
  const T c = std::sqrt(one_minus_v), s = std::sqrt(vis);
  const T alpha = r * r;
  const T wl = aware_fit_terms::stretched_z(nl, alpha), wv = aware_fit_terms::stretched_z(nv, alpha);
  using fit_basis::fit_cubic;
  const T a_l = alpha * std::exp2(fit_cubic(p, r, c, wv)), a_v = alpha * std::exp2(fit_cubic(p, r, c, wl));
  const T q = sqr(alpha) * std::exp2(fit_cubic(p + 20, r, c, wl * wv));
  const T fl = aware_fit_terms::cone_factor(vis, c, s, nl, a_l, fit_cubic(p + 40, r, c, wv));
  const T fv = aware_fit_terms::cone_factor(vis, c, s, nv, a_v, fit_cubic(p + 40, r, c, wl));
  const T f = fl * fv * (vis / (vis + one_minus_v * q));
  return std::clamp(f, T(0), T(1));
}

}  // namespace msh::micro_shadowing
