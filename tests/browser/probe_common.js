// The in-page probes' shared parts (three_probe.js, three_directional_probe.js, three_gltf_probe.js, which
// import it as ./msh-test/probe_common.js: the drivers serve it to the page, see probe_page.mjs): the
// renderer, the float32 and 8-bit targets, the grid of probe pixels and their read-back, the lights as three's
// shaders see them, and the scene that three_probe.js and three_directional_probe.js light and view alike.
import * as THREE from 'three';

// A WebGL2 renderer of width x height pixels on the page (its drawing buffer kept for screenshots).
export function probeRenderer(width, height) {
  const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height);
  document.body.appendChild(renderer.domElement);
  return renderer;
}

// The float32 and the 8-bit render targets the probes read back (nearest, with depth).
export function renderTargets(width, height) {
  const rt = (type) => new THREE.WebGLRenderTarget(width, height, { type, depthBuffer: true, minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter });
  return { rtF: rt(THREE.FloatType), rt8: rt(THREE.UnsignedByteType) };
}

// The probe pixels: a grid[0] x grid[1] grid over the frame, rows from the top.
export function probePoints(width, height, grid) {
  const points = [];
  for (let j = 0; j < grid[1]; ++j)
    for (let i = 0; i < grid[0]; ++i) points.push([Math.floor(width * (i + 0.5) / grid[0]), Math.floor(height * (j + 0.5) / grid[1])]);
  return points;
}

// The probe pixels of one render of debug `mode` for light `k` (-1: every light lit) into P's float32 or 8-bit
// target, with the handles' micro-shadowing enabled or not; then debug off and micro-shadowing on again.
// P: { renderer, scene, camera, rtF, rt8, width, height, points }.
export function readProbes(P, handles, mode, k, float, enabled = true) {
  for (const h of handles) { h.setDebug(mode, k); h.enabled = enabled; }
  const rt = float ? P.rtF : P.rt8, { width: w, height: h } = P;
  P.renderer.setRenderTarget(rt);
  P.renderer.setClearColor(0x000000, 0);
  P.renderer.clear();
  P.renderer.render(P.scene, P.camera);
  const buf = float ? new Float32Array(w * h * 4) : new Uint8Array(w * h * 4);
  P.renderer.readRenderTargetPixels(rt, 0, 0, w, h, buf);
  P.renderer.setRenderTarget(null);
  for (const x of handles) { x.setDebug(null); x.enabled = true; }
  return P.points.map(([x, y]) => Array.from(buf.subarray(4 * ((h - 1 - y) * w + x), 4 * ((h - 1 - y) * w + x) + 4)));
}

// A shaded frame of P's scene on the canvas (sRGB output): the GL error after it.
export function renderShaded(P) {
  P.renderer.setRenderTarget(null);
  P.renderer.setClearColor(0x101014, 1);
  P.renderer.render(P.scene, P.camera);
  P.renderer.getContext().finish();
  return P.renderer.getContext().getError();
}

// A light's position and a directional light's direction (towards it) in the camera's view space.
export function viewPosition(light, camera) {
  return new THREE.Vector3().setFromMatrixPosition(light.matrixWorld).applyMatrix4(camera.matrixWorldInverse).toArray();
}
export function viewDirection(light, camera) {
  return new THREE.Vector3().subVectors(light.position, light.target.position).transformDirection(camera.matrixWorldInverse).toArray();
}
// A rect-area light as WebGLLights sets its uniforms: its centre and half axes in view space.
export function viewRect(rect, camera) {
  const rot = new THREE.Matrix4().extractRotation(new THREE.Matrix4().multiplyMatrices(camera.matrixWorldInverse, rect.matrixWorld));
  return { position: viewPosition(rect, camera), half_width: new THREE.Vector3(rect.width / 2, 0, 0).applyMatrix4(rot).toArray(),
    half_height: new THREE.Vector3(0, rect.height / 2, 0).applyMatrix4(rot).toArray() };
}

// The probes' scene (three_probe.js, three_directional_probe.js): meshes of the three geometries with the three
// materials — the plane at the origin, the sphere at (-1.2, 0.8, 0), the cylinder at (1.3, 0.8, 0.2) — lit by
// a point, a spot, a directional (20° up, 60° round) and a rect-area light and an ambient one, seen by a 45°
// camera from (0, 3.5, 6); the lights as three's shaders see them (view space).
export function probeScene(width, height, geometries, mats) {
  const scene = new THREE.Scene();
  const objs = geometries.map((g, i) => new THREE.Mesh(g, mats[i]));
  objs[1].position.set(-1.2, 0.8, 0);
  objs[2].position.set(1.3, 0.8, 0.2);
  for (const o of objs) scene.add(o);
  const point = new THREE.PointLight(0xffffff, 8, 0, 2);
  point.position.set(-2.5, 2, 1.5);
  const spot = new THREE.SpotLight(0xffffff, 20, 0, THREE.MathUtils.degToRad(40), 0.2, 2);
  spot.position.set(2.5, 3, 2);
  spot.target.position.set(0.5, 0, 0);
  const dir = new THREE.DirectionalLight(0xffffff, 2);
  const el = THREE.MathUtils.degToRad(20), az = THREE.MathUtils.degToRad(60);
  dir.position.set(Math.cos(el) * Math.sin(az), Math.sin(el), Math.cos(el) * Math.cos(az)).multiplyScalar(10);
  const rect = new THREE.RectAreaLight(0xffffff, 5, 2, 0.8);
  rect.position.set(0, 1.2, 2.5);
  rect.lookAt(0, 0.3, 0);
  scene.add(point, spot, spot.target, dir, dir.target, rect, new THREE.AmbientLight(0xffffff, 0.5));
  const camera = new THREE.PerspectiveCamera(45, width / height, 0.1, 50);
  camera.position.set(0, 3.5, 6);
  camera.lookAt(0, 0.5, 0);
  scene.updateMatrixWorld(true);
  camera.updateMatrixWorld(true);
  const lights = { point: { position: viewPosition(point, camera) }, spot: { position: viewPosition(spot, camera) },
    directional: { direction: viewDirection(dir, camera) }, rect: viewRect(rect, camera) };
  return { scene, camera, objs, lights };
}
