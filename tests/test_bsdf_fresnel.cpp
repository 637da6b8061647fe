// Fresnel terms (include/microshadow/bsdf/fresnel.h) against independent forms: the angle form of the Fresnel
// equations, the a²+b² conductor form (Cook & Torrance 1982, as in pbrt-v3), closed-form averages vs
// numerical integration (composite Simpson, not the library's Gauss-Legendre), and the reciprocity identity
// of averages.
#include <gtest/gtest.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/math/quadrature.h>

using namespace msh;
using namespace msh::bsdf;

namespace {

// Composite Simpson on [0,1] with n (even) intervals.
template <class F>
double simpson01(F&& f, int n = 20000) {
  const double h = 1.0 / n;
  double s = f(0.0) + f(1.0);
  for (int i = 1; i < n; ++i) s += f(i * h) * (i % 2 ? 4.0 : 2.0);
  return s * h / 3.0;
}

// Fresnel equations in angle form: r_s = −sin(θi − θt)/sin(θi + θt), r_p = tan(θi − θt)/tan(θi + θt).
double fresnel_angle_form(double cos_i, double eta) {
  const double ti = std::acos(cos_i);
  const double st = std::sin(ti) / eta;
  if (st >= 1) return 1;
  const double tt = std::asin(st);
  if (ti < 1e-9) return sqr((eta - 1) / (eta + 1));
  const double rs = -std::sin(ti - tt) / std::sin(ti + tt);
  const double rp = std::tan(ti - tt) / std::tan(ti + tt);
  return 0.5 * (rs * rs + rp * rp);
}

// Conductor reflectance, a² + b² form (pbrt-v3 FrConductor; Cook & Torrance 1982), incident medium η = 1.
double conductor_ab_form(double c, double eta, double k) {
  const double cos2 = c * c, sin2 = 1 - cos2, eta2 = eta * eta, k2 = k * k;
  const double t0 = eta2 - k2 - sin2;
  const double a2b2 = std::sqrt(t0 * t0 + 4 * eta2 * k2);
  const double t1 = a2b2 + cos2;
  const double a = std::sqrt(0.5 * (a2b2 + t0));
  const double t2 = 2 * c * a;
  const double rs = (t1 - t2) / (t1 + t2);
  const double t3 = cos2 * a2b2 + sin2 * sin2;
  const double t4 = t2 * sin2;
  const double rp = rs * (t3 - t4) / (t3 + t4);
  return 0.5 * (rp + rs);
}

}  // namespace

TEST(Fresnel, SchlickEndpointsAndGeneralizedReducesToSchlick) {
  for (double f0 : {0.0, 0.04, 0.5, 1.0}) {
    EXPECT_DOUBLE_EQ(fresnel_schlick(f0, 1.0), f0);
    EXPECT_DOUBLE_EQ(fresnel_schlick(f0, 0.0), 1.0);
    EXPECT_DOUBLE_EQ(fresnel_schlick(f0, -0.3), 1.0);  // backfacing clamps to grazing
    for (double c : {0.1, 0.37, 0.8})
      EXPECT_NEAR(fresnel_schlick_generalized(f0, 1.0, 0.2, c), f0 + (1 - f0) * std::pow(1 - c, 5), 1e-14);
    // F90 is honoured at grazing, F0 at normal incidence, for any p.
    EXPECT_DOUBLE_EQ(fresnel_schlick_generalized(f0, 0.7, 0.05, 0.0), 0.7);
    EXPECT_DOUBLE_EQ(fresnel_schlick_generalized(f0, 0.7, 3.0, 1.0), f0);
  }
  EXPECT_TRUE(std::isfinite(fresnel_schlick_generalized(0.04, 1.0, 0.0, 0.5)));
}

TEST(Fresnel, DielectricMatchesAngleForm) {
  for (double eta : {1.0001, 1.33, 1.5, 2.4, 1 / 1.5}) {
    for (int i = 0; i <= 200; ++i) {
      const double c = i / 200.0;
      EXPECT_NEAR(fresnel_dielectric(c, eta), fresnel_angle_form(c, eta), 1e-12) << eta << " " << c;
    }
  }
  // Normal incidence, Brewster's angle (r_p = 0), total internal reflection from inside.
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.5), 0.04, 1e-15);
  const double tb = std::atan(1.5);
  const double tt = std::asin(std::sin(tb) / 1.5);
  EXPECT_NEAR(fresnel_dielectric(std::cos(tb), 1.5), 0.5 * sqr(std::sin(tb - tt) / std::sin(tb + tt)), 1e-14);
  EXPECT_EQ(fresnel_dielectric(-0.3, 1.5), 1.0);  // from inside, sin θ = 0.95 > 1/1.5
  EXPECT_EQ(fresnel_dielectric(0.0, 1.5), 1.0);
  EXPECT_TRUE(std::isfinite(fresnel_dielectric(0.5, 0.0)));
  EXPECT_NEAR(f0_from_ior(1.5), 0.04, 1e-15);
}

