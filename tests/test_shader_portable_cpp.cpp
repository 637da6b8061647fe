// shaders/portable/*.h compiled as C++ (<microshadow/shader/portable.h>), one TEST per module, against the
// references of the lavapipe tests (tests/test_shaders_*.cpp) on their inputs (tests/support/*_inputs.h):
// C++ float templates, double closed forms, C++ double code. Bounds: the float32 precision each portable
// comment states; exact equality where the C++ build runs the C++ float template's operations in its order
// (or integer code), said at each check. Also: finite results at degenerate inputs, and a clamped input set
// to NaN giving the value at its lower bound (the prelude's min/max return the non-NaN operand).
#include <gtest/gtest.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/micro_shadowing_anisotropic.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>
#include <microshadow/reference/micro_shadowing_exact.h>
#include <microshadow/render/directional_codec.h>
#include <microshadow/shader/portable.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "support/area_inputs.h"
#include "support/aware_inputs.h"
#include "support/bounded_checks.h"
#include "support/bump_inputs.h"
#include "support/directional_inputs.h"
#include "support/fit_inputs.h"
#include "support/ltc_inputs.h"
#include "support/micro_shadowing_inputs.h"

using namespace msh;
namespace sh = msh::shader;
namespace ms = msh::micro_shadowing;
using sh::float2;
using sh::float3;
using sh::float4;
using test::Family;
using test::nan_clamp_violations;

namespace {

const double kDeg = kPi<double> / 180;

float3 f3(const Vec3f& v) { return float3(v.x, v.y, v.z); }
float3 f3(const Vec3d& v) { return float3(float(v.x), float(v.y), float(v.z)); }
Vec3d d3(const float3& v) { return Vec3d(v.x, v.y, v.z); }

// A table as the prelude's texture view: RGBA texels, x fastest, then y, then z (io::Volume's order); fewer
// channels padded with 0, as the shader tests upload them.
struct Tex {
  std::vector<float4> t;
  int w, h, d;
  explicit Tex(const io::Volume& v) : t(v.texel_count()), w(v.width), h(v.height), d(v.depth) {
    for (std::size_t i = 0; i < t.size(); ++i)
      for (int c = 0; c < v.channels; ++c) t[i][c] = v.data[i * std::size_t(v.channels) + std::size_t(c)];
  }
  sh::Texture3D t3() const { return {t.data(), w, h, d}; }
  sh::Texture2D t2() const { return {t.data(), w, h}; }
};

}  // namespace

