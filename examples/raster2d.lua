-- The classic 2D raster algorithms on a canvas (Foley et al., chapters 3 and 19), one panel each:
-- a fan of Bresenham lines and one of DDA lines, concentric midpoint circles, a pentagram filled
-- with the even-odd and the non-zero rule, a flood-filled outline, and lines and a polygon
-- clipped to a window. Run: wedge run examples/raster2d.lua [out=directory]
local out = (params and params.out) or arg[1] or "out"
os.execute("mkdir -p '" .. out .. "'")
local W, H = 480, 320
local c = canvas{width = W, height = H, background = {1, 1, 1}}
local black, red, blue, green, grey = {0, 0, 0}, {0.85, 0.1, 0.1}, {0.1, 0.2, 0.8}, {0.1, 0.6, 0.2}, {0.6, 0.6, 0.6}

-- Panels of 160 x 160, origin at the bottom left: (0,160) (160,160) (320,160) / (0,0) (160,0) (320,0).
local function panel(i, j) return 160 * i, 160 * j end

-- 1. Bresenham: a fan of 16 lines from the panel's centre.
local x0, y0 = panel(0, 1)
for k = 0, 15 do
  local a = k * math.pi / 8
  c:line{{x0 + 80, y0 + 80}, {x0 + 80 + math.floor(70 * math.cos(a) + 0.5), y0 + 80 + math.floor(70 * math.sin(a) + 0.5)},
         algorithm = "bresenham", color = black}
end

-- 2. DDA: the same fan.
x0, y0 = panel(1, 1)
for k = 0, 15 do
  local a = k * math.pi / 8
  c:line{{x0 + 80, y0 + 80}, {x0 + 80 + math.floor(70 * math.cos(a) + 0.5), y0 + 80 + math.floor(70 * math.sin(a) + 0.5)},
         algorithm = "dda", color = blue}
end

-- 3. Midpoint circles.
x0, y0 = panel(2, 1)
for r = 10, 70, 10 do c:circle{center = {x0 + 80, y0 + 80}, radius = r, color = r % 20 == 0 and red or black} end

-- 4. A pentagram, even-odd (left half) and non-zero (right half).
local function star(cx, cy, r)
  local s = {}
  for k = 0, 4 do
    local a = math.pi / 2 + k * 4 * math.pi / 5
    s[#s + 1] = {cx + r * math.cos(a), cy + r * math.sin(a)}
  end
  return s
end
x0, y0 = panel(0, 0)
local s = star(x0 + 42, y0 + 80, 38)
s.fill, s.color = "even-odd", red
c:polygon(s)
s = star(x0 + 118, y0 + 80, 38)
s.fill, s.color = "nonzero", blue
c:polygon(s)

-- 5. Flood fill: a house outline drawn with lines, its inside filled from a seed.
x0, y0 = panel(1, 0)
local house = {{30, 20}, {130, 20}, {130, 90}, {80, 140}, {30, 90}}
for i = 1, #house do
  local a, b = house[i], house[i % #house + 1]
  c:line{{x0 + a[1], y0 + a[2]}, {x0 + b[1], y0 + b[2]}, color = black}
end
c:flood_fill{{x0 + 80, y0 + 60}, color = green}

-- 6. Clipping: a window, the fan of lines clipped to it (Cohen-Sutherland and Liang-Barsky
-- alternately) and a triangle clipped by Sutherland-Hodgman.
x0, y0 = panel(2, 0)
local wx0, wy0, wx1, wy1 = x0 + 30, y0 + 30, x0 + 130, y0 + 130
c:line{{wx0, wy0}, {wx1, wy0}, color = grey} c:line{{wx1, wy0}, {wx1, wy1}, color = grey}
c:line{{wx1, wy1}, {wx0, wy1}, color = grey} c:line{{wx0, wy1}, {wx0, wy0}, color = grey}
c:clip{window = {wx0, wy0, wx1, wy1}, algorithm = "sutherland_hodgman"}
c:polygon{{x0 + 10, y0 + 60}, {x0 + 150, y0 + 10}, {x0 + 100, y0 + 150}, color = {0.95, 0.8, 0.3}}
for k = 0, 11 do
  c:clip{window = {wx0, wy0, wx1, wy1}, algorithm = k % 2 == 0 and "cohen_sutherland" or "liang_barsky"}
  local a = k * math.pi / 6
  c:line{{x0 + 80, y0 + 80}, {x0 + 80 + math.floor(95 * math.cos(a) + 0.5), y0 + 80 + math.floor(95 * math.sin(a) + 0.5)},
         color = black}
end
c:clip{}

c:save(out .. "/raster2d.png")
print("wrote " .. out .. "/raster2d.png")
