// Normal/roughness filtering (RTR4 §9.13.1): Toksvig 9.76 and its GGX mapping, LEAN/CLEAN moments, variance
// mapping, and the mip-chain builder on normal maps of known slope variance (expected roughness per mip from
// the sample-variance formula σ²(1 − 1/N), N = texels per footprint).
#include <gtest/gtest.h>
#include <microshadow/filter/blend.h>
#include <microshadow/filter/lean.h>
#include <microshadow/filter/runtime/mip_chain.h>
#include <microshadow/filter/toksvig.h>
#include <microshadow/filter/variance_mapping.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <tbb/global_control.h>

#include <random>

using namespace msh;
using namespace msh::filter;

namespace {

// A normal map whose slopes (−n_x/n_z, −n_y/n_z) are i.i.d. Gaussian with per-axis std sx, sy.
std::vector<Vec3f> gaussian_slope_normals(int w, int h, double sx, double sy, uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  std::vector<Vec3f> out(size_t(w) * size_t(h));
  for (auto& n : out) {
    const double bx = sx * nd(rng), by = sy * nd(rng);
    n = Vec3f(normalize(Vec3d(-bx, -by, 1.0)));
  }
  return out;
}

double mean_alpha2(const MipLevel& lv, int channel) {
  double s = 0;
  const size_t n = size_t(lv.width) * size_t(lv.height);
  for (size_t i = 0; i < n; ++i)
    s += std::pow(double(lv.roughness[i * size_t(lv.channels) + size_t(channel)]), 4.0);
  return s / double(n);
}

}  // namespace

TEST(Toksvig, Equation976) {
  EXPECT_NEAR(toksvig_exponent(100.0, 0.9), 0.9 * 100 / (0.9 + 100 * 0.1), 1e-12);
  EXPECT_EQ(toksvig_exponent(50.0, 1.0), 50.0);  // unit-length average: unchanged
  EXPECT_EQ(toksvig_exponent(50.0, 0.0), 0.0);
  // Walter et al. mapping round trip and its anchor α = 1 ↔ α_p = 0.
  for (double a : {0.01, 0.1, 0.5, 1.0})
    EXPECT_NEAR(alpha_from_blinn_phong_exponent(blinn_phong_exponent_from_alpha(a)), a, 1e-12);
  EXPECT_NEAR(blinn_phong_exponent_from_alpha(1.0), 0.0, 1e-15);
  EXPECT_NEAR(toksvig_ggx_alpha(0.3, 1.0), 0.3, 1e-12);
  // Small-angle form: α'² ≈ α² + 2σ² with σ² = (1 − |n̄|)/|n̄| (from α_p ≈ 2/α²).
  const double a = 0.05, len = 0.999, s2 = toksvig_variance(len);
  EXPECT_NEAR(sqr(toksvig_ggx_alpha(a, len)), a * a + 2 * s2, 0.02 * (a * a + 2 * s2));
}

TEST(Lean, MomentsOfKnownNormals) {
  // Two normals with slopes (±0.2, 0): mean 0, variance 0.04 along x; base α = 0.1 adds 0.005 per axis.
  auto m = LeanMoments<double>::from_normal(normalize(Vec3d(-0.2, 0, 1)), 0.1, 0.1);
  m += LeanMoments<double>::from_normal(normalize(Vec3d(0.2, 0, 1)), 0.1, 0.1);
  const auto cov = lean_covariance(m.normalized());
  EXPECT_NEAR(cov.xx, 0.04 + 0.005, 1e-12);
  EXPECT_NEAR(cov.yy, 0.005, 1e-12);
  EXPECT_NEAR(cov.xy, 0.0, 1e-12);
  const Vec2d axy = lean_alpha_xy(cov);
  EXPECT_NEAR(axy.x, std::sqrt(2 * 0.045), 1e-12);
  // CLEAN gives the isotropic LEAN value.
  auto c = CleanMoments<double>::from_normal(normalize(Vec3d(-0.2, 0, 1)), 0.1);
  c += CleanMoments<double>::from_normal(normalize(Vec3d(0.2, 0, 1)), 0.1);
  EXPECT_NEAR(c.alpha(), lean_alpha_isotropic(cov), 1e-12);
}

TEST(VarianceMapping, RoundTripAndAdd) {
  for (double r : {0.0, 0.2, 0.5, 1.0})
    EXPECT_NEAR(slope_variance_to_roughness(roughness_to_slope_variance(r)), r, 1e-12);
  // r = 0.5: α = 0.25, σ² = 0.03125; add 0.01 → α'² = 2(0.04125) = 0.0825.
  EXPECT_NEAR(std::pow(roughness_add_variance(0.5, 0.01), 4), 0.0825, 1e-12);
  EXPECT_EQ(slope_variance_to_roughness(10.0), 1.0);  // clamped to the parameter range
}

