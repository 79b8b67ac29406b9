// Curved solids: each primitive and builder is valid, has the documented Euler counts, and its
// mass properties agree with the closed forms.
#include <catch2/catch.hpp>

#include <cmath>

#include "brep/brep.h"

using namespace wedge;

namespace {
constexpr double pi = 3.14159265358979323846;
void check_diag_inertia(const Mat3& I, const Vec3& expected, double rel) {
  for (int i = 0; i < 3; ++i) {
    INFO("diagonal " << i);
    CHECK(I(i, i) == Approx(expected[i]).epsilon(rel));
    for (int j = 0; j < 3; ++j)
      if (i != j) CHECK(std::abs(I(i, j)) < rel * expected.norm());
  }
}
}  // namespace

TEST_CASE("sphere: V 2 E 1 F 1, volume, area and inertia in closed form", "[brep][curved]") {
  double r = 1.7;
  Model m = sphere(r, Point3(1, 2, 3));
  REQUIRE(m.validate().ok);
  CHECK(m.counts() == EulerCounts{2, 1, 1, 0, 0, 1});
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(4.0 / 3 * pi * r * r * r).epsilon(1e-12));
  CHECK(mp.area == Approx(4 * pi * r * r).epsilon(1e-12));
  CHECK((mp.centroid - Point3(1, 2, 3)).norm() < 1e-12);
  double I = 0.4 * mp.volume * r * r;
  check_diag_inertia(mp.inertia, Vec3(I, I, I), 1e-11);
}

TEST_CASE("cylinder: V 4 E 6 F 4, exact volume and inertia", "[brep][curved]") {
  double r = 0.8, h = 2.5;
  Model m = cylinder(r, h);
  REQUIRE(m.validate().ok);
  CHECK(m.counts() == EulerCounts{4, 6, 4, 0, 0, 1});
  MassProperties mp = m.mass_properties();
  double V = pi * r * r * h;
  CHECK(mp.volume == Approx(V).epsilon(1e-12));
  CHECK(mp.area == Approx(2 * pi * r * r + 2 * pi * r * h).epsilon(1e-12));
  CHECK((mp.centroid - Point3(0, 0, h / 2)).norm() < 1e-12);
  double Ixx = V * (3 * r * r + h * h) / 12, Izz = V * r * r / 2;
  check_diag_inertia(mp.inertia, Vec3(Ixx, Ixx, Izz), 1e-11);
}

TEST_CASE("approximate_volume (validate()'s sign check) is within 1e-6 of the exact volume, at a 64th of the work", "[brep][curved]") {
  // validate() and the builders ask only its sign; 4 Gauss points on half the panels (it took a
  // 16-point rule: 1.7 ms per cylinder, most of the time to build a script's 400 placed drills).
  for (const Model& m : {sphere(1.3, Point3(1, 0, 0)), cylinder(0.2, 5), torus(2, 0.5), cone(1, 0.3, 2)}) {
    const double exact = m.mass_properties().volume;
    CHECK(m.approximate_volume() == Approx(exact).epsilon(1e-6));
  }
}

TEST_CASE("cone: frustum V 4 E 6 F 4 and apex V 3 E 4 F 3, volumes in closed form", "[brep][curved]") {
  double r1 = 1.5, r2 = 0.5, h = 2;
  Model f = cone(r1, r2, h);
  REQUIRE(f.validate().ok);
  CHECK(f.counts() == EulerCounts{4, 6, 4, 0, 0, 1});
  CHECK(f.mass_properties().volume == Approx(pi * h / 3 * (r1 * r1 + r1 * r2 + r2 * r2)).epsilon(1e-12));
  double s = std::hypot(r1 - r2, h);
  CHECK(f.mass_properties().area == Approx(pi * (r1 * r1 + r2 * r2) + pi * (r1 + r2) * s).epsilon(1e-12));
  Model a = cone(r1, 0, h);
  REQUIRE(a.validate().ok);
  CHECK(a.counts() == EulerCounts{3, 4, 3, 0, 0, 1});
  MassProperties ma = a.mass_properties();
  CHECK(ma.volume == Approx(pi * r1 * r1 * h / 3).epsilon(1e-12));
  CHECK((ma.centroid - Point3(0, 0, h / 4)).norm() < 1e-12);
  Model b = cone(0, r1, h);  // apex at the bottom
  REQUIRE(b.validate().ok);
  CHECK(b.counts() == EulerCounts{3, 4, 3, 0, 0, 1});
  CHECK((b.mass_properties().centroid - Point3(0, 0, 0.75 * h)).norm() < 1e-12);
}

