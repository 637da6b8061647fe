// LTC table fitter (see include/microshadow/bsdf/runtime/ltc_baker.h and docs/ltc.md).
#include <fmt/format.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/multiscatter.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>

namespace msh::bsdf {
namespace {

constexpr double kMaxTheta = 1.57;  // θ_v of the last row (cos θ_v = 0 is the fit's degenerate limit)
constexpr double kMinScale = 1e-7;  // lower bound of m11, m22 (keeps M invertible)
constexpr uint32_t kMomentSeed = 0x5eed1u;

struct CellProblem {
  GGX<double> ggx;
  Vec3d v;
  double magnitude = 1;
  Vec3d frame_x{1, 0, 0}, frame_z{0, 0, 1};
  bool isotropic = true;
  int k = 32;

  // M = [X Y Z] · [[m11, 0, m13], [0, m22, 0], [0, 0, 1]].
  Mat3<double> matrix(const std::array<double, 3>& p) const {
    const double m11 = std::max(p[0], kMinScale), m22 = isotropic ? m11 : std::max(p[1], kMinScale);
    const double m13 = isotropic ? 0.0 : p[2];
    const Mat3<double> r = Mat3<double>::from_columns(frame_x, Vec3d(0, 1, 0), frame_z);
    Mat3<double> s;
    s.m = {m11, 0, m13, 0, m22, 0, 0, 0, 1};
    return r * s;
  }

  double brdf_cos(const Vec3d& l) const { return microfacet_specular(ggx, v, l).f1 * std::max(l.z, 0.0); }

  // ∫ |f (n·l) − magnitude · D|³ dl by balance-heuristic MIS of K² LTC and K² BRDF samples (stratified grid).
  double error(const std::array<double, 3>& p, double* norm3 = nullptr) const {
    const Mat3<double> m = matrix(p), minv = m.inverse();
    double e = 0, f3 = 0;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const Vec2d u((i + 0.5) / k, (j + 0.5) / k);
        {
          const Vec3d l = ltc_sample(m, u);
          const double d = ltc_eval(minv, l);
          const double f = brdf_cos(l), pb = microfacet_specular_pdf(ggx, v, l);
          const double den = d + pb;
          if (den > 0) e += std::pow(std::abs(f - magnitude * d), 3.0) / den, f3 += f * f * f / den;
        }
        if (auto s = sample_microfacet_specular(ggx, v, u)) {
          const double d = ltc_eval(minv, s->wi);
          const double f = brdf_cos(s->wi);
          const double den = d + s->pdf;
          if (den > 0) e += std::pow(std::abs(f - magnitude * d), 3.0) / den, f3 += f * f * f / den;
        }
      }
    if (norm3) *norm3 = f3 / double(k * k);
    return e / double(k * k);
  }
};

// Nelder–Mead simplex minimisation (Nelder & Mead 1965; reflection 1, expansion 2, contraction ½, shrink ½)
// over the first `dim` coordinates, initial simplex x0 + δ e_i. Stops after max_it iterations or when the
// simplex's values agree to a relative 1e-7.
template <class F>
std::array<double, 3> nelder_mead(const F& f, std::array<double, 3> x0, int dim, double delta, int max_it,
                                  double* fbest) {
  using P = std::array<double, 3>;
  std::vector<P> x(size_t(dim + 1), x0);
  std::vector<double> fx(size_t(dim + 1));
  for (int i = 0; i < dim; ++i) x[size_t(i + 1)][size_t(i)] += delta;
  for (int i = 0; i <= dim; ++i) fx[size_t(i)] = f(x[size_t(i)]);
  for (int it = 0; it < max_it; ++it) {
    // Order: best first (stable on ties: index order, so the result is deterministic).
    std::vector<int> idx(size_t(dim + 1));
    for (int i = 0; i <= dim; ++i) idx[size_t(i)] = i;
    std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return fx[size_t(a)] < fx[size_t(b)]; });
    std::vector<P> xs(x.size());
    std::vector<double> fs(x.size());
    for (size_t i = 0; i < idx.size(); ++i) xs[i] = x[size_t(idx[i])], fs[i] = fx[size_t(idx[i])];
    x = xs, fx = fs;
    const double fb = fx[0], fw = fx[size_t(dim)];
    if (std::abs(fw - fb) <= 1e-7 * std::abs(fb) + 1e-300) break;
    P c{0, 0, 0};
    for (int i = 0; i < dim; ++i)
      for (int d = 0; d < dim; ++d) c[size_t(d)] += x[size_t(i)][size_t(d)] / dim;
    auto along = [&](double t) {
      P p = x0;
      for (int d = 0; d < dim; ++d)
        p[size_t(d)] = c[size_t(d)] + t * (x[size_t(dim)][size_t(d)] - c[size_t(d)]);
      return p;
    };
    const P xr = along(-1.0);
    const double fr = f(xr);
    if (fr < fx[0]) {
      const P xe = along(-2.0);
      const double fe = f(xe);
      if (fe < fr)
        x[size_t(dim)] = xe, fx[size_t(dim)] = fe;
      else
        x[size_t(dim)] = xr, fx[size_t(dim)] = fr;
    } else if (fr < fx[size_t(dim - 1)]) {
      x[size_t(dim)] = xr, fx[size_t(dim)] = fr;
    } else {
      const bool outside = fr < fw;
      const P xc = along(outside ? -0.5 : 0.5);
      const double fc = f(xc);
      if (fc < (outside ? fr : fw)) {
        x[size_t(dim)] = xc, fx[size_t(dim)] = fc;
      } else {
        for (int i = 1; i <= dim; ++i) {
          for (int d = 0; d < dim; ++d)
            x[size_t(i)][size_t(d)] = x[0][size_t(d)] + 0.5 * (x[size_t(i)][size_t(d)] - x[0][size_t(d)]);
          fx[size_t(i)] = f(x[size_t(i)]);
        }
      }
    }
  }
  size_t b = 0;
  for (size_t i = 1; i < fx.size(); ++i)
    if (fx[i] < fx[b]) b = i;
  *fbest = fx[b];
  return x[b];
}

