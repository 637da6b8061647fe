// The GLSL and HLSL ports of the diffuse-aware ALU fit (shaders/{glsl,hlsl}/micro_shadowing_aware_fit.*):
// they compile with glslangValidator (GLSL 450, GLSL ES 320, HLSL) and, where a Vulkan device is available
// (lavapipe on CI), agree with the C++ float function msh::micro_shadowing::diffuse_aware_alu
// (occlusion/micro_shadowing_aware_fit.h) at 2^14 random inputs over the domain plus boundary and degenerate
// ones within 1e-5, with both early-outs bit-identical (exactly 0).
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>

#include <algorithm>
#include <cmath>

#include "support/fit_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;

namespace {

const vk::Kernel kKernel =
    test::fit_kernel("micro_shadowing_aware_fit", "float", "msh_ms_diffuse_aware_alu(r.x, r.y, r.z, r.w)");

using Rec = test::FitInput;

std::vector<Rec> make_records() { return test::fit_inputs(true); }

void check(const char* label, const std::vector<Rec>& recs, const std::vector<float>& out) {
  double max_diff = 0;
  int early = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Rec& x = recs[i];
    SCOPED_TRACE(testing::Message() << label << " vis " << x.vis << " nl " << x.nl << " nv " << x.nv << " r "
                                    << x.r);
    const float o = out[i];
    ASSERT_TRUE(std::isfinite(o));
    ASSERT_GE(o, 0.0f);
    ASSERT_LE(o, 1.0f);
    const float cpu = micro_shadowing::diffuse_aware_alu(x.vis, x.nl, x.nv, x.r);
    const float vis = std::clamp(x.vis, 0.0f, 1.0f), nl = std::clamp(x.nl, 0.0f, 1.0f),
                nv = std::clamp(x.nv, 0.0f, 1.0f);
    if (micro_shadowing::exact_zero(vis, nl) || micro_shadowing::exact_zero(vis, nv)) {
      ++early;
      ASSERT_EQ(o, 0.0f);  // bit-identical early-outs
    }
    max_diff = std::max(max_diff, double(std::abs(o - cpu)));
  }
  EXPECT_LE(max_diff, 1e-5) << label;
  EXPECT_GT(early, 3000) << label;
  std::printf("[ %s ] %zu inputs: max |shader - C++ float| %.2e; %d early-outs, all exactly 0\n", label,
              recs.size(), max_diff, early);
}

}  // namespace

TEST(ShadersMicroShadowingAwareFit, Compiles) {
  vk::expect_compiles(kKernel, {"float omv = 1.0f - v, c = sqrt(omv)", "float omv = 1.0f - vv, c = sqrt(omv)"});
}

TEST(ShadersMicroShadowingAwareFit, RunsOnVulkanAndMatchesCpp) {
  vk::run_records(kKernel, make_records(), 1, check);
}
