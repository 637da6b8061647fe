// `microshadow bake ltc` and `verify ltc`: the files, sidecar and JSON they write, the round trip through
// every texture format, and bad input (one line on stderr, exit code 2, nothing written).
#include <gtest/gtest.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>

#include <nlohmann/json.hpp>

#include "support/cli_test_util.h"

using namespace msh;
using msh::test::run_cli;
using msh::test::scratch_dir;
namespace fs = std::filesystem;

namespace {
const char* kSmall = " --size 5 --error-samples 8 --iterations 20 --moment-samples 256 --quiet";
}

TEST(LtcCli, BakeWritesTablesSidecarAndVerifyReadsThem) {
  const fs::path dir = scratch_dir("ltc_cli");
  const auto r = run_cli("bake ltc --out " + (dir / "t.npy").string() + kSmall, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["size"], 5);
  EXPECT_TRUE(fs::exists(dir / "t.npy") && fs::exists(dir / "t_amp.npy") && fs::exists(dir / "t.npy.json"));
  const auto side = nlohmann::json::parse(test::slurp(dir / "t.npy.json"));
  EXPECT_EQ(side["moments_file"], "t_amp.npy");
  const bsdf::LtcTable t = bsdf::load_ltc_table(dir / "t.npy");
  EXPECT_EQ(t.size, 5);
  // Same table through dds and exr (float32): identical texels.
  for (const char* ext : {"dds", "exr", "ktx2"}) {
    const fs::path p = dir / (std::string("u.") + ext);
    ASSERT_EQ(run_cli("bake ltc --out " + p.string() + kSmall, dir).code, 0) << ext;
    const bsdf::LtcTable u = bsdf::load_ltc_table(p);
    EXPECT_EQ(u.mat, t.mat) << ext;
    EXPECT_EQ(u.amp, t.amp) << ext;
  }
  const auto v = run_cli("verify ltc " + (dir / "t.npy").string() + " --points 6", dir);
  ASSERT_EQ(v.code, 0) << v.err;
  const auto vj = nlohmann::json::parse(v.out);
  EXPECT_EQ(vj["sphere_vs_ggx"]["count"], 6);
  EXPECT_TRUE(vj["rect_vs_ggx"]["rms_abs"].is_number());
  EXPECT_LE(vj["reference_check_max_relative"].get<double>(), 1e-5);
}

TEST(LtcCli, BadInputIsOneLineExitTwoNothingWritten) {
  const fs::path dir = scratch_dir("ltc_cli");
  for (const std::string& args :
       {"bake ltc --out " + (dir / "a.npy").string() + " --size 1",
        "bake ltc --out " + (dir / "a.png").string(),
        "bake ltc --out " + (dir / "a.npy").string() + " --pixel-format rgba8",
        "bake ltc --out " + (dir / "no/a.npy").string(), "verify ltc " + (dir / "missing.npy").string(),
        "verify ltc " + (dir / "missing.npy").string() + " --points 0"}) {
    const auto r = run_cli(args, dir);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "a.npy") || fs::exists(dir / "a_amp.npy") || fs::exists(dir / "a.png"));
}
