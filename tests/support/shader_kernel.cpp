// The shader tests' driver (see shader_kernel.h).
#include "shader_kernel.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <regex>
#include <sstream>

namespace msh::test::vk {

std::string Kernel::glsl(const std::string& version) const {
  std::string s = "#version " + version + "\n";
  if (version.find("es") != std::string::npos)
    s += "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\nprecision highp "
         "sampler3D;\n";
  for (const std::string& f : glsl_files) s += read_source(f);
  return s + glsl_main;
}

std::string Kernel::hlsl() const {
  std::string s;
  for (const std::string& f : hlsl_files) s += read_source(f);
  return s + hlsl_main;
}

Kernel framed_kernel(std::vector<std::string> glsl_files, std::vector<std::string> hlsl_files,
                     const KernelFrame& frame, const std::string& glsl_types, const std::string& glsl_body,
                     const std::string& hlsl_types, const std::string& hlsl_body) {
  auto hlsl_type = [](const std::string& t) { return t.rfind("vec", 0) == 0 ? "float" + t.substr(3) : t; };
  std::string g = "layout(local_size_x = 64) in;\n" + glsl_types, h = hlsl_types;
  int binding = 0;
  for (const std::string& b : frame.buffers) {
    std::istringstream ss(b);
    std::string dir, type, name;
    ss >> dir >> type >> name;
    const bool in = dir == "in";
    const std::string k = std::to_string(binding++);
    g += "layout(std430, binding = " + k + ") " + (in ? "readonly" : "writeonly") + " buffer B" + k + " { " +
         type + " " + name + "[]; };\n";
    h += "[[vk::binding(" + k + ")]] " + (in ? "" : "RW") + "StructuredBuffer<" + hlsl_type(type) + "> " +
         name + ";\n";
  }
  for (const std::string& t : frame.textures) {
    const std::string dim = t.substr(0, 2), name = t.substr(3), k = std::to_string(binding++);
    g += "layout(binding = " + k + ") uniform sampler" + (dim == "2d" ? "2D " : "3D ") + name + ";\n";
    h += "[[vk::binding(" + k + ")]] Texture" + (dim == "2d" ? "2D" : "3D") + "<float4> " + name + ";\n";
    h += "[[vk::binding(" + k + ")]] SamplerState " + name + "_smp;\n";
  }
  g += "layout(push_constant) uniform PC { uint n; " + frame.push + " } pc;\n";
  h += "struct PC { uint n; " + frame.push + " };\n[[vk::push_constant]] PC pc;\n";
  g += "void main() {\n  uint i = gl_GlobalInvocationID.x;\n  if (i >= pc.n) return;\n" + glsl_body + "}\n";
  h += "[numthreads(64, 1, 1)]\nvoid main(uint3 id : SV_DispatchThreadID) {\n  uint i = id.x;\n  if (i >= "
       "pc.n) "
       "return;\n" +
       hlsl_body + "}\n";
  return Kernel{std::move(glsl_files), g, std::move(hlsl_files), h};
}

std::string hlsl_spelling(const std::string& glsl, const KernelFrame& frame) {
  std::string h = std::regex_replace(glsl, std::regex(R"(\bvec([234])\b)"), "float$1");
  h = std::regex_replace(h, std::regex(R"(\bivec([234])\b)"), "int$1");
  h = std::regex_replace(h, std::regex(R"(\buvec([234])\b)"), "uint$1");
  for (const std::string& t : frame.textures) {
    const std::string name = t.substr(3);
    h = std::regex_replace(h, std::regex("\\b" + name + "\\s*,"), name + ", " + name + "_smp,");
  }
  return h;
}

Kernel framed_kernel(const std::vector<std::string>& libraries, const KernelFrame& frame,
                     const std::string& glsl_types, const std::string& glsl_body) {
  std::vector<std::string> glsl_files, hlsl_files;
  for (const std::string& name : libraries) {
    glsl_files.push_back("shaders/glsl/" + name + ".glsl");
    hlsl_files.push_back("shaders/hlsl/" + name + ".hlsl");
  }
  return framed_kernel(std::move(glsl_files), std::move(hlsl_files), frame, glsl_types, glsl_body,
                       hlsl_spelling(glsl_types, frame), hlsl_spelling(glsl_body, frame));
}

bool run(Context& ctx, const std::string& source, Lang lang, const Dispatch& d, Buffers* out,
         std::string* why, const std::string& hlsl_entry) {
  std::vector<uint32_t> spv;
  if (!compile_shader(source, lang, &spv, why, hlsl_entry)) return false;
  std::vector<std::vector<std::byte>> bytes(d.buffers.size());
  std::vector<std::vector<std::byte>*> ptrs;
  for (std::size_t i = 0; i < d.buffers.size(); ++i) {
    bytes[i].resize(d.buffers[i].size() * sizeof(float));
    if (!bytes[i].empty()) std::memcpy(bytes[i].data(), d.buffers[i].data(), bytes[i].size());
    ptrs.push_back(&bytes[i]);
  }
  const uint32_t groups = uint32_t((d.invocations + 63) / 64);
  if (!ctx.run(spv, ptrs, d.images, d.push.empty() ? nullptr : d.push.data(), uint32_t(d.push.size()), groups,
               why))
    return false;
  out->assign(d.buffers.size(), {});
  for (std::size_t i = 0; i < d.buffers.size(); ++i) {
    (*out)[i].resize(d.buffers[i].size());
    if (!bytes[i].empty()) std::memcpy((*out)[i].data(), bytes[i].data(), bytes[i].size());
  }
  return true;
}

void run_glsl_and_hlsl(const Kernel& k, const Dispatch& d,
                       const std::function<void(const char* label, const Buffers& out)>& check) {
  std::string why;
  Context* ctx = Context::get(&why);  // records the failure itself unless skipping is allowed
  if (!ctx) GTEST_SKIP() << "no Vulkan compute device: " << why;
  std::printf("[ vulkan ] device: %s\n", ctx->device_name().c_str());
  for (const Lang lang : {Lang::kGlsl, Lang::kHlsl}) {
    const char* label = lang == Lang::kGlsl ? "glsl" : "hlsl";
    Buffers out;
    if (!run(*ctx, k.source(lang), lang, d, &out, &why, k.hlsl_entry)) {
      ADD_FAILURE() << label << ": " << why;
      continue;
    }
    check(label, out);
  }
}

void expect_compiles(const Kernel& k) {
  ASSERT_FALSE(glslang_validator().empty()) << "glslangValidator missing: run scripts/install-deps.sh";
  for (const char* version : {"450", "320 es"}) {
    std::vector<uint32_t> spv;
    std::string log;
    EXPECT_TRUE(compile_shader(k.glsl(version), Lang::kGlsl, &spv, &log)) << "GLSL " << version << "\n"
                                                                          << log;
    EXPECT_GT(spv.size(), 100u) << "GLSL " << version;
  }
  std::vector<uint32_t> spv;
  std::string log;
  EXPECT_TRUE(compile_shader(k.hlsl(), Lang::kHlsl, &spv, &log, k.hlsl_entry)) << "HLSL\n" << log;
  EXPECT_GT(spv.size(), 100u) << "HLSL";
}

void expect_broken_source_rejected(const Kernel& k, const std::string& needle, const std::string& broken,
                                   bool hlsl) {
  ASSERT_FALSE(glslang_validator().empty()) << "glslangValidator missing: run scripts/install-deps.sh";
  std::vector<uint32_t> spv;
  std::string log;
  std::string g = k.glsl();
  ASSERT_NE(g.find(needle), std::string::npos) << "GLSL: '" << needle << "' not found";
  g.replace(g.find(needle), needle.size(), broken);
  EXPECT_FALSE(compile_shader(g, Lang::kGlsl, &spv, &log)) << "GLSL accepted '" << broken << "'";
  if (!hlsl) return;
  std::string h = k.hlsl();
  ASSERT_NE(h.find(needle), std::string::npos) << "HLSL: '" << needle << "' not found";
  h.replace(h.find(needle), needle.size(), broken);
  EXPECT_FALSE(compile_shader(h, Lang::kHlsl, &spv, &log, k.hlsl_entry))
      << "HLSL accepted '" << broken << "'";
}

void expect_compiles(const Kernel& k, const BrokenEdit& must_fail) {
  expect_compiles(k);
  expect_broken_source_rejected(k, must_fail.needle, must_fail.broken, must_fail.hlsl);
}

}  // namespace msh::test::vk
