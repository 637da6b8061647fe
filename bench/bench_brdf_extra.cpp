// Cloth, thin film, clear coat and filtering: ns per call (float and double) over a pool of random
// upper-hemisphere direction pairs, and the mip-chain builder per texel.
#include <benchmark/benchmark.h>
#include <microshadow/bsdf/cloth.h>
#include <microshadow/bsdf/layered.h>
#include <microshadow/bsdf/thin_film.h>
#include <microshadow/filter/runtime/mip_chain.h>
#include <microshadow/filter/toksvig.h>
#include <microshadow/math/sampling.h>

#include <vector>

#include "bench_common.h"

namespace {

using namespace msh;
using namespace msh::bsdf;

template <class T, class F>
void run_pairs(benchmark::State& s, F&& f) {
  bench::per_pair(s, bench::dir_pool<T, 7, false>(), f);
}

template <class T>
void BM_VelvetCloth(benchmark::State& s) {
  const VelvetNdf<T> ndf(T(0.5), T(1));
  run_pairs<T>(s, [&](const Vec3<T>& a, const Vec3<T>& b) {
    return velvet_cloth(a, b, Rgb<T>(T(0.5)), Rgb<T>(T(0.04)), ndf);
  });
}
template <class T>
void BM_ImageworksSheen(benchmark::State& s) {
  const SheenNdf<T> ndf(T(0.3));
  run_pairs<T>(s,
               [&](const Vec3<T>& a, const Vec3<T>& b) { return imageworks_sheen(a, b, Rgb<T>(T(1)), ndf); });
}
template <class T>
void BM_DisneySheen(benchmark::State& s) {
  run_pairs<T>(s, [&](const Vec3<T>& a, const Vec3<T>& b) { return disney_sheen(a, b, Rgb<T>(T(1)), T(1)); });
}
template <class T>
void BM_ThinFilmReflectance(benchmark::State& s) {
  ThinFilm<T> tf;
  run_pairs<T>(s,
               [&](const Vec3<T>& a, const Vec3<T>& b) { return tf.reflectance(dot(normalize(a + b), b)); });
}
template <class T>
void BM_ClearCoat(benchmark::State& s) {
  const ClearCoat<T> coat(T(1.5), T(0.05), Rgb<T>(T(0.8), T(0.9), T(1)), normalize(Vec3<T>(T(0.1), 0, 1)));
  run_pairs<T>(s, [&](const Vec3<T>& a, const Vec3<T>& b) { return coat.f(a, b, Rgb<T>(T(0.2))); });
}
template <class T>
void BM_ToksvigGgx(benchmark::State& s) {
  T len = T(0.9);
  for (auto _ : s) {
    benchmark::DoNotOptimize(filter::toksvig_ggx_alpha(T(0.3), len));
    len = len > T(0.99) ? T(0.5) : len + T(1e-3);
  }
}

void BM_RoughnessMips(benchmark::State& s) {
  const int w = int(s.range(0));
  std::vector<Vec3f> n(size_t(w) * size_t(w));
  Pcg32 rng(3);
  for (auto& v : n)
    v = normalize(Vec3f(0.2f * (rng.next_float() - 0.5f), 0.2f * (rng.next_float() - 0.5f), 1.0f));
  for (auto _ : s)
    benchmark::DoNotOptimize(filter::build_roughness_mips(w, w, n, {0.4f}, filter::FilterMethod::Variance));
  s.SetItemsProcessed(int64_t(s.iterations()) * w * w);
}

}  // namespace

BENCHMARK_TEMPLATE(BM_VelvetCloth, float);
BENCHMARK_TEMPLATE(BM_VelvetCloth, double);
BENCHMARK_TEMPLATE(BM_ImageworksSheen, float);
BENCHMARK_TEMPLATE(BM_ImageworksSheen, double);
BENCHMARK_TEMPLATE(BM_DisneySheen, float);
BENCHMARK_TEMPLATE(BM_ThinFilmReflectance, float);
BENCHMARK_TEMPLATE(BM_ThinFilmReflectance, double);
BENCHMARK_TEMPLATE(BM_ClearCoat, float);
BENCHMARK_TEMPLATE(BM_ClearCoat, double);
BENCHMARK_TEMPLATE(BM_ToksvigGgx, float);
BENCHMARK(BM_RoughnessMips)->Arg(512)->Arg(2048)->Unit(benchmark::kMillisecond);
