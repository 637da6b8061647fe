// microshadow_research: the research harnesses, apart from the product CLI (docs/architecture.md).
//   microshadow_research directional [--kinds plaster,bark,gravel] [--size 512] [--scales 1,4,16]
//       [--elevations 5,10,25,45,70] [--azimuths 0,90] [--bake-azimuths 32] [--distances 0,-1] [--quantize]
//       [--threads N] [--out FILE.md] [--json]
// measures every directional representation against the exact texture-space diffuse transport
// (directional_study.h, docs/directional-occlusion.md).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/run_app.h"
#include "directional_study.h"

namespace msh::research {
// A row as JSON: one key per field, named as the field.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(DirectionalStudyRow, kind, representation, bake_distance, k, elevation_deg,
                                   azimuth_deg, bias, rmse_footprint, bytes)
}  // namespace msh::research

namespace {

struct StudyArgs {
  std::vector<std::string> kinds = {"plaster", "bark", "gravel"};
  std::vector<int> scales = {1, 4, 16};
  std::vector<float> elevations = {5, 10, 25, 45, 70}, azimuths = {0, 90}, distances = {0};
  std::string out;
  int size = 512, bake_azimuths = 32, threads = 0;
  bool quantize = false, json = false;
};

void run_study(const StudyArgs& a) {
  std::unique_ptr<tbb::global_control> limit;
  if (a.threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  std::size_t(a.threads));
  msh::research::DirectionalStudyOptions o;
  o.kinds = a.kinds;
  o.size = a.size;
  for (int k : a.scales)
    if (a.size % k != 0) throw msh::InputError(fmt::format("--scales: {} must divide --size {}", k, a.size));
  o.scales = a.scales;
  o.elevations_deg = a.elevations;
  o.azimuths_deg = a.azimuths;
  o.bake_distances = a.distances;
  o.bake_azimuths = a.bake_azimuths;
  o.quantize8 = a.quantize;
  const auto rows = msh::research::directional_study(o);
  if (a.json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& r : rows) j.push_back(r);
    std::cout << j.dump() << std::endl;
  }
  const std::string md = msh::research::directional_study_markdown(rows);
  if (!a.out.empty()) msh::io::write_file_atomic(a.out, md);
  if (!a.json) std::cout << md;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"microshadow research harnesses (not part of the library; docs/architecture.md)"};
  app.require_subcommand(1);
  StudyArgs sa;
  CLI::App* s = app.add_subcommand(
      "directional",
      "Directional micro-occlusion representations against the exact texture-space diffuse transport of "
      "the procedural height fields (docs/directional-occlusion.md)");
  s->add_option("--kinds", sa.kinds, "Materials")->delimiter(',')->capture_default_str();
  s->add_option("--size", sa.size, "Fine texels per side")->check(CLI::Range(8, 8192))->capture_default_str();
  s->add_option("--scales", sa.scales, "Coarse scales k")
      ->delimiter(',')
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  s->add_option("--elevations", sa.elevations, "Light elevations, degrees")
      ->delimiter(',')
      ->check(CLI::Range(0.5f, 89.5f))
      ->capture_default_str();
  s->add_option("--azimuths", sa.azimuths, "Light azimuths from +u towards +v, degrees")
      ->delimiter(',')
      ->capture_default_str();
  s->add_option("--bake-azimuths", sa.bake_azimuths, "Azimuths of the bakes")
      ->check(CLI::Range(5, 4096))
      ->capture_default_str();
  s->add_option("--distances", sa.distances, "Bake ray lengths, texels (0 = unlimited, -1 = 8 % of size)")
      ->delimiter(',')
      ->capture_default_str();
  s->add_flag("--quantize", sa.quantize, "Also rows with 8-bit UNORM channels (fine level and mips)");
  s->add_option("--threads", sa.threads, "Worker threads (0 = all)")->check(CLI::NonNegativeNumber);
  s->add_option("--out", sa.out, "Also write the Markdown tables here");
  s->add_flag("--json", sa.json, "Print every row as JSON instead of the tables");
  s->callback([&] { run_study(sa); });
  return msh::cli::parse_and_run(app, argc, argv, "microshadow_research");
}
