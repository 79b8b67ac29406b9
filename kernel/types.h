// Vectors, points and matrices of wedge: Eigen fixed-size types, column-major like OpenGL.
#pragma once
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

}  // namespace wedge
