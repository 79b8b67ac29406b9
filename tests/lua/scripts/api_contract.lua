-- Every name of the Lua contract (../shared/API.md), section by section, in its positional and its
-- table form, each checked against a value worked out by hand or in closed form (never against
-- wedge itself by another name). The same script runs under `wedge run` and under the stock
-- lua5.4 interpreter with `require "wedge"`; it reaches the API only through the table that
-- require returns. Usage: api_contract.lua OUTDIR
local w = require "wedge"
local out = assert(arg and arg[1], "usage: api_contract.lua OUTDIR")
local pi = math.pi
local checked = 0

local function near(got, want, tol, what)
  if not (math.abs(got - want) <= tol) then
    error(string.format("%s: got %.17g, want %.17g (+-%g)", what, got, want, tol), 2)
  end
  checked = checked + 1
end
local function same(got, want, what)
  if got ~= want then error(string.format("%s: got %s, want %s", what, tostring(got), tostring(want)), 2) end
  checked = checked + 1
end
local function near3(p, q, tol, what)
  for k = 1, #q do near(p[k], q[k], tol, what .. "[" .. k .. "]") end
end
local function box_of(s) local b = s:bounds() return b.min, b.max end

-- The API table holds every name the contract fixes.
for _, name in ipairs{"box", "cube", "sphere", "cylinder", "cone", "torus", "tube", "polyhedron", "union",
                      "difference", "intersection", "matrix", "polygon", "circle", "rect", "bezier", "bspline", "nurbs",
                      "catmull_rom", "natural_spline", "extrude", "revolve", "sweep", "loft", "bezier_surface",
                      "nurbs_surface", "revolved_surface", "extruded_surface", "swept_surface", "teapot", "brep",
                      "tolerance", "export", "import", "render", "drawing", "checker", "canvas", "group", "instance",
                      "array", "radial_array", "version", "params"} do
  same(w[name] ~= nil, true, "wedge." .. name)
end
for _, name in ipairs{"identity", "translate", "rotate", "scale", "oblique", "axonometric"} do
  same(type(w.matrix[name]), "function", "wedge.matrix." .. name)
end

-- ## Solids: positional and table forms
near(w.box(1, 2, 3):volume(), 6, 1e-12, "box(x,y,z) volume")
local lo, hi = box_of(w.box(1, 2, 3))
near3(lo, {0, 0, 0}, 0, "box corner at the origin"); near3(hi, {1, 2, 3}, 0, "box far corner")
lo, hi = box_of(w.box{size = {2, 4, 6}, center = true})
near3(lo, {-1, -2, -3}, 1e-12, "box{center=true} min"); near3(hi, {1, 2, 3}, 1e-12, "box{center=true} max")
near(w.cube(2):volume(), 8, 1e-12, "cube(s)")
lo = box_of(w.cube{size = 2, center = true})
near3(lo, {-1, -1, -1}, 1e-12, "cube{center=true}")
-- Curved primitives at a fine tolerance: the inscribed mesh is within a few 1e-4 of the closed form.
w.tolerance(1e-3)
near(w.sphere(1):volume(), 4 / 3 * pi, 4 / 3 * pi * 3e-3, "sphere(1) volume")
lo, hi = box_of(w.sphere{r = 2, center = {1, 2, 3}})
near3(lo, {-1, 0, 1}, 1e-2, "sphere{r=2, center=} min"); near3(hi, {3, 4, 5}, 1e-2, "sphere{r=2, center=} max")
near(w.cylinder(1, 2):volume(), 2 * pi, 2 * pi * 3e-3, "cylinder(r,h)")
lo, hi = box_of(w.cylinder{r = 1, h = 2, center = true})
near(lo[3], -1, 1e-12, "cylinder{center=true} base"); near(hi[3], 1, 1e-12, "cylinder{center=true} top")
lo = box_of(w.cylinder(1, 2))
near(lo[3], 0, 1e-12, "cylinder base at z=0")
near(w.cone{r1 = 1, r2 = 0, h = 3}:volume(), pi, pi * 3e-3, "cone{r1=1, r2=0, h=3}")           -- pi r^2 h / 3
near(w.cone{r1 = 2, r2 = 1, h = 3}:volume(), 7 * pi, 7 * pi * 3e-3, "frustum cone")             -- pi h (R^2+Rr+r^2) / 3
near(w.torus{R = 2, r = 0.5}:volume(), 2 * pi ^ 2 * 2 * 0.25, 5 * 3e-3, "torus{R, r}")         -- 2 pi^2 R r^2
lo, hi = box_of(w.torus{R = 2, r = 0.5})
near(hi[3] - lo[3], 1, 1e-9, "torus lies in the XY plane (height 2r)")
near(w.tube{r_outer = 2, r_inner = 1, h = 1}:volume(), 3 * pi, 3 * pi * 3e-3, "tube")            -- pi (R^2 - r^2) h
same(w.tube{r_outer = 2, r_inner = 1, h = 1}:euler().H, 1, "tube is one through hole")
w.tolerance(0.01)
local tet = w.polyhedron{points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, faces = {{1, 3, 2}, {1, 2, 4}, {1, 4, 3}, {2, 3, 4}}}
near(tet:volume(), 1 / 6, 1e-15, "polyhedron tetrahedron")
same(tet:is_valid(), true, "polyhedron valid")

