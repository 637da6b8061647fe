// As-used verification of an LTC table against quadrature of GGX over the light (see ltc_baker.h).
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <stdexcept>

namespace msh::bsdf {
namespace {

struct PointResult {
  double r, mu, sigma_deg, elev_deg;
  double peak, ref_sphere, ltc_sphere, ref_rect, ltc_rect, ltc_cap, ref_diff, ltc_diff;
};

void accumulate(LtcErrorStats& s, const PointResult& p, double ref, double val, double floor) {
  const double a = std::abs(val - ref);
  s.rms_abs += a * a, ++s.count;
  if (a > s.max_abs)
    s.max_abs = a, s.worst_roughness = p.r, s.worst_cos_v = p.mu, s.worst_sigma_deg = p.sigma_deg,
    s.worst_elevation_deg = p.elev_deg;
  if (ref >= floor && ref > 0) {
    const double e = a / ref;
    s.rms_rel += e * e, ++s.count_rel, s.max_rel = std::max(s.max_rel, e);
  }
}
void finish(LtcErrorStats& s) {
  s.rms_abs = std::sqrt(s.rms_abs / std::max(1, s.count));
  s.rms_rel = std::sqrt(s.rms_rel / std::max(1, s.count_rel));
}

}  // namespace

LtcVerifyReport verify_ltc_table(const LtcTable& t, const LtcVerifyOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<PointResult> res(size_t(std::max(o.points, 0)));
  const double deg = kPi<double> / 180;
  LtcVerifyReport rep;
  {
    auto lambert = [](const Vec3d& l) { return std::max(0.0, l.z) * kInvPi<double>; };
    for (double sd : {1.0, 10.0, 40.0})
      for (double ed : {90.0, 45.0, 20.0, 5.0, -5.0}) {
        const Vec3d axis(std::cos(ed * deg), 0, std::sin(ed * deg));
        const double q = area::integrate_light(area::Cap{axis, sd * deg}, lambert, {}, {1e-8});
        const double a = area::sphere_form_factor(axis.z, std::sin(sd * deg));
        rep.reference_check = std::max(rep.reference_check, std::abs(q - a) / std::max(a, 1e-4));
      }
    for (double h : {0.3, 1.0, 4.0}) {
      const double q = area::integrate_light(
          area::rect_quad(Vec3d(0.6, 0.35, h), Vec3d(1, 0, 0), Vec3d(0, 1, 0), 0.6, 0.35), lambert, {},
          {1e-8});
      const double a = area::rect_corner_form_factor(1.2, 0.7, h);
      rep.reference_check = std::max(rep.reference_check, std::abs(q - a) / a);
    }
    if (!(rep.reference_check <= 1e-5))
      throw std::runtime_error("verify ltc: the light quadrature fails its closed-form check");
  }
  tbb::parallel_for(0, o.points, [&](int i) {
    auto u = [&](int dim) { return sobol_scrambled<double>(uint32_t(i), dim, o.seed); };
    PointResult p{};
    p.r = o.roughness_min + (1 - o.roughness_min) * u(0);
    p.mu = o.cos_min + (1 - o.cos_min) * u(1);
    p.sigma_deg = o.sigma_min_deg * std::pow(o.sigma_max_deg / o.sigma_min_deg, u(2));
    p.elev_deg = 90 * u(3);
    const double az = kPi<double> * u(4), sig = p.sigma_deg * deg, el = p.elev_deg * deg;
    const Vec3d n(0, 0, 1), v(std::sqrt(1 - p.mu * p.mu), 0, p.mu);
    // Azimuth 0 = the mirror side (−x).
    const Vec3d axis(-std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const GGX<double> g(roughness_to_alpha(p.r));
    auto f = [&](const Vec3d& l) { return microfacet_specular(g, v, l).f1 * std::max(0.0, l.z); };
    auto lambert = [](const Vec3d& l) { return std::max(0.0, l.z) * kInvPi<double>; };
    const LtcCoeffs<double> k = t.fetch(p.r, p.mu);
    const double ss = std::sin(sig), norm_s = ss * ss;  // sphere form factor at normal incidence
    // The lobe peaks at the mirror direction: its z and azimuth are panel edges of the light quadrature.
    area::IntegrandBreaks lobe;
    lobe.has_peak = true, lobe.peak = Vec3d(-v.x, 0, v.z);
    const area::AreaOptions tol{1e-6};
    p.ref_sphere = area::integrate_light(area::Cap{axis, sig}, f, lobe, tol) / norm_s;
    // The highlight's peak: the same light centred on the mirror direction (relative errors are taken where
    // the light shows at least rel_floor of it).
    p.peak = area::integrate_light(area::Cap{lobe.peak, sig}, f, lobe, tol) / norm_s;
    const auto ls = ltc_shade_sphere(k, n, v, axis, ss, o.polygon_sides, o.clip_surface);
    p.ltc_sphere = ls.value(1.0) / norm_s;
    // The polygon approximation alone: the same LTC over the exact cap (above the surface, as shaded).
    const Frame<double> fr = ltc_view_frame(n, v);
    const Mat3<double> minv = k.inv_m();
    area::IntegrandBreaks ltc_lobe;  // D_ltc peaks at M·z
    ltc_lobe.has_peak = true, ltc_lobe.peak = fr.to_world(normalize(minv.inverse() * Vec3d(0, 0, 1)));
    ltc_lobe.below_horizon = !o.clip_surface;
    p.ltc_cap = k.magnitude *
                area::integrate_light(
                    area::Cap{axis, sig}, [&](const Vec3d& l) { return ltc_eval(minv, fr.to_local(l)); },
                    ltc_lobe, tol) /
                norm_s;
    p.ref_diff = area::integrate_light(area::Cap{axis, sig}, lambert, {}, {1e-8}) / norm_s;
    p.ltc_diff = ltc_shade_sphere(LtcCoeffs<double>{}, n, v, axis, ss, o.polygon_sides).value(1.0) / norm_s;
    // Square light of half-size tan σ at distance 1, facing the point, rotated by a Sobol angle about its
    // axis.
    const double h = std::tan(sig),
                 rot = 2 * kPi<double> *
                       std::fmod(0.5 + 0.6180339887498949 * i,
                                 1.0);  // golden-ratio sequence: the Sobol set has 5 dimensions
    const Frame<double> lf = Frame<double>::from_z(axis);
    const Vec3d ex = lf.s * std::cos(rot) + lf.t * std::sin(rot), ey = cross(axis, ex);
    const double norm_r = area::rect_corner_form_factor(h, h, 1.0) * 4;
    p.ref_rect = area::integrate_light(area::rect_quad(axis, ex, ey, h, h), f, lobe, tol) / norm_r;
    const auto corners = ltc_rect_polygon(axis, ex, ey, h, h);
    p.ltc_rect = ltc_shade_polygon(k, n, v, corners.data(), 4, o.clip_surface).value(1.0) / norm_r;
    res[size_t(i)] = p;
  });
  for (const PointResult& p : res) {
    const double floor = o.rel_floor * p.peak;
    accumulate(rep.sphere, p, p.ref_sphere, p.ltc_sphere, floor);
    accumulate(rep.rect, p, p.ref_rect, p.ltc_rect, floor);
    accumulate(rep.sphere_polygon, p, p.ltc_cap, p.ltc_sphere, floor);
    accumulate(rep.diffuse_sphere, p, p.ref_diff, p.ltc_diff, o.rel_floor);
  }
  finish(rep.sphere), finish(rep.rect), finish(rep.sphere_polygon), finish(rep.diffuse_sphere);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return rep;
}

}  // namespace msh::bsdf
