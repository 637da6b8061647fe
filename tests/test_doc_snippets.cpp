// The code blocks of README.md and docs/*.md that a user would paste are tested (docs/architecture.md,
// "Tested snippets"). A fenced block whose info string holds the word `test` (cpp test, python test,
// cmake test, glsl test=HARNESS, hlsl test=HARNESS) is extracted and:
//   - cpp: compiled as one translation unit with -std=c++20 -Wall -Wextra -Werror against an install of this
//     build (`cmake --install` into a temporary prefix; pkg-config microshadow), linked and run if it has a
//     main, in a directory holding the installed default tables (micro_shadowing*.ktx2 + sidecars);
//   - python: run with PYTHONPATH=<build>/python from the source tree (examples/ paths resolve);
//   - cmake: appended to a project that defines my_engine and my_tool, configured against the install prefix
//     only, built, and both programs run;
//   - glsl/hlsl: the block's `#include "X"` lines expanded from shaders/<lang>/X, placed in the harness
//     named by test=HARNESS (the user's inputs and a compute main), compiled with glslangValidator; the
//     micro-shadowing drop-in (test=ms-lut) also runs on the Vulkan device (lavapipe) with the installed
//     default tables and is compared with the C++ sampler (msh::lut::sample_micro_shadowing*).
// A failure names the file and line of the block's opening fence.
#include <gtest/gtest.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/shader_kernel.h"
#include "support/vk_compute.h"

namespace fs = std::filesystem;

