// `microshadow filter` end to end: PNG in, per-mip roughness PNGs out matching the library; bad input → exit
// 2 and no output file.
#include <gtest/gtest.h>
#include <microshadow/filter/runtime/mip_chain.h>
#include <microshadow/io/texture.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

namespace fs = std::filesystem;
using namespace msh;

namespace {

int run(const std::string& args) {
  const std::string cmd = std::string(MSH_CLI_PATH) + " " + args + " > /dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::path(MSH_BINARY_DIR) / "test_filter_cli" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(FilterCli, WritesMipsMatchingTheLibrary) {
  const fs::path d = scratch("ok");
  const int W = 32;
  io::Volume n(W, W, 1, 3);
  std::mt19937 rng(5);
  std::normal_distribution<float> nd(0.0f, 0.15f);
  for (int y = 0; y < W; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec3f v = normalize(Vec3f(nd(rng), nd(rng), 1.0f));
      n.at(x, y, 0, 0) = 0.5f * v.x + 0.5f, n.at(x, y, 0, 1) = 0.5f * v.y + 0.5f,
                    n.at(x, y, 0, 2) = 0.5f * v.z + 0.5f;
    }
  io::write_png(d / "n.png", n, 16);
  io::Volume r(W, W, 1, 1);
  for (size_t i = 0; i < r.data.size(); ++i) r.data[i] = 0.25f + 0.5f * float(i % 7) / 7.0f;
  io::write_png(d / "r.png", r, 16);

  ASSERT_EQ(run("filter --normal " + (d / "n.png").string() + " --roughness " + (d / "r.png").string() +
                " --out " + (d / "out").string() + "/ --method variance"),
            0);
  // The library on the same (re-read, quantized) inputs.
  const io::Volume nin = io::read_image(d / "n.png"), rin = io::read_image(d / "r.png");
  std::vector<Vec3f> nv(size_t(W) * W);
  std::vector<float> rv(size_t(W) * W);
  for (int y = 0; y < W; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + size_t(x);
      nv[i] = Vec3f(2 * nin.at(x, y, 0, 0) - 1, 2 * nin.at(x, y, 0, 1) - 1, 2 * nin.at(x, y, 0, 2) - 1);
      rv[i] = rin.at(x, y, 0, 0);
    }
  const auto mips = filter::build_roughness_mips(W, W, nv, rv, filter::FilterMethod::Variance);
  ASSERT_EQ(mips.size(), 6u);
  for (size_t k = 0; k < mips.size(); ++k) {
    const fs::path p = d / "out" / ("roughness_mip" + std::to_string(k) + ".png");
    ASSERT_TRUE(fs::exists(p)) << p;
    const io::Volume img = io::read_image(p);
    ASSERT_EQ(img.width, mips[k].width);
    for (size_t i = 0; i < img.data.size(); ++i)
      EXPECT_NEAR(img.data[i], mips[k].roughness[i], 1.0 / 65535 + 1e-7);
  }
  // Prefix naming and lean (3 channels: r_x, r_y, 0), limited levels.
  ASSERT_EQ(run("filter --normal " + (d / "n.png").string() + " --roughness-value 0.4 --out " +
                (d / "pre").string() + " --method lean --levels 2"),
            0);
  EXPECT_TRUE(fs::exists(d / "pre_mip1.png"));
  EXPECT_FALSE(fs::exists(d / "pre_mip2.png"));
  EXPECT_EQ(io::read_image(d / "pre_mip0.png").channels, 3);
}

TEST(FilterCli, BadInputExitsTwoWithoutOutput) {
  const fs::path d = scratch("bad");
  io::Volume n(4, 4, 1, 3);
  for (auto& x : n.data) x = 0.5f;
  io::write_png(d / "n.png", n, 8);
  io::Volume r(3, 3, 1, 1);
  io::write_png(d / "r3.png", r, 8);
  const std::string N = " --normal " + (d / "n.png").string();
  EXPECT_EQ(run("filter" + N + " --roughness " + (d / "r3.png").string() + " --out " + (d / "a").string()),
            2);
  EXPECT_EQ(run("filter" + N + " --roughness-value 1.5 --out " + (d / "b").string()), 2);
  EXPECT_EQ(run("filter" + N + " --roughness-value nan --out " + (d / "c").string()), 2);
  EXPECT_EQ(run("filter" + N + " --roughness-value 0.5 --method blur --out " + (d / "e").string()), 2);
  EXPECT_EQ(run("filter" + N + " --out " + (d / "f").string()), 2);  // no roughness
  EXPECT_EQ(run("filter --normal " + (d / "missing.png").string() + " --roughness-value 0.5 --out " +
                (d / "g").string()),
            2);
  EXPECT_EQ(run("filter --normal " + (d / "r3.png").string() + " --roughness-value 0.5 --out " +
                (d / "h").string()),
            2);
  for (const char* p :
       {"a_mip0.png", "b_mip0.png", "c_mip0.png", "e_mip0.png", "f_mip0.png", "g_mip0.png", "h_mip0.png"})
    EXPECT_FALSE(fs::exists(d / p)) << p;
  EXPECT_EQ(run("filter --help"), 0);
}
