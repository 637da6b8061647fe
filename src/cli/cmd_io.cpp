// CLI for texture/image I/O (include/microshadow/io/texture.h):
//   microshadow convert IN OUT [--format dds|ktx2|exr|npy|h|png] [--pixel-format rgba16f] [--symbol lut]
// Reads IN (DDS, KTX2, EXR, NPY, PNG), writes OUT atomically, prints one JSON line (dimensions, value range).
#include <fmt/format.h>
#include <microshadow/io/texture.h>

#include <algorithm>
#include <memory>
#include <string>

#include "common.h"

namespace msh::cli {
namespace {

struct ConvertOptions {
  std::string in, out, format, pixel_format, symbol = "lut";
};

// The default pixel format: half floats with the volume's channel count (8-bit for 8-bit PNG sources).
io::PixelFormat default_pixel_format(int channels, bool unorm) {
  using PF = io::PixelFormat;
  switch (channels) {
    case 1:
      return unorm ? PF::R8Unorm : PF::R16Float;
    case 2:
      return unorm ? PF::RG8Unorm : PF::RG16Float;
    case 4:
      return unorm ? PF::RGBA8Unorm : PF::RGBA16Float;
    default:
      return PF::RGBA16Float;  // DDS/KTX2 will report the mismatch; other formats ignore it
  }
}

void run_convert(const ConvertOptions& o) {
  const io::FileFormat ff =
      o.format.empty() ? io::file_format_from_path(o.out) : io::file_format_from_name(o.format);
  const io::Volume v = io::read_volume(o.in);
  const bool png_in = io::file_format_from_path(o.in) == io::FileFormat::Png;
  const io::PixelFormat pf = o.pixel_format.empty() ? default_pixel_format(v.channels, png_in)
                                                    : io::pixel_format_from_name(o.pixel_format);
  if ((ff == io::FileFormat::Dds || ff == io::FileFormat::Ktx2) &&
      io::pixel_format_channels(pf) != v.channels)
    throw UsageError(fmt::format(
        "'{}' has {} channels but pixel format {} has {}{}", o.in, v.channels, io::pixel_format_name(pf),
        io::pixel_format_channels(pf),
        v.channels == 3 ? " (DDS/KTX2 have no 3-channel formats here: use exr, npy or png)" : ""));
  io::write_volume(o.out, v, ff, pf, o.symbol);
  const auto [lo, hi] = std::minmax_element(v.data.begin(), v.data.end());
  print_json({{"in", o.in},
              {"out", o.out},
              {"width", v.width},
              {"height", v.height},
              {"depth", v.depth},
              {"channels", v.channels},
              {"pixel_format", io::pixel_format_name(pf)},
              {"min", v.data.empty() ? 0.0 : double(*lo)},
              {"max", v.data.empty() ? 0.0 : double(*hi)}});
}

void add_io(Groups& g) {
  const auto [c, o] = add_command<ConvertOptions>(
      g.root, "convert",
      "Convert a texture/volume between DDS, KTX2, EXR, NPY, PNG and C header (docs/formats.md)",
      run_convert);
  c->add_option("IN", o->in, "Input file (.dds .ktx2 .exr .npy .png)")->required();
  c->add_option("OUT", o->out, "Output file; the format follows the extension unless --format is given")
      ->required();
  c->add_option("--format", o->format, "Output format: dds, ktx2, exr, npy, h, png");
  c->add_option(
      "--pixel-format", o->pixel_format,
      "DDS/KTX2 texel format: rgba8 rgba16f rgba32f rg16f rg32f r16f r32f r8 rg8 (default: 16-bit float "
      "with the input's channel count; 8-bit for PNG input). EXR: *16f = half, else float. PNG: *8 = 8 "
      "bits, else 16");
  c->add_option("--symbol", o->symbol, "C identifier of the array in a C header")->capture_default_str();
}

}  // namespace

MSH_CLI_REGISTER(add_io, 80);

}  // namespace msh::cli