TEST(MipChain, KnownVarianceGivesExpectedRoughness) {
  const int W = 256;
  const double s = 0.12, r0 = 0.3, a0 = r0 * r0;
  const auto normals = gaussian_slope_normals(W, W, s, s, 42);
  const std::vector<float> rough{float(r0)};
  const auto var = build_roughness_mips(W, W, normals, rough, FilterMethod::Variance);
  const auto tok = build_roughness_mips(W, W, normals, rough, FilterMethod::Toksvig);
  ASSERT_EQ(var.size(), 9u);
  for (size_t k = 0; k < var.size(); ++k) {
    const double n = std::pow(4.0, double(k));
    const double expect = a0 * a0 + 2 * expected_box_variance(s * s, n);  // α'² = α² + 2σ²(1 − 1/N)
    EXPECT_NEAR(mean_alpha2(var[k], 0), expect, 0.03 * expect) << "level " << k;
    // Toksvig estimates the variance from |n̄| (small-angle model): looser.
    EXPECT_NEAR(mean_alpha2(tok[k], 0), expect, 0.15 * expect) << "toksvig level " << k;
    std::printf("[mip %zu] %3dx%-3d expected r %.4f  variance %.4f  toksvig %.4f\n", k, var[k].width,
                var[k].height, std::pow(expect, 0.25), std::pow(mean_alpha2(var[k], 0), 0.25),
                std::pow(mean_alpha2(tok[k], 0), 0.25));
  }
  EXPECT_NEAR(var.back().mean_normal_variance, s * s, 0.03 * s * s);
}

TEST(MipChain, LeanKeepsAnisotropy) {
  const int W = 128;
  const double sx = 0.2, sy = 0.05, r0 = 0.2, a0 = r0 * r0;
  const auto normals = gaussian_slope_normals(W, W, sx, sy, 7);
  const auto lean = build_roughness_mips(W, W, normals, {float(r0)}, FilterMethod::Lean);
  ASSERT_EQ(lean[0].channels, 2);
  const auto& top = lean.back();
  const double n = double(W) * W;
  EXPECT_NEAR(mean_alpha2(top, 0), a0 * a0 + 2 * expected_box_variance(sx * sx, n), 0.03 * 2 * sx * sx);
  EXPECT_NEAR(mean_alpha2(top, 1), a0 * a0 + 2 * expected_box_variance(sy * sy, n), 0.05 * 2 * sy * sy);
}

TEST(MipChain, FlatNormalsKeepRoughnessAndOddSizesCoverEverything) {
  // 5 × 3 map: levels 5×3, 2×1, 1×1; flat normals → roughness unchanged at every level (per-texel input).
  std::vector<Vec3f> flat(15, Vec3f(0, 0, 1));
  std::vector<float> rough(15);
  for (int i = 0; i < 15; ++i) rough[size_t(i)] = 0.1f + 0.05f * float(i);
  const auto lv = build_roughness_mips(5, 3, flat, rough, FilterMethod::Variance);
  ASSERT_EQ(lv.size(), 3u);
  EXPECT_EQ(lv[1].width, 2);
  EXPECT_EQ(lv[1].height, 1);
  for (int i = 0; i < 15; ++i) EXPECT_NEAR(lv[0].roughness[size_t(i)], rough[size_t(i)], 1e-6);
  // Top: α'² = mean of α² over all 15 texels (variance mapping averages variances, not roughness).
  double m = 0;
  for (float r : rough) m += std::pow(double(r), 4.0) / 15;
  EXPECT_NEAR(std::pow(double(lv[2].roughness[0]), 4.0), m, 1e-6);
}

TEST(MipChain, BitIdenticalAcrossThreadCounts) {
  const auto normals = gaussian_slope_normals(200, 120, 0.1, 0.3, 3);
  std::vector<MipLevel> a, b;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    a = build_roughness_mips(200, 120, normals, {0.4f}, FilterMethod::Lean);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 4);
    b = build_roughness_mips(200, 120, normals, {0.4f}, FilterMethod::Lean);
  }
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].roughness, b[k].roughness);
    EXPECT_EQ(a[k].normal, b[k].normal);
  }
}

