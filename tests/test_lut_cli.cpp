// CLI tests for `microshadow bake micro-shadowing`: outputs, determinism across thread counts, the 2D LUT,
// and bad input (one-line error, exit code 2, no file left behind).
#include <gtest/gtest.h>
#include <microshadow/io/texture.h>
#include <microshadow/lut/micro_shadowing_loader.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

fs::path scratch() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  fs::path p = fs::path(MSH_BINARY_DIR) / "lut_cli_tmp" /
               (std::string(info->name()) + "." + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

struct CliResult {
  int code;
  std::string err;
};

CliResult run(const std::string& args, const fs::path& dir) {
  const fs::path err = dir / "stderr.txt";
  const std::string cmd =
      std::string(MSH_CLI_PATH) + " " + args + " > " + (dir / "stdout.txt").string() + " 2> " + err.string();
  const int status = std::system(cmd.c_str());
  std::ifstream in(err);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text};
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(LutCli, HelpExitsZero) {
  const fs::path d = scratch();
  EXPECT_EQ(run("bake micro-shadowing --help", d).code, 0);
  EXPECT_NE(slurp(d / "stdout.txt").find("--azimuth"), std::string::npos);
}

TEST(LutCli, BitIdenticalFilesForAnyThreadCount) {
  const fs::path d = scratch();
  const std::string common = " bake micro-shadowing --size 9 --samples 512 --phi-nodes 4 --quiet";
  for (const char* ext : {"npy", "dds", "exr"}) {
    ASSERT_EQ(run(common + " --threads 1 --out " + (d / (std::string("a.") + ext)).string(), d).code, 0);
    ASSERT_EQ(run(common + " --threads 2 --out " + (d / (std::string("b.") + ext)).string(), d).code, 0);
    EXPECT_EQ(slurp(d / (std::string("a.") + ext)), slurp(d / (std::string("b.") + ext))) << ext;
  }
  const msh::lut::MicroShadowingLut lut = msh::lut::load_micro_shadowing_lut(d / "a.npy");
  EXPECT_EQ(lut.volume.width, 9);
  EXPECT_EQ(lut.volume.depth, 9);
  EXPECT_EQ(lut.roughness, (std::vector<double>{0.1, 0.4, 0.7, 1.0}));
  EXPECT_TRUE(fs::exists(d / "a.dds.json"));
}

TEST(LutCli, TwoDAndAzimuthShapes) {
  const fs::path d = scratch();
  ASSERT_EQ(
      run("bake micro-shadowing --2d --size 8 --samples 256 --quiet --out " + (d / "t.npy").string(), d).code,
      0);
  EXPECT_EQ(msh::io::read_volume(d / "t.npy").depth, 1);
  ASSERT_EQ(run("bake micro-shadowing --azimuth --size 8 --samples 256 --quiet --roughness 0.3,0.9 --out " +
                    (d / "a.npy").string(),
                d)
                .code,
            0);
  const msh::lut::MicroShadowingLut lut = msh::lut::load_micro_shadowing_lut(d / "a.npy");
  EXPECT_EQ(lut.volume.depth, 24);
  EXPECT_EQ(lut.volume.channels, 2);
  EXPECT_EQ(lut.harmonics, 2);
  EXPECT_EQ(lut.view().n_nv, 8);
}

TEST(LutCli, BadInputIsOneLineExitTwoNoFile) {
  const fs::path d = scratch();
  const std::string out = (d / "x.npy").string();
  const std::string cases[] = {
      "--size 1 --out " + out,
      "--size-nl 1 --out " + out,
      "--size 4096 --out " + out,
      "--roughness nan --out " + out,
      "--roughness 0.5,0.4 --out " + out,
      "--roughness 0.1,1.5 --out " + out,
      "--samples 0 --out " + out,
      "--samples nan --out " + out,
      "--format bmp --out " + out,
      "--pixel-format rgb9e5 --out " + (d / "x.dds").string(),
      "--azimuth --pixel-format rgba8 --out " + (d / "x.dds").string(),
      "--roughness 0.1,0.5,0.9 --out " + (d / "x.dds").string(),
      "--out " + (d / "x.png").string(),
      "--out " + (d / "x.bmp").string(),
      "--out " + (d / "missing" / "x.npy").string(),
      "--phi-nodes 0 --out " + out,
      "--harmonics -2 --out " + out,
      "--threads -1 --out " + out,
  };
  for (const std::string& c : cases) {
    // Small and fast unless the case sets these itself (a repeated option would be its own error).
    std::string base = "bake micro-shadowing --quiet";
    if (c.find("--size ") == std::string::npos) base += " --size 4";
    if (c.find("--samples ") == std::string::npos) base += " --samples 64";
    const CliResult r = run(base + " " + c, d);
    EXPECT_EQ(r.code, 2) << c << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c << "\n" << r.err;
    for (const auto& e : fs::directory_iterator(d)) {
      const std::string name = e.path().filename().string();
      EXPECT_TRUE(name == "stdout.txt" || name == "stderr.txt") << c << " left " << name;
    }
  }
}

}  // namespace
