// CLI tests of `gen-material --height FILE --depth D` (a user's height map baked into the procedural kinds'
// texture set) and `--kind gravel`: the outputs against closed forms (V-groove: bottom cos β, rim 1; the
// material.json depth), thread-count independence, and bad input (one error line, exit 2, no output).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <microshadow/io/texture.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/directional_codec.h>
#include <microshadow/render/texture_gen.h>
#include <support/cli_test_util.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using namespace msh;

namespace {

using Result = msh::test::CliResult;
Result run(const std::string& args) { return msh::test::run_cli(args); }

using msh::test::slurp;

const char* kFiles[] = {"basecolor.png",       "normal.png", "roughness.png", "metallic.png",
                        "micro_occlusion.png", "height.png", "material.json"};

class GenMaterialCli : public msh::test::ScratchDirTest {
 protected:
  GenMaterialCli() : ScratchDirTest("texture_gen_cli_tmp") {}
};

}  // namespace

// A 45° V-groove along y, 12 texels half-width, in a flat plane: 64 × 16 texels, depth D = 16 texels, so the
// groove (12 texels deep) spans h ∈ [0.25, 1].
TEST_F(GenMaterialCli, HeightMapGrooveMatchesClosedForm) {
  const double D = 16;
  io::Volume h(64, 16, 1, 1);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 64; ++i) h.at(i, j, 0, 0) = float(1 - std::max(0, 12 - std::abs(i - 32)) / D);
  io::write_png(dir / "groove.png", h, 16);
  const fs::path out = dir / "set";
  const Result r = run("gen-material --height " + (dir / "groove.png").string() +
                       " --depth 16 --ao-rays 64 --ao-distance 0 --threads 2 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : kFiles) EXPECT_TRUE(fs::exists(out / f)) << f;
  const auto j = nlohmann::json::parse(slurp(out / "material.json"));
  EXPECT_EQ(j["height_texels"].get<double>(), D);
  EXPECT_EQ(j["micro_occlusion"], "micro_occlusion.png");
  const io::Volume v = io::read_image(out / "micro_occlusion.png");
  ASSERT_EQ(v.width, 64);
  // 8-bit file: ± half a step (1/510) plus the bake's quadrature error (< 1e-4 at 64 azimuths here).
  EXPECT_NEAR(v.at(32, 5, 0, 0), std::cos(M_PI / 4), 0.5 / 255 + 1e-4);
  EXPECT_EQ(v.at(20, 5, 0, 0), 1.0f);  // convex rim
  EXPECT_EQ(v.at(5, 5, 0, 0), 1.0f);   // far plane (the rim is at the plane's height)
  // The normal map on the wall: (−dz/dx, 0, 1)/√2 for the wall descending towards +x, i.e. n_x = +1/√2.
  const io::Volume n = io::read_image(out / "normal.png");
  EXPECT_NEAR(n.at(26, 5, 0, 0), 0.5 + 0.5 / std::sqrt(2.0), 1.0 / 65535 + 1e-6);
  EXPECT_NEAR(n.at(26, 5, 0, 2), 0.5 + 0.5 / std::sqrt(2.0), 1.0 / 65535 + 1e-6);
  // The height round-trips bit for bit (16-bit in, 16-bit out).
  const io::Volume hh = io::read_image(out / "height.png");
  for (int i = 0; i < 64; ++i)
    ASSERT_EQ(hh.at(i, 3, 0, 0), io::read_image(dir / "groove.png").at(i, 3, 0, 0));
  // Same bytes with one thread.
  const fs::path out1 = dir / "set1";
  ASSERT_EQ(run("gen-material --height " + (dir / "groove.png").string() +
                " --depth 16 --ao-rays 64 --ao-distance 0 --threads 1 --out " + out1.string())
                .code,
            0);
  for (const char* f : kFiles) EXPECT_EQ(slurp(out / f), slurp(out1 / f)) << f;
}

