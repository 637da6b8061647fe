// microshadow: shaders/portable/ltc.h, written once for GLSL and HLSL in the portable dialect
// (docs/shaders.md): HLSL type names and the msh_* spellings that shaders/glsl/msh_prelude.glsl and
// shaders/hlsl/msh_prelude.hlsl define. Not included directly: GLSL `#include "shaders/glsl/ltc.glsl"`,
// HLSL `#include "shaders/hlsl/ltc.hlsl"` (their top comments say how).
// Linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016, "Real-Time Polygonal-Light Shading with
// Linearly Transformed Cosines"). Port of include/microshadow/bsdf/ltc.h and ltc_shading.h; the table is
// written by `microshadow bake ltc` (docs/ltc.md):
// ltc_mat = RGBA (a, b, c, d) of M^-1 = [[a,0,b],[0,1,0],[c,0,d]], ltc_amp = RG (magnitude, fresnel), both
// n x n, x = roughness, y = sqrt(1 - N.V), sampled with linear filtering and clamp-to-edge.
// Vectors: any one frame (world or view); n, v unit, v above the surface; light vertices relative to the point.
// Precision (float32 on lavapipe vs the C++ double code on the same inputs; tests/test_shaders_ltc.cpp), stated per
// function.
#ifndef MSH_LTC_PORTABLE_H
#define MSH_LTC_PORTABLE_H

#define MSH_LTC_PI 3.14159265358979323846f
#define MSH_LTC_MAX_SIDES 16
#define MSH_LTC_MAX_VERTS 17  // a 16-gon clipped by a plane

// Texture coordinate of the table for (perceptual roughness, N.V), with the texel-centre scale and bias for an
// n x n table (texel i holds i/(n-1)). Exact to float rounding.
MSH_FN float2 msh_ltc_uv(float roughness, float n_dot_v, float n) {
  float2 c = float2(msh_saturate(roughness), sqrt(1.0f - msh_saturate(n_dot_v)));
  return c * ((n - 1.0f) / n) + 0.5f / n;
}

// M^-1 from a texel of ltc_mat (rows (a,0,b), (0,1,0), (c,0,d)).
MSH_FN float3x3 msh_ltc_minv(float4 t) {
  return msh_float3x3_rows(float3(t.x, 0.0f, t.y), float3(0.0f, 1.0f, 0.0f), float3(t.z, 0.0f, t.w));
}

// The LTC frame (rows: tangent toward v, bitangent, n). For v along n any tangent.
MSH_FN float3x3 msh_ltc_view_frame(float3 n, float3 v) {
  float3 t = v - n * dot(n, v);
  if (dot(t, t) > 1e-12f) {
    t = normalize(t);
  } else {  // Duff et al. 2017 tangent of n, as msh::Frame::from_z (the C++ fallback)
    float sg = n.z >= 0.0f ? 1.0f : -1.0f;
    float ka = -1.0f / (sg + n.z);
    t = float3(1.0f + sg * n.x * n.x * ka, sg * n.x * n.y * ka, -sg * n.x);
  }
  float3 b = cross(n, t);
  return msh_float3x3_rows(t, b, n);
}

// D(w) of the LTC (Heitz et al. 2016, eq. 3), w unit in the table's frame. Relative error <= 1e-5.
MSH_FN float msh_ltc_eval(float3x3 minv, float3 w) {
  float3 lo = msh_mul(minv, w);
  float l2 = dot(lo, lo);
  float l = sqrt(l2);
  float cz = lo.z / l;
  if (!(cz > 0.0f) || !(l2 > 0.0f)) return 0.0f;
  return cz / MSH_LTC_PI * abs(determinant(minv)) / (l2 * l);
}

