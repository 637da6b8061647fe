// NDFs, Smith Λ/G1/G2 forms, approximations and the GGX albedo, each against an independent reference:
// numerical quadrature on the sphere (tests/support/chi2.h's adaptive rule), closed forms in double,
// published values.
#include <gtest/gtest.h>
#include <microshadow/microfacet/albedo.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/blinn_phong.h>
#include <microshadow/microfacet/bounded_vndf.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/gtr.h>
#include <microshadow/microfacet/masking.h>
#include <microshadow/microfacet/roughness.h>

#include <functional>

#include "support/chi2.h"

using namespace msh;

namespace {

constexpr double kTwoPi = 2 * kPi<double>;

double integrate_upper(const std::function<double(const Vec3d&)>& f, double tol = 1e-8) {
  return msh::test::integrate_sphere_rect(f, 0.0, 1.0, 0.0, kTwoPi, tol);
}
Vec3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
// Heitz 2014: Λ(v) = (1/μ) ∫ D(m) (−v·m)⁺ dm, for any NDF; an independent 2D quadrature.
template <class NDF>
double lambda_numeric(const NDF& ndf, const Vec3d& v) {
  return integrate_upper([&](const Vec3d& m) { return ndf.D(m) * std::max(0.0, -dot(v, m)); }, 1e-9) / v.z;
}

const double kAlphas[] = {0.05, 0.2, 0.5, 1.0};
const double kThetas[] = {0.0, 0.8, 1.3, 1.55};

template <class NDF>
void check_normalization_and_projected_area(const NDF& ndf, double tol_area, const char* name) {
  const double norm = integrate_upper([&](const Vec3d& m) { return ndf.D(m) * m.z; });
  EXPECT_NEAR(norm, 1.0, 1e-4) << name;
  for (double th : kThetas)
    for (double ph : {0.7}) {
      const Vec3d v = dir(th, ph);
      const double area =
          integrate_upper([&](const Vec3d& m) { return ndf.G1(v, m) * ndf.D(m) * std::max(0.0, dot(v, m)); });
      EXPECT_NEAR(area, v.z, tol_area) << name << " theta " << th << " phi " << ph;
    }
}

}  // namespace

// ---- Normalization ∫D(m)(n·m)dm = 1 and the projected area ∫G1 D (v·m)⁺ dm = n·v (RTR4 9.21, 9.23).
TEST(MicrofacetNdf, GgxNormalizationAndProjectedArea) {
  for (double a : kAlphas) {
    check_normalization_and_projected_area(GGX<double>(a), 1e-4, "ggx iso");
    check_normalization_and_projected_area(GGX<double>(a, 0.5 * a + 0.1), 1e-4, "ggx aniso");
  }
}
TEST(MicrofacetNdf, BeckmannNormalizationAndProjectedArea) {
  for (double a : kAlphas) {
    check_normalization_and_projected_area(Beckmann<double>(a), 1e-4, "beckmann iso");
    check_normalization_and_projected_area(Beckmann<double>(a, 0.5 * a + 0.1), 1e-4, "beckmann aniso");
  }
}
TEST(MicrofacetNdf, GtrNormalizationAndProjectedArea) {
  for (double a : kAlphas)
    for (double g : {1.0, 1.5, 2.0, 3.0})
      check_normalization_and_projected_area(GTR<double>(a, g), 1e-4, "gtr");
}
TEST(MicrofacetNdf, BlinnPhongNormalizationAndApproximateProjectedArea) {
  // D is normalized exactly (9.40). Λ comes from the Beckmann equivalence αb = sqrt(2/(αp + 2)) (Walter et
  // al. 2007), which becomes exact as the surface gets smoother: the projected-area identity
  // ∫ G1 D (v·m)⁺ dm = n·v then holds only approximately, with an error that must shrink as αp grows. The
  // worst errors (0.035 at αp = 2, 0.006 at αp = 10) are reported in docs/microfacet.md.
  double previous = 1e300;
  for (double ap : {2.0, 10.0, 100.0, 1000.0}) {
    const BlinnPhong<double> bp(ap);
    const double norm = integrate_upper([&](const Vec3d& m) { return bp.D(m) * m.z; });
    EXPECT_NEAR(norm, 1.0, 1e-4) << ap;
    double worst = 0;
    for (double th : kThetas) {
      const Vec3d v = dir(th, 0.3);
      const double area =
          integrate_upper([&](const Vec3d& m) { return bp.G1(v, m) * bp.D(m) * std::max(0.0, dot(v, m)); });
      worst = std::max(worst, std::abs(area - v.z));
    }
    EXPECT_LT(worst, previous) << "the error does not shrink at alpha_p " << ap;
    EXPECT_LT(worst, 0.1) << "alpha_p " << ap;  // an approximation of a unit-range quantity, not a guess
    previous = worst;
    RecordProperty("blinn_phong_area_err_" + std::to_string(int(ap)), std::to_string(worst));
  }
  EXPECT_LT(previous, 0.01);  // αp = 1000: αb = 0.045, where the equivalence is close to exact
}

