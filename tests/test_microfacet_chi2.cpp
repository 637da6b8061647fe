// Tests of the chi-square goodness-of-fit harness itself (tests/support/chi2.h): the p-value function against
// closed forms, correct samplers pass, wrong pdfs and out-of-support samples fail.
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>

#include "support/chi2.h"

using namespace msh;
using msh::test::chi2_test_directions;

namespace {

using msh::test::Uniforms;

// The samplers under test, each drawing from u's next pair (never rejecting).
auto cosine_draws(Uniforms& u) {
  return [&u](uint32_t) { return std::optional<Vec3d>(sample_cosine_hemisphere(u.next())); };
}
auto sphere_draws(Uniforms& u) {
  return [&u](uint32_t) { return std::optional<Vec3d>(sample_uniform_sphere(u.next())); };
}
auto vndf_draws(const GGX<double>& g, const Vec3d& wo, Uniforms& u) {
  return [&g, wo, &u](uint32_t) { return std::optional<Vec3d>(g.Sample_wm(wo, u.next())); };
}

// The uniform pdfs of the whole sphere and of the upper hemisphere (zero below).
double sphere_pdf(const Vec3d&) { return 0.25 * kInvPi<double>; }
double upper_hemisphere_pdf(const Vec3d& w) { return w.z > 0 ? 0.5 * kInvPi<double> : 0.0; }

}  // namespace

TEST(Chi2Support, GammaQMatchesClosedForms) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 40.0}) {
    EXPECT_NEAR(msh::test::regularized_gamma_q(1.0, x), std::exp(-x), 1e-13 + 1e-12 * std::exp(-x));
    EXPECT_NEAR(msh::test::regularized_gamma_q(0.5, x), std::erfc(std::sqrt(x)), 1e-12);
    // Q(2, x) = e^{-x}(1 + x)  (χ² survival, 4 dof, at 2x)
    EXPECT_NEAR(msh::test::regularized_gamma_q(2.0, x), std::exp(-x) * (1 + x), 1e-12);
  }
  // Published χ² critical value: P(χ²_100 > 135.807) = 0.01 (NIST/SEMATECH table).
  EXPECT_NEAR(msh::test::regularized_gamma_q(50.0, 135.807 / 2), 0.01, 2e-5);
  EXPECT_EQ(msh::test::regularized_gamma_q(3.0, 0.0), 1.0);
}

TEST(Chi2Support, QuadratureIntegratesPeakedPdf) {
  // GGX NDF at α = 0.02 projected (D·cos) integrates to 1 over the upper hemisphere.
  const GGX<double> g(0.02);
  auto pdf = [&](const Vec3d& m) { return g.pdf_ndf(m); };
  EXPECT_NEAR(msh::test::integrate_sphere_rect(pdf, 0.0, 1.0, 0.0, 2 * kPi<double>, 1e-9), 1.0, 1e-6);
}

TEST(Chi2Support, CosineHemispherePasses) {
  Uniforms u(1);
  auto r = chi2_test_directions(cosine_draws(u), [](const Vec3d& w) { return cosine_hemisphere_pdf(w.z); });
  EXPECT_TRUE(r.pass) << r.table;
  EXPECT_GT(r.dof, 1000);
}

TEST(Chi2Support, UniformSpherePasses) {
  Uniforms u(2);
  auto r = chi2_test_directions(sphere_draws(u), sphere_pdf, 200000);
  EXPECT_TRUE(r.pass) << r.table;
}

TEST(Chi2Support, RejectedSamplesCountTowardNothing) {
  // Uniform sphere samples, lower half rejected: the pdf of the process is 1/(4π) on the upper hemisphere
  // only.
  Uniforms u(3);
  auto r = chi2_test_directions(
      [&](uint32_t) -> std::optional<Vec3d> {
        const Vec3d w = sample_uniform_sphere(u.next());
        if (w.z < 0) return std::nullopt;
        return w;
      },
      [](const Vec3d& w) { return w.z >= 0 ? sphere_pdf(w) : 0.0; }, 200000);
  EXPECT_TRUE(r.pass) << r.table;
}

