// The retriangulation's constrained Delaunay triangulation of one triangle (csg/boolean_cdt.cpp):
// on integer points (so that every in-circle decision is exact) with many collinear points, points
// on the triangle's edges, repeated points and long constraints that cross many edges, the result
// is a triangulation of the triangle, has every point and every constraint, and is Delaunay
// across every edge that is not a constraint.
#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <random>
#include <set>

#include "csg/boolean_impl.h"
#include "kernel/predicates.h"

using namespace wedge;
using namespace wedge::boolean_detail;

namespace {

struct Case {
  Soup soup;
  std::vector<u32> points;
  std::vector<std::array<u32, 2>> constraints;
};

Point2 p2(const Soup& s, u32 v) { return Point2(s.verts[v].x(), s.verts[v].y()); }

// Whether c lies on the closed segment a b.
bool on_segment(const Soup& s, u32 a, u32 b, u32 c) {
  if (wedge::orient2d(p2(s, a), p2(s, b), p2(s, c)) != 0) return false;
  const Vec3 &A = s.verts[a], &B = s.verts[b], &C = s.verts[c];
  return std::min(A.x(), B.x()) <= C.x() && C.x() <= std::max(A.x(), B.x()) && std::min(A.y(), B.y()) <= C.y() &&
         C.y() <= std::max(A.y(), B.y());
}

// Whether segments a b and c d meet anywhere but in a shared end point.
bool segments_meet(const Soup& s, u32 a, u32 b, u32 c, u32 d) {
  const int shared = (a == c) + (a == d) + (b == c) + (b == d);
  if (shared == 2) return true;  // the same segment
  const int o1 = wedge::orient2d(p2(s, a), p2(s, b), p2(s, c)), o2 = wedge::orient2d(p2(s, a), p2(s, b), p2(s, d));
  const int o3 = wedge::orient2d(p2(s, c), p2(s, d), p2(s, a)), o4 = wedge::orient2d(p2(s, c), p2(s, d), p2(s, b));
  if (shared == 1) {
    // Sharing one end: they overlap only if collinear and pointing the same way.
    if (o1 != 0 || o2 != 0) return false;
    const u32 e = (a == c || a == d) ? a : b, x = (e == a) ? b : a, y = (e == c) ? d : c;
    return on_segment(s, e, x, y) || on_segment(s, e, y, x);
  }
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return on_segment(s, a, b, c) || on_segment(s, a, b, d) || on_segment(s, c, d, a) || on_segment(s, c, d, b);
}

// Integer points in the triangle (0, 0), (n, 0), (0, n): `grid` of them on a lattice of step 4
// (rows and columns of collinear points, some on the triangle's edges), `loose` anywhere, and
// `wanted` constraints between random pairs that pass through no other point and meet no other
// constraint but at end points.
Case make_case(int n, int loose, int wanted, unsigned seed) {
  Case c;
  std::mt19937 rng(seed);
  std::map<std::pair<int, int>, u32> at;
  auto add = [&](int x, int y) {
    auto it = at.find({x, y});
    if (it != at.end()) return it->second;
    const u32 id = static_cast<u32>(c.soup.verts.size());
    c.soup.verts.push_back(Vec3(x, y, 0));
    at[{x, y}] = id;
    return id;
  };
  add(0, 0), add(n, 0), add(0, n);
  for (int x = 0; x <= n; x += 4)
    for (int y = 0; x + y <= n; y += 4) add(x, y);
  std::uniform_int_distribution<int> coord(0, n);
  for (int i = 0; i < loose; ++i) {
    int x = coord(rng), y = coord(rng);
    if (x + y > n) x = n - x, y = n - y;
    add(x, y);
  }
  c.soup.tris = {{0, 1, 2}};
  c.soup.operand = {0};
  c.soup.local = {0};
  c.soup.face_id = {-1};
  c.soup.axis = {2};
  c.soup.axis_sign = {1};
  c.soup.operands = 1;
  for (u32 v = 0; v < c.soup.verts.size(); ++v) c.points.push_back(v);
  std::shuffle(c.points.begin(), c.points.end(), rng);
  // Some points twice: the triangulation keeps one vertex.
  for (int i = 0; i < 5; ++i) c.points.push_back(c.points[static_cast<std::size_t>(i) * 3]);
  const u32 nv = static_cast<u32>(c.soup.verts.size());
  std::uniform_int_distribution<u32> pick(0, nv - 1);
  for (int tries = 0; tries < 50 * wanted && static_cast<int>(c.constraints.size()) < wanted; ++tries) {
    const u32 a = pick(rng), b = pick(rng);
    if (a == b) continue;
    bool ok = true;
    for (u32 v = 0; v < nv && ok; ++v)
      if (v != a && v != b && on_segment(c.soup, a, b, v)) ok = false;
    for (const auto& e : c.constraints)
      if (ok && segments_meet(c.soup, a, b, e[0], e[1])) ok = false;
    if (ok) c.constraints.push_back({a, b});
  }
  return c;
}

// Checks that `tris` triangulates the case's triangle with all its points and constraints, and is
// Delaunay across every other edge (in the metric x^2 + (stretch y)^2).
void check(const Case& c, const std::vector<std::array<u32, 3>>& tris, double stretch = 1) {
  const Soup& s = c.soup;
  double area = 0;
  std::map<std::pair<u32, u32>, int> edges;  // directed edge -> its triangle
  std::set<u32> used;
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const auto& T = tris[t];
    REQUIRE(wedge::orient2d(p2(s, T[0]), p2(s, T[1]), p2(s, T[2])) > 0);
    const Vec3 &a = s.verts[T[0]], &b = s.verts[T[1]], &d = s.verts[T[2]];
    area += (b.x() - a.x()) * (d.y() - a.y()) - (b.y() - a.y()) * (d.x() - a.x());
    for (int e = 0; e < 3; ++e) {
      REQUIRE(edges.emplace(std::make_pair(T[e], T[(e + 1) % 3]), static_cast<int>(t)).second);
      used.insert(T[e]);
    }
  }
  const double n = s.verts[1].x();
  CHECK(area == n * n);  // twice the triangle's area, exactly (small integers)
  CHECK(used.size() == s.verts.size());
  // Each edge has a twin, but on the triangle's boundary.
  for (const auto& [e, t] : edges)
    if (!edges.count({e.second, e.first})) {
      const bool boundary = on_segment(s, 0, 1, e.first) && on_segment(s, 0, 1, e.second);
      const bool left = on_segment(s, 0, 2, e.first) && on_segment(s, 0, 2, e.second);
      const bool diagonal = on_segment(s, 1, 2, e.first) && on_segment(s, 1, 2, e.second);
      REQUIRE((boundary || left || diagonal));
    }
  std::set<std::pair<u32, u32>> constrained;
  for (const auto& e : c.constraints) {
    CHECK((edges.count({e[0], e[1]}) + edges.count({e[1], e[0]})) > 0);
    constrained.insert({std::min(e[0], e[1]), std::max(e[0], e[1])});
  }
  // Delaunay: across each edge that is not a constraint, the far vertex is not inside the circle.
  for (const auto& [e, t] : edges) {
    auto twin = edges.find({e.second, e.first});
    if (twin == edges.end() || constrained.count({std::min(e.first, e.second), std::max(e.first, e.second)})) continue;
    const auto& T = tris[static_cast<std::size_t>(t)];
    const auto& U = tris[static_cast<std::size_t>(twin->second)];
    u32 far = U[0] + U[1] + U[2] - e.first - e.second;
    auto q = [&](u32 v) { return Point2(s.verts[v].x(), stretch * s.verts[v].y()); };  // exact: a power of 2
    CHECK(wedge::incircle(q(T[0]), q(T[1]), q(T[2]), q(far)) <= 0);
  }
}

}  // namespace

