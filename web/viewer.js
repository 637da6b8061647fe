// microshadow viewer (docs/viewer.md): WebGL2, the project's own GLSL files (shaders/glsl/*.glsl, fetched and
// concatenated into the fragment shader at load time), a gen-material texture set and the baked cone-layout
// tables (raw half floats, uploaded as 3D textures). Plain JS, no dependencies. Renders on demand only.
import { MICRO_SHADOWING_METHODS, BUMP_TERMINATOR_METHODS } from './methods.js';

const $ = (id) => document.getElementById(id);

function showError(msg) {
  const b = $('banner');
  b.hidden = false;
  b.textContent = (b.textContent ? b.textContent + '\n' : '') + msg;
  console.error(msg);
}

async function fetchOk(url, kind) {
  let r;
  try {
    r = await fetch(url);
  } catch (e) {
    throw new Error(`could not load ${url}: ${e.message}`);
  }
  if (!r.ok) throw new Error(`could not load ${url}: HTTP ${r.status}`);
  return kind === 'json' ? r.json() : kind === 'text' ? r.text() : kind === 'blob' ? r.blob() : r.arrayBuffer();
}

// ---- geometry (world space; y up). Each vertex: position, normal, tangent (dP/du), uv; bitangent = n x t = dP/dv.
function plane(s) {
  const P = [], N = [], T = [], U = [];
  for (const [x, z] of [[-s, s], [s, s], [s, -s], [-s, -s]]) {
    P.push(x, 0, z); N.push(0, 1, 0); T.push(1, 0, 0); U.push((x + s) / (2 * s), (s - z) / (2 * s));
  }
  return { P, N, T, U, I: [0, 1, 2, 0, 2, 3], uvScale: [1, 1] };
}
function sphere(c, r, nu = 96, nv = 48) {
  const P = [], N = [], T = [], U = [], I = [];
  for (let j = 0; j <= nv; ++j) {
    const th = Math.PI * j / nv;
    for (let i = 0; i <= nu; ++i) {
      const ph = 2 * Math.PI * i / nu;
      const n = [Math.sin(th) * Math.cos(ph), Math.cos(th), -Math.sin(th) * Math.sin(ph)];
      P.push(c[0] + r * n[0], c[1] + r * n[1], c[2] + r * n[2]); N.push(...n);
      T.push(-Math.sin(ph), 0, -Math.cos(ph)); U.push(i / nu, 1 - j / nv);
    }
  }
  for (let j = 0; j < nv; ++j)
    for (let i = 0; i < nu; ++i) {
      const a = j * (nu + 1) + i, b = a + nu + 1;
      I.push(a, b, a + 1, a + 1, b, b + 1);
    }
  return { P, N, T, U, I, uvScale: [2, 1] };
}
function cylinder(c, r, h, nu = 96) {
  const P = [], N = [], T = [], U = [], I = [];
  const circ = 2 * Math.PI * r;
  for (let k = 0; k <= 1; ++k)
    for (let i = 0; i <= nu; ++i) {
      const ph = 2 * Math.PI * i / nu, n = [Math.cos(ph), 0, -Math.sin(ph)];
      P.push(c[0] + r * n[0], c[1] + k * h, c[2] + r * n[2]); N.push(...n);
      T.push(-Math.sin(ph), 0, -Math.cos(ph)); U.push(i / nu, k * h / circ);
    }
  for (let i = 0; i < nu; ++i) I.push(i, i + nu + 1, i + 1, i + 1, i + nu + 1, i + nu + 2);
  const base = P.length / 3;  // top cap
  P.push(c[0], c[1] + h, c[2]); N.push(0, 1, 0); T.push(1, 0, 0); U.push(0.5 * r / circ * 2, 0.5 * r / circ * 2);
  for (let i = 0; i <= nu; ++i) {
    const ph = 2 * Math.PI * i / nu, x = r * Math.cos(ph), z = -r * Math.sin(ph);
    P.push(c[0] + x, c[1] + h, c[2] + z); N.push(0, 1, 0); T.push(1, 0, 0);
    U.push((x + r) / circ, (r - z) / circ);
  }
  for (let i = 0; i < nu; ++i) I.push(base, base + 1 + i, base + 2 + i);
  return { P, N, T, U, I, uvScale: [1, 1] };
}

