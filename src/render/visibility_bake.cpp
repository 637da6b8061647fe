// Micro-occlusion bake by exact horizons (see bake_visibility in render/texture_gen.h).
//
// For the piecewise-linear height field (two triangles per cell, vertex (i, j) at height z_ij), a ray from
// the vertex p = (i, j, z_ij) in the direction of azimuth φ and elevation e is blocked iff the surface
// profile Δz(s) = z(p + s·(cos φ, sin φ)) − z_ij along the horizontal line rises above the ray, Δz(s) ≥ s·tan
// e, at a horizontal distance s the ray reaches within its length R (s² + (s tan e)² ≤ R²). The blocked
// elevations form an interval [0, H(φ)) with tan H = max_s min(Δz(s), √(R² − s²)) / s, so the cosine-weighted
// (projected-solid-angle) visibility about +z is V = (1/2π) ∫ cos² H₊(φ) dφ: the elevation integral is
// exact, only the azimuth is sampled. Δz is linear between the profile's breakpoints (cell edges and cell
// diagonals), where the maximum of min(Δz, √(R² − s²))/s lies at a breakpoint or where the line crosses the
// circle, so H is exact too. The first segment from s = 0 has tan H = its slope: the local test whether a
// direction enters the solid at the start point, so convex points are not darkened by the triangles they
// sit on.
//
// Speed: with a finite ray length (the bake's default, 8 % of the map) the breakpoints a walk meets along a
// direction are the same from every vertex, so they are listed once per direction (a ray profile) and
// vertices scan their heights there, 8 neighbours of a row in lockstep ("Profile scans" below; exact, no
// tolerance). The walks remain for unlimited rays: cells are skipped when none of their vertices rises above
// the current horizon (by more than a tolerance of 1e-4 on tan² H, so on V), and the walk stops where
// nothing of the field can (s > (z_max − z_ij) / tan H) or the ray length ends. (A maximum mip pyramid, Tevs
// et al. 2008, was measured slower for the walks: the cells near the horizon line dominate, and its block
// tests skip nothing more.)
//
// On lattice azimuths (bake_horizon_tangents_lattice) the same exact horizons come from one convex-hull sweep
// per line of vertices, at a cost independent of the walk length (see "Lattice sweeps" below).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>
#include <microshadow/render/texture_gen.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <vector>

namespace msh::render {

namespace {

// Tolerance on tan² H: cells and the rest of a walk are skipped when they can raise tan² H by at most this,
// which changes cos² H = 1/(1 + tan² H), i.e. V, by at most kTan2Tolerance (V is never lowered by it). It
// also bounds unlimited walks: beyond s = (z_max − z_ij)/√kTan2Tolerance nothing can matter.
constexpr float kTan2Tolerance = 1e-4f;
// The triangulated surface in a cell with corner heights a = (0, 0), b = (1, 0), c = (1, 1), d = (0, 1) at
// fractions (fx, fy) ∈ [0, 1]²: triangle (a, b, c) where fx ≥ fy, (a, c, d) otherwise; both agree on the
// diagonal. The walks and the sweeps read the surface through this one definition.
inline float cell_height(float a, float b, float c, float d, float fx, float fy) {
  return fx >= fy ? a + fx * (b - a) + fy * (c - b) : a + fy * (d - a) + fx * (c - d);
}

// Heights in texel units, stored with one extra column and row (the wrapped first ones) so a cell's four
// vertices are at p, p + 1, p + w + 1, p + w + 2.
struct Heights {
  int w = 0, h = 0;
  float zmax = 0;
  std::vector<float> z;  // (w + 1) × (h + 1)

  Heights(const Texture& height, float depth) : w(height.width()), h(height.height()) {
    z.resize(std::size_t(w + 1) * (h + 1));
    zmax = -std::numeric_limits<float>::max();
    for (int j = 0; j <= h; ++j)
      for (int i = 0; i <= w; ++i) {
        const float v = (height.at(i % w, j % h, 0) - 1.0f) * depth;
        z[std::size_t(j) * (w + 1) + i] = v;
        zmax = std::max(zmax, v);
      }
  }
  const float* vertex(int i, int j) const { return &z[std::size_t(j) * (w + 1) + i]; }  // i, j in range
};

// The input checks every horizon bake makes, with its name in the message.
void check_depth(const char* fn, float depth) {
  if (!(depth >= 0) || !std::isfinite(depth))
    throw InputError(fmt::format("{}: depth must be finite and >= 0, got {}", fn, depth));
}
void check_unit_directions(const char* fn, const std::vector<Vec2f>& dirs) {
  for (const Vec2f& d : dirs)
    if (!(std::abs(d.x * d.x + d.y * d.y - 1) < 1e-4f))
      throw InputError(fmt::format("{}: azimuth directions must be unit vectors", fn));
}
// The projected-solid-angle weight of one azimuth whose horizon has tangent T: cos² H.
inline double cos2_horizon(float T) { return 1.0 / (1.0 + double(T) * double(T)); }

// A linear piece of the profile from (s_l, z_l) to (s_r, z_r) against the horizon so far, tan H = T: the
// larger of T and the piece's largest min(Δz, √(R² − s²))/s (R = the ray length, limited; unlimited: Δz/s).
// Only the right end can raise T (the left end was the previous piece's right end, or lies on a skipped
// block, already below the gate), except at the start, where Δz/s → the piece's slope, and where the piece
// leaves the disc of radius R between its ends. The walks and the profile scans read pieces through this one
// rule.
inline float piece_raise(float T, float s_l, float z_l, float s_r, float z_r, float R, bool limited) {
  if (!(s_r > s_l)) return T;
  const bool start = s_l < 1e-6f;
  if (!(z_r > s_r * T) && !start) return T;
  if (limited && s_r > R) {  // clip at the ray length
    if (s_l >= R) return T;
    z_r = z_l + (z_r - z_l) * ((R - s_l) / (s_r - s_l));
    s_r = R;
  }
  const float slope = (z_r - z_l) / (s_r - s_l);
  if (start) T = std::max(T, slope);
  if (!limited) return std::max(T, z_r / s_r);
  const float cr = std::sqrt(std::max(R * R - s_r * s_r, 0.0f));
  T = std::max(T, std::min(z_r, cr) / s_r);
  if (z_r > cr && (z_l < 0 || z_l * z_l < R * R - s_l * s_l)) {
    // The piece leaves the disc between its ends: max at the crossing a + m s = √(R² − s²).
    const double m = slope, a0 = double(z_l) - m * s_l, R2 = double(R) * R;
    const double disc = R2 * (1 + m * m) - a0 * a0;
    if (disc >= 0) {
      const double r = std::sqrt(disc);
      for (double s : {(-a0 * m + r) / (1 + m * m), (-a0 * m - r) / (1 + m * m)})
        if (s >= s_l && s <= s_r && s > 0) T = std::max(T, float((a0 + m * s) / s));
    }
  }
  return T;
}

// One horizon walk along azimuth (cx, sy) from vertex (i0, j0): a 2D DDA over the cells the line crosses
// (Amanatides & Woo 1987). Local coordinates: the origin vertex at (0, 0), so positions near the start are
// exact in float.
class HorizonWalk {
 public:
  // thresholds (optional, ascending, n of them): the walk only has to classify tan H against them (see
  // bake_horizon_tangents' overload), so its gate is the next threshold above the current horizon.
  HorizonWalk(const Heights& f, int i0, int j0, float cx, float sy, float R,
              const double* thresholds = nullptr, int n_thresholds = 0)
      : thresholds_(thresholds),
        n_thresholds_(n_thresholds),
        f_(f),
        i0_(i0),
        j0_(j0),
        z0_(*f.vertex(i0, j0)),
        cx_(cx),
        sy_(sy),
        R_(R),
        limited_(std::isfinite(R)),
        rise_(f.zmax - z0_) {
    update();
  }

