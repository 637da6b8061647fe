// microshadow: linearly transformed cosines for GLSL 4.50 / GLSL ES 3.20 (Heitz, Dupuy, Hill, Neubelt 2016,
// "Real-Time Polygonal-Light Shading with Linearly Transformed Cosines"). Include-only: no #version line. Port of
// include/microshadow/bsdf/ltc.h and ltc_shading.h; the table is written by `microshadow bake ltc` (docs/ltc.md):
// ltc_mat = RGBA (a, b, c, d) of M^-1 = [[a,0,b],[0,1,0],[c,0,d]], ltc_amp = RG (magnitude, fresnel), both
// n x n, x = roughness, y = sqrt(1 - N.V), sampled with linear filtering and clamp-to-edge.
// Vectors: any one frame (world or view); n, v unit, v above the surface; light vertices relative to the point.
// Precision (float32 on lavapipe vs the C++ double code on the same inputs; tests/test_shaders_ltc.cpp), stated per
// function. The edge integral uses Hill & Heitz's rational fit of theta/sin(theta), so integrals differ from the
// exact acos form by up to the fit's error (measured, see msh_ltc_edge).
#ifndef MSH_LTC_GLSL
#define MSH_LTC_GLSL

#define MSH_LTC_PI 3.14159265358979323846
#define MSH_LTC_MAX_SIDES 16
#define MSH_LTC_MAX_VERTS 17  // a 16-gon clipped by a plane

// Texture coordinate of the table for (perceptual roughness, N.V), with the texel-centre scale and bias for an
// n x n table (texel i holds i/(n-1)). Exact to float rounding.
vec2 msh_ltc_uv(float roughness, float n_dot_v, float n) {
  vec2 c = vec2(clamp(roughness, 0.0, 1.0), sqrt(1.0 - clamp(n_dot_v, 0.0, 1.0)));
  return c * ((n - 1.0) / n) + 0.5 / n;
}

// M^-1 from a texel of ltc_mat (GLSL mat3 is column-major: columns (a,0,c), (0,1,0), (b,0,d)).
mat3 msh_ltc_minv(vec4 t) { return mat3(vec3(t.x, 0.0, t.z), vec3(0.0, 1.0, 0.0), vec3(t.y, 0.0, t.w)); }

// The LTC frame (rows: tangent toward v, bitangent, n) that carries a vector into the table's frame. For v along n
// any tangent (the lobe is then rotationally symmetric).
mat3 msh_ltc_view_frame(vec3 n, vec3 v) {
  vec3 t = v - n * dot(n, v);
  if (dot(t, t) > 1e-12) {
    t = normalize(t);
  } else {  // Duff et al. 2017 tangent of n, as msh::Frame::from_z (the C++ fallback)
    float sg = n.z >= 0.0 ? 1.0 : -1.0;
    float ka = -1.0 / (sg + n.z);
    t = vec3(1.0 + sg * n.x * n.x * ka, sg * n.x * n.y * ka, -sg * n.x);
  }
  vec3 b = cross(n, t);
  return transpose(mat3(t, b, n));
}

// D(w) of the LTC (Heitz et al. 2016, eq. 3), w unit in the table's frame. Relative error <= 1e-5.
float msh_ltc_eval(mat3 minv, vec3 w) {
  vec3 lo = minv * w;
  float l2 = dot(lo, lo);
  float l = sqrt(l2);
  float cz = lo.z / l;
  if (!(cz > 0.0) || !(l2 > 0.0)) return 0.0;
  return cz / MSH_LTC_PI * abs(determinant(minv)) / (l2 * l);
}

// theta/sin(theta) * cross(a, b) / (2 pi) for unit a, b: the arc's vector form factor (Baum et al. 1989), with
// Hill & Heitz 2016's rational fit of theta/sin(theta) ("Real-Time Area Lighting: a Journey from Research to
// Production", SIGGRAPH course, the rational fit of IntegrateEdgeVec, which includes the 1/(2 pi)).
vec3 msh_ltc_edge(vec3 a, vec3 b) {
  float x = dot(a, b);
  float y = abs(x);
  float p = 0.8543985 + (0.4965155 + 0.0145206 * y) * y;
  float q = 3.4175940 + (4.1616724 + y) * y;
  float v = p / q;
  float ts = x > 0.0 ? v : 0.5 * inversesqrt(max(1.0 - x * x, 1e-7)) - v;
  return cross(a, b) * ts;
}

// Vector form factor (in the cosine's space) of the polygon p[0..count-1] carried by minv and clipped to z >= 0
// (Sutherland-Hodgman, streamed); .z is the signed integral of D over the polygon. count <= 17.
vec3 msh_ltc_polygon_vff(mat3 minv, vec3 p[MSH_LTC_MAX_VERTS], int count) {
  vec3 sum = vec3(0.0), first = vec3(0.0), last = vec3(0.0);
  int emitted = 0;
  for (int i = 0; i < count; ++i) {
    vec3 a = minv * p[i];
    vec3 b = minv * p[(i + 1) % count];
    bool ia = a.z >= 0.0, ib = b.z >= 0.0;
    for (int k = 0; k < 2; ++k) {
      bool emit = k == 0 ? ia : ia != ib;
      if (!emit) continue;
      vec3 q = a;
      if (k == 1) {
        q = a + (b - a) * (a.z / (a.z - b.z));
        q.z = 0.0;
      }
      vec3 u = normalize(q);
      if (emitted == 0) first = u; else sum += msh_ltc_edge(last, u);
      last = u;
      ++emitted;
    }
  }
  if (emitted < 3) return vec3(0.0);
  sum += msh_ltc_edge(last, first);
  return sum;  // msh_ltc_edge already carries 1/(2 pi)
}

