// Micro-occlusion bake (render/texture_gen.h bake_visibility) against closed-form projected-solid-angle
// visibility about +z of piecewise-linear height fields the triangulation represents exactly:
//  flat = 1; a convex apex and a convex ridge/rim = 1 (no point of the field rises above them);
//  a point on a convex slope of angle β: (1 + cos β)/2 (the uphill half sees the tangent plane's horizon);
//  the bottom of a V-groove with walls at β: cos β (H(φ) = atan(tan β |cos φ|), (1/2π)∫cos²H dφ = cos β);
//  a wall at horizontal distance d with ray length R < its height: 1 − acos(q)/π + q √(1 − q²)/π, q = d/R.
// The bake resolves elevation exactly and integrates azimuth with N stratified directions, so the error is
// the azimuthal quadrature's (O(N⁻²) for these integrands, whose only kinks are in the derivative); the
// tolerances below are a few times that bound for the N used, far below the 0.1–0.25 biases of a bake that
// darkens convex points.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/render/texture_gen.h>
#include <support/texture_test_util.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <tuple>

using namespace msh;
using namespace msh::render;
using msh::test::depth_field;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// Ridge along y at x = 64 with slopes tan β down to a flat floor at |x − 64| = 32 (period 128 in x).
Texture ridge(double beta, double depth) {
  const double t = std::tan(beta);
  return depth_field(128, 4, depth, [t](int i, int) { return -t * std::min(std::abs(i - 64), 32); });
}

// Height of vertex (i, j) (wrapped) in texel units, and of the triangulated surface at (x, y): triangle
// (00, 10, 11) where fx ≥ fy, (00, 11, 01) otherwise. Written here independently of the bake.
double vertex_z(const Texture& f, double depth, int i, int j) {
  const int w = f.width(), h = f.height();
  return (double(f.at(((i % w) + w) % w, ((j % h) + h) % h, 0)) - 1) * depth;
}
double surface_z(const Texture& f, double depth, double x, double y) {
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const int i = int(fx0), j = int(fy0);
  const double fx = x - fx0, fy = y - fy0;
  const double a = vertex_z(f, depth, i, j), b = vertex_z(f, depth, i + 1, j),
               c = vertex_z(f, depth, i + 1, j + 1), d = vertex_z(f, depth, i, j + 1);
  return fx >= fy ? a + fx * (b - a) + fy * (c - b) : a + fy * (d - a) + fx * (c - d);
}

// A rough wrapping field: 0.5 + amp · sin(2π i/n) · wave(2π ky j/n) + 0.2 · uniform noise (LCG from seed).
Texture wavy_noisy_field(int n, uint32_t seed, double amp, int ky, bool cosine) {
  auto rnd = [&] {
    seed = seed * 1664525u + 1013904223u;
    return double(seed >> 8) * 0x1p-24;
  };
  Texture f(n, n, 1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double y = 2 * kPiD * ky * j / n;
      f.at(i, j, 0) =
          float(0.5 + amp * std::sin(2 * kPiD * i / n) * (cosine ? std::cos(y) : std::sin(y)) + 0.2 * rnd());
    }
  return f;
}

