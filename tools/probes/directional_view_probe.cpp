// How much of the directional term's error in the study is the data model's floor: the view–light
// correlation (docs/directional-occlusion.md, "View–light correlation"). In texture space, on the procedural
// height fields, exact horizons (bake_horizon_tangents_lattice) and central-difference normals n:
//
//   f(x)  = lit_l(x) · (n · l)⁺                       the diffuse transport the 9 channels fit
//   w(x)  = vis_v(x) · (n · v)⁺ / n_z                 screen area per flat area seen by an orthographic
//                                                      camera along v (vis_v: not masked toward v)
//   GT    = Σ f w / Σ w                               what the camera's pixels average
//   a     = Σ f / N                                   the best any view-independent per-texel data gives
//   b     = Σ f (n · v) / (n_z v_z) / N               a + (E[f s_x] v_x + E[f s_y] v_y) / v_z, s = (n_x, n_y)
//   / n_z:
//                                                      projected area without masking, from two more linear
//                                                      functions of l (E[s] = 0 on a wrapping field, so Σ w
//                                                      without masking is N v_z exactly)
//   c     = Σ f (n · v)⁺ / n_z / Σ (n · v)⁺ / n_z     GT without the masking
//
// It prints a / GT, b / GT and c / GT per material and light (the light and view as in the study: lights at
// azimuth 0° and 90°, the camera at view_elevation looking along +v, i.e. v at azimuth −90°), and the mean
// and max |ratio − 1| per material. A flat field gives exactly 1 everywhere (tests/test_area_probes.cpp runs
// it). Whole-texture means: the scale k does not enter (the study's per-pixel shading does; this is the
// floor).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/texture_gen.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

using namespace msh;
using namespace msh::render;

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;

struct Row {
  std::string kind;
  double elev = 0, az = 0, gt = 0, a = 0, b = 0, c = 0;
  // With --fits: the same a and b from the fitted functions (the fit grid of the bake): a9 = T by the 9
  // channels; b94 / b96 / b99 = a9 plus G_x, G_y each fitted with 4 (band 1: 1, x, y, z) / 6 (band 1 + xz,
  // yz) / 9 (degree 2) functions.
  double a9 = 0, b94 = 0, b96 = 0, b99 = 0;
  // Grazing-view candidates (see candidates()): the inputs. Exact: the slope covariance of the field
  // (s = (n_x, n_y)/n_z; what a LEAN-style second-moment map holds), sxx, sxy, syy. Fitted (with --fits): the
  // 9-channel T (= a9), g6 = G_x v_x + G_y v_y from the 6-function slope channels (the shipped data) and the
  // slope covariance read off those channels: cxx = G_x's x coefficient, cyy = G_y's y coefficient, cxy =
  // the mean of G_x's y and G_y's x coefficients (≈ E[n_z s sᵀ]; no new data).
  double sxx = 0, sxy = 0, syy = 0, nxx = 0, nxy = 0, nyy = 0, g6 = 0, cxx = 0, cxy = 0, cyy = 0;
  std::vector<std::pair<std::string, double>> cand;  // name, value (ratio to GT taken when printed)
};

// Weighted least squares on the bake's direction grid: the coefficients of the first nb poly2 functions
// fitted to samples f[d] (normal equations, Gaussian elimination with partial pivoting, double).
std::vector<double> fit_poly2(const std::vector<Vec3d>& dirs, const std::vector<double>& wts,
                              const std::vector<double>& f, int nb) {
  std::vector<double> G(std::size_t(nb) * (nb + 1), 0.0);
  auto g = [&](int r, int c) -> double& { return G[std::size_t(r) * (nb + 1) + c]; };
  for (std::size_t d = 0; d < dirs.size(); ++d) {
    double b[directional::kPoly2Terms];
    directional::poly2_basis(dirs[d], b);
    for (int r = 0; r < nb; ++r) {
      for (int c = 0; c < nb; ++c) g(r, c) += wts[d] * b[r] * b[c];
      g(r, nb) += wts[d] * b[r] * f[d];
    }
  }
  for (int c = 0; c < nb; ++c) {
    int piv = c;
    for (int r = c + 1; r < nb; ++r)
      if (std::abs(g(r, c)) > std::abs(g(piv, c))) piv = r;
    for (int k = 0; k <= nb; ++k) std::swap(g(c, k), g(piv, k));
    for (int r = c + 1; r < nb; ++r) {
      const double m = g(r, c) / g(c, c);
      for (int k = c; k <= nb; ++k) g(r, k) -= m * g(c, k);
    }
  }
  std::vector<double> x(static_cast<std::size_t>(nb));
  for (int r = nb - 1; r >= 0; --r) {
    double acc = g(r, nb);
    for (int k = r + 1; k < nb; ++k) acc -= g(r, k) * x[std::size_t(k)];
    x[std::size_t(r)] = acc / g(r, r);
  }
  return x;
}

