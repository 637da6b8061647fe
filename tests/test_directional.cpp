// Directional micro-occlusion (occlusion/directional.h, render/directional_bake.h):
//  - the exact texture-space transport against closed forms: flat field = cos θ; a step of height D casts a
//    shadow of horizontal length D / tan e (with a ray length R, none beyond R); a symmetric V-groove's
//    bottom is lit iff e > β;
//  - the horizon-moment channels: zero on a flat field (transport = sin e exactly), exact Fourier analysis
//    of band-limited horizons, box-filterable (mip chain = box means);
//  - the run-time reconstruction against its exact reference (numerical quadrature of E[sin(e − h)⁺] under
//    the uniform model) at continuous, off-knot inputs, in float and double;
//  - determinism whatever the thread count.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/texture_gen.h>
#include <support/texture_test_util.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>

using namespace msh;
using namespace msh::render;
using msh::test::depth_field;
namespace dir = msh::directional;

namespace {

constexpr double kPiD = 3.14159265358979323846;

Vec3f light(double elev_deg, double az_deg) {
  const double e = elev_deg * kPiD / 180, a = az_deg * kPiD / 180;
  return Vec3f(float(std::cos(e) * std::cos(a)), float(std::cos(e) * std::sin(a)), float(std::sin(e)));
}

// A generated texture set of `kind`, size² (one AO ray: the tests read its height field and depth).
TextureSet texture_set(const std::string& kind, int size) {
  GenOptions g;
  g.kind = kind, g.size = size, g.ao_rays = 1;
  return generate_texture_set(g);
}

}  // namespace

TEST(DirectionalExact, FlatFieldIsCosine) {
  const Texture flat = depth_field(32, 16, 4, [](int, int) { return -2.0; });
  for (double e : {5.0, 25.0, 70.0})
    for (double a : {0.0, 37.0, 90.0, 211.0}) {
      const Vec3f l = light(e, a);
      const Texture t = exact_diffuse_transport(flat, 4, l, 0);
      for (int j = 0; j < t.height(); ++j)
        for (int i = 0; i < t.width(); ++i) ASSERT_NEAR(t.at(i, j, 0), l.z, 1e-6) << e << " " << a;
    }
}

// A trench: plateau on columns [0, 32), floor D = 8 texels lower on [32, 64) (wrap: the walls are the ramps
// 63→64 ≡ 0 and 32→31). A floor vertex i looking along +u sees the top of the ramp at distance 64 − i:
// tan H = D / (64 − i), so it is lit iff 64 − i > D / tan e (the shadow length D / tan e); looking along
// −u, the other wall's top at distance i − 31. Floor vertices away from the ramps have n = +z.
TEST(DirectionalExact, StepCastsShadowOfKnownLength) {
  const double D = 8;
  const Texture step = depth_field(64, 4, 16, [&](int i, int) { return i < 32 ? 0.0 : -D; });
  for (double e : {10.0, 20.0, 45.0}) {
    const double tan_e = std::tan(e * kPiD / 180);
    for (double az : {0.0, 180.0}) {
      const Vec3f l = light(e, az);
      const Texture t = exact_diffuse_transport(step, 16, l, 0);
      for (int i = 34; i < 62; ++i) {
        const bool lit = (az == 0.0 ? 64 - i : i - 31) * tan_e > D;
        EXPECT_NEAR(t.at(i, 1, 0), lit ? l.z : 0.0f, 1e-6) << "e " << e << " az " << az << " i " << i;
      }
    }
    // A ray length R: the wall is out of reach for floor vertices farther than R from its top.
    const Vec3f l = light(e, 0);
    const double R = 10;
    const Texture t = exact_diffuse_transport(step, 16, l, float(R));
    for (int i = 34; i < 62; ++i) {
      const double d = 64 - i;  // horizontal distance to the top of the ramp
      // Blocked iff some point of the ramp/plateau within ray length R rises above the ray: the ramp top
      // (d, D) is reached by the ray at length d/cos e, the ramp foot at (d − 1) with height 0 never blocks.
      // Closed form for this profile: blocked iff there is s ∈ [d − 1, d] ∪ [d, ∞) with z(s) ≥ s tan e and
      // s² + z(s)² ≤ R² (the ray reaches the point within R). Evaluated on a fine grid of s.
      bool blocked = false;
      for (double s = d - 1; s <= d + 64 && !blocked; s += 1e-3) {
        const double z = s < d ? D * (s - (d - 1)) : D;
        if (z >= s * std::tan(e * kPiD / 180) &&
            s * s + (s * std::tan(e * kPiD / 180)) * (s * std::tan(e * kPiD / 180)) <= R * R)
          blocked = true;
      }
      EXPECT_NEAR(t.at(i, 1, 0), blocked ? 0.0f : l.z, 1e-6) << "R e " << e << " i " << i;
    }
  }
}

