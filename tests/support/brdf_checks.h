// Checks shared by the BRDF model tests (core and extra registries).
#pragma once

#include <gtest/gtest.h>
#include <microshadow/bsdf/runtime/brdf_model.h>

#include <cmath>
#include <string>

namespace msh::test {

// One pair of directions through a runtime model: f(a, b) finite and ≥ 0, and equal to f(b, a) within
// 1e-9 relative where the model claims Helmholtz reciprocity. Returns f(a, b); `what` names the case in
// failure messages.
inline Rgbd expect_sane_pair(const bsdf::BrdfModel& model, const Vec3d& a, const Vec3d& b,
                             const std::string& what) {
  const Rgbd fab = model.f(a, b), fba = model.f(b, a);
  EXPECT_TRUE(is_finite(fab)) << what;
  if (!is_finite(fab)) return fab;
  EXPECT_GE(min_component(fab), 0.0) << what;
  if (model.reciprocal()) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(fab[c], fba[c], 1e-9 * (1 + std::abs(fab[c]))) << what;
  }
  return fab;
}

}  // namespace msh::test
