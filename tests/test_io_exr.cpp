// EXR writer: read back with OpenEXR's own API (not our reader) and compared with an independent
// float→half rounding oracle; 3D volumes stored as stacked slices with the microshadow:depth attribute.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include <algorithm>
#include <bit>

#include "support/io_test_util.h"

namespace msh::io {
namespace {
using namespace test;

// IEEE binary16 decoded from its bit pattern by the textbook formula (no Imath).
double decode_half_bits(unsigned b) {
  const int sign = (b >> 15) & 1, e = (b >> 10) & 31, m = b & 1023;
  const double mag = e == 0 ? std::ldexp(double(m), -24) : std::ldexp(1.0 + m / 1024.0, e - 15);
  return sign ? -mag : mag;
}

// Nearest finite half to x, ties to the even bit pattern: a brute-force search over all finite halves.
struct HalfOracle {
  std::vector<std::pair<double, unsigned>> table;  // non-negative finite halves (value, bits), sorted
  HalfOracle() {
    for (unsigned b = 0; b < 65536; ++b)
      if (b < 0x8000 && ((b >> 10) & 31) != 31) table.push_back({decode_half_bits(b), b});
    std::sort(table.begin(), table.end());
  }
  double nearest(double x) const { return std::copysign(nearest_nonnegative(std::abs(x)), x); }
  double nearest_nonnegative(double x) const {
    auto it = std::lower_bound(table.begin(), table.end(), std::make_pair(x, 0u));
    if (it == table.end()) return std::prev(it)->first;
    if (it == table.begin()) return it->first;
    const auto lo = std::prev(it);
    const double dlo = x - lo->first, dhi = it->first - x;
    if (dlo < dhi) return lo->first;
    if (dhi < dlo) return it->first;
    return (lo->second & 1) == 0 ? lo->first : it->first;
  }
};

struct ExrData {
  int width = 0, height = 0, depth_attr = -1, slice_attr = -1;
  std::vector<std::string> channels;
  std::vector<Imf::PixelType> types;
  std::vector<float> data;  // interleaved in `channels` order
};

ExrData read_with_openexr(const std::filesystem::path& p) {
  Imf::InputFile in(p.c_str());
  const Imf::Header& h = in.header();
  ExrData r;
  const auto dw = h.dataWindow();
  EXPECT_EQ(dw.min.x, 0);
  EXPECT_EQ(dw.min.y, 0);
  r.width = dw.max.x + 1;
  r.height = dw.max.y + 1;
  if (auto* a = h.findTypedAttribute<Imf::IntAttribute>("microshadow:depth")) r.depth_attr = a->value();
  if (auto* a = h.findTypedAttribute<Imf::IntAttribute>("microshadow:sliceHeight")) r.slice_attr = a->value();
  for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
    r.channels.push_back(it.name());
    r.types.push_back(it.channel().type);
  }
  const int c = int(r.channels.size());
  r.data.resize(std::size_t(r.width) * r.height * c);
  Imf::FrameBuffer fb;
  for (int k = 0; k < c; ++k)
    fb.insert(r.channels[k], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(r.data.data() + k),
                                        sizeof(float) * c, sizeof(float) * c * r.width));
  in.setFrameBuffer(fb);
  in.readPixels(0, r.height - 1);
  return r;
}

// OpenEXR lists channels alphabetically; map our channel k to its name.
std::string channel_name(int channels, int k) {
  if (channels == 1) return "Y";
  return std::string(1, "RGBA"[k]);
}

