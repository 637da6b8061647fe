// Renderer tests: closed-form golden images (analytic sphere and plane under a directional light, Lambert),
// sphere-light irradiance, the height-field ray caster and micro-occlusion bake against geometry with a known
// answer, tangent frames, scene/OBJ parsing errors, image metrics, and determinism across thread counts.
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/image.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/scene.h>
#include <microshadow/render/texture_gen.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

using namespace msh;
using namespace msh::render;

namespace {

// Pure Lambert (specular 0), albedo 0.5, one directional light from elevation 35°, azimuth 20°.
const char* kLambertSphere = R"({
  "camera": {"eye": [0, -4, 1], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 40},
  "materials": {"m": {"base_color": 0.5, "roughness": 0.7, "specular": 0}},
  "objects": [{"type": "sphere", "material": "m", "center": [0, 0, 0], "radius": 1}],
  "lights": [{"type": "directional", "elevation_deg": 35, "azimuth_deg": 20, "intensity": 2}],
  "settings": {"width": 48, "height": 40, "spp": 1, "background": 0.25}
})";

struct Ray {
  Vec3d o, d;
};
// The camera model of docs/renderer.md, in double: pixel centre (x + 0.5, y + 0.5) for spp = 1.
Ray camera_ray(const Scene& s, int x, int y) {
  const Vec3d eye(s.camera.eye), f = normalize(Vec3d(s.camera.target) - eye);
  const Vec3d r = normalize(cross(f, Vec3d(s.camera.up))), up = cross(r, f);
  const double th = std::tan(0.5 * s.camera.fov_deg * kPi<double> / 180);
  const double aspect = double(s.settings.width) / s.settings.height;
  const double px = (2 * (x + 0.5) / s.settings.width - 1) * th * aspect,
               py = (1 - 2 * (y + 0.5) / s.settings.height) * th;
  return {eye, normalize(f + r * px + up * py)};
}

}  // namespace

// Golden image from an independent path: for each pixel, the ray–sphere hit in double and ρ/π · E · max(0,
// n·l). Tolerance: 2e-4 relative (float renderer vs double closed form); pixels whose ray grazes the
// silhouette
// (|discriminant| < 1e-3) are skipped, since float and double may disagree on hit/miss there.
TEST(RenderGolden, LambertSphereMatchesClosedForm) {
  const Scene s = parse_scene(kLambertSphere, "inline.json", ".");
  const Renderer r(s);
  const Vec3d l = Vec3d(direction_from_angles(35, 20));
  int checked_hit = 0, checked_miss = 0;
  for (int y = 0; y < s.settings.height; ++y)
    for (int x = 0; x < s.settings.width; ++x) {
      const Ray ray = camera_ray(s, x, y);
      const double b = dot(ray.o, ray.d), c = dot(ray.o, ray.o) - 1, disc = b * b - c;
      if (std::abs(disc) < 1e-3) continue;
      const Rgbf got = r.render_pixel(x, y);
      double expect = 0.25;
      if (disc > 0) {
        const Vec3d n = normalize(ray.o + ray.d * (-b - std::sqrt(disc)));
        expect = 0.5 / kPi<double> * 2.0 * std::max(0.0, dot(n, l));
        ++checked_hit;
      } else {
        ++checked_miss;
      }
      EXPECT_NEAR(got.r, expect, 2e-4 * std::max(expect, 0.01) + 1e-6) << x << "," << y;
      EXPECT_EQ(got.r, got.g);
    }
  EXPECT_GT(checked_hit, 300);
  EXPECT_GT(checked_miss, 300);
}

// Plane with constant visibility V: every method's term is a closed form of (V, N·L)
// (docs/micro-shadowing.md), written here independently of the micro-shadowing module.
TEST(RenderGolden, PlaneMicroShadowingTermsMatchClosedForms) {
  const double V = 0.6, el = 30, nl = std::sin(el * kPi<double> / 180);
  const double base = 0.5 / kPi<double> * 2.0 * nl;
  const double cos_t = std::sqrt(1 - V);
  const std::vector<std::pair<std::string, double>> cases = {
      {"none", 1.0},
      {"ao", V},
      {"reference", nl > cos_t ? 1.0 : 0.0},
      {"brinck-maximov-2016", std::clamp(nl + 2 * V * V - 1, 0.0, 1.0)},
      {"chan-2018", std::pow(std::clamp(nl / cos_t, 0.0, 1.0), 2.0)},
      {"part1-analytic", std::pow(std::clamp(nl / std::sqrt(1 - std::pow(V, 5)), 0.0, 1.0), 0.75 / V)}};
  for (const auto& [method, term] : cases) {
    const std::string json = R"({
      "camera": {"eye": [0, -2, 2], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30},
      "materials": {"m": {"base_color": 0.5, "specular": 0, "micro_occlusion": 0.6}},
      "objects": [{"type": "plane", "material": "m", "size": [20, 20]}],
      "lights": [{"type": "directional", "elevation_deg": 30, "intensity": 2}],
      "settings": {"width": 8, "height": 8, "spp": 2, "micro_shadowing": ")" +
                             method + R"("}})";
    const Scene s = parse_scene(json, "inline.json", ".");
    const Image img = Renderer(s).render();
    for (const Rgbf& p : img.px) EXPECT_NEAR(p.r, base * term, 1e-5 + 1e-4 * base) << method;
  }
}

// Every method of the registry renders (the renderer has no list of its own), with finite values in [0, the
// unshadowed image] (the directional term of a flat surface is 1); a pair's diffuse component is its diffuse
// term's and its specular component its specular term's, bit for bit.
TEST(RenderMethods, EveryRegistryMethodRendersAndPairsSplitByLobe) {
  const std::string scene = R"({
      "camera": {"eye": [0, -2, 2], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30},
      "materials": {"m": {"base_color": 0.5, "roughness": 0.5, "micro_occlusion": 0.7}},
      "objects": [{"type": "plane", "material": "m", "size": [20, 20]}],
      "lights": [{"type": "directional", "elevation_deg": 40, "azimuth_deg": 30, "intensity": 2}],
      "settings": {"width": 6, "height": 6, "spp": 1, "vndf_samples": 8}})";
  auto render = [&](const std::string& method, Component c) {
    Scene s = parse_scene(scene, "inline.json", ".");
    // Directional channels of a flat surface (transport = N·L: the z channel is 1; slopes 0), all 21.
    s.materials[0].directional = Texture(1, 1, 21);
    s.materials[0].directional.at(0, 0, 3) = 1.0f;
    s.settings.micro_shadowing = method;
    s.settings.component = c;
    return Renderer(s).render();
  };
  const Image none = render("none", Component::Total);
  const auto names = micro_shadowing_names();
  EXPECT_EQ(names.back(), kGroundTruth);
  for (const std::string& name : names) {
    if (name == kGroundTruth) continue;
    const Image img = render(name, Component::Total);
    for (std::size_t i = 0; i < img.px.size(); ++i) {
      EXPECT_TRUE(std::isfinite(img.px[i].r)) << name;
      EXPECT_GE(img.px[i].r, 0.0f) << name;
      EXPECT_LE(img.px[i].r, none.px[i].r * (1 + 1e-6f)) << name;
    }
    const auto plus = name.find('+');
    if (plus == std::string::npos) continue;
    for (const auto& [c, part] : {std::pair{Component::Diffuse, name.substr(0, plus)},
                                  std::pair{Component::Specular, name.substr(plus + 1)}}) {
      const Image a = render(name, c), b = render(part, c);
      for (std::size_t i = 0; i < a.px.size(); ++i) EXPECT_EQ(a.px[i].r, b.px[i].r) << name << " " << part;
    }
  }
}

