// CLI for the linearly transformed cosines table (include/microshadow/bsdf/runtime/ltc_baker.h, docs/ltc.md):
//   microshadow bake ltc --out FILE [--size N] [--format dds|ktx2|exr|npy|h] [--pixel-format rgba32f|rgba16f]
//   microshadow verify ltc FILE [--points N] [--roughness-min R] [--sides N]
// bake writes FILE (M⁻¹ entries, RGBA), <stem>_amp<ext> (magnitude, fresnel; RG) and FILE.json atomically.
#include <fmt/format.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/io/texture.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "common.h"

namespace msh::cli {
namespace {

struct BakeLtcOptions {
  TableOutput out;
  std::string pixel_format = "rgba32f";
  int size = 64, error_samples = 32, iterations = 120, moment_samples = 4096, threads = 0;
  bool quiet = false;
};

void run_bake_ltc(const BakeLtcOptions& a) {
  namespace fs = std::filesystem;
  bsdf::LtcFitOptions o;
  o.size = a.size, o.error_samples = a.error_samples, o.max_iterations = a.iterations;
  o.moment_samples = a.moment_samples, o.threads = a.threads;
  bsdf::validate(o);
  const fs::path out(a.out.out);
  const io::FileFormat ff = table_output_format(a.out);
  io::PixelFormat pf4 = io::PixelFormat::RGBA32Float, pf2 = io::PixelFormat::RG32Float;
  if (a.pixel_format == "rgba16f")
    pf4 = io::PixelFormat::RGBA16Float, pf2 = io::PixelFormat::RG16Float;
  else if (a.pixel_format != "rgba32f")
    throw UsageError(fmt::format("--pixel-format must be rgba32f or rgba16f, got '{}'", a.pixel_format));
  o.progress = progress_in_tenths("fitting LTC table", a.quiet);
  const bsdf::LtcTable t = bsdf::fit_ltc_table(o);
  bsdf::write_ltc_table(out, t, ff, pf4, pf2);
  double max_err = 0, mean_err = 0;
  for (float e : t.fit_error)
    max_err = std::max(max_err, double(e)), mean_err += e / double(t.fit_error.size());
  nlohmann::json j;
  j["out"] = out.string();
  j["moments"] = bsdf::ltc_moments_path(out).string();
  j["sidecar"] = bsdf::ltc_sidecar_path(out).string();
  j["size"] = t.size;
  j["pixel_format"] = a.pixel_format;
  j["fit_seconds_wall"] = t.fit_seconds;
  j["fit_relative_l3_error_max"] = max_err;
  j["fit_relative_l3_error_mean"] = mean_err;
  print_json(j);
}

struct VerifyLtcOptions {
  std::string file;
  bsdf::LtcVerifyOptions v;
  int threads = 0;
};

nlohmann::json stats_json(const bsdf::LtcErrorStats& s) {
  return {{"rms_relative", s.rms_rel},
          {"max_relative", s.max_rel},
          {"relative_count", s.count_rel},
          {"rms_abs", s.rms_abs},
          {"max_abs", s.max_abs},
          {"rms_abs_255", s.rms_abs * 255},
          {"max_abs_255", s.max_abs * 255},
          {"count", s.count},
          {"worst",
           {{"roughness", s.worst_roughness},
            {"n_dot_v", s.worst_cos_v},
            {"sigma_deg", s.worst_sigma_deg},
            {"elevation_deg", s.worst_elevation_deg}}}};
}

void run_verify_ltc(const VerifyLtcOptions& a) {
  const auto& v = a.v;
  require_range(v.roughness_min, 0.0, 1.0, "--roughness-min");
  require_range(v.cos_min, 0.0, 1.0, "--cos-min");
  require_range(v.sigma_min_deg, 0.01, 80.0, "--sigma-min");
  require_range(v.sigma_max_deg, v.sigma_min_deg, 80.0, "--sigma-max");
  if (v.points < 1 || v.points > 1 << 20)
    throw UsageError(fmt::format("--points must be in [1, 2^20], got {}", v.points));
  if (v.polygon_sides < 3 || v.polygon_sides > 16)
    throw UsageError(fmt::format("--sides must be in [3, 16], got {}", v.polygon_sides));
  if (a.threads < 0) throw UsageError("--threads must be ≥ 0");
  const bsdf::LtcTable t = bsdf::load_ltc_table(a.file);
  const auto limit = thread_limit(a.threads);
  const bsdf::LtcVerifyReport r = bsdf::verify_ltc_table(t, v);
  nlohmann::json j;
  j["file"] = a.file;
  j["size"] = t.size;
  j["domain"] = {{"roughness", {v.roughness_min, 1.0}},
                 {"n_dot_v", {v.cos_min, 1.0}},
                 {"sigma_deg", {v.sigma_min_deg, v.sigma_max_deg}},
                 {"elevation_deg", {0, 90}},
                 {"points", v.points},
                 {"polygon_sides", v.polygon_sides},
                 {"surface_clip", v.clip_surface},
                 {"relative_where_reference_at_least_fraction_of_peak", v.rel_floor}};
  j["units"] = "value / light form factor at normal incidence (white Lambert facing the light = 1); F = 1";
  j["sphere_vs_ggx"] = stats_json(r.sphere);
  j["rect_vs_ggx"] = stats_json(r.rect);
  j["sphere_polygon_vs_ltc_cap"] = stats_json(r.sphere_polygon);
  j["diffuse_sphere_vs_lambert"] = stats_json(r.diffuse_sphere);
  j["reference_check_max_relative"] = r.reference_check;
  j["seconds"] = r.seconds;
  print_json(j);
}

void add_ltc(Groups& g) {
  const auto [c, b] = add_command<BakeLtcOptions>(
      g.bake, "ltc",
      "Fit the linearly transformed cosines table of GGX (height-correlated Smith; Heitz et al. 2016) over "
      "(roughness, sqrt(1 - N.V)): writes OUT (M^-1 entries a,b,c,d in RGBA), <stem>_amp<ext> (magnitude, "
      "fresnel in RG) and OUT.json. See docs/ltc.md.",
      run_bake_ltc);
  add_table_output(c, b->out);
  c->add_option("--size", b->size, "Texels per axis")->capture_default_str();
  c->add_option("--pixel-format", b->pixel_format, "rgba32f or rgba16f (dds/ktx2/exr; npy and h are float32)")
      ->capture_default_str();
  c->add_option("--error-samples", b->error_samples, "K: the L3 fit error uses 2 K^2 samples")
      ->capture_default_str();
  c->add_option("--iterations", b->iterations, "Nelder-Mead iterations per texel")->capture_default_str();
  c->add_option("--moment-samples", b->moment_samples, "QMC samples for magnitude, fresnel, mean direction")
      ->capture_default_str();
  add_threads_option(c, b->threads);
  add_quiet_flag(c, b->quiet);

  const auto [vc, v] =
      add_command<VerifyLtcOptions>(g.verify, "ltc",
                                    "As-used error of an LTC table (bilinear fetch off the grid): sphere and "
                                    "square lights of angular radius 1-40 deg at elevations 0-90 deg, LTC "
                                    "shading vs quadrature of GGX x cosine over the light. See docs/ltc.md.",
                                    run_verify_ltc);
  vc->add_option("file", v->file, "The table written by bake ltc (its _amp file beside it)")->required();
  vc->add_option("--points", v->v.points, "Sobol points (roughness, N.V, light size, elevation, azimuth)")
      ->capture_default_str();
  vc->add_option("--roughness-min", v->v.roughness_min, "Lowest roughness measured")->capture_default_str();
  vc->add_option("--cos-min", v->v.cos_min, "Lowest N.V measured")->capture_default_str();
  vc->add_option("--sigma-min", v->v.sigma_min_deg, "Smallest light angular radius (deg)")
      ->capture_default_str();
  vc->add_option("--sigma-max", v->v.sigma_max_deg, "Largest light angular radius (deg)")
      ->capture_default_str();
  vc->add_option("--sides", v->v.polygon_sides, "Sides of the sphere light's polygon")->capture_default_str();
  vc->add_flag(
      "--no-surface-clip", [v](int64_t) { v->v.clip_surface = false; },
      "Clip lights in the LTC's space only (Heitz et al. 2016), not also to the surface's horizon");
  add_threads_option(vc, v->threads);
}

}  // namespace

MSH_CLI_REGISTER(add_ltc, 45);

}  // namespace msh::cli
