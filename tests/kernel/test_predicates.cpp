#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>

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

TEST_CASE("orient3d agrees with exact integer arithmetic where the naive determinant does not", "[predicates]") {
  // Integer coordinates below 2^40: the determinant fits in a 128-bit integer, which gives the
  // true sign. d = a + s(b-a) + t(c-a) with small integers s, t lies exactly on the plane of a, b,
  // c (true sign 0), but the naive double determinant rounds its 2^80-sized products and
  // usually returns a non-zero sign; half of the cases nudge d off the plane by one unit.
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<std::int64_t> coord(0, (std::int64_t(1) << 40) - 1);
  std::uniform_int_distribution<int> param(-2, 2), nudge(0, 1);
  int naive_wrong = 0, cases = 2000;
  for (int i = 0; i < cases; ++i) {
    std::int64_t P[4][3];
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) P[k][j] = coord(rng);
    std::int64_t s = param(rng), t = param(rng);
    for (int j = 0; j < 3; ++j) P[3][j] = P[0][j] + s * (P[1][j] - P[0][j]) + t * (P[2][j] - P[0][j]);
    P[3][2] += nudge(rng);
    __int128 u[3], v[3], w[3];
    for (int j = 0; j < 3; ++j) {
      u[j] = P[1][j] - P[0][j];
      v[j] = P[2][j] - P[0][j];
      w[j] = P[3][j] - P[0][j];
    }
    __int128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
    int truth = (det > 0) - (det < 0);
    Point3 p[4];
    for (int k = 0; k < 4; ++k) p[k] = Point3(double(P[k][0]), double(P[k][1]), double(P[k][2]));
    REQUIRE(orient3d(p[0], p[1], p[2], p[3]) == truth);
    int naive = sgn((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]));
    if (naive != truth) ++naive_wrong;
  }
  CHECK(naive_wrong > cases / 10);  // the naive sign is wrong on a good share of these inputs
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
