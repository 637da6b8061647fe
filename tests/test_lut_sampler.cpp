// Tests of the runtime LUT sampler (lut/micro_shadowing_lut.h): GPU texel addressing, trilinear filtering,
// roughness interpolation, the early-out, the azimuth-aware reconstruction, and the accuracy of the default
// tables against the exact term (occlusion/micro_shadowing.h) at random off-grid configurations.
#include <gtest/gtest.h>
#include <microshadow/lut/micro_shadowing_baker.h>
#include <microshadow/lut/micro_shadowing_loader.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>

#include <cmath>
#include <limits>
#include <vector>

namespace msh::lut {
namespace {

// A table whose channel c holds f_c(V, N·L, N·V) = k0 + k1 V + k2 N·L + k3 N·V + k4 V·N·L·N·V (multilinear).
struct SyntheticTable {
  io::Volume vol;
  std::vector<double> rough = {0.1, 0.4, 0.7, 1.0};
  static double f(int c, double V, double nl, double nv) {
    return 0.1 * c + 0.3 * V - 0.2 * nl + 0.25 * nv + 0.4 * V * nl * nv;
  }
  SyntheticTable(int nx, int ny, int nz, int slabs = 1) : vol(nx, ny, nz * slabs, 4) {
    for (int s = 0; s < slabs; ++s)
      for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
          for (int x = 0; x < nx; ++x)
            for (int c = 0; c < 4; ++c)
              vol.at(x, y, s * nz + z, c) = float(
                  f(c, double(x) / (nx - 1), double(y) / (ny - 1), nz > 1 ? double(z) / (nz - 1) : 1.0) + s);
  }
};

TEST(LutSampler, GpuTexelCoordinateHitsTexelCentres) {
  for (int n : {2, 3, 17, 64, 256})
    for (int i = 0; i < n; ++i)
      EXPECT_NEAR(gpu_texel_coord(float(i) / float(n - 1), n), float(i), 2e-4f * n) << n << " " << i;
  EXPECT_EQ(gpu_texel_coord(-1.0f, 8), 0.0f);  // clamped to the first texel
  EXPECT_NEAR(gpu_texel_coord(2.0f, 8), 7.0f, 1e-5f);
}

TEST(LutSampler, TrilinearReproducesMultilinearFunctions) {
  const SyntheticTable t(9, 7, 5);
  const MicroShadowingLutView view = make_view(t.vol, t.rough, 0);
  Pcg32 rng(1);
  for (int i = 0; i < 2000; ++i) {
    const double V = rng.next_double(), nl = rng.next_double(), nv = rng.next_double();
    const auto ch = fetch_trilinear<double>(view, V, nl, nv);
    for (int c = 0; c < 4; ++c) ASSERT_NEAR(ch[c], SyntheticTable::f(c, V, nl, nv), 1e-5) << V << " " << nl;
  }
}

TEST(LutSampler, RoughnessInterpolatesLinearlyAndClamps) {
  io::Volume vol(2, 2, 2, 4);
  const std::vector<double> rough = {0.1, 0.4, 0.7, 1.0};
  for (std::size_t i = 0; i < vol.data.size(); ++i) vol.data[i] = float(rough[i % 4]);  // channel value = r
  const MicroShadowingLutView view = make_view(vol, rough, 0);
  for (double r = -0.5; r <= 1.5; r += 0.01) {
    const double expect = std::clamp(r, 0.1, 1.0);
    EXPECT_NEAR(sample_micro_shadowing<double>(view, 1.0, 1.0, 0.5, r), expect, 1e-6) << r;
  }
  EXPECT_NEAR(sample_micro_shadowing<double>(view, 1.0, 1.0, 0.5, std::nan("")), 0.1, 1e-6);
  // Two channels and one channel.
  io::Volume v2(2, 2, 1, 2);
  for (std::size_t i = 0; i < v2.data.size(); ++i) v2.data[i] = i % 2 ? 0.8f : 0.2f;
  const MicroShadowingLutView view2 = make_view(v2, {0.25, 0.75}, 0);
  EXPECT_NEAR(sample_micro_shadowing<double>(view2, 1.0, 1.0, 1.0, 0.5), 0.5, 1e-6);
  io::Volume v1(2, 2, 1, 1);
  for (auto& x : v1.data) x = 0.3f;
  EXPECT_NEAR(sample_micro_shadowing<double>(make_view(v1, {0.5}, 0), 1.0, 1.0, 1.0, 0.9), 0.3, 1e-6);
}

TEST(LutSampler, EarlyOutReturnsZeroWithoutLookingAtTheTable) {
  io::Volume vol(4, 4, 4, 4);
  for (auto& x : vol.data) x = 1.0f;
  MicroShadowingLutView view = make_view(vol, {0.1, 0.4, 0.7, 1.0}, 0);
  EXPECT_EQ(sample_micro_shadowing<float>(view, 0.2f, 0.5f, 0.5f, 0.5f), 0.0f);  // 2V + N·L = 0.9 < 1
  EXPECT_EQ(sample_micro_shadowing<float>(view, 0.3f, 0.5f, 0.5f, 0.5f), 1.0f);  // 1.1 ≥ 1: fetched
  view.data = nullptr;                                                           // a fetch would crash
  EXPECT_EQ(sample_micro_shadowing<float>(view, 0.1f, 0.7f, 0.5f, 0.5f), 0.0f);
  EXPECT_EQ(sample_micro_shadowing_azimuth<float>(view, 0.1f, 0.7f, 0.5f, 0.5f, -1.0f), 0.0f);
}

TEST(LutSampler, DegenerateInputsStayFinite) {
  const SyntheticTable t(5, 5, 5);
  const MicroShadowingLutView view = make_view(t.vol, t.rough, 0);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  for (float a : {nan, inf, -inf, -1.0f, 0.0f, 1.0f, 2.0f})
    for (float b : {nan, inf, -inf, 0.0f, 1.0f}) {
      const float r1 = sample_micro_shadowing<float>(view, a, b, a, b);
      const float r2 = sample_micro_shadowing_azimuth<float>(view, b, a, a, b, a);
      EXPECT_TRUE(std::isfinite(r1) && r1 >= 0.0f && r1 <= 1.0f);
      EXPECT_TRUE(std::isfinite(r2) && r2 >= 0.0f && r2 <= 1.0f);
    }
}

TEST(LutSampler, AzimuthSlabsCombineAsCosineSeries) {
  io::Volume vol(2, 2, 6, 4);  // n_nv = 2, harmonics = 2: slabs a0, a1, a2 constant
  const float a[3] = {0.5f, 0.3f, -0.15f};
  for (int z = 0; z < 6; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x)
        for (int c = 0; c < 4; ++c) vol.at(x, y, z, c) = a[z / 2];
  const MicroShadowingLutView view = make_view(vol, {0.1, 0.4, 0.7, 1.0}, 2);
  for (double phi = 0; phi <= kPi<double>; phi += 0.05) {
    const double expect = std::clamp(a[0] + a[1] * std::cos(phi) + a[2] * std::cos(2 * phi), 0.0, 1.0);
    EXPECT_NEAR(sample_micro_shadowing_azimuth<double>(view, 0.9, 0.9, 0.5, 0.5, std::cos(phi)), expect,
                1e-6);
  }
  // The plain sampler reads slab 0 only.
  EXPECT_NEAR(sample_micro_shadowing<double>(view, 0.9, 0.9, 0.5, 0.5), 0.5, 1e-6);
}

TEST(LutSampler, RelativeAzimuthCosine) {
  EXPECT_NEAR(relative_azimuth_cos(Vec3d(1, 0, 1), Vec3d(-2, 0, 1)), -1.0, 1e-12);
  EXPECT_NEAR(relative_azimuth_cos(Vec3d(1, 0, 1), Vec3d(0, 3, 1)), 0.0, 1e-12);
  EXPECT_NEAR(relative_azimuth_cos(Vec3d(1, 1, 0.2), Vec3d(1, 0, 0.7)), std::sqrt(0.5), 1e-12);
  EXPECT_EQ(relative_azimuth_cos(Vec3d(0, 0, 1), Vec3d(1, 0, 0)), 1.0);  // at the pole φ is irrelevant
  EXPECT_EQ(relative_azimuth_cos(Vec3d(0, 0, 0), Vec3d(0, 0, 0)), 1.0);
}

// The default tables against the exact term at random (v, l, V) with roughness at the channel values.
struct Errors {
  double sum_abs = 0, sum_sq = 0, max_abs = 0;
  int n = 0;
  void add(double e) {
    sum_abs += std::abs(e), sum_sq += e * e, max_abs = std::max(max_abs, std::abs(e)), ++n;
  }
  double mean() const { return sum_abs / n; }
  double rms() const { return std::sqrt(sum_sq / n); }
};

TEST(LutSampler, AzimuthAwareTableCutsAzimuthErrorFourfold) {
  // One bake: slab 0 of the azimuth-aware table is the plain LUT (same bake, same values), and the plain
  // sampler reads slab 0 only.
  const auto azim = default_micro_shadowing_lut(false, 2);
  const MicroShadowingLutView va = azim->view();
  Pcg32 rng(31);
  Errors ep, ea, ep_rough, ea_rough;
  while (ep.n < 1500) {
    const double r = kDefaultRoughness[ep.n % 4], a = r * r, V = rng.next_double();
    const Vec3d v = sample_uniform_hemisphere<double>({rng.next_double(), rng.next_double()});
    const Vec3d l = sample_uniform_hemisphere<double>({rng.next_double(), rng.next_double()});
    const double exact = ms::generic_vndf_exact(V, a, a, v, l);
    const double cphi = relative_azimuth_cos(v, l);
    const double e0 = sample_micro_shadowing<double>(va, V, l.z, v.z, r) - exact;
    const double e2 = sample_micro_shadowing_azimuth<double>(va, V, l.z, v.z, r, cphi) - exact;
    ep.add(e0), ea.add(e2);
    if (r >= 0.4) ep_rough.add(e0), ea_rough.add(e2);
  }
  RecordProperty("plain_mean_abs", std::to_string(ep.mean()));
  RecordProperty("azimuth_mean_abs", std::to_string(ea.mean()));
  EXPECT_GE(ep.mean(), 4.0 * ea.mean()) << "plain " << ep.mean() << " azimuth-aware " << ea.mean();
  // RMS for roughness ≥ 0.4; at roughness 0.1 both are limited by the 64-texel resolution of the sharp step.
  EXPECT_GE(ep_rough.rms(), 4.0 * ea_rough.rms())
      << "plain " << ep_rough.rms() << " azimuth " << ea_rough.rms();
  // And the plain table is a good approximation of the azimuth mean it stores.
  EXPECT_LT(ep.mean(), 0.05);
}

}  // namespace
}  // namespace msh::lut