namespace {

struct Snippet {
  std::string file;     // relative to the source tree
  int line = 0;         // of the opening fence (1-based)
  std::string lang;     // first word of the info string
  std::string harness;  // test=NAME ("" for plain `test`)
  std::string code;
  std::string where() const { return file + ":" + std::to_string(line); }
};

// Fenced blocks (``` at the start of a line, optionally indented) of one Markdown text whose info string
// holds the word `test` or `test=NAME`. An unterminated fence is an error (reported as a block with lang
// "!").
std::vector<Snippet> extract_snippets(const std::string& text, const std::string& file) {
  std::vector<Snippet> out;
  std::istringstream in(text);
  std::string line;
  int n = 0;
  bool inside = false;
  Snippet cur;
  bool tested = false;
  static const std::regex open(R"(^\s*```\s*(\S.*)?$)");
  while (std::getline(in, line)) {
    ++n;
    std::smatch m;
    if (!inside) {
      if (!std::regex_match(line, m, open)) continue;
      inside = true;
      cur = Snippet{file, n, "", "", ""};
      tested = false;
      std::istringstream words(m[1].str());
      std::string w;
      words >> cur.lang;
      while (words >> w) {
        if (w == "test")
          tested = true;
        else if (w.rfind("test=", 0) == 0)
          tested = true, cur.harness = w.substr(5);
      }
    } else if (std::regex_match(line, std::regex(R"(^\s*```\s*$)"))) {
      inside = false;
      if (tested) out.push_back(cur);
    } else {
      cur.code += line + "\n";
    }
  }
  if (inside) out.push_back(Snippet{file, cur.line, "!", "", "unterminated fence"});
  return out;
}

std::string read_text(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

const std::vector<Snippet>& all_snippets() {
  static const std::vector<Snippet> all = [] {
    const fs::path src = MSH_SOURCE_DIR;
    std::vector<std::string> files = {"README.md"};
    std::vector<std::string> docs;
    for (const auto& e : fs::directory_iterator(src / "docs"))
      if (e.path().extension() == ".md") docs.push_back("docs/" + e.path().filename().string());
    std::sort(docs.begin(), docs.end());
    files.insert(files.end(), docs.begin(), docs.end());
    std::vector<Snippet> v;
    for (const std::string& f : files) {
      auto s = extract_snippets(read_text(src / f), f);
      v.insert(v.end(), s.begin(), s.end());
    }
    return v;
  }();
  return all;
}

std::vector<Snippet> snippets(const std::string& lang) {
  std::vector<Snippet> v;
  for (const Snippet& s : all_snippets())
    if (s.lang == lang) v.push_back(s);
  return v;
}

// ---- processes and the install prefix
// ------------------------------------------------------------------------

struct Proc {
  int rc = -1;
  std::string out;  // stdout + stderr
};

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

Proc run_cmd(const std::string& cmd) {
  Proc r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t k;
  while ((k = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, k);
  const int st = pclose(p);
  r.rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// A value of the build's CMakeCache.txt ("" if absent).
std::string cache_value(const std::string& key) {
  std::istringstream in(read_text(fs::path(MSH_BINARY_DIR) / "CMakeCache.txt"));
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(':'), eq = line.find('=');
    if (colon != std::string::npos && eq != std::string::npos && line.substr(0, colon) == key)
      return line.substr(eq + 1);
  }
  return "";
}

fs::path make_temp_dir(const std::string& tag) {
  const char* t = std::getenv("TMPDIR");
  std::string tmpl = std::string(t && *t ? t : "/tmp") + "/msh_doc_" + tag + "_XXXXXX";
  std::vector<char> b(tmpl.begin(), tmpl.end());
  b.push_back('\0');
  if (!mkdtemp(b.data())) return {};
  return fs::path(b.data());
}

// One `cmake --install` of this build into a temporary prefix, shared by the C++ and CMake snippet tests and
// removed at exit.
struct Prefix {
  fs::path root, prefix;
  std::string error;
  ~Prefix() {
    std::error_code ec;
    if (!root.empty()) fs::remove_all(root, ec);
  }
};
const Prefix& install_prefix() {
  static Prefix p = [] {
    Prefix x;
    x.root = make_temp_dir("prefix");
    x.prefix = x.root / "prefix";
    const Proc r = run_cmd(quote(cache_value("CMAKE_COMMAND")) + " --install " + quote(MSH_BINARY_DIR) +
                           " --prefix " + quote(x.prefix.string()));
    if (r.rc != 0) x.error = "cmake --install failed:\n" + r.out;
    return x;
  }();
  return p;
}

// A sanitizer build's library needs the sanitizer runtime in every program linked against it (as
// tests/package/consumer_test.cmake does) and preloaded into the Python interpreter (as test_python does).
bool sanitized() {
  const std::string v = cache_value("MSH_SANITIZE");
  return v == "ON" || v == "TRUE" || v == "1" || v == "YES";
}
std::string sanitize_flags() { return sanitized() ? "-fsanitize=address,undefined " : ""; }
std::string python_sanitizer_env() {
  if (!sanitized()) return "";
  const std::string cxx = quote(cache_value("CMAKE_CXX_COMPILER"));
  auto lib = [&](const char* name) {
    std::string p = run_cmd(cxx + " -print-file-name=" + name).out;
    while (!p.empty() && (p.back() == '\n' || p.back() == ' ')) p.pop_back();
    return p;
  };
  return "LD_PRELOAD=" + quote(lib("libasan.so") + " " + lib("libubsan.so")) +
         " ASAN_OPTIONS=detect_leaks=0 ";
}

fs::path tables_dir() { return fs::path(MSH_BINARY_DIR) / "share/microshadow/tables"; }

// A fresh directory with the installed default tables, where C++ snippets run.
fs::path run_dir_with_tables() {
  const fs::path d = make_temp_dir("run");
  for (const auto& e : fs::directory_iterator(tables_dir())) fs::copy_file(e.path(), d / e.path().filename());
  return d;
}

// ---- shader harnesses
// ------------------------------------------------------------------------------------------

// The block with each `#include "X"` line replaced by shaders/<lang>/X with its own includes expanded.
std::string expand_includes(const std::string& code, const std::string& lang) {
  static const std::regex inc(R"(^\s*#\s*include\s*"([^"]+)\"[^\n]*$)");
  std::istringstream in(code);
  std::string line, out;
  while (std::getline(in, line)) {
    std::smatch m;
    if (std::regex_match(line, m, inc))
      out += msh::test::vk::read_source("shaders/" + lang + "/" + m[1].str()) + "\n";
    else
      out += line + "\n";
  }
  return out;
}

// The complete compute shader of a glsl/hlsl block in its harness; "" for an unknown harness.
std::string harness_source(const Snippet& s) {
  const std::string code = expand_includes(s.code, s.lang);
  if (s.harness == "ms-lut" && s.lang == "glsl")
    // The drop-in's functions (the block: includes, samplers at bindings 2 and 3, functions), called per
    // record.
    return "#version 450\n" + code + R"(
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer B0 { vec4 rec[]; };
layout(std430, binding = 1) writeonly buffer B1 { vec4 o[]; };
layout(push_constant) uniform PC { uint n; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  vec4 a = rec[6u * i];  // (vis, roughness, -, -)
  vec3 v = rec[6u * i + 1u].xyz, l = rec[6u * i + 2u].xyz;
  vec3 t = rec[6u * i + 3u].xyz, b = rec[6u * i + 4u].xyz, nn = rec[6u * i + 5u].xyz;
  o[i] = vec4(microShadowing(a.x, v, l, t, b, nn, a.y), microShadowingAzimuth(a.x, v, l, t, b, nn, a.y), 0.0, 0.0);
}
)";
  if (s.harness == "ms-lut" && s.lang == "hlsl")
    return code + R"(
[[vk::binding(0)]] StructuredBuffer<float4> rec;
[[vk::binding(1)]] RWStructuredBuffer<float4> o;
struct PC { uint n; };
[[vk::push_constant]] PC pc;
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
  uint i = id.x;
  if (i >= pc.n) return;
  float4 a = rec[6u * i];
  float3 v = rec[6u * i + 1u].xyz, l = rec[6u * i + 2u].xyz;
  float3 t = rec[6u * i + 3u].xyz, b = rec[6u * i + 4u].xyz, nn = rec[6u * i + 5u].xyz;
  o[i] = float4(microShadowing(a.x, v, l, t, b, nn, a.y), microShadowingAzimuth(a.x, v, l, t, b, nn, a.y), 0.0, 0.0);
}
)";
  if (s.harness == "directional" && s.lang == "glsl")
    // The block is a per-pixel body: the user's textures, ranges and vectors are declared around it.
    return "#version 450\n" + msh::test::vk::read_source("shaders/glsl/directional.glsl") + R"(
layout(local_size_x = 1) in;
layout(binding = 0) uniform sampler2D dir0;
layout(binding = 1) uniform sampler2D dir1;
layout(binding = 2) uniform sampler2D dir8;
layout(std430, binding = 3) buffer B { vec4 io[]; };
const float PI = 3.14159265358979;
void main() {
  vec2 uv = io[0].xy;
  vec4 lo0 = io[1], hi0 = io[2], lo1 = io[3], hi1 = io[4];
  float lo8 = io[5].x, hi8 = io[5].y, albedo = io[5].z, E = io[5].w;
  vec3 l = io[6].xyz, n = io[7].xyz;
)" + code + R"(
  io[8] = vec4(diffuse);
}
)";
  return "";
}

// ---- the installed tables as RGBA32F textures
// -------------------------------------------------------------------

struct Table {
  msh::lut::MicroShadowingLut lut;
  std::vector<float> rgba;
  msh::test::vk::Context::Image image() const {
    return {uint32_t(lut.volume.width), uint32_t(lut.volume.height), uint32_t(lut.volume.depth), rgba.data()};
  }
};
Table load_table(const std::string& name) {
  Table t;
  t.lut = msh::lut::load_micro_shadowing_lut(tables_dir() / name);
  const msh::io::Volume& v = t.lut.volume;
  const std::size_t texels = std::size_t(v.width) * v.height * v.depth;
  t.rgba.assign(texels * 4, 0.0f);
  for (std::size_t i = 0; i < texels; ++i)
    for (int c = 0; c < v.channels && c < 4; ++c) t.rgba[4 * i + c] = v.data[i * v.channels + c];
  return t;
}

}  // namespace

