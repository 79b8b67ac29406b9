// Surfaces. NURBS tensor products after The NURBS Book: derivatives of the homogeneous surface by
// A3.6 and rational derivatives by A4.4; surfaces of revolution of a NURBS curve by A8.1 (each
// control point sweeps the rational quadratic circle of A7.1). The general surface of revolution
// rotates C(v) by Rodrigues' formula, whose u-derivatives are those of cos and sin. Sweeps carry
// the profile along rotation-minimising frames from the double reflection method (Wang, Juettler,
// Zheng, Liu, ACM TOG 27(1), 2008): reflect the frame in the bisector plane of the chord, then in
// the plane that maps the reflected tangent onto the next one. Lofts blend the sections with
// cardinal natural cubic splines. Their meshes are made in tessellate/ (tessellate/surface_mesh.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "surfaces/surfaces.h"
#include "kernel/scaled.h"

namespace wedge {

namespace {

double binomial(int n, int k) {
  double r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

std::vector<double> unique_sorted(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

}  // namespace

// --- Surface ---

std::vector<double> Surface::u_breaks() const {
  auto [a, b] = u_domain();
  return {a, b};
}

std::vector<double> Surface::v_breaks() const {
  auto [a, b] = v_domain();
  return {a, b};
}

void Surface::jet(double u, double v, int d, Vec3* out) const {
  out[0] = eval(u, v);
  int i = 1;
  for (int k = 1; k <= d; ++k)
    for (int kv = 0; kv <= k; ++kv) out[i++] = derivative(u, v, k - kv, kv);
}

void Surface::jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const {
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) jet(u[i], v[j], d, out + (static_cast<std::ptrdiff_t>(i) * nv + j) * 6);
}

void Surface::eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const {
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) out[static_cast<std::ptrdiff_t>(i) * nv + j] = eval(u[i], v[j]);
}

Vec3 Surface::normal(double u, double v) const {
  auto cross_at = [&](double uu, double vv) -> Vec3 {
    Vec3 j[3];
    jet(uu, vv, 1, j);
    const Vec3 &su = j[1], &sv = j[2];
    Vec3 n = su.cross(sv);
    double size = 1e-9 * (1 + j[0].norm());
    if (su.norm() <= size || sv.norm() <= size || !(n.norm() > 1e-9 * su.norm() * sv.norm())) return Vec3::Zero();
    return Vec3(n.normalized());
  };
  Vec3 n = cross_at(u, v);
  if (n != Vec3::Zero()) return n;
  // A pole or a degenerate edge: step a little toward the middle of the domain.
  auto [u0, u1] = u_domain();
  auto [v0, v1] = v_domain();
  double um = 0.5 * (u0 + u1), vm = 0.5 * (v0 + v1);
  for (double f : {1e-7, 1e-5, 1e-3}) {
    n = cross_at(u + f * (um - u), v + f * (vm - v));
    if (n != Vec3::Zero()) return n;
  }
  return Vec3::Zero();
}

bool Surface::inside_trim(double u, double v) const {
  if (trims.empty()) return true;
  bool inside = false;
  for (const TrimLoop& loop : trims) {
    const auto& p = loop.points;
    for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
      if ((p[i].y() > v) != (p[j].y() > v) &&
          u < (p[j].x() - p[i].x()) * (v - p[i].y()) / (p[j].y() - p[i].y()) + p[i].x())
        inside = !inside;
    }
  }
  return inside;
}

// --- Plane ---

Plane::Plane(const Point3& origin, const Vec3& x_axis, const Vec3& y_axis, double u0, double u1, double v0, double v1)
    : origin_(origin), x_(x_axis), y_(y_axis), u0_(u0), u1_(u1), v0_(v0), v1_(v1) {
  if (!origin.allFinite() || !x_axis.allFinite() || !y_axis.allFinite()) fail("plane: origin and axes must be finite");
  n_ = unit_vector(x_axis.cross(y_axis));
  if (!(n_.norm() > 0)) fail("plane: the two axes must be non-zero and not parallel");
  if (!(u1 > u0) || !(v1 > v0)) fail("plane: the parameter ranges must be non-empty");
}

Plane::Plane(const Point3& origin, const Vec3& unit_normal)
    : origin_(origin), n_(unit_normal), u0_(0), u1_(1), v0_(0), v1_(1) {
  if (!origin.allFinite() || !unit_normal.allFinite()) fail("plane: origin and normal must be finite");
  if (std::abs(n_.norm() - 1) > 1e-9) {
    n_ = unit_vector(n_);
    if (!(n_.norm() > 0)) fail("plane: the normal must be non-zero");
  }
  x_ = perpendicular(n_);
  y_ = n_.cross(x_);
}

Vec3 perpendicular(const Vec3& n) {
  Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (a - a.dot(n) * n).normalized();
}

// --- Cylinder ---

Cylinder::Cylinder(const Point3& origin, const Vec3& unit_axis, double radius, double v0, double v1)
    : origin_(origin), axis_(unit_axis), radius_(radius), v0_(v0), v1_(v1) {
  if (!origin.allFinite() || !unit_axis.allFinite() || !(unit_axis.norm() > 0)) fail("cylinder: origin and axis must be finite, the axis non-zero");
  if (!(radius > 0) || !std::isfinite(radius)) fail("cylinder: the radius must be positive and finite, got ", radius);
  if (!(v1 > v0)) fail("cylinder: the parameter range along the axis must be non-empty");
  if (std::abs(axis_.norm() - 1) > 1e-9) axis_.normalize();
  x_ = perpendicular(axis_);
  y_ = axis_.cross(x_);
}

