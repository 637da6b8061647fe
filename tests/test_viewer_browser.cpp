// The browser viewer (`microshadow view`, docs/viewer.md). Server: refuses non-loopback hosts, a port in use,
// a missing texture set and tables the shaders cannot sample (exit 2, one line); exports a static copy and
// serves it with --root; stops cleanly (exit 0) on SIGINT. Browser: headless Debian chromium with SwiftShader
// WebGL2, driven by tests/browser/viewer_test.mjs (playwright-core, `npm ci` in tests/browser by
// scripts/install-deps.sh): it loads the page, switches through every method, probes fixed configurations and
// this test compares each method's shader value at the probe's own inputs (V, N·L, N·V, roughness, cos φ, v,
// l read back from float32 render targets) with the C++ library, in float and as 8-bit output; no console
// errors; error banners for a missing WebGL2 and a failed fetch. The method list (methods.js) is generated
// from the runtime registry, pairs included (each lobe checked against eval_lobes); the server answers only
// requests whose Host header names it (DNS rebinding). Fails without chromium/node/playwright-core unless
// MSH_ALLOW_NO_BROWSER=1 (then skips), as the shader tests do without Vulkan.
#include <Imath/half.h>
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <microshadow/lut/runtime/micro_shadowing_analysis.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/texture_gen.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <thread>

#include "../src/view/shader_source.h"
#include "../src/view/viewer_server.h"
#include "support/cli_test_util.h"
#include "support/view_server_util.h"

namespace fs = std::filesystem;
using namespace msh;
using msh::test::run_cli;
using msh::test::scratch_dir;
using msh::test::slurp;

