// The three.js integration (integrations/three, docs/three.md): the module's generated files (the method list
// from the micro-shadowing registry and the project's GLSL files with their includes expanded: three.js
// compiles WebGL2 shaders, which have no #include) and the example page's static copy. I/O: not part of the
// embeddable core.
#pragma once

#include <filesystem>
#include <string>

#include "viewer_server.h"

namespace msh::view {

// glsl.js: the shader files of `glsl_dir` that the module uses (micro_shadowing, micro_shadowing_fit,
// micro_shadowing_aware, micro_shadowing_aware_fit, micro_shadowing_area .glsl), each with its includes
// expanded (expand_shader_includes), as an ES module exporting MSH_GLSL = { "<file>.glsl": "<text>", ... }.
std::string three_glsl_js(const std::filesystem::path& glsl_dir);

// Writes the module's generated files into `dir` (created if missing): methods.js (methods_js of the runtime
// registry, the viewer's list) and glsl.js (three_glsl_js of assets/shaders/glsl). Each file atomically;
// InputError (one line) when the shaders cannot be read or the files cannot be written.
void write_three_module(const std::filesystem::path& assets, const std::filesystem::path& dir);

// A glTF 2.0 model for the example: a torus (major radius 0.7, tube radius 0.3, 128 x 48 quads) with
// positions, normals, tangents (bitangent = +v, the texture set's normal-map convention), texture
// coordinates tiled 7 x 3, its buffer embedded as a base64 data URI, and one material whose textures are the
// texture set's PNG files under `texture_prefix` (the viewer's data/material/ names): base colour,
// roughness as metallicRoughness (G; metallicFactor 0, so B is unused), normal and the micro-occlusion map
// as the occlusion texture (R). Deterministic.
std::string three_example_gltf(const std::string& texture_prefix);

// Writes the example page's static copy to `out` (written beside it, then renamed): examples/three/*, the
// module as microshadow-three/ (integrations/three/src with freshly generated files), the three.js files the
// page imports (from integrations/three/node_modules/three, installed by `npm ci`), the texture set and
// tables of viewer_data_files under data/, and data/model.gltf. `o.assets` must be the source tree;
// InputError (one line) names what is missing.
void export_three_example(const ViewerOptions& o, const std::filesystem::path& out);

}  // namespace msh::view
