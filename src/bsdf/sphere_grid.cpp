#include <microshadow/bsdf/runtime/albedo.h>
#include <microshadow/bsdf/runtime/sphere_grid.h>
#include <microshadow/math/color.h>
#include <tbb/parallel_for.h>

namespace msh::bsdf {

namespace {
constexpr int kAlbedoBins = 64;
}

io::Volume render_sphere_grid(const std::vector<std::vector<const BrdfModel*>>& rows, int px,
                              const SphereLighting& light) {
  size_t ncols = 0;
  for (const auto& r : rows) ncols = std::max(ncols, r.size());
  const int w = int(ncols) * px, h = int(rows.size()) * px;
  io::Volume img(std::max(w, 1), std::max(h, 1), 1, 3);
  // Directional albedo per cell on μ = k/(bins − 1), for the environment term.
  std::vector<std::vector<std::vector<Rgbd>>> albedo(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    albedo[i].resize(rows[i].size());
    for (size_t j = 0; j < rows[i].size(); ++j) {
      if (!rows[i][j]) continue;
      albedo[i][j].resize(kAlbedoBins);
      tbb::parallel_for(0, kAlbedoBins, [&](int k) {
        const double mu = std::max(double(k) / (kAlbedoBins - 1), 1e-3);
        albedo[i][j][size_t(k)] = directional_albedo(*rows[i][j], mu, uint32_t(light.albedo_samples));
      });
    }
  }
  const Vec3d sun = normalize(light.sun_dir), view(0, 0, 1);
  tbb::parallel_for(0, h, [&](int y) {
    const size_t i = size_t(y / px);
    for (int x = 0; x < w; ++x) {
      const size_t j = size_t(x / px);
      if (j >= rows[i].size() || !rows[i][j]) continue;
      // Pixel centre in the cell, in [−1, 1]² with a 6% margin; y up.
      const double u = ((x % px) + 0.5) / px * 2 - 1, v = 1 - ((y % px) + 0.5) / px * 2;
      const double s = 1.06, nx = u * s, ny = v * s, r2 = nx * nx + ny * ny;
      if (r2 >= 1) continue;
      const Vec3d n(nx, ny, std::sqrt(1 - r2));
      const Framed f = Framed::from_z(n);
      const Vec3d wo = f.to_local(view), wi = f.to_local(sun);
      const double mu = clamp(wo.z, 0.0, 1.0);
      const double fk = mu * (kAlbedoBins - 1);
      const int k = std::min(int(fk), kAlbedoBins - 2);
      const double t = fk - k;
      const auto& a = albedo[i][j];
      Rgbd c = lerp(t, a[size_t(k)], a[size_t(k) + 1]) * light.environment;
      if (wi.z > 0) c += rows[i][j]->f(wo, wi) * (wi.z * light.sun);
      if (!is_finite(c)) c = Rgbd(0.0);
      for (int ch = 0; ch < 3; ++ch) img.at(x, y, 0, ch) = float(c[ch]);
    }
  });
  return img;
}

io::Volume encode_srgb(const io::Volume& linear) {
  io::Volume out = linear;
  for (auto& v : out.data) v = float(linear_to_srgb(saturate(double(v))));
  return out;
}

}  // namespace msh::bsdf
