// The simple curves and the interpolating splines. Bezier curves use de Casteljau's algorithm
// (evaluation, subdivision) and the hodograph for derivatives; elevation is the convex combination
// Q_i = i/(n+1) P_{i-1} + (1 - i/(n+1)) P_i. Polynomial interpolation is Neville's scheme, with the
// derivative of its recurrence for derivatives. The cubic Hermite form carries the natural spline
// (second derivatives M_i from the tridiagonal system h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i +
// h_i M_{i+1} = 6 (slope_i - slope_{i-1}), solved by the Thomas algorithm) and Kochanek & Bartels'
// splines ("Interpolating splines with local tension, continuity, and bias control", SIGGRAPH 1984),
// whose tangents at P_i, with the chords in = P_i - P_{i-1} and out = P_{i+1} - P_i, are
//   leaving P_i   (1-t)(1+b)(1+c)/2 in + (1-t)(1-b)(1-c)/2 out,
//   reaching P_i  (1-t)(1+b)(1-c)/2 in + (1-t)(1-b)(1+c)/2 out,
// Catmull-Rom's (P_{i+1} - P_{i-1}) / 2 at t = b = c = 0; c = -1 makes each segment's end tangents
// its own chord (the polygon itself: corners), c = +1 swaps them (corners that overshoot).
// Tessellation subdivides each chord until interior samples lie within the tolerance; arc length is
// adaptive Gauss-Legendre quadrature of |C'(t)|.
#include <algorithm>
#include <cmath>
#include <functional>

#include "kernel/distance.h"
#include "surfaces/surfaces.h"
#include "kernel/scaled.h"

namespace wedge {

// --- Curve ---

std::vector<double> Curve::breaks() const {
  auto [a, b] = domain();
  return {a, b};
}

bool Curve::closed() const {
  auto [a, b] = domain();
  Point3 p = eval(a), q = eval(b);
  // Relative to the curve's own extent (and its distance from the origin): an absolute 1e-12 called
  // every curve 1e-20 long closed, and a sweep along it failed with "the path is not closed".
  double extent = 0;
  for (int i = 1; i < 8; ++i) extent = std::max(extent, scaled_norm(eval(a + (b - a) * i / 8) - p));
  return scaled_norm(p - q) <= 1e-12 * (extent + scaled_norm(p));
}

void Curve::jet(double t, int d, Vec3* out) const {
  out[0] = eval(t);
  for (int k = 1; k <= d; ++k) out[k] = derivative(t, k);
}

Vec3 Curve::tangent(double t) const {
  // Where the parametrisation stops (a cusp of it), the tangent is that of the first derivative
  // that is not zero: bezier{{0,0},{0,0},{0,0},{1,0}} at 0 has C' = C'' = 0 and C''' = (6, 0), and
  // stopping at the second derivative said it did not move. 64 is the highest order the curves
  // compute (nurbs_curve.cpp); a polynomial's derivatives past its degree are all zero.
  Vec3 d = Vec3::Zero();
  double n = 0;
  for (int k = 1; k <= 64 && n == 0; ++k) {
    d = derivative(t, k);
    n = d.norm();
  }
  return n > 0 && std::isfinite(n) ? Vec3(d / n) : Vec3::Zero();
}

namespace {

double gauss5(const std::function<double(double)>& f, double a, double b) {
  static const double x[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640};
  static const double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                              0.2369268850561891};
  double m = 0.5 * (a + b), h = 0.5 * (b - a), s = 0;
  for (int i = 0; i < 5; ++i) s += w[i] * f(m + h * x[i]);
  return s * h;
}

// Adaptive Gauss-Legendre on [a, b] (pa, pb the curve's points there). `budget` counts the panels
// left for the whole integral, so an integrand that never settles (rounding noise above the
// tolerance at huge coordinates) costs a bounded time and gives the best estimate so far, instead
// of 2^depth panels. An arc is never shorter than its chord: halves that agree on less than the
// chord have missed where the curve moves (a NURBS weight of 1e50 puts the whole way to its control
// point in a parameter interval of 1e-50, where no Gauss point falls), so they are split further,
// and a panel that cannot be split counts at least its chord.
double adaptive(const Curve& c, const std::function<double(double)>& f, double a, double b, const Point3& pa,
                const Point3& pb, double whole, double tol, int depth, long& budget) {
  double m = 0.5 * (a + b);
  double left = gauss5(f, a, m), right = gauss5(f, m, b);
  budget -= 2;
  const double chord = scaled_norm(pb - pa);
  const bool short_of_chord = left + right < chord - tol;
  if (depth <= 0 || budget <= 0 || !std::isfinite(left + right) || (std::abs(left + right - whole) <= tol && !short_of_chord))
    return std::max(left + right, chord);
  const Point3 pm = c.eval(m);
  return adaptive(c, f, a, m, pa, pm, left, tol / 2, depth - 1, budget) +
         adaptive(c, f, m, b, pm, pb, right, tol / 2, depth - 1, budget);
}

}  // namespace

