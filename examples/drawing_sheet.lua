-- A drawing sheet: three orthographic views and an isometric one of a part, each titled, its
-- edges drawn over the shaded faces, hidden edges dashed.
-- Run: wedge run examples/drawing_sheet.lua [out=directory] [hidden=dashed|removed]
local out = params.out or "out"
os.execute("mkdir -p '" .. out .. "'")

local block = extrude(polygon{outer = {{0, 0}, {6, 0}, {6, 1}, {4, 1}, {4, 3}, {0, 3}},
                              holes = {{{1, 1}, {2.5, 1}, {2.5, 2}, {1, 2}}}}, 4)
                :material{diffuse = {0.75, 0.8, 0.9}}
drawing{block, out = out .. "/drawing-sheet.png", size = {900, 700},
        views = {"front", "top", "side", "iso"}, hidden = params.hidden or "dashed"}
print("wrote " .. out .. "/drawing-sheet.png")
