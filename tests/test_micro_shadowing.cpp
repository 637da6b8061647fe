// Micro-shadowing terms (include/microshadow/occlusion/micro_shadowing.h) against independent references:
// closed forms against engine code, limits and hand values, Monte Carlo with samplers and estimators written
// here, a plain 1D quadrature of the θ integrand, a brute-force azimuth mean, and the limits of
// docs/theory.md §3.
#include <gtest/gtest.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace msh;
using namespace msh::micro_shadowing;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Vec3d dir(double cos_theta, double phi) { return spherical_direction(cos_theta, phi); }

// Plain Monte Carlo of the ratio P[n·m > c ∧ m·l > c] / P[n·m > 0 ∧ m·l > 0] with PCG32 (not Sobol, not the
// library estimator), using either VNDF sampler. Returns {ratio, standard error}.
struct McResult {
  double value, sigma;
};
McResult mc_ratio(const GGX<double>& g, const Vec3d& v, const Vec3d& l, double V, int n, bool heitz,
                  uint64_t seed) {
  Pcg32 rng(seed);
  const double c = std::sqrt(1 - V);
  double cone = 0, hemi = 0;
  for (int i = 0; i < n; ++i) {
    const Vec2d u(rng.next_double(), rng.next_double());
    const Vec3d m = heitz ? g.sample_vndf_heitz2018(v, u) : g.sample_vndf_spherical_caps(v, u);
    if (m.z > 0 && dot(m, l) > 0) hemi += 1;
    if (m.z > c && dot(m, l) > c) cone += 1;
  }
  const double r = hemi > 0 ? cone / hemi : 0;
  return {r, std::sqrt(std::max(r * (1 - r), 1.0 / hemi) / std::max(hemi, 1.0))};
}

// Importance-sampling estimate that does not use any VNDF sampler: m uniform on the hemisphere, weight
// D_v(m) / (1/2π). Returns {P[cone], P[hemisphere]}.
std::pair<double, double> mc_uniform(const GGX<double>& g, const Vec3d& v, const Vec3d& l, double V, int n,
                                     uint64_t seed) {
  Pcg32 rng(seed);
  const double c = std::sqrt(1 - V);
  double cone = 0, hemi = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3d m = sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double()));
    const double w = g.D(v, m) * 2 * kPi<double>;
    if (dot(m, l) > 0) hemi += w;
    if (m.z > c && dot(m, l) > c) cone += w;
  }
  return {cone / n, hemi / n};
}

}  // namespace

// ---- Closed forms
// ------------------------------------------------------------------------------------------

// The closed forms are not re-typed here: each is tested against facts that do not depend on how it is
// written — published engine code, its limits, its zero set and saturation line, monotonicity, and values
// derived by hand.

namespace {
// Filament's computeMicroShadowing (shading_lighting.fs / common_lighting.fs), "Chan 2018, Material Advances
// in Call of Duty: WWII", transcribed in float as the engine ships it: an rsqrt aperture, then a square.
float filament_compute_micro_shadowing(float NoL, float visibility) {
  const float aperture = 1.0f / std::sqrt(1.0f - visibility);
  const float micro_shadow = std::clamp(NoL * aperture, 0.0f, 1.0f);
  return micro_shadow * micro_shadow;
}
// Unity HDRP's ComputeMicroShadowing (ShaderLibrary/CommonLighting.hlsl, "The Technical Art of Uncharted 4 -
// Brinck and Maximov 2016") at opacity 1 (its lerp(1, microshadow, opacity) is then microshadow).
float unity_compute_micro_shadowing(float AO, float NdotL) {
  const float aperture = 2.0f * AO * AO;
  return std::clamp(NdotL + aperture - 1.0f, 0.0f, 1.0f);
}
}  // namespace

