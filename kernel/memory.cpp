#include "kernel/memory.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace wedge {

void use_huge_pages(char** argv) {
#ifdef __linux__
  const char* off = std::getenv("WEDGE_HUGE_PAGES");
  if (off && std::strcmp(off, "0") == 0) return;
  const char* old = std::getenv("GLIBC_TUNABLES");
  if (old && std::strstr(old, "glibc.malloc.hugetlb")) return;  // set (by us, or by the user)
  // Huge pages; and freed memory kept for reuse (no block from mmap: every one from the heap,
  // which is not trimmed below 1 GiB) so that a block freed by one stage is not faulted in and
  // zeroed again by the next. (mmap_max=0, not a large mmap_threshold: glibc ignores a threshold
  // above 32 MiB, and every larger block was mapped, unmapped and zeroed again, 2 MiB at a time.)
  const char* ours = "glibc.malloc.hugetlb=1:glibc.malloc.mmap_max=0:glibc.malloc.trim_threshold=1073741824";
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
