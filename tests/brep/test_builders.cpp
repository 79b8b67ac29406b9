// The curved builders (extrude with twist and scale, revolve, sweep, loft): each result is valid,
// has the counts of brep.h's one convention (worked out by hand below), and its exact mass
// properties agree with closed forms: the prismatoid formula, Pappus's theorems, the swept volume
// A * L of a section whose centroid rides on the path, and the integral of a hand-solved natural
// cubic spline.
#include <catch2/catch.hpp>

#include <cmath>

#include "brep/brep.h"

using namespace wedge;

namespace {
constexpr double pi = 3.14159265358979323846;

Section square(double side) {
  double a = side / 2;
  return section_of(Profile{{{-a, -a}, {a, -a}, {a, a}, {-a, a}}, {}});
}
Section rect_section(double x0, double y0, double x1, double y1) {
  return section_of(Profile{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {}});
}
Section disc(double r, const Vec2& c = Vec2::Zero()) { return Section{circle_loop(c, r), {}}; }

void check_valid(const Model& m, const EulerCounts& expected) {
  Validation v = m.validate();
  INFO(v.message);
  REQUIRE(v.ok);
  CHECK(m.counts() == expected);
  CHECK(m.counts().characteristic() == 0);
}
}  // namespace

TEST_CASE("twisted extrusion keeps the cross-section area: the prism's volume, exactly", "[brep][curved][extrude]") {
  // Every z-section of a twisted extrusion is the profile turned: area A at every height.
  Model m = extrude(square(2), 3, radians(90));
  check_valid(m, EulerCounts{8, 12, 6, 0, 0, 1});  // a box's counts: 4 helicoidal sides, 2 caps
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(4 * 3).epsilon(1e-9));
  CHECK((mp.centroid - Point3(0, 0, 1.5)).norm() < 1e-9);
  // Izz: every section is a square of side 2 turned about its centre: A (a^2 + a^2) / 12 per
  // unit height, Izz = h * 4 * 8 / 12.
  CHECK(mp.inertia(2, 2) == Approx(3 * 4 * 8.0 / 12).epsilon(1e-9));

  // A disc twisted is still the cylinder (its sides are two helicoidal halves of one cylinder).
  Model c = extrude(disc(1), 2, radians(270));
  check_valid(c, EulerCounts{4, 6, 4, 0, 0, 1});
  CHECK(c.mass_properties().volume == Approx(2 * pi).epsilon(1e-9));
  CHECK(c.mass_properties().area == Approx(2 * pi + 4 * pi).epsilon(1e-9));
}

TEST_CASE("scaled extrusion is the frustum: V = h A (1 + k + k^2) / 3, with or without twist", "[brep][curved][extrude]") {
  double h = 2, k = 0.5, A = 4;
  for (double twist : {0.0, radians(60)}) {
    INFO("twist " << twist);
    Model m = extrude(square(2), h, twist, k);
    check_valid(m, EulerCounts{8, 12, 6, 0, 0, 1});
    MassProperties mp = m.mass_properties();
    CHECK(mp.volume == Approx(h * A * (1 + k + k * k) / 3).epsilon(1e-9));
    // Centroid of a frustum of areas A1, A2: z = h (A1 + 2 sqrt(A1 A2) + 3 A2) / (4 (A1 + sqrt(A1 A2) + A2)).
    double A2 = A * k * k, s = std::sqrt(A * A2);
    CHECK(mp.centroid.z() == Approx(h * (A + 2 * s + 3 * A2) / (4 * (A + s + A2))).epsilon(1e-9));
  }
  // Scale 0: a pyramid with its apex on the axis: V 5, E 8, F 5.
  Model p = extrude(square(2), 3, 0, 0);
  check_valid(p, EulerCounts{5, 8, 5, 0, 0, 1});
  CHECK(p.mass_properties().volume == Approx(4.0 * 3 / 3).epsilon(1e-9));
  CHECK(p.mass_properties().centroid.z() == Approx(3.0 / 4).epsilon(1e-9));
  // A section with a hole, scaled: both loops shrink, the hole stays a hole.
  Section holed{section_of(Profile{{{-2, -2}, {2, -2}, {2, 2}, {-2, 2}}, {}}).outer, {circle_loop(Vec2::Zero(), 1)}};
  Model t = extrude(holed, 1, 0, 0.5);
  check_valid(t, EulerCounts{4 * 2 + 2 * 2, 4 * 3 + 2 * 3, 4 + 2 + 2, 2, 1, 1});
  CHECK(t.mass_properties().volume == Approx((16 - pi) * (1 + 0.5 + 0.25) / 3).epsilon(1e-9));
}

