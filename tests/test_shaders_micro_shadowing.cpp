// The GLSL and HLSL micro-shadowing shaders (shaders/{glsl,hlsl}/micro_shadowing.*): they compile with
// glslangValidator (GLSL 450, GLSL ES 320, HLSL), and, where a Vulkan device is available (lavapipe on CI),
// every function runs over random and degenerate inputs and agrees with the C++ float code
// (msh::micro_shadowing, GGX, sobol_2d, msh::lut sampler) and with double-precision references written here
// from the closed forms, within the precision each shader file states. The LUT functions read a table baked
// in the test by the library, uploaded as RGBA32F 2D/3D textures with hardware linear filtering.
#include <gtest/gtest.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_baker.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/reference/micro_shadowing_exact.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "support/micro_shadowing_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;
using namespace msh::test::ms_inputs;

namespace {

constexpr int kOut = 8;        // vec4 outputs per record
constexpr uint32_t kSeed = 7;  // Sobol seed for the point check (0 = plain sequence also checked)

// Records (support/micro_shadowing_inputs.h): a = (vis, N.L, alpha_x, alpha_y), v = (view, cos_phi),
// l = (light, sobol index), u = (u1, u2, perceptual roughness, N.V). Outputs o[0..7], see the kernels.

const vk::Kernel kKernel = vk::framed_kernel({"micro_shadowing"},
                                             {{"in Rec rec", "out vec4 o"},
                                              {"3d lut3", "3d lut_az", "2d lut2"},
                                              "int n_est; uint seed; uint n_points;"},
                                             "struct Rec { vec4 a; vec4 v; vec4 l; vec4 u; };\n", R"(
  Rec r = rec[i];
  float vis = r.a.x, nl = r.a.y;
  vec2 alpha = r.a.zw;
  vec3 v = r.v.xyz, l = r.l.xyz;
  uint k = i * 8u;
  o[k + 0u] = vec4(msh_ms_reference_step(vis, nl), msh_ms_brinck_maximov2016(vis, nl), msh_ms_chan2018(vis, nl),
                   msh_ms_part1_analytic(vis, nl));
  float av = msh_ggx_projected_alpha(v, alpha), al = msh_ggx_projected_alpha(l, alpha);
  o[k + 1u] = vec4(msh_ms_exact_zero(vis, nl) ? 1.0 : 0.0, msh_ms_cone_cos(vis), av, al);
  o[k + 2u] = vec4(msh_ggx_sample_vndf(v, alpha, r.u.xy), msh_ggx_g1_projected(v, av));
  float c = msh_ms_cone_cos(vis), cone, hemi, w;
  msh_ms_generic_vndf_sample(c, alpha, v, l, r.u.xy, true, cone, hemi, w);
  o[k + 3u] = vec4(cone, hemi, w, msh_ms_smith_g2_over_g1(msh_ggx_g1_projected(l, al), msh_ggx_g1_projected(v, av), false));
  msh_ms_generic_vndf_sample_isotropic(c, alpha.x, v, l, r.u.xy, false, cone, hemi, w);
  o[k + 4u] = vec4(cone, hemi, w, msh_ms_relative_azimuth_cos(v, l));
  o[k + 5u] = vec4(msh_ms_generic_vndf_estimate(vis, alpha, v, l, pc.n_est, true, 1u),
                   msh_ms_generic_vndf_estimate(vis, alpha.xx, v, l, pc.n_est, false, 0u),
                   msh_ms_lut_sample(lut3, vis, nl, r.u.w, r.u.z), msh_ms_lut_sample_2d(lut2, vis, nl, r.u.z));
  uint idx = uint(r.l.w);
  o[k + 6u] = vec4(msh_ms_lut_sample_azimuth(lut_az, 2, vis, nl, r.u.w, r.u.z, r.v.w),
                   msh_ms_lut_sample_azimuth(lut3, 0, vis, nl, r.u.w, r.u.z, r.v.w),
                   msh_ms_lut_roughness(msh_ms_lut_fetch(lut3, vis, nl, r.u.w), r.u.z, vec4(0.1, 0.4, 0.7, 1.0), 4),
                   0.0);
  o[k + 7u] = vec4(msh_sobol_2d(idx, pc.seed), msh_sobol_2d(idx, 0u).x, msh_hammersley_2d(idx, pc.n_points).y);
)");

// The kernel's buffers (records as 16 floats, outputs), the three tables as textures, the push constants.
vk::Dispatch make_dispatch(const std::vector<Record>& recs, int n_est) {
  std::vector<float> in;
  for (const Record& x : recs)
    in.insert(in.end(), {x.vis, x.nl, x.ax, x.ay, x.v.x, x.v.y, x.v.z, x.cos_phi, x.l.x, x.l.y, x.l.z,
                         float(x.index), x.u1, x.u2, x.roughness, x.nv});
  const Luts& L = luts();
  struct {
    uint32_t n;
    int32_t n_est;
    uint32_t seed, n_points;
  } push{uint32_t(recs.size()), n_est, kSeed, 1u << 20};
  vk::Dispatch d;
  d.buffers = {in, std::vector<float>(recs.size() * kOut * 4)};
  d.images = {
      {uint32_t(L.plain.width), uint32_t(L.plain.height), uint32_t(L.plain.depth), L.plain.data.data()},
      {uint32_t(L.azimuth.width), uint32_t(L.azimuth.height), uint32_t(L.azimuth.depth),
       L.azimuth.data.data()},
      {uint32_t(L.two_d.width), uint32_t(L.two_d.height), 0, L.two_d.data.data()}};
  d.push = vk::push_constants(push);
  d.invocations = recs.size();
  return d;
}

void check(const char* label, const std::vector<Record>& recs, int n_est,
           const std::vector<std::array<float, 4>>& out) {
  const Luts& L = luts();
  // Maximum errors by quantity: vs the C++ float code (f) and vs the double reference (d).
  double e_chan_d = 0, e_brinck_d = 0, e_part1_d = 0, e_part1_small = 0, e_cf_f = 0;
  double e_m_f = 0, e_m_d = 0, e_m_d_sharp = 0, e_m_cpu_d = 0, sum_est_exact = 0, sum_est_exact_cpu = 0,
         e_palpha_d = 0, e_g1_d = 0, e_w_f = 0, e_w_d = 0;
  double e_est_f = 0, e_est_exact = 0, e_est_exact_cpu = 0, e_lut = 0, e_lut_az = 0, e_lut_2d = 0, e_misc = 0;
  int ref_mismatch = 0, flag_mismatch = 0, est_checked = 0, flag_checked = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Record& x = recs[i];
    const auto* o = &out[i * kOut];
    SCOPED_TRACE(testing::Message() << label << " record " << i << " vis " << x.vis << " nl " << x.nl
                                    << " alpha " << x.ax << "," << x.ay << " v " << x.v.x << "," << x.v.y
                                    << "," << x.v.z << " l " << x.l.x << "," << x.l.y << "," << x.l.z);
    for (int k = 0; k < kOut; ++k)
      for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(o[k][c])) << "output " << k << "." << c;
    // Closed forms.
    const float cpu_cf[4] = {
        micro_shadowing::reference_step(x.vis, x.nl), micro_shadowing::brinck_maximov_2016(x.vis, x.nl),
        micro_shadowing::chan_2018(x.vis, x.nl), micro_shadowing::part1_analytic(x.vis, x.nl)};
    const double cos_t = std::sqrt(1 - sat(x.vis));
    if (o[0][0] != cpu_cf[0]) {
      ++ref_mismatch;  // allowed only at the cone boundary (sqrt rounding)
      EXPECT_LT(std::abs(sat(x.nl) - cos_t), 2e-7);
    }
    for (int c = 0; c < 4; ++c) ASSERT_TRUE(o[0][c] >= 0 && o[0][c] <= 1);
    e_cf_f = std::max({e_cf_f, std::abs(double(o[0][1]) - cpu_cf[1]), std::abs(double(o[0][2]) - cpu_cf[2])});
    e_brinck_d = std::max(e_brinck_d, std::abs(o[0][1] - ref_brinck(x.vis, x.nl)));
    e_chan_d = std::max(e_chan_d, std::abs(o[0][2] - ref_chan(x.vis, x.nl)));
    double& e_part1 = (x.vis >= 0.05f || x.vis <= 0) ? e_part1_d : e_part1_small;
    e_part1 = std::max(e_part1, std::abs(o[0][3] - ref_part1(x.vis, x.nl)));
    ASSERT_EQ(o[1][0] != 0, micro_shadowing::exact_zero(x.vis, x.nl));
    const double zero_margin = 2 * sat(x.vis) + sat(x.nl) - 1;  // the early-out in double
    if (std::abs(zero_margin) > 1e-6) {
      ASSERT_EQ(o[1][0] != 0, zero_margin < 0);
    }
    e_misc = std::max(e_misc, std::abs(o[1][1] - cos_t));
    // Projected roughness, G1, the sampler.
    const GGX<float> ggx(x.ax, x.ay);
    const GGX<double> ggx_d(x.ax, x.ay);
    const Vec3d vd(x.v), ld(x.l);
    const double pa_v = ref_projected_alpha(vd, x.ax, x.ay), pa_l = ref_projected_alpha(ld, x.ax, x.ay);
    e_palpha_d = std::max({e_palpha_d, std::abs(o[1][2] - pa_v) / pa_v, std::abs(o[1][3] - pa_l) / pa_l});
    if (length(vd) > 0) e_g1_d = std::max(e_g1_d, std::abs(o[2][3] - ref_g1(vd, pa_v)));
    const Vec2f u(x.u1, x.u2);
    const Vec3f m_f = ggx.Sample_wm(x.v, u);
    const Vec3d m_d = ggx_d.Sample_wm(vd, Vec2d(u.x, u.y));
    const Vec3d m_s(o[2][0], o[2][1], o[2][2]);
    e_m_f = std::max(e_m_f, length(m_s - Vec3d(m_f)));
    // The float sampler (C++ and shader alike) is ill-conditioned below alpha ~0.01 (unstretching by alpha
    // amplifies rounding) and for u.y within 1e-4 of 1 (where the half vector h = c + wi
    // can vanish for grazing v). There the
    // shader is compared with C++ float only; the double error is reported.
    const bool well_conditioned = std::min(x.ax, x.ay) >= 0.01f && x.u2 < 1 - 1e-4f;
    double& e_md = well_conditioned ? e_m_d : e_m_d_sharp;
    e_md = std::max(e_md, length(m_s - m_d));
    if (well_conditioned) e_m_cpu_d = std::max(e_m_cpu_d, length(Vec3d(m_f) - m_d));
    // GenericM_m: weights vs C++ float and the double Smith weight; decisions vs C++ except at the
    // thresholds.
    const double gl = ref_g1(ld, pa_l), gv = length(vd) > 0 ? ref_g1(vd, pa_v) : 1.0;
    const double w_hc = gl / (gl + gv - gl * gv);
    const float cf = micro_shadowing::cone_cos_from_visibility(x.vis);
    const auto s_hc =
        micro_shadowing::generic_vndf_sample(cf, ggx, x.v, x.l, u, micro_shadowing::G2Form::HeightCorrelated);
    const auto s_un = micro_shadowing::generic_vndf_sample(cf, GGX<float>(x.ax), x.v, x.l, u,
                                                           micro_shadowing::G2Form::Uncorrelated);
    const bool unit_l = std::abs(length(ld) - 1) < 1e-5, unit_v = std::abs(length(vd) - 1) < 1e-5;
    // A decision is checked where the sample is not within 1e-4 of a threshold (cone or hemisphere).
    auto decisive_for = [&](const Vec3d& m) {
      return std::min({std::abs(dot(m, ld) - cos_t), std::abs(m.z - cos_t), std::abs(dot(m, ld)),
                       std::abs(m.z)}) > 1e-4;
    };
    const bool decisive = decisive_for(Vec3d(m_f));
    if (unit_l && unit_v) {
      if (o[3][2] != 0 && s_hc.weight != 0) {
        e_w_f = std::max(e_w_f, double(std::abs(o[3][2] - s_hc.weight)));
        e_w_d = std::max(e_w_d, std::abs(o[3][2] - w_hc));
      }
      e_w_f = std::max(e_w_f,
                       double(std::abs(o[3][3] - micro_shadowing::smith_g2_over_g1(
                                                     ggx, x.v, x.l, micro_shadowing::G2Form::Uncorrelated))));
      e_w_d = std::max(e_w_d, std::abs(o[3][3] - gl));
      if (decisive) {
        ++flag_checked;
        const bool same = (o[3][0] != 0) == (s_hc.cone != 0) && (o[3][1] != 0) == (s_hc.hemisphere != 0) &&
                          (o[4][0] != 0) == (s_un.cone != 0) && (o[4][1] != 0) == (s_un.hemisphere != 0);
        if (!same) ++flag_mismatch;
      }
      if (well_conditioned && decisive_for(m_d)) {  // ... and vs the double decision on the double sample
        EXPECT_EQ(o[3][0] != 0, m_d.z > cos_t && dot(m_d, ld) > cos_t);
      }
    }
    e_misc = std::max(e_misc, double(std::abs(o[4][3] - lut::relative_azimuth_cos(x.v, x.l))));
    // Estimators: the same Sobol points as the C++ float estimator; the exact double term as the reference.
    if (unit_l && unit_v && x.v.z > 0 && x.vis >= 0 && x.vis <= 1 && x.nl == x.l.z) {
      const float cpu_hc = micro_shadowing::generic_vndf_estimate(
          x.vis, ggx, x.v, x.l, n_est, micro_shadowing::G2Form::HeightCorrelated, 1);
      const float cpu_un = micro_shadowing::generic_vndf_estimate(x.vis, GGX<float>(x.ax), x.v, x.l, n_est,
                                                                  micro_shadowing::G2Form::Uncorrelated, 0);
      e_est_f = std::max({e_est_f, double(std::abs(o[5][0] - cpu_hc)), double(std::abs(o[5][1] - cpu_un))});
      if (i % 8 == 0 && x.ax >= 0.01 && x.ay >= 0.01) {  // the exact term costs ~20 us
        const double ex = micro_shadowing::generic_vndf_exact(x.vis, x.ax, x.ay, vd, ld);
        e_est_exact = std::max(e_est_exact, std::abs(o[5][0] - ex));
        e_est_exact_cpu = std::max(e_est_exact_cpu, std::abs(cpu_hc - ex));
        sum_est_exact += std::abs(o[5][0] - ex), sum_est_exact_cpu += std::abs(cpu_hc - ex);
        ++est_checked;
      }
    }
    // LUT sampling vs the C++ runtime sampler (same table, same remap; the hardware filter vs float math).
    const float l3 = lut::sample_micro_shadowing(L.plain_v, x.vis, x.nl, x.nv, x.roughness);
    const float l2 = lut::sample_micro_shadowing(L.two_d_v, x.vis, x.nl, 1.0f, x.roughness);
    const float laz =
        lut::sample_micro_shadowing_azimuth(L.azimuth_v, x.vis, x.nl, x.nv, x.roughness, x.cos_phi);
    e_lut = std::max(e_lut, double(std::abs(o[5][2] - l3)));
    e_lut_2d = std::max(e_lut_2d, double(std::abs(o[5][3] - l2)));
    e_lut_az = std::max(e_lut_az, double(std::abs(o[6][0] - laz)));
    e_lut = std::max(e_lut, double(std::abs(o[6][1] - l3)));  // H = 0 through the azimuth path
    if (!micro_shadowing::exact_zero(x.vis, x.nl)) e_lut = std::max(e_lut, double(std::abs(o[6][2] - l3)));
    if (micro_shadowing::exact_zero(x.vis, x.nl)) {
      ASSERT_EQ(o[5][2], 0.0f);
      ASSERT_EQ(o[5][3], 0.0f);
      ASSERT_EQ(o[6][0], 0.0f);
    }
    // Sobol / Hammersley: bit-identical.
    const Vec2f sob = sobol_2d<float>(x.index, kSeed), sob0 = sobol_2d<float>(x.index, 0);
    ASSERT_EQ(o[7][0], sob.x);
    ASSERT_EQ(o[7][1], sob.y);
    ASSERT_EQ(o[7][2], sob0.x);
    ASSERT_EQ(o[7][3], (hammersley_2d<float>(x.index, 1u << 20).y));
  }
  // Tolerances: the precision stated in the shader files (docs/shaders.md has the measured values).
  EXPECT_LE(ref_mismatch, 8) << label;
  EXPECT_LT(e_cf_f, 2.5e-7) << label;
  EXPECT_LT(e_brinck_d, 5e-7) << label;
  EXPECT_LT(e_chan_d, 1e-6) << label;
  EXPECT_LT(e_part1_d, 2e-6) << label;
  EXPECT_LT(e_part1_small, 2e-5) << label;
  EXPECT_LT(e_misc, 5e-7) << label;
  EXPECT_LT(e_palpha_d, 1e-6) << label;
  EXPECT_LT(e_g1_d, 1e-6) << label;
  EXPECT_LT(e_m_f, 5e-6) << label;
  EXPECT_LT(e_m_d, 1e-5) << label;  // the float algorithm's own error (C++ float: printed)
  EXPECT_LT(e_w_f, 1e-6) << label;
  EXPECT_LT(e_w_d, 1e-6) << label;
  EXPECT_GT(flag_checked, 3000) << label;
  EXPECT_EQ(flag_mismatch, 0) << label;
  EXPECT_LE(e_est_f, 2.0 / n_est) << label;
  EXPECT_GT(est_checked, 300) << label;
  // QMC error of the n_est-point estimate vs the exact term (the C++ estimator's is printed beside it).
  EXPECT_LT(e_est_exact, 0.1) << label;
  EXPECT_LT(sum_est_exact / est_checked, 0.01) << label;
  EXPECT_LT(e_lut, 1e-6) << label;
  EXPECT_LT(e_lut_2d, 1e-6) << label;
  EXPECT_LT(e_lut_az, 1e-6) << label;
  std::printf(
      "[ %s ] max |shader - double|: chan %.2e, brinck %.2e, part1 %.2e (vis < 0.05: %.2e), projected alpha "
      "(rel) %.2e, G1 %.2e, sample m %.2e (C++ float %.2e; alpha < 0.01 or u.y at 0 or 1: %.2e), weight "
      "%.2e, cone cos and azimuth cos %.2e\n",
      label, e_chan_d, e_brinck_d, e_part1_d, e_part1_small, e_palpha_d, e_g1_d, e_m_d, e_m_cpu_d,
      e_m_d_sharp, e_w_d, e_misc);
  std::printf(
      "[ %s ] max |shader - C++ float|: closed forms %.2e, m %.2e, weight %.2e, estimate (n = %d) %.2e, "
      "LUT 3D %.2e, 2D %.2e, azimuth %.2e; reference-step boundary flips %d; decision mismatches %d of %d\n",
      label, e_cf_f, e_m_f, e_w_f, n_est, e_est_f, e_lut, e_lut_2d, e_lut_az, ref_mismatch, flag_mismatch,
      flag_checked);
  std::printf(
      "[ %s ] estimate vs exact (%d configurations): max shader %.4f, C++ %.4f; mean shader %.5f, C++ %.5f\n",
      label, est_checked, e_est_exact, e_est_exact_cpu, sum_est_exact / est_checked,
      sum_est_exact_cpu / est_checked);
}

}  // namespace

