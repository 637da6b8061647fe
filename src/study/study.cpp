// The multiscale study (see study/study.h and docs/study.md).
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/image.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/texture_gen.h>
#include <microshadow/study/metrics.h>
#include <microshadow/study/study.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>

namespace msh::study {

using namespace msh::render;
using json = nlohmann::json;

StudyConfig full_config() { return StudyConfig{}; }

StudyConfig quick_config() {
  StudyConfig c;
  c.name = "quick";
  c.materials = {"plaster"};
  c.shapes = {"plane", "cylinder"};
  c.fine_size = 1024;
  c.elevations = {10, 25, 45};
  c.azimuths = {0};
  c.point_light = false;
  c.image_size = 64;
  c.gt_spp = 32;
  c.gt_max_spp = 256;
  c.featured_lights = {"dir-el10-az0"};
  return c;
}

StudyConfig area_config(bool quick) {
  StudyConfig c;
  c.name = quick ? "area-quick" : "area";
  c.materials = {"plaster"};
  c.shapes = {"plane"};
  c.fine_size = quick ? 1024 : 2048;
  c.scales = quick ? std::vector<int>{4} : std::vector<int>{4, 16};
  c.elevations = {};
  c.point_light = c.sphere_light = false;
  c.area_radii_deg = {1, 5, 10, 20, 40};
  c.area_elevations = {25, 50};
  c.area_planar_radii_deg = {10, 20};
  c.widened = c.normal_ablation = false;
  c.featured_lights = {};
  c.image_size = quick ? 32 : 64;
  if (quick) c.gt_spp = 32, c.gt_max_spp = 256;
  return c;
}

namespace {

constexpr float kTileWorld = 2.0f;  // world size of one texture tile
constexpr int kTiles = 3;           // the plane spans kTiles × kTiles tiles: the view never reaches its edge

double secs_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
// Process CPU time (all threads), to report cost on a loaded machine.
double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// Texture sets cached as float32 NPY (exact), keyed by the generation options. More than 4 channels (the
// directional channels): one slice of depth per channel.
io::Volume to_volume(const Texture& t) {
  const bool slices = t.channels() > 4;
  const int c = slices ? 1 : t.channels() == 3 ? 4 : t.channels();
  io::Volume v(t.width(), t.height(), slices ? t.channels() : 1, c);
  for (int y = 0; y < t.height(); ++y)
    for (int x = 0; x < t.width(); ++x)
      for (int k = 0; k < t.channels(); ++k) (slices ? v.at(x, y, k, 0) : v.at(x, y, 0, k)) = t.at(x, y, k);
  return v;
}
Texture from_volume(const io::Volume& v, int channels) {
  const bool slices = channels > 4;
  if (slices ? v.depth != channels : v.channels < channels)
    throw InputError("study: a cached map has the wrong number of channels (delete the material cache)");
  Texture t(v.width, v.height, channels);
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x)
      for (int k = 0; k < channels; ++k) t.at(x, y, k) = slices ? v.at(x, y, k, 0) : v.at(x, y, 0, k);
  return t;
}
io::PixelFormat npy_format(int channels) {
  return channels == 1   ? io::PixelFormat::R32Float
         : channels == 2 ? io::PixelFormat::RG32Float
                         : io::PixelFormat::RGBA32Float;
}

// FNV-1a of a height map's texels: a user map's cache key (its file may change under the same name).
uint64_t height_hash(const Texture& t) {
  uint64_t h = 1469598103934665603ull;
  for (int j = 0; j < t.height(); ++j)
    for (int i = 0; i < t.width(); ++i) {
      uint32_t b;
      const float f = t.at(i, j, 0);
      std::memcpy(&b, &f, 4);
      h = (h ^ b) * 1099511628211ull;
    }
  return h;
}

// user_height: a user's map (go.kind = its name), made by texture_set_from_height with the same options.
TextureSet load_or_generate(const GenOptions& go, const std::filesystem::path& cache, const Log& log,
                            const Texture* user_height = nullptr, float user_depth = 0) {
  const std::string key =
      user_height
          ? fmt::format("user-{}_{}_z{:.9g}_h{:016x}_a{}_d{}", go.kind, user_height->width(), user_depth,
                        height_hash(*user_height), go.ao_rays, go.directional_azimuths)
          : fmt::format("{}_{}_a{}_d{}_s{}", go.kind, go.size, go.ao_rays, go.directional_azimuths, go.seed);
  const auto dir = cache.empty() ? cache : cache / key;
  struct Slot {
    const char* name;
    Texture TextureSet::*map;
    int channels;
  };
  const Slot slots[] = {{"height", &TextureSet::height, 1},
                        {"normal", &TextureSet::normal, 3},
                        {"roughness", &TextureSet::roughness, 1},
                        {"metallic", &TextureSet::metallic, 1},
                        {"base_color", &TextureSet::base_color, 3},
                        {"visibility", &TextureSet::visibility, 1},
                        {"directional", &TextureSet::directional, directional::kDirectionalChannels}};
  if (!dir.empty() && std::filesystem::exists(dir / "depth.txt")) {
    TextureSet s;
    for (const Slot& sl : slots)
      if (go.directional_azimuths > 0 || sl.map != &TextureSet::directional)
        s.*sl.map = from_volume(io::read_volume(dir / (std::string(sl.name) + ".npy")), sl.channels);
    std::ifstream in(dir / "depth.txt");
    in >> s.depth_texels;
    if (log) log("study: texture set from the cache " + dir.string());
    return s;
  }
  TextureSet s =
      user_height ? texture_set_from_height(*user_height, user_depth, go) : generate_texture_set(go);
  if (!dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw InputError(fmt::format("{}: cannot create directory: {}", dir.string(), ec.message()));
    for (const Slot& sl : slots) {
      const Texture& t = s.*sl.map;
      if (t.empty()) continue;
      io::write_volume(dir / (std::string(sl.name) + ".npy"), to_volume(t), io::FileFormat::Npy,
                       npy_format(t.channels() > 4    ? 1
                                  : t.channels() == 3 ? 4
                                                      : t.channels()));
    }
    io::write_file_atomic(dir / "depth.txt", fmt::format("{:.9g}\n", s.depth_texels));
  }
  return s;
}

struct LightSpec {
  std::string name, type;
  Light light;
  double elevation = 0, azimuth = 0;  // of the direction to the light at the view's centre
  double radius_deg = 0;              // area-light section: angular radius seen from the view's centre
};
bool area_sampled(const Light& l) {
  return l.type == LightType::Sphere || l.type == LightType::Disk || l.type == LightType::Rect;
}
bool area_section(const StudyConfig& c) {
  return !c.area_radii_deg.empty() || !c.area_planar_radii_deg.empty();
}

std::string num(double x) { return fmt::format("{:g}", x); }

// The shape's frame at the view's centre: P0 on the mean surface, T = ∂P/∂u, B = ∂P/∂v, N the normal. Lights
// and the camera are placed in this frame, so "elevation" is above the tangent plane at the view's centre.
// plane: z = 0, spanning kTiles × kTiles tiles, centred at u = 1.5 tiles (the rough/smooth boundary).
// cylinder: axis +z, circumference and length one tile (texels square), rotated so that u = 0.5 (the
// rough/smooth boundary) faces the camera at -y; B = ∂P/∂v points down the axis.
struct Frame {
  Vec3f P0, T, B, N;
};
constexpr float kCylRadius = kTileWorld / (2 * kPi<float>), kCylRotate = 0.5f * kPi<float>;
Frame frame_of(const std::string& shape) {
  if (shape == "cylinder") return {{0, -kCylRadius, 0}, {1, 0, 0}, {0, 0, -1}, {0, -1, 0}};
  return {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
}
Vec3f local_dir(const Frame& f, double el_deg, double az_deg) {
  const Vec3f d = direction_from_angles(float(el_deg), float(az_deg));
  return f.T * d.x + f.B * d.y + f.N * d.z;
}

std::vector<LightSpec> make_lights(const StudyConfig& c, const Frame& fr) {
  std::vector<LightSpec> out;
  for (double el : c.elevations)
    for (double az : c.azimuths) {
      LightSpec s;
      s.name = "dir-el" + num(el) + "-az" + num(az);
      s.type = "directional";
      s.light.type = LightType::Directional;
      s.light.direction = local_dir(fr, el, az);
      s.light.color = Rgbf(3.0f);
      s.elevation = el, s.azimuth = az;
      out.push_back(s);
    }
  // Point and sphere lights at fixed positions in the frame (about 2.7 tile widths away), irradiance about 3
  // at normal incidence at the centre, like the directional lights.
  auto positional = [&](const char* name, LightType t, Vec3f p, float radius) {
    LightSpec s;
    s.name = name, s.type = name;
    s.light.type = t;
    s.light.position = fr.P0 + fr.T * p.x + fr.B * p.y + fr.N * p.z;
    s.light.radius = radius;
    s.light.color = Rgbf(3.0f * dot(p, p));
    s.elevation = std::asin(p.z / length(p)) * 180 / kPi<double>;
    s.azimuth = std::atan2(p.y, p.x) * 180 / kPi<double>;
    out.push_back(s);
  };
  if (c.point_light) positional("point", LightType::Point, {-2.0f, -1.0f, 1.5f}, 0.0f);
  if (c.sphere_light) positional("sphere", LightType::Sphere, {1.5f, 1.0f, 2.0f}, 0.5f);
  // Area-light section: at the sphere light's distance from the view's centre, intensity 3 d² (irradiance
  // about 3 at normal incidence, as the directional lights). A sphere's cone must stay 5° above the tangent
  // plane (the height field's slab is open below it).
  const float dist = std::sqrt(1.5f * 1.5f + 1.0f * 1.0f + 2.0f * 2.0f);
  auto area = [&](const std::string& type, double rho, double el) {
    LightSpec s;
    s.name = fmt::format("{}-r{}-el{}", type, num(rho), num(el));
    s.type = type;
    s.elevation = el, s.azimuth = c.area_azimuth, s.radius_deg = rho;
    const Vec3f w = local_dir(fr, el, c.area_azimuth);
    const float r = float(rho * kPi<double> / 180);
    s.light.position = fr.P0 + w * dist;
    s.light.color = Rgbf(3.0f * dist * dist);
    if (type == "sphere") {
      s.light.type = LightType::Sphere;
      s.light.radius = dist * std::sin(r);
    } else {
      // Facing the view's centre; a disk of angular radius ρ, a 2:1 rect of angular half-widths ρ and
      // atan(tan ρ / 2), its long side along the view's u.
      s.light.normal = -w;
      s.light.tangent = normalize(fr.T - w * dot(fr.T, w));
      if (type == "disk") {
        s.light.type = LightType::Disk;
        s.light.radius = dist * std::tan(r);
      } else {
        s.light.type = LightType::Rect;
        s.light.half_size = {dist * std::tan(r), 0.5f * dist * std::tan(r)};
      }
    }
    out.push_back(s);
  };
  for (double el : c.area_elevations)
    for (double rho : c.area_radii_deg)
      if (el - rho >= 5) area("sphere", rho, el);
  for (double rho : c.area_planar_radii_deg) {
    area("disk", rho, c.area_planar_elevation);
    area("rect", rho, c.area_planar_elevation);
  }
  return out;
}

struct Variant {
  std::string term;  // a method of the runtime registry
  bool smooth = false;
  CoarseRoughness rough = CoarseRoughness::Base;
  AreaMs area_ms = AreaMs::Sampled;
};
bool uses_nl(const std::string& m) { return occlusion::find_micro_shadowing_method(m)->uses_ndotl; }

std::vector<Variant> make_variants(const StudyConfig& c, int k) {
  std::vector<Variant> v;
  if (area_section(c)) {
    for (const std::string& name : c.area_terms) {
      const std::string& t = name;
      for (const std::string& mode : c.area_ms_modes) {
        const AreaMs a = area_ms_from_string(mode);
        if (!uses_nl(t) && a != AreaMs::Sampled) continue;  // a constant term: every mode is the same
        // The exact generic term inside the area quadrature costs 40–190 ms per shading point: not rendered
        // (lut3d, its tabulation, stands for it).
        if (t == "generic-vndf" && a == AreaMs::Integrated) continue;
        v.push_back({t, false, CoarseRoughness::Base, a});
      }
    }
    return v;
  }
  for (const auto& t : c.terms) v.push_back({t, false, CoarseRoughness::Base});
  if (c.normal_ablation)
    for (const auto& t : c.terms)
      if (uses_nl(t)) v.push_back({t, true, CoarseRoughness::Base});
  if (c.widened && k > 1)
    for (const auto& t : c.terms) v.push_back({t, false, CoarseRoughness::Widened});
  return v;
}

// Orthographic camera at view_elevation above the tangent plane at the view's centre, looking along +v: the
// view is W = image_size · k fine texels wide, so a pixel covers k texels across and k / sin(view elevation)
// along v there (more towards a cylinder's silhouettes).
Camera camera_for(const StudyConfig& c, const Frame& fr, int k) {
  const float W = float(c.image_size) * float(k) * kTileWorld / float(c.fine_size);
  const float D = 4.0f * kTileWorld, el = float(c.view_elevation) * kPi<float> / 180;
  Camera cam;
  cam.eye = fr.P0 + (fr.N * std::sin(el) - fr.B * std::cos(el)) * D;
  cam.target = fr.P0;
  cam.up = fr.N;
  cam.orthographic = true;
  cam.ortho_height = W;
  return cam;
}

struct Regions {
  Mask rough, smooth, whole;
};

// The texture's rough half (u mod 1 < 0.5) and smooth half, from where each pixel centre's ray (the
// renderer's orthographic camera) meets the mean surface; pixels within 1.5 footprints + 2 fine texels of a
// boundary belong to neither half (they stay in the whole); pixels that miss the shape belong to no region.
Regions make_regions(const StudyConfig& c, const std::string& shape, const Camera& cam, int k) {
  const int n = c.image_size;
  Regions r{Mask(n, n, 0), Mask(n, n, 0), Mask(n, n, 0)};
  const double margin = (1.5 * k + 2.0) / double(c.fine_size);
  const Vec3f f = normalize(cam.target - cam.eye), rt = normalize(cross(f, cam.up)), up = cross(rt, f);
  const float th = 0.5f * cam.ortho_height;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const float px = (2 * (float(x) + 0.5f) / float(n) - 1) * th,
                  py = (1 - 2 * (float(y) + 0.5f) / float(n)) * th;
      const Vec3d o(cam.eye + rt * px + up * py), d(f);
      double u;
      if (shape == "cylinder") {
        // Nearest hit of the infinite cylinder x² + y² = R².
        const double a = d.x * d.x + d.y * d.y, b = o.x * d.x + o.y * d.y,
                     cc = o.x * o.x + o.y * o.y - double(kCylRadius) * kCylRadius;
        const double disc = b * b - a * cc;
        if (!(a > 0) || disc < 0) continue;
        const double t = (-b - std::sqrt(disc)) / a;
        const double phi = std::atan2(o.y + t * d.y, o.x + t * d.x) - kCylRotate;
        u = phi / (2 * kPi<double>);
      } else {
        const double t = -o.z / d.z;
        u = (o.x + t * d.x + 0.5 * kTiles * kTileWorld) / kTileWorld;  // in tiles
      }
      const std::size_t i = std::size_t(y) * n + x;
      r.whole.in[i] = 1;
      const double fu = u - std::floor(u);
      const double dist = std::min({fu, std::abs(fu - 0.5), 1.0 - fu});
      if (dist <= margin) continue;
      (fu < 0.5 ? r.rough : r.smooth).in[i] = 1;
    }
  return r;
}

Material make_material(const std::string& name, const TextureSet& s, bool ground_truth) {
  Material m;
  m.name = name;
  m.base_color = s.base_color;
  m.roughness = s.roughness;
  m.metallic = s.metallic;
  if (ground_truth) {
    m.height = s.height;
    m.height_texels = s.depth_texels;
    m.visibility = Texture::constant({1, 0, 0, 0}, 1);
  } else {
    m.normal = s.normal;
    m.visibility = s.visibility;
    m.directional = s.directional;
  }
  return m;
}

Scene make_scene(const StudyConfig& c, Material m, const std::string& shape) {
  Scene s;
  s.camera = camera_for(c, frame_of(shape), 1);
  Object o;
  if (shape == "cylinder") {
    // The smooth cylinder (what the approximations shade; the ground truth displaces it by the height map),
    // built and rotated as the scene loader does.
    Mesh mesh = make_cylinder(kCylRadius, kTileWorld, 2048);
    const float cr = std::cos(kCylRotate), sr = std::sin(kCylRotate);
    auto rz = [&](Vec3f v) { return Vec3f(cr * v.x - sr * v.y, sr * v.x + cr * v.y, v.z); };
    for (std::size_t i = 0; i < mesh.p.size(); ++i) {
      mesh.p[i] = rz(mesh.p[i]), mesh.n[i] = rz(mesh.n[i]);
      const Vec3f t = rz(Vec3f(mesh.tangent[i][0], mesh.tangent[i][1], mesh.tangent[i][2]));
      mesh.tangent[i] = {t.x, t.y, t.z, mesh.tangent[i][3]};
    }
    o.type = ShapeType::Mesh;
    o.mesh = std::make_shared<Mesh>(std::move(mesh));
    o.cylinder = true, o.cyl_radius = kCylRadius, o.cyl_height = kTileWorld, o.cyl_rotate_z = kCylRotate;
    m.uv_scale = 1.0f;
  } else {
    o.type = ShapeType::Plane;
    o.half_size = {0.5f * kTiles * kTileWorld, 0.5f * kTiles * kTileWorld};
    m.uv_scale = float(kTiles);
  }
  s.materials.push_back(std::move(m));
  s.objects.push_back(o);
  s.lights.resize(1);
  Settings& st = s.settings;
  st.width = st.height = c.image_size;
  st.area_lights = true;
  st.area_samples = c.area_samples;
  st.vndf_samples = c.vndf_samples;
  st.lut_path = c.lut_path;
  st.seed = c.seed;
  s.source = "study";
  return s;
}

// Per component (0 total, 1 diffuse, 2 specular): linear image and per-channel standard error.
struct ComponentImages {
  Image img[3], se[3];
};

void add_total(ComponentImages& c) {
  c.img[0] = Image(c.img[1].width, c.img[1].height);
  c.se[0] = Image(c.img[1].width, c.img[1].height);
  for (std::size_t i = 0; i < c.img[1].px.size(); ++i) {
    c.img[0].px[i] = c.img[1].px[i] + c.img[2].px[i];
    // Diffuse and specular share every ray: the errors add at most linearly.
    if (!c.se[1].px.empty()) c.se[0].px[i] = c.se[1].px[i] + c.se[2].px[i];
  }
}

// Merges a second independent estimate (n2 samples per pixel) into the first (n1).
void merge(RenderResult& a, int n1, const RenderResult& b, int n2) {
  const float w1 = float(n1) / float(n1 + n2), w2 = float(n2) / float(n1 + n2);
  for (std::size_t i = 0; i < a.mean.px.size(); ++i) {
    a.mean.px[i] = a.mean.px[i] * w1 + b.mean.px[i] * w2;
    const Rgbf e1 = a.std_error.px[i] * w1, e2 = b.std_error.px[i] * w2;
    a.std_error.px[i] = Rgbf(std::sqrt(e1.r * e1.r + e2.r * e2.r), std::sqrt(e1.g * e1.g + e2.g * e2.g),
                             std::sqrt(e1.b * e1.b + e2.b * e2.b));
  }
  a.stats.camera_rays += b.stats.camera_rays, a.stats.shadow_rays += b.stats.shadow_rays;
  a.stats.seconds += b.stats.seconds;
}

const char* kComponentName[3] = {"total", "diffuse", "specular"};
const char* kRegionName[3] = {"rough", "smooth", "whole"};

struct GtFloors {
  bool met = true;
  json j = json::object();
};

// The stopping rule: for every component whose mean is at least 2% of the total's, the whole-image bias floor
// below delta_bias / 4 and the rmse_footprint floor below delta_rmse / 4 of the mean.
GtFloors check_floors(const StudyConfig& c, const Plane (&G)[3], const Plane (&S)[3], const Regions& r) {
  GtFloors f;
  const double total_mean = region_mean(G[0], S[0], r.whole).value;
  for (int ci = 0; ci < 3; ++ci) {
    const double mean = region_mean(G[ci], S[ci], r.whole).value;
    const double bf = bias(G[ci], G[ci], S[ci], r.whole).floor;
    const double ff = rmse_footprint(G[ci], G[ci], S[ci], r.whole, c.footprint).floor / mean;
    const bool negligible = !(mean >= 0.02 * total_mean) || !(mean > 0);
    const bool ok = negligible || (bf < 0.25 * c.delta_bias && ff < 0.25 * c.delta_rmse);
    f.met = f.met && ok;
    f.j[kComponentName[ci]] = {{"mean", mean},
                               {"bias_floor", bf},
                               {"rmse_footprint_floor_rel", ff},
                               {"negligible", negligible},
                               {"met", ok}};
  }
  return f;
}

json region_json(const Measure (&m)[3], bool floor) {
  json j = json::object();
  for (int i = 0; i < 3; ++i) j[kRegionName[i]] = floor ? m[i].floor : m[i].value;
  return j;
}

// JSON cannot hold NaN: regions without signal are written as null.
json finite_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }
void scrub(json& j) {
  if (j.is_object() || j.is_array()) {
    for (auto& v : j) scrub(v);
  } else if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    j = nullptr;
  }
}

