// `microshadow plot brdf-spheres` and `eval brdf` for the extra models: output written, values agree with the
// library, bad input → exit 2 and no file.
#include <gtest/gtest.h>
#include <microshadow/io/texture.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;

namespace {
int run(const std::string& args) {
  const int rc = std::system((std::string(MSH_CLI_PATH) + " " + args + " > /dev/null 2>&1").c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}
}  // namespace

TEST(BrdfSpheresCli, WritesGridAndRejectsBadInput) {
  const fs::path d = fs::path(MSH_BINARY_DIR) / "test_bsdf_cloth_cli";
  fs::remove_all(d);
  fs::create_directories(d);
  ASSERT_EQ(
      run("plot brdf-spheres --size 16 --out " + (d / "ok.png").string() +
          " --row velvet-cloth:alpha=0.2,0.5 --row imageworks-sheen:roughness=0.5,0.7,0.9:sheen-color=1,0,0"),
      0);
  const auto img = msh::io::read_image(d / "ok.png");
  EXPECT_EQ(img.width, 48);
  EXPECT_EQ(img.height, 32);
  // Sheen colour (1,0,0): the second row has no green anywhere on the spheres (background is grey 0.02).
  float max_g = 0;
  for (int y = 16; y < 32; ++y)
    for (int x = 0; x < 48; ++x) max_g = std::max(max_g, img.at(x, y, 0, 1));
  EXPECT_LT(max_g, 0.2f);
  EXPECT_EQ(run("plot brdf-spheres --out " + (d / "a.png").string() + " --row nosuch:alpha=1"), 2);
  EXPECT_EQ(run("plot brdf-spheres --out " + (d / "b.png").string() + " --row velvet-cloth:alpha=5"), 2);
  EXPECT_EQ(run("plot brdf-spheres --out " + (d / "c.png").string() + " --row velvet-cloth:alpha=x"), 2);
  EXPECT_EQ(run("plot brdf-spheres --out " + (d / "e.png").string() + " --row velvet-cloth:bogus=1"), 2);
  for (const char* f : {"a.png", "b.png", "c.png", "e.png"}) EXPECT_FALSE(fs::exists(d / f)) << f;
  EXPECT_EQ(run("eval brdf --model thin-film --thickness 2500"), 2);
  EXPECT_EQ(run("eval brdf --model clearcoat --coat-ior 1.5 --ndotv 0.5"), 0);
}
