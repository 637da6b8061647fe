// HeightField::intersect (maximum-mipmap traversal) against its reference HeightField::intersect_dda (the
// plain DDA): the same answer bit for bit — hit or miss, t and the facet normal — for the rays the renderer
// casts (orthographic camera rays, shadow rays from surface points at every elevation and azimuth,
// axis-aligned and diagonal directions, origins tiles away from the base tile, finite tmax) on procedural,
// generated relief, flat, steep random and non-power-of-two height fields; and the pieces it is built from
// (the max pyramid, the exact repeated float addition).
#include <gtest/gtest.h>
#include <microshadow/math/sampling.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/texture_gen.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

using namespace msh;
using namespace msh::render;

namespace {

constexpr float kPiF = 3.14159265358979f;
constexpr float kInfF = std::numeric_limits<float>::infinity();

Texture field(int w, int h, const auto& f) {
  Texture t(w, h, 1);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) t.at(i, j, 0) = f(i, j);
  return t;
}

// Procedural rough relief: a few octaves of wrapping sines with random phases plus per-texel noise.
Texture rough_field(int w, int h, uint64_t seed) {
  Pcg32 rng(seed);
  float ph[8];
  for (float& p : ph) p = 2 * kPiF * rng.next_float();
  return field(w, h, [&](int i, int j) {
    const float x = 2 * kPiF * float(i) / float(w), y = 2 * kPiF * float(j) / float(h);
    float v = 0.5f;
    for (int o = 0; o < 4; ++o) {
      const float f = float(1 << o);
      v += 0.12f / f * std::sin(f * x + ph[2 * o]) * std::cos(f * y + ph[2 * o + 1]);
    }
    return std::clamp(v + 0.05f * (rng.next_float() - 0.5f), 0.0f, 1.0f);
  });
}

Texture generated(const std::string& kind, int size, float* depth) {
  GenOptions o;
  o.kind = kind;
  o.size = size;
  o.ao_rays = 1;  // only the height map is used
  o.ao_max_distance = 1;
  o.directional_azimuths = 0;
  const TextureSet s = generate_texture_set(o);
  *depth = s.depth_texels;
  return s.height;
}

float U01(Pcg32& rng) { return rng.next_float(); }

bool same_bits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

struct Tally {
  uint64_t rays = 0, hits = 0, mismatches = 0;
  std::string first;
};

// One ray through both paths; any difference in hit, t or normal bits is a mismatch.
void compare(const HeightField& hf, const Vec3f& o, const Vec3f& d, float tmin, float tmax, Vec2f lo,
             Vec2f hi, Tally& tally, HeightFieldTraversal* trace = nullptr) {
  float ta = -1, tb = -1;
  Vec3f na(7, 7, 7), nb(7, 7, 7);
  const bool ha = hf.intersect(o, d, tmin, tmax, lo, hi, &ta, &na, trace);
  const bool hb = hf.intersect_dda(o, d, tmin, tmax, lo, hi, &tb, &nb);
  ++tally.rays, tally.hits += hb;
  const bool same =
      ha == hb &&
      (!ha || (same_bits(ta, tb) && same_bits(na.x, nb.x) && same_bits(na.y, nb.y) && same_bits(na.z, nb.z)));
  if (!same && tally.mismatches++ == 0)
    tally.first = "o = (" + std::to_string(o.x) + ", " + std::to_string(o.y) + ", " + std::to_string(o.z) +
                  "), d = (" + std::to_string(d.x) + ", " + std::to_string(d.y) + ", " + std::to_string(d.z) +
                  "), tmax = " + std::to_string(tmax) + ": fast " + std::to_string(ha) + " t " +
                  std::to_string(ta) + ", reference " + std::to_string(hb) + " t " + std::to_string(tb);
}