TEST(IoExr, OpenExrReadsEveryValueHalfAndFloat) {
  const auto dir = scratch_dir();
  const HalfOracle oracle;
  for (bool half : {true, false})
    for (int c = 1; c <= 4; ++c)
      for (auto [w, h, d] : {std::tuple{5, 3, 1}, std::tuple{7, 4, 3}}) {
        SCOPED_TRACE(fmt::format("half={} c={} {}x{}x{}", half, c, w, h, d));
        Volume v = make_volume(w, h, d, c, -500.f, 500.f);
        v.data.back() = 65519.f;  // rounds to 65504 in half
        const auto file = dir / fmt::format("h{}_c{}_d{}.exr", half, c, d);
        if (d == 1)
          write_exr(file, v, half);
        else
          write_volume(file, v, FileFormat::Exr, half ? PixelFormat::RGBA16Float : PixelFormat::RGBA32Float);
        const ExrData r = read_with_openexr(file);
        ASSERT_EQ(r.width, w);
        ASSERT_EQ(r.height, h * d);  // slices stacked vertically
        EXPECT_EQ(r.depth_attr, d);
        EXPECT_EQ(r.slice_attr, h);
        ASSERT_EQ(int(r.channels.size()), c);
        for (auto t : r.types) EXPECT_EQ(t, half ? Imf::HALF : Imf::FLOAT);
        for (int z = 0; z < d; ++z)
          for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
              for (int k = 0; k < c; ++k) {
                const auto pos = std::find(r.channels.begin(), r.channels.end(), channel_name(c, k));
                ASSERT_NE(pos, r.channels.end());
                const int kk = int(pos - r.channels.begin());
                const float got = r.data[(std::size_t(z * h + y) * w + x) * c + kk];
                const float src = v.at(x, y, z, k);
                const double want = half ? oracle.nearest(src) : double(src);
                ASSERT_EQ(std::bit_cast<std::uint32_t>(got), std::bit_cast<std::uint32_t>(float(want)))
                    << "x=" << x << " y=" << y << " z=" << z << " c=" << k << " src=" << src;
              }
        // And our reader reconstructs the volume with the same values.
        const Volume back = d == 1 ? read_image(file) : read_volume(file);
        ASSERT_EQ(back.depth, d);
        ASSERT_EQ(back.channels, c);
        for (std::size_t i = 0; i < v.data.size(); ++i) {
          const double want = half ? oracle.nearest(v.data[i]) : double(v.data[i]);
          ASSERT_EQ(double(back.data[i]), want) << i;
        }
      }
}

TEST(IoExr, ReadsForeignFilesWrittenWithOpenExr) {
  // An RGBA half file with a data window not at the origin, written directly with OpenEXR.
  const auto dir = scratch_dir();
  const int w = 4, h = 3;
  Imf::Header header(Imath::Box2i({0, 0}, {w - 1, h - 1}), Imath::Box2i({10, 20}, {10 + w - 1, 20 + h - 1}));
  for (const char* n : {"R", "G", "B", "A"}) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
  std::vector<float> px(w * h * 4);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = float(i) * 0.5f - 3.f;
  Imf::FrameBuffer fb;
  for (int k = 0; k < 4; ++k)
    fb.insert(std::string(1, "RGBA"[k]),
              Imf::Slice::Make(Imf::FLOAT, px.data() + k, header.dataWindow(), 16, 16 * w));
  {
    Imf::OutputFile out((dir / "f.exr").c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(h);
  }
  const Volume v = read_image(dir / "f.exr");
  EXPECT_EQ(v.width, w);
  EXPECT_EQ(v.height, h);
  EXPECT_EQ(v.channels, 4);
  for (std::size_t i = 0; i < px.size(); ++i) EXPECT_EQ(v.data[i], px[i]);
}

TEST(IoExr, NonFiniteAndOverflowAreErrors) {
  const auto dir = scratch_dir();
  Volume v = make_volume(3, 3, 1, 3, 0.f, 1.f);
  v.data[4] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(write_exr(dir / "a.exr", v, false), InputError);
  v.data[4] = 1e5f;
  EXPECT_THROW(write_exr(dir / "a.exr", v, true), InputError);  // half overflow
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  write_exr(dir / "a.exr", v, false);  // float holds it
  EXPECT_EQ(read_image(dir / "a.exr").data[4], 1e5f);
}

}  // namespace
}  // namespace msh::io
