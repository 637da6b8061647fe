// In-page part of the three.js browser test (tests/browser/three_test.mjs injects it into the example page
// opened with ?probe, whose import map serves three and microshadow-three). A known scene — a plane, a sphere
// and a cylinder with a procedural normal map, V from the material's aoMap (plane), a separate visibility map
// (sphere) and a constant (cylinder) — lit by one point, one spot, one directional and one rect-area light;
// for every method and light it renders the module's debug outputs into float32 and 8-bit render targets and
// reads back the probe pixels: the inputs (V, N·L, N·V, roughness, v, l, the rect light's equivalent cap),
// each lobe's term, the light's direct diffuse and specular with micro-shadowing on and off, and the pixel's
// view-space position and normal (the C++ test recomputes N·L and the equivalent cap from the scene).
import * as THREE from 'three';
import { RectAreaLightUniformsLib } from 'three/addons/lights/RectAreaLightUniformsLib.js';
import * as MSH from 'microshadow-three';
import { probeRenderer, renderTargets, probePoints, readProbes, renderShaded, viewRect, probeScene } from './msh-test/probe_common.js';

const V_LEVELS = [38, 77, 115, 140, 158, 179, 204, 230, 255];  // the visibility texture's bytes
const V_CONST = 0.62;                                           // the cylinder's constant V
const ROUGH = [0.35, 0.6, 0.85];                                // plane, sphere, cylinder
const LIGHT_ORDER = ['point', 'spot', 'directional', 'rect'];   // three's light loop order (index = debug light)
const SAMPLES = 16;                                             // the generic-vndf estimator's samples

function dataTexture(w, h, f, { nearest = false } = {}) {
  const d = new Uint8Array(w * h * 4);
  for (let j = 0; j < h; ++j) for (let i = 0; i < w; ++i) d.set(f(i, j), 4 * (j * w + i));
  const t = new THREE.DataTexture(d, w, h, THREE.RGBAFormat, THREE.UnsignedByteType);
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  if (nearest) { t.minFilter = t.magFilter = THREE.NearestFilter; t.generateMipmaps = false; } else { t.minFilter = THREE.LinearMipmapLinearFilter; t.generateMipmaps = true; }
  t.needsUpdate = true;
  return t;
}

let S = null;
let S_KTX2 = null;

