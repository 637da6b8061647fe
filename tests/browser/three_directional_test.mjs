// Drives headless Debian chromium (SwiftShader WebGL2) for tests/test_three_directional_browser.cpp: opens the
// three.js example page with ?probe (its import map serves three and microshadow-three), injects
// three_directional_probe.js and runs directional-view (and its pair with the generic ALU fit) on a known scene
// with the texture set's 21 channels and with a compact (K < 21) fixture; with --gltf, also a glTF asset through
// the module's GLTFLoader plugin (three_gltf_probe.js). Writes OUT/results.json; the C++ test compares with the
// library.
//
//   node three_directional_test.mjs --url http://127.0.0.1:PORT/ --out DIR --material data/dirmat
//        [--compact data/dircompact] [--bad name=url,...] [--gltf data/gltf/material.gltf]
//        [--bad-gltf name=url,...] [--chromium PATH]
// --bad / --bad-gltf: mips.json / glTF files that must fail to load; their messages go to results
// (errors_by_case, gltf_errors) and their page's console lines to results.bad_console.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';
import { arg, CHROMIUM_ARGS, openProbe } from './probe_page.mjs';

const url = arg('url'), out = arg('out'), material = arg('material'), compact = arg('compact'), gltf = arg('gltf');
const exe = arg('chromium', '/usr/bin/chromium');
const list = (name) => Object.fromEntries((arg(name, '') || '').split(',').filter((s) => s).map((s) => s.split('=')));
const bad = list('bad'), badGltf = list('bad-gltf');
if (!url || !out || !material) {
  console.error('usage: node three_directional_test.mjs --url URL --out DIR --material PATH [--compact PATH] [--bad k=url,...] [--gltf URL] [--chromium PATH]');
  process.exit(2);
}
fs.mkdirSync(out, { recursive: true });
const results = { url, errors: [], screenshots: [], timing: {} };
const T0 = Date.now();
const mark = (k) => { results.timing[k] = (Date.now() - T0) / 1000; };

const browser = await chromium.launch({ executablePath: exe, headless: true, args: CHROMIUM_ARGS });
// HTTP errors are listed in results.http_errors (the bad-input case asks for a missing file on purpose); the
// console line chromium prints for each is left out of results.errors, every other console error or warning
// is kept.
results.http_errors = [];
results.bad_console = [];
const watch = (page, tag, sink = results.errors) => {
  page.on('response', (r) => { if (r.status() >= 400) results.http_errors.push(`${r.status()} ${r.url()}`); });
  page.on('console', (m) => {
    if (m.type() !== 'error' && m.type() !== 'warning') return;
    if (/^Failed to load resource: the server responded with a status of \d+/.test(m.text())) return;
    sink.push(`${tag} console ${m.type()}: ${m.text().slice(0, 2000)}`);
  });
  page.on('pageerror', (e) => results.errors.push(`${tag} pageerror: ${e.message}`));
};
try {
  await probe();
  if (gltf) await gltfProbe();
  if (Object.keys(badGltf).length) await gltfBad();
  mark('done');
} catch (e) {
  results.errors.push(`driver: ${e.message}`);
} finally {
  await browser.close();
}

async function open(tag, script, flag, sink) {
  const W = 192, H = 108;
  const page = await browser.newPage({ viewport: { width: W + 40, height: H + 40 } });
  watch(page, tag, sink);
  await openProbe(page, url, script, flag, 120000);
  return { page, W, H };
}

async function probe() {
  const { page, W, H } = await open('probe', 'three_directional_probe.js', 'mshDirProbeLoaded');
  Object.assign(results, await page.evaluate((o) => window.mshDirProbe.setup(o), { width: W, height: H, grid: [24, 14], material, compact, bad }));
  results.points = await page.evaluate(() => window.mshDirProbe.points());
  mark('setup');
  const jobs = [['directional-view', 'channels21', {}], ['directional-view+generic-vndf-alu', 'channels21', { direct: true }]];
  if (compact) jobs.push(['directional-view', 'compact', {}]);
  results.runs = [];
  for (const [m, c, o] of jobs) {
    const r = await page.evaluate(([a, b, x]) => window.mshDirProbe.run(a, b, x), [m, c, o]);
    if (r.error !== 0) results.errors.push(`gl error ${r.error} with ${m} (${c})`);
    results.runs.push(r);
  }
  results.nearest = [];
  for (const c of compact ? ['channels21_nearest', 'compact_nearest'] : ['channels21_nearest']) {
    const r = await page.evaluate(([a, b]) => window.mshDirProbe.channels(a, b), ['directional-view', c]);
    if (r.error !== 0) results.errors.push(`gl error ${r.error} (${c})`);
    results.nearest.push(r);
  }
  mark('runs');
  for (const [name, on] of [['three_directional_without', false], ['three_directional_with', true]]) {
    const err = await page.evaluate(([o]) => window.mshDirProbe.shaded('directional-view+generic-vndf-alu', 'channels21', o), [on]);
    if (err !== 0) results.errors.push(`gl error ${err} (${name})`);
    const file = path.join(out, `${name}.png`);
    await page.locator('canvas').last().screenshot({ path: file });
    results.screenshots.push(file);
  }
  await page.close();
}

async function gltfProbe() {
  const { page, W, H } = await open('gltf', 'three_gltf_probe.js', 'mshGltfProbeLoaded');
  results.gltf = await page.evaluate((o) => window.mshGltfProbe.run(o), { width: W, height: H, grid: [24, 14], url: gltf });
  if (results.gltf.error) results.errors.push(`gltf: ${results.gltf.error}`);
  const file = path.join(out, 'three_gltf.png');
  await page.locator('canvas').last().screenshot({ path: file });
  results.screenshots.push(file);
  mark('gltf');
  await page.close();
}

async function gltfBad() {
  const { page } = await open('gltf-bad', 'three_gltf_probe.js', 'mshGltfProbeLoaded', results.bad_console);
  results.gltf_errors = {};
  for (const [k, u] of Object.entries(badGltf)) results.gltf_errors[k] = await page.evaluate((x) => window.mshGltfProbe.loadError(x), u);
  mark('gltf_bad');
  await page.close();
}

fs.writeFileSync(path.join(out, 'results.json'), JSON.stringify(results));
console.log(`wrote ${path.join(out, 'results.json')}: ${(results.runs || []).length} runs, ${results.errors.length} errors, ${results.timing.done} s`);
