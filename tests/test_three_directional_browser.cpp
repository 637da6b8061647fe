// directional-view in three.js (integrations/three, docs/three.md "directional-view"). In headless Debian
// chromium (SwiftShader WebGL2, tests/browser/three_directional_test.mjs with three_directional_probe.js): a
// `gen-material --directional-view` texture set's 21 channels (mips/mips.json, KTX2 with mips, through the
// module's loadDirectionalOcclusion) and a compact fixture written here (K = 8 coefficients of a random
// orthonormal basis, "directional_compact" in mips.json) on a plane (three's tangents, bitangent along +v), a
// sphere (tangents with w negated: bitangent along −v) and a cylinder (no tangents, no normal map, u
// mirrored: a left-handed UV frame), lit by a point, a spot, a directional and a rect-area light. Per probe
// pixel and light, each lobe's term is compared with the C++ library (occlusion/directional.h
// directional_view_term at the pixel's channels, l, v and normal in the channels' frame; the pair's specular
// lobe: the registry's generic-vndf-alu); the inputs are checked against the scene (the frame against the
// surfaces' +u, +v and normal, l and v against the lights and the camera, the UVs against the plane, N·L of
// the frame against three's), the channels fetched nearest against the files' texels (level 0, decoded with
// mips.json's ranges: the row orientation), the compact form's channels against mean + basis · coefficients,
// each light's direct light on/off against the terms; bad input (malformed JSON, a missing texture, a wrong
// K, no renderer, no data) throws one clear line. Fails without chromium/node/playwright-core/three unless
// MSH_ALLOW_NO_BROWSER=1 (then skips).
#include <gtest/gtest.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/texture.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>

#include "support/cli_test_util.h"
#include "support/probe_stats.h"
#include "support/view_server_util.h"

namespace fs = std::filesystem;
using namespace msh;
using namespace msh::test;  // the browser tests' helpers (support/view_server_util.h) and run_cli, slurp, ...
using nlohmann::json;

namespace {

constexpr int kCompactK = 8;

// A camera's matrixWorld as three.js gives it (column-major 4x4): view-space directions to world (its
// rotation) and its position.
struct CameraWorld {
  explicit CameraWorld(const json& matrix) : m(matrix) {}
  Vec3d to_world(const Vec3d& v) const {
    return Vec3d(m[0].get<double>() * v.x + m[4].get<double>() * v.y + m[8].get<double>() * v.z,
                 m[1].get<double>() * v.x + m[5].get<double>() * v.y + m[9].get<double>() * v.z,
                 m[2].get<double>() * v.x + m[6].get<double>() * v.y + m[10].get<double>() * v.z);
  }
  Vec3d position() const { return Vec3d(m[12].get<double>(), m[13].get<double>(), m[14].get<double>()); }
  const json& m;
};

// The coefficients a run fetched nearest (N: its position, dir_uv and a read-backs over npts probes) against
// the level-0 texels of tex (4 coefficients a texture) at each lit probe's UV, decoded with the ranges lo,
// hi: the largest |fetched − texel| / max(1, hi − lo) goes to err, the probes compared are counted in n.
// Probes within 0.05 texel of a texel edge are left out (the fetch may take either texel).
void compare_nearest(const json& N, const std::vector<io::Volume>& tex, const json& lo, const json& hi, int K,
                     int npts, double& err, int& n) {
  for (int p = 0; p < npts; ++p) {
    if (!(N["position"][p][3].get<double>() > 0.5)) continue;
    const double u = N["dir_uv"][p][0], v = N["dir_uv"][p][1];
    const int w = tex[0].width, h = tex[0].height;
    const double fu = (u - std::floor(u)) * w, fv = (v - std::floor(v)) * h;
    if (std::abs(fu - std::round(fu)) < 0.05 || std::abs(fv - std::round(fv)) < 0.05) continue;
    const int tx = std::min(int(fu), w - 1), ty = std::min(int(fv), h - 1);
    for (int k = 0; k < K; ++k) {
      const double l = lo[k], range = hi[k].get<double>() - l;
      const double want = l + range * tex[std::size_t(k / 4)].at(tx, ty, 0, k % 4);
      err = std::max(err, std::abs(N["a"][k / 4][p][k % 4].get<double>() - want) / std::max(1.0, range));
    }
    ++n;
  }
}

// A bad input's error (errors[k]): it threw, one line holding each of parts.
void expect_error_line(const json& errors, const char* k, const std::vector<std::string>& parts) {
  ASSERT_TRUE(errors.contains(k) && errors[k].is_string()) << k << " did not throw: " << errors.dump(1);
  const std::string m = errors[k];
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  for (const auto& p : parts) EXPECT_NE(m.find(p), std::string::npos) << k << ": " << m;
}

// 2x2 box means of a level (even sizes), the mip chain gen-material writes.
io::Volume half_level(const io::Volume& v) {
  io::Volume o(v.width / 2, v.height / 2, 1, v.channels);
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x)
      for (int c = 0; c < v.channels; ++c)
        o.at(x, y, 0, c) = 0.25f * (v.at(2 * x, 2 * y, 0, c) + v.at(2 * x + 1, 2 * y, 0, c) +
                                    v.at(2 * x, 2 * y + 1, 0, c) + v.at(2 * x + 1, 2 * y + 1, 0, c));
  return o;
}

