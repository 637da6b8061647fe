// `plot micro-shadowing-fit`: the exact azimuth-mean generic VNDF term (generic_vndf_exact_azimuth_mean) at
// stratified continuous random inputs, with the ALU-only approximation (micro_shadowing_fit.h) and the older
// closed-form terms beside it; the training and validation data of tools/research/fit_micro_shadowing.py and
// the measured error table of docs/micro-shadowing.md ("ALU-only approximation").
//
//   microshadow plot micro-shadowing-fit --out FILE.csv [--samples N] [--seed S] [--near-step M]
//       [--skip-early-out] [--term generic|diffuse-aware] [--rel-tol T]
// --term diffuse-aware: the exact azimuth-mean diffuse micro-BRDF-aware term (reciprocal form,
// diffuse_aware_exact_azimuth_mean, docs/micro-shadowing-aware.md) in place of the generic one, with its ALU
// approximation (micro_shadowing_aware_fit.h) beside it; data of tools/research/fit_micro_shadowing_aware.py.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_aware_exact.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <memory>
#include <numeric>
#include <sstream>
#include <vector>

#include "common.h"

namespace msh::cli {
namespace {

struct FitDataArgs {
  std::string out;
  int samples = 10000, near_step = 0;
  uint32_t seed = 1;
  bool skip_early_out = false;
  std::string term = "generic";
  double rel_tol = 1e-4;  // the diffuse-aware quadrature's (the generic term's exact mean has its own)
};

struct Input {
  double vis, nl, nv, r;
};

// Domain of the fit: V ∈ [0,1], N·L ∈ (0,1], N·V ∈ (0,1], r ∈ [0.1, 1].
constexpr double kRoughMin = 0.1;

// n points stratified per dimension (Latin hypercube: each coordinate takes one uniform point in each of n
// equal strata, strata shuffled independently), uniform over the domain. N·L and N·V are 1 − u (in (0, 1]).
std::vector<Input> latin_hypercube(int n, Pcg32& rng) {
  std::array<std::vector<double>, 4> cols;
  for (auto& col : cols) {
    col.resize(size_t(n));
    for (int i = 0; i < n; ++i) col[size_t(i)] = (i + rng.next_double()) / n;
    for (int i = n - 1; i > 0; --i) std::swap(col[size_t(i)], col[rng.next_u32() % uint32_t(i + 1)]);
  }
  std::vector<Input> pts(static_cast<size_t>(n));
  for (size_t i = 0; i < pts.size(); ++i)
    pts[i] = {cols[0][i], 1 - cols[1][i], 1 - cols[2][i], kRoughMin + (1 - kRoughMin) * cols[3][i]};
  return pts;
}

// Extra points around the low-roughness near-step N·L ≈ cos θc (r ∈ [0.1, 0.5]): N·L = cos θc + α sin θc · t
// with t standard Cauchy (the shape of the step's slope distribution), kept inside the domain.
std::vector<Input> near_step_points(int m, Pcg32& rng) {
  std::vector<Input> pts;
  while (int(pts.size()) < m) {
    const double vis = rng.next_double(), nv = 1 - rng.next_double(), r = 0.1 + 0.4 * rng.next_double();
    const double t = std::tan(kPi<double> * (rng.next_double() - 0.5));
    const double nl = std::sqrt(1 - vis) + r * r * std::sqrt(vis) * t;
    if (!(nl > 0 && nl <= 1) || micro_shadowing::exact_zero(vis, nl)) continue;
    pts.push_back({vis, nl, nv, r});
  }
  return pts;
}

void run_fit_data(const FitDataArgs& a) {
  require_parent_dir(a.out, "--out");  // before the minutes of work
  if (a.samples < 1 || a.samples > 10000000) throw UsageError("--samples must be in [1, 1e7]");
  if (a.near_step < 0 || a.near_step > 10000000) throw UsageError("--near-step must be in [0, 1e7]");
  if (a.term != "generic" && a.term != "diffuse-aware")
    throw UsageError(fmt::format("--term must be generic or diffuse-aware; got '{}'", a.term));
  if (!(a.rel_tol >= 1e-9 && a.rel_tol <= 1e-2)) throw UsageError("--rel-tol must be in [1e-9, 1e-2]");
  const bool generic = a.term == "generic";
  const auto form = micro_shadowing::DiffuseAwareForm::Reciprocal;
  // Where the term is exactly 0 without evaluating anything (the diffuse-aware term: for l and for v).
  const auto early_out = [&](const Input& p) {
    return micro_shadowing::exact_zero(p.vis, p.nl) || (!generic && micro_shadowing::exact_zero(p.vis, p.nv));
  };
  Pcg32 rng(a.seed, 0x5eed0a1u);
  std::vector<Input> pts = latin_hypercube(a.samples, rng);
  if (a.skip_early_out) pts.erase(std::remove_if(pts.begin(), pts.end(), early_out), pts.end());
  const std::vector<Input> extra = near_step_points(a.near_step, rng);
  pts.insert(pts.end(), extra.begin(), extra.end());

  // Independent points: oneTBB over them is deterministic (each value depends on its inputs only).
  std::vector<double> exact(pts.size());
  tbb::parallel_for(size_t(0), pts.size(), [&](size_t i) {
    const Input& p = pts[i];
    exact[i] = generic ? micro_shadowing::generic_vndf_exact_azimuth_mean(p.vis, p.r * p.r, p.nl, p.nv)
                       : micro_shadowing::diffuse_aware_exact_azimuth_mean(p.vis, p.r * p.r, p.nl, p.nv, form,
                                                                           a.rel_tol);
  });

  // Errors of the ALU terms (float, the shader precision) and the older terms, overall and per roughness
  // band. The columns are registry ids (occlusion/runtime/micro_shadowing_methods.h): the term's ALU fit
  // (generic-vndf-alu or diffuse-aware-alu, through the registry's evaluation), the generic fit's two-stage
  // form (generic-vndf-alu-two-stage), and the registry's closed forms of (V, N.L) that depend on N.L (the
  // reference step only beside the diffuse-aware term), in double as the registry's closed_form.
  const occlusion::MicroShadowingEvaluator fit(generic ? "generic-vndf-alu" : "diffuse-aware-alu");
  std::vector<std::string> names = {fit.info().name, two_stage_fit_id()};
  std::vector<double (*)(double, double)> closed;
  for (const std::string& n :
       generic ? occlusion::micro_shadowing_closed_form_terms() : std::vector<std::string>{"reference"}) {
    names.push_back(n);
    closed.push_back(occlusion::find_micro_shadowing_method(n)->closed_form);
  }
  const std::array<double, 4> bands = {0.1, 0.25, 0.55, 1.0 + 1e-12};
  std::vector<std::array<std::vector<double>, 4>> err(names.size());  // [method][band 0..2, all]
  std::ostringstream csv;
  csv << "visibility,ndotl,ndotv,roughness,early_out,exact";
  for (const auto& n : names) csv << "," << n;
  csv << "\n";
  for (size_t i = 0; i < pts.size(); ++i) {
    const Input& p = pts[i];
    std::vector<double> vals = {fit.eval({p.vis, p.nl, p.nv, p.r, std::nullopt, std::nullopt}),
                                double(micro_shadowing::generic_vndf_alu_two_stage(float(p.vis), float(p.nl),
                                                                                   float(p.nv), float(p.r)))};
    for (const auto f : closed) vals.push_back(f(p.vis, p.nl));
    csv << fmt::format("{:.9g},{:.9g},{:.9g},{:.9g},{},{:.9g}", p.vis, p.nl, p.nv, p.r, early_out(p) ? 1 : 0,
                       exact[i]);
    int band = 0;
    while (band < 2 && p.r >= bands[size_t(band) + 1]) ++band;
    for (size_t m = 0; m < names.size(); ++m) {
      csv << fmt::format(",{:.9g}", vals[m]);
      const double e = std::abs(vals[m] - exact[i]);
      err[m][size_t(band)].push_back(e);
      err[m][3].push_back(e);
    }
    csv << "\n";
  }
  io::write_file_atomic(a.out, csv.str());

  auto stats = [](std::vector<double> e) {
    std::sort(e.begin(), e.end());
    if (e.empty()) return nlohmann::json(nullptr);
    const double ss = std::accumulate(e.begin(), e.end(), 0.0, [](double s, double x) { return s + x * x; });
    const size_t k99 = std::min(e.size() - 1, size_t(std::ceil(0.99 * double(e.size()))) - 1);
    return nlohmann::json{{"n", e.size()},
                          {"rms_255", 255 * std::sqrt(ss / double(e.size()))},
                          {"p99_255", 255 * e[k99]},
                          {"max_255", 255 * e.back()}};
  };
  nlohmann::json methods;
  const char* band_names[] = {"[0.10,0.25)", "[0.25,0.55)", "[0.55,1.00]", "all"};
  for (size_t m = 0; m < names.size(); ++m)
    for (size_t b = 0; b < 4; ++b) methods[names[m]][band_names[b]] = stats(err[m][b]);
  print_json({{"file", a.out},
              {"points", pts.size()},
              {"seed", a.seed},
              {"near_step", a.near_step},
              {"skip_early_out", a.skip_early_out},
              {"term", a.term},
              {"domain", "V in [0,1], N.L in (0,1], N.V in (0,1], roughness in [0.1,1] (Latin hypercube)"},
              {"errors_vs_exact_azimuth_mean", methods}});
}

void add_micro_shadowing_fit(Groups& g) {
  const auto [p, a] = add_command<FitDataArgs>(
      g.plot, "micro-shadowing-fit",
      "The exact azimuth-mean micro-shadowing term at stratified random inputs (V, N.L, N.V, roughness in "
      "[0.1, 1]) with the ALU-only approximation and the older terms beside it: CSV for "
      "tools/research/fit_micro_shadowing.py and an error summary (RMS, p99, max in 1/255 per roughness "
      "band) on stdout (docs/micro-shadowing.md).",
      run_fit_data);
  p->add_option("--out", a->out, "Output CSV (written atomically)")->required();
  p->add_option("--samples", a->samples, "Stratified random points over the domain")->capture_default_str();
  p->add_option("--seed", a->seed, "Random seed (training and validation sets use different seeds)")
      ->capture_default_str();
  p->add_option("--near-step", a->near_step,
                "Extra points near the low-roughness step N.L = cos(theta_c) (training only)")
      ->capture_default_str();
  p->add_flag("--skip-early-out", a->skip_early_out,
              "Drop the stratified points inside the early-out region 2V + N.L < 1 (exact there)");
  p->add_option(
       "--term", a->term,
       "generic (generic_vndf_exact_azimuth_mean) | diffuse-aware (diffuse_aware_exact_azimuth_mean, "
       "reciprocal form, docs/micro-shadowing-aware.md)")
      ->capture_default_str();
  p->add_option("--rel-tol", a->rel_tol, "Relative tolerance of the diffuse-aware quadrature")
      ->capture_default_str();
}

}  // namespace

MSH_CLI_REGISTER(add_micro_shadowing_fit, 31);

}  // namespace msh::cli
