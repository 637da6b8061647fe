// Hostile files for the readers (issue 35, item 5): text named .png, FIFOs, devices and symlinks to them,
// DDS/KTX2 files longer or shorter than their header says, float textures with NaN texels, and headers
// claiming absurd dimensions. Always an InputError naming the file, never a hang, a crash or a huge read.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/render/scene.h>
#include <microshadow/render/texture_gen.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stop_token>
#include <thread>

#include "support/io_test_util.h"

namespace msh::io {
namespace {
using namespace test;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::vector<char> read_all(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
void write_all(const fs::path& p, const std::vector<char>& b) {
  fs::remove(p);
  std::ofstream f(p, std::ios::binary);
  f.write(b.data(), std::streamsize(b.size()));
}
// v written in pixel format pf as stem.dds and as stem.ktx2: their paths.
std::vector<fs::path> write_dds_and_ktx2(const fs::path& stem, const Volume& v, PixelFormat pf) {
  std::vector<fs::path> paths;
  for (FileFormat f : {FileFormat::Dds, FileFormat::Ktx2}) {
    paths.push_back(stem.string() + (f == FileFormat::Dds ? ".dds" : ".ktx2"));
    write_volume(paths.back(), v, f, pf);
  }
  return paths;
}

std::uint32_t u32_at(const std::vector<char>& b, std::size_t o) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + o, 4);
  return v;
}
void put_u32_at(std::vector<char>& b, std::size_t o, std::uint32_t v) { std::memcpy(b.data() + o, &v, 4); }

// f() must throw an InputError whose message contains `path` and `needle`.
template <class F>
void expect_input_error(F&& f, const fs::path& path, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << path << ": no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path.string()), std::string::npos) << m;
    EXPECT_NE(m.find(needle), std::string::npos) << m;
  }
}

TEST(IoHostile, TextNamedPngIsNotAPng) {
  const auto dir = scratch_dir();
  const fs::path p = dir / "text.png";
  const std::string text = "hello, this is a text file and not an image at all\n";
  write_all(p, std::vector<char>(text.begin(), text.end()));
  expect_input_error([&] { render::load_height_map(p); }, p, "not a PNG file");
  expect_input_error([&] { read_image(p); }, p, "not a PNG file");
  // A real signature and IHDR with a bit depth / colour type the PNG spec does not have.
  write_volume(dir / "good.png", make_volume(8, 8, 1, 1, 0.f, 1.f), FileFormat::Png, PixelFormat::RGBA8Unorm);
  std::vector<char> b = read_all(dir / "good.png");
  for (auto [bits, type] : {std::pair{104, 0}, std::pair{16, 5}, std::pair{3, 0}}) {
    b[24] = char(bits), b[25] = char(type);
    write_all(p, b);
    expect_input_error([&] { render::load_height_map(p); }, p, "corrupt PNG header");
    EXPECT_THROW(read_image(p), InputError);
  }
}

// Unblocks a reader stuck in open() on the FIFO after 5 s, so that a regression fails instead of hanging.
struct FifoWatchdog {
  std::jthread t;
  explicit FifoWatchdog(const fs::path& p)
      : t([p](std::stop_token st) {
          for (int i = 0; i < 100 && !st.stop_requested(); ++i) std::this_thread::sleep_for(50ms);
          while (!st.stop_requested()) {
            const int fd = ::open(p.c_str(), O_WRONLY | O_NONBLOCK);
            if (fd >= 0) ::close(fd);
            std::this_thread::sleep_for(10ms);
          }
        }) {}
};