namespace {
namespace ms_checks {
using namespace test::ms_inputs;

// A record's inputs as both checks take them: float vectors for the portable functions and the C++ float
// templates, double ones and the projected roughness in double for the references.
struct RecordInputs {
  explicit RecordInputs(const Record& x)
      : v(f3(x.v)),
        l(f3(x.l)),
        a(x.ax, x.ay),
        ggx(x.ax, x.ay),
        pa_vf(sh::msh_ggx_projected_alpha(v, a)),
        pa_lf(sh::msh_ggx_projected_alpha(l, a)),
        vd(x.v),
        ld(x.l),
        pa_v(ref_projected_alpha(vd, x.ax, x.ay)),
        pa_l(ref_projected_alpha(ld, x.ax, x.ay)) {}
  const float3 v, l;
  const float2 a;
  const GGX<float> ggx;
  const float pa_vf, pa_lf;  // the portable projected roughness along v and l
  const Vec3d vd, ld;
  const double pa_v, pa_l;
};

// The closed forms, cone cos, early-out, azimuth cos and projected roughness are the C++ templates' float
// expressions in the same order (std::sqrt, std::pow): identical. Sobol/Hammersley: integer code. Against
// double: each function's stated bound.
void closed_forms(const Record& x, const RecordInputs& in, Family& same, Family& dbl) {
  const auto& [v, l, a, ggx, pa_vf, pa_lf, vd, ld, pa_v, pa_l] = in;
  const float vis = x.vis, nl = x.nl;
  const bool zero = sh::msh_ms_exact_zero(vis, nl);
  same.eq("differ", sh::msh_ms_reference_step(vis, nl), ms::reference_step(vis, nl));
  same.eq("differ", sh::msh_ms_brinck_maximov2016(vis, nl), ms::brinck_maximov_2016(vis, nl));
  same.eq("differ", sh::msh_ms_chan2018(vis, nl), ms::chan_2018(vis, nl));
  same.eq("differ", sh::msh_ms_part1_analytic(vis, nl), ms::part1_analytic(vis, nl));
  same.eq("differ", sh::msh_ms_cone_cos(vis), ms::cone_cos_from_visibility(vis));
  same.eq("differ", zero, ms::exact_zero(vis, nl));
  same.eq("differ", sh::msh_ms_relative_azimuth_cos(v, l), lut::relative_azimuth_cos(x.v, x.l));
  same.eq("differ", pa_vf, ggx.projected_alpha(x.v));
  same.eq("differ", pa_lf, ggx.projected_alpha(x.l));
  for (uint32_t seed : {0u, 7u})
    for (int k = 0; k < 2; ++k)
      same.eq("differ", sh::msh_sobol_2d(x.index, seed)[k], sobol_2d<float>(x.index, seed)[k]);
  same.eq("differ", sh::msh_hammersley_2d(x.index, 1u << 20).y, hammersley_2d<float>(x.index, 1u << 20).y);
  dbl.diff("brinck", 2.4e-7, sh::msh_ms_brinck_maximov2016(vis, nl), ref_brinck(vis, nl));
  dbl.diff("chan", 1e-6, sh::msh_ms_chan2018(vis, nl), ref_chan(vis, nl));
  const bool small = vis > 0 && vis < 0.05f;  // the exponent 0.75 / vis is large
  dbl.diff(small ? "part1 (vis < 0.05)" : "part1", small ? 2e-5 : 2e-6, sh::msh_ms_part1_analytic(vis, nl),
           ref_part1(vis, nl));
  dbl.diff("cone cos", 1.2e-7, sh::msh_ms_cone_cos(vis), std::sqrt(1 - sat(vis)));
  const double margin = 2 * sat(vis) + sat(nl) - 1;  // the early-out in double
  dbl.count("early-out off (margin > 1e-6)", 0, std::abs(margin) > 1e-6 && zero != (margin < 0));
  dbl.diff("projected alpha (rel)", 2.5e-7, pa_vf / pa_v, 1);
  dbl.diff("projected alpha (rel)", 2.5e-7, pa_lf / pa_l, 1);
  const double r_an = sh::msh_ms_lut_roughness_anisotropic(v, l, a);
  dbl.diff("anisotropic roughness (rel)", 1e-6,
           r_an / std::sqrt(std::sqrt(0.5 * (pa_v * pa_v + pa_l * pa_l))), 1);
  dbl.diff("anisotropic roughness (rel)", 1e-6,
           r_an / ms::micro_shadowing_isotropic_roughness(x.ax, x.ay, x.v, x.l), 1);
  if (length(vd) > 0) dbl.diff("G1", 5e-7, sh::msh_ggx_g1_projected(v, pa_vf), ref_g1(vd, pa_v));
}

// The estimator's error against the exact term, summed over the records where it is computed.
struct QmcError {
  double sum = 0;
  int n = 0;
};

// The VNDF sampler (vs C++ float; vs double where the float algorithm is conditioned: alpha >= 0.01,
// u.y < 1 - 1e-4), the generic term's sample (finite; its weight and decisions vs C++ float and double) and
// the estimator (the same Sobol points as C++: 2/n, a flipped decision; vs the exact term its QMC error).
void sampler(const Record& x, const RecordInputs& in, std::size_t i, Family& smp, QmcError& qmc) {
  constexpr int n_est = 128;
  const auto& [v, l, a, ggx, pa_vf, pa_lf, vd, ld, pa_v, pa_l] = in;
  const float2 u(x.u1, x.u2);
  const float vis = x.vis, nl = x.nl;
  const float3 m = sh::msh_ggx_sample_vndf(v, a, u);
  const Vec3d mf(ggx.Sample_wm(x.v, Vec2f(u.x, u.y)));
  smp.max("m vs C++ float", 5e-6, length(d3(m) - mf));
  if (std::min(x.ax, x.ay) >= 0.01f && x.u2 < 1 - 1e-4f)
    smp.max("m vs double", 1e-5, length(d3(m) - GGX<double>(x.ax, x.ay).Sample_wm(vd, Vec2d(u.x, u.y))));
  const float c = sh::msh_ms_cone_cos(vis);
  float hc[3], un[3];  // cone, hemisphere, weight
  sh::msh_ms_generic_vndf_sample(c, a, v, l, u, true, hc[0], hc[1], hc[2]);
  sh::msh_ms_generic_vndf_sample_isotropic(c, x.ax, v, l, u, false, un[0], un[1], un[2]);
  for (float o : {m.x, m.y, m.z, hc[0], hc[1], hc[2], un[0], un[1], un[2]})
    smp.count("not finite", 0, !std::isfinite(o));
  const auto c_hc = ms::generic_vndf_sample(c, ggx, x.v, x.l, Vec2f(u.x, u.y), G2Form::HeightCorrelated);
  const auto c_un =
      ms::generic_vndf_sample(c, GGX<float>(x.ax), x.v, x.l, Vec2f(u.x, u.y), G2Form::Uncorrelated);
  if (std::abs(length(ld) - 1) > 1e-5 || std::abs(length(vd) - 1) > 1e-5) return;
  const double gl = ref_g1(ld, pa_l), gv = ref_g1(vd, pa_v), cos_t = std::sqrt(1 - sat(vis));
  if (hc[2] != 0 && c_hc.weight != 0) {
    smp.diff("weight vs C++ float", 1e-6, hc[2], c_hc.weight);
    smp.diff("weight vs double", 1e-6, hc[2], gl / (gl + gv - gl * gv));
  }
  const float g2 = sh::msh_ms_smith_g2_over_g1(sh::msh_ggx_g1_projected(l, pa_lf),
                                               sh::msh_ggx_g1_projected(v, pa_vf), false);
  smp.diff("weight vs C++ float", 1e-6, g2, ms::smith_g2_over_g1(ggx, x.v, x.l, G2Form::Uncorrelated));
  smp.diff("weight vs double", 1e-6, g2, gl);
  // Decisions agree where the sample is not within 1e-4 of a threshold (the sampler's precision).
  if (std::min({std::abs(dot(mf, ld) - cos_t), std::abs(mf.z - cos_t), std::abs(dot(mf, ld)),
                std::abs(mf.z)}) > 1e-4) {
    smp.at_least("decisions checked", 3000, true);
    smp.count("decision mismatches", 0,
              (hc[0] != 0) != (c_hc.cone != 0) || (hc[1] != 0) != (c_hc.hemisphere != 0) ||
                  (un[0] != 0) != (c_un.cone != 0) || (un[1] != 0) != (c_un.hemisphere != 0));
  }
  if (!(x.v.z > 0 && vis >= 0 && vis <= 1 && nl == x.l.z)) return;
  const float est = sh::msh_ms_generic_vndf_estimate(vis, a, v, l, n_est, true, 1u);
  smp.diff("estimate vs C++ float", 2.0 / n_est, est,
           ms::generic_vndf_estimate(vis, ggx, x.v, x.l, n_est, G2Form::HeightCorrelated, 1));
  smp.diff("estimate vs C++ float", 2.0 / n_est,
           sh::msh_ms_generic_vndf_estimate(vis, float2(x.ax), v, l, n_est, false, 0u),
           ms::generic_vndf_estimate(vis, GGX<float>(x.ax), x.v, x.l, n_est, G2Form::Uncorrelated, 0));
  if (i % 8 == 0 && x.ax >= 0.01 && x.ay >= 0.01) {  // the exact term costs ~20 us
    const double e = std::abs(est - ms::generic_vndf_exact(vis, x.ax, x.ay, vd, ld));
    smp.max("estimate vs exact (QMC)", 0.1, e);
    qmc.sum += e, ++qmc.n;
  }
}

// The seed tables (3D, 2D, azimuth-aware) as the prelude's texture views.
struct SeedTables {
  const Luts& L = luts();
  const Tex plain{L.plain}, az{L.azimuth}, two_d{L.two_d};
};

// The seed tables: the prelude's exact float filter (lerps) vs the C++ sampler's 8-tap sum.
void seed_luts(const std::vector<Record>& recs, const SeedTables& S, Family& lut_f) {
  const Luts& L = S.L;
  for (const Record& x : recs) {
    const float l3 = lut::sample_micro_shadowing(L.plain_v, x.vis, x.nl, x.nv, x.roughness);
    const float g[3] = {
        sh::msh_ms_lut_sample(S.plain.t3(), x.vis, x.nl, x.nv, x.roughness),
        sh::msh_ms_lut_sample_2d(S.two_d.t2(), x.vis, x.nl, x.roughness),
        sh::msh_ms_lut_sample_azimuth(S.az.t3(), kHarmonics, x.vis, x.nl, x.nv, x.roughness, x.cos_phi)};
    lut_f.diff("3D", 1e-6, g[0], l3);
    lut_f.diff("3D", 1e-6,
               sh::msh_ms_lut_sample_azimuth(S.plain.t3(), 0, x.vis, x.nl, x.nv, x.roughness, x.cos_phi), l3);
    const float4 ch = sh::msh_ms_lut_fetch(S.plain.t3(), x.vis, x.nl, x.nv);
    if (!ms::exact_zero(x.vis, x.nl))
      lut_f.diff("3D", 1e-6, sh::msh_ms_lut_roughness(ch, x.roughness, float4(0.1f, 0.4f, 0.7f, 1.0f), 4),
                 l3);
    lut_f.diff("2D", 1e-6, g[1], lut::sample_micro_shadowing(L.two_d_v, x.vis, x.nl, 1.0f, x.roughness));
    lut_f.diff("azimuth", 1e-6, g[2],
               lut::sample_micro_shadowing_azimuth(L.azimuth_v, x.vis, x.nl, x.nv, x.roughness, x.cos_phi));
    lut_f.count("early-outs not exactly 0", 0,
                ms::exact_zero(x.vis, x.nl) && (g[0] != 0 || g[1] != 0 || g[2] != 0));
  }
}

// The cone-layout (default) tables as the prelude's texture views; sample(h < 0, ...) the 3D table, h >= 0
// the azimuth-aware one with h harmonics.
struct ConeTables {
  const ConeLuts& C = cone_luts();
  const Tex plain{C.plain}, az{C.azimuth};
  float sample(int h, float vis, float nl, float nv, float r, float cp) const {
    return h < 0 ? sh::msh_ms_lut_sample_cone(plain.t3(), C.n_rough, vis, nl, nv, r)
                 : sh::msh_ms_lut_sample_cone_azimuth(az.t3(), C.n_rough, h, vis, nl, nv, r, cp);
  }
};

// The cone-layout samplers vs the C++ sampler; bound: docs/shaders.md's for the cone samplers.
void cone_luts_check(const ConeTables& T, Family& lut_f) {
  const ConeLuts& C = T.C;
  lut::MicroShadowingLutView az1 = C.azimuth_v;
  az1.harmonics = 1;
  for (const ConeRecord& x : make_cone_records()) {
    const float g[3] = {T.sample(-1, x.vis, x.nl, x.nv, x.roughness, 0),
                        T.sample(3, x.vis, x.nl, x.nv, x.roughness, x.cos_phi),
                        T.sample(1, x.vis, x.nl, x.nv, x.roughness, x.cos_phi)};
    lut_f.diff("cone", 1e-5, g[0], lut::sample_micro_shadowing(C.plain_v, x.vis, x.nl, x.nv, x.roughness));
    lut_f.diff("cone", 1e-5, g[1],
               lut::sample_micro_shadowing_azimuth(C.azimuth_v, x.vis, x.nl, x.nv, x.roughness, x.cos_phi));
    lut_f.diff("cone", 1e-5, g[2],
               lut::sample_micro_shadowing_azimuth(az1, x.vis, x.nl, x.nv, x.roughness, x.cos_phi));
    lut_f.diff("cone", 1e-5,
               sh::msh_ms_lut_fetch_cone(T.az.t3(), C.n_rough, x.vis, x.nl, x.nv, x.roughness).w,
               lut::fetch_cone(C.azimuth_v, x.vis, x.nl, x.nv, x.roughness)[3]);
    const bool zero = ms::exact_zero(x.vis, x.nl);
    lut_f.count("early-outs not exactly 0", 0, zero && (g[0] != 0 || g[1] != 0 || g[2] != 0));
  }
}

// NaN vis, N.L, N.V -> 0, roughness -> the first knot (0.1), cos phi -> -1.
void nan_clamps(const std::vector<Record>& recs, const SeedTables& S, const ConeTables& T, Family& same,
                Family& lut_f) {
  for (std::size_t i = 0; i < recs.size(); i += 64) {
    const Record& x = recs[i];
    for (auto f : {sh::msh_ms_reference_step, sh::msh_ms_brinck_maximov2016, sh::msh_ms_chan2018,
                   sh::msh_ms_part1_analytic})
      same.count("NaN not at the lower bound", 0, nan_clamp_violations(f, {x.vis, x.nl}, {0, 0}));
    same.count("NaN not at the lower bound", 0,
               nan_clamp_violations([](float p, float q) { return float(sh::msh_ms_exact_zero(p, q)); },
                                    {x.vis, x.nl}, {0, 0}) +
                   nan_clamp_violations(sh::msh_ms_cone_cos, {x.vis}, {0}));
    lut_f.count("NaN not at the lower bound", 0,
                nan_clamp_violations(
                    [&](float p, float q, float r, float t, float cp) {
                      return sh::msh_ms_lut_sample(S.plain.t3(), p, q, r, t) +
                             sh::msh_ms_lut_sample_azimuth(S.az.t3(), kHarmonics, p, q, r, t, cp) +
                             T.sample(3, p, q, r, t, cp);
                    },
                    {x.vis, x.nl, x.nv, x.roughness, x.cos_phi}, {0, 0, 0, 0.1f, -1}));
  }
}

}  // namespace ms_checks
}  // namespace

