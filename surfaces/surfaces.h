// wedge::surfaces — curves and surfaces. The interfaces every curve and surface implements, and
// the concrete kinds: line, circular arc, Bezier, B-spline and NURBS curves (with the exact
// conics), interpolating splines (polynomial, natural cubic, Hermite / Catmull-Rom /
// Kochanek-Bartels, global NURBS interpolation), and the surfaces built on them (plane, bilinear,
// Bezier and NURBS tensor products, exact quadrics, revolved, extruded, swept, lofted, the teapot).
// Every bad argument throws wedge::Error naming the argument and saying why it is bad.
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "kernel/kernel.h"

namespace wedge {

// ---------------------------------------------------------------------------------------------
// Interfaces

// A parametric curve C(t) in 3D (2D curves have z = 0) over the interval [t0, t1].
class Curve {
 public:
  virtual ~Curve() = default;
  virtual std::pair<double, double> domain() const = 0;
  virtual Point3 eval(double t) const = 0;
  // The k-th derivative at t (k = 0 is the point itself).
  virtual Vec3 derivative(double t, int k) const = 0;
  // The point and its derivatives up to order d <= 3 at once, out[0..d] (what a tessellator asks
  // for at every sample: one span search and one set of basis functions instead of d + 1).
  virtual void jet(double t, int d, Vec3* out) const;
  // Parameters where the curve may lose smoothness (knots, segment joints), domain ends included.
  // Tessellation and quadrature split there first.
  virtual std::vector<double> breaks() const;
  // True if C(t0) == C(t1): a closed curve is a profile.
  virtual bool closed() const;
  // True if C is affine in t (a straight piece run at constant speed): quadrature along it can be
  // exact with a few points.
  virtual bool affine() const { return false; }

  // Unit tangent (zero where the curve stops).
  Vec3 tangent(double t) const;
  // Arc length over [a, b] (default: the whole domain) by adaptive Gauss-Legendre quadrature (5 points, split until halves agree).
  double length() const;
  double length(double a, double b) const;
  // Polyline whose chords stay within `tolerance` of the curve (recursive subdivision checked at
  // interior samples of each chord). Returns the parameters; points(...) their positions.
  std::vector<double> parameters(double tolerance) const;
  std::vector<Point3> points(double tolerance) const;
};

using CurvePtr = std::shared_ptr<const Curve>;

// A closed polyline in the (u, v) parameter plane. The outer loop runs counter-clockwise, holes
// clockwise; the B-Rep uses these as a face's boundary on its surface.
struct TrimLoop {
  std::vector<Vec2> points;
};

// A parametric surface S(u, v) over [u0, u1] x [v0, v1].
class Surface {
 public:
  virtual ~Surface() = default;
  virtual std::pair<double, double> u_domain() const = 0;
  virtual std::pair<double, double> v_domain() const = 0;
  virtual Point3 eval(double u, double v) const = 0;
  // The partial derivative d^(ku+kv) S / du^ku dv^kv.
  virtual Vec3 derivative(double u, double v, int ku, int kv) const = 0;
  // The point and its partial derivatives up to order d (1 or 2) at once: out = S, Su, Sv and for
  // d = 2 also Suu, Suv, Svv (surfaces made from curves evaluate their curves once for all).
  virtual void jet(double u, double v, int d, Vec3* out) const;
  // jet() at every (u[i], v[j]) of a grid, the same values: out[(i * nv + j) * 6 + k] (six
  // entries per point for d = 1 too). A surface of revolution turns each profile point by one
  // sine and cosine per column instead of evaluating its profile and angle at every point.
  virtual void jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const;
  // eval() at every (u[i], v[j]) of a grid, the same values: out[i * nv + j].
  virtual void eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const;
  // True if, over each interval between u breaks, S is affine in u and so is |Su x Sv|: the
  // mass integrands (x.N, x x^T N, ...) are then polynomials of degree at most 4 in u, which a
  // 3-point Gauss rule integrates exactly (brep/mass.cpp).
  virtual bool affine_area_in_u() const { return false; }
  // Parameters where the surface may lose smoothness in u / in v (domain ends included).
  virtual std::vector<double> u_breaks() const;
  virtual std::vector<double> v_breaks() const;
  // The unit normal Su x Sv. Where that vanishes (a pole), the normal is taken a small step inside
  // the domain; zero only if the surface is degenerate there too.
  Vec3 normal(double u, double v) const;

