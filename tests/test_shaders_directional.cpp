// The GLSL and HLSL ports of the directional micro-occlusion run-time functions (shaders/{glsl,hlsl}/
// directional.*, one body in shaders/portable/directional.h): they compile with glslangValidator (GLSL 450,
// GLSL ES 320, HLSL) and, where a Vulkan device is available (lavapipe on CI), agree with the C++ float
// functions of occlusion/directional.h (directional_transport, directional_term, decode_unorm8) on random
// channel sets, the flat surface's channels and channels baked from small height fields (and their box mips),
// with lights above and below the horizon. The bound is the float rounding of a 9-term sum: |shader − C++| ≤
// 1e-6 · S, S = Σ|c_i||b_i(l)|, so that cancelling terms (a transport near 0 from large channels) are judged
// by the size of what cancels. Also the SPIR-V cost of the term after spirv-opt -O (docs/shaders.md).
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/directional_codec.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "support/directional_inputs.h"
#include "support/shader_kernel.h"

using namespace msh;
namespace vk = msh::test::vk;
using namespace msh::test::directional_inputs;
namespace dir = msh::directional;

namespace {

// One record: channels c0 = (c_0..c_3), c1 = (c_4..c_7), c8.x = c_8, the light l and the coarse normal n
// (xyz) → (transport packed, transport array, term packed, term array). A second buffer checks the 8-bit
// decode: (unorm, lo, hi) → the vector form and the scalar form per component.
const vk::Kernel kKernel = vk::framed_kernel(
    {"directional"},
    {{"in Rec rec", "out vec4 res", "in Dec dec", "out vec4 decoded"}, {}, "uint nr; uint nd;"},
    "struct Rec { vec4 c0; vec4 c1; vec4 c8; vec4 l; vec4 n; };\n"
    "struct Dec { vec4 u; vec4 lo; vec4 hi; vec4 pad; };\n",
    R"(
  if (i < pc.nr) {
    Rec r = rec[i];
    float c[9];
    c[0] = r.c0.x; c[1] = r.c0.y; c[2] = r.c0.z; c[3] = r.c0.w;
    c[4] = r.c1.x; c[5] = r.c1.y; c[6] = r.c1.z; c[7] = r.c1.w;
    c[8] = r.c8.x;
    res[i] = vec4(msh_dir_transport(r.c0, r.c1, r.c8.x, r.l.xyz), msh_dir_transport(c, r.l.xyz),
                  msh_dir_term(r.c0, r.c1, r.c8.x, r.l.xyz, r.n.xyz), msh_dir_term(c, r.l.xyz, r.n.xyz));
  }
  if (i < pc.nd) {
    Dec d = dec[i];
    vec4 s = vec4(msh_dir_decode_unorm8(d.u.x, d.lo.x, d.hi.x), msh_dir_decode_unorm8(d.u.y, d.lo.y, d.hi.y),
                  msh_dir_decode_unorm8(d.u.z, d.lo.z, d.hi.z), msh_dir_decode_unorm8(d.u.w, d.lo.w, d.hi.w));
    decoded[2u * i] = msh_dir_decode_unorm8(d.u, d.lo, d.hi);
    decoded[2u * i + 1u] = s;
  }
)");

// The bound of the shader files: transport within 1e-6 · S, term within 1e-6 · S / (n · l) + 1e-6 · |term|.
constexpr double kSumTol = 1e-6;
// n · l in float: C++ and the shader may round (and fuse) its 3 products differently, up to ~2 ulps of
// Σ|n_i l_i|; relative to n · l that matters only near the coarse terminator.
constexpr double kDotTol = 2.5e-7;

// The term at one record, its shader forms against the C++ float term, across the records of a run. n · l
// within rounding of the 1e-4 early-out (4e-7 Σ|n_i l_i|): not compared, either side is right (counted in
// boundary); below it: every form and the C++ term exactly 0 (counted in early); above: each form within
// kSumTol · S / (n · l) + (1e-6 + kDotTol Σ|n_i l_i| / (n · l)) · term, its error relative to
// S / (n · l) + term (1 + Σ|n_i l_i| / (n · l)) kept in max_scaled. After each record: d, the largest
// |form − C++| compared there (−1: none), and nl, its n · l.
struct TermCheck {
  int boundary = 0, early = 0;
  double max_scaled = 0, d = -1, nl = 0;

