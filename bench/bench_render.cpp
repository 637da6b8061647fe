// Renderer benchmarks: the default 1024×1024 comparison frame (plaster plane, directional light at 25°, 1
// sample per pixel) per micro-shadowing method, with rays/s and shaded samples/s as counters.
#include <benchmark/benchmark.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/scene.h>
#include <microshadow/render/texture_gen.h>
#include <tbb/global_control.h>

#include <chrono>
#include <memory>
#include <string>

using namespace msh::render;

namespace {

const Scene& comparison_scene() {
  static const Scene scene = [] {
    GenOptions o;
    o.size = 256;
    o.ao_rays = 64;
    const TextureSet t = generate_texture_set(o);
    Scene s;
    s.camera = {{0, -1.3f, 1.7f}, {0, 0, 0}, {0, 0, 1}, 26.0f};  // as examples/plaster_plane.json
    Material m = material_from_texture_set("plaster", t, false);
    m.height = t.height, m.height_texels = t.depth_texels;  // the ground-truth rows displace it too
    s.materials.push_back(m);
    Object plane;
    plane.half_size = {1, 1};
    s.objects.push_back(plane);
    Light l;
    l.direction = direction_from_angles(25, 60);
    l.color = {3, 2.9f, 2.75f};
    s.lights.push_back(l);
    s.settings.width = s.settings.height = 1024;
    s.settings.spp = 1;
    s.settings.vndf_samples = 16;
    return s;
  }();
  return scene;
}

// The study's methods (occlusion/runtime/micro_shadowing_methods.h), then the ground truth.
const std::vector<std::string>& frame_methods() {
  static const std::vector<std::string> m = [] {
    std::vector<std::string> v = msh::occlusion::micro_shadowing_study_methods();
    v.push_back(kGroundTruth);
    return v;
  }();
  return m;
}

void BM_ComparisonFrame1024(benchmark::State& state) {
  Scene s = comparison_scene();
  s.settings.micro_shadowing = frame_methods()[std::size_t(state.range(0))];
  const Renderer r(s);  // LUT load/bake and acceleration structures outside the timed loop
  RenderStats total;
  for (auto _ : state) {
    RenderStats st;
    benchmark::DoNotOptimize(r.render({}, &st));
    total.camera_rays += st.camera_rays, total.shadow_rays += st.shadow_rays;
    total.shaded_samples += st.shaded_samples;
  }
  state.SetLabel(s.settings.micro_shadowing);
  state.counters["rays/s"] =
      benchmark::Counter(double(total.camera_rays + total.shadow_rays), benchmark::Counter::kIsRate);
  state.counters["shaded/s"] = benchmark::Counter(double(total.shaded_samples), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ComparisonFrame1024)
    ->DenseRange(0, int(frame_methods().size()) - 1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

// Ground-truth intersector: the height-field DDA against Embree on the same fine triangles (a 2048² plaster
// height field, 8.4 M triangles, displacing a 2 × 2 plane), one thread, 256² pixels, 1 spp, one directional
// light at 25°: camera rays + shadow rays per second. range(0): 0 = height field, 1 = Embree.
void BM_GroundTruthIntersector2048(benchmark::State& state) {
  static const Scene base = [] {
    GenOptions o;
    o.size = 2048;
    o.ao_rays = 1;  // only the height map is used
    o.ao_max_distance = 1;
    const TextureSet t = generate_texture_set(o);
    Scene s = comparison_scene();
    s.materials[0].height = t.height;
    s.materials[0].height_texels = t.depth_texels;
    s.materials[0].base_color = t.base_color;
    s.materials[0].roughness = t.roughness;
    s.settings.width = s.settings.height = 256;
    s.settings.micro_shadowing = kGroundTruth;
    return s;
  }();
  Scene s = base;
  s.settings.gt_intersector = state.range(0) ? GtIntersector::Embree : GtIntersector::HeightField;
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const auto t0 = std::chrono::steady_clock::now();
  const Renderer r(s);
  const double build = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RenderStats total;
  for (auto _ : state) {
    RenderStats st;
    benchmark::DoNotOptimize(r.render({}, &st));
    total.camera_rays += st.camera_rays, total.shadow_rays += st.shadow_rays;
  }
  state.SetLabel(state.range(0) ? "embree" : "heightfield-dda");
  state.counters["rays/s"] =
      benchmark::Counter(double(total.camera_rays + total.shadow_rays), benchmark::Counter::kIsRate);
  state.counters["build_s"] = build;
}
BENCHMARK(BM_GroundTruthIntersector2048)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(3);

// Scene intersection: a floor plane, `n` analytic spheres, a 24 × 12 UV-sphere mesh and a cylinder mesh,
// a directional and a point light; one thread, 256² pixels, 1 spp, no micro-shadowing. Camera + shadow rays
// per CPU second (the render runs on the calling thread). range(0): number of analytic spheres.
void BM_MixedSceneIntersect256(benchmark::State& state) {
  const int n = int(state.range(0));
  std::string objects = R"({"type": "plane", "material": "m", "center": [0, 0, 0], "size": [12, 12]},
    {"type": "uv-sphere", "material": "m", "center": [-2.5, 1, 0.8], "radius": 0.8, "segments": 24, "rings": 12},
    {"type": "cylinder", "material": "m", "center": [2.5, 1, 0], "radius": 0.5, "height": 1.6})";
  for (int i = 0; i < n; ++i)
    objects += ", {\"type\": \"sphere\", \"material\": \"m\", \"center\": [" +
               std::to_string(-2 + 4.0 * (i % 4) / 3) + ", " + std::to_string(-1.5 + 0.8 * (i / 4)) +
               ", 0.3], \"radius\": 0.3}";
  const std::string json =
      R"({"camera": {"eye": [0, -7, 3.2], "target": [0, 0, 0.6], "up": [0, 0, 1], "fov_deg": 40},
    "materials": {"m": {"base_color": [0.6, 0.6, 0.6], "roughness": 0.5}},
    "objects": [)" +
      objects + R"(],
    "lights": [{"type": "directional", "elevation_deg": 35, "azimuth_deg": 30},
               {"type": "point", "position": [1, -2, 3], "intensity": 6}],
    "settings": {"width": 256, "height": 256, "spp": 1, "micro_shadowing": "none"}})";
  const Scene s = parse_scene(json, "bench_mixed.json", {});
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const Renderer r(s);
  RenderStats total;
  for (auto _ : state) {
    RenderStats st;
    benchmark::DoNotOptimize(r.render({}, &st));
    total.camera_rays += st.camera_rays, total.shadow_rays += st.shadow_rays;
  }
  state.counters["rays/s"] =
      benchmark::Counter(double(total.camera_rays + total.shadow_rays), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MixedSceneIntersect256)->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond)->MinTime(1.0);

}  // namespace
