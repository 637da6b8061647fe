// Cost of the as-used accuracy measurement (lut/runtime/micro_shadowing_verify.h; docs/lut.md "Verify" quotes it):
//   BM_VerifyInputs/0   N inputs and their exact azimuth means (the expensive reference), one thread
//   BM_VerifyInputs/1   the same against the exact term at the input's azimuth
//   BM_VerifyMeasure    the statistics of one cheap callable on 10⁴ precomputed inputs
#include <benchmark/benchmark.h>
#include <microshadow/lut/runtime/micro_shadowing_verify.h>

namespace {

using namespace msh::lut;

void BM_VerifyInputs(benchmark::State& state) {
  VerifyOptions o;
  o.samples = 256;
  o.threads = 1;  // CPU time per input, independent of the machine's load
  o.against = state.range(0) ? VerifyReference::Azimuth : VerifyReference::AzimuthMean;
  for (auto _ : state) benchmark::DoNotOptimize(make_verify_inputs(o));
  state.counters["ms_per_input"] = benchmark::Counter(
      double(o.samples) * 1e-3, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_VerifyInputs)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_VerifyMeasure(benchmark::State& state) {
  VerifyOptions o;
  o.samples = 10000;
  o.threads = 1;
  o.against = VerifyReference::Azimuth;  // the cheaper reference; measure() does not depend on it
  const std::vector<VerifyInput> in = make_verify_inputs(o);
  const MicroShadowingApprox f = [](float V, float nl, float, float, float) { return V * nl; };
  for (auto _ : state) benchmark::DoNotOptimize(measure(in, f, o));
}
BENCHMARK(BM_VerifyMeasure)->Unit(benchmark::kMillisecond);

}  // namespace
