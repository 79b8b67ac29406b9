// The boolean engine on cases with hand-worked answers: boxes (exact volumes), the degenerate
// configurations of issue 11, provenance and operand errors. The CGAL oracle tests are in
// test_boolean_oracle.cpp.
#include <CGAL/Gmpq.h>
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

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
    CHECK(u.triangles.size() == 20);  // the two inner faces are gone: a 2x1x1 box in 10 quads
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
}

TEST_CASE("boolean: a result fed back is known valid, any change to it is checked again", "[boolean]") {
  const Mesh a = cube(0, 0, 0, 2), b = cube(1, 1, 1, 2), c = cube(0.5, 0.5, -1, 1);
  BooleanStats st;
  const BooleanResult r = boolean(BooleanOp::Union, {&a, &b}, &st);
  CHECK(st.trusted == 0);
  boolean(BooleanOp::Difference, {&r.mesh, &c}, &st);
  CHECK(st.trusted == 1);  // the union's result, bit for bit
  // The same result moved by a hair is another mesh: checked (and valid).
  Mesh moved = r.mesh;
  moved.positions[0].x() = std::nextafter(moved.positions[0].x(), 10.0);
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


TEST_CASE("boolean: the engine's filtered orientation tests agree with the exact ones on near-degenerate input",
          "[boolean]") {
  // Points on a line or a plane, each coordinate nudged by a few ulps, at several scales: the
  // float filter must either decide correctly or hand over to the exact predicate.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> nudge(-3, 3);
  auto jiggle = [&](double x) {
    for (int k = nudge(rng); k != 0; k += (k > 0 ? -1 : 1)) x = std::nextafter(x, k > 0 ? INFINITY : -INFINITY);
    return x;
  };
  std::uniform_int_distribution<int> small(-8, 8);
  int decided_zero = 0;
  // Powers of two keep the integer cases exactly degenerate after scaling.
  for (double scale : {std::ldexp(1.0, -490), std::ldexp(1.0, -10), 1.0, std::ldexp(1.0, 23), std::ldexp(1.0, 300)}) {
    for (int n = 0; n < 20000; ++n) {
      Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng)), d;
      double cx, cy;
      if (n % 4 == 0) {  // small integers: d exactly on the plane, (cx, cy) exactly on the line
        a = Vec3(small(rng), small(rng), small(rng));
        b = Vec3(small(rng), small(rng), small(rng));
        c = Vec3(small(rng), small(rng), small(rng));
        d = a + (b - a) * small(rng) + (c - a) * small(rng);
        const int m = small(rng);
        cx = a.x() + m * (b.x() - a.x());
        cy = a.y() + m * (b.y() - a.y());
      } else {
        const double s = u(rng), t = u(rng);
        d = a + s * (b - a) + t * (c - a);  // on the plane, up to rounding
        d = Vec3(jiggle(d.x()), jiggle(d.y()), jiggle(d.z()));
        cx = jiggle(a.x() + s * (b.x() - a.x()));
        cy = jiggle(a.y() + s * (b.y() - a.y()));
      }
      const Vec3 A = a * scale, B = b * scale, C = c * scale, D = d * scale;
      REQUIRE(boolean_detail::orient3d_fast(A, B, C, D) == orient3d(A, B, C, D));
      const int fast = boolean_detail::orient2d_fast(A.x(), A.y(), B.x(), B.y(), cx * scale, cy * scale);
      REQUIRE(fast == orient2d(Point2(A.x(), A.y()), Point2(B.x(), B.y()), Point2(cx * scale, cy * scale)));
      if (fast == 0) ++decided_zero;
    }
  }
  CHECK(decided_zero > 0);  // the cases include exact degeneracies, decided by the exact path
  // Side quads of extrusions: four points that are two points seen along an axis are coplanar
  // (answered without the exact predicate); nudged by an ulp off that, they are not.
  int extruded = 0, off = 0;
  for (int n = 0; n < 20000; ++n) {
    const int k = n % 3, i = (k + 1) % 3, j = (k + 2) % 3;
    Vec3 p, q, a, b, c, d;
    p[i] = u(rng), p[j] = u(rng), q[i] = u(rng), q[j] = u(rng);
    a = p, b = q, c = q, d = p;
    a[k] = u(rng), b[k] = u(rng), c[k] = u(rng), d[k] = u(rng);
    if (n % 5 == 4) {
      d[i] = std::nextafter(d[i], INFINITY);  // off the wall by an ulp
      ++off;
    }
    const int fast = boolean_detail::orient3d_fast(a, b, c, d);
    REQUIRE(fast == orient3d(a, b, c, d));
    if (n % 5 != 4) {
      REQUIRE(fast == 0);
      ++extruded;
    }
  }
  CHECK(extruded > 10000);
  CHECK(off > 1000);
}

