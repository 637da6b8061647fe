// A height map as real micro-geometry, for the ground truth and for baking micro-occlusion.
// Grid space: vertex (i, j) sits at (i, j, z_ij) with z_ij = (h_ij − 1) · depth, i.e. one unit = one texel,
// vertex (i, j) = centre of texel (i, j), the highest possible point at z = 0; the map wraps. Each grid cell
// is two triangles (ij, i+1 j, i+1 j+1) and (ij, i+1 j+1, i j+1): a piecewise-linear surface at texel
// resolution.
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/render/scene.h>

#include <cstdint>
#include <vector>

namespace msh::render {

// What intersect() calls did, summed (for tests and benchmarks): cells whose triangles were tested, and
// blocks of the max pyramid (at any level, single cells included) passed over without a test, with the
// cells the ray visited in them; blocks_jumped: the blocks
// (larger than 64 × 64 cells) whose exit was computed rather than walked cell by cell.
struct HeightFieldTraversal {
  uint64_t cells_tested = 0, blocks_skipped = 0, cells_skipped = 0, blocks_jumped = 0;
};

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
  //
  // Maximum-mipmap traversal (Tevs, Ihrke & Seidel 2008): whole blocks of cells the ray passes above are
  // skipped. The answer (hit or miss, t, normal) is bit-identical to intersect_dda's: the same cells are
  // tested with the same triangle tests and acceptance windows, and the skipped stretches advance the DDA's
  // accumulated crossing times exactly as its repeated additions would (see heightfield.cpp).
  bool intersect(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Vec2f lo, Vec2f hi, float* t_hit,
                 Vec3f* ng, HeightFieldTraversal* trace = nullptr) const;
  // The reference intersect() is tested against: slab clip, then a plain 2D DDA (Amanatides & Woo 1987) over
  // every grid cell, skipping a cell when the ray is above its four corners (+1e-4) and otherwise testing
  // its two triangles (Möller & Trumbore 1997), front faces only.
  bool intersect_dda(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Vec2f lo, Vec2f hi, float* t_hit,
                     Vec3f* ng) const;

  // The max pyramid: level 0 holds each cell's highest corner, level L the maximum over 2^L × 2^L cells.
  // It has levels() levels: while 2^L divides both sides (so the blocks tile the wrapped map exactly) and
  // the level has more than one node along some side; a side that is not divisible by 2 leaves level 0
  // only (the traversal is then a DDA over precomputed cell maxima).
  int levels() const { return int(max_.size()); }
  // Node (i, j) of level L (wraps; i, j in units of 2^L cells).
  float node_max(int level, int i, int j) const;

 private:
  int w_ = 0, h_ = 0;
  float zmin_ = 0, zmax_ = 0;
  std::vector<float> z_;
  std::vector<std::vector<float>> max_;  // max_[L]: (w >> L) × (h >> L) node maxima, row-major
};

namespace heightfield_detail {
// v after k repetitions of the float addition v += b (b > 0, round to nearest even, no excess precision),
// bit-identical to the loop but in O(binades crossed) steps: how intersect() advances the DDA's accumulated
// crossing times over a skipped block.
float repeat_add(float v, float b, uint32_t k);

// The DDA leaving a block: from the next crossing times tx, ty (steps dtx, dty > 0, inf along an axis the ray
// does not cross), nx x steps and ny y steps (>= 1) from the block's far sides, and the ray's end t1 — the
// steps taken kx, ky, the crossing times then, and the time it leaves (tend: the last cell's tnext) — or,
// when the ray ends first (ended), t1 and the steps taken before it ends. leave_block_walk takes the DDA's
// steps one by one; leave_block computes the same state bit for bit with repeat_add.
struct BlockExit {
  uint32_t kx, ky;
  float tx, ty, tend;
  bool ended;
};
BlockExit leave_block_walk(float tx, float ty, float dtx, float dty, uint32_t nx, uint32_t ny, float t1);
BlockExit leave_block(float tx, float ty, float dtx, float dty, uint32_t nx, uint32_t ny, float t1);
}  // namespace heightfield_detail

}  // namespace msh::render
