// gen-material --gltf (render/gltf_export.h, docs/gltf.md): the Khronos glTF validator (npm gltf-validator,
// tests/browser/gltf_validate.mjs) reports 0 errors and 0 warnings on the written asset, with only the
// informational messages docs/gltf.md lists; it reports errors on a broken copy (the check can fail). The
// asset decodes to the texture set: the extension's K, ranges, identity basis and zero mean, each coefficient
// PNG's texels the channels' UNORM8 quantisation, the normal map's green flipped to glTF's +Y up, the ORM
// packing, the plane's tangent frame (bitangent toward −v) and UVs. A compact code (K = 8) goes through the
// same writer and validates; a bad code throws before any file is written, and no partial asset is left.
// Without node or the validator package it fails unless MSH_ALLOW_NO_BROWSER=1 (then skips), as the browser
// tests.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/gltf_export.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "support/cli_test_util.h"
#include "support/view_server_util.h"

namespace fs = std::filesystem;
using namespace msh;
using namespace msh::test;  // run_cli, slurp, ... and the browser tests' kBrowserDir, missing_node_package
using nlohmann::json;

namespace {

std::string missing_validator() { return missing_node_package(kBrowserDir, "gltf-validator"); }

// The validator's report on a .gltf (its JSON), or a failure naming the output.
json validate(const fs::path& gltf, const fs::path& dir) {
  const fs::path report = dir / (gltf.stem().string() + "-report.json");
  const std::string cmd = "cd " + kBrowserDir.string() + " && node gltf_validate.mjs " + gltf.string() +
                          " --out " + report.string() + " > " + (dir / "node.out").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(rc, 0) << slurp(dir / "node.out");
  if (rc != 0 || !fs::exists(report)) return json();
  return json::parse(slurp(report));
}

// The informational messages docs/gltf.md lists: the validator does not know the extension, and so sees its
// textures as unused.
void expect_clean(const json& r, int extension_textures, int first_texture) {
  ASSERT_TRUE(r.is_object());
  const auto& i = r["issues"];
  EXPECT_EQ(i["numErrors"], 0) << i.dump(1);
  EXPECT_EQ(i["numWarnings"], 0) << i.dump(1);
  int unused = 0, unsupported = 0;
  for (const auto& m : i["messages"]) {
    const std::string code = m["code"], ptr = m.value("pointer", "");
    if (code == "UNSUPPORTED_EXTENSION" && ptr == "/extensionsUsed/0") {
      ++unsupported;
    } else if (code == "UNUSED_OBJECT" && ptr.rfind("/textures/", 0) == 0 &&
               std::stoi(ptr.substr(10)) >= first_texture) {
      ++unused;
    } else {
      ADD_FAILURE() << "unexpected validator message: " << m.dump();
    }
  }
  EXPECT_EQ(unsupported, extension_textures > 0 ? 1 : 0);
  EXPECT_EQ(unused, extension_textures);
}

std::vector<unsigned char> bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<unsigned char>(std::istreambuf_iterator<char>(f), {});
}

double q8(double x) { return std::round(std::clamp(x, 0.0, 1.0) * 255) / 255; }

// The validator's report, printed.
void print_report(const json& report) {
  std::printf(
      "gltf-validator %s on gen-material --gltf (plaster 64, 21 channels): %d errors, %d warnings, %d infos, "
      "%d hints\n",
      report.value("validatorVersion", "?").c_str(), report["issues"]["numErrors"].get<int>(),
      report["issues"]["numWarnings"].get<int>(), report["issues"]["numInfos"].get<int>(),
      report["issues"]["numHints"].get<int>());
  for (const auto& m : report["issues"]["messages"])
    std::printf("  %s %s: %s\n", m["code"].get<std::string>().c_str(), m.value("pointer", "").c_str(),
                m["message"].get<std::string>().c_str());
}

// Texture `texture` of asset j (in MAT/gltf) decoded.
io::Volume gltf_image(const json& j, const fs::path& mat, int texture) {
  const int src = j["textures"][texture]["source"];
  return io::read_image(mat / "gltf" / j["images"][src]["uri"].get<std::string>());
}

