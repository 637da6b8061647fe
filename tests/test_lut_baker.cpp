// Tests of the micro-shadowing LUT baker against independent references: the exact quadrature of
// occlusion/micro_shadowing.h (closed-form denominator, Gauss-Kronrod numerator; written by another module)
// and the semi-analytic ring integration of reference/micro_shadowing_ring.h (checked against it here).
#include <gtest/gtest.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/reference/micro_shadowing_ring.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace msh::lut {
namespace {

constexpr double kTol = 0.5 / 255.0;  // the documented accuracy of the default bake at every texel (docs/lut.md)

double texel_value(int i, int n) { return double(i) / (n - 1); }

// The default 64³ × 4 bake, shared by the tests that need it.
const io::Volume& default_bake() {
  static const io::Volume vol = bake_micro_shadowing_lut(BakeOptions{});
  return vol;
}

// docs/lut.md's every-texel figure for this bake (`BM_LutVerifyAllTexels`, all 1,048,576 texels, so no
// sampling error: any subset's max is below it): max |error| 1.445e-3 against the semi-analytic exact mean,
// plus 5e-5 for this test's reference (micro_shadowing::generic_vndf_exact_azimuth_mean agrees with the
// semi-analytic one within 5e-5 on random configurations, 1.3e-5 on texel means): 1.5e-3 = 0.38/255
// (measured here: 3.8e-4).
constexpr double kSeedMax = 1.445e-3 + 5e-5;

TEST(LutBaker, DefaultBakeWithinHalfLsbOfExactOnRandomTexels) {
  const io::Volume& vol = default_bake();
  const BakeOptions o;
  ASSERT_EQ(vol.width, 64);
  ASSERT_EQ(vol.height, 64);
  ASSERT_EQ(vol.depth, 64);
  ASSERT_EQ(vol.channels, 4);
  Pcg32 rng(2024);
  double worst = 0.0;
  int checked = 0;
  while (checked < 500) {
    const int x = int(rng.next_u32() % 64), y = int(rng.next_u32() % 64), z = int(rng.next_u32() % 64);
    const int c = int(rng.next_u32() % 4);
    const double V = texel_value(x, 64), nl = texel_value(y, 64), nv = texel_value(z, 64);
    if (x == 0 || x == 63 || 2 * V + nl < 1) continue;  // exact by construction, tested below
    const double r = o.roughness[c];
    const double exact = micro_shadowing::generic_vndf_exact_azimuth_mean(V, r * r, nl, nv);
    const double err = std::abs(double(vol.at(x, y, z, c)) - exact);
    worst = std::max(worst, err);
    EXPECT_LE(err, kSeedMax) << "texel (" << x << "," << y << "," << z << ") roughness " << r << " lut "
                             << vol.at(x, y, z, c) << " exact " << exact;
    ++checked;
  }
  RecordProperty("max_abs_error", std::to_string(worst));
}

TEST(LutBaker, ExactTexelsAreExact) {
  const io::Volume& vol = default_bake();
  for (int c = 0; c < 4; ++c)
    for (int z = 0; z < 64; ++z)
      for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
          const double V = texel_value(x, 64), nl = texel_value(y, 64);
          const float v = vol.at(x, y, z, c);
          if (x == 63)
            ASSERT_EQ(v, 1.0f);  // V = 1: the cone is the hemisphere
          else if (x == 0 || 2 * V + nl < 1)
            ASSERT_EQ(v, 0.0f);  // V = 0 and the early-out region
          else
            ASSERT_TRUE(v >= 0.0f && v <= 1.0f);
        }
}

TEST(LutBaker, MonotoneInVisibilityUpToNoise) {
  // More visibility never shadows more: the cone region grows with V. Allow the QMC noise level.
  const io::Volume& vol = default_bake();
  for (int c = 0; c < 4; ++c)
    for (int z = 0; z < 64; z += 7)
      for (int y = 0; y < 64; ++y)
        for (int x = 1; x < 64; ++x) ASSERT_GE(vol.at(x, y, z, c), vol.at(x - 1, y, z, c) - 2e-3f);
}

TEST(LutBaker, BitIdenticalForAnyThreadCount) {
  BakeOptions o;
  o.n_vis = 17, o.n_nl = 9, o.n_nv = 5, o.samples = 512, o.phi_nodes = 4, o.harmonics = 2;
  o.threads = 1;
  const io::Volume a = bake_micro_shadowing_lut(o);
  o.threads = 2;
  const io::Volume b = bake_micro_shadowing_lut(o);
  o.threads = 0;
  const io::Volume c = bake_micro_shadowing_lut(o);
  ASSERT_EQ(a.data.size(), b.data.size());
  EXPECT_EQ(0, std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)));
  EXPECT_EQ(0, std::memcmp(a.data.data(), c.data.data(), a.data.size() * sizeof(float)));
}

