// Binned quasi-Monte Carlo baker for the micro-shadowing LUT; see micro_shadowing_baker.h and docs/lut.md.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/math/quadrature.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cmath>
#include <mutex>

namespace msh::lut {

// micro_shadowing_bins.cpp (Highway): bins[j] for the row pass below.
void compute_bins(const float* mz, const float* p, std::size_t n, float zl, float sl, int32_t n_vis,
                  int32_t* bins);
int64_t compute_bins_cone(const float* mz, const float* p, std::size_t n, float zl, float sl, float a,
                          float ulo, float inv_range, int32_t n_vis, int32_t* bins);

void validate_cone(const ConeLayoutParams& p) {
  if (!(p.roughness_min > 0.0f && p.roughness_max > p.roughness_min && p.roughness_max <= 1.0f))
    throw InputError(fmt::format("cone layout roughness range must satisfy 0 < min < max ≤ 1, got [{}, {}]",
                                 p.roughness_min, p.roughness_max));
  if (!(p.roughness_power >= 0.0f && p.roughness_power <= 4.0f))
    throw InputError(fmt::format("cone layout roughness power must be in [0, 4], got {}", p.roughness_power));
  if (!(p.warp_scale > 0.0f && p.warp_scale <= 100.0f))
    throw InputError(fmt::format("cone layout warp scale must be in (0, 100], got {}", p.warp_scale));
  if (p.nl_warp < 0 || p.nl_warp > 4 || p.nl_warp == 3 || p.nv_warp < 0 || p.nv_warp > 4)
    throw InputError("cone layout axis warps must be 0, 1, 2 or 4 (N·V also 3)");
  if (!(p.top_scale >= 0.0f && p.top_scale <= 100.0f))
    throw InputError(fmt::format("cone layout top scale must be in [0, 100], got {}", p.top_scale));
  if (!(p.nv_scale > 0.0f && p.nv_scale <= 100.0f))
    throw InputError(fmt::format("cone layout N·V scale must be in (0, 100], got {}", p.nv_scale));
}

void validate(const BakeOptions& o) {
  auto size_ok = [](int n) { return n >= 2 && n <= 4096; };
  if (!size_ok(o.n_vis))
    throw InputError(fmt::format("Visibility size must be in [2, 4096], got {}", o.n_vis));
  if (!size_ok(o.n_nl)) throw InputError(fmt::format("N·L size must be in [2, 4096], got {}", o.n_nl));
  if (!o.two_d && !size_ok(o.n_nv))
    throw InputError(fmt::format("N·V size must be in [2, 4096], got {}", o.n_nv));
  if (o.layout == LutLayout::Cone) {
    validate_cone(o.cone);
    if (o.n_rough < 2 || o.n_rough > 256)
      throw InputError(fmt::format("roughness slabs must be in [2, 256], got {}", o.n_rough));
    if (o.harmonics < 0 || o.harmonics > 3)
      throw InputError(
          fmt::format("the cone layout holds 0 to 3 harmonics (channels a_0..a_3), got {}", o.harmonics));
  } else if (o.roughness.empty() || o.roughness.size() > 4)
    throw InputError(fmt::format("roughness list must have 1 to 4 values, got {}", o.roughness.size()));
  for (std::size_t i = 0; i < o.roughness.size(); ++i) {
    const double r = o.roughness[i];
    if (!(r >= 0.0 && r <= 1.0)) throw InputError(fmt::format("roughness must be in [0, 1], got {}", r));
    if (i > 0 && !(r > o.roughness[i - 1]))
      throw InputError("roughness values must be strictly increasing (one per channel)");
  }
  if (o.harmonics < 0 || o.harmonics > 8)
    throw InputError(fmt::format("harmonics must be in [0, 8], got {}", o.harmonics));
  if (o.samples < 1 || o.samples > (1 << 24))
    throw InputError(fmt::format("samples must be in [1, 2^24], got {}", o.samples));
  if (o.phi_nodes < 1 || o.phi_nodes > 256)
    throw InputError(fmt::format("phi nodes must be in [1, 256], got {}", o.phi_nodes));
  if (o.threads < 0) throw InputError(fmt::format("threads must be ≥ 0, got {}", o.threads));
  const double values =
      double(o.n_vis) * o.n_nl * (o.two_d ? 1 : o.n_nv) * (o.harmonics + 1) * double(o.roughness.size());
  if (values > double(1 << 28))
    throw InputError(fmt::format("table too large: {} values (at most 2^28)", values));
}

BakeOptions default_bake_options(LutLayout layout, int harmonics) {
  BakeOptions o;
  o.harmonics = harmonics;
  if (layout == LutLayout::Cone) {
    o.layout = LutLayout::Cone;
    o.n_vis = 64, o.n_nl = 48, o.n_nv = 16, o.n_rough = 16;
    if (harmonics > 0) o.n_vis = 48, o.n_nl = 40;  // RGBA16F within 4 MiB; the Fourier truncation dominates
    o.samples = 4096;
  }
  return o;
}

int samples_for_roughness(const BakeOptions& o, double roughness) {
  int n = 1;
  while (n < o.samples) n *= 2;
  if (roughness < 0.25) return std::max(1, n / 4);
  if (roughness < 0.55) return std::max(1, n / 2);
  return n;
}

// The project's Gauss-Legendre rule (math/quadrature.h) mapped to [0, π]; weights sum to 1.
void phi_rule(int n, std::vector<double>& phi, std::vector<double>& weight) {
  const GaussLegendre01<double> gl(n);
  phi.resize(gl.x.size());
  for (size_t i = 0; i < gl.x.size(); ++i) phi[i] = kPi<double> * gl.x[i];
  weight = gl.w;
}

MicroShadowingLutView make_cone_view(const io::Volume& vol, int n_rough, int harmonics,
                                     const ConeLayoutParams& params) {
  validate_cone(params);
  if (vol.channels < 1 || vol.channels > 4)
    throw InputError(fmt::format("a LUT has 1 to 4 channels, got {}", vol.channels));
  if (harmonics < 0 || harmonics >= vol.channels)
    throw InputError(
        fmt::format("cone-layout LUT with {} channels cannot hold {} harmonics", vol.channels, harmonics));
  if (n_rough < 2 || vol.depth % n_rough != 0)
    throw InputError(
        fmt::format("LUT depth {} is not a multiple of {} roughness slabs (≥ 2)", vol.depth, n_rough));
  if (vol.width < 2 || vol.height < 2) throw InputError("a LUT needs at least 2 texels along t and N·L");
  if (vol.data.size() != vol.texel_count() * std::size_t(vol.channels))
    throw InputError("LUT data size mismatch");
  MicroShadowingLutView v;
  v.layout = LutLayout::Cone;
  v.data = vol.data.data();
  v.n_vis = vol.width;
  v.n_nl = vol.height;
  v.n_nv = vol.depth / n_rough;
  v.n_rough = n_rough;
  v.channels = vol.channels;
  v.harmonics = harmonics;
  v.cone = params;
  return v;
}

MicroShadowingLutView make_view(const io::Volume& vol, const std::vector<double>& roughness, int harmonics) {
  if (vol.channels < 1 || vol.channels > 4)
    throw InputError(fmt::format("a LUT has 1 to 4 channels, got {}", vol.channels));
  if (int(roughness.size()) != vol.channels)
    throw InputError(
        fmt::format("{} roughness values for a LUT with {} channels", roughness.size(), vol.channels));
  if (harmonics < 0 || vol.depth % (harmonics + 1) != 0)
    throw InputError(
        fmt::format("LUT depth {} is not a multiple of harmonics + 1 = {}", vol.depth, harmonics + 1));
  if (vol.width < 2 || vol.height < 2)
    throw InputError("a LUT needs at least 2 texels along Visibility and N·L");
  if (vol.data.size() != vol.texel_count() * std::size_t(vol.channels))
    throw InputError("LUT data size mismatch");
  MicroShadowingLutView v;
  v.data = vol.data.data();
  v.n_vis = vol.width;
  v.n_nl = vol.height;
  v.n_nv = vol.depth / (harmonics + 1);
  v.channels = vol.channels;
  v.harmonics = harmonics;
  for (int c = 0; c < vol.channels; ++c) v.roughness[c] = float(roughness[c]);
  return v;
}

namespace {

// VNDF samples of one (α, N·V) pair for one φ node, reduced to what the row pass needs: n·m and the
// tangential part of m along the light's azimuth, (m_x cos φ + m_y sin φ), so m·l = sl·P + zl·n·m.
struct NodeSamples {
  std::vector<float> mz, p;
};

// Precomputed Sobol points of one φ node: (cos 2πu1, sin 2πu1, u2) for the spherical-caps VNDF sampler.
struct NodePoints {
  std::vector<double> c, s, u2;
};

void draw_samples(const NodePoints& pts, std::size_t n, double alpha, double zv, double cos_phi,
                  double sin_phi, NodeSamples& out) {
  // GGX::Sample_wm (Dupuy & Benyoub 2023) for v = (sv, 0, zv), through its hoisted form: the stretched v
  // once per task and cos 2πu1, sin 2πu1 once per φ node (pts.c, pts.s).
  const GGX<double> ggx(alpha);
  const double sv = safe_sqrt(1.0 - zv * zv);
  const Vec3d wi = normalize(Vec3d(alpha * sv, 0.0, zv));
  out.mz.resize(n);
  out.p.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Vec3d m = ggx.sample_vndf_spherical_caps_stretched(wi, pts.u2[j], pts.c[j], pts.s[j]);
    out.mz[j] = float(m.z);
    out.p[j] = float(m.x * cos_phi + m.y * sin_phi);
  }
}

// draw_samples at every φ node (points[k] at azimuth phi[k]) for one (α, N·V) pair.
std::vector<NodeSamples> draw_node_samples(const std::vector<NodePoints>& points, std::size_t n, double alpha,
                                           double zv, const std::vector<double>& phi) {
  std::vector<NodeSamples> smp(points.size());
  for (std::size_t k = 0; k < points.size(); ++k)
    draw_samples(points[k], n, alpha, zv, std::cos(phi[k]), std::sin(phi[k]), smp[k]);
  return smp;
}

// One (N·L, φ) pass: cumulative counts of samples with min(n·m, m·l) > c_i for every Visibility texel i.
// Bin b = floor((n−1)(1 − key²)) + 1 is the first texel whose threshold the key exceeds (key > c_i ⟺
// i > (n−1)(1 − key²)); bin n collects key ≤ 0 (not lit even by the hemisphere).
void histogram(const std::vector<int32_t>& bins, int n_vis, std::vector<uint32_t>& hist) {
  const std::size_t n = bins.size();
  const int32_t* b = bins.data();
  // Four interleaved histograms so consecutive increments of the same bin do not serialize.
  const int stride = n_vis + 1;
  hist.assign(4 * stride, 0u);
  std::size_t j = 0;
  for (; j + 4 <= n; j += 4) {
    ++hist[b[j]];
    ++hist[stride + b[j + 1]];
    ++hist[2 * stride + b[j + 2]];
    ++hist[3 * stride + b[j + 3]];
  }
  for (; j < n; ++j) ++hist[b[j]];
  for (int i = 0; i < stride; ++i) hist[i] += hist[stride + i] + hist[2 * stride + i] + hist[3 * stride + i];
}

void row_pass(const NodeSamples& smp, float zl, float sl, int n_vis, std::vector<int32_t>& bins,
              std::vector<uint32_t>& hist) {
  const std::size_t n = smp.mz.size();
  bins.resize(n);
  compute_bins(smp.mz.data(), smp.p.data(), n, zl, sl, n_vis, bins.data());
  histogram(bins, n_vis, hist);
}

// Cone layout row: bins by the t coordinate of the key's cone (compute_bins_cone); returns the hemisphere
// count.
int64_t row_pass_cone(const NodeSamples& smp, float zl, float sl, float a, float ulo, float inv_range,
                      int n_t, std::vector<int32_t>& bins, std::vector<uint32_t>& hist) {
  const std::size_t n = smp.mz.size();
  bins.resize(n);
  const int64_t lit =
      compute_bins_cone(smp.mz.data(), smp.p.data(), n, zl, sl, a, ulo, inv_range, n_t, bins.data());
  histogram(bins, n_t, hist);
  return lit;
}

// Runs fn(task) for task ∈ [0, tasks) on oneTBB (local arena with o.threads), reporting progress.
template <class F>
void run_tasks(const BakeOptions& o, int tasks, const F& fn) {
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  auto all_rows = [&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, tasks, 1), [&](const tbb::blocked_range<int>& range) {
      for (int t = range.begin(); t != range.end(); ++t) {
        fn(t);
        const int d = ++done;
        if (o.progress) {
          std::lock_guard<std::mutex> lock(progress_mutex);
          o.progress(double(d) / tasks);
        }
      }
    });
  };
  if (o.threads > 0) {
    tbb::task_arena arena(o.threads);  // local limit: other work in the process keeps its threads
    arena.execute(all_rows);
  } else {
    all_rows();
  }
}