  // Trimming: the part of the domain kept is inside the outer loops and outside the holes (even-odd
  // rule over all loops). No loops: the whole domain.
  std::vector<TrimLoop> trims;
  bool inside_trim(double u, double v) const;
  // (Its meshes are made by tessellate/surface_mesh.h.)
};

using SurfacePtr = std::shared_ptr<const Surface>;

// ---------------------------------------------------------------------------------------------
// B-spline basis (The NURBS Book, chapter 2)

// Throws wedge::Error saying in words why `knots` cannot carry `count` control points of this
// degree: wrong length, a decreasing knot, a multiplicity above degree + 1, NaN.
void check_knots(const std::vector<double>& knots, int degree, std::size_t count, const char* what = "knots");
// Throws unless every weight is finite and > 0.
void check_weights(const std::vector<double>& weights, std::size_t count, const char* what = "weights");
// A2.1: the span index i with knots[i] <= u < knots[i+1] (the last non-empty span at the end).
int find_span(int n, int degree, double u, const std::vector<double>& knots);
// A2.2: the degree + 1 non-zero basis functions N[i-p..i] at u.
void basis_functions(int span, double u, int degree, const std::vector<double>& knots, double* N);
// A2.3: the basis functions and their derivatives up to order d: ders[k][j] = N^(k)_{span-p+j}(u).
std::vector<std::vector<double>> basis_derivatives(int span, double u, int degree, int d,
                                                    const std::vector<double>& knots);
// The same into ders[k * (degree + 1) + j], k <= d, with no allocation (degree <= 31).
void basis_derivatives(int span, double u, int degree, int d, const std::vector<double>& knots, double* ders);
// Knot vectors: clamped with uniform interior knots over [0, 1], and unclamped uniform 0, 1, 2, ...
std::vector<double> open_uniform_knots(int degree, std::size_t count);
std::vector<double> uniform_knots(int degree, std::size_t count);

// ---------------------------------------------------------------------------------------------
// Curves

class LineSegment : public Curve {
 public:
  LineSegment(const Point3& a, const Point3& b);
  std::pair<double, double> domain() const override { return {0.0, 1.0}; }
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;
  bool affine() const override { return true; }
  Point3 a, b;
};

// The trigonometric arc C(t) = c + r (cos t x + sin t y), t in [start, end] (radians), with
// y = normal x x; x is `x_axis` made perpendicular to the normal, or a default when zero.
class CircularArc : public Curve {
 public:
  CircularArc(const Point3& center, double radius, double start, double end, const Vec3& normal = Vec3::UnitZ(),
              const Vec3& x_axis = Vec3::Zero());
  std::pair<double, double> domain() const override { return {start_, end_}; }
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;
  void jet(double t, int d, Vec3* out) const override;
  bool closed() const override;

  const Point3& center() const { return center_; }
  double radius() const { return radius_; }
  Vec3 normal() const { return x_.cross(y_); }  // the arc runs counter-clockwise about it
  const Vec3& x_axis() const { return x_; }
  // The same points run the other way (C'(t) = C(-t) about the negated normal, over [-end, -start]).
  CircularArc reversed() const;
  // The image under m, run in the same direction. m must be a similarity (a mirror included):
  // anything else turns the circle into an ellipse (a TransformedCurve then).
  CircularArc transformed(const Mat4& m) const;

 private:
  Point3 center_;
  double radius_, start_, end_;
  Vec3 x_, y_;
};

// The arc from a through m to b (three distinct, non-collinear points): angle 0 at a, counter-
// clockwise about the normal of a, m, b, ending at b.
CircularArc arc_through(const Point3& a, const Point3& m, const Point3& b);

// A Bezier curve of any degree, evaluated by de Casteljau over [0, 1].
class BezierCurve : public Curve {
 public:
  explicit BezierCurve(std::vector<Point3> points);
  std::pair<double, double> domain() const override { return {0.0, 1.0}; }
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;
  void jet(double t, int d, Vec3* out) const override;
  int degree() const { return int(points_.size()) - 1; }
  const std::vector<Point3>& control_points() const { return points_; }
  // The two halves at t, each over [0, 1].
  std::pair<BezierCurve, BezierCurve> subdivide(double t) const;
  // The same curve as a Bezier of degree + 1.
  BezierCurve elevated() const;

