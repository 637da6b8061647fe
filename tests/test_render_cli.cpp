// CLI tests of `render`, `gen-material` and `compare`: bad input gives one error line naming the problem,
// exit code 2 and no output file; output is bit-identical whatever --threads is.
#include <gtest/gtest.h>
#include <microshadow/render/image.h>
#include <support/cli_test_util.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

using Result = msh::test::CliResult;
Result run(const std::string& args) { return msh::test::run_cli(args); }

// Runs the CLI and parses the JSON it prints on stdout (null if the command fails or prints no JSON).
nlohmann::json run_json(const std::string& args) {
  const fs::path out = fs::temp_directory_path() / "msh_render_cli_stdout.txt";
  const std::string cmd = std::string(MSH_CLI_PATH) + " " + args + " > " + out.string() + " 2> /dev/null";
  if (std::system(cmd.c_str()) != 0) return nullptr;
  std::ifstream in(out);
  return nlohmann::json::parse(in, nullptr, false);
}

using msh::test::slurp;

class RenderCli : public msh::test::ScratchDirTest {
 protected:
  RenderCli() : ScratchDirTest("render_cli_tmp") {}
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  }
  static std::string scene(const std::string& material, const std::string& extra_object = "") {
    return R"({"camera": {"eye": [0, -4, 1], "target": [0, 0, 0], "up": [0, 0, 1]},
      "materials": {"m": )" +
           material + R"(}, "objects": [{"type": "sphere", "material": "m"})" + extra_object + R"(],
      "lights": [{"type": "directional", "elevation_deg": 30}], "settings": {"width": 24, "height": 16}})";
  }
};

}  // namespace

TEST_F(RenderCli, BadInputExitsTwoWithOneLineAndNoOutput) {
  const std::string out = (dir / "out").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {write("malformed.json", "{\"materials\": ").string(), "malformed JSON"},
      {write("unknown_key.json", scene("{\"colour\": 1}")).string(), "colour"},
      {write("missing_tex.json", scene("{\"normal\": \"no_such.png\"}")).string(), "no_such.png"},
      {write("bad_obj.json", scene("{}", R"(, {"type": "obj", "file": "broken.obj", "material": "m"})"))
           .string(),
       "broken.obj"},
      {(dir / "does_not_exist.json").string(), "does_not_exist.json"}};
  write("broken.obj", "v 0 0 0\nf 1 2 3\n");
  for (const auto& [file, word] : cases) {
    const Result r = run("render " + file + " --out " + out);
    EXPECT_EQ(r.code, 2) << file << ": " << r.err;
    EXPECT_NE(r.err.find(word), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out + ".exr"));
    EXPECT_FALSE(fs::exists(out + ".png"));
  }
  const fs::path ok = write("ok.json", scene("{}"));
  for (const std::string& args : {std::string("--method magic"), std::string("--width 100000"),
                                  std::string("--bump-terminator sideways"), std::string("--spp 0")}) {
    const Result r = run("render " + ok.string() + " --out " + out + " " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out + ".exr")) << args;
  }
  EXPECT_EQ(run("render " + ok.string() + " --out " + (dir / "no_dir" / "x").string()).code, 2);
  EXPECT_EQ(run("gen-material --kind wood --out " + (dir / "mat").string()).code, 2);
  EXPECT_EQ(run("gen-material --size 100000 --out " + (dir / "mat").string()).code, 2);
  EXPECT_EQ(run("compare " + (dir / "a.exr").string() + " " + (dir / "b.exr").string()).code, 2);
  // The ground truth's depth comes from the texture set: a scene that contradicts material.json is refused.
  ASSERT_EQ(run("gen-material --size 16 --ao-rays 4 --out " + (dir / "mat").string()).code, 0);
  const std::string gt_mat = R"({"height": "mat/height.png", "height_texels": 99})";
  const Result gt = run("render " + write("gt_depth.json", scene(gt_mat)).string() + " --out " + out +
                        " --method ground-truth");
  EXPECT_EQ(gt.code, 2) << gt.err;
  EXPECT_NE(gt.err.find("material.json"), std::string::npos) << gt.err;
  EXPECT_EQ(std::count(gt.err.begin(), gt.err.end(), '\n'), 1) << gt.err;
  EXPECT_FALSE(fs::exists(out + ".exr"));
  EXPECT_EQ(run("render " + ok.string() + " --out " + out + " --component both").code, 2);
  // --std-error needs spp to be a multiple of the error batches (8).
  const Result se = run("render " + ok.string() + " --out " + out + " --std-error --spp 12");
  EXPECT_EQ(se.code, 2) << se.err;
  EXPECT_NE(se.err.find("error batches"), std::string::npos) << se.err;
  EXPECT_FALSE(fs::exists(out + ".exr"));
  ASSERT_EQ(
      run("render " + ok.string() + " --quiet --out " + out + " --std-error --spp 8 --component diffuse")
          .code,
      0);
  EXPECT_TRUE(fs::exists(out + "_stderr.exr"));
  fs::remove(out + ".exr"), fs::remove(out + ".png"), fs::remove(out + "_stderr.exr");
  EXPECT_EQ(run("render --help").code, 0);
  EXPECT_EQ(run("gen-material --help").code, 0);
}