  // tan H (≥ 0).
  float run() {
    if (!(rise_ > 0)) return 0.0f;  // the highest point of the map: nothing rises above it
    const int w = f_.w, h = f_.h, W = w + 1;
    // The cell the line enters from the start vertex (local index di, dj; wrapped index wi, wj).
    int di = cx_ < 0 ? -1 : 0, dj = sy_ < 0 ? -1 : 0;
    int wi = i0_ + di, wj = j0_ + dj;
    if (wi < 0) wi += w;
    if (wj < 0) wj += h;
    const int si = cx_ > 0 ? 1 : -1, sj = sy_ > 0 ? 1 : -1;
    const float inf = std::numeric_limits<float>::infinity();
    // Exit distances through the next x and y grid lines, recomputed from the integer line (no drift).
    const float inv_cx = cx_ != 0 ? 1 / cx_ : 0, inv_sy = sy_ != 0 ? 1 / sy_ : 0;
    const int ox = cx_ > 0 ? 1 : 0, oy = sy_ > 0 ? 1 : 0;
    float sx = cx_ != 0 ? float(di + ox) * inv_cx : inf;
    float sy = sy_ != 0 ? float(dj + oy) * inv_sy : inf;
    const float inv_diag = cx_ != sy_ ? 1 / (cx_ - sy_) : 0;
    const float* row = f_.vertex(0, wj);
    float s = 0, z_in = 0;  // entry of the current cell and Δz there (the start vertex: 0)
    bool z_in_known = true;
    for (;;) {
      const float s_out = std::min(sx, sy);
      const float* p = row + wi;
      const float a = p[0] - z0_, b = p[1] - z0_, c = p[W + 1] - z0_, d = p[W] - z0_;
      if (std::max(std::max(a, b), std::max(c, d)) > s * gate_) {
        const float fdi = float(di), fdj = float(dj);
        // Surface Δz at parameter t in this cell (cell_height); the clamps keep boundary points on the cell.
        auto eval = [&](float t) {
          const float fx = std::clamp(cx_ * t - fdi, 0.0f, 1.0f), fy = std::clamp(sy_ * t - fdj, 0.0f, 1.0f);
          return cell_height(a, b, c, d, fx, fy);
        };
        float s_l = s, z_l = z_in_known ? z_in : eval(s);
        if (cx_ != sy_) {  // diagonal crossing fx = fy
          const float t = (fdi - fdj) * inv_diag;
          if (t > s && t < s_out) {
            const float z_t = eval(t);
            segment(s_l, z_l, t, z_t);
            s_l = t, z_l = z_t;
          }
        }
        z_in = eval(s_out);
        z_in_known = true;
        segment(s_l, z_l, s_out, z_in);
      } else {
        z_in_known = false;
      }
      s = s_out;
      if (s >= limit_) break;
      if (sx < sy) {
        di += si, wi += si, sx = float(di + ox) * inv_cx;
        wi = wi == w ? 0 : wi < 0 ? w - 1 : wi;
      } else {
        dj += sj, wj += sj, sy = float(dj + oy) * inv_sy;
        wj = wj == h ? 0 : wj < 0 ? h - 1 : wj;
        row = f_.vertex(0, wj);
      }
    }
    return T_;
  }

 private:
  // After T changes: the gate g = √(T² + tolerance) and the distance beyond which nothing can pass it —
  // the field's highest point (rise/g) and the ray-length disc (a point at s with Δz/s > g needs
  // s² (1 + g²) < R²).
  void update() {
    if (thresholds_) {
      // The smallest threshold above T, a hair lower (1e-6 relative, far above the float rounding of the
      // gate tests), so a skipped point can never reach it; none left: every threshold is classified.
      while (next_ < n_thresholds_ && !(thresholds_[next_] > double(T_))) ++next_;
      if (next_ == n_thresholds_) {
        gate_ = std::numeric_limits<float>::infinity(), limit_ = 0;
        return;
      }
      gate_ = float(thresholds_[next_] * (1 - 1e-6));
    } else {
      gate_ = std::sqrt(T_ * T_ + kTan2Tolerance);
    }
    limit_ = rise_ / gate_;
    if (limited_) limit_ = std::min(limit_, R_ / std::sqrt(1 + gate_ * gate_));
  }
  void raise(float t) {
    if (t > T_) T_ = t, update();
  }

  // A linear piece of the profile (piece_raise).
  void segment(float s_l, float z_l, float s_r, float z_r) {
    raise(piece_raise(T_, s_l, z_l, s_r, z_r, R_, limited_));
  }

