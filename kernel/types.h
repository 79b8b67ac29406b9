// Vectors, points and matrices of wedge: Eigen fixed-size types, column-major like OpenGL.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace wedge {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Point2 = Vec2;
using Point3 = Vec3;
using Mat3 = Eigen::Matrix3d;   // 2D homogeneous transforms, and 3x3 linear maps
using Mat4 = Eigen::Matrix4d;   // 3D homogeneous transforms (column-major, as glLoadMatrixd)

constexpr double kPi = 3.14159265358979323846;

inline double radians(double degrees) { return degrees * (kPi / 180.0); }
inline double degrees(double radians) { return radians * (180.0 / kPi); }

// |v| and v / |v| scaled first by the largest component: coordinates up to 1e100 are finite, but
// the squared length of a cross product or Newell normal of them (1e400) is not, nor is that of a
// vector near 1e-180 above zero. The zero vector (and a non-finite one) has unit_vector zero.
inline double scaled_norm(const Vec3& v) {
  const double m = v.cwiseAbs().maxCoeff();
  if (!(m > 0) || !std::isfinite(m)) return m;
  return m * (v / m).norm();
}
inline Vec3 unit_vector(const Vec3& v) {
  const double m = v.cwiseAbs().maxCoeff();
  if (!(m > 0) || !std::isfinite(m)) return Vec3::Zero();
  return (v / m).normalized();
}

}  // namespace wedge