TEST(ShadersMicroShadowing, Compiles) { vk::expect_compiles(kKernel); }

// A broken include must fail to compile in both languages: the compile checks are not vacuous.
TEST(ShadersMicroShadowing, CompileCheckRejectsBrokenSource) {
  vk::expect_broken_source_rejected(kKernel, "return x * x;", "return x * y;");
}

TEST(ShadersMicroShadowing, RunsOnVulkanAndMatches) {
  const auto recs = make_records();
  const int n_est = 128;
  vk::run_glsl_and_hlsl(kKernel, make_dispatch(recs, n_est), [&](const char* label, const vk::Buffers& out) {
    check(label, recs, n_est, vk::from_floats<std::array<float, 4>>(out[1]));
  });
}

// ---- Cone-layout LUT samplers (msh_ms_lut_sample_cone*, the default table) --------------------------------
namespace {

const vk::Kernel kConeKernel =
    vk::framed_kernel({"micro_shadowing"},
                      {{"in vec4 rec", "out vec4 o"}, {"3d lut_plain", "3d lut_az"}, "int n_rough;"}, "", R"(
  vec4 a = rec[2u * i], b = rec[2u * i + 1u];  // (vis, N.L, N.V, roughness), (cos_phi, -, -, -)
  o[i] = vec4(msh_ms_lut_sample_cone(lut_plain, pc.n_rough, a.x, a.y, a.z, a.w),
              msh_ms_lut_sample_cone_azimuth(lut_az, pc.n_rough, 3, a.x, a.y, a.z, a.w, b.x),
              msh_ms_lut_sample_cone_azimuth(lut_az, pc.n_rough, 1, a.x, a.y, a.z, a.w, b.x),
              msh_ms_lut_fetch_cone(lut_az, pc.n_rough, a.x, a.y, a.z, a.w).w);
)");

}  // namespace

