// Linearly transformed cosines (bsdf/ltc.h, ltc_shading.h) and the fitted GGX table
// (bsdf/runtime/ltc_baker.h), each against an independent reference: closed-form form factors (Snyder 1996;
// Howell C-11) for the identity LTC and for the light quadrature itself, nested Gauss–Kronrod quadrature of D
// over the sphere, a rectangle and a cap, a chi-square test of the sampler against D, and quadrature of the
// GGX BRDF × cosine over lights for the fitted table at off-grid (roughness, θ_v). A 12×12 table is fitted in
// the test (seconds).
#include <gtest/gtest.h>
#include <microshadow/bsdf/ltc.h>
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/multiscatter.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <cmath>

#include "support/chi2.h"

using namespace msh;
using namespace msh::bsdf;

namespace {

// A general (non-symmetric, tilted) inverse matrix and the structured ones the table holds.
Mat3<double> general_minv() {
  Mat3<double> m;
  m.m = {1.7, 0.2, -0.6, 0.1, 1.3, 0.15, 0.4, -0.1, 0.9};
  return m;
}

const LtcTable& small_table() {
  static const LtcTable t = [] {
    LtcFitOptions o;
    o.size = 12;
    o.error_samples = 24;
    o.max_iterations = 100;
    o.moment_samples = 2048;
    return fit_ltc_table(o);
  }();
  return t;
}

// A D_ltc integrand's panel edges: its peak M·z; all of the light, also below the horizon.
area::IntegrandBreaks ltc_breaks(const Mat3<double>& minv) {
  area::IntegrandBreaks b;
  b.has_peak = true, b.peak = normalize(minv.inverse() * Vec3d(0, 0, 1)), b.below_horizon = true;
  return b;
}

// ∫ over the whole sphere (a cap of radius π about the peak) of D.
double sphere_integral(const Mat3<double>& minv) {
  const area::IntegrandBreaks b = ltc_breaks(minv);
  return area::integrate_light(area::Cap{b.peak, kPi<double>},
                               [&](const Vec3d& l) { return ltc_eval(minv, l); }, b, {1e-7});
}

}  // namespace

TEST(LtcReference, QuadratureMatchesClosedFormFormFactors) {
  auto lambert = [](const Vec3d& l) { return std::max(0.0, l.z) / kPi<double>; };
  // Sphere light above, across and below the horizon (Snyder's clipped form factor).
  for (double sig_deg : {1.0, 10.0, 40.0})
    for (double elev_deg : {90.0, 45.0, 20.0, 5.0, -5.0}) {
      const double sig = sig_deg * kPi<double> / 180, el = elev_deg * kPi<double> / 180;
      const Vec3d axis(std::cos(el), 0, std::sin(el));
      const double q = area::integrate_light(area::Cap{axis, sig}, lambert, {}, {1e-7});
      const double a = area::sphere_form_factor(axis.z, std::sin(sig));
      EXPECT_NEAR(q, a, 1e-7 * std::max(a, 1e-4)) << sig_deg << " " << elev_deg;
    }
  // Rectangle with a corner above the point, parallel to the surface.
  for (double h : {0.3, 1.0, 4.0}) {
    const double a = 1.2, b = 0.7;
    const double q = area::integrate_light(
        area::rect_quad(Vec3d(a / 2, b / 2, h), Vec3d(1, 0, 0), Vec3d(0, 1, 0), a / 2, b / 2), lambert, {},
        {1e-7});
    EXPECT_NEAR(q, area::rect_corner_form_factor(a, b, h), 1e-8) << h;
  }
}