const SCENES = {
  plane: { objects: () => [plane(1.5)], target: [0, 0, 0] },
  sphere: { objects: () => [sphere([0, 0, 0], 1)], target: [0, 0, 0] },
  cylinder: { objects: () => [cylinder([0, -1, 0], 0.8, 2)], target: [0, 0, 0] },
  all: { objects: () => [plane(3), sphere([-1.3, 1, 0], 1), cylinder([1.3, 0, 0], 0.7, 1.8)], target: [0, 0.6, 0] },
};

// ---- shaders
const VERT = `#version 300 es
precision highp float;
layout(location = 0) in vec3 a_pos;
layout(location = 1) in vec3 a_n;
layout(location = 2) in vec3 a_t;
layout(location = 3) in vec2 a_uv;
uniform mat4 u_view_proj;
uniform vec2 u_uv_scale;
out vec3 v_pos; out vec3 v_n; out vec3 v_t; out vec2 v_uv;
void main() {
  v_pos = a_pos; v_n = a_n; v_t = a_t; v_uv = a_uv * u_uv_scale;
  gl_Position = u_view_proj * vec4(a_pos, 1.0);
}`;

function fragmentSource(glsl, methods, bumps) {
  const term = methods.map((m, k) => `  if (m == ${k}) return ${m.glsl};`).join('\n');
  const bump = bumps.map((m, k) => `  if (b == ${k}) return ${m.glsl};`).join('\n');
  return `#version 300 es
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp sampler3D;
${glsl}
#line 1 1
in vec3 v_pos; in vec3 v_n; in vec3 v_t; in vec2 v_uv;
out vec4 o_color;
uniform sampler2D u_base, u_normal, u_rough_tex, u_metal, u_vis_tex;
uniform sampler3D u_lut3d, u_lut2d, u_lut_az;
uniform int u_lut3d_slabs, u_lut2d_slabs, u_lut_az_slabs, u_lut_az_harmonics;
uniform vec3 u_eye, u_light_dir, u_light_pos;
uniform bool u_point, u_bump_hemi;
uniform float u_intensity, u_exposure, u_split, u_normal_strength, u_rough_override, u_vis_override;
uniform int u_method_a, u_method_b, u_bump, u_component, u_mode, u_samples;

float view_term(int m, float vis, float nl, float nv, float rough, float alpha, float cos_phi, vec3 v, vec3 l) {
${term}
  return 1.0;
}
float view_bump(int b, vec3 ng, vec3 ns, vec3 wl) {
${bump}
  return 1.0;
}
vec3 srgb_encode(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
const float PI = 3.14159265358979;

void main() {
  vec3 base = texture(u_base, v_uv).rgb;  // sRGB texture: decoded by the sampler
  float rough = u_rough_override >= 0.0 ? u_rough_override : texture(u_rough_tex, v_uv).r;
  float vis = u_vis_override >= 0.0 ? u_vis_override : texture(u_vis_tex, v_uv).r;
  float metal = texture(u_metal, v_uv).r;
  vec3 tn = texture(u_normal, v_uv).xyz * 2.0 - 1.0;
  tn.xy *= u_normal_strength;
  vec3 ng = normalize(v_n);
  vec3 t = normalize(v_t - ng * dot(ng, v_t)), b = cross(ng, t);
  vec3 ns = normalize(t * tn.x + b * tn.y + ng * tn.z);
  vec3 ts = normalize(t - ns * dot(ns, t)), bs = cross(ns, ts);  // shading frame about the bumped normal
  vec3 wo = normalize(u_eye - v_pos);
  vec3 wl = u_light_dir;
  float E = u_intensity;
  if (u_point) {
    vec3 d = u_light_pos - v_pos;
    float dist2 = max(dot(d, d), 1e-8);
    wl = d * inversesqrt(dist2);
    E = u_intensity / dist2;
  }
  vec3 v = msh_ms_to_shading_frame(wo, ts, bs, ns), l = msh_ms_to_shading_frame(wl, ts, bs, ns);
  float nl = clamp(l.z, 0.0, 1.0), nv = clamp(v.z, 0.0, 1.0);
  float alpha = rough * rough;
  float cos_phi = msh_ms_relative_azimuth_cos(v, l);
  bool right = gl_FragCoord.x >= u_split;
  int m = right ? u_method_b : u_method_a;
  bool lit = dot(ng, wl) > 0.0 && l.z > 0.0;
  float term = lit ? view_term(m, vis, nl, nv, rough, alpha, cos_phi, v, l) : 0.0;
  float bump = lit ? view_bump(u_bump, ng, ns, wl) : 0.0;
  if (u_mode == 2) { o_color = vec4(vis, nl, nv, rough); return; }  // probe: inputs (float target)
  if (u_mode == 3) { o_color = vec4(term, cos_phi, bump, lit ? 1.0 : 0.5); return; }
  if (u_mode == 4) { o_color = vec4(v, 1.0); return; }
  if (u_mode == 5) { o_color = vec4(l, 1.0); return; }
  if (u_mode == 6) { o_color = vec4(ng, 1.0); return; }
  if (u_mode == 7) { o_color = vec4(ns, 1.0); return; }
  if (u_mode == 8) { o_color = vec4(wl, 1.0); return; }
  if (u_mode == 1) { o_color = vec4(vec3(term), 1.0); return; }  // the term, linear grey
  // Lambert + GGX (height-correlated Smith, Schlick Fresnel), Real-Time Rendering 4th ed., eqs. 9.41, 9.42, 9.16.
  vec3 h = normalize(wl + wo);
  float nh = max(dot(ns, h), 0.0), vh = max(dot(wo, h), 0.0);
  float a2 = max(alpha * alpha, 1e-8);
  float dd = nh * nh * (a2 - 1.0) + 1.0;
  float D = a2 / (PI * dd * dd);
  float nvs = max(nv, 1e-4), nls = max(nl, 1e-4);
  float Vis = 0.5 / (nls * sqrt(nvs * nvs * (1.0 - a2) + a2) + nvs * sqrt(nls * nls * (1.0 - a2) + a2));
  vec3 f0 = mix(vec3(0.04), base, metal);
  vec3 F = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);
  vec3 diff = (u_component == 2) ? vec3(0.0) : (1.0 - metal) * base / PI;
  vec3 spec = (u_component == 1) ? vec3(0.0) : D * Vis * F;
  vec3 ambient = (u_component == 2) ? vec3(0.0) : 0.02 * base * (1.0 - metal);
  vec3 c = (diff + spec) * (E * nl * term * bump) + ambient;
  vec3 outc = srgb_encode(c * exp2(u_exposure));
  if (abs(gl_FragCoord.x - u_split) < 0.75) outc = vec3(1.0);
  o_color = vec4(outc, 1.0);
}`;
}

