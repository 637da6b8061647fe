// Chi-square goodness of fit (tests/support/chi2.h, the pbrt-v4 / Mitsuba 3 habit) of every microfacet
// sampler against its own pdf: both GGX VNDF samplers against the analytic VNDF (isotropic, anisotropic,
// normal, grazing and backfacing incidence), the bounded VNDF (over m and over the reflected direction),
// Beckmann VNDF, and plain NDF sampling of every NDF. Peaked lobes (α ≤ 0.1) are also tested on the stretched
// sphere, where they fill the grid.
#include <gtest/gtest.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/blinn_phong.h>
#include <microshadow/microfacet/bounded_vndf.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/gtr.h>

#include "support/chi2.h"

using namespace msh;
using msh::test::Chi2Result;

namespace {

// Šidák correction over every chi-square run in this executable.
constexpr int kTests = 40;
constexpr int kSamples = 250000;

using Rng = msh::test::Uniforms;

Vec3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

template <class Sampler, class Pdf>
Chi2Result run(uint64_t seed, Sampler&& s, Pdf&& p, double stretch_x = 0, double stretch_y = 0) {
  Rng rng(seed);
  auto sample = [&](uint32_t) { return std::optional<Vec3d>(s(rng.next())); };
  std::function<double(const Vec3d&)> pdf = p;
  if (stretch_x > 0)
    return msh::test::chi2_test_directions_stretched(sample, pdf, stretch_x, stretch_y, kSamples, 40, 80,
                                                     0.01, kTests);
  return msh::test::chi2_test_directions(sample, pdf, kSamples, 40, 80, 0.01, kTests);
}

struct Case {
  double ax, ay, theta, phi;
};
const Case kVndfCases[] = {{0.5, 0.5, 0.7, 0.3},   {0.2, 0.6, 1.2, 0.9},
                           {1.0, 1.0, 0.0, 0.0},   {0.3, 0.3, 1.5707963267948966, 0.2},
                           {0.05, 0.05, 0.8, 0.0}, {0.8, 0.1, 2.3, 1.0}};

}  // namespace

namespace {

// A GGX VNDF sampler sample(g, w, u) against the VNDF pdf (chi-square) at every kVndfCases case, then at the
// peaked anisotropic α = (0.05, 0.1) on a stretched grid; seeds from `seed` on.
template <class Sample>
void expect_ggx_vndf_sampler_matches(uint64_t seed, Sample sample) {
  for (const Case& c : kVndfCases) {
    const GGX<double> g(c.ax, c.ay);
    const Vec3d w = dir(c.theta, c.phi);
    auto r = run(
        seed++, [&](Vec2d u) { return sample(g, w, u); }, [&](const Vec3d& m) { return g.PDF(w, m); });
    EXPECT_TRUE(r.pass) << c.ax << "," << c.ay << " theta " << c.theta << "\n" << r.table;
  }
  const GGX<double> g(0.05, 0.1);
  const Vec3d w = dir(1.0, 0.4);
  auto r = run(
      seed++, [&](Vec2d u) { return sample(g, w, u); }, [&](const Vec3d& m) { return g.PDF(w, m); }, 0.05,
      0.1);
  EXPECT_TRUE(r.pass) << r.table;
}

}  // namespace

TEST(MicrofacetSampling, GgxSphericalCapsMatchesVndf) {
  expect_ggx_vndf_sampler_matches(
      100, [](const GGX<double>& g, const Vec3d& w, Vec2d u) { return g.sample_vndf_spherical_caps(w, u); });
}

TEST(MicrofacetSampling, GgxHeitz2018MatchesVndf) {
  expect_ggx_vndf_sampler_matches(
      200, [](const GGX<double>& g, const Vec3d& w, Vec2d u) { return g.sample_vndf_heitz2018(w, u); });
}

