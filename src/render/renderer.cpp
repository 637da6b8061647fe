// The reference renderer (see render/renderer.h).
#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <microshadow/bsdf/diffuse.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/io/error.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>
#include <microshadow/render/heightfield.h>
#include <microshadow/render/renderer.h>
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>

#include "shading_terms.h"

namespace msh::render {

namespace {
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Hit {
  float t = kInf;
  int obj = -1;
  Vec3f p, ng, ns;  // geometric normal (facing the incoming ray), interpolated normal (same side)
  Vec3f tangent{1, 0, 0};
  float tangent_sign = 1;
  Vec2f uv;
  int prim = -1;
  Vec3f bary;  // mesh barycentrics (w0, w1, w2)
  bool heightfield = false;
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

uint32_t pixel_seed(uint32_t seed, int x, int y) {
  return hash_combine(hash_combine(hash_u32(seed), uint32_t(x)), uint32_t(y));
}

}  // namespace

// Shading goes through the library's BRDF code: bsdf::microfacet_specular (RTR4 9.34 with the GGX NDF and the
// height-correlated Smith G2, 9.41 + 9.31), bsdf::fresnel_schlick (9.16) and bsdf::diffuse_lambert (9.61).
Rgbf brdf_cos(const ShadePoint& sp, const Vec3f& wo, const Vec3f& wi, float spec_scale, bool diffuse,
              bool specular) {
  const Vec3f& n = sp.n_shading;
  const float nl = dot(n, wi);
  if (!(nl > 0)) return Rgbf(0.0f);
  const Framef fr = Framef::from_z(n);
  const Vec3f li = fr.to_local(wi), lo_raw = fr.to_local(wo);
  // A normal-mapped normal can face away from the viewer: clamp N·V (the view stays just above the horizon).
  const Vec3f lo(lo_raw.x, lo_raw.y, std::max(lo_raw.z, 1e-4f));
  const Vec3f h = normalize(wi + wo, n);
  const Rgbf f0 = lerp(sp.metallic, Rgbf(0.04f * sp.specular), sp.base_color);
  // specular < 1 also fades the Fresnel rise (specular 0: no Fresnel at all, for closed-form Lambert tests).
  const Rgbf F = lerp(std::min(1.0f, sp.specular), f0, bsdf::fresnel_schlick(f0, saturate(dot(wo, h))));
  Rgbf out(0.0f);
  if (specular) {
    const GGX<float> ggx(roughness_to_alpha(std::max(sp.roughness, 0.02f)));
    const bsdf::SpecularEval<float> e = bsdf::microfacet_specular(ggx, lo, li);
    out += F * (e.f1 * nl * spec_scale);
  }
  if (diffuse)
    out += (Rgbf(1.0f) - F) * bsdf::diffuse_lambert(sp.base_color * (1.0f - sp.metallic), li, lo) * nl;
  return out;
}

struct Renderer::Impl {
  const Scene& scene;
  RTCDevice device = nullptr;
  RTCScene rtc = nullptr;
  std::vector<int> geom_to_obj;
  std::vector<PlaneHF> hfs;
  std::vector<int> obj_hf;  // object → index in hfs or −1
  MicroShadowingTerm ms;
  BumpTerminatorTerm bt;

