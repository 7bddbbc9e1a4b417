#!/usr/bin/env node
// Validates a glTF 2.0 binary with the Khronos glTF validator (npm package gltf-validator, which
// .ci/setup installs into .cache/node_modules) and prints one line of counts, then the issues.
//   node scenes/tools/validate_gltf.js FILE.glb
// Exit codes: 0 no error and no warning, 1 errors or warnings, 2 usage or unreadable file,
// 77 the gltf-validator package is not installed (ctest reads 77 as "skipped").
'use strict';
const fs = require('fs');
const path = require('path');

function loadValidator() {
  const candidates = [process.env.GLTF_VALIDATOR_DIR, path.join(__dirname, '..', '..', '.cache', 'node_modules', 'gltf-validator'),
                      'gltf-validator'];
  for (const c of candidates) {
    if (!c) continue;
    try {
      return require(c);
    } catch (e) {
      // try the next place
    }
  }
  return null;
}

async function main() {
  const file = process.argv[2];
  if (!file || process.argv.length > 3) {
    console.error('usage: node validate_gltf.js FILE.glb');
    return 2;
  }
  const validator = loadValidator();
  if (!validator) {
    console.error('validate_gltf: the npm package gltf-validator is not installed (bash .ci/setup test installs it)');
    return 77;
  }
  let bytes;
  try {
    bytes = fs.readFileSync(file);
  } catch (e) {
    console.error(`validate_gltf: ${file}: ${e.message}`);
    return 2;
  }
  const report = await validator.validateBytes(new Uint8Array(bytes), { maxIssues: 1000 });
  const i = report.issues;
  console.log(`${file}: errors ${i.numErrors}, warnings ${i.numWarnings}, infos ${i.numInfos}, hints ${i.numHints}` +
              ` (gltf-validator ${report.validatorVersion})`);
  const names = ['error', 'warning', 'info', 'hint'];
  for (const m of i.messages) console.log(`  ${names[m.severity]} ${m.code} ${m.pointer || ''}: ${m.message}`);
  return i.numErrors === 0 && i.numWarnings === 0 ? 0 : 1;
}

main().then((code) => process.exit(code), (e) => {
  console.error(`validate_gltf: ${e.message || e}`);
  process.exit(2);
});