double Curve::length(double a, double b) const {
  require_finite(a, "start parameter");
  require_finite(b, "end parameter");
  auto f = [this](double t) { return scaled_norm(derivative(t, 1)); };
  double total = 0;
  std::vector<double> br = breaks();
  std::vector<double> cuts{a};
  for (double x : br)
    if (x > a && x < b) cuts.push_back(x);
  cuts.push_back(b);
  // About 200000 evaluations of the derivative in all: well under a second for any curve here.
  const long per_span = std::max<long>(64, 40000 / static_cast<long>(cuts.size()));
  // The tolerance is relative to the span's own length (its Gauss estimate, or the polyline
  // through the panels' ends where that is longer): 1e-13 * (1 + |whole|) was absolute below a
  // length of 1, and a curve 2e-12 long came out 1.7e-3 short. Each span starts as 16 panels, so
  // that a short fast stretch (a NURBS weight of 1000 puts most of the way into a parameter
  // interval of about 1/30) is not missed by two halves that agree: the weight-1000 parabola was
  // 3.8e-5 short.
  constexpr int kPanels = 16;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    double t[kPanels + 1];
    Point3 p[kPanels + 1];
    double scale = 0, whole[kPanels];
    for (int k = 0; k <= kPanels; ++k) {
      t[k] = k == kPanels ? cuts[i + 1] : cuts[i] + (cuts[i + 1] - cuts[i]) * k / kPanels;
      p[k] = eval(t[k]);
      if (k > 0) scale += scaled_norm(p[k] - p[k - 1]);
    }
    double sum = 0;
    for (int k = 0; k < kPanels; ++k) sum += whole[k] = gauss5(f, t[k], t[k + 1]);
    scale = std::max(scale, std::abs(sum));
    long budget = per_span;
    for (int k = 0; k < kPanels; ++k)
      total += adaptive(*this, f, t[k], t[k + 1], p[k], p[k + 1], whole[k], 1e-13 * scale / kPanels, 30, budget);
  }
  if (!std::isfinite(total))
    fail("the curve's length overflows (", total, "): its coordinates or tangents are too large");
  return total;
}

double Curve::length() const {
  auto [a, b] = domain();
  return length(a, b);
}

std::vector<double> Curve::parameters(double tolerance) const {
  if (!(tolerance > 0) || !std::isfinite(tolerance)) fail("tolerance must be a positive number, got ", tolerance);
  std::vector<double> out;
  std::function<void(double, double, const Point3&, const Point3&, int)> split =
      [&](double a, double b, const Point3& pa, const Point3& pb, int depth) {
        double err = 0;
        for (double f : {0.25, 0.5, 0.75}) err = std::max(err, point_segment_distance(eval(a + f * (b - a)), pa, pb));
        if (out.size() > 1'000'000)
          fail("tolerance ", tolerance, " would need more than a million points on this curve: use a larger tolerance");
        if (err > tolerance && depth < 40) {
          double m = 0.5 * (a + b);
          Point3 pm = eval(m);
          split(a, m, pa, pm, depth + 1);
          split(m, b, pm, pb, depth + 1);
        } else {
          out.push_back(b);
        }
      };
  std::vector<double> br = breaks();
  out.push_back(br.front());
  for (std::size_t i = 0; i + 1 < br.size(); ++i) {
    const int initial = 4;
    for (int j = 0; j < initial; ++j) {
      double a = br[i] + (br[i + 1] - br[i]) * j / initial;
      double b = j + 1 == initial ? br[i + 1] : br[i] + (br[i + 1] - br[i]) * (j + 1) / initial;
      split(a, b, eval(a), eval(b), 0);
    }
  }
  return out;
}