// A direction at elevation e (degrees above the grid plane; negative: downwards) and azimuth a, scaled by s
// (grid-space rays are not unit length: the renderer's are world directions over the texel size). Snapped
// exactly to an axis or a diagonal when asked.
Vec3f direction(float e, float a, float s, int snap) {
  const float er = e * kPiF / 180, ar = a * kPiF / 180;
  Vec3f d(std::cos(er) * std::cos(ar), std::cos(er) * std::sin(ar), std::sin(er));
  const float hxy = std::cos(er);
  if (snap == 1) d.x = 0, d.y = std::copysign(hxy, d.y);  // along y
  if (snap == 2) d.y = 0, d.x = std::copysign(hxy, d.x);  // along x
  if (snap == 3) d.x = std::copysign(hxy * 0.70710678f, d.x), d.y = std::copysign(std::abs(d.x), d.y);
  return d * s;
}

// The renderer's ray kinds over one height field; n rays of each kind.
void check_field(const HeightField& hf, int n, uint64_t seed, Tally& tally,
                 HeightFieldTraversal* trace = nullptr) {
  Pcg32 rng(seed);
  const float w = float(hf.width()), h = float(hf.height());
  auto U = [&](float a, float b) { return a + (b - a) * rng.next_float(); };
  auto snap = [&]() { return rng.next_float() < 0.25f ? int(rng.next_u32() % 4) : 0; };
  for (int k = 0; k < n; ++k) {
    // The plane's extent: 1 to 6 tiles, its corner up to 20 tiles away from the base tile.
    const float far = k % 4 == 0 ? 20.0f : 2.0f;
    const Vec2f lo(std::floor(U(-far, far)) * w - 0.5f, std::floor(U(-far, far)) * h - 0.5f);
    const Vec2f hi(lo.x + std::floor(U(1, 7)) * w, lo.y + std::floor(U(1, 7)) * h);
    const float s = std::pow(10.0f, U(-3, 3));
    // Orthographic camera ray from above, 0–89° off the normal.
    const Vec3f oc(U(lo.x - w, hi.x + w), U(lo.y - h, hi.y + h), hf.z_max() + U(0.01f, 300));
    const Vec3f dc = direction(-90 + U(0, 89), U(0, 360), s, snap());
    const float tmax_c = rng.next_float() < 0.2f ? U(0, 2) * (oc.z - hf.z_min()) / std::abs(dc.z) : kInfF;
    compare(hf, oc, dc, 0, tmax_c, lo, hi, tally, trace);
    // A surface point (the reference's hit of a camera ray inside the extent), then a shadow ray from it at
    // elevation 1–89° (or 1–8°, the long ones), any azimuth, to a directional light or a point light.
    const Vec3f o2(U(lo.x, hi.x), U(lo.y, hi.y), hf.z_max() + 1);
    const Vec3f d2 = direction(-90 + U(0, 60), U(0, 360), 1, 0);
    float t;
    Vec3f ng;
    if (!hf.intersect_dda(o2, d2, 0, kInfF, lo, hi, &t, &ng)) continue;
    const Vec3f p = o2 + d2 * t;
    const float e = k % 2 ? U(1, 8) : U(1, 89);
    const Vec3f ds = direction(e, U(0, 360), s, snap());
    const float tmax_s = rng.next_float() < 0.3f ? U(0, 1) * (hf.z_max() - hf.z_min()) / ds.z : kInfF;
    compare(hf, p, ds, 0, tmax_s, lo, hi, tally, trace);
    // Any direction from anywhere near the slab (below it, level rays inside it, upwards through it).
    const Vec3f og(U(lo.x - 4, hi.x + 4), U(lo.y - 4, hi.y + 4), U(hf.z_min() - 5, hf.z_max() + 5));
    const Vec3f dg = direction(rng.next_float() < 0.1f ? 0.0f : U(-90, 90), U(0, 360), s, snap());
    compare(hf, og, dg, rng.next_float() < 0.5f ? 0.0f : U(0, 10) / s, kInfF, lo, hi, tally, trace);
  }
}

void expect_identical(const char* name, const Tally& t, uint64_t min_rays) {
  EXPECT_EQ(t.mismatches, 0u) << name << ": first mismatch " << t.first;
  EXPECT_GE(t.rays, min_rays) << name;
  // Both outcomes occur (a test where every ray missed would compare nothing).
  EXPECT_GT(t.hits, t.rays / 10) << name;
  EXPECT_LT(t.hits, t.rays - t.rays / 10) << name;
  std::printf("%s: %llu rays, %llu hits, %llu mismatches\n", name, (unsigned long long)t.rays,
              (unsigned long long)t.hits, (unsigned long long)t.mismatches);
}

}  // namespace

