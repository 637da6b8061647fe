// Anisotropic GGX roughness with an isotropic micro-shadowing term (the isotropic LUT, the ALU fit): one
// isotropic α from the roughness projected along l and along v. Engine-facing, header-only.
//
// Both Smith-GGX quantities that depend on the roughness, the masking G1(w) and the VNDF of v, depend on αx,
// αy only through the projected roughness along the azimuth of their direction (stretch invariance: Heitz
// 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs"; Zurita 2026, "Improving
// Direct Lighting Material Occlusion - Part 2", ProjectRoughnessGGX):
//   α(w)² = αx² cos²φ_w + αy² sin²φ_w                                (Real-Time Rendering 4th ed., eq. 9.51)
// The isotropic table is indexed with one α, so the two projections are combined; the combination, its
// as-used error against the exact anisotropic term and the domain of the measurement are in
// docs/micro-shadowing.md ("Other microsurface profiles and anisotropy").
//
// Conventions: shading frame n = +z, tangent = x (αx), bitangent = y (αy); v, l unit. At the pole (w = n) the
// azimuth is undefined and α(w) = sqrt((αx² + αy²)/2), the mean of α(φ)² over φ. Domain: αx, αy ≥ 0 (values
// below GGX's kMinAlpha are clamped to it), finite; NaN α gives NaN (as GGX); the result is finite for any
// finite unit v, l.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>

#include <cmath>

namespace msh::micro_shadowing {

// How the two projections are combined into the one α of an isotropic term.
enum class ProjectedAlphaCombine {
  View,       // α(v): the roughness of the VNDF that is sampled
  Light,      // α(l)
  Geometric,  // sqrt(α(v) α(l))
  Rms,        // sqrt((α(v)² + α(l)²)/2)
};

// α(w) of anisotropic GGX along the azimuth of w (RTR4 9.51; Zurita 2026b ProjectRoughnessGGX).
template <class T>
T projected_alpha(T alpha_x, T alpha_y, const Vec3<T>& w) {
  return GGX<T>(alpha_x, alpha_y).projected_alpha(w);
}

// The isotropic α for an isotropic micro-shadowing term at anisotropic (αx, αy), from α(v) and α(l).
// Default: the root mean square, the measured best of the four against the exact anisotropic term
// (docs/micro-shadowing.md).
template <class T>
T micro_shadowing_isotropic_alpha(T alpha_x, T alpha_y, const Vec3<T>& v, const Vec3<T>& l,
                                  ProjectedAlphaCombine how = ProjectedAlphaCombine::Rms) {
  const T av = projected_alpha(alpha_x, alpha_y, v), al = projected_alpha(alpha_x, alpha_y, l);
  switch (how) {
    case ProjectedAlphaCombine::View:
      return av;
    case ProjectedAlphaCombine::Light:
      return al;
    case ProjectedAlphaCombine::Geometric:
      return std::sqrt(av * al);
    case ProjectedAlphaCombine::Rms:
      break;
  }
  return std::sqrt(T(0.5) * (av * av + al * al));
}

// The same as a perceptual roughness r = sqrt(α) (α = r², docs/theory.md §1), what the LUT samplers take.
template <class T>
T micro_shadowing_isotropic_roughness(T alpha_x, T alpha_y, const Vec3<T>& v, const Vec3<T>& l,
                                      ProjectedAlphaCombine how = ProjectedAlphaCombine::Rms) {
  return std::sqrt(micro_shadowing_isotropic_alpha(alpha_x, alpha_y, v, l, how));
}

}  // namespace msh::micro_shadowing
