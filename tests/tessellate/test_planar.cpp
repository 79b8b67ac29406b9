#include <catch2/catch.hpp>

#include <cmath>
#include <set>

#include "tessellate/tessellate.h"

using namespace wedge;

namespace {
double area_about(const std::vector<Point3>& p, const std::vector<Triangle>& tris, const Vec3& n, bool& all_ccw) {
  double a = 0;
  all_ccw = true;
  for (const auto& t : tris) {
    double s = 0.5 * (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]).dot(n.normalized());
    if (s <= 0) all_ccw = false;
    a += s;
  }
  return a;
}
}  // namespace

TEST_CASE("a square face with a square hole is triangulated without new points", "[planar]") {
  // Outer 4x4 square CCW about +z, hole 2x2 CW, in the plane z = 1.
  std::vector<Point3> p = {{0, 0, 1}, {4, 0, 1}, {4, 4, 1}, {0, 4, 1}, {1, 1, 1}, {1, 3, 1}, {3, 3, 1}, {3, 1, 1}};
  auto tris = triangulate_face(p, {{0, 1, 2, 3}, {4, 5, 6, 7}}, {0, 0, 1});
  bool ccw = false;
  CHECK(area_about(p, tris, {0, 0, 1}, ccw) == Approx(16 - 4));
  CHECK(ccw);
  CHECK(tris.size() == 8);  // an annulus of 8 vertices and 2 loops: V + 2(loops - 2) = 8 triangles
  std::set<std::uint32_t> used;
  for (const auto& t : tris) used.insert(t.begin(), t.end());
  CHECK(used.size() == 8);
}

TEST_CASE("a non-convex face in a tilted plane keeps its concavity", "[planar]") {
  // An L shape of area 3 in the plane x = y (normal (1,-1,0)/sqrt2), CCW about that normal.
  Vec3 u = Vec3(1, 1, 0).normalized(), w(0, 0, 1), n = u.cross(w);
  std::vector<Vec2> l = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  std::vector<Point3> p;
  for (const auto& q : l) p.push_back(q.x() * u + q.y() * w + Vec3(5, 5, 5));
  auto tris = triangulate_face(p, {{0, 1, 2, 3, 4, 5}}, n);
  bool ccw = false;
  CHECK(area_about(p, tris, n, ccw) == Approx(3));
  CHECK(ccw);
  CHECK(tris.size() == 4);
  CHECK(newell_normal(p).normalized().isApprox(n.normalized(), 1e-12));
  CHECK(newell_normal(p).norm() == Approx(2 * 3));
}

TEST_CASE("bad faces are errors in words", "[planar][errors]") {
  std::vector<Point3> p = {{0, 0, 0}, {2, 2, 0}, {2, 0, 0}, {0, 2, 0}};
  CHECK_THROWS_WITH(triangulate_face(p, {{0, 1, 2, 3}}, {0, 0, 1}), Catch::Contains("cross"));
  CHECK_THROWS_WITH(triangulate_face(p, {{0, 1}}, {0, 0, 1}), Catch::Contains("3 or more"));
  CHECK_THROWS_WITH(triangulate_face(p, {{0, 1, 9}}, {0, 0, 1}), Catch::Contains("vertex 9"));
  CHECK_THROWS_WITH(triangulate_face(p, {{0, 1, 2}}, {0, 0, 0}), Catch::Contains("normal is zero"));
}

TEST_CASE("a face of thousands of points on a wavy circle with a hole", "[planar]") {
  // The points go in spatially sorted (in loop order, each new one on the hull flipped edges back
  // to most of the earlier ones). The result is the same kind: every point used, no new one,
  // every triangle counter-clockwise, the area of the polygon.
  const int n = 4000;
  std::vector<Point3> p;
  std::vector<std::uint32_t> outer, hole;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, r = 1 + 0.1 * std::sin(7 * a);
    p.push_back(Point3(r * std::cos(a), r * std::sin(a), 2));
    outer.push_back(static_cast<std::uint32_t>(i));
  }
  for (int i = 0; i < 500; ++i) {
    const double a = -2 * M_PI * i / 500;
    p.push_back(Point3(0.4 * std::cos(a), 0.4 * std::sin(a), 2));
    hole.push_back(static_cast<std::uint32_t>(n + i));
  }
  auto polygon_area = [&](const std::vector<std::uint32_t>& loop) {
    double s = 0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Point3 &a = p[loop[i]], &b = p[loop[(i + 1) % loop.size()]];
      s += a.x() * b.y() - b.x() * a.y();
    }
    return s / 2;
  };
  const auto tris = triangulate_face(p, {outer, hole}, {0, 0, 1});
  bool ccw = false;
  CHECK(area_about(p, tris, {0, 0, 1}, ccw) == Approx(polygon_area(outer) + polygon_area(hole)).epsilon(1e-12));
  CHECK(ccw);
  CHECK(tris.size() == std::size_t(n + 500));  // V + 2(loops - 2)
  std::set<std::uint32_t> used;
  for (const auto& t : tris) used.insert(t.begin(), t.end());
  CHECK(used.size() == std::size_t(n + 500));
  // The hole given twice, one of its points under a second index at the same place: one vertex
  // there, named by the last of the two in loop order, as before the sort.
  p.push_back(p[n + 250]);
  std::vector<std::uint32_t> hole2 = hole;
  hole2[250] = static_cast<std::uint32_t>(p.size() - 1);
  const auto again = triangulate_face(p, {outer, hole, hole2}, {0, 0, 1});
  std::set<std::uint32_t> named;
  for (const auto& t : again) named.insert(t.begin(), t.end());
  CHECK(named.count(static_cast<std::uint32_t>(p.size() - 1)) == 1);
  CHECK(named.count(static_cast<std::uint32_t>(n + 250)) == 0);
}
