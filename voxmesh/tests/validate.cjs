// Runs the Khronos glTF validator (npm package `gltf-validator`) on every file named on the
// command line and prints one JSON line per file: its path, the counts of errors, warnings,
// infos and hints, and the first messages. The package is found in the folder named by the
// environment variable GLTF_VALIDATOR (its node_modules/gltf-validator).
'use strict';
const fs = require('fs');
const path = require('path');

const dir = process.env.GLTF_VALIDATOR;
if (!dir) {
    console.error('GLTF_VALIDATOR is not set');
    process.exit(2);
}
const validator = require(path.join(dir, 'node_modules', 'gltf-validator'));

(async () => {
    for (const file of process.argv.slice(2)) {
        const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
            uri: file,
            maxIssues: 50,
        });
        const issues = report.issues;
        console.log(JSON.stringify({
            file,
            validator: report.validatorVersion,
            errors: issues.numErrors,
            warnings: issues.numWarnings,
            infos: issues.numInfos,
            hints: issues.numHints,
            messages: issues.messages.slice(0, 10),
        }));
    }
})().catch((e) => {
    console.error(String(e));
    process.exit(1);
});
