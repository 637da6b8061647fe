// A height map as real micro-geometry, for the ground truth and for baking micro-occlusion.
// Grid space: vertex (i, j) sits at (i, j, z_ij) with z_ij = (h_ij − 1) · depth, i.e. one unit = one texel,
// vertex (i, j) = centre of texel (i, j), the highest possible point at z = 0; the map wraps. Each grid cell
// is two triangles (ij, i+1 j, i+1 j+1) and (ij, i+1 j+1, i j+1): a piecewise-linear surface at texel
// resolution.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/render/scene.h>

namespace msh::render {

class HeightField {
 public:
  HeightField() = default;
  // depth_texels: depth of the full [0,1] height range in texel units.
  HeightField(const Texture& height, float depth_texels);

  int width() const { return w_; }
  int height() const { return h_; }
  float z(int i, int j) const;           // wraps
  float z_min() const { return zmin_; }  // lowest and highest vertex height
  float z_max() const { return zmax_; }
  // Smooth normal at grid point (x, y): bilinear blend of the central-difference vertex normals (what the
  // generated normal map stores at texel centres).
  Vec3f smooth_normal(float x, float y) const;
  Vec3f vertex_normal(int i, int j) const;

  // First front-face (upward-facing) intersection of o + t·d with the surface for t ∈ [tmin, tmax),
  // restricted to x ∈ [lo.x, hi.x], y ∈ [lo.y, hi.y] (the plane's extent in grid space). Grid-space ray (need
  // not be unit length). On a hit stores t and the geometric (triangle) normal.
  bool intersect(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Vec2f lo, Vec2f hi, float* t_hit,
                 Vec3f* ng) const;

 private:
  int w_ = 0, h_ = 0;
  float zmin_ = 0, zmax_ = 0;
  std::vector<float> z_;
};

}  // namespace msh::render
