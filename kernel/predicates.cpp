// The only translation unit of kernel/ that sees CGAL. Exact_predicates_inexact_constructions_kernel
// evaluates each predicate with interval arithmetic first and falls back to exact (GMP) arithmetic
// only when the interval contains zero, so results are exact at near-double speed.
#include "kernel/predicates.h"

#include <cmath>
#include <limits>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Gmpq.h>
#include <CGAL/intersections.h>

#include "kernel/error.h"
#include "kernel/scaled.h"

namespace wedge {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

void require_finite_point(const Vec3& p) {
  if (!p.allFinite()) fail("predicate input must be finite, got (", p.x(), ", ", p.y(), ", ", p.z(), ")");
}
void require_finite_point(const Vec2& p) {
  if (!p.allFinite()) fail("predicate input must be finite, got (", p.x(), ", ", p.y(), ")");
}

K::Point_2 cg(const Point2& p) { require_finite_point(p); return K::Point_2(p.x(), p.y()); }
K::Point_3 cg(const Point3& p) { require_finite_point(p); return K::Point_3(p.x(), p.y(), p.z()); }

int sign(CGAL::Sign s) { return s == CGAL::POSITIVE ? 1 : (s == CGAL::NEGATIVE ? -1 : 0); }

}  // namespace

int orient2d(const Point2& a, const Point2& b, const Point2& c) {
  return sign(CGAL::orientation(cg(a), cg(b), cg(c)));
}

int orient3d(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  // CGAL::orientation(p,q,r,s) is the sign of det[q-p, r-p, s-p].
  return sign(CGAL::orientation(cg(a), cg(b), cg(c), cg(d)));
}

int volume_sign(const std::vector<Point3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  if (triangles.empty()) return 0;
  for (const auto& p : positions) require_finite_point(p);
  // The filter: the sum in the box's MomentFrame (its centre, a power of two: the volume is the
  // same there, scaled exactly), summed with Neumaier's compensation. A term moves by at most
  // 3 eps |a|1 |b|1 |c|1 through the translation's rounding and 5 eps of that through the
  // determinant's; the compensated sum errs by at most 2 eps |sum| + 2 n eps^2 (the terms'
  // magnitudes). Beyond that bound (doubled) the double sum has the exact sign; within it, the
  // exact sum decides. (With a plain sum's n eps bound, a 100 x 100 x 0.001 plate of a million
  // triangles would take the exact path: that bound is 8 times its volume; this one 6e-5 times.)
  Box3 box;
  for (const auto& T : triangles)
    for (auto v : T) box.extend(positions[v]);
  const double size = box.size().maxCoeff();
  if (size > 0 && std::isfinite(size)) {
    const MomentFrame frame(box);
    double sum = 0, carry = 0, magnitude = 0;
    for (const auto& T : triangles) {
      const Vec3 a = frame.local(positions[T[0]]), b = frame.local(positions[T[1]]), c = frame.local(positions[T[2]]);
      const double term = a.dot(b.cross(c));
      const double next = sum + term;
      carry += std::abs(sum) >= std::abs(term) ? (sum - next) + term : (term - next) + sum;
      sum = next;
      magnitude += a.cwiseAbs().sum() * b.cwiseAbs().sum() * c.cwiseAbs().sum();
    }
    sum += carry;
    const double eps = std::numeric_limits<double>::epsilon(), n = static_cast<double>(triangles.size());
    const double bound = 2 * ((8 + 2 * n * eps) * eps * magnitude * (1 + n * eps) + 2 * eps * std::abs(sum));
    if (std::isfinite(sum) && std::isfinite(bound) && bound > 0 && std::abs(sum) > bound) return sum > 0 ? 1 : -1;
  }
  // Exact: the determinants of the doubles as they are, summed as rationals.
  CGAL::Gmpq total = 0;
  for (const auto& T : triangles) {
    const Point3 &p = positions[T[0]], &q = positions[T[1]], &r = positions[T[2]];
    auto x = [](double d) { return CGAL::Gmpq(d); };
    total += x(p.x()) * (x(q.y()) * x(r.z()) - x(q.z()) * x(r.y())) -
             x(p.y()) * (x(q.x()) * x(r.z()) - x(q.z()) * x(r.x())) +
             x(p.z()) * (x(q.x()) * x(r.y()) - x(q.y()) * x(r.x()));
  }
  return CGAL::sign(total) == CGAL::POSITIVE ? 1 : (CGAL::sign(total) == CGAL::NEGATIVE ? -1 : 0);
}

int incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d) {
  return sign(CGAL::side_of_oriented_circle(cg(a), cg(b), cg(c), cg(d)));
}

int insphere(const Point3& a, const Point3& b, const Point3& c, const Point3& d, const Point3& e) {
  return sign(CGAL::side_of_oriented_sphere(cg(a), cg(b), cg(c), cg(d), cg(e)));
}

bool coplanar(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  return CGAL::coplanar(cg(a), cg(b), cg(c), cg(d));
}

bool collinear(const Point3& a, const Point3& b, const Point3& c) {
  return CGAL::collinear(cg(a), cg(b), cg(c));
}

bool segments_intersect_2d(const Point2& p, const Point2& q, const Point2& a, const Point2& b) {
  auto s1 = cg(p), s2 = cg(q), t1 = cg(a), t2 = cg(b);
  if (s1 == s2 && t1 == t2) return s1 == t1;
  if (s1 == s2) return K::Segment_2(t1, t2).has_on(s1);
  if (t1 == t2) return K::Segment_2(s1, s2).has_on(t1);
  return CGAL::do_intersect(K::Segment_2(s1, s2), K::Segment_2(t1, t2));
}

bool segment_triangle_intersect(const Point3& p, const Point3& q, const Point3& a, const Point3& b,
                                const Point3& c) {
  auto s1 = cg(p), s2 = cg(q), A = cg(a), B = cg(b), C = cg(c);
  if (CGAL::collinear(A, B, C)) {
    // A zero-area triangle is the union of its edges (or a point).
    auto hits = [&](const K::Point_3& u, const K::Point_3& v) {
      if (u == v) return s1 == s2 ? s1 == u : K::Segment_3(s1, s2).has_on(u);
      if (s1 == s2) return K::Segment_3(u, v).has_on(s1);
      return CGAL::do_intersect(K::Segment_3(s1, s2), K::Segment_3(u, v));
    };
    return hits(A, B) || hits(B, C) || hits(C, A);
  }
  K::Triangle_3 t(A, B, C);
  if (s1 == s2) return t.has_on(s1);
  return CGAL::do_intersect(K::Segment_3(s1, s2), t);
}

bool triangles_intersect(const Point3& a0, const Point3& a1, const Point3& a2, const Point3& b0,
                         const Point3& b1, const Point3& b2) {
  auto A0 = cg(a0), A1 = cg(a1), A2 = cg(a2), B0 = cg(b0), B1 = cg(b1), B2 = cg(b2);
  bool da = CGAL::collinear(A0, A1, A2), db = CGAL::collinear(B0, B1, B2);
  if (!da && !db) return CGAL::do_intersect(K::Triangle_3(A0, A1, A2), K::Triangle_3(B0, B1, B2));
  // Degenerate triangles: test edges against the other triangle.
  if (da) {
    return segment_triangle_intersect(a0, a1, b0, b1, b2) || segment_triangle_intersect(a1, a2, b0, b1, b2) ||
           segment_triangle_intersect(a2, a0, b0, b1, b2);
  }
  return segment_triangle_intersect(b0, b1, a0, a1, a2) || segment_triangle_intersect(b1, b2, a0, a1, a2) ||
         segment_triangle_intersect(b2, b0, a0, a1, a2);
}

}  // namespace wedge
