// msh::micro_shadowing::generic_vndf_alu and the two-stage generic_vndf_alu_pixel + generic_vndf_alu_light
// (include/microshadow/occlusion/micro_shadowing_fit.h) against the exact azimuth
// mean generic_vndf_exact_azimuth_mean at independent continuous random inputs (not the fit's training or
// validation points), its exact early-out and limits, and finiteness on degenerate inputs.
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

using namespace msh;

namespace {

struct Errors {
  double rms = 0, max = 0;
  double max_nv_001 = 0;  // max over the points with N·V >= 0.01 (the docs' exception lies below)
  double rms_se = 0;  // standard error of rms: SD(e²) / (2 rms √n), delta method on the mean of e²
  int above_p99 = 0;  // points with |e| > the p99 passed to measure()
  int above_8 = 0;    // points with |e| > 8/255
};

// Uniform random inputs over the documented domain (V ∈ [0,1], N·L, N·V ∈ (0,1], r ∈ [0.1, 1]), early-out
// region included, as `plot micro-shadowing-fit` and docs/micro-shadowing.md measure it.
template <class F>
Errors measure(F term, int n, uint64_t seed, double p99 = 1) {
  Pcg32 rng(seed, 77);
  double ss = 0, s4 = 0, mx = 0;
  Errors out;
  for (int i = 0; i < n; ++i) {
    const double V = rng.next_double(), nl = 1 - rng.next_double(), nv = 1 - rng.next_double();
    const double r = 0.1 + 0.9 * rng.next_double();
    const double e =
        std::abs(term(V, nl, nv, r) - micro_shadowing::generic_vndf_exact_azimuth_mean(V, r * r, nl, nv));
    ss += e * e, s4 += e * e * e * e, mx = std::max(mx, e);
    if (nv >= 0.01) out.max_nv_001 = std::max(out.max_nv_001, e);
    out.above_p99 += e > p99, out.above_8 += e > 8.0 / 255;
  }
  const double m2 = ss / n;
  out.rms = std::sqrt(m2), out.max = mx;
  out.rms_se = m2 > 0 ? std::sqrt(std::max(0.0, s4 / n - m2 * m2) / n) / (2 * out.rms) : 0;
  return out;
}

}  // namespace

// Bounds: the targets (RMS ≤ 2/255, max ≤ 8/255), or docs/micro-shadowing.md's "Measured error" table
// (`plot micro-shadowing-fit --samples 20000 --seed 3`, the same uniform domain, early-out included; RMS / p99
// / max in 1/255: two-stage 0.95 / 3.2 / 9.0, one-call 4.19 / 16.6 / 36.6) with a margin stated from the
// sampling error of these 400 points, never a measured value itself:
// - RMS: documented + 3 standard errors of the 400-point RMS, SE = SD(e²) / (2 RMS √400) from the
//   sample's own moments (measured: two-stage RMS 0.94, SE 0.08; one-call 4.05, SE 0.30); the two-stage
//   form also at the 2/255 target;
// - p99: the count above the documented p99 is Binomial(400, 0.01): mean 4, SD 1.99, asserted ≤ 4 + 3 SD = 9;
//   this bounds the tail of both forms (a sample max has no such margin: no bound on it alone);
// - max ≤ 8/255, the target, for the two-stage form wherever N·V ≥ 0.01. Below that the target is NOT met
//   (9.0/255; 2 of the 20,000 points above 8/255, both at N·V < 0.01, as the docs state), so there the test
//   asserts the documented fraction above 8/255: 1e-4, a count ~ Poisson(0.04) here, asserted ≤ 1
//   (P(≥ 2) = 8e-4). The one-call form meets neither error target (documented). Both must be several times
//   better than the best older closed-form term on the same points (Brinck-Maximov 2016 and the reference
//   step, RMS 50-60/255 here).
TEST(MicroShadowingFit, AccuracyAgainstExactAzimuthMean) {
  const int n = 400;
  const Errors fast = measure(
      [](double V, double nl, double nv, double r) {
        return double(micro_shadowing::generic_vndf_alu(float(V), float(nl), float(nv), float(r)));
      },
      n, 4242, 16.6 / 255);
  const Errors two = measure(
      [](double V, double nl, double nv, double r) {
        const auto px = micro_shadowing::generic_vndf_alu_pixel(float(V), float(nv), float(r));
        return double(micro_shadowing::generic_vndf_alu_light(px, float(nl)));
      },
      n, 4242, 3.2 / 255);
  const Errors bm =
      measure([](double V, double nl, double, double) { return micro_shadowing::brinck_maximov_2016(V, nl); },
              n, 4242);
  const Errors ref = measure(
      [](double V, double nl, double, double) { return micro_shadowing::reference_step(V, nl); }, n, 4242);
  std::printf(
      "[ alu ] %d points: one-call RMS %.2f/255 (SE %.2f) max %.2f/255 above p99 %d; two-stage RMS %.2f/255 "
      "(SE %.2f) max %.2f/255 above p99 %d above 8/255 %d (Brinck-Maximov %.1f / %.1f, reference %.1f / "
      "%.1f)\n",
      n, 255 * fast.rms, 255 * fast.rms_se, 255 * fast.max, fast.above_p99, 255 * two.rms, 255 * two.rms_se,
      255 * two.max, two.above_p99, two.above_8, 255 * bm.rms, 255 * bm.max, 255 * ref.rms, 255 * ref.max);
  const int above_p99_bound = int(std::floor(n * 0.01 + 3 * std::sqrt(n * 0.01 * 0.99)));  // 9
  EXPECT_LE(two.rms, 0.95 / 255 + 3 * two.rms_se);
  EXPECT_LE(two.rms, 2.0 / 255);
  EXPECT_LE(two.above_p99, above_p99_bound);
  EXPECT_LE(two.max_nv_001, 8.0 / 255);
  EXPECT_LE(two.above_8, 1);
  EXPECT_LE(fast.rms, 4.19 / 255 + 3 * fast.rms_se);
  EXPECT_LE(fast.above_p99, above_p99_bound);
  EXPECT_LT(fast.rms, std::min(bm.rms, ref.rms) / 5);
  EXPECT_LT(two.rms, fast.rms);
}

