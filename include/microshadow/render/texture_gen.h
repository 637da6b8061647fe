// Procedural texture sets like the test cases of Zurita 2026 ("Improving Direct Lighting Material
// Occlusion - Part 2"): a height field (damaged plaster: noise, cracks, pits; bark: furrowed ridges; gravel:
// packed stones on sand; and three with steep relief: rock: fractured blocks, cracks, ridged multifractal;
// brick: running-bond paving, rounded bricks, deep mortar joints; cobble: rounded cobblestones in sand)
// turned into a normal map, a roughness map (left half rough, right half smooth, as in that test), a base
// colour, and a micro-occlusion map baked the way artists bake it. A user's own height map goes through the
// same normal map and bake (texture_set_from_height).
#pragma once

#include <microshadow/io/texture.h>
#include <microshadow/render/scene.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace msh::render {

struct TextureSet {
  Texture height, normal, roughness, metallic, base_color, visibility;
  // Directional micro-occlusion (occlusion/directional.h, render/directional_bake.h): 9 linear channels per
  // texel, or 21 with the view correction (GenOptions::directional_view: the 9, then the 12 slope
  // channels); empty when not baked (GenOptions::directional_azimuths = 0).
  Texture directional;
  float depth_texels = 0;  // depth of the full height range in texel units (normal map and bake use it)
  // The fine normals' slope covariance E[n_h n_hᵀ]/E[n_z²] (Σ_xx, Σ_xy, Σ_yy; slope_covariance()): what the
  // `directional-view-masked` method reads, one constant per material, kept at every scale.
  std::array<float, 3> slope_covariance{};
};

// Σ = E[n_h n_hᵀ]/E[n_z²] over a tangent-space normal map (encoded n·0.5 + 0.5, 3 channels): the slope
// covariance of directional::directional_view_masked_transport. InputError on an empty or non-3-channel
// map or non-finite texels.
std::array<float, 3> slope_covariance(const Texture& normal);

struct GenOptions {
  std::string kind = "plaster";  // plaster | bark | gravel | rock | brick | cobble (material_kinds())
  int size = 256;                // texels per side (power of two not required)
  // 0 = the kind's default: plaster 6, bark 12, gravel 8, rock 16, brick 8, cobble 9 texels at size 256,
  // scaled by size / 256 (rock, brick, cobble: mean baked V 0.87, 0.82, 0.81 at 512²).
  float depth_texels = 0;
  int ao_rays = 32;           // azimuths per texel for the micro-occlusion bake (each exact in elevation)
  float ao_max_distance = 0;  // bake ray length, texels; 0 = the kind's default (8% of the size)
  float rough_left = 0.8f, rough_right = 0.3f;
  // Directional micro-occlusion bake (bake_directional_channels, unlimited ray length): azimuths per texel;
  // 0 = not baked.
  int directional_azimuths = 32;
  // Bake the view correction's 12 slope channels too (bake_directional_view_channels: 21 channels), what
  // the `directional-view` method reads.
  bool directional_view = false;
  uint32_t seed = 7;
};

std::vector<std::string> material_kinds();  // the procedural kinds, for messages and the CLI

// Deterministic (pure function of the options; bit-identical whatever the thread count). InputError on an
// unknown kind, size outside [8, 8192], ao_rays outside [1, 65536], negative or non-finite depth/distance.
TextureSet generate_texture_set(const GenOptions& opt);

// The renderer's material of a texture set, as the study renders it. ground_truth: the height field displaced
// and ray traced (height, its depth, base colour, roughness, metallic; visibility 1); otherwise the smooth
// surface the approximations shade (normal map, baked visibility, directional channels, slope covariance,
// base colour, roughness, metallic; no height).
Material material_from_texture_set(const std::string& name, const TextureSet& s, bool ground_truth);

// A user's height map: a 16-bit PNG or an EXR, grey (one channel, grey + alpha, or RGB(A) with R = G = B),
// values in [0, 1], each side in [8, 16384]. InputError with one line naming the file otherwise (missing,
// other format, 8-bit or palette PNG, colour, out-of-range or non-finite heights).
Texture load_height_map(const std::filesystem::path& path);

