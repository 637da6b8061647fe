// Specular microfacet BRDF (9.34), the two-lobe GGX NDF and the runtime specular models: published albedo
// values (Blender Cycles table_ggx_E, docs/theory.md §2), the closed-form GGX visibility 9.43, NDF/VNDF
// normalization of the mixture (9.21, 9.23) by adaptive quadrature, QMC albedo vs quadrature albedo, the
// mirror limit, chi-square of every specular sampler against its pdf.
#include <gtest/gtest.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/runtime/albedo.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/masking.h>

#include "support/chi2.h"

using namespace msh;
using namespace msh::bsdf;

namespace {

double choice(const std::string& model, const std::string& param, const std::string& value) {
  for (const auto& p : find_brdf_model(model).params)
    if (p.name == param)
      for (size_t i = 0; i < p.choices.size(); ++i)
        if (p.choices[i] == value) return double(i);
  ADD_FAILURE() << model << " " << param << " " << value;
  return 0;
}
Vec3d dir(double mu, double phi = 0) { return spherical_direction(mu, phi); }

// ∫ f(wo, wi) cos θi dωi over the upper hemisphere by the adaptive quadrature of the chi-square harness.
double quadrature_albedo(const BrdfModel& m, const Vec3d& wo, double tol = 1e-7) {
  double s = 0;
  const int nphi = 8;
  for (int k = 0; k < nphi; ++k)
    s += msh::test::integrate_sphere_rect(
        [&](const Vec3d& wi) { return m.f(wo, wi).g * std::max(0.0, wi.z); }, 0, 1,
        2 * kPi<double> * k / nphi, 2 * kPi<double> * (k + 1) / nphi, tol);
  return s;
}

using msh::test::Uniforms;

void expect_sampler_matches_pdf(const BrdfModel& m, const Vec3d& wo, const std::string& what,
                                int n = 400000) {
  Uniforms u(hash_u32(uint32_t(std::hash<std::string>{}(what))));
  const auto r = msh::test::chi2_test_directions(
      [&](uint32_t) -> std::optional<Vec3d> {
        const auto s = m.sample(wo, u.next());
        if (!s) return std::nullopt;
        return s->wi;
      },
      [&](const Vec3d& wi) { return m.pdf(wo, wi); }, n, 30, 60);
  EXPECT_TRUE(r.pass) << what << ": p = " << r.p_value << "\n" << r.table;
}

}  // namespace

TEST(Specular, PublishedGgxAlbedoValues) {
  // Blender Cycles table_ggx_E (F = 1, height-correlated): E(1, 1) = 0.306853 (= 1 − ln 2),
  // E(1, (15/31)²) = 0.926694, E(15/31, 1) = 0.457779.
  const double none = choice("ggx", "fresnel", "none");
  struct Case {
    double mu, r, e;
  } cases[] = {{1.0, 1.0, 0.306853}, {1.0, 15.0 / 31, 0.926694}, {15.0 / 31, 1.0, 0.457779}};
  for (const auto& c : cases) {
    const auto m = make_brdf("ggx", {{"roughness", {c.r}}, {"fresnel", {none}}});
    // r is perceptual: α = r² = (15/31)² means r = 15/31.
    EXPECT_NEAR(directional_albedo(*m, c.mu, 1u << 20).r, c.e, 1e-4) << c.mu << " " << c.r;
  }
  EXPECT_NEAR(1 - std::log(2.0), 0.306853, 1e-6);
}

TEST(Specular, HeightCorrelatedVisibilityMatchesClosedForm943) {
  // G2/(4 μo μi) for GGX = 0.5 / (μo sqrt(α² + μi(μi − α²μi)) + μi sqrt(α² + μo(μo − α²μo))) (9.43).
  Pcg32 rng(3);
  for (int i = 0; i < 2000; ++i) {
    const double alpha = 0.02 + 0.98 * rng.next_double();
    const GGX<double> g(alpha);
    const Vec3d wo = dir(0.02 + 0.98 * rng.next_double(), 0.0);
    const Vec3d wi = dir(0.02 + 0.98 * rng.next_double(), 2 * kPi<double> * rng.next_double());
    const auto e = microfacet_specular(g, wo, wi);
    const Vec3d h = normalize(wo + wi);
    const double a2 = alpha * alpha, mo = wo.z, mi = wi.z;
    const double vis =
        0.5 / (mo * std::sqrt(a2 + mi * (mi - a2 * mi)) + mi * std::sqrt(a2 + mo * (mo - a2 * mo)));
    // D from 9.41 (isotropic form), independent of ggx.h's anisotropic expression.
    const double d = a2 / (kPi<double> * sqr(1 + h.z * h.z * (a2 - 1)));
    EXPECT_NEAR(e.f1, d * vis, 1e-9 * (1 + d * vis));
    EXPECT_NEAR(e.cos_hl, dot(h, wi), 1e-12);
    // Separable G2 ≤ height-correlated G2 (its denominator G1o + G1i − G1o G1i ≤ 1).
    EXPECT_LE(microfacet_specular(g, wo, wi, G2Form::Separable).f1, e.f1 * (1 + 1e-12));
  }
}

