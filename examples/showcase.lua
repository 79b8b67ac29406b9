-- wedge showcase: the main example. It grows with every feature that lands.
-- Run: wedge run examples/showcase.lua [output-directory]
local out = arg[1] or "out"

print("wedge " .. version())

-- Transforms (kernel): a rotation about a pivot keeps the pivot fixed.
local pivot = {1, 2, 3}
local m = matrix.rotate(30, {0, 0, 1}, pivot)
local p = m:apply(pivot)
print(string.format("rotate 30 deg about z through (1,2,3): pivot -> (%.3f, %.3f, %.3f)", p[1], p[2], p[3]))
local q = (matrix.translate(1, 0, 0) * matrix.rotate_z(90)):apply({1, 0, 0})
print(string.format("T(1,0,0) * Rz(90) applied to (1,0,0) = (%g, %g, %g)", q[1], q[2], q[3]))

-- Solids, mesh export and rendering arrive with the B-Rep, tessellation and rasterizer issues;
-- until then this example says so instead of writing files.
local have = function(name) return rawget(_G, name) ~= nil end
if have("box") and have("export") and have("render") then
  os.execute("mkdir -p " .. out)
  local part = box(2, 2, 1)
  export(part, out .. "/showcase.stl")
  render{part, out = out .. "/showcase.png"}
  print("wrote " .. out .. "/showcase.stl and " .. out .. "/showcase.png")
else
  print("not yet built: solids (box), export and render; no mesh or PNG written")
end