TEST(MicroShadowingTerms, ChanMatchesFilamentAndBrinckMaximovMatchesUnity) {
  // V < 1: Filament divides by zero at V = 1 (handled by our limit, tested below).
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j <= 64; ++j) {
      const float V = float(i) / 64, nl = float(j) / 64;
      // The two float evaluations differ by rounding only (rsqrt·x vs x/sqrt): a few ulps of 1.
      EXPECT_NEAR(chan_2018(V, nl), filament_compute_micro_shadowing(nl, V), 4e-7f) << V << " " << nl;
      EXPECT_NEAR(brinck_maximov_2016(V, nl), unity_compute_micro_shadowing(V, nl), 2.4e-7f)
          << V << " " << nl;
    }
}

TEST(MicroShadowingTerms, LimitsInVisibility) {
  for (int j = 0; j <= 40; ++j) {
    const double nl = j / 40.0;
    // V = 0: nothing is visible. The cone has cos θ = 1, so only Chan's term (which is not a visibility
    // fraction at V = 0: (N·L)²) is non-zero.
    EXPECT_EQ(reference_step(0.0, nl), 0.0);
    EXPECT_EQ(brinck_maximov_2016(0.0, nl), 0.0);
    EXPECT_EQ(part1_analytic(0.0, nl), 0.0);
    EXPECT_NEAR(chan_2018(0.0, nl), nl * nl, 1e-16);
    // V = 1: the whole hemisphere is visible; every term is 1 for a light above the horizon.
    if (nl > 0) {
      EXPECT_EQ(reference_step(1.0, nl), 1.0);
      EXPECT_EQ(brinck_maximov_2016(1.0, nl), 1.0);
      EXPECT_EQ(chan_2018(1.0, nl), 1.0);
      EXPECT_EQ(part1_analytic(1.0, nl), 1.0);
    }
  }
  // The visibility cone: V = 1 − cos²θ (projected solid angle of a cone, docs/theory.md §1).
  EXPECT_EQ(cone_cos_from_visibility(0.0), 1.0);
  EXPECT_EQ(cone_cos_from_visibility(1.0), 0.0);
  EXPECT_EQ(cone_cos_from_visibility(0.75), 0.5);
  EXPECT_DOUBLE_EQ(cone_cos_from_visibility(0.36), 0.8);
}

TEST(MicroShadowingTerms, ZeroSetsAndSaturationLines) {
  for (int i = 1; i < 40; ++i) {
    const double V = i / 40.0, c = std::sqrt(1 - V);
    // Reference step: lit exactly when N·L > cos θ (strict).
    EXPECT_EQ(reference_step(V, c), 0.0);
    EXPECT_EQ(reference_step(V, std::nextafter(c, 2.0)), 1.0);
    EXPECT_EQ(reference_step(V, std::nextafter(c, 0.0)), 0.0);
    // Chan 2018 reaches 1 exactly on the cone boundary N·L = sqrt(1 − V), is 1/4 at half of it.
    EXPECT_EQ(chan_2018(V, c), 1.0);
    EXPECT_LT(chan_2018(V, std::nextafter(c, 0.0)), 1.0);
    EXPECT_NEAR(chan_2018(V, 0.5 * c), 0.25, 1e-15);
    EXPECT_EQ(chan_2018(V, 0.0), 0.0);
    // Brinck & Maximov 2016: zero on and below the line N·L = 1 − 2V², then slope 1 in N·L.
    const double z = 1 - 2 * V * V;
    if (z > 0) {
      EXPECT_NEAR(brinck_maximov_2016(V, z), 0.0, 1e-15);
      EXPECT_EQ(brinck_maximov_2016(V, 0.5 * z), 0.0);
    }
    if (z + 0.05 < 1 && z + 0.05 > 0) {
      EXPECT_NEAR(brinck_maximov_2016(V, z + 0.05), 0.05, 1e-15) << V;
    }
    // Part 1: saturates at N·L = sqrt(1 − V⁵) and is 0 at N·L = 0.
    const double cp = std::sqrt(1 - std::pow(V, 5));
    EXPECT_NEAR(part1_analytic(V, cp), 1.0, 1e-13);  // V⁵ rounded two ways, raised to 0.75/V ≤ 30
    EXPECT_EQ(part1_analytic(V, std::min(1.0, cp + 1e-9)), 1.0);
    EXPECT_EQ(part1_analytic(V, 0.0), 0.0);
  }
  // At V = 1/√2, 2V² = 1: Brinck & Maximov is N·L itself.
  for (double nl : {0.1, 0.4, 0.9}) EXPECT_NEAR(brinck_maximov_2016(std::sqrt(0.5), nl), nl, 1e-15);
}

