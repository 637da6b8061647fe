// `eval micro-shadowing` and `plot micro-shadowing`: the micro-shadowing terms of
// include/microshadow/occlusion/micro_shadowing.h (docs/micro-shadowing.md).
//
//   microshadow eval micro-shadowing --method generic-vndf --visibility 0.5 --roughness 0.4 --ndotl 0.3
//       --ndotv 0.8 [--phi 1.2] [--roughness-y R] [--samples N] [--g2 height-correlated|uncorrelated] --json
//   (methods: the table of occlusion/runtime/micro_shadowing_methods.h, `--help` lists them)
//   ... --light-radius-deg RHO [--light-shape sphere|disk|rect] [--light-tilt-deg T] [--light-roll-deg R]
//       [--light-half-height-deg H] [--receiver lambert|ggx]: the term averaged over an area light
//       (docs/area-lights.md)
//   microshadow plot micro-shadowing --out DIR [--size N] [--azimuth-configs N] [--mc-samples N]
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/lut/runtime/micro_shadowing_analysis.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/reference/runtime/micro_shadowing_area_method.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <vector>

#include "common.h"

namespace msh::lut {
// summary.json's statistics: one key per field, named as the field.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(AbsErrorSummary, count, rms, p50, p90, p99, max,
                                   frac_above_half_unorm8_step)
}  // namespace msh::lut

