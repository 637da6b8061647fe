// The shader tests' driver (see shader_kernel.h).
#include "shader_kernel.h"

#include <gtest/gtest.h>

#include <cstdio>

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

}  // namespace msh::test::vk