TEST(DocSnippets, ExtractorFindsMarkedFences) {
  const std::string md =
      "text\n```cpp\nint not_tested;\n```\n\n```cpp test\nint main() { return 0; }\n```\n  ```glsl "
      "test=ms-lut\n"
      "float x;\n  ```\n```python\n```\n```cmake test\nfind_package(x)\n```\n```\nplain\n```\n";
  const auto v = extract_snippets(md, "x.md");
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].lang, "cpp");
  EXPECT_EQ(v[0].line, 6);
  EXPECT_EQ(v[0].code, "int main() { return 0; }\n");
  EXPECT_EQ(v[1].lang, "glsl");
  EXPECT_EQ(v[1].harness, "ms-lut");
  EXPECT_EQ(v[1].line, 9);
  EXPECT_EQ(v[2].lang, "cmake");
  EXPECT_EQ(v[2].where(), "x.md:14");
  const auto bad = extract_snippets("```cpp test\nint x;\n", "y.md");
  ASSERT_EQ(bad.size(), 1u);
  EXPECT_EQ(bad[0].lang, "!");
}

// Every marked block is of a language this test runs, shader blocks name a known harness, and each language
// has the blocks the docs promise (a marker lost in an edit fails here, not silently).
TEST(DocSnippets, EveryMarkedBlockIsRunnable) {
  std::map<std::string, int> count;
  for (const Snippet& s : all_snippets()) {
    ++count[s.lang];
    const bool known =
        s.lang == "cpp" || s.lang == "python" || s.lang == "cmake" || s.lang == "glsl" || s.lang == "hlsl";
    EXPECT_TRUE(known) << s.where() << ": a block marked `test` in language '" << s.lang
                       << "' (tested: cpp, python, cmake, glsl, hlsl)"
                       << (s.lang == "!" ? ": unterminated" : "");
    if (s.lang == "glsl" || s.lang == "hlsl") {
      EXPECT_FALSE(harness_source(s).empty()) << s.where() << ": unknown harness test=" << s.harness;
    }
  }
  std::printf("[ snippets ] cpp %d, python %d, cmake %d, glsl %d, hlsl %d\n", count["cpp"], count["python"],
              count["cmake"], count["glsl"], count["hlsl"]);
  EXPECT_GE(count["cpp"], 3);
  EXPECT_GE(count["python"], 1);
  EXPECT_GE(count["cmake"], 2);
  EXPECT_GE(count["glsl"], 2);
  EXPECT_GE(count["hlsl"], 1);
  int drop_ins = 0;
  for (const Snippet& s : all_snippets()) drop_ins += s.harness == "ms-lut";
  EXPECT_EQ(drop_ins, 2) << "the micro-shadowing drop-in in GLSL and HLSL (docs/shaders.md)";
}

