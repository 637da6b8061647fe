// msh::micro_shadowing::diffuse_aware_alu (include/microshadow/occlusion/micro_shadowing_aware_fit.h), the
// ALU-only run-time form of the diffuse micro-BRDF-aware term, against the exact azimuth mean
// diffuse_aware_exact_azimuth_mean (deterministic quadrature) at independent continuous random inputs (not
// the fit's training points, not the Sobol points of `verify micro-shadowing-aware`), its exact early-outs
// and limits, finiteness on degenerate inputs, and the registry method that serves it.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_aware_exact.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

using namespace msh;
using namespace msh::micro_shadowing;

namespace {

struct Errors {
  double rms = 0, max = 0;
  int n = 0;
  double rms_se = 0;  // standard error of rms: SD(e²) / (2 rms √n), delta method on the mean of e²
  int above_p99 = 0;  // points with |e| > 12.3/255, the documented p99
};

// Uniform random inputs over the documented domain (V ∈ [0,1], N·L, N·V ∈ (0,1], r ∈ [0.1, 1]), outside the
// early-out region (exact there, tested below), in float as a shader receives them.
Errors measure(int n, uint64_t seed) {
  Pcg32 rng(seed, 91);
  double ss = 0, s4 = 0, mx = 0;
  int k = 0, above = 0;
  while (k < n) {
    const float V = float(rng.next_double()), nl = float(1 - rng.next_double()),
                nv = float(1 - rng.next_double()), r = float(0.1 + 0.9 * rng.next_double());
    if (exact_zero(V, nl) || exact_zero(V, nv)) continue;
    const double ex =
        diffuse_aware_exact_azimuth_mean(V, double(r) * r, nl, nv, DiffuseAwareForm::Reciprocal, 1e-4);
    const double e = std::abs(double(diffuse_aware_alu(V, nl, nv, r)) - ex);
    ss += e * e, s4 += e * e * e * e, mx = std::max(mx, e), ++k;
    above += e > 12.3 / 255;
  }
  const double m2 = ss / n, rms = std::sqrt(m2);
  return {rms, mx, n, rms > 0 ? std::sqrt(std::max(0.0, s4 / n - m2 * m2) / n) / (2 * rms) : 0, above};
}

}  // namespace

// Asserted at docs/micro-shadowing-aware.md's figures for the fit (`verify micro-shadowing-aware --method
// diffuse-aware-alu --samples 2000`, Owen-scrambled Sobol, seed 1): RMS 3.6/255 and max 31.9/255 outside the
// early-out 2V + N·L < 1 (1,497 points), p99 12.3/255 over all 2000. These 48 points (another generator) also
// skip 2V + N·V < 1, where the fit and the exact term are both exactly 0 (DiffuseAwareAlu.Limits): that
// removes 1/9 of the zero-free domain's points (P(both lit) = 2/3 of P(N·L lit) = 3/4 for uniform V, N·L,
// N·V), all with error 0, so the documented RMS here is 3.6 · √(9/8) = 3.82/255 and the fraction above the
// p99 is at most 1 % · 2000 / 1333 = 1.5 %. Tolerances from the sampling error of 48 points:
// - RMS: 3.82/255 + 3 standard errors of the 48-point RMS, SE = SD(e²) / (2 RMS √48) from the sample's own
//   moments (measured: RMS 3.22/255, SE 0.59/255);
// - p99: the count above 12.3/255 is Binomial(48, 0.015): mean 0.72, SD 0.84, asserted ≤ 0.72 + 3 SD → 3;
// - max: at the documented 31.9/255, no margin: a 48-point sample max exceeds a 1,497-point one with
//   probability 48 / 1545 = 3 % for a random seed; this seed is fixed and below it (measured 12.6/255).
// The older estimate of the same term at 64 samples has RMS 6.3/255 on the verify points; the generic term
// used for the diffuse-aware one is at RMS 62/255: the test also fails a fit that is no better than those.
TEST(DiffuseAwareAlu, AgainstExactAzimuthMean) {
  const Errors e = measure(48, 2027);
  std::printf("[ diffuse-aware-alu ] %d points: RMS %.2f/255 (SE %.2f) max %.2f/255 above p99 %d\n", e.n,
              255 * e.rms, 255 * e.rms_se, 255 * e.max, e.above_p99);
  EXPECT_LE(e.rms, 3.6 * std::sqrt(9.0 / 8.0) / 255 + 3 * e.rms_se);
  EXPECT_LE(e.above_p99, int(std::floor(48 * 0.015 + 3 * std::sqrt(48 * 0.015 * 0.985))));  // 3
  EXPECT_LE(e.max, 31.9 / 255);
}

