// The reference renderer (see render/renderer.h): camera rays, per-pixel sampling and the parallel tile loop.
// Scene set-up, intersection and shading live in scene_setup.cpp, shapes.cpp and integrator.cpp.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>

#include "renderer_impl.h"

namespace msh::render {

namespace {
using tracing::kInf;
uint32_t pixel_seed(uint32_t seed, int x, int y) {
  return hash_combine(hash_combine(hash_u32(seed), uint32_t(x)), uint32_t(y));
}
}  // namespace

// Mean of the pixel's spp samples, taken as `batches` independently scrambled Sobol batches of spp/batches
// samples (batch 0 uses the pixel's own scramble, so batches = 1 is the plain render). With se, stores the
// standard error of the mean from the spread of the batch means.
Rgbf Renderer::Impl::pixel(int x, int y, RenderStats& st, int batches, Rgbf* se, int spp) const {
  Rgbf mean;
  pixel(x, y, st, batches, spp, Components{1, {scene.settings.component, Component::Total}}, &mean, se);
  return mean;
}

void Renderer::Impl::pixel(int x, int y, RenderStats& st, int batches, int spp, const Components& cs,
                           Rgbf* mean, Rgbf* se, const RenderWindow* window) const {
  const Settings& s = scene.settings;
  const Camera& cam = window ? window->camera : scene.camera;
  const Vec3f f = normalize(cam.target - cam.eye);
  const Vec3f r = normalize(cross(f, cam.up));
  const Vec3f up = cross(r, f);
  const float th = cam.orthographic ? 0.5f * cam.ortho_height
                                    : std::tan(0.5f * cam.fov_deg * kPi<float> / 180.0f),
              aspect = float(s.width) / float(s.height);
  const uint32_t ps = pixel_seed(window ? window->seed : s.seed, x, y);
  if (spp == 0) spp = s.spp;
  const int per = spp / batches, n = cs.n;
  Rgbf sum[2] = {Rgbf(0.0f), Rgbf(0.0f)};
  double bm[2][3] = {}, bm2[2][3] = {};
  for (int b = 0; b < batches; ++b) {
    const uint32_t bs = b == 0 ? ps : hash_combine(ps, 0x5bd1e995u + uint32_t(b));
    Rgbf bsum[2] = {Rgbf(0.0f), Rgbf(0.0f)};
    for (int k = 0; k < per; ++k) {
      const int i = b * per + k;
      const Vec2f u = spp == 1 ? Vec2f(0.5f, 0.5f) : sobol_2d<float>(uint32_t(k), bs);
      const float px = (2 * (float(x) + u.x) / float(s.width) - 1) * th * aspect;
      const float py = (1 - 2 * (float(y) + u.y) / float(s.height)) * th;
      const Vec3f d = cam.orthographic ? f : normalize(f + r * px + up * py);
      const Vec3f o = cam.orthographic ? cam.eye + r * px + up * py : cam.eye;
      ++st.camera_rays;
      Hit h;
      if (!intersect(o, d, 0.0f, kInf, h)) {
        for (int c = 0; c < n; ++c) bsum[c] += s.background;
        continue;
      }
      Rgbf L[2];
      shade(h, -d, hash_combine(ps, uint32_t(i)), st, cs, L, window ? &window->light : nullptr);
      for (int c = 0; c < n; ++c) bsum[c] += L[c];
    }
    for (int c = 0; c < n; ++c) {
      sum[c] += bsum[c];
      for (int ch = 0; ch < 3; ++ch) {
        const double m = double(bsum[c][ch]) / per;
        bm[c][ch] += m, bm2[c][ch] += m * m;
      }
    }
  }
  for (int c = 0; c < n; ++c) {
    if (se) {
      float e[3];
      for (int ch = 0; ch < 3; ++ch) {
        const double m = bm[c][ch] / batches;
        const double var = batches > 1 ? std::max(0.0, bm2[c][ch] - batches * m * m) / (batches - 1) : 0.0;
        e[ch] = float(std::sqrt(var / batches));
      }
      se[c] = Rgbf(e[0], e[1], e[2]);
    }
    mean[c] = sum[c] / float(spp);
  }
}

Renderer::Renderer(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}
Renderer::~Renderer() = default;

Rgbf Renderer::render_pixel(int x, int y, RenderStats* stats) const {
  RenderStats st;
  const Rgbf c = impl_->pixel(x, y, st);
  if (stats) *stats = st;
  return c;
}

namespace {
// Runs fn(x, y, stats) over 16×16 tiles in parallel (4×4 where that gives fewer than 64 tiles: a study
// window of 16×16 pixels was one tile, so one thread); fills stats and reports progress. Each pixel's value
// depends only on its own seed, so the tiling never changes the image.
template <class Fn>
void for_each_pixel(const Settings& s, const std::function<void(double)>& progress, RenderStats* stats,
                    Fn&& fn) {
  const auto t0 = std::chrono::steady_clock::now();
  std::atomic<uint64_t> cam{0}, shadow{0}, shaded{0}, done{0};
  const int tile = ((s.width + 15) / 16) * ((s.height + 15) / 16) < 64 ? 4 : 16;
  const uint64_t total = uint64_t(s.width) * s.height;
  tbb::parallel_for(tbb::blocked_range2d<int>(0, s.height, tile, 0, s.width, tile), [&](const auto& r) {
    RenderStats st;
    for (int y = r.rows().begin(); y < r.rows().end(); ++y)
      for (int x = r.cols().begin(); x < r.cols().end(); ++x) fn(x, y, st);
    cam += st.camera_rays, shadow += st.shadow_rays, shaded += st.shaded_samples;
    const uint64_t n = done += uint64_t(r.rows().size()) * r.cols().size();
    if (progress) progress(double(n) / double(total));
  });
  if (stats) {
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    stats->camera_rays = cam, stats->shadow_rays = shadow, stats->shaded_samples = shaded;
  }
}
}  // namespace

Image Renderer::render(const std::function<void(double)>& progress, RenderStats* stats) const {
  const Settings& s = impl_->scene.settings;
  Image img(s.width, s.height);
  for_each_pixel(s, progress, stats,
                 [&](int x, int y, RenderStats& st) { img.at(x, y) = impl_->pixel(x, y, st); });
  return img;
}

RenderResult Renderer::render_batches(int spp, int batches,
                                      const std::function<void(double)>& progress) const {
  const Settings& s = impl_->scene.settings;
  const Impl& impl = *impl_;
  RenderResult res;
  res.batches = batches, res.spp = spp;
  res.mean = Image(s.width, s.height);
  res.std_error = Image(s.width, s.height);
  for_each_pixel(s, progress, &res.stats, [&](int x, int y, RenderStats& st) {
    res.mean.at(x, y) = impl.pixel(x, y, st, batches, &res.std_error.at(x, y), spp);
  });
  return res;
}

namespace {
// The batches of render_with_error: min(error_batches, spp), which must divide spp.
int error_batches(const Scene& scene) {
  const Settings& s = scene.settings;
  const int batches = std::max(1, std::min(s.error_batches, s.spp));
  if (s.spp % batches != 0)
    throw InputError(fmt::format("{}: spp = {} is not a multiple of the {} error batches",
                                 scene.source.string(), s.spp, batches));
  return batches;
}
}  // namespace

RenderResult Renderer::render_with_error(const std::function<void(double)>& progress) const {
  return render_batches(impl_->scene.settings.spp, error_batches(impl_->scene), progress);
}

std::array<RenderResult, 2> Renderer::render_components_with_error(
    const std::function<void(double)>& progress) const {
  const Settings& s = impl_->scene.settings;
  const int batches = error_batches(impl_->scene);
  const Impl& impl = *impl_;
  const Impl::Components cs{2, {Component::Diffuse, Component::Specular}};
  std::array<RenderResult, 2> res;
  for (RenderResult& r : res) {
    r.batches = batches, r.spp = s.spp;
    r.mean = Image(s.width, s.height);
    r.std_error = Image(s.width, s.height);
  }
  for_each_pixel(s, progress, &res[0].stats, [&](int x, int y, RenderStats& st) {
    Rgbf mean[2], se[2];
    impl.pixel(x, y, st, batches, s.spp, cs, mean, se);
    for (int c = 0; c < 2; ++c) res[c].mean.at(x, y) = mean[c], res[c].std_error.at(x, y) = se[c];
  });
  res[1].stats = res[0].stats;
  return res;
}

std::array<RenderResult, 2> Renderer::render_windows_components(const std::vector<RenderWindow>& windows,
                                                                int mosaic_width, int mosaic_height) const {
  const Settings& s = impl_->scene.settings;
  const int batches = error_batches(impl_->scene);
  const Impl& impl = *impl_;
  const std::string& src = impl.scene.source.string();
  if (impl.scene.lights.empty()) throw InputError(fmt::format("{}: a windowed render needs a light", src));
  for (const RenderWindow& w : windows)
    if (w.x0 < 0 || w.y0 < 0 || w.x0 + s.width > mosaic_width || w.y0 + s.height > mosaic_height)
      throw InputError(fmt::format("{}: a {}x{} window at ({}, {}) leaves the {}x{} mosaic", src, s.width,
                                   s.height, w.x0, w.y0, mosaic_width, mosaic_height));
  const Impl::Components cs{2, {Component::Diffuse, Component::Specular}};
  std::array<RenderResult, 2> res;
  for (RenderResult& r : res) {
    r.batches = batches, r.spp = s.spp;
    r.mean = Image(mosaic_width, mosaic_height);
    r.std_error = Image(mosaic_width, mosaic_height);
  }
  // The windows stacked into one column (row Y: window Y / height, its row Y % height), so every window's
  // pixels are in one parallel loop. Each pixel depends on its window's seed and its own position only, so
  // the tiling never changes a bit.
  Settings stacked = s;
  stacked.height = int(windows.size()) * s.height;
  for_each_pixel(stacked, {}, &res[0].stats, [&](int x, int yy, RenderStats& st) {
    const RenderWindow& w = windows[std::size_t(yy / s.height)];
    const int y = yy % s.height;
    Rgbf mean[2], se[2];
    impl.pixel(x, y, st, batches, s.spp, cs, mean, se, &w);
    for (int c = 0; c < 2; ++c)
      res[c].mean.at(w.x0 + x, w.y0 + y) = mean[c], res[c].std_error.at(w.x0 + x, w.y0 + y) = se[c];
  });
  res[1].stats = res[0].stats;
  return res;
}

double rms_std_error(const Image& std_error) {
  double sum = 0;
  for (const Rgbf& e : std_error.px) sum += sqr(double(e.r)) + sqr(double(e.g)) + sqr(double(e.b));
  return std_error.px.empty() ? 0.0 : std::sqrt(sum / (3.0 * double(std_error.px.size())));
}

RenderResult Renderer::render_to_error(double target_rms_std_error, int max_spp,
                                       const std::function<void(double)>& progress) const {
  const Settings& s = impl_->scene.settings;
  const std::string& src = impl_->scene.source.string();
  if (!(target_rms_std_error > 0) || !std::isfinite(target_rms_std_error))
    throw InputError(fmt::format("{}: target standard error must be a positive number", src));
  if (s.error_batches < 2)
    throw InputError(fmt::format("{}: a target standard error needs error_batches >= 2", src));
  const int batches = s.error_batches;
  int spp = (std::max(s.spp, batches) + batches - 1) / batches * batches;
  if (max_spp < spp || max_spp > (1 << 20))
    throw InputError(fmt::format("{}: max spp {} must be in [{}, 2^20]", src, max_spp, spp));
  RenderStats total;
  double seconds = 0;
  for (;;) {
    RenderResult res = render_batches(spp, batches, progress);
    total.camera_rays += res.stats.camera_rays, total.shadow_rays += res.stats.shadow_rays;
    total.shaded_samples += res.stats.shaded_samples, seconds += res.stats.seconds;
    if (rms_std_error(res.std_error) <= target_rms_std_error || 2 * spp > max_spp) {
      res.stats = total, res.stats.seconds = seconds;
      return res;
    }
    spp *= 2;
  }
}

}  // namespace msh::render