-- Booleans of unit cubes overlapping by half: volumes by inclusion-exclusion.
local a, b = w.cube(1), w.cube(1):translate(0.5, 0, 0)
near((a + b):volume(), 1.5, 1e-12, "a + b"); near((a - b):volume(), 0.5, 1e-12, "a - b"); near((a * b):volume(), 0.5, 1e-12, "a * b")
near(w.union(w.cube(1), w.cube(1):translate(2, 0, 0), w.cube(1):translate(4, 0, 0)):volume(), 3, 1e-12, "union(a, b, c)")
near(w.union{w.cube(1), w.cube(1):translate(0.5, 0.5, 0)}:volume(), 1.75, 1e-12, "union{a, b}")
near(w.difference(w.cube(2), w.cube(1), w.cube(1):translate(1, 1, 1)):volume(), 6, 1e-12, "difference(a, b, c)")
near(w.intersection(w.cube(2), w.cube(2):translate(1, 0, 0), w.cube(2):translate(0, 1, 0)):volume(), 2, 1e-12, "intersection(a, b, c)")

-- Transforms of a 1 x 2 x 3 box.
local blk = w.box(1, 2, 3)
lo = box_of(blk:translate(1, 2, 3)); near3(lo, {1, 2, 3}, 0, "s:translate")
lo, hi = box_of(blk:rotate(90, {0, 0, 1})); near3(lo, {-2, 0, 0}, 1e-12, "s:rotate(90, z) min"); near3(hi, {0, 1, 3}, 1e-12, "s:rotate(90, z) max")
lo, hi = box_of(w.cube(1):rotate(180, {0, 0, 1}, {1, 0, 0})); near3(lo, {1, -1, 0}, 1e-12, "s:rotate about a pivot")
lo, hi = box_of(blk:rotate_x(90)); near3(lo, {0, -3, 0}, 1e-12, "s:rotate_x(90) min"); near3(hi, {1, 0, 2}, 1e-12, "s:rotate_x(90) max")
lo, hi = box_of(blk:rotate_y(90)); near3(lo, {0, 0, -1}, 1e-12, "s:rotate_y(90) min"); near3(hi, {3, 2, 0}, 1e-12, "s:rotate_y(90) max")
lo, hi = box_of(blk:rotate_z(90)); near3(lo, {-2, 0, 0}, 1e-12, "s:rotate_z(90) min"); near3(hi, {0, 1, 3}, 1e-12, "s:rotate_z(90) max")
near(blk:scale(2):volume(), 48, 1e-12, "s:scale(k)")
near(blk:scale(1, 2, 3):volume(), 36, 1e-12, "s:scale(kx, ky, kz)")
lo, hi = box_of(blk:mirror({1, 0, 0})); near3(lo, {-1, 0, 0}, 0, "s:mirror min"); near3(hi, {0, 2, 3}, 0, "s:mirror max")
near(blk:mirror({1, 0, 0}):volume(), 6, 1e-12, "a mirrored solid keeps its volume (turned inside out would be -6)")
local sheared = w.cube(1):shear{xy = 1}
near(sheared:volume(), 1, 1e-12, "s:shear keeps the volume")
lo, hi = box_of(sheared); near(hi[1] - lo[1], 2, 1e-12, "s:shear{xy=1}: x grows by y")
lo = box_of(blk:transform(w.matrix.translate(5, 0, 0))); near(lo[1], 5, 0, "s:transform(m)")
-- Matrices
near3(w.matrix.identity():apply({1, 2, 3}), {1, 2, 3}, 0, "matrix.identity")
near3(w.matrix.translate(1, 2, 3):apply({0, 0, 0}), {1, 2, 3}, 0, "matrix.translate")
near3(w.matrix.rotate(90, {0, 0, 1}):apply({1, 0, 0}), {0, 1, 0}, 1e-15, "matrix.rotate")
near3(w.matrix.rotate(90, {0, 0, 1}, {1, 0, 0}):apply({0, 0, 0}), {1, -1, 0}, 1e-15, "matrix.rotate about a pivot")
near3(w.matrix.scale(2, 3, 4):apply({1, 1, 1}), {2, 3, 4}, 0, "matrix.scale")
near3(w.matrix.scale(2, 2, 2, {1, 1, 1}):apply({0, 0, 0}), {-1, -1, -1}, 0, "matrix.scale about a fixed point")
local m = w.matrix.translate(1, 0, 0) * w.matrix.scale(2, 2, 2)
near3(m:apply({1, 1, 1}), {3, 2, 2}, 0, "m1 * m2 applies m2 first")
near3(m:inverse():apply({3, 2, 2}), {1, 1, 1}, 1e-15, "m:inverse")

