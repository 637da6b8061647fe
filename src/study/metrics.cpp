// Study metrics (see study/metrics.h).
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/study/metrics.h>

#include <cmath>
#include <limits>

namespace msh::study {

namespace {
void require_same(const Plane& a, const Plane& b, const Mask& m) {
  if (a.width != b.width || a.height != b.height || m.width != a.width || m.height != a.height)
    throw InputError(fmt::format("study metrics: sizes differ ({}x{}, {}x{}, mask {}x{})", a.width, a.height,
                                 b.width, b.height, m.width, m.height));
}
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

std::size_t Mask::count() const {
  std::size_t n = 0;
  for (uint8_t x : px) n += x != 0;
  return n;
}

Plane luminance(const render::Image& img) {
  Plane p(img.width, img.height);
  for (std::size_t i = 0; i < img.px.size(); ++i)
    p.px[i] = luminance(Rgbd(img.px[i].r, img.px[i].g, img.px[i].b));
  return p;
}

Plane luminance_stderr(const render::Image& se) { return luminance(se); }

Measure region_mean(const Plane& img, const Plane& se, const Mask& m) {
  require_same(img, se, m);
  double s = 0, v = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < img.px.size(); ++i)
    if (m.px[i]) s += img.px[i], v += se.px[i] * se.px[i], ++n;
  if (n == 0) return {0, 0};
  return {s / double(n), std::sqrt(v) / double(n)};
}

Measure bias(const Plane& a, const Plane& g, const Plane& g_se, const Mask& m) {
  require_same(a, g, m);
  require_same(g, g_se, m);
  double sa = 0, sg = 0, v = 0;
  for (std::size_t i = 0; i < a.px.size(); ++i)
    if (m.px[i]) sa += a.px[i], sg += g.px[i], v += g_se.px[i] * g_se.px[i];
  if (!(sg > 0)) return {kNaN, kNaN};
  const double r = sa / sg;
  return {r, std::abs(r) * std::sqrt(v) / sg};
}

Measure rmse(const Plane& a, const Plane& g, const Plane& g_se, const Mask& m) {
  require_same(a, g, m);
  require_same(g, g_se, m);
  double s = 0, v = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.px.size(); ++i)
    if (m.px[i]) {
      const double d = a.px[i] - g.px[i];
      s += d * d, v += g_se.px[i] * g_se.px[i], ++n;
    }
  if (n == 0) return {kNaN, kNaN};
  return {std::sqrt(s / double(n)), std::sqrt(v / double(n))};
}

Blocks block_average(const Plane& img, const Plane& se, const Mask& m, int b) {
  require_same(img, se, m);
  if (b < 1) throw InputError(fmt::format("study: footprint must be >= 1 pixel, got {}", b));
  const int bw = img.width / b, bh = img.height / b;
  Blocks out{Plane(bw, bh), Plane(bw, bh), Mask(bw, bh, 0)};
  const double inv = 1.0 / (double(b) * double(b));
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      double s = 0, v = 0;
      bool all = true;
      for (int y = by * b; y < (by + 1) * b; ++y)
        for (int x = bx * b; x < (bx + 1) * b; ++x) {
          all = all && m.at(x, y);
          s += img.at(x, y), v += se.at(x, y) * se.at(x, y);
        }
      out.mean.at(bx, by) = s * inv;
      out.se.at(bx, by) = std::sqrt(v) * inv;
      out.mask.px[std::size_t(by) * bw + bx] = all ? 1 : 0;
    }
  return out;
}

Measure rmse_footprint(const Plane& a, const Plane& g, const Plane& g_se, const Mask& m, int b) {
  const Plane zero(a.width, a.height);
  const Blocks A = block_average(a, zero, m, b), G = block_average(g, g_se, m, b);
  return rmse(A.mean, G.mean, G.se, G.mask);
}

}  // namespace msh::study
