// CLI for the micro-BRDF-aware terms (docs/micro-shadowing-aware.md):
//   microshadow verify micro-shadowing-aware --method NAME|all [--samples N] [--seed S]
//       [--estimator-samples K] [--rel-tol T] [--threads T] [--json]
//     as-used error of the run-time forms (float) against their exact references at continuous inputs,
//     through the verify method of lut/runtime/micro_shadowing_verify.h (docs/lut.md, Verify); the -alu
//     methods: the diffuse-aware ALU fit (occlusion/micro_shadowing_aware_fit.h);
//   microshadow plot micro-shadowing-aware --out DIR [--size N] [--threads T]
//     maps.csv: generic, specular-aware and diffuse-aware azimuth means over (V, N·L) per roughness and N·V
//     (figures: scripts/plot_micro_shadowing_aware.py).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/lut/runtime/micro_shadowing_verify.h>
#include <microshadow/microfacet/roughness.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/reference/micro_shadowing_aware_exact.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <array>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common.h"

namespace msh::cli {
namespace {

// What is measured: registry ids (specular-aware-alu: the specular mean's closed form in float;
// specular-aware: the same in double, as the registry's specular-aware evaluates it without φ; diffuse-aware,
// diffuse-aware-flux: the estimator at φ; diffuse-aware-alu: the fit against the azimuth mean it
// approximates), and two comparisons named here only: diffuse-aware-alu-at-phi (the fit against the term at
// φ) and generic-vndf-vs-diffuse-aware (the generic term's exact value as an approximation of the
// diffuse-aware term).
const std::vector<std::string> kAwareMethods = {"specular-aware-alu",
                                                "specular-aware",
                                                "diffuse-aware",
                                                "diffuse-aware-flux",
                                                "generic-vndf-vs-diffuse-aware",
                                                "diffuse-aware-alu",
                                                "diffuse-aware-alu-at-phi"};

struct VerifyArgs {
  std::string method = "all";
  int samples = 2000, threads = 0, estimator_samples = 64;
  double rel_tol = 1e-4;  // of the diffuse-aware azimuth mean's quadrature (the ALU fits' reference)
  uint32_t seed = 1;
  bool json = false;
};

Vec3d view_dir(double nv) { return Vec3d(safe_sqrt(1 - nv * nv), 0, nv); }
Vec3d light_dir(double nl, double cos_phi) {
  const double sl = safe_sqrt(1 - nl * nl), c = std::clamp(cos_phi, -1.0, 1.0);
  return Vec3d(sl * c, sl * safe_sqrt(1 - c * c), nl);
}

nlohmann::json stats_json(const lut::ErrorStats& s) {
  return {{"count", s.count},           {"rms_255", s.rms * 255},   {"p99_255", s.p99 * 255},
          {"max_255", s.max_abs * 255}, {"mean_255", s.mean * 255}, {"nonfinite", s.nonfinite}};
}

void run_verify(const VerifyArgs& a) {
  std::vector<std::string> methods;
  for (const auto& m : kAwareMethods)
    if (a.method == "all" || a.method == m) methods.push_back(m);
  if (methods.empty())
    throw UsageError(fmt::format("--method must be all or one of: {}; got '{}'",
                                 fmt::join(kAwareMethods, ", "), a.method));
  nlohmann::json out = nlohmann::json::object();
  for (const std::string& m : methods) {
    lut::VerifyOptions o;
    o.samples = a.samples, o.seed = a.seed, o.threads = a.threads;
    lut::MicroShadowingApprox f;
    const int n = a.estimator_samples;
    if (m == "specular-aware-alu" || m == "specular-aware") {
      o.against = lut::VerifyReference::AzimuthMean;
      o.reference = [](double V, double nl, double nv, double r, double) {
        return micro_shadowing::specular_aware_azimuth_mean_quadrature(V, roughness_to_alpha(r), nl, nv);
      };
      if (m == "specular-aware-alu")
        f = [](float V, float nl, float nv, float r, float) {
          return micro_shadowing::specular_aware_azimuth_mean<float>(V, r * r, nl, nv);
        };
      else
        f = [](float V, float nl, float nv, float r, float) {
          return float(micro_shadowing::specular_aware_azimuth_mean<double>(V, double(r) * r, nl, nv));
        };
    } else if (m == "diffuse-aware-alu" || m == "diffuse-aware-alu-at-phi") {
      // The ALU fit (float, as the shaders run it) against the lobe-weighted azimuth mean it approximates,
      // or (-at-phi) against the term at the input's azimuth, which a renderer at full vectors would want.
      const micro_shadowing::DiffuseAwareForm form = micro_shadowing::DiffuseAwareForm::Reciprocal;
      const double tol = a.rel_tol;
      if (m == "diffuse-aware-alu-at-phi") {
        o.against = lut::VerifyReference::Azimuth;
        o.reference = [form](double V, double nl, double nv, double r, double cp) {
          const double al = roughness_to_alpha(r);
          return micro_shadowing::diffuse_aware_exact(V, al, al, view_dir(nv), light_dir(nl, cp), form);
        };
      } else {
        o.against = lut::VerifyReference::AzimuthMean;
        o.reference = [form, tol](double V, double nl, double nv, double r, double) {
          return micro_shadowing::diffuse_aware_exact_azimuth_mean(V, roughness_to_alpha(r), nl, nv, form,
                                                                   tol);
        };
      }
      f = [](float V, float nl, float nv, float r, float) {
        return micro_shadowing::diffuse_aware_alu(V, nl, nv, r);
      };
    } else {
      const micro_shadowing::DiffuseAwareForm form = m == "diffuse-aware-flux"
                                                         ? micro_shadowing::DiffuseAwareForm::Flux
                                                         : micro_shadowing::DiffuseAwareForm::Reciprocal;
      o.against = lut::VerifyReference::Azimuth;
      o.reference = [form](double V, double nl, double nv, double r, double cp) {
        const double al = roughness_to_alpha(r);
        return micro_shadowing::diffuse_aware_exact(V, al, al, view_dir(nv), light_dir(nl, cp), form);
      };
      if (m == "generic-vndf-vs-diffuse-aware")
        f = [](float V, float nl, float nv, float r, float cp) {
          const double al = roughness_to_alpha(double(r));
          return float(micro_shadowing::generic_vndf_exact(V, al, al, view_dir(nv), light_dir(nl, cp)));
        };
      else
        f = [form, n](float V, float nl, float nv, float r, float cp) {
          const GGX<float> g(roughness_to_alpha(std::max(r, 0.02f)));
          return micro_shadowing::diffuse_aware_estimate<float>(V, g, Vec3f(view_dir(nv)),
                                                                Vec3f(light_dir(nl, cp)), n, form, 1u);
        };
    }
    const lut::VerifyResult r = lut::verify_micro_shadowing(f, o);
    nlohmann::json j{{"all", stats_json(r.all)},
                     {"rest", stats_json(r.rest)},
                     {"against", lut::verify_reference_name(o.against)}};
    nlohmann::json bands = nlohmann::json::array();
    for (const auto& b : r.by_roughness) {
      nlohmann::json x = stats_json(b.stats);
      x["lo"] = b.lo, x["hi"] = b.hi;
      bands.push_back(x);
    }
    j["by_roughness"] = bands;
    if (!r.worst.empty()) {
      const auto& w = r.worst.front();
      j["worst"] = {{"visibility", w.input.visibility},
                    {"n_dot_l", w.input.n_dot_l},
                    {"n_dot_v", w.input.n_dot_v},
                    {"roughness", w.input.roughness},
                    {"cos_phi", w.input.cos_phi},
                    {"exact", w.input.exact},
                    {"approx", w.approx}};
    }
    out[m] = j;
    if (!a.json)
      std::cout << fmt::format(
          "{:32s} against {:8s} RMS {:.3f}/255  p99 {:.3f}/255  max {:.3f}/255  ({} inputs)\n", m,
          lut::verify_reference_name(o.against), r.all.rms * 255, r.all.p99 * 255, r.all.max_abs * 255,
          r.all.count);
  }
  out["samples"] = a.samples, out["seed"] = a.seed, out["estimator_samples"] = a.estimator_samples;
  out["rel_tol"] = a.rel_tol;
  if (a.json) print_json(out);
}

struct PlotArgs {
  std::string out;
  int size = 17, threads = 0;
};

void run_plot(const PlotArgs& a) {
  if (a.out.empty()) throw UsageError("--out is required");
  if (a.size < 2 || a.size > 129) throw UsageError(fmt::format("--size must be in [2, 129], got {}", a.size));
  const std::vector<double> rough = {0.1, 0.4, 0.7, 1.0}, nvs = {1.0, 0.5, 0.1};
  struct Cell {
    double r, nv, V, nl;
  };
  std::vector<Cell> cells;
  for (double r : rough)
    for (double nv : nvs)
      for (int i = 0; i < a.size; ++i)
        for (int j = 0; j < a.size; ++j)
          cells.push_back({r, nv, double(i) / (a.size - 1), double(j) / (a.size - 1)});
  std::vector<std::array<double, 4>> val(cells.size());
  tbb::task_arena arena(a.threads > 0 ? a.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), cells.size(), [&](std::size_t k) {
      const Cell& c = cells[k];
      const double al = roughness_to_alpha(c.r);
      val[k] = {micro_shadowing::generic_vndf_exact_azimuth_mean(c.V, al, c.nl, c.nv),
                micro_shadowing::specular_aware_azimuth_mean<double>(c.V, al, c.nl, c.nv),
                micro_shadowing::diffuse_aware_exact_azimuth_mean(
                    c.V, al, c.nl, c.nv, micro_shadowing::DiffuseAwareForm::Reciprocal, 1e-4),
                micro_shadowing::diffuse_aware_exact_azimuth_mean(
                    c.V, al, c.nl, c.nv, micro_shadowing::DiffuseAwareForm::Flux, 1e-4)};
    });
  });
  std::ostringstream s;
  // The columns by registry id (each the method's value without the azimuth: its azimuth mean).
  s << "roughness,n_dot_v,visibility,n_dot_l,generic-vndf,specular-aware,diffuse-aware,diffuse-aware-flux\n";
  for (std::size_t k = 0; k < cells.size(); ++k)
    s << fmt::format("{},{},{:.6f},{:.6f},{:.7f},{:.7f},{:.7f},{:.7f}\n", cells[k].r, cells[k].nv, cells[k].V,
                     cells[k].nl, val[k][0], val[k][1], val[k][2], val[k][3]);
  const std::filesystem::path dir = make_out_dir(a.out);
  io::write_file_atomic(dir / "maps.csv", s.str());
  std::cout << fmt::format("wrote {} ({} cells)\n", (dir / "maps.csv").string(), cells.size());
}

