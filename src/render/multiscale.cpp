// Coarse texture sets by box filtering a fine set (see render/multiscale.h).
#include <fmt/format.h>
#include <microshadow/filter/lean.h>
#include <microshadow/filter/variance_mapping.h>
#include <microshadow/io/error.h>
#include <microshadow/render/directional_bake.h>
#include <microshadow/render/multiscale.h>
#include <tbb/parallel_for.h>

namespace msh::render {

namespace {

// Box mean of every channel over k × k texels (sums in double, fixed order).

Vec3d decode_normal(const Texture& n, int x, int y) {
  Vec3d v(2.0 * n.at(x, y, 0) - 1.0, 2.0 * n.at(x, y, 1) - 1.0, 2.0 * n.at(x, y, 2) - 1.0);
  if (!is_finite(v)) v = Vec3d(0, 0, 1);
  v.z = std::max(v.z, 1e-4);
  return normalize(v);
}

void check_size(const Texture& t, const Texture& ref, const char* name) {
  if (t.width() != ref.width() || t.height() != ref.height())
    throw InputError(fmt::format("downsample_texture_set: {} map is {}x{}, the height map {}x{}", name,
                                 t.width(), t.height(), ref.width(), ref.height()));
}

}  // namespace

TextureSet downsample_texture_set(const TextureSet& fine, int k, CoarseRoughness mode) {
  if (k < 1) throw InputError(fmt::format("downsample_texture_set: k must be >= 1, got {}", k));
  const Texture& ref = fine.height;
  if (ref.empty()) throw InputError("downsample_texture_set: empty height map");
  check_size(fine.normal, ref, "normal");
  check_size(fine.roughness, ref, "roughness");
  check_size(fine.metallic, ref, "metallic");
  check_size(fine.base_color, ref, "base colour");
  check_size(fine.visibility, ref, "visibility");
  if (!fine.directional.empty()) check_size(fine.directional, ref, "directional");
  if (ref.width() % k != 0 || ref.height() % k != 0)
    throw InputError(fmt::format("downsample_texture_set: size {}x{} is not divisible by k = {}", ref.width(),
                                 ref.height(), k));
  if (k == 1) return fine;

  TextureSet c;
  c.depth_texels = fine.depth_texels / float(k);
  c.slope_covariance = fine.slope_covariance;  // the fine normals' (a per-material constant)
  c.height = box_downsample(fine.height, k);
  c.base_color = box_downsample(fine.base_color, k);
  c.metallic = box_downsample(fine.metallic, k);
  c.visibility = box_downsample(fine.visibility, k);
  // Linear channels: their box mean is the coarse texel's own (occlusion/directional.h).
  if (!fine.directional.empty()) c.directional = box_downsample(fine.directional, k);
  const int w = ref.width() / k, h = ref.height() / k;
  c.normal = Texture(w, h, 3);
  c.roughness = Texture(w, h, 1);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      Vec3d sum(0, 0, 0);
      double rsum = 0;
      filter::CleanMoments<double> m;
      for (int yy = y * k; yy < (y + 1) * k; ++yy)
        for (int xx = x * k; xx < (x + 1) * k; ++xx) {
          const Vec3d n = decode_normal(fine.normal, xx, yy);
          const double r = saturate(double(fine.roughness.at(xx, yy, 0)));
          sum += n;
          rsum += r;
          m += filter::CleanMoments<double>::from_normal(n, 0.0);
        }
      const Vec3d nn = normalize(sum);
      c.normal.at(x, y, 0) = float(0.5 * nn.x + 0.5), c.normal.at(x, y, 1) = float(0.5 * nn.y + 0.5),
                        c.normal.at(x, y, 2) = float(0.5 * nn.z + 0.5);
      const double r_base = rsum / (double(k) * double(k));
      if (mode == CoarseRoughness::Base) {
        c.roughness.at(x, y, 0) = float(r_base);
      } else {
        // CLEAN moments without base roughness: m.alpha()² = var(b_x) + var(b_y), the per-axis normal
        // variance is half of it; added to the base's α²/2 (Beckmann-equivalent mapping).
        const double a = m.alpha();
        c.roughness.at(x, y, 0) = float(filter::roughness_add_variance(r_base, 0.5 * a * a));
      }
    }
  });
  return c;
}

}  // namespace msh::render
