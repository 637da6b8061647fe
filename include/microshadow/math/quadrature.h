// Deterministic 1D quadrature, the one module of the project: adaptive Gauss-Kronrod (7/15), Gauss-Legendre
// rules on [−1, 1] and on [0, 1], and the product rule against a distribution given by its CDF (the
// area-light fast forms). Nodes and sums in double precision; GaussLegendre01<T> stores them as T. Used by
// the GTR Λ table, the GGX albedo reference, the BRDF averages (F̄, Ē) and the table bakers.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace msh {

// The Gauss–Kronrod (7/15) rule on [-1, 1]: nodes x (descending, last = 0), Kronrod weights wk, Gauss weights
// wg for the odd-indexed nodes and the centre (Piessens et al. 1983, QUADPACK, qk15).
struct GaussKronrod15 {
  static constexpr int kHalf = 7;
  static constexpr std::array<double, 8> x = {
      0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
      0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
      0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
      0.207784955007898467600689403773245, 0.0};
  static constexpr std::array<double, 8> wk = {
      0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
      0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
      0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
      0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
  static constexpr std::array<double, 4> wg = {
      0.129484966168869693270611432679082, 0.279705391489276667901467239865264,
      0.381830050505118944950369775488975, 0.417959183673469387755102040816327};
};
// Adaptive Gauss–Kronrod of a function returning N values (std::array<double, N>). An interval is accepted
// when every component's |Kronrod − Gauss| ≤ tol · (its length / total length), or at max_depth.
template <size_t N, class F>
std::array<double, N> gauss_kronrod_adaptive(const F& f, double a, double b, double tol, int max_depth = 30) {
  using Arr = std::array<double, N>;
  struct Item {
    double a, b;
    int depth;
  };
  const double total = b - a;
  Arr sum{};
  if (!(total > 0)) return sum;
  Item stack[64];
  int top = 0;
  stack[top++] = {a, b, 0};
  while (top > 0) {
    const Item it = stack[--top];
    const double c = 0.5 * (it.a + it.b), h = 0.5 * (it.b - it.a);
    Arr k{}, g{};
    const Arr fc = f(c);
    for (size_t j = 0; j < N; ++j)
      k[j] = GaussKronrod15::wk[GaussKronrod15::kHalf] * fc[j],
      g[j] = GaussKronrod15::wg[GaussKronrod15::kHalf / 2] * fc[j];
    for (int i = 0; i < GaussKronrod15::kHalf; ++i) {
      const Arr f1 = f(c - h * GaussKronrod15::x[i]), f2 = f(c + h * GaussKronrod15::x[i]);
      for (size_t j = 0; j < N; ++j) {
        k[j] += GaussKronrod15::wk[i] * (f1[j] + f2[j]);
        if (i % 2 == 1) g[j] += GaussKronrod15::wg[i / 2] * (f1[j] + f2[j]);
      }
    }
    const bool forced = it.depth >= max_depth || top >= 62;
    const double local_tol = tol * (2 * h / total);
    bool ok = true;
    for (size_t j = 0; j < N; ++j) ok = ok && std::abs(h * (k[j] - g[j])) <= local_tol;
    if (ok || forced) {
      for (size_t j = 0; j < N; ++j) sum[j] += h * k[j];
    } else {
      stack[top++] = {c, it.b, it.depth + 1};
      stack[top++] = {it.a, c, it.depth + 1};
    }
  }
  return sum;
}

// Adaptive Gauss-Kronrod (7/15) on [a, b] to absolute tolerance tol: bisects while |K15 − G7| > tol (the
// tolerance halves with each split) or |K15 − G7| ≤ rel_tol·|K15| (panel-relative: also stops where round-off
// dominates), depth ≤ 30. Returns the K15 sums (error usually far below the estimate).
template <class F>
double gauss_kronrod(const F& f, double a, double b, double tol, double rel_tol = 1e-12, int depth = 0) {
  constexpr const auto& xk = GaussKronrod15::x;
  constexpr const auto& wk = GaussKronrod15::wk;
  constexpr const auto& wg = GaussKronrod15::wg;
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  double k = wk[7] * f(c), g = wg[3] * f(c);
  for (int i = 0; i < 7; ++i) {
    const double f1 = f(c - h * xk[size_t(i)]), f2 = f(c + h * xk[size_t(i)]);
    k += wk[size_t(i)] * (f1 + f2);
    if (i % 2 == 1) g += wg[size_t(i / 2)] * (f1 + f2);
  }
  k *= h, g *= h;
  // The relative floor stops the recursion where round-off, not truncation, dominates |K − G|.
  if (depth >= 30 || !std::isfinite(k) || std::abs(k - g) <= std::max(tol, rel_tol * std::abs(k))) return k;
  return gauss_kronrod(f, a, c, 0.5 * tol, rel_tol, depth + 1) +
         gauss_kronrod(f, c, b, 0.5 * tol, rel_tol, depth + 1);
}

// n-point Gauss-Legendre rule on [−1, 1] (n ≥ 1; smaller n is taken as 1), exact for polynomials of degree
// ≤ 2n − 1. Nodes x descending from near +1 to near −1; x[n−1−i] = −x[i] and w[n−1−i] = w[i] exactly. Each
// positive node by Newton iteration on P_n (three-term recurrence) from Tricomi's guess
// cos(π(i + 3/4)/(n + 1/2)), until the Newton step |Δz| < 1e-15 (Numerical Recipes §4.6, "gauleg").
struct GaussLegendre {
  std::vector<double> x, w;