 private:
  std::vector<Point3> points_;
};

// A NURBS curve: degree p, control points P_i, weights w_i > 0 (all 1: a B-spline), knots of
// length n + p + 1. Evaluation by A4.1 / A3.1 on homogeneous points, derivatives by A3.2 + A4.2.
class NurbsCurve : public Curve {
 public:
  NurbsCurve(int degree, std::vector<Point3> points, std::vector<double> knots, std::vector<double> weights = {});
  std::pair<double, double> domain() const override;
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;
  void jet(double t, int d, Vec3* out) const override;
  std::vector<double> breaks() const override;
  // All derivatives 0..d at t (cheaper than d + 1 calls).
  std::vector<Vec3> derivatives(double t, int d) const;

  int degree() const { return degree_; }
  const std::vector<Point3>& control_points() const { return points_; }
  const std::vector<double>& knots() const { return knots_; }
  const std::vector<double>& weights() const { return weights_; }
  bool rational() const;

  // Boehm knot insertion (A5.1, one knot at a time): the same curve with knot u inserted `times`
  // times, never beyond multiplicity = degree.
  NurbsCurve with_knot(double u, int times = 1) const;
  // A5.8: knot u removed up to `times` times, as far as the curve stays within `tolerance`
  // (absolute, in homogeneous coordinates); the inverse of with_knot.
  NurbsCurve without_knot(double u, int times = 1, double tolerance = 1e-9) const;
  // The same curve with degree + 1: split into Bezier segments, elevate each, then remove the knots
  // that elevation made redundant (A5.9's result: each interior knot's multiplicity grows by one).
  NurbsCurve elevated() const;
  // The Bezier segments (as NurbsCurves on their own knot intervals), by knot insertion.
  std::vector<NurbsCurve> bezier_segments() const;

 private:
  int degree_;
  std::vector<Point3> points_;
  std::vector<double> knots_;
  std::vector<double> weights_;
};

// Exact conics as rational quadratic NURBS (A7.1). Angles in radians, measured from x_axis toward
// y_axis; the arc of any angle up to 2 pi is split into at most four pieces of <= 90 degrees.
NurbsCurve nurbs_arc(const Point3& center, const Vec3& x_axis, const Vec3& y_axis, double radius, double start,
                     double end);
NurbsCurve nurbs_circle(const Point3& center, double radius, const Vec3& normal = Vec3::UnitZ());
NurbsCurve nurbs_ellipse(const Point3& center, const Vec3& x_axis, const Vec3& y_axis, double rx, double ry);
// Curves that are piecewise polynomial or rational can convert exactly.
NurbsCurve to_nurbs(const BezierCurve& c);
NurbsCurve to_nurbs(const LineSegment& c);

// A9.1: the NURBS curve of this degree through the points, chord-length parameters and averaged
// knots (non-rational).
NurbsCurve interpolate_nurbs(const std::vector<Point3>& points, int degree = 3);

// The polynomial of degree k-1 through k points at uniform parameters over [0, 1], evaluated by
// Neville's scheme (its derivatives by the differentiated recurrence). Oscillates for large k
// (Runge): that is what it is for.
class PolynomialInterpolant : public Curve {
 public:
  explicit PolynomialInterpolant(std::vector<Point3> points);
  std::pair<double, double> domain() const override { return {0.0, 1.0}; }
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;

 private:
  std::vector<Point3> points_;
  std::vector<double> params_;
};

// A piecewise cubic Hermite curve: at parameters t_i it passes through P_i with derivative D_i.
// The base of the natural spline and of the Catmull-Rom / Kochanek-Bartels family.
class HermiteSpline : public Curve {
 public:
  HermiteSpline(std::vector<double> params, std::vector<Point3> points, std::vector<Vec3> tangents);
  // Separate outgoing (start of segment i) and incoming (end of segment i - 1) tangents: C0 only.
  HermiteSpline(std::vector<double> params, std::vector<Point3> points, std::vector<Vec3> out_tangents,
                std::vector<Vec3> in_tangents);
  std::pair<double, double> domain() const override { return {params_.front(), params_.back()}; }
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;
  std::vector<double> breaks() const override { return params_; }
  // The exact NURBS form: cubic, each segment a Bezier piece (joint knots of multiplicity 3).
  NurbsCurve to_nurbs() const;
  const std::vector<double>& params() const { return params_; }

