// Format/pixel-format names, validation, texel packing and the write_volume/read_volume dispatch.
#include <Imath/half.h>
#include <fmt/format.h>
#include <microshadow/io/bc4.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "texture_internal.h"

namespace msh::io {
namespace fs = std::filesystem;

namespace {
std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}
}  // namespace

FileFormat file_format_from_path(const fs::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".dds") return FileFormat::Dds;
  if (ext == ".ktx2") return FileFormat::Ktx2;
  if (ext == ".exr") return FileFormat::Exr;
  if (ext == ".npy") return FileFormat::Npy;
  if (ext == ".h" || ext == ".hpp") return FileFormat::CHeader;
  if (ext == ".png") return FileFormat::Png;
  throw InputError(fmt::format(
      "'{}': unknown file extension '{}' (expected .dds .ktx2 .exr .npy .h .hpp .png)", path.string(), ext));
}

FileFormat file_format_from_name(const std::string& name) {
  const std::string n = lower(name);
  if (n == "dds") return FileFormat::Dds;
  if (n == "ktx2") return FileFormat::Ktx2;
  if (n == "exr") return FileFormat::Exr;
  if (n == "npy") return FileFormat::Npy;
  if (n == "h" || n == "hpp" || n == "header") return FileFormat::CHeader;
  if (n == "png") return FileFormat::Png;
  throw InputError(fmt::format("unknown file format '{}' (expected dds, ktx2, exr, npy, h, png)", name));
}

PixelFormat pixel_format_from_name(const std::string& name) {
  const std::string n = lower(name);
  for (const codecs::PixelFormatEntry& p : codecs::kPixelFormats)
    if (n == p.name) return p.pf;
  throw InputError(fmt::format(
      "unknown pixel format '{}' (expected rgba8, rgba16f, rgba32f, rg16f, rg32f, r16f, r32f, r8, rg8)",
      name));
}

std::string pixel_format_name(PixelFormat pf) {
  for (const codecs::PixelFormatEntry& p : codecs::kPixelFormats)
    if (pf == p.pf) return p.name;
  return "unknown";
}

int pixel_format_channels(PixelFormat pf) { return codecs::pixel_info(pf).channels; }

void write_volume(const fs::path& path, const Volume& v, FileFormat ff, PixelFormat pf,
                  const std::string& symbol) {
  switch (ff) {
    case FileFormat::Dds:
      codecs::write_dds(path, {v}, pf);
      return;
    case FileFormat::Ktx2:
      codecs::write_ktx2(path, {v}, pf);
      return;
    case FileFormat::Exr:
      codecs::write_exr_volume(path, v, codecs::pixel_info(pf).bytes_per_channel == 2);
      return;
    case FileFormat::Npy:
      codecs::write_npy(path, v);
      return;
    case FileFormat::CHeader:
      codecs::write_c_header(path, v, symbol);
      return;
    case FileFormat::Png:
      codecs::write_png_volume(path, v, codecs::pixel_info(pf).bytes_per_channel == 1 ? 8 : 16);
      return;
  }
  throw InputError("write_volume: invalid file format");
}

void write_texture_mips(const fs::path& path, const std::vector<Volume>& levels, PixelFormat pf) {
  switch (file_format_from_path(path)) {
    case FileFormat::Dds:
      codecs::write_dds(path, levels, pf);
      return;
    case FileFormat::Ktx2:
      codecs::write_ktx2(path, levels, pf);
      return;
    default:
      throw InputError(fmt::format("{}: a mip chain is written as .dds or .ktx2", path.string()));
  }
}

Volume read_texture_level(const fs::path& path, int level) {
  if (level < 0) throw InputError(fmt::format("{}: mip level must be >= 0, got {}", path.string(), level));
  switch (file_format_from_path(path)) {
    case FileFormat::Dds:
      return codecs::read_dds(path, level);
    case FileFormat::Ktx2:
      return codecs::read_ktx2(path, level);
    default:
      throw InputError(fmt::format("{}: mip levels are read from .dds or .ktx2", path.string()));
  }
}

namespace codecs {
void check_mip_chain(const fs::path& path, const std::vector<Volume>& levels) {
  if (levels.empty()) fail(path, "no mip level to write");
  const Volume& l0 = levels[0];
  if (levels.size() > 1 && l0.depth != 1) fail(path, "mip chains are written for 2D textures only");
  const int max_levels = 1 + int(std::log2(double(std::max(l0.width, l0.height))));
  if (int(levels.size()) > max_levels)
    fail(path, fmt::format("{} mip levels for a {}x{} texture (at most {})", levels.size(), l0.width,
                           l0.height, max_levels));
  for (std::size_t i = 1; i < levels.size(); ++i) {
    const Volume& l = levels[i];
    const int w = std::max(1, l0.width >> i), h = std::max(1, l0.height >> i);
    if (l.width != w || l.height != h || l.depth != 1 || l.channels != l0.channels)
      fail(path, fmt::format("mip level {} is {}x{}x{} with {} channels, expected {}x{}x1 with {}", i,
                             l.width, l.height, l.depth, l.channels, w, h, l0.channels));
  }
}
}  // namespace codecs