// The extension against the texture set (MAT/directional.npy): the identity code of the 21 channels, their
// ranges, and six coefficient PNGs holding each channel's UNORM8 quantisation between its range.
void check_extension(const json& j, const fs::path& mat) {
  const auto& ext = j["materials"][0]["extensions"][render::kGltfDirectionalExtension];
  EXPECT_EQ(j["extensionsUsed"], json::array({render::kGltfDirectionalExtension}));
  EXPECT_FALSE(j.contains("extensionsRequired"));
  ASSERT_EQ(ext["coefficients"], 21);
  EXPECT_EQ(ext["channels"], 21);
  EXPECT_EQ(ext["form"], "channels21");
  ASSERT_EQ(ext["textures"].size(), 6u);
  const io::Volume c = io::read_volume(mat / "directional.npy");
  ASSERT_EQ(c.channels, 21);
  render::Texture ct(c.width, c.height, 21);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x)
      for (int k = 0; k < 21; ++k) ct.at(x, y, k) = c.at(x, y, 0, k);
  const render::ChannelRanges cr = render::channel_ranges(ct);
  for (int i = 0; i < 21; ++i) {
    EXPECT_EQ(ext["lo"][i].get<float>(), cr.lo[std::size_t(i)]);
    EXPECT_EQ(ext["hi"][i].get<float>(), cr.hi[std::size_t(i)]);
    EXPECT_EQ(ext["mean"][i].get<double>(), 0.0);
    for (int k = 0; k < 21; ++k) EXPECT_EQ(ext["basis"][i][k].get<double>(), i == k ? 1.0 : 0.0);
  }
  double dir_err = 0;
  for (int t = 0; t < 6; ++t) {
    EXPECT_EQ(ext["textures"][t]["index"], 3 + t);
    const io::Volume im = gltf_image(j, mat, ext["textures"][t]["index"]);
    ASSERT_EQ(im.channels, 4);
    ASSERT_EQ(im.width, c.width);
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x)
        for (int ch = 0; ch < 4; ++ch) {
          const int k = 4 * t + ch;
          const double want = k < 21 ? q8((c.at(x, y, 0, k) - cr.lo[std::size_t(k)]) /
                                          (cr.hi[std::size_t(k)] - cr.lo[std::size_t(k)]))
                                     : (ch == 3 ? 1.0 : 0.0);
          dir_err = std::max(dir_err, std::abs(im.at(x, y, 0, ch) - want));
        }
  }
  // One step at most: the writer rounds in float, this check in double (a tie may round either way).
  EXPECT_LE(dir_err, 1.01 / 255) << "a coefficient PNG differs from the channels' UNORM8 quantisation";
}

// Core maps: the normal's green flipped (glTF: +Y up the image), ORM = (V, roughness, metallic).
void check_core_maps(const json& j, const fs::path& mat) {
  const auto& m = j["materials"][0];
  const io::Volume nrm = gltf_image(j, mat, m["normalTexture"]["index"]),
                   src_n = io::read_image(mat / "normal.png");
  const int orm_index = m["occlusionTexture"]["index"];
  EXPECT_EQ(m["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"], orm_index);
  const io::Volume orm = gltf_image(j, mat, orm_index), vis = io::read_image(mat / "micro_occlusion.png"),
                   rough = io::read_image(mat / "roughness.png"),
                   metal = io::read_image(mat / "metallic.png");
  double n_err = 0, orm_err = 0;
  for (int y = 0; y < src_n.height; ++y)
    for (int x = 0; x < src_n.width; ++x) {
      n_err = std::max({n_err, std::abs(nrm.at(x, y, 0, 0) - q8(src_n.at(x, y, 0, 0))),
                        std::abs(nrm.at(x, y, 0, 1) - q8(1 - src_n.at(x, y, 0, 1))),
                        std::abs(nrm.at(x, y, 0, 2) - q8(src_n.at(x, y, 0, 2)))});
      orm_err = std::max({orm_err, double(std::abs(orm.at(x, y, 0, 0) - vis.at(x, y, 0, 0))),
                          double(std::abs(orm.at(x, y, 0, 1) - rough.at(x, y, 0, 0))),
                          double(std::abs(orm.at(x, y, 0, 2) - metal.at(x, y, 0, 0)))});
    }
  // The texture set's normal.png is 16-bit: its rounding and the writer's 8 bits differ by one step at most.
  EXPECT_LE(n_err, 1.01 / 255) << "normal.png is not the texture set's with green flipped";
  EXPECT_LE(orm_err, 1e-6) << "orm.png is not (V, roughness, metallic)";
}