-- ## Profiles, curves and sweeps
near(w.extrude(w.polygon{{0, 0}, {2, 0}, {2, 1}, {0, 1}}, 3):volume(), 6, 1e-12, "polygon{{x,y}...} extruded")
near(w.extrude(w.polygon{points = {{0, 0}, {2, 0}, {0, 2}}}, 1):volume(), 2, 1e-12, "polygon{points=}")
local holed = w.polygon{outer = {{0, 0}, {3, 0}, {3, 3}, {0, 3}}, holes = {{{1, 1}, {1, 2}, {2, 2}, {2, 1}}}}
near(w.extrude(holed, 1):volume(), 8, 1e-12, "polygon{outer=, holes=}")
same(w.extrude(holed, 1):euler().H, 1, "a holed profile extrudes to genus 1")
w.tolerance(1e-3)
near(w.extrude(w.circle(1), 1):volume(), pi, pi * 3e-3, "circle(r) extruded")
w.tolerance(0.01)
near(w.extrude(w.rect(2, 3), 1):volume(), 6, 1e-12, "rect(w, h)")
lo = box_of(w.extrude(w.rect(2, 3, true), 1)); near3(lo, {-1, -1.5, 0}, 1e-12, "rect(w, h, center)")
-- Curves: de Casteljau by hand for B(t) of {0,0},{1,2},{3,0} at t=1/2: (1/4)P0 + (1/2)P1 + (1/4)P2.
near3(w.bezier{{0, 0}, {1, 2}, {3, 0}}:eval(0.5), {1.25, 1}, 1e-15, "bezier{points}:eval")
near3(w.bezier{points = {{0, 0}, {1, 2}, {3, 0}}}:eval(0.5), {1.25, 1}, 1e-15, "bezier{points=}")
near3(w.bezier{{0, 0}, {1, 2}, {3, 0}}:tangent(0), {1 / math.sqrt(5), 2 / math.sqrt(5)}, 1e-12, "c:tangent (unit, along P1 - P0)")
near(w.bezier{{0, 0, 0}, {1, 1, 1}}:length(), math.sqrt(3), 1e-9, "a 3D segment's length")
local bs = w.bspline{points = {{0, 0}, {1, 2}, {3, 2}, {4, 0}, {6, 1}}, degree = 3, knots = {0, 0, 0, 0, 0.5, 1, 1, 1, 1}}
-- Cox-de Boor at the interior knot 1/2: N = 0, 1/4, 1/2, 1/4, 0, so B(1/2) = (P1 + 2 P2 + P3) / 4.
near3(bs:eval(0.5), {2.75, 1.5}, 1e-12, "bspline{points=, degree=, knots=}")
near3(w.bspline{{0, 0}, {1, 0}, {2, 0}, {3, 0}, degree = 3}:eval(0.5), {1.5, 0}, 1e-12, "bspline{points, degree}: a straight control polygon")
-- A quarter circle as a rational quadratic: every point at distance 1.
local arc = w.nurbs{points = {{1, 0}, {1, 1}, {0, 1}}, weights = {1, math.sqrt(2) / 2, 1}, knots = {0, 0, 0, 1, 1, 1}, degree = 2}
for _, t in ipairs{0.1, 0.5, 0.9} do
  local p = arc:eval(t)
  near(p[1] ^ 2 + p[2] ^ 2, 1, 1e-14, "nurbs quarter circle at t=" .. t)