float display_exposure(const Plane& g) {
  double s = 0;
  for (double v : g.v) s += v;
  const double m = s / double(std::max<std::size_t>(1, g.v.size()));
  return m > 0 ? float(std::log2(0.25 / m)) : 0.0f;
}

std::string variant_label(const Variant& v) {
  std::string s = v.term;
  if (v.smooth) s += "+smooth-normal";
  if (v.rough == CoarseRoughness::Widened) s += "+widened";
  return s;
}

std::string csv_header() {
  std::string h =
      "material,shape,scale,light,light_type,elevation,azimuth,method,ms_normal,roughness,component,gt_mean_"
      "whole";
  for (const char* m :
       {"bias", "bias_stderr", "rmse_footprint", "rmse_footprint_floor", "rmse", "rmse_stderr"})
    for (const char* r : kRegionName) h += fmt::format(",{}_{}", m, r);
  return h + ",ssim\n";
}
std::string csv_value(const json& v) {
  if (v.is_null()) return "";
  if (v.is_number()) return fmt::format("{:.9g}", v.get<double>());
  if (v.is_string()) return v.get<std::string>();
  return v.dump();
}
std::string csv_line(const json& r) {
  std::string s;
  for (const char* k : {"material", "shape", "scale", "light", "light_type", "elevation", "azimuth", "method",
                        "ms_normal", "roughness", "component"})
    s += csv_value(r[k]) + ",";
  s += csv_value(r["gt_mean"]["whole"]);
  for (const char* m :
       {"bias", "bias_stderr", "rmse_footprint", "rmse_footprint_floor", "rmse", "rmse_stderr"})
    for (const char* reg : kRegionName) s += "," + csv_value(r[m][reg]);
  return s + "," + csv_value(r["ssim"]) + "\n";
}