// The view correction reads the camera in the texture's tangent space (x = +u, y = +v): constant channels
// T = l.z, G_x = gx, G_y = gy give the diffuse radiance of `directional` times 1 + (gx v_x + gy v_y)/(v_z
// l.z), v toward the eye. A narrow camera (1°) makes v the same at every pixel; the plane's tangent (+x, or
// +y with v = cross(n, t) = −x) fixes what v_x, v_y are, independently of the renderer's frames.
TEST(RenderMethods, DirectionalViewReadsTheCameraInTangentSpace) {
  struct Case {
    const char* eye;
    const char* tangent;
    float gx, gy, vx, vy;  // v = (vx, vy, 1)/√2 in tangent space
  };
  const double el = 40, lz = std::sin(el * kPi<double> / 180);
  for (const Case& k :
       {Case{"[0, -2, 2]", "[1, 0, 0]", 0.0f, 0.2f, 0, -1},
        Case{"[0, -2, 2]", "[1, 0, 0]", 0.3f, 0.0f, 0, -1},
        Case{"[2, 0, 2]", "[1, 0, 0]", -0.25f, 0.0f, 1, 0}, Case{"[2, 0, 2]", "[0, 1, 0]", 0.0f, 0.2f, 0, -1},
        Case{"[2, 0, 2]", "[0, 1, 0]", 0.3f, 0.0f, 0, -1}}) {
    const std::string json = std::string(R"({
      "camera": {"eye": )") + k.eye +
                             R"(, "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 1},
      "materials": {"m": {"base_color": 0.5, "specular": 0}},
      "objects": [{"type": "plane", "material": "m", "size": [20, 20], "tangent": )" +
                             k.tangent + R"(}],
      "lights": [{"type": "directional", "elevation_deg": 40, "azimuth_deg": 30, "intensity": 2}],
      "settings": {"width": 3, "height": 3, "spp": 1, "component": "diffuse"}})";
    auto render = [&](const char* method) {
      Scene s = parse_scene(json, "inline.json", ".");
      s.materials[0].directional = Texture(1, 1, 21);
      s.materials[0].directional.at(0, 0, 3) = 1.0f;
      s.materials[0].directional.at(0, 0, 9) = k.gx;
      s.materials[0].directional.at(0, 0, 15) = k.gy;
      s.settings.micro_shadowing = method;
      return Renderer(s).render();
    };
    const Image d = render("directional"), v = render("directional-view");
    const double expect = 1 + (k.gx * k.vx + k.gy * k.vy) / lz;
    for (std::size_t i = 0; i < d.px.size(); ++i) {
      ASSERT_GT(d.px[i].r, 0.01f);
      EXPECT_NEAR(v.px[i].r / d.px[i].r, expect, 0.01)
          << k.eye << " " << k.tangent << " " << k.gx << " " << k.gy;
    }
  }
}

// A method that reads the directional channels refuses a material without them, naming both.
TEST(RenderMethods, DirectionalNeedsItsChannels) {
  const std::string scene = R"({
      "materials": {"m": {"base_color": 0.5}}, "objects": [{"type": "plane", "material": "m"}], "lights": [],
      "lights": [{"type": "directional", "elevation_deg": 40, "intensity": 2}],
      "settings": {"width": 4, "height": 4, "micro_shadowing": "directional"}})";
  const Scene s = parse_scene(scene, "inline.json", ".");
  try {
    Renderer r(s);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("directional"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'m'"), std::string::npos) << e.what();
  }
}

// A sphere light of intensity I at distance d, seen by a Lambert plane facing its centre: irradiance is
// π L sin²α = I/d² exactly (uniform sphere fully above the horizon), for area sampling and the representative
// point alike.
TEST(RenderLights, SphereLightIrradianceClosedForm) {
  for (const bool area : {false, true}) {
    const std::string json = std::string(R"({
      "camera": {"eye": [0, -3, 0.5], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 1},
      "materials": {"m": {"base_color": 0.5, "specular": 0}},
      "objects": [{"type": "plane", "material": "m", "size": [4, 4]}],
      "lights": [{"type": "sphere", "position": [0, 0, 2], "radius": 0.8, "intensity": 8}],
      "settings": {"width": 1, "height": 1, "spp": 1, "area_samples": 256, "area_lights": )") +
                             (area ? "true" : "false") + "}}";
    // Look at the origin from the side (the light is not visible to camera rays).
    Scene s = parse_scene(json, "inline.json", ".");
    s.camera.eye = {0.0f, -3.0f, 0.5f};
    s.camera.up = {0, 0, 1};
    const Renderer r(s);
    const Rgbf got = r.render_pixel(0, 0);
    // The pixel ray hits the plane near the origin; the exact formula at that point: I/d² · cos... evaluate
    // it.
    const Vec3d eye(s.camera.eye), d = normalize(Vec3d(s.camera.target) - eye);
    const Vec3d p = eye + d * (-eye.z / d.z);
    const Vec3d c(0, 0, 2);
    const double dist = length(c - p), cosn = (c - p).z / dist;
    // Uniform sphere of radiance L = I/(πr²) fully above the horizon: E = I cosθ / d² (cosθ at the centre).
    const double expect = 0.5 / kPi<double> * 8.0 * cosn / (dist * dist);
    EXPECT_NEAR(got.r, expect, (area ? 0.01 : 1e-4) * expect) << (area ? "area" : "representative");
  }
}

// Every shape is found by one Embree query: the closest hit across analytic spheres, a plane and meshes must
// not depend on the order of the objects (three overlapping depths along the view, each kind in front of
// another somewhere in the frame), and a permutation renders the same image bit for bit.
TEST(Render, ClosestHitAcrossShapeKindsIndependentOfObjectOrder) {
  const std::vector<std::string> objs = {
      R"({"type": "sphere", "material": "a", "center": [0, 0, 0.6], "radius": 0.6})",
      R"({"type": "uv-sphere", "material": "b", "center": [0.5, -0.6, 0.5], "radius": 0.5, "segments": 16, "rings": 8})",
      R"({"type": "cylinder", "material": "c", "center": [-0.6, -0.3, 0], "radius": 0.35, "height": 1.2})",
      R"({"type": "plane", "material": "d", "center": [0, 0, 0.3], "size": [3, 3]})"};
  auto render = [&](const std::vector<int>& order) {
    std::string list;
    for (int i : order) list += (list.empty() ? "" : ", ") + objs[i];
    const std::string json = R"({"camera": {"eye": [0.3, -4, 1.6], "target": [0, 0, 0.4], "up": [0, 0, 1]},
      "materials": {"a": {"base_color": [0.9, 0.1, 0.1]}, "b": {"base_color": [0.1, 0.9, 0.1]},
                    "c": {"base_color": [0.1, 0.1, 0.9]}, "d": {"base_color": [0.5, 0.5, 0.5]}},
      "objects": [)" + list + R"(], "lights": [{"type": "directional", "elevation_deg": 50}],
      "settings": {"width": 40, "height": 32, "spp": 1}})";
    return Renderer(parse_scene(json, "inline.json", ".")).render();
  };
  const Image a = render({0, 1, 2, 3}), b = render({3, 2, 1, 0}), c = render({1, 3, 0, 2});
  ASSERT_EQ(a.px.size(), b.px.size());
  int diff_ab = 0, diff_ac = 0;
  for (std::size_t i = 0; i < a.px.size(); ++i)
    for (int k = 0; k < 3; ++k) diff_ab += a.px[i][k] != b.px[i][k], diff_ac += a.px[i][k] != c.px[i][k];
  EXPECT_EQ(diff_ab, 0);
  EXPECT_EQ(diff_ac, 0);
  // Each material is visible somewhere (the test sees every shape kind win a pixel): the dominant channel of
  // the pixel colours covers red, green, blue and grey.
  bool seen[4] = {};
  for (const Rgbf& p : a.px) {
    if (p.r > 2 * p.g && p.r > 2 * p.b) seen[0] = true;
    if (p.g > 2 * p.r && p.g > 2 * p.b) seen[1] = true;
    if (p.b > 2 * p.r && p.b > 2 * p.g) seen[2] = true;
    if (p.r > 0.05f && std::abs(p.r - p.g) < 0.1f * p.r && std::abs(p.r - p.b) < 0.1f * p.r) seen[3] = true;
  }
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(seen[k]) << k;
}

