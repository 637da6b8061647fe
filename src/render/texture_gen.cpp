// Procedural texture sets (see render/texture_gen.h). Every noise here is periodic so the maps tile, and a
// pure function of (u, v, seed), so generation is deterministic.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/npy.h>
#include <microshadow/io/texture.h>
#include <microshadow/math/sampling.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/image.h>
#include <microshadow/render/texture_gen.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace msh::render {

namespace {

float hash01(int i, int j, uint32_t seed) {
  return float(hash_combine(hash_combine(hash_u32(seed), uint32_t(i)), uint32_t(j))) * 0x1p-32f;
}
int wrap(int i, int p) { return ((i % p) + p) % p; }
float quintic(float t) { return t * t * t * (t * (t * 6 - 15) + 10); }
float smoothstep(float a, float b, float x) {
  const float t = saturate((x - a) / (b - a));
  return t * t * (3 - 2 * t);
}

// Value noise with lattice period p (u, v ∈ [0,1) → one period), in [0,1].
float value_noise(float u, float v, int p, uint32_t seed) {
  const float x = u * p, y = v * p, fx = std::floor(x), fy = std::floor(y);
  const int i = int(fx), j = int(fy);
  const float tx = quintic(x - fx), ty = quintic(y - fy);
  auto h = [&](int a, int b) { return hash01(wrap(a, p), wrap(b, p), seed); };
  return lerp(ty, lerp(tx, h(i, j), h(i + 1, j)), lerp(tx, h(i, j + 1), h(i + 1, j + 1)));
}
// Fractional Brownian motion: octaves of value noise, period doubling; normalized to [0,1].
float fbm(float u, float v, int p, int octaves, uint32_t seed) {
  float s = 0, a = 0.5f, norm = 0;
  for (int k = 0; k < octaves; ++k, p *= 2, a *= 0.5f) {
    s += a * value_noise(u, v, p, hash_combine(seed, uint32_t(k)));
    norm += a;
  }
  return s / norm;
}
// Periodic Worley noise (one feature point per cell, px × py cells): distances F1, F2 in cell units.
Vec2f worley(float u, float v, int px, int py, uint32_t seed) {
  const float x = u * px, y = v * py;
  const int i = int(std::floor(x)), j = int(std::floor(y));
  float f1 = 1e9f, f2 = 1e9f;
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int ci = i + di, cj = j + dj;
      const float fx = float(ci) + hash01(wrap(ci, px), wrap(cj, py), seed);
      const float fy = float(cj) + hash01(wrap(ci, px), wrap(cj, py), seed ^ 0x9e3779b9u);
      const float d = std::hypot(x - fx, y - fy);
      if (d < f1)
        f2 = f1, f1 = d;
      else if (d < f2)
        f2 = d;
    }
  return {f1, f2};
}

float plaster_height(float u, float v, uint32_t seed) {
  float h = 1.0f - 0.10f * fbm(u, v, 8, 5, seed + 1);
  // Chipped areas: flat-bottomed plateaus where a low-frequency noise is low.
  const float c = fbm(u, v, 4, 4, seed + 2);
  h -= 0.35f * smoothstep(0.40f, 0.33f, c);
  // Cracks: Worley cell edges (F2 − F1 small), domain-warped, only where a mask noise allows.
  const float wu = u + 0.04f * (fbm(u, v, 4, 3, seed + 3) - 0.5f),
              wv = v + 0.04f * (fbm(u, v, 4, 3, seed + 4) - 0.5f);
  const Vec2f f = worley(wu, wv, 5, 5, seed + 5);
  const float crack = 1.0f - smoothstep(0.0f, 0.06f, f.y - f.x);
  h -= 0.75f * crack * smoothstep(0.42f, 0.55f, fbm(u, v, 4, 2, seed + 6));
  // Pits: round holes with a parabolic profile, about one in three cells of a 16 × 16 grid.
  const int P = 16;
  const float x = u * P, y = v * P;
  const int i = int(std::floor(x)), j = int(std::floor(y));
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int ci = wrap(i + di, P), cj = wrap(j + dj, P);
      if (hash01(ci, cj, seed + 7) > 0.35f) continue;
      const float cx = float(i + di) + hash01(ci, cj, seed + 8),
                  cy = float(j + dj) + hash01(ci, cj, seed + 9);
      const float r = 0.12f + 0.3f * hash01(ci, cj, seed + 10);
      const float d = std::hypot(x - cx, y - cy) / r;
      if (d < 1) h -= (0.3f + 0.4f * hash01(ci, cj, seed + 11)) * (1 - d * d);
    }
  return saturate(h);
}

