// Manifold (manifold-3d from npm, its WASM build, serial), driven by bench_boolean: reads the
// operands and the recipe bench_boolean wrote to a folder, times the recipe, writes the result
// mesh back for bench_boolean to check, and prints one JSON line.
//
//   node run.mjs <folder> <repeats>
//
// <folder>/recipe.json: {"operands": N, "steps": [{"op": "union"|"intersection"|"difference",
// "inputs": [i, ...]}, ...]}, input -1 meaning the previous step's result; <folder>/opK.bin:
// uint32 vertex count, uint32 triangle count, then the positions (float64 x 3) and the triangles
// (uint32 x 3). The result goes to <folder>/out.bin in the same form.
//
// Manifold's JS meshes hold float32 positions: the operands are rounded to float32 on the way
// in (bench_boolean reports the volume Manifold's output has as it comes back).
import Module from 'manifold-3d';
import fs from 'node:fs';
import path from 'node:path';

const [folder, repeatsArg] = process.argv.slice(2);
const repeats = Math.max(1, Number(repeatsArg ?? 5));
const recipe = JSON.parse(fs.readFileSync(path.join(folder, 'recipe.json'), 'utf8'));

function readMesh(file) {
  const buf = fs.readFileSync(file);
  const nv = buf.readUInt32LE(0), nt = buf.readUInt32LE(4);
  const pos = new Float64Array(buf.buffer.slice(buf.byteOffset + 8, buf.byteOffset + 8 + 24 * nv));
  const tri = new Uint32Array(buf.buffer.slice(buf.byteOffset + 8 + 24 * nv, buf.byteOffset + 8 + 24 * nv + 12 * nt));
  return {pos: Float32Array.from(pos), tri};
}

function writeMesh(file, mesh) {
  const nv = mesh.vertProperties.length / mesh.numProp, nt = mesh.triVerts.length / 3;
  const buf = Buffer.alloc(8 + 24 * nv + 12 * nt);
  buf.writeUInt32LE(nv, 0);
  buf.writeUInt32LE(nt, 4);
  const pos = new Float64Array(3 * nv);
  for (let v = 0; v < nv; ++v)
    for (let k = 0; k < 3; ++k) pos[3 * v + k] = mesh.vertProperties[v * mesh.numProp + k];
  Buffer.from(pos.buffer).copy(buf, 8);
  Buffer.from(new Uint32Array(mesh.triVerts).buffer).copy(buf, 8 + 24 * nv);
  // Written whole, then renamed into place.
  fs.writeFileSync(file + '.tmp', buf);
  fs.renameSync(file + '.tmp', file);
}

const wasm = await Module();
wasm.setup();
const {Manifold, Mesh} = wasm;

const inputs = [];
for (let k = 0; k < recipe.operands; ++k) inputs.push(readMesh(path.join(folder, `op${k}.bin`)));

function once() {
  const made = [];
  const operands = inputs.map(({pos, tri}) => {
    const m = new Manifold(new Mesh({numProp: 3, vertProperties: pos, triVerts: tri}));
    made.push(m);
    return m;
  });
  let previous = null;
  for (const step of recipe.steps) {
    const args = step.inputs.map(i => (i < 0 ? previous : operands[i]));
    const r = args.length === 2 ? Manifold[step.op](args[0], args[1]) : Manifold[step.op](args);
    made.push(r);
    previous = r;
  }
  const mesh = previous.getMesh();  // forces the lazy CSG tree
  const status = previous.status();
  for (const m of made) m.delete();
  return {mesh, status};
}

const times = [];
let last = null;
for (let r = 0; r < repeats; ++r) {
  last = null;  // the previous result released first, as bench_boolean does for every engine
  const t0 = process.hrtime.bigint();
  last = once();
  times.push(Number(process.hrtime.bigint() - t0) / 1e6);
  if (times[0] > 20000) break;  // a slow case runs once
}
times.sort((a, b) => a - b);
const n = times.length;
const median = n % 2 ? times[(n - 1) / 2] : (times[n / 2 - 1] + times[n / 2]) / 2;
writeMesh(path.join(folder, 'out.bin'), last.mesh);
console.log(JSON.stringify({
  ms: median,
  runs: n,
  triangles: last.mesh.triVerts.length / 3,
  status: String(last.status?.value ?? last.status),
  maxrss_kb: process.resourceUsage().maxRSS,
}));
