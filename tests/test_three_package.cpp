// The three.js module as a user installs it (docs/three.md, "Install"; cmake/three_package.cmake). The build
// packs a copy of integrations/three with the generated files written by the CLI into
// build/three/microshadow-three-<version>.tgz: its files are the module's sources, the registry's method list and
// the project's GLSL, its package.json the source's, and the docs state its three range. Then, for the lowest
// and the highest three of that range: a clean folder, `npm init -y; npm install <tgz> three@<version>` (the
// npm cache in build/three/npm-cache, --prefer-offline: downloaded once), examples/three-importmap/index.html
// copied in, the folder served, and the page run in headless Debian chromium (tests/browser/three_test.mjs
// --serve): the import map's four names resolve to the installed folders, three's REVISION is the one
// installed, the shader chunks the module patches are there, and with micro-shadowing the canvas is darker
// than without at every lit pixel under the sun and under the rect-area light (none brighter), with no console
// error. npm refuses a three below the range (ERESOLVE). Without chromium, node, npm, playwright-core or the
// tarball, or with the npm registry unreachable and nothing cached, it fails unless MSH_ALLOW_NO_BROWSER=1
// (then skips), as the other browser tests.
#include <gtest/gtest.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <string>

#include "../src/view/three_example.h"
#include "../src/view/viewer_server.h"
#include "support/cli_test_util.h"
#include "support/view_server_util.h"

namespace fs = std::filesystem;
using msh::test::slurp;
using nlohmann::json;

namespace {

const fs::path kSource = fs::path(MSH_SOURCE_DIR);
const fs::path kBuild = fs::path(MSH_BINARY_DIR);
const fs::path kBrowserDir = kSource / "tests" / "browser";
const fs::path kNpmCache = kBuild / "three" / "npm-cache";

const json& source_package() {
  static const json j = json::parse(slurp(kSource / "integrations" / "three" / "package.json"));
  return j;
}

fs::path tarball() {
  const json& p = source_package();
  return kBuild / "three" / (p["name"].get<std::string>() + "-" + p["version"].get<std::string>() + ".tgz");
}

// The peer range ">=0.L.0 <0.H.0": the lowest version 0.L.0, the highest 0.(H-1) (npm takes its last patch),
// and 0.(L-1).0 below it.
struct Range {
  std::string spec, low, high, below;
  int low_minor = 0, high_minor = 0;
};
Range peer_range() {
  Range r;
  r.spec = source_package()["peerDependencies"]["three"].get<std::string>();
  std::smatch m;
  if (!std::regex_match(r.spec, m, std::regex(R"(>=0\.(\d+)\.0 <0\.(\d+)\.0)"))) return r;
  r.low_minor = std::stoi(m[1]);
  r.high_minor = std::stoi(m[2]) - 1;
  r.low = "0." + std::to_string(r.low_minor) + ".0";
  r.high = "0." + std::to_string(r.high_minor);
  r.below = "0." + std::to_string(r.low_minor - 1) + ".0";
  return r;
}

struct ShRun {
  int code;
  std::string out;
};
// `cmd` in `dir` through the shell, stdout and stderr together.
ShRun sh(const std::string& cmd, const fs::path& dir, const std::string& log) {
  const fs::path out = dir / log;
  const int st = std::system(("cd '" + dir.string() + "' && (" + cmd + ") > '" + out.string() + "' 2>&1").c_str());
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, slurp(out)};
}

// Why the package test cannot run here ("" = it can).
std::string missing_package() {
  std::string why = msh::test::missing_browser_driver(kBrowserDir);
  if (!why.empty()) return why;
  if (std::system("npm --version > /dev/null 2>&1") != 0) return "no npm on PATH (Debian package npm)";
  if (!fs::is_regular_file(tarball()))
    return "no " + tarball().string() +
           ": the build packs it when node and npm are on PATH at configure time (cmake/three_package.cmake)";
  return "";
}
#define REQUIRE_PACKAGE() MSH_REQUIRE_BROWSER(missing_package())

// npm's words for a registry it cannot reach.
bool registry_unreachable(const std::string& out) {
  return std::regex_search(out, std::regex("ENOTFOUND|EAI_AGAIN|ECONNREFUSED|ECONNRESET|ETIMEDOUT|ENETUNREACH|"
                                           "EHOSTUNREACH|network request|request to https?://\\S+ failed"));
}

