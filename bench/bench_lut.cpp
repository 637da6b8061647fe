// Benchmarks of the micro-shadowing LUT (docs/lut.md quotes these numbers):
//   BM_LutBakeDefault         full default bake (64³ × 4 roughness), wall time on all threads
//   BM_LutVerifyAllTexels     the default bake against the semi-analytic exact term on EVERY texel (counters)
//   BM_LutStraightforwardMC   the seed's per-texel Monte Carlo loop on a texel subset, extrapolated to the
//   full
//                             table at the binned baker's error (the speed-up ratio at equal error)
//   BM_LutAzimuthError        what ignoring the azimuth costs at random (v, l), and the azimuth-aware table
//   BM_LutSample*             runtime sampler throughput
#include <benchmark/benchmark.h>
#include <microshadow/lut/micro_shadowing_baker.h>
#include <microshadow/lut/micro_shadowing_exact.h>
#include <microshadow/lut/micro_shadowing_loader.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <sys/resource.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <mutex>
#include <vector>

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

void BM_LutBakeDefault(benchmark::State& state) {
  BakeOptions o;
  o.two_d = state.range(0) != 0;
  const double cpu0 = process_cpu_seconds();
  for (auto _ : state) {
    io::Volume vol = bake_micro_shadowing_lut(o);
    benchmark::DoNotOptimize(vol.data.data());
  }
  state.counters["cpu_s_all_threads_per_bake"] = (process_cpu_seconds() - cpu0) / double(state.iterations());
  const double texels = double(o.n_vis) * o.n_nl * (o.two_d ? 1 : o.n_nv) * o.roughness.size();
  state.counters["texels"] = texels;
  state.counters["texels_per_s"] = benchmark::Counter(texels, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_LutBakeDefault)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);

// Every texel of the default bake against micro_shadowing_semi_analytic_row (16 Gauss-Legendre azimuth nodes,
// measured ≤ 1.5e-4 from the converged value, so the reported maximum is good to about that much).
void BM_LutVerifyAllTexels(benchmark::State& state) {
  const BakeOptions o;
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
      micro_shadowing_semi_analytic_row(r * r, double(y) / (o.n_nl - 1), double(z) / (o.n_nv - 1), vis.data(),
                                        n, ex.data(), 1, 1);
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

// Texels where the table is not exact by construction (0 < V < 1, outside the early-out region).
std::vector<std::array<int, 4>> random_texels(int count, uint64_t seed) {
  const BakeOptions o;
  Pcg32 rng(seed);
  std::vector<std::array<int, 4>> t;
  while (int(t.size()) < count) {
    const int x = int(rng.next_u32() % o.n_vis), y = int(rng.next_u32() % o.n_nl),
              z = int(rng.next_u32() % o.n_nv);
    const int c = int(rng.next_u32() % o.roughness.size());
    if (x == 0 || x == o.n_vis - 1 || 2.0 * x / (o.n_vis - 1) + double(y) / (o.n_nl - 1) < 1.0) continue;
    t.push_back({x, y, z, c});
  }
  return t;
}

// The straightforward baker (seed 002's shader loop per texel: independent random VNDF samples, 16 azimuth
// strata) at state.range(0) samples per texel, on 96 random texels. Its RMS error is compared with the binned
// baker's on the same texels; MC error falls as 1/sqrt(N), so the samples (and time) it needs to match the
// binned baker follow, and the full-table time is extrapolated from the per-texel time.
void BM_LutStraightforwardMC(benchmark::State& state) {
  const int samples = int(state.range(0));
  const BakeOptions o;
  const auto texels = random_texels(96, 4242);
  std::vector<double> exact(texels.size());
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const auto& t = texels[i];
    const double r = o.roughness[t[3]];
    exact[i] = ms::generic_vndf_exact_azimuth_mean(double(t[0]) / (o.n_vis - 1), r * r,
                                                   double(t[1]) / (o.n_nl - 1), double(t[2]) / (o.n_nv - 1));
  }
  static double binned_cpu = 0;
  static const io::Volume binned = [&] {
    const double c0 = process_cpu_seconds();
    io::Volume v = bake_micro_shadowing_lut(o);
    binned_cpu = process_cpu_seconds() - c0;
    return v;
  }();
  double sq_binned = 0, sq_mc = 0, max_mc = 0;
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const auto& t = texels[i];
    sq_binned += std::pow(binned.at(t[0], t[1], t[2], t[3]) - exact[i], 2);
  }
  double seconds = 0;
  for (auto _ : state) {
    sq_mc = 0, max_mc = 0;
    const double cpu0 = process_cpu_seconds();
    for (std::size_t i = 0; i < texels.size(); ++i) {
      const auto& t = texels[i];
      const double r = o.roughness[t[3]];
      const double v = monte_carlo_texel(r * r, double(t[0]) / (o.n_vis - 1), double(t[1]) / (o.n_nl - 1),
                                         double(t[2]) / (o.n_nv - 1), samples, 16, 1000 + i);
      sq_mc += (v - exact[i]) * (v - exact[i]);
      max_mc = std::max(max_mc, std::abs(v - exact[i]));
    }
    seconds = process_cpu_seconds() - cpu0;  // single-threaded loop: process CPU = this thread's CPU
  }
  const double rms_binned = std::sqrt(sq_binned / texels.size()), rms_mc = std::sqrt(sq_mc / texels.size());
  const double per_texel = seconds / texels.size();
  // Non-trivial texels of the default table (the rest are exact for any baker).
  double nontrivial = 0;
  for (int y = 0; y < o.n_nl; ++y)
    for (int x = 1; x + 1 < o.n_vis; ++x)
      if (2.0 * x / (o.n_vis - 1) + double(y) / (o.n_nl - 1) >= 1.0) nontrivial += 1;
  nontrivial *= double(o.n_nv) * o.roughness.size();
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
BENCHMARK(BM_LutStraightforwardMC)->Arg(4096)->Arg(65536)->Iterations(1)->Unit(benchmark::kMillisecond);

