// A hostile fuzzer for the exact mesh-boolean engine (csg/boolean.h). Seeded random cases from
// adversarial generators (fuzz_generators.cpp: coarse grids with exact coplanarities, copies a few
// ulps or 1e-9 rad apart, touching and nested operands, n-ary unions through one point, slivers,
// extreme scales, chains of results, skinny fans, cavities, bad operands), each boolean checked
// against the engine's promise (fuzz_checks.cpp: valid results, exact volume identities, CGAL's
// exact corefinement on small cases, the same bits at 1 and 2 threads, errors naming a bad
// operand). This file is the driver: each case runs in a forked child under a watchdog (a boolean
// over --hang seconds, or a case over 20 times that, is a hang); a crash or a hang leaves the
// operands of the boolean that was running.
//
//   fuzz_boolean [--gen a,b,...] [--seed N] [--cases N] [--minutes M] [--out DIR] [--hang S]
//                [--threads-every N]
//   fuzz_boolean --replay DIR [--op union|intersection|difference] [--pow2 E] [--crop X Y Z R]
//                [--save DIR2]
//   fuzz_boolean --list
//
// Failures go to OUT/fail/<gen>_<seed>_<k>/ (the first 6 of each kind per generator; crashes and
// hangs to OUT/fail/<gen>_<seed>_crash|hang/): the operands as OFF with %.17g, op.txt, and a README
// saying how to replay the boolean and make the case again. Results the engine cannot round to
// doubles go to OUT/unroundable/, booleans over 2 s to OUT/slow/ (the first 6 per generator). The
// per-generator counts go to stdout at the end; the exit status is 1 if anything failed.
// --replay runs the boolean of such a folder again at one thread (scaled by 2^E, each operand
// cropped to the cube of half side R about (X, Y, Z) first, if asked; the operands so changed
// saved to DIR2) and prints what the checks see, then CGAL's volume; the result goes to DIR2 (or
// DIR)/result.off.out. Run it niced: it is CPU-bound (and a build beside it makes cases "slow").
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/csg/fuzz_boolean.h"
#include "kernel/error.h"
#include "tests/support/boolean_cases.h"
#include "tests/support/cgal_oracle.h"

namespace fs = std::filesystem;

namespace wedge::fuzz {

double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// ---------------------------------------------------------------- case files
namespace {

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

// The lines of a README after what happened: how to run the boolean again and make the case again.
std::string how_to_rerun(const std::string& dir) {
  return "\nreplay (where operand files are here): fuzz_boolean --replay " + dir +
         "\nmake the case again: fuzz_boolean --gen " + generators()[state.gen].name + " --seed " +
         std::to_string(state.seed) + " --cases 1\n";
}

}  // namespace

void save_operands(const std::string& dir, BooleanOp op, const std::vector<const Mesh*>& ops) {
  fs::create_directories(dir);
  std::vector<fs::path> old;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".off") old.push_back(e.path());
  for (const auto& p : old) fs::remove(p);
  for (std::size_t i = 0; i < ops.size(); ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "/operand%02zu.off", i);
    write_off(dir + name, *ops[i]);
  }
  write_text(dir + "/op.txt", std::string(boolean_op_name(op)) + "\n");
}

void save_case(const std::string& dir, BooleanOp op, const std::vector<const Mesh*>& ops, const std::string& what) {
  save_operands(dir, op, ops);
  write_text(dir + "/README", what + how_to_rerun(dir));
}

void record_failure(Outcome o, BooleanOp op, const std::vector<const Mesh*>& ops, const std::string& what) {
  count(o);
  ++state.shared->failures;
  const char* name = boolean_op_name(op);
  if (state.shared->outcome[state.gen][o] > 6) {  // enough of this kind from this generator: report, do not save
    std::printf("FAIL %s %s %s (not saved): %s\n", state.case_name.c_str(), name, kOutcomeName[o], what.c_str());
    return;
  }
  const std::string dir = state.out + "/fail/" + state.case_name + "_" + std::to_string(state.fail_k++);
  save_case(dir, op, ops, std::string(name) + ": " + kOutcomeName[o] + ": " + what);
  std::printf("FAIL %s %s %s: %s (%s)\n", state.case_name.c_str(), name, kOutcomeName[o], what.c_str(), dir.c_str());
}

