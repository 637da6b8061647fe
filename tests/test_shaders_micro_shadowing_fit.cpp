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
#include <cstring>
#include <fstream>
#include <sstream>

#include "support/vk_compute.h"

using namespace msh;
namespace vk = msh::test::vk;

namespace {

using vk::read_source;

const char* kGlslMain = R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { vec4 rec[]; };
layout(std430, binding = 1) writeonly buffer Out { vec2 o[]; };
layout(push_constant) uniform PC { uint n; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  vec4 r = rec[i];
  o[i] = vec2(msh_ms_generic_vndf_alu(r.x, r.y, r.z, r.w),
              msh_ms_generic_vndf_alu_light(msh_ms_generic_vndf_alu_pixel(r.x, r.z, r.w), r.y));
}
)";

const char* kHlslMain = R"(
[[vk::binding(0)]] StructuredBuffer<float4> rec;
[[vk::binding(1)]] RWStructuredBuffer<float2> o;
struct PC { uint n; };
[[vk::push_constant]] PC pc;
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
  uint i = id.x;
  if (i >= pc.n) return;
  float4 r = rec[i];
  o[i] = float2(msh_ms_generic_vndf_alu(r.x, r.y, r.z, r.w),
                msh_ms_generic_vndf_alu_light(msh_ms_generic_vndf_alu_pixel(r.x, r.z, r.w), r.y));
}
)";

std::string glsl_source(const char* version) {
  std::string head = std::string("#version ") + version + "\n";
  if (std::string(version).find("es") != std::string::npos)
    head += "precision highp float;\nprecision highp int;\n";
  return head + read_source("shaders/glsl/micro_shadowing_fit.glsl") + kGlslMain;
}
std::string hlsl_source() { return read_source("shaders/hlsl/micro_shadowing_fit.hlsl") + kHlslMain; }

struct Rec {
  float vis, nl, nv, r;
};

// 2^14 uniform random inputs over the domain (roughness also below 0.1), the early-out boundary
// 2 vis + N.L = 1, the cone boundary N.L = cos_t, and degenerate values (0, 1, outside [0, 1], tiny).
std::vector<Rec> make_records() {
  std::vector<Rec> recs;
  Pcg32 rng(909);
  auto u = [&] { return rng.next_float(); };
  for (int i = 0; i < (1 << 14); ++i) recs.push_back({u(), 1 - u(), 1 - u(), u()});
  for (int i = 0; i < 512; ++i) {
    const float vis = u();
    const float nl = i % 2 ? 1.0f - 2.0f * vis : std::sqrt(1.0f - vis);
    recs.push_back({vis, nl, u(), u()});
  }
  const float vals[] = {0.0f, 1.0f, -0.5f, 2.0f, 1e-7f, 0.5f, 0.999999f};
  for (float a : vals)
    for (float b : vals)
      for (float c : vals)
        for (float d : {0.0f, 1e-6f, 0.1f, 1.0f, 1.5f}) recs.push_back({a, b, c, d});
  return recs;
}

bool run_kernel(vk::Context& ctx, const std::string& source, vk::Lang lang, const std::vector<Rec>& recs,
                std::vector<float>* out, std::string* why) {
  std::vector<uint32_t> spv;
  if (!vk::compile_shader(source, lang, &spv, why)) return false;
  std::vector<std::byte> in(recs.size() * 16), res(recs.size() * 8);
  std::memcpy(in.data(), recs.data(), in.size());
  const uint32_t n = uint32_t(recs.size());
  if (!ctx.run(spv, {&in, &res}, &n, sizeof n, (n + 63) / 64, why)) return false;
  out->resize(recs.size() * 2);
  std::memcpy(out->data(), res.data(), res.size());
  return true;
}

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
  ASSERT_FALSE(vk::glslang_validator().empty()) << "glslangValidator missing: run scripts/install-deps.sh";
  std::vector<uint32_t> spv;
  std::string log;
  for (const char* version : {"450", "320 es"})
    EXPECT_TRUE(vk::compile_shader(glsl_source(version), vk::Lang::kGlsl, &spv, &log)) << version << "\n"
                                                                                       << log;
  EXPECT_TRUE(vk::compile_shader(hlsl_source(), vk::Lang::kHlsl, &spv, &log)) << log;
  // A broken source must fail: the compile check is not vacuous.
  std::string g = glsl_source("450"), h = hlsl_source();
  const std::string needle = "float k = nv / (nv + alpha);";
  ASSERT_NE(g.find(needle), std::string::npos);
  ASSERT_NE(h.find(needle), std::string::npos);
  g.replace(g.find(needle), needle.size(), "float k = nv / (nv + alpa);");
  h.replace(h.find(needle), needle.size(), "float k = nv / (nv + alpa);");
  EXPECT_FALSE(vk::compile_shader(g, vk::Lang::kGlsl, &spv, &log));
  EXPECT_FALSE(vk::compile_shader(h, vk::Lang::kHlsl, &spv, &log));
}

TEST(ShadersMicroShadowingFit, RunsOnVulkanAndMatchesCpp) {
  std::string why;
  vk::Context* ctx = vk::Context::get(&why);
  if (!ctx) GTEST_SKIP() << "no Vulkan compute device: " << why;
  const auto recs = make_records();
  std::vector<float> out;
  ASSERT_TRUE(run_kernel(*ctx, glsl_source("450"), vk::Lang::kGlsl, recs, &out, &why)) << why;
  check("glsl", recs, out);
  ASSERT_TRUE(run_kernel(*ctx, hlsl_source(), vk::Lang::kHlsl, recs, &out, &why)) << why;
  check("hlsl", recs, out);
}
