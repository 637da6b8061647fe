// Directional micro-occlusion bake (render/directional_bake.h). The helpers the research harness shares
// (tools/research/directional_study.cpp) are declared in directional_bake_detail.h.
#include <fmt/format.h>
#include <microshadow/io/bc4.h>
#include <microshadow/io/error.h>
#include <microshadow/io/names.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/texture_gen.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "directional_bake_detail.h"

namespace msh::render {

namespace dir = msh::directional;

namespace detail {

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

LsqProjection::LsqProjection(int nb_, const std::vector<Vec2f>& az, int ne_, double eps, int damp_,
                             const std::vector<double>& az_weight)
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

float quantize8(float v, float lo, float hi) {
  const float t = std::clamp((v - lo) / (hi - lo), 0.0f, 1.0f);
  return lo + (hi - lo) * std::round(t * 255.0f) / 255.0f;
}

}  // namespace detail

using namespace detail;

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

namespace {
constexpr Named<DirectionalEncoding> kDirectionalEncodings[] = {{DirectionalEncoding::Float, "float"},
                                                                {DirectionalEncoding::Unorm8, "unorm8"},
                                                                {DirectionalEncoding::Bc4, "bc4"}};
}  // namespace

DirectionalEncoding directional_encoding_from_name(const std::string& name) {
  return value_of<DirectionalEncoding>(kDirectionalEncodings, name, "directional encoding");
}

std::string directional_encoding_name(DirectionalEncoding e) {
  return name_of<DirectionalEncoding>(kDirectionalEncodings, e);
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

}  // namespace msh::render
