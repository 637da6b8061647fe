// Khronos KTX 2.0 (KTX File Format Specification 2.0): identifier, header, index, one level index entry, a
// basic data format descriptor (Khronos Data Format Specification 1.3), key/value data with KTXwriter, then
// the texels (x fastest, then y, then z). No supercompression, one mip level, no array layers, one face.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>

#include <numeric>

#include "texture_internal.h"

namespace msh::io::codecs {
namespace fs = std::filesystem;

namespace {
constexpr unsigned char kIdentifier[12] = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32,
                                           0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};

// Basic DFD of BC4 / BC5 (KDFS 1.3 §5 and §D.4): colour model BC4 (131) / BC5 (132), 4 × 4 texel blocks
// of 8 / 16 bytes, one 64-bit sample per channel (BC4_DATA, or BC5 RED then GREEN at bit 64), UNORM.
std::vector<std::byte> block_dfd(const PixelInfo& pi) {
  const std::uint32_t block_size = 24 + 16 * std::uint32_t(pi.channels);
  std::vector<std::byte> d;
  put_u32(d, 4 + block_size);           // dfdTotalSize
  put_u32(d, 0);                        // vendorId KHRONOS, descriptorType BASICFORMAT
  put_u32(d, 2u | (block_size << 16));  // versionNumber 1.3, descriptorBlockSize
  const std::uint32_t model = pi.channels == 1 ? 131u : 132u;
  put_u32(d, model | (1u << 8) | (1u << 16));  // colorPrimaries BT709, transferFunction LINEAR, flags 0
  put_u32(d, 3u | (3u << 8));                  // texelBlockDimension0..1 = 4 × 4 (stored minus one)
  put_u32(d, std::uint32_t(pi.block_bytes));   // bytesPlane0
  put_u32(d, 0);                               // bytesPlane4..7
  for (int c = 0; c < pi.channels; ++c) {
    put_u32(d,
            std::uint32_t(64 * c) | (63u << 16) | (std::uint32_t(c) << 24));  // offset, length − 1, channel
    put_u32(d, 0);                                                            // samplePosition0..3
    put_u32(d, 0);                                                            // sampleLower
    put_u32(d, 0xFFFFFFFFu);                                                  // sampleUpper
  }
  return d;
}

// Basic DFD for an unpacked little-endian RGBA-ordered format (KDFS 1.3 §5; one sample per channel).
std::vector<std::byte> basic_dfd(PixelFormat pf) {
  const PixelInfo pi = pixel_info(pf);
  if (pi.block_bytes) return block_dfd(pi);
  const std::uint32_t block_size = 24 + 16 * pi.channels;
  std::vector<std::byte> d;
  put_u32(d, 4 + block_size);  // dfdTotalSize
  put_u32(d, 0);               // vendorId = KHR_DF_VENDORID_KHRONOS (0), descriptorType = BASICFORMAT (0)
  put_u32(d, 2u | (block_size << 16));  // versionNumber = KHR_DF_VERSIONNUMBER_1_3 (2), descriptorBlockSize
  // colorModel RGBSDA (1), colorPrimaries BT709 (1), transferFunction LINEAR (1), flags ALPHA_STRAIGHT (0).
  put_u32(d, 1u | (1u << 8) | (1u << 16));
  put_u32(d, 0);                                // texelBlockDimension0..3 = 1x1x1x1 (stored minus one)
  put_u32(d, std::uint32_t(pi.texel_bytes()));  // bytesPlane0
  put_u32(d, 0);                                // bytesPlane4..7
  const int bits = 8 * pi.bytes_per_channel;
  for (int c = 0; c < pi.channels; ++c) {
    const std::uint32_t channel_id = c == 3 ? 15u : std::uint32_t(c);     // R=0 G=1 B=2 A=15
    const std::uint32_t qualifiers = pi.is_float ? (0x80u | 0x40u) : 0u;  // FLOAT | SIGNED for SFLOAT
    put_u32(d, std::uint32_t(c * bits) | (std::uint32_t(bits - 1) << 16) | ((channel_id | qualifiers) << 24));
    put_u32(d, 0);  // samplePosition0..3
    if (pi.is_float) {
      put_u32(d, 0xBF800000u);  // sampleLower = -1.0f
      put_u32(d, 0x3F800000u);  // sampleUpper = 1.0f
    } else {
      put_u32(d, 0);
      put_u32(d, (1u << bits) - 1u);
    }
  }
  return d;
}

void pad_to(std::vector<std::byte>& out, std::size_t alignment) {
  while (out.size() % alignment != 0) out.push_back(std::byte{0});
}
}  // namespace

