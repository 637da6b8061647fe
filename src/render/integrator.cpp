// Direct lighting at a hit: directional, point, sphere (representative point or area sampling), disk and rect
// lights (area sampling), shadow rays with the offset policy of docs/renderer.md, the per-light terms (per
// light sample, at the representative point or integrated over the light: Settings::area_ms), and the BRDF
// through the library's BRDF code.
#include <microshadow/bsdf/diffuse.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>

#include <algorithm>
#include <cmath>

#include "renderer_impl.h"

namespace msh::render {

using tracing::kInf;

RepresentativeDirs representative_dirs(const Light& l, const Vec3f& p, const Vec3f& r) {
  const Vec3f dl = l.position - p;
  const float dist = length(dl);
  const Vec3f wc = dl / dist;
  if (l.type == LightType::Sphere) {
    const Vec3f to_ray = r * dot(dl, r) - dl;
    const Vec3f cp = dl + to_ray * saturate(l.radius / std::max(length(to_ray), 1e-12f));
    return {wc, normalize(cp)};
  }
  // Disk / rect: the reflection ray's hit on the light's plane or, when the ray runs parallel to or away
  // from it, the point of the plane nearest to the ray's point at the centre's distance; then clamped to
  // the shape (Lagarde & de Rousiers 2014, "Moving Frostbite to PBR", §4.7.2).
  const float rn = dot(r, l.normal), h = -dot(dl, l.normal);   // h > 0: p in front of the emitter
  Vec3f q = rn < -1e-6f ? r * (h / -rn) - dl : r * dist - dl;  // offset from the centre
  q = q - l.normal * dot(q, l.normal);
  if (l.type == LightType::Disk) {
    const float lq = length(q);
    if (lq > l.radius) q = q * (l.radius / lq);
  } else {
    const Vec3f b = cross(l.normal, l.tangent);
    q = l.tangent * clamp(dot(q, l.tangent), -l.half_size.x, l.half_size.x) +
        b * clamp(dot(q, b), -l.half_size.y, l.half_size.y);
  }
  return {wc, normalize(dl + q)};
}

AreaSample sample_area_light(const Light& l, const Vec3f& p, const Vec2f& u) {
  AreaSample s;
  const Vec3f dl = l.position - p;
  if (l.type == LightType::Sphere) {
    const float dist = length(dl);
    const float sin2 = sqr(l.radius / dist), cos_max = safe_sqrt(1 - sin2);
    const Framef fr = Framef::from_z(dl / dist);
    s.wi = fr.to_world(sample_uniform_cone(u, cos_max));
    s.inv_pdf = 2 * kPi<float> * (1 - cos_max);
    // Distance to the sphere's near surface along wi.
    const float b = dot(dl, s.wi), c = dot(dl, dl) - sqr(l.radius);
    s.dist = b - safe_sqrt(b * b - c);
    s.valid = true;
    return s;
  }
  // Uniform in area: pdf_ω = d² / (A cos θ_light).
  Vec3f q;
  const Vec3f b = cross(l.normal, l.tangent);
  if (l.type == LightType::Disk) {
    const Vec2f d = sample_uniform_disk_concentric(u);
    q = dl + l.tangent * (l.radius * d.x) + b * (l.radius * d.y);
  } else {
    q = dl + l.tangent * ((2 * u.x - 1) * l.half_size.x) + b * ((2 * u.y - 1) * l.half_size.y);
  }
  const float d2 = dot(q, q), d = std::sqrt(d2);
  if (!(d > 0)) return s;
  s.wi = q / d;
  const float cos_l = -dot(s.wi, l.normal);
  if (!(cos_l > 0)) return s;  // one-sided emitter seen from behind
  s.dist = d;
  s.inv_pdf = light_area(l) * cos_l / d2;
  s.valid = true;
  return s;
}

Rgbf brdf_cos(const ShadePoint& sp, const Vec3f& wo, const Vec3f& wi, float spec_scale, bool diffuse,
              bool specular) {
  const Vec3f& n = sp.n_shading;
  const float nl = dot(n, wi);
  if (!(nl > 0)) return Rgbf(0.0f);
  const Framef fr = Framef::from_z(n);
  const Vec3f li = fr.to_local(wi), lo_raw = fr.to_local(wo);
  // A normal-mapped normal can face away from the viewer: clamp N·V (the view stays just above the horizon).
  const Vec3f lo(lo_raw.x, lo_raw.y, std::max(lo_raw.z, 1e-4f));
  const Vec3f h = normalize(wi + wo, n);
  const Rgbf f0 = lerp(sp.metallic, Rgbf(0.04f * sp.specular), sp.base_color);
  // specular < 1 also fades the Fresnel rise (specular 0: no Fresnel at all, for closed-form Lambert tests).
  const Rgbf F = lerp(std::min(1.0f, sp.specular), f0, bsdf::fresnel_schlick(f0, saturate(dot(wo, h))));
  Rgbf out(0.0f);
  if (specular) {
    const GGX<float> ggx(roughness_to_alpha(std::max(sp.roughness, 0.02f)));
    const bsdf::SpecularEval<float> e = bsdf::microfacet_specular(ggx, lo, li);
    out += F * (e.f1 * nl * spec_scale);
  }
  if (diffuse)
    out += (Rgbf(1.0f) - F) * bsdf::diffuse_lambert(sp.base_color * (1.0f - sp.metallic), li, lo) * nl;
  return out;
}

Rgbf Renderer::Impl::shade(const Hit& h, const Vec3f& wo, uint32_t seed, RenderStats& st) const {
  Rgbf L;
  shade(h, wo, seed, st, Components{1, {scene.settings.component, Component::Total}}, &L);
  return L;
}

ShadePoint Renderer::Impl::shade_point(const Hit& h) const {
  const Object& ob = scene.objects[h.obj];
  const Material& m = scene.materials[ob.material];
  const float u = h.uv.x * m.uv_scale, v = h.uv.y * m.uv_scale;
  ShadePoint sp;
  sp.base_color = m.base_color.sample_rgb(u, v);
  sp.roughness = saturate(m.roughness.sample(u, v));
  sp.metallic = saturate(m.metallic.sample(u, v));
  sp.specular = m.specular;
  sp.n_geometric = h.ng;
  sp.n_smooth = h.ns;
  sp.n_shading = h.ns;
  sp.visibility = 1.0f;
  if (h.gt) return sp;
  sp.visibility = saturate(m.visibility.sample(u, v));
  const Framef fr = Framef::from_zx(h.ns, h.tangent);
  const Vec3f bt = fr.t * h.tangent_sign;
  sp.frame_u = fr.s, sp.frame_v = bt;
  if (!m.directional.empty()) {
    // Only what the method reads (the view correction's 12 slope channels more than double the fetches).
    sp.texel_channels = std::min({m.directional.channels(), int(sp.texel.size()), ms.texel_channels()});
    for (int c = 0; c < sp.texel_channels; ++c) sp.texel[std::size_t(c)] = m.directional.sample(u, v, c);
    sp.slope_covariance = m.slope_covariance;
  }
  if (!m.normal.empty()) {
    const Rgbf nt = m.normal.sample_rgb(u, v);
    const Vec3f tn(m.normal_strength * (2 * nt.r - 1), m.normal_strength * (2 * nt.g - 1), 2 * nt.b - 1);
    sp.n_shading = normalize(fr.s * tn.x + bt * tn.y + h.ns * tn.z, h.ns);
  }
  return sp;
}

// Every component's radiance is accumulated as the single-component render accumulates it (the same
// operations in the same order, a lobe a component does not want contributing nothing, not a zero): what
// makes each output bit-identical to that render.
class Renderer::Impl::HitLighting {
 public:
  HitLighting(const Impl& r, const Hit& h, const Vec3f& wo, const Components& cs, RenderStats& st, Rgbf* out)
      : r_(r), set_(r.scene.settings), h_(h), wo_(wo), sp_(r.shade_point(h)), cs_(cs), st_(st), out_(out) {
    const Object& ob = r.scene.objects[h.obj];
    ++st.shaded_samples;
    // Per component: its lobes; any_d / any_s: some component wants the lobe.
    for (int c = 0; c < cs.n; ++c) {
      want_d_[c] = cs.comp[std::size_t(c)] != Component::Specular;
      want_s_[c] = cs.comp[std::size_t(c)] != Component::Diffuse;
      any_d_ = any_d_ || want_d_[c], any_s_ = any_s_ || want_s_[c];
      out[c] = want_d_[c] ? set_.ambient * sp_.base_color : Rgbf(0.0f);
    }
    // Shadow-ray origin (policy in docs/renderer.md): analytic shapes and meshes push the hit point (or
    // Hanika's offset point) off the surface along the facet normal by 2e-4 · max(1, |p|∞); the height field
    // starts at the hit point itself, no offset: it counts front faces only and a light must be above the
    // hit facet, so the ray cannot re-hit its own facet.
    po_ = h.p;
    if (set_.hanika_offset && ob.type == ShapeType::Mesh && !h.gt) po_ = hanika_offset(*ob.mesh, h);
    eps_ =
        h.gt ? 0.0f
             : 2e-4f * std::max(1.0f, std::max(std::abs(h.p.x), std::max(std::abs(h.p.y), std::abs(h.p.z))));
    // Meshes leave the geometric-hemisphere test to the shadow ray (so that the Hanika offset can light
    // faces whose flat normal already turned away, as a smooth surface would); other shapes test N_g·L.
    is_mesh_ = ob.type == ShapeType::Mesh && !h.gt;
  }

