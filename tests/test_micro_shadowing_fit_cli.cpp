// `microshadow plot micro-shadowing-fit` and `eval micro-shadowing --method generic-vndf-alu`: output, files,
// exit codes.
#include <gtest/gtest.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
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

// plot micro-shadowing-fit ARGS --out DIR/NAME.csv: its stdout summary, and the CSV's header and rows.
struct FitRun {
  nlohmann::json summary;
  std::string header;
  std::vector<std::vector<double>> rows;
};
FitRun run_fit(const std::filesystem::path& dir, const std::string& name, const std::string& args) {
  std::filesystem::create_directories(dir);
  const auto csv = dir / (name + ".csv");
  const test::CliResult r = run("plot micro-shadowing-fit " + args + " --out " + csv.string());
  EXPECT_EQ(r.code, 0) << r.err;
  FitRun f;
  if (r.code != 0) return f;
  f.summary = nlohmann::json::parse(r.out);
  f.rows = read_csv(csv, &f.header);
  return f;
}

// The CSV's header (the inputs, early_out, exact, then the given columns) and size; check(V, N·L, N·V,
// roughness, row) on every row.
template <class Check>
void expect_csv(const FitRun& f, const std::string& columns, std::size_t rows, Check check) {
  EXPECT_EQ(f.header, "visibility,ndotl,ndotv,roughness,early_out,exact," + columns);
  ASSERT_EQ(f.rows.size(), rows);
  const std::size_t n = std::size_t(std::count(f.header.begin(), f.header.end(), ',')) + 1;
  for (const auto& row : f.rows) {
    ASSERT_EQ(row.size(), n);
    check(row[0], row[1], row[2], row[3], row);
  }
}

// The registry's closed forms that depend on N.L, in its order, comma-separated: the older terms' columns (a
// closed form added to the registry is a column without a change here).
std::string registry_closed_forms() {
  std::string s;
  for (const std::string& name : occlusion::micro_shadowing_closed_form_terms())
    s += (s.empty() ? "" : ",") + name;
  return s;
}

TEST(MicroShadowingFitCli, PlotWritesCsvAndSummary) {
  const auto dir = std::filesystem::temp_directory_path() / "msh_test_ms_fit_cli";
  const FitRun f = run_fit(dir, "pts", "--samples 60 --seed 9 --near-step 5");
  EXPECT_EQ(f.summary["points"], 65);
  const auto& alu = f.summary["errors_vs_exact_azimuth_mean"]["generic-vndf-alu"]["all"];
  EXPECT_EQ(alu["n"], 65);
  EXPECT_GE(alu["max_255"].get<double>(), alu["rms_255"].get<double>());
  EXPECT_EQ(registry_closed_forms().rfind("reference,brinck-maximov-2016,chan-2018", 0), 0u);  // row[9] below
  expect_csv(f, "generic-vndf-alu,generic-vndf-alu-two-stage," + registry_closed_forms(), 65,
             [](double V, double nl, double nv, double r, const std::vector<double>& row) {
               EXPECT_TRUE(V >= 0 && V <= 1 && nl > 0 && nl <= 1 && nv > 0 && nv <= 1 && r >= 0.1 && r <= 1);
               EXPECT_EQ(row[4] != 0, micro_shadowing::exact_zero(V, nl));
               EXPECT_NEAR(row[5], micro_shadowing::generic_vndf_exact_azimuth_mean(V, r * r, nl, nv), 1e-8);
               EXPECT_NEAR(row[6],
                           micro_shadowing::generic_vndf_alu(float(V), float(nl), float(nv), float(r)), 1e-7);
               EXPECT_NEAR(row[9], micro_shadowing::brinck_maximov_2016(V, nl), 1e-8);
             });
  // Deterministic: the same seed gives the same file.
  EXPECT_EQ(run_fit(dir, "pts2", "--samples 60 --seed 9 --near-step 5").rows, f.rows);
  std::filesystem::remove_all(dir);
}

TEST(MicroShadowingFitCli, DiffuseAwareColumnsAreRegistryIds) {
  const auto dir = std::filesystem::temp_directory_path() / "msh_test_ms_fit_cli_aware";
  const FitRun f = run_fit(dir, "pts", "--term diffuse-aware --samples 6 --seed 3");
  EXPECT_EQ(f.summary["errors_vs_exact_azimuth_mean"]["diffuse-aware-alu"]["all"]["n"], 6);
  expect_csv(
      f, "diffuse-aware-alu,generic-vndf-alu-two-stage,reference", 6,
      [](double V, double nl, double nv, double r, const std::vector<double>& row) {
        EXPECT_NEAR(row[6], micro_shadowing::diffuse_aware_alu(float(V), float(nl), float(nv), float(r)),
                    1e-7);
        EXPECT_NEAR(row[7],
                    micro_shadowing::generic_vndf_alu_two_stage(float(V), float(nl), float(nv), float(r)),
                    1e-7);
        EXPECT_EQ(row[8], micro_shadowing::reference_step(V, nl));
      });
  std::filesystem::remove_all(dir);
}

TEST(MicroShadowingFitCli, BadInputExitsTwo) {
  EXPECT_EQ(run("plot micro-shadowing-fit --samples 0 --out /tmp/x.csv").code, 2);
  EXPECT_EQ(run("plot micro-shadowing-fit --samples 10 --near-step -1 --out /tmp/x.csv").code, 2);
  EXPECT_EQ(run("plot micro-shadowing-fit --samples 10 --out /nonexistent-dir/x.csv").code, 2);
  EXPECT_EQ(run("plot micro-shadowing-fit --samples 10").code, 2);
}