  void record(const Vec3f& n, const Vec3f& l, double s, float term_cpp, std::initializer_list<float> forms) {
    d = -1;
    nl = double(n.x) * l.x + double(n.y) * l.y + double(n.z) * l.z;
    const double nl_abs =
        std::abs(double(n.x) * l.x) + std::abs(double(n.y) * l.y) + std::abs(double(n.z) * l.z);
    if (std::abs(nl - 1e-4) < 4e-7 * nl_abs) {
      ++boundary;
      return;
    }
    if (!(nl > 1e-4)) {
      ++early;
      ASSERT_EQ(term_cpp, 0.0f);
      for (float f : forms) ASSERT_EQ(f, 0.0f);
      return;
    }
    int k = 0;
    for (float f : forms) {
      const double e = std::abs(double(f) - term_cpp);
      ASSERT_LE(e, kSumTol * s / nl + (1e-6 + kDotTol * nl_abs / nl) * term_cpp)
          << "term form " << k++ << ": shader " << f << " C++ " << term_cpp;
      max_scaled = std::max(max_scaled, e / (s / nl + term_cpp * (1 + nl_abs / nl)));
      d = std::max(d, e);
    }
  }
};

void check(const char* label, const std::vector<Rec>& recs, const std::vector<Dec>& decs,
           const std::vector<std::array<float, 4>>& res, const std::vector<std::array<float, 4>>& decoded) {
  double max_t = 0, max_rel_t = 0, max_rel_term = 0, max_baked_t = 0, max_baked_rel_t = 0, max_baked_term = 0;
  int below = 0, positive = 0;
  TermCheck terms;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const Rec& r = recs[i];
    SCOPED_TRACE(testing::Message() << label << " record " << i << " l " << r.l[0] << "," << r.l[1] << ","
                                    << r.l[2] << " n " << r.n[0] << "," << r.n[1] << "," << r.n[2]);
    const Vec3f l = light(r), n = normal(r);
    const float t_cpp = dir::directional_transport(channels(r), l);
    const float term_cpp = dir::directional_term(channels(r), l, n);
    for (float o : res[i]) {
      ASSERT_TRUE(std::isfinite(o));
      ASSERT_GE(o, 0.0f);
    }
    if (!(l.z > 0)) {  // below the horizon (and ±0): exactly 0, both forms
      ++below;
      for (float o : res[i]) ASSERT_EQ(o, 0.0f);
      continue;
    }
    const double s = sum_scale(r);
    for (int k : {0, 1}) {
      const double d = std::abs(double(res[i][std::size_t(k)]) - t_cpp);
      ASSERT_LE(d, kSumTol * s) << "transport form " << k << ": shader " << res[i][std::size_t(k)] << " C++ "
                                << t_cpp;
      max_t = std::max(max_t, d / s);
      if (t_cpp > 0.1 * s) max_rel_t = std::max(max_rel_t, d / t_cpp);
      if (r.c[9] != 0) {  // flat and baked channels: absolute, and relative where T > 0.01
        max_baked_t = std::max(max_baked_t, d);
        if (t_cpp > 0.01) max_baked_rel_t = std::max(max_baked_rel_t, d / t_cpp);
      }
    }
    if (t_cpp > 0) ++positive;
    ASSERT_NO_FATAL_FAILURE(terms.record(n, l, s, term_cpp, {res[i][2], res[i][3]}));
    if (terms.d < 0) continue;
    if (t_cpp > 0.1 * s) max_rel_term = std::max(max_rel_term, terms.d / term_cpp);
    if (r.c[9] != 0 && terms.nl > 0.01) max_baked_term = std::max(max_baked_term, terms.d);
  }
  EXPECT_GT(below, 2000) << label;
  EXPECT_GT(terms.early, 500) << label;
  EXPECT_GT(positive, 5000) << label;
  EXPECT_LT(terms.boundary, 64) << label;

