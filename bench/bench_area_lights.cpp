// Area-light micro-shadowing: ns per call of the fast forms (occlusion/micro_shadowing_area.h, float as a
// shader runs them) and of the exact quadrature (reference/micro_shadowing_area_exact.h), over a pool of
// random (V, N·L, ρ ∈ [1°, 40°]) inputs; the cone-clipped LTC forms (bsdf/ltc_shading.h) per light: prepare
// the light once, then the reference step (one clipped polygon) or Brinck–Maximov (the product rule).
#include <benchmark/benchmark.h>
#include <microshadow/bsdf/ltc_shading.h>
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

// The cone-clipped LTC forms, float, GGX receiver (fixed LTC coefficients of a mid-roughness, N·V = 0.8
// texel), sphere light (16-gon) about N·L and the cone's 16-gon.
bsdf::Mat3<float> bench_minv() {
  bsdf::LtcCoeffs<float> k;
  k.a = 0.46f, k.b = 0.55f, k.c = -0.21f, k.d = 0.23f;
  return k.inv_m();
}
bsdf::LtcLightCone<float> bench_light(const In& x) {
  return bsdf::ltc_light_cone_sphere(bench_minv(), Vec3f(0, 0, 1), Vec3f(0.6f, 0, 0.8f),
                                     spherical_direction(x.nl, 0.5f), std::sin(x.rho),
                                     bsdf::ltc_tail_weight(0.25f));
}
void BM_LtcConePrepareSphere(benchmark::State& s) {
  run(s, [](const In& x) { return bench_light(x).den; });
}
void BM_LtcConeStepSphere(benchmark::State& s) {  // prepare + one cone
  run(s, [](const In& x) {
    return bsdf::ltc_reference_step_area(bench_light(x), micro_shadowing::cone_cos_from_visibility(x.V));
  });
}
void BM_LtcConeBrinckMaximovSphere(benchmark::State& s) {  // prepare + the product rule (n = 4)
  run(s, [](const In& x) {
    return bsdf::ltc_micro_shadowing_area(
        [&](float z) { return micro_shadowing::brinck_maximov_2016(x.V, z); }, bench_light(x),
        micro_shadowing::brinck_maximov_2016_kinks(x.V));
  });
}
void BM_LtcConeBrinckMaximovSphereN2(benchmark::State& s) {  // the same with n = 2
  run(s, [](const In& x) {
    return bsdf::ltc_micro_shadowing_area(
        [&](float z) { return micro_shadowing::brinck_maximov_2016(x.V, z); }, bench_light(x),
        micro_shadowing::brinck_maximov_2016_kinks(x.V), 2);
  });
}

BENCHMARK(BM_StepAreaCapClosedForm);
BENCHMARK(BM_StepAreaCapMazonka);
BENCHMARK(BM_StepAreaCapOatSander);
BENCHMARK(BM_BrinckMaximovAreaCap);
BENCHMARK(BM_GenericAluAreaCap);
BENCHMARK(BM_ExactStepCapLambert)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LtcConePrepareSphere);
BENCHMARK(BM_LtcConeStepSphere);
BENCHMARK(BM_LtcConeBrinckMaximovSphere);
BENCHMARK(BM_LtcConeBrinckMaximovSphereN2);
BENCHMARK(BM_ExactBrinckMaximovCapGgx)->Unit(benchmark::kMillisecond);

}  // namespace
