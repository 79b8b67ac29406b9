// The boolean engine on cases with hand-worked answers: boxes (exact volumes), the degenerate
// configurations of issue 11, provenance and operand errors. The CGAL oracle tests are in
// test_boolean_oracle.cpp; the predicates and the constructed points, in test_boolean_points.cpp.
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <random>

#include "csg/boolean.h"
#include "csg/boolean_impl.h"
#include "kernel/error.h"
#include "kernel/predicates.h"
#include "kernel/transform.h"

using namespace wedge;

namespace {

Mesh box(Vec3 lo, Vec3 hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i)
    m.add_vertex(Vec3(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()));
  const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (auto& t : f) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

Mesh cube(double x, double y, double z, double s) { return box(Vec3(x, y, z), Vec3(x + s, y + s, z + s)); }

// A closed UV sphere with `n` segments around and n/2 rings.
Mesh sphere(Vec3 c, double r, int n) {
  Mesh m;
  int rings = n / 2;
  m.add_vertex(c + Vec3(0, 0, r));
  for (int i = 1; i < rings; ++i) {
    double th = kPi * i / rings;
    for (int j = 0; j < n; ++j) {
      double ph = 2 * kPi * j / n;
      m.add_vertex(c + r * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  }
  m.add_vertex(c + Vec3(0, 0, -r));
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * n + (j % n)); };
  std::uint32_t south = static_cast<std::uint32_t>(m.positions.size() - 1);
  for (int j = 0; j < n; ++j) m.add_triangle(0, id(1, j), id(1, j + 1));
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < n; ++j) {
      m.add_triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.add_triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  for (int j = 0; j < n; ++j) m.add_triangle(south, id(rings - 1, j + 1), id(rings - 1, j));
  return m;
}

void require_solid(const Mesh& m) {
  INFO(mesh_solid_defect(m, "result"));
  REQUIRE(mesh_solid_defect(m, "result").empty());
}

double vol(BooleanOp op, const Mesh& a, const Mesh& b) {
  Mesh r = boolean(op, a, b);
  if (!r.empty()) require_solid(r);
  return r.volume();
}

// A pyramid over a regular n-gon of radius 1: apex (0, 0, 1), its base fanned from its centre at
// the origin; the side's and the base's face ids.
Mesh pyramid_fan(int n, std::int32_t side_id = -1, std::int32_t base_id = -1) {
  Mesh cone;
  cone.add_vertex(Vec3(0, 0, 1));
  cone.add_vertex(Vec3(0, 0, 0));
  for (int i = 0; i < n; ++i) cone.add_vertex(Vec3(std::cos(2 * kPi * i / n), std::sin(2 * kPi * i / n), 0));
  for (int i = 0; i < n; ++i) {
    const std::uint32_t a = 2 + static_cast<std::uint32_t>(i), b = 2 + static_cast<std::uint32_t>((i + 1) % n);
    cone.add_triangle(a, b, 0, side_id);
    cone.add_triangle(b, a, 1, base_id);
  }
  return cone;
}

}  // namespace

TEST_CASE("boolean: two overlapping boxes, exact volumes", "[boolean]") {
  Mesh a = box(Vec3(0, 0, 0), Vec3(2, 2, 2));
  Mesh b = box(Vec3(1, 1, 1), Vec3(3, 3, 3));
  CHECK(vol(BooleanOp::Union, a, b) == Approx(15).epsilon(1e-12));
  CHECK(vol(BooleanOp::Intersection, a, b) == Approx(1).epsilon(1e-12));
  CHECK(vol(BooleanOp::Difference, a, b) == Approx(7).epsilon(1e-12));
  CHECK(vol(BooleanOp::Difference, b, a) == Approx(7).epsilon(1e-12));
}

TEST_CASE("boolean: a box through a box (a hole) keeps genus", "[boolean]") {
  Mesh a = box(Vec3(0, 0, 0), Vec3(3, 3, 1));
  Mesh b = box(Vec3(1, 1, -1), Vec3(2, 2, 2));
  Mesh r = boolean(BooleanOp::Difference, a, b);
  require_solid(r);
  CHECK(r.volume() == Approx(8).epsilon(1e-12));
  // V - E + F = 2 - 2g with g = 1.
  long V = static_cast<long>(r.positions.size()), F = static_cast<long>(r.triangles.size());
  long E = 3 * F / 2;
  CHECK(V - E + F == 0);
}

TEST_CASE("boolean: degenerate configurations of boxes", "[boolean]") {
  Mesh a = cube(0, 0, 0, 1);
  SECTION("identical operands") {
    CHECK(vol(BooleanOp::Union, a, a) == Approx(1).epsilon(1e-12));
    CHECK(vol(BooleanOp::Intersection, a, a) == Approx(1).epsilon(1e-12));
    CHECK(boolean(BooleanOp::Difference, a, a).empty());
  }
  SECTION("faces touching, coplanar with opposite orientation") {
    Mesh b = cube(1, 0, 0, 1);
    CHECK(vol(BooleanOp::Union, a, b) == Approx(2).epsilon(1e-12));
    Mesh u = boolean(BooleanOp::Union, a, b);
    require_solid(u);
    // The two inner faces are gone, and each long face, four triangles of two operands side by
    // side, is two: a 2x1x1 box in 6 quads.
    CHECK(u.triangles.size() == 12);
    CHECK(boolean(BooleanOp::Intersection, a, b).empty());
    CHECK(vol(BooleanOp::Difference, a, b) == Approx(1).epsilon(1e-12));
  }
  SECTION("coplanar overlapping faces with the same orientation (flush)") {
    Mesh b = box(Vec3(0.25, 0.25, 0.5), Vec3(0.75, 0.75, 1));  // top flush with a's top
    CHECK(vol(BooleanOp::Difference, a, b) == Approx(1 - 0.125).epsilon(1e-12));
    CHECK(vol(BooleanOp::Union, a, b) == Approx(1).epsilon(1e-12));
    CHECK(vol(BooleanOp::Intersection, a, b) == Approx(0.125).epsilon(1e-12));
  }
  SECTION("partly overlapping touching faces (offset)") {
    Mesh b = box(Vec3(1, 0.5, 0.5), Vec3(2, 1.5, 1.5));
    CHECK(vol(BooleanOp::Union, a, b) == Approx(2).epsilon(1e-12));
  }
  SECTION("two cubes sharing only an edge: two shells that touch") {
    Mesh b = cube(1, 1, 0, 1);
    Mesh u = boolean(BooleanOp::Union, a, b);
    require_solid(u);
    CHECK(u.volume() == Approx(2).epsilon(1e-12));
    CHECK(u.positions.size() == 16);  // the shared edge's two vertices are kept apart
  }
  SECTION("touching at a vertex") {
    Mesh b = cube(1, 1, 1, 1);
    Mesh u = boolean(BooleanOp::Union, a, b);
    require_solid(u);
    CHECK(u.volume() == Approx(2).epsilon(1e-12));
    CHECK(u.positions.size() == 16);
    CHECK(boolean(BooleanOp::Intersection, a, b).empty());
  }
  SECTION("nested and disjoint") {
    Mesh in = box(Vec3(0.25, 0.25, 0.25), Vec3(0.75, 0.75, 0.75));
    CHECK(vol(BooleanOp::Union, a, in) == Approx(1).epsilon(1e-12));
    CHECK(vol(BooleanOp::Intersection, a, in) == Approx(0.125).epsilon(1e-12));
    CHECK(vol(BooleanOp::Difference, a, in) == Approx(0.875).epsilon(1e-12));
    Mesh far = cube(5, 5, 5, 1);
    CHECK(vol(BooleanOp::Union, a, far) == Approx(2).epsilon(1e-12));
    CHECK(boolean(BooleanOp::Intersection, a, far).empty());
  }
  SECTION("T-junctions: a face split differently in the other operand") {
    Mesh b = box(Vec3(0, 0, 1), Vec3(0.5, 1, 2));  // sits on half of a's top
    CHECK(vol(BooleanOp::Union, a, b) == Approx(1.5).epsilon(1e-12));
  }
}

