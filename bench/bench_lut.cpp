// Benchmarks of the micro-shadowing LUT (docs/lut.md quotes these numbers):
//   BM_LutBakeDefault: full default bake (arg 0: cone layout, the default; 1: seed 64³ × 4; arg 2: 2D),
//     wall time on all threads and process CPU time
//   BM_LutVerifyAllTexels: the default bake against the semi-analytic exact term on EVERY texel (counters)
//   BM_LutStraightforwardMC: Zurita 2026b's per-texel Monte Carlo loop on a texel subset, extrapolated to the
//     full table at the binned baker's error (the speed-up ratio at equal error)
//   BM_LutAzimuthError: what ignoring the azimuth costs at random (v, l), and the azimuth-aware table
//   BM_LutSample*: runtime sampler throughput
#include <benchmark/benchmark.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/reference/micro_shadowing_ring.h>
#include <sys/resource.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <mutex>
#include <vector>

#include "bench_common.h"

namespace {

using namespace msh;
using namespace msh::lut;

// CPU seconds of the whole process (all threads): on a loaded machine wall time overstates the bake time, and
// Google Benchmark's CPU column counts the main thread only.
double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

LutLayout layout_arg(int64_t a) { return a == 0 ? LutLayout::Cone : LutLayout::Seed; }

void BM_LutBakeDefault(benchmark::State& state) {
  BakeOptions o = default_bake_options(layout_arg(state.range(0)));
  o.two_d = state.range(1) != 0;
  const double cpu0 = process_cpu_seconds();
  for (auto _ : state) {
    io::Volume vol = bake_micro_shadowing_lut(o);
    benchmark::DoNotOptimize(vol.data.data());
  }
  state.counters["cpu_s_all_threads_per_bake"] = (process_cpu_seconds() - cpu0) / double(state.iterations());
  const double texels = double(o.n_vis) * o.n_nl * (o.two_d ? 1 : o.n_nv) *
                        (o.layout == LutLayout::Cone ? o.n_rough : double(o.roughness.size()));
  state.counters["texels"] = texels;
  state.counters["texels_per_s"] = benchmark::Counter(texels, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_LutBakeDefault)
    ->Args({0, 0})
    ->Args({0, 1})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);

// Every texel of the default bake against micro_shadowing_semi_analytic_row (16 Gauss-Legendre azimuth nodes,
// measured ≤ 1.5e-4 from the converged value, so the reported maximum is good to about that much).
void BM_LutVerifyAllTexels(benchmark::State& state) {
  const BakeOptions o;  // the seed layout (texels on the regular grid)
  const io::Volume vol = bake_micro_shadowing_lut(o);
  const int n = o.n_vis;
  std::vector<double> vis(n);
  for (int i = 0; i < n; ++i) vis[i] = double(i) / (n - 1);
  double max_err = 0, sum_sq = 0;
  long count = 0;
  int worst[4] = {0, 0, 0, 0};
  for (auto _ : state) {
    std::mutex m;
    const int rows = int(o.roughness.size()) * o.n_nv * o.n_nl;
    tbb::parallel_for(0, rows, [&](int row) {
      const int c = row / (o.n_nv * o.n_nl), z = (row / o.n_nl) % o.n_nv, y = row % o.n_nl;
      const double r = o.roughness[c];
      std::vector<double> ex(n);
      micro_shadowing::micro_shadowing_semi_analytic_row(
          r * r, double(y) / (o.n_nl - 1), double(z) / (o.n_nv - 1), vis.data(), n, ex.data(), 1, 1);
      double local_max = 0, local_sq = 0;
      int wx = 0;
      for (int x = 0; x < n; ++x) {
        const double e = std::abs(double(vol.at(x, y, z, c)) - ex[x]);
        local_sq += e * e;
        if (e > local_max) local_max = e, wx = x;
      }
      std::lock_guard<std::mutex> lock(m);
      sum_sq += local_sq;
      count += n;
      if (local_max > max_err) max_err = local_max, worst[0] = wx, worst[1] = y, worst[2] = z, worst[3] = c;
    });
  }
  state.counters["max_abs_error"] = max_err;
  state.counters["max_abs_error_x255"] = max_err * 255.0;
  state.counters["rms_error"] = std::sqrt(sum_sq / double(count));
  state.counters["texels_checked"] = double(count);
  state.counters["worst_x"] = worst[0];
  state.counters["worst_y"] = worst[1];
  state.counters["worst_z"] = worst[2];
  state.counters["worst_channel"] = worst[3];
}
BENCHMARK(BM_LutVerifyAllTexels)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

// A texel of a default table with its physical inputs (V, N·L, N·V, roughness) and its storage index.
struct TexelInputs {
  double V, nl, nv, r;
  int x, y, z, c;
};

// Texels where the table is not exact by construction (0 < V < 1, outside the early-out region).
std::vector<TexelInputs> random_texels(const BakeOptions& o, int count, uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<TexelInputs> t;
  while (int(t.size()) < count) {
    const int x = int(rng.next_u32() % o.n_vis), y = int(rng.next_u32() % o.n_nl),
              z = int(rng.next_u32() % o.n_nv);
    if (x == 0 || x == o.n_vis - 1) continue;
    if (o.layout == LutLayout::Cone) {
      const int l = int(rng.next_u32() % o.n_rough);
      const double r = cone_roughness_of_coord(o.cone, double(l) / (o.n_rough - 1));
      const double nl = cone_axis_warp::axis_value(double(y) / (o.n_nl - 1), o.cone.nl_warp);
      const double nv = cone_nv_of_coord(o.cone, double(z) / (o.n_nv - 1), r);
      const float a = cone_warp_width(o.cone, float(r));
      if (cone_theta_of_t(double(x) / (o.n_vis - 1), float(nl), a, o.cone.top_scale) > kPi<double> / 2)
        continue;  // past V = 1 (grazing light): never sampled
      const double V = cone_visibility_of_t(double(x) / (o.n_vis - 1), float(nl), a, o.cone.top_scale);
      t.push_back({V, nl, nv, r, x, y, l * o.n_nv + z, 0});
    } else {
      const int c = int(rng.next_u32() % o.roughness.size());
      const double V = double(x) / (o.n_vis - 1), nl = double(y) / (o.n_nl - 1);
      if (2.0 * V + nl < 1.0) continue;
      t.push_back({V, nl, double(z) / (o.n_nv - 1), o.roughness[c], x, y, z, c});
    }
  }
  return t;
}

// The straightforward baker (Zurita 2026's shader loop per texel: independent random VNDF samples, 16
// azimuth strata) at state.range(0) samples per texel, on 96 random texels of the default table of layout
// state.range(1) (0 cone, 1 seed). Its RMS error is compared with the binned baker's on the same texels; MC
// error falls as 1/sqrt(N), so the samples (and time) it needs to match the binned baker follow, and the
// full-table time is extrapolated from the per-texel time.
void BM_LutStraightforwardMC(benchmark::State& state) {
  const int samples = int(state.range(0));
  const BakeOptions o = default_bake_options(layout_arg(state.range(1)));
  const auto texels = random_texels(o, 96, 4242);
  std::vector<double> exact(texels.size());
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const auto& t = texels[i];
    exact[i] = micro_shadowing::generic_vndf_exact_azimuth_mean(t.V, t.r * t.r, t.nl, t.nv);
  }
  double binned_cpu = 0;
  const double c0 = process_cpu_seconds();
  const io::Volume binned = bake_micro_shadowing_lut(o);
  binned_cpu = process_cpu_seconds() - c0;
  double sq_binned = 0, sq_mc = 0, max_mc = 0;
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const auto& t = texels[i];
    sq_binned += std::pow(binned.at(t.x, t.y, t.z, t.c) - exact[i], 2);
  }
  double seconds = 0;
  for (auto _ : state) {
    sq_mc = 0, max_mc = 0;
    const double cpu0 = process_cpu_seconds();
    for (std::size_t i = 0; i < texels.size(); ++i) {
      const auto& t = texels[i];
      const double v = monte_carlo_texel(t.r * t.r, t.V, t.nl, t.nv, samples, 16, 1000 + i);
      sq_mc += (v - exact[i]) * (v - exact[i]);
      max_mc = std::max(max_mc, std::abs(v - exact[i]));
    }
    seconds = process_cpu_seconds() - cpu0;  // single-threaded loop: process CPU = this thread's CPU
  }
  const double rms_binned = std::sqrt(sq_binned / texels.size()), rms_mc = std::sqrt(sq_mc / texels.size());
  const double per_texel = seconds / texels.size();
  // Non-trivial texels of the default table (the rest are exact for any baker).
  double nontrivial = 0;
  if (o.layout == LutLayout::Cone) {
    nontrivial = double(o.n_vis - 2) * o.n_nl * o.n_nv * o.n_rough;  // (a few past V = 1 included)
  } else {
    for (int y = 0; y < o.n_nl; ++y)
      for (int x = 1; x + 1 < o.n_vis; ++x)
        if (2.0 * x / (o.n_vis - 1) + double(y) / (o.n_nl - 1) >= 1.0) nontrivial += 1;
    nontrivial *= double(o.n_nv) * o.roughness.size();
  }
  const double samples_equal = samples * std::pow(rms_mc / rms_binned, 2);
  state.counters["rms_error_mc"] = rms_mc;
  state.counters["max_error_mc"] = max_mc;
  state.counters["rms_error_binned"] = rms_binned;
  state.counters["cpu_us_per_texel"] = per_texel * 1e6;
  state.counters["samples_for_equal_rms"] = samples_equal;
  state.counters["full_table_cpu_s_at_this_N"] = per_texel * nontrivial;
  state.counters["full_table_cpu_s_at_equal_rms"] = per_texel * (samples_equal / samples) * nontrivial;
  state.counters["binned_bake_cpu_s"] = binned_cpu;
  state.counters["speedup_at_equal_rms"] = per_texel * (samples_equal / samples) * nontrivial / binned_cpu;
}
BENCHMARK(BM_LutStraightforwardMC)
    ->Args({4096, 0})
    ->Args({65536, 0})
    ->Args({65536, 1})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