function compile(gl, type, src) {
  const s = gl.createShader(type);
  gl.shaderSource(s, src);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error('shader compile error:\n' + gl.getShaderInfoLog(s));
  return s;
}

// ---- small matrix helpers (column-major)
function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
  return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
}
function lookAt(e, c, up) {
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const nrm = (a) => { const l = Math.hypot(...a); return a.map((x) => x / l); };
  const cr = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const dt = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const f = nrm(sub(c, e)), s = nrm(cr(f, up)), u = cr(s, f);
  return [s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0, -dt(s, e), -dt(u, e), dt(f, e), 1];
}
function mul(a, b) {
  const o = new Array(16).fill(0);
  for (let c = 0; c < 4; ++c) for (let r = 0; r < 4; ++r) for (let k = 0; k < 4; ++k) o[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return o;
}
const dir = (elDeg, azDeg) => {
  const el = elDeg * Math.PI / 180, az = azDeg * Math.PI / 180;
  return [Math.cos(el) * Math.sin(az), Math.sin(el), Math.cos(el) * Math.cos(az)];
};

class Viewer {
  constructor(canvas) {
    this.canvas = canvas;
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error('WebGL2 is not available in this browser: the viewer needs WebGL2 (see docs/viewer.md)');
    this.gl = gl;
    this.floatTargets = !!gl.getExtension('EXT_color_buffer_float');
    this.aniso = gl.getExtension('EXT_texture_filter_anisotropic');
    this.state = null;
    this.dirty = false;
    this.frames = 0;
  }

  async load() {
    const man = await fetchOk('data/manifest.json', 'json');
    this.manifest = man;
    const files = await Promise.all(man.glsl.map((f) => fetchOk(`shaders/glsl/${f}`, 'text')));
    const glsl = files.map((t, i) => `#line 1 ${i + 2}\n// ---- shaders/glsl/${man.glsl[i]}\n${t}`).join('\n');
    this.glslFiles = man.glsl;
    const has = (fn) => !fn || new RegExp(`\\b${fn}\\s*\\(`).test(glsl);
    this.methods = MICRO_SHADOWING_METHODS.filter((m) => has(m.requires) && (!m.lut || (man.luts && man.luts[m.lut])));
    this.bumps = BUMP_TERMINATOR_METHODS.filter((m) => has(m.requires));
    const gl = this.gl;
    const prog = gl.createProgram();
    gl.attachShader(prog, compile(gl, gl.VERTEX_SHADER, VERT));
    gl.attachShader(prog, compile(gl, gl.FRAGMENT_SHADER, fragmentSource(glsl, this.methods, this.bumps)));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error('shader link error:\n' + gl.getProgramInfoLog(prog));
    this.prog = prog;
    this.loc = {};
    const n = gl.getProgramParameter(prog, gl.ACTIVE_UNIFORMS);
    for (let i = 0; i < n; ++i) {
      const name = gl.getActiveUniform(prog, i).name;
      this.loc[name] = gl.getUniformLocation(prog, name);
    }
    const mat = man.material;
    const [tb, tn, tr, tm, tv] = await Promise.all([
      this.loadImage(mat.base_color, true), this.loadImage(mat.normal), this.loadImage(mat.roughness),
      mat.metallic ? this.loadImage(mat.metallic) : this.constTexture(0), this.loadImage(mat.micro_occlusion)]);
    this.tex = { base: tb, normal: tn, rough: tr, metal: tm, vis: tv };
    this.luts = {};
    for (const [key, L] of Object.entries(man.luts || {})) this.luts[key] = { info: L, tex: await this.loadLut(L) };
    this.dummy3d = this.dummyLut();
  }

  async loadImage(url, srgb = false) {
    const blob = await fetchOk(url, 'blob');
    const img = await createImageBitmap(blob, { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
    const gl = this.gl, t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);  // row j of the PNG = v (the renderer's convention)
    gl.texImage2D(gl.TEXTURE_2D, 0, srgb ? gl.SRGB8_ALPHA8 : gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, img);
    gl.generateMipmap(gl.TEXTURE_2D);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR_MIPMAP_LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.REPEAT);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.REPEAT);
    if (this.aniso) gl.texParameterf(gl.TEXTURE_2D, this.aniso.TEXTURE_MAX_ANISOTROPY_EXT, 8);
    return t;
  }
  constTexture(v) {
    const gl = this.gl, t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, 1, 1, 0, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array([v, v, v, 255]));
    return t;
  }
  async loadLut(L) {
    const buf = await fetchOk(L.url, 'arraybuffer');
    const [w, h, d] = L.size, c = L.channels;
    if (buf.byteLength !== w * h * d * c * 2)
      throw new Error(`${L.url}: ${buf.byteLength} bytes, the manifest says ${w}x${h}x${d}x${c} half floats`);
    const gl = this.gl, t = gl.createTexture();
    const fmt = [[gl.R16F, gl.RED], [gl.RG16F, gl.RG], [gl.RGB16F, gl.RGB], [gl.RGBA16F, gl.RGBA]][c - 1];
    gl.bindTexture(gl.TEXTURE_3D, t);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage3D(gl.TEXTURE_3D, 0, fmt[0], w, h, d, 0, fmt[1], gl.HALF_FLOAT, new Uint16Array(buf));
    // Linear filtering, clamp to edge, no mips: the layout the GLSL samplers expect (docs/lut.md).
    gl.texParameteri(gl.TEXTURE_3D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_3D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    for (const p of [gl.TEXTURE_WRAP_S, gl.TEXTURE_WRAP_T, gl.TEXTURE_WRAP_R]) gl.texParameteri(gl.TEXTURE_3D, p, gl.CLAMP_TO_EDGE);
    return t;
  }
  dummyLut() {
    const gl = this.gl, t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_3D, t);
    gl.texImage3D(gl.TEXTURE_3D, 0, gl.R16F, 1, 1, 1, 0, gl.RED, gl.HALF_FLOAT, new Uint16Array([0]));
    return t;
  }

  setScene(name) {
    if (this.sceneName === name) return;
    const gl = this.gl;
    for (const o of this.objects || []) { gl.deleteVertexArray(o.vao); }
    this.sceneName = name;
    this.objects = SCENES[name].objects().map((g) => {
      const vao = gl.createVertexArray();
      gl.bindVertexArray(vao);
      [g.P, g.N, g.T, g.U].forEach((arr, i) => {
        const b = gl.createBuffer();
        gl.bindBuffer(gl.ARRAY_BUFFER, b);
        gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(arr), gl.STATIC_DRAW);
        gl.enableVertexAttribArray(i);
        gl.vertexAttribPointer(i, i === 3 ? 2 : 3, gl.FLOAT, false, 0, 0);
      });
      const ib = gl.createBuffer();
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(g.I), gl.STATIC_DRAW);
      gl.bindVertexArray(null);
      return { vao, count: g.I.length, uvScale: g.uvScale };
    });
  }

  methodIndex(id) {
    const k = this.methods.findIndex((m) => m.id === id);
    return k < 0 ? 0 : k;
  }

  // Draws the scene with state s into the bound framebuffer (w x h); overrides: {mode, method}.
  draw(s, w, h, ov = {}) {
    const gl = this.gl, L = this.loc;
    this.setScene(s.scene);
    gl.viewport(0, 0, w, h);
    gl.enable(gl.DEPTH_TEST);
    if (ov.mode !== undefined) gl.clearColor(0, 0, 0, 0); else gl.clearColor(0.05, 0.05, 0.06, 1);  // probe: alpha 0 = background
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.useProgram(this.prog);
    const target = SCENES[s.scene].target;
    const cd = dir(s.cam_el, s.cam_az);
    const eye = target.map((x, i) => x + s.cam_dist * cd[i]);
    const up = s.cam_el > 89.5 ? [0, 0, -1] : [0, 1, 0];
    gl.uniformMatrix4fv(L.u_view_proj, false, mul(perspective(0.7, w / h, 0.05, 100), lookAt(eye, target, up)));
    gl.uniform3fv(L.u_eye, eye);
    const ld = dir(s.light_el, s.light_az);
    gl.uniform3fv(L.u_light_dir, ld);
    gl.uniform3fv(L.u_light_pos, target.map((x, i) => x + s.light_dist * ld[i]));
    gl.uniform1i(L.u_point, s.light_type === 'point' ? 1 : 0);
    gl.uniform1f(L.u_intensity, s.light_int);
    gl.uniform1f(L.u_exposure, s.exposure);
    const ma = ov.method !== undefined ? ov.method : this.methodIndex(s.method_a);
    const mb = ov.method !== undefined ? ov.method : this.methodIndex(s.method_b);
    gl.uniform1i(L.u_method_a, ma);
    gl.uniform1i(L.u_method_b, s.split && ov.method === undefined ? mb : ma);
    gl.uniform1f(L.u_split, s.split && ov.method === undefined ? s.split_pos * w : -10);
    gl.uniform1i(L.u_samples, s.samples);
    gl.uniform1i(L.u_bump, ov.bump !== undefined ? ov.bump : Math.max(0, this.bumps.findIndex((b) => b.id === s.bump)));
    gl.uniform1i(L.u_bump_hemi, s.bump_hemi ? 1 : 0);
    gl.uniform1f(L.u_rough_override, s.rough_on ? s.rough : -1);
    gl.uniform1f(L.u_vis_override, s.vis_on ? s.vis : -1);
    gl.uniform1f(L.u_normal_strength, s.normal_strength);
    gl.uniform1i(L.u_component, { both: 0, diffuse: 1, specular: 2 }[s.component]);
    gl.uniform1i(L.u_mode, ov.mode !== undefined ? ov.mode : s.display === 'term' ? 1 : 0);
    const units = [['u_base', this.tex.base], ['u_normal', this.tex.normal], ['u_rough_tex', this.tex.rough],
      ['u_metal', this.tex.metal], ['u_vis_tex', this.tex.vis]];
    units.forEach(([name, t], i) => { gl.activeTexture(gl.TEXTURE0 + i); gl.bindTexture(gl.TEXTURE_2D, t); gl.uniform1i(L[name], i); });
    [['u_lut3d', 'lut3d'], ['u_lut2d', 'lut2d'], ['u_lut_az', 'lut_azimuth']].forEach(([name, key], i) => {
      const lut = this.luts[key];
      gl.activeTexture(gl.TEXTURE0 + 5 + i);
      gl.bindTexture(gl.TEXTURE_3D, lut ? lut.tex : this.dummy3d);
      gl.uniform1i(L[name], 5 + i);
      const slabs = lut ? lut.info.roughness_slabs : 1;
      if (L[name + '_slabs']) gl.uniform1i(L[name + '_slabs'], slabs);
    });
    if (L.u_lut_az_harmonics) gl.uniform1i(L.u_lut_az_harmonics, this.luts.lut_azimuth ? this.luts.lut_azimuth.info.harmonics : 0);
    for (const o of this.objects) {
      gl.uniform2f(L.u_uv_scale, s.tiling * o.uvScale[0], s.tiling * o.uvScale[1]);
      gl.bindVertexArray(o.vao);
      gl.drawElements(gl.TRIANGLES, o.count, gl.UNSIGNED_INT, 0);
    }
    gl.bindVertexArray(null);
  }

  render() {
    const gl = this.gl;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.draw(this.state, this.canvas.width, this.canvas.height);
    this.frames++;
  }

  offscreen(w, h, float) {
    const gl = this.gl, key = `${w}x${h}`;
    this.fbos = this.fbos || {};
    const old = this.fbos[float];
    if (old && old.key === key) return old;
    if (old) { gl.deleteFramebuffer(old.fb); gl.deleteTexture(old.tex); gl.deleteRenderbuffer(old.depth); }
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texStorage2D(gl.TEXTURE_2D, 1, float ? gl.RGBA32F : gl.RGBA8, w, h);
    gl.bindTexture(gl.TEXTURE_2D, null);  // never left on a unit the program samples (a feedback loop)
    const depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, w, h);
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) throw new Error('offscreen framebuffer incomplete');
    this.fbos[float] = { key, fb, tex, depth };
    return this.fbos[float];
  }

  // Pixels (x, y from the top-left, canvas pixels) rendered with an override into an offscreen target: one
  // pixel under a scissor, several from one full frame.
  readPoints(pts, ov, float) {
    const gl = this.gl, w = this.canvas.width, h = this.canvas.height;
    const f = this.offscreen(w, h, float);
    gl.bindFramebuffer(gl.FRAMEBUFFER, f.fb);
    const one = pts.length === 1;
    if (one) {
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(pts[0][0], h - 1 - pts[0][1], 1, 1);
    }
    this.draw(this.state, w, h, ov);
    gl.disable(gl.SCISSOR_TEST);
    const [x0, y0, rw, rh] = one ? [pts[0][0], h - 1 - pts[0][1], 1, 1] : [0, 0, w, h];
    const buf = float ? new Float32Array(rw * rh * 4) : new Uint8Array(rw * rh * 4);
    gl.readPixels(x0, y0, rw, rh, gl.RGBA, float ? gl.FLOAT : gl.UNSIGNED_BYTE, buf);
    const err = gl.getError();
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    if (err !== gl.NO_ERROR) throw new Error(`WebGL error 0x${err.toString(16)} reading pixels`);
    return pts.map(([x, y]) => {
      const i = one ? 0 : 4 * ((h - 1 - y) * w + x);
      return Array.from(buf.subarray(i, i + 4));
    });
  }

  // The probe: the shader's inputs at each pixel and every method's value there (float32 render targets), and
  // with term8 each method's 8-bit "term" display output.
  probeMany(pts, term8 = false) {
    if (!this.floatTargets) throw new Error('the probe needs EXT_color_buffer_float (float render targets)');
    const inputs = this.readPoints(pts, { mode: 2, method: 0 }, true);
    const extra = this.readPoints(pts, { mode: 3, method: 0 }, true);
    const vs = this.readPoints(pts, { mode: 4, method: 0 }, true), ls = this.readPoints(pts, { mode: 5, method: 0 }, true);
    const per = this.methods.map((m, k) => this.readPoints(pts, { mode: 3, method: k }, true));
    const world = [6, 7, 8].map((mode) => this.readPoints(pts, { mode, method: 0 }, true));
    const perBump = this.bumps.map((b, k) => this.readPoints(pts, { mode: 3, method: 0, bump: k }, true));
    const per8 = term8 ? this.methods.map((m, k) => this.readPoints(pts, { mode: 1, method: k }, false)) : null;
    return pts.map(([x, y], i) => {
      const [vis, nl, nv, rough] = inputs[i], [, cos_phi, bump, hit] = extra[i];
      if (!(hit > 0)) return { x, y, hit: false, lit: false };
      const values = {}, t8 = {};
      this.methods.forEach((m, k) => { values[m.id] = per[k][i][0]; if (per8) t8[m.id] = per8[k][i][0]; });
      const p = { x, y, hit: true, visibility: vis, ndotl: nl, ndotv: nv, roughness: rough, cos_phi, bump, lit: hit > 0.75,
        v: vs[i].slice(0, 3), l: ls[i].slice(0, 3), samples: this.state.samples, values };
      p.ng = world[0][i].slice(0, 3); p.ns = world[1][i].slice(0, 3); p.wl = world[2][i].slice(0, 3);
      p.bump_hemi = !!this.state.bump_hemi;
      p.bumps = {};
      this.bumps.forEach((b, k) => { p.bumps[b.id] = perBump[k][i][2]; });
      if (per8) p.term8 = t8;
      return p;
    });
  }
  probe(x, y) { return this.probeMany([[x, y]])[0]; }
}

