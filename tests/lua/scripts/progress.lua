-- Long work shows a progress bar on stderr (forced by WEDGE_PROGRESS=always in the test).
local out = arg[1] or "."
drawing{box(1, 2, 3), out = out .. "/progress-sheet.png", size = {160, 120}, views = {"front", "top", "side", "iso"}}
render{array{box(1, 1, 1), count = 3, step = {2, 0, 0}}, out = out .. "/progress-row.png", size = {60, 40}}
print("progress script done")