TEST(HeightFieldMipmap, RepeatAddEqualsTheLoop) {
  using heightfield_detail::repeat_add;
  Pcg32 rng(11);
  int cases = 0, long_jumps = 0;
  for (int n = 0; n < 20000; ++n) {
    // Starting values from 0 and tiny up to 1e6, steps from far below an ulp of v to far above it, including
    // exact ties (b = (m + ½) ulp).
    float v = n % 50 == 0 ? 0.0f : std::ldexp(1.0f + rng.next_float(), int(rng.next_u32() % 60) - 30);
    float b = std::ldexp(1.0f + rng.next_float(), int(rng.next_u32() % 60) - 40);
    if (n % 7 == 0) {
      int e;
      std::frexp(v, &e);
      b = std::ldexp(float(rng.next_u32() % 64) + 0.5f, e - 24);  // a tie in v's binade
    }
    if (n % 97 == 0) v = -v;
    const uint32_t k = rng.next_u32() % (n % 10 == 0 ? 100000 : 3000);
    float loop = v;
    for (uint32_t s = 0; s < k; ++s) loop += b;
    const float fast = repeat_add(v, b, k);
    ASSERT_TRUE(same_bits(fast, loop))
        << "v " << v << " b " << b << " k " << k << ": " << fast << " vs " << loop;
    ++cases, long_jumps += k > 1000 && loop != v;
  }
  EXPECT_EQ(repeat_add(kInfF, 1.0f, 5), kInfF);
  EXPECT_EQ(repeat_add(2.0f, kInfF, 0), 2.0f);
  EXPECT_GT(long_jumps, 1000);
  EXPECT_EQ(cases, 20000);
}

// Leaving a block by computation equals leaving it step by step: the same steps, crossing times and exit
// time, bit for bit — including diagonal rays (equal steps, where the two axes' crossing times tie), rays
// along an axis, rays that end inside the block and crossing times far from the origin.
TEST(HeightFieldMipmap, LeaveBlockEqualsTheWalk) {
  using namespace heightfield_detail;
  Pcg32 rng(12);
  int ties = 0, ended = 0;
  for (int n = 0; n < 200000; ++n) {
    float dtx = std::ldexp(1.0f + rng.next_float(), int(rng.next_u32() % 24) - 12);
    float dty = n % 3 == 0 ? dtx : dtx * std::ldexp(1.0f + rng.next_float(), int(rng.next_u32() % 6) - 3);
    // The first crossings: up to 2^14 steps from the ray's origin, within a step of each other or tied.
    const float base = dtx * std::ldexp(rng.next_float(), int(rng.next_u32() % 15));
    float tx = base + dtx * rng.next_float();
    float ty = n % 3 == 0 && n % 2 == 0 ? tx : base + dty * rng.next_float();
    if (n % 17 == 0) ty = dty = kInfF;  // along x
    if (n % 19 == 0) std::swap(tx, ty), std::swap(dtx, dty);
    const uint32_t nx = 1 + rng.next_u32() % (n % 4 == 0 ? 4000 : 300), ny = 1 + rng.next_u32() % 300;
    const float t1 = n % 5 == 0 ? base + U01(rng) * 300 * std::min(dtx, dty) : kInfF;
    const BlockExit a = leave_block(tx, ty, dtx, dty, nx, ny, t1),
                    b = leave_block_walk(tx, ty, dtx, dty, nx, ny, t1);
    ASSERT_EQ(a.ended, b.ended) << n;
    ASSERT_TRUE(same_bits(a.tend, b.tend)) << n << ": " << a.tend << " vs " << b.tend;
    ASSERT_EQ(a.kx, b.kx) << n;
    ASSERT_EQ(a.ky, b.ky) << n;
    ASSERT_TRUE(same_bits(a.tx, b.tx) && same_bits(a.ty, b.ty)) << n;
    ended += a.ended;
    if (a.ended) continue;
    // A tie: the exit time equals a crossing time of the other axis (taken before an x exit, not yet taken
    // at a y exit).
    ties += a.kx == nx ? a.ky > 0 && repeat_add(ty, dty, a.ky - 1) == a.tend : a.tx == a.tend;
  }
  std::printf("%d blocks ended inside, %d exits tied with the other axis\n", ended, ties);
  EXPECT_GT(ended, 10000);
  EXPECT_GT(ties, 1000);
}

