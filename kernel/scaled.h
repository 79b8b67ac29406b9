// Lengths, directions and moments of big-but-finite or tiny-but-positive geometry. Coordinates up
// to 1e100 are finite, but the squared length of a cross product or Newell normal of them (1e400)
// is not, nor is that of a vector 1e-180 long; second moments of a solid 1e90 wide (volume x
// size^2, 1e450) overflow. Each helper scales first, by the largest component or by a power of two
// near the size (exact), so that only a result that truly leaves the range of doubles does.
// A header of its own: kernel/types.h is included by every file.
#pragma once
#include <cmath>

#include "kernel/mesh.h"

namespace wedge {

// |v|, scaled by its largest component first.
inline double scaled_norm(const Vec3& v) {
  const double m = v.cwiseAbs().maxCoeff();
  if (!(m > 0) || !std::isfinite(m)) return m;
  return m * (v / m).norm();
}

// v / |v|, scaled by its largest component first; the zero vector (and a non-finite one) gives zero.
inline Vec3 unit_vector(const Vec3& v) {
  const double m = v.cwiseAbs().maxCoeff();
  if (!(m > 0) || !std::isfinite(m)) return Vec3::Zero();
  return (v / m).normalized();
}

// The integrals of a solid measured in a frame of its own: coordinates x = (p - ref) / scale with
// ref near the solid and scale a power of two near its size, so that a solid 1e90 or 1e-90 wide is
// measured as one of size 1 without rounding. from_frame() turns them back into model units; an
// inertia that truly overflows is then infinite (the caller reports it).
struct MomentFrame {
  Point3 ref = Point3::Zero();
  double scale = 1;
  explicit MomentFrame(const Box3& bounds);
  Vec3 local(const Point3& p) const { return (p - ref) / scale; }
  // volume, area, first = integral of x, second = integral of x x^T (symmetric), all in the frame.
  MassProperties from_frame(double volume, double area, const Vec3& first, const Mat3& second) const;
};

}  // namespace wedge
