// The study's cells (see study/study.h): the fine texture sets, the scenes and their camera and regions, the
// ground truth with its stopping rule, every term variant, and each variant's metrics against the ground
// truth.
#include <fmt/format.h>
#include <microshadow/io/atomic_file.h>
#include <microshadow/io/error.h>
#include <microshadow/io/texture.h>
#include <microshadow/occlusion/directional.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/directional_codec.h>
#include <microshadow/render/image.h>
#include <microshadow/render/renderer.h>
#include <microshadow/render/texture_gen.h>
#include <microshadow/study/metrics.h>
#include <microshadow/study/study.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>

#include "study_internal.h"

namespace msh::study {

using namespace msh::render;
using namespace msh::study::detail;
using json = nlohmann::json;

namespace {

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
    throw InputError("study: a cached map has the wrong number of channels");
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
  const bool with_view = go.directional_azimuths > 0 && go.directional_view;
  const char* view = with_view ? "v21" : "";  // the 21 channels of the view correction
  // The bakes' version: raised whenever a bake's output changes, so no cache of an older bake is read (2: the
  // visibility bake's profile scans and their rotations per 8 texels).
  constexpr int kBakeVersion = 2;
  const std::string key = user_height
                              ? fmt::format("user-{}_{}_z{:.9g}_h{:016x}_a{}_d{}{}_b{}", go.kind,
                                            user_height->width(), user_depth, height_hash(*user_height),
                                            go.ao_rays, go.directional_azimuths, view, kBakeVersion)
                              : fmt::format("{}_{}_a{}_d{}{}_s{}_b{}", go.kind, go.size, go.ao_rays,
                                            go.directional_azimuths, view, go.seed, kBakeVersion);
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
                        {"directional", &TextureSet::directional,
                         with_view ? directional::kViewChannels : directional::kDirectionalChannels}};
  // A cached entry is checked on read (every map present with its channels, the key's size, finite texels;
  // the depth finite, positive and, for a user map, the key's): a bad entry is baked again, never used.
  const int want_w = user_height ? user_height->width() : go.size;
  const int want_h = user_height ? user_height->height() : go.size;
  const auto read_cached = [&]() -> std::optional<TextureSet> {
    TextureSet s;
    try {
      for (const Slot& sl : slots) {
        if (go.directional_azimuths == 0 && sl.map == &TextureSet::directional) continue;
        const std::filesystem::path f = dir / (std::string(sl.name) + ".npy");
        Texture t = from_volume(io::read_volume(f), sl.channels);
        if (t.width() != want_w || t.height() != want_h)
          throw InputError(fmt::format("{}: {}x{} texels, the key's {}x{}", f.filename().string(), t.width(),
                                       t.height(), want_w, want_h));
        for (int y = 0; y < t.height(); ++y)
          for (int x = 0; x < t.width(); ++x)
            for (int c = 0; c < t.channels(); ++c)
              if (!std::isfinite(t.at(x, y, c)))
                throw InputError(fmt::format("{}: a texel is not finite", f.filename().string()));
        s.*sl.map = std::move(t);
      }
      require_regular_file(dir / "depth.txt");
      std::ifstream in(dir / "depth.txt");
      if (!(in >> s.depth_texels) || !std::isfinite(s.depth_texels) || !(s.depth_texels > 0) ||
          s.depth_texels > 1e6f || (user_height && s.depth_texels != user_depth))
        throw InputError("depth.txt: not the entry's depth (a finite number > 0" +
                         std::string(user_height ? fmt::format(", {:.9g}", user_depth) : "") + ")");
    } catch (const InputError& e) {
      if (log)
        log(fmt::format("study: the cache entry {} is invalid ({}); baking it again", dir.string(),
                        e.what()));
      return std::nullopt;
    }
    s.slope_covariance = slope_covariance(s.normal);  // not stored: a sum over the fine normals
    return s;
  };
  if (!dir.empty() && std::filesystem::exists(dir / "depth.txt"))
    if (std::optional<TextureSet> s = read_cached()) {
      if (log) log("study: texture set from the cache " + dir.string());
      return std::move(*s);
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

bool area_sampled(const Light& l) {
  return l.type == LightType::Sphere || l.type == LightType::Disk || l.type == LightType::Rect;
}

// cos and sin of an angle in degrees, exact at multiples of 90°.
double cos_deg(double a) {
  const double r = std::fmod(std::abs(a), 360.0);
  if (r == 90 || r == 270) return 0;
  if (r == 0) return 1;
  if (r == 180) return -1;
  return std::cos(a * kPi<double> / 180);
}
double sin_deg(double a) { return cos_deg(90 - a); }

// One window of a cell's view (StudyConfig's views and windows comments): its orthographic camera, where it
// sits in the cell's image, and the world offset of its centre from the view's centre (positional lights
// move with it, so that every window sees the same light).
struct Window {
  Camera cam;
  int x0 = 0, y0 = 0;
  Vec3f offset{0, 0, 0};
};

// The windows of a view, row-major. Each camera looks at its window's centre on the mean surface from
// `view` degrees off the normal at the view azimuth: a pixel covers k fine texels across and
// k / cos(view) along the view.
std::vector<Window> windows_of(const StudyView& v, const Frame& fr, int k, int fine_size) {
  const float W = float(v.width) * float(k) * kTileWorld / float(fine_size);
  const float D = 4.0f * kTileWorld, el = float(90 - v.view) * kPi<float> / 180;
  const Vec3f h = fr.T * float(cos_deg(v.view_azimuth)) + fr.B * float(sin_deg(v.view_azimuth));
  std::vector<Window> out;
  const int n = v.windows;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      Window w;
      if (n > 1) {
        // Window centres from the R2 sequence (Roberts 2018, "The unreasonable effectiveness of quasirandom
        // sequences"): spread over the tile and at no common phase of a periodic texture (a regular grid of
        // centres 512 texels apart put all 16 windows of brick at 2048² in its mortar).
        const double q = double(j * n + i);
        const float du = float(std::fmod(0.5 + q * 0.7548776662466927, 1.0)) - 0.5f;
        const float dv = float(std::fmod(0.5 + q * 0.5698402909980532, 1.0)) - 0.5f;
        w.offset = fr.T * (du * kTileWorld) + fr.B * (dv * kTileWorld);
      }
      w.cam.target = fr.P0 + w.offset;
      w.cam.eye = w.cam.target + (fr.N * std::sin(el) + h * std::cos(el)) * D;
      // Straight down, the image's up points away from the camera's azimuth, as it does just off the normal.
      w.cam.up = v.view < 1e-3 ? -h : fr.N;
      w.cam.orthographic = true;
      w.cam.ortho_height = W * float(v.height) / float(v.width);
      w.x0 = i * v.width, w.y0 = j * v.height;
      out.push_back(w);
    }
  return out;
}

// The texture's rough half (u mod 1 < 0.5) and smooth half, from where each pixel centre's ray (the
// renderer's orthographic camera, window by window) meets the mean surface; pixels within 1.5 footprints + 2
// fine texels of a boundary belong to neither half (they stay in the whole); pixels that miss the shape
// belong to no region.
Regions make_regions(const StudyView& v, const std::string& shape, const std::vector<Window>& windows, int k,
                     int fine_size, int tiles) {
  const int iw = v.image_width(), ih = v.image_height();
  Regions r{Mask(iw, ih, 0), Mask(iw, ih, 0), Mask(iw, ih, 0)};
  const double margin = (1.5 * k + 2.0) / double(fine_size);
  for (const Window& win : windows) {
    const Camera& cam = win.cam;
    const Vec3f f = normalize(cam.target - cam.eye), rt = normalize(cross(f, cam.up)), up = cross(rt, f);
    const float th = 0.5f * cam.ortho_height, aspect = float(v.width) / float(v.height);
    for (int y = 0; y < v.height; ++y)
      for (int x = 0; x < v.width; ++x) {
        const float px = (2 * (float(x) + 0.5f) / float(v.width) - 1) * th * aspect,
                    py = (1 - 2 * (float(y) + 0.5f) / float(v.height)) * th;
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
          u = (o.x + t * d.x + 0.5 * tiles * kTileWorld) / kTileWorld;  // in tiles
        }
        const std::size_t i = std::size_t(win.y0 + y) * iw + std::size_t(win.x0 + x);
        r.whole.px[i] = 1;
        const double fu = u - std::floor(u);
        const double dist = std::min({fu, std::abs(fu - 0.5), 1.0 - fu});
        if (dist <= margin) continue;
        (fu < 0.5 ? r.rough : r.smooth).px[i] = 1;
      }
  }
  return r;
}

