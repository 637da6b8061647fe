// The multiscale study (see study/study.h and docs/study.md): the configurations, the plan (validation, the
// user's maps, cells and variants) and run_study, the composition of the stages.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/directional_codec.h>
#include <microshadow/render/texture_gen.h>
#include <microshadow/study/study.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>

#include "study_internal.h"

namespace msh::study {

using namespace msh::render;
using namespace msh::study::detail;
using json = nlohmann::json;

StudyConfig full_config() {
  StudyConfig c;
  c.near_lights = true;
  // The view sweep (docs/study.md, "Views, azimuths and scales"): the shipped relief term and the terms it
  // is judged against, at grazing views, every light azimuth and every scale; two light elevations (a low
  // and a high sun) keep it to 280 cells per material.
  c.sweep_views = {30, 60, 75, 85};
  c.sweep_elevations = {10, 45};
  c.sweep_azimuths = {0, 45, 90, 135, 180};
  c.sweep_scales = {1, 2, 4, 8, 16, 32, 64};
  c.sweep_terms = {"none", "ao", "directional-view", "directional", "diffuse-aware-alu+lut3d"};
  return c;
}

StudyConfig quick_config() {
  StudyConfig c;
  c.name = "quick";
  c.materials = {"plaster"};
  c.shapes = {"plane", "cylinder"};
  c.fine_size = 1024;
  c.elevations = {10, 25, 45};
  c.azimuths = {0};
  c.point_light = false;
  c.image_size = 64;
  c.gt_spp = 32;
  c.gt_max_spp = 256;
  c.featured_lights = {"dir-el10-az0"};
  return c;
}

StudyConfig area_config(bool quick) {
  StudyConfig c;
  c.name = quick ? "area-quick" : "area";
  c.materials = {"plaster"};
  c.shapes = {"plane"};
  c.fine_size = quick ? 1024 : 2048;
  c.scales = quick ? std::vector<int>{4} : std::vector<int>{4, 16};
  c.elevations = {};
  c.point_light = c.sphere_light = false;
  c.area_radii_deg = {1, 5, 10, 20, 40};
  c.area_elevations = {25, 50};
  c.area_planar_radii_deg = {10, 20};
  c.widened = c.normal_ablation = false;
  c.featured_lights = {};
  c.image_size = quick ? 32 : 64;
  if (quick) c.gt_spp = 32, c.gt_max_spp = 256;
  return c;
}

std::pair<std::string, std::string> split_study_term(const std::string& term) {
  const std::size_t at = term.find('@');
  if (at == std::string::npos) return {term, ""};
  return {term.substr(0, at), term.substr(at + 1)};
}

namespace {

std::string num(double x) { return fmt::format("{:g}", x); }

Vec3f local_dir(const Frame& f, double el_deg, double az_deg) {
  const Vec3f d = direction_from_angles(float(el_deg), float(az_deg));
  return f.T * d.x + f.B * d.y + f.N * d.z;
}

// Directional lights at every elevation × azimuth.
void add_directional(std::vector<StudyLight>& out, const Frame& fr, const std::vector<double>& elevations,
                     const std::vector<double>& azimuths) {
  for (double el : elevations)
    for (double az : azimuths) {
      StudyLight s;
      s.name = "dir-el" + num(el) + "-az" + num(az);
      s.type = "directional";
      s.light.type = LightType::Directional;
      s.light.direction = local_dir(fr, el, az);
      s.light.color = Rgbf(3.0f);
      s.elevation = el, s.azimuth = az;
      out.push_back(s);
    }
}

// The lights of the main grid at scale k (a fine texel is texel_world world units).
std::vector<StudyLight> make_lights(const StudyConfig& c, const Frame& fr, int k, float texel_world) {
  std::vector<StudyLight> out;
  add_directional(out, fr, c.elevations, c.azimuths);
  // Point and sphere lights at fixed positions in the frame (about 2.7 tile widths away), irradiance about 3
  // at normal incidence at the centre, like the directional lights.
  auto positional = [&](const char* name, LightType t, Vec3f p, float radius) {
    StudyLight s;
    s.name = name, s.type = t == LightType::Point ? "point" : "sphere";
    s.light.type = t;
    s.light.position = fr.P0 + fr.T * p.x + fr.B * p.y + fr.N * p.z;
    s.light.radius = radius;
    s.light.color = Rgbf(3.0f * dot(p, p));
    s.elevation = std::asin(p.z / length(p)) * 180 / kPi<double>;
    s.azimuth = std::atan2(p.y, p.x) * 180 / kPi<double>;
    out.push_back(s);
  };
  if (c.point_light) positional("point", LightType::Point, {-2.0f, -1.0f, 1.5f}, 0.0f);
  if (c.sphere_light) positional("sphere", LightType::Sphere, {1.5f, 1.0f, 2.0f}, 0.5f);
  if (c.near_lights) {
    // near_light_footprints footprints from the view's centre at elevation 30°, azimuth 45°; the sphere's
    // radius is one footprint (angular radius asin(1 / near_light_footprints)).
    const float fp = float(c.footprint) * float(k) * texel_world;
    const Vec3f p = direction_from_angles(30.0f, 45.0f) * (float(c.near_light_footprints) * fp);
    positional("point-near", LightType::Point, p, 0.0f);
    positional("sphere-near", LightType::Sphere, p, fp);
  }
  // Area-light section: at the sphere light's distance from the view's centre, intensity 3 d² (irradiance
  // about 3 at normal incidence, as the directional lights). A sphere's cone must stay 5° above the tangent
  // plane (the height field's slab is open below it).
  const float dist = std::sqrt(1.5f * 1.5f + 1.0f * 1.0f + 2.0f * 2.0f);
  auto area = [&](const std::string& type, double rho, double el) {
    StudyLight s;
    s.name = fmt::format("{}-r{}-el{}", type, num(rho), num(el));
    s.type = type;
    s.elevation = el, s.azimuth = c.area_azimuth, s.radius_deg = rho;
    const Vec3f w = local_dir(fr, el, c.area_azimuth);
    const float r = float(rho * kPi<double> / 180);
    s.light.position = fr.P0 + w * dist;
    s.light.color = Rgbf(3.0f * dist * dist);
    if (type == "sphere") {
      s.light.type = LightType::Sphere;
      s.light.radius = dist * std::sin(r);
    } else {
      // Facing the view's centre; a disk of angular radius ρ, a 2:1 rect of angular half-widths ρ and
      // atan(tan ρ / 2), its long side along the view's u.
      s.light.normal = -w;
      s.light.tangent = normalize(fr.T - w * dot(fr.T, w));
      if (type == "disk") {
        s.light.type = LightType::Disk;
        s.light.radius = dist * std::tan(r);
      } else {
        s.light.type = LightType::Rect;
        s.light.half_size = {dist * std::tan(r), 0.5f * dist * std::tan(r)};
      }
    }
    out.push_back(s);
  };
  for (double el : c.area_elevations)
    for (double rho : c.area_radii_deg)
      if (el - rho >= 5) area("sphere", rho, el);
  for (double rho : c.area_planar_radii_deg) {
    area("disk", rho, c.area_planar_elevation);
    area("rect", rho, c.area_planar_elevation);
  }
  return out;
}

bool uses_nl(const std::string& m) {
  return occlusion::find_micro_shadowing_method(split_study_term(m).first)->uses_ndotl;
}

// A term with a compact form: its method must read the directional channels and the form must parse for
// their count.
void check_term(const std::string& t) {
  const auto [method, form] = split_study_term(t);
  micro_shadowing_from_string(method);
  if (form.empty() && t.find('@') != std::string::npos)
    throw InputError(fmt::format("term '{}': no form after '@'", t));
  if (form.empty()) return;
  const auto* info = occlusion::find_micro_shadowing_method(method);
  if (!info->needs_texel || info->is_pair())
    throw InputError(
        fmt::format("term '{}': only a method that reads the directional channels takes a form", t));
  if (form == "unorm8" || form == "bc4") return;  // per-channel storage (render::DirectionalEncoding)
  render::parse_directional_form(form, std::max(info->texel_channels, directional::kDirectionalChannels));
}

std::vector<StudyVariant> make_variants(const StudyConfig& c, int k) {
  std::vector<StudyVariant> v;
  if (area_section(c)) {
    for (const std::string& name : c.area_terms) {
      const std::string& t = name;
      for (const std::string& mode : c.area_ms_modes) {
        const AreaMs a = area_ms_from_string(mode);
        if (!uses_nl(t) && a != AreaMs::Sampled) continue;  // a constant term: every mode is the same
        // The exact generic term inside the area quadrature costs 40–190 ms per shading point: not rendered
        // (lut3d, its tabulation, stands for it).
        if (t == "generic-vndf" && a == AreaMs::Integrated) continue;
        v.push_back({t, false, CoarseRoughness::Base, a});
      }
    }
    return v;
  }
  for (const auto& t : c.terms) v.push_back({t, false, CoarseRoughness::Base});
  if (c.normal_ablation)
    for (const auto& t : c.terms)
      if (uses_nl(t)) v.push_back({t, true, CoarseRoughness::Base});
  if (c.widened && k > 1)
    for (const auto& t : c.terms) v.push_back({t, false, CoarseRoughness::Widened});
  return v;
}

// The main grid's scales, then the sweep's that it lacks.
std::vector<int> all_scales(const StudyConfig& c) {
  std::vector<int> v = c.scales;
  if (!c.sweep_views.empty())
    for (int k : c.sweep_scales)
      if (std::find(v.begin(), v.end(), k) == v.end()) v.push_back(k);
  return v;
}

void validate(const StudyConfig& c) {
  auto bad = [](const std::string& what) { throw InputError("study: " + what); };
  if (c.materials.empty() && c.user_materials.empty()) bad("no materials");
  if (c.scales.empty()) bad("no scales");
  // The procedural kinds' fine size (a user map's side is checked when it is loaded).
  for (int k : all_scales(c))
    if (!c.materials.empty() && (k < 1 || c.fine_size % k != 0))
      bad(fmt::format("scale {} does not divide the fine size {}", k, c.fine_size));
  for (int k : all_scales(c))
    if (k < 1) bad(fmt::format("scale {} must be >= 1", k));
  std::vector<std::string> names = c.materials;
  for (const UserMaterial& u : c.user_materials) {
    if (u.name.empty()) bad(fmt::format("{}: a user material needs a name", u.height.string()));
    if (!(u.depth_texels > 0) || !std::isfinite(u.depth_texels) || u.depth_texels > 1e4f)
      bad(fmt::format("{}: depth must be in (0, 10000] texels, got {}", u.height.string(), u.depth_texels));
    names.push_back(u.name);
  }
  // Rows, images and timings are keyed by the material's name.
  for (size_t i = 0; i < names.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (names[i] == names[j]) bad(fmt::format("two materials are named '{}' (rename one file)", names[i]));
  for (const auto& s : c.shapes)
    if (s != "plane" && s != "cylinder") bad(fmt::format("unknown shape '{}' (plane, cylinder)", s));
  if (c.elevations.empty() && !c.point_light && !c.sphere_light && !area_section(c)) bad("no lights");
  for (double r : c.area_radii_deg)
    if (!(r > 0 && r <= 60)) bad(fmt::format("area-light angular radius must be in (0, 60], got {}", r));
  for (double r : c.area_planar_radii_deg)
    if (!(r > 0 && r <= 60)) bad(fmt::format("area-light angular radius must be in (0, 60], got {}", r));
  for (double e : c.area_elevations)
    if (!(e > 5 && e < 90)) bad(fmt::format("area-light elevation must be in (5, 90), got {}", e));
  if (area_section(c) && !(c.area_planar_elevation - 5 >= 0 && c.area_planar_elevation < 90))
    bad("area_planar_elevation must be in [5, 90)");
  try {
    for (const auto& t : c.terms) check_term(t);
    for (const auto& t : c.area_terms) check_term(t);
    for (const auto& m : c.area_ms_modes) area_ms_from_string(m);
  } catch (const InputError& e) {
    bad(e.what());
  }
  if (c.terms.empty() && !area_section(c)) bad("no terms");
  for (const auto* list : {&c.terms, &c.area_terms})
    for (const auto& t : *list)
      if (t == kGroundTruth) bad("ground-truth is the reference, not a term");
  if (area_section(c) && make_lights(c, frame_of("plane"), 1, 1.0f).empty())
    bad("no area light keeps its cone 5 degrees above the horizon");
  for (const auto* list : {&c.elevations, &c.sweep_elevations})
    for (double e : *list)
      if (!(e > 0 && e < 90)) bad(fmt::format("light elevation must be in (0, 90), got {}", e));
  for (const auto* list : {&c.azimuths, &c.sweep_azimuths, &c.view_azimuths, &c.sweep_view_azimuths})
    for (double a : *list)
      if (!(a >= -360 && a <= 360)) bad(fmt::format("azimuth must be in [-360, 360] degrees, got {}", a));
  if (c.views.empty() || c.view_azimuths.empty()) bad("no views");
  for (const auto* list : {&c.views, &c.sweep_views})
    for (double v : *list)
      if (!(v >= 0 && v <= 89))
        bad(fmt::format("view angle must be in [0, 89] degrees off the normal, got {}", v));
  if (!c.sweep_views.empty()) {
    if (c.sweep_view_azimuths.empty() || c.sweep_elevations.empty() || c.sweep_azimuths.empty() ||
        c.sweep_scales.empty() || c.sweep_terms.empty())
      bad("the view sweep needs view azimuths, light elevations and azimuths, scales and terms");
    for (const auto& t : c.sweep_terms)
      if (std::find(c.terms.begin(), c.terms.end(), t) == c.terms.end())
        bad(fmt::format("sweep term '{}' is not one of the study's terms", t));
  }
  if (!(c.near_light_footprints >= 1.5 && c.near_light_footprints <= 1000))
    bad("near_light_footprints must be in [1.5, 1000]");
  if (c.max_windows < 1 || c.max_windows > 16) bad("max_windows must be in [1, 16]");
  if (c.image_size < 8 || c.image_size > 4096) bad("image size must be in [8, 4096]");
  if (c.footprint < 1 || c.footprint > 8) bad("footprint must be in [1, 8]");
  if (c.gt_spp < 8 || c.gt_spp % 8 != 0) bad("gt_spp must be a multiple of 8");
  if (c.gt_max_spp < c.gt_spp) bad("gt_max_spp must be >= gt_spp");
  if (!c.sweep_views.empty() &&
      (c.sweep_gt_spp < 8 || c.sweep_gt_spp % 8 != 0 || c.sweep_gt_max_spp < c.sweep_gt_spp))
    bad("sweep_gt_spp must be a multiple of 8 and at most sweep_gt_max_spp");
  if (c.method_spp < 1) bad("method_spp must be >= 1");
  for (int k : all_scales(c))
    if (!c.materials.empty() && c.fine_size / k < c.footprint)
      bad(fmt::format("at scale {} the texture ({} texels) is narrower than one footprint ({} pixels)", k,
                      c.fine_size, c.footprint));
}

// The user's height maps, loaded and checked (square, side divisible by every scale, at least the view's
// width) before any work, so a bad file is one error line and nothing is written.
std::vector<Texture> load_user_maps(const StudyConfig& c) {
  std::vector<Texture> maps;
  for (const UserMaterial& u : c.user_materials) {
    Texture h = load_height_map(u.height);
    const std::string f = u.height.string();
    if (h.width() != h.height())
      throw InputError(fmt::format("study: {}: height map is {}x{}; the study needs a square map", f,
                                   h.width(), h.height()));
    for (int k : all_scales(c)) {
      if (h.width() % k != 0)
        throw InputError(
            fmt::format("study: {}: scale {} does not divide the map's size {}", f, k, h.width()));
      if (h.width() / k < c.footprint)
        throw InputError(fmt::format(
            "study: {}: at scale {} the map ({} texels) is narrower than one footprint ({} pixels)", f, k,
            h.width(), c.footprint));
    }
    maps.push_back(std::move(h));
  }
  return maps;
}

}  // namespace

StudyView study_view(const StudyConfig& c, const std::string& shape, int fine_size, double view,
                     double view_azimuth, int k) {
  StudyView v;
  v.view = view, v.view_azimuth = view_azimuth;
  const int fp = c.footprint;
  const int across = std::min(c.image_size, fine_size / k);  // at most one texture width
  const double cos30 = std::cos(kPi<double> / 6), cv = std::cos(view * kPi<double> / 180);
  // Rows: the same texture area as at 30° (cv / cos30 rounded to a whole number of footprints).
  const double rows = double(across) * std::min(1.0, cv / cos30);
  // As many windows as there are footprints across (up to max_windows per side) wherever the view covers a
  // quarter of the texture or less: the ratio is a mean over the texture's regions, and 16 windows were too
  // few (rock at 2048², k = 1, view 30°: mean |bias − 1| of directional-view 0.37 with 4 × 4 windows, 0.031
  // with 16 × 16 of the same total area; docs/study.md "Windows").
  v.windows =
      shape == "plane" && fine_size / (c.image_size * k) >= 4 ? std::clamp(across / fp, 1, c.max_windows) : 1;
  const int n = v.windows;
  v.width = std::max(fp, across / n / fp * fp);
  v.height = std::max(fp, int(std::lround(rows / n / fp)) * fp);
  // How far the view reaches on the plane, in tiles from its centre along u or v: the windows' centres
  // (spread over the middle tile: up to 1/2 tile along u and v) and each window's rectangle (k fine texels
  // across a pixel, k / cos(view) along, turned by the view azimuth).
  const double tile_px = double(fine_size) / k;  // pixels across one tile
  const double a = 0.5 * v.width, b = 0.5 * v.height / std::max(cv, 1e-3);
  const double phi = view_azimuth * kPi<double> / 180, cs = std::abs(std::cos(phi)),
               sn = std::abs(std::sin(phi));
  v.extent = (n > 1 ? 0.5 : 0.0) + std::max(a * sn + b * cs, a * cs + b * sn) / tile_px;
  return v;
}

UserMaterial user_material_from_folder(const std::filesystem::path& dir) {
  const std::string d = dir.string();
  if (!std::filesystem::is_directory(dir)) throw InputError(fmt::format("{}: material folder not found", d));
  const auto mj = dir / "material.json";
  require_regular_file(mj, "material.json ");
  std::ifstream in(mj);
  if (!in) throw InputError(fmt::format("{}: no material.json (a gen-material folder holds one)", d));
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: material.json is not JSON ({})", d, e.what()));
  }
  if (!j.is_object() || !j.contains("height_texels") || !j["height_texels"].is_number())
    throw InputError(fmt::format("{}: material.json has no numeric height_texels", d));
  // Checked as a double: a float conversion of a value beyond float range is undefined behaviour.
  const double depth = j["height_texels"].get<double>();
  if (!(depth > 0 && depth <= 1e4))
    throw InputError(fmt::format("{}: material.json height_texels {} is outside (0, 10000]", d, depth));
  if (j.contains("height") && !j["height"].is_string())
    throw InputError(fmt::format("{}: material.json \"height\" is not a file name", d));
  const std::string height = j.value("height", std::string("height.png"));
  UserMaterial u;
  // The folder's name; "dir/" has an empty filename, so take the parent's.
  u.name = (dir.has_filename() ? dir : dir.parent_path()).filename().string();
  u.height = dir / height;
  u.depth_texels = float(depth);
  if (!std::filesystem::exists(u.height))
    throw InputError(fmt::format("{}: height map {} not found", d, height));
  return u;
}

StudyPlan plan_study(const StudyConfig& cfg) {
  validate(cfg);
  std::vector<Texture> user_maps = load_user_maps(cfg);
  StudyPlan plan;
  plan.config = cfg;
  for (const std::string& kind : cfg.materials) plan.materials.push_back({kind, cfg.fine_size, {}, 0});
  for (std::size_t i = 0; i < cfg.user_materials.size(); ++i) {
    const int side = user_maps[i].width();
    plan.materials.push_back(
        {cfg.user_materials[i].name, side, std::move(user_maps[i]), cfg.user_materials[i].depth_texels});
  }
  for (int k : cfg.scales) plan.variants[k] = make_variants(cfg, k);
  if (!cfg.sweep_views.empty())
    for (int k : cfg.sweep_scales)
      for (const std::string& t : cfg.sweep_terms) plan.sweep_variants[k].push_back({t});
  for (std::size_t m = 0; m < plan.materials.size(); ++m)
    for (const std::string& shape : cfg.shapes) {
      const Frame fr = frame_of(shape);
      const int fine = plan.materials[m].fine_size;
      const float texel_world = kTileWorld / float(fine);
      // The cells of a material × shape: scale → view → light, the main grid's first at each scale.
      std::vector<StudyLight> sweep_lights;
      add_directional(sweep_lights, fr, cfg.sweep_elevations, cfg.sweep_azimuths);
      for (int k : all_scales(cfg)) {
        const bool main_k = std::find(cfg.scales.begin(), cfg.scales.end(), k) != cfg.scales.end();
        std::set<std::string> main_keys;  // view|view azimuth|light of the main grid at k
        const std::vector<StudyLight> lights =
            main_k ? make_lights(cfg, fr, k, texel_world) : std::vector<StudyLight>{};
        if (main_k)
          for (double v : cfg.views)
            for (double va : cfg.view_azimuths) {
              const StudyView view = study_view(cfg, shape, fine, v, va, k);
              for (const StudyLight& light : lights) {
                plan.cells.push_back({m, shape, k, view, light, false});
                main_keys.insert(fmt::format("{}|{}|{}", num(v), num(va), light.name));
              }
            }
        const bool sweep_k =
            std::find(cfg.sweep_scales.begin(), cfg.sweep_scales.end(), k) != cfg.sweep_scales.end();
        if (!cfg.sweep_views.empty() && sweep_k)
          for (double v : cfg.sweep_views)
            for (double va : cfg.sweep_view_azimuths) {
              const StudyView view = study_view(cfg, shape, fine, v, va, k);
              for (const StudyLight& light : sweep_lights)
                if (!main_keys.count(fmt::format("{}|{}|{}", num(v), num(va), light.name)))
                  plan.cells.push_back({m, shape, k, view, light, true});
            }
      }
    }
  return plan;
}

json run_study(const StudyConfig& cfg, const std::filesystem::path& out, const Log& log_fn) {
  const StudyPlan plan = plan_study(cfg);
  const auto t_start = std::chrono::steady_clock::now();
  const double cpu_start = cpu_seconds();
  auto log = [&](const std::string& s) {
    if (log_fn) log_fn(s);
  };
  std::error_code ec;
  std::filesystem::create_directories(out / "images", ec);
  if (ec) throw InputError(fmt::format("{}: cannot create directory: {}", out.string(), ec.message()));

  CellRunner runner(plan, log_fn);
  std::vector<CellResult> cells;
  cells.reserve(plan.cells.size());
  for (const StudyCell& cell : plan.cells) {
    CellResult r = runner.run(cell);
    write_featured_images(r, out);
    r.featured.clear();  // written: a full study would otherwise hold every featured image until the end
    // ETA: the cells' mean wall time so far times the cells left, plus the mean texture generation so far
    // for each material not generated yet.
    const std::size_t done = cells.size() + 1, left = plan.cells.size() - done;
    const double gen = runner.preparation_timing()["generate_seconds"].get<double>();
    const std::size_t gen_done = runner.preparation_timing()["materials"].size();
    const std::size_t gen_left = plan.materials.size() - cell.material - 1;  // cells go material by material
    const double eta = std::max(0.0, secs_since(t_start) - gen) / double(done) * double(left) +
                       gen / double(std::max<std::size_t>(1, gen_done)) * double(gen_left);
    log(fmt::format(
        "study: [{}/{}] {} {} k={} view {:g}/{:g} {}: ground truth {} spp ({}), {} terms; {:.1f} s "
        "+ {:.1f} s; ETA {}",
        done, plan.cells.size(), plan.materials[cell.material].name, cell.shape, cell.scale, cell.view.view,
        cell.view.view_azimuth, cell.light.name, r.ground_truth["spp"].get<int>(),
        r.ground_truth["floors_met"].get<bool>() ? "floors met" : "floors NOT met",
        plan.variants_of(cell).size(), r.ground_truth_seconds, r.methods_seconds,
        eta >= 60 ? fmt::format("{} min {:02d} s", int(eta) / 60, int(eta) % 60)
                  : fmt::format("{:.0f} s", eta)));
    cells.push_back(std::move(r));
  }

  const json results = aggregate_results(plan, cells);
  write_results(results, out);
  const json timing =
      aggregate_timing(cells, runner.preparation_timing(), secs_since(t_start), cpu_seconds() - cpu_start);
  io::write_file_atomic(out / "timing.json", timing.dump(1) + "\n");
  const auto seconds = [&](const char* key) { return timing[key].get<double>(); };
  log(
      fmt::format("study: {} rows, {:.0f} s wall, {:.0f} s CPU (generation {:.0f} s, ground truth {:.0f} s, "
                  "terms {:.0f} s) -> {}",
                  results["rows"].size(), seconds("total_seconds"), seconds("total_cpu_seconds"),
                  seconds("generate_seconds"), seconds("ground_truth_seconds"), seconds("methods_seconds"),
                  out.string()));
  return results;
}

}  // namespace msh::study