void write_ktx2(const fs::path& path, const std::vector<Volume>& levels, PixelFormat pf) {
  check_mip_chain(path, levels);
  const Volume& v = levels[0];
  std::vector<std::vector<std::byte>> texels;
  for (const Volume& l : levels) texels.push_back(encode_texels(l, pf, path));
  const std::size_t n_levels = levels.size();
  const PixelInfo pi = pixel_info(pf);
  const std::vector<std::byte> dfd = basic_dfd(pf);
  std::vector<std::byte> kvd;
  {
    const std::string key = "KTXwriter";
    const std::string value = fmt::format("microshadow {}", MSH_VERSION);
    const std::uint32_t len = std::uint32_t(key.size() + 1 + value.size() + 1);  // both NUL-terminated
    put_u32(kvd, len);
    for (char c : key) kvd.push_back(std::byte(c));
    kvd.push_back(std::byte{0});
    for (char c : value) kvd.push_back(std::byte(c));
    kvd.push_back(std::byte{0});
    pad_to(kvd, 4);  // valuePadding (counted in kvdByteLength)
  }
  const std::size_t index_end = 12 + 36 + 32 + 24 * n_levels;  // identifier, header, index, level entries
  const std::size_t dfd_offset = index_end;
  const std::size_t kvd_offset = dfd_offset + dfd.size();
  // mipPadding: lcm(texel block size, 4) (KTX 2.0 §3.9.7).
  const std::size_t alignment =
      std::lcm(std::size_t(pi.block_bytes ? pi.block_bytes : pi.texel_bytes()), std::size_t(4));
  const auto align = [&](std::size_t o) { return (o + alignment - 1) / alignment * alignment; };
  // Level data smallest first (KTX 2.0 §3.9 "Mip Level Array"), each level aligned (mipPadding).
  std::vector<std::size_t> level_offset(n_levels);
  std::size_t end = kvd_offset + kvd.size();
  for (std::size_t i = n_levels; i-- > 0;) {
    level_offset[i] = align(end);
    end = level_offset[i] + texels[i].size();
  }

  std::vector<std::byte> out;
  out.reserve(end);
  for (unsigned char c : kIdentifier) out.push_back(std::byte(c));
  put_u32(out, pixel_format_entry(pf).vk);
  put_u32(out, std::uint32_t(pi.block_bytes ? 1 : pi.bytes_per_channel));  // typeSize (1 for block formats)
  put_u32(out, std::uint32_t(v.width));
  put_u32(out, std::uint32_t(v.height));
  put_u32(out, v.depth > 1 ? std::uint32_t(v.depth) : 0u);  // pixelDepth: 0 for 2D
  put_u32(out, 0);                                          // layerCount: not an array
  put_u32(out, 1);                                          // faceCount
  put_u32(out, std::uint32_t(n_levels));                    // levelCount
  put_u32(out, 0);                                          // supercompressionScheme: none
  put_u32(out, std::uint32_t(dfd_offset));
  put_u32(out, std::uint32_t(dfd.size()));
  put_u32(out, std::uint32_t(kvd_offset));
  put_u32(out, std::uint32_t(kvd.size()));
  put_u64(out, 0);  // sgdByteOffset
  put_u64(out, 0);  // sgdByteLength
  for (std::size_t i = 0; i < n_levels; ++i) {
    put_u64(out, level_offset[i]);   // levels[i].byteOffset
    put_u64(out, texels[i].size());  // levels[i].byteLength
    put_u64(out, texels[i].size());  // levels[i].uncompressedByteLength
  }
  out.insert(out.end(), dfd.begin(), dfd.end());
  out.insert(out.end(), kvd.begin(), kvd.end());
  for (std::size_t i = n_levels; i-- > 0;) {
    pad_to(out, alignment);  // mipPadding
    out.insert(out.end(), texels[i].begin(), texels[i].end());
  }
  write_file_atomic(path, out);
}

