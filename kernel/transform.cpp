#include "kernel/transform.h"

#include <cmath>

#include "kernel/error.h"
#include "kernel/scaled.h"

namespace wedge {

namespace {

void require_finite3(const Vec3& v, const char* what) {
  if (!v.allFinite()) fail(what, " must be finite, got (", v.x(), ", ", v.y(), ", ", v.z(), ")");
}

// cos/sin that are exact at multiples of 90 degrees, so rotate_z(90) maps x to y exactly.
void exact_cos_sin(double deg, double& c, double& s) {
  require_finite(deg, "angle");
  double r = std::fmod(deg, 360.0);
  if (r < 0) r += 360.0;
  if (r == 0.0) { c = 1; s = 0; return; }
  if (r == 90.0) { c = 0; s = 1; return; }
  if (r == 180.0) { c = -1; s = 0; return; }
  if (r == 270.0) { c = 0; s = -1; return; }
  c = std::cos(radians(deg));
  s = std::sin(radians(deg));
}

}  // namespace

Mat4 identity() { return Mat4::Identity(); }

Mat4 translate(const Vec3& d) {
  require_finite3(d, "translation");
  Mat4 m = Mat4::Identity();
  m.block<3, 1>(0, 3) = d;
  return m;
}

Mat4 rotate_x(double deg) {
  double c, s;
  exact_cos_sin(deg, c, s);
  Mat4 m = Mat4::Identity();
  m(1, 1) = c; m(1, 2) = -s;
  m(2, 1) = s; m(2, 2) = c;
  return m;
}

Mat4 rotate_y(double deg) {
  double c, s;
  exact_cos_sin(deg, c, s);
  Mat4 m = Mat4::Identity();
  m(0, 0) = c; m(0, 2) = s;
  m(2, 0) = -s; m(2, 2) = c;
  return m;
}

Mat4 rotate_z(double deg) {
  double c, s;
  exact_cos_sin(deg, c, s);
  Mat4 m = Mat4::Identity();
  m(0, 0) = c; m(0, 1) = -s;
  m(1, 0) = s; m(1, 1) = c;
  return m;
}

Mat4 rotate(double deg, const Vec3& axis) {
  require_finite3(axis, "rotation axis");
  // Scaled first: an axis (1e308, 1e308, 0) has an infinite norm, and divided by it gave the zero
  // axis (a rotation that changed the volume); (5e-324, 0, 0) is a direction all the same.
  const Vec3 a = unit_vector(axis);
  if (a == Vec3::Zero()) fail("rotation axis must be non-zero, got (0, 0, 0)");
  double c, s;
  exact_cos_sin(deg, c, s);
  // Rodrigues' formula, in the form glRotate documents.
  double t = 1 - c;
  double x = a.x(), y = a.y(), z = a.z();
  Mat4 m = Mat4::Identity();
  m(0, 0) = x * x * t + c;     m(0, 1) = x * y * t - z * s; m(0, 2) = x * z * t + y * s;
  m(1, 0) = y * x * t + z * s; m(1, 1) = y * y * t + c;     m(1, 2) = y * z * t - x * s;
  m(2, 0) = x * z * t - y * s; m(2, 1) = y * z * t + x * s; m(2, 2) = z * z * t + c;
  return m;
}

Mat4 rotate(double deg, const Vec3& axis, const Point3& pivot) {
  require_finite3(pivot, "pivot");
  return translate(pivot) * rotate(deg, axis) * translate(-pivot);
}

Mat4 rotate_euler(double x_deg, double y_deg, double z_deg) {
  return rotate_z(z_deg) * rotate_y(y_deg) * rotate_x(x_deg);
}

Mat4 scale(const Vec3& k) {
  require_finite3(k, "scale factors");
  Mat4 m = Mat4::Identity();
  m(0, 0) = k.x(); m(1, 1) = k.y(); m(2, 2) = k.z();
  return m;
}

Mat4 scale(const Vec3& k, const Point3& fixed) {
  require_finite3(fixed, "fixed point");
  return translate(fixed) * scale(k) * translate(-fixed);
}

Mat4 reflect(const Vec3& normal, const Point3& point) {
  require_finite3(normal, "mirror normal");
  require_finite3(point, "mirror point");
  const double big = normal.cwiseAbs().maxCoeff();
  if (big == 0) fail("mirror normal must be non-zero, got (0, 0, 0)");
  // Householder: I - 2 v v^T / (v.v), about the plane v.x = v.point, from the normal as given
  // (scaled by a power of two, exactly, to a largest coordinate in [1, 2): no overflow or
  // underflow in v.v), each entry divided once at the end. Through the rounded unit normal, the
  // mirror about (1, 1, 0) had 1 - 2e-16 where it swaps x and y, and a centred cube minus its
  // mirror image kept two sliver shells of area 8 (now the swap is exact, and the result empty).
  const int e = -std::ilogb(big);  // (per coordinate: 2^1074 itself is past a double's range)
  const Vec3 v(std::ldexp(normal.x(), e), std::ldexp(normal.y(), e), std::ldexp(normal.z(), e));
  const double vv = v.squaredNorm();
  Mat4 m = Mat4::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) -= 2 * v[i] * v[j] / vv;
  const double d = v.dot(point);
  for (int i = 0; i < 3; ++i) m(i, 3) = 2 * d * v[i] / vv;
  return m;
}

