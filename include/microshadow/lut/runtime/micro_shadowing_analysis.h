// Studies of the generic micro-shadowing term behind `plot micro-shadowing` (docs/micro-shadowing.md): maps
// of every term over (V, N·L), their error against the exact azimuth mean, what ignoring the azimuth costs
// (and what a table with H Fourier harmonics keeps), and the exact term against a plain Monte Carlo estimate.
// Tool code (oneTBB, allocation), not for an engine; every result is deterministic whatever the thread count.
#pragma once

#include <microshadow/math/vec.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace msh::lut {

// The configuration convention of the studies and of `eval micro-shadowing`: v in the xz plane (azimuth 0 =
// along the tangent), l at relative azimuth φ. N·V, N·L ∈ [0, 1].
Vec3d study_view_dir(double n_dot_v);
Vec3d study_light_dir(double n_dot_l, double phi);

// Nearest-rank percentile p ∈ [0, 1] of sorted values (0 for an empty set).
double percentile_nearest_rank(const std::vector<double>& sorted, double p);

// Every closed-form term and the exact azimuth mean (generic_vndf_exact_azimuth_mean, α = r²) at one point.
struct TermMapCell {
  double roughness, n_dot_v, visibility, n_dot_l;
  double reference, brinck_maximov, chan, part1, generic;
};
// The grid i/(n − 1) × j/(n − 1) over (V, N·L) for each roughness and N·V (roughness outermost, V innermost).
// n ≥ 2.
std::vector<TermMapCell> term_maps(int n, const std::vector<double>& roughness,
                                   const std::vector<double>& n_dot_v);

// RMS, max |e| and mean signed e of each closed-form term against the generic term over the cells of one
// (roughness, N·V) pair, in the order of kTermNames: the method registry's ids of the closed forms
// (occlusion/runtime/micro_shadowing_methods.h; kExactTermName: the generic term's).
struct TermError {
  double rms, max_abs, mean_signed;
};
inline constexpr const char* kTermNames[4] = {"reference", "brinck-maximov-2016", "chan-2018",
                                              "part1-analytic"};
inline constexpr const char* kExactTermName = "generic-vndf";
std::array<TermError, 4> term_map_errors(const std::vector<TermMapCell>& cells, double roughness,
                                         double n_dot_v);

// Azimuth study: random (V, roughness ∈ [0.1, 1], N·L, N·V, φ ∈ [0, π]) configurations (PCG32, stream k for
// configuration k); the exact term at φ, its azimuth mean (what a table without an azimuth axis stores at
// best), and the Fourier cosine coefficients a_0..a_4 over [0, π] (96-point Gauss-Legendre; 0 at the
// early-out).
inline constexpr int kAzimuthStudyHarmonics = 4;
struct AzimuthConfig {
  double visibility, roughness, n_dot_l, n_dot_v, phi, exact, mean;
  std::array<double, kAzimuthStudyHarmonics + 1> a;
  // exact − saturate(a_0 + Σ_{h ≤ H} a_h cos(hφ)): the error of a table with H harmonic slabs. H ≤ 4.
  double truncation_error(int harmonics) const;
};
std::vector<AzimuthConfig> azimuth_study(std::size_t configs);

// Statistics of |e| for the azimuth study: H = 0: exact − mean; H ≥ 1: truncation_error(H). Over all
// configurations or only those outside the early-out 2V + N·L < 1.
struct AbsErrorSummary {
  std::size_t count = 0;
  double rms = 0, p50 = 0, p90 = 0, p99 = 0, max = 0;
  double frac_above_half_unorm8_step = 0;  // fraction with |e| > 0.5/255
};
AbsErrorSummary azimuth_error_summary(const std::vector<AzimuthConfig>& configs, int harmonics,
                                      bool outside_early_out);

// The exact term (generic_vndf_exact) against a Monte Carlo estimate with `samples` PCG32 samples of the
// spherical-caps VNDF sampler (an independent path: no Sobol points, no quadrature), at fixed points
// {V, αx, αy, N·L, N·V, φ}. sigma is the binomial standard error of the ratio.
struct MonteCarloCheck {
  std::array<double, 6> point;
  double exact, mc, sigma;
};
std::vector<MonteCarloCheck> monte_carlo_validation(int64_t samples);

}  // namespace msh::lut