  explicit Impl(const Scene& s) : scene(s), ms(s.settings), bt(s.settings.bump_terminator) {
    obj_hf.assign(s.objects.size(), -1);
    bool any_mesh = false;
    for (const auto& o : s.objects) any_mesh |= o.type == ShapeType::Mesh;
    if (any_mesh) {
      device = rtcNewDevice(nullptr);
      if (!device) throw std::runtime_error("Embree: cannot create a device");
      rtc = rtcNewScene(device);
      rtcSetSceneBuildQuality(rtc, RTC_BUILD_QUALITY_HIGH);
      for (std::size_t i = 0; i < s.objects.size(); ++i) {
        const Object& o = s.objects[i];
        if (o.type != ShapeType::Mesh) continue;
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), o.mesh->p.size()));
        for (std::size_t k = 0; k < o.mesh->p.size(); ++k)
          vb[3 * k] = o.mesh->p[k].x, vb[3 * k + 1] = o.mesh->p[k].y, vb[3 * k + 2] = o.mesh->p[k].z;
        auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), o.mesh->tri.size()));
        for (std::size_t k = 0; k < o.mesh->tri.size(); ++k)
          for (int c = 0; c < 3; ++c) ib[3 * k + c] = o.mesh->tri[k][c];
        rtcCommitGeometry(g);
        const unsigned id = rtcAttachGeometry(rtc, g);
        rtcReleaseGeometry(g);
        if (geom_to_obj.size() <= id) geom_to_obj.resize(id + 1, -1);
        geom_to_obj[id] = int(i);
      }
      rtcCommitScene(rtc);
    }
    if (s.settings.micro_shadowing == MicroShadowing::GroundTruth) {
      for (std::size_t i = 0; i < s.objects.size(); ++i) {
        const Object& o = s.objects[i];
        const Material& m = s.materials[o.material];
        if (o.type != ShapeType::Plane || m.height.empty()) continue;
        PlaneHF p;
        p.obj = int(i);
        p.T = o.tangent, p.N = o.normal, p.B = cross(o.normal, o.tangent), p.c = o.center,
        p.half = o.half_size;
        const float tu = 2 * o.half_size.x / (m.uv_scale * float(m.height.width()));
        const float tv = 2 * o.half_size.y / (m.uv_scale * float(m.height.height()));
        if (std::abs(tu - tv) > 0.01f * tu)
          throw InputError(fmt::format("{}: ground truth needs square texels on the plane (material '{}')",
                                       s.source.string(), m.name));
        p.texel = tu;
        if (!(m.height_texels > 0))
          throw InputError(
              fmt::format("{}: ground truth: material '{}' has a height map but no height_texels "
                          "(set it in the scene or ship material.json beside the height map)",
                          s.source.string(), m.name));
        p.hf = HeightField(m.height, m.height_texels);
        p.lo = {-0.5f, -0.5f};
        p.hi = {2 * o.half_size.x / tu - 0.5f, 2 * o.half_size.y / tu - 0.5f};
        obj_hf[i] = int(hfs.size());
        hfs.push_back(std::move(p));
      }
      if (hfs.empty())
        throw InputError(fmt::format("{}: ground-truth needs a plane whose material has a 'height' map",
                                     s.source.string()));
    }
  }
  ~Impl() {
    if (rtc) rtcReleaseScene(rtc);
    if (device) rtcReleaseDevice(device);
  }

  // Closest hit along o + t d, t ∈ (tmin, tmax).
  bool intersect(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Hit& h) const {
    h.t = tmax;
    bool found = false;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      const Object& ob = scene.objects[i];
      if (ob.type == ShapeType::Plane) {
        if (obj_hf[i] >= 0) {
          const PlaneHF& p = hfs[obj_hf[i]];
          float t;
          Vec3f ng;
          if (p.hf.intersect(p.to_grid_p(o), p.to_grid_d(d), tmin, h.t, p.lo, p.hi, &t, &ng)) {
            h.t = t, h.obj = int(i), h.heightfield = true, found = true;
            h.ng = normalize(p.to_world_d(ng));
          }
          continue;
        }
        const float dn = dot(d, ob.normal);
        if (std::abs(dn) < 1e-12f) continue;
        const float t = dot(ob.center - o, ob.normal) / dn;
        if (!(t > tmin && t < h.t)) continue;
        const Vec3f q = o + d * t - ob.center;
        const Vec3f B = cross(ob.normal, ob.tangent);
        const float s = dot(q, ob.tangent), r = dot(q, B);
        if (std::abs(s) > ob.half_size.x || std::abs(r) > ob.half_size.y) continue;
        h.t = t, h.obj = int(i), h.heightfield = false, found = true;
        h.ng = h.ns = ob.normal;
        h.tangent = ob.tangent, h.tangent_sign = 1;
        h.uv = {(s + ob.half_size.x) / (2 * ob.half_size.x), (r + ob.half_size.y) / (2 * ob.half_size.y)};
      } else if (ob.type == ShapeType::Sphere) {
        const Vec3f oc = o - ob.center;
        const float a = dot(d, d), b = dot(oc, d), c = dot(oc, oc) - ob.radius * ob.radius;
        const float disc = b * b - a * c;
        if (disc < 0) continue;
        const float sq = std::sqrt(disc);
        float t = (-b - sq) / a;
        if (!(t > tmin)) t = (-b + sq) / a;
        if (!(t > tmin && t < h.t)) continue;
        h.t = t, h.obj = int(i), h.heightfield = false, found = true;
      }
    }
    if (rtc) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      RTCRayHit rh{};
      rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
      rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
      rh.ray.tnear = tmin, rh.ray.tfar = h.t, rh.ray.mask = 0xFFFFFFFFu, rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(rtc, &ctx, &rh);
      if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID && rh.ray.tfar < h.t) {
        h.t = rh.ray.tfar, h.obj = geom_to_obj[rh.hit.geomID], h.prim = int(rh.hit.primID), found = true;
        h.heightfield = false;
        h.bary = {1 - rh.hit.u - rh.hit.v, rh.hit.u, rh.hit.v};
      }
    }
    if (!found) return false;
    h.p = o + d * h.t;
    const Object& ob = scene.objects[h.obj];
    if (ob.type == ShapeType::Sphere) {
      const Vec3f n = normalize(h.p - ob.center);
      h.ng = h.ns = n;
      const float phi = std::atan2(n.y, n.x), theta = safe_acos(n.z);
      h.uv = {(phi < 0 ? phi + 2 * kPi<float> : phi) / (2 * kPi<float>), theta / kPi<float>};
      h.tangent =
          normalize(Vec3f(-n.y, n.x, 0.0f), Vec3f(1, 0, 0));  // ∂P/∂u (east); bitangent = ∂P/∂v (south)
      h.tangent_sign =
          dot(cross(n, h.tangent), Vec3f(n.z * n.x, n.z * n.y, -(n.x * n.x + n.y * n.y))) < 0 ? -1 : 1;
    } else if (ob.type == ShapeType::Mesh) {
      const Mesh& m = *ob.mesh;
      const auto& tr = m.tri[h.prim];
      const Vec3f& w = h.bary;
      h.ng = normalize(cross(m.p[tr[1]] - m.p[tr[0]], m.p[tr[2]] - m.p[tr[0]]));
      h.ns = normalize(m.n[tr[0]] * w.x + m.n[tr[1]] * w.y + m.n[tr[2]] * w.z, h.ng);
      if (dot(h.ng, h.ns) < 0) h.ng = -h.ng;
      h.uv = {m.uv[tr[0]].x * w.x + m.uv[tr[1]].x * w.y + m.uv[tr[2]].x * w.z,
              m.uv[tr[0]].y * w.x + m.uv[tr[1]].y * w.y + m.uv[tr[2]].y * w.z};
      Vec3f t(0, 0, 0);
      for (int k = 0; k < 3; ++k)
        t += Vec3f(m.tangent[tr[k]][0], m.tangent[tr[k]][1], m.tangent[tr[k]][2]) * w[k];
      h.tangent = t;
      h.tangent_sign = m.tangent[tr[0]][3];
    } else if (h.heightfield) {
      // The ground truth shades the piecewise-linear surface it traces: the facet normal is the shading
      // normal, the normal of the light test and the normal of the shadow-ray policy (docs/renderer.md).
      const PlaneHF& p = hfs[obj_hf[h.obj]];
      const Vec3f g = p.to_grid_p(h.p);
      h.ns = h.ng;
      h.tangent = p.T, h.tangent_sign = 1;
      const Material& mat = scene.materials[ob.material];
      h.uv = {(g.x + 0.5f) / (float(p.hf.width()) * mat.uv_scale),
              (g.y + 0.5f) / (float(p.hf.height()) * mat.uv_scale)};
    }
    // Face the incoming ray.
    if (dot(h.ng, d) > 0) h.ng = -h.ng, h.ns = -h.ns;
    return true;
  }

  // Any hit along o + t d, t ∈ (tmin, tmax).
  bool occluded(const Vec3f& o, const Vec3f& d, float tmin, float tmax) const {
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      const Object& ob = scene.objects[i];
      if (ob.type == ShapeType::Plane) {
        if (obj_hf[i] >= 0) {
          const PlaneHF& p = hfs[obj_hf[i]];
          float t;
          if (p.hf.intersect(p.to_grid_p(o), p.to_grid_d(d), tmin, tmax, p.lo, p.hi, &t, nullptr))
            return true;
          continue;
        }
        const float dn = dot(d, ob.normal);
        if (std::abs(dn) < 1e-12f) continue;
        const float t = dot(ob.center - o, ob.normal) / dn;
        if (!(t > tmin && t < tmax)) continue;
        const Vec3f q = o + d * t - ob.center;
        if (std::abs(dot(q, ob.tangent)) <= ob.half_size.x &&
            std::abs(dot(q, cross(ob.normal, ob.tangent))) <= ob.half_size.y)
          return true;
      } else if (ob.type == ShapeType::Sphere) {
        const Vec3f oc = o - ob.center;
        const float a = dot(d, d), b = dot(oc, d), c = dot(oc, oc) - ob.radius * ob.radius;
        const float disc = b * b - a * c;
        if (disc < 0) continue;
        const float sq = std::sqrt(disc);
        const float t0 = (-b - sq) / a, t1 = (-b + sq) / a;
        if ((t0 > tmin && t0 < tmax) || (t1 > tmin && t1 < tmax)) return true;
      }
    }
    if (rtc) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      RTCRay r{};
      r.org_x = o.x, r.org_y = o.y, r.org_z = o.z, r.dir_x = d.x, r.dir_y = d.y, r.dir_z = d.z;
      r.tnear = tmin, r.tfar = tmax, r.mask = 0xFFFFFFFFu, r.flags = 0;
      rtcOccluded1(rtc, &ctx, &r);
      if (r.tfar < 0) return true;
    }
    return false;
  }

  Rgbf shade(const Hit& h, const Vec3f& wo, uint32_t seed, RenderStats& st) const {
    const Object& ob = scene.objects[h.obj];
    const Material& m = scene.materials[ob.material];
    const Settings& set = scene.settings;
    const float u = h.uv.x * m.uv_scale, v = h.uv.y * m.uv_scale;
    ShadePoint sp;
    sp.base_color = m.base_color.sample_rgb(u, v);
    sp.roughness = saturate(m.roughness.sample(u, v));
    sp.metallic = saturate(m.metallic.sample(u, v));
    sp.specular = m.specular;
    sp.n_geometric = h.ng;
    sp.n_smooth = h.ns;
    sp.n_shading = h.ns;
    sp.visibility = 1.0f;
    if (!h.heightfield) {
      sp.visibility = saturate(m.visibility.sample(u, v));
      if (!m.normal.empty()) {
        const Framef fr = Framef::from_zx(h.ns, h.tangent);
        const Vec3f bt = fr.t * h.tangent_sign;
        const Vec3f tn(m.normal_strength * (2 * m.normal.sample(u, v, 0) - 1),
                       m.normal_strength * (2 * m.normal.sample(u, v, 1) - 1),
                       2 * m.normal.sample(u, v, 2) - 1);
        sp.n_shading = normalize(fr.s * tn.x + bt * tn.y + h.ns * tn.z, h.ns);
      }
    }
    ++st.shaded_samples;
    const bool want_d = set.component != Component::Specular, want_s = set.component != Component::Diffuse;
    Rgbf L = want_d ? set.ambient * sp.base_color : Rgbf(0.0f);
    // Shadow-ray origin (policy in docs/renderer.md): analytic shapes and meshes push the hit point (or
    // Hanika's offset point) off the surface along the facet normal by 2e-4 · max(1, |p|∞); the height field
    // starts at the hit point itself, no offset: it counts front faces only and a light must be above the
    // hit facet, so the ray cannot re-hit its own facet.
    Vec3f po = h.p;
    if (set.hanika_offset && ob.type == ShapeType::Mesh) po = hanika_offset(*ob.mesh, h);
    const float eps =
        h.heightfield
            ? 0.0f
            : 2e-4f * std::max(1.0f, std::max(std::abs(h.p.x), std::max(std::abs(h.p.y), std::abs(h.p.z))));
    auto shadow = [&](const Vec3f& wi, float dist) {
      ++st.shadow_rays;
      return occluded(po + h.ng * eps, wi, 0.0f, dist);
    };
    auto term = [&](const Vec3f& wi, uint32_t s) {
      // Light reaching the micro-surface: micro-shadowing (V from the map, N·L and N·V with the shading
      // normal) times the bump-terminator term.
      return ms.eval(sp, wo, wi, h.tangent, s) * bt.eval(sp.n_smooth, sp.n_shading, wi);
    };
    // Meshes leave the geometric-hemisphere test to the shadow ray (so that the Hanika offset can light faces
    // whose flat normal already turned away, as a smooth surface would); other shapes test N_g·L.
    const bool is_mesh = ob.type == ShapeType::Mesh;
    auto above = [&](const Vec3f& wi) { return is_mesh || dot(h.ng, wi) > 0; };
    for (std::size_t li = 0; li < scene.lights.size(); ++li) {
      const Light& light = scene.lights[li];
      const uint32_t ls = hash_combine(seed, uint32_t(li));
      if (light.type == LightType::Directional || light.type == LightType::Point) {
        Vec3f wi = light.direction;
        float dist = kInf;
        Rgbf E = light.color;
        if (light.type == LightType::Point) {
          const Vec3f dl = light.position - h.p;
          dist = length(dl);
          if (!(dist > 0)) continue;
          wi = dl / dist;
          E = E / (dist * dist);
        }
        if (!above(wi) || !(dot(sp.n_shading, wi) > 0)) continue;
        const float k = term(wi, ls);
        if (!(k > 0)) continue;
        if (shadow(wi, dist * (1 - 1e-4f))) continue;
        L += brdf_cos(sp, wo, wi, 1.0f, want_d, want_s) * E * k;
      } else if (!set.area_lights) {
        // Representative point (Karis 2013): diffuse toward the centre, specular toward the point of the
        // sphere closest to the reflection ray, with the (α / α')² energy normalization.
        const Vec3f dl = light.position - h.p;
        const float dist = length(dl);
        if (!(dist > light.radius)) continue;
        const Vec3f wc = dl / dist;
        const Rgbf E = light.color / (dist * dist);
        if (shadow(wc, dist - light.radius)) continue;
        if (want_d && above(wc) && dot(sp.n_shading, wc) > 0)
          L += brdf_cos(sp, wo, wc, 1.0f, true, false) * E * term(wc, ls);
        const Vec3f r = reflect(wo, sp.n_shading);
        const Vec3f to_ray = r * dot(dl, r) - dl;
        const Vec3f cp = dl + to_ray * saturate(light.radius / std::max(length(to_ray), 1e-12f));
        const Vec3f ws = normalize(cp);
        if (want_s && above(ws) && dot(sp.n_shading, ws) > 0) {
          const float a = roughness_to_alpha(std::max(sp.roughness, 0.02f));
          const float a2 = saturate(a + light.radius / (2 * dist));
          L += brdf_cos(sp, wo, ws, sqr(a / a2), false, true) * E * term(ws, ls);
        }
      } else {
        // Reference: uniform sampling of the cone subtended by the sphere; radiance Le = I / (π r²).
        const Vec3f dl = light.position - h.p;
        const float dist = length(dl);
        if (!(dist > light.radius)) continue;
        const float sin2 = sqr(light.radius / dist), cos_max = safe_sqrt(1 - sin2);
        const Framef fr = Framef::from_z(dl / dist);
        const Rgbf Le = light.color / (kPi<float> * sqr(light.radius));
        const float inv_pdf = 2 * kPi<float> * (1 - cos_max);
        Rgbf acc(0.0f);
        for (int k = 0; k < set.area_samples; ++k) {
          const Vec3f wi = fr.to_world(sample_uniform_cone(sobol_2d<float>(uint32_t(k), ls + 1), cos_max));
          if (!above(wi) || !(dot(sp.n_shading, wi) > 0)) continue;
          const float t = term(wi, hash_combine(ls, uint32_t(k)));
          if (!(t > 0)) continue;
          // Distance to the sphere's near surface along wi.
          const float b = dot(dl, wi), c = dot(dl, dl) - sqr(light.radius);
          const float tl = b - safe_sqrt(b * b - c);
          if (shadow(wi, tl * (1 - 1e-4f))) continue;
          acc += brdf_cos(sp, wo, wi, 1.0f, want_d, want_s) * Le * (t * inv_pdf);
        }
        L += acc / float(set.area_samples);
      }
    }
    return L;
  }

  // Hanika 2021 (RTG II ch. 4): shadow-ray origin on the smooth surface implied by the vertex normals.
  static Vec3f hanika_offset(const Mesh& m, const Hit& h) {
    const auto& tr = m.tri[h.prim];
    return bump::hanika2021_shadow_origin(h.p, std::array<Vec3f, 3>{m.p[tr[0]], m.p[tr[1]], m.p[tr[2]]},
                                          std::array<Vec3f, 3>{m.n[tr[0]], m.n[tr[1]], m.n[tr[2]]},
                                          std::array<float, 3>{h.bary.x, h.bary.y, h.bary.z});
  }

  // Mean of the pixel's spp samples, taken as `batches` independently scrambled Sobol batches of spp/batches
  // samples (batch 0 uses the pixel's own scramble, so batches = 1 is the plain render). With se, stores the
  // standard error of the mean from the spread of the batch means.
  Rgbf pixel(int x, int y, RenderStats& st, int batches = 1, Rgbf* se = nullptr) const {
    const Settings& s = scene.settings;
    const Camera& cam = scene.camera;
    const Vec3f f = normalize(cam.target - cam.eye);
    const Vec3f r = normalize(cross(f, cam.up));
    const Vec3f up = cross(r, f);
    const float th = cam.orthographic ? 0.5f * cam.ortho_height
                                      : std::tan(0.5f * cam.fov_deg * kPi<float> / 180.0f),
                aspect = float(s.width) / float(s.height);
    const uint32_t ps = pixel_seed(s.seed, x, y);
    const int per = s.spp / batches;
    Rgbf sum(0.0f);
    double bm[3] = {0, 0, 0}, bm2[3] = {0, 0, 0};
    for (int b = 0; b < batches; ++b) {
      const uint32_t bs = b == 0 ? ps : hash_combine(ps, 0x5bd1e995u + uint32_t(b));
      Rgbf bsum(0.0f);
      for (int k = 0; k < per; ++k) {
        const int i = b * per + k;
        const Vec2f u = s.spp == 1 ? Vec2f(0.5f, 0.5f) : sobol_2d<float>(uint32_t(k), bs);
        const float px = (2 * (float(x) + u.x) / float(s.width) - 1) * th * aspect;
        const float py = (1 - 2 * (float(y) + u.y) / float(s.height)) * th;
        const Vec3f d = cam.orthographic ? f : normalize(f + r * px + up * py);
        const Vec3f o = cam.orthographic ? cam.eye + r * px + up * py : cam.eye;
        ++st.camera_rays;
        Hit h;
        if (!intersect(o, d, 0.0f, kInf, h)) {
          bsum += s.background;
          continue;
        }
        bsum += shade(h, -d, hash_combine(ps, uint32_t(i)), st);
      }
      sum += bsum;
      for (int c = 0; c < 3; ++c) {
        const double m = double(bsum[c]) / per;
        bm[c] += m, bm2[c] += m * m;
      }
    }
    if (se) {
      float e[3];
      for (int c = 0; c < 3; ++c) {
        const double mean = bm[c] / batches;
        const double var = batches > 1 ? std::max(0.0, bm2[c] - batches * mean * mean) / (batches - 1) : 0.0;
        e[c] = float(std::sqrt(var / batches));
      }
      *se = Rgbf(e[0], e[1], e[2]);
    }
    return sum / float(s.spp);
  }
};

