// Renderer::render_components_with_error: diffuse and specular from one pass, each bit-identical (mean and
// standard error) to its own render_with_error with Settings::component = Diffuse / Specular — on the ground
// truth's height-field plane and on a coarse scene (plane, analytic sphere, mesh) with micro-shadowing terms
// (one term, a per-lobe pair, the directional-view channels, a Monte Carlo estimator), every light type
// (directional, point, sphere area-sampled and by its representative point, disk, rect) and every area_ms.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/texture_gen.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using namespace msh;
using namespace msh::render;

namespace {

const TextureSet& rock_set() {
  static const TextureSet t = [] {
    GenOptions g;
    g.kind = "rock";
    g.size = 64;
    g.ao_rays = 8;
    g.directional_azimuths = 8;
    g.directional_view = true;  // the 21 channels directional-view reads
    return generate_texture_set(g);
  }();
  return t;
}

std::vector<Light> lights(bool planar) {
  std::vector<Light> ls(3);
  ls[0].direction = direction_from_angles(20, 30), ls[0].color = {2, 1.8f, 1.6f};
  ls[1].type = LightType::Point, ls[1].position = {0.7f, -0.4f, 1.5f}, ls[1].color = {3, 3, 3};
  ls[2].type = LightType::Sphere, ls[2].position = {-1.0f, 0.8f, 1.2f}, ls[2].radius = 0.3f;
  ls[2].color = {2, 2.5f, 3};
  if (planar) {
    Light d, r;
    d.type = LightType::Disk, d.position = {0.3f, 0.9f, 1.4f}, d.normal = normalize(Vec3f(0, -0.4f, -1));
    d.radius = 0.4f, d.color = {2, 2, 2};
    r.type = LightType::Rect, r.position = {-0.5f, -0.9f, 1.1f}, r.normal = normalize(Vec3f(0.3f, 0.5f, -1));
    r.tangent = normalize(Vec3f(1, 0, 0.3f)), r.half_size = {0.3f, 0.2f}, r.color = {1.5f, 1.5f, 1.5f};
    ls.push_back(d), ls.push_back(r);
  }
  return ls;
}

// A plane, an analytic sphere and a UV-sphere mesh with the rock set (normal map, micro-occlusion,
// directional channels), ambient and background light, the bump-terminator term.
Scene coarse_scene(const std::string& method) {
  const TextureSet& t = rock_set();
  Scene s;
  s.camera = {{0, -2.2f, 1.6f}, {0, 0, 0.2f}, {0, 0, 1}, 40.0f};
  Material m;
  m.name = "rock";
  m.base_color = t.base_color, m.normal = t.normal, m.roughness = t.roughness, m.metallic = t.metallic;
  m.visibility = t.visibility, m.directional = t.directional, m.uv_scale = 2;
  s.materials.push_back(m);
  Object plane, sphere, mesh;
  plane.half_size = {1.5f, 1.5f};
  sphere.type = ShapeType::Sphere, sphere.center = {0.5f, 0.3f, 0.35f}, sphere.radius = 0.35f;
  Mesh uv = make_uv_sphere(0.3f, 12, 6);
  for (Vec3f& p : uv.p) p = p + Vec3f(-0.5f, -0.2f, 0.3f);
  mesh.type = ShapeType::Mesh, mesh.mesh = std::make_shared<Mesh>(uv);
  s.objects = {plane, sphere, mesh};
  s.lights = lights(true);
  Settings& st = s.settings;
  st.width = st.height = 16, st.spp = 8, st.error_batches = 4;
  st.micro_shadowing = method, st.vndf_samples = 4;
  st.area_lights = true, st.area_samples = 3;
  st.ambient = {0.05f, 0.04f, 0.03f}, st.background = {0.01f, 0.02f, 0.03f};
  st.bump_terminator = BumpTerminator::kConty2019;
  st.seed = 5;
  return s;
}

// The ground truth: the plane displaced by the rock height map, the study's orthographic camera 60° above it.
Scene ground_truth_scene() {
  const TextureSet& t = rock_set();
  Scene s;
  s.camera.eye = {0, -1.0f, 1.73f}, s.camera.target = {0, 0, 0}, s.camera.up = {0, 0, 1};
  s.camera.orthographic = true, s.camera.ortho_height = 1.2f;
  Material m = material_from_texture_set("rock", t, true);
  m.uv_scale = 3;
  s.materials.push_back(m);
  Object plane;
  plane.half_size = {3, 3};
  s.objects = {plane};
  s.lights = lights(false);
  s.lights[0].direction = direction_from_angles(10, 0);
  Settings& st = s.settings;
  st.width = st.height = 24, st.spp = 8, st.error_batches = 8;
  st.micro_shadowing = kGroundTruth;
  st.area_lights = true, st.area_samples = 4;
  st.ambient = {0.02f, 0.02f, 0.02f};
  st.seed = 9;
  return s;
}

bool same_bits(const Image& a, const Image& b) {
  return a.px.size() == b.px.size() && std::memcmp(a.px.data(), b.px.data(), a.px.size() * sizeof(Rgbf)) == 0;
}

double total(const Image& a) {
  double s = 0;
  for (const Rgbf& c : a.px) s += double(c.r) + double(c.g) + double(c.b);
  return s;
}

// One pass against the two separate renders of the scene.
void expect_components_identical(Scene s, const std::string& what) {
  s.settings.component = Component::Total;  // not read by the one-pass render
  const std::array<RenderResult, 2> both = Renderer(s).render_components_with_error();
  const Component comps[2] = {Component::Diffuse, Component::Specular};
  for (int c = 0; c < 2; ++c) {
    s.settings.component = comps[c];
    const RenderResult one = Renderer(s).render_with_error();
    EXPECT_TRUE(same_bits(both[c].mean, one.mean)) << what << ": " << to_string(comps[c]) << " mean";
    EXPECT_TRUE(same_bits(both[c].std_error, one.std_error))
        << what << ": " << to_string(comps[c]) << " error";
    EXPECT_EQ(both[c].batches, one.batches);
    EXPECT_EQ(both[c].spp, one.spp);
    // The rays are traced once: as many as one component's own render.
    EXPECT_EQ(both[c].stats.camera_rays, one.stats.camera_rays) << what;
    EXPECT_EQ(both[c].stats.shadow_rays, one.stats.shadow_rays) << what;
    // Not trivially equal: light and noise in both components.
    EXPECT_GT(total(one.mean), 0.0) << what;
    EXPECT_GT(total(one.std_error), 0.0) << what;
  }
  EXPECT_FALSE(same_bits(both[0].mean, both[1].mean)) << what;
}

}  // namespace