// The compact fixture: K coefficients a = basisᵀ (c − mean) of the material's fine channels on a random
// orthonormal basis (21 x K, Gram–Schmidt, fixed seed), stored as gen-material stores the channels (UNORM8
// between each coefficient's fine-level range, 4 per RGBA8 KTX2 with the box mip chain) and described by
// mips.json's "directional_compact".
json write_compact_fixture(const fs::path& material, const fs::path& out) {
  const io::Volume c = io::read_volume(material / "directional.npy");
  EXPECT_EQ(c.channels, directional::kViewChannels);
  const int n = directional::kViewChannels, K = kCompactK;
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  std::vector<std::vector<double>> B(n, std::vector<double>(K));  // B[i][k]
  for (int k = 0; k < K; ++k) {
    std::vector<double> col(n);
    for (auto& x : col) x = g(rng);
    for (int j = 0; j < k; ++j) {
      double d = 0;
      for (int i = 0; i < n; ++i) d += col[i] * B[i][j];
      for (int i = 0; i < n; ++i) col[i] -= d * B[i][j];
    }
    double len = 0;
    for (double x : col) len += x * x;
    for (int i = 0; i < n; ++i) B[i][k] = col[i] / std::sqrt(len);
  }
  std::vector<double> mean(n, 0.0);
  const double texels = double(c.width) * c.height;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      for (int i = 0; i < n; ++i) mean[i] += c.at(x, y, 0, i) / texels;
  io::Volume a(c.width, c.height, 1, K);
  std::vector<double> lo(K, 1e30), hi(K, -1e30);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      for (int k = 0; k < K; ++k) {
        double s = 0;
        for (int i = 0; i < n; ++i) s += B[i][k] * (c.at(x, y, 0, i) - mean[i]);
        a.at(x, y, 0, k) = float(s);
        lo[k] = std::min(lo[k], s), hi[k] = std::max(hi[k], s);
      }
  fs::create_directories(out / "mips");
  json textures = json::array();
  for (int t = 0; 4 * t < K; ++t) {
    io::Volume u(c.width, c.height, 1, 4);
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x)
        for (int ch = 0; ch < 4; ++ch) {
          const int k = 4 * t + ch;
          u.at(x, y, 0, ch) = k < K ? float((a.at(x, y, 0, k) - lo[k]) / (hi[k] - lo[k])) : 0.0f;
        }
    std::vector<io::Volume> levels{u};
    while (levels.back().width % 2 == 0 && levels.back().height % 2 == 0)
      levels.push_back(half_level(levels.back()));
    const std::string name = "directional_compact_" + std::to_string(t) + ".ktx2";
    io::write_texture_mips(out / "mips" / name, levels, io::PixelFormat::RGBA8Unorm);
    textures.push_back(name);
  }
  json j = {{"directional_compact",
             {{"form", "pca8"},
              {"coefficients", K},
              {"channels", n},
              {"textures", textures},
              {"lo", lo},
              {"hi", hi},
              {"mean", mean},
              {"basis", B}}}};
  io::write_file_atomic(out / "mips" / "mips.json", j.dump(1) + "\n");
  return j["directional_compact"];
}

const fs::path kCopy = fs::path(MSH_BINARY_DIR) / "three_directional_example";
const fs::path kShots = fs::path(MSH_BINARY_DIR) / "three_directional_screenshots";
const fs::path kMat = kCopy / "data" / "dirmat";

