// `eval brdf`, `bake ggx-albedo`, `bake dfg`, `bake brdf-shipped`: the BRDF models and their tables.
#include <fmt/format.h>
#include <microshadow/bsdf/albedo.h>
#include <microshadow/bsdf/brdf_model.h>
#include <microshadow/bsdf/tables.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/texture.h>

#include <map>
#include <memory>
#include <set>

#include "common.h"

namespace msh::cli {
namespace {

// One CLI option per distinct parameter name over every model; values are parsed once the model is known.
struct EvalBrdfArgs {
  std::string model;
  double ndotv = 1.0;
  std::string light;
  bool albedo = false;
  bool json = false;
  bool list = false;
  uint32_t samples = 1u << 18;
  std::map<std::string, std::string> raw;  // param name → text as given
};

std::vector<double> parse_param(const bsdf::ParamSpec& spec, const std::string& text) {
  if (!spec.choices.empty()) {
    for (size_t i = 0; i < spec.choices.size(); ++i)
      if (spec.choices[i] == text) return {double(i)};
    std::string known;
    for (const auto& c : spec.choices) known += (known.empty() ? "" : ", ") + c;
    throw UsageError(fmt::format("--{} must be one of: {}; got '{}'", spec.name, known, text));
  }
  std::vector<double> v;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    while (end && *end == ' ') ++end;
    if (item.empty() || end == item.c_str() || *end != '\0' || !std::isfinite(x))
      throw UsageError(fmt::format("--{} must be finite number(s), got '{}'", spec.name, text));
    v.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return v;
}

nlohmann::json rgb_json(const Rgbd& c) { return nlohmann::json::array({c.r, c.g, c.b}); }

nlohmann::json models_json() {
  nlohmann::json arr = nlohmann::json::array();
  for (const auto& m : bsdf::brdf_models()) {
    nlohmann::json params = nlohmann::json::array();
    for (const auto& p : m.params) {
      nlohmann::json jp = {{"name", p.name}, {"help", p.help}, {"components", p.components}};
      if (p.choices.empty()) {
        jp["default"] = p.def;
        jp["range"] = {p.lo, p.hi};
      } else {
        jp["choices"] = p.choices;
        jp["default"] = p.choices.at(size_t(p.def.at(0)));
      }
      params.push_back(jp);
    }
    arr.push_back({{"name", m.name}, {"summary", m.summary}, {"source", m.source}, {"params", params}});
  }
  return arr;
}

void run_eval_brdf(const EvalBrdfArgs& a) {
  if (a.list) {
    if (a.json) {
      print_json({{"models", models_json()}});
    } else {
      for (const auto& m : bsdf::brdf_models()) {
        std::string ps;
        for (const auto& p : m.params) ps += " --" + p.name;
        fmt::print("{:24s} {}\n{:24s}   source: {}\n{:24s}   params:{}\n", m.name, m.summary, "", m.source,
                   "", ps);
      }
    }
    return;
  }
  if (a.model.empty()) throw UsageError("--model is required (see --list)");
  const bsdf::ModelInfo& info = bsdf::find_brdf_model(a.model);
  bsdf::BrdfParams given;
  for (const auto& [name, text] : a.raw) {
    const bsdf::ParamSpec* spec = nullptr;
    for (const auto& p : info.params)
      if (p.name == name) spec = &p;
    if (!spec) throw UsageError(fmt::format("model '{}' has no parameter --{}", info.name, name));
    given.values[name] = parse_param(*spec, text);
  }
  const bsdf::BrdfParams params = bsdf::complete_params(info, given);
  require_range(a.ndotv, 0.0, 1.0, "--ndotv");
  const auto model = info.make(params);
  const double mu = a.ndotv;
  const Vec3d wo(safe_sqrt(1.0 - mu * mu), 0.0, mu);

  nlohmann::json out = {{"model", info.name}, {"ndotv", mu}};
  nlohmann::json jp = nlohmann::json::object();
  for (const auto& p : info.params) {
    const auto& v = params.values.at(p.name);
    if (!p.choices.empty())
      jp[p.name] = p.choices.at(size_t(v.at(0)));
    else if (p.components == 1)
      jp[p.name] = v.at(0);
    else
      jp[p.name] = v;
  }
  out["params"] = jp;
  if (a.albedo) {
    if (a.samples < 1 || a.samples > (1u << 26)) throw UsageError("--samples must be in [1, 2^26]");
    const Rgbd e = bsdf::directional_albedo(*model, wo, a.samples);
    out["albedo"] = rgb_json(e);
    out["samples"] = a.samples;
    if (a.json)
      print_json(out);
    else
      fmt::print("{:.9g} {:.9g} {:.9g}\n", e.r, e.g, e.b);
    return;
  }
  // Default light: the mirror direction of the view (the specular peak).
  Vec3d wi(-wo.x, -wo.y, wo.z);
  if (!a.light.empty()) {
    const Vec3d l = parse_vec3(a.light, "--light");
    if (!(length(l) > 1e-12)) throw UsageError("--light must be a non-zero vector");
    wi = normalize(l);
  }
  const Rgbd f = model->f(wo, wi);
  out["view"] = {wo.x, wo.y, wo.z};
  out["light"] = {wi.x, wi.y, wi.z};
  out["value"] = rgb_json(f);
  out["pdf"] = model->pdf(wo, wi);
  if (a.json)
    print_json(out);
  else
    fmt::print("{:.9g} {:.9g} {:.9g}\n", f.r, f.g, f.b);
}

// ---- Bakers.

struct BakeArgs {
  std::string out, pixel_format, variant = "split-sum";
  int size = 32;
  uint32_t samples = 1u << 14;
};

io::PixelFormat checked_pixel_format(const std::string& name, const std::string& def) {
  const io::PixelFormat pf = io::pixel_format_from_name(name.empty() ? def : name);
  const int c = io::pixel_format_channels(pf);
  if (pf == io::PixelFormat::RGBA8Unorm || pf == io::PixelFormat::R8Unorm || pf == io::PixelFormat::RG8Unorm)
    throw UsageError("BRDF tables need a float pixel format (r16f, rg16f, rgba16f, r32f, rg32f, rgba32f)");
  if (c != 1 && c != 2 && c != 4) throw UsageError("unsupported channel count");
  return pf;
}

void check_bake(const BakeArgs& a) {
  if (a.out.empty()) throw UsageError("--out is required");
  if (a.size < 2 || a.size > 1024)
    throw UsageError(fmt::format("--size must be in [2, 1024], got {}", a.size));
  if (a.samples < 1 || a.samples > (1u << 24)) throw UsageError("--samples must be in [1, 2^24]");
}

// Channels: 1 → E; 2 → E, Ē(r); 4 → E, Ē, E_Fc, Ē_Fc.
void run_bake_ggx_albedo(const BakeArgs& a) {
  check_bake(a);
  const io::FileFormat ff = io::file_format_from_path(a.out);
  const io::PixelFormat pf = checked_pixel_format(a.pixel_format, "rg32f");
  const int ch = io::pixel_format_channels(pf);
  const auto t = bsdf::bake_ggx_albedo(a.size, a.size, a.samples);
  io::Volume v(a.size, a.size, 1, ch);
  for (int j = 0; j < a.size; ++j)
    for (int i = 0; i < a.size; ++i) {
      const size_t k = size_t(j) * size_t(a.size) + size_t(i);
      const double vals[4] = {t.e[k], t.e_avg[size_t(j)], t.e_fc[k], t.efc_avg[size_t(j)]};
      for (int c = 0; c < ch; ++c) v.at(i, j, 0, c) = float(vals[c]);
    }
  io::write_volume(a.out, v, ff, pf, "msh_ggx_albedo");
}

// split-sum (Karis): (E − E_Fc, E_Fc); multiscatter (Filament): (E_Fc, E). 4 channels add the cosine-weighted
// averages over μ of the first two.
void run_bake_dfg(const BakeArgs& a) {
  check_bake(a);
  if (a.variant != "split-sum" && a.variant != "multiscatter")
    throw UsageError(fmt::format("--variant must be split-sum or multiscatter, got '{}'", a.variant));
  const io::FileFormat ff = io::file_format_from_path(a.out);
  const io::PixelFormat pf = checked_pixel_format(a.pixel_format, "rg16f");
  const int ch = io::pixel_format_channels(pf);
  const auto t = bsdf::bake_ggx_albedo(a.size, a.size, a.samples);
  const bool karis = a.variant == "split-sum";
  io::Volume v(a.size, a.size, 1, ch);
  for (int j = 0; j < a.size; ++j)
    for (int i = 0; i < a.size; ++i) {
      const size_t k = size_t(j) * size_t(a.size) + size_t(i);
      const double e = t.e[k], efc = t.e_fc[k], ea = t.e_avg[size_t(j)], efa = t.efc_avg[size_t(j)];
      const double vals[4] = {karis ? e - efc : efc, karis ? efc : e, karis ? ea - efa : efa,
                              karis ? efa : ea};
      for (int c = 0; c < ch; ++c) v.at(i, j, 0, c) = float(vals[c]);
    }
  io::write_volume(a.out, v, ff, pf, karis ? "msh_dfg_split_sum" : "msh_dfg_multiscatter");
}

void run_bake_shipped(const BakeArgs& a) {
  if (a.out.empty()) throw UsageError("--out is required");
  const auto t =
      bsdf::bake_ggx_albedo(bsdf::kShippedTableSize, bsdf::kShippedTableSize, bsdf::kShippedTableSamples);
  io::write_file_atomic(a.out, bsdf::shipped_tables_header(t));
}

void add_brdf(Groups& g) {
  auto eval_args = std::make_shared<EvalBrdfArgs>();
  CLI::App* e = g.eval->add_subcommand("brdf",
                                       "Evaluate a BRDF model f(v, l) (no cosine) at N.V = --ndotv, view in "
                                       "the xz plane, light --light (default: "
                                       "the mirror direction), or its directional albedo with --albedo. "
                                       "--list shows every model and parameter.");
  e->add_option("--model", eval_args->model, "Model name (see --list)");
  e->add_option("--ndotv", eval_args->ndotv, "N.V of the view direction, in [0, 1]")
      ->check(Finite)
      ->default_val(1.0);
  e->add_option("--light", eval_args->light, "Light direction X,Y,Z in the shading frame (normalized)");
  e->add_flag("--albedo", eval_args->albedo,
              "Print the directional albedo at N.V (deterministic QMC with the model's importance sampling)");
  e->add_option("--samples", eval_args->samples, "QMC samples for --albedo (power of two best)")
      ->default_val(1u << 18);
  e->add_flag("--json", eval_args->json, "Print one JSON object");
  e->add_flag("--list", eval_args->list, "List the models and their parameters");
  // Union of the parameter names of every model.
  std::set<std::string> seen;
  for (const auto& m : bsdf::brdf_models())
    for (const auto& p : m.params) {
      if (!seen.insert(p.name).second) continue;
      const std::string name = p.name;
      std::string help = p.help;
      if (!p.choices.empty()) {
        help += " {";
        for (size_t i = 0; i < p.choices.size(); ++i) help += (i ? "|" : "") + p.choices[i];
        help += "}";
      } else if (p.components == 3) {
        help += " (V or R,G,B)";
      }
      e->add_option_function<std::string>(
          "--" + name, [eval_args, name](const std::string& s) { eval_args->raw[name] = s; }, help);
    }
  e->callback([eval_args] { run_eval_brdf(*eval_args); });
}

void add_brdf_bake(Groups& g) {
  auto ba = std::make_shared<BakeArgs>();
  CLI::App* b = g.bake->add_subcommand(
      "ggx-albedo",
      "Bake the GGX (height-correlated Smith, F = 1) directional albedo E(mu, r): x = N.V = i/(n-1), y = "
      "perceptual "
      "roughness r = j/(n-1) (alpha = r^2). Channels: 1 -> E; 2 -> E, Ebar(r); 4 -> E, Ebar, E_Fc, Ebar_Fc.");
  b->add_option("--out", ba->out, "Output file: .dds .ktx2 .exr .npy .h")->required();
  b->add_option("--size", ba->size, "Texels per axis")->default_val(32);
  b->add_option("--samples", ba->samples, "QMC samples per texel")->default_val(1u << 14);
  b->add_option("--pixel-format", ba->pixel_format, "r16f, rg16f, rgba16f, r32f, rg32f (default), rgba32f");
  b->callback([ba] { run_bake_ggx_albedo(*ba); });

  auto bd = std::make_shared<BakeArgs>();
  bd->size = 128;
  bd->samples = 1u << 12;
  CLI::App* d = g.bake->add_subcommand("dfg",
                                       "Bake the split-sum DFG table: x = N.V = i/(n-1), y = perceptual "
                                       "roughness r = j/(n-1). split-sum (Karis): "
                                       "(scale, bias), E = F0*scale + bias; multiscatter (Filament): (DFG.x, "
                                       "DFG.y), E = mix(x, y, F0), y = E(F=1). "
                                       "RGBA adds the cosine-weighted averages over N.V of R and G.");
  d->add_option("--out", bd->out, "Output file: .dds .ktx2 .exr .npy .h")->required();
  d->add_option("--size", bd->size, "Texels per axis")->default_val(128);
  d->add_option("--samples", bd->samples, "QMC samples per texel")->default_val(1u << 12);
  d->add_option("--variant", bd->variant, "split-sum or multiscatter")->default_val("split-sum");
  d->add_option("--pixel-format", bd->pixel_format, "rg16f (default), rgba16f, rg32f, rgba32f");
  d->callback([bd] { run_bake_dfg(*bd); });

  auto bs = std::make_shared<BakeArgs>();
  CLI::App* s = g.bake->add_subcommand(
      "brdf-shipped",
      "Regenerate include/microshadow/bsdf/tables_data.h (32x32 GGX E and E_Fc, 2^16 samples)");
  s->add_option("--out", bs->out, "Output C++ header")->required();
  s->callback([bs] { run_bake_shipped(*bs); });
}

}  // namespace

MSH_CLI_REGISTER(add_brdf, 60);
MSH_CLI_REGISTER(add_brdf_bake, 61);

}  // namespace msh::cli
