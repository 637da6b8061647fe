// Directional micro-occlusion bake and its texture-space measurement (render/directional_bake.h).
#include <fmt/format.h>
#include <microshadow/io/bc4.h>
#include <microshadow/io/error.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/texture_gen.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>

namespace msh::render {

namespace dir = msh::directional;

namespace {

constexpr double kDeg = kPi<double> / 180.0;

std::vector<Vec2f> uniform_azimuths(int n) {
  std::vector<Vec2f> d(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double phi = 2 * kPi<double> * (k + 0.5) / n;
    d[std::size_t(k)] = Vec2f(float(std::cos(phi)), float(std::sin(phi)));
  }
  return d;
}

std::vector<Vec3f> fine_normals(const Texture& height, float depth) {
  const HeightField hf(height, depth);
  const int w = height.width(), h = height.height();
  std::vector<Vec3f> n(std::size_t(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) n[std::size_t(j) * w + i] = hf.vertex_normal(i, j);
  return n;
}

// Slope dz/ds of the tangent plane of normal n along the horizontal unit direction d.
float facet_slope(const Vec3f& n, const Vec2f& d) { return -(n.x * d.x + n.y * d.y) / n.z; }

// The 10 horizon-moment channels of one texel from its horizons along `dirs` (uniform azimuths).
void horizon_channels(const float* tan_h, const Vec3f& n, const std::vector<Vec2f>& dirs, float* out) {
  double acc[dir::kHorizonChannels] = {};
  const int na = int(dirs.size());
  for (int a = 0; a < na; ++a) {
    double w[dir::kHorizonTerms];
    dir::fourier_analysis_weights<double>(dirs[a].x, dirs[a].y, na, w);
    const double s = dir::signed_horizon_sine<double>(tan_h[a], facet_slope(n, dirs[a]));
    for (int m = 0; m < dir::kHorizonTerms; ++m)
      acc[m] += w[m] * s, acc[dir::kHorizonTerms + m] += w[m] * s * s;
  }
  for (int c = 0; c < dir::kHorizonChannels; ++c) out[c] = float(acc[c]);
}

Vec3f light_dir(double elev_deg, Vec2f az) {
  const double ce = std::cos(elev_deg * kDeg), se = std::sin(elev_deg * kDeg);
  return Vec3f(float(ce * az.x), float(ce * az.y), float(se));
}

Vec2f azimuth_dir(double az_deg) {
  // Exact axes for the measured azimuths 0° and 90° (the walks then follow grid lines exactly).
  if (az_deg == 0) return Vec2f(1, 0);
  if (az_deg == 90) return Vec2f(0, 1);
  return Vec2f(float(std::cos(az_deg * kDeg)), float(std::sin(az_deg * kDeg)));
}

// Per-texel lit · (n · l)⁺ from the horizon tangents along l's azimuth.
float transport_texel(float tan_h, const Vec3f& n, const Vec3f& l) {
  const double horiz = std::sqrt(double(l.x) * l.x + double(l.y) * l.y);
  const double tan_e = horiz > 0 ? double(l.z) / horiz : std::numeric_limits<double>::infinity();
  return tan_e > double(tan_h) ? std::max(dot(n, l), 0.0f) : 0.0f;
}

// Small dense inverse (Gauss–Jordan with partial pivoting), row-major n × n.
std::vector<double> invert(std::vector<double> a, int n) {
  std::vector<double> inv(std::size_t(n) * n, 0.0);
  for (int i = 0; i < n; ++i) inv[std::size_t(i) * n + i] = 1;
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(a[std::size_t(r) * n + c]) > std::abs(a[std::size_t(p) * n + c])) p = r;
    for (int k = 0; k < n; ++k) {
      std::swap(a[std::size_t(c) * n + k], a[std::size_t(p) * n + k]);
      std::swap(inv[std::size_t(c) * n + k], inv[std::size_t(p) * n + k]);
    }
    const double d = a[std::size_t(c) * n + c];
    for (int k = 0; k < n; ++k) a[std::size_t(c) * n + k] /= d, inv[std::size_t(c) * n + k] /= d;
    for (int r = 0; r < n; ++r) {
      if (r == c) continue;
      const double f = a[std::size_t(r) * n + c];
      for (int k = 0; k < n; ++k)
        a[std::size_t(r) * n + k] -= f * a[std::size_t(c) * n + k],
            inv[std::size_t(r) * n + k] -= f * inv[std::size_t(c) * n + k];
    }
  }
  return inv;
}

// Weighted least-squares projection of a hemisphere function sampled on a direction grid onto the first
// nb poly2 functions: coefficients = P · f. The grid: the bake azimuths × ne elevations (uniform in e), the
// weight cos e (solid angle) / (0.1 + sin e)² (roughly relative error, so grazing lights count), times the
// azimuth's share of the circle relative to a uniform one (az_weight; empty = uniform azimuths).
struct LsqProjection {
  int nb = 0, ne = 0, na = 0;
  std::vector<Vec3f> dirs;  // [a · ne + j]
  std::vector<float> P;     // nb × dirs
  int damp = 0;  // > 0: basis × (1 − z)^damp, fitted to the residual f − n · l (see "resid-poly2")
  LsqProjection(int nb_, const std::vector<Vec2f>& az, int ne_, double eps = 0.1, int damp_ = 0,
                const std::vector<double>& az_weight = {})
      : nb(nb_), ne(ne_), na(int(az.size())), damp(damp_) {
    std::vector<double> w;
    std::vector<double> B;  // dirs × nb
    for (int a = 0; a < na; ++a)
      for (int j = 0; j < ne; ++j) {
        const double e = (j + 0.5) / ne * kPi<double> / 2;
        const Vec3f d(float(std::cos(e) * az[a].x), float(std::cos(e) * az[a].y), float(std::sin(e)));
        dirs.push_back(d);
        w.push_back(std::cos(e) / ((eps + std::sin(e)) * (eps + std::sin(e))) *
                    (az_weight.empty() ? 1.0 : az_weight[std::size_t(a)]));
        double b[dir::kPoly12Terms];
        dir::poly12_basis<double>(Vec3d(d), b);
        for (double& v : b) v *= std::pow(1.0 - std::sin(e), damp);
        B.insert(B.end(), b, b + nb);
      }
    const int nd = int(dirs.size());
    std::vector<double> G(std::size_t(nb) * nb, 0.0);
    for (int d = 0; d < nd; ++d)
      for (int r = 0; r < nb; ++r)
        for (int c = 0; c < nb; ++c)
          G[std::size_t(r) * nb + c] += w[d] * B[std::size_t(d) * nb + r] * B[std::size_t(d) * nb + c];
    const auto Gi = invert(G, nb);
    P.assign(std::size_t(nb) * nd, 0.0f);
    for (int r = 0; r < nb; ++r)
      for (int d = 0; d < nd; ++d) {
        double s = 0;
        for (int c = 0; c < nb; ++c) s += Gi[std::size_t(r) * nb + c] * B[std::size_t(d) * nb + c];
        P[std::size_t(r) * nd + d] = float(s * w[d]);
      }
  }
};

float quantize8(float v, float lo, float hi) {
  const float t = std::clamp((v - lo) / (hi - lo), 0.0f, 1.0f);
  return lo + (hi - lo) * std::round(t * 255.0f) / 255.0f;
}

}  // namespace

