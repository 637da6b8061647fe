// Height-field ray casting: slab clip, 2D DDA over grid cells (Amanatides & Woo 1987), two exact ray-triangle
// tests per cell (Möller & Trumbore 1997); intersect() skips blocks of cells through a max pyramid (Tevs,
// Ihrke & Seidel 2008, "Maximum mipmaps for fast, accurate, and scalable dynamic height field rendering").
//
// Why intersect() returns intersect_dda()'s answer bit for bit. The DDA's answer depends on the sequence of
// cells it visits and on each cell's interval [tcell, tnext], both of which come from the accumulated
// crossing times tx += dtx, ty += dty (not from exact products), and on which cells it tests. intersect()
// reproduces that sequence exactly:
//  - A skipped block is left in the state the DDA would reach cell by cell: the DDA merges the x-crossing
//    times X(k) (k additions of dtx to tx) and the y-crossing times Y(m), taking the x step when X < Y; so
//    it leaves a block through x iff the time of its last x crossing inside the block is < that of its last
//    y crossing, and the other axis has then taken every crossing <= (< for x) that time. X(k) is computed
//    without k additions by repeat_add below (exact: within one binade a float sum moves by a constant
//    number of ulps), or for small blocks by the same additions as the DDA.
//  - A block is skipped only when every cell of it would be skipped by the DDA's own test: the ray's height
//    o.z + d.z·t (computed as the DDA computes it, monotone in t) at the block's first tcell and last tnext
//    is above the block's maximum + 1e-3 >= every cell's highest corner + 1e-4. A rising ray (d.z >= 0) needs
//    only the first.
//  - Cells that are not skipped run the same code as the DDA (test_cell), with the same tcell, tnext.
//  - The DDA's guard (at most 2^20 cells) is counted over skipped cells too.
#include <microshadow/render/heightfield.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>

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
  if (w_ == 0 || h_ == 0) return;
  // Level 0: the highest corner of each cell (the DDA's bound), then 2 × 2 maxima while both sides halve.
  std::vector<float> m0(z_.size());
  for (int j = 0; j < h_; ++j)
    for (int i = 0; i < w_; ++i)
      m0[std::size_t(j) * w_ + i] =
          std::max(std::max(z(i, j), z(i + 1, j)), std::max(z(i, j + 1), z(i + 1, j + 1)));
  max_.push_back(std::move(m0));
  for (int l = 1; w_ % (1 << l) == 0 && h_ % (1 << l) == 0 && (w_ >> l) * (h_ >> l) > 1; ++l) {
    const int w = w_ >> l, h = h_ >> l, wp = w_ >> (l - 1);
    const std::vector<float>& p = max_.back();
    std::vector<float> m(std::size_t(w) * h);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const std::size_t a = std::size_t(2 * j) * wp + 2 * i, b = a + wp;
        m[std::size_t(j) * w + i] = std::max(std::max(p[a], p[a + 1]), std::max(p[b], p[b + 1]));
      }
    max_.push_back(std::move(m));
  }
}

float HeightField::z(int i, int j) const {
  i %= w_, j %= h_;
  if (i < 0) i += w_;
  if (j < 0) j += h_;
  return z_[std::size_t(j) * w_ + i];
}