  double max_dec = 0;
  for (std::size_t i = 0; i < decs.size(); ++i) {
    const Dec& x = decs[i];
    for (int form : {0, 1})
      for (std::size_t c = 0; c < 4; ++c) {
        const float got = decoded[2 * i + std::size_t(form)][c];
        const float want = dir::decode_unorm8(x.u[c], x.lo[c], x.hi[c]);
        const double scale = std::abs(double(x.lo[c])) + std::abs(double(x.hi[c]) - x.lo[c]);
        const double d = std::abs(double(got) - want);
        ASSERT_LE(d, 2.5e-7 * scale) << label << " decode " << i << "," << c;  // 2 roundings of ~1.2e-7
        if (x.u[c] == 0.0f) {
          ASSERT_EQ(got, x.lo[c]) << label;  // the range's low end is exact
        }
        max_dec = std::max(max_dec, d / scale);
      }
  }
  std::printf(
      "[ %s ] %zu records (%d below the horizon, %d n.l early-outs, all exactly 0; %d on the n.l boundary "
      "not compared): max |shader - C++ float| / S: transport %.2e, term (x n.l / (S + term n.l)) %.2e; "
      "relative where T > 0.1 S: transport %.2e, term %.2e; flat and baked channels: transport %.2e "
      "absolute, %.2e relative where T > 0.01, term %.2e absolute where n.l > 0.01; decode %zu x 8: %.2e of "
      "|lo| + |hi - lo|\n",
      label, recs.size(), below, terms.early, terms.boundary, max_t, terms.max_scaled, max_rel_t,
      max_rel_term, max_baked_t, max_baked_rel_t, max_baked_term, decs.size(), max_dec);
}

// ---- The view correction (21 channels packed in 6 vec4, msh_dir_view_transport / msh_dir_view_term) ----

// One record: the 6 packed vec4 (c[5].w = origin: 0 random, 1 flat, 2 baked; the shader never reads it),
// the light l, the view v and the coarse normal n → (transport, term, 0, 0).
const vk::Kernel kViewKernel = vk::framed_kernel({"directional"}, {{"in VRec rec", "out vec4 res"}, {}, ""},
                                                 "struct VRec { vec4 c[6]; vec4 l; vec4 v; vec4 n; };\n",
                                                 R"(
  if (i < pc.n) {
    VRec r = rec[i];
    vec4 c[6] = r.c;
    res[i] = vec4(msh_dir_view_transport(c, r.l.xyz, r.v.xyz), msh_dir_view_term(c, r.l.xyz, r.v.xyz, r.n.xyz),
                  0.0, 0.0);
  }
)");

