// DDS and KTX2 writers: every header field and every texel checked by an independent Python parser written
// from the specifications (tests/support/msh_iocheck.py), then read back by our reader.
#include <Imath/half.h>
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include "support/io_test_util.h"

namespace msh::io {
namespace {
using namespace test;

const PixelFormat kAll[] = {PixelFormat::RGBA8Unorm, PixelFormat::RGBA16Float, PixelFormat::RGBA32Float,
                            PixelFormat::RG16Float,  PixelFormat::RG32Float,   PixelFormat::R16Float,
                            PixelFormat::R32Float,   PixelFormat::R8Unorm,     PixelFormat::RG8Unorm};

struct Dims {
  int w, h, d;
};
const Dims kDims[] = {{5, 3, 1}, {7, 5, 3}, {1, 1, 1}, {3, 1, 2}};

// UNORM values span [-0.2, 1.2] to exercise saturation; float values span [-300, 300] (within half range).
Volume test_volume(PixelFormat pf, Dims k) {
  const int c = pixel_format_channels(pf);
  const bool unorm =
      pf == PixelFormat::RGBA8Unorm || pf == PixelFormat::R8Unorm || pf == PixelFormat::RG8Unorm;
  return unorm ? make_volume(k.w, k.h, k.d, c, -0.2f, 1.2f) : make_volume(k.w, k.h, k.d, c, -300.f, 300.f);
}

void check_format(FileFormat ff, const char* ext, const char* cmd) {
  const auto dir = scratch_dir();
  PythonBatch batch(dir / "checks.txt");
  for (PixelFormat pf : kAll)
    for (Dims k : kDims) {
      SCOPED_TRACE(fmt::format("{} {}x{}x{}", pixel_format_name(pf), k.w, k.h, k.d));
      const Volume v = test_volume(pf, k);
      // Fresh names each case: replacing files (rename over, truncate) makes ext4 flush, slow on a shared
      // disk.
      const std::string stem = fmt::format("{}_{}x{}x{}", pixel_format_name(pf), k.w, k.h, k.d);
      const auto file = dir / (stem + "." + ext), raw = dir / (stem + ".raw");
      write_volume(file, v, ff, pf);
      write_raw(raw, v);
      batch.add(fmt::format("{} {} {} {} {} {} {} {}", cmd, quote(file), quote(raw), k.d, k.h, k.w,
                            v.channels, pixel_format_name(pf)));
      // Our reader returns the stored values: float32 exact, half = the stored half, UNORM = q/255.
      const Volume r = read_volume(file);
      ASSERT_EQ(r.width, k.w);
      ASSERT_EQ(r.height, k.h);
      ASSERT_EQ(r.depth, k.d);
      ASSERT_EQ(r.channels, v.channels);
      for (std::size_t i = 0; i < v.data.size(); ++i) {
        const float x = v.data[i], y = r.data[i];
        switch (pf) {
          case PixelFormat::RGBA32Float:
          case PixelFormat::RG32Float:
          case PixelFormat::R32Float:
            ASSERT_EQ(std::bit_cast<std::uint32_t>(x), std::bit_cast<std::uint32_t>(y));
            break;
          case PixelFormat::RGBA8Unorm:
          case PixelFormat::R8Unorm:
          case PixelFormat::RG8Unorm: {
            ASSERT_LE(std::abs(std::clamp(x, 0.f, 1.f) - y), 0.5f / 255.f + 1e-7f) << i;
            const double q = double(y) * 255.0;
            ASSERT_NEAR(q, std::round(q), 1e-4) << i;  // a code value
            break;
          }
          default:
            // Within half an ulp of half precision (relative 2^-11), or the subnormal spacing 2^-24 / 2.
            ASSERT_LE(std::abs(x - y), std::max(std::abs(x) * 0x1p-11f, 0x1p-25f)) << i;
        }
      }
    }
  batch.run_all();
}

TEST(IoDds, HeaderAndTexelsMatchSpec) { check_format(FileFormat::Dds, "dds", "dds"); }
TEST(IoKtx2, HeaderDfdKvdAndTexelsMatchSpec) { check_format(FileFormat::Ktx2, "ktx2", "ktx2"); }

// Our readers on files from the independent Python encoders (DDS without the optional PITCH/MIPMAPCOUNT
// flags, KTX2 with two key/value entries): every value equals the stored value decoded by numpy.
void read_foreign(const char* cmd, const char* ext) {
  const auto dir = scratch_dir();
  PythonBatch batch(dir / "make.txt");
  std::vector<std::tuple<std::string, PixelFormat, Dims>> files;
  for (PixelFormat pf : kAll)
    for (Dims k : kDims) {
      const Volume v = test_volume(pf, k);
      const std::string stem = fmt::format("{}_{}x{}x{}", pixel_format_name(pf), k.w, k.h, k.d);
      write_raw(dir / (stem + ".raw"), v);
      batch.add(fmt::format("{} {} {} {} {} {} {} {}", cmd, quote(dir / (stem + ext)),
                            quote(dir / (stem + ".raw")), k.d, k.h, k.w, v.channels, pixel_format_name(pf)));
      files.emplace_back(stem, pf, k);
    }
  batch.run_all();
  for (const auto& [stem, pf, k] : files) {
    SCOPED_TRACE(stem);
    const Volume r = read_volume(dir / (stem + ext));
    ASSERT_EQ(r.width, k.w);
    ASSERT_EQ(r.height, k.h);
    ASSERT_EQ(r.depth, k.d);
    ASSERT_EQ(r.channels, pixel_format_channels(pf));
    std::vector<float> want(r.data.size());
    std::ifstream(dir / (stem + ext + ".expected.raw"), std::ios::binary)
        .read(reinterpret_cast<char*>(want.data()), std::streamsize(want.size() * 4));
    for (std::size_t i = 0; i < want.size(); ++i)
      ASSERT_NEAR(r.data[i], want[i], 1e-7 * std::abs(want[i])) << i;
  }
}

TEST(IoDds, ReadsFilesFromAnIndependentEncoder) { read_foreign("make-dds", ".dds"); }
TEST(IoKtx2, ReadsFilesFromAnIndependentEncoder) { read_foreign("make-ktx2", ".ktx2"); }

TEST(IoDdsKtx2, HalfOverflowIsAnErrorNothingWritten) {
  const auto dir = scratch_dir();
  Volume v = make_volume(2, 2, 1, 4, 0.f, 1.f);
  v.data[5] = 70000.f;  // > 65504: would become +inf in half
  EXPECT_THROW(write_volume(dir / "a.dds", v, FileFormat::Dds, PixelFormat::RGBA16Float), InputError);
  EXPECT_THROW(write_volume(dir / "a.ktx2", v, FileFormat::Ktx2, PixelFormat::RGBA16Float), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "a.dds"));
  EXPECT_FALSE(std::filesystem::exists(dir / "a.ktx2"));
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  // 65504 itself is representable and 65519 rounds down to it (ties-to-even boundary is 65520).
  v.data[5] = 65519.f;
  write_volume(dir / "b.dds", v, FileFormat::Dds, PixelFormat::RGBA16Float);
  EXPECT_EQ(read_volume(dir / "b.dds").data[5], 65504.f);
}

}  // namespace
}  // namespace msh::io