async function setup({ width, height, grid, tables = true }) {
  RectAreaLightUniformsLib.init();
  const man = await (await fetch('data/manifest.json')).json();
  const luts = {};
  for (const [k, L] of Object.entries(man.luts || {})) luts[k] = await MSH.loadMicroShadowingLut(L.url);
  const renderer = probeRenderer(width, height);
  const vis = dataTexture(8, 8, (i, j) => { const v = V_LEVELS[(3 * i + 5 * j) % V_LEVELS.length]; return [v, v, v, 255]; }, { nearest: true });
  // Smooth bumps: h = 0.12 (sin 2πu sin 2πv + 0.5 sin 6πu), normal = normalize(−∂h/∂u, −∂h/∂v, 1).
  const N = 64;
  const nmap = dataTexture(N, N, (i, j) => {
    const u = (i + 0.5) / N, v = (j + 0.5) / N, tp = 2 * Math.PI;
    const hu = 0.12 * tp * (Math.cos(tp * u) * Math.sin(tp * v) + 1.5 * Math.cos(3 * tp * u));
    const hv = 0.12 * tp * Math.sin(tp * u) * Math.cos(tp * v);
    const l = Math.hypot(hu, hv, 1);
    return [-hu / l, -hv / l, 1 / l].map((x) => Math.round((x * 0.5 + 0.5) * 255)).concat([255]);
  });
  const mat = (r) => new THREE.MeshStandardMaterial({ color: 0xcccccc, roughness: r, metalness: 0, normalMap: nmap });
  const mats = ROUGH.map(mat);
  for (const m of mats) m.aoMap = vis;
  const { scene, camera, lights } = probeScene(width, height, [new THREE.PlaneGeometry(5, 5).rotateX(-Math.PI / 2),
    new THREE.SphereGeometry(0.8, 64, 32), new THREE.CylinderGeometry(0.6, 0.6, 1.6, 64, 1, true)], mats);
  S = { renderer, scene, camera, mats, luts, vis, width, height, ...renderTargets(width, height), handles: [],
    points: probePoints(width, height, grid) };
  // The texel methods (directional-view, which read a texture set's directional channels) are
  // tested by three_directional_probe.js.
  const methods = MSH.MICRO_SHADOWING_METHODS.filter((m) => !m.texel).map((m) => ({ id: m.id, label: m.label, lut: m.lut || null, cpp: m.cpp,
    pair: m.glsl_diffuse !== undefined, lobes: MSH.methodLobes(m.id) }));
  // The NPY loader: the test writes the default 3D table as float32 NPY (data/lut3d.npy, the format of
  // `bake micro-shadowing --out lut.npy`); its half floats against the served raw half floats.
  let npy = null;
  if (luts.lut3d && tables) {  // tables: false (the timing) needs no NPY/KTX2 files
    const T = await MSH.loadMicroShadowingLut('data/lut3d.npy');
    const a = T.texture.image.data, b = luts.lut3d.texture.image.data;
    let maxUlps = 0;
    for (let i = 0; i < Math.min(a.length, b.length); ++i) maxUlps = Math.max(maxUlps, Math.abs(a[i] - b[i]));
    npy = { size: T.size, channels: T.channels, slabs: T.slabs, f16_size: luts.lut3d.size, n: a.length, f16_n: b.length, max_ulps: maxUlps };
    // And the installed default table (share/microshadow/tables/micro_shadowing.ktx2, R16F; the test copies it
    // to data/lut3d.ktx2) through three's KTX2Loader: the same half floats.
    const K = await MSH.loadMicroShadowingLut('data/lut3d.ktx2', { renderer });
    const k = K.texture.image.data;
    let kUlps = 0;
    for (let i = 0; i < Math.min(k.length, b.length); ++i) kUlps = Math.max(kUlps, Math.abs(k[i] - b[i]));
    npy.ktx2 = { size: K.size, channels: K.channels, n: k.length, max_ulps: kUlps, type: K.texture.type, is3d: !!K.texture.isData3DTexture };
    S_KTX2 = K;  // rendered with in the last run (three_test.mjs)
  }
  return { npy, methods, lights, light_order: LIGHT_ORDER, samples: SAMPLES, v_levels: V_LEVELS.map((b) => b / 255), v_const: V_CONST, roughness: ROUGH,
    luts: Object.fromEntries(Object.entries(luts).map(([k, L]) => [k, { size: L.size, slabs: L.slabs, harmonics: L.harmonics, url: L.url }])),
    revision: THREE.REVISION };
}

// The method on the three materials: V from the aoMap on all three, or (variant) from the aoMap on the
// plane, the separate visibility map on the sphere and the constant on the cylinder.
function attach(method, variant = false, aoOnIndirect = true, luts = S.luts, extra = {}) {
  for (const h of S.handles) h.dispose();
  const base = { method, luts, debug: true, samples: SAMPLES, aoOnIndirect, ...extra };
  S.handles = [MSH.addMicroShadowing(S.mats[0], { ...base }),
    MSH.addMicroShadowing(S.mats[1], variant ? { ...base, visibilityMap: S.vis } : base),
    MSH.addMicroShadowing(S.mats[2], variant ? { ...base, visibility: V_CONST } : base)];
}

// The probe pixels of one render of debug `mode` for light `k` (-1: every light lit), rows from the top.
function read(mode, k, float, enabled = true) { return readProbes(S, S.handles, mode, k, float, enabled); }

