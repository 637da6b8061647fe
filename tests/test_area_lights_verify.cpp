// The analysis behind `verify area-lights` (reference/runtime/area_lights_verify.h): the error summary on
// hand-computable errors; the input points; on a prefix of the Sobol points of docs/area-lights.md (§4–5),
// the exact closed form against the quadrature, every maximum within the documented maximum over the whole
// set (the points are the same, so a prefix's maximum cannot exceed it), float within the documented distance
// of double and the documented orderings of the forms; empty blocks; to_json is what the CLI prints; bad
// options throw InputError with the CLI's messages.
#include <gtest/gtest.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/reference/runtime/area_lights_verify.h>
#include <support/cli_test_util.h>
#include <support/ltc_test_table.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

using namespace msh;
using namespace msh::area;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;

// A documented maximum over the whole point set, printed to `unit` (its last digit): bounds the maximum over
// any prefix of the set.
void expect_within_documented_max(const ErrorSummary& s, double documented, double unit, const char* what) {
  EXPECT_LE(s.max_255, documented + unit / 2) << what;
}

// A float form within `tol` (1/255) of its double form at every point: their RMS and max differ by at most
// that much.
void expect_float_close(const ErrorSummary& f, const ErrorSummary& d, double tol, const char* what) {
  EXPECT_EQ(f.count, d.count) << what;
  EXPECT_NEAR(f.rms_255, d.rms_255, tol) << what;
  EXPECT_NEAR(f.max_255, d.max_255, tol) << what;
}

class AreaLightsVerify : public test::ScratchDirTest {
 protected:
  AreaLightsVerify() : ScratchDirTest("area_lights_verify") {}
  // A small LTC table (6², quick fit) in the scratch directory: the GGX rows depend on it, the rows checked
  // against the documented 64² figures do not.
  std::string small_ltc_file() const {
    const bsdf::LtcTable t = test::small_ltc_table(6, 8, 30, 256);
    const std::filesystem::path p = dir / "ltc6.dds";
    bsdf::write_ltc_table(p, t, io::FileFormat::Dds, io::PixelFormat::RGBA32Float,
                          io::PixelFormat::RG32Float);
    return p.string();
  }
};

}  // namespace

TEST(AreaLightsVerifySummary, HandComputed) {
  EXPECT_FALSE(summarize_errors({}).has_value());
  const auto s = summarize_errors({-2 / 255.0, 1 / 255.0, 0.0, 3 / 255.0});
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->count, 4u);
  EXPECT_NEAR(s->rms_255, std::sqrt(14.0 / 4), 1e-12);
  EXPECT_NEAR(s->bias_255, 0.5, 1e-12);
  EXPECT_NEAR(s->p99_255, 3, 1e-12);
  EXPECT_NEAR(s->max_255, 3, 1e-12);
  // Nearest rank: the 99th percentile of |e| = 1..200 (shuffled signs) is the 198th value.
  std::vector<double> e;
  for (int i = 1; i <= 200; ++i) e.push_back((i % 3 ? 1 : -1) * i / 255.0);
  EXPECT_NEAR(summarize_errors(e)->p99_255, 198, 1e-9);
  EXPECT_NEAR(summarize_errors(e)->max_255, 200, 1e-9);
}

TEST(AreaLightsVerifyPoints, DomainAndRadiusRange) {
  VerifyOptions o;
  o.rho_min_deg = 5, o.rho_max_deg = 20;
  for (uint32_t i = 0; i < 256; ++i) {
    const VerifyPoint p = verify_point(i, o);
    EXPECT_TRUE(p.visibility >= 0 && p.visibility <= 1 && p.n_dot_l >= 0 && p.n_dot_l <= 1) << i;
    EXPECT_TRUE(p.n_dot_v >= 0 && p.n_dot_v <= 1 && p.roughness >= 0 && p.roughness <= 1) << i;
    EXPECT_TRUE(p.rho >= 5 * kDeg - 1e-15 && p.rho <= 20 * kDeg + 1e-15) << i;
    EXPECT_TRUE(p.tilt >= -60 * kDeg && p.tilt <= 60 * kDeg && p.aspect >= 0.25 && p.aspect <= 1) << i;
  }
  o.rho_min_deg = o.rho_max_deg = 10;
  EXPECT_DOUBLE_EQ(verify_point(7, o).rho, 10 * kDeg);
}

