// The probe programs of tools/probes/ (docs/area-lights.md §5, "GGX receiver"): usage and bad arguments
// (exit 2, one line); the output's rows finite and in range; their points are verify area-lights' (the
// Lambert closed form row and the LTC rows at β = 0 and β = ltc_tail_weight = 1.5 α^1.5 equal what
// `verify area-lights` reports for those forms on the same points and table, up to the quadratures'
// tolerances); --first selects the points (the sums of squares of two ranges add up to their union's); the
// documented ordering of the representative point and the Lambert form.
#include <gtest/gtest.h>
#include <support/cli_test_util.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>

using namespace msh;

namespace {

class AreaProbes : public test::ScratchDirTest {
 protected:
  AreaProbes() : ScratchDirTest("area_probes") {}
  test::CliResult run(const std::string& program, const std::string& args) const {
    const std::string cmd =
        program + " " + args + " > " + (dir / "out.txt").string() + " 2> " + (dir / "err.txt").string();
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::slurp(dir / "out.txt"),
            test::slurp(dir / "err.txt")};
  }
  // The probe's JSON, every row checked: a finite RMS ≤ max ≤ 255 (the step is in [0, 1]); the row names
  // unique.
  nlohmann::json rows(const std::string& program, const std::string& args, size_t count) const {
    const test::CliResult r = run(program, args + " --json");
    EXPECT_EQ(r.code, 0) << args << "\n" << r.err;
    if (r.code != 0) return nlohmann::json();
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["rows"].size(), count);
    std::set<std::string> names;
    for (const nlohmann::json& row : j["rows"]) {
      const double rms = row["rms_255"].get<double>(), mx = row["max_255"].get<double>();
      EXPECT_TRUE(std::isfinite(rms) && rms >= 0 && rms <= mx + 1e-12 && mx <= 255) << row.dump();
      names.insert(row["form"].get<std::string>());
    }
    EXPECT_EQ(names.size(), count);
    return j;
  }
  // The row named `form`.
  static nlohmann::json row(const nlohmann::json& j, const std::string& form) {
    for (const nlohmann::json& r : j["rows"])
      if (r["form"] == form) return r;
    ADD_FAILURE() << "no row " << form;
    return {{"rms_255", NAN}, {"max_255", NAN}};
  }
  // The probe's row against verify area-lights' form: the same errors but for the exact reference, at
  // relative tolerance 1e-6 in the probe (≤ 2.6e-4/255 on a ratio in [0, 1]), 1e-7 or 1e-8 in verify.
  static void expect_same(const nlohmann::json& probe_row, const nlohmann::json& verify_form) {
    EXPECT_NEAR(probe_row["rms_255"].get<double>(), verify_form["rms_255"].get<double>(), 3e-4)
        << probe_row.dump();
    EXPECT_NEAR(probe_row["max_255"].get<double>(), verify_form["max_255"].get<double>(), 3e-4)
        << probe_row.dump();
  }
};

}  // namespace

TEST_F(AreaProbes, UsageAndBadArguments) {
  // The LTC probe gets a table name that does not exist: a bad argument fails first, before the table is
  // read.
  for (const auto& [program, table] :
       {std::pair<std::string, std::string>{MSH_PROBE_PATH, ""}, {MSH_LTC_PROBE_PATH, " --ltc none.dds"}}) {
    const test::CliResult help = run(program, "--help");
    EXPECT_EQ(help.code, 0) << program;
    EXPECT_NE(help.out.find("--points"), std::string::npos) << program;
    EXPECT_NE(help.out.find("--first"), std::string::npos) << program;
    for (const char* args :
         {"--points 0", "--points x", "--points 2000000", "--first -1", "--bogus", "extra"}) {
      const test::CliResult r = run(program, args + table);
      EXPECT_EQ(r.code, 2) << program << " " << args;
      EXPECT_TRUE(r.out.empty()) << program << " " << args;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << program << " " << args << ": " << r.err;
      EXPECT_EQ(r.err.find("none.dds"), std::string::npos) << program << " " << args << ": " << r.err;
    }
  }
  // The LTC probe needs a table, and a readable one.
  for (const std::string& args :
       {std::string("--points 2"), "--points 2 --ltc " + (dir / "none.dds").string()}) {
    const test::CliResult r = run(MSH_LTC_PROBE_PATH, args);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
}

TEST_F(AreaProbes, CapFormsOnVerifyPoints) {
  const nlohmann::json j = rows(MSH_PROBE_PATH, "--points 24", 21);
  const test::CliResult v = test::run_cli(
      "verify area-lights --points 24 --generic-points 0 --shape-points 0 --ltc-points 0 --aware-points 0 "
      "--json",
      dir);
  ASSERT_EQ(v.code, 0) << v.err;
  expect_same(row(j, "Lambert closed form"),
              nlohmann::json::parse(v.out)["errors"]["step_closed_form_for_ggx_receiver"]);
  // docs/area-lights.md: the representative point is far worse than the Lambert form (66 vs 17 RMS).
  EXPECT_GT(
      row(j, "representative point (Karis 2013 closest point to the mirror ray)")["rms_255"].get<double>(),
      2 * row(j, "Lambert closed form")["rms_255"].get<double>());
  // --first: points [0, 8) and [8, 24) make up [0, 24), row by row.
  const nlohmann::json a = rows(MSH_PROBE_PATH, "--points 8", 21),
                       b = rows(MSH_PROBE_PATH, "--points 16 --first 8", 21);
  for (size_t f = 0; f < 21; ++f) {
    auto ss = [&](const nlohmann::json& x, int n) {
      return n * std::pow(x["rows"][f]["rms_255"].get<double>(), 2);
    };
    EXPECT_NEAR(ss(a, 8) + ss(b, 16), ss(j, 24), 1e-9 * (1 + ss(j, 24))) << f;
    EXPECT_DOUBLE_EQ(std::max(a["rows"][f]["max_255"].get<double>(), b["rows"][f]["max_255"].get<double>()),
                     j["rows"][f]["max_255"].get<double>())
        << f;
  }
}

TEST_F(AreaProbes, LtcTailOnVerifyPoints) {
  const std::string table = (dir / "ltc6.npy").string();
  ASSERT_EQ(
      test::run_cli(
          "bake ltc --size 6 --error-samples 8 --iterations 30 --moment-samples 256 --quiet --out " + table,
          dir)
          .code,
      0);
  const nlohmann::json j = rows(MSH_LTC_PROBE_PATH, "--points 24 --ltc " + table, 17);
  EXPECT_EQ(j["ltc_table"], table);
  const test::CliResult v = test::run_cli(
      "verify area-lights --points 1 --generic-points 0 --shape-points 0 --ltc-points 24 --aware-points 0 "
      "--ltc " +
          table + " --json",
      dir);
  ASSERT_EQ(v.code, 0) << v.err;
  const nlohmann::json errors = nlohmann::json::parse(v.out)["errors"];
  expect_same(row(j, "beta = 0"), errors["ltc_cap_step_ggx_cone_clip_no_tail"]);
  expect_same(row(j, "beta = 1.5 alpha^1.5"), errors["ltc_cap_step_ggx_cone_clip"]);
}
