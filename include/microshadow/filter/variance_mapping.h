// Variance mapping (RTR4 §9.13.1; Hill 2011/2012 "Specular Showdown in the Wild West", Lazarov 2011 Call of
// Duty: Black Ops): when building the mip chain, the normal-map variance lost by averaging is converted to
// roughness: roughness → variance, add the normal variance, variance → roughness. Here in slope space with
// the Beckmann mapping shared by LEAN/CLEAN (lean.h): per-axis slope variance σ² = α²/2, α = perceptual
// roughness². Header-only, templated on the scalar, no I/O.
#pragma once

#include <microshadow/filter/lean.h>
#include <microshadow/math/vec.h>

namespace msh::filter {

// The GGX α ↔ slope-variance convention, as the total (two-axis) slope variance per α²:
//  - kBeckmannEquivalent = 1: GGX α treated as the Beckmann α (per-axis variance α²/2), the common practice
//  RTR4
//    §9.13.1 describes for Toksvig/variance mapping with GGX (and LEAN/CLEAN's Beckmann lobes);
//  - kConty2019 = 2: σ² = 2α² (Conty Estevez et al. 2019 §12.3.1, occlusion/bump_terminator.h ggx_variance):
//    their fit of GGX's (infinite) variance with the tail ignored; a normal-map variance then widens α half
//    as much.
inline constexpr double kBeckmannEquivalent = 1.0;
inline constexpr double kConty2019 = 2.0;

// Perceptual roughness r (docs/theory.md §1: α = r²) → per-axis slope variance k α²/2. r clamped to [0,1].
template <class T>
T roughness_to_slope_variance(T r, T k = T(kBeckmannEquivalent)) {
  const T a = saturate(r);
  return T(0.5) * k * sqr(a * a);
}
// Inverse: α = sqrt(2σ²/k), r = sqrt(α), clamped to [0,1] (α > 1 is outside the parameter range). k > 0.
template <class T>
T slope_variance_to_roughness(T var, T k = T(kBeckmannEquivalent)) {
  const T a = std::min(std::sqrt(T(2) * std::max(var, T(0)) / std::max(k, T(1e-6))), T(1));
  return std::sqrt(a);
}
// Roughness widened by an extra per-axis slope variance (e.g. the normal-map variance of a mip footprint).
template <class T>
T roughness_add_variance(T r, T var_normal, T k = T(kBeckmannEquivalent)) {
  return slope_variance_to_roughness(roughness_to_slope_variance(r, k) + std::max(var_normal, T(0)), k);
}

// Expected mean of the sample variance of N i.i.d. values of variance σ²: σ² (1 − 1/N) — the variance a box
// filter over N texels recovers (used by tests and the demo to predict mip roughness).
template <class T>
T expected_box_variance(T var, T n) {
  return n > T(0) ? var * (T(1) - T(1) / n) : T(0);
}

}  // namespace msh::filter