Mat4 shear(const Shear& s) {
  for (double v : {s.xy, s.xz, s.yx, s.yz, s.zx, s.zy}) require_finite(v, "shear factor");
  Mat4 m = Mat4::Identity();
  m(0, 1) = s.xy; m(0, 2) = s.xz;
  m(1, 0) = s.yx; m(1, 2) = s.yz;
  m(2, 0) = s.zx; m(2, 1) = s.zy;
  return m;
}

Mat4 inverse(const Mat4& m) {
  if (!m.allFinite()) fail("cannot invert a matrix with non-finite entries");
  if (m.row(3) == Eigen::RowVector4d(0, 0, 0, 1)) {
    // Affine: the linear part's inverse and the moved translation. LU of the whole 4x4 judged the
    // rank against its largest entry, so a view of a part 1e10 away (translation 1e10, rotation
    // entries 1) came out "singular (rank 3 of 4)".
    // Singular only where a pivot is exactly zero: scale(1e-200, 1, 1) has the inverse
    // scale(1e200, 1, 1), which a threshold relative to the largest pivot called "rank 3".
    Eigen::FullPivLU<Mat3> lu(m.topLeftCorner<3, 3>());
    lu.setThreshold(0);
    if (!lu.isInvertible()) fail("matrix is singular (rank ", lu.rank() + 1, " of 4): it has no inverse");
    Mat4 out = Mat4::Identity();
    out.topLeftCorner<3, 3>() = lu.inverse();
    out.topRightCorner<3, 1>() = -out.topLeftCorner<3, 3>() * m.topRightCorner<3, 1>();
    if (!out.allFinite()) fail("the inverse of the matrix overflows (it is nearly singular)");
    return out;
  }
  Eigen::FullPivLU<Mat4> lu(m);
  if (!lu.isInvertible()) fail("matrix is singular (rank ", lu.rank(), " of 4): it has no inverse");
  return lu.inverse();
}

Point3 apply_point(const Mat4& m, const Point3& p) {
  Vec4 h = m * p.homogeneous();
  if (h.w() == 1.0) return h.head<3>();
  if (h.w() == 0.0) fail("point maps to infinity (w = 0) under this projective transform");
  return h.head<3>() / h.w();
}

Vec3 apply_vector(const Mat4& m, const Vec3& v) { return m.block<3, 3>(0, 0) * v; }

