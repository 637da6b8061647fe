// `verify area-lights`: the area-light fast forms (occlusion/micro_shadowing_area.h) measured as used against
// the exact quadrature (reference/micro_shadowing_area_exact.h) at Sobol inputs over V ∈ [0, 1],
// N·L ∈ [0, 1] (the cap's centre), light radius ρ ∈ [1°, 40°] (docs/area-lights.md):
//
//   microshadow verify area-lights [--points N] [--generic-points M] [--shape-points K] [--ltc-points L]
//                                  [--ltc FILE] [--json]
//
// The LTC block (--ltc-points) measures the cone-clipped LTC forms of bsdf/ltc_shading.h (GGX and Lambertian
// receivers, sphere, disk and rect lights) with the LTC table FILE (bake ltc), or a 16² table fitted here.
//
// Errors are |fast − exact| in units of 1/255 (RMS, p99, max) over all points.
#include <fmt/format.h>
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "common.h"

namespace msh::cli {
namespace {

constexpr double kDeg = kPi<double> / 180;

struct VerifyArgs {
  int points = 2048, generic_points = 96, shape_points = 512, ltc_points = 512, aware_points = 16,
      diffuse_aware_points = 0;
  std::string ltc;  // LTC table file; empty: fit a 16² table
  double rho_min_deg = 1, rho_max_deg = 40;
  bool json = false;
};

// One input point: padded 2D Owen-scrambled Sobol (independent seeds per pair of dimensions).
// Disk and rect lights also take a tilt ∈ [−60°, 60°] from facing the point, a roll ∈ [0°, 360°) and an
// aspect ∈ [0.25, 1] (rect half-height / half-width).
struct Input {
  double V, nl, rho, nv, r, phi_v;
  double tilt, roll, aspect;
};
Input input_at(uint32_t i, const VerifyArgs& a) {
  const Vec2d p = sobol_2d<double>(i, 0x51u), q = sobol_2d<double>(i, 0x9e37u),
              s = sobol_2d<double>(i, 0x7f4au), o = sobol_2d<double>(i, 0x3c6eu),
              w = sobol_2d<double>(i, 0x2545u);
  return {p.x,
          p.y,
          (a.rho_min_deg + (a.rho_max_deg - a.rho_min_deg) * q.x) * kDeg,
          q.y,
          s.x,
          s.y * kPi<double>,
          (-60 + 120 * o.x) * kDeg,
          2 * kPi<double> * o.y,
          0.25 + 0.75 * w.x};
}

// The disk and rect lights of a point (centred on its N·L direction), and the rect's corners in float.
struct ShapeLights {
  area::Disk disk;
  area::Quad quad;
  std::array<Vec3f, 4> quad_float;
};
ShapeLights shape_lights(const Input& in) {
  const Vec3d c = spherical_direction(in.nl, 0.0);
  ShapeLights s{area::disk_tilted(c, in.rho, in.tilt, in.roll),
                area::rect_tilted(c, in.rho, in.rho * in.aspect, in.tilt, in.roll),
                {}};
  for (size_t k = 0; k < 4; ++k) s.quad_float[k] = Vec3f(s.quad.corners[k]);
  return s;
}

// The view and roughness of a point in the LTC and aware blocks' domain: N·V ≥ 0.05, roughness ≥ 0.1.
struct ClampedView {
  double nv, r, alpha;
  Vec3d v;
};
ClampedView clamped_view(const Input& in) {
  const double nv = std::max(0.05, in.nv), r = std::max(0.1, in.r);
  return {nv, r, roughness_to_alpha(r), spherical_direction(nv, in.phi_v)};
}

// A sphere light's cone-clipped LTC in float (with the tail), as a shader evaluates it.
bsdf::LtcLightCone<float> sphere_cone_float(const bsdf::LtcCoeffs<double>& k, const ClampedView& g,
                                            const Vec3d& c, double rho) {
  const bsdf::LtcCoeffs<float> kf = {float(k.a), float(k.b), float(k.c), float(k.d)};
  return bsdf::ltc_light_cone_sphere(kf.inv_m(), Vec3f(0, 0, 1), Vec3f(g.v), Vec3f(c), float(std::sin(rho)),
                                     bsdf::ltc_tail_weight(float(g.alpha)));
}

// A point of the LTC and aware blocks: its clamped view, the sphere light (cap) centred on its N·L direction,
// the GGX receiver, the table's LTC there and the cap's cone-clipped LTC with the tail (double and float).
struct GgxCapPoint {
  ClampedView g;
  Vec3d n, c;
  area::Cap cap;
  area::Receiver ggx;
  bsdf::LtcCoeffs<double> k;
  bsdf::LtcLightCone<double> lc;
  bsdf::LtcLightCone<float> lf;
};
GgxCapPoint ggx_cap_point(const Input& in, const bsdf::LtcTable& table) {
  const ClampedView g = clamped_view(in);
  const Vec3d n(0, 0, 1), c = spherical_direction(in.nl, 0.0);
  const bsdf::LtcCoeffs<double> k = table.fetch(g.r, g.nv);
  return {g,
          n,
          c,
          area::Cap{c, in.rho},
          area::Receiver::ggx(g.alpha, g.v),
          k,
          bsdf::ltc_light_cone_sphere(k.inv_m(), n, g.v, c, std::sin(in.rho), bsdf::ltc_tail_weight(g.alpha)),
          sphere_cone_float(k, g, c, in.rho)};
}

// One row of errors per Sobol point i < count: fill(input_at(i), row), in parallel.
template <size_t N, class Fill>
std::vector<std::array<double, N>> error_rows(int count, const VerifyArgs& a, const Fill& fill) {
  auto rows = std::vector<std::array<double, N>>(size_t(count));
  tbb::parallel_for(0, count, [&](int i) { fill(input_at(uint32_t(i), a), rows[size_t(i)]); });
  return rows;
}

nlohmann::json summary(std::vector<double> err) {
  if (err.empty()) return nullptr;
  double ss = 0, bias = 0;
  for (double& e : err) ss += e * e, bias += e, e = std::abs(e);
  std::sort(err.begin(), err.end());
  const size_t n = err.size();
  auto q = [&](double p) { return err[std::min(n - 1, size_t(std::ceil(p * double(n))) - (p > 0 ? 1 : 0))]; };
  return {{"count", n},
          {"rms_255", 255 * std::sqrt(ss / double(n))},
          {"bias_255", 255 * bias / double(n)},
          {"p99_255", 255 * q(0.99)},
          {"max_255", 255 * err.back()}};
}

void run_verify(const VerifyArgs& a) {
  if (a.points < 1 || a.points > (1 << 20)) throw UsageError(fmt::format("--points must be in [1, 2^20]"));
  if (a.shape_points < 0 || a.shape_points > (1 << 16))
    throw UsageError(fmt::format("--shape-points must be in [0, 2^16]"));
  if (a.generic_points < 0 || a.generic_points > (1 << 16))
    throw UsageError(fmt::format("--generic-points must be in [0, 2^16]"));
  if (a.ltc_points < 0 || a.ltc_points > (1 << 16))
    throw UsageError(fmt::format("--ltc-points must be in [0, 2^16]"));
  if (a.aware_points < 0 || a.aware_points > (1 << 16))
    throw UsageError(fmt::format("--aware-points must be in [0, 2^16]"));
  if (a.diffuse_aware_points < 0 || a.diffuse_aware_points > (1 << 16))
    throw UsageError(fmt::format("--diffuse-aware-points must be in [0, 2^16]"));
  if (!(a.rho_min_deg >= 0 && a.rho_min_deg <= a.rho_max_deg && a.rho_max_deg <= 90))
    throw UsageError("--rho-min-deg and --rho-max-deg must satisfy 0 <= min <= max <= 90");

  // The LTC table first, so that a bad --ltc fails before any work.
  std::string ltc_source = "none";
  bsdf::LtcTable table;
  if (a.ltc_points > 0 || a.aware_points > 0) {
    if (a.ltc.empty()) {
      bsdf::LtcFitOptions fo;
      fo.size = 16;
      table = bsdf::fit_ltc_table(fo);
      ltc_source = "16x16 table fitted in process (bake ltc --size 16)";
    } else {
      table = bsdf::load_ltc_table(a.ltc);
      ltc_source = a.ltc;
    }
  }

  // Closed-form terms (cheap exact references): one row of errors per point and form.
  enum Form {
    kStepCosine,       // reference_step_area_cap (exact cosine-weighted closed form)
    kStepMazonka,      // solid-angle ratio (Mazonka 2012)
    kStepOatSander,    // solid-angle ratio (Oat & Sander 2007)
    kStepPoint,        // the point value at the centre
    kStepGgxReceiver,  // the Lambert closed form used for a GGX receiver (exact GGX-weighted reference)
    kBm,
    kBmFloat,
    kBmPoint,
    kChan,
    kChanFloat,
    kChanPoint,
    kPart1,
    kPart1Float,
    kPart1Point,
    kOatSanderOmega,  // |Ω_OS − Ω_Mazonka| / Ω_cap for cap ∩ cone
    kForms
  };
  static const char* names[kForms] = {"step_cosine_closed_form",
                                      "step_solid_angle_mazonka",
                                      "step_solid_angle_oat_sander",
                                      "step_point_at_centre",
                                      "step_closed_form_for_ggx_receiver",
                                      "brinck_maximov_2016_area_n4",
                                      "brinck_maximov_2016_area_n4_float",
                                      "brinck_maximov_2016_point_at_centre",
                                      "chan_2018_area_n4",
                                      "chan_2018_area_n4_float",
                                      "chan_2018_point_at_centre",
                                      "part1_analytic_area_n4",
                                      "part1_analytic_area_n4_float",
                                      "part1_analytic_point_at_centre",
                                      "oat_sander_vs_mazonka_solid_angle_fraction_of_light"};
  const auto rows = error_rows<kForms>(a.points, a, [&](const Input& in, auto& r) {
    const area::Cap cap{spherical_direction(in.nl, 0.0), in.rho};
    auto exact = [&](const auto& t) {
      return area::area_micro_shadowing_exact(cap, area::Receiver::lambert(), t);
    };
    const double step = exact(area::reference_step_term(in.V));
    r[kStepCosine] = micro_shadowing::reference_step_area_cap(in.V, in.nl, in.rho) - step;
    r[kStepMazonka] = micro_shadowing::reference_step_area_cap_solid_angle(in.V, in.nl, in.rho) - step;
    r[kStepOatSander] = micro_shadowing::reference_step_area_cap_oat_sander(in.V, in.nl, in.rho) - step;
    r[kStepPoint] = micro_shadowing::reference_step(in.V, in.nl) - step;
    {
      const Vec3d v = spherical_direction(std::max(0.05, in.nv), in.phi_v);
      const area::Receiver ggx = area::Receiver::ggx(roughness_to_alpha(std::max(0.1, in.r)), v);
      r[kStepGgxReceiver] = micro_shadowing::reference_step_area_cap(in.V, in.nl, in.rho) -
                            area::area_micro_shadowing_exact(cap, ggx, area::reference_step_term(in.V));
    }
    const float Vf = float(in.V), lf = float(in.nl), rf = float(in.rho);
    const double bm = exact(area::brinck_maximov_2016_term(in.V));
    r[kBm] = micro_shadowing::brinck_maximov_2016_area_cap(in.V, in.nl, in.rho) - bm;
    r[kBmFloat] = double(micro_shadowing::brinck_maximov_2016_area_cap(Vf, lf, rf)) - bm;
    r[kBmPoint] = micro_shadowing::brinck_maximov_2016(in.V, in.nl) - bm;
    const double ch = exact(area::chan_2018_term(in.V));
    r[kChan] = micro_shadowing::chan_2018_area_cap(in.V, in.nl, in.rho) - ch;
    r[kChanFloat] = double(micro_shadowing::chan_2018_area_cap(Vf, lf, rf)) - ch;
    r[kChanPoint] = micro_shadowing::chan_2018(in.V, in.nl) - ch;
    const double p1 = exact(area::part1_analytic_term(in.V));
    r[kPart1] = micro_shadowing::part1_analytic_area_cap(in.V, in.nl, in.rho) - p1;
    r[kPart1Float] = double(micro_shadowing::part1_analytic_area_cap(Vf, lf, rf)) - p1;
    r[kPart1Point] = micro_shadowing::part1_analytic(in.V, in.nl) - p1;
    const double t = std::acos(micro_shadowing::cone_cos_from_visibility(in.V)), th = std::acos(in.nl);
    r[kOatSanderOmega] = (micro_shadowing::cap_intersection_solid_angle_oat_sander(in.rho, t, th) -
                          micro_shadowing::cap_intersection_solid_angle(in.rho, t, th)) /
                         (2 * kPi<double> * (1 - std::cos(in.rho)));
  });

  // The generic term's azimuth mean (Lambertian receiver): its ALU fit through the product rule, against
  // the exact quadrature of the exact azimuth mean; and the quadrature alone (exact mean as M).
  enum GForm { kGenAlu, kGenQuadOnly, kGenAluPoint, kGenAluPointError, kGForms };
  static const char* gnames[kGForms] = {"generic_vndf_alu_area_n4_float", "generic_vndf_exact_mean_area_n4",
                                        "generic_vndf_alu_point_at_centre",
                                        "generic_vndf_alu_point_error_at_centre (the fit alone)"};
  const auto grows = error_rows<kGForms>(a.generic_points, a, [&](const Input& in, auto& r) {
    const double alpha = roughness_to_alpha(in.r);
    auto mean = [&](double z) {
      return micro_shadowing::generic_vndf_exact_azimuth_mean(in.V, alpha, z, in.nv);
    };
    const area::Cap cap{spherical_direction(in.nl, 0.0), in.rho};
    const area::PointTerm term{
        [&](const Vec3d& l) { return mean(std::clamp(l.z, 0.0, 1.0)); }, {1 - 2 * in.V}, true};
    const double ex = area::area_micro_shadowing_exact(cap, area::Receiver::lambert(), term, {1e-7});
    r[kGenAlu] = double(micro_shadowing::generic_vndf_alu_area_cap(float(in.V), float(in.nl), float(in.nv),
                                                                   float(in.r), float(in.rho))) -
                 ex;
    r[kGenQuadOnly] = micro_shadowing::area_cap_lambert(mean, in.nl, in.rho,
                                                        micro_shadowing::generic_vndf_kinks(in.V, in.r)) -
                      ex;
    r[kGenAluPoint] =
        double(micro_shadowing::generic_vndf_alu(float(in.V), float(in.nl), float(in.nv), float(in.r))) - ex;
    r[kGenAluPointError] =
        double(micro_shadowing::generic_vndf_alu(float(in.V), float(in.nl), float(in.nv), float(in.r))) -
        mean(in.nl);
  });

  // Disk and rect lights, Lambertian receiver: the equivalent cap (same vector form factor) with the cap
  // forms, against the exact quadrature over the true shape. Domain: V, centre N·L ∈ [0, 1]; ρ (disk edge,
  // rect half-width) ∈ [ρmin, ρmax]; rect half-height = ρ · aspect, aspect ∈ [0.25, 1]; tilt ∈ [−60°, 60°]
  // from facing the point; roll ∈ [0°, 360°).
  enum SForm {
    kDiskStep,
    kDiskStepFloat,
    kDiskStepPoint,
    kDiskBm,
    kDiskBmPoint,
    kDiskChan,
    kDiskPart1,
    kRectStep,
    kRectStepFloat,
    kRectStepPoint,
    kRectBm,
    kRectBmPoint,
    kRectChan,
    kRectPart1,
    kSForms
  };
  static const char* snames[kSForms] = {"disk_step_equivalent_cap",
                                        "disk_step_equivalent_cap_float",
                                        "disk_step_point_at_centre",
                                        "disk_brinck_maximov_2016_equivalent_cap_n4",
                                        "disk_brinck_maximov_2016_point_at_centre",
                                        "disk_chan_2018_equivalent_cap_n4",
                                        "disk_part1_analytic_equivalent_cap_n4",
                                        "rect_step_equivalent_cap",
                                        "rect_step_equivalent_cap_float",
                                        "rect_step_point_at_centre",
                                        "rect_brinck_maximov_2016_equivalent_cap_n4",
                                        "rect_brinck_maximov_2016_point_at_centre",
                                        "rect_chan_2018_equivalent_cap_n4",
                                        "rect_part1_analytic_equivalent_cap_n4"};
  const auto srows = error_rows<kSForms>(a.shape_points, a, [&](const Input& in, auto& r) {
    const ShapeLights sl = shape_lights(in);
    const area::Disk& disk = sl.disk;
    const area::Quad& quad = sl.quad;
    const Vec3d Fd = micro_shadowing::disk_vector_form_factor(disk.center, disk.normal, disk.radius);
    const Vec3d Fr = micro_shadowing::polygon_vector_form_factor(quad.corners.data(), 4);
    auto shape_rows = [&](const area::Shape& sh, const Vec3d& F, float step_float, int base) {
      auto exact = [&](const auto& t) {
        return area::area_micro_shadowing_exact(sh, area::Receiver::lambert(), t, {1e-7});
      };
      const micro_shadowing::EquivalentCap<double> e = micro_shadowing::equivalent_cap(F);
      const double step = exact(area::reference_step_term(in.V));
      r[size_t(base + 0)] = micro_shadowing::reference_step_area_cap(in.V, e.n_dot_l, e.rho) - step;
      r[size_t(base + 1)] = double(step_float) - step;
      r[size_t(base + 2)] = micro_shadowing::reference_step(in.V, in.nl) - step;
      const double bm = exact(area::brinck_maximov_2016_term(in.V));
      r[size_t(base + 3)] = micro_shadowing::brinck_maximov_2016_area_cap(in.V, e.n_dot_l, e.rho) - bm;
      r[size_t(base + 4)] = micro_shadowing::brinck_maximov_2016(in.V, in.nl) - bm;
      r[size_t(base + 5)] =
          micro_shadowing::chan_2018_area_cap(in.V, e.n_dot_l, e.rho) - exact(area::chan_2018_term(in.V));
      r[size_t(base + 6)] = micro_shadowing::part1_analytic_area_cap(in.V, e.n_dot_l, e.rho) -
                            exact(area::part1_analytic_term(in.V));
    };
    shape_rows(disk, Fd,
               micro_shadowing::reference_step_area_equivalent_cap(
                   float(in.V), micro_shadowing::disk_vector_form_factor(
                                    Vec3f(float(disk.center.x), float(disk.center.y), float(disk.center.z)),
                                    Vec3f(float(disk.normal.x), float(disk.normal.y), float(disk.normal.z)),
                                    float(disk.radius))),
               kDiskStep);
    shape_rows(quad, Fr,
               micro_shadowing::reference_step_area_equivalent_cap(
                   float(in.V), micro_shadowing::polygon_vector_form_factor(sl.quad_float.data(), 4)),
               kRectStep);
  });

  // The cone-clipped LTC forms (bsdf/ltc_shading.h): every light is a polygon (a sphere and a disk as their
  // 16-gons), the visibility cone its 16-gon. GGX receiver (roughness r ∈ [0.1, 1], N·V ∈ [0.05, 1], view
  // azimuth ∈ [0, π]) with the table fetched bilinearly and the cosine tail, against the exact GGX-weighted
  // quadrature; Lambertian receiver (identity LTC, no tail) for disks and rects. Same shape domain as above.
  enum LForm {
    kCapStepGgx,
    kCapStepGgxFloat,
    kCapStepGgxNoTail,
    kCapStepGgxLambertClosedForm,
    kCapStepGgxRepresentative,
    kCapBmGgx,
    kCapBmGgxLambertProductRule,
    kCapBmGgxRepresentative,
    kCapChanGgx,
    kCapPart1Ggx,
    kDiskStepGgx,
    kDiskStepGgxEquivalentCap,
    kDiskBmGgx,
    kRectStepGgx,
    kRectStepGgxEquivalentCap,
    kRectStepGgxRepresentative,
    kRectBmGgx,
    kDiskStepLambert,
    kDiskBmLambert,
    kDiskChanLambert,
    kDiskPart1Lambert,
    kRectStepLambert,
    kRectStepLambertFloat,
    kRectBmLambert,
    kRectChanLambert,
    kRectPart1Lambert,
    kLForms
  };
  static const char* lnames[kLForms] = {"ltc_cap_step_ggx_cone_clip",
                                        "ltc_cap_step_ggx_cone_clip_float",
                                        "ltc_cap_step_ggx_cone_clip_no_tail",
                                        "ltc_cap_step_ggx_lambert_closed_form",
                                        "ltc_cap_step_ggx_point_at_ltc_representative_direction",
                                        "ltc_cap_brinck_maximov_2016_ggx_cone_clip_n4",
                                        "ltc_cap_brinck_maximov_2016_ggx_lambert_product_rule",
                                        "ltc_cap_brinck_maximov_2016_ggx_point_at_ltc_representative",
                                        "ltc_cap_chan_2018_ggx_cone_clip_n4",
                                        "ltc_cap_part1_analytic_ggx_cone_clip_n4",
                                        "ltc_disk_step_ggx_cone_clip",
                                        "ltc_disk_step_ggx_lambert_equivalent_cap",
                                        "ltc_disk_brinck_maximov_2016_ggx_cone_clip_n4",
                                        "ltc_rect_step_ggx_cone_clip",
                                        "ltc_rect_step_ggx_lambert_equivalent_cap",
                                        "ltc_rect_step_ggx_point_at_ltc_representative_direction",
                                        "ltc_rect_brinck_maximov_2016_ggx_cone_clip_n4",
                                        "ltc_disk_step_lambert_cone_clip",
                                        "ltc_disk_brinck_maximov_2016_lambert_cone_clip_n4",
                                        "ltc_disk_chan_2018_lambert_cone_clip_n4",
                                        "ltc_disk_part1_analytic_lambert_cone_clip_n4",
                                        "ltc_rect_step_lambert_cone_clip",
                                        "ltc_rect_step_lambert_cone_clip_float",
                                        "ltc_rect_brinck_maximov_2016_lambert_cone_clip_n4",
                                        "ltc_rect_chan_2018_lambert_cone_clip_n4",
                                        "ltc_rect_part1_analytic_lambert_cone_clip_n4"};
  const auto lrows = error_rows<kLForms>(a.ltc_points, a, [&](const Input& in, auto& row) {
    const GgxCapPoint p = ggx_cap_point(in, table);
    const Vec3d &n = p.n, &v = p.g.v, &c = p.c;
    const area::Cap& cap = p.cap;
    const ShapeLights sl = shape_lights(in);
    const area::Disk& disk = sl.disk;
    const area::Quad& quad = sl.quad;
    const area::Receiver &ggx = p.ggx, lam = area::Receiver::lambert();
    auto exact = [&](const area::Shape& sh, const area::Receiver& rc, const auto& t) {
      return area::area_micro_shadowing_exact(sh, rc, t, {1e-7});
    };
    const double V = in.V, ct = micro_shadowing::cone_cos_from_visibility(V);
    const auto step_t = area::reference_step_term(V);
    const auto bm_t = area::brinck_maximov_2016_term(V);
    auto bm = [V](double z) { return micro_shadowing::brinck_maximov_2016(V, z); };
    auto chan = [V](double z) { return micro_shadowing::chan_2018(V, z); };
    auto part1 = [V](double z) { return micro_shadowing::part1_analytic(V, z); };
    const auto bk = micro_shadowing::brinck_maximov_2016_kinks(V);
    const auto chan_t = area::chan_2018_term(V), part1_t = area::part1_analytic_term(V);
    const auto chan_k = micro_shadowing::chan_2018_kinks(V),
               part1_k = micro_shadowing::part1_analytic_kinks(V);
    const bsdf::LtcCoeffs<double>& k = p.k;
    const bsdf::Mat3<double> minv = k.inv_m(), id{};
    const double tail = bsdf::ltc_tail_weight(p.g.alpha);
    const auto& lc = p.lc;
    const auto ld = bsdf::ltc_light_cone_disk(minv, n, v, disk.center, disk.normal, disk.radius, tail);
    const auto lr = bsdf::ltc_light_cone_polygon(minv, n, v, quad.corners.data(), 4, tail);
    const auto ldl = bsdf::ltc_light_cone_disk(id, n, v, disk.center, disk.normal, disk.radius);
    const auto lrl = bsdf::ltc_light_cone_polygon(id, n, v, quad.corners.data(), 4);
    const auto rep_cap = bsdf::ltc_shade_sphere(k, n, v, c, std::sin(in.rho));
    const auto rep_rect = bsdf::ltc_shade_polygon(k, n, v, quad.corners.data(), 4);
    const auto eqd = micro_shadowing::equivalent_cap(
        micro_shadowing::disk_vector_form_factor(disk.center, disk.normal, disk.radius));
    const auto eqr =
        micro_shadowing::equivalent_cap(micro_shadowing::polygon_vector_form_factor(quad.corners.data(), 4));
    const double sc = exact(cap, ggx, step_t), bc = exact(cap, ggx, bm_t);
    row[kCapStepGgx] = bsdf::ltc_reference_step_area(lc, ct) - sc;
    row[kCapStepGgxFloat] = double(bsdf::ltc_reference_step_area(p.lf, float(ct))) - sc;
    row[kCapStepGgxNoTail] =
        bsdf::ltc_reference_step_area(bsdf::ltc_light_cone_sphere(minv, n, v, c, std::sin(in.rho)), ct) - sc;
    row[kCapStepGgxLambertClosedForm] = micro_shadowing::reference_step_area_cap(V, in.nl, in.rho) - sc;
    row[kCapStepGgxRepresentative] =
        bsdf::ltc_ms_at_representative(rep_cap,
                                       [&](double z) { return micro_shadowing::reference_step(V, z); }) -
        sc;
    row[kCapBmGgx] = bsdf::ltc_micro_shadowing_area(bm, lc, bk) - bc;
    row[kCapBmGgxLambertProductRule] = micro_shadowing::brinck_maximov_2016_area_cap(V, in.nl, in.rho) - bc;
    row[kCapBmGgxRepresentative] = bsdf::ltc_ms_at_representative(rep_cap, bm) - bc;
    row[kCapChanGgx] = bsdf::ltc_micro_shadowing_area(chan, lc, chan_k) - exact(cap, ggx, chan_t);
    row[kCapPart1Ggx] = bsdf::ltc_micro_shadowing_area(part1, lc, part1_k) - exact(cap, ggx, part1_t);
    const double sd = exact(disk, ggx, step_t), sr = exact(quad, ggx, step_t);
    row[kDiskStepGgx] = bsdf::ltc_reference_step_area(ld, ct) - sd;
    row[kDiskStepGgxEquivalentCap] = micro_shadowing::reference_step_area_cap(V, eqd.n_dot_l, eqd.rho) - sd;
    row[kDiskBmGgx] = bsdf::ltc_micro_shadowing_area(bm, ld, bk) - exact(disk, ggx, bm_t);
    row[kRectStepGgx] = bsdf::ltc_reference_step_area(lr, ct) - sr;
    row[kRectStepGgxEquivalentCap] = micro_shadowing::reference_step_area_cap(V, eqr.n_dot_l, eqr.rho) - sr;
    row[kRectStepGgxRepresentative] =
        bsdf::ltc_ms_at_representative(rep_rect,
                                       [&](double z) { return micro_shadowing::reference_step(V, z); }) -
        sr;
    row[kRectBmGgx] = bsdf::ltc_micro_shadowing_area(bm, lr, bk) - exact(quad, ggx, bm_t);
    // The four N·L-only terms of a Lambertian receiver (identity LTC) through the cone-clipped form over
    // `sh`, against the exact quadrature; returns the exact step integral.
    auto lambert_rows = [&](const area::Shape& sh, const auto& cone, int step, int bm_i, int chan_i,
                            int part1_i) {
      const double s = exact(sh, lam, step_t);
      row[size_t(step)] = bsdf::ltc_reference_step_area(cone, ct) - s;
      row[size_t(bm_i)] = bsdf::ltc_micro_shadowing_area(bm, cone, bk) - exact(sh, lam, bm_t);
      row[size_t(chan_i)] = bsdf::ltc_micro_shadowing_area(chan, cone, chan_k) - exact(sh, lam, chan_t);
      row[size_t(part1_i)] = bsdf::ltc_micro_shadowing_area(part1, cone, part1_k) - exact(sh, lam, part1_t);
      return s;
    };
    lambert_rows(disk, ldl, kDiskStepLambert, kDiskBmLambert, kDiskChanLambert, kDiskPart1Lambert);
    const double srl =
        lambert_rows(quad, lrl, kRectStepLambert, kRectBmLambert, kRectChanLambert, kRectPart1Lambert);
    // The rect's step in float, as a shader evaluates it (same exact integral).
    const auto lrf =
        bsdf::ltc_light_cone_polygon(bsdf::Mat3<float>{}, Vec3f(0, 0, 1), Vec3f(v), sl.quad_float.data(), 4);
    row[kRectStepLambertFloat] = double(bsdf::ltc_reference_step_area(lrf, float(ct))) - srl;
  });

  // The generic and micro-BRDF-aware terms over a sphere light. GGX receiver (same domain as the LTC block):
  // the azimuth means (generic: exact mean and its ALU fit; specular-aware: closed form) through the
  // cone-clipped LTC product rule, against the exact quadrature of the FULL-direction term over the light
  // (the light at azimuth 0, the view at φ_v). Diffuse-aware, Lambertian receiver (--diffuse-aware-points):
  // its ALU fit through the cap product rule against the exact quadrature of the exact azimuth mean (every
  // point value is a 2D VNDF quadrature: ~10 s CPU per light).
  enum AForm {
    kGenLtcExactMean,
    kGenLtcAlu,
    kGenLambertProductRuleAlu,
    kGenRepresentative,
    kSpecLtc,
    kSpecLtcFloat,
    kSpecRepresentative,
    kAForms
  };
  static const char* anames[kAForms] = {"ggx_cap_generic_vndf_exact_mean_ltc_cone_clip_n4",
                                        "ggx_cap_generic_vndf_alu_ltc_cone_clip_n4_float",
                                        "ggx_cap_generic_vndf_alu_lambert_product_rule",
                                        "ggx_cap_generic_vndf_exact_point_at_ltc_representative",
                                        "ggx_cap_specular_aware_mean_ltc_cone_clip_n4",
                                        "ggx_cap_specular_aware_mean_ltc_cone_clip_n4_float",
                                        "ggx_cap_specular_aware_point_at_ltc_representative"};
  const auto arows = error_rows<kAForms>(a.aware_points, a, [&](const Input& in, auto& row) {
    const GgxCapPoint p = ggx_cap_point(in, table);
    const double nv = p.g.nv, r = p.g.r, alpha = p.g.alpha;
    const Vec3d& v = p.g.v;
    const area::Cap& cap = p.cap;
    const area::Receiver& ggx = p.ggx;
    const double V = in.V;
    const bsdf::LtcLightCone<double>& lc = p.lc;
    const bsdf::LtcLightCone<float>& lf = p.lf;
    const Vec3d rep = bsdf::ltc_shade_sphere(p.k, p.n, v, p.c, std::sin(in.rho)).direction;
    const double gen =
        area::area_micro_shadowing_exact(cap, ggx, area::generic_vndf_term(V, alpha, alpha, v), {1e-6});
    const auto gk = micro_shadowing::generic_vndf_kinks(V, r);
    row[kGenLtcExactMean] =
        bsdf::ltc_micro_shadowing_area(
            [&](double z) { return micro_shadowing::generic_vndf_exact_azimuth_mean(V, alpha, z, nv); }, lc,
            gk) -
        gen;
    row[kGenLtcAlu] =
        double(bsdf::ltc_micro_shadowing_area(
            [&](float z) { return micro_shadowing::generic_vndf_alu(float(V), z, float(nv), float(r)); }, lf,
            micro_shadowing::generic_vndf_kinks(float(V), float(r)))) -
        gen;
    row[kGenLambertProductRuleAlu] = double(micro_shadowing::generic_vndf_alu_area_cap(
                                         float(V), float(in.nl), float(nv), float(r), float(in.rho))) -
                                     gen;
    row[kGenRepresentative] = micro_shadowing::generic_vndf_exact(V, alpha, alpha, v, rep) - gen;
    const double spec = area::area_micro_shadowing_exact(cap, ggx, area::specular_aware_term(V, v), {1e-6});
    row[kSpecLtc] =
        bsdf::ltc_micro_shadowing_area(
            [&](double z) { return micro_shadowing::specular_aware_azimuth_mean(V, alpha, z, nv); }, lc,
            micro_shadowing::specular_aware_kinks(V, nv)) -
        spec;
    row[kSpecLtcFloat] =
        double(bsdf::ltc_micro_shadowing_area(
            [&](float z) {
              return micro_shadowing::specular_aware_azimuth_mean(float(V), float(alpha), z, float(nv));
            },
            lf, micro_shadowing::specular_aware_kinks(float(V), float(nv)))) -
        spec;
    row[kSpecRepresentative] = micro_shadowing::specular_aware(V, v, rep) - spec;
  });
  std::vector<double> daware(size_t(a.diffuse_aware_points)), daware_point(daware.size());
  tbb::parallel_for(0, a.diffuse_aware_points, [&](int i) {
    const Input in = input_at(uint32_t(i), a);
    const ClampedView g = clamped_view(in);
    const double nv = g.nv, r = g.r, alpha = g.alpha;
    const area::Cap cap{spherical_direction(in.nl, 0.0), in.rho};
    const double ex = area::area_micro_shadowing_exact(
        cap, area::Receiver::lambert(),
        area::diffuse_aware_azimuth_mean_term(in.V, alpha, nv, micro_shadowing::DiffuseAwareForm::Reciprocal),
        {1e-6});
    const float Vf = float(in.V), nvf = float(nv), rf = float(r);
    daware[size_t(i)] = double(micro_shadowing::area_cap_lambert(
                            [&](float z) { return micro_shadowing::diffuse_aware_alu(Vf, z, nvf, rf); },
                            float(in.nl), float(in.rho), micro_shadowing::diffuse_aware_kinks(Vf))) -
                        ex;
    daware_point[size_t(i)] = double(micro_shadowing::diffuse_aware_alu(Vf, float(in.nl), nvf, rf)) - ex;
  });

  nlohmann::json forms = nlohmann::json::object();
  // One summary per form (column) of a table of rows.
  auto add_forms = [&forms](const auto& table, const char* const* form_names, int count) {
    for (int f = 0; f < count; ++f) {
      std::vector<double> e;
      for (const auto& r : table) e.push_back(r[size_t(f)]);
      forms[form_names[f]] = summary(e);
    }
  };
  add_forms(srows, snames, kSForms);
  add_forms(rows, names, kForms);
  add_forms(grows, gnames, kGForms);
  add_forms(lrows, lnames, kLForms);
  add_forms(arows, anames, kAForms);
  forms["lambert_cap_diffuse_aware_alu_product_rule_n4_float"] = summary(daware);
  forms["lambert_cap_diffuse_aware_alu_point_at_centre"] = summary(daware_point);
  const nlohmann::json out = {
      {"domain",
       {{"visibility", {0, 1}},
        {"ndotl_centre", {0, 1}},
        {"light_radius_deg", {a.rho_min_deg, a.rho_max_deg}},
        {"ndotv", {0, 1}},
        {"roughness", {0, 1}},
        {"sampling", "padded 2D Owen-scrambled Sobol"},
        {"light", "spherical cap centred on the N.L direction, Lambertian receiver unless stated"}}},
      {"points", a.points},
      {"generic_points", a.generic_points},
      {"shape_points", a.shape_points},
      {"ltc_points", a.ltc_points},
      {"ltc_table", ltc_source},
      {"aware_points", a.aware_points},
      {"diffuse_aware_points", a.diffuse_aware_points},
      {"ltc_domain",
       "sphere (cap), disk and rect lights as above; GGX receiver: roughness in [0.1, 1], N.V in [0.05, 1], "
       "view azimuth in [0, pi], LTC fetched bilinearly, tail weight 1.5 alpha^1.5, against the exact "
       "GGX-weighted quadrature; Lambertian receiver: identity LTC, no tail; light and cone as 16-gons"},
      {"shape_domain",
       "disk (edge radius rho) and rect (half-width rho, half-height rho * aspect, aspect in [0.25, 1]) "
       "centred "
       "on the N.L direction, tilt in [-60, 60] deg from facing the point, roll in [0, 360) deg; Lambertian "
       "receiver; fast form = the cap forms at the equivalent cap (same vector form factor)"},
      {"errors", forms}};
  if (a.json) {
    print_json(out);
    return;
  }
  fmt::print("{:<58} {:>8} {:>9} {:>9} {:>9}\n", "form (|error| in 1/255)", "count", "rms", "p99", "max");
  for (const auto& [k, v] : forms.items())
    if (!v.is_null())
      fmt::print("{:<58} {:>8} {:>9.4f} {:>9.4f} {:>9.4f}\n", k, v["count"].get<int>(),
                 v["rms_255"].get<double>(), v["p99_255"].get<double>(), v["max_255"].get<double>());
}

void add_area_lights(Groups& g) {
  auto a = std::make_shared<VerifyArgs>();
  CLI::App* c = g.verify->add_subcommand(
      "area-lights",
      "Area-light micro-shadowing fast forms (occlusion/micro_shadowing_area.h) against the exact quadrature "
      "at Sobol inputs (docs/area-lights.md): errors in 1/255.");
  c->add_option("--points", a->points, "Sobol points for the closed-form terms")->capture_default_str();
  c->add_option("--generic-points", a->generic_points, "Sobol points for the generic term (slow reference)")
      ->capture_default_str();
  c->add_option("--shape-points", a->shape_points, "Sobol points for the disk and rect lights")
      ->capture_default_str();
  c->add_option("--rho-min-deg", a->rho_min_deg, "Smallest light radius (degrees)")
      ->check(Finite)
      ->capture_default_str();
  c->add_option("--rho-max-deg", a->rho_max_deg, "Largest light radius (degrees)")
      ->check(Finite)
      ->capture_default_str();
  c->add_option("--ltc-points", a->ltc_points,
                "Sobol points for the cone-clipped LTC forms (bsdf/ltc_shading.h), 0 = skip")
      ->capture_default_str();
  c->add_option("--aware-points", a->aware_points,
                "Sobol points for the generic and specular-aware terms over a sphere light, GGX receiver "
                "(exact full-direction reference: 0.1 s to minutes of CPU each)")
      ->capture_default_str();
  c->add_option("--diffuse-aware-points", a->diffuse_aware_points,
                "Sobol points for the diffuse-aware ALU fit over a sphere light, Lambertian receiver (exact "
                "reference: 8 s to minutes of CPU each)")
      ->capture_default_str();
  c->add_option("--ltc", a->ltc, "LTC table (bake ltc); default: fit a 16x16 table here (about 9 s CPU)");
  c->add_flag("--json", a->json, "Print one JSON object");
  c->callback([a] { run_verify(*a); });
}

}  // namespace

MSH_CLI_REGISTER(add_area_lights, 75);

}  // namespace msh::cli
