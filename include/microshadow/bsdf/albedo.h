// Directional albedo E(wo) = ∫ f(wo, wi) (n·wi) dwi (RTR4 9.8) by deterministic quasi-Monte Carlo: an
// Owen-scrambled 2D Sobol sequence (fixed seed) drives the BRDF's own importance sampler, so the estimate is
// a pure function of (model, wo, n) — identical on every machine and thread count.
#pragma once

#include <microshadow/bsdf/brdf_model.h>
#include <microshadow/math/sampling.h>

#include <cstdint>

namespace msh::bsdf {

// Fixed scrambling seed of every albedo estimate in the project.
inline constexpr uint32_t kAlbedoSeed = 0x6a1bd0e5u;

// Σ weight(u_i) / n over the first n Sobol points. weight(u) returns f · cos / pdf for the sample drawn from
// u (zero for a failed sample). W may be a scalar or a colour; n should be a power of two (a (0,m,2)-net).
template <class T, class W, class WeightFn>
W qmc_integrate_2d(WeightFn&& weight, uint32_t n, uint32_t seed = kAlbedoSeed) {
  W sum{};
  for (uint32_t i = 0; i < n; ++i) sum += weight(sobol_2d<T>(i, seed));
  return sum * (T(1) / T(n));
}

// Directional albedo of a runtime model for view direction wo (local frame, wo.z > 0), with n samples of
// the model's own sampler (src/bsdf/albedo.cpp). Converges to ~1e-5 at n = 2^18 for the shipped models.
Rgbd directional_albedo(const BrdfModel& model, const Vec3d& wo, uint32_t n = 1u << 18);
// Same at N·V = mu, view in the xz plane (the isotropic models' albedo depends on mu only).
Rgbd directional_albedo(const BrdfModel& model, double mu, uint32_t n = 1u << 18);

}  // namespace msh::bsdf