Point3 Cylinder::eval(double u, double v) const {
  double c, s;
  cos_sin(u, c, s);
  return origin_ + radius_ * (c * x_ + s * y_) + v * axis_;
}

Vec3 Cylinder::derivative(double u, double v, int ku, int kv) const {
  if (ku == 0 && kv == 0) return eval(u, v);
  if (kv > 1 || (kv == 1 && ku > 0)) return Vec3::Zero();
  if (kv == 1) return axis_;
  double c, s;  // d^k/du^k (cos u, sin u) = (cos(u + k pi/2), sin(u + k pi/2))
  cos_sin(u + ku * kPi / 2, c, s);
  return radius_ * (c * x_ + s * y_);
}

Vec3 Plane::derivative(double u, double v, int ku, int kv) const {
  if (ku == 0 && kv == 0) return eval(u, v);
  if (ku + kv > 1) return Vec3::Zero();
  return ku == 1 ? x_ : y_;
}

// --- NURBS surface ---

NurbsSurface::NurbsSurface(int udegree, int vdegree, std::vector<std::vector<Point3>> points,
                           std::vector<double> uknots, std::vector<double> vknots,
                           std::vector<std::vector<double>> weights)
    : p_(udegree), q_(vdegree), points_(std::move(points)), uknots_(std::move(uknots)), vknots_(std::move(vknots)),
      weights_(std::move(weights)) {
  if (points_.empty() || points_[0].empty()) fail("points: the control grid is empty");
  if (p_ > 30 || q_ > 30) fail("degree must be at most 30");
  std::size_t m = points_[0].size();
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (points_[i].size() != m)
      fail("points: the control grid must be rectangular: row ", i + 1, " has ", points_[i].size(), " points, row 1 has ", m);
    for (std::size_t j = 0; j < m; ++j)
      if (!points_[i][j].allFinite()) fail("points: point [", i + 1, "][", j + 1, "] is not finite");
  }
  check_knots(uknots_, p_, points_.size(), "uknots");
  check_knots(vknots_, q_, m, "vknots");
  if (weights_.empty()) weights_.assign(points_.size(), std::vector<double>(m, 1.0));
  if (weights_.size() != points_.size()) fail("weights: need one row of weights per row of points");
  for (std::size_t i = 0; i < weights_.size(); ++i) {
    if (weights_[i].size() != m) fail("weights: row ", i + 1, " must hold ", m, " weights");
    for (std::size_t j = 0; j < m; ++j)
      if (!(std::isfinite(weights_[i][j]) && weights_[i][j] > 0))
        fail("weights: weight [", i + 1, "][", j + 1, "] must be a positive finite number, got ", weights_[i][j]);
  }
}

std::pair<double, double> NurbsSurface::u_domain() const { return {uknots_[p_], uknots_[points_.size()]}; }
std::pair<double, double> NurbsSurface::v_domain() const { return {vknots_[q_], vknots_[points_[0].size()]}; }

std::vector<double> NurbsSurface::u_breaks() const {
  auto [a, b] = u_domain();
  std::vector<double> out;
  for (double k : uknots_)
    if (k >= a && k <= b) out.push_back(k);
  return unique_sorted(out);
}

std::vector<double> NurbsSurface::v_breaks() const {
  auto [a, b] = v_domain();
  std::vector<double> out;
  for (double k : vknots_)
    if (k >= a && k <= b) out.push_back(k);
  return unique_sorted(out);
}

Point3 NurbsSurface::eval(double u, double v) const {
  int nu = int(points_.size()), nv = int(points_[0].size());
  int su = find_span(nu, p_, u, uknots_), sv = find_span(nv, q_, v, vknots_);
  double Nu[31], Nv[31];
  basis_functions(su, u, p_, uknots_, Nu);
  basis_functions(sv, v, q_, vknots_, Nv);
  Vec3 a = Vec3::Zero();
  double w = 0;
  for (int k = 0; k <= p_; ++k) {
    int i = su - p_ + k;
    for (int l = 0; l <= q_; ++l) {
      int j = sv - q_ + l;
      double c = Nu[k] * Nv[l] * weights_[i][j];
      a += c * points_[i][j];
      w += c;
    }
  }
  return a / w;
}