  // A directional or point light.
  void delta(const Light& light, uint32_t ls) {
    Vec3f wi = light.direction;
    float dist = kInf;
    Rgbf E = light.color;
    if (light.type == LightType::Point) {
      const Vec3f dl = light.position - h_.p;
      dist = length(dl);
      if (!(dist > 0)) return;
      wi = dl / dist;
      E = E / (dist * dist);
    }
    if (!above(wi) || !(dot(sp_.n_shading, wi) > 0)) return;
    const LobeTerms k = term(wi, ls);
    if (!k.any()) return;
    if (shadow(wi, dist * (1 - 1e-4f))) return;
    for (int c = 0; c < cs_.n; ++c) out_[c] += lobes(wi, 1.0f, want_d_[c], want_s_[c], k, E);
  }

  // A sphere light at its representative point (Karis 2013): diffuse toward the centre, specular toward the
  // point of the sphere closest to the reflection ray, with the (α / α')² energy normalization.
  void representative(const Light& light, uint32_t ls) {
    const Vec3f dl = light.position - h_.p;
    const float dist = length(dl);
    if (!(dist > light.radius)) return;
    const RepresentativeDirs rd = representative_dirs(light, h_.p, reflect(wo_, sp_.n_shading));
    const Vec3f wc = rd.wc, ws = rd.ws;
    const Rgbf E = light.color / (dist * dist);
    if (shadow(wc, dist - light.radius)) return;
    if (any_d_ && above(wc) && dot(sp_.n_shading, wc) > 0) {
      const Rgbf Ld = brdf_cos(sp_, wo_, wc, 1.0f, true, false) * E * term(wc, ls).diffuse;
      for (int c = 0; c < cs_.n; ++c)
        if (want_d_[c]) out_[c] += Ld;
    }
    if (any_s_ && above(ws) && dot(sp_.n_shading, ws) > 0) {
      const float a = roughness_to_alpha(std::max(sp_.roughness, 0.02f));
      const float a2 = saturate(a + light.radius / (2 * dist));
      const Rgbf Ls = brdf_cos(sp_, wo_, ws, sqr(a / a2), false, true) * E * term(ws, ls).specular;
      for (int c = 0; c < cs_.n; ++c)
        if (want_s_[c]) out_[c] += Ls;
    }
  }

