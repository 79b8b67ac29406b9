// Curves: basis properties, knot insertion and degree elevation leave the curve in place, exact
// conics, interpolation, Kochanek-Bartels vs Catmull-Rom, derivatives vs central differences, and
// the tessellation / arc length against known values.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "surfaces/surfaces.h"

using namespace wedge;

namespace {

double max_deviation(const Curve& a, const Curve& b, int samples = 1000) {
  auto [t0, t1] = a.domain();
  double worst = 0;
  for (int i = 0; i < samples; ++i) {
    double t = t0 + (t1 - t0) * i / (samples - 1);
    worst = std::max(worst, (a.eval(t) - b.eval(t)).norm());
  }
  return worst;
}

// Checks derivatives 1..kmax against central differences of the order below.
void check_derivatives(const Curve& c, int kmax, double tol) {
  auto [a, b] = c.domain();
  double h = 1e-5 * (b - a);
  for (int i = 1; i < 20; ++i) {
    double t = a + (b - a) * (i + 0.37) / 20.5;
    for (int k = 1; k <= kmax; ++k) {
      Vec3 fd = (c.derivative(t + h, k - 1) - c.derivative(t - h, k - 1)) / (2 * h);
      Vec3 d = c.derivative(t, k);
      INFO("t = " << t << ", k = " << k << ", analytic " << d.transpose() << ", numeric " << fd.transpose());
      CHECK((d - fd).norm() <= tol * (1 + d.norm()));
    }
  }
}

NurbsCurve sample_nurbs() {
  std::vector<Point3> P{{0, 0, 0}, {1, 2, 0}, {3, 3, 1}, {4, 0, 2}, {6, 1, 0}, {7, 3, -1}, {9, 0, 0}};
  std::vector<double> W{1, 0.5, 2, 1, 3, 0.7, 1};
  std::vector<double> U{0, 0, 0, 0, 0.2, 0.5, 0.5, 1, 1, 1, 1};
  return NurbsCurve(3, P, U, W);
}

}  // namespace

TEST_CASE("B-spline basis functions are non-negative and sum to one", "[basis]") {
  std::vector<double> U{0, 0, 0, 0, 0.1, 0.3, 0.3, 0.6, 0.9, 1, 1, 1, 1};
  int p = 3, n = int(U.size()) - p - 1;
  for (int i = 0; i <= 1000; ++i) {
    double u = i / 1000.0;
    int span = find_span(n, p, u, U);
    REQUIRE(U[span] <= u);
    REQUIRE((u < U[span + 1] || (u == 1 && span == n - 1)));
    double N[4];
    basis_functions(span, u, p, U, N);
    double sum = 0;
    for (double x : N) {
      CHECK(x >= 0);
      sum += x;
    }
    CHECK(sum == Approx(1).margin(1e-14));
    // The derivatives of a partition of unity sum to zero.
    auto ders = basis_derivatives(span, u, p, 2, U);
    CHECK(ders[1][0] + ders[1][1] + ders[1][2] + ders[1][3] == Approx(0).margin(1e-10));
    for (int j = 0; j <= p; ++j) CHECK(ders[0][j] == Approx(N[j]).margin(1e-15));
  }
}

TEST_CASE("knot vectors and weights are checked, with the reason in words", "[basis]") {
  std::vector<Point3> P{{0, 0, 0}, {1, 1, 0}, {2, 0, 0}, {3, 1, 0}};
  CHECK_THROWS_WITH(NurbsCurve(3, P, {0, 0, 0, 0, 1, 1, 1}), Catch::Contains("need 8 knots"));
  CHECK_THROWS_WITH(NurbsCurve(3, P, {0, 0, 0, 0, 1, 1, 0.5, 1}), Catch::Contains("non-decreasing"));
  CHECK_THROWS_WITH(NurbsCurve(4, P, {0, 0, 0, 0, 0, 1, 1, 1, 1}), Catch::Contains("at least 5 control points"));
  CHECK_THROWS_WITH(NurbsCurve(3, P, {0, 0, 0, 0, 1, 1, 1, 1}, {1, 0, 1, 1}), Catch::Contains("weight 2"));
  CHECK_THROWS_WITH(NurbsCurve(3, P, {0, 0, 0, 0, 1, 1, 1, 1}, {1, -1, 1, 1}), Catch::Contains("positive"));
  double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(NurbsCurve(3, P, {0, 0, 0, 0, nan, 1, 1, 1}), Catch::Contains("knot 5"));
  CHECK_THROWS_WITH(NurbsCurve(1, P, {0, 0, 0.5, 0.5, 0.5, 1}), Catch::Contains("appears 3 times"));
  std::vector<Point3> bad = P;
  bad[2].x() = nan;
  CHECK_THROWS_WITH(NurbsCurve(3, bad, {0, 0, 0, 0, 1, 1, 1, 1}), Catch::Contains("point 3"));
  CHECK_THROWS_AS(BezierCurve({{0, 0, 0}}), Error);
}

