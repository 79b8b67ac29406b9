// The boolean fuzzer's checks (see fuzz_boolean.cpp): a case's booleans run at one thread and
// judged against the engine's promise (csg/boolean.h). On valid operands each of the three ops
// must give a valid result (tests/support result_defect: closed, 2-manifold, outward by its exact
// volume sign, no exact self-intersection; and the engine's own mesh_solid_defect) with one
// operand and source per triangle; its exact volume must keep vol(A u B) + vol(A n B) = vol A +
// vol B and vol(A - B) = vol A - vol(A n B) (n operands: A - rest against A n union(rest), and
// the one-pass union against a pairwise fold), stay within the bounds of each op, and match CGAL's
// exact corefinement (small cases) or boxes_volume (axis-parallel boxes). One op of every
// threads_every-th seed runs again at 2 threads and must give the same bits. A bad operand must
// be refused with a wedge::Error naming it. Results the engine cannot round to doubles ("cannot
// be rounded") and booleans over the work budget are allowed, and counted apart.
#include <poll.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "bench/csg/fuzz_boolean.h"
#include "csg/membership.h"
#include "kernel/error.h"
#include "kernel/transform.h"
#include "tests/support/boolean_cases.h"
#include "tests/support/cgal_oracle.h"

namespace wedge::fuzz {

using namespace wedge::testing;

namespace {

std::unique_ptr<tbb::global_control> g_thread_limit;  // the limit set_threads keeps alive

constexpr BooleanOp kOps[3] = {BooleanOp::Union, BooleanOp::Intersection, BooleanOp::Difference};

struct Run {
  bool ok = false;
  bool foreign = false;  // boolean() threw something that is not a wedge::Error
  BooleanResult r;
  std::string error;
};

bool xyz_less(const Vec3& a, const Vec3& b) {
  return a.x() != b.x() ? a.x() < b.x() : a.y() != b.y() ? a.y() < b.y() : a.z() < b.z();
}

std::size_t triangles_of(const std::vector<const Mesh*>& ops) {
  std::size_t n = 0;
  for (auto* m : ops) n += m->triangles.size();
  return n;
}

bool same_bits(const BooleanResult& a, const BooleanResult& b) {
  const auto& p = a.mesh.positions;
  const auto& q = b.mesh.positions;
  return a.mesh.triangles == b.mesh.triangles && a.mesh.face_ids == b.mesh.face_ids && a.operand == b.operand &&
         a.source == b.source && p.size() == q.size() &&
         (p.empty() || std::memcmp(p.data(), q.data(), p.size() * sizeof(Point3)) == 0);
}

Run run_boolean(BooleanOp op, const std::vector<const Mesh*>& ops) {
  // The operands first, where the driver finds them if this boolean crashes or hangs.
  save_operands(state.out + "/work/" + std::to_string(getpid()), op, ops);
  std::snprintf(state.shared->current, sizeof state.shared->current, "%s %s (%zu operands)", state.case_name.c_str(),
                boolean_op_name(op), ops.size());
  Run run;
  ++state.shared->booleans[state.gen];
  const double t0 = now_s();
  state.shared->bool_start = t0;
  BooleanStats st;
  try {
    run.r = boolean(op, ops, &st);
    run.ok = true;
  } catch (const Error& e) {
    run.error = e.what();
  } catch (const std::exception& e) {
    run.foreign = true;
    run.error = std::string("not a wedge::Error: ") + e.what();
  } catch (...) {
    run.foreign = true;
    run.error = "an exception that is not a std::exception";
  }
  state.shared->bool_start = 0;
  const double seconds = now_s() - t0;
  if (seconds > 2) {
    count(kSlow);
    // Where the time went (stage ms as BooleanStats gives them), so a slow case says which stage to look at.
    std::printf("SLOW %s %s %.1fs operands=%zu triangles=%zu result=%zu stages(ms)=%.0f/%.0f/%.0f/%.0f/%.0f "
                "pairs=%zu pieces=%zu resolutions=%zu reorders=%zu %s\n",
                state.case_name.c_str(), boolean_op_name(op), seconds, ops.size(), triangles_of(ops),
                run.ok ? run.r.mesh.triangles.size() : 0, st.check, st.broad, st.arrange, st.classify, st.output,
                st.pairs, st.pieces, st.resolutions, st.reorders, run.ok ? "" : run.error.c_str());
    // The first 6 of each generator's kept for --replay (OUT/slow/<gen>_<seed>_<k>/).
    if (state.shared->outcome[state.gen][kSlow] <= 6)
      save_case(state.out + "/slow/" + state.case_name + "_" + std::to_string(state.fail_k++), op, ops,
                std::string(boolean_op_name(op)) + ": slow: " + std::to_string(seconds) + " s");
  }
  return run;
}

// The mesh with each vertex whose triangles make several fans given one vertex per fan;
// `pinched` gets the positions split, once each. The kernel's split_fans splits the vertices
// whose fans come from separate vertices of `original`, and leaves a vertex that is in two fans
// in `original` too; here every corner of `original` is a vertex of its own (both meshes have the
// same triangles in the same order), so every such vertex is split.
Mesh split_pinches(const Mesh& m, std::vector<Vec3>* pinched) {
  Mesh corners;
  for (const auto& t : m.triangles) {
    const std::uint32_t a = corners.add_vertex(m.positions[t[0]]);
    corners.add_vertex(m.positions[t[1]]);
    corners.add_vertex(m.positions[t[2]]);
    corners.add_triangle(a, a + 1, a + 2);
  }
  Mesh split = split_fans(m, corners);
  pinched->assign(split.positions.begin() + static_cast<std::ptrdiff_t>(m.positions.size()), split.positions.end());
  std::sort(pinched->begin(), pinched->end(), xyz_less);
  pinched->erase(std::unique(pinched->begin(), pinched->end()), pinched->end());
  return split;
}

// Judges a boolean on valid operands and counts its outcome; true when it gave a result that passed.
bool check_run(BooleanOp op, const std::vector<const Mesh*>& ops, const Run& run) {
  if (!run.ok) {
    if (!run.foreign && (run.error.find("rounded") != std::string::npos || run.error.find("rounding") != std::string::npos)) {
      count(kUnroundable);
      std::printf("UNROUNDABLE %s %s: %s\n", state.case_name.c_str(), boolean_op_name(op), run.error.c_str());
      const std::string dir = state.out + "/unroundable/" + state.case_name + "_" + std::to_string(state.fail_k++);
      save_case(dir, op, ops, std::string(boolean_op_name(op)) + ": " + run.error);
    } else if (!run.foreign && run.error.find("budget") != std::string::npos) {
      count(kBudget);
    } else if (!run.foreign && run.error.find("subnormal") != std::string::npos &&
               std::any_of(ops.begin(), ops.end(), [](const Mesh* m) {
                 return std::any_of(m->positions.begin(), m->positions.end(), [](const Point3& p) {
                   return std::fpclassify(p.x()) == FP_SUBNORMAL || std::fpclassify(p.y()) == FP_SUBNORMAL ||
                          std::fpclassify(p.z()) == FP_SUBNORMAL;
                 });
               })) {
      count(kSubnormal);  // refused, rightly (an operand has one)
    } else {
      record_failure(kError, op, ops, "error on valid operands: " + run.error);
    }
    return false;
  }
  const Mesh& m = run.r.mesh;
  std::string d = result_defect(m);
  if (d.empty()) {
    if (run.r.operand.size() != m.triangles.size() || run.r.source.size() != m.triangles.size())
      d = "operand/source arrays not one per triangle";
    else
      for (std::size_t t = 0; t < m.triangles.size() && d.empty(); ++t) {
        const int o = run.r.operand[t];
        if (o < 0 || o >= static_cast<int>(ops.size()) || run.r.source[t] < 0 ||
            run.r.source[t] >= static_cast<int>(ops[o]->triangles.size()))
          d = "provenance out of range at triangle " + std::to_string(t);
      }
  }
  if (d.find("non-manifold vertex") != std::string::npos) {
    // A vertex index shared by two fans: is that all, and were the points coincident vertices of
    // an operand (touching shells passed through) or made by this boolean?
    std::vector<Vec3> pinched;
    if (result_defect(split_pinches(m, &pinched)).empty()) {
      bool merged = true;
      for (const Vec3& q : pinched) {
        bool dup = false;
        for (auto* o : ops) dup = dup || std::count(o->positions.begin(), o->positions.end(), q) > 1;
        merged = merged && dup;
      }
      record_failure(merged ? kPinchMerged : kPinchNew, op, ops,
                     std::to_string(pinched.size()) + " pinched vertices (" + std::to_string(m.triangles.size()) +
                         " triangles; valid once split): " + d);
      return false;
    }
  }
  if (!d.empty()) {
    record_failure(kInvalid, op, ops, "invalid result (" + std::to_string(m.triangles.size()) + " triangles): " + d);
    return false;
  }
  const std::string own = mesh_solid_defect(m, "result");
  if (!own.empty()) {
    record_failure(kInvalid, op, ops, "result_defect finds the result valid but mesh_solid_defect says: " + own);
    return false;
  }
  return true;
}

// The exact volume, scaled back by 2^-pow2 per length (exact where the coordinates stay normal).
double vol(const Mesh& m, int pow2) { return exact_volume(pow2 == 0 ? m : scaled_pow2(m, -pow2)); }

void check_near(const std::string& what, double got, double want, double tol, BooleanOp op,
                const std::vector<const Mesh*>& ops, Outcome o = kVolume) {
  if (std::isfinite(got) && std::isfinite(want) && std::abs(got - want) <= tol) return;
  char buf[400];
  std::snprintf(buf, sizeof buf, "%s: %.17g, expected %.17g (diff %.3g, tolerance %.3g)", what.c_str(), got, want,
                got - want, tol);
  record_failure(o, op, ops, buf);
}

void check_within(const char* what, double got, double lo, double hi, double tol, BooleanOp op,
                  const std::vector<const Mesh*>& ops) {
  if (got >= lo - tol && got <= hi + tol) return;
  char buf[400];
  std::snprintf(buf, sizeof buf, "%s: %.17g, outside [%.17g, %.17g] (tolerance %.3g)", what, got, lo, hi, tol);
  record_failure(kVolume, op, ops, buf);
}

// Where the engine's volume and CGAL's disagree: an estimate of the result's volume from points
// drawn at random in the operands' box, each placed exactly in or out of every operand
// (classify_point: a ray's crossings, decided exactly; not the boolean engine), in rounds of
// 10,000 up to 640,000 points or 30 s. True with the estimate and its standard deviation when
// it tells them apart: CGAL's volume more than 6 deviations off and the engine's within 3.
bool monte_carlo_sides_with_engine(BooleanOp op, const std::vector<const Mesh*>& ops, double engine, double cgal,
                                   double& estimate, double& sd, long& points) {
  Box3 box;
  for (auto* m : ops)
    for (const auto& p : m->positions) box.extend(p);
  const Vec3 size = box.max - box.min;
  const double vbox = size.x() * size.y() * size.z();
  if (!(vbox > 0) || !std::isfinite(vbox)) return false;
  std::uint64_t x = 0x9e3779b97f4a7c15ull ^ static_cast<std::uint64_t>(std::hash<double>{}(engine));
  auto uniform = [&] {  // xorshift64*, in [0, 1)
    x ^= x >> 12, x ^= x << 25, x ^= x >> 27;
    return static_cast<double>((x * 0x2545f4914f6cdd1dull) >> 11) * 0x1p-53;
  };
  const auto t0 = std::chrono::steady_clock::now();
  long in = 0;
  points = 0;
  while (points < 640000 && std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 30) {
    for (int i = 0; i < 10000; ++i, ++points) {
      const Point3 p(box.min.x() + uniform() * size.x(), box.min.y() + uniform() * size.y(), box.min.z() + uniform() * size.z());
      bool any = false, all = true, first = false, rest = false;
      for (std::size_t k = 0; k < ops.size(); ++k) {
        const bool inside = classify_point(*ops[k], p) == Membership::Inside;
        any |= inside;
        all &= inside;
        if (k == 0) first = inside;
        else rest |= inside;
      }
      in += op == BooleanOp::Union ? any : op == BooleanOp::Intersection ? all : first && !rest;
    }
    const double f = static_cast<double>(in) / static_cast<double>(points);
    estimate = vbox * f;
    sd = vbox * std::sqrt(std::max(f * (1 - f), 1.0 / static_cast<double>(points)) / static_cast<double>(points));
    if (std::abs(cgal - estimate) > 6 * sd && std::abs(engine - estimate) < 3 * sd) return true;
  }
  return false;
}

bool has_coincident_vertices(const Mesh& m) {
  std::vector<Vec3> p = m.positions;
  std::sort(p.begin(), p.end(), xyz_less);
  return std::adjacent_find(p.begin(), p.end()) != p.end();
}

// The three ops on one set of valid operands, with the checks across them. `keep`, if given,
// receives the result of `keep_op` if it passed.
void run_set(const std::vector<const Mesh*>& ops, const Case& c, BooleanOp keep_op = BooleanOp::Union,
             std::optional<BooleanResult>* keep = nullptr) {
  const int p2 = c.pow2;
  double vs = 0, area = 0, reach = 0;
  std::vector<double> vin;
  for (auto* m : ops) {
    vin.push_back(vol(*m, p2));
    vs += std::abs(vin.back());
    const Mesh unit = p2 ? scaled_pow2(*m, -p2) : *m;
    area += unit.area();
    for (const auto& p : unit.positions) reach = std::max(reach, p.cwiseAbs().maxCoeff());
  }
  // The bounds every result's volume keeps: union in [max, sum], intersection in [0, min],
  // difference in [0, vol A] (held below, and to CGAL's volume too).
  const double vmin = *std::min_element(vin.begin(), vin.end()), vmax = *std::max_element(vin.begin(), vin.end());
  double vsum = 0;
  for (double x : vin) vsum += x;
  // Rounding moves each result vertex by about an ulp of the largest coordinate.
  const double ulp = reach > 0 ? std::ldexp(1.0, std::ilogb(reach) - 52) : 0;
  const double tol = 1e-9 * vs + 256 * area * ulp;
  double v[3] = {0, 0, 0};
  bool have[3] = {false, false, false};
  for (int k = 0; k < 3; ++k) {
    const BooleanOp op = kOps[k];
    const Run run = run_boolean(op, ops);
    if (!check_run(op, ops, run)) continue;
    count(kOk);
    have[k] = true;
    v[k] = vol(run.r.mesh, p2);
    if (keep && op == keep_op) *keep = run.r;
    if (state.seed % state.threads_every == 0 && k == static_cast<int>(state.seed / state.threads_every % 3)) {
      set_threads(2);
      const Run again = run_boolean(op, ops);
      set_threads(1);
      if (!again.ok || !same_bits(again.r, run.r))
        record_failure(kBitsDiffer, op, ops, again.ok ? "result bits differ at 2 threads" : "2 threads: " + again.error);
    }
    // Small cases: CGAL's exact corefinement as the reference (it refuses non-manifold results).
    double want = 0;
    if (!c.no_oracle && triangles_of(ops) <= 3000 && p2 == 0 && ops.size() <= 5) {
      std::snprintf(state.shared->current, sizeof state.shared->current, "%s oracle %s", state.case_name.c_str(),
                    boolean_op_name(op));
      if (oracle_volume(op, ops, &want) && std::isfinite(vs) && want >= -tol) {
        // CGAL's own volume outside what any result of the operation can have (a union smaller
        // than its largest operand: nary_point seed 6106, 1.56 against operands up to 2.88) is
        // CGAL's error: reported, not counted against the engine, whose volume the bounds
        // below check.
        const double lo = op == BooleanOp::Union ? vmax : op == BooleanOp::Difference ? std::max(0.0, 2 * vin[0] - vsum) : 0.0;
        const double hi = op == BooleanOp::Union ? vsum : op == BooleanOp::Difference ? vin[0] : vmin;
        if (want < lo - tol || want > hi + tol)
          std::printf("ORACLE-WRONG %s %s (CGAL's volume %.17g outside [%.17g, %.17g]; wedge's %.17g)\n",
                      state.case_name.c_str(), boolean_op_name(op), want, lo, hi, v[k]);
        else if (double est = 0, sd = 0; !(std::abs(v[k] - want) <= tol)) {
          // Told apart by counting points (CGAL's corefinement has been wrong on unions of touching
          // grids: grid_rot 6322, 8161, 8289, 8737; grid_mixed 8614, 9175), or a failure.
          long points = 0;
          if (p2 == 0 && monte_carlo_sides_with_engine(op, ops, v[k], want, est, sd, points))
            std::printf("ORACLE-WRONG %s %s (CGAL's volume %.17g; wedge's %.17g; %ld random points say %.6g, sd %.2g)\n",
                        state.case_name.c_str(), boolean_op_name(op), want, v[k], points, est, sd);
          else
            check_near(std::string("volume vs CGAL's ") + boolean_op_name(op), v[k], want, tol, op, ops, kOracle);
        }
      }
    }
  }
  if (!std::isfinite(vs) || !std::isfinite(tol)) return;  // volumes overflow (a huge operand): validity only
  if (c.axis_boxes && p2 == 0) {
    if (have[0]) check_near("union volume vs boxes_volume", v[0], boxes_volume(kOps[0], c.boxes), tol, kOps[0], ops);
    if (have[2]) check_near("difference volume vs boxes_volume", v[2], boxes_volume(kOps[2], c.boxes), tol, kOps[2], ops);
  }
  if (have[0]) check_within("union volume outside [max, sum] of the operands'", v[0], vmax, vsum, tol, kOps[0], ops);
  if (have[1]) check_within("intersection volume outside [0, min] of the operands'", v[1], 0, vmin, tol, kOps[1], ops);
  if (have[2]) check_within("difference volume outside [0, vol A]", v[2], 0, vin[0], tol, kOps[2], ops);
  if (ops.size() <= 2) {
    if (have[0] && have[1]) check_near("vol(AuB)+vol(AnB) vs volA+volB", v[0] + v[1], vin[0] + vin[1], tol, kOps[0], ops);
    if (have[1] && have[2]) check_near("vol(A-B) vs volA-vol(AnB)", v[2], vin[0] - v[1], tol, kOps[2], ops);
    return;
  }
  if (have[2]) {
    // first minus the rest = first minus (first n union(rest)), by the engine in separate booleans
    const std::vector<const Mesh*> rest(ops.begin() + 1, ops.end());
    const Run u = run_boolean(BooleanOp::Union, rest);
    if (check_run(BooleanOp::Union, rest, u)) {
      const std::vector<const Mesh*> pair = {ops[0], &u.r.mesh};
      const Run x = run_boolean(BooleanOp::Intersection, pair);
      if (check_run(BooleanOp::Intersection, pair, x))
        check_near("n-ary vol(A - rest) vs volA - vol(A n union(rest))", v[2], vin[0] - vol(x.r.mesh, p2), tol, kOps[2], ops);
    }
  }
  if (have[0]) {  // the n-ary union in one pass against a pairwise fold
    Mesh cur = *ops[0];
    bool fine = true;
    for (std::size_t i = 1; i < ops.size() && fine; ++i) {
      const std::vector<const Mesh*> pair = {&cur, ops[i]};
      const Run s = run_boolean(BooleanOp::Union, pair);
      fine = check_run(BooleanOp::Union, pair, s);
      if (fine) cur = s.r.mesh;
    }
    if (fine) check_near("n-ary union vs pairwise fold", v[0], vol(cur, p2), tol * static_cast<double>(ops.size()), kOps[0], ops);
  }
}

// A case whose operand c.bad_index is bad: every op must refuse it, naming it.
void run_bad(const Case& c, const std::vector<const Mesh*>& ops) {
  const std::string which = std::to_string(c.bad_index + 1) + " (kind " + c.note + ")";
  const std::string want = ops.size() == 2 ? (c.bad_index == 0 ? "first operand" : "second operand")
                                           : "operand " + std::to_string(c.bad_index + 1);
  for (BooleanOp op : kOps) {
    const Run run = run_boolean(op, ops);
    if (run.ok) {
      const std::string d = result_defect(run.r.mesh);
      if (c.mendable && d.empty()) count(kOk);  // mended, as boolean.h allows
      else record_failure(kBadAccepted, op, ops, "bad operand " + which + " accepted; result defect: '" + d + "'");
    } else if (run.foreign || run.error.find(want) == std::string::npos) {
      record_failure(kBadMsg, op, ops, "bad operand " + which + ": message does not name '" + want + "': " + run.error);
    } else {
      count(kOk);
    }
  }
}

}  // namespace

void set_threads(int n) {
  g_thread_limit.reset();  // TBB obeys the smallest of the live limits: the old one goes first
  if (n > 0) g_thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, n);
}

