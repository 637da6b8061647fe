// microshadow: shaders/portable/micro_shadowing_area.h, written once for GLSL and HLSL in the portable dialect
// (docs/shaders.md): HLSL type names and the msh_* spellings that shaders/glsl/msh_prelude.glsl and
// shaders/hlsl/msh_prelude.hlsl define. Not included directly: GLSL `#include "shaders/glsl/micro_shadowing_area.glsl"`,
// HLSL `#include "shaders/hlsl/micro_shadowing_area.hlsl"` (their top comments say how).
// Area-light micro-shadowing. Needs micro_shadowing (the point terms) and micro_shadowing_fit (the
// generic term's ALU fit) included first. Ports of include/microshadow/occlusion/micro_shadowing_area.h
// (definitions, derivations and measured errors: docs/area-lights.md).
//
// A spherical-cap light (a sphere light, or a disk facing the point) of angular radius rho (radians,
// [0, pi/2]) centred at N.L = n_dot_l, Lambertian receiver: M_area = the point term averaged over the cap
// with the (n.l) weight. rho = 0 returns the point term. vis = micro-occlusion visibility in projected solid
// angle (cone half-angle t: cos t = sqrt(1 - vis)).
// Precision (float32 on lavapipe vs the C++ functions in double at the same float inputs,
// tests/test_shaders_micro_shadowing_area.cpp): stated per function. Accuracy of each form against the
// exact quadrature: docs/area-lights.md. NaN/Inf inputs are not guaranteed on GPUs.
#ifndef MSH_MICRO_SHADOWING_AREA_PORTABLE_H
#define MSH_MICRO_SHADOWING_AREA_PORTABLE_H

// Defined in micro_shadowing_fit; declared here so that the files also work concatenated in name order
// (the browser viewer), where this file comes first.
MSH_FN float msh_ms_generic_vndf_alu(float vis, float n_dot_l, float n_dot_v, float roughness);
// Half-angle of the visibility cone, atan(sqrt(vis), sqrt(1 - vis)).
MSH_FN float msh_ms_cone_angle(float vis) {
  float v = clamp(vis, 0.0f, 1.0f);
  return msh_atan2(sqrt(v), sqrt(1.0f - v));
}

// The spherical triangle with sides a, b, c in the float-stable forms of msh::ms::spherical_geometry::ThinTriangle:
// x = sqrt(G) (Gram determinant), y = cos a - cos b cos c, z = cos b - cos a cos c.
MSH_FN float3 msh_ms_thin_triangle(float a, float b, float c) {
  float s = 0.5f * (a + b + c);
  float A = sin(s), B = sin(s - a), C = sin(s - b), D = sin(s - c);
  return float3(2.0f * sqrt(max(0.0f, A * B * C * D)), A * B - C * D, A * C - B * D);
}
MSH_FN float msh_ms_atan2_safe(float y, float x) { return (x == 0.0f && y == 0.0f) ? 0.0f : msh_atan2(y, x); }

// Solid angle of the intersection of two caps of radii r1, r2 in [0, pi/2], axes gamma apart (Mazonka 2012,
// "Solid Angle of Conical Surfaces, Polyhedral Cones, and Intersecting Spherical Caps"), in the float-stable
// form 4 w1 sin^2(r1/2) + 4 w2 sin^2(r2/2) - 2 E (E by L'Huilier). |diff| vs C++ double <= 1e-4 sr
// (2.0e-5 measured).
MSH_FN float msh_ms_cap_intersection_solid_angle(float r1, float r2, float gamma) {
  r1 = clamp(r1, 0.0f, 0.5f * MSH_MS_PI), r2 = clamp(r2, 0.0f, 0.5f * MSH_MS_PI), gamma = clamp(gamma, 0.0f, MSH_MS_PI);
  if (gamma >= r1 + r2) return 0.0f;
  float sm = sin(0.5f * min(r1, r2));
  float full = 4.0f * MSH_MS_PI * sm * sm;
  if (gamma <= abs(r1 - r2)) return full;
  float3 t = msh_ms_thin_triangle(r1, r2, gamma);
  float w1 = msh_ms_atan2_safe(t.x, t.z), w2 = msh_ms_atan2_safe(t.x, t.y);
  float s = 0.5f * (r1 + r2 + gamma);
  float p = tan(0.5f * s) * tan(0.5f * (s - r1)) * tan(0.5f * (s - r2)) * tan(0.5f * (s - gamma));
  float ex = 4.0f * atan(sqrt(max(0.0f, p)));
  float s1 = sin(0.5f * r1), s2 = sin(0.5f * r2);
  return clamp(4.0f * w1 * s1 * s1 + 4.0f * w2 * s2 * s2 - 2.0f * ex, 0.0f, full);
}

