// Settling (csg/boolean_settle.cpp): triangles buried in an operand that drops them leave the
// arrangement with their pairs. The results must be the solids the whole arrangement gives: boxes
// against the exact volumes of their grid cells, a truss against its unions two at a time.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <random>

#include "csg/boolean.h"
#include "kernel/transform.h"
#include "tests/support/boolean_cases.h"

using namespace wedge;
using wedge::testing::box_mesh;
using wedge::testing::boxes_volume;
using wedge::testing::grid_box;

namespace {

Mesh box_between(const Vec3& lo, const Vec3& hi) { return box_mesh(lo, hi - lo); }

void require_solid(const Mesh& m) {
  INFO(mesh_solid_defect(m, "result"));
  REQUIRE(mesh_solid_defect(m, "result").empty());
}

// The boolean of all `meshes` in one pass, required to be a valid solid (or empty); its stats in st.
BooleanResult one_pass(BooleanOp op, const std::vector<Mesh>& meshes, BooleanStats& st) {
  std::vector<const Mesh*> ops;
  for (const auto& m : meshes) ops.push_back(&m);
  BooleanResult r = boolean(op, ops, &st);
  if (!r.mesh.empty()) require_solid(r.mesh);
  return r;
}

}  // namespace

TEST_CASE("boolean: triangles buried in an operand that drops them leave the arrangement, the result unchanged",
          "[boolean][settle]") {
  SECTION("a bar's end inside a cube, crossing a second bar's face there") {
    // The bar a's end cap (x = -0.3) lies inside the cube and meets only c's bottom face (z = 0):
    // settled by the cube, and the cut it would make in c's face left out.
    const Mesh cube = box_between(Vec3(-1, -1, -1), Vec3(1, 1, 1));
    const Mesh a = box_between(Vec3(-0.3, -0.1, -0.1), Vec3(2, 0.1, 0.1));
    const Mesh c = grid_box(Vec3(-0.5, -0.3, 0), Vec3(0.5, 2, 0.2), 64);
    BooleanStats st;
    const BooleanResult r = boolean(BooleanOp::Union, {&cube, &a, &c}, &st);
    require_solid(r.mesh);
    CHECK(st.settled >= 2);
    CHECK(r.mesh.volume() == Approx(8 + 0.04 + 0.2).epsilon(1e-12));
    // In a difference the cube is not a subtrahend: nothing settles, and the same region goes.
    BooleanStats sd;
    const BooleanResult d = boolean(BooleanOp::Difference, {&cube, &a, &c}, &sd);
    require_solid(d.mesh);
    CHECK(sd.settled == 0);
    const std::vector<std::array<Vec3, 2>> boxes = {
        {Vec3(-1, -1, -1), Vec3(1, 1, 1)}, {Vec3(-0.3, -0.1, -0.1), Vec3(2, 0.1, 0.1)}, {Vec3(-0.5, -0.3, 0), Vec3(0.5, 2, 0.2)}};
    CHECK(d.mesh.volume() == Approx(boxes_volume(BooleanOp::Difference, boxes)).epsilon(1e-12));
  }
  SECTION("a subtrahend's end inside another subtrahend") {
    // b's end (z = -0.3) is inside the drill d and crosses the bar e there: settled by d.
    const Mesh plate = box_between(Vec3(-2, -2, -1), Vec3(2, 2, 1));
    const Mesh b = box_between(Vec3(-0.1, -0.1, -0.3), Vec3(0.1, 0.1, 3));
    const Mesh d = box_between(Vec3(-0.5, -0.5, -3), Vec3(0.5, 0.5, 0));
    const Mesh e = grid_box(Vec3(0, -3, -0.4), Vec3(0.05, 3, -0.2), 64);
    BooleanStats st;
    const BooleanResult r = boolean(BooleanOp::Difference, {&plate, &b, &d, &e}, &st);
    require_solid(r.mesh);
    CHECK(st.settled >= 2);
    std::vector<std::array<Vec3, 2>> boxes = {{Vec3(-2, -2, -1), Vec3(2, 2, 1)}, {Vec3(-0.1, -0.1, -0.3), Vec3(0.1, 0.1, 3)},
                                              {Vec3(-0.5, -0.5, -3), Vec3(0.5, 0.5, 0)}, {Vec3(0, -3, -0.4), Vec3(0.05, 3, -0.2)}};
    CHECK(r.mesh.volume() == Approx(boxes_volume(BooleanOp::Difference, boxes)).epsilon(1e-12));
  }
  SECTION("inside an operand's box but outside the operand: not settled") {
    // Two crossing bars in the corner of a ball's box, outside the ball: each bar's triangles
    // meet the other bar and not the ball, and a ray finds them outside it.
    const Mesh ball = wedge::testing::icosphere(Point3(0, 0, 0), 1, 320);
    const std::vector<std::array<Vec3, 2>> bars = {{Vec3(0.8, 0.7, 0.8), Vec3(0.95, 0.9, 0.9)},
                                                   {Vec3(0.85, 0.75, 0.7), Vec3(0.9, 0.85, 0.95)}};
    const Mesh a = grid_box(bars[0][0], bars[0][1], 16), b = box_between(bars[1][0], bars[1][1]);
    BooleanStats st;
    const BooleanResult r = boolean(BooleanOp::Union, {&ball, &a, &b}, &st);
    require_solid(r.mesh);
    CHECK(st.settled == 0);
    CHECK(r.mesh.volume() == Approx(ball.volume() + boxes_volume(BooleanOp::Union, bars)).epsilon(1e-12));
  }
  SECTION("a lattice truss: struts' caps at the nodes' centres, inside the balls") {
    const std::vector<Mesh> truss = wedge::testing::octet_truss(1, 0.08, 12, 80);
    BooleanStats st;
    const BooleanResult r = one_pass(BooleanOp::Union, truss, st);
    CHECK(st.settled > 0);
    // The struts' caps (12 triangles each, two per strut; the last 8 operands are the balls) lie
    // in the balls' cores, and nothing else does: settled before the broad phase.
    CHECK(st.in_cores == (truss.size() - 8) * 2 * 12);
    CHECK(st.in_cores <= st.settled);
    CHECK(st.settled_pairs > 0);  // struts' walls crossing near a node, inside its ball's core
    {
      // The same bits with one thread as with all of them.
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      BooleanStats s1;
      const BooleanResult r1 = one_pass(BooleanOp::Union, truss, s1);
      CHECK(r1.mesh.positions == r.mesh.positions);
      CHECK(r1.mesh.triangles == r.mesh.triangles);
      CHECK(s1.settled == st.settled);
      CHECK(s1.in_cores == st.in_cores);
      CHECK(s1.settled_pairs == st.settled_pairs);
    }
    // Folded two at a time (nothing settles with two operands): the same solid.
    Mesh folded = truss[0];
    for (std::size_t i = 1; i < truss.size(); ++i) folded = boolean(BooleanOp::Union, folded, truss[i]);
    CHECK(r.mesh.volume() == Approx(folded.volume()).epsilon(1e-9));
  }
  SECTION("an operand inside a ball's core that crosses itself: still found") {
    // Only operands whose own pairs need no look (results, or one-to-one on a sphere about their
    // centre) are settled before the broad phase, which checks the others for self-crossings.
    const Mesh ball = wedge::testing::icosphere(Point3(0, 0, 0), 1, 320);
    const Mesh bar = box_between(Vec3(-2, -0.1, -0.1), Vec3(2, 0.1, 0.1));
    Mesh crossed = box_between(Vec3(-0.2, -0.2, -0.2), Vec3(0.1, 0.1, 0.1));
    const Mesh other = box_between(Vec3(-0.1, -0.1, -0.1), Vec3(0.2, 0.2, 0.2));
    const auto base = static_cast<std::uint32_t>(crossed.positions.size());
    crossed.positions.insert(crossed.positions.end(), other.positions.begin(), other.positions.end());
    for (auto T : other.triangles) crossed.triangles.push_back({T[0] + base, T[1] + base, T[2] + base});
    crossed.face_ids.assign(crossed.triangles.size(), -1);
    for (BooleanOp op : {BooleanOp::Union, BooleanOp::Difference}) {
      INFO(boolean_op_name(op));
      std::string message;
      try {
        boolean(op, {&ball, &bar, &crossed});
      } catch (const Error& e) {
        message = e.what();
      }
      CHECK(message.find("operand 3 intersects itself") != std::string::npos);
    }
  }
  SECTION("random parts in and across a ball: one pass as folded two at a time") {
    // Parts whose triangles lie in the ball's core are settled before the broad phase; the
    // result must be the solid the folded booleans (two operands: nothing settles) give.
    std::mt19937 rng(11);
    auto r = [&](double a, double b) { return a + (b - a) * std::uniform_real_distribution<double>(0, 1)(rng); };
    std::size_t in_cores = 0;
    for (int trial = 0; trial < 12; ++trial) {
      std::vector<Mesh> meshes = {wedge::testing::icosphere(Point3(0, 0, 0), r(0.7, 1), 320)};
      const int n = 2 + trial % 4;
      for (int i = 0; i < n; ++i) {
        const Mat4 m = translate(Vec3(r(-0.5, 0.5), r(-0.5, 0.5), r(-0.5, 0.5))) *
                       rotate(r(0, 360), Vec3(r(-1, 1), r(-1, 1), r(0.1, 1)));
        const double size = r(0.1, 0.5);
        meshes.push_back(i % 2 ? box_mesh(Point3(-size / 2, -size / 2, -size / 2), Vec3(size, size, size), m)
                               : wedge::testing::cylinder_mesh(size / 3, -size, r(0, 2), 16, m));
      }
      for (BooleanOp op : {BooleanOp::Union, BooleanOp::Difference}) {
        INFO("trial " << trial << ", " << boolean_op_name(op));
        BooleanStats st;
        const BooleanResult one = one_pass(op, meshes, st);
        in_cores += st.in_cores;
        Mesh folded = meshes[0];
        for (std::size_t i = 1; i < meshes.size(); ++i) folded = boolean(op, folded, meshes[i]);
        CHECK(one.mesh.volume() == Approx(folded.volume()).epsilon(1e-9));
      }
    }
    CHECK(in_cores > 0);
  }
  SECTION("random boxes on a coarse grid: touching, nested and crossing") {
    // Seed 7 puts pieces' centroids on settled triangles, seed 3 on triangles whose cut with the
    // piece's own was left out for a core: classify() must drop both kinds.
    std::size_t settled = 0, settled_pairs = 0;
    for (unsigned seed : {7u, 3u}) {
      std::mt19937 rng(seed);
      for (int round = 0; round < 40; ++round) {
        std::vector<std::array<Vec3, 2>> boxes;
        std::vector<Mesh> meshes;
        const int n = 3 + round % 5;
        for (int i = 0; i < n; ++i) {
          Vec3 lo, hi;
          for (int d = 0; d < 3; ++d) {
            int a = static_cast<int>(rng() % 9), b = static_cast<int>(rng() % 9);
            if (a == b) b = a + 1;
            lo[d] = std::min(a, b) * 0.25;
            hi[d] = std::max(a, b) * 0.25;
          }
          boxes.push_back({lo, hi});
          meshes.push_back(grid_box(lo, hi, 1 + static_cast<int>(rng() % 12)));
        }
        for (BooleanOp op : {BooleanOp::Union, BooleanOp::Difference}) {
          INFO("seed " << seed << ", round " << round << ", " << boolean_op_name(op));
          BooleanStats st;
          const BooleanResult r = one_pass(op, meshes, st);
          settled += st.settled;
          settled_pairs += st.settled_pairs;
          CHECK(r.mesh.volume() == Approx(boxes_volume(op, boxes)).margin(1e-12));
        }
      }
    }
    CHECK(settled > 0);
    CHECK(settled_pairs > 0);
  }
  SECTION("bars crossing inside a ball and leaving it") {
    // The bars' faces cross one another near the centre, inside the ball's core (their cuts there
    // leave the arrangement) and again outside the ball, where the cuts bound the result.
    const Mesh ball = wedge::testing::icosphere(Point3(0, 0, 0), 1, 1280);
    const std::vector<std::array<Vec3, 2>> bars = {{Vec3(-2, -0.1, -0.1), Vec3(2, 0.1, 0.1)},
                                                   {Vec3(-0.1, -2, -0.1), Vec3(0.1, 2, 0.1)},
                                                   {Vec3(-0.15, -0.15, -2), Vec3(0.15, 0.15, 2)}};
    std::vector<Mesh> meshes = {ball};
    for (const auto& b : bars) meshes.push_back(box_between(b[0], b[1]));  // faces from end to end
    BooleanStats st;
    const BooleanResult r = one_pass(BooleanOp::Union, meshes, st);
    CHECK(st.settled_pairs > 0);
    // The bars' union outside the ball, exactly: the bars' union minus the parts inside the ball,
    // the latter from the engine's own intersection of each bar with the ball (no settling: two
    // operands).
    Mesh inside = boolean(BooleanOp::Union, {&meshes[1], &meshes[2], &meshes[3]}).mesh;
    const double bars_in_ball = boolean(BooleanOp::Intersection, {&inside, &ball}).mesh.volume();
    CHECK(r.mesh.volume() == Approx(ball.volume() + boxes_volume(BooleanOp::Union, bars) - bars_in_ball).epsilon(1e-9));
  }
}