// theta/sin(theta) * cross(a, b) / (2 pi) for unit a, b (Baum et al. 1989), with Hill & Heitz 2016's rational fit of
// theta/sin(theta) / (2 pi) ("Real-Time Area Lighting: a Journey from Research to Production", IntegrateEdgeVec).
MSH_FN float3 msh_ltc_edge(float3 a, float3 b) {
  float x = dot(a, b);
  float y = abs(x);
  float p = 0.8543985f + (0.4965155f + 0.0145206f * y) * y;
  float q = 3.4175940f + (4.1616724f + y) * y;
  float v = p / q;
  float ts = x > 0.0f ? v : 0.5f * msh_rsqrt(max(1.0f - x * x, 1e-7f)) - v;
  return cross(a, b - a) * ts;  // = cross(a, b), without float cancellation on short edges (tiny lights)
}

// One edge a -> b of the streamed vector-form-factor sum (Sutherland-Hodgman to z >= 0 in the cosine's space, then
// the edge sum; ltc.h ltc_integrate_polygon_o): emits a if above, and the edge's crossing of z = 0. Shared by
// msh_ltc_polygon_vff and msh_ltc_cone_weight.
MSH_FN void msh_ltc_vff_edge(float3 a, float3 b, MSH_INOUT(float3) sum, MSH_INOUT(float3) first, MSH_INOUT(float3) last,
                      MSH_INOUT(int) emitted) {
  bool ia = a.z >= 0.0f, ib = b.z >= 0.0f;
  for (int k = 0; k < 2; ++k) {
    bool emit = k == 0 ? ia : ia != ib;
    if (!emit) continue;
    float3 q = a;
    if (k == 1) {
      q = a + (b - a) * (a.z / (a.z - b.z));
      q.z = 0.0f;
    }
    float3 u = normalize(q);
    if (emitted == 0) first = u; else sum += msh_ltc_edge(last, u);
    last = u;
    ++emitted;
  }
}

// Closes the streamed sum (msh_ltc_vff_edge): fewer than 3 emitted vertices is an empty polygon.
MSH_FN float3 msh_ltc_vff_close(float3 sum, float3 first, float3 last, int emitted) {
  return emitted < 3 ? float3(0.0f, 0.0f, 0.0f) : sum + msh_ltc_edge(last, first);  // msh_ltc_edge carries 1/(2 pi)
}

// Vector form factor (in the cosine's space) of the polygon carried by minv and clipped to z >= 0 (streamed
// Sutherland-Hodgman); .z is the signed integral of D over the polygon. count <= 17.
MSH_FN float3 msh_ltc_polygon_vff(float3x3 minv, float3 p[MSH_LTC_MAX_VERTS], int count) {
  float3 sum = float3(0.0f, 0.0f, 0.0f), first = sum, last = sum;
  int emitted = 0;
  for (int i = 0; i < count; ++i)
    msh_ltc_vff_edge(msh_mul(minv, p[i]), msh_mul(minv, p[(i + 1) % count]), sum, first, last, emitted);
  return msh_ltc_vff_close(sum, first, last, emitted);
}

// Clips the polygon p[0..count-1] (shading frame, n = +z) to the surface's horizon z >= 0 into q; returns the new
// count (ltc.h ltc_integrate_polygon's clip_surface: the LTC's mass below the surface is dropped). Exact.
MSH_FN int msh_ltc_clip_surface(float3 p[MSH_LTC_MAX_SIDES], int count, MSH_OUT_ARRAY(float3, q, MSH_LTC_MAX_VERTS)) {
  for (int k = 0; k < MSH_LTC_MAX_VERTS; ++k) q[k] = float3(0.0f, 0.0f, 0.0f);
  int m = 0;
  for (int i = 0; i < count; ++i) {
    float3 a = p[i], b = p[(i + 1) % count];
    if (a.z >= 0.0f) q[m++] = a;
    if ((a.z >= 0.0f) != (b.z >= 0.0f)) {
      float3 c = a + (b - a) * (a.z / (a.z - b.z));
      c.z = 0.0f;
      q[m++] = c;
    }
  }
  return m;
}

