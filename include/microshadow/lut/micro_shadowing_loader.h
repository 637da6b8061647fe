// Loading a baked micro-shadowing LUT from a file (any format io::read_volume reads) and the table's
// metadata.
//
// Roughness per channel and harmonic count travel in a JSON sidecar "<file>.json" written by
// `microshadow bake micro-shadowing` (docs/lut.md). Without a sidecar the documented defaults apply:
// roughness 0.1, 0.4, 0.7, 1.0 (REFERENCE.md §1) for a 4-channel table, no harmonics. Explicit values
// override both.
#pragma once

#include <microshadow/io/texture.h>
#include <microshadow/lut/micro_shadowing_baker.h>
#include <microshadow/lut/micro_shadowing_lut.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace msh::lut {

// A table with its metadata; view() is valid as long as the object lives (and is not moved from).
struct MicroShadowingLut {
  io::Volume volume;
  std::vector<double> roughness;
  int harmonics = 0;
  MicroShadowingLutView view() const { return make_view(volume, roughness, harmonics); }
};

// Sidecar path of a table file: "<file>.json".
std::filesystem::path sidecar_path(const std::filesystem::path& table);

// JSON text of the sidecar for a table baked with `o` (roughness, harmonics, sizes, samples, seed, ...).
std::string sidecar_json(const BakeOptions& o);

// Reads `path` (io::read_volume) and its sidecar if present. Throws msh::InputError on an unreadable or
// inconsistent file (channel count ≠ roughness count, depth not a multiple of harmonics + 1).
MicroShadowingLut load_micro_shadowing_lut(const std::filesystem::path& path,
                                           std::optional<std::vector<double>> roughness = std::nullopt,
                                           std::optional<int> harmonics = std::nullopt);

// The default table (64³ RGBA, or the 64² 2D LUT), azimuth-aware when harmonics > 0, baked on first use and
// cached for the process (thread-safe). For `eval micro-shadowing --method lut3d|lut2d`.
std::shared_ptr<const MicroShadowingLut> default_micro_shadowing_lut(bool two_d, int harmonics = 0);

}  // namespace msh::lut
