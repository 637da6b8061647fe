// BRDF models part 1: ns per evaluation (float, as in an engine, and double) over a pool of random
// upper-hemisphere direction pairs; VNDF sampling; the albedo integrator and one DFG texel bake.
#include <benchmark/benchmark.h>
#include <microshadow/bsdf/diffuse.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/multiscatter.h>
#include <microshadow/bsdf/runtime/albedo.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/math/sampling.h>

#include <vector>

#include "bench_common.h"

namespace {

using namespace msh;
using namespace msh::bsdf;

template <class T>
void BM_BsdfGgxSchlick(benchmark::State& s) {
  const GGX<T> g(T(0.25));
  bench::per_pair(s, bench::dir_pool<T, 99, true>(), [&](auto& wo, auto& wi, auto&) {
    const auto e = microfacet_specular(g, wo, wi);
    return fresnel_schlick(T(0.04), e.cos_hl) * e.f1;
  });
}
template <class T>
void BM_BsdfGgxConductor(benchmark::State& s) {
  const GGX<T> g(T(0.25));
  bench::per_pair(s, bench::dir_pool<T, 99, true>(), [&](auto& wo, auto& wi, auto&) {
    const auto e = microfacet_specular(g, wo, wi);
    return fresnel_conductor(e.cos_hl, T(0.143), T(3.983)) * e.f1;
  });
}
template <class T>
void BM_BsdfGgxMultiscatter(benchmark::State& s) {
  const GGX<T> g(T(0.49));
  const T favg = fresnel_average_schlick<T>(T(0.5));
  bench::per_pair(s, bench::dir_pool<T, 99, true>(), [&](auto& wo, auto& wi, auto&) {
    const auto e = microfacet_specular(g, wo, wi);
    return fresnel_schlick(T(0.5), e.cos_hl) * e.f1 + ggx_multiscatter(favg, T(0.7), wi, wo);
  });
}
template <class T>
void BM_BsdfGgxDualLobe(benchmark::State& s) {
  const GGXMixture<T> m(GGX<T>(T(0.04)), GGX<T>(T(0.5)), T(0.3));
  bench::per_pair(s, bench::dir_pool<T, 99, true>(),
                  [&](auto& wo, auto& wi, auto&) { return microfacet_specular(m, wo, wi).f1; });
}
template <class T>
void BM_BsdfGgxSampleVndf(benchmark::State& s) {
  const GGX<T> g(T(0.25));
  bench::per_pair(s, bench::dir_pool<T, 99, true>(), [&](auto& wo, auto&, auto& u) {
    const auto r = sample_microfacet_specular(g, wo, u);
    return r ? r->weight_f1 : T(0);
  });
}
template <class T>
void BM_BsdfDisneyDiffuse(benchmark::State& s) {
  bench::per_pair(s, bench::dir_pool<T, 99, true>(),
                  [&](auto& wo, auto& wi, auto&) { return diffuse_disney(T(0.8), T(0.5), T(0.3), wi, wo); });
}
template <class T>
void BM_BsdfHammon(benchmark::State& s) {
  bench::per_pair(s, bench::dir_pool<T, 99, true>(), [&](auto& wo, auto& wi, auto&) {
    return diffuse_hammon(T(0.8), T(0.25), T(0.04), wi, wo);
  });
}
template <class T>
void BM_BsdfOrenNayar(benchmark::State& s) {
  bench::per_pair(s, bench::dir_pool<T, 99, true>(),
                  [&](auto& wo, auto& wi, auto&) { return diffuse_oren_nayar(T(0.8), T(0.5), wi, wo); });
}
template <class T>
void BM_BsdfOrenNayarQualitative(benchmark::State& s) {
  bench::per_pair(s, bench::dir_pool<T, 99, true>(), [&](auto& wo, auto& wi, auto&) {
    return diffuse_oren_nayar_qualitative(T(0.8), T(0.5), wi, wo);
  });
}
template <class T>
void BM_BsdfKsk(benchmark::State& s) {
  const T ravg = ggx_albedo_schlick_avg(T(0.04), T(0.5));
  bench::per_pair(s, bench::dir_pool<T, 99, true>(), [&](auto& wo, auto& wi, auto&) {
    return diffuse_ksk(T(0.8), ggx_albedo_schlick(T(0.04), wi.z, T(0.5)),
                       ggx_albedo_schlick(T(0.04), wo.z, T(0.5)), ravg, wi, wo);
  });
}

void BM_BsdfDfgTexel4096(benchmark::State& s) {
  double mu = 0.1;
  for (auto _ : s) {
    benchmark::DoNotOptimize(ggx_dfg_reference(mu, 0.6, 4096));
    mu = mu > 0.9 ? 0.1 : mu + 0.1;
  }
}

BENCHMARK(BM_BsdfGgxSchlick<float>);
BENCHMARK(BM_BsdfGgxSchlick<double>);
BENCHMARK(BM_BsdfGgxConductor<float>);
BENCHMARK(BM_BsdfGgxMultiscatter<float>);
BENCHMARK(BM_BsdfGgxDualLobe<float>);
BENCHMARK(BM_BsdfGgxSampleVndf<float>);
BENCHMARK(BM_BsdfDisneyDiffuse<float>);
BENCHMARK(BM_BsdfHammon<float>);
BENCHMARK(BM_BsdfOrenNayar<float>);
BENCHMARK(BM_BsdfOrenNayarQualitative<float>);
BENCHMARK(BM_BsdfKsk<float>);
BENCHMARK(BM_BsdfDfgTexel4096);

}  // namespace
