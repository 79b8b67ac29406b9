// Parallel helpers over oneTBB. Work items must be independent; exceptions thrown by a body
// propagate to the caller (TBB rethrows the first one).
#pragma once
#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace wedge {

template <class F>
void parallel_for(std::size_t begin, std::size_t end, F&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
}

}  // namespace wedge