// The fixtures and one run of the driver (the probe scene, the compact fixture, the bad inputs and the glTF
// asset through the plugin), shared by the tests below; "" when it ran, else why not.
struct DriverRun {
  std::string failure;
  json res;
};
const DriverRun& driver_run() {
  static const DriverRun run = [] {
    DriverRun out;
    const auto fail = [&](const std::string& why) {
      out.failure = why;
      return out;
    };
    const fs::path dir = scratch_dir("three_directional");
    fs::remove_all(kShots);
    fs::remove_all(kCopy);
    {
      const auto r =
          run_cli("view --three --export " + kCopy.string() + " --cache " + kViewerCache.string(), dir);
      if (r.code != 0) return fail("view --three --export: " + r.err);
    }
    // The texture set as a user makes it (KTX2 mips and mips.json; the glTF asset with the compact form
    // pca8, two coefficient PNGs), small: 128² has 8 levels.
    {
      const auto r = run_cli(
          "gen-material --kind plaster --size 128 --directional-view --directional-form pca8 "
          "--gltf --out " +
              kMat.string(),
          dir);
      if (r.code != 0) return fail("gen-material: " + r.err);
    }
    const json compact = write_compact_fixture(kMat, kCopy / "data" / "dircompact");
    // Bad glTF copies for the plugin (beside the good one: its .bin and PNGs resolve).
    const json good = json::parse(slurp(kMat / "gltf" / "material.gltf"));
    std::string bad_gltf;
    const auto bad_g = [&](const std::string& name, const std::string& text) {
      std::ofstream(kMat / "gltf" / (name + ".gltf")) << text;
      bad_gltf += (bad_gltf.empty() ? "" : ",") + name + "=data/dirmat/gltf/" + name + ".gltf";
    };
    const std::string E = "/materials/0/extensions/MSH_materials_directional_occlusion";
    bad_g("bad_k",
          good.patch(json::parse(R"([{"op": "replace", "path": ")" + E + R"(/coefficients", "value": 9}])"))
              .dump());
    bad_g("bad_channels",
          good.patch(json::parse(R"([{"op": "replace", "path": ")" + E + R"(/channels", "value": 20}])"))
              .dump());
    bad_g("bad_basis",
          good.patch(json::parse(R"([{"op": "remove", "path": ")" + E + R"(/basis/20"}])")).dump());
    bad_g("bad_texture",
          good.patch(json::parse(R"([{"op": "replace", "path": "/images/3/uri", "value": "missing.png"}])"))
              .dump());
    bad_g("bad_json", good.dump().substr(0, 200));
    // Bad input for the loader.
    const auto bad = [&](const std::string& name, const std::string& text) {
      fs::create_directories(kCopy / "data" / name / "mips");
      std::ofstream(kCopy / "data" / name / "mips" / "mips.json") << text;
      return name + "=data/" + name + "/mips/mips.json";
    };
    json missing = {{"directional_compact", compact}};
    missing["directional_compact"]["textures"][1] = "no_such_file.ktx2";
    json wrong_k = {{"directional_compact", compact}};
    wrong_k["directional_compact"]["coefficients"] = 9;
    json no_dir = {{"levels", 1}, {"maps", json::object()}};
    const std::string bads = bad("bad_json", "{\"directional\": [1, 2,") + "," +
                             bad("bad_missing", missing.dump()) + "," + bad("bad_k", wrong_k.dump()) + "," +
                             bad("bad_none", no_dir.dump());
    // The missing texture's neighbour must exist for that case to be about the missing file.
    fs::copy_file(kCopy / "data" / "dircompact" / "mips" / "directional_compact_0.ktx2",
                  kCopy / "data" / "bad_missing" / "mips" / "directional_compact_0.ktx2");

    const std::string failure = serve_and_drive(
        kCopy, "three_directional_test.mjs",
        "--out " + kShots.string() + " --material data/dirmat --compact data/dircompact --bad " + bads +
            " --gltf data/dirmat/gltf/material.gltf --bad-gltf " + bad_gltf,
        dir);
    if (!failure.empty()) return fail(failure);
    out.res = json::parse(slurp(kShots / "results.json"));
    return out;
  }();
  return run;
}

// l and v in the channels' frame (x, y, z in view space) against the scene's, and the frame's normal n_t
// against three's N·L (where N·L is neither 0 nor 1, whose clamps hide a difference).
struct FrameInputs {
  double lt = 0, vt = 0, nl = 0;
  void view(const Vec3d& P, const Vec3d& x, const Vec3d& y, const Vec3d& z, const Vec3f& v_t) {
    const Vec3d vv = normalize(-P);
    vt = std::max(vt, length(Vec3d(v_t) - Vec3d(dot(vv, x), dot(vv, y), dot(vv, z))));
  }
  void light(const Vec3d& wl, const Vec3d& x, const Vec3d& y, const Vec3d& z, const Vec3f& l_t,
             const Vec3f& n_t, float n_dot_l) {
    lt = std::max(lt, length(Vec3d(l_t) - Vec3d(dot(wl, x), dot(wl, y), dot(wl, z))));
    if (n_dot_l > 0.01f && n_dot_l < 0.99f) nl = std::max(nl, std::abs(double(dot(n_t, l_t)) - n_dot_l));
  }
};

