-- Newell's teapot (32 bicubic Bezier patches) and a NURBS surface: evaluated, meshed at two
-- tolerances and rendered with a checker texture and Phong shading.
-- Run: wedge run examples/teapot.lua [out=directory] [tolerance=0.01]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
local pot = teapot()
for _, tol in ipairs{0.1, params.tolerance or 0.01} do
  local m = pot:mesh{tolerance = tol}
  print(string.format("teapot at tolerance %g: %d triangles", tol, #m.triangles))
end
local p, n = pot:eval(0.5, 0.5), pot:normal(0.5, 0.5)
print(string.format("first patch at (0.5, 0.5): (%.4f, %.4f, %.4f), normal (%.3f, %.3f, %.3f)", p[1], p[2], p[3], n[1], n[2], n[3]))

-- A wavy NURBS sheet: 5 x 5 control points, cubic both ways, a heavier weight in the middle.
local grid, weights = {}, {}
for i = 1, 5 do
  grid[i], weights[i] = {}, {}
  for j = 1, 5 do
    grid[i][j] = {i - 3, j - 3, 0.6 * math.sin(i + j)}
    weights[i][j] = (i == 3 and j == 3) and 3 or 1
  end
end
local sheet = nurbs_surface{points = grid, weights = weights, udegree = 3, vdegree = 3}
render{pot, out = out .. "/teapot-phong.png", size = {400, 300}, shading = "phong",
       camera = {eye = {6, -6, 5}, center = {0, 0, 1.2}, up = {0, 0, 1}, fovy = 30},
       lights = {{type = "point", position = {5, -5, 8}, specular = {1, 1, 1}}}}
print("wrote " .. out .. "/teapot-phong.png")
render{sheet, out = out .. "/nurbs-sheet.png", size = {300, 300}, view = "iso", two_side = true, cull = "none"}
print("wrote " .. out .. "/nurbs-sheet.png")