// The classified walks (bake_horizon_tangents with thresholds) against the exact ones on a rough wrapping
// field, unlimited and finite ray length: for every threshold τ, t < τ must agree with the exact tan H
// wherever the exact walk knows the side (it under-estimates tan² H by at most its 1e-4 tolerance: t_exact ≥
// τ means blocked, t_exact² + 1e-4 < τ² means lit), and t ≤ the exact horizon + float rounding (a lower
// bound).
TEST(VisibilityBake, ClassifiedHorizonsAgreeWithExactOnes) {
  const Texture f = wavy_noisy_field(32, 7, 0.3, 3, false);
  std::vector<Vec2f> dirs;
  std::vector<std::vector<double>> thr;
  for (int k = 0; k < 12; ++k) {
    const double phi = 2 * kPiD * (k + 0.5) / 12;
    dirs.emplace_back(float(std::cos(phi)), float(std::sin(phi)));
    std::vector<double> t;
    for (int e = 0; e < 16; ++e) t.push_back(std::tan((e + 0.5) / 16 * kPiD / 2 + 1e-3 * k));
    thr.push_back(t);
  }
  int decided = 0, blocked = 0;
  for (float R : {0.0f, 7.0f}) {
    const auto exact = bake_horizon_tangents(f, 6.0f, dirs, R);
    const auto cls = bake_horizon_tangents(f, 6.0f, dirs, R, thr);
    ASSERT_EQ(exact.size(), cls.size());
    for (std::size_t p = 0; p < exact.size(); ++p) {
      const std::size_t k = p % dirs.size();
      EXPECT_LE(cls[p], exact[p] * (1 + 1e-5f) + std::sqrt(1e-4f)) << p;
      for (double tau : thr[k]) {
        const double te = exact[p];
        if (te >= tau) {
          EXPECT_FALSE(cls[p] < tau) << "pixel-dir " << p << " tau " << tau << ": blocked, classified lit";
          ++decided, ++blocked;
        } else if (te * te + 1e-4 < tau * tau) {
          EXPECT_TRUE(cls[p] < tau) << "pixel-dir " << p << " tau " << tau << ": lit, classified blocked";
          ++decided;
        }
      }
    }
  }
  EXPECT_GT(decided, 20000);
  EXPECT_GT(blocked, 2000);  // the field is rough enough that both sides are exercised
  EXPECT_THROW(bake_horizon_tangents(f, 6.0f, dirs, 0.0f, {{1.0}}), InputError);  // one list per direction
  std::vector<std::vector<double>> unsorted = thr;
  unsorted[3] = {0.5, 0.2};
  EXPECT_THROW(bake_horizon_tangents(f, 6.0f, dirs, 0.0f, unsorted), InputError);
}

}  // namespace

TEST(VisibilityBake, FlatIsOne) {
  const Texture f = depth_field(32, 32, 4, [](int, int) { return -1.0; });
  for (float R : {8.0f, 0.0f}) {
    const Texture v = bake_visibility(f, 4, 16, R);
    for (int j = 0; j < 32; ++j)
      for (int i = 0; i < 32; ++i) ASSERT_EQ(v.at(i, j, 0), 1.0f);
  }
}

// Cone of slope 0.48 with flat outskirts: the apex sees nothing above it.
TEST(VisibilityBake, ConvexApexIsOne) {
  const double m = 0.48;
  const Texture f = depth_field(
      64, 64, 40, [m](int i, int j) { return -m * std::min(std::hypot(i - 32.0, j - 32.0), 24.0); });
  const Texture v = bake_visibility(f, 40, 64, 40);
  EXPECT_EQ(v.at(32, 32, 0), 1.0f);
  // Mid-slope of the triangulated cone: close to the tangent plane's (1 + cos β)/2; the triangle slopes
  // deviate from the cone's gradient by O(1/r), so only a loose check here (the ridge test is exact).
  EXPECT_NEAR(v.at(44, 32, 0), 0.5 * (1 + std::cos(std::atan(m))), 3e-3);
}

TEST(VisibilityBake, ConvexRidgeAndSlope) {
  for (double beta_deg : {20.0, 45.0, 70.0}) {
    const double beta = beta_deg * kPiD / 180;
    const Texture f = ridge(beta, 40);
    // Ray length 90: the neighbouring ridges (≥ 96 texels away where they rise above the slope point) are out
    // of reach, the own ridge and slope are in reach.
    const Texture v = bake_visibility(f, 40, 256, 90);
    EXPECT_EQ(v.at(64, 1, 0), 1.0f) << beta_deg;                                // convex ridge
    EXPECT_NEAR(v.at(48, 1, 0), 0.5 * (1 + std::cos(beta)), 2e-5) << beta_deg;  // slope, uphill at +x
    EXPECT_NEAR(v.at(80, 1, 0), 0.5 * (1 + std::cos(beta)), 2e-5) << beta_deg;  // slope, uphill at −x
    // Floor point 16 texels from both slopes, rays of 10 texels: nothing in reach.
    EXPECT_EQ(bake_visibility(f, 40, 16, 10).at(112, 1, 0), 1.0f) << beta_deg;
  }
}

