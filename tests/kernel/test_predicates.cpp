#include <catch2/catch.hpp>

#include <cmath>

#include "kernel/kernel.h"

using namespace wedge;

namespace {
// The textbook floating-point determinant, to show where it fails.
double naive_orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}
int sgn(double x) { return (x > 0) - (x < 0); }
}  // namespace

TEST_CASE("orient2d on easy cases", "[predicates]") {
  CHECK(orient2d({0, 0}, {1, 0}, {0, 1}) == 1);
  CHECK(orient2d({0, 0}, {0, 1}, {1, 0}) == -1);
  CHECK(orient2d({0, 0}, {1, 1}, {2, 2}) == 0);
}

TEST_CASE("orient2d is exact where naive double arithmetic gets the sign wrong", "[predicates]") {
  // Points a within a few ulps of (0.5, 0.5), tested against the line through (12,12) and
  // (24,24), which is y = x (after Kettner et al., "Classroom examples of robustness problems").
  // The exact sign is sign(ay - ax); the naive determinant rounds a - b and loses it.
  Vec2 b(12, 12), c(24, 24);
  int naive_wrong = 0;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      Vec2 a(0.5 + i * std::ldexp(1.0, -53), 0.5 + j * std::ldexp(1.0, -53));
      // Exact truth: a is on the line y = x iff ax == ay; left of b->c (above) iff ay > ax.
      int truth = sgn(a.y() - a.x());
      // Orientation (b, c, a): c - b = (12, 12), a - b: sign of 12*(ay - by) - 12*(ax - bx) = sign(ay - ax).
      CHECK(orient2d(b, c, a) == truth);
      if (sgn(naive_orient2d(b, c, a)) != truth) ++naive_wrong;
    }
  }
  // The naive formula is wrong on many of these inputs; the exact one on none.
  CHECK(naive_wrong > 100);
}

TEST_CASE("orient3d is exact on nearly coplanar points", "[predicates]") {
  Point3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK(orient3d(a, b, c, {0.3, 0.3, 1}) == 1);
  CHECK(orient3d(a, b, c, {0.3, 0.3, -1}) == -1);
  CHECK(orient3d(a, b, c, {0.3, 0.3, 0}) == 0);
  CHECK(orient3d(a, b, c, {5, 7, 1e-300}) == 1);  // far below any float tolerance
  // A plane that is not axis-aligned, and points placed on it by construction whose
  // coordinates are rounded: the exact predicate agrees with exact reasoning about a
  // case we can decide by hand, x + y + z = 1.5 with dyadic coordinates (exactly on it).
  Point3 p(0.5, 0.5, 0.5), q(1.5, 0, 0), r(0, 1.5, 0);
  CHECK(orient3d(p, q, r, {0.25, 0.25, 1.0}) == 0);
  CHECK(orient3d(p, q, r, {0.25, 0.25, std::nextafter(1.0, 2.0)}) != 0);
  CHECK(coplanar(p, q, r, {0.25, 0.25, 1.0}));
  CHECK_FALSE(coplanar(p, q, r, {0.25, 0.25, std::nextafter(1.0, 0.0)}));
}

TEST_CASE("naive orient3d misjudges points one ulp off a skew plane; the exact predicate does not", "[predicates]") {
  // Plane through three points with large, non-representable-sum coordinates.
  Point3 a(1e8 + 0.1, 3.3, 1), b(2.2, 1e8 + 0.7, 2), c(5.5, 6.6, 1e8 + 0.3);
  auto naive = [](const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
    return sgn((b - a).cross(c - a).dot(d - a));
  };
  // Sample points along a line through the plane, step by ulps; the exact sign is monotone
  // along the line (negative, then zero or positive): check that the predicate is monotone,
  // which naive arithmetic is not.
  Point3 base = (a + b + c) / 3.0;
  int prev = -2, exact_changes = 0, naive_changes = 0, prev_naive = -2;
  for (int i = -200; i <= 200; ++i) {
    Point3 d(base.x(), base.y(), base.z() + i * std::ldexp(base.z(), -52));
    int s = orient3d(a, b, c, d), n = naive(a, b, c, d);
    if (prev != -2 && s != prev) ++exact_changes;
    if (prev_naive != -2 && n != prev_naive) ++naive_changes;
    prev = s;
    prev_naive = n;
  }
  CHECK(exact_changes <= 2);    // - ... (0) ... +
  CHECK(naive_changes > 2);     // flips back and forth
}

TEST_CASE("incircle and insphere", "[predicates]") {
  CHECK(incircle({0, 0}, {1, 0}, {0, 1}, {0.5, 0.5}) == 1);
  CHECK(incircle({0, 0}, {1, 0}, {0, 1}, {2, 2}) == -1);
  CHECK(incircle({0, 0}, {1, 0}, {0, 1}, {1, 1}) == 0);  // cocircular: exact zero
  CHECK(incircle({0, 0}, {1, 0}, {0, 1}, {1, std::nextafter(1.0, 2.0)}) == -1);
  Point3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  REQUIRE(orient3d(a, b, c, d) == 1);
  CHECK(insphere(a, b, c, d, {0.25, 0.25, 0.25}) == 1);
  CHECK(insphere(a, b, c, d, {3, 3, 3}) == -1);
  CHECK(insphere(a, b, c, d, {1, 1, 1}) == 0);  // the cube's far corner lies on the sphere
}

TEST_CASE("segment and triangle intersection tests, including touching and degenerate", "[predicates]") {
  Point3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK(segment_triangle_intersect({0.2, 0.2, -1}, {0.2, 0.2, 1}, a, b, c));
  CHECK_FALSE(segment_triangle_intersect({0.8, 0.8, -1}, {0.8, 0.8, 1}, a, b, c));
  CHECK(segment_triangle_intersect({0.5, 0.5, -1}, {0.5, 0.5, 1}, a, b, c));  // through the edge
  CHECK(segment_triangle_intersect({0.2, 0.2, 0}, {0.2, 0.2, 1}, a, b, c));   // touches at an end
  CHECK_FALSE(segment_triangle_intersect({0.2, 0.2, 1e-300}, {0.2, 0.2, 1}, a, b, c));
  // Degenerate triangle (a segment) crossed by a segment.
  CHECK(segment_triangle_intersect({0.5, -1, 0}, {0.5, 1, 0}, a, b, {2, 0, 0}));
  CHECK(segments_intersect_2d({0, 0}, {2, 2}, {0, 2}, {2, 0}));
  CHECK_FALSE(segments_intersect_2d({0, 0}, {1, 1}, {0, 2}, {0.9, 1.1}));
  CHECK(segments_intersect_2d({0, 0}, {1, 1}, {1, 1}, {2, 0}));  // shared endpoint
  CHECK(triangles_intersect(a, b, c, {0.2, 0.2, -1}, {0.2, 0.2, 1}, {5, 5, 1}));
  CHECK_FALSE(triangles_intersect(a, b, c, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}));
}

TEST_CASE("predicates reject non-finite input with a clear error", "[predicates][errors]") {
  CHECK_THROWS_WITH(orient2d({0, 0}, {1, 0}, {std::nan(""), 1}), Catch::Contains("finite"));
}
