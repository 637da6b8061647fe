// Height-field intersection: the maximum-mipmap traversal (HeightField::intersect) against the plain DDA it
// reproduces (HeightField::intersect_dda) on the same rays: the study's rock at 2048² and its default depth
// (128 texels), the study's plane (3 × 3 tiles) and camera (orthographic, 60° above the plane, 64 × 64 pixels
// of 4 × 4 texels), shadow rays from the camera rays' hits toward directional lights at 5° and 25° (azimuths
// 0° and 90°, as the study's); one thread.
#include <benchmark/benchmark.h>
#include <microshadow/math/sampling.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/texture_gen.h>

#include <cmath>
#include <limits>
#include <vector>

using namespace msh;
using namespace msh::render;

namespace {

struct Ray {
  Vec3f o, d;
};

struct RockRays {
  HeightField hf;
  Vec2f lo, hi;
  std::vector<Ray> camera, shadow5, shadow25, lit5;
};

const RockRays& rock_rays() {
  static const RockRays r = [] {
    GenOptions g;
    g.kind = "rock";
    g.size = 2048;
    g.ao_rays = 1;  // only the height map is used
    g.ao_max_distance = 1;
    g.directional_azimuths = 0;
    const TextureSet t = generate_texture_set(g);
    RockRays r{HeightField(t.height, t.depth_texels),
               {-0.5f, -0.5f},
               {3 * 2048 - 0.5f, 3 * 2048 - 0.5f},
               {},
               {},
               {},
               {}};
    // Grid-space directions are world directions over the texel size (2 / 2048 world units), as the
    // renderer's.
    const float scale = 1024.0f, el = 60.0f * kPi<float> / 180;
    const Vec3f f = Vec3f(0, std::cos(el), -std::sin(el)) * scale;
    Pcg32 rng(5);
    auto light = [&](float elev, int k) {
      const float e = elev * kPi<float> / 180, a = k % 2 ? kPi<float> / 2 : 0.0f;
      return Vec3f(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)) * scale;
    };
    const float inf = std::numeric_limits<float>::infinity();
    for (int k = 0; r.camera.size() < 4096; ++k) {
      // The pixels of a 64 × 64 image, 4 texels apart (the study's scale k = 4), in raster order, each at a
      // random point of its footprint in the middle tile; the camera ray through it from 4 tiles away.
      const Vec3f p(2048 * 1.3f + 4 * (float(k % 64) + rng.next_float()),
                    2048 * 1.3f + 4 * (float(k / 64) + rng.next_float()), 0);
      const Ray c{p - f * (4 * 2048 / scale), f};
      float t;
      Vec3f ng;
      if (!r.hf.intersect_dda(c.o, c.d, 0, inf, r.lo, r.hi, &t, &ng)) continue;
      r.camera.push_back(c);
      const Vec3f h = c.o + c.d * t;
      r.shadow5.push_back({h, light(5, k)});
      r.shadow25.push_back({h, light(25, k)});
      if (!r.hf.intersect_dda(h, light(5, k), 0, inf, r.lo, r.hi, &t, &ng))
        r.lit5.push_back({h, light(5, k)});
    }
    return r;
  }();
  return r;
}

// range(0): 0 camera rays, 1 shadow rays at 5°, 2 at 25°, 3 the shadow rays at 5° that reach the light (the
// longest: they leave the 128-texel slab); range(1): 0 the plain DDA, 1 the max mipmap.
void BM_HeightFieldRock2048(benchmark::State& state) {
  const RockRays& r = rock_rays();
  const std::vector<Ray>* sets[] = {&r.camera, &r.shadow5, &r.shadow25, &r.lit5};
  const std::vector<Ray>& rays = *sets[state.range(0)];
  const bool mipmap = state.range(1) != 0;
  const float inf = std::numeric_limits<float>::infinity();
  uint64_t n = 0, hits = 0;
  for (auto _ : state)
    for (const Ray& ray : rays) {
      float t;
      Vec3f ng;
      hits += mipmap ? r.hf.intersect(ray.o, ray.d, 0, inf, r.lo, r.hi, &t, &ng)
                     : r.hf.intersect_dda(ray.o, ray.d, 0, inf, r.lo, r.hi, &t, &ng);
      ++n;
    }
  HeightFieldTraversal tr;
  for (const Ray& ray : rays) {
    float t;
    Vec3f ng;
    r.hf.intersect(ray.o, ray.d, 0, inf, r.lo, r.hi, &t, &ng, &tr);
  }
  static const char* kind[] = {"camera", "shadow-5deg", "shadow-25deg", "shadow-5deg-lit"};
  state.SetLabel(std::string(kind[state.range(0)]) + (mipmap ? " max-mipmap" : " dda"));
  state.counters["rays/s"] = benchmark::Counter(double(n), benchmark::Counter::kIsRate);
  state.counters["ns/ray"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["hit%"] = 100.0 * double(hits) / double(std::max<uint64_t>(n, 1));
  state.counters["tested/ray"] = double(tr.cells_tested) / double(rays.size());
  state.counters["skipped/ray"] = double(tr.cells_skipped) / double(rays.size());
}
BENCHMARK(BM_HeightFieldRock2048)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(1.0);

}  // namespace
