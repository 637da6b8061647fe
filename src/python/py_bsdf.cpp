// microshadow.brdf_models / eval_brdf / brdf_pdf / sample_brdf: every BRDF model of the runtime registry
// (include/microshadow/bsdf/runtime/brdf_model.h) by name, vectorized over directions. Parameters are one
// value per call (a model instance is configured once), with the names and ranges of `eval brdf --list`.
#include <fmt/format.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/io/error.h>
#include <type_traits>

#include "py_common.h"

namespace msh::py {
namespace {

using namespace pybind11::literals;

// Model from a name and keyword parameters (Python names may use '_' for the CLI's '-'; enumerated
// parameters take their choice name; colours a number or 3 numbers).
std::unique_ptr<bsdf::BrdfModel> make_model(const std::string& name, const pyb::dict& kw) {
  const bsdf::ModelInfo& info = bsdf::find_brdf_model(name);
  bsdf::BrdfParams given;
  for (const auto& [k, v] : kw) {
    std::string key = pyb::str(k);
    for (char& c : key)
      if (c == '_') c = '-';
    const bsdf::ParamSpec* spec = nullptr;
    for (const auto& p : info.params)
      if (p.name == key) spec = &p;
    if (!spec) throw InputError(fmt::format("model '{}' has no parameter --{}", info.name, key));
    if (!spec->choices.empty()) {
      const std::string text = pyb::str(v);
      std::vector<double> idx;
      for (std::size_t i = 0; i < spec->choices.size(); ++i)
        if (spec->choices[i] == text) idx = {double(i)};
      if (idx.empty()) {
        std::string known;
        for (const auto& c : spec->choices) known += (known.empty() ? "" : ", ") + c;
        throw InputError(fmt::format("--{} must be one of: {}; got '{}'", spec->name, known, text));
      }
      given.values[key] = idx;
    } else if (PyFloat_Check(v.ptr()) || PyLong_Check(v.ptr())) {
      given.values[key] = {v.cast<double>()};
    } else {
      given.values[key] =
          pyb::cast<std::vector<double>>(pyb::module_::import("numpy").attr("ravel")(v).attr("tolist")());
    }
  }
  return info.make(bsdf::complete_params(info, given));
}

pyb::list models_list() {
  pyb::list out;
  for (const auto& m : bsdf::brdf_models()) {
    pyb::list params;
    for (const auto& p : m.params) {
      pyb::dict d("name"_a = p.name, "help"_a = p.help, "components"_a = p.components);
      if (p.choices.empty()) {
        d["default"] = p.def;
        d["range"] = pyb::make_tuple(p.lo, p.hi);
      } else {
        d["choices"] = p.choices;
        d["default"] = p.choices.at(std::size_t(p.def.at(0)));
      }
      params.append(d);
    }
    out.append(
        pyb::dict("name"_a = m.name, "summary"_a = m.summary, "source"_a = m.source, "params"_a = params));
  }
  return out;
}

// The binding of eval_brdf and brdf_pdf: the model by name and keywords, then value(model, wo, wi) at every
// broadcast (wo, wi) pair; a double per pair gives shape (...), a Vec3d gives (..., 3).
template <class Value>
auto at_direction_pairs(Value value) {
  return [value](const std::string& model, pyb::handle wo, pyb::handle wi, const pyb::kwargs& kw) {
    const auto brdf = make_model(model, kw);
    const Broadcast b = broadcast({{wo, "wo", 3, Domain::Direction}, {wi, "wi", 3, Domain::Direction}});
    const auto at = [&](const auto& r, std::size_t i) { return value(*brdf, r.vec(0, i), r.vec(1, i)); };
    if constexpr (std::is_same_v<std::invoke_result_t<Value, const bsdf::BrdfModel&, Vec3d, Vec3d>, double>)
      return map_scalar(b, at);
    else
      return map_vec3(b, at);
  };
}

}  // namespace

void register_bsdf(pyb::module_& m) {
  m.def("brdf_models", &models_list,
        "Every BRDF model of the registry (as `microshadow eval brdf --list --json`): a list of dicts with "
        "name, summary, source and params (name, help, components, default, range or choices).");
  m.def("eval_brdf", at_direction_pairs([](const bsdf::BrdfModel& brdf, const Vec3d& wo, const Vec3d& wi) {
          const Rgbd f = brdf.f(wo, wi);
          return Vec3d(f.r, f.g, f.b);
        }),
        "model"_a, "wo"_a, "wi"_a,
        "BRDF value f(wo, wi) (no cosine) of a model by name, RGB: shape (..., 3). wo (view) and wi (light) "
        "are unit directions of shape (..., 3) in the local frame (n = +z), broadcast like numpy ufuncs; "
        "float32 in -> float32 out. Keyword arguments are the model's parameters (brdf_models(); '_' may "
        "replace '-', e.g. base_color=(1, 0.5, 0.2), fresnel='schlick'); missing ones take their defaults, "
        "out-of-range ones raise ValueError with the CLI's message.");
  m.def("brdf_pdf", at_direction_pairs([](const bsdf::BrdfModel& brdf, const Vec3d& wo, const Vec3d& wi) {
          return brdf.pdf(wo, wi);
        }),
        "model"_a, "wo"_a, "wi"_a,
        "Solid-angle pdf of sample_brdf's wi given wo for a model by name (parameters as for eval_brdf).");
  m.def(
      "sample_brdf",
      [](const std::string& model, pyb::handle wo, pyb::handle u, const pyb::kwargs& kw) {
        const auto brdf = make_model(model, kw);
        const Broadcast b = broadcast({{wo, "wo", 3, Domain::Direction}, {u, "u", 2, Domain::Uniform}}, /*force_f64=*/true);
        pyb::array_t<double> wi = make_output<double>(b, 3), f = make_output<double>(b, 3),
                             pdf = make_output<double>(b);
        double *pw = wi.mutable_data(), *pf = f.mutable_data(), *pp = pdf.mutable_data();
        const Reader<double> r(&b);
        {
          pyb::gil_scoped_release release;
          parallel_each(b.n, [&](std::size_t i) {
            const auto s = brdf->sample(r.vec(0, i), Vec2d(r(1, i, 0), r(1, i, 1)));
            const Vec3d w = s ? s->wi : Vec3d(0, 0, 0);
            const Rgbd c = s ? s->f : Rgbd(0, 0, 0);
            pw[3 * i] = w.x, pw[3 * i + 1] = w.y, pw[3 * i + 2] = w.z;
            pf[3 * i] = c.r, pf[3 * i + 1] = c.g, pf[3 * i + 2] = c.b;
            pp[i] = s ? s->pdf : 0.0;
          });
        }
        return pyb::make_tuple(wi, f, finish(pdf, b));
      },
      "model"_a, "wo"_a, "u"_a,
      "Importance-samples wi given wo (shape (..., 3)) from uniform numbers u (shape (..., 2)): returns "
      "(wi (..., 3), f (..., 3), pdf (...)) in float64; a failed sample gives wi = f = 0 and pdf = 0. "
      "Parameters as for eval_brdf.");
}

}  // namespace msh::py
