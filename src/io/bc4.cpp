// BC4 encoder and decoder (include/microshadow/io/bc4.h).
#include <microshadow/io/bc4.h>
#include <microshadow/io/error.h>

#include <algorithm>
#include <cmath>

namespace msh::io {

std::array<float, 8> bc4_palette(std::uint8_t red0, std::uint8_t red1) {
  const float a = red0, b = red1;
  std::array<float, 8> p{};
  p[0] = a / 255.0f, p[1] = b / 255.0f;
  if (red0 > red1) {
    for (int i = 1; i <= 6; ++i) p[std::size_t(i) + 1] = (float(7 - i) * a + float(i) * b) / (7.0f * 255.0f);
  } else {
    for (int i = 1; i <= 4; ++i) p[std::size_t(i) + 1] = (float(5 - i) * a + float(i) * b) / (5.0f * 255.0f);
    p[6] = 0.0f, p[7] = 1.0f;
  }
  return p;
}

void bc4_decode_block(const Bc4Block& block, float texels[16]) {
  const std::array<float, 8> p = bc4_palette(block[0], block[1]);
  std::uint64_t bits = 0;
  for (int i = 0; i < 6; ++i) bits |= std::uint64_t(block[std::size_t(i) + 2]) << (8 * i);
  for (int t = 0; t < 16; ++t) texels[t] = p[(bits >> (3 * t)) & 7u];
}

namespace {

// Nearest palette index of each texel and the block's squared error.
double assign(const std::array<float, 8>& p, const float v[16], std::uint8_t idx[16]) {
  double sse = 0;
  for (int t = 0; t < 16; ++t) {
    int best = 0;
    float bd = std::abs(v[t] - p[0]);
    for (int i = 1; i < 8; ++i)
      if (const float d = std::abs(v[t] - p[std::size_t(i)]); d < bd) bd = d, best = i;
    idx[t] = std::uint8_t(best);
    sse += double(bd) * bd;
  }
  return sse;
}

Bc4Block pack(int red0, int red1, const std::uint8_t idx[16]) {
  Bc4Block b{};
  b[0] = std::uint8_t(red0), b[1] = std::uint8_t(red1);
  std::uint64_t bits = 0;
  for (int t = 0; t < 16; ++t) bits |= std::uint64_t(idx[t]) << (3 * t);
  for (int i = 0; i < 6; ++i) b[std::size_t(i) + 2] = std::uint8_t(bits >> (8 * i));
  return b;
}

}  // namespace

Bc4Block bc4_encode_block(const float texels[16]) {
  float v[16];
  float lo = 1, hi = 0;
  for (int t = 0; t < 16; ++t) {
    v[t] = std::isnan(texels[t]) ? 0.0f : std::clamp(texels[t], 0.0f, 1.0f);
    lo = std::min(lo, v[t]), hi = std::max(hi, v[t]);
  }
  const int rhi = int(std::lround(255.0f * hi)), rlo = int(std::lround(255.0f * lo));
  std::uint8_t idx[16] = {}, trial[16];
  if (rhi == rlo) return pack(rhi, rlo, idx);  // constant after rounding: every index 0
  double best = -1;
  int b0 = rhi, b1 = rlo;
  for (int d0 = -1; d0 <= 1; ++d0)
    for (int d1 = -1; d1 <= 1; ++d1) {
      const int r0 = std::clamp(rhi + d0, 0, 255), r1 = std::clamp(rlo + d1, 0, 255);
      if (r0 <= r1) continue;
      const double e = assign(bc4_palette(std::uint8_t(r0), std::uint8_t(r1)), v, trial);
      // The min/max pair (d0 = d1 = 0) is visited in this order too; strict < keeps the first best.
      if (best < 0 || e < best) best = e, b0 = r0, b1 = r1, std::copy(trial, trial + 16, idx);
    }
  return pack(b0, b1, idx);
}

std::vector<Bc4Block> bc4_encode(const float* data, int width, int height, std::size_t stride) {
  if (width < 1 || height < 1) throw InputError("bc4_encode: empty image");
  const int bw = (width + 3) / 4, bh = (height + 3) / 4;
  std::vector<Bc4Block> out(std::size_t(bw) * std::size_t(bh));
  float t[16];
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
          const int x = std::min(4 * bx + i, width - 1), y = std::min(4 * by + j, height - 1);
          t[4 * j + i] = data[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * stride];
        }
      out[std::size_t(by) * std::size_t(bw) + std::size_t(bx)] = bc4_encode_block(t);
    }
  return out;
}

void bc4_decode(const std::vector<Bc4Block>& blocks, int width, int height, float* out, std::size_t stride) {
  const int bw = (width + 3) / 4, bh = (height + 3) / 4;
  if (width < 1 || height < 1 || blocks.size() != std::size_t(bw) * std::size_t(bh))
    throw InputError("bc4_decode: block count does not match the image size");
  float t[16];
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      bc4_decode_block(blocks[std::size_t(by) * std::size_t(bw) + std::size_t(bx)], t);
      for (int j = 0; j < 4 && 4 * by + j < height; ++j)
        for (int i = 0; i < 4 && 4 * bx + i < width; ++i)
          out[(std::size_t(4 * by + j) * std::size_t(width) + std::size_t(4 * bx + i)) * stride] =
              t[4 * j + i];
    }
}

}  // namespace msh::io