TEST(LutBaker, TwoDLutIsTheNdotVOneSlice) {
  BakeOptions o;
  o.n_vis = 16, o.n_nl = 12, o.n_nv = 6, o.samples = 1024, o.phi_nodes = 4;
  const io::Volume v3 = bake_micro_shadowing_lut(o);
  o.two_d = true;
  const io::Volume v2 = bake_micro_shadowing_lut(o);
  ASSERT_EQ(v2.depth, 1);
  for (int c = 0; c < 4; ++c)
    for (int y = 0; y < 12; ++y)
      for (int x = 0; x < 16; ++x) ASSERT_EQ(v2.at(x, y, 0, c), v3.at(x, y, 5, c));
}

TEST(LutBaker, HarmonicSlabsMatchExactFourierCoefficients) {
  // a_0 = mean over φ, a_h = (2/π) ∫_0^π term(φ) cos(hφ) dφ, from the independent exact term at 48 Gauss
  // nodes.
  BakeOptions o;
  o.n_vis = 8, o.n_nl = 8, o.n_nv = 8, o.harmonics = 2;
  o.roughness = {0.4, 1.0};
  const io::Volume vol = bake_micro_shadowing_lut(o);
  ASSERT_EQ(vol.depth, 24);
  std::vector<double> phi, w;
  phi_rule(48, phi, w);
  double worst = 0;
  for (int c = 0; c < 2; ++c)
    for (int z : {0, 3, 7})
      for (int y : {2, 5, 7})
        for (int x : {3, 5, 6}) {
          const double V = texel_value(x, 8), nl = texel_value(y, 8), nv = texel_value(z, 8);
          const double a = o.roughness[c] * o.roughness[c];
          double coef[3] = {0, 0, 0};
          const Vec3d v(std::sqrt(1 - nv * nv), 0, nv);
          for (std::size_t k = 0; k < phi.size(); ++k) {
            const double sl = std::sqrt(1 - nl * nl);
            const Vec3d l(sl * std::cos(phi[k]), sl * std::sin(phi[k]), nl);
            const double t = micro_shadowing::generic_vndf_exact(V, a, a, v, l);
            for (int h = 0; h < 3; ++h) coef[h] += (h ? 2.0 : 1.0) * w[k] * t * std::cos(h * phi[k]);
          }
          for (int h = 0; h < 3; ++h) {
            const double got = vol.at(x, y, h * 8 + z, c);
            worst = std::max(worst, std::abs(got - coef[h]));
            EXPECT_NEAR(got, coef[h], h == 0 ? kTol : 2 * kTol)
                << "h=" << h << " texel " << x << "," << y << "," << z << " r=" << o.roughness[c];
          }
        }
  RecordProperty("max_abs_error", std::to_string(worst));
}

TEST(LutBaker, PhiRuleIntegratesPolynomialsExactly) {
  for (int n : {1, 4, 16}) {
    std::vector<double> phi, w;
    phi_rule(n, phi, w);
    for (int k = 0; k < 2 * n; ++k) {
      double s = 0;
      for (int i = 0; i < n; ++i) s += w[i] * std::pow(phi[i], k);
      const double exact = std::pow(kPi<double>, k) / (k + 1);  // (1/π)∫_0^π φ^k dφ
      EXPECT_NEAR(s, exact, 1e-12 * std::max(1.0, exact)) << "n=" << n << " k=" << k;
    }
  }
}