// Oat & Sander 2007 ("Ambient Aperture Lighting"): the smaller cap's area times smoothstep(0, 1, 1 - (gamma -
// |r1 - r2|)/(r1 + r2 - |r1 - r2|)). An approximation of the above (error: docs/area-lights.md).
// |diff| vs C++ double <= 1e-4 sr (8.7e-6 measured).
MSH_FN float msh_ms_cap_intersection_solid_angle_oat_sander(float r1, float r2, float gamma) {
  r1 = clamp(r1, 0.0f, 0.5f * MSH_MS_PI), r2 = clamp(r2, 0.0f, 0.5f * MSH_MS_PI), gamma = clamp(gamma, 0.0f, MSH_MS_PI);
  float sm = sin(0.5f * min(r1, r2));
  float full = 4.0f * MSH_MS_PI * sm * sm;
  float diff = abs(r1 - r2);
  if (gamma <= diff) return full;
  if (gamma >= r1 + r2) return 0.0f;
  float x = clamp(1.0f - (gamma - diff) / (r1 + r2 - diff), 0.0f, 1.0f);
  return full * x * x * (3.0f - 2.0f * x);
}

// Integral of (n.l) over the cap (radius rho, centre theta_c from n) intersected with the cone n.l > cos t
// (t = pi/2: the horizon): exact, from the boundary formula (Arvo 1995, "Applications of Irradiance
// Tensors"), E = cos(theta_c) w1 sin^2(rho) - cos(rho) sqrt(G) + w2 sin^2(t). |diff| vs C++ double <= 5e-5
// (6.4e-6 measured).
MSH_FN float msh_ms_cap_cone_projected_solid_angle(float rho, float theta_c, float t) {
  rho = clamp(rho, 0.0f, 0.5f * MSH_MS_PI), t = clamp(t, 0.0f, 0.5f * MSH_MS_PI), theta_c = clamp(theta_c, 0.0f, MSH_MS_PI);
  float sr = sin(rho), st = sin(t), cc = cos(theta_c);
  if (theta_c >= rho + t) return 0.0f;
  if (theta_c <= t - rho) return MSH_MS_PI * sr * sr * cc;
  if (theta_c <= rho - t) return MSH_MS_PI * st * st;
  float3 g = msh_ms_thin_triangle(t, rho, theta_c);
  float w1 = msh_ms_atan2_safe(g.x, g.y), w2 = msh_ms_atan2_safe(g.x, g.z);
  return max(0.0f, cc * w1 * sr * sr - cos(rho) * g.x + w2 * st * st);
}

// acos as atan(sqrt((1 - x)(1 + x)), x): GPU acos may be a coarse polynomial (1.6e-4 rad error measured on
// lavapipe, within the Vulkan precision rules); atan is ~3e-6 there.
MSH_FN float msh_ms_acos_accurate(float x) {
  x = clamp(x, -1.0f, 1.0f);
  return msh_atan2(sqrt(max(0.0f, (1.0f - x) * (1.0f + x))), x);
}
MSH_FN float msh_ms_cap_theta(float n_dot_l) { return msh_ms_acos_accurate(n_dot_l); }