TEST(MicrofacetNdf, ClosedFormsMatchRtr4Equations) {
  // 9.41 (GGX), 9.35 (Beckmann), 9.40 (Blinn-Phong), 9.46 (GTR) written in θ, evaluated independently.
  for (double a : {0.1, 0.5, 1.0})
    for (double th : {0.0, 0.3, 1.0, 1.5}) {
      const Vec3d m = dir(th, 0.4);
      const double c = std::cos(th), c2 = c * c;
      EXPECT_NEAR(GGX<double>(a).D(m), a * a / (kPi<double> * sqr(1 + c2 * (a * a - 1))),
                  1e-12 * (1 + 1 / a));
      const double db = std::exp((c2 - 1) / (a * a * c2)) / (kPi<double> * a * a * c2 * c2);
      EXPECT_NEAR(Beckmann<double>(a).D(m), db, 1e-12 * (1 + db));
      EXPECT_NEAR(GTR<double>(a, 2.0).D(m), GGX<double>(a).D(m), 1e-12 * (1 + GGX<double>(a).D(m)));
      const double k1 = a == 1.0 ? 1.0 : (a * a - 1) / std::log(a * a);
      EXPECT_NEAR(GTR<double>(a, 1.0).D(m), k1 / (kPi<double> * (1 + c2 * (a * a - 1))), 1e-12);
    }
  EXPECT_NEAR(BlinnPhong<double>(20).D(dir(0.3, 0)), 22 / (2 * kPi<double>)*std::pow(std::cos(0.3), 20),
              1e-12);
  // Anisotropic 9.52 / 9.53 at a tangent-plane direction.
  const Vec3d m = normalize(Vec3d(0.3, -0.2, 0.9));
  const double ax = 0.2, ay = 0.4, e = (sqr(m.x / ax) + sqr(m.y / ay)) / sqr(m.z);
  EXPECT_NEAR(Beckmann<double>(ax, ay).D(m), std::exp(-e) / (kPi<double> * ax * ay * std::pow(m.z, 4)),
              1e-10);
  EXPECT_NEAR(GGX<double>(ax, ay).D(m),
              1 / (kPi<double> * ax * ay * sqr(sqr(m.x / ax) + sqr(m.y / ay) + m.z * m.z)), 1e-10);
}