std::vector<Point3> Curve::points(double tolerance) const {
  std::vector<Point3> out;
  for (double t : parameters(tolerance)) out.push_back(eval(t));
  return out;
}

// --- line and arc ---

LineSegment::LineSegment(const Point3& a_, const Point3& b_) : a(a_), b(b_) {
  if (!a.allFinite() || !b.allFinite()) fail("line segment end points must be finite");
}

Point3 LineSegment::eval(double t) const { return a + t * (b - a); }

Vec3 LineSegment::derivative(double t, int k) const {
  if (k == 0) return eval(t);
  return k == 1 ? Vec3(b - a) : Vec3::Zero();
}

CircularArc::CircularArc(const Point3& center, double radius, double start, double end, const Vec3& normal,
                         const Vec3& x_axis)
    : center_(center), radius_(radius), start_(start), end_(end) {
  require_positive(radius, "radius");
  require_finite(start, "start angle");
  require_finite(end, "end angle");
  if (!(end > start)) fail("arc end angle (", end, ") must be greater than its start angle (", start, ")");
  if (!center.allFinite()) fail("arc centre must be finite");
  if (!(normal.norm() > 0) || !normal.allFinite()) fail("arc normal must be a non-zero vector");
  Vec3 n = normal.normalized();
  x_ = n == Vec3::UnitZ() ? Vec3::UnitX() : Vec3(std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY());
  if (x_axis.allFinite() && (x_axis - x_axis.dot(n) * n).norm() > 1e-12 * x_axis.norm() && x_axis.norm() > 0) x_ = x_axis;
  x_ = (x_ - x_.dot(n) * n).normalized();
  y_ = n.cross(x_);
}

namespace {
// cos and sin at an angle snapped to the nearest 2^-44 of a turn, from one octant's values by
// exact symmetries: the same doubles for one point of a circle however its parameter was reached
// (t, t - 2 pi, -t on the reversed circle). A tube's hole (its circle run backwards, sampled over
// [-2 pi, 0]) and a cylinder of its radius had rim points an ulp apart (20 of 52 the same), and
// the pin in the hole left slivers between the walls. The snap moves the point by at most
// 2^-45 of a turn (2e-13 of the radius), and not where the angle is a multiple of pi / 2.
void cos_sin_snapped(double t, double& c, double& s) {
  constexpr double kGrid = 0x1p44;
  constexpr long long kTurn = 1LL << 44, kQuarter = kTurn / 4, kEighth = kTurn / 8;
  const double turns = t / (2 * kPi);
  if (!(std::abs(turns) < 0x1p8)) {
    cos_sin(t, c, s);
    return;
  }
  long long m = std::llround((turns - std::floor(turns)) * kGrid) % kTurn;
  const long long q = m / kQuarter;
  long long r = m % kQuarter;
  const bool swap = r > kEighth;
  if (swap) r = kQuarter - r;
  double c0 = 1, s0 = 0;
  if (r != 0) {
    const double a = 2 * kPi * (static_cast<double>(r) / kGrid);
    c0 = std::cos(a);
    s0 = std::sin(a);
  }
  if (swap) std::swap(c0, s0);
  switch (q) {
    case 0: c = c0, s = s0; break;
    case 1: c = -s0, s = c0; break;
    case 2: c = -c0, s = -s0; break;
    default: c = s0, s = -c0; break;
  }
}
}  // namespace

Point3 CircularArc::eval(double t) const {
  double c, s;
  cos_sin_snapped(t, c, s);
  return center_ + radius_ * (c * x_ + s * y_);
}

Vec3 CircularArc::derivative(double t, int k) const {
  if (k == 0) return eval(t);
  // d^k/dt^k (cos t, sin t) = (cos(t + k pi/2), sin(t + k pi/2))
  double c, s;
  cos_sin(t + k * kPi / 2, c, s);
  return radius_ * (c * x_ + s * y_);
}

