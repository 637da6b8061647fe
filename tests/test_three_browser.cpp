// The three.js integration (integrations/three, docs/three.md). Without a browser: the module's generated
// files are the registry's method list and the project's GLSL files with their includes expanded; the
// example's glTF model is valid (buffer, counts, unit normals, tangent frame along +u, +v); the example's
// static copy holds the page, the module, three.js and the data, and bad option combinations fail with one
// line. In headless Debian chromium (SwiftShader WebGL2, tests/browser/three_test.mjs with playwright-core):
// a known scene lit by a point, a spot, a directional and a rect-area light, every method of the module's
// list, each lobe's term read back per probe pixel (float32 and 8-bit render targets) and compared with the
// C++ library at the pixel's inputs (V, N·L, N·V, roughness, v, l, the rect light's equivalent cap), which
// are themselves checked against the scene (N·L, N·V and the cap recomputed from the pixel's position and
// normal and the lights; V one of the texture's values or the constant); each light's direct diffuse and
// specular with micro-shadowing on and off differ by exactly the lobes' terms; no console errors;
// screenshots, the module's size and the frame time at 1280x720 printed. docs/three.md's glTF block on an
// asset with a shared mesh, a material without occlusion, an unlit one and a clearcoat one
// (tests/browser/three_scene_probe.js): each material patched once or skipped with its code, a second call
// changing nothing, the render changed on the patched quads only. Fails without
// chromium/node/playwright-core/three unless MSH_ALLOW_NO_BROWSER=1 (then skips), as the viewer test.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/texture.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "../src/view/shader_source.h"
#include "../src/view/three_example.h"
#include "../src/view/viewer_server.h"
#include "support/cli_test_util.h"
#include "support/probe_stats.h"
#include "support/view_server_util.h"

namespace fs = std::filesystem;
using namespace msh;
using namespace msh::test;  // the browser tests' helpers (support/view_server_util.h) and run_cli, slurp, ...
using nlohmann::json;

namespace {

const fs::path kSource = fs::path(MSH_SOURCE_DIR);

// Fails (or skips, see MSH_REQUIRE_BROWSER) where the browser part cannot run.
#define REQUIRE_BROWSER() MSH_REQUIRE_BROWSER(missing_three_browser())

int count_lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

// The example's static copy, written once per process (the default tables bake in seconds).
const fs::path& example_copy() {
  static const fs::path dir = [] {
    const fs::path d = fs::path(MSH_BINARY_DIR) / "three_example";
    const auto r = run_cli("view --three --export " + d.string() + " --cache " + kViewerCache.string(),
                           scratch_dir("three"));
    EXPECT_EQ(r.code, 0) << r.err;
    return d;
  }();
  return dir;
}

using Server = ViewServer;

// three_test.mjs on the served static copy (its module) with `args`, its output in `out`: its results.json,
// or null after a failure.
json run_three_test(const fs::path& copy, const fs::path& out, const std::string& args, const fs::path& dir) {
  const std::string failure = serve_and_drive(
      copy, "three_test.mjs",
      "--out " + out.string() + " --module " + (copy / "microshadow-three").string() + " " + args, dir);
  if (!failure.empty()) {
    ADD_FAILURE() << failure;
    return json();
  }
  return json::parse(slurp(out / "results.json"));
}

// ---- without a browser --------------------------------------------------------------------------------

TEST(ThreeModule, GeneratedFilesAreTheRegistryAndTheShaders) {
  const fs::path dir = scratch_dir("three");
  msh::view::write_three_module(kSource, dir / "gen");
  EXPECT_EQ(slurp(dir / "gen" / "methods.js"), msh::view::methods_js(occlusion::micro_shadowing_methods()));
  const std::string glsl = slurp(dir / "gen" / "glsl.js");
  for (const char* f : {"micro_shadowing.glsl", "micro_shadowing_fit.glsl", "micro_shadowing_aware.glsl",
                        "micro_shadowing_aware_fit.glsl", "micro_shadowing_area.glsl", "directional.glsl"}) {
    const std::string text = msh::view::expand_shader_includes(kSource / "shaders" / "glsl" / f);
    EXPECT_NE(glsl.find(json(f).dump() + ": " + json(text).dump()), std::string::npos) << f;
    EXPECT_EQ(text.find("\n#include"), std::string::npos) << f;
  }
  // The CLI writes the same files; a wrong combination of options is one line and exit 2.
  const auto r = run_cli("view --three-module " + (dir / "cli").string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(dir / "cli" / "methods.js"), slurp(dir / "gen" / "methods.js"));
  EXPECT_EQ(slurp(dir / "cli" / "glsl.js"), glsl);
  for (const std::string& bad :
       {"view --three-module " + (dir / "x").string() + " --three", "view --three --root " + dir.string()}) {
    const auto b = run_cli(bad, dir);
    EXPECT_EQ(b.code, 2) << bad;
    EXPECT_EQ(count_lines(b.err), 1) << b.err;
  }
  // The module's sources are in the tree; the generated files are not.
  EXPECT_TRUE(fs::is_regular_file(kSource / "integrations" / "three" / "src" / "index.js"));
  EXPECT_TRUE(fs::is_regular_file(kSource / "integrations" / "three" / "package-lock.json"));
}

std::vector<unsigned char> unbase64(const std::string& s) {
  std::vector<unsigned char> out;
  uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    int v = c >= 'A' && c <= 'Z'   ? c - 'A'
            : c >= 'a' && c <= 'z' ? c - 'a' + 26
            : c >= '0' && c <= '9' ? c - '0' + 52
            : c == '+'             ? 62
            : c == '/'             ? 63
                                   : -1;
    if (v < 0) break;
    acc = acc << 6 | uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(uint8_t(acc >> bits));
    }
  }
  return out;
}