// V-groove along v with walls at β: the bottom vertex is lit along ±u iff e > β, along v always.
TEST(DirectionalExact, GrooveBottomLitAboveWallAngle) {
  const double beta = 30 * kPiD / 180, tb = std::tan(beta);
  const Texture groove =
      depth_field(128, 4, 64, [&](int i, int) { return -tb * (32 - std::min(std::abs(i - 64), 32)); });
  for (double e : {20.0, 29.0, 31.0, 60.0}) {
    const Vec3f l = light(e, 0);
    const Texture t = exact_diffuse_transport(groove, 64, l, 0);
    EXPECT_NEAR(t.at(64, 1, 0), e > 30 ? l.z : 0.0f, 1e-6) << e;
    const Texture tv = exact_diffuse_transport(groove, 64, light(e, 90), 0);
    EXPECT_NEAR(tv.at(64, 1, 0), light(e, 90).z, 1e-6) << e;
  }
}

TEST(DirectionalChannels, FlatFieldGivesZeroChannelsAndExactTransport) {
  const Texture flat = depth_field(16, 16, 4, [](int, int) { return -1.0; });
  const Texture ch = bake_horizon_moment_channels(flat, 4, 16, 0);
  ASSERT_EQ(ch.channels(), dir::kHorizonChannels);
  float c[dir::kHorizonChannels];
  for (int k = 0; k < ch.channels(); ++k) {
    c[k] = ch.at(3, 5, k);
    EXPECT_EQ(c[k], 0.0f);
  }
  for (double e : {3.0, 17.0, 55.0, 88.0}) {
    const Vec3f l = light(e, 123.4);
    EXPECT_NEAR(dir::hm_transport(c, l), l.z, 1e-6);
  }
}

// Horizons whose sine is a Fourier polynomial of order ≤ 2 are analysed exactly by N ≥ 5 uniform samples,
// and the reconstruction at any azimuth (not a sample) returns the polynomial.
TEST(DirectionalChannels, FourierAnalysisExactForBandLimitedHorizons) {
  auto s_of = [](double phi) {
    return 0.2 + 0.15 * std::cos(phi) - 0.1 * std::sin(phi) + 0.05 * std::sin(2 * phi);
  };
  for (int N : {8, 16, 32}) {
    double ch[dir::kHorizonChannels] = {};
    for (int k = 0; k < N; ++k) {
      const double phi = 2 * kPiD * (k + 0.5) / N, s = s_of(phi);
      double w[dir::kHorizonTerms];
      dir::fourier_analysis_weights(std::cos(phi), std::sin(phi), N, w);
      for (int m = 0; m < dir::kHorizonTerms; ++m) ch[m] += w[m] * s;
    }
    for (double phi : {0.1234, 1.0, 2.5, 4.0, 5.9}) {
      double f[dir::kHorizonTerms], m1 = 0;
      dir::fourier_basis(std::cos(phi) * 0.3, std::sin(phi) * 0.3, f);  // a non-unit direction
      for (int m = 0; m < dir::kHorizonTerms; ++m) m1 += ch[m] * f[m];
      EXPECT_NEAR(m1, s_of(phi), 1e-12) << N << " " << phi;
    }
  }
}

// Exact reference of the reconstruction: E[max(0, sin e cos h − cos e sin h)] over sin h ~ U[a, b] by a
// fine midpoint rule (the integrand is continuous, with one kink at sin h = sin e).
double transport_quadrature(double mean, double var, double e) {
  const double half = std::sqrt(3 * var), a = std::max(mean - half, -1.0), b = std::min(mean + half, 1.0);
  const int n = 200000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double s = a + (b - a) * (i + 0.5) / n;
    sum += std::max(0.0, std::sin(e) * std::sqrt(1 - s * s) - std::cos(e) * s);
  }
  return sum / n;
}

TEST(DirectionalRuntime, TransportMatchesQuadratureOffKnots) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0, 1);
  double max_err_d = 0, max_err_f = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const double mean = -0.3 + 1.0 * U(rng), var = 0.04 * U(rng) * U(rng),
                 e = (0.5 + 89 * U(rng)) * kPiD / 180;
    const double ref = transport_quadrature(mean, var, e);
    const double got = dir::horizon_transport(mean, var, std::sin(e), std::cos(e));
    const float gotf =
        dir::horizon_transport(float(mean), float(var), float(std::sin(e)), float(std::cos(e)));
    max_err_d = std::max(max_err_d, std::abs(got - ref));
    max_err_f = std::max(max_err_f, std::abs(double(gotf) - ref));
  }
  EXPECT_LT(max_err_d, 1e-6);
  EXPECT_LT(max_err_f, 2e-4);  // float cancellation in the antiderivative difference
  // Zero variance: the point value sin(e − h)⁺.
  EXPECT_NEAR(dir::horizon_transport(0.5, 0.0, std::sin(0.7), std::cos(0.7)),
              std::max(0.0, std::sin(0.7 - std::asin(0.5))), 1e-12);
  EXPECT_EQ(dir::horizon_transport(0.5, 0.0, std::sin(0.4), std::cos(0.4)), 0.0);
}