// One method: both lobes' terms of the four lights (float and 8-bit); with o.inputs the inputs of every
// light (V, N·L, N·V, roughness; v, l; the rect light's cap; position, normal), with o.direct each light's
// direct light with micro-shadowing on and off; with o.ktx2 the 3D table loaded from KTX2.
function run(method, o = {}) {
  const t0 = performance.now();
  attach(method, !!o.variant, true, o.ktx2 ? { ...S.luts, lut3d: S_KTX2 } : S.luts);
  const gl = S.renderer.getContext();
  const out = { method, variant: !!o.variant, terms_d: read('terms_diffuse', -1, true), terms_s: read('terms_specular', -1, true),
    terms8_d: read('terms_diffuse', -1, false), terms8_s: read('terms_specular', -1, false) };
  out.first_ms = performance.now() - t0;
  if (o.inputs || o.direct) {
    out.lights = [];
    for (let k = 0; k < LIGHT_ORDER.length; ++k) {
      const L = {};
      if (o.inputs) for (const m of ['inputs', 'v', 'l', 'position', 'normal'].concat(LIGHT_ORDER[k] === 'rect' ? ['cap'] : [])) L[m] = read(m, k, true);
      if (o.direct) { L.direct_on = read('direct', k, true); L.direct_off = read('direct', k, true, false); }
      out.lights.push(L);
    }
  }
  out.error = gl.getError();
  out.ms = performance.now() - t0;
  return out;
}

// The AO switch: three's indirect diffuse light with aoOnIndirect true and false, and V (V from the aoMap).
function aoSwitch(method) {
  attach(method, false, true);
  const on = read('indirect', -1, true), inputs = read('inputs', 0, true);
  attach(method, false, false);
  const off = read('indirect', -1, true);
  return { on, off, inputs };
}

// A shaded frame on the canvas (sRGB output) with every light, micro-shadowing on or off.
function shaded(method, enabled) {
  attach(method);
  for (const h of S.handles) h.enabled = enabled;
  return renderShaded(S);
}

// ---- areaLights 'cap' / 'center' and micro-shadowing off (docs/three.md, "Rect-area lights" and "Cost")

const RECT = LIGHT_ORDER.indexOf('rect');
function rectLight() { let r = null; S.scene.traverse((o) => { if (o.isRectAreaLight) r = o; }); return r; }
// The rect light as three's shaders see it (view space), for the C++ side.
function rectView(rect) { return { ...viewRect(rect, S.camera), width: rect.width, height: rect.height }; }

// The whole float32 frame of the shaded scene (every light, debug off: the shipped program).
function frame() {
  const { width: w, height: h } = S;
  S.renderer.setRenderTarget(S.rtF);
  S.renderer.setClearColor(0x000000, 0);
  S.renderer.clear();
  S.renderer.render(S.scene, S.camera);
  const buf = new Float32Array(w * h * 4);
  S.renderer.readRenderTargetPixels(S.rtF, 0, 0, w, h, buf);
  S.renderer.setRenderTarget(null);
  return buf;
}
function frameDiff(a, b) {
  let max = 0, n = 0;
  for (let i = 0; i < a.length; ++i) { const d = Math.abs(a[i] - b[i]); if (d > 0) ++n; if (d > max) max = d; }
  return { max, differing: n, values: a.length };
}

