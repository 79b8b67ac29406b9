-- A wireframe model beside the wireframe display of a solid: wireframe(s) keeps only the solid's
-- edges (no faces) as polylines, exported as OBJ polylines; render{s, wireframe=true} draws the
-- solid's triangles as lines.
-- Run: wedge run examples/wireframe.lua [out=directory]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")
local part = extrude(polygon{outer = {{0, 0}, {6, 0}, {6, 1}, {4, 1}, {4, 3}, {0, 3}},
                             holes = {{{1, 1}, {2.5, 1}, {2.5, 2}, {1, 2}}}}, 4)
local w = wireframe(part, {color = {0.1, 0.2, 0.6}})
print(string.format("wireframe: %d polylines, %d segments, length %.3f", #w, w:segments(), w:length()))
print("wrote " .. out .. "/part-wire.obj (" .. export(w, out .. "/part-wire.obj") .. " segments)")
render{w, out = out .. "/wireframe-model.png", size = {320, 320}, view = "iso"}
render{part, out = out .. "/wireframe-display.png", size = {320, 320}, view = "iso", wireframe = true, cull = "none"}
print("wrote " .. out .. "/wireframe-model.png and " .. out .. "/wireframe-display.png")
