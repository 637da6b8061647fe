// Shared pieces of the benchmarks (one executable, microshadow_bench).
#pragma once

#include <benchmark/benchmark.h>

#include <cstddef>
#include <vector>

namespace msh::bench {

// The usual per-call loop: each iteration calls f on the next of a fixed pool of prepared inputs (cycling
// through the first 256, so that the loop measures f and not the input generation) and keeps the result.
template <class P, class F>
void per_call(benchmark::State& st, const std::vector<P>& pool, F&& f) {
  std::size_t i = 0;
  for (auto _ : st) benchmark::DoNotOptimize(f(pool[i++ & 255]));
}

}  // namespace msh::bench