TEST_CASE("boolean: n-ary union and intersection in one pass", "[boolean]") {
  Mesh a = cube(0, 0, 0, 2), b = cube(1, 0, 0, 2), c = cube(0, 1, 0, 2);
  auto u = boolean(BooleanOp::Union, {&a, &b, &c});
  require_solid(u.mesh);
  CHECK(u.mesh.volume() == Approx(16).epsilon(1e-12));  // [0,3]x[0,2]x[0,2] and [0,2]x[2,3]x[0,2]
  auto i = boolean(BooleanOp::Intersection, {&a, &b, &c});
  require_solid(i.mesh);
  CHECK(i.mesh.volume() == Approx(2).epsilon(1e-12));
  auto d = boolean(BooleanOp::Difference, {&a, &b, &c});
  require_solid(d.mesh);
  CHECK(d.mesh.volume() == Approx(8 - 4 - 4 + 2).epsilon(1e-12));
}

TEST_CASE("boolean: spheres, volume identities", "[boolean]") {
  Mesh a = sphere(Vec3(0, 0, 0), 1, 32);
  Mesh b = sphere(Vec3(0.5, 0.3, 0.2), 1, 32);
  double va = a.volume(), vb = b.volume();
  double u = vol(BooleanOp::Union, a, b), n = vol(BooleanOp::Intersection, a, b), d = vol(BooleanOp::Difference, a, b);
  CHECK(u + n == Approx(va + vb).epsilon(1e-9));
  CHECK(d == Approx(va - n).epsilon(1e-9));
}

TEST_CASE("boolean: provenance names the source triangle", "[boolean]") {
  Mesh a = cube(0, 0, 0, 2);
  Mesh b = cube(1, 1, 1, 2);
  a.face_ids.assign(a.triangles.size(), 7);
  auto r = boolean(BooleanOp::Difference, {&a, &b});
  REQUIRE(r.operand.size() == r.mesh.triangles.size());
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    const Mesh& src = r.operand[t] == 0 ? a : b;
    REQUIRE(r.source[t] >= 0);
    REQUIRE(r.source[t] < static_cast<int>(src.triangles.size()));
    CHECK(r.mesh.face_ids[t] == (r.operand[t] == 0 ? 7 : -1));
    // The output triangle lies in the plane of its source triangle.
    const auto& s = src.triangles[r.source[t]];
    Vec3 n = (src.positions[s[1]] - src.positions[s[0]]).cross(src.positions[s[2]] - src.positions[s[0]]);
    for (int k = 0; k < 3; ++k)
      CHECK(std::abs(n.dot(r.mesh.positions[r.mesh.triangles[t][k]] - src.positions[s[0]])) < 1e-12);
  }
}

TEST_CASE("boolean: bad operands are errors naming the operand and the spot", "[boolean]") {
  Mesh a = cube(0, 0, 0, 1);
  Mesh open = a;
  open.triangles.pop_back();
  CHECK_THROWS_WITH(boolean(BooleanOp::Union, a, open), Catch::Contains("second operand is not closed"));
  Mesh flipped = a;
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  CHECK_THROWS_WITH(boolean(BooleanOp::Union, flipped, a), Catch::Contains("first operand is inside out"));
  // Two shells (not seen one-to-one from a point: the volume's sign is summed), and a sphere, each
  // turned inside out.
  Mesh apart = cube(0, 0, 0, 1);
  apart.append(cube(3, 0, 0, 1));
  Mesh ball = sphere(Vec3(0.5, 0.5, 0.5), 0.7, 24);
  for (Mesh* m : {&apart, &ball}) {
    CHECK_NOTHROW(boolean(BooleanOp::Union, a, *m));
    for (auto& t : m->triangles) std::swap(t[1], t[2]);
    CHECK_THROWS_WITH(boolean(BooleanOp::Union, a, *m), Catch::Contains("second operand is inside out"));
  }
  Mesh one_flipped = a;  // closed, but one triangle turned over: its edges run twice one way
  std::swap(one_flipped.triangles[3][1], one_flipped.triangles[3][2]);
  CHECK_THROWS_WITH(boolean(BooleanOp::Union, a, one_flipped),
                    Catch::Contains("second operand is not consistently oriented: edge") &&
                        Catch::Contains("is used 2 times in one direction"));
  Mesh touching = a;  // two shells sharing one edge: allowed (each 2-manifold), and unchanged by a union
  touching.append(cube(1, 1, 0, 1));
  CHECK(boolean(BooleanOp::Union, touching, touching).triangles.size() == 24);
  Mesh two = a;
  two.append(cube(0.5, 0.5, 0.5, 1));  // two overlapping shells in one mesh
  CHECK_THROWS_WITH(boolean(BooleanOp::Union, a, two), Catch::Contains("second operand intersects itself"));
  // The operands are checked on one soup of all of them, each on its own: a hole in the face that
  // one cube shares with another is not closed by the other's triangles there, whatever their
  // order, and a closed operand beside it is not blamed.
  for (std::size_t drop = 0; drop < 12; ++drop) {
    Mesh holed = cube(1, 0, 0, 1);
    holed.triangles.erase(holed.triangles.begin() + static_cast<std::ptrdiff_t>(drop));
    CHECK_THROWS_WITH(boolean(BooleanOp::Union, a, holed), Catch::Contains("second operand is not closed"));
    CHECK_THROWS_WITH(boolean(BooleanOp::Union, {&holed, &a, &a}), Catch::Contains("operand 1 is not closed"));
    Mesh turned = cube(1, 0, 0, 1);
    std::swap(turned.triangles[drop][1], turned.triangles[drop][2]);
    CHECK_THROWS_WITH(boolean(BooleanOp::Union, {&a, &a, &turned}), Catch::Contains("operand 3 is not consistently oriented"));
  }
}

