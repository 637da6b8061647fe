// As-used accuracy measurement of micro-shadowing approximations. See micro_shadowing_verify.h.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/io/names.h>
#include <microshadow/lut/runtime/micro_shadowing_verify.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace msh::lut {

namespace {
constexpr Named<VerifyReference> kReferences[] = {{VerifyReference::AzimuthMean, "mean"},
                                                  {VerifyReference::Azimuth, "azimuth"}};
}  // namespace

VerifyReference verify_reference_from_name(const std::string& name) {
  return value_of<VerifyReference>(kReferences, name, "--against reference");
}

const char* verify_reference_name(VerifyReference r) { return name_of<VerifyReference>(kReferences, r); }

namespace {
void validate_edges(const std::vector<double>& e, const char* what) {
  if (e.size() < 2) throw InputError(fmt::format("{}: at least two band edges are needed", what));
  // Strictly increasing; one zero-width band [e, e] (a roughness range of one value) is allowed.
  const bool single = e.size() == 2 && e[0] == e[1];
  for (std::size_t i = 0; i < e.size(); ++i)
    if (!std::isfinite(e[i]) || (i > 0 && !single && !(e[i] > e[i - 1])))
      throw InputError(fmt::format("{}: band edges must be finite and strictly increasing", what));
}

template <class F>
void run_parallel(int threads, std::size_t n, const F& body) {
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
                      });
  });
}

// Band i of `edges` holding x: [e_i, e_{i+1}), the last band closed; −1 outside. Compared in float, the
// precision of the inputs (a range [0.4, 0.4] holds the input 0.4f).
int band_of(const std::vector<double>& edges, float x) {
  const int nb = int(edges.size()) - 1;
  for (int i = 0; i < nb; ++i) {
    const float lo = float(edges[i]), hi = float(edges[i + 1]);
    if (x >= lo && (x < hi || (i == nb - 1 && x <= hi))) return i;
  }
  return -1;
}
}  // namespace

void validate(const VerifyOptions& o) {
  if (o.samples < 1 || o.samples > 10000000)
    throw InputError(fmt::format("--samples must be in [1, 10^7], got {}", o.samples));
  if (!(o.roughness_min >= 0.0 && o.roughness_max <= 1.0 && o.roughness_min <= o.roughness_max))
    throw InputError(fmt::format("the roughness range must satisfy 0 ≤ min ≤ max ≤ 1, got [{}, {}]",
                                 o.roughness_min, o.roughness_max));
  if (o.threads < 0) throw InputError(fmt::format("--threads must be ≥ 0, got {}", o.threads));
  if (o.worst < 0) throw InputError(fmt::format("--worst must be ≥ 0, got {}", o.worst));
  validate_edges(o.roughness_bands, "roughness bands");
  validate_edges(o.n_dot_v_bands, "N.V bands");
}

double verify_reference_value(VerifyReference against, double visibility, double n_dot_l, double n_dot_v,
                              double roughness, double cos_phi) {
  const double alpha = roughness_to_alpha(std::clamp(roughness, 0.0, 1.0));
  if (against == VerifyReference::AzimuthMean)
    return micro_shadowing::generic_vndf_exact_azimuth_mean(visibility, alpha, n_dot_l, n_dot_v);
  const double nv = std::clamp(n_dot_v, 0.0, 1.0), nl = std::clamp(n_dot_l, 0.0, 1.0);
  const double c = std::clamp(cos_phi, -1.0, 1.0), s = std::sqrt(std::max(0.0, 1.0 - c * c));
  const double sl = std::sqrt(std::max(0.0, 1.0 - nl * nl));
  return micro_shadowing::generic_vndf_exact(visibility, alpha, alpha,
                                             Vec3d(std::sqrt(std::max(0.0, 1.0 - nv * nv)), 0, nv),
                                             Vec3d(sl * c, sl * s, nl));
}