// ---- Smith Λ against the independent integral (Heitz 2014).
TEST(MicrofacetLambda, ExactFormsMatchNumericalIntegral) {
  for (double a : {0.1, 0.5, 1.0})
    for (double th : {0.3, 1.0, 1.4})
      for (double ph : {1.0}) {
        const Vec3d v = dir(th, ph);
        const GGX<double> g(a, 0.7 * a);
        const Beckmann<double> b(a, 0.7 * a);
        const double lg = lambda_numeric(g, v), lb = lambda_numeric(b, v);
        // The 2D quadrature of this kinked integrand is good to ~1e-5 (the 1D GTR rule, tested below at γ =
        // 2, reaches 1e-9 against the GGX closed form).
        EXPECT_NEAR(g.Lambda(v), lg, 3e-5 * (1 + lg)) << a << " " << th;
        EXPECT_NEAR(b.Lambda(v), lb, 3e-5 * (1 + lb)) << a << " " << th;
      }
}
TEST(MicrofacetLambda, GtrTableMatchesGgxClosedFormAtGamma2) {
  for (double a : {0.01, 0.1, 0.3, 0.7, 1.0}) {
    const GTR<double> t(a, 2.0);
    const GGX<double> g(a);
    for (int i = 1; i < 400; ++i) {
      const Vec3d v = dir(i / 400.0 * 0.5 * kPi<double>, 0.2);
      EXPECT_NEAR(t.Lambda(v), g.Lambda(v), 1e-5 * g.Lambda(v) + 1e-12) << a << " " << i;
      EXPECT_NEAR(t.G1(v), g.G1(v), 1e-7);
    }
  }
}
TEST(MicrofacetLambda, GtrTableMatchesNumericalIntegralOtherGammas) {
  for (double a : {0.1, 0.5})
    for (double gm : {1.0, 1.5, 3.0}) {
      const GTR<double> t(a, gm);
      for (double th : {0.2, 0.8, 1.3, 1.5}) {
        const Vec3d v = dir(th, 0);
        const double ln = lambda_numeric(t, v);
        EXPECT_NEAR(t.Lambda(v), ln, 1e-5 * ln + 1e-9) << a << " " << gm << " " << th;
      }
    }
}
TEST(MicrofacetLambda, BeckmannRationalApproximationWithinStatedError) {
  // Walter et al. 2007: the rational G1 is within 0.35% of the exact Beckmann G1.
  double worst = 0;
  for (int i = 1; i <= 20000; ++i) {
    const double a = i * 2e-4;
    const double ge = 1 / (1 + Beckmann<double>::lambda_of_a(a)),
                 ga = 1 / (1 + Beckmann<double>::lambda_approx_of_a(a));
    worst = std::max(worst, std::abs(ga - ge) / ge);
  }
  EXPECT_LT(worst, 0.0035);
  RecordProperty("beckmann_g1_approx_max_rel_err", std::to_string(worst));
}
TEST(MicrofacetLambda, BlinnPhongUsesBeckmannEquivalence) {
  EXPECT_NEAR(blinn_phong_exponent_from_beckmann(0.5), 6.0, 1e-12);
  EXPECT_NEAR(beckmann_alpha_from_blinn_phong(6.0), 0.5, 1e-12);
  const BlinnPhong<double> bp(6.0);
  const Vec3d v = dir(1.1, 0.2);
  EXPECT_EQ(bp.Lambda(v), Beckmann<double>(0.5).Lambda(v));
}