// The full run-time path from channels (Fourier evaluation at an off-knot azimuth, moments, transport) in
// float against double, and against the quadrature reference of the moments it reconstructs.
TEST(DirectionalRuntime, FloatMatchesDoubleThroughChannels) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    double ch[dir::kHorizonChannels];
    float chf[dir::kHorizonChannels];
    const double m = 0.4 * U(rng) - 0.1, v = 0.02 * U(rng);
    const double g[dir::kHorizonTerms] = {m, 0.1 * (U(rng) - 0.5), 0.1 * (U(rng) - 0.5),
                                          0.05 * (U(rng) - 0.5), 0.05 * (U(rng) - 0.5)};
    for (int k = 0; k < dir::kHorizonTerms; ++k) ch[k] = g[k], ch[dir::kHorizonTerms + k] = 0;
    ch[dir::kHorizonTerms] = m * m + v + 0.01;  // a constant second moment ≥ the mean's square
    for (int c = 0; c < dir::kHorizonChannels; ++c) chf[c] = float(ch[c]);
    const double e = (1 + 88 * U(rng)) * kPiD / 180, a = 2 * kPiD * U(rng);
    const Vec3d l(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
    const double td = dir::hm_transport(ch, l);
    const float tf = dir::hm_transport(chf, Vec3f(l));
    EXPECT_NEAR(double(tf), td, 3e-4);
    double mean, var;
    dir::horizon_moments(ch, l, &mean, &var);
    EXPECT_NEAR(td, transport_quadrature(mean, var, e), 1e-6);
  }
}

TEST(DirectionalChannels, MipChainIsBoxMeans) {
  const TextureSet s = texture_set("bark", 64);
  const Texture ch = bake_horizon_moment_channels(s.height, s.depth_texels, 16, 0);
  const auto chain = box_mip_chain(ch);
  ASSERT_EQ(chain.size(), 7u);
  for (int lv : {2, 4}) {
    const Texture direct = box_downsample(ch, 1 << lv);
    for (int j = 0; j < direct.height(); ++j)
      for (int i = 0; i < direct.width(); ++i)
        for (int c = 0; c < direct.channels(); ++c)
          ASSERT_NEAR(chain[lv].at(i, j, c), direct.at(i, j, c), 1e-6);
  }
}

TEST(DirectionalChannels, DeterministicWhateverTheThreadCount) {
  const TextureSet s = texture_set("gravel", 64);
  Texture a, b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    a = bake_horizon_moment_channels(s.height, s.depth_texels, 16, 0);
  }
  b = bake_horizon_moment_channels(s.height, s.depth_texels, 16, 0);
  for (int j = 0; j < a.height(); ++j)
    for (int i = 0; i < a.width(); ++i)
      for (int c = 0; c < a.channels(); ++c) ASSERT_EQ(a.at(i, j, c), b.at(i, j, c));
}

TEST(DirectionalChannels, RejectsBadInput) {
  const Texture flat = depth_field(16, 16, 4, [](int, int) { return -1.0; });
  EXPECT_THROW(bake_horizon_moment_channels(flat, 4, 2, 0), InputError);
  EXPECT_THROW(box_downsample(flat, 3), InputError);
  EXPECT_THROW(exact_diffuse_transport(flat, 4, Vec3f(0, 0, -1), 0), InputError);
}

// ---- The shipped representation: degree-2 least-squares transport ----

