// Multiscale texture sets (render/multiscale.h): k = 1 is the identity; a normal map with a known slope
// variance widens the roughness by the closed form α'² = α² + var(b_x) + var(b_y); the coarse visibility mean
// equals the fine mean; the filtered normal is the renormalised mean; bad k throws.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/render/multiscale.h>
#include <support/texture_test_util.h>
#include <tbb/global_control.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

using namespace msh;
using namespace msh::render;

namespace {

// A small fine set with varied content (deterministic pseudo-random values).
TextureSet make_set(int n) {
  TextureSet s;
  s.depth_texels = 8;
  s.height = Texture(n, n, 1), s.normal = Texture(n, n, 3), s.roughness = Texture(n, n, 1);
  s.metallic = Texture(n, n, 1), s.base_color = Texture(n, n, 3), s.visibility = Texture(n, n, 1);
  uint32_t state = 12345;
  auto rnd = [&] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) * 0x1p-24f;
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      s.height.at(i, j, 0) = rnd();
      const Vec3f nn = normalize(Vec3f(rnd() - 0.5f, rnd() - 0.5f, 1.0f));
      for (int c = 0; c < 3; ++c) s.normal.at(i, j, c) = 0.5f * nn[c] + 0.5f;
      s.roughness.at(i, j, 0) = 0.2f + 0.6f * rnd();
      s.metallic.at(i, j, 0) = rnd() < 0.5f ? 0.0f : 1.0f;
      for (int c = 0; c < 3; ++c) s.base_color.at(i, j, c) = rnd();
      s.visibility.at(i, j, 0) = 0.5f + 0.5f * rnd();
    }
  return s;
}

using msh::test::same;

double mean(const Texture& t, int c = 0) {
  double s = 0;
  for (int j = 0; j < t.height(); ++j)
    for (int i = 0; i < t.width(); ++i) s += t.at(i, j, c);
  return s / (double(t.width()) * t.height());
}

}  // namespace

TEST(Multiscale, KOneIsTheIdentity) {
  const TextureSet f = make_set(16);
  for (CoarseRoughness m : {CoarseRoughness::Base, CoarseRoughness::Widened}) {
    const TextureSet c = downsample_texture_set(f, 1, m);
    EXPECT_TRUE(same(c.height, f.height) && same(c.normal, f.normal) && same(c.roughness, f.roughness) &&
                same(c.metallic, f.metallic) && same(c.base_color, f.base_color) &&
                same(c.visibility, f.visibility));
    EXPECT_EQ(c.depth_texels, f.depth_texels);
  }
}

TEST(Multiscale, BoxMeansAndVisibilityMeanPreserved) {
  const TextureSet f = make_set(64);
  for (int k : {2, 4, 16}) {
    const TextureSet c = downsample_texture_set(f, k, CoarseRoughness::Base);
    ASSERT_EQ(c.visibility.width(), 64 / k);
    EXPECT_EQ(c.depth_texels, 8.0f / float(k));
    // Each coarse V is the mean of its k × k fine texels (an independent sum here), so the global means agree
    // to float rounding of the stored coarse values (≤ 1 ulp each, relative 6e-8).
    EXPECT_NEAR(mean(c.visibility), mean(f.visibility), 2e-7) << k;
    EXPECT_NEAR(mean(c.height), mean(f.height), 2e-7) << k;
    EXPECT_NEAR(mean(c.base_color, 2), mean(f.base_color, 2), 2e-7) << k;
    EXPECT_NEAR(mean(c.roughness), mean(f.roughness), 2e-7) << k;
    double s = 0;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) s += f.visibility.at(k + i, 2 * k + j, 0);
    EXPECT_NEAR(c.visibility.at(1, 2, 0), s / (k * k), 1e-7) << k;
    // Filtered normal: the renormalised mean of the fine unit normals.
    Vec3d n(0, 0, 0);
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        Vec3d v(2.0 * f.normal.at(i, j, 0) - 1, 2.0 * f.normal.at(i, j, 1) - 1,
                2.0 * f.normal.at(i, j, 2) - 1);
        n += normalize(v);
      }
    n = normalize(n);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(c.normal.at(0, 0, ch), 0.5 * n[ch] + 0.5, 1e-6) << k;
  }
}

