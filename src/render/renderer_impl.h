// Private to src/render/: the renderer's implementation, split by concern — scene and Embree set-up
// (scene_setup.cpp), ray-shape intersection through the one Embree scene (shapes.cpp), lights and BRDF
// (integrator.cpp), camera and the tile loop (renderer.cpp).
#pragma once

#include <embree3/rtcore.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/renderer.h>

#include <array>
#include <limits>
#include <memory>
#include <vector>

#include "shading_terms.h"

namespace msh::render {
namespace tracing {
inline constexpr float kInf = std::numeric_limits<float>::infinity();

struct Hit {
  float t = kInf;
  int obj = -1;
  Vec3f p, ng, ns;  // geometric normal (facing the incoming ray), interpolated normal (same side)
  Vec3f tangent{1, 0, 0};
  float tangent_sign = 1;
  Vec2f uv;
  int prim = -1;
  Vec3f bary;                // mesh barycentrics (w0, w1, w2)
  bool heightfield = false;  // the height-field DDA of a ground-truth plane
  bool gt = false;           // ground-truth micro-geometry (DDA or displaced Embree mesh)
};

// A plane rendered as its height map (ground truth), in the grid space of render/heightfield.h.
struct PlaneHF {
  int obj = -1;
  HeightField hf;
  float texel = 1;  // world size of one texel
  Vec3f T, B, N, c;
  Vec2f half, lo, hi;
  Vec3f to_grid_p(const Vec3f& p) const {
    const Vec3f q = p - c;
    return {(dot(q, T) + half.x) / texel - 0.5f, (dot(q, B) + half.y) / texel - 0.5f, dot(q, N) / texel};
  }
  Vec3f to_grid_d(const Vec3f& d) const { return Vec3f(dot(d, T), dot(d, B), dot(d, N)) / texel; }
  Vec3f to_world_d(const Vec3f& g) const { return T * g.x + B * g.y + N * g.z; }
};

}  // namespace tracing

// Representative directions of an area light seen from p (Karis 2013, "Real Shading in Unreal Engine 4"):
// wc toward the centre (the diffuse lobe's), ws toward the point of the light closest to the reflection ray r
// (the specular lobe's). Sphere: Karis's closest point; disk / rect: Lagarde & de Rousiers 2014.
struct RepresentativeDirs {
  Vec3f wc, ws;
};
RepresentativeDirs representative_dirs(const Light& l, const Vec3f& p, const Vec3f& r);

// One sample of a sphere, disk or rect light from p for the uniform variate u: the direction wi, the distance
// to the emitting surface along it, and 1 / pdf in solid angle. A sphere is sampled uniformly in the cone it
// subtends (pdf 1 / (2π (1 − cos θmax))), a disk or rect uniformly in area (pdf d² / (A cos θ_light)).
// valid = false when the sample sees the back of a one-sided disk or rect.
struct AreaSample {
  Vec3f wi{0, 0, 1};
  float dist = 0, inv_pdf = 0;
  bool valid = false;
};
AreaSample sample_area_light(const Light& l, const Vec3f& p, const Vec2f& u);

struct Renderer::Impl {
  using Hit = tracing::Hit;
  using PlaneHF = tracing::PlaneHF;
  const Scene& scene;
  RTCDevice device = nullptr;
  RTCScene rtc = nullptr;
  std::vector<int> geom_to_obj;
  std::vector<PlaneHF> hfs;
  std::vector<int> obj_hf;                       // object → index in hfs or −1
  std::vector<std::shared_ptr<Mesh>> gt_meshes;  // displaced ground-truth meshes (Embree, front faces only)
  std::vector<int> obj_gt_mesh;                  // object → index in gt_meshes or −1
  // Embree user geometry for the analytic planes and spheres and the height-field planes: one per object,
  // so every shape is found by the one rtcIntersect1 / rtcOccluded1 (Embree user data points here).
  struct UserShape {
    const Impl* impl;
    int obj;
  };
  std::vector<UserShape> user_shapes;
  MicroShadowingTerm ms;
  BumpTerminatorTerm bt;

