// Internals of the directional bake (directional_bake.cpp) that the research harness
// (tools/research/directional_study.cpp) shares with it. Not installed: the product's interface is
// include/microshadow/render/directional_bake.h.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/render/directional_bake.h>

#include <vector>

namespace msh::render::detail {

// n azimuths, uniform and offset half a step: (cos φ_k, sin φ_k), φ_k = 2π (k + ½) / n.
std::vector<Vec2f> uniform_azimuths(int n);

// The central-difference vertex normal of every fine texel (HeightField::vertex_normal), row-major.
std::vector<Vec3f> fine_normals(const Texture& height, float depth);

// The 10 horizon-moment channels of one texel from its horizon tangents along `dirs` (uniform azimuths).
void horizon_channels(const float* tan_h, const Vec3f& n, const std::vector<Vec2f>& dirs, float* out);

// Per-texel lit · (n · l)⁺ from the horizon tangent along l's azimuth (lit: tan e > tan_h).
float transport_texel(float tan_h, const Vec3f& n, const Vec3f& l);

// Weighted least-squares projection of a hemisphere function sampled on a direction grid onto the first
// nb poly2 functions: coefficients = P · f. The grid: the bake azimuths × ne elevations (uniform in e), the
// weight cos e (solid angle) / (eps + sin e)² (roughly relative error, so grazing lights count), times the
// azimuth's share of the circle relative to a uniform one (az_weight; empty = uniform azimuths).
struct LsqProjection {
  int nb = 0, ne = 0, na = 0;
  std::vector<Vec3f> dirs;  // [a · ne + j]
  std::vector<float> P;     // nb × dirs
  int damp = 0;  // > 0: basis × (1 − z)^damp, fitted to the residual f − n · l (see "resid-poly2")
  LsqProjection(int nb, const std::vector<Vec2f>& az, int ne, double eps = 0.1, int damp = 0,
                const std::vector<double>& az_weight = {});
};

// v stored as 8-bit UNORM between lo and hi (clamped) and decoded again.
float quantize8(float v, float lo, float hi);

}  // namespace msh::render::detail
