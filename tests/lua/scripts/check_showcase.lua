-- Checks what examples/showcase.lua wrote into the directory arg[1].
local dir = assert(arg[1], "usage: check_showcase.lua DIR")
local plate = import(dir .. "/plate.stl")
assert(math.abs(plate:volume() - 20) < 1e-4, "plate volume " .. plate:volume())
local e = plate:euler()
assert(e.S == 1 and e.H == 1, "the plate is one shell with one through hole")
for _, name in ipairs{"plate.png", "spire.png", "teapot.png", "plate-views.png"} do
  local f = assert(io.open(dir .. "/" .. name, "rb"), "missing " .. name)
  local header = f:read(8)
  f:close()
  assert(header == "\137PNG\r\n\26\n", name .. " is not a PNG")
end
print("showcase output: ok")
