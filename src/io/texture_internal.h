// Private helpers shared by the texture/image readers and writers in src/io/.
#pragma once

#include <microshadow/io/texture.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace msh::io::codecs {

static_assert(std::endian::native == std::endian::little, "the file writers assume a little-endian host");

// Hard limits that keep a corrupt header from requesting absurd allocations.
inline constexpr int kMaxDimension = 1 << 16;
inline constexpr std::size_t kMaxElements = std::size_t(1) << 28;  // floats in one Volume (1 GiB)
inline constexpr int kMaxSide2D = 16384;  // each side of a 2D DDS / KTX2 texture (docs/formats.md)

struct PixelInfo {
  int channels;
  int bytes_per_channel;  // 1 (UNORM8), 2 (half), 4 (float)
  bool is_float;
  int block_bytes = 0;  // block-compressed: bytes per 4 × 4 block (BC4 8, BC5 16); 0 = one texel at a time
  int texel_bytes() const { return channels * bytes_per_channel; }
  // Bytes of a w × h × d image (whole 4 × 4 blocks for the block-compressed formats).
  std::size_t image_bytes(std::size_t w, std::size_t h, std::size_t d) const {
    return block_bytes ? (w + 3) / 4 * ((h + 3) / 4) * d * std::size_t(block_bytes)
                       : w * h * d * std::size_t(texel_bytes());
  }
};
PixelInfo pixel_info(PixelFormat pf);  // pixel_format_entry(pf).info

// Every PixelFormat, in declaration order: its name (pixel_format_from_name), layout (pixel_info) and its
// codes in the two GPU container formats: DXGI_FORMAT (DDS DX10 header, Microsoft "DXGI_FORMAT enumeration")
// and VkFormat (KTX2 vkFormat, Vulkan 1.3 specification), both the little-endian unpacked RGBA-ordered kind.
struct PixelFormatEntry {
  PixelFormat pf;
  const char* name;
  PixelInfo info;
  std::uint32_t dxgi;  // DXGI_FORMAT_*
  std::uint32_t vk;    // VK_FORMAT_*
};
inline constexpr PixelFormatEntry kPixelFormats[] = {
    {PixelFormat::RGBA8Unorm, "rgba8", {4, 1, false}, 28, 37},    // R8G8B8A8_UNORM
    {PixelFormat::RGBA16Float, "rgba16f", {4, 2, true}, 10, 97},  // R16G16B16A16_FLOAT / _SFLOAT
    {PixelFormat::RGBA32Float, "rgba32f", {4, 4, true}, 2, 109},  // R32G32B32A32_FLOAT / _SFLOAT
    {PixelFormat::RG16Float, "rg16f", {2, 2, true}, 34, 83},      // R16G16_FLOAT / _SFLOAT
    {PixelFormat::RG32Float, "rg32f", {2, 4, true}, 16, 103},     // R32G32_FLOAT / _SFLOAT
    {PixelFormat::R16Float, "r16f", {1, 2, true}, 54, 76},        // R16_FLOAT / _SFLOAT
    {PixelFormat::R32Float, "r32f", {1, 4, true}, 41, 100},       // R32_FLOAT / _SFLOAT
    {PixelFormat::R8Unorm, "r8", {1, 1, false}, 61, 9},           // R8_UNORM
    {PixelFormat::RG8Unorm, "rg8", {2, 1, false}, 49, 16},        // R8G8_UNORM
    {PixelFormat::BC4Unorm, "bc4", {1, 1, false, 8}, 80, 139},    // BC4_UNORM / BC4_UNORM_BLOCK
    {PixelFormat::BC5Unorm, "bc5", {2, 1, false, 16}, 83, 141}};  // BC5_UNORM / BC5_UNORM_BLOCK

// The table's row of `pf` (InputError for a value outside the enum).
const PixelFormatEntry& pixel_format_entry(PixelFormat pf);

// The reverse of a code column (&PixelFormatEntry::dxgi or ::vk): false when no format has `value`.
inline bool pixel_format_from_code(std::uint32_t value, std::uint32_t PixelFormatEntry::*code,
                                   PixelFormat& pf) {
  for (const PixelFormatEntry& e : kPixelFormats)
    if (e.*code == value) return pf = e.pf, true;
  return false;
}

// Dimensions positive and within limits, data.size() consistent, every value finite; InputError naming
// `path`.
void validate_volume(const Volume& v, const std::filesystem::path& path, int min_channels = 1,
                     int max_channels = 1 << 16);
