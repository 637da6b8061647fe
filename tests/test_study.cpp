// The multiscale study: metric functions against hand-computable cases, and the study's results.json
// (schema, counts, determinism across thread counts, bad configurations) on a tiny configuration.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/study/metrics.h>
#include <microshadow/study/study.h>
#include <support/cli_test_util.h>
#include <support/study_test_util.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using namespace msh::study;

namespace {

Plane ramp(int w, int h) {
  Plane p(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) p.at(x, y) = 0.5 + 0.01 * x + 0.03 * y + 0.2 * std::sin(0.7 * x * y);
  return p;
}

using msh::test::slurp;

}  // namespace

TEST(StudyMetrics, BiasOfAScaledImageIsTheScale) {
  const Plane g = ramp(12, 8);
  Plane a = g;
  for (double& v : a.px) v *= 1.37;
  const Plane se(12, 8, 0.0);
  const Mask all(12, 8, 1);
  EXPECT_NEAR(bias(a, g, se, all).value, 1.37, 1e-12);
  EXPECT_EQ(bias(a, g, se, all).floor, 0.0);
  // Over a sub-region too.
  Mask left(12, 8, 0);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 6; ++x) left.px[std::size_t(y) * 12 + x] = 1;
  EXPECT_NEAR(bias(a, g, se, left).value, 1.37, 1e-12);
}

TEST(StudyMetrics, BiasFloorFromPerPixelErrors) {
  // g = 2 on n = 40 pixels with σ = 0.1 each: the mean's relative error is 0.1 √n / (2 n).
  const Plane g(8, 5, 2.0), se(8, 5, 0.1);
  Plane a(8, 5, 3.0);
  const Mask all(8, 5, 1);
  const Measure b = bias(a, g, se, all);
  EXPECT_NEAR(b.value, 1.5, 1e-12);
  EXPECT_NEAR(b.floor, 1.5 * 0.1 * std::sqrt(40.0) / 80.0, 1e-12);
  const Measure m = region_mean(g, se, all);
  EXPECT_NEAR(m.value, 2.0, 1e-12);
  EXPECT_NEAR(m.floor, 0.1 / std::sqrt(40.0), 1e-12);
}

TEST(StudyMetrics, FootprintRmseOfAZeroMeanPatternIsZero) {
  // a = g + a ±c checkerboard: zero mean inside every 2×2 (and 4×4) footprint.
  const Plane g = ramp(16, 12);
  Plane a = g;
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 16; ++x) a.at(x, y) += ((x + y) % 2 ? 0.25 : -0.25);
  const Plane se(16, 12, 0.0);
  const Mask all(16, 12, 1);
  EXPECT_NEAR(rmse(a, g, se, all).value, 0.25, 1e-12);
  EXPECT_NEAR(rmse_footprint(a, g, se, all, 1).value, 0.25, 1e-12);  // b = 1 is the per-pixel RMSE
  EXPECT_NEAR(rmse_footprint(a, g, se, all, 2).value, 0.0, 1e-12);
  EXPECT_NEAR(rmse_footprint(a, g, se, all, 4).value, 0.0, 1e-12);
  // A constant offset survives the averaging unchanged.
  Plane c = g;
  for (double& v : c.px) v += 0.1;
  EXPECT_NEAR(rmse_footprint(c, g, se, all, 4).value, 0.1, 1e-12);
}

TEST(StudyMetrics, NoiseFloors) {
  // σ = 0.2 on every pixel: per-pixel floor 0.2, footprint (b × b) floor 0.2 / b.
  const Plane g = ramp(8, 8), se(8, 8, 0.2);
  const Mask all(8, 8, 1);
  EXPECT_NEAR(rmse(g, g, se, all).floor, 0.2, 1e-12);
  EXPECT_NEAR(rmse_footprint(g, g, se, all, 4).floor, 0.05, 1e-12);
  EXPECT_EQ(rmse(g, g, se, all).value, 0.0);
}

TEST(StudyMetrics, BlocksOutsideTheMaskAreDropped) {
  // One pixel of the second 2×2 block is outside the mask: that block's large error must not count.
  Plane g(4, 2, 1.0), a(4, 2, 1.0);
  a.at(2, 0) = a.at(3, 0) = a.at(2, 1) = a.at(3, 1) = 5.0;
  Mask m(4, 2, 1);
  m.px[3] = 0;
  const Plane se(4, 2, 0.0);
  const Blocks b = block_average(a, se, m, 2);
  ASSERT_EQ(b.mean.width, 2);
  EXPECT_EQ(b.mask.count(), 1u);
  EXPECT_NEAR(rmse_footprint(a, g, se, m, 2).value, 0.0, 1e-12);
  // A partial last column of blocks is dropped too (5 wide, b = 2: two blocks per row).
  EXPECT_EQ(block_average(Plane(5, 2, 1.0), Plane(5, 2, 0.0), Mask(5, 2, 1), 2).mean.width, 2);
  EXPECT_THROW(block_average(g, se, m, 0), msh::InputError);
}