namespace {

// Cube c with a flat triangle: its triangle t's neighbour across the edge from t's corner k is
// split at the edge's midpoint m, and the flat triangle (x, m, y) fills the slit, as a mesh
// rounded to floats (an STL file) can have.
Mesh with_flat_triangle(const Mesh& c, std::size_t t, int k) {
  Mesh m = c;
  const std::uint32_t x = m.triangles[t][k], y = m.triangles[t][(k + 1) % 3];
  const std::uint32_t mid = m.add_vertex(0.5 * (m.positions[x] + m.positions[y]));
  for (auto& u : m.triangles)
    for (int c2 = 0; c2 < 3; ++c2)
      if (u[c2] == y && u[(c2 + 1) % 3] == x) {
        const std::uint32_t e = u[(c2 + 2) % 3];
        u = {y, mid, e};
        m.add_triangle(mid, x, e);
        m.add_triangle(x, mid, y);
        return m;
      }
  return m;
}

}  // namespace

TEST_CASE("boolean: zero-area operand triangles that lose no point are mended, the rest reported", "[boolean]") {
  const Mesh a = cube(0, 0, 0, 2), b = cube(1, 1, 1, 2);
  for (std::size_t t = 0; t < 12; ++t)
    for (int k = 0; k < 3; ++k) {
      Mesh flat = with_flat_triangle(a, t, k);
      REQUIRE(flat.triangles.size() == 14);
      REQUIRE(collinear(flat.positions[flat.triangles[13][0]], flat.positions[flat.triangles[13][1]],
                        flat.positions[flat.triangles[13][2]]));
      BooleanResult r = boolean(BooleanOp::Difference, {&flat, &b});
      require_solid(r.mesh);
      CHECK(r.mesh.volume() == 7.0);
      for (std::size_t i = 0; i < r.mesh.triangles.size(); ++i)
        if (r.operand[i] == 0) CHECK(r.source[i] < 13);  // the flat one's place went to its neighbour
      CHECK(boolean(BooleanOp::Union, {&b, &flat}).mesh.volume() == 15.0);
    }
  // Two flat triangles in a row: the second's neighbour is mended first.
  Mesh two = with_flat_triangle(with_flat_triangle(a, 0, 0), 3, 1);
  CHECK(boolean(BooleanOp::Intersection, {&two, &b}).mesh.volume() == 1.0);
  // A triangle with two corners at one point is dropped: its other two edges meet their twins.
  Mesh pinched = a;
  pinched.add_triangle(pinched.triangles[0][0], pinched.triangles[0][0], pinched.triangles[0][1]);
  pinched.add_triangle(pinched.triangles[0][1], pinched.triangles[0][0], pinched.triangles[0][0]);
  CHECK(boolean(BooleanOp::Difference, {&pinched, &b}).mesh.volume() == 7.0);
  // A flat triangle whose long edge has no neighbour is still an error naming it.
  Mesh torn = with_flat_triangle(a, 0, 0);
  const auto x = torn.triangles[13][0], y = torn.triangles[13][2];
  for (std::size_t i = 0; i < 13; ++i)
    for (int c = 0; c < 3; ++c)
      if (torn.triangles[i][c] == x && torn.triangles[i][(c + 1) % 3] == y) torn.triangles.erase(torn.triangles.begin() + i);
  CHECK_THROWS_WITH(boolean(BooleanOp::Union, a, torn), Catch::Contains("second operand has a zero-area triangle #"));
}

TEST_CASE("boolean: many flat triangles, some on the same edge one after another, are all mended", "[boolean]") {
  // Each step splits an edge of the mesh so far at its midpoint with a flat triangle; a later
  // step may split an edge of an earlier flat triangle's neighbour or of the flat triangle itself
  // (then its neighbour across the long edge is flat too, and is mended first).
  std::mt19937 rng(11);
  // On a grid of 2^-10, so that every midpoint is exact (and the flat triangles exactly flat).
  Mesh base = sphere(Vec3(0, 0, 0), 1, 16);
  for (auto& p : base.positions) p = (p * 1024.0).array().round().matrix() / 1024.0;
  const Mesh cut = cube(0, 0, 0, 2);
  const double expected = boolean(BooleanOp::Difference, {&base, &cut}).mesh.volume();
  for (int trial = 0; trial < 60; ++trial) {
    Mesh m = base;
    const int steps = 1 + trial % 10;
    for (int k = 0; k < steps; ++k) {
      // Half the time the newest flat triangle itself.
      const std::size_t t = k > 0 && rng() % 2 ? m.triangles.size() - 1
                                                : std::uniform_int_distribution<std::size_t>(0, m.triangles.size() - 1)(rng);
      const int e = static_cast<int>(rng() % 3);
      // Not where the midpoint is a vertex already (a flat triangle's long edge split again at
      // the same point): that would be a mesh touching itself.
      const Vec3 mid = 0.5 * (m.positions[m.triangles[t][e]] + m.positions[m.triangles[t][(e + 1) % 3]]);
      if (std::find(m.positions.begin(), m.positions.end(), mid) != m.positions.end()) continue;
      m = with_flat_triangle(m, t, e);
      const auto& F = m.triangles.back();
      REQUIRE(collinear(m.positions[F[0]], m.positions[F[1]], m.positions[F[2]]));
    }
    BooleanResult r = boolean(BooleanOp::Difference, {&m, &cut});
    require_solid(r.mesh);
    CHECK(r.mesh.volume() == Approx(expected).epsilon(1e-12));
  }
}