// Clips the polygon p[0..count-1] (shading frame, n = +z) to the surface's horizon z >= 0 into q; returns the new
// count (ltc.h ltc_integrate_polygon's clip_surface: the LTC's mass below the surface is dropped). Exact.
int msh_ltc_clip_surface(vec3 p[MSH_LTC_MAX_SIDES], int count, out vec3 q[MSH_LTC_MAX_VERTS]) {
  for (int k = 0; k < MSH_LTC_MAX_VERTS; ++k) q[k] = vec3(0.0);
  int m = 0;
  for (int i = 0; i < count; ++i) {
    vec3 a = p[i], b = p[(i + 1) % count];
    if (a.z >= 0.0) q[m++] = a;
    if ((a.z >= 0.0) != (b.z >= 0.0)) {
      vec3 c = a + (b - a) * (a.z / (a.z - b.z));
      c.z = 0.0;
      q[m++] = c;
    }
  }
  return m;
}

// The regular N-gon (N <= 16) of the same area as the disk of radius tan(sigma) that subtends a sphere light of
// sin(sigma) = sin_sigma around unit `axis` (ltc.h ltc_sphere_polygon). Vertices to float rounding.
void msh_ltc_sphere_polygon(vec3 axis, float sin_sigma, int sides, out vec3 p[MSH_LTC_MAX_SIDES]) {
  float s = clamp(sin_sigma, 0.0, 0.9999);
  float rc = s / sqrt(1.0 - s * s) * sqrt(2.0 * MSH_LTC_PI / (float(sides) * sin(2.0 * MSH_LTC_PI / float(sides))));
  // Duff et al. 2017 frame about the axis (same as msh::Frame::from_z).
  float sg = axis.z >= 0.0 ? 1.0 : -1.0;
  float ka = -1.0 / (sg + axis.z);
  float kb = axis.x * axis.y * ka;
  vec3 e1 = vec3(1.0 + sg * axis.x * axis.x * ka, sg * kb, -sg * axis.x);
  vec3 e2 = vec3(kb, sg + axis.y * axis.y * ka, -axis.y);
  for (int k = 0; k < MSH_LTC_MAX_SIDES; ++k) {
    float ph = 2.0 * MSH_LTC_PI * float(k) / float(sides);
    p[k] = k < sides ? axis + (e1 * cos(ph) + e2 * sin(ph)) * rc : vec3(0.0);
  }
}

// One light shaded with one LTC: .x = integral of D over the light (clamped to [0,1]), .yzw = representative
// direction normalize(M F) in the caller's frame (ltc_shading.h ltc_representative_direction).
// Integral: absolute error <= 5e-5 vs the C++ double code (measured max 1.5e-5); direction: 1 - cos <= 1e-6.
vec4 msh_ltc_finish(mat3 frame, vec4 t, vec3 f) {
  float integral = clamp(abs(f.z), 0.0, 1.0);
  if (f.z < 0.0) f = -f;
  // M f up to a positive scale: the adjugate of M^-1 times sign(det M^-1).
  float det = t.x * t.w - t.y * t.z;
  vec3 mf = vec3(t.w * f.x - t.y * f.z, det * f.y, t.x * f.z - t.z * f.x) * (det < 0.0 ? -1.0 : 1.0);
  vec3 dir = integral > 0.0 ? normalize(transpose(frame) * mf) : transpose(frame)[2];
  return vec4(integral, dir);
}

// Rectangle (any planar quad) light: corners relative to the shading point, clipped to the surface's horizon and
// to the LTC's (ltc_shade_polygon with clip_surface). t = the ltc_mat texel.
vec4 msh_ltc_rect(vec4 t, vec3 n, vec3 v, vec3 p0, vec3 p1, vec3 p2, vec3 p3) {
  mat3 fr = msh_ltc_view_frame(n, v);
  vec3 p[MSH_LTC_MAX_SIDES];
  for (int k = 0; k < MSH_LTC_MAX_SIDES; ++k) p[k] = vec3(0.0);
  p[0] = fr * p0, p[1] = fr * p1, p[2] = fr * p2, p[3] = fr * p3;
  vec3 q[MSH_LTC_MAX_VERTS];
  int m = msh_ltc_clip_surface(p, 4, q);
  return msh_ltc_finish(fr, t, msh_ltc_polygon_vff(msh_ltc_minv(t), q, m));
}

// Sphere light: unit centre direction to_light, sin(sigma) = radius / distance, polygon of `sides` (3..16), clipped
// to the surface's horizon and to the LTC's (ltc_shade_sphere with clip_surface).
vec4 msh_ltc_sphere(vec4 t, vec3 n, vec3 v, vec3 to_light, float sin_sigma, int sides) {
  mat3 fr = msh_ltc_view_frame(n, v);
  vec3 p[MSH_LTC_MAX_SIDES];
  sides = clamp(sides, 3, MSH_LTC_MAX_SIDES);
  msh_ltc_sphere_polygon(fr * to_light, sin_sigma, sides, p);
  vec3 q[MSH_LTC_MAX_VERTS];
  int m = msh_ltc_clip_surface(p, sides, q);
  return msh_ltc_finish(fr, t, msh_ltc_polygon_vff(msh_ltc_minv(t), q, m));
}

// The shaded value per unit radiance (Schlick F0), times the light's micro-shadowing factor ms_area (docs/ltc.md:
// M_area of the light, or the point term at the representative direction .yzw). amp = (magnitude, fresnel).
float msh_ltc_specular(vec4 ltc, vec2 amp, float f0, float ms_area) {
  return (f0 * amp.x + (1.0 - f0) * amp.y) * ltc.x * ms_area;
}

#endif  // MSH_LTC_GLSL
