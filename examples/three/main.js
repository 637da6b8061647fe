// The three.js example (docs/three.md): the texture set (data/material/, the built-in plaster or any
// gen-material folder) on a plane, a sphere and a cylinder, and a glTF model with an occlusion map
// (data/model.gltf), lit by a moving sun, a point, a spot or a rect-area light, with micro-shadowing from
// microshadow-three. ?probe loads nothing: the browser test builds its own scenes with the same modules.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { RectAreaLightUniformsLib } from 'three/addons/lights/RectAreaLightUniformsLib.js';
import { RectAreaLightHelper } from 'three/addons/helpers/RectAreaLightHelper.js';
import { addMicroShadowing, loadMicroShadowingLut, MICRO_SHADOWING_METHODS, DEFAULT_METHOD } from 'microshadow-three';

const $ = (id) => document.getElementById(id);
function showError(msg) {
  const b = $('banner');
  b.hidden = false;
  b.textContent = (b.textContent ? `${b.textContent}\n` : '') + msg;
  console.error(msg);
}

async function loadTexture(url, srgb) {
  const t = await new THREE.TextureLoader().loadAsync(url);
  t.flipY = false;  // row j of the PNG = v: the texture set's convention (normal map y = +v)
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.colorSpace = srgb ? THREE.SRGBColorSpace : THREE.NoColorSpace;
  t.anisotropy = 8;
  return t;
}

// The manifest, its tables (loadMicroShadowingLut) and the texture set's maps.
async function loadAssets() {
  const man = await (await fetch('data/manifest.json')).json();
  const luts = {};
  for (const [k, L] of Object.entries(man.luts || {})) luts[k] = await loadMicroShadowingLut(L.url);
  const m = man.material;
  const [base, normal, rough, metal, ao] = await Promise.all([loadTexture(m.base_color, true), loadTexture(m.normal),
    loadTexture(m.roughness), m.metallic ? loadTexture(m.metallic) : null, loadTexture(m.micro_occlusion)]);
  return { material: m, luts, maps: { base, normal, rough, metal, ao } };
}

// The renderer filling the window, the scene, the camera and its orbit controls.
function makeView() {
  const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(window.innerWidth, window.innerHeight);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.toneMapping = THREE.NeutralToneMapping;
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0x202226);
  const camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 0.05, 100);
  camera.position.set(0, 3.2, 7.5);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.set(0, 0.7, 0);
  controls.update();
  return { renderer, scene, camera, controls };
}

// The texture set on a plane, a sphere and a cylinder, one material per object (the textures' repeat
// differs: texel size about equal on every surface), and the glTF model; returns every material.
async function addObjects(scene, { base, normal, rough, metal, ao }) {
  const plasterMaterial = (rx, ry) => {
    const tex = (t) => { if (!t) return null; const c = t.clone(); c.repeat.set(rx, ry); return c; };
    return new THREE.MeshStandardMaterial({ map: tex(base), normalMap: tex(normal), roughnessMap: tex(rough),
      metalnessMap: tex(metal), metalness: metal ? 1 : 0, roughness: 1, aoMap: tex(ao) });
  };
  const objects = [
    new THREE.Mesh(new THREE.PlaneGeometry(6, 6).rotateX(-Math.PI / 2), plasterMaterial(3, 3)),
    new THREE.Mesh(new THREE.SphereGeometry(0.9, 96, 48), plasterMaterial(2, 1)),
    new THREE.Mesh(new THREE.CylinderGeometry(0.7, 0.7, 1.8, 96, 1, true), plasterMaterial(2, 1)),
  ];
  objects[1].position.set(-1.7, 0.9, 0);
  objects[2].position.set(1.7, 0.9, 0);
  for (const o of objects) scene.add(o);
  const gltf = await new GLTFLoader().loadAsync('data/model.gltf');
  const model = gltf.scene;
  model.position.set(0, 0.3, 1.6);
  scene.add(model);
  const materials = objects.map((o) => o.material);
  model.traverse((o) => { if (o.isMesh) materials.push(o.material); });
  return materials;
}

// A weak sky for the indirect light (where three applies AO), and the direct lights (one shown at a time).
function addLights(scene) {
  scene.add(new THREE.HemisphereLight(0xbfd4ff, 0x302820, 0.35));
  const sun = new THREE.DirectionalLight(0xfff1e0, 3.5);
  const point = new THREE.PointLight(0xfff1e0, 12, 0, 2);
  const spot = new THREE.SpotLight(0xfff1e0, 30, 0, Math.PI / 5, 0.3, 2);
  const rect = new THREE.RectAreaLight(0xfff1e0, 6, 2.5, 0.6);
  rect.add(new RectAreaLightHelper(rect));
  for (const l of [sun, point, spot, rect]) scene.add(l);
  scene.add(sun.target, spot.target);
  return { sun, point, spot, rect };
}

