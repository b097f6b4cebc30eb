// Validates glTF 2.0 files with the Khronos glTF Validator (npm gltf-validator, installed by
// tools/install-gltf-validator.sh into .cache/gltf-validator). Prints each file's counts of errors, warnings,
// infos and hints, and every error and warning; exits 1 when any file has an error, 2 when one cannot be read.
//   node tools/gltf-validate.js FILE.glb|FILE.gltf ...
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require(process.env.PB_GLTF_VALIDATOR_MODULE ||
                          path.join(__dirname, '..', '.cache', 'gltf-validator', 'node_modules', 'gltf-validator'));

async function validate(file) {
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      fs.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)), (err, data) => err ? reject(err.toString()) : resolve(data));
    }),
  });
  const i = report.issues;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints ` +
              `(glTF Validator ${report.validatorVersion})`);
  for (const m of i.messages)
    if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} at ${m.pointer}: ${m.message}`);
  return i.numErrors;
}

(async () => {
  let errors = 0;
  for (const file of process.argv.slice(2)) {
    try {
      errors += await validate(file);
    } catch (e) {
      console.log(`${file}: cannot be validated: ${e}`);
      process.exit(2);
    }
  }
  process.exit(errors > 0 ? 1 : 0);
})();
