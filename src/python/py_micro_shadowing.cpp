// microshadow.eval_micro_shadowing / micro_shadowing_methods: every micro-shadowing method of the runtime
// registry (include/microshadow/occlusion/runtime/micro_shadowing_methods.h), vectorized. A method added to
// the registry appears here without any change.
//
// Two paths, identical results (tests/python/test_micro_shadowing.py checks every element):
//   * registry: MicroShadowingEvaluator::eval per element (oneTBB over elements; the generic-vndf exact term,
//     its Sobol estimator, ALU fits, ...);
//   * fast: the header-only closed-form terms (occlusion/micro_shadowing.h) and the LUT sampler
//     (lut/micro_shadowing_lut.h) called directly in a tight loop, with the registry only for the messages
//     of bad input (the first bad element is re-evaluated through the registry, which throws the CLI's
//     message).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>  // lut::MicroShadowingLut (the registry's tables)
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>

#include <atomic>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>

#include "py_common.h"

namespace msh::py {
namespace {

using namespace pybind11::literals;
using occlusion::MicroShadowingEvaluator;
using occlusion::MicroShadowingOptions;
using occlusion::MicroShadowingQuery;

micro_shadowing::G2Form parse_g2(const std::string& s) {
  if (s == "height-correlated") return micro_shadowing::G2Form::HeightCorrelated;
  if (s == "uncorrelated") return micro_shadowing::G2Form::Uncorrelated;
  throw InputError(fmt::format("--g2 must be height-correlated or uncorrelated, got '{}'", s));
}

// Evaluators are cached per (method, options) so that repeated calls do not rebuild them (accessed with the
// GIL held only).
std::shared_ptr<const MicroShadowingEvaluator> evaluator(const std::string& method,
                                                         const MicroShadowingOptions& o,
                                                         const std::string& g2) {
  static std::map<std::string, std::shared_ptr<const MicroShadowingEvaluator>> cache;
  std::string key = fmt::format("{}\n{}\n{}\n{}\n{}", method, o.samples, o.seed, g2, o.lut_path);
  if (!o.lut_path.empty()) {
    std::error_code ec;
    const auto t = std::filesystem::last_write_time(o.lut_path, ec);
    key += fmt::format("\n{}", ec ? 0 : t.time_since_epoch().count());
  }
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  auto e = std::make_shared<const MicroShadowingEvaluator>(method, o);
  if (cache.size() > 64) cache.clear();
  cache.emplace(key, e);
  return e;
}

constexpr double kPiD = 3.14159265358979323846;

template <class T, class F>
pyb::object fast_loop(const Broadcast& b, F&& term, std::size_t& first_bad) {
  pyb::array_t<T> out = make_output<T>(b);
  T* o = out.mutable_data();
  const Reader<T> r(&b);
  std::atomic<std::size_t> bad{std::numeric_limits<std::size_t>::max()};
  {
    pyb::gil_scoped_release release;
    parallel_chunks(b.n, [&](std::size_t begin, std::size_t end) {
      // Local copies: not reloaded after the terms' (rare) libm calls.
      const Reader<T> rl = r;
      T* const out_p = o;
      for (std::size_t i = begin; i < end; ++i) {
        const double v = rl(0, i), nl = rl(1, i), nv = rl(2, i), ro = rl(3, i);
        // The CLI's domain: every input in [0, 1] (NaN fails); the registry reports the first bad element.
        if (!(v >= 0 && v <= 1 && nl >= 0 && nl <= 1 && nv >= 0 && nv <= 1 && ro >= 0 && ro <= 1)) {
          std::size_t cur = bad.load();
          while (i < cur && !bad.compare_exchange_weak(cur, i)) {
          }
          return;
        }
        out_p[i] = T(term(rl, i, v, nl, nv, ro));
      }
    });
  }
  first_bad = bad.load();
  return finish(out, b);
}

// A pair (occlusion/runtime/micro_shadowing_methods.h) has one term per lobe: lobe picks it.
const occlusion::MicroShadowingMethodInfo* lobe_term(const std::string& method,
                                                     const std::optional<std::string>& lobe) {
  if (lobe && *lobe != "diffuse" && *lobe != "specular")
    throw InputError(fmt::format("lobe must be 'diffuse' or 'specular', got '{}'", *lobe));
  const occlusion::MicroShadowingMethodInfo* info = occlusion::find_micro_shadowing_method(method);
  if (!info || !info->is_pair()) return info;
  if (!lobe)
    throw InputError(
        fmt::format("{} is a pair ({} on the diffuse lobe, {} on the specular lobe): pass "
                    "lobe='diffuse' or lobe='specular'",
                    method, info->diffuse, info->specular));
  return occlusion::find_micro_shadowing_method(*lobe == "diffuse" ? info->diffuse : info->specular);
}

pyb::object eval(const std::string& method_arg, pyb::handle visibility, pyb::handle ndotl, pyb::handle ndotv,
                 pyb::handle roughness, pyb::handle phi, std::optional<int64_t> samples, uint32_t seed,
                 const std::string& g2, pyb::object lut, pyb::handle roughness_y, const std::string& path,
                 const std::optional<std::string>& lobe) {
  if (path != "auto" && path != "registry")
    throw pyb::value_error(fmt::format("path must be 'auto' or 'registry', got '{}'", path));
  const occlusion::MicroShadowingMethodInfo* term = lobe_term(method_arg, lobe);
  const std::string method = term ? term->name : method_arg;  // unknown: the registry's message below
  const bool pair_part = term && method != method_arg;
  // A pair's option that only its other term takes does not apply to this one.
  if (pair_part && !term->accepts_samples) samples.reset();
  if (pair_part && !term->accepts_lut) lut = pyb::none();
  MicroShadowingOptions o;
  o.samples = samples.value_or(0);
  if (samples && (*samples < 1 || *samples > (int64_t(1) << 30)))
    throw InputError(fmt::format("--samples must be in [1, 2^30], got {}", *samples));
  o.seed = seed;
  o.g2 = parse_g2(g2);
  if (!lut.is_none()) o.lut_path = pyb::str(pyb::module_::import("os").attr("fspath")(lut));
  const auto ev = evaluator(method, o, g2);

  const bool has_phi = !phi.is_none(), has_ry = !roughness_y.is_none();
  // The registry range-checks every input with the CLI's message (NaN fails): Domain::Checked.
  constexpr Domain kC = Domain::Checked;
  std::vector<ArgSpec> args = {{visibility, "visibility", 0, kC},
                               {ndotl, "ndotl", 0, kC},
                               {ndotv, "ndotv", 0, kC},
                               {roughness, "roughness", 0, kC}};
  const std::size_t iphi = args.size();
  if (has_phi) args.push_back({phi, "phi", 0, kC});
  const std::size_t iry = args.size();
  if (has_ry) args.push_back({roughness_y, "roughness_y", 0, kC});
  const Broadcast b = broadcast(args);

  // float32(π) rounds above π: a float32 phi equal to it means π (else np.float32(np.pi) would be rejected).
  const double pi_f32 = double(float(kPiD));
  auto read_phi = [&](const auto& r, std::size_t i) {
    const double p = r(iphi, i);
    return b.f32 && p > kPiD && p <= pi_f32 ? kPiD : p;
  };
  auto query = [&](const auto& r, std::size_t i) {
    MicroShadowingQuery q;
    q.visibility = r(0, i), q.n_dot_l = r(1, i), q.n_dot_v = r(2, i), q.roughness = r(3, i);
    if (has_phi) q.phi = read_phi(r, i);
    if (has_ry) q.roughness_y = r(iry, i);
    return q;
  };
  auto run = [&](auto tag) -> pyb::object {
    using T = decltype(tag);
    const Reader<T> r(&b);
    // Option errors (phi / samples / roughness_y where the method takes none, a LUT without harmonics for
    // phi, ...) come from the registry on the first element, with the CLI's message.
    if (b.n > 0) ev->eval(query(r, 0));
    // The registry says which terms have a fast form (MicroShadowingMethodInfo::closed_form, table_sample);
    // an option only the per-element path takes (phi, samples, roughness_y) sends the call there.
    const bool fast = path == "auto" && term && (term->closed_form || term->table_sample);
    if (!fast || has_ry || o.samples > 0 || (term->closed_form && has_phi))
      return map_scalar(b, [&](const auto& rr, std::size_t i) { return ev->eval(query(rr, i)); });

    std::size_t bad = 0;
    pyb::object out;
    if (const auto f = term->closed_form) {  // a term of (V, N·L) alone
      out = fast_loop<T>(
          b, [f](const auto&, std::size_t, double v, double nl, double, double) { return f(v, nl); }, bad);
    } else {
      // The registry's own table (a file loaded once, or the default table baked on first use).
      const auto table = b.n > 0 ? ev->table(has_phi) : nullptr;
      if (!table) return make_output<T>(b);
      const lut::MicroShadowingLutView view = table->view();
      // phi on a mean-only table is an error for every point outside the early-out: the registry reports
      // it.
      if (has_phi && view.harmonics == 0)
        return map_scalar(b, [&](const auto& rr, std::size_t i) { return ev->eval(query(rr, i)); });
      const bool two_d = term->table_sample == 2;
      out = fast_loop<T>(
          b,
          [&](const auto& rr, std::size_t i, double v, double nl, double nv, double ro) -> double {
            const double n = two_d ? 1.0 : nv;
            if (!has_phi) return lut::sample_micro_shadowing(view, v, nl, n, ro);
            const double p = read_phi(rr, i);
            if (!(p >= 0 && p <= kPiD)) return std::numeric_limits<double>::quiet_NaN();  // reported below
            return lut::sample_micro_shadowing_azimuth(view, v, nl, n, ro, std::cos(p));
          },
          bad);
      if (has_phi) {
        // A phi out of [0, π] was written as NaN: the first bad element (of any input) is reported.
        for (std::size_t i = 0; i < std::min(bad, b.n); ++i)
          if (!(read_phi(r, i) >= 0 && read_phi(r, i) <= kPiD)) {
            bad = i;
            break;
          }
      }
    }
    if (bad != std::numeric_limits<std::size_t>::max()) {
      ev->eval(query(r, bad));  // throws the CLI's message for that element
      throw InputError(fmt::format("{}: input out of domain at element {}", method, bad));
    }
    return out;
  };
  return b.f32 ? run(float{}) : run(double{});
}

}  // namespace

void register_micro_shadowing(pyb::module_& m) {
  m.def(
      "micro_shadowing_methods",
      [](bool details) -> pyb::object {
        pyb::list out;
        for (const auto& i : occlusion::micro_shadowing_methods()) {
          if (!details) {
            out.append(i.name);
            continue;
          }
          out.append(json_to_python(occlusion::micro_shadowing_method_json(i)));
        }
        return out;
      },
      "details"_a = false,
      "Names of every micro-shadowing method (the CLI's `eval micro-shadowing --method` and `render "
      "--method` values; `microshadow methods`), in the registry's order; details=True returns one dict per "
      "method with every field of `microshadow methods --json` (the same text, from one function): name, "
      "label, "
      "summary, diffuse, specular, pair, in_study, uses_ndotl, uses_roughness, uses_ndotv, accepts_phi, "
      "accepts_roughness_y, accepts_samples, accepts_lut, needs_texel (per-texel channels, renderer only), "
      "texel_channels, texel_bake (the command that bakes them), uses_visibility (reads V), table_sample (3 "
      "or "
      "2 for the table samplers), use (when to use it) and glsl (id, expr, requires, lut of each shader "
      "form). "
      "A pair D+S has the term D on the diffuse lobe and S on the specular lobe.");
  m.def(
      "eval_micro_shadowing", &eval, "method"_a, "visibility"_a, "ndotl"_a, "ndotv"_a = 1.0,
      "roughness"_a = 0.5, "phi"_a = pyb::none(), "samples"_a = pyb::none(), "seed"_a = 1,
      "g2"_a = "height-correlated", "lut"_a = pyb::none(), "roughness_y"_a = pyb::none(), "path"_a = "auto",
      "lobe"_a = pyb::none(),
      "Micro-shadowing term (docs/micro-shadowing.md) of any registered method, as `microshadow eval "
      "micro-shadowing --method METHOD ... --json` prints its 'value', vectorized.\n\n"
      "visibility, ndotl, ndotv, roughness, phi, roughness_y: numbers or arrays, broadcast together like "
      "numpy ufuncs. visibility V in [0, 1] (projected solid angle), N.L and N.V in [0, 1], perceptual "
      "roughness in [0, 1] (alpha = roughness^2), phi the relative azimuth of l and v in [0, pi] (a float32 "
      "phi of float32(pi), just above pi, is read as pi; None: "
      "the mean over the azimuth, what a LUT stores), roughness_y for anisotropic GGX (generic-vndf). "
      "samples: the Sobol estimator with N samples (generic-vndf; None: the exact quadrature), seed its "
      "scrambling seed, g2 'height-correlated' or 'uncorrelated'. lut: a table file for lut3d / lut2d "
      "(None: the default table, baked on first use).\n\n"
      "dtype: float32 arrays give float32 (the CLI's double value, rounded once), anything else float64; "
      "all-scalar input gives a numpy scalar. Unknown method, options a method does not take, values out "
      "of their domain (including NaN) and shape mismatches raise ValueError with the CLI's message. "
      "Computed with the GIL released, in parallel (oneTBB) for large arrays, bit-identical for any "
      "thread count. path='registry' forces the per-element registry evaluation (for tests; the default "
      "'auto' runs the closed-form terms and the LUT sampler in a tight loop, same values). lobe: 'diffuse' "
      "or 'specular', the term of a pair on that lobe (required for a pair; ignored for a single term).");
}

}  // namespace msh::py