// A flat field: f(l) = l.z, in the span of the basis, so the fit is exact: c = (0, 0, 0, 1, 0, …) and the
// run-time transport is l.z at any continuous direction.
TEST(DirectionalPoly2, FlatFieldFitIsExact) {
  const Texture flat = depth_field(16, 16, 4, [](int, int) { return -1.0; });
  const Texture ch = bake_directional_channels(flat, 4, 32, 0);
  ASSERT_EQ(ch.channels(), dir::kDirectionalChannels);
  float c[dir::kDirectionalChannels];
  for (int k = 0; k < dir::kDirectionalChannels; ++k) {
    c[k] = ch.at(7, 3, k);
    EXPECT_NEAR(c[k], k == 3 ? 1.0f : 0.0f, 2e-5) << k;
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(0, 1);
  for (int t = 0; t < 50; ++t) {
    const Vec3f l = light(0.5 + 89 * U(rng), 360 * U(rng));
    EXPECT_NEAR(dir::directional_transport(c, l), l.z, 3e-5);
    EXPECT_NEAR(dir::directional_term(c, l, Vec3f(0, 0, 1)), 1.0f, 3e-5 / l.z + 1e-6);
  }
  EXPECT_EQ(dir::directional_transport(c, Vec3f(0.6f, 0, -0.8f)), 0.0f);
}

// Dense weighted least squares by the normal equations (double), for the independent reference: the
// coefficients of the first nb of the 9 functions.
std::vector<double> lsq_solve(const std::vector<std::array<double, 9>>& B, const std::vector<double>& w,
                              const std::vector<double>& f, int nb = 9) {
  double G[9][10] = {};
  for (std::size_t d = 0; d < B.size(); ++d)
    for (int r = 0; r < nb; ++r) {
      for (int c = 0; c < nb; ++c) G[r][c] += w[d] * B[d][r] * B[d][c];
      G[r][nb] += w[d] * B[d][r] * f[d];
    }
  for (int c = 0; c < nb; ++c) {  // Gaussian elimination, partial pivoting
    int p = c;
    for (int r = c + 1; r < nb; ++r)
      if (std::abs(G[r][c]) > std::abs(G[p][c])) p = r;
    for (int k = 0; k <= nb; ++k) std::swap(G[c][k], G[p][k]);
    for (int r = c + 1; r < nb; ++r) {
      const double m = G[r][c] / G[c][c];
      for (int k = c; k <= nb; ++k) G[r][k] -= m * G[c][k];
    }
  }
  std::vector<double> x(static_cast<std::size_t>(nb));
  for (int r = nb - 1; r >= 0; --r) {
    double s = G[r][nb];
    for (int k = r + 1; k < nb; ++k) s -= G[r][k] * x[std::size_t(k)];
    x[std::size_t(r)] = s / G[r][r];
  }
  return x;
}

// The baker against its definition, computed independently: the exact transport of every fit direction
// (exact_diffuse_transport, one full-field horizon walk per direction) fitted by dense least squares per
// texel; then the run-time reconstruction at continuous directions off the fit grid, in float, against the
// reference polynomial, on a gravel field with real cast shadows.
TEST(DirectionalPoly2, BakerMatchesIndependentFitOffTheGrid) {
  const TextureSet s = texture_set("gravel", 16);
  const int na = 8;
  const Texture ch = bake_directional_channels(s.height, s.depth_texels, na, 0);
  // The fit's azimuths: lattice steps near the uniform ones, weighted by their share of the circle.
  const DirectionalBakeAzimuths az = directional_bake_azimuths(na);
  ASSERT_EQ(int(az.steps.size()), na);
  double wsum = 0;
  for (int a = 0; a < na; ++a) {
    const double phi = std::atan2(double(az.steps[std::size_t(a)].q), double(az.steps[std::size_t(a)].p));
    EXPECT_LE(std::abs(std::remainder(phi - 2 * kPiD * (a + 0.5) / na, 2 * kPiD)), 0.5 * kPiD / 180);
    wsum += az.weights[std::size_t(a)];
  }
  EXPECT_NEAR(wsum, na, 1e-9);  // the shares cover the circle once
  std::vector<std::array<double, 9>> B;
  std::vector<double> w;
  std::vector<Texture> T;
  for (int a = 0; a < na; ++a)
    for (int j = 0; j < dir::kFitElevations; ++j) {
      const LatticeStep st = az.steps[std::size_t(a)];
      const double phi = std::atan2(double(st.q), double(st.p)),
                   e = (j + 0.5) / dir::kFitElevations * kPiD / 2;
      const Vec3f l(float(std::cos(e) * std::cos(phi)), float(std::cos(e) * std::sin(phi)),
                    float(std::sin(e)));
      std::array<double, 9> b;
      dir::poly2_basis(Vec3d(l), b.data());
      B.push_back(b);
      w.push_back(std::cos(e) * dir::fit_weight(std::sin(e)) * az.weights[std::size_t(a)]);
      T.push_back(exact_diffuse_transport(s.height, s.depth_texels, l, 0));
    }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0, 1);
  double max_coef = 0, max_eval = 0;
  for (int y = 0; y < 16; y += 3)
    for (int x = 0; x < 16; x += 3) {
      std::vector<double> f;
      for (const auto& t : T) f.push_back(t.at(x, y, 0));
      const auto ref = lsq_solve(B, w, f);
      float c[9];
      for (int k = 0; k < 9; ++k) {
        c[k] = ch.at(x, y, k);
        max_coef = std::max(max_coef, std::abs(double(c[k]) - ref[std::size_t(k)]));
      }
      for (int t = 0; t < 20; ++t) {
        const Vec3f l = light(1 + 88 * U(rng), 360 * U(rng));
        double b[9], r = 0;
        dir::poly2_basis(Vec3d(l), b);
        for (int k = 0; k < 9; ++k) r += ref[std::size_t(k)] * b[k];
        max_eval = std::max(max_eval, std::abs(double(dir::directional_transport(c, l)) - std::max(r, 0.0)));
      }
    }
  EXPECT_LT(max_coef, 1e-3);
  EXPECT_LT(max_eval, 2e-3);

  // The view correction's channels against the same independent fit of f · n_x/n_z and f · n_y/n_z (n: the
  // height field's vertex normal, as the bake uses).
  const Texture sc = bake_directional_slope_channels(s.height, s.depth_texels, na, 0);
  ASSERT_EQ(sc.channels(), dir::kSlopeChannels);
  const HeightField hf(s.height, s.depth_texels);
  double max_slope_coef = 0;
  for (int y = 0; y < 16; y += 3)
    for (int x = 0; x < 16; x += 3) {
      const Vec3f nv = hf.vertex_normal(x, y);
      for (int axis = 0; axis < 2; ++axis) {
        std::vector<double> f;
        for (const auto& t : T) f.push_back(t.at(x, y, 0) * double(axis ? nv.y : nv.x) / nv.z);
        const int ns = dir::kSlopeTerms;
        const auto ref = lsq_solve(B, w, f, ns);
        for (int k = 0; k < ns; ++k)
          max_slope_coef =
              std::max(max_slope_coef, std::abs(double(sc.at(x, y, axis * ns + k)) - ref[std::size_t(k)]));
      }
    }
  EXPECT_LT(max_slope_coef, 1e-3);

  // The one-pass 21-channel bake (what gen-material --directional-view writes) is both bakes, bit for bit.
  const Texture v21 = bake_directional_view_channels(s.height, s.depth_texels, na, 0);
  ASSERT_EQ(v21.channels(), dir::kViewChannels);
  for (int y = 0; y < s.height.height(); ++y)
    for (int x = 0; x < s.height.width(); ++x)
      for (int k = 0; k < dir::kViewChannels; ++k)
        ASSERT_EQ(v21.at(x, y, k), k < 9 ? ch.at(x, y, k) : sc.at(x, y, k - 9)) << x << " " << y << " " << k;
  EXPECT_THROW(bake_directional_view_channels(s.height, s.depth_texels, 3, 0), InputError);
}