TEST(MicroShadowingTerms, HandDerivedValues) {
  // V = 0.75: cos θ = 1/2. Chan: (0.25/0.5)² = 1/4. Brinck & Maximov: 0.25 + 2·(9/16) − 1 = 3/8.
  EXPECT_DOUBLE_EQ(chan_2018(0.75, 0.25), 0.25);
  EXPECT_DOUBLE_EQ(brinck_maximov_2016(0.75, 0.25), 0.375);
  EXPECT_DOUBLE_EQ(brinck_maximov_2016(0.5, 0.75), 0.25);  // 0.75 + 0.5 − 1
  // Part 1 at V = 3/4: exponent 0.75/V = 1, so the term is linear, N·L / sqrt(1 − 243/1024) = N·L·32/√781.
  EXPECT_NEAR(part1_analytic(0.75, 0.5), 16 / std::sqrt(781.0), 1e-15);
  EXPECT_NEAR(part1_analytic(0.75, 0.25), 8 / std::sqrt(781.0), 1e-15);
  // Part 1 at V = 3/8: exponent 2, 1 − V⁵ = 1 − 243/32768 = 32525/32768: (N·L)² · 32768/32525.
  EXPECT_NEAR(part1_analytic(0.375, 0.5), 0.25 * 32768 / 32525, 1e-15);
  // Part 1 at V = 1/2: exponent 3/2, 1 − V⁵ = 31/32: (0.5·sqrt(32/31))^1.5.
  EXPECT_NEAR(part1_analytic(0.5, 0.5), std::pow(0.25 * 32 / 31, 0.75), 1e-15);
}

TEST(MicroShadowingTerms, MonotoneInVisibilityAndNdotL) {
  // Every term is non-decreasing in V (more visible hemisphere, more light) and in N·L (a higher light).
  const int n = 200;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j < n; ++j) {
      const double a = double(j) / n, b = double(j + 1) / n, x = double(i) / n;
      // In V at fixed N·L = x, and in N·L at fixed V = x.
      EXPECT_LE(reference_step(a, x), reference_step(b, x));
      EXPECT_LE(brinck_maximov_2016(a, x), brinck_maximov_2016(b, x));
      EXPECT_LE(chan_2018(a, x), chan_2018(b, x));
      EXPECT_LE(part1_analytic(a, x), part1_analytic(b, x)) << a << " " << x;
      EXPECT_LE(reference_step(x, a), reference_step(x, b));
      EXPECT_LE(brinck_maximov_2016(x, a), brinck_maximov_2016(x, b));
      EXPECT_LE(chan_2018(x, a), chan_2018(x, b));
      EXPECT_LE(part1_analytic(x, a), part1_analytic(x, b));
    }
}

TEST(MicroShadowingTerms, FloatAgreesWithDouble) {
  // The float instantiation differs from the double one by float rounding only (a few ulps of 1; Part 1's
  // pow with exponent up to 0.75/V amplifies the base's relative rounding by that exponent).
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      const float V = float(i) / 40, nl = float(j) / 40;
      EXPECT_NEAR(brinck_maximov_2016(V, nl), brinck_maximov_2016(double(V), double(nl)), 3e-7);
      EXPECT_NEAR(chan_2018(V, nl), chan_2018(double(V), double(nl)), 5e-7);
      EXPECT_NEAR(part1_analytic(V, nl), part1_analytic(double(V), double(nl)),
                  i > 0 ? 6e-7 * (0.75 / V + 1) : 0.0);
      EXPECT_EQ(reference_step(V, nl), float(reference_step(double(V), double(nl)))) << V << " " << nl;
    }
}

