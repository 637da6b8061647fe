// `microshadow study [--quick] --out DIR`: the multiscale comparison of every micro-shadowing term against a
// ray-traced fine height field (docs/study.md).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/study/study.h>

#include <cstdlib>
#include <iostream>
#include <memory>

#include "common.h"

namespace msh::cli {
namespace {

struct StudyArgs {
  std::string out, materials, cache, shapes, area_ms, scales, methods;
  bool quick = false, quiet = false, area = false;
  int threads = 0, fine_size = 0, image_size = 0, gt_max_spp = 0;
};

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
  s->add_option("--methods", a->methods,
                "Comma-separated micro-shadowing methods (`microshadow methods`; default: the methods marked "
                "for the study; with --area-lights, the area section's terms)");
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
