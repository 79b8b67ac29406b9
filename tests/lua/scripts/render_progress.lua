-- A render of some 80,000 triangles: several batches, so the rasterizer's progress bar shows (forced
-- by WEDGE_PROGRESS=always in the test). Usage: render_progress.lua OUTDIR
local out = arg[1] or "."
local s = sphere(1)
local n = s:triangles{tolerance = 2e-4}
tolerance(2e-4)
render{s, out = out .. "/render-progress.png", size = {64, 64}}
print(string.format("render progress script done: %d triangles", n))
