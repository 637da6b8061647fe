// microshadow for three.js (docs/three.md): micro-shadowing — the micro-occlusion of a surface acting on
// direct light (docs/micro-shadowing.md) — on MeshStandardMaterial and MeshPhysicalMaterial, through three's
// public extension point `onBeforeCompile`. The shader code is the project's own GLSL (shaders/glsl/*.glsl,
// generated/glsl.js) and the method list the runtime registry's (generated/methods.js); both are written by
// `microshadow view --three-module src/generated` (`npm run build`).
//
// What it changes: three's RE_Direct (directional, point, spot lights) and RE_Direct_RectArea (RectAreaLight)
// are wrapped: each light's diffuse and specular contributions are multiplied by the method's diffuse- and
// specular-lobe terms at V (the visibility), N·L, N·V and the material's roughness (three's perceptual
// roughness, after its specular anti-aliasing). A RectAreaLight uses the area-light form: the equivalent cap
// of the rectangle (its vector form factor, docs/area-lights.md §5) with the product-rule cap form of the
// term where one exists, else the term at the cap's axis (areaLights 'center': the point term at the direction
// to the rectangle's centre). Indirect light, clearcoat and sheen are unchanged;
// three's AO on indirect light is kept or dropped (aoOnIndirect).
import { Matrix3 } from 'three';
import { MICRO_SHADOWING_METHODS as REGISTRY_METHODS } from './generated/methods.js';
import { MSH_GLSL } from './generated/glsl.js';
import { DIRECTIONAL_CHANNELS, directionalOcclusion } from './directional.js';
export { loadMicroShadowingLut, parseNpy } from './luts.js';
export { loadDirectionalOcclusion, directionalOcclusion, prepareCoefficientTexture, DIRECTIONAL_CHANNELS } from './directional.js';
export { MicroShadowGLTFPlugin, GLTF_DIRECTIONAL_EXTENSION, GLTF_DEFAULT_METHOD } from './gltf.js';

// The recommended method when only an AO / micro-occlusion map exists and no table is wanted (README's guide,
// docs/choosing.md): the diffuse-aware ALU fit on the diffuse lobe, the generic ALU fit on the specular lobe.
export const DEFAULT_METHOD = 'diffuse-aware-alu+generic-vndf-alu';

// Area-light forms (shaders/glsl/micro_shadowing_area.glsl) of the registry terms that have one (the registry's
// area_cap, generated/methods.js): over the equivalent cap (nl_cap = N·L of its axis, rho = its angular
// radius), Lambertian receiver. Other terms are evaluated at the cap's axis.
export const AREA_FORMS = Object.fromEntries(
  REGISTRY_METHODS.filter((m) => m.area_cap).map((m) => [m.cpp.method, m.area_cap]));

// How a RectAreaLight is micro-shadowed (options.areaLights): 'cap' (default) — the rectangle's vector form
// factor, its equivalent cap and the term's cap form (AREA_FORMS) or the point term at the cap's axis; 'center'
// — the point term at the direction to the rectangle's centre (no form factor, no cap: cheaper, less accurate
// for large or near lights, docs/three.md "Rect-area lights: 'cap' or 'center'").
export const AREA_LIGHT_MODES = ['cap', 'center'];

// The shader files the terms need (micro_shadowing_area only when the scene has RectAreaLights).
const GLSL_FILES = ['micro_shadowing.glsl', 'micro_shadowing_fit.glsl', 'micro_shadowing_aware.glsl', 'micro_shadowing_aware_fit.glsl'];
const GLSL_AREA = 'micro_shadowing_area.glsl';
// The directional channels' functions (msh_dir_view_term), only for the texel methods.
const GLSL_DIRECTIONAL = 'directional.glsl';

// Debug outputs (options.debug, setDebug): what the fragment writes instead of its colour, for one light.
export const DEBUG_MODES = {
  inputs: 1,   // (V, N·L, N·V, roughness)
  terms: 2,    // (diffuse-lobe term, specular-lobe term, cos φ, 1 lit / 0.5 not lit)
  v: 3,        // v in the shading frame (n = +z)
  l: 4,        // l in the shading frame (a RectAreaLight: the equivalent cap's axis)
  cap: 5,      // RectAreaLight: (N·L of the equivalent cap's axis, its angular radius, |F|, 1); areaLights 'center': (N·L of the centre's direction, 0, 0, 1)
  position: 6, // view-space position
  normal: 7,   // view-space shading normal
  direct: 8,   // (direct diffuse, direct specular) of the light, green channel
  terms_diffuse: 9,   // the diffuse-lobe term of the first four lights of the loop (all lights lit)
  terms_specular: 10, // the specular-lobe term of the first four lights
  indirect: 11,  // three's indirect diffuse light (after its AO, when aoOnIndirect)
  // directional-view only (options.directional):
  dir_c0: 12, dir_c1: 13, dir_c2: 14, dir_c3: 15, dir_c4: 16, dir_c5: 17, // the 21 channels as msh_dir_view_term reads them (c[k] = 4k .. 4k+3)
  dir_a0: 18, dir_a1: 19, dir_a2: 20, dir_a3: 21, dir_a4: 22, dir_a5: 23, // the K decoded coefficients a (texture t = a[4t .. 4t+3])
  dir_l: 24,     // the light in the channels' tangent frame (x = +u, y = +v, z = the geometric normal), l_t
  dir_v: 25,     // the view in that frame, view_t
  dir_n: 26,     // the shading normal in that frame, n_t
  dir_uv: 27,    // (u, v) of the channels' fetch
  dir_x: 28, dir_y: 29, dir_z: 30, // the frame's axes in view space
};