TEST(StudyMetrics, LuminanceOfGreyIsTheGrey) {
  msh::render::Image img(2, 1);
  img.px[0] = {0.3f, 0.3f, 0.3f};
  img.px[1] = {1.0f, 0.0f, 0.0f};
  const Plane l = luminance(img);
  EXPECT_NEAR(l.px[0], 0.3, 1e-6);
  EXPECT_NEAR(l.px[1], 0.2126, 1e-7);
}

TEST(StudyMetrics, EmptyOrDarkRegions) {
  const Plane z(4, 4, 0.0);
  const Mask none(4, 4, 0), all(4, 4, 1);
  EXPECT_TRUE(std::isnan(bias(z, z, z, all).value));  // no signal: no ratio
  EXPECT_TRUE(std::isnan(rmse(z, z, z, none).value));
  EXPECT_EQ(region_mean(z, z, none).value, 0.0);
}

namespace {
// The quick configuration (plaster, plane and cylinder, azimuth 0, no point light) shrunk to seconds.
StudyConfig tiny() {
  StudyConfig c = quick_config();
  c.name = "tiny";
  c.fine_size = 64;
  c.ao_rays = 4;
  c.scales = {1, 4};
  c.elevations = {25};
  c.sphere_light = true;
  c.area_samples = 4;
  c.image_size = 16;
  c.footprint = 4;
  c.gt_spp = 8;
  c.gt_max_spp = 16;
  c.featured_lights = {"dir-el25-az0"};
  return c;
}
}  // namespace

TEST(Study, TinyRunSchemaAndDeterminism) {
  const fs::path d1 = fs::temp_directory_path() / "msh_test_study_1",
                 d2 = fs::temp_directory_path() / "msh_test_study_2";
  fs::remove_all(d1), fs::remove_all(d2);
  nlohmann::json r1, r2;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    r1 = run_study(tiny(), d1);
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    r2 = run_study(tiny(), d2);
  }
  EXPECT_EQ(slurp(d1 / "results.json"), slurp(d2 / "results.json"));
  EXPECT_EQ(slurp(d1 / "results.csv"), slurp(d2 / "results.csv"));
  for (const char* f : {"results.json", "results.csv", "summary.md", "study.html", "timing.json"})
    EXPECT_TRUE(fs::exists(d1 / f)) << f;

  // Rows: 1 material × 2 shapes × 2 lights × (k = 1: every term + the smooth-normal ablation of those that
  // read N·L; k = 4: + every term with the widened roughness) × 3 components. The terms are the registry's
  // study list: 19 today, 15 of them read N·L.
  const std::vector<std::string> terms = tiny().terms;
  ASSERT_EQ(terms, msh::occlusion::micro_shadowing_study_methods());
  ASSERT_EQ(terms.size(), 19u);
  const auto n_nl = std::count_if(terms.begin(), terms.end(), [](const std::string& t) {
    return msh::occlusion::find_micro_shadowing_method(t)->uses_ndotl;
  });
  EXPECT_EQ(n_nl, 15);
  EXPECT_EQ(r1["config"]["terms"].get<std::vector<std::string>>(), terms);
  const auto& rows = r1["rows"];
  EXPECT_EQ(rows.size(), std::size_t(2 * 2 * ((19 + 15) + (19 + 15 + 19)) * 3));
  std::set<std::string> seen;
  for (const auto& row : rows) seen.insert(row["method"].get<std::string>());
  EXPECT_EQ(seen, std::set<std::string>(terms.begin(), terms.end()));
  EXPECT_EQ(r1["ground_truth"].size(), 8u);
  for (const auto& row : rows) {
    for (const char* k :
         {"material", "shape", "scale", "light", "method", "component", "bias", "rmse_footprint", "rmse",
          "rmse_stderr", "ssim", "bias_stderr", "rmse_footprint_floor", "ms_normal", "roughness", "gt_mean"})
      ASSERT_TRUE(row.contains(k)) << k;
    for (const char* k :
         {"bias", "bias_stderr", "rmse_footprint", "rmse_footprint_floor", "rmse", "rmse_stderr"})
      for (const char* reg : {"rough", "smooth", "whole"})
        ASSERT_TRUE(row[k].contains(reg)) << k << " " << reg;
    if (row["component"] != "total") continue;
    // The total always has signal: every metric is a finite number (JSON null would mark a NaN).
    for (const char* k : {"bias", "rmse_footprint", "rmse", "rmse_stderr"}) {
      // On the tiny cylinder (5 pixels wide at k = 4) no 4 × 4 footprint may lie entirely on the surface.
      if (std::string(k) == "rmse_footprint" && row["shape"] == "cylinder" && row["scale"] == 4) continue;
      ASSERT_TRUE(row[k]["whole"].is_number()) << k << " " << row.dump();
    }
    EXPECT_LE(row["ssim"].get<double>(), 1.0 + 1e-9);
  }
  // The footprint average can only remove error: rmse_footprint <= rmse (for the whole view).
  for (const auto& row : rows) {
    if (row["rmse"]["whole"].is_number() && row["rmse_footprint"]["whole"].is_number()) {
      EXPECT_LE(row["rmse_footprint"]["whole"].get<double>(), row["rmse"]["whole"].get<double>() + 1e-12);
    }
  }
  EXPECT_TRUE(r1["summary"].contains("cells"));
  EXPECT_FALSE(r1["summary"]["cells"].empty());
}

