// The three.js browser tests' probe statistics (test_three_browser, test_three_directional_browser): per light
// and per method lobe, the largest |three.js − C++| over the lit probe pixels, float32 and 8-bit, printed as a
// table and written as JSON; and the two helpers both read their probe scenes with.
#pragma once

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <microshadow/math/vec.h>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace msh::test {

// A 3-vector of the page's results (a JSON array of three numbers).
inline Vec3d vec3(const nlohmann::json& a) {
  return Vec3d(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
}

// The direction to a light of a probe scene (view space, the page's `lights` entry of that type) from a point
// P: a directional light's direction, else towards its position.
inline Vec3d light_dir(const nlohmann::json& lights, const std::string& type, const Vec3d& P) {
  return type == "directional" ? normalize(vec3(lights[type]["direction"]))
                               : normalize(vec3(lights[type]["position"]) - P);
}

struct ProbeStat {
  double max_float = 0, max_8bit = 0;
  int n = 0;
  void add(double err_float, double err_8bit) {
    max_float = std::max(max_float, err_float);
    max_8bit = std::max(max_8bit, err_8bit);
    ++n;
  }
};
using ProbeStats = std::map<std::string, std::map<std::string, ProbeStat>>;  // [light][what]

// The table of stats: a row per `what` of the first light of order (its label padded to `width`), a cell per
// light of order, printed by cell(light, stat), which returns the cell's JSON; the JSON table
// {what: {light: cell}} is written to `file`.
template <class Cell>
void print_probe_table(ProbeStats& stats, const std::vector<std::string>& order, int width, Cell&& cell,
                       const std::filesystem::path& file) {
  nlohmann::json table;
  for (const auto& [what, unused] : stats[order[0]]) {
    std::printf("  %-*s", width, what.c_str());
    for (const auto& light : order) table[what][light] = cell(light, stats[light][what]);
    std::printf("\n");
  }
  std::ofstream(file) << table.dump(1) << "\n";
}

}  // namespace msh::test
