#include <catch2/catch.hpp>

#include <cmath>

#include "brep_helpers.h"

using namespace wedge;

namespace {
void check_mat(const Mat3& a, const Mat3& b, double eps = 1e-9) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      INFO("entry " << i << "," << j);
      CHECK(a(i, j) == Approx(b(i, j)).margin(eps));
    }
}
// The inertia about its own centroid of an axis-aligned box with sides s and volume V.
Mat3 box_inertia(const Vec3& s) {
  double V = s.prod();
  return (V / 12.0 * Vec3(s.y() * s.y() + s.z() * s.z(), s.x() * s.x() + s.z() * s.z(), s.x() * s.x() + s.y() * s.y()))
      .asDiagonal();
}
// Parallel-axis shift of an inertia tensor by offset d for mass V.
Mat3 shifted(const Mat3& I, double V, const Vec3& d) {
  return I + V * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
}
std::vector<std::vector<int>> cube_faces() {
  return {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
}
std::vector<Point3> cube_points() {
  std::vector<Point3> p;
  for (int i = 0; i < 8; ++i) p.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  return p;
}
}  // namespace

TEST_CASE("a box's mass properties are exact", "[brep][mass]") {
  Model m = box(Vec3(2, 3, 4), Point3(1, 2, 3));
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(24).epsilon(1e-14));
  CHECK(mp.area == Approx(52).epsilon(1e-14));
  CHECK(mp.centroid.x() == Approx(2));
  CHECK(mp.centroid.y() == Approx(3.5));
  CHECK(mp.centroid.z() == Approx(5));
  check_mat(mp.inertia, box_inertia(Vec3(2, 3, 4)), 1e-12);
  Box3 b = m.bounds();
  CHECK(b.min == Point3(1, 2, 3));
  CHECK(b.max == Point3(3, 5, 7));
}

TEST_CASE("an L-shaped prism matches the sum of its two boxes", "[brep][mass]") {
  Model m = prism({{{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 2}, {0, 2}}, {}}, 2);
  CHECK(m.counts() == EulerCounts{12, 18, 8, 0, 0, 1});
  REQUIRE(m.validate().ok);
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(8));
  CHECK(mp.area == Approx(2 * 4 + 2 * 10));
  Point3 c(1.25, 0.75, 1);
  CHECK((mp.centroid - c).norm() < 1e-12);
  Mat3 I = shifted(box_inertia(Vec3(3, 1, 2)), 6, Point3(1.5, 0.5, 1) - c) + shifted(box_inertia(Vec3(1, 1, 2)), 2, Point3(0.5, 1.5, 1) - c);
  check_mat(mp.inertia, I, 1e-12);
}

TEST_CASE("a prism with a hole: the hole's volume and area are taken out", "[brep][mass]") {
  Model m = prism({{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {{{1, 1}, {1, 3}, {3, 3}, {3, 1}}}}, 1);
  CHECK(m.counts() == EulerCounts{16, 24, 10, 2, 1, 1});
  REQUIRE(m.validate().ok);
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(12));
  CHECK(mp.area == Approx(2 * 12 + 16 + 8));
  CHECK((mp.centroid - Point3(2, 2, 0.5)).norm() < 1e-12);
  Mat3 I = box_inertia(Vec3(4, 4, 1)) - box_inertia(Vec3(2, 2, 1));
  check_mat(mp.inertia, I, 1e-12);
}

TEST_CASE("pyramids and frusta match their closed forms", "[brep][mass]") {
  std::vector<Vec2> sq = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  SECTION("square pyramid, side 2, height 3") {
    Model m = frustum(sq, 3, 0, Vec2(0, 0));
    CHECK(m.counts() == EulerCounts{5, 8, 5, 0, 0, 1});
    MassProperties mp = m.mass_properties();
    double a = 2, h = 3, V = a * a * h / 3;
    CHECK(mp.volume == Approx(V));
    CHECK((mp.centroid - Point3(0, 0, h / 4)).norm() < 1e-12);
    double side = std::sqrt(h * h + 1);
    CHECK(mp.area == Approx(a * a + 4 * 0.5 * a * side));
    Mat3 I = Vec3(V * (a * a / 20 + 3 * h * h / 80), V * (a * a / 20 + 3 * h * h / 80), V * a * a / 10).asDiagonal();
    check_mat(mp.inertia, I, 1e-12);
  }
  SECTION("frustum: V = h/3 (A1 + A2 + sqrt(A1 A2))") {
    Model m = frustum(sq, 3, 0.5, Vec2(0, 0));
    CHECK(m.counts() == EulerCounts{8, 12, 6, 0, 0, 1});
    CHECK(m.mass_properties().volume == Approx(3.0 / 3 * (4 + 1 + 2)));
  }
  SECTION("a clockwise base is turned round") {
    std::vector<Vec2> cw(sq.rbegin(), sq.rend());
    CHECK(frustum(cw, 3, 0, Vec2(0, 0)).mass_properties().volume == Approx(4));
  }
}