  const double* thresholds_;
  int n_thresholds_, next_ = 0;
  const Heights& f_;
  int i0_, j0_;
  float z0_, cx_, sy_, R_;
  bool limited_;
  float rise_, T_ = 0, gate_ = 0, limit_ = 0;
};

// ---- Profile scans (finite ray length) ----
//
// Every walk starts on a vertex, so the breakpoints a walk along a given direction meets (where its line
// crosses x = integer, y = integer or a cell diagonal x − y = integer) are at the same distances and the same
// offsets from its start vertex, whatever the vertex. A ray profile lists them once per direction; a vertex's
// horizon is then a scan of its heights at those offsets through piece_raise, with no cell traversal and no
// wrap logic (the heights are padded by the ray length). Same pieces, same rule as the walk, but exact: the
// scan stops only where nothing can raise T any more (s > (z_max − z_0)/T, or the disc), no tolerance.

// Heights in texel units padded by P texels on every side (wrapped), so every profile offset from every
// vertex of the map is in range.
// Vertices scanned together: consecutive in a row, one profile, lane by lane in lockstep (vectorised).
constexpr int kLanes = 8;

// The side of the squares of PaddedHeights::block_max: a profile block and its kLanes start vertices fit
// in one.
constexpr int kSkipWindow = 16;

// out[i] = max(in[i·stride .. (min(i + k, n) − 1)·stride]) for i < n: the window clipped at the end.
// A monotone queue: each input enters and leaves it once.
void sliding_max(const float* in, std::ptrdiff_t stride, int n, int k, float* out, std::vector<int>& queue) {
  queue.resize(std::size_t(n));
  int head = 0, tail = 0, next = 0;  // queue[head, tail): indices of decreasing values
  for (int i = 0; i < n; ++i) {
    for (const int hi = std::min(i + k, n); next < hi; ++next) {
      while (tail > head && in[queue[tail - 1] * stride] <= in[next * stride]) --tail;
      queue[tail++] = next;
    }
    while (queue[head] < i) ++head;
    out[i * stride] = in[queue[head] * stride];
  }
}

struct PaddedHeights {
  int w = 0, h = 0, P = 0, PW = 0;
  float zmax = 0;
  // Above the rounding of a height interpolated between two vertices minus another (a few ulps of the
  // largest |z|): scan_profile's skip test.
  float margin = 0;
  std::vector<float> z;  // (w + 2P) × (h + 2P)
  // block_max[y·PW + x] = the highest padded height in [x, x + kSkipWindow) × [y, y + kSkipWindow) (clipped
  // at the array's end): the bound the scans skip profile blocks by.
  std::vector<float> block_max;