// ---- G2 forms (9.27–9.32) and the GGX visibility closed forms (9.43–9.45).
TEST(MicrofacetMasking, G2FormsPropertiesAndLimits) {
  const GGX<double> g(0.4, 0.25);
  Pcg32 rng(11);
  auto rnd_dir = [&] { return sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double())); };
  for (int i = 0; i < 20000; ++i) {
    const Vec3d v = rnd_dir(), l = rnd_dir(), m = normalize(v + l);
    const double g1v = g.G1(v, m), g1l = g.G1(l, m), mn = std::min(g1v, g1l);
    const double sep = G2_separable(g, v, l, m), hc = G2_height_correlated(g, v, l, m);
    const double dc = G2_direction_correlated(g, v, l, m, lambda_ashikhmin<double>);
    const double dc2 = G2_direction_correlated(g, v, l, m, lambda_van_ginneken<double>);
    const double hdc = G2_height_direction_correlated(g, v, l, m, lambda_ashikhmin<double>);
    for (double x : {sep, hc, dc, dc2, hdc}) {
      EXPECT_LE(x, mn + 1e-15);  // G2 ≤ min(G1(v), G1(l)) holds for every form
      EXPECT_GE(x, 0.0);
    }
    EXPECT_LE(sep, hc + 1e-15);  // uncorrelated over-darkens
    EXPECT_LE(hc, hdc + 1e-15);  // λ ≤ 1 shrinks the denominator
    // Reciprocity.
    EXPECT_NEAR(hc, G2_height_correlated(g, l, v, m), 1e-15);
    EXPECT_NEAR(hdc, G2_height_direction_correlated(g, l, v, m, lambda_ashikhmin<double>), 1e-15);
    EXPECT_NEAR(dc, G2_direction_correlated(g, l, v, m, lambda_ashikhmin<double>), 1e-15);
    // Height-correlated equals 1/(1 + Λv + Λl) (9.31) directly.
    EXPECT_NEAR(hc, 1 / (1 + g.Lambda(v) + g.Lambda(l)), 1e-12);
    // 9.32 with λ from 9.29, directly.
    const double lv = g.Lambda(v), ll = g.Lambda(l), lam = lambda_ashikhmin(relative_azimuth(v, l));
    EXPECT_NEAR(hdc, 1 / (1 + std::max(lv, ll) + lam * std::min(lv, ll)), 1e-12);
  }
  // φ = 0: the direction-correlated forms reduce to min(G1, G1) (heightfield property).
  const Vec3d v = dir(1.0, 0.3), l = dir(0.5, 0.3), m = normalize(v + l);
  EXPECT_NEAR(G2_direction_correlated(g, v, l, m, lambda_ashikhmin<double>), std::min(g.G1(v, m), g.G1(l, m)),
              1e-12);
  EXPECT_NEAR(G2_height_direction_correlated(g, v, l, m, lambda_van_ginneken<double>),
              std::min(g.G1(v), g.G1(l)), 1e-12);
  // v = l: every correlated form gives G1; the separable one G1².
  EXPECT_NEAR(G2_height_direction_correlated(g, v, v, normalize(v + v), lambda_ashikhmin<double>), g.G1(v),
              1e-12);
  EXPECT_NEAR(G2_separable(g, v, v, v), sqr(g.G1(v)), 1e-12);
  // Limits: α → 0 and n·v → 1 give G → 1.
  const GGX<double> smooth(1e-4);
  EXPECT_NEAR(smooth.G2(dir(1.2, 0), dir(1.3, 2)), 1.0, 1e-6);
  EXPECT_NEAR(g.G1(Vec3d(0, 0, 1)), 1.0, 1e-15);
  EXPECT_NEAR(Beckmann<double>(0.7).G1(Vec3d(0, 0, 1)), 1.0, 1e-15);
  EXPECT_NEAR(GTR<double>(0.7, 1.5).G1(Vec3d(0, 0, 1)), 1.0, 1e-12);
  // Published λ values: 9.29 at σ = 15° ~ 0.26 rad: 1 − e^{−7.3·0.0676}; 9.30 at φ = 1/4.41: 1/2.
  EXPECT_NEAR(lambda_van_ginneken(1 / 4.41), 0.5, 1e-12);
  EXPECT_NEAR(lambda_ashikhmin(0.0), 0.0, 1e-15);
}