namespace {
Volume read_volume_any(const fs::path& path) {
  switch (file_format_from_path(path)) {
    case FileFormat::Dds:
      return codecs::read_dds(path);
    case FileFormat::Ktx2:
      return codecs::read_ktx2(path);
    case FileFormat::Exr:
      return codecs::read_exr(path, true);
    case FileFormat::Npy:
      return codecs::read_npy(path);
    case FileFormat::Png:
      return codecs::read_png(path, true);
    case FileFormat::CHeader:
      break;
  }
  throw InputError(
      fmt::format("'{}': reading C headers is not supported (use .npy for a readable copy)", path.string()));
}
}  // namespace

Volume read_volume(const fs::path& path) {
  Volume v = read_volume_any(path);
  // The writers refuse non-finite values; a file holding one (half or float Inf/NaN bit patterns, '<f8'
  // beyond float range) is corrupt for us, and would otherwise reach a sampler as NaN.
  codecs::validate_volume(v, path);
  return v;
}

Volume read_image(const fs::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".png") return codecs::read_png(path, false);
  if (ext == ".exr") return codecs::read_exr(path, false);
  throw InputError(fmt::format("'{}': images must be .png or .exr", path.string()));
}

void write_png(const fs::path& path, const Volume& image, int bits) {
  if (bits != 8 && bits != 16)
    throw InputError(fmt::format("'{}': PNG bit depth must be 8 or 16", path.string()));
  codecs::write_png_volume(path, image, bits);
}

void write_exr(const fs::path& path, const Volume& image, bool half) {
  codecs::write_exr_volume(path, image, half);
}

namespace codecs {

void fail(const fs::path& path, const std::string& what) {
  throw InputError(fmt::format("'{}': {}", path.string(), what));
}

const PixelFormatEntry& pixel_format_entry(PixelFormat pf) {
  for (const PixelFormatEntry& e : kPixelFormats)
    if (e.pf == pf) return e;
  throw InputError("invalid pixel format");
}
PixelInfo pixel_info(PixelFormat pf) { return pixel_format_entry(pf).info; }

void check_dimensions(const fs::path& path, long long w, long long h, long long d, long long c) {
  if (w < 1 || h < 1 || d < 1 || c < 1 || w > kMaxDimension || h > kMaxDimension || d > kMaxDimension ||
      c > kMaxDimension)
    fail(path, fmt::format("invalid dimensions {}x{}x{} with {} channels", w, h, d, c));
  if (std::size_t(w) * std::size_t(h) * std::size_t(d) * std::size_t(c) > kMaxElements)
    fail(path, fmt::format("dimensions {}x{}x{}x{} exceed the size limit", w, h, d, c));
}

void validate_volume(const Volume& v, const fs::path& path, int min_channels, int max_channels) {
  validate_values(v.data, v.width, v.height, v.depth, v.channels, path, min_channels, max_channels);
}

void validate_values(std::span<const float> data, int width, int height, int depth, int channels,
                     const fs::path& path, int min_channels, int max_channels) {
  check_dimensions(path, width, height, depth, channels);
  if (channels < min_channels || channels > max_channels)
    fail(path, fmt::format("{} channels not supported by this format (expected {}..{})", channels,
                           min_channels, max_channels));
  const std::size_t texels = std::size_t(width) * std::size_t(height) * std::size_t(depth);
  if (data.size() != texels * std::size_t(channels))
    fail(path, fmt::format("volume data holds {} values, expected {}x{}x{}x{} = {}", data.size(), width,
                           height, depth, channels, texels * std::size_t(channels)));
  for (std::size_t i = 0; i < data.size(); ++i) {
    if (!std::isfinite(data[i])) {
      const std::size_t c = i % std::size_t(channels), t = i / std::size_t(channels);
      const std::size_t x = t % std::size_t(width), y = (t / std::size_t(width)) % std::size_t(height),
                        z = t / (std::size_t(width) * std::size_t(height));
      fail(path,
           fmt::format("non-finite value {} at x={} y={} z={} c={}; nothing written", data[i], x, y, z, c));
    }
  }
}

std::uint8_t to_unorm8(float x) {
  const double s = std::clamp(double(x), 0.0, 1.0);
  return std::uint8_t(std::floor(s * 255.0 + 0.5));
}
std::uint16_t to_unorm16(float x) {
  const double s = std::clamp(double(x), 0.0, 1.0);
  return std::uint16_t(std::floor(s * 65535.0 + 0.5));
}

std::vector<std::byte> encode_texels(const Volume& v, PixelFormat pf, const fs::path& path) {
  const PixelInfo pi = pixel_info(pf);
  validate_volume(v, path);
  if (v.channels != pi.channels)
    fail(path, fmt::format("pixel format {} needs {} channels, the volume has {}", pixel_format_name(pf),
                           pi.channels, v.channels));
  if (pi.block_bytes) {
    if (v.depth != 1) fail(path, fmt::format("pixel format {} is 2D only", pixel_format_name(pf)));
    std::vector<std::vector<Bc4Block>> ch;
    for (int c = 0; c < v.channels; ++c)
      ch.push_back(bc4_encode(v.data.data() + c, v.width, v.height, std::size_t(v.channels)));
    std::vector<std::byte> out;
    out.reserve(pi.image_bytes(std::size_t(v.width), std::size_t(v.height), 1));
    for (std::size_t b = 0; b < ch[0].size(); ++b)
      for (const auto& blocks : ch)
        for (std::uint8_t x : blocks[b]) out.push_back(std::byte(x));
    return out;
  }
  std::vector<std::byte> out(v.data.size() * std::size_t(pi.bytes_per_channel));
  for (std::size_t i = 0; i < v.data.size(); ++i) {
    const float x = v.data[i];
    std::byte* dst = out.data() + i * pi.bytes_per_channel;
    if (pi.bytes_per_channel == 1) {
      *dst = std::byte(to_unorm8(x));
    } else if (pi.bytes_per_channel == 2) {
      const Imath::half h(x);  // round to nearest even
      if (h.isInfinity())
        fail(path,
             fmt::format("value {} at index {} overflows half float (max 65504); nothing written", x, i));
      const std::uint16_t bits = h.bits();
      std::memcpy(dst, &bits, 2);
    } else {
      std::memcpy(dst, &x, 4);
    }
  }
  return out;
}

Volume decode_texels(std::span<const std::byte> bytes, PixelFormat pf, int w, int h, int d) {
  const PixelInfo pi = pixel_info(pf);
  Volume v(w, h, d, pi.channels);
  if (pi.block_bytes) {  // d = 1 (the readers refuse 3D block-compressed files)
    const std::size_t n = pi.image_bytes(std::size_t(w), std::size_t(h), 1) / std::size_t(pi.block_bytes);
    for (int c = 0; c < pi.channels; ++c) {
      std::vector<Bc4Block> blocks(n);
      for (std::size_t b = 0; b < n; ++b)
        std::memcpy(blocks[b].data(), bytes.data() + b * std::size_t(pi.block_bytes) + 8 * std::size_t(c), 8);
      bc4_decode(blocks, w, h, v.data.data() + c, std::size_t(pi.channels));
    }
    return v;
  }
  for (std::size_t i = 0; i < v.data.size(); ++i) {
    const std::byte* src = bytes.data() + i * pi.bytes_per_channel;
    if (pi.bytes_per_channel == 1) {
      v.data[i] = float(std::to_integer<unsigned>(*src)) / 255.0f;
    } else if (pi.bytes_per_channel == 2) {
      std::uint16_t bits;
      std::memcpy(&bits, src, 2);
      Imath::half hv;
      hv.setBits(bits);
      v.data[i] = float(hv);
    } else {
      std::memcpy(&v.data[i], src, 4);
    }
  }
  return v;
}

std::vector<std::byte> read_file(const fs::path& path) {
  require_regular_file(path);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) fail(path, "cannot open file");
  const std::streamoff size = in.tellg();
  if (size < 0) fail(path, "cannot read file");
  std::vector<std::byte> bytes(static_cast<std::size_t>(size));
  in.seekg(0);
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size)) fail(path, "cannot read file");
  return bytes;
}