TEST_CASE("boolean: triangles around one vertex that cross each other are caught", "[boolean]") {
  // A double cone whose rim winds twice around its axis (a pentagram: five points taken 0, 144,
  // 288, 72, 216 degrees): closed, consistently oriented, outward, every vertex one fan;
  // but the triangles at each apex overlap, and the crossing pairs share only the apex. The
  // self-check's star certificates (a fan seen along one direction, winding once) must not pass
  // these two fans.
  Mesh m;
  const double deg[5] = {0, 144, 288, 72, 216};
  for (double d : deg) m.add_vertex({5 + std::cos(d * kPi / 180), 5 + std::sin(d * kPi / 180), 0});
  const auto top = m.add_vertex({5, 5, 1}), bottom = m.add_vertex({5, 5, -1});
  for (std::uint32_t i = 0; i < 5; ++i) {
    m.add_triangle(top, i, (i + 1) % 5);
    m.add_triangle(bottom, (i + 1) % 5, i);
  }
  const Mesh a = cube(0, 0, 0, 1);
  CHECK_THROWS_WITH(boolean(BooleanOp::Union, a, m), Catch::Contains("second operand intersects itself"));
  using namespace boolean_detail;
  {
    const Soup soup = make_soup({&m});
    const auto cert = star_certificates(soup);
    for (std::size_t t = 0; t < soup.tris.size(); ++t)
      for (int c = 0; c < 3; ++c) {
        const Vec3& p = soup.verts[soup.tris[t][c]];
        const bool apex = p.x() == 5 && p.y() == 5;
        if (apex) CHECK((cert[t] >> c & 1) == 0);  // the apexes' fans wind twice
      }
  }
  // The same with the rim once around (0, 60, ..., 300 degrees): valid, and its union with a
  // far cube has both volumes.
  Mesh ok;
  for (int i = 0; i < 6; ++i) ok.add_vertex({5 + std::cos(i * kPi / 3), 5 + std::sin(i * kPi / 3), 0});
  const auto t2 = ok.add_vertex({5, 5, 1}), b2 = ok.add_vertex({5, 5, -1});
  for (std::uint32_t i = 0; i < 6; ++i) {
    ok.add_triangle(t2, i, (i + 1) % 6);
    ok.add_triangle(b2, (i + 1) % 6, i);
  }
  CHECK(boolean(BooleanOp::Union, a, ok).volume() == Approx(1 + ok.volume()).epsilon(1e-12));
  const Soup soup = make_soup({&ok, &a});
  const auto cert = star_certificates(soup);
  CHECK(std::count(cert.begin(), cert.end(), 7) == static_cast<std::ptrdiff_t>(cert.size()));  // every star, cube corners too
}

TEST_CASE("boolean: operands seen one-to-one from their centre skip the pairwise self-check, and only those",
          "[boolean]") {
  using namespace boolean_detail;
  auto embedded = [](const std::vector<const Mesh*>& ms) {
    const Soup soup = make_soup(ms);
    return radially_embedded(soup, nullptr, corner_lists(soup, nullptr));
  };
  // A box, a sphere and a cylinder (convex: every triangle seen from the centre one way round).
  const Mesh b = cube(0, 0, 0, 2), s = sphere(Vec3(5, 0, 0), 1, 16);
  Mesh c;
  for (int i = 0; i < 24; ++i) {
    c.add_vertex({10 + std::cos(i * kPi / 12), std::sin(i * kPi / 12), 0});
    c.add_vertex({10 + std::cos(i * kPi / 12), std::sin(i * kPi / 12), 3});
  }
  const auto bottom = c.add_vertex({10, 0, 0}), top = c.add_vertex({10, 0, 3});
  for (std::uint32_t i = 0; i < 24; ++i) {
    const std::uint32_t b0 = 2 * i, t0 = b0 + 1, b1 = 2 * ((i + 1) % 24), t1 = b1 + 1;
    c.add_triangle(b0, b1, t1);
    c.add_triangle(b0, t1, t0);
    c.add_triangle(bottom, b1, b0);
    c.add_triangle(top, t0, t1);
  }
  CHECK(embedded({&b, &s, &c}) == std::vector<char>{1, 1, 1});
  // Two overlapping cubes in one mesh: each seen one-to-one from the common centre, but two
  // sheets (V - E + F = 4): not passed, and the pairwise check finds the crossing.
  Mesh two = cube(0, 0, 0, 2);
  two.append(cube(0.5, 0.5, 0.5, 2));
  CHECK(embedded({&two}) == std::vector<char>{0});
  CHECK_THROWS_WITH(boolean(BooleanOp::Union, b, two), Catch::Contains("second operand intersects itself"));
  // A ring (genus 1: V - E + F = 0) is not star-shaped: not passed, checked pairwise, valid.
  Mesh ring;
  const int n = 12, k = 6;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      const double u = 2 * kPi * i / n, v = 2 * kPi * j / k, r = 3 + std::cos(v);
      ring.add_vertex({r * std::cos(u), r * std::sin(u), std::sin(v)});
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      const auto a = static_cast<std::uint32_t>(i * k + j), b1 = static_cast<std::uint32_t>(((i + 1) % n) * k + j),
                 c1 = static_cast<std::uint32_t>(((i + 1) % n) * k + (j + 1) % k),
                 d = static_cast<std::uint32_t>(i * k + (j + 1) % k);
      ring.add_triangle(a, b1, c1);
      ring.add_triangle(a, c1, d);
    }
  CHECK(embedded({&ring}) == std::vector<char>{0});
  CHECK(boolean(BooleanOp::Union, ring, cube(20, 0, 0, 2)).volume() == Approx(ring.volume() + 8).epsilon(1e-9));
  // The double cone over a pentagram (two apex fans winding twice): V - E + F = 2, not passed.
  Mesh m;
  const double deg[5] = {0, 144, 288, 72, 216};
  for (double d : deg) m.add_vertex({std::cos(d * kPi / 180), std::sin(d * kPi / 180), 0});
  const auto ta = m.add_vertex({0, 0, 1}), ba = m.add_vertex({0, 0, -1});
  for (std::uint32_t i = 0; i < 5; ++i) {
    m.add_triangle(ta, i, (i + 1) % 5);
    m.add_triangle(ba, (i + 1) % 5, i);
  }
  CHECK(embedded({&m}) == std::vector<char>{0});
  // A pyramid whose first triangle is a sliver (C 1e-17 off the line x = y of its edge A - B):
  // its centroid rounds onto that edge, so the ray from the centre through it meets an edge and
  // counts nothing for sure; rays through other triangles are tried, and the pyramid passes.
  Mesh pyr;
  const auto A = pyr.add_vertex({0, 0, 0}), B = pyr.add_vertex({3, 3, 0}), C = pyr.add_vertex({1e-17, 0, 0}),
             D = pyr.add_vertex({0, 3, 0}), E = pyr.add_vertex({1, 2, 3});
  pyr.add_triangle(A, B, C);
  pyr.add_triangle(A, D, B);
  pyr.add_triangle(C, B, E);
  pyr.add_triangle(A, C, E);
  pyr.add_triangle(D, A, E);
  pyr.add_triangle(B, D, E);
  REQUIRE((pyr.positions[A] + pyr.positions[B] + pyr.positions[C]) / 3.0 == Vec3(1, 1, 0));  // on the edge
  CHECK(embedded({&pyr}) == std::vector<char>{1});
  CHECK(boolean(BooleanOp::Union, pyr, cube(20, 0, 0, 2)).volume() == Approx(pyr.volume() + 8).epsilon(1e-12));
}

