// Issue 16's benchmark: CSG trees of a CAD kind, evaluated with and without the evaluator's cache
// and bounding-box pruning, at 1 and 2 threads; and how long a cancel takes to stop an evaluation.
//
//   bench_tree [repeats] [bosses per side, default 20] [threads, default "12"] [evaluators, default "012"]
//              [fan-in of the first two settings, default 32] [cancel latency: 1 (default) or 0]
//
// threads: the thread counts to run, as digits ("2": two threads only); evaluators: which of the
// three evaluator settings below to run, by index ("0": balanced unions with cache and pruning).
// The median is of the evaluation (the model built, then its mesh asked for); "built" is the median
// time to build the model's tree (Manifold's tree.mjs times both: compare it with their sum), and
// "mass" the time the volume then takes (the curved correction over the evaluated mesh).
//
// Models (fresh trees for every run, so nothing is cached across runs):
//   plate: a 42 x 42 x 2 plate with 400 instances (20 x 20) of one drilled boss (a cylinder r 0.6,
//          h 2 on top, drilled r 0.3 through boss and plate), all one n-ary union minus the drills;
//   gear:  a disc r 10 with 60 teeth (boxes) unioned, drilled by a centre hole and 6 lightening holes;
//   spokes: 24 cylinders through one point, unioned (operands piled on one another).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>

#include "csg/brep_leaf.h"
#include "csg/csg.h"
#include "kernel/memory.h"

using namespace wedge;

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

int g_n = 20;  // bosses per side

Solid plate_model() {
  const int n = g_n;
  Solid plate = brep_solid(box(Vec3(2 * n + 2, 2 * n + 2, 2)));
  // One boss, drilled; every instance is a transform of this one node.
  Solid boss = Solid::boolean(BooleanOp::Difference, {brep_solid(cylinder(0.6, 2, Point3(0, 0, 1.5))),
                                                      brep_solid(cylinder(0.3, 3, Point3(0, 0, 1)))});
  Solid drill = brep_solid(cylinder(0.2, 5, Point3(0, 0, -1)));
  std::vector<Solid> parts{plate}, drills;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      Mat4 m = translate(Vec3(2 + 2 * i, 2 + 2 * j, 0));
      parts.push_back(boss.transformed(m));
      drills.push_back(drill.transformed(m));
    }
  Solid body = Solid::boolean(BooleanOp::Union, parts);
  std::vector<Solid> ops{body};
  ops.insert(ops.end(), drills.begin(), drills.end());
  return Solid::boolean(BooleanOp::Difference, ops);
}

Solid gear_model() {
  Solid disc = brep_solid(cylinder(10, 2));
  Solid tooth = brep_solid(box(Vec3(1.6, 0.8, 2), Point3(9.5, -0.4, 0)));
  std::vector<Solid> parts{disc};
  for (int k = 0; k < 60; ++k) parts.push_back(tooth.transformed(rotate_z(6.0 * k)));
  std::vector<Solid> ops{Solid::boolean(BooleanOp::Union, parts), brep_solid(cylinder(2, 4, Point3(0, 0, -1)))};
  for (int k = 0; k < 6; ++k) ops.push_back(brep_solid(cylinder(1.5, 4, Point3(6 * std::cos(k * kPi / 3), 6 * std::sin(k * kPi / 3), -1))));
  return Solid::boolean(BooleanOp::Difference, ops);
}

// 24 spokes through one point: cylinders r 0.2, 4 long, centred on the origin and turned by 7.5
// degrees about x, unioned (every centre in every box: a stack of 24, EvalOptions::stack_fan_in).
Solid spokes_model() {
  std::vector<Solid> parts;
  for (int k = 0; k < 24; ++k) parts.push_back(brep_solid(cylinder(0.2, 4, Point3(0, 0, -2))).transformed(rotate_x(7.5 * k)));
  return Solid::boolean(BooleanOp::Union, parts);
}

struct Row {
  double seconds;
  double build;
  double mass;
  double volume;
  std::size_t triangles;
  EvalStats stats;
};

Row run(Solid (*make)(), const EvalOptions& o, int threads) {
  tbb::global_control g(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  set_eval_options(o);
  EvalStats stats;
  EvalControl c;
  c.stats = &stats;
  set_eval_control(&c);
  const double b0 = now();
  Solid s = make();
  const double build = now() - b0;
  Tolerance tol;
  double t0 = now();
  const std::size_t triangles = s.mesh(tol).triangle_count();  // forces the tree, as Manifold's getMesh()
  double t = now() - t0;
  const double m0 = now();
  double v = s.mass_properties(tol).volume;  // from the evaluated mesh and its surfaces
  const double mass = now() - m0;
  set_eval_control(nullptr);
  set_eval_options({});
  return {t, build, mass, v, triangles, stats};
}

}  // namespace