TEST_F(RenderCli, OutputIndependentOfThreadCount) {
  const fs::path s = write("s.json", scene(R"({"base_color": [0.6, 0.4, 0.3], "micro_occlusion": 0.5})"));
  const std::string a = (dir / "a").string(), b = (dir / "b").string();
  ASSERT_EQ(
      run("render " + s.string() + " --quiet --spp 3 --method chan-2018,generic-vndf --threads 1 --out " + a)
          .code,
      0);
  ASSERT_EQ(
      run("render " + s.string() + " --quiet --spp 3 --method chan-2018,generic-vndf --threads 2 --out " + b)
          .code,
      0);
  for (const char* m : {"_chan-2018.exr", "_generic-vndf.exr", "_chan-2018.png"}) {
    const std::string x = slurp(a + m), y = slurp(b + m);
    EXPECT_FALSE(x.empty()) << m;
    EXPECT_EQ(x, y) << m;
  }
  // compare: identical images give RMSE 0 and SSIM 1; the diff PNG is written.
  const nlohmann::json j =
      run_json("compare " + a + "_chan-2018.exr " + b + "_chan-2018.exr --diff " + (dir / "d.png").string());
  ASSERT_TRUE(j.is_object()) << j;
  EXPECT_EQ(j.at("rmse").get<double>(), 0.0) << j;
  EXPECT_EQ(j.at("ssim").get<double>(), 1.0) << j;
  EXPECT_TRUE(fs::exists(dir / "d.png"));
}

TEST_F(RenderCli, CompareConstantImagesGivesKnownErrors) {
  // Two constant grey images, 0.25 and 0.75 (exact in half and float EXR): every channel differs by 0.5, so
  // RMSE = 0.5. SSIM of constant images has no variance terms: (2 a b + C1) / (a² + b² + C1), C1 = 0.01²,
  // with a, b the display (sRGB-encoded, IEC 61966-2-1) luminances of the two greys.
  msh::render::Image a(40, 30), b(40, 30);
  for (auto& p : a.px) p = msh::Rgbf(0.25f);
  for (auto& p : b.px) p = msh::Rgbf(0.75f);
  msh::render::write_exr(dir / "a.exr", a);
  msh::render::write_exr(dir / "b.exr", b);
  const nlohmann::json j =
      run_json("compare " + (dir / "a.exr").string() + " " + (dir / "b.exr").string() + " --downsample 2");
  ASSERT_TRUE(j.is_object()) << j;
  EXPECT_NEAR(j.at("rmse").get<double>(), 0.5, 1e-7) << j;
  EXPECT_NEAR(j.at("rmse_downsampled").get<double>(), 0.5, 1e-7) << j;
  const double sa = 1.055 * std::pow(0.25, 1 / 2.4) - 0.055, sb = 1.055 * std::pow(0.75, 1 / 2.4) - 0.055;
  const double c1 = 1e-4, expect = (2 * sa * sb + c1) / (sa * sa + sb * sb + c1);
  EXPECT_NEAR(j.at("ssim").get<double>(), expect, 1e-5) << j;
  EXPECT_NEAR(j.at("ssim_downsampled").get<double>(), expect, 1e-5) << j;
  // Symmetric in A and B.
  const nlohmann::json k = run_json("compare " + (dir / "b.exr").string() + " " + (dir / "a.exr").string());
  ASSERT_TRUE(k.is_object()) << k;
  EXPECT_NEAR(k.at("rmse").get<double>(), 0.5, 1e-7) << k;
}
