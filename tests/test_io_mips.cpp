// Mip chains in DDS and KTX2 (io::write_texture_mips, io::read_texture_level): every level reads back, the
// files follow the containers' layout rules checked here byte by byte (not through our reader), and a chain
// of wrong sizes is refused without a file.
#include <gtest/gtest.h>
#include <microshadow/io/bc4.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <tuple>
#include <vector>

namespace fs = std::filesystem;
using namespace msh;

namespace {
std::vector<io::Volume> chain(int w, int h, int c) {
  std::vector<io::Volume> levels;
  uint32_t s = 12345;
  for (int i = 0;; ++i) {
    io::Volume v(std::max(1, w >> i), std::max(1, h >> i), 1, c);
    for (float& x : v.data) {
      s = s * 1664525u + 1013904223u;
      x = float(s >> 8) / float(1 << 24);  // in [0, 1): exact in float32, 8-bit UNORM rounds it
    }
    levels.push_back(v);
    if (v.width == 1 && v.height == 1) break;
  }
  return levels;
}
std::vector<unsigned char> bytes_of(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}
uint32_t u32(const std::vector<unsigned char>& b, std::size_t o) {
  uint32_t v;
  std::memcpy(&v, b.data() + o, 4);
  return v;
}
uint64_t u64(const std::vector<unsigned char>& b, std::size_t o) {
  uint64_t v;
  std::memcpy(&v, b.data() + o, 8);
  return v;
}
}  // namespace

TEST(IoMips, EveryLevelReadsBackInBothContainers) {
  const fs::path dir = fs::temp_directory_path() / "msh_test_io_mips";
  fs::create_directories(dir);
  for (const char* ext : {".dds", ".ktx2"})
    for (const auto& [pf, c, tol] : {std::tuple{io::PixelFormat::RGBA32Float, 4, 0.0f},
                                     std::tuple{io::PixelFormat::R8Unorm, 1, 0.5f / 255}}) {
      const auto levels = chain(16, 4, c);
      ASSERT_EQ(levels.size(), 5u);  // 16x4, 8x2, 4x1, 2x1, 1x1
      const fs::path p = dir / (std::string("t") + ext);
      io::write_texture_mips(p, levels, pf);
      for (int i = 0; i < int(levels.size()); ++i) {
        const io::Volume r = io::read_texture_level(p, i);
        ASSERT_EQ(r.width, levels[std::size_t(i)].width) << ext << " level " << i;
        ASSERT_EQ(r.height, levels[std::size_t(i)].height);
        for (std::size_t k = 0; k < r.data.size(); ++k)
          ASSERT_NEAR(r.data[k], levels[std::size_t(i)].data[k], tol + 1e-7f) << ext << " level " << i;
      }
      EXPECT_THROW(io::read_texture_level(p, int(levels.size())), InputError) << ext;
      // read_volume is level 0.
      EXPECT_EQ(io::read_volume(p).data, io::read_texture_level(p, 0).data);
    }
  fs::remove_all(dir);
}

// KTX 2.0 (Khronos, §3.9 "Level Index", §3.10 "Mip Level Array"): levelCount in the header, one 24-byte index
// entry per level with level 0 first, data stored smallest level first, each level aligned to
// lcm(texel size, 4), file ends with level 0. DDS (Microsoft, "DDS_HEADER"): dwMipMapCount, DDSD_MIPMAPCOUNT,
// DDSCAPS_COMPLEX | DDSCAPS_MIPMAP | DDSCAPS_TEXTURE, levels packed after the 148-byte headers, level 0
// first.
TEST(IoMips, ContainersFollowTheirSpecifications) {
  const fs::path dir = fs::temp_directory_path() / "msh_test_io_mips_spec";
  fs::create_directories(dir);
  const auto levels = chain(8, 8, 4);  // 4 levels
  io::write_texture_mips(dir / "t.ktx2", levels, io::PixelFormat::RGBA16Float);
  const auto k = bytes_of(dir / "t.ktx2");
  EXPECT_EQ(u32(k, 40), 4u);  // levelCount
  std::size_t prev = 0;
  for (int i = 3; i >= 0; --i) {
    const uint64_t off = u64(k, 80 + 24 * std::size_t(i)), len = u64(k, 88 + 24 * std::size_t(i));
    const int side = 8 >> i;
    EXPECT_EQ(len, uint64_t(side * side * 8)) << i;
    EXPECT_EQ(off % 8, 0u) << i;
    EXPECT_GE(off, prev) << i;  // smallest first
    prev = std::size_t(off + len);
  }
  EXPECT_EQ(prev, k.size());  // level 0 last
  io::write_texture_mips(dir / "t.dds", levels, io::PixelFormat::RGBA16Float);
  const auto d = bytes_of(dir / "t.dds");
  EXPECT_EQ(u32(d, 28), 4u);                           // dwMipMapCount
  EXPECT_TRUE(u32(d, 8) & 0x20000u);                   // DDSD_MIPMAPCOUNT
  EXPECT_EQ(u32(d, 108), 0x1000u | 0x8u | 0x400000u);  // dwCaps
  EXPECT_EQ(d.size(), 148u + 8u * (64 + 16 + 4 + 1));
  fs::remove_all(dir);
}