TEST(Ltc, IdentityPolygonIsTheFormFactor) {
  const Mat3<double> id;
  for (double h : {0.3, 1.0, 4.0}) {
    const double a = 1.2, b = 0.7;
    const auto p = ltc_rect_polygon(Vec3d(a / 2, b / 2, h), Vec3d(1, 0, 0), Vec3d(0, 1, 0), a / 2, b / 2);
    EXPECT_NEAR(ltc_integrate_polygon(id, p.data(), 4).integral, area::rect_corner_form_factor(a, b, h),
                1e-12);
  }
  // A quad straddling the horizon: the clipped part only (closed form by splitting at z = 0 is the same rect
  // tilted; compare with quadrature of the clamped cosine instead).
  const Vec3d c(0.3, 0.2, 0.1), ex = normalize(Vec3d(1, 0, 0.3)), ey = normalize(Vec3d(0, 0.6, -1));
  const auto p = ltc_rect_polygon(c, ex, ey, 0.5, 0.4);
  const double q =
      area::integrate_light(area::rect_quad(c, ex, ey, 0.5, 0.4),
                            [](const Vec3d& l) { return std::max(0.0, l.z) / kPi<double>; }, {}, {1e-9});
  EXPECT_NEAR(ltc_integrate_polygon(id, p.data(), 4).integral, q, 1e-7);
}

TEST(Ltc, DIntegratesToOneOverTheSphere) {
  EXPECT_NEAR(sphere_integral(Mat3<double>{}), 1.0, 1e-6);
  EXPECT_NEAR(sphere_integral(general_minv()), 1.0, 1e-6);
  const LtcTable& t = small_table();
  for (auto [r, mu] : {std::pair{0.37, 0.83}, std::pair{0.66, 0.31}, std::pair{0.95, 0.12}})
    EXPECT_NEAR(sphere_integral(t.fetch(r, mu).inv_m()), 1.0, 1e-5) << r << " " << mu;
}

TEST(Ltc, PolygonIntegralMatchesQuadrature) {
  const LtcTable& t = small_table();
  const std::vector<Mat3<double>> ms = {general_minv(), t.fetch(0.45, 0.7).inv_m(),
                                        t.fetch(0.8, 0.2).inv_m()};
  // Rectangles above, crossing the transformed horizon, and tilted.
  const std::vector<std::array<Vec3d, 3>> rects = {
      {Vec3d(0.2, 0.1, 1.0), Vec3d(1, 0, 0), Vec3d(0, 1, 0)},
      {Vec3d(1.0, -0.3, 0.15), normalize(Vec3d(0, 1, 0.2)), normalize(Vec3d(0.3, 0, 1))},
      {Vec3d(-0.6, 0.4, 0.5), normalize(Vec3d(1, 1, 0)), normalize(Vec3d(-0.2, 0.2, 1))},
  };
  for (size_t mi = 0; mi < ms.size(); ++mi)
    for (size_t ri = 0; ri < rects.size(); ++ri) {
      const auto& [c, ex, ey] = rects[ri];
      const auto p = ltc_rect_polygon(c, ex, ey, 0.4, 0.3);
      const double a = ltc_integrate_polygon(ms[mi], p.data(), 4).integral;
      const double q = area::integrate_light(area::rect_quad(c, ex, ey, 0.4, 0.3),
                                             [&](const Vec3d& l) { return ltc_eval(ms[mi], l); },
                                             ltc_breaks(ms[mi]), {1e-8});
      EXPECT_NEAR(a, q, 1e-6 * std::max(q, 1e-3)) << mi << " " << ri;
    }
}

TEST(Ltc, SpherePolygonApproximatesTheCap) {
  // The area-matched 16-gon against quadrature of D over the exact cap. Bound: the polygon's solid angle
  // differs from the cap's by O(σ²(π/N)²) relative (docs/ltc.md); 1% covers σ ≤ 40° with margin, and an
  // inscribed (not area-matched) 16-gon would already be 2.6% short.
  const LtcTable& t = small_table();
  const Mat3<double> ms[] = {Mat3<double>{}, t.fetch(0.5, 0.6).inv_m(), general_minv()};
  for (const auto& m : ms)
    for (double sig_deg : {2.0, 15.0, 40.0})
      for (double el_deg : {80.0, 40.0, 10.0}) {
        const double sig = sig_deg * kPi<double> / 180, el = el_deg * kPi<double> / 180;
        const Vec3d axis(std::cos(el), 0.1, std::sin(el));
        const Vec3d ax = normalize(axis);
        const double q = area::integrate_light(
            area::Cap{ax, sig}, [&](const Vec3d& l) { return ltc_eval(m, l); }, ltc_breaks(m), {1e-6});
        const double a = ltc_integrate_sphere(m, ax, std::sin(sig), 16).integral;
        EXPECT_NEAR(a, q, 0.01 * q + 1e-9) << sig_deg << " " << el_deg;
      }
}

