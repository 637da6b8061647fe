// Texture-set benchmarks: procedural generation + normal map + micro-occlusion bake per kind (the study's
// fine sets: 2048², 8 azimuths, default ray length 8 % of the size), the bake alone, and the multiscale
// downsample. Counters: texels/s and horizon walks/s (one walk = one azimuth of one texel, every elevation
// resolved). Wall time (UseRealTime): the work runs on oneTBB's threads.
#include <benchmark/benchmark.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/multiscale.h>
#include <microshadow/render/texture_gen.h>

#include <cmath>
#include <map>
#include <string>
#include <vector>

using namespace msh::render;

namespace {

const char* kKinds[] = {"plaster", "bark", "gravel"};

void BM_GenMaterial(benchmark::State& state) {
  GenOptions o;
  o.kind = kKinds[state.range(0)];
  o.size = int(state.range(1));
  o.ao_rays = int(state.range(2));
  for (auto _ : state) benchmark::DoNotOptimize(generate_texture_set(o));
  const double texels = double(o.size) * o.size;
  state.counters["texels/s"] = benchmark::Counter(texels, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["walks/s"] =
      benchmark::Counter(texels * o.ao_rays, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(o.kind);
}
BENCHMARK(BM_GenMaterial)
    ->ArgsProduct({{0, 1, 2}, {512}, {8}})
    ->ArgsProduct({{0, 1, 2}, {2048}, {8}})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

const TextureSet& fine_set(int kind, int size) {
  static std::map<std::pair<int, int>, TextureSet> cache;
  auto it = cache.find({kind, size});
  if (it == cache.end()) {
    GenOptions o;
    o.kind = kKinds[kind];
    o.size = size;
    o.ao_rays = 1;
    o.ao_max_distance = 0.5f;  // a negligible bake: BM_BakeVisibility times it alone
    it = cache.emplace(std::make_pair(kind, size), generate_texture_set(o)).first;
  }
  return it->second;
}

// The bake alone (height already generated), default ray length.
void BM_BakeVisibility(benchmark::State& state) {
  const int kind = int(state.range(0)), size = int(state.range(1)), az = int(state.range(2));
  const TextureSet& s = fine_set(kind, size);
  for (auto _ : state) benchmark::DoNotOptimize(bake_visibility(s.height, s.depth_texels, az, 0.08f * size));
  const double texels = double(size) * size;
  state.counters["walks/s"] = benchmark::Counter(texels * az, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(kKinds[kind]);
}
BENCHMARK(BM_BakeVisibility)
    ->ArgsProduct({{0, 1, 2}, {1024}, {8}})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// Finite-ray horizons, 8 uniform azimuths, ray length 8 % of the size (the bake's default): arg 1 = 0 the
// walks (bake_horizon_tangents: cell DDA, 1e-4 tolerance; what bake_visibility ran before the profile
// scans), 1 the profile scans (bake_horizon_tangents_profiles: what bake_visibility runs). Counter: walks/s.
void BM_FiniteHorizons(benchmark::State& state) {
  const int kind = int(state.range(0)), path = int(state.range(1)), size = 1024;
  const TextureSet& s = fine_set(kind, size);
  std::vector<msh::Vec2f> dirs;
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * 3.14159265358979323846 * (k + 0.5) / 8;
    dirs.emplace_back(float(std::cos(a)), float(std::sin(a)));
  }
  const float R = 0.08f * size;
  for (auto _ : state) {
    if (path == 0) benchmark::DoNotOptimize(bake_horizon_tangents(s.height, s.depth_texels, dirs, R));
    if (path == 1)
      benchmark::DoNotOptimize(bake_horizon_tangents_profiles(s.height, s.depth_texels, dirs, R));
  }
  state.counters["walks/s"] =
      benchmark::Counter(double(size) * size * 8, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(std::string(kKinds[kind]) + (path == 0 ? " walks" : " profile scans"));
}
BENCHMARK(BM_FiniteHorizons)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// The directional bake's horizons on the rock kind (depth scaled with the size, as gen-material does), 32
// azimuths, unlimited rays: arg 0 = the lattice sweep (what the bake uses), 1 = the walks classified against
// the fit's elevations on the same directions (the bake's path for a finite ray length); and the whole bake
// (arg 2: horizons + normals + fit). Counter: vertex-azimuths/s.
void BM_DirectionalHorizons(benchmark::State& state) {
  const int size = int(state.range(0)), path = int(state.range(1));
  static std::map<int, TextureSet> cache;
  if (!cache.count(size)) {
    GenOptions o;
    o.kind = "rock", o.size = size, o.ao_rays = 1, o.ao_max_distance = 0.5f, o.directional_azimuths = 0;
    cache.emplace(size, generate_texture_set(o));
  }
  const TextureSet& s = cache.at(size);
  const DirectionalBakeAzimuths az = directional_bake_azimuths(32);
  std::vector<std::vector<double>> tan_e(az.dirs.size());
  for (auto& t : tan_e)
    for (int e = 0; e < 16; ++e) t.push_back(std::tan((e + 0.5) / 16 * 1.5707963267948966));
  for (auto _ : state) {
    if (path == 0)
      benchmark::DoNotOptimize(bake_horizon_tangents_lattice(s.height, s.depth_texels, az.steps));
    if (path == 1)
      benchmark::DoNotOptimize(bake_horizon_tangents(s.height, s.depth_texels, az.dirs, 0, tan_e));
    if (path == 2) benchmark::DoNotOptimize(bake_directional_channels(s.height, s.depth_texels, 32, 0));
  }
  state.counters["vertex-azimuths/s"] =
      benchmark::Counter(double(size) * size * 32, benchmark::Counter::kIsIterationInvariantRate);
  state.SetLabel(path == 0 ? "lattice sweep" : path == 1 ? "classified walks" : "whole bake");
}
BENCHMARK(BM_DirectionalHorizons)
    ->ArgsProduct({{512}, {0, 1, 2}})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

void BM_DownsampleTextureSet(benchmark::State& state) {
  const TextureSet& s = fine_set(0, 2048);
  const int k = int(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(downsample_texture_set(s, k, CoarseRoughness::Widened));
  state.counters["fine texels/s"] =
      benchmark::Counter(2048.0 * 2048.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_DownsampleTextureSet)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
