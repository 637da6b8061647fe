// Variance mapping (RTR4 §9.13.1; Hill 2011/2012 "Specular Showdown in the Wild West", Lazarov 2011 Call of
// Duty: Black Ops): when building the mip chain, the normal-map variance lost by averaging is converted to
// roughness: roughness → variance, add the normal variance, variance → roughness. Here in slope space with
// the Beckmann mapping shared by LEAN/CLEAN (lean.h): per-axis slope variance σ² = α²/2, α = perceptual
// roughness². Header-only, templated on the scalar, no I/O.
#pragma once

#include <microshadow/filter/lean.h>
#include <microshadow/math/vec.h>

namespace msh::filter {

// Perceptual roughness r (REFERENCE §1: α = r²) → per-axis slope variance α²/2 = r⁴/2. r clamped to [0,1].
template <class T>
T roughness_to_slope_variance(T r) {
  const T a = saturate(r);
  return T(0.5) * sqr(a * a);
}
// Inverse: α = sqrt(2σ²), r = sqrt(α), clamped to [0,1] (α > 1 is outside the parameter range).
template <class T>
T slope_variance_to_roughness(T var) {
  const T a = std::min(std::sqrt(T(2) * std::max(var, T(0))), T(1));
  return std::sqrt(a);
}
// Roughness widened by an extra per-axis slope variance (e.g. the normal-map variance of a mip footprint).
template <class T>
T roughness_add_variance(T r, T var_normal) {
  return slope_variance_to_roughness(roughness_to_slope_variance(r) + std::max(var_normal, T(0)));
}

// Expected mean of the sample variance of N i.i.d. values of variance σ²: σ² (1 − 1/N) — the variance a box
// filter over N texels recovers (used by tests and the demo to predict mip roughness).
template <class T>
T expected_box_variance(T var, T n) {
  return n > T(0) ? var * (T(1) - T(1) / n) : T(0);
}

}  // namespace msh::filter