// The texture set of a given height map (one channel in [0, 1]; depth_texels ∈ (0, 1e4] = depth of the
// full [0, 1] range in texels): the same normal map and micro-occlusion bake as the procedural kinds
// (opt.ao_rays, opt.ao_max_distance; default distance 8 % of the larger side), roughness split as
// opt.rough_left / opt.rough_right, base colour 0.5 grey, metallic 0. opt.kind, size, depth, seed unused.
TextureSet texture_set_from_height(const Texture& height, float depth_texels, const GenOptions& opt);

// Tangent-space normal map of a height map by central differences (wrap), encoded n·0.5 + 0.5;
// x = +u (columns), y = +v (rows, top to bottom). depth_texels as in HeightField.
Texture normal_map_from_height(const Texture& height, float depth_texels);

// Micro-occlusion as artists bake it: for each texel (vertex (i, j) of the HeightField surface), the
// projected-solid-angle visibility about the flat normal +z, V = (1/π) ∫ vis(ω) cos θ dω, where a direction
// is visible if its ray of length max_distance texels leaves the surface without a hit (rays longer than that
// count as unoccluded; max_distance ≤ 0 or +inf = unlimited). Computed by exact horizons (elevation integral
// in closed form, see src/render/visibility_bake.cpp): `azimuths` stratified azimuths per texel, rotated by
// one of M = max(1, 256 / azimuths) offsets picked by a hash per run of 8 texels in a row (the box means
// see M · azimuths directions), each resolving every elevation, so the only error is the azimuthal quadrature
// (O(N⁻²) where the horizon varies smoothly). A direction that enters the solid at the start point is
// blocked, one that leaves it is not: no darkening of convex points, no leak at concave ones. Domain:
// azimuths ∈ [1, 65536], depth finite ≥ 0; otherwise InputError. Deterministic, bit-identical whatever the
// thread count. Finite ray lengths (up to about the map's size) are exact: bake_horizon_tangents_profiles.
// Unlimited rays (and longer ones) take the walks of bake_horizon_tangents, which skip parts of the field
// that could change a texel's V by at most 1e-4 (V is never lowered by that); this also ends unlimited rays.
Texture bake_visibility(const Texture& height, float depth_texels, int azimuths, float max_distance);

// The exact-horizon walks of bake_visibility, kept: tan H ≥ 0 of the horizon at every vertex (i, j) along
// each horizontal direction dirs[k] = (cos φ, sin φ) (grid axes: x = +i columns, y = +j rows), same surface,
// start-point rule, ray length (max_distance ≤ 0 or +inf = unlimited) and 1e-4 tolerance on tan² H (a
// horizon is never over-estimated by it). Layout: [(j · width + i) · dirs.size() + k]. Light along dirs[k]
// at elevation e reaches the vertex iff tan e > tan H. Deterministic whatever the thread count.
std::vector<float> bake_horizon_tangents(const Texture& height, float depth_texels,
                                         const std::vector<Vec2f>& dirs, float max_distance);
// The same horizons for a finite ray length by ray profiles: the breakpoints (cell edges and diagonals) a
// walk from a vertex meets along dirs[k] are at the same distances and offsets from every vertex, so they are
// listed once per direction and each vertex scans its heights there (src/render/visibility_bake.cpp). Exact:
// no tolerance (tan H ≥ the walks' by at most their 1e-4 on tan² H, up to float rounding). Same layout.
// InputError for max_distance ≤ 0 or above what the padding allows (about the map's size: 4× the map's
// texels, at least 4 M, padded), and as bake_horizon_tangents.
std::vector<float> bake_horizon_tangents_profiles(const Texture& height, float depth_texels,
                                                  const std::vector<Vec2f>& dirs, float max_distance);
