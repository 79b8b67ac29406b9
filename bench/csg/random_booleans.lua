-- Random booleans of turned and moved solids (cubes, cylinders, spheres, and a cube minus a
-- cylinder: a moved boolean result), each as union, intersection and difference; prints every
-- boolean that fails and the count. A stress run for the engine and the tree (bench/RESULTS.md):
--   SEED=1 N=40 wedge run bench/csg/random_booleans.lua
math.randomseed(tonumber(os.getenv("SEED") or "1"))
local function r(a, b) return a + (b - a) * math.random() end
local function shape()
  local k = math.random(1, 4)
  local s, desc
  local p1, p2 = r(0.5, 2), r(0.5, 2)
  if k == 1 then s = cube(p1); desc = string.format("cube(%.17g)", p1)
  elseif k == 2 then s = cylinder(p1 / 2, p2); desc = string.format("cylinder(%.17g, %.17g)", p1 / 2, p2)
  elseif k == 3 then s = sphere(p1 / 2); desc = string.format("sphere(%.17g)", p1 / 2)
  else s = cube(1) - cylinder(0.3, 3); desc = "(cube(1) - cylinder(0.3, 3))" end
  local ang, ax = r(0, 360), {r(-1, 1), r(-1, 1), r(0.1, 1)}
  s = s:rotate(ang, ax)
  desc = desc .. string.format(":rotate(%.17g, {%.17g, %.17g, %.17g})", ang, ax[1], ax[2], ax[3])
  local t
  if math.random() < 0.3 then t = {math.random(0, 1) * 0.5, 0, 0} else t = {r(-0.7, 0.7), r(-0.7, 0.7), r(-0.7, 0.7)} end
  s = s:translate(t[1], t[2], t[3])
  desc = desc .. string.format(":translate(%.17g, %.17g, %.17g)", t[1], t[2], t[3])
  return s, desc, k
end
local fails, total = 0, 0
for i = 1, tonumber(os.getenv("N") or "30") do
  local a, da, ka = shape()
  local b, db, kb = shape()
  for _, op in ipairs({"+", "*", "-"}) do
    total = total + 1
    local ok, err = pcall(function()
      local s = op == "+" and a + b or (op == "*" and a * b or a - b)
      return s:volume()
    end)
    if not ok then
      fails = fails + 1
      print(string.format("FAIL %d %s kinds %d %d\n  a = %s\n  b = %s\n  %s", i, op, ka, kb, da, db, tostring(err):sub(1, 120)))
    end
  end
end
print("fails", fails, "of", total)
