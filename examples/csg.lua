-- Constructive solid geometry: the classic CSG figure (a cube intersected with a sphere, less three
-- cylinders along the axes) and a drilled bracket, by the exact boolean engine. Each result is
-- checked before it is drawn: the figure is one valid shell of genus 5 (three crossing bores), the
-- bracket's volume is the closed form's within the tessellation's error.
-- Run: wedge run examples/csg.lua [out=directory] [holes=4]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
local holes = params.holes or 4
tolerance(0.01)

-- The classic figure: (cube * sphere) - (cylinder_x + cylinder_y + cylinder_z).
local cube_ = cube{size = 2, center = true}:material{diffuse = {0.85, 0.25, 0.2}}
local ball = sphere(1.3):material{diffuse = {0.2, 0.45, 0.85}}
local function bar(axis)
  local c = cylinder{r = 0.55, h = 3, center = true}:material{diffuse = {0.3, 0.7, 0.3}}
  if axis == "x" then return c:rotate_y(90) elseif axis == "y" then return c:rotate_x(90) end
  return c
end
local figure = cube_ * ball - (bar("x") + bar("y") + bar("z"))
local e = figure:euler()
assert(figure:is_valid() and e.S == 1 and e.H == 5, "the classic figure should be one valid shell of genus 5")
print(string.format("classic figure: volume %.4f, V=%d E=%d F=%d H=%d S=%d, valid %s",
                    figure:volume(), e.V, e.E, e.F, e.H, e.S, tostring(figure:is_valid())))
render{figure, out = out .. "/csg-figure.png", size = {400, 400}, view = "iso", shading = "phong"}
print("wrote " .. out .. "/csg-figure.png")
-- The CSG tree as a picture: its leaves, the intermediate nodes and the result, side by side.
local tree = group{name = "csg tree"}
local nodes = {cube_, ball, cube_ * ball, bar("x") + bar("y") + bar("z"), figure}
for i, node in ipairs(nodes) do tree:add(instance(node, {transform = matrix.translate(3.2 * (i - 1), 0, 0)})) end
render{tree, out = out .. "/csg-tree.png", size = {800, 240}, shading = "phong",
       camera = {eye = {6.4, -16, 7}, center = {6.4, 0, 0}, up = {0, 0, 1}, fovy = 18}}
print("wrote " .. out .. "/csg-tree.png")

-- A bracket: a plate with `holes` drilled holes and a boss, by union and difference.
local plate = box(8, 4, 0.5)
local boss = cylinder(1, 2):translate(4, 2, 0)
local drills = {}
for k = 1, holes do drills[#drills + 1] = cylinder(0.3, 1):translate(8 * k / (holes + 1), 0.8, -0.25) end
drills[#drills + 1] = cylinder(0.5, 3):translate(4, 2, -0.5)
local bracket = difference(plate + boss, table.unpack(drills))
-- volume in closed form: plate + boss above the plate - the holes through the plate - the bore
local want = 8 * 4 * 0.5 + math.pi * 1 ^ 2 * 1.5 - holes * math.pi * 0.3 ^ 2 * 0.5 - math.pi * 0.5 ^ 2 * 2
assert(math.abs(bracket:volume() - want) < 2e-3 * want, "the bracket's volume is off the closed form")
print(string.format("bracket: volume %.4f (closed form %.4f for the round holes), genus %d",
                    bracket:volume(), want, bracket:euler().H))
render{bracket:material{diffuse = {0.75, 0.75, 0.8}, specular = {0.5, 0.5, 0.5}, shininess = 30},
       out = out .. "/csg-bracket.png", size = {480, 320}, view = {"two_point", angle = 30}, shading = "phong"}
print("wrote " .. out .. "/csg-bracket.png")
print("wrote " .. out .. "/csg-bracket.stl (" .. export(bracket, out .. "/csg-bracket.stl") .. " triangles)")
