#include "common.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <vector>

namespace msh::cli {

Vec3d parse_vec3(const std::string& text, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    while (end && *end == ' ') ++end;
    if (item.empty() || end == item.c_str() || (end && *end != '\0') || !std::isfinite(x))
      throw UsageError(fmt::format("{} must be three finite numbers X,Y,Z, got '{}'", what, text));
    v.push_back(x);
  }
  if (v.size() != 3) throw UsageError(fmt::format("{} must be three numbers X,Y,Z, got '{}'", what, text));
  return {v[0], v[1], v[2]};
}

void require_range(double v, double lo, double hi, const std::string& what) {
  if (!(v >= lo && v <= hi)) throw UsageError(fmt::format("{} must be in [{}, {}], got {}", what, lo, hi, v));
}

void print_json(const nlohmann::json& j) { std::cout << j.dump() << std::endl; }

const CLI::Validator Finite(
    [](std::string& s) -> std::string {
      char* end = nullptr;
      const double x = std::strtod(s.c_str(), &end);
      if (end == s.c_str() || !std::isfinite(x)) return "must be a finite number, got '" + s + "'";
      return {};
    },
    "FINITE");

}  // namespace msh::cli