Renderer::Renderer(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}
Renderer::~Renderer() = default;

Rgbf Renderer::render_pixel(int x, int y, RenderStats* stats) const {
  RenderStats st;
  const Rgbf c = impl_->pixel(x, y, st);
  if (stats) *stats = st;
  return c;
}

namespace {
// Runs fn(x, y, stats) over 16×16 tiles in parallel; fills stats and reports progress.
template <class Fn>
void for_each_pixel(const Settings& s, const std::function<void(double)>& progress, RenderStats* stats,
                    Fn&& fn) {
  const auto t0 = std::chrono::steady_clock::now();
  std::atomic<uint64_t> cam{0}, shadow{0}, shaded{0}, done{0};
  constexpr int kTile = 16;
  const uint64_t total = uint64_t(s.width) * s.height;
  tbb::parallel_for(tbb::blocked_range2d<int>(0, s.height, kTile, 0, s.width, kTile), [&](const auto& r) {
    RenderStats st;
    for (int y = r.rows().begin(); y < r.rows().end(); ++y)
      for (int x = r.cols().begin(); x < r.cols().end(); ++x) fn(x, y, st);
    cam += st.camera_rays, shadow += st.shadow_rays, shaded += st.shaded_samples;
    const uint64_t n = done += uint64_t(r.rows().size()) * r.cols().size();
    if (progress) progress(double(n) / double(total));
  });
  if (stats) {
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    stats->camera_rays = cam, stats->shadow_rays = shadow, stats->shaded_samples = shaded;
  }
}
}  // namespace

Image Renderer::render(const std::function<void(double)>& progress, RenderStats* stats) const {
  const Settings& s = impl_->scene.settings;
  Image img(s.width, s.height);
  for_each_pixel(s, progress, stats,
                 [&](int x, int y, RenderStats& st) { img.at(x, y) = impl_->pixel(x, y, st); });
  return img;
}

RenderResult Renderer::render_with_error(const std::function<void(double)>& progress) const {
  const Settings& s = impl_->scene.settings;
  RenderResult res;
  res.batches = std::max(1, std::min(s.error_batches, s.spp));
  if (s.spp % res.batches != 0)
    throw InputError(fmt::format("{}: spp = {} is not a multiple of the {} error batches",
                                 impl_->scene.source.string(), s.spp, res.batches));
  res.mean = Image(s.width, s.height);
  res.std_error = Image(s.width, s.height);
  for_each_pixel(s, progress, &res.stats, [&](int x, int y, RenderStats& st) {
    res.mean.at(x, y) = impl_->pixel(x, y, st, res.batches, &res.std_error.at(x, y));
  });
  return res;
}

}  // namespace msh::render