// ---- UI
const CONTROLS = ['scene', 'tiling', 'cam_el', 'cam_az', 'cam_dist', 'light_type', 'light_el', 'light_az', 'light_dist',
  'light_int', 'exposure', 'method_a', 'method_b', 'split', 'split_pos', 'samples', 'bump', 'bump_hemi', 'rough_on', 'rough',
  'normal_strength', 'vis_on', 'vis', 'component', 'display'];

function readControls() {
  const s = {};
  for (const id of CONTROLS) {
    const e = $(id);
    s[id] = e.type === 'checkbox' ? e.checked : e.type === 'range' ? Number(e.value) : e.value;
  }
  return s;
}
function writeControls(s) {
  for (const [k, v] of Object.entries(s)) {
    const e = $(k);
    if (!e) throw new Error(`unknown control '${k}'`);
    if (e.type === 'checkbox') e.checked = !!v; else e.value = String(v);
  }
  showOutputs();
}
function showOutputs() {
  for (const e of document.querySelectorAll('input[type=range]')) {
    const o = e.parentElement.querySelector('output');
    if (o) o.textContent = e.value;
  }
}

function formatProbe(p, viewer) {
  const f = (x) => (typeof x === 'number' ? x.toFixed(4) : String(x));
  const lines = [`pixel (${p.x}, ${p.y})${p.lit ? '' : '  (not lit: N_g·L or N·L <= 0)'}`,
    `V ${f(p.visibility)}  N·L ${f(p.ndotl)}  N·V ${f(p.ndotv)}`, `roughness ${f(p.roughness)}  cos φ ${f(p.cos_phi)}  bump ${f(p.bump)}`, ''];
  lines.push(`bump terminator: ${viewer.bumps.map((b) => `${b.id} ${f(p.bumps[b.id])}`).join(', ')}`, '');
  for (const m of viewer.methods) lines.push(`${f(p.values[m.id])}  ${m.label}${m.id === 'generic-vndf' ? ` (N = ${p.samples})` : ''}`);
  return lines.join('\n');
}