 private:
  std::vector<double> params_;
  std::vector<Point3> points_;
  std::vector<Vec3> out_, in_;
};

// The natural cubic spline through the points (C2, zero second derivative at the ends),
// chord-length parameters, second derivatives from one tridiagonal solve.
HermiteSpline natural_spline(const std::vector<Point3>& points);
// The same at given increasing parameters.
HermiteSpline natural_spline(const std::vector<double>& params, const std::vector<Point3>& points);

// Kochanek-Bartels: tension, bias and continuity (all 0: Catmull-Rom), uniform parameters 0..n-1
// (0..n if closed). An open spline takes its end tangents from mirrored phantom points.
HermiteSpline kochanek_bartels(const std::vector<Point3>& points, double tension = 0, double bias = 0,
                               double continuity = 0, bool closed = false);
HermiteSpline catmull_rom(const std::vector<Point3>& points, bool closed = false);

// ---------------------------------------------------------------------------------------------
// Surfaces

// The plane origin + u x_axis + v y_axis over the given domain.
class Plane : public Surface {
 public:
  Plane(const Point3& origin, const Vec3& x_axis, const Vec3& y_axis, double u0 = 0, double u1 = 1, double v0 = 0,
        double v1 = 1);
  // The plane through origin with this unit normal, x_axis = perpendicular(normal) and
  // y_axis = normal x x_axis (so Su x Sv = normal), over [0, 1]^2: a B-Rep face's plane, bounded by
  // the face's loops rather than by the domain.
  Plane(const Point3& origin, const Vec3& unit_normal);
  std::pair<double, double> u_domain() const override { return {u0_, u1_}; }
  std::pair<double, double> v_domain() const override { return {v0_, v1_}; }
  Point3 eval(double u, double v) const override { return origin_ + u * x_ + v * y_; }
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  const Point3& origin() const { return origin_; }
  const Vec3& x_axis() const { return x_; }
  const Vec3& y_axis() const { return y_; }
  const Vec3& unit_normal() const { return n_; }  // x_axis x y_axis, normalised

 private:
  Point3 origin_;
  Vec3 x_, y_, n_;
  double u0_, u1_, v0_, v1_;
};

// A unit vector perpendicular to the unit vector n (x, or y when n is near x, made perpendicular).
Vec3 perpendicular(const Vec3& n);

// The circular cylinder S(u, v) = origin + radius (cos u x + sin u y) + v axis, with
// x = perpendicular(axis), y = axis x x; u in [0, 2 pi], v in [v0, v1] (default [0, 1]; a B-Rep
// face bounds it by its loops). Su x Sv points away from the axis.
class Cylinder : public Surface {
 public:
  Cylinder(const Point3& origin, const Vec3& unit_axis, double radius, double v0 = 0, double v1 = 1);
  std::pair<double, double> u_domain() const override { return {0.0, 2 * kPi}; }
  std::pair<double, double> v_domain() const override { return {v0_, v1_}; }
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  const Point3& origin() const { return origin_; }
  const Vec3& axis() const { return axis_; }
  double radius() const { return radius_; }

 private:
  Point3 origin_;
  Vec3 axis_, x_, y_;
  double radius_, v0_, v1_;
};

// A NURBS tensor-product surface: points[i][j] with i along u, j along v. Evaluation and
// derivatives by A3.6 on homogeneous points and A4.4.
class NurbsSurface : public Surface {
 public:
  NurbsSurface(int udegree, int vdegree, std::vector<std::vector<Point3>> points, std::vector<double> uknots,
               std::vector<double> vknots, std::vector<std::vector<double>> weights = {});
  std::pair<double, double> u_domain() const override;
  std::pair<double, double> v_domain() const override;
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  std::vector<double> u_breaks() const override;
  std::vector<double> v_breaks() const override;
  // SKL[k][l] for k + l <= d.
  std::vector<std::vector<Vec3>> derivatives(double u, double v, int d) const;

  int udegree() const { return p_; }
  int vdegree() const { return q_; }
  const std::vector<std::vector<Point3>>& control_points() const { return points_; }
  const std::vector<std::vector<double>>& weights() const { return weights_; }
  const std::vector<double>& uknots() const { return uknots_; }
  const std::vector<double>& vknots() const { return vknots_; }

