#include <catch2/catch.hpp>

#include <cmath>

#include "kernel/kernel.h"

using namespace wedge;

namespace {
template <class A, class B>
bool near(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b, double tol) {
  return (a - b).cwiseAbs().maxCoeff() <= tol;
}
}  // namespace

TEST_CASE("translate moves points but not vectors", "[transform]") {
  Mat4 t = translate({1, 2, 3});
  CHECK(apply_point(t, {1, 1, 1}) == Vec3(2, 3, 4));
  CHECK(apply_vector(t, {1, 1, 1}) == Vec3(1, 1, 1));
}

TEST_CASE("rotations about the axes match hand-worked values", "[transform]") {
  CHECK(apply_point(rotate_z(90), {1, 0, 0}) == Vec3(0, 1, 0));   // exact at multiples of 90
  CHECK(apply_point(rotate_x(90), {0, 1, 0}) == Vec3(0, 0, 1));
  CHECK(apply_point(rotate_y(90), {0, 0, 1}) == Vec3(1, 0, 0));
  Vec3 p = apply_point(rotate_z(30), {1, 0, 0});
  CHECK(near(p, Vec3(std::sqrt(3.0) / 2, 0.5, 0), 1e-15));
  // About an arbitrary axis: 120 degrees about (1,1,1) cycles the axes.
  CHECK(near(apply_point(rotate(120, {1, 1, 1}), {1, 0, 0}), Vec3(0, 1, 0), 1e-15));
  // The general formula agrees with the axis-specific matrices.
  CHECK(near(rotate(37, {0, 0, 1}), rotate_z(37), 1e-15));
  CHECK(near(rotate(-51, {2, 0, 0}), rotate_x(-51), 1e-15));
  CHECK(near(rotate(200, {0, 5, 0}), rotate_y(200), 1e-15));
}

TEST_CASE("rotating 30 degrees about z through the pivot (1,2,3) is T(p) Rz T(-p) and fixes the pivot", "[transform]") {
  Vec3 pivot(1, 2, 3);
  Mat4 r = rotate(30, {0, 0, 1}, pivot);
  Mat4 expected = translate({1, 2, 3}) * rotate_z(30) * translate({-1, -2, -3});
  CHECK(near(r, expected, 1e-15));
  CHECK(near(apply_point(r, pivot), pivot, 1e-15));
  // A point one unit along x from the pivot swings to angle 30 degrees around it.
  Vec3 q = apply_point(r, pivot + Vec3(1, 0, 0));
  CHECK(near(q, pivot + Vec3(std::cos(radians(30)), std::sin(radians(30)), 0), 1e-15));
  // Hand-worked entries of the matrix: translation column = p - R p.
  double c = std::sqrt(3.0) / 2, s = 0.5;
  CHECK(r(0, 3) == Approx(1 - (c * 1 - s * 2)).margin(1e-15));
  CHECK(r(1, 3) == Approx(2 - (s * 1 + c * 2)).margin(1e-15));
  CHECK(r(2, 3) == 0);
}

TEST_CASE("the 2D inverse of [[7,3],[2,1]] is [[1,-3],[-2,7]]", "[transform]") {
  Mat3 m = Mat3::Identity();
  m(0, 0) = 7; m(0, 1) = 3;
  m(1, 0) = 2; m(1, 1) = 1;
  Mat3 inv = inverse_2d(m);
  CHECK(inv(0, 0) == Approx(1).margin(1e-14));
  CHECK(inv(0, 1) == Approx(-3).margin(1e-14));
  CHECK(inv(1, 0) == Approx(-2).margin(1e-14));
  CHECK(inv(1, 1) == Approx(7).margin(1e-14));
  CHECK((m * inv - Mat3::Identity()).cwiseAbs().maxCoeff() <= 1e-12);
}

TEST_CASE("composition does not commute: rotation then translation differs from translation then rotation", "[transform]") {
  Mat4 r = rotate_z(90), t = translate({1, 0, 0});
  CHECK_FALSE(near(r * t, t * r, 1e-9));
  // R*T applies T first: (0,0,0) -> (1,0,0) -> (0,1,0); T*R: (0,0,0) -> (0,0,0) -> (1,0,0).
  CHECK(apply_point(r * t, {0, 0, 0}) == Vec3(0, 1, 0));
  CHECK(apply_point(t * r, {0, 0, 0}) == Vec3(1, 0, 0));
}

TEST_CASE("a matrix times its inverse is the identity within 1e-12", "[transform]") {
  Mat4 m = translate({3, -2, 7}) * rotate(33, {1, 2, 3}, {4, 5, 6}) * scale({2, 0.5, 3}) *
           shear({.xy = 0.3, .zx = -0.7});
  CHECK(near(m * inverse(m), Mat4::Identity(), 1e-12));
  CHECK(near(inverse(m) * m, Mat4::Identity(), 1e-12));
  CHECK(near(inverse(inverse(m)), m, 1e-12));
}

