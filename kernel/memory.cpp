#include "kernel/memory.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace wedge {

void tune_malloc(char** argv) {
#ifdef __linux__
  const char* mode = std::getenv("WEDGE_HUGE_PAGES");
  if (mode && std::strcmp(mode, "0") == 0) return;
  const char* old = std::getenv("GLIBC_TUNABLES");
  if (old && std::strstr(old, "glibc.malloc.mmap_max")) return;  // set (by us, or by the user)
  // Freed memory kept for reuse (no block from mmap: every one from the heap, which is not
  // trimmed below 1 GiB) so that a block freed by one stage is not faulted in and zeroed again by
  // the next. (mmap_max=0, not a large mmap_threshold: glibc ignores a threshold above 32 MiB.)
  std::string ours = "glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=1073741824";
  if (mode && std::strcmp(mode, "1") == 0) ours += ":glibc.malloc.hugetlb=1";
  std::string tunables = old && *old ? std::string(old) + ":" + ours : ours;
  if (setenv("GLIBC_TUNABLES", tunables.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Not executed again (no /proc, say): run on as we are, and leave the environment as it was.
  if (old) setenv("GLIBC_TUNABLES", old, 1);
  else unsetenv("GLIBC_TUNABLES");
#else
  (void)argv;
#endif
}

}  // namespace wedge