TEST(ShadersMicroShadowing, ConeLutCompiles) { vk::expect_compiles(kConeKernel); }

TEST(ShadersMicroShadowing, ConeLutMatchesCppOnVulkan) {
  const ConeLuts& L = cone_luts();
  const auto recs = make_cone_records();
  ASSERT_GE(recs.size(), 10000u);
  std::vector<float> in;
  for (const ConeRecord& x : recs) in.insert(in.end(), {x.vis, x.nl, x.nv, x.roughness, x.cos_phi, 0, 0, 0});
  struct {
    uint32_t n;
    int32_t n_rough;
  } push{uint32_t(recs.size()), L.n_rough};
  vk::Dispatch d;
  d.buffers = {in, std::vector<float>(recs.size() * 4)};
  d.images = {{uint32_t(L.plain_rgba.width), uint32_t(L.plain_rgba.height), uint32_t(L.plain_rgba.depth),
               L.plain_rgba.data.data()},
              {uint32_t(L.azimuth.width), uint32_t(L.azimuth.height), uint32_t(L.azimuth.depth),
               L.azimuth.data.data()}};
  d.push = vk::push_constants(push);
  d.invocations = recs.size();
  lut::MicroShadowingLutView az1 = L.azimuth_v;
  az1.harmonics = 1;
  vk::run_glsl_and_hlsl(kConeKernel, d, [&](const char* label, const vk::Buffers& buffers) {
    const auto out = vk::from_floats<std::array<float, 4>>(buffers[1]);
    double e_plain = 0, e_az = 0, e_az1 = 0, e_fetch = 0;
    int zeros = 0;
    for (size_t i = 0; i < recs.size(); ++i) {
      const ConeRecord& x = recs[i];
      const float p = lut::sample_micro_shadowing(L.plain_v, x.vis, x.nl, x.nv, x.roughness);
      const float a3 =
          lut::sample_micro_shadowing_azimuth(L.azimuth_v, x.vis, x.nl, x.nv, x.roughness, x.cos_phi);
      const float a1 = lut::sample_micro_shadowing_azimuth(az1, x.vis, x.nl, x.nv, x.roughness, x.cos_phi);
      const float f3 = lut::fetch_cone(L.azimuth_v, x.vis, x.nl, x.nv, x.roughness)[3];
      for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(out[i][c])) << label << " record " << i;
      if (micro_shadowing::exact_zero(x.vis, x.nl)) {  // the early-out: exactly 0 in both, no fetch
        ++zeros;
        ASSERT_EQ(out[i][0], 0.0f) << label << " record " << i;
        ASSERT_EQ(out[i][1], 0.0f) << label << " record " << i;
        ASSERT_EQ(p, 0.0f);
      }
      e_plain = std::max(e_plain, double(std::abs(out[i][0] - p)));
      e_az = std::max(e_az, double(std::abs(out[i][1] - a3)));
      e_az1 = std::max(e_az1, double(std::abs(out[i][2] - a1)));
      e_fetch = std::max(e_fetch, double(std::abs(out[i][3] - f3)));
    }
    EXPECT_GT(zeros, 2000) << label;
    EXPECT_LT(e_plain, 1e-5) << label;
    EXPECT_LT(e_az, 1e-5) << label;
    EXPECT_LT(e_az1, 1e-5) << label;
    EXPECT_LT(e_fetch, 1e-5) << label;
    std::printf(
        "[ %s ] cone LUT, %zu inputs: max |shader - C++ float| plain %.2e, azimuth H=3 %.2e, H=1 %.2e, "
        "a_3 %.2e; early-outs %d (bit-identical 0)\n",
        label, recs.size(), e_plain, e_az, e_az1, e_fetch, zeros);
  });
}
