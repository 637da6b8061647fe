// Per-light terms of the renderer: micro-shadowing (docs/micro-shadowing.md) and the bump-terminator fix
// (docs/bump-terminator.md). Private to src/render/.
#pragma once

#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/occlusion/runtime/micro_shadowing_methods.h>
#include <microshadow/render/renderer.h>

#include <functional>
#include <memory>

namespace msh::render {

// The micro-shadowing term: V from the micro-occlusion map; N·L and N·V with the shading (normal-mapped)
// normal, as the shaders of Zurita 2026, "Improving Direct Lighting Material Occlusion – Part 2" do. Every
// method of the runtime registry (occlusion/runtime/micro_shadowing_methods.h) through its per-light
// evaluation: one term on both lobes, or a pair with one term per lobe.
struct LobeTerms {
  float diffuse, specular;
  bool any() const { return diffuse > 0.0f || specular > 0.0f; }
};

class MicroShadowingTerm {
 public:
  // InputError on an unknown method, an unreadable LUT file or a LUT that does not fit the method.
  explicit MicroShadowingTerm(const Settings& s);
  bool per_lobe() const { return method_ && method_->info().is_pair(); }
  // The per-texel channels the method reads (0: none).
  int texel_channels() const { return method_ ? method_->info().texel_channels : 0; }
  // Both lobes' terms (equal unless the method is a pair).
  LobeTerms eval_lobes(const ShadePoint& sp, const Vec3f& wo, const Vec3f& wi, const Vec3f& tangent,
                       uint32_t seed) const {
    if (!method_) return {1.0f, 1.0f};
    const Vec3f& n = smooth_ ? sp.n_smooth : sp.n_shading;
    const Framef fr = Framef::from_zx(n, tangent);
    occlusion::MicroShadowingShadeInput in;
    in.visibility = sp.visibility;
    in.roughness = sp.roughness;
    Vec3f v = fr.to_local(wo);
    v.z = std::max(v.z, 1e-4f);  // normal-mapped normals can face away from the viewer
    in.v = normalize(v);
    in.l = fr.to_local(wi);
    in.seed = seed;
    if (needs_texel_) {
      in.texel = sp.texel.data(), in.texel_channels = sp.texel_channels;
      const auto tangent_space = [&](const Vec3f& w) {
        return Vec3f(dot(w, sp.frame_u), dot(w, sp.frame_v), dot(w, sp.n_smooth));
      };
      in.l_tangent = tangent_space(wi), in.n_tangent = tangent_space(sp.n_shading);
      in.v_tangent = tangent_space(wo);
      in.slope_covariance = sp.slope_covariance.data();
    }
    const occlusion::MicroShadowingLobes t = method_->shade(in);
    return {t.diffuse, t.specular};
  }
  // One value for callers that want one: the diffuse lobe's.
  float eval(const ShadePoint& sp, const Vec3f& wo, const Vec3f& wi, const Vec3f& tangent,
             uint32_t seed) const {
    return eval_lobes(sp, wo, wi, tangent, seed).diffuse;
  }
  // Settings::area_ms == Integrated: the term averaged over the solid angle of light l (sphere, disk or
  // rect) seen from p, weighted by the receiver — Lambert (specular = false) or the GGX lobe for wo
  // (specular = true): M_area = ∫ M(l) f(v, l) (n·l)⁺ dl / ∫ f(v, l) (n·l)⁺ dl, by the exact deterministic
  // quadrature of reference/micro_shadowing_area_exact.h (n: the term's normal). extra(wi) multiplies the
  // term inside the integral (the bump-terminator term; extra_is_one skips it); seed: the stream of a Monte
  // Carlo term (generic-vndf takes its exact term instead). In terms_glue.cpp.
  float eval_area(const ShadePoint& sp, const Vec3f& wo, const Vec3f& tangent, const Light& l, const Vec3f& p,
                  bool specular, const std::function<float(const Vec3f&)>& extra, bool extra_is_one,
                  uint32_t seed) const;

 private:
  std::shared_ptr<const occlusion::MicroShadowingEvaluator> method_;  // null: none, ground truth
  bool smooth_;
  bool exact_generic_ = false;  // generic-vndf: eval_area integrates its exact term
  bool z_only_ = false;         // the value depends on l through N·L only (eval_area's fast path)
  bool needs_texel_ = false;    // reads ShadePoint::texel (directional micro-occlusion)
};

// Bump-terminator shadowing of the light (docs/bump-terminator.md): ng = the unperturbed (interpolated)
// normal, ns = the bumped normal.
class BumpTerminatorTerm {
 public:
  explicit BumpTerminatorTerm(BumpTerminator m);
  float eval(const Vec3f& ng, const Vec3f& ns, const Vec3f& l) const;

 private:
  BumpTerminator mode_;
};

}  // namespace msh::render