  explicit Impl(const Scene& s);
  ~Impl();
  // Rejects hits on triangles the ray meets from behind (outward winding of the displaced meshes).
  static void front_face_filter(const RTCFilterFunctionNArguments* args);
  // Embree user-geometry callbacks of the analytic and height-field shapes (shapes.cpp).
  static void user_bounds(const RTCBoundsFunctionArguments* args);
  static void user_intersect(const RTCIntersectFunctionNArguments* args);
  static void user_occluded(const RTCOccludedFunctionNArguments* args);
  // Closest hit of object i (a plane, sphere or height-field plane) along o + t d, t ∈ (tmin, tmax) (the
  // height field: [tmin, tmax)). Stores t and, for a flat plane, its (s, r) offsets along tangent and
  // bitangent; for the height field, the grid-space facet normal.
  bool shape_hit(int i, const Vec3f& o, const Vec3f& d, float tmin, float tmax, float& t, Vec2f& sr,
                 Vec3f& ng) const;
  // Any hit of object i along o + t d, t ∈ (tmin, tmax).
  bool shape_occluded(int i, const Vec3f& o, const Vec3f& d, float tmin, float tmax) const;
  // World-space bounds of object i (a plane, sphere or height-field plane), padded.
  void shape_bounds(int i, RTCBounds& bounds) const;
  void setup_ground_truth(const Scene& s);
  // Closest hit along o + t d, t ∈ (tmin, tmax).
  bool intersect(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Hit& h) const;
  // Any hit along o + t d, t ∈ (tmin, tmax).
  bool occluded(const Vec3f& o, const Vec3f& d, float tmin, float tmax) const;
  // The components one pass renders: out[c] is what a render with Settings::component = comp[c] gives.
  struct Components {
    int n = 1;
    std::array<Component, 2> comp{Component::Total, Component::Total};
  };
  // Direct light from every light at a hit, seen from wo, for Settings::component.
  Rgbf shade(const Hit& h, const Vec3f& wo, uint32_t seed, RenderStats& st) const;
  // The same for each of cs's components from the same shadow rays and terms (out[0 … cs.n)): each bit for
  // bit what shade() gives with Settings::component = that component.
  // light0: replaces the scene's first light (a mosaic window's, Renderer::render_windows_components).
  void shade(const Hit& h, const Vec3f& wo, uint32_t seed, RenderStats& st, const Components& cs, Rgbf* out,
             const Light* light0 = nullptr) const;
  // The material at a hit as the terms read it: base colour, roughness, metallic, the tangent frame, the
  // normal-mapped shading normal, V and the directional channels the method reads (none on the ground truth).
  ShadePoint shade_point(const Hit& h) const;
  // One hit's direct lighting, per kind of light (integrator.cpp): what shade() does for each light.
  class HitLighting;
  // Hanika 2021 (RTG II ch. 4): shadow-ray origin on the smooth surface implied by the vertex normals.
  static Vec3f hanika_offset(const Mesh& m, const Hit& h);
  // Mean of the pixel's spp samples, taken as `batches` independently scrambled Sobol batches of spp/batches
  // samples (batch 0 uses the pixel's own scramble, so batches = 1 is the plain render). With se, stores the
  // standard error of the mean from the spread of the batch means.
  // spp = 0: settings.spp.
  Rgbf pixel(int x, int y, RenderStats& st, int batches = 1, Rgbf* se = nullptr, int spp = 0) const;
  // The same for each of cs's components from the same samples: mean[c] and, with se, se[c].
  // window: its camera, first light and seed replace the scene's.
  void pixel(int x, int y, RenderStats& st, int batches, int spp, const Components& cs, Rgbf* mean, Rgbf* se,
             const RenderWindow* window = nullptr) const;
};

}  // namespace msh::render