  // with_block_max false: the heights alone (the lattice sweeps read no skip bound).
  PaddedHeights(const Texture& height, float depth, int pad, bool with_block_max = true)
      : w(height.width()), h(height.height()), P(pad) {
    PW = w + 2 * P;
    // kLanes of slack: a row's last block of lanes reads up to kLanes − 1 texels past the map (discarded).
    z.resize(std::size_t(PW) * std::size_t(h + 2 * P) + kLanes);
    zmax = -std::numeric_limits<float>::max();
    for (int j = 0; j < h + 2 * P; ++j)
      for (int i = 0; i < PW; ++i) {
        const int si = ((i - P) % w + w) % w, sj = ((j - P) % h + h) % h;
        const float v = (height.at(si, sj, 0) - 1.0f) * depth;
        z[std::size_t(j) * PW + i] = v;
        zmax = std::max(zmax, v);
        margin = std::max(margin, std::abs(v));
      }
    margin = margin * 1e-6f + std::numeric_limits<float>::min();
    if (!with_block_max) return;
    // Separable: the row maxima, then their column maxima.
    const int rows = h + 2 * P;
    std::vector<float> rowmax(z.size());
    block_max.resize(z.size());
    tbb::parallel_for(0, rows, [&](int j) {
      std::vector<int> q;
      sliding_max(z.data() + std::size_t(j) * PW, 1, PW, kSkipWindow, rowmax.data() + std::size_t(j) * PW, q);
    });
    tbb::parallel_for(0, PW, [&](int i) {
      std::vector<int> q;
      sliding_max(rowmax.data() + i, PW, rows, kSkipWindow, block_max.data() + i, q);
    });
  }
  std::size_t base(int i, int j) const { return std::size_t(j + P) * PW + std::size_t(i + P); }
};

// One breakpoint of a ray profile: distance s from the start vertex, its height the interpolation of the
// vertices at offsets a and b (relative to the start, in the padded array) with weight t on b.
struct ProfilePoint {
  float s;
  int32_t a, b;
  float t;
  float inv_s;  // 1/s
  float cr;     // √(R² − s²), 0 beyond R (the disc's height there, as piece_raise computes it)
};

// The padding a ray of length R needs: the last breakpoint lies at most one cell diagonal beyond R.
int profile_padding(float R) { return int(std::ceil(R)) + 3; }

// The profile scans pad the map by the ray length; above this many padded texels (4× the map, at least
// 4 M) the walks run instead, which wrap in place.
double max_profile_length(int w, int h) {
  const double cap = std::max(4.0 * w * h, double(1 << 22));
  // (w + 2P)(h + 2P) ≤ cap, P = ⌈R⌉ + 3: the largest R.
  const double P = (-(w + h) + std::sqrt(double(w + h) * (w + h) - 4.0 * (double(w) * h - cap))) / 4;
  return std::floor(P) - 4;
}
bool profiles_fit(int w, int h, float R) {
  return std::isfinite(R) && R > 0 && R <= max_profile_length(w, h);
}

// bake_visibility's directions: azimuths × M, M = max(1, kRotatedDirections / azimuths) rotations.
constexpr int kRotatedDirections = 256;

// A run of breakpoints [e0, e1) (e0 ≥ 1) whose vertices, from any of kLanes consecutive start vertices,
// lie in the kSkipWindow square at offset `box` from the first lane's start: if no live lane can pass its
// horizon anywhere in the square, the scan skips the run (scan_profile).
struct ProfileBlock {
  int32_t e0, e1;
  int32_t box;  // offset of the square's corner in the padded array
};

struct Profile {
  std::vector<ProfilePoint> pts;
  std::vector<ProfileBlock> blocks;  // covering [1, pts.size()), ascending
};

// The breakpoints along (c, sn) (unit) up to and including the first at s ≥ R, ascending, coincident ones
// merged; and their blocks.
Profile ray_profile(double c, double sn, double R, int PW) {
  struct Cross {
    double s;
    int kind;  // 0: x = X, 1: y = Y, 2: x − y = D
    int n;     // X, Y or D
  };
  std::vector<Cross> cs;
  const double rates[3] = {c, sn, c - sn};
  double first_beyond = std::numeric_limits<double>::infinity();
  for (int kind = 0; kind < 3; ++kind) {
    const double r = std::abs(rates[kind]);
    if (r < 1e-12) continue;
    const int sign = rates[kind] > 0 ? 1 : -1;
    for (int n = 1;; ++n) {
      const double s = n / r;
      cs.push_back({s, kind, sign * n});
      if (s >= R) {
        first_beyond = std::min(first_beyond, s);
        break;
      }
    }
  }
  std::sort(cs.begin(), cs.end(), [](const Cross& x, const Cross& y) { return x.s < y.s; });
  Profile prof;
  std::vector<ProfilePoint>& out = prof.pts;
  struct Cell {
    int ax, ay, bx, by;
  };
  std::vector<Cell> cells;
  double last = -1;
  for (const Cross& x : cs) {
    if (x.s > first_beyond) break;
    if (x.s - last < 1e-9 * std::max(1.0, x.s)) continue;  // the same point reached by two crossings
    last = x.s;
    const double px = c * x.s, py = sn * x.s;
    int ax, ay, bx, by;
    double t;
    if (x.kind == 0) {  // on the vertical edge x = X: between (X, ⌊y⌋) and (X, ⌊y⌋ + 1)
      ax = bx = x.n, ay = int(std::floor(py)), by = ay + 1, t = py - ay;
    } else if (x.kind == 1) {  // on the horizontal edge y = Y
      ay = by = x.n, ax = int(std::floor(px)), bx = ax + 1, t = px - ax;
    } else {  // on the diagonal of cell (X0, X0 − D) from its corner (0, 0) to (1, 1)
      ax = int(std::floor(px)), ay = ax - x.n, bx = ax + 1, by = ay + 1, t = px - ax;
    }
    const float sf = float(x.s), Rf = float(R);
    out.push_back({sf, int32_t(ay * PW + ax), int32_t(by * PW + bx), float(std::clamp(t, 0.0, 1.0)), 1 / sf,
                   std::sqrt(std::max(Rf * Rf - sf * sf, 0.0f))});
    cells.push_back({ax, ay, bx, by});
  }
  // Blocks, greedily: extend while the vertices of the run, shifted by 0 … kLanes − 1 along x, fit in the
  // square.
  for (std::size_t e = 1; e < out.size();) {
    int x0 = std::min(cells[e].ax, cells[e].bx), x1 = std::max(cells[e].ax, cells[e].bx);
    int y0 = std::min(cells[e].ay, cells[e].by), y1 = std::max(cells[e].ay, cells[e].by);
    std::size_t e1 = e + 1;
    for (; e1 < out.size(); ++e1) {
      const Cell& q = cells[e1];
      const int nx0 = std::min({x0, q.ax, q.bx}), nx1 = std::max({x1, q.ax, q.bx});
      const int ny0 = std::min({y0, q.ay, q.by}), ny1 = std::max({y1, q.ay, q.by});
      if (nx1 + kLanes - 1 - nx0 >= kSkipWindow || ny1 - ny0 >= kSkipWindow) break;
      x0 = nx0, x1 = nx1, y0 = ny0, y1 = ny1;
    }
    prof.blocks.push_back({int32_t(e), int32_t(e1), int32_t(y0 * PW + x0)});
    e = e1;
  }
  return prof;
}

// The kLanes lanes in groups of 4 (GCC/Clang vector extensions: one SSE register each, the x86-64 baseline;
// other targets get their own 128-bit registers or scalar code). Every lane computes the same float
// operations in the same order as a scalar scan would, so the result does not depend on the mapping.
constexpr int kGroup = 4, kGroups = kLanes / kGroup;
using Lane4 = float __attribute__((vector_size(kGroup * sizeof(float))));
using Mask4 = int32_t __attribute__((vector_size(kGroup * sizeof(float))));
static_assert(kLanes % kGroup == 0);

inline Lane4 load4(const float* p) {
  Lane4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// Whether any lane of comparison masks (0 or −1 per lane) is set.
inline bool any_lane(const Mask4 (&m)[kGroups]) {
  Mask4 a = m[0];
  for (int g = 1; g < kGroups; ++g) a |= m[g];
  uint64_t q[2];
  std::memcpy(q, &a, sizeof q);
  return (q[0] | q[1]) != 0;
}

// tan H at the kLanes consecutive vertices from padded index `base` along a profile, rays of length R
// (finite), into T_out[kLanes]. Each lane is the scan of one vertex through piece_raise: the first piece (the
// start slope) and pieces that reach the disc or the ray's end take it as it is; every other piece can only
// raise T to its right end's Δz/s (inside the disc), which the lanes do together without branches. A lane
// stops where nothing can raise its T any more: from s with s·T ≥ z_max − z_0 (no point rises higher) or
// s²(1 + T²) ≥ R² (no point of the disc beyond passes T); the scan ends when every lane has stopped. So each
// vertex gets its own scan's result, whatever its neighbours.
//
// Blocks of breakpoints are skipped where, for every lane still live, the highest height in the block's
// square (PaddedHeights::block_max) lies below the lane's horizon line over the whole block, s·T at the
// block's nearer end for T ≥ 0 (its farther end for T < 0), with f.margin for the rounding of the
// interpolated heights: then no breakpoint of the block passes, and a piece whose right end does not pass
// changes nothing (above), so skipping leaves every T as the full scan would.
void scan_profile(const PaddedHeights& f, std::size_t base, const Profile& prof, float R, float* T_out) {
  const float* z = f.z.data() + base;
  const float R2 = R * R;
  Lane4 z0[kGroups], rise[kGroups], T[kGroups], z_l[kGroups];
  for (int g = 0; g < kGroups; ++g)
    z0[g] = load4(z + g * kGroup), rise[g] = f.zmax - z0[g], T[g] = Lane4{} + 0.0f, z_l[g] = T[g];
  float s_l = 0;
  // Δz of group g at breakpoint p; which lanes of group g still scan (from s_l on): −1 where they do.
  const auto dz_at = [&](const ProfilePoint& p, int g) {
    const Lane4 za = load4(z + p.a + g * kGroup), zb = load4(z + p.b + g * kGroup);
    return za + p.t * (zb - za) - z0[g];
  };
  const auto scanning = [&](int g) -> Mask4 {
    return (s_l * T[g] < rise[g]) & (s_l * s_l * (1 + T[g] * T[g]) < R2);
  };
  // One breakpoint for every lane; live: the lanes that scan, taken at the start of the block. A lane that
  // stops inside a block keeps stepping to the block's end, which cannot change its T: past s·T ≥ z_max − z_0
  // no breakpoint passes the line, and past the disc a passing one is a hard piece whose disc-clipped value
  // piece_raise finds below T. (Both up to float rounding: the float micro-occlusion mips of the six kinds at
  // 512² and every output of rock at 2048² are bit-identical to the per-step test.) Testing once per block
  // takes the test off the chain from one step's T to the next: 14 % faster. A stopped lane never scans again
  // (s_l only grows, its T no longer changes), so the scan ends at the first block with no lane live.
  const auto step = [&](const ProfilePoint& p, bool first, const Mask4(&live)[kGroups]) {
    Lane4 zr[kGroups];
    Mask4 hard[kGroups];
    for (int g = 0; g < kGroups; ++g) {
      zr[g] = dz_at(p, g);
      const Mask4 pass = live[g] & (zr[g] > p.s * T[g]);
      // The first piece, the disc or the ray's end: the scalar rule below.
      hard[g] = first ? live[g] : pass & (zr[g] > p.cr);
      const Lane4 raised = zr[g] * p.inv_s;
      T[g] = (pass & ~hard[g] & (raised > T[g])) ? raised : T[g];
    }
    if (any_lane(hard)) [[unlikely]]
      for (int g = 0; g < kGroups; ++g)
        for (int l = 0; l < kGroup; ++l)
          if (hard[g][l]) T[g][l] = piece_raise(T[g][l], s_l, z_l[g][l], p.s, zr[g][l], R, true);
    s_l = p.s;
    for (int g = 0; g < kGroups; ++g) z_l[g] = zr[g];
  };
  if (!prof.pts.empty()) {
    Mask4 live0[kGroups];
    for (int g = 0; g < kGroups; ++g) live0[g] = scanning(g);
    step(prof.pts[0], true, live0);
    const ProfilePoint* pts = prof.pts.data();
    for (const ProfileBlock& b : prof.blocks) {
      Mask4 live[kGroups], blocking[kGroups];
      const float top = f.block_max[base + std::size_t(std::ptrdiff_t(b.box))];
      const float sa = pts[b.e0].s, sb = pts[b.e1 - 1].s;
      for (int g = 0; g < kGroups; ++g) {
        live[g] = scanning(g);
        const Lane4 line_a = sa * T[g], line_b = sb * T[g];
        blocking[g] = live[g] & ~(top - z0[g] + f.margin <= (line_a < line_b ? line_a : line_b));
      }
      if (!any_lane(live)) break;
      if (!any_lane(blocking)) {
        // No live lane can pass anywhere in the block: its last breakpoint's heights are the next piece's
        // left end.
        for (int g = 0; g < kGroups; ++g) z_l[g] = dz_at(pts[b.e1 - 1], g);
        s_l = sb;
        continue;
      }
      for (int e = b.e0; e < b.e1; ++e) step(pts[e], false, live);
    }
  }
  std::memcpy(T_out, T, sizeof T);
}

}  // namespace

Texture bake_visibility(const Texture& height, float depth, int azimuths, float max_distance) {
  if (azimuths < 1 || azimuths > 65536) throw InputError("bake_visibility: azimuths must be in [1, 65536]");
  check_depth("bake_visibility", depth);
  if (std::isnan(max_distance)) throw InputError("bake_visibility: max distance is NaN");
  if (height.empty()) throw InputError("bake_visibility: empty height map");
  const float R = max_distance > 0 ? max_distance : std::numeric_limits<float>::infinity();
  const int w = height.width(), h = height.height();
  Texture vis(w, h, 1);
  // Stratified azimuths, rotated (Cranley–Patterson) by one of M offsets picked by a hash per run of kLanes
  // texels in a row (they scan together), so the quadrature error is not a pattern and box means see
  // M · azimuths directions.
  const int M = std::max(1, kRotatedDirections / azimuths);
  auto rotation = [&](int i, int j) {
    const double u = double(hash_combine(hash_u32(uint32_t(i)), uint32_t(j))) * 0x1p-32;
    return std::min(int(u * M), M - 1);
  };
  auto phi = [&](int k, int r) { return 2 * kPi<double> * (double(k) + (r + 0.5) / M) / double(azimuths); };
  if (profiles_fit(w, h, R)) {
    const PaddedHeights f(height, depth, profile_padding(R));
    std::vector<Profile> prof(std::size_t(azimuths) * M);
    tbb::parallel_for(0, azimuths * M, [&](int q) {
      const double a = phi(q / M, q % M);
      prof[std::size_t(q)] = ray_profile(std::cos(a), std::sin(a), R, f.PW);
    });
    tbb::parallel_for(0, h, [&](int j) {
      double sum[kLanes];
      float T[kLanes];
      for (int i0 = 0; i0 < w; i0 += kLanes) {
        // One rotation per block of kLanes texels in a row (they scan one profile together).
        const int r = rotation(i0 / kLanes, j), n = std::min(kLanes, w - i0);
        std::fill(sum, sum + kLanes, 0.0);
        for (int k = 0; k < azimuths; ++k) {
          scan_profile(f, f.base(i0, j), prof[std::size_t(k) * M + r], R, T);
          for (int l = 0; l < n; ++l) sum[l] += cos2_horizon(T[l]);
        }
        for (int l = 0; l < n; ++l) vis.at(i0 + l, j, 0) = float(sum[l] / double(azimuths));
      }
    });
    return vis;
  }
  const Heights f(height, depth);
  tbb::parallel_for(0, h, [&](int j) {
    for (int i = 0; i < w; ++i) {
      const int r = rotation(i / kLanes, j);
      double sum = 0;
      for (int k = 0; k < azimuths; ++k) {
        const double a = phi(k, r);
        const float T = HorizonWalk(f, i, j, float(std::cos(a)), float(std::sin(a)), R).run();
        sum += cos2_horizon(T);
      }
      vis.at(i, j, 0) = float(sum / double(azimuths));
    }
  });
  return vis;
}

std::vector<float> bake_horizon_tangents_profiles(const Texture& height, float depth,
                                                  const std::vector<Vec2f>& dirs, float max_distance) {
  check_depth("bake_horizon_tangents_profiles", depth);
  if (height.empty()) throw InputError("bake_horizon_tangents_profiles: empty height map");
  const int w = height.width(), h = height.height(), n = int(dirs.size());
  if (!(max_distance > 0) || !profiles_fit(w, h, max_distance))
    throw InputError(fmt::format(
        "bake_horizon_tangents_profiles: the ray length must be > 0 and at most {} texels here, got {}",
        max_profile_length(w, h), max_distance));
  check_unit_directions("bake_horizon_tangents_profiles", dirs);
  const PaddedHeights f(height, depth, profile_padding(max_distance));
  std::vector<Profile> prof;
  for (const Vec2f& d : dirs) prof.push_back(ray_profile(d.x, d.y, max_distance, f.PW));
  std::vector<float> out(std::size_t(w) * h * std::size_t(n));
  tbb::parallel_for(0, h, [&](int j) {
    float T[kLanes];
    for (int i0 = 0; i0 < w; i0 += kLanes)
      for (int k = 0; k < n; ++k) {
        scan_profile(f, f.base(i0, j), prof[std::size_t(k)], max_distance, T);
        for (int l = 0; l < std::min(kLanes, w - i0); ++l) out[(std::size_t(j) * w + i0 + l) * n + k] = T[l];
      }
  });
  return out;
}

namespace {
// Both forms of bake_horizon_tangents: exact tangents (thresholds null) or classified against thresholds.
std::vector<float> horizon_walks(const Texture& height, float depth, const std::vector<Vec2f>& dirs,
                                 float max_distance, const std::vector<std::vector<double>>* thresholds) {
  check_depth("bake_horizon_tangents", depth);
  if (std::isnan(max_distance)) throw InputError("bake_horizon_tangents: max distance is NaN");
  if (height.empty()) throw InputError("bake_horizon_tangents: empty height map");
  check_unit_directions("bake_horizon_tangents", dirs);
  if (thresholds) {
    if (thresholds->size() != dirs.size())
      throw InputError("bake_horizon_tangents: one threshold list per direction is needed");
    for (const auto& t : *thresholds)
      if (!std::is_sorted(t.begin(), t.end()) || (!t.empty() && !(t.front() > 0)))
        throw InputError("bake_horizon_tangents: thresholds must be positive and ascending");
  }
  const float R = max_distance > 0 ? max_distance : std::numeric_limits<float>::infinity();
  const Heights f(height, depth);
  const int w = height.width(), h = height.height(), n = int(dirs.size());
  std::vector<float> out(std::size_t(w) * h * n);
  tbb::parallel_for(0, h, [&](int j) {
    for (int i = 0; i < w; ++i)
      for (int k = 0; k < n; ++k) {
        const auto* t = thresholds ? &(*thresholds)[std::size_t(k)] : nullptr;
        out[(std::size_t(j) * w + i) * n + k] =
            HorizonWalk(f, i, j, dirs[k].x, dirs[k].y, R, t ? t->data() : nullptr, t ? int(t->size()) : 0)
                .run();
      }
  });
  return out;
}
}  // namespace

// ---- Lattice sweeps ----

namespace {

int gcd_int(int a, int b) { return std::gcd(std::abs(a), std::abs(b)); }

// A breakpoint of the profile between a vertex and the next one along a step (p, q): where the line crosses
// a cell edge or a cell diagonal, at parameter t ∈ (0, 1) of the step. Its height is the triangulated
// surface at (t p, t q) from the vertex: cell (ci, cj) from the vertex, fractions (fx, fy) in it.
struct Breakpoint {
  double t;
  int ci, cj;
  float fx, fy;
};

std::vector<Breakpoint> step_breakpoints(LatticeStep st) {
  std::vector<double> ts;
  const int ap = std::abs(st.p), aq = std::abs(st.q), ad = std::abs(st.p - st.q);
  for (int m = 1; m < ap; ++m) ts.push_back(double(m) / ap);  // x = integer
  for (int m = 1; m < aq; ++m) ts.push_back(double(m) / aq);  // y = integer
  for (int m = 1; m < ad; ++m) ts.push_back(double(m) / ad);  // x − y = integer (a cell diagonal)
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end(), [](double a, double b) { return b - a < 1e-12; }), ts.end());
  std::vector<Breakpoint> out;
  double prev = 0;
  for (double t : ts) {
    // The cell is the one the segment crosses just before t (it holds the midpoint with the previous
    // breakpoint), so the point is on that cell's boundary or diagonal; the clamps keep the fractions in
    // [0, 1].
    const double tm = 0.5 * (prev + t);
    prev = t;
    const double xm = tm * st.p, ym = tm * st.q;
    const int ci = int(std::floor(xm)), cj = int(std::floor(ym));
    const float fx = float(std::clamp(t * st.p - ci, 0.0, 1.0)),
                fy = float(std::clamp(t * st.q - cj, 0.0, 1.0));
    out.push_back({t, ci, cj, fx, fy});
  }
  return out;
}

}  // namespace

