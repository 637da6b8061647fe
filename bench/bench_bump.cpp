// Bump-terminator terms and the Hanika offset: ns per call, float and double, over a fixed pool of random
// inputs (so the branches of Chiang's term are exercised in realistic proportions).
#include <benchmark/benchmark.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>

#include <array>
#include <vector>

#include "bench_common.h"

namespace {

using namespace msh;

template <class T>
struct Inputs {
  std::vector<Vec3<T>> ng, ns, l;
};

template <class T>
const Inputs<T>& inputs() {
  static const Inputs<T> in = [] {
    Inputs<T> r;
    Pcg32 rng(42);
    for (int i = 0; i < 4096; ++i) {
      const Vec3d ng = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
      const Framed f = Framed::from_z(ng);
      const Vec3d ns = f.to_world(sample_uniform_cone(Vec2d(rng.next_double(), rng.next_double()), 0.5));
      const Vec3d l = f.to_world(sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double())));
      r.ng.push_back(Vec3<T>(ng)), r.ns.push_back(Vec3<T>(ns)), r.l.push_back(Vec3<T>(l));
    }
    return r;
  }();
  return in;
}

template <class T, bump::Method M>
void BM_BumpTerm(benchmark::State& state) {
  const Inputs<T>& in = inputs<T>();
  bench::per_index<4096>(state, [&](std::size_t i) { return bump::term(M, in.ng[i], in.ns[i], in.l[i]); });
}
BENCHMARK(BM_BumpTerm<float, bump::Method::kConty2019>)->Name("bump/conty2019/float");
BENCHMARK(BM_BumpTerm<double, bump::Method::kConty2019>)->Name("bump/conty2019/double");
BENCHMARK(BM_BumpTerm<float, bump::Method::kChiang2019>)->Name("bump/chiang2019/float");
BENCHMARK(BM_BumpTerm<double, bump::Method::kChiang2019>)->Name("bump/chiang2019/double");

// Listing 12.1 as written (float), for comparison with our cross-product form.
void BM_ContyListing(benchmark::State& state) {
  const Inputs<float>& in = inputs<float>();
  size_t i = 0;
  for (auto _ : state) {
    const Vec3f &ng = in.ng[i], &ns = in.ns[i], &l = in.l[i];
    const float cos_d = std::min(std::abs(dot(ng, ns)), 1.0f);
    const float tan2_d = (1 - cos_d * cos_d) / (cos_d * cos_d);
    const float alpha2 = std::clamp(0.125f * tan2_d, 0.0f, 1.0f);
    const float cos_i = std::max(std::abs(dot(ng, l)), 1e-6f);
    const float tan2_i = (1 - cos_i * cos_i) / (cos_i * cos_i);
    benchmark::DoNotOptimize(2.0f / (1 + std::sqrt(1 + alpha2 * tan2_i)));
    i = (i + 1) & 4095;
  }
}
BENCHMARK(BM_ContyListing)->Name("bump/conty2019_listing/float");

void BM_Hanika(benchmark::State& state) {
  const Inputs<float>& in = inputs<float>();
  size_t i = 0;
  for (auto _ : state) {
    const std::array<Vec3f, 3> pos{in.ng[i], in.ns[i], in.l[i]};
    const std::array<Vec3f, 3> nrm{in.ng[(i + 1) & 4095], in.ns[(i + 2) & 4095], in.l[(i + 3) & 4095]};
    const Vec3f p = (pos[0] + pos[1] + pos[2]) * (1.0f / 3.0f);
    benchmark::DoNotOptimize(bump::hanika2021_shadow_origin(p, pos, nrm, 1.0f / 3.0f, 1.0f / 3.0f));
    i = (i + 1) & 4095;
  }
}
BENCHMARK(BM_Hanika)->Name("bump/hanika2021_offset/float");

}  // namespace