TEST_CASE("a singular matrix has no inverse and says so", "[transform]") {
  CHECK_THROWS_WITH(inverse(scale({1, 0, 1})), Catch::Contains("singular"));
}

TEST_CASE("scale about a fixed point leaves it fixed", "[transform]") {
  Mat4 s = scale({2, 3, 4}, {1, 1, 1});
  CHECK(apply_point(s, {1, 1, 1}) == Vec3(1, 1, 1));
  CHECK(apply_point(s, {2, 2, 2}) == Vec3(3, 4, 5));
}

TEST_CASE("reflect mirrors across a plane and reverses orientation", "[transform]") {
  Mat4 m = reflect({0, 0, 1}, {0, 0, 2});
  CHECK(near(apply_point(m, {1, 2, 3}), Vec3(1, 2, 1), 1e-15));
  CHECK(reverses_orientation(m));
  CHECK_FALSE(reverses_orientation(rotate(40, {1, 1, 0})));
  CHECK(near(m * m, Mat4::Identity(), 1e-15));
}

TEST_CASE("the six 3D shears", "[transform]") {
  Vec3 p(1, 2, 3);
  CHECK(apply_point(shear({.xy = 2}), p) == Vec3(1 + 4, 2, 3));
  CHECK(apply_point(shear({.xz = 2}), p) == Vec3(1 + 6, 2, 3));
  CHECK(apply_point(shear({.yx = 2}), p) == Vec3(1, 2 + 2, 3));
  CHECK(apply_point(shear({.yz = 2}), p) == Vec3(1, 2 + 6, 3));
  CHECK(apply_point(shear({.zx = 2}), p) == Vec3(1, 2, 3 + 2));
  CHECK(apply_point(shear({.zy = 2}), p) == Vec3(1, 2, 3 + 4));
}

TEST_CASE("the 2D shear x' = x + y cot(theta)", "[transform]") {
  Mat3 s = shear_x_2d(45);
  CHECK(apply_point_2d(s, {1, 2}).x() == Approx(3).margin(1e-14));
  CHECK(apply_point_2d(s, {1, 2}).y() == 2);
  Mat3 s60 = shear_x_2d(60);
  CHECK(apply_point_2d(s60, {0, 1}).x() == Approx(1 / std::sqrt(3.0)).margin(1e-15));
  CHECK_THROWS_WITH(shear_x_2d(0), Catch::Contains("multiple of 180"));
  CHECK_THROWS_WITH(shear_x_2d(180), Catch::Contains("multiple of 180"));
  CHECK_THROWS_WITH(shear_x_2d(-540), Catch::Contains("multiple of 180"));
}

TEST_CASE("a mirror about a plane through the diagonal swaps coordinates exactly", "[transform]") {
  // Through the rounded unit normal (0.7071..., 0.7071..., 0) the swap's entries were 1 - 2e-16,
  // and a centred cube minus its mirror image kept sliver shells of area 8.
  const Mat4 m = reflect({1, 1, 0});
  CHECK(m(0, 0) == 0);
  CHECK(m(0, 1) == -1);
  CHECK(m(1, 0) == -1);
  CHECK(m(1, 1) == 0);
  CHECK(m(2, 2) == 1);
  const Mat4 p = reflect({0, 3, 3}, {0, 1, 0});  // y <-> -z about the plane y + z = 1
  CHECK(p(1, 2) == -1);
  CHECK(p(2, 1) == -1);
  CHECK(p(1, 3) == 1);
  CHECK(p(2, 3) == 1);
  // Huge and tiny normals are directions all the same.
  CHECK(reflect({1e300, 1e300, 0}) == m);
  CHECK(reflect({5e-324, 5e-324, 0}) == m);
  CHECK_THROWS_WITH(reflect({0, 0, 0}), Catch::Contains("non-zero"));
}

TEST_CASE("2D rotation about a pivot and reflection", "[transform]") {
  Mat3 r = rotate_2d(90, {1, 1});
  CHECK(apply_point_2d(r, {1, 1}) == Vec2(1, 1));
  CHECK(apply_point_2d(r, {2, 1}) == Vec2(1, 2));
  Mat3 m = reflect_2d({1, 1});  // the line y = x swaps coordinates
  CHECK((apply_point_2d(m, {3, 5}) - Vec2(5, 3)).norm() < 1e-14);
}