std::vector<VerifyInput> make_verify_inputs(const VerifyOptions& o) {
  validate(o);
  const uint32_t seed = o.seed;
  std::vector<VerifyInput> in(std::size_t(o.samples));
  run_parallel(o.threads, in.size(), [&](std::size_t i) {
    const uint32_t k = uint32_t(i);
    auto u = [&](int d) { return sobol_scrambled<double>(k, d, seed); };
    VerifyInput& p = in[i];
    p.visibility = float(u(0));
    p.n_dot_l = float(1.0 - u(1));
    p.n_dot_v = float(1.0 - u(2));
    p.roughness = float(o.roughness_min + (o.roughness_max - o.roughness_min) * u(3));
    p.roughness = std::clamp(p.roughness, float(o.roughness_min), float(o.roughness_max));
    p.cos_phi = float(std::cos(kPi<double> * u(4)));
    p.exact = o.reference ? o.reference(p.visibility, p.n_dot_l, p.n_dot_v, p.roughness, p.cos_phi)
                          : verify_reference_value(o.against, p.visibility, p.n_dot_l, p.n_dot_v, p.roughness,
                                                   p.cos_phi);
  });
  return in;
}

ErrorStats error_stats(const std::vector<double>& errors) {
  ErrorStats s;
  s.count = errors.size();
  if (errors.empty()) return s;
  std::vector<double> a(errors.size());
  double sum2 = 0, sum = 0;
  for (std::size_t i = 0; i < errors.size(); ++i) {
    double e = errors[i];
    if (!std::isfinite(e)) ++s.nonfinite, e = 1.0;
    a[i] = std::abs(e);
    sum2 += e * e, sum += e;
    s.max_abs = std::max(s.max_abs, a[i]);
  }
  const double n = double(errors.size());
  s.rms = std::sqrt(sum2 / n);
  s.mean = sum / n;
  // Nearest rank: the smallest |e| with at least 99% of the values ≤ it.
  const std::size_t rank = std::size_t(std::ceil(0.99 * n));
  std::nth_element(a.begin(), a.begin() + (rank - 1), a.end());
  s.p99 = a[rank - 1];
  return s;
}

VerifyResult measure(const std::vector<VerifyInput>& inputs, const MicroShadowingApprox& f,
                     const VerifyOptions& o) {
  validate(o);
  const std::size_t n = inputs.size();
  std::vector<double> approx(n), err(n);
  run_parallel(o.threads, n, [&](std::size_t i) {
    const VerifyInput& p = inputs[i];
    approx[i] = double(f(p.visibility, p.n_dot_l, p.n_dot_v, p.roughness, p.cos_phi));
    err[i] = approx[i] - p.exact;
  });
  VerifyResult r;
  r.all = error_stats(err);
  const int nr = int(o.roughness_bands.size()) - 1, nn = int(o.n_dot_v_bands.size()) - 1;
  std::vector<std::vector<double>> br(nr), bn(nn);
  std::vector<double> eo, rest;
  for (std::size_t i = 0; i < n; ++i) {
    const VerifyInput& p = inputs[i];
    (micro_shadowing::exact_zero(p.visibility, p.n_dot_l) ? eo : rest).push_back(err[i]);
    if (const int b = band_of(o.roughness_bands, p.roughness); b >= 0) br[b].push_back(err[i]);
    if (const int b = band_of(o.n_dot_v_bands, p.n_dot_v); b >= 0) bn[b].push_back(err[i]);
  }
  r.early_out = error_stats(eo);
  r.rest = error_stats(rest);
  for (int b = 0; b < nr; ++b)
    r.by_roughness.push_back({o.roughness_bands[b], o.roughness_bands[b + 1], error_stats(br[b])});
  for (int b = 0; b < nn; ++b)
    r.by_n_dot_v.push_back({o.n_dot_v_bands[b], o.n_dot_v_bands[b + 1], error_stats(bn[b])});

  auto key = [&](std::size_t i) { return std::isfinite(err[i]) ? std::abs(err[i]) : 2.0; };
  std::vector<std::size_t> idx(n);
  std::iota(idx.begin(), idx.end(), std::size_t(0));
  const std::size_t k = std::min(n, std::size_t(o.worst));
  std::partial_sort(idx.begin(), idx.begin() + k, idx.end(), [&](std::size_t a, std::size_t b) {
    return key(a) > key(b) || (key(a) == key(b) && a < b);
  });
  for (std::size_t j = 0; j < k; ++j)
    r.worst.push_back({idx[j], inputs[idx[j]], approx[idx[j]], err[idx[j]]});
  r.approx = std::move(approx);
  return r;
}

VerifyResult verify_micro_shadowing(const MicroShadowingApprox& f, const VerifyOptions& o) {
  return measure(make_verify_inputs(o), f, o);
}

}  // namespace msh::lut