TEST(Study, BadConfigurations) {
  const fs::path d = fs::temp_directory_path() / "msh_test_study_bad";
  StudyConfig c = tiny();
  c.scales = {3};  // does not divide 64
  EXPECT_THROW(run_study(c, d), msh::InputError);
  c = tiny();
  c.shapes = {"torus"};
  EXPECT_THROW(run_study(c, d), msh::InputError);
  c = tiny();
  c.scales = {32};  // 64 / 32 = 2 coarse texels: narrower than one 4-pixel footprint
  EXPECT_THROW(run_study(c, d), msh::InputError);
  c = tiny();
  c.elevations = {90};
  EXPECT_THROW(run_study(c, d), msh::InputError);
  c = tiny();
  c.views = {95};
  EXPECT_THROW(run_study(c, d), msh::InputError);
  c = tiny();
  c.views = {};
  EXPECT_THROW(run_study(c, d), msh::InputError);
  c = tiny();
  c.view_azimuths = {std::nan("")};
  EXPECT_THROW(run_study(c, d), msh::InputError);
  c = tiny();
  c.sweep_views = {60};
  c.sweep_elevations = {10}, c.sweep_azimuths = {45}, c.sweep_scales = {4};
  c.sweep_terms = {"directional-view"};  // not one of the study's terms
  c.terms = {"none"};
  EXPECT_THROW(run_study(c, d), msh::InputError);
  c.sweep_scales = {};
  c.sweep_terms = {"none"};
  EXPECT_THROW(run_study(c, d), msh::InputError);  // a sweep without scales
  // Compact forms: only on a method that reads the directional channels, and a form that parses.
  for (const char* t : {"ao@pca8", "directional-view@pca22", "directional@pca10", "directional-view@pcaX",
                        "directional-view@", "nosuch@pca8"}) {
    c = tiny();
    c.terms = {"none", t};
    EXPECT_THROW(run_study(c, d), msh::InputError) << t;
  }
  EXPECT_FALSE(fs::exists(d / "results.json"));
}

// A compact form of the directional channels ("method@form") renders its stored level in place of the float
// channels: the full-rank float code reproduces the float rows; 4 coefficients at 8 bits do not (the form
// really is what was rendered); the float rows are the same whether or not forms ran beside them.
TEST(Study, CompactDirectionalForms) {
  const fs::path d = fs::temp_directory_path() / "msh_test_study_forms",
                 d0 = fs::temp_directory_path() / "msh_test_study_forms0";
  StudyConfig c = tiny();
  c.shapes = {"plane"};
  c.sphere_light = false;
  c.widened = false, c.normal_ablation = false;
  c.directional_azimuths = 8;
  c.terms = {"directional-view", "directional-view@pca21f", "directional-view@pca4", "directional@pca9x16"};
  const nlohmann::json r = run_study(c, d);
  c.terms = {"directional-view"};
  const nlohmann::json r0 = run_study(c, d0);
  std::map<std::string, std::vector<double>> bias;
  for (const auto& row : r["rows"])
    if (row["component"] == "diffuse") bias[row["method"].get<std::string>()].push_back(row["bias"]["whole"]);
  std::vector<double> alone;
  for (const auto& row : r0["rows"])
    if (row["component"] == "diffuse") alone.push_back(row["bias"]["whole"]);
  ASSERT_EQ(bias.size(), 4u);
  const auto& f = bias["directional-view"];
  ASSERT_FALSE(f.empty());
  EXPECT_EQ(f, alone);
  double d4 = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    EXPECT_NEAR(bias["directional-view@pca21f"][i], f[i], 1e-4 * f[i]) << i;
    d4 = std::max(d4, std::abs(bias["directional-view@pca4"][i] - f[i]));
  }
  EXPECT_GT(d4, 1e-3);
}

