// NPY writer/reader: files read back by numpy (independent) and compared bit for bit with the source.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include "support/io_test_util.h"

namespace msh::io {
namespace {
using namespace test;

TEST(IoNpy, NumpyReadsEveryValue) {
  const auto dir = scratch_dir();
  PythonBatch batch(dir / "checks.txt");
  struct Case {
    int w, h, d, c;
  };
  for (const Case& k :
       {Case{5, 3, 1, 4}, Case{7, 5, 3, 4}, Case{1, 1, 1, 1}, Case{4, 6, 2, 2}, Case{3, 2, 5, 7}}) {
    Volume v = make_volume(k.w, k.h, k.d, k.c, -1e3f, 1e3f);
    v.data.back() = std::numeric_limits<float>::denorm_min();
    const std::string stem = fmt::format("{}x{}x{}x{}", k.w, k.h, k.d, k.c);
    const auto npy = dir / (stem + ".npy"), raw = dir / (stem + ".raw");
    write_volume(npy, v, FileFormat::Npy);
    write_raw(raw, v);
    batch.add(fmt::format("npy {} {} {} {} {} {}", quote(npy), quote(raw), k.d, k.h, k.w, k.c));
  }
  batch.run_all();
}

TEST(IoNpy, ReadsBackExactlyAndNumpyFiles) {
  const auto dir = scratch_dir();
  const Volume v = make_volume(6, 4, 3, 4, -2.f, 5.f);
  write_volume(dir / "a.npy", v, FileFormat::Npy);
  const Volume r = read_volume(dir / "a.npy");
  EXPECT_EQ(r.width, 6);
  EXPECT_EQ(r.height, 4);
  EXPECT_EQ(r.depth, 3);
  EXPECT_EQ(r.channels, 4);
  ASSERT_EQ(r.data.size(), v.data.size());
  EXPECT_EQ(0, std::memcmp(r.data.data(), v.data.data(), v.data.size() * 4));

  // Files written by numpy itself: (H, W, C) float32, (H, W) float64, (D, H, W, C) float32; value = formula.
  std::string out;
  const std::string py = fmt::format(
      "import numpy as np\n"
      "d='{}'\n"
      "np.save(d+'/hwc.npy', np.arange(2*3*4, dtype='<f4').reshape(2,3,4) * 0.25)\n"
      "np.save(d+'/hw.npy', np.arange(2*3, dtype='<f8').reshape(2,3) / 3)\n"
      "np.save(d+'/dhwc.npy', (np.arange(2*3*4*2, dtype='<f4') - 7).reshape(2,3,4,2))\n",
      dir.string());
  std::ofstream(dir / "gen.py") << py;
  ASSERT_EQ(run(fmt::format("{} {}", kPython, quote(dir / "gen.py")), &out), 0) << out;
  const Volume hwc = read_volume(dir / "hwc.npy");
  EXPECT_EQ(hwc.width, 3);
  EXPECT_EQ(hwc.height, 2);
  EXPECT_EQ(hwc.depth, 1);
  EXPECT_EQ(hwc.channels, 4);
  for (std::size_t i = 0; i < hwc.data.size(); ++i) EXPECT_EQ(hwc.data[i], float(i) * 0.25f);
  const Volume hw = read_volume(dir / "hw.npy");
  EXPECT_EQ(hw.channels, 1);
  EXPECT_EQ(hw.width, 3);
  for (std::size_t i = 0; i < hw.data.size(); ++i) EXPECT_EQ(hw.data[i], float(double(i) / 3.0));
  const Volume dhwc = read_volume(dir / "dhwc.npy");
  EXPECT_EQ(dhwc.depth, 2);
  EXPECT_EQ(dhwc.channels, 2);
  EXPECT_EQ(dhwc.at(3, 2, 1, 1), float(((1 * 3 + 2) * 4 + 3) * 2 + 1 - 7));
}

}  // namespace
}  // namespace msh::io