float bark_height(float u, float v, uint32_t seed) {
  // Vertical ridges with sharp furrows: a warped cosine along u (12 ridges per tile), flattened on top.
  const float warp = 0.6f * (fbm(u, v, 4, 4, seed + 1) - 0.5f) + 0.15f * (fbm(u, v, 16, 2, seed + 2) - 0.5f);
  const float s = 0.5f + 0.5f * std::cos(2 * kPi<float> * (12 * u + warp * 3));
  float h = 0.1f + 0.9f * std::pow(s, 0.35f) * (0.8f + 0.2f * fbm(u, v, 16, 3, seed + 3));
  // Horizontal fissures across the ridges: elongated Worley cells.
  const Vec2f f = worley(u, v, 12, 4, seed + 4);
  h -= 0.45f * (1.0f - smoothstep(0.0f, 0.08f, f.y - f.x)) *
       smoothstep(0.45f, 0.6f, fbm(u, v, 8, 2, seed + 5));
  return saturate(h);
}

// The relief kinds made of pieces (gravel, rock, brick, cobble) return this: the height in [0, 1] and the
// id hash of the piece the point lies on (stone, block, brick; 0 = the bed, mortar or sand between them),
// from which the colour pass takes a per-piece tone.
struct PieceSample {
  float h;
  uint32_t piece;
};
// A piece's tone in [0, 1) from its id: the top 24 bits of its hash.
float piece_tone(uint32_t id) { return float(hash_u32(id) >> 8) * 0x1p-24f; }

// The colour of a piece sample: `bed` between the pieces, else from lo to hi by the piece's tone, shaded by
// the large-scale tint (fBm in [0, 1]).
Rgbf piece_colour(const PieceSample& p, Rgbf bed, Rgbf lo, Rgbf hi, float tint) {
  return p.piece == 0 ? bed : lerp(piece_tone(p.piece), lo, hi) * (0.85f + 0.15f * tint);
}

// The sand bed of cobble and gravel.
Rgbf sand_colour(float tint) { return Rgbf(0.42f, 0.36f, 0.28f) * (0.8f + 0.2f * tint); }

// Gravel: packed stones on a sandy bed. One stone per cell of a 20 × 20 jittered grid (a random half of the
// cells get a second, smaller stone), each an elliptical dome (random radii 0.35–0.75 cell, orientation,
// height 0.55–1) with a flattened-sphere profile √(1 − q²)^0.8; the surface is the highest dome, or the
// bed (fine fBm around 0.12) where no stone is. Stone radii stay below one cell, so the 3 × 3 neighbour
// cells hold every stone that can reach a point. Returns the height and the id hash of the top stone (for
// its colour; 0 = bed).
PieceSample gravel_height(float u, float v, uint32_t seed) {
  const int P = 20;
  const float x = u * P, y = v * P;
  const int i = int(std::floor(x)), j = int(std::floor(y));
  PieceSample out{0.08f + 0.08f * fbm(u, v, 64, 3, seed + 1), 0u};
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int ci = wrap(i + di, P), cj = wrap(j + dj, P);
      for (int k = 0; k < 2; ++k) {
        const uint32_t sd = seed + 10 + 16 * uint32_t(k);
        if (k == 1 && hash01(ci, cj, sd + 15) < 0.5f) continue;
        const float cx = float(i + di) + hash01(ci, cj, sd), cy = float(j + dj) + hash01(ci, cj, sd + 1);
        const float size = k == 0 ? 1.0f : 0.6f;
        const float ra = size * (0.45f + 0.3f * hash01(ci, cj, sd + 2)),
                    rb = ra * (0.6f + 0.4f * hash01(ci, cj, sd + 3));
        const float th = kPi<float> * hash01(ci, cj, sd + 4), c = std::cos(th), sn = std::sin(th);
        const float px = x - cx, py = y - cy, a = (c * px + sn * py) / ra, b = (-sn * px + c * py) / rb;
        const float q2 = a * a + b * b;
        if (q2 >= 1) continue;
        const float top = size * (0.55f + 0.45f * hash01(ci, cj, sd + 5));
        const float hv = top * std::pow(1 - q2, 0.4f);
        if (hv > out.h) out = {hv, hash_combine(hash_combine(uint32_t(ci), uint32_t(cj)), uint32_t(k) + 1)};
      }
    }
  out.h = saturate(out.h);
  return out;
}