// A height map's file name becomes the material's name and the featured images' file names: a hostile one
// (it ends the attribute and adds an onerror handler in an unescaped page) is percent-encoded in every img
// src of study.html, escaped in its text, and each src still names the image written.
TEST(Study, HostileMaterialNameIsEscapedInTheReport) {
  const fs::path d = fs::temp_directory_path() / ("msh_test_study_hostile." + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  const std::string name = "x' onerror='alert(1);<b>\"&";
  msh::io::Volume v(32, 32, 1, 1);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) v.at(i, j, 0, 0) = float(0.5 + 0.4 * std::sin(0.4 * i) * std::cos(0.3 * j));
  msh::io::write_png(d / (name + ".png"), v, 16);
  StudyConfig c = tiny();
  c.materials = {}, c.shapes = {"plane"}, c.sphere_light = false, c.scales = {1};
  c.terms = {"none", "ao"};
  c.widened = c.normal_ablation = false;
  c.user_materials = {{name, d / (name + ".png"), 4}};
  run_study(c, d / "out");
  const std::string html = slurp(d / "out" / "study.html");
  EXPECT_EQ(html.find("onerror='"), std::string::npos);
  EXPECT_EQ(html.find("<b>"), std::string::npos);
  int srcs = 0;
  for (std::size_t at = html.find("src='"); at != std::string::npos; at = html.find("src='", at + 1)) {
    const std::size_t end = html.find('\'', at + 5);
    ASSERT_NE(end, std::string::npos);
    const std::string url = html.substr(at + 5, end - at - 5);
    for (char ch : url) EXPECT_EQ(std::string("\"<> &").find(ch), std::string::npos) << url;
    std::string path;  // percent-decoded
    for (std::size_t i = 0; i < url.size(); ++i)
      if (url[i] == '%' && i + 2 < url.size()) {
        path += char(std::stoi(url.substr(i + 1, 2), nullptr, 16));
        i += 2;
      } else {
        path += url[i];
      }
    EXPECT_TRUE(fs::exists(d / "out" / path)) << path;
    ++srcs;
  }
  EXPECT_GT(srcs, 0);
  fs::remove_all(d);
}

