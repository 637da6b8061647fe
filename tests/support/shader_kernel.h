// The one driver of the shader tests (tests/test_shaders_*.cpp): a kernel = the shader library files under
// test + a small compute main per language that calls them; compile checks in GLSL 450, GLSL ES 320 and HLSL;
// one dispatch from float arrays to float arrays on the Vulkan device (lavapipe on CI), in both languages.
// Built on the harness of vk_compute.h (glslangValidator + a dlopen'ed Vulkan loader).
//
// Typical use:
//   const vk::Kernel k{{"shaders/glsl/foo.glsl"}, kGlslMain, {"shaders/hlsl/foo.hlsl"}, kHlslMain};
//   TEST(ShadersFoo, Compiles) { vk::expect_compiles(k); }
//   TEST(ShadersFoo, RunsOnVulkanAndMatches) {
//     vk::Dispatch d;
//     d.buffers = {vk::to_floats(records), std::vector<float>(records.size() * 4)};
//     d.push = vk::push_constants(uint32_t(records.size()));
//     d.invocations = records.size();
//     vk::run_glsl_and_hlsl(k, d, [&](const char* label, const vk::Buffers& out) { check(label, out[1]); });
//   }
// Without a Vulkan device run_glsl_and_hlsl fails the test (Context::get records the failure) unless
// MSH_ALLOW_NO_VULKAN=1 is set, in which case it is a GTEST_SKIP.
#pragma once

#include <cstddef>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "vk_compute.h"

namespace msh::test::vk {

// A compute kernel in both languages. Every kernel runs 64 invocations per workgroup along x
// (`layout(local_size_x = 64) in;` / `[numthreads(64, 1, 1)]`). GLSL's entry point is `main` (glslang
// accepts no other); HLSL's is `hlsl_entry`, renamed to `main` in the SPIR-V.
struct Kernel {
  std::vector<std::string> glsl_files;  // library files, relative to the source tree, in include order
  std::string glsl_main;                // appended after them
  std::vector<std::string> hlsl_files;
  std::string hlsl_main;
  std::string hlsl_entry = "main";

  // "#version <version>" (+ highp precision lines for ES versions), the files, then the main.
  std::string glsl(const std::string& version = "450") const;
  std::string hlsl() const;
  std::string source(Lang lang) const { return lang == Lang::kGlsl ? glsl() : hlsl(); }
};

using Buffers = std::vector<std::vector<float>>;

// The data of one dispatch.
struct Dispatch {
  Buffers buffers;                     // storage buffers at bindings 0.. (each uploaded and read back)
  std::vector<Context::Image> images;  // sampled RGBA32F textures at the bindings after the buffers
  std::vector<std::byte> push;         // push-constant block (push_constants below); empty: none
  std::size_t invocations = 0;         // ⌈invocations / 64⌉ workgroups
};

// Trivially copyable records made of 4-byte fields (floats, and the odd uint32) <-> float arrays.
template <class T>
std::vector<float> to_floats(const std::vector<T>& records) {
  static_assert(std::is_trivially_copyable_v<T> && sizeof(T) % sizeof(float) == 0);
  std::vector<float> f(records.size() * sizeof(T) / sizeof(float));
  if (!f.empty()) std::memcpy(f.data(), records.data(), f.size() * sizeof(float));
  return f;
}
template <class T>
std::vector<T> from_floats(const std::vector<float>& f) {
  static_assert(std::is_trivially_copyable_v<T> && sizeof(T) % sizeof(float) == 0);
  std::vector<T> records(f.size() * sizeof(float) / sizeof(T));
  if (!records.empty()) std::memcpy(records.data(), f.data(), records.size() * sizeof(T));
  return records;
}
template <class P>
std::vector<std::byte> push_constants(const P& p) {
  static_assert(std::is_trivially_copyable_v<P>);
  std::vector<std::byte> b(sizeof(P));
  std::memcpy(b.data(), &p, sizeof(P));
  return b;
}

// Compiles `source` and runs `d` on `ctx`; *out receives the storage buffers after the dispatch. False with
// the compiler log or the Vulkan error in *why.
bool run(Context& ctx, const std::string& source, Lang lang, const Dispatch& d, Buffers* out,
         std::string* why, const std::string& hlsl_entry = "main");

// Runs `d` with the GLSL 450 kernel, then with the HLSL kernel, and calls check("glsl" / "hlsl", buffers)
// after each. Records a failure if a compilation or a run fails; without a device see the header comment.
void run_glsl_and_hlsl(const Kernel& k, const Dispatch& d,
                       const std::function<void(const char* label, const Buffers& out)>& check);

// EXPECTs that the kernel compiles as GLSL 450, GLSL ES 320 and HLSL to a non-trivial module (the compiler
// log in the failure message); fails at once if glslangValidator is missing.
void expect_compiles(const Kernel& k);

// The compile checks are not vacuous: replacing `needle` (which must occur) by `broken` in the GLSL (and,
// if `hlsl`, in the HLSL) source must make the compilation fail.
void expect_broken_source_rejected(const Kernel& k, const std::string& needle, const std::string& broken,
                                   bool hlsl = true);

}  // namespace msh::test::vk