// Bilinear wrap-addressed lookup against an independent double-precision evaluation of the documented
// convention (texel (i, j) centred at ((i + 0.5)/w, (j + 0.5)/h), wrap by the mathematical modulo), at
// off-texel points on and far outside [0, 1)², including negative coordinates and |u| large enough to need
// many wraps.
TEST(Texture, BilinearWrapMatchesIndependentReference) {
  const int w = 7, h = 5;
  Texture t(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) t.at(x, y, c) = float(std::sin(1.3 * x + 2.1 * y + 0.7 * c) + 0.1 * c);
  auto ref = [&](float u, float v, int c) {
    // The pixel position is formed in float as the texture does; everything after in double.
    const double x = double(u * float(w) - 0.5f), y = double(v * float(h) - 0.5f);
    const double fx = std::floor(x), fy = std::floor(y), tx = x - fx, ty = y - fy;
    auto md = [](double a, int n) {  // mathematical modulo (std::fmod is exact)
      const double r = std::fmod(a, double(n));
      return int(r < 0 ? r + n : r);
    };
    auto at = [&](double xx, double yy) { return double(t.at(md(xx, w), md(yy, h), c)); };
    return (1 - ty) * ((1 - tx) * at(fx, fy) + tx * at(fx + 1, fy)) +
           ty * ((1 - tx) * at(fx, fy + 1) + tx * at(fx + 1, fy + 1));
  };
  int n = 0;
  for (float u : {0.0f, 0.013f, 0.37f, 0.999f, 1.0f, -0.21f, -3.77f, 12.6f, 4097.31f, -65537.9f})
    for (float v : {0.0f, 0.5f, 0.91f, -1.45f, 31.07f, -9999.5f}) {
      const Rgbf s = t.sample_rgb(u, v);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(t.sample(u, v, c), ref(u, v, c), 1e-5) << u << " " << v << " " << c;
        EXPECT_EQ(s[c], t.sample(u, v, c));
        ++n;
      }
    }
  EXPECT_EQ(n, 180);
  // Texel centres return the texel itself, in every wrapped copy (to the rounding of u + k).
  for (int x = 0; x < w; ++x)
    for (int k : {-3, 0, 2})
      EXPECT_NEAR(t.sample((float(x) + 0.5f) / float(w) + float(k), 0.5f / float(h), 1), t.at(x, 0, 1), 1e-5);
  // Channels past the last clamp to it; an empty texture samples 0; non-finite coordinates give NaN, not UB.
  Texture g(2, 2, 1);
  g.at(0, 0, 0) = 0.25f, g.at(1, 0, 0) = 0.5f, g.at(0, 1, 0) = 0.75f, g.at(1, 1, 0) = 1.0f;
  const Rgbf gs = g.sample_rgb(0.4f, 0.6f);
  EXPECT_EQ(gs.r, gs.g);
  EXPECT_EQ(gs.r, gs.b);
  EXPECT_EQ(Texture().sample(0.3f, 0.3f), 0.0f);
  EXPECT_TRUE(std::isnan(t.sample(std::numeric_limits<float>::infinity(), 0.5f)));
  EXPECT_TRUE(std::isnan(t.sample(0.5f, std::nanf(""))));
  EXPECT_NEAR(t.sample(3e20f, 0.5f), ref(3e20f, 0.5f, 0), 1e-5);  // past the int64 range: the fmod path
}

// Height-field ray casting against a tilted plane (a ramp z = a x + b y + c in grid space, vertex (i, j) at
// height (h_ij − 1)·depth): the hit is the ray–plane intersection in closed form, the normal the plane's.
TEST(HeightField, RampIntersectionIsExact) {
  const float depth = 4.0f;
  Texture h(32, 32, 1);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) h.at(i, j, 0) = (float(i) + 0.5f * float(j)) / 46.5f;
  const HeightField hf(h, depth);
  const double a = depth / 46.5, b = 0.5 * depth / 46.5, c = -depth;
  const Vec3d n_expect = normalize(Vec3d(-a, -b, 1));
  int hits = 0;
  for (int k = 0; k < 64; ++k) {
    // Ray origins above the interior, directions spread over the upper hemisphere (away from the wrap seam).
    const Vec3f o(6.0f + 0.29f * float(k), 20.0f - 0.17f * float(k), 3.0f);
    const Vec3f d =
        normalize(Vec3f(0.3f * std::cos(0.7f * float(k)), 0.3f * std::sin(0.7f * float(k)), -1.0f));
    float t;
    Vec3f ng;
    ASSERT_TRUE(hf.intersect(o, d, 0, 1e9f, {0, 0}, {31, 31}, &t, &ng)) << k;
    const Vec3d od(o), dd(d);
    const double t_expect = (a * od.x + b * od.y + c - od.z) / (dd.z - a * dd.x - b * dd.y);
    EXPECT_NEAR(t, t_expect, 1e-5 * t_expect) << k;
    EXPECT_NEAR(dot(Vec3d(ng), n_expect), 1.0, 1e-6) << k;
    ++hits;
  }
  EXPECT_EQ(hits, 64);
  float t;
  Vec3f ng;
  // Upward rays, rays outside the extent and rays that hit only the back of the surface miss.
  const Vec3f o(10.3f, 12.7f, 3.0f), d = normalize(Vec3f(0.3f, -0.2f, -1.0f));
  EXPECT_FALSE(hf.intersect(o, Vec3f(0, 0, 1), 0, 1e9f, {0, 0}, {31, 31}, &t, &ng));
  EXPECT_FALSE(hf.intersect(o, d, 0, 1e9f, {25, 25}, {31, 31}, &t, &ng));
  EXPECT_FALSE(hf.intersect(Vec3f(10.3f, 12.7f, -10.0f), Vec3f(0, 0, 1), 0, 1e9f, {0, 0}, {31, 31}, &t, &ng));
}