// The user's own height maps (study --height / --material): a 16-bit PNG written here is studied under its
// file's stem, through the procedural kinds' generation path (the directional channels are baked because a
// term reads them: the material cache holds them); bad maps are InputErrors before anything is written.
TEST(Study, UserHeightMaps) {
  const fs::path d = fs::temp_directory_path() / ("msh_test_study_user." + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  auto write_map = [&](const std::string& name, int w, int h) {
    msh::io::Volume v(w, h, 1, 1);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        v.at(i, j, 0, 0) = float(0.5 + 0.5 * std::sin(2 * M_PI * i / 16) * std::sin(2 * M_PI * j / 16));
    msh::io::write_png(d / name, v, 16);
    return d / name;
  };
  StudyConfig c = tiny();
  c.materials = {};
  c.shapes = {"plane"};
  c.sphere_light = false;
  c.terms = {"none", "directional"};
  c.widened = c.normal_ablation = false;
  c.featured_lights = {};
  c.user_materials = {{"my_bumps", write_map("my_bumps.png", 64, 64), 4}};
  c.material_cache = d / "cache";
  const nlohmann::json r = run_study(c, d / "out");
  EXPECT_EQ(r["config"]["materials"], nlohmann::json::array({"my_bumps"}));
  EXPECT_EQ(r["config"]["user_materials"][0]["depth_texels"].get<double>(), 4.0);
  // 1 light × 2 scales × 2 terms × 3 components.
  ASSERT_EQ(r["rows"].size(), 12u);
  for (const auto& row : r["rows"]) {
    EXPECT_EQ(row["material"], "my_bumps");
    if (row["component"] == "total") {
      EXPECT_TRUE(row["bias"]["whole"].is_number());
    }
  }
  int cached = 0;
  for (const auto& e : fs::directory_iterator(d / "cache"))
    cached += e.path().filename().string().rfind("user-my_bumps_64_", 0) == 0 &&
              fs::exists(e.path() / "directional.npy");
  EXPECT_EQ(cached, 1);
  // A bad cache entry is checked on read and baked again, never used: a map of another size, a non-finite
  // texel, a depth of 1e30, a truncated file; each run's rows equal the first run's.
  {
    fs::path entry;
    for (const auto& e : fs::directory_iterator(d / "cache"))
      if (e.path().filename().string().rfind("user-my_bumps_64_", 0) == 0) entry = e.path();
    const auto rows = [](const nlohmann::json& j) { return j["rows"].dump(); };
    const std::string want = rows(r);
    const auto corrupt = [&](const std::string& what, const std::function<void()>& f) {
      f();
      EXPECT_EQ(rows(run_study(c, d / "out")), want) << what;
    };
    corrupt("visibility 32x32", [&] {
      msh::io::write_volume(entry / "visibility.npy", msh::io::Volume(32, 32, 1, 1),
                            msh::io::FileFormat::Npy);
    });
    corrupt("NaN roughness", [&] {  // float32 texels at the end of the file: texel (3, 5) patched in place
      const auto at = fs::file_size(entry / "roughness.npy") - 64 * 64 * 4 + (5 * 64 + 3) * 4;
      std::fstream f(entry / "roughness.npy", std::ios::in | std::ios::out | std::ios::binary);
      const float nan = std::nanf("");
      f.seekp(std::streamoff(at));
      f.write(reinterpret_cast<const char*>(&nan), 4);
    });
    corrupt("depth 1e30", [&] { std::ofstream(entry / "depth.txt") << "1e30\n"; });
    corrupt("truncated height", [&] { fs::resize_file(entry / "height.npy", 100); });
  }
  // From a gen-material folder: named after the folder, depth from material.json.
  fs::create_directories(d / "paving");
  fs::copy_file(d / "my_bumps.png", d / "paving" / "height.png");
  std::ofstream(d / "paving" / "material.json") << R"({"height": "height.png", "height_texels": 3.5})";
  const UserMaterial f = user_material_from_folder(d / "paving");
  EXPECT_EQ(f.name, "paving");
  EXPECT_EQ(f.depth_texels, 3.5f);
  EXPECT_EQ(f.height, d / "paving" / "height.png");
  EXPECT_EQ(user_material_from_folder(d / "paving/").name, "paving");
  EXPECT_THROW(user_material_from_folder(d / "nowhere"), msh::InputError);
  EXPECT_THROW(user_material_from_folder(d / "cache"), msh::InputError);  // no material.json
  // A depth out of (0, 10000] (1e300 was cast to float: undefined behaviour) or a height that is not a file
  // name (nlohmann's type_error escaped): InputError (fuzz/fuzz_material_json.cpp).
  for (const char* text :
       {R"({"height_texels": 1e300})", R"({"height_texels": -1})", R"({"height_texels": 0})",
        R"({"height": 5, "height_texels": 3})", R"({"height": null, "height_texels": 3})"}) {
    std::ofstream(d / "paving" / "material.json") << text;
    EXPECT_THROW(user_material_from_folder(d / "paving"), msh::InputError) << text;
  }

  // Bad maps and depths: one InputError each, nothing written.
  const fs::path bad_out = d / "bad";
  const StudyConfig good = c;
  auto expect_bad = [&](const UserMaterial& u, std::vector<int> scales = {1, 4}) {
    StudyConfig b = good;
    b.user_materials = {u};
    b.scales = scales;
    EXPECT_THROW(run_study(b, bad_out), msh::InputError) << u.height;
  };
  expect_bad({"missing", d / "missing.png", 4});
  expect_bad({"my_bumps", d / "my_bumps.png", 0});
  expect_bad({"my_bumps", d / "my_bumps.png", std::nanf("")});
  expect_bad({"wide", write_map("wide.png", 64, 32), 4});  // not square
  expect_bad({"my_bumps", d / "my_bumps.png", 4}, {3});    // 3 does not divide 64
  expect_bad({"my_bumps", d / "my_bumps.png", 4}, {32});   // 2 coarse texels: narrower than a footprint
  StudyConfig twice = good;
  twice.user_materials.push_back(good.user_materials[0]);
  EXPECT_THROW(run_study(twice, bad_out), msh::InputError);
  EXPECT_FALSE(fs::exists(bad_out));
  fs::remove_all(d);
}

// The area-light section (docs/area-lights.md) on a tiny configuration: sphere lights of two sizes, a
// disk and a rect; rows per {light, term, area_ms}, the area summary, bit-identical across thread counts,
// and representative / integrated rows kept out of the main verdict cells.
TEST(Study, TinyAreaLightRun) {
  StudyConfig c = area_config(true);
  c.name = "tiny-area";
  c.fine_size = 64;
  c.ao_rays = 4;
  c.scales = {4};
  c.image_size = 8;
  c.footprint = 2;
  c.area_samples = 4;
  c.method_spp = 1;
  c.vndf_samples = 8;
  c.gt_spp = 8;
  c.gt_max_spp = 8;
  c.area_radii_deg = {5, 40};
  c.area_elevations = {50};
  c.area_planar_radii_deg = {10};
  // Per-process directories: other checkouts may run this test at the same time.
  const std::string pid = std::to_string(::getpid());
  const fs::path d1 = fs::temp_directory_path() / ("msh_test_area_study_1_" + pid),
                 d2 = fs::temp_directory_path() / ("msh_test_area_study_2_" + pid);
  fs::remove_all(d1), fs::remove_all(d2);
  nlohmann::json r1;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    r1 = run_study(c, d1);
  }
  {
    tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
    run_study(c, d2);
  }
  EXPECT_EQ(slurp(d1 / "results.json"), slurp(d2 / "results.json"));
  ASSERT_TRUE(fs::exists(d1 / "area_summary.md"));
  // 4 lights (sphere 5° and 40° at 50°, disk and rect of 10°) × (none, ao; reference S/R/I; generic-vndf
  // S/R; lut3d S/R/I = 10 variants) × 3 components.
  const auto& rows = r1["rows"];
  EXPECT_EQ(r1["ground_truth"].size(), 4u);
  ASSERT_EQ(rows.size(), std::size_t(4 * 10 * 3));
  std::map<std::string, int> modes;
  for (const auto& row : rows) {
    ASSERT_TRUE(row.contains("area_ms")) << row.dump();
    ASSERT_TRUE(row["light_radius_deg"].is_number());
    ++modes[row["area_ms"].get<std::string>()];
    if (row["component"] == "total") {
      ASSERT_TRUE(row["bias"]["whole"].is_number()) << row.dump();
    }
  }
  EXPECT_EQ(modes["sampled"], 4 * 5 * 3);
  EXPECT_EQ(modes["representative"], 4 * 3 * 3);
  EXPECT_EQ(modes["integrated"], 4 * 2 * 3);
  // area_summary: one cell per light and component, each with every {method}/{mode}.
  const auto& cells = r1["area_summary"];
  ASSERT_EQ(cells.size(), 4u * 3u);
  for (const auto& cell : cells) {
    EXPECT_EQ(cell["methods"].size(), 10u) << cell.dump();
    EXPECT_TRUE(cell["methods"].contains("lut3d/integrated"));
  }
  const std::string md = slurp(d1 / "area_summary.md");
  for (const char* s :
       {"| sphere | 5° | 50° |", "| sphere | 40° | 50° |", "| disk | 10° | 45° |", "| rect | 10° |"})
    EXPECT_NE(md.find(s), std::string::npos) << s;
  // The main verdict cells hold each method once per light (the sampled rows only).
  for (const auto& cell : r1["summary"]["cells"])
    for (const auto& [m, e] : cell["methods"].items()) EXPECT_EQ(e["n"].get<int>(), 1) << m;
  fs::remove_all(d1), fs::remove_all(d2);
}