std::set<std::string> files_under(const fs::path& root) {
  std::set<std::string> s;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) s.insert(fs::relative(e.path(), root).string());
  return s;
}

TEST(ThreePackage, TarballHoldsTheModuleAndItsGeneratedFiles) {
  REQUIRE_PACKAGE();
  const fs::path dir = msh::test::scratch_dir("three_package");
  const ShRun x = sh("tar xzf '" + tarball().string() + "'", dir, "tar.out");
  ASSERT_EQ(x.code, 0) << x.out;
  const fs::path pkg = dir / "package";
  // The module's sources as they are in the tree, the two generated files, package.json: nothing else.
  std::set<std::string> want = {"package.json", "src/generated/methods.js", "src/generated/glsl.js"};
  for (const auto& e : fs::directory_iterator(kSource / "integrations" / "three" / "src"))
    if (e.path().extension() == ".js") {
      const std::string rel = "src/" + e.path().filename().string();
      want.insert(rel);
      EXPECT_EQ(slurp(pkg / rel), slurp(e.path())) << rel;
    }
  EXPECT_EQ(files_under(pkg), want);
  EXPECT_EQ(slurp(pkg / "src" / "generated" / "methods.js"),
            msh::view::methods_js(msh::occlusion::micro_shadowing_methods()));
  EXPECT_EQ(slurp(pkg / "src" / "generated" / "glsl.js"), msh::view::three_glsl_js(kSource / "shaders" / "glsl"));
  EXPECT_EQ(json::parse(slurp(pkg / "package.json")), source_package());
  // three is a peer dependency with a stated range, the docs give the same range.
  const Range r = peer_range();
  ASSERT_FALSE(r.low.empty()) << "peerDependencies.three is not '>=0.L.0 <0.H.0': " << r.spec;
  EXPECT_FALSE(source_package().contains("dependencies"));
  // docs/three.md shows the example page's import map as it is.
  const std::string page = slurp(kSource / "examples" / "three-importmap" / "index.html");
  const auto a = page.find("<script type=\"importmap\">"), b = page.find("</script>", a);
  ASSERT_NE(b, std::string::npos);
  EXPECT_NE(slurp(kSource / "docs" / "three.md").find(page.substr(a, b + 9 - a)), std::string::npos)
      << "docs/three.md does not show the import map of examples/three-importmap/index.html";
  for (const char* doc : {"README.md", "docs/three.md"})
    EXPECT_NE(slurp(kSource / doc).find("`" + r.spec + "`"), std::string::npos) << doc << " does not state " << r.spec;
  fs::remove_all(dir);
}