// The regular N-gon (N <= 16) of the same area as the disk of radius tan(sigma) that subtends a sphere light of
// sin(sigma) = sin_sigma around unit `axis` (ltc.h ltc_sphere_polygon). Vertices to float rounding.
MSH_FN void msh_ltc_sphere_polygon(float3 axis, float sin_sigma, int sides, MSH_OUT_ARRAY(float3, p, MSH_LTC_MAX_SIDES)) {
  float s = clamp(sin_sigma, 0.0f, 0.9999f);
  float rc = s / sqrt(1.0f - s * s) * sqrt(2.0f * MSH_LTC_PI / (float(sides) * sin(2.0f * MSH_LTC_PI / float(sides))));
  float sg = axis.z >= 0.0f ? 1.0f : -1.0f;  // Duff et al. 2017 frame (msh::Frame::from_z)
  float ka = -1.0f / (sg + axis.z);
  float kb = axis.x * axis.y * ka;
  float3 e1 = float3(1.0f + sg * axis.x * axis.x * ka, sg * kb, -sg * axis.x);
  float3 e2 = float3(kb, sg + axis.y * axis.y * ka, -axis.y);
  for (int k = 0; k < MSH_LTC_MAX_SIDES; ++k) {
    float ph = 2.0f * MSH_LTC_PI * float(k) / float(sides);
    p[k] = k < sides ? axis + (e1 * cos(ph) + e2 * sin(ph)) * rc : float3(0.0f, 0.0f, 0.0f);
  }
}

// .x = integral of D over the light (clamped to [0,1]), .yzw = representative direction normalize(M F).
// Integral: absolute error <= 5e-5 vs the C++ double code (measured max 1.5e-5); direction: 1 - cos <= 1e-6.
MSH_FN float4 msh_ltc_finish(float3x3 frame, float4 t, float3 f) {
  float integral = msh_saturate(abs(f.z));
  if (f.z < 0.0f) f = -f;
  float det = t.x * t.w - t.y * t.z;  // M f up to a positive scale: adjugate times sign(det)
  float3 mf = float3(t.w * f.x - t.y * f.z, det * f.y, t.x * f.z - t.z * f.x) * (det < 0.0f ? -1.0f : 1.0f);
  float3 dir = integral > 0.0f ? normalize(msh_mul(mf, frame)) : msh_mul(float3(0.0f, 0.0f, 1.0f), frame);
  return float4(integral, dir);
}

// Rectangle (any planar quad) light: corners relative to the shading point, clipped to the surface's horizon and
// to the LTC's (ltc_shade_polygon with clip_surface). t = the ltc_mat texel.
// Integral: absolute error <= 5e-5 vs the C++ double code (measured max 1.5e-5); direction: 1 - cos <= 1e-6.
MSH_FN float4 msh_ltc_rect(float4 t, float3 n, float3 v, float3 p0, float3 p1, float3 p2, float3 p3) {
  float3x3 fr = msh_ltc_view_frame(n, v);
  float3 p[MSH_LTC_MAX_SIDES];
  for (int k = 0; k < MSH_LTC_MAX_SIDES; ++k) p[k] = float3(0.0f, 0.0f, 0.0f);
  p[0] = msh_mul(fr, p0); p[1] = msh_mul(fr, p1); p[2] = msh_mul(fr, p2); p[3] = msh_mul(fr, p3);
  float3 q[MSH_LTC_MAX_VERTS];
  int m = msh_ltc_clip_surface(p, 4, q);
  return msh_ltc_finish(fr, t, msh_ltc_polygon_vff(msh_ltc_minv(t), q, m));
}

// Sphere light: unit centre direction to_light, sin(sigma) = radius / distance, polygon of `sides` (3..16), clipped
// to the surface's horizon and to the LTC's (ltc_shade_sphere with clip_surface).
MSH_FN float4 msh_ltc_sphere(float4 t, float3 n, float3 v, float3 to_light, float sin_sigma, int sides) {
  float3x3 fr = msh_ltc_view_frame(n, v);
  float3 p[MSH_LTC_MAX_SIDES];
  sides = clamp(sides, 3, MSH_LTC_MAX_SIDES);
  msh_ltc_sphere_polygon(msh_mul(fr, to_light), sin_sigma, sides, p);
  float3 q[MSH_LTC_MAX_VERTS];
  int m = msh_ltc_clip_surface(p, sides, q);
  return msh_ltc_finish(fr, t, msh_ltc_polygon_vff(msh_ltc_minv(t), q, m));
}

