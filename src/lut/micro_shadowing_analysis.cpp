// Studies of the generic micro-shadowing term (include/microshadow/lut/runtime/micro_shadowing_analysis.h).
#include <microshadow/lut/runtime/micro_shadowing_analysis.h>
#include <microshadow/math/quadrature.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace msh::lut {

Vec3d study_view_dir(double n_dot_v) { return {safe_sqrt(1 - n_dot_v * n_dot_v), 0.0, n_dot_v}; }

Vec3d study_light_dir(double n_dot_l, double phi) {
  const double s = safe_sqrt(1 - n_dot_l * n_dot_l);
  return {s * std::cos(phi), s * std::sin(phi), n_dot_l};
}

double percentile_nearest_rank(const std::vector<double>& s, double p) {
  if (s.empty()) return 0;
  const double rank = std::ceil(p * double(s.size()));
  return s[std::min(s.size() - 1, size_t(std::max(1.0, rank)) - 1)];
}

std::vector<TermMapCell> term_maps(int n, const std::vector<double>& roughness,
                                   const std::vector<double>& n_dot_v) {
  std::vector<TermMapCell> cells;
  for (double r : roughness)
    for (double nv : n_dot_v)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          cells.push_back({r, nv, double(i) / (n - 1), double(j) / (n - 1), 0, 0, 0, 0, 0});
  tbb::parallel_for(size_t(0), cells.size(), [&](size_t k) {
    TermMapCell& c = cells[k];
    c.reference = micro_shadowing::reference_step(c.visibility, c.n_dot_l);
    c.brinck_maximov = micro_shadowing::brinck_maximov_2016(c.visibility, c.n_dot_l);
    c.chan = micro_shadowing::chan_2018(c.visibility, c.n_dot_l);
    c.part1 = micro_shadowing::part1_analytic(c.visibility, c.n_dot_l);
    c.generic = micro_shadowing::generic_vndf_exact_azimuth_mean(
        c.visibility, roughness_to_alpha(c.roughness), c.n_dot_l, c.n_dot_v);
  });
  return cells;
}

std::array<TermError, 4> term_map_errors(const std::vector<TermMapCell>& cells, double roughness,
                                         double n_dot_v) {
  double s2[4] = {}, mx[4] = {}, sm[4] = {};
  int cnt = 0;
  for (const TermMapCell& c : cells) {
    if (c.roughness != roughness || c.n_dot_v != n_dot_v) continue;
    const double vals[4] = {c.reference, c.brinck_maximov, c.chan, c.part1};
    for (int q = 0; q < 4; ++q) {
      const double d = vals[q] - c.generic;
      s2[q] += d * d, sm[q] += d, mx[q] = std::max(mx[q], std::abs(d));
    }
    ++cnt;
  }
  std::array<TermError, 4> out{};
  for (int q = 0; q < 4; ++q) out[q] = {std::sqrt(s2[q] / cnt), mx[q], sm[q] / cnt};
  return out;
}

double AzimuthConfig::truncation_error(int harmonics) const {
  double s = a[0];
  for (int h = 1; h <= harmonics; ++h) s += a[h] * std::cos(h * phi);
  return exact - saturate(s);
}

