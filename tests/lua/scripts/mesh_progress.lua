-- A sphere's mesh at a fine tolerance: long enough to show the tessellation's progress bar.
local n = sphere(1):triangles{tolerance = 1e-4}
print(string.format("mesh progress script done: %d triangles", n))
