// Drives headless Debian chromium (SwiftShader WebGL2) through the viewer for tests/test_viewer_browser.cpp:
// loads the page, switches through every method (screenshots), probes fixed configurations (the shader's
// inputs and every method's float value, plus the 8-bit term output), checks the error banners (no WebGL2, a
// failed fetch) and collects console errors. Writes OUT/results.json; the C++ test compares with the library.
// --methods FILE: the page gets FILE as its methods.js (the test's list: the served one plus test pairs).
//
//   node viewer_test.mjs --url http://127.0.0.1:PORT/ --out DIR [--chromium /usr/bin/chromium] [--methods FILE]
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const arg = (name, def) => {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? process.argv[i + 1] : def;
};
const url = arg('url');
const out = arg('out');
const exe = arg('chromium', '/usr/bin/chromium');
const methodsFile = arg('methods');
if (!url || !out) {
  console.error('usage: node viewer_test.mjs --url URL --out DIR [--chromium PATH]');
  process.exit(2);
}
fs.mkdirSync(out, { recursive: true });

// SwiftShader: a CPU WebGL2 (no GPU needed); the flags the project uses everywhere (docs/viewer.md).
export const CHROMIUM_ARGS = ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
  '--no-sandbox', '--disable-dev-shm-usage'];

const W = 480, H = 270;
// Fixed configurations: camera, light and material controls (docs/viewer.md lists the controls).
const CONFIGS = [
  { name: 'plane-directional', state: { scene: 'plane', cam_el: 40, cam_az: 0, cam_dist: 4, light_type: 'directional', light_el: 25, light_az: 30, tiling: 2, normal_strength: 1, rough_on: false, vis_on: false, samples: 32, split: false, display: 'term', bump: 'none', bump_hemi: false } },
  { name: 'plane-flat-visibility', state: { scene: 'plane', cam_el: 55, cam_az: 30, cam_dist: 3.5, light_type: 'directional', light_el: 40, light_az: -40, tiling: 2, normal_strength: 0, rough_on: false, vis_on: true, vis: 0.45, samples: 32, split: false, display: 'term', bump: 'none', bump_hemi: false } },
  { name: 'sphere-point', state: { scene: 'sphere', cam_el: 30, cam_az: 20, cam_dist: 3.5, light_type: 'point', light_el: 35, light_az: -60, light_dist: 2.5, tiling: 2, normal_strength: 1.5, rough_on: true, rough: 0.55, vis_on: true, vis: 0.8, samples: 16, split: false, display: 'term', bump: 'conty-2019', bump_hemi: false }, region: [0.3, 0.1, 0.7, 0.9] },
  { name: 'cylinder-grazing', state: { scene: 'cylinder', cam_el: 15, cam_az: 0, cam_dist: 4.5, light_type: 'directional', light_el: 8, light_az: 70, tiling: 2, normal_strength: 1, rough_on: false, vis_on: true, vis: 0.62, samples: 64, split: false, display: 'term', bump: 'chiang-2019', bump_hemi: true }, region: [0.3, 0.1, 0.7, 0.9] },
];
const GRID = [8, 6];  // probe points per configuration: a grid over its region (background ones dropped)