// Ridged multifractal (Musgrave): 1 − |2n − 1| makes sharp crests; each octave is weighted by the one
// before, so fine detail gathers on the crests and the valleys stay smooth, as on weathered rock. In [0, 1].
float ridged(float u, float v, int p, int octaves, uint32_t seed) {
  float s = 0, a = 0.5f, w = 1, norm = 0;
  for (int k = 0; k < octaves; ++k, p *= 2, a *= 0.5f) {
    float r = 1 - std::abs(2 * value_noise(u, v, p, hash_combine(seed, uint32_t(k))) - 1);
    r = r * r * w;
    w = saturate(2 * r);
    s += a * r;
    norm += a;
  }
  return s / norm;
}

// Worley noise that also returns the nearest feature's cell (wrapped) and its offset from the point, in cell
// units: per-cell shapes (rock blocks, cobbles) need which cell they are in, not just the distances.
struct WorleyCell {
  float f1, f2;
  int ci, cj;    // nearest feature's cell, wrapped to [0, px) × [0, py)
  float dx, dy;  // point − feature, cell units
};
WorleyCell worley_cell(float u, float v, int px, int py, uint32_t seed) {
  const float x = u * px, y = v * py;
  const int i = int(std::floor(x)), j = int(std::floor(y));
  WorleyCell w{1e9f, 1e9f, 0, 0, 0, 0};
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int ci = wrap(i + di, px), cj = wrap(j + dj, py);
      const float fx = float(i + di) + hash01(ci, cj, seed),
                  fy = float(j + dj) + hash01(ci, cj, seed ^ 0x9e3779b9u);
      const float d = std::hypot(x - fx, y - fy);
      if (d < w.f1)
        w.f2 = w.f1, w.f1 = d, w.ci = ci, w.cj = cj, w.dx = x - fx, w.dy = y - fy;
      else if (d < w.f2)
        w.f2 = d;
    }
  return w;
}

// The Worley cell (cells × cells) of (u, v) displaced by `warp` × (fBm − 0.5) in each axis (period `period`,
// `octaves` octaves): the cells' edges wander instead of being straight Voronoi edges. Seeds seed .. seed
// + 2.
WorleyCell warped_worley_cell(float u, float v, float warp, int period, int octaves, int cells,
                              uint32_t seed) {
  const float wu = u + warp * (fbm(u, v, period, octaves, seed + 1) - 0.5f),
              wv = v + warp * (fbm(u, v, period, octaves, seed + 2) - 0.5f);
  return worley_cell(wu, wv, cells, cells, seed + 3);
}