TEST(ShaderPortableCpp, MicroShadowing) {
  using namespace ms_checks;
  const std::vector<Record> recs = make_records();
  const SeedTables seed;
  // Bounds: shaders/portable/micro_shadowing.h, each function's comment. (Families print in reverse order.)
  Family lut_f{"LUT samplers vs the C++ sampler"}, smp{"VNDF sampling and GenericM_m"},
      dbl{"micro-shadowing vs double"},
      same{"closed forms, cone cos, early-out, azimuth cos, projected alpha, Sobol vs C++ float"};
  QmcError qmc;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const RecordInputs in(recs[i]);
    closed_forms(recs[i], in, same, dbl);
    sampler(recs[i], in, i, smp, qmc);
  }
  smp.at_least("estimates vs exact", 300, qmc.n);
  smp.max("mean estimate vs exact", 0.01, qmc.sum / qmc.n);
  seed_luts(recs, seed, lut_f);
  const ConeTables cone;
  cone_luts_check(cone, lut_f);
  nan_clamps(recs, seed, cone, same, lut_f);
}

TEST(ShaderPortableCpp, Fit) {
  Family f{"ALU fit vs C++ float"};  // shaders/portable/micro_shadowing_fit.h: |diff| <= 1e-5
  const std::vector<test::FitInput> recs = test::fit_inputs(false);
  const auto two_stage = [](float vis, float nl, float nv, float r) {
    return sh::msh_ms_generic_vndf_alu_light(sh::msh_ms_generic_vndf_alu_pixel(vis, nv, r), nl);
  };
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const test::FitInput& x = recs[i];
    const float one = sh::msh_ms_generic_vndf_alu(x.vis, x.nl, x.nv, x.r);
    const float two = two_stage(x.vis, x.nl, x.nv, x.r);
    ASSERT_TRUE(one >= 0 && one <= 1 && two >= 0 && two <= 1) << "record " << i;  // NaN fails too
    f.diff("one-call", 1e-5, one, ms::generic_vndf_alu(x.vis, x.nl, x.nv, x.r));
    f.diff("two-stage", 1e-5, two,
           ms::generic_vndf_alu_light(ms::generic_vndf_alu_pixel(x.vis, x.nv, x.r), x.nl));
    f.count("early-outs not exactly 0", 0, ms::exact_zero(x.vis, x.nl) && (one != 0 || two != 0));
    if (i % 64 == 0)  // NaN vis, N.L, N.V -> 0, roughness -> 0.01
      f.count("NaN not at the lower bound", 0,
              nan_clamp_violations(sh::msh_ms_generic_vndf_alu, {x.vis, x.nl, x.nv, x.r}, {0, 0, 0, 0.01f}) +
                  nan_clamp_violations(two_stage, {x.vis, x.nl, x.nv, x.r}, {0, 0, 0, 0.01f}));
  }
}