TEST_CASE("full revolve: a ring of genus 1 whose volume and area follow Pappus", "[brep][curved][revolve]") {
  // The rectangle [1, 2] x [0, 1.5]: area 1.5 with centroid at radius 1.5; perimeter 5 with its
  // centroid at radius 1.5.
  Model m = revolve(rect_section(1, 0, 2, 1.5), 2 * pi);
  // Per profile vertex two vertices (start and half-way) and two edges; per piece one seam edge
  // and one face.
  check_valid(m, EulerCounts{8, 12, 4, 0, 1, 1});
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(2 * pi * 1.5 * 1.5).epsilon(1e-9));
  CHECK(mp.area == Approx(2 * pi * 1.5 * 5).epsilon(1e-9));
  CHECK((mp.centroid - Point3(0, 0, 0.75)).norm() < 1e-9);
  // Izz of the annular tube: pi h (R^4 - r^4) / 2.
  CHECK(mp.inertia(2, 2) == Approx(pi * 1.5 * (16 - 1) / 2).epsilon(1e-9));
}

TEST_CASE("partial revolve gets planar end caps, Pappus on the swept fraction", "[brep][curved][revolve]") {
  double angle = radians(90);
  Model m = revolve(rect_section(1, 0, 2, 1.5), angle);
  check_valid(m, EulerCounts{8, 12, 6, 0, 0, 1});
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(angle * 1.5 * 1.5).epsilon(1e-9));
  CHECK(mp.area == Approx(2 * 1.5 + angle * 1.5 * 5).epsilon(1e-9));
  // The centroid of an annular sector of angle a: radius (2 sin(a/2) / a) * (2/3)(R^3 - r^3)/(R^2 - r^2),
  // on the bisector at 45 degrees.
  double rc = 2 * std::sin(angle / 2) / angle * (2.0 / 3) * (8 - 1) / (4 - 1);
  CHECK(mp.centroid.x() == Approx(rc / std::sqrt(2.0)).epsilon(1e-9));
  CHECK(mp.centroid.y() == Approx(rc / std::sqrt(2.0)).epsilon(1e-9));
}

TEST_CASE("a profile touching the axis revolves to poles, not degenerate faces", "[brep][curved][revolve]") {
  // The triangle (0,0), (1,0), (0,1): a cone. The piece on the axis gives no face, its ends are
  // poles (one vertex each, no strut edge).
  Section tri = section_of(Profile{{{0, 0}, {1, 0}, {0, 1}}, {}});
  Model full = revolve(tri, 2 * pi);
  // Poles 2, the off-axis corner 2; struts 2, seams 2; faces 2 (base disc, cone).
  check_valid(full, EulerCounts{4, 4, 2, 0, 0, 1});
  CHECK(full.mass_properties().volume == Approx(pi / 3).epsilon(1e-9));
  CHECK(full.mass_properties().area == Approx(pi + pi * std::sqrt(2.0)).epsilon(1e-9));
  // Half a turn: two triangular caps; the axis piece is one edge shared by the caps.
  Model half = revolve(tri, pi);
  check_valid(half, EulerCounts{4, 6, 4, 0, 0, 1});
  CHECK(half.mass_properties().volume == Approx(pi / 6).epsilon(1e-9));
  CHECK(half.mass_properties().area == Approx((pi + pi * std::sqrt(2.0)) / 2 + 1).epsilon(1e-9));
  // A half disc on the axis revolves to the sphere (two poles, one seam).
  Section half_disc{{std::make_shared<const CircularArc>(Point3::Zero(), 1.5, -pi / 2, pi / 2),
                     std::make_shared<const LineSegment>(Point3(0, 1.5, 0), Point3(0, -1.5, 0))},
                    {}};
  Model s = revolve(half_disc, 2 * pi);
  check_valid(s, EulerCounts{2, 1, 1, 0, 0, 1});
  CHECK(s.mass_properties().volume == Approx(4.0 / 3 * pi * 1.5 * 1.5 * 1.5).epsilon(1e-12));
}