bool oracle_volume(BooleanOp op, const std::vector<const Mesh*>& ops, double* volume) {
  // Touching shells (coincident vertices) make CGAL's corefinement wrong or crash: no reference.
  // So do operands of several shells (cavities: CGAL's result was off by the cavity's volume).
  for (auto* m : ops) {
    if (has_coincident_vertices(*m)) return false;
    try {
      if (euler_counts(*m).S > 1) return false;
    } catch (const Error&) {
      return false;  // not a closed 2-manifold
    }
  }
  int fd[2];
  if (pipe(fd) != 0) {
    std::printf("ORACLE-SKIPPED %s %s: pipe: %s\n", state.case_name.c_str(), boolean_op_name(op), std::strerror(errno));
    return false;
  }
  std::fflush(stdout);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) {
    std::printf("ORACLE-SKIPPED %s %s: fork: %s\n", state.case_name.c_str(), boolean_op_name(op), std::strerror(errno));
    close(fd[0]);
    close(fd[1]);
    return false;
  }
  if (pid == 0) {
    // Dies with this process, which the driver kills on a hang.
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent) _exit(1);
    close(fd[0]);
    const OracleResult r = ops.size() == 2 ? oracle_boolean(op, *ops[0], *ops[1]) : oracle_nary(op, ops);
    const double msg[2] = {r.ok ? 1.0 : 0.0, r.volume};
    _exit(write(fd[1], msg, sizeof msg) == static_cast<ssize_t>(sizeof msg) ? 0 : 1);
  }
  close(fd[1]);
  // CGAL's corefinement can loop for good (a 4-operand union through one point ran 11 minutes
  // in its constrained triangulation): given --hang seconds, then killed and reported as the
  // oracle's, not left to the driver, which would call the case a hang of the engine's.
  pollfd pfd{fd[0], POLLIN, 0};
  int ready = 0;
  do ready = poll(&pfd, 1, static_cast<int>(std::min(state.hang, 1e6) * 1000));
  while (ready < 0 && errno == EINTR);
  if (ready == 0) {
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    close(fd[0]);
    std::printf("ORACLE-HANG %s %s (over %g s)\n", state.case_name.c_str(), boolean_op_name(op), state.hang);
    return false;
  }
  double msg[2] = {0, 0};
  const bool got = read(fd[0], msg, sizeof msg) == static_cast<ssize_t>(sizeof msg);
  close(fd[0]);
  int status = 0;
  const bool waited = waitpid(pid, &status, 0) == pid;
  if (!got || !waited || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const std::string how = !waited             ? "lost"
                            : WIFSIGNALED(status) ? std::string("signal ") + strsignal(WTERMSIG(status))
                                                  : "exit status " + std::to_string(WEXITSTATUS(status));
    std::printf("ORACLE-CRASH %s %s (%s)\n", state.case_name.c_str(), boolean_op_name(op), how.c_str());
    return false;
  }
  *volume = msg[1];
  return msg[0] == 1.0;
}

