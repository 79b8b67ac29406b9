#include "kernel/memory.h"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

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

namespace wedge {

namespace {

constexpr std::size_t kKeptFrom = std::size_t{1} << 18;  // 256 KiB
constexpr std::size_t kKeptCap = std::size_t{1} << 29;   // 512 MiB

struct KeptBlocks {
  std::mutex mutex;
  std::vector<std::pair<void*, std::size_t>> kept;  // (block, its size), oldest first
  std::vector<std::pair<void*, std::size_t>> lent;  // blocks lent for fewer bytes than their size
  std::size_t bytes = 0;                             // in `kept`
};
// (Never destroyed: a vector's block may be given back during static destruction.)
KeptBlocks& blocks() {
  static KeptBlocks* b = new KeptBlocks;
  return *b;
}

}  // namespace

void* take_block(std::size_t bytes) {
  if (bytes >= kKeptFrom) {
    KeptBlocks& b = blocks();
    std::lock_guard<std::mutex> lock(b.mutex);
    std::size_t best = b.kept.size();
    for (std::size_t i = 0; i < b.kept.size(); ++i) {
      const std::size_t size = b.kept[i].second;
      if (size >= bytes && size / 2 <= bytes && (best == b.kept.size() || size < b.kept[best].second)) best = i;
    }
    if (best < b.kept.size()) {
      const auto [p, size] = b.kept[best];
      // (Room for its record first: if that throws, nothing has changed.)
      if (size != bytes && b.lent.size() == b.lent.capacity()) b.lent.reserve(2 * b.lent.size() + 8);
      b.kept.erase(b.kept.begin() + static_cast<std::ptrdiff_t>(best));
      b.bytes -= size;
      if (size != bytes) b.lent.push_back({p, size});
      return p;
    }
  }
  return ::operator new(bytes);
}

void give_block(void* p, std::size_t bytes) noexcept {
  if (!p) return;
  if (bytes < kKeptFrom) {
    ::operator delete(p);
    return;
  }
  KeptBlocks& b = blocks();
  std::lock_guard<std::mutex> lock(b.mutex);
  for (std::size_t i = 0; i < b.lent.size(); ++i)
    if (b.lent[i].first == p) {
      bytes = b.lent[i].second;
      b.lent[i] = b.lent.back();
      b.lent.pop_back();
      break;
    }
  try {
    b.kept.push_back({p, bytes});
  } catch (...) {  // (no room for the record: the block is freed instead)
    ::operator delete(p);
    return;
  }
  b.bytes += bytes;
  std::size_t n = 0;  // the oldest go first, while over the cap
  while (b.bytes > kKeptCap) {
    b.bytes -= b.kept[n].second;
    ::operator delete(b.kept[n++].first);
  }
  b.kept.erase(b.kept.begin(), b.kept.begin() + static_cast<std::ptrdiff_t>(n));
}

void release_kept_blocks() noexcept {
  std::vector<std::pair<void*, std::size_t>> kept;
  {
    KeptBlocks& b = blocks();
    std::lock_guard<std::mutex> lock(b.mutex);
    kept.swap(b.kept);
    b.bytes = 0;
  }
  for (const auto& k : kept) ::operator delete(k.first);
}

std::size_t kept_bytes() noexcept {
  KeptBlocks& b = blocks();
  std::lock_guard<std::mutex> lock(b.mutex);
  return b.bytes;
}

}  // namespace wedge