// The fewest azimuths: at 4 the 9-function fit is singular (x² − y² vanishes on all of 45°, 135°, …), which
// gave all-NaN channels; every bake refuses it, and from kMinDirectionalAzimuths = 5 on the channels are
// finite and fit a flat field exactly (T = l.z: c = e₃).
TEST(DirectionalBake, FewestAzimuthsRefusedOrFinite) {
  const Texture flat = depth_field(8, 8, 4, [](int, int) { return -1.0; });
  const Texture rough = generate_texture_set([] {
                          GenOptions o;
                          o.kind = "gravel", o.size = 16, o.ao_rays = 4, o.directional_azimuths = 0;
                          return o;
                        }())
                            .height;
  EXPECT_THROW(bake_directional_channels(rough, 4, 4, 0), InputError);
  EXPECT_THROW(bake_directional_slope_channels(rough, 4, 4, 0), InputError);
  EXPECT_THROW(bake_directional_view_channels(rough, 4, 4, 0), InputError);
  EXPECT_THROW(directional_bake_azimuths(4), InputError);
  GenOptions g;
  g.kind = "gravel", g.size = 16, g.directional_azimuths = 4;
  EXPECT_THROW(generate_texture_set(g), InputError);
  for (int na : {5, 6, 7}) {
    const Texture v = bake_directional_view_channels(rough, 4, na, 0);
    for (int y = 0; y < v.height(); ++y)
      for (int x = 0; x < v.width(); ++x)
        for (int k = 0; k < v.channels(); ++k) ASSERT_TRUE(std::isfinite(v.at(x, y, k))) << na << " " << k;
    const Texture f = bake_directional_channels(flat, 4, na, 0);
    for (int k = 0; k < dir::kPoly2Terms; ++k)
      EXPECT_NEAR(f.at(3, 3, k), k == 3 ? 1.0f : 0.0f, 1e-4f) << na << " " << k;
  }
}

// The view correction on relief: whole-texture (the box mean of every texel), at the study's lights and
// camera (60°, looking along +v), directional_view_transport on the mean channels against the exact
// projected-area mean E[f (n · v)/(n_z v_z)] computed here from exact_diffuse_transport, and against the
// camera-weighted value with masking, Σ f w / Σ w, w = vis_v (n · v)⁺/n_z; T alone (the 9 channels) is
// farther from the latter on average. A flat field has zero slope channels.
TEST(DirectionalView, SlopeChannelsCorrectTheViewOnRelief) {
  const Texture flat = depth_field(16, 16, 4, [](int, int) { return -1.0; });
  const Texture fz = bake_directional_slope_channels(flat, 4, 32, 0);
  for (int k = 0; k < dir::kSlopeChannels; ++k) EXPECT_NEAR(fz.at(5, 9, k), 0.0f, 1e-6f) << k;

  const TextureSet s = texture_set("gravel", 64);
  const int N = 64;
  const Texture c9 = box_downsample(bake_directional_channels(s.height, s.depth_texels, 32, 0), N);
  const Texture c12 = box_downsample(bake_directional_slope_channels(s.height, s.depth_texels, 32, 0), N);
  float c[9], gs[dir::kSlopeChannels];
  for (int k = 0; k < 9; ++k) c[k] = c9.at(0, 0, k);
  for (int k = 0; k < dir::kSlopeChannels; ++k) gs[k] = c12.at(0, 0, k);
  const HeightField hf(s.height, s.depth_texels);
  const double ve = 60 * kPiD / 180;
  const Vec3f v(0.0f, float(-std::cos(ve)), float(std::sin(ve)));
  // Masking toward the camera: lit toward v (the exact transport's lit test at v, n · v > 0 there).
  const Texture seen = exact_diffuse_transport(s.height, s.depth_texels, v, 0);
  double err_view = 0, err_t = 0, max_b = 0;
  int count = 0;
  for (double e : {5.0, 10.0, 25.0, 45.0, 70.0})
    for (double az : {0.0, 90.0}) {
      const Vec3f l = light(e, az);
      const Texture t = exact_diffuse_transport(s.height, s.depth_texels, l, 0);
      double sb = 0, sfw = 0, sw = 0;
      for (int y = 0; y < N; ++y)
        for (int x = 0; x < N; ++x) {
          const Vec3f n = hf.vertex_normal(x, y);
          const double f = t.at(x, y, 0), nv = dot(n, v);
          sb += f * nv / (n.z * v.z);
          const double wv = seen.at(x, y, 0) > 0 ? std::max(nv, 0.0) / n.z : 0.0;
          sfw += f * wv, sw += wv;
        }
      const double b = sb / (N * N), gt = sfw / sw;
      const double fitted = dir::directional_view_transport(c, gs, l, v);
      // The degree-2 fits of T and G against the exact b: within the fits' error (measured 2026-12-02 on
      // this field: max 0.047; the probe's 512² fields: 0.002–0.048 mean per material).
      max_b = std::max(max_b, std::abs(fitted / b - 1));
      err_view += std::abs(fitted / gt - 1), err_t += std::abs(dir::directional_transport(c, l) / gt - 1);
      ++count;
    }
  std::printf("gravel 64²: max |fitted/b - 1| %.3f; mean |ratio - 1| to the camera: corrected %.3f, T %.3f\n",
              max_b, err_view / count, err_t / count);
  EXPECT_LT(err_view, 0.5 * err_t);
  EXPECT_LT(max_b, 0.1);
}