// One set of uniform objects per material, shared by every program three compiles for it: three keeps a
// material's programs by cache key and, when it goes back to one compiled before, keeps the uniforms of the
// material's latest compilation, so every compilation must hand over the same objects, with every name.
const UNIFORMS = new WeakMap();
const ACTIVE = new WeakMap();
// How many times each material was patched. three binds the uniforms of a material's latest compilation; after
// dispose() that can be three's own program, without the module's names, and a new patch with the same options
// would go back to the module's program compiled before, its uniforms unbound. So every patch after the first
// has a cache key of its own (one compilation); first patches keep the shared key (one program for every
// material with the same options).
const PATCHES = new WeakMap();
const LUT_UNIFORMS = { lut3d: 'u_lut3d', lut2d: 'u_lut2d', lut_azimuth: 'u_lut_az' };
function materialUniforms(material) {
  let u = UNIFORMS.get(material);
  if (!u) {
    u = { msh_enabled: { value: true }, u_samples: { value: 32 }, msh_debug_mode: { value: 0 }, msh_debug_light: { value: -1 },
      msh_visibility: { value: 1 }, msh_visibility_map: { value: null }, msh_visibility_map_transform: { value: new Matrix3() },
      u_lut_az_harmonics: { value: 0 },
      msh_dir_lo: { value: [] }, msh_dir_hi: { value: [] }, msh_dir_mean: { value: [] }, msh_dir_basis: { value: [] } };
    for (let t = 0; t < 6; ++t) u[`msh_dir_tex${t}`] = { value: null };
    for (const n of Object.values(LUT_UNIFORMS)) { u[n] = { value: null }; u[`${n}_slabs`] = { value: 1 }; }
    UNIFORMS.set(material, u);
  }
  return u;
}

const asList = (x) => (x === undefined || x === null ? [] : [].concat(x));

// The registry's methods whose GLSL functions the shipped shader files define (as the viewer filters them).
// Of the forms that read per-texel directional channels ("texel"), the view-corrected ones (21 channels:
// directional-view and its pair with a specular term; options.directional); the 9-channel directional term
// is not wired.
const LIBRARY_TEXT = [...GLSL_FILES, GLSL_AREA, GLSL_DIRECTIONAL].map((f) => MSH_GLSL[f] || '').join('\n');
export const MICRO_SHADOWING_METHODS = REGISTRY_METHODS.filter((m) => (!m.texel || m.texel === 'directional_view') &&
  asList(m.requires).every((fn) => new RegExp(`\\b${fn}\\s*\\(`).test(LIBRARY_TEXT)));

// The method's entry of generated/methods.js; throws (one line) listing the methods for an unknown id.
export function findMethod(id) {
  const m = MICRO_SHADOWING_METHODS.find((e) => e.id === id);
  if (!m) throw new Error(`microshadow: unknown method '${id}'; methods: ${MICRO_SHADOWING_METHODS.map((e) => e.id).join(', ')}`);
  return m;
}

// Each lobe's term of a method: { diffuse: {term, glsl, area, form}, specular: {...} } where term is the
// registry name, glsl the point expression, area the RectAreaLight expression and form 'cap' (the area form)
// or 'axis' (the point term at the cap's axis).
// With areaLights 'center' every lobe's RectAreaLight form is the point term at the rectangle's centre
// (form 'center').
export function methodLobes(id, areaLights = 'cap') {
  const m = findMethod(id);
  const lobe = (glsl, cpp) => {
    const a = areaLights === 'center' ? null : AREA_FORMS[cpp.method];
    return { term: cpp.method, glsl, area: a || glsl, form: areaLights === 'center' ? 'center' : a ? 'cap' : 'axis', cpp };
  };
  return m.glsl_diffuse !== undefined
    ? { diffuse: lobe(m.glsl_diffuse, m.cpp.diffuse), specular: lobe(m.glsl_specular, m.cpp.specular) }
    : { diffuse: lobe(m.glsl, m.cpp), specular: lobe(m.glsl, m.cpp) };
}

function glslLibrary(areaCap) {
  for (const f of [...GLSL_FILES, GLSL_AREA, GLSL_DIRECTIONAL])
    if (typeof MSH_GLSL[f] !== 'string') throw new Error(`microshadow: generated/glsl.js has no ${f} (run npm run build)`);
  return `${GLSL_FILES.map((f) => `// ---- shaders/glsl/${f}\n${MSH_GLSL[f]}`).join('\n')}
${areaCap ? `#if NUM_RECT_AREA_LIGHTS > 0
// ---- shaders/glsl/${GLSL_AREA}
${MSH_GLSL[GLSL_AREA]}
#endif` : '// areaLights: \'center\' (no area-light forms)'}
#ifdef MSH_DIR
// ---- shaders/glsl/${GLSL_DIRECTIONAL}
${MSH_GLSL[GLSL_DIRECTIONAL]}
#endif
`;
}

// The directional channels (options.directional, directional.js): NT coefficient textures, decoded per
// channel (msh_dir_decode_unorm8), composed into the 21 channels (identity: the coefficients are the channels),
// and the channels' tangent frame: x = +u, y = +v of the channel textures (rows top to bottom: the textures are
// uploaded unflipped), z = the geometric normal (docs/directional-occlusion.md, "The stored channels"). x is
// three's tangent where the geometry has one (its direction, u, is fixed by glTF/MikkTSpace), else the
// derivative frame of the UVs; y = cross(z, x) with the sign of +v taken from the UVs' screen-space
// derivatives (the bitangent's sign differs between conventions: glTF/MikkTSpace assets point it toward −v).
function directionalBlock(dir) {
  const NT = dir.textures;
  const fetch = Array.from({ length: NT }, (_, t) =>
    `  msh_dir_a[${t}] = msh_dir_decode_unorm8(texture(msh_dir_tex${t}, uv), msh_dir_lo[${t}], msh_dir_hi[${t}]);`).join('\n');
  const compose = dir.identity
    ? Array.from({ length: 6 }, (_, k) => `  msh_dir_c[${k}] = ${k < NT ? `msh_dir_a[${k}]` : 'vec4(0.0)'};`).join('\n')
    : `  float c[24];
  for (int i = 0; i < ${DIRECTIONAL_CHANNELS}; ++i) {
    float s = msh_dir_mean[i / 4][i % 4];
    for (int t = 0; t < ${NT}; ++t) s += dot(msh_dir_basis[i * ${NT} + t], msh_dir_a[t]);
    c[i] = s;
  }
  for (int i = ${DIRECTIONAL_CHANNELS}; i < 24; ++i) c[i] = 0.0;
  for (int k = 0; k < 6; ++k) msh_dir_c[k] = vec4(c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]);`;
  return `
