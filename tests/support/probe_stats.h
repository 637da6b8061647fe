// The three.js browser tests' probe statistics (test_three_browser, test_three_directional_browser): per light
// and per method lobe, the largest |three.js − C++| over the lit probe pixels, float32 and 8-bit, printed as a
// table and written as JSON.
#pragma once

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace msh::test {

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