// Random configurations: roughness at the channel values, V uniform, v and l uniform on the hemisphere.
// "exact" is the exact term at the actual azimuth. Errors of: the exact azimuth mean (what any LUT stores:
// the cost of ignoring the azimuth), the plain default LUT, and the azimuth-aware default LUT (H = 2).
void BM_LutAzimuthError(benchmark::State& state) {
  const auto azim = default_micro_shadowing_lut(false, 2);
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
      const double exact = ms::generic_vndf_exact(V, a, a, v, l);
      const double cphi = relative_azimuth_cos(v, l);
      const double e_mean = micro_shadowing_semi_analytic_azimuth_mean(a, V, l.z, v.z, 1) - exact;
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

void BM_LutSamplePlain(benchmark::State& state) {
  const auto lut = default_micro_shadowing_lut(false, 0);
  const MicroShadowingLutView view = lut->view();
  Pcg32 rng(3);
  std::vector<float> in(4096 * 4);
  for (auto& x : in) x = rng.next_float();
  std::size_t i = 0;
  for (auto _ : state) {
    const float* p = &in[(i++ & 4095) * 4];
    benchmark::DoNotOptimize(sample_micro_shadowing<float>(view, p[0], p[1], p[2], p[3]));
  }
}
BENCHMARK(BM_LutSamplePlain);

void BM_LutSampleAzimuth(benchmark::State& state) {
  const auto lut = default_micro_shadowing_lut(false, 2);
  const MicroShadowingLutView view = lut->view();
  Pcg32 rng(3);
  std::vector<float> in(4096 * 5);
  for (auto& x : in) x = rng.next_float();
  std::size_t i = 0;
  for (auto _ : state) {
    const float* p = &in[(i++ & 4095) * 5];
    benchmark::DoNotOptimize(
        sample_micro_shadowing_azimuth<float>(view, p[0], p[1], p[2], p[3], 2.0f * p[4] - 1.0f));
  }
}
BENCHMARK(BM_LutSampleAzimuth);

}  // namespace
