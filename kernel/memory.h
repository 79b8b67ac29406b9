// Process-wide memory settings for wedge's programs (the `wedge` runner and the benchmarks).
#pragma once

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

}  // namespace wedge