// Random configurations: roughness at the channel values, V uniform, v and l uniform on the hemisphere.
// "exact" is the exact term at the actual azimuth. Errors of: the exact azimuth mean (what any LUT stores:
// the cost of ignoring the azimuth), the plain seed-layout LUT, and the azimuth-aware seed-layout LUT (H =
// 2). (The cone layout's azimuth figures: tests/test_lut_sampler.cpp and docs/lut.md.)
void BM_LutAzimuthError(benchmark::State& state) {
  const auto azim = default_micro_shadowing_lut(false, 2, LutLayout::Seed);
  const MicroShadowingLutView view = azim->view();
  struct Acc {
    double sa = 0, sq = 0, mx = 0;
    void add(double e) { sa += std::abs(e), sq += e * e, mx = std::max(mx, std::abs(e)); }
  } mean_only, plain, aware, plain_r, aware_r;
  int n = 0, n_r = 0;
  for (auto _ : state) {
    Pcg32 rng(7);
    for (int i = 0; i < 2000; ++i) {
      const double r = kDefaultRoughness[i % 4], a = r * r, V = rng.next_double();
      const Vec3d v = sample_uniform_hemisphere<double>({rng.next_double(), rng.next_double()});
      const Vec3d l = sample_uniform_hemisphere<double>({rng.next_double(), rng.next_double()});
      const double exact = micro_shadowing::generic_vndf_exact(V, a, a, v, l);
      const double cphi = relative_azimuth_cos(v, l);
      const double e_mean =
          micro_shadowing::micro_shadowing_semi_analytic_azimuth_mean(a, V, l.z, v.z, 1) - exact;
      const double e0 = sample_micro_shadowing<double>(view, V, l.z, v.z, r) - exact;
      const double e2 = sample_micro_shadowing_azimuth<double>(view, V, l.z, v.z, r, cphi) - exact;
      mean_only.add(e_mean), plain.add(e0), aware.add(e2), ++n;
      if (r >= 0.4) plain_r.add(e0), aware_r.add(e2), ++n_r;
    }
  }
  state.counters["azimuth_mean_vs_exact_mean_abs"] = mean_only.sa / n;
  state.counters["azimuth_mean_vs_exact_rms"] = std::sqrt(mean_only.sq / n);
  state.counters["azimuth_mean_vs_exact_max"] = mean_only.mx;
  state.counters["plain_lut_mean_abs"] = plain.sa / n;
  state.counters["plain_lut_rms"] = std::sqrt(plain.sq / n);
  state.counters["azimuth_lut_mean_abs"] = aware.sa / n;
  state.counters["azimuth_lut_rms"] = std::sqrt(aware.sq / n);
  state.counters["plain_lut_rms_r>=0.4"] = std::sqrt(plain_r.sq / n_r);
  state.counters["azimuth_lut_rms_r>=0.4"] = std::sqrt(aware_r.sq / n_r);
  state.counters["mean_abs_ratio"] = plain.sa / aware.sa;
}
BENCHMARK(BM_LutAzimuthError)->Iterations(1)->Unit(benchmark::kMillisecond);

// Sampler throughput, arg 0: the cone layout (default), 1: the seed layout.
void BM_LutSamplePlain(benchmark::State& state) {
  const auto lut = default_micro_shadowing_lut(false, 0, layout_arg(state.range(0)));
  const MicroShadowingLutView view = lut->view();
  bench::per_row(state, bench::uniform_rows<4>(3),
                 [&](const auto& p) { return sample_micro_shadowing<float>(view, p[0], p[1], p[2], p[3]); });
}
BENCHMARK(BM_LutSamplePlain)->Arg(0)->Arg(1);

void BM_LutSampleAzimuth(benchmark::State& state) {
  const LutLayout layout = layout_arg(state.range(0));
  const auto lut = default_micro_shadowing_lut(false, layout == LutLayout::Cone ? 3 : 2, layout);
  const MicroShadowingLutView view = lut->view();
  bench::per_row(state, bench::uniform_rows<5>(3), [&](const auto& p) {
    return sample_micro_shadowing_azimuth<float>(view, p[0], p[1], p[2], p[3], 2.0f * p[4] - 1.0f);
  });
}
BENCHMARK(BM_LutSampleAzimuth)->Arg(0)->Arg(1);

}  // namespace
