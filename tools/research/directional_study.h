// Research harness: the directional micro-occlusion representations (cone terms, least-squares fits of
// several bases and weights, horizon moments, residual fits) measured against the exact texture-space
// diffuse transport of the procedural height fields. It produced the comparison in
// docs/directional-occlusion.md and docs/directional-occlusion-table.md that chose the shipped 9-channel fit;
// it is not part of the library (run it with `microshadow_research directional`).
#pragma once

#include <string>
#include <vector>

namespace msh::research {

struct DirectionalStudyOptions {
  std::vector<std::string> kinds = {"plaster", "bark", "gravel"};
  int size = 512;
  std::vector<int> scales = {1, 4, 16};
  std::vector<float> elevations_deg = {5, 10, 25, 45, 70};
  std::vector<float> azimuths_deg = {0, 90};
  int bake_azimuths = 32;  // azimuths of every bake (offset half a step: lights are off-knot)
  std::vector<float> bake_distances = {0};  // texels, 0 = unlimited; < 0 = the study default (8 % of size)
  bool quantize8 = false;                   // also rows with the channels stored as 8-bit UNORM (and mips)
};

struct DirectionalStudyRow {
  std::string kind, representation;
  float bake_distance = 0;  // texels, 0 = unlimited
  int k = 1;
  float elevation_deg = 0, azimuth_deg = 0;
  double bias = 0;            // Σ T̃ / Σ T over the texture (T = exact, unlimited)
  double rmse_footprint = 0;  // RMSE of T̃ − T over 4 × 4 coarse-texel blocks / mean T
  int bytes = 0;              // per texel at 8 bits per channel
};

std::vector<DirectionalStudyRow> directional_study(const DirectionalStudyOptions& opt);

// Markdown tables of the rows: per representation × material × k, the bias per light and its mean/max
// |bias − 1| and mean footprint RMSE; and the overall summary per representation.
std::string directional_study_markdown(const std::vector<DirectionalStudyRow>& rows);

}  // namespace msh::research