${Array.from({ length: NT }, (_, t) => `uniform sampler2D msh_dir_tex${t};`).join('\n')}
uniform vec4 msh_dir_lo[${NT}], msh_dir_hi[${NT}];
${dir.identity ? '' : `uniform vec4 msh_dir_mean[6];\nuniform vec4 msh_dir_basis[${DIRECTIONAL_CHANNELS * NT}];`}
varying vec2 vMshDirUv;
vec4 msh_dir_a[${NT}];
vec4 msh_dir_c[6];
vec3 msh_dir_x = vec3(1.0, 0.0, 0.0), msh_dir_y = vec3(0.0, 1.0, 0.0), msh_dir_z = vec3(0.0, 0.0, 1.0), msh_dir_n = vec3(0.0, 0.0, 1.0);
vec3 msh_dir_to_frame(vec3 w) { return vec3(dot(w, msh_dir_x), dot(w, msh_dir_y), dot(w, msh_dir_z)); }
// pos: view-space position; ng: the geometric normal; ns: the shading normal (after the normal map).
void msh_dir_setup(vec3 pos, vec3 ng, vec3 ns, vec2 uv) {
${fetch}
${compose}
  vec3 q0 = dFdx(pos), q1 = dFdy(pos);
  vec2 st0 = dFdx(uv), st1 = dFdy(uv);
  vec3 q1perp = cross(q1, ng), q0perp = cross(ng, q0);
  vec3 bd = q1perp * st0.y + q0perp * st1.y;  // along +v on the surface (three's getTangentFrame)
#ifdef USE_TANGENT
  vec3 t = vTangent;
#else
  vec3 t = q1perp * st0.x + q0perp * st1.x;   // along +u
#endif
  msh_dir_z = ng;
  msh_dir_x = normalize(t - ng * dot(ng, t));
  vec3 y = cross(ng, msh_dir_x);
  msh_dir_y = dot(y, bd) < 0.0 ? -y : y;
  msh_dir_n = normalize(msh_dir_to_frame(ns));
}
#define dir_v msh_dir_c
`;
}

// The light and the view in the directional channels' frame, for the texel terms (point and area lights alike).
const DIR_FRAME = `#ifdef MSH_DIR
  vec3 l_t = msh_dir_to_frame(lw), view_t = msh_dir_to_frame(vw), n_t = msh_dir_n;
#ifdef MSH_DEBUG
  if (msh_light_index == msh_debug_light) { msh_dbg_dir_l = vec4(l_t, 1.0); msh_dbg_dir_v = vec4(view_t, 1.0); }
#endif
#endif`;