void CircularArc::jet(double t, int d, Vec3* out) const {
  // The k-th derivative turns the radius vector by k pi/2: (c, s) -> (-s, c) -> (-c, -s) -> (s, -c).
  double c, s;
  cos_sin(t, c, s);
  Vec3 a = radius_ * (c * x_ + s * y_), b = radius_ * (c * y_ - s * x_);
  out[0] = center_ + a;
  if (d >= 1) out[1] = b;
  if (d >= 2) out[2] = -a;
  if (d >= 3) out[3] = -b;
}

bool CircularArc::closed() const { return end_ - start_ >= 2 * kPi - 1e-12; }

CircularArc CircularArc::reversed() const {
  // With normal -n the second axis is -y: c + r (cos t x - sin t y) at t = -s is C(s).
  return CircularArc(center_, radius_, -end_, -start_, -normal(), x_);
}

CircularArc CircularArc::transformed(const Mat4& m) const {
  // A similarity maps x, y to s Q x, s Q y; the image's normal is their cross product, which a
  // mirror (det Q = -1) turns against Q n.
  Vec3 x = apply_vector(m, x_), y = apply_vector(m, y_);
  double s = x.norm();
  return CircularArc(apply_point(m, center_), radius_ * s, start_, end_, x.cross(y), x / s);
}

CircularArc arc_through(const Point3& a, const Point3& m, const Point3& b) {
  Vec3 u = m - a, w = b - a;
  Vec3 n = u.cross(w);
  double n2 = n.squaredNorm();
  if (!(n2 > 1e-30)) fail("arc_through: the three points are collinear or coincide");
  // Circumcentre of triangle a, m, b; a -> m -> b turns counter-clockwise about n.
  Point3 c = a + (w.squaredNorm() * n.cross(u) + u.squaredNorm() * w.cross(n)) / (2 * n2);
  Vec3 axis = n.normalized();
  Vec3 x = (a - c).normalized();
  Vec3 y = axis.cross(x);
  Vec3 d = b - c;
  double sweep = std::atan2(d.dot(y), d.dot(x));
  if (sweep <= 1e-12) sweep += 2 * kPi;
  return CircularArc(c, (a - c).norm(), 0.0, sweep, axis, x);
}

// --- Bezier ---

BezierCurve::BezierCurve(std::vector<Point3> points) : points_(std::move(points)) {
  if (points_.size() < 2) fail("a Bezier curve needs at least 2 control points, got ", points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i)
    if (!points_[i].allFinite()) fail("points: point ", i + 1, " has a coordinate that is not a finite number");
}

Point3 BezierCurve::eval(double t) const {
  std::vector<Point3> q = points_;
  for (std::size_t r = 1; r < q.size(); ++r)
    for (std::size_t i = 0; i + r < q.size(); ++i) q[i] = (1 - t) * q[i] + t * q[i + 1];
  return q[0];
}

void BezierCurve::jet(double t, int d, Vec3* out) const {
  const int n = degree();
  if (d > 3 || n > 31) {
    Curve::jet(t, d, out);
    return;
  }
  // One de Casteljau triangle: the k-th derivative is n (n-1) ... (n-k+1) times the k-th forward
  // difference of the k + 1 points of level n - k.
  Vec3 q[32];
  for (int i = 0; i <= n; ++i) q[i] = points_[static_cast<std::size_t>(i)];
  for (int k = 1; k <= d; ++k) out[k] = Vec3::Zero();
  auto record = [&](int level) {
    const int k = n - level;
    if (k < 1 || k > d) return;
    double scale = 1;
    for (int r = 0; r < k; ++r) scale *= n - r;
    Vec3 diff = k == 1 ? Vec3(q[1] - q[0]) : k == 2 ? Vec3(q[2] - 2 * q[1] + q[0]) : Vec3(q[3] - 3 * q[2] + 3 * q[1] - q[0]);
    out[k] = scale * diff;
  };
  record(0);
  for (int r = 1; r <= n; ++r) {
    for (int i = 0; i + r <= n; ++i) q[i] = (1 - t) * q[i] + t * q[i + 1];
    record(r);
  }
  out[0] = q[0];
}