json config_json(const StudyConfig& c) {
  // "materials": every material of the rows (the report's per-material tables), the user's maps last.
  std::vector<std::string> names = c.materials;
  json user = json::array();
  for (const UserMaterial& u : c.user_materials) {
    names.push_back(u.name);
    user.push_back(
        {{"name", u.name}, {"height", u.height.filename().string()}, {"depth_texels", u.depth_texels}});
  }
  return {{"name", c.name},
          {"materials", names},
          {"user_materials", user},
          {"fine_size", c.fine_size},
          {"ao_rays", c.ao_rays},
          {"directional_azimuths", c.directional_azimuths},
          {"scales", c.scales},
          {"shapes", c.shapes},
          {"elevations", c.elevations},
          {"azimuths", c.azimuths},
          {"point_light", c.point_light},
          {"sphere_light", c.sphere_light},
          {"image_size", c.image_size},
          {"view_elevation", c.view_elevation},
          {"method_spp", c.method_spp},
          {"vndf_samples", c.vndf_samples},
          {"area_samples", c.area_samples},
          {"gt_spp", c.gt_spp},
          {"gt_max_spp", c.gt_max_spp},
          {"footprint", c.footprint},
          {"delta_bias", c.delta_bias},
          {"delta_rmse", c.delta_rmse},
          {"widened", c.widened},
          {"normal_ablation", c.normal_ablation},
          {"terms", c.terms},
          {"seed", c.seed}};
}
json config_json_area(const StudyConfig& c) {
  json j = config_json(c);
  if (area_section(c))
    j["area"] = {{"radii_deg", c.area_radii_deg},
                 {"elevations", c.area_elevations},
                 {"planar_radii_deg", c.area_planar_radii_deg},
                 {"planar_elevation", c.area_planar_elevation},
                 {"azimuth", c.area_azimuth},
                 {"terms", c.area_terms},
                 {"area_ms", c.area_ms_modes}};
  return j;
}