// The cap-over-cone measure of the three cap forms below, of the cone of half-angle t and the cap of angular
// radius rho whose axis is th from the normal: 0 = (n.l)-weighted (projected) solid angle, 1 = solid angle
// (Mazonka 2012), 2 = Oat & Sander 2007's solid angle. Precision: stated per form below.
MSH_FN float msh_ms_cap_measure(int form, float rho, float t, float th) {
  if (form == 0) return msh_ms_cap_cone_projected_solid_angle(rho, th, t);
  if (form == 1) return msh_ms_cap_intersection_solid_angle(rho, t, th);
  return msh_ms_cap_intersection_solid_angle_oat_sander(rho, t, th);
}
// measure(cap within the visibility cone) / measure(cap above the horizon) for msh_ms_cap_measure's form;
// rho = 0 returns the point term. Precision: stated per form below.
MSH_FN float msh_ms_reference_step_area_cap_form(int form, float vis, float n_dot_l, float rho) {
  rho = clamp(rho, 0.0f, 0.5f * MSH_MS_PI);
  if (!(rho > 0.0f)) return msh_ms_reference_step(vis, n_dot_l);
  float th = msh_ms_cap_theta(n_dot_l), t = msh_ms_cone_angle(vis);
  float den = msh_ms_cap_measure(form, rho, 0.5f * MSH_MS_PI, th);
  return den > 0.0f ? clamp(msh_ms_cap_measure(form, rho, t, th) / den, 0.0f, 1.0f) : 0.0f;
}

// The reference step over a cap light, Lambertian receiver, EXACT (cosine-weighted): E(cap, cone) /
// E(cap, horizon). |diff| vs C++ double <= 1.5e-3 = 0.4/255 for rho >= 1 degree (6.6e-4 measured; a light
// straddling the cone amplifies the GPU's trigonometric error by ~1/rho); accuracy vs the exact quadrature:
// docs/area-lights.md.
MSH_FN float msh_ms_reference_step_area_cap(float vis, float n_dot_l, float rho) {
  return msh_ms_reference_step_area_cap_form(0, vis, n_dot_l, rho);
}

// The same ratio with plain solid angles (Mazonka 2012): drops the (n.l) weight inside the light (what an
// ambient-aperture style engine computes; its error: docs/area-lights.md). |diff| vs C++ double <= 1.5e-3
// for rho >= 1 degree (1.1e-4 measured).
MSH_FN float msh_ms_reference_step_area_cap_solid_angle(float vis, float n_dot_l, float rho) {
  return msh_ms_reference_step_area_cap_form(1, vis, n_dot_l, rho);
}

// The same with Oat & Sander 2007 for both solid angles. |diff| vs C++ double <= 1.5e-3 for rho >= 1 degree
// (1.2e-4 measured).
MSH_FN float msh_ms_reference_step_area_cap_oat_sander(float vis, float n_dot_l, float rho) {
  return msh_ms_reference_step_area_cap_form(2, vis, n_dot_l, rho);
}

// ---- Product rule for terms of N.L only (msh::ms::area_cap_lambert with n = 4) ------------------------------

#define MSH_MS_AREA_BRINCK_MAXIMOV_2016 1
#define MSH_MS_AREA_CHAN_2018 2
#define MSH_MS_AREA_PART1_ANALYTIC 3
#define MSH_MS_AREA_GENERIC_VNDF_ALU 4

