// The GLSL and HLSL LTC shaders (shaders/{glsl,hlsl}/ltc.*): they compile (GLSL 450, GLSL ES 320, HLSL), and
// on a Vulkan device (lavapipe on CI) the table fetch, D, and the sphere and rectangle integrals with their
// representative directions agree with the C++ double code (bsdf/ltc.h, ltc_shading.h) on random lights over
// random frames, within the precision the shader files state. The table is fitted in the test (8×8) and
// uploaded as RGBA32F 2D textures with hardware linear filtering.
#include <gtest/gtest.h>
#include <microshadow/bsdf/ltc.h>
#include <microshadow/bsdf/ltc_shading.h>
#include <microshadow/bsdf/runtime/ltc_baker.h>
#include <microshadow/math/sampling.h>

#include <array>

#include "support/ltc_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
using namespace msh::bsdf;
namespace vk = msh::test::vk;
using namespace msh::test::ltc_inputs::integrals;

namespace {

constexpr int kOut = 4;  // vec4 outputs per record

const vk::Kernel kKernel = vk::framed_kernel(
    {"shaders/glsl/ltc.glsl"}, {"shaders/hlsl/ltc.hlsl"},
    {{"in Rec rec", "out vec4 o"}, {"2d ltc_mat", "2d ltc_amp"}, "float size;"},
    "struct Rec { vec4 a; vec4 n; vec4 v; vec4 l; vec4 w; vec4 c; vec4 ex; vec4 ey; };\n", R"(
  Rec r = rec[i];
  vec2 uv = msh_ltc_uv(r.a.x, r.a.y, pc.size);
  vec4 t = textureLod(ltc_mat, uv, 0.0);
  vec2 amp = textureLod(ltc_amp, uv, 0.0).xy;
  uint k = i * 4u;
  o[k + 0u] = t;
  o[k + 1u] = vec4(amp, msh_ltc_eval(msh_ltc_minv(vec4(r.a.zw, r.w.w, 1.0)), r.w.xyz), msh_ltc_specular(vec4(0.5), amp, 0.04, 0.75));
  o[k + 2u] = msh_ltc_sphere(t, r.n.xyz, r.v.xyz, r.l.xyz, r.l.w, int(r.a.w > 0.0 ? 16.0 : 8.0));
  vec3 c = r.c.xyz, ex = r.ex.xyz * r.ex.w, ey = r.ey.xyz * r.ey.w;
  o[k + 3u] = msh_ltc_rect(t, r.n.xyz, r.v.xyz, c - ex - ey, c + ex - ey, c + ex + ey, c - ex + ey);
)",
    "struct Rec { float4 a; float4 n; float4 v; float4 l; float4 w; float4 c; float4 ex; float4 ey; };\n", R"(
  Rec r = rec[i];
  float2 uv = msh_ltc_uv(r.a.x, r.a.y, pc.size);
  float4 t = ltc_mat.SampleLevel(ltc_mat_smp, uv, 0.0);
  float2 amp = ltc_amp.SampleLevel(ltc_amp_smp, uv, 0.0).xy;
  uint k = i * 4u;
  o[k + 0u] = t;
  o[k + 1u] = float4(amp, msh_ltc_eval(msh_ltc_minv(float4(r.a.zw, r.w.w, 1.0)), r.w.xyz), msh_ltc_specular(float4(0.5, 0.5, 0.5, 0.5), amp, 0.04, 0.75));
  o[k + 2u] = msh_ltc_sphere(t, r.n.xyz, r.v.xyz, r.l.xyz, r.l.w, int(r.a.w > 0.0 ? 16.0 : 8.0));
  float3 c = r.c.xyz, ex = r.ex.xyz * r.ex.w, ey = r.ey.xyz * r.ey.w;
  o[k + 3u] = msh_ltc_rect(t, r.n.xyz, r.v.xyz, c - ex - ey, c + ex - ey, c + ex + ey, c - ex + ey);
)");

