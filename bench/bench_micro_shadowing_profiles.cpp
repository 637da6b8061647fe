// The generic micro-shadowing term for other microsurface profiles and anisotropy: ns per estimator sample
// (16-sample estimate, float) for Smith-GGX, Smith-Beckmann and Beckmann-Spizzichino + V-cavity, per exact
// evaluation (double) of the Beckmann and V-cavity references, and per projected-roughness combination
// (float), over fixed pools of random anisotropic inputs outside the early-out region.
#include <benchmark/benchmark.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/vcavity.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_anisotropic.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/reference/micro_shadowing_vcavity.h>

#include <vector>

#include "bench_common.h"

namespace {

using namespace msh;
using namespace msh::micro_shadowing;

struct Point {
  double V, ax, ay;
  Vec3d v, l;
};

const std::vector<Point>& points() {
  static const std::vector<Point> p = bench::pool_of_256<Point>(13, [](Pcg32& rng) -> std::optional<Point> {
    Point q;
    q.V = rng.next_double();
    const double nl = rng.next_double(), nv = 0.05 + 0.95 * rng.next_double();
    q.ax = sqr(0.1 + 0.9 * rng.next_double()), q.ay = sqr(0.1 + 0.9 * rng.next_double());
    if (exact_zero(q.V, nl)) return std::nullopt;
    q.v = spherical_direction(nv, 2 * kPi<double> * rng.next_double());
    q.l = spherical_direction(nl, 2 * kPi<double> * rng.next_double());
    return q;
  });
  return p;
}

template <class Dist>
void BM_Estimate16(benchmark::State& st) {
  const auto& p = points();
  std::vector<Dist> d;
  for (const Point& q : p) {
    if constexpr (std::is_same_v<Dist, BeckmannVCavity<float>>)
      d.emplace_back(Beckmann<float>(float(q.ax), float(q.ay)));
    else
      d.emplace_back(float(q.ax), float(q.ay));
  }
  size_t i = 0;
  for (auto _ : st) {
    const Point& q = p[i & 255];
    benchmark::DoNotOptimize(
        generic_vndf_estimate(float(q.V), d[i & 255], Vec3f(q.v), Vec3f(q.l), 16, G2Form::HeightCorrelated));
    ++i;
  }
}
BENCHMARK(BM_Estimate16<GGX<float>>)->Name("profiles/estimate_16/ggx");
BENCHMARK(BM_Estimate16<Beckmann<float>>)->Name("profiles/estimate_16/beckmann");
BENCHMARK(BM_Estimate16<BeckmannVCavity<float>>)->Name("profiles/estimate_16/vcavity");

void BM_ExactBeckmann(benchmark::State& st) {
  bench::per_call(st, points(), [](const Point& q) {
    return generic_vndf_exact(q.V, Beckmann<double>(q.ax, q.ay), q.v, q.l);
  });
}
BENCHMARK(BM_ExactBeckmann)->Name("profiles/exact/beckmann");

void BM_ExactVCavity(benchmark::State& st) {
  bench::per_call(st, points(), [](const Point& q) {
    return generic_vcavity_exact(q.V, BeckmannVCavity<double>(Beckmann<double>(q.ax, q.ay)), q.v, q.l);
  });
}
BENCHMARK(BM_ExactVCavity)->Name("profiles/exact/vcavity");

void BM_ProjectedRoughness(benchmark::State& st) {
  bench::per_call(st, points(), [](const Point& q) {
    return micro_shadowing_isotropic_roughness(float(q.ax), float(q.ay), Vec3f(q.v), Vec3f(q.l));
  });
}
BENCHMARK(BM_ProjectedRoughness)->Name("profiles/projected_roughness/float");

}  // namespace