TEST_F(AreaLightsVerify, PrefixWithinTheDocumentedFigures) {
  VerifyOptions o;
  o.points = 128, o.generic_points = 16, o.shape_points = 48, o.ltc_points = 48, o.aware_points = 2;
  o.diffuse_aware_points = 1;
  o.ltc = small_ltc_file();
  const VerifyResult r = verify_area_lights(o);
  ASSERT_TRUE(r.generic && r.shapes && r.ltc && r.aware && r.diffuse_aware);
  EXPECT_EQ(r.ltc_table, o.ltc);
  const CapErrors& c = r.cap;
  EXPECT_EQ(c.step_point_at_centre.count, 128u);
  EXPECT_EQ(r.generic->generic_vndf_alu_area_n4_float.count, 16u);
  EXPECT_EQ(r.shapes->rect_step_equivalent_cap.count, 48u);
  EXPECT_EQ(r.ltc->ltc_cap_step_ggx_cone_clip.count, 48u);
  EXPECT_EQ(r.aware->ggx_cap_specular_aware_mean_ltc_cone_clip_n4.count, 2u);
  EXPECT_EQ(r.diffuse_aware->lambert_cap_diffuse_aware_alu_point_at_centre.count, 1u);

  // §4: the closed form is the quadrature (max 6.6e-8/255 over 2048 points).
  EXPECT_LT(c.step_cosine_closed_form.max_255, 1e-6);
  expect_within_documented_max(c.step_solid_angle_mazonka, 65.8, 0.1, "Mazonka");
  expect_within_documented_max(c.step_solid_angle_oat_sander, 81.9, 0.1, "Oat-Sander");
  expect_within_documented_max(c.step_point_at_centre, 252, 1, "step point");
  expect_within_documented_max(c.oat_sander_vs_mazonka_solid_angle_fraction_of_light, 34.1, 0.1,
                               "OS - Mazonka");
  // §5: the product rule over the cap, the point values, the Lambert closed form for a GGX receiver.
  expect_within_documented_max(c.brinck_maximov_2016_area_n4, 0.088, 0.001, "BM cap");
  expect_within_documented_max(c.chan_2018_area_n4, 0.215, 0.001, "Chan cap");
  expect_within_documented_max(c.part1_analytic_area_n4, 0.215, 0.001, "Part 1 cap");
  expect_within_documented_max(c.brinck_maximov_2016_point_at_centre, 94.6, 0.1, "BM point");
  expect_within_documented_max(c.chan_2018_point_at_centre, 233, 1, "Chan point");
  expect_within_documented_max(c.part1_analytic_point_at_centre, 197, 1, "Part 1 point");
  expect_within_documented_max(c.step_closed_form_for_ggx_receiver, 202, 1, "Lambert form, GGX receiver");
  // "(double / float)": one row each in the docs, to the 3 decimals printed.
  expect_float_close(c.brinck_maximov_2016_area_n4_float, c.brinck_maximov_2016_area_n4, 5e-4, "BM float");
  expect_float_close(c.chan_2018_area_n4_float, c.chan_2018_area_n4, 5e-4, "Chan float");
  expect_float_close(c.part1_analytic_area_n4_float, c.part1_analytic_area_n4, 5e-4, "Part 1 float");
  // The point values are worse than the area forms (the reason for the area forms).
  EXPECT_GT(c.step_point_at_centre.rms_255, c.step_solid_angle_mazonka.rms_255);
  EXPECT_GT(c.brinck_maximov_2016_point_at_centre.rms_255, 100 * c.brinck_maximov_2016_area_n4.rms_255);

  // §5, the generic term (96 points documented).
  const GenericCapErrors& g = *r.generic;
  expect_within_documented_max(g.generic_vndf_exact_mean_area_n4, 0.082, 0.001, "generic exact mean");
  expect_within_documented_max(g.generic_vndf_alu_area_n4_float, 12.7, 0.1, "generic ALU");
  expect_within_documented_max(g.generic_vndf_alu_point_error_at_centre, 15.6, 0.1, "generic fit alone");
  expect_within_documented_max(g.generic_vndf_alu_point_at_centre, 119, 1, "generic point");

  // §5, disk and rect lights through the equivalent cap (512 points documented).
  const ShapeErrors& s = *r.shapes;
  expect_within_documented_max(s.disk_step_equivalent_cap, 42.4, 0.1, "disk step");
  expect_within_documented_max(s.disk_brinck_maximov_2016_equivalent_cap_n4, 10.4, 0.1, "disk BM");
  expect_within_documented_max(s.disk_chan_2018_equivalent_cap_n4, 25.3, 0.1, "disk Chan");
  expect_within_documented_max(s.disk_part1_analytic_equivalent_cap_n4, 15.3, 0.1, "disk Part 1");
  expect_within_documented_max(s.disk_step_point_at_centre, 205, 1, "disk point");
  expect_within_documented_max(s.disk_brinck_maximov_2016_point_at_centre, 86.9, 0.1, "disk BM point");
  expect_within_documented_max(s.rect_step_equivalent_cap, 76.3, 0.1, "rect step");
  expect_within_documented_max(s.rect_brinck_maximov_2016_equivalent_cap_n4, 35.0, 0.1, "rect BM");
  expect_within_documented_max(s.rect_chan_2018_equivalent_cap_n4, 71.9, 0.1, "rect Chan");
  expect_within_documented_max(s.rect_part1_analytic_equivalent_cap_n4, 40.3, 0.1, "rect Part 1");
  expect_within_documented_max(s.rect_step_point_at_centre, 216, 1, "rect point");
  expect_within_documented_max(s.rect_brinck_maximov_2016_point_at_centre, 93.4, 0.1, "rect BM point");
  expect_float_close(s.disk_step_equivalent_cap_float, s.disk_step_equivalent_cap, 4e-4, "disk step float");
  expect_float_close(s.rect_step_equivalent_cap_float, s.rect_step_equivalent_cap, 4e-4, "rect step float");
  EXPECT_GT(s.disk_step_point_at_centre.rms_255, s.disk_step_equivalent_cap.rms_255);
  EXPECT_GT(s.rect_step_point_at_centre.rms_255, s.rect_step_equivalent_cap.rms_255);

  // §5, the cone-clipped LTC: the rows that do not depend on the table (Lambertian receiver: identity LTC;
  // the Lambertian cap forms for a GGX receiver).
  const LtcErrors& l = *r.ltc;
  expect_within_documented_max(l.ltc_disk_step_lambert_cone_clip, 12.6, 0.1, "LTC disk step");
  expect_within_documented_max(l.ltc_disk_brinck_maximov_2016_lambert_cone_clip_n4, 0.8, 0.1, "LTC disk BM");
  expect_within_documented_max(l.ltc_disk_chan_2018_lambert_cone_clip_n4, 3.7, 0.1, "LTC disk Chan");
  expect_within_documented_max(l.ltc_disk_part1_analytic_lambert_cone_clip_n4, 1.0, 0.1, "LTC disk Part 1");
  expect_within_documented_max(l.ltc_rect_step_lambert_cone_clip, 15.3, 0.1, "LTC rect step");
  expect_within_documented_max(l.ltc_rect_brinck_maximov_2016_lambert_cone_clip_n4, 0.8, 0.1, "LTC rect BM");
  expect_within_documented_max(l.ltc_rect_chan_2018_lambert_cone_clip_n4, 3.9, 0.1, "LTC rect Chan");
  expect_within_documented_max(l.ltc_rect_part1_analytic_lambert_cone_clip_n4, 1.5, 0.1, "LTC rect Part 1");
  expect_within_documented_max(l.ltc_cap_step_ggx_lambert_closed_form, 198, 1, "GGX cap, closed form");
  expect_within_documented_max(l.ltc_disk_step_ggx_lambert_equivalent_cap, 161, 1,
                               "GGX disk, equivalent cap");
  expect_within_documented_max(l.ltc_rect_step_ggx_lambert_equivalent_cap, 222, 1,
                               "GGX rect, equivalent cap");
  expect_float_close(l.ltc_rect_step_lambert_cone_clip_float, l.ltc_rect_step_lambert_cone_clip, 0.01,
                     "LTC rect step float");
  // The Lambertian cone clip is the better fast form for disks and rects (same points as the shape block).
  EXPECT_LT(l.ltc_disk_step_lambert_cone_clip.rms_255, s.disk_step_equivalent_cap.rms_255);
  EXPECT_LT(l.ltc_rect_step_lambert_cone_clip.rms_255, s.rect_step_equivalent_cap.rms_255);

  // The aware blocks: the table-independent row (16 points documented) and the diffuse-aware fit (2).
  expect_within_documented_max(r.aware->ggx_cap_generic_vndf_alu_lambert_product_rule, 29.9, 0.1,
                               "generic ALU, Lambert product rule, GGX receiver");
  expect_within_documented_max(r.diffuse_aware->lambert_cap_diffuse_aware_alu_product_rule_n4_float, 0.82,
                               0.01, "diffuse-aware ALU through the product rule");
}