Texture box_downsample(const Texture& t, int k) {
  if (k < 1 || t.empty() || t.width() % k != 0 || t.height() % k != 0)
    throw InputError(
        fmt::format("box_downsample: k = {} must divide the size {}x{}", k, t.width(), t.height()));
  const int W = t.width() / k, H = t.height() / k, C = t.channels();
  const double inv = 1.0 / (double(k) * double(k));
  Texture out(W, H, C);
  tbb::parallel_for(0, H, [&](int J) {
    std::vector<double> acc(static_cast<std::size_t>(C));
    for (int I = 0; I < W; ++I) {
      std::fill(acc.begin(), acc.end(), 0.0);
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i)
          for (int c = 0; c < C; ++c) acc[std::size_t(c)] += t.at(I * k + i, J * k + j, c);
      for (int c = 0; c < C; ++c) out.at(I, J, c) = float(acc[std::size_t(c)] * inv);
    }
  });
  return out;
}

ChannelRanges channel_ranges(const Texture& t) {
  ChannelRanges r{std::vector<float>(std::size_t(t.channels()), 1e30f),
                  std::vector<float>(std::size_t(t.channels()), -1e30f)};
  for (int j = 0; j < t.height(); ++j)
    for (int i = 0; i < t.width(); ++i)
      for (int c = 0; c < t.channels(); ++c)
        r.lo[std::size_t(c)] = std::min(r.lo[std::size_t(c)], t.at(i, j, c)),
        r.hi[std::size_t(c)] = std::max(r.hi[std::size_t(c)], t.at(i, j, c));
  for (int c = 0; c < t.channels(); ++c)
    if (!(r.hi[std::size_t(c)] > r.lo[std::size_t(c)])) r.hi[std::size_t(c)] = r.lo[std::size_t(c)] + 1;
  return r;
}

DirectionalEncoding directional_encoding_from_name(const std::string& name) {
  if (name == "float") return DirectionalEncoding::Float;
  if (name == "unorm8") return DirectionalEncoding::Unorm8;
  if (name == "bc4") return DirectionalEncoding::Bc4;
  throw InputError(fmt::format("directional encoding must be float, unorm8 or bc4, got '{}'", name));
}

std::string directional_encoding_name(DirectionalEncoding e) {
  return e == DirectionalEncoding::Float ? "float" : e == DirectionalEncoding::Unorm8 ? "unorm8" : "bc4";
}

void store_directional_channels(Texture& t, const ChannelRanges& r, DirectionalEncoding e) {
  if (e == DirectionalEncoding::Float || t.empty()) return;
  if (r.lo.size() != std::size_t(t.channels()) || r.hi.size() != std::size_t(t.channels()))
    throw InputError(
        fmt::format("store_directional_channels: {} ranges for {} channels", r.lo.size(), t.channels()));
  const int w = t.width(), h = t.height(), nc = t.channels();
  std::vector<float> u(std::size_t(w) * std::size_t(h));
  for (int c = 0; c < nc; ++c) {
    const float lo = r.lo[std::size_t(c)], hi = r.hi[std::size_t(c)];
    if (e == DirectionalEncoding::Unorm8) {
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) t.at(i, j, c) = quantize8(t.at(i, j, c), lo, hi);
      continue;
    }
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        u[std::size_t(j) * std::size_t(w) + std::size_t(i)] = (t.at(i, j, c) - lo) / (hi - lo);
    io::bc4_decode(io::bc4_encode(u.data(), w, h, 1), w, h, u.data(), 1);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        t.at(i, j, c) = dir::decode_unorm8(u[std::size_t(j) * std::size_t(w) + std::size_t(i)], lo, hi);
  }
}

std::vector<Texture> box_mip_chain(const Texture& t) {
  std::vector<Texture> chain{t};
  while (chain.back().width() % 2 == 0 && chain.back().height() % 2 == 0 && chain.back().width() > 1 &&
         chain.back().height() > 1)
    chain.push_back(box_downsample(chain.back(), 2));
  return chain;
}

