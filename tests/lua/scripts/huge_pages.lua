-- The runner asks glibc's malloc for transparent huge pages (kernel/memory.h): GLIBC_TUNABLES
-- holds the tunable, and where the kernel gives huge pages on request, a large allocation is
-- backed by them.
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
