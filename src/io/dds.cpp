// DirectDraw Surface with the DX10 extension header (Microsoft docs: "DDS_HEADER", "DDS_PIXELFORMAT",
// "DDS_HEADER_DXT10"): "DDS " + 124-byte DDS_HEADER + 20-byte DDS_HEADER_DXT10 + texels (x fastest, then y,
// then z), no padding between rows or slices; a 2D texture may carry its mip chain (level 0 first, each level
// right after the previous one).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>

#include <algorithm>

#include "texture_internal.h"

namespace msh::io::codecs {
namespace fs = std::filesystem;

namespace {
// DDS_HEADER.dwFlags
constexpr std::uint32_t DDSD_CAPS = 0x1, DDSD_HEIGHT = 0x2, DDSD_WIDTH = 0x4, DDSD_PITCH = 0x8,
                        DDSD_PIXELFORMAT = 0x1000, DDSD_MIPMAPCOUNT = 0x20000, DDSD_LINEARSIZE = 0x80000,
                        DDSD_DEPTH = 0x800000;
constexpr std::uint32_t DDPF_FOURCC = 0x4;
constexpr std::uint32_t DDSCAPS_TEXTURE = 0x1000, DDSCAPS_COMPLEX = 0x8, DDSCAPS_MIPMAP = 0x400000;
constexpr std::uint32_t DDSCAPS2_VOLUME = 0x200000;
constexpr std::uint32_t FOURCC_DX10 = 0x30315844;  // 'D','X','1','0'
constexpr std::uint32_t DIM_TEXTURE2D = 3, DIM_TEXTURE3D = 4;
constexpr std::size_t kHeaderBytes = 4 + 124 + 20;

}  // namespace

void write_dds(const fs::path& path, const std::vector<Volume>& levels, PixelFormat pf) {
  check_mip_chain(path, levels);
  const Volume& v = levels[0];
  std::vector<std::byte> texels;
  for (const Volume& l : levels) {
    const std::vector<std::byte> t = encode_texels(l, pf, path);
    texels.insert(texels.end(), t.begin(), t.end());
  }
  const std::uint32_t n_levels = std::uint32_t(levels.size());
  const PixelInfo pi = pixel_info(pf);
  const bool volume = v.depth > 1;
  std::vector<std::byte> out;
  out.reserve(kHeaderBytes + texels.size());
  put_u32(out, 0x20534444);  // "DDS "
  // DDS_HEADER
  put_u32(out, 124);  // dwSize
  put_u32(out, DDSD_CAPS | DDSD_HEIGHT | DDSD_WIDTH | (pi.block_bytes ? DDSD_LINEARSIZE : DDSD_PITCH) |
                   DDSD_PIXELFORMAT | DDSD_MIPMAPCOUNT | (volume ? DDSD_DEPTH : 0u));
  put_u32(out, std::uint32_t(v.height));
  put_u32(out, std::uint32_t(v.width));
  // dwPitchOrLinearSize: the row pitch, or for a block-compressed format the top level's size in bytes.
  put_u32(out, std::uint32_t(pi.block_bytes ? pi.image_bytes(std::size_t(v.width), std::size_t(v.height), 1)
                                            : std::size_t(v.width * pi.texel_bytes())));
  put_u32(out, volume ? std::uint32_t(v.depth) : 0u);  // dwDepth
  put_u32(out, n_levels);                              // dwMipMapCount
  for (int i = 0; i < 11; ++i) put_u32(out, 0);        // dwReserved1
  // DDS_PIXELFORMAT: the real format is in the DX10 header.
  put_u32(out, 32);
  put_u32(out, DDPF_FOURCC);
  put_u32(out, FOURCC_DX10);
  for (int i = 0; i < 5; ++i) put_u32(out, 0);  // dwRGBBitCount, R/G/B/A masks
  put_u32(out, DDSCAPS_TEXTURE | (n_levels > 1 ? DDSCAPS_COMPLEX | DDSCAPS_MIPMAP : 0u));  // dwCaps
  put_u32(out, volume ? DDSCAPS2_VOLUME : 0u);                                             // dwCaps2
  put_u32(out, 0);                                                                         // dwCaps3
  put_u32(out, 0);                                                                         // dwCaps4
  put_u32(out, 0);                                                                         // dwReserved2
  // DDS_HEADER_DXT10
  put_u32(out, pixel_format_entry(pf).dxgi);
  put_u32(out, volume ? DIM_TEXTURE3D : DIM_TEXTURE2D);
  put_u32(out, 0);  // miscFlag (not a cube map)
  put_u32(out, 1);  // arraySize (must be 1 for 3D)
  put_u32(out, 0);  // miscFlags2: DDS_ALPHA_MODE_UNKNOWN
  out.insert(out.end(), texels.begin(), texels.end());
  write_file_atomic(path, out);
}

Volume read_dds(const fs::path& path, int level) {
  // The header only; the texels of the requested level are read after it, nothing beyond them.
  const std::vector<std::byte> bytes = read_file_prefix(path, kHeaderBytes);
  ByteReader r{bytes, &path};
  r.require(0, kHeaderBytes);
  if (r.u32(0) != 0x20534444) fail(path, "not a DDS file (bad magic)");
  if (r.u32(4) != 124 || r.u32(4 + 72) != 32) fail(path, "corrupt DDS header (bad dwSize)");
  const std::uint32_t flags = r.u32(8);
  const std::uint32_t height = r.u32(12), width = r.u32(16);
  const std::uint32_t depth_field = r.u32(24);
  if (!(r.u32(4 + 76) & DDPF_FOURCC) || r.u32(4 + 80) != FOURCC_DX10)
    fail(path, "only DDS files with a DX10 header are supported");
  const std::uint32_t caps2 = r.u32(4 + 108);
  const std::uint32_t dxgi = r.u32(128), dim = r.u32(132), misc = r.u32(136), array_size = r.u32(140);
  PixelFormat pf;
  if (!pixel_format_from_code(dxgi, &PixelFormatEntry::dxgi, pf))
    fail(path, fmt::format("unsupported DXGI format {}", dxgi));
  if (misc & 0x4) fail(path, "cube maps are not supported");
  if (array_size > 1) fail(path, "texture arrays are not supported");
  long long depth = 1;
  if (dim == DIM_TEXTURE3D) {
    if (!(flags & DDSD_DEPTH) || !(caps2 & DDSCAPS2_VOLUME))
      fail(path, "3D DDS without DDSD_DEPTH/DDSCAPS2_VOLUME");
    depth = depth_field;
  } else if (dim != DIM_TEXTURE2D) {
    fail(path, fmt::format("unsupported DDS resource dimension {}", dim));
  }
  const PixelInfo pi = pixel_info(pf);
  check_dimensions(path, width, height, depth, pi.channels);
  if (depth == 1 && (width > std::uint32_t(kMaxSide2D) || height > std::uint32_t(kMaxSide2D)))
    fail(path, fmt::format("2D texture {}x{} exceeds the limit of {} per side", width, height, kMaxSide2D));
  if (pi.block_bytes && depth != 1) fail(path, "3D block-compressed DDS files are not supported");
  // Level `level`: the levels before it are packed after the header, level 0 first.
  const std::uint32_t n_levels = (flags & DDSD_MIPMAPCOUNT) && r.u32(28) > 0 ? r.u32(28) : 1;
  if (std::uint32_t(level) >= n_levels)
    fail(path, fmt::format("mip level {} requested, the file has {}", level, n_levels));
  if (level > 0 && depth != 1) fail(path, "mip levels of 3D DDS files are not supported");
  std::size_t offset = kHeaderBytes;
  std::uint32_t w = width, h = height;
  for (int i = 0; i < level; ++i) {
    offset += pi.image_bytes(w, h, 1);
    w = std::max(1u, w / 2), h = std::max(1u, h / 2);
  }
  const std::size_t n = pi.image_bytes(w, h, std::size_t(depth));
  const std::vector<std::byte> texels = read_file_range(path, offset, n);  // further levels are not read
  Volume v = decode_texels(texels, pf, int(w), int(h), int(depth));
  if (pi.is_float) require_finite_texels(path, v, level);
  return v;
}

}  // namespace msh::io::codecs
