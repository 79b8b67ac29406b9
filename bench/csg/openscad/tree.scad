// bench_tree's models for OpenSCAD 2021 (Debian `openscad`, CGAL Nef polyhedra), with circles cut
// into as many segments as wedge's tessellator gives them at chordal 0.01, angle 15 degrees.
//
//   openscad -o out.stl -D n=20 -D 'model="plate"' tree.scad     (model "plate" or "gear")
n = 20;
model = "plate";
function segs(r) = max(ceil(180 / acos(1 - 0.01 / r)), 24);
module cyl(r, h, p) translate(p) cylinder(r = r, h = h, $fn = segs(r));
module boss() difference() { cyl(0.6, 2, [0, 0, 1.5]); cyl(0.3, 3, [0, 0, 1]); }
module plate() difference() {
  union() {
    cube([2 * n + 2, 2 * n + 2, 2]);
    for (i = [0:n - 1], j = [0:n - 1]) translate([2 + 2 * i, 2 + 2 * j, 0]) boss();
  }
  for (i = [0:n - 1], j = [0:n - 1]) translate([2 + 2 * i, 2 + 2 * j, 0]) cyl(0.2, 5, [0, 0, -1]);
}
module gear() difference() {
  union() {
    cyl(10, 2, [0, 0, 0]);
    for (k = [0:59]) rotate([0, 0, 6 * k]) translate([9.5, -0.4, 0]) cube([1.6, 0.8, 2]);
  }
  cyl(2, 4, [0, 0, -1]);
  for (k = [0:5]) cyl(1.5, 4, [6 * cos(60 * k), 6 * sin(60 * k), -1]);
}
if (model == "plate") plate(); else gear();