// Owen-scrambled Sobol points per φ node (independent scrambles), as (cos 2πu1, sin 2πu1, u2).
std::vector<NodePoints> make_points(const BakeOptions& o, int K, int max_samples) {
  std::vector<NodePoints> points(K);
  for (int k = 0; k < K; ++k) {
    const uint32_t seed = hash_combine(o.seed, uint32_t(k) + 1u) | 1u;  // seed 0 would mean "unscrambled"
    NodePoints& pt = points[k];
    pt.c.resize(max_samples), pt.s.resize(max_samples), pt.u2.resize(max_samples);
    for (int j = 0; j < max_samples; ++j) {
      const Vec2d u = sobol_2d<double>(uint32_t(j), seed);
      pt.c[j] = std::cos(2.0 * kPi<double> * u.x);
      pt.s[j] = std::sin(2.0 * kPi<double> * u.x);
      pt.u2[j] = u.y;
    }
  }
  return points;
}

// The cone layout (micro_shadowing_lut.h): one task per (roughness slab, N·V slice), rows along N·L, the t
// row of each from one binned pass per φ node.
io::Volume bake_cone(const BakeOptions& o) {
  const int n_t = o.n_vis, n_nl = o.n_nl, n_nv = o.two_d ? 1 : o.n_nv, H = o.harmonics, nr = o.n_rough;
  io::Volume vol(n_t, n_nl, n_nv * nr, H + 1);
  std::vector<double> phi, wphi;
  phi_rule(o.phi_nodes, phi, wphi);
  const int K = o.phi_nodes;
  std::vector<double> rough(nr);
  int max_samples = 1;
  for (int l = 0; l < nr; ++l) {
    rough[l] = cone_roughness_of_coord(o.cone, nr > 1 ? double(l) / (nr - 1) : 0.0);
    max_samples = std::max(max_samples, samples_for_roughness(o, rough[l]));
  }
  const std::vector<NodePoints> points = make_points(o, K, max_samples);
  run_tasks(o, nr * n_nv, [&](int task) {
    const int l = task / n_nv, z = task % n_nv;
    const double alpha = std::max(roughness_to_alpha(rough[l]), double(GGX<double>::kMinAlpha));
    const float a = cone_warp_width(o.cone, float(rough[l]));
    const double zv = o.two_d ? 1.0 : cone_nv_of_coord(o.cone, double(z) / (n_nv - 1), rough[l]);
    const std::size_t n_samples = std::size_t(samples_for_roughness(o, rough[l]));
    const std::vector<NodeSamples> smp = draw_node_samples(points, n_samples, alpha, zv, phi);
    std::vector<int32_t> bins;
    std::vector<uint32_t> hist;
    std::vector<double> acc((H + 1) * n_t), ratio(n_t);
    for (int y = 0; y < n_nl; ++y) {
      const float zl = float(cone_axis_warp::axis_value(double(y) / (n_nl - 1), o.cone.nl_warp));
      const float sl = std::sqrt(std::max(0.0f, 1.0f - zl * zl));
      const float ulo = cone_axis_warp::warp_u(-std::sqrt(0.5f * (1.0f - zl)), a);
      const float dtop = cone_d_top(zl, a, o.cone.top_scale);
      const float inv = 1.0f / (cone_axis_warp::warp_u(dtop, a) - ulo);

      std::fill(acc.begin(), acc.end(), 0.0);
      for (int k = 0; k < K; ++k) {
        const double den = double(row_pass_cone(smp[k], zl, sl, a, ulo, inv, n_t, bins, hist));
        uint64_t cum = 0;
        for (int i = 0; i < n_t; ++i) {
          cum += hist[i];
          ratio[i] = double(cum);
        }
        if (!(den > 0.0)) continue;
        for (int h = 0; h <= H; ++h) {
          const double w = h == 0 ? wphi[k] : 2.0 * wphi[k] * std::cos(h * phi[k]);
          for (int i = 0; i < n_t; ++i) acc[h * n_t + i] += w * (ratio[i] / den);
        }
      }
      for (int h = 0; h <= H; ++h)
        for (int i = 0; i < n_t; ++i) {
          double value = acc[h * n_t + i];
          if (i == n_t - 1)
            value = h == 0 ? 1.0 : 0.0;  // t = 1, at or just past V = 1: the hemisphere, azimuth-free
          else if (i == 0)
            value = 0.0;  // the early-out boundary 2V + N·L = 1
          else if (h == 0)
            value = clamp(value, 0.0, 1.0);  // also past V = 1 (never sampled): the term's value there, 1
          else  // |a_h| ≤ (2/π)∫|cos hφ| dφ = 4/π for a term in [0, 1]; bounds the continuation past V = 1
            value = clamp(value, -4.0 / kPi<double>, 4.0 / kPi<double>);
          vol.at(i, y, l * n_nv + z, h) = float(value);
        }
    }
  });
  return vol;
}

}  // namespace

