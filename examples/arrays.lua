-- Arrays of instances: a row, a grid (an array of arrays) and a ring (radial_array), each a scene
-- group that shares one prototype; exported as one mesh and as one file per part.
-- Run: wedge run examples/arrays.lua [out=directory] [teeth=24]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
local teeth = params.teeth or 24

local post = box{size = {0.4, 0.4, 1.5}}:material{diffuse = {0.7, 0.7, 0.75}}
local fence = array{post, count = 8, step = {1, 0, 0}}
local grid = array{array{box(0.6, 0.6, 0.3):material{diffuse = {0.3, 0.6, 0.3}}, count = 5, step = {1, 0, 0}},
                   count = 3, step = {0, 1, 0}, transform = matrix.translate(1, 2, 0)}
-- a gear-like ring: teeth around a hub
local tooth = box{size = {0.6, 0.3, 0.5}}:translate(0, -0.15, 0):material{diffuse = {0.85, 0.6, 0.2}}
local ring = radial_array{tooth, count = teeth, radius = 2, transform = matrix.translate(3, -3.5, 0), name = "gear"}
ring:add(extrude(polygon{outer = (function()
  local pts = {}
  for k = 0, 47 do pts[#pts + 1] = {2.05 * math.cos(k * math.pi / 24), 2.05 * math.sin(k * math.pi / 24)} end
  return pts end)()}, 0.5):material{diffuse = {0.85, 0.6, 0.2}})

local yard = group{fence, grid, ring}
print(string.format("%d parts in the yard, %d teeth", #yard:table(), teeth))
render{yard, out = out .. "/arrays.png", size = {640, 480}, view = {"two_point", angle = 35}}
print("wrote " .. out .. "/arrays.png")
print("wrote " .. out .. "/arrays.obj (" .. export(yard, out .. "/arrays.obj") .. " triangles)")
local files = export(fence, out .. "/fence-post.stl", {split = true})
print("wrote " .. #files .. " files: " .. files[1] .. " ... " .. files[#files])
