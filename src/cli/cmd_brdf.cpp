// `eval brdf`, `bake ggx-albedo`, `bake dfg`, `bake brdf-shipped`: the BRDF models and their tables.
#include <fmt/format.h>
#include <microshadow/bsdf/runtime/albedo.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/bsdf/runtime/sphere_grid.h>
#include <microshadow/bsdf/runtime/tables.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/texture.h>

#include <filesystem>
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
  return parse_list(text, "--" + spec.name);
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
  TableOutput out;  // brdf-shipped: out.out is the C++ header
  std::string pixel_format, variant = "split-sum";
  int size = 32;
  uint32_t samples = 1u << 14;
};

io::PixelFormat checked_pixel_format(const std::string& name, const std::string& def) {
  const io::PixelFormat pf = io::pixel_format_from_name(name.empty() ? def : name);
  const int c = io::pixel_format_channels(pf);
  if (pf == io::PixelFormat::RGBA8Unorm || pf == io::PixelFormat::R8Unorm ||
      pf == io::PixelFormat::RG8Unorm || pf == io::PixelFormat::BC4Unorm || pf == io::PixelFormat::BC5Unorm)
    throw UsageError("BRDF tables need a float pixel format (r16f, rg16f, rgba16f, r32f, rg32f, rgba32f)");
  if (c != 1 && c != 2 && c != 4) throw UsageError("unsupported channel count");
  return pf;
}

void check_bake(const BakeArgs& a) {
  if (a.size < 2 || a.size > 1024)
    throw UsageError(fmt::format("--size must be in [2, 1024], got {}", a.size));
  if (a.samples < 1 || a.samples > (1u << 24)) throw UsageError("--samples must be in [1, 2^24]");
}

// Channels: 1 → E; 2 → E, Ē(r); 4 → E, Ē, E_Fc, Ē_Fc.
void run_bake_ggx_albedo(const BakeArgs& a) {
  check_bake(a);
  const io::FileFormat ff = table_output_format(a.out);
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
  io::write_volume(a.out.out, v, ff, pf, "msh_ggx_albedo");
}

// split-sum (Karis): (E − E_Fc, E_Fc); multiscatter (Filament): (E_Fc, E). 4 channels add the cosine-weighted
// averages over μ of the first two.
void run_bake_dfg(const BakeArgs& a) {
  check_bake(a);
  if (a.variant != "split-sum" && a.variant != "multiscatter")
    throw UsageError(fmt::format("--variant must be split-sum or multiscatter, got '{}'", a.variant));
  const io::FileFormat ff = table_output_format(a.out);
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
  io::write_volume(a.out.out, v, ff, pf, karis ? "msh_dfg_split_sum" : "msh_dfg_multiscatter");
}

void run_bake_shipped(const BakeArgs& a) {
  require_parent_dir(a.out.out, "--out");
  const auto t =
      bsdf::bake_ggx_albedo(bsdf::kShippedTableSize, bsdf::kShippedTableSize, bsdf::kShippedTableSamples);
  io::write_file_atomic(a.out.out, bsdf::shipped_tables_header(t));
}

void add_brdf(Groups& g) {
  const auto [e, eval_args] =
      add_command<EvalBrdfArgs>(g.eval, "brdf",
                                "Evaluate a BRDF model f(v, l) (no cosine) at N.V = --ndotv, view in the xz "
                                "plane, light --light (default: the mirror direction), or its directional "
                                "albedo with --albedo. --list shows every model and parameter.",
                                run_eval_brdf);
  e->add_option("--model", eval_args->model, "Model name (see --list)");
  e->add_option("--ndotv", eval_args->ndotv, "N.V of the view direction, in [0, 1]")
      ->check(Finite)
      ->default_val(1.0);
  e->add_option("--light", eval_args->light, "Light direction X,Y,Z in the shading frame (normalized)");
  e->add_flag("--albedo", eval_args->albedo,
              "Print the directional albedo at N.V (deterministic QMC with the model's importance sampling)");
  e->add_option("--samples", eval_args->samples, "QMC samples for --albedo (power of two best)")
      ->default_val(1u << 18);
  add_json_flag(e, eval_args->json);
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
}