TEST_CASE("boolean: star certificates set every corner's bit at two threads, run after run", "[boolean]") {
  // Each triangle's three corner bits are set from its three vertices, which parallel blocks of
  // vertices certify at once. With a plain |= on the shared byte, one in about a hundred runs on
  // these spheres lost a bit (the radial check then used them: an operand not seen as embedded
  // went to the pairwise self-check, some 30 million pairs for a 1M-triangle sphere). Each run
  // must certify every corner of both spheres, and both spheres stay radially embedded.
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
  using namespace boolean_detail;
  const Mesh a = sphere(Vec3(0, 0, 0), 1, 256), b = sphere(Vec3(0.5, 0.1, 0.2), 1, 256);
  const Soup soup = make_soup({&a, &b});
  const CornerLists corners = corner_lists(soup, nullptr);
  int whole = 0, both = 0;
  constexpr int kRuns = 300;
  for (int run = 0; run < kRuns; ++run) {
    const auto cert = star_certificates(soup, corners);
    whole += std::count(cert.begin(), cert.end(), 7) == static_cast<std::ptrdiff_t>(cert.size());
    const auto pass = radially_embedded(soup, nullptr, corners);
    both += pass[0] && pass[1];
  }
  CHECK(whole == kRuns);
  CHECK(both == kRuns);
}

TEST_CASE("boolean: star certificates of a vertex that two operands share are each operand's own", "[boolean]") {
  // Most vertices' bits are set per vertex, from the one operand whose corners they are; a vertex
  // two operands share (cubes touching at a corner: positions are welded across operands) keeps
  // a star per operand, each certified on its own. Every corner is certified, the shared one in
  // both cubes.
  using namespace boolean_detail;
  const Mesh a = cube(0, 0, 0, 1), b = cube(1, 1, 1, 1);
  const Soup soup = make_soup({&a, &b});
  REQUIRE(soup.verts.size() == 15);  // 16 corners, one shared
  const auto cert = star_certificates(soup);
  CHECK(std::count(cert.begin(), cert.end(), 7) == static_cast<std::ptrdiff_t>(cert.size()));
  // The same with only the second cube listed: its bits alone, the first cube's none.
  const std::vector<char> trusted{1, 0};
  const auto half = star_certificates(soup, &trusted);
  for (std::size_t t = 0; t < soup.tris.size(); ++t) CHECK(half[t] == (soup.operand[t] == 1 ? 7 : 0));
}

TEST_CASE("boolean: sort_edges orders by key then value, few records among many points or not", "[boolean]") {
  // Records far fewer than the points (a large result that pairs most edges directly) take a
  // radix sort of the keys; the rest a counting sort by first vertex. Both give the order of a
  // comparison sort by (key, value), repeated keys and values included.
  using namespace boolean_detail;
  std::mt19937 rng(7);
  for (const std::size_t points : {std::size_t(64), std::size_t(1) << 20}) {
    for (const std::size_t m : {std::size_t(0), std::size_t(1), std::size_t(1000), std::size_t(70000)}) {
      EdgeRecs recs(m);
      std::uniform_int_distribution<u32> vertex(0, static_cast<u32>(points - 1)), value(0, 50);
      for (auto& r : recs) {
        u32 a = vertex(rng), b = vertex(rng) % 8 == 0 ? vertex(rng) : (a + 1) % static_cast<u32>(points);
        if (a > b) std::swap(a, b);
        r = {static_cast<std::uint64_t>(a) << 32 | b, value(rng)};
      }
      std::vector<std::pair<std::uint64_t, u32>> want;
      for (const auto& r : recs) want.push_back({r.key, r.value});
      std::sort(want.begin(), want.end());
      sort_edges(recs, points);
      REQUIRE(recs.size() == want.size());
      bool same = true;
      for (std::size_t i = 0; i < m; ++i) same = same && recs[i].key == want[i].first && recs[i].value == want[i].second;
      CHECK(same);
    }
  }
}