void validate(const StudyConfig& c) {
  auto bad = [](const std::string& what) { throw InputError("study: " + what); };
  if (c.materials.empty() && c.user_materials.empty()) bad("no materials");
  if (c.scales.empty()) bad("no scales");
  // The procedural kinds' fine size (a user map's side is checked when it is loaded).
  for (int k : c.scales)
    if (!c.materials.empty() && (k < 1 || c.fine_size % k != 0))
      bad(fmt::format("scale {} does not divide the fine size {}", k, c.fine_size));
  for (int k : c.scales)
    if (k < 1) bad(fmt::format("scale {} must be >= 1", k));
  std::vector<std::string> names = c.materials;
  for (const UserMaterial& u : c.user_materials) {
    if (u.name.empty()) bad(fmt::format("{}: a user material needs a name", u.height.string()));
    if (!(u.depth_texels > 0) || !std::isfinite(u.depth_texels) || u.depth_texels > 1e4f)
      bad(fmt::format("{}: depth must be in (0, 10000] texels, got {}", u.height.string(), u.depth_texels));
    names.push_back(u.name);
  }
  // Rows, images and timings are keyed by the material's name.
  for (size_t i = 0; i < names.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (names[i] == names[j]) bad(fmt::format("two materials are named '{}' (rename one file)", names[i]));
  for (const auto& s : c.shapes)
    if (s != "plane" && s != "cylinder") bad(fmt::format("unknown shape '{}' (plane, cylinder)", s));
  if (c.elevations.empty() && !c.point_light && !c.sphere_light && !area_section(c)) bad("no lights");
  for (double r : c.area_radii_deg)
    if (!(r > 0 && r <= 60)) bad(fmt::format("area-light angular radius must be in (0, 60], got {}", r));
  for (double r : c.area_planar_radii_deg)
    if (!(r > 0 && r <= 60)) bad(fmt::format("area-light angular radius must be in (0, 60], got {}", r));
  for (double e : c.area_elevations)
    if (!(e > 5 && e < 90)) bad(fmt::format("area-light elevation must be in (5, 90), got {}", e));
  if (area_section(c) && !(c.area_planar_elevation - 5 >= 0 && c.area_planar_elevation < 90))
    bad("area_planar_elevation must be in [5, 90)");
  try {
    for (const auto& t : c.terms) micro_shadowing_from_string(t);
    for (const auto& t : c.area_terms) micro_shadowing_from_string(t);
    for (const auto& m : c.area_ms_modes) area_ms_from_string(m);
  } catch (const InputError& e) {
    bad(e.what());
  }
  if (c.terms.empty() && !area_section(c)) bad("no terms");
  for (const auto* list : {&c.terms, &c.area_terms})
    for (const auto& t : *list)
      if (t == kGroundTruth) bad("ground-truth is the reference, not a term");
  if (area_section(c) && make_lights(c, frame_of("plane")).empty())
    bad("no area light keeps its cone 5 degrees above the horizon");
  for (double e : c.elevations)
    if (!(e > 0 && e < 90)) bad(fmt::format("light elevation must be in (0, 90), got {}", e));
  if (c.image_size < 8 || c.image_size > 4096) bad("image size must be in [8, 4096]");
  if (c.footprint < 1 || c.footprint > c.image_size) bad("footprint must be in [1, image size]");
  if (c.gt_spp < 8 || c.gt_spp % 8 != 0) bad("gt_spp must be a multiple of 8");
  if (c.gt_max_spp < c.gt_spp) bad("gt_max_spp must be >= gt_spp");
  if (c.method_spp < 1) bad("method_spp must be >= 1");
  for (int k : c.scales)
    if (!c.materials.empty() && double(c.image_size) * k * kTileWorld / c.fine_size > kTileWorld * 1.01)
      bad(fmt::format("at scale {} the view ({} pixels x {} texels) is wider than the texture ({} texels)", k,
                      c.image_size, k, c.fine_size));
}

// The user's height maps, loaded and checked (square, side divisible by every scale, at least the view's
// width) before any work, so a bad file is one error line and nothing is written.
std::vector<Texture> load_user_maps(const StudyConfig& c) {
  std::vector<Texture> maps;
  for (const UserMaterial& u : c.user_materials) {
    Texture h = load_height_map(u.height);
    const std::string f = u.height.string();
    if (h.width() != h.height())
      throw InputError(fmt::format("study: {}: height map is {}x{}; the study needs a square map", f,
                                   h.width(), h.height()));
    for (int k : c.scales) {
      if (h.width() % k != 0)
        throw InputError(
            fmt::format("study: {}: scale {} does not divide the map's size {}", f, k, h.width()));
      if (double(c.image_size) * k * kTileWorld / h.width() > kTileWorld * 1.01)
        throw InputError(fmt::format(
            "study: {}: at scale {} the view ({} pixels x {} texels) is wider than the map ({} texels)", f, k,
            c.image_size, k, h.width()));
    }
    maps.push_back(std::move(h));
  }
  return maps;
}

}  // namespace

