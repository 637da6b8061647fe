// Specular microfacet BRDF (RTR4 9.34; Walter et al. 2007) for any microfacet distribution with a Smith
// masking function, its VNDF importance sampling (Heitz 2014/2018, Dupuy & Benyoub 2023), and the two-lobe
// GGX NDF that Imageworks exposes as one extended NDF (Kulla & Conty 2017; RTR4 §9.8.1 "multiple specular
// lobes").
//
// A distribution `Dist` provides: D(m) (normalized, ∫ D (n·m) dm = 1), G1(w) (Smith, no χ⁺ factor), and for
// sampling Sample_wm(w, u) / PDF(w, m) (visible normals). msh::GGX<T> fits; so does GGXMixture<T> below.
// Local shading frame, n = +z; wo = view v, wi = light l. Fresnel is applied by the caller with cos_hl = h·l.
#pragma once

#include <microshadow/math/sampling.h>
#include <microshadow/math/vec.h>
#include <microshadow/microfacet/ggx.h>

#include <optional>

namespace msh::bsdf {

// G2Form, smith_g2 and smith_g2_over_g1o: microfacet/smith.h (one definition for the library).
using msh::G2Form;
using msh::smith_g2;
using msh::smith_g2_over_g1o;

// The value of 9.34 without Fresnel, and the cosine its Fresnel factor takes.
template <class T>
struct SpecularEval {
  T f1 = T(0);      // D(h) G2(l, v, h) / (4 |n·l| |n·v|)
  T cos_hl = T(1);  // h·l (= h·v), the argument of F(h, l)
};

// RTR4 9.34 with F = 1 and any G2 form given as g2(wo, wi, h) (zero where microfacet_specular is), e.g. the
// direction-correlated forms of microfacet/masking.h: [&](auto& o, auto& i, auto& h) { return
// G2_direction_correlated(ndf, o, i, h, λ); }.
template <class T, class Dist, class G2Fn>
SpecularEval<T> microfacet_specular_custom_g2(const Dist& dist, const Vec3<T>& wo, const Vec3<T>& wi,
                                              G2Fn&& g2) {
  SpecularEval<T> r;
  if (!(wo.z > T(0)) || !(wi.z > T(0))) return r;
  const Vec3<T> hs = wo + wi;
  const T l2 = dot(hs, hs);
  if (!(l2 > T(1e-24))) return r;
  const Vec3<T> h = hs / std::sqrt(l2);
  r.cos_hl = saturate(dot(h, wi));
  const T f = dist.D(h) * g2(wo, wi, h) / (T(4) * wo.z * wi.z);
  r.f1 = std::isfinite(f) ? f : T(0);
  return r;
}

// RTR4 9.34 with F = 1 and the Smith G2 of `form`. Zero when either direction is at or below the horizon, or
// when l = −v (h undefined).
template <class T, class Dist>
SpecularEval<T> microfacet_specular(const Dist& dist, const Vec3<T>& wo, const Vec3<T>& wi,
                                    G2Form form = G2Form::HeightCorrelated) {
  return microfacet_specular_custom_g2(dist, wo, wi, [&](const Vec3<T>& o, const Vec3<T>& i, const Vec3<T>&) {
    return smith_g2(dist.G1(o), dist.G1(i), form);
  });
}

// Solid-angle pdf of wi under VNDF sampling: D_wo(h) / (4 |wo·h|) (Heitz 2014, eq. 17 + reflection Jacobian).
template <class T, class Dist>
T microfacet_specular_pdf(const Dist& dist, const Vec3<T>& wo, const Vec3<T>& wi) {
  if (!(wo.z > T(0)) || !(wi.z > T(0))) return T(0);
  const Vec3<T> hs = wo + wi;
  const T l2 = dot(hs, hs);
  if (!(l2 > T(1e-24))) return T(0);
  const Vec3<T> h = hs / std::sqrt(l2);
  const T c = dot(wo, h);
  if (!(c > T(0))) return T(0);
  const T p = dist.PDF(wo, h) / (T(4) * c);
  return std::isfinite(p) ? p : T(0);
}

template <class T>
struct SpecularSample {
  Vec3<T> wi;
  T pdf = T(0);
  T weight_f1 = T(0);  // f1 · (n·l) / pdf = G2 / G1(wo): the F = 1 estimator weight
  T cos_hl = T(1);
};

// Samples wi = reflect(wo, m), m ~ D_wo (visible normals). Empty when wi falls below the horizon (that
// sample carries zero weight: single-scattering energy loss).
template <class T, class Dist>
std::optional<SpecularSample<T>> sample_microfacet_specular(const Dist& dist, const Vec3<T>& wo, Vec2<T> u,
                                                            G2Form form = G2Form::HeightCorrelated) {
  if (!(wo.z > T(0))) return std::nullopt;
  const Vec3<T> m = dist.Sample_wm(wo, u);
  const T c = dot(wo, m);
  if (!(c > T(0))) return std::nullopt;
  const Vec3<T> wi = reflect(wo, m);
  if (!(wi.z > T(0))) return std::nullopt;
  SpecularSample<T> s;
  s.wi = wi;
  s.pdf = dist.PDF(wo, m) / (T(4) * c);
  if (!(s.pdf > T(0)) || !std::isfinite(s.pdf)) return std::nullopt;
  s.weight_f1 = smith_g2_over_g1o(dist.G1(wo), dist.G1(wi), form);
  s.cos_hl = saturate(c);
  return s;
}

// Two GGX lobes mixed at the NDF level, D = (1 − w) D_a + w D_b (Imageworks, Kulla & Conty 2017: "a mix of
// two GGX NDFs exposed as an extended NDF"; RTR4 §9.8.1). Smith Λ is linear in the slope distribution, so
// Λ = (1 − w) Λ_a + w Λ_b exactly, and the VNDF is sampled exactly by picking lobe b with probability
// w G1(wo) / G1_b(wo), then sampling that lobe's VNDF.
template <class T>
class GGXMixture {
 public:
  GGXMixture(const GGX<T>& a, const GGX<T>& b, T w) : a_(a), b_(b), w_(saturate(w)) {}
  const GGX<T>& a() const { return a_; }
  const GGX<T>& b() const { return b_; }
  T weight() const { return w_; }