float HeightField::node_max(int level, int i, int j) const {
  const int w = w_ >> level, h = h_ >> level;
  i %= w, j %= h;
  if (i < 0) i += w;
  if (j < 0) j += h;
  return max_[std::size_t(level)][std::size_t(j) * w + i];
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
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr uint32_t kGuard = 1u << 20;  // the DDA gives up after this many cells

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

// The two triangles of cell (i, j) (corner heights z00 … z11), accepting a hit in [tmin, tmax) within the
// cell's interval [tcell, tnext] widened by a relative 1e-4.
inline bool test_cell(const Vec3f& o, const Vec3f& d, int i, int j, float z00, float z10, float z01,
                      float z11, float tmin, float tmax, float tcell, float tnext, float* t_hit, Vec3f* ng) {
  const Vec3f A(float(i), float(j), z00), B(float(i + 1), float(j), z10), C(float(i + 1), float(j + 1), z11),
      D(float(i), float(j + 1), z01);
  // Front faces only (normals point up, +z): a ray above the surface can only enter through a front face,
  // and a ray leaving the surface from a point on it never re-hits its own triangle, so no origin offset
  // is needed (an offset lets rays from the foot of a steep slope leak through it).
  const Vec3f n1 = cross(B - A, C - A), n2 = cross(C - A, D - A);
  const float ta = dot(d, n1) < 0 ? tri_hit(o, d, A, B, C) : kInf;
  const float tb = dot(d, n2) < 0 ? tri_hit(o, d, A, C, D) : kInf;
  const float eps = 1e-4f * (tnext - tcell + 1e-3f);
  float best = kInf;
  Vec3f n;
  if (ta >= tmin && ta >= tcell - eps && ta <= tnext + eps && ta < best) best = ta, n = n1;
  if (tb >= tmin && tb >= tcell - eps && tb <= tnext + eps && tb < best) best = tb, n = n2;
  if (best < kInf && best < tmax) {
    *t_hit = best;
    if (ng) *ng = normalize(n);
    return true;
  }
  return false;
}

}  // namespace

// v after k repetitions of the float addition v += b (b > 0), without the k additions. Inside one binade
// [2^(E−127), 2^(E−126)) every float is a multiple of its ulp u = 2^(E−150), so v + b = (v/u + b/u)·u rounds
// to v + c with c = b rounded to a multiple of u — the same c at every step — unless b/u ends in exactly ½,
// where the tie goes to the even multiple: then the first step may add the other neighbour, and every later
// one adds the even one. So: as many steps of c as keep each step's exact sum at least 2u below the binade's
// end (checked in double, whose rounding there is far below u), plain additions across the binade's end,
// and so on. Non-normal or non-positive v, infinite b, few steps: plain additions.
float heightfield_detail::repeat_add(float v, float b, uint32_t k) {
  const auto exponent = [](float x) { return int(std::bit_cast<uint32_t>(x) >> 23); };  // E of x > 0
  const auto pow2 = [](int e) { return std::bit_cast<double>(uint64_t(e + 1023) << 52); };
  while (k > 0) {
    if (!std::isfinite(v)) return v + b;  // stays inf (or NaN) whatever the remaining steps
    if (k < 4 || !(v >= FLT_MIN) || !(b < kInf)) {
      v += b, --k;
      continue;
    }
    const int e = exponent(v);
    const double u = pow2(e - 150), top = pow2(e - 126);
    if (!(double(b) < top)) {  // one step leaves the binade
      v += b, --k;
      continue;
    }
    const double q = double(b) * pow2(150 - e);  // b / u, exact, < 2^24
    const int64_t m = int64_t(q);                // floor
    const double f = q - double(m);
    double c = double(f < 0.5 ? m : m + 1) * u;
    if (f == 0.5) {
      const float a = v + b;
      --k;
      if (exponent(a) != e) {
        v = a;
        continue;
      }
      v = a;  // an even multiple of u now
      c = double(m % 2 == 0 ? m : m + 1) * u;
    }
    if (c == 0) return v;  // b below half an ulp: v no longer moves
    // Steps s = 0 … S−1 start at v + s·c and need v + s·c + b ≤ top − 2u.
    const double room = top - 2 * u - double(b) - double(v);
    if (double(k - 1) * c <= room) return float(double(v) + double(k) * c);
    // One less than the bound (the quotient may round up); truncation is the floor here, or 0 when negative.
    const int64_t steps = int64_t(room / c);
    if (steps < 1) {  // at the binade's end: plain additions into the next binade
      do v += b, --k;
      while (k > 0 && exponent(v) == e);
      continue;
    }
    v = float(double(v) + double(steps) * c), k -= uint32_t(steps);
  }
  return v;
}