void check_directional_azimuths(const char* what, int azimuths) {
  if (azimuths < kMinDirectionalAzimuths || azimuths > kMaxDirectionalAzimuths)
    throw InputError(fmt::format(
        "{}: azimuths must be in [{}, {}] (the fits' azimuthal harmonics up to order "
        "2 need at least {}), got {}",
        what, kMinDirectionalAzimuths, kMaxDirectionalAzimuths, kMinDirectionalAzimuths, azimuths));
}

DirectionalBakeAzimuths directional_bake_azimuths(int azimuths) {
  check_directional_azimuths("directional_bake_azimuths", azimuths);
  DirectionalBakeAzimuths r;
  const int na = azimuths;
  if (na > kMaxLatticeAzimuths) {
    r.dirs = uniform_azimuths(na);
    r.weights.assign(std::size_t(na), 1.0);
    return r;
  }
  r.steps = lattice_azimuths(na, kLatticeAzimuthErrorDeg);
  std::vector<double> phi;
  for (const LatticeStep& st : r.steps) {
    r.dirs.push_back(lattice_direction(st));
    phi.push_back(lattice_azimuth(st));
  }
  // Each azimuth's share of the circle: half the arcs to its neighbours (the targets are ascending and the
  // error is below half their spacing, so the steps keep their order), relative to 2π/na.
  for (int a = 0; a < na; ++a) {
    const double next = phi[std::size_t((a + 1) % na)], prev = phi[std::size_t((a + na - 1) % na)];
    auto arc = [](double x) { return x - 2 * kPi<double> * std::floor(x / (2 * kPi<double>)); };
    r.weights.push_back(0.5 * (arc(next - phi[std::size_t(a)]) + arc(phi[std::size_t(a)] - prev)) * na /
                        (2 * kPi<double>));
  }
  return r;
}

namespace {
// What fit_directional's sums read: lit[a · wh + p] (the first lit elevation), the fine normals, the fit's
// directions [a · ne + e], and the suffix sums S (below) of the projection rows.
struct FitRows {
  const uint8_t* lit;
  std::size_t wh;
  int w, na, ne;
  const Vec3f* n;
  const Vec3f* dirs;
  const double* S;
};

// The fit is Σ_d P[r][d] f(d) over the lit directions with f = (n · l_d)⁺. Within an azimuth, n · l(e) =
// cos e (n_h · u_a) + sin e n_z rises with e (its derivative −sin e (n_h · u_a) + cos e n_z is > 0 where it
// is ≤ 0, n_z > 0), so the directions that count are a suffix e ≥ s of the azimuth's elevations, and on it f
// = n · l_d is linear in n: Σ_{e ≥ s} P[r][d] f(d) = n_x SX + n_y SY + n_z SZ with the suffix sums S[a][s] =
// (SX, SY, SZ)[rows] = Σ_{e ≥ s} P[r][a·ne + e] · (l_x, l_y, l_z). One texel then costs one table row per
// azimuth instead of a product per lit direction. The slope functions f · n_x/n_z and f · n_y/n_z are that
// sum of their own rows times the texel's constant slope.
std::vector<double> fit_suffix_sums(const std::vector<Vec3f>& dirs, int na, int ne,
                                    const std::vector<const float*>& P) {
  const int rows = int(P.size());
  std::vector<double> S(std::size_t(na) * std::size_t(ne + 1) * 3 * std::size_t(rows), 0.0);
  for (int a = 0; a < na; ++a)
    for (int e = ne - 1; e >= 0; --e) {
      const int d = a * ne + e;
      const double l[3] = {dirs[std::size_t(d)].x, dirs[std::size_t(d)].y, dirs[std::size_t(d)].z};
      double* here = &S[(std::size_t(a) * std::size_t(ne + 1) + std::size_t(e)) * 3 * std::size_t(rows)];
      const double* next = here + 3 * std::size_t(rows);
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < rows; ++r)
          here[c * rows + r] = next[c * rows + r] + double(P[std::size_t(r)][d]) * l[c];
    }
  return S;
}

// One texel's sums: the 9 of T (transport), then the 12 slope sums (slopes); kRows = the rows of S (9, 6 or
// 15).
template <int kRows>
[[gnu::always_inline]] inline void fit_texel(const FitRows& R, std::size_t p, bool transport, bool slopes,
                                             double* out) {
  double acc[3 * kRows] = {};
  const Vec3f np = R.n[p];
  for (int a = 0; a < R.na; ++a) {
    int s = R.lit[std::size_t(a) * R.wh + p];
    // Past the elevations the texel's own plane hides (n · l ≤ 0: they add nothing).
    while (s < R.ne && !(dot(np, R.dirs[std::size_t(a * R.ne + s)]) > 0.0f)) ++s;
    const double* row = &R.S[(std::size_t(a) * std::size_t(R.ne + 1) + std::size_t(s)) * 3 * kRows];
    for (int i = 0; i < 3 * kRows; ++i) acc[i] += row[i];
  }
  double v[kRows];
  for (int r = 0; r < kRows; ++r)
    v[r] = double(np.x) * acc[r] + double(np.y) * acc[kRows + r] + double(np.z) * acc[2 * kRows + r];
  constexpr int nb = dir::kPoly2Terms, ns = dir::kSlopeTerms;
  const int t0 = transport ? nb : 0;
  for (int r = 0; r < t0; ++r) out[r] = v[r];
  if (slopes) {
    const double sx = double(np.x) / np.z, sy = double(np.y) / np.z;
    for (int r = 0; r < ns; ++r) out[t0 + r] = v[t0 + r] * sx, out[t0 + ns + r] = v[t0 + r] * sy;
  }
}

