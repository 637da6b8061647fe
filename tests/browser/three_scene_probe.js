// In-page part of the glTF-scene check of tests/test_three_browser.cpp (three_test.mjs --scene-snippet): builds a
// glTF asset in the page — one mesh used by two nodes (its material shared, with an occlusion texture), a
// material without occlusion, a KHR_materials_unlit one (three's MeshBasicMaterial) and a
// KHR_materials_clearcoat one with occlusion (MeshPhysicalMaterial), one quad per node in a row — and renders
// it as GLTFLoader makes it (no micro-shadowing) into a float32 target. The test then runs docs/three.md's
// glTF block (a module it writes: `scene` and the model's URL from here) and calls check(): the report, a
// second call, a call with other options, and the same render with the patched model, region by region.
// api() checks addMicroShadowing's idempotency, dispose(), arrays of materials and the roll-back on fresh
// materials. Facts go back to the C++ test, which asserts them.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import * as MSH from 'microshadow-three';

const W = 260, H = 65;                                    // the camera's 5.2 x 1.3 view at 50 px per unit
const NODES = [['shared_a', 0, -2], ['shared_b', 0, -1], ['plain', 1, 0], ['unlit', 2, 1], ['clearcoat', 3, 2]];  // name, mesh, x
const HALF = 0.4;                                         // the quads' half size

// A 4 x 4 grey PNG (the occlusion texture: V = 128/255).
function greyPng(v) {
  const c = document.createElement('canvas');
  c.width = c.height = 4;
  const g = c.getContext('2d');
  g.fillStyle = `rgb(${v}, ${v}, ${v})`;
  g.fillRect(0, 0, 4, 4);
  return c.toDataURL('image/png');
}

function gltfAsset() {
  const pos = [-HALF, -HALF, 0, HALF, -HALF, 0, HALF, HALF, 0, -HALF, HALF, 0];
  const nrm = [0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1];
  const uv = [0, 1, 1, 1, 1, 0, 0, 0];
  const idx = [0, 1, 2, 0, 2, 3];
  const bytes = new Uint8Array(48 + 48 + 32 + 12);
  new Float32Array(bytes.buffer, 0, 12).set(pos);
  new Float32Array(bytes.buffer, 48, 12).set(nrm);
  new Float32Array(bytes.buffer, 96, 8).set(uv);
  new Uint16Array(bytes.buffer, 128, 6).set(idx);
  const pbr = (rgb) => ({ baseColorFactor: [...rgb, 1], metallicFactor: 0, roughnessFactor: 0.6 });
  return {
    asset: { version: '2.0' },
    extensionsUsed: ['KHR_materials_unlit', 'KHR_materials_clearcoat'],
    scene: 0,
    scenes: [{ nodes: NODES.map((_, i) => i) }],
    nodes: NODES.map(([name, mesh, x]) => ({ name, mesh, translation: [x, 0, 0] })),
    meshes: [0, 1, 2, 3].map((m) => ({ primitives: [{ attributes: { POSITION: 0, NORMAL: 1, TEXCOORD_0: 2 }, indices: 3, material: m }] })),
    materials: [
      { name: 'shared', pbrMetallicRoughness: pbr([0.8, 0.8, 0.8]), occlusionTexture: { index: 0 } },
      { name: 'no_occlusion', pbrMetallicRoughness: pbr([0.8, 0.8, 0.8]) },
      { name: 'unlit', pbrMetallicRoughness: pbr([0.8, 0.5, 0.3]), extensions: { KHR_materials_unlit: {} } },
      { name: 'clearcoat', pbrMetallicRoughness: pbr([0.3, 0.5, 0.8]), occlusionTexture: { index: 0 },
        extensions: { KHR_materials_clearcoat: { clearcoatFactor: 0.8, clearcoatRoughnessFactor: 0.2 } } },
    ],
    textures: [{ source: 0, sampler: 0 }],
    images: [{ uri: greyPng(128) }],
    samplers: [{ magFilter: 9728, minFilter: 9728 }],
    buffers: [{ byteLength: bytes.length, uri: `data:application/octet-stream;base64,${btoa(String.fromCharCode(...bytes))}` }],
    bufferViews: [{ buffer: 0, byteOffset: 0, byteLength: 48 }, { buffer: 0, byteOffset: 48, byteLength: 48 },
      { buffer: 0, byteOffset: 96, byteLength: 32 }, { buffer: 0, byteOffset: 128, byteLength: 12 }],
    accessors: [
      { bufferView: 0, componentType: 5126, count: 4, type: 'VEC3', min: [-HALF, -HALF, 0], max: [HALF, HALF, 0] },
      { bufferView: 1, componentType: 5126, count: 4, type: 'VEC3' },
      { bufferView: 2, componentType: 5126, count: 4, type: 'VEC2' },
      { bufferView: 3, componentType: 5123, count: 6, type: 'SCALAR' },
    ],
  };
}