 private:
  int p_, q_;
  std::vector<std::vector<Point3>> points_;
  std::vector<double> uknots_, vknots_;
  std::vector<std::vector<double>> weights_;
};

// Bezier patch of any degree (grid[i][j], i along u) and the bilinear patch, as NURBS.
NurbsSurface bezier_surface(const std::vector<std::vector<Point3>>& grid);
NurbsSurface bilinear_surface(const Point3& p00, const Point3& p10, const Point3& p01, const Point3& p11);
// A8.1: the exact NURBS surface of revolution of a NURBS curve about the axis through `point`
// along `axis`, by `angle` radians (u: around the axis, v: along the curve).
NurbsSurface nurbs_revolve(const NurbsCurve& curve, const Point3& point, const Vec3& axis, double angle);
// Exact quadrics and the torus, as NURBS (axis +Z through the origin-side centre).
NurbsSurface nurbs_sphere(const Point3& center, double radius);
NurbsSurface nurbs_cylinder(const Point3& base, double radius, double height);
NurbsSurface nurbs_cone(const Point3& base, double r1, double r2, double height);
NurbsSurface nurbs_torus(const Point3& center, double major, double minor);

// The surface of revolution of any curve: S(u, v) = rotation by u about the axis of C(v),
// u in [0, angle] (radians). Exact, with analytic derivatives.
class RevolvedSurface : public Surface {
 public:
  RevolvedSurface(CurvePtr curve, const Point3& point, const Vec3& axis, double angle);
  std::pair<double, double> u_domain() const override { return {0.0, angle_}; }
  std::pair<double, double> v_domain() const override { return curve_->domain(); }
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  std::vector<double> v_breaks() const override { return curve_->breaks(); }

 private:
  CurvePtr curve_;
  Point3 point_;
  Vec3 axis_;
  double angle_;
};

// S(u, v) = C(u) + v * direction, v in [0, 1].
class ExtrudedSurface : public Surface {
 public:
  ExtrudedSurface(CurvePtr curve, const Vec3& direction);
  std::pair<double, double> u_domain() const override { return curve_->domain(); }
  std::pair<double, double> v_domain() const override { return {0.0, 1.0}; }
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  std::vector<double> u_breaks() const override { return curve_->breaks(); }

 private:
  CurvePtr curve_;
  Vec3 direction_;
};

// An orthonormal frame along a path: tangent t, and r, s spanning the normal plane (r x s = t).
struct Frame {
  Point3 origin;
  Vec3 t, r, s;
};

// Rotation-minimising frames along a curve by the double reflection method (Wang, Juettler,
// Zheng, Liu, "Computation of rotation minimizing frames", ACM TOG 27(1), 2008), at `count`
// uniformly spaced parameters (ends included).
std::vector<Frame> rotation_minimizing_frames(const Curve& path, int count);

// Throws unless the tangent of `path` is continuous (no corner: a sweep along it would tear).
void require_smooth_path(const Curve& path);

// A profile (its x, y in the path's normal plane: x along r, y along s) swept along a 3D path with
// rotation-minimising frames. u: along the profile, v: along the path. The frame at any v is the
// double-reflection step from the nearest precomputed frame, so it is continuous. The v
// derivatives up to order 2 are analytic (the RMF does not turn about the tangent:
// r' = -(r.t') t); higher orders are central differences of those.
// `close_frames` (a closed, smooth path): the RMF comes back turned about the tangent by its
// holonomy angle; the profile is turned against it linearly along v, so that S(u, v1) = S(u, v0)
// and the swept surface closes into a ring. Throws if the path is not closed or has a corner
// where it closes, if the path has a corner anywhere (its tangent jumps: the surface would tear
// there), or if it bends tighter than the profile reaches from it (the surface would fold).
// The frames a swept surface turns its profile by: `count` rotation-minimising frames along the
// path (the checks SweptSurface's constructor names: closed and smooth where it closes with
// `close_frames`, no corner), made once and shared by the faces of one sweep (a sweep of a
// 5,000-point profile made and held 5,000 copies: 290 MB).
struct SweepFrames {
  CurvePtr path;
  std::vector<Frame> frames;
  std::vector<double> params;
  std::vector<Vec3> bend;  // per frame: the path's curvature vector kappa N (zero where none)
  double twist_rate = 0;   // the closing twist: the profile's turn per unit v
};
std::shared_ptr<const SweepFrames> sweep_frames(CurvePtr path, int count = 512, bool close_frames = false);

class SweptSurface : public Surface {
 public:
  SweptSurface(CurvePtr profile, CurvePtr path, int frames = 512, bool close_frames = false);
  SweptSurface(CurvePtr profile, std::shared_ptr<const SweepFrames> frames);
  std::pair<double, double> u_domain() const override { return profile_->domain(); }
  std::pair<double, double> v_domain() const override { return along_->path->domain(); }
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  void jet(double u, double v, int d, Vec3* out) const override;
  void jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const override;
  void eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const override;
  std::vector<double> u_breaks() const override { return profile_->breaks(); }
  // The path's own (a Catmull-Rom or B-spline path bends unevenly across its knots).
  std::vector<double> v_breaks() const override { return along_->path->breaks(); }
  Frame frame(double v) const;
  // The turn of the profile per unit v (radians; 0 unless close_frames).
  double twist_rate() const { return along_->twist_rate; }

