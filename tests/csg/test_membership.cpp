// Point membership and cell decomposition against closed forms: boxes and their booleans decided
// exactly (points on faces, edges and corners, and the doubles next to them), a sphere within
// its tolerance, and octree volume bounds that bracket the exact volume and tighten.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "csg/brep_leaf.h"
#include "csg/csg.h"

using namespace wedge;

namespace {
Solid box_solid(const Vec3& size, const Point3& corner = Point3::Zero()) { return brep_solid(box(size, corner)); }

// The closed form for the regularised difference [0,2]^3 - [1,3]^3.
Membership l_shape(const Point3& p) {
  auto in_closed = [](const Point3& q, double lo, double hi) { return (q.array() >= lo).all() && (q.array() <= hi).all(); };
  auto in_open = [](const Point3& q, double lo, double hi) { return (q.array() > lo).all() && (q.array() < hi).all(); };
  bool closure = in_closed(p, 0, 2) && !in_open(p, 1, 3);
  bool interior = in_open(p, 0, 2) && !in_closed(p, 1, 3);
  return interior ? Membership::Inside : closure ? Membership::Boundary : Membership::Outside;
}
}  // namespace

TEST_CASE("contains: a box's interior, faces, edges, corners and the doubles beside them", "[membership]") {
  Solid b = box_solid(Vec3(1, 2, 3));
  Tolerance tol;
  REQUIRE(b.polyhedral());
  CHECK(b.contains({0.5, 1, 1.5}, tol) == Membership::Inside);
  CHECK(b.contains({1, 1, 1.5}, tol) == Membership::Boundary);   // face
  CHECK(b.contains({1, 2, 1.5}, tol) == Membership::Boundary);   // edge
  CHECK(b.contains({1, 2, 3}, tol) == Membership::Boundary);     // corner
  CHECK(b.contains({0, 0, 0}, tol) == Membership::Boundary);
  const double above = std::nextafter(1.0, 2.0), below = std::nextafter(1.0, 0.0);
  CHECK(b.contains({above, 1, 1.5}, tol) == Membership::Outside);
  CHECK(b.contains({below, 1, 1.5}, tol) == Membership::Inside);
  CHECK(b.contains({0.5, 1, std::nextafter(3.0, 4.0)}, tol) == Membership::Outside);
  CHECK(b.contains({0.5, 1, -1e-300}, tol) == Membership::Outside);
  CHECK(b.contains({0.5, 1, 1e-300}, tol) == Membership::Inside);
  CHECK(b.contains({5, 5, 5}, tol) == Membership::Outside);
  CHECK(Solid().contains({0, 0, 0}, tol) == Membership::Outside);
  CHECK_THROWS_WITH(b.contains({std::nan(""), 0, 0}, tol), Catch::Contains("not finite"));
}

TEST_CASE("contains: a boolean result agrees with the closed form on a grid through its faces", "[membership]") {
  Solid d = Solid::boolean(BooleanOp::Difference, {box_solid(Vec3(2, 2, 2)), box_solid(Vec3(2, 2, 2), Point3(1, 1, 1))});
  Tolerance tol;
  REQUIRE(d.polyhedral());
  int counts[3] = {0, 0, 0};
  for (int i = -1; i <= 13; ++i)
    for (int j = -1; j <= 13; ++j)
      for (int k = -1; k <= 13; k += 2) {
        Point3 p(i * 0.25, j * 0.25, k * 0.25);
        Membership want = l_shape(p);
        INFO(p.transpose());
        REQUIRE(d.contains(p, tol) == want);
        ++counts[int(want)];
      }
  // The grid met every kind of answer, boundary included.
  CHECK(counts[0] > 0);
  CHECK(counts[1] > 0);
  CHECK(counts[2] > 0);
}

TEST_CASE("contains: random points in a rotated, translated box", "[membership]") {
  Mat4 m = translate(Vec3(0.3, -0.2, 0.1)) * rotate(37, Vec3(1, 2, 3).normalized());
  Solid b = box_solid(Vec3(1, 2, 3)).transformed(m);
  Mat4 inv = m.inverse();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 3.5);
  Tolerance tol;
  int inside = 0;
  for (int n = 0; n < 400; ++n) {
    Point3 p(u(rng), u(rng), u(rng));
    Point3 q = apply_point(inv, p);
    // Skip points so near a face that rounding of the transformed box could decide them.
    double d = std::min({q.x(), 1 - q.x(), q.y(), 2 - q.y(), q.z(), 3 - q.z()});
    if (std::abs(d) < 1e-9) continue;
    Membership want = d > 0 ? Membership::Inside : Membership::Outside;
    inside += want == Membership::Inside;
    REQUIRE(b.contains(p, tol) == want);
  }
  CHECK(inside > 5);
}