// The driver's plain outputs: no console errors; the only failed requests, the bad-input cases' missing
// textures (KTX2 for the loader, PNG for the glTF plugin); the module lists directional-view and its pair
// with the generic ALU fit (the 21-channel texel forms); bad input, one clear line each; the loaded codes are
// the files'.
void check_driver_outputs(const json& res, const json& mips) {
  EXPECT_TRUE(res["errors"].empty()) << res["errors"].dump(1);
  ASSERT_EQ(res["http_errors"].size(), 2u) << res["http_errors"].dump(1);
  EXPECT_NE(res["http_errors"][0].get<std::string>().find("404 "), std::string::npos);
  EXPECT_NE(res["http_errors"][0].get<std::string>().find("/bad_missing/mips/no_such_file.ktx2"),
            std::string::npos);
  EXPECT_NE(res["http_errors"][1].get<std::string>().find("404 "), std::string::npos);
  EXPECT_NE(res["http_errors"][1].get<std::string>().find("/dirmat/gltf/missing.png"), std::string::npos);
  ASSERT_TRUE(res.contains("runs")) << res["errors"].dump(1);
  std::vector<std::string> ids;
  for (const auto& m : res["methods"]) ids.push_back(m["id"]);
  EXPECT_EQ(ids, (std::vector<std::string>{"directional-view", "directional-view+generic-vndf-alu"}));
  const auto has = [&](const char* k, const std::vector<std::string>& parts) {
    expect_error_line(res.at("errors_by_case"), k, parts);
  };
  has("bad_json", {"bad_json/mips/mips.json", "not valid JSON"});
  has("bad_missing", {"no_such_file.ktx2"});
  has("bad_k", {"K = 9 needs 3 textures", "lists 2"});
  has("bad_none", {"no directional channels"});
  has("no_directional", {"directional-view", "loadDirectionalOcclusion"});
  has("wrong_k", {"K = 9 needs 3 coefficient textures"});
  has("no_renderer", {"needs the renderer"});
  const auto& codes = res["codes"];
  EXPECT_EQ(codes["channels21"]["K"], 21);
  EXPECT_TRUE(codes["channels21"]["identity"].get<bool>());
  EXPECT_EQ(codes["channels21"]["textures"], 6);
  EXPECT_EQ(codes["channels21"]["lo"], mips["directional"]["lo"]);
  EXPECT_EQ(codes["compact"]["K"], kCompactK);
  EXPECT_FALSE(codes["compact"]["identity"].get<bool>());
  EXPECT_EQ(codes["compact"]["form"], "pca8");
  for (const auto& m : codes["channels21"]["maps"]) {
    EXPECT_EQ(m["width"], 128);
    EXPECT_EQ(m["levels"], 8) << "the KTX2 mip chain";
  }
}

// What the probes of the scene gather.
struct SceneProbes {
  ProbeStats stats;  // [light][run lobe]
  FrameInputs inputs;
  double frame_err = 0, ortho_err = 0, uv_err = 0, compose_err = 0, direct_err = 0;
  int frame_n[3] = {0, 0, 0}, direct_n = 0;  // probes on the plane, the sphere, the cylinder
};

// The probe scene's camera and the sphere's and cylinder's placement, read once from the page's results.
struct SceneObjects {
  explicit SceneObjects(const json& res)
      : cam(res["camera_world"]),
        sphere_c(vec3(res["objects"]["sphere"])),
        cyl_c(vec3(res["objects"]["cylinder"])),
        sphere_r(res["objects"]["sphere_radius"].get<double>()) {}
  const CameraWorld cam;
  const Vec3d sphere_c, cyl_c;
  const double sphere_r;
};

// The channels' frame (x, y, z, view space) at probe p of run R: orthonormal, and against the surface's +u,
// +v and normal in world space (the object told from the position); on the plane, the UV.
void check_frame(const SceneObjects& s, const json& R, int p, const Vec3d& P, const Vec3d (&frame)[3],
                 SceneProbes& out) {
  const auto& [x, y, z] = frame;
  const CameraWorld& cam = s.cam;
  out.ortho_err =
      std::max({out.ortho_err, std::abs(length(x) - 1), std::abs(length(y) - 1), std::abs(length(z) - 1),
                std::abs(dot(x, y)), std::abs(dot(y, z)), std::abs(dot(x, z))});
  const Vec3d Pw = cam.to_world(P) + cam.position();
  Vec3d ex, ey, ez;
  int obj = -1;
  if (std::abs(Pw.y) < 1e-3) {
    obj = 0, ex = Vec3d(1, 0, 0), ey = Vec3d(0, 0, -1), ez = Vec3d(0, 1, 0);
    // UV on the plane: 3 repeats over 5 units, +v toward −z.
    const auto& uv = R["dir_uv"][p];
    out.uv_err = std::max({out.uv_err, std::abs(uv[0].get<double>() - 3 * (Pw.x + 2.5) / 5),
                           std::abs(uv[1].get<double>() - 3 * (2.5 - Pw.z) / 5)});
  } else if (std::abs(length(Pw - s.sphere_c) - s.sphere_r) < 0.02) {
    obj = 1, ez = normalize(Pw - s.sphere_c);
  } else {
    obj = 2;
    const Vec3d r = Pw - s.cyl_c;
    ez = normalize(Vec3d(r.x, 0, r.z));
  }
  if (obj > 0) {
    const Vec3d up(0, 1, 0);
    ex = normalize(cross(up, ez)) * (obj == 2 ? -1.0 : 1.0);  // the cylinder's u is mirrored
    ey = normalize(up - ez * dot(ez, up));
  }
  ++out.frame_n[obj];
  out.frame_err = std::max({out.frame_err, length(cam.to_world(x) - ex), length(cam.to_world(y) - ey),
                            length(cam.to_world(z) - ez)});
}