TEST_CASE("boolean: points with coordinates fixed by their definition are exact doubles, and the fast predicates on "
          "them agree with exact ones",
          "[boolean]") {
  // Random segments and planes, some axis-parallel (their points have coordinates known without
  // arithmetic), some generic. A point the engine calls a double must lie exactly on every plane
  // and segment that defines it (checked with the kernel's exact predicates); side() must agree
  // with orient3d on the plane's vertices (walls: a, b, a + e_k).
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> small(-6, 6);
  std::uniform_real_distribution<double> u(-3, 3);
  Mesh m;
  auto coord = [&](int i) { return i % 3 == 0 ? double(small(rng)) : u(rng); };
  for (int i = 0; i < 60; ++i) m.add_vertex(Vec3(coord(i), coord(i + 1), coord(i + 2)));
  // Axis-parallel vertex pairs and triples: shared coordinates.
  for (int i = 0; i < 60; ++i) {
    Vec3 p = m.positions[i];
    const int k = i % 3;
    Vec3 q = p, r = p;
    q[(k + 1) % 3] = u(rng);
    r[(k + 2) % 3] = u(rng);
    q[(k + 2) % 3] = small(rng);
    m.add_vertex(q);
    m.add_vertex(r);
  }
  std::vector<const Mesh*> one{&m};
  boolean_detail::Soup soup = boolean_detail::make_soup(one);
  REQUIRE(soup.verts.size() == m.positions.size());  // no two positions merged: ids are the mesh's
  boolean_detail::Points pts(soup);
  using boolean_detail::u32;
  const auto nv = static_cast<u32>(soup.verts.size());
  std::uniform_int_distribution<u32> pick(0, nv - 1), base(0, 59);
  // Vertex i < 60 and its two companions q = 60 + 2i (coordinate i % 3 kept) and r = 61 + 2i (only
  // coordinate (i + 2) % 3 changed): (i, r) is an axis-parallel segment, (i, q, r) lies in the
  // plane x_{i % 3} = const.
  auto plane = [&]() {
    const u32 i = base(rng);
    switch (rng() % 3) {
      case 0: return boolean_detail::Plane::of_triangle({i, 60 + 2 * i, 61 + 2 * i});
      case 1: return boolean_detail::Plane::wall(pick(rng), pick(rng), static_cast<int>(rng() % 3));
      default: return boolean_detail::Plane::of_triangle({pick(rng), pick(rng), pick(rng)});
    }
  };
  auto vert = [&](boolean_detail::u32 v) { return soup.verts[v]; };
  auto on_plane = [&](const boolean_detail::Plane& P, const Vec3& x) {
    if (P.axis < 0) return orient3d(vert(P.a), vert(P.b), vert(P.c), x) == 0;
    const int i = (P.axis + 1) % 3, j = (P.axis + 2) % 3;
    return orient2d(Point2(vert(P.a)[i], vert(P.a)[j]), Point2(vert(P.b)[i], vert(P.b)[j]), Point2(x[i], x[j])) == 0;
  };
  auto degenerate = [&](const boolean_detail::Plane& P) {
    if (P.axis < 0) return collinear(vert(P.a), vert(P.b), vert(P.c));
    const int i = (P.axis + 1) % 3, j = (P.axis + 2) % 3;
    return vert(P.a)[i] == vert(P.b)[i] && vert(P.a)[j] == vert(P.b)[j];
  };
  int doubles = 0, sides = 0;
  for (int n = 0; n < 12000; ++n) {
    boolean_detail::PointDef d;
    if (n % 2 == 0) {
      d.kind = boolean_detail::PointDef::Lpi;
      if (rng() % 2) {
        d.p = base(rng);
        d.q = 61 + 2 * d.p;
      } else {
        d.p = pick(rng);
        d.q = pick(rng);
      }
      if (d.q == d.p) continue;
      d.P[0] = plane();
      if (degenerate(d.P[0])) continue;
      // The segment must cross the plane (W != 0): p and q on strictly opposite sides.
      if (pts.side(d.P[0], d.p) * pts.side(d.P[0], d.q) >= 0) continue;
    } else {
      d.kind = boolean_detail::PointDef::Tpi;
      for (auto& P : d.P) P = plane();
      if (degenerate(d.P[0]) || degenerate(d.P[1]) || degenerate(d.P[2])) continue;
      bool independent = false;
      for (int k = 0; k < 3 && !independent; ++k)
        if (pts.cross_sign(d.P[1], d.P[2], k) != 0) independent = true;
      if (!independent) continue;
      // Three independent planes: det of the normals != 0 (checked on doubles far from zero).
      Vec3 nn[3];
      for (int k = 0; k < 3; ++k) {
        const auto& P = d.P[k];
        nn[k] = P.axis < 0 ? (vert(P.b) - vert(P.a)).cross(vert(P.c) - vert(P.a))
                           : (vert(P.b) - vert(P.a)).cross(Vec3::Unit(P.axis));
      }
      const double det = nn[0].dot(nn[1].cross(nn[2]));
      if (!(std::abs(det) > 1e-6 * nn[0].norm() * nn[1].norm() * nn[2].norm())) continue;
    }
    const u32 id = pts.add(d);
    const Vec3 x = pts.approx(id);
    if (pts.is_double(id)) {
      ++doubles;
      if (d.kind == boolean_detail::PointDef::Lpi) {
        REQUIRE(on_plane(d.P[0], x));
        REQUIRE(collinear(vert(d.p), vert(d.q), x));
      } else {
        REQUIRE(on_plane(d.P[0], x));
        REQUIRE(on_plane(d.P[1], x));
        REQUIRE(on_plane(d.P[2], x));
      }
      for (int k = 0; k < 20; ++k) {
        const u32 a = pick(rng), b = pick(rng), c = pick(rng);
        const int axis = static_cast<int>(rng() % 3);
        if (!collinear(vert(a), vert(b), vert(c)))
          REQUIRE(pts.side(boolean_detail::Plane::of_triangle({a, b, c}), id) == orient3d(vert(a), vert(b), vert(c), x));
        const Vec3 a1 = vert(a) + Vec3::Unit(axis);
        if (a1 - Vec3::Unit(axis) == vert(a) && !(vert(a) - vert(b)).isZero())
          REQUIRE(pts.side(boolean_detail::Plane::wall(a, b, axis), id) == orient3d(vert(a), vert(b), a1, x));
        REQUIRE(pts.compare(id, a, axis) == (x[axis] < vert(a)[axis] ? -1 : x[axis] > vert(a)[axis] ? 1 : 0));
        ++sides;
      }
    }
  }
  CHECK(doubles > 150);
  CHECK(sides > 3000);
}