MSH_FN float msh_ms_area_point_term(int term, float vis, float z, float n_dot_v, float roughness) {
  if (term == MSH_MS_AREA_BRINCK_MAXIMOV_2016) return msh_ms_brinck_maximov2016(vis, z);
  if (term == MSH_MS_AREA_CHAN_2018) return msh_ms_chan2018(vis, z);
  if (term == MSH_MS_AREA_PART1_ANALYTIC) return msh_ms_part1_analytic(vis, z);
  return msh_ms_generic_vndf_alu(vis, z, n_dot_v, roughness);
}
// The N.L values where the term kinks or turns sharply (panel edges), -1: none. Part 1: its kink and where it
// reaches 0.03; generic: the early-out, the cone and the cone +- 4 max(alpha, 0.02) sin t.
MSH_FN float4 msh_ms_area_term_kinks(int term, float vis, float roughness) {
  float v = clamp(vis, 0.0f, 1.0f);
  if (term == MSH_MS_AREA_BRINCK_MAXIMOV_2016) return float4(1.0f - 2.0f * v * v, 2.0f - 2.0f * v * v, -1.0f, -1.0f);
  if (term == MSH_MS_AREA_CHAN_2018) return float4(msh_ms_cone_cos(v), -1.0f, -1.0f, -1.0f);
  if (term == MSH_MS_AREA_PART1_ANALYTIC) {
    float cp = sqrt(max(0.0f, 1.0f - v * v * v * v * v));
    return float4(cp, cp * exp2(log2(0.03f) * v / 0.75f), -1.0f, -1.0f);
  }
  float c = msh_ms_cone_cos(v), r = clamp(roughness, 0.0f, 1.0f);
  float w = max(r * r, 0.02f) * sqrt(v);
  return float4(1.0f - 2.0f * v, c, c - 4.0f * w, c + 4.0f * w);
}

// Complementary CDF in z = n.l of the cosine-weighted cap: S(z) = E(cap, n.l > z) / E(cap, n.l > 0).
MSH_FN float msh_ms_cap_ccdf(float z, float rho, float th, float den, float z_lo, float z_hi) {
  if (!(z > z_lo)) return 1.0f;
  if (!(z < z_hi) || !(den > 0.0f)) return 0.0f;
  return clamp(msh_ms_cap_cone_projected_solid_angle(rho, th, msh_ms_acos_accurate(z)) / den, 0.0f, 1.0f);
}

