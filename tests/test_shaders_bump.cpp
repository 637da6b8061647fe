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
#include <cstring>
#include <fstream>
#include <sstream>

#include "support/vk_compute.h"

using namespace msh;
namespace vk = msh::test::vk;

namespace {

using vk::read_source;

// Compute kernels around the library: one record = (ng, ns, l) as vec4s → (conty, chiang, conty+test,
// chiang+test); a second entry evaluates the Hanika offset: (p, p0, p1, p2, n0, n1, n2, b) → p'.
const char* kGlslMain = R"(
layout(local_size_x = 64) in;
struct Rec { vec4 ng; vec4 ns; vec4 l; };
struct Tri { vec4 p; vec4 p0; vec4 p1; vec4 p2; vec4 n0; vec4 n1; vec4 n2; vec4 b; };
layout(std430, binding = 0) readonly buffer In { Rec rec[]; };
layout(std430, binding = 1) writeonly buffer Out { vec4 res[]; };
layout(std430, binding = 2) readonly buffer InT { Tri tri[]; };
layout(std430, binding = 3) writeonly buffer OutT { vec4 moved[]; };
layout(push_constant) uniform PC { uint n; uint nt; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.n) {
    vec3 ng = rec[i].ng.xyz, ns = rec[i].ns.xyz, l = rec[i].l.xyz;
    res[i] = vec4(msh_bump_conty2019(ng, ns, l, false), msh_bump_chiang2019(ng, ns, l, false),
                  msh_bump_conty2019(ng, ns, l, true), msh_bump_chiang2019(ng, ns, l, true));
  }
  if (i < pc.nt) {
    Tri t = tri[i];
    moved[i] = vec4(msh_hanika2021_shadow_origin(t.p.xyz, t.p0.xyz, t.p1.xyz, t.p2.xyz, t.n0.xyz, t.n1.xyz,
                                                 t.n2.xyz, t.b.xyz), 0.0);
  }
}
)";

const char* kHlslMain = R"(
struct Rec { float4 ng; float4 ns; float4 l; };
struct Tri { float4 p; float4 p0; float4 p1; float4 p2; float4 n0; float4 n1; float4 n2; float4 b; };
[[vk::binding(0)]] StructuredBuffer<Rec> rec;
[[vk::binding(1)]] RWStructuredBuffer<float4> res;
[[vk::binding(2)]] StructuredBuffer<Tri> tri;
[[vk::binding(3)]] RWStructuredBuffer<float4> moved;
struct PC { uint n; uint nt; };
[[vk::push_constant]] PC pc;
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
  uint i = id.x;
  if (i < pc.n) {
    float3 ng = rec[i].ng.xyz, ns = rec[i].ns.xyz, l = rec[i].l.xyz;
    res[i] = float4(msh_bump_conty2019(ng, ns, l, false), msh_bump_chiang2019(ng, ns, l, false),
                    msh_bump_conty2019(ng, ns, l, true), msh_bump_chiang2019(ng, ns, l, true));
  }
  if (i < pc.nt) {
    Tri t = tri[i];
    moved[i] = float4(msh_hanika2021_shadow_origin(t.p.xyz, t.p0.xyz, t.p1.xyz, t.p2.xyz, t.n0.xyz, t.n1.xyz,
                                                   t.n2.xyz, t.b.xyz), 0.0);
  }
}
)";

std::string glsl_source(const char* version) {
  return std::string("#version ") + version + "\n" + read_source("shaders/glsl/bump_terminator.glsl") +
         kGlslMain;
}
std::string hlsl_source() { return read_source("shaders/hlsl/bump_terminator.hlsl") + kHlslMain; }

struct Record {
  Vec3f ng, ns, l;
};
struct TriRecord {
  Vec3f p, p0, p1, p2, n0, n1, n2, b;
};

void put(std::vector<std::byte>& buf, const Vec3f& v) {
  const float f[4] = {v.x, v.y, v.z, 0.0f};
  const auto* b = reinterpret_cast<const std::byte*>(f);
  buf.insert(buf.end(), b, b + sizeof f);
}

// Inputs: random configurations plus the exact cases (no perturbation, light along N_g, zero vectors).
std::vector<Record> make_records() {
  std::vector<Record> r;
  Pcg32 rng(77);
  for (int i = 0; i < 8192; ++i) {
    const Vec3d ng = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
    const Framed f = Framed::from_z(ng);
    const Vec3d ns = f.to_world(sample_uniform_cone(Vec2d(rng.next_double(), rng.next_double()), 0.05));
    const Vec3d l = sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()));
    const double scale = std::exp(rng.next_double() * 4 - 2);  // not unit length
    r.push_back({Vec3f(ng), Vec3f(ns * scale), Vec3f(l)});
  }
  for (int i = 0; i < 256; ++i) {
    const Vec3f ng = Vec3f(sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double())));
    const Vec3f l = Vec3f(sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double())));
    const Vec3f ns = Vec3f(sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double())));
    r.push_back({ng, ng, l});       // no perturbation → exactly 1
    r.push_back({ng, ns, ng});      // light along N_g → Conty exactly 1
    r.push_back({ng, Vec3f(), l});  // zero shading normal → 1 (0 with the hemisphere test)
  }
  return r;
}