void add_brdf_bake(Groups& g) {
  const auto [b, ba] = add_command<BakeArgs>(
      g.bake, "ggx-albedo",
      "Bake the GGX (height-correlated Smith, F = 1) directional albedo E(mu, r): x = N.V = i/(n-1), y = "
      "perceptual roughness r = j/(n-1) (alpha = r^2). Channels: 1 -> E; 2 -> E, Ebar(r); 4 -> E, Ebar, "
      "E_Fc, Ebar_Fc.",
      run_bake_ggx_albedo);
  add_table_output(b, ba->out);
  b->add_option("--size", ba->size, "Texels per axis")->default_val(32);
  b->add_option("--samples", ba->samples, "QMC samples per texel")->default_val(1u << 14);
  b->add_option("--pixel-format", ba->pixel_format, "r16f, rg16f, rgba16f, r32f, rg32f (default), rgba32f");

  auto bd = std::make_shared<BakeArgs>();
  bd->size = 128;
  bd->samples = 1u << 12;
  CLI::App* d = g.bake->add_subcommand("dfg",
                                       "Bake the split-sum DFG table: x = N.V = i/(n-1), y = perceptual "
                                       "roughness r = j/(n-1). split-sum (Karis): (scale, bias), E = "
                                       "F0*scale + bias; multiscatter (Filament): (DFG.x, DFG.y), E = "
                                       "mix(x, y, F0), y = E(F=1). RGBA adds the cosine-weighted averages "
                                       "over N.V of R and G.");
  add_table_output(d, bd->out);
  d->add_option("--size", bd->size, "Texels per axis")->default_val(128);
  d->add_option("--samples", bd->samples, "QMC samples per texel")->default_val(1u << 12);
  d->add_option("--variant", bd->variant, "split-sum or multiscatter")->default_val("split-sum");
  d->add_option("--pixel-format", bd->pixel_format, "rg16f (default), rgba16f, rg32f, rgba32f");
  d->callback([bd] { run_bake_dfg(*bd); });

  const auto [s, bs] = add_command<BakeArgs>(
      g.bake, "brdf-shipped",
      "Regenerate include/microshadow/bsdf/tables_data.h (32x32 GGX E and E_Fc, 2^16 samples)",
      run_bake_shipped);
  s->add_option("--out", bs->out.out, "Output C++ header")->required();
}

// ---- Sphere-grid figures.

double choice_index(const std::string& model, const std::string& param, const std::string& value) {
  for (const auto& p : bsdf::find_brdf_model(model).params)
    if (p.name == param)
      for (size_t i = 0; i < p.choices.size(); ++i)
        if (p.choices[i] == value) return double(i);
  throw std::logic_error("no choice " + value);
}

struct SphereFigure {
  std::string file, caption;
  std::vector<std::string> row_labels;
  std::vector<std::vector<std::unique_ptr<bsdf::BrdfModel>>> rows;
};

std::vector<double> ramp(double a, double b, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(a + (b - a) * i / (n - 1));
  return v;
}

