-- The winged-edge B-Rep from Lua: a block built one Euler operator at a time, its counts checked
-- against V - E + F - R + 2H - 2S = 0 after every step, then handed over as a Solid; and the
-- primitives built the same way inside (box, cube, polyhedron).
-- Run: wedge run examples/euler.lua [out=directory]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
local function show(b, what)
  local c = b:counts()
  local chi = c.V - c.E + c.F - c.R + 2 * c.H - 2 * c.S
  print(string.format("%-34s V=%2d E=%2d F=%2d R=%d H=%d S=%d   V-E+F-R+2H-2S = %d", what, c.V, c.E, c.F, c.R, c.H, c.S, chi))
  assert(chi == 0)
end

local b = brep()
local v1, top = b:mvfs{0, 0, 0}                 show(b, "mvfs: one vertex, face, shell")
local _, v2 = b:mev(top, v1, {3, 0, 0})
local _, v3 = b:mev(top, v2, {3, 2, 0})
local _, v4 = b:mev(top, v3, {0, 2, 0})         show(b, "3 x mev: the base outline")
local _, bottom = b:mef(top, v4, v1)            show(b, "mef: a lamina, top and bottom")
local up = {}
for i, v in ipairs{v1, v2, v3, v4} do
  local p = b:point(v)
  local _, t = b:mev(top, v, {p[1], p[2], 1})
  up[i] = t
end                                             show(b, "4 x mev: the vertical edges")
for i = 1, 4 do b:mef(top, up[i], up[i % 4 + 1]) end
                                                show(b, "4 x mef: the side faces")
assert(b:validate())

-- Undo one side face and put it back: kef is the inverse of mef.
local e, f = b:mef(top, up[1], up[3])           show(b, "mef: the top split along a diagonal")
b:kef(e, f)                                     show(b, "kef: and joined again")

local s = b:solid()
print(string.format("as a Solid: volume %.6f, area %.6f, valid %s", s:volume(), s:area(), tostring(s:is_valid())))

-- The primitives are B-Reps too, so their counts are exact, not those of a triangle mesh.
local e2 = box(1, 2, 3):euler()
print(string.format("box(1, 2, 3):euler() V=%d E=%d F=%d", e2.V, e2.E, e2.F))
local tet = polyhedron{points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, faces = {{1, 3, 2}, {1, 2, 4}, {1, 4, 3}, {2, 3, 4}}}
print(string.format("tetrahedron: volume %.6f (1/6 = %.6f), centroid (%.3f, %.3f, %.3f)", tet:volume(), 1 / 6,
                    table.unpack(tet:centroid())))

-- A precondition that fails names itself and leaves the model as it was.
local ok, err = pcall(b.kemr, b, 999)
print("kemr on a missing edge: " .. tostring(err))
show(b, "unchanged after the failed kemr")

-- The block as the Euler operators left it, drawn as a sheet: three views and an isometric one,
-- each with its edges.
drawing{s:material{diffuse = {0.55, 0.7, 0.85}}, out = out .. "/euler-block.png", size = {480, 360},
        views = {"front", "top", "side", "iso"}, hidden = "dashed"}
print("wrote " .. out .. "/euler-block.png")