std::vector<TriRecord> make_tris() {
  std::vector<TriRecord> t;
  Pcg32 rng(78);
  for (int i = 0; i < 2048; ++i) {
    auto u = [&] { return Vec3f(sample_uniform_sphere(Vec2d(rng.next_double(), rng.next_double()))); };
    float a = float(rng.next_double()), b = float(rng.next_double());
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const Vec3f p0 = u(), p1 = u(), p2 = u();
    const Vec3f bary(1 - a - b, a, b);
    const Vec3f p = p0 * bary.x + p1 * bary.y + p2 * bary.z;
    t.push_back({p, p0, p1, p2, u(), u() * 2.0f, u(), bary});
  }
  return t;
}

// Runs one shader on the device; returns false (with the reason) if the run itself failed.
bool run_kernel(vk::Context& ctx, const std::string& source, vk::Lang lang, const std::vector<Record>& recs,
                const std::vector<TriRecord>& tris, std::vector<std::array<float, 4>>* res,
                std::vector<std::array<float, 4>>* moved, std::string* why) {
  std::vector<uint32_t> spv;
  if (!vk::compile_shader(source, lang, &spv, why)) return false;
  std::vector<std::byte> in, out(recs.size() * 16), in_t, out_t(tris.size() * 16);
  for (const Record& r : recs) put(in, r.ng), put(in, r.ns), put(in, r.l);
  for (const TriRecord& t : tris)
    for (const Vec3f& v : {t.p, t.p0, t.p1, t.p2, t.n0, t.n1, t.n2, t.b}) put(in_t, v);
  const uint32_t push[2] = {uint32_t(recs.size()), uint32_t(tris.size())};
  const uint32_t groups = uint32_t((std::max(recs.size(), tris.size()) + 63) / 64);
  if (!ctx.run(spv, {&in, &out, &in_t, &out_t}, push, sizeof push, groups, why)) return false;
  res->resize(recs.size());
  moved->resize(tris.size());
  std::memcpy(res->data(), out.data(), out.size());
  std::memcpy(moved->data(), out_t.data(), out_t.size());
  return true;
}

// Conty reference (listing 12.1) and Chiang closed form in double, on unit vectors.
double conty_ref(const Vec3d& ng, const Vec3d& ns, const Vec3d& l) {
  const double cos_d = std::min(std::abs(dot(ng, ns)), 1.0);
  const double alpha2 = std::clamp(0.125 * (1 - cos_d * cos_d) / (cos_d * cos_d), 0.0, 1.0);
  const double cos_i = std::max(std::abs(dot(ng, l)), 1e-6);
  return 2.0 / (1 + std::sqrt(1 + alpha2 * (1 - cos_i * cos_i) / (cos_i * cos_i)));
}
double chiang_ref(const Vec3d& ng, const Vec3d& ns, const Vec3d& l) {
  const double g = dot(ng, l) / (dot(ns, l) * dot(ng, ns));
  return g >= 1 ? 1 : (g < 0 ? 0 : -g * g * g + g * g + g);
}

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

TEST(ShadersBump, GlslCompiles) {
  ASSERT_FALSE(vk::glslang_validator().empty()) << "glslangValidator missing: run scripts/install-deps.sh";
  for (const char* version : {"450", "320 es"}) {
    std::vector<uint32_t> spv;
    std::string log;
    EXPECT_TRUE(vk::compile_shader(glsl_source(version), vk::Lang::kGlsl, &spv, &log)) << version << "\n"
                                                                                       << log;
    EXPECT_GT(spv.size(), 100u);
  }
}

TEST(ShadersBump, HlslCompiles) {
  ASSERT_FALSE(vk::glslang_validator().empty()) << "glslangValidator missing: run scripts/install-deps.sh";
  std::vector<uint32_t> spv;
  std::string log;
  EXPECT_TRUE(vk::compile_shader(hlsl_source(), vk::Lang::kHlsl, &spv, &log)) << log;
}

// A broken shader must fail to compile: the compile check is not vacuous.
TEST(ShadersBump, CompileCheckRejectsBrokenSource) {
  ASSERT_FALSE(vk::glslang_validator().empty());
  std::vector<uint32_t> spv;
  std::string log;
  std::string broken = glsl_source("450");
  broken.replace(broken.find("return s2 / c8;"), 15, "return s2 / c8");
  EXPECT_FALSE(vk::compile_shader(broken, vk::Lang::kGlsl, &spv, &log));
}

TEST(ShadersBump, RunsOnVulkanAndMatches) {
  std::string why;
  vk::Context* ctx = vk::Context::get(&why);
  if (!ctx) GTEST_SKIP() << "no Vulkan compute device: " << why;
  std::printf("[ vulkan ] device: %s\n", ctx->device_name().c_str());
  const auto recs = make_records();
  const auto tris = make_tris();
  std::vector<std::array<float, 4>> res, moved;
  ASSERT_TRUE(run_kernel(*ctx, glsl_source("450"), vk::Lang::kGlsl, recs, tris, &res, &moved, &why)) << why;
  check_results("glsl", recs, tris, res, moved);
  ASSERT_TRUE(run_kernel(*ctx, hlsl_source(), vk::Lang::kHlsl, recs, tris, &res, &moved, &why)) << why;
  check_results("hlsl", recs, tris, res, moved);
}