TEST(MicrofacetSampling, GgxBoundedVndfOverNormalsAndReflections) {
  uint64_t seed = 300;
  for (const Case& c : {Case{0.5, 0.5, 0.7, 0.3}, Case{0.2, 0.6, 1.3, 0.9}, Case{0.9, 0.9, 1.5, 0.0}}) {
    const GGX<double> g(c.ax, c.ay);
    const Vec3d w = dir(c.theta, c.phi);
    auto rm = run(
        seed++, [&](Vec2d u) { return sample_bounded_vndf(g, w, u); },
        [&](const Vec3d& m) { return pdf_bounded_vndf(g, w, m); });
    EXPECT_TRUE(rm.pass) << "m: " << c.ax << " theta " << c.theta << "\n" << rm.table;
    auto ro = run(
        seed++, [&](Vec2d u) { return reflect(w, sample_bounded_vndf(g, w, u)); },
        [&](const Vec3d& o) { return pdf_bounded_vndf_reflection(g, w, o); });
    EXPECT_TRUE(ro.pass) << "o: " << c.ax << " theta " << c.theta << "\n" << ro.table;
  }
}

TEST(MicrofacetSampling, BeckmannVndf) {
  uint64_t seed = 400;
  for (const Case& c : kVndfCases) {
    const Beckmann<double> b(c.ax, c.ay);
    const Vec3d w = dir(c.theta, c.phi);
    auto r = run(
        seed++, [&](Vec2d u) { return b.Sample_wm(w, u); }, [&](const Vec3d& m) { return b.PDF(w, m); });
    EXPECT_TRUE(r.pass) << c.ax << "," << c.ay << " theta " << c.theta << "\n" << r.table;
  }
  const Beckmann<double> b(0.05, 0.1);
  const Vec3d w = dir(1.0, 0.4);
  auto r = run(
      seed++, [&](Vec2d u) { return b.Sample_wm(w, u); }, [&](const Vec3d& m) { return b.PDF(w, m); }, 0.05,
      0.1);
  EXPECT_TRUE(r.pass) << r.table;
}

TEST(MicrofacetSampling, PlainNdfSampling) {
  uint64_t seed = 500;
  auto check = [&](const auto& ndf, const char* name) {
    auto r = run(
        seed++, [&](Vec2d u) { return ndf.sample_ndf(u); }, [&](const Vec3d& m) { return ndf.pdf_ndf(m); });
    EXPECT_TRUE(r.pass) << name << "\n" << r.table;
  };
  check(GGX<double>(0.3), "ggx");
  check(GGX<double>(0.2, 0.7), "ggx aniso");
  check(Beckmann<double>(0.4), "beckmann");
  check(Beckmann<double>(0.6, 0.15), "beckmann aniso");
  check(BlinnPhong<double>(20.0), "blinn-phong 20");
  check(BlinnPhong<double>(0.0), "blinn-phong 0");
  check(GTR<double>(0.3, 1.0), "gtr 1");
  check(GTR<double>(0.4, 3.0), "gtr 3");
  check(GTR<double>(1.0, 1.5), "gtr alpha 1");
}

TEST(MicrofacetSampling, FloatSamplersAgreeWithDouble) {
  // The float instantiation follows the double one to float precision (same u). Away from normal incidence:
  // the Beckmann sampler switches to the closed-form normal-incidence mapping at cos θ > 0.99999, a different
  // (equally exact) map of u, so float and double may pick different branches there.
  const GGX<float> gf(0.3f, 0.5f);
  const GGX<double> gd(0.3, 0.5);
  const Beckmann<float> bf(0.3f, 0.5f);
  const Beckmann<double> bd(0.3, 0.5);
  Rng rng(7);
  for (int i = 0; i < 10000; ++i) {
    const Vec2d u = rng.next();
    const Vec2f uf(float(u.x), float(u.y));
    const Vec3d w = dir(0.01 + 1.2 * u.y, 6 * u.x);
    const Vec3f wf(w);
    const Vec3d a = Vec3d(gf.Sample_wm(wf, uf)), b = gd.Sample_wm(w, Vec2d(uf.x, uf.y));
    EXPECT_LT(length(a - b), 1e-4);
    const Vec3d c = Vec3d(bf.Sample_wm(wf, uf)), d = bd.Sample_wm(w, Vec2d(uf.x, uf.y));
    EXPECT_LT(length(c - d), 5e-3);  // float Newton tolerance 1e-6 on the CDF
  }
}