TEST(RenderComponents, GroundTruthOnePassEqualsTwoRenders) {
  for (const bool area : {true, false}) {  // sphere light area-sampled, or by its representative point
    Scene s = ground_truth_scene();
    s.settings.area_lights = area;
    expect_components_identical(s,
                                area ? "ground truth, area-sampled sphere" : "ground truth, representative");
  }
}

TEST(RenderComponents, MicroShadowingTermsOnePassEqualsTwoRenders) {
  for (const char* method : {"none", "ao", "diffuse-aware-alu+lut3d", "directional-view", "generic-vndf",
                             "diffuse-aware+specular-aware"})
    for (const AreaMs am : {AreaMs::Sampled, AreaMs::Representative}) {
      Scene s = coarse_scene(method);
      s.settings.area_ms = am;
      expect_components_identical(s, std::string(method) + ", area_ms " + to_string(am));
    }
  // Representative points for the sphere light.
  Scene r = coarse_scene("diffuse-aware-alu+lut3d");
  r.settings.area_lights = false;
  expect_components_identical(r, "diffuse-aware-alu+lut3d, representative sphere");
}

TEST(RenderComponents, IntegratedAreaTermOnePassEqualsTwoRenders) {
  // The exact quadrature per shading point is slow: a few pixels, the area lights only, no bump term.
  for (const char* method : {"ao", "diffuse-aware-alu+lut3d"}) {
    Scene s = coarse_scene(method);
    s.settings.area_ms = AreaMs::Integrated;
    s.settings.bump_terminator = BumpTerminator::kNone;
    s.settings.width = s.settings.height = 6, s.settings.spp = 4;
    s.lights = {s.lights[2], s.lights[3]};  // sphere and disk
    expect_components_identical(s, std::string(method) + ", area_ms integrated");
  }
}

