// As-used accuracy of the area-light fast forms (occlusion/micro_shadowing_area.h, the cone-clipped LTC forms
// of bsdf/ltc_shading.h) against the exact quadrature (reference/micro_shadowing_area_exact.h): the analysis
// behind `microshadow verify area-lights`. docs/area-lights.md (§4–5) describes the measure and gives the
// figures.
//
// Inputs: the first N points of a padded 2D Owen-scrambled Sobol sequence (independent seeds per pair of
// dimensions): V ∈ [0, 1], N·L ∈ [0, 1] (the light's centre, at azimuth 0), light radius ρ ∈ [ρmin, ρmax],
// N·V ∈ [0, 1], roughness ∈ [0, 1], view azimuth ∈ [0, π]; disk and rect lights also take a tilt ∈ [−60°,
// 60°] from facing the point, a roll ∈ [0°, 360°) and an aspect ∈ [0.25, 1] (rect half-height / half-width).
// Every block uses the same sequence, so a smaller count measures a prefix of a larger one.
// Errors are fast − exact, summarized in units of 1/255. Threads (oneTBB) split the points; every point is
// computed on its own and the summaries run in point order, so results are bit-identical for any thread
// count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace msh::area {

struct VerifyOptions {
  int points = 2048;             // closed-form terms over a cap, Lambertian receiver: [1, 2^20]
  int generic_points = 96;       // the generic term's azimuth mean over a cap (slow reference): [0, 2^16]
  int shape_points = 512;        // disk and rect lights through the equivalent cap: [0, 2^16]
  int ltc_points = 512;          // the cone-clipped LTC forms: [0, 2^16]
  int aware_points = 16;         // generic and specular-aware terms, sphere light, GGX receiver: [0, 2^16]
  int diffuse_aware_points = 0;  // the diffuse-aware ALU fit, sphere light, Lambertian receiver: [0, 2^16]
  std::string ltc;  // LTC table file (bake ltc); empty: a 16² table fitted in process (≈ 9 s CPU)
  double rho_min_deg = 1, rho_max_deg = 40;  // 0 ≤ min ≤ max ≤ 90
};

// Throws msh::InputError naming the first bad field (by its command-line option).
void validate(const VerifyOptions& o);

// One input point (see the top of this file); angles in radians.
struct VerifyPoint {
  double visibility, n_dot_l, rho, n_dot_v, roughness, phi_v;
  double tilt, roll, aspect;
};
// Point i of the sequence for the light radius range of `o`.
VerifyPoint verify_point(uint32_t i, const VerifyOptions& o);

// Signed errors e = fast − exact over a set of points, in units of 1/255. p99 is the nearest-rank 99th
// percentile of |e|.
struct ErrorSummary {
  std::size_t count = 0;
  double rms_255 = 0, bias_255 = 0, p99_255 = 0, max_255 = 0;
};
// std::nullopt for no errors.
std::optional<ErrorSummary> summarize_errors(std::vector<double> errors);

// Closed-form terms over a cap (light centred on the N·L direction), Lambertian receiver unless stated.
struct CapErrors {
  ErrorSummary step_cosine_closed_form;      // reference_step_area_cap (exact cosine-weighted closed form)
  ErrorSummary step_solid_angle_mazonka;     // solid-angle ratio (Mazonka 2012)
  ErrorSummary step_solid_angle_oat_sander;  // solid-angle ratio (Oat & Sander 2007)
  ErrorSummary step_point_at_centre;         // the point value at the centre
  // The Lambert closed form used for a GGX receiver (N·V ≥ 0.05, roughness ≥ 0.1) against the exact
  // GGX-weighted quadrature.
  ErrorSummary step_closed_form_for_ggx_receiver;
  ErrorSummary brinck_maximov_2016_area_n4, brinck_maximov_2016_area_n4_float,
      brinck_maximov_2016_point_at_centre;
  ErrorSummary chan_2018_area_n4, chan_2018_area_n4_float, chan_2018_point_at_centre;
  ErrorSummary part1_analytic_area_n4, part1_analytic_area_n4_float, part1_analytic_point_at_centre;
  // |Ω_OS − Ω_Mazonka| / Ω_cap for cap ∩ cone (a difference of solid angles, not of terms).
  ErrorSummary oat_sander_vs_mazonka_solid_angle_fraction_of_light;
};

// The generic term's azimuth mean over a cap, Lambertian receiver, against the exact quadrature of the exact
// azimuth mean.
struct GenericCapErrors {
  ErrorSummary generic_vndf_alu_area_n4_float;   // its ALU fit through the product rule
  ErrorSummary generic_vndf_exact_mean_area_n4;  // the exact mean through the product rule (quadrature alone)
  ErrorSummary generic_vndf_alu_point_at_centre;
  ErrorSummary generic_vndf_alu_point_error_at_centre;  // the fit alone: against the exact mean at the centre
};

