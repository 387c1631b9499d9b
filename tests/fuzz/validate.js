// Runs the Khronos glTF validator (npm gltf-validator) on each file named on the command line and prints one JSON
// line per file: {"file", "errors", "warnings", "first"} (first: the first error's code and message). External
// resources are read from the file's folder. Used by compare_validator.py.
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

async function validate(file) {
  const folder = path.dirname(file);
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 50,
    externalResourceFunction: (uri) => new Promise((resolve, reject) => {
      fs.readFile(path.join(folder, decodeURIComponent(uri)), (err, data) => err ? reject(err.toString()) : resolve(data));
    }),
  });
  const first = report.issues.messages.find((m) => m.severity === 0);
  return {file, errors: report.issues.numErrors, warnings: report.issues.numWarnings,
          first: first ? `${first.code}: ${first.message} (${first.pointer || ''})` : ''};
}

(async () => {
  for (const file of process.argv.slice(2)) {
    try {
      console.log(JSON.stringify(await validate(file)));
    } catch (e) {
      console.log(JSON.stringify({file, errors: -1, warnings: 0, first: `validator failed: ${e}`}));
    }
  }
})();