TEST(IoMips, WrongChainsAreRefusedWithoutAFile) {
  const fs::path dir = fs::temp_directory_path() / "msh_test_io_mips_bad";
  fs::create_directories(dir);
  auto levels = chain(8, 8, 4);
  levels[2] = io::Volume(3, 2, 1, 4);
  for (const char* name : {"a.dds", "a.ktx2"}) {
    EXPECT_THROW(io::write_texture_mips(dir / name, levels, io::PixelFormat::RGBA32Float), InputError);
    EXPECT_FALSE(fs::exists(dir / name));
  }
  auto too_many = chain(4, 4, 4);
  too_many.push_back(io::Volume(1, 1, 1, 4));
  EXPECT_THROW(io::write_texture_mips(dir / "b.ktx2", too_many, io::PixelFormat::RGBA32Float), InputError);
  EXPECT_THROW(io::write_texture_mips(dir / "c.exr", chain(4, 4, 4), io::PixelFormat::RGBA32Float),
               InputError);
  fs::remove_all(dir);
}

// Block-compressed chains (BC4, BC5): every level reads back as the BC4 codec's decode of its encode
// (io/bc4.h, tested against the specification in test_io_bc4), levels under 4 × 4 are one block; the
// containers carry the block layout: DDS DXGI 80 / 83 with DDSD_LINEARSIZE = level 0's bytes; KTX2 vkFormat
// 139 / 141, typeSize 1, a DFD with colour model 131 / 132, 4 × 4 blocks of 8 / 16 bytes, one 64-bit sample
// per channel, levels aligned to the block size; 3D volumes are refused.
TEST(IoMips, BlockCompressedChainsInBothContainers) {
  const fs::path dir = fs::temp_directory_path() / "msh_test_io_mips_bc";
  fs::create_directories(dir);
  for (const auto& [pf, c, block, dxgi, vk] : {std::tuple{io::PixelFormat::BC4Unorm, 1, 8u, 80u, 139u},
                                               std::tuple{io::PixelFormat::BC5Unorm, 2, 16u, 83u, 141u}}) {
    const auto levels = chain(16, 8, c);  // 16x8, 8x4, 4x2, 2x1, 1x1
    ASSERT_EQ(levels.size(), 5u);
    const std::size_t blocks[] = {8, 2, 1, 1, 1};
    for (const char* ext : {".dds", ".ktx2"}) {
      const fs::path p = dir / (std::string("t") + ext);
      io::write_texture_mips(p, levels, pf);
      for (int i = 0; i < 5; ++i) {
        const io::Volume& in = levels[std::size_t(i)];
        const io::Volume r = io::read_texture_level(p, i);
        ASSERT_EQ(r.width, in.width);
        ASSERT_EQ(r.height, in.height);
        ASSERT_EQ(r.channels, c);
        for (int ch = 0; ch < c; ++ch) {
          std::vector<float> want(std::size_t(in.width * in.height));
          io::bc4_decode(io::bc4_encode(in.data.data() + ch, in.width, in.height, std::size_t(c)), in.width,
                         in.height, want.data(), 1);
          for (std::size_t k = 0; k < want.size(); ++k)
            ASSERT_EQ(r.data[k * std::size_t(c) + std::size_t(ch)], want[k]) << ext << " level " << i;
        }
      }
    }
    const auto d = bytes_of(dir / "t.dds");
    EXPECT_EQ(u32(d, 128), dxgi);
    EXPECT_TRUE(u32(d, 8) & 0x80000u);  // DDSD_LINEARSIZE
    EXPECT_FALSE(u32(d, 8) & 0x8u);     // not DDSD_PITCH
    EXPECT_EQ(u32(d, 20), 8 * block);   // dwPitchOrLinearSize: level 0, 4 × 2 blocks
    std::size_t total = 0;
    for (std::size_t b : blocks) total += b * block;
    EXPECT_EQ(d.size(), 148u + total);
    const auto k = bytes_of(dir / "t.ktx2");
    EXPECT_EQ(u32(k, 12), vk);
    EXPECT_EQ(u32(k, 16), 1u);  // typeSize
    const std::size_t dfd = u32(k, 48);
    EXPECT_EQ(u32(k, dfd), 4 + 24 + 16 * std::uint32_t(c));     // dfdTotalSize
    EXPECT_EQ(u32(k, dfd + 12) & 0xFFu, c == 1 ? 131u : 132u);  // colorModel
    EXPECT_EQ(u32(k, dfd + 16), 3u | (3u << 8));                // texelBlockDimension 4 × 4
    EXPECT_EQ(u32(k, dfd + 20), block);                         // bytesPlane0
    for (int s = 0; s < c; ++s) {
      const std::uint32_t w = u32(k, dfd + 28 + 16 * std::size_t(s));
      EXPECT_EQ(w & 0xFFFFu, 64u * std::uint32_t(s));                       // bitOffset
      EXPECT_EQ((w >> 16) & 0xFFu, 63u);                                    // bitLength − 1
      EXPECT_EQ(w >> 24, std::uint32_t(s));                                 // BC4_DATA / BC5 RED, GREEN
      EXPECT_EQ(u32(k, dfd + 28 + 16 * std::size_t(s) + 12), 0xFFFFFFFFu);  // sampleUpper
    }
    for (int i = 0; i < 5; ++i) {
      EXPECT_EQ(u64(k, 88 + 24 * std::size_t(i)), blocks[i] * block) << i;  // byteLength
      EXPECT_EQ(u64(k, 80 + 24 * std::size_t(i)) % block, 0u) << i;         // aligned
    }
    EXPECT_THROW(io::write_volume(dir / "v.ktx2", io::Volume(4, 4, 2, c), io::FileFormat::Ktx2, pf),
                 InputError);
    EXPECT_FALSE(fs::exists(dir / "v.ktx2"));
  }
  fs::remove_all(dir);
}