let S = null;

// The renderer, the lit scene (a directional light at N·L ≈ 0.39 and an ambient light), the model's URL and
// the model rendered as GLTFLoader makes it.
async function setup() {
  const renderer = new THREE.WebGLRenderer({ antialias: false });
  renderer.setPixelRatio(1);
  renderer.setSize(W, H);
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const sun = new THREE.DirectionalLight(0xffffff, 3);
  sun.position.set(1, 0.35, 0.45).multiplyScalar(10);
  scene.add(sun, sun.target, new THREE.AmbientLight(0xffffff, 0.3));
  const camera = new THREE.OrthographicCamera(-2.6, 2.6, 0.65, -0.65, 0.1, 10);
  camera.position.set(0, 0, 3);
  camera.lookAt(0, 0, 0);
  camera.updateMatrixWorld(true);
  const rt = new THREE.WebGLRenderTarget(W, H, { type: THREE.FloatType, minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter });
  const url = URL.createObjectURL(new Blob([JSON.stringify(gltfAsset())], { type: 'model/gltf+json' }));
  S = { renderer, scene, camera, rt, url };
  const base = await new GLTFLoader().loadAsync(url);
  scene.add(base.scene);
  S.before = render();
  scene.remove(base.scene);
  return { width: W, height: H, nodes: NODES.map((n) => n[0]) };
}

// One render of the scene into the float target: each node's quad (its projected square, 1 px inset) as rows of
// floats, and its centre pixel.
function render() {
  const { renderer, scene, camera, rt } = S;
  renderer.setRenderTarget(rt);
  renderer.setClearColor(0x000000, 0);
  renderer.clear();
  renderer.render(scene, camera);
  const buf = new Float32Array(W * H * 4);
  renderer.readRenderTargetPixels(rt, 0, 0, W, H, buf);
  renderer.setRenderTarget(null);
  const px = (x, y) => Array.from(buf.subarray(4 * (y * W + x), 4 * (y * W + x) + 3));
  const out = { gl_error: renderer.getContext().getError(), nodes: {} };
  for (const [name, , x] of NODES) {
    const to = (wx, wy) => { const p = new THREE.Vector3(wx, wy, 0).project(camera); return [(p.x + 1) / 2 * W, (p.y + 1) / 2 * H]; };
    const [x0, y0] = to(x - HALF, -HALF), [x1, y1] = to(x + HALF, HALF), [cx, cy] = to(x, 0);
    const region = [];
    for (let j = Math.ceil(y0) + 1; j < Math.floor(y1) - 1; ++j)
      for (let i = Math.ceil(x0) + 1; i < Math.floor(x1) - 1; ++i) region.push(px(i, j));
    out.nodes[name] = { centre: px(Math.floor(cx), Math.floor(cy)), region };
  }
  return out;
}

// Each node's quad before and after: pixels compared, the largest channel difference, the centre pixels.
function compare(before, after) {
  const out = {};
  for (const name of Object.keys(before.nodes)) {
    const a = before.nodes[name], b = after.nodes[name];
    let differing = 0, maxDiff = 0, darker = 0;
    a.region.forEach((p, k) => {
      const d = Math.max(...p.map((v, c) => Math.abs(v - b.region[k][c])));
      if (d > 0) ++differing;
      if (b.region[k][0] + b.region[k][1] + b.region[k][2] < p[0] + p[1] + p[2]) ++darker;
      maxDiff = Math.max(maxDiff, d);
    });
    out[name] = { pixels: a.region.length, differing, darker, max_diff: maxDiff, centre_before: a.centre, centre_after: b.centre };
  }
  return out;
}

const describe = (list) => list.map((e) => ({ name: e.material.name, type: e.material.type, ...(e.code ? { code: e.code, reason: e.reason } : {}) }));
const errorOf = (f) => { try { f(); return null; } catch (e) { return String(e.message || e); } };

