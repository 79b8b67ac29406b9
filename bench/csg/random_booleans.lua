-- Random booleans of turned and moved solids (cubes, cylinders, spheres, and a cube minus a
-- cylinder: a moved boolean result), each as union, intersection and difference; prints every
-- boolean that fails and the count. A stress run for the engine and the tree (bench/RESULTS.md):
--   SEED=1 N=40 wedge run bench/csg/random_booleans.lua
-- KINDS=5 adds a fifth kind: the cube minus a cylinder moved 1.8e-17 along x, a part with a wall
-- that thin (far below a double's rounding once turned).
math.randomseed(tonumber(os.getenv("SEED") or "1"))
local function r(a, b) return a + (b - a) * math.random() end
local function shape()
  local k = math.random(1, tonumber(os.getenv("KINDS") or "4"))
  local s, desc
  local p1, p2 = r(0.5, 2), r(0.5, 2)
  if k == 1 then s = cube(p1); desc = string.format("cube(%.17g)", p1)
  elseif k == 2 then s = cylinder(p1 / 2, p2); desc = string.format("cylinder(%.17g, %.17g)", p1 / 2, p2)
  elseif k == 3 then s = sphere(p1 / 2); desc = string.format("sphere(%.17g)", p1 / 2)
  elseif k == 4 then s = cube(1) - cylinder(0.3, 3); desc = "(cube(1) - cylinder(0.3, 3))"
  else
    s = cube(1) - cylinder(0.3, 3):translate(1.8369701987210297e-17, 0, 0)
    desc = "(cube(1) - cylinder(0.3, 3):translate(1.8369701987210297e-17, 0, 0))"
  end
  local ang, ax = r(0, 360), {r(-1, 1), r(-1, 1), r(0.1, 1)}
  s = s:rotate(ang, ax)
  desc = desc .. string.format(":rotate(%.17g, {%.17g, %.17g, %.17g})", ang, ax[1], ax[2], ax[3])
  local t
  if math.random() < 0.3 then t = {math.random(0, 1) * 0.5, 0, 0} else t = {r(-0.7, 0.7), r(-0.7, 0.7), r(-0.7, 0.7)} end
  s = s:translate(t[1], t[2], t[3])
  desc = desc .. string.format(":translate(%.17g, %.17g, %.17g)", t[1], t[2], t[3])
  return s, desc, k
end
local fails, total, off = 0, 0, 0
for i = 1, tonumber(os.getenv("N") or "30") do
  local a, da, ka = shape()
  local b, db, kb = shape()
  local v = {}
  for _, op in ipairs({"+", "*", "-"}) do
    total = total + 1
    local ok, err = pcall(function()
      local s = op == "+" and a + b or (op == "*" and a * b or a - b)
      return s:volume()
    end)
    if ok then
      v[op] = err
    else
      fails = fails + 1
      print(string.format("FAIL %d %s kinds %d %d\n  a = %s\n  b = %s\n  %s", i, op, ka, kb, da, db, tostring(err):sub(1, 120)))
    end
  end
  -- The volume identities: vol(a + b) + vol(a * b) = vol(a) + vol(b), vol(a - b) = vol(a) - vol(a * b),
  -- to 1e-5 (volume() corrects for curved faces, to about 1e-6 where curved faces cut each other).
  if v["+"] and v["*"] and v["-"] then
    local va, vb = a:volume(), b:volume()
    local e1 = math.abs(v["+"] + v["*"] - va - vb) / (va + vb)
    local e2 = math.abs(v["-"] - va + v["*"]) / va
    if e1 > 1e-5 or e2 > 1e-5 then
      off = off + 1
      print(string.format("VOLUME %d kinds %d %d: identity errors %.3g %.3g\n  a = %s\n  b = %s", i, ka, kb, e1, e2, da, db))
    end
  end
end
print("fails", fails, "of", total, "volume identities off", off)