TEST_CASE("a profile with a hole revolves to nested rings: a ring with a ring-shaped cavity", "[brep][curved][revolve]") {
  // A square [1, 3] x [-1, 1] with a disc hole of radius 0.5 at (2, 0): Pappus with area
  // 4 - pi/4 whose centroid is at radius 2. The hole sweeps a closed torus inside: two shells of
  // genus 1 (outer: V 8 E 12 F 4; cavity: V 4 E 6 F 2).
  Section s{rect_section(1, -1, 3, 1).outer, {circle_loop(Vec2(2, 0), 0.5)}};
  Model m = revolve(s, 2 * pi);
  check_valid(m, EulerCounts{12, 18, 6, 0, 2, 2});
  CHECK(m.mass_properties().volume == Approx(2 * pi * 2 * (4 - pi / 4)).epsilon(1e-9));
  CHECK(m.mass_properties().area == Approx(2 * pi * 2 * (8 + pi)).epsilon(1e-9));
}

TEST_CASE("revolve refuses a profile across the axis and angles out of range", "[brep][curved][revolve][errors]") {
  CHECK_THROWS_WITH(revolve(rect_section(-1, 0, 1, 1), pi), Catch::Contains("x < 0"));
  CHECK_THROWS_WITH(revolve(rect_section(1, 0, 2, 1), 0), Catch::Contains("angle must be in (0, 360]"));
  CHECK_THROWS_WITH(revolve(rect_section(1, 0, 2, 1), 7), Catch::Contains("angle must be in (0, 360]"));
}

TEST_CASE("sweep along an open path: volume A L and lateral area P L for a centred section", "[brep][curved][sweep]") {
  // With rotation-minimising frames the volume element is (1 - k x) dA ds: the term in x vanishes
  // when the section's centroid is on the path, so V = A L; likewise the side area is P L when the
  // perimeter's centroid is on it.
  double r = 0.3, R = 2;
  auto arc = std::make_shared<const CircularArc>(Point3::Zero(), R, 0.0, pi / 2, Vec3::UnitY());
  Model m = sweep_along(disc(r), arc);
  check_valid(m, EulerCounts{4, 6, 4, 0, 0, 1});
  MassProperties mp = m.mass_properties();
  double L = R * pi / 2;
  CHECK(mp.volume == Approx(pi * r * r * L).epsilon(1e-7));
  CHECK(mp.area == Approx(2 * pi * r * L + 2 * pi * r * r).epsilon(1e-7));

  // A square along a space curve (a cubic Bezier): V = A L with L the path's length, computed
  // here by composite Simpson on |C'| (independent of the sweep).
  auto bez = std::make_shared<const BezierCurve>(std::vector<Point3>{{0, 0, 0}, {1, 0, 1}, {2, 1, 1}, {3, 1, 2}});
  double len = 0;
  int n = 2000;
  for (int i = 0; i <= n; ++i) {
    double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
    len += w * bez->derivative(double(i) / n, 1).norm();
  }
  len /= 3.0 * n;
  Model b = sweep_along(square(0.2), bez);
  check_valid(b, EulerCounts{8, 12, 6, 0, 0, 1});
  CHECK(b.mass_properties().volume == Approx(0.04 * len).epsilon(1e-6));
  CHECK(b.mass_properties().area == Approx(0.8 * len + 2 * 0.04).epsilon(1e-6));
}