TEST_CASE("Euler rotation is Rz Ry Rx", "[transform]") {
  CHECK(near(rotate_euler(10, 20, 30), rotate_z(30) * rotate_y(20) * rotate_x(10), 1e-15));
  // x applied first: (0,1,0) -> Rx(90) -> (0,0,1) -> Rz(90) leaves it.
  CHECK(near(apply_point(rotate_euler(90, 0, 90), {0, 1, 0}), Vec3(0, 0, 1), 1e-15));
}

TEST_CASE("normals transform by the inverse transpose", "[transform]") {
  // Non-uniform scale: the plane x + y = 1 becomes x/2 + y = 1, whose normal is (1, 2, 0)/|.|.
  Mat4 s = scale({2, 1, 1});
  Vec3 n = apply_normal(s, Vec3(1, 1, 0).normalized());
  CHECK(near(n, Vec3(1, 2, 0).normalized(), 1e-15));
  CHECK_FALSE(near(apply_vector(s, Vec3(1, 1, 0)).normalized(), n, 1e-3));
}

TEST_CASE("normals transform under far-from-unit scales and strong shears, and a mirror keeps them outward", "[transform]") {
  // The inverse transpose of a general matrix, against Eigen's inverse.
  Mat4 m = Mat4::Identity();
  m.block<3, 3>(0, 0) << 2, 0.3, -1, 0.5, 1, 0.2, -0.4, 0.7, 3;
  const Vec3 n = Vec3(0.3, -0.8, 0.5).normalized();
  const Mat3 inv_t = m.block<3, 3>(0, 0).inverse().transpose();
  CHECK(near(apply_normal(m, n), Vec3((inv_t * n).normalized()), 1e-15));
  // A shear of 1e8 (determinant 1) maps the plane y = 0 to itself, and the plane x = 0 to
  // x = 1e8 y. It was refused as a singular matrix.
  Mat4 shear = Mat4::Identity();
  shear(0, 1) = 1e8;
  CHECK(near(apply_normal(shear, Vec3(0, 1, 0)), Vec3(0, 1, 0), 1e-15));
  CHECK(near(apply_normal(shear, Vec3(1, 0, 0)), Vec3(1, -1e8, 0).normalized(), 1e-15));
  // Scales of 1e-120 and 1e120 (their determinants under- and overflow a double).
  CHECK(near(apply_normal(scale({1e-120, 1e-120, 1e-120}), n), n, 1e-15));
  CHECK(near(apply_normal(scale({1e120, 1e120, 1e120}), n), n, 1e-15));
  CHECK(near(apply_normal(scale({1e-200, 1, 1}), Vec3(1, 1, 0).normalized()), Vec3(1, 0, 0), 1e-15));
  // A mirror: the normal is mirrored with the surface (the inverse transpose of a reflection is
  // itself), not turned inward.
  CHECK(near(apply_normal(scale({-1, 1, 1}), Vec3(1, 0, 0)), Vec3(-1, 0, 0), 1e-15));
  CHECK(near(apply_normal(scale({-2, 1, 1}), n), Vec3((scale({-2, 1, 1}).block<3, 3>(0, 0).inverse().transpose() * n).normalized()), 1e-15));
  // Singular: refused.
  CHECK_THROWS_WITH(apply_normal(scale({1, 1, 0}), n), Catch::Contains("singular"));
  Mat4 flat = Mat4::Identity();
  flat.col(1) = flat.col(0);
  CHECK_THROWS_WITH(apply_normal(flat, n), Catch::Contains("singular"));
}

TEST_CASE("projection matrices have glFrustum / gluPerspective / glOrtho entries", "[transform]") {
  Mat4 f = frustum(-1, 1, -1, 1, 1, 10);
  CHECK(f(0, 0) == 1);
  CHECK(f(1, 1) == 1);
  CHECK(f(2, 2) == Approx(-11.0 / 9));
  CHECK(f(2, 3) == Approx(-20.0 / 9));
  CHECK(f(3, 2) == -1);
  CHECK(f(3, 3) == 0);
  // gluPerspective(90, 1, 1, 10) is glFrustum(-1, 1, -1, 1, 1, 10).
  CHECK(near(perspective(90, 1, 1, 10), f, 1e-15));
  // The near plane maps to NDC z = -1, the far plane to +1.
  CHECK(apply_point(f, {0, 0, -1}).z() == Approx(-1));
  CHECK(apply_point(f, {0, 0, -10}).z() == Approx(1));
  Mat4 o = ortho(0, 800, 0, 600, -1, 1);
  CHECK(near(apply_point(o, {800, 600, 0}), Vec3(1, 1, 0), 1e-15));
  CHECK(near(apply_point(o, {0, 0, 0}), Vec3(-1, -1, 0), 1e-15));
  CHECK(o(2, 2) == -1);
}

