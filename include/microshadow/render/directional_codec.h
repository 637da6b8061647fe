// Compact forms of the directional channels (docs/directional-occlusion.md, "Compact forms"): a per-material
// linear code. K coefficients per texel, a = E (c − mean), stored as K UNORM values (4 per RGBA texture),
// decoded by c = mean + B a and then evaluated as the float channels are. Every step before the quantisation
// is linear, so the box mean of the coefficients (a mip level) decodes to the box mean of the channels: the
// mips stay exact up to the quantisation of each level.
//
// The code is a principal-component basis in the transport metric: the channels enter the run time only
// through T(l, v) = φ(l, v) · c (occlusion/directional.h: the 9 transport channels on b(l), the 12 slope
// channels on the first 6 of b(l) times v_x/v_z and v_y/v_z), so the error that matters for a texel is
// (c − ĉ)ᵀ M (c − ĉ) with M = Σ w φ φᵀ over lights and views, each weighted by 1/T̄² (T̄: the material's mean
// transport for that light and view) so that every light counts by its relative error, as the study's bias
// does. The K-dimensional subspace that minimises the texels' mean error in that norm is spanned by the
// leading eigenvectors of Lᵀ Σ L (M = L Lᵀ, Σ the channels' covariance) mapped back by L⁻ᵀ (a weighted PCA,
// Jolliffe 2002 "Principal Component Analysis" §14.2.1, generalised PCA with a metric).
#pragma once

#include <microshadow/render/scene.h>

#include <string>
#include <vector>

namespace msh::render {

struct DirectionalCodec {
  std::string form;               // "pca<K>" (8-bit), "pca<K>x16" (16-bit), "pca<K>f" (float coefficients)
  int channels = 0;               // C: what it decodes to (9 for directional, 21 for directional-view)
  int coefficients = 0;           // K ≤ C
  int bits = 8;                   // UNORM bits per coefficient: 8 or 16; 0 = float (the projection alone)
  std::vector<float> mean;        // C: the fine channels' mean
  std::vector<float> basis;       // C × K row-major: c_i = mean_i + Σ_k basis[i K + k] a_k
  std::vector<float> encode;      // K × C row-major: a_k = Σ_i encode[k C + i] (c_i − mean_i)
  std::vector<float> lo, hi;      // K: a_k = lo_k + (hi_k − lo_k) u_k, the fine coefficients' range
  std::vector<double> explained;  // K: the share of the metric-weighted variance each component carries
  // The code with each coefficient's affine decode folded in (directional::decode_folded_code, what the
  // shaders take): channel_i = folded_mean_i + Σ_k folded_basis[i K + k] u_k, u_k the stored UNORM value.
  std::vector<float> folded_mean() const;
  std::vector<float> folded_basis() const;
  // basis and folded_basis as C rows of K (mips.json and the glTF extension store them so).
  std::vector<std::vector<float>> basis_rows() const;
  std::vector<std::vector<float>> folded_basis_rows() const;
  // Bytes per texel as stored (K · bits / 8; float: 4 K) and texture fetches (RGBA: ⌈K / 4⌉).
  double bytes_per_texel() const { return coefficients * (bits == 0 ? 4.0 : bits / 8.0); }
  int fetches() const { return (coefficients + 3) / 4; }
};

// Parses a form name, "pca<K>", "pca<K>x16" or "pca<K>f" with 1 ≤ K ≤ channels; InputError otherwise.
// Sets form, channels, coefficients, bits.
DirectionalCodec parse_directional_form(const std::string& form, int channels);

// The metric M (C × C, row-major, symmetric positive definite) of the channels' transport, for C = 9
// (directional: T = c · b(l)) or 21 (directional-view): lights at elevations 5°, 10°, …, 75° × 24 azimuths,
// views (21 channels) along the normal and 30° and 60° off it × 8 azimuths, each (l, v) weighted by
// 1 / max(φ(l, v) · mean, 0.01)². InputError for another C.
std::vector<double> directional_transport_metric(const std::vector<float>& mean);

// Fits the form's code to the fine channels (9 or 21 channels, every value finite): mean, the weighted PCA
// basis, and each coefficient's range over the fine texels. Deterministic whatever the thread count.
// InputError on a bad form or channel count.
DirectionalCodec fit_directional_codec(const Texture& fine, const std::string& form);

// The K float coefficients of each texel, unquantised: a = E (c − mean).
Texture encode_directional(const Texture& channels, const DirectionalCodec& codec);
// The channels from K coefficients: c = mean + B a.
Texture decode_directional(const Texture& coefficients, const DirectionalCodec& codec);
// Rounds every coefficient to its UNORM grid (codec.bits; clamped to [lo, hi]); float: unchanged.
void quantize_coefficients(Texture& coefficients, const DirectionalCodec& codec);
// What an engine reads back from a level of the stored form: encode, quantise, decode (C channels). The
// study measures a form at scale k as store_through_codec(box_downsample(fine, k)): the stored mip level.
Texture store_through_codec(const Texture& channels, const DirectionalCodec& codec);

}  // namespace msh::render