TEST(ShaderPortableCpp, Area) {
  using namespace test::area_inputs;
  // shaders/portable/micro_shadowing_area.h: |diff| vs C++ double for lights of at least 1 degree.
  const char* names[10] = {"step", "step solid angle", "step Oat-Sander", "cap-cone E", "Brinck-Maximov",
                           "Chan", "Part 1",           "generic ALU",     "Mazonka",    "Oat-Sander"};
  const double tol[10] = {1.5e-3, 1.5e-3, 1.5e-3, 5e-5, 2e-3, 2e-3, 2e-3, 2e-3, 1e-4, 1e-4};
  Family f{"area cap forms vs C++ double"}, s{"disk and quad lights vs C++ double"};
  const std::vector<cap::Rec> recs = cap::make_records();
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const cap::Rec& x = recs[i];
    const float th = sh::msh_ms_cap_theta(x.nl), t = sh::msh_ms_cone_angle(x.vis);
    const float got[10] = {sh::msh_ms_reference_step_area_cap(x.vis, x.nl, x.rho),
                           sh::msh_ms_reference_step_area_cap_solid_angle(x.vis, x.nl, x.rho),
                           sh::msh_ms_reference_step_area_cap_oat_sander(x.vis, x.nl, x.rho),
                           sh::msh_ms_cap_cone_projected_solid_angle(x.rho, th, t),
                           sh::msh_ms_brinck_maximov2016_area_cap(x.vis, x.nl, x.rho),
                           sh::msh_ms_chan2018_area_cap(x.vis, x.nl, x.rho),
                           sh::msh_ms_part1_analytic_area_cap(x.vis, x.nl, x.rho),
                           sh::msh_ms_generic_vndf_alu_area_cap(x.vis, x.nl, x.nv, x.r, x.rho),
                           sh::msh_ms_cap_intersection_solid_angle(x.rho, t, th),
                           sh::msh_ms_cap_intersection_solid_angle_oat_sander(x.rho, t, th)};
    const std::array<double, 10> ref = cap::cpu_outputs<double>(x);
    for (int k = 0; k < 10; ++k) {
      ASSERT_TRUE(std::isfinite(got[k])) << names[k] << " record " << i;
      if (x.rho >= float(kDeg)) f.max(names[k], tol[k], std::abs(got[k] - ref[std::size_t(k)]));
    }
    // rho = 0: the point terms' own functions, identical.
    f.count("rho = 0 differ from the point terms", 0,
            x.rho == 0 &&
                (got[0] != ms::reference_step(x.vis, x.nl) ||
                 got[4] != ms::brinck_maximov_2016(x.vis, x.nl) || got[5] != ms::chan_2018(x.vis, x.nl)));
    if (i % 64 == 0)  // NaN vis, N.V -> 0, N.L -> -1 (msh_ms_cap_theta clamps to [-1, 1]), roughness -> 0.01
      f.count("NaN not at the lower bound", 0,
              nan_clamp_violations(sh::msh_ms_reference_step_area_cap, {x.vis, x.nl, x.rho}, {0, -1, 0}) +
                  nan_clamp_violations(sh::msh_ms_generic_vndf_alu_area_cap, {x.vis, x.nl, x.nv, x.r, x.rho},
                                       {0, -1, 0, 0.01f, 0}));
  }
  // Disk and rectangle lights through the equivalent cap, at the same float inputs: each light's F, its
  // equivalent cap (compared where |F| > 1e-4: the axis is ill-conditioned for an edge-on disk) and step.
  for (const shapes::Rec& x : shapes::make_records()) {
    using shapes::v3;
    const auto light = [&](float3 F, float3 c, const Vec3d& rF) {
      const float2 e = sh::msh_ms_equivalent_cap(F, c);
      const float st = sh::msh_ms_reference_step_area_equivalent_cap(x.vis, F, c);
      const auto re = ms::equivalent_cap(rF, d3(c));
      for (int k = 0; k < 3; ++k) s.diff("F (per component)", 2e-5, F[k], (&rF.x)[k]);
      s.count("not finite", 0, !std::isfinite(e.x + e.y + st));
      if (length(rF) > 1e-4) s.max("cap", 1e-4, std::max(std::abs(e.x - re.n_dot_l), std::abs(e.y - re.rho)));
      if (re.rho >= kDeg)
        s.diff("step", 1.5e-3, st, ms::reference_step_area_equivalent_cap(double(x.vis), rF, d3(c)));
      if (F.x == 0 && F.y == 0 && F.z == 0)  // zero size: the point value at the centre, exactly
        s.count("F = 0 not the point value", 0, st != sh::msh_ms_reference_step(x.vis, e.x) || e.y != 0);
    };
    const float3 q[4] = {f3(v3(x.q[0])), f3(v3(x.q[1])), f3(v3(x.q[2])), f3(v3(x.q[3]))};
    const Vec3d qd[4] = {d3(q[0]), d3(q[1]), d3(q[2]), d3(q[3])};
    light(sh::msh_ms_quad_vector_form_factor(q[0], q[1], q[2], q[3]), q[0] + q[1] + q[2] + q[3],
          ms::polygon_vector_form_factor(qd, 4));
    light(sh::msh_ms_disk_vector_form_factor(f3(v3(x.c)), f3(v3(x.nd)), x.R), f3(v3(x.c)),
          ms::disk_vector_form_factor(v3(x.c), v3(x.nd), double(x.R)));
  }
}