TEST_F(AreaLightsVerify, EmptyBlocksAndTheCliPrintsToJson) {
  VerifyOptions o;
  o.points = 8, o.generic_points = 0, o.shape_points = 4, o.ltc_points = 0, o.aware_points = 0;
  const VerifyResult r = verify_area_lights(o);
  EXPECT_FALSE(r.generic || r.ltc || r.aware || r.diffuse_aware);
  ASSERT_TRUE(r.shapes.has_value());
  EXPECT_EQ(r.ltc_table, "none");
  size_t present = 0, absent = 0;
  for (const NamedErrorSummary& f : named_errors(r)) (f.summary ? present : absent) += 1;
  EXPECT_EQ(present, 15u + 14u);
  EXPECT_EQ(absent, 4u + 26u + 7u + 2u);
  const nlohmann::json j = to_json(r);
  EXPECT_TRUE(j["errors"]["ltc_cap_step_ggx_cone_clip"].is_null());
  EXPECT_EQ(j["errors"]["disk_step_equivalent_cap"]["count"].get<int>(), 4);
  EXPECT_EQ(j["errors"].size(), present + absent);

  const std::string args =
      "verify area-lights --points 8 --generic-points 0 --shape-points 4 --ltc-points 0 --aware-points 0";
  const test::CliResult json = test::run_cli(args + " --json", dir);
  ASSERT_EQ(json.code, 0) << json.err;
  EXPECT_EQ(json.out, j.dump() + "\n");
  // The table: a header and one line per measured form.
  const test::CliResult text = test::run_cli(args, dir);
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_EQ(size_t(std::count(text.out.begin(), text.out.end(), '\n')), 1 + present);
  EXPECT_NE(text.out.find("\nrect_step_equivalent_cap "), std::string::npos);
}

