// The analysis behind `verify area-lights`. See area_lights_verify.h; the measure and its figures:
// docs/area-lights.md (§4–5).
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/reference/runtime/area_lights_verify.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace msh::area {
namespace {

constexpr double kDeg = kPi<double> / 180;

// The disk and rect lights of a point (centred on its N·L direction), and the rect's corners in float.
struct ShapeLights {
  Disk disk;
  Quad quad;
  std::array<Vec3f, 4> quad_float;
};
ShapeLights shape_lights(const VerifyPoint& in) {
  const Vec3d c = spherical_direction(in.n_dot_l, 0.0);
  ShapeLights s{disk_tilted(c, in.rho, in.tilt, in.roll),
                rect_tilted(c, in.rho, in.rho * in.aspect, in.tilt, in.roll),
                {}};
  for (size_t k = 0; k < 4; ++k) s.quad_float[k] = Vec3f(s.quad.corners[k]);
  return s;
}

// The view and roughness of a point in the LTC and aware blocks' domain: N·V ≥ 0.05, roughness ≥ 0.1.
struct ClampedView {
  double nv, r, alpha;
  Vec3d v;
};
ClampedView clamped_view(const VerifyPoint& in) {
  const double nv = std::max(0.05, in.n_dot_v), r = std::max(0.1, in.roughness);
  return {nv, r, roughness_to_alpha(r), spherical_direction(nv, in.phi_v)};
}

// A sphere light's cone-clipped LTC in float (with the tail), as a shader evaluates it.
bsdf::LtcLightCone<float> sphere_cone_float(const bsdf::LtcCoeffs<double>& k, const ClampedView& g,
                                            const Vec3d& c, double rho) {
  const bsdf::LtcCoeffs<float> kf = {float(k.a), float(k.b), float(k.c), float(k.d)};
  return bsdf::ltc_light_cone_sphere(kf.inv_m(), Vec3f(0, 0, 1), Vec3f(g.v), Vec3f(c), float(std::sin(rho)),
                                     bsdf::ltc_tail_weight(float(g.alpha)));
}

// A point of the LTC and aware blocks: its clamped view, the sphere light (cap) centred on its N·L direction,
// the GGX receiver, the table's LTC there and the cap's cone-clipped LTC with the tail (double and float).
struct GgxCapPoint {
  ClampedView g;
  Vec3d n, c;
  Cap cap;
  Receiver ggx;
  bsdf::LtcCoeffs<double> k;
  bsdf::LtcLightCone<double> lc;
  bsdf::LtcLightCone<float> lf;
};
GgxCapPoint ggx_cap_point(const VerifyPoint& in, const bsdf::LtcTable& table) {
  const ClampedView g = clamped_view(in);
  const Vec3d n(0, 0, 1), c = spherical_direction(in.n_dot_l, 0.0);
  const bsdf::LtcCoeffs<double> k = table.fetch(g.r, g.nv);
  return {g,
          n,
          c,
          Cap{c, in.rho},
          Receiver::ggx(g.alpha, g.v),
          k,
          bsdf::ltc_light_cone_sphere(k.inv_m(), n, g.v, c, std::sin(in.rho), bsdf::ltc_tail_weight(g.alpha)),
          sphere_cone_float(k, g, c, in.rho)};
}

// One row of errors per Sobol point i < count: fill(verify_point(i), row), in parallel.
template <size_t N, class Fill>
std::vector<std::array<double, N>> error_rows(int count, const VerifyOptions& a, const Fill& fill) {
  auto rows = std::vector<std::array<double, N>>(size_t(count));
  tbb::parallel_for(0, count, [&](int i) { fill(verify_point(uint32_t(i), a), rows[size_t(i)]); });
  return rows;
}

// A form of block B: its output name and its field. Each block's forms are one list, X(B, column, field
// [, suffix]): it makes both the enum of the columns of the block's rows of errors and the table of names
// and fields in the same order; the output name is the field's name (plus the suffix, where one is given).
template <class B>
struct Form {
  const char* name;
  ErrorSummary B::*field;
};
#define MSH_FORM_ENUM(B, column, field, ...) column,
#define MSH_FORM_ROW(B, column, field, ...) Form<B>{#field __VA_ARGS__, &B::field},

// The step forms: the exact cosine-weighted closed form (reference_step_area_cap), the solid-angle ratios of
// Mazonka 2012 and of Oat & Sander 2007, the point value at the centre, and the Lambert closed form used for
// a GGX receiver (against the exact GGX-weighted reference); then each fast form's area, float and point
// values; last, |Ω_OS − Ω_Mazonka| / Ω_cap for cap ∩ cone.
#define MSH_CAP_FORMS(X, B)                                 \
  X(B, kStepCosine, step_cosine_closed_form)                \
  X(B, kStepMazonka, step_solid_angle_mazonka)              \
  X(B, kStepOatSander, step_solid_angle_oat_sander)         \
  X(B, kStepPoint, step_point_at_centre)                    \
  X(B, kStepGgxReceiver, step_closed_form_for_ggx_receiver) \
  X(B, kBm, brinck_maximov_2016_area_n4)                    \
  X(B, kBmFloat, brinck_maximov_2016_area_n4_float)         \
  X(B, kBmPoint, brinck_maximov_2016_point_at_centre)       \
  X(B, kChan, chan_2018_area_n4)                            \
  X(B, kChanFloat, chan_2018_area_n4_float)                 \
  X(B, kChanPoint, chan_2018_point_at_centre)               \
  X(B, kPart1, part1_analytic_area_n4)                      \
  X(B, kPart1Float, part1_analytic_area_n4_float)           \
  X(B, kPart1Point, part1_analytic_point_at_centre)         \
  X(B, kOatSanderOmega, oat_sander_vs_mazonka_solid_angle_fraction_of_light)
enum CapForm { MSH_CAP_FORMS(MSH_FORM_ENUM, CapErrors) kCapForms };
constexpr std::array<Form<CapErrors>, kCapForms> kCapTable = {{MSH_CAP_FORMS(MSH_FORM_ROW, CapErrors)}};

#define MSH_GENERIC_FORMS(X, B)                        \
  X(B, kGenAlu, generic_vndf_alu_area_n4_float)        \
  X(B, kGenQuadOnly, generic_vndf_exact_mean_area_n4)  \
  X(B, kGenAluPoint, generic_vndf_alu_point_at_centre) \
  X(B, kGenAluPointError, generic_vndf_alu_point_error_at_centre, " (the fit alone)")
enum GenericForm { MSH_GENERIC_FORMS(MSH_FORM_ENUM, GenericCapErrors) kGenericForms };
constexpr std::array<Form<GenericCapErrors>, kGenericForms> kGenericTable = {
    {MSH_GENERIC_FORMS(MSH_FORM_ROW, GenericCapErrors)}};

#define MSH_SHAPE_FORMS(X, B)                                  \
  X(B, kDiskStep, disk_step_equivalent_cap)                    \
  X(B, kDiskStepFloat, disk_step_equivalent_cap_float)         \
  X(B, kDiskStepPoint, disk_step_point_at_centre)              \
  X(B, kDiskBm, disk_brinck_maximov_2016_equivalent_cap_n4)    \
  X(B, kDiskBmPoint, disk_brinck_maximov_2016_point_at_centre) \
  X(B, kDiskChan, disk_chan_2018_equivalent_cap_n4)            \
  X(B, kDiskPart1, disk_part1_analytic_equivalent_cap_n4)      \
  X(B, kRectStep, rect_step_equivalent_cap)                    \
  X(B, kRectStepFloat, rect_step_equivalent_cap_float)         \
  X(B, kRectStepPoint, rect_step_point_at_centre)              \
  X(B, kRectBm, rect_brinck_maximov_2016_equivalent_cap_n4)    \
  X(B, kRectBmPoint, rect_brinck_maximov_2016_point_at_centre) \
  X(B, kRectChan, rect_chan_2018_equivalent_cap_n4)            \
  X(B, kRectPart1, rect_part1_analytic_equivalent_cap_n4)
enum ShapeForm { MSH_SHAPE_FORMS(MSH_FORM_ENUM, ShapeErrors) kShapeForms };
constexpr std::array<Form<ShapeErrors>, kShapeForms> kShapeTable = {
    {MSH_SHAPE_FORMS(MSH_FORM_ROW, ShapeErrors)}};

#define MSH_LTC_FORMS(X, B)                                                                  \
  X(B, kCapStepGgx, ltc_cap_step_ggx_cone_clip)                                              \
  X(B, kCapStepGgxFloat, ltc_cap_step_ggx_cone_clip_float)                                   \
  X(B, kCapStepGgxNoTail, ltc_cap_step_ggx_cone_clip_no_tail)                                \
  X(B, kCapStepGgxLambertClosedForm, ltc_cap_step_ggx_lambert_closed_form)                   \
  X(B, kCapStepGgxRepresentative, ltc_cap_step_ggx_point_at_ltc_representative_direction)    \
  X(B, kCapBmGgx, ltc_cap_brinck_maximov_2016_ggx_cone_clip_n4)                              \
  X(B, kCapBmGgxLambertProductRule, ltc_cap_brinck_maximov_2016_ggx_lambert_product_rule)    \
  X(B, kCapBmGgxRepresentative, ltc_cap_brinck_maximov_2016_ggx_point_at_ltc_representative) \
  X(B, kCapChanGgx, ltc_cap_chan_2018_ggx_cone_clip_n4)                                      \
  X(B, kCapPart1Ggx, ltc_cap_part1_analytic_ggx_cone_clip_n4)                                \
  X(B, kDiskStepGgx, ltc_disk_step_ggx_cone_clip)                                            \
  X(B, kDiskStepGgxEquivalentCap, ltc_disk_step_ggx_lambert_equivalent_cap)                  \
  X(B, kDiskBmGgx, ltc_disk_brinck_maximov_2016_ggx_cone_clip_n4)                            \
  X(B, kRectStepGgx, ltc_rect_step_ggx_cone_clip)                                            \
  X(B, kRectStepGgxEquivalentCap, ltc_rect_step_ggx_lambert_equivalent_cap)                  \
  X(B, kRectStepGgxRepresentative, ltc_rect_step_ggx_point_at_ltc_representative_direction)  \
  X(B, kRectBmGgx, ltc_rect_brinck_maximov_2016_ggx_cone_clip_n4)                            \
  X(B, kDiskStepLambert, ltc_disk_step_lambert_cone_clip)                                    \
  X(B, kDiskBmLambert, ltc_disk_brinck_maximov_2016_lambert_cone_clip_n4)                    \
  X(B, kDiskChanLambert, ltc_disk_chan_2018_lambert_cone_clip_n4)                            \
  X(B, kDiskPart1Lambert, ltc_disk_part1_analytic_lambert_cone_clip_n4)                      \
  X(B, kRectStepLambert, ltc_rect_step_lambert_cone_clip)                                    \
  X(B, kRectStepLambertFloat, ltc_rect_step_lambert_cone_clip_float)                         \
  X(B, kRectBmLambert, ltc_rect_brinck_maximov_2016_lambert_cone_clip_n4)                    \
  X(B, kRectChanLambert, ltc_rect_chan_2018_lambert_cone_clip_n4)                            \
  X(B, kRectPart1Lambert, ltc_rect_part1_analytic_lambert_cone_clip_n4)
enum LtcForm { MSH_LTC_FORMS(MSH_FORM_ENUM, LtcErrors) kLtcForms };
constexpr std::array<Form<LtcErrors>, kLtcForms> kLtcTable = {{MSH_LTC_FORMS(MSH_FORM_ROW, LtcErrors)}};

#define MSH_AWARE_FORMS(X, B)                                                      \
  X(B, kGenLtcExactMean, ggx_cap_generic_vndf_exact_mean_ltc_cone_clip_n4)         \
  X(B, kGenLtcAlu, ggx_cap_generic_vndf_alu_ltc_cone_clip_n4_float)                \
  X(B, kGenLambertProductRuleAlu, ggx_cap_generic_vndf_alu_lambert_product_rule)   \
  X(B, kGenRepresentative, ggx_cap_generic_vndf_exact_point_at_ltc_representative) \
  X(B, kSpecLtc, ggx_cap_specular_aware_mean_ltc_cone_clip_n4)                     \
  X(B, kSpecLtcFloat, ggx_cap_specular_aware_mean_ltc_cone_clip_n4_float)          \
  X(B, kSpecRepresentative, ggx_cap_specular_aware_point_at_ltc_representative)
enum AwareForm { MSH_AWARE_FORMS(MSH_FORM_ENUM, AwareErrors) kAwareForms };
constexpr std::array<Form<AwareErrors>, kAwareForms> kAwareTable = {
    {MSH_AWARE_FORMS(MSH_FORM_ROW, AwareErrors)}};

#define MSH_DIFFUSE_AWARE_FORMS(X, B)                                         \
  X(B, kDiffuseAwareAlu, lambert_cap_diffuse_aware_alu_product_rule_n4_float) \
  X(B, kDiffuseAwareAluPoint, lambert_cap_diffuse_aware_alu_point_at_centre)
enum DiffuseAwareForm { MSH_DIFFUSE_AWARE_FORMS(MSH_FORM_ENUM, DiffuseAwareErrors) kDiffuseAwareForms };
constexpr std::array<Form<DiffuseAwareErrors>, kDiffuseAwareForms> kDiffuseAwareTable = {
    {MSH_DIFFUSE_AWARE_FORMS(MSH_FORM_ROW, DiffuseAwareErrors)}};
#undef MSH_FORM_ENUM
#undef MSH_FORM_ROW

// One summary per form (column) of a block's rows (at least one row).
template <class B, size_t N>
B summarize_block(const std::vector<std::array<double, N>>& rows, const std::array<Form<B>, N>& forms) {
  B block;
  for (size_t f = 0; f < N; ++f) {
    std::vector<double> e;
    for (const auto& r : rows) e.push_back(r[f]);
    block.*forms[f].field = *summarize_errors(e);
  }
  return block;
}

// Closed-form terms (cheap exact references): one row of errors per point and form.
CapErrors cap_errors(const VerifyOptions& a) {
  const auto rows = error_rows<kCapForms>(a.points, a, [&](const VerifyPoint& in, auto& r) {
    const Cap cap{spherical_direction(in.n_dot_l, 0.0), in.rho};
    auto exact = [&](const auto& t) { return area_micro_shadowing_exact(cap, Receiver::lambert(), t); };
    const double step = exact(reference_step_term(in.visibility));
    r[kStepCosine] = micro_shadowing::reference_step_area_cap(in.visibility, in.n_dot_l, in.rho) - step;
    r[kStepMazonka] =
        micro_shadowing::reference_step_area_cap_solid_angle(in.visibility, in.n_dot_l, in.rho) - step;
    r[kStepOatSander] =
        micro_shadowing::reference_step_area_cap_oat_sander(in.visibility, in.n_dot_l, in.rho) - step;
    r[kStepPoint] = micro_shadowing::reference_step(in.visibility, in.n_dot_l) - step;
    {
      const Vec3d v = spherical_direction(std::max(0.05, in.n_dot_v), in.phi_v);
      const Receiver ggx = Receiver::ggx(roughness_to_alpha(std::max(0.1, in.roughness)), v);
      r[kStepGgxReceiver] = micro_shadowing::reference_step_area_cap(in.visibility, in.n_dot_l, in.rho) -
                            area_micro_shadowing_exact(cap, ggx, reference_step_term(in.visibility));
    }
    const float Vf = float(in.visibility), lf = float(in.n_dot_l), rf = float(in.rho);
    const double bm = exact(brinck_maximov_2016_term(in.visibility));
    r[kBm] = micro_shadowing::brinck_maximov_2016_area_cap(in.visibility, in.n_dot_l, in.rho) - bm;
    r[kBmFloat] = double(micro_shadowing::brinck_maximov_2016_area_cap(Vf, lf, rf)) - bm;
    r[kBmPoint] = micro_shadowing::brinck_maximov_2016(in.visibility, in.n_dot_l) - bm;
    const double ch = exact(chan_2018_term(in.visibility));
    r[kChan] = micro_shadowing::chan_2018_area_cap(in.visibility, in.n_dot_l, in.rho) - ch;
    r[kChanFloat] = double(micro_shadowing::chan_2018_area_cap(Vf, lf, rf)) - ch;
    r[kChanPoint] = micro_shadowing::chan_2018(in.visibility, in.n_dot_l) - ch;
    const double p1 = exact(part1_analytic_term(in.visibility));
    r[kPart1] = micro_shadowing::part1_analytic_area_cap(in.visibility, in.n_dot_l, in.rho) - p1;
    r[kPart1Float] = double(micro_shadowing::part1_analytic_area_cap(Vf, lf, rf)) - p1;
    r[kPart1Point] = micro_shadowing::part1_analytic(in.visibility, in.n_dot_l) - p1;
    const double t = std::acos(micro_shadowing::cone_cos_from_visibility(in.visibility)),
                 th = std::acos(in.n_dot_l);
    r[kOatSanderOmega] = (micro_shadowing::cap_intersection_solid_angle_oat_sander(in.rho, t, th) -
                          micro_shadowing::cap_intersection_solid_angle(in.rho, t, th)) /
                         (2 * kPi<double> * (1 - std::cos(in.rho)));
  });
  return summarize_block(rows, kCapTable);
}

// The generic term's azimuth mean (Lambertian receiver): its ALU fit through the product rule, against
// the exact quadrature of the exact azimuth mean; and the quadrature alone (exact mean as M).
GenericCapErrors generic_errors(const VerifyOptions& a) {
  const auto rows = error_rows<kGenericForms>(a.generic_points, a, [&](const VerifyPoint& in, auto& r) {
    const double alpha = roughness_to_alpha(in.roughness);
    auto mean = [&](double z) {
      return micro_shadowing::generic_vndf_exact_azimuth_mean(in.visibility, alpha, z, in.n_dot_v);
    };
    const Cap cap{spherical_direction(in.n_dot_l, 0.0), in.rho};
    const PointTerm term{
        [&](const Vec3d& l) { return mean(std::clamp(l.z, 0.0, 1.0)); }, {1 - 2 * in.visibility}, true};
    const double ex = area_micro_shadowing_exact(cap, Receiver::lambert(), term, {1e-7});
    r[kGenAlu] =
        double(micro_shadowing::generic_vndf_alu_area_cap(
            float(in.visibility), float(in.n_dot_l), float(in.n_dot_v), float(in.roughness), float(in.rho))) -
        ex;
    r[kGenQuadOnly] =
        micro_shadowing::area_cap_lambert(mean, in.n_dot_l, in.rho,
                                          micro_shadowing::generic_vndf_kinks(in.visibility, in.roughness)) -
        ex;
    r[kGenAluPoint] = double(micro_shadowing::generic_vndf_alu(float(in.visibility), float(in.n_dot_l),
                                                               float(in.n_dot_v), float(in.roughness))) -
                      ex;
    r[kGenAluPointError] = double(micro_shadowing::generic_vndf_alu(float(in.visibility), float(in.n_dot_l),
                                                                    float(in.n_dot_v), float(in.roughness))) -
                           mean(in.n_dot_l);
  });
  return summarize_block(rows, kGenericTable);
}

// Disk and rect lights, Lambertian receiver: the equivalent cap (same vector form factor) with the cap
// forms, against the exact quadrature over the true shape. Domain: V, centre N·L ∈ [0, 1]; ρ (disk edge,
// rect half-width) ∈ [ρmin, ρmax]; rect half-height = ρ · aspect, aspect ∈ [0.25, 1]; tilt ∈ [−60°, 60°]
// from facing the point; roll ∈ [0°, 360°).
ShapeErrors shape_errors(const VerifyOptions& a) {
  const auto rows = error_rows<kShapeForms>(a.shape_points, a, [&](const VerifyPoint& in, auto& r) {
    const ShapeLights sl = shape_lights(in);
    const Disk& disk = sl.disk;
    const Quad& quad = sl.quad;
    const Vec3d Fd = micro_shadowing::disk_vector_form_factor(disk.center, disk.normal, disk.radius);
    const Vec3d Fr = micro_shadowing::polygon_vector_form_factor(quad.corners.data(), 4);
    auto shape_rows = [&](const Shape& sh, const Vec3d& F, float step_float, int base) {
      auto exact = [&](const auto& t) {
        return area_micro_shadowing_exact(sh, Receiver::lambert(), t, {1e-7});
      };
      const micro_shadowing::EquivalentCap<double> e = micro_shadowing::equivalent_cap(F);
      const double step = exact(reference_step_term(in.visibility));
      r[size_t(base + 0)] = micro_shadowing::reference_step_area_cap(in.visibility, e.n_dot_l, e.rho) - step;
      r[size_t(base + 1)] = double(step_float) - step;
      r[size_t(base + 2)] = micro_shadowing::reference_step(in.visibility, in.n_dot_l) - step;
      const double bm = exact(brinck_maximov_2016_term(in.visibility));
      r[size_t(base + 3)] =
          micro_shadowing::brinck_maximov_2016_area_cap(in.visibility, e.n_dot_l, e.rho) - bm;
      r[size_t(base + 4)] = micro_shadowing::brinck_maximov_2016(in.visibility, in.n_dot_l) - bm;
      r[size_t(base + 5)] = micro_shadowing::chan_2018_area_cap(in.visibility, e.n_dot_l, e.rho) -
                            exact(chan_2018_term(in.visibility));
      r[size_t(base + 6)] = micro_shadowing::part1_analytic_area_cap(in.visibility, e.n_dot_l, e.rho) -
                            exact(part1_analytic_term(in.visibility));
    };
    shape_rows(
        disk, Fd,
        micro_shadowing::reference_step_area_equivalent_cap(
            float(in.visibility),
            micro_shadowing::disk_vector_form_factor(
                Vec3f(float(disk.center.x), float(disk.center.y), float(disk.center.z)),
                Vec3f(float(disk.normal.x), float(disk.normal.y), float(disk.normal.z)), float(disk.radius))),
        kDiskStep);
    shape_rows(
        quad, Fr,
        micro_shadowing::reference_step_area_equivalent_cap(
            float(in.visibility), micro_shadowing::polygon_vector_form_factor(sl.quad_float.data(), 4)),
        kRectStep);
  });
  return summarize_block(rows, kShapeTable);
}

// The cone-clipped LTC forms (bsdf/ltc_shading.h): every light is a polygon (a sphere and a disk as their
// 16-gons), the visibility cone its 16-gon. GGX receiver (roughness r ∈ [0.1, 1], N·V ∈ [0.05, 1], view
// azimuth ∈ [0, π]) with the table fetched bilinearly and the cosine tail, against the exact GGX-weighted
// quadrature; Lambertian receiver (identity LTC, no tail) for disks and rects. Same shape domain as above.
LtcErrors ltc_errors(const VerifyOptions& a, const bsdf::LtcTable& table) {
  const auto rows = error_rows<kLtcForms>(a.ltc_points, a, [&](const VerifyPoint& in, auto& row) {
    const GgxCapPoint p = ggx_cap_point(in, table);
    const Vec3d &n = p.n, &v = p.g.v, &c = p.c;
    const Cap& cap = p.cap;
    const ShapeLights sl = shape_lights(in);
    const Disk& disk = sl.disk;
    const Quad& quad = sl.quad;
    const Receiver &ggx = p.ggx, lam = Receiver::lambert();
    auto exact = [&](const Shape& sh, const Receiver& rc, const auto& t) {
      return area_micro_shadowing_exact(sh, rc, t, {1e-7});
    };
    const double V = in.visibility, ct = micro_shadowing::cone_cos_from_visibility(V);
    const auto step_t = reference_step_term(V);
    const auto bm_t = brinck_maximov_2016_term(V);
    auto bm = [V](double z) { return micro_shadowing::brinck_maximov_2016(V, z); };
    auto chan = [V](double z) { return micro_shadowing::chan_2018(V, z); };
    auto part1 = [V](double z) { return micro_shadowing::part1_analytic(V, z); };
    const auto bk = micro_shadowing::brinck_maximov_2016_kinks(V);
    const auto chan_t = chan_2018_term(V), part1_t = part1_analytic_term(V);
    const auto chan_k = micro_shadowing::chan_2018_kinks(V),
               part1_k = micro_shadowing::part1_analytic_kinks(V);
    const bsdf::LtcCoeffs<double>& k = p.k;
    const bsdf::Mat3<double> minv = k.inv_m(), id{};
    const double tail = bsdf::ltc_tail_weight(p.g.alpha);
    const auto& lc = p.lc;
    const auto ld = bsdf::ltc_light_cone_disk(minv, n, v, disk.center, disk.normal, disk.radius, tail);
    const auto lr = bsdf::ltc_light_cone_polygon(minv, n, v, quad.corners.data(), 4, tail);
    const auto ldl = bsdf::ltc_light_cone_disk(id, n, v, disk.center, disk.normal, disk.radius);
    const auto lrl = bsdf::ltc_light_cone_polygon(id, n, v, quad.corners.data(), 4);
    const auto rep_cap = bsdf::ltc_shade_sphere(k, n, v, c, std::sin(in.rho));
    const auto rep_rect = bsdf::ltc_shade_polygon(k, n, v, quad.corners.data(), 4);
    const auto eqd = micro_shadowing::equivalent_cap(
        micro_shadowing::disk_vector_form_factor(disk.center, disk.normal, disk.radius));
    const auto eqr =
        micro_shadowing::equivalent_cap(micro_shadowing::polygon_vector_form_factor(quad.corners.data(), 4));
    const double sc = exact(cap, ggx, step_t), bc = exact(cap, ggx, bm_t);
    row[kCapStepGgx] = bsdf::ltc_reference_step_area(lc, ct) - sc;
    row[kCapStepGgxFloat] = double(bsdf::ltc_reference_step_area(p.lf, float(ct))) - sc;
    row[kCapStepGgxNoTail] =
        bsdf::ltc_reference_step_area(bsdf::ltc_light_cone_sphere(minv, n, v, c, std::sin(in.rho)), ct) - sc;
    row[kCapStepGgxLambertClosedForm] = micro_shadowing::reference_step_area_cap(V, in.n_dot_l, in.rho) - sc;
    row[kCapStepGgxRepresentative] =
        bsdf::ltc_ms_at_representative(rep_cap,
                                       [&](double z) { return micro_shadowing::reference_step(V, z); }) -
        sc;
    row[kCapBmGgx] = bsdf::ltc_micro_shadowing_area(bm, lc, bk) - bc;
    row[kCapBmGgxLambertProductRule] =
        micro_shadowing::brinck_maximov_2016_area_cap(V, in.n_dot_l, in.rho) - bc;
    row[kCapBmGgxRepresentative] = bsdf::ltc_ms_at_representative(rep_cap, bm) - bc;
    row[kCapChanGgx] = bsdf::ltc_micro_shadowing_area(chan, lc, chan_k) - exact(cap, ggx, chan_t);
    row[kCapPart1Ggx] = bsdf::ltc_micro_shadowing_area(part1, lc, part1_k) - exact(cap, ggx, part1_t);
    const double sd = exact(disk, ggx, step_t), sr = exact(quad, ggx, step_t);
    row[kDiskStepGgx] = bsdf::ltc_reference_step_area(ld, ct) - sd;
    row[kDiskStepGgxEquivalentCap] = micro_shadowing::reference_step_area_cap(V, eqd.n_dot_l, eqd.rho) - sd;
    row[kDiskBmGgx] = bsdf::ltc_micro_shadowing_area(bm, ld, bk) - exact(disk, ggx, bm_t);
    row[kRectStepGgx] = bsdf::ltc_reference_step_area(lr, ct) - sr;
    row[kRectStepGgxEquivalentCap] = micro_shadowing::reference_step_area_cap(V, eqr.n_dot_l, eqr.rho) - sr;
    row[kRectStepGgxRepresentative] =
        bsdf::ltc_ms_at_representative(rep_rect,
                                       [&](double z) { return micro_shadowing::reference_step(V, z); }) -
        sr;
    row[kRectBmGgx] = bsdf::ltc_micro_shadowing_area(bm, lr, bk) - exact(quad, ggx, bm_t);
    // The four N·L-only terms of a Lambertian receiver (identity LTC) through the cone-clipped form over
    // `sh`, against the exact quadrature; returns the exact step integral.
    auto lambert_rows = [&](const Shape& sh, const auto& cone, int step, int bm_i, int chan_i, int part1_i) {
      const double s = exact(sh, lam, step_t);
      row[size_t(step)] = bsdf::ltc_reference_step_area(cone, ct) - s;
      row[size_t(bm_i)] = bsdf::ltc_micro_shadowing_area(bm, cone, bk) - exact(sh, lam, bm_t);
      row[size_t(chan_i)] = bsdf::ltc_micro_shadowing_area(chan, cone, chan_k) - exact(sh, lam, chan_t);
      row[size_t(part1_i)] = bsdf::ltc_micro_shadowing_area(part1, cone, part1_k) - exact(sh, lam, part1_t);
      return s;
    };
    lambert_rows(disk, ldl, kDiskStepLambert, kDiskBmLambert, kDiskChanLambert, kDiskPart1Lambert);
    const double srl =
        lambert_rows(quad, lrl, kRectStepLambert, kRectBmLambert, kRectChanLambert, kRectPart1Lambert);
    // The rect's step in float, as a shader evaluates it (same exact integral).
    const auto lrf =
        bsdf::ltc_light_cone_polygon(bsdf::Mat3<float>{}, Vec3f(0, 0, 1), Vec3f(v), sl.quad_float.data(), 4);
    row[kRectStepLambertFloat] = double(bsdf::ltc_reference_step_area(lrf, float(ct))) - srl;
  });
  return summarize_block(rows, kLtcTable);
}

// The generic and specular-aware terms over a sphere light, GGX receiver (same domain as the LTC block):
// the azimuth means (generic: exact mean and its ALU fit; specular-aware: closed form) through the
// cone-clipped LTC product rule, against the exact quadrature of the FULL-direction term over the light
// (the light at azimuth 0, the view at φ_v).
AwareErrors aware_errors(const VerifyOptions& a, const bsdf::LtcTable& table) {
  const auto rows = error_rows<kAwareForms>(a.aware_points, a, [&](const VerifyPoint& in, auto& row) {
    const GgxCapPoint p = ggx_cap_point(in, table);
    const double nv = p.g.nv, r = p.g.r, alpha = p.g.alpha;
    const Vec3d& v = p.g.v;
    const Cap& cap = p.cap;
    const Receiver& ggx = p.ggx;
    const double V = in.visibility;
    const bsdf::LtcLightCone<double>& lc = p.lc;
    const bsdf::LtcLightCone<float>& lf = p.lf;
    const Vec3d rep = bsdf::ltc_shade_sphere(p.k, p.n, v, p.c, std::sin(in.rho)).direction;
    const double gen = area_micro_shadowing_exact(cap, ggx, generic_vndf_term(V, alpha, alpha, v), {1e-6});
    const auto gk = micro_shadowing::generic_vndf_kinks(V, r);
    row[kGenLtcExactMean] =
        bsdf::ltc_micro_shadowing_area(
            [&](double z) { return micro_shadowing::generic_vndf_exact_azimuth_mean(V, alpha, z, nv); }, lc,
            gk) -
        gen;
    row[kGenLtcAlu] =
        double(bsdf::ltc_micro_shadowing_area(
            [&](float z) { return micro_shadowing::generic_vndf_alu(float(V), z, float(nv), float(r)); }, lf,
            micro_shadowing::generic_vndf_kinks(float(V), float(r)))) -
        gen;
    row[kGenLambertProductRuleAlu] = double(micro_shadowing::generic_vndf_alu_area_cap(
                                         float(V), float(in.n_dot_l), float(nv), float(r), float(in.rho))) -
                                     gen;
    row[kGenRepresentative] = micro_shadowing::generic_vndf_exact(V, alpha, alpha, v, rep) - gen;
    const double spec = area_micro_shadowing_exact(cap, ggx, specular_aware_term(V, v), {1e-6});
    row[kSpecLtc] =
        bsdf::ltc_micro_shadowing_area(
            [&](double z) { return micro_shadowing::specular_aware_azimuth_mean(V, alpha, z, nv); }, lc,
            micro_shadowing::specular_aware_kinks(V, nv)) -
        spec;
    row[kSpecLtcFloat] =
        double(bsdf::ltc_micro_shadowing_area(
            [&](float z) {
              return micro_shadowing::specular_aware_azimuth_mean(float(V), float(alpha), z, float(nv));
            },
            lf, micro_shadowing::specular_aware_kinks(float(V), float(nv)))) -
        spec;
    row[kSpecRepresentative] = micro_shadowing::specular_aware(V, v, rep) - spec;
  });
  return summarize_block(rows, kAwareTable);
}

// The diffuse-aware term, Lambertian receiver: its ALU fit through the cap product rule against the exact
// quadrature of the exact azimuth mean (every point value is a 2D VNDF quadrature: ~10 s CPU per light).
DiffuseAwareErrors diffuse_aware_errors(const VerifyOptions& a) {
  const auto rows =
      error_rows<kDiffuseAwareForms>(a.diffuse_aware_points, a, [&](const VerifyPoint& in, auto& row) {
        const ClampedView g = clamped_view(in);
        const double nv = g.nv, r = g.r, alpha = g.alpha;
        const Cap cap{spherical_direction(in.n_dot_l, 0.0), in.rho};
        const double ex = area_micro_shadowing_exact(
            cap, Receiver::lambert(),
            diffuse_aware_azimuth_mean_term(in.visibility, alpha, nv,
                                            micro_shadowing::DiffuseAwareForm::Reciprocal),
            {1e-6});
        const float Vf = float(in.visibility), nvf = float(nv), rf = float(r);
        row[kDiffuseAwareAlu] =
            double(micro_shadowing::area_cap_lambert(
                [&](float z) { return micro_shadowing::diffuse_aware_alu(Vf, z, nvf, rf); },
                float(in.n_dot_l), float(in.rho), micro_shadowing::diffuse_aware_kinks(Vf))) -
            ex;
        row[kDiffuseAwareAluPoint] =
            double(micro_shadowing::diffuse_aware_alu(Vf, float(in.n_dot_l), nvf, rf)) - ex;
      });
  return summarize_block(rows, kDiffuseAwareTable);
}

// Appends every form of `forms` by name, with its summary in `block` (none when the block is empty).
template <class B, size_t N>
void add_named(std::vector<NamedErrorSummary>& out, const B* block, const std::array<Form<B>, N>& forms) {
  for (const Form<B>& f : forms)
    out.push_back({f.name, block ? std::optional<ErrorSummary>(block->*f.field) : std::nullopt});
}

}  // namespace

void validate(const VerifyOptions& a) {
  if (a.points < 1 || a.points > (1 << 20)) throw InputError("--points must be in [1, 2^20]");
  if (a.shape_points < 0 || a.shape_points > (1 << 16))
    throw InputError("--shape-points must be in [0, 2^16]");
  if (a.generic_points < 0 || a.generic_points > (1 << 16))
    throw InputError("--generic-points must be in [0, 2^16]");
  if (a.ltc_points < 0 || a.ltc_points > (1 << 16)) throw InputError("--ltc-points must be in [0, 2^16]");
  if (a.aware_points < 0 || a.aware_points > (1 << 16))
    throw InputError("--aware-points must be in [0, 2^16]");
  if (a.diffuse_aware_points < 0 || a.diffuse_aware_points > (1 << 16))
    throw InputError("--diffuse-aware-points must be in [0, 2^16]");
  if (!(a.rho_min_deg >= 0 && a.rho_min_deg <= a.rho_max_deg && a.rho_max_deg <= 90))
    throw InputError("--rho-min-deg and --rho-max-deg must satisfy 0 <= min <= max <= 90");
}

VerifyPoint verify_point(uint32_t i, const VerifyOptions& a) {
  const Vec2d p = sobol_2d<double>(i, 0x51u), q = sobol_2d<double>(i, 0x9e37u),
              s = sobol_2d<double>(i, 0x7f4au), o = sobol_2d<double>(i, 0x3c6eu),
              w = sobol_2d<double>(i, 0x2545u);
  return {p.x,
          p.y,
          (a.rho_min_deg + (a.rho_max_deg - a.rho_min_deg) * q.x) * kDeg,
          q.y,
          s.x,
          s.y * kPi<double>,
          (-60 + 120 * o.x) * kDeg,
          2 * kPi<double> * o.y,
          0.25 + 0.75 * w.x};
}

std::optional<ErrorSummary> summarize_errors(std::vector<double> err) {
  if (err.empty()) return std::nullopt;
  double ss = 0, bias = 0;
  for (double& e : err) ss += e * e, bias += e, e = std::abs(e);
  std::sort(err.begin(), err.end());
  const size_t n = err.size();
  auto q = [&](double p) { return err[std::min(n - 1, size_t(std::ceil(p * double(n))) - (p > 0 ? 1 : 0))]; };
  return ErrorSummary{n, 255 * std::sqrt(ss / double(n)), 255 * bias / double(n), 255 * q(0.99),
                      255 * err.back()};
}

VerifyResult verify_area_lights(const VerifyOptions& a) {
  validate(a);
  VerifyResult r;
  r.options = a;
  // The LTC table first, so that a bad file fails before any work.
  r.ltc_table = "none";
  bsdf::LtcTable table;
  if (a.ltc_points > 0 || a.aware_points > 0) {
    if (a.ltc.empty()) {
      bsdf::LtcFitOptions fo;
      fo.size = 16;
      table = bsdf::fit_ltc_table(fo);
      r.ltc_table = "16x16 table fitted in process (bake ltc --size 16)";
    } else {
      table = bsdf::load_ltc_table(a.ltc);
      r.ltc_table = a.ltc;
    }
  }
  r.cap = cap_errors(a);
  if (a.generic_points > 0) r.generic = generic_errors(a);
  if (a.shape_points > 0) r.shapes = shape_errors(a);
  if (a.ltc_points > 0) r.ltc = ltc_errors(a, table);
  if (a.aware_points > 0) r.aware = aware_errors(a, table);
  if (a.diffuse_aware_points > 0) r.diffuse_aware = diffuse_aware_errors(a);
  return r;
}

std::vector<NamedErrorSummary> named_errors(const VerifyResult& r) {
  std::vector<NamedErrorSummary> out;
  add_named(out, &r.cap, kCapTable);
  add_named(out, r.generic ? &*r.generic : nullptr, kGenericTable);
  add_named(out, r.shapes ? &*r.shapes : nullptr, kShapeTable);
  add_named(out, r.ltc ? &*r.ltc : nullptr, kLtcTable);
  add_named(out, r.aware ? &*r.aware : nullptr, kAwareTable);
  add_named(out, r.diffuse_aware ? &*r.diffuse_aware : nullptr, kDiffuseAwareTable);
  return out;
}

nlohmann::json to_json(const VerifyResult& r) {
  const VerifyOptions& a = r.options;
  nlohmann::json forms = nlohmann::json::object();
  for (const NamedErrorSummary& f : named_errors(r)) {
    if (!f.summary) {
      forms[f.name] = nullptr;
      continue;
    }
    const ErrorSummary& s = *f.summary;
    forms[f.name] = {{"count", s.count},
                     {"rms_255", s.rms_255},
                     {"bias_255", s.bias_255},
                     {"p99_255", s.p99_255},
                     {"max_255", s.max_255}};
  }
  return {
      {"domain",
       {{"visibility", {0, 1}},
        {"ndotl_centre", {0, 1}},
        {"light_radius_deg", {a.rho_min_deg, a.rho_max_deg}},
        {"ndotv", {0, 1}},
        {"roughness", {0, 1}},
        {"sampling", "padded 2D Owen-scrambled Sobol"},
        {"light", "spherical cap centred on the N.L direction, Lambertian receiver unless stated"}}},
      {"points", a.points},
      {"generic_points", a.generic_points},
      {"shape_points", a.shape_points},
      {"ltc_points", a.ltc_points},
      {"ltc_table", r.ltc_table},
      {"aware_points", a.aware_points},
      {"diffuse_aware_points", a.diffuse_aware_points},
      {"ltc_domain",
       "sphere (cap), disk and rect lights as above; GGX receiver: roughness in [0.1, 1], N.V in [0.05, 1], "
       "view azimuth in [0, pi], LTC fetched bilinearly, tail weight 1.5 alpha^1.5, against the exact "
       "GGX-weighted quadrature; Lambertian receiver: identity LTC, no tail; light and cone as 16-gons"},
      {"shape_domain",
       "disk (edge radius rho) and rect (half-width rho, half-height rho * aspect, aspect in [0.25, 1]) "
       "centred on the N.L direction, tilt in [-60, 60] deg from facing the point, roll in [0, 360) deg; "
       "Lambertian "
       "receiver; fast form = the cap forms at the equivalent cap (same vector form factor)"},
      {"errors", forms}};
}

}  // namespace msh::area
