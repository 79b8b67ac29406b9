// Process-wide memory settings for wedge's programs (the `wedge` runner and the benchmarks).
#pragma once

namespace wedge {

// Asks glibc's malloc to back the heap with transparent huge pages (2 MiB instead of 4 KiB), the
// glibc tunable `glibc.malloc.hugetlb=1`, and to keep freed memory for reuse instead of giving
// it back to the kernel (no block from mmap, a trim threshold of 1 GiB). A tunable is read only when a process starts, so this
// adds it to GLIBC_TUNABLES and executes the program again (/proc/self/exe, same arguments, same
// process id). It returns without doing anything where the tunable is already set, where
// WEDGE_HUGE_PAGES=0, or where the program cannot be executed again.
//
// Why: this machine's kernel hands out anonymous memory in 4 KiB pages unless asked (THP
// "madvise" mode), and a page fault costs about 8 us under its hypervisor; two 1M-triangle spheres
// take 376k faults (a third of the run) with 4 KiB pages, 16k with huge ones and 1.5k when freed
// blocks are reused (bench/RESULTS.md).
// Call it first in main(), before any thread starts. A library cannot do this for its host
// program: C++ applications that link wedge set the tunable in their own environment.
void use_huge_pages(char** argv);

}  // namespace wedge