// V-groove (walls at β, 10 texels deep-wide) in a flat plane: bottom cos β, convex rim 1.
TEST(VisibilityBake, VGrooveBottomAndRim) {
  for (double beta_deg : {30.0, 45.0, 60.0}) {
    const double t = std::tan(beta_deg * kPiD / 180);
    // Unlimited and short rays (the walls start at the bottom: same answer); width 65 × 7 (odd: no 2 × 2
    // block level, the cell-only walk) as well as 64 × 8.
    for (const auto& [w, h, R] :
         {std::tuple{64, 8, 0.0f}, std::tuple{64, 8, 6.0f}, std::tuple{65, 7, 0.0f}}) {
      const Texture f =
          depth_field(w, h, 100, [t](int i, int) { return -t * std::max(0, 10 - std::abs(i - 32)); });
      const Texture v = bake_visibility(f, 100, 128, R);
      EXPECT_NEAR(v.at(32, 3, 0), std::cos(beta_deg * kPiD / 180), 1e-5) << beta_deg << " R=" << R;
      EXPECT_EQ(v.at(22, 3, 0), 1.0f) << beta_deg;  // rim
      EXPECT_EQ(v.at(42, 3, 0), 1.0f) << beta_deg;
    }
  }
}

// A wall (a one-texel ramp 10⁵ texels high, unreachable) at horizontal distance d from a point on a flat
// floor, ray length R: blocked where the ray reaches the wall, R cos e cos φ ≥ d.
TEST(VisibilityBake, WallAtFiniteDistance) {
  const double H = 1e5;
  const Texture f = depth_field(256, 8, H, [H](int i, int) { return i >= 105 && i <= 200 ? 0.0 : -H; });
  for (double d : {1.0, 2.0, 4.0, 6.0}) {
    const double R = 8, q = d / R;
    const Texture v = bake_visibility(f, float(H), 512, float(R));
    const double expect = 1 - std::acos(q) / kPiD + q * std::sqrt(1 - q * q) / kPiD;
    // Extra tolerance: the ramp's finite slope moves the hit by ≤ R/H = 8e-5 texel.
    EXPECT_NEAR(v.at(int(104 - d), 3, 0), expect, 1e-4) << "d=" << d;
  }
}

TEST(VisibilityBake, ThreadIndependentAndBadInput) {
  const Texture f = depth_field(
      48, 40, 12, [](int i, int j) { return -6 - 5 * std::sin(0.4 * i) * std::cos(0.3 * j + 0.2 * i); });
  Texture a;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    a = bake_visibility(f, 12, 24, 10);
  }
  const Texture b = bake_visibility(f, 12, 24, 10);
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 48; ++i) ASSERT_EQ(a.at(i, j, 0), b.at(i, j, 0));
  EXPECT_THROW(bake_visibility(f, 12, 0, 10), InputError);
  EXPECT_THROW(bake_visibility(f, -1, 8, 10), InputError);
  EXPECT_THROW(bake_visibility(f, 12, 8, std::nanf("")), InputError);
}