TEST(ThreeModule, GltfModelIsValid) {
  const json g = json::parse(msh::view::three_example_gltf("material/"));
  EXPECT_EQ(g["asset"]["version"], "2.0");
  const std::string uri = g["buffers"][0]["uri"];
  const std::string prefix = "data:application/octet-stream;base64,";
  ASSERT_EQ(uri.rfind(prefix, 0), 0u);
  const auto buf = unbase64(uri.substr(prefix.size()));
  ASSERT_EQ(buf.size(), g["buffers"][0]["byteLength"].get<std::size_t>());
  const auto& prim = g["meshes"][0]["primitives"][0];
  const auto floats = [&](int accessor) {
    const auto& a = g["accessors"][accessor];
    const auto& v = g["bufferViews"][a["bufferView"].get<int>()];
    const std::size_t off = v["byteOffset"], len = v["byteLength"];
    EXPECT_LE(off + len, buf.size());
    std::vector<float> f(len / 4);
    std::memcpy(f.data(), buf.data() + off, len);
    return f;
  };
  const auto P = floats(prim["attributes"]["POSITION"]), N = floats(prim["attributes"]["NORMAL"]);
  const auto T = floats(prim["attributes"]["TANGENT"]), U = floats(prim["attributes"]["TEXCOORD_0"]);
  const int n = g["accessors"][0]["count"];
  constexpr int nu = 128, nv = 48;
  ASSERT_EQ(n, (nu + 1) * (nv + 1));
  ASSERT_EQ(P.size(), 3u * n);
  ASSERT_EQ(T.size(), 4u * n);
  const auto& ia = g["accessors"][prim["indices"].get<int>()];
  EXPECT_EQ(ia["count"], nu * nv * 6);
  EXPECT_EQ(ia["componentType"], 5123);
  const auto& iv = g["bufferViews"][ia["bufferView"].get<int>()];
  for (std::size_t k = 0; k < ia["count"].get<std::size_t>(); ++k) {
    uint16_t i;
    std::memcpy(&i, buf.data() + iv["byteOffset"].get<std::size_t>() + 2 * k, 2);
    ASSERT_LT(i, n);
  }
  // Unit normals; the tangent along +u and the bitangent cross(N, T) w along +v (the normal map's y).
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = j * (nu + 1) + i, b = a + 1, c = a + nu + 1;
      const Vec3d p(P[3 * a], P[3 * a + 1], P[3 * a + 2]), nn(N[3 * a], N[3 * a + 1], N[3 * a + 2]);
      const Vec3d t(T[4 * a], T[4 * a + 1], T[4 * a + 2]);
      const double w = T[4 * a + 3];
      ASSERT_NEAR(length(nn), 1.0, 1e-6);
      ASSERT_NEAR(std::abs(w), 1.0, 0.0);
      const Vec3d du = Vec3d(P[3 * b], P[3 * b + 1], P[3 * b + 2]) - p,
                  dv = Vec3d(P[3 * c], P[3 * c + 1], P[3 * c + 2]) - p;
      ASSERT_GT(U[2 * b] - U[2 * a], 0.0f);
      ASSERT_GT(U[2 * c + 1] - U[2 * a + 1], 0.0f);
      ASSERT_GT(dot(t, du), 0.0) << i << " " << j;
      ASSERT_GT(dot(cross(nn, t) * w, dv), 0.0) << i << " " << j;
      ASSERT_NEAR(dot(nn, t), 0.0, 1e-6);
    }
  const auto& mat = g["materials"][0];
  const int occ = mat["occlusionTexture"]["index"];
  EXPECT_EQ(g["images"][g["textures"][occ]["source"].get<int>()]["uri"], "material/micro_occlusion.png");
  EXPECT_EQ(mat["pbrMetallicRoughness"]["metallicFactor"], 0.0);
  // Deterministic.
  EXPECT_EQ(msh::view::three_example_gltf("material/"), msh::view::three_example_gltf("material/"));
}

TEST(ThreeExample, ExportsAStaticCopy) {
  REQUIRE_BROWSER();
  const fs::path& copy = example_copy();
  for (const char* f :
       {"index.html", "main.js", "README.txt", "microshadow-three/index.js", "microshadow-three/luts.js",
        "microshadow-three/generated/methods.js", "microshadow-three/generated/glsl.js",
        "three/build/three.module.js", "three/build/three.core.js", "three/LICENSE",
        "three/examples/jsm/loaders/GLTFLoader.js", "data/manifest.json", "data/model.gltf", "data/lut3d.f16",
        "data/lut3d.json", "data/material/micro_occlusion.png"})
    EXPECT_TRUE(fs::is_regular_file(copy / f)) << f;
  EXPECT_EQ(slurp(copy / "microshadow-three" / "generated" / "methods.js"),
            msh::view::methods_js(occlusion::micro_shadowing_methods()));
  EXPECT_EQ(slurp(copy / "microshadow-three" / "index.js"),
            slurp(kSource / "integrations" / "three" / "src" / "index.js"));
  EXPECT_EQ(slurp(copy / "data" / "model.gltf"), msh::view::three_example_gltf("material/"));
  // The three.js copied is the locked version.
  const json lock = json::parse(slurp(kSource / "integrations" / "three" / "package-lock.json"));
  EXPECT_EQ(json::parse(slurp(copy / "three" / "package.json"))["version"],
            lock["packages"]["node_modules/three"]["version"]);
}

// `view --three` serves the example from a copy in the cache directory, removed when Ctrl-C stops it.
TEST(ThreeExample, ServesTheExampleAndCleansUp) {
  REQUIRE_BROWSER();
  const fs::path dir = scratch_dir("three");
  Server s = start_view({"--three", "--port", "0", "--cache", kViewerCache.string()}, dir);
  if (s.url.empty()) {
    stop_view(s);
    FAIL() << "the server printed no URL: " << slurp(s.err);
  }
  const fs::path served = kViewerCache / ("three-example-" + std::to_string(s.pid));
  EXPECT_TRUE(fs::is_regular_file(served / "index.html"));
  const auto [st, page] = http_get(s.url, "/");
  EXPECT_NE(st.find("200"), std::string::npos) << st;
  EXPECT_NE(page.find("importmap"), std::string::npos);
  EXPECT_EQ(http_get(s.url, "/microshadow-three/generated/methods.js").second,
            msh::view::methods_js(occlusion::micro_shadowing_methods()));
  EXPECT_EQ(http_get(s.url, "/data/model.gltf").second, msh::view::three_example_gltf("material/"));
  EXPECT_NE(http_get(s.url, "/three/build/three.module.js").first.find("200"), std::string::npos);
  EXPECT_EQ(stop_view(s), 0) << slurp(s.err);
  EXPECT_FALSE(fs::exists(served)) << "the served copy was left in the cache";
}

// ---- the browser ---------------------------------------------------------------------------------------

// docs/three.md's glTF block ("## A glTF model", the first js block) with 'model.glb' replaced by `model`
// (a JS expression); "" when the section, the block or 'model.glb' is missing.
std::string docs_gltf_block(const std::string& model) {
  const std::string doc = slurp(kSource / "docs" / "three.md");
  const auto h = doc.find("## A glTF model");
  const auto a = h == std::string::npos ? h : doc.find("```js\n", h);
  const auto b = a == std::string::npos ? a : doc.find("```", a + 6);
  if (b == std::string::npos) return "";
  std::string block = doc.substr(a + 6, b - a - 6);
  const auto glb = block.find("'model.glb'");
  if (glb == std::string::npos) return "";
  return block.replace(glb, 11, model);
}

