// CLI for the as-used accuracy measurement (include/microshadow/lut/runtime/micro_shadowing_verify.h,
// docs/lut.md):
//   microshadow verify micro-shadowing-lut FILE [--samples N] [--seed S] [--against mean|azimuth]
//       [--sampler auto|plain|azimuth] [--gpu-weights BITS] [--json]
//   microshadow verify micro-shadowing-term --method NAME|all [--samples N] [--against mean|azimuth] [--json]
// A table is measured through the public samplers an engine calls (sample_micro_shadowing,
// sample_micro_shadowing_azimuth); the terms through the method registry
// (occlusion/runtime/micro_shadowing_methods.h), by their registry ids.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/lut/runtime/micro_shadowing_verify.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common.h"

namespace msh::cli {
namespace {

struct CommonArgs {
  int samples = 10000, threads = 0, worst = 10;
  uint32_t seed = 1;
  std::string against = "mean", roughness_range, roughness_bands = "0.1,0.25,0.55,1.0",
              nv_bands = "0,0.25,0.5,0.75,1";
  std::string csv;
  bool json = false;
};

struct LutArgs : CommonArgs {
  std::string file, sampler = "auto", roughness;
  int harmonics = -1, gpu_weights = 0;
};

struct TermArgs : CommonArgs {
  std::string method = "all";
};

// Band edges `text` restricted to [lo, hi]: lo, the edges strictly inside, hi.
std::vector<double> clip_edges(const std::string& text, double lo, double hi, const std::string& what) {
  std::vector<double> e{lo};
  for (double x : parse_list(text, what))
    if (x > lo && x < hi) e.push_back(x);
  if (hi > lo) e.push_back(hi);
  if (e.size() < 2) e.push_back(lo);  // a zero-width range: one closed band [lo, lo]
  return e;
}

lut::VerifyOptions make_options(const CommonArgs& a, double rmin, double rmax) {
  lut::VerifyOptions o;
  o.samples = a.samples;
  o.seed = a.seed;
  o.against = lut::verify_reference_from_name(a.against);
  o.threads = a.threads;
  o.worst = a.worst;
  if (!a.roughness_range.empty()) {
    const std::vector<double> r = parse_list(a.roughness_range, "--roughness-range");
    if (r.size() != 2) throw UsageError("--roughness-range must be two numbers LO,HI");
    rmin = r[0], rmax = r[1];
  }
  o.roughness_min = rmin, o.roughness_max = rmax;
  lut::validate(o);  // the range before the bands are clipped to it
  o.roughness_bands = clip_edges(a.roughness_bands, rmin, rmax, "--roughness-bands");
  o.n_dot_v_bands = parse_list(a.nv_bands, "--nv-bands");
  lut::validate(o);
  return o;
}

nlohmann::json stats_json(const lut::ErrorStats& s) {
  return {{"count", s.count},
          {"nonfinite", s.nonfinite},
          {"rms", s.rms},
          {"p99", s.p99},
          {"max", s.max_abs},
          {"mean", s.mean},
          {"rms_255", s.rms * 255.0},
          {"p99_255", s.p99 * 255.0},
          {"max_255", s.max_abs * 255.0}};
}

nlohmann::json result_json(const lut::VerifyResult& r) {
  nlohmann::json j;
  j["all"] = stats_json(r.all);
  j["early_out"] = stats_json(r.early_out);
  j["rest"] = stats_json(r.rest);
  for (const auto* bands : {&r.by_roughness, &r.by_n_dot_v}) {
    nlohmann::json arr = nlohmann::json::array();
    for (const lut::VerifyBand& b : *bands) {
      nlohmann::json x = stats_json(b.stats);
      x["lo"] = b.lo, x["hi"] = b.hi;
      arr.push_back(x);
    }
    j[bands == &r.by_roughness ? "by_roughness" : "by_n_dot_v"] = arr;
  }
  nlohmann::json w = nlohmann::json::array();
  for (const lut::VerifyWorst& x : r.worst) {
    const lut::VerifyInput& p = x.input;
    w.push_back({{"index", x.index},
                 {"visibility", p.visibility},
                 {"n_dot_l", p.n_dot_l},
                 {"n_dot_v", p.n_dot_v},
                 {"roughness", p.roughness},
                 {"cos_phi", p.cos_phi},
                 {"exact", p.exact},
                 {"approx", std::isfinite(x.approx) ? nlohmann::json(x.approx) : nlohmann::json()},
                 {"error", std::isfinite(x.error) ? nlohmann::json(x.error) : nlohmann::json()}});
  }
  j["worst"] = w;
  return j;
}

void print_stats_row(const std::string& label, const lut::ErrorStats& s) {
  std::cout << fmt::format("  {:<24} {:>7} {:>8.3f} {:>8.3f} {:>8.3f} {:>10.3e} {:>10.3e} {:>+10.2e}{}\n",
                           label, s.count, s.rms * 255, s.p99 * 255, s.max_abs * 255, s.rms, s.max_abs,
                           s.mean,
                           s.nonfinite ? fmt::format("  ({} non-finite)", s.nonfinite) : std::string());
}

void print_result(const lut::VerifyResult& r) {
  std::cout << fmt::format("  {:<24} {:>7} {:>8} {:>8} {:>8} {:>10} {:>10} {:>10}\n", "inputs", "count",
                           "RMS/255", "p99/255", "max/255", "RMS", "max", "mean");
  print_stats_row("all", r.all);
  print_stats_row("early-out (2V+N.L<1)", r.early_out);
  print_stats_row("rest", r.rest);
  for (std::size_t i = 0; i < r.by_roughness.size(); ++i) {
    const auto& b = r.by_roughness[i];
    print_stats_row(
        fmt::format("roughness [{:.2f}, {:.2f}{}", b.lo, b.hi, i + 1 == r.by_roughness.size() ? "]" : ")"),
        b.stats);
  }
  for (std::size_t i = 0; i < r.by_n_dot_v.size(); ++i) {
    const auto& b = r.by_n_dot_v[i];
    print_stats_row(
        fmt::format("N.V [{:.2f}, {:.2f}{}", b.lo, b.hi, i + 1 == r.by_n_dot_v.size() ? "]" : ")"), b.stats);
  }
  if (r.worst.empty()) return;
  std::cout << fmt::format("  worst inputs:\n  {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>9}\n", "V",
                           "N.L", "N.V", "roughness", "cos_phi", "exact", "approx", "err/255");
  for (const lut::VerifyWorst& w : r.worst) {
    const lut::VerifyInput& p = w.input;
    std::cout << fmt::format(
        "  {:>10.8f} {:>10.8f} {:>10.8f} {:>10.8f} {:>+10.7f} {:>10.7f} {:>10.7f} {:>+9.3f}\n", p.visibility,
        p.n_dot_l, p.n_dot_v, p.roughness, p.cos_phi, p.exact, w.approx, w.error * 255);
  }
}

// --csv: every input with its exact and approximate value (one file per method; atomic write).
void write_csv(const std::string& path, const std::vector<lut::VerifyInput>& in, const lut::VerifyResult& r) {
  const std::filesystem::path p(path);
  std::string text = "index,visibility,n_dot_l,n_dot_v,roughness,cos_phi,exact,approx,error\n";
  for (std::size_t i = 0; i < in.size(); ++i) {
    const lut::VerifyInput& x = in[i];
    text += fmt::format("{},{},{},{},{},{},{},{},{}\n", i, x.visibility, x.n_dot_l, x.n_dot_v, x.roughness,
                        x.cos_phi, x.exact, r.approx[i], r.approx[i] - x.exact);
  }
  io::write_file_atomic(p, text);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The table and its sidecar. A sidecar is required unless --roughness is given: without one the roughness per
// channel would be a guess, and the measure would measure the guess. The loader checks the rest (layout,
// sizes recorded in the sidecar against the file, channel and slab counts).
lut::MicroShadowingLut load_checked(const LutArgs& a) {
  namespace fs = std::filesystem;
  const fs::path path(a.file);
  if (!fs::is_regular_file(path)) throw UsageError(fmt::format("'{}': no such file", a.file));
  const fs::path side = lut::sidecar_path(path);
  if (!fs::exists(side) && a.roughness.empty())
    throw UsageError(
        fmt::format("'{}': no sidecar '{}' (give --roughness, and --harmonics for an azimuth-aware "
                    "table, to measure it without one)",
                    a.file, side.string()));
  std::optional<std::vector<double>> rough;
  if (!a.roughness.empty()) rough = parse_list(a.roughness, "--roughness");
  std::optional<int> harm;
  if (a.harmonics >= 0) harm = a.harmonics;
  return lut::load_micro_shadowing_lut(path, rough, harm);
}

void run_lut(const LutArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  if (a.gpu_weights < 0 || a.gpu_weights > 16)
    throw UsageError(fmt::format("--gpu-weights must be in [0, 16] bits, got {}", a.gpu_weights));
  if (a.sampler != "auto" && a.sampler != "plain" && a.sampler != "azimuth")
    throw UsageError(fmt::format("--sampler must be auto, plain or azimuth, got '{}'", a.sampler));
  const lut::MicroShadowingLut table = load_checked(a);
  lut::MicroShadowingLutView view = table.view();
  // --gpu-weights: the sampler's own option, weights rounded down to 1/2^bits on every hardware-filtered
  // axis.
  view.filter_weight_bits = a.gpu_weights;
  const bool cone = table.layout == lut::LutLayout::Cone;
  const double rmin = cone ? lut::short_float(table.cone.roughness_min) : table.roughness.front();
  const double rmax = cone ? lut::short_float(table.cone.roughness_max) : table.roughness.back();
  const lut::VerifyOptions o = make_options(a, rmin, rmax);
  if (a.sampler == "azimuth" && view.harmonics == 0)
    throw UsageError("--sampler azimuth needs an azimuth-aware table (harmonics > 0)");
  const bool azimuth = a.sampler == "azimuth" || (a.sampler == "auto" && view.harmonics > 0 &&
                                                  o.against == lut::VerifyReference::Azimuth);
  // The samplers exactly as an engine calls them.
  lut::MicroShadowingApprox f;
  if (azimuth)
    f = [&view](float V, float nl, float nv, float r, float c) {
      return lut::sample_micro_shadowing_azimuth<float>(view, V, nl, nv, r, c);
    };
  else
    f = [&view](float V, float nl, float nv, float r, float) {
      return lut::sample_micro_shadowing<float>(view, V, nl, nv, r);
    };
  if (!a.csv.empty()) require_parent_dir(a.csv, "--csv");
  const std::vector<lut::VerifyInput> inputs = lut::make_verify_inputs(o);
  const lut::VerifyResult r = lut::measure(inputs, f, o);
  if (!a.csv.empty()) write_csv(a.csv, inputs, r);
  const double seconds = seconds_since(t0);
  const char* sampler = azimuth ? "azimuth" : "plain";
  const int bits = a.gpu_weights;
  const std::string layout = lut::layout_name(table.layout);
  const std::string roughness_text = cone ? fmt::format("{} slabs over [{}, {}]", view.n_rough, rmin, rmax)
                                          : fmt::format("channels {}", fmt::join(table.roughness, "/"));
  if (a.json) {
    nlohmann::json j = result_json(r);
    j["file"] = a.file;
    j["layout"] = layout;
    j["size"] = {view.n_vis, view.n_nl, view.n_nv};
    j["channels"] = view.channels;
    if (cone)
      j["roughness_slabs"] = view.n_rough;
    else
      j["table_roughness"] = table.roughness;
    j["harmonics"] = view.harmonics;
    j["sampler"] = sampler;
    j["gpu_weights"] = bits;
    j["against"] = lut::verify_reference_name(o.against);
    j["samples"] = o.samples;
    j["seed"] = o.seed;
    j["roughness_range"] = {o.roughness_min, o.roughness_max};
    j["seconds"] = seconds;
    print_json(j);
    return;
  }
  std::cout << fmt::format(
      "{}: {} layout, {}x{}x{} texels, roughness {}, harmonics {}\n"
      "sampler {}{}, against the exact {}, N = {} inputs (seed {}), roughness uniform in [{}, {}]; error = "
      "approx - exact; {:.1f} s\n",
      a.file, layout, view.n_vis, view.n_nl, view.n_nv, roughness_text, view.harmonics, sampler,
      bits ? fmt::format(", filter weights rounded down to 1/{}", 1 << bits) : std::string(),
      o.against == lut::VerifyReference::AzimuthMean ? "azimuth mean" : "term at the input's azimuth",
      o.samples, o.seed, o.roughness_min, o.roughness_max, seconds);
  print_result(r);
}

// The terms measured, by their registry ids (occlusion/runtime/micro_shadowing_methods.h): the registry's
// closed forms of (V, N.L) that depend on N.L and the generic term's ALU fit, as the renderer runs them
// (MicroShadowingEvaluator::shade: float, as a shader); the fit's two-stage form (per pixel + per light),
// under its form id generic-vndf-alu-two-stage; and the exact generic term itself, generic-vndf, evaluated
// like every term here without the azimuth (its exact azimuth mean: against the azimuth, the best any
// azimuth-blind approximation can do).
struct Term {
  std::string name;
  lut::MicroShadowingApprox f;
};

const std::vector<Term>& terms() {
  using occlusion::MicroShadowingEvaluator;
  static const std::vector<Term> t = [] {
    std::vector<Term> v;
    const auto shaded = [](std::shared_ptr<const MicroShadowingEvaluator> e) {
      return Term{e->info().name, [e](float V, float nl, float nv, float r, float) {
                    occlusion::MicroShadowingShadeInput in;
                    in.visibility = V, in.roughness = r;
                    in.v = {std::sqrt(std::max(0.0f, 1 - nv * nv)), 0, nv};
                    in.l = {std::sqrt(std::max(0.0f, 1 - nl * nl)), 0, nl};
                    return e->shade(in).diffuse;
                  }};
    };
    for (const std::string& name : occlusion::micro_shadowing_closed_form_terms())
      v.push_back(shaded(std::make_shared<MicroShadowingEvaluator>(name)));
    v.push_back(shaded(std::make_shared<MicroShadowingEvaluator>("generic-vndf-alu")));
    v.push_back({two_stage_fit_id(), [](float V, float nl, float nv, float r, float) {
                   return micro_shadowing::generic_vndf_alu_two_stage(V, nl, nv, r);
                 }});
    const auto exact = std::make_shared<const MicroShadowingEvaluator>("generic-vndf");
    v.push_back({exact->info().name, [exact](float V, float nl, float nv, float r, float) {
                   return float(exact->eval({V, nl, nv, r, std::nullopt, std::nullopt}));
                 }});
    return v;
  }();
  return t;
}

std::vector<std::string> term_names() {
  std::vector<std::string> n;
  for (const Term& t : terms()) n.push_back(t.name);
  return n;
}

void run_term(const TermArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<const Term*> methods;
  for (const Term& t : terms())
    if (a.method == "all" || t.name == a.method) methods.push_back(&t);
  if (methods.empty())
    throw UsageError(
        fmt::format("--method must be all or one of: {}; got '{}'", fmt::join(term_names(), ", "), a.method));
  const lut::VerifyOptions o = make_options(a, 0.1, 1.0);
  if (!a.csv.empty()) {
    if (methods.size() != 1) throw UsageError("--csv needs one --method");
    require_parent_dir(a.csv, "--csv");
  }
  const std::vector<lut::VerifyInput> inputs = lut::make_verify_inputs(o);  // shared by every method
  std::vector<lut::VerifyResult> results;
  for (const Term* m : methods) results.push_back(lut::measure(inputs, m->f, o));
  if (!a.csv.empty()) write_csv(a.csv, inputs, results[0]);
  const double seconds = seconds_since(t0);
  if (a.json) {
    nlohmann::json j;
    j["against"] = lut::verify_reference_name(o.against);
    j["samples"] = o.samples;
    j["seed"] = o.seed;
    j["roughness_range"] = {o.roughness_min, o.roughness_max};
    j["seconds"] = seconds;
    nlohmann::json arr = nlohmann::json::array();
    for (std::size_t i = 0; i < methods.size(); ++i) {
      nlohmann::json x = result_json(results[i]);
      x["method"] = methods[i]->name;
      arr.push_back(x);
    }
    j["results"] = arr;
    print_json(j);
    return;
  }
  std::cout << fmt::format(
      "closed-form micro-shadowing terms against the exact {}, N = {} inputs (seed {}), roughness uniform in "
      "[{}, {}]; error = approx - exact; {:.1f} s\n",
      o.against == lut::VerifyReference::AzimuthMean ? "azimuth mean" : "term at the input's azimuth",
      o.samples, o.seed, o.roughness_min, o.roughness_max, seconds);
  for (std::size_t i = 0; i < methods.size(); ++i) {
    std::cout << methods[i]->name << ":\n";
    print_result(results[i]);
  }
}

void add_common(CLI::App* c, CommonArgs& a) {
  c->add_option("--samples", a.samples, "Number of random inputs N")->capture_default_str();
  c->add_option("--seed", a.seed, "Scrambling seed of the inputs")->capture_default_str();
  c->add_option(
       "--against", a.against,
       "mean: the exact azimuth mean (a plain table's target); azimuth: the exact term at the input's "
       "relative azimuth")
      ->capture_default_str();
  c->add_option("--roughness-range", a.roughness_range,
                "LO,HI: roughness range of the inputs (default: the table's channel range; terms: 0.1,1)");
  c->add_option("--roughness-bands", a.roughness_bands, "Band edges of the per-roughness rows")
      ->capture_default_str();
  c->add_option("--nv-bands", a.nv_bands, "Band edges of the per-N.V rows")->capture_default_str();
  c->add_option("--worst", a.worst, "How many worst inputs to list")->capture_default_str();
  add_threads_option(c, a.threads);
  c->add_option("--csv", a.csv,
                "Also write every input with its exact and approximate value to this CSV file");
  add_json_flag(c, a.json, "Print one JSON object instead of the table");
}

void add_verify(Groups& g) {
  const auto [l, la] = add_command<LutArgs>(
      g.verify, "micro-shadowing-lut",
      "Accuracy of a baked micro-shadowing table as an engine samples it: N stratified random continuous "
      "inputs (V, N.L, N.V, roughness over the table's range, azimuth), through the library's sampler, "
      "against the exact term (docs/lut.md, Verify)",
      run_lut);
  l->add_option("file", la->file, "Table file (from `bake micro-shadowing`, with its .json sidecar)")
      ->required();
  l->add_option("--sampler", la->sampler,
                "auto (azimuth-aware sampler when --against azimuth and the table has harmonics) | plain | "
                "azimuth")
      ->capture_default_str();
  l->add_option(
       "--gpu-weights", la->gpu_weights,
       "Quantise the linear-filter weights to 1/2^BITS (rounded down) as GPU filtering hardware does (8 on "
       "current GPUs; 0: exact float weights)")
      ->capture_default_str();
  l->add_option("--roughness", la->roughness, "Roughness per channel (overrides the sidecar)");
  l->add_option("--harmonics", la->harmonics, "Harmonic count (overrides the sidecar)");
  add_common(l, *la);

  const auto [t, ta] = add_command<TermArgs>(
      g.verify, "micro-shadowing-term",
      "The same measure for the registry's closed forms of (V, N.L) that depend on N.L, the generic term's "
      "ALU-only fit (generic-vndf-alu, and its two-stage form generic-vndf-alu-two-stage) and the exact "
      "generic term's azimuth mean (generic-vndf), on one shared set of inputs; --method lists them",
      run_term);
  t->add_option("--method", ta->method, "all | " + fmt::format("{}", fmt::join(term_names(), " | ")))
      ->capture_default_str();
  add_common(t, *ta);
}

}  // namespace

MSH_CLI_REGISTER(add_verify, 60);

}  // namespace msh::cli
