-- A script's loop that adds one box at a time: s = s + b, N times (issue 14). Measures building
-- the tree (CPU seconds, os.clock) and, with EVAL=1, evaluating it.
--   N=4000 OP=+ EVAL=1 STEP=0.3 wedge run bench/csg/chain.lua
-- OP: + (union), - (difference); STEP: box spacing along x (0.7 disjoint, 0.3 each overlapping
-- the next).
local N = tonumber(os.getenv("N") or 1000)
local op = os.getenv("OP") or "+"
local eval = os.getenv("EVAL") == "1"
local t0 = os.clock()
local s = box(1, 1, 1)
for i = 1, N do
  local b = box(0.5, 0.5, 0.5):translate(i * (tonumber(os.getenv("STEP")) or 0.7), 0, 0)
  if op == "+" then s = s + b elseif op == "-" then s = s - b else s = s * box(1000, 1000, 1000) end
end
local t1 = os.clock()
local v = 0
if eval then v = s:volume() end
local t2 = os.clock()
print(string.format("N=%d op=%s build %.3f s eval %.3f s volume %g", N, op, t1 - t0, t2 - t1, v))