TEST(ThreePackage, InstallsInACleanFolderAndRendersAtBothEndsOfTheRange) {
  REQUIRE_PACKAGE();
  const Range r = peer_range();
  ASSERT_FALSE(r.low.empty()) << "peerDependencies.three is not '>=0.L.0 <0.H.0': " << r.spec;
  const std::string npm = "npm --no-audit --no-fund --loglevel=error --prefer-offline --cache '" + kNpmCache.string() + "'";
  const std::string tgz = tarball().string();
  for (const auto& [version, minor] : {std::pair{r.low, r.low_minor}, std::pair{r.high, r.high_minor}}) {
    SCOPED_TRACE("three@" + version);
    const auto t0 = std::chrono::steady_clock::now();
    const fs::path dir = kBuild / "three_package" / ("three-" + version);
    fs::remove_all(dir);
    fs::create_directories(dir);
    // As a new user: an empty project, the tarball and three.
    const ShRun init = sh("npm init -y", dir, "npm_init.out");
    ASSERT_EQ(init.code, 0) << init.out;
    const ShRun inst = sh(npm + " install '" + tgz + "' three@" + version, dir, "npm_install.out");
    if (inst.code != 0 && registry_unreachable(inst.out))
      MSH_REQUIRE_BROWSER("the npm registry is unreachable and three@" + version + " is not in " +
                          kNpmCache.string() + ": " + inst.out.substr(0, 300));
    ASSERT_EQ(inst.code, 0) << inst.out;
    const double install_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const fs::path mod = dir / "node_modules" / "microshadow-three";
    EXPECT_TRUE(fs::is_regular_file(mod / "src" / "generated" / "methods.js"));
    EXPECT_FALSE(fs::is_symlink(mod)) << "npm linked the module instead of installing it";
    const std::string three_version =
        json::parse(slurp(dir / "node_modules" / "three" / "package.json"))["version"].get<std::string>();
    EXPECT_EQ(three_version.rfind("0." + std::to_string(minor) + ".", 0), 0u) << three_version;
    EXPECT_EQ(json::parse(slurp(dir / "package.json"))["dependencies"]["three"].is_string(), true);

    // The import-map page, served from the folder.
    fs::copy_file(kSource / "examples" / "three-importmap" / "index.html", dir / "index.html");
    const fs::path out = kBuild / "three_package" / ("out-" + version);
    fs::remove_all(out);
    const ShRun drv = sh("node '" + (kBrowserDir / "three_test.mjs").string() + "' --serve '" + dir.string() +
                           "' --page index.html --out '" + out.string() + "' --chromium " + msh::test::chromium_path(),
                       kBuild / "three_package", "node_" + version + ".out");
    ASSERT_EQ(drv.code, 0) << drv.out;
    const json res = json::parse(slurp(out / "results.json"));
    EXPECT_TRUE(res["errors"].empty()) << res["errors"].dump(1);
    const json& p = res["package"];
    ASSERT_TRUE(p["loaded"].get<bool>()) << res["errors"].dump(1);
    EXPECT_EQ(p["revision"], std::to_string(minor));
    EXPECT_EQ(p["handle_method"], p["method"]);
    EXPECT_TRUE(p["luts_same_module"].get<bool>()) << "microshadow-three/luts is not the installed module's luts.js";
    EXPECT_TRUE(p["addon_loaded"].get<bool>()) << "three/addons/ did not resolve";
    EXPECT_TRUE(p["missing"].empty()) << p["missing"].dump(1);
    EXPECT_EQ(p["gl_error"], 0);
    const std::set<std::string> served = p["served"].get<std::set<std::string>>();
    for (const char* f : {"index.html", "node_modules/three/build/three.module.js",
                          "node_modules/three/examples/jsm/lights/RectAreaLightUniformsLib.js",
                          "node_modules/microshadow-three/src/index.js", "node_modules/microshadow-three/src/luts.js",
                          "node_modules/microshadow-three/src/generated/methods.js",
                          "node_modules/microshadow-three/src/generated/glsl.js"})
      EXPECT_TRUE(served.count(f)) << f << " was not loaded";
    // The term is on: under each light alone, every lit pixel darker or equal with micro-shadowing, almost all
    // darker, none brighter (V 0.45 and 0.8 on the floor, the sun 20 degrees high).
    for (const char* light : {"sun", "rect"}) {
      const json& L = p["lights"][light];
      const int lit = L["lit"], darker = L["darker"], brighter = L["brighter"];
      EXPECT_GE(lit, 20000) << light << ": " << L.dump();
      EXPECT_EQ(brighter, 0) << light << ": " << L.dump();
      EXPECT_GE(darker, int(0.99 * lit)) << light << ": " << L.dump();
      EXPECT_LT(L["mean_on"].get<double>(), 0.8 * L["mean_off"].get<double>()) << light << ": " << L.dump();
      std::printf("three %s (r%s) %-4s: %d lit px, %d darker, %d brighter; mean %.3f -> %.3f, centre %.3f -> %.3f\n",
                  three_version.c_str(), p["revision"].get<std::string>().c_str(), light, lit, darker, brighter,
                  L["mean_off"].get<double>(), L["mean_on"].get<double>(), L["centre_off"].get<double>(),
                  L["centre_on"].get<double>());
    }
    std::printf("three %s: npm install %.1f s, page %.1f s\n", three_version.c_str(), install_s,
                p["timing"]["done"].get<double>());
  }
  // Below the range npm refuses the pair (the range is what package.json states, not advice).
  const fs::path dir = kBuild / "three_package" / "below";
  fs::remove_all(dir);
  fs::create_directories(dir);
  ASSERT_EQ(sh("npm init -y", dir, "npm_init.out").code, 0);
  const ShRun below = sh(npm + " install --dry-run '" + tgz + "' three@" + r.below, dir, "npm_install.out");
  if (below.code != 0 && registry_unreachable(below.out))
    MSH_REQUIRE_BROWSER("the npm registry is unreachable: " + below.out.substr(0, 300));
  EXPECT_NE(below.code, 0) << below.out;
  EXPECT_NE(below.out.find("ERESOLVE"), std::string::npos) << below.out;
}

}  // namespace
