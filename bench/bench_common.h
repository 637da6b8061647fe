// Shared pieces of the benchmarks (one executable, microshadow_bench).
#pragma once

#include <benchmark/benchmark.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <vector>

namespace msh::bench {

// The usual per-call loop over prepared inputs: iteration i calls f(i mod N) (N a power of two) and keeps the
// result, so that the loop measures f and not the input generation.
template <std::size_t N, class F>
void per_index(benchmark::State& st, F&& f) {
  static_assert(N > 0 && (N & (N - 1)) == 0, "N must be a power of two");
  std::size_t i = 0;
  for (auto _ : st) benchmark::DoNotOptimize(f(i++ & (N - 1)));
}

// The same over the first 256 entries of a pool: f(pool[i mod 256]).
template <class P, class F>
void per_call(benchmark::State& st, const std::vector<P>& pool, F&& f) {
  per_index<256>(st, [&](std::size_t k) { return f(pool[k]); });
}

// 4096 rows of K uniform floats in [0, 1) from Pcg32(seed), drawn row after row; per_row calls f(row i mod
// 4096).
template <std::size_t K>
std::vector<std::array<float, K>> uniform_rows(uint64_t seed) {
  std::vector<std::array<float, K>> r(4096);
  Pcg32 rng(seed);
  for (auto& row : r)
    for (float& x : row) x = rng.next_float();
  return r;
}
template <std::size_t K, class F>
void per_row(benchmark::State& st, const std::vector<std::array<float, K>>& rows, F&& f) {
  per_index<4096>(st, [&](std::size_t k) { return f(rows[k]); });
}

// A pool of 256 inputs outside the early-out region: draw(rng) from Pcg32(seed) until 256 are kept
// (std::nullopt rejects a draw).
template <class P, class Draw>
std::vector<P> pool_of_256(uint64_t seed, Draw draw) {
  std::vector<P> r;
  Pcg32 rng(seed);
  while (r.size() < 256)
    if (const std::optional<P> q = draw(rng)) r.push_back(*q);
  return r;
}

// 4096 direction pairs (wo, wi) uniform over the upper hemisphere from Pcg32(seed); with `with_u` each pair
// is followed by a uniform 2D sample u (drawn in that order: wo, wi, u).
template <class T>
struct DirPool {
  std::vector<Vec3<T>> wo, wi;
  std::vector<Vec2<T>> u;
};
template <class T>
DirPool<T> make_dir_pool(uint64_t seed, bool with_u) {
  DirPool<T> r;
  Pcg32 rng(seed);
  for (int i = 0; i < 4096; ++i) {
    r.wo.push_back(Vec3<T>(sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double()))));
    r.wi.push_back(Vec3<T>(sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double()))));
    if (with_u) r.u.push_back(Vec2<T>(T(rng.next_double()), T(rng.next_double())));
  }
  return r;
}
// The pool of (Seed, WithU), made once.
template <class T, uint64_t Seed, bool WithU>
const DirPool<T>& dir_pool() {
  static const DirPool<T> p = make_dir_pool<T>(Seed, WithU);
  return p;
}

// Per call of f(wo, wi) (or f(wo, wi, u) for a pool with u) over the 4096 entries of `pool`.
template <class T, class F>
void per_pair(benchmark::State& st, const DirPool<T>& pool, F&& f) {
  per_index<4096>(st, [&](std::size_t i) {
    if constexpr (std::is_invocable_v<F&, const Vec3<T>&, const Vec3<T>&, const Vec2<T>&>)
      return f(pool.wo[i], pool.wi[i], pool.u[i]);
    else
      return f(pool.wo[i], pool.wi[i]);
  });
}

}  // namespace msh::bench