// A configuration whose verdict direction is known: grazing light (5° elevation) on a relief material (bark)
// at k = 4. There the true micro-shadowing darkens the surface far more than the light-independent occlusion
// fraction `ao` does, so `ao` (and `none`, brighter still) must come out brighter than the ground truth.
// Measured on this configuration (256² fine bark, 32² pixels, 16–32 GT spp; seeds 1–5): ao bias 2.33–2.39
// with bias_stderr 0.020–0.021 (the study's noise floor, from the per-pixel errors of both images; the spread
// over seeds, SD 0.022, agrees with it), none 2.90–2.98 ± 0.025. Asserted: ao > 1 + 10 SE (≈ 1.2) and > 1.5
// (38 seed-SDs below the measured 2.33), none − ao > 10 combined SE (≈ 0.33; measured 0.57). 0.2 s.
TEST(Study, GrazingLightOnReliefAoIsBrighterThanGroundTruth) {
  StudyConfig c = msh::test::tiny_plane_study("tiny-verdict", "bark", 256, {4}, {5}, 32);
  c.terms = {"none", "ao"};
  c.widened = c.normal_ablation = false;
  c.featured_lights = {"dir-el5-az0"};
  const fs::path d = fs::temp_directory_path() / ("msh_test_study_verdict_" + std::to_string(::getpid()));
  fs::remove_all(d);
  const nlohmann::json r = run_study(c, d);
  std::map<std::string, std::pair<double, double>> bias;  // method → (bias, bias_stderr), whole view, total
  for (const auto& row : r["rows"]) {
    if (row["component"] != "total") continue;
    ASSERT_TRUE(row["bias"]["whole"].is_number()) << row.dump();
    bias[row["method"].get<std::string>()] = {row["bias"]["whole"].get<double>(),
                                              row["bias_stderr"]["whole"].get<double>()};
  }
  ASSERT_EQ(bias.size(), 2u);
  for (const auto& [m, b] : bias)
    std::printf("[ verdict ] %s: bias %.4f ± %.4f\n", m.c_str(), b.first, b.second);
  const auto [ao, ao_se] = bias["ao"];
  const auto [none, none_se] = bias["none"];
  EXPECT_GT(ao, 1 + 10 * ao_se);
  EXPECT_GT(ao, 1.5);
  EXPECT_GT(none, ao + 10 * std::hypot(ao_se, none_se));
  fs::remove_all(d);
}

