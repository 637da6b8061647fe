// Compact forms of the directional channels (render/directional_codec.h), on channels baked from generated
// relief:
//  - the weighted PCA is optimal as claimed: the mean error (c − ĉ)ᵀ M (c − ĉ), computed directly, equals the
//    discarded share of the metric-weighted variance (the eigenvalue tail), and no random subspace of the
//    same dimension does better;
//  - the mips stay exact: the coefficients of a box mean are the box mean of the coefficients, and decode
//    likewise; the full-rank float form reproduces the channels;
//  - quantisation error within half a UNORM step; deterministic whatever the thread count; bad input errors.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/directional_codec.h>
#include <microshadow/render/texture_gen.h>
#include <tbb/global_control.h>

#include <cmath>
#include <random>

using namespace msh;
using namespace msh::render;
namespace dir = msh::directional;

namespace {

const Texture& rock_channels() {
  static const Texture t = [] {
    GenOptions g;
    g.kind = "rock", g.size = 64, g.ao_rays = 1;
    const TextureSet s = generate_texture_set(g);
    return bake_directional_view_channels(s.height, s.depth_texels, 16, 0);
  }();
  return t;
}

// Mean over texels of (x − y)ᵀ M (x − y), channel textures of C channels (y empty: the codec's mean).
double metric_error(const Texture& x, const Texture* y, const std::vector<float>& mean,
                    const std::vector<double>& M) {
  const int C = x.channels();
  double s = 0;
  std::vector<double> d(static_cast<std::size_t>(C));
  for (int j = 0; j < x.height(); ++j)
    for (int i = 0; i < x.width(); ++i) {
      for (int c = 0; c < C; ++c)
        d[std::size_t(c)] = double(x.at(i, j, c)) - (y ? y->at(i, j, c) : mean[std::size_t(c)]);
      for (int a = 0; a < C; ++a)
        for (int b = 0; b < C; ++b) s += d[std::size_t(a)] * M[std::size_t(a) * C + b] * d[std::size_t(b)];
    }
  return s / (double(x.width()) * x.height());
}

// Solves the small dense system A x = b (Gaussian elimination with partial pivoting).
std::vector<double> solve(std::vector<double> A, std::vector<double> b) {
  const int n = int(b.size());
  for (int c = 0; c < n; ++c) {
    int p = c;
    for (int r = c + 1; r < n; ++r)
      if (std::abs(A[std::size_t(r) * n + c]) > std::abs(A[std::size_t(p) * n + c])) p = r;
    for (int k = 0; k < n; ++k) std::swap(A[std::size_t(c) * n + k], A[std::size_t(p) * n + k]);
    std::swap(b[std::size_t(c)], b[std::size_t(p)]);
    for (int r = c + 1; r < n; ++r) {
      const double f = A[std::size_t(r) * n + c] / A[std::size_t(c) * n + c];
      for (int k = c; k < n; ++k) A[std::size_t(r) * n + k] -= f * A[std::size_t(c) * n + k];
      b[std::size_t(r)] -= f * b[std::size_t(c)];
    }
  }
  std::vector<double> x(static_cast<std::size_t>(n));
  for (int r = n - 1; r >= 0; --r) {
    double s = b[std::size_t(r)];
    for (int k = r + 1; k < n; ++k) s -= A[std::size_t(r) * n + k] * x[std::size_t(k)];
    x[std::size_t(r)] = s / A[std::size_t(r) * n + r];
  }
  return x;
}

}  // namespace

TEST(DirectionalCodec, FormNames) {
  const DirectionalCodec a = parse_directional_form("pca8", 21);
  EXPECT_EQ(a.coefficients, 8);
  EXPECT_EQ(a.bits, 8);
  EXPECT_EQ(a.bytes_per_texel(), 8.0);
  EXPECT_EQ(a.fetches(), 2);
  const DirectionalCodec b = parse_directional_form("pca6x16", 21);
  EXPECT_EQ(b.bits, 16);
  EXPECT_EQ(b.bytes_per_texel(), 12.0);
  EXPECT_EQ(parse_directional_form("pca21f", 21).bits, 0);
  EXPECT_EQ(parse_directional_form("pca9", 9).fetches(), 3);
  for (const char* bad : {"pca", "pca0", "pca22", "pca10", "pca8x8", "pcaf", "pc8", "pca-1", "pca8 "})
    EXPECT_THROW(parse_directional_form(bad, std::string(bad) == "pca10" ? 9 : 21), InputError) << bad;
  EXPECT_THROW(parse_directional_form("pca4", 12), InputError);
}