double eval_poly2(const std::vector<double>& c, const Vec3d& l) {
  double b[directional::kPoly2Terms];
  directional::poly2_basis(l, b);
  double s = 0;
  for (std::size_t i = 0; i < c.size(); ++i) s += c[i] * b[i];
  return s;
}

// The whole-texture means T(l) = E[f], G_x(l) = E[f s_x], G_y(l) = E[f s_y] on the bake's direction grid
// (32 lattice azimuths × kFitElevations), fitted; the box mean of per-texel fits is this fit (linearity).
void add_fits(const Texture& height, float depth, const std::vector<Vec3f>& n, double view_elev,
              std::vector<Row>& rows, std::size_t first) {
  const DirectionalBakeAzimuths az = directional_bake_azimuths(32);
  const auto T = bake_horizon_tangents_lattice(height, depth, az.steps);
  const std::size_t na = az.steps.size(), N = n.size();
  const int ne = directional::kFitElevations;
  std::vector<Vec3d> dirs;
  std::vector<double> wts, ft, fx, fy;
  for (std::size_t a = 0; a < na; ++a)
    for (int j = 0; j < ne; ++j) {
      const double e = (j + 0.5) / ne * 90 * kDeg;
      const Vec3d l(std::cos(e) * az.dirs[a].x, std::cos(e) * az.dirs[a].y, std::sin(e));
      const double tan_e = std::tan(e);
      double st = 0, sx = 0, sy = 0;
      for (std::size_t p = 0; p < N; ++p) {
        if (!(tan_e > T[p * na + a])) continue;
        const double f = std::max(double(n[p].x) * l.x + double(n[p].y) * l.y + double(n[p].z) * l.z, 0.0);
        st += f, sx += f * n[p].x / n[p].z, sy += f * n[p].y / n[p].z;
      }
      dirs.push_back(l);
      wts.push_back(std::cos(e) * directional::fit_weight(std::sin(e)) * az.weights[a]);
      ft.push_back(st / double(N)), fx.push_back(sx / double(N)), fy.push_back(sy / double(N));
    }
  const auto ct = fit_poly2(dirs, wts, ft, 9), cx4 = fit_poly2(dirs, wts, fx, 4),
             cy4 = fit_poly2(dirs, wts, fy, 4), cx6 = fit_poly2(dirs, wts, fx, 6),
             cy6 = fit_poly2(dirs, wts, fy, 6), cx9 = fit_poly2(dirs, wts, fx, 9),
             cy9 = fit_poly2(dirs, wts, fy, 9);
  const double ve = view_elev * kDeg, vx = 0, vy = -std::cos(ve), vz = std::sin(ve);
  for (std::size_t i = first; i < rows.size(); ++i) {
    Row& r = rows[i];
    const double e = r.elev * kDeg, a = r.az * kDeg;
    const Vec3d l(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
    r.a9 = eval_poly2(ct, l);
    r.b94 = r.a9 + (eval_poly2(cx4, l) * vx + eval_poly2(cy4, l) * vy) / vz;
    r.b96 = r.a9 + (eval_poly2(cx6, l) * vx + eval_poly2(cy6, l) * vy) / vz;
    r.b99 = r.a9 + (eval_poly2(cx9, l) * vx + eval_poly2(cy9, l) * vy) / vz;
    r.g6 = eval_poly2(cx6, l) * vx + eval_poly2(cy6, l) * vy;
    r.cxx = cx6[1], r.cyy = cy6[2], r.cxy = 0.5 * (cx6[2] + cy6[1]);
  }
}

// The lattice step of an azimuth that is a multiple of 45 degrees (axes and diagonals: exact horizons).
LatticeStep axis_step(double az) {
  if (std::abs(az - 45.0 * std::lround(az / 45.0)) > 1e-9)
    throw InputError("azimuths must be multiples of 45");
  static const LatticeStep steps[8] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
  return steps[std::lround(az / 45.0) & 7];
}

std::vector<Row> measure(const Texture& height, float depth, const std::string& kind,
                         const std::vector<double>& elevations, const std::vector<double>& azimuths,
                         double view_elev, bool fits) {
  const int w = height.width(), h = height.height();
  const std::size_t N = std::size_t(w) * h;
  std::vector<LatticeStep> steps;
  for (double az : azimuths) steps.push_back(axis_step(az));
  steps.push_back({0, -1});  // toward the camera
  const auto T = bake_horizon_tangents_lattice(height, depth, steps);
  const std::size_t ns = steps.size(), iv = ns - 1;
  const HeightField hf(height, depth);
  std::vector<Vec3f> n(N);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) n[std::size_t(j) * w + i] = hf.vertex_normal(i, j);
  const double ve = view_elev * kDeg;
  const Vec3f v(0.0f, float(-std::cos(ve)), float(std::sin(ve)));
  const double tan_v = std::tan(ve);
  std::vector<Row> rows;
  for (std::size_t ai = 0; ai < azimuths.size(); ++ai)
    for (double e : elevations) {
      const double az = azimuths[ai] * kDeg, er = e * kDeg;
      const Vec3f l(float(std::cos(er) * std::cos(az)), float(std::cos(er) * std::sin(az)),
                    float(std::sin(er)));
      const double tan_l = std::tan(er);
      double sf = 0, sfw = 0, sw = 0, sb = 0, sfc = 0, swc = 0, qxx = 0, qxy = 0, qyy = 0, mxx = 0, mxy = 0,
             myy = 0, mzz = 0;
      for (std::size_t p = 0; p < N; ++p) {
        const double f = tan_l > T[p * ns + ai] ? std::max(double(dot(n[p], l)), 0.0) : 0.0;
        const double nv = dot(n[p], v), nz = n[p].z;
        const double wc = std::max(nv, 0.0) / nz, wm = tan_v > T[p * ns + iv] ? wc : 0.0;
        sf += f, sfw += f * wm, sw += wm, sb += f * nv / (nz * v.z), sfc += f * wc, swc += wc;
        const double px = n[p].x / nz, py = n[p].y / nz;
        qxx += px * px, qxy += px * py, qyy += py * py;
        mxx += double(n[p].x) * n[p].x, mxy += double(n[p].x) * n[p].y, myy += double(n[p].y) * n[p].y,
            mzz += nz * nz;
      }
      const double gt = sw > 0 ? sfw / sw : 0;
      Row r;
      r.kind = kind, r.elev = e, r.az = azimuths[ai], r.gt = gt, r.a = sf / double(N), r.b = sb / double(N);
      r.c = swc > 0 ? sfc / swc : 0;
      r.sxx = qxx / double(N), r.sxy = qxy / double(N), r.syy = qyy / double(N);
      // normal-based slope covariance E[n_h n_hᵀ]/E[n_z²] (what a Toksvig/LEAN-style normal variance gives)
      r.nxx = mxx / mzz, r.nxy = mxy / mzz, r.nyy = myy / mzz;
      rows.push_back(r);
    }
  if (fits) add_fits(height, depth, n, view_elev, rows, 0);
  return rows;
}

