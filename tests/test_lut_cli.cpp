// CLI tests for `microshadow bake micro-shadowing`: outputs, determinism across thread counts, both layouts,
// sidecar round trips for every format, the 2D LUT, and bad input (one-line error, exit code 2, no file left
// behind), also for tables read back (bad layout names, mismatched sidecars, truncated files).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <microshadow/io/texture.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/math/sampling.h>
#include <support/cli_test_util.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

fs::path scratch() { return msh::test::scratch_dir("lut_cli_tmp"); }

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

using msh::test::slurp;

TEST(LutCli, HelpExitsZero) {
  const fs::path d = scratch();
  EXPECT_EQ(run("bake micro-shadowing --help", d).code, 0);
  EXPECT_NE(slurp(d / "stdout.txt").find("--azimuth"), std::string::npos);
}

TEST(LutCli, BitIdenticalFilesForAnyThreadCount) {
  const fs::path d = scratch();
  const std::string common =
      " bake micro-shadowing --layout seed --size 9 --samples 512 --phi-nodes 4 --quiet";
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

// Progress on stderr at tenths of the work, increasing, ending at 100% (a tenth may be passed over when
// workers report out of order); nothing with --quiet.
TEST(LutCli, ProgressInTenthsUnlessQuiet) {
  const fs::path d = scratch();
  const std::string bake = "bake micro-shadowing --layout seed --size 6 --samples 64 --phi-nodes 3 --out " +
                           (d / "p.npy").string();
  const CliResult loud = run(bake, d);
  ASSERT_EQ(loud.code, 0) << loud.err;
  std::istringstream lines(loud.err);
  int last = 0, count = 0;
  for (std::string line; std::getline(lines, line); ++count) {
    int p = -1;
    ASSERT_EQ(std::sscanf(line.c_str(), "microshadow: baking micro-shadowing LUT: %d%%", &p), 1) << line;
    EXPECT_EQ(p % 10, 0) << line;
    EXPECT_GT(p, last) << loud.err;
    last = p;
  }
  EXPECT_EQ(last, 100) << loud.err;
  EXPECT_GE(count, 5) << loud.err;  // 24 tasks: at most a few tenths passed over
  const CliResult quiet = run(bake + " --quiet", d);
  ASSERT_EQ(quiet.code, 0);
  EXPECT_EQ(quiet.err, "");
}

TEST(LutCli, TwoDAndAzimuthShapes) {
  const fs::path d = scratch();
  ASSERT_EQ(run("bake micro-shadowing --layout seed --2d --size 8 --samples 256 --quiet --out " +
                    (d / "t.npy").string(),
                d)
                .code,
            0);
  EXPECT_EQ(msh::io::read_volume(d / "t.npy").depth, 1);
  ASSERT_EQ(run("bake micro-shadowing --layout seed --azimuth --size 8 --samples 256 --quiet --roughness "
                "0.3,0.9 --out " +
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
      "--layout seed --size 1 --out " + out,
      "--size-nl 1 --out " + out,
      "--layout seed --size 4096 --out " + out,
      "--layout seed --roughness nan --out " + out,
      "--layout seed --roughness 0.5,0.4 --out " + out,
      "--layout seed --roughness 0.1,1.5 --out " + out,
      "--layout seed --roughness 0.1,0.5,0.9 --out " + (d / "x.dds").string(),
      "--layout bogus --out " + out,
      "--layout SEED --out " + out,
      "--size 8 --out " + out,                  // cone layout: --size-t etc.
      "--roughness 0.1,0.5 --out " + out,       // cone layout: slabs, not channels
      "--layout seed --size-t 8 --out " + out,  // seed layout: no t axis
      "--roughness-slabs 1 --out " + out,
      "--roughness-range 0.5,0.2 --out " + out,
      "--roughness-range 0,1 --out " + out,
      "--roughness-range 0.1 --out " + out,
      "--harmonics 4 --out " + out,  // cone layout: a_0..a_3
      "--size-t 1 --out " + out,
      "--samples 0 --out " + out,
      "--samples nan --out " + out,
      "--format bmp --out " + out,
      "--pixel-format rgb9e5 --out " + (d / "x.dds").string(),
      "--azimuth --pixel-format rgba8 --out " + (d / "x.dds").string(),
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
    const bool seed = c.find("--layout seed") != std::string::npos;
    if (seed && c.find("--size ") == std::string::npos && c.find("--size-t") == std::string::npos)
      base += " --size 4";
    if (!seed && c.find("--size") == std::string::npos)
      base += " --size-t 4 --size-nl 3 --size-nv 3 --roughness-slabs 2";
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

// Both layouts, every file format and pixel format: bake → file + sidecar → load_micro_shadowing_lut gives
// the layout, the metadata and the in-process bake's texels (within the pixel format's rounding), and the
// loaded view samples like the in-process one at random continuous inputs.
TEST(LutCli, SidecarRoundTripBothLayoutsEveryFormat) {
  namespace lut = msh::lut;
  const fs::path d = scratch();
  struct Layout {
    const char* args;
    lut::BakeOptions o;
  };
  lut::BakeOptions cone = lut::default_bake_options(lut::LutLayout::Cone);
  cone.n_vis = 6, cone.n_nl = 5, cone.n_nv = 3, cone.n_rough = 3, cone.samples = 64, cone.phi_nodes = 3;
  lut::BakeOptions cone_az = cone;
  cone_az.harmonics = 3;
  lut::BakeOptions seed = lut::default_bake_options(lut::LutLayout::Seed);
  seed.n_vis = seed.n_nl = seed.n_nv = 5, seed.samples = 64, seed.phi_nodes = 3;
  const std::string cone_args =
      " --size-t 6 --size-nl 5 --size-nv 3 --roughness-slabs 3 --samples 64 --phi-nodes 3";
  const Layout layouts[] = {
      {"", cone}, {" --azimuth", cone_az}, {" --layout seed --size 5 --samples 64 --phi-nodes 3", seed}};
  int checked = 0;
  for (int li = 0; li < 3; ++li) {
    const Layout& L = layouts[li];
    const bool is_cone = L.o.layout == lut::LutLayout::Cone;
    const msh::io::Volume ref = lut::bake_micro_shadowing_lut(L.o);
    for (const std::string fmt : {"npy", "dds", "ktx2", "exr"})
      for (const std::string pf : {"rgba16f", "rgba32f", "rgba8"}) {
        if (fmt == "npy" && pf != "rgba32f") continue;     // NPY is always float32
        if (L.o.harmonics > 0 && pf == "rgba8") continue;  // signed coefficients: rejected (tested below)
        const fs::path f = d / fmt::format("t{}_{}.{}", li, pf, fmt);
        // fmt::format rather than a chain of operator+ (GCC 12 reports a false -Wrestrict on the chain).
        const std::string args = fmt::format("bake micro-shadowing --quiet{}{} --pixel-format {} --out {}",
                                             is_cone ? cone_args : "", L.args, pf, f.string());
        ASSERT_EQ(run(args, d).code, 0) << args;
        const lut::MicroShadowingLut t = lut::load_micro_shadowing_lut(f);
        EXPECT_EQ(t.layout, L.o.layout) << f;
        EXPECT_EQ(t.harmonics, L.o.harmonics) << f;
        EXPECT_EQ(t.volume.width, ref.width);
        EXPECT_EQ(t.volume.height, ref.height);
        EXPECT_EQ(t.volume.depth, ref.depth);
        if (is_cone) {
          EXPECT_EQ(t.n_rough, L.o.n_rough);
          EXPECT_EQ(t.cone.warp_scale, L.o.cone.warp_scale);
          EXPECT_EQ(t.cone.roughness_min, L.o.cone.roughness_min);
        } else {
          EXPECT_EQ(t.roughness, L.o.roughness);
        }
        // The storage rounding docs/lut.md states: rgba8 ≤ 0.5/255 (+ float slack); rgba16f round to nearest,
        // ≤ half an ulp = 2⁻¹¹ |value| (≤ 2.4e-4 below 1; the azimuth coefficients may exceed 1), 2⁻²⁵ for
        // subnormals; rgba32f exact. e: the largest error beyond its own bound (≤ 0).
        double e = 0;
        for (std::size_t i = 0; i < ref.texel_count(); ++i)
          for (int c = 0; c < ref.channels; ++c) {
            const double want = ref.data[i * ref.channels + c],
                         got = t.volume.data[i * t.volume.channels + c];
            const double tol = pf == "rgba8" ? 0.5 / 255 + 1e-6
                               : pf == "rgba16f"
                                   ? std::max(std::ldexp(std::abs(want), -11), std::ldexp(1.0, -25))
                                   : 0.0;
            e = std::max(e, std::abs(got - want) - tol);
          }
        EXPECT_LE(e, 0.0) << f;
        // Per stored value, for |values| < 2 (the largest coefficient magnitude): rgba16f half an ulp ≤ 2⁻¹⁰.
        const double value_tol =
            pf == "rgba8" ? 0.5 / 255 + 1e-6 : (pf == "rgba16f" ? std::ldexp(1.0, -10) : 0.0);
        // Sampling through the loaded view vs the in-process view, off the texels.
        const lut::MicroShadowingLutView va = t.view();
        const lut::MicroShadowingLutView vb =
            is_cone ? lut::make_cone_view(ref, L.o.n_rough, L.o.harmonics, L.o.cone)
                    : lut::make_view(ref, L.o.roughness, L.o.harmonics);
        msh::Pcg32 rng(5);
        for (int k = 0; k < 200; ++k) {
          const float V = float(rng.next_double()), nl = float(rng.next_double()),
                      nv = float(rng.next_double());
          const float r = float(0.1 + 0.9 * rng.next_double()), cphi = float(2 * rng.next_double() - 1);
          EXPECT_NEAR(lut::sample_micro_shadowing_azimuth(va, V, nl, nv, r, cphi),
                      lut::sample_micro_shadowing_azimuth(vb, V, nl, nv, r, cphi), 4 * value_tol + 1e-6);
        }
        ++checked;
      }
  }
  EXPECT_EQ(checked, 10 + 7 + 10);  // 10 per layout, no rgba8 for the azimuth-aware table
}

// Tables read back by a command (eval --method lut3d --lut FILE): bad layout names, mismatched or broken
// sidecars, truncated files → one line on stderr, exit 2.
TEST(LutCli, BadTablesAndSidecarsExitTwo) {
  const fs::path d = scratch();
  const fs::path a = d / "a.dds", b = d / "b.dds";
  ASSERT_EQ(
      run("bake micro-shadowing --quiet --size-t 6 --size-nl 5 --size-nv 3 --roughness-slabs 3 --samples "
          "64 --phi-nodes 3 --out " +
              a.string(),
          d)
          .code,
      0);
  ASSERT_EQ(run("bake micro-shadowing --quiet --layout seed --size 5 --samples 64 --phi-nodes 3 --out " +
                    b.string(),
                d)
                .code,
            0);
  const std::string eval =
      "eval micro-shadowing --method lut3d --visibility 0.7 --ndotl 0.6 --ndotv 0.4 --lut ";
  ASSERT_EQ(run(eval + a.string(), d).code, 0);
  ASSERT_EQ(run(eval + b.string(), d).code, 0);
  const std::string side_a = slurp(fs::path(a.string() + ".json")),
                    side_b = slurp(fs::path(b.string() + ".json"));
  auto write = [](const fs::path& p, const std::string& text) {
    fs::remove(p);
    std::ofstream(p, std::ios::binary) << text;
  };
  auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
    return s;
  };
  const fs::path c = d / "c.dds", cs = fs::path(c.string() + ".json");
  const std::string table_a = slurp(a), table_b = slurp(b);
  struct Case {
    std::string what, table, sidecar;
  };
  const Case cases[] = {
      {"bad layout name", table_a, replace(side_a, "\"layout\": \"cone\"", "\"layout\": \"conic\"")},
      {"seed sidecar next to a cone table", table_a, side_b},
      {"cone sidecar next to a seed table", table_b, side_a},
      {"sidecar sizes differ", table_a, replace(side_a, "\"size_t\": 6", "\"size_t\": 7")},
      {"slabs do not divide the depth", table_a,
       replace(side_a, "\"roughness_slabs\": 3", "\"roughness_slabs\": 2")},
      {"missing field", table_a, replace(side_a, "\"warp_scale\"", "\"warp_scalx\"")},
      {"bad warp", table_a, replace(side_a, "\"nl_warp\": 4", "\"nl_warp\": 9")},
      {"not JSON", table_a, "{ layout: "},
      {"truncated table", table_a.substr(0, table_a.size() / 2), side_a},
      {"truncated header", table_a.substr(0, 60), side_a},
      {"empty table", "", side_a},
  };
  for (const Case& k : cases) {
    write(c, k.table);
    write(cs, k.sidecar);
    const CliResult r = run(eval + c.string(), d);
    EXPECT_EQ(r.code, 2) << k.what << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << k.what << "\n" << r.err;
  }
  // A cone table without its sidecar cannot be read as a seed table silently: 1 channel, no roughness.
  fs::remove(cs);
  write(c, table_a);
  const CliResult r = run(eval + c.string(), d);
  EXPECT_EQ(r.code, 2) << r.err;
  // --phi with a plain table: refused (the harmonics are not there), with an azimuth-aware table: used.
  EXPECT_EQ(run(eval + a.string() + " --phi 1.0", d).code, 2);
  const fs::path az = d / "az.npy";
  ASSERT_EQ(
      run("bake micro-shadowing --quiet --azimuth --size-t 6 --size-nl 5 --size-nv 3 --roughness-slabs 3 "
          "--samples 64 --phi-nodes 3 --out " +
              az.string(),
          d)
          .code,
      0);
  EXPECT_EQ(run(eval + az.string() + " --phi 1.0", d).code, 0);
}

}  // namespace