TEST(Chi2Support, WrongPdfFails) {
  Uniforms u(4);
  // Cosine-distributed samples against the uniform-hemisphere pdf.
  auto r = chi2_test_directions(cosine_draws(u), upper_hemisphere_pdf, 100000);
  EXPECT_FALSE(r.pass);
  EXPECT_LT(r.p_value, 1e-10);
  EXPECT_FALSE(r.table.empty());
}

TEST(Chi2Support, SubtlyWrongPeakedPdfFails) {
  // GGX VNDF samples at α = 0.05 against the VNDF of α = 0.0525 (5% off): the peak is inside one θ row.
  Uniforms u(5);
  const GGX<double> g(0.05), wrong(0.0525);
  const Vec3d wo = normalize(Vec3d(0.6, 0.2, 0.75));
  auto r = msh::test::chi2_test_directions_stretched(
      vndf_draws(g, wo, u), [&](const Vec3d& m) { return wrong.PDF(wo, m); }, 0.05, 0.05);
  EXPECT_FALSE(r.pass) << "p = " << r.p_value;
}

TEST(Chi2Support, PeakedVndfPasses) {
  Uniforms u(6);
  const GGX<double> g(0.05);
  const Vec3d wo = normalize(Vec3d(0.6, 0.2, 0.75));
  auto r = chi2_test_directions(vndf_draws(g, wo, u), [&](const Vec3d& m) { return g.PDF(wo, m); });
  EXPECT_TRUE(r.pass) << r.table;
}

TEST(Chi2Support, PeakedVndfPassesStretched) {
  Uniforms u(6);
  const GGX<double> g(0.05, 0.02);
  const Vec3d wo = normalize(Vec3d(0.6, 0.2, 0.75));
  auto r = msh::test::chi2_test_directions_stretched(
      vndf_draws(g, wo, u), [&](const Vec3d& m) { return g.PDF(wo, m); }, 0.05, 0.02);
  EXPECT_TRUE(r.pass) << r.table;
}

TEST(Chi2Support, StretchedUniformSpherePasses) {
  // The stretch is a bijection of the sphere with a known Jacobian: uniform samples still match 1/(4π).
  Uniforms u(10);
  auto r = msh::test::chi2_test_directions_stretched(sphere_draws(u), sphere_pdf, 0.3, 0.6, 200000);
  EXPECT_TRUE(r.pass) << r.table;
}

TEST(Chi2Support, SampleInZeroMassCellFails) {
  Uniforms u(7);
  // Uniform sphere samples against a pdf that is zero below the horizon (and twice as large above).
  auto r = chi2_test_directions(sphere_draws(u), upper_hemisphere_pdf, 100000);
  EXPECT_FALSE(r.pass);
  EXPECT_NE(r.table.find("has pdf 0"), std::string::npos);
}

TEST(Chi2Support, NonUnitSampleFails) {
  Uniforms u(8);
  auto r = chi2_test_directions(
      [&](uint32_t i) {
        const Vec3d w = sample_uniform_sphere(u.next());
        return std::optional<Vec3d>(i == 17 ? w * 2.0 : w);
      },
      sphere_pdf, 50000);
  EXPECT_FALSE(r.pass);
}

TEST(Chi2Support, SidakCorrectionLowersThreshold) {
  // One fixed run with a mildly wrong pdf (1% of the mass moved to a uniform lobe), judged alone and as one
  // of 1e6 runs. Its p-value lies between the two thresholds, so the verdict must flip.
  auto run = [](int n_tests) {
    Uniforms u(9);
    return chi2_test_directions(
        cosine_draws(u),
        [](const Vec3d& w) {
          return w.z > 0 ? 0.99 * cosine_hemisphere_pdf(w.z) + 0.01 * 0.5 * kInvPi<double> : 0.0;
        },
        500000, 10, 10, 0.01, n_tests);
  };
  const auto one = run(1), many = run(1000000);
  EXPECT_EQ(one.statistic, many.statistic);
  ASSERT_LT(one.p_value, 0.01);
  ASSERT_GT(one.p_value, 1.0 - std::pow(0.99, 1e-6));
  EXPECT_FALSE(one.pass);
  EXPECT_TRUE(many.pass);
}
