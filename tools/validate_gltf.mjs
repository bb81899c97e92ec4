// Runs the Khronos glTF validator on each file given:
//   node tools/validate_gltf.mjs FILE...
// Prints "FILE: N errors, M warnings" per file, then each error and warning (code, message, JSON
// pointer). Exits 1 if any file has errors or cannot be validated, 2 on a usage error.
// Sinew writes self-contained files (GLB, or .gltf with data: URIs), so any external reference
// is refused, which the validator reports as an error.
import { readFile } from 'node:fs/promises';
import { validateBytes } from 'gltf-validator';

const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node tools/validate_gltf.mjs FILE...');
  process.exit(2);
}

const severityNames = ['error', 'warning', 'info', 'hint'];
let failed = false;
for (const file of files) {
  try {
    const bytes = new Uint8Array(await readFile(file));
    const report = await validateBytes(bytes, {
      uri: file,
      maxIssues: 0,  // unlimited
      writeTimestamp: false,
      externalResourceFunction: (uri) =>
        Promise.reject(new Error(`external resource '${uri}' (expected everything embedded)`)),
    });
    const { numErrors, numWarnings, messages } = report.issues;
    console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings`);
    for (const message of messages) {
      if (message.severity > 1) continue;  // infos and hints are not problems
      const where =
        message.pointer ?? (message.offset !== undefined ? `byte ${message.offset}` : '');
      console.log(`  ${severityNames[message.severity]} ${message.code}: ${message.message}` +
                  (where ? ` (${where})` : ''));
    }
    if (numErrors > 0) failed = true;
  } catch (error) {
    console.log(`${file}: cannot be validated: ${error}`);
    failed = true;
  }
}
process.exit(failed ? 1 : 0);