TEST(MicroShadowingTerms, FiniteAndInRangeForEveryInput) {
  const std::vector<double> xs = {kNaN, kInf, -kInf,     -1, -1e-300,  0, 1e-310,
                                  1e-7, 0.5,  1 - 1e-16, 1,  1 + 1e-9, 2};
  for (double V : xs)
    for (double nl : xs) {
      for (double r : {reference_step(V, nl), brinck_maximov_2016(V, nl), chan_2018(V, nl),
                       part1_analytic(V, nl), cone_cos_from_visibility(V)}) {
        ASSERT_TRUE(std::isfinite(r)) << V << " " << nl;
        ASSERT_GE(r, 0.0);
        ASSERT_LE(r, 1.0);
      }
      const float Vf = float(V), nlf = float(nl);
      for (float r : {reference_step(Vf, nlf), brinck_maximov_2016(Vf, nlf), chan_2018(Vf, nlf),
                      part1_analytic(Vf, nlf)}) {
        ASSERT_TRUE(std::isfinite(r));
        ASSERT_GE(r, 0.0f);
        ASSERT_LE(r, 1.0f);
      }
      // Exact evaluations with the same junk in every slot.
      for (double a : {kNaN, 0.0, 0.3, kInf}) {
        const double e = generic_vndf_exact(V, a, a, Vec3d(nl, 0, 0.5), Vec3d(0.2, nl, 0.9));
        ASSERT_TRUE(std::isfinite(e));
        ASSERT_GE(e, 0.0);
        ASSERT_LE(e, 1.0);
      }
      const double m = generic_vndf_exact_azimuth_mean(V, 0.3, nl, nl);
      ASSERT_TRUE(std::isfinite(m));
      ASSERT_GE(m, 0.0);
      ASSERT_LE(m, 1.0);
    }
  // Zero, backfacing and grazing vectors.
  const GGX<float> gf(0.3f);
  for (Vec3f v : {Vec3f(0, 0, 0), Vec3f(1, 0, 0), Vec3f(0, 0, -1), Vec3f(0.6f, 0, -0.8f)})
    for (Vec3f l : {Vec3f(0, 0, 0), Vec3f(0, 1, 0), Vec3f(0, 0, -1), Vec3f(0, 0, 1)}) {
      const float e = generic_vndf_estimate(0.8f, gf, v, l, 64, G2Form::HeightCorrelated);
      ASSERT_TRUE(std::isfinite(e));
      const double x = generic_vndf_exact(0.8, 0.3, 0.3, Vec3d(v), Vec3d(l));
      ASSERT_TRUE(std::isfinite(x));
      ASSERT_GE(x, 0.0);
      ASSERT_LE(x, 1.0);
      const GenericSample<float> s =
          generic_vndf_sample(0.5f, gf, v, l, Vec2f(0.3f, 0.7f), G2Form::Uncorrelated);
      ASSERT_TRUE(std::isfinite(s.cone) && std::isfinite(s.hemisphere) && std::isfinite(s.weight));
    }
}

// ---- Exact generic term
// ------------------------------------------------------------------------------------

// The θ antiderivative used by the quadrature, against composite Simpson on the original θ integrand
// (a sinθ + b cosθ) sinθ / (k sin²θ + cos²θ)².
TEST(MicroShadowingExact, ThetaAntiderivativeMatchesSimpson) {
  Pcg32 rng(3);
  for (int t = 0; t < 50; ++t) {
    const double a = 2 * rng.next_double() - 1, b = rng.next_double();
    const double k = std::pow(10.0, 4 * rng.next_double() - 1);  // α from ~0.01 to ~3
    const double t0 = 0.5 * kPi<double> * rng.next_double(),
                 t1 = t0 + (0.5 * kPi<double> - t0) * rng.next_double();
    const int n = 20000;
    double s = 0;
    for (int i = 0; i <= n; ++i) {
      const double th = t0 + (t1 - t0) * i / n;
      const double f = (a * std::sin(th) + b * std::cos(th)) * std::sin(th) /
                       sqr(k * sqr(std::sin(th)) + sqr(std::cos(th)));
      s += f * (i == 0 || i == n ? 1 : (i % 2 ? 4 : 2));
    }
    s *= (t1 - t0) / (3.0 * n);
    const double sk = std::sqrt(k);
    const double F = exact_quadrature::gv_F(t1, a, b, k, sk) - exact_quadrature::gv_F(t0, a, b, k, sk);
    EXPECT_NEAR(F, s, 1e-9 * (1 + std::abs(s))) << "a=" << a << " b=" << b << " k=" << k;
  }
}

