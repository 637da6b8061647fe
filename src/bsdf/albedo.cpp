#include <microshadow/bsdf/runtime/albedo.h>

namespace msh::bsdf {

Rgbd directional_albedo(const BrdfModel& model, const Vec3d& wo, uint32_t n) {
  return qmc_integrate_2d<double, Rgbd>(
      [&](Vec2d u) -> Rgbd {
        const auto s = model.sample(wo, u);
        if (!s || !(s->pdf > 0.0) || !(s->wi.z > 0.0)) return Rgbd(0.0);
        const Rgbd w = s->f * (s->wi.z / s->pdf);
        return is_finite(w) ? w : Rgbd(0.0);
      },
      n);
}

Rgbd directional_albedo(const BrdfModel& model, double mu, uint32_t n) {
  mu = clamp(mu, 0.0, 1.0);
  return directional_albedo(model, Vec3d(safe_sqrt(1.0 - mu * mu), 0.0, mu), n);
}

}  // namespace msh::bsdf
