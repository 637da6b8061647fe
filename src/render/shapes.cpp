// Ray–shape intersection through one Embree scene: meshes (and the ground truth's displaced meshes) as
// triangles, analytic planes and spheres and the ground truth's height-field DDA as user geometry.
#include <algorithm>
#include <cmath>

#include "renderer_impl.h"

namespace msh::render {

bool Renderer::Impl::shape_hit(int i, const Vec3f& o, const Vec3f& d, float tmin, float tmax, float& t,
                               Vec2f& sr, Vec3f& ng) const {
  const Object& ob = scene.objects[i];
  if (ob.type == ShapeType::Plane) {
    if (obj_hf[i] >= 0) {
      const PlaneHF& p = hfs[obj_hf[i]];
      return p.hf.intersect(p.to_grid_p(o), p.to_grid_d(d), tmin, tmax, p.lo, p.hi, &t, &ng);
    }
    const float dn = dot(d, ob.normal);
    if (std::abs(dn) < 1e-12f) return false;
    t = dot(ob.center - o, ob.normal) / dn;
    if (!(t > tmin && t < tmax)) return false;
    const Vec3f q = o + d * t - ob.center;
    const Vec3f B = cross(ob.normal, ob.tangent);
    sr = {dot(q, ob.tangent), dot(q, B)};
    return std::abs(sr.x) <= ob.half_size.x && std::abs(sr.y) <= ob.half_size.y;
  }
  const Vec3f oc = o - ob.center;  // sphere
  const float a = dot(d, d), b = dot(oc, d), c = dot(oc, oc) - ob.radius * ob.radius;
  const float disc = b * b - a * c;
  if (disc < 0) return false;
  const float sq = std::sqrt(disc);
  t = (-b - sq) / a;
  if (!(t > tmin)) t = (-b + sq) / a;
  return t > tmin && t < tmax;
}

bool Renderer::Impl::shape_occluded(int i, const Vec3f& o, const Vec3f& d, float tmin, float tmax) const {
  // Any hit in range is the closest one's existence: a sphere's far root is tested when the near one is
  // before tmin, and the near root ≤ the far one.
  float t;
  Vec2f sr;
  Vec3f ng;
  return shape_hit(i, o, d, tmin, tmax, t, sr, ng);
}

void Renderer::Impl::shape_bounds(int i, RTCBounds& bounds) const {
  const Object& ob = scene.objects[i];
  const float inf = tracing::kInf;
  Vec3f lo(inf, inf, inf), hi(-inf, -inf, -inf);
  auto add = [&](const Vec3f& p) {
    lo = Vec3f(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = Vec3f(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
  };
  if (ob.type == ShapeType::Sphere) {
    const Vec3f r(ob.radius, ob.radius, ob.radius);
    add(ob.center - r), add(ob.center + r);
  } else if (obj_hf[i] >= 0) {
    // The DDA's clip box: x, y over the plane's grid extent, z over the height slab (one unit per texel),
    // mapped back to world space.
    const PlaneHF& p = hfs[obj_hf[i]];
    for (float gx : {p.lo.x, p.hi.x})
      for (float gy : {p.lo.y, p.hi.y})
        for (float gz : {p.hf.z_min(), p.hf.z_max()})
          add(p.c + p.to_world_d(Vec3f((gx + 0.5f) * p.texel - p.half.x, (gy + 0.5f) * p.texel - p.half.y,
                                       gz * p.texel)));
  } else {
    const Vec3f B = cross(ob.normal, ob.tangent);
    for (float a : {-1.0f, 1.0f})
      for (float b : {-1.0f, 1.0f})
        add(ob.center + ob.tangent * (a * ob.half_size.x) + B * (b * ob.half_size.y));
  }
  // Padding: the box only culls; a flat plane's box is flat, and the shape tests round differently from
  // Embree's box test.
  const float ext = std::max(
      {1.0f, std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
  const float pad = 1e-3f * ext;
  bounds.lower_x = lo.x - pad, bounds.lower_y = lo.y - pad, bounds.lower_z = lo.z - pad;
  bounds.upper_x = hi.x + pad, bounds.upper_y = hi.y + pad, bounds.upper_z = hi.z + pad;
}

void Renderer::Impl::user_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* u = static_cast<const UserShape*>(args->geometryUserPtr);
  u->impl->shape_bounds(u->obj, *args->bounds_o);
}

void Renderer::Impl::user_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto* u = static_cast<const UserShape*>(args->geometryUserPtr);
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned k = 0; k < args->N; ++k) {
    if (args->valid[k] != -1) continue;
    const Vec3f o(RTCRayN_org_x(ray, args->N, k), RTCRayN_org_y(ray, args->N, k),
                  RTCRayN_org_z(ray, args->N, k));
    const Vec3f d(RTCRayN_dir_x(ray, args->N, k), RTCRayN_dir_y(ray, args->N, k),
                  RTCRayN_dir_z(ray, args->N, k));
    float t;
    Vec2f sr;
    Vec3f ng;
    if (!u->impl->shape_hit(u->obj, o, d, RTCRayN_tnear(ray, args->N, k), RTCRayN_tfar(ray, args->N, k), t,
                            sr, ng))
      continue;
    RTCRayN_tfar(ray, args->N, k) = t;
    RTCHitN_u(hit, args->N, k) = sr.x, RTCHitN_v(hit, args->N, k) = sr.y;
    RTCHitN_Ng_x(hit, args->N, k) = ng.x, RTCHitN_Ng_y(hit, args->N, k) = ng.y;
    RTCHitN_Ng_z(hit, args->N, k) = ng.z;
    RTCHitN_primID(hit, args->N, k) = args->primID;
    RTCHitN_geomID(hit, args->N, k) = args->geomID;
    RTCHitN_instID(hit, args->N, k, 0) = args->context->instID[0];
  }
}

void Renderer::Impl::user_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto* u = static_cast<const UserShape*>(args->geometryUserPtr);
  for (unsigned k = 0; k < args->N; ++k) {
    if (args->valid[k] != -1) continue;
    RTCRayN* ray = args->ray;
    const Vec3f o(RTCRayN_org_x(ray, args->N, k), RTCRayN_org_y(ray, args->N, k),
                  RTCRayN_org_z(ray, args->N, k));
    const Vec3f d(RTCRayN_dir_x(ray, args->N, k), RTCRayN_dir_y(ray, args->N, k),
                  RTCRayN_dir_z(ray, args->N, k));
    if (u->impl->shape_occluded(u->obj, o, d, RTCRayN_tnear(ray, args->N, k), RTCRayN_tfar(ray, args->N, k)))
      RTCRayN_tfar(ray, args->N, k) = -tracing::kInf;
  }
}

// Closest hit along o + t d, t ∈ (tmin, tmax): one Embree query over every shape, then the hit's frame.
bool Renderer::Impl::intersect(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Hit& h) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh{};
  rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
  rh.ray.dir_x = d.x, rh.ray.dir_y = d.y, rh.ray.dir_z = d.z;
  rh.ray.tnear = tmin, rh.ray.tfar = tmax, rh.ray.mask = 0xFFFFFFFFu, rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(rtc, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || !(rh.ray.tfar < tmax)) return false;
  h.t = rh.ray.tfar, h.obj = geom_to_obj[rh.hit.geomID], h.prim = int(rh.hit.primID);
  const Object& ob = scene.objects[h.obj];
  h.gt = obj_gt_mesh[h.obj] >= 0 || obj_hf[h.obj] >= 0;
  h.heightfield = obj_hf[h.obj] >= 0;
  if (ob.type == ShapeType::Mesh || obj_gt_mesh[h.obj] >= 0) {
    h.bary = {1 - rh.hit.u - rh.hit.v, rh.hit.u, rh.hit.v};
  } else if (h.heightfield) {
    h.ng = normalize(hfs[obj_hf[h.obj]].to_world_d(Vec3f(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z)));
  } else if (ob.type == ShapeType::Plane) {
    const float s = rh.hit.u, r = rh.hit.v;
    h.ng = h.ns = ob.normal;
    h.tangent = ob.tangent, h.tangent_sign = 1;
    h.uv = {(s + ob.half_size.x) / (2 * ob.half_size.x), (r + ob.half_size.y) / (2 * ob.half_size.y)};
  }
  h.p = o + d * h.t;
  if (ob.type == ShapeType::Sphere) {
    const Vec3f n = normalize(h.p - ob.center);
    h.ng = h.ns = n;
    const float phi = std::atan2(n.y, n.x), theta = safe_acos(n.z);
    h.uv = {(phi < 0 ? phi + 2 * kPi<float> : phi) / (2 * kPi<float>), theta / kPi<float>};
    h.tangent = normalize(Vec3f(-n.y, n.x, 0.0f), Vec3f(1, 0, 0));  // ∂P/∂u (east); bitangent = ∂P/∂v (south)
    h.tangent_sign =
        dot(cross(n, h.tangent), Vec3f(n.z * n.x, n.z * n.y, -(n.x * n.x + n.y * n.y))) < 0 ? -1 : 1;
  } else if (h.gt && !h.heightfield) {
    // Displaced ground-truth mesh: facet normal for everything, like the height field.
    const Mesh& m = *gt_meshes[obj_gt_mesh[h.obj]];
    const auto& tr = m.tri[h.prim];
    const Vec3f& w = h.bary;
    h.ng = h.ns = normalize(cross(m.p[tr[1]] - m.p[tr[0]], m.p[tr[2]] - m.p[tr[0]]));
    h.uv = {m.uv[tr[0]].x * w.x + m.uv[tr[1]].x * w.y + m.uv[tr[2]].x * w.z,
            m.uv[tr[0]].y * w.x + m.uv[tr[1]].y * w.y + m.uv[tr[2]].y * w.z};
    h.tangent = normalize(m.p[tr[1]] - m.p[tr[0]]), h.tangent_sign = 1;
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
bool Renderer::Impl::occluded(const Vec3f& o, const Vec3f& d, float tmin, float tmax) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r{};
  r.org_x = o.x, r.org_y = o.y, r.org_z = o.z, r.dir_x = d.x, r.dir_y = d.y, r.dir_z = d.z;
  r.tnear = tmin, r.tfar = tmax, r.mask = 0xFFFFFFFFu, r.flags = 0;
  rtcOccluded1(rtc, &ctx, &r);
  return r.tfar < 0;
}

}  // namespace msh::render