TEST(Fresnel, ConductorMatchesABFormAndLimits) {
  const double etas[] = {0.143, 0.2, 1.5, 2.9};
  const double ks[] = {0.0, 0.5, 3.983, 8.0};
  for (double eta : etas)
    for (double k : ks)
      for (int i = 0; i <= 100; ++i) {
        const double c = i / 100.0;
        EXPECT_NEAR(fresnel_conductor(c, eta, k), conductor_ab_form(c, eta, k), 1e-12)
            << eta << " " << k << " " << c;
      }
  for (double eta : etas)
    for (double k : ks) {
      EXPECT_NEAR(fresnel_conductor(1.0, eta, k), (sqr(eta - 1) + k * k) / (sqr(eta + 1) + k * k), 1e-14);
      EXPECT_NEAR(fresnel_conductor(0.0, eta, k), 1.0, 1e-12);
    }
  // k = 0 is a dielectric (above the critical angle when η > 1).
  for (double c : {0.05, 0.4, 0.9})
    EXPECT_NEAR(fresnel_conductor(c, 1.5, 0.0), fresnel_dielectric(c, 1.5), 1e-13);
}

TEST(Fresnel, AveragesMatchNumericalIntegrals) {
  // 9.59 (generalized Schlick) and 9.60 (Schlick) against Simpson on 2 ∫ F(μ) μ dμ (9.58).
  for (double f0 : {0.0, 0.04, 0.5, 0.9})
    for (double f90 : {1.0, 0.6})
      for (double p : {0.05, 0.2, 1.0, 3.0}) {
        const double num =
            simpson01([&](double mu) { return 2 * mu * fresnel_schlick_generalized(f0, f90, p, mu); });
        // Simpson converges slowly for p > 1 ((1 − μ)^(1/p) has an unbounded derivative at μ = 1).
        EXPECT_NEAR(fresnel_average_schlick_generalized(f0, f90, p), num, 1e-6)
            << f0 << " " << f90 << " " << p;
      }
  for (double f0 : {0.0, 0.04, 1.0}) {
    const double num = simpson01([&](double mu) { return 2 * mu * fresnel_schlick(f0, mu); });
    EXPECT_NEAR(fresnel_average_schlick<double>(f0), num, 1e-10);
  }
  for (double eta : {1.33, 1.5, 2.0}) {
    const double num = simpson01([&](double mu) { return 2 * mu * fresnel_dielectric(mu, eta); });
    EXPECT_NEAR(fresnel_average_dielectric(eta), num, 1e-7);
  }
  const double numc = simpson01([&](double mu) { return 2 * mu * fresnel_conductor(mu, 0.143, 3.983); });
  EXPECT_NEAR(fresnel_average_conductor(0.143, 3.983), numc, 1e-8);
}

TEST(Fresnel, DielectricAveragesObeyReciprocityAndPublishedFit) {
  // Energy reciprocity of the interface: η² (1 − F̄_internal) = 1 − F̄_external (e.g. Jensen et al. 2001,
  // §2.4).
  for (double eta : {1.2, 1.33, 1.5, 2.0}) {
    const double ext = fresnel_average_dielectric(eta);
    const double in = simpson01([&](double mu) { return 2 * mu * fresnel_dielectric(mu, 1 / eta); }, 200000);
    EXPECT_NEAR(eta * eta * (1 - in), 1 - ext, 2e-5) << eta;
    // Egan & Hilgeman 1979 fit of the internal diffuse reflectance, F_dr(η) = −1.440/η² + 0.710/η + 0.668 +
    // 0.0636 η (published accuracy ≈ 0.5%).
    const double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    EXPECT_NEAR(in, fdr, 0.006) << eta;
  }
}

TEST(Quadrature, GaussLegendreIsExactForPolynomials) {
  const GaussLegendre01<double> gl(8);
  double sw = 0;
  for (double w : gl.w) sw += w;
  EXPECT_NEAR(sw, 1.0, 1e-14);
  // Degree 15 is exact with 8 nodes: ∫ x^15 = 1/16.
  EXPECT_NEAR(gl.integrate([](double x) { return std::pow(x, 15); }), 1.0 / 16, 1e-14);
}
