// Scene JSON parser: strict (unknown keys are errors), every message names the file and the key.
#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/io/names.h>
#include <microshadow/io/texture.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/scene.h>
#include <microshadow/render/texture_gen.h>

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace msh::render {

namespace {
using json = nlohmann::json;

// Names the renderer had before the registry became the one list of terms.
const std::vector<std::pair<const char*, const char*>> kRenamedMethods = {
    {"part1", "part1-analytic"},
    {"aware", "diffuse-aware+specular-aware"},
    {"aware-flux", "diffuse-aware-flux+specular-aware"},
    {"aware-alu", "diffuse-aware-alu+specular-aware"}};
constexpr Named<Component> kComponentNames[] = {
    {Component::Total, "total"}, {Component::Diffuse, "diffuse"}, {Component::Specular, "specular"}};

constexpr Named<AreaMs> kAreaMsNames[] = {{AreaMs::Sampled, "sampled"},
                                          {AreaMs::Representative, "representative"},
                                          {AreaMs::Integrated, "integrated"}};

struct Ctx {
  std::string file;
  std::filesystem::path assets;
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(fmt::format("{}: {}: {}", file, where, what));
  }
  void keys(const json& j, const std::string& where, std::initializer_list<const char*> allowed) const {
    if (!j.is_object()) fail(where, "expected a JSON object");
    std::set<std::string> ok(allowed.begin(), allowed.end());
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!ok.count(it.key())) {
        std::string list;
        for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
        fail(where, fmt::format("unknown key '{}' (known: {})", it.key(), list));
      }
  }
  float num(const json& j, const std::string& where, double lo, double hi) const {
    if (!j.is_number()) fail(where, "expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi)
      fail(where, fmt::format("must be in [{}, {}], got {}", lo, hi, v));
    return float(v);
  }
  int integer(const json& j, const std::string& where, int lo, int hi) const {
    if (!j.is_number_integer()) fail(where, "expected an integer");
    const long long v = j.get<long long>();
    if (v < lo || v > hi) fail(where, fmt::format("must be in [{}, {}], got {}", lo, hi, v));
    return int(v);
  }
  bool boolean(const json& j, const std::string& where) const {
    if (!j.is_boolean()) fail(where, "expected true or false");
    return j.get<bool>();
  }
  std::string str(const json& j, const std::string& where) const {
    if (!j.is_string()) fail(where, "expected a string");
    return j.get<std::string>();
  }
  Vec3f vec3(const json& j, const std::string& where, double lim = 1e6) const {
    if (!j.is_array() || j.size() != 3) fail(where, "expected an array of 3 numbers");
    return {num(j[0], where, -lim, lim), num(j[1], where, -lim, lim), num(j[2], where, -lim, lim)};
  }
  Vec3f unit(const json& j, const std::string& where) const {
    const Vec3f v = vec3(j, where);
    if (!(length(v) > 1e-6f)) fail(where, "must be a non-zero vector");
    return normalize(v);
  }
  Rgbf rgb(const json& j, const std::string& where, double hi) const {
    if (j.is_number()) return Rgbf(num(j, where, 0, hi));
    const Vec3f v = vec3(j, where);
    for (int k = 0; k < 3; ++k)
      if (v[k] < 0 || v[k] > hi) fail(where, fmt::format("components must be in [0, {}]", hi));
    return {v.x, v.y, v.z};
  }
  std::filesystem::path path(const json& j, const std::string& where) const {
    const std::filesystem::path p = str(j, where);
    return p.is_absolute() ? p : assets / p;
  }
};

// A texture slot: a file name, or a constant (number or [r,g,b]).
Texture texture_slot(const Ctx& c, const json& j, const std::string& where, int channels, bool srgb) {
  if (j.is_string()) {
    try {
      return load_texture(c.path(j, where), srgb);
    } catch (const InputError& e) {
      c.fail(where, e.what());
    }
  }
  if (channels == 1) return Texture::constant({c.num(j, where, 0, 1), 0, 0, 0}, 1);
  const Rgbf v = c.rgb(j, where, 1);
  return Texture::constant({v.r, v.g, v.b, 1}, 3);
}

// Directional micro-occlusion channels (occlusion/directional.h): a float32 NPY of shape (1, h, w, 9) as
// gen-material writes it (directional.npy); every value finite.
Texture directional_slot(const std::filesystem::path& path, const Ctx& c, const std::string& where) {
  try {
    return load_directional_channels(path);
  } catch (const InputError& e) {
    c.fail(where, e.what());
  }
}

Material parse_material(const Ctx& c, const std::string& name, const json& j) {
  const std::string w = "materials." + name;
  c.keys(j, w,
         {"base_color", "normal", "roughness", "metallic", "micro_occlusion", "height", "height_texels",
          "uv_scale", "normal_strength", "specular", "directional"});
  Material m;
  m.name = name;
  m.base_color = j.contains("base_color") ? texture_slot(c, j["base_color"], w + ".base_color", 3, true)
                                          : Texture::constant({0.8f, 0.8f, 0.8f, 1}, 3);
  if (j.contains("normal")) m.normal = texture_slot(c, j["normal"], w + ".normal", 3, false);
  m.roughness = j.contains("roughness") ? texture_slot(c, j["roughness"], w + ".roughness", 1, false)
                                        : Texture::constant({0.5f, 0, 0, 0}, 1);
  m.metallic = j.contains("metallic") ? texture_slot(c, j["metallic"], w + ".metallic", 1, false)
                                      : Texture::constant({0, 0, 0, 0}, 1);
  m.visibility = j.contains("micro_occlusion")
                     ? texture_slot(c, j["micro_occlusion"], w + ".micro_occlusion", 1, false)
                     : Texture::constant({1, 0, 0, 0}, 1);
  if (j.contains("height")) m.height = texture_slot(c, j["height"], w + ".height", 1, false);
  if (j.contains("height_texels")) m.height_texels = c.num(j["height_texels"], w + ".height_texels", 0, 1e4);
  if (j.contains("directional"))
    m.directional = directional_slot(c.path(j["directional"], w + ".directional"), c, w + ".directional");
  // The depth a texture set was generated and baked with travels in material.json beside its height map:
  // taken from there when the scene omits it, and a scene value that disagrees is an error.
  if (j.contains("height") && j["height"].is_string()) {
    const auto mj = c.path(j["height"], w + ".height").parent_path() / "material.json";
    require_regular_file(mj, "material.json ");
    std::ifstream in(mj);
    if (in) {
      json set;
      try {
        set = json::parse(in);
      } catch (const json::exception& e) {  // parse_error, and out_of_range for a number overflow
        c.fail(w + ".height", fmt::format("{}: malformed JSON: {}", mj.string(), e.what()));
      }
      // The directional channels the texture set was baked with, unless the scene names its own.
      if (set.is_object() && set.contains("directional") && set["directional"].is_string() &&
          !j.contains("directional"))
        m.directional = directional_slot(mj.parent_path() / set["directional"].get<std::string>(), c,
                                         mj.string() + ": directional");
      if (set.is_object() && set.contains("height_texels")) {
        if (!set["height_texels"].is_number())
          c.fail(w + ".height", fmt::format("{}: height_texels is not a number", mj.string()));
        const double d = set["height_texels"].get<double>();
        if (!j.contains("height_texels")) {
          m.height_texels = c.num(set["height_texels"], mj.string() + ": height_texels", 0, 1e4);
        } else if (std::abs(d - m.height_texels) > 1e-4 * std::max(1.0, d)) {
          c.fail(
              w + ".height_texels",
              fmt::format("{} disagrees with {} (height_texels {}, the depth the texture set was baked with)",
                          m.height_texels, mj.string(), d));
        }
      }
    }
  }
  if (j.contains("uv_scale")) m.uv_scale = c.num(j["uv_scale"], w + ".uv_scale", 1e-3, 1e4);
  if (j.contains("specular")) m.specular = c.num(j["specular"], w + ".specular", 0, 25);
  if (j.contains("normal_strength"))
    m.normal_strength = c.num(j["normal_strength"], w + ".normal_strength", 0, 100);
  return m;
}

Object parse_object(const Ctx& c, const json& j, const std::string& w,
                    const std::map<std::string, int>& mats) {
  c.keys(j, w,
         {"type", "material", "center", "normal", "tangent", "size", "radius", "height", "segments", "rings",
          "file", "scale", "rotate_z_deg"});
  if (!j.contains("type")) c.fail(w, "missing 'type' (plane, sphere, uv-sphere, cylinder, obj)");
  if (!j.contains("material")) c.fail(w, "missing 'material'");
  Object o;
  const std::string mat = c.str(j["material"], w + ".material");
  if (!mats.count(mat)) c.fail(w + ".material", fmt::format("unknown material '{}'", mat));
  o.material = mats.at(mat);
  const std::string type = c.str(j["type"], w + ".type");
  if (j.contains("center")) o.center = c.vec3(j["center"], w + ".center");
  auto allow_only = [&](std::initializer_list<const char*> keys) {
    std::set<std::string> ok(keys.begin(), keys.end());
    ok.insert({"type", "material", "center"});
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!ok.count(it.key())) c.fail(w, fmt::format("key '{}' does not apply to type '{}'", it.key(), type));
  };
  if (type == "plane") {
    allow_only({"normal", "tangent", "size"});
    if (j.contains("normal")) o.normal = c.unit(j["normal"], w + ".normal");
    if (j.contains("tangent")) o.tangent = c.unit(j["tangent"], w + ".tangent");
    o.tangent = normalize(o.tangent - o.normal * dot(o.tangent, o.normal));
    if (!(length(o.tangent) > 0.5f) || std::abs(dot(o.tangent, o.normal)) > 1e-3f)
      c.fail(w + ".tangent", "must not be parallel to the normal");
    if (j.contains("size")) {
      const json& s = j["size"];
      if (!s.is_array() || s.size() != 2) c.fail(w + ".size", "expected [width, height]");
      o.half_size = {0.5f * c.num(s[0], w + ".size", 1e-6, 1e6), 0.5f * c.num(s[1], w + ".size", 1e-6, 1e6)};
    }
    o.type = ShapeType::Plane;
  } else if (type == "sphere") {
    allow_only({"radius"});
    if (j.contains("radius")) o.radius = c.num(j["radius"], w + ".radius", 1e-6, 1e6);
    o.type = ShapeType::Sphere;
  } else if (type == "uv-sphere" || type == "cylinder" || type == "obj") {
    Mesh m;
    float scale = 1.0f, rot = 0.0f;
    if (type == "uv-sphere") {
      allow_only({"radius", "segments", "rings", "rotate_z_deg"});
      const float r = j.contains("radius") ? c.num(j["radius"], w + ".radius", 1e-6, 1e6) : 1.0f;
      const int seg = j.contains("segments") ? c.integer(j["segments"], w + ".segments", 3, 4096) : 12;
      const int rings = j.contains("rings") ? c.integer(j["rings"], w + ".rings", 2, 4096) : 6;
      m = make_uv_sphere(r, seg, rings);
    } else if (type == "cylinder") {
      allow_only({"radius", "height", "segments", "rotate_z_deg"});
      const float r = j.contains("radius") ? c.num(j["radius"], w + ".radius", 1e-6, 1e6) : 1.0f;
      const float h = j.contains("height") ? c.num(j["height"], w + ".height", 1e-6, 1e6) : 2.0f;
      const int seg = j.contains("segments") ? c.integer(j["segments"], w + ".segments", 3, 65536) : 32;
      m = make_cylinder(r, h, seg);
      o.cylinder = true, o.cyl_radius = r, o.cyl_height = h;
    } else {
      allow_only({"file", "scale", "rotate_z_deg"});
      if (!j.contains("file")) c.fail(w, "missing 'file'");
      try {
        m = load_obj(c.path(j["file"], w + ".file"));
      } catch (const InputError& e) {
        c.fail(w + ".file", e.what());
      }
      if (j.contains("scale")) scale = c.num(j["scale"], w + ".scale", 1e-6, 1e6);
    }
    if (j.contains("rotate_z_deg"))
      rot = c.num(j["rotate_z_deg"], w + ".rotate_z_deg", -360, 360) * kPi<float> / 180;
    o.cyl_rotate_z = rot;
    const float cr = std::cos(rot), sr = std::sin(rot);
    auto rz = [&](Vec3f v) { return Vec3f(cr * v.x - sr * v.y, sr * v.x + cr * v.y, v.z); };
    for (std::size_t i = 0; i < m.p.size(); ++i) {
      m.p[i] = rz(m.p[i]) * scale + o.center;
      m.n[i] = rz(m.n[i]);
      const Vec3f t = rz(Vec3f(m.tangent[i][0], m.tangent[i][1], m.tangent[i][2]));
      m.tangent[i] = {t.x, t.y, t.z, m.tangent[i][3]};
    }
    o.type = ShapeType::Mesh;
    o.mesh = std::make_shared<Mesh>(std::move(m));
  } else {
    c.fail(w + ".type",
           fmt::format("unknown object type '{}' (plane, sphere, uv-sphere, cylinder, obj)", type));
  }
  return o;
}

