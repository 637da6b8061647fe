// The V-cavity microsurface profile (Torrance & Sparrow 1967; Cook & Torrance 1982, "A Reflectance Model for
// Computer Graphics") over a symmetric NDF, by default Beckmann (the Beckmann–Spizzichino + V-cavity
// microsurface). Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs" (JCGT
// 3(2)), in its V-cavity section, derives its masking from the microsurface made of symmetric V-shaped
// grooves and shows that it is an exact masking function for that profile: the visible normals it defines
// integrate to one.
//
// Unlike the Smith profile, the masking of a direction depends on the microfacet normal m:
//   G1(w, m) = χ⁺(w·m) min(1, 2 (n·m)(n·w) / (w·m))                   (Heitz 2014, V-cavity masking; n = +z)
//   G2(wo, wi, m) = min(G1(wo, m), G1(wi, m))                          (Cook & Torrance 1982, their G)
//   G2_uncorrelated(wo, wi, m) = G1(wo, m) G1(wi, m)
//   D_w(m) = G1(w, m) (w·m)⁺ D(m) / (w·n)                              (Heitz 2014, eq. 16)
// Visible-normal sampling (Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using the
// Distribution of Visible Normals", V-cavity case): draw m with pdf D(m)(n·m), let m' = (−m_x, −m_y, m_z)
// be the other facet of its groove, and keep m' with probability (w·m')⁺ / ((w·m)⁺ + (w·m')⁺), else m. The
// pdf of the result is D_w(m) because (w·m) + (w·m') = 2(n·m)(n·w) and D(m) = D(m').
//
// Domain: the NDF must be symmetric under m → m' (true for GGX and Beckmann with axis-aligned αx, αy);
// directions unit, in the shading frame. w.z < 0 is mirrored to −w (as the Smith samplers do). Every member
// is finite for finite unit inputs (grazing and the pole included).
#pragma once

#include <microshadow/math/vec.h>
#include <microshadow/microfacet/beckmann.h>

#include <algorithm>
#include <cmath>

namespace msh {

template <class Ndf>
class VCavity {
 public:
  using Scalar = typename Ndf::Scalar;
  using T = Scalar;

  VCavity() = default;
  explicit VCavity(const Ndf& ndf) : ndf_(ndf) {}
  const Ndf& ndf() const { return ndf_; }
  T alpha_x() const { return ndf_.alpha_x(); }
  T alpha_y() const { return ndf_.alpha_y(); }

  // NDF D(m) of the underlying distribution.
  T D(const Vec3<T>& m) const { return ndf_.D(m); }

  // G1(w, m) = χ⁺(w·m) min(1, 2 (n·m)(n·w)/(w·m)); 0 when w or m is below the horizon.
  T G1(const Vec3<T>& w, const Vec3<T>& m) const {
    const T wm = dot(w, m);
    if (!(wm > T(0)) || !(w.z > T(0)) || !(m.z > T(0))) return T(0);
    return std::min(T(1), T(2) * m.z * w.z / wm);
  }
  // Cook–Torrance G = min(G1(wo, m), G1(wi, m)).
  T G2(const Vec3<T>& wo, const Vec3<T>& wi, const Vec3<T>& m) const {
    return std::min(G1(wo, m), G1(wi, m));
  }
  T G2_uncorrelated(const Vec3<T>& wo, const Vec3<T>& wi, const Vec3<T>& m) const {
    return G1(wo, m) * G1(wi, m);
  }

  // D_w(m) = D(m) min((w·m)⁺, 2 (n·m)(n·w)) / (n·w): the G1 product written without the 0/0 at w·m = 0.
  // w.z < 0 uses −w; 0 at grazing w.
  T D(const Vec3<T>& w, const Vec3<T>& m) const {
    const Vec3<T> wu = w.z < T(0) ? -w : w;
    if (!(wu.z > T(0)) || !(m.z > T(0))) return T(0);
    const T wm = std::max(T(0), dot(wu, m));
    return ndf_.D(m) * std::min(wm, T(2) * m.z * wu.z) / wu.z;
  }
  T PDF(const Vec3<T>& w, const Vec3<T>& m) const { return D(w, m); }

  // Heitz & d'Eon 2014 V-cavity sampler: u draws m from D(m)(n·m) (the NDF's sample_ndf), u_flip ∈ [0, 1)
  // chooses between m and its groove partner m'. pdf D_w(m).
  Vec3<T> Sample_wm(const Vec3<T>& w, Vec2<T> u, T u_flip) const {
    const Vec3<T> wu = w.z < T(0) ? -w : w;
    const Vec3<T> m = ndf_.sample_ndf(u);
    const Vec3<T> mp(-m.x, -m.y, m.z);
    const T a = std::max(T(0), dot(wu, m)), b = std::max(T(0), dot(wu, mp));
    return u_flip * (a + b) < b ? mp : m;
  }

 private:
  Ndf ndf_{};
};

// The Beckmann–Spizzichino + V-cavity microsurface.
template <class T>
using BeckmannVCavity = VCavity<Beckmann<T>>;

}  // namespace msh