// Disk and rect lights, Lambertian receiver: the cap forms at the equivalent cap (same vector form factor),
// and the point value at the centre, against the exact quadrature over the true shape.
struct ShapeErrors {
  ErrorSummary disk_step_equivalent_cap, disk_step_equivalent_cap_float, disk_step_point_at_centre,
      disk_brinck_maximov_2016_equivalent_cap_n4, disk_brinck_maximov_2016_point_at_centre,
      disk_chan_2018_equivalent_cap_n4, disk_part1_analytic_equivalent_cap_n4;
  ErrorSummary rect_step_equivalent_cap, rect_step_equivalent_cap_float, rect_step_point_at_centre,
      rect_brinck_maximov_2016_equivalent_cap_n4, rect_brinck_maximov_2016_point_at_centre,
      rect_chan_2018_equivalent_cap_n4, rect_part1_analytic_equivalent_cap_n4;
};

// The cone-clipped LTC forms (cap, disk and rect lights as 16-gons, the cone as its 16-gon). GGX receiver
// (roughness ∈ [0.1, 1], N·V ∈ [0.05, 1]; the table fetched bilinearly, tail weight ltc_tail_weight) against
// the exact GGX-weighted quadrature, beside the Lambertian cap forms and the point term at the LTC's
// representative direction; Lambertian receiver (identity LTC, no tail) for disks and rects.
struct LtcErrors {
  ErrorSummary ltc_cap_step_ggx_cone_clip, ltc_cap_step_ggx_cone_clip_float,
      ltc_cap_step_ggx_cone_clip_no_tail, ltc_cap_step_ggx_lambert_closed_form,
      ltc_cap_step_ggx_point_at_ltc_representative_direction;
  ErrorSummary ltc_cap_brinck_maximov_2016_ggx_cone_clip_n4,
      ltc_cap_brinck_maximov_2016_ggx_lambert_product_rule,
      ltc_cap_brinck_maximov_2016_ggx_point_at_ltc_representative;
  ErrorSummary ltc_cap_chan_2018_ggx_cone_clip_n4, ltc_cap_part1_analytic_ggx_cone_clip_n4;
  ErrorSummary ltc_disk_step_ggx_cone_clip, ltc_disk_step_ggx_lambert_equivalent_cap,
      ltc_disk_brinck_maximov_2016_ggx_cone_clip_n4;
  ErrorSummary ltc_rect_step_ggx_cone_clip, ltc_rect_step_ggx_lambert_equivalent_cap,
      ltc_rect_step_ggx_point_at_ltc_representative_direction, ltc_rect_brinck_maximov_2016_ggx_cone_clip_n4;
  ErrorSummary ltc_disk_step_lambert_cone_clip, ltc_disk_brinck_maximov_2016_lambert_cone_clip_n4,
      ltc_disk_chan_2018_lambert_cone_clip_n4, ltc_disk_part1_analytic_lambert_cone_clip_n4;
  ErrorSummary ltc_rect_step_lambert_cone_clip, ltc_rect_step_lambert_cone_clip_float,
      ltc_rect_brinck_maximov_2016_lambert_cone_clip_n4, ltc_rect_chan_2018_lambert_cone_clip_n4,
      ltc_rect_part1_analytic_lambert_cone_clip_n4;
};

// The generic and specular-aware terms over a sphere light, GGX receiver (the LTC block's domain): their
// azimuth means through the cone-clipped LTC product rule, against the exact quadrature of the full-direction
// term.
struct AwareErrors {
  ErrorSummary ggx_cap_generic_vndf_exact_mean_ltc_cone_clip_n4,
      ggx_cap_generic_vndf_alu_ltc_cone_clip_n4_float, ggx_cap_generic_vndf_alu_lambert_product_rule,
      ggx_cap_generic_vndf_exact_point_at_ltc_representative;
  ErrorSummary ggx_cap_specular_aware_mean_ltc_cone_clip_n4,
      ggx_cap_specular_aware_mean_ltc_cone_clip_n4_float, ggx_cap_specular_aware_point_at_ltc_representative;
};

// The diffuse-aware ALU fit over a sphere light, Lambertian receiver, against the exact quadrature of the
// exact azimuth mean.
struct DiffuseAwareErrors {
  ErrorSummary lambert_cap_diffuse_aware_alu_product_rule_n4_float,
      lambert_cap_diffuse_aware_alu_point_at_centre;
};

// A block is empty (std::nullopt) when its point count is 0.
struct VerifyResult {
  VerifyOptions options;
  std::string ltc_table;  // what the LTC blocks used: the file, the in-process fit, or "none"
  CapErrors cap;
  std::optional<GenericCapErrors> generic;
  std::optional<ShapeErrors> shapes;
  std::optional<LtcErrors> ltc;
  std::optional<AwareErrors> aware;
  std::optional<DiffuseAwareErrors> diffuse_aware;
};

// validate(o), then the LTC table (a bad file fails before any work), then every block.
VerifyResult verify_area_lights(const VerifyOptions& o);

// Every form of `r` by its output name (block by block, in the order of the structs above); std::nullopt for
// the forms of an empty block.
struct NamedErrorSummary {
  std::string name;
  std::optional<ErrorSummary> summary;
};
std::vector<NamedErrorSummary> named_errors(const VerifyResult& r);

// The JSON object of `verify area-lights --json`: the domain, the point counts, the LTC table and "errors"
// (name → {count, rms_255, bias_255, p99_255, max_255} or null).
nlohmann::json to_json(const VerifyResult& r);

}  // namespace msh::area