// The C++ value of one lobe's term at a probe pixel: the point term (the registry's evaluator, at the pixel's
// azimuth, its own v and l or in two stages as the GLSL form says), or for the rect light's 'cap' form the
// area-light fast form over the equivalent cap (occlusion/micro_shadowing_area.h).
struct Reference {
  std::map<std::string, std::unique_ptr<occlusion::MicroShadowingEvaluator>> evaluators;
  double eval(const json& lobe, bool rect, float V, float nl, float nv, float r, const Vec3f& v,
              const Vec3f& l, double nl_cap, double rho, int samples) {
    const json& c = lobe["cpp"];
    const std::string term = c["method"];
    if (rect && lobe["form"] == "cap") {
      if (term == "reference") return micro_shadowing::reference_step_area_cap<double>(V, nl_cap, rho);
      if (term == "brinck-maximov-2016")
        return micro_shadowing::brinck_maximov_2016_area_cap<double>(V, nl_cap, rho);
      if (term == "chan-2018") return micro_shadowing::chan_2018_area_cap<double>(V, nl_cap, rho);
      if (term == "part1-analytic") return micro_shadowing::part1_analytic_area_cap<double>(V, nl_cap, rho);
      if (term == "generic-vndf-alu")
        return micro_shadowing::generic_vndf_alu_area_cap<double>(V, nl_cap, nv, r, rho);
      ADD_FAILURE() << "no C++ area form for " << term;
      return -1;
    }
    if (c.value("frame", false)) {
      const float a = r * r;
      return micro_shadowing::generic_vndf_estimate<float>(V, GGX<float>(a, a), v, l, samples,
                                                           micro_shadowing::G2Form::HeightCorrelated, 1u);
    }
    if (c.value("two_stage", false)) return micro_shadowing::generic_vndf_alu_two_stage<float>(V, nl, nv, r);
    // The shader ports the float closed form (shaders/glsl/micro_shadowing_aware.glsl); the registry
    // evaluates it in double, which differs by up to 1e-3 at low roughness (docs/micro-shadowing-aware.md).
    if (term == "specular-aware-alu")
      return micro_shadowing::specular_aware_azimuth_mean<float>(V, r * r, nl, nv);
    const bool with_phi = c.value("phi", false);
    auto& e = evaluators[term];
    if (!e) e = std::make_unique<occlusion::MicroShadowingEvaluator>(term);
    occlusion::MicroShadowingQuery q{V, nl, nv, r, std::nullopt, std::nullopt};
    if (with_phi) q.phi = std::acos(std::clamp(double(lut::relative_azimuth_cos(v, l)), -1.0, 1.0));
    return e->eval(q);
  }
};

// The tables the page loads besides the served raw half floats, written into the copy: the default 3D table
// as `bake micro-shadowing --out lut.npy` writes it (float32 NPY and its sidecar), for the module's NPY
// loader, and as `make install` ships it (share/microshadow/tables/micro_shadowing.ktx2, baked at build time
// by `bake micro-shadowing`), for three's KTX2Loader.
void add_table_files(const fs::path& copy) {
  io::write_volume(copy / "data" / "lut3d.npy", lut::default_micro_shadowing_lut(false)->volume,
                   io::FileFormat::Npy);
  io::write_file_atomic(copy / "data" / "lut3d.npy.json",
                        lut::sidecar_json(lut::default_bake_options(lut::LutLayout::Cone)));
  const fs::path ktx2 =
      fs::path(MSH_BINARY_DIR) / "share" / "microshadow" / "tables" / "micro_shadowing.ktx2";
  ASSERT_TRUE(fs::is_regular_file(ktx2)) << ktx2 << " is missing: build the target microshadow_tables";
  fs::copy_file(ktx2, copy / "data" / "lut3d.ktx2", fs::copy_options::overwrite_existing);
  fs::copy_file(ktx2.string() + ".json", copy / "data" / "lut3d.ktx2.json",
                fs::copy_options::overwrite_existing);
}

// docs/three.md's glTF block as written, in a harness: a scene, the example's glTF model for model.glb, one
// render; the harness reports each mesh's program cache key (the module's key when the call took).
void write_gltf_snippet(const fs::path& file) {
  const std::string block = docs_gltf_block("'data/model.gltf'");
  ASSERT_FALSE(block.empty()) << "docs/three.md has no glTF block loading 'model.glb'";
  std::ofstream(file)
      << "import * as THREE from 'three';\nconst scene = new THREE.Scene();\n"
      << block
      << "\ntry {\n  const r = new THREE.WebGLRenderer();\n  r.setSize(64, 64);\n"
         "  const cam = new THREE.PerspectiveCamera(40, 1, 0.1, 20);\n  cam.position.set(0, 1, 3);\n"
         "  cam.lookAt(0, 0, 0);\n  scene.add(new THREE.DirectionalLight(0xffffff, 2));\n  r.render(scene, "
         "cam);\n"
         "  const keys = [];\n  scene.traverse((o) => { if (o.isMesh) "
         "keys.push(o.material.customProgramCacheKey()); });\n"
         "  window.mshSnippet = { keys, gl_error: r.getContext().getError(), programs: "
         "r.info.programs.length };\n"
         "} catch (e) { window.mshSnippet = { error: e.message }; }\n";
}

// The page loaded the example; docs/three.md's glTF block patched every mesh of the glTF model and compiled.
void check_example_and_snippet(const json& res) {
  EXPECT_TRUE(res["errors"].empty()) << res["errors"].dump(1);
  ASSERT_TRUE(res.value("example_loaded", false)) << res["errors"].dump(1);
  EXPECT_GT(res["example_mean"].get<double>(), 0.05) << "the example's frame is (nearly) black";
  const auto& sn = res["snippet"];
  ASSERT_TRUE(sn.is_object() && !sn.contains("error")) << sn.dump();
  ASSERT_FALSE(sn["keys"].empty());
  for (const auto& k : sn["keys"])
    EXPECT_NE(k.get<std::string>().find("msh:diffuse-aware-alu+generic-vndf-alu:aoMap"), std::string::npos)
        << k;
  EXPECT_EQ(sn["gl_error"], 0);
  EXPECT_GE(sn["programs"].get<int>(), 1);
  for (const auto& f : res["screenshots"]) EXPECT_TRUE(fs::is_regular_file(f.get<std::string>())) << f;
}