std::vector<std::vector<Vec3>> NurbsSurface::derivatives(double u, double v, int d) const {
  int nu = int(points_.size()), nv = int(points_[0].size());
  int su = find_span(nu, p_, u, uknots_), sv = find_span(nv, q_, v, vknots_);
  auto Du = basis_derivatives(su, u, p_, d, uknots_);
  auto Dv = basis_derivatives(sv, v, q_, d, vknots_);
  std::vector<std::vector<Vec3>> A(d + 1, std::vector<Vec3>(d + 1, Vec3::Zero()));
  std::vector<std::vector<double>> W(d + 1, std::vector<double>(d + 1, 0.0));
  std::vector<Vec4> temp(q_ + 1);
  for (int k = 0; k <= d; ++k) {
    for (int s = 0; s <= q_; ++s) {
      temp[s] = Vec4::Zero();
      for (int r = 0; r <= p_; ++r) {
        int i = su - p_ + r, j = sv - q_ + s;
        double w = weights_[i][j];
        Vec4 pw;
        pw << w * points_[i][j], w;
        temp[s] += Du[k][r] * pw;
      }
    }
    for (int l = 0; k + l <= d; ++l) {
      Vec4 sum = Vec4::Zero();
      for (int s = 0; s <= q_; ++s) sum += Dv[l][s] * temp[s];
      A[k][l] = sum.head<3>();
      W[k][l] = sum[3];
    }
  }
  std::vector<std::vector<Vec3>> S(d + 1, std::vector<Vec3>(d + 1, Vec3::Zero()));
  for (int k = 0; k <= d; ++k)
    for (int l = 0; k + l <= d; ++l) {
      Vec3 v2 = A[k][l];
      for (int j = 1; j <= l; ++j) v2 -= binomial(l, j) * W[0][j] * S[k][l - j];
      for (int i = 1; i <= k; ++i) {
        v2 -= binomial(k, i) * W[i][0] * S[k - i][l];
        Vec3 v3 = Vec3::Zero();
        for (int j = 1; j <= l; ++j) v3 += binomial(l, j) * W[i][j] * S[k - i][l - j];
        v2 -= binomial(k, i) * v3;
      }
      S[k][l] = v2 / W[0][0];
    }
  return S;
}

Vec3 NurbsSurface::derivative(double u, double v, int ku, int kv) const {
  if (ku < 0 || kv < 0) fail("derivative orders must be >= 0");
  if (ku == 0 && kv == 0) return eval(u, v);
  return derivatives(u, v, ku + kv)[ku][kv];
}

NurbsSurface bezier_surface(const std::vector<std::vector<Point3>>& grid) {
  if (grid.size() < 2 || grid[0].size() < 2)
    fail("a Bezier patch needs at least 2 x 2 control points, got ", grid.size(), " x ", grid.empty() ? 0 : grid[0].size());
  int p = int(grid.size()) - 1, q = int(grid[0].size()) - 1;
  std::vector<double> U(p + 1, 0.0), V(q + 1, 0.0);
  U.insert(U.end(), p + 1, 1.0);
  V.insert(V.end(), q + 1, 1.0);
  return NurbsSurface(p, q, grid, U, V);
}

NurbsSurface bilinear_surface(const Point3& p00, const Point3& p10, const Point3& p01, const Point3& p11) {
  return bezier_surface({{p00, p01}, {p10, p11}});
}

// --- revolution ---

namespace {

// The rational quadratic arc over [0, angle] of A7.1 as (cos, sin, distance factor, weight) rows
// and its knots.
struct ArcTemplate {
  std::vector<double> c, s, scale, w, knots;
};

ArcTemplate arc_template(double angle) {
  if (!(angle > 0) || angle > 2 * kPi + 1e-12) fail("angle must be in (0, 360] degrees, got ", degrees(angle));
  int narcs = std::clamp(int(std::ceil(angle / (kPi / 2) - 1e-9)), 1, 4);
  double d = angle / narcs, w1 = std::cos(d / 2);
  ArcTemplate t;
  auto add = [&](double a, double scale, double w) {
    double c, s;
    cos_sin(a, c, s);
    t.c.push_back(c);
    t.s.push_back(s);
    t.scale.push_back(scale);
    t.w.push_back(w);
  };
  t.knots = {0, 0, 0};
  add(0, 1, 1);
  for (int i = 1; i <= narcs; ++i) {
    add((i - 0.5) * d, 1 / w1, w1);
    add(i * d, 1, 1);
    if (i < narcs) t.knots.insert(t.knots.end(), 2, double(i) / narcs);
  }
  if (angle >= 2 * kPi - 1e-15) {
    t.c.back() = 1;
    t.s.back() = 0;
  }
  t.knots.insert(t.knots.end(), 3, 1.0);
  return t;
}

Vec3 unit_axis(const Vec3& axis) {
  if (!axis.allFinite() || !(axis.norm() > 0)) fail("axis must be a non-zero vector");
  return axis.normalized();
}

}  // namespace

NurbsSurface nurbs_revolve(const NurbsCurve& curve, const Point3& point, const Vec3& axis, double angle) {
  require_finite(angle, "angle");
  if (!point.allFinite()) fail("axis point must be finite");
  Vec3 a = unit_axis(axis);
  ArcTemplate t = arc_template(angle);
  const auto& P = curve.control_points();
  const auto& Wc = curve.weights();
  std::size_t nu = t.c.size(), nv = P.size();
  std::vector<std::vector<Point3>> grid(nu, std::vector<Point3>(nv));
  std::vector<std::vector<double>> W(nu, std::vector<double>(nv));
  for (std::size_t j = 0; j < nv; ++j) {
    Point3 O = point + (P[j] - point).dot(a) * a;
    Vec3 X = P[j] - O;
    Vec3 Y = a.cross(X);
    for (std::size_t i = 0; i < nu; ++i) {
      grid[i][j] = O + t.scale[i] * (t.c[i] * X + t.s[i] * Y);
      W[i][j] = t.w[i] * Wc[j];
    }
  }
  return NurbsSurface(2, curve.degree(), std::move(grid), t.knots, curve.knots(), std::move(W));
}

NurbsSurface nurbs_sphere(const Point3& center, double radius) {
  require_positive(radius, "radius");
  NurbsCurve half = nurbs_arc(center, Vec3::UnitX(), Vec3::UnitZ(), radius, -kPi / 2, kPi / 2);
  return nurbs_revolve(half, center, Vec3::UnitZ(), 2 * kPi);
}