// Micro-occlusion bake: a flat field is fully visible; at the foot of a (practically) infinite wall, half of
// the cosine-weighted hemisphere is blocked, V → 1/2 (the wall occupies the half-space x > 0; rays reach at
// most 8 texels, so the far wall of the wrapped stripe, 31 texels away, is out of reach).
TEST(TextureGen, BakeMatchesKnownVisibility) {
  Texture flat(32, 8, 1);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 32; ++i) flat.at(i, j, 0) = 0.7f;
  const Texture v0 = bake_visibility(flat, 5.0f, 64, 8.0f);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 32; ++i) EXPECT_EQ(v0.at(i, j, 0), 1.0f);
  Texture wall(64, 8, 1);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 64; ++i) wall.at(i, j, 0) = i >= 32 ? 1.0f : 0.0f;
  // 256 azimuths: the bake integrates each azimuth's elevation exactly, so the azimuth rule's error on this
  // piecewise-smooth horizon is far below the tolerance.
  const Texture v = bake_visibility(wall, 1000.0f, 256, 8.0f);
  // Near-vertical directions with sin θ < 1/8 can clear the 1-texel ramp: at most sin²θ = 1/64 more
  // visibility.
  EXPECT_NEAR(v.at(31, 3, 0), 0.5f + 0.5f / 64, 0.02f);
}

TEST(TextureGen, DeterministicAndThreadIndependent) {
  GenOptions o;
  o.size = 32;
  o.ao_rays = 16;
  TextureSet a, b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    a = generate_texture_set(o);
  }
  b = generate_texture_set(o);
  for (int j = 0; j < 32; ++j)
    for (int i = 0; i < 32; ++i) {
      EXPECT_EQ(a.height.at(i, j, 0), b.height.at(i, j, 0));
      EXPECT_EQ(a.visibility.at(i, j, 0), b.visibility.at(i, j, 0));
    }
  o.kind = "wood";
  EXPECT_THROW(generate_texture_set(o), InputError);
}

// The ground truth of a flat height field equals the flat plane without micro-shadowing.
TEST(RenderGroundTruth, FlatHeightFieldEqualsFlatPlane) {
  const auto dir = std::filesystem::temp_directory_path() / "msh_test_render_flat";
  std::filesystem::create_directories(dir);
  TextureSet set;
  set.height = Texture(16, 16, 1);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) set.height.at(i, j, 0) = 1.0f;
  set.normal = normal_map_from_height(set.height, 4);
  set.roughness = set.metallic = set.visibility = set.height;
  set.base_color = Texture::constant({0.5f, 0.5f, 0.5f, 1}, 3);
  set.depth_texels = 4;
  write_texture_set(dir, set);
  const std::string json = R"({
    "camera": {"eye": [0, -1.5, 1.5], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30},
    "materials": {"m": {"base_color": 0.5, "normal": "normal.png", "roughness": 0.6, "height": "height.png",
                        "height_texels": 4}},
    "objects": [{"type": "plane", "material": "m", "size": [2, 2]}],
    "lights": [{"type": "directional", "elevation_deg": 30, "intensity": 2}],
    "settings": {"width": 16, "height": 16, "spp": 1}})";
  Scene s = parse_scene(json, "inline.json", dir);
  const Image flat = Renderer(s).render();
  s.settings.micro_shadowing = kGroundTruth;
  const Image gt = Renderer(s).render();
  EXPECT_LT(rmse(flat, gt), 1e-4);
  std::filesystem::remove_all(dir);
}

// MikkTSpace convention on the UV sphere: tangent along ∂P/∂u (east), bitangent sign makes w·(n × t) point
// along ∂P/∂v (south, v grows from the north pole).
TEST(Mesh, UvSphereTangentsFollowConvention) {
  const Mesh m = make_uv_sphere(1.0f, 16, 8);
  for (std::size_t i = 0; i < m.p.size(); ++i) {
    const Vec3f n = m.n[i];
    const float s = std::sqrt(n.x * n.x + n.y * n.y);
    if (s < 0.2f) continue;  // poles: ∂P/∂u vanishes
    const Vec3f east(-n.y / s, n.x / s, 0), t(m.tangent[i][0], m.tangent[i][1], m.tangent[i][2]);
    EXPECT_GT(dot(t, east), 0.97f) << i;
    const Vec3f b = cross(n, t) * m.tangent[i][3];
    EXPECT_LT(b.z, 0.0f) << i;  // south
  }
}

TEST(Mesh, ObjLoaderAndErrors) {
  const auto dir = std::filesystem::temp_directory_path() / "msh_test_render_obj";
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir / "quad.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                       "f 1/1 2/2 3/3 4/4\n";
    std::ofstream(dir / "bad.obj") << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
    std::ofstream(dir / "junk.obj") << "v 0 zero 0\n";
  }
  const Mesh m = load_obj(dir / "quad.obj");
  EXPECT_EQ(m.tri.size(), 2u);
  for (const auto& n : m.n) EXPECT_NEAR(n.z, 1.0f, 1e-6f);
  for (const auto& t : m.tangent) EXPECT_NEAR(t[0], 1.0f, 1e-5f);
  for (const char* f : {"bad.obj", "junk.obj", "missing.obj"}) {
    try {
      load_obj(dir / f);
      ADD_FAILURE() << f;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(SceneJson, StrictErrorsNameFileAndKey) {
  // A valid one-sphere scene with this "settings" object.
  const auto with_settings = [](const std::string& settings) {
    return R"({"materials": {"m": {}}, "objects": [{"type": "sphere", "material": "m"}], "lights": [],
               "settings": )" +
           settings + "}";
  };
  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"materials": {"m": {}}, "objects": [{"type": "sphere", "material": "m"}], "lights": [], "bogus": 1})",
       "bogus"},
      {R"({"materials": {"m": {"roughnes": 0.5}}, "objects": [{"type": "sphere", "material": "m"}], "lights": []})",
       "roughnes"},
      {R"({"materials": {"m": {}}, "objects": [{"type": "torus", "material": "m"}], "lights": []})", "torus"},
      {R"({"materials": {"m": {}}, "objects": [{"type": "sphere", "material": "x"}], "lights": []})", "'x'"},
      {R"({"materials": {"m": {"base_color": "nope.png"}}, "objects": [{"type": "sphere", "material": "m"}],
          "lights": []})",
       "nope.png"},
      {with_settings(R"({"micro_shadowing": "magic"})"), "magic"},
      {with_settings(R"({"micro_shadowing": "part1"})"), "is now called 'part1-analytic'"},
      {with_settings(R"({"width": 100000})"), "width"},
      {R"({"materials": {"m": {}}, "objects": [{"type": "sphere", "material": "m", "radius": -1}], "lights": []})",
       "radius"},
      {with_settings(R"({"component": "both"})"), "component"},
      {with_settings(R"({"ground_truth_intersector": "optix"})"), "ground_truth_intersector"},
      {R"({"camera": {"projection": "fisheye"}, "materials": {"m": {}},
          "objects": [{"type": "sphere", "material": "m"}], "lights": []})",
       "projection"},
      {with_settings(R"({"error_batches": 0})"), "error_batches"},
      {R"({"materials": {"m": {}}, "objects": [)", "malformed JSON"}};
  for (const auto& [json, word] : bad) {
    try {
      parse_scene(json, "scene_under_test.json", ".");
      ADD_FAILURE() << "accepted: " << json;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("scene_under_test.json"), std::string::npos) << msg;
      EXPECT_NE(msg.find(word), std::string::npos) << msg;
    }
  }
}

