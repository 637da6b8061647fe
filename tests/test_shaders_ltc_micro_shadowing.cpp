// The GLSL and HLSL ports of the LTC cone-clipped area-light micro-shadowing (shaders/{glsl,hlsl}/ltc.*:
// msh_ltc_ms_step_sphere/_rect, msh_ltc_ms_brinck_maximov_sphere/_rect, msh_ltc_tail_weight) compile (GLSL
// 450, GLSL ES 320, HLSL) and, on a Vulkan device (lavapipe on CI), agree with the C++ double code
// (bsdf/ltc_shading.h LtcLightCone, ltc_reference_step_area, ltc_micro_shadowing_area with
// brinck_maximov_2016_kinks) at the same float inputs: random sphere and rectangle lights over random frames,
// Lambertian (identity M⁻¹, no tail) and GGX receivers (LTC coefficients from a small table fitted here, tail
// 1.5 α^1.5), random visibility, plus degenerate inputs (light below the horizon, V = 0, V = 1, tiny lights,
// cos t near 0 and 1, view along n) that must stay finite and in [0, 1]. Also checks the Lambertian sphere
// light's step against the exact cap-cone form (occlusion/micro_shadowing_area.h reference_step_area_cap), an
// independent reference of the K-gon approximations.
#include <gtest/gtest.h>
#include <microshadow/bsdf/ltc.h>
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_area.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "support/ltc_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
using namespace msh::bsdf;
namespace vk = msh::test::vk;
using namespace msh::test::ltc_inputs::cone;

namespace {

// Lavapipe compiles each inlined cone clip (Sutherland–Hodgman over 40-vertex local arrays) in several
// seconds, so the run kernel inlines each building block once: invocation j shades record j/2's sphere (j
// even) or rectangle (j odd) light with the builders msh_ltc_cone_sphere / _rect, then msh_ltc_cone_ccdf (the
// step) and msh_ltc_cone_brinck_maximov; the one-line wrappers msh_ltc_ms_* (compositions of these) are
// compile-checked in their own kernel. Outputs per invocation: (step, Brinck–Maximov, z_lo, z_hi),
// (tail weight, clipped light's vertex count, 0, 0).
constexpr int kOut = 2;

const std::string kBody = R"(
  Rec r = rec[i / 2u];
  V3 c = r.c.xyz, ex = r.ex.xyz * r.ex.w, ey = r.ey.xyz * r.ey.w;
  V3 p0 = c - ex - ey, p1 = c + ex - ey, p2 = c + ex + ey, p3 = c - ex + ey;
  int sides = int(r.k.x), nodes = int(r.k.y);
#if MSH_WRAPPERS
  o[2u * i] = V4(msh_ltc_ms_step_sphere(r.t, r.n.xyz, r.v.xyz, r.l.xyz, r.l.w, sides, r.n.w, r.v.w),
                 msh_ltc_ms_step_rect(r.t, r.n.xyz, r.v.xyz, p0, p1, p2, p3, r.n.w, r.v.w),
                 msh_ltc_ms_brinck_maximov_sphere(r.t, r.n.xyz, r.v.xyz, r.l.xyz, r.l.w, sides, r.n.w, r.c.w, nodes),
                 msh_ltc_ms_brinck_maximov_rect(r.t, r.n.xyz, r.v.xyz, p0, p1, p2, p3, r.n.w, r.c.w, nodes));
#else
  MshLtcCone s;
  if ((i & 1u) == 0u)
    s = msh_ltc_cone_sphere(r.t, r.n.xyz, r.v.xyz, r.l.xyz, r.l.w, sides, r.n.w);
  else
    s = msh_ltc_cone_rect(r.t, r.n.xyz, r.v.xyz, p0, p1, p2, p3, r.n.w);
  o[2u * i] = V4(msh_ltc_cone_ccdf(s, r.v.w), msh_ltc_cone_brinck_maximov(s, r.c.w, nodes), s.z_lo, s.z_hi);
  o[2u * i + 1u] = V4(msh_ltc_tail_weight(r.k.z), float(s.n), 0.0, 0.0);
#endif
)";