TEST_CASE("boolean: cut points round within an ulp, and the predicates on them (collinear, "
          "near-cocircular) agree with exact rational arithmetic, and the flip test is never wrong",
          "[boolean]") {
  // Segments cut by axis planes (z = c: the short formula) and by generic triangle planes; their
  // points' exact coordinates computed here in rationals (GMP), independently of the engine.
  // Several cuts of one segment are collinear with its end points (answered without arithmetic
  // by the engine); cuts of a polygon's chords by one plane are nearly cocircular.
  using Q = CGAL::Gmpq;
  using boolean_detail::u32;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  Mesh m;
  for (int i = 0; i < 24; ++i) {  // a 24-gon's vertical edges, bottom and top turned by a step
    const double a = 2 * kPi * i / 24, b = 2 * kPi * (i + 1) / 24;
    m.add_vertex(Vec3(0.6 * std::cos(a) + 3, 0.6 * std::sin(a) - 1, -1.25));
    m.add_vertex(Vec3(0.6 * std::cos(b) + 3, 0.6 * std::sin(b) - 1, 2.5));
  }
  for (int i = 0; i < 30; ++i) m.add_vertex(Vec3(3 + u(rng), u(rng) - 1, 0.6 + u(rng)));
  m.add_vertex(Vec3(-5, -5, 0.7));  // an axis plane z = 0.7 (a triangle whose vertices share z)
  m.add_vertex(Vec3(5, -5, 0.7));
  m.add_vertex(Vec3(0, 5, 0.7));
  std::vector<const Mesh*> one{&m};
  boolean_detail::Soup soup = boolean_detail::make_soup(one);
  REQUIRE(soup.verts.size() == m.positions.size());
  boolean_detail::Points pts(soup);
  const auto nv = static_cast<u32>(soup.verts.size());
  const boolean_detail::Plane zplane = boolean_detail::Plane::of_triangle({nv - 3, nv - 2, nv - 1});
  auto qv = [&](u32 v) { return std::array<Q, 3>{Q(soup.verts[v].x()), Q(soup.verts[v].y()), Q(soup.verts[v].z())}; };
  std::vector<u32> ids;
  std::vector<std::array<Q, 3>> exact;
  std::vector<std::size_t> zcuts;
  auto add_cut = [&](u32 p, u32 q, const boolean_detail::Plane& P) {
    if (pts.side(P, p) * pts.side(P, q) >= 0) return false;
    boolean_detail::PointDef d;
    d.kind = boolean_detail::PointDef::Lpi;
    d.p = p;
    d.q = q;
    d.P[0] = P;
    const auto A = qv(P.a), B = qv(P.b), C = qv(P.c), X = qv(p), Y = qv(q);
    std::array<Q, 3> e1, e2, n;
    for (int i = 0; i < 3; ++i) e1[i] = B[i] - A[i], e2[i] = C[i] - A[i];
    n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    Q num = 0, den = 0;
    for (int i = 0; i < 3; ++i) num += n[i] * (A[i] - X[i]), den += n[i] * (Y[i] - X[i]);
    const Q t = num / den;
    std::array<Q, 3> x;
    for (int i = 0; i < 3; ++i) x[i] = X[i] + t * (Y[i] - X[i]);
    ids.push_back(pts.add(d));
    exact.push_back(x);
    return true;
  };
  for (u32 i = 0; i < 24; ++i) {
    REQUIRE(add_cut(2 * i, 2 * i + 1, zplane));  // the chords' cuts by z = 0.7: nearly cocircular
    zcuts.push_back(ids.size() - 1);
    for (int k = 0; k < 3; ++k) {  // the same segment cut by generic planes: collinear cuts
      const u32 a = 48 + static_cast<u32>(rng() % 30), b = 48 + static_cast<u32>(rng() % 30), c = 48 + static_cast<u32>(rng() % 30);
      if (a != b && b != c && a != c && !collinear(soup.verts[a], soup.verts[b], soup.verts[c]))
        add_cut(2 * i, 2 * i + 1, boolean_detail::Plane::of_triangle({a, b, c}));
    }
  }
  REQUIRE(ids.size() > 50);
  // Rounding: within an ulp; the box holds the exact coordinate.
  for (std::size_t n = 0; n < ids.size(); ++n)
    for (int i = 0; i < 3; ++i) {
      const double x = pts.approx(ids[n])[i];
      const Q& e = exact[n][i];
      INFO("point " << n << " coordinate " << i);
      REQUIRE(Q(pts.box(ids[n])[i]) <= e);
      REQUIRE(e <= Q(pts.box(ids[n])[i + 3]));
      REQUIRE((Q(std::nextafter(x, -INFINITY)) < e && e < Q(std::nextafter(x, INFINITY))));
    }
  // Every point: the cuts, then the segments' end points.
  std::vector<u32> all = ids;
  std::vector<std::array<Q, 3>> ex = exact;
  for (u32 v = 0; v < 48; ++v) {
    all.push_back(v);
    ex.push_back(qv(v));
  }
  auto sgn = [](const Q& x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); };
  std::uniform_int_distribution<std::size_t> pick(0, all.size() - 1);
  int zeros = 0, near_cocircular = 0, inside = 0, found = 0;
  for (int n = 0; n < 20000; ++n) {
    int k = static_cast<int>(rng() % 3);
    std::size_t a = pick(rng), b = pick(rng), c = pick(rng), d = pick(rng);
    if (n % 4 == 0) {  // two cuts of one segment and an end point, or three cuts of it
      const u32 seg = static_cast<u32>(rng() % 24);
      std::vector<std::size_t> on;
      for (std::size_t x = 0; x < all.size(); ++x) {
        const auto& D = pts.def(all[x]);
        if ((D.kind == boolean_detail::PointDef::Lpi && D.p == 2 * seg) || all[x] == 2 * seg || all[x] == 2 * seg + 1)
          on.push_back(x);
      }
      a = on[rng() % on.size()], b = on[rng() % on.size()], c = on[rng() % on.size()];
    }
    if (n % 4 == 1) {  // four cuts of the chords by z = 0.7, seen along z
      a = zcuts[rng() % 24], b = zcuts[rng() % 24], c = zcuts[rng() % 24], d = zcuts[rng() % 24];
      k = 2;
    }
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const auto &A = ex[a], &B = ex[b], &C = ex[c], &D = ex[d];
    const int o = sgn((B[i] - A[i]) * (C[j] - A[j]) - (B[j] - A[j]) * (C[i] - A[i]));
    zeros += o == 0 && a != b && b != c && a != c;
    REQUIRE(pts.orient2d(all[a], all[b], all[c], k) == o);
    Q r[3][3];
    const std::array<Q, 3>* P3[3] = {&A, &B, &C};
    for (int q = 0; q < 3; ++q) {
      r[q][0] = (*P3[q])[i] - D[i];
      r[q][1] = (*P3[q])[j] - D[j];
      r[q][2] = r[q][0] * r[q][0] + r[q][1] * r[q][1];
    }
    const Q det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                  r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    near_cocircular += n % 4 == 1 && a != b && a != c && a != d && b != c && b != d && c != d;
    // The retriangulation's flip test: "inside" only where exactly inside, and (on quadruples
    // not chosen near-cocircular) it finds nearly every one that is.
    const int certain = pts.incircle_certain(all[a], all[b], all[c], all[d], k);
    REQUIRE((certain == 1 || certain == -1));
    if (certain == 1) REQUIRE(sgn(det) == 1);
    if (n % 4 != 1 && sgn(det) == 1) {
      ++inside;
      found += certain == 1;
    }
  }
  CHECK(zeros > 1000);
  CHECK(near_cocircular > 1000);
  CHECK(inside > 1000);
  CHECK(found >= inside * 95 / 100);
}