// The NPY table loads to the same texture as the raw half floats (same size; half conversions agree to 1
// ulp). The installed KTX2 table (R16F, through three's KTX2Loader) holds the raw tables' half floats, and
// lut3d renders through it exactly as through them.
void check_table_loaders(const json& res) {
  ASSERT_TRUE(res["npy"].is_object()) << "the NPY table was not loaded";
  EXPECT_EQ(res["npy"]["size"], res["npy"]["f16_size"]);
  EXPECT_EQ(res["npy"]["n"], res["npy"]["f16_n"]);
  EXPECT_LE(res["npy"]["max_ulps"].get<int>(), 1);
  ASSERT_TRUE(res["npy"].contains("ktx2")) << "the KTX2 table was not loaded";
  const auto& kt = res["npy"]["ktx2"];
  EXPECT_TRUE(kt.value("is3d", false));
  EXPECT_EQ(kt["size"], res["npy"]["f16_size"]);
  EXPECT_EQ(kt["n"], res["npy"]["f16_n"]);
  EXPECT_EQ(kt["max_ulps"].get<int>(), 0);
  const std::size_t nm = res["methods"].size();
  ASSERT_EQ(res["runs"].size(), nm + 2);
  const auto& K = res["runs"][nm + 1];
  ASSERT_EQ(K["method"], "lut3d");
  const auto it = std::find_if(res["runs"].begin(), res["runs"].end(),
                               [](const json& r) { return r["method"] == "lut3d"; });
  double kd = 0;
  for (const char* key : {"terms_d", "terms_s"})
    for (int p = 0; p < int(res["points"].size()); ++p)
      for (int k = 0; k < 4; ++k)
        kd = std::max(kd, std::abs(K[key][p][k].get<double>() - (*it)[key][p][k].get<double>()));
  EXPECT_EQ(kd, 0.0) << "lut3d through the KTX2 table differs from the raw half floats";
}

// Every method of the registry with a GLSL form is in the module's list, and none is left out (the module
// keeps the entries whose GLSL functions its shader files define), except the forms that read per-texel
// directional channels ("texel"): the probe leaves them out, they need a texture set's channels
// (test_three_directional_browser tests directional-view).
void check_method_list(const json& res) {
  std::vector<std::string> ids;
  for (const auto& m : res["methods"]) ids.push_back(m["id"]);
  for (const char* want : {"none", "ao", "reference", "brinck-maximov-2016", "chan-2018", "part1-analytic",
                           "generic-vndf", "generic-vndf-alu", "lut3d", "lut2d", "lut3d-azimuth",
                           "diffuse-aware-alu+generic-vndf-alu", "diffuse-aware-alu+lut3d"})
    EXPECT_NE(std::find(ids.begin(), ids.end(), want), ids.end()) << want;
  const std::string mjs = msh::view::methods_js(occlusion::micro_shadowing_methods());
  std::size_t entries = 0, texel = 0;
  for (auto p = mjs.find("\n  {\"id\":"); p != std::string::npos; p = mjs.find("\n  {\"id\":", p + 1)) {
    const std::string line = mjs.substr(p + 1, mjs.find('\n', p + 1) - p - 1);
    (line.find("\"texel\"") != std::string::npos ? texel : entries) += 1;
  }
  EXPECT_GE(texel, 1u) << "the registry's directional form (texel) is not in methods.js";
  EXPECT_EQ(res["methods"].size(), entries) << "a method of methods.js is missing from the module's list";
  for (const auto& id : ids)
    EXPECT_EQ(id.find("directional"), std::string::npos) << id << " needs texel data";
  ASSERT_EQ(res["runs"].size(), res["methods"].size() + 2);
}

// What the probe pixels gather: per light type, each method's and lobe's deviation from the library, and
// the scene checks of the inputs.
struct ProbeResults {
  ProbeStats stats;  // [light type][method + lobe]
  std::map<std::string, double> scene_nl, scene_nv, scene_cap;
  std::map<std::string, int> lit_count;
  double direct_max = 0;
  int direct_n = 0, v_const_seen = 0;
};

// One probe pixel under one light (`type`, the k-th of res["light_order"]) as the page read it.
struct ProbePixel {
  std::string type;
  int p = 0, k = 0;
  bool rect = false;
  float V = 0, nl = 0, nv = 0, r = 0;
  Vec3f v, l;
  Vec3d P, n;
  double nl_cap = 0, rho = 0;  // rect: the equivalent cap's N.L and angular radius
};

// The pixel's inputs against the scene: V one of the texture's levels (or the constant of the variant run),
// roughness of a level, N.V from the pixel's position and normal, N.L from the light (the rect light: its
// equivalent cap as three places it, WebGLLights, seen from the pixel).
void check_pixel_inputs(const json& res, const ProbePixel& x, bool variant, ProbeResults& out) {
  const auto& lights = res["lights"];
  bool level = false;
  for (double lv : res["v_levels"]) level = level || std::abs(x.V - lv) < 1e-6;
  const bool is_const = variant && std::abs(x.V - res["v_const"].get<double>()) < 1e-6;
  out.v_const_seen += is_const;
  EXPECT_TRUE(level || is_const) << x.type << " V = " << x.V;
  bool rough_ok = false;
  for (double lv : res["roughness"]) rough_ok = rough_ok || (x.r >= lv - 1e-6 && x.r <= lv + 0.15);
  EXPECT_TRUE(rough_ok) << x.type << " roughness " << x.r;
  const double nv_scene = std::clamp(dot(x.n, -normalize(x.P)), 0.0, 1.0);
  out.scene_nv[x.type] = std::max(out.scene_nv[x.type], std::abs(x.nv - nv_scene));
  if (!x.rect) {
    const Vec3d wl = light_dir(lights, x.type, x.P);
    out.scene_nl[x.type] =
        std::max(out.scene_nl[x.type], std::abs(x.nl - std::clamp(dot(x.n, wl), 0.0, 1.0)));
  } else {
    const Vec3d c = vec3(lights["rect"]["position"]) - x.P, hw = vec3(lights["rect"]["half_width"]),
                hh = vec3(lights["rect"]["half_height"]);
    const Vec3d corners[4] = {c + hw - hh, c - hw - hh, c - hw + hh, c + hw + hh};
    const Vec3d F = micro_shadowing::polygon_vector_form_factor(corners, 4);
    const double lf = length(F), q = std::clamp(lf / 3.14159265358979323846, 0.0, 1.0);
    out.scene_cap[x.type] = std::max({out.scene_cap[x.type], std::abs(x.nl_cap - dot(F, x.n) / lf),
                                      std::abs(x.rho - std::atan2(std::sqrt(q), std::sqrt(1 - q)))});
  }
}

