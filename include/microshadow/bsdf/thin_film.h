// Thin-film interference on a substrate (RTR4 §9.11.2): Belcour & Barla 2017, "A Practical Extension to
// Microfacet Theory for the Modeling of Varying Iridescence" (SIGGRAPH). The Airy reflectance of a film
// (air | film η2, thickness d | substrate η3 + iκ3) is written as a Fourier series in the optical path
// difference OPD = 2 η2 d cos θ2, and each term is integrated analytically against the CIE 1931 XYZ matching
// functions approximated by Gaussians in the frequency (1/λ) domain; series truncated at m = 3 (their
// choice).
//
// Units and conventions: thickness d in nanometres (visible effects for d ≲ 1000 nm); η2 = film IOR (real,
// ≥ 1), η3 + iκ3 = substrate IOR (κ3 = 0: dielectric), all relative to the outside medium (air, η1 = 1) and
// wavelength-independent (the method's assumption). cos θ1 = h·l for a microfacet BRDF. Output: linear
// Rec.709 RGB, white-balanced so that a spectrally flat reflectance R gives RGB = (R, R, R) (Belcour & Barla
// output CIE RGB with an E-white; we use XYZ → Rec.709 followed by a per-channel scale that maps E-white to
// (1,1,1)), clamped to [0,1] like the reference implementation. Like the paper's code, η2 blends towards 1
// over d ∈ [0, 30] nm (smoothstep), so d = 0 gives exactly the bare substrate Fresnel and the truncated
// series stays continuous there.
#pragma once

#include <microshadow/math/color.h>
#include <microshadow/math/vec.h>

#include <complex>

namespace msh::bsdf {

namespace thin_film_fresnel {

// Complex Fresnel amplitudes (s, p) for incidence from a real medium n1 onto n2 + i k2 (Born & Wolf §1.5),
// in the convention r21 = −r12, t12 t21 = 1 − r12² used by the Airy sum. cos1 in [0,1].
template <class T>
void fresnel_amplitudes(T cos1, T n1, std::complex<T> n2, std::complex<T>& rs, std::complex<T>& rp) {
  using C = std::complex<T>;
  const T sin2 = std::max(T(0), T(1) - cos1 * cos1);
  const C cos2 = std::sqrt(C(T(1)) - (n1 * n1 * sin2) / (n2 * n2));
  rs = (n1 * cos1 - n2 * cos2) / (n1 * cos1 + n2 * cos2);
  rp = (n2 * cos1 - n1 * cos2) / (n2 * cos1 + n1 * cos2);
}

// Fourier transform of the XYZ matching functions (Belcour & Barla 2017, supplemental code): Gaussian fits in
// frequency space, evaluated at optical path difference `opd` (nm) with phase shift `shift`; normalized so
// that sensitivity(0, 0) ≈ (1, 1, 1).
template <class T>
Rgb<T> sensitivity(T opd_nm, T shift) {
  const T phase = T(2) * kPi<T> * opd_nm * T(1e-9);
  const T val[3] = {T(5.4856e-13), T(4.4201e-13), T(5.2481e-13)};
  const T pos[3] = {T(1.6810e+06), T(1.7953e+06), T(2.2084e+06)};
  const T var[3] = {T(4.3278e+09), T(9.3046e+09), T(6.6121e+09)};
  T xyz[3];
  for (int i = 0; i < 3; ++i)
    xyz[i] = val[i] * std::sqrt(T(2) * kPi<T> * var[i]) * std::cos(pos[i] * phase + shift) *
             std::exp(-var[i] * phase * phase);
  xyz[0] += T(9.7470e-14) * std::sqrt(T(2) * kPi<T> * T(4.5282e+09)) *
            std::cos(T(2.2399e+06) * phase + shift) * std::exp(T(-4.5282e+09) * phase * phase);
  const T s = T(1) / T(1.0685e-7);
  return {xyz[0] * s, xyz[1] * s, xyz[2] * s};
}

// CIE XYZ → linear Rec.709 (IEC 61966-2-1), then divided per channel by the image of E-white (1,1,1) so a
// flat spectrum stays grey.
template <class T>
Rgb<T> xyz_to_rgb_ewhite(const Rgb<T>& xyz) {
  const T m[3][3] = {{T(3.2404542), T(-1.5371385), T(-0.4985314)},
                     {T(-0.9692660), T(1.8760108), T(0.0415560)},
                     {T(0.0556434), T(-0.2040259), T(1.0572252)}};
  T out[3];
  for (int i = 0; i < 3; ++i) {
    const T w = m[i][0] + m[i][1] + m[i][2];
    out[i] = (m[i][0] * xyz.r + m[i][1] * xyz.g + m[i][2] * xyz.b) / w;
  }
  return {out[0], out[1], out[2]};
}

}  // namespace thin_film_fresnel

template <class T>
struct ThinFilm {
  T thickness_nm = T(400);   // film thickness d (nm), ≥ 0
  T film_ior = T(1.45);      // η2 ≥ 1 (values below 1 are clamped to 1)
  T substrate_ior = T(2.9);  // η3 > 0
  T substrate_k = T(3.0);    // κ3 ≥ 0 (extinction; 0 for a dielectric substrate)