// The same for values laid out as a Volume of these dimensions.
void validate_values(std::span<const float> data, int width, int height, int depth, int channels,
                     const std::filesystem::path& path, int min_channels = 1, int max_channels = 1 << 16);
// Dimensions read from a file: InputError naming `path` unless they are within limits.
void check_dimensions(const std::filesystem::path& path, long long w, long long h, long long d, long long c);

// Packs the volume into little-endian texels of `pf` (channel count must match: InputError). Half: round to
// nearest even, overflow to infinity is an InputError. UNORM8: floor(saturate(x)*255 + 0.5).
std::vector<std::byte> encode_texels(const Volume& v, PixelFormat pf, const std::filesystem::path& path);
// BC4/BC5: the blocks of each channel (io/bc4.h), BC5's red block before its green one; 2D only (InputError).
// The inverse: `bytes` must hold exactly pixel_info(pf).image_bytes(w, h, d) bytes.
Volume decode_texels(std::span<const std::byte> bytes, PixelFormat pf, int w, int h, int d);

std::uint8_t to_unorm8(float x);
std::uint16_t to_unorm16(float x);

// The whole file; InputError naming it when it cannot be opened or read (or is not a regular file).
std::vector<std::byte> read_file(const std::filesystem::path& path);
// At most `max_bytes` from the start of the file (fewer when the file is shorter): a header.
std::vector<std::byte> read_file_prefix(const std::filesystem::path& path, std::size_t max_bytes);
// Exactly `size` bytes at `offset`; InputError "truncated" naming the file when it is shorter. Nothing else
// of the file is read.
std::vector<std::byte> read_file_range(const std::filesystem::path& path, std::size_t offset,
                                       std::size_t size);
// InputError naming the file and the mip level at the first non-finite value of a decoded float texture.
void require_finite_texels(const std::filesystem::path& path, const Volume& v, int level);

// Little-endian field access with bounds checks (InputError "truncated" naming `path`).
struct ByteReader {
  std::span<const std::byte> bytes;
  const std::filesystem::path* path;
  void require(std::size_t offset, std::size_t size) const;
  std::uint32_t u32(std::size_t offset) const {
    require(offset, 4);
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + offset, 4);
    return v;
  }
  std::uint64_t u64(std::size_t offset) const {
    require(offset, 8);
    std::uint64_t v;
    std::memcpy(&v, bytes.data() + offset, 8);
    return v;
  }
};

// Appends little-endian values to a byte buffer (resize + memcpy: GCC 12's -Wstringop-overflow misreads an
// inlined insert of a 4-byte range into a fresh vector).
inline void put_u32(std::vector<std::byte>& out, std::uint32_t v) {
  const std::size_t n = out.size();
  out.resize(n + 4);
  std::memcpy(out.data() + n, &v, 4);
}
inline void put_u64(std::vector<std::byte>& out, std::uint64_t v) {
  const std::size_t n = out.size();
  out.resize(n + 8);
  std::memcpy(out.data() + n, &v, 8);
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what);

// Per-format entry points (one .cpp each).
void write_npy(const std::filesystem::path& path, const Volume& v);
Volume read_npy(const std::filesystem::path& path);
void write_exr_volume(const std::filesystem::path& path, const Volume& v, bool half);
Volume read_exr(const std::filesystem::path& path, bool as_volume);
// DDS and KTX2 take a mip chain: levels[0] the full texture, further levels 2D and halved (check_mip_chain).
void write_dds(const std::filesystem::path& path, const std::vector<Volume>& levels, PixelFormat pf);
Volume read_dds(const std::filesystem::path& path, int level = 0);
void write_ktx2(const std::filesystem::path& path, const std::vector<Volume>& levels, PixelFormat pf);
Volume read_ktx2(const std::filesystem::path& path, int level = 0);
// InputError unless levels is non-empty, level i is max(1, w0 >> i) × max(1, h0 >> i) × 1 with the
// channels of level 0 for i ≥ 1 (only 2D textures have mips here), and there are at most 1 + log2(max side).
void check_mip_chain(const std::filesystem::path& path, const std::vector<Volume>& levels);
void write_c_header(const std::filesystem::path& path, const Volume& v, const std::string& symbol);
void write_png_volume(const std::filesystem::path& path, const Volume& v, int bits);
Volume read_png(const std::filesystem::path& path, bool as_volume);

}  // namespace msh::io::codecs
