// Runs the Khronos glTF validator (npm gltf-validator, pinned in package-lock.json) on a .gltf file with its
// external resources (buffers, images) read from beside it, for tests/test_gltf_validator.cpp
// (docs/gltf.md). Writes the validator's JSON report to OUT (or stdout); exit 0 when it ran (the C++ test
// reads the counts), 2 on a usage or I/O error.
//
//   node gltf_validate.mjs FILE.gltf [--out REPORT.json]
import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

const file = process.argv[2];
const outIdx = process.argv.indexOf('--out');
const out = outIdx > 0 ? process.argv[outIdx + 1] : null;
if (!file) {
  console.error('usage: node gltf_validate.mjs FILE.gltf [--out REPORT.json]');
  process.exit(2);
}
try {
  const bytes = new Uint8Array(fs.readFileSync(file));
  const dir = path.dirname(file);
  const report = await validator.validateBytes(bytes, {
    uri: path.basename(file),
    maxIssues: 0,  // all
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      fs.readFile(path.join(dir, decodeURIComponent(uri)), (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
    }),
  });
  const text = JSON.stringify(report, null, 1);
  if (out) fs.writeFileSync(out, text); else console.log(text);
  const i = report.issues;
  console.error(`gltf-validator ${report.validatorVersion}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
} catch (e) {
  console.error(`gltf_validate: ${e.message || e}`);
  process.exit(2);
}
