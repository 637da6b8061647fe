// Glue between the renderer and the other areas' headers: bump-terminator and micro-shadowing terms.
#include <microshadow/lut/micro_shadowing_lut.h>
#include <microshadow/lut/runtime/micro_shadowing_loader.h>
#include <microshadow/occlusion/bump_terminator.h>
#include <microshadow/reference/micro_shadowing_area_exact.h>

#include <cmath>
#include <functional>

#include "shading_terms.h"

namespace msh::render {

BumpTerminatorTerm::BumpTerminatorTerm(BumpTerminator m) : mode_(m) {}

float BumpTerminatorTerm::eval(const Vec3f& ng, const Vec3f& ns, const Vec3f& l) const {
  return bump::term(mode_, ng, ns, l);
}

MicroShadowingTerm::MicroShadowingTerm(const Settings& s) : smooth_(s.ms_smooth_normal) {
  const std::string& name = s.micro_shadowing;
  if (name == "none" || s.ground_truth()) return;
  const occlusion::MicroShadowingMethodInfo* info = occlusion::find_micro_shadowing_method(name);
  if (!info) micro_shadowing_from_string(name);  // throws the message listing the names
  occlusion::MicroShadowingOptions o;
  if (info->accepts_samples) o.samples = s.vndf_samples;
  if (info->accepts_lut) o.lut_path = s.lut_path;
  method_ = std::make_shared<const occlusion::MicroShadowingEvaluator>(name, o);
  exact_generic_ = name == "generic-vndf";
  needs_texel_ = info->needs_texel;
  // A LUT method on a table without the azimuth harmonics reads N·L and N·V only (so does every term that
  // does not take φ).
  const auto table = method_->table(false);
  z_only_ = !info->is_pair() && !info->needs_texel &&
            (!info->accepts_phi || (table && table->view().harmonics == 0));
}

float MicroShadowingTerm::eval_area(const ShadePoint& sp, const Vec3f& wo, const Vec3f& tangent,
                                    const Light& l, const Vec3f& p, bool specular,
                                    const std::function<float(const Vec3f&)>& extra, bool extra_is_one,
                                    uint32_t seed) const {
  if (!method_) return 1.0f;
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
  // Type-erased here (the renderer is not engine code): the terms' own callables differ in type.
  area::PointTerm<std::function<double(const Vec3d&)>> term;
  if (exact_generic_) {
    // The exact generic term (the renderer's per-direction estimate is Monte Carlo: not for quadrature).
    auto g = area::generic_vndf_term(V, alpha, alpha, v, 1e-4);
    term = {std::move(g.M), std::move(g.z_breaks), g.z_only};
  } else {
    // Every other method through the renderer's own evaluation at the world direction: the lobe's own term
    // (a pair's terms differ per lobe); z_only_ when it reads N·L only (and N·V, fixed here).
    term.M = [&, seed, specular](const Vec3d& ld) {
      const LobeTerms t = eval_lobes(sp, wo, fr.to_world(Vec3f(ld)), tangent, seed);
      return double(specular ? t.specular : t.diffuse);
    };
    term.z_breaks = area::standard_z_breaks(V);
    term.z_only = z_only_;
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
