// The study's stages (study/study.h) on a tiny plan: the plan's cells and variants, the measurement of an
// image against the ground truth, and one cell run alone, which must give exactly what run_study produces for
// that cell (rows, ground-truth row, image entries and files) and a verdict whose direction is known.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/study/study.h>
#include <support/cli_test_util.h>
#include <support/study_test_util.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

namespace fs = std::filesystem;
using namespace msh::study;
using nlohmann::json;

namespace {

// Plaster on the plane, k = 1 and 4, directional lights at 25° and 45°: four cells.
StudyConfig tiny_plaster() {
  StudyConfig c = msh::test::tiny_plane_study("tiny-cell", "plaster", 128, {1, 4}, {25, 45}, 16);
  c.terms = {"none", "ao", "reference"};
  c.featured_lights = {"dir-el45-az0"};
  return c;
}

}  // namespace

TEST(StudyPlan, CellsInRunOrderAndVariantsPerScale) {
  const StudyPlan plan = plan_study(tiny_plaster());
  ASSERT_EQ(plan.materials.size(), 1u);
  EXPECT_EQ(plan.materials[0].name, "plaster");
  EXPECT_EQ(plan.materials[0].fine_size, 128);
  EXPECT_FALSE(plan.materials[0].user());
  // material → shape → scale → light.
  ASSERT_EQ(plan.cells.size(), 4u);
  const std::pair<int, const char*> order[] = {
      {1, "dir-el25-az0"}, {1, "dir-el45-az0"}, {4, "dir-el25-az0"}, {4, "dir-el45-az0"}};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(plan.cells[i].material, 0u);
    EXPECT_EQ(plan.cells[i].shape, "plane");
    EXPECT_EQ(plan.cells[i].scale, order[i].first);
    EXPECT_EQ(plan.cells[i].light.name, order[i].second);
    EXPECT_EQ(plan.cells[i].light.type, "directional");
  }
  EXPECT_EQ(plan.cells[3].light.elevation, 45.0);
  // k = 1: the three terms and the smooth-normal ablation of the one that reads N·L (reference); k = 4: and
  // the three with the widened roughness.
  ASSERT_EQ(plan.variants.size(), 2u);
  EXPECT_EQ(plan.variants.at(1).size(), 4u);
  ASSERT_EQ(plan.variants.at(4).size(), 7u);
  EXPECT_EQ(plan.variants.at(4)[3].term, "reference");
  EXPECT_TRUE(plan.variants.at(4)[3].smooth_normal);
  EXPECT_EQ(plan.variants.at(4)[6].roughness, msh::render::CoarseRoughness::Widened);
  // The plan is where a bad configuration is refused.
  StudyConfig bad = tiny_plaster();
  bad.scales = {3};  // does not divide 128
  EXPECT_THROW(plan_study(bad), msh::InputError);
}

// The ground truth measured against itself and against itself × 1.25: bias 1 and 1.25 in every region and
// component, RMSE 0 against itself, SSIM 1.
TEST(StudyMeasure, ScaledGroundTruth) {
  ComponentImages gi;
  for (int ci = 0; ci < 3; ++ci) {
    gi.img[ci] = msh::render::Image(8, 8);
    gi.se[ci] = msh::render::Image(8, 8);
    for (std::size_t i = 0; i < gi.img[ci].px.size(); ++i) {
      const float v = 0.2f + 0.01f * float(i % 13) + 0.1f * float(ci);
      gi.img[ci].px[i] = msh::Rgbf(v, 0.9f * v, 0.8f * v);
      gi.se[ci].px[i] = msh::Rgbf(0.01f);
    }
  }
  const GroundTruth gt = make_ground_truth(gi);
  Regions reg{Mask(8, 8, 0), Mask(8, 8, 0), Mask(8, 8, 1)};
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) (x < 4 ? reg.rough : reg.smooth).px[std::size_t(y) * 8 + x] = 1;
  ComponentImages scaled = gi;
  for (auto& img : scaled.img)
    for (auto& p : img.px) p = p * 1.25f;
  const auto same = measure_variant(gi, gt, reg, 4), brighter = measure_variant(scaled, gt, reg, 4);
  for (int ci = 0; ci < 3; ++ci)
    for (const char* r : {"rough", "smooth", "whole"}) {
      EXPECT_NEAR(same[ci]["bias"][r].get<double>(), 1.0, 1e-12) << ci << r;
      EXPECT_EQ(same[ci]["rmse"][r].get<double>(), 0.0) << ci << r;
      EXPECT_GT(same[ci]["bias_stderr"][r].get<double>(), 0.0) << ci << r;
      EXPECT_NEAR(brighter[ci]["bias"][r].get<double>(), 1.25, 1e-6) << ci << r;
      EXPECT_EQ(brighter[ci]["gt_mean"][r], same[ci]["gt_mean"][r]);
    }
  for (int ci = 0; ci < 3; ++ci) EXPECT_NEAR(same[ci]["ssim"].get<double>(), 1.0, 1e-9);
}