TEST(MipChain, BadInput) {
  EXPECT_THROW(build_roughness_mips(4, 4, std::vector<Vec3f>(15), {0.5f}, FilterMethod::Variance),
               InputError);
  EXPECT_THROW(
      build_roughness_mips(4, 4, std::vector<Vec3f>(16), std::vector<float>(3), FilterMethod::Variance),
      InputError);
  EXPECT_THROW(filter_method_from_name("clean-ish"), InputError);
  // Degenerate normals (zero, NaN, backfacing) give finite output.
  std::vector<Vec3f> bad{Vec3f(0, 0, 0), Vec3f(NAN, 0, 1), Vec3f(0, 0, -1), Vec3f(1, 0, 0)};
  for (auto m : {FilterMethod::Toksvig, FilterMethod::Variance, FilterMethod::Lean}) {
    const auto lv = build_roughness_mips(2, 2, bad, {0.5f}, m);
    for (const auto& l : lv)
      for (float r : l.roughness) EXPECT_TRUE(std::isfinite(r) && r >= 0 && r <= 1);
  }
}

TEST(Blend, LinearAndVarianceSpace) {
  EXPECT_NEAR(blend_linear(0.25, 1.0, 3.0), 1.5, 1e-15);
  const Rgbd c = blend_linear(0.5, Rgbd(0, 0.2, 1), Rgbd(1, 0.4, 1));
  EXPECT_NEAR(c.g, 0.3, 1e-15);
  // r = 0.2 and 0.6 at t = 0.5: α² = (0.2⁴ + 0.6⁴)/2.
  EXPECT_NEAR(std::pow(blend_roughness(0.5, 0.2, 0.6), 4), 0.5 * (std::pow(0.2, 4) + std::pow(0.6, 4)),
              1e-15);
  EXPECT_NEAR(blend_roughness(0.0, 0.2, 0.6), 0.2, 1e-15);
}

TEST(Blend, SlopeBlendOfHeightMaps) {
  // Two planar height fields h = a·x and h = c·x: their blend (1−t)a + tc has the blended slope.
  const Vec3d na = normalize(Vec3d(-0.3, 0, 1)), nb = normalize(Vec3d(0.5, 0.2, 1));
  const Vec3d m = blend_normals_slopes(0.25, na, nb);
  EXPECT_NEAR(-m.x / m.z, 0.75 * 0.3 + 0.25 * -0.5, 1e-12);
  EXPECT_NEAR(-m.y / m.z, 0.25 * -0.2, 1e-12);
  EXPECT_NEAR(length(blend_normals_slopes(1.0, na, nb) - nb), 0.0, 1e-12);
}

TEST(Blend, ReorientedNormalMappingIsTheRotation) {
  const Vec3d base = normalize(Vec3d(0.4, -0.3, 0.8)), detail = normalize(Vec3d(-0.2, 0.5, 0.9));
  // Independent reference: Rodrigues rotation taking +z to base, applied to detail.
  const Vec3d z(0, 0, 1), k = normalize(cross(z, base));
  const double th = std::acos(base.z);
  const Vec3d rot =
      detail * std::cos(th) + cross(k, detail) * std::sin(th) + k * (dot(k, detail) * (1 - std::cos(th)));
  const Vec3d got = detail_normal_rnm(base, detail);
  EXPECT_NEAR(length(got - rot), 0.0, 1e-12);
  EXPECT_NEAR(length(detail_normal_rnm(base, z) - base), 0.0, 1e-12);      // flat detail → base
  EXPECT_NEAR(length(detail_normal_rnm(z, detail) - detail), 0.0, 1e-12);  // flat base → detail
  EXPECT_TRUE(is_finite(detail_normal_rnm(Vec3d(0, 0, -1), detail)));
  EXPECT_TRUE(is_finite(detail_normal_rnm(Vec3d(0, 0, 0), Vec3d(0, 0, 0))));
}

TEST(VarianceMapping, Conty2019Convention) {
  // k = 2 matches bump_terminator.h: total slope variance 2α² ↔ per-axis α² (σ² = 2 × per-axis).
  for (double var : {0.001, 0.02, 0.2}) {
    const double r = slope_variance_to_roughness(var, kConty2019);
    EXPECT_NEAR(r * r, bump::ggx_alpha_from_variance(2 * var), 1e-12);
  }
  // The mip builder with k = 2: α'² = α0² + 2s²(1 − 1/N)/2.
  const int W = 128;
  const double s = 0.1, r0 = 0.4, a0 = r0 * r0;
  const auto normals = gaussian_slope_normals(W, W, s, s, 9);
  const auto lv = build_roughness_mips(W, W, normals, {float(r0)}, FilterMethod::Variance, 0, kConty2019);
  const double expect = a0 * a0 + expected_box_variance(s * s, double(W) * W);
  EXPECT_NEAR(mean_alpha2(lv.back(), 0), expect, 0.03 * expect);
  EXPECT_THROW(build_roughness_mips(W, W, normals, {0.4f}, FilterMethod::Variance, 0, -1.0), InputError);
}
