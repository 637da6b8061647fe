// Per-light terms of the renderer: micro-shadowing (docs/micro-shadowing.md) and the bump-terminator fix
// (docs/bump-terminator.md). Private to src/render/.
#pragma once

#include <fmt/format.h>
#include <microshadow/io/error.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/micro_shadowing.h>
#include <microshadow/occlusion/micro_shadowing_aware.h>
#include <microshadow/occlusion/micro_shadowing_aware_fit.h>
#include <microshadow/render/renderer.h>

#include <functional>
#include <memory>

namespace msh::render {

class LutSampler;  // src/render/terms_glue.cpp
std::shared_ptr<const LutSampler> load_lut_sampler(const std::string& path, bool two_d);
// cos_phi: relative azimuth of l and v about the normal (used by an azimuth-aware table, else ignored).
float sample_lut(const LutSampler& lut, float V, float n_dot_l, float n_dot_v, float roughness,
                 float cos_phi);

// The micro-shadowing term: V from the micro-occlusion map; N·L and N·V with the shading (normal-mapped)
// normal, as the shaders of Zurita 2026, "Improving Direct Lighting Material Occlusion – Part 2" do.
// Multiplies diffuse and specular of one light, except the micro-BRDF-aware methods, which have one term per
// lobe (eval_lobes; docs/micro-shadowing-aware.md).
struct LobeTerms {
  float diffuse, specular;
  bool any() const { return diffuse > 0.0f || specular > 0.0f; }
};

class MicroShadowingTerm {
 public:
  explicit MicroShadowingTerm(const Settings& s)
      : mode_(s.micro_shadowing), n_(s.vndf_samples), smooth_(s.ms_smooth_normal) {
    if (mode_ == MicroShadowing::Lut3d || mode_ == MicroShadowing::Lut2d) {
      lut_ = load_lut_sampler(s.lut_path, mode_ == MicroShadowing::Lut2d);
    }
  }
  bool per_lobe() const {
    return mode_ == MicroShadowing::Aware || mode_ == MicroShadowing::AwareFlux ||
           mode_ == MicroShadowing::AwareAlu;
  }
  // Both lobes' terms; equal for every method but the aware ones.
  LobeTerms eval_lobes(const ShadePoint& sp, const Vec3f& wo, const Vec3f& wi, const Vec3f& tangent,
                       uint32_t seed) const {
    if (!per_lobe()) {
      const float t = eval(sp, wo, wi, tangent, seed);
      return {t, t};
    }
    const Vec3f& n = smooth_ ? sp.n_smooth : sp.n_shading;
    const float V = sp.visibility;
    if (micro_shadowing::exact_zero(V, dot(n, wi))) return {0.0f, 0.0f};
    const Framef fr = Framef::from_zx(n, tangent);
    Vec3f v = fr.to_local(wo);
    v.z = std::max(v.z, 1e-4f);
    v = normalize(v);
    const Vec3f l = fr.to_local(wi);
    if (mode_ == MicroShadowing::AwareAlu)  // the diffuse term's ALU fit of its azimuth mean: N·L, N·V only
      return {micro_shadowing::diffuse_aware_alu(V, l.z, v.z, sp.roughness),
              micro_shadowing::specular_aware(V, v, l)};
    const GGX<float> ggx(roughness_to_alpha(std::max(sp.roughness, 0.02f)));
    const auto form = mode_ == MicroShadowing::Aware ? micro_shadowing::DiffuseAwareForm::Reciprocal
                                                     : micro_shadowing::DiffuseAwareForm::Flux;
    return {micro_shadowing::diffuse_aware_estimate(V, ggx, v, l, n_, form, seed | 1u),
            micro_shadowing::specular_aware(V, v, l)};
  }
  // Settings::area_ms == Integrated: the term averaged over the solid angle of light l (sphere, disk or
  // rect) seen from p, weighted by the receiver — Lambert (specular = false) or the GGX lobe for wo
  // (specular = true): M_area = ∫ M(l) f(v, l) (n·l)⁺ dl / ∫ f(v, l) (n·l)⁺ dl, by the exact deterministic
  // quadrature of reference/micro_shadowing_area_exact.h (n: the term's normal). extra(wi) multiplies the
  // term inside the integral (the bump-terminator term; extra_is_one skips it); seed: the stream of a Monte
  // Carlo term (unused: generic-vndf takes the exact term). In terms_glue.cpp.
  float eval_area(const ShadePoint& sp, const Vec3f& wo, const Vec3f& tangent, const Light& l, const Vec3f& p,
                  bool specular, const std::function<float(const Vec3f&)>& extra, bool extra_is_one,
                  uint32_t seed) const;
  float eval(const ShadePoint& sp, const Vec3f& wo, const Vec3f& wi, const Vec3f& tangent,
             uint32_t seed) const {
    const Vec3f& n = smooth_ ? sp.n_smooth : sp.n_shading;
    const float V = sp.visibility, nl = dot(n, wi);
    switch (mode_) {
      case MicroShadowing::Aware:
      case MicroShadowing::AwareFlux:
      case MicroShadowing::AwareAlu: {  // one value for callers that want one: the diffuse lobe's
        return eval_lobes(sp, wo, wi, tangent, seed).diffuse;
      }
      case MicroShadowing::None:
      case MicroShadowing::GroundTruth:
        return 1.0f;
      case MicroShadowing::AO:
        return V;
      case MicroShadowing::Reference:
        return micro_shadowing::reference_step(V, nl);
      case MicroShadowing::BrinckMaximov:
        return micro_shadowing::brinck_maximov_2016(V, nl);
      case MicroShadowing::Chan:
        return micro_shadowing::chan_2018(V, nl);
      case MicroShadowing::Part1:
        return micro_shadowing::part1_analytic(V, nl);
      case MicroShadowing::GenericVndf: {
        if (micro_shadowing::exact_zero(V, nl)) return 0.0f;
        const Framef fr = Framef::from_zx(n, tangent);
        Vec3f v = fr.to_local(wo);
        v.z = std::max(v.z, 1e-4f);
        const GGX<float> ggx(roughness_to_alpha(std::max(sp.roughness, 0.02f)));
        return micro_shadowing::generic_vndf_estimate(V, ggx, normalize(v), fr.to_local(wi), n_,
                                                      micro_shadowing::G2Form::HeightCorrelated, seed | 1u);
      }
      case MicroShadowing::Lut3d:
      case MicroShadowing::Lut2d: {
        if (micro_shadowing::exact_zero(V, nl)) return 0.0f;  // Zurita 2026 (Part 2) early-out: no LUT fetch
        // Relative azimuth of the tangent-plane projections of wo and wi (for azimuth-aware tables).
        const Vec3f pv = wo - dot(n, wo) * n, pl = wi - dot(n, wi) * n;
        const float d = std::sqrt(dot(pv, pv) * dot(pl, pl));
        const float cos_phi = d > 0.0f ? clamp(dot(pv, pl) / d, -1.0f, 1.0f) : 1.0f;
        return sample_lut(*lut_, V, nl, saturate(dot(n, wo)), sp.roughness, cos_phi);
      }
    }
    return 1.0f;
  }

 private:
  MicroShadowing mode_;
  int n_;
  bool smooth_;
  std::shared_ptr<const LutSampler> lut_;
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