// The standard normal pdf and cdf, and R(m, s) = E[(m + s Z)⁺] for Z ~ N(0, 1) (= max(m, 0) at s = 0).
double npdf(double x) { return 0.3989422804014327 * std::exp(-0.5 * x * x); }
double ncdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }
double ramp_mean(double m, double s) {
  if (!(s > 1e-12)) return std::max(m, 0.0);
  return m * ncdf(m / s) + s * npdf(m / s);
}
// Smith's Λ for Gaussian slopes (Beckmann) of std σ along the direction's azimuth, from cos θ = z:
// R(z, σ sin θ)/z − 1 (Heitz 2014, eq. 72-73 with α = √2 σ).
double smith_lambda(double z, double sigma) {
  const double st = std::sqrt(std::max(1 - z * z, 0.0));
  return ramp_mean(z, sigma * st) / z - 1;
}

// Grazing-view candidates, all from the fitted data the run time has (T by the 9 channels, G by the 6 + 6)
// unless named "exact" (exact whole-texture T and G, to separate the model from the fit). v = the view as in
// measure(): azimuth -90°, elevation view_elev. g = G_x v_x + G_y v_y. Shipped: max(0, T + g / max(v_z,
// 0.1)).
void candidates(std::vector<Row>& rows, double view_elev) {
  const double ve = view_elev * kDeg, vz = std::sin(ve), sv = std::cos(ve);  // sin θ_v = cos(elevation)
  for (Row& r : rows) {
    const double t = r.a9, g = r.g6, te = r.a, ge = (r.b - r.a) * vz;
    const double la = r.az * kDeg, lc = std::cos(la), ls = std::sin(la), lz = std::sin(r.elev * kDeg);
    auto var_along = [](double xx, double xy, double yy, double c, double s) {
      return std::max(xx * c * c + 2 * xy * c * s + yy * s * s, 0.0);
    };
    // view azimuth (0, -1): σ_v² = Σ_yy
    const double sig_v_exact = std::sqrt(r.syy), sig_v_chan = std::sqrt(std::max(r.cyy, 0.0));
    const double sig_l_exact = std::sqrt(var_along(r.sxx, r.sxy, r.syy, lc, ls)),
                 sig_l_chan = std::sqrt(var_along(r.cxx, r.cxy, r.cyy, lc, ls));
    auto& c = r.cand;
    c.clear();
    auto clamp_form = [&](double vmin) { return std::max(t + g / std::max(vz, vmin), 0.0); };
    c.push_back({"shipped (v_z>=0.1)", clamp_form(0.1)});
    c.push_back({"T alone", std::max(t, 0.0)});
    c.push_back({"clamp 0.2", clamp_form(0.2)});
    c.push_back({"clamp 0.3", clamp_form(0.3)});
    c.push_back({"clamp 0.5", clamp_form(0.5)});
    // fade: T + g v_z / max(v_z, v0)²: 1/v_z above v0, → 0 linearly below
    for (double v0 : {0.3, 0.5}) {
      const double m = std::max(vz, v0);
      c.push_back({fmt::format("fade {:g}", v0), std::max(t + g * vz / (m * m), 0.0)});
    }
    // Smith: R(T v_z + g, T σ_v sin θ_v) / R(v_z, σ_v sin θ_v)
    auto smith = [&](double tt, double gg, double sig) {
      return ramp_mean(tt * vz + gg, std::max(tt, 0.0) * sig * sv) / ramp_mean(vz, sig * sv);
    };
    // height-correlated masking-shadowing (Heitz 2014 eq. 99 over the separable form):
    // κ = (1 + Λ_v)(1 + Λ_l) / (1 + Λ_v + Λ_l)
    auto kappa = [&](double sig_v, double sig_l) {
      const double lv = smith_lambda(vz, sig_v), ll = smith_lambda(lz, sig_l);
      return (1 + lv) * (1 + ll) / (1 + lv + ll);
    };
    (void)sig_l_exact, (void)sig_l_chan;
    c.push_back({"smith sigma E[s2]", smith(t, g, sig_v_exact)});
    c.push_back({"smith sigma exact T,G", smith(te, ge, std::sqrt(r.nyy))});
    c.push_back({"smith sigma chan", smith(t, g, sig_v_chan)});
    const double sig_v_n = std::sqrt(r.nyy), sig_l_n = std::sqrt(var_along(r.nxx, r.nxy, r.nyy, lc, ls));
    c.push_back({"smith sigma normals (view az)", smith(t, g, sig_v_n)});
    c.push_back({"smith+hc sigma normals", smith(t, g, sig_v_n) * kappa(sig_v_n, sig_l_n)});
    // the same with a logistic ramp (softplus) instead of the Gaussian one: R ≈ (s/k) ln(1 + exp(k m/s)),
    // k = ln 2/φ(0) (equal at m = 0): one exp and one log per ramp in a shader
    auto soft = [](double m, double sd) {
      if (!(sd > 1e-12)) return std::max(m, 0.0);
      const double k = 1.7374, x = k * m / sd;
      return sd / k * (x > 30 ? x : std::log1p(std::exp(x)));
    };
    c.push_back({"softplus sigma normals (view az)",
                 soft(t * vz + g, std::max(t, 0.0) * sig_v_n * sv) / soft(vz, sig_v_n * sv)});
    c.push_back({"smith sigma normals iso", smith(t, g, std::sqrt(0.5 * (r.nxx + r.nyy)))});
    for (double sg : {0.25, 0.35, 0.5}) c.push_back({fmt::format("smith sigma={:g}", sg), smith(t, g, sg)});
  }
}