TEST_F(AreaLightsVerify, BadOptionsThrowTheCliMessages) {
  const std::vector<std::pair<std::function<void(VerifyOptions&)>, std::string>> cases = {
      {[](VerifyOptions& o) { o.points = 0; }, "--points must be in [1, 2^20]"},
      {[](VerifyOptions& o) { o.points = (1 << 20) + 1; }, "--points must be in [1, 2^20]"},
      {[](VerifyOptions& o) { o.generic_points = -1; }, "--generic-points must be in [0, 2^16]"},
      {[](VerifyOptions& o) { o.shape_points = 70000; }, "--shape-points must be in [0, 2^16]"},
      {[](VerifyOptions& o) { o.ltc_points = -1; }, "--ltc-points must be in [0, 2^16]"},
      {[](VerifyOptions& o) { o.aware_points = 70000; }, "--aware-points must be in [0, 2^16]"},
      {[](VerifyOptions& o) { o.diffuse_aware_points = -1; }, "--diffuse-aware-points must be in [0, 2^16]"},
      {[](VerifyOptions& o) { o.rho_min_deg = 30, o.rho_max_deg = 20; },
       "--rho-min-deg and --rho-max-deg must satisfy 0 <= min <= max <= 90"},
      {[](VerifyOptions& o) { o.rho_max_deg = 91; },
       "--rho-min-deg and --rho-max-deg must satisfy 0 <= min <= max <= 90"},
      {[](VerifyOptions& o) { o.rho_min_deg = std::nan(""); },
       "--rho-min-deg and --rho-max-deg must satisfy 0 <= min <= max <= 90"},
  };
  for (const auto& [edit, message] : cases) {
    VerifyOptions o;
    edit(o);
    try {
      verify_area_lights(o);
      ADD_FAILURE() << "no error: " << message;
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), message);
    }
  }
  // A missing LTC table fails before any work when a block needs it, and is not read otherwise.
  VerifyOptions o;
  o.points = 1, o.generic_points = 0, o.shape_points = 0, o.ltc_points = 1, o.aware_points = 0;
  o.ltc = (dir / "none.dds").string();
  EXPECT_THROW(verify_area_lights(o), InputError);
  o.ltc_points = 0;
  EXPECT_EQ(verify_area_lights(o).ltc_table, "none");
}