TEST_CASE("boolean cdt: collinear rows, points on the edges, repeats and long constraints", "[boolean]") {
  for (unsigned seed = 1; seed <= 12; ++seed) {
    Case c = make_case(64, 60, 40, seed);
    Points pts(c.soup);
    std::vector<std::array<u32, 3>> tris;
    constrained_delaunay(pts, 2, 0.01, {0, 1, 2}, c.points, c.constraints, tris);
    INFO("seed " << seed << ", " << c.soup.verts.size() << " points, " << c.constraints.size() << " constraints");
    REQUIRE(c.constraints.size() >= 20);
    check(c, tris);
  }
}

TEST_CASE("boolean cdt: a constraint through collinear points is split at them", "[boolean]") {
  // The constraint from (0, 0) to (0, 64) runs along the triangle's edge through every lattice
  // point on it; one from (4, 4) to (40, 4) through a row.
  Case c = make_case(64, 0, 0, 7);
  c.constraints = {{0, 2}};
  u32 a = kNone, b = kNone;
  for (u32 v = 0; v < c.soup.verts.size(); ++v) {
    if (c.soup.verts[v] == Vec3(4, 4, 0)) a = v;
    if (c.soup.verts[v] == Vec3(40, 4, 0)) b = v;
  }
  REQUIRE(a != kNone);
  REQUIRE(b != kNone);
  c.constraints.push_back({a, b});
  Points pts(c.soup);
  std::vector<std::array<u32, 3>> tris;
  constrained_delaunay(pts, 2, 0.01, {0, 1, 2}, c.points, c.constraints, tris);
  // Each piece between neighbouring lattice points on the two constraints is an edge.
  auto id = [&](int x, int y) {
    for (u32 v = 0; v < c.soup.verts.size(); ++v)
      if (c.soup.verts[v] == Vec3(x, y, 0)) return v;
    return kNone;
  };
  c.constraints.clear();
  for (int y = 0; y < 64; y += 4) c.constraints.push_back({id(0, y), id(0, y + 4)});
  for (int x = 4; x < 40; x += 4) c.constraints.push_back({id(x, 4), id(x + 4, 4)});
  check(c, tris);
}

TEST_CASE("boolean cdt: in a metric, the triangulation is Delaunay where that metric maps the points", "[boolean]") {
  // q(x, y) = x^2 + 4 y^2: the circles are the ellipses of the plane stretched by 2 along y.
  const Points::Metric metric{1, 0, 4};
  for (unsigned seed = 1; seed <= 6; ++seed) {
    Case c = make_case(64, 60, 40, seed);
    Points pts(c.soup);
    std::vector<std::array<u32, 3>> tris, plain;
    constrained_delaunay(pts, 2, 0.01, {0, 1, 2}, c.points, c.constraints, tris, nullptr, &metric);
    INFO("seed " << seed);
    check(c, tris, 2);
    // Not the plain triangulation: the metric changed some edges.
    constrained_delaunay(pts, 2, 0.01, {0, 1, 2}, c.points, c.constraints, plain);
    auto sorted = [](std::vector<std::array<u32, 3>> v) {
      for (auto& t : v) std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      std::sort(v.begin(), v.end());
      return v;
    };
    CHECK(sorted(tris) != sorted(plain));
  }
}