// --clamp-scales: the clamp's share of the error at small k. The 9-channel fit is linear, so the box mean of
// the channels over a k × k footprint is the fit of the footprint's mean transport; the run time clamps
// max(0, ·) after the fetch. At k = 1 a shadowed texel's fit is negative (a degree-2 polynomial cannot hold a
// step at the horizon) and the clamp raises it; at larger k the negative and positive lobes cancel before
// the clamp. Printed per material and light: the mean over the footprints of max(0, fit) at k = 1, 2, 4, 8,
// 16 over the mean exact transport, and the unclamped fit's (the same at every k: the fit of the mean).
void clamp_scales(const std::vector<std::string>& kinds, int size, const std::vector<double>& el,
                  const std::vector<double>& az) {
  const int ks[] = {1, 2, 4, 8, 16};
  std::cout << "| material | light (elev/az) | unclamped fit / exact |";
  for (int k : ks) std::cout << fmt::format(" k = {} |", k);
  std::cout << " negative texels |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& kind : kinds) {
    GenOptions g;
    g.kind = kind, g.size = size, g.ao_rays = 1, g.ao_max_distance = 0.5f, g.directional_azimuths = 0;
    const TextureSet s = generate_texture_set(g);
    const Texture ch = bake_directional_channels(s.height, s.depth_texels, 32, 0);
    for (double e : el)
      for (double a : az) {
        const Vec3f l(float(std::cos(e * kDeg) * std::cos(a * kDeg)),
                      float(std::cos(e * kDeg) * std::sin(a * kDeg)), float(std::sin(e * kDeg)));
        const Texture f = exact_diffuse_transport(s.height, s.depth_texels, l, 0);
        double exact = 0, raw = 0;
        long negative = 0;
        for (int y = 0; y < size; ++y)
          for (int x = 0; x < size; ++x) {
            exact += f.at(x, y, 0);
            double b[directional::kPoly2Terms];
            directional::poly2_basis(Vec3d(l.x, l.y, l.z), b);
            double t = 0;
            for (int i = 0; i < directional::kPoly2Terms; ++i) t += ch.at(x, y, i) * b[i];
            raw += t, negative += t < 0;
          }
        std::cout << fmt::format("| {} | {:g}/{:g} | {:.3f} |", kind, e, a, raw / exact);
        for (int k : ks) {
          if (size % k) continue;
          double sum = 0;
          for (int by = 0; by < size / k; ++by)
            for (int bx = 0; bx < size / k; ++bx) {
              double c[directional::kPoly2Terms] = {};
              for (int y = by * k; y < (by + 1) * k; ++y)
                for (int x = bx * k; x < (bx + 1) * k; ++x)
                  for (int i = 0; i < directional::kPoly2Terms; ++i) c[i] += ch.at(x, y, i);
              sum +=
                  directional::directional_transport(c, Vec3d(l.x, l.y, l.z));  // k² × the clamped block mean
            }
          std::cout << fmt::format(" {:.3f} |", sum / exact);
        }
        std::cout << fmt::format(" {:.1f} % |\n", 100.0 * double(negative) / (double(size) * size));
      }
  }
}