// After docs/three.md's block ran on its own copy of the model: the report, a second call, a call with other
// options, addMicroShadowing on a patched material, the render.
function check(gltf, report, options) {
  try {
    const meshes = {};
    gltf.scene.traverse((o) => { if (o.isMesh) meshes[o.name] = o; });
    const mats = [...new Set(Object.values(meshes).map((m) => m.material))];
    const state = () => mats.map((m) => ({ version: m.version, hook: m.onBeforeCompile }));
    const out = {
      asset: { meshes: Object.keys(meshes), materials: mats.length,
        shared: meshes.shared_a && meshes.shared_b && meshes.shared_a.material === meshes.shared_b.material,
        types: Object.fromEntries(Object.entries(meshes).map(([n, m]) => [n, m.material.type])),
        aomap: Object.fromEntries(Object.entries(meshes).map(([n, m]) => [n, !!m.material.aoMap])),
        clearcoat: meshes.clearcoat ? meshes.clearcoat.material.clearcoat : null },
      patched: describe(report.patched),
      skipped: describe(report.skipped),
      handles: new Set(report.patched.map((p) => p.handle)).size,
    };
    // The same call again: the same handles, nothing patched twice (no new hook, no recompilation).
    const before = state();
    const again = MSH.addMicroShadowingToScene(gltf.scene, options);
    const after = state();
    out.again = { patched: describe(again.patched), skipped: describe(again.skipped),
      same_handles: again.patched.length === report.patched.length && again.patched.every((p, i) => p.handle === report.patched[i].handle && p.material === report.patched[i].material),
      unchanged: before.every((s, i) => s.version === after[i].version && s.hook === after[i].hook) };
    // Other options: every patched material is a conflict, nothing changes.
    const other = MSH.addMicroShadowingToScene(gltf.scene, { ...options, method: 'chan-2018' });
    const after2 = state();
    out.other = { patched: describe(other.patched), skipped: describe(other.skipped),
      unchanged: before.every((s, i) => s.version === after2[i].version && s.hook === after2[i].hook) };
    // addMicroShadowing on the shared material: the same handle with the same options, one line naming the
    // option otherwise.
    const shared = meshes.shared_a.material, h = report.patched.find((p) => p.material === shared)?.handle;
    out.single = { same: MSH.addMicroShadowing(shared, options) === h && MSH.addMicroShadowing(shared, { ...options, method: MSH.DEFAULT_METHOD }) === h,
      other_error: errorOf(() => MSH.addMicroShadowing(shared, { ...options, aoOnIndirect: false })) };
    // The patched model rendered as the unpatched one was.
    S.scene.updateMatrixWorld(true);
    const rendered = render();
    out.gl_error = rendered.gl_error;
    out.regions = compare(S.before, rendered);
    out.keys = Object.fromEntries(Object.entries(meshes).map(([n, m]) => [n, m.material.customProgramCacheKey()]));
    out.programs = S.renderer.info.programs.length;
    return out;
  } catch (e) {
    return { error: String(e.message || e) };
  }
}

