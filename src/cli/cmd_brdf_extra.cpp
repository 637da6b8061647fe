// Figure helper for the BRDF models (a stand-in until the renderer takes BRDF models):
//   microshadow plot brdf-spheres --out FILE.png --row "MODEL:PARAM=v1,v2,...[:OTHER=x[,y,z]]" [--row ...]
//       [--size PX] [--exposure STOPS]
// Each row renders one model on analytic spheres (orthographic camera along +z, no shadows), one sphere per
// value of the swept parameter. Lighting: a key directional light (upper left, front) and a rim light from
// behind, both white with irradiance 3 and 2 at normal incidence; tangent = projection of world +x (fibers
// for Kajiya-Kay). Output: 8-bit sRGB PNG (exact IEC 61966-2-1 curve), written atomically.
#include <fmt/format.h>
#include <microshadow/bsdf/runtime/brdf_model.h>
#include <microshadow/io/texture.h>
#include <microshadow/math/color.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common.h"

namespace msh::cli {
namespace {

struct RowSpec {
  std::string model, sweep;
  std::vector<double> values;
  bsdf::BrdfParams fixed;
};

std::vector<double> parse_numbers(const std::string& s, const std::string& what) {
  std::vector<double> v;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ',')) {
    try {
      size_t used = 0;
      const double x = std::stod(tok, &used);
      if (used != tok.size() || !std::isfinite(x)) throw std::invalid_argument(tok);
      v.push_back(x);
    } catch (const std::exception&) {
      throw UsageError(fmt::format("{}: '{}' is not a finite number", what, tok));
    }
  }
  if (v.empty()) throw UsageError(fmt::format("{}: no values", what));
  return v;
}

RowSpec parse_row(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream ss(text);
  std::string p;
  while (std::getline(ss, p, ':')) parts.push_back(p);
  if (parts.size() < 2) throw UsageError(fmt::format("--row '{}': expected MODEL:PARAM=v1,v2,...", text));
  RowSpec r;
  r.model = parts[0];
  const auto& info = bsdf::find_brdf_model(r.model);
  for (size_t i = 1; i < parts.size(); ++i) {
    const auto eq = parts[i].find('=');
    if (eq == std::string::npos)
      throw UsageError(fmt::format("--row '{}': '{}' is not NAME=VALUES", text, parts[i]));
    const std::string name = parts[i].substr(0, eq);
    const auto vals = parse_numbers(parts[i].substr(eq + 1), "--row " + name);
    if (i == 1)
      r.sweep = name, r.values = vals;
    else
      r.fixed.values[name] = vals;
  }
  // Validate every column's parameter set now (names, ranges): no file is written on bad input.
  for (double v : r.values) {
    auto g = r.fixed;
    bool three = false;
    for (const auto& s : info.params) three |= s.name == r.sweep && s.components == 3;
    g.values[r.sweep] = three ? std::vector<double>{v, v, v} : std::vector<double>{v};
    bsdf::complete_params(info, g);
  }
  return r;
}

struct PlotOptions {
  std::string out;
  std::vector<std::string> rows;
  int size = 96;
  double exposure = 0;
};

void run_plot(const PlotOptions& o) {
  if (o.rows.empty()) throw UsageError("give at least one --row");
  if (o.size < 8 || o.size > 1024)
    throw UsageError(fmt::format("--size must be in [8, 1024], got {}", o.size));
  require_range(o.exposure, -20, 20, "--exposure");
  std::vector<RowSpec> rows;
  size_t cols = 0;
  for (const auto& t : o.rows) rows.push_back(parse_row(t)), cols = std::max(cols, rows.back().values.size());
  const int S = o.size, W = int(cols) * S, H = int(rows.size()) * S;
  io::Volume img(W, H, 1, 3);
  const Vec3d key = normalize(Vec3d(-0.5, 0.6, 0.65)), rim = normalize(Vec3d(0.4, 0.3, -0.85));
  const double scale = std::exp2(o.exposure);
  for (size_t ri = 0; ri < rows.size(); ++ri) {
    const auto& r = rows[ri];
    const auto& info = bsdf::find_brdf_model(r.model);
    for (size_t ci = 0; ci < r.values.size(); ++ci) {
      auto g = r.fixed;
      bool three = false;
      for (const auto& s : info.params) three |= s.name == r.sweep && s.components == 3;
      g.values[r.sweep] = three ? std::vector<double>{r.values[ci], r.values[ci], r.values[ci]}
                                : std::vector<double>{r.values[ci]};
      const auto model = info.make(bsdf::complete_params(info, g));
      tbb::parallel_for(tbb::blocked_range<int>(0, S), [&](const tbb::blocked_range<int>& br) {
        for (int y = br.begin(); y != br.end(); ++y)
          for (int x = 0; x < S; ++x) {
            const double px = (x + 0.5) / S * 2 - 1, py = 1 - (y + 0.5) / S * 2;
            const double r2 = (px * px + py * py) / 0.9025;  // sphere radius 0.95 of the cell
            Rgbd c(0.02);                                    // background
            if (r2 < 1) {
              const Vec3d n(px / 0.95, py / 0.95, std::sqrt(1 - r2));
              const Frame<double> f = Frame<double>::from_zx(n, Vec3d(1, 0, 0));
              const Vec3d wo = f.to_local(Vec3d(0, 0, 1));
              c = Rgbd(0);
              for (const auto& [l, e] : {std::pair{key, 3.0}, std::pair{rim, 2.0}}) {
                const Vec3d wi = f.to_local(l);
                if (wi.z > 0) c += model->f(wo, wi) * (e * wi.z);
              }
            }
            c = c * scale;
            const Rgbd s = linear_to_srgb(Rgbd(saturate(c.r), saturate(c.g), saturate(c.b)));
            const int X = int(ci) * S + x, Y = int(ri) * S + y;
            img.at(X, Y, 0, 0) = float(s.r), img.at(X, Y, 0, 1) = float(s.g), img.at(X, Y, 0, 2) = float(s.b);
          }
      });
    }
  }
  io::write_png(o.out, img, 8);
  print_json({{"file", o.out}, {"width", W}, {"height", H}, {"rows", o.rows}});
}

void add_brdf_extra(Groups& g) {
  const auto [p, o] = add_command<PlotOptions>(
      g.plot, "brdf-spheres",
      "Grid of analytically shaded spheres: one row per model, one sphere per swept parameter value",
      run_plot);
  p->add_option("--out", o->out, "Output PNG (8-bit sRGB)")->required();
  p->add_option("--row", o->rows, "MODEL:PARAM=v1,v2,...[:OTHER=x[,y,z]] (repeatable; see eval brdf --list)")
      ->required();
  p->add_option("--size", o->size, "Sphere cell size in pixels")->capture_default_str();
  p->add_option("--exposure", o->exposure, "Exposure in stops")->check(Finite)->capture_default_str();
}

}  // namespace

MSH_CLI_REGISTER(add_brdf_extra, 71);

}  // namespace msh::cli