TEST_CASE("knot insertion leaves the curve unchanged", "[nurbs]") {
  NurbsCurve c = sample_nurbs();
  NurbsCurve d = c.with_knot(0.37).with_knot(0.5).with_knot(0.8, 3);
  CHECK(d.control_points().size() == c.control_points().size() + 5);  // 0.5 was already double
  CHECK(max_deviation(c, d) < 1e-12);
  // Unclamped uniform knots, inserting at the ends of the domain too.
  std::vector<Point3> P{{0, 0, 0}, {1, 2, 0}, {3, 3, 1}, {4, 0, 2}, {6, 1, 0}};
  NurbsCurve u(3, P, uniform_knots(3, P.size()));
  NurbsCurve v = u.with_knot(3, 3).with_knot(5, 3).with_knot(4.5, 2);
  CHECK(max_deviation(u, v) < 1e-12);
}

TEST_CASE("knot removal undoes knot insertion", "[nurbs]") {
  NurbsCurve c = sample_nurbs();
  NurbsCurve d = c.with_knot(0.37, 2).without_knot(0.37, 2);
  REQUIRE(d.knots() == c.knots());
  for (std::size_t i = 0; i < c.control_points().size(); ++i) {
    CHECK((d.control_points()[i] - c.control_points()[i]).norm() < 1e-12);
    CHECK(d.weights()[i] == Approx(c.weights()[i]).epsilon(1e-12));
  }
  // A knot the curve needs (its C1 break at 0.5) cannot be removed: the curve stays as it was.
  NurbsCurve kept = c.without_knot(0.5, 1);
  CHECK(kept.knots() == c.knots());
  CHECK(max_deviation(c, kept) < 1e-14);
}

TEST_CASE("degree elevation leaves the curve unchanged", "[nurbs]") {
  NurbsCurve c = sample_nurbs();
  NurbsCurve e = c.elevated();
  CHECK(e.degree() == 4);
  // The NURBS Book's count: n + (distinct interior knots + 1) new control points (0.2 and 0.5 here),
  // and each interior knot's multiplicity grows by one.
  CHECK(e.control_points().size() == c.control_points().size() + 3);
  CHECK(std::count(e.knots().begin(), e.knots().end(), 0.5) == 3);
  CHECK(std::count(e.knots().begin(), e.knots().end(), 0.2) == 2);
  CHECK(max_deviation(c, e) < 1e-12);
  NurbsCurve e2 = e.elevated();
  CHECK(e2.degree() == 5);
  CHECK(max_deviation(c, e2) < 1e-12);
  std::vector<Point3> P{{0, 0, 0}, {1, 2, 0}, {3, 3, 1}, {4, 0, 2}, {6, 1, 0}};
  NurbsCurve u(2, P, uniform_knots(2, P.size()));
  CHECK(max_deviation(u, u.elevated()) < 1e-12);
}

TEST_CASE("Bezier: de Casteljau, subdivision and elevation", "[bezier]") {
  BezierCurve b({{0, 0, 0}, {1, 3, 0}, {3, -1, 1}, {4, 2, 0}, {5, 0, 0}});
  CHECK(max_deviation(b, b.elevated()) < 1e-12);
  CHECK(max_deviation(b, to_nurbs(b)) < 1e-12);
  auto [l, r] = b.subdivide(0.3);
  for (int i = 0; i <= 100; ++i) {
    double s = i / 100.0;
    CHECK((l.eval(s) - b.eval(0.3 * s)).norm() < 1e-13);
    CHECK((r.eval(s) - b.eval(0.3 + 0.7 * s)).norm() < 1e-13);
  }
  // A cubic Bezier by the Bernstein formula.
  BezierCurve c({{0, 0, 0}, {1, 2, 0}, {3, 2, 0}, {4, 0, 0}});
  double t = 0.4, s = 1 - t;
  Point3 expect = s * s * s * Point3(0, 0, 0) + 3 * s * s * t * Point3(1, 2, 0) + 3 * s * t * t * Point3(3, 2, 0) +
                  t * t * t * Point3(4, 0, 0);
  CHECK((c.eval(t) - expect).norm() < 1e-15);
  check_derivatives(b, 5, 1e-6);
  CHECK(b.derivative(0.5, 5).norm() == 0);
}

