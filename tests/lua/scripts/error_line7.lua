-- A script whose error is on line 7: the runner must report line 7.
local m = matrix.translate(1, 2, 3)
local p = m:apply({0, 0, 0})
assert(p[1] == 1)

-- the next line passes a string where a number belongs
local bad = matrix.translate("one", 2, 3)
