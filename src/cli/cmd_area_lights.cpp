// `verify area-lights`: the area-light fast forms (occlusion/micro_shadowing_area.h) measured as used against
// the exact quadrature (reference/micro_shadowing_area_exact.h) at Sobol inputs over V ∈ [0, 1],
// N·L ∈ [0, 1] (the cap's centre), light radius ρ ∈ [1°, 40°] (docs/area-lights.md):
//
//   microshadow verify area-lights [--points N] [--generic-points M] [--shape-points K] [--json]
//
// Errors are |fast − exact| in units of 1/255 (RMS, p99, max) over all points.
#include <fmt/format.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
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
  int points = 2048, generic_points = 96, shape_points = 512;
  double rho_min_deg = 1, rho_max_deg = 40;
  bool json = false;
};

// One input point: padded 2D Owen-scrambled Sobol (independent seeds per pair of dimensions).
struct Input {
  double V, nl, rho, nv, r, phi_v;
};
Input input_at(uint32_t i, const VerifyArgs& a) {
  const Vec2d p = sobol_2d<double>(i, 0x51u), q = sobol_2d<double>(i, 0x9e37u),
              s = sobol_2d<double>(i, 0x7f4au);
  return {p.x, p.y, (a.rho_min_deg + (a.rho_max_deg - a.rho_min_deg) * q.x) * kDeg,
          q.y, s.x, s.y * kPi<double>};
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
  if (!(a.rho_min_deg >= 0 && a.rho_min_deg <= a.rho_max_deg && a.rho_max_deg <= 90))
    throw UsageError("--rho-min-deg and --rho-max-deg must satisfy 0 <= min <= max <= 90");

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
  std::vector<std::array<double, kForms>> rows(size_t(a.points));
  tbb::parallel_for(0, a.points, [&](int i) {
    const Input in = input_at(uint32_t(i), a);
    const area::Cap cap{spherical_direction(in.nl, 0.0), in.rho};
    auto exact = [&](const auto& t) {
      return area::area_micro_shadowing_exact(cap, area::Receiver::lambert(), t);
    };
    auto& r = rows[size_t(i)];
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
  std::vector<std::array<double, kGForms>> grows(size_t(a.generic_points));
  tbb::parallel_for(0, a.generic_points, [&](int i) {
    const Input in = input_at(uint32_t(i), a);
    const double alpha = roughness_to_alpha(in.r);
    auto mean = [&](double z) {
      return micro_shadowing::generic_vndf_exact_azimuth_mean(in.V, alpha, z, in.nv);
    };
    const area::Cap cap{spherical_direction(in.nl, 0.0), in.rho};
    const area::PointTerm term{
        [&](const Vec3d& l) { return mean(std::clamp(l.z, 0.0, 1.0)); }, {1 - 2 * in.V}, true};
    const double ex = area::area_micro_shadowing_exact(cap, area::Receiver::lambert(), term, {1e-7});
    auto& r = grows[size_t(i)];
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
  std::vector<std::array<double, kSForms>> srows(size_t(a.shape_points));
  tbb::parallel_for(0, a.shape_points, [&](int i) {
    const Input in = input_at(uint32_t(i), a);
    const Vec2d o = sobol_2d<double>(uint32_t(i), 0x3c6eu), w = sobol_2d<double>(uint32_t(i), 0x2545u);
    const double tilt = (-60 + 120 * o.x) * kDeg, roll = 2 * kPi<double> * o.y, aspect = 0.25 + 0.75 * w.x;
    const Vec3d c = spherical_direction(in.nl, 0.0);
    const area::Disk disk = area::disk_tilted(c, in.rho, tilt, roll);
    const area::Quad quad = area::rect_tilted(c, in.rho, in.rho * aspect, tilt, roll);
    const Vec3d Fd = micro_shadowing::disk_vector_form_factor(disk.center, disk.normal, disk.radius);
    const Vec3d Fr = micro_shadowing::polygon_vector_form_factor(quad.corners.data(), 4);
    std::array<Vec3f, 4> qf;
    for (int k = 0; k < 4; ++k)
      qf[size_t(k)] = Vec3f(float(quad.corners[size_t(k)].x), float(quad.corners[size_t(k)].y),
                            float(quad.corners[size_t(k)].z));
    auto& r = srows[size_t(i)];
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
                   float(in.V), micro_shadowing::polygon_vector_form_factor(qf.data(), 4)),
               kRectStep);
  });

  nlohmann::json forms = nlohmann::json::object();
  for (int f = 0; f < kSForms; ++f) {
    std::vector<double> e;
    for (const auto& r : srows) e.push_back(r[size_t(f)]);
    forms[snames[f]] = summary(e);
  }
  for (int f = 0; f < kForms; ++f) {
    std::vector<double> e;
    for (const auto& r : rows) e.push_back(r[size_t(f)]);
    forms[names[f]] = summary(e);
  }
  for (int f = 0; f < kGForms; ++f) {
    std::vector<double> e;
    for (const auto& r : grows) e.push_back(r[size_t(f)]);
    forms[gnames[f]] = summary(e);
  }
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
  c->add_flag("--json", a->json, "Print one JSON object");
  c->callback([a] { run_verify(*a); });
}

}  // namespace

MSH_CLI_REGISTER(add_area_lights, 75);

}  // namespace msh::cli
