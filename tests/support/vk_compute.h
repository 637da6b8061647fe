// Tiny Vulkan compute harness for shader tests: compile GLSL/HLSL to SPIR-V with glslangValidator, run one
// compute dispatch on whatever Vulkan device is present (lavapipe, the Mesa CPU driver, on CI), read the
// storage buffers back. The Vulkan loader is opened at run time (dlopen "libvulkan.so.1"), so nothing links
// against Vulkan and tests that do not use it are unaffected. Without a loader/device Context::get records a
// test failure (so a machine without Vulkan cannot pass the shader tests silently) unless the environment
// variable MSH_ALLOW_NO_VULKAN=1 allows it; the shader tests then GTEST_SKIP the run part (compile checks
// still run). Sanitizer builds never run the driver and skip without a failure.
//
// Shader tests do not call this directly: they go through the driver of shader_kernel.h (a kernel in both
// languages, float arrays in and out, the compile checks).
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../../src/view/shader_source.h"

namespace msh::test::vk {

enum class Lang { kGlsl, kHlsl };

// Path of glslangValidator ("" if not found on PATH or in /usr/bin).
std::string glslang_validator();

// Compiles a complete compute shader (GLSL with its #version line and `void main()`, or HLSL with the entry
// function `hlsl_entry`, renamed `main` in the module) to Vulkan SPIR-V. Returns false with the compiler's
// log on failure (or when glslangValidator is missing).
bool compile_shader(const std::string& source, Lang lang, std::vector<uint32_t>* spirv, std::string* log,
                    const std::string& hlsl_entry = "main");

// True when MSH_ALLOW_NO_VULKAN=1 is set: a missing Vulkan device is then a skip, not a failure.
bool no_vulkan_allowed();

// A Vulkan instance + device with a compute queue; created once per process on first use.
class Context {
 public:
  // The shared context, or nullptr with the reason in *why (no loader, no device, sanitizer build, ...).
  // Returning nullptr also adds a non-fatal gtest failure to the calling test unless no_vulkan_allowed() or
  // the build is a sanitizer build.
  static Context* get(std::string* why);

  const std::string& device_name() const { return device_name_; }

  // Runs `spirv` (entry point "main", descriptor set 0, storage buffers at bindings 0..buffers.size()-1, an
  // optional push-constant block) as groups_x × 1 × 1 workgroups. Every buffer is uploaded before and
  // downloaded after the dispatch. Returns false with a reason on any Vulkan error.
  bool run(const std::vector<uint32_t>& spirv, const std::vector<std::vector<std::byte>*>& buffers,
           const void* push, uint32_t push_size, uint32_t groups_x, std::string* why);

  // A read-only RGBA32F texture, bound as a combined image sampler with linear filtering (min/mag), no
  // mipmaps, clamp-to-edge addressing and normalized coordinates. depth = 0: a 2D image; depth ≥ 1: a 3D
  // image. texels: width·height·max(depth,1)·4 floats, x fastest, then y, then z.
  struct Image {
    uint32_t width = 0, height = 0, depth = 0;
    const float* texels = nullptr;
  };
  // As run() above, plus `images` at bindings buffers.size() .. buffers.size() + images.size() − 1 (GLSL
  // sampler2D / sampler3D; HLSL Texture2D/3D and a SamplerState sharing the binding via [[vk::binding(k)]]).
  // Fails with a reason if the device cannot linearly filter RGBA32F.
  bool run(const std::vector<uint32_t>& spirv, const std::vector<std::vector<std::byte>*>& buffers,
           const std::vector<Image>& images, const void* push, uint32_t push_size, uint32_t groups_x,
           std::string* why);

  struct Impl;

 private:
  Context() = default;
  Impl* impl_ = nullptr;
  std::string device_name_;
};

// A shader source file of the repository (path relative to the source tree) with its #include lines
// expanded, the text the viewer serves (src/view/shader_source.h).
inline std::string read_source(const std::string& rel) {
  return msh::view::expand_shader_includes(std::string(MSH_SOURCE_DIR) + "/" + rel);
}

}  // namespace msh::test::vk
