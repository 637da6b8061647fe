// Clear coat over a base (RTR4 §9.12): limits stated by the construction, closed forms at normal incidence,
// the coat normal, and energy over a grid with a white Lambert base (numerical integration in double).
#include <gtest/gtest.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/layered.h>

using namespace msh;
using namespace msh::bsdf;

namespace {
// ∫ f cos dω over the hemisphere, midpoint rule in (cos θ, φ), n × 2n cells.
template <class F>
Rgbd hemisphere_integral(F&& f, int n) {
  Rgbd s(0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double c = (i + 0.5) / n, phi = (j + 0.5) * kPi<double> / n;
      s += f(spherical_direction(c, phi)) * c;
    }
  return s * (2 * kPi<double> / (2.0 * n * n));
}
}  // namespace

TEST(ClearCoat, IndexMatchedCoatIsTheBase) {
  // η = 1: no reflection at the coat (F = 0), no refraction: f = f_base exactly (clear tint).
  const ClearCoat<double> coat(1.0, 0.1, Rgbd(1), Vec3d(0, 0, 1));
  const Vec3d wo = normalize(Vec3d(0.3, 0.2, 0.9)), wi = normalize(Vec3d(-0.5, 0.1, 0.4));
  const Rgbd base(0.2, 0.5, 0.7);
  const Rgbd f = coat.f(wo, wi, base);
  EXPECT_NEAR(f.r, 0.2, 1e-12);
  EXPECT_NEAR(f.b, 0.7, 1e-12);
}

TEST(ClearCoat, NormalIncidenceClosedForm) {
  // wo = wi = n: base weight = (1 − F0)² τ² (path 1 + 1 through a coat with cos θt = 1).
  const double eta = 1.5, F0 = sqr((eta - 1) / (eta + 1));
  const ClearCoat<double> coat(eta, 0.3, Rgbd(0.5, 0.8, 1.0), Vec3d(0, 0, 1));
  const Rgbd w = coat.base_weight(Vec3d(0, 0, 1), Vec3d(0, 0, 1));
  EXPECT_NEAR(w.r, sqr(1 - F0) * 0.25, 1e-12);
  EXPECT_NEAR(w.g, sqr(1 - F0) * 0.64, 1e-12);
  EXPECT_NEAR(w.b, sqr(1 - F0), 1e-12);
  // Oblique: path = 2 / cos θt with Snell's law.
  const double mu = 0.5, ct = std::sqrt(1 - (1 - mu * mu) / (eta * eta));
  const Vec3d d = spherical_direction(mu, 0.0);
  const double F = fresnel_dielectric(mu, eta);
  EXPECT_NEAR(coat.base_weight(d, d).r, sqr(1 - F) * std::pow(0.5, 2 / ct), 1e-12);
}

TEST(ClearCoat, CoatLobeFollowsTheCoatNormal) {
  // A smooth coat tilted by 20°: the coat lobe peaks at the mirror of wo about the coat normal.
  const Vec3d nc = spherical_direction(std::cos(20 * kPi<double> / 180), 0.0);
  const ClearCoat<double> coat(1.5, 0.05, Rgbd(1), nc);
  const Vec3d wo = spherical_direction(std::cos(30 * kPi<double> / 180), kPi<double>);
  const Vec3d mirror = reflect(wo, nc);
  ASSERT_GT(mirror.z, 0);
  const double peak = coat.f_coat(wo, mirror).r;
  const Vec3d flat_mirror = reflect(wo, Vec3d(0, 0, 1));
  EXPECT_GT(peak, 100 * coat.f_coat(wo, flat_mirror).r);
  // Exact peak value for a mirror configuration: F(cos) D(n_c) G2 / (4 cos²) with h = n_c.
  const GGX<double> g(0.05);
  const Vec3d o = Frame<double>::from_z(nc).to_local(wo);
  const double expect =
      fresnel_dielectric(o.z, 1.5) * g.D(Vec3d(0, 0, 1)) * g.G2(o, Vec3d(-o.x, -o.y, o.z)) / (4 * o.z * o.z);
  EXPECT_NEAR(peak, expect, 1e-9 * expect);
}

TEST(ClearCoat, EnergyWithWhiteLambertBase) {
  // Directional albedo of coat + Fresnel-weighted white Lambert ≤ 1 over a grid (deterministic quadrature;
  // the rough coats are resolved by the 400 × 800 grid).
  double worst = 0;
  for (double eta : {1.0, 1.3, 1.5, 2.0, 3.0})
    for (double a : {0.05, 0.2, 0.5, 1.0})
      for (double mu : {1.0, 0.5, 0.1}) {
        const ClearCoat<double> coat(eta, a, Rgbd(1), Vec3d(0, 0, 1));
        const Vec3d wo = spherical_direction(mu, 0.0);
        const Rgbd e =
            hemisphere_integral([&](const Vec3d& wi) { return coat.f(wo, wi, Rgbd(kInvPi<double>)); }, 400);
        worst = std::max(worst, e.r);
        EXPECT_LE(e.r, 1.0 + 2e-3) << "eta " << eta << " alpha " << a << " mu " << mu;
      }
  std::printf("[clear coat, white Lambert base] max albedo %.4f\n", worst);
}

TEST(ClearCoat, FiniteOnDegenerateInput) {
  const ClearCoat<float> coat(0.0f, 0.0f, Rgb<float>(0), Vec3f(0, 0, 0));
  for (const Vec3f& a : {Vec3f(0, 0, 1), Vec3f(1, 0, 0), Vec3f(0, 0, -1), Vec3f(0, 0, 0)})
    for (const Vec3f& b : {Vec3f(0, 0, 1), Vec3f(1, 0, 0), Vec3f(0, 1e-6f, 1)}) {
      EXPECT_TRUE(is_finite(coat.f(a, b, Rgb<float>(1))));
      EXPECT_TRUE(is_finite(coat.base_weight(a, b)));
    }
}