// The run-time storage of the channels (store_directional_channels): float untouched; 8-bit UNORM the
// rounding of (x − lo)/(hi − lo) to 1/255 decoded by decode_unorm8; BC4 within its per-block bound
// (io/bc4.h: ≤ 4 b, b = max(0.5, (255 · block span + 1) / 14) / 255 of the range) and, on average, within the
// mean of b (a rounding to a grid of step 2 b errs by b/2 on average); ranges are per channel.
TEST(DirectionalStorage, FloatUnorm8AndBc4AsAnEngineReadsThem) {
  const TextureSet s = texture_set("gravel", 64);
  const Texture fine = bake_directional_view_channels(s.height, s.depth_texels, 32, 0);
  const ChannelRanges r = channel_ranges(fine);
  const Texture coarse = box_downsample(fine, 4);  // 16², every value inside the fine ranges
  Texture f = coarse, u8 = coarse, bc = coarse;
  store_directional_channels(f, r, DirectionalEncoding::Float);
  store_directional_channels(u8, r, DirectionalEncoding::Unorm8);
  store_directional_channels(bc, r, DirectionalEncoding::Bc4);
  double e8 = 0, ebc = 0, eb = 0;
  for (int c = 0; c < coarse.channels(); ++c) {
    const double lo = r.lo[std::size_t(c)], span = r.hi[std::size_t(c)] - lo;
    for (int by = 0; by < 4; ++by)
      for (int bx = 0; bx < 4; ++bx) {
        double bmin = 1e30, bmax = -1e30;
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i) {
            const double x = coarse.at(4 * bx + i, 4 * by + j, c);
            bmin = std::min(bmin, x), bmax = std::max(bmax, x);
          }
        const double b = std::max(0.5, (255 * (bmax - bmin) / span + 1) / 14) / 255 * span;
        for (int j = 0; j < 4; ++j)
          for (int i = 0; i < 4; ++i) {
            const int x = 4 * bx + i, y = 4 * by + j;
            const double v = coarse.at(x, y, c);
            ASSERT_EQ(f.at(x, y, c), coarse.at(x, y, c));
            const double q = std::round((v - lo) / span * 255) / 255;
            ASSERT_NEAR(u8.at(x, y, c), lo + span * q, 1e-6 * span) << c;
            ASSERT_LE(std::abs(bc.at(x, y, c) - v), 4 * b + 1e-6 * span) << c << " " << x << "," << y;
            e8 += std::abs(u8.at(x, y, c) - v) / span, ebc += std::abs(bc.at(x, y, c) - v) / span;
            eb += b / span;
          }
      }
  }
  const double n = double(coarse.channels()) * 256;
  std::printf(
      "gravel 64² → 16², 21 channels: mean |error| / range: unorm8 %.5f, bc4 %.5f (mean bound %.5f)\n",
      e8 / n, ebc / n, eb / n);
  EXPECT_LT(e8 / n, 0.5 / 255 * 1.01);  // rounding: at most half a step, about a quarter on average
  EXPECT_LT(ebc, eb);
  Texture bad = coarse;
  EXPECT_THROW(store_directional_channels(bad, ChannelRanges{{0.f}, {1.f}}, DirectionalEncoding::Bc4),
               InputError);
  EXPECT_THROW(directional_encoding_from_name("bc7"), InputError);
  for (auto e : {DirectionalEncoding::Float, DirectionalEncoding::Unorm8, DirectionalEncoding::Bc4})
    EXPECT_EQ(directional_encoding_from_name(directional_encoding_name(e)), e);
}

