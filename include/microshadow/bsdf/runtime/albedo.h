// Directional albedo E(wo) = ∫ f(wo, wi) (n·wi) dwi (RTR4 9.8) of a runtime BrdfModel by deterministic
// quasi-Monte Carlo (bsdf/qmc.h): the fixed-seed Owen-scrambled Sobol sequence drives the model's own
// importance sampler, so the estimate is a pure function of (model, wo, n) — identical on every machine and
// thread count.
#pragma once

#include <microshadow/bsdf/qmc.h>
#include <microshadow/bsdf/runtime/brdf_model.h>

#include <cstdint>

namespace msh::bsdf {

// Directional albedo of a runtime model for view direction wo (local frame, wo.z > 0), with n samples of
// the model's own sampler (src/bsdf/albedo.cpp). Converges to ~1e-5 at n = 2^18 for the shipped models.
Rgbd directional_albedo(const BrdfModel& model, const Vec3d& wo, uint32_t n = 1u << 18);
// Same at N·V = mu, view in the xz plane (the isotropic models' albedo depends on mu only).
Rgbd directional_albedo(const BrdfModel& model, double mu, uint32_t n = 1u << 18);

}  // namespace msh::bsdf