// The shaded value per unit radiance (Schlick F0), times the light's micro-shadowing factor ms_area (docs/ltc.md).
MSH_FN float msh_ltc_specular(float4 ltc, float2 amp, float f0, float ms_area) {
  return (f0 * amp.x + (1.0f - f0) * amp.y) * ltc.x * ms_area;
}

// ---- micro-shadowing of an LTC-shaded light without the representative point ------------------------------------
// Port of ltc_shading.h LtcLightCone (docs/area-lights.md sec. 5): for a point term that depends on N.L only, M_area
// depends on the light only through the distribution of z = n.l under the weight w = D_ltc + tail (n.l)/pi over the
// light (identity M^-1 and tail = 0: a Lambertian receiver, exact up to the polygons). Its complementary CDF S(z)
// is the weight of the light's polygon clipped by the cone {n.l > z}, the cone as its regular
// MSH_LTC_CONE_SIDES-gon of equal gnomonic area (planes through the shading point), over the light's weight. The
// reference step's M_area is S(cos_t); a term of N.L is the product rule of M against dP (math/quadrature.h
// integrate_by_ccdf). Cost of one S: MSH_LTC_CONE_SIDES clip passes over <= 40 vertices and two polygon integrals.
// Precision vs the C++ double LtcLightCone at the same float inputs (tests/test_shaders_ltc_micro_shadowing.cpp):
// stated per function; the difference is the edge fit and float32 rounding (the K-gon is the same in both).

#define MSH_LTC_CONE_SIDES 16
#define MSH_LTC_IDENTITY msh_float3x3_rows(float3(1.0f, 0.0f, 0.0f), float3(0.0f, 1.0f, 0.0f), float3(0.0f, 0.0f, 1.0f))
#define MSH_LTC_CLIP_VERTS 40  // light (<= 16) + horizon (1) + cone (16) + margin: LtcLightCone::kMaxClipped

// A light prepared for S(z) (LtcLightCone): its polygon in the LTC frame clipped to the horizon, the LTC, the tail
// weight, the light's total weight den and its range [z_lo, z_hi] of n.l.
struct MshLtcCone {
  float3 p[MSH_LTC_MAX_VERTS];
  int n;
  float3x3 minv;
  float tail, den, z_lo, z_hi;
};

// The weight of the cosine tail beside the LTC for a GGX receiver of alpha = roughness^2: 1.5 alpha^1.5
// (ltc_shading.h ltc_tail_weight; chosen and measured in docs/area-lights.md sec. 5). Exact to float rounding.
MSH_FN float msh_ltc_tail_weight(float alpha) {
  float a = clamp(alpha, 0.0f, 1.0f);
  return 1.5f * a * sqrt(a);
}

// Keeps the part of src[0..n-1] with dot(d, p) >= 0 (a plane through the shading point) in dst; returns the count,
// 0 if fewer than 3 are left (ltc_shading.h ltc_clip_polygon). Exact up to float rounding of the crossings.
MSH_FN int msh_ltc_clip_plane(float3 src[MSH_LTC_CLIP_VERTS], int n, float3 d, MSH_OUT_ARRAY(float3, dst, MSH_LTC_CLIP_VERTS)) {
  int m = 0;
  float3 a = src[0];
  float da = dot(d, a);
  for (int i = 0; i < n; ++i) {  // one array read per edge: b becomes the next a
    float3 b = src[i + 1 < n ? i + 1 : 0];
    float db = dot(d, b);
    if (da >= 0.0f && m < MSH_LTC_CLIP_VERTS) dst[m++] = a;
    if ((da >= 0.0f) != (db >= 0.0f) && m < MSH_LTC_CLIP_VERTS) dst[m++] = a + (b - a) * (da / (da - db));
    a = b;
    da = db;
  }
  return m < 3 ? 0 : m;
}