 private:
  CurvePtr profile_;
  std::shared_ptr<const SweepFrames> along_;
  // The profile's point (or u-derivative of order ku) turned by the closing twist at v.
  Vec3 turned(double u, double v, int ku) const;
  // Throws where the profile reaches the centre of the path's curvature (the surface folds).
  void require_no_fold() const;
};

// The skinned surface through section curves C_0..C_{n-1}: S(u, v) = sum_i C_i(u) N_i(v) with N_i
// the cardinal natural cubic splines on increasing v_i from 0 to 1 (by default i / (n - 1)); linear
// for two sections: a ruled surface. S(u, v_i) = C_i(u). Sections are reparametrised linearly onto
// [0, 1]. A natural spline reproduces linear data exactly, so sections placed at heights z_i with
// v_i = (z_i - z_0) / (z_{n-1} - z_0) give z(u, v) linear in v: the surface neither leaves the slab
// of the sections nor folds back in z, and identical sections give a straight prism (with
// uniform v_i, heights {0, 0.1, 1} made z dip below 0 and fold back on itself).
class LoftedSurface : public Surface {
 public:
  explicit LoftedSurface(std::vector<CurvePtr> sections, std::vector<double> params = {});
  std::pair<double, double> u_domain() const override { return {0.0, 1.0}; }
  std::pair<double, double> v_domain() const override { return {0.0, 1.0}; }
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  void jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const override;
  void eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const override;
  std::vector<double> v_breaks() const override;

 private:
  std::vector<CurvePtr> sections_;
  std::vector<HermiteSpline> cardinal_;
  void grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const;
};

// ---------------------------------------------------------------------------------------------
// Curves and surfaces made from others (surfaces/derived.cpp): what the B-Rep builders attach to
// edges and faces. Each keeps its source alive through the shared pointer.

// C(t0 + t1 - t): the same points run the other way, over the same domain.
class ReversedCurve : public Curve {
 public:
  explicit ReversedCurve(CurvePtr c);
  std::pair<double, double> domain() const override { return curve_->domain(); }
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;
  void jet(double t, int d, Vec3* out) const override;
  std::vector<double> breaks() const override;
  bool affine() const override { return curve_->affine(); }

 private:
  CurvePtr curve_;
};

// The piece of a curve over [a, b] (inside its domain), with the curve's own parameter.
class SubCurve : public Curve {
 public:
  SubCurve(CurvePtr c, double a, double b);
  std::pair<double, double> domain() const override { return {a_, b_}; }
  Point3 eval(double t) const override { return curve_->eval(t); }
  Vec3 derivative(double t, int k) const override { return curve_->derivative(t, k); }
  void jet(double t, int d, Vec3* out) const override { curve_->jet(t, d, out); }
  std::vector<double> breaks() const override;
  bool affine() const override { return curve_->affine(); }
  const CurvePtr& source() const { return curve_; }

 private:
  CurvePtr curve_;
  double a_, b_;
};

// An iso-parameter line of a surface: t -> S(t, value) (along u) or S(value, t) (along v), over
// [a, b] of that parameter.
class IsoCurve : public Curve {
 public:
  IsoCurve(SurfacePtr s, bool along_u, double value, double a, double b);
  std::pair<double, double> domain() const override { return {a_, b_}; }
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;
  std::vector<double> breaks() const override;