// Row j's sums, texel by texel (channels side by side). Cloned for AVX2 (wider vectors for the table rows).
[[gnu::target_clones("avx2", "default")]] void fit_row(const FitRows& R, int j, bool transport, bool slopes,
                                                       double* out) {
  constexpr int nb = dir::kPoly2Terms, ns = dir::kSlopeTerms;
  const int nc = (transport ? nb : 0) + (slopes ? 2 * ns : 0);
  for (int i = 0; i < R.w; ++i) {
    const std::size_t p = std::size_t(j) * std::size_t(R.w) + std::size_t(i);
    double* o = out + std::size_t(i) * std::size_t(nc);
    if (transport && slopes)
      fit_texel<nb + ns>(R, p, true, true, o);
    else if (transport)
      fit_texel<nb>(R, p, true, false, o);
    else
      fit_texel<ns>(R, p, false, true, o);
  }
}

// Which functions of the fit: f = lit · (n · l)⁺ (9 channels), f · n_x/n_z then f · n_y/n_z (6 each, 12),
// or both (21, in that order).
enum class FitOutput { Transport, Slopes, Both };
// The fits of bake_directional_channels, bake_directional_slope_channels and bake_directional_view_channels:
// one set of horizons, one pass.
Texture fit_directional(const Texture& height, float depth, int azimuths, float max_distance,
                        FitOutput what) {
  const DirectionalBakeAzimuths az = directional_bake_azimuths(azimuths);
  const auto& dirs = az.dirs;
  const LsqProjection proj(dir::kPoly2Terms, dirs, dir::kFitElevations, dir::kFitEpsilon, 0, az.weights);
  const int w = height.width(), h = height.height(), na = azimuths, ne = proj.ne, nd = int(proj.dirs.size());
  // tan e of every fit direction as transport_texel computes it; ascending in e within an azimuth, so the
  // lit directions of an azimuth are those from the first one above the horizon up (and the walks only
  // have to classify the horizon against them).
  std::vector<std::vector<double>> tan_e(std::size_t(na), std::vector<double>(std::size_t(ne), 0.0));
  for (int a = 0; a < na; ++a)
    for (int e = 0; e < ne; ++e) {
      const Vec3f& l = proj.dirs[std::size_t(a * ne + e)];
      tan_e[std::size_t(a)][std::size_t(e)] = double(l.z) / std::sqrt(double(l.x) * l.x + double(l.y) * l.y);
    }
  // Per azimuth a and texel p, the first lit elevation: lit[a · w·h + p] = the first e with tan e > tan H.
  // Unlimited rays on lattice azimuths: one exact sweep per line, classified as it goes; otherwise the
  // classified walks.
  const std::size_t wh = std::size_t(w) * std::size_t(h);
  std::vector<uint8_t> lit;
  if (!az.steps.empty() && !(max_distance > 0)) {
    lit = bake_horizon_classes_lattice(height, depth, az.steps, tan_e);
  } else {
    const auto tan_h = bake_horizon_tangents(height, depth, dirs, max_distance, tan_e);
    lit.resize(wh * std::size_t(na));
    tbb::parallel_for(0, h, [&](int j) {
      for (std::size_t p = std::size_t(j) * w; p < std::size_t(j + 1) * w; ++p)
        for (int a = 0; a < na; ++a) {
          const double T = tan_h[p * std::size_t(na) + std::size_t(a)];
          const auto& te = tan_e[std::size_t(a)];
          int e = 0;
          while (e < ne && !(te[std::size_t(e)] > T)) ++e;
          lit[std::size_t(a) * wh + p] = uint8_t(e);
        }
    });
  }
  const auto n = fine_normals(height, depth);
  // The suffix sums of the projection rows: the 9 functions of T, then the kSlopeTerms of the slope fits
  // (their own least squares, not a subset of T's rows).
  constexpr int nb = dir::kPoly2Terms, ns = dir::kSlopeTerms;
  const bool transport = what != FitOutput::Slopes, slopes = what != FitOutput::Transport;
  const std::optional<LsqProjection> slope_proj =
      slopes ? std::optional<LsqProjection>(std::in_place, ns, dirs, dir::kFitElevations, dir::kFitEpsilon, 0,
                                            az.weights)
             : std::nullopt;
  std::vector<const float*> P;
  for (int r = 0; transport && r < nb; ++r) P.push_back(&proj.P[std::size_t(r) * std::size_t(nd)]);
  for (int r = 0; slopes && r < ns; ++r) P.push_back(&slope_proj->P[std::size_t(r) * std::size_t(nd)]);
  const std::vector<double> S = fit_suffix_sums(proj.dirs, na, ne, P);
  Texture out(w, h, (transport ? nb : 0) + (slopes ? 2 * ns : 0));
  const FitRows rows{lit.data(), wh, w, na, ne, n.data(), proj.dirs.data(), S.data()};
  tbb::parallel_for(0, h, [&](int j) {
    std::vector<double> sums(std::size_t(w) * std::size_t(out.channels()));
    fit_row(rows, j, transport, slopes, sums.data());
    for (int i = 0; i < w; ++i)
      for (int r = 0; r < out.channels(); ++r)
        out.at(i, j, r) = float(sums[std::size_t(i) * std::size_t(out.channels()) + std::size_t(r)]);
  });
  return out;
}
}  // namespace

Texture bake_directional_channels(const Texture& height, float depth, int azimuths, float max_distance) {
  check_directional_azimuths("bake_directional_channels", azimuths);
  return fit_directional(height, depth, azimuths, max_distance, FitOutput::Transport);
}

