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

// The crossing-planes test (crossing_triangles_meet, Guigue and Devillers' comparison of the two
// segments on the planes' line) against CGAL's do_intersect (through triangles_intersect), on
// pairs in general position (random doubles, where every orientation is non-zero) and on small
// integer coordinates (where corners touch the other plane, edges meet, and the segments touch
// end to end: triangles_clash then takes its other tests). Both orders of the pair, and each
// triangle turned both ways, so that every case of the turning and the swaps is met.
TEST_CASE("boolean: triangles whose planes cross meet exactly when CGAL says so", "[boolean][clash]") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> real(-1.0, 1.0);
  std::uniform_int_distribution<int> small(-2, 2);
  int meet = 0, miss = 0, general = 0, checked = 0;
  for (int n = 0; n < 60000; ++n) {
    const bool integer = n % 2 == 1;
    auto point = [&] {
      return integer ? Vec3(small(rng), small(rng), small(rng)) : Vec3(real(rng), real(rng), 0.5 * real(rng));
    };
    Vec3 v[6];
    for (auto& p : v) p = point();
    if ((v[1] - v[0]).cross(v[2] - v[0]).norm() == 0 || (v[4] - v[3]).cross(v[5] - v[3]).norm() == 0) continue;
    const bool expect = triangles_intersect(v[0], v[1], v[2], v[3], v[4], v[5]);
    Mesh m;
    m.positions.assign(v, v + 6);
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    if (n % 3 == 1) m.triangles[0] = {0, 2, 1};
    if (n % 5 < 2) m.triangles[1] = {3, 5, 4};
    std::vector<const Mesh*> one{&m};
    const Soup soup = make_soup(one);
    if (soup.verts.size() != 6) continue;  // a shared corner: not this test's case
    INFO("case " << n);
    CHECK(triangles_clash(soup, 0, 1) == expect);
    CHECK(triangles_clash(soup, 1, 0) == expect);
    // The segment comparison itself, where it applies.
    const Vec3* t[3] = {&v[0], &v[1], &v[2]};
    const Vec3* u[3] = {&v[3], &v[4], &v[5]};
    int st[3], su[3];
    for (int k = 0; k < 3; ++k) {
      st[k] = orient3d_fast(v[3], v[4], v[5], v[k]);
      su[k] = orient3d_fast(v[0], v[1], v[2], v[3 + k]);
    }
    const bool crossing = st[0] * st[1] * st[2] != 0 && su[0] * su[1] * su[2] != 0 && !(st[0] == st[1] && st[1] == st[2]) &&
                          !(su[0] == su[1] && su[1] == su[2]);
    if (crossing) {
      CHECK(crossing_triangles_meet(t, st, u, su) == expect);
      CHECK(crossing_triangles_meet(u, su, t, st) == expect);
      ++general;
      (expect ? meet : miss)++;
    }
    ++checked;
  }
  CHECK(checked > 50000);
  CHECK(general > 5000);
  CHECK(meet > 1000);
  CHECK(miss > 1000);
}
