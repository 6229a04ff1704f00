// Runs the Khronos glTF validator (npm gltf-validator) over the given files and writes a report:
//   node validate.mjs <report.json> <file.gltf|.glb> ...
// The report records, per file, its SHA-256 and the validator's error / warning / info counts, so
// that a test without network access (tests/data/gltf/check_validation_report.cmake) can check that
// every committed file is the one that was validated and had 0 errors. Exits 1 when a file has
// errors (each is printed).
import { readFileSync, writeFileSync } from 'node:fs';
import { createHash } from 'node:crypto';
import { basename, dirname, join } from 'node:path';
import { createRequire } from 'node:module';
import validator from 'gltf-validator';

const [report, ...files] = process.argv.slice(2);
if (!report || files.length === 0) {
  console.error('usage: node validate.mjs <report.json> <file> ...');
  process.exit(2);
}
const version = createRequire(import.meta.url)('gltf-validator/package.json').version;

const results = {};
let failed = false;
for (const file of files) {
  const bytes = new Uint8Array(readFileSync(file));
  const result = await validator.validateBytes(bytes, {
    uri: basename(file),
    externalResourceFunction: (uri) => Promise.resolve(new Uint8Array(readFileSync(join(dirname(file), decodeURIComponent(uri))))),
  });
  const { numErrors, numWarnings, numInfos } = result.issues;
  results[basename(file)] = {
    sha256: createHash('sha256').update(bytes).digest('hex'),
    errors: numErrors,
    warnings: numWarnings,
    infos: numInfos,
    messages: result.issues.messages.map((m) => `${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} ${m.pointer ?? ''}: ${m.message}`),
  };
  console.log(`${basename(file)}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos`);
  for (const m of result.issues.messages.filter((m) => m.severity === 0)) console.log(`  ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (numErrors > 0) failed = true;
}
writeFileSync(report, JSON.stringify({ validator: `gltf-validator ${version}`, files: results }, null, 1) + '\n');
process.exit(failed ? 1 : 0);