  explicit GaussLegendre(int n) : x(size_t(std::max(n, 1))), w(size_t(std::max(n, 1))) {
    n = std::max(n, 1);
    const int m = (n + 1) / 2;
    for (int i = 0; i < m; ++i) {
      double z = std::cos(3.14159265358979323846 * (i + 0.75) / (n + 0.5)), pp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p1 = 1.0, p2 = 0.0;  // P_j(z), P_{j−1}(z)
        for (int j = 1; j <= n; ++j) {
          const double p3 = p2;
          p2 = p1;
          p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
        }
        pp = n * (z * p1 - p2) / (z * z - 1.0);  // P_n'(z)
        const double dz = p1 / pp;
        z -= dz;
        if (std::abs(dz) < 1e-15) break;
      }
      // For odd n the middle node is written twice; −z (the second write) is its value.
      x[size_t(i)] = z;
      x[size_t(n - 1 - i)] = -z;
      w[size_t(i)] = w[size_t(n - 1 - i)] = 2.0 / ((1.0 - z * z) * pp * pp);
    }
  }
};

// The n-point Gauss-Legendre rule mapped to [0, 1]: nodes ascending, weights summing to 1.
template <class T>
struct GaussLegendre01 {
  std::vector<T> x, w;

  explicit GaussLegendre01(int n) {
    const GaussLegendre r(n);
    x.resize(r.x.size()), w.resize(r.x.size());
    for (size_t i = 0; i < r.x.size(); ++i) x[i] = T(0.5 * (1.0 - r.x[i])), w[i] = T(0.5 * r.w[i]);
  }

  template <class F>
  auto integrate(F&& f) const {
    auto s = f(x[0]) * w[0];
    for (size_t i = 1; i < x.size(); ++i) s += f(x[i]) * w[i];
    return s;
  }
};

// ∫₀¹ f(x) dx with n Gauss-Legendre nodes.
template <class T, class F>
auto gauss_legendre_01(int n, F&& f) {
  return GaussLegendre01<T>(n).integrate(f);
}

