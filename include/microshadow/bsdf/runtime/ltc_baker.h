// Fitter ("baker") of the isotropic GGX LTC table (Heitz, Dupuy, Hill, Neubelt 2016, "Real-Time
// Polygonal-Light Shading with Linearly Transformed Cosines", §4 and their fitting code's scheme, our own
// implementation): for each (roughness r, θ_v) of an n×n grid, M = [X Y Z] · [[m11, 0, m13], [0, m22, 0], [0,
// 0, 1]] with Z the BRDF's mean direction (∫ f (n·l) l dl) and X = (Z.z, 0, −Z.x), fitted by Nelder–Mead to
// minimise the L3 error ∫ |f(v,l)(n·l) − magnitude · D(l)|³ dl, estimated with both LTC and BRDF samples
// (balance-heuristic MIS over a fixed stratified grid). Warm starts: θ_v = 0 is isotropic (m11 = m22, m13 =
// 0) and starts from the next rougher row's θ_v = 0 fit (r = 1 starts from the identity); each θ_v > 0 starts
// from the previous θ_v of the same roughness. The θ_v = 0 column is fitted first (sequentially), then the
// roughness rows in parallel (oneTBB): every cell sees the same warm start as in the sequential order, so the
// table is bit-identical for any thread count. BRDF: microfacet_specular (GGX, height-correlated Smith G2).
// magnitude/fresnel: ggx_dfg_reference (E and E_Fc, bsdf/multiscatter.h). Table layout in docs/ltc.md.
#pragma once

#include <microshadow/bsdf/ltc.h>
#include <microshadow/io/texture.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace msh::bsdf {

struct LtcFitOptions {
  int size = 64;              // n: texels per axis (≥ 2)
  int error_samples = 32;     // K: the L3 error uses K² LTC samples + K² BRDF samples (≥ 4)
  int max_iterations = 120;   // Nelder–Mead iterations per cell (≥ 1)
  int moment_samples = 4096;  // QMC samples for magnitude, fresnel and the mean direction (≥ 16)
  int threads = 0;            // 0: oneTBB's default; the result does not depend on it
  std::function<void(double fraction_done)> progress;  // serialized; may be called from worker threads
};

// Throws msh::InputError naming the first bad field.
void validate(const LtcFitOptions& o);

// The fitted table: mat[(j·n + i)·4 + c] = (a, b, c, d) of M⁻¹ (ltc.h), amp[(j·n + i)·2 + c] = (magnitude,
// fresnel), i along roughness r = i/(n − 1), j along y = sqrt(1 − cos θ_v) = j/(n − 1) (θ_v ≤ 1.57).
struct LtcTable {
  int size = 0;
  std::vector<float> mat, amp;
  std::vector<float>
      fit_error;           // per texel: the fit's relative L3 error (L3 error / magnitude³), diagnostics
  double fit_seconds = 0;  // wall time of the fit
  LtcFitOptions options;   // what it was fitted with (progress not kept)

  LtcCoeffs<double> fetch(double roughness, double cos_theta_v) const;  // bilinear, as a shader does
};

// Fits one cell: the LTC of GGX at (roughness, view), warm-started at `start` = (m11, m22, m13) in the frame
// of the BRDF's mean direction (isotropic: m22 = m11 and m13 = 0 are forced, the frame is the identity).
// Returns the fitted (m11, m22, m13) and fills `out` with the normalized M⁻¹ entries and moments.
struct LtcCellFit {
  double m11 = 1, m22 = 1, m13 = 0;
  double error = 0;  // relative L3 error ‖f cos − magnitude·D‖₃ / ‖f cos‖₃ at the fit
  LtcCoeffs<double> coeffs;
};
LtcCellFit fit_ltc_cell(double roughness, double theta_v, const LtcCellFit& start, bool isotropic,
                        const LtcFitOptions& o);

// The whole table (validate(o) first).
LtcTable fit_ltc_table(const LtcFitOptions& o);

// The table as textures: n×n RGBA (M⁻¹ entries) and n×n RG (magnitude, fresnel).
io::Volume ltc_matrix_volume(const LtcTable& t);
io::Volume ltc_moments_volume(const LtcTable& t);

// File names: FILE holds M⁻¹, "<stem>_amp<ext>" beside it the moments, "FILE.json" the sidecar.
std::filesystem::path ltc_moments_path(const std::filesystem::path& table);
std::filesystem::path ltc_sidecar_path(const std::filesystem::path& table);
std::string ltc_sidecar_json(const LtcTable& t, const std::filesystem::path& table,
                             const std::string& pixel_format);

// Writes the two textures and the sidecar atomically (each file written to a temp and renamed).
void write_ltc_table(const std::filesystem::path& path, const LtcTable& t, io::FileFormat ff,
                     io::PixelFormat pf4, io::PixelFormat pf2);
// Reads a table written by write_ltc_table (DDS, KTX2, EXR, NPY; the sidecar is optional). InputError on a
// missing moments file, mismatched sizes or wrong channel counts.
LtcTable load_ltc_table(const std::filesystem::path& path);

}  // namespace msh::bsdf

namespace msh::bsdf {

// As-used accuracy of an LTC table (docs/ltc.md): at `points` (roughness, cos θ_v, light) drawn by a
// Sobol sequence off the grid — r ∈ [roughness_min, 1], cos θ_v ∈ [cos_min, 1], angular radius σ log-uniform
// in [sigma_min_deg, sigma_max_deg], light centre elevation uniform in [0°, 90°] and azimuth in [0°, 180°]
// from the mirror direction's side — the LTC-shaded sphere light (ltc_shade_sphere, N-gon) and square light
// (half-size tan σ at distance 1, facing the point) with the table fetched bilinearly, against nested
// Gauss–Kronrod quadrature of f(v,l)(n·l) over the light (area::integrate_light,
// reference/micro_shadowing_area_exact.h), F = 1. Values are normalized by the light's form factor at normal
// incidence (the light scaled so a white Lambert surface facing it reflects 1), so absolute errors read in
// display units (×255 = 8-bit steps).
struct LtcVerifyOptions {
  int points = 256;
  double roughness_min = 0.1, cos_min = 0.05, sigma_min_deg = 1, sigma_max_deg = 40;
  int polygon_sides = 16;
  bool clip_surface = true;  // false: clip in the LTC's space only, as Heitz et al. 2016
  // Relative errors only where the reference ≥ rel_floor × the highlight's peak (the same light centred on
  // the mirror direction); the diffuse check: where the reference ≥ rel_floor (normalized units).
  double rel_floor = 0.1;
  uint32_t seed = 3;
};
struct LtcErrorStats {
  double rms_rel = 0, max_rel = 0, rms_abs = 0, max_abs = 0;  // abs in normalized units
  int count_rel = 0, count = 0;
  double worst_roughness = 0, worst_cos_v = 0, worst_sigma_deg = 0, worst_elevation_deg = 0;  // at max_abs
};
struct LtcVerifyReport {
  LtcErrorStats sphere, rect, sphere_polygon,
      diffuse_sphere;  // sphere_polygon: N-gon vs the LTC over the cap
  // The reference's self-check, run first: the largest relative error of the light quadrature against the
  // closed forms (Lambert over sphere lights at elevations −5°..90°, clipped or not, Snyder 1996; over a
  // rectangle, Howell C-11). verify_ltc_table throws if it exceeds 1e-5.
  double reference_check = 0;
  double seconds = 0;
};
LtcVerifyReport verify_ltc_table(const LtcTable& t, const LtcVerifyOptions& o);

}  // namespace msh::bsdf