std::vector<double> parse_list(const std::string& s, const char* what) {
  std::vector<double> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      out.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InputError(fmt::format("{}: '{}' is not a number", what, item));
    }
  }
  if (out.empty()) throw InputError(fmt::format("{}: empty list", what));
  return out;
}

// The rows as JSON (ratios to the ground truth).
void print_json(const std::vector<Row>& rows, int size, double view_elev, bool fits) {
  nlohmann::json j;
  j["size"] = size, j["view_elevation"] = view_elev;
  for (const Row& r : rows)
    j["rows"].push_back({{"kind", r.kind},
                         {"elevation", r.elev},
                         {"azimuth", r.az},
                         {"gt", r.gt},
                         {"view_independent", r.gt > 0 ? r.a / r.gt : 0},
                         {"slope_corrected", r.gt > 0 ? r.b / r.gt : 0},
                         {"no_masking", r.gt > 0 ? r.c / r.gt : 0},
                         {"fit9", r.gt > 0 ? r.a9 / r.gt : 0},
                         {"fit9_slope4", r.gt > 0 ? r.b94 / r.gt : 0},
                         {"fit9_slope6", r.gt > 0 ? r.b96 / r.gt : 0},
                         {"fit9_slope9", r.gt > 0 ? r.b99 / r.gt : 0}});
  if (fits)
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (const auto& [name, value] : rows[i].cand)
        j["rows"][i]["candidates"][name] = rows[i].gt > 0 ? value / rows[i].gt : 0;
  std::cout << j.dump(1) << "\n";
}