Light parse_light(const Ctx& c, const json& j, const std::string& w) {
  c.keys(j, w,
         {"type", "direction", "elevation_deg", "azimuth_deg", "position", "radius", "color", "intensity",
          "normal", "tangent", "size"});
  if (!j.contains("type")) c.fail(w, "missing 'type' (directional, point, sphere, disk, rect)");
  const std::string type = c.str(j["type"], w + ".type");
  Light l;
  const float scale = j.contains("intensity") ? c.num(j["intensity"], w + ".intensity", 0, 1e9) : 1.0f;
  l.color = (j.contains("color") ? c.rgb(j["color"], w + ".color", 1e9) : Rgbf(1.0f)) * scale;
  const bool planar = type == "disk" || type == "rect";
  if (!planar && (j.contains("normal") || j.contains("tangent") || j.contains("size")))
    c.fail(w, "'normal', 'tangent' and 'size' apply to disk and rect lights only");
  if (type == "directional") {
    l.type = LightType::Directional;
    if (j.contains("position") || j.contains("radius"))
      c.fail(w, "a directional light has no position or radius");
    if (j.contains("direction") && (j.contains("elevation_deg") || j.contains("azimuth_deg")))
      c.fail(w, "give either 'direction' or 'elevation_deg'/'azimuth_deg', not both");
    if (j.contains("direction")) {
      l.direction = c.unit(j["direction"], w + ".direction");
    } else {
      const float el =
          j.contains("elevation_deg") ? c.num(j["elevation_deg"], w + ".elevation_deg", -90, 90) : 45;
      const float az = j.contains("azimuth_deg") ? c.num(j["azimuth_deg"], w + ".azimuth_deg", -360, 360) : 0;
      l.direction = direction_from_angles(el, az);
    }
  } else if (type == "point" || type == "sphere" || planar) {
    if (j.contains("direction") || j.contains("elevation_deg") || j.contains("azimuth_deg"))
      c.fail(w, fmt::format("a {} light has a 'position', not a direction", type));
    if (!j.contains("position")) c.fail(w, "missing 'position'");
    l.position = c.vec3(j["position"], w + ".position");
    if (type == "point") {
      l.type = LightType::Point;
      if (j.contains("radius")) c.fail(w, "a point light has no radius (use type 'sphere')");
    } else if (type == "sphere" || type == "disk") {
      l.type = type == "sphere" ? LightType::Sphere : LightType::Disk;
      if (!j.contains("radius")) c.fail(w, "missing 'radius'");
      l.radius = c.num(j["radius"], w + ".radius", 1e-6, 1e6);
      if (j.contains("size")) c.fail(w, "a disk light has a 'radius', not a size");
    } else {
      l.type = LightType::Rect;
      if (j.contains("radius")) c.fail(w, "a rect light has a 'size', not a radius");
      if (!j.contains("size")) c.fail(w, "missing 'size' ([width, height])");
      const json& s = j["size"];
      if (!s.is_array() || s.size() != 2) c.fail(w + ".size", "expected [width, height]");
      l.half_size = {0.5f * c.num(s[0], w + ".size", 1e-6, 1e6), 0.5f * c.num(s[1], w + ".size", 1e-6, 1e6)};
    }
    if (planar) {
      // Default: facing down (a ceiling light).
      if (j.contains("normal")) l.normal = c.unit(j["normal"], w + ".normal");
      if (j.contains("tangent")) l.tangent = c.unit(j["tangent"], w + ".tangent");
      Vec3f t = l.tangent - l.normal * dot(l.tangent, l.normal);
      if (!(length(t) > 1e-3f)) {
        if (j.contains("tangent")) c.fail(w + ".tangent", "must not be parallel to the normal");
        t = Framef::from_z(l.normal).s;  // the default tangent is parallel to the given normal
      }
      l.tangent = normalize(t);
    }
  } else {
    c.fail(w + ".type",
           fmt::format("unknown light type '{}' (directional, point, sphere, disk, rect)", type));
  }
  return l;
}