// Each lobe's term of run R at the pixel against the library's.
void check_pixel_terms(const json& method, const std::string& id, const json& R, const ProbePixel& x,
                       int samples, Reference& ref, ProbeResults& out) {
  for (int lobe = 0; lobe < 2; ++lobe) {
    const json& lb = method["lobes"][lobe ? "specular" : "diffuse"];
    const std::string term = lb["cpp"]["method"];
    // A rect light uses the term's cap form where the registry gives one (area_cap, which the module
    // reads from its generated methods.js), else the point term at the cap's axis.
    if (x.rect) {
      const auto* info = occlusion::find_micro_shadowing_method(term);
      const bool has_cap = info && !info->glsl.empty() && !info->glsl.front().area_cap.empty();
      EXPECT_EQ(lb["form"], has_cap ? "cap" : "axis") << id << " " << term;
    }
    if (term == "reference" && !x.rect && std::abs(double(x.nl) - std::sqrt(1.0 - x.V)) < 1e-4) continue;
    const double want = ref.eval(lb, x.rect, x.V, x.nl, x.nv, x.r, x.v, x.l, x.nl_cap, x.rho, samples);
    const double got = R[lobe ? "terms_s" : "terms_d"][x.p][x.k];
    const double got8 = R[lobe ? "terms8_s" : "terms8_d"][x.p][x.k].get<double>() / 255.0;
    // The contract: 8-bit output within 2/255 of the library. The float32 value besides: within the
    // shaders' documented precision for forms of arithmetic and square roots (1e-4); LUTs: half floats
    // and the GPU's filter weights (1e-3); the estimator: a sample whose decision flips moves it by
    // 1/n. Forms built on sin/cos/atan/acos (the rect light's cap forms, specular-aware-alu) are
    // asserted at 2/255 only: their documented precision is lavapipe's, SwiftShader's transcendentals
    // differ more (the table printed below and docs/three.md give the float deviation).
    double tol = 1e-4, tol8 = 2.0 / 255;
    if (lb["cpp"].value("frame", false)) tol = 2.0 / samples + 1e-4, tol8 = 1.0 / 255 + 2.0 / samples;
    if (term.rfind("lut", 0) == 0) tol = 1e-3;
    if ((x.rect && lb["form"] == "cap") || term == "specular-aware-alu") tol = tol8;
    const std::string what = id + (lobe ? " specular" : " diffuse");
    EXPECT_NEAR(got, want, tol)
        << what << " (" << x.type << ") at V=" << x.V << " N.L=" << x.nl << " N.V=" << x.nv << " r=" << x.r
        << (x.rect ? " cap N.L=" + std::to_string(x.nl_cap) + " rho=" + std::to_string(x.rho) : "");
    EXPECT_NEAR(got8, want, tol8) << what << " 8-bit (" << x.type << ")";
    out.stats[x.type][what].add(std::abs(got - want), std::abs(got8 - want));
  }
}

// Micro-shadowing multiplies the light's direct diffuse and specular by the two lobes' terms (the
// variant run renders each light with it on and off).
void check_pixel_direct(const json& L, const json& R, const ProbePixel& x, ProbeResults& out) {
  const auto &on = L["direct_on"][x.p], &off = L["direct_off"][x.p];
  for (int lobe = 0; lobe < 2; ++lobe) {
    const double o = off[lobe], term = R[lobe ? "terms_s" : "terms_d"][x.p][x.k];
    if (!(o > 1e-4)) continue;
    const double d = std::abs(on[lobe].get<double>() - o * term) / o;
    EXPECT_LE(d, 1e-4) << x.type << (lobe ? " specular" : " diffuse") << ": on " << on[lobe] << " off " << o
                       << " term " << term;
    out.direct_max = std::max(out.direct_max, d);
    ++out.direct_n;
  }
}

// Every run (a method each, then the variant with V from the aoMap, a map and a constant), light and lit
// probe pixel: the inputs against the scene (once per input set), the terms against the library, and in the
// variant run the direct light on and off.
void check_probes(const json& res, Reference& ref, ProbeResults& out) {
  const std::vector<std::string> order = res["light_order"];
  const int samples = res["samples"];
  const auto& plain_inputs = res["runs"][0]["lights"];
  const std::size_t nm = res["methods"].size();
  ASSERT_TRUE(res["runs"][nm]["variant"].get<bool>());
  const int npts = int(res["points"].size());
  for (std::size_t run = 0; run <= nm; ++run) {
    const auto& R = res["runs"][run];
    const bool variant = R["variant"];
    const auto& in = variant ? R["lights"] : plain_inputs;
    const auto& m = res["methods"][std::min(run, nm - 1)];
    ASSERT_EQ(R["method"], variant ? json("diffuse-aware-alu+generic-vndf-alu") : m["id"]);
    const json& method = variant ? *std::find_if(res["methods"].begin(), res["methods"].end(),
                                                 [&](const json& x) { return x["id"] == R["method"]; })
                                 : m;
    const std::string id = method["id"].get<std::string>() + (variant ? " (V: aoMap, map, constant)" : "");
    for (int k = 0; k < int(order.size()); ++k) {
      const auto& L = in[k];
      for (int p = 0; p < npts; ++p) {
        const auto& pos = L["position"][p];
        if (!(pos[3].get<double>() > 0.5)) continue;  // background
        ProbePixel x;
        x.type = order[k], x.p = p, x.k = k, x.rect = x.type == "rect";
        x.V = L["inputs"][p][0], x.nl = L["inputs"][p][1], x.nv = L["inputs"][p][2], x.r = L["inputs"][p][3];
        x.v = Vec3f(vec3(L["v"][p])), x.l = Vec3f(vec3(L["l"][p]));
        x.P = vec3(pos), x.n = vec3(L["normal"][p]);
        if (x.rect) x.nl_cap = L["cap"][p][0], x.rho = L["cap"][p][1];
        if (run == 0 || variant) check_pixel_inputs(res, x, variant, out);
        if (!(x.rect ? x.rho > 0 : x.nl > 0)) continue;  // unlit
        ++out.lit_count[x.type];
        check_pixel_terms(method, id, R, x, samples, ref, out);
        if (variant) check_pixel_direct(L, R, x, out);
      }
    }
  }
}

// Enough lit pixels per light; the inputs as the scene gives them; the variant run saw the cylinder
// (constant V) and enough pixels for the direct on/off check.
void check_probe_coverage(const json& res, ProbeResults& pr) {
  for (const std::string& t : res["light_order"].get<std::vector<std::string>>()) {
    EXPECT_GE(pr.lit_count[t] / int(res["runs"].size()), 20) << t << ": too few lit probe pixels";
    if (t != "rect") {
      EXPECT_LE(pr.scene_nl[t], 1e-4) << t << ": N.L differs from the scene's";
    } else {
      EXPECT_LE(pr.scene_cap[t], 1e-3) << "the rect light's equivalent cap differs from the scene's";
    }
    EXPECT_LE(pr.scene_nv[t], 1e-4) << t << ": N.V differs from the scene's";
  }
  EXPECT_GT(pr.v_const_seen, 0) << "no pixel of the cylinder (constant V) was probed";
  EXPECT_GE(pr.direct_n, 100) << "too few pixels for the on/off check of the direct light";
}