double theta_for_row(int j, int n) {
  const double y = double(j) / double(n - 1);
  return std::min(kMaxTheta, std::acos(std::clamp(1.0 - y * y, -1.0, 1.0)));
}

}  // namespace

void validate(const LtcFitOptions& o) {
  if (o.size < 2 || o.size > 1024)
    throw InputError(fmt::format("--size must be in [2, 1024], got {}", o.size));
  if (o.error_samples < 4 || o.error_samples > 1024)
    throw InputError(fmt::format("--error-samples must be in [4, 1024], got {}", o.error_samples));
  if (o.max_iterations < 1)
    throw InputError(fmt::format("--iterations must be ≥ 1, got {}", o.max_iterations));
  if (o.moment_samples < 16)
    throw InputError(fmt::format("--moment-samples must be ≥ 16, got {}", o.moment_samples));
  if (o.threads < 0) throw InputError(fmt::format("--threads must be ≥ 0, got {}", o.threads));
}

LtcCellFit fit_ltc_cell(double roughness, double theta_v, const LtcCellFit& start, bool isotropic,
                        const LtcFitOptions& o) {
  CellProblem pb{GGX<double>(roughness_to_alpha(std::clamp(roughness, 0.0, 1.0))),
                 Vec3d(std::sin(theta_v), 0, std::cos(theta_v))};
  pb.isotropic = isotropic;
  pb.k = o.error_samples;
  const double mu = pb.v.z;
  // Moments (E_Fc, E) from the library's reference (same α clamp as the BRDF: r² ≥ GGX::kMinAlpha).
  const Vec2d dfg = ggx_dfg_reference(mu, std::max(roughness, std::sqrt(GGX<double>::kMinAlpha)),
                                      uint32_t(o.moment_samples));
  pb.magnitude = dfg.y;
  LtcCellFit r;
  r.coeffs.magnitude = dfg.y, r.coeffs.fresnel = dfg.x;
  if (!isotropic) {
    // Mean direction ∫ f (n·l) l dl by VNDF sampling (the y part vanishes by symmetry and is dropped).
    Vec3d avg{};
    for (int i = 0; i < o.moment_samples; ++i)
      if (auto s = sample_microfacet_specular(pb.ggx, pb.v, sobol_2d<double>(uint32_t(i), kMomentSeed)))
        avg += s->wi * s->weight_f1;
    avg.y = 0;
    pb.frame_z = normalize(avg, Vec3d(0, 0, 1));
    pb.frame_x = Vec3d(pb.frame_z.z, 0, -pb.frame_z.x);
  }
  double err = 0;  // the minimum (unused: recomputed with its norm below)
  const std::array<double, 3> best =
      nelder_mead([&](const std::array<double, 3>& p) { return pb.error(p); },
                  {start.m11, isotropic ? start.m11 : start.m22, isotropic ? 0.0 : start.m13},
                  isotropic ? 1 : 3, 0.05, o.max_iterations, &err);
  r.m11 = std::max(best[0], kMinScale);
  r.m22 = isotropic ? r.m11 : std::max(best[1], kMinScale);
  r.m13 = isotropic ? 0.0 : best[2];
  // Relative L3 error ‖f cos − magnitude·D‖₃ / ‖f cos‖₃ (same samples).
  double f3 = 0;
  const double e3 = pb.error({r.m11, r.m22, r.m13}, &f3);
  r.error = f3 > 0 ? std::cbrt(e3 / f3) : 0.0;
  const Mat3<double> minv = pb.matrix({r.m11, r.m22, r.m13}).inverse();
  const double s = minv(1, 1);
  r.coeffs.a = minv(0, 0) / s, r.coeffs.b = minv(0, 2) / s, r.coeffs.c = minv(2, 0) / s,
  r.coeffs.d = minv(2, 2) / s;
  return r;
}