TEST(ImageMetrics, RmseAndSsim) {
  Image a(32, 32), b(32, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x)
      a.at(x, y) = Rgbf(float((x * 7 + y * 3) % 11) / 11.0f), b.at(x, y) = a.at(x, y) + Rgbf(0.1f);
  EXPECT_NEAR(rmse(a, b), 0.1, 1e-6);
  EXPECT_NEAR(ssim(a, a, 0), 1.0, 1e-12);
  EXPECT_LT(ssim(a, Image(32, 32), 0), 0.5);
  EXPECT_NEAR(srgb_decode(srgb_encode(0.3f)), 0.3f, 1e-6f);
}

// Every pixel has its own random streams: the image is bit-identical with 1 and 2 threads.
TEST(RenderDeterminism, SameImageWhateverTheThreadCount) {
  const std::string json = R"({
    "camera": {"eye": [0, -6, 3], "target": [0, 0, 0.5], "up": [0, 0, 1], "fov_deg": 40},
    "materials": {"a": {"base_color": [0.7, 0.3, 0.2], "roughness": 0.3, "micro_occlusion": 0.7},
                  "b": {"base_color": 0.5, "roughness": 0.8}},
    "objects": [{"type": "uv-sphere", "material": "a", "center": [-1, 0, 1], "radius": 1},
                {"type": "cylinder", "material": "a", "center": [1.5, 0, 0.5], "radius": 0.5, "height": 1},
                {"type": "plane", "material": "b", "size": [10, 10]}],
    "lights": [{"type": "sphere", "position": [2, -2, 3], "radius": 0.5, "intensity": 10},
               {"type": "directional", "elevation_deg": 40, "intensity": 1}],
    "settings": {"width": 40, "height": 30, "spp": 3, "micro_shadowing": "generic-vndf", "vndf_samples": 8,
                 "area_lights": true, "area_samples": 4, "hanika_offset": true}})";
  const Scene s = parse_scene(json, "inline.json", ".");
  Image one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = Renderer(s).render();
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = Renderer(s).render();
  }
  ASSERT_EQ(one.px.size(), two.px.size());
  for (std::size_t i = 0; i < one.px.size(); ++i) ASSERT_TRUE(one.px[i] == two.px[i]) << i;
  double sum = 0;
  for (const Rgbf& p : one.px) sum += p.r;
  EXPECT_GT(sum, 1.0);  // the scene is lit
}

// With a (constant) normal map, the shading normal n_s sets the cosine, and the term's N·L comes from n_s
// (default) or from the unperturbed normal (micro_shadowing_normal = smooth): both closed forms.
TEST(RenderGolden, MicroShadowingNormalChoice) {
  // Tangent-space normal (0.3, 0, 0.954) encoded n·0.5 + 0.5; the plane's tangent is +x, the light comes from
  // +x.
  const double nx = 0.3, nz = std::sqrt(1 - nx * nx), V = 0.5, el = 20;
  const Vec3d l(std::cos(el * kPi<double> / 180), 0, std::sin(el * kPi<double> / 180));
  const double nl_shading = nx * l.x + nz * l.z, nl_flat = l.z;
  auto chan = [&](double nl) { return std::pow(std::clamp(nl / std::sqrt(1 - V), 0.0, 1.0), 2.0); };
  for (const bool smooth : {false, true}) {
    const std::string json = std::string(R"({
      "camera": {"eye": [0, -2, 2], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 20},
      "materials": {"m": {"base_color": 0.5, "specular": 0, "micro_occlusion": 0.5,
                          "normal": [0.65, 0.5, 0.9770084209183945]}},
      "objects": [{"type": "plane", "material": "m", "size": [20, 20]}],
      "lights": [{"type": "directional", "elevation_deg": 20, "intensity": 2}],
      "settings": {"width": 4, "height": 4, "spp": 1, "micro_shadowing": "chan-2018",
                   "micro_shadowing_normal": ")") +
                             (smooth ? "smooth" : "shading") + R"("}})";
    const Image img = Renderer(parse_scene(json, "inline.json", ".")).render();
    const double expect = 0.5 / kPi<double> * 2.0 * nl_shading * chan(smooth ? nl_flat : nl_shading);
    for (const Rgbf& p : img.px) EXPECT_NEAR(p.r, expect, 2e-4 * expect) << smooth;
  }
}

// settings.component: on a flat GGX + Lambert plane (F0 = 0.04, roughness 0.5) seen through one pixel, the
// specular part is Schlick F · D · G2 / (4 N·V) · E and the diffuse part (1 − F) ρ/π N·L · E, written here in
// double from the textbook formulas (RTR4 9.34, 9.41, 9.31, 9.16, 9.62-style coupling with F(v·h)).
TEST(RenderComponent, DiffuseAndSpecularMatchClosedForms) {
  const double el = 40, az = 180, r = 0.5, a = r * r, rho = 0.5, E = 2;
  for (const char* comp : {"total", "diffuse", "specular"}) {
    const std::string json = std::string(R"({
      "camera": {"eye": [1.5, 0, 1.2], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 0.01},
      "materials": {"m": {"base_color": 0.5, "roughness": 0.5}},
      "objects": [{"type": "plane", "material": "m", "size": [4, 4]}],
      "lights": [{"type": "directional", "elevation_deg": 40, "azimuth_deg": 180, "intensity": 2}],
      "settings": {"width": 1, "height": 1, "spp": 1, "component": ")") +
                             comp + R"("}})";
    const Scene s = parse_scene(json, "inline.json", ".");
    const Rgbf got = Renderer(s).render_pixel(0, 0);
    const Vec3d v = normalize(Vec3d(1.5, 0, 1.2)), l = Vec3d(direction_from_angles(float(el), float(az)));
    const Vec3d h = normalize(v + l);
    const double F = 0.04 + 0.96 * std::pow(1 - dot(v, h), 5);
    const double D = a * a / (kPi<double> * sqr(h.z * h.z * (a * a - 1) + 1));
    auto lambda = [&](const Vec3d& w) {
      const double t2 = (1 - w.z * w.z) / (w.z * w.z);
      return 0.5 * (-1 + std::sqrt(1 + a * a * t2));
    };
    const double G2 = 1 / (1 + lambda(v) + lambda(l));
    const double spec = F * D * G2 / (4 * v.z) * E, diff = (1 - F) * rho / kPi<double> * l.z * E;
    const double expect = std::string(comp) == "total"     ? spec + diff
                          : std::string(comp) == "diffuse" ? diff
                                                           : spec;
    EXPECT_NEAR(got.r, expect, 1e-3 * expect) << comp;
  }
  EXPECT_THROW(component_from_string("both"), InputError);
}

