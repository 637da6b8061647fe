// `eval brdf`, `bake ggx-albedo`, `bake dfg`: values equal the library's, bad input exits 2 with one line and
// no file, baked files read back with the documented axes and channels.
#include <gtest/gtest.h>
#include <microshadow/bsdf/multiscatter.h>
#include <microshadow/bsdf/runtime/albedo.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/io/texture.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

using namespace msh;
using namespace msh::bsdf;
namespace fs = std::filesystem;

namespace {

struct CliRun {
  int rc;
  std::string out, err;
};

CliRun cli(const std::string& args) {
  static int counter = 0;
  const fs::path errp =
      fs::path(MSH_BINARY_DIR) / ("test_bsdf_cli_err_" + std::to_string(counter++) + ".txt");
  const std::string cmd = std::string(MSH_CLI_PATH) + " " + args + " 2>" + errp.string();
  FILE* p = popen(cmd.c_str(), "r");
  CliRun r{-1, "", ""};
  if (!p) return r;
  char buf[4096];
  while (fgets(buf, sizeof buf, p)) r.out += buf;
  const int st = pclose(p);
  r.rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  FILE* e = fopen(errp.string().c_str(), "r");
  if (e) {
    while (fgets(buf, sizeof buf, e)) r.err += buf;
    fclose(e);
  }
  fs::remove(errp);
  return r;
}

fs::path tmpdir() {
  const fs::path d = fs::path(MSH_BINARY_DIR) / "test_bsdf_cli_out";
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(BrdfCli, AlbedoExampleMatchesLibrary) {
  const CliRun r = cli("eval brdf --model ggx --roughness 0.7 --fresnel none --albedo --ndotv 0.5 --json");
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const ModelInfo& info = find_brdf_model("ggx");
  BrdfParams p;
  p.values = {{"roughness", {0.7}}, {"fresnel", {0.0}}};
  const auto m = info.make(complete_params(info, p));
  EXPECT_EQ(j["albedo"][0].get<double>(), directional_albedo(*m, 0.5).r);
  EXPECT_EQ(j["params"]["fresnel"], "none");
  // Independent sanity: the shipped table at the same point (bilinear, r = 0.7 between texels).
  EXPECT_NEAR(j["albedo"][1].get<double>(), ggx_E(0.5, 0.7), 2e-3);
}

TEST(BrdfCli, ValueMatchesLibrary) {
  const CliRun r = cli(
      "eval brdf --model oren-nayar --sigma 0.3 --rho 0.2,0.4,0.6 --ndotv 0.8 --light 0.3,0.1,0.9 --json");
  ASSERT_EQ(r.rc, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const ModelInfo& info = find_brdf_model("oren-nayar");
  BrdfParams p;
  p.values = {{"sigma", {0.3}}, {"rho", {0.2, 0.4, 0.6}}};
  const auto m = info.make(complete_params(info, p));
  const Vec3d wo(std::sqrt(1 - 0.64), 0, 0.8);
  const Rgbd f = m->f(wo, normalize(Vec3d(0.3, 0.1, 0.9)));
  EXPECT_EQ(j["value"][2].get<double>(), f.b);
  EXPECT_EQ(j["value"][0].get<double>(), f.r);
}

TEST(BrdfCli, BadInputExitsTwoWithOneLine) {
  const char* bad[] = {"eval brdf --model nope --ndotv 0.5",
                       "eval brdf --model ggx --ndotv 1.5",
                       "eval brdf --model ggx --ndotv nan",
                       "eval brdf --model ggx --roughness nan",
                       "eval brdf --model beckmann --roughness nan",
                       "eval microfacet --alpha nan",
                       "eval microfacet --ndf beckmann --alpha 0.3 --alpha-y nan",
                       "eval microfacet --ndf gtr --alpha 0.3 --gamma nan",
                       "eval brdf --model ggx --roughness 2",
                       "eval brdf --model ggx --fresnel fancy",
                       "eval brdf --model lambert --roughness 0.5",
                       "eval brdf --model lambert --rho 1,2",
                       "eval brdf --model ggx --light 0,0,0",
                       "eval brdf --model ggx --f0 abc",
                       "eval brdf --ndotv 0.5",
                       "bake dfg --out x.txt",
                       "bake dfg --variant nope --out x.npy",
                       "bake dfg --size 1 --out x.npy",
                       "bake dfg --out x.png",  // a table is not an image
                       "bake ggx-albedo --out x.png",
                       "bake ggx-albedo --out x.npy --format png",
                       "bake ggx-albedo --out x.npy --format gif"};
  for (const char* a : bad) {
    const CliRun r = cli(a);
    EXPECT_EQ(r.rc, 2) << a << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << a << "\n" << r.err;
  }
  // Unwritable output: exit 2, no file.
  const fs::path target = tmpdir() / "missing_dir" / "dfg.npy";
  const CliRun r = cli("bake dfg --size 4 --samples 16 --out " + target.string());
  EXPECT_EQ(r.rc, 2);
  EXPECT_FALSE(fs::exists(target));
  EXPECT_EQ(cli("eval brdf --help").rc, 0);
  EXPECT_EQ(cli("bake dfg --help").rc, 0);
  EXPECT_EQ(cli("bake ggx-albedo --help").rc, 0);
  EXPECT_EQ(cli("eval brdf --list --json").rc, 0);
}

TEST(BrdfCli, BakedTablesHaveDocumentedLayout) {
  const fs::path d = tmpdir();
  // ggx-albedo, 4 channels (E, Ē, E_Fc, Ē_Fc): texel (i, j) at μ = i/(n−1), r = j/(n−1) is the reference.
  ASSERT_EQ(
      cli("bake ggx-albedo --size 8 --samples 256 --pixel-format rgba32f --out " + (d / "e.npy").string()).rc,
      0);
  const io::Volume e = io::read_volume(d / "e.npy");
  ASSERT_EQ(e.width, 8);
  ASSERT_EQ(e.height, 8);
  ASSERT_EQ(e.channels, 4);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      const Vec2d ref = ggx_dfg_reference(i / 7.0, j / 7.0, 256);
      EXPECT_EQ(e.at(i, j, 0, 0), float(ref.y));
      EXPECT_EQ(e.at(i, j, 0, 2), float(ref.x));
      EXPECT_EQ(e.at(i, j, 0, 1), e.at(0, j, 0, 1));  // Ē(r) constant along x
    }
  EXPECT_NEAR(e.at(0, 7, 0, 1), ggx_E_avg(1.0), 2e-3);
  // dfg split-sum (scale, bias) vs multiscatter (x, y): scale + bias = y, bias = x; α = 0 row (y = 0 texels).
  ASSERT_EQ(cli("bake dfg --size 16 --samples 1024 --pixel-format rg32f --out " + (d / "a.npy").string()).rc,
            0);
  ASSERT_EQ(cli("bake dfg --size 16 --samples 1024 --pixel-format rg32f --variant multiscatter --out " +
                (d / "b.npy").string())
                .rc,
            0);
  const io::Volume a = io::read_volume(d / "a.npy"), b = io::read_volume(d / "b.npy");
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) {
      EXPECT_NEAR(a.at(i, j, 0, 0) + a.at(i, j, 0, 1), b.at(i, j, 0, 1), 1e-6);
      EXPECT_EQ(a.at(i, j, 0, 1), b.at(i, j, 0, 0));
    }
  for (int i = 0; i < 16; ++i) {
    const double mu = i / 15.0;
    EXPECT_NEAR(b.at(i, 0, 0, 0), std::pow(1 - mu, 5), 1e-6);
    EXPECT_NEAR(b.at(i, 0, 0, 1), 1.0, 1e-6);
  }
  // RG16F DDS for engines.
  EXPECT_EQ(cli("bake dfg --size 8 --samples 64 --out " + (d / "dfg.dds").string()).rc, 0);
  EXPECT_TRUE(fs::exists(d / "dfg.dds"));
  // --format overrides the extension: the same table as the .npy above, written as NPY under another name.
  ASSERT_EQ(cli("bake dfg --size 16 --samples 1024 --pixel-format rg32f --format npy --out " +
                (d / "a.table").string())
                .rc,
            0);
  const auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(bytes(d / "a.table"), bytes(d / "a.npy"));
}