  // Area sampling (the reference): a sphere uniformly in its subtended cone (radiance I / (π r²)), a disk or
  // rect uniformly in area (radiance I / area, one-sided), one shadow ray per sample; the term per sample
  // (AreaMs::Sampled) or one term per lobe after the samples (docs/renderer.md).
  void area(const Light& light, uint32_t ls) {
    const Vec3f dl = light.position - h_.p;
    const float dist = length(dl);
    if (light.type == LightType::Sphere ? !(dist > light.radius) : !(dot(dl, light.normal) < 0)) return;
    const Rgbf Le = light.type == LightType::Sphere ? light.color / (kPi<float> * sqr(light.radius))
                                                    : light.color / light_area(light);
    const bool per_sample = set_.area_ms == AreaMs::Sampled;
    Rgbf acc[2] = {Rgbf(0.0f), Rgbf(0.0f)}, acc_d(0.0f), acc_s(0.0f);
    for (int k = 0; k < set_.area_samples; ++k) {
      const AreaSample smp = sample_area_light(light, h_.p, sobol_2d<float>(uint32_t(k), ls + 1));
      if (!smp.valid) continue;
      const Vec3f wi = smp.wi;
      if (!above(wi) || !(dot(sp_.n_shading, wi) > 0)) continue;
      if (per_sample) {
        const LobeTerms t = term(wi, hash_combine(ls, uint32_t(k)));
        if (!t.any()) continue;
        if (shadow(wi, smp.dist * (1 - 1e-4f))) continue;
        for (int c = 0; c < cs_.n; ++c)
          acc[c] += r_.ms.per_lobe() ? lobes(wi, 1.0f, want_d_[c], want_s_[c], t, Le * smp.inv_pdf)
                                     : brdf_cos(sp_, wo_, wi, 1.0f, want_d_[c], want_s_[c]) * Le *
                                           (t.diffuse * smp.inv_pdf);
      } else {
        if (shadow(wi, smp.dist * (1 - 1e-4f))) continue;
        if (any_d_) acc_d += brdf_cos(sp_, wo_, wi, 1.0f, true, false) * Le * smp.inv_pdf;
        if (any_s_) acc_s += brdf_cos(sp_, wo_, wi, 1.0f, false, true) * Le * smp.inv_pdf;
      }
    }
    if (per_sample) {
      for (int c = 0; c < cs_.n; ++c) out_[c] += acc[c] / float(set_.area_samples);
      return;
    }
    const uint32_t ts = hash_combine(ls, 0x52455052u);  // the one term's random stream (generic-vndf)
    float m_d = 0.0f, m_s = 0.0f;
    if (set_.area_ms == AreaMs::Representative) {
      const RepresentativeDirs rd = representative_dirs(light, h_.p, reflect(wo_, sp_.n_shading));
      if (any_d_) m_d = term(rd.wc, ts).diffuse;
      if (any_s_) m_s = term(rd.ws, ts).specular;
    } else {
      const std::function<float(const Vec3f&)> bump = [&](const Vec3f& wi) {
        return r_.bt.eval(sp_.n_smooth, sp_.n_shading, wi);
      };
      const bool no_bump = set_.bump_terminator == BumpTerminator::kNone;
      if (any_d_ && acc_d.r + acc_d.g + acc_d.b > 0)
        m_d = r_.ms.eval_area(sp_, wo_, h_.tangent, light, h_.p, false, bump, no_bump, ts);
      if (any_s_ && acc_s.r + acc_s.g + acc_s.b > 0)
        m_s = r_.ms.eval_area(sp_, wo_, h_.tangent, light, h_.p, true, bump, no_bump, ts);
    }
    // A lobe the component does not want: its sum and term stay at zero, as in its own render.
    for (int c = 0; c < cs_.n; ++c)
      out_[c] += ((want_d_[c] ? acc_d : Rgbf(0.0f)) * (want_d_[c] ? m_d : 0.0f) +
                  (want_s_[c] ? acc_s : Rgbf(0.0f)) * (want_s_[c] ? m_s : 0.0f)) /
                 float(set_.area_samples);
  }