void check_view(const char* label, const std::vector<VRec>& recs,
                const std::vector<std::array<float, 4>>& res) {
  double max_t = 0, max_baked_rel = 0;
  int below = 0, positive = 0, clamped_view = 0, free_view = 0;
  TermCheck terms;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const VRec& r = recs[i];
    SCOPED_TRACE(testing::Message() << label << " view record " << i);
    const Vec3f l(r.l[0], r.l[1], r.l[2]), v(r.v[0], r.v[1], r.v[2]), n(r.n[0], r.n[1], r.n[2]);
    const float t_cpp = dir::directional_view_transport(r.c.data(), r.c.data() + 9, l, v);
    const float term_cpp = dir::directional_view_term(r.c.data(), l, v, n);
    ASSERT_TRUE(std::isfinite(res[i][0]) && std::isfinite(res[i][1]));
    ASSERT_GE(res[i][0], 0.0f);
    ASSERT_GE(res[i][1], 0.0f);
    if (!(l.z > 0)) {
      ++below;
      ASSERT_EQ(res[i][0], 0.0f);
      ASSERT_EQ(res[i][1], 0.0f);
      continue;
    }
    clamped_view += v.z < dir::kMinViewZ;
    free_view += v.z > dir::kMinViewZ;
    const double s = view_sum_scale(r);
    const double d = std::abs(double(res[i][0]) - t_cpp);
    ASSERT_LE(d, kSumTol * s) << "transport: shader " << res[i][0] << " C++ " << t_cpp;
    max_t = std::max(max_t, d / s);
    if (r.c[23] == 2 && t_cpp > 0.01) max_baked_rel = std::max(max_baked_rel, d / t_cpp);
    positive += t_cpp > 0;
    ASSERT_NO_FATAL_FAILURE(terms.record(n, l, s, term_cpp, {res[i][1]}));
  }
  EXPECT_GT(below, 500) << label;
  EXPECT_GT(terms.early, 200) << label;
  EXPECT_GT(positive, 2000) << label;
  EXPECT_GT(clamped_view, 200) << label;
  EXPECT_GT(free_view, 200) << label;  // both sides of the view clamp
  EXPECT_LT(terms.boundary, 16) << label;
  std::printf(
      "[ %s ] view correction: %zu records (%d below the horizon, %d n.l early-outs, exactly 0; %d with v_z "
      "< 0.1): max |shader - C++ float| / S_v: transport %.2e, term %.2e; baked channels: %.2e relative "
      "where T > 0.01\n",
      label, recs.size(), below, terms.early, clamped_view, max_t, terms.max_scaled, max_baked_rel);
}

// Runs a command, returns its exit status.
int sh(const std::string& cmd) { return std::system(cmd.c_str()); }

}  // namespace

TEST(ShadersDirectional, Compiles) {
  vk::expect_compiles(kKernel, {"s += c[8] * (l.z * l.z);", "s += c[8] * (l.z * l.w);"});
}

TEST(ShadersDirectional, RunsOnVulkanAndMatchesCpp) {
  const auto recs = make_records();
  const auto decs = make_decodes();
  vk::run_two_record_sets(
      kKernel, {vk::to_floats(recs), recs.size(), 4}, {vk::to_floats(decs), decs.size(), 8},
      [&](const char* label, const std::vector<float>& res, const std::vector<float>& decoded) {
        check(label, recs, decs, vk::from_floats<std::array<float, 4>>(res),
              vk::from_floats<std::array<float, 4>>(decoded));
      });
}

TEST(ShadersDirectional, ViewCompiles) {
  vk::expect_compiles(kViewKernel, {"float vz = max(v.z, 0.5f);", "float vz = max(v.z, 0.5f)"});
}

TEST(ShadersDirectional, ViewRunsOnVulkanAndMatchesCpp) {
  const auto recs = make_view_records();
  vk::run_records(kViewKernel, recs, 4,
                  [&](const char* label, const std::vector<VRec>& r, const std::vector<float>& out) {
                    check_view(label, r, vk::from_floats<std::array<float, 4>>(out));
                  });
}

// ---- Compact forms: msh_dir_code8_decode / msh_dir_code4_decode then msh_dir_view_transport ----

