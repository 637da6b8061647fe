#include "common.h"

#include <fmt/format.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <vector>

namespace msh::cli {

std::vector<double> parse_list(const std::string& text, const std::string& what) {
  std::vector<double> v;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    while (end && *end == ' ') ++end;
    if (item.empty() || end == item.c_str() || *end != '\0' || !std::isfinite(x))
      throw UsageError(
          fmt::format("{} must be a comma-separated list of finite numbers, got '{}'", what, text));
    v.push_back(x);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return v;
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> v;
  std::string rest = text;
  while (!rest.empty()) {
    const auto comma = rest.find(',');
    v.push_back(rest.substr(0, comma));
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
  }
  return v;
}

Vec3d parse_vec3(const std::string& text, const std::string& what) {
  const std::vector<double> v = parse_list(text, what);
  if (v.size() != 3) throw UsageError(fmt::format("{} must be three numbers X,Y,Z, got '{}'", what, text));
  return {v[0], v[1], v[2]};
}

CLI::Option* add_threads_option(CLI::App* command, int& threads) {
  return command
      ->add_option("--threads", threads, "Worker threads (0 = all cores); the output does not depend on it")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
}

std::unique_ptr<tbb::global_control> thread_limit(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               std::size_t(threads));
}

void print_json(const nlohmann::json& j) { std::cout << j.dump() << std::endl; }

std::string two_stage_fit_id() {
  const occlusion::MicroShadowingMethodInfo& m = *occlusion::find_micro_shadowing_method("generic-vndf-alu");
  for (const occlusion::MicroShadowingGlsl& g : m.glsl)
    if (g.two_stage) return m.form_id(g);
  throw std::logic_error("the registry's generic-vndf-alu has no two-stage form");
}

const CLI::Validator Finite(
    [](std::string& s) -> std::string {
      char* end = nullptr;
      const double x = std::strtod(s.c_str(), &end);
      if (end == s.c_str() || !std::isfinite(x)) return "must be a finite number, got '" + s + "'";
      return {};
    },
    "FINITE");

}  // namespace msh::cli