namespace {
using heightfield_detail::repeat_add;

// The first m ∈ [0, nmax] at which the sequence X(m) = repeat_add(x0, b, m) is past t (X(m) > t, or ≥ t when
// strict), given that X(nmax) is; returns m and X(m).
std::pair<uint32_t, float> first_past(float x0, float b, uint32_t nmax, float t, bool strict) {
  const auto past = [&](float x) { return strict ? x >= t : x > t; };
  if (past(x0)) return {0, x0};
  uint32_t m = 0;
  float x = x0;
  if (nmax > 16) {
    // Start a little before the estimate: the accumulated rounding is at most m·ulp(t)/2 ≤ m·t·2^−24.
    const double est = (double(t) - double(x0)) / double(b);
    const double slack = 2 + est * std::abs(double(t)) / double(b) * 0x1p-23;
    const double m0 = std::min(est - slack, double(nmax));
    if (m0 >= 1) {
      const float xm = repeat_add(x0, b, uint32_t(m0));
      if (!past(xm)) m = uint32_t(m0), x = xm;  // else (never seen) walk from the start
    }
  }
  while (m < nmax && !past(x)) x += b, ++m;
  return {m, x};
}
}  // namespace

namespace {
// The DDA's steps through a block, as intersect_dda takes them. (Selecting the step without the branch on
// tx < ty was not faster.)
inline heightfield_detail::BlockExit walk_block(float tx, float ty, float dtx, float dty, uint32_t nx,
                                                uint32_t ny, float t1) {
  heightfield_detail::BlockExit e{0, 0, tx, ty, 0, false};
  for (;;) {
    const float tn = std::min(std::min(e.tx, e.ty), t1);
    if (tn >= t1) {
      e.tend = t1, e.ended = true;
      return e;
    }
    e.tend = tn;
    if (e.tx < e.ty) {
      e.tx += dtx;
      if (++e.kx == nx) return e;
    } else {
      e.ty += dty;
      if (++e.ky == ny) return e;
    }
  }
}
}  // namespace

heightfield_detail::BlockExit heightfield_detail::leave_block_walk(float tx, float ty, float dtx, float dty,
                                                                   uint32_t nx, uint32_t ny, float t1) {
  return walk_block(tx, ty, dtx, dty, nx, ny, t1);
}

heightfield_detail::BlockExit heightfield_detail::leave_block(float tx, float ty, float dtx, float dty,
                                                              uint32_t nx, uint32_t ny, float t1) {
  BlockExit e{0, 0, tx, ty, 0, false};
  const float xe = repeat_add(tx, dtx, nx - 1), ye = repeat_add(ty, dty, ny - 1);
  if (std::min(xe, ye) >= t1) {  // every crossing before t1 is taken
    e.tend = t1, e.ended = true;
    std::tie(e.kx, e.tx) = first_past(tx, dtx, nx - 1, t1, true);
    std::tie(e.ky, e.ty) = first_past(ty, dty, ny - 1, t1, true);
  } else if (xe < ye) {  // leaves through x at xe; y has taken every crossing <= xe
    e.tend = xe, e.kx = nx, e.tx = xe + dtx;
    const auto [k, t] = first_past(ty, dty, ny - 1, xe, false);
    e.ky = k, e.ty = t;
  } else {  // leaves through y at ye; x has taken every crossing < ye
    e.tend = ye, e.ky = ny, e.ty = ye + dty;
    const auto [k, t] = first_past(tx, dtx, nx - 1, ye, true);
    e.kx = k, e.tx = t;
  }
  return e;
}