// Every block of any language that calls a seed-layout sampler says so: the installed tables are cone layout.
TEST(DocSnippets, SeedLayoutSamplersOnlyWhereSeedLayoutIsSaid) {
  const fs::path src = MSH_SOURCE_DIR;
  std::vector<fs::path> files = {src / "README.md"};
  for (const auto& e : fs::directory_iterator(src / "docs"))
    if (e.path().extension() == ".md") files.push_back(e.path());
  static const std::regex seed(R"(msh_ms_lut_sample(_2d|_azimuth)?\s*\()");
  for (const fs::path& f : files) {
    std::istringstream in(read_text(f));
    std::string line, block;
    int n = 0, start = 0;
    bool inside = false;
    while (std::getline(in, line)) {
      ++n;
      if (line.find("```") != std::string::npos && line.find_first_not_of(" ") == line.find("```")) {
        if (inside && std::regex_search(block, seed)) {
          EXPECT_NE(block.find("seed"), std::string::npos)
              << f.lexically_relative(src).string() << ":" << start
              << ": a code block calls a seed-layout sampler on (by default) a "
              << "cone-layout table; use msh_ms_lut_sample_cone* or say the table is --layout seed";
        }
        inside = !inside, start = n, block.clear();
      } else if (inside) {
        block += line + "\n";
      }
    }
  }
}

TEST(DocSnippets, ShaderBlocksCompile) {
  ASSERT_FALSE(msh::test::vk::glslang_validator().empty()) << "glslangValidator missing";
  for (const std::string lang : {"glsl", "hlsl"})
    for (const Snippet& s : snippets(lang)) {
      const std::string src = harness_source(s);
      if (src.empty()) continue;  // reported by EveryMarkedBlockIsRunnable
      std::vector<uint32_t> spv;
      std::string log;
      const auto l = lang == "glsl" ? msh::test::vk::Lang::kGlsl : msh::test::vk::Lang::kHlsl;
      EXPECT_TRUE(msh::test::vk::compile_shader(src, l, &spv, &log)) << s.where() << " (" << lang << ")\n"
                                                                     << log;
      EXPECT_GT(spv.size(), 100u) << s.where();
    }
}