Volume read_ktx2(const fs::path& path, int level) {
  // Identifier, header, index and the level entries up to `level` (the level index is at most 2^16 levels
  // long here: check_dimensions caps the sides); the texels are read after it, nothing beyond them.
  const std::size_t head = 80 + 24 * (std::size_t(std::max(level, 0)) + 1);
  const std::vector<std::byte> bytes = read_file_prefix(path, head);
  ByteReader r{bytes, &path};
  r.require(0, 12 + 36 + 32 + 24);
  if (std::memcmp(bytes.data(), kIdentifier, 12) != 0) fail(path, "not a KTX2 file (bad identifier)");
  const std::uint32_t vk = r.u32(12), width = r.u32(20), height = r.u32(24), depth = r.u32(28);
  const std::uint32_t layers = r.u32(32), faces = r.u32(36), levels = r.u32(40), scheme = r.u32(44);
  PixelFormat pf;
  if (!pixel_format_from_code(vk, &PixelFormatEntry::vk, pf))
    fail(path, fmt::format("unsupported vkFormat {}", vk));
  if (scheme != 0) fail(path, "supercompressed KTX2 files are not supported");
  if (layers > 1 || faces != 1) fail(path, "KTX2 arrays and cube maps are not supported");
  if (height == 0) fail(path, "1D KTX2 textures are not supported");
  const PixelInfo pi = pixel_info(pf);
  const long long d = depth == 0 ? 1 : depth;
  check_dimensions(path, width, height, d, pi.channels);
  if (d == 1 && (width > std::uint32_t(kMaxSide2D) || height > std::uint32_t(kMaxSide2D)))
    fail(path, fmt::format("2D texture {}x{} exceeds the limit of {} per side", width, height, kMaxSide2D));
  if (pi.block_bytes && d != 1) fail(path, "3D block-compressed KTX2 files are not supported");
  // levelCount 0 means "generate mips at load": level 0 only is stored.
  if (std::uint32_t(level) >= std::max(levels, 1u))
    fail(path, fmt::format("mip level {} requested, the file has {}", level, std::max(levels, 1u)));
  if (level > 0 && d != 1) fail(path, "mip levels of 3D KTX2 files are not supported");
  const std::size_t entry = 80 + 24 * std::size_t(level);
  r.require(entry, 24);
  const std::uint64_t offset = r.u64(entry), length = r.u64(entry + 8);
  const std::uint32_t w = std::max(1u, width >> level), h = std::max(1u, height >> level);
  const std::size_t n = pi.image_bytes(w, h, std::size_t(d));
  if (length != n) fail(path, fmt::format("level {} holds {} bytes, expected {}", level, length, n));
  std::error_code ec;
  const std::uintmax_t file_size = fs::file_size(path, ec);
  if (ec || offset > file_size)
    fail(path, fmt::format("truncated or corrupt file (level {} offset past the end)", level));
  const std::vector<std::byte> texels = read_file_range(path, std::size_t(offset), n);
  Volume v = decode_texels(texels, pf, int(w), int(h), int(d));
  if (pi.is_float) require_finite_texels(path, v, level);
  return v;
}

}  // namespace msh::io::codecs