void check(const char* lang, const std::vector<Record>& recs, const std::vector<std::array<float, 4>>& o) {
  const LtcTable& t = table();
  // Filtering bound: lavapipe (like GPUs) quantizes the bilinear weights to 8 bits, so a fetch may differ
  // from the exact bilinear value by up to 2 · 2⁻⁹ of the largest neighbour difference (both axes).
  double step[6] = {0, 0, 0, 0, 0, 0};
  for (int j = 0; j < t.size; ++j)
    for (int i = 0; i < t.size; ++i)
      for (int c = 0; c < 6; ++c) {
        const float* tab = c < 4 ? t.mat.data() : t.amp.data();
        const int ch = c < 4 ? 4 : 2, cc = c < 4 ? c : c - 4;
        auto at = [&](int x, int y) { return double(tab[(size_t(y) * t.size + size_t(x)) * ch + cc]); };
        if (i + 1 < t.size) step[c] = std::max(step[c], std::abs(at(i + 1, j) - at(i, j)));
        if (j + 1 < t.size) step[c] = std::max(step[c], std::abs(at(i, j + 1) - at(i, j)));
      }
  double e_fetch = 0, e_eval = 0, e_sph = 0, e_rect = 0, e_dir = 0, e_spec = 0;
  int n_clipped = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Record& r = recs[i];
    const auto* q = &o[i * kOut];
    const LtcCoeffs<double> k = t.fetch(r.a[0], r.a[1]);
    const double fk[6] = {k.a, k.b, k.c, k.d, k.magnitude, k.fresnel};
    const double gk[6] = {q[0][0], q[0][1], q[0][2], q[0][3], q[1][0], q[1][1]};
    for (int c = 0; c < 6; ++c) {
      const double e = std::abs(fk[c] - gk[c]) / (2 * step[c] / 512 + 1e-6);
      e_fetch = std::max(e_fetch, e);  // ≤ 1 passes
    }
    // Everything below with the GPU's fetched coefficients, so only the shader arithmetic is measured.
    LtcCoeffs<double> g;
    g.a = q[0][0], g.b = q[0][1], g.c = q[0][2], g.d = q[0][3], g.magnitude = q[1][0], g.fresnel = q[1][1];
    LtcCoeffs<double> ev;
    ev.a = r.a[2], ev.b = r.a[3], ev.c = r.w[3], ev.d = 1;
    const double d = ltc_eval(ev.inv_m(), get(r.w));
    e_eval = std::max(e_eval, std::abs(d - q[1][2]) / std::max(d, 1e-3));
    e_spec = std::max(e_spec, std::abs((0.04 * g.magnitude + 0.96 * g.fresnel) * 0.5 * 0.75 - q[1][3]));
    const auto s = ltc_shade_sphere(g, get(r.n), get(r.v), get(r.l), double(r.l[3]), r.a[3] > 0 ? 16 : 8);
    e_sph = std::max(e_sph, std::abs(s.integral - q[2][0]));
    const Vec3d c = get(r.c), ex = get(r.ex) * double(r.ex[3]), ey = get(r.ey) * double(r.ey[3]);
    const Vec3d p[4] = {c - ex - ey, c + ex - ey, c + ex + ey, c - ex + ey};
    const auto rr = ltc_shade_polygon(g, get(r.n), get(r.v), p, 4);
    // Lights crossing the surface's horizon: the surface clip changes the integral (the records exercise it).
    if (std::abs(rr.integral - ltc_shade_polygon(g, get(r.n), get(r.v), p, 4, false).integral) > 1e-3)
      ++n_clipped;
    e_rect = std::max(e_rect, std::abs(rr.integral - q[3][0]));
    if (s.integral > 1e-3)
      e_dir = std::max(e_dir, 1 - dot(s.direction, normalize(Vec3d(q[2][1], q[2][2], q[2][3]))));
    if (rr.integral > 1e-3)
      e_dir = std::max(e_dir, 1 - dot(rr.direction, normalize(Vec3d(q[3][1], q[3][2], q[3][3]))));
  }
  std::printf(
      "[ %s ] fetch %.3g (of bound), eval rel %.3g, sphere %.3g, rect %.3g, dir 1-cos %.3g, spec %.3g, %d "
      "clipped\n",
      lang, e_fetch, e_eval, e_sph, e_rect, e_dir, e_spec, n_clipped);
  EXPECT_GE(n_clipped, 20) << lang;
  EXPECT_LE(e_fetch, 1.0) << lang;
  EXPECT_LE(e_eval, 1e-5) << lang;  // ltc.glsl: msh_ltc_eval relative error ≤ 1e-5
  EXPECT_LE(e_sph, 5e-5) << lang;   // ltc.glsl: integrals, absolute ≤ 5e-5 (the edge fit and float)
  EXPECT_LE(e_rect, 5e-5) << lang;
  EXPECT_LE(e_dir, 1e-6) << lang;  // representative direction: 1 − cos ≤ 1e-6
  EXPECT_LE(e_spec, 1e-6) << lang;
}

}  // namespace

TEST(ShadersLtc, Compiles) { vk::expect_compiles(kKernel); }

TEST(ShadersLtc, RunsOnVulkanAndMatches) {
  const auto recs = make_records();
  const LtcTable& t = table();
  std::vector<float> amp4(size_t(t.size) * t.size * 4, 0.f);
  for (size_t k = 0; k < size_t(t.size) * t.size; ++k)
    amp4[k * 4] = t.amp[k * 2], amp4[k * 4 + 1] = t.amp[k * 2 + 1];
  struct {
    uint32_t n;
    float size;
  } push{uint32_t(recs.size()), float(t.size)};
  vk::Dispatch d;
  d.buffers = {vk::to_floats(recs), std::vector<float>(recs.size() * kOut * 4)};
  d.images = {{uint32_t(t.size), uint32_t(t.size), 0, t.mat.data()},
              {uint32_t(t.size), uint32_t(t.size), 0, amp4.data()}};
  d.push = vk::push_constants(push);
  d.invocations = recs.size();
  vk::run_glsl_and_hlsl(kKernel, d, [&](const char* label, const vk::Buffers& out) {
    check(label, recs, vk::from_floats<std::array<float, 4>>(out[1]));
  });
}
