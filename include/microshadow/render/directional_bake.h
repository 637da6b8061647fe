// Directional micro-occlusion: the bake of the channels (occlusion/directional.h), their mip chain and
// storage, and the exact texture-space diffuse transport of a height field. The measurement that compares the
// representations with it is research, apart from the product: tools/research/directional_study.h.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/render/scene.h>
#include <microshadow/render/texture_gen.h>

#include <string>
#include <vector>

namespace msh::render {

// The fit's azimuths for a given count: up to kMaxLatticeAzimuths, lattice steps (texture_gen.h
// lattice_azimuths) within kLatticeAzimuthErrorDeg of the uniform φ_a = 2π(a + ½)/azimuths, each weighted by
// its share of the circle (half the arcs to its neighbours, relative to 2π/azimuths); above, the uniform
// azimuths themselves, weight 1, steps empty. InputError outside [kMinDirectionalAzimuths,
// kMaxDirectionalAzimuths].
constexpr int kMaxLatticeAzimuths = 64;
// The fewest azimuths the fits take: their functions carry azimuthal harmonics of orders 0, 1 and 2 (x² − y²
// and x y are cos 2φ and sin 2φ), five unknowns in φ, which 4 azimuths cannot separate (at 45°, 135°, …
// x² − y² is 0 on every direction: a singular fit, NaN channels).
constexpr int kMinDirectionalAzimuths = 5;
constexpr int kMaxDirectionalAzimuths = 4096;
constexpr double kLatticeAzimuthErrorDeg = 0.5;
struct DirectionalBakeAzimuths {
  std::vector<LatticeStep> steps;  // empty above kMaxLatticeAzimuths
  std::vector<Vec2f> dirs;         // unit, ascending azimuth
  std::vector<double> weights;
};
DirectionalBakeAzimuths directional_bake_azimuths(int azimuths);
// InputError "<what>: azimuths must be in [kMinDirectionalAzimuths, kMaxDirectionalAzimuths] …" outside
// that range: the check of every directional bake (and of gen-material's option).
void check_directional_azimuths(const char* what, int azimuths);

// The 9 directional channels (occlusion/directional.h: the weighted least-squares fit of degree ≤ 2 of
// lit · (n · l)⁺ over the hemisphere, channel order 1, x, y, z, xz, yz, x² − y², xy, z²) of a height map
// (values in [0, 1], depth_texels as in HeightField), per texel: the transport is exact on the fit's
// direction grid (the azimuths of directional_bake_azimuths × directional::kFitElevations elevations), n =
// the central-difference normal of normal_map_from_height. Horizons: with unlimited rays (max_distance ≤ 0,
// the measured choice) on lattice azimuths, exact by bake_horizon_tangents_lattice (one sweep per line, cost
// independent of the depth); otherwise the walks of bake_horizon_tangents classified against the fit
// directions' elevations (lit is exact) with ray length max_distance texels. Float32, unencoded (8-bit: see
// directional::decode_unorm8). Deterministic whatever the thread count. InputError on azimuths outside
// [kMinDirectionalAzimuths, kMaxDirectionalAzimuths] (and as bake_horizon_tangents).
Texture bake_directional_channels(const Texture& height, float depth_texels, int azimuths,
                                  float max_distance);

// The view correction's 12 channels (docs/directional-occlusion.md, "The view–light correlation floor"):
// the same weighted least squares, grid, horizons and normals with the first directional::kSlopeTerms = 6
// functions (1, x, y, z, xz, yz) applied to f · n_x/n_z (channels 0–5) and f · n_y/n_z (channels 6–11),
// f = lit · (n · l)⁺. Linear, so box means are the coarse
// texel's own fit. directional::directional_view_transport reads them. Errors as bake_directional_channels.
Texture bake_directional_slope_channels(const Texture& height, float depth_texels, int azimuths,
                                        float max_distance);

// Both in one pass (one set of horizons): directional::kViewChannels = 21 channels, the 9 of
// bake_directional_channels then the 12 of bake_directional_slope_channels, each equal to its own bake.
// What the `directional-view` method reads (directional::directional_view_term). Errors as above.
Texture bake_directional_view_channels(const Texture& height, float depth_texels, int azimuths,
                                       float max_distance);

// The 10 horizon-moment channels (directional.h, "hm" alternatives) with the same azimuths, horizons and
// normals; facet slopes where nothing rises above the tangent plane.
Texture bake_horizon_moment_channels(const Texture& height, float depth_texels, int azimuths,
                                     float max_distance);

// Box mean over k × k texels (every channel, summed in double, times 1/k²; width and height divisible by k):
// mip level log2 k of a box-filtered chain, and every map of downsample_texture_set. InputError otherwise.
Texture box_downsample(const Texture& t, int k);

// Mip chain by repeated 2 × 2 box means: level 0 = t, down to 1 texel on the shorter side (each side halved
// while even). Equal to box_downsample(t, 2^level) up to float rounding.
std::vector<Texture> box_mip_chain(const Texture& t);

// Per-channel [lo, hi] of a texture (the 8-bit UNORM storage of the directional channels, decoded by
// directional::decode_unorm8; hi = lo + 1 for a constant channel). Every mip level uses the fine level's.
struct ChannelRanges {
  std::vector<float> lo, hi;
};
ChannelRanges channel_ranges(const Texture& t);

// How the channels are stored for the run time, each channel between the fine level's range (channel_ranges):
// Float (exact), Unorm8 (8-bit UNORM, 1 byte per channel, what gen-material's mips hold) or Bc4 (BC4 blocks,
// io/bc4.h: 4 bits per channel, 4 × 4 texels per block). directional_encoding_from_name: "float", "unorm8",
// "bc4"; InputError otherwise.
enum class DirectionalEncoding { Float, Unorm8, Bc4 };
DirectionalEncoding directional_encoding_from_name(const std::string& name);
std::string directional_encoding_name(DirectionalEncoding e);
// Replaces every channel of t by what an engine reads back from that storage (decoded to float before any
// filtering, as texture units do): values outside [lo, hi] are clamped. Float leaves t as it is.
void store_directional_channels(Texture& t, const ChannelRanges& ranges, DirectionalEncoding e);

// The exact diffuse transport per fine texel (vertex) of a directional light l (grid/tangent space, unit,
// l.z > 0): lit(x, l) · (n(x) · l)⁺, lit = the ray toward l leaves the surface (tan e > tan H along the
// light's azimuth, exact horizon: bake_horizon_tangents classified against tan e, ray length max_distance,
// ≤ 0 = unlimited), n = the central-difference normal. One channel. The coarse transport at scale k is
// box_downsample(result, k).
Texture exact_diffuse_transport(const Texture& height, float depth_texels, Vec3f l, float max_distance);

}  // namespace msh::render