// The plan's last cell (k = 4, light at 45°) run alone, against the full run that renders the three other
// cells before it: the same rows, ground-truth row, image entries and image files, to the bit.
//
// And its verdict, known in advance: without micro-shadowing (none) the coarse plaster is brighter than the
// ground truth, whose fine pits and cracks shadow the surface; ao, darkened by the mean visibility, comes
// closer. Measured (whole view, total; seeds 1–5): none 1.047–1.052 ± 0.0026 (bias ± bias_stderr, the spread
// over seeds agrees), ao 1.007–1.012 ± 0.0025, |none − 1| − |ao − 1| = 0.039–0.040. Asserted: none > 1 + 10
// SE (≈ 1.026), and |none − 1| − |ao − 1| > 5 combined SE (≈ 0.018).
TEST(StudyCell, OneCellAloneIsWhatTheFullRunProducesForIt) {
  const StudyConfig cfg = tiny_plaster();
  const StudyPlan plan = plan_study(cfg);
  const StudyCell& cell = plan.cells.back();
  ASSERT_EQ(cell.scale, 4);
  ASSERT_EQ(cell.light.name, "dir-el45-az0");
  const CellResult alone = run_cell(plan, cell);

  const fs::path d = fs::temp_directory_path() / ("msh_test_study_cell_" + std::to_string(::getpid()));
  fs::remove_all(d);
  const json full = run_study(cfg, d / "full");
  auto of_cell = [&](const json& list) {
    json out = json::array();
    for (const json& e : list)
      if (e["scale"] == cell.scale && e["light"] == cell.light.name) out.push_back(e);
    return out;
  };
  ASSERT_EQ(alone.rows.size(), 7u * 3u);  // 7 variants at k = 4, 3 components
  EXPECT_EQ(alone.rows, of_cell(full["rows"]));
  const json gt = of_cell(full["ground_truth"]);
  ASSERT_EQ(gt.size(), 1u);
  EXPECT_EQ(alone.ground_truth, gt[0]);
  // Featured light: the ground truth and the three base-roughness, shading-normal terms, each with its
  // difference image.
  ASSERT_EQ(alone.images.size(), 4u);
  EXPECT_EQ(alone.images, of_cell(full["images"]));
  ASSERT_EQ(alone.featured.size(), 7u);
  fs::create_directories(d / "alone" / "images");
  write_featured_images(alone, d / "alone");
  for (const FeaturedImage& f : alone.featured)
    EXPECT_EQ(msh::test::slurp(d / "alone" / f.file), msh::test::slurp(d / "full" / f.file)) << f.file;

  std::map<std::string, std::pair<double, double>> bias;  // method → (bias, bias_stderr), whole view, total
  for (const json& row : alone.rows)
    if (row["component"] == "total" && row["ms_normal"] == "shading" && row["roughness"] == "base")
      bias[row["method"].get<std::string>()] = {row["bias"]["whole"].get<double>(),
                                                row["bias_stderr"]["whole"].get<double>()};
  const auto [none, none_se] = bias.at("none");
  const auto [ao, ao_se] = bias.at("ao");
  std::printf("[ verdict ] none %.4f ± %.4f, ao %.4f ± %.4f\n", none, none_se, ao, ao_se);
  EXPECT_GT(none, 1 + 10 * none_se);
  EXPECT_GT(std::abs(none - 1) - std::abs(ao - 1), 5 * std::hypot(none_se, ao_se));
  fs::remove_all(d);
}
