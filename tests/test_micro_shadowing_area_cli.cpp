// `microshadow eval micro-shadowing ... --light-radius-deg RHO` (area lights) and `verify area-lights`:
// ρ = 0 is bit-identical to the point value, the value matches the library's closed form / exact quadrature,
// light shapes and receivers, bad input exits 2 with one line on stderr.
#include <gtest/gtest.h>
#include <microshadow/lut/runtime/micro_shadowing_analysis.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "support/cli_test_util.h"

using namespace msh;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;

nlohmann::json eval_json(const std::string& args) {
  const test::CliResult r = test::run_cli("eval micro-shadowing " + args + " --json");
  EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
  return r.code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json();
}

}  // namespace

TEST(AreaLightsCli, ZeroRadiusIsThePointValueBitForBit) {
  for (const std::string base :
       {"--method reference --visibility 0.5 --ndotl 0.72",
        "--method brinck-maximov-2016 --visibility 0.4 --ndotl 0.3",
        "--method chan-2018 --visibility 0.6 --ndotl 0.5",
        "--method part1-analytic --visibility 0.3 --ndotl 0.9",
        "--method generic-vndf --visibility 0.5 --ndotl 0.7 --roughness 0.4 --ndotv 0.8 --phi 1.1",
        "--method generic-vndf --visibility 0.5 --ndotl 0.7 --roughness 0.4 --ndotv 0.8",
        "--method generic-vndf-alu --visibility 0.5 --ndotl 0.7 --roughness 0.4 --ndotv 0.8"}) {
    const nlohmann::json p = eval_json(base), a = eval_json(base + " --light-radius-deg 0");
    EXPECT_EQ(p["value"].get<double>(), a["value"].get<double>()) << base;
    EXPECT_EQ(a["light"]["radius_deg"].get<double>(), 0.0);
    const nlohmann::json g = eval_json(base + " --light-radius-deg 0 --receiver ggx --light-shape disk");
    EXPECT_EQ(p["value"].get<double>(), g["value"].get<double>()) << base;
  }
}

TEST(AreaLightsCli, SphereMatchesClosedFormAndQuadrature) {
  const double V = 0.5, nl = 0.72, rho = 12.5;
  const nlohmann::json j =
      eval_json("--method reference --visibility 0.5 --ndotl 0.72 --light-radius-deg 12.5");
  EXPECT_NEAR(j["value"].get<double>(), micro_shadowing::reference_step_area_cap(V, nl, rho * kDeg), 1e-8);
  EXPECT_EQ(j["light"]["point_value"].get<double>(), micro_shadowing::reference_step(V, nl));
  // A facing disk is the same cap.
  const nlohmann::json d = eval_json(
      "--method reference --visibility 0.5 --ndotl 0.72 --light-radius-deg 12.5 --light-shape disk");
  EXPECT_NEAR(d["value"].get<double>(), j["value"].get<double>(), 1e-7);
  // Brinck–Maximov: the exact quadrature of the library.
  const nlohmann::json b =
      eval_json("--method brinck-maximov-2016 --visibility 0.4 --ndotl 0.3 --light-radius-deg 30");
  EXPECT_NEAR(
      b["value"].get<double>(),
      area::area_micro_shadowing_exact(area::Cap{lut::study_light_dir(0.3, 0.0), 30 * kDeg},
                                       area::Receiver::lambert(), area::brinck_maximov_2016_term(0.4)),
      1e-9);
}

TEST(AreaLightsCli, ReceiverShapesAndAzimuth) {
  // GGX receiver: the light's azimuth matters, also for a term that does not read it.
  const std::string base =
      "--method reference --visibility 0.5 --ndotl 0.6 --ndotv 0.7 --roughness 0.3 "
      "--light-radius-deg 20 --receiver ggx";
  const double a0 = eval_json(base + " --phi 0")["value"].get<double>();
  const double a3 = eval_json(base + " --phi 3")["value"].get<double>();
  const area::Receiver rec = area::Receiver::ggx(0.09, lut::study_view_dir(0.7));
  EXPECT_NEAR(a3,
              area::area_micro_shadowing_exact(area::Cap{lut::study_light_dir(0.6, 3.0), 20 * kDeg}, rec,
                                               area::reference_step_term(0.5)),
              1e-9);
  EXPECT_GT(std::abs(a0 - a3), 1e-3);
  // Rectangles: a square differs from a thin strip; tilt changes the value; values in [0, 1].
  const std::string r =
      "--method chan-2018 --visibility 0.5 --ndotl 0.6 --light-radius-deg 20 --light-shape rect";
  const double sq = eval_json(r)["value"].get<double>();
  const double strip = eval_json(r + " --light-half-height-deg 2")["value"].get<double>();
  const double tilted = eval_json(r + " --light-tilt-deg 50 --light-roll-deg 30")["value"].get<double>();
  for (double x : {sq, strip, tilted}) {
    EXPECT_GE(x, 0.0);
    EXPECT_LE(x, 1.0);
  }
  EXPECT_GT(std::abs(sq - strip), 1e-4);
  EXPECT_GT(std::abs(sq - tilted), 1e-4);
}

