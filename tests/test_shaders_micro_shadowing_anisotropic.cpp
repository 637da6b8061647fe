// The anisotropic-roughness helper of the micro-shadowing shaders (msh_ms_lut_roughness_anisotropic in
// shaders/{glsl,hlsl}/micro_shadowing.*): it compiles (GLSL 450, GLSL ES 320, HLSL) and, on a Vulkan device
// (lavapipe), agrees with the C++ float function micro_shadowing::micro_shadowing_isotropic_roughness and
// with a double evaluation of the formula written here, over random anisotropic roughness and directions,
// poles included.
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/occlusion/micro_shadowing_anisotropic.h>

#include <cmath>
#include <vector>

#include "support/random_records.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;

namespace {

const vk::Kernel kKernel = vk::framed_kernel(
    {"micro_shadowing"}, {{"in Rec rec", "out float o"}, {}, ""},
    "struct Rec { vec4 v; vec4 l; };  // v.w, l.w: alpha_x, alpha_y\n",
    "  o[i] = msh_ms_lut_roughness_anisotropic(rec[i].v.xyz, rec[i].l.xyz, vec2(rec[i].v.w, rec[i].l.w));\n");

struct Rec {
  Vec3f v;
  float ax;
  Vec3f l;
  float ay;
};

std::vector<Rec> make_records() {
  std::vector<Rec> recs = test::random_records<Rec>(4096, 515, [](auto& u, int) {
    const double ax = 0.01 + u(), ay = 0.01 + u();
    return Rec{Vec3f(spherical_direction(u(), 2 * kPi<double> * u())), float(ax * ax),
               Vec3f(spherical_direction(u(), 2 * kPi<double> * u())), float(ay * ay)};
  });
  // Poles (azimuth undefined) and α below GGX's kMinAlpha.
  recs.push_back({Vec3f(0, 0, 1), 0.3f, Vec3f(0, 0, 1), 0.7f});
  recs.push_back({Vec3f(0, 0, 1), 0.3f, Vec3f(1, 0, 0), 0.7f});
  recs.push_back({Vec3f(0, 1, 0), 0.0f, Vec3f(0.6f, 0, 0.8f), 0.0f});
  return recs;
}

// sqrt(sqrt((α(v)² + α(l)²)/2)) in double, α(w)² = (αx² x² + αy² y²)/(x² + y²), (αx² + αy²)/2 at the pole.
double formula(const Rec& r) {
  const double ax = std::max(double(r.ax), 1e-4), ay = std::max(double(r.ay), 1e-4);
  auto a2 = [&](const Vec3f& w) {
    const double s2 = double(w.x) * w.x + double(w.y) * w.y;
    return s2 > 0 ? (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / s2 : 0.5 * (ax * ax + ay * ay);
  };
  return std::sqrt(std::sqrt(0.5 * (a2(r.v) + a2(r.l))));
}

void check(const char* label, const std::vector<Rec>& recs, const std::vector<float>& out) {
  double max_rel_cpp = 0, max_rel_formula = 0;
  for (size_t i = 0; i < recs.size(); ++i) {
    const Rec& r = recs[i];
    const float cpp = micro_shadowing::micro_shadowing_isotropic_roughness(r.ax, r.ay, r.v, r.l);
    ASSERT_TRUE(std::isfinite(out[i])) << label << " " << i;
    max_rel_cpp = std::max(max_rel_cpp, std::abs(double(out[i]) - cpp) / cpp);
    max_rel_formula = std::max(max_rel_formula, std::abs(double(out[i]) - formula(r)) / formula(r));
  }
  EXPECT_LE(max_rel_cpp, 1e-6) << label;
  EXPECT_LE(max_rel_formula, 1e-6) << label;
  std::printf("[ %s ] %zu inputs: max relative |shader - C++ float| %.2e, |shader - double formula| %.2e\n",
              label, recs.size(), max_rel_cpp, max_rel_formula);
}

}  // namespace

static_assert(sizeof(Rec) == 32);

TEST(ShadersMicroShadowingAnisotropic, Compiles) { vk::expect_compiles(kKernel); }

TEST(ShadersMicroShadowingAnisotropic, RunsOnVulkanAndMatchesCpp) {
  vk::run_records(kKernel, make_records(), 1, check);
}
