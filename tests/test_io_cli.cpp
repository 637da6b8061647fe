// `microshadow convert`: round trip through every format, exit code 2 and no file on bad input.
#include <gtest/gtest.h>
#include <microshadow/io/texture.h>

#include "support/io_test_util.h"

namespace msh::io {
namespace {
using namespace test;

TEST(IoCli, ConvertRoundTripAndErrors) {
  const auto dir = scratch_dir();
  const Volume v = make_volume(5, 4, 3, 4, 0.f, 1.f);
  write_volume(dir / "src.npy", v, FileFormat::Npy);
  std::string out;
  auto cli = [&](const std::string& args) { return run(fmt::format("{} {}", MSH_CLI_PATH, args), &out); };
  // npy → exr (float) → ktx2 (rgba32f) → dds (rgba32f) → npy: exact.
  ASSERT_EQ(
      cli(fmt::format("convert {} {} --pixel-format rgba32f", quote(dir / "src.npy"), quote(dir / "a.exr"))),
      0)
      << out;
  ASSERT_EQ(
      cli(fmt::format("convert {} {} --pixel-format rgba32f", quote(dir / "a.exr"), quote(dir / "a.ktx2"))),
      0)
      << out;
  ASSERT_EQ(
      cli(fmt::format("convert {} {} --pixel-format rgba32f", quote(dir / "a.ktx2"), quote(dir / "a.dds"))),
      0)
      << out;
  ASSERT_EQ(cli(fmt::format("convert {} {}", quote(dir / "a.dds"), quote(dir / "b.npy"))), 0) << out;
  EXPECT_NE(out.find("\"depth\":3"), std::string::npos) << out;
  EXPECT_EQ(read_volume(dir / "b.npy").data, v.data);
  // Default pixel format: half floats.
  ASSERT_EQ(cli(fmt::format("convert {} {} --format ktx2", quote(dir / "src.npy"), quote(dir / "c.bin"))), 0)
      << out;
  EXPECT_NE(out.find("rgba16f"), std::string::npos) << out;

  const auto before = std::distance(std::filesystem::directory_iterator(dir), {});
  EXPECT_EQ(cli(fmt::format("convert {} {}", quote(dir / "missing.npy"), quote(dir / "x.dds"))), 2) << out;
  EXPECT_EQ(cli(fmt::format("convert {} {}", quote(dir / "src.npy"), quote(dir / "x.tga"))), 2) << out;
  EXPECT_EQ(
      cli(fmt::format("convert {} {} --pixel-format rg16f", quote(dir / "src.npy"), quote(dir / "x.dds"))), 2)
      << out;
  EXPECT_EQ(
      cli(fmt::format("convert {} {} --pixel-format bogus", quote(dir / "src.npy"), quote(dir / "x.dds"))), 2)
      << out;
  EXPECT_EQ(cli(fmt::format("convert {} {}", quote(dir / "src.npy"), quote(dir / "no" / "x.dds"))), 2) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << "one-line error: " << out;
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), before)
      << "a failed convert left a file";
  EXPECT_EQ(cli("convert --help"), 0);
}

}  // namespace
}  // namespace msh::io
