// Unity HDRP's Micro Shadows term (hdrp-micro-shadows), written once in shaders/portable/micro_shadowing.h
// and entered in the registry from there: against its closed form in double, lerp(1, saturate(N.L + 2 V^2 -
// 1), 0.85) (Unity HDRP's ComputeMicroShadowing at its documentation's 0.85 opacity), through every path a
// user takes: the registry's eval (double) and shade (the renderer's float), the C++ build of the shader
// function (<microshadow/engine.h>), and the GLSL and HLSL builds on lavapipe; within the precision its
// comment states (5e-7), at 2^14 random inputs and the degenerate ones of the fit tests (outside [0, 1] too).
#include <gtest/gtest.h>
#include <microshadow/engine.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>

#include <algorithm>
#include <cmath>

#include "support/fit_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
using namespace msh::occlusion;
namespace vk = msh::test::vk;

namespace {

constexpr double kBound = 5e-7;  // the precision shaders/portable/micro_shadowing.h states

// The closed form in double, written here from HDRP's ComputeMicroShadowing; inputs clamped to [0, 1].
double hdrp(double vis, double nl) {
  const double v = std::clamp(vis, 0.0, 1.0), l = std::clamp(nl, 0.0, 1.0);
  const double microshadow = std::clamp(l + 2 * v * v - 1, 0.0, 1.0);
  return 1.0 + 0.85 * (microshadow - 1.0);
}

}  // namespace

TEST(MicroShadowingHdrp, RegistryAndCppBuildMatchTheClosedForm) {
  const MicroShadowingEvaluator e("hdrp-micro-shadows");
  EXPECT_NE(e.info().closed_form, nullptr);  // a closed form of (V, N.L): Python's fast path, the guide
  EXPECT_EQ(e.info().glsl.at(0).expr, "msh_ms_hdrp_micro_shadows(vis, nl)");
  EXPECT_TRUE(e.info().glsl.at(0).area_cap.empty());  // no cap form: three.js takes it at the light's axis
  double max_eval = 0, max_shade = 0, max_cpp = 0;
  for (const test::FitInput& x : test::fit_inputs(false)) {
    const double want = hdrp(x.vis, x.nl);
    SCOPED_TRACE(testing::Message() << "vis " << x.vis << " nl " << x.nl);
    const float cpp = shader::msh_ms_hdrp_micro_shadows(x.vis, x.nl);
    max_cpp = std::max(max_cpp, std::abs(cpp - want));
    if (x.vis < 0 || x.vis > 1 || x.nl < 0 || x.nl > 1) continue;  // eval and shade take the domain only
    MicroShadowingQuery q;
    q.visibility = x.vis, q.n_dot_l = x.nl;
    max_eval = std::max(max_eval, std::abs(e.eval(q) - want));
    MicroShadowingShadeInput in;
    in.visibility = x.vis;
    in.l = Vec3f(std::sqrt(std::max(0.0f, 1 - x.nl * x.nl)), 0, x.nl);
    max_shade = std::max(max_shade, std::abs(double(e.shade(in).diffuse) - hdrp(x.vis, in.l.z)));
  }
  std::printf("[ hdrp ] max |x - double|: eval %.2e, shade %.2e, C++ build %.2e\n", max_eval, max_shade,
              max_cpp);
  EXPECT_LE(max_eval, kBound);
  EXPECT_LE(max_shade, kBound);
  EXPECT_LE(max_cpp, kBound);
  // The term fades Brinck & Maximov: 1 - 0.85 where the cone shadows fully, 1 where it is open.
  EXPECT_NEAR(shader::msh_ms_hdrp_micro_shadows(0.0f, 0.5f), 0.15f, 1e-7f);
  EXPECT_EQ(shader::msh_ms_hdrp_micro_shadows(1.0f, 0.5f), 1.0f);
}

TEST(MicroShadowingHdrp, ShadersMatchTheClosedForm) {
  const vk::Kernel k = test::fit_kernel("micro_shadowing", "float", "msh_ms_hdrp_micro_shadows(r.x, r.y)");
  vk::expect_compiles(k);
  vk::run_records(
      k, test::fit_inputs(false), 1,
      [](const char* label, const std::vector<test::FitInput>& recs, const std::vector<float>& out) {
        double max_diff = 0;
        for (std::size_t i = 0; i < recs.size(); ++i)
          max_diff = std::max(max_diff, std::abs(out[i] - hdrp(recs[i].vis, recs[i].nl)));
        std::printf("[ %s ] max |shader - double| %.2e\n", label, max_diff);
        EXPECT_LE(max_diff, kBound) << label;
      });
}
