// Exact geometric predicates. Every function here returns the sign or answer that exact real
// arithmetic on the given doubles would give, whatever the input: a fast floating-point filter
// answers the easy cases and exact arithmetic (CGAL's filtered kernel, confined to
// predicates.cpp) the close ones. Signs are -1, 0, +1.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "kernel/types.h"

namespace wedge {

// +1 if a, b, c turn counter-clockwise (c left of the directed line a->b), -1 clockwise, 0 collinear.
int orient2d(const Point2& a, const Point2& b, const Point2& c);
// The sign of det[b-a, c-a, d-a]: +1 if d lies on the side of plane abc from which a, b, c
// appear counter-clockwise (the side the normal (b-a)x(c-a) points to), -1 on the other side,
// 0 when the four points are coplanar.
int orient3d(const Point3& a, const Point3& b, const Point3& c, const Point3& d);
// For a, b, c counter-clockwise: +1 if d is inside their circumcircle, -1 outside, 0 on it.
// (The sign flips when a, b, c are clockwise, as for the oriented predicate.)
int incircle(const Point2& a, const Point2& b, const Point2& c, const Point2& d);
// For a positively oriented tetrahedron (orient3d(a,b,c,d) = +1): +1 if e is inside the
// circumsphere, -1 outside, 0 on it.
int insphere(const Point3& a, const Point3& b, const Point3& c, const Point3& d, const Point3& e);
// The sign of the sum over `triangles` (a, b, c) of det[a, b, c]: six times the signed volume that
// a closed mesh of these triangles bounds (the sum does not depend on where the origin is).
int volume_sign(const std::vector<Point3>& positions, const std::vector<std::array<std::uint32_t, 3>>& triangles);
bool coplanar(const Point3& a, const Point3& b, const Point3& c, const Point3& d);
bool collinear(const Point3& a, const Point3& b, const Point3& c);

// Closed intersection tests (touching counts). Degenerate inputs (a segment of zero length, a
// triangle of zero area) are handled as points/segments, exactly.
bool segments_intersect_2d(const Point2& p, const Point2& q, const Point2& a, const Point2& b);
bool segment_triangle_intersect(const Point3& p, const Point3& q, const Point3& a, const Point3& b,
                                const Point3& c);
bool triangles_intersect(const Point3& a0, const Point3& a1, const Point3& a2, const Point3& b0,
                         const Point3& b1, const Point3& b2);

}  // namespace wedge
