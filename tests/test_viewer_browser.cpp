// The browser viewer (`microshadow view`, docs/viewer.md). Server: refuses non-loopback hosts, a port in use,
// a missing texture set and tables the shaders cannot sample (exit 2, one line); exports a static copy and
// serves it with --root; stops cleanly (exit 0) on SIGINT. Browser: headless Debian chromium with SwiftShader
// WebGL2, driven by tests/browser/viewer_test.mjs (playwright-core, `npm ci` in tests/browser by
// scripts/install-deps.sh): it loads the page, switches through every method, probes fixed configurations and
// this test compares each method's shader value at the probe's own inputs (V, N·L, N·V, roughness, cos φ, v,
// l read back from float32 render targets) with the C++ library, in float and as 8-bit output; no console
// errors; error banners for a missing WebGL2 and a failed fetch. Fails without chromium/node/playwright-core
// unless MSH_ALLOW_NO_BROWSER=1 (then skips), as the shader tests do without Vulkan.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <microshadow/lut/runtime/micro_shadowing_analysis.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_exact.h>
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
#include <thread>

#include "../src/view/shader_source.h"
#include "support/cli_test_util.h"

namespace fs = std::filesystem;
using namespace msh;
using msh::test::run_cli;
using msh::test::scratch_dir;
using msh::test::slurp;

