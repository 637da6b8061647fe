// Renderer benchmarks: the default 1024×1024 comparison frame (plaster plane, directional light at 25°, 1
// sample per pixel) per micro-shadowing method, with rays/s and shaded samples/s as counters.
#include <benchmark/benchmark.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/scene.h>
#include <microshadow/render/texture_gen.h>

#include <memory>

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
    Material m;
    m.name = "plaster";
    m.base_color = t.base_color;
    m.normal = t.normal;
    m.roughness = t.roughness;
    m.metallic = t.metallic;
    m.visibility = t.visibility;
    m.height = t.height;
    m.height_texels = t.depth_texels;
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

void BM_ComparisonFrame1024(benchmark::State& state) {
  Scene s = comparison_scene();
  s.settings.micro_shadowing = MicroShadowing(state.range(0));
  const Renderer r(s);  // LUT load/bake and acceleration structures outside the timed loop
  RenderStats total;
  for (auto _ : state) {
    RenderStats st;
    benchmark::DoNotOptimize(r.render({}, &st));
    total.camera_rays += st.camera_rays, total.shadow_rays += st.shadow_rays;
    total.shaded_samples += st.shaded_samples;
  }
  state.SetLabel(to_string(s.settings.micro_shadowing));
  state.counters["rays/s"] =
      benchmark::Counter(double(total.camera_rays + total.shadow_rays), benchmark::Counter::kIsRate);
  state.counters["shaded/s"] = benchmark::Counter(double(total.shaded_samples), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ComparisonFrame1024)
    ->DenseRange(int(MicroShadowing::None), int(MicroShadowing::GroundTruth))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

}  // namespace