io::Volume bake_micro_shadowing_lut(const BakeOptions& o) {
  validate(o);
  if (o.layout == LutLayout::Cone) return bake_cone(o);
  const int n_vis = o.n_vis, n_nl = o.n_nl, n_nv = o.two_d ? 1 : o.n_nv, H = o.harmonics;
  const int nr = int(o.roughness.size());
  io::Volume vol(n_vis, n_nl, n_nv * (H + 1), nr);

  std::vector<double> phi, wphi;
  phi_rule(o.phi_nodes, phi, wphi);
  const int K = o.phi_nodes;
  // A smaller sample count uses a prefix (a power-of-2 prefix of a Sobol sequence is itself a net).
  int max_samples = 1;
  for (double r : o.roughness) max_samples = std::max(max_samples, samples_for_roughness(o, r));
  const std::vector<NodePoints> points = make_points(o, K, max_samples);

  const int tasks = nr * n_nv;
  std::atomic<int> done{0};
  std::mutex progress_mutex;
  auto run = [&](int task) {
    const int r = task / n_nv, z = task % n_nv;
    const double alpha = std::max(roughness_to_alpha(o.roughness[r]), double(GGX<double>::kMinAlpha));
    const double zv = o.two_d ? 1.0 : double(z) / (n_nv - 1);
    const std::size_t n_samples = std::size_t(samples_for_roughness(o, o.roughness[r]));
    const std::vector<NodeSamples> smp = draw_node_samples(points, n_samples, alpha, zv, phi);
    std::vector<int32_t> bins;
    std::vector<uint32_t> hist;
    std::vector<double> acc((H + 1) * n_vis), ratio(n_vis);
    for (int y = 0; y < n_nl; ++y) {
      const double zl = double(y) / (n_nl - 1);
      const float zlf = float(zl), slf = float(safe_sqrt(1.0 - zl * zl));
      std::fill(acc.begin(), acc.end(), 0.0);
      for (int k = 0; k < K; ++k) {
        row_pass(smp[k], zlf, slf, n_vis, bins, hist);
        uint64_t cum = 0;
        for (int i = 0; i < n_vis; ++i) {
          cum += hist[i];
          ratio[i] = double(cum);
        }
        const double den = ratio[n_vis - 1];
        if (!(den > 0.0)) continue;  // no VNDF mass faces l at this φ: the term is 0 for V < 1
        for (int h = 0; h <= H; ++h) {
          const double w = h == 0 ? wphi[k] : 2.0 * wphi[k] * std::cos(h * phi[k]);
          for (int i = 0; i < n_vis; ++i) acc[h * n_vis + i] += w * (ratio[i] / den);
        }
      }
      for (int h = 0; h <= H; ++h)
        for (int i = 0; i < n_vis; ++i) {
          const double V = double(i) / (n_vis - 1);
          double value = acc[h * n_vis + i];
          if (i == n_vis - 1)
            value = h == 0 ? 1.0 : 0.0;  // V = 1: the hemisphere itself
          else if (i == 0 || 2.0 * V + zl < 1.0)
            value = 0.0;  // V = 0 and the exact early-out
          else if (h == 0)
            value = clamp(value, 0.0, 1.0);
          vol.at(i, y, h * n_nv + z, r) = float(value);
        }
    }
    const int d = ++done;
    if (o.progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      o.progress(double(d) / tasks);
    }
  };

  auto all_rows = [&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, tasks, 1), [&](const tbb::blocked_range<int>& range) {
      for (int t = range.begin(); t != range.end(); ++t) run(t);
    });
  };
  if (o.threads > 0) {
    tbb::task_arena arena(o.threads);  // local limit: other work in the process keeps its threads
    arena.execute(all_rows);
  } else {
    all_rows();
  }
  return vol;
}

