// PNG writer/reader: written files decoded by an independent Python PNG decoder (zlib + unfiltering, CRCs
// checked); PNGs written by an independent Python encoder (gray, GA, RGB, RGBA, 8/16 bit, palette + tRNS)
// read by our libpng reader.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include "support/io_test_util.h"

namespace msh::io {
namespace {
using namespace test;

TEST(IoPng, PythonDecodesEverySample) {
  const auto dir = scratch_dir();
  PythonBatch batch(dir / "checks.txt");
  for (int bits : {8, 16})
    for (int c = 1; c <= 4; ++c)
      for (auto [w, h, d] : {std::tuple{5, 3, 1}, std::tuple{9, 4, 3}, std::tuple{1, 1, 1}}) {
        SCOPED_TRACE(fmt::format("bits={} c={} {}x{}x{}", bits, c, w, h, d));
        const Volume v = make_volume(w, h, d, c, -0.1f, 1.1f);
        const std::string stem = fmt::format("b{}_c{}_{}x{}x{}", bits, c, w, h, d);
        const auto file = dir / (stem + ".png"), raw = dir / (stem + ".raw");
        if (d == 1)
          write_png(file, v, bits);
        else
          write_volume(file, v, FileFormat::Png,
                       bits == 8 ? PixelFormat::RGBA8Unorm : PixelFormat::RGBA16Float);
        write_raw(raw, v);
        batch.add(fmt::format("png {} {} {} {} {} {} {}", quote(file), quote(raw), d, h, w, c, bits));
        // libpng round trip: within half a code value of the saturated source.
        const Volume r = d == 1 ? read_image(file) : read_volume(file);
        ASSERT_EQ(r.width, w);
        ASSERT_EQ(r.height, h);
        ASSERT_EQ(r.depth, d);
        ASSERT_EQ(r.channels, c);
        const float tol = 0.5f / float((1 << bits) - 1) + 1e-7f;
        for (std::size_t i = 0; i < v.data.size(); ++i)
          ASSERT_LE(std::abs(std::clamp(v.data[i], 0.f, 1.f) - r.data[i]), tol) << i;
      }
  batch.run_all();
}

TEST(IoPng, ReadsPngsFromAnIndependentEncoder) {
  const auto dir = scratch_dir();
  struct Case {
    int c, bits;
    bool palette;
  };
  for (const Case& k : {Case{1, 8, false}, Case{2, 16, false}, Case{3, 8, false}, Case{4, 16, false},
                        Case{1, 16, false}, Case{3, 8, true}, Case{4, 8, true}}) {
    SCOPED_TRACE(fmt::format("c={} bits={} palette={}", k.c, k.bits, k.palette));
    const int w = 6, h = 5;
    const Volume v = make_volume(w, h, 1, k.c, 0.f, 1.f);
    const std::string stem = fmt::format("in_c{}_b{}_p{}", k.c, k.bits, k.palette);
    const auto file = dir / (stem + ".png"), raw = dir / (stem + ".raw");
    write_raw(raw, v);
    std::string out;
    ASSERT_EQ(run(fmt::format("{} {} make-png {} {} {} {} {} {} {}", kPython, checker(), quote(file),
                              quote(raw), h, w, k.c, k.bits, k.palette ? "palette" : ""),
                  &out),
              0)
        << out;
    std::vector<float> expected(v.data.size());
    std::ifstream(dir / (stem + ".png.expected.raw"), std::ios::binary)
        .read(reinterpret_cast<char*>(expected.data()), std::streamsize(expected.size() * 4));
    const Volume r = read_image(file);
    ASSERT_EQ(r.width, w);
    ASSERT_EQ(r.height, h);
    ASSERT_EQ(r.channels, k.c);  // palette expands to RGB, tRNS to alpha
    for (std::size_t i = 0; i < expected.size(); ++i) ASSERT_NEAR(r.data[i], expected[i], 1e-6) << i;
  }
}

}  // namespace
}  // namespace msh::io