TEST_CASE("contains: a sphere within its tolerance", "[membership][slow]") {
  Solid s = brep_solid(sphere(2, Point3(1, 0, 0)));
  Tolerance tol;
  tol.chordal = 1e-3;
  REQUIRE(!s.polyhedral());
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  for (int n = 0; n < 200; ++n) {
    Vec3 v(u(rng), u(rng), u(rng));
    double r = v.norm();
    if (std::abs(r - 2) < 3 * tol.chordal) continue;
    Point3 p = Point3(1, 0, 0) + v;
    REQUIRE(s.contains(p, tol) == (r < 2 ? Membership::Inside : Membership::Outside));
  }
  // On the sphere (to within the tolerance) is the boundary.
  CHECK(s.contains(Point3(1, 0, 2), tol) == Membership::Boundary);
  CHECK(s.contains(Point3(1 + 2 * std::cos(0.3), 2 * std::sin(0.3), 0), tol) == Membership::Boundary);
}

TEST_CASE("contains: a curved leaf is tessellated once per tolerance and not again on every call", "[membership]") {
  // contains() took the leaf's mesh afresh each call: sphere(1000) at 0.001 spent 15 s and 2 GB
  // per call, and a bisection by contains() grew past 2 GB.
  EvalStats stats;
  EvalControl control;
  control.stats = &stats;
  set_eval_control(&control);
  struct Off {
    ~Off() { set_eval_control(nullptr); }
  } off;
  Tolerance tol;
  Solid s = brep_solid(sphere(1)), moved = s.transformed(translate(Vec3(5, 0, 0)));
  for (int i = 0; i < 3; ++i) {
    CHECK(s.contains({0, 0, 0}, tol) == Membership::Inside);
    CHECK(moved.contains({5, 0, 0}, tol) == Membership::Inside);
  }
  CHECK(stats.cached >= 4);  // the second and third calls of each found the first's mesh
  const long before = stats.cached;
  CHECK(s.cells(0.5, tol).cells.size() > 0);
  CHECK(stats.cached == before + 1);
}

TEST_CASE("cells: octree volume bounds bracket the exact volume and tighten", "[membership][cells]") {
  Tolerance tol;
  SECTION("a box and an L-shaped difference (exact volumes 6 and 7)") {
    Solid b = box_solid(Vec3(1, 2, 3), Point3(0.1, 0.2, 0.3));
    Solid d = Solid::boolean(BooleanOp::Difference, {box_solid(Vec3(2, 2, 2)), box_solid(Vec3(2, 2, 2), Point3(1, 1, 1))});
    for (auto [s, v] : {std::pair{b, 6.0}, std::pair{d, 7.0}}) {
      double gap = 1e300;
      for (double size : {0.8, 0.4, 0.2, 0.1}) {
        CellDecomposition c = s.cells(size, tol);
        INFO("size " << size);
        CHECK(c.volume_min <= v);
        CHECK(c.volume_max >= v);
        CHECK(c.volume_max - c.volume_min < gap);
        gap = c.volume_max - c.volume_min;
        if (size <= 0.4) CHECK(c.inside > 0);
        CHECK(c.boundary > 0);
        CHECK(static_cast<long>(c.cells.size()) == c.inside + c.boundary + c.outside);
      }
      // The boundary cells of size h cover a shell about the surface's area times a few h.
      CHECK(gap < 2.0);
    }
  }
  SECTION("a sphere (4/3 pi r^3) and a torus (2 pi^2 R r^2), curved, bracketed") {
    tol.chordal = 1e-3;
    Solid sp = brep_solid(sphere(1.5));
    Solid to = brep_solid(torus(2, 0.5));
    const double vs = 4.0 / 3.0 * kPi * 1.5 * 1.5 * 1.5, vt = 2 * kPi * kPi * 2 * 0.25;
    for (auto [s, v] : {std::pair{sp, vs}, std::pair{to, vt}}) {
      double gap = 1e300;
      for (double size : {0.5, 0.25, 0.125}) {
        CellDecomposition c = s.cells(size, tol);
        CHECK(c.volume_min <= v);
        CHECK(c.volume_max >= v);
        CHECK(c.volume_max - c.volume_min < gap);
        gap = c.volume_max - c.volume_min;
      }
      CHECK(gap < 0.5 * v);
    }
  }
  CHECK_THROWS_WITH(box_solid(Vec3(1, 1, 1)).cells(0, tol), Catch::Contains("size must be a positive number"));
  CHECK_THROWS_WITH(box_solid(Vec3(1, 1, 1)).cells(1e-6, tol), Catch::Contains("choose a larger size"));
}

TEST_CASE("cells: a size larger than the solid gives one boundary cell about its bounds, not an infinite one", "[membership][cells]") {
  // The root cell was the bounds widened by a thousandth of the size: 1e297 at size 1e300, so
  // volume_max was infinite. The L-shaped difference has volume 7 in its 2 x 2 x 2 bounds.
  Tolerance tol;
  Solid d = Solid::boolean(BooleanOp::Difference, {box_solid(Vec3(2, 2, 2)), box_solid(Vec3(2, 2, 2), Point3(1, 1, 1))});
  for (double size : {3.0, 1e10, 1e300, std::numeric_limits<double>::max()}) {
    INFO("size " << size);
    CellDecomposition c = d.cells(size, tol);
    CHECK(c.boundary == 1);
    CHECK(c.inside == 0);
    CHECK(c.volume_min == 0);
    CHECK(c.volume_max >= 7);
    CHECK(c.volume_max <= 8 * 1.02);  // the bounds widened by a thousandth of their diagonal a side
  }
}