LtcTable fit_ltc_table(const LtcFitOptions& o) {
  validate(o);
  const int n = o.size;
  LtcTable t;
  t.size = n;
  t.options = o;
  t.options.progress = nullptr;
  t.mat.assign(size_t(n) * n * 4, 0.f);
  t.amp.assign(size_t(n) * n * 2, 0.f);
  t.fit_error.assign(size_t(n) * n, 0.f);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<LtcCellFit> cells(size_t(n) * n);
  std::mutex mu;
  std::atomic<int> done{0};
  auto report = [&] {
    const int d = ++done;
    if (o.progress) {
      std::lock_guard<std::mutex> lock(mu);
      o.progress(double(d) / double(n * n));
    }
  };
  auto cell = [&](int i, int j) -> LtcCellFit& { return cells[size_t(j) * n + size_t(i)]; };
  // θ_v = 0 column, from r = 1 (identity start) down to r = 0, each from the rougher neighbour.
  for (int i = n - 1; i >= 0; --i) {
    const LtcCellFit start = i == n - 1 ? LtcCellFit{} : cell(i + 1, 0);
    cell(i, 0) = fit_ltc_cell(double(i) / (n - 1), 0.0, start, true, o);
    report();
  }
  // Then every roughness row along θ_v, rows in parallel (each row's chain only reads its own cells).
  std::unique_ptr<tbb::global_control> gc;
  if (o.threads > 0)
    gc = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               size_t(o.threads));
  tbb::parallel_for(0, n, [&](int i) {
    for (int j = 1; j < n; ++j) {
      cell(i, j) = fit_ltc_cell(double(i) / (n - 1), theta_for_row(j, n), cell(i, j - 1), false, o);
      report();
    }
  });
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const LtcCellFit& c = cell(i, j);
      const size_t k = size_t(j) * n + size_t(i);
      t.mat[k * 4 + 0] = float(c.coeffs.a), t.mat[k * 4 + 1] = float(c.coeffs.b);
      t.mat[k * 4 + 2] = float(c.coeffs.c), t.mat[k * 4 + 3] = float(c.coeffs.d);
      t.amp[k * 2 + 0] = float(c.coeffs.magnitude), t.amp[k * 2 + 1] = float(c.coeffs.fresnel);
      t.fit_error[k] = float(c.error);
    }
  t.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return t;
}