// aoOnIndirect: three's AO multiplies the indirect diffuse light by V when on, and is left out when off.
void check_ao_switch(const json& res) {
  const auto& ao = res["ao_switch"];
  int ao_n = 0;
  for (int p = 0; p < int(res["points"].size()); ++p) {
    const double on = ao["on"][p][1], off = ao["off"][p][1], V = ao["inputs"][p][0];
    if (!(ao["off"][p][3].get<double>() > 0.5)) continue;
    ASSERT_GT(off, 1e-3) << "no indirect light at a probe pixel";
    EXPECT_NEAR(on, off * V, 1e-4 * off) << "aoOnIndirect at V = " << V;
    ++ao_n;
  }
  EXPECT_GE(ao_n, 50);
}

// areaLights: the option's API (the two modes, a bad value or another key one line, the default 'cap').
void check_area_api(const json& A) {
  ASSERT_TRUE(A.is_object()) << "no areaLights results";
  EXPECT_EQ(A["error"], 0);
  for (const char* lobe : {"diffuse", "specular"}) EXPECT_EQ(A["lobes"][lobe]["form"], "center") << lobe;
  EXPECT_EQ(A["handle_forms"], json({"center", "center"}));
  EXPECT_NE(A["key"].get<std::string>().find(":area-center"), std::string::npos) << A["key"];
  const auto& api = A["api"];
  const std::string bad = api["bad"].is_string() ? api["bad"] : "",
                    other = api["other"].is_string() ? api["other"] : "";
  EXPECT_NE(bad.find("areaLights must be 'cap' or 'center'"), std::string::npos) << api.dump();
  EXPECT_NE(other.find("'areaLights'"), std::string::npos) << api.dump();
  EXPECT_EQ(bad.find('\n'), std::string::npos) << bad;
  EXPECT_EQ(other.find('\n'), std::string::npos) << other;
  EXPECT_TRUE(api["default_same"].get<bool>()) << "{} and { areaLights: 'cap' } differ";
  EXPECT_EQ(api["after_dispose"], "center");
  EXPECT_EQ(api["modes"], json({"cap", "center"}));
}

// areaLights 'center' (three_probe.js area()): over the rect light each lobe's term is the point term at the
// direction to the rectangle's centre, N.L that of the centre as three places the light; it is not the cap
// form (the two differ at the probes). Micro-shadowing off gives the module-absent frame bit for bit
// (float32, every light, 'cap' and 'center'); on differs (the comparison sees the term).
void check_area_center(const json& A, int npts, int samples, Reference& ref) {
  double center_nl = 0, center_float = 0, center_8bit = 0, cap_vs_center = 0;
  int center_n = 0;
  const Vec3d c0 = vec3(A["rect"]["position"]);
  const auto& C = A["center"];
  for (int p = 0; p < npts; ++p) {
    if (!(C["terms"][p][3].get<double>() > 0.75)) continue;  // the centre below the horizon, or no surface
    const auto& in = C["inputs"][p];
    const float V = in[0], nl = in[1], nv = in[2], r = in[3];
    const Vec3d P = vec3(C["position"][p]), n = normalize(vec3(C["normal"][p]));
    center_nl = std::max(center_nl, std::abs(nl - std::clamp(dot(n, normalize(c0 - P)), 0.0, 1.0)));
    const Vec3f v(C["v"][p][0].get<float>(), C["v"][p][1].get<float>(), C["v"][p][2].get<float>());
    const Vec3f l(C["l"][p][0].get<float>(), C["l"][p][1].get<float>(), C["l"][p][2].get<float>());
    for (int lobe = 0; lobe < 2; ++lobe) {
      const json& lb = A["lobes"][lobe ? "specular" : "diffuse"];
      const double want = ref.eval(lb, false, V, nl, nv, r, v, l, 0, 0, samples);
      const double got = C["terms"][p][lobe], got8 = C["terms8"][p][lobe].get<double>() / 255;
      EXPECT_NEAR(got, want, 1e-4) << "areaLights 'center' " << (lobe ? "specular" : "diffuse")
                                   << " at V=" << V << " N.L=" << nl << " N.V=" << nv << " r=" << r;
      EXPECT_NEAR(got8, want, 2.0 / 255) << "areaLights 'center' 8-bit";
      center_float = std::max(center_float, std::abs(got - want));
      center_8bit = std::max(center_8bit, std::abs(got8 - want));
      cap_vs_center = std::max(cap_vs_center, std::abs(got - A["cap"]["terms"][p][lobe].get<double>()));
    }
    ++center_n;
  }
  EXPECT_GE(center_n, 20) << "too few probe pixels lit by the rect light's centre";
  EXPECT_LE(center_nl, 1e-4) << "areaLights 'center': N.L is not that of the rectangle's centre";
  EXPECT_GT(cap_vs_center, 1.0 / 255) << "areaLights 'center' gives the cap form";
  for (const char* mode : {"cap", "center"}) {
    const auto& d = A["disabled"][mode];
    EXPECT_EQ(d["off"]["differing"], 0)
        << mode << ": enabled = false differs from the module absent: " << d["off"].dump();
    EXPECT_GT(d["on"]["max"].get<double>(), 1e-3) << mode << ": on does not differ from absent";
  }
  std::printf(
      "areaLights 'center' (%s): %d lit probe pixels, N.L of the centre %.1e, |three.js - C++ point term| "
      "%.2f/255 at 8 bits (%.3f/255 float); max |center - cap| %.1f/255; enabled = false vs absent: %d / %d "
      "float32 values differ ('cap'), %d ('center')\n",
      A["method"].get<std::string>().c_str(), center_n, center_nl, center_8bit * 255, center_float * 255,
      cap_vs_center * 255, A["disabled"]["cap"]["off"]["differing"].get<int>(),
      A["disabled"]["cap"]["off"]["values"].get<int>(),
      A["disabled"]["center"]["off"]["differing"].get<int>());
}

