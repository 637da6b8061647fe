// The research harness of tools/research/directional_study.h.
#include "directional_study.h"

#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/texture_gen.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "render/directional_bake_detail.h"

namespace msh::research {

namespace dir = msh::directional;
using namespace msh::render;
using namespace msh::render::detail;

namespace {

constexpr double kDeg = kPi<double> / 180.0;

Vec3f light_dir(double elev_deg, Vec2f az) {
  const double ce = std::cos(elev_deg * kDeg), se = std::sin(elev_deg * kDeg);
  return Vec3f(float(ce * az.x), float(ce * az.y), float(se));
}

Vec2f azimuth_dir(double az_deg) {
  // Exact axes for the measured azimuths 0° and 90° (the walks then follow grid lines exactly).
  if (az_deg == 0) return Vec2f(1, 0);
  if (az_deg == 90) return Vec2f(0, 1);
  return Vec2f(float(std::cos(az_deg * kDeg)), float(std::sin(az_deg * kDeg)));
}

struct Rep {
  std::string name;
  int bytes;
};

// Representations, in table order. Channel counts at 8 bits each (the coarse normal is the engine's normal
// map and not counted).
const std::vector<Rep>& reps() {
  static const std::vector<Rep> r = {{"ao", 1},
                                     {"reference", 1},
                                     {"chan-2018", 1},
                                     {"bent-cone", 4},
                                     {"sh1-lsq", 4},
                                     {"poly2-lsq", 9},
                                     {"poly2-lsq-eps0.03", 9},
                                     {"poly2-lsq-eps0.3", 9},
                                     {"poly12-lsq", 12},
                                     {"poly12-lsq-eps0.03", 12},
                                     {"resid-poly2-p1", 12},
                                     {"resid-poly2-p1-unit", 9},
                                     {"resid-poly2-p1-eps0.01", 12},
                                     {"resid-poly2-p2", 12},
                                     {"horizon-fourier", 5},
                                     {"hm-lit-cos", 10},
                                     {"hm-transport", 10}};
  return r;
}

struct Fine {
  int w = 0, h = 0;
  std::vector<Vec3f> n;
  Texture chans;  // per texel: V, bent (3), sh1 (4), poly2 (9), hm (10) = 27
};

constexpr int kChV = 0, kChBent = 1, kChSh1 = 4, kChPoly2 = 8, kChHm = 17, kChPoly2a = 27, kChPoly2b = 36,
              kChPoly12 = 45, kChPoly12a = 57, kChResid1 = 69, kChResid2 = 78, kChNmean = 87, kChResid3 = 90,
              kChCount = 99;

Texture bake_all_channels(const Texture& height, const std::vector<Vec2f>& dirs,
                          const std::vector<float>& tan_h, const std::vector<Vec3f>& n,
                          const std::vector<std::pair<const LsqProjection*, int>>& lsq) {
  const int w = height.width(), h = height.height(), na = int(dirs.size());
  Texture out(w, h, kChCount);
  tbb::parallel_for(0, h, [&](int j) {
    const LsqProjection& p2 = *lsq[0].first;
    std::vector<float> f(p2.dirs.size());
    for (int i = 0; i < w; ++i) {
      const std::size_t p = std::size_t(j) * w + i;
      const float* th = &tan_h[p * std::size_t(na)];
      double V = 0;
      Vec3d bent(0, 0, 0);
      for (int a = 0; a < na; ++a) {
        const double t = th[a];
        V += 1.0 / (1.0 + t * t);
        bent += dir::bent_vector_azimuth<double>(t, dirs[a].x, dirs[a].y);
      }
      float* o = &out.at(i, j, 0);
      o[kChV] = float(V / na);
      o[kChBent] = float(bent.x / na), o[kChBent + 1] = float(bent.y / na),
      o[kChBent + 2] = float(bent.z / na);
      for (int a = 0; a < na; ++a)
        for (int e = 0; e < p2.ne; ++e) {
          const int d = a * p2.ne + e;
          f[std::size_t(d)] = transport_texel(th[a], n[p], p2.dirs[std::size_t(d)]);
        }
      const int nd = int(f.size());
      for (const auto& [proj, first] : lsq)
        for (int r = 0; r < proj->nb; ++r) {
          double sum = 0;
          for (int d = 0; d < nd; ++d) {
            const double fd =
                proj->damp ? f[std::size_t(d)] - dot(n[p], p2.dirs[std::size_t(d)]) : f[std::size_t(d)];
            sum += double(proj->P[std::size_t(r) * nd + d]) * fd;
          }
          o[first + r] = float(sum);
        }
      horizon_channels(th, n[p], dirs, o + kChHm);
      o[kChNmean] = n[p].x, o[kChNmean + 1] = n[p].y, o[kChNmean + 2] = n[p].z;
    }
  });
  return out;
}

// 8-bit storage of the channels (channel_ranges): the same ranges for every mip level, quantised again after
// the box mean.
using Ranges = ChannelRanges;
void quantize_channels(Texture& t, const Ranges& r) {
  for (int j = 0; j < t.height(); ++j)
    for (int i = 0; i < t.width(); ++i)
      for (int c = 0; c < t.channels(); ++c)
        t.at(i, j, c) = quantize8(t.at(i, j, c), r.lo[std::size_t(c)], r.hi[std::size_t(c)]);
}

float eval_rep(const std::string& rep, const float* ch, const Vec3f& nc, const Vec3f& l) {
  if (rep.rfind("resid-poly2", 0) == 0) {
    const bool unit = rep.find("-unit") != std::string::npos;  // the renormalised coarse normal instead
    const int power = rep[std::string("resid-poly2-p").size()] - '0';
    float b[dir::kPoly2Terms];
    dir::poly2_basis(l, b);
    const float* d = ch + (rep.find("eps0.01") != std::string::npos ? kChResid3
                           : power == 1                             ? kChResid1
                                                                    : kChResid2);
    float s = 0;
    for (int m = 0; m < dir::kPoly2Terms; ++m) s += d[m] * b[m];
    const Vec3f nm(ch[kChNmean], ch[kChNmean + 1], ch[kChNmean + 2]);  // stored (and quantised) mean normal
    return std::max(dot(unit ? nc : nm, l) + s * std::pow(1 - l.z, float(power)), 0.0f);
  }
  const float nl = std::max(dot(nc, l), 0.0f);
  const float V = std::clamp(ch[kChV], 0.0f, 1.0f), cos_t = std::sqrt(1 - V);
  if (rep == "ao") return V * nl;
  if (rep == "reference") return nl > cos_t ? nl : 0.0f;
  if (rep == "chan-2018") {
    const float x = cos_t > 0 ? std::min(nl / cos_t, 1.0f) : 1.0f;
    return x * x * nl;
  }
  if (rep == "bent-cone") {
    Vec3f b(ch[kChBent], ch[kChBent + 1], ch[kChBent + 2]);
    const float len = std::sqrt(dot(b, b));
    b = len > 0 ? b / len : Vec3f(0, 0, 1);
    return dot(b, l) > cos_t ? nl : 0.0f;
  }
  if (rep == "poly2-lsq-eps0.03") return dir::directional_transport(ch + kChPoly2a, l);  // the shipped one
  if (rep.find("-lsq") != std::string::npos) {
    float b[dir::kPoly12Terms];
    dir::poly12_basis(l, b);
    const int first = rep == "sh1-lsq"             ? kChSh1
                      : rep == "poly2-lsq"         ? kChPoly2
                      : rep == "poly2-lsq-eps0.03" ? kChPoly2a
                      : rep == "poly2-lsq-eps0.3"  ? kChPoly2b
                      : rep == "poly12-lsq"        ? kChPoly12
                                                   : kChPoly12a;
    const int nb = first == kChSh1 ? 4 : first >= kChPoly12 ? 12 : 9;
    float s = 0;
    for (int m = 0; m < nb; ++m) s += ch[first + m] * b[m];
    return std::max(s, 0.0f);
  }
  const float* hm = ch + kChHm;
  if (rep == "horizon-fourier") {  // the mean horizon only: a step at its Fourier value
    float f[dir::kHorizonTerms];
    dir::fourier_basis(l.x, l.y, f);
    float m1 = 0;
    for (int m = 0; m < dir::kHorizonTerms; ++m) m1 += hm[m] * f[m];
    return l.z > m1 ? nl : 0.0f;
  }
  if (rep == "hm-lit-cos") return dir::hm_lit_cosine(hm, l, nc);
  if (rep == "hm-transport") return dir::hm_transport(hm, l);
  throw InputError("unknown representation " + rep);
}

struct Light {
  float elev, az;
  Vec3f l;
  int ai;  // its azimuth's index in the horizon tangents
};

// The exact transport of each light per fine texel from horizon tangents along the lights' azimuths
// (tan_h[p · n_az + ai]).
std::vector<Texture> exact_per_light(const std::vector<Light>& lights, const std::vector<float>& tan_h,
                                     std::size_t n_az, const std::vector<Vec3f>& n, int w, int h) {
  std::vector<Texture> out;
  for (const auto& L : lights) {
    Texture t(w, h, 1);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const std::size_t p = std::size_t(j) * w + i;
        t.at(i, j, 0) = transport_texel(tan_h[p * n_az + std::size_t(L.ai)], n[p], L.l);
      }
    out.push_back(std::move(t));
  }
  return out;
}

// Σ approx / Σ exact over the texture, and the RMSE of their B × B block means relative to the mean.
std::pair<double, double> bias_and_footprint_rmse(const Texture& tk, const Texture& approx, int B) {
  const int W = tk.width(), H = tk.height();
  double st = 0, sa = 0;
  for (int J = 0; J < H; ++J)
    for (int I = 0; I < W; ++I) st += tk.at(I, J, 0), sa += approx.at(I, J, 0);
  double se = 0;
  int nb = 0;
  for (int J = 0; J + B <= H; J += B)
    for (int I = 0; I + B <= W; I += B) {
      double bt = 0, ba = 0;
      for (int j = 0; j < B; ++j)
        for (int i = 0; i < B; ++i) bt += tk.at(I + i, J + j, 0), ba += approx.at(I + i, J + j, 0);
      const double d = (ba - bt) / (B * B);
      se += d * d, ++nb;
    }
  const double mean_t = st / (double(W) * H);
  return {st > 0 ? sa / st : 0, mean_t > 0 ? std::sqrt(se / std::max(nb, 1)) / mean_t : 0};
}

}  // namespace

