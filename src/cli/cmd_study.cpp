// `microshadow study [--quick] --out DIR`: the multiscale comparison of every micro-shadowing term against a
// ray-traced fine height field (docs/study.md).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/study/study.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

#include "common.h"

namespace msh::cli {
namespace {

struct StudyArgs {
  std::string out, materials, cache, shapes, area_ms, scales, methods, heights, depths, encoding = "float";
  std::vector<std::string> folders;
  bool quick = false, quiet = false, area = false;
  int threads = 0, fine_size = 0, image_size = 0, gt_max_spp = 0;
};

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

void add_study(Groups& g) {
  auto a = std::make_shared<StudyArgs>();
  CLI::App* s = g.root->add_subcommand(
      "study",
      "Multiscale study: every micro-shadowing term on coarse texture sets against a ray-traced fine height "
      "field; writes DIR/results.json, results.csv, summary.md, study.html");
  s->add_option("--out", a->out, "Output directory (created)")->required();
  s->add_flag("--quick", a->quick,
              "Reduced study for make demo (one material, three lights, smaller images)");
  s->add_flag(
      "--area-lights", a->area,
      "Area-light section instead (docs/area-lights.md): sphere lights of 1-40 degrees angular "
      "radius, a disk and a rect; micro-shadowing per sample, at the representative point, integrated; "
      "also writes DIR/area_summary.md");
  s->add_option(
      "--area-ms", a->area_ms,
      "With --area-lights: comma-separated modes (sampled, representative, integrated; default all)");
  s->add_option("--materials", a->materials, "Comma-separated material kinds (default: the study's list)");
  s->add_option(
      "--height", a->heights,
      "The user's height maps as materials: comma-separated 16-bit PNG or EXR files (grey, values in "
      "[0,1], square; each named by its file's stem in the results; needs --depth). Without "
      "--materials, only the user's maps are studied");
  s->add_option("--depth", a->depths,
                "With --height: depth of the full [0,1] range in texels, one per file or one for all");
  s->add_option(
      "--material", a->folders,
      "A gen-material folder (height.png + material.json's height_texels) as a material named after "
      "the folder; repeatable or comma-separated");
  s->add_option("--methods", a->methods,
                "Comma-separated micro-shadowing methods (`microshadow methods`; default: the methods marked "
                "for the study; with --area-lights, the area section's terms)");
  s->add_option("--directional-encoding", a->encoding,
                "Storage of the directional channels on the coarse sets: float, unorm8 (gen-material's 8-bit "
                "mips) or bc4 (4 bits per channel); each channel between the fine level's range")
      ->capture_default_str();
  s->add_option("--scales", a->scales, "Comma-separated scales k (default: the study's list)");
  s->add_option("--shapes", a->shapes, "Comma-separated shapes: plane, cylinder (default: the study's list)");
  s->add_option("--fine-size", a->fine_size, "Fine height field size in texels (default 2048, quick 1024)")
      ->check(CLI::Range(64, 8192));
  s->add_option("--image-size", a->image_size, "Image pixels per side at every scale")
      ->check(CLI::Range(8, 4096));
  s->add_option("--gt-max-spp", a->gt_max_spp, "Cap on ground-truth samples per pixel")
      ->check(CLI::Range(8, 1 << 20));
  s->add_option("--material-cache", a->cache,
                "Cache the fine texture sets in DIR (float NPY) and reuse them on later runs");
  s->add_option("--threads", a->threads, "Worker threads (0 = all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024));
  s->add_flag("--quiet", a->quiet, "No progress on stderr");
  s->callback([a] {
    const auto limit = thread_limit(a->threads);
    study::StudyConfig c = a->area    ? study::area_config(a->quick)
                           : a->quick ? study::quick_config()
                                      : study::full_config();
    if (!a->materials.empty()) c.materials = split_list(a->materials);
    c.user_materials = user_materials(*a);
    if (!c.user_materials.empty() && a->materials.empty()) c.materials.clear();
    if (!a->shapes.empty()) c.shapes = split_list(a->shapes);
    if (!a->methods.empty()) (a->area ? c.area_terms : c.terms) = split_list(a->methods);
    if (!a->area_ms.empty()) c.area_ms_modes = split_list(a->area_ms);
    if (!a->scales.empty()) {
      c.scales.clear();
      for (const std::string& k : split_list(a->scales)) {
        char* end = nullptr;
        const long v = std::strtol(k.c_str(), &end, 10);
        if (k.empty() || *end != '\0' || v < 1 || v > 4096)
          throw InputError(fmt::format("--scales: '{}' is not a scale in [1, 4096]", k));
        c.scales.push_back(int(v));
      }
    }
    if (a->fine_size) c.fine_size = a->fine_size;
    if (a->image_size) c.image_size = a->image_size;
    if (a->gt_max_spp) c.gt_max_spp = a->gt_max_spp;
    c.material_cache = a->cache;
    c.directional_encoding = render::directional_encoding_from_name(a->encoding);
    const bool quiet = a->quiet;
    const auto res = study::run_study(c, a->out, [quiet](const std::string& line) {
      if (!quiet) std::cerr << line << std::endl;
    });
    int met = 0;
    for (const auto& gt : res["ground_truth"]) met += gt["floors_met"].get<bool>();
    print_json({{"out", a->out},
                {"study", c.name},
                {"rows", res["rows"].size()},
                {"ground_truth_configurations", res["ground_truth"].size()},
                {"floors_met", met},
                {"results", a->out + "/results.json"},
                {"html", a->out + "/study.html"}});
  });
}

}  // namespace

MSH_CLI_REGISTER(add_study, 95);

}  // namespace msh::cli