UserMaterial user_material_from_folder(const std::filesystem::path& dir) {
  const std::string d = dir.string();
  if (!std::filesystem::is_directory(dir)) throw InputError(fmt::format("{}: material folder not found", d));
  const auto mj = dir / "material.json";
  std::ifstream in(mj);
  if (!in) throw InputError(fmt::format("{}: no material.json (a gen-material folder holds one)", d));
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: material.json is not JSON ({})", d, e.what()));
  }
  if (!j.is_object() || !j.contains("height_texels") || !j["height_texels"].is_number())
    throw InputError(fmt::format("{}: material.json has no numeric height_texels", d));
  const std::string height = j.value("height", std::string("height.png"));
  UserMaterial u;
  // The folder's name; "dir/" has an empty filename, so take the parent's.
  u.name = (dir.has_filename() ? dir : dir.parent_path()).filename().string();
  u.height = dir / height;
  u.depth_texels = j["height_texels"].get<float>();
  if (!std::filesystem::exists(u.height))
    throw InputError(fmt::format("{}: height map {} not found", d, height));
  return u;
}

json run_study(const StudyConfig& cfg_in, const std::filesystem::path& out, const Log& log_fn) {
  const StudyConfig& cfg = cfg_in;
  validate(cfg);
  const std::vector<Texture> user_maps = load_user_maps(cfg);
  const auto t_start = std::chrono::steady_clock::now();
  const double cpu_start = cpu_seconds();
  auto log = [&](const std::string& s) {
    if (log_fn) log_fn(s);
  };
  std::error_code ec;
  std::filesystem::create_directories(out / "images", ec);
  if (ec) throw InputError(fmt::format("{}: cannot create directory: {}", out.string(), ec.message()));

  json gt_rows = json::array(), rows = json::array(), images = json::array();
  json area_rep = json::array();  // area-light section: representative against integrated / sampled
  json timing = {{"materials", json::object()}};
  double t_gen = 0, t_gt = 0, t_methods = 0;
  std::map<std::string, double> variant_cpu;
  uint64_t gt_rays = 0;
  double gt_ray_seconds = 0;
  const int steps = int((cfg.materials.size() + cfg.user_materials.size()) * cfg.shapes.size() *
                        cfg.scales.size() * make_lights(cfg, frame_of("plane")).size());
  int step = 0;

  // The procedural kinds, then the user's maps (index m - materials.size()).
  for (size_t m = 0; m < cfg_in.materials.size() + cfg_in.user_materials.size(); ++m) {
    const size_t ui = m - cfg_in.materials.size();
    const bool user = m >= cfg_in.materials.size();
    const std::string kind = user ? cfg_in.user_materials[ui].name : cfg_in.materials[m];
    // A user map's side is its fine size: the camera, regions and floors below read it from cfg.
    StudyConfig mat_cfg = cfg_in;
    if (user) mat_cfg.fine_size = user_maps[ui].width();
    const StudyConfig& cfg = mat_cfg;
    auto t0 = std::chrono::steady_clock::now();
    GenOptions go;
    go.kind = kind;
    go.size = cfg.fine_size;
    go.ao_rays = cfg.ao_rays;
    go.directional_azimuths = 0;
    for (const auto* list : {&cfg.terms, &cfg.area_terms})
      for (const std::string& t : *list)
        if (occlusion::find_micro_shadowing_method(t)->needs_texel)
          go.directional_azimuths = cfg.directional_azimuths;
    log(fmt::format("study: generating the fine {} texture set ({}^2 texels, {} bake rays)", kind,
                    cfg.fine_size, cfg.ao_rays));
    const TextureSet fine = user ? load_or_generate(go, cfg.material_cache, log_fn, &user_maps[ui],
                                                    cfg_in.user_materials[ui].depth_texels)
                                 : load_or_generate(go, cfg.material_cache, log_fn);
    const double tg = secs_since(t0);
    t_gen += tg;
    timing["materials"][kind] = {{"generate_seconds", tg}};
    for (const std::string& shape : cfg.shapes) {
      const Frame fr = frame_of(shape);
      const auto lights = make_lights(cfg, fr);
      Scene gt_scene = make_scene(cfg, make_material(kind, fine, true), shape);
      gt_scene.settings.micro_shadowing = kGroundTruth;
      gt_scene.settings.error_batches = 8;
      // One ground-truth renderer per material and shape (a displaced cylinder's BVH takes tens of seconds):
      // the Renderer keeps a reference to the scene and reads the camera, lights, spp, seed and component at
      // render time, so they are changed in gt_scene between renders.
      const auto t_build = std::chrono::steady_clock::now();
      const Renderer gt_renderer(gt_scene);
      timing["materials"][kind]["gt_build_seconds_" + shape] = secs_since(t_build);
      for (int k : cfg.scales) {
        const Camera cam = camera_for(cfg, fr, k);
        gt_scene.camera = cam;
        const Regions reg = make_regions(cfg, shape, cam, k);
        const Mask* masks[3] = {&reg.rough, &reg.smooth, &reg.whole};
        const auto variants = make_variants(cfg, k);
        Scene coarse[2] = {
            make_scene(cfg,
                       make_material(kind, downsample_texture_set(fine, k, CoarseRoughness::Base), false),
                       shape),
            Scene{}};
        if (cfg.widened && k > 1)
          coarse[1] = make_scene(
              cfg, make_material(kind, downsample_texture_set(fine, k, CoarseRoughness::Widened), false),
              shape);
        coarse[0].camera = coarse[1].camera = cam;
        for (const LightSpec& ls : lights) {
          ++step;
          const auto t_light = std::chrono::steady_clock::now();
          // Ground truth: diffuse and specular rendered alone; rounds of independent estimates (new seed),
          // doubling the samples, until the floors are met or gt_max_spp.
          gt_scene.lights[0] = ls.light;
          RenderResult acc[2];
          int spp = 0, rounds = 0;
          ComponentImages G;
          Plane GL[3], GS[3];
          GtFloors floors;
          while (true) {
            const int n = spp == 0 ? cfg.gt_spp : spp;
            for (int ci = 0; ci < 2; ++ci) {
              gt_scene.settings.component = ci == 0 ? Component::Diffuse : Component::Specular;
              gt_scene.settings.spp = n;
              gt_scene.settings.seed = cfg.seed + 7919u * uint32_t(rounds);
              RenderResult res = gt_renderer.render_with_error();
              if (spp == 0)
                acc[ci] = std::move(res);
              else
                merge(acc[ci], spp, res, n);
            }
            spp += n, ++rounds;
            for (int ci = 0; ci < 2; ++ci) G.img[ci + 1] = acc[ci].mean, G.se[ci + 1] = acc[ci].std_error;
            add_total(G);
            for (int ci = 0; ci < 3; ++ci) GL[ci] = luminance(G.img[ci]), GS[ci] = luminance_stderr(G.se[ci]);
            floors = check_floors(cfg, GL, GS, reg);
            if (floors.met || spp * 2 > cfg.gt_max_spp) break;
          }
          const double t_gt_light = secs_since(t_light);
          t_gt += t_gt_light;
          for (int ci = 0; ci < 2; ++ci) {
            gt_rays += acc[ci].stats.camera_rays + acc[ci].stats.shadow_rays;
            gt_ray_seconds += acc[ci].stats.seconds;
          }
          gt_rows.push_back({{"material", kind},
                             {"shape", shape},
                             {"scale", k},
                             {"light", ls.name},
                             {"spp", spp},
                             {"rounds", rounds},
                             {"floors_met", floors.met},
                             {"components", floors.j},
                             {"camera_rays", acc[0].stats.camera_rays + acc[1].stats.camera_rays},
                             {"shadow_rays", acc[0].stats.shadow_rays + acc[1].stats.shadow_rays}});
          const bool featured = std::find(cfg.featured_lights.begin(), cfg.featured_lights.end(), ls.name) !=
                                cfg.featured_lights.end();
          const float exposure = display_exposure(GL[0]);
          const std::string stem = fmt::format("{}_{}_k{}_{}", kind, shape, k, ls.name);
          if (featured) {
            write_png(out / "images" / (stem + "_ground-truth.png"), G.img[0], exposure);
            images.push_back({{"material", kind},
                              {"shape", shape},
                              {"scale", k},
                              {"light", ls.name},
                              {"method", "ground-truth"},
                              {"image", "images/" + stem + "_ground-truth.png"}});
          }
          // Every term on the coarse set, same camera.
          const auto t_m = std::chrono::steady_clock::now();
          std::map<std::string, std::array<Plane, 3>> area_lum;  // "method/area_ms" → luminance per component
          for (const Variant& v : variants) {
            Scene& sc = coarse[v.rough == CoarseRoughness::Widened ? 1 : 0];
            sc.lights[0] = ls.light;
            sc.settings.micro_shadowing = v.term;
            sc.settings.ms_smooth_normal = v.smooth;
            sc.settings.area_ms = v.area_ms;
            sc.settings.spp = cfg.method_spp;
            // generic-vndf: vndf_samples per light; evaluated per area sample, they are spread over them.
            sc.settings.vndf_samples = area_sampled(ls.light) && v.area_ms != AreaMs::Representative
                                           ? std::max(1, cfg.vndf_samples / cfg.area_samples)
                                           : cfg.vndf_samples;
            sc.settings.seed = cfg.seed;
            ComponentImages M;
            const double cpu_v = cpu_seconds();
            for (int ci = 0; ci < 2; ++ci) {
              sc.settings.component = ci == 0 ? Component::Diffuse : Component::Specular;
              const Renderer r(sc);
              M.img[ci + 1] = r.render();
            }
            add_total(M);
            const std::string label = variant_label(v);
            variant_cpu[label + (area_sampled(ls.light) ? " (area light)" : "")] += cpu_seconds() - cpu_v;
            for (int ci = 0; ci < 3; ++ci) {
              const Plane A = luminance(M.img[ci]);
              Measure b[3], f[3], e[3], gm[3];
              for (int ri = 0; ri < 3; ++ri) {
                b[ri] = bias(A, GL[ci], GS[ci], *masks[ri]);
                f[ri] = rmse_footprint(A, GL[ci], GS[ci], *masks[ri], cfg.footprint);
                e[ri] = rmse(A, GL[ci], GS[ci], *masks[ri]);
                gm[ri] = region_mean(GL[ci], GS[ci], *masks[ri]);
              }
              rows.push_back(
                  {{"material", kind},
                   {"shape", shape},
                   {"scale", k},
                   {"light", ls.name},
                   {"light_type", ls.type},
                   {"elevation", ls.elevation},
                   {"azimuth", ls.azimuth},
                   {"method", v.term},
                   {"ms_normal", v.smooth ? "smooth" : "shading"},
                   {"roughness", v.rough == CoarseRoughness::Widened ? "widened" : "base"},
                   {"component", kComponentName[ci]},
                   {"gt_mean", region_json(gm, false)},
                   {"bias", region_json(b, false)},
                   {"bias_stderr", region_json(b, true)},
                   {"rmse_footprint", region_json(f, false)},
                   {"rmse_footprint_floor", region_json(f, true)},
                   {"rmse", region_json(e, false)},
                   {"rmse_stderr", region_json(e, true)},
                   {"ssim", finite_or_null(ssim(M.img[ci], G.img[ci], display_exposure(GL[ci])))}});
              if (area_section(cfg)) {
                rows.back()["area_ms"] = to_string(v.area_ms);
                rows.back()["light_radius_deg"] = ls.radius_deg;
                area_lum[v.term + "/" + to_string(v.area_ms)][ci] = A;
              }
            }
            if (featured && !v.smooth && v.rough == CoarseRoughness::Base) {
              const std::string& m = v.term;
              write_png(out / "images" / (stem + "_" + m + ".png"), M.img[0], exposure);
              write_png_display(out / "images" / (stem + "_" + m + "_diff.png"),
                                difference_image(M.img[0], G.img[0], exposure));
              images.push_back({{"material", kind},
                                {"shape", shape},
                                {"scale", k},
                                {"light", ls.name},
                                {"method", m},
                                {"image", "images/" + stem + "_" + m + ".png"},
                                {"diff", "images/" + stem + "_" + m + "_diff.png"}});
            }
          }
          // The representative point's own error: its image against the integrated (or, without one, the
          // per-sample) image of the same term, same light samples.
          for (const std::string& t : cfg.area_terms) {
            if (!area_lum.count(t + "/representative")) continue;
            const bool has_int = area_lum.count(t + "/integrated") > 0;
            if (!has_int && !area_lum.count(t + "/sampled")) continue;
            const auto& R = area_lum[t + "/representative"];
            const auto& X = area_lum[t + (has_int ? "/integrated" : "/sampled")];
            for (int ci = 0; ci < 3; ++ci) {
              const Plane zero(R[ci].width, R[ci].height, 0.0);
              const double gm = region_mean(GL[ci], GS[ci], reg.whole).value;
              area_rep.push_back(
                  {{"material", kind},
                   {"scale", k},
                   {"light", ls.name},
                   {"light_type", ls.type},
                   {"light_radius_deg", ls.radius_deg},
                   {"elevation", ls.elevation},
                   {"component", kComponentName[ci]},
                   {"method", t},
                   {"against", has_int ? "integrated" : "sampled"},
                   {"ratio", finite_or_null(bias(R[ci], X[ci], zero, reg.whole).value)},
                   {"rmse_footprint_rel",
                    finite_or_null(rmse_footprint(R[ci], X[ci], zero, reg.whole, cfg.footprint).value / gm)},
                   {"rmse_rel", finite_or_null(rmse(R[ci], X[ci], zero, reg.whole).value / gm)}});
            }
          }
          const double tm = secs_since(t_m);
          t_methods += tm;
          log(fmt::format(
              "study: [{}/{}] {} {} k={} {}: ground truth {} spp ({}), {} terms; {:.1f} s + {:.1f} s", step,
              steps, kind, shape, k, ls.name, spp, floors.met ? "floors met" : "floors NOT met",
              variants.size(), t_gt_light, tm));
        }
      }
    }
  }

  json results = {
      {"config", config_json_area(cfg)}, {"ground_truth", gt_rows}, {"rows", rows}, {"images", images}};
  scrub(results);
  results["summary"] = summarize(results["rows"], cfg);
  if (area_section(cfg)) {
    results["area_summary"] = summarize_area(results["rows"]);
    results["area_representative"] = area_rep;
    scrub(results["area_representative"]);
  }
  std::string csv = csv_header();
  for (const auto& r : results["rows"]) csv += csv_line(r);
  io::write_file_atomic(out / "results.json", results.dump(1) + "\n");
  io::write_file_atomic(out / "results.csv", csv);
  io::write_file_atomic(out / "summary.md", summary_markdown(results));
  if (area_section(cfg)) io::write_file_atomic(out / "area_summary.md", area_summary_markdown(results));
  write_study_html(results, out);
  timing["generate_seconds"] = t_gen;
  timing["ground_truth_seconds"] = t_gt;
  timing["methods_seconds"] = t_methods;
  timing["total_seconds"] = secs_since(t_start);
  timing["total_cpu_seconds"] = cpu_seconds() - cpu_start;
  timing["ground_truth_rays"] = gt_rays;
  timing["term_cpu_seconds"] = variant_cpu;
  timing["ground_truth_rays_per_second"] = gt_ray_seconds > 0 ? double(gt_rays) / gt_ray_seconds : 0.0;
  io::write_file_atomic(out / "timing.json", timing.dump(1) + "\n");
  log(
      fmt::format("study: {} rows, {:.0f} s wall, {:.0f} s CPU (generation {:.0f} s, ground truth {:.0f} s, "
                  "terms {:.0f} s) -> {}",
                  rows.size(), timing["total_seconds"].get<double>(),
                  timing["total_cpu_seconds"].get<double>(), t_gen, t_gt, t_methods, out.string()));
  return results;
}

}  // namespace msh::study