// Fractured rock: blocks (Worley cells, 6 × 6) each a tilted plane at its own level, so neighbouring blocks
// meet in steps and ledges; deep cracks along the block edges; a ridged multifractal for the weathered
// surface; a few large fracture planes (straight cliffs crossing the tile) cut across everything. Returns
// the height and the block id (for its colour).
PieceSample rock_height(float u, float v, uint32_t seed) {
  const WorleyCell c = warped_worley_cell(u, v, 0.05f, 4, 3, 6, seed);
  const float base = 0.35f + 0.3f * hash01(c.ci, c.cj, seed + 4);
  const float gx = 0.5f * (hash01(c.ci, c.cj, seed + 5) - 0.5f),
              gy = 0.5f * (hash01(c.ci, c.cj, seed + 6) - 0.5f);
  float h = base + gx * c.dx + gy * c.dy + 0.3f * ridged(u, v, 8, 5, seed + 7);
  // Cracks between blocks: V-shaped, 0.08 cell wide.
  h -= 0.35f * (1.0f - smoothstep(0.0f, 0.08f, c.f2 - c.f1));
  // Fracture planes: 3 families of straight cliffs of integer direction (so they tile): a terrace per period.
  for (int k = 0; k < 3; ++k) {
    const uint32_t sd = seed + 20 + 4 * uint32_t(k);
    const int a = 1 + int(3 * hash01(k, 0, sd)), b = int(4 * hash01(k, 1, sd)) - 2;
    const float t = float(a) * u + float(b) * v + hash01(k, 2, sd);
    const float f = t - std::floor(t);  // position across the plane's period
    h += 0.12f * (smoothstep(0.47f, 0.53f, f) - smoothstep(0.95f, 1.0f, f)) - 0.06f;
  }
  return {saturate(h), hash_combine(uint32_t(c.ci), uint32_t(c.cj)) | 1u};
}

// Brick paving, running bond: 8 × 16 bricks of 2:1 per tile, alternate rows shifted by half a brick. Each
// brick is a rounded box (a quarter-circle edge 0.22 brick-height wide) standing on a mortar bed, with its
// own level and a slight tilt (settled paving), and a little surface noise. Returns the height and the
// brick id (0 = mortar).
PieceSample brick_height(float u, float v, uint32_t seed) {
  const int cols = 8, rows = 16;
  const float y = v * rows, fy = std::floor(y);
  const int row = int(fy);
  const float x = u * cols + (row % 2 ? 0.5f : 0.0f), fx = std::floor(x);
  const int col = wrap(int(fx), cols);
  // Local coordinates from the brick's centre in brick-height units (a brick is 2 × 1).
  const float px = 2 * (x - fx - 0.5f), py = y - fy - 0.5f;
  const float mortar = 0.06f, round = 0.22f;  // joint half-width and edge radius, brick-height units
  const float qx = std::abs(px) - (1 - mortar - round), qy = std::abs(py) - (0.5f - mortar - round);
  const float sdf =
      std::hypot(std::max(qx, 0.0f), std::max(qy, 0.0f)) + std::min(std::max(qx, qy), 0.0f) - round;
  const float bed = 0.1f + 0.06f * fbm(u, v, 64, 3, seed + 1);
  if (sdf >= 0) return {saturate(bed), 0u};
  const float t = std::min(-sdf / round, 1.0f);
  const float profile = std::sqrt(1 - (1 - t) * (1 - t));  // quarter circle: round arris
  const float top =
      0.78f + 0.12f * hash01(col, row, seed + 2) + 0.06f * (hash01(col, row, seed + 3) - 0.5f) * px +
      0.12f * (hash01(col, row, seed + 4) - 0.5f) * py + 0.05f * (fbm(u, v, 32, 4, seed + 5) - 0.5f);
  return {saturate(bed + (top - bed) * profile), hash_combine(uint32_t(col), uint32_t(row)) | 1u};
}

// Cobblestones: one rounded stone per cell of a 12 × 12 jittered grid (Voronoi cells, so the stones fill the
// plane like set cobbles); each a dome whose height follows the distance to the cell's edge, (F2 − F1)/2,
// with its own height; sand in the joints. Returns the height and the stone id (0 = sand).
PieceSample cobble_height(float u, float v, uint32_t seed) {
  const WorleyCell c = warped_worley_cell(u, v, 0.02f, 8, 2, 12, seed);
  const float edge = 0.5f * (c.f2 - c.f1);  // distance to the cell's edge, cell units
  const float joint = 0.05f;
  const float sand = 0.08f + 0.08f * fbm(u, v, 64, 3, seed + 4);
  if (edge <= joint) return {saturate(sand), 0u};
  const float t = std::min((edge - joint) / 0.3f, 1.0f);
  const float dome = std::sqrt(1 - (1 - t) * (1 - t));  // round shoulders, flattish top
  const float top = 0.7f + 0.3f * hash01(c.ci, c.cj, seed + 5) + 0.04f * (fbm(u, v, 32, 3, seed + 6) - 0.5f);
  return {saturate(sand + (top - sand) * dome), hash_combine(uint32_t(c.ci), uint32_t(c.cj)) | 1u};
}

}  // namespace

