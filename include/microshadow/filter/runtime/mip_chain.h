// Roughness mip-chain builder for a normal + roughness texture pair (RTR4 §9.13.1): each mip level's
// roughness is widened by the normal variance of its footprint, with Toksvig (9.76, GGX mapping), variance
// mapping (slope variance, CLEAN-style isotropic) or LEAN (anisotropic α_x, α_y). Library code (src/filter/),
// threads with oneTBB; results are bit-identical whatever the thread count (each texel sums a fixed set in
// fixed order).
#pragma once

#include <microshadow/math/vec.h>

#include <string>
#include <vector>

namespace msh::filter {

enum class FilterMethod { Toksvig, Variance, Lean };
// "toksvig", "variance", "lean"; throws msh::InputError otherwise.
FilterMethod filter_method_from_name(const std::string& name);
std::string filter_method_name(FilterMethod m);

struct MipLevel {
  int width = 0, height = 0;
  int channels = 1;                 // 1 (perceptual roughness r) or 2 for Lean (r_x, r_y)
  std::vector<float> roughness;     // width*height*channels, row-major, x fastest
  std::vector<float> normal;        // width*height*3: the renormalized mean normal of the footprint
  double mean_normal_variance = 0;  // mean over texels of the per-axis slope variance of the footprint
};

// normals: width*height unit-ish tangent-space normals (renormalized; n_z ≤ 0 is clamped to a tiny positive
// value). roughness: width*height perceptual roughness in [0,1] (clamped), or a single value for a constant.
// Levels: 0 (the input resolution) down to 1×1 (each level halves, floor, min 1; odd sizes give the last
// texel a 3-wide footprint), or at most max_levels when > 0. Throws msh::InputError on size mismatch.
// ggx_variance_scale: the GGX α ↔ slope-variance convention k of variance_mapping.h (1 = Beckmann
// equivalence, 2 = Conty et al. 2019's σ² = 2α²); used by Variance and Lean (Toksvig uses the Walter et al.
// exponent mapping).
std::vector<MipLevel> build_roughness_mips(int width, int height, const std::vector<Vec3f>& normals,
                                           const std::vector<float>& roughness, FilterMethod method,
                                           int max_levels = 0, double ggx_variance_scale = 1.0);

}  // namespace msh::filter