// Slopes b_x = ±s in a checkerboard (var b_x = s², b_y = 0), constant base roughness r: at k = 2 and 8 the
// widened roughness is sqrt(sqrt(α² + s²)), α = r²; Base keeps r; the filtered normal is +z.
TEST(Multiscale, KnownNormalVarianceWidensRoughness) {
  const int n = 32;
  TextureSet f = make_set(n);
  for (double s : {0.1, 0.5, 1.0}) {
    const double r = 0.4, a = r * r;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double sx = ((i + j) % 2 == 0 ? s : -s);
        const Vec3d nn = normalize(Vec3d(sx, 0, 1));  // slope −n_x/n_z = −sx
        for (int c = 0; c < 3; ++c) f.normal.at(i, j, c) = float(0.5 * nn[c] + 0.5);
        f.roughness.at(i, j, 0) = float(r);
      }
    for (int k : {2, 8}) {
      const TextureSet w = downsample_texture_set(f, k, CoarseRoughness::Widened);
      const TextureSet b = downsample_texture_set(f, k, CoarseRoughness::Base);
      const double expect = std::min(1.0, std::sqrt(std::sqrt(a * a + s * s)));
      // Tolerance: the normal map is stored in float (slopes to ~1e-7 relative).
      EXPECT_NEAR(w.roughness.at(1, 1, 0), expect, 2e-5) << s << " k=" << k;
      EXPECT_NEAR(b.roughness.at(1, 1, 0), r, 1e-6);
      EXPECT_NEAR(w.normal.at(2, 1, 2), 1.0, 1e-6);
    }
  }
  // Equal fine normals: Widened = Base.
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) f.normal.at(i, j, c) = c == 2 ? 1.0f : 0.5f;
  EXPECT_NEAR(downsample_texture_set(f, 4, CoarseRoughness::Widened).roughness.at(0, 0, 0), 0.4, 1e-6);
}

TEST(Multiscale, ThreadIndependentAndBadInput) {
  const TextureSet f = make_set(32);
  TextureSet a;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    a = downsample_texture_set(f, 4, CoarseRoughness::Widened);
  }
  const TextureSet b = downsample_texture_set(f, 4, CoarseRoughness::Widened);
  EXPECT_TRUE(same(a.roughness, b.roughness) && same(a.normal, b.normal) && same(a.visibility, b.visibility));
  EXPECT_THROW(downsample_texture_set(f, 0, CoarseRoughness::Base), InputError);
  EXPECT_THROW(downsample_texture_set(f, 3, CoarseRoughness::Base), InputError);
  TextureSet bad = f;
  bad.visibility = Texture(16, 16, 1);
  EXPECT_THROW(downsample_texture_set(bad, 2, CoarseRoughness::Base), InputError);
}

// What gen-material writes (render::write_texture_set_mips) is what the study shades: level log2 k of every
// map's float32 file equals the study's coarse set at scale k bit for bit, and the KTX2/DDS chains hold the
// same levels in their engine formats (8-bit UNORM within half a step; the directional channels within half a
// step of their per-channel range).
TEST(Multiscale, WrittenMipChainIsTheStudysCoarseSet) {
  msh::render::GenOptions o;
  o.kind = "bark";
  o.size = 32;
  o.ao_rays = 4;
  o.directional_azimuths = 8;
  const msh::render::TextureSet fine = msh::render::generate_texture_set(o);
  ASSERT_EQ(fine.directional.channels(), 9);
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "msh_test_mips_set";
  std::filesystem::remove_all(dir);
  msh::render::write_texture_set_mips(dir, fine);
  const auto chain = msh::render::texture_set_mip_chain(fine);
  ASSERT_EQ(chain.size(), 6u);  // 32, 16, 8, 4, 2, 1
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(dir / "mips" / "mips.json"));
  const std::vector<float> lo = j["directional"]["lo"], hi = j["directional"]["hi"];
  for (int L = 0; L < 6; ++L) {
    const msh::render::TextureSet c =
        L == 0 ? fine : msh::render::downsample_texture_set(fine, 1 << L, msh::render::CoarseRoughness::Base);
    const auto v = msh::io::read_volume(dir / "mips" / fmt::format("micro_occlusion_mip{}.npy", L));
    const auto v8 = msh::io::read_texture_level(dir / "mips" / "micro_occlusion.ktx2", L);
    ASSERT_EQ(v.width, c.visibility.width());
    for (int y = 0; y < v.height; ++y)
      for (int x = 0; x < v.width; ++x) {
        ASSERT_EQ(v.at(x, y, 0, 0), c.visibility.at(x, y, 0)) << L;
        ASSERT_NEAR(v8.at(x, y, 0, 0), c.visibility.at(x, y, 0), 0.5 / 255 + 1e-6) << L;
      }
    for (int f = 0; f < 3; ++f) {
      const auto d = msh::io::read_volume(dir / "mips" / fmt::format("directional_{}_mip{}.npy", f, L));
      const auto d8 = msh::io::read_texture_level(dir / "mips" / fmt::format("directional_{}.dds", f), L);
      for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x)
          for (int ch = 0; ch < d.channels; ++ch) {
            const int g = 4 * f + ch;
            ASSERT_EQ(d.at(x, y, 0, ch), c.directional.at(x, y, g)) << L << " " << g;
            const float dec =
                lo[std::size_t(g)] + (hi[std::size_t(g)] - lo[std::size_t(g)]) * d8.at(x, y, 0, ch);
            ASSERT_NEAR(dec, c.directional.at(x, y, g),
                        0.5 / 255 * (hi[std::size_t(g)] - lo[std::size_t(g)]) + 1e-6)
                << L << " " << g;
          }
    }
  }
  std::filesystem::remove_all(dir);
}
