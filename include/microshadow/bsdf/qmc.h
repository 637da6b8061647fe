// Deterministic quasi-Monte Carlo integration over [0, 1)² with the project's fixed scrambling seed: an
// Owen-scrambled 2D Sobol sequence (math/sampling.h), so every estimate is a pure function of its inputs and
// n — identical on every machine and thread count. Header-only; used by the albedo estimators (BRDF tables,
// the runtime models' directional albedo).
#pragma once

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

}  // namespace msh::bsdf
