// Area lights in the renderer (docs/renderer.md): disk and rect lights against closed forms of the irradiance
// of a Lambertian plane (π L sin²ρ for a disk facing the point; Lambert's polygon formula for a tilted rect
// or a tilted disk taken as a 720-gon), one-sided emission, the micro-shadowing modes under an area light
// (settings.area_ms) against closed forms, and the scene JSON's errors for the new keys. Every Monte Carlo
// comparison allows 4 standard errors of the rendered pixel (render_with_error) plus the reference's own
// rounding.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <microshadow/io/error.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/scene.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace msh;
using namespace msh::render;

namespace {

// Lambert plane (albedo 0.5, specular 0) seen straight down by a tiny orthographic camera: the one pixel's
// samples all land within 1e-4 of the origin.
std::string scene_json(const std::string& light, const std::string& settings = "",
                       const std::string& material_extra = "") {
  return R"({
    "camera": {"eye": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "projection": "orthographic",
               "ortho_height": 1e-4},
    "materials": {"m": {"base_color": 0.5, "specular": 0)" +
         material_extra + R"(}},
    "objects": [{"type": "plane", "material": "m", "size": [40, 40]}],
    "lights": [)" +
         light + R"(],
    "settings": {"width": 1, "height": 1, "spp": 64, "error_batches": 8, "area_samples": 64)" +
         settings + "}}";
}

struct Pixel {
  double value, se;
};
Pixel render_one(const Scene& s) {
  const RenderResult r = Renderer(s).render_with_error();
  return {r.mean.px[0].r, r.std_error.px[0].r};
}

// Irradiance at the origin (normal +z) from a Lambertian polygon of radiance L (vertices in order), by
// Lambert's formula E = L/2 Σ Θ_i (n · γ_i), γ_i the unit normal of the plane through the origin and the edge
// (Arvo 1995, "Applications of Irradiance Tensors ..."). The polygon must lie above the horizon.
double polygon_irradiance(const std::vector<Vec3d>& v, double L) {
  double e = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Vec3d a = normalize(v[i]), b = normalize(v[(i + 1) % v.size()]);
    const double theta = std::acos(std::clamp(dot(a, b), -1.0, 1.0));
    e += theta * normalize(cross(a, b)).z;
  }
  return std::abs(0.5 * L * e);
}

Vec3d rotate_x(const Vec3d& v, double a) {
  return {v.x, std::cos(a) * v.y - std::sin(a) * v.z, std::sin(a) * v.y + std::cos(a) * v.z};
}

}  // namespace

// A disk of radius R at height h facing the point: E = π L sin²ρ, sin²ρ = R² / (R² + h²), L = I / (π R²).
TEST(RenderAreaLights, DiskFacingThePointMatchesClosedForm) {
  for (const double R : {0.3, 1.0, 4.0}) {
    const double h = 1.5, I = 7;
    const Scene s = parse_scene(scene_json(fmt::format(R"({{"type": "disk", "position": [0, 0, {}],
        "normal": [0, 0, -1], "radius": {}, "intensity": {}}})",
                                                       h, R, I)),
                                "inline.json", ".");
    const Pixel p = render_one(s);
    const double L = I / (kPi<double> * R * R), E = kPi<double> * L * R * R / (R * R + h * h);
    const double expect = 0.5 / kPi<double> * E;
    EXPECT_GT(p.se, 0.0);
    EXPECT_NEAR(p.value, expect, 4 * p.se + 1e-5 * expect) << "R = " << R << ", se " << p.se;
  }
}