// The weight of q[0..m-1] (shading frame, above the horizon; LtcLightCone::weight): the LTC's integral (carried by
// minv, clipped to z >= 0 in the cosine's space: ltc.h ltc_integrate_polygon_o) plus tail times the polygon's own
// form factor, both streamed in one pass over the vertices. Each integral as msh_ltc_polygon_vff (the edge fit).
MSH_FN float msh_ltc_cone_weight(float3x3 minv, float tail, float3 q[MSH_LTC_CLIP_VERTS], int m) {
  float3 s0 = float3(0.0f, 0.0f, 0.0f), f0 = s0, l0 = s0, s1 = s0, f1 = s0, l1 = s0;
  int e0 = 0, e1 = 0;
  float3 a = q[0];
  for (int i = 0; i < m; ++i) {
    float3 b = q[i + 1 < m ? i + 1 : 0];
    msh_ltc_vff_edge(msh_mul(minv, a), msh_mul(minv, b), s0, f0, l0, e0);
    if (tail > 0.0f) msh_ltc_vff_edge(a, b, s1, f1, l1, e1);
    a = b;
  }
  float w = abs(msh_ltc_vff_close(s0, f0, l0, e0).z);
  if (tail > 0.0f) w += tail * abs(msh_ltc_vff_close(s1, f1, l1, e1).z);
  return w;
}

// Prepares a light (LtcLightCone::make): p[0..count-1] its corners in the LTC frame (n = +z), t the ltc_mat texel
// (float4(1, 0, 0, 1): identity), tail >= 0. A light the LTC misses falls back to the tail (identity, tail 1); the n.l
// range is the corners' minimum and the arcs' maximum (1 if the polygon holds n): |diff| vs C++ double <= 1e-4
// (3.6e-7 measured).
MSH_FN MshLtcCone msh_ltc_cone_make(float4 t, float3 p[MSH_LTC_MAX_SIDES], int count, float tail) {
  MshLtcCone c;
  c.minv = msh_ltc_minv(t);
  c.tail = tail > 0.0f ? tail : 0.0f;
  c.den = 0.0f; c.z_lo = 0.0f; c.z_hi = 0.0f;
  c.n = msh_ltc_clip_surface(p, clamp(count, 0, MSH_LTC_MAX_SIDES), c.p);
  if (c.n < 3) {
    c.n = 0;
    return c;
  }
  float3 q[MSH_LTC_CLIP_VERTS];
  for (int i = 0; i < MSH_LTC_MAX_VERTS; ++i) q[i] = c.p[i];  // the rest is never read
  c.den = msh_ltc_cone_weight(c.minv, c.tail, q, c.n);
  if (!(c.den > 0.0f)) {
    c.tail = 1.0f; c.minv = MSH_LTC_IDENTITY;
    c.den = msh_ltc_cone_weight(c.minv, c.tail, q, c.n);
  }
  c.z_lo = 1.0f; c.z_hi = 0.0f;
  bool pos = true, neg = true;
  for (int i = 0; i < c.n; ++i) {
    float3 a = normalize(c.p[i]), b = normalize(c.p[(i + 1) % c.n]);
    c.z_lo = min(c.z_lo, a.z);
    float zmax = max(a.z, b.z);
    float ab = clamp(dot(a, b), -1.0f, 1.0f);
    float3 e = b - a * ab;  // toward b, orthogonal to a
    float le = length(e);
    if (le > 0.0f) {
      float ez = e.z / le;
      float ang = msh_atan2(le, ab), s = (ez == 0.0f && a.z == 0.0f) ? 0.0f : msh_atan2(ez, a.z);
      if (s > 0.0f && s < ang) zmax = max(zmax, sqrt(a.z * a.z + ez * ez));
    }
    c.z_hi = max(c.z_hi, zmax);
    float side = cross(a, b).z;
    pos = pos && side >= 0.0f;
    neg = neg && side <= 0.0f;
  }
  if (pos || neg) c.z_hi = 1.0f;
  c.z_lo = msh_saturate(c.z_lo); c.z_hi = msh_saturate(c.z_hi);
  return c;
}

