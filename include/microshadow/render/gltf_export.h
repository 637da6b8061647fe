// A texture set as a glTF 2.0 sample asset (docs/gltf.md): a textured plane with normals, UVs and tangents,
// the core metallic-roughness material (base colour, normal map, occlusion/roughness/metallic packed in one
// ORM texture) and, when the set has directional channels, the material extension
// MSH_materials_directional_occlusion (the channels as a linear code: K coefficient textures, their ranges,
// a mean and a basis; docs/schema/MSH_materials_directional_occlusion.schema.json).
#pragma once

#include <microshadow/render/texture_gen.h>

#include <filesystem>
#include <string>
#include <vector>

namespace msh::render {

inline constexpr const char* kGltfDirectionalExtension = "MSH_materials_directional_occlusion";

// The extension's linear code: K coefficient channels a_k (coefficients: K channels per texel, float),
// stored as UNORM8 between [lo_k, hi_k], four per RGBA8 PNG; the 21 channels of directional-view are
// c_i = mean_i + Σ_k basis[i][k] a_k (occlusion/directional.h, directional_view_term).
struct DirectionalCode {
  std::string form = "channels21";
  std::vector<float> lo, hi;              // K each
  std::vector<float> mean;                // 21
  std::vector<std::vector<float>> basis;  // 21 rows of K
  Texture coefficients;                   // K channels
  int k() const { return coefficients.channels(); }
};

// The 21 channels themselves (K = 21, identity basis, zero mean, each channel's fine-level range:
// channel_ranges, the ranges gen-material's mips use). InputError unless the texture has 21 channels.
DirectionalCode identity_directional_code(const Texture& channels21);

// A compact form as the extension's code (render/directional_codec.h, an 8-bit pca<K> fitted to these 21
// channels): the fine level's coefficients encode_directional gives, the codec's ranges, mean and basis; the
// PNGs quantise each coefficient to 8 bits as the mips' directional_compact_<t> do. InputError unless the
// texture has 21 channels and the codec decodes to 21.
struct DirectionalCodec;
DirectionalCode compact_directional_code(const Texture& channels21, const DirectionalCodec& codec);

// Checks a code (sizes, finite numbers, hi ≥ lo, the texture's size against width × height); InputError
// naming the problem.
void check_directional_code(const DirectionalCode& code, int width, int height);

// Writes DIR/NAME.gltf, DIR/NAME.bin and the PNGs (basecolor.png sRGB, normal.png with glTF's +Y-up green,
// orm.png, directional_<t>.png) into a temporary directory beside DIR, then renames it to DIR (an existing
// DIR is replaced): a failure leaves no partial asset. code == nullptr: no extension. InputError on bad input
// or a failed write.
void write_texture_set_gltf(const std::filesystem::path& dir, const TextureSet& set,
                            const DirectionalCode* code, const std::string& name = "material");

// The glTF JSON alone (for tests): buffer and image URIs relative to the .gltf.
std::string texture_set_gltf_json(const TextureSet& set, const DirectionalCode* code, const std::string& name,
                                  std::size_t* bin_bytes = nullptr);
// The .bin: positions, normals, tangents, UVs, indices of the plane.
std::vector<unsigned char> texture_set_gltf_bin();

}  // namespace msh::render
