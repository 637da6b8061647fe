// Bad input for every io format: unwritable paths, NaN, wrong channel counts, unknown names, and truncated or
// corrupted files (every prefix length and random byte flips): always InputError, never a crash or a file.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/names.h>
#include <microshadow/io/texture.h>

#include "support/io_test_util.h"

namespace msh::io {
namespace {
using namespace test;
namespace fs = std::filesystem;

// Every file format with the extension its files are written under.
struct FormatExt {
  FileFormat format;
  const char* ext;
};
constexpr FormatExt kFormatExts[] = {{FileFormat::Dds, ".dds"},   {FileFormat::Ktx2, ".ktx2"},
                                     {FileFormat::Exr, ".exr"},   {FileFormat::Npy, ".npy"},
                                     {FileFormat::CHeader, ".h"}, {FileFormat::Png, ".png"}};
const char* ext(FileFormat f) {
  for (const FormatExt& fe : kFormatExts)
    if (fe.format == f) return fe.ext;
  return "";
}

TEST(IoErrors, Names) {
  EXPECT_EQ(file_format_from_path("a/b.KTX2"), FileFormat::Ktx2);
  EXPECT_EQ(file_format_from_path("x.hpp"), FileFormat::CHeader);
  EXPECT_EQ(file_format_from_name("npy"), FileFormat::Npy);
  EXPECT_EQ(pixel_format_from_name("rg16f"), PixelFormat::RG16Float);
  EXPECT_EQ(pixel_format_from_name("R8"), PixelFormat::R8Unorm);
  EXPECT_THROW(file_format_from_path("a.tga"), InputError);
  EXPECT_THROW(file_format_from_path("noext"), InputError);
  EXPECT_THROW(file_format_from_name("jpeg"), InputError);
  EXPECT_THROW(pixel_format_from_name("rgb8"), InputError);
  EXPECT_THROW(read_image("x.dds"), InputError);
  for (const char* n : {"rgba8", "rgba16f", "rgba32f", "rg16f", "rg32f", "r16f", "r32f", "r8", "rg8"})
    EXPECT_EQ(pixel_format_name(pixel_format_from_name(n)), n);
}

// io/names.h: one table per enum gives both directions, and the unknown-name error lists the table.
TEST(IoErrors, NameTables) {
  enum class Fruit { Apple, Pear, Plum };
  constexpr Named<Fruit> kFruits[] = {{Fruit::Apple, "apple"}, {Fruit::Pear, "pear"}};
  for (const Named<Fruit>& n : kFruits) {
    EXPECT_STREQ(name_of<Fruit>(kFruits, n.value), n.name);
    EXPECT_EQ(value_of<Fruit>(kFruits, n.name, "fruit"), n.value);
  }
  EXPECT_STREQ(name_of<Fruit>(kFruits, Fruit::Plum), "?");  // not in the table
  EXPECT_EQ(names_of<Fruit>(kFruits), "apple, pear");
  try {
    value_of<Fruit>(kFruits, "Apple", "fruit");  // names are exact: no case folding
    ADD_FAILURE() << "accepted 'Apple'";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "unknown fruit 'Apple' (known: apple, pear)");
  }
}

TEST(IoErrors, UnwritableDirectoryNaNAndChannelMismatchLeaveNoFile) {
  const auto dir = scratch_dir();
  const Volume v = make_volume(4, 3, 2, 4, 0.f, 1.f);
  for (const FormatExt& fe : kFormatExts) {
    const FileFormat f = fe.format;
    SCOPED_TRACE(ext(f));
    EXPECT_THROW(write_volume(dir / "missing" / (std::string("a") + ext(f)), v, f), InputError);
    Volume nan = v;
    nan.data[7] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(write_volume(dir / (std::string("a") + ext(f)), nan, f), InputError);
    nan.data[7] = -std::numeric_limits<float>::infinity();
    EXPECT_THROW(write_volume(dir / (std::string("a") + ext(f)), nan, f), InputError);
    Volume bad = v;
    bad.data.pop_back();  // size inconsistent with the dimensions
    EXPECT_THROW(write_volume(dir / (std::string("a") + ext(f)), bad, f), InputError);
    Volume empty;
    EXPECT_THROW(write_volume(dir / (std::string("a") + ext(f)), empty, f), InputError);
  }
  // Channel count must match the pixel format for DDS/KTX2.
  EXPECT_THROW(write_volume(dir / "a.dds", v, FileFormat::Dds, PixelFormat::RG16Float), InputError);
  EXPECT_THROW(write_volume(dir / "a.ktx2", v, FileFormat::Ktx2, PixelFormat::R8Unorm), InputError);
  // EXR and PNG take 1..4 channels.
  const Volume five = make_volume(2, 2, 1, 5, 0.f, 1.f);
  EXPECT_THROW(write_exr(dir / "a.exr", five), InputError);
  EXPECT_THROW(write_png(dir / "a.png", five), InputError);
  EXPECT_THROW(write_png(dir / "a.png", make_volume(2, 2, 1, 3, 0.f, 1.f), 12), InputError);
  EXPECT_TRUE(fs::is_empty(dir)) << "a failed write left a file behind";
}

TEST(IoErrors, FailedWriteKeepsThePreviousFile) {
  const auto dir = scratch_dir();
  const Volume v = make_volume(3, 2, 1, 4, 0.f, 1.f);
  write_volume(dir / "a.npy", v, FileFormat::Npy);
  Volume nan = v;
  nan.data[0] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(write_volume(dir / "a.npy", nan, FileFormat::Npy), InputError);
  EXPECT_EQ(read_volume(dir / "a.npy").data, v.data);
}

std::vector<char> slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}
// Removes the file before rewriting it: truncating a file in place makes ext4 flush it (auto_da_alloc), slow.
void dump(const fs::path& p, const std::vector<char>& b, std::size_t n) {
  fs::remove(p);
  std::ofstream(p, std::ios::binary).write(b.data(), std::streamsize(n));
}

