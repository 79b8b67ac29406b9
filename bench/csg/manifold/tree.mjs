// Manifold (manifold-3d from npm, WASM) on bench_tree's models, built with Manifold's own
// primitives and its lazy CSG tree, with circles cut into as many segments as wedge's tessellator
// gives them at the same tolerance (chordal 0.01, angle 15 degrees: the larger of the two counts).
//
//   node tree.mjs [repeats] [bosses per side, default 20]
//
// Prints one JSON line per model: median ms (model built and its mesh forced), triangles, volume.
import Module from 'manifold-3d';

const repeats = Math.max(1, Number(process.argv[2] ?? 3));
const n = Math.max(1, Number(process.argv[3] ?? 20));

const wasm = await Module();
wasm.setup();
const {Manifold} = wasm;

const chordal = 0.01, angle = 15;
const segments = r => Math.max(Math.ceil(Math.PI / Math.acos(1 - chordal / r)), Math.ceil(360 / angle));
const cylinder = (r, h, [x, y, z]) => Manifold.cylinder(h, r, r, segments(r)).translate([x, y, z]);

function plate() {
  const body = [Manifold.cube([2 * n + 2, 2 * n + 2, 2])];
  const boss = Manifold.difference(cylinder(0.6, 2, [0, 0, 1.5]), cylinder(0.3, 3, [0, 0, 1]));
  const drill = cylinder(0.2, 5, [0, 0, -1]);
  const drills = [];
  for (let i = 0; i < n; ++i)
    for (let j = 0; j < n; ++j) {
      body.push(boss.translate([2 + 2 * i, 2 + 2 * j, 0]));
      drills.push(drill.translate([2 + 2 * i, 2 + 2 * j, 0]));
    }
  return Manifold.difference([Manifold.union(body), ...drills]);
}

function gear() {
  const parts = [cylinder(10, 2, [0, 0, 0])];
  const tooth = Manifold.cube([1.6, 0.8, 2]).translate([9.5, -0.4, 0]);
  for (let k = 0; k < 60; ++k) parts.push(tooth.rotate([0, 0, 6 * k]));
  const ops = [Manifold.union(parts), cylinder(2, 4, [0, 0, -1])];
  for (let k = 0; k < 6; ++k) ops.push(cylinder(1.5, 4, [6 * Math.cos(k * Math.PI / 3), 6 * Math.sin(k * Math.PI / 3), -1]));
  return Manifold.difference(ops);
}

for (const [name, make] of [['plate of drilled bosses', plate], ['gear, 60 teeth, drilled', gear]]) {
  const times = [];
  let triangles = 0, volume = 0, status = '';
  for (let r = 0; r < repeats; ++r) {
    const t0 = process.hrtime.bigint();
    const m = make();
    const mesh = m.getMesh();  // forces the lazy CSG tree
    times.push(Number(process.hrtime.bigint() - t0) / 1e6);
    triangles = mesh.triVerts.length / 3;
    volume = m.volume();
    status = String(m.status()?.value ?? m.status());
    m.delete();
  }
  times.sort((a, b) => a - b);
  console.log(JSON.stringify({model: name, bosses: n * n, ms: times[Math.floor(times.length / 2)], runs: times.length, triangles, volume, status}));
}