// j[key], if present, as a name that from_string turns into `out`; its InputError is reported at `w.key`.
template <class T, class FromString>
void parse_named(const Ctx& c, const json& j, const std::string& w, const char* key, FromString from_string,
                 T& out) {
  if (!j.contains(key)) return;
  const std::string where = w + "." + key;
  try {
    out = from_string(c.str(j[key], where));
  } catch (const InputError& e) {
    c.fail(where, e.what());
  }
}

void parse_settings(const Ctx& c, const json& j, Settings& s) {
  const std::string w = "settings";
  c.keys(j, w,
         {"width", "height", "spp", "micro_shadowing", "vndf_samples", "bump_terminator", "hanika_offset",
          "area_lights", "area_samples", "exposure", "background", "ambient", "lut", "seed",
          "micro_shadowing_normal", "component", "error_batches", "ground_truth_intersector", "area_ms"});
  if (j.contains("width")) s.width = c.integer(j["width"], w + ".width", 1, 16384);
  if (j.contains("height")) s.height = c.integer(j["height"], w + ".height", 1, 16384);
  if (j.contains("spp")) s.spp = c.integer(j["spp"], w + ".spp", 1, 65536);
  parse_named(c, j, w, "micro_shadowing", micro_shadowing_from_string, s.micro_shadowing);
  parse_named(c, j, w, "component", component_from_string, s.component);
  if (j.contains("error_batches"))
    s.error_batches = c.integer(j["error_batches"], w + ".error_batches", 1, 1 << 16);
  if (j.contains("vndf_samples"))
    s.vndf_samples = c.integer(j["vndf_samples"], w + ".vndf_samples", 1, 1 << 20);
  parse_named(c, j, w, "bump_terminator", bump_terminator_from_string, s.bump_terminator);
  if (j.contains("micro_shadowing_normal")) {
    const std::string n = c.str(j["micro_shadowing_normal"], w + ".micro_shadowing_normal");
    if (n != "shading" && n != "smooth")
      c.fail(w + ".micro_shadowing_normal", "expected 'shading' or 'smooth'");
    s.ms_smooth_normal = n == "smooth";
  }
  if (j.contains("ground_truth_intersector")) {
    const std::string n = c.str(j["ground_truth_intersector"], w + ".ground_truth_intersector");
    if (n != "heightfield" && n != "embree")
      c.fail(w + ".ground_truth_intersector", "expected 'heightfield' or 'embree'");
    s.gt_intersector = n == "embree" ? GtIntersector::Embree : GtIntersector::HeightField;
  }
  if (j.contains("hanika_offset")) s.hanika_offset = c.boolean(j["hanika_offset"], w + ".hanika_offset");
  if (j.contains("area_lights")) s.area_lights = c.boolean(j["area_lights"], w + ".area_lights");
  parse_named(c, j, w, "area_ms", area_ms_from_string, s.area_ms);
  if (j.contains("area_samples"))
    s.area_samples = c.integer(j["area_samples"], w + ".area_samples", 1, 1 << 16);
  if (j.contains("exposure")) s.exposure = c.num(j["exposure"], w + ".exposure", -30, 30);
  if (j.contains("background")) s.background = c.rgb(j["background"], w + ".background", 1e6);
  if (j.contains("ambient")) s.ambient = c.rgb(j["ambient"], w + ".ambient", 1e6);
  if (j.contains("lut")) s.lut_path = c.path(j["lut"], w + ".lut").string();
  if (j.contains("seed")) s.seed = uint32_t(c.integer(j["seed"], w + ".seed", 0, 2147483647));
}

}  // namespace

