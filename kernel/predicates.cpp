// The only translation unit of kernel/ that sees CGAL. Exact_predicates_inexact_constructions_kernel
// evaluates each predicate with interval arithmetic first and falls back to exact (GMP) arithmetic
// only when the interval contains zero, so results are exact at near-double speed.
#include "kernel/predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include "kernel/error.h"

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
