// Frame time of the viewer per micro-shadowing method at 1280x720 under headless chromium + SwiftShader (a CPU
// WebGL2: a GPU is orders of magnitude faster), and the page's load size. Starts its own `microshadow view`.
//
//   node bench/browser/frame_time.mjs [--cli build/bin/microshadow] [--frames 4] [--chromium /usr/bin/chromium]
//
// Needs playwright-core in tests/browser/node_modules (`npm ci` there; scripts/install-deps.sh does it).
// Prints a Markdown table (docs/viewer.md). Wall-clock times: on a shared machine they include others' load.
import { createRequire } from 'node:module';
import { spawn } from 'node:child_process';
import os from 'node:os';

const require = createRequire(new URL('../../tests/browser/package.json', import.meta.url));
const { chromium } = require('playwright-core');
const arg = (n, d) => { const i = process.argv.indexOf(`--${n}`); return i > 0 ? process.argv[i + 1] : d; };
const cli = arg('cli', 'build/bin/microshadow');
const frames = Number(arg('frames', '4'));
const exe = arg('chromium', '/usr/bin/chromium');

const server = spawn(cli, ['view', '--port', '0', '--cache', arg('cache', 'build/viewer_cache')], { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve, reject) => {
  let out = '';
  server.stdout.on('data', (d) => { out += d; const m = out.match(/http:\/\/\S+/); if (m) resolve(m[0]); });
  server.on('exit', (c) => reject(new Error(`microshadow view exited with ${c}`)));
});
const browser = await chromium.launch({ executablePath: exe, headless: true,
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--no-sandbox', '--disable-dev-shm-usage'] });
try {
  const page = await browser.newPage({ viewport: { width: 1700, height: 900 } });
  let bytes = 0, files = 0;
  page.on('response', (r) => { bytes += Number(r.headers()['content-length'] || 0); files++; });
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.mshViewer !== undefined, null, { timeout: 300000 });
  if (!(await page.evaluate(() => window.mshViewer.ready))) throw new Error(await page.evaluate(() => window.mshViewer.error));
  const loadS = (Date.now() - t0) / 1000;
  await page.evaluate(() => window.mshViewer.resize(1280, 720));
  const methods = await page.evaluate(() => window.mshViewer.methods);
  const base = { scene: 'plane', display: 'shaded', split: false, cam_el: 40, cam_az: 0, cam_dist: 4, light_type: 'directional', light_el: 25, light_az: 30, samples: 32 };
  const rows = [];
  for (const m of methods) {
    const ms = await page.evaluate(([s, n]) => { window.mshViewer.set(s); return window.mshViewer.time(n); }, [{ ...base, method_a: m.id }, frames]);
    rows.push([m.id, ms]);
  }
  const split = await page.evaluate(([s, n]) => { window.mshViewer.set(s); return window.mshViewer.time(n); },
    [{ ...base, split: true, method_a: 'chan-2018', method_b: 'lut3d' }, frames]);
  console.log(`| method (plane, 1280x720, shaded, N = 32 for generic-vndf) | ms / frame |`);
  console.log('|---|---|');
  for (const [id, ms] of rows) console.log(`| ${id} | ${ms.toFixed(1)} |`);
  console.log(`| A/B split chan-2018 / lut3d | ${split.toFixed(1)} |`);
  console.log(`\nload: ${files} responses, ${(bytes / 1048576).toFixed(2)} MiB, ${loadS.toFixed(1)} s to ready; ` +
    `${frames} frames per method; load average ${os.loadavg().map((x) => x.toFixed(1)).join(' ')} on ${os.cpus().length} cores`);
} finally {
  await browser.close();
  server.kill('SIGINT');
}