LtcCoeffs<double> LtcTable::fetch(double roughness, double cos_theta_v) const {
  return ltc_fetch<double>(mat.data(), amp.data(), size, roughness, cos_theta_v);
}

io::Volume ltc_matrix_volume(const LtcTable& t) {
  io::Volume v(t.size, t.size, 1, 4);
  v.data = t.mat;
  return v;
}
io::Volume ltc_moments_volume(const LtcTable& t) {
  io::Volume v(t.size, t.size, 1, 2);
  v.data = t.amp;
  return v;
}

std::filesystem::path ltc_moments_path(const std::filesystem::path& table) {
  std::filesystem::path p =
      table.parent_path() / (table.stem().string() + "_amp" + table.extension().string());
  return p;
}
std::filesystem::path ltc_sidecar_path(const std::filesystem::path& table) {
  std::filesystem::path p = table;
  p += ".json";
  return p;
}

std::string ltc_sidecar_json(const LtcTable& t, const std::filesystem::path& table,
                             const std::string& pixel_format) {
  nlohmann::json j;
  j["format"] = "microshadow LTC table";
  j["brdf"] = "GGX, height-correlated Smith G2 (bsdf/specular.h microfacet_specular), alpha = roughness^2";
  j["size"] = t.size;
  j["axes"] = {{"x", "perceptual roughness r = i/(n-1)"},
               {"y", "sqrt(1 - cos(theta_v)) = j/(n-1), theta_v <= 1.57"}};
  j["matrix_file"] = table.filename().string();
  j["matrix_channels"] = "a, b, c, d of M^-1 = [[a,0,b],[0,1,0],[c,0,d]] (view in the xz-plane, v.x >= 0)";
  j["moments_file"] = ltc_moments_path(table).filename().string();
  j["moments_channels"] = "magnitude = int f cos (F=1), fresnel = int f cos (1 - v.h)^5";
  j["pixel_format"] = pixel_format;
  j["fit"] = {{"error", "L3, MIS of LTC and BRDF samples"},
              {"error_samples", t.options.error_samples},
              {"max_iterations", t.options.max_iterations},
              {"moment_samples", t.options.moment_samples},
              {"fit_seconds_wall", t.fit_seconds}};
  return j.dump(2) + "\n";
}

void write_ltc_table(const std::filesystem::path& path, const LtcTable& t, io::FileFormat ff,
                     io::PixelFormat pf4, io::PixelFormat pf2) {
  io::write_volume(path, ltc_matrix_volume(t), ff, pf4, "ltc_mat");
  io::write_volume(ltc_moments_path(path), ltc_moments_volume(t), ff, pf2, "ltc_amp");
  io::write_file_atomic(ltc_sidecar_path(path), ltc_sidecar_json(t, path, io::pixel_format_name(pf4)));
}

LtcTable load_ltc_table(const std::filesystem::path& path) {
  const io::Volume m = io::read_volume(path);
  const std::filesystem::path ap = ltc_moments_path(path);
  if (!std::filesystem::exists(ap))
    throw InputError(fmt::format("LTC table '{}': moments file '{}' not found", path.string(), ap.string()));
  const io::Volume a = io::read_volume(ap);
  if (m.channels != 4 || m.depth != 1 || m.width != m.height || m.width < 2)
    throw InputError(
        fmt::format("LTC table '{}' must be a square 2D RGBA texture, got {}x{}x{} with {} channels",
                    path.string(), m.width, m.height, m.depth, m.channels));
  if (a.channels != 2 || a.depth != 1 || a.width != m.width || a.height != m.height)
    throw InputError(
        fmt::format("LTC moments '{}' must be a {}x{} RG texture", ap.string(), m.width, m.height));
  LtcTable t;
  t.size = m.width;
  t.mat = m.data;
  t.amp = a.data;
  for (float x : t.mat)
    if (!std::isfinite(x))
      throw InputError(fmt::format("LTC table '{}' holds non-finite values", path.string()));
  return t;
}

}  // namespace msh::bsdf