std::vector<AzimuthConfig> azimuth_study(std::size_t configs) {
  std::vector<AzimuthConfig> az(configs);
  for (size_t k = 0; k < az.size(); ++k) {
    Pcg32 rng(0x5eed + k, 7);
    az[k] = {rng.next_double(),
             0.1 + 0.9 * rng.next_double(),
             rng.next_double(),
             rng.next_double(),
             kPi<double> * rng.next_double(),
             0,
             0,
             {}};
  }
  const GaussLegendre gl(96);
  tbb::parallel_for(size_t(0), az.size(), [&](size_t k) {
    AzimuthConfig& z = az[k];
    const double al = roughness_to_alpha(z.roughness);
    const Vec3d v = study_view_dir(z.n_dot_v);
    z.exact = micro_shadowing::generic_vndf_exact(z.visibility, al, al, v, study_light_dir(z.n_dot_l, z.phi));
    z.mean = micro_shadowing::generic_vndf_exact_azimuth_mean(z.visibility, al, z.n_dot_l, z.n_dot_v);
    z.a.fill(0.0);
    if (micro_shadowing::exact_zero(z.visibility, z.n_dot_l)) return;
    for (size_t i = 0; i < gl.x.size(); ++i) {
      const double p = 0.5 * kPi<double> * (gl.x[i] + 1);
      const double f =
          micro_shadowing::generic_vndf_exact(z.visibility, al, al, v, study_light_dir(z.n_dot_l, p), 1e-6);
      for (int h = 0; h <= kAzimuthStudyHarmonics; ++h)
        z.a[h] += (h == 0 ? 0.5 : 1.0) * gl.w[i] * f * std::cos(h * p);
    }
  });
  return az;
}

AbsErrorSummary azimuth_error_summary(const std::vector<AzimuthConfig>& configs, int harmonics,
                                      bool outside_early_out) {
  std::vector<double> e;
  for (const AzimuthConfig& z : configs)
    if (!outside_early_out || !micro_shadowing::exact_zero(z.visibility, z.n_dot_l))
      e.push_back(std::abs(harmonics == 0 ? z.exact - z.mean : z.truncation_error(harmonics)));
  std::sort(e.begin(), e.end());
  double s2 = 0;
  for (double x : e) s2 += x * x;
  const double above = double(std::count_if(e.begin(), e.end(), [](double x) { return x > 0.5 / 255; }));
  AbsErrorSummary s;
  s.count = e.size();
  s.rms = e.empty() ? 0.0 : std::sqrt(s2 / double(e.size()));
  s.p50 = percentile_nearest_rank(e, 0.5);
  s.p90 = percentile_nearest_rank(e, 0.9);
  s.p99 = percentile_nearest_rank(e, 0.99);
  s.max = e.empty() ? 0.0 : e.back();
  s.frac_above_half_unorm8_step = e.empty() ? 0.0 : above / double(e.size());
  return s;
}

std::vector<MonteCarloCheck> monte_carlo_validation(int64_t samples) {
  const std::vector<std::array<double, 6>> pts = {
      {0.5, 0.16, 0.16, 0.3, 0.8, 1.2}, {0.8, 0.49, 0.49, 0.6, 0.3, 2.5}, {0.9, 0.01, 0.01, 0.35, 0.5, 0.4},
      {0.7, 1.0, 1.0, 0.9, 0.1, 3.0},   {0.6, 0.09, 0.64, 0.5, 0.6, 0.8}, {0.95, 0.25, 0.25, 0.2, 0.95, 1.6}};
  std::vector<MonteCarloCheck> out(pts.size());
  tbb::parallel_for(size_t(0), pts.size(), [&](size_t k) {
    const auto& p = pts[k];
    const GGX<double> g(p[1], p[2]);
    const Vec3d v = study_view_dir(p[4]), l = study_light_dir(p[3], p[5]);
    const double c = std::sqrt(1 - p[0]);
    Pcg32 rng(99 + k, 3);
    double cone = 0, hemi = 0;
    for (int64_t i = 0; i < samples; ++i) {
      const Vec3d m = g.sample_vndf_spherical_caps(v, Vec2d(rng.next_double(), rng.next_double()));
      hemi += (m.z > 0 && dot(m, l) > 0);
      cone += (m.z > c && dot(m, l) > c);
    }
    const double r = hemi > 0 ? cone / hemi : 0;
    out[k] = {p, micro_shadowing::generic_vndf_exact(p[0], p[1], p[2], v, l), r,
              std::sqrt(r * (1 - r) / std::max(hemi, 1.0))};
  });
  return out;
}

}  // namespace msh::lut
