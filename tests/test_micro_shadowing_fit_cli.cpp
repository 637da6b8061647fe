// `microshadow plot micro-shadowing-fit` and `eval micro-shadowing --method generic-vndf-alu`: output, files,
// exit codes.
#include <gtest/gtest.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_test_util.h"

using namespace msh;

namespace {

test::CliResult run(const std::string& args) { return test::run_cli(args); }

std::vector<std::vector<double>> read_csv(const std::filesystem::path& p, std::string* header) {
  std::ifstream f(p);
  std::getline(f, *header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(f, line);) {
    std::vector<double> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace

TEST(MicroShadowingFitCli, EvalAlu) {
  const test::CliResult r =
      run("eval micro-shadowing --method generic-vndf-alu --visibility 0.5 --roughness 0.4 --ndotl 0.8 "
          "--ndotv 0.6 "
          "--json");
  ASSERT_EQ(r.code, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["method"], "generic-vndf-alu");
  EXPECT_EQ(j["value"].get<double>(), double(micro_shadowing::generic_vndf_alu(0.5f, 0.8f, 0.6f, 0.4f)));
  EXPECT_EQ(j["two_stage"].get<double>(),
            double(micro_shadowing::generic_vndf_alu_two_stage(0.5f, 0.8f, 0.6f, 0.4f)));
  // Both are near the exact term here (well inside their measured max error).
  const double exact = micro_shadowing::generic_vndf_exact_azimuth_mean(0.5, 0.16, 0.8, 0.6);
  EXPECT_NEAR(j["value"].get<double>(), exact, 0.05);
  EXPECT_NEAR(j["two_stage"].get<double>(), exact, 0.05);
  EXPECT_EQ(run("eval micro-shadowing --method generic-vndf-alu --visibility 0.5 --ndotl 0.5 --phi 1").code,
            2);
}

TEST(MicroShadowingFitCli, PlotWritesCsvAndSummary) {
  const auto dir = std::filesystem::temp_directory_path() / "msh_test_ms_fit_cli";
  std::filesystem::create_directories(dir);
  const auto csv = dir / "pts.csv";
  const test::CliResult r =
      run("plot micro-shadowing-fit --samples 60 --seed 9 --near-step 5 --out " + csv.string());
  ASSERT_EQ(r.code, 0);
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["points"], 65);
  const auto& alu = j["errors_vs_exact_azimuth_mean"]["generic-vndf-alu"]["all"];
  EXPECT_EQ(alu["n"], 65);
  EXPECT_GE(alu["max_255"].get<double>(), alu["rms_255"].get<double>());
  std::string header;
  const auto rows = read_csv(csv, &header);
  EXPECT_EQ(header,
            "visibility,ndotl,ndotv,roughness,early_out,exact,generic-vndf-alu,generic-vndf-alu-two-stage,"
            "reference,"
            "brinck-maximov-2016,chan-2018,part1-analytic");
  ASSERT_EQ(rows.size(), 65u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 12u);
    const double V = row[0], nl = row[1], nv = row[2], r = row[3];
    EXPECT_TRUE(V >= 0 && V <= 1 && nl > 0 && nl <= 1 && nv > 0 && nv <= 1 && r >= 0.1 && r <= 1);
    EXPECT_EQ(row[4] != 0, micro_shadowing::exact_zero(V, nl));
    EXPECT_NEAR(row[5], micro_shadowing::generic_vndf_exact_azimuth_mean(V, r * r, nl, nv), 1e-8);
    EXPECT_NEAR(row[6], micro_shadowing::generic_vndf_alu(float(V), float(nl), float(nv), float(r)), 1e-7);
    EXPECT_NEAR(row[9], micro_shadowing::brinck_maximov_2016(V, nl), 1e-8);
  }
  // Deterministic: the same seed gives the same file.
  const auto csv2 = dir / "pts2.csv";
  ASSERT_EQ(run("plot micro-shadowing-fit --samples 60 --seed 9 --near-step 5 --out " + csv2.string()).code,
            0);
  std::string h2;
  EXPECT_EQ(read_csv(csv2, &h2), rows);
  std::filesystem::remove_all(dir);
}

TEST(MicroShadowingFitCli, DiffuseAwareColumnsAreRegistryIds) {
  const auto dir = std::filesystem::temp_directory_path() / "msh_test_ms_fit_cli_aware";
  std::filesystem::create_directories(dir);
  const auto csv = dir / "pts.csv";
  const test::CliResult r =
      run("plot micro-shadowing-fit --term diffuse-aware --samples 6 --seed 3 --out " + csv.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["errors_vs_exact_azimuth_mean"]["diffuse-aware-alu"]["all"]["n"], 6);
  std::string header;
  const auto rows = read_csv(csv, &header);
  EXPECT_EQ(header,
            "visibility,ndotl,ndotv,roughness,early_out,exact,diffuse-aware-alu,generic-vndf-alu-two-stage,"
            "reference");
  ASSERT_EQ(rows.size(), 6u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 9u);
    const double V = row[0], nl = row[1], nv = row[2], r = row[3];
    EXPECT_NEAR(row[6], micro_shadowing::diffuse_aware_alu(float(V), float(nl), float(nv), float(r)), 1e-7);
    EXPECT_NEAR(row[7], micro_shadowing::generic_vndf_alu_two_stage(float(V), float(nl), float(nv), float(r)),
                1e-7);
    EXPECT_EQ(row[8], micro_shadowing::reference_step(V, nl));
  }
  std::filesystem::remove_all(dir);
}

TEST(MicroShadowingFitCli, BadInputExitsTwo) {
  EXPECT_EQ(run("plot micro-shadowing-fit --samples 0 --out /tmp/x.csv").code, 2);
  EXPECT_EQ(run("plot micro-shadowing-fit --samples 10 --near-step -1 --out /tmp/x.csv").code, 2);
  EXPECT_EQ(run("plot micro-shadowing-fit --samples 10 --out /nonexistent-dir/x.csv").code, 2);
  EXPECT_EQ(run("plot micro-shadowing-fit --samples 10").code, 2);
}
