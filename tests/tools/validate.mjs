// Prints the Khronos glTF validator's report of each file named on the
// command line as one JSON line: {"file": ..., "issues": [{"code", "severity", "pointer"}]}.
// External resources are not loaded: the files the tests make are self-contained.
import { readFileSync } from "node:fs";
import validator from "gltf-validator";

for (const file of process.argv.slice(2)) {
  const data = new Uint8Array(readFileSync(file));
  const report = await validator.validateBytes(data, {
    uri: file,
    maxIssues: 0,
    externalResourceFunction: () => Promise.reject(new Error("external resources are not read")),
  });
  const issues = report.issues.messages.map((m) => ({
    code: m.code,
    severity: m.severity,
    pointer: m.pointer ?? "",
  }));
  console.log(JSON.stringify({ file, issues }));
}