std::vector<DirectionalStudyRow> directional_study(const DirectionalStudyOptions& opt) {
  std::vector<DirectionalStudyRow> rows;
  const auto bake_dirs = uniform_azimuths(opt.bake_azimuths);
  const LsqProjection p1(4, bake_dirs, 16), p2(dir::kPoly2Terms, bake_dirs, 16),
      p2a(dir::kPoly2Terms, bake_dirs, dir::kFitElevations, dir::kFitEpsilon),
      p2b(dir::kPoly2Terms, bake_dirs, 16, 0.3), p12(dir::kPoly12Terms, bake_dirs, 16),
      p12a(dir::kPoly12Terms, bake_dirs, 16, 0.03),
      r1(dir::kPoly2Terms, bake_dirs, dir::kFitElevations, dir::kFitEpsilon, 1),
      r2(dir::kPoly2Terms, bake_dirs, dir::kFitElevations, dir::kFitEpsilon, 2),
      r3(dir::kPoly2Terms, bake_dirs, dir::kFitElevations, 0.01, 1);
  const std::vector<std::pair<const LsqProjection*, int>> lsq = {
      {&p2, kChPoly2},     {&p1, kChSh1},    {&p2a, kChPoly2a}, {&p2b, kChPoly2b}, {&p12, kChPoly12},
      {&p12a, kChPoly12a}, {&r1, kChResid1}, {&r2, kChResid2},  {&r3, kChResid3}};
  for (const auto& kind : opt.kinds) {
    GenOptions g;
    g.kind = kind, g.size = opt.size, g.ao_rays = 1;  // V is re-baked here from the same horizons
    const TextureSet set = generate_texture_set(g);
    const float depth = set.depth_texels;
    const int w = set.height.width(), h = set.height.height();
    const auto n = fine_normals(set.height, depth);
    // Exact transport per fine texel and light, unlimited rays.
    std::vector<Vec2f> light_az;
    for (float a : opt.azimuths_deg) light_az.push_back(azimuth_dir(a));
    const auto tan_light = bake_horizon_tangents(set.height, depth, light_az, 0);
    std::vector<Light> lights;
    for (std::size_t ai = 0; ai < light_az.size(); ++ai)
      for (float e : opt.elevations_deg)
        lights.push_back({e, opt.azimuths_deg[ai], light_dir(e, light_az[ai]), int(ai)});
    const std::vector<Texture> exact = exact_per_light(lights, tan_light, light_az.size(), n, w, h);
    Texture normals(w, h, 3);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        const Vec3f& v = n[std::size_t(j) * w + i];
        normals.at(i, j, 0) = v.x, normals.at(i, j, 1) = v.y, normals.at(i, j, 2) = v.z;
      }
    for (float dist_opt : opt.bake_distances) {
      const float dist = dist_opt < 0 ? 0.08f * float(std::max(w, h)) : dist_opt;
      const auto tan_h = bake_horizon_tangents(set.height, depth, bake_dirs, dist);
      const Texture fine_ch = bake_all_channels(set.height, bake_dirs, tan_h, n, lsq);
      // The exact transport with the bake's ray length: what a perfect representation of this bake gives.
      const std::vector<Texture> exact_limited =
          dist > 0 ? exact_per_light(lights, bake_horizon_tangents(set.height, depth, light_az, dist),
                                     light_az.size(), n, w, h)
                   : std::vector<Texture>{};
      for (int q = 0; q < (opt.quantize8 ? 2 : 1); ++q) {
        Texture fc = fine_ch;
        const Ranges ranges = channel_ranges(fine_ch);
        if (q) quantize_channels(fc, ranges);
        for (int k : opt.scales) {
          Texture ck = box_downsample(fc, k);
          if (q) quantize_channels(ck, ranges);
          const Texture nk = box_downsample(normals, k);
          const int W = ck.width(), H = ck.height(), B = 4;
          for (std::size_t li = 0; li < lights.size(); ++li) {
            const Texture tk = box_downsample(exact[li], k);
            std::vector<std::pair<std::string, int>> names;
            for (const auto& r : reps()) names.push_back({r.name, r.bytes});
            if (dist > 0 && q == 0) names.push_back({"exact-limited", 0});
            for (const auto& [name, bytes] : names) {
              Texture approx(W, H, 1);
              if (name == "exact-limited") {
                approx = box_downsample(exact_limited[li], k);
              } else {
                for (int J = 0; J < H; ++J)
                  for (int I = 0; I < W; ++I) {
                    const Vec3f nmean(nk.at(I, J, 0), nk.at(I, J, 1), nk.at(I, J, 2));
                    const Vec3f nc = nmean / std::sqrt(dot(nmean, nmean));
                    approx.at(I, J, 0) = eval_rep(name, &ck.at(I, J, 0), nc, lights[li].l);
                  }
              }
              const auto [bias, rmse] = bias_and_footprint_rmse(tk, approx, B);
              DirectionalStudyRow row;
              row.kind = kind, row.representation = q ? name + "@8bit" : name, row.bake_distance = dist,
              row.k = k;
              row.elevation_deg = lights[li].elev, row.azimuth_deg = lights[li].az;
              row.bias = bias, row.rmse_footprint = rmse;
              row.bytes = bytes;
              rows.push_back(row);
            }
          }
        }
      }
    }
  }
  return rows;
}