double lattice_azimuth(LatticeStep s) { return std::atan2(double(s.q), double(s.p)); }

Vec2f lattice_direction(LatticeStep s) {
  const double n = std::hypot(double(s.p), double(s.q));
  return Vec2f(float(s.p / n), float(s.q / n));
}

std::vector<LatticeStep> lattice_azimuths(int n, double max_error_deg) {
  if (n < 1 || n > 4096) throw InputError(fmt::format("lattice_azimuths: n must be in [1, 4096], got {}", n));
  if (!(max_error_deg >= 0.01 && max_error_deg <= 45))
    throw InputError(
        fmt::format("lattice_azimuths: max error must be in [0.01, 45] degrees, got {}", max_error_deg));
  const double tol = max_error_deg * kPi<double> / 180;
  std::vector<LatticeStep> out;
  for (int a = 0; a < n; ++a) {
    const double phi = 2 * kPi<double> * (a + 0.5) / n;
    const double c = std::cos(phi), sn = std::sin(phi);
    for (int M = 1;; ++M) {
      // On the ring max(|p|, |q|) = M the azimuth is monotonic along each side, so the closest steps to φ
      // are the two lattice points beside the ray's crossing of its side. (A non-primitive one has the
      // azimuth of a step on a smaller ring, already farther than the tolerance.) O(1) per ring.
      double best = std::numeric_limits<double>::infinity();
      LatticeStep bs;
      const bool x_side = std::abs(c) >= std::abs(sn);
      const double other = x_side ? M * sn / std::abs(c) : M * c / std::abs(sn);
      for (double o : {std::floor(other), std::ceil(other)}) {
        const int k = int(std::clamp(o, double(-M), double(M)));
        const int p = x_side ? (c > 0 ? M : -M) : k, q = x_side ? k : (sn > 0 ? M : -M);
        if (gcd_int(p, q) != 1) continue;
        const double d = std::abs(std::remainder(std::atan2(double(q), double(p)) - phi, 2 * kPi<double>));
        if (d < best) best = d, bs = {p, q};
      }
      if (best <= tol) {
        out.push_back(bs);
        break;
      }
    }
  }
  return out;
}

