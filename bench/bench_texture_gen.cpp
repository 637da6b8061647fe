// Texture-set benchmarks: procedural generation + normal map + micro-occlusion bake per kind (the study's
// fine sets: 2048², 8 azimuths, default ray length 8 % of the size), the bake alone, and the multiscale
// downsample. Counters: texels/s and horizon walks/s (one walk = one azimuth of one texel, every elevation
// resolved). Wall time (UseRealTime): the work runs on oneTBB's threads.
#include <benchmark/benchmark.h>
#include <microshadow/render/multiscale.h>
#include <microshadow/render/texture_gen.h>

#include <map>
#include <string>

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

void BM_DownsampleTextureSet(benchmark::State& state) {
  const TextureSet& s = fine_set(0, 2048);
  const int k = int(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(downsample_texture_set(s, k, CoarseRoughness::Widened));
  state.counters["fine texels/s"] =
      benchmark::Counter(2048.0 * 2048.0, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_DownsampleTextureSet)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