// One record: the fetched coefficients u0 (u_0..3), u1 (u_4..7), the light and the view → (transport from
// the 8-coefficient code, from the 4-coefficient code, decoded channel 8 of each). Buffer 2 holds the two
// folded codes: fm8 (6 vec4), fb8 (48), fm4 (6), fb4 (24).
const vk::Kernel kCodeKernel =
    vk::framed_kernel({"directional"}, {{"in CRec rec", "out vec4 res", "in vec4 code"}, {}, ""},
                      "struct CRec { vec4 u0; vec4 u1; vec4 l; vec4 v; };\n", R"(
  if (i < pc.n) {
    CRec r = rec[i];
    vec4 fm8[6];
    vec4 fb8[48];
    vec4 fm4[6];
    vec4 fb4[24];
    for (int j = 0; j < 6; ++j) { fm8[j] = code[j]; fm4[j] = code[54 + j]; }
    for (int j = 0; j < 48; ++j) fb8[j] = code[6 + j];
    for (int j = 0; j < 24; ++j) fb4[j] = code[60 + j];
    vec4 c8[6];
    vec4 c4[6];
    msh_dir_code8_decode(r.u0, r.u1, fm8, fb8, c8);
    msh_dir_code4_decode(r.u0, fm4, fb4, c4);
    res[i] = vec4(msh_dir_view_transport(c8, r.l.xyz, r.v.xyz), msh_dir_view_transport(c4, r.l.xyz, r.v.xyz),
                  c8[2].x, c4[2].x);
  }
)");

struct CRec {
  std::array<float, 4> u0, u1, l, v;
};