TEST(LutExact, SemiAnalyticMatchesIndependentQuadrature) {
  Pcg32 rng(77);
  for (int i = 0; i < 300; ++i) {
    const double r = 0.05 + 0.95 * rng.next_double(), a = r * r;
    const double V = rng.next_double(), nl = i % 9 == 0 ? 0.0 : rng.next_double();
    const double nv = i % 5 == 0 ? 0.0 : rng.next_double(), phi = kPi<double> * rng.next_double();
    const double sl = std::sqrt(1 - nl * nl);
    const double ref = micro_shadowing::generic_vndf_exact(V, a, a, Vec3d(std::sqrt(1 - nv * nv), 0, nv),
                                                           Vec3d(sl * std::cos(phi), sl * std::sin(phi), nl));
    EXPECT_NEAR(micro_shadowing::micro_shadowing_semi_analytic(a, V, nl, nv, phi), ref, 5e-5)
        << "r=" << r << " V=" << V << " nl=" << nl << " nv=" << nv << " phi=" << phi;
  }
  for (int i = 0; i < 20; ++i) {
    const double r = 0.1 + 0.9 * rng.next_double(), a = r * r;
    const double V = 0.5 + 0.5 * rng.next_double(), nl = rng.next_double(), nv = rng.next_double();
    EXPECT_NEAR(micro_shadowing::micro_shadowing_semi_analytic_azimuth_mean(a, V, nl, nv),
                micro_shadowing::generic_vndf_exact_azimuth_mean(V, a, nl, nv), 5e-5);
  }
}

TEST(LutExact, RowMatchesPointwise) {
  std::vector<double> vis = {0.0, 0.2, 0.5, 0.7, 0.9, 0.99, 1.0}, out(vis.size());
  micro_shadowing::micro_shadowing_semi_analytic_row(0.3, 0.4, 0.6, vis.data(), int(vis.size()), out.data());
  for (std::size_t i = 0; i < vis.size(); ++i)
    EXPECT_NEAR(out[i], micro_shadowing::generic_vndf_exact_azimuth_mean(vis[i], 0.3, 0.4, 0.6), 5e-5)
        << vis[i];
}

TEST(LutBaker, StraightforwardMonteCarloTexelConverges) {
  // The seed's per-sample estimator (bench baseline): unbiased up to O(1/N), so within 5σ of the exact value.
  const double cases[][4] = {{0.16, 0.8, 0.7, 0.5}, {1.0, 0.9, 0.3, 0.2}, {0.49, 0.6, 0.5, 0.05}};
  for (const auto& t : cases) {
    const double exact = micro_shadowing::generic_vndf_exact_azimuth_mean(t[1], t[0], t[2], t[3]);
    const int n = 1 << 16;
    const double got = monte_carlo_texel(t[0], t[1], t[2], t[3], n, 16, 5);
    EXPECT_NEAR(got, exact, 5 * 0.5 / std::sqrt(0.5 * n)) << t[0] << " " << t[1];
  }
}

TEST(LutBaker, RejectsBadOptions) {
  auto bad = [](auto edit) {
    BakeOptions o;
    edit(o);
    EXPECT_THROW(validate(o), InputError);
  };
  bad([](BakeOptions& o) { o.n_vis = 1; });
  bad([](BakeOptions& o) { o.n_nl = 0; });
  bad([](BakeOptions& o) { o.n_nv = -3; });
  bad([](BakeOptions& o) { o.roughness = {}; });
  bad([](BakeOptions& o) { o.roughness = {0.1, 0.2, 0.3, 0.4, 0.5}; });
  bad([](BakeOptions& o) { o.roughness = {0.5, 0.4}; });
  bad([](BakeOptions& o) { o.roughness = {std::nan("")}; });
  bad([](BakeOptions& o) { o.roughness = {1.5}; });
  bad([](BakeOptions& o) { o.samples = 0; });
  bad([](BakeOptions& o) { o.phi_nodes = 0; });
  bad([](BakeOptions& o) { o.harmonics = -1; });
  bad([](BakeOptions& o) { o.threads = -1; });
  BakeOptions ok;
  ok.two_d = true, ok.n_nv = 0;  // N·V size is unused for the 2D LUT
  EXPECT_NO_THROW(validate(ok));
}

TEST(LutLoader, RoundTripWithSidecarAndDefaults) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(MSH_BINARY_DIR) / "lut_test_tmp" / std::to_string(::getpid());
  fs::create_directories(dir);
  BakeOptions o;
  o.n_vis = 8, o.n_nl = 6, o.n_nv = 4, o.samples = 256, o.phi_nodes = 2, o.harmonics = 1;
  o.roughness = {0.2, 0.9};
  const io::Volume vol = bake_micro_shadowing_lut(o);
  const fs::path p = dir / "t.npy";
  io::write_volume(p, vol, io::FileFormat::Npy, io::PixelFormat::RGBA32Float);
  EXPECT_THROW(load_micro_shadowing_lut(p), InputError);  // 2 channels, no sidecar, no roughness given
  io::write_file_atomic(sidecar_path(p), sidecar_json(o));
  const MicroShadowingLut lut = load_micro_shadowing_lut(p);
  EXPECT_EQ(lut.roughness, o.roughness);
  EXPECT_EQ(lut.harmonics, 1);
  const MicroShadowingLutView view = lut.view();
  EXPECT_EQ(view.n_nv, 4);
  EXPECT_EQ(view.channels, 2);
  EXPECT_EQ(lut.volume.data, vol.data);
  EXPECT_THROW(load_micro_shadowing_lut(p, std::vector<double>{0.1, 0.5, 0.9}), InputError);
  EXPECT_THROW(load_micro_shadowing_lut(p, std::nullopt, 2), InputError);  // depth 8 not a multiple of 3
  fs::remove_all(dir);
}