namespace {

// Into [0, m): one add or subtract for the usual small offsets, the remainder otherwise (tiny maps).
inline int wrap_index(int v, int m) {
  if (v >= m) v -= m;
  if (v < 0) v += m;
  return v >= 0 && v < m ? v : ((v % m) + m) % m;
}

// What the sweeps of one step (p, q) share: its lines, and each line's profile points (a vertex, then its
// breakpoints) with their distances and cell offsets, the same for every line.
struct StepLines {
  std::vector<Breakpoint> bps;
  int per = 1;                           // profile points per step: the vertex, then its breakpoints
  int K = 0;                             // vertices per line
  std::size_t N = 0;                     // profile points per line, K · per
  std::vector<int> starts;               // one start vertex per line, in memory order
  std::vector<std::ptrdiff_t> cell_off;  // each breakpoint's cell corner from the vertex (padded heights)
  int r0 = 0, r1 = 0, c0 = 0, c1 = 0;    // the rows and columns a step's cells span from its vertex
  std::vector<double> ss;                // distances along the line
  double L = 0;                          // the line's length (one period)
};

StepLines step_lines(LatticeStep st, int w, int h, int PW) {
  StepLines sl;
  sl.bps = step_breakpoints(st);
  const double len = std::hypot(double(st.p), double(st.q));
  // Vertices per line: the smallest K with K p ≡ 0 (mod w) and K q ≡ 0 (mod h).
  const int kx = w / std::gcd(w, std::abs(st.p)), ky = h / std::gcd(h, std::abs(st.q));
  sl.K = std::lcm(kx, ky);
  // One start vertex per line, in memory order (neighbouring lines run side by side through memory).
  std::vector<char> seen(std::size_t(w) * h, 0);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      if (seen[std::size_t(j) * w + i]) continue;
      sl.starts.push_back(j * w + i);
      int x = i, y = j;
      for (int m = 0; m < sl.K; ++m) {
        seen[std::size_t(y) * w + x] = 1;
        x = wrap_index(x + st.p, w), y = wrap_index(y + st.q, h);
      }
    }
  sl.per = 1 + int(sl.bps.size());
  std::vector<double> s_off(std::size_t(sl.per), 0.0);  // the points' distances from the step's vertex
  for (int b = 1; b < sl.per; ++b) s_off[std::size_t(b)] = sl.bps[std::size_t(b - 1)].t * len;
  sl.cell_off.resize(sl.bps.size());
  for (std::size_t b = 0; b < sl.bps.size(); ++b) {
    sl.cell_off[b] = std::ptrdiff_t(sl.bps[b].cj) * PW + sl.bps[b].ci;
    sl.r0 = std::min(sl.r0, sl.bps[b].cj), sl.r1 = std::max(sl.r1, sl.bps[b].cj + 1);
    sl.c0 = std::min(sl.c0, sl.bps[b].ci), sl.c1 = std::max(sl.c1, sl.bps[b].ci + 1);
  }
  sl.N = std::size_t(sl.K) * sl.per;
  sl.ss.resize(sl.N);
  for (int m = 0; m < sl.K; ++m)
    for (int b = 0; b < sl.per; ++b)
      sl.ss[std::size_t(m) * sl.per + b] = double(m) * len + s_off[std::size_t(b)];
  sl.L = double(sl.K) * len;
  return sl;
}