double monte_carlo_texel(double alpha, double visibility, double n_dot_l, double n_dot_v, int samples,
                         int phi_strata, uint64_t seed) {
  const GGX<float> ggx(float(std::max(alpha, 1e-4)));
  const float c = float(std::sqrt(std::max(0.0, 1.0 - visibility)));
  const float zv = float(n_dot_v), zl = float(n_dot_l);
  const Vec3f v(std::sqrt(std::max(0.0f, 1.0f - zv * zv)), 0.0f, zv);
  const float sl = std::sqrt(std::max(0.0f, 1.0f - zl * zl));
  Pcg32 rng(seed, 0x9e3779b97f4a7c15ULL);
  const int per = std::max(1, samples / std::max(1, phi_strata));
  double sum = 0.0;
  for (int k = 0; k < phi_strata; ++k) {
    const float phi = kPi<float> * (float(k) + rng.next_float()) / float(phi_strata);
    const Vec3f l(sl * std::cos(phi), sl * std::sin(phi), zl);
    double cone = 0.0, hemi = 0.0;
    for (int j = 0; j < per; ++j) {
      const Vec3f m = ggx.Sample_wm(v, {rng.next_float(), rng.next_float()});
      const float ml = dot(m, l);
      // Zurita 2026b, MicroShadowingTermPZGenericVNDFBased: the Smith weight G2/G1 is constant here and
      // cancels.
      hemi += (m.z > 0.0f && ml > 0.0f) ? 1.0 : 0.0;
      cone += (m.z > c && ml > c) ? 1.0 : 0.0;
    }
    sum += hemi > 0.0 ? cone / hemi : 0.0;
  }
  return sum / phi_strata;
}

}  // namespace msh::lut
