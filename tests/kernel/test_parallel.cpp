// wedge::parallel_for inside a task group that a sibling's exception cancels. TBB then cuts the
// nested loop short without an exception of its own; a caller that went on used results never
// made: a CSG tree with a failing operand beside a busy one crashed (s = s + s:mirror("x")
// :translate(...), six times: SIGSEGV in the boolean's corner sums, or a null operand). The loop
// must throw instead, and the sibling's exception must be the one the outer caller sees.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "kernel/parallel.h"

using namespace wedge;

TEST_CASE("a nested parallel_for cut short by a sibling's failure throws instead of returning", "[kernel][parallel]") {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  std::atomic<bool> inner_started{false}, inner_returned{false};
  std::atomic<std::size_t> inner_done{0};
  constexpr std::size_t kInner = 1000;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  bool concurrent = true;
  try {
    tbb::parallel_for(0, 2, 1, [&](int i) {
      if (i == 0) {
        // Fail once the other task is inside its loop (or give up waiting: one thread only).
        while (!inner_started && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
        if (!inner_started) concurrent = false;
        throw std::runtime_error("the sibling's failure");
      }
      parallel_for(0, kInner, [&](std::size_t) {
        inner_started = true;
        // Each iteration waits until the group is cancelled, so the loop cannot finish first.
        while (!tbb::is_current_task_group_canceling() && std::chrono::steady_clock::now() < deadline)
          std::this_thread::yield();
        ++inner_done;
      });
      inner_returned = true;  // reached only if the cut-short loop returned normally
    });
    FAIL("the sibling's exception did not propagate");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()) == "the sibling's failure");
  }
  if (!concurrent) {
    WARN("one thread only: the two tasks did not run at once");
    return;
  }
  CHECK(inner_done < kInner);  // the loop was cut short ...
  CHECK_FALSE(inner_returned);  // ... and said so
}

TEST_CASE("block compaction and prefix sums give the serial result, blocks of any size, at one and two threads",
          "[kernel][parallel]") {
  // Keep every item whose value is divisible by 3; each item counts value % 5 outputs.
  std::vector<unsigned> value(100003);
  for (std::size_t i = 0; i < value.size(); ++i) value[i] = static_cast<unsigned>((i * 2654435761u) >> 7);
  std::vector<unsigned> kept_serial, prefix_serial{0};
  for (unsigned v : value) {
    if (v % 3 == 0) kept_serial.push_back(v);
    prefix_serial.push_back(prefix_serial.back() + v % 5);
  }
  for (int threads : {1, 2})
    for (std::size_t block : {std::size_t(1), std::size_t(7), std::size_t(4096), std::size_t(1) << 20}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const auto from = block_starts(value.size(), block, [&](std::size_t lo, std::size_t hi) {
        std::size_t n = 0;
        for (std::size_t i = lo; i < hi; ++i) n += value[i] % 3 == 0;
        return n;
      });
      REQUIRE(from.from.size() == (value.size() + block - 1) / block + 1);
      std::vector<unsigned> kept(from.total());
      fill_blocks(from, [&](std::size_t lo, std::size_t hi, std::size_t w) {
        for (std::size_t i = lo; i < hi; ++i)
          if (value[i] % 3 == 0) kept[w++] = value[i];
      });
      CHECK(kept == kept_serial);
      std::vector<unsigned> prefix;
      parallel_prefix(prefix, value.size(), block, [&](std::size_t i) { return value[i] % 5; });
      CHECK(prefix == prefix_serial);
      std::vector<char> seen(value.size(), 0);
      parallel_blocks(value.size(), block, [&](std::size_t lo, std::size_t hi) {
        for (std::size_t i = lo; i < hi; ++i) ++seen[i];
      });
      CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<std::ptrdiff_t>(value.size()));
    }
  std::vector<unsigned> none;
  parallel_prefix(none, 0, 64, [](std::size_t) { return 1u; });
  CHECK(none == std::vector<unsigned>{0});
  CHECK(block_starts(0, 64, [](std::size_t, std::size_t) { return std::size_t(1); }).from == std::vector<std::size_t>{0});
}

TEST_CASE("parallel_invoke runs both halves and passes a half's failure on", "[kernel][parallel]") {
  for (int threads : {1, 2}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    std::vector<int> a, b;
    parallel_invoke([&] { a.assign(1000, 1); }, [&] { parallel_for(0, 1000, [&](std::size_t) {}), b.assign(500, 2); });
    CHECK(a == std::vector<int>(1000, 1));
    CHECK(b == std::vector<int>(500, 2));
    std::atomic<bool> other_ran{false};
    CHECK_THROWS_WITH(parallel_invoke([&] { throw Error("the first half failed"); }, [&] { other_ran = true; }),
                      "the first half failed");
    CHECK_THROWS_WITH(parallel_invoke([&] { other_ran = true; }, [&] { throw Error("the second half failed"); }),
                      "the second half failed");
  }
}
