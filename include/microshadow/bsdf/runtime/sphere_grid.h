// Sphere-grid figures of BRDF models (RTR4 figs. 9.39, 9.41 style): each cell is an orthographic sphere seen
// along +z, lit by a uniform white environment (its exact contribution is the directional albedo E(N·V),
// tabulated per model) plus one directional light. Deterministic; threads (oneTBB) only split pixel rows.
#pragma once

#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/io/texture.h>

#include <vector>

namespace msh::bsdf {

struct SphereLighting {
  double environment = 0.4;             // radiance of the uniform environment
  Vec3d sun_dir = {-0.45, 0.55, 0.70};  // towards the light, world frame (x right, y up, z to the viewer)
  double sun = 1.6;                     // irradiance of the directional light at normal incidence
  int albedo_samples = 1 << 12;         // QMC samples per tabulated E(μ) value
};

// rows[i][j]: the model of row i, column j (nullptr = empty cell). Each cell is px × px; linear RGB output
// (3 channels, not tone mapped).
io::Volume render_sphere_grid(const std::vector<std::vector<const BrdfModel*>>& rows, int px,
                              const SphereLighting& light = {});

// Linear → sRGB-encoded 8-bit-ready values in [0,1] (clamped), for write_png.
io::Volume encode_srgb(const io::Volume& linear);

}  // namespace msh::bsdf