TEST(Specular, CustomG2MatchesCoreMaskingForms) {
  // specular.h's G2 forms vs the core's microfacet/masking.h (written separately), through the custom-G2
  // entry.
  Pcg32 rng(8);
  const Beckmann<double> b(0.4, 0.25);
  const GGX<double> g(0.3, 0.6);
  for (int i = 0; i < 1000; ++i) {
    const Vec3d wo = dir(0.05 + 0.95 * rng.next_double(), 2 * kPi<double> * rng.next_double());
    const Vec3d wi = dir(0.05 + 0.95 * rng.next_double(), 2 * kPi<double> * rng.next_double());
    const auto hc = microfacet_specular_custom_g2(
        b, wo, wi,
        [&](const Vec3d& o, const Vec3d& l, const Vec3d& h) { return G2_height_correlated(b, o, l, h); });
    EXPECT_NEAR(microfacet_specular(b, wo, wi).f1, hc.f1, 1e-12 * (1 + hc.f1));
    const auto sep = microfacet_specular_custom_g2(
        g, wo, wi, [&](const Vec3d& o, const Vec3d& l, const Vec3d& h) { return G2_separable(g, o, l, h); });
    EXPECT_NEAR(microfacet_specular(g, wo, wi, G2Form::Separable).f1, sep.f1, 1e-12 * (1 + sep.f1));
  }
}

TEST(Specular, DegenerateInputsAreFiniteAndZero) {
  const GGX<double> g(0.3);
  EXPECT_EQ(microfacet_specular(g, Vec3d(0, 0, 1), Vec3d(0, 0, -1)).f1, 0.0);     // below the horizon
  EXPECT_EQ(microfacet_specular(g, Vec3d(1, 0, 0), Vec3d(-1, 0, 0)).f1, 0.0);     // grazing, l = −v
  EXPECT_EQ(microfacet_specular(g, Vec3d(1, 0, 0), Vec3d(0.6, 0, 0.8)).f1, 0.0);  // grazing view
  EXPECT_EQ(microfacet_specular_pdf(g, Vec3d(0, 0, 1), Vec3d(0, 0, -1)), 0.0);
  const GGX<float> gf(0.0f);  // α = 0 is clamped
  const auto e = microfacet_specular(gf, Vec3f(0, 0, 1), Vec3f(0, 0, 1));
  EXPECT_TRUE(std::isfinite(e.f1));
  EXPECT_GT(e.f1, 0.0f);
  EXPECT_FALSE(sample_microfacet_specular(g, Vec3d(0, 0, -1), Vec2d(0.5, 0.5)).has_value());
}

TEST(Specular, MixtureNdfAndVndfAreNormalized) {
  // ∫ D(m)(n·m) dm = 1 (9.21) and ∫ G1(v) D(m) (v·m)⁺ dm = n·v (9.23) for the two-lobe NDF with the mixed Λ.
  const GGXMixture<double> mix(GGX<double>(0.05), GGX<double>(0.6), 0.35);
  double s = 0;
  for (int k = 0; k < 4; ++k)
    s += msh::test::integrate_sphere_rect([&](const Vec3d& m) { return mix.D(m) * std::max(0.0, m.z); }, 0, 1,
                                          kPi<double> * k / 2, kPi<double> * (k + 1) / 2, 1e-8);
  EXPECT_NEAR(s, 1.0, 1e-5);
  for (double mu : {0.1, 0.5, 0.95}) {
    const Vec3d v = dir(mu, 0.3);
    double t = 0;
    for (int k = 0; k < 4; ++k)
      t += msh::test::integrate_sphere_rect(
          [&](const Vec3d& m) { return mix.G1(v) * mix.D(m) * std::max(0.0, dot(v, m)); }, 0, 1,
          kPi<double> * k / 2, kPi<double> * (k + 1) / 2, 1e-8);
    EXPECT_NEAR(t, mu, 1e-4 * (1 + mu)) << mu;
  }
  // w = 0 and w = 1 reduce to the single lobes.
  const Vec3d v = dir(0.4, 0.0), m = normalize(Vec3d(0.1, 0.2, 1.0));
  const GGXMixture<double> m0(GGX<double>(0.2), GGX<double>(0.7), 0.0),
      m1(GGX<double>(0.2), GGX<double>(0.7), 1.0);
  EXPECT_NEAR(m0.D(v, m), GGX<double>(0.2).D(v, m), 1e-12);
  EXPECT_NEAR(m1.D(v, m), GGX<double>(0.7).D(v, m), 1e-12);
}

