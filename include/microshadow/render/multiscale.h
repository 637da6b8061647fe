// Multiscale texture sets: the set an engine would use at 1/k resolution of a fine texture set, i.e. what a
// mip chain of the fine maps gives at level log2 k (box filter over k × k fine texels). The fine height
// field is the real surface (the ground truth renders it); the coarse set is what the approximations shade.
#pragma once

#include <microshadow/render/texture_gen.h>

#include <filesystem>
#include <vector>

namespace msh::render {

// Coarse roughness: Base = the box mean r̄ of the fine perceptual roughness; Widened = r̄ widened by the slope
// variance of the fine normals over the coarse texel (CLEAN moments, Baker 2011 / Olano & Baker 2010 "LEAN
// Mapping"; isotropic variance mapping with the Beckmann-equivalent GGX convention,
// filter/variance_mapping.h): with α = r̄² and b = −(n_x, n_y)/n_z, α'² = α² + var(b_x) + var(b_y), r' =
// sqrt(α') clamped to ≤ 1. Widened = Base where the fine normals are all equal.
enum class CoarseRoughness { Base, Widened };

// The texture set at 1/k resolution of `fine` (k ≥ 1; fine width and height divisible by k), every map the
// box mean over k × k fine texels:
//  - normal: the renormalised mean of the fine unit normals (the filtered normal), encoded n·0.5 + 0.5;
//  - visibility: the mean of the fine projected-solid-angle visibility (what a mip chain of the
//    micro-occlusion map gives; the coarse mean equals the fine mean up to float rounding of the sums);
//  - roughness: see CoarseRoughness; base colour (linear), metallic and height: box means;
//  - depth_texels = fine.depth_texels / k (the same physical depth in coarse texel units).
// k = 1 returns a copy of `fine` (for either mode). Throws InputError on k < 1, a size not divisible by k,
// or maps whose sizes differ. Deterministic, bit-identical whatever the thread count.
TextureSet downsample_texture_set(const TextureSet& fine, int k, CoarseRoughness mode);

// The mip chain of a texture set: level L = downsample_texture_set(fine, 2^L, Base), for every L while 2^L
// divides both sides (down to 1 × 1 for a power-of-two set). Level log2 k is exactly the study's coarse set
// at scale k.
std::vector<TextureSet> texture_set_mip_chain(const TextureSet& fine);

// Writes dir/mips/: for every map its whole chain as KTX2 and DDS (<map>.ktx2, <map>.dds; engine formats:
// normal RGBA8 (n·0.5 + 0.5), roughness, metallic, micro_occlusion R8, base colour RGBA16F linear, height
// R16F; directional as three files directional_{0,1,2} holding channels 0–3, 4–7 (RGBA8) and 8 (R8), or
// with the view correction's 21 channels five RGBA8 files directional_0..4 (channels 4f..4f+3) and
// directional_5 (channel 20, R8), as 8-bit UNORM between per-channel ranges [lo, hi] of the fine level), each
// level also as float32 NPY
// (<map>_mip<L>.npy, the exact values the study shades), and mips.json (levels, sizes, formats, the
// directional ranges). With directional_bc, the directional channels also block-compressed between the same
// ranges (io/bc4.h; 4 bits per channel): directional_bc_{f} holds channels 2f, 2f + 1 as BC5 and an odd last
// channel alone as BC4 (9 channels: 4 BC5 + 1 BC4 = 4.5 bytes per texel; 21: 10 BC5 + 1 BC4 = 10.5 bytes),
// KTX2 and DDS only (the NPY levels are the exact values). With a directional_form (an 8-bit
// render/directional_codec.h form, "pca<K>"), the compact form too: the code fitted to the fine channels,
// directional_compact_{t} (KTX2 and DDS, RGBA8 UNORM; coefficient 4t + c in channel c, unused channels 0;
// level L = the code of the channels' level L, quantised) and its level 0 as dir/directional_compact_{t}.png
// (RGBA8, linear data), described in mips.json's "directional_compact" (form, coefficients, channels,
// textures, lo, hi, mean, basis: channel_i = mean_i + Σ_k basis[i][k] (lo_k + (hi_k − lo_k) unorm_k)).
// Atomic files; InputError on an unwritable directory, a bad form or a form without directional channels.
void write_texture_set_mips(const std::filesystem::path& dir, const TextureSet& fine,
                            bool directional_bc = false, const std::string& directional_form = "");
// The same with a code already fitted to fine.directional (fit_directional_codec; 8-bit), or none.
struct DirectionalCodec;
void write_texture_set_mips(const std::filesystem::path& dir, const TextureSet& fine, bool directional_bc,
                            const DirectionalCodec* codec);

}  // namespace msh::render
