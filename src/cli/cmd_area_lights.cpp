// `verify area-lights`: the area-light fast forms (occlusion/micro_shadowing_area.h) measured as used against
// the exact quadrature (reference/micro_shadowing_area_exact.h) at Sobol inputs over V ∈ [0, 1],
// N·L ∈ [0, 1] (the cap's centre), light radius ρ ∈ [1°, 40°] (docs/area-lights.md):
//
//   microshadow verify area-lights [--points N] [--generic-points M] [--shape-points K] [--ltc-points L]
//                                  [--ltc FILE] [--json]
//
// The analysis is reference/runtime/area_lights_verify.h; this file parses the options and prints its results
// as a table (|error| in 1/255: RMS, p99, max, by form name) or as one JSON object.
#include <fmt/format.h>
#include <microshadow/reference/runtime/area_lights_verify.h>

#include <map>
#include <memory>

#include "common.h"

namespace msh::cli {
namespace {

struct VerifyArgs {
  area::VerifyOptions options;
  bool json = false;
};

void run_verify(const VerifyArgs& a) {
  const area::VerifyResult r = area::verify_area_lights(a.options);
  if (a.json) {
    print_json(area::to_json(r));
    return;
  }
  // By name, as the JSON object orders them; the forms of an empty block are left out.
  std::map<std::string, area::ErrorSummary> forms;
  for (const area::NamedErrorSummary& f : area::named_errors(r))
    if (f.summary) forms.emplace(f.name, *f.summary);
  fmt::print("{:<58} {:>8} {:>9} {:>9} {:>9}\n", "form (|error| in 1/255)", "count", "rms", "p99", "max");
  for (const auto& [name, s] : forms)
    fmt::print("{:<58} {:>8} {:>9.4f} {:>9.4f} {:>9.4f}\n", name, s.count, s.rms_255, s.p99_255, s.max_255);
}

void add_area_lights(Groups& g) {
  auto a = std::make_shared<VerifyArgs>();
  area::VerifyOptions& o = a->options;
  CLI::App* c = g.verify->add_subcommand(
      "area-lights",
      "Area-light micro-shadowing fast forms (occlusion/micro_shadowing_area.h) against the exact "
      "quadrature at Sobol inputs (docs/area-lights.md): errors in 1/255.");
  c->add_option("--points", o.points, "Sobol points for the closed-form terms")->capture_default_str();
  c->add_option("--generic-points", o.generic_points, "Sobol points for the generic term (slow reference)")
      ->capture_default_str();
  c->add_option("--shape-points", o.shape_points, "Sobol points for the disk and rect lights")
      ->capture_default_str();
  c->add_option("--rho-min-deg", o.rho_min_deg, "Smallest light radius (degrees)")
      ->check(Finite)
      ->capture_default_str();
  c->add_option("--rho-max-deg", o.rho_max_deg, "Largest light radius (degrees)")
      ->check(Finite)
      ->capture_default_str();
  c->add_option("--ltc-points", o.ltc_points,
                "Sobol points for the cone-clipped LTC forms (bsdf/ltc_shading.h), 0 = skip")
      ->capture_default_str();
  c->add_option("--aware-points", o.aware_points,
                "Sobol points for the generic and specular-aware terms over a sphere light, GGX receiver "
                "(exact full-direction reference: 0.1 s to minutes of CPU each)")
      ->capture_default_str();
  c->add_option("--diffuse-aware-points", o.diffuse_aware_points,
                "Sobol points for the diffuse-aware ALU fit over a sphere light, Lambertian receiver (exact "
                "reference: 8 s to minutes of CPU each)")
      ->capture_default_str();
  c->add_option("--ltc", o.ltc, "LTC table (bake ltc); default: fit a 16x16 table here (about 9 s CPU)");
  add_json_flag(c, a->json);
  c->callback([a] { run_verify(*a); });
}

}  // namespace

MSH_CLI_REGISTER(add_area_lights, 75);

}  // namespace msh::cli