// The closed-form hemisphere probability (Lambert over the stretched VNDF) and the azimuthal quadrature with
// c = 0 are two independent derivations of the same number; also P = 1 for l = n (VNDF normalization).
TEST(MicroShadowingExact, ClosedFormDenominatorMatchesQuadrature) {
  Pcg32 rng(5);
  for (int t = 0; t < 300; ++t) {
    const double ax = 0.02 + 1.2 * rng.next_double(), ay = t % 2 ? ax : 0.02 + rng.next_double();
    const GGX<double> g(ax, ay);
    Vec3d v = sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double()));
    Vec3d l = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
    if (t == 0) v = {0, 0, 1};
    if (t == 1) v = {1, 0, 0};
    if (t == 2) l = {0, 0, 1};
    const double a = exact_quadrature::vndf_hemisphere_probability(g, v, l);
    const double b = exact_quadrature::vndf_region_probability(g, v, l, 0.0, 1e-12);
    EXPECT_NEAR(a, b, 1e-10) << t;
    if (t == 2) {
      EXPECT_NEAR(a, 1.0, 1e-12);
    }
  }
  // Octant hand value: ∫ over x, y, z > 0 of z dm = π/4.
  EXPECT_NEAR(
      exact_quadrature::clamped_cosine_over_hemispheres(Vec3d(0, 0, 1), Vec3d(1, 0, 0), Vec3d(0, 1, 0)),
      kPi<double> / 4, 1e-15);
}

// Exact vs Monte Carlo with 2^20 PCG32 samples per point, both VNDF samplers, at random anisotropic points.
// Tolerance: 5 standard errors + 1e-6.
TEST(MicroShadowingExact, MatchesMonteCarloAtRandomPoints) {
  Pcg32 rng(17);
  int tested = 0;
  for (int t = 0; t < 24; ++t) {
    const double V = 0.35 + 0.65 * rng.next_double();
    const double ax = 0.05 + 0.95 * rng.next_double(), ay = t % 3 == 0 ? ax : 0.05 + 0.95 * rng.next_double();
    const Vec3d v = dir(rng.next_double(), 2 * kPi<double> * rng.next_double());
    const Vec3d l = dir(rng.next_double(), 2 * kPi<double> * rng.next_double());
    const GGX<double> g(ax, ay);
    const double e = generic_vndf_exact(V, ax, ay, v, l);
    const McResult mc = mc_ratio(g, v, l, V, 1 << 20, t % 2 == 1, 1000 + t);
    EXPECT_NEAR(e, mc.value, 5 * mc.sigma + 1e-6)
        << "V=" << V << " ax=" << ax << " ay=" << ay << " nv=" << v.z << " nl=" << l.z;
    tested += e > 0.01;
  }
  EXPECT_GE(tested, 8);  // the points are not all in the trivially-zero region
}

