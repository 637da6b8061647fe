// Mip chains in DDS and KTX2 (io::write_texture_mips, io::read_texture_level): every level reads back, the
// files follow the containers' layout rules checked here byte by byte (not through our reader), and a chain
// of wrong sizes is refused without a file.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
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