TEST(HeightFieldMipmap, PyramidHoldsBlockMaxima) {
  // 48 × 40 = 16 · 3 × 8 · 5: levels 0–3; level 0 wraps (the last column's cells reach column 0).
  const Texture t = rough_field(48, 40, 3);
  const HeightField hf(t, 9.0f);
  ASSERT_EQ(hf.levels(), 4);
  for (int l = 0; l < hf.levels(); ++l)
    for (int J = 0; J < 40 >> l; ++J)
      for (int I = 0; I < 48 >> l; ++I) {
        float m = -kInfF;
        for (int j = J << l; j <= ((J + 1) << l); ++j)
          for (int i = I << l; i <= ((I + 1) << l); ++i) m = std::max(m, hf.z(i, j));
        ASSERT_EQ(hf.node_max(l, I, J), m) << l << " " << I << " " << J;
        ASSERT_EQ(hf.node_max(l, I - 3 * (48 >> l), J + 2 * (40 >> l)), m);  // wraps
      }
  EXPECT_EQ(HeightField(rough_field(75, 49, 1), 4.0f).levels(), 1);
  EXPECT_EQ(HeightField(rough_field(64, 64, 1), 4.0f).levels(), 6);  // down to 2 × 2
  EXPECT_EQ(HeightField(rough_field(64, 16, 1), 4.0f).levels(), 5);  // down to 4 × 1
}

TEST(HeightFieldMipmap, RoughAndFlatFieldsMatchTheReference) {
  Tally rough, flat;
  HeightFieldTraversal tr;
  check_field(HeightField(rough_field(128, 128, 5), 12.0f), 12000, 21, rough, &tr);
  expect_identical("rough 128^2", rough, 30000);
  check_field(HeightField(field(64, 64, [](int, int) { return 1.0f; }), 5.0f), 8000, 22, flat);
  expect_identical("flat 64^2", flat, 20000);
  // The traversal passes over cells in blocks (the comparison would pass trivially if it walked every cell).
  std::printf("rough 128^2: %llu cells tested, %llu skipped in %llu blocks\n",
              (unsigned long long)tr.cells_tested, (unsigned long long)tr.cells_skipped,
              (unsigned long long)tr.blocks_skipped);
  EXPECT_GT(tr.cells_skipped, 2 * tr.blocks_skipped);
}

TEST(HeightFieldMipmap, StudyReliefMatchesTheReference) {
  for (const char* kind : {"rock", "cobble"}) {
    float depth = 0;
    const Texture h = generated(kind, 256, &depth);
    const HeightField hf(h, depth);
    Tally t;
    check_field(hf, 30000, 31, t);
    expect_identical(kind, t, 75000);
  }
}

TEST(HeightFieldMipmap, SteepAndNonPowerOfTwoFieldsMatchTheReference) {
  Pcg32 rng(9);
  Tally steep, npot, odd;
  // Independent random heights, 40 texels deep: walls of up to 40 texels between neighbouring vertices.
  check_field(HeightField(field(64, 64, [&](int, int) { return rng.next_float(); }), 40.0f), 15000, 41,
              steep);
  expect_identical("steep random 64^2", steep, 40000);
  check_field(HeightField(rough_field(96, 80, 7), 10.0f), 15000, 42, npot);  // levels 0–4
  expect_identical("96 x 80", npot, 40000);
  check_field(HeightField(rough_field(75, 49, 8), 10.0f), 10000, 43, odd);  // level 0 only
  expect_identical("75 x 49", odd, 25000);
}