void run_case(const Case& c, Rng& r) {
  std::vector<const Mesh*> ops;
  for (auto& m : c.ops) ops.push_back(&m);
  if (c.bad) return run_bad(c, ops);
  // The promise is for valid operands; a generator may make an invalid one (a snapped sphere):
  // the engine must refuse it or give a valid result. (A chain checks its later operands as it goes.)
  for (std::size_t i = 0; i < (c.chain ? 1 : ops.size()); ++i) {
    const std::string d = result_defect(*ops[i]);
    if (d.empty()) continue;
    count(kSkipped);
    const Run run = run_boolean(BooleanOp::Union, ops);
    if (run.ok) {
      const std::string rd = result_defect(run.r.mesh);
      if (!rd.empty())
        record_failure(kBadAccepted, BooleanOp::Union, ops,
                       "operand " + std::to_string(i + 1) + " invalid (" + d + ") accepted, result invalid: " + rd);
      else
        std::printf("NOTE %s operand %zu invalid per result_defect (%s) but accepted, result valid\n",
                    state.case_name.c_str(), i + 1, d.c_str());
    }
    return;
  }
  if (!c.chain) return run_set(ops, c);
  Mesh cur = c.ops[0];
  for (std::size_t i = 1; i < c.ops.size(); ++i) {
    if (!result_defect(c.ops[i]).empty()) {  // a snapped primitive with a collapsed triangle: left out
      count(kSkipped);
      continue;
    }
    Mesh other = c.ops[i];
    // Sometimes the other operand is the current result itself, moved a little (nearly coincident sheets).
    if (coin(r, 0.2) && !cur.empty()) {
      const Vec3 ctr = vertex_mean(cur);
      const int how = irand(r, 0, 2);
      other = how == 0   ? rot(cur, uni(r, 1e-9, 1e-3), rand_dir(r), ctr)
              : how == 1 ? moved(cur, rand_dir(r) * uni(r, 1e-12, 1e-3))
                         : cur.transformed(reflect(rand_dir(r), ctr));
      if (!result_defect(other).empty()) other = c.ops[i];
    }
    const BooleanOp next = static_cast<BooleanOp>(irand(r, 0, 2));
    std::optional<BooleanResult> kept;
    run_set({&cur, &other}, c, next, &kept);
    if (!kept) return;  // that op failed (reported): the chain ends
    cur = kept->mesh.empty() ? c.ops[i] : kept->mesh;
    if (cur.triangles.size() > 60000) return;
  }
}

}  // namespace wedge::fuzz
