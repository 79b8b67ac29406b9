// Flat quadrilaterals (csg/boolean_quads.cpp): two cut triangles of one face retriangulated as
// one, the cut points on their shared diagonal left out. The results must be the exact solids,
// valid, with their provenance, and the same at any thread count; the counts say the step ran.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include "csg/boolean.h"
#include "tests/support/boolean_cases.h"
#include "tests/support/cgal_oracle.h"

using namespace wedge;
using wedge::testing::box_mesh;
using wedge::testing::boxes_volume;
using wedge::testing::grid_box;

namespace {

// The boolean of all `meshes` in one pass; its result closed, manifold, outward and free of
// self-intersections (exactly, after rounding).
BooleanResult run(BooleanOp op, const std::vector<Mesh>& meshes, BooleanStats& st) {
  std::vector<const Mesh*> ops;
  for (const auto& m : meshes) ops.push_back(&m);
  BooleanResult r = boolean(op, ops, &st);
  INFO(testing::result_defect(r.mesh));
  CHECK(testing::result_defect(r.mesh).empty());
  return r;
}

}  // namespace

TEST_CASE("boolean: cut triangles of one flat face are retriangulated as quadrilaterals", "[boolean][quads]") {
  SECTION("a plate minus cylinders: each side quad's diagonal crossed twice") {
    // Every side of a cylinder (16 quads of two triangles) is cut by the plate's top and bottom,
    // each crossing its diagonal once: those 2 x 16 points per cylinder are no vertices now.
    const auto ops = testing::plate_and_cylinders(3, 16);
    BooleanStats st;
    const BooleanResult r = run(BooleanOp::Difference, ops, st);
    CHECK(r.mesh.volume() == Approx(testing::plate_with_holes_volume(ops)).epsilon(1e-12));
    CHECK(st.quads >= 9 * 16);
    CHECK(st.quad_points >= 2 * 9 * 16);
    // Every output triangle still names a triangle of its own face (the cylinders' walls keep
    // their face id) and lies in its plane.
    for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
      const Mesh& src = ops[static_cast<std::size_t>(r.operand[t])];
      const auto& s = src.triangles[static_cast<std::size_t>(r.source[t])];
      CHECK(r.mesh.face_ids[t] == src.face_ids[static_cast<std::size_t>(r.source[t])]);
      const Vec3 n = (src.positions[s[1]] - src.positions[s[0]]).cross(src.positions[s[2]] - src.positions[s[0]]);
      for (int k = 0; k < 3; ++k)
        CHECK(std::abs(n.normalized().dot(r.mesh.positions[r.mesh.triangles[t][k]] - src.positions[s[0]])) < 1e-12);
    }
    // The same bits at two threads.
    BooleanStats s2;
    BooleanResult r2;
    {
      tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
      r2 = run(BooleanOp::Difference, ops, s2);
    }
    CHECK(r2.mesh.positions == r.mesh.positions);
    CHECK(r2.mesh.triangles == r.mesh.triangles);
    CHECK(r2.source == r.source);
    CHECK(s2.quads == st.quads);
    CHECK(s2.quad_points == st.quad_points);
  }
  SECTION("a slab through faces of many squares: each cut line crosses a chain of diagonals") {
    // The cube's sides are 8 x 8 squares of two triangles; the slabs cut every side square they
    // cross along lines that pass through several squares' diagonals in turn.
    const Mesh cube = grid_box(Vec3(0, 0, 0), Vec3(3, 3, 3), 8);
    const std::vector<std::array<Vec3, 2>> boxes = {{Vec3(0, 0, 0), Vec3(3, 3, 3)},
                                                    {Vec3(-1, -1, 1.1), Vec3(4, 4, 1.7)},
                                                    {Vec3(0.7, -1, -1), Vec3(1.3, 4, 4)}};
    const std::vector<Mesh> ops = {cube, box_mesh(boxes[1][0], boxes[1][1] - boxes[1][0]),
                                   box_mesh(boxes[2][0], boxes[2][1] - boxes[2][0])};
    BooleanStats st;
    const BooleanResult d = run(BooleanOp::Difference, ops, st);
    CHECK(d.mesh.volume() == Approx(boxes_volume(BooleanOp::Difference, boxes)).epsilon(1e-12));
    CHECK(st.quads > 0);
    CHECK(st.quad_points > 0);
    BooleanStats su;
    const BooleanResult u = run(BooleanOp::Union, ops, su);
    CHECK(u.mesh.volume() == Approx(boxes_volume(BooleanOp::Union, boxes)).epsilon(1e-12));
    CHECK(su.quad_points > 0);
  }
  SECTION("a box flush over half a face, its edge across the diagonal: the diagonal's points stay") {
    // b's bottom lies on a's top (z = 1) and covers the half of it around x < 0.5; a's top
    // diagonal runs from (0, 0) to (1, 1) and b's edge x = 0.5 crosses it: there the diagonal is a
    // cut of b's face, and the point must stay where both faces have it.
    const Mesh a = box_mesh(Point3(0, 0, 0), Vec3(1, 1, 1));
    const Mesh b = box_mesh(Point3(-0.5, -0.25, 1), Vec3(1, 1.5, 0.5));
    const Mesh c = box_mesh(Point3(0.2, -1, 0.3), Vec3(0.2, 3, 1.5));  // crosses both, cuts a's top
    BooleanStats st;
    const BooleanResult u = run(BooleanOp::Union, {a, b, c}, st);
    const std::vector<std::array<Vec3, 2>> boxes = {{Vec3(0, 0, 0), Vec3(1, 1, 1)},
                                                    {Vec3(-0.5, -0.25, 1), Vec3(0.5, 1.25, 1.5)},
                                                    {Vec3(0.2, -1, 0.3), Vec3(0.4, 2, 1.8)}};
    CHECK(u.mesh.volume() == Approx(boxes_volume(BooleanOp::Union, boxes)).epsilon(1e-12));
    BooleanStats sd;
    const BooleanResult d = run(BooleanOp::Difference, {a, b, c}, sd);
    CHECK(d.mesh.volume() == Approx(boxes_volume(BooleanOp::Difference, boxes)).epsilon(1e-12));
  }
  SECTION("a box's corner on a diagonal: two cuts meet there at a right angle, and the point stays") {
    // a's top is split along (0, 0, 1) - (1, 1, 1); c's vertical edge x = y = 0.5 stands on it, so
    // c's two faces cut a's top along lines that end on the diagonal, one in each half.
    const Mesh a = box_mesh(Point3(0, 0, 0), Vec3(1, 1, 1));
    const Mesh c = box_mesh(Point3(0.5, 0.5, 0.5), Vec3(1, 1, 1));
    const std::vector<std::array<Vec3, 2>> boxes = {{Vec3(0, 0, 0), Vec3(1, 1, 1)},
                                                    {Vec3(0.5, 0.5, 0.5), Vec3(1.5, 1.5, 1.5)}};
    for (BooleanOp op : {BooleanOp::Union, BooleanOp::Difference}) {
      BooleanStats st;
      const BooleanResult r = run(op, {a, c}, st);
      CHECK(r.mesh.volume() == Approx(boxes_volume(op, boxes)).epsilon(1e-12));
    }
    BooleanStats st;
    const BooleanResult r = run(BooleanOp::Intersection, {a, c}, st);
    CHECK(r.mesh.volume() == Approx(0.125).epsilon(1e-12));
  }
}
