// Small distance helpers on approximate (double) geometry, for adaptive sampling and error
// estimates; exact decisions go through kernel/predicates.h.
#pragma once
#include <algorithm>

#include "kernel/types.h"

namespace wedge {

// Distance from p to the closed segment [a, b] (to a itself when the segment has no length).
inline double point_segment_distance(const Point3& p, const Point3& a, const Point3& b) {
  const Vec3 ab = b - a;
  const double l2 = ab.squaredNorm();
  const double s = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

}  // namespace wedge