Vec3 BezierCurve::derivative(double t, int k) const {
  if (k < 0) fail("derivative order must be >= 0, got ", k);
  int n = degree();
  if (k > n) return Vec3::Zero();
  // The k-th hodograph: forward differences scaled by n (n-1) ... (n-k+1), then de Casteljau.
  std::vector<Point3> q = points_;
  double scale = 1;
  for (int r = 0; r < k; ++r) {
    for (std::size_t i = 0; i + 1 < q.size(); ++i) q[i] = q[i + 1] - q[i];
    q.pop_back();
    scale *= (n - r);
  }
  for (std::size_t r = 1; r < q.size(); ++r)
    for (std::size_t i = 0; i + r < q.size(); ++i) q[i] = (1 - t) * q[i] + t * q[i + 1];
  return scale * q[0];
}

std::pair<BezierCurve, BezierCurve> BezierCurve::subdivide(double t) const {
  if (!(t > 0 && t < 1)) fail("subdivision parameter must be in (0, 1), got ", t);
  std::vector<Point3> q = points_, left, right;
  std::size_t n = q.size();
  left.push_back(q[0]);
  right.push_back(q[n - 1]);
  for (std::size_t r = 1; r < n; ++r) {
    for (std::size_t i = 0; i + r < n; ++i) q[i] = (1 - t) * q[i] + t * q[i + 1];
    left.push_back(q[0]);
    right.push_back(q[n - 1 - r]);
  }
  std::reverse(right.begin(), right.end());
  return {BezierCurve(std::move(left)), BezierCurve(std::move(right))};
}

BezierCurve BezierCurve::elevated() const {
  std::size_t n = points_.size();  // degree n - 1 -> n
  std::vector<Point3> q(n + 1);
  q[0] = points_[0];
  q[n] = points_[n - 1];
  for (std::size_t i = 1; i < n; ++i) {
    double a = double(i) / double(n);
    q[i] = a * points_[i - 1] + (1 - a) * points_[i];
  }
  return BezierCurve(std::move(q));
}

// --- polynomial interpolation ---

PolynomialInterpolant::PolynomialInterpolant(std::vector<Point3> points) : points_(std::move(points)) {
  if (points_.size() < 2) fail("polynomial interpolation needs at least 2 points, got ", points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (!points_[i].allFinite()) fail("points: point ", i + 1, " has a coordinate that is not a finite number");
    params_.push_back(double(i) / double(points_.size() - 1));
  }
}

Point3 PolynomialInterpolant::eval(double t) const { return derivative(t, 0); }

Vec3 PolynomialInterpolant::derivative(double t, int k) const {
  if (k < 0) fail("derivative order must be >= 0, got ", k);
  std::size_t n = points_.size();
  if (std::size_t(k) >= n) return Vec3::Zero();  // beyond the degree n - 1
  // D[m][i]: m-th derivative of the polynomial through points i..i+L at level L.
  std::vector<std::vector<Vec3>> D(k + 1, std::vector<Vec3>(n, Vec3::Zero()));
  for (std::size_t i = 0; i < n; ++i) D[0][i] = points_[i];
  for (std::size_t L = 1; L < n; ++L) {
    for (std::size_t i = 0; i + L < n; ++i) {
      double ti = params_[i], tj = params_[i + L], h = tj - ti;
      for (int m = k; m >= 0; --m) {
        Vec3 v = (t - ti) * D[m][i + 1] - (t - tj) * D[m][i];
        if (m > 0) v += m * (D[m - 1][i + 1] - D[m - 1][i]);
        D[m][i] = v / h;
      }
    }
  }
  return D[k][0];
}

// --- Hermite family ---

HermiteSpline::HermiteSpline(std::vector<double> params, std::vector<Point3> points, std::vector<Vec3> tangents)
    : HermiteSpline(std::move(params), std::move(points), tangents, tangents) {}