TEST_CASE("boolean: a result fed back is known valid, any change to it is checked again", "[boolean]") {
  const Mesh a = cube(0, 0, 0, 2), b = cube(1, 1, 1, 2), c = cube(0.5, 0.5, -1, 1);
  BooleanStats st;
  const BooleanResult r = boolean(BooleanOp::Union, {&a, &b}, &st);
  CHECK(st.trusted == 0);
  boolean(BooleanOp::Difference, {&r.mesh, &c}, &st);
  CHECK(st.trusted == 1);  // the union's result, bit for bit
  // The same result moved by a hair (an ulp of a vertex off the origin: one at the origin would
  // get a subnormal coordinate, refused) is another mesh: checked (and valid).
  Mesh moved = r.mesh;
  std::size_t off_origin = 0;
  while (moved.positions[off_origin].x() == 0) ++off_origin;
  moved.positions[off_origin].x() = std::nextafter(moved.positions[off_origin].x(), 10.0);
  boolean(BooleanOp::Difference, {&moved, &c}, &st);
  CHECK(st.trusted == 0);
  // A result with a second shell pushed through it intersects itself, and is still caught.
  Mesh broken = r.mesh;
  broken.append(cube(-0.5, -0.5, -0.5, 1));
  CHECK_THROWS_WITH(boolean(BooleanOp::Difference, {&broken, &c}), Catch::Contains("first operand intersects itself"));
  // Faces reversed: inside out, caught although the positions are the result's.
  Mesh flipped = r.mesh;
  for (auto& t : flipped.triangles) std::swap(t[1], t[2]);
  CHECK_THROWS_WITH(boolean(BooleanOp::Difference, {&flipped, &c}), Catch::Contains("first operand is inside out"));
}

TEST_CASE("boolean: a cancel request is seen inside the stages, and leaves nothing behind", "[boolean]") {
  const Mesh a = sphere(Vec3(0, 0, 0), 1, 96), b = sphere(Vec3(0.4, 0.3, 0.2), 1, 96);
  // Not cancelled: the check is asked from inside the stages too (throttled to one call per
  // 2 ms), not only at the five stage boundaries.
  std::atomic<int> calls{0};
  const CancelCheck count = [&] {
    ++calls;
    return false;
  };
  BooleanStats st;
  const BooleanResult whole = boolean(BooleanOp::Union, {&a, &b}, &st, &count);
  INFO("calls " << calls.load() << ", stages (ms) " << st.check << " " << st.broad << " " << st.arrange << " "
                << st.classify << " " << st.output);
  CHECK(calls.load() > 5);
  // Cancelled at the check's second call (inside a stage or at a boundary): Cancelled, and the
  // next boolean gives the same result as before.
  std::atomic<int> n{0};
  const CancelCheck stop = [&] { return ++n >= 2; };
  CHECK_THROWS_AS(boolean(BooleanOp::Union, {&a, &b}, nullptr, &stop), Cancelled);
  const BooleanResult again = boolean(BooleanOp::Union, {&a, &b});
  CHECK(again.mesh.positions == whole.mesh.positions);
  CHECK(again.mesh.triangles == whole.mesh.triangles);
}

TEST_CASE("boolean: a chain of booleans stays valid", "[boolean]") {
  Mesh r = cube(0, 0, 0, 4);
  for (int i = 0; i < 12; ++i) {
    double x = 0.3 * i, y = 0.17 * i;
    Mesh c = box(Vec3(x, y, 3.5 - 0.1 * i), Vec3(x + 0.9, y + 1.3, 5));
    r = boolean(i % 2 ? BooleanOp::Union : BooleanOp::Difference, r, c);
    require_solid(r);
  }
  CHECK(r.volume() > 0);
}

TEST_CASE("boolean: random rotated boxes satisfy the volume identities", "[boolean]") {
  std::uint64_t seed = 12345;
  auto rnd = [&] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(seed >> 11) / 9007199254740992.0;
  };
  for (int i = 0; i < 30; ++i) {
    Mesh a = box(Vec3(0, 0, 0), Vec3(1 + rnd(), 1 + rnd(), 1 + rnd()));
    Mesh b = box(Vec3(0, 0, 0), Vec3(0.5 + rnd(), 0.5 + rnd(), 0.5 + rnd()));
    Mat4 m = translate(Vec3(rnd(), rnd(), rnd())) * rotate(360 * rnd(), Vec3(rnd() - 0.5, rnd() - 0.5, rnd() + 0.1));
    if (i % 3 == 0) m = translate(Vec3(0.5, 0.25, 0));  // axis-aligned: coplanar faces
    b = b.transformed(m);
    double va = a.volume(), vb = b.volume();
    double u = vol(BooleanOp::Union, a, b), n = vol(BooleanOp::Intersection, a, b), d = vol(BooleanOp::Difference, a, b);
    INFO("case " << i);
    CHECK(u + n == Approx(va + vb).epsilon(1e-9));
    CHECK(d == Approx(va - n).epsilon(1e-9).margin(1e-12));
  }
}

TEST_CASE("boolean: identical and nearly identical spheres", "[boolean]") {
  Mesh a = sphere(Vec3(0, 0, 0), 1, 24);
  CHECK(vol(BooleanOp::Union, a, a) == Approx(a.volume()).epsilon(1e-12));
  CHECK(boolean(BooleanOp::Difference, a, a).empty());
  // The same sphere moved by a billionth: slivers everywhere, still valid. (Moved by a few ulps,
  // the rounded result can self-intersect where the repair cannot help: the engine then throws;
  // snap rounding is the next step.)
  Mesh b = a.transformed(translate(Vec3(1e-9, 2e-9, -1e-9)));
  double u = vol(BooleanOp::Union, a, b), n = vol(BooleanOp::Intersection, a, b);
  CHECK(u + n == Approx(a.volume() + b.volume()).epsilon(1e-9));
  // Rotated about its axis by a tiny angle.
  Mesh c = a.transformed(rotate(1e-7, Vec3(0, 0, 1)));
  double uc = vol(BooleanOp::Union, a, c), nc = vol(BooleanOp::Intersection, a, c);
  CHECK(uc + nc == Approx(a.volume() + c.volume()).epsilon(1e-9));
}

TEST_CASE("boolean: very large and very small coordinates together", "[boolean]") {
  Mesh a = box(Vec3(-1e6, -1e6, -1e6), Vec3(1e6, 1e6, 1e6));
  Mesh b = box(Vec3(0, 0, 0), Vec3(1e-6, 1e-6, 2e6));
  double d = vol(BooleanOp::Difference, a, b);
  CHECK(d == Approx(8e18 - 1e-12 * 1e6).epsilon(1e-12));
  Mesh r = boolean(BooleanOp::Difference, a, b);
  CHECK(r.triangles.size() > 12);
}

