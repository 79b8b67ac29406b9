// Process-wide memory: malloc's settings for wedge's programs, and the large blocks kept between runs.
#pragma once

#include <cstddef>
#include <new>
#include <vector>

namespace wedge {

// Asks glibc's malloc to keep freed memory for reuse instead of giving it back to the kernel: no
// block from mmap (glibc.malloc.mmap_max=0) and the heap not trimmed below 1 GiB. With
// WEDGE_HUGE_PAGES=1 also to back the heap with transparent huge pages (glibc.malloc.hugetlb=1).
// A tunable is read only when a process starts, so this adds them to GLIBC_TUNABLES and executes
// the program again (/proc/self/exe, same arguments, same process id). It returns without doing
// anything where the tunables are already set, where WEDGE_HUGE_PAGES=0, or where the program
// cannot be executed again.
//
// Why: a large boolean frees blocks of tens of megabytes that the next stage allocates again;
// glibc maps every block over 32 MiB on its own and unmaps it when freed, so each one was faulted
// in and zeroed again (on the lattice of 512 spheres, a quarter of the run). Huge pages are not
// the default: where the kernel must compact memory to find them (THP "madvise" mode, a machine
// whose memory other processes have fragmented) a fault took milliseconds, and two 1M-triangle
// spheres ran 1.3x slower with them than with 4 KiB pages (bench/RESULTS.md).
// Call it first in main(), before any thread starts. A library cannot do this for its host
// program: C++ applications that link wedge set the tunables in their own environment.
void tune_malloc(char** argv);

// The earlier name of tune_malloc().
inline void use_huge_pages(char** argv) { tune_malloc(argv); }

// Large blocks kept between runs. A block of 256 KiB or more given back (give_block) is kept,
// up to 512 MiB in all, for the next request of between half its size and its size (take_block),
// instead of going back to malloc. Why: on the benchmark's VM a page the process has not touched
// costs some 11 us to fault in (a memset of 200 KB), and glibc, its freed memory fragmented by
// the blocks of a boolean's many sizes, placed a second boolean's arrays on fresh pages: the
// plate minus 400 cylinders faulted 4,000 pages in the second run's arrangement. A run asks for
// the same sizes as the one before it, so the blocks a boolean's points and tables held are the
// next one's. Thread-safe; release_kept_blocks() frees them all.
void* take_block(std::size_t bytes);
void give_block(void* p, std::size_t bytes) noexcept;
void release_kept_blocks() noexcept;
std::size_t kept_bytes() noexcept;  // held by the cache now

// A std::allocator whose large blocks come from, and go back to, the cache above.
template <class T>
struct Kept {
  static_assert(alignof(T) <= __STDCPP_DEFAULT_NEW_ALIGNMENT__, "Kept's blocks have operator new's alignment");
  using value_type = T;
  Kept() = default;
  template <class U>
  Kept(const Kept<U>&) noexcept {}
  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(take_block(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t n) noexcept { give_block(p, n * sizeof(T)); }
  template <class U>
  bool operator==(const Kept<U>&) const noexcept { return true; }
};
template <class T>
using KeptVector = std::vector<T, Kept<T>>;

}  // namespace wedge
