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

#include <microshadow/math/vec.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
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

// The usual kernel frame, generated so that each test writes only its types and its per-invocation body:
// one invocation per record i < pc.n (the first push constant), storage buffers and textures in binding
// order. The body sees `i`, the buffers and textures by name, `pc`; HLSL textures come with a SamplerState
// named <texture>_smp.
struct KernelFrame {
  // One per binding: "in TYPE NAME" (read-only) or "out TYPE NAME" (write-only) arrays, TYPE in GLSL
  // spelling (vecN is floatN in the HLSL frame, other type names are the same in both languages).
  std::vector<std::string> buffers;
  std::vector<std::string> textures;  // "2d NAME" or "3d NAME", at the bindings after the buffers
  std::string push;                   // push-constant fields after `uint n;`, e.g. "int n_est;"
};
Kernel framed_kernel(std::vector<std::string> glsl_files, std::vector<std::string> hlsl_files,
                     const KernelFrame& frame, const std::string& glsl_types, const std::string& glsl_body,
                     const std::string& hlsl_types, const std::string& hlsl_body);
// The same with the types and the body written once, in GLSL (the HLSL copy is derived by hlsl_spelling),
// around the shader libraries named by `libraries`: shaders/glsl/<name>.glsl and shaders/hlsl/<name>.hlsl,
// in include order.
Kernel framed_kernel(const std::vector<std::string>& libraries, const KernelFrame& frame,
                     const std::string& glsl_types, const std::string& glsl_body);

// GLSL test-kernel code in HLSL spelling, for bodies that use only what both languages share: vecN, ivecN,
// uvecN -> floatN, intN, uintN, and every texture of `frame` passed as an argument (`tex,`) gains its
// SamplerState (`tex, tex_smp,`), as the HLSL shader libraries take them.
std::string hlsl_spelling(const std::string& glsl, const KernelFrame& frame);

using Buffers = std::vector<std::vector<float>>;

// The data of one dispatch.
struct Dispatch {
  Buffers buffers;                     // storage buffers at bindings 0.. (each uploaded and read back)
  std::vector<Context::Image> images;  // sampled RGBA32F textures at the bindings after the buffers
  std::vector<std::byte> push;         // push-constant block (push_constants below); empty: none
  std::size_t invocations = 0;         // ⌈invocations / 64⌉ workgroups
};

// Trivially copyable records made of 4-byte fields (floats, and the odd uint32) <-> float arrays: the bytes
// of `from` as an array of `To` (a trailing partial record is dropped).
template <class To, class From>
std::vector<To> records_as(const std::vector<From>& from) {
  static_assert(std::is_trivially_copyable_v<To> && std::is_trivially_copyable_v<From>);
  static_assert(sizeof(To) % sizeof(float) == 0 && sizeof(From) % sizeof(float) == 0);
  std::vector<To> to(from.size() * sizeof(From) / sizeof(To));
  if (!to.empty()) std::memcpy(to.data(), from.data(), to.size() * sizeof(To));
  return to;
}
template <class T>
std::vector<float> to_floats(const std::vector<T>& records) {
  return records_as<float>(records);
}
template <class T>
std::vector<T> from_floats(const std::vector<float>& f) {
  return records_as<T>(f);
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

// The usual dispatch: `records` in buffer 0, `out_floats` floats per record in buffer 1, one invocation per
// record, push constants `push` (empty: the record count as one uint32); check(label, records, buffer 1)
// after each language.
template <class Rec, class Check>
void run_records(const Kernel& k, const std::vector<Rec>& records, std::size_t out_floats, Check&& check,
                 std::vector<std::byte> push = {}) {
  Dispatch d;
  d.buffers = {to_floats(records), std::vector<float>(records.size() * out_floats)};
  d.push = push.empty() ? push_constants(uint32_t(records.size())) : std::move(push);
  d.invocations = records.size();
  run_glsl_and_hlsl(k, d, [&](const char* label, const Buffers& out) { check(label, records, out[1]); });
}

// Two record sets in one dispatch: set a's floats in buffer 0 (a.count records, a.out_floats floats each
// written to buffer 1), set b's in buffer 2 (outputs in buffer 3), one invocation per record of the larger
// set, push constants {invocations, a.count, b.count}; check(label, buffer 1, buffer 3) after each language.
struct RecordSet {
  std::vector<float> floats;
  std::size_t count, out_floats;
};
template <class Check>
void run_two_record_sets(const Kernel& k, const RecordSet& a, const RecordSet& b, Check&& check) {
  Dispatch d;
  d.buffers = {a.floats, std::vector<float>(a.count * a.out_floats), b.floats,
               std::vector<float>(b.count * b.out_floats)};
  d.invocations = std::max(a.count, b.count);
  d.push =
      push_constants(std::array<uint32_t, 3>{uint32_t(d.invocations), uint32_t(a.count), uint32_t(b.count)});
  run_glsl_and_hlsl(k, d, [&](const char* label, const Buffers& out) { check(label, out[1], out[3]); });
}

// EXPECTs that the kernel compiles as GLSL 450, GLSL ES 320 and HLSL to a non-trivial module (the compiler
// log in the failure message); fails at once if glslangValidator is missing.
void expect_compiles(const Kernel& k);

// The compile checks are not vacuous: replacing `needle` (which must occur) by `broken` in the GLSL (and,
// if `hlsl`, in the HLSL) source must make the compilation fail.
void expect_broken_source_rejected(const Kernel& k, const std::string& needle, const std::string& broken,
                                   bool hlsl = true);

// Both checks of a shader test's Compiles case: expect_compiles(k), then the edit `needle` -> `broken` (in
// the HLSL too if `hlsl`) must be rejected.
struct BrokenEdit {
  std::string needle, broken;
  bool hlsl = true;
};
void expect_compiles(const Kernel& k, const BrokenEdit& must_fail);

// A record's vec4 slot: xyz from a direction or point, w a scalar (float, as the shader reads it); and back.
inline void put(float* d, const Vec3d& x, double w = 0) {
  d[0] = float(x.x), d[1] = float(x.y), d[2] = float(x.z), d[3] = float(w);
}
inline Vec3d get(const float* d) { return Vec3d(d[0], d[1], d[2]); }

}  // namespace msh::test::vk