TEST_F(GenMaterialCli, BadHeightInputExitsTwoWithOneLine) {
  io::Volume g(16, 16, 1, 1), c(16, 16, 1, 3);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) {
      g.at(i, j, 0, 0) = float(i) / 15;
      for (int k = 0; k < 3; ++k) c.at(i, j, 0, k) = float(k) / 3;
    }
  io::write_png(dir / "g16.png", g, 16);
  io::write_png(dir / "g8.png", g, 8);
  io::write_png(dir / "rgb.png", c, 16);
  std::ofstream(dir / "notes.txt") << "x";
  const std::string g16 = (dir / "g16.png").string();
  const std::pair<std::string, std::string> cases[] = {
      {"--height " + (dir / "missing.png").string() + " --depth 4", "not found"},
      {"--height " + g16, "--depth"},
      {"--height " + g16 + " --depth 0", "--depth"},
      {"--height " + g16 + " --depth -3", "--depth"},
      {"--height " + g16 + " --depth nan", "--depth"},
      {"--height " + g16 + " --depth 4 --kind bark", "exclusive"},
      {"--height " + g16 + " --depth 4 --size 64", "exclusive"},
      {"--height " + (dir / "g8.png").string() + " --depth 4", "16 bits"},
      {"--height " + (dir / "rgb.png").string() + " --depth 4", "not a grey image"},
      {"--height " + (dir / "notes.txt").string() + " --depth 4", "16-bit PNG or an EXR"},
  };
  for (const auto& [args, expect] : cases) {
    const fs::path out = dir / "out";
    const Result r = run("gen-material " + args + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find(expect), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out / "material.json")) << args;
  }
}

TEST_F(GenMaterialCli, GravelKind) {
  const fs::path out = dir / "gravel";
  const Result r = run("gen-material --kind gravel --size 32 --ao-rays 4 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : kFiles) EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_EQ(nlohmann::json::parse(slurp(out / "material.json"))["height_texels"].get<double>(), 1.0);
  EXPECT_EQ(run("gen-material --kind wood --out " + out.string()).code, 2);
}

// gen-material writes every map's mip chain (mips/: KTX2, DDS, each level as NPY; the directional channels
// with their 8-bit ranges), and --no-mips / --directional-azimuths 0 leave them out.
TEST_F(GenMaterialCli, WritesMipChains) {
  const fs::path out = dir / "mips";
  Result r =
      run("gen-material --kind bark --size 16 --ao-rays 4 --directional-azimuths 8 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "mips" / "mips.json"));
  EXPECT_EQ(j["levels"].get<int>(), 5);  // 16, 8, 4, 2, 1
  for (const char* m : {"normal", "roughness", "metallic", "micro_occlusion", "basecolor", "height",
                        "directional_0", "directional_1", "directional_2"}) {
    EXPECT_TRUE(fs::exists(out / "mips" / (std::string(m) + ".ktx2"))) << m;
    EXPECT_TRUE(fs::exists(out / "mips" / (std::string(m) + ".dds"))) << m;
    const io::Volume last = io::read_texture_level(out / "mips" / (std::string(m) + ".ktx2"), 4);
    EXPECT_EQ(last.width, 1) << m;
    EXPECT_TRUE(fs::exists(out / "mips" / (std::string(m) + "_mip4.npy"))) << m;
  }
  EXPECT_EQ(j["directional"]["lo"].size(), 9u);
  const fs::path bare = dir / "bare";
  r = run("gen-material --kind bark --size 16 --ao-rays 4 --directional-azimuths 0 --no-mips --out " +
          bare.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(bare / "mips"));
  EXPECT_EQ(run("gen-material --kind bark --size 16 --directional-azimuths 2 --out " + bare.string()).code,
            2);
  // 4 azimuths made NaN channels after writing six files; now refused before any work, nothing written.
  const fs::path four = dir / "four";
  r = run("gen-material --kind bark --size 16 --directional-azimuths 4 --out " + four.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("at least 5"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(four));

  // --directional-view: 21 channels in directional.npy (the 9 as without it, then the 12 slope channels),
  // six mip files (the last one R8), a renderer material that the directional-view method accepts.
  const fs::path view = dir / "view";
  r = run(
      "gen-material --kind bark --size 16 --ao-rays 4 --directional-azimuths 8 --directional-view --out " +
      view.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const render::Texture d9 = render::load_directional_channels(out / "directional.npy");
  const render::Texture d21 = render::load_directional_channels(view / "directional.npy");
  ASSERT_EQ(d21.channels(), 21);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x)
      for (int k = 0; k < 9; ++k) ASSERT_EQ(d21.at(x, y, k), d9.at(x, y, k));
  const nlohmann::json jv = nlohmann::json::parse(slurp(view / "mips" / "mips.json"));
  EXPECT_EQ(jv["directional"]["lo"].size(), 21u);
  for (int f = 0; f < 6; ++f)
    EXPECT_TRUE(fs::exists(view / "mips" / fmt::format("directional_{}.ktx2", f))) << f;
  EXPECT_FALSE(fs::exists(view / "mips" / "directional_6.ktx2"));
  const auto write_scene = [&](const fs::path& set, const std::string& name) {
    const std::string f = (dir / name).string();
    std::ofstream(f) << R"({"materials": {"m": {"height": ")" << (set / "height.png").string()
                     << R"(", "normal": ")" << (set / "normal.png").string()
                     << R"("}}, "objects": [{"type": "plane", "material": "m"}],
      "lights": [{"type": "directional", "elevation_deg": 20}], "settings": {"width": 8, "height": 8}})";
    return f;
  };
  r = run("render " + write_scene(view, "view.json") + " --method directional-view --out " +
          (dir / "v.png").string());
  EXPECT_EQ(r.code, 0) << r.err;
  // --directional-bc: the 21 channels also as BC5 pairs and a last BC4 (11 files, 10.5 bytes per texel),
  // whose every level decodes to what the study's --directional-encoding bc4 shades at that level.
  const fs::path bc = dir / "bc";
  r =
      run("gen-material --kind bark --size 16 --ao-rays 4 --directional-azimuths 8 --directional-view "
          "--directional-bc --out " +
          bc.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json jb = nlohmann::json::parse(slurp(bc / "mips" / "mips.json"));
  const render::Texture fine_bc = render::load_directional_channels(bc / "directional.npy");
  const render::ChannelRanges ranges = render::channel_ranges(fine_bc);
  const std::vector<render::Texture> mips = render::box_mip_chain(fine_bc);
  for (int f = 0; f < 11; ++f) {
    const std::string name = fmt::format("directional_bc_{}", f);
    EXPECT_EQ(jb["maps"][name]["format"], f < 10 ? "bc5" : "bc4") << f;
    for (const char* ext : {".ktx2", ".dds"})
      for (int L : {0, 1, 4}) {
        const io::Volume v = io::read_texture_level(bc / "mips" / (name + ext), L);
        render::Texture want = mips[std::size_t(L)];
        render::store_directional_channels(want, ranges, render::DirectionalEncoding::Bc4);
        for (int y = 0; y < v.height; ++y)
          for (int x = 0; x < v.width; ++x)
            for (int c = 0; c < v.channels; ++c) {
              const std::size_t k = std::size_t(2 * f + c);
              ASSERT_NEAR(ranges.lo[k] + (ranges.hi[k] - ranges.lo[k]) * v.at(x, y, 0, c),
                          want.at(x, y, int(k)), 1e-5f * (ranges.hi[k] - ranges.lo[k]))
                  << name << ext << " level " << L;
            }
      }
  }
  EXPECT_FALSE(fs::exists(bc / "mips" / "directional_bc_11.ktx2"));
  EXPECT_EQ(run("gen-material --kind bark --size 16 --directional-bc --no-mips --out " + bc.string()).code,
            2);

  // The 9-channel set is refused by the method that reads 21.
  r = run("render " + write_scene(out, "nine.json") + " --method directional-view --out " +
          (dir / "v9.png").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("21"), std::string::npos) << r.err;
}

