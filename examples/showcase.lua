-- wedge showcase: the main example. Builds a bracket from B-Rep primitives (every face made by
-- Euler operators), checks it, exports it as STL and renders it, then renders Newell's teapot.
-- Run: wedge run examples/showcase.lua [output-directory]
local out = arg[1] or "out"
os.execute("mkdir -p '" .. out .. "'")
print("wedge " .. version())

-- A rotation about a pivot keeps the pivot fixed.
local p = matrix.rotate(30, {0, 0, 1}, {1, 2, 3}):apply({1, 2, 3})
print(string.format("rotate 30 deg about z through (1,2,3): pivot -> (%g, %g, %g)", p[1], p[2], p[3]))

-- A plate with a square window, extruded through Euler operators, and a pyramid on a block.
local plate = extrude(polygon{outer = {{0, 0}, {6, 0}, {6, 4}, {0, 4}},
                              holes = {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}}}, 1)
local e = plate:euler()
print(string.format("plate: V=%d E=%d F=%d R=%d H=%d S=%d  (V-E+F-R+2H-2S = %d)",
  e.V, e.E, e.F, e.R, e.H, e.S, e.V - e.E + e.F - e.R + 2 * e.H - 2 * e.S))
print(string.format("plate: volume %.3f, area %.3f, valid %s", plate:volume(), plate:area(), tostring(plate:is_valid())))

local spire = extrude(rect(1.5, 1.5, true), 2, {scale = 0}):translate(4.5, 2, 1)
local c = spire:centroid()
print(string.format("spire: volume %.4f (a pyramid: area*h/3 = %.4f), centroid z %.3f", spire:volume(), 1.5 * 1.5 * 2 / 3, c[3]))

local n = export(plate, out .. "/plate.stl")
print("wrote " .. out .. "/plate.stl (" .. n .. " triangles)")

render{plate:material{diffuse = {0.8, 0.5, 0.2}, specular = {0.4, 0.4, 0.4}, shininess = 30},
       out = out .. "/plate.png", size = {640, 480},
       camera = {eye = {10, -8, 9}, center = {3, 2, 0.5}, up = {0, 0, 1}, fovy = 35},
       lights = {{type = "directional", direction = {-0.4, 0.6, -1}}}}
print("wrote " .. out .. "/plate.png")

render{spire:material{diffuse = {0.3, 0.5, 0.9}}, out = out .. "/spire.png", size = {320, 320}, view = "iso"}
print("wrote " .. out .. "/spire.png")

render{teapot(), out = out .. "/teapot.png", size = {640, 480}, shading = "phong",
       camera = {eye = {6, -6, 5}, center = {0, 0, 1.2}, up = {0, 0, 1}, fovy = 30},
       lights = {{type = "point", position = {5, -5, 8}}}}
print("wrote " .. out .. "/teapot.png")

-- A multi-view orthographic sheet of the plate: front, top, side and isometric views.
drawing{plate:material{diffuse = {0.8, 0.5, 0.2}}, out = out .. "/plate-views.png", size = {640, 480}}
print("wrote " .. out .. "/plate-views.png")
