// The studies behind `plot micro-shadowing` (lut/runtime/micro_shadowing_analysis.h), each against an
// independent computation: the Fourier coefficients against a midpoint rule of the exact term and against the
// adaptive azimuth mean, the Monte Carlo check against its own binomial error, the error table against
// hand-built cells.
#include <gtest/gtest.h>
#include <microshadow/lut/runtime/micro_shadowing_analysis.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

namespace msh::lut {
namespace {

TEST(MicroShadowingAnalysis, PercentileIsNearestRank) {
  const std::vector<double> s = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  EXPECT_EQ(percentile_nearest_rank(s, 0.5), 5);
  EXPECT_EQ(percentile_nearest_rank(s, 0.9), 9);
  EXPECT_EQ(percentile_nearest_rank(s, 0.91), 10);
  EXPECT_EQ(percentile_nearest_rank(s, 0.0), 1);
  EXPECT_EQ(percentile_nearest_rank(s, 1.0), 10);
  EXPECT_EQ(percentile_nearest_rank({}, 0.5), 0);
}

// a_0 is the azimuth mean and a_h = (2/π) ∫_0^π f(φ) cos(hφ) dφ; checked with a 256-point midpoint rule of
// generic_vndf_exact (a different rule from the study's 96-point Gauss-Legendre) and with the adaptive mean.
TEST(MicroShadowingAnalysis, FourierCoefficientsMatchIndependentQuadrature) {
  const std::vector<AzimuthConfig> az = azimuth_study(12);
  ASSERT_EQ(az.size(), 12u);
  int checked = 0;
  for (const AzimuthConfig& z : az) {
    const double al = roughness_to_alpha(z.roughness);
    const Vec3d v = study_view_dir(z.n_dot_v);
    EXPECT_NEAR(
        z.exact,
        micro_shadowing::generic_vndf_exact(z.visibility, al, al, v, study_light_dir(z.n_dot_l, z.phi)),
        1e-12);
    if (micro_shadowing::exact_zero(z.visibility, z.n_dot_l)) {
      for (double a : z.a) EXPECT_EQ(a, 0.0);
      EXPECT_EQ(z.mean, 0.0);
      continue;
    }
    ++checked;
    EXPECT_NEAR(z.a[0], z.mean, 2e-5);
    const int n = 256;
    std::array<double, kAzimuthStudyHarmonics + 1> ref{};
    for (int i = 0; i < n; ++i) {
      const double p = kPi<double> * (i + 0.5) / n;
      const double f =
          micro_shadowing::generic_vndf_exact(z.visibility, al, al, v, study_light_dir(z.n_dot_l, p));
      for (int h = 0; h <= kAzimuthStudyHarmonics; ++h)
        ref[h] += (h == 0 ? 1.0 : 2.0) * f * std::cos(h * p) / n;
    }
    for (int h = 0; h <= kAzimuthStudyHarmonics; ++h) EXPECT_NEAR(z.a[h], ref[h], 1e-4) << h;
    // The truncation error is exact minus the saturated partial sum.
    double s = z.a[0] + z.a[1] * std::cos(z.phi) + z.a[2] * std::cos(2 * z.phi);
    EXPECT_DOUBLE_EQ(z.truncation_error(2), z.exact - std::clamp(s, 0.0, 1.0));
  }
  EXPECT_GE(checked, 4);
}

TEST(MicroShadowingAnalysis, SummaryCountsAndOrdersStatistics) {
  const std::vector<AzimuthConfig> az = azimuth_study(40);
  const AbsErrorSummary all = azimuth_error_summary(az, 0, false), lit = azimuth_error_summary(az, 0, true);
  EXPECT_EQ(all.count, 40u);
  size_t outside = 0;
  for (const AzimuthConfig& z : az) outside += !micro_shadowing::exact_zero(z.visibility, z.n_dot_l);
  EXPECT_EQ(lit.count, outside);
  for (const AbsErrorSummary& s : {all, lit}) {
    EXPECT_LE(s.p50, s.p90);
    EXPECT_LE(s.p90, s.p99);
    EXPECT_LE(s.p99, s.max);
    EXPECT_LE(s.rms, s.max);
    EXPECT_GE(s.frac_above_half_unorm8_step, 0.0);
    EXPECT_LE(s.frac_above_half_unorm8_step, 1.0);
  }
}

TEST(MicroShadowingAnalysis, MonteCarloAgreesWithinItsError) {
  for (const MonteCarloCheck& m : monte_carlo_validation(int64_t(1) << 15)) {
    EXPECT_GT(m.sigma, 0.0);
    EXPECT_NEAR(m.mc, m.exact, 5 * m.sigma + 1e-9);
  }
}

TEST(MicroShadowingAnalysis, TermErrorsOfHandBuiltCells) {
  // Two cells of (0.4, 0.5) with known differences to the generic term; one cell of another pair ignored.
  const std::vector<TermMapCell> cells = {{0.4, 0.5, 0, 0, 1.0, 0.5, 0.5, 0.25, 0.5},
                                          {0.4, 0.5, 0, 0, 0.0, 0.5, 0.1, 0.25, 0.5},
                                          {0.7, 0.5, 0, 0, 9.0, 9.0, 9.0, 9.0, 0.0}};
  const std::array<TermError, 4> e = term_map_errors(cells, 0.4, 0.5);
  EXPECT_DOUBLE_EQ(e[0].rms, 0.5);
  EXPECT_DOUBLE_EQ(e[0].max_abs, 0.5);
  EXPECT_DOUBLE_EQ(e[0].mean_signed, 0.0);
  EXPECT_DOUBLE_EQ(e[1].max_abs, 0.0);
  EXPECT_DOUBLE_EQ(e[2].max_abs, 0.4);
  EXPECT_DOUBLE_EQ(e[2].mean_signed, -0.2);
  EXPECT_DOUBLE_EQ(e[3].rms, 0.25);
  // term_maps: the grid and the terms at a cell.
  const std::vector<TermMapCell> g = term_maps(3, {0.4}, {1.0, 0.5});
  ASSERT_EQ(g.size(), 18u);
  const TermMapCell& c = g[9 + 3 * 1 + 2];  // N·V 0.5, N·L 0.5, V 1
  EXPECT_EQ(c.n_dot_v, 0.5);
  EXPECT_EQ(c.n_dot_l, 0.5);
  EXPECT_EQ(c.visibility, 1.0);
  EXPECT_EQ(c.chan, micro_shadowing::chan_2018(1.0, 0.5));
  EXPECT_EQ(c.generic, micro_shadowing::generic_vndf_exact_azimuth_mean(1.0, 0.16, 0.5, 0.5));
}

// The columns are named by the registry's ids: kTermNames (the four older terms the maps show) are closed
// forms of (V, N·L) of the registry that depend on N·L, in its order, and each cell's value is the registry's
// closed form; kExactTermName evaluates (without the azimuth) to the cell's generic value.
TEST(MicroShadowingAnalysis, TermNamesAreTheRegistrysClosedForms) {
  const std::vector<std::string> closed = occlusion::micro_shadowing_closed_form_terms();
  auto at = closed.begin();  // each name found after the previous one: a subsequence, in the registry's order
  for (const char* name : kTermNames) {
    at = std::find(at, closed.end(), std::string(name));
    EXPECT_NE(at, closed.end()) << name << " is not a closed form of the registry (or out of its order)";
  }
  const std::vector<TermMapCell> g = term_maps(4, {0.4}, {0.7});
  const occlusion::MicroShadowingEvaluator exact(kExactTermName);
  for (const TermMapCell& c : g) {
    const double vals[4] = {c.reference, c.brinck_maximov, c.chan, c.part1};
    for (int q = 0; q < 4; ++q)
      EXPECT_EQ(vals[q],
                occlusion::find_micro_shadowing_method(kTermNames[q])->closed_form(c.visibility, c.n_dot_l))
          << kTermNames[q];
    EXPECT_EQ(c.generic,
              exact.eval({c.visibility, c.n_dot_l, c.n_dot_v, c.roughness, std::nullopt, std::nullopt}));
  }
}

}  // namespace
}  // namespace msh::lut
