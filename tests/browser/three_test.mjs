// Drives headless Debian chromium (SwiftShader WebGL2) through the three.js example for
// tests/test_three_browser.cpp: opens the example page with ?probe, injects three_probe.js (the known scene and
// its read-backs) and runs every method of the module's list for every light type; then opens the example
// itself at 1280x720 for screenshots and the frame time with and without micro-shadowing, and measures the
// module's size. Collects console errors. Writes OUT/results.json; the C++ test compares with the library.
//
//   node three_test.mjs --url http://127.0.0.1:PORT/ --out DIR --module DIR/microshadow-three
//        [--chromium /usr/bin/chromium] [--figure FILE.png [--figure-only]] [--frames N] [--snippet FILE.js]
//        [--scene-snippet FILE.js] [--light-timing [--width 640 --height 360 --rounds 5]]
// --figure: also copy the with/without split at grazing sun (docs/three.md's figure) to FILE; --figure-only:
// only that (no probe, no frame time). --snippet: a module run in the probe page after the probe (docs/three.md's
// glTF block in a harness); it sets window.mshSnippet, recorded as results.snippet. --scene-snippet: only the
// glTF-scene check (three_scene_probe.js: a glTF asset built in the page, rendered before; then FILE, the docs'
// glTF block on it, which sets window.mshSnippet), recorded as results.scene; no probe, no example.
//
//   node three_test.mjs --serve DIR --page index.html --out DIR [--chromium PATH] [--revision R]
// The installed package (tests/test_three_package.cpp): serves DIR (a folder where `npm install <tgz> three`
// ran, with examples/three-importmap/index.html copied in) over HTTP from this process, opens the page, and
// records in results.package what it made: three's REVISION, the import map's four names resolved, the shader
// chunks and identifiers the module patches, and per light (the sun, the rect-area light, each alone) the
// canvas read back with micro-shadowing off and on.
// --light-timing: only the frame time per light type (the probe's scene at WIDTHxHEIGHT lit by one light type
// at a time, micro-shadowing on / off / absent, interleaved rounds of --frames frames, median over --rounds;
// three_probe.js timing()), recorded as results.light_timing and printed as a table; docs/three.md "Cost".
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';
import zlib from 'node:zlib';
import { arg, CHROMIUM_ARGS, openProbe } from './probe_page.mjs';

const url = arg('url'), out = arg('out'), moduleDir = arg('module'), figure = arg('figure');
const exe = arg('chromium', '/usr/bin/chromium'), frames = Number(arg('frames', '3'));
const figureOnly = process.argv.includes('--figure-only');
const snippet = arg('snippet'), sceneSnippet = arg('scene-snippet');
const serveDir = arg('serve'), pageName = arg('page', 'index.html');
const lightTiming = process.argv.includes('--light-timing');
// The docs figure: the sun 7° above the horizon behind the camera, the split through the glTF torus and the
// plane; left without micro-shadowing, right with the recommended pair.
const FIGURE = { elevation: 7, azimuth: 200, camera: [0, 1.1, -3.6], target: [0, 0.3, -0.5], panel: false, split: true, attached: true, light: 'sun' };
if (!out || (!serveDir && (!url || !moduleDir))) {
  console.error('usage: node three_test.mjs --url URL --out DIR --module DIR [--chromium PATH] [--figure FILE] [--frames N]; or --serve DIR --page FILE --out DIR');
  process.exit(2);
}
fs.mkdirSync(out, { recursive: true });
const DEFAULT_PAIR = 'diffuse-aware-alu+generic-vndf-alu';
if (serveDir) {
  await packagePage();
  process.exit(0);
}

const results = { url, errors: [], screenshots: [], timing: {} };
const T0 = Date.now();
const mark = (k) => { results.timing[k] = (Date.now() - T0) / 1000; };

// The module as a user ships it: every file under microshadow-three/, raw and gzip -9.
const files = [];
const walk = (d) => { for (const e of fs.readdirSync(d, { withFileTypes: true })) { const p = path.join(d, e.name); if (e.isDirectory()) walk(p); else files.push(p); } };
walk(moduleDir);
const all = Buffer.concat(files.sort().map((f) => fs.readFileSync(f)));
results.bundle = { files: files.map((f) => path.relative(moduleDir, f)), bytes: all.length, gzip_bytes: zlib.gzipSync(all, { level: 9 }).length,
  glsl_bytes: fs.statSync(path.join(moduleDir, 'generated', 'glsl.js')).size };

