// CLI tests of `microshadow study --height FILE[,FILE…] --depth D[,D…]` and `--material DIR`: rows named
// by the file's stem or the folder, gen-material's relief kinds (rock, brick, cobble) studied from their
// folders, and every bad input (missing or unreadable file, 8-bit map, wrong depth count, non-positive depth,
// a size the scales do not divide or narrower than a footprint, a view or azimuth out of its range, a folder
// without material.json) is one error line, exit 2, before any work (no output directory).
#include <gtest/gtest.h>
#include <microshadow/io/texture.h>
#include <support/cli_test_util.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace fs = std::filesystem;
using namespace msh;

namespace {

class StudyCli : public msh::test::ScratchDirTest {
 protected:
  StudyCli() : ScratchDirTest("study_cli_tmp") {}
  msh::test::CliResult run(const std::string& args) { return msh::test::run_cli(args, dir); }
  std::string map(const std::string& name, int size, int bits = 16) {
    io::Volume v(size, size, 1, 1);
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i)
        v.at(i, j, 0, 0) = float(0.5 + 0.5 * std::sin(0.4 * i) * std::cos(0.3 * j));
    io::write_png(dir / name, v, bits);
    return (dir / name).string();
  }
  // A fast study around the user's maps: one light, two terms, small images.
  std::string tiny() const {
    return " --quick --shapes plane --scales 1,4 --image-size 16 --methods none,ao --gt-max-spp 32 --quiet "
           "--threads 2 --out " +
           (dir / "out").string();
  }
};

}  // namespace

