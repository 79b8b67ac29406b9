// Vectors, points and matrices of wedge: Eigen fixed-size types, column-major like OpenGL.
#pragma once
#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

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

// cos and sin of an angle in radians, exactly 0 and +-1 where the angle is a multiple of pi/2 to
// within a few ulps, so a circle's quarter points lie on its axes. (std::cos(pi / 2) is 6.1e-17:
// cube(1) - cylinder(0.3, 3) kept a wall 1.8e-17 wide beside x = 0, which a turn then folded.)
inline void cos_sin(double a, double& c, double& s) {
  const double q = std::nearbyint(a / (kPi / 2));
  if (std::abs(q) < 1e6 && std::abs(a - q * (kPi / 2)) <= 2e-15 * std::max(1.0, std::abs(a))) {
    static constexpr double kc[4] = {1, 0, -1, 0}, ks[4] = {0, 1, 0, -1};
    const int k = static_cast<int>(((static_cast<long long>(q) % 4) + 4) % 4);
    c = kc[k];
    s = ks[k];
    return;
  }
  c = std::cos(a);
  s = std::sin(a);
}

}  // namespace wedge