// The plane: bitangent cross(N, T) w toward −v (glTF), u along +x, v along +z.
void check_plane_frame(const json& j, const fs::path& mat) {
  const auto bin = bytes(mat / "gltf" / "material.bin");
  ASSERT_EQ(bin.size(), j["buffers"][0]["byteLength"].get<std::size_t>());
  const auto floats = [&](int accessor) {
    const auto& v = j["bufferViews"][j["accessors"][accessor]["bufferView"].get<int>()];
    std::vector<float> f(v["byteLength"].get<std::size_t>() / 4);
    std::memcpy(f.data(), bin.data() + v["byteOffset"].get<std::size_t>(), f.size() * 4);
    return f;
  };
  const auto& attr = j["meshes"][0]["primitives"][0]["attributes"];
  const auto P = floats(attr["POSITION"]), N = floats(attr["NORMAL"]), T = floats(attr["TANGENT"]),
             U = floats(attr["TEXCOORD_0"]);
  for (int i = 0; i < 4; ++i) {
    const Vec3d n(N[3 * i], N[3 * i + 1], N[3 * i + 2]), t(T[4 * i], T[4 * i + 1], T[4 * i + 2]);
    const Vec3d b = cross(n, t) * double(T[4 * i + 3]);
    EXPECT_NEAR(b.x, 0, 1e-7);
    EXPECT_NEAR(b.y, 0, 1e-7);
    EXPECT_NEAR(b.z, -1, 1e-7);
    for (int k = 0; k < 4; ++k) {  // u along +x, v along +z
      EXPECT_EQ(U[2 * k] - U[2 * i] > 0, P[3 * k] - P[3 * i] > 0);
      EXPECT_EQ(U[2 * k + 1] - U[2 * i + 1] > 0, P[3 * k + 2] - P[3 * i + 2] > 0);
    }
  }
}

TEST(GltfExport, GenMaterialAssetValidatesAndDecodes) {
  MSH_REQUIRE_BROWSER(missing_validator());
  const fs::path dir = scratch_dir("gltf");
  const fs::path mat = dir / "plaster";
  const auto r = run_cli(
      "gen-material --kind plaster --size 64 --directional-view --gltf --no-mips --out " + mat.string(), dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const fs::path g = mat / "gltf" / "material.gltf";
  ASSERT_TRUE(fs::is_regular_file(g));
  // No temporary directory left beside it.
  for (const auto& e : fs::directory_iterator(mat))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  const json report = validate(g, dir);
  expect_clean(report, 6, 3);
  print_report(report);
  const json j = json::parse(slurp(g));
  ASSERT_NO_FATAL_FAILURE(check_extension(j, mat));
  check_core_maps(j, mat);
  ASSERT_NO_FATAL_FAILURE(check_plane_frame(j, mat));
  // The check can fail: a copy whose accessor reads past its buffer view.
  json broken = j;
  broken["accessors"][0]["count"] = 40;
  std::ofstream(mat / "gltf" / "broken.gltf") << broken.dump();
  const json rb = validate(mat / "gltf" / "broken.gltf", dir);
  ASSERT_TRUE(rb.is_object());
  EXPECT_GT(rb["issues"]["numErrors"].get<int>(), 0) << "the validator found no error in a broken asset";
}

// The writer is generic over the code: a compact K = 8 code (random orthonormal basis, the channels' means)
// writes two coefficient textures and validates; a wrong code throws before anything is written.
TEST(GltfExport, CompactCodeAndBadInput) {
  MSH_REQUIRE_BROWSER(missing_validator());
  const fs::path dir = scratch_dir("gltf");
  render::GenOptions o;
  o.size = 32;
  o.directional_view = true;
  const render::TextureSet set = render::generate_texture_set(o);
  constexpr int K = 8, n = directional::kViewChannels;
  render::DirectionalCode code;
  code.form = "pca8";
  std::mt19937 rng(3);
  std::normal_distribution<float> gauss;
  code.basis.assign(n, std::vector<float>(K));
  for (auto& row : code.basis)
    for (auto& b : row) b = gauss(rng);
  code.mean.assign(n, 0.1f);
  code.coefficients = render::Texture(32, 32, K);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x)
      for (int k = 0; k < K; ++k) code.coefficients.at(x, y, k) = set.directional.at(x, y, k) * 2 - 0.3f;
  const render::ChannelRanges cr = render::channel_ranges(code.coefficients);
  code.lo = cr.lo, code.hi = cr.hi;
  const fs::path out = dir / "compact";
  render::write_texture_set_gltf(out, set, &code);
  const json j = json::parse(slurp(out / "material.gltf"));
  const auto& ext = j["materials"][0]["extensions"][render::kGltfDirectionalExtension];
  EXPECT_EQ(ext["coefficients"], K);
  EXPECT_EQ(ext["form"], "pca8");
  EXPECT_EQ(ext["textures"].size(), 2u);
  EXPECT_EQ(ext["basis"].size(), std::size_t(n));
  EXPECT_EQ(ext["basis"][0].size(), std::size_t(K));
  expect_clean(validate(out / "material.gltf", dir), 2, 3);
  // Written again over the existing asset: replaced.
  render::write_texture_set_gltf(out, set, nullptr);
  const json j2 = json::parse(slurp(out / "material.gltf"));
  EXPECT_FALSE(j2["materials"][0].contains("extensions"));
  EXPECT_FALSE(fs::exists(out / "directional_0.png")) << "the old asset's files were left";
  expect_clean(validate(out / "material.gltf", dir), 0, 3);

  // Bad codes: InputError naming the problem, no asset, no temporary directory.
  const auto expect_throw = [&](render::DirectionalCode bad, const std::string& part) {
    const fs::path target = dir / "bad";
    try {
      render::write_texture_set_gltf(target, set, &bad);
      ADD_FAILURE() << "no error for " << part;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(target));
    for (const auto& e : fs::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  };
  render::DirectionalCode b = code;
  b.lo.pop_back();
  expect_throw(b, "lo and hi need K = 8 entries");
  b = code;
  b.basis[3].push_back(0);
  expect_throw(b, "every basis row needs K = 8 entries");
  b = code;
  b.mean.resize(20);
  expect_throw(b, "mean needs 21 entries");
  b = code;
  b.hi[2] = b.lo[2];
  expect_throw(b, "coefficient 2: hi");
  b = code;
  b.coefficients = render::Texture(16, 32, K);
  expect_throw(b, "the coefficient texture is 16x32");
  // The identity code needs 21 channels.
  EXPECT_THROW(render::identity_directional_code(render::Texture(4, 4, 9)), InputError);
}

}  // namespace

