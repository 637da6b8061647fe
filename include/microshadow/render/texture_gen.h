// Procedural texture sets that look like the seed's test cases: a height field (damaged plaster: noise,
// cracks, pits; or bark: furrowed ridges) turned into a normal map, a roughness map (left half rough, right
// half smooth, as in the seed's test), a base colour, and a micro-occlusion map baked the way artists bake
// it.
#pragma once

#include <microshadow/render/scene.h>

#include <filesystem>
#include <string>

namespace msh::render {

struct TextureSet {
  Texture height, normal, roughness, metallic, base_color, visibility;
  float depth_texels = 0;  // depth of the full height range in texel units (normal map and bake use it)
};

struct GenOptions {
  std::string kind = "plaster";  // plaster | bark
  int size = 256;                // texels per side (power of two not required)
  float depth_texels = 0;        // 0 = the kind's default (plaster 6, bark 10 texels at size 256, scaled)
  int ao_rays = 128;             // rays per texel for the micro-occlusion bake
  float ao_max_distance = 0;     // texels; 0 = the kind's default (8% of the size)
  float rough_left = 0.8f, rough_right = 0.3f;
  uint32_t seed = 7;
};

// Deterministic (pure function of the options; bit-identical whatever the thread count).
TextureSet generate_texture_set(const GenOptions& opt);

// Tangent-space normal map of a height map by central differences (wrap), encoded n·0.5 + 0.5;
// x = +u (columns), y = +v (rows, top to bottom). depth_texels as in HeightField.
Texture normal_map_from_height(const Texture& height, float depth_texels);

// Micro-occlusion as artists bake it: for each texel, the fraction of `rays` cosine-weighted directions about
// the flat normal (+z) that leave the height field within `max_distance` texels without a hit (rays longer
// than that count as unoccluded). Projected-solid-angle visibility, REFERENCE.md §1.
Texture bake_visibility(const Texture& height, float depth_texels, int rays, float max_distance);

// Writes basecolor.png (sRGB), normal.png, roughness.png, metallic.png, micro_occlusion.png, height.png
// (16-bit) and material.json (the scene-material snippet with height_texels) into dir (created if missing).
void write_texture_set(const std::filesystem::path& dir, const TextureSet& set);

}  // namespace msh::render