// Every truncation (all prefix lengths up to 512 bytes, then a stride) of a valid file: InputError or a
// well-formed volume, never a crash. Then random byte corruptions of the header region.
TEST(IoErrors, TruncatedAndCorruptFilesAreInputErrors) {
  const auto dir = scratch_dir();
  const Volume v = make_volume(6, 5, 3, 4, 0.f, 1.f);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&] {
    return state = state * 6364136223846793005ull + 1442695040888963407ull, unsigned(state >> 33);
  };
  for (FileFormat f :
       {FileFormat::Dds, FileFormat::Ktx2, FileFormat::Exr, FileFormat::Npy, FileFormat::Png}) {
    SCOPED_TRACE(ext(f));
    const fs::path good = dir / (std::string("good") + ext(f)), bad = dir / (std::string("bad") + ext(f));
    write_volume(good, v, f, f == FileFormat::Png ? PixelFormat::RGBA8Unorm : PixelFormat::RGBA16Float);
    const std::vector<char> bytes = slurp(good);
    ASSERT_GT(bytes.size(), 64u);
    int errors = 0;
    for (std::size_t n = 0; n < bytes.size(); n += (n < 512 ? 1 : 97)) {
      dump(bad, bytes, n);
      try {
        const Volume r = read_volume(bad);
        ADD_FAILURE() << "truncated to " << n << " of " << bytes.size() << " bytes but read " << r.width
                      << "x" << r.height;
      } catch (const InputError& e) {
        ++errors;
        EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << "error must name the file";
      }
    }
    EXPECT_GT(errors, 0);
    for (int trial = 0; trial < 300; ++trial) {
      std::vector<char> c = bytes;
      const std::size_t span = std::min<std::size_t>(c.size(), 256);
      for (int k = 0; k < 3; ++k) c[next() % span] = char(next());
      dump(bad, c, c.size());
      try {
        const Volume r = read_volume(bad);  // a corrupted but still decodable file is fine
        EXPECT_EQ(r.data.size(), r.texel_count() * std::size_t(r.channels));
      } catch (const InputError&) {
      }
    }
  }
  EXPECT_THROW(read_volume(dir / "does_not_exist.npy"), InputError);
  EXPECT_THROW(read_image(dir / "does_not_exist.png"), InputError);
  EXPECT_THROW(read_image(dir / "does_not_exist.exr"), InputError);
}

}  // namespace
}  // namespace msh::io