// Gauss–Legendre rules on [0, 1] for n = 1..4 nodes (ascending) and their weights.
template <class T>
struct GaussLegendreSmall {
  static void get(int n, T* x, T* w) {
    switch (n) {
      case 1:
        x[0] = T(0.5), w[0] = T(1);
        break;
      case 2:
        x[0] = T(0.21132486540518711775), x[1] = T(0.78867513459481288225);
        w[0] = w[1] = T(0.5);
        break;
      case 3:
        x[0] = T(0.11270166537925831148), x[1] = T(0.5), x[2] = T(0.88729833462074168852);
        w[0] = w[2] = T(0.27777777777777777778), w[1] = T(0.44444444444444444444);
        break;
      default:
        x[0] = T(0.06943184420297371239), x[1] = T(0.33000947820757186760);
        x[2] = T(0.66999052179242813240), x[3] = T(0.93056815579702628761);
        w[0] = w[3] = T(0.17392742256872692869), w[1] = w[2] = T(0.32607257743127307131);
        break;
    }
  }
};

// Sorts pts[1..count−2] ascending in place, keeping both ends (the panel edges of integrate_by_ccdf: z_lo first,
// the range's top last; insertion sort, a handful of points).
template <class T>
void sort_interior(T* pts, int count) {
  for (int i = 1; i < count - 1; ++i)
    for (int j = i; j > 1 && pts[j - 1] > pts[j]; --j) std::swap(pts[j - 1], pts[j]);
}

// ∫ M dP over [z_lo, z_hi] for a distribution P on the line given by its complementary CDF S (S(z_lo) = 1,
// S(z_hi) = 0): the product rule "by parts" of docs/area-lights.md §5. The range is split at pts[0..count−1]
// (ascending; pts[0] = z_lo; points outside [z_lo, z_hi] are clamped to it, so empty panels drop out). On
// each panel [a, b] M is replaced by its interpolating polynomial Σ M(z_i) L_i(z) at the n ∈ [1, 4]
// Gauss–Legendre nodes z_i and integrated against dP exactly:
//   ∫_a^b L_i dP = L_i(a) S(a) − L_i(b) S(b) + ∫_a^b L_i'(z) S(z) dz,
// the last integral by the same n-point rule. S is only ever evaluated, never differentiated, so P may have
// integrable singular densities (a square-root edge) inside S. Put M's kinks at panel edges: within a panel
// the rule is exact for M of degree < n and S of degree ≤ n. Cost per panel: n evaluations of M, n + 1 of S.
template <class T, class F, class S>
T integrate_by_ccdf(F&& M, S&& ccdf, const T* pts, int count, T z_hi, int n = 4) {
  n = std::clamp(n, 1, 4);
  T x[4], w[4], L0[4], L1[4], D[4][4];
  GaussLegendreSmall<T>::get(n, x, w);
  for (int i = 0; i < n; ++i) {  // Lagrange basis at 0 and 1, and its derivative at the nodes
    L0[i] = L1[i] = T(1);
    for (int q = 0; q < n; ++q)
      if (q != i) L0[i] *= (T(0) - x[q]) / (x[i] - x[q]), L1[i] *= (T(1) - x[q]) / (x[i] - x[q]);
    for (int j = 0; j < n; ++j) {
      T d = T(0);
      for (int m = 0; m < n; ++m) {
        if (m == i) continue;
        T p = T(1) / (x[i] - x[m]);
        for (int q = 0; q < n; ++q)
          if (q != i && q != m) p *= (x[j] - x[q]) / (x[i] - x[q]);
        d += p;
      }
      D[j][i] = d;
    }
  }
  const T z_lo = pts[0];
  T sum = T(0), a = z_lo, Sa = T(1);
  for (int p = 1; p < count; ++p) {
    const T b = pts[p] > z_lo ? std::min(pts[p], z_hi) : z_lo;
    if (!(b > a)) continue;
    const T h = b - a, Sb = ccdf(b);
    T Sj[4], Mj[4];
    for (int j = 0; j < n; ++j) Sj[j] = ccdf(a + h * x[j]), Mj[j] = M(a + h * x[j]);
    for (int i = 0; i < n; ++i) {
      T W = L0[i] * Sa - L1[i] * Sb;
      for (int j = 0; j < n; ++j) W += w[j] * D[j][i] * Sj[j];
      sum += W * Mj[i];
    }
    a = b, Sa = Sb;
  }
  return sum;
}

}  // namespace msh