// A rough random field (wrapping, steep in places) against a brute-force reference written independently:
// for 256 regular azimuths, the profile of the triangulated surface sampled every 0.01 texel up to the ray
// length, tan H = max min(Δz, √(R² − s²))/s. The bake's azimuths are rotated per texel, so the two differ by
// both quadratures (≈ 1e-5 at N = 256) plus the sampling's miss of a breakpoint (Δz error ≤ slope · 0.01).
TEST(VisibilityBake, RandomFieldMatchesBruteForce) {
  const int n = 24;
  const double depth = 5;
  const Texture f = wavy_noisy_field(n, 99, 0.25, 2, true);
  auto zv = [&](int i, int j) { return vertex_z(f, depth, i, j); };
  auto surf = [&](double x, double y) { return surface_z(f, depth, x, y); };
  for (double R : {6.0, 30.0}) {  // 30 > the period: the walk wraps
    const Texture v = bake_visibility(f, float(depth), 256, float(R));
    double max_err = 0, sum_err = 0;
    int count = 0;
    for (int j = 0; j < n; j += 3)
      for (int i = 0; i < n; i += 3) {
        const double z0 = zv(i, j);
        double vis = 0;
        const int M = 256;
        for (int k = 0; k < M; ++k) {
          const double phi = 2 * kPiD * (k + 0.5) / M, cx = std::cos(phi), sy = std::sin(phi);
          double T = 0;
          for (double s = 0.01; s <= R; s += 0.01) {
            const double dz = surf(i + cx * s, j + sy * s) - z0;
            T = std::max(T, std::min(dz, std::sqrt(std::max(R * R - s * s, 0.0))) / s);
          }
          vis += 1 / (1 + T * T);
        }
        vis /= M;
        const double e = v.at(i, j, 0) - vis;
        max_err = std::max(max_err, std::abs(e));
        sum_err += e;
        ++count;
      }
    EXPECT_LT(max_err, 1e-3) << "R=" << R;
    EXPECT_LT(std::abs(sum_err / count), 2e-4) << "R=" << R;
    std::printf("R=%g: max |bake - brute force| %.2e, mean %.2e over %d texels\n", R, max_err,
                sum_err / count, count);
  }
}

// ---- Profile scans (bake_horizon_tangents_profiles: bake_visibility's path for finite rays) ----

