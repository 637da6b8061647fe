// Regression inputs from fuzzing the readers (docs/fuzzing.md): every file under tests/data/fuzz/ once
// crashed a reader, tripped a sanitizer, allocated far more than the file could hold or produced a non-finite
// value; each must now give msh::InputError and nothing else. The file name says which reader reads it:
//   volume_*.<ext>  io::read_volume        obj_*.obj    render::load_obj
//   scene_*.json    render::parse_scene    lut_*        lut::load_micro_shadowing_lut, input split as in
//                                                       fuzz/fuzz_lut.cpp (sidecar text, NUL, .npy table)
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/render/scene.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>

#include "support/cli_test_util.h"

namespace fs = std::filesystem;
using namespace msh;

// The largest single allocation since the last reset: a reader must check sizes against the file before it
// allocates (docs/formats.md), so reading a few-KB corrupt file must never allocate tens of MB.
static std::atomic<std::size_t> g_max_alloc{0};
void* operator new(std::size_t n) {
  std::size_t m = g_max_alloc.load();
  while (n > m && !g_max_alloc.compare_exchange_weak(m, n)) {
  }
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// Both operators are ours (malloc/free), but GCC, once it inlines them into a `new T` (as it does in the
// ASan build), takes the pair for a mismatch: -Wmismatched-new-delete is a false positive here.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace {
const fs::path kDir = fs::path(MSH_SOURCE_DIR) / "tests" / "data" / "fuzz";

// Reads `p` through the reader its name selects; `scratch` holds the split LUT inputs.
void read_through(const fs::path& p, const fs::path& scratch) {
  const std::string name = p.filename().string();
  if (name.rfind("volume_", 0) == 0) {
    (void)io::read_volume(p);
  } else if (name.rfind("obj_", 0) == 0) {
    (void)render::load_obj(p);
  } else if (name.rfind("scene_", 0) == 0) {
    (void)render::parse_scene(test::slurp(p), p, fs::path(MSH_SOURCE_DIR) / "examples");
  } else if (name.rfind("lut_", 0) == 0) {
    const std::string bytes = test::slurp(p);
    const fs::path table = scratch / "table.npy", side = lut::sidecar_path(table);
    fs::remove(side);
    const auto nul = bytes.find('\0');
    if (nul != std::string::npos) std::ofstream(side, std::ios::binary) << bytes.substr(0, nul);
    std::ofstream(table, std::ios::binary) << bytes.substr(nul == std::string::npos ? 0 : nul + 1);
    (void)lut::load_micro_shadowing_lut(table);
  } else {
    FAIL() << name << ": unknown prefix (volume_, obj_, scene_, lut_)";
  }
}
}  // namespace

TEST(FuzzRegressions, EveryFileGivesInputError) {
  const fs::path scratch = test::scratch_dir("fuzz_regressions");
  int n = 0;
  for (const auto& e : fs::directory_iterator(kDir)) {
    ++n;
    SCOPED_TRACE(e.path().filename().string());
    bool input_error = false;
    g_max_alloc = 0;
    try {
      read_through(e.path(), scratch);
    } catch (const InputError& err) {
      input_error = true;
      EXPECT_NE(std::string(err.what()), "");
    }
    EXPECT_TRUE(input_error) << e.path() << " was accepted";
    EXPECT_LT(g_max_alloc.load(), std::size_t(16) << 20)
        << "largest allocation while reading a " << fs::file_size(e.path()) << "-byte file";
  }
  EXPECT_GE(n, 3);  // the directory is found and holds the committed findings
  fs::remove_all(scratch);
}

// The same NPY with a payload that matches its shape is accepted: the rejections above are about the bytes
// that are wrong, not about the format.
TEST(FuzzRegressions, WellFormedTwinIsAccepted) {
  const fs::path scratch = test::scratch_dir("fuzz_regressions");
  io::Volume v(1, 2, 1, 1);
  v.data = {0.5f, 0.25f};
  io::write_volume(scratch / "ok.npy", v, io::FileFormat::Npy);
  EXPECT_EQ(io::read_volume(scratch / "ok.npy").data, v.data);
  fs::remove_all(scratch);
}