TEST_F(StudyCli, BadUserMapsAreOneErrorLineExit2) {
  const std::string a = map("a.png", 64), b = map("b.png", 64), c8 = map("c8.png", 64, 8),
                    small = map("s.png", 48);
  fs::create_directories(dir / "nojson");
  const std::string cases[] = {
      "--height " + (dir / "missing.png").string() + " --depth 4",  // missing file
      "--height " + c8 + " --depth 4",                              // 8-bit PNG
      "--height " + a + "," + b + " --depth 4,5,6",                 // wrong depth count
      "--height " + a + " --depth 0",                               // non-positive depth
      "--height " + a + " --depth -2",
      "--height " + a,                                   // no depth
      "--depth 4",                                       // no map
      "--height " + a + "," + a + " --depth 4",          // the same name twice
      "--height " + small + " --depth 4 --scales 1,32",  // 32 does not divide 48
      "--height " + a + " --depth 4 --scales 1,32",      // 2 coarse texels: narrower than a footprint
      "--height " + a + " --depth 4 --views 95",         // a view past grazing
      "--height " + a + " --depth 4 --views 30,x",       // not a number
      "--height " + a + " --depth 4 --view-azimuths 400",
      "--height " + a + " --depth 4 --light-azimuths nan",
      "--height " + a + " --depth 4 --light-elevations 0",
      "--height " + a + " --depth 4 --sweep --no-sweep",
      "--material " + (dir / "nojson").string(),  // no material.json
      "--material " + (dir / "nowhere").string(),
      "--height " + a + " --depth 4 --directional-encoding bc7",  // not a storage
      // the cache inside the output folder (a warm cache is read, not written: the folder's replacement
      // would remove it)
      "--height " + a + " --depth 4 --material-cache " + (dir / "out" / "cache").string(),
  };
  for (const std::string& args : cases) {
    std::string full = "study " + args + " --image-size 16 --quiet --out " + (dir / "out").string();
    if (args.find("--scales") == std::string::npos) full += " --scales 1,4";
    const auto r = run(full);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("error"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out")) << args;
  }
}

// A good user map (and a gen-material folder): rows named after the stem (the folder), exit 0.
TEST_F(StudyCli, UserMapRowsCarryTheStem) {
  const std::string a = map("my_rock.png", 64);
  fs::create_directories(dir / "paving");
  fs::copy_file(a, dir / "paving" / "height.png");
  std::ofstream(dir / "paving" / "material.json") << R"({"height": "height.png", "height_texels": 3})";
  const auto r = run("study --height " + a + " --depth 4 --material " + (dir / "paving").string() + tiny());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(msh::test::slurp(dir / "out" / "results.json"));
  EXPECT_EQ(j["config"]["materials"], nlohmann::json::array({"my_rock", "paving"}));
  std::set<std::string> names;
  for (const auto& row : j["rows"]) names.insert(row["material"].get<std::string>());
  EXPECT_EQ(names, (std::set<std::string>{"my_rock", "paving"}));
}

// gen-material's relief kinds report their mean baked V, and their folders go straight into the study
// (--material repeated): the user's path from a baked set to a ranking.
TEST_F(StudyCli, GenMaterialFoldersIntoTheStudy) {
  for (const char* kind : {"rock", "brick", "cobble"}) {
    const auto g = run(std::string("gen-material --kind ") + kind +
                       " --size 64 --ao-rays 8 --threads 2 --out " + (dir / kind).string());
    ASSERT_EQ(g.code, 0) << g.err;
    const auto j = nlohmann::json::parse(g.out);
    EXPECT_GT(j["mean_visibility"].get<double>(), 0.7) << kind;
    EXPECT_LT(j["mean_visibility"].get<double>(), 0.95) << kind;
  }
  const auto r = run("study --material " + (dir / "rock").string() + "," + (dir / "brick").string() +
                     " --material " + (dir / "cobble").string() + tiny());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(msh::test::slurp(dir / "out" / "results.json"));
  EXPECT_EQ(j["config"]["materials"], nlohmann::json::array({"rock", "brick", "cobble"}));
  EXPECT_EQ(j["config"]["user_materials"][0]["depth_texels"].get<double>(), 4.0);  // 16 × 64 / 256
}

// Views and azimuths from the command line: the rows carry them, and the summary has a table per view.
TEST_F(StudyCli, ViewsAndAzimuthsReachTheRows) {
  const std::string a = map("my_rock.png", 64);
  const auto r = run(
      "study --height " + a +
      " --depth 4 --views 30,75 --view-azimuths 270,0 --light-azimuths 45 --light-elevations 20" + tiny());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(msh::test::slurp(dir / "out" / "results.json"));
  std::set<std::pair<double, double>> views;
  for (const auto& row : j["rows"]) {
    views.insert({row["view"].get<double>(), row["view_azimuth"].get<double>()});
    if (row["light_type"] != "directional") continue;  // --quick's sphere light
    EXPECT_EQ(row["azimuth"].get<double>(), 45);
    EXPECT_EQ(row["elevation"].get<double>(), 20);
  }
  EXPECT_EQ(views, (std::set<std::pair<double, double>>{{30, 270}, {30, 0}, {75, 270}, {75, 0}}));
  const std::string md = msh::test::slurp(dir / "out" / "summary.md");
  EXPECT_NE(md.find("By view"), std::string::npos);
  EXPECT_NE(md.find("75° / 0°"), std::string::npos);
  EXPECT_NE(msh::test::slurp(dir / "out" / "results.csv").find("view,view_azimuth"), std::string::npos);
}

// A study of the user's own maps without --quick uses the small default set: the shipped terms and those
// they are judged against, the directional lights and the near point light, the Bias stopping rule.
TEST_F(StudyCli, UserMapsGetTheSmallDefaultSet) {
  const std::string a = map("my_rock.png", 64);
  const auto r = run("study --height " + a + " --depth 4 --scales 1,4 --image-size 16 --threads 2 --out " +
                     (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("ETA"), std::string::npos) << r.err;  // progress with an ETA on stderr
  const auto j = nlohmann::json::parse(msh::test::slurp(dir / "out" / "results.json"));
  EXPECT_EQ(j["config"]["name"], "user");
  EXPECT_EQ(j["config"]["terms"],
            nlohmann::json::array({"none", "ao", "directional-view", "diffuse-aware-alu+lut3d"}));
  EXPECT_EQ(j["config"]["gt_rule"], "bias");
  std::set<std::string> lights;
  for (const auto& g : j["ground_truth"]) lights.insert(g["light"].get<std::string>());
  EXPECT_EQ(lights.size(), 12u);  // 5 elevations × 2 azimuths, point-near, sphere-near
  EXPECT_TRUE(lights.count("point-near"));
}

// --scales sets the view sweep's scales too: `--sweep --scales 4` renders the sweep at k = 4 only (its
// default is k = 1–64).
TEST_F(StudyCli, ScalesSetTheSweepsScales) {
  const std::string a = map("my_rock.png", 64);
  const auto r = run("study --height " + a +
                     " --depth 4 --sweep --quick --shapes plane --scales 4 --image-size 16 --methods none,ao "
                     "--gt-max-spp 32 --quiet --threads 2 --out " +
                     (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(msh::test::slurp(dir / "out" / "results.json"));
  EXPECT_EQ(j["config"]["sweep"]["scales"], nlohmann::json::array({4})) << j["config"]["sweep"].dump();
  std::set<int> sweep_scales;
  for (const auto& row : j["rows"])
    if (row["grid"] == "sweep") sweep_scales.insert(row["scale"].get<int>());
  EXPECT_EQ(sweep_scales, std::set<int>{4});
}
