// The drivers' shared parts (three_test.mjs, three_directional_test.mjs): the command line, headless chromium's
// flags, and the probe page — the example opened with ?probe, an in-page probe script injected into it, and
// the probes' shared module (probe_common.js) served to the page as ./msh-test/probe_common.js.
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));

// The value after --name on the command line, or def.
export const arg = (name, def) => {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? process.argv[i + 1] : def;
};

// Headless Debian chromium with SwiftShader WebGL2.
export const CHROMIUM_ARGS = ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist', '--no-sandbox', '--disable-dev-shm-usage'];

// Opens url?probe in `page` (the page's requests for msh-test/<file> answered with tests/browser/<file>), waits
// up to exampleTimeout ms for the example to start, injects tests/browser/<script> as a module and waits until
// it sets window[flag].
export async function openProbe(page, url, script, flag, exampleTimeout = 60000) {
  await page.route('**/msh-test/*.js', (route) => route.fulfill({ contentType: 'text/javascript; charset=utf-8',
    path: path.join(here, path.basename(new URL(route.request().url()).pathname)) }));
  await page.goto(`${url}?probe`);
  await page.waitForFunction(() => window.mshExampleReady !== undefined, null, { timeout: exampleTimeout });
  await page.addScriptTag({ type: 'module', content: fs.readFileSync(path.join(here, script), 'utf8') });
  await page.waitForFunction((f) => window[f] === true, flag, { timeout: 60000 });
}
