// The GLSL and HLSL ports of the micro-BRDF-aware terms (shaders/{glsl,hlsl}/micro_shadowing_aware.*): they
// compile with glslangValidator (GLSL 450, GLSL ES 320, HLSL) and, where a Vulkan device is available
// (lavapipe on CI), agree with the C++ float functions of occlusion/micro_shadowing_aware.h at random inputs
// over the domain plus degenerate ones, within the precision each shader function states.
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>

#include <algorithm>
#include <cmath>

#include "support/aware_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;
using namespace msh::test::aware_inputs;

namespace {

constexpr int kEst = 32;  // estimator samples

const vk::Kernel kKernel = vk::framed_kernel({"micro_shadowing", "micro_shadowing_aware"},
                                             {{"in Rec rec", "out vec4 o"}, {}, "int n_est;"},
                                             "struct Rec { vec4 a; vec4 v; vec4 l; };\n", R"(
  Rec r = rec[i];
  o[2u * i] = vec4(msh_ms_specular_aware(r.a.x, r.v.xyz, r.l.xyz),
                   msh_ms_specular_aware_azimuth_mean(r.a.x, r.a.y, r.a.z, r.a.w),
                   msh_ms_lambert_cap_fraction(r.v.w, r.l.w),
                   msh_ms_diffuse_aware_estimate(r.a.x, vec2(r.a.y, r.a.y), r.v.xyz, r.l.xyz, pc.n_est, true, 1u));
  o[2u * i + 1u] = vec4(msh_ms_diffuse_aware_estimate(r.a.x, vec2(r.a.y, r.a.y), r.v.xyz, r.l.xyz, pc.n_est, false, 1u),
                        0.0, 0.0, 0.0);
)");

void check(const char* label, const std::vector<Rec>& recs, const std::vector<float>& out) {
  int spec_flip = 0, est_off = 0;
  double d_mean = 0, d_cap = 0, d_est_max = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Rec& x = recs[i];
    const float* o = &out[8 * i];
    for (int k = 0; k < 5; ++k) {
      ASSERT_TRUE(std::isfinite(o[k])) << label << " " << i << " " << k;
      ASSERT_GE(o[k], 0.0f);
      ASSERT_LE(o[k], 1.0f);
    }
    spec_flip += o[0] != micro_shadowing::specular_aware(x.vis, x.v, x.l);
    d_mean = std::max(
        d_mean,
        double(std::abs(o[1] - micro_shadowing::specular_aware_azimuth_mean(x.vis, x.alpha, x.nl, x.nv))));
    d_cap = std::max(d_cap, double(std::abs(o[2] - micro_shadowing::lambert_cap_fraction(x.cos_m, x.c))));
    const GGX<float> g(x.alpha);
    for (int k = 0; k < 2; ++k) {
      const float cpu = micro_shadowing::diffuse_aware_estimate(
          x.vis, g, x.v, x.l, kEst,
          k == 0 ? micro_shadowing::DiffuseAwareForm::Reciprocal : micro_shadowing::DiffuseAwareForm::Flux,
          1u);
      const double d = std::abs(o[k == 0 ? 3 : 4] - cpu);
      if (d > 1e-4) ++est_off;
      d_est_max = std::max(d_est_max, d);
    }
  }
  EXPECT_LE(spec_flip, int(recs.size() / 1000)) << label;  // only inputs within rounding of a boundary
  EXPECT_LE(d_mean, 2e-4) << label;
  EXPECT_LE(d_cap, 1e-4) << label;  // GPU acos/atan: measured 4.8e-5
  EXPECT_LE(est_off, int(recs.size() / 100)) << label;
  EXPECT_LE(d_est_max, 0.25) << label;
  std::printf(
      "[ %s ] %zu inputs: specular flips %d, |mean diff| %.2e, |cap diff| %.2e, estimator > 1e-4: %d "
      "(max %.2e)\n",
      label, recs.size(), spec_flip, d_mean, d_cap, est_off, d_est_max);
}

}  // namespace

TEST(ShadersMicroShadowingAware, Compiles) {
  vk::expect_compiles(kKernel, {"float c = msh_ms_cone_cos(V), len = sqrt(len2);",
                                "float c = msh_ms_cone_cos(V), len = sqrt(lem2);", false});
}

TEST(ShadersMicroShadowingAware, MatchesCppOnVulkan) {
  const std::vector<Rec> recs = make_records();
  struct {
    uint32_t n;
    int32_t n_est;
  } pc{uint32_t(recs.size()), kEst};
  vk::run_records(kKernel, recs, 8, check, vk::push_constants(pc));
}