int main(int argc, char** argv) {
  wedge::tune_malloc(argv);  // first: it may execute the program again
  int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  if (argc > 2) g_n = std::max(1, std::atoi(argv[2]));
  const std::string threads_list = argc > 3 ? argv[3] : "12", config_list = argc > 4 ? argv[4] : "012";
  const std::size_t fan_in = argc > 5 ? static_cast<std::size_t>(std::max(0, std::atoi(argv[5]))) : 32;
  const bool cancel_latency = argc > 6 ? std::atoi(argv[6]) != 0 : true;
  struct Model {
    const char* name;
    Solid (*make)();
  } models[] = {{"plate of drilled bosses", plate_model},
                {"gear, 60 teeth, drilled", gear_model},
                {"24 spokes through one point", spokes_model}};
  std::printf("plate: %d x %d bosses\n", g_n, g_n);
  struct Config {
    const char* name;
    EvalOptions o;
  };
  const std::string fan = "(fan-in " + std::to_string(fan_in) + ")";
  const std::string balanced = "cache+prune, unions balanced " + fan, unpruned = "no cache, no prune " + fan;
  const Config configs[] = {{balanced.c_str(), {true, true, true, fan_in}},
                            {"cache+prune, each union one engine pass", {true, true, true, 0}},
                            {unpruned.c_str(), {false, false, true, fan_in}}};
  std::printf("| model | evaluator | threads | median s | built s | mass s | engine calls | tessellation, check, broad, intersection, classification, output ms (summed) | volume | triangles |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& m : models)
    for (std::size_t ci = 0; ci < std::size(configs); ++ci)
      for (char tc : threads_list) {
        const auto& c = configs[ci];
        const int threads = tc - '0';
        if (config_list.find(char('0' + ci)) == std::string::npos || threads < 1) continue;
        std::vector<double> times, builds, masses;
        Row last{};
        for (int r = 0; r < repeats; ++r) {
          last = run(m.make, c.o, threads);
          times.push_back(last.seconds);
          builds.push_back(last.build);
          masses.push_back(last.mass);
        }
        std::sort(times.begin(), times.end());
        std::sort(builds.begin(), builds.end());
        std::sort(masses.begin(), masses.end());
        const EvalStats& st = last.stats;
        std::printf("| %s | %s | %d | %.3f | %.3f | %.3f | %ld | %.0f, %.0f, %.0f, %.0f, %.0f, %.0f | %.6f | %zu |\n", m.name, c.name, threads,
                    times[times.size() / 2], builds[builds.size() / 2], masses[masses.size() / 2], st.booleans, st.tessellate, st.check, st.broad, st.arrange, st.classify, st.output, last.volume,
                    last.triangles);
        std::fflush(stdout);
      }
  // Cancel latency: a flag raised part-way through the plate; the time until evaluation returns.
  if (cancel_latency)
  for (std::size_t fan_in : {std::size_t(32), std::size_t(0)}) {
  EvalOptions o;
  o.union_fan_in = fan_in;
  set_eval_options(o);
  std::printf("\ncancel latency (plate, 2 threads, union fan-in %zu):", fan_in);
  for (double after : {0.2, 0.5, 1.0, 3.0}) {
    std::atomic<bool> stop{false};
    std::atomic<double> raised{0};
    EvalControl c;
    c.cancelled = [&] { return stop.load(); };
    set_eval_control(&c);
    Solid s = plate_model();
    std::thread t([&] {
      std::this_thread::sleep_for(std::chrono::duration<double>(after));
      raised = now();
      stop = true;
    });
    double end = 0;
    bool cancelled = false;
    try {
      s.mass_properties(Tolerance{});
    } catch (const Cancelled&) {
      cancelled = true;
    }
    end = now();
    t.join();
    set_eval_control(nullptr);
    if (cancelled) std::printf(" %.0f ms (raised at %.1f s);", 1e3 * (end - raised.load()), after);
    else std::printf(" finished before %.1f s;", after);
  }
  }
  set_eval_options({});
  std::printf("\n");
  return 0;
}