end
near(arc:length(), pi / 2, 1e-7, "nurbs quarter circle length")
-- Catmull-Rom passes through its interior points: at t = k/(n-1) for a non-closed curve.
local cr = w.catmull_rom{{0, 0}, {1, 1}, {2, 0}, {3, 1}, closed = false, tension = 0, bias = 0, continuity = 0}
near3(cr:eval(0), {0, 0}, 1e-12, "catmull_rom starts at its first point")
near3(cr:eval(1), {3, 1}, 1e-12, "catmull_rom ends at its last point")
local ns = w.natural_spline{{0, 0}, {1, 1}, {2, 0}}
near3(ns:eval(0), {0, 0}, 1e-12, "natural_spline start"); near3(ns:eval(1), {2, 0}, 1e-12, "natural_spline end")
near3(ns:eval(0.5), {1, 1}, 1e-9, "natural_spline passes through its middle point")
local pts = w.circle(1):points{tolerance = 1e-3}
for _, p in ipairs(pts) do near(math.sqrt(p[1] ^ 2 + p[2] ^ 2), 1, 1e-12, "c:points{} on the circle") end
-- chordal error of a regular n-gon: 1 - cos(pi/n) <= tolerance
same(1 - math.cos(pi / (#pts - 1)) <= 1e-3, true, "c:points{tolerance=} meets its tolerance")
-- Sweeps
near(w.extrude(w.rect(1, 1, true), 1, {twist = 90, scale = 1}):volume(), 1, 1e-3, "extrude{twist=} keeps the area")
near(w.extrude(w.rect(2, 2, true), 3, {scale = 0.5}):volume(), 7, 1e-9, "extrude{scale=}: a frustum, h (A1 + sqrt(A1 A2) + A2) / 3")
w.tolerance(1e-3)
local ring = w.polygon{{1, 0}, {2, 0}, {2, 1}, {1, 1}}
near(w.revolve(ring):volume(), 2 * pi * 1.5 * 1, 2 * pi * 1.5 * 3e-3, "revolve (Pappus: 2 pi x-bar A)")
near(w.revolve(ring, {angle = 90}):volume(), pi / 2 * 1.5, pi / 2 * 1.5 * 3e-3, "revolve{angle=90}")
lo, hi = box_of(w.revolve(ring)); near(hi[3], 1, 1e-9, "revolve: y becomes z")
near(w.sweep(w.circle(0.1), w.bezier{{0, 0, 0}, {0, 0, 1}, {0, 0, 2}}):volume(), pi * 0.01 * 2, pi * 0.01 * 2 * 3e-3, "sweep along a line")
w.tolerance(0.01)
near(w.loft{profiles = {w.rect(2, 2, true), w.rect(2, 2, true)}, heights = {0, 3}}:volume(), 12, 1e-9, "loft of equal sections: a prism")
near(w.loft{profiles = {w.rect(2, 2, true), w.rect(1, 1, true)}, heights = {0, 3}}:volume(), 7, 1e-9, "loft of squares 2 and 1 (ruled: a frustum)")
near(w.extrude(w.bspline{points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}, degree = 1}, 2):volume(), 2, 1e-12, "a closed curve is a profile")

-- ## Free-form surfaces
local bilinear = w.bezier_surface{{{0, 0, 0}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 1}}}   -- z = u v
near3(bilinear:eval(0.5, 0.5), {0.5, 0.5, 0.25}, 1e-15, "bezier_surface:eval (bilinear)")
local n = bilinear:normal(0.5, 0.5)    -- normal of z = xy at (1/2, 1/2): (-y, -x, 1) normalised
local len = math.sqrt(0.25 + 0.25 + 1)
near(math.abs(n[3]), 1 / len, 1e-12, "S:normal z"); near(math.abs(n[1]), 0.5 / len, 1e-12, "S:normal x")
same(#bilinear:mesh{tolerance = 0.01}.triangles > 0, true, "S:mesh{tolerance=}")
local grid = {}
for i = 1, 4 do grid[i] = {} for j = 1, 4 do grid[i][j] = {i - 1, j - 1, 0} end end
near3(w.nurbs_surface{points = grid, udegree = 3, vdegree = 3}:eval(0.5, 0.5), {1.5, 1.5, 0}, 1e-12, "nurbs_surface of a flat grid")
local rs = w.revolved_surface(w.bezier{{1, 0, 0}, {1, 0, 1}})       -- a unit cylinder's side
local p = rs:eval(0.3, 0.7); near(p[1] ^ 2 + p[2] ^ 2, 1, 1e-12, "revolved_surface: radius 1 everywhere")
p = w.revolved_surface(w.bezier{{1, 0, 0}, {1, 0, 1}}, {angle = 90}):eval(1, 0)
same(p[1] >= -1e-12 and p[2] >= -1e-12, true, "revolved_surface{angle=90} stays in one quadrant")
near3(w.extruded_surface(w.bezier{{1, 0, 0}, {0, 1, 0}}, {0, 0, 2}):eval(0.5, 1), {0.5, 0.5, 2}, 1e-12, "extruded_surface")
same(w.swept_surface(w.circle(0.1), w.bezier{{0, 0, 0}, {0, 0, 1}}) ~= nil, true, "swept_surface")
local teapot = w.teapot()
same(#teapot:mesh{tolerance = 0.05}.triangles > 1000, true, "teapot() meshes (32 patches)")

-- ## Queries
local q = w.box(1, 2, 3)
near(q:area(), 22, 1e-12, "s:area"); near3(q:centroid(), {0.5, 1, 1.5}, 1e-12, "s:centroid")
local I = q:inertia()   -- a box about its centroid: m (b^2 + c^2) / 12 with m = 6
near(I[1][1], 6 * (4 + 9) / 12, 1e-9, "s:inertia Ixx"); near(I[2][2], 6 * (1 + 9) / 12, 1e-9, "Iyy"); near(I[1][2], 0, 1e-9, "Ixy")
local e = q:euler(); same(e.V .. " " .. e.E .. " " .. e.F .. " " .. e.S, "8 12 6 1", "s:euler of a box")
same(q:is_valid(), true, "s:is_valid"); same(q:triangles{tolerance = 0.1}, 12, "s:triangles of a box")
local kinds = {}
for _, f in ipairs(w.cylinder(1, 1):faces()) do kinds[f.surface] = (kinds[f.surface] or 0) + 1 end
same(kinds.plane, 2, "s:faces: a cylinder's two caps"); same(kinds.cylinder ~= nil, true, "s:faces: a cylindrical side")
same(w.cube(1):contains({0.5, 0.5, 0.5}), "inside", "s:contains inside")
same(w.cube(1):contains({2, 0.5, 0.5}), "outside", "s:contains outside")
same(w.cube(1):contains({1, 0.5, 0.5}), "boundary", "s:contains boundary")
local cells = w.cube(1):translate(0.1, 0.1, 0.1):cells{size = 0.25}
same(cells.volume_min <= 1 and 1 <= cells.volume_max, true, "s:cells brackets the volume")

-- ## Low-level B-Rep: a triangular lamina, then a tetrahedron
local br = w.brep()
local v1, f1 = br:mvfs{0, 0, 0}
local _, v2 = br:mev(f1, v1, {1, 0, 0})
local _, v3 = br:mev(f1, v2, {0, 1, 0})
local _, f2 = br:mef(f1, v3, v1)
local c = br:counts(); same(c.V .. c.E .. c.F .. c.S, "3321", "b:mvfs/mev/mef counts")
local _, v4 = br:mev(f1, v1, {0, 0, 1})      -- f1 is the lamina's upper side: the apex rises from it
br:mef(f1, v4, v2); br:mef(f1, v4, v3)
c = br:counts(); same(c.V .. c.E .. c.F .. c.S, "4641", "a tetrahedron by Euler operators")
same(br:validate(), true, "b:validate")
near(br:solid():volume(), 1 / 6, 1e-15, "b:solid() volume")

-- ## Tessellation and files
w.tolerance(0.01); w.tolerance{chordal = 0.01, angle = 15}
for _, ext in ipairs{"stl", "obj", "ply", "off"} do
  local path = out .. "/contract." .. ext
  w.export(w.box(1, 2, 3), path)
  near(w.import(path):volume(), 6, 1e-12, "export/import ." .. ext)
end
w.export(w.box(1, 2, 3), out .. "/contract-ascii.stl", {ascii = true, tolerance = 0.1})
local f = assert(io.open(out .. "/contract-ascii.stl")); same(f:read(5), "solid", "export{ascii=true} writes ASCII STL"); f:close()

-- ## Rendering: the files are PNGs of the asked size
local function png_size(path)
  local fh = assert(io.open(path, "rb")); local head = fh:read(24); fh:close()
  same(head:sub(2, 4), "PNG", path .. " is a PNG")
  return string.unpack(">I4", head, 17), string.unpack(">I4", head, 21)
end
local img = out .. "/contract.png"
w.render{w.box(1, 1, 1), out = img, size = {64, 48}}
local pw, ph = png_size(img); same(pw .. "x" .. ph, "64x48", "render size=")
w.render{w.box(1, 1, 1), out = img, size = {32, 24}, camera = {eye = {5, 5, 5}, center = {0, 0, 0}, up = {0, 0, 1}, fovy = 45, near = 0.1, far = 100}}
w.render{w.box(1, 1, 1), out = img, size = {32, 24}, camera = {projection = "ortho", left = -2, right = 2, bottom = -2, top = 2, near = 0.1, far = 100}}
for _, view in ipairs{"front", "top", "side", "iso", "dimetric", "trimetric", "cavalier", "cabinet", "one_point", "two_point", "three_point", "oblique"} do
  w.render{w.box(1, 1, 1), out = img, size = {32, 24}, view = view}
end
w.render{w.box(1, 1, 1):material{ambient = {0.2, 0.2, 0.2}, diffuse = {0.8, 0.1, 0.1}, specular = {1, 1, 1}, shininess = 20,
                                 emission = {0, 0, 0}, texture = w.checker{n = 8}},
         out = img, size = {32, 24},
         lights = {{type = "point", position = {3, 3, 3}, ambient = {0, 0, 0}, diffuse = {1, 1, 1}, specular = {1, 1, 1}, attenuation = {1, 0, 0}},
                   {type = "directional", direction = {0, 0, -1}},
                   {type = "spot", position = {0, 0, 5}, direction = {0, 0, -1}, cutoff = 45, exponent = 0}},
         ambient = {0.2, 0.2, 0.2}, local_viewer = false, two_side = false, shading = "phong", wireframe = false, cull = "back",
         depth = "less", fog = {start = 1, stop = 10, color = {1, 1, 1}}, antialias = 2, background = {1, 1, 1}}
w.drawing{w.box(1, 2, 3), out = out .. "/contract-sheet.png", size = {80, 60}, views = {"front", "top", "side", "iso"}}
pw, ph = png_size(out .. "/contract-sheet.png"); same(pw .. "x" .. ph, "80x60", "drawing size=")
-- matrix.oblique{angle=, ratio=} shears in the view frame (z towards the viewer): the receding axis
-- (a step away, -z) is drawn at `ratio` of its length at `angle` to the x axis; x and y stay whole.
p = w.matrix.oblique{angle = 30, ratio = 0.5}:apply({0, 0, -1})
near(p[1], 0.5 * math.cos(pi / 6), 1e-12, "matrix.oblique{angle=30, ratio=0.5} receding x")
near(p[2], 0.5 * math.sin(pi / 6), 1e-12, "matrix.oblique{angle=30, ratio=0.5} receding y")
near3(w.matrix.oblique{angle = 30, ratio = 0.5}:apply({1, 1, 0}), {1, 1, 0}, 1e-15, "matrix.oblique keeps the picture plane")
-- matrix.axonometric{} (isometric by default): the three unit axes project to equal lengths.
local iso = w.matrix.axonometric{}
local lens = {}
for k = 1, 3 do
  local u = {0, 0, 0}; u[k] = 1
  local v = iso:apply(u); lens[k] = math.sqrt(v[1] ^ 2 + v[2] ^ 2)
end
near(lens[1], math.sqrt(2 / 3), 1e-12, "isometric x"); near(lens[2], math.sqrt(2 / 3), 1e-12, "isometric y"); near(lens[3], math.sqrt(2 / 3), 1e-12, "isometric z")

-- ## 2D raster algorithms
local cv = w.canvas{width = 50, height = 50, background = {1, 1, 1}}
cv:line{{0, 0}, {49, 49}, algorithm = "bresenham", color = {0, 0, 0}}
near3(cv:pixel(10, 10), {0, 0, 0}, 0, "c:line bresenham sets the diagonal")
cv:line{{0, 49}, {49, 0}, algorithm = "dda", color = {0, 0, 1}}
near3(cv:pixel(10, 39), {0, 0, 1}, 0, "c:line dda sets the anti-diagonal")
cv:circle{center = {25, 25}, radius = 10, color = {1, 0, 0}}
near3(cv:pixel(35, 25), {1, 0, 0}, 0, "c:circle passes through (cx + r, cy)")
cv:polygon{{2, 30}, {12, 30}, {12, 40}, {2, 40}, fill = "even-odd", color = {0, 1, 0}}
near3(cv:pixel(7, 35), {0, 1, 0}, 0, "c:polygon even-odd fills inside")
cv:polygon{{2, 2}, {8, 2}, {8, 8}, {2, 8}, fill = "nonzero", color = {0, 1, 1}}
near3(cv:pixel(5, 5), {0, 1, 1}, 0, "c:polygon nonzero fills inside")
cv:flood_fill{{45, 5}, color = {1, 1, 0}}
near3(cv:pixel(47, 20), {1, 1, 0}, 0, "c:flood_fill fills the region of its seed")
for _, alg in ipairs{"cohen_sutherland", "liang_barsky", "sutherland_hodgman"} do cv:clip{window = {10, 10, 40, 40}, algorithm = alg} end
cv:save(out .. "/contract-canvas.png")
pw, ph = png_size(out .. "/contract-canvas.png"); same(pw .. "x" .. ph, "50x50", "c:save")

-- ## Scenes
local root = w.group()
local arm = w.group{transform = w.matrix.translate(10, 0, 0)}
root:add(arm); arm:add(w.cube(1))
lo, hi = box_of(root); near3(lo, {10, 0, 0}, 1e-12, "a child inherits its parent's transform")
local proto = w.group(); proto:add(w.cube(1))
local inst = w.instance(proto)
proto:add(w.cube(1):translate(0, 0, 5))
lo, hi = box_of(inst); near(hi[3], 6, 1e-12, "instance(x) shares x: a change to x shows in the instance")
local row = w.array{w.cube(1), count = 5, step = {2, 0, 0}}
lo, hi = box_of(row); near(hi[1], 9, 1e-12, "array{count=5, step=2}: the last copy at x = 8")
same(#row:table(), 5, "array:table() lists five instances")
local wheel = w.radial_array{w.cube{size = 0.2, center = true}, count = 4, axis = {0, 0, 1}, radius = 5}
lo, hi = box_of(wheel); near(hi[1], 5.1, 1e-12, "radial_array radius"); near(lo[2], -5.1, 1e-12, "radial_array quarter turns")
local rows = wheel:table()
near(rows[2].rotation[3], 90, 1e-9, "g:table() rotation of the second spoke"); near3(rows[1].translation, {5, 0, 0}, 1e-12, "g:table() translation")
w.export(root, out .. "/contract-scene.obj")
near(w.import(out .. "/contract-scene.obj"):volume(), 1, 1e-12, "export(scene)")
w.render{root, out = out .. "/contract-scene.png", size = {32, 24}}

print("api contract: ok, " .. checked .. " checks")
