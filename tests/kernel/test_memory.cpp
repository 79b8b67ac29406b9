// The cache of large blocks kept between runs (kernel/memory.h): which requests a kept block
// serves, what it counts and frees, and a Kept vector's contents when its block is reused.
#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

#include <tbb/global_control.h>

#include "kernel/memory.h"
#include "kernel/parallel.h"

using namespace wedge;

namespace {
constexpr std::size_t kMiB = std::size_t{1} << 20;
}

TEST_CASE("a kept block serves the next request between half its size and its size", "[kernel][memory]") {
  release_kept_blocks();
  void* p = take_block(4 * kMiB);
  give_block(p, 4 * kMiB);
  CHECK(kept_bytes() == 4 * kMiB);
  // Larger than the block, or less than half of it: not this block.
  void* larger = take_block(4 * kMiB + 1);
  CHECK(larger != p);
  void* smaller = take_block(2 * kMiB - 1);
  CHECK(smaller != p);
  CHECK(kept_bytes() == 4 * kMiB);
  // Between: the block itself, lent for fewer bytes; given back, it counts at its full size.
  void* again = take_block(3 * kMiB);
  CHECK(again == p);
  CHECK(kept_bytes() == 0);
  give_block(again, 3 * kMiB);
  CHECK(kept_bytes() == 4 * kMiB);
  give_block(larger, 4 * kMiB + 1);
  give_block(smaller, 2 * kMiB - 1);
  CHECK(kept_bytes() == 10 * kMiB);
  // The smallest block that serves is the one lent (here both 4 MiB blocks would).
  void* best = take_block(2 * kMiB + 1);
  CHECK(best == p);
  give_block(best, 2 * kMiB + 1);
  release_kept_blocks();
  CHECK(kept_bytes() == 0);
}

TEST_CASE("small blocks are not kept, and the kept bytes stay under the cap, the oldest freed first",
          "[kernel][memory]") {
  release_kept_blocks();
  void* small = take_block(100 * 1024);
  give_block(small, 100 * 1024);
  CHECK(kept_bytes() == 0);
  give_block(nullptr, 8 * kMiB);
  CHECK(kept_bytes() == 0);
  // (Blocks of 200 MiB are reserved, never touched: no page of them is faulted in.)
  void* a = take_block(200 * kMiB);
  void* b = take_block(200 * kMiB);
  void* c = take_block(200 * kMiB);
  give_block(a, 200 * kMiB);
  give_block(b, 200 * kMiB);
  CHECK(kept_bytes() == 400 * kMiB);
  give_block(c, 200 * kMiB);  // 600 MiB is over the cap of 512: `a` goes
  CHECK(kept_bytes() == 400 * kMiB);
  void* first = take_block(200 * kMiB);
  void* second = take_block(200 * kMiB);
  CHECK(((first == b && second == c) || (first == c && second == b)));
  give_block(first, 200 * kMiB);
  give_block(second, 200 * kMiB);
  release_kept_blocks();
  CHECK(kept_bytes() == 0);
}

TEST_CASE("a Kept vector reuses a block and still starts from value-initialized elements", "[kernel][memory]") {
  release_kept_blocks();
  const std::uint32_t* data = nullptr;
  {
    std::vector<std::uint32_t, Kept<std::uint32_t>> v(kMiB, 0xdeadbeefu);
    data = v.data();
  }
  CHECK(kept_bytes() == 4 * kMiB);
  std::vector<std::uint32_t, Kept<std::uint32_t>> w(kMiB);
  CHECK(w.data() == data);
  bool zero = true;
  for (std::uint32_t x : w) zero = zero && x == 0;
  CHECK(zero);
  // Growth gives the old block back and takes a new one.
  w.resize(3 * kMiB);
  CHECK(w.data() != data);
  CHECK(kept_bytes() == 4 * kMiB);
  CHECK(w[kMiB - 1] == 0);
  CHECK(w[3 * kMiB - 1] == 0);
}

TEST_CASE("blocks taken and given back on several threads at once are all accounted for", "[kernel][memory]") {
  release_kept_blocks();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 4);
  // Each round takes and gives back blocks of 1 to 4 MiB on every thread.
  parallel_for(0, 256, [](std::size_t i) {
    const std::size_t bytes = (1 + i % 4) * kMiB;
    auto* p = static_cast<unsigned char*>(take_block(bytes));
    p[0] = static_cast<unsigned char>(i);
    p[bytes - 1] = static_cast<unsigned char>(i);
    CHECK((p[0] == p[bytes - 1]));
    give_block(p, bytes);
  });
  const std::size_t kept = kept_bytes();
  CHECK(kept > 0);
  CHECK(kept <= 512 * kMiB);
  // The blocks of 1 and 2 MiB are lent again for 1 MiB each; given back, each counts in full.
  std::vector<void*> taken;
  for (;;) {
    const std::size_t before = kept_bytes();
    void* p = take_block(kMiB);
    if (kept_bytes() == before) {  // a new block: no kept one serves
      ::operator delete(p);
      break;
    }
    taken.push_back(p);
  }
  CHECK(!taken.empty());
  for (void* p : taken) give_block(p, kMiB);
  CHECK(kept_bytes() == kept);
  release_kept_blocks();
  CHECK(kept_bytes() == 0);
}
