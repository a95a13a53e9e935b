// Converts the npm package `bunny` (positions/cells arrays) into a Wavefront OBJ on stdout.
// Usage: node volumes/make_bunny_obj.js PATH/TO/UNPACKED/bunny/package > volumes/bunny.obj
// OBJ indices are 1-based; the package's cells are 0-based triangles.
"use strict";
const path = require("path");
const packageDir = process.argv[2];
if (!packageDir) {
  console.error("usage: node make_bunny_obj.js PACKAGE_DIR > bunny.obj");
  process.exit(1);
}
const bunny = require(path.resolve(packageDir));
const meta = require(path.resolve(packageDir, "package.json"));
const lines = [
  `# Stanford bunny (Stanford 3D Scanning Repository) from the npm package ${meta.name}@${meta.version}` +
    ` (licence: ${meta.license})`,
  `# converted by volumes/make_bunny_obj.js: ${bunny.positions.length} vertices, ` +
    `${bunny.cells.length} triangles`,
];
for (const p of bunny.positions) lines.push(`v ${p[0]} ${p[1]} ${p[2]}`);
for (const c of bunny.cells) lines.push(`f ${c.map((i) => i + 1).join(" ")}`);
process.stdout.write(lines.join("\n") + "\n");