// Linearity, the point of the representation: the reconstruction (before its clamp) of the box-mean
// channels is the box mean of the per-texel reconstructions, at any direction; and the mip chain is the box
// means.
TEST(DirectionalPoly2, BoxMeanOfChannelsIsMeanOfReconstructions) {
  const TextureSet s = texture_set("bark", 32);
  const Texture ch = bake_directional_channels(s.height, s.depth_texels, 16, 0);
  const Texture c8 = box_downsample(ch, 8);
  const auto chain = box_mip_chain(ch);
  for (double e : {4.0, 13.7, 52.0})
    for (double az : {17.0, 200.0}) {
      const Vec3d l(light(e, az));
      double b[9];
      dir::poly2_basis(l, b);
      for (int J = 0; J < 4; ++J)
        for (int I = 0; I < 4; ++I) {
          double fine = 0, coarse = 0, mip = 0;
          for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 8; ++i)
              for (int k = 0; k < 9; ++k) fine += b[k] * ch.at(I * 8 + i, J * 8 + j, k) / 64.0;
          for (int k = 0; k < 9; ++k) coarse += b[k] * c8.at(I, J, k), mip += b[k] * chain[3].at(I, J, k);
          EXPECT_NEAR(coarse, fine, 1e-5);
          EXPECT_NEAR(mip, fine, 1e-5);
        }
    }
}

// Accuracy at a continuous light (azimuth and elevation off every grid): the whole-texture transport of the
// representation against the exact one, bark and gravel at 128², k = 1 and 16 (measured 2026-12-02 with the
// lattice azimuths: 0.967–1.050 over these 12 cases; the bound 0.08 leaves room for float rounding, not for
// a regression of the fit).
TEST(DirectionalPoly2, WholeTextureBiasAtContinuousLights) {
  for (const char* kind : {"bark", "gravel"}) {
    const TextureSet s = texture_set(kind, 128);
    const Texture ch = bake_directional_channels(s.height, s.depth_texels, 32, 0);
    for (int k : {1, 16}) {
      const Texture ck = box_downsample(ch, k);
      for (auto [e, az] : {std::pair{7.3, 31.0}, std::pair{18.0, 121.0}, std::pair{60.5, 250.0}}) {
        const Vec3f l = light(e, az);
        const Texture t = exact_diffuse_transport(s.height, s.depth_texels, l, 0);
        double st = 0, sa = 0;
        for (int j = 0; j < t.height(); ++j)
          for (int i = 0; i < t.width(); ++i) st += t.at(i, j, 0);
        float c[9];
        for (int J = 0; J < ck.height(); ++J)
          for (int I = 0; I < ck.width(); ++I) {
            for (int q = 0; q < 9; ++q) c[q] = ck.at(I, J, q);
            sa += dir::directional_transport(c, l) * double(k) * k;
          }
        EXPECT_NEAR(sa / st, 1.0, 0.08) << kind << " k " << k << " e " << e << " az " << az;
        std::printf("%s k=%d e=%.1f az=%.0f: bias %.4f\n", kind, k, e, az, sa / st);
      }
    }
  }
}

// The masked view correction (directional_view_masked_transport; measured in the renderer, not the shipped
// form: docs/study.md "Grazing views"). R(m, s) = E[(m + s Z)⁺] against a Simpson quadrature of the normal
// density; the seen area R(v_z, s) against a Monte Carlo of Gaussian slopes (the projected area of a facet of
// slope p is v_z − p · v_h); s = 0 gives the unclamped form T + g/v_z; a uniformly lit material (f = t₀ on
// every facet: T = t₀, G = 0) gives t₀ at every view; finite at v_z ≤ 0 and with a negative Σ.
TEST(DirectionalViewMasked, RampMeanMatchesQuadrature) {
  for (double m : {-2.0, -0.3, 0.0, 0.17, 1.5})
    for (double s : {0.05, 0.4, 1.0, 3.0}) {
      // The integrand is smooth from its kink z₀ = −m/s up: Simpson over [z₀, z₀ + 40].
      const int n = 20000;
      const double lo = -m / s, hi = lo + 40, h = (hi - lo) / n;
      double sum = 0;
      for (int i = 0; i <= n; ++i) {
        const double z = lo + i * h, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        sum += w * (m + s * z) * std::exp(-0.5 * z * z) / std::sqrt(2 * kPiD);
      }
      EXPECT_NEAR(dir::ramp_mean(m, s), sum * h / 3, 1e-9) << m << " " << s;
    }
  EXPECT_EQ(dir::ramp_mean(-0.5, 0.0), 0.0);
  EXPECT_EQ(dir::ramp_mean(0.5, 0.0), 0.5);
}

TEST(DirectionalViewMasked, SeenAreaIsSmithsForGaussianSlopes) {
  // Slopes p ~ N(0, Σ) with Σ = [[0.3, 0.1], [0.1, 0.2]]; Cholesky factor for sampling.
  const double sxx = 0.3, sxy = 0.1, syy = 0.2;
  const double l11 = std::sqrt(sxx), l21 = sxy / l11, l22 = std::sqrt(syy - l21 * l21);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> nd;
  for (double ve : {30.0, 60.0, 80.0}) {
    const double e = ve * kPiD / 180;  // elevation above the plane
    const Vec3d v(std::cos(e) * std::cos(0.7), std::cos(e) * std::sin(0.7), std::sin(e));
    const int n = 400000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
      const double z1 = nd(rng), z2 = nd(rng);
      const double px = l11 * z1, py = l21 * z1 + l22 * z2;
      const double a = std::max(v.z - (px * v.x + py * v.y), 0.0);
      sum += a, sum2 += a * a;
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    const double s = std::sqrt(sxx * v.x * v.x + 2 * sxy * v.x * v.y + syy * v.y * v.y);
    EXPECT_NEAR(dir::ramp_mean(v.z, s), mean, 4 * se) << ve;
    // A uniformly lit material: the form returns t₀ whatever the view and Σ.
    double ch[dir::kViewChannels] = {};
    ch[0] = 0.37;
    const double cov[3] = {sxx, sxy, syy};
    EXPECT_NEAR(dir::directional_view_masked_transport(ch, ch + 9, Vec3d(0.3, -0.2, 0.93), v, cov), 0.37,
                1e-12);
  }
}

