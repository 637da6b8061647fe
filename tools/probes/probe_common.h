// Shared by the probes of tools/probes/ (docs/area-lights.md §5, "GGX receiver: the cap forms are not
// enough"): their command line, their input points and their output.
//
// A probe measures candidate fast forms for the reference step over a sphere light seen by a GGX receiver
// against the exact GGX-weighted quadrature (reference/micro_shadowing_area_exact.h, relative tolerance 1e-6)
// at the points [first, first + N) of verify area-lights' Sobol sequence (reference/runtime/
// area_lights_verify.h, default light radii 1°–40°) in the domain of its LTC block: N·V ≥ 0.05, roughness
// ≥ 0.1, the light centred on the N·L direction at azimuth 0, the view at azimuth φ_v. It prints, per form,
// the RMS and max of |form − exact| over the points in 1/255, as a table or as one JSON object. Points are
// computed in parallel (oneTBB) and summed in index order: the output does not depend on the thread count.
#pragma once

#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>
#include <microshadow/reference/runtime/area_lights_verify.h>
#include <tbb/parallel_for.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace msh::probes {

struct ProbeArgs {
  int points = 300;  // N
  int first = 0;     // the first Sobol index (points from 300 on were not used to choose parameters)
  bool json = false;
};

inline void add_probe_options(CLI::App& app, ProbeArgs& a) {
  app.add_option("--points", a.points, "Number of Sobol points N")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  app.add_option("--first", a.first, "First Sobol index: the points are [first, first + N)")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str();
  app.add_flag("--json", a.json, "Print one JSON object");
}

// Parses the command line (--help: the usage, exit 0; a bad argument: one line on stderr, exit 2), then runs
// `body`; an InputError from it (a bad table file) is one line on stderr, exit 2.
template <class Body>
int run_probe(CLI::App& app, int argc, char** argv, const Body& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << app.get_name() << ": error: " << e.what() << " (see --help)" << std::endl;
    return 2;
  }
  try {
    body();
  } catch (const InputError& e) {
    std::cerr << app.get_name() << ": error: " << e.what() << std::endl;
    return 2;
  } catch (const std::exception& e) {
    std::cerr << app.get_name() << ": failed: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}

// One point: the sphere light (cap), the GGX receiver and the exact reference step over the light.
struct GgxCapInput {
  double V, n_dot_l, rho, n_dot_v, roughness, alpha;
  Vec3d v;
  area::Cap cap;
  area::Receiver receiver;
  double exact_step;
};

inline GgxCapInput ggx_cap_input(uint32_t i) {
  const area::VerifyPoint p = area::verify_point(i, area::VerifyOptions{});
  GgxCapInput in;
  in.V = p.visibility, in.n_dot_l = p.n_dot_l, in.rho = p.rho;
  in.n_dot_v = std::max(0.05, p.n_dot_v), in.roughness = std::max(0.1, p.roughness);
  in.alpha = roughness_to_alpha(in.roughness);
  in.v = spherical_direction(in.n_dot_v, p.phi_v);
  in.cap = area::Cap{spherical_direction(in.n_dot_l, 0.0), in.rho};
  in.receiver = area::Receiver::ggx(in.alpha, in.v);
  in.exact_step =
      area::area_micro_shadowing_exact(in.cap, in.receiver, area::reference_step_term(in.V), {1e-6});
  return in;
}

// The error summary of one form over the points, in 1/255.
struct ProbeRow {
  std::string form;
  double rms_255, max_255;
};

// errors_at(input) returns the error of every form (in the order of `forms`) at one point.
template <class ErrorsAt>
std::vector<ProbeRow> probe_rows(const ProbeArgs& a, const std::vector<std::string>& forms,
                                 const ErrorsAt& errors_at) {
  std::vector<std::vector<double>> e(size_t(a.points));
  tbb::parallel_for(0, a.points,
                    [&](int i) { e[size_t(i)] = errors_at(ggx_cap_input(uint32_t(a.first + i))); });
  std::vector<ProbeRow> rows;
  for (size_t f = 0; f < forms.size(); ++f) {
    double ss = 0, mx = 0;
    for (const std::vector<double>& pe : e) ss += pe[f] * pe[f], mx = std::max(mx, std::abs(pe[f]));
    rows.push_back({forms[f], 255 * std::sqrt(ss / a.points), 255 * mx});
  }
  return rows;
}

// The table (one line per form), or one JSON object {first, points, rows: [{form, rms_255, max_255}], extra}.
inline void print_rows(const std::vector<ProbeRow>& rows, const ProbeArgs& a,
                       const nlohmann::json& extra = nlohmann::json::object()) {
  if (a.json) {
    nlohmann::json j = extra;
    j["first"] = a.first, j["points"] = a.points, j["rows"] = nlohmann::json::array();
    for (const ProbeRow& r : rows)
      j["rows"].push_back({{"form", r.form}, {"rms_255", r.rms_255}, {"max_255", r.max_255}});
    std::cout << j.dump() << std::endl;
    return;
  }
  fmt::print("points {}–{}, |error| in 1/255\n", a.first, a.first + a.points - 1);
  for (const ProbeRow& r : rows)
    fmt::print("{:<72} RMS {:6.2f}  max {:6.1f}\n", r.form, r.rms_255, r.max_255);
}

}  // namespace msh::probes