TEST(ShaderPortableCpp, Aware) {
  const std::vector<test::aware_inputs::Rec> recs = test::aware_inputs::make_records();
  const int n_est = 32;
  Family f{"aware vs C++ float"};
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const test::aware_inputs::Rec& x = recs[i];
    const float3 v = f3(x.v), l = f3(x.l);
    const float got[5] = {sh::msh_ms_specular_aware(x.vis, v, l),
                          sh::msh_ms_specular_aware_azimuth_mean(x.vis, x.alpha, x.nl, x.nv),
                          sh::msh_ms_lambert_cap_fraction(x.cos_m, x.c),
                          sh::msh_ms_diffuse_aware_estimate(x.vis, float2(x.alpha), v, l, n_est, true, 1u),
                          sh::msh_ms_diffuse_aware_estimate(x.vis, float2(x.alpha), v, l, n_est, false, 1u)};
    for (float o : got) ASSERT_TRUE(o >= 0 && o <= 1) << "record " << i;  // NaN fails too
    // The indicator, the closed-form mean and the cap fraction are the C++ float expressions in the same
    // order (std::sqrt, acos, atan2, sin, cos): identical for finite inputs.
    f.eq("indicator, mean, cap fraction differ", got[0], ms::specular_aware(x.vis, x.v, x.l));
    f.eq("indicator, mean, cap fraction differ", got[1],
         ms::specular_aware_azimuth_mean(x.vis, x.alpha, x.nl, x.nv));
    f.eq("indicator, mean, cap fraction differ", got[2], ms::lambert_cap_fraction(x.cos_m, x.c));
    // The estimator, the same Sobol points: its sampler divides by the length where C++ multiplies by the
    // reciprocal, so a sample within rounding of a cone boundary may flip (the comment's exception; a flip
    // moves one sample's weight, bounded as in the shader test).
    for (int k = 0; k < 2; ++k) {
      const auto form = k == 0 ? ms::DiffuseAwareForm::Reciprocal : ms::DiffuseAwareForm::Flux;
      const double d = std::abs(
          got[3 + k] - ms::diffuse_aware_estimate(x.vis, GGX<float>(x.alpha), x.v, x.l, n_est, form, 1u));
      f.count("estimates beyond 1e-4 of C++ float", double(recs.size() / 100), d > 1e-4);
      f.max("estimate vs C++ float", 0.25, d);
    }
    if (i % 16 == 0)  // NaN vis, N.L, N.V -> 0, alpha -> 1e-4; cos_m -> -1, c -> 0
      f.count("NaN not at the lower bound", 0,
              nan_clamp_violations(sh::msh_ms_specular_aware_azimuth_mean, {x.vis, x.alpha, x.nl, x.nv},
                                   {0, 1e-4f, 0, 0}) +
                  nan_clamp_violations(sh::msh_ms_lambert_cap_fraction, {x.cos_m, x.c}, {-1, 0}) +
                  nan_clamp_violations(
                      [&](float p) {
                        return sh::msh_ms_specular_aware(p, v, l) +
                               sh::msh_ms_diffuse_aware_estimate(p, float2(x.alpha), v, l, 8, true, 1u);
                      },
                      {x.vis}, {0}));
  }
}

TEST(ShaderPortableCpp, AwareFit) {
  // The C++ float template's expressions in its order, with its coefficients rounded to float (checked):
  // identical (the portable comment's 1e-5 is for GPUs).
  Family f{"aware ALU fit vs C++ float, same operations"};
  for (int k = 0; k < 60; ++k)
    f.count("coefficients differ", 0, sh::MSH_AWARE_ALU_P[k] != float(ms::kDiffuseAwareAluReciprocal[k]));
  const std::vector<test::FitInput> recs = test::fit_inputs(true);
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const test::FitInput& x = recs[i];
    const float o = sh::msh_ms_diffuse_aware_alu(x.vis, x.nl, x.nv, x.r);
    ASSERT_TRUE(o >= 0 && o <= 1) << "record " << i;
    f.max("|diff|", 0, std::abs(o - ms::diffuse_aware_alu(x.vis, x.nl, x.nv, x.r)));
    const float vis = std::clamp(x.vis, 0.0f, 1.0f);
    const bool early = ms::exact_zero(vis, std::clamp(x.nl, 0.0f, 1.0f)) ||
                       ms::exact_zero(vis, std::clamp(x.nv, 0.0f, 1.0f));
    f.count("early-outs not exactly 0", 0, early && o != 0);
    if (i % 64 == 0)  // NaN vis, N.L, N.V -> 0, roughness -> 0.01
      f.count("NaN not at the lower bound", 0,
              nan_clamp_violations(sh::msh_ms_diffuse_aware_alu, {x.vis, x.nl, x.nv, x.r}, {0, 0, 0, 0.01f}));
  }
}

