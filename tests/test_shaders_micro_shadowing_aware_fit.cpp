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

#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;

namespace {

const char* kGlslMain = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { vec4 rec[]; };
layout(std430, binding = 1) writeonly buffer Out { float o[]; };
layout(push_constant) uniform PC { uint n; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  vec4 r = rec[i];
  o[i] = msh_ms_diffuse_aware_alu(r.x, r.y, r.z, r.w);
}
)";

const char* kHlslMain = R"(
[[vk::binding(0)]] StructuredBuffer<float4> rec;
[[vk::binding(1)]] RWStructuredBuffer<float> o;
struct PC { uint n; };
[[vk::push_constant]] PC pc;
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
  uint i = id.x;
  if (i >= pc.n) return;
  float4 r = rec[i];
  o[i] = msh_ms_diffuse_aware_alu(r.x, r.y, r.z, r.w);
}
)";

const vk::Kernel kKernel{{"shaders/glsl/micro_shadowing_aware_fit.glsl"},
                         kGlslMain,
                         {"shaders/hlsl/micro_shadowing_aware_fit.hlsl"},
                         kHlslMain};

struct Rec {
  float vis, nl, nv, r;
};

// 2^14 uniform random inputs over the domain (roughness also below 0.1), the early-out boundaries
// 2 vis + N.L = 1 and 2 vis + N.V = 1, the cone boundary N.L = cos_t, and degenerate values (0, 1, outside
// [0, 1], tiny).
std::vector<Rec> make_records() {
  std::vector<Rec> recs;
  Pcg32 rng(909);
  auto u = [&] { return rng.next_float(); };
  for (int i = 0; i < (1 << 14); ++i) recs.push_back({u(), 1 - u(), 1 - u(), u()});
  for (int i = 0; i < 512; ++i) {
    const float vis = u();
    const float nl = i % 2 ? 1.0f - 2.0f * vis : std::sqrt(1.0f - vis);
    recs.push_back({vis, nl, u(), u()});
    recs.push_back({vis, u(), nl, u()});
  }
  const float vals[] = {0.0f, 1.0f, -0.5f, 2.0f, 1e-7f, 0.5f, 0.999999f};
  for (float a : vals)
    for (float b : vals)
      for (float c : vals)
        for (float d : {0.0f, 1e-6f, 0.1f, 1.0f, 1.5f}) recs.push_back({a, b, c, d});
  return recs;
}

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
  vk::expect_compiles(kKernel);
  vk::expect_broken_source_rejected(kKernel, "float omv = 1.0 - v, c = sqrt(omv)",
                                    "float omv = 1.0 - vv, c = sqrt(omv)");
}

TEST(ShadersMicroShadowingAwareFit, RunsOnVulkanAndMatchesCpp) {
  const auto recs = make_records();
  vk::Dispatch d;
  d.buffers = {vk::to_floats(recs), std::vector<float>(recs.size())};
  d.push = vk::push_constants(uint32_t(recs.size()));
  d.invocations = recs.size();
  vk::run_glsl_and_hlsl(kKernel, d,
                        [&](const char* label, const vk::Buffers& out) { check(label, recs, out[1]); });
}
