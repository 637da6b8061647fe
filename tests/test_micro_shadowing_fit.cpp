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
#include <limits>
#include <vector>

using namespace msh;

namespace {

struct Errors {
  double rms = 0, max = 0;
};

// Uniform random inputs over the documented domain (V ∈ [0,1], N·L, N·V ∈ (0,1], r ∈ [0.1, 1]), early-out
// region included, as `plot micro-shadowing-fit` and docs/micro-shadowing.md measure it.
template <class F>
Errors measure(F term, int n, uint64_t seed) {
  Pcg32 rng(seed, 77);
  double ss = 0, mx = 0;
  for (int i = 0; i < n; ++i) {
    const double V = rng.next_double(), nl = 1 - rng.next_double(), nv = 1 - rng.next_double();
    const double r = 0.1 + 0.9 * rng.next_double();
    const double e =
        std::abs(term(V, nl, nv, r) - micro_shadowing::generic_vndf_exact_azimuth_mean(V, r * r, nl, nv));
    ss += e * e, mx = std::max(mx, e);
  }
  return {std::sqrt(ss / n), mx};
}

}  // namespace

// Bounds. The targets are RMS <= 2/255 and max <= 8/255 over the domain. The two-stage form is
// asserted at the RMS target (its validation in docs/micro-shadowing.md, 20000 points of another seed,
// measured RMS 0.95/255: a 400-point sample stays below 2/255 with margin); its measured max is 9.0/255 (2 of
// 20000 points above 8/255, all at N.V < 0.01), so the max is asserted at 12/255, the documented max plus
// margin for points the validation did not visit. The one-call 40-operation form is asserted at its
// documented accuracy (validation RMS 4.2/255, max 37/255) with the same kind of margins. Both must be
// several times better than the best older closed-form term on the same points (Brinck-Maximov 2016 and the
// reference step, RMS 50-60/255 on this measure).
TEST(MicroShadowingFit, AccuracyAgainstExactAzimuthMean) {
  const int n = 400;
  const Errors fast = measure(
      [](double V, double nl, double nv, double r) {
        return double(micro_shadowing::generic_vndf_alu(float(V), float(nl), float(nv), float(r)));
      },
      n, 4242);
  const Errors two = measure(
      [](double V, double nl, double nv, double r) {
        const auto px = micro_shadowing::generic_vndf_alu_pixel(float(V), float(nv), float(r));
        return double(micro_shadowing::generic_vndf_alu_light(px, float(nl)));
      },
      n, 4242);
  const Errors bm =
      measure([](double V, double nl, double, double) { return micro_shadowing::brinck_maximov_2016(V, nl); },
              n, 4242);
  const Errors ref = measure(
      [](double V, double nl, double, double) { return micro_shadowing::reference_step(V, nl); }, n, 4242);
  std::printf(
      "[ alu ] %d points: one-call RMS %.2f/255 max %.2f/255; two-stage RMS %.2f/255 max %.2f/255 "
      "(Brinck-Maximov %.1f / %.1f, reference %.1f / %.1f)\n",
      n, 255 * fast.rms, 255 * fast.max, 255 * two.rms, 255 * two.max, 255 * bm.rms, 255 * bm.max,
      255 * ref.rms, 255 * ref.max);
  EXPECT_LE(two.rms, 2.0 / 255);
  EXPECT_LE(two.max, 12.0 / 255);
  EXPECT_LE(fast.rms, 5.5 / 255);
  EXPECT_LE(fast.max, 40.0 / 255);
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
