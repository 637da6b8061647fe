// Shadow-ray origin offset for smooth-shaded low-poly meshes: Hanika 2021, "Hacking the Shadow Terminator"
// (Ray Tracing Gems II, ch. 4); docs/theory.md §4.
//
// A flat triangle with interpolated vertex normals shades like a curved surface but shadows like a flat one:
// near the terminator the shadow ray leaves from the flat face and hits the neighbouring faces, giving the
// blocky "shadow terminator" pattern. Hanika moves the shadow-ray origin to an approximation of the smooth
// surface: p is projected onto the tangent plane of each vertex (p_i, n_i), only where p lies below that
// plane (convex parts; concave parts are left alone), and the projections are blended with the barycentrics:
//   p' = p + Σ b_i (p − p_i − min(0, (p − p_i)·n_i) n_i) = p − Σ b_i min(0, (p − p_i)·n_i) n_i
// (the two forms are equal for p = Σ b_i p_i; we evaluate the second, which does not add the intersection
// error of p twice). Use p' only as the origin of shadow (light) rays, never for shading.
#pragma once

#include <microshadow/math/vec.h>

#include <array>
#include <limits>

namespace msh::bump {

// Hanika 2021 shadow-ray origin (see above). p: the hit point; pos/nrm: the triangle's vertex positions and
// vertex (shading) normals, in the same order as the barycentrics bary = (b0, b1, b2), b0 + b1 + b2 = 1
// (Embree's (u, v) gives b = (1 − u − v, u, v)). Normals need not be unit length: the projection divides by
// |n_i|², so a zero or non-finite normal, or a non-finite distance, simply contributes no move. The move is
// along the vertex normals only, by Σ b_i max(0, −(p − p_i)·n̂_i) n̂_i: never below the tangent planes' side.
// Domain: finite p, positions; barycentrics in [0, 1] (values outside extrapolate, still finite).
template <class T>
Vec3<T> hanika2021_shadow_origin(const Vec3<T>& p, const std::array<Vec3<T>, 3>& pos,
                                 const std::array<Vec3<T>, 3>& nrm, const std::array<T, 3>& bary) {
  Vec3<T> out = p;
  for (int i = 0; i < 3; ++i) {
    const T n2 = dot(nrm[i], nrm[i]);
    if (!(n2 > T(0) && n2 <= std::numeric_limits<T>::max())) continue;
    const T d = dot(p - pos[i], nrm[i]) / n2;  // signed height of p above vertex i's tangent plane, × |n_i|⁻¹
    if (d < T(0)) out -= (bary[i] * d) * nrm[i];  // below the plane: lift onto it (weighted)
  }
  return out;
}

// Convenience overload for Embree-style (u, v): b = (1 − u − v, u, v).
template <class T>
Vec3<T> hanika2021_shadow_origin(const Vec3<T>& p, const std::array<Vec3<T>, 3>& pos,
                                 const std::array<Vec3<T>, 3>& nrm, T u, T v) {
  return hanika2021_shadow_origin(p, pos, nrm, std::array<T, 3>{T(1) - u - v, u, v});
}

}  // namespace msh::bump