TEST(MicrofacetMasking, GgxVisibilityClosedFormsAndApproximations) {
  double worst_karis = 0, worst_hammon = 0;
  for (double a : {0.01, 0.1, 0.3, 0.6, 1.0})
    for (int i = 1; i <= 50; ++i)
      for (int j = 1; j <= 50; ++j) {
        const double mo = i / 50.0, mi = j / 50.0;
        const GGX<double> g(a);
        const Vec3d v(std::sqrt(1 - mo * mo), 0, mo), l(-std::sqrt(1 - mi * mi), 0, mi);
        const double exact = g.G2(v, l) / (4 * mo * mi);
        EXPECT_NEAR(ggx_visibility_height_correlated(mo, mi, a), exact, 1e-12 * exact);  // 9.43 is exact
        const double gk = karis_G1(mo, a), ge = g.G1(v);
        const double gh = hammon_visibility(mo, mi, a) * 4 * mo * mi, g2 = g.G2(v, l);
        // At α = 1 GGX's Λ is (1/μ − 1)/2, so G1 = 2μ/(1 + μ) and the height-correlated G2 = 2μoμi/(μo + μi):
        // both approximations are exact there (Karis 2013 states it for his G1).
        if (a == 1.0) {
          EXPECT_NEAR(gk, ge, 1e-12) << mo;
          EXPECT_NEAR(gh, g2, 1e-12) << mo << ' ' << mi;
        }
        worst_karis = std::max(worst_karis, std::abs(gk - ge));
        worst_hammon = std::max(worst_hammon, std::abs(gh - g2));
      }
  // The formulas at hand-computed points (9.44, 9.45): Karis 2μ/(μ(2 − α) + α) at μ = α = 0.5 is 0.8; Hammon
  // 0.5/lerp(2μoμi, μo + μi, α) at μo = 0.5, μi = 0.25, α = 0.5 is 0.5/0.5 = 1.
  EXPECT_NEAR(karis_G1(0.5, 0.5), 0.8, 1e-15);
  EXPECT_NEAR(hammon_visibility(0.5, 0.25, 0.5), 1.0, 1e-15);
  // Smooth limit: both → the exact value 1 (G) as α → 0.
  EXPECT_NEAR(karis_G1(0.3, 1e-6), 1.0, 1e-5);
  EXPECT_NEAR(hammon_visibility(0.3, 0.6, 1e-6) * 4 * 0.3 * 0.6, 1.0, 1e-5);
  // The worst error over this grid is what docs/microfacet.md reports (not a bound: a measurement).
  RecordProperty("karis_max_abs_err", std::to_string(worst_karis));
  RecordProperty("hammon_max_abs_err", std::to_string(worst_hammon));
  std::printf("Karis G1 max |err| %.4f, Hammon G2 max |err| %.4f\n", worst_karis, worst_hammon);
}

TEST(MicrofacetRoughness, Mappings) {
  double ax, ay;
  alpha_disney_anisotropic(0.5, 0.0, ax, ay);
  EXPECT_DOUBLE_EQ(ax, 0.25);
  EXPECT_DOUBLE_EQ(ay, 0.25);
  alpha_disney_anisotropic(0.5, 1.0, ax, ay);
  EXPECT_NEAR(ax / ay, 10.0, 1e-12);  // 9.54: aspect ratio limited to 10:1
  EXPECT_NEAR(ax * ay, 0.0625, 1e-12);
  alpha_imageworks_anisotropic(0.5, 0.5, ax, ay);
  EXPECT_DOUBLE_EQ(ax, 0.375);
  EXPECT_DOUBLE_EQ(ay, 0.125);
  EXPECT_DOUBLE_EQ(roughness_to_alpha(0.5), 0.25);
  EXPECT_DOUBLE_EQ(alpha_to_roughness(0.25), 0.5);
}