std::vector<std::byte> read_file_prefix(const fs::path& path, std::size_t max_bytes) {
  require_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file");
  std::vector<std::byte> bytes(max_bytes);
  in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(max_bytes));
  bytes.resize(std::size_t(in.gcount()));
  return bytes;
}

std::vector<std::byte> read_file_range(const fs::path& path, std::size_t offset, std::size_t size) {
  require_regular_file(path);
  std::error_code ec;
  const std::uintmax_t file_size = fs::file_size(path, ec);
  if (ec) fail(path, "cannot read file");
  if (offset > file_size || size > file_size - offset)
    fail(path, fmt::format("truncated or corrupt file (needs {} bytes at offset {}, file has {})", size,
                           offset, file_size));
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open file");
  std::vector<std::byte> bytes(size);
  in.seekg(std::streamoff(offset));
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
    fail(path, "cannot read file");
  return bytes;
}

void require_finite_texels(const fs::path& path, const Volume& v, int level) {
  for (std::size_t i = 0; i < v.data.size(); ++i) {
    if (std::isfinite(v.data[i])) continue;
    const std::size_t c = i % v.channels, t = i / v.channels;
    const std::size_t x = t % v.width, y = (t / v.width) % v.height,
                      z = t / (std::size_t(v.width) * v.height);
    fail(path, fmt::format("mip level {}: non-finite value {} at x={} y={} z={} c={}", level, v.data[i], x, y,
                           z, c));
  }
}

void ByteReader::require(std::size_t offset, std::size_t size) const {
  if (offset > bytes.size() || size > bytes.size() - offset)
    fail(*path, fmt::format("truncated or corrupt file (needs {} bytes at offset {}, file has {})", size,
                            offset, bytes.size()));
}

}  // namespace codecs
}  // namespace msh::io
