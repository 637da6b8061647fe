// Area-light micro-shadowing: ns per call of the fast forms (occlusion/micro_shadowing_area.h, float as a
// shader runs them) and of the exact quadrature (reference/micro_shadowing_area_exact.h), over a pool of
// random (V, N·L, ρ ∈ [1°, 40°]) inputs.
#include <benchmark/benchmark.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <vector>

namespace {

using namespace msh;

struct In {
  float V, nl, nv, r, rho;
};
const std::vector<In>& pool() {
  static const std::vector<In> p = [] {
    std::vector<In> v;
    Pcg32 rng(5);
    for (int i = 0; i < 1024; ++i)
      v.push_back({rng.next_float(), rng.next_float(), rng.next_float(), rng.next_float(),
                   (1 + 39 * rng.next_float()) * kPi<float> / 180});
    return v;
  }();
  return p;
}

template <class F>
void run(benchmark::State& state, F&& f) {
  const auto& p = pool();
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f(p[i]));
    i = (i + 1) & (p.size() - 1);
  }
}

void BM_StepAreaCapClosedForm(benchmark::State& s) {
  run(s, [](const In& x) { return micro_shadowing::reference_step_area_cap(x.V, x.nl, x.rho); });
}
void BM_StepAreaCapMazonka(benchmark::State& s) {
  run(s, [](const In& x) { return micro_shadowing::reference_step_area_cap_solid_angle(x.V, x.nl, x.rho); });
}
void BM_StepAreaCapOatSander(benchmark::State& s) {
  run(s, [](const In& x) { return micro_shadowing::reference_step_area_cap_oat_sander(x.V, x.nl, x.rho); });
}
void BM_BrinckMaximovAreaCap(benchmark::State& s) {
  run(s, [](const In& x) { return micro_shadowing::brinck_maximov_2016_area_cap(x.V, x.nl, x.rho); });
}
void BM_GenericAluAreaCap(benchmark::State& s) {
  run(s, [](const In& x) { return micro_shadowing::generic_vndf_alu_area_cap(x.V, x.nl, x.nv, x.r, x.rho); });
}
void BM_ExactStepCapLambert(benchmark::State& s) {
  run(s, [](const In& x) {
    return area::area_micro_shadowing_exact(area::Cap{spherical_direction(double(x.nl), 0.5), double(x.rho)},
                                            area::Receiver::lambert(),
                                            area::reference_step_term(double(x.V)));
  });
}
void BM_ExactBrinckMaximovCapGgx(benchmark::State& s) {
  run(s, [](const In& x) {
    const area::Receiver r = area::Receiver::ggx(0.2, spherical_direction(0.7, 0.0));
    return area::area_micro_shadowing_exact(area::Cap{spherical_direction(double(x.nl), 0.5), double(x.rho)},
                                            r, area::brinck_maximov_2016_term(double(x.V)));
  });
}

BENCHMARK(BM_StepAreaCapClosedForm);
BENCHMARK(BM_StepAreaCapMazonka);
BENCHMARK(BM_StepAreaCapOatSander);
BENCHMARK(BM_BrinckMaximovAreaCap);
BENCHMARK(BM_GenericAluAreaCap);
BENCHMARK(BM_ExactStepCapLambert)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ExactBrinckMaximovCapGgx)->Unit(benchmark::kMillisecond);

}  // namespace