TEST(IoHostile, NonRegularFilesAreRefusedBeforeOpening) {
  const auto dir = scratch_dir();
  for (const char* name : {"t.png", "t.exr", "t.dds", "t.ktx2", "t.npy", "m.obj", "s.json"}) {
    SCOPED_TRACE(name);
    const fs::path fifo = dir / name, link = dir / (std::string("link_") + name);
    fs::remove(fifo), fs::remove(link);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    fs::create_symlink(fifo, link);
    const FifoWatchdog watchdog(fifo);
    for (const fs::path& p : {fifo, link}) {
      const std::string ext = p.extension().string();
      if (ext == ".obj") {
        expect_input_error([&] { render::load_obj(p); }, p, "not a regular file (a FIFO)");
      } else if (ext == ".json") {
        expect_input_error([&] { render::load_scene(p); }, p, "not a regular file (a FIFO)");
      } else {
        expect_input_error([&] { read_volume(p); }, p, "not a regular file (a FIFO)");
        if (ext == ".png" || ext == ".exr") {
          expect_input_error([&] { read_image(p); }, p, "not a regular file (a FIFO)");
          expect_input_error([&] { render::load_height_map(p); }, p, "not a regular file (a FIFO)");
        }
        if (ext == ".dds" || ext == ".ktx2")
          expect_input_error([&] { read_texture_level(p, 0); }, p, "not a regular file (a FIFO)");
      }
    }
  }
  // A device read without end, and a directory.
  expect_input_error([&] { render::load_obj("/dev/zero"); }, "/dev/zero", "not a regular file (a device)");
  fs::create_directories(dir / "d.npy");
  expect_input_error([&] { read_volume(dir / "d.npy"); }, dir / "d.npy", "not a regular file (a directory)");
}

TEST(IoHostile, DdsAndKtx2ReadOnlyTheBytesTheHeaderDescribes) {
  const auto dir = scratch_dir();
  for (const fs::path& p :
       write_dds_and_ktx2(dir / "big", make_volume(64, 64, 1, 4, 0.f, 1.f), PixelFormat::RGBA8Unorm)) {
    const Volume expected = read_texture_level(p, 0);
    // A sparse 3 GiB tail (no disk blocks): the reader must take the 64² payload and stop there.
    fs::resize_file(p, std::uintmax_t(3) << 30);
    const Volume got = read_texture_level(p, 0);
    EXPECT_EQ(got.width, 64);
    EXPECT_EQ(got.height, 64);
    EXPECT_EQ(got.data, expected.data);
    fs::remove(p);
  }
}

TEST(IoHostile, TruncatedDdsAndKtx2AreRefused) {
  const auto dir = scratch_dir();
  for (const fs::path& p :
       write_dds_and_ktx2(dir / "t", make_volume(16, 16, 1, 4, 0.f, 1.f), PixelFormat::RGBA32Float)) {
    std::vector<char> b = read_all(p);
    b.resize(b.size() - 5);
    write_all(p, b);
    expect_input_error([&] { read_texture_level(p, 0); }, p, "truncated");
  }
}

TEST(IoHostile, NonFiniteTexelsInFloatFormatsAreRefused) {
  const auto dir = scratch_dir();
  const Volume v = make_volume(8, 8, 1, 4, 0.f, 1.f);
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()};
  for (FileFormat f : {FileFormat::Dds, FileFormat::Ktx2}) {
    for (PixelFormat pf : {PixelFormat::RGBA32Float, PixelFormat::RGBA16Float}) {
      for (float x : bad) {
        const fs::path p = dir / (f == FileFormat::Dds ? "n.dds" : "n.ktx2");
        write_texture_mips(p, {v, make_volume(4, 4, 1, 4, 0.f, 1.f)}, pf);
        std::vector<char> b = read_all(p);
        // Level 1's texel (1, 2), channel 2: KTX2 level index entry 1 at byte 80 + 24; DDS after level 0.
        const std::size_t bpc = pf == PixelFormat::RGBA32Float ? 4 : 2;
        const std::size_t level1 =
            f == FileFormat::Ktx2 ? std::size_t(u32_at(b, 80 + 24)) : 148 + 8 * 8 * 4 * bpc;
        const std::size_t at = level1 + ((2 * 4 + 1) * 4 + 2) * bpc;
        if (bpc == 4) {
          std::memcpy(b.data() + at, &x, 4);
        } else {
          const std::uint16_t h = std::isnan(x) ? 0x7e00 : 0x7c00;
          std::memcpy(b.data() + at, &h, 2);
        }
        write_all(p, b);
        EXPECT_NO_THROW(read_texture_level(p, 0));
        expect_input_error([&] { read_texture_level(p, 1); }, p, "mip level 1: non-finite value");
      }
    }
  }
}

