-- Run by the stock lua5.4 interpreter: `lua5.4 require_params.lua teeth=24 name=gear`.
local w = require "wedge"
assert(w.params.teeth == 24 and math.type(w.params.teeth) == "integer", tostring(w.params.teeth))
assert(w.params.name == "gear")
local ok, err = pcall(w.matrix.rotate, "x")
assert(err:find("^bad argument #1 to 'matrix.rotate'"), err)
ok, err = pcall(w.box, -1, 1, 1)
assert(err:find("^bad argument #1 to 'box'"), err)
print("require params: ok")
