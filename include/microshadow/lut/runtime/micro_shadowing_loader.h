// Loading a baked micro-shadowing LUT from a file (any format io::read_volume reads) and the table's
// metadata.
//
// The layout ("seed" or "cone"), roughness per channel or slab parameters and the harmonic count travel in a
// JSON sidecar "<file>.json" written by `microshadow bake micro-shadowing` (docs/lut.md). A cone-layout
// table needs its sidecar. Without a sidecar a table is read as the seed layout with the documented
// defaults: roughness 0.1, 0.4, 0.7, 1.0 (Zurita 2026) for a 4-channel table, no harmonics. Explicit values
// override both (seed layout only).
#pragma once

#include <microshadow/io/texture.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
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
  LutLayout layout = LutLayout::Seed;
  std::vector<double> roughness;  // seed layout: roughness per channel
  int harmonics = 0;
  int n_rough = 0;        // cone layout: roughness slabs
  ConeLayoutParams cone;  // cone layout: warps
  MicroShadowingLutView view() const {
    return layout == LutLayout::Cone ? make_cone_view(volume, n_rough, harmonics, cone)
                                     : make_view(volume, roughness, harmonics);
  }
};

// The shortest decimal that reads back as the same float (for JSON: 0.1f → 0.1).
double short_float(float f);

// "seed" / "cone", and back (throws InputError naming the accepted names).
const char* layout_name(LutLayout l);
LutLayout layout_from_name(const std::string& name);

// Sidecar path of a table file: "<file>.json".
std::filesystem::path sidecar_path(const std::filesystem::path& table);

// JSON text of the sidecar for a table baked with `o` (roughness, harmonics, sizes, samples, seed, ...).
std::string sidecar_json(const BakeOptions& o);

// Reads `path` (io::read_volume) and its sidecar if present. Throws msh::InputError on an unreadable or
// inconsistent file (unknown layout, sizes in the sidecar ≠ the file's, channel count ≠ roughness count,
// depth not a multiple of harmonics + 1 or of the roughness slabs).
MicroShadowingLut load_micro_shadowing_lut(const std::filesystem::path& path,
                                           std::optional<std::vector<double>> roughness = std::nullopt,
                                           std::optional<int> harmonics = std::nullopt);

// The default table of a layout (default_bake_options; two_d: the N·V = 1 slice only), azimuth-aware when
// harmonics > 0, baked on first use and cached for the process (thread-safe). For `eval micro-shadowing
// --method lut3d|lut2d` and the renderer.
std::shared_ptr<const MicroShadowingLut> default_micro_shadowing_lut(bool two_d, int harmonics = 0,
                                                                     LutLayout layout = LutLayout::Cone);

}  // namespace msh::lut
