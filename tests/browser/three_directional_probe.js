// In-page part of the three.js directional-view test (tests/browser/three_directional_test.mjs injects it into
// the example page opened with ?probe; tests/test_three_directional_browser.cpp compares with the C++
// library). A known scene with a gen-material texture set's directional channels (mips/mips.json through
// loadDirectionalOcclusion, KTX2 with mips): a plane (three's computeTangents: bitangent along +v), a sphere
// (tangents with w negated, the glTF/MikkTSpace sign: bitangent along −v, normalScale.y = −1 to keep the normal
// map right) and a cylinder without normal map or tangents, its u mirrored (the UV derivative frame, left-handed),
// lit by a point, a spot,
// a directional and a rect-area light. Per run it renders the module's debug outputs into float32 and 8-bit
// targets and reads back the probe pixels: both lobes' terms, the light, view and normal in the channels'
// frame, the 21 channels and the K coefficients as the shader decoded them, the UV, the frame's axes,
// position and normal; with { direct } each light's direct light with micro-shadowing on and off.
import * as THREE from 'three';
import { RectAreaLightUniformsLib } from 'three/addons/lights/RectAreaLightUniformsLib.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';
import * as MSH from 'microshadow-three';
import { probeRenderer, renderTargets, probePoints, readProbes, renderShaded, probeScene } from './msh-test/probe_common.js';

const LIGHT_ORDER = ['point', 'spot', 'directional', 'rect'];
const ROUGH = [0.45, 0.6, 0.8];
let S = null;

async function ktx2(url, renderer) {
  const l = new KTX2Loader().detectSupport(renderer);
  try {
    const t = await l.loadAsync(url);
    t.colorSpace = THREE.NoColorSpace;
    t.wrapS = t.wrapT = THREE.RepeatWrapping;
    t.minFilter = THREE.LinearMipmapLinearFilter;
    t.magFilter = THREE.LinearFilter;
    t.unpackAlignment = 1;
    t.needsUpdate = true;
    return t;
  } finally { l.dispose(); }
}

// The same code with its textures sampled nearest at level 0 (the channels of one texel of the file).
function nearest(code) {
  const maps = code.maps.map((t) => { const c = t.clone(); c.minFilter = c.magFilter = THREE.NearestFilter; c.needsUpdate = true; return c; });
  return { ...code, maps };
}

async function errorOf(f) {
  try { await f(); return null; } catch (e) { return String(e.message || e); }
}

async function setup({ width, height, grid, material, compact, bad }) {
  RectAreaLightUniformsLib.init();
  const renderer = probeRenderer(width, height);
  renderer.domElement.style.cssText = 'position: fixed; left: 0; top: 0; z-index: 10';  // above the example's panel (screenshots)
  const dir21 = await MSH.loadDirectionalOcclusion(`${material}/mips/mips.json`, { renderer, prefer: 'directional' });
  const dirCompact = compact ? await MSH.loadDirectionalOcclusion(`${compact}/mips/mips.json`, { renderer }) : null;
  const normal = await ktx2(`${material}/mips/normal.ktx2`, renderer);
  const ao = await ktx2(`${material}/mips/micro_occlusion.ktx2`, renderer);
  const mats = ROUGH.map((r) => new THREE.MeshStandardMaterial({ color: 0xcccccc, roughness: r, metalness: 0 }));
  mats[0].normalMap = normal;
  mats[1].normalMap = normal;
  mats[1].normalScale.set(1, -1);
  for (const m of mats) m.aoMap = ao;
  const plane = new THREE.PlaneGeometry(5, 5).rotateX(-Math.PI / 2);
  const uv = plane.attributes.uv;
  for (let i = 0; i < uv.count; ++i) uv.setXY(i, 3 * uv.getX(i), 3 * uv.getY(i));  // 3 repeats: the mips are used
  plane.computeTangents();
  const sphere = new THREE.SphereGeometry(0.8, 64, 32);
  sphere.computeTangents();
  const tan = sphere.attributes.tangent;
  for (let i = 0; i < tan.count; ++i) tan.setW(i, -tan.getW(i));
  const cylinder = new THREE.CylinderGeometry(0.6, 0.6, 1.6, 64, 1, true);
  const cuv = cylinder.attributes.uv;  // mirrored in u: +v is then −cross(normal, +u), the frame's sign must follow
  for (let i = 0; i < cuv.count; ++i) cuv.setX(i, 1 - cuv.getX(i));
  const { scene, camera, objs, lights } = probeScene(width, height, [plane, sphere, cylinder], mats);
  S = { renderer, scene, camera, mats, width, height, ...renderTargets(width, height), handles: [],
    codes: { channels21: dir21, compact: dirCompact, channels21_nearest: nearest(dir21), compact_nearest: dirCompact ? nearest(dirCompact) : null },
    points: probePoints(width, height, grid) };
  // Bad input: each must throw one clear line (the C++ test checks the messages).
  const errors = {};
  for (const [k, url] of Object.entries(bad || {}))
    errors[k] = await errorOf(() => MSH.loadDirectionalOcclusion(url, { renderer }));
  errors.no_directional = await errorOf(async () => MSH.addMicroShadowing(new THREE.MeshStandardMaterial(), { method: 'directional-view' }));
  errors.wrong_k = await errorOf(async () => MSH.directionalOcclusion({ K: 9, lo: dir21.lo.slice(0, 9), hi: dir21.hi.slice(0, 9),
    basis: Array.from({ length: 21 }, () => new Array(9).fill(0)), textures: dir21.maps.slice(0, 2) }, 'fixture'));
  errors.no_renderer = await errorOf(() => MSH.loadDirectionalOcclusion(`${material}/mips/mips.json`));
  const codeInfo = (c) => c && { form: c.form, K: c.K, textures: c.textures, identity: c.identity, lo: c.lo, hi: c.hi, mean: c.mean, basis: c.basis,
    maps: c.maps.map((t) => ({ width: t.image.width, height: t.image.height, levels: t.mipmaps.length, format: t.format })) };
  const methods = MSH.MICRO_SHADOWING_METHODS.filter((m) => m.texel).map((m) => ({ id: m.id, lobes: MSH.methodLobes(m.id) }));
  return { lights, light_order: LIGHT_ORDER, methods, roughness: ROUGH, errors_by_case: errors, revision: THREE.REVISION,
    camera_world: camera.matrixWorld.toArray(), objects: { sphere: objs[1].position.toArray(), sphere_radius: 0.8,
      cylinder: objs[2].position.toArray(), cylinder_radius: 0.6, cylinder_half_height: 0.8, plane_half: 2.5 },
    codes: { channels21: codeInfo(dir21), compact: codeInfo(dirCompact) } };
}