// The 21 channels run R read at probe p into c; the compact form's are mean + basis · a (code cd).
void read_channels(const json& R, const json& cd, int p, float (&c)[21], SceneProbes& out) {
  for (int i = 0; i < 21; ++i) c[i] = R["c"][i / 4][p][i % 4];
  if (!cd["identity"].get<bool>()) {
    for (int i = 0; i < 21; ++i) {
      double s = cd["mean"][i].get<double>(), scale = std::abs(s);
      for (int k = 0; k < int(cd["K"]); ++k) {
        const double b = cd["basis"][i][k], ak = R["a"][k / 4][p][k % 4];
        s += b * ak, scale += std::abs(b * ak);
      }
      out.compose_err = std::max(out.compose_err, std::abs(c[i] - s) / std::max(scale, 1e-3));
    }
  } else {
    for (int i = 0; i < 21; ++i)
      out.compose_err =
          std::max(out.compose_err, double(std::abs(c[i] - R["a"][i / 4][p][i % 4].get<float>())));
  }
}

// One lit probe of run R under light k: l and v in the frame against the scene; each lobe's term against the
// library (directional_view_term at the pixel's channels; the pair's specular lobe, the generic ALU fit, over
// the rect light its area-cap form as the module wires it: built on sin/cos, 2/255 as test_three_browser
// holds it); the direct light on/off against the terms.
void check_light_terms(const json& res, const json& R, int k, int p, const Vec3d& P, const Vec3d (&frame)[3],
                       const float (&c)[21], occlusion::MicroShadowingEvaluator& generic_alu,
                       SceneProbes& out) {
  const std::string type = res["light_order"][k], method = R["method"];
  const bool rect = type == "rect", pair = method != "directional-view";
  const std::string run_name = method + " (" + R["code"].get<std::string>() + ")";
  const auto& L = R["lights"][k];
  const float V = L["inputs"][p][0], nl = L["inputs"][p][1], nv = L["inputs"][p][2], r = L["inputs"][p][3];
  const Vec3f l_t(vec3(L["l_t"][p])), v_t(vec3(L["v_t"][p])), n_t(vec3(R["dir_n"][p]));
  if (!(rect ? L["cap"][p][1].get<double>() > 0 : nl > 0)) return;  // unlit
  const auto& [x, y, z] = frame;
  out.inputs.view(P, x, y, z, v_t);
  if (!rect) out.inputs.light(light_dir(res["lights"], type, P), x, y, z, l_t, n_t, nl);
  const float want_dir = directional::directional_view_term<float>(c, l_t, v_t, n_t);
  for (int lobe = 0; lobe < 2; ++lobe) {
    double want = want_dir, tol = 1e-4 * std::max(1.0, std::abs(double(want_dir)));
    if (lobe == 1 && pair && !rect)
      want = generic_alu.eval({V, nl, nv, r, std::nullopt, std::nullopt}), tol = 1e-4;
    if (lobe == 1 && pair && rect)
      want = micro_shadowing::generic_vndf_alu_area_cap<double>(V, L["cap"][p][0].get<double>(), nv, r,
                                                                L["cap"][p][1].get<double>()),
      tol = 2.0 / 255;
    const double got = R[lobe ? "terms_s" : "terms_d"][p][k];
    const double got8 = R[lobe ? "terms8_s" : "terms8_d"][p][k].get<double>() / 255.0;
    const std::string what = run_name + (lobe ? " specular" : " diffuse");
    // float32: the shader and C++ float agree to rounding (the term divides by N·L: relative); the 8-bit
    // output (clamped to [0, 1]) within 2/255.
    EXPECT_NEAR(got, want, tol) << what << " (" << type << ") l_t " << l_t.x << " " << l_t.y << " " << l_t.z;
    EXPECT_NEAR(got8, std::clamp(want, 0.0, 1.0), 2.0 / 255) << what << " 8-bit (" << type << ")";
    out.stats[type][what].add(std::abs(got - want) / std::max(1.0, std::abs(want)),
                              std::abs(got8 - std::clamp(want, 0.0, 1.0)));
  }
  if (!L.contains("direct_on")) return;
  for (int lobe = 0; lobe < 2; ++lobe) {
    const double o = L["direct_off"][p][lobe], t = R[lobe ? "terms_s" : "terms_d"][p][k];
    if (!(o > 1e-4)) continue;
    const double d = std::abs(L["direct_on"][p][lobe].get<double>() - o * t) / (o * std::max(1.0, t));
    out.direct_err = std::max(out.direct_err, d);
    ++out.direct_n;
  }
}