Texture bake_directional_slope_channels(const Texture& height, float depth, int azimuths,
                                        float max_distance) {
  check_directional_azimuths("bake_directional_slope_channels", azimuths);
  return fit_directional(height, depth, azimuths, max_distance, FitOutput::Slopes);
}

Texture bake_directional_view_channels(const Texture& height, float depth, int azimuths, float max_distance) {
  check_directional_azimuths("bake_directional_view_channels", azimuths);
  return fit_directional(height, depth, azimuths, max_distance, FitOutput::Both);
}

Texture bake_horizon_moment_channels(const Texture& height, float depth, int azimuths, float max_distance) {
  check_directional_azimuths("bake_horizon_moment_channels", azimuths);
  const auto dirs = uniform_azimuths(azimuths);
  const auto tan_h = bake_horizon_tangents(height, depth, dirs, max_distance);
  const auto n = fine_normals(height, depth);
  const int w = height.width(), h = height.height();
  Texture out(w, h, dir::kHorizonChannels);
  tbb::parallel_for(0, h, [&](int j) {
    for (int i = 0; i < w; ++i) {
      const std::size_t p = std::size_t(j) * w + i;
      horizon_channels(&tan_h[p * dirs.size()], n[p], dirs, &out.at(i, j, 0));
    }
  });
  return out;
}

Texture exact_diffuse_transport(const Texture& height, float depth, Vec3f l, float max_distance) {
  if (!(l.z > 0) || !(std::abs(dot(l, l) - 1) < 1e-4f))
    throw InputError("exact_diffuse_transport: the light must be a unit vector above the tangent plane");
  const float horiz = std::sqrt(l.x * l.x + l.y * l.y);
  const Vec2f az = horiz > 0 ? Vec2f(l.x / horiz, l.y / horiz) : Vec2f(1, 0);
  // Classified against the light's own tan e (transport_texel's value): lit is exact, no horizon tolerance.
  const double tan_e = horiz > 0 ? double(l.z) / std::sqrt(double(l.x) * l.x + double(l.y) * l.y)
                                 : std::numeric_limits<double>::infinity();
  const auto tan_h = std::isfinite(tan_e)
                         ? bake_horizon_tangents(height, depth, {az}, max_distance, {{tan_e}})
                         : std::vector<float>(std::size_t(height.width()) * height.height(), 0.0f);
  const auto n = fine_normals(height, depth);
  const int w = height.width(), h = height.height();
  Texture out(w, h, 1);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t p = std::size_t(j) * w + i;
      out.at(i, j, 0) = transport_texel(tan_h[p], n[p], l);
    }
  return out;
}

// ---- The measurement ----

