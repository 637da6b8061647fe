// Roughness parameterizations (docs/theory.md §1; RTR4 §9.8.1). The user-facing roughness r ∈ [0, 1] maps to
// the GGX/Beckmann α = r² (Burley 2012; roughness_to_alpha in ggx.h); anisotropy by Disney (9.54) or
// Imageworks (9.55); Blinn-Phong exponent ↔ Beckmann α in blinn_phong.h.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>

#include <cmath>

namespace msh {

// Disney anisotropy (Burley 2012, 9.54): aspect = sqrt(1 − 0.9 k), αx = r²/aspect, αy = r² aspect. r, k ∈
// [0,1] (clamped); the 0.9 limits the aspect ratio αx/αy to 10:1.
template <class T>
void alpha_disney_anisotropic(T r, T k_aniso, T& alpha_x, T& alpha_y) {
  const T rr = saturate(r), aspect = std::sqrt(T(1) - T(0.9) * saturate(k_aniso));
  alpha_x = rr * rr / aspect;
  alpha_y = rr * rr * aspect;
}

// Imageworks anisotropy (Kulla & Conty 2017, 9.55): αx = r²(1 + k), αy = r²(1 − k). r ∈ [0,1], k ∈ [−1, 1]
// (clamped); k = ±1 gives a zero α, which the NDF classes clamp to their kMinAlpha.
template <class T>
void alpha_imageworks_anisotropic(T r, T k_aniso, T& alpha_x, T& alpha_y) {
  const T rr = saturate(r), k = clamp(k_aniso, T(-1), T(1));
  alpha_x = rr * rr * (T(1) + k);
  alpha_y = rr * rr * (T(1) - k);
}

// Inverse of roughness_to_alpha: r = sqrt(α), α clamped to [0, 1].
template <class T>
T alpha_to_roughness(T alpha) {
  return std::sqrt(saturate(alpha));
}

}  // namespace msh