// The mean metric error of the K-term code equals the discarded share of the weighted variance, computed
// from the eigenvalues; and K random subspaces (each with its own best coefficients in the metric) do worse.
TEST(DirectionalCodec, ErrorIsTheEigenvalueTailAndOptimal) {
  const Texture& ch = rock_channels();
  for (int K : {2, 6, 12}) {
    const DirectionalCodec c = fit_directional_codec(ch, fmt::format("pca{}f", K));
    const std::vector<double> M = directional_transport_metric(c.mean);
    const double total = metric_error(ch, nullptr, c.mean, M);
    const Texture rec = decode_directional(encode_directional(ch, c), c);
    const double err = metric_error(ch, &rec, c.mean, M);
    double kept = 0;
    for (double e : c.explained) kept += e;
    EXPECT_NEAR(err / total, 1 - kept, 2e-4 + 1e-3 * (1 - kept)) << K;
    // Random K-dimensional subspaces: their M-orthogonal projection (normal equations BᵀMB a = BᵀM d).
    std::mt19937 rng(7 + K);
    std::normal_distribution<double> nd;
    const int C = ch.channels();
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<double> B(std::size_t(C) * K);
      for (double& x : B) x = nd(rng);
      std::vector<double> MB(std::size_t(C) * K, 0.0), BMB(std::size_t(K) * K, 0.0);
      for (int i = 0; i < C; ++i)
        for (int k = 0; k < K; ++k)
          for (int j = 0; j < C; ++j)
            MB[std::size_t(i) * K + k] += M[std::size_t(i) * C + j] * B[std::size_t(j) * K + k];
      for (int a = 0; a < K; ++a)
        for (int b = 0; b < K; ++b)
          for (int i = 0; i < C; ++i)
            BMB[std::size_t(a) * K + b] += B[std::size_t(i) * K + a] * MB[std::size_t(i) * K + b];
      Texture r(ch.width(), ch.height(), C);
      for (int y = 0; y < ch.height(); ++y)
        for (int x = 0; x < ch.width(); ++x) {
          std::vector<double> rhs(std::size_t(K), 0.0);
          for (int k = 0; k < K; ++k)
            for (int i = 0; i < C; ++i)
              rhs[std::size_t(k)] += MB[std::size_t(i) * K + k] * (ch.at(x, y, i) - c.mean[std::size_t(i)]);
          const std::vector<double> a = solve(BMB, rhs);
          for (int i = 0; i < C; ++i) {
            double v = c.mean[std::size_t(i)];
            for (int k = 0; k < K; ++k) v += B[std::size_t(i) * K + k] * a[std::size_t(k)];
            r.at(x, y, i) = float(v);
          }
        }
      EXPECT_GT(metric_error(ch, &r, c.mean, M), err) << K << " trial " << trial;
    }
  }
}