// The scans against the walks (which under-estimate tan² H by at most their 1e-4 tolerance and never
// over-estimate it) and an independent brute force (the triangulated surface sampled every 0.005 texel up to
// the ray length, tan H = max min(Δz, √(R² − s²))/s). Directions on the axes and the diagonals (coincident
// breakpoints: vertices on the line), steep and shallow ones, both signs; ray lengths short, longer than the
// period (the padding wraps more than once) and with the disc binding (depth ≫ R); a width that is not a
// multiple of the 8 lanes.
TEST(VisibilityBake, ProfileScansEqualWalksAndBruteForce) {
  std::vector<Vec2f> dirs;
  for (double deg : {0.0, 90.0, 180.0, 270.0, 45.0, 135.0, -45.0, 17.3, 101.7, 200.1, 291.4, 333.3})
    dirs.emplace_back(float(std::cos(deg * kPiD / 180)), float(std::sin(deg * kPiD / 180)));
  const int w = 29, h = 22;
  Texture f(w, h, 1);
  uint32_t seed = 4242u;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      seed = seed * 1664525u + 1013904223u;
      f.at(i, j, 0) = float(0.5 + 0.3 * std::sin(2 * kPiD * i / w) * std::cos(4 * kPiD * j / h) +
                            0.2 * double(seed >> 8) * 0x1p-24);
    }
  for (auto [depth, R] : {std::pair{7.0, 5.0}, std::pair{7.0, 40.0}, std::pair{60.0, 6.0}}) {
    const auto prof = bake_horizon_tangents_profiles(f, float(depth), dirs, float(R));
    const auto walk = bake_horizon_tangents(f, float(depth), dirs, float(R));
    ASSERT_EQ(prof.size(), walk.size());
    int raised = 0;
    for (std::size_t p = 0; p < prof.size(); ++p) {
      ASSERT_TRUE(std::isfinite(prof[p]) && prof[p] >= 0) << p;
      EXPECT_GE(prof[p], walk[p] * (1 - 1e-5f) - 1e-6f) << "vertex-dir " << p << " R=" << R;
      EXPECT_LE(double(prof[p]) * prof[p], double(walk[p]) * walk[p] + 1e-4 + 1e-5 * walk[p]) << p;
      raised += prof[p] > 0.05f;
    }
    EXPECT_GT(raised, int(prof.size()) / 4) << "R=" << R;
    double max_err = 0, g = 0;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        g = std::max({g, std::abs(vertex_z(f, depth, i + 1, j) - vertex_z(f, depth, i, j)),
                      std::abs(vertex_z(f, depth, i, j + 1) - vertex_z(f, depth, i, j))});
    for (std::size_t k = 0; k < dirs.size(); ++k)
      for (int j = 0; j < h; j += 5)
        for (int i = 0; i < w; i += 4) {
          const double z0 = vertex_z(f, depth, i, j);
          double T = 0;
          for (double s = 0.005; s <= R; s += 0.005) {
            const double dz = surface_z(f, depth, i + dirs[k].x * s, j + dirs[k].y * s) - z0;
            T = std::max(T, std::min(dz, std::sqrt(std::max(R * R - s * s, 0.0))) / s);
          }
          const float got = prof[(std::size_t(j) * w + i) * dirs.size() + k];
          // The samples lie on the surface, so T is a lower bound; it misses the maximiser by ≤ 0.0025 texel,
          // Δz by ≤ 0.0025 · √2 · g (g the steepest vertex-to-vertex rise), which is a loose guard here (the
          // walks above are the tight reference): ≤ 0.015 g in tan H wherever the maximiser is ≥ ¼ texel
          // out, and nearer it is the first piece, linear from the start and sampled exactly.
          EXPECT_GE(got, T - 1e-5) << i << "," << j << " dir " << k << " R=" << R;
          EXPECT_LE(got, T + 0.015 * g) << i << "," << j << " dir " << k << " R=" << R;
          max_err = std::max(max_err, std::abs(double(got) - T));
        }
    std::printf("depth %g R=%g: max |scan - brute force| %.2e\n", depth, R, max_err);
  }
  EXPECT_THROW(bake_horizon_tangents_profiles(f, 7.0f, dirs, 0.0f), InputError);  // unlimited: walks only
  EXPECT_THROW(bake_horizon_tangents_profiles(f, 7.0f, dirs, 1e6f), InputError);  // beyond the padding
  EXPECT_THROW(bake_horizon_tangents_profiles(f, 7.0f, {Vec2f(1, 1)}, 5.0f), InputError);
}

// ---- Lattice sweeps (bake_horizon_tangents_lattice) ----