namespace {

struct Rep {
  std::string name;
  int bytes;
};

// Representations, in table order. Channel counts at 8 bits each (the coarse normal is the engine's normal
// map and not counted).
const std::vector<Rep>& reps() {
  static const std::vector<Rep> r = {{"ao", 1},
                                     {"reference", 1},
                                     {"chan-2018", 1},
                                     {"bent-cone", 4},
                                     {"sh1-lsq", 4},
                                     {"poly2-lsq", 9},
                                     {"poly2-lsq-eps0.03", 9},
                                     {"poly2-lsq-eps0.3", 9},
                                     {"poly12-lsq", 12},
                                     {"poly12-lsq-eps0.03", 12},
                                     {"resid-poly2-p1", 12},
                                     {"resid-poly2-p1-unit", 9},
                                     {"resid-poly2-p1-eps0.01", 12},
                                     {"resid-poly2-p2", 12},
                                     {"horizon-fourier", 5},
                                     {"hm-lit-cos", 10},
                                     {"hm-transport", 10}};
  return r;
}

struct Fine {
  int w = 0, h = 0;
  std::vector<Vec3f> n;
  Texture chans;  // per texel: V, bent (3), sh1 (4), poly2 (9), hm (10) = 27
};

constexpr int kChV = 0, kChBent = 1, kChSh1 = 4, kChPoly2 = 8, kChHm = 17, kChPoly2a = 27, kChPoly2b = 36,
              kChPoly12 = 45, kChPoly12a = 57, kChResid1 = 69, kChResid2 = 78, kChNmean = 87, kChResid3 = 90,
              kChCount = 99;

Texture bake_all_channels(const Texture& height, const std::vector<Vec2f>& dirs,
                          const std::vector<float>& tan_h, const std::vector<Vec3f>& n,
                          const std::vector<std::pair<const LsqProjection*, int>>& lsq) {
  const int w = height.width(), h = height.height(), na = int(dirs.size());
  Texture out(w, h, kChCount);
  tbb::parallel_for(0, h, [&](int j) {
    const LsqProjection& p2 = *lsq[0].first;
    std::vector<float> f(p2.dirs.size());
    for (int i = 0; i < w; ++i) {
      const std::size_t p = std::size_t(j) * w + i;
      const float* th = &tan_h[p * std::size_t(na)];
      double V = 0;
      Vec3d bent(0, 0, 0);
      for (int a = 0; a < na; ++a) {
        const double t = th[a];
        V += 1.0 / (1.0 + t * t);
        bent += dir::bent_vector_azimuth<double>(t, dirs[a].x, dirs[a].y);
      }
      float* o = &out.at(i, j, 0);
      o[kChV] = float(V / na);
      o[kChBent] = float(bent.x / na), o[kChBent + 1] = float(bent.y / na),
      o[kChBent + 2] = float(bent.z / na);
      for (int a = 0; a < na; ++a)
        for (int e = 0; e < p2.ne; ++e) {
          const int d = a * p2.ne + e;
          f[std::size_t(d)] = transport_texel(th[a], n[p], p2.dirs[std::size_t(d)]);
        }
      const int nd = int(f.size());
      for (const auto& [proj, first] : lsq)
        for (int r = 0; r < proj->nb; ++r) {
          double sum = 0;
          for (int d = 0; d < nd; ++d) {
            const double fd =
                proj->damp ? f[std::size_t(d)] - dot(n[p], p2.dirs[std::size_t(d)]) : f[std::size_t(d)];
            sum += double(proj->P[std::size_t(r) * nd + d]) * fd;
          }
          o[first + r] = float(sum);
        }
      horizon_channels(th, n[p], dirs, o + kChHm);
      o[kChNmean] = n[p].x, o[kChNmean + 1] = n[p].y, o[kChNmean + 2] = n[p].z;
    }
  });
  return out;
}

// 8-bit storage of the channels (channel_ranges): the same ranges for every mip level, quantised again after
// the box mean.
using Ranges = ChannelRanges;
void quantize_channels(Texture& t, const Ranges& r) {
  for (int j = 0; j < t.height(); ++j)
    for (int i = 0; i < t.width(); ++i)
      for (int c = 0; c < t.channels(); ++c)
        t.at(i, j, c) = quantize8(t.at(i, j, c), r.lo[std::size_t(c)], r.hi[std::size_t(c)]);
}

float eval_rep(const std::string& rep, const float* ch, const Vec3f& nc, const Vec3f& l) {
  if (rep.rfind("resid-poly2", 0) == 0) {
    const bool unit = rep.find("-unit") != std::string::npos;  // the renormalised coarse normal instead
    const int power = rep[std::string("resid-poly2-p").size()] - '0';
    float b[dir::kPoly2Terms];
    dir::poly2_basis(l, b);
    const float* d = ch + (rep.find("eps0.01") != std::string::npos ? kChResid3
                           : power == 1                             ? kChResid1
                                                                    : kChResid2);
    float s = 0;
    for (int m = 0; m < dir::kPoly2Terms; ++m) s += d[m] * b[m];
    const Vec3f nm(ch[kChNmean], ch[kChNmean + 1], ch[kChNmean + 2]);  // stored (and quantised) mean normal
    return std::max(dot(unit ? nc : nm, l) + s * std::pow(1 - l.z, float(power)), 0.0f);
  }
  const float nl = std::max(dot(nc, l), 0.0f);
  const float V = std::clamp(ch[kChV], 0.0f, 1.0f), cos_t = std::sqrt(1 - V);
  if (rep == "ao") return V * nl;
  if (rep == "reference") return nl > cos_t ? nl : 0.0f;
  if (rep == "chan-2018") {
    const float x = cos_t > 0 ? std::min(nl / cos_t, 1.0f) : 1.0f;
    return x * x * nl;
  }
  if (rep == "bent-cone") {
    Vec3f b(ch[kChBent], ch[kChBent + 1], ch[kChBent + 2]);
    const float len = std::sqrt(dot(b, b));
    b = len > 0 ? b / len : Vec3f(0, 0, 1);
    return dot(b, l) > cos_t ? nl : 0.0f;
  }
  if (rep == "poly2-lsq-eps0.03") return dir::directional_transport(ch + kChPoly2a, l);  // the shipped one
  if (rep.find("-lsq") != std::string::npos) {
    float b[dir::kPoly12Terms];
    dir::poly12_basis(l, b);
    const int first = rep == "sh1-lsq"             ? kChSh1
                      : rep == "poly2-lsq"         ? kChPoly2
                      : rep == "poly2-lsq-eps0.03" ? kChPoly2a
                      : rep == "poly2-lsq-eps0.3"  ? kChPoly2b
                      : rep == "poly12-lsq"        ? kChPoly12
                                                   : kChPoly12a;
    const int nb = first == kChSh1 ? 4 : first >= kChPoly12 ? 12 : 9;
    float s = 0;
    for (int m = 0; m < nb; ++m) s += ch[first + m] * b[m];
    return std::max(s, 0.0f);
  }
  const float* hm = ch + kChHm;
  if (rep == "horizon-fourier") {  // the mean horizon only: a step at its Fourier value
    float f[dir::kHorizonTerms];
    dir::fourier_basis(l.x, l.y, f);
    float m1 = 0;
    for (int m = 0; m < dir::kHorizonTerms; ++m) m1 += hm[m] * f[m];
    return l.z > m1 ? nl : 0.0f;
  }
  if (rep == "hm-lit-cos") return dir::hm_lit_cosine(hm, l, nc);
  if (rep == "hm-transport") return dir::hm_transport(hm, l);
  throw InputError("unknown representation " + rep);
}

}  // namespace

