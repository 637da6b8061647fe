// Height-field ray casting: slab clip, 2D DDA over grid cells (Amanatides & Woo 1987), two exact ray-triangle
// tests per cell (Möller & Trumbore 1997).
#include <microshadow/render/heightfield.h>

#include <cmath>
#include <limits>

namespace msh::render {

HeightField::HeightField(const Texture& height, float depth)
    : w_(height.width()), h_(height.height()), z_(std::size_t(w_) * h_) {
  zmin_ = std::numeric_limits<float>::max(), zmax_ = -zmin_;
  for (int j = 0; j < h_; ++j)
    for (int i = 0; i < w_; ++i) {
      const float v = (height.at(i, j, 0) - 1.0f) * depth;
      z_[std::size_t(j) * w_ + i] = v;
      zmin_ = std::min(zmin_, v), zmax_ = std::max(zmax_, v);
    }
}

float HeightField::z(int i, int j) const {
  i %= w_, j %= h_;
  if (i < 0) i += w_;
  if (j < 0) j += h_;
  return z_[std::size_t(j) * w_ + i];
}

Vec3f HeightField::vertex_normal(int i, int j) const {
  const float dx = 0.5f * (z(i + 1, j) - z(i - 1, j)), dy = 0.5f * (z(i, j + 1) - z(i, j - 1));
  return normalize(Vec3f(-dx, -dy, 1.0f));
}

Vec3f HeightField::smooth_normal(float x, float y) const {
  const float fx = std::floor(x), fy = std::floor(y), tx = x - fx, ty = y - fy;
  const int i = int(fx), j = int(fy);
  const Vec3f n = (1 - ty) * ((1 - tx) * vertex_normal(i, j) + tx * vertex_normal(i + 1, j)) +
                  ty * ((1 - tx) * vertex_normal(i, j + 1) + tx * vertex_normal(i + 1, j + 1));
  return normalize(n);
}

namespace {
// Möller–Trumbore; returns t or +inf.
inline float tri_hit(const Vec3f& o, const Vec3f& d, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  const Vec3f e1 = b - a, e2 = c - a, pv = cross(d, e2);
  const float det = dot(e1, pv);
  if (std::abs(det) < 1e-12f) return std::numeric_limits<float>::infinity();
  const float inv = 1.0f / det;
  const Vec3f tv = o - a;
  const float u = dot(tv, pv) * inv;
  if (u < -1e-6f || u > 1 + 1e-6f) return std::numeric_limits<float>::infinity();
  const Vec3f qv = cross(tv, e1);
  const float v = dot(d, qv) * inv;
  if (v < -1e-6f || u + v > 1 + 1e-6f) return std::numeric_limits<float>::infinity();
  return dot(e2, qv) * inv;
}
}  // namespace

bool HeightField::intersect(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Vec2f lo, Vec2f hi,
                            float* t_hit, Vec3f* ng) const {
  if (w_ == 0) return false;
  // Clip to the slab [zmin, zmax] and the xy extent.
  float t0 = tmin, t1 = tmax;
  auto clip = [&](float oc, float dc, float a, float b) {
    if (dc == 0.0f) return oc >= a && oc <= b;
    float ta = (a - oc) / dc, tb = (b - oc) / dc;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    return t0 <= t1;
  };
  if (!clip(o.z, d.z, zmin_ - 1e-4f, zmax_ + 1e-4f) || !clip(o.x, d.x, lo.x, hi.x) ||
      !clip(o.y, d.y, lo.y, hi.y))
    return false;
  const Vec3f p0 = o + d * t0;
  int i = int(std::floor(p0.x)), j = int(std::floor(p0.y));
  const int si = d.x > 0 ? 1 : -1, sj = d.y > 0 ? 1 : -1;
  const float inf = std::numeric_limits<float>::infinity();
  const float dtx = d.x != 0 ? std::abs(1.0f / d.x) : inf, dty = d.y != 0 ? std::abs(1.0f / d.y) : inf;
  float tx = d.x != 0 ? ((d.x > 0 ? float(i + 1) : float(i)) - o.x) / d.x : inf;
  float ty = d.y != 0 ? ((d.y > 0 ? float(j + 1) : float(j)) - o.y) / d.y : inf;
  float tcell = t0;
  for (int guard = 0; guard < 1 << 20; ++guard) {
    const float tnext = std::min(std::min(tx, ty), t1);
    const float z00 = z(i, j), z10 = z(i + 1, j), z01 = z(i, j + 1), z11 = z(i + 1, j + 1);
    // Skip cells the ray passes entirely above (cheap bound test).
    const float za = o.z + d.z * tcell, zb = o.z + d.z * tnext;
    if (std::min(za, zb) <= std::max(std::max(z00, z10), std::max(z01, z11)) + 1e-4f) {
      const Vec3f A(float(i), float(j), z00), B(float(i + 1), float(j), z10),
          C(float(i + 1), float(j + 1), z11), D(float(i), float(j + 1), z01);
      // Front faces only (normals point up, +z): a ray above the surface can only enter through a front face,
      // and a ray leaving the surface from a point on it never re-hits its own triangle, so no origin offset
      // is needed (an offset lets rays from the foot of a steep slope leak through it).
      const Vec3f n1 = cross(B - A, C - A), n2 = cross(C - A, D - A);
      const float ta = dot(d, n1) < 0 ? tri_hit(o, d, A, B, C) : inf;
      const float tb = dot(d, n2) < 0 ? tri_hit(o, d, A, C, D) : inf;
      const float eps = 1e-4f * (tnext - tcell + 1e-3f);
      float best = inf;
      Vec3f n;
      if (ta >= tmin && ta >= tcell - eps && ta <= tnext + eps && ta < best) best = ta, n = n1;
      if (tb >= tmin && tb >= tcell - eps && tb <= tnext + eps && tb < best) best = tb, n = n2;
      if (best < inf && best < tmax) {
        *t_hit = best;
        if (ng) *ng = normalize(n);
        return true;
      }
    }
    if (tnext >= t1) break;
    tcell = tnext;
    if (tx < ty) {
      i += si, tx += dtx;
    } else {
      j += sj, ty += dty;
    }
  }
  return false;
}

}  // namespace msh::render
