// Ray–shape intersection: analytic planes and spheres, the ground truth's height-field DDA and Embree meshes.
#include <cmath>

#include "renderer_impl.h"

namespace msh::render {

// Closest hit along o + t d, t ∈ (tmin, tmax).
bool Renderer::Impl::intersect(const Vec3f& o, const Vec3f& d, float tmin, float tmax, Hit& h) const {
  h.t = tmax;
  bool found = false;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& ob = scene.objects[i];
    if (obj_gt_mesh[i] >= 0) continue;  // traced by Embree
    if (ob.type == ShapeType::Plane) {
      if (obj_hf[i] >= 0) {
        const PlaneHF& p = hfs[obj_hf[i]];
        float t;
        Vec3f ng;
        if (p.hf.intersect(p.to_grid_p(o), p.to_grid_d(d), tmin, h.t, p.lo, p.hi, &t, &ng)) {
          h.t = t, h.obj = int(i), h.heightfield = h.gt = true, found = true;
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
      h.t = t, h.obj = int(i), h.heightfield = h.gt = false, found = true;
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
      h.t = t, h.obj = int(i), h.heightfield = h.gt = false, found = true;
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
      h.gt = obj_gt_mesh[h.obj] >= 0;
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
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& ob = scene.objects[i];
    if (obj_gt_mesh[i] >= 0) continue;  // traced by Embree
    if (ob.type == ShapeType::Plane) {
      if (obj_hf[i] >= 0) {
        const PlaneHF& p = hfs[obj_hf[i]];
        float t;
        if (p.hf.intersect(p.to_grid_p(o), p.to_grid_d(d), tmin, tmax, p.lo, p.hi, &t, nullptr)) return true;
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

}  // namespace msh::render
