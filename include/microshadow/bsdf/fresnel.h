// Fresnel reflectance: Schlick (RTR4 9.16), generalized Schlick (9.18), exact dielectric and conductor
// (Born & Wolf; pbrt-v4 §9.3), and their cosine-weighted hemispherical averages F̄ (9.58–9.60).
// cos_i is the cosine between the incident direction and the (micro)normal: n·l for a flat mirror, h·l in a
// microfacet BRDF. Header-only, templated on the scalar; every function is finite for every finite input.
#pragma once

#include <microshadow/math/color.h>
#include <microshadow/math/quadrature.h>
#include <microshadow/math/vec.h>

#include <complex>

namespace msh::bsdf {

// (1 − cos)⁵ with cos clamped to [0,1]: the Schlick weight.
template <class T>
T schlick_weight(T cos_i) {
  const T m = T(1) - saturate(cos_i);
  const T m2 = m * m;
  return m2 * m2 * m;
}

// Schlick 1994 (RTR4 9.16): F = F0 + (1 − F0)(1 − cos⁺)⁵. Domain: F0 in [0,1]; any cos (clamped).
template <class T, class C>
C fresnel_schlick(const C& f0, T cos_i) {
  return f0 + (C(T(1)) - f0) * schlick_weight(cos_i);
}

// Generalized Schlick (RTR4 9.18, Kulla & Conty 2017): F = F0 + (F90 − F0)(1 − cos⁺)^(1/p). p = 1/5 is 9.16.
// Domain: p > 0 (smaller p → sharper rise at grazing); p ≤ 0 is clamped to a tiny positive value.
template <class T, class C>
C fresnel_schlick_generalized(const C& f0, const C& f90, T p, T cos_i) {
  const T q = T(1) / std::max(p, T(1e-6));
  const T w = std::pow(T(1) - saturate(cos_i), q);
  return f0 + (f90 - f0) * w;
}

// Exact unpolarized Fresnel reflectance of a dielectric interface (Born & Wolf; pbrt-v4 FrDielectric).
// eta = n_transmitted / n_incident. cos_i < 0 means the ray arrives from the other side (eta is inverted).
// Returns 1 under total internal reflection. eta ≤ 0 is clamped to a tiny positive value.
template <class T>
T fresnel_dielectric(T cos_i, T eta) {
  cos_i = clamp(cos_i, T(-1), T(1));
  eta = std::max(eta, T(1e-6));
  if (cos_i < T(0)) {
    eta = T(1) / eta;
    cos_i = -cos_i;
  }
  const T sin2_t = (T(1) - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= T(1)) return T(1);
  const T cos_t = safe_sqrt(T(1) - sin2_t);
  const T r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const T r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return T(0.5) * (r_parl * r_parl + r_perp * r_perp);
}

// Exact unpolarized reflectance of a conductor with complex relative IOR eta + i k (pbrt-v4 FrComplex).
// Domain: cos_i in [0,1] (clamped), eta > 0, k ≥ 0. At normal incidence ((η−1)² + k²)/((η+1)² + k²).
template <class T>
T fresnel_conductor(T cos_i, T eta, T k) {
  using C = std::complex<T>;
  cos_i = saturate(cos_i);
  const C e(std::max(eta, T(1e-6)), std::max(k, T(0)));
  const T sin2_i = T(1) - cos_i * cos_i;
  const C sin2_t = sin2_i / (e * e);
  const C cos_t = std::sqrt(C(T(1)) - sin2_t);
  const C r_parl = (e * cos_i - cos_t) / (e * cos_i + cos_t);
  const C r_perp = (cos_i - e * cos_t) / (cos_i + e * cos_t);
  const T r = T(0.5) * (std::norm(r_parl) + std::norm(r_perp));
  return std::isfinite(r) ? std::min(r, T(1)) : T(1);
}
template <class T>
Rgb<T> fresnel_conductor(T cos_i, const Rgb<T>& eta, const Rgb<T>& k) {
  return {fresnel_conductor(cos_i, eta.r, k.r), fresnel_conductor(cos_i, eta.g, k.g),
          fresnel_conductor(cos_i, eta.b, k.b)};
}

// Normal-incidence reflectance of a dielectric, ((η − 1)/(η + 1))² (RTR4 9.17).
template <class T>
T f0_from_ior(T eta) {
  return sqr((eta - T(1)) / (eta + T(1)));
}

// ---- Cosine-weighted hemispherical averages F̄ = 2 ∫₀¹ F(μ) μ dμ (RTR4 9.58).

// Closed form for the generalized Schlick form (RTR4 9.59, Kulla & Conty 2017).
template <class T, class C>
C fresnel_average_schlick_generalized(const C& f0, const C& f90, T p) {
  p = std::max(p, T(1e-6));
  const T den = T(2) * p * p + T(3) * p + T(1);
  return (f90 * (T(2) * p * p) + f0 * (T(3) * p + T(1))) / den;
}
// Closed form for Schlick (RTR4 9.60): 20/21 F0 + 1/21.
template <class T, class C>
C fresnel_average_schlick(const C& f0) {
  return f0 * (T(20) / T(21)) + C(T(1) / T(21));
}
// Numerical 9.58 (64-point Gauss-Legendre on μ; the integrand is smooth except at TIR, where the kink is
// resolved to ~1e-5) for the exact dielectric, external side (eta = n_t / n_i).
template <class T>
T fresnel_average_dielectric(T eta) {
  return gauss_legendre_01<T>(64, [&](T mu) { return T(2) * mu * fresnel_dielectric(mu, eta); });
}
// Numerical 9.58 for a conductor (smooth integrand; 64-point Gauss-Legendre).
template <class T>
T fresnel_average_conductor(T eta, T k) {
  return gauss_legendre_01<T>(64, [&](T mu) { return T(2) * mu * fresnel_conductor(mu, eta, k); });
}

}  // namespace msh::bsdf