// The inverse transpose without an inverse: for columns c0, c1, c2 of the linear part L,
// L^-T n = (n0 c1 x c2 + n1 c2 x c0 + n2 c0 x c1) / det L. The columns are made unit length first
// (L^-T n = L'^-T D n, L = L' D^-1 with D = diag(1 / |c_i|)), so that a scale of 1e-120 or 1e120
// neither underflows nor overflows; only the sign of the determinant is used. A shear of 1e8,
// far from singular (determinant 1) but beyond an LU's rank threshold, was refused as singular.
Vec3 apply_normal(const Mat4& m, const Vec3& n) {
  const Mat3 l = m.block<3, 3>(0, 0);
  Vec3 u[3], w;
  for (int i = 0; i < 3; ++i) {
    double len = l.col(i).norm();
    if (!(len > 0) || !std::isfinite(len)) len = l.col(i).stableNorm();  // (norm() of (1e-200, 0, 0) underflows to 0)
    if (!(len > 0) || !std::isfinite(len)) fail("cannot transform a normal by a singular matrix");
    u[i] = l.col(i) / len;
    w[i] = n[i] / len;
  }
  const double big = w.cwiseAbs().maxCoeff();
  if (!std::isfinite(big)) fail("cannot transform a normal: it is not finite");
  if (big > 0) w /= big;
  const double det = u[0].dot(u[1].cross(u[2]));
  if (!(det != 0)) fail("cannot transform a normal by a singular matrix");
  Vec3 r = w[0] * u[1].cross(u[2]) + w[1] * u[2].cross(u[0]) + w[2] * u[0].cross(u[1]);
  if (det < 0) r = -r;
  const double len = r.norm();
  return len > 0 ? Vec3(r / len) : r;
}

bool reverses_orientation(const Mat4& m) { return m.block<3, 3>(0, 0).determinant() < 0; }

Mat4 look_at(const Point3& eye, const Point3& center, const Vec3& up) {
  require_finite3(eye, "eye");
  require_finite3(center, "center");
  require_finite3(up, "up");
  Vec3 f = center - eye;
  if (!(f.norm() > 0)) fail("look_at: eye and center are the same point");
  f.normalize();
  Vec3 s = f.cross(up);
  if (!(s.norm() > 0)) fail("look_at: up vector is parallel to the view direction");
  s.normalize();
  Vec3 u = s.cross(f);
  Mat4 m = Mat4::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  return m * translate(-eye);
}

Mat4 frustum(double l, double r, double b, double t, double n, double f) {
  for (double v : {l, r, b, t, n, f}) require_finite(v, "frustum bound");
  if (l == r || b == t || n == f) fail("frustum: left/right, bottom/top and near/far must differ");
  if (!(n > 0) || !(f > 0)) fail("frustum: near and far must be positive, got near=", n, " far=", f);
  Mat4 m = Mat4::Zero();
  m(0, 0) = 2 * n / (r - l);
  m(0, 2) = (r + l) / (r - l);
  m(1, 1) = 2 * n / (t - b);
  m(1, 2) = (t + b) / (t - b);
  m(2, 2) = -(f + n) / (f - n);
  m(2, 3) = -2 * f * n / (f - n);
  m(3, 2) = -1;
  return m;
}

Mat4 perspective(double fovy, double aspect, double n, double f) {
  require_finite(fovy, "fovy");
  require_finite(aspect, "aspect");
  if (!(fovy > 0 && fovy < 180)) fail("perspective: fovy must be in (0, 180) degrees, got ", fovy);
  if (!(aspect > 0)) fail("perspective: aspect must be positive, got ", aspect);
  if (!(n > 0) || !(f > 0) || n == f) fail("perspective: need 0 < near != far, got near=", n, " far=", f);
  double cot = 1.0 / std::tan(radians(fovy) / 2);
  Mat4 m = Mat4::Zero();
  m(0, 0) = cot / aspect;
  m(1, 1) = cot;
  m(2, 2) = (f + n) / (n - f);
  m(2, 3) = 2 * f * n / (n - f);
  m(3, 2) = -1;
  return m;
}

