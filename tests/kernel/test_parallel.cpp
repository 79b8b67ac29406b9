// wedge::parallel_for inside a task group that a sibling's exception cancels. TBB then cuts the
// nested loop short without an exception of its own; a caller that went on used results never
// made: a CSG tree with a failing operand beside a busy one crashed (s = s + s:mirror("x")
// :translate(...), six times: SIGSEGV in the boolean's corner sums, or a null operand). The loop
// must throw instead, and the sibling's exception must be the one the outer caller sees.
#include <catch2/catch.hpp>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

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
