-- About a second of CSG work, one boolean node after another (unions and differences alternate, so
-- each node waits for the one before), for the runner's progress bar: shown on a terminal, never on
-- a pipe or a file, never with --quiet.
tolerance(0.0001)
local s = sphere(1)
for i = 1, 24 do
  if i % 2 == 1 then s = s - cube(0.4):translate(0.1 * i - 1.2, -0.2, 0.7)
  else s = s + sphere(0.5):translate(0.1 * i - 1.2, 0.8, 0) end
end
print(string.format("long csg script done: volume %.3f", s:volume()))