TEST(Ltc, SamplerMatchesD) {
  const LtcTable& t = small_table();
  for (const Mat3<double>& minv : {general_minv(), t.fetch(0.55, 0.5).inv_m()}) {
    const Mat3<double> m = minv.inverse();
    test::Uniforms u(42);
    const auto r =
        test::chi2_test_directions([&](uint32_t) -> std::optional<Vec3d> { return ltc_sample(m, u.next()); },
                                   [&](const Vec3d& w) { return ltc_eval(minv, w); }, 200000, 20, 40);
    EXPECT_TRUE(r.pass) << "p = " << r.p_value << "\n" << r.table;
  }
}

TEST(LtcFit, MomentsMatchTheAlbedo) {
  // magnitude and fresnel against the shipped E, E_Fc tables (a different bake: 32² table, its own samples).
  const LtcTable& t = small_table();
  for (int j = 0; j < t.size; j += 3)
    for (int i = 2; i < t.size; i += 3) {
      const double r = double(i) / (t.size - 1), y = double(j) / (t.size - 1);
      const double mu = std::cos(std::min(1.57, std::acos(1 - y * y)));
      const size_t k = size_t(j) * t.size + size_t(i);
      EXPECT_NEAR(t.amp[k * 2], ggx_E(mu, r), 0.01) << r << " " << mu;
      EXPECT_NEAR(t.amp[k * 2 + 1], ggx_E_fc(mu, r), 0.01) << r << " " << mu;
    }
}

TEST(LtcFit, OffGridTableMatchesGgxQuadrature) {
  // The as-used path (bilinear fetch at Sobol points off the grid, LTC-shaded sphere and square lights)
  // against quadrature of GGX × cosine over the light, r ∈ [0.3, 1], N·V ∈ [0.3, 1], σ ∈ [2°, 30°]. Bounds:
  // Heitz et al. 2016 (Fig. 9) show GGX LTC errors of a few percent away from grazing; a coarse 12² table
  // adds the bilinear error, so we require an RMS relative error ≤ 10% (on lights showing ≥ 10% of the
  // highlight's peak) and a worst error ≤ 30%. The negative control — the same table with every M⁻¹ replaced
  // by the identity (the right magnitude, a Lambertian shape) — must fail both, so the bound does detect a
  // wrong fit.
  const LtcTable& t = small_table();
  LtcVerifyOptions o;
  o.points = 48, o.roughness_min = 0.3, o.cos_min = 0.3, o.sigma_min_deg = 2, o.sigma_max_deg = 30;
  const LtcVerifyReport r = verify_ltc_table(t, o);
  std::printf("sphere rms %.4f max %.4f (n %d), rect rms %.4f max %.4f\n", r.sphere.rms_rel, r.sphere.max_rel,
              r.sphere.count_rel, r.rect.rms_rel, r.rect.max_rel);
  EXPECT_GE(r.sphere.count_rel, 10);
  EXPECT_LE(r.sphere.rms_rel, 0.10);
  EXPECT_LE(r.rect.rms_rel, 0.10);
  EXPECT_LE(r.sphere.max_rel, 0.30);
  EXPECT_LE(r.rect.max_rel, 0.30);
  LtcTable bad = t;
  for (size_t k = 0; k < size_t(t.size) * t.size; ++k)
    bad.mat[k * 4 + 0] = 1, bad.mat[k * 4 + 1] = 0, bad.mat[k * 4 + 2] = 0, bad.mat[k * 4 + 3] = 1;
  const LtcVerifyReport rb = verify_ltc_table(bad, o);
  std::printf("control: sphere rms %.4f max %.4f\n", rb.sphere.rms_rel, rb.sphere.max_rel);
  EXPECT_GT(rb.sphere.rms_rel, 0.10);
  EXPECT_GT(rb.sphere.max_rel, 0.30);
}