const browser = await chromium.launch({ executablePath: exe, headless: true, args: CHROMIUM_ARGS });
const watch = (page, tag) => {
  page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') results.errors.push(`${tag} console ${m.type()}: ${m.text().slice(0, 2000)}`); });
  page.on('pageerror', (e) => results.errors.push(`${tag} pageerror: ${e.message}`));
};
try {
  if (lightTiming) await lightTimes();
  else if (sceneSnippet) await sceneCheck();
  else if (!figureOnly) await probe();
  if (!figureOnly && !sceneSnippet && !lightTiming) await example();
  if (figure) await figureShot();
  mark('done');
} catch (e) {
  results.errors.push(`driver: ${e.message}`);
} finally {
  await browser.close();
}

// ---- the probe: known scene, every method, every light
async function probe() {
  const W = 192, H = 108, GRID = [24, 14];
  const page = await browser.newPage({ viewport: { width: W + 40, height: H + 40 } });
  watch(page, 'probe');
  await openProbe(page, url, 'three_probe.js', 'mshProbeLoaded');
  Object.assign(results, await page.evaluate((o) => window.mshProbe.setup(o), { width: W, height: H, grid: GRID }));
  results.points = await page.evaluate(() => window.mshProbe.points());
  mark('setup');
  results.runs = [];
  // Every method with V from the aoMap (the first also reads the inputs), then the recommended pair with the
  // three V sources (its own inputs) and each light's direct light on and off, then lut3d with the table
  // loaded from KTX2.
  const jobs = results.methods.map((m, i) => [m.id, { inputs: i === 0 }]);
  jobs.push([DEFAULT_PAIR, { variant: true, inputs: true, direct: true }], ['lut3d', { ktx2: true }]);
  for (const [id, o] of jobs) {
    const r = await page.evaluate(([i, opt]) => window.mshProbe.run(i, opt), [id, o]);
    if (r.error !== 0) results.errors.push(`gl error ${r.error} with ${id}`);
    results.runs.push(r);
  }
  results.ao_switch = await page.evaluate((id) => window.mshProbe.aoSwitch(id), DEFAULT_PAIR);
  mark('methods');
  // areaLights 'center' against the point term at the centre, off against absent, 'cap' against 'center' for
  // rect lights of 3 sizes (x 0.5, 1, 2) at 2 distances (x 1, 0.5 from the point the light looks at).
  const configs = [[0.5, 1], [1, 1], [2, 1], [0.5, 0.5], [1, 0.5], [2, 0.5]];
  results.area = await page.evaluate(([m, ms, c]) => window.mshProbe.area(m, ms, c), [DEFAULT_PAIR, [DEFAULT_PAIR, 'brinck-maximov-2016'], configs]);
  if (results.area.error !== 0) results.errors.push(`gl error ${results.area.error} (area)`);
  mark('area');
  if (snippet) {
    await page.addScriptTag({ type: 'module', content: fs.readFileSync(snippet, 'utf8') });
    await page.waitForFunction(() => window.mshSnippet !== undefined, null, { timeout: 120000 });
    results.snippet = await page.evaluate(() => window.mshSnippet);
    mark('snippet');
  }
  for (const [name, on] of [['three_probe_without', false], ['three_probe_with', true]]) {
    const err = await page.evaluate(([p, on]) => window.mshProbe.shaded(p, on), [DEFAULT_PAIR, on]);
    if (err !== 0) results.errors.push(`gl error ${err} (${name})`);
    const file = path.join(out, `${name}.png`);
    await page.locator('canvas').screenshot({ path: file });
    results.screenshots.push(file);
  }
  await page.close();
}

