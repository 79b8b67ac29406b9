// Parallel helpers over oneTBB. Work items must be independent; exceptions thrown by a body
// propagate to the caller (TBB rethrows the first one).
#pragma once
#include <algorithm>
#include <cstddef>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "kernel/error.h"

namespace wedge {

template <class F>
void parallel_for(std::size_t begin, std::size_t end, F&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
  // A loop run inside a task whose group was cancelled (a sibling task threw, and TBB rethrows
  // that first exception where the group began) returns early, iterations skipped, with no
  // exception of its own: its caller went on with results never made (a null operand in the CSG
  // tree, a missing block of the boolean's sums: a crash, for a tree with a failing operand beside
  // a busy one). It throws here instead; TBB keeps the first exception, so the sibling's is seen.
  if (tbb::is_current_task_group_canceling()) throw Error("parallel work cancelled by a failure beside it");
}

// How many threads a parallel loop started here can use: the current arena's, within the
// process's limit (tbb::global_control; the arena's own count does not see it).
inline std::size_t thread_count() {
  return static_cast<std::size_t>(std::min<std::size_t>(
      static_cast<std::size_t>(tbb::this_task_arena::max_concurrency()),
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)));
}

// a() and b() side by side: independent work, each too small or too serial to fill the threads
// by itself. As for parallel_for, a failure beside them in a cancelled group throws here.
template <class A, class B>
void parallel_invoke(A&& a, B&& b) {
  tbb::parallel_invoke(a, b);
  if (tbb::is_current_task_group_canceling()) throw Error("parallel work cancelled by a failure beside it");
}

// body(lo, hi) for the blocks [lo, hi) of `block` items that cover [0, n), in parallel.
template <class F>
void parallel_blocks(std::size_t n, std::size_t block, F&& body) {
  parallel_for(0, (n + block - 1) / block, [&](std::size_t b) { body(b * block, std::min(n, (b + 1) * block)); });
}

// The first half of a compaction whose output is in item order at any thread count:
// count(lo, hi), in parallel over the blocks of `block` items of [0, n), says how many outputs a
// block makes; block_starts returns where each block's outputs start. fill_blocks then writes
// each block's outputs from its start, over the same blocks.
struct BlockStarts {
  std::size_t n = 0, block = 1;
  std::vector<std::size_t> from;  // per block, its first output; one entry more: the total
  std::size_t total() const { return from.back(); }
};

template <class Count>
BlockStarts block_starts(std::size_t n, std::size_t block, Count&& count) {
  const std::size_t blocks = (n + block - 1) / block;
  BlockStarts s{n, block, std::vector<std::size_t>(blocks + 1, 0)};
  parallel_for(0, blocks, [&](std::size_t b) { s.from[b + 1] = count(b * block, std::min(n, (b + 1) * block)); });
  for (std::size_t b = 0; b < blocks; ++b) s.from[b + 1] += s.from[b];
  return s;
}

// fill(lo, hi, start) for each block of s, in parallel.
template <class Fill>
void fill_blocks(const BlockStarts& s, Fill&& fill) {
  parallel_for(0, s.from.size() - 1,
               [&](std::size_t b) { fill(b * s.block, std::min(s.n, (b + 1) * s.block), s.from[b]); });
}

// out[0] = 0 and out[i + 1] = count(0) + ... + count(i) for i in [0, n) (where each item's
// outputs start): sums within blocks of `block` items in parallel, then each block's start added.
// (`out` may be a vector whose allocator leaves new elements unset: each is written here.)
template <class Vector, class Count>
void parallel_prefix(Vector& out, std::size_t n, std::size_t block, Count&& count) {
  using T = typename Vector::value_type;
  out.resize(n + 1);
  out[0] = T(0);
  const auto from = block_starts(n, block, [&](std::size_t lo, std::size_t hi) {
    T sum = 0;
    for (std::size_t i = lo; i < hi; ++i) out[i + 1] = sum += count(i);
    return static_cast<std::size_t>(sum);
  });
  fill_blocks(from, [&](std::size_t lo, std::size_t hi, std::size_t start) {
    for (std::size_t i = lo; i < hi; ++i) out[i + 1] += static_cast<T>(start);
  });
}

}  // namespace wedge