TEST(ShaderPortableCpp, Ltc) {
  namespace li = test::ltc_inputs;
  using test::vk::get;  // a record's vec4 slot as a Vec3d
  // The integrals on test_shaders_ltc.cpp's records and 8x8 table, fetched through the prelude's texture.
  const bsdf::LtcTable& tab = li::integrals::table();
  const int n = tab.size;
  const Tex mat(bsdf::ltc_matrix_volume(tab)), amp(bsdf::ltc_moments_volume(tab));
  // The prelude filters with float weights: the fetch is the double bilinear value up to the rounding of the
  // coordinate (a few ulp of n texels, times a neighbour difference <= 2 max|texel|, on both axes) and of the
  // lerps (a few ulp of max|texel|): (2n + 1) 1e-6 max|texel| per channel (lavapipe quantizes to 8 bits).
  double big[6] = {};
  for (std::size_t i = 0; i < mat.t.size(); ++i)
    for (int c = 0; c < 6; ++c)
      big[c] = std::max<double>(big[c], std::abs(c < 4 ? mat.t[i][c] : amp.t[i][c - 4]));
  Family f{"LTC vs C++ double"},
      g{"LTC cone micro-shadowing vs C++ double"};  // bounds: shaders/portable/ltc.h
  for (const li::integrals::Record& r : li::integrals::make_records()) {
    const float2 uv = sh::msh_ltc_uv(r.a[0], r.a[1], float(n));
    const float4 t = sh::msh_cpp_sample(mat.t2(), uv), am = sh::msh_cpp_sample(amp.t2(), uv);
    const bsdf::LtcCoeffs<double> k = tab.fetch(r.a[0], r.a[1]);
    const double want[6] = {k.a, k.b, k.c, k.d, k.magnitude, k.fresnel},
                 got[6] = {t.x, t.y, t.z, t.w, am.x, am.y};
    for (int c = 0; c < 6; ++c)
      f.diff("fetch / max|texel|", (2 * n + 1) * 1e-6, got[c] / big[c], want[c] / big[c]);
    // Below, the prelude's fetch in both (as the shader test): only the functions are compared.
    bsdf::LtcCoeffs<double> gk, ev;
    gk.a = t.x, gk.b = t.y, gk.c = t.z, gk.d = t.w, gk.magnitude = am.x, gk.fresnel = am.y;
    ev.a = r.a[2], ev.b = r.a[3], ev.c = r.w[3], ev.d = 1;
    const double d = bsdf::ltc_eval(ev.inv_m(), get(r.w)), dd = std::max(d, 1e-3);
    f.diff("D (rel)", 1e-5,
           sh::msh_ltc_eval(sh::msh_ltc_minv(float4(r.a[2], r.a[3], r.w[3], 1)), f3(get(r.w))) / dd, d / dd);
    f.diff("specular", 1e-6, sh::msh_ltc_specular(float4(0.5f), float2(am.x, am.y), 0.04f, 0.75f),
           (0.04 * gk.magnitude + 0.96 * gk.fresnel) * 0.5 * 0.75);
    const Vec3d nd = get(r.n), vd = get(r.v), c = get(r.c), ex = get(r.ex) * double(r.ex[3]),
                ey = get(r.ey) * double(r.ey[3]);
    const Vec3d p[4] = {c - ex - ey, c + ex - ey, c + ex + ey, c - ex + ey};
    const int sides = r.a[3] > 0 ? 16 : 8;
    const float4 s = sh::msh_ltc_sphere(t, f3(nd), f3(vd), f3(get(r.l)), r.l[3], sides),
                 q = sh::msh_ltc_rect(t, f3(nd), f3(vd), f3(p[0]), f3(p[1]), f3(p[2]), f3(p[3]));
    const auto rs = bsdf::ltc_shade_sphere(gk, nd, vd, get(r.l), double(r.l[3]), sides),
               rr = bsdf::ltc_shade_polygon(gk, nd, vd, p, 4);
    f.diff("sphere and rect integrals", 5e-5, s.x, rs.integral);
    f.diff("sphere and rect integrals", 5e-5, q.x, rr.integral);
    for (const auto& [o, w] : {std::pair{s, rs}, std::pair{q, rr}})
      if (w.integral > 1e-3)
        f.max("direction 1 - cos", 1e-6, 1 - dot(w.direction, normalize(Vec3d(o.y, o.z, o.w))));
  }
  // NaN roughness, N.V, alpha -> 0 (msh_saturate, clamp).
  f.count("NaN not at the lower bound", 0,
          nan_clamp_violations(sh::msh_ltc_tail_weight, {0.3f}, {0}) +
              nan_clamp_violations(
                  [](float r, float nv) { return dot(sh::msh_ltc_uv(r, nv, 8.0f), float2(1, 3)); },
                  {0.5f, 0.7f}, {0, 0}));

  // The cone-clipped micro-shadowing on test_shaders_ltc_micro_shadowing.cpp's records (random, then
  // degenerate: k[3] = 1, kind i % 8) vs its C++ double LtcLightCone; the wrappers msh_ltc_ms_* are called
  // directly (the shader test inlines their parts).
  const std::vector<li::cone::Record> recs = li::cone::make_records();
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const li::cone::Record& r = recs[i];
    const float4 t(r.t[0], r.t[1], r.t[2], r.t[3]);
    const float3 n = f3(get(r.n)), v = f3(get(r.v)), l = f3(get(r.l)), c = f3(get(r.c));
    const float3 ex = f3(get(r.ex)) * r.ex[3], ey = f3(get(r.ey)) * r.ey[3];
    const float3 p0 = c - ex - ey, p1 = c + ex - ey, p2 = c + ex + ey, p3 = c - ex + ey;
    const float tail = r.n[3], cos_t = r.v[3], vis = r.c[3];
    const int sides = int(r.k[0]), nodes = int(r.k[1]);
    const sh::MshLtcCone cs = sh::msh_ltc_cone_sphere(t, n, v, l, r.l[3], sides, tail),
                         cr = sh::msh_ltc_cone_rect(t, n, v, p0, p1, p2, p3, tail);
    const float o[4] = {sh::msh_ltc_ms_step_sphere(t, n, v, l, r.l[3], sides, tail, cos_t),
                        sh::msh_ltc_ms_step_rect(t, n, v, p0, p1, p2, p3, tail, cos_t),
                        sh::msh_ltc_ms_brinck_maximov_sphere(t, n, v, l, r.l[3], sides, tail, vis, nodes),
                        sh::msh_ltc_ms_brinck_maximov_rect(t, n, v, p0, p1, p2, p3, tail, vis, nodes)};
    for (float y : {o[0], o[1], o[2], o[3], cs.z_lo, cs.z_hi, cr.z_lo, cr.z_hi})
      g.count("outputs not in [0, 1]", 0, !(y >= 0 && y <= 1));
    g.diff("tail weight", 1e-6, sh::msh_ltc_tail_weight(r.k[2]), bsdf::ltc_tail_weight(double(r.k[2])));
    const li::cone::Cpu x = li::cone::cpu(r);
    const double e = std::max({std::abs(x.step_s - o[0]), std::abs(x.step_r - o[1]), std::abs(x.bm_s - o[2]),
                               std::abs(x.bm_r - o[3])});
    if (r.k[3] > 0) {  // degenerate: V = 0 and lights below the horizon exactly 0, V = 1 exactly 1
      const int kind = int(i % 8);
      g.count("degenerate off", 0,
              ((kind == 0 || kind == 3) && (o[0] != 0 || o[1] != 0)) ||
                  (kind == 1 && x.sphere.den > 0 && o[0] != 1));
      const double min_den = kind == 4 ? 0.0 : 1e-7;  // as the shader test: slivers of weight < 1e-7 excepted
      if (x.sphere.den > min_den && x.rect.den > min_den) g.max("degenerate", 1e-3, e);
      continue;
    }
    g.max("step and Brinck-Maximov", 1e-3, e);
    for (const auto& [cc, cx] : {std::pair{cs, x.sphere}, std::pair{cr, x.rect}})
      if (cx.n > 0)
        g.max("z range", 1e-4, std::max(std::abs(cx.z_lo - cc.z_lo), std::abs(cx.z_hi - cc.z_hi)));
  }
}