// The two components add up to the total (ambient in the diffuse one only; no background, which every
// component's render adds), to float rounding: the total sums the lobes in another order.
TEST(RenderComponents, ComponentsAddUpToTheTotal) {
  std::vector<Scene> scenes = {ground_truth_scene(), coarse_scene("ao"),
                               coarse_scene("diffuse-aware-alu+lut3d")};
  for (Scene& s : scenes) {
    s.settings.background = {0, 0, 0};
    const std::array<RenderResult, 2> both = Renderer(s).render_components_with_error();
    s.settings.component = Component::Total;
    const RenderResult t = Renderer(s).render_with_error();
    double worst = 0;
    for (std::size_t i = 0; i < t.mean.px.size(); ++i)
      for (int ch = 0; ch < 3; ++ch) {
        const double sum = double(both[0].mean.px[i][ch]) + double(both[1].mean.px[i][ch]);
        worst = std::max(worst, std::abs(sum - double(t.mean.px[i][ch])) / (std::abs(sum) + 1e-6));
      }
    EXPECT_LT(worst, 1e-5) << s.settings.micro_shadowing;
    EXPECT_GT(total(both[0].mean), 0.0);
    EXPECT_GT(total(both[1].mean), 0.0);
  }
}

TEST(RenderComponents, RejectsSppNotAMultipleOfTheBatches) {
  Scene s = ground_truth_scene();
  s.settings.spp = 12;  // 8 batches
  EXPECT_THROW(Renderer(s).render_components_with_error(), InputError);
  s.settings.spp = 16;
  EXPECT_NO_THROW(Renderer(s).render_components_with_error());
}

// render_windows_components: every window bit-identical (mean and standard error, both components) to
// render_components_with_error with the scene's camera, first light and seed set to the window's, on the
// ground truth and a coarse scene, with a directional and a moved point light as the first light; pixels
// no window covers stay 0; a window outside the mosaic is an InputError.
TEST(RenderComponents, WindowMosaicEqualsOneRenderPerWindow) {
  for (const bool gt : {true, false}) {
    for (const LightType first : {LightType::Directional, LightType::Point}) {
      Scene s = gt ? ground_truth_scene() : coarse_scene("directional-view");
      s.settings.width = 5, s.settings.height = 3;  // odd sizes: no tiling accident
      if (first == LightType::Point) std::swap(s.lights[0], s.lights[1]);
      std::vector<RenderWindow> ws;
      for (int i = 0; i < 4; ++i) {
        RenderWindow w{s.camera, s.lights[0], 100u + 7u * uint32_t(i), 5 * (i % 2), 3 * (i / 2)};
        w.camera.eye = w.camera.eye + Vec3f(0.1f * float(i), -0.05f * float(i), 0);
        w.camera.target = w.camera.target + Vec3f(0.1f * float(i), -0.05f * float(i), 0);
        if (first == LightType::Point) w.light.position = w.light.position + Vec3f(0.2f * float(i), 0, 0);
        ws.push_back(w);
      }
      const std::string what = std::string(gt ? "ground truth" : "coarse") +
                               (first == LightType::Point ? ", point light first" : ", directional first");
      const Renderer r(s);
      const std::array<RenderResult, 2> mosaic = r.render_windows_components(ws, 11, 7);  // a column spare
      for (std::size_t wi = 0; wi < ws.size(); ++wi) {
        Scene one = s;
        one.camera = ws[wi].camera, one.lights[0] = ws[wi].light, one.settings.seed = ws[wi].seed;
        const std::array<RenderResult, 2> ref = Renderer(one).render_components_with_error();
        for (int c = 0; c < 2; ++c)
          for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 5; ++x) {
              const Rgbf a = mosaic[c].mean.at(ws[wi].x0 + x, ws[wi].y0 + y), b = ref[c].mean.at(x, y);
              const Rgbf ea = mosaic[c].std_error.at(ws[wi].x0 + x, ws[wi].y0 + y),
                         eb = ref[c].std_error.at(x, y);
              ASSERT_EQ(std::memcmp(&a, &b, sizeof(Rgbf)), 0) << what << " window " << wi << " c " << c;
              ASSERT_EQ(std::memcmp(&ea, &eb, sizeof(Rgbf)), 0) << what << " window " << wi << " c " << c;
            }
        EXPECT_GT(total(ref[0].mean), 0.0) << what;
      }
      for (int y = 0; y < 7; ++y) EXPECT_EQ(mosaic[0].mean.at(10, y).r, 0.0f);
      EXPECT_EQ(mosaic[0].stats.camera_rays, uint64_t(4 * 5 * 3 * s.settings.spp)) << what;
      ws[3].x0 = 7;  // 7 + 5 > 11
      EXPECT_THROW(r.render_windows_components(ws, 11, 7), InputError) << what;
    }
  }
}