TEST(IoHostile, AbsurdHeaderDimensionsAreRefusedBeforeAllocating) {
  const auto dir = scratch_dir();
  for (FileFormat f : {FileFormat::Dds, FileFormat::Ktx2}) {
    const fs::path p = dir / (f == FileFormat::Dds ? "huge.dds" : "huge.ktx2");
    write_volume(p, make_volume(8, 8, 1, 1, 0.f, 1.f), f, PixelFormat::R8Unorm);
    std::vector<char> b = read_all(p);
    // width / height fields: DDS dwHeight at 12, dwWidth at 16; KTX2 pixelWidth at 20, pixelHeight at 24.
    const std::size_t wo = f == FileFormat::Dds ? 16 : 20, ho = f == FileFormat::Dds ? 12 : 24;
    put_u32_at(b, wo, 16385), put_u32_at(b, ho, 8);
    write_all(p, b);
    expect_input_error([&] { read_texture_level(p, 0); }, p, "exceeds the limit of 16384 per side");
    put_u32_at(b, wo, 16384), put_u32_at(b, ho, 16384);  // 2^28 texels of R8: within the limits, too short
    write_all(p, b);
    expect_input_error([&] { read_texture_level(p, 0); }, p,
                       f == FileFormat::Dds ? "truncated" : "expected 268435456");
    put_u32_at(b, wo, 0xFFFFFFFFu), put_u32_at(b, ho, 0xFFFFFFFFu);
    write_all(p, b);
    expect_input_error([&] { read_texture_level(p, 0); }, p, "invalid dimensions");
  }
}

}  // namespace
}  // namespace msh::io

// Writers never replace what is not a regular file (`convert x.npy /dev/null` made /dev/null a regular file):
// a FIFO and a directory as targets, through the atomic writer and a format writer; each refused with the
// path named, the FIFO still a FIFO, no temporary file left. A regular file and a symlink to one are written.
TEST(IoHostile, WritersRefuseTargetsThatAreNotRegularFiles) {
  namespace fs = std::filesystem;
  const auto dir = msh::io::test::scratch_dir();
  const fs::path fifo = dir / "pipe.npy";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_directories(dir / "folder.npy");
  msh::io::Volume v(2, 2, 1, 1);
  for (const fs::path& target : std::vector<fs::path>{fifo, dir / "folder.npy"}) {
    try {
      msh::io::write_file_atomic(target, std::string_view("x"));
      ADD_FAILURE() << "no error for " << target;
    } catch (const msh::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(target.string()), std::string::npos) << e.what();
    }
    EXPECT_THROW(msh::io::write_volume(target, v, msh::io::FileFormat::Npy), msh::InputError) << target;
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_directory(dir / "folder.npy"));
  msh::io::write_volume(dir / "plain.npy", v, msh::io::FileFormat::Npy);
  fs::create_symlink(dir / "plain.npy", dir / "link.npy");
  msh::io::write_file_atomic(dir / "link.npy", std::string_view("y"));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// Temporaries never outlive a run (issue 35, item 1): SIGINT in the middle of a write removes the one in
// flight and the process still dies of the signal; a later run's first write into the folder removes those a
// dead process left (SIGKILL) and leaves a live process's alone.
TEST(IoHostile, SignalsAndTheNextRunRemoveTemporaries) {
  namespace fs = std::filesystem;
  const auto dir = msh::io::test::scratch_dir();
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    msh::io::install_temporary_cleanup();
    msh::io::AtomicPath ap(dir / "big.npy");
    std::ofstream(ap.temp()) << "half written";
    ::kill(::getpid(), SIGINT);
    ::_exit(3);  // not reached: SIGINT's default action ends the process
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
  int left = 0;
  for (const auto& e : fs::directory_iterator(dir)) ++left, ADD_FAILURE() << "left behind: " << e.path();
  EXPECT_EQ(left, 0);

  // A dead process's temporaries (a reaped child's pid) and a live one's (pid 1).
  const pid_t gone = ::fork();
  ASSERT_GE(gone, 0);
  if (gone == 0) ::_exit(0);
  ASSERT_EQ(::waitpid(gone, &status, 0), gone);
  const fs::path dead = dir / fmt::format(".a.npy.tmp-{}-0", gone), live = dir / ".b.npy.tmp-1-0",
                 odd = dir / ".c.npy.tmp-x-0";
  for (const fs::path& p : {dead, live, odd}) std::ofstream(p) << "x";
  msh::io::write_file_atomic(dir / "new.txt", std::string_view("new"));
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(live));
  EXPECT_TRUE(fs::exists(odd));
  EXPECT_TRUE(fs::exists(dir / "new.txt"));
}