TEST_CASE("boolean: points collinear by their definitions are found so without exact arithmetic, and only those",
          "[boolean]") {
  // A cylinder's side quad b0 b1 t1 t0 (planar; its diagonal b0 t1) cut by a plate's face z = 1:
  // the cuts of b0 t0, b0 t1 and b1 t1 lie on one line (the face's plane and the quad's), though
  // none is a double and no two share a segment. The same with t1 lifted off the quad's plane
  // (a quad that is not planar): not collinear, and orient2d says so.
  using boolean_detail::u32;
  Mesh m;
  const double a0 = 0.3, a1 = 0.5;
  m.add_vertex({std::cos(a0), std::sin(a0), -0.5});  // b0
  m.add_vertex({std::cos(a0), std::sin(a0), 1.5});   // t0
  m.add_vertex({std::cos(a1), std::sin(a1), -0.5});  // b1
  m.add_vertex({std::cos(a1), std::sin(a1), 1.5});   // t1
  m.add_vertex({std::cos(a1) + 1e-3, std::sin(a1) - 1e-3, 1.5});  // t1 off the quad's plane
  m.add_vertex({-5, -5, 1});
  m.add_vertex({5, -5, 1});
  m.add_vertex({0, 5, 1});
  std::vector<const Mesh*> one{&m};
  const boolean_detail::Soup soup = boolean_detail::make_soup(one);
  boolean_detail::Points pts(soup);
  const boolean_detail::Plane face = boolean_detail::Plane::of_triangle({5, 6, 7});
  auto lpi = [&](u32 p, u32 q) {
    boolean_detail::PointDef d;
    d.kind = boolean_detail::PointDef::Lpi;
    d.p = p;
    d.q = q;
    d.P[0] = face;
    return pts.add(d);
  };
  const u32 A = lpi(0, 1), M = lpi(0, 3), B = lpi(2, 3), M2 = lpi(0, 4), B2 = lpi(2, 4);
  for (u32 x : {M, M2, B2}) CHECK_FALSE(pts.is_double(x));  // the diagonal's cuts are not doubles
  CHECK(pts.collinear_by_definition(A, M, B));
  CHECK(pts.collinear_by_definition(B, A, M));
  CHECK(pts.orient2d(A, M, B, 2) == 0);
  CHECK(pts.orient2d(M, A, B, 2) == 0);
  CHECK_FALSE(pts.collinear_by_definition(A, M2, B2));
  CHECK(pts.orient2d(A, M2, B2, 2) != 0);
  CHECK(pts.orient2d(A, M2, B2, 2) == -pts.orient2d(M2, A, B2, 2));
  // On a plane by definition: the cuts lie on the face; A on every plane through its segment.
  CHECK(pts.on_plane(M, face));
  CHECK(pts.on_plane(A, boolean_detail::Plane::of_triangle({0, 1, 2})));
  CHECK_FALSE(pts.on_plane(M2, boolean_detail::Plane::of_triangle({0, 1, 2})));
  // Three TPIs on the face and on the quad's plane (each with a third plane of its own) are
  // collinear by two planes they all lie on; with the off-plane quad for one of them, not.
  auto tpi = [&](const boolean_detail::Plane& q, const boolean_detail::Plane& x) {
    boolean_detail::PointDef d;
    d.kind = boolean_detail::PointDef::Tpi;
    d.P[0] = face;
    d.P[1] = q;
    d.P[2] = x;
    return pts.add(d);
  };
  const auto quad = boolean_detail::Plane::of_triangle({0, 1, 3}), quad2 = boolean_detail::Plane::of_triangle({0, 1, 4});
  const u32 P1 = tpi(quad, boolean_detail::Plane::wall(5, 1, 2)), P2 = tpi(quad, boolean_detail::Plane::wall(6, 3, 2)),
            P3 = tpi(boolean_detail::Plane::of_triangle({2, 3, 0}), boolean_detail::Plane::wall(7, 0, 2)),
            P4 = tpi(quad2, boolean_detail::Plane::wall(7, 2, 2));
  CHECK(pts.collinear_by_definition(P1, P2, P3));  // {2, 3, 0} is the quad's plane too
  CHECK(pts.orient2d(P1, P2, P3, 2) == 0);
  CHECK_FALSE(pts.collinear_by_definition(P1, P2, P4));
  CHECK(pts.orient2d(P1, P2, P4, 2) != 0);
}

