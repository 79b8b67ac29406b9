// triangles_clash (the engine's exact test of whether two triangles meet beyond what they share)
// against kernel/predicates' general triangles_intersect, on triangles that share no vertex where
// one lies in a plane z = c and the other touches that plane at a corner, crosses it, or stays
// off it. Integer coordinates make touching at a point, on an edge and at a corner common.
#include <catch2/catch.hpp>

#include <random>

#include "csg/boolean_impl.h"
#include "kernel/predicates.h"

using namespace wedge;
using namespace wedge::boolean_detail;

TEST_CASE("boolean: a triangle in an axis plane and one touching that plane at a corner clash exactly when the corner is in it",
          "[boolean][clash]") {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> xy(-3, 3), up(1, 3);
  int touched_inside = 0, touched_outside = 0, crossing = 0, apart = 0, checked = 0;
  for (int n = 0; n < 20000; ++n) {
    const double c = n % 2 ? 0.0 : 0.5;  // the plane z = c
    Mesh m;
    Vec3 a(xy(rng), xy(rng), c), b(xy(rng), xy(rng), c), d(xy(rng), xy(rng), c);
    // The other triangle: a corner on the plane, or none, the others above or below or across.
    const int kind = n % 4;
    const double s = n % 3 ? 1 : -1;
    Vec3 p(xy(rng), xy(rng), kind == 0 ? c + s * up(rng) : c);
    Vec3 q(xy(rng), xy(rng), c + s * up(rng));
    Vec3 r(xy(rng), xy(rng), kind == 3 ? c - s * up(rng) : c + s * up(rng));
    m.positions = {a, b, d, p, q, r};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    const Vec3 e1 = b - a, e2 = d - a, f1 = q - p, f2 = r - p;
    if (e1.cross(e2).norm() == 0 || f1.cross(f2).norm() == 0) continue;  // degenerate
    if (n % 5 == 0) std::swap(m.triangles[0], m.triangles[1]);       // the flat one second
    std::vector<const Mesh*> one{&m};
    const Soup soup = make_soup(one);
    if (soup.verts.size() != 6) continue;  // two corners at one point: they would share a vertex
    const bool expect = triangles_intersect(a, b, d, p, q, r);
    INFO("case " << n);
    CHECK(triangles_clash(soup, 0, 1) == expect);
    CHECK(triangles_clash(soup, 1, 0) == expect);
    ++checked;
    if (kind == 3) crossing += expect;
    else if (kind == 0) apart += !expect;
    else (expect ? touched_inside : touched_outside)++;
  }
  // Each kind of configuration came up many times.
  CHECK(checked > 15000);
  CHECK(touched_inside > 500);
  CHECK(touched_outside > 500);
  CHECK(crossing > 500);
  CHECK(apart > 2000);
}