// Every run (method and code), probe on a surface and light.
void check_scene_probes(const json& res, SceneProbes& out) {
  occlusion::MicroShadowingEvaluator generic_alu("generic-vndf-alu");
  const SceneObjects scene(res);
  const int npts = int(res["points"].size());
  for (const auto& R : res["runs"]) {
    const json& cd = res["codes"][R["code"].get<std::string>()];
    for (int p = 0; p < npts; ++p) {
      const auto& pos = R["position"][p];
      if (!(pos[3].get<double>() > 0.5)) continue;
      const Vec3d P = vec3(pos);
      const Vec3d frame[3] = {vec3(R["dir_x"][p]), vec3(R["dir_y"][p]), vec3(R["dir_z"][p])};
      check_frame(scene, R, p, P, frame, out);
      float c[21];
      read_channels(R, cd, p, c, out);
      for (int k = 0; k < int(res["light_order"].size()); ++k)
        check_light_terms(res, R, k, p, P, frame, c, generic_alu, out);
    }
  }
  EXPECT_LE(out.ortho_err, 1e-4) << "the channels' frame is not orthonormal";
  EXPECT_LE(out.frame_err, 0.03) << "the channels' frame differs from the surfaces' +u, +v, normal";
  for (int o = 0; o < 3; ++o) EXPECT_GE(out.frame_n[o], 20) << "too few probes on object " << o;
  EXPECT_LE(out.uv_err, 1e-3);
  EXPECT_LE(out.inputs.lt, 1e-4) << "l in the channels' frame differs from the scene's";
  EXPECT_LE(out.inputs.vt, 1e-4) << "v in the channels' frame differs from the scene's";
  EXPECT_LE(out.inputs.nl, 1e-4) << "the frame's normal does not give three's N.L";
  EXPECT_LE(out.compose_err, 1e-5) << "the channels differ from mean + basis . coefficients";
  EXPECT_LE(out.direct_err, 1e-4) << "direct light on/off differs from the terms";
  EXPECT_GE(out.direct_n, 100);
  for (const std::string& t : res["light_order"].get<std::vector<std::string>>())
    for (const auto& [what, st] : out.stats[t])
      EXPECT_GE(st.n, 20) << t << " " << what << ": too few lit probes";
}

// Nearest fetches: the channels (21) and the coefficients (compact) are the files' level-0 texels at the
// pixel's UV (row y = floor(v · h): the textures' rows run along +v), decoded with the files' ranges.
void check_nearest_fetches(const json& res, double& near_err, int& near_n) {
  for (const auto& N : res["nearest"]) {
    const bool is_compact = N["code"] == "compact_nearest";
    const fs::path mdir = is_compact ? kCopy / "data" / "dircompact" / "mips" : kMat / "mips";
    const json& cd = res["codes"][is_compact ? "compact" : "channels21"];
    const int K = cd["K"];
    std::vector<io::Volume> tex;
    for (int t = 0; 4 * t < K; ++t)
      tex.push_back(
          io::read_texture_level(mdir / (is_compact ? "directional_compact_" + std::to_string(t) + ".ktx2"
                                                    : "directional_" + std::to_string(t) + ".ktx2"),
                                 0));
    compare_nearest(N, tex, cd["lo"], cd["hi"], K, int(res["points"].size()), near_err, near_n);
  }
  EXPECT_LE(near_err, 1e-5) << "the fetched channels are not the files' texels at the pixel's UV";
  EXPECT_GE(near_n, 100);
}

TEST(ThreeDirectional, MatchesTheLibraryAtProbes) {
  MSH_REQUIRE_BROWSER(missing_three_browser());
  const DriverRun& run = driver_run();
  ASSERT_TRUE(run.failure.empty()) << run.failure;
  const json& res = run.res;
  const json mips = json::parse(slurp(kMat / "mips" / "mips.json"));
  ASSERT_EQ(mips["directional"]["channels"], directional::kViewChannels);
  ASSERT_NO_FATAL_FAILURE(check_driver_outputs(res, mips));
  SceneProbes s;
  ASSERT_NO_FATAL_FAILURE(check_scene_probes(res, s));
  double near_err = 0;
  int near_n = 0;
  check_nearest_fetches(res, near_err, near_n);
  std::printf(
      "three.js r%s, %d probe points; frame vs surfaces %.1e (orthonormal %.1e; probes plane %d, sphere %d, "
      "cylinder %d), l %.1e, v %.1e, N.L %.1e, uv %.1e; compose %.1e; nearest channels vs files %.1e (n=%d); "
      "direct on/off %.1e (n=%d); driver %.0f s\n",
      res["revision"].get<std::string>().c_str(), int(res["points"].size()), s.frame_err, s.ortho_err,
      s.frame_n[0], s.frame_n[1], s.frame_n[2], s.inputs.lt, s.inputs.vt, s.inputs.nl, s.uv_err,
      s.compose_err, near_err, near_n, s.direct_err, s.direct_n, res["timing"]["done"].get<double>());
  std::printf("max |three.js - C++|: 8-bit output in 1/255 (float32, relative to max(1, |term|)) n:\n");
  print_probe_table(
      s.stats, res["light_order"].get<std::vector<std::string>>(), 62,
      [](const std::string& t, const ProbeStat& st) {
        std::printf(" %s %4.2f (%.1e) %3d", t.c_str(), st.max_8bit * 255, st.max_float, st.n);
        return json{{"max_8bit_255", st.max_8bit * 255}, {"max_float_rel", st.max_float}, {"n", st.n}};
      },
      kShots / "comparison.json");
}

