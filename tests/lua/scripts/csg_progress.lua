-- Three boolean nodes (two differences and their union) for the runner's progress bar and --stats.
tolerance(0.01)
local a = box(2, 2, 2) - sphere(0.5):translate(1, 1, 2)
local b = box(2, 2, 2):translate(1, 1, 1) - sphere(0.5):translate(2, 2, 3)
local u = a + b
local e = u:euler()
print(string.format("csg progress script done: volume %.3f, S %d", u:volume(), e.S))
