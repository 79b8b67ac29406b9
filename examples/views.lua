-- The course's views of one part: multiview orthographic (front, top, side), axonometric
-- (isometric, dimetric, trimetric), oblique (cavalier, cabinet) and perspective with one, two and
-- three vanishing points, on one drawing sheet and as separate pictures.
-- Run: wedge run examples/views.lua [out=directory] [angle=45]
local out = params.out or arg[1] or "out"
os.execute("mkdir -p '" .. out .. "'")

-- An L-shaped bracket with a square window in its upright.
local foot = extrude(polygon{{0, 0}, {4, 0}, {4, 3}, {0, 3}}, 1)
local upright = extrude(polygon{outer = {{0, 0}, {3, 0}, {3, 3}, {0, 3}},
                                holes = {{{1, 1}, {2, 1}, {2, 2}, {1, 2}}}}, 1)
                  :rotate(90, "x"):translate(0, 1, 1)
local part = group{foot:material{diffuse = {0.85, 0.55, 0.25}},
                   upright:material{diffuse = {0.3, 0.55, 0.85}}}

local angle = params.angle or 45
drawing{part, out = out .. "/views-sheet.png", size = {1200, 900}, columns = 4,
        views = {"front", "top", "side", "iso", "dimetric", "trimetric",
                 {"cavalier", angle = angle}, {"cabinet", angle = angle},
                 "one_point", "two_point", "three_point"}}
print("wrote " .. out .. "/views-sheet.png")

for _, v in ipairs{"iso", "cabinet", "two_point"} do
  render{part, out = out .. "/view-" .. v .. ".png", size = {320, 240}, view = v}
  print("wrote " .. out .. "/view-" .. v .. ".png")
end

-- The projection matrices themselves: a unit step along each axis, as each projection draws it.
local function show(name, m)
  local o = m:apply({0, 0, 0})
  local parts = {}
  for _, a in ipairs{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}} do
    local p = m:apply(a)
    parts[#parts + 1] = string.format("(%.3f, %.3f)", p[1] - o[1], p[2] - o[2])
  end
  print(string.format("%-10s x -> %s  y -> %s  z (towards the viewer) -> %s", name, parts[1], parts[2], parts[3]))
end
show("isometric", matrix.axonometric{})
show("trimetric", matrix.axonometric{rx = 20, ry = -30})
show("cavalier", matrix.oblique{angle = angle, ratio = 1})
show("cabinet", matrix.oblique{angle = angle, ratio = 0.5})