NurbsSurface nurbs_cylinder(const Point3& base, double radius, double height) {
  return nurbs_cone(base, radius, radius, height);
}

NurbsSurface nurbs_cone(const Point3& base, double r1, double r2, double height) {
  require_finite(r1, "r1");
  require_finite(r2, "r2");
  require_positive(height, "height");
  if (r1 < 0 || r2 < 0 || (r1 == 0 && r2 == 0)) fail("cone radii must be >= 0 and not both 0, got ", r1, " and ", r2);
  NurbsCurve side(1, {base + Vec3(r1, 0, 0), base + Vec3(r2, 0, height)}, {0, 0, 1, 1});
  return nurbs_revolve(side, base, Vec3::UnitZ(), 2 * kPi);
}

NurbsSurface nurbs_torus(const Point3& center, double major, double minor) {
  require_positive(major, "major radius");
  require_positive(minor, "minor radius");
  if (!(minor < major)) fail("torus minor radius (", minor, ") must be smaller than the major radius (", major, ")");
  NurbsCurve tube = nurbs_arc(center + Vec3(major, 0, 0), Vec3::UnitX(), Vec3::UnitZ(), minor, 0, 2 * kPi);
  return nurbs_revolve(tube, center, Vec3::UnitZ(), 2 * kPi);
}

RevolvedSurface::RevolvedSurface(CurvePtr curve, const Point3& point, const Vec3& axis, double angle)
    : curve_(std::move(curve)), point_(point), axis_(unit_axis(axis)), angle_(angle) {
  if (!curve_) fail("revolved surface: no curve");
  if (!point.allFinite()) fail("axis point must be finite");
  require_finite(angle, "angle");
  if (!(angle > 0) || angle > 2 * kPi + 1e-12) fail("angle must be in (0, 360] degrees, got ", degrees(angle));
}

Point3 RevolvedSurface::eval(double u, double v) const { return derivative(u, v, 0, 0); }

Vec3 RevolvedSurface::derivative(double u, double v, int ku, int kv) const {
  if (ku < 0 || kv < 0) fail("derivative orders must be >= 0");
  Vec3 x = curve_->derivative(v, kv);
  if (kv == 0) x -= point_;
  Vec3 along = axis_.dot(x) * axis_, perp = x - along, side = axis_.cross(x);
  double c, s;
  cos_sin(u + ku * kPi / 2, c, s);
  Vec3 r = perp * c + side * s;
  if (ku == 0) r += along + (kv == 0 ? point_ : Vec3::Zero());
  return r;
}

// --- extrusion ---

ExtrudedSurface::ExtrudedSurface(CurvePtr curve, const Vec3& direction) : curve_(std::move(curve)), direction_(direction) {
  if (!curve_) fail("extruded surface: no curve");
  if (!direction.allFinite() || direction == Vec3::Zero()) fail("extrusion vector must be a non-zero finite vector");
}

Point3 ExtrudedSurface::eval(double u, double v) const { return curve_->eval(u) + v * direction_; }

Vec3 ExtrudedSurface::derivative(double u, double v, int ku, int kv) const {
  if (ku < 0 || kv < 0) fail("derivative orders must be >= 0");
  if (kv == 0) return ku == 0 ? eval(u, v) : curve_->derivative(u, ku);
  return (kv == 1 && ku == 0) ? direction_ : Vec3::Zero();
}

// --- rotation-minimising frames and sweeps ---

namespace {

Frame reflect_step(const Frame& f, const Point3& x1, const Vec3& t1) {
  // A step of the size of rounding (x1 a few ulps from f.origin, or t1 from tL) has a direction
  // that is noise, and a reflection across it turns the frame anywhere: such a step is no step.
  Vec3 v1 = x1 - f.origin;
  double c1 = v1.squaredNorm();
  Vec3 rL = f.r, tL = f.t;
  // Relative to the points' own size (an absolute floor of 1e-24 took every step of a path 1e-20
  // long for rounding, and the frames never turned).
  if (c1 > 1e-24 * std::max(f.origin.squaredNorm(), x1.squaredNorm())) {
    rL = f.r - (2 / c1) * v1.dot(f.r) * v1;
    tL = f.t - (2 / c1) * v1.dot(f.t) * v1;
  }
  Vec3 v2 = t1 - tL;
  double c2 = v2.squaredNorm();
  Vec3 r1 = c2 > 1e-24 ? Vec3(rL - (2 / c2) * v2.dot(rL) * v2) : rL;
  // Re-orthonormalise against round-off accumulated over many steps.
  r1 = (r1 - r1.dot(t1) * t1).normalized();
  return Frame{x1, t1, r1, t1.cross(r1)};
}

double angle_of(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

Vec3 path_tangent(const Curve& path, double t) {
  Vec3 d = path.tangent(t);
  if (d == Vec3::Zero()) fail("sweep path has no tangent at parameter ", t);
  return d;
}

// Six significant digits, for a message ("90", "(0, 0, 5)"), not 17.
std::string short_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", std::abs(x) < 1e-12 ? 0.0 : x);
  return buf;
}
std::string point_text(const Point3& p) {
  return "(" + short_text(p.x()) + ", " + short_text(p.y()) + ", " + short_text(p.z()) + ")";
}

}  // namespace

