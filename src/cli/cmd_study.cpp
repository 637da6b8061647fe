// `microshadow study [--quick] --out DIR`: the multiscale comparison of every micro-shadowing term against a
// ray-traced fine height field (docs/study.md).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/study/study.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

#include "common.h"

namespace msh::cli {
namespace {

struct StudyArgs {
  std::string out, materials, cache, shapes, area_ms, scales, methods, heights, depths, encoding = "float";
  std::string views, view_azimuths, light_azimuths, light_elevations, gt_rule;
  std::vector<std::string> folders;
  bool quick = false, quiet = false, area = false, sweep = false, no_sweep = false, no_ablations = false,
       near = false, no_near = false;
  int threads = 0, fine_size = 0, image_size = 0, gt_max_spp = 0, max_windows = 0;
};

// A comma-separated list of angles in degrees, each in [lo, hi]; bad input: one error line, exit 2.
std::vector<double> angles(const std::string& text, const char* what, double lo, double hi) {
  const std::vector<double> v = parse_list(text, what);
  if (v.empty()) throw UsageError(fmt::format("{}: empty list", what));
  for (double a : v)
    if (!(a >= lo && a <= hi))
      throw UsageError(fmt::format("{}: {} is not in [{}, {}] degrees", what, a, lo, hi));
  return v;
}

// The small default set of a study of the user's own maps (docs/study.md, "Relief materials and the user's
// own maps"): the terms the guide ships and the ones they are judged against, the main grid's directional
// lights and the lights near the surface, no ablations, no sweep, the Bias stopping rule.
void user_map_defaults(study::StudyConfig& c) {
  c.name = "user";
  c.terms = {"none", "ao", "directional-view", "diffuse-aware-alu+lut3d"};
  c.widened = c.normal_ablation = false;
  c.point_light = c.sphere_light = false;
  c.near_lights = true;
  c.sweep_views.clear();
  c.featured_lights = {"dir-el10-az0"};
  // The ground truth stops when the bias floors of the total and the diffuse are below 0.0025 (from 32
  // samples per pixel; the footprint RMSE keeps its floor in the rows): most cells stop at 32-64 samples
  // instead of the full rule's 512 (docs/study.md).
  c.gt_rule = study::StudyConfig::GtRule::Bias;
  c.gt_spp = 32;
  c.gt_max_spp = 256;
}

// --height FILE[,FILE…] --depth D[,D…] and --material DIR[,DIR…]; bad lists: one error line, exit 2.
std::vector<study::UserMaterial> user_materials(const StudyArgs& a) {
  std::vector<study::UserMaterial> out;
  const auto files = split_list(a.heights);
  if (files.empty() != a.depths.empty())
    throw UsageError(files.empty() ? "--depth needs --height"
                                   : "--height needs --depth (texels per unit height)");
  if (!files.empty()) {
    const std::vector<double> d = parse_list(a.depths, "--depth");
    if (d.size() != 1 && d.size() != files.size())
      throw UsageError(
          fmt::format("--depth: {} values for {} height map{} (give one per file, or one for all)", d.size(),
                      files.size(), files.size() == 1 ? "" : "s"));
    for (size_t i = 0; i < files.size(); ++i) {
      const double di = d.size() == 1 ? d[0] : d[i];
      if (files[i].empty()) throw UsageError("--height: empty file name in the list");
      if (!(di > 0 && di <= 1e4))
        throw UsageError(fmt::format("--depth: {} is not a depth in (0, 10000] texels", di));
      const std::filesystem::path p(files[i]);
      out.push_back({p.stem().string(), p, float(di)});
    }
  }
  for (const std::string& arg : a.folders)
    for (const std::string& f : split_list(arg)) {
      if (f.empty()) throw UsageError("--material: empty folder name in the list");
      out.push_back(study::user_material_from_folder(f));
    }
  return out;
}

// The study's configuration from the command line: the preset (area, quick or full), then each option over
// it.
study::StudyConfig study_config(const StudyArgs& a) {
  study::StudyConfig c = a.area    ? study::area_config(a.quick)
                         : a.quick ? study::quick_config()
                                   : study::full_config();
  if (!a.materials.empty()) c.materials = split_list(a.materials);
  c.user_materials = user_materials(a);
  if (!c.user_materials.empty() && a.materials.empty()) {
    c.materials.clear();
    if (!a.area && !a.quick) user_map_defaults(c);
  }
  if (a.sweep && a.no_sweep) throw UsageError("--sweep and --no-sweep: give one");
  if (a.near && a.no_near) throw UsageError("--near-lights and --no-near-lights: give one");
  if (a.sweep) {
    const study::StudyConfig full = study::full_config();
    c.sweep_views = full.sweep_views, c.sweep_view_azimuths = full.sweep_view_azimuths;
    c.sweep_elevations = full.sweep_elevations, c.sweep_azimuths = full.sweep_azimuths;
    c.sweep_scales = full.sweep_scales, c.sweep_terms = full.sweep_terms;
  }
  if (a.no_sweep) c.sweep_views.clear();
  if (a.no_ablations) c.widened = c.normal_ablation = false;
  if (a.near) c.near_lights = true;
  if (a.no_near) c.near_lights = false;
  if (!a.views.empty()) c.views = angles(a.views, "--views", 0, 89);
  if (!a.view_azimuths.empty()) c.view_azimuths = angles(a.view_azimuths, "--view-azimuths", -360, 360);
  if (!a.light_azimuths.empty()) c.azimuths = angles(a.light_azimuths, "--light-azimuths", -360, 360);
  if (!a.light_elevations.empty()) {
    c.elevations = angles(a.light_elevations, "--light-elevations", 0, 90);
    for (double e : c.elevations)
      if (!(e > 0 && e < 90)) throw UsageError(fmt::format("--light-elevations: {} is not in (0, 90)", e));
  }
  if (a.max_windows) c.max_windows = a.max_windows;
  if (!a.gt_rule.empty())
    c.gt_rule = a.gt_rule == "bias" ? study::StudyConfig::GtRule::Bias : study::StudyConfig::GtRule::Full;
  if (!a.shapes.empty()) c.shapes = split_list(a.shapes);
  if (!a.methods.empty()) {
    (a.area ? c.area_terms : c.terms) = split_list(a.methods);
    // The sweep renders the chosen methods it has, and the chosen compact forms of those (method@form).
    std::vector<std::string> sweep;
    for (const std::string& t : c.terms)
      if (std::find(c.sweep_terms.begin(), c.sweep_terms.end(), study::split_study_term(t).first) !=
          c.sweep_terms.end())
        sweep.push_back(t);
    c.sweep_terms = sweep;
    if (sweep.empty()) c.sweep_views.clear();
  }
  if (!a.area_ms.empty()) c.area_ms_modes = split_list(a.area_ms);
  if (!a.scales.empty()) {
    c.scales.clear();
    for (const std::string& k : split_list(a.scales)) {
      char* end = nullptr;
      const long v = std::strtol(k.c_str(), &end, 10);
      if (k.empty() || *end != '\0' || v < 1 || v > 4096)
        throw InputError(fmt::format("--scales: '{}' is not a scale in [1, 4096]", k));
      c.scales.push_back(int(v));
    }
    // The view sweep at the chosen scales too (e.g. --scales 1,2,4,8 --sweep: the sweep's k <= 8 cells).
    if (!c.sweep_views.empty()) c.sweep_scales = c.scales;
  }
  if (a.fine_size) c.fine_size = a.fine_size;
  if (a.image_size) c.image_size = a.image_size;
  if (a.gt_max_spp) c.gt_max_spp = a.gt_max_spp;
  c.material_cache = a.cache;
  c.directional_encoding = render::directional_encoding_from_name(a.encoding);
  return c;
}

void run_study_command(const StudyArgs& a) {
  const auto limit = thread_limit(a.threads);
  const study::StudyConfig c = study_config(a);
  const bool quiet = a.quiet;
  if (!a.cache.empty()) {
    // A warm cache is read, not written: inside the output folder, the folder's replacement would remove
    // it.
    const auto rel = std::filesystem::absolute(a.cache).lexically_normal().lexically_relative(
        std::filesystem::absolute(a.out).lexically_normal());
    if (!rel.empty() && *rel.begin() != "..")
      throw UsageError(
          "--material-cache must not lie inside --out (the output folder is replaced as a whole)");
  }
  io::OutputFolder folder(a.out);
  const auto res = study::run_study(c, a.out, [quiet](const std::string& line) {
    if (!quiet) std::cerr << line << std::endl;
  });
  const auto stale = folder.finish();
  int met = 0;
  for (const auto& gt : res["ground_truth"]) met += gt["floors_met"].get<bool>();
  print_json({{"out", a.out},
              {"study", c.name},
              {"rows", res["rows"].size()},
              {"ground_truth_configurations", res["ground_truth"].size()},
              {"floors_met", met},
              {"results", a.out + "/results.json"},
              {"html", a.out + "/study.html"},
              {"stale_removed", stale}});
}

void add_study(Groups& g) {
  auto a = std::make_shared<StudyArgs>();
  CLI::App* s = g.root->add_subcommand(
      "study",
      "Multiscale study: every micro-shadowing term on coarse texture sets against a ray-traced fine height "
      "field; writes DIR/results.json, results.csv, summary.md, study.html");
  add_out_dir_option(s, a->out);
  s->add_flag("--quick", a->quick,
              "Reduced study for make demo (one material, three lights, smaller images)");
  s->add_flag(
      "--area-lights", a->area,
      "Area-light section instead (docs/area-lights.md): sphere lights of 1-40 degrees angular radius, a "
      "disk and a rect; micro-shadowing per sample, at the representative point, integrated; also writes "
      "DIR/area_summary.md");
  s->add_option(
      "--area-ms", a->area_ms,
      "With --area-lights: comma-separated modes (sampled, representative, integrated; default all)");
  s->add_option("--materials", a->materials, "Comma-separated material kinds (default: the study's list)");
  s->add_option(
      "--height", a->heights,
      "The user's height maps as materials: comma-separated 16-bit PNG or EXR files (grey, values in [0,1], "
      "square; each named by its file's stem in the results; needs --depth). Without --materials, only the "
      "user's maps are studied");
  s->add_option("--depth", a->depths,
                "With --height: depth of the full [0,1] range in texels, one per file or one for all");
  s->add_option(
      "--material", a->folders,
      "A gen-material folder (height.png + material.json's height_texels) as a material named after the "
      "folder; repeatable or comma-separated");
  s->add_option("--methods", a->methods,
                "Comma-separated micro-shadowing methods (`microshadow methods`; default: the methods "
                "marked for the study; with --area-lights, the area section's terms). A method that reads "
                "the directional channels may name a compact form, METHOD@FORM, FORM = pca<K> (8-bit), "
                "pca<K>x16, pca<K>f, or unorm8 / bc4 per channel (docs/directional-occlusion.md, \"Compact "
                "forms\"), e.g. directional-view@pca8");
  s->add_option("--directional-encoding", a->encoding,
                "Storage of the directional channels on the coarse sets: float, unorm8 (gen-material's 8-bit "
                "mips) or bc4 (4 bits per channel); each channel between the fine level's range")
      ->capture_default_str();
  s->add_option(
      "--scales", a->scales,
      "Comma-separated scales k (default: the study's list); the view sweep, when on, runs at these scales "
      "too");
  s->add_option(
      "--views", a->views,
      "Comma-separated view angles, degrees off the normal in [0, 89] (default 30; the full study's sweep "
      "adds 60, 75, 85)");
  s->add_option(
      "--view-azimuths", a->view_azimuths,
      "Comma-separated azimuths of the direction to the camera, degrees from +u towards +v (default 270: "
      "the camera at -v looking along +v)");
  s->add_option(
      "--light-azimuths", a->light_azimuths,
      "Comma-separated azimuths of the directional lights, degrees from +u towards +v (default 0,90; the "
      "full study's sweep adds 45, 135, 180)");
  s->add_option("--light-elevations", a->light_elevations,
                "Comma-separated elevations of the directional lights above the plane, degrees in (0, 90) "
                "(default 5,10,25,45,70)");
  s->add_flag("--sweep", a->sweep,
              "Add the full study's view sweep (views 30-85, light azimuths 0-180, k = 1-64, the shipped "
              "terms) to --quick or a study of your own maps");
  s->add_flag("--no-sweep", a->no_sweep, "Leave the view sweep out of the full study");
  s->add_flag("--no-ablations", a->no_ablations,
              "Render each term once: without the widened-roughness and smooth-normal variants (their rows "
              "are then absent)");
  s->add_flag("--near-lights", a->near, "Add the point and sphere lights near the surface (full study: on)");
  s->add_flag("--no-near-lights", a->no_near, "Leave the lights near the surface out");
  s->add_option("--max-windows", a->max_windows,
                "Windows per side at most where the view covers a quarter of the texture or less (default "
                "16: one footprint each at 64 pixels)")
      ->check(CLI::Range(1, 16));
  s->add_option("--shapes", a->shapes, "Comma-separated shapes: plane, cylinder (default: the study's list)");
  s->add_option("--fine-size", a->fine_size, "Fine height field size in texels (default 2048, quick 1024)")
      ->check(CLI::Range(64, 8192));
  s->add_option("--image-size", a->image_size, "Image pixels per side at every scale")
      ->check(CLI::Range(8, 4096));
  s->add_option("--gt-max-spp", a->gt_max_spp, "Cap on ground-truth samples per pixel")
      ->check(CLI::Range(8, 1 << 20));
  s->add_option(
       "--gt-rule", a->gt_rule,
       "The ground truth's stopping rule: full (bias and footprint-RMSE floors of every component; the "
       "default) or bias (the bias floors of the total and the diffuse; the default for your own maps)")
      ->check(CLI::IsMember({"full", "bias"}));
  s->add_option(
      "--material-cache", a->cache,
      "Cache the fine texture sets in DIR (float NPY) and reuse them on later runs (keyed by material, "
      "size, seed or height-map hash and depth, bake settings and bake version; an entry whose maps or "
      "depth do not match its key or hold non-finite values is baked again)");
  add_threads_option(s, a->threads);
  add_quiet_flag(s, a->quiet);
  s->callback([a] { run_study_command(*a); });
}

}  // namespace

MSH_CLI_REGISTER(add_study, 95);

}  // namespace msh::cli