 private:
  bool shadow(const Vec3f& wi, float dist) const {
    ++st_.shadow_rays;
    return r_.occluded(po_ + h_.ng * eps_, wi, 0.0f, dist);
  }
  // Light reaching the micro-surface: micro-shadowing (V from the map, N·L and N·V with the shading normal)
  // times the bump-terminator term.
  LobeTerms term(const Vec3f& wi, uint32_t s) const {
    const float b = r_.bt.eval(sp_.n_smooth, sp_.n_shading, wi);
    const LobeTerms t = r_.ms.eval_lobes(sp_, wo_, wi, h_.tangent, s);
    return LobeTerms{t.diffuse * b, t.specular * b};
  }
  // The BRDF times the lobes' terms: one product when both lobes share the term (every method but the aware
  // ones, bit-identical to the single-term renderer), else each lobe with its own.
  Rgbf lobes(const Vec3f& wi, float spec_scale, bool d, bool s, const LobeTerms& k, const Rgbf& E) const {
    if (!r_.ms.per_lobe()) return brdf_cos(sp_, wo_, wi, spec_scale, d, s) * E * k.diffuse;
    Rgbf out(0.0f);
    if (d) out += brdf_cos(sp_, wo_, wi, spec_scale, true, false) * E * k.diffuse;
    if (s) out += brdf_cos(sp_, wo_, wi, spec_scale, false, true) * E * k.specular;
    return out;
  }
  bool above(const Vec3f& wi) const { return is_mesh_ || dot(h_.ng, wi) > 0; }