Material material_from_texture_set(const std::string& name, const TextureSet& s, bool ground_truth) {
  Material m;
  m.name = name;
  m.base_color = s.base_color;
  m.roughness = s.roughness;
  m.metallic = s.metallic;
  if (ground_truth) {
    m.height = s.height;
    m.height_texels = s.depth_texels;
    m.visibility = Texture::constant({1, 0, 0, 0}, 1);
  } else {
    m.normal = s.normal;
    m.visibility = s.visibility;
    m.directional = s.directional;
    m.slope_covariance = s.slope_covariance;
  }
  return m;
}

Texture normal_map_from_height(const Texture& height, float depth) {
  HeightField hf(height, depth);
  Texture n(height.width(), height.height(), 3);
  for (int j = 0; j < height.height(); ++j)
    for (int i = 0; i < height.width(); ++i) {
      const Vec3f v = hf.vertex_normal(i, j);
      n.at(i, j, 0) = 0.5f * v.x + 0.5f, n.at(i, j, 1) = 0.5f * v.y + 0.5f, n.at(i, j, 2) = 0.5f * v.z + 0.5f;
    }
  return n;
}

namespace {

void check_bake_options(const GenOptions& opt) {
  if (opt.ao_rays < 1 || opt.ao_rays > 65536) throw InputError("ao rays must be in [1, 65536]");
  if (!(opt.ao_max_distance >= 0) || !std::isfinite(opt.ao_max_distance))
    throw InputError("ao distance must be finite and >= 0");
  if (opt.directional_azimuths != 0)  // 0: not baked
    check_directional_azimuths("directional azimuths (0 = not baked)", opt.directional_azimuths);
}

// Normal map and micro-occlusion bake of a set whose height, colour, roughness and metallic are filled.
void finish_set(TextureSet& s, const GenOptions& opt) {
  const float maxd = opt.ao_max_distance > 0 ? opt.ao_max_distance
                                             : 0.08f * float(std::max(s.height.width(), s.height.height()));
  s.normal = normal_map_from_height(s.height, s.depth_texels);
  s.visibility = bake_visibility(s.height, s.depth_texels, opt.ao_rays, maxd);
  if (opt.directional_azimuths > 0)
    s.directional =
        opt.directional_view
            ? bake_directional_view_channels(s.height, s.depth_texels, opt.directional_azimuths, 0.0f)
            : bake_directional_channels(s.height, s.depth_texels, opt.directional_azimuths, 0.0f);
  s.slope_covariance = slope_covariance(s.normal);
}

// The test roughness of Zurita 2026, "Improving Direct Lighting Material Occlusion – Part 2": rough on the
// left half, smooth on the right half (noise breaks banding).
float split_roughness(const GenOptions& opt, float u, float noise) {
  return saturate((u < 0.5f ? opt.rough_left : opt.rough_right) + noise);
}

}  // namespace

std::array<float, 3> slope_covariance(const Texture& normal) {
  if (normal.empty() || normal.channels() != 3)
    throw InputError(
        fmt::format("slope_covariance: the normal map must have 3 channels, got {}", normal.channels()));
  double xx = 0, xy = 0, yy = 0, zz = 0;
  for (int j = 0; j < normal.height(); ++j)
    for (int i = 0; i < normal.width(); ++i) {
      const double nx = 2.0 * normal.at(i, j, 0) - 1, ny = 2.0 * normal.at(i, j, 1) - 1,
                   nz = 2.0 * normal.at(i, j, 2) - 1;
      if (!std::isfinite(nx) || !std::isfinite(ny) || !std::isfinite(nz))
        throw InputError("slope_covariance: a normal is not finite");
      xx += nx * nx, xy += nx * ny, yy += ny * ny, zz += nz * nz;
    }
  if (!(zz > 0)) return {0.0f, 0.0f, 0.0f};
  return {float(xx / zz), float(xy / zz), float(yy / zz)};
}

