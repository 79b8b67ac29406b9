-- A humanoid figure of ellipsoids and cylinders as a scene graph: one unit sphere and one unit
-- cylinder surface are the prototypes, every body part an instance of them scaled into shape, the
-- limbs hung from joints (groups) so that a turned shoulder carries the elbow and hand with it.
-- Run: wedge run examples/humanoid.lua [shoulder=60] [elbow=30] [hip=20] [knee=-30] [out=directory]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")

-- The prototypes: a unit sphere (a semicircle revolved: x is the radius, y becomes z) and a unit
-- cylinder wall along +z (a circle extruded).
local r2 = math.sqrt(0.5)
local semicircle = nurbs{points = {{0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}},
                         weights = {1, r2, 1, r2, 1}, knots = {0, 0, 0, 0.5, 0.5, 1, 1, 1}, degree = 2}
local sphere_proto = group{name = "ellipsoid"}
sphere_proto:add(revolved_surface(semicircle))
local cylinder_proto = group{name = "cylinder"}
cylinder_proto:add(extruded_surface(circle(1), {0, 0, 1}))

local skin = {diffuse = {0.9, 0.75, 0.6}, ambient = {0.9, 0.75, 0.6}}
local cloth = {diffuse = {0.25, 0.35, 0.7}, ambient = {0.25, 0.35, 0.7}, specular = {0.3, 0.3, 0.3}, shininess = 20}

local function ellipsoid(rx, ry, rz, at, material)
  return instance(sphere_proto, {transform = matrix.translate(at[1], at[2], at[3]) * matrix.scale(rx, ry, rz), material = material})
end
local function cylinder(r, h, at, material)
  return instance(cylinder_proto, {transform = matrix.translate(at[1], at[2], at[3]) * matrix.scale(r, r, h), material = material})
end

-- A limb hanging down (-z) from a joint: upper part, a joint, lower part, end.
local function limb(name, side, upper, lower, r, bend1, bend2, material, end_part)
  local top = group{name = name, transform = matrix.translate(side, 0, 0) * matrix.rotate(bend1, "x")}
  top:add(cylinder(r, upper, {0, 0, -upper}, material), ellipsoid(r * 1.1, r * 1.1, r * 1.1, {0, 0, 0}, material))
  local low = group{name = name .. "_lower", transform = matrix.translate(0, 0, -upper) * matrix.rotate(bend2, "x")}
  low:add(ellipsoid(r, r, r, {0, 0, 0}, material), cylinder(r * 0.9, lower, {0, 0, -lower}, material), end_part)
  top:add(low)
  return top
end

local shoulder, elbow = params.shoulder or 60, params.elbow or 30
local hip, knee = params.hip or 20, params.knee or -30
local body = group{name = "body", transform = matrix.translate(0, 0, 3.4)}
body:add(ellipsoid(0.55, 0.35, 0.8, {0, 0, 0.5}, cloth))           -- torso
body:add(ellipsoid(0.3, 0.3, 0.38, {0, 0, 1.75}, skin))            -- head
body:add(cylinder(0.12, 0.3, {0, 0, 1.2}, skin))                   -- neck
local hand = ellipsoid(0.13, 0.08, 0.18, {0, 0, -1.05}, skin)
local foot = ellipsoid(0.15, 0.3, 0.1, {0, -0.15, -1.35}, cloth)
body:add(limb("left_arm", 0.7, 0.8, 0.85, 0.11, -shoulder, -elbow, skin, hand))
body:add(limb("right_arm", -0.7, 0.8, 0.85, 0.11, shoulder / 3, -elbow / 3, skin, hand))
body:add(limb("left_leg", 0.25, 1.3, 1.3, 0.16, -hip, -knee, cloth, foot))
body:add(limb("right_leg", -0.25, 1.3, 1.3, 0.16, hip, 0, cloth, foot))
local figure = group{name = "figure", body}

print(string.format("%d parts from 2 prototypes", #figure:table()))
render{figure, out = out .. "/humanoid.png", size = {400, 500}, view = {"three_point", distance = 4},
       cull = "none", two_side = true, lights = {{type = "directional", direction = {-0.4, 0.8, -0.6}}}}
print("wrote " .. out .. "/humanoid.png")