TEST_CASE("torus: V 4 E 6 F 2 H 1, Pappus's volume and area", "[brep][curved]") {
  double R = 2, r = 0.5;
  Model m = torus(R, r);
  REQUIRE(m.validate().ok);
  CHECK(m.counts() == EulerCounts{4, 6, 2, 0, 1, 1});
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(2 * pi * pi * R * r * r).epsilon(1e-12));
  CHECK(mp.area == Approx(4 * pi * pi * R * r).epsilon(1e-12));
  double V = mp.volume;
  check_diag_inertia(mp.inertia, Vec3(V * (4 * R * R + 5 * r * r) / 8, V * (4 * R * R + 5 * r * r) / 8, V * (4 * R * R + 3 * r * r) / 4),
                     1e-11);
}

TEST_CASE("tube: V 8 E 12 F 6 R 2 H 1, annulus volume", "[brep][curved]") {
  Model m = tube(2, 1, 3);
  REQUIRE(m.validate().ok);
  CHECK(m.counts() == EulerCounts{8, 12, 6, 2, 1, 1});
  CHECK(m.mass_properties().volume == Approx(pi * 3 * 3).epsilon(1e-12));
}

TEST_CASE("profiles of thousands of points: a prism with a hole and a revolve", "[brep][curved]") {
  // The builders' chains of mev start at the chain's tip and their mefs relabel the shorter side
  // of the loop they split (both were walks along the whole loop: quadratic in the points).
  const int n = 2000;
  std::vector<Vec2> outer, hole, half;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * pi * i / n;
    outer.emplace_back(2 * std::cos(a), 2 * std::sin(a));
    hole.emplace_back(std::cos(-a), std::sin(-a));
    const double b = -pi / 2 + pi * i / (n - 1);
    half.emplace_back(std::cos(b), std::sin(b));
  }
  half.front().x() = half.back().x() = 0;  // (on the axis)
  auto polygon_area = [](const std::vector<Vec2>& p) {
    double s = 0;
    for (std::size_t i = 0; i < p.size(); ++i) s += p[i].x() * p[(i + 1) % p.size()].y() - p[(i + 1) % p.size()].x() * p[i].y();
    return s / 2;
  };
  const Model ring = prism({outer, {hole}}, 1.5);
  CHECK(ring.validate().ok);
  CHECK(ring.faces().size() == std::size_t(2 * n + 2));
  CHECK(ring.mass_properties().volume == Approx(1.5 * (polygon_area(outer) + polygon_area(hole))).epsilon(1e-12));
  const Model spun = revolve(section_of({half, {}}), 2 * pi);
  CHECK(spun.validate().ok);
  // The solid of the polygon turned about its chord: a sphere less the sagittas' rings.
  double v = 0;
  for (int i = 0; i + 1 < n; ++i) {  // (Pappus, piece by piece: area times the centroid's path)
    const Vec2 &p = half[i], &q = half[i + 1];
    const double area = (p.x() + q.x()) / 2 * (q.y() - p.y());
    const double cx = (p.x() * p.x() + p.x() * q.x() + q.x() * q.x()) / (3 * (p.x() + q.x()));
    v += 2 * pi * cx * area;
  }
  CHECK(spun.mass_properties().volume == Approx(v).epsilon(1e-9));
}