function parsBlock(lobes, luts, debug, visSource, dir, areaLights) {
  const areaCap = areaLights !== 'center';
  const lutDecl = luts.map((k) => {
    const u = LUT_UNIFORMS[k];
    return `uniform highp sampler3D ${u};\nuniform int ${u}_slabs;${k === 'lut_azimuth' ? '\nuniform int u_lut_az_harmonics;' : ''}`;
  }).join('\n');
  return `
// ---- microshadow (integrations/three, docs/three.md) ----
// sampler3D has no default precision in GLSL ES 3.00; three declares one in its prefix in later versions (r187
// does, r160 does not), with the renderer's precision, as here: the table samplers' function parameters need it.
#if defined( LOW_PRECISION )
precision lowp sampler3D;
#elif defined( MEDIUM_PRECISION )
precision mediump sampler3D;
#else
precision highp sampler3D;
#endif
${dir ? '#define MSH_DIR\n' : ''}${areaCap ? '' : '#define MSH_AREA_CENTER\n'}${glslLibrary(areaCap)}
${dir ? directionalBlock(dir) : ''}
${lutDecl}
uniform bool msh_enabled;
uniform int u_samples;
${visSource === 'map' ? 'uniform sampler2D msh_visibility_map;\nvarying vec2 vMshVisUv;' : ''}
${visSource === 'constant' ? 'uniform float msh_visibility;' : ''}
float msh_vis = 1.0;   // V of this pixel, set before the light loop
int msh_light_index = 0;
#ifdef MSH_DEBUG
uniform int msh_debug_mode, msh_debug_light;
vec4 msh_dbg_inputs = vec4(0.0), msh_dbg_terms = vec4(0.0), msh_dbg_v = vec4(0.0), msh_dbg_l = vec4(0.0);
vec4 msh_dbg_cap = vec4(0.0), msh_dbg_direct = vec4(0.0), msh_dbg_d = vec4(0.0), msh_dbg_s = vec4(0.0);
vec4 msh_dbg_dir_l = vec4(0.0), msh_dbg_dir_v = vec4(0.0);
#endif

// The method's terms (diffuse lobe, specular lobe) at one light direction; lw, vw: the light and the view in
// view space (the texel terms take them into the channels' frame).
vec2 msh_point_terms(float vis, float nl, float nv, float rough, float alpha, float cos_phi, vec3 v, vec3 l, vec3 lw, vec3 vw) {
${DIR_FRAME}
  return vec2(${lobes.diffuse.glsl}, ${lobes.specular.glsl});
}
#if NUM_RECT_AREA_LIGHTS > 0 && !defined(MSH_AREA_CENTER)
vec2 msh_area_terms(float vis, float nl_cap, float rho, float nv, float rough, float alpha, vec3 v, vec3 l, vec3 lw, vec3 vw) {
  float nl = clamp(nl_cap, 0.0, 1.0);
  float cos_phi = msh_ms_relative_azimuth_cos(v, l);
${DIR_FRAME}
  return vec2(${lobes.diffuse.area}, ${lobes.specular.area});
}
#endif

// An orthonormal frame (t, b) about the unit normal n (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"): the terms depend only on directions relative to n.
void msh_frame(vec3 n, out vec3 t, out vec3 b) {
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z), c = n.x * n.y * a;
  t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
  b = vec3(c, s + n.y * n.y * a, -n.y);
}

bool msh_record(vec4 inputs, vec4 terms, vec3 v, vec3 l) {
#ifdef MSH_DEBUG
  bool mine = msh_debug_light < 0 || msh_light_index == msh_debug_light;
  if (msh_light_index == msh_debug_light) {
    msh_dbg_inputs = inputs; msh_dbg_terms = terms; msh_dbg_v = vec4(v, 1.0); msh_dbg_l = vec4(l, 1.0);
  }
  if (msh_light_index < 4) { msh_dbg_d[msh_light_index] = terms.x; msh_dbg_s[msh_light_index] = terms.y; }
  ++msh_light_index;
  return mine;
#else
  return true;
#endif
}

// One light's diffuse and specular from three's own shading (own), scaled by the texel terms ms (x: diffuse
// lobe, y: specular lobe) into reflectedLight.
void msh_add_direct(const in ReflectedLight own, vec2 ms, inout ReflectedLight reflectedLight) {
  reflectedLight.directDiffuse += own.directDiffuse * ms.x;
  reflectedLight.directSpecular += own.directSpecular * ms.y;
#ifdef MSH_DEBUG
  if (msh_light_index - 1 == msh_debug_light) msh_dbg_direct = vec4(own.directDiffuse.g * ms.x, own.directSpecular.g * ms.y, 0.0, 1.0);
#endif
}

void msh_RE_Direct(const in IncidentLight directLight, const in vec3 geometryPosition, const in vec3 geometryNormal,
                   const in vec3 geometryViewDir, const in vec3 geometryClearcoatNormal, const in PhysicalMaterial material,
                   inout ReflectedLight reflectedLight) {
  ReflectedLight own = ReflectedLight(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
  RE_Direct_Physical(directLight, geometryPosition, geometryNormal, geometryViewDir, geometryClearcoatNormal, material, own);
  vec3 t, b;
  msh_frame(geometryNormal, t, b);
  vec3 v = msh_ms_to_shading_frame(geometryViewDir, t, b, geometryNormal);
  vec3 l = msh_ms_to_shading_frame(directLight.direction, t, b, geometryNormal);
  float nl = clamp(l.z, 0.0, 1.0), nv = clamp(v.z, 0.0, 1.0), rough = material.roughness;
  float cos_phi = msh_ms_relative_azimuth_cos(v, l);
  vec2 ms = msh_enabled ? msh_point_terms(msh_vis, nl, nv, rough, rough * rough, cos_phi, v, l, directLight.direction, geometryViewDir) : vec2(1.0);
  if (!msh_record(vec4(msh_vis, nl, nv, rough), vec4(ms, cos_phi, nl > 0.0 ? 1.0 : 0.5), v, l)) return;
  msh_add_direct(own, ms, reflectedLight);
}
#undef RE_Direct
#define RE_Direct msh_RE_Direct

#if NUM_RECT_AREA_LIGHTS > 0
void msh_RE_Direct_RectArea(const in RectAreaLight rectAreaLight, const in vec3 geometryPosition, const in vec3 geometryNormal,
                            const in vec3 geometryViewDir, const in vec3 geometryClearcoatNormal, const in PhysicalMaterial material,
                            inout ReflectedLight reflectedLight) {
  ReflectedLight own = ReflectedLight(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
  RE_Direct_RectArea_Physical(rectAreaLight, geometryPosition, geometryNormal, geometryViewDir, geometryClearcoatNormal, material, own);
  vec3 n = geometryNormal, t, b;
  msh_frame(n, t, b);
  vec3 c = rectAreaLight.position - geometryPosition;
#ifdef MSH_AREA_CENTER
  // areaLights 'center': the point term at the direction to the rectangle's centre.
  vec3 lw = normalize(c);
  vec3 v = msh_ms_to_shading_frame(geometryViewDir, t, b, n), l = msh_ms_to_shading_frame(lw, t, b, n);
  float nl = clamp(l.z, 0.0, 1.0), nv = clamp(v.z, 0.0, 1.0), rough = material.roughness;
  float cos_phi = msh_ms_relative_azimuth_cos(v, l);
  vec2 ms = msh_enabled ? msh_point_terms(msh_vis, nl, nv, rough, rough * rough, cos_phi, v, l, lw, geometryViewDir) : vec2(1.0);
#ifdef MSH_DEBUG
  if (msh_light_index == msh_debug_light) msh_dbg_cap = vec4(l.z, 0.0, 0.0, 1.0);
#endif
  if (!msh_record(vec4(msh_vis, nl, nv, rough), vec4(ms, cos_phi, nl > 0.0 ? 1.0 : 0.5), v, l)) return;
#else
  vec3 hw = rectAreaLight.halfWidth, hh = rectAreaLight.halfHeight;
  // The rectangle's corners seen from the point (three's order), its vector form factor and equivalent cap.
  vec3 F = msh_ms_quad_vector_form_factor(msh_ms_to_shading_frame(c + hw - hh, t, b, n), msh_ms_to_shading_frame(c - hw - hh, t, b, n),
                                          msh_ms_to_shading_frame(c - hw + hh, t, b, n), msh_ms_to_shading_frame(c + hw + hh, t, b, n));
  vec3 cs = msh_ms_to_shading_frame(c, t, b, n);
  vec2 cap = msh_ms_equivalent_cap(F, cs);
  float lf = length(F);
  vec3 l = lf > 0.0 ? F / lf : normalize(cs);
  vec3 v = msh_ms_to_shading_frame(geometryViewDir, t, b, n);
  float nv = clamp(v.z, 0.0, 1.0), rough = material.roughness;
  // The texel terms at the equivalent cap's axis, back in view space.
  vec2 ms = msh_enabled ? msh_area_terms(msh_vis, cap.x, cap.y, nv, rough, rough * rough, v, l, t * l.x + b * l.y + n * l.z, geometryViewDir) : vec2(1.0);
#ifdef MSH_DEBUG
  if (msh_light_index == msh_debug_light) msh_dbg_cap = vec4(cap, lf, 1.0);
#endif
  if (!msh_record(vec4(msh_vis, clamp(cap.x, 0.0, 1.0), nv, rough), vec4(ms, msh_ms_relative_azimuth_cos(v, l), lf > 0.0 ? 1.0 : 0.5), v, l)) return;
#endif
  msh_add_direct(own, ms, reflectedLight);
}
#undef RE_Direct_RectArea
#define RE_Direct_RectArea msh_RE_Direct_RectArea
#endif
// ---- end microshadow ----
`;
}

