// What the three files of the boolean fuzzer share: fuzz_boolean.cpp (the driver: options, one
// forked child per case under a watchdog, the case files, the report), fuzz_generators.cpp (the
// adversarial cases) and fuzz_checks.cpp (running a boolean and checking it against the engine's
// promise). A case, the random helpers, the outcome counters a child shares with the driver, and
// the run's state.
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "csg/boolean.h"
#include "kernel/mesh.h"
#include "kernel/types.h"
#include "bench/csg/off_file.h"

namespace wedge::fuzz {

// ---------------------------------------------------------------- random numbers
using Rng = std::mt19937_64;
inline double uni(Rng& r, double a, double b) { return std::uniform_real_distribution<double>(a, b)(r); }
inline int irand(Rng& r, int a, int b) { return std::uniform_int_distribution<int>(a, b)(r); }
inline double ir(Rng& r, int a, int b) { return irand(r, a, b); }  // an integer as a coordinate
inline bool coin(Rng& r, double p = 0.5) { return uni(r, 0, 1) < p; }
Vec3 rand_dir(Rng& r);  // a unit vector, uniform over the sphere

// ---------------------------------------------------------------- mesh helpers (fuzz_generators.cpp)
Mesh rot(const Mesh& m, double deg, const Vec3& axis, const Point3& pivot);
Mesh moved(const Mesh& m, const Vec3& d);
Mesh scaled_pow2(const Mesh& m, int e);  // every coordinate times 2^e (exact unless it leaves the normal range)
Mesh flipped(const Mesh& m);             // every triangle reversed
Vec3 vertex_mean(const Mesh& m);         // inside a convex operand

// ---------------------------------------------------------------- a case
struct Case {
  std::vector<Mesh> ops;
  bool bad = false;  // operand bad_index deliberately invalid: every op must throw naming it
  int bad_index = -1;
  bool mendable = false;  // ... or, for this kind of bad operand, may mend it and give a valid result
  bool axis_boxes = false;  // operands are the axis-parallel `boxes` (boxes_volume is the reference)
  std::vector<std::array<Vec3, 2>> boxes;
  int pow2 = 0;        // operands are a unit-size case scaled by 2^pow2: volumes compared scaled back
  bool chain = false;  // run as a chain of steps (ops[0], then each later operand with a random op)
  bool no_oracle = false;  // CGAL's corefinement not asked (it runs for minutes on such operands)
  std::string note;    // which variant the generator chose (in failure messages)
};

struct Gen {
  const char* name;
  Case (*make)(Rng&);
};
const std::vector<Gen>& generators();

// ---------------------------------------------------------------- outcomes
// Per boolean, or per case for a crash, a hang or an error of the fuzzer itself (harness). ok,
// unroundable, budget, subnormal (an operand with a subnormal coordinate, refused by the engine),
// slow and skipped-operand are counts; harness errors are reported apart; the rest are failures.
enum Outcome {
  kOk, kUnroundable, kBudget, kSubnormal, kError, kInvalid, kPinchMerged, kPinchNew, kVolume, kOracle, kBadAccepted,
  kBadMsg, kBitsDiffer, kCrash, kHang, kSlow, kSkipped, kHarness, kOutcomes
};
inline constexpr const char* kOutcomeName[kOutcomes] = {
    "ok", "unroundable", "budget", "subnormal", "error", "invalid", "pinch-merged", "pinch-new", "volume", "oracle",
    "bad-accepted", "bad-message", "bits-differ", "crash", "hang", "slow(>2s)", "skipped-operand", "harness-error"};

// In memory shared by the driver and its children (mmap, MAP_SHARED): a child counts, the driver
// reads bool_start while the child runs and the rest once it has ended.
constexpr int kMaxGens = 32;
struct Shared {
  std::atomic<double> bool_start;  // wall time (now_s) the running boolean started, 0 when none runs
  int booleans[kMaxGens];
  int outcome[kMaxGens][kOutcomes];
  int failures;
  char current[512];  // what the child is doing (for the driver's hang and crash reports)
};
static_assert(std::atomic<double>::is_always_lock_free, "bool_start is shared between processes");

struct State {
  Shared* shared = nullptr;
  int gen = 0;                 // index in generators() of the running case
  std::string out = "/tmp/fuzz";
  std::string case_name;       // "<gen>_<seed>"
  std::uint64_t seed = 0;
  int fail_k = 0;              // folders the running case has saved so far (numbers them)
  double hang = 30;            // seconds a boolean may take before it counts as a hang (a case: 20 times that)
  int threads_every = 8;       // one op of every threads_every-th seed runs again at 2 threads
};
inline State state;

inline void count(Outcome o) { ++state.shared->outcome[state.gen][o]; }
double now_s();  // steady clock, seconds

// ---------------------------------------------------------------- case files (fuzz_boolean.cpp)
// write_off and read_off: off_file.h.
// DIR/operandNN.off (earlier .off files removed) and DIR/op.txt.
void save_operands(const std::string& dir, BooleanOp op, const std::vector<const Mesh*>& ops);
// The same and DIR/README: `what`, and how to replay the case and make it again.
void save_case(const std::string& dir, BooleanOp op, const std::vector<const Mesh*>& ops, const std::string& what);
// Counts a failure of the running case, prints it, and (the first 6 of each kind per generator)
// saves its operands to OUT/fail/<gen>_<seed>_<k>/ with a README.
void record_failure(Outcome o, BooleanOp op, const std::vector<const Mesh*>& ops, const std::string& what);

// ---------------------------------------------------------------- checks (fuzz_checks.cpp)
void set_threads(int n);  // TBB's thread limit for the booleans that follow (0: TBB's default)
// Runs a case's booleans and checks each against the promise, counting outcomes; `r` continues
// the case's stream (a chain's choices).
void run_case(const Case& c, Rng& r);
// CGAL's exact corefinement in a forked process (it crashes on some of these inputs): true with
// its exact volume, rounded once, in `volume`; false when it refused or crashed, or an operand
// has touching shells or several shells.
bool oracle_volume(BooleanOp op, const std::vector<const Mesh*>& ops, double* volume);

}  // namespace wedge::fuzz
