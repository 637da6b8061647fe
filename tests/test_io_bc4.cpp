// BC4 codec (io/bc4.h) against the format's specification (Microsoft, "Block Compression (Direct3D 10)"):
// the decoder on hand-made blocks whose bytes are written out here, the encoder against an independent
// min/max encoder written in this file (never worse in squared error; that one within its error bound) and
// exact on blocks made of palette points; whole images with partial blocks and a stride.
#include <gtest/gtest.h>
#include <microshadow/io/bc4.h>
#include <microshadow/io/error.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

using namespace msh;

namespace {

// The specification's palette, in double: 8 points for red0 > red1, else 6 and the constants 0 and 1.
std::vector<double> spec_palette(int r0, int r1) {
  std::vector<double> p = {r0 / 255.0, r1 / 255.0};
  if (r0 > r1)
    for (int i = 1; i <= 6; ++i) p.push_back(((7 - i) * r0 + i * r1) / (7.0 * 255.0));
  else {
    for (int i = 1; i <= 4; ++i) p.push_back(((5 - i) * r0 + i * r1) / (5.0 * 255.0));
    p.push_back(0.0), p.push_back(1.0);
  }
  return p;
}

// The plain min/max encoder: endpoints round(255 max), round(255 min), nearest point. Its squared error.
double minmax_sse(const float v[16]) {
  float lo = 1, hi = 0;
  for (int t = 0; t < 16; ++t) lo = std::min(lo, v[t]), hi = std::max(hi, v[t]);
  const auto p = spec_palette(int(std::lround(255.0 * hi)), int(std::lround(255.0 * lo)));
  double sse = 0;
  for (int t = 0; t < 16; ++t) {
    double d = 1e9;
    for (double q : p) d = std::min(d, std::abs(v[t] - q));
    sse += d * d;
  }
  return sse;
}

}  // namespace

TEST(Bc4, DecodesTheSpecificationsLayout) {
  // Texel t has index t mod 8: the 3-bit fields 0, 1, …, 7 packed little-endian give 0x88 0xC6 0xFA, twice.
  const io::Bc4Block b = {200, 100, 0x88, 0xC6, 0xFA, 0x88, 0xC6, 0xFA};
  float t[16];
  io::bc4_decode_block(b, t);
  const auto p = spec_palette(200, 100);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(t[i], p[std::size_t(i % 8)], 1e-7) << i;
  EXPECT_NEAR(t[2], 1300.0 / 1785.0, 1e-7);  // (6 · 200 + 100) / 7 / 255
  // red0 ≤ red1: six points, then exactly 0 and 1.
  const io::Bc4Block c = {0, 255, 0x88, 0xC6, 0xFA, 0x88, 0xC6, 0xFA};
  io::bc4_decode_block(c, t);
  const float want[8] = {0.0f, 1.0f, 0.2f, 0.4f, 0.6f, 0.8f, 0.0f, 1.0f};
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(t[i], want[i % 8], 1e-7) << i;
  // All indices 7.
  const io::Bc4Block d = {10, 3, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
  io::bc4_decode_block(d, t);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(t[i], (10.0 + 6 * 3.0) / (7 * 255.0), 1e-7);
}

TEST(Bc4, EncoderIsExactOnPalettePoints) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const int r1 = int(rng() % 255), r0 = r1 + 1 + int(rng() % unsigned(255 - r1));
    const auto p = spec_palette(r0, r1);
    float v[16], out[16];
    for (int t = 0; t < 16; ++t) v[t] = float(p[rng() % 8]);
    const unsigned a = rng() % 16, b = (a + 1 + rng() % 15) % 16;  // both endpoints present, a ≠ b
    v[a] = float(p[0]), v[b] = float(p[1]);
    io::bc4_decode_block(io::bc4_encode_block(v), out);
    for (int t = 0; t < 16; ++t) ASSERT_NEAR(out[t], v[t], 1e-6) << trial << " " << t;
  }
  float c[16], out[16];
  std::fill(c, c + 16, 77.0f / 255.0f);
  io::bc4_decode_block(io::bc4_encode_block(c), out);
  for (float x : out) EXPECT_FLOAT_EQ(x, 77.0f / 255.0f);
}

