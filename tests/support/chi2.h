// Chi-square goodness-of-fit test for direction samplers (the habit of pbrt-v4's and Mitsuba 3's
// sampler tests).
//
// Samples are histogrammed on a (cos θ, φ) grid over the FULL sphere; since dω = d(cos θ) dφ, the expected
// mass of a cell is the plain integral of pdf(cos θ, φ) over the rectangle, computed here by adaptive
// tensor Gauss-Legendre quadrature (5×5 nodes, refined 2×2 until the parent and children estimates agree to
// 1e-3 expected counts or a depth of 14), so very peaked pdfs (GGX VNDF at α = 0.05) are integrated
// accurately. Cells with expected count < 5 are pooled (pbrt-v4 / Mitsuba 3); a sample in a cell of zero
// expected mass is an immediate failure; the p-value is Q(dof/2, χ²/2) (regularized upper incomplete gamma).
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace msh::test {

// Independent uniform pairs from a fixed PCG32 stream, the sample source of the chi-square tests (a
// low-discrepancy sequence would make χ² too small).
struct Uniforms {
  Pcg32 rng;
  explicit Uniforms(uint64_t seed) : rng(seed) {}
  Vec2d next() {
    const double a = rng.next_double();
    return {a, rng.next_double()};
  }
};

struct Chi2Result {
  bool pass = false;
  double p_value = 0;
  double statistic = 0;
  int dof = 0;
  std::string table;  // observed/expected dump, filled on failure
};

// Draws n_samples directions via sample(i) (nullopt = rejected sample, counts toward nothing), histograms
// them on a (cos θ, φ) grid over the full sphere (theta_bins × phi_bins), integrates pdf (solid angle, may be
// zero in regions) over each cell numerically, pools cells with expected count < 5, fails on any sample in a
// zero-expectation cell (or any non-finite / non-unit sample), and applies a Šidák-corrected significance
// over n_tests runs: pass iff p ≥ 1 − (1 − significance)^(1/n_tests). Expected counts are n_samples × ∫cell
// pdf, so a sampler that rejects samples must return a pdf that integrates to its acceptance rate.
Chi2Result chi2_test_directions(const std::function<std::optional<Vec3d>(uint32_t)>& sample,
                                const std::function<double(const Vec3d&)>& pdf, int n_samples = 1000000,
                                int theta_bins = 40, int phi_bins = 80, double significance = 0.01,
                                int n_tests = 1);

// The same test after the bijection w → w' = normalize(w.x/ax, w.y/ay, w.z) of the sphere, with the pdf
// carried over by its Jacobian: pdf'(w') = pdf(w) · ax·ay / |S w'|³, S = diag(ax, ay, 1), w = S w'/|S w'|.
// Spreads a lobe of width ~α around the pole over the whole grid, so samplers of peaked distributions are
// tested with full power (at α = 0.05 the plain grid puts every sample in its top cos θ row). ax, ay > 0.
Chi2Result chi2_test_directions_stretched(const std::function<std::optional<Vec3d>(uint32_t)>& sample,
                                          const std::function<double(const Vec3d&)>& pdf, double ax,
                                          double ay, int n_samples = 1000000, int theta_bins = 40,
                                          int phi_bins = 80, double significance = 0.01, int n_tests = 1);

// Regularized upper incomplete gamma Q(a, x) = Γ(a, x)/Γ(a), a > 0, x ≥ 0 (Numerical Recipes §6.2: series for
// x < a + 1, Lentz continued fraction otherwise). Q(k/2, χ²/2) is the chi-square survival function.
double regularized_gamma_q(double a, double x);

// ∫∫ f(cos θ, φ) over [z0, z1] × [phi0, phi1] by the adaptive quadrature used for the expected counts,
// to absolute tolerance abs_tol. Exposed so tests can integrate pdfs over the sphere with the same rule.
double integrate_sphere_rect(const std::function<double(const Vec3d&)>& pdf, double z0, double z1,
                             double phi0, double phi1, double abs_tol);

}  // namespace msh::test
