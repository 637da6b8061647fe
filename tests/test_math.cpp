// Vector/frame helpers and the low-discrepancy sequences.
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>

#include <set>
#include <vector>

using namespace msh;

TEST(Frame, FromZIsOrthonormalEverywhere) {
  Pcg32 rng(7);
  for (int i = 0; i < 100000; ++i) {
    Vec3d n = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
    if (i == 0) n = {0, 0, -1};
    if (i == 1) n = {0, 0, 1};
    const Framed f = Framed::from_z(n);
    ASSERT_NEAR(dot(f.s, f.s), 1.0, 1e-12);
    ASSERT_NEAR(dot(f.t, f.t), 1.0, 1e-12);
    ASSERT_NEAR(dot(f.s, f.t), 0.0, 1e-12);
    ASSERT_NEAR(dot(f.s, n), 0.0, 1e-12);
    ASSERT_NEAR(dot(f.t, n), 0.0, 1e-12);
    // Right-handed: s × t = n.
    const Vec3d c = cross(f.s, f.t);
    ASSERT_NEAR(length(c - n), 0.0, 1e-12);
    const Vec3d w{0.3, -0.5, 0.81};
    const Vec3d back = f.to_world(f.to_local(w));
    ASSERT_NEAR(length(back - w), 0.0, 1e-12);
  }
}

TEST(Frame, FromZxKeepsTangentDirection) {
  const Vec3d n = normalize(Vec3d(0.1, 0.2, 1.0));
  const Framed f = Framed::from_zx(n, Vec3d(1, 0, 0));
  EXPECT_GT(f.s.x, 0.99);
  EXPECT_NEAR(dot(f.s, n), 0.0, 1e-15);
  // Degenerate tangent falls back to a valid frame.
  const Framed g = Framed::from_zx(n, n);
  EXPECT_NEAR(dot(g.s, n), 0.0, 1e-12);
  EXPECT_NEAR(length(g.s), 1.0, 1e-12);
}

TEST(Vec, NormalizeDegenerateReturnsFallback) {
  EXPECT_EQ(normalize(Vec3d(0, 0, 0)), Vec3d(0, 0, 1));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(normalize(Vec3d(nan, 0, 0)), Vec3d(0, 0, 1));
  EXPECT_EQ(saturate(nan), 0.0);
  EXPECT_EQ(safe_sqrt(-1e-17), 0.0);
}

// Every 2^k prefix of the 2D Sobol sequence (scrambled or not) is a (0,k,2)-net: each elementary interval
// of area 2^-k holds exactly one point. This is the property the micro-shadowing estimators rely on.
TEST(Sobol, PrefixesAreZeroNets) {
  for (uint32_t seed : {0u, 1u, 12345u}) {
    for (int k = 1; k <= 10; ++k) {
      const uint32_t n = 1u << k;
      for (int a = 0; a <= k; ++a) {
        const int b = k - a;
        std::set<std::pair<uint32_t, uint32_t>> cells;
        for (uint32_t i = 0; i < n; ++i) {
          const Vec2d p = sobol_2d<double>(i, seed);
          cells.insert({uint32_t(p.x * (1u << a)), uint32_t(p.y * (1u << b))});
        }
        ASSERT_EQ(cells.size(), n) << "seed " << seed << " k " << k << " a " << a;
      }
    }
  }
}

TEST(Sobol, DifferentSeedsDiffer) {
  EXPECT_NE(sobol_2d<double>(5, 1).x, sobol_2d<double>(5, 2).x);
  EXPECT_EQ(sobol_2d<double>(5, 3).x, sobol_2d<double>(5, 3).x);
}

// Sobol in 5 dimensions: the first points of Joe & Kuo's reference generator (Gray-code order, point g is
// natural point g ^ (g >> 1)), dims 0 and 1 equal the 2D sequence, and every dimension of every 2^k prefix
// (scrambled or not) is stratified into 2^k intervals.
TEST(Sobol, FiveDimensionsJoeKuo) {
  const double expected[6][5] = {{0, 0, 0, 0, 0},
                                 {0.5, 0.5, 0.5, 0.5, 0.5},
                                 {0.75, 0.25, 0.25, 0.25, 0.75},
                                 {0.25, 0.75, 0.75, 0.75, 0.25},
                                 {0.375, 0.375, 0.625, 0.875, 0.375},
                                 {0.875, 0.875, 0.125, 0.375, 0.875}};
  for (uint32_t g = 0; g < 6; ++g)
    for (int d = 0; d < kSobolMaxDims; ++d)
      EXPECT_EQ(u32_to_unit<double>(sobol_u32(g ^ (g >> 1), d)), expected[g][d]) << g << " " << d;
  for (uint32_t i = 0; i < 5000; ++i) {
    ASSERT_EQ(sobol_u32(i, 0), sobol_dim0(i));
    ASSERT_EQ(sobol_u32(i, 1), sobol_dim1(i));
  }
  // Scrambled indices use all 32 bits (sobol_dim1 reads byte tables there).
  for (uint32_t i = 0; i < 200000; ++i) {
    const uint32_t x = hash_u32(i);
    ASSERT_EQ(sobol_u32(x, 0), sobol_dim0(x));
    ASSERT_EQ(sobol_u32(x, 1), sobol_dim1(x));
  }
  for (uint32_t seed : {0u, 7u}) {
    for (int k = 1; k <= 12; ++k) {
      const uint32_t n = 1u << k;
      for (int d = 0; d < kSobolMaxDims; ++d) {
        std::set<uint32_t> cells;
        for (uint32_t i = 0; i < n; ++i) {
          const double x = seed ? sobol_scrambled<double>(i, d, seed) : u32_to_unit<double>(sobol_u32(i, d));
          ASSERT_GE(x, 0.0);
          ASSERT_LT(x, 1.0);
          cells.insert(uint32_t(x * n));
        }
        ASSERT_EQ(cells.size(), n) << "seed " << seed << " k " << k << " dim " << d;
      }
    }
  }
  EXPECT_NE(sobol_scrambled<double>(3, 2, 1), sobol_scrambled<double>(3, 2, 2));
}

TEST(Pcg32, UniformMeanAndRange) {
  Pcg32 rng(42);
  double sum = 0;
  for (int i = 0; i < 1000000; ++i) {
    const float f = rng.next_float();
    ASSERT_GE(f, 0.0f);
    ASSERT_LT(f, 1.0f);
    sum += f;
  }
  EXPECT_NEAR(sum / 1e6, 0.5, 1e-3);  // σ of the mean = 0.289/1000
  Pcg32 a(1), b(1);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(a.next_u32(), b.next_u32());
}

TEST(Warps, CosineHemisphereMean) {
  // E[cos θ] under cos θ/π is 2/3.
  double sum = 0;
  const int n = 1 << 16;
  for (int i = 0; i < n; ++i) sum += sample_cosine_hemisphere(sobol_2d<double>(i)).z;
  EXPECT_NEAR(sum / n, 2.0 / 3.0, 1e-4);
}
