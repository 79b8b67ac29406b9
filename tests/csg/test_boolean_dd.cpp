// The exact predicates' double-double stage (csg/boolean_dd.h) against rational arithmetic: its
// error bound holds through long chains of sums and products, also where they cancel; the signs
// it gives are the exact ones; it declines (2) rather than guess at zeros, overflow and underflow;
// and it decides nearly everything that is not degenerate (it is not a stage that always passes).
#include <CGAL/Gmpq.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "csg/boolean_dd.h"

using wedge::boolean_detail::DD;
using Q = CGAL::Gmpq;

namespace {

int sgn(const Q& x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }

// |exact - (hi + lo)| <= err, in rationals.
bool bound_holds(const DD& x, const Q& exact) {
  if (!(x.err < INFINITY)) return true;  // no claim
  Q d = exact - Q(x.hi) - Q(x.lo);
  if (d < 0) d = -d;
  return d <= Q(x.err);
}

struct Both {
  DD d;
  Q q;
};

}  // namespace

TEST_CASE("boolean dd: the error bound holds through chains of sums and products that cancel", "[boolean][dd]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(0.5, 1.0);
  std::uniform_int_distribution<int> expo(-20, 20);
  auto random_double = [&] { return std::ldexp(mant(rng), expo(rng)) * (rng() % 2 ? 1 : -1); };
  int checked = 0, decided = 0, cancelled = 0;
  for (int run = 0; run < 2000; ++run) {
    std::vector<Both> v;
    for (int i = 0; i < 6; ++i) {
      const double x = random_double();
      v.push_back({DD(x), Q(x)});
    }
    for (int step = 0; step < 24; ++step) {
      const Both& a = v[rng() % v.size()];
      const Both& b = v[rng() % v.size()];
      Both r;
      switch (rng() % 4) {
        case 0:
          r = {a.d + b.d, a.q + b.q};
          break;
        case 1:
          r = {a.d - b.d, a.q - b.q};
          break;
        case 2:
          r = {a.d * b.d, a.q * b.q};
          break;
        default: {
          // a minus a copy of itself rebuilt another way ((a + c) - c): a cancellation to (nearly)
          // nothing, the case the bound must survive.
          const double c = random_double();
          r = {(a.d + DD(c)) - DD(c) - a.d + b.d * DD(std::ldexp(1.0, -60)), (a.q + Q(c)) - Q(c) - a.q + b.q * Q(std::ldexp(1.0, -60))};
          ++cancelled;
        }
      }
      if (!std::isfinite(r.d.hi)) continue;
      ++checked;
      INFO("run " << run << " step " << step << ": " << r.d.hi << " + " << r.d.lo << " +- " << r.d.err);
      REQUIRE(bound_holds(r.d, r.q));
      const int s = wedge::boolean_detail::sign_of(r.d);
      if (s != 2) {
        REQUIRE(s == sgn(r.q));
        ++decided;
      }
      v.push_back(r);
    }
  }
  CHECK(checked > 40000);
  CHECK(cancelled > 10000);
  CHECK(decided > checked * 9 / 10);
}