TEST(ShadersDirectional, CompactFormsRunOnVulkanAndMatchCpp) {
  // Codes fitted to channels baked from a rough field; coefficients: every texel's own (encoded from its
  // channels and those of its box mips) and random UNORM values.
  const render::Texture ch = render::bake_directional_view_channels(test_field(2, 32), 6.0f, 32, 0.0f);
  const render::DirectionalCodec c8 = render::fit_directional_codec(ch, "pca8"),
                                 c4 = render::fit_directional_codec(ch, "pca4");
  const std::vector<float> fm8 = c8.folded_mean(), fb8 = c8.folded_basis(), fm4 = c4.folded_mean(),
                           fb4 = c4.folded_basis();
  std::vector<float> code(84 * 4, 0.0f);
  for (int i = 0; i < 21; ++i) {
    code[std::size_t(i)] = fm8[std::size_t(i)], code[std::size_t(54 * 4 + i)] = fm4[std::size_t(i)];
    for (int k = 0; k < 8; ++k) code[std::size_t(6 * 4 + 8 * i + k)] = fb8[std::size_t(8 * i + k)];
    for (int k = 0; k < 4; ++k) code[std::size_t(60 * 4 + 4 * i + k)] = fb4[std::size_t(4 * i + k)];
  }
  std::vector<std::array<float, 8>> us;
  for (int k : {1, 4}) {
    const render::Texture t = k == 1 ? ch : render::box_downsample(ch, k);
    const render::Texture a8 = render::encode_directional(t, c8), a4 = render::encode_directional(t, c4);
    for (int y = 0; y < t.height(); y += 2)
      for (int x = 0; x < t.width(); x += 2) {
        std::array<float, 8> u{};
        for (int q = 0; q < 8; ++q)
          u[std::size_t(q)] =
              (a8.at(x, y, q) - c8.lo[std::size_t(q)]) / (c8.hi[std::size_t(q)] - c8.lo[std::size_t(q)]);
        us.push_back(u);
      }
  }
  Pcg32 rng(91);
  for (int n = 0; n < 256; ++n) {
    std::array<float, 8> u{};
    for (float& x : u) x = float(rng.next_double());
    us.push_back(u);
  }
  std::vector<CRec> recs;
  for (const auto& u : us) {
    const Vec3f l(sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double())));
    const Vec3f v(sample_uniform_hemisphere(Vec2d(rng.next_double(), rng.next_double())));
    recs.push_back(
        {{u[0], u[1], u[2], u[3]}, {u[4], u[5], u[6], u[7]}, {l.x, l.y, l.z, 0}, {v.x, v.y, v.z, 0}});
  }
  vk::Dispatch d;
  d.buffers = {vk::to_floats(recs), std::vector<float>(recs.size() * 4), code};
  d.push = vk::push_constants(uint32_t(recs.size()));
  d.invocations = recs.size();
  vk::run_glsl_and_hlsl(kCodeKernel, d, [&](const char* label, const vk::Buffers& out) {
    const auto res = vk::from_floats<std::array<float, 4>>(out[1]);
    double worst = 0, worst_c = 0;
    int positive = 0;
    for (std::size_t r = 0; r < recs.size(); ++r) {
      const CRec& q = recs[r];
      const Vec3d l(q.l[0], q.l[1], q.l[2]), v(q.v[0], q.v[1], q.v[2]);
      for (int form = 0; form < 2; ++form) {
        const int K = form == 0 ? 8 : 4;
        const std::vector<float>&fm = form == 0 ? fm8 : fm4, &fb = form == 0 ? fb8 : fb4;
        double u[8], cd[21], mag[21];
        for (int k = 0; k < 8; ++k) u[k] = k < 4 ? q.u0[std::size_t(k)] : q.u1[std::size_t(k - 4)];
        for (int i = 0; i < 21; ++i) {
          cd[i] = fm[std::size_t(i)], mag[i] = std::abs(fm[std::size_t(i)]);
          for (int k = 0; k < K; ++k)
            cd[i] += double(fb[std::size_t(i * K + k)]) * u[k],
                mag[i] += std::abs(fb[std::size_t(i * K + k)] * u[k]);
        }
        // The decoded channel 8 against the double decode: a few roundings of the (K + 1)-term sum.
        const double e8 = std::abs(res[r][std::size_t(2 + form)] - cd[8]) / mag[8];
        worst_c = std::max(worst_c, e8);
        EXPECT_LE(e8, 1e-6) << label << " record " << r << " form " << K;
        // The transport against the double evaluation, relative to the magnitude of what is summed.
        const double t = dir::directional_view_transport(cd, cd + 9, l, v);
        double b[9], S = 0;
        dir::poly2_basis(Vec3d(std::abs(l.x), std::abs(l.y), std::abs(l.z)), b);
        b[6] = l.x * l.x + l.y * l.y;
        const double vz = std::max(v.z, dir::kMinViewZ);
        for (int i = 0; i < 9; ++i) S += mag[i] * b[i];
        for (int i = 0; i < 6; ++i)
          S += (mag[9 + i] * std::abs(v.x) + mag[15 + i] * std::abs(v.y)) * b[i] / vz;
        const double e = std::abs(res[r][std::size_t(form)] - t) / S;
        worst = std::max(worst, e);
        EXPECT_LE(e, 2e-6) << label << " record " << r << " form " << K;
        positive += t > 1e-3;
      }
    }
    EXPECT_GT(positive, int(recs.size()) / 2) << label;
    std::printf(
        "[ %s ] compact forms: %zu records, channel max %.2g, transport max %.2g (relative to the sums)\n",
        label, recs.size(), worst_c, worst);
  });
}

