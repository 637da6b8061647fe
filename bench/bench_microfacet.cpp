// ns per call of the microfacet core in float (the engine type): D, Λ, G2 and the samplers, isotropic and
// anisotropic. Inputs come from a fixed pre-generated table so the loop measures the function, not the RNG.
#include <benchmark/benchmark.h>
#include <microshadow/microfacet/albedo.h>
#include <microshadow/microfacet/beckmann.h>
#include <microshadow/microfacet/blinn_phong.h>
#include <microshadow/microfacet/bounded_vndf.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/microfacet/gtr.h>
#include <microshadow/microfacet/masking.h>

#include <vector>

#include "bench_common.h"

using namespace msh;

namespace {

constexpr size_t kN = 4096;  // power of two: index by mask

struct Data {
  std::vector<Vec3f> w, l, m;
  std::vector<Vec2f> u;
  Data() {
    Pcg32 rng(42);
    for (size_t i = 0; i < kN; ++i) {
      auto uv = [&] { return Vec2f(rng.next_float(), rng.next_float()); };
      w.push_back(sample_uniform_hemisphere(uv()));
      l.push_back(sample_uniform_hemisphere(uv()));
      m.push_back(sample_cosine_hemisphere(uv()));
      u.push_back(uv());
    }
  }
};
const Data& data() {
  static const Data d;
  return d;
}

template <class NDF>
NDF make(bool aniso);
template <>
GGX<float> make(bool a) {
  return a ? GGX<float>(0.2f, 0.5f) : GGX<float>(0.3f);
}
template <>
Beckmann<float> make(bool a) {
  return a ? Beckmann<float>(0.2f, 0.5f) : Beckmann<float>(0.3f);
}
template <>
BlinnPhong<float> make(bool) {
  return BlinnPhong<float>(20.0f);
}
template <>
GTR<float> make(bool) {
  return GTR<float>(0.3f, 1.5f);
}

// The calls of the NDF interface that BM_Ndf<NDF, Op> times: Op(ndf, inputs, k).
constexpr auto kD = [](const auto& ndf, const Data& d, size_t k) { return ndf.D(d.m[k]); };
constexpr auto kLambda = [](const auto& ndf, const Data& d, size_t k) { return ndf.Lambda(d.w[k]); };
constexpr auto kG2 = [](const auto& ndf, const Data& d, size_t k) { return ndf.G2(d.w[k], d.l[k]); };
constexpr auto kSampleNdf = [](const auto& ndf, const Data& d, size_t k) { return ndf.sample_ndf(d.u[k]); };
constexpr auto kSampleVndf = [](const auto& ndf, const Data& d, size_t k) {
  return ndf.Sample_wm(d.w[k], d.u[k]);
};

// GGX's other VNDF samplers (Heitz 2018; Eto & Tokuyoshi 2023, bounded) and the bounded sampler's pdf.
constexpr auto kHeitz2018 = [](const auto& g, const Data& d, size_t k) {
  return g.sample_vndf_heitz2018(d.w[k], d.u[k]);
};
constexpr auto kBoundedVndf = [](const auto& g, const Data& d, size_t k) {
  return sample_bounded_vndf(g, d.w[k], d.u[k]);
};
constexpr auto kBoundedVndfPdf = [](const auto& g, const Data& d, size_t k) {
  return pdf_bounded_vndf_reflection(g, d.w[k], d.l[k]);
};

// Argument 0: the isotropic NDF, 1: the anisotropic one (make<NDF>).
template <class NDF, const auto& Op>
void BM_Ndf(benchmark::State& st) {
  const NDF ndf = make<NDF>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return Op(ndf, d, k); });
}
void BM_GgxVisibility943(benchmark::State& st) {
  const Data& d = data();
  bench::per_index<kN>(st,
                       [&](size_t k) { return ggx_visibility_height_correlated(d.w[k].z, d.l[k].z, 0.3f); });
}
void BM_HammonVisibility945(benchmark::State& st) {
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return hammon_visibility(d.w[k].z, d.l[k].z, 0.3f); });
}
void BM_GgxAlbedoQuadrature(benchmark::State& st) {
  const double alpha = st.range(0) / 100.0;
  for (auto _ : st) benchmark::DoNotOptimize(ggx_directional_albedo(0.5, alpha));
}
void BM_GtrTableBuild(benchmark::State& st) {
  for (auto _ : st) benchmark::DoNotOptimize(GTR<float>(0.3f, 1.5f));
}

}  // namespace

// Arg(0) = isotropic, Arg(1) = anisotropic.
BENCHMARK_TEMPLATE(BM_Ndf, GGX<float>, kD)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, Beckmann<float>, kD)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, BlinnPhong<float>, kD)->Arg(0);
BENCHMARK_TEMPLATE(BM_Ndf, GTR<float>, kD)->Arg(0);
BENCHMARK_TEMPLATE(BM_Ndf, GGX<float>, kLambda)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, Beckmann<float>, kLambda)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, GTR<float>, kLambda)->Arg(0);
BENCHMARK_TEMPLATE(BM_Ndf, GGX<float>, kG2)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, Beckmann<float>, kG2)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, GTR<float>, kG2)->Arg(0);
BENCHMARK(BM_GgxVisibility943);
BENCHMARK(BM_HammonVisibility945);
BENCHMARK_TEMPLATE(BM_Ndf, GGX<float>, kSampleVndf)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, GGX<float>, kHeitz2018)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, GGX<float>, kBoundedVndf)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, GGX<float>, kBoundedVndfPdf)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, Beckmann<float>, kSampleVndf)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, GGX<float>, kSampleNdf)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, Beckmann<float>, kSampleNdf)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_Ndf, BlinnPhong<float>, kSampleNdf)->Arg(0);
BENCHMARK_TEMPLATE(BM_Ndf, GTR<float>, kSampleNdf)->Arg(0);
BENCHMARK(BM_GgxAlbedoQuadrature)->Arg(1)->Arg(30)->Arg(100)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GtrTableBuild)->Unit(benchmark::kMillisecond);

// ns per point of the scrambled 2D Sobol sequence (the renderer's pixel and area-light samples).
void BM_Sobol2dScrambled(benchmark::State& st) {
  uint32_t i = 0;
  for (auto _ : st) benchmark::DoNotOptimize(sobol_2d<float>(i++, 0x9e3779b9u));
}
BENCHMARK(BM_Sobol2dScrambled);
