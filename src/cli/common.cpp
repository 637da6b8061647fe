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

CLI::Option* add_quiet_flag(CLI::App* command, bool& quiet) {
  return command->add_flag("--quiet", quiet, "No progress on stderr");
}

CLI::Option* add_json_flag(CLI::App* command, bool& json, const std::string& what) {
  return command->add_flag("--json", json, what);
}

CLI::Option* add_out_dir_option(CLI::App* command, std::string& dir) {
  return command->add_option("--out", dir, "Output directory (created with its parents if missing)")
      ->required();
}

void add_table_output(CLI::App* command, TableOutput& t) {
  command
      ->add_option("--out", t.out,
                   "Output file: .dds .ktx2 .exr .npy .h (format by extension unless --format)")
      ->required();
  command->add_option("--format", t.format, "dds, ktx2, exr, npy or h (overrides the extension)");
}

io::FileFormat table_output_format(const TableOutput& t, const std::string& hint) {
  const io::FileFormat ff =
      t.format.empty() ? io::file_format_from_path(t.out) : io::file_format_from_name(t.format);
  if (ff == io::FileFormat::Png)
    throw UsageError("a table cannot be written as PNG (use dds, ktx2, exr, npy or h" + hint + ")");
  require_parent_dir(t.out, "--out");
  return ff;
}

std::filesystem::path make_out_dir(const std::string& dir, const std::string& option) {
  namespace fs = std::filesystem;
  const fs::path p(dir);
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec || !fs::is_directory(p))
    throw UsageError(fmt::format("{}: cannot create directory '{}'", option, dir));
  return p;
}

void require_parent_dir(const std::filesystem::path& file, const std::string& option) {
  if (file.has_parent_path() && !std::filesystem::is_directory(file.parent_path()))
    throw UsageError(fmt::format("{}: directory '{}' does not exist", option, file.parent_path().string()));
}

std::function<void(double)> progress_in_tenths(const std::string& what, bool quiet) {
  if (quiet) return {};
  return [what, last = 0](double f) mutable {
    const int step = int(f * 10.0 + 1e-9);
    if (step <= last) return;  // workers may report out of order: never go back
    last = step;
    std::cerr << fmt::format("microshadow: {}: {:3d}%\n", what, step * 10);
  };
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