namespace {
// Depth of the full height range in texels at size 256 (scaled with the size): chosen so that the baked
// mean V lies in 0.78–0.89 for the relief kinds (rock, brick, cobble; measured at 512², docs/study.md).
float default_depth_at_256(const std::string& kind) {
  if (kind == "plaster") return 6.0f;
  if (kind == "bark") return 12.0f;
  if (kind == "rock") return 16.0f;
  if (kind == "brick") return 8.0f;
  if (kind == "cobble") return 9.0f;
  return 8.0f;  // gravel
}
}  // namespace

std::vector<std::string> material_kinds() { return {"plaster", "bark", "gravel", "rock", "brick", "cobble"}; }

TextureSet generate_texture_set(const GenOptions& opt) {
  const auto kinds = material_kinds();
  if (std::find(kinds.begin(), kinds.end(), opt.kind) == kinds.end())
    throw InputError(
        fmt::format("unknown material kind '{}' (plaster, bark, gravel, rock, brick, cobble)", opt.kind));
  if (opt.size < 8 || opt.size > 8192)
    throw InputError(fmt::format("size must be in [8, 8192], got {}", opt.size));
  check_bake_options(opt);
  if (!(opt.depth_texels >= 0) || !std::isfinite(opt.depth_texels))
    throw InputError("depth must be finite and >= 0");
  const int n = opt.size;
  const float scale = float(n) / 256.0f;
  const float default_depth = default_depth_at_256(opt.kind);
  TextureSet s;
  s.depth_texels = opt.depth_texels > 0 ? opt.depth_texels : default_depth * scale;
  s.height = Texture(n, n, 1);
  s.base_color = Texture(n, n, 3);
  s.roughness = Texture(n, n, 1);
  s.metallic = Texture(n, n, 1);
  tbb::parallel_for(0, n, [&](int j) {
    for (int i = 0; i < n; ++i) {
      const float u = (float(i) + 0.5f) / float(n), v = (float(j) + 0.5f) / float(n);
      const float tint = fbm(u, v, 8, 3, opt.seed + 50);
      float hv;
      Rgbf c;
      if (opt.kind == "plaster") {
        hv = plaster_height(u, v, opt.seed);
        c = Rgbf(0.80f, 0.77f, 0.72f) * (0.80f + 0.12f * hv + 0.08f * tint);
      } else if (opt.kind == "bark") {
        hv = bark_height(u, v, opt.seed);
        c = Rgbf(0.36f, 0.25f, 0.17f) * (0.55f + 0.3f * hv + 0.15f * tint);
      } else if (opt.kind == "rock") {
        const PieceSample r = rock_height(u, v, opt.seed);
        hv = r.h;
        // Grey stone, per-block shade, darker in the cracks.
        const float a = piece_tone(r.piece);
        c = Rgbf(0.46f, 0.44f, 0.41f) * (0.55f + 0.35f * hv + 0.15f * a) * (0.9f + 0.1f * tint);
      } else if (opt.kind == "brick") {
        const PieceSample b = brick_height(u, v, opt.seed);
        hv = b.h;
        const Rgbf mortar = Rgbf(0.55f, 0.53f, 0.49f) * (0.85f + 0.15f * tint);
        c = piece_colour(b, mortar, Rgbf(0.52f, 0.22f, 0.14f), Rgbf(0.62f, 0.34f, 0.22f), tint);
      } else if (opt.kind == "cobble") {
        const PieceSample cb = cobble_height(u, v, opt.seed);
        hv = cb.h;
        c = piece_colour(cb, sand_colour(tint), Rgbf(0.40f, 0.40f, 0.40f), Rgbf(0.50f, 0.44f, 0.38f), tint);
      } else {
        const PieceSample g = gravel_height(u, v, opt.seed);
        hv = g.h;
        if (g.piece == 0) {
          c = sand_colour(tint);
        } else {
          // Per-stone grey to warm-brown tint and brightness.
          const float a = piece_tone(g.piece), b = piece_tone(g.piece ^ 0x5bd1e995u);
          c = lerp(a, Rgbf(0.50f, 0.50f, 0.49f), Rgbf(0.55f, 0.45f, 0.35f)) * (0.6f + 0.5f * b) *
              (0.9f + 0.1f * tint);
        }
      }
      s.height.at(i, j, 0) = hv;
      s.base_color.at(i, j, 0) = c.r, s.base_color.at(i, j, 1) = c.g, s.base_color.at(i, j, 2) = c.b;
      s.roughness.at(i, j, 0) = split_roughness(opt, u, 0.04f * (tint - 0.5f));
      s.metallic.at(i, j, 0) = 0.0f;
    }
  });
  finish_set(s, opt);
  return s;
}