// The camera of a cell (StudyConfig's views and windows comments): the default view is the study's earlier
// one; grazing views keep the texture area with fewer rows; where the view covers a small part of the
// texture it is split into windows spread over it.
TEST(StudyViews, GeometryPerViewAndScale) {
  const StudyConfig c = full_config();
  const StudyView v30 = study_view(c, "plane", 2048, 30, 270, 16);
  EXPECT_EQ(v30.windows, 1);
  EXPECT_EQ(v30.width, 64);
  EXPECT_EQ(v30.height, 64);
  // Along the view (azimuth 270: along v) it reaches 32 rows × 16 texels / cos 30° of the 2048 of a tile.
  EXPECT_NEAR(v30.extent, 32.0 * 16 / std::cos(M_PI / 6) / 2048, 1e-9);
  // k = 1 at 2048²: the view is 64 of 2048 texels, so 16 × 16 windows of one 4 × 4-pixel footprint; the
  // same down to k = 8 (a quarter of the texture), none from k = 16 (half).
  const StudyView k1 = study_view(c, "plane", 2048, 30, 270, 1);
  EXPECT_EQ(k1.windows, 16);
  EXPECT_EQ(k1.width, 4);
  EXPECT_EQ(k1.height, 4);
  EXPECT_EQ(k1.image_width(), 64);
  EXPECT_EQ(study_view(c, "plane", 2048, 30, 270, 2).windows, 16);
  EXPECT_EQ(study_view(c, "plane", 2048, 30, 270, 8).windows, 16);
  EXPECT_EQ(study_view(c, "plane", 1024, 30, 270, 4).windows, 16);
  EXPECT_EQ(study_view(c, "plane", 1024, 30, 270, 8).windows, 1);
  EXPECT_EQ(study_view(c, "cylinder", 2048, 30, 270, 1).windows, 1);  // windows on planes only
  // 60° off the normal: 64 cos 60° / cos 30° = 36.9 rows, a whole number of 4-pixel footprints: 36.
  const StudyView v60 = study_view(c, "plane", 2048, 60, 270, 16);
  EXPECT_EQ(v60.width, 64);
  EXPECT_EQ(v60.height, 36);
  // 85°: 6.4 rows -> 8; 0° (straight down): 64 rows, as at 30°.
  EXPECT_EQ(study_view(c, "plane", 2048, 85, 270, 16).height, 8);
  EXPECT_EQ(study_view(c, "plane", 2048, 0, 270, 16).height, 64);
  // k = 64 at 2048²: 32 coarse texels across, so 32 pixels.
  EXPECT_EQ(study_view(c, "plane", 2048, 30, 270, 64).width, 32);
  // A view azimuth of 0 turns the view's long side onto u: the same extent.
  EXPECT_NEAR(study_view(c, "plane", 2048, 30, 0, 16).extent, v30.extent, 1e-9);
}

// The full study's view sweep: views 30-85°, light azimuths 0-180°, k = 1-64 for the shipped terms; a
// cell the main grid has is not rendered twice, and every cell is unique.
TEST(StudyViews, FullPlanSweepAddsViewsWithoutRepeatingCells) {
  StudyConfig c = full_config();
  c.materials = {"plaster"};
  const StudyPlan p = plan_study(c);
  // Main grid: 3 scales × (10 directional + point, sphere, point-near, sphere-near). Sweep: 7 scales × 4
  // views × 10 directional lights (elevations 10, 45 × 5 azimuths), less the 3 scales × 4 lights (10, 45 ×
  // 0, 90) the main grid has at 30°.
  EXPECT_EQ(p.cells.size(), std::size_t(3 * 14 + 7 * 4 * 10 - 3 * 4));
  std::set<std::string> keys;
  int sweep = 0;
  for (const StudyCell& cell : p.cells) {
    const std::string key = std::to_string(cell.scale) + "|" + std::to_string(cell.view.view) + "|" +
                            std::to_string(cell.view.view_azimuth) + "|" + cell.light.name;
    EXPECT_TRUE(keys.insert(key).second) << key;
    if (cell.sweep) {
      ++sweep;
      EXPECT_EQ(p.variants_of(cell).size(), c.sweep_terms.size());
      EXPECT_EQ(cell.light.type, "directional");
    } else {
      EXPECT_EQ(cell.view.view, 30);
    }
  }
  EXPECT_EQ(sweep, 7 * 4 * 10 - 3 * 4);
  // The near lights sit near_light_footprints footprints from the view's centre at each scale.
  for (const StudyCell& cell : p.cells)
    if (cell.light.name == "point-near") {
      const double fp = c.footprint * cell.scale * 2.0 / c.fine_size;  // world units (a tile is 2)
      EXPECT_NEAR(msh::length(cell.light.light.position), c.near_light_footprints * fp, 1e-5);
      EXPECT_NEAR(cell.light.elevation, 30, 1e-3);
    }
}