TEST_CASE("boolean: n-ary operations on crossing rotated boxes agree with inclusion-exclusion", "[boolean]") {
  // Three boxes whose faces cross inside one another's triangles, so that a triangle's cut
  // segments meet each other (triple points) and are split at several points each.
  Mesh a = box(Vec3(0, 0, 0), Vec3(2, 2, 2));
  Mesh b = box(Vec3(-1, -1, -1), Vec3(1, 1, 1)).transformed(translate(Vec3(1, 1, 1.2)) * rotate(33, Vec3(1, 2, 3)));
  Mesh c = box(Vec3(-1, -0.7, -0.9), Vec3(1, 0.7, 0.9)).transformed(translate(Vec3(1.1, 0.9, 0.8)) * rotate(71, Vec3(-2, 1, 0.5)));
  Mesh s = sphere(Vec3(1.0, 1.1, 0.9), 0.95, 24);
  std::vector<const Mesh*> all{&a, &b, &c, &s};
  auto v = [](const BooleanResult& r) {
    require_solid(r.mesh);
    return r.mesh.volume();
  };
  double va = a.volume(), vb = b.volume(), vc = c.volume(), vs = s.volume();
  double ab = v(boolean(BooleanOp::Intersection, {&a, &b})), ac = v(boolean(BooleanOp::Intersection, {&a, &c}));
  double as = v(boolean(BooleanOp::Intersection, {&a, &s})), bc = v(boolean(BooleanOp::Intersection, {&b, &c}));
  double bs = v(boolean(BooleanOp::Intersection, {&b, &s})), cs = v(boolean(BooleanOp::Intersection, {&c, &s}));
  double abc = v(boolean(BooleanOp::Intersection, {&a, &b, &c})), abs_ = v(boolean(BooleanOp::Intersection, {&a, &b, &s}));
  double acs = v(boolean(BooleanOp::Intersection, {&a, &c, &s})), bcs = v(boolean(BooleanOp::Intersection, {&b, &c, &s}));
  double abcs = v(boolean(BooleanOp::Intersection, all));
  double u = v(boolean(BooleanOp::Union, all));
  double expect = va + vb + vc + vs - ab - ac - as - bc - bs - cs + abc + abs_ + acs + bcs - abcs;
  CHECK(u == Approx(expect).epsilon(1e-9));
  // a minus the rest = a - (a n (b u c u s))
  double d = v(boolean(BooleanOp::Difference, all));
  CHECK(d == Approx(va - (ab + ac + as - abc - abs_ - acs + abcs)).epsilon(1e-9));
}


TEST_CASE("boolean: a sphere and its copy turned by 1e-14 degrees, vertices a rounding apart, are welded", "[boolean]") {
  // The copy's vertices are the sphere's moved by at most a few ulps. The result of the
  // difference was slivers between two sheets a rounding apart, and no re-resolution could round
  // it ("cannot be rounded to doubles without a self-intersection (4 re-resolutions tried)").
  // The engine now welds such operands' vertices and decides the coinciding sheets exactly.
  const Mesh a = sphere(Vec3(0, 0, 0), 1, 32);
  const Mesh b = a.transformed(rotate(1e-14, Vec3(0.3, 1, 0.2)));
  REQUIRE(b.positions != a.positions);
  const double va = a.volume();
  BooleanResult d, u;
  REQUIRE_NOTHROW(d = boolean(BooleanOp::Difference, {&a, &b}));
  CHECK(d.mesh.triangles.empty());
  REQUIRE_NOTHROW(u = boolean(BooleanOp::Union, {&a, &b}));
  CHECK(u.mesh.volume() == Approx(va).epsilon(1e-12));
  CHECK(mesh_solid_defect(u.mesh).empty());  // closed, manifold, outward, no self-intersection (exact)
}

TEST_CASE("boolean: make_soup welds equal positions into the vertices a serial pass numbers, at any thread count",
          "[boolean]") {
  using namespace boolean_detail;
  // Three operands of 40,000 positions each (several of make_soup's parallel blocks), half of
  // them drawn from a pool of 343 positions (equal positions within an operand, across operands
  // and across blocks, -0 beside 0), half distinct; triangles on random indices.
  std::mt19937 rng(7);
  const double pool[7] = {-1.0, -0.0, 0.0, 0.5, 1.0, 2.5, 1e-300};
  std::uniform_int_distribution<int> pick(0, 6), coin(0, 1);
  std::uniform_real_distribution<double> any(-10, 10);
  std::vector<Mesh> ms(3);
  std::size_t distinct = 0;  // positions drawn outside the pool
  for (Mesh& m : ms) {
    for (int v = 0; v < 40000; ++v) {
      const bool from_pool = coin(rng);
      distinct += !from_pool;
      m.positions.push_back(from_pool ? Vec3(pool[pick(rng)], pool[pick(rng)], pool[pick(rng)])
                                      : Vec3(any(rng), any(rng), any(rng)));
    }
    std::uniform_int_distribution<std::uint32_t> idx(0, 39999);
    for (int t = 0; t < 30000; ++t) m.triangles.push_back({idx(rng), idx(rng), idx(rng)});
  }
  const std::vector<const Mesh*> ops{&ms[0], &ms[1], &ms[2]};
  // The reference: one serial pass, a vertex per new position (-0 as 0) in the order met.
  std::map<std::array<double, 3>, std::uint32_t> seen;
  std::vector<Vec3> verts;
  std::vector<std::int32_t> vertex_operand;  // the operand whose positions a vertex holds, -2 several
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (const Mesh* m : ops) {
    const auto op = static_cast<std::int32_t>(m - ms.data());
    std::vector<std::uint32_t> id(m->positions.size());
    for (std::size_t v = 0; v < m->positions.size(); ++v) {
      const Vec3& p = m->positions[v];
      const std::array<double, 3> key{p.x() + 0.0, p.y() + 0.0, p.z() + 0.0};
      auto [it, fresh] = seen.emplace(key, static_cast<std::uint32_t>(verts.size()));
      if (fresh) verts.push_back(Vec3(key[0], key[1], key[2])), vertex_operand.push_back(op);
      else if (vertex_operand[it->second] != op) vertex_operand[it->second] = -2;
      id[v] = it->second;
    }
    for (const auto& T : m->triangles) tris.push_back({id[T[0]], id[T[1]], id[T[2]]});
  }
  REQUIRE(verts.size() > distinct);
  REQUIRE(verts.size() <= distinct + 343);  // the pool's positions, drawn some 60,000 times, were welded
  for (int threads : {1, 2}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    const Soup soup = make_soup(ops);
    REQUIRE(soup.verts.size() == verts.size());
    CHECK(soup.verts == verts);
    CHECK(std::equal(soup.tris.begin(), soup.tris.end(), tris.begin(), tris.end()));
    CHECK(std::equal(soup.vertex_operand.begin(), soup.vertex_operand.end(), vertex_operand.begin(), vertex_operand.end()));
    for (const Vec3& p : soup.verts)
      for (int i = 0; i < 3; ++i) CHECK_FALSE((std::signbit(p[i]) && p[i] == 0));
    CHECK(soup.operand[30000] == 1);
    CHECK(soup.local[30001] == 1);
    // Each operand's box: over its positions (-0 as 0), whichever block they were in.
    REQUIRE(soup.boxes.size() == 3);
    for (int o = 0; o < 3; ++o) {
      std::array<double, 6> box = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
      for (const Vec3& p : ms[o].positions)
        for (int i = 0; i < 3; ++i) box[i] = std::min(box[i], p[i] + 0.0), box[i + 3] = std::max(box[i + 3], p[i] + 0.0);
      CHECK(soup.boxes[o] == box);
    }
  }
}