namespace {

const fs::path kBrowserDir = fs::path(MSH_SOURCE_DIR) / "tests" / "browser";
// The built-in plaster is generated once into this cache (a few CPU-seconds) and reused by later runs.
const fs::path kCache = fs::path(MSH_BINARY_DIR) / "viewer_cache";

std::string missing_browser() { return msh::test::missing_browser_driver(kBrowserDir); }
#define REQUIRE_BROWSER() MSH_REQUIRE_BROWSER(missing_browser())

int count_lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

using msh::test::chromium_path;
using msh::test::http_get;
using msh::test::http_get_host;
using msh::test::url_port;
using Server = msh::test::ViewServer;
Server start_server(const std::vector<std::string>& args, const fs::path& dir) {
  return msh::test::start_view(args, dir);
}
int stop_server(Server& s, int sig = SIGINT) { return msh::test::stop_view(s, sig); }

// A small cone-layout table (2 roughness slabs, 4 x 4 x 2 texels) at `out`; the CLI's exit code.
int bake_small_cone_table(const fs::path& out) {
  return run_cli(
             "bake micro-shadowing --size-t 4 --size-nl 4 --size-nv 2 --roughness-slabs 2 --samples 16 "
             "--phi-nodes 2 --quiet --out " +
                 out.string(),
             out.parent_path())
      .code;
}

TEST(ViewerServer, RefusesNonLoopbackHosts) {
  const fs::path dir = scratch_dir("viewer");
  for (const char* host : {"0.0.0.0", "192.168.1.10", "::", "example.com", "128.0.0.1"}) {
    const auto r = run_cli(std::string("view --port 0 --host ") + host, dir);
    EXPECT_EQ(r.code, 2) << host;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("loopback"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

TEST(ViewerServer, RefusesAPortInUse) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
  ASSERT_EQ(listen(fd, 1), 0);
  socklen_t len = sizeof(a);
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  const int port = ntohs(a.sin_port);
  const auto r =
      run_cli("view --port " + std::to_string(port) + " --cache " + kCache.string(), scratch_dir("viewer"));
  close(fd);
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("in use"), std::string::npos) << r.err;
}

TEST(ViewerServer, RefusesBadTexturesAndTables) {
  const fs::path dir = scratch_dir("viewer");
  auto expect_one_line = [&](const std::string& args, const std::string& what) {
    const auto r = run_cli("view --port 0 --cache " + kCache.string() + " " + args, dir);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
  };
  expect_one_line("--material " + (dir / "nothing").string(), "no material.json");
  // A texture set whose normal map is missing.
  ASSERT_EQ(
      run_cli("gen-material --kind plaster --size 16 --ao-rays 2 --out " + (dir / "m").string(), dir).code,
      0);
  fs::remove(dir / "m" / "normal.png");
  expect_one_line("--material " + (dir / "m").string(), "normal texture");
  // A seed-layout table (the viewer's GLSL samples the cone layout) and a cone table whose sidecar does not
  // match the file.
  ASSERT_EQ(run_cli("bake micro-shadowing --layout seed --size 4 --samples 16 --phi-nodes 2 --quiet --out " +
                        (dir / "seed.npy").string(),
                    dir)
                .code,
            0);
  expect_one_line("--lut " + (dir / "seed.npy").string(), "seed-layout");
  ASSERT_EQ(bake_small_cone_table(dir / "cone.npy"), 0);
  std::string side = slurp(dir / "cone.npy.json");
  const auto p = side.find("\"size_n_dot_l\"");
  ASSERT_NE(p, std::string::npos) << side;
  side.replace(side.find(':', p) + 1, side.find_first_of(",}", p) - side.find(':', p) - 1, " 9");
  std::ofstream(dir / "cone.npy.json") << side;
  expect_one_line("--lut " + (dir / "cone.npy").string(), "sidecar");
}

TEST(ViewerServer, ExportsAStaticCopyAndServesIt) {
  const fs::path dir = scratch_dir("viewer");
  const fs::path copy = dir / "viewer";
  const auto r = run_cli("view --export " + copy.string() + " --cache " + kCache.string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"index.html", "viewer.js", "methods.js", "bump_methods.js", "data/manifest.json",
                        "data/lut3d.f16", "data/material/micro_occlusion.png"})
    EXPECT_TRUE(fs::is_regular_file(copy / f)) << f;
  // The method list generated from the registry (the source tree has none).
  EXPECT_EQ(slurp(copy / "methods.js"), msh::view::methods_js(occlusion::micro_shadowing_methods()));
  EXPECT_FALSE(fs::exists(fs::path(MSH_SOURCE_DIR) / "web" / "methods.js"));
  // The GLSL files are the project's own with their includes expanded (the prelude and the portable body in
  // the text, no #include left: WebGL2 has none).
  const std::string ms = slurp(copy / "shaders/glsl/micro_shadowing.glsl");
  EXPECT_EQ(
      ms, msh::view::expand_shader_includes(fs::path(MSH_SOURCE_DIR) / "shaders/glsl/micro_shadowing.glsl"));
  EXPECT_EQ(ms.find("\n#include"), std::string::npos);
  EXPECT_NE(ms.find("#define MSH_PRELUDE_GLSL"), std::string::npos);
  EXPECT_NE(ms.find("float msh_ms_cone_cos(float vis)"), std::string::npos);
  const auto man = nlohmann::json::parse(slurp(copy / "data/manifest.json"));
  const auto& L = man["luts"]["lut3d"];
  EXPECT_EQ(fs::file_size(copy / "data/lut3d.f16"), std::size_t(L["size"][0].get<int>()) *
                                                        L["size"][1].get<int>() * L["size"][2].get<int>() *
                                                        L["channels"].get<int>() * 2);

  Server s = start_server({"--root", copy.string(), "--port", "0"}, dir);
  ASSERT_FALSE(s.url.empty());
  const auto [status, body] = http_get(s.url, "/data/manifest.json");
  EXPECT_NE(status.find("200"), std::string::npos) << status;
  EXPECT_EQ(nlohmann::json::parse(body)["glsl"], man["glsl"]);
  EXPECT_NE(http_get(s.url, "/../CMakeLists.txt").first.find("404"), std::string::npos);
  EXPECT_NE(http_get(s.url, "/data/nothing.bin").first.find("404"), std::string::npos);
  EXPECT_EQ(stop_server(s, SIGTERM), 0) << slurp(s.err);
}

// --lut FILE: a cone-layout table replaces the default of its kind (here the 3D one), served as its half
// floats.
// A texture set with directional channels: the page gets them as three RGBA16F layers per level of the box
// mip chain, level after level (docs/viewer.md); decoded here and compared with the NPY and its box mean.
TEST(ViewerServer, ServesTheDirectionalChannelsWithTheirMips) {
  const fs::path dir = scratch_dir("viewer");
  ASSERT_EQ(
      run_cli("gen-material --kind rock --size 32 --no-mips --out " + (dir / "rock").string(), dir).code, 0);
  const auto r =
      run_cli("view --export " + (dir / "v").string() + " --material " + (dir / "rock").string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto man = nlohmann::json::parse(slurp(dir / "v" / "data" / "manifest.json"));
  ASSERT_TRUE(man["material"].contains("directional")) << man["material"].dump();
  const auto& d = man["material"]["directional"];
  EXPECT_EQ(d["layers"].get<int>(), 3);
  ASSERT_EQ(d["levels"].size(), 6u);  // 32² … 1²
  const std::string blob = slurp(dir / "v" / d["url"].get<std::string>());
  const render::Texture fine = render::load_directional_channels(dir / "rock" / "directional.npy");
  const auto chain = render::box_mip_chain(fine);
  std::size_t off = 0, total = 0;
  for (const auto& l : d["levels"]) total += std::size_t(l[0].get<int>()) * l[1].get<int>() * 3 * 4 * 2;
  ASSERT_EQ(blob.size(), total);
  const auto half_at = [&](std::size_t i) {
    const uint16_t b = uint16_t(uint8_t(blob[2 * i])) | uint16_t(uint16_t(uint8_t(blob[2 * i + 1])) << 8);
    Imath::half h;
    h.setBits(b);
    return float(h);
  };
  double worst = 0;
  for (std::size_t level = 0; level < chain.size(); ++level) {
    const render::Texture& t = chain[level];
    ASSERT_EQ(d["levels"][level][0].get<int>(), t.width());
    for (int layer = 0; layer < 3; ++layer)
      for (int y = 0; y < t.height(); ++y)
        for (int x = 0; x < t.width(); ++x)
          for (int c = 0; c < 4; ++c, ++off) {
            const int k = 4 * layer + c;
            const float want = k < 9 ? t.at(x, y, k) : 0.0f;
            worst = std::max(worst, double(std::abs(half_at(off) - want)) / std::max(1e-3f, std::abs(want)));
          }
  }
  EXPECT_LE(worst, 1.0 / 2048) << "not the half-float rounding of the channels and their box mips";
  // A broken directional file is one line, exit 2.
  std::ofstream(dir / "rock" / "directional.npy", std::ios::trunc) << "not an npy";
  const auto bad =
      run_cli("view --export " + (dir / "w").string() + " --material " + (dir / "rock").string(), dir);
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(count_lines(bad.err), 1) << bad.err;
  EXPECT_NE(bad.err.find("directional.npy"), std::string::npos) << bad.err;
}

TEST(ViewerServer, UsesAGivenConeTable) {
  const fs::path dir = scratch_dir("viewer");
  ASSERT_EQ(bake_small_cone_table(dir / "cone.npy"), 0);
  const auto r = run_cli("view --export " + (dir / "v").string() + " --cache " + kCache.string() + " --lut " +
                             (dir / "cone.npy").string(),
                         dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto man = nlohmann::json::parse(slurp(dir / "v" / "data" / "manifest.json"));
  EXPECT_EQ(man["luts"]["lut3d"]["source"], (dir / "cone.npy").string());
  EXPECT_EQ(man["luts"]["lut3d"]["size"], nlohmann::json({4, 4, 4}));
  EXPECT_EQ(man["luts"]["lut3d"]["roughness_slabs"], 2);
  EXPECT_EQ(fs::file_size(dir / "v" / "data" / "lut3d.f16"), 4u * 4 * 4 * 2);
  EXPECT_EQ(slurp(dir / "v" / "data" / "lut3d.json"), slurp(dir / "cone.npy.json"));
  EXPECT_NE(man["luts"]["lut2d"]["source"].get<std::string>().find("default"), std::string::npos);
}

// The Host header must name the server (127.0.0.1, localhost or [::1] with its port): a page of another site
// reaching it through DNS rebinding sends its own name and gets 403, before any route.
TEST(ViewerServer, AnswersOnlyRequestsForItsOwnHost) {
  using msh::view::is_allowed_host_header;
  for (const char* h : {"127.0.0.1:8080", "localhost:8080", "LocalHost:8080", "[::1]:8080", "127.1.2.3:8080"})
    EXPECT_TRUE(is_allowed_host_header(h, 8080)) << h;
  for (const char* h :
       {"", "127.0.0.1", "localhost", "127.0.0.1:8081", "127.0.0.1:80800", "evil.example:8080",
        "localhost.evil.example:8080", "127.0.0.1.evil.example:8080", "[::2]:8080", "::1:8080", "[::1]8080",
        "0.0.0.0:8080", "128.0.0.1:8080", "127.0.0.1:8080 "})
    EXPECT_FALSE(is_allowed_host_header(h, 8080)) << h;
  EXPECT_TRUE(is_allowed_host_header("localhost", 80));  // browsers omit the default port

  const fs::path dir = scratch_dir("viewer");
  Server s = start_server({"--port", "0", "--cache", kCache.string()}, dir);
  ASSERT_FALSE(s.url.empty());
  const std::string port = std::to_string(url_port(s.url));
  for (const std::string& host : {"127.0.0.1:" + port, "localhost:" + port, "[::1]:" + port}) {
    const auto [status, body] = http_get_host(s.url, "/", host);
    EXPECT_NE(status.find(" 200"), std::string::npos) << host << ": " << status;
    EXPECT_NE(body.find("<canvas"), std::string::npos) << host;
  }
  for (const std::optional<std::string>& host :
       {std::optional<std::string>("evil.example:" + port), std::optional<std::string>("127.0.0.1:1"),
        std::optional<std::string>("127.0.0.1"), std::optional<std::string>()}) {
    for (const char* path : {"/", "/data/manifest.json", "/methods.js", "/no/such/file"}) {
      const auto [status, body] = http_get_host(s.url, path, host);
      EXPECT_NE(status.find(" 403"), std::string::npos) << host.value_or("(none)") << path << ": " << status;
      EXPECT_NE(body.find("forbidden"), std::string::npos) << body;
      EXPECT_LT(body.size(), 200u);
    }
  }
  // methods.js is the registry's list, generated per request.
  const auto [status, body] = http_get(s.url, "/methods.js");
  EXPECT_NE(status.find(" 200"), std::string::npos) << status;
  EXPECT_EQ(body, msh::view::methods_js(occlusion::micro_shadowing_methods()));
  EXPECT_EQ(stop_server(s, SIGTERM), 0) << slurp(s.err);
}

// The entries of a generated methods.js, by id (one JSON object per line).
std::map<std::string, nlohmann::json> methods_js_entries(const std::string& js) {
  std::map<std::string, nlohmann::json> r;
  std::size_t start = 0;
  while (start < js.size()) {
    const std::size_t end = std::min(js.find('\n', start), js.size());
    std::string line = js.substr(start, end - start);
    start = end + 1;
    if (line.rfind("  {", 0) != 0) continue;
    if (line.back() == ',') line.pop_back();
    const auto j = nlohmann::json::parse(line);
    EXPECT_EQ(r.count(j["id"]), 0u) << "duplicate id " << j["id"];
    r[j["id"]] = j;
  }
  return r;
}

// methods.js comes from the registry: one entry per GLSL form of each single term (the expressions the viewer
// had before, unchanged), one per pair whose terms both have a form (the lobes' expressions are the terms'
// first forms); a term added to the registry appears with no viewer edit.
TEST(ViewerServer, MethodsJsIsGeneratedFromTheRegistry) {
  const auto& reg = occlusion::micro_shadowing_methods();
  const std::string js = msh::view::methods_js(reg);
  EXPECT_NE(js.find("export const MICRO_SHADOWING_METHODS = ["), std::string::npos);
  const auto e = methods_js_entries(js);
  const std::map<std::string, std::string> before = {
      {"none", "1.0"},
      {"ao", "vis"},
      {"reference", "msh_ms_reference_step(vis, nl)"},
      {"brinck-maximov-2016", "msh_ms_brinck_maximov2016(vis, nl)"},
      {"chan-2018", "msh_ms_chan2018(vis, nl)"},
      {"part1-analytic", "msh_ms_part1_analytic(vis, nl)"},
      {"generic-vndf", "msh_ms_generic_vndf_estimate(vis, vec2(alpha), v, l, u_samples, true, 1u)"},
      {"generic-vndf-alu", "msh_ms_generic_vndf_alu(vis, nl, nv, rough)"},
      {"generic-vndf-alu-two-stage",
       "msh_ms_generic_vndf_alu_light(msh_ms_generic_vndf_alu_pixel(vis, nv, rough), nl)"},
      {"lut3d", "msh_ms_lut_sample_cone(u_lut3d, u_lut3d_slabs, vis, nl, nv, rough)"},
      {"lut2d", "msh_ms_lut_sample_cone(u_lut2d, u_lut2d_slabs, vis, nl, 1.0, rough)"},
      {"lut3d-azimuth",
       "msh_ms_lut_sample_cone_azimuth(u_lut_az, u_lut_az_slabs, u_lut_az_harmonics, vis, nl, nv, rough, "
       "cos_phi)"}};
  for (const auto& [id, glsl] : before) {
    ASSERT_EQ(e.count(id), 1u) << id;
    EXPECT_EQ(e.at(id)["glsl"], glsl) << id;
  }
  EXPECT_EQ(e.at("lut3d-azimuth")["lut"], "lut_azimuth");
  EXPECT_EQ(e.at("lut3d-azimuth")["cpp"], nlohmann::json({{"method", "lut3d"}, {"phi", true}}));
  EXPECT_EQ(e.at("generic-vndf")["cpp"],
            nlohmann::json({{"method", "generic-vndf"}, {"samples", true}, {"frame", true}}));
  EXPECT_EQ(e.at("generic-vndf-alu-two-stage")["cpp"],
            nlohmann::json({{"method", "generic-vndf-alu"}, {"two_stage", true}}));
  std::size_t n = 0;
  for (const auto& m : reg) {
    if (!m.is_pair()) {
      for (const auto& g : m.glsl) {
        ++n;
        ASSERT_EQ(e.count(m.form_id(g)), 1u) << m.form_id(g);
        EXPECT_EQ(e.at(m.form_id(g))["label"], m.label + g.label_suffix);
      }
      continue;
    }
    const auto* d = occlusion::find_micro_shadowing_method(m.diffuse);
    const auto* sp = occlusion::find_micro_shadowing_method(m.specular);
    const bool offered = !d->glsl.empty() && !sp->glsl.empty();
    EXPECT_EQ(e.count(m.name), offered ? 1u : 0u) << m.name;
    if (offered) {
      ++n;
      EXPECT_EQ(e.at(m.name)["glsl_diffuse"], d->glsl.front().expr);
      EXPECT_EQ(e.at(m.name)["glsl_specular"], sp->glsl.front().expr);
    }
  }
  EXPECT_EQ(e.size(), n);

  // A new term and pairs over the list: no viewer edit.
  auto more = reg;
  occlusion::MicroShadowingMethodInfo t;
  t.name = "test-term", t.label = "test term";
  occlusion::MicroShadowingGlsl tg;
  tg.expr = "msh_test(vis, nl)", tg.requires_fn = "msh_test", tg.lut = "lut2d";
  t.glsl.push_back(tg);
  more.push_back(t);
  occlusion::MicroShadowingMethodInfo p1;
  p1.name = "chan-2018+lut3d", p1.label = "test pair", p1.diffuse = "chan-2018", p1.specular = "lut3d";
  more.push_back(p1);
  occlusion::MicroShadowingMethodInfo p2 = p1;
  p2.name = "generic-vndf+specular-aware", p2.diffuse = "generic-vndf", p2.specular = "specular-aware";
  more.push_back(p2);
  const bool specular_has_glsl = !occlusion::find_micro_shadowing_method("specular-aware")->glsl.empty();
  const auto e2 = methods_js_entries(msh::view::methods_js(more));
  EXPECT_EQ(e2.size(), n + 2 + (specular_has_glsl ? 1 : 0));
  ASSERT_EQ(e2.count("test-term"), 1u);
  EXPECT_EQ(e2.at("test-term"), nlohmann::json({{"id", "test-term"},
                                                {"label", "test term"},
                                                {"glsl", "msh_test(vis, nl)"},
                                                {"requires", "msh_test"},
                                                {"lut", "lut2d"},
                                                {"cpp", {{"method", "test-term"}}}}));
  ASSERT_EQ(e2.count("chan-2018+lut3d"), 1u);
  const auto& pj = e2.at("chan-2018+lut3d");
  EXPECT_EQ(pj["glsl_diffuse"], before.at("chan-2018"));
  EXPECT_EQ(pj["glsl_specular"], before.at("lut3d"));
  EXPECT_EQ(pj["requires"], nlohmann::json({"msh_ms_chan2018", "msh_ms_lut_sample_cone"}));
  EXPECT_EQ(pj["lut"], nlohmann::json({"lut3d"}));
  EXPECT_EQ(pj["cpp"], nlohmann::json({{"method", "chan-2018+lut3d"},
                                       {"diffuse", {{"method", "chan-2018"}}},
                                       {"specular", {{"method", "lut3d"}}}}));
  EXPECT_EQ(e2.count("generic-vndf+specular-aware"), specular_has_glsl ? 1u : 0u);
}

// Every shaders/glsl/*.glsl file compiles as GLSL ES 3.00 (WebGL2), the way the page concatenates them (all
// files, sorted, includes expanded as the server sends them, one fragment shader), with glslangValidator: a
// check that needs no browser.
TEST(ViewerShaders, GlslFilesCompileAsGlslEs300) {
  const fs::path dir = scratch_dir("viewer");
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(fs::path(MSH_SOURCE_DIR) / "shaders" / "glsl"))
    if (e.path().extension() == ".glsl") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 3u);
  std::string src =
      "#version 300 es\nprecision highp float;\nprecision highp int;\nprecision highp sampler2D;\n"
      "precision highp sampler3D;\n";
  for (const auto& f : files) src += msh::view::expand_shader_includes(f) + "\n";
  src += "out vec4 o;\nvoid main() { o = vec4(1.0); }\n";
  std::ofstream(dir / "all.frag") << src;
  const int rc = std::system(
      ("glslangValidator " + (dir / "all.frag").string() + " > " + (dir / "log.txt").string() + " 2>&1")
          .c_str());
  EXPECT_EQ(rc, 0) << slurp(dir / "log.txt");
}

// ---- the browser ---------------------------------------------------------------------------------------

struct Stat {
  double max_float = 0, max_8bit = 0, max_vs_exact = 0;
  int n = 0;
};

// The page's method list: the registry's, plus GLSL forms for the registry terms that have none (their GLSL
// functions exist in shaders/glsl/; a form in the registry takes precedence) and test pairs, so that the
// pair path of the shader is checked whichever registry pairs have GLSL forms. The test pairs' names go to
// `test_pairs`.
std::vector<occlusion::MicroShadowingMethodInfo> page_methods(std::set<std::string>& test_pairs) {
  auto methods = occlusion::micro_shadowing_methods();
  const std::map<std::string, std::pair<std::string, std::string>> test_forms = {
      {"diffuse-aware-alu", {"msh_ms_diffuse_aware_alu(vis, nl, nv, rough)", "msh_ms_diffuse_aware_alu"}},
      {"specular-aware",
       {"msh_ms_specular_aware_azimuth_mean(vis, alpha, nl, nv)", "msh_ms_specular_aware_azimuth_mean"}}};
  for (auto& m : methods)
    if (const auto it = test_forms.find(m.name); it != test_forms.end() && m.glsl.empty()) {
      occlusion::MicroShadowingGlsl g;
      g.expr = it->second.first, g.requires_fn = it->second.second;
      m.glsl.push_back(g);
    }
  for (const auto& [d, sp] : {std::pair<std::string, std::string>{"chan-2018", "lut3d"},
                              std::pair<std::string, std::string>{"generic-vndf-alu", "generic-vndf"}}) {
    occlusion::MicroShadowingMethodInfo t;
    t.name = d + "+" + sp, t.label = "test pair " + t.name, t.diffuse = d, t.specular = sp;
    if (occlusion::find_micro_shadowing_method(t.name)) continue;
    methods.push_back(t);
    test_pairs.insert(t.name);
  }
  return methods;
}

// The page served with that list (the generator's output, as the server serves it for the registry alone:
// ViewerServer tests) and driven by viewer_test.mjs; its results.json in `res`.
void run_viewer(const fs::path& dir, const fs::path& shots,
                const std::vector<occlusion::MicroShadowingMethodInfo>& methods, nlohmann::json& res) {
  std::ofstream(dir / "methods.js") << msh::view::methods_js(methods);
  Server s = start_server({"--port", "0", "--cache", kCache.string()}, dir);
  ASSERT_FALSE(s.url.empty());
  const std::string cmd = "cd " + kBrowserDir.string() + " && node viewer_test.mjs --url " + s.url +
                          " --out " + shots.string() + " --chromium " + chromium_path() + " --methods " +
                          (dir / "methods.js").string() + " > " + (dir / "node.out").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  // Ctrl-C: a clean exit.
  EXPECT_EQ(stop_server(s), 0) << slurp(s.err);
  ASSERT_EQ(rc, 0) << slurp(dir / "node.out");
  res = nlohmann::json::parse(slurp(shots / "results.json"));
}

// The page loaded without errors, its banners say what fails, the shaded view is lit; every GLSL term the
// project has is offered (none dropped because its function or table went missing), and so is every method
// of the list (registry and test pairs) and every bump-terminator method.
void check_page_and_lists(const nlohmann::json& res,
                          const std::vector<occlusion::MicroShadowingMethodInfo>& methods) {
  EXPECT_TRUE(res["errors"].empty()) << res["errors"].dump(1);
  ASSERT_TRUE(res["loaded"].get<bool>());
  EXPECT_TRUE(res["banner"]["no-webgl2"]["visible"].get<bool>());
  EXPECT_NE(res["banner"]["no-webgl2"]["text"].get<std::string>().find("WebGL2"), std::string::npos);
  EXPECT_TRUE(res["banner"]["fetch-fails"]["visible"].get<bool>());
  EXPECT_NE(res["banner"]["fetch-fails"]["text"].get<std::string>().find("could not load"),
            std::string::npos);
  EXPECT_GT(res["shadedMean"].get<double>(), 0.03) << "the shaded view is (nearly) black";
  for (const auto& f : res["screenshots"]) EXPECT_TRUE(fs::is_regular_file(f.get<std::string>())) << f;
  std::vector<std::string> ids;
  for (const auto& m : res["methods"]) ids.push_back(m["id"]);
  for (const char* want :
       {"none", "ao", "reference", "brinck-maximov-2016", "chan-2018", "part1-analytic", "generic-vndf",
        "generic-vndf-alu", "generic-vndf-alu-two-stage", "lut3d", "lut2d", "lut3d-azimuth", "directional",
        "directional+generic-vndf-alu", "directional-view", "directional-view+generic-vndf-alu"})
    EXPECT_NE(std::find(ids.begin(), ids.end(), want), ids.end()) << want;
  const auto listed = methods_js_entries(msh::view::methods_js(methods));
  EXPECT_EQ(ids.size(), listed.size());
  for (const auto& [id, entry] : listed) EXPECT_NE(std::find(ids.begin(), ids.end(), id), ids.end()) << id;
  std::vector<std::string> bumps;
  for (const auto& b : res["bumps"]) bumps.push_back(b);
  for (const char* want : {"none", "conty-2019", "chiang-2019"})
    EXPECT_NE(std::find(bumps.begin(), bumps.end(), want), bumps.end()) << want;
}

// What the probes gather: per method and lobe (or bump method) the deviations, and the counts.
struct ViewerProbes {
  std::map<std::string, std::unique_ptr<occlusion::MicroShadowingEvaluator>> evaluators;
  std::map<std::string, Stat> stats;
  int lit_total = 0, texel_probes = 0, texel_nonzero = 0;
};

// A probe pixel's 3-vector `key` (a JSON array of three numbers) as the page's float.
Vec3f probe_vec(const nlohmann::json& p, const char* key) {
  return Vec3f(p[key][0].get<float>(), p[key][1].get<float>(), p[key][2].get<float>());
}

// A lit probe pixel's inputs as the page read them.
struct ProbeInputs {
  float V, nl, nv, r, cphi;
  Vec3f v, l;
  int n;       // the estimator's samples
  double phi;  // the relative azimuth
};

// What a lobe should read at a probe: the library's value, the tolerances of the float32 and 8-bit reads,
// and the exact generic term where one applies (-1 otherwise).
struct Expected {
  double want = 1, tol = 1e-4, tol8 = 1.0 / 255, exact = -1;
};

// A texel form: the directional term at the channels the shader fetched (filtered half floats, read back as
// float), its tangent-space light and normal: the port's documented float bound (docs/shaders.md; S = sum
// |c_i b_i(l)|), the 8-bit display clamped to 1 (the term may exceed 1 near the coarse terminator).
void texel_expected(const nlohmann::json& p, const nlohmann::json& form, const std::string& id, Expected& e,
                    ViewerProbes& out) {
  ASSERT_TRUE(p.contains("directional")) << "a texel method without probed channels (" << id << ")";
  // The view correction's forms read all 21 channels and the tangent-space view (directional.h).
  const int nch = occlusion::find_micro_shadowing_method(form["method"])->texel_channels;
  ASSERT_GE(int(p["directional"].size()), nch) << id;
  float ch[directional::kViewChannels], b[directional::kDirectionalChannels];
  for (int k = 0; k < nch; ++k) ch[k] = p["directional"][k].get<float>();
  const Vec3f lt = probe_vec(p, "l_tangent"), nt = probe_vec(p, "n_tangent"), vt = probe_vec(p, "v_tangent");
  directional::poly2_basis(lt, b);
  // S of each 9-term sum (the view's G sums weighted as in shaders/portable/directional.h).
  double S = 0, nl_abs = std::abs(nt.x * lt.x) + std::abs(nt.y * lt.y) + std::abs(nt.z * lt.z);
  const double vz = std::max(double(vt.z), directional::kMinViewZ);
  for (int k = 0; k < nch; ++k) {
    const int ns = directional::kSlopeTerms;
    const double w = k < 9 ? 1.0 : k < 9 + ns ? std::abs(vt.x) / vz : std::abs(vt.y) / vz;
    S += std::abs(double(ch[k]) * b[k < 9 ? k : (k - 9) % ns]) * w;
  }
  e.want = nch == directional::kViewChannels ? directional::directional_view_term<float>(ch, lt, vt, nt)
                                             : directional::directional_term<float>(ch, lt, nt);
  const double ntl = std::max(1e-4, double(dot(nt, lt)));
  e.tol = 1e-6 * S / ntl + (1e-6 + 2.5e-7 * nl_abs / ntl) * std::abs(e.want) + 1e-7;
  e.tol8 = 1.0 / 255 + e.tol;
  ++out.texel_probes;
  if (S > 0) ++out.texel_nonzero;
}

// One lobe of a method (`form`: the method's cpp entry, or a pair's lobe) at a probe. A pair against the
// registry's eval_lobes; a test pair (not in the registry), or a pair with a texel lobe (its eval needs the
// texel's channels), each lobe against its own term.
void lobe_expected(const nlohmann::json& p, const ProbeInputs& x, const nlohmann::json& c,
                   const nlohmann::json& form, int lobe, const std::string& id, Expected& e,
                   ViewerProbes& out) {
  const bool pair = c.contains("diffuse");
  const std::string method = form["method"];
  const bool texel_pair = pair && (c["diffuse"].value("texel", false) || c["specular"].value("texel", false));
  const std::string eval_name =
      occlusion::find_micro_shadowing_method(c["method"]) && !texel_pair ? c["method"] : form["method"];
  if (form.value("texel", false)) {
    texel_expected(p, form, id, e, out);
  } else if (form.value("frame", false)) {
    // The Sobol estimator at the pixel's own v and l (it is not rotation-invariant about n).
    EXPECT_EQ(method, "generic-vndf") << "no C++ evaluation here for the frame form of " << method;
    const float a = x.r * x.r;
    e.want = micro_shadowing::generic_vndf_estimate<float>(x.V, GGX<float>(a, a), x.v, x.l, x.n,
                                                           micro_shadowing::G2Form::HeightCorrelated, 1u);
    e.tol = 2.0 / x.n + 1e-4, e.tol8 = 1.0 / 255 + 2.0 / x.n;
    e.exact = micro_shadowing::generic_vndf_exact(x.V, double(a), double(a), Vec3d(x.v), Vec3d(x.l));
  } else if (form.value("two_stage", false)) {
    e.want = micro_shadowing::generic_vndf_alu_two_stage<float>(x.V, x.nl, x.nv, x.r);
  } else {
    const bool with_phi = form.value("phi", false);
    auto& ev = out.evaluators[eval_name + (with_phi ? "@phi" : "")];
    if (!ev) ev = std::make_unique<occlusion::MicroShadowingEvaluator>(eval_name);
    occlusion::MicroShadowingQuery q{x.V, x.nl, x.nv, x.r, std::nullopt, std::nullopt};
    if (with_phi) q.phi = x.phi;
    const auto lobes = ev->eval_lobes(q);
    e.want = lobe ? lobes.second : lobes.first;
  }
  if (method.rfind("lut", 0) == 0 || method == "generic-vndf-alu") {
    // Tables: half floats in the texture (2^-11 relative) and the GPU's filter weights.
    if (method.rfind("lut", 0) == 0) e.tol = 1e-3, e.tol8 = 2.0 / 255;
    const double a = double(x.r) * x.r;
    e.exact =
        form.value("phi", false)
            ? micro_shadowing::generic_vndf_exact(x.V, a, a, lut::study_view_dir(x.nv),
                                                  lut::study_light_dir(x.nl, x.phi))
            : micro_shadowing::generic_vndf_exact_azimuth_mean(x.V, a, x.nl, method == "lut2d" ? 1.0 : x.nv);
  }
}

// Every method's lobes at a lit probe pixel against the library.
void check_probe_methods(const nlohmann::json& res, const nlohmann::json& cfg, const nlohmann::json& p,
                         ViewerProbes& out) {
  ProbeInputs x{p["visibility"], p["ndotl"], p["ndotv"], p["roughness"], p["cos_phi"], {}, {},
                p["samples"],    0};
  ASSERT_TRUE(x.V >= 0 && x.V <= 1 && x.nl >= 0 && x.nl <= 1 && x.nv >= 0 && x.nv <= 1 && x.r >= 0 &&
              x.r <= 1);
  x.v = probe_vec(p, "v");
  x.l = probe_vec(p, "l");
  x.phi = std::acos(std::clamp(double(x.cphi), -1.0, 1.0));
  for (const auto& m : res["methods"]) {
    const std::string id = m["id"];
    const auto& c = m["cpp"];
    const bool pair = c.contains("diffuse");
    for (int lobe = 0; lobe < (pair ? 2 : 1); ++lobe) {
      const auto& form = pair ? c[lobe ? "specular" : "diffuse"] : c;
      const double got = lobe ? p["values_specular"][id] : p["values"][id];
      const double got8 = (lobe ? p["term8_specular"][id] : p["term8"][id]).get<double>() / 255.0;
      Expected e;
      ASSERT_NO_FATAL_FAILURE(lobe_expected(p, x, c, form, lobe, id, e, out));
      if (form["method"] == "reference" && std::abs(double(x.nl) - std::sqrt(1.0 - x.V)) < 1e-4)
        continue;  // boundary
      const std::string what = pair ? id + (lobe ? " specular" : " diffuse") : id;
      EXPECT_NEAR(got, e.want, e.tol) << what << " at V=" << x.V << " N.L=" << x.nl << " N.V=" << x.nv
                                      << " r=" << x.r << " cos_phi=" << x.cphi << " (" << cfg["name"] << ")";
      EXPECT_NEAR(got8, std::min(e.want, 1.0), e.tol8) << what << " 8-bit (" << cfg["name"] << ")";
      Stat& st = out.stats[what];
      st.max_float = std::max(st.max_float, std::abs(got - e.want));
      st.max_8bit = std::max(st.max_8bit, std::abs(got8 - std::min(e.want, 1.0)));
      if (e.exact >= 0) st.max_vs_exact = std::max(st.max_vs_exact, std::abs(got - e.exact));
      ++st.n;
    }
  }
}

// An unlit pixel reads 0 for every method (both lobes of a pair).
void check_unlit_probe(const nlohmann::json& res, const nlohmann::json& p) {
  for (const auto& m : res["methods"]) {
    const std::string id = m["id"];
    EXPECT_EQ(p["values"][id].get<double>(), 0.0) << "unlit pixel " << id;
    if (m["pair"].get<bool>()) {
      EXPECT_EQ(p["values_specular"][id].get<double>(), 0.0) << "unlit pixel " << id;
    }
  }
}

// The bump-terminator terms at the pixel's own normals and light direction (world space), C++ float.
void check_probe_bumps(const nlohmann::json& res, const nlohmann::json& cfg, const nlohmann::json& p,
                       ViewerProbes& out) {
  const Vec3f ng = probe_vec(p, "ng"), ns = probe_vec(p, "ns"), wl = probe_vec(p, "wl");
  const auto test = p["bump_hemi"].get<bool>() ? bump::HemisphereTest::kOn : bump::HemisphereTest::kOff;
  for (const auto& id : res["bumps"]) {
    bump::Method m = bump::Method::kNone;
    double want = 1;
    if (id != "none") {
      ASSERT_TRUE(bump::parse_method(id.get<std::string>(), m)) << id;
      want = bump::term(m, ng, ns, wl, test);
    }
    const double got = p["bumps"][id.get<std::string>()];
    EXPECT_NEAR(got, want, 1e-4) << id << " (" << cfg["name"] << ")";
    Stat& st = out.stats["bump " + id.get<std::string>()];
    st.max_float = std::max(st.max_float, std::abs(got - want));
    ++st.n;
  }
}

// Every configuration's probes: the methods at the lit ones, 0 at the others, then the bump terminator.
void check_configs(const nlohmann::json& res, ViewerProbes& out) {
  for (const auto& cfg : res["configs"]) {
    int lit = 0;
    for (const auto& p : cfg["probes"]) {
      if (!p["lit"].get<bool>()) {
        check_unlit_probe(res, p);
        continue;
      }
      ++lit;
      ASSERT_NO_FATAL_FAILURE(check_probe_methods(res, cfg, p, out));
    }
    for (const auto& p : cfg["probes"]) {
      if (p["lit"].get<bool>()) {
        ASSERT_NO_FATAL_FAILURE(check_probe_bumps(res, cfg, p, out));
      }
    }
    EXPECT_GE(lit, 6) << cfg["name"] << ": too few lit probe pixels for a meaningful comparison";
    out.lit_total += lit;
  }
  // The built-in plaster carries the directional channels: the texel forms were compared where they hold
  // data.
  EXPECT_GT(out.texel_probes, 0) << "no directional probe was compared";
  EXPECT_GT(out.texel_nonzero, out.texel_probes / 2) << "the probed directional channels are (mostly) zero";
}

void print_viewer_summary(const nlohmann::json& res, const std::set<std::string>& test_pairs,
                          const ViewerProbes& out) {
  int pairs = 0, registry_pairs = 0;
  for (const auto& m : res["methods"])
    if (m["pair"].get<bool>()) ++pairs, registry_pairs += test_pairs.count(m["id"]) ? 0 : 1;
  EXPECT_GE(pairs, 1) << "no pair was checked";
  double worst8 = 0;
  for (const auto& [id, st] : out.stats) worst8 = std::max(worst8, st.max_8bit);
  std::printf(
      "viewer: %zu methods (%d pairs: %d of the registry, %d test pairs), %d lit probe pixels, max 8-bit "
      "deviation %.2f/255; |shader - C++| per method and lobe (float32 target / 8-bit output), and vs the "
      "exact generic term where one applies:\n",
      res["methods"].size(), pairs, registry_pairs, pairs - registry_pairs, out.lit_total, worst8 * 255);
  for (const auto& [id, st] : out.stats)
    std::printf("  %-36s n=%3d  float %.2e  8-bit %.2f/255  vs exact %s\n", id.c_str(), st.n, st.max_float,
                st.max_8bit * 255, st.max_vs_exact > 0 ? std::to_string(st.max_vs_exact).c_str() : "-");
}

TEST(ViewerBrowser, EveryMethodMatchesTheLibrary) {
  REQUIRE_BROWSER();
  const fs::path dir = scratch_dir("viewer");
  const fs::path shots = fs::path(MSH_BINARY_DIR) / "viewer_screenshots";
  fs::remove_all(shots);
  std::set<std::string> test_pairs;
  const auto methods = page_methods(test_pairs);
  nlohmann::json res;
  ASSERT_NO_FATAL_FAILURE(run_viewer(dir, shots, methods, res));
  ASSERT_NO_FATAL_FAILURE(check_page_and_lists(res, methods));
  ViewerProbes probes;
  ASSERT_NO_FATAL_FAILURE(check_configs(res, probes));
  print_viewer_summary(res, test_pairs, probes);
}

}  // namespace