// ---- Bounded VNDF: reflection pdf never below the VNDF's on valid reflections, and integrates to ≤ 1.
TEST(MicrofacetBoundedVndf, PdfDominatesVndfAndIsNormalized) {
  for (double a : {0.1, 0.6})
    for (double th : {0.3, 1.5}) {
      const GGX<double> g(a, 0.8 * a);
      const Vec3d wi = dir(th, 0.5);
      const double total = msh::test::integrate_sphere_rect(
          [&](const Vec3d& m) { return pdf_bounded_vndf(g, wi, m); }, 0, 1, 0, kTwoPi, 1e-6);
      EXPECT_NEAR(total, 1.0, 2e-3) << a << " " << th;  // discontinuous pdf: coarse quadrature bound
      const double up_b =
          integrate_upper([&](const Vec3d& o) { return pdf_bounded_vndf_reflection(g, wi, o); }, 1e-6);
      const double up_v =
          integrate_upper([&](const Vec3d& o) { return pdf_vndf_reflection(g, wi, o); }, 1e-6);
      EXPECT_GE(up_b, up_v - 1e-4);  // fewer samples wasted below the horizon
      for (int i = 0; i < 200; ++i) {
        const Vec3d o = dir((i % 20) / 20.0 * 1.5, i / 20 * 0.6);
        const double pb = pdf_bounded_vndf_reflection(g, wi, o), pv = pdf_vndf_reflection(g, wi, o);
        if (pb > 0) {
          EXPECT_GE(pb, pv * (1 - 1e-12));
        }
      }
    }
}

// ---- GGX directional albedo.
TEST(MicrofacetAlbedo, PublishedValuesAndClosedForm) {
  // docs/theory.md §2 (Blender Cycles table_ggx_E), 6 decimals.
  EXPECT_NEAR(ggx_directional_albedo(1.0, 1.0), 0.306853, 1e-6);
  EXPECT_NEAR(ggx_directional_albedo(1.0, sqr(15.0 / 31)), 0.926694, 1.5e-6);
  EXPECT_NEAR(ggx_directional_albedo(15.0 / 31, 1.0), 0.457779, 1.5e-6);
  // α = 1: D = 1/π; at μ = 1, E = 1 − ln 2 in closed form.
  EXPECT_NEAR(ggx_directional_albedo(1.0, 1.0), 1 - std::log(2.0), 1e-9);
  EXPECT_NEAR(ggx_directional_albedo(1.0f, 1.0f), float(1 - std::log(2.0)), 1e-6f);
}
TEST(MicrofacetAlbedo, MatchesIndependentQmcAndRefinedRule) {
  // QMC over visible normals: E = E_m[(1 + Λv)/(1 + Λv + Λl) χ(l.z > 0)] with m ~ VNDF (Heitz 2018 sampler),
  // 2^18 Owen-scrambled Sobol points; error ~1e-5.
  for (double a : {0.05, 0.35, 0.8})
    for (double mu : {0.1, 0.6, 1.0}) {
      const GGX<double> g(a);
      const Vec3d v(std::sqrt(1 - mu * mu), 0, mu);
      double s = 0;
      const uint32_t n = 1u << 18;
      for (uint32_t i = 0; i < n; ++i) {
        const Vec3d m = g.sample_vndf_heitz2018(v, sobol_2d<double>(i, 1234));
        const Vec3d l = reflect(v, m);
        if (l.z > 0) s += (1 + g.Lambda(v)) / (1 + g.Lambda(v) + g.Lambda(l));
      }
      const double e = ggx_directional_albedo(mu, a);
      EXPECT_NEAR(e, s / n, 5e-5) << a << " " << mu;
      EXPECT_NEAR(e, albedo_quadrature::ggx_directional_albedo_rule(mu, a, 24, 2.0), 1e-7) << a << " " << mu;
    }
}
TEST(MicrofacetAlbedo, LimitsAndBounds) {
  EXPECT_EQ(ggx_directional_albedo(0.0, 0.5), 0.0);
  EXPECT_NEAR(ggx_directional_albedo(0.8, 1e-4), 1.0, 1e-6);  // mirror, F = 1, no masking
  for (double a : {1e-3, 0.05, 0.3, 1.0})
    for (double mu : {1e-3, 0.1, 0.5, 1.0}) {
      const double e = ggx_directional_albedo(mu, a);
      EXPECT_GT(e, 0.0);
      EXPECT_LE(e, 1.0);
      EXPECT_NEAR(e, albedo_quadrature::ggx_directional_albedo_rule(mu, a, 24, 2.0), 1e-6) << a << " " << mu;
    }
}