vk::Kernel kernel(bool wrappers) {
  const std::string def = std::string("#define MSH_WRAPPERS ") + (wrappers ? "1" : "0") + "\n";
  return vk::framed_kernel(
      {"shaders/glsl/ltc.glsl"}, {"shaders/hlsl/ltc.hlsl"}, {{"in Rec rec", "out vec4 o"}, {}, ""},
      def + "#define V3 vec3\n#define V4 vec4\n" +
          "struct Rec { vec4 t; vec4 n; vec4 v; vec4 l; vec4 c; vec4 ex; vec4 ey; vec4 k; };\n",
      kBody,
      def + "#define V3 float3\n#define V4 float4\n" +
          "struct Rec { float4 t; float4 n; float4 v; float4 l; float4 c; float4 ex; float4 ey; float4 k; "
          "};\n",
      kBody);
}

void check(const char* lang, const std::vector<Record>& recs, const std::vector<std::array<float, 4>>& o) {
  double e_step = 0, e_bm = 0, e_tail = 0, e_z = 0, e_cap = 0;
  double e_step_lambert = 0, e_step_ggx = 0, e_deg = 0;
  int n_tiny = 0;
  int n_bad = 0, n_mid = 0, n_deg_nonzero = 0, n_cap = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Record& r = recs[i];
    const auto& gs = o[2 * i * kOut];        // sphere: step, Brinck–Maximov, z_lo, z_hi
    const auto& gr = o[(2 * i + 1) * kOut];  // rectangle
    const std::array<float, 4> g = {gs[0], gr[0], gs[1], gr[1]};
    for (const auto& q : {gs, gr})
      for (int c = 0; c < 4; ++c)
        if (!std::isfinite(q[size_t(c)]) || q[size_t(c)] < 0.f || q[size_t(c)] > 1.f) {
          if (++n_bad <= 5)
            std::printf("  [ %s ] record %zu output %d = %g\n", lang, i, c, double(q[size_t(c)]));
        }
    e_tail = std::max(e_tail, std::abs(ltc_tail_weight(double(r.k[2])) - double(o[2 * i * kOut + 1][0])));
    const Cpu x = cpu(r);
    if (r.k[3] > 0) {  // degenerate: finiteness and range above; V = 0 / below the horizon give exactly 0
      const int kind = int(i % 8);
      if ((kind == 0 || kind == 3) && (g[0] != 0.f || g[1] != 0.f)) ++n_deg_nonzero;
      if (kind == 1 && x.sphere.den > 0 && g[0] != 1.f) ++n_deg_nonzero;  // V = 1: all of the light is lit
      // And the same bound as the random records for lights of weight ≥ 1e-7 (the 0.001° lights have ~1e-10
      // and are included: the short edges do not cancel in msh_ltc_edge). A sliver above the horizon of
      // weight ~1e-9 loses its projected area to float cancellation (measured 0.05 on one at cos t = 1e-4).
      for (int l = 0; l < 2; ++l) {
        const LtcLightCone<double>& cone = l == 0 ? x.sphere : x.rect;
        if (!(cone.den > (kind == 4 ? 0.0 : 1e-7))) continue;
        const double e = std::max(std::abs((l == 0 ? x.step_s : x.step_r) - g[size_t(l)]),
                                  std::abs((l == 0 ? x.bm_s : x.bm_r) - g[size_t(2 + l)]));
        e_deg = std::max(e_deg, e);
        if (kind == 4) ++n_tiny;
      }
      continue;
    }
    const double es = std::max(std::abs(x.step_s - g[0]), std::abs(x.step_r - g[1]));
    e_step = std::max(e_step, es);
    (r.t[1] == 0 && r.t[2] == 0 && r.n[3] == 0 ? e_step_lambert : e_step_ggx) =
        std::max(r.t[1] == 0 && r.t[2] == 0 && r.n[3] == 0 ? e_step_lambert : e_step_ggx, es);
    e_bm = std::max(e_bm, std::max(std::abs(x.bm_s - g[2]), std::abs(x.bm_r - g[3])));
    if (x.sphere.n > 0)
      e_z = std::max({e_z, std::abs(x.sphere.z_lo - gs[2]), std::abs(x.sphere.z_hi - gs[3])});
    if (x.rect.n > 0) e_z = std::max({e_z, std::abs(x.rect.z_lo - gr[2]), std::abs(x.rect.z_hi - gr[3])});
    if (x.step_s > 0.02 && x.step_s < 0.98) ++n_mid;
    // Lambertian sphere light wholly above the horizon: the exact cap-cone ratio (16-gon light and cone).
    const Vec3d n = get(r.n), l = get(r.l);
    const double rho = std::asin(double(r.l[3])), nl = dot(n, l) / length(l);
    if (r.n[3] == 0 && r.t[1] == 0 && int(r.k[0]) == 16 &&
        std::acos(std::min(nl, 1.0)) + rho < kPi<double> / 2) {
      const double V = 1 - double(r.v[3]) * double(r.v[3]);
      e_cap = std::max(e_cap, std::abs(micro_shadowing::reference_step_area_cap(V, nl, rho) - g[0]));
      ++n_cap;
    }
  }
  std::printf(
      "[ %s ] max |GPU - C++|: step %.3g (Lambert %.3g, GGX %.3g), Brinck-Maximov %.3g, tail %.3g, z range "
      "%.3g; %d steps in (0.02, 0.98); Lambert sphere step vs exact cap %.3g (%d); %d bad, %d degenerate "
      "off; degenerate records %.3g (%d tiny lights)\n",
      lang, e_step, e_step_lambert, e_step_ggx, e_bm, e_tail, e_z, n_mid, e_cap, n_cap, n_bad, n_deg_nonzero,
      e_deg, n_tiny);
  EXPECT_EQ(n_bad, 0) << lang;
  EXPECT_EQ(n_deg_nonzero, 0) << lang;
  EXPECT_GE(n_mid, 200) << lang;  // the step is exercised off its trivial values
  EXPECT_GE(n_cap, 100) << lang;
  EXPECT_LE(e_step, 1e-3) << lang;  // ltc.glsl: msh_ltc_ms_step_* |diff| ≤ 1e-3
  EXPECT_LE(e_bm, 1e-3) << lang;    // ltc.glsl: msh_ltc_ms_brinck_maximov_* |diff| ≤ 1e-3
  EXPECT_LE(e_deg, 1e-3) << lang;
  EXPECT_GE(n_tiny, 80) << lang;
  EXPECT_LE(e_tail, 1e-6) << lang;
  EXPECT_LE(e_z, 1e-4) << lang;
  EXPECT_LE(e_cap, 0.03) << lang;  // the two 16-gons against the exact cap-cone ratio: 0.016 measured
}

}  // namespace

TEST(ShadersLtcMicroShadowing, Compiles) {
  vk::expect_compiles(kernel(false));
  vk::expect_compiles(kernel(true));
  // Not vacuous: a type error inside the cone clip (GLSL and HLSL) must be rejected.
  vk::expect_broken_source_rejected(kernel(false), "float db = dot(d, b);", "float db = dot(d, b, b);");
}

TEST(ShadersLtcMicroShadowing, RunsOnVulkanAndMatches) {
  const auto recs = make_records();
  const size_t n = 2 * recs.size();  // a sphere and a rectangle light per record
  vk::Dispatch d;
  d.buffers = {vk::to_floats(recs), std::vector<float>(n * kOut * 4)};
  d.push = vk::push_constants(uint32_t(n));
  d.invocations = n;
  vk::run_glsl_and_hlsl(kernel(false), d, [&](const char* label, const vk::Buffers& out) {
    check(label, recs, vk::from_floats<std::array<float, 4>>(out[1]));
  });
}