// The renderer's bump-terminator methods are the registry's (bump::kMethods): every name round-trips, a scene
// file's settings take them, and anything else is refused with the list (the renderer's former "off" with
// its new name).
TEST(Render, BumpTerminatorNamesAreTheRegistrys) {
  for (const bump::MethodInfo& i : bump::kMethods) {
    EXPECT_EQ(bump_terminator_from_string(std::string(i.name)), i.method);
    EXPECT_EQ(std::string_view(to_string(i.method)), i.name);
    const std::string json =
        R"({"camera": {"eye": [0, -3, 2], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30},
      "materials": {"m": {"base_color": 0.5}}, "objects": [{"type": "plane", "material": "m"}], "lights": [],
      "settings": {"bump_terminator": ")" +
        std::string(i.name) + R"("}})";
    EXPECT_EQ(parse_scene(json, "inline.json", ".").settings.bump_terminator, i.method) << i.name;
  }
  EXPECT_EQ(Settings{}.bump_terminator, bump::Method::kNone);
  try {
    bump_terminator_from_string("sideways");
    ADD_FAILURE() << "sideways accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none, conty-2019, chiang-2019"), std::string::npos) << e.what();
  }
  // The renderer's former name of none is refused with the new one (as for the micro-shadowing methods).
  try {
    bump_terminator_from_string("off");
    ADD_FAILURE() << "off accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("now called 'none'"), std::string::npos) << e.what();
  }
}

namespace {

// A plane under a sphere light with one area sample per camera sample (a noisy image), size x size pixels.
Scene noisy_sphere_light_scene(int size, int spp) {
  const std::string json = R"({
    "camera": {"eye": [0, -3, 2], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 30},
    "materials": {"m": {"base_color": 0.5, "roughness": 0.4}},
    "objects": [{"type": "plane", "material": "m", "size": [4, 4]}],
    "lights": [{"type": "sphere", "position": [0.5, 0, 1.5], "radius": 1.0, "intensity": 10}],
    "settings": {"width": )" +
                           std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(, "spp": )" +
                           std::to_string(spp) + R"(, "area_lights": true, "area_samples": 1}})";
  return parse_scene(json, "inline.json", ".");
}

}  // namespace

// render_with_error: with one batch the mean is render() bit for bit; with 8 batches the stated standard
// error matches the scatter of the pixel means over 24 independent seeds (a noisy sphere light with one area
// sample per camera sample).
TEST(RenderError, StandardErrorMatchesScatterOverSeeds) {
  Scene s = noisy_sphere_light_scene(6, 16);
  s.settings.error_batches = 1;
  {
    const Renderer r(s);
    const RenderResult one = r.render_with_error();
    const Image plain = r.render();
    ASSERT_EQ(one.batches, 1);
    for (std::size_t i = 0; i < plain.px.size(); ++i) {
      EXPECT_TRUE(one.mean.px[i] == plain.px[i]) << i;
      EXPECT_EQ(one.std_error.px[i].r, 0.0f);
    }
  }
  s.settings.error_batches = 8;
  const int seeds = 24, n = 36;
  std::vector<double> sum(n, 0), sum2(n, 0), se2(n, 0);
  for (int k = 0; k < seeds; ++k) {
    s.settings.seed = uint32_t(100 + k);
    const RenderResult res = Renderer(s).render_with_error();
    ASSERT_EQ(res.batches, 8);
    for (int i = 0; i < n; ++i) {
      const double m = res.mean.px[i].r;
      sum[i] += m, sum2[i] += m * m, se2[i] += sqr(double(res.std_error.px[i].r));
    }
  }
  double emp = 0, pred = 0;
  for (int i = 0; i < n; ++i) {
    emp += (sum2[i] - sum[i] * sum[i] / seeds) / (seeds - 1);
    pred += se2[i] / seeds;
  }
  ASSERT_GT(pred, 0);
  // Pooled over 36 pixels × 24 seeds, the variance ratio is within ±25% with overwhelming probability.
  EXPECT_NEAR(emp / pred, 1.0, 0.25) << emp << " " << pred;
  s.settings.spp = 12;
  EXPECT_THROW(Renderer(s).render_with_error(), InputError);
}

