-- The seed's worked example of Euler operators: a block with a protrusion, a sharp-cornered
-- depression, a round-cornered depression and a round through hole, built one feature at a time
-- by Euler operators. Prints each feature's own counts and the total, and checks the
-- Euler-Poincare formula V - E + F - R + 2H - 2S = 0 on every row.
--   build/wedge run examples/worked_example.lua [out.stl]
local s, rows = worked_example()

local function line(name, c)
  local sum = c.V - c.E + c.F - c.R + 2 * c.H - 2 * c.S
  print(string.format("%-22s %4d %4d %4d %4d %4d %4d   %d", name, c.V, c.E, c.F, c.R, c.H, c.S, sum))
  assert(sum == 0, name .. ": V - E + F - R + 2H - 2S is " .. sum)
end

print(string.format("%-22s %4s %4s %4s %4s %4s %4s   %s", "feature", "V", "E", "F", "R", "H", "S", "V-E+F-R+2H-2S"))
local total = {V = 0, E = 0, F = 0, R = 0, H = 0, S = 0}
for _, r in ipairs(rows) do
  line(r.name, r)
  for k in pairs(total) do total[k] = total[k] + r[k] end
end
line("total", total)

local e = s:euler()
line("solid", e)
for k in pairs(total) do
  assert(e[k] == total[k], "the solid's " .. k .. " (" .. e[k] .. ") differs from the table's total (" .. total[k] .. ")")
end
assert(s:is_valid(), "the worked example does not validate")
print(string.format("valid: yes   volume: %.6g   area: %.6g", s:volume(), s:area()))

-- A mesh file when the first argument names one; the picture in out=directory (default "out").
if arg[1] and not arg[1]:find("=") then
  export(s, arg[1])
  print("wrote " .. arg[1])
end
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
render{s:material{diffuse = {0.8, 0.6, 0.35}}, out = out .. "/worked-example.png", size = {480, 360}, view = "iso",
       shading = "flat", lights = {{type = "directional", direction = {-0.3, 0.5, -1}}, {type = "directional", direction = {0.6, 0.4, -0.3}, diffuse = {0.4, 0.4, 0.4}}}}
print("wrote " .. out .. "/worked-example.png")
