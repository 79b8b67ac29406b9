// The engine's table of constructed points (Points, boolean_exact.cpp): where the interval filter
// bounds a point only loosely, its box must still be the two doubles around its exact coordinate.
#include <catch2/catch.hpp>

#include <cmath>

#include "csg/boolean_impl.h"

using namespace wedge;
using namespace wedge::boolean_detail;

namespace {
double ulps(double lo, double hi) {
  const double u = std::ldexp(1.0, std::ilogb(std::max(std::abs(lo), std::abs(hi))) - 52);
  return (hi - lo) / u;
}
}  // namespace

TEST_CASE("boolean points: a segment nearly parallel to a plane cuts it at a point boxed within an ulp", "[boolean][points]") {
  // Plane z = 0.1 x + 0.3 y tilted through rounded coordinates, and segments that cross it at a
  // grazing angle: their W (the segment's direction against the plane's normal) is a few
  // roundings, so the filter's quotient spans far more than 64 ulps, and the box was left that
  // wide (five spheres turned by 1e-13 degrees: 6,384 such points, each then compared exactly
  // with every other point of the run).
  int loose = 0;
  for (int k = 1; k <= 40; ++k) {
    const double eps = std::ldexp(1.0, -40 - k);
    Mesh m;
    m.positions = {{0.1, 0.2, 0.1 * 0.1 + 0.3 * 0.2}, {3.7, 0.3, 0.37 + 0.09}, {0.3, 2.9, 0.03 + 0.87},
                   {0.7, 0.9, 0.07 + 0.27 - eps}, {2.3, 1.3, 0.23 + 0.39 + eps}, {5, 5, 9}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    std::vector<const Mesh*> one{&m};
    const Soup soup = make_soup(one);
    Points pts(soup);
    PointDef d;
    d.kind = PointDef::Lpi;
    d.p = 3;
    d.q = 4;
    d.P[0] = Plane::of_triangle(soup.tris[0]);
    if (pts.side(d.P[0], 3) * pts.side(d.P[0], 4) >= 0) continue;  // the segment does not cross
    const IntervalH h = pts.interval(pts.add(d));
    const u32 p = static_cast<u32>(pts.size() - 1);
    const auto box = pts.box(p);
    const Vec3& a = pts.approx(p);
    for (int i = 0; i < 3; ++i) {
      INFO("k " << k << " axis " << i);
      CHECK(ulps(box[i], box[i + 3]) <= 1);
      CHECK(box[i] <= a[i]);
      CHECK(a[i] <= box[i + 3]);
      // The filter's quotient, for the record of how loose it was.
      const double wlo = h.lo[3], whi = h.hi[3];
      if (wlo > 0 || whi < 0) {
        const double q[4] = {h.lo[i] / wlo, h.lo[i] / whi, h.hi[i] / wlo, h.hi[i] / whi};
        if (ulps(std::min({q[0], q[1], q[2], q[3]}), std::max({q[0], q[1], q[2], q[3]})) > 64) ++loose;
      } else {
        ++loose;
      }
    }
  }
  CHECK(loose > 10);  // the loose filter path is what is tested
}