TEST(ShaderPortableCpp, Directional) {
  namespace di = test::directional_inputs;
  namespace dir = msh::directional;
  Family f{"directional vs C++ float"};  // bounds: shaders/portable/directional.h
  for (const di::Rec& r : di::make_records()) {
    const float* c = di::channels(r);
    const Vec3f l = di::light(r), n = di::normal(r);
    float ca[9];
    std::copy(c, c + 9, ca);
    const float4 c0(c[0], c[1], c[2], c[3]), c1(c[4], c[5], c[6], c[7]);
    const float tp = sh::msh_dir_transport(c0, c1, c[8], f3(l)),
                mp = sh::msh_dir_term(c0, c1, c[8], f3(l), f3(n));
    const float t_cpp = dir::directional_transport(c, l), m_cpp = dir::directional_term(c, l, n);
    // The array forms are the C++ sums (same products, same order), n . l the same 3-term sum: identical.
    f.eq("array forms differ", sh::msh_dir_transport(ca, f3(l)), t_cpp);
    f.eq("array forms differ", sh::msh_dir_term(ca, f3(l), f3(n)), m_cpp);
    f.count("packed forms negative or NaN", 0, !(tp >= 0 && mp >= 0));
    const double nl = sh::dot(f3(n), f3(l));  // the C++ n . l (same sum): the same early-out
    f.count("early-outs not exactly 0", 0, (!(l.z > 0) && tp != 0) || (!(nl > 1e-4) && mp != 0));
    if (!(l.z > 0)) continue;
    // The packed form adds the 9 products in another association: within 1e-6 S, S = sum |c_i b_i(l)|; the
    // term within 1e-6 S / (n . l) + (1e-6 + 2.5e-7 sum |n_i l_i| / (n . l)) term (shown divided by that).
    const double s = di::sum_scale(r),
                 nl_abs = std::abs(n.x * l.x) + std::abs(n.y * l.y) + std::abs(n.z * l.z);
    f.diff("packed transport / S", 1e-6, tp / s, t_cpp / s);
    if (nl > 1e-4)
      f.max("packed term / its bound", 1,
            std::abs(double(mp) - m_cpp) / (1e-6 * s / nl + (1e-6 + 2.5e-7 * nl_abs / nl) * m_cpp));
  }
  for (const di::Dec& x : di::make_decodes()) {  // lo + (hi - lo) u, the C++ expression: identical
    const float4 u(x.u[0], x.u[1], x.u[2], x.u[3]), lo(x.lo[0], x.lo[1], x.lo[2], x.lo[3]),
        hi(x.hi[0], x.hi[1], x.hi[2], x.hi[3]);
    for (int k = 0; k < 4; ++k) {
      f.eq("8-bit decodes differ", sh::msh_dir_decode_unorm8(u, lo, hi)[k],
           dir::decode_unorm8(u[k], lo[k], hi[k]));
      f.eq("8-bit decodes differ", sh::msh_dir_decode_unorm8(u[k], lo[k], hi[k]),
           dir::decode_unorm8(u[k], lo[k], hi[k]));
    }
  }
  // The view correction: each sum in the C++ order, the same v_z clamp and n . l: identical.
  for (const di::VRec& r : di::make_view_records()) {
    float4 c[6];
    for (int k = 0; k < 24; ++k) c[k / 4][k % 4] = r.c[std::size_t(k)];
    const Vec3f l(r.l[0], r.l[1], r.l[2]), v(r.v[0], r.v[1], r.v[2]), n(r.n[0], r.n[1], r.n[2]);
    f.eq("view forms differ", sh::msh_dir_view_transport(c, f3(l), f3(v)),
         dir::directional_view_transport(r.c.data(), r.c.data() + 9, l, v));
    f.eq("view forms differ", sh::msh_dir_view_term(c, f3(l), f3(v), f3(n)),
         dir::directional_view_term(r.c.data(), l, v, n));
  }
  // The compact forms, codes fitted to a rough field's channels, random UNORM coefficients: each channel
  // within 1e-6 of what its (K + 1)-term sum adds, the transport within 2e-6 S of the double evaluation of
  // the double decode (the decode's and the transport's rounding; as the shader test).
  const render::Texture ch = render::bake_directional_view_channels(di::test_field(2, 32), 6.0f, 32, 0.0f);
  Pcg32 rng(91);
  for (const char* form : {"pca8", "pca4"}) {
    const render::DirectionalCodec code = render::fit_directional_codec(ch, form);
    const int K = int(code.lo.size());
    const std::vector<float> fm = code.folded_mean(), fb = code.folded_basis();
    float4 fm4[6], fb8[48], fb4[24];  // msh_dir_code*_decode's layout: 4 coefficients of a channel per float4
    for (int i = 0; i < 21; ++i) fm4[i / 4][i % 4] = fm[std::size_t(i)];
    for (int i = 0; i < 21 * K; ++i) (K == 8 ? fb8[i / 4] : fb4[i / 4])[i % 4] = fb[std::size_t(i)];
    for (int s = 0; s < 512; ++s) {
      float4 u0, u1, c[6];
      for (int k = 0; k < 4; ++k) u0[k] = float(rng.next_double()), u1[k] = float(rng.next_double());
      K == 8 ? sh::msh_dir_code8_decode(u0, u1, fm4, fb8, c) : sh::msh_dir_code4_decode(u0, fm4, fb4, c);
      // The double decode, and |fm_i| + sum_k |fb_ik u_k| (channel i's scale) as a channel set: S below.
      double cd[21];
      di::VRec mag{};
      for (int i = 0; i < 21; ++i) {
        cd[i] = fm[std::size_t(i)], mag.c[std::size_t(i)] = std::abs(fm[std::size_t(i)]);
        for (int k = 0; k < K; ++k) {
          const double t = double(fb[std::size_t(i * K + k)]) * (k < 4 ? u0[k] : u1[k - 4]);
          cd[i] += t, mag.c[std::size_t(i)] += float(std::abs(t));
        }
        const double scale = mag.c[std::size_t(i)];
        f.diff("compact channels / their sums", 1e-6, c[i / 4][i % 4] / scale, cd[i] / scale);
      }
      const Vec3d l(sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double()))),
          v(sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double())));
      mag.l = {float(l.x), float(l.y), float(l.z), 0}, mag.v = {float(v.x), float(v.y), float(v.z), 0};
      const double S = di::view_sum_scale(mag);
      f.diff("compact transport / S", 2e-6, sh::msh_dir_view_transport(c, f3(l), f3(v)) / S,
             dir::directional_view_transport(cd, cd + 9, l, v) / S);
    }
  }
}

