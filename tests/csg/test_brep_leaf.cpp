#include <catch2/catch.hpp>

#include <cmath>

#include "csg/brep_leaf.h"

using namespace wedge;

TEST_CASE("a B-Rep leaf answers exactly and tessellates watertight", "[csg][brep]") {
  SECTION("a box") {
    Solid s = brep_solid(box(Vec3(2, 3, 4)));
    MassProperties mp = s.mass_properties(Tolerance{});
    CHECK(mp.volume == Approx(24).epsilon(1e-14));
    CHECK(s.euler(Tolerance{}) == EulerCounts{8, 12, 6, 0, 0, 1});
    CHECK(s.validate(Tolerance{}).empty());
    Mesh m = s.mesh(Tolerance{});
    CHECK(m.triangle_count() == 12);
    CHECK(m.volume() == Approx(24));
    CHECK(euler_counts(m).characteristic() == 0);
  }
  SECTION("the worked example, arcs and cylinders included") {
    Solid s = brep_solid(worked_example());
    CHECK(s.euler(Tolerance{}) == EulerCounts{44, 66, 27, 5, 1, 1});
    Tolerance tol;
    tol.chordal = 1e-4;
    Mesh m = s.mesh(tol);
    EulerCounts mc = euler_counts(m);  // throws unless closed and 2-manifold
    CHECK(mc.S == 1);
    CHECK(mc.H == 1);
    double expected = 320 + 8 - 4 - (4 * 2.5 - (4 - kPi) * 0.25) - 4 * kPi;
    CHECK(m.volume() == Approx(expected).epsilon(1e-4));
    // Curved faces: the volume comes from the mesh.
    CHECK(s.mass_properties(tol).volume == Approx(expected).epsilon(1e-4));
  }
  SECTION("the worked example at coarse and default tolerances") {
    // Its cylinder faces are strips between two arcs whose edges are sampled each on its own, so
    // the arcs may get different numbers of points (at 0.01, the default, the hole's did, and
    // tessellation failed). Every point of the mesh is within the tolerance of the surface and
    // only the curved faces (the hole, r = 1, h = 4; four quarter-round corners, r = 0.5, 2.5 deep:
    // some 33 square units) are approximated, so the volume is within 40 * tolerance.
    Solid s = brep_solid(worked_example());
    const double expected = 320 + 8 - 4 - (4 * 2.5 - (4 - kPi) * 0.25) - 4 * kPi;
    for (double chordal : {0.3, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005}) {
      INFO("tolerance " << chordal);
      Tolerance tol;
      tol.chordal = chordal;
      Mesh m = s.mesh(tol);
      EulerCounts mc = euler_counts(m);  // throws unless closed and 2-manifold
      CHECK(mc.S == 1);
      CHECK(mc.H == 1);
      CHECK(std::abs(m.volume() - expected) <= 40 * chordal);
    }
  }
  SECTION("a mirrored box stays an exact, valid B-Rep") {
    Solid s = brep_solid(box(Vec3(1, 2, 3))).transformed(reflect(Vec3(1, 0, 0), Point3(5, 0, 0)));
    CHECK(s.validate(Tolerance{}).empty());
    MassProperties mp = s.mass_properties(Tolerance{});
    CHECK(mp.volume == Approx(6));
    CHECK(mp.centroid.x() == Approx(9.5));
  }
  SECTION("a prism with a hole as a Solid") {
    Solid s = prism_solid({{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}}}, 2);
    CHECK(s.euler(Tolerance{}) == EulerCounts{16, 24, 10, 2, 1, 1});
    CHECK(s.mass_properties(Tolerance{}).volume == Approx(24));
    CHECK(s.mesh(Tolerance{}).volume() == Approx(24));
  }
  SECTION("an invalid model is refused") {
    Model m;
    m.mvfs(Point3(0, 0, 0));
    CHECK_THROWS_WITH(brep_solid(std::move(m)), Catch::StartsWith("not a valid solid:"));
  }
}

