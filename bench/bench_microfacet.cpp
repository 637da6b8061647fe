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

template <class NDF>
void BM_D(benchmark::State& st) {
  const NDF ndf = make<NDF>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return ndf.D(d.m[k]); });
}
template <class NDF>
void BM_Lambda(benchmark::State& st) {
  const NDF ndf = make<NDF>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return ndf.Lambda(d.w[k]); });
}
template <class NDF>
void BM_G2(benchmark::State& st) {
  const NDF ndf = make<NDF>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return ndf.G2(d.w[k], d.l[k]); });
}
template <class NDF>
void BM_SampleNdf(benchmark::State& st) {
  const NDF ndf = make<NDF>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return ndf.sample_ndf(d.u[k]); });
}
template <class NDF>
void BM_SampleVndf(benchmark::State& st) {
  const NDF ndf = make<NDF>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return ndf.Sample_wm(d.w[k], d.u[k]); });
}
void BM_GgxHeitz2018(benchmark::State& st) {
  const GGX<float> g = make<GGX<float>>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return g.sample_vndf_heitz2018(d.w[k], d.u[k]); });
}
void BM_GgxBoundedVndf(benchmark::State& st) {
  const GGX<float> g = make<GGX<float>>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return sample_bounded_vndf(g, d.w[k], d.u[k]); });
}
void BM_GgxBoundedVndfPdf(benchmark::State& st) {
  const GGX<float> g = make<GGX<float>>(st.range(0));
  const Data& d = data();
  bench::per_index<kN>(st, [&](size_t k) { return pdf_bounded_vndf_reflection(g, d.w[k], d.l[k]); });
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
BENCHMARK(BM_D<GGX<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_D<Beckmann<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_D<BlinnPhong<float>>)->Arg(0);
BENCHMARK(BM_D<GTR<float>>)->Arg(0);
BENCHMARK(BM_Lambda<GGX<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_Lambda<Beckmann<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_Lambda<GTR<float>>)->Arg(0);
BENCHMARK(BM_G2<GGX<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_G2<Beckmann<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_G2<GTR<float>>)->Arg(0);
BENCHMARK(BM_GgxVisibility943);
BENCHMARK(BM_HammonVisibility945);
BENCHMARK(BM_SampleVndf<GGX<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_GgxHeitz2018)->Arg(0)->Arg(1);
BENCHMARK(BM_GgxBoundedVndf)->Arg(0)->Arg(1);
BENCHMARK(BM_GgxBoundedVndfPdf)->Arg(0)->Arg(1);
BENCHMARK(BM_SampleVndf<Beckmann<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_SampleNdf<GGX<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_SampleNdf<Beckmann<float>>)->Arg(0)->Arg(1);
BENCHMARK(BM_SampleNdf<BlinnPhong<float>>)->Arg(0);
BENCHMARK(BM_SampleNdf<GTR<float>>)->Arg(0);
BENCHMARK(BM_GgxAlbedoQuadrature)->Arg(1)->Arg(30)->Arg(100)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GtrTableBuild)->Unit(benchmark::kMillisecond);
