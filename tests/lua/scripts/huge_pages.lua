-- The runner's malloc settings (kernel/memory.h): GLIBC_TUNABLES holds the tunables; with
-- WEDGE_HUGE_PAGES=1, where the kernel gives huge pages on request, a large allocation is backed
-- by them.
local t = os.getenv("GLIBC_TUNABLES") or ""
io.write("tunables: ", t, "\n")
local f = io.open("/sys/kernel/mm/transparent_hugepage/enabled")
local mode = f and f:read("l") or ""
if f then f:close() end
if mode:find("%[madvise%]") or mode:find("%[always%]") then
  local big = string.rep("x", 64 * 1024 * 1024)  -- 64 MiB through malloc
  local s = io.open("/proc/self/smaps_rollup"):read("a")
  local kb = tonumber(s:match("AnonHugePages:%s*(%d+)")) or 0
  io.write("huge pages: ", kb > 0 and "yes" or "no", " (", kb, " kB, ", #big, " bytes held)\n")
else
  io.write("huge pages: not offered by the kernel (", mode, ")\n")
end
-- Freed memory is kept for reuse: a 64 MiB block, once freed, still counts in the resident set
-- (glibc would otherwise have mapped it on its own and unmapped it at once).
local function rss_kb()
  local s = io.open("/proc/self/status"):read("a")
  return tonumber(s:match("VmRSS:%s*(%d+)")) or 0
end
do
  local block = string.rep("y", 64 * 1024 * 1024)
  assert(#block == 64 * 1024 * 1024)
end
collectgarbage()
collectgarbage()
io.write("freed 64 MiB kept: ", rss_kb() >= 64 * 1024 and "yes" or "no", " (resident ", rss_kb(), " kB)\n")