std::string directional_study_markdown(const std::vector<DirectionalStudyRow>& rows) {
  // Group: (distance, representation) → (kind, k) → rows.
  std::vector<std::string> rep_order;
  std::vector<float> dists;
  for (const auto& r : rows) {
    if (std::find(rep_order.begin(), rep_order.end(), r.representation) == rep_order.end())
      rep_order.push_back(r.representation);
    if (std::find(dists.begin(), dists.end(), r.bake_distance) == dists.end())
      dists.push_back(r.bake_distance);
  }
  std::ostringstream o;
  for (float dist : dists) {
    o << fmt::format("\n### Bake distance {}\n\n", dist > 0 ? fmt::format("{} texels", dist) : "unlimited");
    // Light header from the first (rep, kind, k) group.
    std::vector<std::string> light_names;
    {
      const auto& r0 =
          *std::find_if(rows.begin(), rows.end(), [&](const auto& r) { return r.bake_distance == dist; });
      for (const auto& r : rows)
        if (r.bake_distance == dist && r.representation == r0.representation && r.kind == r0.kind &&
            r.k == r0.k)
          light_names.push_back(fmt::format("{:g}/{:g}", r.elevation_deg, r.azimuth_deg));
    }
    o << "Bias = Σ T̃ / Σ T per light (elevation°/azimuth°); mean and max |bias − 1| over the lights; "
         "footprint "
         "RMSE / mean T (mean over the lights).\n\n";
    o << "| representation | bytes | material | k |";
    for (const auto& l : light_names) o << " " << l << " |";
    o << " mean abs(b−1) | max abs(b−1) | fp RMSE |\n|---|---|---|---|";
    for (std::size_t i = 0; i < light_names.size() + 3; ++i) o << "---|";
    o << "\n";
    struct Sum {
      double mean_dev = 0, max_dev = 0, rmse = 0;
      int n = 0;
    };
    std::map<std::string, Sum> overall;
    for (const auto& rep : rep_order) {
      std::vector<std::pair<std::string, int>> groups;
      for (const auto& r : rows)
        if (r.bake_distance == dist && r.representation == rep &&
            std::find(groups.begin(), groups.end(), std::make_pair(r.kind, r.k)) == groups.end())
          groups.push_back({r.kind, r.k});
      for (const auto& [kind, k] : groups) {
        double md = 0, mx = 0, rm = 0;
        int cnt = 0, bytes = 0;
        std::string cells;
        for (const auto& r : rows)
          if (r.bake_distance == dist && r.representation == rep && r.kind == kind && r.k == k) {
            const double d = std::abs(r.bias - 1);
            md += d, mx = std::max(mx, d), rm += r.rmse_footprint, ++cnt, bytes = r.bytes;
            cells += fmt::format(" {:.3f} |", r.bias);
          }
        md /= cnt, rm /= cnt;
        o << fmt::format("| {} | {} | {} | {} |{} {:.3f} | {:.3f} | {:.3f} |\n", rep, bytes, kind, k, cells,
                         md, mx, rm);
        auto& s = overall[rep];
        s.mean_dev += md, s.max_dev = std::max(s.max_dev, mx), s.rmse += rm, ++s.n;
      }
    }
    // Footprint RMSE against the best cone term (ao, reference, chan-2018 of the same storage): per cell
    // (material, k, light) and per group (material, k; mean over the lights).
    auto fp_of = [&](const std::string& rep, const std::string& kind, int k, float e, float az) {
      for (const auto& r : rows)
        if (r.bake_distance == dist && r.representation == rep && r.kind == kind && r.k == k &&
            r.elevation_deg == e && r.azimuth_deg == az)
          return r.rmse_footprint;
      return std::numeric_limits<double>::quiet_NaN();
    };
    o << "\nSummary over materials and k (mean of the per-group means; max over all lights; cells = "
         "(material, "
         "k, light) where the footprint RMSE is below that of every cone term (ao, reference, chan-2018); "
         "groups = (material, k) where the mean over the lights is below the best cone term's):\n\n"
         "| representation | bytes | mean abs(b−1) | max abs(b−1) | mean fp RMSE | fp < best cone: cells | "
         "groups |\n|---|---|---|---|---|---|---|\n";
    for (const auto& rep : rep_order) {
      const auto& s = overall[rep];
      if (!s.n) continue;
      const std::string suffix = rep.find("@8bit") != std::string::npos ? "@8bit" : "";
      int cells = 0, cells_won = 0, bytes = 0;
      std::map<std::pair<std::string, int>, std::array<double, 4>> groups;  // sums: rep, ao, ref, chan
      for (const auto& r : rows) {
        if (r.bake_distance != dist || r.representation != rep) continue;
        bytes = r.bytes;
        double cone[3];
        int ci = 0;
        for (const char* c : {"ao", "reference", "chan-2018"})
          cone[ci++] = fp_of(std::string(c) + suffix, r.kind, r.k, r.elevation_deg, r.azimuth_deg);
        ++cells;
        cells_won += r.rmse_footprint < std::min({cone[0], cone[1], cone[2]});
        auto& g = groups[{r.kind, r.k}];
        g[0] += r.rmse_footprint, g[1] += cone[0], g[2] += cone[1], g[3] += cone[2];
      }
      int groups_won = 0;
      for (const auto& [key, g] : groups) groups_won += g[0] < std::min({g[1], g[2], g[3]});
      o << fmt::format("| {} | {} | {:.3f} | {:.3f} | {:.3f} | {}/{} | {}/{} |\n", rep, bytes,
                       s.mean_dev / s.n, s.max_dev, s.rmse / s.n, cells_won, cells, groups_won,
                       groups.size());
    }
  }
  return o.str();
}

}  // namespace msh::research