Texture load_height_map(const std::filesystem::path& path) {
  const std::string name = path.string();
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: height map not found", name));
  std::string ext = path.extension().string();
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  if (ext != ".png" && ext != ".exr")
    throw InputError(fmt::format("{}: height map must be a 16-bit PNG or an EXR", name));
  if (ext == ".png") {
    // Signature (8 bytes), then the IHDR chunk: length 13 at byte 8, type "IHDR" at byte 12, bit depth at
    // byte 24, colour type at byte 25 (PNG spec §5.2, §11.2.2). 8-bit heights make terraces.
    require_regular_file(path, "height map ");
    std::ifstream f(path, std::ios::binary);
    unsigned char hdr[26] = {};
    static constexpr unsigned char kSig[12] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13};
    if (!f.read(reinterpret_cast<char*>(hdr), 26) || std::memcmp(hdr, kSig, 12) != 0 ||
        std::memcmp(hdr + 12, "IHDR", 4) != 0)
      throw InputError(fmt::format("{}: not a PNG file (bad signature or IHDR)", name));
    const int bits = hdr[24], type = hdr[25];
    // The bit depths and colour types of PNG spec table 11.1; anything else is a corrupt header.
    const bool valid_bits = bits == 1 || bits == 2 || bits == 4 || bits == 8 || bits == 16;
    const bool valid_type = type == 0 || type == 2 || type == 3 || type == 4 || type == 6;
    if (!valid_bits || !valid_type)
      throw InputError(
          fmt::format("{}: corrupt PNG header (bit depth {}, colour type {})", name, bits, type));
    if (type == 3) throw InputError(fmt::format("{}: palette PNG; a height map must be grey", name));
    if (bits != 16)
      throw InputError(
          fmt::format("{}: {}-bit PNG; a height map needs 16 bits (or EXR): {} levels make visible terraces",
                      name, bits, 1 << bits));
  }
  const Texture t = load_texture(path, false);
  if (t.width() < 8 || t.height() < 8 || t.width() > 16384 || t.height() > 16384)
    throw InputError(
        fmt::format("{}: height map is {}x{}; each side must be in [8, 16384]", name, t.width(), t.height()));
  // Grey: one channel (grey + alpha: the first), or RGB(A) with R = G = B everywhere.
  const int colour = t.channels() >= 3 ? 3 : 1;
  Texture h(t.width(), t.height(), 1);
  for (int j = 0; j < t.height(); ++j)
    for (int i = 0; i < t.width(); ++i) {
      const float g = t.at(i, j, 0);
      for (int c = 1; c < colour; ++c)
        if (t.at(i, j, c) != g)
          throw InputError(fmt::format("{}: not a grey image (texel ({}, {}) has R, G, B = {}, {}, {})", name,
                                       i, j, g, t.at(i, j, 1), t.at(i, j, 2)));
      if (!(g >= 0.0f && g <= 1.0f))
        throw InputError(fmt::format("{}: height {} at texel ({}, {}) is outside [0, 1]", name, g, i, j));
      h.at(i, j, 0) = g;
    }
  return h;
}

