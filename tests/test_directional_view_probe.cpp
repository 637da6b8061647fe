// tools/probes/directional_view_probe (docs/directional-occlusion.md, "The view–light correlation floor"):
// usage and bad arguments (exit 2, one line, nothing on stdout); on a flat field every form equals the
// camera-weighted ground truth exactly (f = l_z, n = z: the weights cancel); on relief the measurement shows
// what it documents: the slope-corrected mean is closer to the ground truth than the view-independent mean
// on every light of a small gravel field, and the fitted forms track the exact ones.
#include <gtest/gtest.h>
#include <support/cli_test_util.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

using namespace msh;

namespace {

class ViewProbe : public test::ScratchDirTest {
 protected:
  ViewProbe() : ScratchDirTest("view_probe") {}
  test::CliResult run(const std::string& args) const {
    const std::string cmd = std::string(MSH_VIEW_PROBE_PATH) + " " + args + " > " +
                            (dir / "out.txt").string() + " 2> " + (dir / "err.txt").string();
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::slurp(dir / "out.txt"),
            test::slurp(dir / "err.txt")};
  }
};

}  // namespace

TEST_F(ViewProbe, UsageAndBadArguments) {
  const test::CliResult help = run("--help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("--view-elevation"), std::string::npos);
  for (const char* args : {"--size 4", "--elevations 0", "--elevations 5,x", "--azimuths 30",
                           "--view-elevation 90", "--kinds granite", "--bogus"}) {
    const test::CliResult r = run(std::string(args) + " --size 16");
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_TRUE(r.out.empty()) << args;
    EXPECT_FALSE(r.err.empty()) << args;
  }
}

TEST_F(ViewProbe, FlatFieldIsExact) {
  const test::CliResult r = run("--flat --size 16 --fits --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["rows"].size(), 10u);
  for (const auto& row : j["rows"])
    for (const char* k : {"view_independent", "slope_corrected", "no_masking"})
      EXPECT_NEAR(row[k].get<double>(), 1.0, 1e-9) << k << " " << row.dump();
  // The fits reproduce l_z exactly (it is in the span of the basis), up to the solve's rounding.
  for (const auto& row : j["rows"])
    for (const char* k : {"fit9", "fit9_slope4", "fit9_slope9"})
      EXPECT_NEAR(row[k].get<double>(), 1.0, 1e-6) << k << " " << row.dump();
}

TEST_F(ViewProbe, SlopeCorrectionCloserOnRelief) {
  const test::CliResult r = run("--kinds gravel --size 64 --fits --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  ASSERT_EQ(j["rows"].size(), 10u);
  double worst_a = 0;
  for (const auto& row : j["rows"]) {
    const double a = std::abs(row["view_independent"].get<double>() - 1),
                 b = std::abs(row["slope_corrected"].get<double>() - 1);
    EXPECT_LE(b, a + 1e-12) << row.dump();
    worst_a = std::max(worst_a, a);
    for (const char* k : {"gt", "fit9", "fit9_slope4", "fit9_slope9"})
      EXPECT_TRUE(std::isfinite(row[k].get<double>())) << k;
  }
  EXPECT_GT(worst_a, 0.05);  // the correlation is real on this field, so the comparison means something
}
