// Texture I/O throughput: write and read a 64³ RGBA volume (the default micro-shadowing LUT size) in every
// format. Files go to the system temp directory; the numbers include the atomic rename.
#include <benchmark/benchmark.h>
#include <microshadow/io/texture.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

namespace {
using namespace msh::io;

Volume lut_volume(int n = 64) {
  Volume v(n, n, n, 4);
  for (std::size_t i = 0; i < v.data.size(); ++i) v.data[i] = float(0.5 + 0.5 * std::sin(0.001 * double(i)));
  return v;
}

std::filesystem::path temp_file(const char* ext) {
  return std::filesystem::temp_directory_path() / ("msh_bench_io_" + std::to_string(::getpid()) + ext);
}

void BM_Write(benchmark::State& state, FileFormat ff, PixelFormat pf, const char* ext) {
  const Volume v = lut_volume();
  const auto p = temp_file(ext);
  for (auto _ : state) write_volume(p, v, ff, pf);
  state.SetItemsProcessed(state.iterations() * std::int64_t(v.texel_count()));
  std::filesystem::remove(p);
}

void BM_Read(benchmark::State& state, FileFormat ff, PixelFormat pf, const char* ext) {
  const Volume v = lut_volume();
  const auto p = temp_file(ext);
  write_volume(p, v, ff, pf);
  for (auto _ : state) benchmark::DoNotOptimize(read_volume(p));
  state.SetItemsProcessed(state.iterations() * std::int64_t(v.texel_count()));
  std::filesystem::remove(p);
}

struct IoCase {
  const char* name;
  FileFormat ff;
  PixelFormat pf;
  const char* ext;
  bool readable;  // C headers are written only
};
constexpr IoCase kIoCases[] = {{"dds_rgba16f", FileFormat::Dds, PixelFormat::RGBA16Float, ".dds", true},
                               {"ktx2_rgba16f", FileFormat::Ktx2, PixelFormat::RGBA16Float, ".ktx2", true},
                               {"exr_half", FileFormat::Exr, PixelFormat::RGBA16Float, ".exr", true},
                               {"npy_f32", FileFormat::Npy, PixelFormat::RGBA32Float, ".npy", true},
                               {"c_header", FileFormat::CHeader, PixelFormat::RGBA32Float, ".h", false},
                               {"png_8bit", FileFormat::Png, PixelFormat::RGBA8Unorm, ".png", true}};

// BM_Write/<name> for every case, then BM_Read/<name> for the readable ones.
const bool kIoRegistered = [] {
  for (const IoCase& c : kIoCases)
    benchmark::RegisterBenchmark((std::string("BM_Write/") + c.name).c_str(), BM_Write, c.ff, c.pf, c.ext)
        ->Unit(benchmark::kMillisecond);
  for (const IoCase& c : kIoCases)
    if (c.readable)
      benchmark::RegisterBenchmark((std::string("BM_Read/") + c.name).c_str(), BM_Read, c.ff, c.pf, c.ext)
          ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