// 'center' against 'cap' at the probes, rect lights of 3 sizes at 2 distances (printed and written to
// `file`; docs/three.md).
void print_area_accuracy(const json& A, const fs::path& file) {
  std::printf(
      "areaLights 'center' - 'cap' per lobe, in 1/255 (RMS / max |d|) over the probe pixels where the "
      "rectangle's centre is above the horizon; horizon: pixels where only part of it is (there 'center' is "
      "the term at N.L = 0):\n");
  json accuracy = json::array();
  for (const auto& e : A["accuracy"]) {
    std::vector<double> rho = e["rho"];
    std::sort(rho.begin(), rho.end());
    const json& lit = e["center_lit"];
    int horizon = 0;
    for (const auto& x : lit) horizon += !x.get<bool>();
    const auto rms_max = [&](const json& a) {
      double s2 = 0, m = 0;
      int k = 0;
      for (std::size_t i = 0; i < a.size(); ++i)
        if (lit[i].get<bool>())
          s2 += a[i].get<double>() * a[i].get<double>(), m = std::max(m, std::abs(a[i].get<double>())), ++k;
      return std::pair<double, double>{k ? std::sqrt(s2 / k) * 255 : 0, m * 255};
    };
    const auto [dr, dm] = rms_max(e["d"]);
    const auto [sr, sm] = rms_max(e["s"]);
    const double rmed = rho.empty() ? 0 : rho[rho.size() / 2] * 180 / 3.14159265358979323846;
    const double rmax = rho.empty() ? 0 : rho.back() * 180 / 3.14159265358979323846;
    const double w = e["rect"]["width"], h = e["rect"]["height"];
    std::printf(
        "  %-36s rect %.1f x %.1f, distance x %.1f: n %3zu (horizon %2d), rho median %4.1f deg (max %4.1f); "
        "diffuse %5.1f / %5.1f, specular %5.1f / %5.1f\n",
        e["method"].get<std::string>().c_str(), w, h, e["distance"].get<double>(), rho.size() - horizon,
        horizon, rmed, rmax, dr, dm, sr, sm);
    EXPECT_FALSE(rho.empty()) << e["method"] << " size x" << e["size"] << " distance x" << e["distance"];
    accuracy.push_back({{"method", e["method"]},
                        {"width", w},
                        {"height", h},
                        {"distance", e["distance"]},
                        {"n", rho.size() - horizon},
                        {"horizon", horizon},
                        {"rho_median_deg", rmed},
                        {"rho_max_deg", rmax},
                        {"diffuse_rms_255", dr},
                        {"diffuse_max_255", dm},
                        {"specular_rms_255", sr},
                        {"specular_max_255", sm}});
  }
  std::ofstream(file) << accuracy.dump(1) << "\n";
}

// The run's figures (module size, frame time, the scene checks) and the table of the probe deviations,
// written to DIR/comparison.json.
void print_probe_summary(const json& res, ProbeResults& pr, double secs, const fs::path& shots) {
  const auto& bundle = res["bundle"];
  const std::vector<std::string> order = res["light_order"];
  std::printf(
      "three.js r%s: %zu methods x 4 lights, %d probe points; module %.1f kB (%.1f kB gzip, GLSL %.1f kB); "
      "frame at 1280x720 (SwiftShader) %.0f ms with micro-shadowing, %.0f ms without; scene checks: N.L "
      "%.1e, N.V %.1e, cap %.1e; direct on/off relative %.1e (n=%d); test %.0f s (driver %.0f s)\n",
      res["revision"].get<std::string>().c_str(), res["methods"].size(), int(res["points"].size()),
      bundle["bytes"].get<double>() / 1000, bundle["gzip_bytes"].get<double>() / 1000,
      bundle["glsl_bytes"].get<double>() / 1000, res["frame_ms"]["with"].get<double>(),
      res["frame_ms"]["without"].get<double>(),
      std::max({pr.scene_nl["point"], pr.scene_nl["spot"], pr.scene_nl["directional"]}),
      std::max({pr.scene_nv["point"], pr.scene_nv["spot"], pr.scene_nv["directional"], pr.scene_nv["rect"]}),
      pr.scene_cap["rect"], pr.direct_max, pr.direct_n, secs, res["timing"]["done"].get<double>());
  std::printf(
      "max |three.js - C++| per method and lobe, 8-bit output in 1/255 (float32 target in 1/255):\n  %-58s",
      "method, lobe");
  for (const auto& t : order) std::printf(" %-17s", t.c_str());
  std::printf("\n");
  print_probe_table(
      pr.stats, order, 58,
      [](const std::string&, const ProbeStat& st) {
        std::printf(" %5.2f (%6.3f) %3d", st.max_8bit * 255, st.max_float * 255, st.n);
        return json{{"max_8bit_255", st.max_8bit * 255}, {"max_float_255", st.max_float * 255}, {"n", st.n}};
      },
      shots / "comparison.json");
}

TEST(ThreeBrowser, EveryLightAndMethodMatchesTheLibrary) {
  REQUIRE_BROWSER();
  const auto t_start = std::chrono::steady_clock::now();
  const fs::path dir = scratch_dir("three");
  const fs::path shots = fs::path(MSH_BINARY_DIR) / "three_screenshots";
  fs::remove_all(shots);
  const fs::path& copy = example_copy();
  ASSERT_TRUE(fs::is_regular_file(copy / "index.html"));
  ASSERT_NO_FATAL_FAILURE(add_table_files(copy));
  ASSERT_NO_FATAL_FAILURE(write_gltf_snippet(dir / "snippet.js"));
  // The static copy served as is (`microshadow view --root`), the driver in the browser.
  const json res = run_three_test(copy, shots, "--snippet " + (dir / "snippet.js").string(), dir);
  ASSERT_TRUE(res.is_object());
  ASSERT_NO_FATAL_FAILURE(check_example_and_snippet(res));
  ASSERT_NO_FATAL_FAILURE(check_table_loaders(res));
  ASSERT_NO_FATAL_FAILURE(check_method_list(res));
  Reference ref;
  ProbeResults probes;
  ASSERT_NO_FATAL_FAILURE(check_probes(res, ref, probes));
  check_probe_coverage(res, probes);
  ASSERT_NO_FATAL_FAILURE(check_ao_switch(res));
  ASSERT_NO_FATAL_FAILURE(check_area_api(res["area"]));
  check_area_center(res["area"], int(res["points"].size()), res["samples"], ref);
  print_area_accuracy(res["area"], shots / "area_center.json");
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  print_probe_summary(res, probes, secs, shots);
}