 private:
  SurfacePtr surface_;
  bool along_u_;
  double value_, a_, b_;
};

// m applied to a curve / surface (an affine map: derivatives take its linear part).
class TransformedCurve : public Curve {
 public:
  TransformedCurve(CurvePtr c, const Mat4& m);
  std::pair<double, double> domain() const override { return curve_->domain(); }
  Point3 eval(double t) const override;
  Vec3 derivative(double t, int k) const override;
  std::vector<double> breaks() const override { return curve_->breaks(); }
  bool affine() const override { return curve_->affine(); }

 private:
  CurvePtr curve_;
  Mat4 m_;
};
class TransformedSurface : public Surface {
 public:
  TransformedSurface(SurfacePtr s, const Mat4& m);
  std::pair<double, double> u_domain() const override { return surface_->u_domain(); }
  std::pair<double, double> v_domain() const override { return surface_->v_domain(); }
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  std::vector<double> u_breaks() const override { return surface_->u_breaks(); }
  std::vector<double> v_breaks() const override { return surface_->v_breaks(); }

 private:
  SurfacePtr surface_;
  Mat4 m_;
};

// What the B-Rep does to the curve of an edge (surfaces/derived.cpp). A CircularArc stays one
// wherever it can (reversed, moved by a similarity, split, joined), so that an arc edge is still
// known as an arc; other curves are wrapped.
// c run the other way over a domain of the same length (a ReversedCurve unless c is an arc).
CurvePtr reversed_curve(const CurvePtr& c);
// c moved by the affine map m (a TransformedCurve unless c is an arc and m a similarity).
CurvePtr transformed_curve(const CurvePtr& c, const Mat4& m);
// The parameter of c nearest p (32 samples per piece between breaks, then golden-section search).
double closest_parameter(const Curve& c, const Point3& p);
// c cut at parameter t inside its domain into the pieces before and after t (arcs stay arcs,
// other curves become SubCurves of the curve that c is a piece of).
std::pair<CurvePtr, CurvePtr> split_curve(const CurvePtr& c, double t);
// The inverse of split_curve: a followed by b as one curve, when they are consecutive pieces of
// one circle or one curve (a's end is b's start); nullptr otherwise.
CurvePtr joined_curve(const CurvePtr& a, const CurvePtr& b);

// OpenSCAD's revolve of a profile curve in the XY plane (x the radius, y the height):
// S(u, v) = (x(u) cos v, x(u) sin v, y(u)), u along the profile, v in [0, angle] (radians).
// Exact, with analytic derivatives of every order.
class RevolutionSurface : public Surface {
 public:
  RevolutionSurface(CurvePtr profile, double angle);
  std::pair<double, double> u_domain() const override { return profile_->domain(); }
  std::pair<double, double> v_domain() const override { return {0.0, angle_}; }
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  void jet(double u, double v, int d, Vec3* out) const override;
  void jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const override;
  void eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const override;
  std::vector<double> u_breaks() const override { return profile_->breaks(); }
  // A straight profile piece not crossing the axis: S = (x cos v, x sin v, y) with x, y affine in
  // u, and |Su x Sv| = |x| |c'| (Su lies in the meridian plane, Sv across it).
  bool affine_area_in_u() const override;
  const CurvePtr& profile() const { return profile_; }
  double angle() const { return angle_; }

 private:
  CurvePtr profile_;
  double angle_;
};

// OpenSCAD's linear_extrude with twist and scale of a profile curve in the XY plane:
// S(u, v) = R(twist v) (1 + (scale - 1) v) P(u) + (0, 0, height v), v in [0, 1]. A twist gives
// the exact helicoidal surface; derivatives analytic in both parameters.
class TwistedExtrusionSurface : public Surface {
 public:
  TwistedExtrusionSurface(CurvePtr profile, double height, double twist, double scale);
  std::pair<double, double> u_domain() const override { return profile_->domain(); }
  std::pair<double, double> v_domain() const override { return {0.0, 1.0}; }
  Point3 eval(double u, double v) const override;
  Vec3 derivative(double u, double v, int ku, int kv) const override;
  void jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const override;
  void eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const override;
  std::vector<double> u_breaks() const override { return profile_->breaks(); }

 private:
  CurvePtr profile_;
  double height_, twist_, scale_;
  void grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const;
};

// Newell's teapot: the 32 bicubic Bezier patches (rim, body, lid, handle, spout, bottom), z up.
std::vector<NurbsSurface> teapot();

}  // namespace wedge
