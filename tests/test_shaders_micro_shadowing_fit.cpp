// The GLSL and HLSL ports of the ALU-only micro-shadowing approximations (shaders/{glsl,hlsl}/
// micro_shadowing_fit.*): they compile with glslangValidator (GLSL 450, GLSL ES 320, HLSL) and, where a
// Vulkan device is available (lavapipe on CI), agree with the C++ float functions
// (msh::micro_shadowing::generic_vndf_alu and the two stages generic_vndf_alu_pixel + generic_vndf_alu_light)
// at 2^14 random inputs over the domain plus degenerate ones within 1e-5, with the early-out bit-identical
// (exactly 0).
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>

#include <algorithm>
#include <cmath>

#include "support/fit_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;

namespace {

const vk::Kernel kKernel = test::fit_kernel(
    "micro_shadowing_fit", "vec2",
    "vec2(msh_ms_generic_vndf_alu(r.x, r.y, r.z, r.w),\n"
    "              msh_ms_generic_vndf_alu_light(msh_ms_generic_vndf_alu_pixel(r.x, r.z, r.w), r.y))");

using Rec = test::FitInput;

std::vector<Rec> make_records() { return test::fit_inputs(false); }

void check(const char* label, const std::vector<Rec>& recs, const std::vector<float>& out) {
  double max_diff = 0, max_diff_2 = 0;
  int early = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Rec& x = recs[i];
    SCOPED_TRACE(testing::Message() << label << " vis " << x.vis << " nl " << x.nl << " nv " << x.nv << " r "
                                    << x.r);
    const float fast = out[2 * i], two = out[2 * i + 1];
    for (float o : {fast, two}) {
      ASSERT_TRUE(std::isfinite(o));
      ASSERT_GE(o, 0.0f);
      ASSERT_LE(o, 1.0f);
    }
    const float cpu = micro_shadowing::generic_vndf_alu(x.vis, x.nl, x.nv, x.r);
    const float cpu2 = micro_shadowing::generic_vndf_alu_light(
        micro_shadowing::generic_vndf_alu_pixel(x.vis, x.nv, x.r), x.nl);
    if (micro_shadowing::exact_zero(x.vis, x.nl)) {
      ++early;
      ASSERT_EQ(fast, 0.0f);  // bit-identical early-out
      ASSERT_EQ(two, 0.0f);
    }
    max_diff = std::max(max_diff, double(std::abs(fast - cpu)));
    max_diff_2 = std::max(max_diff_2, double(std::abs(two - cpu2)));
  }
  EXPECT_LE(max_diff, 1e-5) << label;
  EXPECT_LE(max_diff_2, 1e-5) << label;
  EXPECT_GT(early, 3000) << label;
  std::printf(
      "[ %s ] %zu inputs: max |shader - C++ float| one-call %.2e, two-stage %.2e; %d early-outs, all exactly "
      "0\n",
      label, recs.size(), max_diff, max_diff_2, early);
}

}  // namespace

TEST(ShadersMicroShadowingFit, Compiles) {
  vk::expect_compiles(kKernel, {"float k = nv / (nv + alpha);", "float k = nv / (nv + alpa);"});
}

TEST(ShadersMicroShadowingFit, RunsOnVulkanAndMatchesCpp) {
  vk::run_records(kKernel, make_records(), 2, check);
}
