-- Loaded by the stock lua5.4 interpreter with LUA_CPATH pointing at the built module.
local w = require "wedge"
local p = (w.matrix.translate(1, 2, 3) * w.matrix.scale(2)):apply({1, 1, 1})
assert(p[1] == 3 and p[2] == 4 and p[3] == 5, "unexpected point")
local ok, err = pcall(function() return w.matrix.rotate("ninety") end)
assert(not ok and err:find("bad argument #1 to 'rotate'"), err)
print("require wedge: ok " .. w.version())
