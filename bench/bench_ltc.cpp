// Benchmarks of the LTC table (docs/ltc.md quotes these numbers):
//   BM_LtcFitCell      one Nelder–Mead cell fit of the default bake (K = 32, 120 iterations), warm-started
//   from
//                      the previous θ_v as in the table; × n² ≈ the bake's CPU time
//   BM_LtcShadeSphere  ltc_shade_sphere (16-gon, float) per call; BM_LtcShadeRect the same for a quad
#include <benchmark/benchmark.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/bsdf/ltc_shading.h>

namespace {

using namespace msh;
using namespace msh::bsdf;

void BM_LtcFitCell(benchmark::State& state) {
  const LtcFitOptions o;
  const double r = 0.5, th0 = 0.78, th1 = 0.80;
  LtcCellFit start = fit_ltc_cell(r, 0.0, LtcCellFit{}, true, o);
  start = fit_ltc_cell(r, th0, start, false, o);
  for (auto _ : state) benchmark::DoNotOptimize(fit_ltc_cell(r, th1, start, false, o));
}
BENCHMARK(BM_LtcFitCell)->Unit(benchmark::kMillisecond);

LtcCoeffs<float> bench_coeffs() {
  LtcCoeffs<float> k;
  k.a = 0.46f, k.b = 0.55f, k.c = -0.21f, k.d = 0.23f, k.magnitude = 0.87f, k.fresnel = 0.05f;
  return k;
}

void BM_LtcShadeSphere(benchmark::State& state) {
  const LtcCoeffs<float> k = bench_coeffs();
  const Vec3f n(0, 0, 1), v(0.6f, 0, 0.8f);
  float x = 0;
  for (auto _ : state) {
    const Vec3f l = normalize(Vec3f(-0.6f + x, 0.1f, 0.8f));
    benchmark::DoNotOptimize(ltc_shade_sphere(k, n, v, l, 0.2f, 16).integral);
    x = x > 0.1f ? 0.f : x + 1e-4f;
  }
}
BENCHMARK(BM_LtcShadeSphere);

void BM_LtcShadeRect(benchmark::State& state) {
  const LtcCoeffs<float> k = bench_coeffs();
  const Vec3f n(0, 0, 1), v(0.6f, 0, 0.8f);
  float x = 0;
  for (auto _ : state) {
    const auto p =
        ltc_rect_polygon(Vec3f(-0.6f + x, 0.1f, 0.8f), Vec3f(1, 0, 0), Vec3f(0, 0.8f, 0.6f), 0.2f, 0.1f);
    benchmark::DoNotOptimize(ltc_shade_polygon(k, n, v, p.data(), 4).integral);
    x = x > 0.1f ? 0.f : x + 1e-4f;
  }
}
BENCHMARK(BM_LtcShadeRect);

}  // namespace