  // Belcour & Barla 2017 (§4, eqs. 9–12 and the supplemental code): spectrally integrated reflectance of the
  // film stack at incidence cos θ1 = h·l, as linear Rec.709 RGB in [0,1]. Finite for every input; cos θ1 ≤ 0
  // is treated as grazing (cos θ1 = 0).
  Rgb<T> reflectance(T cos1) const {
    using C = std::complex<T>;
    cos1 = saturate(cos1);
    const T d = std::max(thickness_nm, T(0));
    // smoothstep(0, 30 nm, d): η2 → 1 as d → 0 (Belcour & Barla's code, Dinc in μm: smoothstep(0, 0.03,
    // Dinc)).
    const T s = saturate(d / T(30));
    const T eta2 = lerp(s * s * (T(3) - T(2) * s), T(1), std::max(film_ior, T(1)));
    const T sin2_1 = T(1) - cos1 * cos1;
    const T cos2 = safe_sqrt(T(1) - sin2_1 / (eta2 * eta2));  // η2 ≥ 1: no total internal reflection

    // First interface (air → film, real): intensities and phases (0 or π) per polarization.
    C r12s, r12p;
    thin_film_fresnel::fresnel_amplitudes(cos1, T(1), C(eta2), r12s, r12p);
    // Second interface (film → substrate), complex.
    C r23s, r23p;
    thin_film_fresnel::fresnel_amplitudes(
        cos2, eta2, C(std::max(substrate_ior, T(1e-6)), std::max(substrate_k, T(0))), r23s, r23p);
    const T opd = T(2) * eta2 * d * cos2;

    Rgb<T> xyz(T(0));
    const C r12v[2] = {r12s, r12p}, r23v[2] = {r23s, r23p};
    for (int pol = 0; pol < 2; ++pol) {
      const T R12 = std::norm(r12v[pol]);
      const T R23 = std::min(std::norm(r23v[pol]), T(1));
      const T phi12 = std::real(r12v[pol]) < T(0) ? kPi<T> : T(0);
      const T phi21 = kPi<T> - phi12;
      const T phi23 = std::arg(r23v[pol]);
      const T phi2 = phi21 + phi23;
      const T T121 = T(1) - R12;
      const T R123 = R12 * R23;
      const T r123 = std::sqrt(R123);
      // Airy sum: R(δ) = C0 + 2 Σ_m C_m cos(m(δ + φ2)), C0 = R12 + Rs, C_m = (Rs − T121) r123^m.
      const T Rs = R123 < T(1) ? T121 * T121 * R23 / (T(1) - R123) : T(0);
      Rgb<T> acc = thin_film_fresnel::sensitivity(T(0), T(0)) * (R12 + Rs);
      T Cm = Rs - T121;
      for (int m = 1; m <= 3; ++m) {
        Cm *= r123;
        acc += thin_film_fresnel::sensitivity(T(m) * opd, T(m) * phi2) * (T(2) * Cm);
      }
      xyz += acc * T(0.5);  // unpolarized: mean of s and p
    }
    // Divide by the DC sensitivity so a flat spectrum gives XYZ = (R, R, R) exactly (the fit gives ≈ 1 ±
    // 1e-3).
    const Rgb<T> rgb = thin_film_fresnel::xyz_to_rgb_ewhite(xyz / thin_film_fresnel::sensitivity(T(0), T(0)));
    return {saturate(rgb.r), saturate(rgb.g), saturate(rgb.b)};
  }
};

}  // namespace msh::bsdf
