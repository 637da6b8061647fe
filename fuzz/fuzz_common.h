// Shared by the libFuzzer targets: the readers take a path, so each input is written to a per-process scratch
// file (in RAM under /dev/shm when it exists) and read back through the same entry point a user calls.
#pragma once

#include <microshadow/io/texture.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace msh::fuzz {

// A scratch path "<dir>/msh_fuzz_<pid>_<tag><ext>", stable for the process.
inline std::filesystem::path scratch_path(const std::string& tag, const std::string& ext) {
  static const std::filesystem::path dir = std::filesystem::exists("/dev/shm")
                                               ? std::filesystem::path("/dev/shm")
                                               : std::filesystem::temp_directory_path();
  return dir / ("msh_fuzz_" + std::to_string(::getpid()) + "_" + tag + ext);
}

inline void write_bytes(const std::filesystem::path& p, const std::uint8_t* data, std::size_t size) {
  std::ofstream f(p, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

// The input written to this process's scratch file "…_<tag><ext>" (scratch_path): its path, for the reader.
inline std::filesystem::path input_file(const std::string& tag, const std::string& ext,
                                        const std::uint8_t* data, std::size_t size) {
  const std::filesystem::path p = scratch_path(tag, ext);
  write_bytes(p, data, size);
  return p;
}

// The readers' contract for a returned volume (docs/formats.md): positive sizes, as many values as the sizes
// say, every one finite. Anything else aborts (a finding).
inline void check_volume(const io::Volume& v) {
  if (v.width < 1 || v.height < 1 || v.depth < 1 || v.channels < 1) std::abort();
  if (v.data.size() != v.texel_count() * std::size_t(v.channels)) std::abort();
  for (float x : v.data)
    if (!std::isfinite(x)) std::abort();
}

}  // namespace msh::fuzz
