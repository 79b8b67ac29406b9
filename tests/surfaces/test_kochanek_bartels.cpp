// Kochanek-Bartels splines against hand-worked tangents and against Catmull-Rom's matrix form
// (an independent formula: catmull_rom is kochanek_bartels with t = b = c = 0, so comparing the
// two with each other would prove nothing).
#include <catch2/catch.hpp>

#include <vector>

#include "surfaces/surfaces.h"

using namespace wedge;

TEST_CASE("Kochanek-Bartels tangents have the paper's signs: continuity -1 gives corners", "[interpolation]") {
  // Three sides of a unit square. At Q1 = (1, 0, 0) the chord in is (1, 0, 0) and the chord out
  // (0, 1, 0); at Q2 = (1, 1, 0) in is (0, 1, 0), out (-1, 0, 0). Kochanek & Bartels (1984) with
  // t = b = 0: leaving P_i (1 + c)/2 in + (1 - c)/2 out, reaching P_i (1 - c)/2 in + (1 + c)/2 out.
  const std::vector<Point3> sq{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  // c = 1/2: leaving Q1 0.75 (1, 0, 0) + 0.25 (0, 1, 0) = (0.75, 0.25, 0) (at a joint the
  // derivative is the one of the segment that starts there); reaching Q2 0.25 (0, 1, 0) +
  // 0.75 (-1, 0, 0) = (-0.75, 0.25, 0). The cubic Hermite midpoint (P1 + P2)/2 + (m1 - m2)/8 is
  // then (1.1875, 0.5, 0).
  const HermiteSpline half = kochanek_bartels(sq, 0, 0, 0.5);
  CHECK((half.derivative(1, 1) - Vec3(0.75, 0.25, 0)).norm() < 1e-15);
  CHECK((half.derivative(2 - 1e-9, 1) - Vec3(-0.75, 0.25, 0)).norm() < 1e-7);
  CHECK((half.eval(1.5) - Point3(1.1875, 0.5, 0)).norm() < 1e-14);
  // c = -1: each segment's end tangents are its own chord, so the middle segment is the side
  // from Q1 to Q2 itself (box corners).
  const HermiteSpline box = kochanek_bartels(sq, 0, 0, -1);
  for (int j = 0; j <= 8; ++j) CHECK((box.eval(1 + j / 8.0) - Point3(1, j / 8.0, 0)).norm() < 1e-14);
  CHECK((box.derivative(1, 1) - Vec3(0, 1, 0)).norm() < 1e-15);
  // c = +1: leaving Q1 along the chord in, (1, 0, 0): the corner overshoots.
  CHECK((kochanek_bartels(sq, 0, 0, 1).derivative(1, 1) - Vec3(1, 0, 0)).norm() < 1e-15);
  // Bias +1 (c = 0) takes the tangent at Q1 from the chord in alone: (1, 0, 0); bias -1 from the
  // chord out: (0, 1, 0). Tension 1 makes it zero.
  CHECK((kochanek_bartels(sq, 0, 1, 0).derivative(1, 1) - Vec3(1, 0, 0)).norm() < 1e-15);
  CHECK((kochanek_bartels(sq, 0, -1, 0).derivative(1, 1) - Vec3(0, 1, 0)).norm() < 1e-15);
  CHECK(kochanek_bartels(sq, 1, 0, 0).derivative(1, 1).norm() < 1e-15);
}

TEST_CASE("catmull_rom is Catmull-Rom's matrix form on every segment, the ends by phantom points",
          "[interpolation]") {
  const std::vector<Point3> Q{{0, 0, 0}, {1, 2, 0}, {2, 2.5, 1}, {4, 0, 1}, {5, -1, 0}, {7, 1, 2}};
  const HermiteSpline cr = catmull_rom(Q, false);
  // The end segments use the mirrored phantom points 2 Q0 - Q1 and 2 Q5 - Q4 (surfaces.h).
  auto q = [&](long i) -> Point3 {
    if (i < 0) return 2 * Q[0] - Q[1];
    if (i >= long(Q.size())) return 2 * Q.back() - Q[Q.size() - 2];
    return Q[std::size_t(i)];
  };
  for (long i = 0; i + 1 < long(Q.size()); ++i)
    for (int j = 0; j <= 10; ++j) {
      const double s = j / 10.0, s2 = s * s, s3 = s2 * s;
      const Point3 a = q(i - 1), b = q(i), c = q(i + 1), d = q(i + 2);
      const Point3 expect =
          0.5 * ((2 * b) + (-a + c) * s + (2 * a - 5 * b + 4 * c - d) * s2 + (-a + 3 * b - 3 * c + d) * s3);
      INFO("segment " << i << ", s = " << s);
      CHECK((cr.eval(double(i) + s) - expect).norm() < 1e-13);
    }
}
