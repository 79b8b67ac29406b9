// The engine's stages on the cases where its time goes, as CPU time of the whole process (so that
// a loaded machine inflates it less than wall time) and wall time per stage (BooleanStats).
//
//   bench_stages [case] [threads, default 1] [repeats, default 3]
//
// Cases: plate (a plate minus 400 cylinders of 32 sides), menger (the level-3 sponge), sph65
// (two overlapping 65k-triangle spheres, union), sph4k and sph1m (the same at 4k and 1M, not in all), lattice (the
// union of 8 x 8 x 8 overlapping spheres of 1280 triangles), classic (cube n sphere, then minus
// three cylinders), truss (the union of an octet truss: 126 struts and 27 balls), bosses (issue 16's plate as meshes: a 42 x 42 x 2
// plate united with 400 bored bosses of 24 sides in one pass, then minus 400 drills), or all;
// or dir:PATH, the boolean of a folder the fuzzer saved (off_file.h).
// Each line gives the minimum over the repeats of the CPU time and of each stage, and a hash of the
// last result's bits (the same at any thread count, and after any change that keeps the engine's
// decisions).
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "csg/boolean.h"
#include "csg/boolean_impl.h"
#include <chrono>
#include "kernel/transform.h"
#include "tests/support/boolean_cases.h"
#include "kernel/memory.h"
#include "bench/csg/off_file.h"

using namespace wedge;
using namespace wedge::testing;

namespace {

int g_repeats = 3;

Mesh run(const char* name, BooleanOp op, const std::vector<Mesh>& ops) {
  std::vector<const Mesh*> p;
  for (const auto& m : ops) p.push_back(&m);
  BooleanStats best;
  best.check = best.broad = best.arrange = best.classify = best.output = 1e300;
  double cpu = 1e300;
  BooleanResult r;
  for (int i = 0; i < g_repeats; ++i) {
    BooleanStats st;
    r = BooleanResult{};  // the previous result released first, as bench_boolean does
    const std::clock_t c0 = std::clock();
    r = boolean(op, p, &st);
    cpu = std::min(cpu, 1000.0 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    best.check = std::min(best.check, st.check);
    best.broad = std::min(best.broad, st.broad);
    best.arrange = std::min(best.arrange, st.arrange);
    best.classify = std::min(best.classify, st.classify);
    best.output = std::min(best.output, st.output);
    best.pairs = st.pairs;
    best.pieces = st.pieces;
    best.collapses = st.collapses;
    best.resolutions = st.resolutions;
    best.quads = st.quads;
    best.quad_points = st.quad_points;
  }
  // The result's bits (positions, triangles, face ids, provenance), hashed: a change to the engine
  // that keeps its decisions keeps this.
  std::uint64_t bits = 0xcbf29ce484222325ull;
  auto mix = [&](std::uint64_t v) { bits = (bits ^ v) * 0x100000001b3ull; };
  for (const auto& q : r.mesh.positions)
    for (int k = 0; k < 3; ++k) mix(std::bit_cast<std::uint64_t>(q[k]));
  for (const auto& t : r.mesh.triangles) mix(static_cast<std::uint64_t>(t[0]) << 42 ^ static_cast<std::uint64_t>(t[1]) << 21 ^ t[2]);
  for (std::size_t t = 0; t < r.operand.size(); ++t)
    mix(static_cast<std::uint64_t>(static_cast<std::uint32_t>(r.operand[t])) << 32 | static_cast<std::uint32_t>(r.source[t]));
  for (auto f : r.mesh.face_ids) mix(static_cast<std::uint32_t>(f));
  std::printf("| %s | %.0f | %.1f, %.1f, %.1f, %.1f, %.1f | %zu | %.9f | %zu / %zu | %zu / %zu | %zu / %zu | %016llx |\n", name,
              cpu, best.check, best.broad, best.arrange, best.classify, best.output, r.mesh.triangles.size(), r.mesh.volume(),
              best.collapses, best.resolutions, best.pairs, best.pieces, best.quads, best.quad_points,
              static_cast<unsigned long long>(bits));
  std::fflush(stdout);
  return r.mesh;
}

void bosses() {
  const int n = 20, sides = 24;
  const Mesh boss = run("boss (cylinder minus bore)", BooleanOp::Difference,
                        {cylinder_mesh(0.6, 0.5, 2.5, sides), cylinder_mesh(0.3, -0.5, 3.0, sides)});
  std::vector<Mesh> parts{box_mesh(Point3(0, 0, 0), Vec3(2 * n + 2, 2 * n + 2, 2))}, drills;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Mat4 m = translate(Vec3(2 + 2 * i, 2 + 2 * j, 0));
      Mesh b = boss;
      for (auto& q : b.positions) q = apply_point(m, q);
      parts.push_back(std::move(b));
      drills.push_back(cylinder_mesh(0.2, -1, 4, sides, m));
    }
  std::vector<Mesh> d{run("plate + 400 bosses, union", BooleanOp::Union, parts)};
  d.insert(d.end(), drills.begin(), drills.end());
  run("... minus 400 drills", BooleanOp::Difference, d);
}

}  // namespace