// ---- Cone layout ---------------------------------------------------------------------------------------

// The physical inputs of a cone-layout texel (the inverse maps of the sampler's coordinates).
struct ConeTexel {
  double V, nl, nv, r;
  bool past_one;  // past V = 1 (grazing light): the continuation, never sampled
};
ConeTexel cone_texel(const BakeOptions& o, int x, int y, int z, int slab) {
  const double r = cone_roughness_of_coord(o.cone, double(slab) / (o.n_rough - 1));
  const double nl = cone_axis_warp::axis_value(double(y) / (o.n_nl - 1), o.cone.nl_warp);
  const double nv = cone_nv_of_coord(o.cone, double(z) / (o.n_nv - 1), r);
  const float a = cone_warp_width(o.cone, float(r));
  const double theta = cone_theta_of_t(double(x) / (o.n_vis - 1), float(nl), a, o.cone.top_scale);
  return {cone_visibility_of_t(double(x) / (o.n_vis - 1), float(nl), a, o.cone.top_scale), nl, nv, r,
          theta > kPi<double> / 2};
}

const io::Volume& default_cone_bake() {
  static const io::Volume vol = bake_micro_shadowing_lut(default_bake_options());
  return vol;
}

TEST(LutBakerCone, DefaultBakeWithinHalfLsbOfExactOnRandomTexels) {
  const BakeOptions o = default_bake_options();
  const io::Volume& vol = default_cone_bake();
  ASSERT_EQ(o.layout, LutLayout::Cone);
  ASSERT_EQ(vol.width, o.n_vis);
  ASSERT_EQ(vol.depth, o.n_nv * o.n_rough);
  ASSERT_EQ(vol.channels, 1);
  Pcg32 rng(77);
  double worst = 0.0;
  for (int checked = 0; checked < 300;) {
    const int x = 1 + int(rng.next_u32() % (o.n_vis - 2)), y = int(rng.next_u32() % o.n_nl);
    const int z = int(rng.next_u32() % o.n_nv), l = int(rng.next_u32() % o.n_rough);
    const ConeTexel t = cone_texel(o, x, y, z, l);
    if (!(t.nv > 0.0) || t.past_one) continue;  // outside the sampled domain
    const double exact = micro_shadowing::generic_vndf_exact_azimuth_mean(t.V, t.r * t.r, t.nl, t.nv);
    const double err = std::abs(double(vol.at(x, y, l * o.n_nv + z, 0)) - exact);
    worst = std::max(worst, err);
    EXPECT_LE(err, kTol) << "texel (" << x << "," << y << "," << z << "," << l << ") V " << t.V << " N·L "
                         << t.nl << " N·V " << t.nv << " r " << t.r << " exact " << exact;
    ++checked;
  }
  RecordProperty("max_abs_error", std::to_string(worst));
}

TEST(LutBakerCone, EndColumnsAreExactAndTexelsSitInTheLitRange) {
  // (The sampler at V = 1 gives 1 within the bake noise: LutSamplerCone tests.)
  const BakeOptions o = default_bake_options();
  const io::Volume& vol = default_cone_bake();
  for (int z = 0; z < vol.depth; ++z)
    for (int y = 0; y < vol.height; ++y) {
      EXPECT_EQ(vol.at(0, y, z, 0), 0.0f);              // t = 0: the early-out boundary 2V + N·L = 1
      EXPECT_EQ(vol.at(vol.width - 1, y, z, 0), 1.0f);  // t = 1: just past V = 1, where the term is 1
    }
  // Every texel's cone half-angle lies in [θ_l/2, θ_l + π/2], increasing along x from the early-out
  // boundary; the axis reaches V = 1.
  for (int y = 0; y < o.n_nl; y += 3) {
    double prev = -1;
    const double nl = cone_axis_warp::axis_value(double(y) / (o.n_nl - 1), o.cone.nl_warp);
    const float a = cone_warp_width(o.cone, 0.3f);
    for (int x = 0; x < o.n_vis; ++x) {
      const double th = cone_theta_of_t(double(x) / (o.n_vis - 1), float(nl), a, o.cone.top_scale);
      EXPECT_GE(th, 0.5 * std::acos(float(nl)) - 1e-6);
      EXPECT_LE(th, std::acos(float(nl)) + kPi<double> / 2 + 1e-6);
      EXPECT_GT(th, prev);
      prev = th;
    }
    EXPECT_GE(prev, kPi<double> / 2 - 1e-6);
    EXPECT_NEAR(cone_theta_of_t(0.0, float(nl), a, o.cone.top_scale), 0.5 * std::acos(float(nl)), 1e-6);
  }
}