TEST(Bc4, EncoderNeverWorseThanMinMaxAndWithinItsBound) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0, 1);
  double worst_ratio = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    float v[16], out[16];
    const int kind = trial % 4;
    const float base = u(rng), span = kind == 0 ? 1.0f : kind == 1 ? 0.05f : kind == 2 ? 0.004f : 0.3f;
    const float gx = u(rng) - 0.5f, gy = u(rng) - 0.5f;
    for (int t = 0; t < 16; ++t) {
      const float x = kind == 3 ? base + span * (gx * float(t % 4) + gy * float(t / 4)) / 3  // smooth ramp
                                : base + span * (u(rng) - 0.5f);
      v[t] = std::clamp(x, 0.0f, 1.0f);
    }
    float lo = 1, hi = 0;
    for (float x : v) lo = std::min(lo, x), hi = std::max(hi, x);
    io::bc4_decode_block(io::bc4_encode_block(v), out);
    double sse = 0, emax = 0;
    for (int t = 0; t < 16; ++t)
      sse += double(out[t] - v[t]) * (out[t] - v[t]), emax = std::max(emax, double(std::abs(out[t] - v[t])));
    const double ref = minmax_sse(v);
    // The library's palette is float, this file's double: each texel's error may differ by δ = 1e-7.
    const double delta = 1e-7;
    ASSERT_LE(sse, ref + 2 * delta * std::sqrt(16 * ref) + 16 * delta * delta) << trial;
    // The min/max encoder's per-texel bound, so the chosen pair's squared error is within 16 of its square.
    const double bound = std::max(0.5, (255.0 * (hi - lo) + 1.0) / 14.0) / 255.0;
    ASSERT_LE(ref, 16 * bound * bound + 1e-12) << trial;
    ASSERT_LE(emax, 4 * bound + 1e-7) << trial;
    worst_ratio = std::max(worst_ratio, emax / bound);
  }
  RecordProperty("worst_max_error_over_bound", std::to_string(worst_ratio));
}

TEST(Bc4, ClampsAndReadsNanAsZero) {
  float v[16], out[16];
  for (int t = 0; t < 16; ++t) v[t] = t % 2 ? 2.0f : -1.0f;
  v[3] = std::numeric_limits<float>::quiet_NaN();
  io::bc4_decode_block(io::bc4_encode_block(v), out);
  for (int t = 0; t < 16; ++t) EXPECT_FLOAT_EQ(out[t], t % 2 && t != 3 ? 1.0f : 0.0f) << t;
}

TEST(Bc4, ImagesWithPartialBlocksAndAStride) {
  const int w = 7, h = 5, stride = 3;
  std::vector<float> img(std::size_t(w * h * stride));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < stride; ++c)
        img[std::size_t((y * w + x) * stride + c)] = 0.1f * float(c) + 0.01f * float(x + 2 * y);
  const auto blocks = io::bc4_encode(img.data() + 1, w, h, stride);
  ASSERT_EQ(blocks.size(), 4u);  // 2 × 2 blocks
  std::vector<float> out = img;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out[std::size_t((y * w + x) * stride + 1)] = -1;
  io::bc4_decode(blocks, w, h, out.data() + 1, stride);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < stride; ++c) {
        const std::size_t i = std::size_t((y * w + x) * stride + c);
        if (c != 1)
          EXPECT_EQ(out[i], img[i]);  // other channels untouched
        else                          // each block spans ≤ 0.09: error ≤ (255 · 0.09 + 1) / 14 / 255
          EXPECT_NEAR(out[i], img[i], (255 * 0.09 + 1) / 14 / 255) << x << "," << y;
      }
  EXPECT_THROW(io::bc4_encode(img.data(), 0, 4, 1), InputError);
  EXPECT_THROW(io::bc4_decode(blocks, 9, 5, out.data(), 1), InputError);
}