// Both samplers give the same estimate of the same configuration (statistically), and each matches an
// estimator that samples m uniformly and weights by the VNDF value.
TEST(MicroShadowingExact, SamplersAndUniformImportanceSamplingAgree) {
  const GGX<double> g(0.5, 0.3);
  const Vec3d v = dir(0.4, 0.3), l = dir(0.7, 2.1);
  const double V = 0.8;
  const McResult a = mc_ratio(g, v, l, V, 1 << 20, false, 1), b = mc_ratio(g, v, l, V, 1 << 20, true, 2);
  EXPECT_NEAR(a.value, b.value, 5 * std::hypot(a.sigma, b.sigma));
  const auto [pc, ph] = mc_uniform(g, v, l, V, 1 << 21, 3);
  const double e = generic_vndf_exact(V, 0.5, 0.3, v, l);
  EXPECT_NEAR(pc / ph, e, 5e-3);
  EXPECT_NEAR(ph, exact_quadrature::vndf_hemisphere_probability(g, v, l), 5e-3);
}

TEST(MicroShadowingExact, Limits) {
  Pcg32 rng(23);
  for (int t = 0; t < 100; ++t) {
    const double a = 0.05 + rng.next_double();
    const Vec3d v = dir(rng.next_double(), 2 * kPi<double> * rng.next_double());
    const Vec3d l = dir(0.01 + 0.99 * rng.next_double(), 2 * kPi<double> * rng.next_double());
    EXPECT_EQ(generic_vndf_exact(0.0, a, a, v, l), 0.0);  // V = 0: no cone
    EXPECT_EQ(generic_vndf_exact(1.0, a, a, v, l), 1.0);  // V = 1: the cone is the hemisphere
    // Close to the ends, continuous.
    EXPECT_LT(generic_vndf_exact(1e-6, a, a, v, l), 1e-3);
    EXPECT_GT(generic_vndf_exact(1 - 1e-8, a, a, v, l), 0.99);
  }
  // α → 0: the reference step, away from its discontinuity. GGX tails carry mass ~α²/d² at angle d from n,
  // so at α = 1e-4 and a margin of 0.02 in N·L the deviation is ~1e-5.
  for (int i = 1; i < 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const double V = i / 20.0, nl = j / 20.0, c = std::sqrt(1 - V);
      if (std::abs(nl - c) < 0.02) continue;
      const Vec3d v = dir(0.3 + 0.035 * j, 0.0), l = dir(nl, 1.0);
      EXPECT_NEAR(generic_vndf_exact(V, 1e-4, 1e-4, v, l), reference_step(V, nl), 1e-4) << V << " " << nl;
    }
  // N·V = 1: independent of the azimuth of l; the azimuth mean equals any single azimuth.
  for (double V : {0.3, 0.6, 0.9})
    for (double a : {0.01, 0.16, 0.49, 1.0}) {
      const double e0 = generic_vndf_exact(V, a, a, Vec3d(0, 0, 1), dir(0.6, 0.0));
      for (double phi : {0.5, 1.7, 3.0})
        EXPECT_NEAR(generic_vndf_exact(V, a, a, Vec3d(0, 0, 1), dir(0.6, phi)), e0, 1e-9);
      EXPECT_NEAR(generic_vndf_exact_azimuth_mean(V, a, 0.6, 1.0), e0, 1e-9);
    }
}

TEST(MicroShadowingExact, MonotoneInVisibilityAndRotationInvariant) {
  Pcg32 rng(29);
  for (int t = 0; t < 40; ++t) {
    const double a = 0.05 + rng.next_double(), b = 0.05 + rng.next_double();
    const Vec3d v = dir(rng.next_double(), 2 * kPi<double> * rng.next_double());
    const Vec3d l = dir(rng.next_double(), 2 * kPi<double> * rng.next_double());
    double prev = 0;
    for (int i = 0; i <= 20; ++i) {
      const double e = generic_vndf_exact(i / 20.0, a, b, v, l);
      EXPECT_GE(e, prev - 1e-9);
      prev = e;
    }
    // Rotating v and l by 90° about n swaps the roles of αx and αy.
    const auto rot = [](const Vec3d& w) { return Vec3d(-w.y, w.x, w.z); };
    EXPECT_NEAR(generic_vndf_exact(0.7, a, b, v, l), generic_vndf_exact(0.7, b, a, rot(v), rot(l)), 1e-9);
    // Isotropic: any rotation about n.
    const double psi = 2 * kPi<double> * rng.next_double(), cs = std::cos(psi), sn = std::sin(psi);
    const auto rz = [&](const Vec3d& w) { return Vec3d(cs * w.x - sn * w.y, sn * w.x + cs * w.y, w.z); };
    EXPECT_NEAR(generic_vndf_exact(0.7, a, a, v, l), generic_vndf_exact(0.7, a, a, rz(v), rz(l)), 1e-9);
  }
}