// 1. areaLights 'center' with the method: each lobe's term of the rect light and its inputs at the probe pixels
// (the C++ side evaluates the point term at the direction to the rectangle's centre). 2. Micro-shadowing off
// (enabled = false, debug off) against the module absent (the materials disposed), 'cap' and 'center': the whole
// float32 frame; on against absent for contrast. 3. 'cap' against 'center' for rect lights of several sizes and
// distances (methods: the list given), with the cap's N·L and angular radius.
function area(method, methods, configs) {
  const gl = S.renderer.getContext();
  const out = { method, rect: rectView(rectLight()) };
  attach(method, false, true, S.luts, { areaLights: 'center' });
  out.lobes = MSH.methodLobes(method, 'center');
  out.handle_forms = [S.handles[0].lobes.diffuse.form, S.handles[0].lobes.specular.form];
  out.key = S.mats[0].customProgramCacheKey();
  out.center = { terms: read('terms', RECT, true), terms8: read('terms', RECT, false) };
  for (const m of ['inputs', 'v', 'l', 'position', 'normal', 'cap']) out.center[m] = read(m, RECT, true);
  attach(method, false, true, S.luts, { areaLights: 'cap' });
  out.cap = { terms: read('terms', RECT, true) };
  // The option's checks: another value throws one line; another mode on a patched material is a conflict
  // naming it; the default is 'cap' (the same handle).
  const error = (f) => { try { f(); return null; } catch (e) { return e.message; } };
  const fresh = new THREE.MeshStandardMaterial({ aoMap: S.vis });
  out.api = { bad: error(() => MSH.addMicroShadowing(fresh, { areaLights: 'disk' })), modes: MSH.AREA_LIGHT_MODES };
  const hc = MSH.addMicroShadowing(fresh, { areaLights: 'cap' });
  out.api.default_same = MSH.addMicroShadowing(fresh, {}) === hc;
  out.api.other = error(() => MSH.addMicroShadowing(fresh, { areaLights: 'center' }));
  hc.dispose();
  out.api.after_dispose = MSH.addMicroShadowing(fresh, { areaLights: 'center' }).lobes.specular.form;
  // 2. off = absent
  out.disabled = {};
  for (const mode of ['cap', 'center']) {
    for (const h of S.handles) h.dispose();
    S.handles = S.mats.map((m) => MSH.addMicroShadowing(m, { method, luts: S.luts, areaLights: mode }));
    for (const h of S.handles) h.enabled = false;
    const off = frame();
    for (const h of S.handles) h.enabled = true;
    const on = frame();
    for (const h of S.handles) h.dispose();
    S.handles = [];
    const absent = frame();
    out.disabled[mode] = { off: frameDiff(off, absent), on: frameDiff(on, absent) };
  }
  // 3. cap against center, per rect light size and distance (scaled about the point it looks at)
  const rect = rectLight(), p0 = rect.position.clone(), w0 = rect.width, h0 = rect.height, target = new THREE.Vector3(0, 0.3, 0);
  out.accuracy = [];
  for (const id of methods) {
    const runs = {};
    for (const mode of ['cap', 'center']) {
      attach(id, false, true, S.luts, { areaLights: mode });
      runs[mode] = configs.map(([size, dist]) => {
        rect.width = w0 * size; rect.height = h0 * size;
        rect.position.copy(target).addScaledVector(p0.clone().sub(target), dist);
        rect.lookAt(target);
        rect.updateMatrixWorld(true);
        const r = { terms: read('terms', RECT, true) };
        if (mode === 'cap') r.cap = read('cap', RECT, true);
        return r;
      });
    }
    configs.forEach(([size, dist], c) => {
      rect.width = w0 * size; rect.height = h0 * size;
      rect.position.copy(target).addScaledVector(p0.clone().sub(target), dist);
      rect.lookAt(target);
      rect.updateMatrixWorld(true);
      const e = { method: id, size, distance: dist, rect: rectView(rect), d: [], s: [], rho: [], nl_cap: [], center_lit: [] };
      S.points.forEach((_, p) => {
        const a = runs.cap[c].terms[p], b = runs.center[c].terms[p], cap = runs.cap[c].cap[p];
        if (!(a[3] === 1 || b[3] === 1)) return;   // neither form lit
        e.d.push(b[0] - a[0]); e.s.push(b[1] - a[1]); e.rho.push(cap[1]); e.nl_cap.push(cap[0]);
        e.center_lit.push(b[3] === 1);   // false: the centre below the horizon, part of the rectangle above
      });
      out.accuracy.push(e);
    });
  }
  rect.width = w0; rect.height = h0; rect.position.copy(p0); rect.lookAt(target); rect.updateMatrixWorld(true);
  for (const h of S.handles) h.dispose();
  S.handles = [];
  out.error = gl.getError();
  return out;
}

