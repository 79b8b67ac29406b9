// Parallel helpers over oneTBB. Work items must be independent; exceptions thrown by a body
// propagate to the caller (TBB rethrows the first one).
#pragma once
#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
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

}  // namespace wedge
