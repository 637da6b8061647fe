// The GLSL and HLSL equivalent-cap forms for disk and rectangle lights (shaders/{glsl,hlsl}/
// micro_shadowing_area.*: msh_ms_quad_vector_form_factor, msh_ms_disk_vector_form_factor,
// msh_ms_equivalent_cap, msh_ms_reference_step_area_equivalent_cap) compile and, on the Vulkan device
// (lavapipe), agree with the C++ functions of occlusion/micro_shadowing_area.h in double at the same float
// inputs, on random tilted disks and rects (1°–40°, tilt ±60°, any roll) and degenerate ones.
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing_area.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "support/area_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;
using namespace msh::test::area_inputs::shapes;

namespace {

// Record: 4 quad corners, disk centre, disk normal (xyz + w: radius / vis / pad), 6 vec4.
// Output: F_quad.xyz + step_quad, F_disk.xyz + step_disk, cap_quad.xy + cap_disk.xy: 3 vec4.
const vk::Kernel kKernel =
    vk::framed_kernel({"micro_shadowing", "micro_shadowing_fit", "micro_shadowing_area"},
                      {{"in vec4 rec", "out vec4 o"}, {}, ""}, "", R"(
  uint b = 6u * i;
  vec3 q0 = rec[b].xyz, q1 = rec[b + 1u].xyz, q2 = rec[b + 2u].xyz, q3 = rec[b + 3u].xyz;
  vec3 c = rec[b + 4u].xyz, nd = rec[b + 5u].xyz;
  float R = rec[b + 4u].w, vis = rec[b + 5u].w;
  vec3 Fq = msh_ms_quad_vector_form_factor(q0, q1, q2, q3), Fd = msh_ms_disk_vector_form_factor(c, nd, R);
  vec3 qc = q0 + q1 + q2 + q3;
  o[3u * i] = vec4(Fq, msh_ms_reference_step_area_equivalent_cap(vis, Fq, qc));
  o[3u * i + 1u] = vec4(Fd, msh_ms_reference_step_area_equivalent_cap(vis, Fd, c));
  o[3u * i + 2u] = vec4(msh_ms_equivalent_cap(Fq, qc), msh_ms_equivalent_cap(Fd, c));
)");

void check(const char* label, const std::vector<Rec>& recs, const std::vector<float>& out) {
  // max |shader − C++ double at the same float inputs|; tolerances as the shader file states.
  double dF = 0, dstep = 0, dcap = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Rec& x = recs[i];
    const float* o = &out[i * 12];
    for (int k = 0; k < 12; ++k)
      ASSERT_TRUE(std::isfinite(o[k])) << label << " record " << i << " output " << k;
    const Vec3d q[4] = {v3(x.q[0]), v3(x.q[1]), v3(x.q[2]), v3(x.q[3])};
    const Vec3d qc = q[0] + q[1] + q[2] + q[3];
    const Vec3d Fq = micro_shadowing::polygon_vector_form_factor(q, 4);
    const Vec3d Fd = micro_shadowing::disk_vector_form_factor(v3(x.c), v3(x.nd), double(x.R));
    const auto eq = micro_shadowing::equivalent_cap(Fq, qc),
               ed = micro_shadowing::equivalent_cap(Fd, v3(x.c));
    const double sq = micro_shadowing::reference_step_area_equivalent_cap(double(x.vis), Fq, qc);
    const double sd = micro_shadowing::reference_step_area_equivalent_cap(double(x.vis), Fd, v3(x.c));
    for (int j = 0; j < 3; ++j) {
      const double e = std::max(std::abs(o[j] - (&Fq.x)[j]), std::abs(o[4 + j] - (&Fd.x)[j]));
      dF = std::max(dF, e);
    }
    // The cap's axis is ill-conditioned where F → 0 (an edge-on disk): compared for lights of at least 0.5°.
    if (length(Fq) > 1e-4 && length(Fd) > 1e-4)
      dcap = std::max({dcap, std::abs(o[8] - eq.n_dot_l), std::abs(o[9] - eq.rho),
                       std::abs(o[10] - ed.n_dot_l), std::abs(o[11] - ed.rho)});
    // Lights of at least 1° (the zero-size records give the point value, compared exactly below).
    if (eq.rho >= kPi<double> / 180 && ed.rho >= kPi<double> / 180)
      dstep = std::max({dstep, std::abs(o[3] - sq), std::abs(o[7] - sd)});
  }
  const float* z = &out[(recs.size() - 2) * 12];
  EXPECT_EQ(z[3], micro_shadowing::reference_step(0.5f, z[8])) << label << " zero-size quad";
  EXPECT_EQ(z[9], 0.0f) << label;
  EXPECT_LE(dF, 2e-5) << label;
  EXPECT_LE(dcap, 1e-4) << label;
  EXPECT_LE(dstep, 1.5e-3) << label;
  std::printf("[ %s ] max |shader - C++ double|: F %.2e, equivalent cap (N.L, rho) %.2e, step %.2e\n", label,
              dF, dcap, dstep);
}

}  // namespace

TEST(ShadersMicroShadowingAreaShapes, Compiles) {
  vk::expect_compiles(kKernel, {"float I0 = 6.28318530718f / D", "float I0 = 6.28318530718f / DD"});
}

TEST(ShadersMicroShadowingAreaShapes, RunsOnVulkanAndMatchesCpp) {
  vk::run_records(kKernel, make_records(), 12, check);
}