HermiteSpline::HermiteSpline(std::vector<double> params, std::vector<Point3> points, std::vector<Vec3> out_tangents,
                             std::vector<Vec3> in_tangents)
    : params_(std::move(params)), points_(std::move(points)), out_(std::move(out_tangents)), in_(std::move(in_tangents)) {
  if (points_.size() < 2) fail("a Hermite spline needs at least 2 points, got ", points_.size());
  if (params_.size() != points_.size() || out_.size() != points_.size() || in_.size() != points_.size())
    fail("a Hermite spline needs one parameter and one tangent per point");
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (!points_[i].allFinite()) fail("points: point ", i + 1, " has a coordinate that is not a finite number");
    if (!out_[i].allFinite() || !in_[i].allFinite()) fail("tangents: tangent ", i + 1, " is not finite");
    if (!std::isfinite(params_[i])) fail("parameter ", i + 1, " is not finite");
    if (i > 0 && !(params_[i] > params_[i - 1])) fail("parameters must increase: parameter ", i + 1, " is not greater than parameter ", i);
  }
}

Point3 HermiteSpline::eval(double t) const { return derivative(t, 0); }

Vec3 HermiteSpline::derivative(double t, int k) const {
  if (k < 0) fail("derivative order must be >= 0, got ", k);
  if (k > 3) return Vec3::Zero();
  std::size_t n = params_.size();
  std::size_t i = std::upper_bound(params_.begin(), params_.end(), t) - params_.begin();
  i = std::clamp<std::size_t>(i == 0 ? 0 : i - 1, 0, n - 2);
  double h = params_[i + 1] - params_[i], s = (t - params_[i]) / h;
  double b[4];  // h00, h10, h01, h11 and their s-derivatives
  switch (k) {
    case 0: b[0] = (2 * s - 3) * s * s + 1; b[1] = ((s - 2) * s + 1) * s; b[2] = (3 - 2 * s) * s * s; b[3] = (s - 1) * s * s; break;
    case 1: b[0] = 6 * s * s - 6 * s; b[1] = 3 * s * s - 4 * s + 1; b[2] = -6 * s * s + 6 * s; b[3] = 3 * s * s - 2 * s; break;
    case 2: b[0] = 12 * s - 6; b[1] = 6 * s - 4; b[2] = -12 * s + 6; b[3] = 6 * s - 2; break;
    default: b[0] = 12; b[1] = 6; b[2] = -12; b[3] = 6; break;
  }
  Vec3 v = b[0] * points_[i] + b[1] * h * out_[i] + b[2] * points_[i + 1] + b[3] * h * in_[i + 1];
  return v / std::pow(h, k);
}

NurbsCurve HermiteSpline::to_nurbs() const {
  std::vector<Point3> P;
  std::vector<double> K(4, params_.front());
  for (std::size_t i = 0; i + 1 < params_.size(); ++i) {
    double h = params_[i + 1] - params_[i];
    if (i == 0) P.push_back(points_[0]);
    P.push_back(points_[i] + h * out_[i] / 3);
    P.push_back(points_[i + 1] - h * in_[i + 1] / 3);
    P.push_back(points_[i + 1]);
    K.insert(K.end(), i + 2 == params_.size() ? 4 : 3, params_[i + 1]);
  }
  return NurbsCurve(3, std::move(P), std::move(K));
}

HermiteSpline natural_spline(const std::vector<Point3>& P) {
  std::size_t n = P.size();
  if (n < 2) fail("a natural spline needs at least 2 points, got ", n);
  for (std::size_t i = 0; i < n; ++i)
    if (!P[i].allFinite()) fail("points: point ", i + 1, " has a coordinate that is not a finite number");
  std::vector<double> t(n, 0.0);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    double h = scaled_norm(P[i + 1] - P[i]);
    if (h == 0) fail("points ", i + 1, " and ", i + 2, " coincide: a spline needs distinct consecutive points");
    // The chord lengths are the parameters: points 1e308 apart gave "parameters must increase".
    if (!std::isfinite(t[i] + h)) fail("points ", i + 1, " and ", i + 2, " are too far apart: the length along the points overflows");
    t[i + 1] = t[i] + h;
  }
  return natural_spline(t, P);
}