// --directional-form pca<K>: the compact form's KTX2/DDS levels and level-0 PNGs decode, through mips.json's
// code alone (lo, hi, mean, basis), to the study's stored level of that form (render::store_through_codec of
// the box mean) within one float rounding, and close to the float channels; bad forms and combinations
// exit 2 before anything is written.
TEST_F(GenMaterialCli, WritesTheCompactForm) {
  const fs::path out = dir / "compact";
  Result r =
      run("gen-material --kind rock --size 32 --ao-rays 4 --directional-azimuths 8 --directional-view "
          "--directional-form pca6 --out " +
          out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "mips" / "mips.json"))["directional_compact"];
  ASSERT_EQ(j["coefficients"].get<int>(), 6);
  ASSERT_EQ(j["channels"].get<int>(), 21);
  ASSERT_EQ(j["textures"].size(), 2u);
  const render::Texture fine = render::load_directional_channels(out / "directional.npy");
  const render::DirectionalCodec codec = render::fit_directional_codec(fine, "pca6");
  const std::vector<render::Texture> chain = render::box_mip_chain(fine);
  for (int L : {0, 2, 5}) {
    const render::Texture want = render::store_through_codec(chain[std::size_t(L)], codec);
    for (const char* ext : {".ktx2", ".dds", ".png"}) {
      if (std::string(ext) == ".png" && L > 0) continue;
      std::vector<io::Volume> tex;
      for (int t = 0; t < 2; ++t) {
        const fs::path p = std::string(ext) == ".png"
                               ? out / fmt::format("directional_compact_{}.png", t)
                               : out / "mips" / fmt::format("directional_compact_{}{}", t, ext);
        tex.push_back(std::string(ext) == ".png" ? io::read_image(p) : io::read_texture_level(p, L));
        ASSERT_EQ(tex.back().width, want.width()) << p;
      }
      double worst = 0, scale = 0;
      for (int y = 0; y < want.height(); ++y)
        for (int x = 0; x < want.width(); ++x)
          for (int i = 0; i < 21; ++i) {
            double c = j["mean"][i].get<double>();
            for (int k = 0; k < 6; ++k) {
              const double lo = j["lo"][k], hi = j["hi"][k];
              c += j["basis"][i][k].get<double>() *
                   (lo + (hi - lo) * tex[std::size_t(k / 4)].at(x, y, 0, k % 4));
            }
            worst = std::max(worst, std::abs(c - want.at(x, y, i)));
            scale = std::max(scale, double(std::abs(want.at(x, y, i))));
          }
      EXPECT_LT(worst, 1e-4 * (1 + scale)) << ext << " level " << L;
    }
  }
  // Unused channels of the last texture are 0.
  EXPECT_EQ(io::read_texture_level(out / "mips" / "directional_compact_1.ktx2", 0).at(3, 3, 0, 3), 0.0f);
  for (const char* bad :
       {"--directional-form pca8x16", "--directional-form pca22", "--directional-form x",
        "--directional-form pca8 --no-mips", "--directional-form pca8 --directional-azimuths 0"}) {
    const fs::path o = dir / "bad";
    r = run(
        fmt::format("gen-material --kind rock --size 16 --directional-view {} --out {}", bad, o.string()));
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_FALSE(fs::exists(o)) << bad;
  }
}