// A run's output folder as a whole: the second run removes the files the first wrote and it did not (with
// the directories they leave empty), never a file the tool did not write nor one outside the folder named in
// a hand-edited list; a run that does not finish removes nothing.
TEST(IoHostile, OutputFolderRemovesTheEarlierRunsStaleFiles) {
  namespace fs = std::filesystem;
  const auto root = msh::io::test::scratch_dir();
  const fs::path dir = root / "out";
  {
    msh::io::OutputFolder f(dir);
    fs::create_directories(dir / "mips" / "deep");
    for (const char* n : {"a.txt", "b.txt", "mips/m0.npy", "mips/deep/d.npy"})
      msh::io::write_file_atomic(dir / n, std::string_view(n));
    msh::io::write_file_atomic(root / "outside.txt", std::string_view("not in the folder"));
    EXPECT_TRUE(f.finish().empty());
  }
  std::ofstream(dir / "mine.txt") << "the user's";
  std::ofstream(dir / msh::io::OutputFolder::kManifest, std::ios::app) << "../outside.txt\n/etc/hostname\n";
  {
    msh::io::OutputFolder f(dir);  // no finish: an interrupted run
    msh::io::write_file_atomic(dir / "a.txt", std::string_view("again"));
  }
  EXPECT_TRUE(fs::exists(dir / "b.txt"));
  {
    msh::io::OutputFolder f(dir);
    msh::io::write_file_atomic(dir / "a.txt", std::string_view("third"));
    const auto removed = f.finish();
    EXPECT_EQ(removed, (std::vector<std::string>{"b.txt", "mips/deep/d.npy", "mips/m0.npy"}));
  }
  EXPECT_TRUE(fs::exists(dir / "a.txt"));
  EXPECT_TRUE(fs::exists(dir / "mine.txt"));
  EXPECT_TRUE(fs::exists(root / "outside.txt"));
  EXPECT_FALSE(fs::exists(dir / "b.txt"));
  EXPECT_FALSE(fs::exists(dir / "mips"));
  std::ifstream in(dir / msh::io::OutputFolder::kManifest);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\na.txt\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("b.txt"), std::string::npos) << text;
  EXPECT_THROW(msh::io::OutputFolder(dir / "a.txt"), msh::InputError);
}

// A folder written whole under a temporary name and renamed (gen-material --gltf): the list names its files
// where they end up, so it is the same on every run (no process id in it), and a later run without the folder
// removes it.
TEST(IoHostile, OutputFolderRecordsARenamedDirectoryUnderItsFinalName) {
  namespace fs = std::filesystem;
  const auto root = msh::io::test::scratch_dir();
  const fs::path dir = root / "out";
  const auto manifest = [&] {
    std::ifstream in(dir / msh::io::OutputFolder::kManifest);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  fs::create_directories(dir);
  std::string first;
  for (int run = 0; run < 2; ++run) {
    msh::io::OutputFolder f(dir);
    msh::io::write_file_atomic(dir / "a.txt", std::string_view("a"));
    const fs::path tmp = dir / (".sub.tmp-" + std::to_string(1000 + run));
    fs::create_directories(tmp / "deep");
    for (const char* n : {"x.gltf", "deep/y.png"}) msh::io::write_file_atomic(tmp / n, std::string_view(n));
    if (fs::exists(dir / "sub")) fs::remove_all(dir / "sub");
    msh::io::rename_recorded_directory(tmp, dir / "sub");
    EXPECT_TRUE(f.finish().empty());
    if (run == 0) first = manifest();
  }
  EXPECT_EQ(manifest(), first);
  EXPECT_NE(first.find("\nsub/x.gltf\n"), std::string::npos) << first;
  EXPECT_NE(first.find("\nsub/deep/y.png\n"), std::string::npos) << first;
  EXPECT_EQ(first.find(".tmp-"), std::string::npos) << first;
  {
    msh::io::OutputFolder f(dir);
    msh::io::write_file_atomic(dir / "a.txt", std::string_view("a"));
    EXPECT_EQ(f.finish(), (std::vector<std::string>{"sub/deep/y.png", "sub/x.gltf"}));
  }
  EXPECT_FALSE(fs::exists(dir / "sub"));
}