TEST_CASE("boolean: Dsu unions by blocks give the sets and roots of serial unions, at any thread count", "[boolean]") {
  using namespace boolean_detail;
  std::mt19937 rng(11);
  const u32 n = 300000;
  // Pairs mostly near each other (within a block of 65536), some anywhere (across blocks).
  std::vector<std::array<u32, 2>> pairs;
  std::uniform_int_distribution<u32> any(0, n - 1), near(0, 40);
  for (int k = 0; k < 200000; ++k) {
    const u32 a = any(rng);
    pairs.push_back({a, k % 10 == 0 ? any(rng) : std::min(n - 1, a + near(rng))});
  }
  Dsu serial(n);
  for (const auto& [a, b] : pairs) serial.unite(a, b);
  // Each pair handed to the block of its first element.
  std::vector<std::vector<std::array<u32, 2>>> by_block((n + 65535) / 65536);
  for (const auto& p : pairs) by_block[p[0] / 65536].push_back(p);
  for (int threads : {1, 2}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    Dsu blocked(n);
    blocked.unite_blocks(n, 65536, [&](std::size_t lo, std::size_t, auto&& unite) {
      for (const auto& [a, b] : by_block[lo / 65536]) unite(a, b);
    });
    std::size_t differ = 0;
    for (u32 x = 0; x < n; ++x) differ += blocked.root(x) != serial.find(x);
    CHECK(differ == 0);
  }
}

TEST_CASE("boolean: an operand's positions that no triangle uses change nothing", "[boolean]") {
  // (Operand boxes are taken over the positions: one far away makes a box that holds everything.)
  const Mesh a = sphere(Vec3(0, 0, 0), 1, 32), b = sphere(Vec3(0.5, 0.2, 0.1), 1, 32);
  for (BooleanOp op : {BooleanOp::Union, BooleanOp::Intersection, BooleanOp::Difference}) {
    const Mesh plain = boolean(op, a, b);
    Mesh far_a = a, far_b = b;
    far_a.positions.push_back(Vec3(1e6, -1e6, 1e6));
    far_b.positions.push_back(Vec3(-1e6, 1e6, -1e6));
    const Mesh r = boolean(op, far_a, far_b);
    CHECK(r.triangles == plain.triangles);
    CHECK(r.positions == plain.positions);
  }
}

TEST_CASE("boolean: a cube's corner on the hub of a fan of 1000 triangles", "[boolean]") {
  // A pyramid over a regular 1000-gon (apex (0, 0, 1), base fanned from its centre at the
  // origin): the cube [0, 0.3]^3 has its corner on the base's hub, so the cube's bottom face is
  // cut by the 250 fan edges of its quadrant, all through that corner, and its sides by the
  // apex triangles. (The triangulator looked each edge up by walking around the hub: a billion
  // steps for 10,000 sides.) The cube lies inside the pyramid: the union is the pyramid, the
  // difference takes the cube's volume out.
  const int n = 1000;
  const Mesh cone = pyramid_fan(n);
  const double pyramid = n * std::sin(2 * kPi / n) / 6;
  REQUIRE(cone.volume() == Approx(pyramid).epsilon(1e-12));
  const Mesh c = cube(0, 0, 0, 0.3);
  const Mesh u = boolean(BooleanOp::Union, cone, c);
  require_solid(u);
  CHECK(u.volume() == Approx(pyramid).epsilon(1e-12));
  const Mesh d = boolean(BooleanOp::Difference, cone, c);
  require_solid(d);
  CHECK(d.volume() == Approx(pyramid - 0.027).epsilon(1e-12));
  const Mesh i = boolean(BooleanOp::Intersection, cone, c);
  require_solid(i);
  CHECK(i.volume() == Approx(0.027).epsilon(1e-12));
}

TEST_CASE("boolean: a pyramid over a 3000-gon with its tip cut off: the long cut pieces of its side are checked", "[boolean]") {
  // The side's pieces below the cut run from the rim nearly to the axis: their boxes meet those
  // of hundreds of neighbours, and each has a rounded cut point, so the rounding check looked at
  // every such pair (and at each pair of a side piece and a triangle of the base under it). The
  // side, one face id, is certified embedded by its projection along z on the rounded doubles,
  // and its pairs are not looked at; the result must still be exactly valid.
  const int n = 3000;
  const Mesh cone = pyramid_fan(n, 1, 0);
  const double pyramid = n * std::sin(2 * kPi / n) / 6;
  // The box takes the part above z = 0.85 (a copy of the pyramid scaled by 0.15, inside the box).
  const Mesh tip = box(Vec3(-0.25, -0.25, 0.85), Vec3(0.25, 0.25, 1.5));
  const BooleanResult d = boolean(BooleanOp::Difference, {&cone, &tip});
  require_solid(d.mesh);
  CHECK(d.mesh.volume() == Approx(pyramid * (1 - 0.15 * 0.15 * 0.15)).epsilon(1e-12));
  CHECK(d.mesh.triangles.size() == std::size_t(4 * n - 2));  // side quads, base, the cut's (n - 2)
}
