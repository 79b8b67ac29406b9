// Homogeneous transforms: 4x4 for 3D, 3x3 for 2D. Angles are in degrees, as in OpenGL and the
// Lua API. Matrices act on column vectors (p' = M p), so compose(A, B) = A * B applies B first.
// The projection and viewing matrices are the exact ones glFrustum, glOrtho, gluPerspective and
// gluLookAt multiply onto the current matrix.
#pragma once
#include "kernel/types.h"

namespace wedge {

// --- 3D ---
Mat4 identity();
Mat4 translate(const Vec3& d);
Mat4 rotate_x(double deg);
Mat4 rotate_y(double deg);
Mat4 rotate_z(double deg);
// About an axis through the origin (right-handed: counter-clockwise looking down the axis).
// Throws if the axis is zero or not finite.
Mat4 rotate(double deg, const Vec3& axis);
// About an axis through `pivot`: T(p) R T(-p). The pivot is a fixed point.
Mat4 rotate(double deg, const Vec3& axis, const Point3& pivot);
// Euler angles: R = Rz(z) Ry(y) Rx(x), so x is applied first.
Mat4 rotate_euler(double x_deg, double y_deg, double z_deg);
Mat4 scale(const Vec3& k);
Mat4 scale(const Vec3& k, const Point3& fixed);  // T(f) S T(-f): `fixed` does not move
// Mirror in the plane through `point` with normal `normal` (need not be unit).
Mat4 reflect(const Vec3& normal, const Point3& point = Point3::Zero());

// The six 3D shears: the new x gains xy*y + xz*z, the new y gains yx*x + yz*z,
// the new z gains zx*x + zy*y.
struct Shear {
  double xy = 0, xz = 0, yx = 0, yz = 0, zx = 0, zy = 0;
};
Mat4 shear(const Shear& s);

// Throws wedge::Error if m is singular (|det| below 1e-300 relative to its scale) or not finite.
Mat4 inverse(const Mat4& m);
inline Mat4 transpose(const Mat4& m) { return m.transpose(); }
inline Mat4 compose(const Mat4& a, const Mat4& b) { return a * b; }  // b first, then a

// Applies m to a point (with the homogeneous divide when w != 1), a direction (no translation)
// and a surface normal (the inverse transpose of the linear part, renormalised).
Point3 apply_point(const Mat4& m, const Point3& p);
Vec3 apply_vector(const Mat4& m, const Vec3& v);
Vec3 apply_normal(const Mat4& m, const Vec3& n);
// True when the linear part reverses orientation (a mirror): faces must be flipped.
bool reverses_orientation(const Mat4& m);

// Viewing and projection, with OpenGL's conventions (eye looks down -z, NDC z in [-1, 1]).
Mat4 look_at(const Point3& eye, const Point3& center, const Vec3& up);
Mat4 frustum(double left, double right, double bottom, double top, double near, double far);
Mat4 perspective(double fovy_deg, double aspect, double near, double far);
Mat4 ortho(double left, double right, double bottom, double top, double near, double far);

// --- 2D (3x3 homogeneous) ---
Mat3 identity_2d();
Mat3 translate_2d(const Vec2& d);
Mat3 rotate_2d(double deg);
Mat3 rotate_2d(double deg, const Point2& pivot);
Mat3 scale_2d(const Vec2& k);
Mat3 scale_2d(const Vec2& k, const Point2& fixed);
// Mirror in the line through `point` with direction `dir`.
Mat3 reflect_2d(const Vec2& dir, const Point2& point = Point2::Zero());
// x' = x + y cot(theta): the shear that leans the y axis to angle theta from the x axis.
Mat3 shear_x_2d(double theta_deg);
// y' = y + x cot(theta).
Mat3 shear_y_2d(double theta_deg);
Mat3 inverse_2d(const Mat3& m);
Point2 apply_point_2d(const Mat3& m, const Point2& p);

}  // namespace wedge