std::vector<std::string> micro_shadowing_names() {
  std::vector<std::string> r;
  for (const auto& i : occlusion::micro_shadowing_methods()) r.push_back(i.name);
  r.push_back(kGroundTruth);
  return r;
}
std::string micro_shadowing_from_string(const std::string& s) {
  if (s == kGroundTruth || occlusion::find_micro_shadowing_method(s)) return s;
  for (const auto& [old, now] : kRenamedMethods)
    if (s == old) throw InputError(fmt::format("micro-shadowing method '{}' is now called '{}'", s, now));
  throw InputError(fmt::format("unknown micro-shadowing method '{}' (known: {}, {})", s,
                               occlusion::micro_shadowing_method_names(), kGroundTruth));
}
const char* to_string(Component c) { return name_of<Component>(kComponentNames, c); }
Component component_from_string(const std::string& s) {
  return value_of<Component>(kComponentNames, s, "component");
}
const char* to_string(AreaMs a) { return name_of<AreaMs>(kAreaMsNames, a); }
AreaMs area_ms_from_string(const std::string& s) {
  return value_of<AreaMs>(kAreaMsNames, s, "area-light micro-shadowing mode");
}
float light_area(const Light& l) {
  if (l.type == LightType::Disk) return kPi<float> * l.radius * l.radius;
  if (l.type == LightType::Rect) return 4 * l.half_size.x * l.half_size.y;
  return 0.0f;
}
const char* to_string(BumpTerminator b) { return bump::method_name(b).data(); }  // a literal's view
BumpTerminator bump_terminator_from_string(const std::string& s) {
  BumpTerminator m;
  if (bump::parse_method(s, m)) return m;
  if (s == "off")
    throw InputError("bump-terminator method 'off' is now called 'none'");  // the renderer's old name
  throw InputError(fmt::format("unknown bump-terminator method '{}' (known: {})", s, bump::method_names()));
}

