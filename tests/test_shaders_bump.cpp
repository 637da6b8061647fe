// The GLSL and HLSL bump-terminator shaders (shaders/{glsl,hlsl}/bump_terminator.*): they compile with
// glslangValidator, and, where a Vulkan device is available (lavapipe on CI), they run and agree with the C++
// float code and with a double-precision evaluation of the closed forms, within the precision each shader
// file states.
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>

#include <array>

#include "support/bump_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;
using namespace msh::test::bump_inputs;

namespace {

// Compute kernels around the library: one record = (ng, ns, l) as vec4s → (conty, chiang, conty+test,
// chiang+test); a second entry evaluates the Hanika offset: (p, p0, p1, p2, n0, n1, n2, b) → p'.
const vk::Kernel kKernel = vk::framed_kernel(
    {"bump_terminator"},
    {{"in Rec rec", "out vec4 res", "in Tri tri", "out vec4 moved"}, {}, "uint nr; uint nt;"},
    "struct Rec { vec4 ng; vec4 ns; vec4 l; };\n"
    "struct Tri { vec4 p; vec4 p0; vec4 p1; vec4 p2; vec4 n0; vec4 n1; vec4 n2; vec4 b; };\n",
    R"(
  if (i < pc.nr) {
    vec3 ng = rec[i].ng.xyz, ns = rec[i].ns.xyz, l = rec[i].l.xyz;
    res[i] = vec4(msh_bump_conty2019(ng, ns, l, false), msh_bump_chiang2019(ng, ns, l, false),
                  msh_bump_conty2019(ng, ns, l, true), msh_bump_chiang2019(ng, ns, l, true));
  }
  if (i < pc.nt) {
    Tri t = tri[i];
    moved[i] = vec4(msh_hanika2021_shadow_origin(t.p.xyz, t.p0.xyz, t.p1.xyz, t.p2.xyz, t.n0.xyz, t.n1.xyz,
                                                 t.n2.xyz, t.b.xyz), 0.0);
  }
)");

void put(std::vector<float>& buf, const Vec3f& v) { buf.insert(buf.end(), {v.x, v.y, v.z, 0.0f}); }

void check_results(const char* label, const std::vector<Record>& recs, const std::vector<TriRecord>& tris,
                   const std::vector<std::array<float, 4>>& res,
                   const std::vector<std::array<float, 4>>& moved) {
  using bump::HemisphereTest;
  double err_conty[3] = {0, 0, 0}, err_chiang = 0, diff_cpu = 0;
  int exact_checked = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Record& r = recs[i];
    const float cpu[4] = {bump::conty2019(r.ng, r.ns, r.l), bump::chiang2019(r.ng, r.ns, r.l),
                          bump::conty2019(r.ng, r.ns, r.l, HemisphereTest::kOn),
                          bump::chiang2019(r.ng, r.ns, r.l, HemisphereTest::kOn)};
    for (int k = 0; k < 4; ++k) {
      ASSERT_TRUE(std::isfinite(res[i][k]) && res[i][k] >= 0 && res[i][k] <= 1) << label << " record " << i;
    }
    if (r.ns == r.ng) {
      ASSERT_EQ(res[i][0], 1.0f) << label << ": no perturbation must give exactly 1 (Conty), record " << i;
      ASSERT_EQ(res[i][1], 1.0f) << label << ": no perturbation must give exactly 1 (Chiang), record " << i;
      ++exact_checked;
    }
    if (r.l == r.ng) {
      ASSERT_EQ(res[i][0], 1.0f) << label << ": light along N_g, record " << i;
    }
    if (dot(r.ns, r.ns) == 0.0f) {
      ASSERT_EQ(res[i][0], 1.0f) << label;
      ASSERT_EQ(res[i][2], 0.0f) << label;
      continue;
    }
    const Vec3d ng = normalize(Vec3d(r.ng)), ns = normalize(Vec3d(r.ns)), l = normalize(Vec3d(r.l));
    const double c = std::abs(dot(ng, l));
    const int bin = c < 0.01 ? 0 : (c < 0.05 ? 1 : 2);
    err_conty[bin] = std::max(err_conty[bin], std::abs(res[i][0] - conty_ref(ng, ns, l)));
    diff_cpu = std::max(diff_cpu, double(std::abs(res[i][0] - cpu[0])));
    if (std::abs(dot(ns, l)) > 1e-3) {
      err_chiang = std::max(err_chiang, std::abs(res[i][1] - chiang_ref(ng, ns, l)));
      diff_cpu = std::max(diff_cpu, double(std::abs(res[i][1] - cpu[1])));
    }
    // The hemisphere test agrees with the CPU away from its boundary.
    if (std::abs(dot(ng, l)) > 1e-5 && std::abs(dot(ns, l)) > 1e-3) {
      ASSERT_NEAR(res[i][2], cpu[2], 1e-4) << label << " record " << i;
      ASSERT_NEAR(res[i][3], cpu[3], 1e-4) << label << " record " << i;
    }
  }
  EXPECT_GT(exact_checked, 200);
  // The precision stated in the shader files.
  EXPECT_LT(err_conty[0], 1e-4) << label;
  EXPECT_LT(err_conty[1], 5e-6) << label;
  EXPECT_LT(err_conty[2], 1e-6) << label;
  EXPECT_LT(err_chiang, 2e-5) << label;
  std::printf(
      "[ %s ] max |shader - double|: conty %.2e / %.2e / %.2e (|cos_i| <0.01, <0.05, >=0.05), chiang "
      "%.2e; max |shader - C++ float| %.2e\n",
      label, err_conty[0], err_conty[1], err_conty[2], err_chiang, diff_cpu);
  double err_hanika = 0;
  for (size_t i = 0; i < tris.size(); ++i) {
    const TriRecord& t = tris[i];
    const Vec3d want = bump::hanika2021_shadow_origin(Vec3d(t.p), {Vec3d(t.p0), Vec3d(t.p1), Vec3d(t.p2)},
                                                      {Vec3d(t.n0), Vec3d(t.n1), Vec3d(t.n2)},
                                                      std::array<double, 3>{t.b.x, t.b.y, t.b.z});
    err_hanika = std::max(err_hanika, length(Vec3d(moved[i][0], moved[i][1], moved[i][2]) - want));
  }
  EXPECT_LT(err_hanika, 2e-6) << label;
}

}  // namespace

TEST(ShadersBump, Compiles) { vk::expect_compiles(kKernel, {"return s2 / c8;", "return s2 / c8", false}); }

TEST(ShadersBump, RunsOnVulkanAndMatches) {
  const auto recs = make_records();
  const auto tris = make_tris();
  std::vector<float> in, in_t;
  for (const Record& r : recs) put(in, r.ng), put(in, r.ns), put(in, r.l);
  for (const TriRecord& t : tris)
    for (const Vec3f& v : {t.p, t.p0, t.p1, t.p2, t.n0, t.n1, t.n2, t.b}) put(in_t, v);
  vk::run_two_record_sets(
      kKernel, {in, recs.size(), 4}, {in_t, tris.size(), 4},
      [&](const char* label, const std::vector<float>& res, const std::vector<float>& moved) {
        check_results(label, recs, tris, vk::from_floats<std::array<float, 4>>(res),
                      vk::from_floats<std::array<float, 4>>(moved));
      });
}