std::vector<DirectionalStudyRow> directional_study(const DirectionalStudyOptions& opt) {
  std::vector<DirectionalStudyRow> rows;
  const auto bake_dirs = uniform_azimuths(opt.bake_azimuths);
  const LsqProjection p1(4, bake_dirs, 16), p2(dir::kPoly2Terms, bake_dirs, 16),
      p2a(dir::kPoly2Terms, bake_dirs, dir::kFitElevations, dir::kFitEpsilon),
      p2b(dir::kPoly2Terms, bake_dirs, 16, 0.3), p12(dir::kPoly12Terms, bake_dirs, 16),
      p12a(dir::kPoly12Terms, bake_dirs, 16, 0.03),
      r1(dir::kPoly2Terms, bake_dirs, dir::kFitElevations, dir::kFitEpsilon, 1),
      r2(dir::kPoly2Terms, bake_dirs, dir::kFitElevations, dir::kFitEpsilon, 2),
      r3(dir::kPoly2Terms, bake_dirs, dir::kFitElevations, 0.01, 1);
  const std::vector<std::pair<const LsqProjection*, int>> lsq = {
      {&p2, kChPoly2},     {&p1, kChSh1},    {&p2a, kChPoly2a}, {&p2b, kChPoly2b}, {&p12, kChPoly12},
      {&p12a, kChPoly12a}, {&r1, kChResid1}, {&r2, kChResid2},  {&r3, kChResid3}};
  for (const auto& kind : opt.kinds) {
    GenOptions g;
    g.kind = kind, g.size = opt.size, g.ao_rays = 1;  // V is re-baked here from the same horizons
    const TextureSet set = generate_texture_set(g);
    const float depth = set.depth_texels;
    const int w = set.height.width(), h = set.height.height();
    const auto n = fine_normals(set.height, depth);
    // Exact transport per fine texel and light, unlimited rays.
    std::vector<Vec2f> light_az;
    for (float a : opt.azimuths_deg) light_az.push_back(azimuth_dir(a));
    const auto tan_light = bake_horizon_tangents(set.height, depth, light_az, 0);
    struct Light {
      float elev, az;
      Vec3f l;
      int ai;
    };
    std::vector<Light> lights;
    for (std::size_t ai = 0; ai < light_az.size(); ++ai)
      for (float e : opt.elevations_deg)
        lights.push_back({e, opt.azimuths_deg[ai], light_dir(e, light_az[ai]), int(ai)});
    std::vector<Texture> exact;
    for (const auto& L : lights) {
      Texture t(w, h, 1);
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
          const std::size_t p = std::size_t(j) * w + i;
          t.at(i, j, 0) = transport_texel(tan_light[p * light_az.size() + std::size_t(L.ai)], n[p], L.l);
        }
      exact.push_back(std::move(t));
    }
    Texture normals(w, h, 3);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const Vec3f& v = n[std::size_t(j) * w + i];
        normals.at(i, j, 0) = v.x, normals.at(i, j, 1) = v.y, normals.at(i, j, 2) = v.z;
      }
    for (float dist_opt : opt.bake_distances) {
      const float dist = dist_opt < 0 ? 0.08f * float(std::max(w, h)) : dist_opt;
      const auto tan_h = bake_horizon_tangents(set.height, depth, bake_dirs, dist);
      const Texture fine_ch = bake_all_channels(set.height, bake_dirs, tan_h, n, lsq);
      // The exact transport with the bake's ray length: what a perfect representation of this bake gives.
      std::vector<Texture> exact_limited;
      if (dist > 0) {
        const auto tl = bake_horizon_tangents(set.height, depth, light_az, dist);
        for (const auto& L : lights) {
          Texture t(w, h, 1);
          for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
              const std::size_t p = std::size_t(j) * w + i;
              t.at(i, j, 0) = transport_texel(tl[p * light_az.size() + std::size_t(L.ai)], n[p], L.l);
            }
          exact_limited.push_back(std::move(t));
        }
      }
      for (int q = 0; q < (opt.quantize8 ? 2 : 1); ++q) {
        Texture fc = fine_ch;
        const Ranges ranges = channel_ranges(fine_ch);
        if (q) quantize_channels(fc, ranges);
        for (int k : opt.scales) {
          Texture ck = box_downsample(fc, k);
          if (q) quantize_channels(ck, ranges);
          const Texture nk = box_downsample(normals, k);
          const int W = ck.width(), H = ck.height(), B = 4;
          for (std::size_t li = 0; li < lights.size(); ++li) {
            const Texture tk = box_downsample(exact[li], k);
            std::vector<std::pair<std::string, int>> names;
            for (const auto& r : reps()) names.push_back({r.name, r.bytes});
            if (dist > 0 && q == 0) names.push_back({"exact-limited", 0});
            for (const auto& [name, bytes] : names) {
              Texture approx(W, H, 1);
              if (name == "exact-limited") {
                approx = box_downsample(exact_limited[li], k);
              } else {
                for (int J = 0; J < H; ++J)
                  for (int I = 0; I < W; ++I) {
                    const Vec3f nmean(nk.at(I, J, 0), nk.at(I, J, 1), nk.at(I, J, 2));
                    const Vec3f nc = nmean / std::sqrt(dot(nmean, nmean));
                    approx.at(I, J, 0) = eval_rep(name, &ck.at(I, J, 0), nc, lights[li].l);
                  }
              }
              double st = 0, sa = 0;
              for (int J = 0; J < H; ++J)
                for (int I = 0; I < W; ++I) st += tk.at(I, J, 0), sa += approx.at(I, J, 0);
              double se = 0;
              int nb = 0;
              for (int J = 0; J + B <= H; J += B)
                for (int I = 0; I + B <= W; I += B) {
                  double bt = 0, ba = 0;
                  for (int j = 0; j < B; ++j)
                    for (int i = 0; i < B; ++i)
                      bt += tk.at(I + i, J + j, 0), ba += approx.at(I + i, J + j, 0);
                  const double d = (ba - bt) / (B * B);
                  se += d * d, ++nb;
                }
              const double mean_t = st / (double(W) * H);
              DirectionalStudyRow row;
              row.kind = kind, row.representation = q ? name + "@8bit" : name, row.bake_distance = dist,
              row.k = k;
              row.elevation_deg = lights[li].elev, row.azimuth_deg = lights[li].az;
              row.bias = st > 0 ? sa / st : 0;
              row.rmse_footprint = mean_t > 0 ? std::sqrt(se / std::max(nb, 1)) / mean_t : 0;
              row.bytes = bytes;
              rows.push_back(row);
            }
          }
        }
      }
    }
  }
  return rows;
}