TextureSet texture_set_from_height(const Texture& height, float depth_texels, const GenOptions& opt) {
  if (!(depth_texels > 0) || !std::isfinite(depth_texels) || depth_texels > 1e4f)
    throw InputError(fmt::format("depth must be in (0, 10000] texels, got {}", depth_texels));
  if (height.empty() || height.channels() != 1) throw InputError("height map must have one channel");
  check_bake_options(opt);
  const int w = height.width(), h = height.height();
  TextureSet s;
  s.depth_texels = depth_texels;
  s.height = height;
  s.base_color = Texture(w, h, 3);
  s.roughness = Texture(w, h, 1);
  s.metallic = Texture(w, h, 1);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      for (int c = 0; c < 3; ++c) s.base_color.at(i, j, c) = 0.5f;
      s.roughness.at(i, j, 0) = split_roughness(opt, (float(i) + 0.5f) / float(w), 0.0f);
    }
  finish_set(s, opt);
  return s;
}

io::Volume texture_volume(const Texture& t) {
  io::Volume v(t.width(), t.height(), 1, t.channels());
  for (int y = 0; y < t.height(); ++y)
    for (int x = 0; x < t.width(); ++x)
      for (int c = 0; c < t.channels(); ++c) v.at(x, y, 0, c) = t.at(x, y, c);
  return v;
}

std::span<const float> texture_values(const Texture& t) {
  if (t.empty()) return {};
  // Texture's const at() returns values; the non-const one gives the address of its first (only read here).
  const float* first = &const_cast<Texture&>(t).at(0, 0, 0);
  return {first, std::size_t(t.width()) * std::size_t(t.height()) * std::size_t(t.channels())};
}

Texture load_directional_channels(const std::filesystem::path& path) {
  const io::Volume v = io::read_volume(path);
  if (v.depth != 1 ||
      (v.channels != directional::kDirectionalChannels && v.channels != directional::kViewChannels))
    throw InputError(fmt::format(
        "{}: expected {} or {} channels per texel (1, h, w, {} or {}), got {} x {} x {} x {}", path.string(),
        directional::kDirectionalChannels, directional::kViewChannels, directional::kDirectionalChannels,
        directional::kViewChannels, v.depth, v.height, v.width, v.channels));
  Texture t(v.width, v.height, v.channels);
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x)
      for (int k = 0; k < v.channels; ++k) {
        const float f = v.at(x, y, 0, k);
        if (!std::isfinite(f)) throw InputError(fmt::format("{}: non-finite value", path.string()));
        t.at(x, y, k) = f;
      }
  return t;
}

namespace {
void write_tex(const std::filesystem::path& p, const Texture& t, bool srgb, int bits) {
  io::Volume v(t.width(), t.height(), 1, t.channels());
  for (int y = 0; y < t.height(); ++y)
    for (int x = 0; x < t.width(); ++x)
      for (int c = 0; c < t.channels(); ++c)
        v.at(x, y, 0, c) = srgb ? srgb_encode(t.at(x, y, c)) : t.at(x, y, c);
  io::write_png(p, v, bits);
}
}  // namespace

void write_texture_set(const std::filesystem::path& dir, const TextureSet& s) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create directory: {}", dir.string(), ec.message()));
  write_tex(dir / "basecolor.png", s.base_color, true, 8);
  write_tex(dir / "normal.png", s.normal, false, 16);
  write_tex(dir / "roughness.png", s.roughness, false, 8);
  write_tex(dir / "metallic.png", s.metallic, false, 8);
  write_tex(dir / "micro_occlusion.png", s.visibility, false, 8);
  write_tex(dir / "height.png", s.height, false, 16);
  // The directional channels (float32, (1, h, w, 9 or 21)): the renderer takes them from material.json.
  if (!s.directional.empty()) {
    io::write_npy(dir / "directional.npy", texture_values(s.directional), s.directional.width(),
                  s.directional.height(), 1, s.directional.channels());
  }
  const std::string json = fmt::format(
      "{{\n  \"base_color\": \"basecolor.png\",\n  \"normal\": \"normal.png\",\n  \"roughness\": "
      "\"roughness.png\",\n"
      "  \"metallic\": \"metallic.png\",\n  \"micro_occlusion\": \"micro_occlusion.png\",\n"
      "  \"height\": \"height.png\",\n{}  \"height_texels\": {}\n}}\n",
      s.directional.empty() ? "" : "  \"directional\": \"directional.npy\",\n", s.depth_texels);
  io::write_file_atomic(dir / "material.json", json);
}

}  // namespace msh::render