namespace {

// ---------------------------------------------------------------- replay
struct ReplayOptions {
  std::string dir;
  std::string op;    // instead of DIR/op.txt's
  int pow2 = 0;      // scale the operands by 2^pow2 first
  double crop_r = 0;  // crop each operand to the cube of half side crop_r about crop_c (an intersection by the engine)
  Vec3 crop_c = Vec3::Zero();
  std::string save;  // where the operands so changed, and the result, go
};

int replay(const ReplayOptions& o) {
  state.case_name = o.dir;
  const BooleanOp op = o.op.empty() ? read_case_op(o.dir) : parse_op(o.op);
  std::vector<Mesh> ms = read_case_operands(o.dir);
  if (o.pow2)
    for (auto& m : ms) m = scaled_pow2(m, o.pow2);
  if (o.crop_r > 0) {
    const Mesh box = wedge::testing::box_mesh(o.crop_c - Vec3(1, 1, 1) * o.crop_r, Vec3(2, 2, 2) * o.crop_r);
    for (auto& m : ms) {
      m = boolean(BooleanOp::Intersection, {&m, &box}).mesh;
      m.face_ids.clear();
    }
  }
  std::vector<const Mesh*> ops;
  for (auto& m : ms) ops.push_back(&m);
  if (!o.save.empty()) save_operands(o.save, op, ops);
  for (std::size_t i = 0; i < ms.size(); ++i)
    std::printf("operand %zu: %zu triangles, exact volume %.17g, defect '%s'\n", i + 1, ms[i].triangles.size(),
                wedge::testing::exact_volume(ms[i]), wedge::testing::result_defect(ms[i]).c_str());
  set_threads(1);
  const double t0 = now_s();
  try {
    BooleanStats st;
    const BooleanResult r = boolean(op, ops, &st);
    std::printf("%s: %.3f s, %zu triangles, welded %zu, reorders %zu, resolutions %zu, collapses %zu, flat shells %zu\n",
                boolean_op_name(op), now_s() - t0, r.mesh.triangles.size(), st.welded, st.reorders, st.resolutions, st.collapses,
                st.flat_shells);
    std::string where;
    const bool crosses = wedge::testing::exact_self_intersects(r.mesh, &where);
    std::printf("result defect: '%s'\nclosed_manifold_outward: '%s'\nexact self-intersection: %s %s\n"
                "mesh_solid_defect: '%s'\nexact volume %.17g\n",
                wedge::testing::result_defect(r.mesh).c_str(), wedge::testing::closed_manifold_outward(r.mesh).c_str(),
                crosses ? "YES" : "no", where.c_str(), mesh_solid_defect(r.mesh, "result").c_str(),
                wedge::testing::exact_volume(r.mesh));
    write_off((o.save.empty() ? o.dir : o.save) + "/result.off.out", r.mesh);
  } catch (const Error& e) {
    std::printf("%s: wedge::Error after %.3f s: %s\n", boolean_op_name(op), now_s() - t0, e.what());
  }
  // (CGAL's corefinement of many nearly coincident operands can take many minutes: 5 at most.)
  double volume = 0;
  const bool ok = ops.size() <= 5 && oracle_volume(op, ops, &volume);
  std::printf("CGAL: %s volume %.17g\n", ok ? "ok" : "refused/crashed/skipped (touching shells, > 5 operands)", volume);
  return 0;
}

// ---------------------------------------------------------------- a case in a child
constexpr int kHarnessExit = 3;  // a child's exit status for an error of the fuzzer itself

[[noreturn]] void run_child(pid_t driver) {
  // Dies with the driver (a fuzz run stopped by a signal leaves no case running).
  if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != driver) _exit(1);
  int status = 0;
  try {
    set_threads(1);
    Rng r(state.seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(state.gen) * 1000003ull);
    bool made = false;
    Case c;
    try {
      c = generators()[state.gen].make(r);
      made = true;
    } catch (const std::exception& e) {  // nonmanifold_ops makes an operand by the engine
      record_failure(kError, BooleanOp::Union, {}, std::string("the generator threw: ") + e.what());
    }
    if (made) run_case(c, r);
    fs::remove_all(state.out + "/work/" + std::to_string(getpid()));
  } catch (const std::exception& e) {
    std::printf("HARNESS-ERROR %s: %s\n", state.case_name.c_str(), e.what());
    status = kHarnessExit;
  }
  std::fflush(stdout);
  _exit(status);
}