namespace {

// Top view (orthographic, ortho_height) of a plane of size × 64 with the V-groove height field
// |x mod 8 − 4| / 4 (size × 64 texels), Lambert ρ = 0.5, one directional light of intensity 2 at 20°
// elevation, width × height pixels of 64 spp, ground-truth micro-shadowing.
Scene v_groove_scene(int ortho_height, int size, int width, int height) {
  const std::string json = R"({
    "camera": {"eye": [0, 0, 50], "target": [0, 0, 0], "up": [0, 1, 0], "projection": "orthographic",
               "ortho_height": )" +
                           std::to_string(ortho_height) + R"(},
    "materials": {"m": {"base_color": 0.5, "specular": 0, "roughness": 0.5}},
    "objects": [{"type": "plane", "material": "m", "size": [)" +
                           std::to_string(size) + R"(, 64]}],
    "lights": [{"type": "directional", "elevation_deg": 20, "azimuth_deg": 0, "intensity": 2}],
    "settings": {"width": )" +
                           std::to_string(width) + R"(, "height": )" + std::to_string(height) +
                           R"(, "spp": 64, "micro_shadowing": "ground-truth"}})";
  Scene s = parse_scene(json, "inline.json", ".");
  Texture h(size, 64, 1);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < size; ++i) h.at(i, j, 0) = float(std::abs(i % 8 - 4)) / 4.0f;
  s.materials[0].height = h;
  return s;
}

}  // namespace

// Ground truth against a closed form: a V-groove height field (period 8 texels, walls at slope angle β, kinks
// on vertices so the walls are planar), pure Lambert (specular 0), one directional light from +x at
// elevation e, seen straight down by an orthographic camera over two whole periods. Per period (x ∈ [0, 8],
// peak at 0 and 8, bottom at 4): the wall facing the light (N·L = sin(e + β)) is lit for
// x ≤ min(4, 8 tan e / (tan β + tan e)) — above that the next peak blocks the light — and the wall facing
// away (N·L = sin(e − β)) is lit, unshadowed, when e > β. Mean radiance = ρE/(8π) [x_lit sin(e+β) + 4 max(0,
// sin(e−β))]. Checked to 4 standard errors of the image mean (render_with_error) + 2e-4 relative.
TEST(RenderGroundTruth, VGrooveMeanRadianceMatchesClosedForm) {
  struct Case {
    double beta, el;
  };
  for (const GtIntersector gi : {GtIntersector::HeightField, GtIntersector::Embree})
    for (const Case cs : {Case{45, 20}, Case{45, 60}, Case{26.565, 10}, Case{26.565, 35}, Case{60, 75}}) {
      Scene s = v_groove_scene(16, 64, 32, 32);
      s.settings.gt_intersector = gi;
      const double tb = std::tan(cs.beta * kPi<double> / 180), te = std::tan(cs.el * kPi<double> / 180);
      s.materials[0].height_texels = float(4 * tb);
      s.lights[0].direction = direction_from_angles(float(cs.el), 0);
      const RenderResult res = Renderer(s).render_with_error();
      double mean = 0, var = 0;
      for (std::size_t i = 0; i < res.mean.px.size(); ++i)
        mean += res.mean.px[i].r, var += sqr(double(res.std_error.px[i].r));
      const double n = double(res.mean.px.size());
      mean /= n;
      const double se = std::sqrt(var) / n;
      const double b = cs.beta * kPi<double> / 180, e = cs.el * kPi<double> / 180;
      const double x_lit = std::min(4.0, 8 * te / (tb + te));
      const double expect =
          0.5 * 2 / (8 * kPi<double>)*(x_lit * std::sin(e + b) + 4 * std::max(0.0, std::sin(e - b)));
      EXPECT_NEAR(mean, expect, 4 * se + 2e-4 * expect)
          << "beta " << cs.beta << " el " << cs.el << " se " << se;
    }
}

// The same closed form on a 2048 × 64-texel V-groove field with each pixel covering 16 × 16 texels
// (orthographic, the whole field in view): the multiscale ground truth's setting, grid coordinates up to
// 2048.
TEST(RenderGroundTruth, FineVGroove2048SixteenTexelsPerPixel) {
  const double tb = 1, te = std::tan(20 * kPi<double> / 180);
  for (const GtIntersector gi : {GtIntersector::HeightField, GtIntersector::Embree}) {
    Scene s = v_groove_scene(64, 2048, 128, 4);
    s.settings.gt_intersector = gi;
    s.materials[0].height_texels = 4;
    const RenderResult res = Renderer(s).render_with_error();
    // Skip the first and last pixel columns: the shadow of the plane's far edge (no geometry beyond it).
    double mean = 0, var = 0, n = 0;
    for (int y = 0; y < 4; ++y)
      for (int x = 1; x < 127; ++x)
        mean += res.mean.at(x, y).r, var += sqr(double(res.std_error.at(x, y).r)), ++n;
    mean /= n;
    const double se = std::sqrt(var) / n;
    const double b = kPi<double> / 4, e = 20 * kPi<double> / 180;
    const double expect = 0.5 * 2 / (8 * kPi<double>)*std::min(4.0, 8 * te / (tb + te)) * std::sin(e + b);
    EXPECT_NEAR(mean, expect, 4 * se + 5e-4 * expect) << int(gi) << " se " << se;
  }
}

// A displaced cylinder (flat height map: a 512-sided prism with facet shading) seen side-on by an
// orthographic camera, lit by a directional light at angle a from the view in the plane normal to the axis:
// mean radiance over the projected width = ρE/(4π) [sin a + (π − a) cos a] (Lambert; polygon error
// O(1/512²)).
TEST(RenderGroundTruth, DisplacedCylinderMatchesClosedForm) {
  const char* json = R"({
    "camera": {"eye": [0, -10, 0], "target": [0, 0, 0], "up": [0, 0, 1], "projection": "orthographic",
               "ortho_height": 2},
    "materials": {"m": {"base_color": 0.5, "specular": 0, "roughness": 0.5, "height_texels": 3}},
    "objects": [{"type": "cylinder", "material": "m", "radius": 1, "height": 3.14159, "segments": 16}],
    "lights": [{"type": "directional", "direction": [0, -1, 0], "intensity": 2}],
    "settings": {"width": 64, "height": 16, "spp": 16, "micro_shadowing": "ground-truth"}})";
  for (const double a_deg : {0.0, 30.0, 70.0}) {
    Scene s = parse_scene(json, "inline.json", ".");
    // 512 × 256 texels: texel = 2π/512 around, 3.14159/256 along (square); taller than the view.
    Texture h(512, 256, 1);
    for (int j = 0; j < 256; ++j)
      for (int i = 0; i < 512; ++i) h.at(i, j, 0) = 1.0f;
    s.materials[0].height = h;
    const double a = a_deg * kPi<double> / 180;
    s.lights[0].direction = Vec3f(Vec3d(std::sin(a), -std::cos(a), 0));
    const RenderResult res = Renderer(s).render_with_error();
    double sum = 0, var = 0;
    int n = 0;
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 64; ++x)
        sum += res.mean.at(x, y).r, var += sqr(double(res.std_error.at(x, y).r)), ++n;
    // The view spans 8 world units across (aspect 4) and the cylinder covers 2 of them, over the full view
    // height: mean over the cylinder's projected width = image mean × 4 (background 0).
    const double mean = sum / n * 4.0, se = std::sqrt(var) / n * 4.0;
    const double expect = 0.5 * 2 / (4 * kPi<double>)*(std::sin(a) + (kPi<double> - a) * std::cos(a));
    EXPECT_NEAR(mean, expect, 4 * se + 1e-3 * expect) << a_deg;
  }
}

// The ground truth with a sphere light by area sampling: on a flat height field the irradiance is the closed
// form I cos θ / d² (as for the analytic plane), with both intersectors.
TEST(RenderGroundTruth, SphereLightAreaSamplingOnFlatField) {
  const char* json = R"({
    "camera": {"eye": [0, -3, 0.5], "target": [0, 0, 0], "up": [0, 0, 1], "fov_deg": 1},
    "materials": {"m": {"base_color": 0.5, "specular": 0, "height_texels": 4}},
    "objects": [{"type": "plane", "material": "m", "size": [4, 4]}],
    "lights": [{"type": "sphere", "position": [0, 0, 2], "radius": 0.8, "intensity": 8}],
    "settings": {"width": 1, "height": 1, "spp": 1, "area_samples": 256, "area_lights": true,
                 "micro_shadowing": "ground-truth"}})";
  for (const GtIntersector gi : {GtIntersector::HeightField, GtIntersector::Embree}) {
    Scene s = parse_scene(json, "inline.json", ".");
    s.settings.gt_intersector = gi;
    Texture h(64, 64, 1);
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 64; ++i) h.at(i, j, 0) = 1.0f;
    s.materials[0].height = h;
    const Rgbf got = Renderer(s).render_pixel(0, 0);
    const Vec3d eye(s.camera.eye), d = normalize(Vec3d(s.camera.target) - eye);
    const Vec3d p = eye + d * (-eye.z / d.z), c(0, 0, 2);
    const double dist = length(c - p), expect = 0.5 / kPi<double> * 8.0 * (c - p).z / dist / (dist * dist);
    EXPECT_NEAR(got.r, expect, 0.01 * expect) << int(gi);
  }
}