TEST(ShaderPortableCpp, Bump) {
  namespace bi = test::bump_inputs;
  using bump::HemisphereTest;
  Family f{"bump"};  // bounds: shaders/portable/bump_terminator.h
  for (const bi::Record& r : bi::make_records()) {
    const float3 ng = f3(r.ng), ns = f3(r.ns), l = f3(r.l);
    const float got[4] = {sh::msh_bump_conty2019(ng, ns, l, false), sh::msh_bump_chiang2019(ng, ns, l, false),
                          sh::msh_bump_conty2019(ng, ns, l, true), sh::msh_bump_chiang2019(ng, ns, l, true)};
    // The C++ float terms' expressions (cross and dot written out, the same clamps) in the same order:
    // identical for finite inputs.
    f.count("differ from C++ float", 0,
            got[0] != bump::conty2019(r.ng, r.ns, r.l) || got[1] != bump::chiang2019(r.ng, r.ns, r.l) ||
                got[2] != bump::conty2019(r.ng, r.ns, r.l, HemisphereTest::kOn) ||
                got[3] != bump::chiang2019(r.ng, r.ns, r.l, HemisphereTest::kOn));
    for (float o : got) f.count("outside [0, 1] or NaN", 0, !(o >= 0 && o <= 1));
    f.count("exact cases not exactly 1 (0)", 0,
            (r.ns == r.ng && (got[0] != 1 || got[1] != 1)) || (r.l == r.ng && got[0] != 1) ||
                (dot(r.ns, r.ns) == 0 && (got[0] != 1 || got[2] != 0)));
    if (dot(r.ns, r.ns) == 0) continue;
    const Vec3d ngd = normalize(Vec3d(r.ng)), nsd = normalize(Vec3d(r.ns)), ld = normalize(Vec3d(r.l));
    const double cos_i = std::abs(dot(ngd, ld)), e = std::abs(got[0] - bi::conty_ref(ngd, nsd, ld));
    // Conty: 1e-6 for |cos(ng, l)| >= 0.05, 5e-6 for >= 0.01; below ~1.2e-7 / alpha (the shader test's 1e-4).
    f.max(cos_i < 0.01 ? "Conty, |cos_i| < 0.01" : (cos_i < 0.05 ? "Conty, < 0.05" : "Conty, >= 0.05"),
          cos_i < 0.01 ? 1e-4 : (cos_i < 0.05 ? 5e-6 : 1e-6), e);
    if (std::abs(dot(nsd, ld)) > 1e-3) f.max("Chiang", 2e-5, std::abs(got[1] - bi::chiang_ref(ngd, nsd, ld)));
  }
  const float3 z(0.0f), a(0.3f, -0.2f, 0.9f), b(-0.5f, 0.1f, 0.8f);  // zero vectors give 1 (no correction)
  for (float o : {sh::msh_bump_conty2019(z, a, b, false), sh::msh_bump_chiang2019(z, a, b, false),
                  sh::msh_bump_conty2019(a, b, z, false), sh::msh_bump_chiang2019(a, b, z, false)})
    f.count("zero vectors not 1", 0, o != 1);
  for (const bi::TriRecord& t : bi::make_tris()) {  // the shader test's bound
    const float3 p = sh::msh_hanika2021_shadow_origin(f3(t.p), f3(t.p0), f3(t.p1), f3(t.p2), f3(t.n0),
                                                      f3(t.n1), f3(t.n2), f3(t.b));
    const Vec3d want = bump::hanika2021_shadow_origin(Vec3d(t.p), {Vec3d(t.p0), Vec3d(t.p1), Vec3d(t.p2)},
                                                      {Vec3d(t.n0), Vec3d(t.n1), Vec3d(t.n2)},
                                                      std::array<double, 3>{t.b.x, t.b.y, t.b.z});
    f.max("Hanika origin vs double", 2e-6, length(d3(p) - want));
  }
}