function replaceOnce(src, find, repl, what) {
  if (!src.includes(find))
    throw new Error(`microshadow: '${find}' not found in the ${what} shader: this three.js version is not supported (microshadow-three supports three >=0.160.0 <0.188.0, the peerDependencies of its package.json)`);
  return src.replace(find, repl);
}

// The effective options of a call, defaults applied and checked (a bad option throws one line): cfg is what
// two calls on one material are compared by; lobes, luts (the table names) and dir (the directional code)
// what patching needs. hasAoMap: whether the material has an aoMap (directional-view alone reads no V).
function resolveOptions(options, hasAoMap) {
  const method = options.method || DEFAULT_METHOD;
  const entry = findMethod(method);
  const areaLights = options.areaLights === undefined ? 'cap' : options.areaLights;
  if (!AREA_LIGHT_MODES.includes(areaLights))
    throw new Error(`microshadow: areaLights must be 'cap' or 'center', got ${JSON.stringify(options.areaLights)}`);
  const lobes = methodLobes(method, areaLights);
  const luts = asList(entry.lut);
  for (const k of luts)
    if (!options.luts || !options.luts[k] || !options.luts[k].texture)
      throw new Error(`microshadow: method '${method}' samples the table '${k}': pass luts: { ${k}: await loadMicroShadowingLut(URL) }`);
  // The texel methods read the directional channels (docs/three.md, "directional-view").
  const texel = !!entry.texel;
  let dir = null;
  if (texel) {
    if (!options.directional)
      throw new Error(`microshadow: method '${method}' reads the directional channels: pass directional: await loadDirectionalOcclusion(URL of mips/mips.json, { renderer })`);
    dir = options.directional.uniforms ? options.directional : directionalOcclusion(options.directional, `method '${method}'`);
  }
  // A method that reads no V (directional-view alone) needs no aoMap.
  const readsV = !(texel && lobes.diffuse.term === 'directional-view' && lobes.specular.term === 'directional-view');
  let visSource = 'aoMap';
  if (!readsV && options.visibility === undefined && !options.visibilityMap && !hasAoMap) visSource = 'none';
  else if (typeof options.visibility === 'number') visSource = 'constant';
  else if (options.visibility === 'map' || options.visibilityMap) visSource = 'map';
  else if (options.visibility !== undefined && options.visibility !== 'aoMap')
    throw new Error(`microshadow: visibility must be 'aoMap', 'map' or a number in [0, 1], got ${JSON.stringify(options.visibility)}`);
  if (visSource === 'constant' && !(options.visibility >= 0 && options.visibility <= 1))
    throw new Error(`microshadow: a constant visibility must be in [0, 1], got ${options.visibility}`);
  if (visSource === 'map' && !(options.visibilityMap && options.visibilityMap.isTexture))
    throw new Error("microshadow: visibility 'map' needs options.visibilityMap (a THREE.Texture, V in channel R)");
  const cfg = { method, visibility: visSource === 'constant' ? options.visibility : visSource,
    visibilityMap: visSource === 'map' ? options.visibilityMap : null, aoOnIndirect: options.aoOnIndirect !== false,
    debug: !!options.debug, samples: options.samples || 32, luts: Object.fromEntries(luts.map((k) => [k, options.luts[k]])),
    directional: texel ? options.directional : null, areaLights };
  return { cfg, visSource, lobes, luts, dir };
}

