// Union-find for the boolean engine's passes (patches, vertex copies, shells): serial,
// shared between threads, and by blocks. Included by boolean_impl.h.
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "kernel/parallel.h"

namespace wedge::boolean_detail {

// Union-find over 0..n-1; a set's representative is its smallest member (so results do not
// depend on the order of unions).
class Dsu {
 public:
  // (Each element its own set, written once: not zeroed first; in parallel where there are many,
  // as for a large result's corners.)
  explicit Dsu(std::size_t n) : p_(new std::uint32_t[n]) {
    parallel_blocks(n, std::size_t(1) << 16, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) p_[i] = static_cast<std::uint32_t>(i);
    });
  }
  std::uint32_t find(std::uint32_t x) {
    while (p_[x] != x) x = p_[x] = p_[p_[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) p_[std::max(a, b)] = std::min(a, b);
  }
  // The same, safe to call from several threads at once (not mixed with find() or unite()): a
  // root is linked under the smaller root by a compare-and-swap, and paths are halved by another.
  // Parents only ever decrease, so each set's root is its smallest element, as with unite(),
  // whatever the order of the calls.
  std::uint32_t find_shared(std::uint32_t x) {
    for (;;) {
      std::uint32_t p = std::atomic_ref<std::uint32_t>(p_[x]).load(std::memory_order_relaxed);
      if (p == x) return x;
      const std::uint32_t g = std::atomic_ref<std::uint32_t>(p_[p]).load(std::memory_order_relaxed);
      if (g != p) std::atomic_ref<std::uint32_t>(p_[x]).compare_exchange_weak(p, g, std::memory_order_relaxed);
      x = g;
    }
  }
  void unite_shared(std::uint32_t a, std::uint32_t b) {
    for (;;) {
      a = find_shared(a);
      b = find_shared(b);
      if (a == b) return;
      if (a > b) std::swap(a, b);
      std::uint32_t expected = b;  // b is a root unless another thread linked it meanwhile: then again
      if (std::atomic_ref<std::uint32_t>(p_[b]).compare_exchange_strong(expected, a, std::memory_order_relaxed)) return;
    }
  }
  // The root of x's set by plain loads, changing nothing: for any number of threads at once after
  // the unions (halving the paths with a compare-and-swap a step was a third of a million
  // patches' roots).
  std::uint32_t root(std::uint32_t x) const {
    while (p_[x] != x) x = p_[x];
    return x;
  }
  // Unions of the pairs that pairs(lo, hi, unite) names for each block [lo, hi) of `block` items
  // of 0 .. n - 1 (items of the caller's, not this set's elements), the blocks in parallel by
  // unite_shared; with one thread, in order by unite(), with plain loads and stores (a
  // compare-and-swap per step was 3 ms of a million-triangle result's shells). The same roots
  // either way. Not mixed with other unions.
  template <class Pairs>
  void unite_each(std::size_t n, std::size_t block, Pairs&& pairs) {
    if (thread_count() == 1) {
      for (std::size_t lo = 0; lo < n; lo += block)
        pairs(lo, std::min(n, lo + block), [&](std::uint32_t a, std::uint32_t b) { unite(a, b); });
      return;
    }
    parallel_blocks(n, block, [&](std::size_t lo, std::size_t hi) {
      pairs(lo, hi, [&](std::uint32_t a, std::uint32_t b) { unite_shared(a, b); });
    });
  }
  // Unions of the pairs that pairs(lo, hi, unite) names for each block [lo, hi) of `block` items
  // of 0 .. n - 1, the blocks in parallel: a pair within the block is united at once, with plain
  // loads and stores (a compare-and-swap per link and per halving step was most of the cost of
  // uniting a million triangles' patches), the others afterwards by unite_shared. Each set's root
  // is still its smallest element. Only where every element is its own set or linked within its
  // block (as in a new Dsu): a block's finds then stay in the block, which no other thread writes.
  template <class Pairs>
  void unite_blocks(std::size_t n, std::size_t block, Pairs&& pairs) {
    const std::size_t blocks = (n + block - 1) / block;
    std::vector<std::vector<std::array<std::uint32_t, 2>>> across(blocks);
    parallel_for(0, blocks, [&](std::size_t k) {
      const std::size_t lo = k * block, hi = std::min(n, lo + block);
      pairs(lo, hi, [&](std::uint32_t a, std::uint32_t b) {
        if (a >= lo && a < hi && b >= lo && b < hi) unite(a, b);
        else across[k].push_back({a, b});
      });
    });
    parallel_for(0, blocks, [&](std::size_t k) {
      for (const auto& [a, b] : across[k]) unite_shared(a, b);
    });
  }

 private:
  std::unique_ptr<std::uint32_t[]> p_;
};

}  // namespace wedge::boolean_detail