// addMicroShadowing and addMicroShadowingToScene on fresh materials: named checks, each { ok, detail }.
function api() {
  const checks = {};
  const run = (name, f) => { try { const d = f(); checks[name] = { ok: d === true, detail: d === true ? '' : String(d) }; } catch (e) { checks[name] = { ok: false, detail: `threw: ${e.message}` }; } };
  const ao = new THREE.DataTexture(new Uint8Array([128, 128, 128, 255]), 1, 1);
  const std = (name) => Object.assign(new THREE.MeshStandardMaterial({ aoMap: ao }), { name });
  const proto = THREE.MeshStandardMaterial.prototype;
  const geo = new THREE.PlaneGeometry(1, 1);

  run('same options: the same handle', () => {
    const m = std('a'), h = MSH.addMicroShadowing(m);
    return (MSH.addMicroShadowing(m) === h && MSH.addMicroShadowing(m, { method: MSH.DEFAULT_METHOD, visibility: 'aoMap', aoOnIndirect: true, samples: 32 }) === h) || 'another handle';
  });
  run('other options: one line naming the option and dispose()', () => {
    const m = std('b'), h = MSH.addMicroShadowing(m, { visibility: 0.5 });
    const msg = errorOf(() => MSH.addMicroShadowing(m, { visibility: 0.6 }));
    const ok = msg && msg.includes("'visibility'") && msg.includes('dispose()') && !msg.includes('\n');
    h.dispose();
    return ok || `message: ${msg}`;
  });
  run('dispose: the material back, patched again with a new handle; a stale dispose does nothing', () => {
    const m = std('c'), h1 = MSH.addMicroShadowing(m);
    h1.dispose();
    if (m.onBeforeCompile !== proto.onBeforeCompile || m.customProgramCacheKey !== proto.customProgramCacheKey) return 'not restored';
    const h2 = MSH.addMicroShadowing(m, { aoOnIndirect: false });
    if (h2 === h1) return 'the disposed handle came back';
    const hook = m.onBeforeCompile;
    h1.dispose();
    if (m.onBeforeCompile !== hook || MSH.addMicroShadowing(m, { aoOnIndirect: false }) !== h2) return 'the stale dispose undid the new patch';
    h2.dispose();
    h2.dispose();
    return m.onBeforeCompile === proto.onBeforeCompile || 'not restored after the second patch';
  });
  run('dispose, a render without, the same options again: the module renders again (its uniforms bound)', () => {
    // three keeps a material's programs by cache key and binds the uniforms of the last program it compiled:
    // re-patched with the key of a program compiled before dispose(), the module's uniforms were unbound.
    const m = std('again'), scene = new THREE.Scene(), sun = new THREE.DirectionalLight(0xffffff, 3);
    sun.position.set(0.3, 0.15, 1);  // N·L 0.95: inside the visibility cone of V = 0.5, partly shadowed
    scene.add(new THREE.Mesh(geo, m), sun, sun.target);
    const camera = new THREE.OrthographicCamera(-0.5, 0.5, 0.5, -0.5, 0.1, 10);
    camera.position.set(0, 0, 3);
    camera.lookAt(0, 0, 0);
    const rt = new THREE.WebGLRenderTarget(4, 4, { type: THREE.FloatType });
    const centre = () => {
      S.renderer.setRenderTarget(rt);
      S.renderer.render(scene, camera);
      const buf = new Float32Array(4 * 4 * 4);
      S.renderer.readRenderTargetPixels(rt, 0, 0, 4, 4, buf);
      S.renderer.setRenderTarget(null);
      return buf[4 * (2 * 4 + 2)];
    };
    // A uniform changed after the new patch (the visibility constant, through handle.uniforms) must reach the
    // program: unbound, it kept its earlier value.
    const h1 = MSH.addMicroShadowing(m, { visibility: 0.5 }), on = centre();
    h1.dispose();
    const off = centre();
    const h2 = MSH.addMicroShadowing(m, { visibility: 0.5 }), again = centre();
    h2.uniforms.msh_visibility.value = 1;
    const open = centre();
    h2.dispose();
    rt.dispose();
    const ok = on > 0.01 && on < off - 0.01 && Math.abs(again - on) <= 1e-6 && open > on + 0.01;
    return ok || JSON.stringify({ on, off, again, open });
  });
  run('arrays of materials and shared materials: each material once', () => {
    const a = std('array_a'), basic = new THREE.MeshBasicMaterial({ name: 'array_basic' });
    const g = new THREE.Group();
    g.add(new THREE.Mesh(geo, [a, basic]), new THREE.Mesh(geo, a), new THREE.Mesh(geo, [basic, a]));
    const r = MSH.addMicroShadowingToScene(g);
    const ok = r.patched.length === 1 && r.patched[0].material === a && r.skipped.length === 1 && r.skipped[0].code === 'unsupported';
    r.patched[0]?.handle.dispose();
    return ok || JSON.stringify({ patched: describe(r.patched), skipped: describe(r.skipped) });
  });
  run('a bad option throws before any material changes', () => {
    const a = std('bad_a'), g = new THREE.Group();
    g.add(new THREE.Mesh(geo, a), new THREE.Mesh(geo, new THREE.MeshBasicMaterial()));
    const msg = errorOf(() => MSH.addMicroShadowingToScene(g, { method: 'no-such-method' }));
    return (msg && msg.includes('unknown method') && a.onBeforeCompile === proto.onBeforeCompile && a.version === 0) || `message ${msg}, version ${a.version}`;
  });
  run('a patch that fails: the ones done rolled back, the error thrown', () => {
    const a = std('roll_a'), frozen = std('roll_frozen');
    Object.defineProperty(frozen, 'onBeforeCompile', { value: proto.onBeforeCompile, writable: false });
    const g = new THREE.Group();
    g.add(new THREE.Mesh(geo, a), new THREE.Mesh(geo, frozen));
    const msg = errorOf(() => MSH.addMicroShadowingToScene(g));
    if (!msg || !msg.includes('onBeforeCompile')) return `not the frozen material's error: ${msg}`;
    if (a.version < 2) return 'the first material was never patched (patched and restored: two updates)';
    if (a.onBeforeCompile !== proto.onBeforeCompile || a.customProgramCacheKey !== proto.customProgramCacheKey) return 'the first material was left patched';
    const h = MSH.addMicroShadowing(a, { aoOnIndirect: false });  // no conflict: the roll-back released it
    h.dispose();
    return true;
  });
  return checks;
}

window.mshScene = { setup, check, api, get scene() { return S.scene; }, get url() { return S.url; } };
window.mshSceneLoaded = true;