// α → 0 is the reference step (the S terms become sign functions); checked away from the step itself,
// and against the exact term there (tiny roughness: both are the step).
TEST(MicroShadowingFit, SmallRoughnessIsTheReferenceStep) {
  Pcg32 rng(5, 5);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const float V = rng.next_float(), nl = 1 - rng.next_float(), nv = 1 - rng.next_float();
    if (std::abs(nl - std::sqrt(1 - V)) < 0.02f || micro_shadowing::exact_zero(V, nl)) continue;
    EXPECT_NEAR(micro_shadowing::generic_vndf_alu(V, nl, nv, 0.0f), micro_shadowing::reference_step(V, nl),
                1e-3)
        << V << " " << nl;
    EXPECT_NEAR(micro_shadowing::generic_vndf_alu_two_stage(V, nl, nv, 0.0f),
                micro_shadowing::reference_step(V, nl), 1e-3)
        << V << " " << nl;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(MicroShadowingFit, ExactEarlyOutAndLimits) {
  Pcg32 rng(11, 3);
  for (int i = 0; i < 4000; ++i) {
    const float V = rng.next_float(), nl = 1 - rng.next_float(), nv = 1 - rng.next_float();
    const float r = rng.next_float();
    if (micro_shadowing::exact_zero(V, nl)) {
      EXPECT_EQ(micro_shadowing::generic_vndf_alu(V, nl, nv, r), 0.0f);
      EXPECT_EQ(micro_shadowing::generic_vndf_alu_two_stage(V, nl, nv, r), 0.0f);
    }
    EXPECT_EQ(micro_shadowing::generic_vndf_alu_two_stage(0.0f, nl, nv, r), 0.0f);
    EXPECT_EQ(micro_shadowing::generic_vndf_alu_two_stage(1.0f, nl, nv, r), 1.0f);
    EXPECT_EQ(micro_shadowing::generic_vndf_alu(0.0f, nl, nv, r), 0.0f);  // V = 0: no visible cone
    EXPECT_EQ(micro_shadowing::generic_vndf_alu(1.0f, nl, nv, r), 1.0f);  // V = 1: the whole hemisphere
    EXPECT_EQ(micro_shadowing::generic_vndf_alu(0.0, double(nl), double(nv), double(r)), 0.0);
    EXPECT_EQ(micro_shadowing::generic_vndf_alu(1.0, double(nl), double(nv), double(r)), 1.0);
    // On the early-out boundary the exact term is 0 too; the fit must be small there (within its max).
    const float b = std::max(0.0f, 1.0f - 2.0f * V);
    if (b > 0) {
      EXPECT_LE(micro_shadowing::generic_vndf_alu(V, b, nv, r), 40.0f / 255) << V << " " << nv << " " << r;
      EXPECT_LE(micro_shadowing::generic_vndf_alu_two_stage(V, b, nv, r), 12.0f / 255)
          << V << " " << nv << " " << r;
    }
  }
}

TEST(MicroShadowingFit, FiniteOnDegenerateInputs) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float vals[] = {nan, inf, -inf, -1.0f, 0.0f, 1e-38f, 1e-7f, 0.5f, 1.0f, 2.0f};
  for (float V : vals)
    for (float nl : vals)
      for (float nv : vals)
        for (float r : vals) {
          const float f = micro_shadowing::generic_vndf_alu(V, nl, nv, r),
                      f2 = micro_shadowing::generic_vndf_alu_two_stage(V, nl, nv, r);
          ASSERT_TRUE(f >= 0.0f && f <= 1.0f) << V << " " << nl << " " << nv << " " << r << " -> " << f;
          ASSERT_TRUE(f2 >= 0.0f && f2 <= 1.0f) << V << " " << nl << " " << nv << " " << r << " -> " << f2;
          // Inputs are clamped: the value equals the one at the clamped inputs (NaN → 0; roughness: 0.01).
          auto sat = [](float x) { return saturate(x); };
          const float rc = std::isnan(r) ? 0.01f : std::clamp(r, 0.01f, 1.0f);
          ASSERT_EQ(f, micro_shadowing::generic_vndf_alu(sat(V), sat(nl), sat(nv), rc));
          ASSERT_EQ(f2, micro_shadowing::generic_vndf_alu_two_stage(sat(V), sat(nl), sat(nv), rc));
        }
}