TEST_CASE("boolean dd: orientation and in-circle signs near degeneracy are exact or declined", "[boolean][dd]") {
  // Points on a line y = m x + c through rounded coordinates, nudged by a few ulps: the exact
  // orientation is zero or tiny; the stage must never give a wrong sign, and on points exactly on
  // a line with exact products (a slope of 2^k) it may say 0 only because nothing was rounded.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int zeros = 0, declined = 0, right = 0;
  for (int n = 0; n < 20000; ++n) {
    const double m = n % 3 == 0 ? 2.0 : u(rng), c = u(rng);
    double x[3], y[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = u(rng);
      y[k] = m * x[k] + c;
      if (n % 5 == 0) y[k] = std::nextafter(y[k], rng() % 2 ? INFINITY : -INFINITY);
    }
    const DD bx = DD(x[1]) - DD(x[0]), by = DD(y[1]) - DD(y[0]), cx = DD(x[2]) - DD(x[0]), cy = DD(y[2]) - DD(y[0]);
    const DD det = bx * cy - by * cx;
    const Q qdet = (Q(x[1]) - Q(x[0])) * (Q(y[2]) - Q(y[0])) - (Q(y[1]) - Q(y[0])) * (Q(x[2]) - Q(x[0]));
    REQUIRE(bound_holds(det, qdet));
    const int s = wedge::boolean_detail::sign_of(det);
    zeros += sgn(qdet) == 0;
    if (s == 2) {
      ++declined;
    } else {
      REQUIRE(s == sgn(qdet));
      ++right;
    }
    // The in-circle determinant of four points near a circle, as the engine's rows (x, y, x^2 + y^2).
    double px[4], py[4];
    for (int k = 0; k < 4; ++k) {
      const double t = u(rng) * 3;
      px[k] = std::cos(t);
      py[k] = std::sin(t);
    }
    DD r[3][3];
    Q qr[3][3];
    for (int k = 0; k < 3; ++k) {
      r[k][0] = DD(px[k]) - DD(px[3]);
      r[k][1] = DD(py[k]) - DD(py[3]);
      r[k][2] = r[k][0] * r[k][0] + r[k][1] * r[k][1];
      qr[k][0] = Q(px[k]) - Q(px[3]);
      qr[k][1] = Q(py[k]) - Q(py[3]);
      qr[k][2] = qr[k][0] * qr[k][0] + qr[k][1] * qr[k][1];
    }
    const DD ic = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                  r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    const Q qic = qr[0][0] * (qr[1][1] * qr[2][2] - qr[1][2] * qr[2][1]) - qr[0][1] * (qr[1][0] * qr[2][2] - qr[1][2] * qr[2][0]) +
                  qr[0][2] * (qr[1][0] * qr[2][1] - qr[1][1] * qr[2][0]);
    REQUIRE(bound_holds(ic, qic));
    const int si = wedge::boolean_detail::sign_of(ic);
    if (si != 2) REQUIRE(si == sgn(qic));
  }
  CHECK(zeros > 500);
  CHECK(right > 10000);
  CHECK(declined < 10000);
}

TEST_CASE("boolean dd: overflow, underflow and NaN are declined, exact zeros of doubles are kept", "[boolean][dd]") {
  using wedge::boolean_detail::sign_of;
  CHECK(sign_of(DD(1e200) * DD(1e200)) == 2);                  // overflow
  CHECK(sign_of(DD(1e200) * DD(1e200) - DD(1e300)) == 2);
  CHECK(sign_of(DD(1e-200) * DD(1e-200)) == 2);                // Dekker's product inexact
  CHECK(sign_of((DD(1e-150) * DD(3e-150)) * DD(1e10)) == 2);
  CHECK(sign_of(DD(std::nan("")) + DD(1)) == 2);
  CHECK(sign_of(DD(INFINITY) - DD(INFINITY)) == 2);
  CHECK(sign_of(DD(3e250) * DD(1e-250)) == 1);
  CHECK(sign_of(DD(0x1p1000) * DD(0x1p-990)) == 2);             // a finite product whose split overflows
  // Products and sums of two doubles are exact: their zeros are certain.
  CHECK(sign_of(DD(0.1) * DD(0.3) - DD(0.3) * DD(0.1)) == 0);
  CHECK(sign_of(DD(0.1) - DD(0.1)) == 0);
  CHECK(sign_of(DD(0.1) * DD(0.3) + DD(1e-40)) == 1);
  // A zero reached through rounded steps is not certain.
  const DD third = DD(1) * DD(1.0 / 3);
  const DD a = (third * DD(3) + DD(1e-20)) * DD(7);
  CHECK(sign_of(a - a) == 2);
  CHECK(sign_of(a - a + DD(1e-10)) == 1);
}