// The micro-shadowing drop-in, as pasted, on lavapipe with the installed default tables, against the C++
// sampler on the same tables and inputs. Tolerance 2/255 (what an 8-bit target cannot tell apart); the
// measured difference is printed (float rounding of the same arithmetic: ~1e-7).
TEST(DocSnippets, MicroShadowingDropInMatchesCppOnInstalledTables) {
  namespace vk = msh::test::vk;
  const Table plain = load_table("micro_shadowing.ktx2"), az = load_table("micro_shadowing_azimuth.ktx2"),
              two_d = load_table("micro_shadowing_2d.ktx2");
  ASSERT_EQ(plain.lut.layout, msh::lut::LutLayout::Cone);
  ASSERT_EQ(az.lut.layout, msh::lut::LutLayout::Cone);
  ASSERT_EQ(az.lut.harmonics, 3);
  // The block hard-codes the slab count: it must be the installed tables'.
  for (const Table* t : {&plain, &az, &two_d}) ASSERT_EQ(t->lut.n_rough, 16);

  // Inputs: a random shading frame, view and light mostly above the surface (some below and grazing), vis in
  // [0, 1], roughness in [0, 1.1] (outside the table's range too).
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  using V3 = msh::Vec3<float>;
  auto unit = [&] {
    for (;;) {
      V3 p(2 * u(rng) - 1, 2 * u(rng) - 1, 2 * u(rng) - 1);
      const float l = std::sqrt(dot(p, p));
      if (l > 0.1f && l < 1.0f) return p / l;
    }
  };
  struct Rec {
    float vis, rough;
    V3 v, l, t, b, n;
  };
  std::vector<Rec> recs;
  for (int i = 0; i < 8192; ++i) {
    const V3 n = unit(), t0 = unit();
    const V3 t = normalize(t0 - n * dot(n, t0)), b = cross(n, t);
    V3 v = unit(), l = unit();
    if (i % 8 != 0) {  // 7 in 8 above the surface
      if (dot(v, n) < 0) v = v - n * (2 * dot(v, n));
      if (dot(l, n) < 0) l = l - n * (2 * dot(l, n));
    }
    recs.push_back({u(rng), 1.1f * u(rng), v, l, t, b, n});
  }
  std::vector<float> in;
  for (const Rec& r : recs) {
    in.insert(in.end(), {r.vis, r.rough, 0, 0});
    for (const V3* w : {&r.v, &r.l, &r.t, &r.b, &r.n}) in.insert(in.end(), {w->x, w->y, w->z, 0});
  }

  std::string why;
  vk::Context* ctx = vk::Context::get(&why);
  if (!ctx) GTEST_SKIP() << "no Vulkan compute device: " << why;
  const double tol = 2.0 / 255.0;
  for (const std::string lang : {"glsl", "hlsl"})
    for (const Snippet& s : snippets(lang)) {
      if (s.harness != "ms-lut") continue;
      for (const Table* msLut : {&plain, &two_d}) {
        vk::Dispatch d;
        d.buffers = {in, std::vector<float>(recs.size() * 4)};
        d.images = {msLut->image(), az.image()};
        d.push = vk::push_constants(uint32_t(recs.size()));
        d.invocations = recs.size();
        vk::Buffers out;
        ASSERT_TRUE(vk::run(*ctx, harness_source(s), lang == "glsl" ? vk::Lang::kGlsl : vk::Lang::kHlsl, d,
                            &out, &why))
            << s.where() << ": " << why;
        const auto pv = msLut->lut.view(), av = az.lut.view();
        double e_plain = 0, e_az = 0;
        int zeros = 0, lit = 0;
        for (std::size_t i = 0; i < recs.size(); ++i) {
          const Rec& r = recs[i];
          const V3 V(dot(r.v, r.t), dot(r.v, r.b), dot(r.v, r.n)),
              L(dot(r.l, r.t), dot(r.l, r.b), dot(r.l, r.n));
          const float m = msh::lut::sample_micro_shadowing<float>(pv, r.vis, L.z, V.z, r.rough);
          const float a = msh::lut::sample_micro_shadowing_azimuth<float>(
              av, r.vis, L.z, V.z, r.rough, msh::lut::relative_azimuth_cos(V, L));
          const float gm = out[1][4 * i], ga = out[1][4 * i + 1];
          ASSERT_TRUE(std::isfinite(gm) && std::isfinite(ga)) << s.where() << " record " << i;
          e_plain = std::max(e_plain, double(std::abs(gm - m)));
          e_az = std::max(e_az, double(std::abs(ga - a)));
          zeros += m == 0 && gm == 0;
          lit += m > 0.05f && m < 0.95f;
        }
        const char* table = msLut == &plain ? "micro_shadowing.ktx2" : "micro_shadowing_2d.ktx2";
        EXPECT_LE(e_plain, tol) << s.where() << " " << lang << " " << table;
        EXPECT_LE(e_az, tol) << s.where() << " " << lang << " micro_shadowing_azimuth.ktx2";
        EXPECT_GT(zeros, 1000) << s.where();  // the early-out region is exercised
        EXPECT_GT(lit, 1000) << s.where();    // and the partially lit one
        std::printf(
            "[ %s ] %s, %zu inputs on %s: max |shader - C++| %s %.2e (%.4f/255), azimuth %.2e "
            "(%.4f/255); %d zeros, %d in (0.05, 0.95)\n",
            lang.c_str(), s.where().c_str(), recs.size(), ctx->device_name().c_str(), table, e_plain,
            e_plain * 255, e_az, e_az * 255, zeros, lit);
      }
    }
}