namespace {
// gen-material --directional-form pca8 --gltf: the extension carries the same fitted code as mips.json's
// "directional_compact" (form, ranges, mean, basis), its two PNGs are the mips' level-0 coefficient PNGs
// texel for texel, and the asset validates with no error or warning.
TEST(GltfExport, GenMaterialCompactFormIsTheMipsCode) {
  MSH_REQUIRE_BROWSER(missing_validator());
  const fs::path dir = scratch_dir("gltf_compact");
  const fs::path mat = dir / "mat";
  const auto r = run_cli(
      "gen-material --kind rock --size 64 --directional-view --directional-form pca8 --gltf "
      "--out " +
          mat.string(),
      dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const json g = json::parse(slurp(mat / "gltf" / "material.gltf"));
  const json& ext = g["materials"][0]["extensions"][render::kGltfDirectionalExtension];
  const json mips = json::parse(slurp(mat / "mips" / "mips.json"));
  const json& dc = mips["directional_compact"];
  EXPECT_EQ(ext["form"], "pca8");
  EXPECT_EQ(ext["coefficients"], 8);
  for (const char* k : {"lo", "hi", "mean", "basis"}) EXPECT_EQ(ext[k], dc[k]) << k;
  ASSERT_EQ(ext["textures"].size(), 2u);
  for (int t = 0; t < 2; ++t) {
    const io::Volume a = gltf_image(g, mat, ext["textures"][t]["index"]);
    const io::Volume b = io::read_image(mat / ("directional_compact_" + std::to_string(t) + ".png"));
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    ASSERT_EQ(a.channels, b.channels);
    int differ = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x)
        for (int c = 0; c < a.channels; ++c) differ += a.at(x, y, 0, c) != b.at(x, y, 0, c);
    EXPECT_EQ(differ, 0) << "texture " << t;
  }
  expect_clean(validate(mat / "gltf" / "material.gltf", dir), 2, 3);
}
}  // namespace