// S(z) (LtcLightCone::ccdf): the share of the light's weight with n.l > z; 1 for z <= z_lo, 0 for z >= z_hi and for a
// light below the horizon. The K-gon's corners are scaled by cos(t) (same planes, no tan(t) overflow near z = 0).
// |diff| vs C++ double <= 1e-3 (5.7e-4 measured, see msh_ltc_ms_step_sphere).
MSH_FN float msh_ltc_cone_ccdf(MshLtcCone c, float z) {
  if (!(c.den > 0.0f)) return 0.0f;
  if (!(z > c.z_lo)) return 1.0f;
  if (!(z < c.z_hi)) return 0.0f;
  float k = float(MSH_LTC_CONE_SIDES);
  float r = sqrt(max(0.0f, 1.0f - z * z)) * sqrt(2.0f * MSH_LTC_PI / (k * sin(2.0f * MSH_LTC_PI / k)));
  float3 a[MSH_LTC_CLIP_VERTS], b[MSH_LTC_CLIP_VERTS];
  for (int i = 0; i < MSH_LTC_MAX_VERTS; ++i) a[i] = c.p[i];  // the rest is never read
  int m = c.n;
  float3 u0 = float3(r, 0.0f, z), u = u0;
  for (int i = 0; i < MSH_LTC_CONE_SIDES && m > 0; i += 2) {  // ping-pong a -> b -> a
    float ph = 2.0f * MSH_LTC_PI * float(i + 1) / k;
    float3 w = float3(r * cos(ph), r * sin(ph), z);
    m = msh_ltc_clip_plane(a, m, cross(u, w), b);
    ph = 2.0f * MSH_LTC_PI * float(i + 2) / k;
    u = i + 2 == MSH_LTC_CONE_SIDES ? u0 : float3(r * cos(ph), r * sin(ph), z);
    m = msh_ltc_clip_plane(b, m, cross(w, u), a);
  }
  return m > 0 ? clamp(msh_ltc_cone_weight(c.minv, c.tail, a, m) / c.den, 0.0f, 1.0f) : 0.0f;
}

// The lights of msh_ltc_sphere / msh_ltc_rect as cones (ltc_shading.h ltc_light_cone_sphere / _polygon): a sphere
// light as its area-matched `sides`-gon (3..16), a quad as given; n, v, to_light, corners as in msh_ltc_sphere/rect.
MSH_FN MshLtcCone msh_ltc_cone_sphere(float4 t, float3 n, float3 v, float3 to_light, float sin_sigma, int sides, float tail) {
  float3x3 fr = msh_ltc_view_frame(n, v);
  float3 p[MSH_LTC_MAX_SIDES];
  sides = clamp(sides, 3, MSH_LTC_MAX_SIDES);
  msh_ltc_sphere_polygon(msh_mul(fr, to_light), sin_sigma, sides, p);
  return msh_ltc_cone_make(t, p, sides, tail);
}
MSH_FN MshLtcCone msh_ltc_cone_rect(float4 t, float3 n, float3 v, float3 p0, float3 p1, float3 p2, float3 p3, float tail) {
  float3x3 fr = msh_ltc_view_frame(n, v);
  float3 p[MSH_LTC_MAX_SIDES];
  for (int k = 0; k < MSH_LTC_MAX_SIDES; ++k) p[k] = float3(0.0f, 0.0f, 0.0f);
  p[0] = msh_mul(fr, p0); p[1] = msh_mul(fr, p1); p[2] = msh_mul(fr, p2); p[3] = msh_mul(fr, p3);
  return msh_ltc_cone_make(t, p, 4, tail);
}