// The glTF run's plain outputs: the plugin's method and code (the compact form pca8 of gen-material
// --directional-form pca8 --gltf: two RGBA8 coefficient PNGs) with the maps three needs; bad assets: the
// load rejects with one line naming the problem, and their page's console has GLTFLoader's own line for the
// missing image, nothing else.
void check_gltf_outputs(const json& all, const json& G, const json& ext) {
  EXPECT_EQ(G["method"], "directional-view+generic-vndf-alu");
  EXPECT_EQ(G["code"]["K"], ext["coefficients"]);
  EXPECT_EQ(ext["form"], "pca8");
  EXPECT_EQ(G["code"]["K"], 8);
  EXPECT_EQ(G["code"]["textures"], 2);
  EXPECT_FALSE(G["code"]["identity"].get<bool>());
  EXPECT_TRUE(G["aomap"].get<bool>() && G["normalmap"].get<bool>() && G["tangents"].get<bool>());
  EXPECT_EQ(G["gl_error"], 0);
  const auto has = [&](const char* k, const std::vector<std::string>& parts) {
    expect_error_line(all["gltf_errors"], k, parts);
  };
  has("bad_k", {"glTF material 0", "K = 9 needs 3 textures, the extension lists 2"});
  has("bad_channels", {"'channels' must be 21, got 20"});
  has("bad_basis", {"'basis' must have 21 rows", "got 20"});
  has("bad_texture", {"texture 3 (missing.png) did not load"});
  has("bad_json", {"JSON"});
  EXPECT_EQ(all["bad_console"].size(), 1u) << all["bad_console"].dump(1);
  for (const auto& l : all["bad_console"])
    EXPECT_NE(l.get<std::string>().find("THREE.GLTFLoader: Couldn't load texture"), std::string::npos) << l;
}

// What the glTF plane's probes gather.
struct GltfProbes {
  std::map<std::string, ProbeStat> stats;  // [light + lobe]
  FrameInputs inputs;
  double frame_err = 0, uv_err = 0, direct_err = 0;
  int n_pix = 0, direct_n = 0;
};

// Probe p under light k: l and v in the frame against the scene, each lobe's term against the library, the
// direct light on/off against the terms.
void check_gltf_light(const json& G, int k, int p, const Vec3d& P, const Vec3d (&frame)[3],
                      const float (&c)[21], occlusion::MicroShadowingEvaluator& generic_alu,
                      GltfProbes& out) {
  const std::string type = G["light_order"][k];
  const auto& L = G["lights_read"][k];
  const float V = L["inputs"][p][0], nl = L["inputs"][p][1], nv = L["inputs"][p][2], r = L["inputs"][p][3];
  if (!(nl > 0)) return;
  const Vec3f l_t(vec3(L["l_t"][p])), v_t(vec3(L["v_t"][p])), n_t(vec3(G["dir_n"][p]));
  const auto& [x, y, z] = frame;
  out.inputs.light(light_dir(G["lights"], type, P), x, y, z, l_t, n_t, nl);
  out.inputs.view(P, x, y, z, v_t);
  const float want_dir = directional::directional_view_term<float>(c, l_t, v_t, n_t);
  for (int lobe = 0; lobe < 2; ++lobe) {
    const double want =
        lobe == 0 ? double(want_dir) : generic_alu.eval({V, nl, nv, r, std::nullopt, std::nullopt});
    const double tol = lobe == 0 ? 1e-4 * std::max(1.0, std::abs(want)) : 1e-4;
    const double got = G[lobe ? "terms_s" : "terms_d"][p][k];
    const double got8 = G[lobe ? "terms8_s" : "terms8_d"][p][k].get<double>() / 255.0;
    EXPECT_NEAR(got, want, tol) << (lobe ? "specular" : "diffuse") << " (" << type << ")";
    EXPECT_NEAR(got8, std::clamp(want, 0.0, 1.0), 2.0 / 255) << (lobe ? "specular" : "diffuse") << " 8-bit";
    out.stats[type + (lobe ? " specular" : " diffuse")].add(
        std::abs(got - want) / std::max(1.0, std::abs(want)), std::abs(got8 - std::clamp(want, 0.0, 1.0)));
    const double o = L["direct_off"][p][lobe];
    if (o > 1e-4) {
      out.direct_err = std::max(out.direct_err, std::abs(L["direct_on"][p][lobe].get<double>() - o * got) /
                                                    (o * std::max(1.0, got)));
      ++out.direct_n;
    }
  }
}