  T D(const Vec3<T>& wm) const { return (T(1) - w_) * a_.D(wm) + w_ * b_.D(wm); }
  // G1 / |cos θ| = 1 / ((1 − w) |cos|/G1_a + w |cos|/G1_b): finite at grazing.
  T G1_over_cos(const Vec3<T>& w) const {
    const T ia = a_.G1_over_cos(w), ib = b_.G1_over_cos(w);
    if (!(ia > T(0)) || !(ib > T(0))) return T(0);
    return T(1) / ((T(1) - w_) / ia + w_ / ib);
  }
  T G1(const Vec3<T>& w) const { return std::min(T(1), std::abs(w.z) * G1_over_cos(w)); }
  T G2(const Vec3<T>& wo, const Vec3<T>& wi) const {
    return smith_g2(G1(wo), G1(wi), G2Form::HeightCorrelated);
  }
  // VNDF D_w(m) = G1(w) max(0, w·m) D(m) / |w·n|.
  T D(const Vec3<T>& w, const Vec3<T>& wm) const {
    const Vec3<T> wu = w.z < T(0) ? -w : w;
    return G1_over_cos(wu) * std::max(T(0), dot(wu, wm)) * D(wm);
  }
  T PDF(const Vec3<T>& w, const Vec3<T>& wm) const { return D(w, wm); }
  // Probability of drawing the visible normal from lobe b.
  T prob_b(const Vec3<T>& w) const {
    if (w_ <= T(0)) return T(0);
    if (w_ >= T(1)) return T(1);
    const T ib = b_.G1_over_cos(w);
    return ib > T(0) ? saturate(w_ * G1_over_cos(w) / ib) : w_;
  }
  Vec3<T> Sample_wm(const Vec3<T>& w, Vec2<T> u) const {
    const T pb = prob_b(w);
    if (u.x < pb) return b_.Sample_wm(w, Vec2<T>(std::min(u.x / pb, kOneMinusEpsilon<T>), u.y));
    return a_.Sample_wm(w, Vec2<T>(std::min((u.x - pb) / (T(1) - pb), kOneMinusEpsilon<T>), u.y));
  }

 private:
  GGX<T> a_, b_;
  T w_;
};

// Imageworks anisotropy (RTR4 9.55): αx = r²(1 + k), αy = r²(1 − k), k in [−1, 1].
template <class T>
GGX<T> ggx_imageworks_aniso(T roughness, T k) {
  const T a = roughness * roughness;
  return GGX<T>(a * (T(1) + k), a * (T(1) - k));
}

}  // namespace msh::bsdf