// M_area of the reference step (lit iff N.L > cos_t, cos_t = sqrt(1 - vis)) over an LTC-shaded light: S(cos_t)
// (ltc_reference_step_area). t: the ltc_mat texel, float4(1, 0, 0, 1) for a Lambertian receiver; tail: 0 for Lambert,
// msh_ltc_tail_weight(alpha) for GGX. |diff| vs C++ double <= 1e-3 (5.7e-4 measured, Lambert 3.6e-5; the largest
// for low-roughness GGX lights far off the highlight, float cancellation in the edge sums: docs/area-lights.md sec. 7).
MSH_FN float msh_ltc_ms_step_sphere(float4 t, float3 n, float3 v, float3 to_light, float sin_sigma, int sides, float tail,
                             float cos_t) {
  return msh_ltc_cone_ccdf(msh_ltc_cone_sphere(t, n, v, to_light, sin_sigma, sides, tail), cos_t);
}
MSH_FN float msh_ltc_ms_step_rect(float4 t, float3 n, float3 v, float3 p0, float3 p1, float3 p2, float3 p3, float tail, float cos_t) {
  return msh_ltc_cone_ccdf(msh_ltc_cone_rect(t, n, v, p0, p1, p2, p3, tail), cos_t);
}

// M_area of Brinck & Maximov 2016's term saturate(N.L + 2 vis^2 - 1) (the point term of micro_shadowing,
// written inline so that this file stays includable alone) over a prepared light: the product rule of the C++
// ltc_micro_shadowing_area with the term's kinks, which for this piecewise-linear term reduces by parts to
// M(z_lo) + integral of S over its sloped panel [max(z_lo, 1 - 2 vis^2), min(z_hi, 2 - 2 vis^2)], by `nodes` (1..4)
// Gauss-Legendre points (the C++ rule's arithmetic: exact for the linear piece). |diff| vs C++ double <= 1e-3
// (2.5e-4 measured).
MSH_FN float msh_ltc_cone_brinck_maximov(MshLtcCone c, float vis, int nodes) {
  if (!(c.den > 0.0f)) return 0.0f;
  float v2 = 2.0f * clamp(vis, 0.0f, 1.0f) * clamp(vis, 0.0f, 1.0f);
  float sum = clamp(c.z_lo + v2 - 1.0f, 0.0f, 1.0f);
  if (!(c.z_hi > c.z_lo)) return sum;
  float a = max(c.z_lo, 1.0f - v2), b = min(c.z_hi, 2.0f - v2);
  if (!(b > a)) return sum;
  int n = clamp(nodes, 1, 4);
  float4 x = n == 1 ? float4(0.5f, 0.0f, 0.0f, 0.0f)
         : n == 2 ? float4(0.21132486540518712f, 0.78867513459481288f, 0.0f, 0.0f)
         : n == 3 ? float4(0.11270166537925831f, 0.5f, 0.88729833462074169f, 0.0f)
                  : float4(0.06943184420297371f, 0.33000947820757187f, 0.66999052179242813f, 0.93056815579702629f);
  float4 w = n == 1 ? float4(1.0f, 0.0f, 0.0f, 0.0f)
         : n == 2 ? float4(0.5f, 0.5f, 0.0f, 0.0f)
         : n == 3 ? float4(0.27777777777777778f, 0.44444444444444444f, 0.27777777777777778f, 0.0f)
                  : float4(0.17392742256872693f, 0.32607257743127307f, 0.32607257743127307f, 0.17392742256872693f);
  float s = 0.0f;
  for (int j = 0; j < n; ++j) s += w[j] * msh_ltc_cone_ccdf(c, a + (b - a) * x[j]);
  return clamp(sum + (b - a) * s, 0.0f, 1.0f);
}
MSH_FN float msh_ltc_ms_brinck_maximov_sphere(float4 t, float3 n, float3 v, float3 to_light, float sin_sigma, int sides, float tail,
                                       float vis, int nodes) {
  return msh_ltc_cone_brinck_maximov(msh_ltc_cone_sphere(t, n, v, to_light, sin_sigma, sides, tail), vis, nodes);
}
MSH_FN float msh_ltc_ms_brinck_maximov_rect(float4 t, float3 n, float3 v, float3 p0, float3 p1, float3 p2, float3 p3, float tail,
                                     float vis, int nodes) {
  return msh_ltc_cone_brinck_maximov(msh_ltc_cone_rect(t, n, v, p0, p1, p2, p3, tail), vis, nodes);
}

#endif  // MSH_LTC_PORTABLE_H
