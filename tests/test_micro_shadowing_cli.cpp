// `microshadow eval micro-shadowing` / `plot micro-shadowing`: JSON output, exit codes, files.
#include <gtest/gtest.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/cli_test_util.h"

using namespace msh;

namespace {

test::CliResult run(const std::string& args) { return test::run_cli(args); }

nlohmann::json eval_json(const std::string& args) {
  const test::CliResult r = run("eval micro-shadowing " + args + " --json");
  EXPECT_EQ(r.code, 0) << args;
  return nlohmann::json::parse(r.out);
}

}  // namespace

TEST(MicroShadowingCli, EvalJson) {
  const auto j = eval_json("--method generic-vndf --visibility 0.5 --roughness 0.4 --ndotl 0.3 --ndotv 0.8");
  EXPECT_EQ(j["method"], "generic-vndf");
  EXPECT_EQ(j["early_out"], false);
  EXPECT_TRUE(j["inputs"]["phi"].is_null());
  EXPECT_NEAR(j["inputs"]["alpha_x"].get<double>(), 0.16, 1e-15);
  EXPECT_NEAR(j["value"].get<double>(), micro_shadowing::generic_vndf_exact_azimuth_mean(0.5, 0.16, 0.3, 0.8),
              1e-12);

  const auto k =
      eval_json("--method generic-vndf --visibility 0.5 --roughness 0.4 --ndotl 0.3 --ndotv 0.8 --phi 1.2");
  const Vec3d v(std::sqrt(1 - 0.64), 0, 0.8),
      l(std::sqrt(1 - 0.09) * std::cos(1.2), std::sqrt(1 - 0.09) * std::sin(1.2), 0.3);
  EXPECT_NEAR(k["value"].get<double>(), micro_shadowing::generic_vndf_exact(0.5, 0.16, 0.16, v, l), 1e-12);

  // Estimator: close to the exact value; differs between seeds; reproducible for one seed.
  const std::string est =
      "--method generic-vndf --visibility 0.8 --roughness 0.6 --ndotl 0.5 --ndotv 0.4 --phi 0.7 --samples "
      "65536";
  const double e1 = eval_json(est)["value"], e2 = eval_json(est + " --seed 9")["value"],
               e1b = eval_json(est)["value"];
  const double ex = eval_json(
      "--method generic-vndf --visibility 0.8 --roughness 0.6 --ndotl 0.5 --ndotv 0.4 --phi 0.7")["value"];
  EXPECT_EQ(e1, e1b);
  EXPECT_NE(e1, e2);
  EXPECT_NEAR(e1, ex, 5e-3);
  EXPECT_NEAR(e2, ex, 5e-3);

  // Closed-form terms and the early-out flag.
  EXPECT_DOUBLE_EQ(eval_json("--method chan-2018 --visibility 0.75 --ndotl 0.25")["value"].get<double>(),
                   0.25);
  EXPECT_DOUBLE_EQ(
      eval_json("--method brinck-maximov-2016 --visibility 0.75 --ndotl 0.25")["value"].get<double>(), 0.375);
  EXPECT_EQ(eval_json("--method reference --visibility 0.75 --ndotl 0.51")["value"].get<double>(), 1.0);
  EXPECT_EQ(eval_json("--method part1-analytic --visibility 1 --ndotl 0.1")["value"].get<double>(), 1.0);
  const auto z = eval_json("--method generic-vndf --visibility 0.2 --roughness 1 --ndotl 0.5 --ndotv 0.1");
  EXPECT_EQ(z["early_out"], true);
  EXPECT_EQ(z["value"].get<double>(), 0.0);
  // Both G2 forms give the same exact value (the Smith weight cancels).
  EXPECT_EQ(
      eval_json("--visibility 0.7 --roughness 0.5 --ndotl 0.6 --g2 uncorrelated")["value"].get<double>(),
      eval_json("--visibility 0.7 --roughness 0.5 --ndotl 0.6 --g2 height-correlated")["value"]
          .get<double>());
  // Plain output: one number.
  const test::CliResult r = run("eval micro-shadowing --method chan-2018 --visibility 0.75 --ndotl 0.25");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out, "0.25\n");
}

// LUT methods (the LUT module's default table, baked on first use): wired to the right slice and close to the
// exact azimuth mean (the table's own accuracy is tested in test_lut*).
TEST(MicroShadowingCli, LutMethods) {
  const auto a = eval_json("--method lut3d --visibility 0.7 --roughness 0.4 --ndotl 0.6 --ndotv 0.3");
  EXPECT_EQ(a["lut_layout"], "cone");  // the default table
  EXPECT_EQ(a["lut_size"][2], 16);
  EXPECT_EQ(a["lut_roughness_slabs"], 16);
  EXPECT_NEAR(a["value"].get<double>(), micro_shadowing::generic_vndf_exact_azimuth_mean(0.7, 0.16, 0.6, 0.3),
              0.01);
  const auto b = eval_json("--method lut2d --visibility 0.7 --roughness 0.4 --ndotl 0.6 --ndotv 0.3");
  EXPECT_EQ(b["lut_size"][2], 1);
  EXPECT_NEAR(b["value"].get<double>(), micro_shadowing::generic_vndf_exact_azimuth_mean(0.7, 0.16, 0.6, 1.0),
              0.01);
  EXPECT_EQ(eval_json("--method lut3d --visibility 0.2 --roughness 0.4 --ndotl 0.5")["value"].get<double>(),
            0.0);
}