TEST(Specular, QmcAlbedoMatchesQuadrature) {
  const double none = choice("ggx", "fresnel", "none");
  for (double r : {0.5, 0.8}) {
    for (double mu : {0.2, 0.7}) {
      const auto m = make_brdf("ggx", {{"roughness", {r}}, {"fresnel", {none}}});
      EXPECT_NEAR(directional_albedo(*m, mu, 1u << 18).g, quadrature_albedo(*m, dir(mu)), 2e-4)
          << r << " " << mu;
    }
  }
  const auto d = make_brdf("ggx-dual", {{"roughness", {0.5}},
                                        {"roughness2", {0.9}},
                                        {"mix", {0.4}},
                                        {"fresnel", {choice("ggx-dual", "fresnel", "dielectric")}}});
  EXPECT_NEAR(directional_albedo(*d, 0.6, 1u << 18).g, quadrature_albedo(*d, dir(0.6)), 2e-4);
  const auto b = make_brdf("beckmann", {{"roughness", {0.7}}, {"fresnel", {none}}, {"g2", {1.0}}});
  EXPECT_NEAR(directional_albedo(*b, 0.35, 1u << 18).g, quadrature_albedo(*b, dir(0.35)), 2e-4);
}

TEST(Specular, MirrorLimitReturnsFresnel) {
  // r → 0: the lobe is a mirror with G2 → 1, so the albedo is F(μ).
  for (double mu : {0.3, 0.8}) {
    const auto m =
        make_brdf("ggx", {{"roughness", {0.02}}, {"fresnel", {choice("ggx", "fresnel", "conductor")}}});
    const Rgbd e = directional_albedo(*m, mu, 1u << 14);
    EXPECT_NEAR(e.r, fresnel_conductor(mu, 0.143, 3.983), 2e-3);
    EXPECT_NEAR(e.b, fresnel_conductor(mu, 1.442, 1.603), 2e-3);
  }
}

TEST(Specular, SamplersMatchTheirPdf) {
  const double none = choice("ggx", "fresnel", "none");
  const auto g1 = make_brdf("ggx", {{"roughness", {0.3}}, {"fresnel", {none}}});
  expect_sampler_matches_pdf(*g1, dir(0.6, 0.2), "ggx r=0.3");
  const auto g2 = make_brdf("ggx", {{"roughness", {0.7}}, {"anisotropy", {0.6}}});
  expect_sampler_matches_pdf(*g2, dir(0.3, 1.0), "ggx aniso");
  const auto g3 = make_brdf("ggx", {{"roughness", {0.8}}, {"multiscatter", {1}}});
  expect_sampler_matches_pdf(*g3, dir(0.4, 0.0), "ggx + multiscatter");
  const auto d = make_brdf("ggx-dual", {{"roughness", {0.2}}, {"roughness2", {0.8}}, {"mix", {0.5}}});
  expect_sampler_matches_pdf(*d, dir(0.5, 0.0), "ggx-dual");
  const auto b = make_brdf("beckmann", {{"roughness", {0.5}}, {"anisotropy", {-0.4}}});
  expect_sampler_matches_pdf(*b, dir(0.45, 0.7), "beckmann");
  const auto k = make_brdf("ggx-ksk", {{"roughness", {0.4}}});
  expect_sampler_matches_pdf(*k, dir(0.7, 0.0), "ggx-ksk");
}

TEST(Specular, SampledValueAndPdfAgreeWithEvaluation) {
  const auto m = make_brdf("ggx-dual", {{"roughness", {0.3}}, {"roughness2", {0.7}}, {"mix", {0.25}}});
  Pcg32 rng(11);
  const Vec3d wo = dir(0.55, 0.4);
  for (int i = 0; i < 1000; ++i) {
    const auto s = m->sample(wo, Vec2d(rng.next_double(), rng.next_double()));
    if (!s) continue;
    EXPECT_NEAR(s->pdf, m->pdf(wo, s->wi), 1e-9 * s->pdf);
    EXPECT_NEAR(s->f.g, m->f(wo, s->wi).g, 1e-12 * (1 + s->f.g));
  }
}