// Deep equality of effective options: plain objects and arrays by their entries, anything else (textures,
// tables, directional codes) by identity. Returns the first option that differs, or null.
const isPlain = (x) => x !== null && typeof x === 'object' && (Array.isArray(x) || Object.getPrototypeOf(x) === Object.prototype);
function deepEqual(a, b) {
  if (Object.is(a, b)) return true;
  if (!isPlain(a) || !isPlain(b) || Array.isArray(a) !== Array.isArray(b)) return false;
  const ka = Object.keys(a), kb = Object.keys(b);
  return ka.length === kb.length && ka.every((k) => Object.hasOwn(b, k) && deepEqual(a[k], b[k]));
}
const differingOption = (a, b) => Object.keys(a).find((k) => !deepEqual(a[k], b[k])) || null;

// Whether micro-shadowing can go on this material with these options: { problem: { code, reason } } or
// { resolved } (resolveOptions'). A bad option throws; a material that cannot take it is a problem.
function checkMaterial(material, options) {
  if (!material || !material.isMeshStandardMaterial)
    return { problem: { code: 'unsupported', reason: `addMicroShadowing needs a MeshStandardMaterial or MeshPhysicalMaterial, got ${material ? material.type : material}` } };
  const resolved = resolveOptions(options, !!material.aoMap);
  if (resolved.visSource === 'aoMap' && !material.aoMap)
    return { problem: { code: 'no-aomap', reason: 'the material has no aoMap: set material.aoMap (the glTF occlusion texture) first, or pass visibilityMap or a constant visibility' } };
  const active = ACTIVE.get(material);
  const key = active && differingOption(active.cfg, resolved.cfg);
  if (key) {
    const shown = (x) => (x !== null && typeof x === 'object' ? 'an object' : JSON.stringify(x));
    return { problem: { code: 'conflict', reason: `this material has micro-shadowing already with another '${key}' (${shown(active.cfg[key])}, now ${shown(resolved.cfg[key])}): call dispose() on its handle first` } };
  }
  return { problem: null, resolved };
}

// Adds micro-shadowing to a MeshStandardMaterial or MeshPhysicalMaterial (docs/three.md). Options:
//   method       a method id of MICRO_SHADOWING_METHODS (default DEFAULT_METHOD); a pair 'D+S' puts term D on
//                the diffuse lobe and S on the specular lobe
//   visibility   where V comes from: 'aoMap' (default: the material's aoMap, channel R, with aoMapIntensity
//                as three applies it; the glTF occlusion texture), 'map' (options.visibilityMap, channel R,
//                UV channel 0 with the texture's transform) or a number in [0, 1] (a constant V)
//   visibilityMap  the texture for visibility 'map' (giving it selects 'map')
//   aoOnIndirect keep three's AO on indirect light (default true); false: the aoMap is V only
//   luts         { lut3d, lut2d, lut_azimuth }: tables from loadMicroShadowingLut, required by the methods
//                that sample them
//   directional  the directional channels (loadDirectionalOcclusion, or the glTF extension's through
//                gltf.js), required by the texel methods (directional-view and its pair)
//   samples      samples of the generic-vndf estimator (default 32)
//   debug        compile the debug outputs (setDebug); off by default (no cost)
//   areaLights   'cap' (default: the equivalent cap of each RectAreaLight and the term's cap form) or 'center'
//                (the point term at the direction to the rectangle's centre: cheaper, less accurate)
// Returns a handle: enabled (get/set: micro-shadowing on or off; off is three's own program, compiled at the
// first switch and kept: no cost when off), method, lobes,
// uniforms, setDebug(mode | null, lightIndex), dispose() (restores the material's own onBeforeCompile).
// Idempotent per material: a second call with the same options (deep-equal after the defaults; textures and
// tables by identity) returns the same handle; other options throw, naming the option, until dispose().
export function addMicroShadowing(material, options = {}) {
  const { problem, resolved } = checkMaterial(material, options);
  if (problem) throw new Error(`microshadow: ${problem.reason}`);
  const active = ACTIVE.get(material);
  return active ? active.handle : patch(material, resolved);
}

// Adds micro-shadowing to every distinct material of the meshes under root (docs/three.md, "A glTF model"):
// each once however many meshes share it, arrays of materials included. Every material is checked before
// any is changed; a bad option throws. Returns { patched: [{ material, handle }], skipped: [{ material, code,
// reason }] } with code 'unsupported' (not a MeshStandardMaterial or MeshPhysicalMaterial: glTF's unlit
// materials), 'no-aomap' (V from the aoMap, which it has not) or 'conflict' (micro-shadowing already, with
// other options); a material patched before with the same options is listed with its handle. If patching
// fails, the materials patched by this call are restored and the error is thrown again.
export function addMicroShadowingToScene(root, options = {}) {
  resolveOptions(options, true);  // a bad option throws here, before anything is looked at
  const materials = new Set();
  root.traverse((o) => { if (o.isMesh) for (const m of asList(o.material)) if (m) materials.add(m); });
  const checked = [...materials].map((material) => ({ material, ...checkMaterial(material, options) }));
  const patched = [], skipped = [], added = [];
  try {
    for (const { material, problem, resolved } of checked) {
      if (problem) {
        skipped.push({ material, ...problem });
        continue;
      }
      const active = ACTIVE.get(material);
      const handle = active ? active.handle : patch(material, resolved);
      if (!active) added.push(handle);
      patched.push({ material, handle });
    }
  } catch (e) {
    for (const h of added.reverse()) h.dispose();
    throw e;
  }
  return { patched, skipped };
}