// Lines go in bundles of kBundle neighbours (consecutive starts, side by side in memory), their profiles
// read in lockstep so the rows a step crosses are read once for the whole bundle.
constexpr std::size_t kBundle = 8;

// Reads the profiles of the bundle's nl lines starting at starts[l0]: zs[u · N + i] the height of point i
// of line u, vid[u · K + m] its m-th vertex, top[u] its highest point (the first if several).
void read_bundle(const PaddedHeights& f, LatticeStep st, const StepLines& sl, int w, int h, std::size_t l0,
                 std::size_t nl, float* zs, int* vid, std::size_t* top) {
  const int PW = f.PW, per = sl.per, K = sl.K;
  const std::size_t N = sl.N;
  int xs[kBundle], ys[kBundle];
  float ztop[kBundle];
  for (std::size_t u = 0; u < nl; ++u) {
    xs[u] = sl.starts[l0 + u] % w, ys[u] = sl.starts[l0 + u] / w;
    top[u] = 0, ztop[u] = -std::numeric_limits<float>::infinity();
  }
  // The bundle's first and last lines kAhead steps ahead: their cells are prefetched (the lines cross the
  // rows diagonally, which the hardware's stride prefetch does not follow).
  constexpr int kAhead = 8;
  int ax[2] = {wrap_index(xs[0] + kAhead * st.p, w), wrap_index(xs[nl - 1] + kAhead * st.p, w)};
  int ay[2] = {wrap_index(ys[0] + kAhead * st.q, h), wrap_index(ys[nl - 1] + kAhead * st.q, h)};
  for (int m = 0; m < K; ++m) {
    {
      const float* a = f.z.data() + f.base(ax[0], ay[0]);
      const float* b = f.z.data() + f.base(ax[1], ay[1]);
      // One span when the bundle's lines sit side by side in a row (the usual case), else each end.
      const bool one_span = ay[0] == ay[1] && ax[1] >= ax[0] && ax[1] - ax[0] <= 2 * int(kBundle);
      for (int rr = sl.r0; rr <= sl.r1; ++rr) {
        const float* lo = a + std::ptrdiff_t(rr) * PW + sl.c0;
        const float* hi = (one_span ? b : a) + std::ptrdiff_t(rr) * PW + sl.c1;
        for (const float* q = lo; q <= hi; q += 16) __builtin_prefetch(q);
        __builtin_prefetch(hi);
        if (!one_span) {
          __builtin_prefetch(b + std::ptrdiff_t(rr) * PW + sl.c0);
          __builtin_prefetch(b + std::ptrdiff_t(rr) * PW + sl.c1);
        }
      }
      for (int t = 0; t < 2; ++t) ax[t] = wrap_index(ax[t] + st.p, w), ay[t] = wrap_index(ay[t] + st.q, h);
    }
    for (std::size_t u = 0; u < nl; ++u) {
      const int x = xs[u], y = ys[u];
      float* z = &zs[u * N + std::size_t(m) * per];
      const float* v = f.z.data() + f.base(x, y);
      z[0] = *v;
      vid[u * std::size_t(K) + std::size_t(m)] = y * w + x;
      for (int b = 1; b < per; ++b) {
        const Breakpoint& bp = sl.bps[std::size_t(b - 1)];
        const float* c = v + sl.cell_off[std::size_t(b - 1)];
        z[b] = cell_height(c[0], c[1], c[PW + 1], c[PW], bp.fx, bp.fy);
      }
      for (int b = 0; b < per; ++b)
        if (z[b] > ztop[u]) ztop[u] = z[b], top[u] = std::size_t(m) * per + std::size_t(b);
      xs[u] = wrap_index(x + st.p, w), ys[u] = wrap_index(y + st.q, h);
    }
  }
}