namespace {
// A square 16-bit height map of low, smooth bumps.
fs::path write_bumps(const fs::path& d, const std::string& name, int size, int period) {
  msh::io::Volume v(size, size, 1, 1);
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i)
      v.at(i, j, 0, 0) = float(0.5 + 0.5 * std::sin(2 * M_PI * i / period) * std::sin(2 * M_PI * j / period));
  msh::io::write_png(d / name, v, 16);
  return d / name;
}
}  // namespace

// Every view, view azimuth and window layout renders the ground truth and the terms through the same
// cameras and planes: on a nearly flat relief (0.02 texel deep) the term `none` IS the ground truth up to
// sampling noise, at every view up to 85°, with windows at k = 1 and under the lights near the surface.
TEST(StudyViews, NearlyFlatReliefMatchesTheGroundTruthAtEveryView) {
  const fs::path d = fs::temp_directory_path() / ("msh_test_study_views." + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  StudyConfig c = tiny();
  c.materials = {};
  c.user_materials = {{"flat", write_bumps(d, "flat.png", 128, 32), 0.02f}};
  c.shapes = {"plane"};
  c.image_size = 8;
  c.scales = {1, 2, 8};  // 128 / (8 k) >= 4 at k = 1, 2: 8 / 4 = 2 windows per side; none at k = 8
  c.views = {0, 60, 85};
  c.view_azimuths = {270, 45};
  c.elevations = {25};
  c.azimuths = {135};
  c.point_light = c.sphere_light = false;
  c.near_lights = true;
  c.terms = {"none"};
  c.widened = c.normal_ablation = false;
  c.featured_lights = {};
  c.gt_spp = 32;
  c.gt_max_spp = 64;
  c.method_spp = 16;
  const nlohmann::json r = run_study(c, d / "out");
  // 3 scales × 3 views × 2 view azimuths × 3 lights.
  ASSERT_EQ(r["ground_truth"].size(), 54u);
  for (const auto& g : r["ground_truth"]) {
    const int n = g["scale"] == 8 ? 1 : 2;
    EXPECT_EQ(g["windows"].get<int>(), n);
    EXPECT_EQ(g["image"][0].get<int>(), 8);  // 8 pixels across: n windows of 8 / n
  }
  int checked = 0;
  for (const auto& row : r["rows"]) {
    if (row["component"] == "specular") continue;  // the specular alone can be a few pixels' highlight
    ASSERT_TRUE(row["bias"]["whole"].is_number()) << row.dump();
    // The noise of 32-64 ground-truth and 16 term samples per pixel over 32-64 pixels: a few 1e-3.
    EXPECT_NEAR(row["bias"]["whole"].get<double>(), 1.0, 0.02) << row.dump();
    ++checked;
  }
  EXPECT_EQ(checked, 54 * 2);
  fs::remove_all(d);
}

// The Bias stopping rule (the view sweep, the user's maps' small set) stops once the bias floors of the total
// and the diffuse are under a quarter of the ranking resolution: never later than the Full rule, and where it
// stops before the cap those floors are met.
TEST(StudyViews, BiasRuleStopsOnTheBiasFloors) {
  StudyConfig c = tiny();
  c.shapes = {"plane"};
  c.terms = {"none"};
  c.widened = c.normal_ablation = false;
  c.featured_lights = {};
  c.gt_spp = 8;
  c.gt_max_spp = 256;
  const fs::path d = fs::temp_directory_path() / ("msh_test_study_rule." + std::to_string(::getpid()));
  const nlohmann::json full = run_study(c, d / "full");
  c.gt_rule = StudyConfig::GtRule::Bias;
  const nlohmann::json bias = run_study(c, d / "bias");
  ASSERT_EQ(full["ground_truth"].size(), bias["ground_truth"].size());
  int earlier = 0;
  for (std::size_t i = 0; i < bias["ground_truth"].size(); ++i) {
    const auto &b = bias["ground_truth"][i], &f = full["ground_truth"][i];
    EXPECT_EQ(b["rule"], "bias");
    EXPECT_EQ(f["rule"], "full");
    EXPECT_LE(b["spp"].get<int>(), f["spp"].get<int>());
    earlier += b["spp"].get<int>() < f["spp"].get<int>();
    if (b["spp"].get<int>() * 2 <= 256) {
      for (const char* comp : {"total", "diffuse"}) {
        EXPECT_LT(b["components"][comp]["bias_floor"].get<double>(), 0.0025) << b.dump();
      }
    }
  }
  EXPECT_GT(earlier, 0);
  fs::remove_all(d);
}