TEST(DirectionalCodec, MipsStayExactAndFullRankRoundTrips) {
  const Texture& ch = rock_channels();
  const DirectionalCodec c = fit_directional_codec(ch, "pca8f");
  const Texture a = encode_directional(ch, c);
  for (int k : {2, 8}) {
    const Texture mean_then_encode = encode_directional(box_downsample(ch, k), c);
    const Texture encode_then_mean = box_downsample(a, k);
    const Texture d1 = decode_directional(encode_then_mean, c),
                  d2 = box_downsample(decode_directional(a, c), k);
    for (int y = 0; y < mean_then_encode.height(); ++y)
      for (int x = 0; x < mean_then_encode.width(); ++x) {
        for (int q = 0; q < 8; ++q)
          EXPECT_NEAR(mean_then_encode.at(x, y, q), encode_then_mean.at(x, y, q), 2e-5) << k;
        for (int i = 0; i < 21; ++i) EXPECT_NEAR(d1.at(x, y, i), d2.at(x, y, i), 2e-5) << k;
      }
  }
  const DirectionalCodec full = fit_directional_codec(ch, "pca21f");
  const Texture back = store_through_codec(ch, full);
  double worst = 0;
  for (int y = 0; y < ch.height(); ++y)
    for (int x = 0; x < ch.width(); ++x)
      for (int i = 0; i < 21; ++i)
        worst = std::max(worst, double(std::abs(back.at(x, y, i) - ch.at(x, y, i))));
  EXPECT_LT(worst, 1e-4);
  // The 9-channel directional code too.
  Texture nine(ch.width(), ch.height(), 9);
  for (int y = 0; y < ch.height(); ++y)
    for (int x = 0; x < ch.width(); ++x)
      for (int i = 0; i < 9; ++i) nine.at(x, y, i) = ch.at(x, y, i);
  const Texture back9 = store_through_codec(nine, fit_directional_codec(nine, "pca9f"));
  for (int y = 0; y < ch.height(); y += 7)
    for (int x = 0; x < ch.width(); x += 5)
      for (int i = 0; i < 9; ++i) EXPECT_NEAR(back9.at(x, y, i), nine.at(x, y, i), 1e-4);
}

TEST(DirectionalCodec, QuantisationWithinHalfAStep) {
  const Texture& ch = rock_channels();
  for (const char* form : {"pca8", "pca4x16"}) {
    const DirectionalCodec c = fit_directional_codec(ch, form);
    const Texture a = encode_directional(box_downsample(ch, 4), c);
    Texture q = a;
    quantize_coefficients(q, c);
    const double steps = double((1 << c.bits) - 1);
    for (int y = 0; y < a.height(); ++y)
      for (int x = 0; x < a.width(); ++x)
        for (int k = 0; k < c.coefficients; ++k) {
          const double range = c.hi[std::size_t(k)] - c.lo[std::size_t(k)];
          // Half a step, plus the float rounding of lo + (hi − lo) u (a few ulps of the range's end).
          const double ulps =
              8 * 1.2e-7 * std::max(std::abs(c.lo[std::size_t(k)]), std::abs(c.hi[std::size_t(k)]));
          EXPECT_LE(std::abs(q.at(x, y, k) - a.at(x, y, k)), 0.5 * range / steps + ulps) << form;
          const double u = (q.at(x, y, k) - c.lo[std::size_t(k)]) / range * steps;
          EXPECT_NEAR(u, std::round(u), 1e-2) << form;  // on the grid
        }
  }
}

TEST(DirectionalCodec, DeterministicWhateverTheThreads) {
  const Texture& ch = rock_channels();
  DirectionalCodec one, two;
  {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, 1);
    one = fit_directional_codec(ch, "pca8");
  }
  {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, 2);
    two = fit_directional_codec(ch, "pca8");
  }
  EXPECT_EQ(one.basis, two.basis);
  EXPECT_EQ(one.encode, two.encode);
  EXPECT_EQ(one.lo, two.lo);
  EXPECT_EQ(one.hi, two.hi);
  EXPECT_EQ(one.mean, two.mean);
}

TEST(DirectionalCodec, BadInput) {
  Texture t = rock_channels();
  t.at(3, 5, 7) = std::nanf("");
  EXPECT_THROW(fit_directional_codec(t, "pca8"), InputError);
  EXPECT_THROW(fit_directional_codec(Texture(8, 8, 12), "pca8"), InputError);
  const DirectionalCodec c = fit_directional_codec(rock_channels(), "pca8");
  EXPECT_THROW(encode_directional(Texture(8, 8, 9), c), InputError);
  EXPECT_THROW(decode_directional(Texture(8, 8, 7), c), InputError);
  EXPECT_THROW(directional_transport_metric(std::vector<float>(10, 0.0f)), InputError);
}