TEST(AreaLightsCli, GenericMeanTermOverALight) {
  // Without --phi the generic term is its azimuth mean; over a light with a Lambertian receiver that is the
  // exact azimuth mean of M_area (docs/area-lights.md §5): compare with the library.
  const nlohmann::json j = eval_json(
      "--method generic-vndf --visibility 0.55 --ndotl 0.6 --roughness 0.5 --ndotv 0.7 --light-radius-deg "
      "15");
  const area::PointTerm mean{[](const Vec3d& l) {
                               return micro_shadowing::generic_vndf_exact_azimuth_mean(
                                   0.55, 0.25, std::clamp(l.z, 0.0, 1.0), 0.7);
                             },
                             area::standard_z_breaks(0.55), true};
  EXPECT_NEAR(j["value"].get<double>(),
              area::area_micro_shadowing_exact(area::Cap{lut::study_light_dir(0.6, 0.0), 15 * kDeg},
                                               area::Receiver::lambert(), mean),
              1e-7);
  EXPECT_NE(j["light"]["estimator"].get<std::string>().find("azimuth mean"), std::string::npos);
}

TEST(AreaLightsCli, BadInputExitsTwo) {
  const std::string base = "eval micro-shadowing --method reference --visibility 0.5 --ndotl 0.3 ";
  for (const char* args :
       {"--light-radius-deg -1", "--light-radius-deg 91", "--light-radius-deg nan",
        "--light-radius-deg 10 --light-shape cone", "--light-radius-deg 10 --receiver phong",
        "--light-shape disk", "--receiver ggx", "--light-radius-deg 10 --light-tilt-deg 10",
        "--light-radius-deg 10 --light-shape disk --light-tilt-deg 90",
        "--light-radius-deg 90 --light-shape rect",
        "--light-radius-deg 10 --light-shape disk --light-half-height-deg 3",
        "--light-radius-deg 10 --light-shape rect --light-half-height-deg 95",
        "--light-radius-deg 10 --phi 4"}) {
    const test::CliResult r = test::run_cli(base + args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_TRUE(r.out.empty()) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
  // A light of 90° radius is valid (its lower half is below the horizon).
  const test::CliResult ok = test::run_cli(base + "--light-radius-deg 90");
  EXPECT_EQ(ok.code, 0);
}

TEST(AreaLightsCli, VerifyRuns) {
  // A small LTC table (bake ltc, 6²) keeps the LTC block quick; its accuracy is tested in
  // test_micro_shadowing_area_ltc.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("msh_area_verify." + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string table = (dir / "ltc6.npy").string();
  ASSERT_EQ(test::run_cli("bake ltc --size 6 --error-samples 8 --iterations 30 --moment-samples 256 --quiet "
                          "--out " +
                          table)
                .code,
            0);
  const test::CliResult r = test::run_cli(
      "verify area-lights --points 32 --generic-points 2 --shape-points 8 --ltc-points 8 "
      "--aware-points 2 --ltc " +
      table + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_LT(j["errors"]["step_cosine_closed_form"]["max_255"].get<double>(), 1e-6);
  EXPECT_GT(j["errors"]["step_point_at_centre"]["max_255"].get<double>(), 1.0);
  // The Lambertian cone clip is exact up to the 16-gons (verify at 512 points: RMS 0.79/255, max 15.3/255).
  EXPECT_LT(j["errors"]["ltc_rect_step_lambert_cone_clip"]["max_255"].get<double>(), 20.0);
  EXPECT_EQ(j["errors"]["ltc_cap_step_ggx_cone_clip"]["count"].get<int>(), 8);
  EXPECT_EQ(j["errors"]["ggx_cap_specular_aware_mean_ltc_cone_clip_n4"]["count"].get<int>(), 2);
  EXPECT_TRUE(j["errors"]["lambert_cap_diffuse_aware_alu_product_rule_n4_float"].is_null());
  EXPECT_EQ(test::run_cli("verify area-lights --points 0").code, 2);
  EXPECT_EQ(test::run_cli("verify area-lights --points 4 --ltc-points -1").code, 2);
  const test::CliResult missing =
      test::run_cli("verify area-lights --points 4 --ltc-points 2 --ltc " + (dir / "none.npy").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  std::filesystem::remove_all(dir);
}