TEST_CASE("boolean: two edges that cross get one point definition from all four pairs of their triangles",
          "[boolean]") {
  // Edge p q (of triangles T, T') crosses edge r s (of U, U') at the origin. Each of the four pairs
  // (T or T', U or U') meets there; the point must come out as one definition, so that it is
  // interned once instead of being found equal to three others by exact arithmetic.
  Mesh m;
  const auto p = m.add_vertex({-1, 0, 0}), q = m.add_vertex({1, 0, 0}), c = m.add_vertex({0, 1, 1});
  const auto c2 = m.add_vertex({0.2, -1, 0.5});
  const auto r = m.add_vertex({0, 0.5, -0.5}), s = m.add_vertex({0, -0.5, 0.5}), w = m.add_vertex({0.5, 0.3, 0.2});
  const auto w2 = m.add_vertex({-0.5, 0.4, 0.1});
  const auto T = m.add_triangle(p, q, c), T2 = m.add_triangle(q, p, c2);
  const auto U = m.add_triangle(r, s, w), U2 = m.add_triangle(s, r, w2);
  std::vector<const Mesh*> one{&m};
  boolean_detail::Soup soup = boolean_detail::make_soup(one);
  boolean_detail::Points pts(soup);
  std::vector<boolean_detail::PointDef> at_origin;
  for (auto t : {T, T2})
    for (auto u : {U, U2}) {
      const boolean_detail::PairCut cut = boolean_detail::intersect_pair(pts, t, u);
      std::vector<boolean_detail::PointDef> ends = cut.points;
      for (const auto& sg : cut.segs_t) {
        ends.push_back(sg.a);
        ends.push_back(sg.b);
      }
      int found = 0;
      for (const auto& d : ends) {
        const auto id = pts.add(d);
        if (pts.approx(id).norm() == 0) {
          at_origin.push_back(d);
          ++found;
        }
      }
      INFO("pair " << t << ", " << u);
      REQUIRE(found == 1);
    }
  REQUIRE(at_origin.size() == 4);
  for (const auto& d : at_origin) {
    REQUIRE(d.kind == at_origin[0].kind);
    REQUIRE(d.p == at_origin[0].p);
    REQUIRE(d.q == at_origin[0].q);
    REQUIRE(d.P[0] == at_origin[0].P[0]);
  }
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
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (const Mesh* m : ops) {
    std::vector<std::uint32_t> id(m->positions.size());
    for (std::size_t v = 0; v < m->positions.size(); ++v) {
      const Vec3& p = m->positions[v];
      const std::array<double, 3> key{p.x() + 0.0, p.y() + 0.0, p.z() + 0.0};
      auto [it, fresh] = seen.emplace(key, static_cast<std::uint32_t>(verts.size()));
      if (fresh) verts.push_back(Vec3(key[0], key[1], key[2]));
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
    CHECK(soup.tris == tris);
    for (const Vec3& p : soup.verts)
      for (int i = 0; i < 3; ++i) CHECK_FALSE((std::signbit(p[i]) && p[i] == 0));
    CHECK(soup.operand[30000] == 1);
    CHECK(soup.local[30001] == 1);
  }
}