TEST_CASE("the NURBS circle is exact", "[conics]") {
  for (double r : {1.0, 0.001, 7.5}) {
    NurbsCurve c = nurbs_circle(Point3(0, 0, 0), r);
    CHECK(c.closed());
    for (int i = 0; i <= 1000; ++i) {
      Point3 p = c.eval(i / 1000.0);
      CHECK(std::abs(p.norm() - r) <= 1e-14 * std::max(1.0, r));
      CHECK(p.z() == 0);
    }
  }
  NurbsCurve off = nurbs_circle(Point3(1, 2, 3), 2.0, Vec3(1, 1, 1));
  for (int i = 0; i <= 200; ++i) {
    Point3 p = off.eval(i / 200.0);
    CHECK(std::abs((p - Point3(1, 2, 3)).norm() - 2) < 1e-14 * 4);
    CHECK(std::abs((p - Point3(1, 2, 3)).dot(Vec3(1, 1, 1))) < 1e-13);
  }
  // Arcs of odd angles: within the radius and ending at the right angle.
  for (double deg : {30.0, 90.0, 135.0, 270.0, 359.0}) {
    NurbsCurve a = nurbs_arc(Point3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 3, 0, radians(deg));
    Point3 e = a.eval(1);
    CHECK((e - Point3(3 * std::cos(radians(deg)), 3 * std::sin(radians(deg)), 0)).norm() < 1e-14 * 3);
    for (int i = 0; i <= 100; ++i) CHECK(std::abs(a.eval(i / 100.0).norm() - 3) < 4e-15 * 3);
  }
  NurbsCurve el = nurbs_ellipse(Point3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY(), 3, 1);
  for (int i = 0; i <= 200; ++i) {
    Point3 p = el.eval(i / 200.0);
    CHECK(p.x() * p.x() / 9 + p.y() * p.y() == Approx(1).epsilon(1e-14));
  }
  CHECK_THROWS_WITH(nurbs_circle(Point3(0, 0, 0), -1), Catch::Contains("radius"));
}

TEST_CASE("rational derivatives agree with central differences", "[nurbs]") {
  check_derivatives(sample_nurbs(), 3, 1e-5);
  check_derivatives(nurbs_circle(Point3(0, 0, 0), 2), 3, 1e-5);
  check_derivatives(CircularArc(Point3(1, 0, 0), 2, 0.1, 3.0, Vec3(0, 1, 1)), 3, 1e-6);
  // The derivative of the circle is perpendicular to its radius.
  NurbsCurve c = nurbs_circle(Point3(0, 0, 0), 2);
  for (int i = 0; i < 50; ++i) {
    double t = i / 50.0;
    CHECK(std::abs(c.eval(t).dot(c.derivative(t, 1))) < 1e-12 * c.derivative(t, 1).norm());
  }
}

