-- wedge curves and free-form surfaces: every constructor of API.md's "Profiles, curves and sweeps"
-- and "Free-form surfaces" sections, with a number printed for each.
-- Run: wedge run examples/surfaces.lua [out=directory]
local function fmt(p) return string.format("(%.4f, %.4f%s)", p[1], p[2], p[3] and string.format(", %.4f", p[3]) or "") end

-- Curves: parameters run over [0, 1] for every kind.
local c = circle(2)
print("circle(2): length " .. string.format("%.12f", c:length()) .. " (4 pi = " .. string.format("%.12f", 4 * math.pi) .. ")")
print("  polyline within 0.001: " .. #c:points{tolerance = 0.001} .. " points")
local b = bezier{{0, 0}, {1, 2}, {3, 2}, {4, 0}}
print("bezier at 0.5: " .. fmt(b:eval(0.5)) .. ", tangent " .. fmt(b:tangent(0.5)))
local data = {{0, 0}, {1, 2}, {2, 2.5}, {4, 0}, {5, 1}}
print("natural_spline through 5 points, length " .. string.format("%.4f", natural_spline{data}:length()))
local cr = catmull_rom{data, closed = true, tension = 0.2}
print("closed Kochanek-Bartels spline is closed: " .. tostring(cr:closed()))
local helix = {}
for i = 0, 40 do helix[#helix + 1] = {math.cos(i / 4), math.sin(i / 4), i / 20} end
local path = bspline{helix, degree = 3}
print("3D B-spline of 41 control points: length " .. string.format("%.4f", path:length()))

-- Surfaces: (u, v) in [0, 1] x [0, 1]; S:mesh returns a table of vertices/normals/uvs/triangles.
local vase = revolved_surface(natural_spline{{{1, 0}, {1.5, 1}, {0.8, 2}, {1.2, 3}}})
local m = vase:mesh{tolerance = 0.01}
print("revolved vase: " .. #m.vertices .. " vertices, " .. #m.triangles .. " triangles at tolerance 0.01")
local tube = swept_surface(circle(0.1), path)
print("tube swept along the helix: point at (0.25, 0.5) " .. fmt(tube:eval(0.25, 0.5)))
local pot = teapot()
local pm = pot:mesh{tolerance = 0.01}
print("teapot: " .. pot:patches() .. " patches, " .. #pm.triangles .. " triangles at tolerance 0.01")
print("  lid knob top " .. fmt(pot:eval(0, 0, 21)) .. ", normal there " .. fmt(pot:normal(0, 0, 21)))

-- The vase, the tube along its helix and the teapot side by side, as one scene.
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
local shelf = group{
  group{vase, material = {diffuse = {0.55, 0.7, 0.9}, specular = {0.5, 0.5, 0.5}, shininess = 30}},
  group{tube, transform = matrix.translate(3.5, 0, 0), material = {diffuse = {0.85, 0.55, 0.2}}},
  group{pot, transform = matrix.translate(8, 0, 0) * matrix.scale(0.6, 0.6, 0.6), material = {diffuse = {0.8, 0.3, 0.3}}},
}
render{shelf, out = out .. "/surfaces.png", size = {640, 280}, shading = "phong", two_side = true, cull = "none",
       camera = {eye = {4.5, -13, 6}, center = {4.5, 0, 1.4}, up = {0, 0, 1}, fovy = 30}}
print("wrote " .. out .. "/surfaces.png")