// ---- frame time per light type (--light-timing)
async function lightTimes() {
  const W = Number(arg('width', '640')), H = Number(arg('height', '360')), rounds = Number(arg('rounds', '5'));
  const page = await browser.newPage({ viewport: { width: W + 40, height: H + 40 } });
  watch(page, 'timing');
  await openProbe(page, url, 'three_probe.js', 'mshProbeLoaded');
  await page.evaluate((o) => window.mshProbe.setup(o), { width: W, height: H, grid: [1, 1], tables: false });
  const r = await page.evaluate((o) => window.mshProbe.timing(o), { rounds, frames });
  if (r.error !== 0) results.errors.push(`gl error ${r.error} (timing)`);
  results.light_timing = r;
  const f = (x) => x.toFixed(2);
  console.log(`frame time per light type, ${r.width}x${r.height}, ${r.method}, ${r.frames} frames per round, ${r.rounds} interleaved rounds: median ms, median of the rounds' ratios`);
  console.log('| light | on ms | off ms | absent ms | on / absent | off / absent | on / off |');
  console.log('| --- | --- | --- | --- | --- | --- | --- |');
  for (const e of r.table)
    console.log(`| ${e.light} | ${e.ms.on.toFixed(0)} | ${e.ms.off.toFixed(0)} | ${e.ms.absent.toFixed(0)} | ${f(e.on_absent)} | ${f(e.off_absent)} | ${f(e.on_off)} |`);
  mark('light_timing');
  await page.close();
}

// ---- the glTF scene: docs/three.md's block on an asset with a shared mesh, a material without occlusion, an
// unlit one and a clearcoat one (three_scene_probe.js); the block's console.info lines in results.scene.info
async function sceneCheck() {
  const page = await browser.newPage({ viewport: { width: 320, height: 120 } });
  watch(page, 'scene');
  const info = [];
  let failed = false;
  page.on('console', (m) => { if (m.type() === 'info') info.push(m.text()); });
  page.on('pageerror', () => { failed = true; });
  await openProbe(page, url, 'three_scene_probe.js', 'mshSceneLoaded');
  const scene = { setup: await page.evaluate(() => window.mshScene.setup()) };
  scene.api = await page.evaluate(() => window.mshScene.api());
  mark('scene_setup');
  await page.addScriptTag({ type: 'module', content: fs.readFileSync(sceneSnippet, 'utf8') });
  // The block's module sets window.mshSnippet, or fails (a page error: recorded in results.errors).
  for (let t = 0; t < 480 && !failed; ++t) {
    if (await page.evaluate(() => window.mshSnippet !== undefined)) break;
    await new Promise((r) => setTimeout(r, 250));
  }
  scene.snippet = await page.evaluate(() => window.mshSnippet ?? null);
  scene.info = info;
  results.scene = scene;
  mark('scene');
  await page.close();
}

// ---- the example at 1280x720: screenshots, frame time with and without micro-shadowing
async function example() {
  const ex = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  watch(ex, 'example');
  await ex.goto(url);
  await ex.waitForFunction(() => window.mshExampleReady !== undefined, null, { timeout: 180000 });
  results.example_loaded = await ex.evaluate(() => window.mshExampleReady);
  mark('example');
  if (results.example_loaded) {
    await ex.evaluate(() => { window.mshExample.resize(1280, 720); window.mshExample.set({ animate: false, azimuth: 65, elevation: 8 }); });
    // Interleaved rounds (with, without, with, without): SwiftShader shares the cores with whatever else runs.
    const t = { with: [], without: [] };
    for (let round = 0; round < 2; ++round)
      for (const [name, s] of [['with', { attached: true }], ['without', { attached: false }]]) {
        await ex.evaluate((st) => window.mshExample.set(st), s);
        t[name].push(await ex.evaluate((n) => window.mshExample.time(n), frames));
      }
    const mean = (a) => a.reduce((x, y) => x + y, 0) / a.length;
    results.frame_ms = { with: mean(t.with), without: mean(t.without), rounds: t, frames_per_round: frames };
    mark('frame_time');
    const shots = [['three_example_with', { attached: true, split: false }],
      ['three_example_without', { attached: false, split: false }], ['three_grazing_split', FIGURE]];
    for (const [name, s] of shots) {
      const err = await ex.evaluate((st) => { window.mshExample.set(st); return window.mshExample.render(); }, s);
      if (err !== 0) results.errors.push(`gl error ${err} (${name})`);
      const file = path.join(out, `${name}.png`);
      await ex.screenshot({ path: file });
      results.screenshots.push(file);
    }
    // A nearly black frame means nothing was drawn.
    results.example_mean = await ex.evaluate(() => {
      const gl = window.mshExample.renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
      const px = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
      let s = 0;
      for (let i = 0; i < px.length; i += 4) s += px[i] + px[i + 1] + px[i + 2];
      return s / (3 * 255 * w * h);
    });
  }
  await ex.close();
}
// ---- the docs figure at 960x540 (docs/figures/three_grazing.png)
async function figureShot() {
  const W = 960, H = 540;
  const p = await browser.newPage({ viewport: { width: W, height: H } });
  watch(p, 'figure');
  await p.goto(url);
  await p.waitForFunction(() => window.mshExampleReady !== undefined, null, { timeout: 180000 });
  if (!(await p.evaluate(() => window.mshExampleReady))) { results.errors.push('figure: the example did not load'); return; }
  const err = await p.evaluate(([w, h, st]) => { window.mshExample.resize(w, h); window.mshExample.set(st); return window.mshExample.render(); }, [W, H, FIGURE]);
  if (err !== 0) results.errors.push(`gl error ${err} (figure)`);
  await p.screenshot({ path: figure });
  results.screenshots.push(figure);
  await p.close();
}

