// Micro-shadowing terms: ns per closed-form term (float), per generic VNDF sample (float), per estimate of
// 16 samples, per exact evaluation and per exact azimuth mean (double), over fixed pools of random inputs
// outside the early-out region (inside it every generic variant returns immediately).
#include <benchmark/benchmark.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <vector>

#include "bench_common.h"

namespace {

using namespace msh;
using namespace msh::micro_shadowing;

struct Point {
  double V, alpha, nl, nv, phi;
  Vec3d v, l;
};

const std::vector<Point>& points() {
  static const std::vector<Point> p = bench::pool_of_256<Point>(11, [](Pcg32& rng) -> std::optional<Point> {
    Point q;
    q.V = rng.next_double(), q.nl = rng.next_double(), q.nv = rng.next_double();
    q.alpha = sqr(0.1 + 0.9 * rng.next_double()), q.phi = kPi<double> * rng.next_double();
    if (exact_zero(q.V, q.nl)) return std::nullopt;
    q.v = spherical_direction(q.nv, 0.0), q.l = spherical_direction(q.nl, q.phi);
    return q;
  });
  return p;
}

template <float (*F)(float, float)>
void BM_ClosedForm(benchmark::State& st) {
  bench::per_call(st, points(), [](const Point& q) { return F(float(q.V), float(q.nl)); });
}
BENCHMARK(BM_ClosedForm<reference_step<float>>)->Name("reference_step/float");
BENCHMARK(BM_ClosedForm<brinck_maximov_2016<float>>)->Name("brinck_maximov_2016/float");
BENCHMARK(BM_ClosedForm<chan_2018<float>>)->Name("chan_2018/float");
BENCHMARK(BM_ClosedForm<part1_analytic<float>>)->Name("part1_analytic/float");

void BM_GenericSample(benchmark::State& st) {
  const auto& p = points();
  std::vector<GGX<float>> g;
  for (const Point& q : p) g.emplace_back(float(q.alpha));
  uint32_t i = 0;
  for (auto _ : st) {
    const Point& q = p[i & 255];
    benchmark::DoNotOptimize(generic_vndf_sample(float(cone_cos_from_visibility(q.V)), g[i & 255], Vec3f(q.v),
                                                 Vec3f(q.l), sobol_2d<float>(i, 1),
                                                 G2Form::HeightCorrelated));
    ++i;
  }
}
BENCHMARK(BM_GenericSample)->Name("generic_vndf_sample/float");

void BM_GenericEstimate16(benchmark::State& st) {
  bench::per_call(st, points(), [](const Point& q) {
    return generic_vndf_estimate(float(q.V), GGX<float>(float(q.alpha)), Vec3f(q.v), Vec3f(q.l), 16,
                                 G2Form::HeightCorrelated);
  });
}
BENCHMARK(BM_GenericEstimate16)->Name("generic_vndf_estimate_16/float");

void BM_Exact(benchmark::State& st) {
  bench::per_call(st, points(),
                  [](const Point& q) { return generic_vndf_exact(q.V, q.alpha, q.alpha, q.v, q.l); });
}
BENCHMARK(BM_Exact)->Name("generic_vndf_exact/double")->Unit(benchmark::kMicrosecond);

void BM_ExactAzimuthMean(benchmark::State& st) {
  bench::per_call(st, points(),
                  [](const Point& q) { return generic_vndf_exact_azimuth_mean(q.V, q.alpha, q.nl, q.nv); });
}
BENCHMARK(BM_ExactAzimuthMean)->Name("generic_vndf_exact_azimuth_mean/double")->Unit(benchmark::kMillisecond);

}  // namespace