const results = { url, errors: [], configs: [], screenshots: [], banner: {}, timing: {} };
const T0 = Date.now();
const mark = (k) => { results.timing[k] = (Date.now() - T0) / 1000; };
const browser = await chromium.launch({ executablePath: exe, headless: true, args: CHROMIUM_ARGS });
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 760 } });
  page.on('console', (m) => { if (m.type() === 'error') results.errors.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => results.errors.push(`pageerror: ${e.message}`));
  if (methodsFile)
    await page.route('**/methods.js', (r) => r.fulfill({ status: 200, contentType: 'text/javascript; charset=utf-8', body: fs.readFileSync(methodsFile, 'utf8') }));
  await page.goto(url);
  await page.waitForFunction(() => window.mshViewer !== undefined, null, { timeout: 120000 });
  const ok = await page.evaluate(() => window.mshViewer.ready);
  results.loaded = ok;
  mark('loaded');
  if (!ok) results.errors.push(`page: ${await page.evaluate(() => window.mshViewer.error)}`);
  if (ok) {
    results.methods = await page.evaluate(() => window.mshViewer.methods);
    results.bumps = await page.evaluate(() => window.mshViewer.bumps);
    results.manifest = await page.evaluate(() => window.mshViewer.manifest);
    await page.evaluate(([w, h]) => window.mshViewer.resize(w, h), [W, H]);
    for (const cfg of CONFIGS) {
      const c = { name: cfg.name, state: cfg.state, probes: [] };
      await page.evaluate((s) => window.mshViewer.set(s), cfg.state);
      // Every method: render (GL errors recorded), screenshot of the canvas.
      for (const m of results.methods) {
        const err = await page.evaluate((id) => { window.mshViewer.set({ method_a: id }); return window.mshViewer.render(); }, m.id);
        if (err !== 0) results.errors.push(`gl error ${err} rendering ${m.id} (${cfg.name})`);
        if (cfg.name === CONFIGS[0].name) {
          const file = path.join(out, `viewer_${cfg.name}_${m.id}.png`);
          await page.locator('#gl').screenshot({ path: file });
          results.screenshots.push(file);
        }
      }
      const [rx0, ry0, rx1, ry1] = cfg.region || [0, 0, 1, 1], pts = [];
      for (let j = 0; j < GRID[1]; ++j)
        for (let i = 0; i < GRID[0]; ++i)
          pts.push([Math.floor(W * (rx0 + (rx1 - rx0) * (i + 0.5) / GRID[0])), Math.floor(H * (ry0 + (ry1 - ry0) * (j + 0.5) / GRID[1]))]);
      c.probes = (await page.evaluate((p) => window.mshViewer.probeMany(p, true), pts)).filter((p) => p.hit);
      results.configs.push(c);
      mark(cfg.name);
    }
    // The A/B split in the shaded display, and the specular-only toggle: screenshots.
    await page.evaluate(([w, h]) => window.mshViewer.resize(w, h), [960, 540]);
    for (const [name, s] of [['split-shaded', { display: 'shaded', split: true, method_a: 'chan-2018', method_b: 'lut3d' }],
      ['split-specular', { display: 'shaded', split: true, method_a: 'chan-2018', method_b: 'lut3d', component: 'specular' }], ['all-three', { display: 'shaded', scene: 'all', cam_dist: 7, cam_el: 25 }]]) {
      const err = await page.evaluate((st) => { window.mshViewer.set(st); return window.mshViewer.render(); }, { ...CONFIGS[0].state, ...s });
      if (err !== 0) results.errors.push(`gl error ${err} (${name})`);
      const file = path.join(out, `viewer_${name}.png`);
      await page.screenshot({ path: file });
      results.screenshots.push(file);
    }
    // A nearly black screenshot means nothing was drawn: record the mean of the shaded canvas.
    results.shadedMean = await page.evaluate(() => {
      const c = document.getElementById('gl'), gl = c.getContext('webgl2');
      const px = new Uint8Array(c.width * c.height * 4);
      gl.readPixels(0, 0, c.width, c.height, gl.RGBA, gl.UNSIGNED_BYTE, px);
      let s = 0;
      for (let i = 0; i < px.length; i += 4) s += px[i] + px[i + 1] + px[i + 2];
      return s / (3 * 255 * c.width * c.height);
    });
  }
  mark('screens');
  await page.close();

  // Error banners: no WebGL2 (getContext('webgl2') -> null), and a failed fetch (the manifest answers 404).
  for (const kind of ['no-webgl2', 'fetch-fails']) {
    const p = await browser.newPage();
    if (kind === 'no-webgl2')
      await p.addInitScript(() => {
        const orig = HTMLCanvasElement.prototype.getContext;
        HTMLCanvasElement.prototype.getContext = function (t, ...a) { return t === 'webgl2' ? null : orig.call(this, t, ...a); };
      });
    else await p.route('**/data/manifest.json', (r) => r.fulfill({ status: 404, body: 'not found' }));
    await p.goto(url);
    await p.waitForFunction(() => window.mshViewer !== undefined, null, { timeout: 60000 });
    results.banner[kind] = await p.evaluate(() => {
      const b = document.getElementById('banner');
      return { visible: !b.hidden, text: b.textContent };
    });
    await p.screenshot({ path: path.join(out, `viewer_banner_${kind}.png`) });
    await p.close();
  }
  mark('banners');
} catch (e) {
  results.errors.push(`driver: ${e.message}`);
} finally {
  await browser.close();
}
fs.writeFileSync(path.join(out, 'results.json'), JSON.stringify(results, null, 1));
console.log(`wrote ${path.join(out, 'results.json')}: ${results.configs.length} configurations, ${results.errors.length} errors`);