Mat4 ortho(double l, double r, double b, double t, double n, double f) {
  for (double v : {l, r, b, t, n, f}) require_finite(v, "ortho bound");
  if (l == r || b == t || n == f) fail("ortho: left/right, bottom/top and near/far must differ");
  Mat4 m = Mat4::Identity();
  m(0, 0) = 2 / (r - l);
  m(1, 1) = 2 / (t - b);
  m(2, 2) = -2 / (f - n);
  m(0, 3) = -(r + l) / (r - l);
  m(1, 3) = -(t + b) / (t - b);
  m(2, 3) = -(f + n) / (f - n);
  return m;
}

// --- 2D ---

Mat3 identity_2d() { return Mat3::Identity(); }

Mat3 translate_2d(const Vec2& d) {
  if (!d.allFinite()) fail("translation must be finite");
  Mat3 m = Mat3::Identity();
  m(0, 2) = d.x();
  m(1, 2) = d.y();
  return m;
}

Mat3 rotate_2d(double deg) {
  double c, s;
  exact_cos_sin(deg, c, s);
  Mat3 m = Mat3::Identity();
  m(0, 0) = c; m(0, 1) = -s;
  m(1, 0) = s; m(1, 1) = c;
  return m;
}

Mat3 rotate_2d(double deg, const Point2& pivot) {
  return translate_2d(pivot) * rotate_2d(deg) * translate_2d(-pivot);
}

Mat3 scale_2d(const Vec2& k) {
  if (!k.allFinite()) fail("scale factors must be finite");
  Mat3 m = Mat3::Identity();
  m(0, 0) = k.x();
  m(1, 1) = k.y();
  return m;
}

Mat3 scale_2d(const Vec2& k, const Point2& fixed) {
  return translate_2d(fixed) * scale_2d(k) * translate_2d(-fixed);
}

Mat3 reflect_2d(const Vec2& dir, const Point2& point) {
  if (!dir.allFinite() || !(dir.norm() > 0)) fail("mirror line direction must be finite and non-zero");
  Vec2 d = dir.normalized();
  Mat3 m = Mat3::Identity();
  m.block<2, 2>(0, 0) = 2.0 * d * d.transpose() - Eigen::Matrix2d::Identity();
  return translate_2d(point) * m * translate_2d(-point);
}

Mat3 shear_x_2d(double theta) {
  require_finite(theta, "shear angle");
  // sin(180 deg) in doubles is 1.2e-16, not 0: test the angle itself, not its sine.
  if (std::fmod(theta, 180.0) == 0) fail("shear angle must not be a multiple of 180 degrees, got ", theta);
  double s = std::sin(radians(theta));
  Mat3 m = Mat3::Identity();
  m(0, 1) = std::cos(radians(theta)) / s;
  return m;
}

Mat3 shear_y_2d(double theta) {
  require_finite(theta, "shear angle");
  double s = std::sin(radians(theta));
  if (s == 0) fail("shear angle must not be a multiple of 180 degrees, got ", theta);
  Mat3 m = Mat3::Identity();
  m(1, 0) = std::cos(radians(theta)) / s;
  return m;
}

Mat3 inverse_2d(const Mat3& m) {
  if (!m.allFinite()) fail("cannot invert a matrix with non-finite entries");
  Eigen::FullPivLU<Mat3> lu(m);
  if (!lu.isInvertible()) fail("matrix is singular (rank ", lu.rank(), " of 3): it has no inverse");
  return lu.inverse();
}

Point2 apply_point_2d(const Mat3& m, const Point2& p) {
  Eigen::Vector3d h = m * p.homogeneous();
  if (h.z() == 0.0) fail("point maps to infinity (w = 0)");
  return h.head<2>() / h.z();
}

}  // namespace wedge