// The horizons of one line's vertices from its profile zl (vertices vl), by a convex hull swept backwards
// from the profile's highest point `top` once around: nothing beyond it (one period further) rises above it,
// so it hides every point there from every point before it. (The highest point may be a breakpoint: they
// interpolate vertices off the line.) hs, hz: scratch of N points for the hull ahead, farthest first.
template <class Store>
void sweep_line(const StepLines& sl, int k, const float* zl, const int* vl, std::size_t top, double* hs,
                double* hz, const Store& store) {
  const int per = sl.per;
  std::size_t n_h = 0;
  // Points hi − 1 down to lo, shifted back by `shift`; point idx is breakpoint b = idx mod per of step
  // m = idx / per (b = 0: the vertex), both counted down rather than divided.
  auto sweep = [&](std::size_t hi, std::size_t lo, double shift) {
    if (hi <= lo) return;
    std::size_t m = (hi - 1) / std::size_t(per);
    int b = int((hi - 1) % std::size_t(per));
    for (std::size_t idx = hi; idx-- > lo;) {
      const double s = sl.ss[idx] - shift, z = zl[idx];
      // Drop the nearest hull point while the next one is at least as steep from here (it is then under the
      // chord to it, for this point and every one before it): (zA − z)/(sA − s) ≥ (zB − z)/(sB − s),
      // denominators > 0.
      while (n_h >= 2 && (hz[n_h - 2] - z) * (hs[n_h - 1] - s) >= (hz[n_h - 1] - z) * (hs[n_h - 2] - s))
        --n_h;
      if (b == 0) {  // a vertex: its horizon
        store(k, vl[m], n_h ? float(std::max((hz[n_h - 1] - z) / (hs[n_h - 1] - s), 0.0)) : 0.0f);
        b = per, --m;
      }
      --b;
      hs[n_h] = s, hz[n_h] = z, ++n_h;
    }
  };
  sweep(top + 1, 0, 0.0);
  sweep(sl.N, top + 1, sl.L);
}

// The sweeps of bake_horizon_tangents_lattice: store(k, v, T) receives tan H of vertex v = j·w + i along step
// k, once per vertex and step.
template <class Store>
void lattice_sweeps(const char* fn, const Texture& height, float depth, const std::vector<LatticeStep>& steps,
                    const Store& store) {
  check_depth(fn, depth);
  if (height.empty()) throw InputError(fmt::format("{}: empty height map", fn));
  for (const LatticeStep& st : steps)
    if (gcd_int(st.p, st.q) != 1)
      throw InputError(fmt::format("{}: step ({}, {}) is not primitive", fn, st.p, st.q));
  // Padded by the largest step plus a cell, so every breakpoint's cell from any vertex is inside the array
  // at a fixed offset from the vertex: no wrapping per breakpoint.
  int pad = 2;
  for (const LatticeStep& st : steps) pad = std::max(pad, std::max(std::abs(st.p), std::abs(st.q)) + 2);
  const PaddedHeights f(height, depth, pad, false);
  const int w = height.width(), h = height.height(), n = int(steps.size());
  for (int k = 0; k < n; ++k) {
    const LatticeStep st = steps[std::size_t(k)];
    const StepLines sl = step_lines(st, w, h, f.PW);
    const std::size_t N = sl.N, K = std::size_t(sl.K);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sl.starts.size(), kBundle), [&](const auto& r) {
      std::vector<float> zs(N * kBundle);
      std::vector<int> vid(K * kBundle);
      std::vector<double> hs(N), hz(N);
      for (std::size_t l0 = r.begin(); l0 < r.end(); l0 += kBundle) {
        const std::size_t nl = std::min(kBundle, r.end() - l0);
        std::size_t top[kBundle];
        read_bundle(f, st, sl, w, h, l0, nl, zs.data(), vid.data(), top);
        for (std::size_t u = 0; u < nl; ++u)
          sweep_line(sl, k, &zs[u * N], &vid[u * K], top[u], hs.data(), hz.data(), store);
      }
    });
  }
}
}  // namespace

std::vector<float> bake_horizon_tangents_lattice(const Texture& height, float depth,
                                                 const std::vector<LatticeStep>& steps) {
  const std::size_t n = steps.size();
  std::vector<float> out;
  if (!height.empty()) out.resize(std::size_t(height.width()) * std::size_t(height.height()) * n);
  lattice_sweeps("bake_horizon_tangents_lattice", height, depth, steps,
                 [&](int k, int v, float T) { out[std::size_t(v) * n + std::size_t(k)] = T; });
  return out;
}

std::vector<uint8_t> bake_horizon_classes_lattice(const Texture& height, float depth,
                                                  const std::vector<LatticeStep>& steps,
                                                  const std::vector<std::vector<double>>& thresholds) {
  if (thresholds.size() != steps.size())
    throw InputError("bake_horizon_classes_lattice: one threshold list per step is needed");
  for (const auto& t : thresholds)
    if (t.size() > 255) throw InputError("bake_horizon_classes_lattice: at most 255 thresholds per step");
  const std::size_t wh = height.empty() ? 0 : std::size_t(height.width()) * std::size_t(height.height());
  std::vector<uint8_t> out(wh * steps.size());
  lattice_sweeps("bake_horizon_classes_lattice", height, depth, steps, [&](int k, int v, float T) {
    const std::vector<double>& t = thresholds[std::size_t(k)];
    const int nt = int(t.size());
    int e = 0;
    while (e < nt && !(t[std::size_t(e)] > double(T))) ++e;
    out[std::size_t(k) * wh + std::size_t(v)] = uint8_t(e);
  });
  return out;
}

std::vector<float> bake_horizon_tangents(const Texture& height, float depth, const std::vector<Vec2f>& dirs,
                                         float max_distance) {
  return horizon_walks(height, depth, dirs, max_distance, nullptr);
}

std::vector<float> bake_horizon_tangents(const Texture& height, float depth, const std::vector<Vec2f>& dirs,
                                         float max_distance,
                                         const std::vector<std::vector<double>>& thresholds) {
  return horizon_walks(height, depth, dirs, max_distance, &thresholds);
}

}  // namespace msh::render