// The rows as Markdown: the ratio to the ground truth of each form per light (unless summary), then the mean
// (max) |ratio - 1| per material, and with fits the slope covariances.
void print_tables(const std::vector<Row>& rows, double view_elev, bool fits, bool cand_only, bool summary) {
  // Columns: ratio to GT of each form.
  struct Col {
    std::string name;
    std::function<double(const Row&)> v;
  };
  std::vector<Col> cols;
  auto member = [](double Row::*m) { return [m](const Row& r) { return r.*m; }; };
  if (!cand_only) {
    cols = {{"view-independent a", member(&Row::a)},
            {"slope-corrected b", member(&Row::b)},
            {"unmasked c", member(&Row::c)}};
    if (fits) {
      cols.push_back({"9-channel fit", member(&Row::a9)});
      cols.push_back({"fit + slope band 1 (+8)", member(&Row::b94)});
      cols.push_back({"fit + slope 6 functions (+12)", member(&Row::b96)});
      cols.push_back({"fit + slope degree 2 (+18)", member(&Row::b99)});
    }
  } else {
    cols.push_back({"unmasked c (exact)", member(&Row::c)});
    for (std::size_t q = 0; q < rows.front().cand.size(); ++q)
      cols.push_back({rows.front().cand[q].first, [q](const Row& r) { return r.cand[q].second; }});
  }
  std::string head = "| material | light (elev/az) |", rule = "|---|---|";
  for (const Col& c : cols) head += fmt::format(" {} / GT |", c.name), rule += "---|";
  if (!summary) {
    std::cout << head << "\n" << rule << "\n";
    for (const Row& r : rows) {
      std::cout << fmt::format("| {} | {:g}/{:g} (GT {:.4f}) |", r.kind, r.elev, r.az, r.gt);
      for (const Col& c : cols) std::cout << fmt::format(" {:.3f} |", c.v(r) / r.gt);
      std::cout << "\n";
    }
    std::cout << "\n";
  }
  std::cout << "mean (max) |ratio - 1| over the lights, view elevation " << view_elev << "\n\n| material |";
  for (const Col& c : cols) std::cout << " " << c.name << " |";
  std::cout << "\n" << rule.substr(4) << "\n";
  std::vector<double> am(cols.size()), ax(cols.size());
  std::size_t nk = 0;
  for (std::size_t i = 0; i < rows.size();) {
    std::size_t j = i;
    std::vector<double> m(cols.size()), x(cols.size());
    for (; j < rows.size() && rows[j].kind == rows[i].kind; ++j)
      for (std::size_t q = 0; q < cols.size(); ++q) {
        const double d = std::abs(cols[q].v(rows[j]) / rows[j].gt - 1);
        m[q] += d, x[q] = std::max(x[q], d);
      }
    std::cout << "| " << rows[i].kind << " |";
    for (std::size_t q = 0; q < cols.size(); ++q) {
      std::cout << fmt::format(" {:.3f} ({:.3f}) |", m[q] / double(j - i), x[q]);
      am[q] += m[q] / double(j - i), ax[q] = std::max(ax[q], x[q]);
    }
    std::cout << "\n";
    ++nk;
    i = j;
  }
  std::cout << "| **all** |";
  for (std::size_t q = 0; q < cols.size(); ++q)
    std::cout << fmt::format(" {:.3f} ({:.3f}) |", am[q] / double(nk), ax[q]);
  std::cout << "\n";
  if (fits) {
    std::cout << "\nslope covariance, exact (E[s sT]) and read off the slope channels (xx, xy, yy)\n";
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (i == 0 || rows[i].kind != rows[i - 1].kind)
        std::cout << fmt::format(
            "{}: exact {:.4f} {:.4f} {:.4f}; normals {:.4f} {:.4f} {:.4f}; channels {:.4f} {:.4f} {:.4f}\n",
            rows[i].kind, rows[i].sxx, rows[i].sxy, rows[i].syy, rows[i].nxx, rows[i].nxy, rows[i].nyy,
            rows[i].cxx, rows[i].cxy, rows[i].cyy);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Directional micro-occlusion: the view-light correlation floor in texture space (whole-texture means "
      "of "
      "the exact transport, with and without the camera's projected area and masking; "
      "docs/directional-occlusion.md)"};
  std::string kinds = "plaster,bark,gravel,rock,brick,cobble", elevations = "5,10,25,45,70",
              azimuths = "0,90";
  int size = 512;
  double view_elev = 60;
  bool json = false, flat = false, fits = false, cand_only = false, summary = false;
  app.add_option("--kinds", kinds, "Comma-separated material kinds")->capture_default_str();
  app.add_option("--size", size, "Texels per side")->check(CLI::Range(8, 8192))->capture_default_str();
  app.add_option("--elevations", elevations, "Light elevations, degrees")->capture_default_str();
  app.add_option("--azimuths", azimuths, "Light azimuths, multiples of 45 degrees")->capture_default_str();
  app.add_option("--view-elevation", view_elev, "Camera elevation, degrees, looking along +v")
      ->check(CLI::Range(1.0, 89.0))
      ->capture_default_str();
  app.add_flag("--flat", flat, "A flat field instead of the kinds (every ratio is 1)");
  app.add_flag(
      "--fits", fits,
      "Also the fitted forms: T by the 9 channels, and T plus the slope-weighted G_x, G_y fitted with 4 "
      "or 9 functions each");
  app.add_flag(
      "--candidates", cand_only,
      "Grazing-view candidate forms only (implies --fits): the shipped form, T alone, v_z clamps, fades, "
      "Smith-normalised forms");
  app.add_flag("--summary", summary, "Only the mean (max) table");
  bool clamp = false;
  app.add_flag("--clamp-scales", clamp,
               "The run-time clamp max(0, fit) per footprint at k = 1-16 against the exact mean transport "
               "(view-independent; what the fit's clamp adds at small k)");
  app.add_flag("--json", json, "Print the rows as JSON");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (cand_only) fits = true;
    const auto el = parse_list(elevations, "--elevations"), az = parse_list(azimuths, "--azimuths");
    for (double e : el)
      if (!(e > 0 && e < 90)) throw InputError(fmt::format("--elevations: {} is not in (0, 90)", e));
    if (clamp) {
      std::vector<std::string> ks;
      std::stringstream cs(kinds);
      for (std::string k; std::getline(cs, k, ',');) ks.push_back(k);
      clamp_scales(ks, size, el, az);
      return 0;
    }
    std::vector<Row> rows;
    if (flat) {
      rows = measure(Texture(size, size, 1), 4.0f, "flat", el, az, view_elev, fits);
    } else {
      std::stringstream ss(kinds);
      std::string kind;
      while (std::getline(ss, kind, ',')) {
        GenOptions g;
        g.kind = kind, g.size = size, g.ao_rays = 1, g.ao_max_distance = 0.5f, g.directional_azimuths = 0;
        const TextureSet s = generate_texture_set(g);
        const auto r = measure(s.height, s.depth_texels, kind, el, az, view_elev, fits);
        rows.insert(rows.end(), r.begin(), r.end());
      }
    }
    if (fits) candidates(rows, view_elev);
    if (json)
      print_json(rows, size, view_elev, fits);
    else
      print_tables(rows, view_elev, fits, cand_only, summary);
  } catch (const std::exception& e) {
    std::cerr << "directional_view_probe: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