// M_area of the term (one of MSH_MS_AREA_*) over a cap light, Lambertian receiver: on each N.L panel between
// the cap's ends, the term's kinks (msh_ms_area_term_kinks) and cos|theta_c - rho|, the term's interpolating
// polynomial at 4 Gauss-Legendre nodes integrated exactly against the cap's closed-form CDF (by parts).
// n_dot_v and roughness are read by the generic ALU term only. 4 evaluations of the term and 5 of the CDF per
// panel (at most 6 panels). |diff| vs C++ double <= 2e-3 = 0.5/255 for rho >= 1 degree (9.4e-4 measured);
// accuracy vs the exact quadrature: docs/area-lights.md.
MSH_FN float msh_ms_area_cap_lambert(int term, float vis, float n_dot_l, float n_dot_v, float roughness, float rho) {
  rho = clamp(rho, 0.0f, 0.5f * MSH_MS_PI);
  float nl = clamp(n_dot_l, -1.0f, 1.0f);
  if (!(rho > 0.0f)) return msh_ms_area_point_term(term, vis, nl, n_dot_v, roughness);
  float th = msh_ms_cap_theta(nl);
  float den = msh_ms_cap_cone_projected_solid_angle(rho, th, 0.5f * MSH_MS_PI);
  float z_lo = max(0.0f, cos(min(MSH_MS_PI, th + rho)));
  float z_b = cos(abs(th - rho));
  float z_hi = th < rho ? 1.0f : z_b;
  if (!(den > 0.0f) || !(z_hi > z_lo)) return 0.0f;
  MSH_STATIC_CONST float X[4] = MSH_ARRAY(float, 4)
      0.06943184420297371f, 0.33000947820757187f, 0.66999052179242813f, 0.93056815579702629f MSH_ARRAY_END;
  MSH_STATIC_CONST float L0[4] = MSH_ARRAY(float, 4)
      1.5267881254572664f, -0.8136324494869271f, 0.40076152031165035f, -0.11391719628198989f MSH_ARRAY_END;
  MSH_STATIC_CONST float L1[4] = MSH_ARRAY(float, 4)
      -0.11391719628198982f, 0.40076152031165f, -0.8136324494869264f, 1.5267881254572657f MSH_ARRAY_END;
  // E[j][i] = w_j L_i'(x_j): row j = node.
  MSH_STATIC_CONST float E[16] = MSH_ARRAY(float, 16)
      -1.1590524262142825f, 1.6906282616122867f, -0.7335501572643867f, 0.20197432186638278f,
      -0.4940375280205474f, -0.25069398334779586f, 0.9590904657302993f, -0.21435895436195604f,
      0.21435895436195612f, -0.9590904657302998f, 0.2506939833477962f, 0.4940375280205473f,
      -0.20197432186638287f, 0.7335501572643869f, -1.6906282616122863f, 1.1590524262142823f MSH_ARRAY_END;
  float4 k = msh_ms_area_term_kinks(term, vis, roughness);
  float pts[6] = MSH_ARRAY(float, 6) k.x, k.y, k.z, k.w, z_b, z_hi MSH_ARRAY_END;
  for (int i = 1; i < 5; ++i)  // insertion sort of the interior points (z_hi stays last)
    for (int j = i; j > 0; --j)
      if (pts[j - 1] > pts[j]) { float tmp = pts[j]; pts[j] = pts[j - 1]; pts[j - 1] = tmp; }
  float sum = 0.0f, a = z_lo, Sa = 1.0f;
  for (int p = 0; p < 6; ++p) {
    float b = pts[p] > z_lo ? min(pts[p], z_hi) : z_lo;
    if (!(b > a)) continue;
    float h = b - a, Sb = msh_ms_cap_ccdf(b, rho, th, den, z_lo, z_hi);
    float S[4], M[4];
    for (int j = 0; j < 4; ++j) {
      float z = a + h * X[j];
      S[j] = msh_ms_cap_ccdf(z, rho, th, den, z_lo, z_hi);
      M[j] = msh_ms_area_point_term(term, vis, z, n_dot_v, roughness);
    }
    for (int i = 0; i < 4; ++i) {
      float W = L0[i] * Sa - L1[i] * Sb;
      for (int j = 0; j < 4; ++j) W += E[4 * j + i] * S[j];
      sum += W * M[i];
    }
    a = b, Sa = Sb;
  }
  return clamp(sum, 0.0f, 1.0f);
}

// Convenience forms (Lambertian receiver, cap light of radius rho).
MSH_FN float msh_ms_brinck_maximov2016_area_cap(float vis, float n_dot_l, float rho) {
  return msh_ms_area_cap_lambert(MSH_MS_AREA_BRINCK_MAXIMOV_2016, vis, n_dot_l, 1.0f, 0.5f, rho);
}
MSH_FN float msh_ms_chan2018_area_cap(float vis, float n_dot_l, float rho) {
  return msh_ms_area_cap_lambert(MSH_MS_AREA_CHAN_2018, vis, n_dot_l, 1.0f, 0.5f, rho);
}
MSH_FN float msh_ms_part1_analytic_area_cap(float vis, float n_dot_l, float rho) {
  return msh_ms_area_cap_lambert(MSH_MS_AREA_PART1_ANALYTIC, vis, n_dot_l, 1.0f, 0.5f, rho);
}
MSH_FN float msh_ms_generic_vndf_alu_area_cap(float vis, float n_dot_l, float n_dot_v, float roughness, float rho) {
  return msh_ms_area_cap_lambert(MSH_MS_AREA_GENERIC_VNDF_ALU, vis, n_dot_l, n_dot_v, roughness, rho);
}

// ---- disk and rectangle lights, Lambertian receiver: the equivalent cap ----------------------------------
// The cap with the light's vector form factor F = integral of l over the light (unclipped): axis F/|F|,
// sin^2(rho) = |F|/pi (msh::micro_shadowing::equivalent_cap, docs/area-lights.md sec. 5); feed it to any cap
// form above, e.g. msh_ms_brinck_maximov2016_area_cap(vis, e.x, e.y) with e = msh_ms_equivalent_cap(F, c).

