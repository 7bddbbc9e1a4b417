// Converts the npm package bunny@1.0.1 ({positions, cells}) to an OBJ on stdout.
// Usage: node bunny_to_obj.js PACKAGE_DIR
const pkg = require(require('path').resolve(process.argv[2]));
const out = ['# Stanford bunny, from the npm package bunny@1.0.1'];
for (const p of pkg.positions) out.push(`v ${p[0]} ${p[1]} ${p[2]}`);
for (const c of pkg.cells) out.push(`f ${c[0] + 1} ${c[1] + 1} ${c[2] + 1}`);
process.stdout.write(out.join('\n') + '\n');