// Moves the child's work folder (the operands of the boolean it was running, if it ran one) to
// OUT/fail/<case>_<suffix>/ and writes its README there; reports what it cannot do.
void keep_work(pid_t pid, const std::string& suffix, const std::string& what) {
  const std::string work = state.out + "/work/" + std::to_string(pid);
  const std::string dir = state.out + "/fail/" + state.case_name + "_" + suffix;
  std::error_code ec;
  fs::remove_all(dir, ec);
  if (fs::exists(work, ec)) fs::rename(work, dir, ec);
  else fs::create_directories(dir, ec);
  if (ec) std::fprintf(stderr, "fuzz_boolean: cannot keep %s as %s: %s\n", work.c_str(), dir.c_str(), ec.message().c_str());
  try {
    write_text(dir + "/README", what + how_to_rerun(dir));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_boolean: %s\n", e.what());
  }
}

// Waits for the case's child, killing it on a hang, and counts how it ended.
void watch(pid_t pid) {
  Shared& sh = *state.shared;
  const double start = now_s();
  int status = 0;
  for (;;) {
    const pid_t w = waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (w < 0) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    const double bs = sh.bool_start, t = now_s();
    if ((bs > 0 && t - bs > state.hang) || t - start > 20 * state.hang) {
      kill(pid, SIGKILL);  // its CGAL child, if any, dies with it
      waitpid(pid, &status, 0);
      ++sh.outcome[state.gen][kHang];
      ++sh.failures;
      std::ostringstream what;
      what << "hang: " << sh.current << " ran over " << (bs > 0 ? state.hang : 20 * state.hang) << " s ("
           << (bs > 0 ? "in a boolean" : "the case in all") << ")";
      keep_work(pid, "hang", what.str());
      std::printf("FAIL %s %s\n", state.case_name.c_str(), what.str().c_str());
      return;
    }
    usleep(20000);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  if (WIFEXITED(status) && WEXITSTATUS(status) == kHarnessExit) {
    ++sh.outcome[state.gen][kHarness];
    keep_work(pid, "harness", std::string("error of the fuzzer during ") + sh.current);
    return;
  }
  ++sh.outcome[state.gen][kCrash];
  ++sh.failures;
  const std::string how = WIFSIGNALED(status) ? std::string("signal ") + strsignal(WTERMSIG(status))
                                              : "exit status " + std::to_string(WEXITSTATUS(status));
  keep_work(pid, "crash", "crash (" + how + ") during " + sh.current);
  std::printf("FAIL %s crash (%s) during %s\n", state.case_name.c_str(), how.c_str(), sh.current);
}

// Prints the counts; returns the failures and harness errors.
int print_table(const std::vector<int>& chosen, long cases) {
  const Shared& sh = *state.shared;
  std::printf("\n%-16s %8s", "generator", "booleans");
  for (const char* name : kOutcomeName) std::printf(" %s", name);
  std::printf("\n");
  int harness = 0;
  for (int gi : chosen) {
    std::printf("%-16s %8d", generators()[gi].name, sh.booleans[gi]);
    for (int o = 0; o < kOutcomes; ++o) std::printf(" %*d", static_cast<int>(std::strlen(kOutcomeName[o])), sh.outcome[gi][o]);
    std::printf("\n");
    harness += sh.outcome[gi][kHarness];
  }
  std::printf("cases %ld, failures %d, harness errors %d\n", cases, sh.failures, harness);
  return sh.failures + harness;
}

const char* const kUsage =
    "usage: fuzz_boolean [--gen a,b,...] [--seed N] [--cases N] [--minutes M] [--out DIR] [--hang S]\n"
    "                    [--threads-every N]\n"
    "       fuzz_boolean --replay DIR [--op union|intersection|difference] [--pow2 E] [--crop X Y Z R]\n"
    "                    [--save DIR2]\n"
    "       fuzz_boolean --list\n"
    "Defaults: all generators, seed 1, 1000000 cases, 10 minutes, out /tmp/fuzz, hang 30 s, threads-every 8.\n";

int run(int argc, char** argv) {
  std::vector<std::string> gens;
  std::uint64_t seed0 = 1;
  long cases = 1000000;
  double minutes = 10;
  ReplayOptions rp;
  bool replaying = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " wants a value");
      return argv[++i];
    };
    const auto number = [&]() {
      const std::string s = next();
      char* end = nullptr;
      const double x = std::strtod(s.c_str(), &end);
      if (s.empty() || *end != '\0') throw std::runtime_error(a + " wants a number, not '" + s + "'");
      return x;
    };
    const auto whole = [&]() {
      const std::string s = next();
      char* end = nullptr;
      errno = 0;
      const unsigned long long x = std::strtoull(s.c_str(), &end, 10);
      if (s.empty() || s[0] == '-' || *end != '\0' || errno) throw std::runtime_error(a + " wants a whole number, not '" + s + "'");
      return x;
    };
    if (a == "--help" || a == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (a == "--list") {
      for (const auto& g : generators()) std::printf("%s\n", g.name);
      return 0;
    } else if (a == "--replay") {
      rp.dir = next();
      replaying = true;
    } else if (a == "--op") rp.op = next();
    else if (a == "--pow2") rp.pow2 = static_cast<int>(number());
    else if (a == "--crop") {
      for (int k = 0; k < 3; ++k) rp.crop_c[k] = number();
      rp.crop_r = number();
    } else if (a == "--save") rp.save = next();
    else if (a == "--gen") {
      std::stringstream ss(next());
      for (std::string s; std::getline(ss, s, ',');) gens.push_back(s);
    } else if (a == "--seed") seed0 = whole();
    else if (a == "--cases") cases = static_cast<long>(whole());
    else if (a == "--minutes") minutes = number();
    else if (a == "--out") state.out = next();
    else if (a == "--hang") state.hang = number();
    else if (a == "--threads-every") state.threads_every = static_cast<int>(std::min(whole(), 1000000ull));
    else {
      std::fprintf(stderr, "unknown argument %s\n%s", a.c_str(), kUsage);
      return 2;
    }
  }
  if (replaying) return replay(rp);
  if (state.threads_every < 1) throw std::runtime_error("--threads-every wants a whole number from 1");
  if (generators().size() > static_cast<std::size_t>(kMaxGens)) throw std::runtime_error("more generators than Shared has room for");
  for (const auto& g : gens)
    if (std::none_of(generators().begin(), generators().end(), [&](const Gen& x) { return g == x.name; }))
      throw std::runtime_error("no generator '" + g + "' (--list lists them)");
  std::vector<int> chosen;
  for (int i = 0; i < static_cast<int>(generators().size()); ++i)
    if (gens.empty() || std::find(gens.begin(), gens.end(), generators()[i].name) != gens.end()) chosen.push_back(i);
  fs::create_directories(state.out + "/fail");
  fs::create_directories(state.out + "/work");
  void* mem = mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (mem == MAP_FAILED) throw std::runtime_error(std::string("mmap: ") + std::strerror(errno));
  state.shared = new (mem) Shared();
  const pid_t driver = getpid();
  const double end = now_s() + 60 * minutes;
  long done = 0;
  for (std::uint64_t seed = seed0; done < cases && now_s() < end; ++seed) {
    for (int gi : chosen) {
      if (done >= cases || now_s() >= end) break;
      state.gen = gi;
      state.seed = seed;
      state.case_name = std::string(generators()[gi].name) + "_" + std::to_string(seed);
      state.fail_k = 0;
      state.shared->bool_start = 0;  // a crashed or killed child may have left it set
      std::snprintf(state.shared->current, sizeof state.shared->current, "%s (before its first boolean)",
                    state.case_name.c_str());
      std::fflush(stdout);
      const pid_t pid = fork();
      if (pid < 0) {
        std::fprintf(stderr, "fuzz_boolean: fork: %s; stopping\n", std::strerror(errno));
        print_table(chosen, done);
        return 1;
      }
      if (pid == 0) run_child(driver);
      ++done;
      watch(pid);
    }
  }
  return print_table(chosen, done) > 0 ? 1 : 0;
}

}  // namespace
}  // namespace wedge::fuzz

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // whole lines, also from a child that crashes
  try {
    return wedge::fuzz::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_boolean: %s\n", e.what());
    return 2;
  }
}