TEST_CASE("interpolating splines pass through their points", "[interpolation]") {
  std::vector<Point3> Q{{0, 0, 0}, {1, 2, 0}, {2, 2.5, 1}, {4, 0, 1}, {5, -1, 0}, {7, 1, 2}};
  SECTION("global NURBS interpolation") {
    for (int p : {1, 2, 3, 5}) {
      NurbsCurve c = interpolate_nurbs(Q, p);
      double total = 0;
      std::vector<double> t{0};
      for (std::size_t i = 1; i < Q.size(); ++i) t.push_back(total += (Q[i] - Q[i - 1]).norm());
      for (std::size_t i = 0; i < Q.size(); ++i) CHECK((c.eval(t[i] / total) - Q[i]).norm() < 1e-12);
    }
    CHECK_THROWS_WITH(interpolate_nurbs({{0, 0, 0}, {1, 1, 1}}, 3), Catch::Contains("at least 4 points"));
    std::vector<Point3> many;
    for (int i = 0; i < 45; ++i) many.emplace_back(i, std::sin(0.3 * i), 0);
    CHECK_THROWS_WITH(interpolate_nurbs(many, 40), Catch::Contains("degree must be at most 30, got 40"));
  }
  SECTION("natural cubic spline: through the points, C2, zero curvature at the ends") {
    HermiteSpline s = natural_spline(Q);
    const auto& t = s.params();
    for (std::size_t i = 0; i < Q.size(); ++i) CHECK((s.eval(t[i]) - Q[i]).norm() < 1e-12);
    for (std::size_t i = 1; i + 1 < Q.size(); ++i) {
      double e = 1e-9;
      CHECK((s.derivative(t[i] - e, 2) - s.derivative(t[i] + e, 2)).norm() < 1e-6);
      CHECK((s.derivative(t[i] - e, 1) - s.derivative(t[i] + e, 1)).norm() < 1e-6);
    }
    CHECK(s.derivative(t.front(), 2).norm() < 1e-12);
    CHECK(s.derivative(t.back(), 2).norm() < 1e-12);
    check_derivatives(s, 3, 1e-5);
    CHECK(max_deviation(s, s.to_nurbs()) < 1e-12);
  }
  SECTION("polynomial interpolation") {
    PolynomialInterpolant p(Q);
    for (std::size_t i = 0; i < Q.size(); ++i) CHECK((p.eval(double(i) / (Q.size() - 1)) - Q[i]).norm() < 1e-12);
    check_derivatives(p, 3, 1e-5);
    // Degree k-1 reproduces a polynomial of that degree exactly.
    std::vector<Point3> cubic;
    for (int i = 0; i < 4; ++i) {
      double x = i / 3.0;
      cubic.emplace_back(x, x * x * x - x, 0);
    }
    PolynomialInterpolant q(cubic);
    CHECK(q.eval(0.5).y() == Approx(0.125 - 0.5).margin(1e-14));
    CHECK(q.derivative(0.5, 3).y() == Approx(6).margin(1e-9));
  }
  SECTION("Catmull-Rom and Kochanek-Bartels, open and closed") {
    for (bool closed : {false, true}) {
      HermiteSpline kb = kochanek_bartels(Q, 0.3, -0.2, 0.4, closed);
      for (std::size_t i = 0; i < Q.size(); ++i) CHECK((kb.eval(double(i)) - Q[i]).norm() < 1e-12);
      if (closed) CHECK((kb.eval(double(Q.size())) - Q[0]).norm() < 1e-12);
      CHECK(kb.closed() == closed);
      check_derivatives(kb, 3, 1e-5);
      CHECK(max_deviation(kb, kb.to_nurbs()) < 1e-12);
    }
  }
}

TEST_CASE("Kochanek-Bartels with t = b = c = 0 is Catmull-Rom", "[interpolation]") {
  std::vector<Point3> Q{{0, 0, 0}, {1, 2, 0}, {2, 2.5, 1}, {4, 0, 1}, {5, -1, 0}, {7, 1, 2}};
  HermiteSpline kb = kochanek_bartels(Q, 0, 0, 0, false);
  HermiteSpline cr = catmull_rom(Q, false);
  // Catmull-Rom's classic matrix form on the interior segments (catmull_rom is checked against it
  // on every segment in test_kochanek_bartels.cpp).
  for (std::size_t i = 1; i + 2 < Q.size(); ++i)
    for (int j = 0; j <= 10; ++j) {
      double s = j / 10.0, s2 = s * s, s3 = s2 * s;
      Point3 expect = 0.5 * ((2 * Q[i]) + (-Q[i - 1] + Q[i + 1]) * s + (2 * Q[i - 1] - 5 * Q[i] + 4 * Q[i + 1] - Q[i + 2]) * s2 +
                             (-Q[i - 1] + 3 * Q[i] - 3 * Q[i + 1] + Q[i + 2]) * s3);
      CHECK((kb.eval(i + s) - expect).norm() < 1e-13);
    }
  // Continuity 0 keeps the tangent continuous at the points; continuity != 0 breaks it there.
  HermiteSpline kinked = kochanek_bartels(Q, 0, 0, 0.5);
  double e = 1e-9;
  CHECK((cr.derivative(2 - e, 1) - cr.derivative(2 + e, 1)).norm() < 1e-6);
  CHECK((kinked.derivative(2 - e, 1) - kinked.derivative(2 + e, 1)).norm() > 0.1);
  // Tension 1 gives zero tangents at the points.
  HermiteSpline tight = kochanek_bartels(Q, 1, 0, 0);
  CHECK(tight.derivative(2, 1).norm() < 1e-14);
}

