// Glue between the renderer and the other areas' headers: bump-terminator terms and the micro-shadowing LUT.
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <cmath>

#include "shading_terms.h"

namespace msh::render {

BumpTerminatorTerm::BumpTerminatorTerm(BumpTerminator m) : mode_(m) {}

float BumpTerminatorTerm::eval(const Vec3f& ng, const Vec3f& ns, const Vec3f& l) const {
  switch (mode_) {
    case BumpTerminator::Off:
      return 1.0f;
    case BumpTerminator::Conty2019:
      return bump::conty2019(ng, ns, l);
    case BumpTerminator::Chiang2019:
      return bump::chiang2019(ng, ns, l);
  }
  return 1.0f;
}

class LutSampler {
 public:
  std::shared_ptr<const lut::MicroShadowingLut> table;
  lut::MicroShadowingLutView view;
  bool two_d = false;
};

std::shared_ptr<const LutSampler> load_lut_sampler(const std::string& path, bool two_d) {
  auto s = std::make_shared<LutSampler>();
  s->two_d = two_d;
  // No file: the LUT module's default table (cone layout, 3D or N·V = 1, baked once per process and cached).
  s->table = path.empty()
                 ? lut::default_micro_shadowing_lut(two_d)
                 : std::make_shared<const lut::MicroShadowingLut>(lut::load_micro_shadowing_lut(path));
  s->view = s->table->view();
  return s;
}

// The 2D LUT is the N·V = 1 slice (Zurita 2026): N·V is not looked up. Any layout (the view dispatches); an
// azimuth-aware table is evaluated at the light's azimuth, never reduced to its mean silently.
float sample_lut(const LutSampler& l, float V, float n_dot_l, float n_dot_v, float roughness, float cos_phi) {
  const float nv = l.two_d ? 1.0f : n_dot_v;
  if (l.view.harmonics > 0)
    return lut::sample_micro_shadowing_azimuth(l.view, V, n_dot_l, nv, roughness, cos_phi);
  return lut::sample_micro_shadowing(l.view, V, n_dot_l, nv, roughness);
}

float MicroShadowingTerm::eval_area(const ShadePoint& sp, const Vec3f& wo, const Vec3f& tangent,
                                    const Light& l, const Vec3f& p, bool specular,
                                    const std::function<float(const Vec3f&)>& extra, bool extra_is_one,
                                    uint32_t seed) const {
  if (mode_ == MicroShadowing::None || mode_ == MicroShadowing::GroundTruth) return 1.0f;
  // The light as seen from p, in the term's frame (n = +z), as the exact reference takes it.
  const Vec3f& n = smooth_ ? sp.n_smooth : sp.n_shading;
  const Framef fr = Framef::from_zx(n, tangent);
  auto local = [&](const Vec3f& w) { return Vec3d(fr.to_local(w)); };
  const Vec3f dl = l.position - p;
  const float dist = length(dl);
  area::Shape shape;
  if (l.type == LightType::Sphere) {
    shape = area::Cap{normalize(local(dl)), std::asin(std::min(1.0, double(l.radius) / dist))};
  } else if (l.type == LightType::Disk) {
    const Vec3d c = normalize(local(dl)), ln = normalize(local(l.normal));
    if (std::abs(dot(c, ln)) > 1 - 1e-9)
      shape = area::disk_facing(c, std::atan(double(l.radius) / dist));  // exactly a cap
    else
      shape = area::Disk{c, ln, double(l.radius) / dist};
  } else {
    const Vec3f b = cross(l.normal, l.tangent);
    const Vec3f hu = l.tangent * l.half_size.x, hw = b * l.half_size.y;
    shape = area::Quad{{normalize(local(dl + hu + hw)), normalize(local(dl - hu + hw)),
                        normalize(local(dl - hu - hw)), normalize(local(dl + hu - hw))}};
  }
  const double alpha = roughness_to_alpha(std::max(double(sp.roughness), 0.02));
  Vec3d v = local(wo);
  v.z = std::max(v.z, 1e-4);
  v = normalize(v);
  const area::Receiver rec = specular ? area::Receiver::ggx(alpha, v) : area::Receiver::lambert();
  area::AreaOptions opt;
  opt.rel_tol = 1e-4;
  const double V = sp.visibility;
  area::PointTerm<std::function<double(const Vec3d&)>> term;
  if (mode_ == MicroShadowing::GenericVndf) {
    // The exact generic term (the renderer's per-direction estimate is Monte Carlo: not for quadrature).
    auto g = area::generic_vndf_term(V, alpha, alpha, v, 1e-4);
    term.M = g.M, term.z_breaks = g.z_breaks, term.z_only = g.z_only;
  } else {
    // Every other term through the renderer's own evaluation at the world direction; all but an
    // azimuth-aware LUT depend on N·L only (and N·V, fixed here).
    term.M = [&, seed](const Vec3d& ld) {
      return double(eval(sp, wo, fr.to_world(Vec3f(ld)), tangent, seed));
    };
    term.z_breaks = area::standard_z_breaks(V);
    term.z_only = !(lut_ && lut_->view.harmonics > 0);
  }
  if (!extra_is_one) {
    term.M = [m = term.M, &extra, &fr](const Vec3d& ld) {
      return m(ld) * double(extra(fr.to_world(Vec3f(ld))));
    };
    term.z_only = false;
  }
  return float(area::area_micro_shadowing_exact(shape, rec, term, opt));
}

}  // namespace msh::render
