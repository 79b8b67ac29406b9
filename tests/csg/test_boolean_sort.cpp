// radix_sort, the engine's stable sort by a 64-bit key: against std::stable_sort, serial and by
// blocks in parallel (above 32,768 elements with more than one thread), on keys that share
// digits (passes left out), keys with few values (long runs of equal keys, where stability
// shows) and random full-width keys.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <tbb/global_control.h>

#include "csg/boolean_impl.h"

using namespace wedge::boolean_detail;

namespace {
struct Item {
  std::uint64_t key;
  std::uint32_t at;  // its place before sorting: equal keys must keep their order
};

std::vector<Item> items(std::size_t n, int kind, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Item> v(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t k = rng();
    if (kind == 1) k %= 7;                                    // few values: long runs of equals
    if (kind == 2) k = (k & 0x7ff00000000ull) | 0x5000000000000000ull;  // one digit varies
    if (kind == 3) k = 42;                                    // all equal: every pass left out
    v[i] = {k, static_cast<std::uint32_t>(i)};
  }
  return v;
}
}  // namespace

TEST_CASE("boolean: radix_sort orders stably by key, serially and by blocks in parallel", "[boolean][sort]") {
  for (const std::size_t threads : {1, 2}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    for (const std::size_t n : {std::size_t(0), std::size_t(1), std::size_t(1000), std::size_t(40000), std::size_t(100003)})
      for (int kind = 0; kind < 4; ++kind) {
        INFO("threads " << threads << ", n " << n << ", kind " << kind);
        auto v = items(n, kind, static_cast<std::uint32_t>(n * 4 + kind));
        auto want = v;
        std::stable_sort(want.begin(), want.end(), [](const Item& a, const Item& b) { return a.key < b.key; });
        radix_sort(v, [](const Item& x) { return x.key; });
        REQUIRE(v.size() == want.size());
        bool same = true;
        for (std::size_t i = 0; i < n && same; ++i) same = v[i].key == want[i].key && v[i].at == want[i].at;
        REQUIRE(same);
      }
  }
}