namespace msh::cli {
namespace {

using micro_shadowing::G2Form;

struct EvalArgs {
  std::string method = "generic-vndf", g2 = "height-correlated", lut;
  double visibility = 1, roughness = 0.5, ndotl = 1, ndotv = 1, phi = 0, roughness_y = 0;
  int64_t samples = 0;
  uint32_t seed = 1;
  bool json = false;
  CLI::Option *phi_opt = nullptr, *ry_opt = nullptr, *samples_opt = nullptr;
  // Area light (docs/area-lights.md).
  std::string light_shape = "sphere", receiver = "lambert";
  double light_radius_deg = 0, light_tilt_deg = 0, light_roll_deg = 0, light_half_height_deg = 0;
  CLI::Option *radius_opt = nullptr, *shape_opt = nullptr, *tilt_opt = nullptr, *roll_opt = nullptr,
              *hh_opt = nullptr, *receiver_opt = nullptr;
};

// The light of the area options, centred on the N.L direction at azimuth phi (v at azimuth 0).
area::Shape area_light_shape(const EvalArgs& a, double phi) {
  const double deg = kPi<double> / 180;
  const Vec3d c = lut::study_light_dir(a.ndotl, phi);
  const double rho = a.light_radius_deg * deg, tilt = a.light_tilt_deg * deg, roll = a.light_roll_deg * deg;
  if (a.light_shape == "disk") return area::disk_tilted(c, rho, tilt, roll);
  if (a.light_shape == "rect") {
    const double hh = a.hh_opt->count() ? a.light_half_height_deg * deg : rho;
    return area::rect_tilted(c, rho, hh, tilt, roll);
  }
  return area::Cap{c, rho};
}

// Validates the area options; false when none is given (the point term).
bool check_area_args(const EvalArgs& a) {
  const bool any = a.shape_opt->count() || a.tilt_opt->count() || a.roll_opt->count() || a.hh_opt->count() ||
                   a.receiver_opt->count();
  if (!a.radius_opt->count()) {
    if (any)
      throw UsageError(
          "--light-shape, --light-tilt-deg, --light-roll-deg, --light-half-height-deg and --receiver need "
          "--light-radius-deg");
    return false;
  }
  require_range(a.light_radius_deg, 0, 90, "--light-radius-deg");
  if (a.light_shape != "sphere" && a.light_shape != "disk" && a.light_shape != "rect")
    throw UsageError(fmt::format("--light-shape must be sphere, disk or rect, got '{}'", a.light_shape));
  if (a.receiver != "lambert" && a.receiver != "ggx")
    throw UsageError(fmt::format("--receiver must be lambert or ggx, got '{}'", a.receiver));
  if (a.light_shape == "sphere" && (a.tilt_opt->count() || a.roll_opt->count() || a.hh_opt->count()))
    throw UsageError("--light-tilt-deg, --light-roll-deg and --light-half-height-deg apply to disk and rect");
  if (a.light_shape == "disk" && a.hh_opt->count())
    throw UsageError("--light-half-height-deg applies to rect only");
  if (a.light_shape != "sphere") {
    if (!(a.light_radius_deg < 90))
      throw UsageError(
          fmt::format("--light-radius-deg of a {} must be < 90, got {}", a.light_shape, a.light_radius_deg));
    if (!(std::abs(a.light_tilt_deg) < 90))
      throw UsageError(fmt::format("--light-tilt-deg must be in (-90, 90), got {}", a.light_tilt_deg));
    require_range(a.light_roll_deg, -360, 360, "--light-roll-deg");
    if (a.hh_opt->count() && !(a.light_half_height_deg >= 0 && a.light_half_height_deg < 90))
      throw UsageError(
          fmt::format("--light-half-height-deg must be in [0, 90), got {}", a.light_half_height_deg));
  }
  return true;
}

G2Form parse_g2(const std::string& s) {
  if (s == "height-correlated") return G2Form::HeightCorrelated;
  if (s == "uncorrelated") return G2Form::Uncorrelated;
  throw UsageError(fmt::format("--g2 must be height-correlated or uncorrelated, got '{}'", s));
}

// What the LUT methods report beside the value: which table, its layout and sizes.
void describe_table(nlohmann::json& out, const lut::MicroShadowingLut& table, const std::string& path,
                    bool has_phi) {
  const lut::MicroShadowingLutView view = table.view();
  out["lut"] = path.empty() ? nlohmann::json("default (baked on first use)") : nlohmann::json(path);
  out["lut_layout"] = lut::layout_name(view.layout);
  out["lut_size"] = {view.n_vis, view.n_nl, view.n_nv};
  if (view.layout == lut::LutLayout::Cone) {
    out["lut_roughness_slabs"] = view.n_rough;
    out["lut_roughness_range"] = {lut::short_float(view.cone.roughness_min),
                                  lut::short_float(view.cone.roughness_max)};
  } else {
    out["lut_roughness"] = table.roughness;
  }
  out["harmonics"] = view.harmonics;
  out["azimuth"] = has_phi && view.harmonics > 0 ? "fixed (Fourier harmonics)" : "mean over [0, pi]";
}

// Parses, evaluates through the method table (occlusion/runtime/micro_shadowing_methods.h) and prints.
void run_eval(const EvalArgs& a) {
  const bool has_phi = a.phi_opt->count() > 0, has_ry = a.ry_opt->count() > 0;
  if (a.samples_opt->count() && (a.samples < 1 || a.samples > (int64_t(1) << 30)))
    throw UsageError(fmt::format("--samples must be in [1, 2^30], got {}", a.samples));
  const G2Form form = parse_g2(a.g2);
  const occlusion::MicroShadowingEvaluator method(a.method, {a.samples, a.seed, form, a.lut});
  const bool area_mode = check_area_args(a);
  occlusion::MicroShadowingQuery q{a.visibility, a.ndotl, a.ndotv, a.roughness, std::nullopt, std::nullopt};
  // With a light, --phi is the light's azimuth for every method (a GGX receiver depends on it); the term
  // itself reads it only if it accepts it.
  if (has_phi && (!area_mode || method.info().accepts_phi)) q.phi = a.phi;
  if (has_ry) q.roughness_y = a.roughness_y;
  if (area_mode && has_phi) require_range(a.phi, 0, kPi<double>, "--phi (relative azimuth, radians)");
  if (method.info().is_pair()) {
    // A pair has one value per lobe.
    if (area_mode)
      throw UsageError(
          fmt::format("--light-radius-deg does not apply to the pair {}: evaluate {} and {} one "
                      "at a time",
                      a.method, method.info().diffuse, method.info().specular));
    const auto [d, s] = method.eval_lobes(q);  // validates every input first
    nlohmann::json out = {{"method", a.method},
                          {"diffuse_method", method.info().diffuse},
                          {"specular_method", method.info().specular},
                          {"diffuse", d},
                          {"specular", s}};
    if (a.json)
      print_json(out);
    else
      fmt::print("{:.9g} {:.9g}\n", d, s);
    return;
  }
  double value = method.eval(q);  // validates every input first
  nlohmann::json light;
  if (area_mode) {
    const area::Shape shape = area_light_shape(a, has_phi ? a.phi : 0.0);
    const bool ggx = a.receiver == "ggx";
    const double axr = roughness_to_alpha(a.roughness),
                 ayr = roughness_to_alpha(has_ry ? a.roughness_y : a.roughness);
    const area::Receiver rec =
        ggx ? area::Receiver::ggx(axr, ayr, lut::study_view_dir(a.ndotv)) : area::Receiver::lambert();
    light = {{"shape", a.light_shape},
             {"radius_deg", a.light_radius_deg},
             {"azimuth", has_phi ? a.phi : 0.0},
             {"receiver", a.receiver},
             {"point_value", value}};
    if (a.light_shape != "sphere") light["tilt_deg"] = a.light_tilt_deg, light["roll_deg"] = a.light_roll_deg;
    if (a.light_shape == "rect")
      light["half_height_deg"] = a.hh_opt->count() ? a.light_half_height_deg : a.light_radius_deg;
    // A zero-size light is the point value itself (bit-identical to the command without a light).
    if (!area::shape_is_point(shape)) value = occlusion::area_micro_shadowing(method, q, shape, rec);
    light["estimator"] = area::shape_is_point(shape)
                             ? "point value (zero-size light)"
                             : (q.phi || !method.info().accepts_phi
                                    ? "exact quadrature over the light"
                                    : "exact quadrature over the light of the term's azimuth mean");
  }

  const double ax = roughness_to_alpha(a.roughness),
               ay = roughness_to_alpha(has_ry ? a.roughness_y : a.roughness);
  const bool early = micro_shadowing::exact_zero(a.visibility, a.ndotl);
  nlohmann::json inputs = {
      {"visibility", a.visibility}, {"roughness", a.roughness}, {"alpha_x", ax}, {"alpha_y", ay},
      {"ndotl", a.ndotl},           {"ndotv", a.ndotv},         {"g2", a.g2}};
  inputs["phi"] = has_phi ? nlohmann::json(a.phi) : nlohmann::json(nullptr);
  nlohmann::json out = {{"method", a.method}, {"inputs", inputs}, {"early_out", early}};
  const std::string& m = a.method;
  if (method.info().accepts_lut) {
    // The default table is not baked for an early-out point: the sampler returns 0 before any fetch.
    if (!a.lut.empty() || !early)
      describe_table(out, *method.table(has_phi), a.lut, has_phi);
    else
      out["lut"] = "default (not needed: early-out)";
  } else if (m == "generic-vndf-alu") {
    // value = the one-call form, two_stage = the per-pixel + per-light form (float, as a shader runs them).
    out["two_stage"] = micro_shadowing::generic_vndf_alu_two_stage(float(a.visibility), float(a.ndotl),
                                                                   float(a.ndotv), float(a.roughness));
    out["azimuth"] = "mean over [0, pi]";
  } else if (m == "generic-vndf" || m == "generic-vndf-beckmann" || m == "generic-vcavity") {
    // The generic term of a microsurface profile (GGX, Smith-Beckmann, Beckmann-Spizzichino + V-cavity).
    out["azimuth"] = has_phi ? "fixed" : "mean over [0, pi]";
    if (a.samples > 0) {
      out["samples"] = a.samples;
      out["seed"] = a.seed;
      out["estimator"] = has_phi ? "sobol-owen" : "sobol-owen, 32 azimuth strata";
    } else {
      out["samples"] = nullptr;
      out["estimator"] = "exact quadrature (|error| < 1e-6)";
    }
  }
  if (area_mode) out["light"] = light;
  out["value"] = value;
  if (a.json)
    print_json(out);
  else
    fmt::print("{:.9g}\n", value);
}

// ---- plot ------------------------------------------------------------------------------------------------

struct PlotArgs {
  std::string out;
  int size = 33;
  int azimuth_configs = 2000;
  int64_t mc_samples = int64_t(1) << 22;
};

const std::vector<double> kPlotRoughness = {0.0, 0.1, 0.4, 0.7, 1.0};
const std::vector<double> kPlotNdotV = {1.0, 0.5, 0.1};

std::string fmtd(double x) { return fmt::format("{:.9g}", x); }

void run_plot(const PlotArgs& a) {
  if (a.out.empty()) throw UsageError("--out is required");
  if (a.size < 2 || a.size > 257) throw UsageError(fmt::format("--size must be in [2, 257], got {}", a.size));
  if (a.azimuth_configs < 0 || a.azimuth_configs > 1000000)
    throw UsageError("--azimuth-configs must be in [0, 1e6]");
  if (a.mc_samples < 0 || a.mc_samples > (int64_t(1) << 28))
    throw UsageError("--mc-samples must be in [0, 2^28]");
  const std::filesystem::path dir = make_out_dir(a.out);

  // 1. Maps of every method over (Visibility, N·L) for each roughness and N·V (generic: azimuth mean).
  const int n = a.size;
  const std::vector<lut::TermMapCell> cells = lut::term_maps(n, kPlotRoughness, kPlotNdotV);
  std::ostringstream maps;
  maps << "roughness,ndotv,visibility,ndotl," << fmt::format("{}", fmt::join(lut::kTermNames, ",")) << ','
       << lut::kExactTermName << '\n';
  for (const lut::TermMapCell& c : cells)
    maps << fmtd(c.roughness) << ',' << fmtd(c.n_dot_v) << ',' << fmtd(c.visibility) << ',' << fmtd(c.n_dot_l)
         << ',' << fmtd(c.reference) << ',' << fmtd(c.brinck_maximov) << ',' << fmtd(c.chan) << ','
         << fmtd(c.part1) << ',' << fmtd(c.generic) << '\n';
  io::write_file_atomic(dir / "maps.csv", maps.str());

  // 2. Error of the older terms vs the exact generic term, per roughness and N·V (RMS and max over the map).
  std::ostringstream err;
  err << "roughness,ndotv,method,rms,max_abs,mean_signed\n";
  for (double r : kPlotRoughness)
    for (double nv : kPlotNdotV) {
      const std::array<lut::TermError, 4> e = lut::term_map_errors(cells, r, nv);
      for (int q = 0; q < 4; ++q)
        err << fmtd(r) << ',' << fmtd(nv) << ',' << lut::kTermNames[q] << ',' << fmtd(e[q].rms) << ','
            << fmtd(e[q].max_abs) << ',' << fmtd(e[q].mean_signed) << '\n';
    }
  io::write_file_atomic(dir / "errors.csv", err.str());

  // 3. Beyond the seed: what ignoring the azimuth costs, and what H Fourier harmonics keep.
  const std::vector<lut::AzimuthConfig> az = lut::azimuth_study(size_t(a.azimuth_configs));
  std::ostringstream azc;
  azc << "visibility,roughness,ndotl,ndotv,phi,exact,azimuth_mean,error,error_h1,error_h2,error_h4\n";
  for (const lut::AzimuthConfig& z : az)
    azc << fmtd(z.visibility) << ',' << fmtd(z.roughness) << ',' << fmtd(z.n_dot_l) << ',' << fmtd(z.n_dot_v)
        << ',' << fmtd(z.phi) << ',' << fmtd(z.exact) << ',' << fmtd(z.mean) << ',' << fmtd(z.exact - z.mean)
        << ',' << fmtd(z.truncation_error(1)) << ',' << fmtd(z.truncation_error(2)) << ','
        << fmtd(z.truncation_error(4)) << '\n';
  io::write_file_atomic(dir / "azimuth_error.csv", azc.str());
  nlohmann::json summary = nlohmann::json::object();
  for (int H : {0, 1, 2, 4})
    for (int subset = 0; subset < 2; ++subset) {
      const lut::AbsErrorSummary s = lut::azimuth_error_summary(az, H, subset == 1);
      summary[fmt::format("harmonics_{}", H)][subset == 0 ? "all" : "outside_early_out"] = s;
    }

  // 4. Exact vs a high-sample Monte Carlo (PCG32, spherical-caps sampler) at a few fixed points.
  std::ostringstream val;
  val << "visibility,alpha_x,alpha_y,ndotl,ndotv,phi,exact,mc,mc_sigma,samples\n";
  if (a.mc_samples > 0)
    for (const lut::MonteCarloCheck& m : lut::monte_carlo_validation(a.mc_samples)) {
      for (double x : m.point) val << fmtd(x) << ',';
      val << fmtd(m.exact) << ',' << fmtd(m.mc) << ',' << fmtd(m.sigma) << ',' << a.mc_samples << '\n';
    }
  io::write_file_atomic(dir / "validation.csv", val.str());

  summary["size"] = n;
  summary["azimuth_configs"] = a.azimuth_configs;
  nlohmann::json jsum = {{"azimuth_error", summary},
                         {"files", {"maps.csv", "errors.csv", "azimuth_error.csv", "validation.csv"}}};
  io::write_file_atomic(dir / "summary.json", jsum.dump(2) + "\n");
  print_json(jsum);
}

// ---- methods ---------------------------------------------------------------------------------------------

struct MethodsArgs {
  bool json = false, study = false, names = false, uses_ndotl = false, bump = false;
};

// The registry as a table or JSON (what the demo and scripts/render_report.py read); --bump: the
// bump-terminator registry (occlusion/bump_terminator.h).
void run_methods(const MethodsArgs& a) {
  nlohmann::json list = nlohmann::json::array();
  std::string text;
  if (a.bump) {
    if (a.study || a.uses_ndotl) throw UsageError("--study and --uses-ndotl select micro-shadowing methods");
    for (const bump::MethodInfo& i : bump::kMethods) {
      list.push_back({{"name", i.name},
                      {"label", i.label},
                      {"summary", i.summary},
                      {"glsl", i.glsl},
                      {"requires", i.requires_fn}});
      text += a.names ? (text.empty() ? "" : ",") + std::string(i.name)
                      : fmt::format("{:<38} {}\n", i.name, i.label);
    }
  }
  for (const occlusion::MicroShadowingMethodInfo& i : occlusion::micro_shadowing_methods()) {
    if (a.bump || (a.study && !i.in_study) || (a.uses_ndotl && !i.uses_ndotl)) continue;
    list.push_back(nlohmann::json::parse(occlusion::micro_shadowing_method_json(i)));
    text += a.names ? (text.empty() ? "" : ",") + i.name
                    : fmt::format("{:<38} {}{}\n", i.name, i.label, i.in_study ? "  [study]" : "");
  }
  if (a.names) text += "\n";
  if (a.json)
    print_json(list);
  else
    fmt::print("{}", text);
}

void add_micro_shadowing(Groups& g) {
  {
    const auto [m, ma] = add_command<MethodsArgs>(
        g.root, "methods",
        "List the micro-shadowing methods (the one table that eval, render, study, the viewer and Python "
        "share): name, label, and [study] for the study's default set; a name D+S is a pair (D on the "
        "diffuse lobe, S on the specular lobe)",
        run_methods);
    add_json_flag(m, ma->json, "One JSON array: every field of each method");
    m->add_flag("--study", ma->study, "Only the methods the study renders by default");
    m->add_flag("--uses-ndotl", ma->uses_ndotl, "Only the methods that depend on N.L (not none, ao)");
    m->add_flag("--names", ma->names, "Only the names, comma-separated on one line (for --method lists)");
    m->add_flag(
        "--bump", ma->bump,
        "The bump-terminator methods instead (render --bump-terminator, eval bump-terminator --method)");
  }
  const auto [e, ea] =
      add_command<EvalArgs>(g.eval, "micro-shadowing",
                            "Micro-shadowing term at one point (docs/micro-shadowing.md). generic-vndf "
                            "without --phi: the mean over the relative azimuth phi in [0, pi] (what a LUT "
                            "stores); with --phi: the exact term at that azimuth. Without --samples the "
                            "generic term is the exact quadrature (error < 1e-6).",
                            run_eval);
  e->add_option("--method", ea->method, occlusion::micro_shadowing_method_names())->capture_default_str();
  e->add_option("--visibility", ea->visibility,
                "Micro-occlusion visibility V in [0, 1] (projected solid angle)")
      ->check(Finite)
      ->required();
  e->add_option("--roughness", ea->roughness,
                "Perceptual roughness r in [0, 1] (alpha = r^2); alpha_x if anisotropic")
      ->check(Finite)
      ->capture_default_str();
  ea->ry_opt =
      e->add_option("--roughness-y", ea->roughness_y, "Perceptual roughness along y (anisotropic GGX)")
          ->check(Finite);
  e->add_option("--ndotl", ea->ndotl, "N.L in [0, 1]")->check(Finite)->required();
  e->add_option("--ndotv", ea->ndotv, "N.V in [0, 1]")->check(Finite)->capture_default_str();
  ea->phi_opt =
      e->add_option("--phi", ea->phi, "Relative azimuth of l and v in [0, pi] (radians)")->check(Finite);
  ea->samples_opt =
      e->add_option("--samples", ea->samples,
                    "Estimate with N Owen-scrambled Sobol VNDF samples (the loop of Zurita 2026b)");
  e->add_option("--seed", ea->seed, "Scrambling seed of --samples")->capture_default_str();
  e->add_option("--g2", ea->g2, "height-correlated | uncorrelated (Smith G2/G1 weight)")
      ->capture_default_str();
  e->add_option(
      "--lut", ea->lut,
      "LUT file for lut3d / lut2d (from `bake micro-shadowing`; default: the default table, baked on first "
      "use; with --phi an azimuth-aware one)");
  ea->radius_opt = e->add_option("--light-radius-deg", ea->light_radius_deg,
                                 "Area light (docs/area-lights.md): angular radius in degrees [0, 90] of a "
                                 "sphere light centred on the N.L direction (at azimuth --phi, default 0); "
                                 "value = the term averaged over the light, 0 = the point value. disk: the "
                                 "edge's angular radius when facing; rect: the half-width's angle")
                       ->check(Finite);
  ea->shape_opt =
      e->add_option("--light-shape", ea->light_shape, "sphere | disk | rect")->capture_default_str();
  ea->tilt_opt = e->add_option("--light-tilt-deg", ea->light_tilt_deg,
                               "disk/rect: tilt of the light's plane from facing the point, degrees in (-90, "
                               "90) (about its w axis; > 0 turns the normal toward N)")
                     ->check(Finite);
  ea->roll_opt = e->add_option("--light-roll-deg", ea->light_roll_deg,
                               "disk/rect: rotation of the light's u axis about the centre direction, "
                               "degrees (0: u in the plane of N and the centre)")
                     ->check(Finite);
  ea->hh_opt = e->add_option("--light-half-height-deg", ea->light_half_height_deg,
                             "rect: angle of the half-height (along w), degrees in [0, 90); default: "
                             "--light-radius-deg (a square)")
                   ->check(Finite);
  ea->receiver_opt = e->add_option("--receiver", ea->receiver,
                                   "Weight over the light: lambert ((n.l)) or ggx (the GGX specular BRDF at "
                                   "--roughness and --ndotv, F = 1, times (n.l))")
                         ->capture_default_str();
  add_json_flag(e, ea->json);

  const auto [p, pa] = add_command<PlotArgs>(
      g.plot, "micro-shadowing",
      "Figure data for the micro-shadowing terms: maps.csv (every method over Visibility x N.L for roughness "
      "0, 0.1, 0.4, 0.7, 1 and N.V 1, 0.5, 0.1), errors.csv (older terms vs the exact generic term), "
      "azimuth_error.csv (exact term vs its azimuth mean at random configurations), validation.csv (exact vs "
      "Monte Carlo), summary.json. PNGs: scripts/plot_micro_shadowing.py.",
      run_plot);
  add_out_dir_option(p, pa->out);
  p->add_option("--size", pa->size, "Grid points per axis of the maps")->capture_default_str();
  p->add_option("--azimuth-configs", pa->azimuth_configs, "Random configurations of the azimuth study")
      ->capture_default_str();
  p->add_option("--mc-samples", pa->mc_samples, "Monte Carlo samples per validation point (0: skip)")
      ->capture_default_str();
}

}  // namespace

MSH_CLI_REGISTER(add_micro_shadowing, 30);

}  // namespace msh::cli