Vec3f direction_from_angles(float el, float az) {
  const float e = el * kPi<float> / 180, a = az * kPi<float> / 180;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

Scene parse_scene(const std::string& text, const std::filesystem::path& source,
                  const std::filesystem::path& assets) {
  Ctx c{source.string(), assets};
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, and out_of_range for a number overflow
    throw InputError(fmt::format("{}: malformed JSON: {}", c.file, e.what()));
  }
  c.keys(j, "scene", {"camera", "materials", "objects", "lights", "settings", "description"});
  Scene s;
  s.source = source;
  if (j.contains("camera")) {
    const json& cj = j["camera"];
    c.keys(cj, "camera", {"eye", "target", "up", "fov_deg", "projection", "ortho_height"});
    if (cj.contains("projection")) {
      const std::string pr = c.str(cj["projection"], "camera.projection");
      if (pr != "perspective" && pr != "orthographic")
        c.fail("camera.projection", "expected 'perspective' or 'orthographic'");
      s.camera.orthographic = pr == "orthographic";
    }
    if (cj.contains("ortho_height"))
      s.camera.ortho_height = c.num(cj["ortho_height"], "camera.ortho_height", 1e-6, 1e6);
    if (cj.contains("eye")) s.camera.eye = c.vec3(cj["eye"], "camera.eye");
    if (cj.contains("target")) s.camera.target = c.vec3(cj["target"], "camera.target");
    if (cj.contains("up")) s.camera.up = c.unit(cj["up"], "camera.up");
    if (cj.contains("fov_deg")) s.camera.fov_deg = c.num(cj["fov_deg"], "camera.fov_deg", 0.01, 179);
    const Vec3f f = s.camera.target - s.camera.eye;
    if (!(length(f) > 1e-6f)) c.fail("camera", "eye and target coincide");
    if (length(cross(normalize(f), s.camera.up)) < 1e-4f)
      c.fail("camera.up", "parallel to the view direction");
  }
  std::map<std::string, int> mats;
  if (!j.contains("materials") || !j["materials"].is_object() || j["materials"].empty())
    c.fail("materials", "expected a non-empty object of named materials");
  for (auto it = j["materials"].begin(); it != j["materials"].end(); ++it) {
    mats[it.key()] = int(s.materials.size());
    s.materials.push_back(parse_material(c, it.key(), it.value()));
  }
  if (!j.contains("objects") || !j["objects"].is_array() || j["objects"].empty())
    c.fail("objects", "expected a non-empty array");
  for (std::size_t i = 0; i < j["objects"].size(); ++i)
    s.objects.push_back(parse_object(c, j["objects"][i], fmt::format("objects[{}]", i), mats));
  if (!j.contains("lights") || !j["lights"].is_array()) c.fail("lights", "expected an array");
  for (std::size_t i = 0; i < j["lights"].size(); ++i)
    s.lights.push_back(parse_light(c, j["lights"][i], fmt::format("lights[{}]", i)));
  if (j.contains("settings")) parse_settings(c, j["settings"], s.settings);
  if (j.contains("description")) c.str(j["description"], "description");
  return s;
}

Scene load_scene(const std::filesystem::path& path, const std::filesystem::path& asset_dir) {
  require_regular_file(path, "scene file ");
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open scene file", path.string()));
  std::stringstream ss;
  ss << in.rdbuf();
  const auto assets = asset_dir.empty() ? path.parent_path() : asset_dir;
  return parse_scene(ss.str(), path, assets.empty() ? std::filesystem::path(".") : assets);
}

}  // namespace msh::render