// exact_zero ⇒ exact 0 for every roughness and view; a brute-force search over 2^16 VNDF samples finds no
// cone sample; just across the boundary the value is tiny and positive.
TEST(MicroShadowingExact, EarlyOutIsExact) {
  Pcg32 rng(31);
  for (int t = 0; t < 200; ++t) {
    const double V = 0.5 * rng.next_double();
    const double nl = (1 - 2 * V) * rng.next_double();
    ASSERT_TRUE(exact_zero(V, nl));
    const double a = 0.01 + 1.5 * rng.next_double();
    const Vec3d v = dir(rng.next_double(), 2 * kPi<double> * rng.next_double());
    const Vec3d l = dir(nl, 2 * kPi<double> * rng.next_double());
    EXPECT_EQ(generic_vndf_exact(V, a, a * 0.7, v, l), 0.0);
    EXPECT_EQ(generic_vndf_exact_azimuth_mean(V, a, nl, v.z), 0.0);
    EXPECT_EQ(generic_vndf_estimate(V, GGX<double>(a), v, l, 16, G2Form::HeightCorrelated), 0.0);
    if (t < 20) {
      const GGX<double> g(a);
      const double c = std::sqrt(1 - V);
      for (uint32_t i = 0; i < (1u << 16); ++i) {
        const Vec3d m = g.Sample_wm(v, sobol_2d<double>(i, 7));
        ASSERT_FALSE(m.z > c && dot(m, l) > c);
      }
    }
  }
  // Just inside the lit region the cone is a sliver around the bisector of n and l: the term starts at 0.
  for (double V : {0.1, 0.3, 0.45})
    for (double a : {0.1, 0.5, 1.0}) {
      const double nl = 1 - 2 * V + 1e-4;
      const double e = generic_vndf_exact_azimuth_mean(V, a, nl, 0.7);
      EXPECT_GE(e, 0.0);
      EXPECT_LT(e, 1e-3) << V << " " << a;
      EXPECT_GT(generic_vndf_exact_azimuth_mean(V, a, std::min(1.0, nl + 0.3), 0.7), e);
    }
}

// The azimuth mean against a brute-force 512-point midpoint rule over the exact term.
TEST(MicroShadowingExact, AzimuthMeanMatchesBruteForce) {
  for (auto [V, a, nl, nv] : std::vector<std::array<double, 4>>{{0.6, 0.16, 0.5, 0.3},
                                                                {0.6875, 1.0, 0.5625, 0.125},
                                                                {0.9, 0.01, 0.4, 0.8},
                                                                {0.4, 0.49, 0.9, 0.05}}) {
    const double m = generic_vndf_exact_azimuth_mean(V, a, nl, nv);
    const Vec3d v = dir(nv, 0.0);
    double s = 0;
    const int n = 512;
    for (int i = 0; i < n; ++i) s += generic_vndf_exact(V, a, a, v, dir(nl, kPi<double> * (i + 0.5) / n));
    EXPECT_NEAR(m, s / n, 5e-6) << V << " " << a << " " << nl << " " << nv;
  }
}