  const Impl& r_;
  const Settings& set_;
  const Hit& h_;
  const Vec3f wo_;
  const ShadePoint sp_;
  const Components& cs_;
  RenderStats& st_;
  Rgbf* out_;
  bool want_d_[2] = {false, false}, want_s_[2] = {false, false}, any_d_ = false, any_s_ = false;
  Vec3f po_;
  float eps_ = 0;
  bool is_mesh_ = false;
};

void Renderer::Impl::shade(const Hit& h, const Vec3f& wo, uint32_t seed, RenderStats& st,
                           const Components& cs, Rgbf* out, const Light* light0) const {
  HitLighting lighting(*this, h, wo, cs, st, out);
  for (std::size_t li = 0; li < scene.lights.size(); ++li) {
    const Light& light = li == 0 && light0 ? *light0 : scene.lights[li];
    const uint32_t ls = hash_combine(seed, uint32_t(li));
    if (light.type == LightType::Directional || light.type == LightType::Point)
      lighting.delta(light, ls);
    else if (light.type == LightType::Sphere && !scene.settings.area_lights)
      lighting.representative(light, ls);
    else
      lighting.area(light, ls);
  }
}

// Hanika 2021 (RTG II ch. 4): shadow-ray origin on the smooth surface implied by the vertex normals.
Vec3f Renderer::Impl::hanika_offset(const Mesh& m, const Hit& h) {
  const auto& tr = m.tri[h.prim];
  return bump::hanika2021_shadow_origin(h.p, std::array<Vec3f, 3>{m.p[tr[0]], m.p[tr[1]], m.p[tr[2]]},
                                        std::array<Vec3f, 3>{m.n[tr[0]], m.n[tr[1]], m.n[tr[2]]},
                                        std::array<float, 3>{h.bary.x, h.bary.y, h.bary.z});
}

}  // namespace msh::render