int main(int argc, char** argv) {
  wedge::tune_malloc(argv);  // first: it may execute the program again
  const std::string which = argc > 1 ? argv[1] : "all";
  const int threads = argc > 2 ? std::max(1, std::atoi(argv[2])) : 1;
  g_repeats = argc > 3 ? std::max(1, std::atoi(argv[3])) : 3;
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  std::printf("threads %d, minimum of %d runs\n\n| case | CPU ms | check, broad, arrange, classify, output ms (wall) | "
              "triangles | volume | collapses / resolutions | pairs / pieces | quads / points | result bits (hash) |\n"
              "|---|---|---|---|---|---|---|---|---|\n",
              threads, g_repeats);
  const bool all = which == "all";
  if (all || which == "plate") run("plate minus 400 cylinders", BooleanOp::Difference, plate_and_cylinders(20, 32));
  if (all || which == "menger") run("Menger sponge, level 3", BooleanOp::Difference, menger_operands(3));
  if (all || which == "truss") run("octet truss, 3x3x3 nodes, union", BooleanOp::Union, octet_truss(2, 0.08, 32, 320));
  if (which == "sph4k") run("spheres 4k, union", BooleanOp::Union, overlapping_spheres(4096));
  if (all || which == "sph65") run("spheres 65k, union", BooleanOp::Union, overlapping_spheres(65536));
  if (which == "sph1m") run("spheres 1M, union", BooleanOp::Union, overlapping_spheres(1048576));
  if (which == "soup") {
    const auto ops = overlapping_spheres(1048576);
    std::vector<const Mesh*> p;
    for (const auto& m : ops) p.push_back(&m);
    double best = 1e300;
    std::size_t nv = 0;
    for (int i = 0; i < g_repeats; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      const auto s = boolean_detail::make_soup(p, nullptr);
      best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      nv = s.verts.size();
    }
    std::printf("make_soup, two 1M spheres: %.1f ms (%zu vertices)\n", best, nv);
  }
  if (which == "sph1md") run("spheres 1M, difference", BooleanOp::Difference, overlapping_spheres(1048576));
  if (all || which == "classic") {
    const std::vector<Mesh> ops = classic_figure_operands(16384, 128);
    const Mesh a = run("classic figure: cube n sphere", BooleanOp::Intersection, {ops[0], ops[1]});
    run("... minus three cylinders", BooleanOp::Difference, {a, ops[2], ops[3], ops[4]});
  }
  if (all || which == "lattice") run("lattice 512 spheres union", BooleanOp::Union, sphere_lattice(8, 1280));
  if (all || which == "bosses") bosses();
  if (which.rfind("dir:", 0) == 0) {
    const std::string dir = which.substr(4);
    try {
      run(dir.c_str(), fuzz::read_case_op(dir), fuzz::read_case_operands(dir));
    } catch (const std::runtime_error& e) {
      std::fprintf(stderr, "bench_stages: %s\n", e.what());
      return 1;
    }
  }
  return 0;
}