// The anisotropic azimuth mean against the same brute-force rule, and equal to the isotropic mean at αx = αy.
TEST(MicroShadowingExact, AnisotropicAzimuthMeanMatchesBruteForce) {
  for (auto [V, ax, ay, nl, nv] : std::vector<std::array<double, 5>>{
           {0.6, 0.16, 0.49, 0.5, 0.3}, {0.8, 0.04, 0.5, 0.7, 0.9}, {0.5, 0.81, 0.09, 0.3, 0.1}}) {
    const double m = generic_vndf_exact_azimuth_mean_anisotropic(V, ax, ay, nl, nv);
    const Vec3d v = dir(nv, 0.0);
    double s = 0;
    const int n = 512;
    for (int i = 0; i < n; ++i) s += generic_vndf_exact(V, ax, ay, v, dir(nl, kPi<double> * (i + 0.5) / n));
    EXPECT_NEAR(m, s / n, 5e-6) << V << " " << ax << " " << ay << " " << nl << " " << nv;
    EXPECT_NEAR(generic_vndf_exact_azimuth_mean_anisotropic(V, ax, ax, nl, nv),
                generic_vndf_exact_azimuth_mean(V, ax, nl, nv), 2e-6);
  }
}

// ---- Estimators ------------------------------------------------------------------------------------------

// The Smith weight is constant in m, so both G2 forms give the same ratio although their weights differ.
TEST(MicroShadowingEstimate, G2FormsAgreeWhereTheWeightCancels) {
  Pcg32 rng(37);
  for (int t = 0; t < 30; ++t) {
    const double V = 0.4 + 0.6 * rng.next_double(), ax = 0.05 + rng.next_double(),
                 ay = 0.05 + rng.next_double();
    const Vec3d v = dir(0.05 + 0.95 * rng.next_double(), 2 * kPi<double> * rng.next_double());
    const Vec3d l = dir(0.05 + 0.95 * rng.next_double(), 2 * kPi<double> * rng.next_double());
    const GGX<double> g(ax, ay);
    const double hc = generic_vndf_estimate(V, g, v, l, 1024, G2Form::HeightCorrelated, 5);
    const double un = generic_vndf_estimate(V, g, v, l, 1024, G2Form::Uncorrelated, 5);
    EXPECT_NEAR(hc, un, 1e-12);
    const GenericSample<double> a =
        generic_vndf_sample(0.5, g, v, l, Vec2d(0.3, 0.6), G2Form::HeightCorrelated);
    const GenericSample<double> b = generic_vndf_sample(0.5, g, v, l, Vec2d(0.3, 0.6), G2Form::Uncorrelated);
    if (a.weight > 0) {
      // Height-correlated G2/G1 = G1(l)/(G1(l) + G1(v) − G1(l)G1(v)) ≥ G1(l) = uncorrelated; equal only if
      // G1(v) = 1.
      const double gl = g.G1(l), gv = g.G1(v);
      EXPECT_NEAR(b.weight, gl, 1e-15);
      EXPECT_NEAR(a.weight, gl / (gl + gv - gl * gv), 1e-15);
      EXPECT_GT(a.weight, b.weight);
    }
  }
}

// The Monte Carlo estimator of Zurita 2026b (Owen-scrambled Sobol, float) converges to the exact term;
// independent seeds scatter around it.
TEST(MicroShadowingEstimate, ConvergesToExact) {
  Pcg32 rng(41);
  for (int t = 0; t < 20; ++t) {
    const float V = 0.5f + 0.5f * rng.next_float(), a = 0.1f + 0.9f * rng.next_float();
    const Vec3d vd = dir(0.1 + 0.9 * rng.next_double(), 2 * kPi<double> * rng.next_double());
    const Vec3d ld = dir(0.1 + 0.9 * rng.next_double(), 2 * kPi<double> * rng.next_double());
    const double e = generic_vndf_exact(V, a, a, vd, ld);
    const float est =
        generic_vndf_estimate(V, GGX<float>(a), Vec3f(vd), Vec3f(ld), 1 << 16, G2Form::HeightCorrelated, 3);
    EXPECT_NEAR(est, e, 2e-3) << t;
    double mean = 0;
    for (uint32_t s = 1; s <= 32; ++s)
      mean += generic_vndf_estimate(double(V), GGX<double>(a), vd, ld, 64, G2Form::HeightCorrelated, s) / 32;
    EXPECT_NEAR(mean, e, 0.02) << t;
  }
}
