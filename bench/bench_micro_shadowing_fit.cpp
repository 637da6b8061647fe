// ALU-only micro-shadowing approximations (micro_shadowing_fit.h): ns per call in C++ float, over a fixed
// pool of random inputs outside the early-out region (inside it both return after one compare). The two-stage
// form is timed per pixel (stage 1), per light (stage 2) and both together.
#include <benchmark/benchmark.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>

#include <vector>

#include "bench_common.h"

namespace {

using namespace msh;
using namespace msh::micro_shadowing;

struct Input {
  float V, nl, nv, r;
};

const std::vector<Input>& inputs() {
  static const std::vector<Input> p = bench::pool_of_256<Input>(12, [](Pcg32& rng) -> std::optional<Input> {
    const Input q{rng.next_float(), 1 - rng.next_float(), 1 - rng.next_float(),
                  0.1f + 0.9f * rng.next_float()};
    if (exact_zero(q.V, q.nl)) return std::nullopt;
    return q;
  });
  return p;
}

void BM_AluOneCall(benchmark::State& st) {
  bench::per_call(st, inputs(), [](const Input& q) { return generic_vndf_alu(q.V, q.nl, q.nv, q.r); });
}
BENCHMARK(BM_AluOneCall);

void BM_AluTwoStagePixel(benchmark::State& st) {
  bench::per_call(st, inputs(), [](const Input& q) { return generic_vndf_alu_pixel(q.V, q.nv, q.r); });
}
BENCHMARK(BM_AluTwoStagePixel);

void BM_AluTwoStageLight(benchmark::State& st) {
  const auto& p = inputs();
  std::vector<GenericVndfAluPixel<float>> px;
  for (const Input& q : p) px.push_back(generic_vndf_alu_pixel(q.V, q.nv, q.r));
  size_t i = 0;
  for (auto _ : st) {
    const size_t k = i++ & 255;
    benchmark::DoNotOptimize(generic_vndf_alu_light(px[k], p[k].nl));
  }
}
BENCHMARK(BM_AluTwoStageLight);

void BM_AluTwoStageBoth(benchmark::State& st) {
  bench::per_call(st, inputs(),
                  [](const Input& q) { return generic_vndf_alu_two_stage(q.V, q.nl, q.nv, q.r); });
}
BENCHMARK(BM_AluTwoStageBoth);

}  // namespace