TEST_CASE("polyhedron builds any closed 2-manifold through Euler operators", "[brep][polyhedron]") {
  SECTION("a cube") {
    Model m = polyhedron(cube_points(), cube_faces());
    CHECK(m.counts() == EulerCounts{8, 12, 6, 0, 0, 1});
    CHECK(m.mass_properties().volume == Approx(1));
  }
  SECTION("a torus of quads has H = 1") {
    int n = 8, k = 6;
    std::vector<Point3> pts;
    std::vector<std::vector<int>> faces;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < k; ++j) {
        double u = 2 * kPi * i / n, v = 2 * kPi * j / k;
        pts.emplace_back((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
        int a = i * k + j, b = ((i + 1) % n) * k + j, c = ((i + 1) % n) * k + (j + 1) % k, d = i * k + (j + 1) % k;
        faces.push_back({a, b, c, d});
      }
    Model m = polyhedron(pts, faces);
    CHECK(m.counts() == EulerCounts{n * k, 2 * n * k, n * k, 0, 1, 1});
    CHECK(m.validate().ok);
    CHECK(m.mass_properties().volume > 0);
  }
}

TEST_CASE("polyhedron rejects open, non-manifold and inconsistent input", "[brep][polyhedron]") {
  auto faces = cube_faces();
  SECTION("open") {
    faces.pop_back();
    CHECK_THROWS_WITH(polyhedron(cube_points(), faces), Catch::Contains("the surface is open: edge"));
  }
  SECTION("one face turned round") {
    std::reverse(faces[0].begin(), faces[0].end());
    CHECK_THROWS_WITH(polyhedron(cube_points(), faces), Catch::Contains("is used in the same direction by faces"));
  }
  SECTION("all faces turned inwards") {
    for (auto& f : faces) std::reverse(f.begin(), f.end());
    CHECK_THROWS_WITH(polyhedron(cube_points(), faces), Catch::Contains("positive volume"));
  }
  SECTION("two cubes sharing a vertex") {
    auto pts = cube_points();
    for (int i = 1; i < 8; ++i) pts.push_back(Point3(1, 1, 1) + cube_points()[static_cast<std::size_t>(i)]);
    for (auto f : cube_faces()) {
      for (int& i : f) i = i == 0 ? 7 : i + 7;
      faces.push_back(f);
    }
    CHECK_THROWS_WITH(polyhedron(pts, faces), Catch::Contains("point 8 is non-manifold"));
  }
  SECTION("bad indices") {
    faces[0][0] = 8;
    CHECK_THROWS_WITH(polyhedron(cube_points(), faces), Catch::Contains("names point 9, but there are 8 points"));
    faces[0] = {0, 2, 2, 1};
    CHECK_THROWS_WITH(polyhedron(cube_points(), faces), Catch::Contains("uses point 3 twice"));
    auto pts = cube_points();
    pts.emplace_back(5, 5, 5);
    CHECK_THROWS_WITH(polyhedron(pts, cube_faces()), Catch::Contains("point 9 is used by no face"));
  }
  SECTION("a face that is not flat") {
    auto pts = cube_points();
    pts[7] = Point3(1.2, 1, 1);
    CHECK_THROWS_WITH(polyhedron(pts, cube_faces()), Catch::Contains("is not planar"));
  }
}

TEST_CASE("transforms move the geometry, a mirror keeps faces pointing out", "[brep][transform]") {
  Model m = prism({{{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 2}, {0, 2}}, {}}, 2);
  MassProperties before = m.mass_properties();
  SECTION("rotation and translation") {
    m.transform(translate(Vec3(1, 2, 3)) * rotate(30, Vec3(1, 1, 0)));
    CHECK(m.validate().ok);
    CHECK(m.mass_properties().volume == Approx(before.volume));
  }
  SECTION("mirror") {
    m.transform(reflect(Vec3(1, 0, 0)));
    Validation v = m.validate();
    INFO(v.message);
    CHECK(v.ok);
    MassProperties after = m.mass_properties();
    CHECK(after.volume == Approx(before.volume));
    CHECK(after.centroid.x() == Approx(-before.centroid.x()));
    CHECK(m.counts() == EulerCounts{12, 18, 8, 0, 0, 1});
  }
  SECTION("mirror of the worked example with its arcs") {
    Model w = worked_example();
    double vol = w.approximate_volume();
    w.transform(reflect(Vec3(0, 1, 1)));
    Validation v = w.validate();
    INFO(v.message);
    CHECK(v.ok);
    CHECK(w.approximate_volume() == Approx(vol));
  }
  SECTION("non-uniform scale") {
    m.transform(scale(Vec3(2, 1, 1)));
    CHECK(m.mass_properties().volume == Approx(2 * before.volume));
    Model w = worked_example();
    CHECK_THROWS_WITH(w.transform(scale(Vec3(2, 1, 1))), Catch::Contains("ellipses"));
  }
}
