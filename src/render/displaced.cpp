// Displaced plane and cylinder meshes for the ground truth (see displaced.h).
#include "displaced.h"

#include <fmt/format.h>
#include <microshadow/io/error.h>

#include <cmath>

namespace msh::render {

void check_ground_truth_texels(float tu, float tv, const Material& m, const std::string& where) {
  if (std::abs(tu - tv) > 0.01f * tu)
    throw InputError(fmt::format("{}: ground truth needs square texels (material '{}': {} × {} world units)",
                                 where, m.name, tu, tv));
  if (!(m.height_texels > 0))
    throw InputError(
        fmt::format("{}: ground truth: material '{}' has a height map but no height_texels (set it "
                    "in the scene or ship material.json beside the height map)",
                    where, m.name));
}

namespace {
// Heights of the repeated map in texel units, z ≤ 0 (the top of the range on the base surface).
float depth_at(const Material& m, int i, int j) { return (m.height.texel(i, j, 0) - 1.0f) * m.height_texels; }
// Two triangles per cell of an nu × nv vertex grid (row-major, vertex (i, j) = j·nu + i); `flip` reverses the
// winding.
void grid_triangles(Mesh& mesh, int nu, int nv, bool flip) {
  mesh.tri.reserve(std::size_t(nu - 1) * (nv - 1) * 2);
  for (int j = 0; j + 1 < nv; ++j)
    for (int i = 0; i + 1 < nu; ++i) {
      const int i1 = i + 1;
      const uint32_t a = uint32_t(j * nu + i), b = uint32_t(j * nu + i1), c = uint32_t((j + 1) * nu + i1),
                     d = uint32_t((j + 1) * nu + i);
      if (!flip) {
        mesh.tri.push_back({a, b, c});
        mesh.tri.push_back({a, c, d});
      } else {
        mesh.tri.push_back({a, c, b});
        mesh.tri.push_back({a, d, c});
      }
    }
}
}  // namespace

Mesh displaced_plane_mesh(const Object& o, const Material& m, const std::string& where) {
  const int W = int(std::lround(m.uv_scale * float(m.height.width()))),
            H = int(std::lround(m.uv_scale * float(m.height.height())));
  const float tu = 2 * o.half_size.x / float(W), tv = 2 * o.half_size.y / float(H);
  check_ground_truth_texels(tu, tv, m, where);
  const Vec3f B = cross(o.normal, o.tangent);
  Mesh mesh;
  const int nu = W + 1, nv = H + 1;
  mesh.p.reserve(std::size_t(nu) * nv);
  mesh.uv.reserve(std::size_t(nu) * nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const float x = (float(i) + 0.5f) * tu - o.half_size.x, y = (float(j) + 0.5f) * tu - o.half_size.y;
      mesh.p.push_back(o.center + o.tangent * x + B * y + o.normal * (depth_at(m, i, j) * tu));
      mesh.uv.push_back({(float(i) + 0.5f) / float(W), (float(j) + 0.5f) / float(H)});
    }
  grid_triangles(mesh, nu, nv, false);
  return mesh;
}

Mesh displaced_cylinder_mesh(const Object& o, const Material& m, const std::string& where) {
  const int W = int(std::lround(m.uv_scale * float(m.height.width()))),
            H = int(std::lround(m.uv_scale * float(m.height.height())));
  const float R = o.cyl_radius, len = o.cyl_height;
  const float tu = 2 * kPi<float> * R / float(W), tv = len / float(H);
  check_ground_truth_texels(tu, tv, m, where);
  const float cr = std::cos(o.cyl_rotate_z), sr = std::sin(o.cyl_rotate_z);
  Mesh mesh;
  // Column W repeats column 0 at the same position (u past 1: textures wrap), so no triangle interpolates u
  // across the seam.
  const int nu = W + 1;
  mesh.p.reserve(std::size_t(nu) * H);
  mesh.uv.reserve(std::size_t(nu) * H);
  for (int j = 0; j < H; ++j)
    for (int i = 0; i < nu; ++i) {
      const float u = (float(i) + 0.5f) / float(W), v = (float(j) + 0.5f) / float(H);
      const double phi = 2 * kPi<double> * (double(i % W) + 0.5) / double(W);
      const float r = R + depth_at(m, i % W, j) * tu;
      const float x = r * float(std::cos(phi)), y = r * float(std::sin(phi));
      mesh.p.push_back(o.center + Vec3f(cr * x - sr * y, sr * x + cr * y, (0.5f - v) * len));
      mesh.uv.push_back({u, v});
    }
  // Grid order (u around, v down the axis) gives inward normals: reverse the winding.
  grid_triangles(mesh, nu, H, true);
  return mesh;
}

}  // namespace msh::render