// ---- frame time per light type (three_test.mjs --light-timing): the probe scene's three materials lit by one
// light type at a time; micro-shadowing on, off (enabled = false) and absent (materials without the module),
// interleaved rounds, each the mean of `frames` frames ended by a 1-pixel read-back; median over rounds.
function timing({ method = 'diffuse-aware-alu+generic-vndf-alu', rounds = 5, frames = 3 } = {}) {
  const { renderer, scene, camera } = S;
  for (const h of S.handles) h.dispose();
  S.handles = [];
  const meshes = [];
  scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
  const lights = {};
  scene.traverse((o) => {
    if (o.isPointLight) lights.point = o; else if (o.isSpotLight) lights.spot = o;
    else if (o.isDirectionalLight) lights.directional = o; else if (o.isRectAreaLight) lights.rect = o;
    else if (o.isAmbientLight) lights.ambient = o;
  });
  lights.hemisphere = new THREE.HemisphereLight(0xbfd4ff, 0x403020, 1.0);
  scene.add(lights.hemisphere);
  const absent = S.mats.map((m) => m.clone());
  const sets = { cap: S.mats.map((m) => m.clone()), center: S.mats.map((m) => m.clone()) };
  const handles = { cap: sets.cap.map((m) => MSH.addMicroShadowing(m, { method, luts: S.luts, areaLights: 'cap' })),
    center: sets.center.map((m) => MSH.addMicroShadowing(m, { method, luts: S.luts, areaLights: 'center' })) };
  const types = [['directional', ['directional'], 'cap'], ['point', ['point'], 'cap'], ['spot', ['spot'], 'cap'],
    ['rect-cap', ['rect'], 'cap'], ['rect-center', ['rect'], 'center'], ['hemisphere+ambient', ['hemisphere', 'ambient'], 'cap']];
  const gl = renderer.getContext(), px = new Uint8Array(4);
  renderer.setRenderTarget(null);
  const configure = (set, enabled) => {
    meshes.forEach((o, i) => { o.material = set === 'absent' ? absent[i] : sets[set][i]; });
    if (set !== 'absent') for (const h of handles[set]) h.enabled = enabled;
  };
  const time = () => {
    renderer.render(scene, camera); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    const t0 = performance.now();
    for (let i = 0; i < frames; ++i) { renderer.render(scene, camera); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px); }
    return (performance.now() - t0) / frames;
  };
  const median = (a) => { const b = [...a].sort((x, y) => x - y), k = b.length >> 1; return b.length % 2 ? b[k] : (b[k - 1] + b[k]) / 2; };
  const table = [];
  for (const [name, on, set] of types) {
    for (const [k, L] of Object.entries(lights)) L.visible = on.includes(k);
    const cfgs = [['on', set, true], ['off', set, false], ['absent', 'absent', true]];
    const compile0 = performance.now();
    for (const [, s, e] of cfgs) { configure(s, e); time(); }   // compile and warm up
    const compile_ms = performance.now() - compile0;
    const t = { on: [], off: [], absent: [] };
    for (let r = 0; r < rounds; ++r)
      for (const [k, s, e] of (r % 2 ? [...cfgs].reverse() : cfgs)) { configure(s, e); t[k].push(time()); }
    // Ratios within each round (the three configurations close in time), then their median.
    const m = { on: median(t.on), off: median(t.off), absent: median(t.absent) };
    const ratio = (a, b) => median(t[a].map((x, r) => x / t[b][r]));
    table.push({ light: name, ms: m, on_absent: ratio('on', 'absent'), off_absent: ratio('off', 'absent'), on_off: ratio('on', 'off'), rounds: t, compile_ms });
  }
  for (const L of Object.values(lights)) L.visible = true;
  scene.remove(lights.hemisphere);
  meshes.forEach((o, i) => { o.material = S.mats[i]; });
  return { method, width: S.width, height: S.height, rounds, frames, table, error: gl.getError() };
}

window.mshProbe = { setup, run, shaded, aoSwitch, area, timing, points: () => S.points };

window.mshProbeLoaded = true;
