// Curved solids: each primitive and builder is valid, has the documented Euler counts, and its
// mass properties agree with the closed forms.
#include <catch2/catch.hpp>

#include <cmath>

#include "brep/brep.h"
#include "kernel/transform.h"
#include "surfaces/surfaces.h"

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
  CHECK(spun.mass_properties().volume == Approx(v).epsilon(1e-12));
}

TEST_CASE("a revolved rectangle's mass properties are exact: 3 points across each straight piece", "[brep][curved]") {
  // Revolved straight pieces are affine in the profile's parameter, and so is their area element
  // (|x| times the piece's length): the mass integrands are polynomials of degree 4 or less
  // there, which exact_mass integrates with 3 Gauss points and one panel per piece. A hollow
  // cylinder, radii 1 and 2, height 3: every moment in closed form.
  const Model m = revolve(section_of({{{1, 0}, {2, 0}, {2, 3}, {1, 3}}, {}}), 2 * pi);
  REQUIRE(m.validate().ok);
  const MassProperties mp = m.mass_properties();
  const double V = pi * (4 - 1) * 3;
  CHECK(mp.volume == Approx(V).epsilon(1e-14));
  CHECK(mp.area == Approx(2 * pi * (1 + 2) * 3 + 2 * pi * (4 - 1)).epsilon(1e-14));
  CHECK((mp.centroid - Point3(0, 0, 1.5)).norm() < 1e-14);
  check_diag_inertia(mp.inertia, Vec3(V / 12 * (3 * 5 + 9), V / 12 * (3 * 5 + 9), V / 2 * 5), 1e-13);
  // The rule is taken only where the area element is affine: a straight piece across the axis
  // has |x| bent at the axis.
  const auto straight = std::make_shared<const LineSegment>(Point3(1, 0, 0), Point3(2, 1, 0));
  const auto across = std::make_shared<const LineSegment>(Point3(-1, 0, 0), Point3(2, 1, 0));
  CHECK(RevolutionSurface(straight, 2 * pi).affine_area_in_u());
  CHECK_FALSE(RevolutionSurface(across, 2 * pi).affine_area_in_u());
  CHECK_FALSE(RevolutionSurface(std::make_shared<const CircularArc>(Point3(2, 0, 0), 1.0, -1.0, 1.0), 2 * pi).affine_area_in_u());
  CHECK(RevolutionSurface(std::make_shared<const ReversedCurve>(straight), 2 * pi).affine_area_in_u());
}

TEST_CASE("bounds of turned curved solids hold every surface point and are tight", "[brep][curved]") {
  // bounds() samples each edge and face, then refines only the extremes that may reach past every
  // sample: the box must still be the solid's (each model's box in closed form), and a dense
  // sampling of its faces lies inside it.
  auto dense_check = [](const Model& m, const Box3& b) {
    Box3 seen;
    for (FaceId f : m.faces().ids()) {
      const FaceSurface& fs = m.surface(f);
      if (!fs.parametric) continue;
      const auto [u0, u1] = fs.surface->u_domain();
      const auto [v0, v1] = fs.surface->v_domain();
      for (int i = 0; i <= 97; ++i)
        for (int j = 0; j <= 97; ++j) seen.extend(fs.surface->eval(u0 + (u1 - u0) * i / 97, v0 + (v1 - v0) * j / 97));
    }
    for (int k = 0; k < 3; ++k) {
      INFO("axis " << k);
      CHECK(seen.min[k] >= b.min[k] - 1e-12);
      CHECK(seen.max[k] <= b.max[k] + 1e-12);
    }
  };
  SECTION("a sphere turned 10 degrees about z") {
    Model m = sphere(5, Point3(1, 2, 3));
    m.transform(rotate(10, Vec3(0, 0, 1), Point3(0, 0, 0)));
    const Box3 b = m.bounds();
    const Point3 c = rotate(10, Vec3(0, 0, 1), Point3(0, 0, 0)).block<3, 3>(0, 0) * Point3(1, 2, 3);
    for (int k = 0; k < 3; ++k) {
      CHECK(b.min[k] == Approx(c[k] - 5).margin(1e-9));
      CHECK(b.max[k] == Approx(c[k] + 5).margin(1e-9));
    }
    dense_check(m, b);
  }
  SECTION("a torus turned about a skew axis") {
    Model m = torus(2, 0.5);
    const Vec3 axis = Vec3(1, 2, 3).normalized();
    m.transform(rotate(37, axis));
    const Box3 b = m.bounds();
    const Vec3 a = rotate(37, axis).block<3, 3>(0, 0) * Vec3(0, 0, 1);  // the torus's axis, turned
    for (int k = 0; k < 3; ++k) {
      const double half = 2 * std::sqrt(1 - a[k] * a[k]) + 0.5;
      CHECK(b.min[k] == Approx(-half).margin(1e-9));
      CHECK(b.max[k] == Approx(half).margin(1e-9));
    }
    dense_check(m, b);
  }
  SECTION("a revolve of a wavy profile of 400 points, turned") {
    std::vector<Vec2> p;
    for (int i = 0; i < 400; ++i) {
      const double t = 2 * pi * i / 400, r = 1 + 0.1 * std::sin(17 * t);
      p.emplace_back(3 + r * std::cos(t), r * std::sin(t));
    }
    Model m = revolve(section_of({p, {}}), 2 * pi);
    const Mat4 turn = rotate(23, Vec3(1, 1, 0));
    m.transform(turn);
    const Box3 b = m.bounds();
    // A profile point at radius x, height y sweeps a circle about the turned axis a: along axis k
    // it reaches y a_k +- x sqrt(1 - a_k^2); along a straight piece that is linear, so the box is
    // the points' extremes.
    const Vec3 a = turn.block<3, 3>(0, 0) * Vec3(0, 0, 1);
    for (int k = 0; k < 3; ++k) {
      double lo = INFINITY, hi = -INFINITY;
      for (const Vec2& q : p) {
        const double off = q.x() * std::sqrt(1 - a[k] * a[k]);
        lo = std::min(lo, q.y() * a[k] - off), hi = std::max(hi, q.y() * a[k] + off);
      }
      CHECK(b.min[k] == Approx(lo).margin(1e-9));
      CHECK(b.max[k] == Approx(hi).margin(1e-9));
    }
    dense_check(m, b);
  }
}