async function main() {
  const canvas = $('gl');
  let viewer;
  try {
    viewer = new Viewer(canvas);
    await viewer.load();
  } catch (e) {
    showError(e.message);
    window.mshViewer = { error: e.message, ready: Promise.resolve(false) };
    return;
  }
  for (const sel of ['method_a', 'method_b']) {
    $(sel).innerHTML = viewer.methods.map((m) => `<option value="${m.id}">${m.label}</option>`).join('');
  }
  $('method_a').value = viewer.methods.some((m) => m.id === 'chan-2018') ? 'chan-2018' : viewer.methods[0].id;
  $('method_b').value = viewer.methods.some((m) => m.id === 'lut3d') ? 'lut3d' : viewer.methods[viewer.methods.length - 1].id;
  $('bump').innerHTML = viewer.bumps.map((m) => `<option value="${m.id}">${m.label}</option>`).join('');
  const m = viewer.manifest;
  $('info').textContent = `texture set: ${m.material.name}; tables: ${Object.entries(m.luts || {}).map(([k, L]) =>
    `${k} ${L.size.join('×')}×${L.channels} (${L.source})`).join(', ')}; GLSL: ${viewer.glslFiles.join(', ')}`;

  const labels = () => {
    const s = viewer.state, lab = (id) => (viewer.methods.find((x) => x.id === id) || {}).label || id;
    $('label-a').textContent = s.split ? `A: ${lab(s.method_a)}` : lab(s.method_a);
    $('label-b').textContent = s.split ? `B: ${lab(s.method_b)}` : '';
  };
  let pending = false;
  const update = () => {
    viewer.state = readControls();
    showOutputs();
    labels();
    if (!pending) {
      pending = true;
      requestAnimationFrame(() => {
        pending = false;
        try { viewer.render(); } catch (e) { showError(e.message); }
      });
    }
  };
  $('panel').addEventListener('input', update);
  $('panel').addEventListener('change', update);

  // Drag: the light direction (x: azimuth, y: elevation); a click without a drag: the probe.
  let drag = null;
  canvas.addEventListener('pointerdown', (e) => { drag = { x: e.clientX, y: e.clientY, moved: false }; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    if (!drag.moved && Math.hypot(dx, dy) < 3) return;
    drag.moved = true;
    drag.x = e.clientX; drag.y = e.clientY;
    const az = ((Number($('light_az').value) + dx * 0.5 + 540) % 360) - 180;
    $('light_az').value = az;
    $('light_el').value = Math.min(90, Math.max(0, Number($('light_el').value) - dy * 0.3));
    update();
  });
  canvas.addEventListener('pointerup', (e) => {
    if (drag && !drag.moved) {
      const r = canvas.getBoundingClientRect();
      const x = Math.floor((e.clientX - r.left) * canvas.width / r.width), y = Math.floor((e.clientY - r.top) * canvas.height / r.height);
      try { const p = viewer.probe(x, y); $('probe').textContent = p.hit ? formatProbe(p, viewer) : `pixel (${x}, ${y}): background`; } catch (err) { showError(err.message); }
    }
    drag = null;
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    $('cam_dist').value = Math.min(12, Math.max(1.5, Number($('cam_dist').value) * (e.deltaY > 0 ? 1.1 : 1 / 1.1)));
    update();
  }, { passive: false });

  update();
  // For scripts (the browser test, the frame-time bench): set controls, render synchronously, probe.
  window.mshViewer = {
    ready: Promise.resolve(true),
    methods: viewer.methods.map((x) => ({ id: x.id, label: x.label, lut: x.lut || null, cpp: x.cpp || null })),
    bumps: viewer.bumps.map((x) => x.id),
    manifest: viewer.manifest,
    set(s) { writeControls(s); viewer.state = readControls(); labels(); },
    resize(w, h) { canvas.width = w; canvas.height = h; },
    render() { viewer.render(); viewer.gl.finish(); return viewer.gl.getError(); },
    // Renders n frames and returns the mean milliseconds per frame (each ends with a 1-pixel readback, so the
    // GPU work is included).
    time(n) {
      const gl = viewer.gl, px = new Uint8Array(4);
      viewer.render(); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
      const t0 = performance.now();
      for (let i = 0; i < n; ++i) { viewer.render(); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px); }
      return (performance.now() - t0) / n;
    },
    probe(x, y) { return viewer.probe(x, y); },
    probeMany(pts, term8) { return viewer.probeMany(pts, term8); },
    size() { return [canvas.width, canvas.height]; },
  };
}

window.addEventListener('error', (e) => showError(`error: ${e.message}`));
window.addEventListener('unhandledrejection', (e) => showError(`error: ${e.reason && e.reason.message ? e.reason.message : e.reason}`));
main();