// tiles: the plane spans tiles × tiles texture tiles (odd), centred on the view.
Scene make_scene(const StudyConfig& c, Material m, const std::string& shape, int tiles) {
  Scene s;
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
    o.half_size = {0.5f * float(tiles) * kTileWorld, 0.5f * float(tiles) * kTileWorld};
    m.uv_scale = float(tiles);
  }
  s.materials.push_back(std::move(m));
  s.objects.push_back(o);
  s.lights.resize(1);
  Settings& st = s.settings;
  st.area_lights = true;
  st.area_samples = c.area_samples;
  st.vndf_samples = c.vndf_samples;
  st.lut_path = c.lut_path;
  st.seed = c.seed;
  s.source = "study";
  return s;
}

// The total (component 0) of diffuse (1) and specular (2).
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

struct GtFloors {
  bool met = true;
  json j = json::object();
};

// The stopping rule (StudyConfig::GtRule): Full = for every component whose mean is at least 2% of the
// total's, the whole-image bias floor below delta_bias / 4 and the rmse_footprint floor below delta_rmse / 4
// of the mean; Bias = the bias floor of the total and the diffuse (unless negligible) alone.
GtFloors check_floors(const StudyConfig& c, StudyConfig::GtRule rule, const Plane (&G)[3],
                      const Plane (&S)[3], const Regions& r) {
  GtFloors f;
  const double total_mean = region_mean(G[0], S[0], r.whole).value;
  for (int ci = 0; ci < 3; ++ci) {
    const double mean = region_mean(G[ci], S[ci], r.whole).value;
    const double bf = bias(G[ci], G[ci], S[ci], r.whole).floor;
    const double ff = rmse_footprint(G[ci], G[ci], S[ci], r.whole, c.footprint).floor / mean;
    const bool negligible = !(mean >= 0.02 * total_mean) || !(mean > 0);
    const bool ok = rule == StudyConfig::GtRule::Bias
                        ? ci == 2 || negligible || bf < 0.25 * c.delta_bias
                        : negligible || (bf < 0.25 * c.delta_bias && ff < 0.25 * c.delta_rmse);
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

// The keys that say which cell a record belongs to; its ground truth, rows and featured images start from
// them (json objects keep their keys sorted, so the files do not depend on the order they are added in).
json cell_keys(const StudyCell& cell, const std::string& material) {
  return {{"material", material},
          {"shape", cell.shape},
          {"scale", cell.scale},
          {"view", cell.view.view},
          {"view_azimuth", cell.view.view_azimuth},
          {"light", cell.light.name}};
}

// A value, or null where it is NaN (JSON cannot hold NaN).
json finite_or_null(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

float display_exposure(const Plane& g) {
  double s = 0;
  for (double v : g.px) s += v;
  const double m = s / double(std::max<std::size_t>(1, g.px.size()));
  return m > 0 ? float(std::log2(0.25 / m)) : 0.0f;
}

// timing.json's key of a variant.
std::string variant_label(const StudyVariant& v) {
  std::string s = v.term;
  if (v.smooth_normal) s += "+smooth-normal";
  if (v.roughness == CoarseRoughness::Widened) s += "+widened";
  return s;
}

// The material's GenOptions: the directional channels are baked only when a term reads them.
GenOptions gen_options(const StudyConfig& c, const std::string& kind) {
  GenOptions go;
  go.kind = kind;
  go.size = c.fine_size;
  go.ao_rays = c.ao_rays;
  go.directional_azimuths = 0;
  for (const auto* list : {&c.terms, &c.area_terms})
    for (const std::string& t : *list) {
      const auto* info = occlusion::find_micro_shadowing_method(split_study_term(t).first);
      if (info->needs_texel) go.directional_azimuths = c.directional_azimuths;
      if (info->texel_channels > directional::kDirectionalChannels) go.directional_view = true;
    }
  return go;
}

}  // namespace

GroundTruth make_ground_truth(ComponentImages images) {
  GroundTruth g;
  g.images = std::move(images);
  for (int ci = 0; ci < 3; ++ci) {
    g.lum[ci] = luminance(g.images.img[ci]);
    g.lum_se[ci] = luminance_stderr(g.images.se[ci]);
  }
  return g;
}

std::array<json, 3> measure_variant(const ComponentImages& variant, const GroundTruth& gt,
                                    const Regions& regions, int footprint) {
  const Mask* masks[3] = {&regions.rough, &regions.smooth, &regions.whole};
  std::array<json, 3> out;
  for (int ci = 0; ci < 3; ++ci) {
    const Plane A = luminance(variant.img[ci]);
    const Plane &G = gt.lum[ci], &S = gt.lum_se[ci];
    Measure b[3], f[3], e[3], gm[3];
    for (int ri = 0; ri < 3; ++ri) {
      b[ri] = bias(A, G, S, *masks[ri]);
      f[ri] = rmse_footprint(A, G, S, *masks[ri], footprint);
      e[ri] = rmse(A, G, S, *masks[ri]);
      gm[ri] = region_mean(G, S, *masks[ri]);
    }
    out[ci] = {{"gt_mean", region_json(gm, false)},
               {"bias", region_json(b, false)},
               {"bias_stderr", region_json(b, true)},
               {"rmse_footprint", region_json(f, false)},
               {"rmse_footprint_floor", region_json(f, true)},
               {"rmse", region_json(e, false)},
               {"rmse_stderr", region_json(e, true)},
               {"ssim", finite_or_null(ssim(variant.img[ci], gt.images.img[ci], display_exposure(G)))}};
  }
  return out;
}

// The shared state, one level per member group; each level is rebuilt when a cell differs from the last at
// that level, and rebuilding a level clears the levels below it.
struct CellRunner::State {
  const StudyPlan& plan;
  Log log;
  json timing = {{"generate_seconds", 0.0}, {"materials", json::object()}};
  // Material: the plan's configuration with the material's fine size (camera, regions and floors read it).
  std::optional<std::size_t> material;
  StudyConfig cfg;
  TextureSet fine;
  // Material × shape: the plane's tiles, the ground-truth scene and its renderer. The Renderer keeps a
  // reference to the scene and reads the camera, lights, image size, spp, seed and component at render time,
  // so they are changed in the scene between renders.
  std::string shape;
  int tiles = 3;
  std::unique_ptr<Scene> gt_scene;
  std::unique_ptr<Renderer> gt_renderer;
  // Material × shape × scale: the coarse scenes (base roughness, and widened at k > 1), and per compact form
  // of the directional channels (a term "method@form") the coarse level as that form stores it, swapped into
  // the scene's material for the term's render.
  int scale = 0;
  Scene coarse[2];
  std::map<std::string, Texture> form_levels;
  // Material: the compact forms' codes, fitted to the fine channels when a term first asks.
  std::map<std::string, DirectionalCodec> codecs;
  // ... × view: the windows and the regions.
  std::optional<std::pair<double, double>> view;
  std::vector<Window> windows;
  Regions regions;

  State(const StudyPlan& p, Log l) : plan(p), log(std::move(l)) {}

  // The plane's tiles for every cell of the material × shape (the ground truth's geometry is built once):
  // the farthest any of its views reaches, and a margin that a shadow ray 5° above the plane or a camera ray
  // 85° off the normal crosses over the relief's depth (11.5 depths), at least 3/4 tile.
  int plane_tiles(std::size_t material_index, const std::string& sh) const {
    double extent = 0;
    for (const StudyCell& c : plan.cells)
      if (c.material == material_index && c.shape == sh) extent = std::max(extent, c.view.extent);
    const double margin = std::max(0.75, 11.5 * double(fine.depth_texels) / double(cfg.fine_size));
    return 2 * int(std::ceil(extent + margin - 0.5)) + 1;
  }

  void prepare(const StudyCell& cell) {
    const StudyMaterial& mat = plan.materials.at(cell.material);
    if (material != cell.material) {
      clear_shape();
      fine = TextureSet{};
      codecs.clear();
      material.reset();
      cfg = plan.config;
      cfg.fine_size = mat.fine_size;
      const GenOptions go = gen_options(cfg, mat.name);
      if (log)
        log(fmt::format("study: generating the fine {} texture set ({}^2 texels, {} bake rays)", mat.name,
                        cfg.fine_size, cfg.ao_rays));
      const auto t0 = std::chrono::steady_clock::now();
      fine = mat.user() ? load_or_generate(go, cfg.material_cache, log, &mat.user_height, mat.depth_texels)
                        : load_or_generate(go, cfg.material_cache, log);
      const double tg = secs_since(t0);
      timing["generate_seconds"] = timing["generate_seconds"].get<double>() + tg;
      timing["materials"][mat.name] = {{"generate_seconds", tg}};
      material = cell.material;
    }
    if (shape != cell.shape) {
      clear_shape();
      tiles = cell.shape == "plane" ? plane_tiles(cell.material, cell.shape) : 1;
      gt_scene = std::make_unique<Scene>(
          make_scene(cfg, material_from_texture_set(mat.name, fine, true), cell.shape, tiles));
      gt_scene->settings.micro_shadowing = kGroundTruth;
      gt_scene->settings.error_batches = 8;
      const auto t_build = std::chrono::steady_clock::now();
      gt_renderer = std::make_unique<Renderer>(*gt_scene);
      timing["materials"][mat.name]["gt_build_seconds_" + cell.shape] = secs_since(t_build);
      shape = cell.shape;
    }
    if (scale != cell.scale) {
      const int k = cell.scale;
      coarse[0] = coarse[1] = Scene{};
      form_levels.clear();
      view.reset();
      // The coarse set at k is mip level log2 k, its directional channels stored as an engine would read
      // them.
      const auto coarse_set = [&](CoarseRoughness mode) {
        TextureSet s = downsample_texture_set(fine, k, mode);
        if (!s.directional.empty())
          store_directional_channels(s.directional, channel_ranges(fine.directional),
                                     cfg.directional_encoding);
        return s;
      };
      coarse[0] = make_scene(
          cfg, material_from_texture_set(mat.name, coarse_set(CoarseRoughness::Base), false), shape, tiles);
      if (cfg.widened && k > 1)
        coarse[1] =
            make_scene(cfg, material_from_texture_set(mat.name, coarse_set(CoarseRoughness::Widened), false),
                       shape, tiles);
      scale = k;
    }
    const std::pair<double, double> vk{cell.view.view, cell.view.view_azimuth};
    if (view != vk) {
      windows = windows_of(cell.view, frame_of(shape), cell.scale, cfg.fine_size);
      regions = make_regions(cell.view, shape, windows, cell.scale, cfg.fine_size, tiles);
      view = vk;
    }
  }

  // The coarse level of the directional channels as the compact form stores it (the fine code's level of
  // scale k: encoded, quantised, decoded).
  Texture& form_level(const std::string& form, int k) {
    auto it = form_levels.find(form);
    if (it != form_levels.end()) return it->second;
    if (form == "unorm8" || form == "bc4") {  // every channel on its own, between the fine level's range
      Texture t = box_downsample(fine.directional, k);
      store_directional_channels(t, channel_ranges(fine.directional), directional_encoding_from_name(form));
      return form_levels.emplace(form, std::move(t)).first->second;
    }
    auto c = codecs.find(form);
    if (c == codecs.end()) {
      const auto t0 = std::chrono::steady_clock::now();
      c = codecs.emplace(form, fit_directional_codec(fine.directional, form)).first;
      if (log)
        log(fmt::format("study: fitted the directional form {} ({} coefficients, {:.3f} s)", form,
                        c->second.coefficients, secs_since(t0)));
    }
    return form_levels.emplace(form, store_through_codec(box_downsample(fine.directional, k), c->second))
        .first->second;
  }

  // The steps of CellRunner::run (defined below, after render_mosaic).
  GroundTruth ground_truth(const StudyCell& cell, CellResult& out);
  ComponentImages render_variant(const StudyCell& cell, const StudyVariant& v, CellResult& out);

  // Clears the shape and scale levels (the renderer before the scene it refers to).
  void clear_shape() {
    scale = 0;
    form_levels.clear();
    coarse[0] = coarse[1] = Scene{};
    view.reset();
    windows.clear();
    regions = Regions{};
    gt_renderer.reset();
    gt_scene.reset();
    shape.clear();
  }
};

namespace {

// The cell's image as one mosaic of its windows (Renderer::render_windows_components, every window's pixels
// in one parallel loop): per window its camera, the light (a positional light moved with the window) and
// the seed (the first window's is the scene's own); the scene's size is one window's.
std::array<RenderResult, 2> render_mosaic(Scene& sc, const Renderer& r, const StudyView& v,
                                          const std::vector<Window>& windows, const Light& light,
                                          uint32_t seed) {
  sc.settings.width = v.width, sc.settings.height = v.height;
  std::vector<RenderWindow> rw;
  rw.reserve(windows.size());
  for (std::size_t wi = 0; wi < windows.size(); ++wi) {
    const Window& w = windows[wi];
    RenderWindow x{w.cam, light, seed + 104729u * uint32_t(wi), w.x0, w.y0};
    if (light.type != LightType::Directional) x.light.position = light.position + w.offset;
    rw.push_back(x);
  }
  return r.render_windows_components(rw, v.image_width(), v.image_height());
}

}  // namespace

CellRunner::CellRunner(const StudyPlan& plan, Log log)
    : state_(std::make_unique<State>(plan, std::move(log))) {}
CellRunner::~CellRunner() = default;

const json& CellRunner::preparation_timing() const { return state_->timing; }

// Ground truth: diffuse and specular rendered alone; rounds of independent estimates (new seed), doubling
// the samples, until the floors are met or gt_max_spp. Fills the cell's ground-truth row and ray counts.
GroundTruth CellRunner::State::ground_truth(const StudyCell& cell, CellResult& out) {
  const auto t_light = std::chrono::steady_clock::now();
  const StudyView& view = cell.view;
  const StudyConfig::GtRule rule = cell.sweep ? StudyConfig::GtRule::Bias : cfg.gt_rule;
  const int first_spp = cell.sweep ? cfg.sweep_gt_spp : cfg.gt_spp;
  const int max_spp = cell.sweep ? cfg.sweep_gt_max_spp : cfg.gt_max_spp;
  RenderResult acc[2];
  int spp = 0, rounds = 0;
  GroundTruth G;
  GtFloors floors;
  while (true) {
    const int n = spp == 0 ? first_spp : spp;
    gt_scene->settings.spp = n;
    // Diffuse and specular from one pass (each bit-identical to its own render), all windows at once. Both
    // carry the pass's rays: counted once (on the diffuse).
    std::array<RenderResult, 2> res = render_mosaic(*gt_scene, *gt_renderer, view, windows, cell.light.light,
                                                    cfg.seed + 7919u * uint32_t(rounds));
    res[1].stats = RenderStats{};
    for (int ci = 0; ci < 2; ++ci) {
      if (spp == 0)
        acc[ci] = std::move(res[ci]);
      else
        merge(acc[ci], spp, res[ci], n);
    }
    spp += n, ++rounds;
    ComponentImages gi;
    for (int ci = 0; ci < 2; ++ci) gi.img[ci + 1] = acc[ci].mean, gi.se[ci + 1] = acc[ci].std_error;
    add_total(gi);
    G = make_ground_truth(std::move(gi));
    floors = check_floors(cfg, rule, G.lum, G.lum_se, regions);
    if (floors.met || spp * 2 > max_spp) break;
  }
  out.ground_truth_seconds = secs_since(t_light);
  for (int ci = 0; ci < 2; ++ci) {
    out.ground_truth_rays += acc[ci].stats.camera_rays + acc[ci].stats.shadow_rays;
    out.ground_truth_ray_seconds += acc[ci].stats.seconds;
  }
  out.ground_truth = cell_keys(cell, plan.materials[cell.material].name);
  out.ground_truth.update({{"windows", view.windows},
                           {"grid", cell.sweep ? "sweep" : "main"},
                           {"image", {view.image_width(), view.image_height()}},
                           {"spp", spp},
                           {"rounds", rounds},
                           {"rule", rule == StudyConfig::GtRule::Bias ? "bias" : "full"},
                           {"floors_met", floors.met},
                           {"components", floors.j},
                           {"camera_rays", acc[0].stats.camera_rays + acc[1].stats.camera_rays},
                           {"shadow_rays", acc[0].stats.shadow_rays + acc[1].stats.shadow_rays}});
  return G;
}

// One term on the coarse set, same camera: its three components (total, diffuse, specular); its CPU time
// into the cell's per-variant account.
ComponentImages CellRunner::State::render_variant(const StudyCell& cell, const StudyVariant& v,
                                                  CellResult& out) {
  const StudyLight& ls = cell.light;
  Scene& sc = coarse[v.roughness == CoarseRoughness::Widened ? 1 : 0];
  const auto [method, form] = split_study_term(v.term);
  sc.settings.micro_shadowing = method;
  // A compact form: its stored level in place of the float channels for this render (swapped back below).
  Texture* swapped = form.empty() ? nullptr : &form_level(form, cell.scale);
  if (swapped)
    for (Material& m : sc.materials) std::swap(m.directional, *swapped);
  sc.settings.ms_smooth_normal = v.smooth_normal;
  sc.settings.area_ms = v.area_ms;
  sc.settings.spp = cfg.method_spp;
  // generic-vndf: vndf_samples per light; evaluated per area sample, they are spread over them.
  sc.settings.vndf_samples = area_sampled(ls.light) && v.area_ms != AreaMs::Representative
                                 ? std::max(1, cfg.vndf_samples / cfg.area_samples)
                                 : cfg.vndf_samples;
  // Diffuse and specular from one pass; with one batch each mean is bit-identical to render() of that
  // component alone (Renderer::render_components_with_error).
  sc.settings.error_batches = 1;
  ComponentImages M;
  const double cpu_v = cpu_seconds();
  const Renderer r(sc);
  {
    std::array<RenderResult, 2> rc = render_mosaic(sc, r, cell.view, windows, ls.light, cfg.seed);
    M.img[1] = std::move(rc[0].mean), M.img[2] = std::move(rc[1].mean);
  }
  if (swapped)
    for (Material& m : sc.materials) std::swap(m.directional, *swapped);
  add_total(M);
  out.variant_cpu_seconds[variant_label(v) + (area_sampled(ls.light) ? " (area light)" : "")] +=
      cpu_seconds() - cpu_v;
  return M;
}

namespace {

// "method/area_ms" → the term's luminance per component under an area light.
using AreaLuminance = std::map<std::string, std::array<Plane, 3>>;

// The representative point's own error: its image against the integrated (or, without one, the per-sample)
// image of the same term, same light samples.
json area_representative_rows(const StudyConfig& cfg, const StudyCell& cell, const std::string& kind,
                              const GroundTruth& G, const Regions& reg, AreaLuminance& area_lum) {
  const StudyLight& ls = cell.light;
  json rows = json::array();
  for (const std::string& t : cfg.area_terms) {
    if (!area_lum.count(t + "/representative")) continue;
    const bool has_int = area_lum.count(t + "/integrated") > 0;
    if (!has_int && !area_lum.count(t + "/sampled")) continue;
    const auto& R = area_lum[t + "/representative"];
    const auto& X = area_lum[t + (has_int ? "/integrated" : "/sampled")];
    for (int ci = 0; ci < 3; ++ci) {
      const Plane zero(R[ci].width, R[ci].height, 0.0);
      const double gm = region_mean(G.lum[ci], G.lum_se[ci], reg.whole).value;
      rows.push_back(
          {{"material", kind},
           {"scale", cell.scale},
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
  return rows;
}

}  // namespace

CellResult CellRunner::run(const StudyCell& cell) {
  State& st = *state_;
  st.prepare(cell);
  const StudyConfig& cfg = st.cfg;
  const std::string& kind = st.plan.materials[cell.material].name;
  const std::string& shape = cell.shape;
  const int k = cell.scale;
  const StudyLight& ls = cell.light;
  const StudyView& view = cell.view;
  CellResult out;
  const GroundTruth G = st.ground_truth(cell, out);
  out.rows = json::array();
  out.images = json::array();
  const bool featured =
      std::find(cfg.featured_lights.begin(), cfg.featured_lights.end(), ls.name) != cfg.featured_lights.end();
  const float exposure = display_exposure(G.lum[0]);
  // The default view keeps the earlier file names; others add the view.
  const bool default_view = view.view == 30 && view.view_azimuth == 270;
  const std::string stem = default_view ? fmt::format("{}_{}_k{}_{}", kind, shape, k, ls.name)
                                        : fmt::format("{}_{}_k{}_v{:g}-az{:g}_{}", kind, shape, k, view.view,
                                                      view.view_azimuth, ls.name);
  auto feature = [&](const std::string& method, const Image& img) {
    const std::string file = "images/" + stem + "_" + method + ".png";
    out.featured.push_back({file, img, exposure, false});
    json e = cell_keys(cell, kind);
    e["method"] = method;
    e["image"] = file;
    if (method != "ground-truth") {
      const std::string diff = "images/" + stem + "_" + method + "_diff.png";
      out.featured.push_back({diff, difference_image(img, G.images.img[0], exposure), 0, true});
      e["diff"] = diff;
    }
    out.images.push_back(e);
  };
  if (featured) feature("ground-truth", G.images.img[0]);

  // Every term on the coarse set, same camera.
  const auto t_m = std::chrono::steady_clock::now();
  AreaLuminance area_lum;
  for (const StudyVariant& v : st.plan.variants_of(cell)) {
    const ComponentImages M = st.render_variant(cell, v, out);
    const std::array<json, 3> measured = measure_variant(M, G, st.regions, cfg.footprint);
    for (int ci = 0; ci < 3; ++ci) {
      json row = cell_keys(cell, kind);
      row.update({{"grid", cell.sweep ? "sweep" : "main"},
                  {"light_type", ls.type},
                  {"elevation", ls.elevation},
                  {"azimuth", ls.azimuth},
                  {"method", v.term},
                  {"ms_normal", v.smooth_normal ? "smooth" : "shading"},
                  {"roughness", v.roughness == CoarseRoughness::Widened ? "widened" : "base"},
                  {"component", kComponentName[ci]}});
      row.update(measured[ci]);
      if (area_section(cfg)) {
        row["area_ms"] = to_string(v.area_ms);
        row["light_radius_deg"] = ls.radius_deg;
        area_lum[v.term + "/" + to_string(v.area_ms)][ci] = luminance(M.img[ci]);
      }
      out.rows.push_back(std::move(row));
    }
    if (featured && !v.smooth_normal && v.roughness == CoarseRoughness::Base) feature(v.term, M.img[0]);
  }
  out.area_representative = area_representative_rows(cfg, cell, kind, G, st.regions, area_lum);
  out.methods_seconds = secs_since(t_m);
  scrub(out.ground_truth);
  scrub(out.rows);
  scrub(out.area_representative);
  return out;
}

CellResult run_cell(const StudyPlan& plan, const StudyCell& cell, const Log& log) {
  CellRunner runner(plan, log);
  return runner.run(cell);
}

void write_featured_images(const CellResult& cell, const std::filesystem::path& out_dir) {
  for (const FeaturedImage& f : cell.featured)
    if (f.display)
      write_png_display(out_dir / f.file, f.image);
    else
      write_png(out_dir / f.file, f.image, f.exposure);
}

}  // namespace msh::study
