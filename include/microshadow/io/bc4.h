// BC4 block compression (DXGI_FORMAT_BC4_UNORM, VK_FORMAT_BC4_UNORM_BLOCK, RGTC1 / ATI1): one channel,
// 4 × 4 texels in 8 bytes (4 bits per texel). Microsoft, "Block Compression (Direct3D 10)", BC4 section;
// Khronos Data Format Specification 1.3, §"RGTC". Pure computation (no files, no threads): the study and the
// texture writers use it to store and to measure the directional channels as an engine samples them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace msh::io {

// Byte 0 = red_0, byte 1 = red_1, bytes 2–7 = sixteen 3-bit palette indices, texel t = x + 4 y at bits
// 3t … 3t + 2 of the little-endian 48-bit integer. Palette (values / 255): red_0 > red_1: red_0, red_1 and
// the six interior points ((7 − i) red_0 + i red_1) / 7, i = 1 … 6 (indices 2 … 7); otherwise red_0, red_1,
// the four points ((5 − i) red_0 + i red_1) / 5 (indices 2 … 5), then 0 and 1 (indices 6, 7).
using Bc4Block = std::array<std::uint8_t, 8>;

// The block's 8 palette values in [0, 1] (the UNORM decode, exact in float; hardware may differ by ≤ 1/510
// on the interior points, which the D3D specification allows).
std::array<float, 8> bc4_palette(std::uint8_t red0, std::uint8_t red1);
// Decodes one block into texels[16] (row-major 4 × 4).
void bc4_decode_block(const Bc4Block& block, float texels[16]);
// Encodes 16 texels (row-major 4 × 4; clamped to [0, 1], NaN read as 0). The 8-point mode only: among the
// endpoints round(255 max) + {−1, 0, 1} and round(255 min) + {−1, 0, 1} (red_0 > red_1), the pair with the
// least squared error, each texel at its nearest palette point (ties: the first pair, the lowest index).
// A constant block is stored exactly (red_0 = red_1). Squared error: never above the min/max pair's, whose
// error per texel is ≤ b = max(0.5, (255 (max − min) + 1) / 14) / 255; the chosen pair's per texel is ≤ 4 b
// (measured ≤ 1.68 b on tests/test_io_bc4.cpp's 20,000 blocks). Deterministic.
Bc4Block bc4_encode_block(const float texels[16]);

// One channel of a width × height image (value of texel (x, y) at data[(y · width + x) · stride]) as
// ceil(width/4) × ceil(height/4) blocks, row-major; a partial block repeats its last row and column.
// InputError on an empty image (bc4_decode: also on a block count that does not match).
std::vector<Bc4Block> bc4_encode(const float* data, int width, int height, std::size_t stride);
// The inverse: writes every texel of the image (the repeated texels of partial blocks are dropped).
void bc4_decode(const std::vector<Bc4Block>& blocks, int width, int height, float* out, std::size_t stride);

}  // namespace msh::io