// Ground truth (height-field plane, displaced cylinder through Embree, sphere light by area sampling): the
// image is bit-identical with 1 and 2 threads.
TEST(RenderGroundTruth, SameImageWhateverTheThreadCount) {
  const char* json = R"({
    "camera": {"eye": [0, -5, 2.5], "target": [0, 0, 0.5], "up": [0, 0, 1], "fov_deg": 40},
    "materials": {"m": {"base_color": [0.7, 0.5, 0.3], "roughness": 0.4, "height_texels": 3}},
    "objects": [{"type": "plane", "material": "m", "size": [4, 4]},
                {"type": "cylinder", "material": "m", "center": [0, 0, 0.8], "radius": 0.5, "height": 1.5708}],
    "lights": [{"type": "sphere", "position": [2, -2, 3], "radius": 0.5, "intensity": 10},
               {"type": "directional", "elevation_deg": 25, "intensity": 1}],
    "settings": {"width": 32, "height": 24, "spp": 4, "area_lights": true, "area_samples": 4,
                 "micro_shadowing": "ground-truth"}})";
  Scene s = parse_scene(json, "inline.json", ".");
  // Square texels on each surface: the plane 64 × 64, the cylinder 128 × 64 (2π·0.5/128 = 1.5708/64).
  Texture hp(64, 64, 1), hc(128, 64, 1);
  for (int j = 0; j < 64; ++j) {
    for (int i = 0; i < 64; ++i)
      hp.at(i, j, 0) = 0.5f + 0.5f * std::sin(0.4f * float(i)) * std::cos(0.3f * float(j));
    for (int i = 0; i < 128; ++i) hc.at(i, j, 0) = 0.5f + 0.5f * std::sin(0.5f * float(i + j));
  }
  s.materials.push_back(s.materials[0]);
  s.materials[0].height = hp;
  s.materials[1].height = hc;
  s.objects[1].material = 1;
  Image one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = Renderer(s).render();
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = Renderer(s).render();
  }
  double sum = 0;
  for (std::size_t i = 0; i < one.px.size(); ++i) {
    ASSERT_TRUE(one.px[i] == two.px[i]) << i;
    sum += one.px[i].r;
  }
  EXPECT_GT(sum, 1.0);
}

// render_to_error doubles spp until the RMS standard error is at most the target: the result meets it, the
// previous spp would not have (its render, repeated through render_with_error, is above it), and the returned
// image is the render_with_error image at that spp bit for bit.
TEST(RenderError, RenderToErrorStopsAtTheTarget) {
  Scene s = noisy_sphere_light_scene(8, 8);
  const double target = 2e-3;
  const RenderResult res = Renderer(s).render_to_error(target, 4096);
  EXPECT_LE(rms_std_error(res.std_error), target);
  ASSERT_GT(res.spp, 8);
  EXPECT_EQ(res.batches, 8);
  Scene half = s;
  half.settings.spp = res.spp / 2;
  EXPECT_GT(rms_std_error(Renderer(half).render_with_error().std_error), target);
  Scene same = s;
  same.settings.spp = res.spp;
  const RenderResult direct = Renderer(same).render_with_error();
  for (std::size_t i = 0; i < res.mean.px.size(); ++i) {
    ASSERT_TRUE(res.mean.px[i] == direct.mean.px[i]) << i;
    ASSERT_TRUE(res.std_error.px[i] == direct.std_error.px[i]) << i;
  }
  EXPECT_THROW(Renderer(s).render_to_error(0.0, 4096), InputError);
  EXPECT_THROW(Renderer(s).render_to_error(1e-3, 4), InputError);
  s.settings.error_batches = 1;
  EXPECT_THROW(Renderer(s).render_to_error(1e-3, 4096), InputError);
}

// height_texels travels with the texture set: taken from material.json beside the height map when the scene
// omits it, accepted when equal, refused (naming material.json) when different.
TEST(SceneJson, HeightTexelsFromMaterialJson) {
  const auto dir = std::filesystem::temp_directory_path() / "msh_test_render_depth";
  std::filesystem::create_directories(dir);
  TextureSet set;
  set.height = Texture(8, 8, 1);
  set.normal = normal_map_from_height(set.height, 3.5f);
  set.roughness = set.metallic = set.visibility = set.height;
  set.base_color = Texture::constant({0.5f, 0.5f, 0.5f, 1}, 3);
  set.depth_texels = 3.5f;
  write_texture_set(dir, set);
  auto scene = [](const std::string& depth) {
    return R"({"materials": {"m": {"height": "height.png")" + depth +
           R"(}}, "objects": [{"type": "plane", "material": "m"}], "lights": []})";
  };
  EXPECT_EQ(parse_scene(scene(""), "s.json", dir).materials[0].height_texels, 3.5f);
  EXPECT_EQ(parse_scene(scene(R"(, "height_texels": 3.5)"), "s.json", dir).materials[0].height_texels, 3.5f);
  try {
    parse_scene(scene(R"(, "height_texels": 4)"), "s.json", dir);
    ADD_FAILURE() << "accepted a depth that contradicts material.json";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("material.json"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// A scene material takes the directional channels from the gen-material folder's material.json (beside the
// height map) or from its own "directional" key; a file without 9 channels is refused naming the key.
TEST(RenderMethods, SceneReadsDirectionalChannels) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "msh_test_scene_directional";
  std::filesystem::remove_all(dir);
  GenOptions o;
  o.size = 16;
  o.ao_rays = 4;
  o.directional_azimuths = 8;
  write_texture_set(dir, generate_texture_set(o));
  const auto scene = [&](const std::string& extra) {
    return R"({"materials": {"m": {"height": ")" + (dir / "height.png").string() + "\"" + extra +
           R"(}}, "objects": [{"type": "plane", "material": "m"}], "lights": [],
              "settings": {"micro_shadowing": "directional"}})";
  };
  const Scene s = parse_scene(scene(""), "inline.json", ".");
  EXPECT_EQ(s.materials[0].directional.channels(), 9);
  EXPECT_EQ(s.materials[0].directional.width(), 16);
  EXPECT_NO_THROW(Renderer{s});
  try {
    parse_scene(scene(R"(, "directional": ")" + (dir / "height.png").string() + "\""), "inline.json", ".");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("materials.m.directional"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}
