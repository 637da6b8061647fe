// Direct lighting at a hit: directional, point and sphere lights (representative point or area sampling),
// shadow rays with the offset policy of docs/renderer.md, the per-light terms, and the BRDF through the
// library's BRDF code.
#include <microshadow/bsdf/diffuse.h>
#include <microshadow/bsdf/fresnel.h>
#include <microshadow/bsdf/specular.h>
#include <microshadow/math/sampling.h>
#include <microshadow/microfacet/ggx.h>
#include <microshadow/occlusion/shadow_terminator_offset.h>

#include <cmath>

#include "renderer_impl.h"

namespace msh::render {

using detail::kInf;

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
  const Object& ob = scene.objects[h.obj];
  const Material& m = scene.materials[ob.material];
  const Settings& set = scene.settings;
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
  if (!h.gt) {
    sp.visibility = saturate(m.visibility.sample(u, v));
    if (!m.normal.empty()) {
      const Framef fr = Framef::from_zx(h.ns, h.tangent);
      const Vec3f bt = fr.t * h.tangent_sign;
      const Rgbf nt = m.normal.sample_rgb(u, v);
      const Vec3f tn(m.normal_strength * (2 * nt.r - 1), m.normal_strength * (2 * nt.g - 1), 2 * nt.b - 1);
      sp.n_shading = normalize(fr.s * tn.x + bt * tn.y + h.ns * tn.z, h.ns);
    }
  }
  ++st.shaded_samples;
  const bool want_d = set.component != Component::Specular, want_s = set.component != Component::Diffuse;
  Rgbf L = want_d ? set.ambient * sp.base_color : Rgbf(0.0f);
  // Shadow-ray origin (policy in docs/renderer.md): analytic shapes and meshes push the hit point (or
  // Hanika's offset point) off the surface along the facet normal by 2e-4 · max(1, |p|∞); the height field
  // starts at the hit point itself, no offset: it counts front faces only and a light must be above the
  // hit facet, so the ray cannot re-hit its own facet.
  Vec3f po = h.p;
  if (set.hanika_offset && ob.type == ShapeType::Mesh && !h.gt) po = hanika_offset(*ob.mesh, h);
  const float eps =
      h.gt ? 0.0f
           : 2e-4f * std::max(1.0f, std::max(std::abs(h.p.x), std::max(std::abs(h.p.y), std::abs(h.p.z))));
  auto shadow = [&](const Vec3f& wi, float dist) {
    ++st.shadow_rays;
    return occluded(po + h.ng * eps, wi, 0.0f, dist);
  };
  auto term = [&](const Vec3f& wi, uint32_t s) {
    // Light reaching the micro-surface: micro-shadowing (V from the map, N·L and N·V with the shading
    // normal) times the bump-terminator term.
    const float b = bt.eval(sp.n_smooth, sp.n_shading, wi);
    const LobeTerms t = ms.eval_lobes(sp, wo, wi, h.tangent, s);
    return LobeTerms{t.diffuse * b, t.specular * b};
  };
  // The BRDF times the lobes' terms: one product when both lobes share the term (every method but the aware
  // ones, bit-identical to the single-term renderer), else each lobe with its own.
  auto shade = [&](const Vec3f& wi, float spec_scale, bool d, bool sp_, const LobeTerms& k, const Rgbf& E) {
    if (!ms.per_lobe()) return brdf_cos(sp, wo, wi, spec_scale, d, sp_) * E * k.diffuse;
    Rgbf r(0.0f);
    if (d) r += brdf_cos(sp, wo, wi, spec_scale, true, false) * E * k.diffuse;
    if (sp_) r += brdf_cos(sp, wo, wi, spec_scale, false, true) * E * k.specular;
    return r;
  };
  // Meshes leave the geometric-hemisphere test to the shadow ray (so that the Hanika offset can light faces
  // whose flat normal already turned away, as a smooth surface would); other shapes test N_g·L.
  const bool is_mesh = ob.type == ShapeType::Mesh && !h.gt;
  auto above = [&](const Vec3f& wi) { return is_mesh || dot(h.ng, wi) > 0; };
  for (std::size_t li = 0; li < scene.lights.size(); ++li) {
    const Light& light = scene.lights[li];
    const uint32_t ls = hash_combine(seed, uint32_t(li));
    if (light.type == LightType::Directional || light.type == LightType::Point) {
      Vec3f wi = light.direction;
      float dist = kInf;
      Rgbf E = light.color;
      if (light.type == LightType::Point) {
        const Vec3f dl = light.position - h.p;
        dist = length(dl);
        if (!(dist > 0)) continue;
        wi = dl / dist;
        E = E / (dist * dist);
      }
      if (!above(wi) || !(dot(sp.n_shading, wi) > 0)) continue;
      const LobeTerms k = term(wi, ls);
      if (!k.any()) continue;
      if (shadow(wi, dist * (1 - 1e-4f))) continue;
      L += shade(wi, 1.0f, want_d, want_s, k, E);
    } else if (!set.area_lights) {
      // Representative point (Karis 2013): diffuse toward the centre, specular toward the point of the
      // sphere closest to the reflection ray, with the (α / α')² energy normalization.
      const Vec3f dl = light.position - h.p;
      const float dist = length(dl);
      if (!(dist > light.radius)) continue;
      const Vec3f wc = dl / dist;
      const Rgbf E = light.color / (dist * dist);
      if (shadow(wc, dist - light.radius)) continue;
      if (want_d && above(wc) && dot(sp.n_shading, wc) > 0)
        L += brdf_cos(sp, wo, wc, 1.0f, true, false) * E * term(wc, ls).diffuse;
      const Vec3f r = reflect(wo, sp.n_shading);
      const Vec3f to_ray = r * dot(dl, r) - dl;
      const Vec3f cp = dl + to_ray * saturate(light.radius / std::max(length(to_ray), 1e-12f));
      const Vec3f ws = normalize(cp);
      if (want_s && above(ws) && dot(sp.n_shading, ws) > 0) {
        const float a = roughness_to_alpha(std::max(sp.roughness, 0.02f));
        const float a2 = saturate(a + light.radius / (2 * dist));
        L += brdf_cos(sp, wo, ws, sqr(a / a2), false, true) * E * term(ws, ls).specular;
      }
    } else {
      // Reference: uniform sampling of the cone subtended by the sphere; radiance Le = I / (π r²).
      const Vec3f dl = light.position - h.p;
      const float dist = length(dl);
      if (!(dist > light.radius)) continue;
      const float sin2 = sqr(light.radius / dist), cos_max = safe_sqrt(1 - sin2);
      const Framef fr = Framef::from_z(dl / dist);
      const Rgbf Le = light.color / (kPi<float> * sqr(light.radius));
      const float inv_pdf = 2 * kPi<float> * (1 - cos_max);
      Rgbf acc(0.0f);
      for (int k = 0; k < set.area_samples; ++k) {
        const Vec3f wi = fr.to_world(sample_uniform_cone(sobol_2d<float>(uint32_t(k), ls + 1), cos_max));
        if (!above(wi) || !(dot(sp.n_shading, wi) > 0)) continue;
        const LobeTerms t = term(wi, hash_combine(ls, uint32_t(k)));
        if (!t.any()) continue;
        // Distance to the sphere's near surface along wi.
        const float b = dot(dl, wi), c = dot(dl, dl) - sqr(light.radius);
        const float tl = b - safe_sqrt(b * b - c);
        if (shadow(wi, tl * (1 - 1e-4f))) continue;
        acc += ms.per_lobe() ? shade(wi, 1.0f, want_d, want_s, t, Le * inv_pdf)
                             : brdf_cos(sp, wo, wi, 1.0f, want_d, want_s) * Le * (t.diffuse * inv_pdf);
      }
      L += acc / float(set.area_samples);
    }
  }
  return L;
}

// Hanika 2021 (RTG II ch. 4): shadow-ray origin on the smooth surface implied by the vertex normals.
Vec3f Renderer::Impl::hanika_offset(const Mesh& m, const Hit& h) {
  const auto& tr = m.tri[h.prim];
  return bump::hanika2021_shadow_origin(h.p, std::array<Vec3f, 3>{m.p[tr[0]], m.p[tr[1]], m.p[tr[2]]},
                                        std::array<Vec3f, 3>{m.n[tr[0]], m.n[tr[1]], m.n[tr[2]]},
                                        std::array<float, 3>{h.bary.x, h.bary.y, h.bary.z});
}

}  // namespace msh::render