TEST(LtcFit, BitIdenticalForAnyThreadCount) {
  LtcFitOptions o;
  o.size = 6, o.error_samples = 8, o.max_iterations = 30, o.moment_samples = 256;
  o.threads = 1;
  const LtcTable a = fit_ltc_table(o);
  o.threads = 2;
  const LtcTable b = fit_ltc_table(o);
  EXPECT_EQ(a.mat, b.mat);
  EXPECT_EQ(a.amp, b.amp);
}

TEST(LtcShading, MicroShadowingHookAndRepresentativeDirection) {
  const LtcTable& t = small_table();
  const Vec3d n(0, 0, 1), v(std::sin(0.6), 0, std::cos(0.6));
  const LtcCoeffs<double> k = t.fetch(0.4, v.z);
  // A small sphere light: the representative direction is the light's centre.
  const Vec3d c = normalize(Vec3d(-0.5, 0.2, 0.8));
  const auto small = ltc_shade_sphere(k, n, v, c, std::sin(0.3 * kPi<double> / 180));
  EXPECT_GT(dot(small.direction, c), std::cos(0.3 * kPi<double> / 180));
  // The micro-shadowing factor multiplies the value; the point stand-in sees the representative N·L.
  const double ms = ltc_ms_at_representative(small, [](double nl) { return nl * nl; });
  EXPECT_NEAR(ms, sqr(c.z), 0.01);
  EXPECT_NEAR(small.value(0.04, 0.5), 0.5 * small.value(0.04), 1e-15);
  // A light below the horizon gives 0 and a finite direction.
  const auto below = ltc_shade_sphere(k, n, v, normalize(Vec3d(0.3, 0, -0.9)), 0.1);
  EXPECT_EQ(below.integral, 0.0);
  EXPECT_TRUE(is_finite(below.direction));
}

TEST(Ltc, SurfaceClippedPolygonMatchesQuadrature) {
  // clip_surface: ∫_P D [ω.z ≥ 0] for quads crossing the surface's horizon, against quadrature of the same.
  const LtcTable& t = small_table();
  for (const Mat3<double>& m : {general_minv(), t.fetch(0.45, 0.3).inv_m(), t.fetch(0.8, 0.15).inv_m()}) {
    const Vec3d c(-0.8, 0.2, 0.05), ex = normalize(Vec3d(0, 1, 0.1)), ey = normalize(Vec3d(0.2, 0, 1));
    const auto p = ltc_rect_polygon(c, ex, ey, 0.5, 0.4);
    const double a = ltc_integrate_polygon(m, p.data(), 4, true).integral;
    // Quadrature over the part above the horizon only (the inner rule starts at the horizon line, so the jump
    // of D [ω.z ≥ 0] is on a panel edge): t ≥ t*(s) = −(c.z + s ex.z) / ey.z (ey.z > 0 here).
    const Vec3d nl = cross(ex, ey);
    auto inner = [&](double s) {
      const double t0 = std::clamp(-(c.z + s * ex.z) / ey.z, -0.4, 0.4);
      return gauss_kronrod(
          [&](double tt) {
            const Vec3d x = c + ex * s + ey * tt;
            const double d2 = dot(x, x), d = std::sqrt(d2);
            return ltc_eval(m, x / d) * std::abs(dot(nl, x)) / (d2 * d);
          },
          t0, 0.4, 1e-13, 1e-10);
    };
    const double q = gauss_kronrod(inner, -0.5, 0.5, 1e-13, 1e-10);
    EXPECT_NEAR(a, q, 1e-7 * std::max(q, 1e-3));
    // ... and never more than the unclipped integral.
    EXPECT_LE(a, ltc_integrate_polygon(m, p.data(), 4).integral + 1e-15);
  }
}