TEST(DocSnippets, CppBlocksCompileAndRun) {
  const auto blocks = snippets("cpp");
  ASSERT_FALSE(blocks.empty());
  const Prefix& p = install_prefix();
  ASSERT_TRUE(p.error.empty()) << p.error;
  fs::path pcdir;
  for (const auto& e : fs::recursive_directory_iterator(p.prefix))
    if (e.path().filename() == "microshadow.pc") pcdir = e.path().parent_path();
  ASSERT_FALSE(pcdir.empty()) << "microshadow.pc not installed";
  const Proc flags =
      run_cmd("PKG_CONFIG_PATH=" + quote(pcdir.string()) + " pkg-config --cflags --libs microshadow");
  ASSERT_EQ(flags.rc, 0) << flags.out;
  std::string f = flags.out;
  while (!f.empty() && (f.back() == '\n' || f.back() == ' ')) f.pop_back();
  const std::string cxx = cache_value("CMAKE_CXX_COMPILER");
  const Proc ccache = run_cmd("command -v ccache");
  const std::string launcher = ccache.rc == 0 ? "CCACHE_BASEDIR=/ ccache " : "";
  const fs::path dir = run_dir_with_tables();
  int i = 0;
  for (const Snippet& s : blocks) {
    const std::string base = "snippet" + std::to_string(i++);
    // Diagnostics name the Markdown file and line.
    std::ofstream(dir / (base + ".cpp")) << "#line " << s.line + 1 << " \"" << s.file << "\"\n" << s.code;
    const bool has_main = std::regex_search(s.code, std::regex(R"(\bint\s+main\s*\()"));
    const std::string cmd = "cd " + quote(dir.string()) + " && " + launcher + quote(cxx) +
                            " -std=c++20 -O1 -Wall -Wextra -Werror " + sanitize_flags() +
                            (has_main ? "" : "-c ") + base + ".cpp -o " + base + (has_main ? " " + f : ".o");
    const Proc c = run_cmd(cmd);
    EXPECT_EQ(c.rc, 0) << s.where() << ": does not compile\n" << cmd << "\n" << c.out;
    if (c.rc != 0 || !has_main) continue;
    const Proc r = run_cmd("cd " + quote(dir.string()) + " && ./" + base);
    EXPECT_EQ(r.rc, 0) << s.where() << ": exits " << r.rc << "\n" << r.out;
    std::printf("[ cpp ] %s: ok%s", s.where().c_str(),
                r.out.empty() ? "\n" : (", prints:\n" + r.out).c_str());
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

TEST(DocSnippets, PythonBlocksRun) {
  const auto blocks = snippets("python");
  ASSERT_FALSE(blocks.empty());
  std::string py = cache_value("Python_EXECUTABLE");
  if (py.empty()) py = "python3";
  const fs::path dir = make_temp_dir("py");
  int i = 0;
  for (const Snippet& s : blocks) {
    const fs::path f = dir / ("snippet" + std::to_string(i++) + ".py");
    std::ofstream(f) << std::string(std::size_t(s.line), '\n') << s.code;  // line numbers = the doc's
    const Proc r =
        run_cmd("cd " + quote(MSH_SOURCE_DIR) + " && " + python_sanitizer_env() +
                "PYTHONDONTWRITEBYTECODE=1 PYTHONPATH=" + quote(std::string(MSH_BINARY_DIR) + "/python") +
                " " + quote(py) + " " + quote(f.string()));
    EXPECT_EQ(r.rc, 0) << s.where() << " (the traceback's line numbers are the doc's)\n" << r.out;
    std::printf("[ python ] %s: %s\n", s.where().c_str(), r.rc == 0 ? "ok" : "FAILED");
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

TEST(DocSnippets, CmakeBlocksConfigureBuildAndRun) {
  const auto blocks = snippets("cmake");
  ASSERT_FALSE(blocks.empty());
  const Prefix& p = install_prefix();
  ASSERT_TRUE(p.error.empty()) << p.error;
  const std::string cmake = quote(cache_value("CMAKE_COMMAND"));
  const Proc ccache = run_cmd("command -v ccache");
  const std::string launcher = ccache.rc == 0 ? " -DCMAKE_CXX_COMPILER_LAUNCHER=ccache" : "";
  const fs::path dir = make_temp_dir("cmake");
  int i = 0;
  for (const Snippet& s : blocks) {
    const fs::path proj = dir / ("snippet" + std::to_string(i++));
    fs::create_directories(proj);
    // The block's targets: an engine program on <microshadow/engine.h> alone and a tool that uses the library
    // (it reads the installed default table).
    std::ofstream(proj / "engine.cpp") << "#include <microshadow/engine.h>\n#include <cstdio>\n"
                                          "int main() { std::printf(\"engine ok\\n\"); return 0; }\n";
    std::ofstream(proj / "tool.cpp")
        << "#include <microshadow/lut/runtime/micro_shadowing_loader.h>\n#include <cstdio>\n"
           "int main(int, char** argv) {\n"
           "  const auto lut = msh::lut::load_micro_shadowing_lut(argv[1]);\n"
           "  std::printf(\"tool %.6f\\n\", msh::lut::sample_micro_shadowing<float>(lut.view(), 0.6f, 0.4f, "
           "0.8f, "
           "0.5f));\n  return 0;\n}\n";
    std::ofstream(proj / "CMakeLists.txt")
        << "cmake_minimum_required(VERSION 3.25)\nproject(doc_snippet CXX)\n"
           "set(CMAKE_CXX_STANDARD 20)\nadd_executable(my_engine engine.cpp)\n"
           "add_executable(my_tool tool.cpp)\n"
        << "# " << s.where() << "\n"
        << s.code;
    const Proc c =
        run_cmd(cmake + " -S " + quote(proj.string()) + " -B " + quote((proj / "build").string()) +
                " -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + quote(p.prefix.string()) +
                " -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_CXX_COMPILER=" +
                quote(cache_value("CMAKE_CXX_COMPILER")) + launcher +
                (sanitized() ? " -DCMAKE_CXX_FLAGS=-fsanitize=address,undefined "
                               "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=address,undefined"
                             : ""));
    ASSERT_EQ(c.rc, 0) << s.where() << ": configure failed\n" << c.out;
    const Proc b = run_cmd(cmake + " --build " + quote((proj / "build").string()));
    ASSERT_EQ(b.rc, 0) << s.where() << ": build failed\n" << b.out;
    const Proc e = run_cmd(quote((proj / "build/my_engine").string()));
    EXPECT_EQ(e.rc, 0) << s.where() << e.out;
    const Proc t = run_cmd(quote((proj / "build/my_tool").string()) + " " +
                           quote((p.prefix / "share/microshadow/tables/micro_shadowing.ktx2").string()));
    EXPECT_EQ(t.rc, 0) << s.where() << t.out;
    EXPECT_NE(t.out.find("tool 0."), std::string::npos) << s.where() << t.out;
    std::printf("[ cmake ] %s: configured, built, ran: %s", s.where().c_str(), t.out.c_str());
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}
