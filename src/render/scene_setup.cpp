// Renderer set-up: the ground truth's displaced geometry and the Embree scene (see renderer_impl.h).
#include <fmt/format.h>
#include <microshadow/io/error.h>

#include <cmath>
#include <stdexcept>

#include "displaced.h"
#include "renderer_impl.h"

namespace msh::render {

Renderer::Impl::Impl(const Scene& s) : scene(s), ms(s.settings), bt(s.settings.bump_terminator) {
  obj_hf.assign(s.objects.size(), -1);
  obj_gt_mesh.assign(s.objects.size(), -1);
  if (s.settings.ground_truth()) setup_ground_truth(s);
  if (const int need = ms.texel_channels(); need > 0)
    for (const Material& m : s.materials)
      if (m.directional.channels() < need)
        throw InputError(
            fmt::format("micro-shadowing method '{}' needs the {} directional micro-occlusion "
                        "channels per texel; material '{}' has {} (gen-material bakes them)",
                        s.settings.micro_shadowing, need, m.name, m.directional.channels()));
  // One Embree scene holds every shape: meshes as triangles, analytic planes and spheres and the
  // height-field planes as user geometry (one primitive each), geometry ids in object order.
  device = rtcNewDevice(nullptr);
  if (!device) throw std::runtime_error("Embree: cannot create a device");
  rtc = rtcNewScene(device);
  rtcSetSceneBuildQuality(rtc, RTC_BUILD_QUALITY_HIGH);
  user_shapes.reserve(s.objects.size());  // stable addresses: Embree keeps pointers into it
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const Object& o = s.objects[i];
    const bool gt = obj_gt_mesh[i] >= 0;
    RTCGeometry g;
    if (o.type == ShapeType::Mesh || gt) {
      const Mesh& mesh = gt ? *gt_meshes[obj_gt_mesh[i]] : *o.mesh;
      g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                             3 * sizeof(float), mesh.p.size()));
      for (std::size_t k = 0; k < mesh.p.size(); ++k)
        vb[3 * k] = mesh.p[k].x, vb[3 * k + 1] = mesh.p[k].y, vb[3 * k + 2] = mesh.p[k].z;
      auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                3 * sizeof(unsigned), mesh.tri.size()));
      for (std::size_t k = 0; k < mesh.tri.size(); ++k)
        for (int c = 0; c < 3; ++c) ib[3 * k + c] = mesh.tri[k][c];
      if (gt) {
        // Ground-truth micro-geometry counts front faces only, like the height-field DDA (shadow-ray
        // policy).
        rtcSetGeometryUserData(g, const_cast<Mesh*>(&mesh));
        rtcSetGeometryIntersectFilterFunction(g, front_face_filter);
        rtcSetGeometryOccludedFilterFunction(g, front_face_filter);
      }
    } else {
      g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
      user_shapes.push_back({this, int(i)});
      rtcSetGeometryUserPrimitiveCount(g, 1);
      rtcSetGeometryUserData(g, &user_shapes.back());
      rtcSetGeometryBoundsFunction(g, user_bounds, nullptr);
      rtcSetGeometryIntersectFunction(g, user_intersect);
      rtcSetGeometryOccludedFunction(g, user_occluded);
    }
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(rtc, g);
    rtcReleaseGeometry(g);
    if (geom_to_obj.size() <= id) geom_to_obj.resize(id + 1, -1);
    geom_to_obj[id] = int(i);
  }
  rtcCommitScene(rtc);
}

Renderer::Impl::~Impl() {
  if (rtc) rtcReleaseScene(rtc);
  if (device) rtcReleaseDevice(device);
}

// Rejects hits on triangles the ray meets from behind (outward winding of the displaced meshes).
void Renderer::Impl::front_face_filter(const RTCFilterFunctionNArguments* args) {
  const auto* m = static_cast<const Mesh*>(args->geometryUserPtr);
  for (unsigned k = 0; k < args->N; ++k) {
    if (args->valid[k] != -1) continue;
    const auto& t = m->tri[RTCHitN_primID(args->hit, args->N, k)];
    const Vec3f n = cross(m->p[t[1]] - m->p[t[0]], m->p[t[2]] - m->p[t[0]]);
    const Vec3f d(RTCRayN_dir_x(args->ray, args->N, k), RTCRayN_dir_y(args->ray, args->N, k),
                  RTCRayN_dir_z(args->ray, args->N, k));
    if (!(dot(n, d) < 0)) args->valid[k] = 0;
  }
}

void Renderer::Impl::setup_ground_truth(const Scene& s) {
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    const Object& o = s.objects[i];
    const Material& m = s.materials[o.material];
    if (m.height.empty()) continue;
    if (o.type == ShapeType::Mesh && o.cylinder) {
      obj_gt_mesh[i] = int(gt_meshes.size());
      gt_meshes.push_back(std::make_shared<Mesh>(displaced_cylinder_mesh(o, m, s.source.string())));
      continue;
    }
    if (o.type != ShapeType::Plane) continue;
    if (s.settings.gt_intersector == GtIntersector::Embree) {
      obj_gt_mesh[i] = int(gt_meshes.size());
      gt_meshes.push_back(std::make_shared<Mesh>(displaced_plane_mesh(o, m, s.source.string())));
      continue;
    }
    PlaneHF p;
    p.obj = int(i);
    p.T = o.tangent, p.N = o.normal, p.B = cross(o.normal, o.tangent), p.c = o.center, p.half = o.half_size;
    const float tu = 2 * o.half_size.x / (m.uv_scale * float(m.height.width()));
    const float tv = 2 * o.half_size.y / (m.uv_scale * float(m.height.height()));
    check_ground_truth_texels(tu, tv, m, s.source.string());
    p.texel = tu;
    p.hf = HeightField(m.height, m.height_texels);
    p.lo = {-0.5f, -0.5f};
    p.hi = {2 * o.half_size.x / tu - 0.5f, 2 * o.half_size.y / tu - 0.5f};
    obj_hf[i] = int(hfs.size());
    hfs.push_back(std::move(p));
  }
  if (hfs.empty() && gt_meshes.empty())
    throw InputError(fmt::format(
        "{}: ground-truth needs a plane or cylinder whose material has a 'height' map", s.source.string()));
}

}  // namespace msh::render