// ---- the installed package: a static server on the folder, the import-map page, the term on each light
async function packagePage() {
  const http = await import('node:http');
  const root = path.resolve(serveDir);
  const TYPES = { '.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8', '.mjs': 'text/javascript; charset=utf-8', '.json': 'application/json', '.png': 'image/png' };
  const served = [];
  const server = http.createServer((req, res) => {
    const rel = decodeURIComponent(new URL(req.url, 'http://127.0.0.1').pathname).replace(/^\/+/, '');
    const file = path.resolve(root, rel || 'index.html');
    if (!file.startsWith(`${root}${path.sep}`) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      res.writeHead(404, { 'Content-Type': 'text/plain' });
      res.end(`not found: /${rel}\n`);
      return;
    }
    served.push(path.relative(root, file));
    res.writeHead(200, { 'Content-Type': TYPES[path.extname(file)] ?? 'application/octet-stream', 'Cache-Control': 'no-store' });
    res.end(fs.readFileSync(file));
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  const base = `http://127.0.0.1:${server.address().port}/`;
  const res = { url: base, errors: [], timing: {} };
  const t0 = Date.now();
  const browser = await chromium.launch({ executablePath: exe, headless: true, args: CHROMIUM_ARGS });
  try {
    const page = await browser.newPage({ viewport: { width: 320, height: 240 } });
    let failed = false;
    page.on('console', (m) => { if (m.type() === 'error' || m.type() === 'warning') res.errors.push(`page console ${m.type()}: ${m.text().slice(0, 2000)}`); });
    page.on('pageerror', (e) => { failed = true; res.errors.push(`page pageerror: ${e.message}`); });
    page.on('requestfailed', (r) => { failed = true; res.errors.push(`request failed: ${r.url()}`); });
    page.on('response', (r) => { if (r.status() >= 400) { failed = true; res.errors.push(`HTTP ${r.status()}: ${r.url()}`); } });
    await page.goto(`${base}${pageName}`);
    for (let t = 0; t < 480 && !failed; ++t) {
      if (await page.evaluate(() => window.mshDemo !== undefined)) break;
      await new Promise((r) => setTimeout(r, 250));
    }
    res.loaded = await page.evaluate(() => window.mshDemo !== undefined);
    res.timing.loaded = (Date.now() - t0) / 1000;
    if (res.loaded) Object.assign(res, await page.evaluate(async () => {
      const d = window.mshDemo, THREE = d.THREE;
      const out = { revision: THREE.REVISION, method: d.method, handle_method: d.handle.method };
      // The import map's names: the subpath's loader is the main entry's (one module instance), the addon ran.
      const main = await import('microshadow-three');
      out.luts_same_module = typeof d.loadMicroShadowingLut === 'function' && d.loadMicroShadowingLut === main.loadMicroShadowingLut;
      const addons = await import('three/addons/lights/RectAreaLightUniformsLib.js');
      out.addon_loaded = typeof addons.RectAreaLightUniformsLib?.init === 'function' && THREE.UniformsLib.LTC_FLOAT_1 !== undefined;
      // What the module patches, by name, in this three: the includes and the identifiers its GLSL reads.
      const L = THREE.ShaderLib.physical, C = THREE.ShaderChunk;
      const need = {
        'fragment #include <lights_physical_pars_fragment>': L.fragmentShader, 'fragment #include <lights_fragment_begin>': L.fragmentShader,
        'fragment #include <aomap_fragment>': L.fragmentShader, 'fragment #include <dithering_fragment>': L.fragmentShader,
        'fragment #include <normal_fragment_maps>': L.fragmentShader, 'vertex #include <common>': L.vertexShader, 'vertex #include <uv_vertex>': L.vertexShader,
        'RE_Direct_Physical( const in IncidentLight directLight, const in vec3 geometryPosition, const in vec3 geometryNormal, const in vec3 geometryViewDir, const in vec3 geometryClearcoatNormal, const in PhysicalMaterial material, inout ReflectedLight reflectedLight )': C.lights_physical_pars_fragment,
        'RE_Direct_RectArea_Physical( const in RectAreaLight rectAreaLight, const in vec3 geometryPosition, const in vec3 geometryNormal, const in vec3 geometryViewDir, const in vec3 geometryClearcoatNormal, const in PhysicalMaterial material, inout ReflectedLight reflectedLight )': C.lights_physical_pars_fragment,
        'vAoMapUv': C.aomap_fragment, 'aoMapIntensity': C.aomap_fragment, 'nonPerturbedNormal': C.normal_fragment_begin,
      };
      out.missing = Object.entries(need).filter(([k, src]) => !src.includes(k.replace(/^(fragment|vertex) /, ''))).map(([k]) => k);
      // Each light alone, micro-shadowing off then on: the canvas read back (8-bit sRGB).
      const gl = d.renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
      const grab = () => { d.render(); const px = new Uint8Array(w * h * 4); gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px); return px; };
      out.lights = {};
      for (const name of Object.keys(d.lights)) {
        for (const [k, l] of Object.entries(d.lights)) l.visible = k === name;
        d.handle.enabled = false;
        const off = grab();
        d.handle.enabled = true;
        const on = grab();
        let lit = 0, darker = 0, brighter = 0, sumOff = 0, sumOn = 0, maxDrop = 0;
        for (let i = 0; i < off.length; i += 4) {
          if (off[i] < 8) continue;  // background and unlit floor
          ++lit; sumOff += off[i]; sumOn += on[i];
          if (on[i] < off[i]) ++darker;
          if (on[i] > off[i]) ++brighter;
          maxDrop = Math.max(maxDrop, off[i] - on[i]);
        }
        const c = 4 * ((h >> 1) * w + (w >> 1));
        out.lights[name] = { pixels: w * h, lit, darker, brighter, mean_off: sumOff / Math.max(lit, 1) / 255, mean_on: sumOn / Math.max(lit, 1) / 255,
          max_drop: maxDrop / 255, centre_off: off[c] / 255, centre_on: on[c] / 255 };
      }
      for (const l of Object.values(d.lights)) l.visible = true;
      d.handle.enabled = true;
      d.render();
      out.gl_error = gl.getError();
      return out;
    }));
    res.timing.done = (Date.now() - t0) / 1000;
    const shot = path.join(out, 'importmap_page.png');
    await page.screenshot({ path: shot });
    res.screenshot = shot;
    await page.close();
  } catch (e) {
    res.errors.push(`driver: ${e.message}`);
  } finally {
    await browser.close();
    server.close();
  }
  res.served = [...new Set(served)].sort();
  fs.writeFileSync(path.join(out, 'results.json'), JSON.stringify({ errors: res.errors, package: res }));
  console.log(`wrote ${path.join(out, 'results.json')}: three r${res.revision}, ${res.errors.length} errors, ${res.timing.done} s`);
}

fs.writeFileSync(path.join(out, 'results.json'), JSON.stringify(results));
console.log(`wrote ${path.join(out, 'results.json')}: ${(results.runs || []).length} methods, ${results.errors.length} errors, ${results.timing.done} s`);