// A path's tangent must be continuous: at a corner the profile's plane turns at once, the swept
// surface is torn apart there (S(u, c-) != S(u, c+)), its volume is wrong and no tolerance can
// mesh the tear. Corners of a piecewise curve lie at its breaks; there the turn across a small
// step is compared with the turn over the same step on either side, which a smooth curve keeps
// comparable and a corner does not.
void require_smooth_path(const Curve& path) {
  auto [a, b] = path.domain();
  const double h = 1e-7 * (b - a);
  for (double c : path.breaks()) {
    if (!(c - 2 * h > a && c + 2 * h < b)) continue;
    const Vec3 t0 = path_tangent(path, c - 2 * h), t1 = path_tangent(path, c - h), t2 = path_tangent(path, c + h),
               t3 = path_tangent(path, c + 2 * h);
    const double across = angle_of(t1, t2);
    if (across > 1e-6 && across > 100 * std::max(angle_of(t0, t1), angle_of(t2, t3)))
      fail("sweep: the path turns by ", short_text(degrees(across)), " degrees at ", point_text(path.eval(c)),
           ": a swept solid needs a path with a continuous tangent (round the corner, e.g. a bspline of degree 3)");
  }
}

std::vector<Frame> rotation_minimizing_frames(const Curve& path, int count) {
  if (count < 2) fail("frame count must be at least 2, got ", count);
  auto [a, b] = path.domain();
  std::vector<Frame> frames;
  Frame f;
  f.origin = path.eval(a);
  f.t = path_tangent(path, a);
  Vec3 seed = std::abs(f.t.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  f.r = (seed - seed.dot(f.t) * f.t).normalized();
  f.s = f.t.cross(f.r);
  frames.push_back(f);
  for (int i = 1; i < count; ++i) {
    double t = a + (b - a) * i / (count - 1);
    frames.push_back(reflect_step(frames.back(), path.eval(t), path_tangent(path, t)));
  }
  return frames;
}

std::shared_ptr<const SweepFrames> sweep_frames(CurvePtr path, int count, bool close_frames) {
  if (!path) fail("swept surface: missing profile or path");
  auto out = std::make_shared<SweepFrames>();
  out->path = std::move(path);
  const Curve& c = *out->path;
  out->frames = rotation_minimizing_frames(c, count);
  auto [a, b] = c.domain();
  for (int i = 0; i < count; ++i) out->params.push_back(a + (b - a) * i / (count - 1));
  if (close_frames) {
    const Frame& f0 = out->frames.front();
    const Frame& f1 = out->frames.back();
    double size = 0;
    for (const Frame& f : out->frames) size = std::max(size, (f.origin - f0.origin).norm());
    if (!c.closed() || (f1.origin - f0.origin).norm() > 1e-9 * std::max(size, 1e-300))
      fail("sweep: the path is not closed");
    if (angle_of(f0.t, f1.t) > 1e-6)
      fail("sweep: a closed path must be smooth where it closes (its tangent turns by ", degrees(angle_of(f0.t, f1.t)),
           " degrees there)");
    // The end frame is the start frame turned by phi about t: turn the profile by -phi over v.
    double phi = std::atan2(f1.r.dot(f0.s), f1.r.dot(f0.r));
    out->twist_rate = -phi / (b - a);
  }
  // (After the closing check, whose message names a corner where a closed path closes.)
  require_smooth_path(c);
  // The curvature vector kappa N at each frame (zero where the path stops or runs straight).
  for (double v : out->params) {
    const Vec3 d1 = c.derivative(v, 1), d2 = c.derivative(v, 2);
    const double L = d1.norm();
    Vec3 bend = Vec3::Zero();
    if (L > 0) {
      const Vec3 t = d1 / L, t1 = (d2 - d2.dot(t) * t) / L;  // dt/dv = |C'| kappa N
      const double k = t1.norm() / L;
      if (k > 0) bend = k * (t1 / t1.norm());
    }
    out->bend.push_back(bend);
  }
  return out;
}

SweptSurface::SweptSurface(CurvePtr profile, CurvePtr path, int frames, bool close_frames)
    : SweptSurface(std::move(profile), sweep_frames(std::move(path), frames, close_frames)) {}

SweptSurface::SweptSurface(CurvePtr profile, std::shared_ptr<const SweepFrames> frames)
    : profile_(std::move(profile)), along_(std::move(frames)) {
  if (!profile_ || !along_) fail("swept surface: missing profile or path");
  require_no_fold();
}

// With the rotation-minimising frame, S_v = |C'| (1 - kappa (p . N)) t (N the principal normal,
// p the placed profile point): where the profile reaches as far towards the centre of curvature
// as the radius of curvature, S_v vanishes and the surface folds back over itself, enclosing
// parts of space twice (a hairpin swept with a wide profile was reported valid with a wrong
// volume). Checked at the stored frames against samples of the profile.
void SweptSurface::require_no_fold() const {
  std::vector<double> us;
  const std::vector<double> br = profile_->breaks();
  for (std::size_t i = 0; i + 1 < br.size(); ++i)
    for (int k = 0; k < 16; ++k) us.push_back(br[i] + (br[i + 1] - br[i]) * k / 16);
  us.push_back(br.back());
  std::vector<Vec3> ps;  // the profile's samples (turned by the closing twist per frame below)
  for (double u : us) ps.push_back(Vec3(profile_->eval(u)));
  const double v0 = along_->path->domain().first;
  double worst = 0, worst_radius = 0, worst_reach = 0, worst_v = 0;
  for (std::size_t i = 0; i < along_->params.size(); ++i) {
    const Vec3& bend = along_->bend[i];
    const double k = bend.norm();
    if (!(k > 0)) continue;
    const double v = along_->params[i];
    const Vec3 N = bend / k;
    const Frame& f = along_->frames[i];
    double c = 1, sn = 0;
    if (along_->twist_rate != 0) c = std::cos(along_->twist_rate * (v - v0)), sn = std::sin(along_->twist_rate * (v - v0));
    for (const Vec3& q : ps) {
      const Vec3 p(c * q.x() - sn * q.y(), sn * q.x() + c * q.y(), q.z());
      const double reach = (p.x() * f.r + p.y() * f.s).dot(N);
      if (k * reach > worst) worst = k * reach, worst_radius = 1 / k, worst_reach = reach, worst_v = v;
    }
  }
  if (worst >= 1)
    fail("sweep: the path bends with radius ", short_text(worst_radius), " at ", point_text(along_->path->eval(worst_v)),
         ", but the profile reaches ", short_text(worst_reach),
         " from the path towards the bend's centre: the swept surface folds over itself there (bend the path more gently or "
         "use a smaller profile)");
}

Frame SweptSurface::frame(double v) const {
  std::size_t i = std::upper_bound(along_->params.begin(), along_->params.end(), v) - along_->params.begin();
  i = i == 0 ? 0 : std::min(i - 1, along_->params.size() - 1);
  if (v == along_->params[i]) return along_->frames[i];
  return reflect_step(along_->frames[i], along_->path->eval(v), path_tangent(*along_->path, v));
}

Vec3 SweptSurface::turned(double u, double v, int ku) const {
  Vec3 p = ku == 0 ? Vec3(profile_->eval(u)) : profile_->derivative(u, ku);
  if (along_->twist_rate == 0) return p;
  double th = along_->twist_rate * (v - along_->path->domain().first), c = std::cos(th), s = std::sin(th);
  return Vec3(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z());
}

Point3 SweptSurface::eval(double u, double v) const {
  Frame f = frame(v);
  Vec3 p = turned(u, v, 0);
  return f.origin + p.x() * f.r + p.y() * f.s + p.z() * f.t;
}

Vec3 SweptSurface::derivative(double u, double v, int ku, int kv) const {
  if (ku < 0 || kv < 0) fail("derivative orders must be >= 0");
  Frame f = frame(v);
  if (kv == 0) {
    if (ku == 0) return eval(u, v);
    Vec3 p = turned(u, v, ku);
    return p.x() * f.r + p.y() * f.s + p.z() * f.t;
  }
  // S = O + X r + Y s + z t, (X, Y) the profile's (x, y) turned by w (v - v0) (w the twist rate;
  // X' = -w Y, Y' = w X). With L = |C'| and t = C'/L (primes: d/dv):
  //   t' = (C2 - L1 t) / L with L1 = C2.t, and t'' = (C3 - L2 t - 2 L1 t') / L with L2 = C3.t + C2.t'
  // (Ck the k-th derivative of the path). A rotation-minimising frame does not turn about t, so
  // r' = -(r.t') t (and s likewise), and differentiating again (r'.t' = 0):
  // r'' = -(r.t'') t - (r.t') t'. The frame evaluated here is the double-reflection step from the
  // nearest stored frame, which turns about t only by that method's O(h^4) error, so these agree
  // with differences of eval() to that order. Orders above two, and points where C' vanishes, are
  // central differences of the analytic order below.
  Vec3 d1 = along_->path->derivative(v, 1);
  Vec3 d2 = along_->path->derivative(v, 2);
  double L = d1.norm();
  auto [a, b] = along_->path->domain();
  if (kv > 2 || !(L > 1e-12 * (1 + d2.norm()))) {
    double h = 1e-4 * (b - a);
    double c = std::clamp(v, a + h, b - h);
    return (derivative(u, c + h, ku, kv - 1) - derivative(u, c - h, ku, kv - 1)) / (2 * h);
  }
  Vec3 t = d1 / L;
  double L1 = d2.dot(t);
  Vec3 t1 = (d2 - L1 * t) / L;
  Vec3 r1 = -f.r.dot(t1) * t, s1 = -f.s.dot(t1) * t;
  Vec3 p = turned(u, v, ku);
  double w = along_->twist_rate;
  double X = p.x(), Y = p.y(), X1 = -w * Y, Y1 = w * X;
  Vec3 d;
  if (kv == 1) {
    d = (ku == 0 ? d1 : Vec3::Zero()) + X * r1 + Y * s1 + p.z() * t1 + X1 * f.r + Y1 * f.s;
  } else {
    Vec3 d3 = along_->path->derivative(v, 3);
    double L2 = d3.dot(t) + d2.dot(t1);
    Vec3 t2 = (d3 - L2 * t - 2 * L1 * t1) / L;
    Vec3 r2 = -f.r.dot(t2) * t - f.r.dot(t1) * t1, s2 = -f.s.dot(t2) * t - f.s.dot(t1) * t1;
    d = (ku == 0 ? d2 : Vec3::Zero()) + X * r2 + Y * s2 + p.z() * t2 + 2 * (X1 * r1 + Y1 * s1) - w * w * (X * f.r + Y * f.s);
  }
  return d;
}

void SweptSurface::eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const {
  // As eval(), with each column's frame and closing twist and each row's profile point once.
  std::vector<Frame> fs(static_cast<std::size_t>(nv));
  std::vector<std::array<double, 2>> turn(static_cast<std::size_t>(nv), {1.0, 0.0});
  const double w = along_->twist_rate, v0 = along_->path->domain().first;
  for (int j = 0; j < nv; ++j) {
    fs[static_cast<std::size_t>(j)] = frame(v[j]);
    if (w != 0) turn[static_cast<std::size_t>(j)] = {std::cos(w * (v[j] - v0)), std::sin(w * (v[j] - v0))};
  }
  for (int i = 0; i < nu; ++i) {
    const Vec3 q(profile_->eval(u[i]));
    for (int j = 0; j < nv; ++j) {
      const Frame& f = fs[static_cast<std::size_t>(j)];
      const auto [c, sn] = turn[static_cast<std::size_t>(j)];
      const Vec3 p = w == 0 ? q : Vec3(c * q.x() - sn * q.y(), sn * q.x() + c * q.y(), q.z());
      out[static_cast<std::ptrdiff_t>(i) * nv + j] = f.origin + p.x() * f.r + p.y() * f.s + p.z() * f.t;
    }
  }
}

void SweptSurface::jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const {
  if (d != 1) {
    Surface::jet_grid(u, nu, v, nv, d, out);
    return;
  }
  // As jet() at d = 1, with each column's path jet, frame and twist and each row's profile jet
  // once (a column where the path stops goes point by point, as jet() does).
  struct Column {
    bool ok = false;
    Vec3 p1;
    Frame f;
    Vec3 r1, s1, t1;
    double ct = 1, st = 0;
  };
  std::vector<Column> cols(static_cast<std::size_t>(nv));
  const double w = along_->twist_rate;
  for (int j = 0; j < nv; ++j) {
    Column& col = cols[static_cast<std::size_t>(j)];
    Vec3 P[3];
    along_->path->jet(v[j], 2, P);
    const double L = P[1].norm();
    if (!(L > 1e-12 * (1 + P[2].norm()))) continue;
    col.ok = true;
    col.p1 = P[1];
    const Vec3 t = P[1] / L;
    std::size_t i = static_cast<std::size_t>(std::upper_bound(along_->params.begin(), along_->params.end(), v[j]) - along_->params.begin());
    i = i == 0 ? 0 : std::min(i - 1, along_->params.size() - 1);
    col.f = v[j] == along_->params[i] ? along_->frames[i] : reflect_step(along_->frames[i], P[0], t);
    if (w != 0) {
      const double th = w * (v[j] - along_->path->domain().first);
      col.ct = std::cos(th), col.st = std::sin(th);
    }
    const double L1 = P[2].dot(t);
    col.t1 = (P[2] - L1 * t) / L;
    col.r1 = -col.f.r.dot(col.t1) * t, col.s1 = -col.f.s.dot(col.t1) * t;
  }
  for (int i = 0; i < nu; ++i) {
    Vec3 c0[2];
    profile_->jet(u[i], 1, c0);
    for (int j = 0; j < nv; ++j) {
      Vec3* o = out + (static_cast<std::ptrdiff_t>(i) * nv + j) * 6;
      const Column& col = cols[static_cast<std::size_t>(j)];
      if (!col.ok) {
        jet(u[i], v[j], 1, o);
        continue;
      }
      Vec3 c[2] = {c0[0], c0[1]};
      if (w != 0)
        for (int k = 0; k <= 1; ++k) c[k] = Vec3(col.ct * c[k].x() - col.st * c[k].y(), col.st * c[k].x() + col.ct * c[k].y(), c[k].z());
      const Frame& f = col.f;
      auto place = [&](const Vec3& p) -> Vec3 { return p.x() * f.r + p.y() * f.s + p.z() * f.t; };
      o[0] = f.origin + place(c[0]);
      o[1] = place(c[1]);
      o[2] = col.p1 + (c[0].x() * col.r1 + c[0].y() * col.s1 + c[0].z() * col.t1 - w * c[0].y() * f.r + w * c[0].x() * f.s);
    }
  }
}

void SweptSurface::jet(double u, double v, int d, Vec3* out) const {
  // derivative()'s formulas with the path, the frame and the profile evaluated once.
  Vec3 P[4];
  along_->path->jet(v, d + 1, P);
  const double L = P[1].norm();
  if (d > 2 || !(L > 1e-12 * (1 + P[2].norm()))) {
    Surface::jet(u, v, d, out);
    return;
  }
  const Vec3 t = P[1] / L;
  std::size_t i = static_cast<std::size_t>(std::upper_bound(along_->params.begin(), along_->params.end(), v) - along_->params.begin());
  i = i == 0 ? 0 : std::min(i - 1, along_->params.size() - 1);
  const Frame f = v == along_->params[i] ? along_->frames[i] : reflect_step(along_->frames[i], P[0], t);
  Vec3 c[3];
  profile_->jet(u, d, c);
  if (along_->twist_rate != 0) {
    double th = along_->twist_rate * (v - along_->path->domain().first), ct = std::cos(th), st = std::sin(th);
    for (int k = 0; k <= d; ++k) c[k] = Vec3(ct * c[k].x() - st * c[k].y(), st * c[k].x() + ct * c[k].y(), c[k].z());
  }
  auto place = [&](const Vec3& p) -> Vec3 { return p.x() * f.r + p.y() * f.s + p.z() * f.t; };
  const double L1 = P[2].dot(t);
  const Vec3 t1 = (P[2] - L1 * t) / L;
  const Vec3 r1 = -f.r.dot(t1) * t, s1 = -f.s.dot(t1) * t;
  const double w = along_->twist_rate;
  // The v derivative of the placed profile point p (its turn by the twist included).
  auto along = [&](const Vec3& p) -> Vec3 {
    return p.x() * r1 + p.y() * s1 + p.z() * t1 - w * p.y() * f.r + w * p.x() * f.s;
  };
  out[0] = f.origin + place(c[0]);
  out[1] = place(c[1]);
  out[2] = P[1] + along(c[0]);
  if (d == 2) {
    const double L2 = P[3].dot(t) + P[2].dot(t1);
    const Vec3 t2 = (P[3] - L2 * t - 2 * L1 * t1) / L;
    const Vec3 r2 = -f.r.dot(t2) * t - f.r.dot(t1) * t1, s2 = -f.s.dot(t2) * t - f.s.dot(t1) * t1;
    const double X = c[0].x(), Y = c[0].y();
    out[3] = place(c[2]);
    out[4] = along(c[1]);
    out[5] = P[2] + X * r2 + Y * s2 + c[0].z() * t2 + 2 * (-w * Y * r1 + w * X * s1) - w * w * (X * f.r + Y * f.s);
  }
}

// --- lofting ---

LoftedSurface::LoftedSurface(std::vector<CurvePtr> sections, std::vector<double> params) : sections_(std::move(sections)) {
  std::size_t n = sections_.size();
  if (n < 2) fail("a loft needs at least 2 sections, got ", n);
  for (std::size_t i = 0; i < n; ++i)
    if (!sections_[i]) fail("loft: section ", i + 1, " is missing");
  std::vector<double> v(n);
  if (params.empty()) {
    for (std::size_t i = 0; i < n; ++i) v[i] = double(i) / double(n - 1);
  } else {
    if (params.size() != n) fail("loft: ", n, " sections but ", params.size(), " parameters");
    if (params.front() != 0 || params.back() != 1) fail("loft: section parameters must run from 0 to 1");
    for (std::size_t i = 1; i < n; ++i)
      if (!(params[i] > params[i - 1])) fail("loft: section parameters must increase (parameter ", i + 1, " is ", params[i], ")");
    v = std::move(params);
  }
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<Point3> e(n, Point3::Zero());
    e[i] = Point3(1, 0, 0);
    cardinal_.push_back(natural_spline(v, e));
  }
}