TEST_CASE("lookAt puts the eye at the origin looking down -z", "[transform]") {
  Mat4 v = look_at({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
  CHECK(near(v, translate({0, 0, -5}), 1e-15));
  Mat4 w = look_at({5, 5, 5}, {0, 0, 0}, {0, 0, 1});
  CHECK(near(apply_point(w, {5, 5, 5}), Vec3::Zero(), 1e-14));
  Vec3 c = apply_point(w, {0, 0, 0});
  CHECK(c.x() == Approx(0).margin(1e-14));
  CHECK(c.y() == Approx(0).margin(1e-14));
  CHECK(c.z() == Approx(-std::sqrt(75.0)));
  // The world up (0,0,1) projects to +y on screen.
  CHECK(apply_vector(w, {0, 0, 1}).y() > 0);
  CHECK_THROWS_WITH(look_at({0, 0, 1}, {0, 0, 0}, {0, 0, 1}), Catch::Contains("parallel"));
}

TEST_CASE("bad transform input is an error naming what was wrong", "[transform][errors]") {
  CHECK_THROWS_WITH(rotate(10, {0, 0, 0}), Catch::Contains("axis must be non-zero"));
  CHECK_THROWS_WITH(translate({std::nan(""), 0, 0}), Catch::Contains("translation must be finite"));
  CHECK_THROWS_WITH(rotate_z(INFINITY), Catch::Contains("angle"));
  CHECK_THROWS_WITH(perspective(0, 1, 1, 10), Catch::Contains("fovy"));
  CHECK_THROWS_AS(frustum(-1, 1, -1, 1, 0, 10), Error);
}

TEST_CASE("transforms of extreme but finite numbers: axes scaled before their length, affine inverses exact",
          "[transform][extreme]") {
  // An axis whose squared length overflows is a direction all the same (it gave the zero axis, and
  // rotate(30, {1e308, 1e308, 0}) changed a box's volume); so is one whose squared length underflows.
  CHECK(near(rotate(30, {1e308, 1e308, 0}), rotate(30, {1, 1, 0}), 1e-15));
  CHECK(near(rotate(30, {5e-324, 0, 0}), rotate_x(30), 1e-15));
  CHECK(near(reflect({1e300, 0, 1e300}, {0, 0, 0}), reflect({1, 0, 1}, {0, 0, 0}), 1e-15));
  CHECK_THROWS_WITH(rotate(30, {0, 0, 0}), "rotation axis must be non-zero, got (0, 0, 0)");
  // A view of a part 1e10 away: LU of the 4x4 called it "singular (rank 3 of 4)".
  const Mat4 view = rotate(35, {1, 2, 3}) * translate({-1e10, 2e10, -3e10});
  CHECK(near(inverse(view) * view, Mat4::Identity(), 1e-6));
  CHECK(inverse(translate({1e300, 0, 0})) == translate({-1e300, 0, 0}));
  // Invertible however small the factor; singular only at zero.
  CHECK(inverse(scale({1e-200, 1, 1})) == scale({1e200, 1, 1}));
  CHECK_THROWS_WITH(inverse(scale({1, 0, 1})), "matrix is singular (rank 3 of 4): it has no inverse");
  CHECK_THROWS_WITH(inverse(scale({1e-310, 1, 1})), "the inverse of the matrix overflows (it is nearly singular)");
}

TEST_CASE("cos_sin is exact at multiples of a right angle and std's elsewhere", "[transform]") {
  // The tessellators' circles: a quarter point must lie on its axis, whichever way the angle was
  // computed (pi / 2, 2 pi * 1 / 4, 3 * (pi / 2), -pi).
  struct Case {
    double a, c, s;
  };
  const Case exact[] = {{0, 1, 0},          {kPi / 2, 0, 1},         {2 * kPi * 1 / 4, 0, 1}, {kPi, -1, 0},
                        {3 * (kPi / 2), 0, -1}, {2 * kPi, 1, 0},      {-kPi / 2, 0, -1},       {-kPi, -1, 0},
                        {5 * (kPi / 2), 0, 1},  {std::nextafter(kPi / 2, 4.0), 0, 1}};
  for (const Case& k : exact) {
    double c = 7, s = 7;
    cos_sin(k.a, c, s);
    INFO("angle " << k.a);
    CHECK(c == k.c);
    CHECK(s == k.s);
  }
  for (double a : {0.1, 1.0, kPi / 2 - 1e-9, kPi / 3, -2.5, 100.0}) {
    double c = 7, s = 7;
    cos_sin(a, c, s);
    CHECK(c == std::cos(a));
    CHECK(s == std::sin(a));
  }
  // Nothing but the angle decides: a NaN stays NaN.
  double c = 0, s = 0;
  cos_sin(std::nan(""), c, s);
  CHECK(std::isnan(c));
  CHECK(std::isnan(s));
}
