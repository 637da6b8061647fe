// CLI for the bump-terminator terms (include/microshadow/occlusion/bump_terminator.h):
//   microshadow eval bump-terminator --method conty-2019|chiang-2019|none --geometric-normal X,Y,Z
//       --shading-normal X,Y,Z --light X,Y,Z [--hemisphere-test] [--json]
//   microshadow plot bump-terminator --out DIR     (CSV figure data; scripts/plot_bump_terminator.py draws
//   it)
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/occlusion/bump_terminator.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "common.h"

namespace msh::cli {
namespace {

constexpr double kDeg = kPi<double> / 180.0;

// Parses a direction: three finite numbers, not all zero; returned normalized (scaled first, so 1e-200 or
// 1e200 components are fine).
Vec3d parse_direction(const std::string& text, const std::string& what) {
  const Vec3d v = parse_vec3(text, what);
  const double m = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (!(m > 0)) throw UsageError(fmt::format("{} must be a non-zero vector, got '{}'", what, text));
  return normalize(v / m);
}

double angle_deg(const Vec3d& a, const Vec3d& b) { return std::atan2(length(cross(a, b)), dot(a, b)) / kDeg; }

struct EvalOptions {
  std::string method = "conty-2019";
  std::string ng = "0,0,1", ns, light;
  bool hemisphere_test = false;
  bool json = false;
};

void run_eval(const EvalOptions& o) {
  bump::Method m{};
  if (!bump::parse_method(o.method, m)) throw UsageError(fmt::format("unknown --method '{}'", o.method));
  const Vec3d ng = parse_direction(o.ng, "--geometric-normal");
  const Vec3d ns = parse_direction(o.ns, "--shading-normal");
  const Vec3d l = parse_direction(o.light, "--light");
  const auto test = o.hemisphere_test ? bump::HemisphereTest::kOn : bump::HemisphereTest::kOff;
  const double value = bump::term(m, ng, ns, l, test);

  nlohmann::json j;
  j["value"] = value;
  j["method"] = std::string(bump::method_name(m));
  j["hemisphere_test"] = o.hemisphere_test;
  j["geometric_normal"] = {ng.x, ng.y, ng.z};
  j["shading_normal"] = {ns.x, ns.y, ns.z};
  j["light"] = {l.x, l.y, l.z};
  j["perturbation_deg"] = angle_deg(ng, ns);  // θ_d = angle(N_g, N_s)
  j["light_angle_deg"] = angle_deg(ng, l);    // θ_i = angle(N_g, L)
  j["geometric_cos"] = dot(ng, l);            // N_g·L
  j["shading_cos"] = dot(ns, l);              // N_s·L
  if (m == bump::Method::kConty2019) {
    const double a2 = bump::alpha2_from_normals(ng, ns);
    j["alpha2"] = a2;
    j["alpha"] = std::sqrt(a2);
    j["ggx_variance"] = bump::ggx_variance(std::sqrt(a2));
  } else if (m == bump::Method::kChiang2019) {
    const double den = dot(ns, l) * dot(ng, ns);
    if (den != 0)
      j["g"] = dot(ng, l) / den;
    else
      j["g"] = nullptr;  // ±∞ or 0/0: the term is 1 (see bump_terminator.h)
  }
  if (o.json) {
    print_json(j);
    return;
  }
  std::cout << fmt::format("{} = {:.9g}\n", bump::method_name(m), value);
  for (const char* k : {"perturbation_deg", "light_angle_deg", "geometric_cos", "shading_cos", "alpha2", "g"})
    if (j.contains(k)) std::cout << fmt::format("  {} = {}\n", k, j[k].dump());
}

// ---------------------------------------------------------------------------------------------------------
// plot bump-terminator: figure data in the spirit of figure 12.4 of Conty Estevez et al. 2019 (Ray Tracing
// Gems ch. 12).

struct PlotOptions {
  std::string out;
};

void run_plot(const PlotOptions& o) {
  namespace fs = std::filesystem;
  const fs::path dir = make_out_dir(o.out);

  const Vec3d ng(0, 0, 1);
  auto tilted = [](double deg, double phi_deg) {
    return spherical_direction(std::cos(deg * kDeg), phi_deg * kDeg);
  };
  auto light = [&](double theta_deg) { return tilted(theta_deg, 0.0); };  // light in the x–z plane

  // (1) The terms against the light angle θ_i (angle to N_g), for several perturbations θ_d. The light sits
  // at azimuth 0; N_s is tilted by θ_d at azimuth φ (0 = toward the light, 180 = away). Conty depends on θ_d
  // only.
  std::string curves = "method,perturbation_deg,phi_deg,light_deg,value\n";
  const std::vector<double> deltas = {1, 5, 10, 20, 30, 45, 60, 75};
  for (bump::Method m : {bump::Method::kConty2019, bump::Method::kChiang2019})
    for (double d : deltas)
      for (double phi : {0.0, 90.0, 180.0}) {
        if (m == bump::Method::kConty2019 && phi != 0.0) continue;
        for (int k = 0; k <= 900; ++k) {
          const double th = k * 0.1;
          const double v = bump::term(m, ng, tilted(d, phi), light(th));
          curves += fmt::format("{},{},{},{:.1f},{:.9g}\n", bump::method_name(m), d, phi, th, v);
        }
      }

  // (2) What the fix does to a Lambert-shaded surface across the geometric terminator: N_s tilted by θ_d
  // toward the light; the geometric shadow (a shadow ray / shadow map) removes the light once θ_i > 90°.
  // shaded = [θ_i < 90°] · max(0, N_s·L) · term.
  std::string shading = "perturbation_deg,light_deg,none,conty-2019,chiang-2019\n";
  for (double d : {10.0, 30.0})
    for (int k = 0; k <= 1100; ++k) {
      const double th = k * 0.1;
      const Vec3d l = light(th), ns = tilted(d, 0.0);
      const double lit = th < 90.0 ? std::max(0.0, dot(ns, l)) : 0.0;
      shading += fmt::format("{},{:.1f},{:.9g},{:.9g},{:.9g}\n", d, th, lit, lit * bump::conty2019(ng, ns, l),
                             lit * bump::chiang2019(ng, ns, l));
    }

  // (3) Where the two methods differ most: a grid over θ_d, θ_i, φ (light above both hemispheres).
  struct Worst {
    double diff = -1, d = 0, th = 0, phi = 0, conty = 0, chiang = 0;
  };
  Worst worst, worst_phi[3];  // overall; and for N_s tilted toward (φ = 0), sideways (90), away (180)
  double sum = 0;
  long n = 0;
  std::string grid = "perturbation_deg,phi_deg,light_deg,conty-2019,chiang-2019\n";
  for (int id = 1; id <= 80; ++id)
    for (int ip = 0; ip <= 36; ++ip)
      for (int it = 0; it < 90; ++it) {
        const double d = id, phi = ip * 5.0, th = it + 0.5;
        const Vec3d ns = tilted(d, phi), l = light(th);
        if (!(dot(ns, l) > 0)) continue;
        const double a = bump::conty2019(ng, ns, l), b = bump::chiang2019(ng, ns, l), diff = std::abs(a - b);
        sum += diff, ++n;
        if (diff > worst.diff) worst = {diff, d, th, phi, a, b};
        if (ip % 18 == 0 && diff > worst_phi[ip / 18].diff) worst_phi[ip / 18] = {diff, d, th, phi, a, b};
        if (id % 10 == 0 && ip % 9 == 0) grid += fmt::format("{},{},{},{:.9g},{:.9g}\n", d, phi, th, a, b);
      }
  auto at = [](const Worst& w) {
    return nlohmann::json{
        {"max_abs_difference", w.diff}, {"perturbation_deg", w.d}, {"phi_deg", w.phi}, {"light_deg", w.th},
        {"conty-2019", w.conty},        {"chiang-2019", w.chiang}};
  };
  nlohmann::json summary;
  summary["grid"] = "perturbation 1..80 deg step 1, azimuth 0..180 step 5, light 0.5..89.5 step 1, N_s.L > 0";
  summary["points"] = n;
  summary["mean_abs_difference"] = sum / double(n);
  summary["worst"] = at(worst);
  summary["worst_tilt_toward_light"] = at(worst_phi[0]);
  summary["worst_tilt_sideways"] = at(worst_phi[1]);
  summary["worst_tilt_away"] = at(worst_phi[2]);

  io::write_file_atomic(dir / "bump_terminator_curves.csv", curves);
  io::write_file_atomic(dir / "bump_terminator_shading.csv", shading);
  io::write_file_atomic(dir / "bump_terminator_compare.csv", grid);
  io::write_file_atomic(dir / "bump_terminator_compare.json", summary.dump(2) + "\n");
  print_json({{"out", dir.string()},
              {"files",
               {"bump_terminator_curves.csv", "bump_terminator_shading.csv", "bump_terminator_compare.csv",
                "bump_terminator_compare.json"}},
              {"compare", summary}});
}

void add_bump(Groups& g) {
  const auto [e, eo] = add_command<EvalOptions>(
      g.eval, "bump-terminator",
      "Bump-terminator shadowing factor for one light (Conty Estevez et al. 2019 or Chiang et al. 2019). "
      "Vectors need not be normalized; a zero or non-finite vector is an error.",
      run_eval);
  // The choices and their help from the registry (occlusion/bump_terminator.h).
  std::vector<std::string> names;
  std::string help;
  for (const bump::MethodInfo& i : bump::kMethods) {
    names.emplace_back(i.name);
    help += fmt::format("{}{} ({})", help.empty() ? "" : "; ", i.name, i.summary);
  }
  e->add_option("--method", eo->method, help)->check(CLI::IsMember(names))->capture_default_str();
  e->add_option("--geometric-normal", eo->ng, "Geometric (unperturbed) normal N_g, X,Y,Z")
      ->capture_default_str();
  e->add_option("--shading-normal", eo->ns, "Shading (bumped) normal N_s, X,Y,Z")->required();
  e->add_option("--light", eo->light, "Direction to the light L, X,Y,Z (pointing away from the surface)")
      ->required();
  e->add_flag("--hemisphere-test", eo->hemisphere_test,
              "Return 0 unless N_g.L > 0 and N_s.L > 0 (light above both hemispheres). Off by default: the "
              "published terms use |cos| and are symmetric in the sign of each vector");
  add_json_flag(e, eo->json, "Print one JSON object (value, angles, alpha2 or g)");

  const auto [p, po] = add_command<PlotOptions>(
      g.plot, "bump-terminator",
      "Write the bump-terminator figure data (CSV, like Ray Tracing Gems fig. 12.4) and a Conty-vs-Chiang "
      "comparison (JSON) into DIR; scripts/plot_bump_terminator.py draws the PNG",
      run_plot);
  add_out_dir_option(p, po->out);
}

}  // namespace

MSH_CLI_REGISTER(add_bump, 50);

}  // namespace msh::cli