TEST(LutBakerCone, BitIdenticalForAnyThreadCountAndAzimuthSlabZeroIsThePlainTable) {
  BakeOptions o = default_bake_options();
  o.n_vis = 16, o.n_nl = 8, o.n_nv = 5, o.n_rough = 4, o.samples = 512, o.phi_nodes = 4;
  o.threads = 1;
  const io::Volume a = bake_micro_shadowing_lut(o);
  o.threads = 2;
  const io::Volume b = bake_micro_shadowing_lut(o);
  EXPECT_EQ(a.data, b.data);
  o.harmonics = 3;
  const io::Volume h = bake_micro_shadowing_lut(o);
  ASSERT_EQ(h.channels, 4);
  for (std::size_t i = 0; i < a.texel_count(); ++i) ASSERT_EQ(h.data[4 * i], a.data[i]);
}

TEST(LutBakerCone, ValidateRejectsBadConeOptions) {
  auto bad = [](auto edit) {
    BakeOptions o = default_bake_options();
    edit(o);
    EXPECT_THROW(validate(o), InputError);
  };
  bad([](BakeOptions& o) { o.n_rough = 1; });
  bad([](BakeOptions& o) { o.harmonics = 4; });
  bad([](BakeOptions& o) { o.cone.roughness_min = 0.0f; });
  bad([](BakeOptions& o) { o.cone.roughness_max = 0.05f; });
  bad([](BakeOptions& o) { o.cone.warp_scale = std::nanf(""); });
  bad([](BakeOptions& o) { o.cone.nl_warp = 3; });
  bad([](BakeOptions& o) { o.cone.nv_scale = 0.0f; });
  bad([](BakeOptions& o) { o.cone.roughness_power = -1.0f; });
  EXPECT_NO_THROW(validate(default_bake_options()));
}

TEST(LutLoader, ConeRoundTripWithSidecar) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(MSH_BINARY_DIR) / "lut_test_tmp" / ("cone" + std::to_string(::getpid()));
  fs::create_directories(dir);
  BakeOptions o = default_bake_options();
  o.n_vis = 8, o.n_nl = 6, o.n_nv = 4, o.n_rough = 3, o.samples = 128, o.phi_nodes = 2, o.harmonics = 1;
  o.cone.warp_scale = 1.5f, o.cone.roughness_min = 0.2f;
  const io::Volume vol = bake_micro_shadowing_lut(o);
  const fs::path p = dir / "t.npy";
  io::write_volume(p, vol, io::FileFormat::Npy, io::PixelFormat::RGBA32Float);
  EXPECT_THROW(load_micro_shadowing_lut(p), InputError);  // 2 channels, no sidecar
  io::write_file_atomic(sidecar_path(p), sidecar_json(o));
  const MicroShadowingLut lut = load_micro_shadowing_lut(p);
  EXPECT_EQ(lut.layout, LutLayout::Cone);
  EXPECT_EQ(lut.n_rough, 3);
  EXPECT_EQ(lut.harmonics, 1);
  EXPECT_EQ(lut.cone.warp_scale, 1.5f);
  EXPECT_EQ(lut.cone.roughness_min, 0.2f);
  const MicroShadowingLutView view = lut.view();
  EXPECT_EQ(view.layout, LutLayout::Cone);
  EXPECT_EQ(view.n_nv, 4);
  EXPECT_EQ(lut.volume.data, vol.data);
  EXPECT_THROW(load_micro_shadowing_lut(p, std::vector<double>{0.1, 0.5}), InputError);  // no channels
  EXPECT_THROW(load_micro_shadowing_lut(p, std::nullopt, 2), InputError);  // 2 channels hold H ≤ 1
  fs::remove_all(dir);
}

}  // namespace
}  // namespace msh::lut