void add_aware(Groups& g) {
  const auto [v, va] = add_command<VerifyArgs>(
      g.verify, "micro-shadowing-aware",
      "As-used error of the micro-BRDF-aware run-time forms (float) against their exact references at "
      "continuous Sobol inputs (docs/micro-shadowing-aware.md)",
      run_verify);
  v->add_option("--method", va->method, "all | " + fmt::format("{}", fmt::join(kAwareMethods, " | ")))
      ->capture_default_str();
  v->add_option("--samples", va->samples, "Inputs")->check(CLI::Range(1, 10000000))->capture_default_str();
  v->add_option("--seed", va->seed, "Sobol scrambling seed")->capture_default_str();
  v->add_option("--estimator-samples", va->estimator_samples, "VNDF samples of the diffuse-aware estimator")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  v->add_option("--rel-tol", va->rel_tol,
                "Relative tolerance of the exact diffuse-aware azimuth mean (reference of the -alu methods)")
      ->check(CLI::Range(1e-9, 1e-2))
      ->capture_default_str();
  add_threads_option(v, va->threads);
  add_json_flag(v, va->json);

  const auto [p, pa] =
      add_command<PlotArgs>(g.plot, "micro-shadowing-aware",
                            "Generic, specular-aware and diffuse-aware azimuth means over (V, N.L) per "
                            "roughness and N.V (maps.csv; figures: scripts/plot_micro_shadowing_aware.py)",
                            run_plot);
  add_out_dir_option(p, pa->out);
  p->add_option("--size", pa->size, "Grid points per axis")->capture_default_str();
  add_threads_option(p, pa->threads);
}

}  // namespace

MSH_CLI_REGISTER(add_aware, 61);

}  // namespace msh::cli