// A rerun replaces the folder as a whole (issue 35, item 1): gen-material with the directional channels and
// their BC mips, then without them, leaves no directional.npy nor directional mips (71 files at 32², all
// left behind before), keeps a file of the user's, and reports what it removed.
TEST_F(GenMaterialCli, RerunLeavesNoStaleFiles) {
  const fs::path out = dir / "set";
  Result r =
      run("gen-material --kind plaster --size 32 --ao-rays 4 --directional-view --directional-bc --out " +
          out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(fs::exists(out / "directional.npy"));
  std::ofstream(out / "notes.txt") << "mine";
  r = run("gen-material --kind plaster --size 32 --ao-rays 4 --directional-azimuths 0 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(fs::exists(out / "directional.npy"));
  int directional_left = 0;
  for (const auto& e : fs::recursive_directory_iterator(out))
    directional_left += e.path().filename().string().find("directional") != std::string::npos;
  EXPECT_EQ(directional_left, 0);
  EXPECT_EQ(j["stale_removed"].size(), 71u);
  EXPECT_TRUE(fs::exists(out / "notes.txt"));
  EXPECT_TRUE(fs::exists(out / "mips" / "mips.json"));
  for (const char* f : kFiles) EXPECT_TRUE(fs::exists(out / f)) << f;
}

// `bake directional`: directional.json names one channel per NPY channel, 9 (the T basis) or 21 with --view
// (then G_x and G_y on the first 6 functions each; it named 27 before, the 9-function slope set).
TEST_F(GenMaterialCli, BakeDirectionalNamesEveryChannel) {
  io::Volume h(32, 32, 1, 1);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) h.at(i, j, 0, 0) = float(0.5 + 0.4 * std::sin(0.5 * i) * std::cos(0.4 * j));
  io::write_png(dir / "h.png", h, 16);
  for (const bool view : {false, true}) {
    const fs::path out = dir / (view ? "v" : "t");
    const Result r = run("bake directional " + (dir / "h.png").string() + " --depth 4 --azimuths 8 --out " +
                         out.string() + (view ? " --view" : ""));
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(out / "directional.json"));
    const io::Volume v = io::read_volume(out / "directional_mip0.npy");
    const std::size_t want = view ? 21 : 9;
    EXPECT_EQ(std::size_t(v.channels), want);
    ASSERT_EQ(j["channels"].size(), want);
    EXPECT_EQ(j["range_lo"].size(), want);
    EXPECT_EQ(j["channels"][8], "zz");
    if (view) {
      EXPECT_EQ(j["channels"][9], "gx:1");
      EXPECT_EQ(j["channels"][14], "gx:yz");
      EXPECT_EQ(j["channels"][15], "gy:1");
      EXPECT_EQ(j["channels"][20], "gy:yz");
    }
  }
}