// A rect tilted by 35° about x and shifted off the normal, and a disk tilted the same way: Lambert's polygon
// formula (the disk as a 720-gon, whose irradiance differs from the disk's by O(720⁻²)).
TEST(RenderAreaLights, TiltedRectAndDiskMatchPolygonFormula) {
  const double tilt = 35 * kPi<double> / 180, I = 5;
  const Vec3d c(0.4, -0.3, 1.2);
  // The emitter's normal: −z tilted by 35° about x; tangent +x.
  const Vec3d n = rotate_x(Vec3d(0, 0, -1), tilt), t(1, 0, 0), b = cross(n, t);
  const std::string nrm = fmt::format("[{:.17g}, {:.17g}, {:.17g}]", n.x, n.y, n.z);
  const std::string pos = fmt::format("[{}, {}, {}]", c.x, c.y, c.z);
  {
    const double w = 1.4, hh = 0.6;
    const Scene s = parse_scene(
        scene_json(fmt::format(R"({{"type": "rect", "position": {}, "normal": {}, "tangent": [1, 0, 0],
            "size": [{}, {}], "intensity": {}}})",
                               pos, nrm, w, hh, I)),
        "inline.json", ".");
    const Pixel p = render_one(s);
    const double L = I / (w * hh);
    const std::vector<Vec3d> v = {c + t * (-w / 2) + b * (-hh / 2), c + t * (w / 2) + b * (-hh / 2),
                                  c + t * (w / 2) + b * (hh / 2), c + t * (-w / 2) + b * (hh / 2)};
    const double expect = 0.5 / kPi<double> * polygon_irradiance(v, L);
    EXPECT_NEAR(p.value, expect, 4 * p.se + 1e-5 * expect) << "rect, se " << p.se;
  }
  {
    const double R = 0.7;
    const Scene s = parse_scene(scene_json(fmt::format(R"({{"type": "disk", "position": {}, "normal": {},
            "radius": {}, "intensity": {}}})",
                                                       pos, nrm, R, I)),
                                "inline.json", ".");
    const Pixel p = render_one(s);
    const double L = I / (kPi<double> * R * R);
    std::vector<Vec3d> v;
    for (int i = 0; i < 720; ++i) {
      const double a = 2 * kPi<double> * i / 720;
      v.push_back(c + t * (R * std::cos(a)) + b * (R * std::sin(a)));
    }
    const double expect = 0.5 / kPi<double> * polygon_irradiance(v, L);
    EXPECT_NEAR(p.value, expect, 4 * p.se + 2e-5 * expect) << "disk, se " << p.se;
  }
}

// Disk and rect emit from the front face only: turned away from the plane they light nothing.
TEST(RenderAreaLights, OneSidedEmission) {
  for (const char* l :
       {R"({"type": "disk", "position": [0, 0, 1], "normal": [0, 0, 1], "radius": 0.5})",
        R"({"type": "rect", "position": [0, 0, 1], "normal": [0, 0.2, 1], "size": [1, 2]})"}) {
    const Scene s = parse_scene(scene_json(l), "inline.json", ".");
    EXPECT_EQ(render_one(s).value, 0.0) << l;
  }
}

// The three micro-shadowing modes under a disk of radius R at height h above the point, with the reference
// step of visibility V (lit where N·L > cos θ_V = sqrt(1 − V)): the directions with N·L > cos θ_V are those
// to the disk's points within s* = h tan θ_V of its centre, so
//   sampled        = the irradiance of the disk of radius min(R, s*): π L s*² / (s*² + h²);
//   representative = step at the centre (N·L = 1 > cos θ_V): the whole disk's irradiance;
// and with AO (a constant term V) every mode gives V times the irradiance.
TEST(RenderAreaLights, MicroShadowingModesUnderADiskMatchClosedForms) {
  const double R = 2.0, h = 1.0, I = 6, V = 0.3;
  const double L = I / (kPi<double> * R * R);
  const double sstar = h * std::tan(std::acos(std::sqrt(1 - V)));
  ASSERT_LT(sstar, R);
  auto irr = [&](double r) { return kPi<double> * L * r * r / (r * r + h * h); };
  const std::string light =
      fmt::format(R"({{"type": "disk", "position": [0, 0, {}], "radius": {}, "intensity": {}}})", h, R, I);
  const std::string mat = fmt::format(R"(, "micro_occlusion": {})", V);
  auto run = [&](const char* method, const char* mode) {
    const std::string set = fmt::format(R"(, "micro_shadowing": "{}", "area_ms": "{}")", method, mode);
    return render_one(parse_scene(scene_json(light, set, mat), "inline.json", "."));
  };
  const double k = 0.5 / kPi<double>;
  const Pixel samp = run("reference", "sampled"), rep = run("reference", "representative");
  EXPECT_NEAR(samp.value, k * irr(sstar), 4 * samp.se + 1e-5 * k * irr(sstar)) << samp.se;
  EXPECT_NEAR(rep.value, k * irr(R), 4 * rep.se + 1e-5 * k * irr(R)) << rep.se;
  const Pixel ao_s = run("ao", "sampled"), ao_r = run("ao", "representative");
  EXPECT_NEAR(ao_s.value, k * V * irr(R), 4 * ao_s.se + 1e-5 * k * irr(R));
  // Same light samples, the constant term applied per sample or once: equal to float rounding.
  EXPECT_NEAR(ao_r.value, ao_s.value, 1e-5 * ao_s.value);
  // integrated = M_area (Lambert) × the sampled irradiance, M_area = irr(s*) / irr(R) exactly.
  const Pixel integ = run("reference", "integrated"), ao_i = run("ao", "integrated");
  EXPECT_NEAR(integ.value, k * irr(sstar), 4 * rep.se * irr(sstar) / irr(R) + 1e-5 * k * irr(sstar));
  EXPECT_NEAR(ao_i.value, ao_s.value, 1e-5 * ao_s.value);
}