// Sets the patched material's uniforms from the resolved options.
function setUniforms(uniforms, { cfg, visSource, luts, dir }) {
  uniforms.msh_enabled.value = true;
  uniforms.u_samples.value = cfg.samples;
  uniforms.msh_debug_mode.value = 0;
  uniforms.msh_debug_light.value = -1;
  if (visSource === 'constant') uniforms.msh_visibility.value = cfg.visibility;
  if (visSource === 'map') uniforms.msh_visibility_map.value = cfg.visibilityMap;
  if (dir) {
    for (let t = 0; t < 6; ++t) uniforms[`msh_dir_tex${t}`].value = t < dir.textures ? dir.maps[t] : null;
    uniforms.msh_dir_lo.value = dir.uniforms.lo;
    uniforms.msh_dir_hi.value = dir.uniforms.hi;
    uniforms.msh_dir_mean.value = dir.uniforms.mean;
    uniforms.msh_dir_basis.value = dir.uniforms.basis;
  }
  for (const k of luts) {
    const L = cfg.luts[k], u = LUT_UNIFORMS[k];
    uniforms[u].value = L.texture;
    uniforms[`${u}_slabs`].value = L.slabs;
    if (k === 'lut_azimuth') uniforms.u_lut_az_harmonics.value = L.harmonics;
  }
}

// three's AO on indirect light left out (aoOnIndirect = false).
function withoutIndirectAo(fs) {
  return replaceOnce(fs, '#include <aomap_fragment>', '// microshadow: aoOnIndirect = false, three\'s AO on indirect light left out', 'fragment');
}

// The debug outputs (options.debug): after dithering, gl_FragColor is the output msh_debug_mode names
// (DEBUG_MODES); with directional channels also their inputs and frame.
function debugOutputs(dir) {
  return `#include <dithering_fragment>
	if ( msh_debug_mode == 1 ) gl_FragColor = msh_dbg_inputs;
	else if ( msh_debug_mode == 2 ) gl_FragColor = msh_dbg_terms;
	else if ( msh_debug_mode == 3 ) gl_FragColor = msh_dbg_v;
	else if ( msh_debug_mode == 4 ) gl_FragColor = msh_dbg_l;
	else if ( msh_debug_mode == 5 ) gl_FragColor = msh_dbg_cap;
	else if ( msh_debug_mode == 6 ) gl_FragColor = vec4( geometryPosition, 1.0 );
	else if ( msh_debug_mode == 7 ) gl_FragColor = vec4( geometryNormal, 1.0 );
	else if ( msh_debug_mode == 8 ) gl_FragColor = msh_dbg_direct;
	else if ( msh_debug_mode == 9 ) gl_FragColor = msh_dbg_d;
	else if ( msh_debug_mode == 10 ) gl_FragColor = msh_dbg_s;
	else if ( msh_debug_mode == 11 ) gl_FragColor = vec4( reflectedLight.indirectDiffuse, 1.0 );${dir ? `
	else if ( msh_debug_mode >= 12 && msh_debug_mode <= 17 ) gl_FragColor = msh_dir_c[ msh_debug_mode - 12 ];
${Array.from({ length: dir.textures }, (_, t) => `	else if ( msh_debug_mode == ${18 + t} ) gl_FragColor = msh_dir_a[ ${t} ];`).join('\n')}
	else if ( msh_debug_mode == 24 ) gl_FragColor = msh_dbg_dir_l;
	else if ( msh_debug_mode == 25 ) gl_FragColor = msh_dbg_dir_v;
	else if ( msh_debug_mode == 26 ) gl_FragColor = vec4( msh_dir_n, 1.0 );
	else if ( msh_debug_mode == 27 ) gl_FragColor = vec4( vMshDirUv, 0.0, 1.0 );
	else if ( msh_debug_mode == 28 ) gl_FragColor = vec4( msh_dir_x, 1.0 );
	else if ( msh_debug_mode == 29 ) gl_FragColor = vec4( msh_dir_y, 1.0 );
	else if ( msh_debug_mode == 30 ) gl_FragColor = vec4( msh_dir_z, 1.0 );` : ''}`;
}

// three's fragment shader with micro-shadowing: the module's functions after the lights' pars, the
// directional frame after the normal maps, V before the lights, three's AO on indirect light left out
// without aoOnIndirect, the debug outputs with debug.
function patchFragment(fs, { lobes, luts, debug, visSource, dir, areaLights, aoOnIndirect }) {
  fs = replaceOnce(fs, '#include <lights_physical_pars_fragment>',
    `#include <lights_physical_pars_fragment>\n${debug ? '#define MSH_DEBUG\n' : ''}${parsBlock(lobes, luts, debug, visSource, dir, areaLights)}`, 'fragment');
  if (dir) fs = replaceOnce(fs, '#include <normal_fragment_maps>', '#include <normal_fragment_maps>\n\tmsh_dir_setup( - vViewPosition, nonPerturbedNormal, normal, vMshDirUv );', 'fragment');
  const vis = visSource === 'aoMap'
    ? '#ifdef USE_AOMAP\n\tmsh_vis = ( texture2D( aoMap, vAoMapUv ).r - 1.0 ) * aoMapIntensity + 1.0;\n#endif'
    : visSource === 'map' ? '\tmsh_vis = texture2D( msh_visibility_map, vMshVisUv ).r;'
    : visSource === 'none' ? '\tmsh_vis = 1.0;' : '\tmsh_vis = msh_visibility;';
  fs = replaceOnce(fs, '#include <lights_fragment_begin>', `${vis}\n\tmsh_vis = clamp( msh_vis, 0.0, 1.0 );\n#include <lights_fragment_begin>`, 'fragment');
  if (!aoOnIndirect) fs = withoutIndirectAo(fs);
  if (debug) fs = replaceOnce(fs, '#include <dithering_fragment>', debugOutputs(dir), 'fragment');
  return fs;
}