HermiteSpline natural_spline(const std::vector<double>& t, const std::vector<Point3>& P) {
  std::size_t n = P.size();
  if (n < 2) fail("a natural spline needs at least 2 points, got ", n);
  if (t.size() != n) fail("a natural spline needs one parameter per point");
  std::vector<double> h(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = t[i + 1] - t[i];
    if (!(h[i] > 0)) fail("parameters must increase: parameter ", i + 2, " is not greater than parameter ", i + 1);
  }
  std::vector<Vec3> M(n, Vec3::Zero());
  if (n > 2) {
    // Thomas algorithm on the interior unknowns M_1..M_{n-2}.
    std::size_t m = n - 2;
    std::vector<double> diag(m), upper(m);
    std::vector<Vec3> rhs(m);
    for (std::size_t j = 0; j < m; ++j) {
      std::size_t i = j + 1;
      diag[j] = 2 * (h[i - 1] + h[i]);
      upper[j] = h[i];
      rhs[j] = 6 * ((P[i + 1] - P[i]) / h[i] - (P[i] - P[i - 1]) / h[i - 1]);
    }
    for (std::size_t j = 1; j < m; ++j) {
      double w = h[j] / diag[j - 1];  // lower[j] = h[j] (= h_{i-1} for i = j + 1)
      diag[j] -= w * upper[j - 1];
      rhs[j] -= w * rhs[j - 1];
    }
    M[m] = rhs[m - 1] / diag[m - 1];
    for (std::size_t j = m - 1; j-- > 0;) M[j + 1] = (rhs[j] - upper[j] * M[j + 2]) / diag[j];
  }
  std::vector<Vec3> D(n);
  for (std::size_t i = 0; i + 1 < n; ++i) D[i] = (P[i + 1] - P[i]) / h[i] - h[i] * (2 * M[i] + M[i + 1]) / 6;
  D[n - 1] = (P[n - 1] - P[n - 2]) / h[n - 2] + h[n - 2] * (M[n - 2] + 2 * M[n - 1]) / 6;
  return HermiteSpline(t, P, std::move(D));
}

HermiteSpline kochanek_bartels(const std::vector<Point3>& points, double tension, double bias, double continuity,
                               bool closed) {
  // Kochanek & Bartels define the three parameters on -1..1; far outside it the tangents grow
  // without bound (tension 1e300 makes them overflow) and the curve loops.
  for (auto [x, what] : {std::pair{tension, "tension"}, {bias, "bias"}, {continuity, "continuity"}}) {
    require_finite(x, what);
    if (x < -1 || x > 1) fail(what, " must be within -1..1 (Kochanek-Bartels), got ", x);
  }
  std::size_t n = points.size();
  if (n < (closed ? 3u : 2u))
    fail(closed ? "a closed spline needs at least 3 points, got " : "a spline needs at least 2 points, got ", n);
  for (std::size_t i = 0; i < n; ++i)
    if (!points[i].allFinite()) fail("points: point ", i + 1, " has a coordinate that is not a finite number");
  auto at = [&](long i) -> Point3 {
    if (closed) return points[((i % long(n)) + long(n)) % long(n)];
    if (i < 0) return 2 * points[0] - points[1];
    if (i >= long(n)) return 2 * points[n - 1] - points[n - 2];
    return points[i];
  };
  double t = tension, b = bias, c = continuity;
  std::size_t count = closed ? n + 1 : n;
  std::vector<double> params(count);
  std::vector<Point3> P(count);
  std::vector<Vec3> out(count), in(count);
  for (std::size_t i = 0; i < count; ++i) {
    Vec3 before = at(long(i)) - at(long(i) - 1), after = at(long(i) + 1) - at(long(i));
    out[i] = (1 - t) * (1 + b) * (1 + c) / 2 * before + (1 - t) * (1 - b) * (1 - c) / 2 * after;
    in[i] = (1 - t) * (1 + b) * (1 - c) / 2 * before + (1 - t) * (1 - b) * (1 + c) / 2 * after;
    params[i] = double(i);
    P[i] = at(long(i));
  }
  return HermiteSpline(std::move(params), std::move(P), std::move(out), std::move(in));
}

HermiteSpline catmull_rom(const std::vector<Point3>& points, bool closed) {
  return kochanek_bartels(points, 0, 0, 0, closed);
}

}  // namespace wedge