// The specular lobe under a tilted rect (GGX, α = 0.25, F0 = 1 so that Fresnel is exactly 1, as in M_area's
// weight): per-sample and integrated micro-shadowing estimate the same ∫ M f cos L dl (no macro shadows), for
// the reference step and the 3D LUT; the representative point differs from both by more than the noise
// (the step's cone edge crosses the light).
TEST(RenderAreaLights, IntegratedEqualsSampledForTheSpecularLobe) {
  const std::string light =
      R"({"type": "rect", "position": [0.9, 0, 0.9], "normal": [-0.7071068, 0, -0.7071068],
          "tangent": [0, 1, 0], "size": [1.2, 0.8], "intensity": 4})";
  const std::string mat = R"(, "roughness": 0.5, "metallic": 1, "base_color": 1, "micro_occlusion": 0.55)";
  for (const char* method : {"reference", "lut3d"}) {
    auto run = [&](const char* mode) {
      std::string json = scene_json(light,
                                    fmt::format(R"(, "micro_shadowing": "{}", "area_ms": "{}",
                                          "component": "specular", "spp": 128)",
                                                method, mode),
                                    mat);
      // View from the mirror side of the rect at 45° (the highlight's neighbourhood).
      json.replace(json.find("[0, 0, 3]"), 9, "[-3, 0, 3]");
      return render_one(parse_scene(json, "inline.json", "."));
    };
    const Pixel s = run("sampled"), i = run("integrated"), r = run("representative");
    ASSERT_GT(s.value, 0.0);
    EXPECT_NEAR(i.value, s.value, 4 * std::hypot(s.se, i.se) + 1e-4 * s.value)
        << method << " se " << s.se << " " << i.se;
    if (std::string(method) == "reference")
      EXPECT_GT(std::abs(r.value - s.value), 6 * std::hypot(s.se, r.se)) << r.value << " " << s.value;
  }
}

TEST(RenderAreaLights, SceneJsonErrors) {
  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"type": "disk", "position": [0, 0, 1]})", "radius"},
      {R"({"type": "rect", "position": [0, 0, 1]})", "size"},
      {R"({"type": "rect", "position": [0, 0, 1], "size": [1]})", "size"},
      {R"({"type": "rect", "position": [0, 0, 1], "size": [1, 1], "radius": 1})", "radius"},
      {R"({"type": "disk", "position": [0, 0, 1], "radius": 1, "size": [1, 1]})", "size"},
      {R"({"type": "sphere", "position": [0, 0, 1], "radius": 1, "normal": [0, 0, 1]})", "normal"},
      {R"({"type": "disk", "position": [0, 0, 1], "radius": 1, "normal": [0, 0, 0]})", "normal"},
      {R"({"type": "rect", "position": [0, 0, 1], "size": [1, 1], "tangent": [0, 0, 2]})", "tangent"},
      {R"({"type": "disk", "radius": 1})", "position"}};
  for (const auto& [light, key] : bad) {
    try {
      parse_scene(scene_json(light), "inline.json", ".");
      ADD_FAILURE() << "accepted " << light;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("lights[0]"), std::string::npos) << e.what();
    }
  }
  try {
    parse_scene(scene_json(R"({"type": "point", "position": [0, 0, 1]})", R"(, "area_ms": "centre")"),
                "inline.json", ".");
    ADD_FAILURE() << "accepted area_ms centre";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("settings.area_ms"), std::string::npos) << e.what();
  }
  // The default tangent of a disk facing ±x (parallel to the default +x) is replaced, not an error.
  const Scene s = parse_scene(
      scene_json(R"({"type": "disk", "position": [1, 0, 1], "normal": [-1, 0, 0], "radius": 0.5})"),
      "inline.json", ".");
  EXPECT_NEAR(std::abs(dot(s.lights[0].tangent, s.lights[0].normal)), 0.0f, 1e-6f);
}
