// radix_sort: the stable sort by a 64-bit key that the boolean engine's passes use (tree order,
// pairs, edge records, triangulation entries), and chunk_offsets, the middle of the counting sorts
// by vertex (corner lists, edge records). Included by boolean_impl.h.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernel/parallel.h"

namespace wedge::boolean_detail {

// Sorts v stably by key(x) (an unsigned 64-bit value below 2^bits): least significant digit
// first, 11 bits at a time, passes over a digit that every element shares left out (each such
// digit still costs a counting pass: a narrow key says so with `bits`). With more than one thread
// and many elements, each pass counts and scatters by blocks in parallel (each block's share of
// a digit placed after the earlier blocks' shares: the same order as the serial pass, so the
// same result at any thread count); the serial passes were a third of a 130k-triangle tree's
// build, and a tenth of its boolean's time outside parallel loops at two threads.
template <class T, class A, class Key>
inline void radix_sort(std::vector<T, A>& v, Key&& key, int bits = 64) {
  const std::size_t n = v.size();
  if (n < 2) return;
  std::vector<T, A> spare(n);
  constexpr std::size_t kDigits = 2048, kBlock = 16384;
  if (n < 2 * kBlock || thread_count() == 1) {
    std::vector<std::uint32_t> count(kDigits + 1);
    for (int shift = 0; shift < bits; shift += 11) {
      std::fill(count.begin(), count.end(), 0u);
      for (const T& x : v) ++count[((key(x) >> shift) & 0x7ff) + 1];
      if (count[1 + ((key(v[0]) >> shift) & 0x7ff)] == n) continue;  // one digit everywhere
      for (std::size_t d = 0; d < kDigits; ++d) count[d + 1] += count[d];
      for (const T& x : v) spare[count[(key(x) >> shift) & 0x7ff]++] = x;
      v.swap(spare);
    }
    return;
  }
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::uint32_t> at(blocks * kDigits);  // per block and digit: a count, then where it goes
  std::vector<std::uint32_t> run(kDigits + 1);
  for (int shift = 0; shift < bits; shift += 11) {
    parallel_for(0, blocks, [&](std::size_t b) {
      std::uint32_t* c = at.data() + b * kDigits;
      std::fill(c, c + kDigits, 0u);
      for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) ++c[(key(v[i]) >> shift) & 0x7ff];
    });
    // Where each digit starts (its total over the blocks, summed in order), then each block's
    // place in it (the earlier blocks' counts added): both in the blocks' own order of memory.
    std::fill(run.begin(), run.end(), 0u);
    for (std::size_t b = 0; b < blocks; ++b)
      for (std::size_t d = 0; d < kDigits; ++d) run[d + 1] += at[b * kDigits + d];
    if (run[1 + ((key(v[0]) >> shift) & 0x7ff)] == n) continue;  // one digit everywhere
    for (std::size_t d = 0; d < kDigits; ++d) run[d + 1] += run[d];
    for (std::size_t b = 0; b < blocks; ++b)
      for (std::size_t d = 0; d < kDigits; ++d) {
        const std::uint32_t c = at[b * kDigits + d];
        at[b * kDigits + d] = run[d];
        run[d] += c;
      }
    parallel_for(0, blocks, [&](std::size_t b) {
      std::uint32_t* to = at.data() + b * kDigits;
      for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) spare[to[(key(v[i]) >> shift) & 0x7ff]++] = v[i];
    });
    v.swap(spare);
  }
}

// The middle of a counting sort done over chunks of the items at once: counts[c][k] (chunk c's
// items of key k, for keys 0 .. keys - 1) become where chunk c's items of key k go (keys in order,
// each key's chunks in order), and off[k] where key k's items start (off holds keys + 1 entries).
// Per block of keys in parallel, from the block's start.
template <class Off>
inline void chunk_offsets(std::vector<std::vector<std::uint32_t>>& counts, std::size_t keys, Off& off) {
  const std::size_t chunks = counts.size();
  const auto from = block_starts(keys, 16384, [&](std::size_t lo, std::size_t hi) {
    std::size_t n = 0;
    for (std::size_t k = lo; k < hi; ++k)
      for (std::size_t c = 0; c < chunks; ++c) n += counts[c][k];
    return n;
  });
  fill_blocks(from, [&](std::size_t lo, std::size_t hi, std::size_t at) {
    for (std::size_t k = lo; k < hi; ++k) {
      off[k] = static_cast<std::uint32_t>(at);
      for (std::size_t c = 0; c < chunks; ++c) {
        const std::uint32_t n = counts[c][k];
        counts[c][k] = static_cast<std::uint32_t>(at);
        at += n;
      }
    }
  });
  off[keys] = static_cast<std::uint32_t>(from.total());
}

}  // namespace wedge::boolean_detail