// The exact properties the header states, in float and double.
TEST(DiffuseAwareAlu, Limits) {
  {
    Pcg32 rng(5, 3);
    for (int i = 0; i < 2000; ++i) {
      const float nl = float(rng.next_double()), nv = float(rng.next_double()), r = float(rng.next_double());
      const float V = float(rng.next_double());
      // V = 1 → 1 (any N·L, N·V > 0, roughness), V = 0 → 0.
      if (nl > 0 && nv > 0) {
        EXPECT_EQ(diffuse_aware_alu(1.0f, nl, nv, r), 1.0f);
        EXPECT_EQ(diffuse_aware_alu(1.0, double(nl), double(nv), double(r)), 1.0);
      }
      EXPECT_EQ(diffuse_aware_alu(0.0f, nl, nv, r), 0.0f);
      // The exact early-outs 2V + N·L < 1 and 2V + N·V < 1 give exactly 0, as the exact term does.
      const bool zero = exact_zero(V, nl) || exact_zero(V, nv);
      const float f = diffuse_aware_alu(V, nl, nv, r);
      if (zero) {
        EXPECT_EQ(f, 0.0f) << V << " " << nl << " " << nv;
      }
      EXPECT_TRUE(f >= 0.0f && f <= 1.0f);
    }
  }
  // Exact reference agrees on the early-outs (so they are the term's, not the fit's).
  EXPECT_EQ(diffuse_aware_exact_azimuth_mean(0.3, 0.25, 0.35, 0.9, DiffuseAwareForm::Reciprocal), 0.0);
  EXPECT_EQ(diffuse_aware_exact_azimuth_mean(0.3, 0.25, 0.9, 0.35, DiffuseAwareForm::Reciprocal), 0.0);
  EXPECT_GT(diffuse_aware_exact_azimuth_mean(0.3, 0.25, 0.9, 0.35, DiffuseAwareForm::Flux), 0.0);
}

// The reciprocal term is symmetric in l and v (the integrand D (m·v)(m·l) with cone tests on both); the fit's
// form is symmetric by construction, and the exact term is, up to its quadrature tolerance.
TEST(DiffuseAwareAlu, ReciprocalSymmetry) {
  Pcg32 rng(8, 1);
  for (int i = 0; i < 500; ++i) {
    const float V = float(rng.next_double()), nl = float(rng.next_double()), nv = float(rng.next_double()),
                r = float(rng.next_double());
    EXPECT_NEAR(diffuse_aware_alu(V, nl, nv, r), diffuse_aware_alu(V, nv, nl, r), 2e-6f);
  }
  EXPECT_NEAR(diffuse_aware_exact_azimuth_mean(0.7, 0.3, 0.8, 0.45, DiffuseAwareForm::Reciprocal),
              diffuse_aware_exact_azimuth_mean(0.7, 0.3, 0.45, 0.8, DiffuseAwareForm::Reciprocal), 1e-5);
}

// Degenerate inputs: N·V = 0, N·L = 0, roughness 0 and 1, NaN and ±Inf anywhere: finite, in [0, 1].
TEST(DiffuseAwareAlu, DegenerateInputsFinite) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const float vals[] = {0.0f, 1e-30f, 1e-7f, 0.25f, 0.5f, 0.999999f, 1.0f, -1.0f, 2.0f, nan, inf, -inf};
  for (float V : vals)
    for (float nl : vals)
      for (float nv : vals)
        for (float r : vals) {
          const float f = diffuse_aware_alu(V, nl, nv, r);
          ASSERT_TRUE(std::isfinite(f) && f >= 0.0f && f <= 1.0f) << V << " " << nl << " " << nv << " " << r;
          const double d = diffuse_aware_alu(double(V), double(nl), double(nv), double(r));
          ASSERT_TRUE(std::isfinite(d) && d >= 0.0 && d <= 1.0);
        }
  // NaN maps to 0 (V, N·L, N·V) as every term of micro_shadowing.h: V = 0 and N·L = 0 give 0 (as the exact
  // term), N·V = 0 the N·V → 0 value.
  EXPECT_EQ(diffuse_aware_alu(nan, 0.9f, 0.9f, 0.5f), 0.0f);
  EXPECT_EQ(diffuse_aware_alu(0.8f, nan, 0.9f, 0.5f), 0.0f);
  EXPECT_EQ(diffuse_aware_alu(0.8f, 0.9f, nan, 0.5f), diffuse_aware_alu(0.8f, 0.9f, 0.0f, 0.5f));
  EXPECT_EQ(diffuse_aware_exact_azimuth_mean(0.8, 0.25, 0.0, 0.9, DiffuseAwareForm::Reciprocal), 0.0);
  // Roughness 0 is evaluated at 0.01 (outside the fitted [0.1, 1]), where the exact term is the step
  // χ(N·L > c) χ(N·V > c) (docs/micro-shadowing-aware.md §4): far from the cone's edge the extrapolated fit
  // keeps the step's side (a limit check, not an accuracy claim: below r = 0.1 the fit is not measured; these
  // points are 8-19/255 off, docs/micro-shadowing-aware.md).
  for (const auto& [nl, nv] : {std::pair{0.9, 0.9}, std::pair{0.9, 0.3}, std::pair{0.6, 0.95}}) {
    const double ex = diffuse_aware_exact_azimuth_mean(0.8, 1e-4, nl, nv, DiffuseAwareForm::Reciprocal, 1e-4);
    EXPECT_NEAR(ex, (nl > 0.45 && nv > 0.45) ? 1.0 : 0.0, 0.02);  // c = 0.447
    EXPECT_NEAR(diffuse_aware_alu(0.8f, float(nl), float(nv), 0.0f), ex, 0.1);
  }
}

// The registry method serves the header function in float (what `eval micro-shadowing` prints).
TEST(DiffuseAwareAlu, RegistryMethod) {
  const occlusion::MicroShadowingEvaluator rec("diffuse-aware-alu");
  occlusion::MicroShadowingQuery q;
  q.visibility = 0.62, q.n_dot_l = 0.71, q.n_dot_v = 0.83, q.roughness = 0.44;
  EXPECT_EQ(rec.eval(q), double(diffuse_aware_alu(0.62f, 0.71f, 0.83f, 0.44f)));
  q.phi = 1.0;
  EXPECT_THROW(rec.eval(q), InputError);  // the fit is the azimuth mean: no --phi
}