// docs/three.md's glTF block on an asset with what ordinary models hold (tests/browser/three_scene_probe.js
// builds it in the page): a mesh used by two nodes (its material shared, with an occlusion texture), a
// material without occlusion, a KHR_materials_unlit one (MeshBasicMaterial) and a KHR_materials_clearcoat one
// with occlusion (MeshPhysicalMaterial). addMicroShadowingToScene patches the two materials with an aoMap
// once each and skips the others with their codes; a second call returns the same handles and changes
// nothing; other options give conflicts; the render changes on the patched quads and nowhere else (float32,
// bit for bit). Besides, addMicroShadowing's idempotency, dispose(), arrays of materials and the roll-back on
// fresh materials (the page's named checks).
TEST(ThreeBrowser, GltfBlockPatchesEachSceneMaterialOnce) {
  REQUIRE_BROWSER();
  const fs::path dir = scratch_dir("three");
  const fs::path out = fs::path(MSH_BINARY_DIR) / "three_scene";
  fs::remove_all(out);
  const fs::path& copy = example_copy();
  ASSERT_TRUE(fs::is_regular_file(copy / "index.html"));
  const std::string block = docs_gltf_block("window.mshScene.url");
  ASSERT_FALSE(block.empty()) << "docs/three.md has no glTF block loading 'model.glb'";
  // The block as written; the page's scene for `scene`, the asset's URL for 'model.glb'.
  std::ofstream(dir / "scene_snippet.js")
      << "const scene = window.mshScene.scene;\n"
      << block << "\nwindow.mshSnippet = window.mshScene.check(gltf, report, options);\n";
  const json res = run_three_test(copy, out, "--scene-snippet " + (dir / "scene_snippet.js").string(), dir);
  ASSERT_TRUE(res.is_object());
  EXPECT_TRUE(res["errors"].empty()) << res["errors"].dump(1);
  ASSERT_TRUE(res["scene"].is_object()) << res["errors"].dump(1);
  const json& sc = res["scene"];

  // addMicroShadowing and addMicroShadowingToScene on fresh materials.
  ASSERT_TRUE(sc["api"].is_object() && !sc["api"].empty()) << sc["api"].dump();
  for (const auto& [name, c] : sc["api"].items())
    EXPECT_TRUE(c["ok"].get<bool>()) << name << ": " << c["detail"];

  const json& sn = sc["snippet"];
  ASSERT_TRUE(sn.is_object() && !sn.contains("error")) << sn.dump() << "\n" << res["errors"].dump(1);
  // The asset as GLTFLoader made it: five meshes, four materials, the two nodes of one mesh sharing one.
  const json& as = sn["asset"];
  EXPECT_EQ(as["meshes"].size(), 5u) << as.dump();
  EXPECT_EQ(as["materials"], 4) << as.dump();
  EXPECT_TRUE(as["shared"].get<bool>()) << "the mesh used by two nodes does not share its material";
  EXPECT_EQ(as["types"]["shared_a"], "MeshStandardMaterial");
  EXPECT_EQ(as["types"]["plain"], "MeshStandardMaterial");
  EXPECT_EQ(as["types"]["unlit"], "MeshBasicMaterial");
  EXPECT_EQ(as["types"]["clearcoat"], "MeshPhysicalMaterial");
  EXPECT_GT(as["clearcoat"].get<double>(), 0.0);
  EXPECT_TRUE(as["aomap"]["shared_a"].get<bool>() && as["aomap"]["clearcoat"].get<bool>());
  EXPECT_FALSE(as["aomap"]["plain"].get<bool>());

  // The report: the two materials with an aoMap patched, each once; the others skipped with their codes.
  const auto names = [](const json& list, const char* key) {
    std::vector<std::string> v;
    for (const auto& e : list) v.push_back(e[key].get<std::string>());
    std::sort(v.begin(), v.end());
    return v;
  };
  using Names = std::vector<std::string>;
  EXPECT_EQ(names(sn["patched"], "name"), (Names{"clearcoat", "shared"})) << sn["patched"].dump();
  EXPECT_EQ(sn["handles"], 2);
  EXPECT_EQ(names(sn["skipped"], "code"), (Names{"no-aomap", "unsupported"})) << sn["skipped"].dump();
  EXPECT_EQ(names(sn["skipped"], "name"), (Names{"no_occlusion", "unlit"})) << sn["skipped"].dump();
  for (const auto& e : sn["skipped"]) {
    const std::string reason = e["reason"];
    EXPECT_FALSE(reason.empty());
    EXPECT_EQ(reason.find('\n'), std::string::npos) << reason;
  }
  // The block's console.info line per skipped material.
  EXPECT_EQ(sc["info"].size(), 2u) << sc["info"].dump(1);
  // The same call again: the same handles, the same skips, no material changed (version, hook).
  EXPECT_TRUE(sn["again"]["same_handles"].get<bool>()) << sn["again"].dump();
  EXPECT_TRUE(sn["again"]["unchanged"].get<bool>()) << "the second call patched again";
  EXPECT_EQ(names(sn["again"]["skipped"], "code"), (Names{"no-aomap", "unsupported"}));
  // Another method: the patched two are conflicts, nothing patched, nothing changed.
  EXPECT_TRUE(sn["other"]["patched"].empty()) << sn["other"].dump();
  EXPECT_EQ(names(sn["other"]["skipped"], "code"),
            (Names{"conflict", "conflict", "no-aomap", "unsupported"}));
  EXPECT_TRUE(sn["other"]["unchanged"].get<bool>());
  // addMicroShadowing on the shared material: its handle again; other options, one line naming the option.
  EXPECT_TRUE(sn["single"]["same"].get<bool>());
  const std::string other_error = sn["single"]["other_error"].is_string() ? sn["single"]["other_error"] : "";
  EXPECT_NE(other_error.find("'aoOnIndirect'"), std::string::npos) << other_error;
  EXPECT_NE(other_error.find("dispose()"), std::string::npos) << other_error;
  EXPECT_EQ(other_error.find('\n'), std::string::npos) << other_error;
  // The programs: the module's key on the patched materials only.
  for (const auto& [mesh, key] : sn["keys"].items()) {
    const bool patched = mesh == "shared_a" || mesh == "shared_b" || mesh == "clearcoat";
    EXPECT_EQ(
        key.get<std::string>().find("msh:diffuse-aware-alu+generic-vndf-alu:aoMap") != std::string::npos,
        patched)
        << mesh << ": " << key;
  }
  // The render against the same asset without the module: the patched quads darker at every pixel (the term
  // on: V = 128/255 at N.L 0.39), the unlit and no-occlusion quads bit for bit the same.
  EXPECT_EQ(sn["gl_error"], 0);
  for (const auto& [node, r] : sn["regions"].items()) {
    const int n = r["pixels"];
    EXPECT_GE(n, 400) << node;
    const bool patched = node == "shared_a" || node == "shared_b" || node == "clearcoat";
    if (patched) {
      EXPECT_EQ(r["darker"].get<int>(), n) << node << ": " << r.dump();
      EXPECT_GT(r["max_diff"].get<double>(), 2.0 / 255) << node << ": " << r.dump();
      EXPECT_NE(r["centre_before"], r["centre_after"]) << node;
    } else {
      EXPECT_EQ(r["differing"].get<int>(), 0) << node << ": " << r.dump();
      EXPECT_EQ(r["centre_before"], r["centre_after"]) << node;
    }
    std::printf("  %-10s %4d px: %4d differ, %4d darker, max |diff| %.4f; centre %.4f -> %.4f (R)\n",
                node.c_str(), n, r["differing"].get<int>(), r["darker"].get<int>(),
                r["max_diff"].get<double>(), r["centre_before"][0].get<double>(),
                r["centre_after"][0].get<double>());
  }
  EXPECT_EQ(sn["regions"].size(), 5u);
}

}  // namespace