// The same walks when only the comparison of tan H with given values matters: thresholds[k] (ascending, > 0)
// for dirs[k]. The result t satisfies, for every threshold τ of its direction, t < τ ⟺ tan H < τ (tan H the
// exact horizon, without the 1e-4 tolerance above); t itself is a lower bound of tan H. A walk stops as soon
// as no further point can cross the next threshold above its horizon, which makes it several times shorter
// (the directional bake needs exactly this: which fit directions are lit).
std::vector<float> bake_horizon_tangents(const Texture& height, float depth_texels,
                                         const std::vector<Vec2f>& dirs, float max_distance,
                                         const std::vector<std::vector<double>>& thresholds);

// A horizontal direction on the integer grid: the primitive step (p, q) (gcd(|p|, |q|) = 1), azimuth
// atan2(q, p) (x = +i columns, y = +j rows). The line through a vertex along it meets a vertex every step, so
// all the vertices on one line share one height profile, and one sweep finds all their horizons.
struct LatticeStep {
  int p = 1, q = 0;
};

// n azimuths near the uniform ones φ_a = 2π(a + ½)/n: for each, among the primitive steps of the smallest
// max(|p|, |q|) that has one within max_error_deg of φ_a, the closest to φ_a. InputError for n outside
// [1, 4096] or max_error_deg outside [0.01, 45].
std::vector<LatticeStep> lattice_azimuths(int n, double max_error_deg);

// Azimuth (radians, in (−π, π]) and unit direction of a lattice step.
double lattice_azimuth(LatticeStep s);
Vec2f lattice_direction(LatticeStep s);

// tan H ≥ 0 of the exact horizon at every vertex along each lattice step, unlimited ray length: the same
// surface, start-point rule and layout as bake_horizon_tangents (and equal to its exact value up to float
// rounding: no tolerance). One sweep per line of vertices (per step, the lines through the vertices wrap onto
// themselves), keeping the upper convex hull of the profile ahead (the horizon of a point is its tangent to
// that hull; Timonen & Westerholm 2010, "Scalable Height Field Self-Shadowing", here on the exact
// triangulated profile of a lattice line, whose breakpoints are the same on every step). Starting each sweep
// at the line's highest vertex makes one pass enough. Cost O(vertices · Σ(|p| + |q| + |p − q|)), independent
// of the relief's depth. InputError on an empty map, a non-primitive step or depth not finite ≥ 0.
// Deterministic whatever the thread count.
std::vector<float> bake_horizon_tangents_lattice(const Texture& height, float depth_texels,
                                                 const std::vector<LatticeStep>& steps);

// The same sweeps, each horizon only classified against thresholds[k] (one list per step, at most 255):
// out[k · w·h + j·w + i] = the first index e with thresholds[k][e] > tan H (as a double), the list's size if
// none; for ascending thresholds, how many lie at or below tan H. One byte per vertex and step (a quarter of
// the tangents' memory), step-major. InputError as bake_horizon_tangents_lattice, or when thresholds has
// another size than steps or a list is longer than 255.
std::vector<uint8_t> bake_horizon_classes_lattice(const Texture& height, float depth_texels,
                                                  const std::vector<LatticeStep>& steps,
                                                  const std::vector<std::vector<double>>& thresholds);

// The texture as a 2D io::Volume (same channels, values as they are), for the writers of io/texture.h.
io::Volume texture_volume(const Texture& t);
// The texture's values in that layout (texel-major, channels side by side), without a copy: for
// io::write_npy (io/npy.h). Empty for an empty texture.
std::span<const float> texture_values(const Texture& t);

// Reads directional channels as write_texture_set writes them (directional.npy: float32 NPY of shape
// (1, h, w, 9), or (1, h, w, 21) with the view correction; or any volume reader's format with depth 1 and 9
// or 21 channels). InputError naming the file if it is unreadable, has another shape or holds a non-finite
// value.
Texture load_directional_channels(const std::filesystem::path& path);

// Writes basecolor.png (sRGB), normal.png, roughness.png, metallic.png, micro_occlusion.png, height.png
// (16-bit), directional.npy (the 9 or 21 directional channels, float32 (1, h, w, 9 or 21), when baked) and
// material.json (the scene-material snippet with height_texels and directional; a scene that names height.png
// takes both from it) into dir (created if missing).
void write_texture_set(const std::filesystem::path& dir, const TextureSet& set);

}  // namespace msh::render