std::string directional_study_markdown(const std::vector<DirectionalStudyRow>& rows) {
  // Group: (distance, representation) → (kind, k) → rows.
  std::vector<std::string> rep_order;
  std::vector<float> dists;
  for (const auto& r : rows) {
    if (std::find(rep_order.begin(), rep_order.end(), r.representation) == rep_order.end())
      rep_order.push_back(r.representation);
    if (std::find(dists.begin(), dists.end(), r.bake_distance) == dists.end())
      dists.push_back(r.bake_distance);
  }
  std::ostringstream o;
  for (float dist : dists) {
    o << fmt::format("\n### Bake distance {}\n\n", dist > 0 ? fmt::format("{} texels", dist) : "unlimited");
    // Light header from the first (rep, kind, k) group.
    std::vector<std::string> light_names;
    {
      const auto& r0 =
          *std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.bake_distance == dist; });
      for (const auto& r : rows)
        if (r.bake_distance == dist && r.representation == r0.representation && r.kind == r0.kind &&
            r.k == r0.k)
          light_names.push_back(fmt::format("{:g}/{:g}", r.elevation_deg, r.azimuth_deg));
    }
    o << "Bias = Σ T̃ / Σ T per light (elevation°/azimuth°); mean and max |bias − 1| over the lights; "
         "footprint "
         "RMSE / mean T (mean over the lights).\n\n";
    o << "| representation | bytes | material | k |";
    for (const auto& l : light_names) o << " " << l << " |";
    o << " mean abs(b−1) | max abs(b−1) | fp RMSE |\n|---|---|---|---|";
    for (std::size_t i = 0; i < light_names.size() + 3; ++i) o << "---|";
    o << "\n";
    struct Sum {
      double mean_dev = 0, max_dev = 0, rmse = 0;
      int n = 0;
    };
    std::map<std::string, Sum> overall;
    for (const auto& rep : rep_order) {
      std::vector<std::pair<std::string, int>> groups;
      for (const auto& r : rows)
        if (r.bake_distance == dist && r.representation == rep &&
            std::find(groups.begin(), groups.end(), std::make_pair(r.kind, r.k)) == groups.end())
          groups.push_back({r.kind, r.k});
      for (const auto& [kind, k] : groups) {
        double md = 0, mx = 0, rm = 0;
        int cnt = 0, bytes = 0;
        std::string cells;
        for (const auto& r : rows)
          if (r.bake_distance == dist && r.representation == rep && r.kind == kind && r.k == k) {
            const double d = std::abs(r.bias - 1);
            md += d, mx = std::max(mx, d), rm += r.rmse_footprint, ++cnt, bytes = r.bytes;
            cells += fmt::format(" {:.3f} |", r.bias);
          }
        md /= cnt, rm /= cnt;
        o << fmt::format("| {} | {} | {} | {} |{} {:.3f} | {:.3f} | {:.3f} |\n", rep, bytes, kind, k, cells,
                         md, mx, rm);
        auto& s = overall[rep];
        s.mean_dev += md, s.max_dev = std::max(s.max_dev, mx), s.rmse += rm, ++s.n;
      }
    }
    // Footprint RMSE against the best cone term (ao, reference, chan-2018 of the same storage): per cell
    // (material, k, light) and per group (material, k; mean over the lights).
    auto fp_of = [&](const std::string& rep, const std::string& kind, int k, float e, float az) {
      for (const auto& r : rows)
        if (r.bake_distance == dist && r.representation == rep && r.kind == kind && r.k == k &&
            r.elevation_deg == e && r.azimuth_deg == az)
          return r.rmse_footprint;
      return std::numeric_limits<double>::quiet_NaN();
    };
    o << "\nSummary over materials and k (mean of the per-group means; max over all lights; cells = "
         "(material, "
         "k, light) where the footprint RMSE is below that of every cone term (ao, reference, chan-2018); "
         "groups = (material, k) where the mean over the lights is below the best cone term's):\n\n"
         "| representation | bytes | mean abs(b−1) | max abs(b−1) | mean fp RMSE | fp < best cone: cells | "
         "groups |\n|---|---|---|---|---|---|---|\n";
    for (const auto& rep : rep_order) {
      const auto& s = overall[rep];
      if (!s.n) continue;
      const std::string suffix = rep.find("@8bit") != std::string::npos ? "@8bit" : "";
      int cells = 0, cells_won = 0, bytes = 0;
      std::map<std::pair<std::string, int>, std::array<double, 4>> groups;  // sums: rep, ao, ref, chan
      for (const auto& r : rows) {
        if (r.bake_distance != dist || r.representation != rep) continue;
        bytes = r.bytes;
        double cone[3];
        int ci = 0;
        for (const char* c : {"ao", "reference", "chan-2018"})
          cone[ci++] = fp_of(std::string(c) + suffix, r.kind, r.k, r.elevation_deg, r.azimuth_deg);
        ++cells;
        cells_won += r.rmse_footprint < std::min({cone[0], cone[1], cone[2]});
        auto& g = groups[{r.kind, r.k}];
        g[0] += r.rmse_footprint, g[1] += cone[0], g[2] += cone[1], g[3] += cone[2];
      }
      int groups_won = 0;
      for (const auto& [key, g] : groups) groups_won += g[0] < std::min({g[1], g[2], g[3]});
      o << fmt::format("| {} | {} | {:.3f} | {:.3f} | {:.3f} | {}/{} | {}/{} |\n", rep, bytes,
                       s.mean_dev / s.n, s.max_dev, s.rmse / s.n, cells_won, cells, groups_won,
                       groups.size());
    }
  }
  return o.str();
}

}  // namespace msh::render