TEST_CASE("sweep along a closed path is a ring of genus 1 (the torus for a circle)", "[brep][curved][sweep]") {
  double r = 0.5, R = 2;
  auto path = std::make_shared<const CircularArc>(Point3::Zero(), R, 0.0, 2 * pi);
  Model m = sweep_along(disc(r), path);
  check_valid(m, EulerCounts{4, 6, 2, 0, 1, 1});
  MassProperties mp = m.mass_properties();
  CHECK(mp.volume == Approx(2 * pi * pi * R * r * r).epsilon(1e-7));
  CHECK(mp.area == Approx(4 * pi * pi * R * r).epsilon(1e-7));
  CHECK(mp.centroid.norm() < 1e-7);
  // A square section around a closed, non-planar smooth path (a (2,3) torus-knot-like closed
  // B-spline would do; a tilted ellipse keeps the closed form): an ellipse's section centroid
  // rides on it, so V = A L.
  auto ellipse = std::make_shared<const NurbsCurve>(
      2,
      std::vector<Point3>{{3, 0, 0}, {3, 2, 1}, {0, 2, 1}, {-3, 2, 1}, {-3, 0, 0}, {-3, -2, -1}, {0, -2, -1}, {3, -2, -1}, {3, 0, 0}},
      std::vector<double>{0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1},
      std::vector<double>{1, std::sqrt(0.5), 1, std::sqrt(0.5), 1, std::sqrt(0.5), 1, std::sqrt(0.5), 1});
  double len = ellipse->length();
  Model e = sweep_along(square(0.4), ellipse);
  check_valid(e, EulerCounts{8, 12, 4, 0, 1, 1});
  CHECK(e.mass_properties().volume == Approx(0.16 * len).epsilon(1e-6));
}

TEST_CASE("a closed path with a corner where it closes is refused by name", "[brep][curved][sweep][errors]") {
  auto tri = std::make_shared<const NurbsCurve>(1, std::vector<Point3>{{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {0, 0, 0}},
                                                std::vector<double>{0, 0, 1, 2, 3, 3});
  CHECK_THROWS_WITH(sweep_along(disc(0.2), tri), Catch::Contains("smooth"));
}

TEST_CASE("loft: ruled between two sections, a natural cubic spline through three", "[brep][curved][loft]") {
  // Two squares of side 2 at z = 0 and side 1 at z = 2: the frustum, V = h (A1 + A2 + sqrt(A1 A2)) / 3.
  Model f = loft({square(2), square(1)}, {0, 2});
  check_valid(f, EulerCounts{8, 12, 6, 0, 0, 1});
  CHECK(f.mass_properties().volume == Approx(2.0 * (4 + 1 + 2) / 3).epsilon(1e-9));
  // Circles of radius 1, 2, 1 at z = 0, 1, 2: the radius is the natural cubic spline through them,
  // r(t) = 1 + 1.5 t - 0.5 t^3 on [0, 1] and its mirror (solved by hand: r'' (0) = 0, r'(1) = 0 by
  // symmetry), so V = 2 pi int_0^1 r^2 dt = 2 pi (1 + 0.75 + 1/28 + 1.5 - 0.25 - 0.3).
  Model s = loft({disc(1), disc(2), disc(1)}, {0, 1, 2});
  check_valid(s, EulerCounts{4, 6, 4, 0, 0, 1});
  CHECK(s.mass_properties().volume == Approx(2 * pi * (2.7 + 1.0 / 28)).epsilon(1e-9));
  // Sections with holes loft hole to hole.
  Section a{square(4).outer, {circle_loop(Vec2::Zero(), 1)}}, b{square(4).outer, {circle_loop(Vec2::Zero(), 1)}};
  Model t = loft({a, b}, {0, 3});
  REQUIRE(t.validate().ok);
  CHECK(t.counts().H == 1);
  CHECK(t.mass_properties().volume == Approx(3 * (16 - pi)).epsilon(1e-9));
}

TEST_CASE("loft refuses mismatched sections by name", "[brep][curved][loft][errors]") {
  CHECK_THROWS_WITH(loft({square(2)}, {0}), Catch::Contains("at least two"));
  CHECK_THROWS_WITH(loft({square(2), disc(1)}, {0, 1}), Catch::Contains("pieces"));
  CHECK_THROWS_WITH(loft({square(2), square(1)}, {1, 0}), Catch::Contains("increase"));
}