// The direct lights placed for the state's elevation and azimuth; only the chosen one visible.
function placeLights({ sun, point, spot, rect }, state) {
  const el = THREE.MathUtils.degToRad(state.elevation), az = THREE.MathUtils.degToRad(state.azimuth);
  const d = new THREE.Vector3(Math.cos(el) * Math.sin(az), Math.sin(el), Math.cos(el) * Math.cos(az));
  sun.position.copy(d).multiplyScalar(10);
  point.position.copy(d).multiplyScalar(3.5).add(new THREE.Vector3(0, 0.3, 0));
  spot.position.copy(d).multiplyScalar(5);
  spot.target.position.set(0, 0.5, 0);
  rect.position.copy(d).multiplyScalar(3.5).add(new THREE.Vector3(0, 0.3, 0));
  rect.lookAt(0, 0.5, 0);
  for (const [k, l] of Object.entries({ sun, point, spot, rect })) l.visible = state.light === k;
}

async function main() {
  RectAreaLightUniformsLib.init();
  const { material: m, luts, maps } = await loadAssets();
  const { renderer, scene, camera, controls } = makeView();
  const materials = await addObjects(scene, maps);
  const lights = addLights(scene);

  const state = { attached: true, method: DEFAULT_METHOD, enabled: true, ao_indirect: true, light: 'sun', elevation: 12, animate: true,
    azimuth: 40, split: false, panel: true, camera: null, target: null };
  // directional-view (texel) reads a texture set's channel mips (loadDirectionalOcclusion); the example serves
  // the texture set without them, so its menu leaves it out (tests/browser/three_directional_probe.js uses it).
  const available = MICRO_SHADOWING_METHODS.filter((e) => !e.texel && [].concat(e.lut || []).every((k) => luts[k]));
  $('method').innerHTML = available.map((e) => `<option value="${e.id}">${e.label}</option>`).join('');
  let handles = [];
  const apply = () => {
    for (const h of handles) h.dispose();
    handles = state.attached ? materials.map((mat) => addMicroShadowing(mat, { method: state.method, luts, aoOnIndirect: state.ao_indirect })) : [];
    for (const h of handles) h.enabled = state.enabled;
  };
  const render = () => {
    placeLights(lights, state);
    const w = renderer.domElement.width, h = renderer.domElement.height;
    if (!state.split) {
      for (const x of handles) x.enabled = state.enabled;
      renderer.setScissorTest(false);
      renderer.render(scene, camera);
      return;
    }
    // Left: without micro-shadowing, right: with (the same frame).
    renderer.setScissorTest(true);
    for (const [x0, on] of [[0, false], [w / 2, true]]) {
      for (const x of handles) x.enabled = on;
      renderer.setScissor(x0, 0, w / 2, h);
      renderer.render(scene, camera);
    }
    renderer.setScissorTest(false);
  };
  const set = (s) => {
    const recompile = ['method', 'ao_indirect', 'attached'].some((k) => k in s && s[k] !== state[k]);
    Object.assign(state, s);
    if (recompile) apply();
    for (const k of ['method', 'enabled', 'ao_indirect', 'light', 'elevation', 'animate']) {
      const e = $(k);
      if (e.type === 'checkbox') e.checked = !!state[k]; else e.value = String(state[k]);
    }
    $('split_on').checked = state.split;
    $('split').hidden = !state.split;
    $('split_right').textContent = `with micro-shadowing (${(available.find((e) => e.id === state.method) || { label: state.method }).label})`;
    $('panel').hidden = !state.panel;
    $('elevation_out').textContent = String(state.elevation);
    if (s.camera) camera.position.fromArray(s.camera);
    if (s.target) controls.target.fromArray(s.target);
    if (s.camera || s.target) controls.update();
  };
  apply();
  set({});
  $('info').textContent = `${m.name}; tables: ${Object.keys(luts).join(', ') || 'none'}; three r${THREE.REVISION}`;
  $('panel').addEventListener('input', () => set({ method: $('method').value, enabled: $('enabled').checked,
    ao_indirect: $('ao_indirect').checked, light: $('light').value, elevation: Number($('elevation').value), animate: $('animate').checked,
    split: $('split_on').checked }));
  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });
  let last = performance.now();
  renderer.setAnimationLoop((now) => {
    if (state.animate) state.azimuth = (state.azimuth + (now - last) * 0.012) % 360;
    last = now;
    render();
  });

  // For scripts (the browser test's screenshots and frame time, the docs figure): set the state, resize,
  // render once synchronously; attached: false removes micro-shadowing (the materials as three has them).
  window.mshExample = {
    THREE, renderer, scene, camera, controls, materials, state, handles: () => handles,
    set, render() { render(); renderer.getContext().finish(); return renderer.getContext().getError(); },
    // Mean milliseconds per frame over n frames, each ended by a 1-pixel readback (the GPU work included).
    time(n) {
      const gl = renderer.getContext(), px = new Uint8Array(4);
      render(); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
      const t0 = performance.now();
      for (let i = 0; i < n; ++i) { render(); gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px); }
      return (performance.now() - t0) / n;
    },
    resize(w, h) { renderer.setAnimationLoop(null); renderer.setSize(w, h, false); camera.aspect = w / h; camera.updateProjectionMatrix(); },
  };
}

if (new URLSearchParams(location.search).has('probe')) {
  window.mshExampleReady = true;
} else {
  main().then(() => { window.mshExampleReady = true; }).catch((e) => { showError(`error: ${e.message}`); window.mshExampleReady = false; });
}