std::vector<double> LoftedSurface::v_breaks() const { return cardinal_[0].params(); }

Point3 LoftedSurface::eval(double u, double v) const { return derivative(u, v, 0, 0); }

void LoftedSurface::eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const {
  std::vector<Vec3> j(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv) * 6);
  grid(u, nu, v, nv, 0, j.data());
  for (std::size_t k = 0; k < static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv); ++k) out[k] = j[k * 6];
}

void LoftedSurface::jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const {
  if (d != 1) {
    Surface::jet_grid(u, nu, v, nv, d, out);
    return;
  }
  grid(u, nu, v, nv, 1, out);
}

// derivative()'s sums at every grid point (out[...6 per point]: S, and with d = 1 Su and Sv),
// with each column's blending weights and each row's section points computed once.
void LoftedSurface::grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const {
  const std::size_t n = sections_.size(), cols = static_cast<std::size_t>(nv);
  std::vector<double> N(cols * n), N1(d ? cols * n : 0);
  for (std::size_t j = 0; j < cols; ++j)
    for (std::size_t i = 0; i < n; ++i) {
      N[j * n + i] = cardinal_[i].derivative(v[j], 0).x();
      if (d) N1[j * n + i] = cardinal_[i].derivative(v[j], 1).x();
    }
  std::vector<Vec3> C(n), C1(n);
  std::vector<double> len(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto [a, b] = sections_[i]->domain();
    len[i] = b - a;
  }
  for (int r = 0; r < nu; ++r) {
    for (std::size_t i = 0; i < n; ++i) {
      auto [a, b] = sections_[i]->domain();
      C[i] = sections_[i]->derivative(a + u[r] * (b - a), 0);
      if (d) C1[i] = sections_[i]->derivative(a + u[r] * (b - a), 1);
    }
    for (std::size_t j = 0; j < cols; ++j) {
      Vec3* o = out + (static_cast<std::ptrdiff_t>(r) * nv + static_cast<std::ptrdiff_t>(j)) * 6;
      Vec3 s = Vec3::Zero(), su = Vec3::Zero(), sv = Vec3::Zero();
      for (std::size_t i = 0; i < n; ++i) {
        const double w = N[j * n + i];
        if (w != 0) {
          s += w * std::pow(len[i], 0) * C[i];
          if (d) su += w * std::pow(len[i], 1) * C1[i];
        }
        if (d && N1[j * n + i] != 0) sv += N1[j * n + i] * std::pow(len[i], 0) * C[i];
      }
      o[0] = s;
      if (d) o[1] = su, o[2] = sv;
    }
  }
}

Vec3 LoftedSurface::derivative(double u, double v, int ku, int kv) const {
  if (ku < 0 || kv < 0) fail("derivative orders must be >= 0");
  Vec3 s = Vec3::Zero();
  for (std::size_t i = 0; i < sections_.size(); ++i) {
    double N = cardinal_[i].derivative(v, kv).x();
    if (N == 0) continue;
    auto [a, b] = sections_[i]->domain();
    s += N * std::pow(b - a, ku) * sections_[i]->derivative(a + u * (b - a), ku);
  }
  return s;
}

}  // namespace wedge
