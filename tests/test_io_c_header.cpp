// C header writer: the generated header is compiled by the system C and C++ compilers into a program that
// dumps the array bytes and the #defines; every value must round-trip bit for bit.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>

#include <bit>
#include <cfloat>

#include "support/io_test_util.h"

namespace msh::io {
namespace {
using namespace test;

void compile_and_compare(const char* compiler, const char* std_flag) {
  const auto dir = scratch_dir();
  Volume v = make_volume(5, 3, 2, 3, -1e4f, 1e4f);
  // Values whose decimal form is delicate: extremes, subnormals, integers, negative zero.
  const float tricky[] = {FLT_MAX,     -FLT_MAX, FLT_MIN,  std::numeric_limits<float>::denorm_min(),
                          1e-40f,      -0.0f,    1.0f,     123456792.0f,
                          0.1f,        1.0f / 3, 16777216, -2.5e-38f,
                          0.99999994f, 1e10f,    65504.f,  3.4028233e38f};
  for (std::size_t i = 0; i < std::size(tricky); ++i) v.data[i] = tricky[i];
  write_volume(dir / "table.h", v, FileFormat::CHeader, PixelFormat::RGBA32Float, "my_table");
  std::ofstream(dir / "main.c")
      << "#include <stdio.h>\n#include \"table.h\"\n"
         "int main(void) {\n"
         "  FILE* f = fopen(\"out.bin\", \"wb\");\n"
         "  if (!f) return 1;\n"
         "  fwrite(my_table, 1, sizeof my_table, f);\n"
         "  fclose(f);\n"
         "  printf(\"%d %d %d %d %d\\n\", MY_TABLE_WIDTH, MY_TABLE_HEIGHT, MY_TABLE_DEPTH,\n"
         "         MY_TABLE_CHANNELS, (int)(sizeof my_table / sizeof(float)));\n"
         "  return 0;\n}\n";
  std::string out;
  const std::string cmd =
      fmt::format("cd {} && {} {} -x {} -Wall -Wextra -pedantic -Werror main.c -o prog && ./prog", quote(dir),
                  compiler, std_flag, std::string(compiler) == "cc" ? "c" : "c++");
  ASSERT_EQ(run(cmd, &out), 0) << cmd << "\n" << out;
  EXPECT_EQ(out, fmt::format("5 3 2 3 {}\n", v.data.size()));
  std::ifstream f(dir / "out.bin", std::ios::binary);
  std::vector<float> got(v.data.size() + 1);
  f.read(reinterpret_cast<char*>(got.data()), std::streamsize(got.size() * 4));
  ASSERT_EQ(std::size_t(f.gcount()), v.data.size() * 4);
  for (std::size_t i = 0; i < v.data.size(); ++i)
    ASSERT_EQ(std::bit_cast<std::uint32_t>(got[i]), std::bit_cast<std::uint32_t>(v.data[i]))
        << "index " << i << " wrote " << v.data[i] << " read " << got[i];
}

TEST(IoCHeader, CompilesAsCAndRoundTripsExactly) { compile_and_compare("cc", "-std=c99"); }
TEST(IoCHeader, CompilesAsCxxAndRoundTripsExactly) { compile_and_compare("c++", "-std=c++17"); }

TEST(IoCHeader, RejectsBadSymbolAndNonFinite) {
  const auto dir = scratch_dir();
  Volume v = make_volume(2, 2, 1, 1, 0.f, 1.f);
  EXPECT_THROW(write_volume(dir / "a.h", v, FileFormat::CHeader, PixelFormat::R32Float, "1abc"), InputError);
  EXPECT_THROW(write_volume(dir / "a.h", v, FileFormat::CHeader, PixelFormat::R32Float, "a-b"), InputError);
  v.data[2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(write_volume(dir / "a.h", v, FileFormat::CHeader, PixelFormat::R32Float, "ok"), InputError);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  EXPECT_THROW(read_volume(dir / "a.h"), InputError);
}

}  // namespace
}  // namespace msh::io