// The sweep against two references: the exact walks along the same direction (which under-estimate tan² H by
// at most their 1e-4 tolerance and never over-estimate it), and an independent brute force (the profile of
// the triangulated surface sampled every 0.005 of a step over two periods of the line, where the horizon must
// lie; its miss of a breakpoint costs at most slope · 0.005 · |step| in Δz). On a square and a non-square
// rough field, steps on the axes, the diagonals and steep rational slopes, both signs.
TEST(LatticeSweep, EqualsExactWalksAndBruteForce) {
  const std::vector<LatticeStep> steps = {{1, 0},  {0, 1}, {-1, 0}, {0, -1}, {1, 1},  {-1, 1},
                                          {1, -1}, {2, 1}, {3, -2}, {-5, 3}, {1, -7}, {7, 4}};
  std::vector<Vec2f> dirs;
  for (const LatticeStep& s : steps) dirs.push_back(lattice_direction(s));
  for (auto [w, h] : {std::pair{32, 32}, std::pair{24, 40}}) {
    Texture f(w, h, 1);
    uint32_t seed = 12345u + uint32_t(w);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        seed = seed * 1664525u + 1013904223u;
        f.at(i, j, 0) = float(0.5 + 0.3 * std::sin(2 * kPiD * i / w) * std::cos(4 * kPiD * j / h) +
                              0.2 * double(seed >> 8) * 0x1p-24);
      }
    const double depth = 7;
    const auto sweep = bake_horizon_tangents_lattice(f, float(depth), steps);
    const auto walk = bake_horizon_tangents(f, float(depth), dirs, 0);
    ASSERT_EQ(sweep.size(), walk.size());
    int raised = 0;
    for (std::size_t p = 0; p < sweep.size(); ++p) {
      ASSERT_TRUE(std::isfinite(sweep[p]) && sweep[p] >= 0) << p;
      EXPECT_GE(sweep[p], walk[p] * (1 - 1e-5f) - 1e-6f) << "vertex-step " << p;
      EXPECT_LE(double(sweep[p]) * sweep[p], double(walk[p]) * walk[p] + 1e-4 + 1e-5 * walk[p]) << p;
      raised += sweep[p] > 0.05f;
    }
    EXPECT_GT(raised, int(sweep.size()) / 4);  // the field is rough enough for real horizons
    auto zv = [&](int i, int j) { return vertex_z(f, depth, i, j); };
    auto surf = [&](double x, double y) { return surface_z(f, depth, x, y); };
    double max_err = 0;
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const LatticeStep st = steps[k];
      const double len = std::hypot(double(st.p), double(st.q));
      const int period = std::lcm(w / std::gcd(w, std::abs(st.p)), h / std::gcd(h, std::abs(st.q)));
      for (int j = 1; j < h; j += 7)
        for (int i = 2; i < w; i += 5) {
          const double z0 = zv(i, j);
          double T = 0;
          for (double t = 0.005; t <= 2.0 * period; t += 0.005)
            T = std::max(T, (surf(i + t * st.p, j + t * st.q) - z0) / (t * len));
          const float got = sweep[(std::size_t(j) * w + i) * steps.size() + k];
          // Sampling misses a breakpoint by ≤ 0.0025 of a step on each side: Δz ≤ 2 · 0.0025 · |step| ·
          // slope.
          EXPECT_GE(got, T - 1e-6) << i << "," << j << " step " << st.p << "," << st.q;
          EXPECT_LE(got, T + 0.02) << i << "," << j << " step " << st.p << "," << st.q;
          max_err = std::max(max_err, std::abs(double(got) - T));
        }
    }
    std::printf("%dx%d: max |sweep - brute force| %.2e\n", w, h, max_err);
  }
}

TEST(LatticeSweep, ThreadIndependentAndBadInput) {
  const Texture f = depth_field(
      48, 40, 12, [](int i, int j) { return -6 - 5 * std::sin(0.4 * i) * std::cos(0.3 * j + 0.2 * i); });
  const auto steps = lattice_azimuths(32, 0.5);
  std::vector<float> a;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    a = bake_horizon_tangents_lattice(f, 12, steps);
  }
  EXPECT_EQ(a, bake_horizon_tangents_lattice(f, 12, steps));
  EXPECT_THROW(bake_horizon_tangents_lattice(f, 12, {{2, 4}}), InputError);
  EXPECT_THROW(bake_horizon_tangents_lattice(f, 12, {{0, 0}}), InputError);
  EXPECT_THROW(bake_horizon_tangents_lattice(f, -1, steps), InputError);
  EXPECT_THROW(bake_horizon_tangents_lattice(Texture(), 12, steps), InputError);
}