// F of a quad light with corners v0..v3 (directions from the shading point, any length, either winding):
// Lambert's formula 0.5 sum theta_i n_i (Arvo 1995). |diff| vs C++ double <= 2e-5 (per component; F and
// the disk's below together 2.7e-6 measured).
MSH_FN float3 msh_ms_quad_vector_form_factor(float3 v0, float3 v1, float3 v2, float3 v3) {
  float3 p[4] =
      MSH_ARRAY(float3, 4) normalize(v0), normalize(v1), normalize(v2), normalize(v3) MSH_ARRAY_END;
  float3 F = float3(0.0f, 0.0f, 0.0f), m = float3(0.0f, 0.0f, 0.0f);
  for (int i = 0; i < 4; ++i) {
    float3 a = p[i], b = p[(i + 1) % 4];
    float3 x = cross(a, b);
    float sx = length(x);
    if (sx > 0.0f) F += x * (msh_atan2(sx, dot(a, b)) / sx);
    m += a;
  }
  F *= 0.5f;
  return dot(F, m) < 0.0f ? -F : F;
}

// F of a disk light: centre c (from the shading point, any distance > 0), normal nd (either sign), radius R;
// the closed form of occlusion/micro_shadowing_area.h (boundary formula on the rim). |diff| vs C++ double
// <= 2e-5 (per component).
MSH_FN float3 msh_ms_disk_vector_form_factor(float3 c, float3 nd, float R) {
  float3 n = normalize(nd);
  // Orthonormal frame about n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
  float sgn = n.z >= 0.0f ? 1.0f : -1.0f;
  float a = -1.0f / (sgn + n.z), b = n.x * n.y * a;
  float3 s = float3(1.0f + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
  float3 t = float3(b, sgn + n.y * n.y * a, -n.y);
  float r = max(R, 0.0f);
  float A = dot(c, c) + r * r, B = 2.0f * r * dot(c, s), C = 2.0f * r * dot(c, t);
  float hb = length(float2(B, C));
  // The point on the rim of a disk seen edge-on: zero solid angle, the integrals singular.
  if (!(A - hb > 1e-6f * A)) return float3(0.0f, 0.0f, 0.0f);
  float D = sqrt((A - hb) * (A + hb));
  float I0 = 6.28318530718f / D, k = -6.28318530718f / (D * (D + A));
  float3 F = 0.5f * (cross(c, t) * (r * k * B) - cross(c, s) * (r * k * C) + n * (r * r * I0));
  return dot(F, c) < 0.0f ? -F : F;
}

// The equivalent cap of F: float2(N.L of its axis, its angular radius). F = 0 (a light of zero size): the
// zero-size cap at `center` (so the cap forms give the point value there). |diff| vs C++ double <= 1e-4 for
// lights of at least 0.5 degree (4.3e-5 measured).
MSH_FN float2 msh_ms_equivalent_cap(float3 F, float3 center) {
  float len = length(F);
  if (!(len > 0.0f)) {
    float lc = length(center);
    return float2(lc > 0.0f ? clamp(center.z / lc, -1.0f, 1.0f) : 1.0f, 0.0f);
  }
  float q = clamp(len / 3.14159265358979f, 0.0f, 1.0f);
  return float2(clamp(F.z / len, -1.0f, 1.0f), msh_atan2(sqrt(q), sqrt(1.0f - q)));
}

// The reference step over a disk or quad light through its equivalent cap (error vs the exact quadrature:
// docs/area-lights.md sec. 5). |diff| vs C++ double <= 1.5e-3 for lights of at least 1 degree (5.6e-4
// measured).
MSH_FN float msh_ms_reference_step_area_equivalent_cap(float vis, float3 F, float3 center) {
  float2 e = msh_ms_equivalent_cap(F, center);
  return msh_ms_reference_step_area_cap(vis, e.x, e.y);
}


#endif  // MSH_MICRO_SHADOWING_AREA_PORTABLE_H