namespace {

const fs::path kBrowserDir = fs::path(MSH_SOURCE_DIR) / "tests" / "browser";
// The built-in plaster is generated once into this cache (a few CPU-seconds) and reused by later runs.
const fs::path kCache = fs::path(MSH_BINARY_DIR) / "viewer_cache";

std::string chromium_path() {
  const char* e = std::getenv("MSH_CHROMIUM");
  return e && *e ? e : "/usr/bin/chromium";
}

// Why the browser test cannot run here ("" = it can).
std::string missing_browser() {
  if (access(chromium_path().c_str(), X_OK) != 0)
    return "no chromium at " + chromium_path() + " (Debian package chromium)";
  if (std::system("node --version > /dev/null 2>&1") != 0) return "no node on PATH (Debian package nodejs)";
  if (!fs::exists(kBrowserDir / "node_modules" / "playwright-core" / "package.json"))
    return "playwright-core is not installed: run `npm ci` in tests/browser (scripts/install-deps.sh does)";
  return "";
}

#define REQUIRE_BROWSER()                                                        \
  do {                                                                           \
    const std::string why = missing_browser();                                   \
    if (!why.empty()) {                                                          \
      const char* allow = std::getenv("MSH_ALLOW_NO_BROWSER");                   \
      if (allow && std::string(allow) == "1") GTEST_SKIP() << why;               \
      FAIL() << why << " (set MSH_ALLOW_NO_BROWSER=1 to skip the browser test)"; \
    }                                                                            \
  } while (0)

int count_lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// A `microshadow view ...` process with stdout/stderr in files; the URL from its first line.
struct Server {
  pid_t pid = -1;
  fs::path out, err;
  std::string url;
};

Server start_server(const std::vector<std::string>& args, const fs::path& dir) {
  Server s;
  s.out = dir / "server.out";
  s.err = dir / "server.err";
  s.pid = fork();
  if (s.pid == 0) {
    if (!freopen(s.out.c_str(), "w", stdout) || !freopen(s.err.c_str(), "w", stderr)) _exit(127);
    std::vector<char*> argv;
    std::vector<std::string> all = {MSH_CLI_PATH, "view"};
    all.insert(all.end(), args.begin(), args.end());
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(MSH_CLI_PATH, argv.data());
    _exit(127);
  }
  // The server prints its URL once it serves (the default tables bake at start-up: seconds; the plaster is
  // generated on the first run only).
  for (int i = 0; i < 3000; ++i) {
    const std::string o = slurp(s.out);
    const auto p = o.find("http://");
    if (p != std::string::npos && o.find(' ', p) != std::string::npos) {
      s.url = o.substr(p, o.find(' ', p) - p);
      return s;
    }
    int status = 0;
    if (waitpid(s.pid, &status, WNOHANG) == s.pid) {
      s.pid = -1;
      ADD_FAILURE() << "the server exited: " << slurp(s.err);
      return s;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ADD_FAILURE() << "the server printed no URL in 300 s";
  return s;
}

// SIGINT (Ctrl-C), then the exit code (−1: did not exit in 30 s, or not normally).
int stop_server(Server& s, int sig = SIGINT) {
  if (s.pid <= 0) return -1;
  kill(s.pid, sig);
  for (int i = 0; i < 300; ++i) {
    int status = 0;
    if (waitpid(s.pid, &status, WNOHANG) == s.pid) {
      s.pid = -1;
      return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  kill(s.pid, SIGKILL);
  waitpid(s.pid, nullptr, 0);
  s.pid = -1;
  return -1;
}

// GET path over a plain socket (HTTP/1.0): the status line and the body.
std::pair<std::string, std::string> http_get(const std::string& url, const std::string& path) {
  const auto colon = url.rfind(':');
  const int port = std::stoi(url.substr(colon + 1));
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(uint16_t(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
    close(fd);
    return {"connect failed", ""};
  }
  const std::string req = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
  if (write(fd, req.data(), req.size()) != ssize_t(req.size())) {
    close(fd);
    return {"write failed", ""};
  }
  std::string resp;
  char buf[65536];
  for (ssize_t n; (n = read(fd, buf, sizeof(buf))) > 0;) resp.append(buf, std::size_t(n));
  close(fd);
  const auto eol = resp.find("\r\n"), body = resp.find("\r\n\r\n");
  return {resp.substr(0, eol), body == std::string::npos ? "" : resp.substr(body + 4)};
}

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
  for (const char* f : {"index.html", "viewer.js", "methods.js", "data/manifest.json", "data/lut3d.f16",
                        "data/material/micro_occlusion.png"})
    EXPECT_TRUE(fs::is_regular_file(copy / f)) << f;
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

TEST(ViewerBrowser, EveryMethodMatchesTheLibrary) {
  REQUIRE_BROWSER();
  const fs::path dir = scratch_dir("viewer");
  const fs::path shots = fs::path(MSH_BINARY_DIR) / "viewer_screenshots";
  fs::remove_all(shots);
  Server s = start_server({"--port", "0", "--cache", kCache.string()}, dir);
  ASSERT_FALSE(s.url.empty());
  const std::string cmd = "cd " + kBrowserDir.string() + " && node viewer_test.mjs --url " + s.url +
                          " --out " + shots.string() + " --chromium " + chromium_path() + " > " +
                          (dir / "node.out").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  // Ctrl-C: a clean exit.
  EXPECT_EQ(stop_server(s), 0) << slurp(s.err);
  ASSERT_EQ(rc, 0) << slurp(dir / "node.out");
  const auto res = nlohmann::json::parse(slurp(shots / "results.json"));

  EXPECT_TRUE(res["errors"].empty()) << res["errors"].dump(1);
  ASSERT_TRUE(res["loaded"].get<bool>());
  EXPECT_TRUE(res["banner"]["no-webgl2"]["visible"].get<bool>());
  EXPECT_NE(res["banner"]["no-webgl2"]["text"].get<std::string>().find("WebGL2"), std::string::npos);
  EXPECT_TRUE(res["banner"]["fetch-fails"]["visible"].get<bool>());
  EXPECT_NE(res["banner"]["fetch-fails"]["text"].get<std::string>().find("could not load"),
            std::string::npos);
  EXPECT_GT(res["shadedMean"].get<double>(), 0.03) << "the shaded view is (nearly) black";
  for (const auto& f : res["screenshots"]) EXPECT_TRUE(fs::is_regular_file(f.get<std::string>())) << f;

  // Every GLSL term the project has is offered (none dropped because its function or table went missing).
  std::vector<std::string> ids;
  for (const auto& m : res["methods"]) ids.push_back(m["id"]);
  for (const char* want :
       {"none", "ao", "reference", "brinck-maximov-2016", "chan-2018", "part1-analytic", "generic-vndf",
        "generic-vndf-alu", "generic-vndf-alu-two-stage", "lut3d", "lut2d", "lut-azimuth"})
    EXPECT_NE(std::find(ids.begin(), ids.end(), want), ids.end()) << want;

  std::vector<std::string> bumps;
  for (const auto& b : res["bumps"]) bumps.push_back(b);
  for (const char* want : {"none", "conty-2019", "chiang-2019"})
    EXPECT_NE(std::find(bumps.begin(), bumps.end(), want), bumps.end()) << want;

  std::map<std::string, std::unique_ptr<occlusion::MicroShadowingEvaluator>> evaluators;
  std::map<std::string, Stat> stats;
  int lit_total = 0;
  for (const auto& cfg : res["configs"]) {
    int lit = 0;
    for (const auto& p : cfg["probes"]) {
      if (!p["lit"].get<bool>()) {
        for (const auto& m : res["methods"])
          EXPECT_EQ(p["values"][m["id"].get<std::string>()].get<double>(), 0.0) << "unlit pixel";
        continue;
      }
      ++lit;
      const float V = p["visibility"], nl = p["ndotl"], nv = p["ndotv"], r = p["roughness"],
                  cphi = p["cos_phi"];
      ASSERT_TRUE(V >= 0 && V <= 1 && nl >= 0 && nl <= 1 && nv >= 0 && nv <= 1 && r >= 0 && r <= 1);
      const Vec3f v(p["v"][0].get<float>(), p["v"][1].get<float>(), p["v"][2].get<float>());
      const Vec3f l(p["l"][0].get<float>(), p["l"][1].get<float>(), p["l"][2].get<float>());
      const int n = p["samples"];
      const double phi = std::acos(std::clamp(double(cphi), -1.0, 1.0));
      for (const auto& m : res["methods"]) {
        const std::string id = m["id"];
        const double got = p["values"][id], got8 = p["term8"][id].get<double>() / 255.0;
        const auto& c = m["cpp"];
        double want = 1, tol = 1e-4, tol8 = 1.0 / 255, exact = -1;
        if (!c.is_null()) {
          const std::string method = c["method"];
          if (c.value("frame", false)) {
            // The Sobol estimator at the pixel's own v and l (it is not rotation-invariant about n).
            const float a = r * r;
            want = micro_shadowing::generic_vndf_estimate<float>(
                V, GGX<float>(a, a), v, l, n, micro_shadowing::G2Form::HeightCorrelated, 1u);
            tol = 2.0 / n + 1e-4, tol8 = 1.0 / 255 + 2.0 / n;
            exact = micro_shadowing::generic_vndf_exact(V, double(a), double(a), Vec3d(v), Vec3d(l));
          } else if (c.value("two_stage", false)) {
            want = micro_shadowing::generic_vndf_alu_two_stage<float>(V, nl, nv, r);
          } else {
            const bool with_phi = c.value("phi", false);
            auto& e = evaluators[method + (with_phi ? "@phi" : "")];
            if (!e) e = std::make_unique<occlusion::MicroShadowingEvaluator>(method);
            occlusion::MicroShadowingQuery q{V, nl, nv, r, std::nullopt, std::nullopt};
            if (with_phi) q.phi = phi;
            want = e->eval(q);
          }
          if (method.rfind("lut", 0) == 0 || method == "generic-vndf-alu") {
            // Tables: half floats in the texture (2^-11 relative) and the GPU's filter weights.
            if (method.rfind("lut", 0) == 0) tol = 1e-3, tol8 = 2.0 / 255;
            exact = c.value("phi", false) ? micro_shadowing::generic_vndf_exact(
                                                V, double(r) * r, double(r) * r, lut::study_view_dir(nv),
                                                lut::study_light_dir(nl, phi))
                                          : micro_shadowing::generic_vndf_exact_azimuth_mean(
                                                V, double(r) * r, nl, method == "lut2d" ? 1.0 : nv);
          }
          if (method == "reference" && std::abs(double(nl) - std::sqrt(1.0 - V)) < 1e-4)
            continue;  // boundary
        }
        EXPECT_NEAR(got, want, tol) << id << " at V=" << V << " N.L=" << nl << " N.V=" << nv << " r=" << r
                                    << " cos_phi=" << cphi << " (" << cfg["name"] << ")";
        EXPECT_NEAR(got8, want, tol8) << id << " 8-bit (" << cfg["name"] << ")";
        Stat& st = stats[id];
        st.max_float = std::max(st.max_float, std::abs(got - want));
        st.max_8bit = std::max(st.max_8bit, std::abs(got8 - want));
        if (exact >= 0) st.max_vs_exact = std::max(st.max_vs_exact, std::abs(got - exact));
        ++st.n;
      }
    }
    // The bump-terminator terms at the pixel's own normals and light direction (world space), C++ float.
    for (const auto& p : cfg["probes"]) {
      if (!p["lit"].get<bool>()) continue;
      auto vec = [&](const char* k) {
        return Vec3f(p[k][0].get<float>(), p[k][1].get<float>(), p[k][2].get<float>());
      };
      const Vec3f ng = vec("ng"), ns = vec("ns"), wl = vec("wl");
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
        Stat& st = stats["bump " + id.get<std::string>()];
        st.max_float = std::max(st.max_float, std::abs(got - want));
        ++st.n;
      }
    }
    EXPECT_GE(lit, 6) << cfg["name"] << ": too few lit probe pixels for a meaningful comparison";
    lit_total += lit;
  }
  std::printf(
      "viewer: %d lit probe pixels; |shader - C++| per method (float32 target / 8-bit output), and vs the "
      "exact generic term where one applies:\n",
      lit_total);
  for (const auto& [id, st] : stats)
    std::printf("  %-28s n=%3d  float %.2e  8-bit %.2f/255  vs exact %s\n", id.c_str(), st.n, st.max_float,
                st.max_8bit * 255, st.max_vs_exact > 0 ? std::to_string(st.max_vs_exact).c_str() : "-");
}

}  // namespace