// The classified sweep (what the directional bake uses) against the tangents classified afterwards: the
// first threshold above tan H, per step and vertex, step-major; thresholds that the tangents hit exactly
// (so "above" must be strict), an empty list and a list with a NaN-free repeat.
TEST(LatticeSweep, ClassesEqualClassifiedTangents) {
  const Texture f = depth_field(
      48, 40, 12, [](int i, int j) { return -6 - 5 * std::sin(0.4 * i) * std::cos(0.3 * j + 0.2 * i); });
  const auto steps = lattice_azimuths(7, 0.5);
  const auto tan_h = bake_horizon_tangents_lattice(f, 12, steps);
  const std::size_t wh = 48 * 40, n = steps.size();
  std::vector<std::vector<double>> th(n);
  for (std::size_t k = 0; k < n; ++k)
    for (int e = 0; e < 16; ++e) th[k].push_back(std::tan((e + 0.5) / 16 * kPiD / 2) * (0.5 + 0.1 * k));
  th[1] = {double(tan_h[5 * n + 1]), double(tan_h[9 * n + 1]), 0.5, 0.5, 2.0};
  std::sort(th[1].begin(), th[1].end());
  th[2].clear();
  std::vector<uint8_t> classes;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    classes = bake_horizon_classes_lattice(f, 12, steps, th);
  }
  EXPECT_EQ(classes, bake_horizon_classes_lattice(f, 12, steps, th));
  ASSERT_EQ(classes.size(), wh * n);
  int lit_some = 0, lit_none = 0;
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t v = 0; v < wh; ++v) {
      std::size_t e = 0;
      while (e < th[k].size() && !(th[k][e] > double(tan_h[v * n + k]))) ++e;
      ASSERT_EQ(classes[k * wh + v], e) << "step " << k << " vertex " << v;
      lit_some += e > 0 && e < th[k].size(), lit_none += e == th[k].size() && !th[k].empty();
    }
  EXPECT_GT(lit_some, int(wh));  // the classes are not all the same
  EXPECT_GT(lit_none, 0);
  EXPECT_THROW(bake_horizon_classes_lattice(f, 12, steps, {}), InputError);
  EXPECT_THROW(bake_horizon_classes_lattice(f, 12, {{1, 0}}, {std::vector<double>(256, 1.0)}), InputError);
  EXPECT_THROW(bake_horizon_classes_lattice(f, 12, {{2, 4}}, {{1.0}}), InputError);
}

// Every azimuth within the tolerance of its uniform target, primitive, and of the smallest ring that has
// one (no step of smaller max(|p|, |q|) is within the tolerance).
TEST(LatticeSweep, LatticeAzimuthsNearUniform) {
  for (int n : {4, 16, 32, 64})
    for (double tol : {0.5, 0.1}) {
      const auto steps = lattice_azimuths(n, tol);
      ASSERT_EQ(int(steps.size()), n);
      for (int a = 0; a < n; ++a) {
        const LatticeStep s = steps[std::size_t(a)];
        const double phi = 2 * kPiD * (a + 0.5) / n;
        const double err = std::abs(std::remainder(lattice_azimuth(s) - phi, 2 * kPiD)) * 180 / kPiD;
        EXPECT_LE(err, tol) << n << " " << a;
        EXPECT_EQ(std::gcd(std::abs(s.p), std::abs(s.q)), 1);
        const int M = std::max(std::abs(s.p), std::abs(s.q));
        for (int p = -(M - 1); p < M; ++p)
          for (int q = -(M - 1); q < M; ++q) {
            if (!p && !q) continue;
            EXPECT_GT(std::abs(std::remainder(std::atan2(q, p) - phi, 2 * kPiD)) * 180 / kPiD, tol);
          }
        const Vec2f d = lattice_direction(s);
        EXPECT_NEAR(d.x * d.x + d.y * d.y, 1.0f, 1e-6f);
      }
    }
  // The far end of the domain stays fast (one O(1) test per ring) and within its tolerance.
  const auto fine = lattice_azimuths(4096, 0.01);
  ASSERT_EQ(fine.size(), 4096u);
  for (int a = 0; a < 4096; ++a)
    EXPECT_LE(std::abs(std::remainder(lattice_azimuth(fine[std::size_t(a)]) - 2 * kPiD * (a + 0.5) / 4096,
                                      2 * kPiD)) *
                  180 / kPiD,
              0.01)
        << a;
  EXPECT_THROW(lattice_azimuths(0, 0.5), InputError);
  EXPECT_THROW(lattice_azimuths(8, 0), InputError);
  EXPECT_THROW(lattice_azimuths(8, 50), InputError);
}
