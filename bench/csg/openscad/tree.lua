-- bench_tree's models as a wedge script, the same as tree.scad: the pair that the ladder
-- (ladder.sh) times whole-process, `wedge run` against `openscad`, each exporting an STL.
--
--   wedge run tree.lua n=5 model=plate out=out.stl      (model "plate" or "gear")
tolerance(0.01)
local n = params.n or 20
local model = params.model or "plate"
local out = params.out or "out.stl"

local function plate()
  local parts = {box(2 * n + 2, 2 * n + 2, 2)}
  -- One drilled boss; every instance is a moved copy of this one node.
  local boss = cylinder(0.6, 2):translate(0, 0, 1.5) - cylinder(0.3, 3):translate(0, 0, 1)
  local drill = cylinder(0.2, 5):translate(0, 0, -1)
  local drills = {}
  for i = 0, n - 1 do
    for j = 0, n - 1 do
      parts[#parts + 1] = boss:translate(2 + 2 * i, 2 + 2 * j, 0)
      drills[#drills + 1] = drill:translate(2 + 2 * i, 2 + 2 * j, 0)
    end
  end
  return difference(union(table.unpack(parts)), table.unpack(drills))
end

local function gear()
  local parts = {cylinder(10, 2)}
  local tooth = box(1.6, 0.8, 2):translate(9.5, -0.4, 0)
  for k = 0, 59 do parts[#parts + 1] = tooth:rotate_z(6 * k) end
  local ops = {union(table.unpack(parts)), cylinder(2, 4):translate(0, 0, -1)}
  for k = 0, 5 do
    local a = math.rad(60 * k)
    ops[#ops + 1] = cylinder(1.5, 4):translate(6 * math.cos(a), 6 * math.sin(a), -1)
  end
  return difference(table.unpack(ops))
end

local s = model == "plate" and plate() or gear()
export(s, out)
print(string.format("%s n=%d volume %.6f triangles %d", model, n, s:volume(), s:triangles()))
