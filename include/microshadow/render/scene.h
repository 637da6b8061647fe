// Scene description for the reference renderer: camera, glTF-style texture-set materials, shapes, lights and
// render settings, as parsed from a scene JSON file (format in docs/renderer.md).
#pragma once

#include <microshadow/math/color.h>
#include <microshadow/math/vec.h>
#include <microshadow/occlusion/bump_terminator.h>

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace msh::render {

// A float texture with 1–4 channels, sampled bilinearly with wrap addressing. Texel (i, j) covers
// u ∈ [i/w, (i+1)/w), its centre at (i + 0.5)/w; row j = 0 is the top of the image (v = 0).
class Texture {
 public:
  Texture() = default;
  Texture(int w, int h, int c) : w_(w), h_(h), c_(c), data_(std::size_t(w) * h * c, 0.0f) {}
  static Texture constant(std::array<float, 4> value, int channels);
  int width() const { return w_; }
  int height() const { return h_; }
  int channels() const { return c_; }
  bool empty() const { return data_.empty(); }
  float& at(int x, int y, int c) { return data_[(std::size_t(y) * w_ + x) * c_ + c]; }
  float at(int x, int y, int c) const { return data_[(std::size_t(y) * w_ + x) * c_ + c]; }
  // Texel with wrap addressing (any integer coordinates).
  float texel(int x, int y, int c) const;
  // Bilinear sample of channel c (channel index clamped to the last one) at (u, v), wrap addressing.
  float sample(float u, float v, int c = 0) const;
  // Channels 0, 1, 2 (each clamped to the last channel) of the bilinear sample at (u, v).
  Rgbf sample_rgb(float u, float v) const;

 private:
  struct Footprint {
    std::array<std::size_t, 4> i;  // data offsets of texels (x0, y0), (x1, y0), (x0, y1), (x1, y1)
    float tx, ty;                  // bilinear weights of x1 and y1
  };
  Footprint footprint(float u, float v) const;
  float filter(const Footprint& f, int c) const;
  int w_ = 0, h_ = 0, c_ = 0;
  std::vector<float> data_;
};

// Reads a PNG or EXR as a texture. PNG colour textures (srgb = true) are decoded from sRGB to linear; data
// textures (normal, roughness, metallic, visibility, height) are read as-is. InputError naming the file.
Texture load_texture(const std::filesystem::path& path, bool srgb);

// glTF-style metallic-roughness material with a micro-occlusion (visibility) map and an optional height map
// (used only by the ground-truth displacement render).
struct Material {
  std::string name;
  Texture base_color;  // linear RGB
  Texture normal;  // tangent space, encoded n·0.5 + 0.5; x = +u (tangent), y = +v (bitangent); empty = flat
  Texture roughness;  // perceptual roughness r (α = r²)
  Texture metallic;   // 0 = dielectric (F0 = 0.04), 1 = metal (F0 = base colour)
  Texture
      visibility;  // micro-occlusion V ∈ [0,1] (projected-solid-angle visibility, docs/micro-shadowing.md)
  Texture height;  // [0,1]; empty = no displacement
  // Directional micro-occlusion channels (occlusion/directional.h; tangent space of the normal map), sampled
  // bilinearly (they are linear); empty = none (the methods that need them refuse the scene).
  Texture directional;
  // The fine normals' slope covariance (Σ_xx, Σ_xy, Σ_yy; render::slope_covariance), what the
  // `directional-view-masked` method reads; zero: that method takes the unclamped view correction.
  std::array<float, 3> slope_covariance{};
  float height_texels = 0.0f;    // depth of the full height range in texel units (ground truth only)
  float uv_scale = 1.0f;         // texture repeats per unit of the object's uv
  float specular = 1.0f;         // dielectric F0 = 0.04 · specular (0 = pure Lambert, for closed-form tests)
  float normal_strength = 1.0f;  // scales the tangent-space x, y of the normal map (bump-terminator figures)
};

// A triangle mesh with per-vertex attributes; tangents follow the MikkTSpace convention (xyz = ∂P/∂u
// orthogonalised against n, w = ±1 with bitangent = w · cross(n, t) pointing along ∂P/∂v).
struct Mesh {
  std::vector<Vec3f> p, n;
  std::vector<Vec2f> uv;
  std::vector<std::array<float, 4>> tangent;
  std::vector<std::array<uint32_t, 3>> tri;
};

// Per-vertex tangents (MikkTSpace convention): per-triangle ∂P/∂u, ∂P/∂v from uv differences, accumulated per
// vertex weighted by the corner angle, Gram-Schmidt against the vertex normal, handedness from ∂P/∂v.
void compute_tangents(Mesh& m);
// Generators: UV sphere (smooth normals, `segments` around, `rings` pole to pole) and a capped-free cylinder
// along +z (radius, height, smooth side normals), both centred at the origin.
Mesh make_uv_sphere(float radius, int segments, int rings);
Mesh make_cylinder(float radius, float height, int segments);
// Wavefront OBJ (v, vt, vn, f; polygons fan-triangulated; negative indices). InputError naming file and line.
Mesh load_obj(const std::filesystem::path& path);

enum class ShapeType { Plane, Sphere, Mesh };

struct Object {
  ShapeType type = ShapeType::Plane;
  int material = 0;
  // Plane: centre, unit normal, unit tangent (+u), half extents along tangent and bitangent. uv ∈ [0,1]².
  Vec3f center{0, 0, 0}, normal{0, 0, 1}, tangent{1, 0, 0};
  Vec2f half_size{1, 1};
  // Sphere: centre, radius; uv = (φ/2π, θ/π) with θ from +z.
  float radius = 1.0f;
  // Mesh (world space after the object's transform).
  std::shared_ptr<Mesh> mesh;
  // A `cylinder` mesh keeps its parameters, so that the ground truth can displace it by its height map.
  bool cylinder = false;
  float cyl_radius = 1.0f, cyl_height = 2.0f, cyl_rotate_z = 0.0f;  // rotation about z in radians
};

enum class LightType { Directional, Point, Sphere, Disk, Rect };

struct Light {
  LightType type = LightType::Directional;
  Vec3f direction{0, 0, 1};  // directional: unit vector towards the light
  Vec3f position{0, 0, 0};   // point / sphere / disk / rect: centre
  float radius = 0.0f;       // sphere / disk
  // Disk / rect: one-sided emitters lighting the half-space in front of `normal` (unit); a rect spans
  // ±half_size.x along `tangent` (unit, orthogonal to normal) and ±half_size.y along normal × tangent.
  Vec3f normal{0, 0, -1}, tangent{1, 0, 0};
  Vec2f half_size{0.5f, 0.5f};
  // Directional: irradiance at normal incidence; point / sphere: intensity (W/sr; a sphere's radiance is
  // I / (π r²)); disk / rect: intensity along the normal (W/sr; radiance I / area, Lambertian emitter).
  Rgbf color{1, 1, 1};
};
// Area of a disk or rect light's emitting face (0 for other types).
float light_area(const Light& l);

struct Camera {
  Vec3f eye{0, -4, 2}, target{0, 0, 0}, up{0, 0, 1};
  float fov_deg = 40.0f;  // vertical field of view (perspective)
  // Orthographic: parallel rays along target − eye from a view rectangle ortho_height high (world units)
  // centred on the eye, so every pixel covers the same footprint on a plane facing the camera.
  bool orthographic = false;
  float ortho_height = 2.0f;
};

// The micro-shadowing of a render: a method of the runtime registry by name
// (occlusion/runtime/micro_shadowing_methods.h: one term on both lobes, or a named diffuse + specular pair),
// or kGroundTruth: the height map rendered as real ray-traced micro-geometry, no normal or visibility map.
inline constexpr const char* kGroundTruth = "ground-truth";
// The name itself when it is a registry method or kGroundTruth; otherwise InputError listing the valid names
// (and the new name of a renamed one).
std::string micro_shadowing_from_string(const std::string& s);
// Every registry method, then kGroundTruth.
std::vector<std::string> micro_shadowing_names();

// Which part of the BRDF is rendered: the full BRDF, only the (1 − F)-weighted Lambert lobe, or only the
// GGX specular lobe. Every light, every micro-shadowing term and the ground truth honour it; the constant
// ambient counts as diffuse.
enum class Component { Total, Diffuse, Specular };
const char* to_string(Component c);
Component component_from_string(const std::string& s);  // InputError listing total, diffuse, specular

// The bump-terminator method: the bump-terminator registry's (occlusion/bump_terminator.h, bump::kMethods;
// names none, conty-2019, chiang-2019).
using BumpTerminator = bump::Method;

// Micro-shadowing under an area light (an area-sampled sphere, disk or rect; docs/renderer.md):
//  Sampled        — the term evaluated per light sample (the estimator of ∫ M f cos L dω);
//  Representative — the term evaluated once, at the representative point's direction (Karis 2013: the
//                   centre for the diffuse lobe, the point of the light closest to the reflection ray for
//                   the specular lobe), multiplying the area-sampled diffuse and specular;
//  Integrated     — the term averaged over the light's solid angle, weighted by the receiver (Lambert for
//                   the diffuse lobe, GGX for the specular), by deterministic quadrature, multiplying the
//                   area-sampled diffuse and specular.
enum class AreaMs { Sampled, Representative, Integrated };
const char* to_string(AreaMs a);
AreaMs area_ms_from_string(const std::string& s);  // InputError listing sampled, representative, integrated
const char* to_string(BumpTerminator b);           // the registry's name
BumpTerminator bump_terminator_from_string(const std::string& s);  // InputError listing the registry's names

// Intersector of the ground truth's displaced planes: the height-field DDA (render/heightfield.h) or Embree
// on the same triangles (displaced cylinders always use Embree).
enum class GtIntersector { HeightField, Embree };

struct Settings {
  int width = 512, height = 512, spp = 4;
  Component component = Component::Total;
  // Renderer::render_with_error: the spp samples of a pixel are split into this many independently scrambled
  // Sobol batches (spp must be a multiple of min(error_batches, spp)); the spread of the batch means gives
  // the standard error. 1 reproduces render() bit for bit (and gives no error estimate).
  int error_batches = 8;
  std::string micro_shadowing = "none";  // micro_shadowing_from_string's names
  int vndf_samples = 32;                 // samples per light of the methods with a Sobol estimator
  // Normal for the micro-shadowing term's N·L and N·V: false = the shading (normal-mapped) normal, as the
  // shaders of Zurita 2026 do; true = the unperturbed (interpolated) normal, the frame the micro-occlusion
  // bake's cone uses.
  bool ms_smooth_normal = false;
  BumpTerminator bump_terminator = BumpTerminator::kNone;
  bool hanika_offset = false;
  GtIntersector gt_intersector = GtIntersector::HeightField;
  // Sphere lights: true = area sampling (reference), false = representative point. Disk and rect lights are
  // always area-sampled.
  bool area_lights = false;
  int area_samples = 16;
  AreaMs area_ms = AreaMs::Sampled;  // micro-shadowing under area-sampled lights (see AreaMs)
  float exposure = 0.0f;
  Rgbf background{0, 0, 0};
  Rgbf ambient{0, 0, 0};  // constant ambient radiance times base colour (unshadowed; 0 in comparisons)
  std::string
      lut_path;  // micro-shadowing LUT file of the LUT methods (empty: the LUT module's default table)
  uint32_t seed = 1;
  bool ground_truth() const { return micro_shadowing == kGroundTruth; }
};

struct Scene {
  Camera camera;
  std::vector<Material> materials;
  std::vector<Object> objects;
  std::vector<Light> lights;
  Settings settings;
  std::filesystem::path source;  // the JSON file, for messages
};

// Parses a scene JSON file. Relative texture/OBJ paths resolve against `asset_dir` (default: the JSON file's
// directory). Unknown keys, wrong types, unknown names, missing files and absurd values throw InputError
// naming the file and the offending key.
Scene load_scene(const std::filesystem::path& path, const std::filesystem::path& asset_dir = {});
Scene parse_scene(const std::string& json_text, const std::filesystem::path& source_name,
                  const std::filesystem::path& asset_dir);

// Directional light direction from elevation above the z = 0 plane and azimuth from +x (degrees).
Vec3f direction_from_angles(float elevation_deg, float azimuth_deg);

}  // namespace msh::render
