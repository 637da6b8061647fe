// The shader tests' driver (tests/support/shader_kernel.h) on a kernel whose result is known exactly:
// out[i] = in[i] * 2 + offset (powers of two and small integers: exact in float on any device), with the
// HLSL entry function not called main, several buffers and a push-constant block.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/shader_kernel.h"

namespace vk = msh::test::vk;

namespace {

const vk::Kernel kKernel{{},
                         R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { float x[]; };
layout(std430, binding = 1) writeonly buffer Out { float y[]; };
layout(std430, binding = 2) writeonly buffer Count { uint ids[]; };
layout(push_constant) uniform PC { uint n; float offset; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  y[i] = x[i] * 2.0 + pc.offset;
  ids[i] = i + 1u;
}
)",
                         {},
                         R"(
[[vk::binding(0)]] StructuredBuffer<float> x;
[[vk::binding(1)]] RWStructuredBuffer<float> y;
[[vk::binding(2)]] RWStructuredBuffer<uint> ids;
struct PC { uint n; float offset; };
[[vk::push_constant]] PC pc;
[numthreads(64, 1, 1)]
void twice_plus(uint3 id : SV_DispatchThreadID) {
  uint i = id.x;
  if (i >= pc.n) return;
  y[i] = x[i] * 2.0 + pc.offset;
  ids[i] = i + 1u;
}
)",
                         "twice_plus"};

}  // namespace

TEST(ShaderKernel, CompilesAndRejectsBrokenSource) {
  vk::expect_compiles(kKernel);
  vk::expect_broken_source_rejected(kKernel, "x[i] * 2.0", "x[i] * two");
}

TEST(ShaderKernel, RunsBothLanguagesExactly) {
  const uint32_t n = 1000;  // not a multiple of 64: the last group is partial
  std::vector<float> x(n);
  for (uint32_t i = 0; i < n; ++i) x[i] = float(i) - 500.0f;
  struct {
    uint32_t n;
    float offset;
  } push{n, 0.25f};
  vk::Dispatch d;
  d.buffers = {x, std::vector<float>(n), std::vector<float>(n + 8)};
  d.push = vk::push_constants(push);
  d.invocations = n;
  int checked = 0;
  vk::run_glsl_and_hlsl(kKernel, d, [&](const char* label, const vk::Buffers& out) {
    ASSERT_EQ(out.size(), 3u) << label;
    EXPECT_EQ(out[0], x) << label;  // the input comes back unchanged
    const auto ids = vk::from_floats<uint32_t>(out[2]);
    for (uint32_t i = 0; i < n; ++i) {
      ASSERT_EQ(out[1][i], x[i] * 2 + 0.25f) << label << " " << i;
      ASSERT_EQ(ids[i], i + 1) << label << " " << i;
    }
    for (uint32_t i = n; i < n + 8; ++i) ASSERT_EQ(ids[i], 0u) << label << ": invocation past n ran";
    ++checked;
  });
  if (!IsSkipped()) {
    EXPECT_EQ(checked, 2);
  }
}

// The single-body framed_kernel derives the HLSL body by hlsl_spelling: GLSL vector types become HLSL's
// (whole words only) and each framed texture passed as an argument gains its SamplerState.
TEST(ShaderKernel, HlslSpellingOfAGlslBody) {
  const vk::KernelFrame frame{{"in vec4 rec", "out vec4 o"}, {"3d lut3", "2d lut"}, ""};
  EXPECT_EQ(
      vk::hlsl_spelling("vec4 a = vec4(f(lut3, x), g(lut , y), lut3x, 0.0); uvec2 u; ivec3 k; vec4x w;",
                        frame),
      "float4 a = float4(f(lut3, lut3_smp, x), g(lut, lut_smp, y), lut3x, 0.0); uint2 u; int3 k; vec4x w;");
  const vk::Kernel k = vk::framed_kernel({"micro_shadowing_fit"}, {{"in vec4 rec", "out vec2 o"}, {}, ""},
                                         "struct S { vec3 p; };\n", "  o[i] = rec[i].xy;\n");
  EXPECT_EQ(k.glsl_files, std::vector<std::string>{"shaders/glsl/micro_shadowing_fit.glsl"});
  EXPECT_EQ(k.hlsl_files, std::vector<std::string>{"shaders/hlsl/micro_shadowing_fit.hlsl"});
  EXPECT_NE(k.hlsl_main.find("struct S { float3 p; };"), std::string::npos) << k.hlsl_main;
  EXPECT_NE(k.hlsl_main.find("StructuredBuffer<float4> rec;"), std::string::npos) << k.hlsl_main;
  EXPECT_NE(k.glsl_main.find("  o[i] = rec[i].xy;\n"), std::string::npos) << k.glsl_main;
}

// The include expansion the shader tests and the viewer's server use (src/view/shader_source.h): paths
// relative to the including file, nested; every entry point expands to its prelude and its portable body with
// no #include left; a missing file, a cycle and an unquoted path are one-line InputErrors.
TEST(ShaderKernel, ExpandsIncludesRelativeToTheIncludingFile) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("msh_include_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "a" / "b");
  std::ofstream(dir / "a" / "top.glsl") << "top\n  #include \"b/mid.h\"\nend\n";
  std::ofstream(dir / "a" / "b" / "mid.h") << "mid\n#include \"../leaf.h\"\n";
  std::ofstream(dir / "a" / "leaf.h") << "leaf\n";
  EXPECT_EQ(msh::view::expand_shader_includes(dir / "a" / "top.glsl"), "top\nmid\nleaf\nend\n");
  std::ofstream(dir / "a" / "missing.glsl") << "#include \"nothing.h\"\n";
  EXPECT_THROW(msh::view::expand_shader_includes(dir / "a" / "missing.glsl"), msh::InputError);
  std::ofstream(dir / "a" / "cycle.glsl") << "#include \"cycle.glsl\"\n";
  EXPECT_THROW(msh::view::expand_shader_includes(dir / "a" / "cycle.glsl"), msh::InputError);
  std::ofstream(dir / "a" / "unquoted.glsl") << "#include <x.h>\n";
  EXPECT_THROW(msh::view::expand_shader_includes(dir / "a" / "unquoted.glsl"), msh::InputError);
  fs::remove_all(dir);
  for (const char* lang : {"glsl", "hlsl"})
    for (const auto& e : fs::directory_iterator(fs::path(MSH_SOURCE_DIR) / "shaders" / lang)) {
      const std::string text = msh::view::expand_shader_includes(e.path());
      EXPECT_EQ(text.find("\n#include"), std::string::npos) << e.path();
      EXPECT_NE(text.find(std::string("#define MSH_PRELUDE_") + (lang[0] == 'g' ? "GLSL" : "HLSL")),
                std::string::npos)
          << e.path();
    }
}