function attach(method, code) {
  for (const h of S.handles) h.dispose();
  S.handles = S.mats.map((m) => MSH.addMicroShadowing(m, { method, directional: S.codes[code], debug: true }));
}

function read(mode, k, float, enabled = true) { return readProbes(S, S.handles, mode, k, float, enabled); }

// One method with one code: the terms of the four lights (float, 8-bit); per light: the inputs, l_t, view_t;
// once: n_t, the channels, the coefficients, uv, the frame, position, normal; with o.direct the direct light
// on and off.
function run(method, code, o = {}) {
  const t0 = performance.now();
  attach(method, code);
  const gl = S.renderer.getContext();
  const out = { method, code, terms_d: read('terms_diffuse', -1, true), terms_s: read('terms_specular', -1, true),
    terms8_d: read('terms_diffuse', -1, false), terms8_s: read('terms_specular', -1, false) };
  out.c = [0, 1, 2, 3, 4, 5].map((k) => read(`dir_c${k}`, 0, true));
  out.a = Array.from({ length: S.codes[code].textures }, (_, t) => read(`dir_a${t}`, 0, true));
  for (const m of ['dir_n', 'dir_uv', 'dir_x', 'dir_y', 'dir_z', 'position', 'normal']) out[m] = read(m, 0, true);
  out.lights = LIGHT_ORDER.map((_, k) => {
    const L = { inputs: read('inputs', k, true), l_t: read('dir_l', k, true), v_t: read('dir_v', k, true) };
    if (LIGHT_ORDER[k] === 'rect') L.cap = read('cap', k, true);
    if (o.direct) { L.direct_on = read('direct', k, true); L.direct_off = read('direct', k, true, false); }
    return L;
  });
  out.error = gl.getError();
  out.ms = performance.now() - t0;
  return out;
}

// The channels only (nearest run): c, a and uv.
function channels(method, code) {
  attach(method, code);
  const out = { method, code, c: [0, 1, 2, 3, 4, 5].map((k) => read(`dir_c${k}`, 0, true)),
    a: Array.from({ length: S.codes[code].textures }, (_, t) => read(`dir_a${t}`, 0, true)), dir_uv: read('dir_uv', 0, true), position: read('position', 0, true) };
  out.error = S.renderer.getContext().getError();
  return out;
}

function shaded(method, code, enabled) {
  attach(method, code);
  for (const h of S.handles) { h.setDebug(null); h.enabled = enabled; }
  return renderShaded(S);
}

window.mshDirProbe = { setup, run, channels, shaded, points: () => S.points };
window.mshDirProbeLoaded = true;
