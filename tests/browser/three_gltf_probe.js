// In-page part of the glTF check of tests/test_three_directional_browser.cpp (three_directional_test.mjs
// --gltf): loads a `gen-material --gltf` asset with three's GLTFLoader and the module's MicroShadowGLTFPlugin
// (the MSH_materials_directional_occlusion extension, docs/gltf.md), renders its plane under a point, a spot
// and a directional light and reads back, per probe pixel, the module's debug outputs: both lobes' terms
// (float32, 8-bit), the inputs, l, v and the normal in the channels' frame, the channels and coefficients as
// the shader decoded them, the UV, the frame, the position; then the channels fetched nearest (level 0), and
// each light's direct light with the method on and off.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import * as MSH from 'microshadow-three';
import { probeRenderer, renderTargets, probePoints, readProbes, viewPosition, viewDirection } from './msh-test/probe_common.js';

const LIGHT_ORDER = ['point', 'spot', 'directional'];

async function run({ width, height, grid, url }) {
  try {
    const renderer = probeRenderer(width, height);
    renderer.domElement.style.cssText = 'position: fixed; left: 0; top: 0; z-index: 10';  // above the example's panel (screenshots)
    // The documented lines (docs/three.md, "glTF"), with the debug outputs on for the read-backs.
    const loader = new GLTFLoader().register((parser) => new MSH.MicroShadowGLTFPlugin(parser, { debug: true }));
    const gltf = await loader.loadAsync(url);
    const scene = new THREE.Scene();
    gltf.scene.scale.setScalar(4);  // the 1 m plane as 4 m
    scene.add(gltf.scene);
    const meshes = [];
    gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
    const handles = meshes.map((m) => m.material.userData.microshadow).filter((h) => h);
    if (handles.length !== meshes.length) return { error: `${meshes.length - handles.length} of ${meshes.length} meshes got no micro-shadowing` };
    const point = new THREE.PointLight(0xffffff, 8, 0, 2);
    point.position.set(-1.5, 1.2, 1.0);
    const spot = new THREE.SpotLight(0xffffff, 20, 0, THREE.MathUtils.degToRad(45), 0.2, 2);
    spot.position.set(1.8, 2.2, 1.5);
    spot.target.position.set(0.3, 0, -0.2);
    const dir = new THREE.DirectionalLight(0xffffff, 2);
    const el = THREE.MathUtils.degToRad(25), az = THREE.MathUtils.degToRad(-40);
    dir.position.set(Math.cos(el) * Math.sin(az), Math.sin(el), Math.cos(el) * Math.cos(az)).multiplyScalar(10);
    scene.add(point, spot, spot.target, dir, dir.target, new THREE.AmbientLight(0xffffff, 0.4));
    const camera = new THREE.PerspectiveCamera(45, width / height, 0.1, 50);
    camera.position.set(0.4, 2.6, 3.4);
    camera.lookAt(0, 0, -0.3);
    scene.updateMatrixWorld(true);
    camera.updateMatrixWorld(true);
    const points = probePoints(width, height, grid);
    const P = { renderer, scene, camera, ...renderTargets(width, height), width, height, points };
    let hs = handles;
    const read = (mode, k, float, enabled = true) => readProbes(P, hs, mode, k, float, enabled);
    const code = handles[0].directional;
    const out = { method: handles[0].method, points, light_order: LIGHT_ORDER, revision: THREE.REVISION,
      code: { form: code.form, K: code.K, textures: code.textures, identity: code.identity },
      camera_world: camera.matrixWorld.toArray(), scale: 4,
      lights: { point: { position: viewPosition(point, camera) }, spot: { position: viewPosition(spot, camera) },
        directional: { direction: viewDirection(dir, camera) } },
      aomap: !!meshes[0].material.aoMap, normalmap: !!meshes[0].material.normalMap, tangents: !!meshes[0].geometry.attributes.tangent,
      map_color_space: meshes[0].material.map ? meshes[0].material.map.colorSpace : null };
    out.terms_d = read('terms_diffuse', -1, true);
    out.terms_s = read('terms_specular', -1, true);
    out.terms8_d = read('terms_diffuse', -1, false);
    out.terms8_s = read('terms_specular', -1, false);
    out.c = [0, 1, 2, 3, 4, 5].map((k) => read(`dir_c${k}`, 0, true));
    out.a = Array.from({ length: code.textures }, (_, t) => read(`dir_a${t}`, 0, true));
    for (const m of ['dir_n', 'dir_uv', 'dir_x', 'dir_y', 'dir_z', 'position']) out[m] = read(m, 0, true);
    out.lights_read = LIGHT_ORDER.map((_, k) => ({ inputs: read('inputs', k, true), l_t: read('dir_l', k, true), v_t: read('dir_v', k, true),
      direct_on: read('direct', k, true), direct_off: read('direct', k, true, false) }));
    // A shaded frame for the screenshot (left on the canvas).
    renderer.setClearColor(0x101014, 1);
    renderer.render(scene, camera);
    // The same code fetched nearest at level 0: the PNG texels as the shader decodes them.
    const near = { ...code, maps: code.maps.map((t) => { const c = t.clone(); c.minFilter = c.magFilter = THREE.NearestFilter; c.generateMipmaps = false; c.needsUpdate = true; return c; }) };
    for (const h of handles) h.dispose();
    hs = meshes.map((m) => MSH.addMicroShadowing(m.material, { method: out.method, directional: near, debug: true }));
    out.nearest = { a: Array.from({ length: code.textures }, (_, t) => read(`dir_a${t}`, 0, true)), dir_uv: read('dir_uv', 0, true), position: read('position', 0, true) };
    out.gl_error = renderer.getContext().getError();
    return out;
  } catch (e) {
    return { error: String(e.message || e) };
  }
}

// Bad input: the error the load throws (one line), or null when it loaded.
async function loadError(url) {
  try {
    await new GLTFLoader().register((parser) => new MSH.MicroShadowGLTFPlugin(parser)).loadAsync(url);
    return null;
  } catch (e) {
    return String(e.message || e);
  }
}

window.mshGltfProbe = { run, loadError };
window.mshGltfProbeLoaded = true;