TEST(MicroShadowingCli, BadInputExitsTwo) {
  for (const char* args :
       {"--visibility 1.5 --ndotl 0.3", "--visibility nan --ndotl 0.3", "--visibility 0.5 --ndotl inf",
        "--visibility 0.5 --ndotl -0.1", "--visibility 0.5 --ndotl 0.3 --roughness 2",
        "--visibility 0.5 --ndotl 0.3 --method nope", "--visibility 0.5 --ndotl 0.3 --phi 4",
        "--visibility 0.5 --ndotl 0.3 --samples 0", "--visibility 0.5 --ndotl 0.3 --g2 separable",
        "--visibility 0.5", "--visibility 0.5 --ndotl 0.3 --method chan-2018 --samples 8",
        "--visibility 0.5 --ndotl 0.3 --method lut3d --lut /nonexistent.dds",
        "--visibility 0.5 --ndotl 0.3 --method lut2d --roughness-y 0.2", "--visibility 0.5 --ndotl abc"}) {
    const test::CliResult r = run(std::string("eval micro-shadowing ") + args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_TRUE(r.out.empty()) << args;
  }
  EXPECT_EQ(run("eval micro-shadowing --help").code, 0);
  EXPECT_EQ(run("plot micro-shadowing --help").code, 0);
  EXPECT_EQ(
      run("plot micro-shadowing --out /proc/msh_no_such_dir/x --size 3 --azimuth-configs 2 --mc-samples 0")
          .code,
      2);
  EXPECT_EQ(run("plot micro-shadowing --out /tmp --size 1").code, 2);
}

// methods --bump lists the bump-terminator registry (the names render --bump-terminator takes); the
// micro-shadowing filters do not apply to it.
TEST(MicroShadowingCli, MethodsBumpListsTheBumpRegistry) {
  const test::CliResult names = run("methods --bump --names");
  ASSERT_EQ(names.code, 0) << names.err;
  std::string want;
  for (const bump::MethodInfo& i : bump::kMethods) {
    if (!want.empty()) want += ',';
    want += i.name;
  }
  EXPECT_EQ(names.out, want + "\n");
  const test::CliResult json = run("methods --bump --json");
  ASSERT_EQ(json.code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  ASSERT_EQ(j.size(), std::size(bump::kMethods));
  EXPECT_EQ(j[1]["name"], "conty-2019");
  EXPECT_EQ(j[1]["label"], std::string(bump::kMethods[1].label));
  EXPECT_EQ(run("methods --bump --study").code, 2);
}

TEST(MicroShadowingCli, PlotWritesCsvsDeterministically) {
  const std::filesystem::path d1 = std::filesystem::path(MSH_BINARY_DIR) / "test_ms_plot1",
                              d2 = std::filesystem::path(MSH_BINARY_DIR) / "test_ms_plot2";
  std::filesystem::remove_all(d1);
  std::filesystem::remove_all(d2);
  const std::string opts = " --size 5 --azimuth-configs 16 --mc-samples 4096";
  ASSERT_EQ(run("plot micro-shadowing --out " + d1.string() + opts).code, 0);
  ASSERT_EQ(run("plot micro-shadowing --out " + d2.string() + opts).code, 0);
  for (const char* f : {"maps.csv", "errors.csv", "azimuth_error.csv", "validation.csv", "summary.json"}) {
    const std::string a = test::slurp(d1 / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, test::slurp(d2 / f)) << f;
  }
  const std::string maps = test::slurp(d1 / "maps.csv");
  EXPECT_EQ(
      maps.substr(0, maps.find('\n')),
      "roughness,ndotv,visibility,ndotl,reference,brinck-maximov-2016,chan-2018,part1-analytic,generic-vndf");
  // 5 roughness × 3 N·V × 5 × 5 rows + header.
  EXPECT_EQ(std::count(maps.begin(), maps.end(), '\n'), 5 * 3 * 25 + 1);
  const auto s = nlohmann::json::parse(test::slurp(d1 / "summary.json"));
  EXPECT_EQ(s["azimuth_error"]["harmonics_0"]["all"]["count"], 16);
  std::filesystem::remove_all(d1);
  std::filesystem::remove_all(d2);
}
