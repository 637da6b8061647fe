// Toksvig 2005, "Mipmapping Normal Maps" (JGT 10(3)); RTR4 eq. 9.76: the length |n̄| of an average of unit
// normals shrinks as their spread grows; the Blinn-Phong exponent is reduced accordingly:
//   α'_p = |n̄| α_p / (|n̄| + α_p (1 − |n̄|)).
// GGX mapping (RTR4 §9.13.1, "fairly common ... α_p = 2 α_g⁻² − 2", the Walter et al. 2007 Beckmann
// equivalence applied to GGX). Header-only, templated on the scalar, no I/O.
#pragma once

#include <microshadow/math/vec.h>

namespace msh::filter {

// RTR4 9.76. Domain: α_p ≥ 0, |n̄| in [0,1] (clamped). |n̄| = 1 returns α_p; |n̄| = 0 returns 0 (isotropic).
template <class T>
T toksvig_exponent(T alpha_p, T len) {
  len = saturate(len);
  alpha_p = std::max(alpha_p, T(0));
  const T den = len + alpha_p * (T(1) - len);
  return den > T(0) ? len * alpha_p / den : T(0);
}

// Walter et al. 2007: Blinn-Phong exponent ↔ Beckmann (used for GGX) α: α_p = 2/α² − 2, α = sqrt(2/(α_p +
// 2)). α is clamped to [1e-4, 1] (α = 1 ↔ α_p = 0).
template <class T>
T blinn_phong_exponent_from_alpha(T alpha) {
  const T a = clamp(alpha, T(1e-4), T(1));
  return T(2) / (a * a) - T(2);
}
template <class T>
T alpha_from_blinn_phong_exponent(T alpha_p) {
  return std::sqrt(T(2) / (std::max(alpha_p, T(0)) + T(2)));
}

// 9.76 in the GGX mapping: the widened α for a texel whose averaged unit normal has length |n̄|. In [α, 1].
template <class T>
T toksvig_ggx_alpha(T alpha, T len) {
  const T a = alpha_from_blinn_phong_exponent(toksvig_exponent(blinn_phong_exponent_from_alpha(alpha), len));
  return std::max(a, clamp(alpha, T(1e-4), T(1)));
}

// Toksvig's variance estimate behind 9.76: σ² = (1 − |n̄|)/|n̄| (then α'_p = α_p / (1 + α_p σ²)). |n̄| ≤ 0 →
// large.
template <class T>
T toksvig_variance(T len) {
  len = saturate(len);
  return len > T(0) ? (T(1) - len) / len : T(1e30);
}

}  // namespace msh::filter