// Rays the plain DDA walks furthest: shadow rays at 1–15° over a deep field spanning several tiles, from
// origins far from the base tile (the accumulated crossing times then carry the most rounding).
TEST(HeightFieldMipmap, LongGrazingRaysMatchTheReference) {
  float depth = 0;
  const Texture h = generated("rock", 256, &depth);
  const HeightField hf(h, 4 * depth);
  Pcg32 rng(51);
  Tally t;
  HeightFieldTraversal tr;
  auto U = [&](float a, float b) { return a + (b - a) * rng.next_float(); };
  for (int k = 0; k < 20000; ++k) {
    const Vec2f lo(-2000.5f + 256 * float(k % 16), 1000.5f), hi(lo.x + 2048, lo.y + 2048);
    const Vec3f o(U(lo.x, hi.x), U(lo.y, hi.y), hf.z_max() + 1);
    float th;
    Vec3f ng;
    if (!hf.intersect_dda(o, Vec3f(0, 0, -1), 0, kInfF, lo, hi, &th, &ng)) continue;
    const float s = std::pow(10.0f, U(-3, 3));
    const Vec3f d = direction(U(1, 15), U(0, 360), s, k % 5 == 0 ? 1 + k % 3 : 0);
    compare(hf, o + Vec3f(0, 0, -th), d, 0, kInfF, lo, hi, t, &tr);
  }
  expect_identical("grazing rock", t, 19000);
  std::printf("grazing rock: %llu cells tested, %llu skipped in %llu blocks\n",
              (unsigned long long)tr.cells_tested, (unsigned long long)tr.cells_skipped,
              (unsigned long long)tr.blocks_skipped);
  EXPECT_GT(tr.cells_skipped, 3 * tr.cells_tested);
  EXPECT_GT(tr.cells_skipped, 4 * tr.blocks_skipped);
}

// Blocks larger than 64 × 64 cells, whose exit is computed (repeat_add) rather than walked: a 1024² field
// with a low flat half (x < 512, and y < 256 in the other half) and rough mountains elsewhere, 40 texels
// deep; rays at every height over the flat parts, level, rising and falling slowly, along and across the
// axes, over an extent of up to 6 tiles up to 20 tiles from the base tile.
TEST(HeightFieldMipmap, LargeBlocksMatchTheReference) {
  const Texture rough = rough_field(1024, 1024, 61);
  const HeightField hf(
      field(1024, 1024, [&](int i, int j) { return i < 512 || j < 256 ? 0.1f : rough.at(i, j, 0); }), 40.0f);
  ASSERT_EQ(hf.levels(), 10);
  Pcg32 rng(62);
  Tally t;
  HeightFieldTraversal tr;
  auto U = [&](float a, float b) { return a + (b - a) * rng.next_float(); };
  for (int k = 0; k < 40000; ++k) {
    const float far = k % 3 == 0 ? 20.0f : 1.0f;
    const Vec2f lo(std::floor(U(-far, far)) * 1024 - 0.5f, std::floor(U(-far, far)) * 1024 - 0.5f);
    const Vec2f hi(lo.x + std::floor(U(1, 7)) * 1024, lo.y + std::floor(U(1, 7)) * 1024);
    const Vec3f o(U(lo.x, hi.x), U(lo.y, hi.y), U(hf.z_min() - 1, hf.z_max() + 1));
    const float s = std::pow(10.0f, U(-3, 3));
    const Vec3f d = direction(k % 5 == 0 ? 0.0f : U(-3, 3), U(0, 360), s, k % 4 == 0 ? 1 + k % 3 : 0);
    compare(hf, o, d, rng.next_float() < 0.5f ? 0.0f : U(0, 100) / s,
            rng.next_float() < 0.3f ? U(0, 3000) / s : kInfF, lo, hi, t, &tr);
  }
  expect_identical("large blocks", t, 40000);
  std::printf("large blocks: %llu cells tested, %llu skipped in %llu blocks (%llu jumped)\n",
              (unsigned long long)tr.cells_tested, (unsigned long long)tr.cells_skipped,
              (unsigned long long)tr.blocks_skipped, (unsigned long long)tr.blocks_jumped);
  EXPECT_GT(tr.blocks_jumped, 20000u);
}
