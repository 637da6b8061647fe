// The GLSL and HLSL area-light micro-shadowing shaders (shaders/{glsl,hlsl}/micro_shadowing_area.*): they
// compile with glslangValidator (GLSL 450, GLSL ES 320, HLSL) and, where a Vulkan device is available
// (lavapipe on CI), every function agrees with the C++ float code of occlusion/micro_shadowing_area.h on
// random and degenerate inputs within the precision the shader files state; ρ = 0 gives the point terms.
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/occlusion/micro_shadowing_fit.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "support/area_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;
using namespace msh::test::area_inputs::cap;

namespace {

constexpr int kOut = 3;  // vec4 outputs per record

const vk::Kernel kKernel =
    vk::framed_kernel({"micro_shadowing", "micro_shadowing_fit", "micro_shadowing_area"},
                      {{"in vec4 rec", "out vec4 o"}, {}, ""}, "", R"(
  vec4 a = rec[2u * i], b = rec[2u * i + 1u];
  float vis = a.x, nl = a.y, nv = a.z, r = a.w, rho = b.x;
  float th = msh_ms_cap_theta(nl), t = msh_ms_cone_angle(vis);
  o[3u * i] = vec4(msh_ms_reference_step_area_cap(vis, nl, rho), msh_ms_reference_step_area_cap_solid_angle(vis, nl, rho),
                   msh_ms_reference_step_area_cap_oat_sander(vis, nl, rho), msh_ms_cap_cone_projected_solid_angle(rho, th, t));
  o[3u * i + 1u] = vec4(msh_ms_brinck_maximov2016_area_cap(vis, nl, rho), msh_ms_chan2018_area_cap(vis, nl, rho),
                        msh_ms_part1_analytic_area_cap(vis, nl, rho), msh_ms_generic_vndf_alu_area_cap(vis, nl, nv, r, rho));
  o[3u * i + 2u] = vec4(msh_ms_cap_intersection_solid_angle(rho, t, th),
                        msh_ms_cap_intersection_solid_angle_oat_sander(rho, t, th), t, th);
)");

void check(const char* label, const std::vector<Rec>& recs, const std::vector<float>& out) {
  // max |shader − C++ double at the same float inputs| over lights of at least 1° (the C++ float code is
  // printed beside for comparison). The tolerances are the precision the shader files state; lavapipe's
  // sin/cos/atan/acos are within the Vulkan precision rules, far looser than C++'s.
  const char* names[10] = {"step_area", "step_solid_angle", "step_oat_sander",  "cap_cone_E", "bm_area",
                           "chan_area", "part1_area",       "generic_alu_area", "mazonka",    "oat_sander"};
  const double tol[10] = {1.5e-3, 1.5e-3, 1.5e-3, 5e-5, 2e-3, 2e-3, 2e-3, 2e-3, 1e-4, 1e-4};
  double maxd[10] = {0}, maxf[10] = {0};
  const float deg = 3.14159265f / 180;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Rec& x = recs[i];
    const float* o = &out[i * kOut * 4];
    const std::array<double, 10> ref = cpu_outputs<double>(x);
    const std::array<float, 10> cpu = cpu_outputs<float>(x);
    for (int k = 0; k < 10; ++k) {
      ASSERT_TRUE(std::isfinite(o[k])) << label << " " << names[k] << " record " << i;
      if (x.rho < 1 * deg) continue;
      maxd[k] = std::max(maxd[k], std::abs(double(o[k]) - ref[size_t(k)]));
      maxf[k] = std::max(maxf[k], std::abs(double(cpu[size_t(k)]) - ref[size_t(k)]));
    }
    if (x.rho == 0.0f) {  // the point terms
      ASSERT_EQ(o[0], micro_shadowing::reference_step(x.vis, x.nl)) << label;
      ASSERT_NEAR(o[4], micro_shadowing::brinck_maximov_2016(x.vis, x.nl), 1e-6) << label;
      ASSERT_NEAR(o[5], micro_shadowing::chan_2018(x.vis, x.nl), 1e-6) << label;
    }
  }
  {  // the shader's own cone angle and cap angle (inputs of everything above)
    double dt = 0, dth = 0;
    size_t worst = 0;
    for (size_t i = 0; i < recs.size(); ++i) {
      const float* o = &out[i * kOut * 4];
      const double et = std::abs(o[10] - micro_shadowing::cone_angle(double(recs[i].vis)));
      const double eth = std::abs(o[11] - micro_shadowing::cap_theta(double(recs[i].nl)));
      if (eth > dth) worst = i;
      dt = std::max(dt, et), dth = std::max(dth, eth);
    }
    std::printf("[ %s ] cone angle max err %.2e rad, cap angle (acos N.L) max err %.2e rad at N.L = %.8g\n",
                label, dt, dth, double(recs[worst].nl));
  }
  for (int k = 0; k < 10; ++k) {
    EXPECT_LE(maxd[k], tol[k]) << label << " " << names[k];
    std::printf("[ %s ] %-18s max |shader - C++ double| %.2e (C++ float %.2e; tolerance %.0e)\n", label,
                names[k], maxd[k], maxf[k], tol[k]);
  }
}

}  // namespace

TEST(ShadersMicroShadowingArea, Compiles) {
  vk::expect_compiles(kKernel, {"float h = b - a, Sb", "float h = b - aa, Sb", false});
}

TEST(ShadersMicroShadowingArea, RunsOnVulkanAndMatchesCpp) {
  vk::run_records(kKernel, make_records(), kOut * 4, check);
}