namespace {
// The ray clipped to the slab [zlo, zhi] (widened by 1e-4) and the xy extent [lo, hi] (t0, t1), and the DDA's
// start (Amanatides & Woo 1987): the cell holding the entry point, the steps, the crossing times of the next
// x and y grid lines and their increments. false: the ray misses. Shared by both traversals, so that they
// start from the same bits.
struct DdaStart {
  float t0, t1;
  int i, j, si, sj;
  float dtx, dty, tx, ty;
};
bool dda_start(const Vec3f& o, const Vec3f& d, float tmin, float tmax, float zlo, float zhi, Vec2f lo,
               Vec2f hi, DdaStart& s) {
  float t0 = tmin, t1 = tmax;
  auto clip = [&](float oc, float dc, float a, float b) {
    if (dc == 0.0f) return oc >= a && oc <= b;
    float ta = (a - oc) / dc, tb = (b - oc) / dc;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    return t0 <= t1;
  };
  if (!clip(o.z, d.z, zlo - 1e-4f, zhi + 1e-4f) || !clip(o.x, d.x, lo.x, hi.x) || !clip(o.y, d.y, lo.y, hi.y))
    return false;
  const float inf = kInf;
  const Vec3f p0 = o + d * t0;
  s.t0 = t0, s.t1 = t1;
  s.i = int(std::floor(p0.x)), s.j = int(std::floor(p0.y));
  s.si = d.x > 0 ? 1 : -1, s.sj = d.y > 0 ? 1 : -1;
  s.dtx = d.x != 0 ? std::abs(1.0f / d.x) : inf, s.dty = d.y != 0 ? std::abs(1.0f / d.y) : inf;
  s.tx = d.x != 0 ? ((d.x > 0 ? float(s.i + 1) : float(s.i)) - o.x) / d.x : inf;
  s.ty = d.y != 0 ? ((d.y > 0 ? float(s.j + 1) : float(s.j)) - o.y) / d.y : inf;
  return true;
}

}  // namespace