// Every probe on the plane: the frame against its +u (+x), +v (+z) and normal, the UV, then each light.
void check_gltf_probes(const json& G, GltfProbes& out) {
  const CameraWorld cam(G["camera_world"]);
  const double scale = G["scale"];
  occlusion::MicroShadowingEvaluator generic_alu("generic-vndf-alu");
  for (int p = 0; p < int(G["points"].size()); ++p) {
    const auto& pos = G["position"][p];
    if (!(pos[3].get<double>() > 0.5)) continue;
    ++out.n_pix;
    const Vec3d P = vec3(pos), Pw = cam.to_world(P) + cam.position();
    const Vec3d frame[3] = {vec3(G["dir_x"][p]), vec3(G["dir_y"][p]), vec3(G["dir_z"][p])};
    out.frame_err = std::max({out.frame_err, length(cam.to_world(frame[0]) - Vec3d(1, 0, 0)),
                              length(cam.to_world(frame[1]) - Vec3d(0, 0, 1)),
                              length(cam.to_world(frame[2]) - Vec3d(0, 1, 0))});
    out.uv_err = std::max({out.uv_err, std::abs(G["dir_uv"][p][0].get<double>() - (Pw.x / scale + 0.5)),
                           std::abs(G["dir_uv"][p][1].get<double>() - (Pw.z / scale + 0.5))});
    float c[21];
    for (int i = 0; i < 21; ++i) c[i] = G["c"][i / 4][p][i % 4];
    for (int k = 0; k < int(G["light_order"].size()); ++k)
      check_gltf_light(G, k, p, P, frame, c, generic_alu, out);
  }
  EXPECT_GE(out.n_pix, 100) << "too few probes on the plane";
  EXPECT_LE(out.frame_err, 1e-4) << "the channels' frame differs from the plane's +u, +v, normal";
  EXPECT_LE(out.uv_err, 1e-4);
  EXPECT_LE(out.inputs.lt, 1e-4);
  EXPECT_LE(out.inputs.vt, 1e-4);
  EXPECT_LE(out.inputs.nl, 1e-4);
  EXPECT_LE(out.direct_err, 1e-4);
  EXPECT_GE(out.direct_n, 100);
  for (const auto& [what, st] : out.stats) EXPECT_GE(st.n, 30) << what << ": too few lit probes";
}

// The glTF asset of gen-material --gltf through three's GLTFLoader and the module's MicroShadowGLTFPlugin
// (docs/gltf.md): the plugin puts directional-view + generic ALU on the plane's material with the extension's
// code; per probe and light, each lobe's term against the C++ library; the frame against the plane's +u (+x),
// +v (+z: glTF's v runs down the image, the tangent's bitangent toward -v) and normal; the coefficients
// fetched nearest against the PNG texels decoded with the extension's ranges (the PNGs unflipped, not
// premultiplied, not colour-converted); direct light on/off against the terms.
TEST(ThreeDirectional, GltfPluginMatchesTheLibraryAtProbes) {
  MSH_REQUIRE_BROWSER(missing_three_browser());
  const DriverRun& run = driver_run();
  ASSERT_TRUE(run.failure.empty()) << run.failure;
  ASSERT_TRUE(run.res.contains("gltf")) << run.res["errors"].dump(1);
  const json& G = run.res["gltf"];
  ASSERT_FALSE(G.contains("error")) << G["error"];
  const json gj = json::parse(slurp(kMat / "gltf" / "material.gltf"));
  const json& ext = gj["materials"][0]["extensions"]["MSH_materials_directional_occlusion"];
  check_gltf_outputs(run.res, G, ext);
  GltfProbes s;
  check_gltf_probes(G, s);
  // Nearest: the PNG texels at the pixel's UV, decoded with the extension's ranges.
  double near_err = 0;
  int near_n = 0;
  std::vector<io::Volume> png;
  for (const auto& t : ext["textures"]) {
    const int src = gj["textures"][t["index"].get<int>()]["source"];
    png.push_back(io::read_image(kMat / "gltf" / gj["images"][src]["uri"].get<std::string>()));
  }
  compare_nearest(G["nearest"], png, ext["lo"], ext["hi"], ext["coefficients"], int(G["points"].size()),
                  near_err, near_n);
  EXPECT_LE(near_err, 1e-5) << "the fetched coefficients are not the PNG texels at the pixel's UV";
  EXPECT_GE(near_n, 100);
  std::printf(
      "glTF (gen-material --directional-form pca8 --gltf, plaster 128) through MicroShadowGLTFPlugin: %d "
      "plane probes; frame %.1e, uv %.1e, l %.1e, v %.1e, N.L %.1e, nearest vs PNG %.1e (n=%d), direct "
      "on/off %.1e (n=%d)\n",
      s.n_pix, s.frame_err, s.uv_err, s.inputs.lt, s.inputs.vt, s.inputs.nl, near_err, near_n, s.direct_err,
      s.direct_n);
  std::printf("max |three.js - C++|: 8-bit in 1/255 (float32 relative) n:\n");
  for (const auto& [what, st] : s.stats)
    std::printf("  %-24s %4.2f (%.1e) %3d\n", what.c_str(), st.max_8bit * 255, st.max_float, st.n);
}

}  // namespace