TEST_CASE("tessellation stays within the chordal tolerance, arc length", "[tessellation]") {
  NurbsCurve c = nurbs_circle(Point3(0, 0, 0), 1);
  CHECK(c.length() == Approx(2 * kPi).epsilon(1e-12));
  CHECK(CircularArc(Point3(0, 0, 0), 2, 0, kPi).length() == Approx(2 * kPi).epsilon(1e-12));
  CHECK(LineSegment(Point3(0, 0, 0), Point3(3, 4, 0)).length() == Approx(5).epsilon(1e-14));
  for (double tol : {0.1, 0.01, 0.001}) {
    std::vector<double> ts = c.parameters(tol);
    std::vector<Point3> ps = c.points(tol);
    REQUIRE(ps.size() == ts.size());
    // For a unit circle, a chord of angle a deviates 1 - cos(a/2): the coarsest chord that fits.
    double worst = 0;
    for (std::size_t i = 0; i + 1 < ps.size(); ++i) {
      Point3 m = 0.5 * (ps[i] + ps[i + 1]);
      worst = std::max(worst, 1 - m.norm());
      for (int j = 1; j < 20; ++j) {
        Point3 q = c.eval(ts[i] + (ts[i + 1] - ts[i]) * j / 20.0);
        Vec3 ab = ps[i + 1] - ps[i];
        double s = std::clamp((q - ps[i]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        worst = std::max(worst, (q - (ps[i] + s * ab)).norm());
      }
    }
    CHECK(worst <= tol);
    CHECK(ps.size() < 4 * std::ceil(kPi / std::acos(1 - tol)) + 20);  // not absurdly fine
  }
  CHECK_THROWS_WITH(c.points(0), Catch::Contains("tolerance"));
}

TEST_CASE("high-degree polynomial interpolation oscillates where a cubic spline does not (Runge)", "[interpolation]") {
  // Runge's function 1 / (1 + 25 x^2) sampled at 15 uniform points on [-1, 1].
  auto f = [](double x) { return 1 / (1 + 25 * x * x); };
  std::vector<Point3> Q;
  for (int i = 0; i < 15; ++i) {
    double x = -1 + 2.0 * i / 14;
    Q.emplace_back(x, f(x), 0);
  }
  PolynomialInterpolant poly(Q);
  NurbsCurve spline = interpolate_nurbs(Q, 3);
  double poly_err = 0, spline_err = 0;
  for (int i = 0; i <= 2000; ++i) {
    double t = i / 2000.0;
    Point3 p = poly.eval(t);  // uniform parameters: x = -1 + 2 t
    poly_err = std::max(poly_err, std::abs(p.y() - f(p.x())));
    Point3 s = spline.eval(t);
    spline_err = std::max(spline_err, std::abs(s.y() - f(s.x())));
  }
  CHECK(poly_err > 1.0);
  CHECK(spline_err < 0.05);
}

TEST_CASE("arc length answers quickly on extreme curves, and overflow is an error", "[curves][extreme]") {
  // A parabola-like Bezier at 1e200: the length scales exactly with the coordinates, so it is
  // 1e200 times the unit curve's (computed at ordinary size), to quadrature accuracy. Before, the
  // squares of the derivative overflowed and adaptive quadrature recursed 2^30 times.
  BezierCurve unit({{0, 0, 0}, {1, 1, 0}, {2, 0, 0}});
  BezierCurve huge({{0, 0, 0}, {1e200, 1e200, 0}, {2e200, 0, 0}});
  // The unit curve's length in closed form: |C'(t)| = 2 sqrt(1 + (1 - 2t)^2).
  const double s = std::sqrt(2.0);
  const double unit_length = s + std::log(1 + s);  // = integral of sqrt(1 + u^2) over [-1, 1] = sqrt2 + asinh 1
  CHECK(unit.length() == Approx(unit_length).epsilon(1e-12));
  CHECK(huge.length() == Approx(1e200 * unit_length).epsilon(1e-9));
  BezierCurve overflow({{0, 0, 0}, {1e308, 1e308, 0}, {-1e308, 1e308, 0}, {1e308, 0, 0}});
  CHECK_THROWS_WITH(overflow.length(), Catch::Contains("length overflows"));
}

TEST_CASE("Kochanek-Bartels parameters outside -1..1 are refused by name", "[curves][extreme]") {
  std::vector<Point3> Q = {{0, 0, 0}, {1, 1, 0}, {2, 0, 0}};
  CHECK_THROWS_WITH(kochanek_bartels(Q, 1e300, 0, 0), Catch::Contains("tension must be within -1..1"));
  CHECK_THROWS_WITH(kochanek_bartels(Q, 0, -2, 0), Catch::Contains("bias must be within -1..1 (Kochanek-Bartels), got -2"));
  CHECK_THROWS_WITH(kochanek_bartels(Q, 0, 0, std::nan("")), Catch::Contains("continuity must be a finite number"));
  CHECK(kochanek_bartels(Q, 1, -1, 1).length() > 0);
}