bool HeightField::intersect_dda(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Vec2f lo, Vec2f hi,
                                float* t_hit, Vec3f* ng) const {
  DdaStart st;
  if (w_ == 0 || !dda_start(o, d, tmin, tmax, zmin_, zmax_, lo, hi, st)) return false;
  auto [tcell, t1, i, j, si, sj, dtx, dty, tx, ty] = st;
  for (uint32_t guard = 0; guard < kGuard; ++guard) {
    const float tnext = std::min(std::min(tx, ty), t1);
    const float z00 = z(i, j), z10 = z(i + 1, j), z01 = z(i, j + 1), z11 = z(i + 1, j + 1);
    // Skip cells the ray passes entirely above (cheap bound test).
    const float za = o.z + d.z * tcell, zb = o.z + d.z * tnext;
    if (std::min(za, zb) <= std::max(std::max(z00, z10), std::max(z01, z11)) + 1e-4f &&
        test_cell(o, d, i, j, z00, z10, z01, z11, tmin, tmax, tcell, tnext, t_hit, ng))
      return true;
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

bool HeightField::intersect(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Vec2f lo, Vec2f hi,
                            float* t_hit, Vec3f* ng, HeightFieldTraversal* trace) const {
  DdaStart st;
  if (w_ == 0 || !dda_start(o, d, tmin, tmax, zmin_, zmax_, lo, hi, st)) return false;
  auto [tcell, t1, i, j, si, sj, dtx, dty, tx, ty] = st;

  const int top = levels() - 1;
  // Wrapped cell index (the remainder of a block's index is then the wrapped index >> level: every level's
  // block size divides the sides).
  const bool pow2 = (w_ & (w_ - 1)) == 0 && (h_ & (h_ - 1)) == 0;
  const auto wrap = [pow2](int a, int n) {
    if (pow2) return a & (n - 1);
    a %= n;
    return a < 0 ? a + n : a;
  };
  const float* cell_max = max_[0].data();
  // Blocks up to kWalkLevel (64 × 64 cells) are left by the DDA's own additions (no memory access, a few
  // instructions per cell); larger ones by repeat_add (a few hundred instructions whatever the size). On the
  // study's rock at 2048², shadow rays at 5–45° took the same time with the threshold anywhere from 6 to 9
  // and 10–35 % longer at 2–4.
  constexpr int kWalkLevel = 6;
  constexpr float kMargin = 1e-3f;  // > the cells' 1e-4
  uint32_t cells = 0;               // cells visited, tested or skipped (the DDA's guard)
  int level = 0;
  for (;;) {
    if (level == 0) {
      // One cell, exactly as intersect_dda.
      const float tnext = std::min(std::min(tx, ty), t1);
      const int iw = wrap(i, w_), jw = wrap(j, h_);
      const float za = o.z + d.z * tcell, zb = o.z + d.z * tnext;
      if (std::min(za, zb) <= cell_max[std::size_t(jw) * w_ + iw] + 1e-4f) {
        if (trace) ++trace->cells_tested;
        const float* r0 = z_.data() + std::size_t(jw) * w_;
        const float* r1 = z_.data() + std::size_t(jw + 1 == h_ ? 0 : jw + 1) * w_;
        const int iw1 = iw + 1 == w_ ? 0 : iw + 1;
        if (test_cell(o, d, i, j, r0[iw], r0[iw1], r1[iw], r1[iw1], tmin, tmax, tcell, tnext, t_hit, ng))
          return true;
      } else if (trace) {
        ++trace->blocks_skipped, ++trace->cells_skipped;
      }
      if (++cells >= kGuard || tnext >= t1) return false;
      tcell = tnext;
      if (tx < ty) {
        i += si, tx += dtx;
      } else {
        j += sj, ty += dty;
      }
      level = std::min(1, top);
      continue;
    }
    // The block of 2^level × 2^level cells holding (i, j): the ray enters it (or is already in it) at tcell.
    const float m = max_[std::size_t(level)][std::size_t(wrap(j, h_) >> level) * std::size_t(w_ >> level) +
                                             std::size_t(wrap(i, w_) >> level)] +
                    kMargin;
    const float z_in = o.z + d.z * tcell;
    if (!(z_in > m)) {
      --level;
      continue;
    }
    const int bi = (i >> level) << level, bj = (j >> level) << level, size = 1 << level;
    if (d.z < 0) {
      // A falling ray is lowest where it leaves the block. Where the line leaves the block's square, in
      // exact-product arithmetic, tells (up to rounding) whether it can pass: descending is always safe, so
      // blocks it clearly cannot pass are not walked.
      const float ex = d.x != 0 ? (float(si > 0 ? bi + size : bi) - o.x) / d.x : kInf;
      const float ey = d.y != 0 ? (float(sj > 0 ? bj + size : bj) - o.y) / d.y : kInf;
      if (!(o.z + d.z * std::min(std::min(ex, ey), t1) > m)) {
        --level;
        continue;
      }
    }
    // Steps to leave the block along x and along y.
    const uint32_t nx = uint32_t(si > 0 ? bi + size - i : i - bi + 1);
    const uint32_t ny = uint32_t(sj > 0 ? bj + size - j : j - bj + 1);
    if (trace && level > kWalkLevel) ++trace->blocks_jumped;
    const heightfield_detail::BlockExit e =
        level <= kWalkLevel ? walk_block(tx, ty, dtx, dty, nx, ny, t1)
                            : heightfield_detail::leave_block(tx, ty, dtx, dty, nx, ny, t1);
    const uint32_t kx = e.kx, ky = e.ky;
    const float tend = e.tend;
    const bool ended = e.ended;
    const float ntx = e.tx, nty = e.ty;
    // A falling ray is lowest where it leaves the block.
    if (d.z < 0 && !(o.z + d.z * tend > m)) {
      --level;
      continue;
    }
    if (trace) ++trace->blocks_skipped, trace->cells_skipped += kx + ky + (ended ? 1 : 0);
    if (ended) return false;
    cells += kx + ky;
    if (cells >= kGuard) return false;
    i += si * int(kx), j += sj * int(ky), tx = ntx, ty = nty, tcell = tend;
    level = std::min(level + 1, top);
  }
}

}  // namespace msh::render
