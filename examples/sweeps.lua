-- Sweeps and lofts: a profile moved through space makes a solid. A twisted column (extrude with
-- twist and scale), a goblet (revolve of a spline profile), a coil spring (sweep of a circle along
-- a helix, with rotation-minimising frames) and a tapered duct (a loft between two sections).
-- Each solid's volume is checked against a closed form (Pappus, the prism rule, the circle's area
-- times the path's length) before it is drawn.
-- Run: wedge run examples/sweeps.lua [out=directory] [turns=4] [twist=90]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
local turns = params.turns or 4
local twist = params.twist or 90
tolerance(0.005)
local function check(name, got, want, rel)
  print(string.format("%-18s volume %9.5f, closed form %9.5f", name, got, want))
  assert(math.abs(got - want) <= rel * want, name .. ": the volume is off the closed form")
end

-- A square column turned by `twist` degrees over its height: every section is the same square, so
-- the volume is the prism's, area x height.
local column = extrude(rect(1, 1, true), 3, {twist = twist})
check("twisted column", column:volume(), 1 * 3, 1e-3)

-- A goblet: revolve a closed profile (x is the radius, y becomes z). Pappus: V = 2 pi x-bar A,
-- here for a polygon profile, whose area and centroid are worked out by the shoelace formula.
local profile = {{0, 0}, {1.2, 0}, {1.2, 0.15}, {0.25, 0.3}, {0.2, 1.6}, {1.1, 2.2}, {1.3, 3.4}, {1.2, 3.4},
                 {1.0, 2.35}, {0.0, 2.0}}
local area, mx = 0, 0
for i = 1, #profile do
  local p, q = profile[i], profile[i % #profile + 1]
  local c = p[1] * q[2] - q[1] * p[2]
  area, mx = area + c / 2, mx + (p[1] + q[1]) * c / 6
end
local goblet = revolve(polygon(profile))
check("goblet", goblet:volume(), 2 * math.pi * mx, 5e-3)

-- A coil spring: a circle of radius 0.12 swept along a helix of radius 1 and pitch 0.5. The
-- volume is the circle's area times the path's length (Pappus-Guldinus for a sweep whose radius
-- of curvature stays above the circle's radius).
local pts = {}
local steps = 24 * turns
for k = 0, steps do
  local t = k / steps * turns * 2 * math.pi
  pts[#pts + 1] = {math.cos(t), math.sin(t), 0.5 * t / (2 * math.pi)}
end
local helix = catmull_rom{points = pts}
local spring = sweep(circle(0.12), helix)
check("spring", spring:volume(), math.pi * 0.12 ^ 2 * helix:length(), 1e-2)

-- A tapered duct: a loft from a square of side 2 at z=0 to one of side 1 at z=2, each given as eight
-- points; the ruled loft between two similar squares is a frustum.
local function square(s, turn)
  local ring = {}
  for k = 0, 7 do
    local a = math.rad(turn + 45 * k)
    local r = s / math.max(math.abs(math.cos(math.rad(45 * k))), math.abs(math.sin(math.rad(45 * k))))
    ring[#ring + 1] = {r * math.cos(a), r * math.sin(a)}
  end
  return polygon(ring)
end
local duct = loft{profiles = {square(1, 0), square(0.5, 0)}, heights = {0, 2}}
check("duct", duct:volume(), 2 * (4 + 2 + 1) / 3, 1e-9)   -- h (A1 + sqrt(A1 A2) + A2) / 3, A = 4, 1

local shelf = group{
  instance(column:material{diffuse = {0.85, 0.55, 0.2}}, {transform = matrix.translate(0, 0, 0)}),
  instance(goblet:material{diffuse = {0.6, 0.75, 0.9}, specular = {0.6, 0.6, 0.6}, shininess = 40},
           {transform = matrix.translate(3.2, 0, 0)}),
  instance(spring:material{diffuse = {0.7, 0.7, 0.72}, specular = {0.8, 0.8, 0.8}, shininess = 60},
           {transform = matrix.translate(6.4, 0, 0)}),
  instance(duct:material{diffuse = {0.45, 0.7, 0.4}}, {transform = matrix.translate(9.6, 0, 0)}),
}
render{shelf, out = out .. "/sweeps.png", size = {800, 300}, shading = "phong",
       camera = {eye = {4.8, -14, 7}, center = {4.8, 0, 1.4}, up = {0, 0, 1}, fovy = 24}}
print("wrote " .. out .. "/sweeps.png")
print("wrote " .. out .. "/spring.stl (" .. export(spring, out .. "/spring.stl") .. " triangles)")