// three's vertex shader with the UVs the fragment shader reads: the visibility map's (its transform) and
// the directional channels' (UV channel 0, no transform).
function patchVertex(vs, visSource, dir) {
  const decl = [], set = [];
  if (visSource === 'map') {
    decl.push('uniform mat3 msh_visibility_map_transform;\nvarying vec2 vMshVisUv;');
    set.push('\tvMshVisUv = ( msh_visibility_map_transform * vec3( uv, 1.0 ) ).xy;');
  }
  if (dir) { decl.push('varying vec2 vMshDirUv;'); set.push('\tvMshDirUv = uv;'); }  // UV channel 0, no transform
  vs = replaceOnce(vs, '#include <common>', `#include <common>\n${decl.join('\n')}`, 'vertex');
  vs = replaceOnce(vs, '#include <uv_vertex>', `#include <uv_vertex>\n${set.join('\n')}`, 'vertex');
  return vs;
}

// The handle of a patched material (addMicroShadowing's comment); previous, previousKey: the material's own
// hooks, restored by dispose().
function makeHandle(material, { method, lobes, uniforms, dir, debug, visSource, previous, previousKey }) {
  const handle = {
    method,
    lobes,
    uniforms,
    directional: dir,
    get enabled() { return uniforms.msh_enabled.value; },
    // Off: without debug, the material's program becomes three's own (material.needsUpdate: a program of its
    // own, compiled once, kept by three beside the module's, so switching back and forth compiles nothing more).
    set enabled(on) {
      if (uniforms.msh_enabled.value === !!on) return;
      uniforms.msh_enabled.value = !!on;
      if (!debug && ACTIVE.get(material)?.handle === handle) material.needsUpdate = true;
    },
    // Debug output (needs options.debug): a DEBUG_MODES name, or null for the normal colour; lightIndex is
    // the light's place in three's light loop (point, spot, directional, then RectAreaLights, each in scene
    // order); with lightIndex >= 0 the other lights' direct light is left out.
    setDebug(mode, lightIndex = 0) {
      if (!debug) throw new Error('microshadow: setDebug needs addMicroShadowing(material, { debug: true })');
      if (mode !== null && !DEBUG_MODES[mode]) throw new Error(`microshadow: unknown debug mode '${mode}'; modes: ${Object.keys(DEBUG_MODES).join(', ')}`);
      uniforms.msh_debug_mode.value = mode === null ? 0 : DEBUG_MODES[mode];
      uniforms.msh_debug_light.value = mode === null ? -1 : lightIndex;
    },
    // The visibility map's UV transform follows the texture's (texture.matrix); call after changing it.
    updateVisibilityTransform() {
      if (visSource !== 'map') return;
      const t = uniforms.msh_visibility_map.value;
      if (t.matrixAutoUpdate) t.updateMatrix();
      uniforms.msh_visibility_map_transform.value.copy(t.matrix);
    },
    // Restores the material; a handle disposed already (or replaced since) does nothing.
    dispose() {
      if (ACTIVE.get(material)?.handle !== handle) return;
      ACTIVE.delete(material);
      material.onBeforeCompile = previous;
      material.customProgramCacheKey = previousKey;
      material.needsUpdate = true;
    },
  };
  return handle;
}

function patch(material, { cfg, visSource, lobes, luts, dir }) {
  const { method, aoOnIndirect, debug, areaLights } = cfg;
  const uniforms = materialUniforms(material);
  setUniforms(uniforms, { cfg, visSource, luts, dir });
  // The material's own hooks (not three's defaults) are kept: called first, and part of the cache key.
  const proto = Object.getPrototypeOf(material);
  const previous = material.onBeforeCompile, previousKey = material.customProgramCacheKey;
  const userCompile = previous !== proto.onBeforeCompile ? previous : null;
  const userKey = previousKey !== proto.customProgramCacheKey ? previousKey : null;
  const patches = (PATCHES.get(material) ?? 0) + 1;
  PATCHES.set(material, patches);
  const key = `msh:${method}:${visSource}:${aoOnIndirect}:${debug}${dir ? `:dir${dir.textures}${dir.identity ? 'i' : 'b'}` : ''}${areaLights === 'center' ? ':area-center' : ''}${patches > 1 ? `:patch${patches}` : ''}`;
  // With debug the switch stays a uniform (the debug outputs read the inputs with micro-shadowing off too).
  const offProgram = () => !debug && !uniforms.msh_enabled.value;
  material.onBeforeCompile = function (shader, renderer) {
    if (userCompile) userCompile.call(this, shader, renderer);
    Object.assign(shader.uniforms, uniforms);
    // Off (handle.enabled = false, without debug): three's own shader, nothing of the module in it (a program
    // of its own, compiled at the first switch: a branch on the uniform before the form factor did not save
    // the work under SwiftShader, docs/three.md "Cost").
    if (offProgram()) {
      if (!aoOnIndirect) shader.fragmentShader = withoutIndirectAo(shader.fragmentShader);
      return;
    }
    shader.fragmentShader = patchFragment(shader.fragmentShader, { lobes, luts, debug, visSource, dir, areaLights, aoOnIndirect });
    if (visSource === 'map' || dir) shader.vertexShader = patchVertex(shader.vertexShader, visSource, dir);
  };
  material.customProgramCacheKey = function () {
    return `${userKey ? userKey.call(this) : userCompile ? userCompile.toString() : ''}|${key}${offProgram() ? ':off' : ''}`;
  };
  material.needsUpdate = true;

  const handle = makeHandle(material, { method, lobes, uniforms, dir, debug, visSource, previous, previousKey });
  ACTIVE.set(material, { handle, cfg });
  handle.updateVisibilityTransform();
  return handle;
}