// The cost row of docs/shaders.md: a compute kernel calling only the function, counted by the project's one
// SPIR-V counter (scripts/spirv_cost.py: glslangValidator → spirv-opt -O → spirv-dis; its rule says which
// instructions are arithmetic): the instructions of the inlined entry point (≈ 20 of them are the kernel's 4
// vec4 loads and its store), the arithmetic ones by opcode and the image samples.
TEST(ShadersDirectional, SpirvCost) {
  if (sh("command -v spirv-opt > /dev/null 2>&1 && command -v spirv-dis > /dev/null 2>&1 && "
         "command -v glslangValidator > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "spirv-opt / spirv-dis / glslangValidator not found (Debian: spirv-tools, glslang-tools)";
  const std::string lib = vk::read_source("shaders/glsl/directional.glsl");
  const std::map<std::string, std::string> calls = {
      {"term", "msh_dir_term(a, b, c.w, c.xyz, d.xyz)"},
      {"view term (21 channels)",
       "msh_dir_view_term(vec4[6](a, b, c, d, a.yzwx, b.yzwx), c.xyz, d.xyz, a.xyz)"},
      {"term, array", "msh_dir_term(float[9](a.x, a.y, a.z, a.w, b.x, b.y, b.z, b.w, c.w), c.xyz, d.xyz)"},
      {"transport", "msh_dir_transport(a, b, c.w, c.xyz)"},
      // The compact forms: the folded code from a storage buffer (uniforms in an engine), the decode, then
      // the view transport.
      {"view transport, 8-coefficient code", "msh_dir_code8_view(a, b, c.xyz, d.xyz)"},
      {"view transport, 4-coefficient code", "msh_dir_code4_view(a, c.xyz, d.xyz)"},
      {"decode 9 channels",
       "dot(msh_dir_decode_unorm8(a, b, c), vec4(1.0)) + "
       "dot(msh_dir_decode_unorm8(d, a, b), vec4(1.0)) + msh_dir_decode_unorm8(c.w, d.x, d.y)"}};
  const std::filesystem::path tmp =
      std::filesystem::temp_directory_path() / ("msh_dir_spirv_" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  for (const auto& [name, call] : calls) {
    const std::string src =
        "#version 450\n" + lib +
        "layout(std140, binding = 2) uniform Code { vec4 fm[6]; vec4 fb[48]; };\n"
        "float msh_dir_code8_view(vec4 u0, vec4 u1, vec3 l, vec3 v) {\n"
        "  vec4 c[6];\n  msh_dir_code8_decode(u0, u1, fm, fb, c);\n  return msh_dir_view_transport(c, l, "
        "v);\n}\n"
        "float msh_dir_code4_view(vec4 u, vec3 l, vec3 v) {\n  vec4 f4[24];\n"
        "  for (int j = 0; j < 24; ++j) f4[j] = fb[j];\n"
        "  vec4 c[6];\n  msh_dir_code4_decode(u, fm, f4, c);\n  return msh_dir_view_transport(c, l, v);\n}\n"
        "layout(local_size_x = 64) in;\n"
        "layout(std430, binding = 0) readonly buffer In { vec4 rec[]; };\n"
        "layout(std430, binding = 1) writeonly buffer Out { float o[]; };\n"
        "void main() {\n  uint i = gl_GlobalInvocationID.x;\n"
        "  vec4 a = rec[4u * i], b = rec[4u * i + 1u], c = rec[4u * i + 2u], d = rec[4u * i + 3u];\n"
        "  o[i] = " +
        call + ";\n}\n";
    {
      std::ofstream f(tmp / "k.comp");
      f << src;
    }
    const std::string t = tmp.string();
    ASSERT_EQ(sh("/usr/bin/python3 " + std::string(MSH_SOURCE_DIR) + "/scripts/spirv_cost.py " + t +
                 "/k.comp --json > " + t + "/counts.json"),
              0)
        << name;
    const nlohmann::json c = nlohmann::json::parse(std::ifstream(tmp / "counts.json"));
    const int total = c.at("instructions"), arith = c.at("arithmetic"), samples = c.at("image_samples");
    std::string hist;
    for (const auto& [op, k] : c.at("ops").items()) hist += " " + op + " " + std::to_string(int(k));
    std::printf("[ spirv-opt -O ] %s: %d instructions, %d arithmetic (%s ), %d image samples\n", name.c_str(),
                total, arith, hist.c_str(), samples);
    EXPECT_EQ(samples, 0);
    // An ALU-only term: a handful of products and sums (the view term: three 9-term sums; a K-coefficient
    // code adds 21 K-term dot products).
    const int limit = name.find("8-coefficient") != std::string::npos   ? 200
                      : name.find("4-coefficient") != std::string::npos ? 140
                      : name.rfind("view", 0) == 0                      ? 90
                                                                        : 40;
    EXPECT_LE(arith, limit) << name;
  }
  std::filesystem::remove_all(tmp);
}
