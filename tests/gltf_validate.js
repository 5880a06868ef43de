// The Khronos glTF validator on one file and the resources it names: exits 1 on any error.
// usage: node gltf_validate.js VALIDATOR_DIR FILE.gltf
const fs = require('fs'), path = require('path');
const validator = require(process.argv[2]);
const file = process.argv[3];
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
  uri: file,
  externalResourceFunction: (uri) => new Promise((resolve, reject) => {
    fs.readFile(path.join(path.dirname(file), decodeURIComponent(uri)), (err, data) => err ? reject(err.toString()) : resolve(new Uint8Array(data)));
  }),
}).then((report) => { console.log(JSON.stringify(report.issues, null, 1)); process.exit(report.issues.numErrors ? 1 : 0); })
  .catch((e) => { console.error(e); process.exit(2); });
