// Include expansion of the shader library files (see shader_source.h).
#include "shader_source.h"

#include <fmt/format.h>
#include <microshadow/io/error.h>

#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace msh::view {
namespace {

std::string expand(const fs::path& file, int depth) {
  if (depth > 16)
    throw InputError(fmt::format("shader includes nested deeper than 16 at '{}' (a cycle?)", file.string()));
  require_regular_file(file, "shader file ");
  std::ifstream f(file, std::ios::binary);
  if (!f) throw InputError(fmt::format("cannot read the shader file '{}'", file.string()));
  std::string out, line;
  while (std::getline(f, line)) {
    const std::size_t p = line.find_first_not_of(" \t");
    if (p != std::string::npos && line.compare(p, 8, "#include") == 0) {
      const std::size_t a = line.find('"', p + 8), b = a == std::string::npos ? a : line.find('"', a + 1);
      if (b == std::string::npos)
        throw InputError(fmt::format("'{}': an #include without a \"quoted\" path: {}", file.string(), line));
      out += expand(file.parent_path() / line.substr(a + 1, b - a - 1), depth + 1);
      continue;
    }
    out += line;
    out += '\n';
  }
  return out;
}

}  // namespace

std::string expand_shader_includes(const fs::path& file) { return expand(file, 0); }

}  // namespace msh::view