TEST(DirectionalViewMasked, FlatSigmaIsTheUnclampedFormAndDegenerateInputsStayFinite) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-0.3f, 0.3f);
  float ch[dir::kViewChannels];
  for (float& c : ch) c = u(rng);
  ch[0] = 0.6f;
  const float zero[3] = {0, 0, 0}, neg[3] = {-1, 0, -1}, big[3] = {1e6f, 0, 1e6f};
  const Vec3f l = normalize(Vec3f(0.2f, 0.4f, 0.8f));
  for (float ve : {20.0f, 45.0f, 70.0f, 88.0f}) {
    const float e = ve * float(kPiD) / 180;
    const Vec3f v(0.3f * std::cos(e), -0.95f * std::cos(e), std::sin(e));
    const Vec3f vn = normalize(v);
    // s = 0: max(0, T + g / v_z) computed independently from the channels
    float b[9];
    dir::poly2_basis(l, b);
    float t = 0, gx = 0, gy = 0;
    for (int i = 0; i < 9; ++i) t += ch[i] * b[i];
    for (int i = 0; i < dir::kSlopeTerms; ++i) gx += ch[9 + i] * b[i], gy += ch[15 + i] * b[i];
    const float want = std::max(t + (gx * vn.x + gy * vn.y) / vn.z, 0.0f);
    EXPECT_NEAR(dir::directional_view_masked_transport(ch, ch + 9, l, vn, zero), want, 1e-5f * (1 + want))
        << ve;
    EXPECT_EQ(dir::directional_view_masked_transport(ch, ch + 9, l, vn, neg),
              dir::directional_view_masked_transport(ch, ch + 9, l, vn, zero));
    EXPECT_TRUE(std::isfinite(dir::directional_view_masked_transport(ch, ch + 9, l, vn, big)));
  }
  for (const Vec3f& v : {Vec3f(0, -1, 0), Vec3f(0.6f, 0, -0.8f)}) {
    const float r = dir::directional_view_masked_term(ch, l, v, Vec3f(0, 0, 1), zero);
    const float c[3] = {0.2f, 0.05f, 0.3f};
    const float rs = dir::directional_view_masked_term(ch, l, v, Vec3f(0, 0, 1), c);
    EXPECT_TRUE(std::isfinite(r) && r >= 0) << r;
    EXPECT_TRUE(std::isfinite(rs) && rs >= 0) << rs;
  }
  EXPECT_EQ(dir::directional_view_masked_transport(ch, ch + 9, Vec3f(0.6f, 0, -0.8f), Vec3f(0, 0, 1), zero),
            0.0f);
}

// slope_covariance: a constant tilted normal n gives n_h n_hᵀ / n_z²; a sinusoidal height field z = A sin(2π
// x / P) gives Σ_xx = E[n_x²]/E[n_z²] from its closed-form slopes, Σ_xy = Σ_yy = 0.
TEST(DirectionalViewMasked, SlopeCovarianceOfKnownNormalMaps) {
  Texture t(8, 8, 3);
  const Vec3d n = normalize(Vec3d(0.3, -0.2, 0.9));
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i)
      t.at(i, j, 0) = float(0.5 * n.x + 0.5), t.at(i, j, 1) = float(0.5 * n.y + 0.5),
                 t.at(i, j, 2) = float(0.5 * n.z + 0.5);
  const auto s = slope_covariance(t);
  EXPECT_NEAR(s[0], n.x * n.x / (n.z * n.z), 1e-5);
  EXPECT_NEAR(s[1], n.x * n.y / (n.z * n.z), 1e-5);
  EXPECT_NEAR(s[2], n.y * n.y / (n.z * n.z), 1e-5);
  Texture w(64, 4, 3);
  double xx = 0, zz = 0;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 64; ++i) {
      const double p = 0.8 * std::cos(2 * kPiD * (i + 0.5) / 64), r = std::sqrt(1 + p * p);
      w.at(i, j, 0) = float(0.5 * (-p / r) + 0.5), w.at(i, j, 1) = 0.5f, w.at(i, j, 2) = float(0.5 / r + 0.5);
      xx += p * p / (r * r), zz += 1 / (r * r);
    }
  const auto sw = slope_covariance(w);
  EXPECT_NEAR(sw[0], xx / zz, 1e-5);
  EXPECT_NEAR(sw[1], 0.0, 1e-6);
  EXPECT_NEAR(sw[2], 0.0, 1e-6);
  EXPECT_THROW(slope_covariance(Texture(4, 4, 1)), InputError);
}
