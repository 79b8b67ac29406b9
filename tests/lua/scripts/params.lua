-- Prints what a script sees of its arguments: `wedge run params.lua teeth=24 name=gear plain`.
local keys = {}
for k in pairs(params) do keys[#keys + 1] = k end
table.sort(keys)
local parts = {}
for _, k in ipairs(keys) do parts[#parts + 1] = k .. "=" .. tostring(params[k]) .. ":" .. (math.type(params[k]) or type(params[k])) end
print("params: " .. table.concat(parts, ",") .. "; args: " .. table.concat(arg, ",") .. ";")