std::vector<SphereFigure> sphere_figures(int cols) {
  std::vector<SphereFigure> figs;
  const auto rs = ramp(0.1, 1.0, cols);
  {
    SphereFigure f{"spheres_multiscatter.png",
                   "RTR4 fig. 9.39: roughness 0.1 -> 1 left to right; gold without / with the Kulla-Conty "
                   "multiple-bounce lobe, black dielectric (IOR 1.5) without / with",
                   {"gold, single scattering", "gold, + multiple bounce",
                    "black dielectric, single scattering", "black dielectric, + multiple bounce"},
                   {}};
    const double cond = choice_index("ggx", "fresnel", "conductor"),
                 diel = choice_index("ggx", "fresnel", "dielectric");
    for (const double fr : {cond, diel})
      for (const double ms : {0.0, 1.0}) {
        std::vector<std::unique_ptr<bsdf::BrdfModel>> row;
        for (double r : rs)
          row.push_back(
              bsdf::make_brdf("ggx", {{"roughness", {r}}, {"fresnel", {fr}}, {"multiscatter", {ms}}}));
        f.rows.push_back(std::move(row));
      }
    figs.push_back(std::move(f));
  }
  {
    SphereFigure f{
        "spheres_ksk.png",
        "RTR4 fig. 9.41: GGX (F0 0.04, multiple bounce) + Lambert vs + Kelemen/Szirmay-Kalos coupled "
        "diffuse; rows 1-2 roughness 0.1 -> 0.5, rows 3-4 0.55 -> 1",
        {"+ Lambert (low r)", "+ KSK coupled (low r)", "+ Lambert (high r)", "+ KSK coupled (high r)"},
        {}};
    for (const auto& range : {ramp(0.1, 0.5, cols), ramp(0.55, 1.0, cols)})
      for (const char* m : {"ggx-lambert", "ggx-ksk"}) {
        std::vector<std::unique_ptr<bsdf::BrdfModel>> row;
        for (double r : range)
          row.push_back(
              bsdf::make_brdf(m, {{"roughness", {r}}, {"rho", {0.5, 0.25, 0.12}}, {"multiscatter", {1.0}}}));
        f.rows.push_back(std::move(row));
      }
    figs.push_back(std::move(f));
  }
  {
    SphereFigure f{"spheres_diffuse.png",
                   "Diffuse models, roughness (Oren-Nayar sigma 0 -> 1.2 rad) increasing left to right",
                   {"lambert", "shirley (9.64)", "disney-diffuse", "disney-diffuse, subsurface 1", "hammon",
                    "oren-nayar", "oren-nayar-qualitative"},
                   {}};
    const std::vector<double> rho = {0.8, 0.8, 0.8};
    auto row_of = [&](auto fn) {
      std::vector<std::unique_ptr<bsdf::BrdfModel>> row;
      for (int c = 0; c < cols; ++c) row.push_back(fn(double(c) / (cols - 1)));
      f.rows.push_back(std::move(row));
    };
    row_of([&](double) { return bsdf::make_brdf("lambert", {{"rho", rho}}); });
    row_of([&](double) { return bsdf::make_brdf("shirley", {{"rho", rho}}); });
    row_of([&](double t) {
      return bsdf::make_brdf("disney-diffuse", {{"base-color", rho}, {"roughness", {t}}});
    });
    row_of([&](double t) {
      return bsdf::make_brdf("disney-diffuse",
                             {{"base-color", rho}, {"roughness", {t}}, {"subsurface", {1.0}}});
    });
    row_of([&](double t) { return bsdf::make_brdf("hammon", {{"rho", rho}, {"roughness", {t}}}); });
    row_of([&](double t) { return bsdf::make_brdf("oren-nayar", {{"rho", rho}, {"sigma", {1.2 * t}}}); });
    row_of([&](double t) {
      return bsdf::make_brdf("oren-nayar-qualitative", {{"rho", rho}, {"sigma", {1.2 * t}}});
    });
    figs.push_back(std::move(f));
  }
  return figs;
}

struct PlotArgs {
  std::string out;
  int size = 96, cols = 6;
};

void run_plot_spheres(const PlotArgs& a) {
  if (a.size < 8 || a.size > 1024)
    throw UsageError(fmt::format("--size must be in [8, 1024], got {}", a.size));
  if (a.cols < 2 || a.cols > 16)
    throw UsageError(fmt::format("--columns must be in [2, 16], got {}", a.cols));
  const std::filesystem::path dir = make_out_dir(a.out);
  std::string legend;
  for (const auto& f : sphere_figures(a.cols)) {
    std::vector<std::vector<const bsdf::BrdfModel*>> rows;
    for (const auto& r : f.rows) {
      rows.emplace_back();
      for (const auto& m : r) rows.back().push_back(m.get());
    }
    const io::Volume img = bsdf::encode_srgb(bsdf::render_sphere_grid(rows, a.size));
    io::write_png(dir / f.file, img, 8);
    legend += f.file + ": " + f.caption + "\n";
    for (size_t i = 0; i < f.row_labels.size(); ++i)
      legend += fmt::format("  row {}: {}\n", i + 1, f.row_labels[i]);
  }
  io::write_file_atomic(dir / "spheres.txt", legend);
}

void add_brdf_plot(Groups& g) {
  const auto [p, pa] =
      add_command<PlotArgs>(g.plot, "brdf-figures",
                            "Render sphere grids of the BRDF models (uniform white environment + one "
                            "directional light, orthographic): spheres_multiscatter.png (RTR4 fig. 9.39), "
                            "spheres_ksk.png (fig. 9.41), spheres_diffuse.png, spheres.txt",
                            run_plot_spheres);
  add_out_dir_option(p, pa->out);
  p->add_option("--size", pa->size, "Pixels per sphere")->default_val(96);
  p->add_option("--columns", pa->cols, "Spheres per row (roughness steps)")->default_val(6);
}

}  // namespace

MSH_CLI_REGISTER(add_brdf, 60);
MSH_CLI_REGISTER(add_brdf_plot, 61);
MSH_CLI_REGISTER(add_brdf_bake, 61);

}  // namespace msh::cli