TEST_CASE("a B-Rep leaf moved by a similarity gives its source's mesh moved, tessellated once", "[csg][brep]") {
  // A placed copy (translate, rotate, mirror, uniform scale) is not validated again and not
  // tessellated again: its mesh is the source's, moved; the source keeps it for all its copies.
  Tolerance tol;
  tol.chordal = 0.01;
  const Solid source = brep_solid(cylinder(0.5, 2));
  const Mesh base = source.mesh(tol);
  for (const Mat4& m : {Mat4(translate(Vec3(3, -2, 1))), Mat4(rotate_z(37) * translate(Vec3(1, 0, 0))),
                        Mat4(reflect(Vec3(1, 1, 0).normalized(), Point3(2, 0, 0)))}) {
    const Solid copy = source.transformed(m);
    const Mesh moved = copy.mesh(tol);
    const Mesh want = base.transformed(m);
    CHECK(moved.positions == want.positions);  // bit for bit: the same points moved
    CHECK(moved.triangles == want.triangles);
    CHECK(copy.validate(tol).empty());
    CHECK(moved.volume() == Approx(base.volume()).epsilon(1e-12));  // outward after a mirror too
    CHECK(copy.mass_properties(tol).volume == Approx(kPi * 0.25 * 2).epsilon(1e-12));
    // A copy of a copy composes the moves on the first source.
    const Solid again = copy.transformed(translate(Vec3(0, 0, 5)));
    CHECK(again.mesh(tol).positions == base.transformed(translate(Vec3(0, 0, 5)) * m).positions);
  }
  // An enlarged copy keeps the tolerance in its own units: the source is tessellated finer.
  const Solid big = source.transformed(scale(Vec3(4, 4, 4)));
  const Mesh b = big.mesh(tol);
  CHECK(b.triangle_count() > base.triangle_count());
  CHECK(b.volume() == Approx(kPi * 4 * 8).epsilon(2 * tol.chordal / 2));  // within the chordal error of r = 2
  // A stretch is no similarity: that copy is a model of its own, validated and tessellated.
  const Solid stretched = brep_solid(box(Vec3(1, 1, 1))).transformed(scale(Vec3(1, 2, 3)));
  CHECK(stretched.mass_properties(tol).volume == Approx(6));
  CHECK(stretched.validate(tol).empty());
}

TEST_CASE("a symmetric leaf's copy alone keeps the move asked and as an operand stands as its canonical twin", "[csg][brep]") {
  // Alone, a turned sphere is its source's mesh turned (a texture on it turns with it); as a
  // boolean's operand it is placed by its symmetry, its source's very mesh, so that a sphere minus
  // its turned copy is empty.
  const Symmetry point{Symmetry::Kind::Point, Point3::Zero(), Vec3::UnitZ(), false};
  const Solid s = brep_solid(sphere(1, Point3::Zero()), point);
  const Solid turned = s.transformed(rotate_z(30));
  Tolerance tol;
  const Mesh source = s.mesh(tol);
  const Mesh alone = turned.mesh(tol);
  REQUIRE(alone.positions.size() == source.positions.size());
  const Mesh asked = source.transformed(rotate_z(30));
  for (std::size_t i = 0; i < asked.positions.size(); ++i) CHECK((alone.positions[i] - asked.positions[i]).norm() <= 1e-15);
  bool moved = false;
  for (std::size_t i = 0; i < source.positions.size(); ++i) moved = moved || source.positions[i] != alone.positions[i];
  CHECK(moved);
  const Solid d = Solid::boolean(BooleanOp::Difference, {s, turned});
  CHECK(d.mesh(tol).triangles.empty());
  // A move asked twice through its canonical placement (placed already): no twin of the twin.
  CHECK(canonical_move(canonical_move(rotate_z(30), point), point) == canonical_move(rotate_z(30), point));
  // Without a symmetry, a turned sphere's copy is another solid to the engine.
  const Solid plain = brep_solid(sphere(1, Point3::Zero()));
  const Solid d2 = Solid::boolean(BooleanOp::Difference, {plain, plain.transformed(rotate_z(30))});
  CHECK(!d2.mesh(tol).triangles.empty());
}
