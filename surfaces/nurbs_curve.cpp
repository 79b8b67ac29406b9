// NURBS curves after The NURBS Book (Piegl & Tiller): a rational curve is a B-spline in
// homogeneous space, Cw(u) = sum N_i,p(u) (w_i P_i, w_i). Points by A4.1, derivatives of Cw by A3.2
// and the rational derivatives by A4.2 (Leibniz rule on A(u) = w(u) C(u)). Knot insertion is
// Boehm's single-knot formula (A5.1 one knot at a time); knot removal is A5.8 one knot at a time
// (solve the insertion equations from both ends, accept if they meet within the tolerance). Degree
// elevation splits into Bezier pieces by insertion, raises each piece with the Bezier formula, and
// removes the knots that became redundant, which gives A5.9's result. Conics are rational quadratics (A7.1): a circular arc of
// at most 90 degrees has middle weight cos(half angle), and an ellipse is its affine image.
// Global interpolation is A9.1 (chord-length parameters, averaged knots, one linear solve).
#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "surfaces/surfaces.h"

namespace wedge {

namespace {

constexpr int kMaxDegree = 30;

double binomial(int n, int k) {
  double r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

void require_points_finite(const std::vector<Point3>& points, const char* what) {
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite()) fail(what, ": point ", i + 1, " has a coordinate that is not a finite number");
}

}  // namespace

NurbsCurve::NurbsCurve(int degree, std::vector<Point3> points, std::vector<double> knots, std::vector<double> weights)
    : degree_(degree), points_(std::move(points)), knots_(std::move(knots)), weights_(std::move(weights)) {
  if (degree_ > kMaxDegree) fail("degree must be at most ", kMaxDegree, ", got ", degree_);
  require_points_finite(points_, "points");
  check_knots(knots_, degree_, points_.size());
  if (weights_.empty()) weights_.assign(points_.size(), 1.0);
  check_weights(weights_, points_.size());
}

std::pair<double, double> NurbsCurve::domain() const {
  return {knots_[degree_], knots_[points_.size()]};
}

bool NurbsCurve::rational() const {
  return std::any_of(weights_.begin(), weights_.end(), [&](double w) { return w != weights_[0]; });
}

std::vector<double> NurbsCurve::breaks() const {
  auto [a, b] = domain();
  std::vector<double> out;
  for (double k : knots_)
    if (k >= a && k <= b && (out.empty() || k != out.back())) out.push_back(k);
  return out;
}

Point3 NurbsCurve::eval(double t) const {
  int n = int(points_.size());
  int span = find_span(n, degree_, t, knots_);
  double N[kMaxDegree + 1];
  basis_functions(span, t, degree_, knots_, N);
  Vec3 a = Vec3::Zero();
  double w = 0;
  for (int j = 0; j <= degree_; ++j) {
    int i = span - degree_ + j;
    a += N[j] * weights_[i] * points_[i];
    w += N[j] * weights_[i];
  }
  return a / w;
}

std::vector<Vec3> NurbsCurve::derivatives(double t, int d) const {
  int n = int(points_.size());
  int span = find_span(n, degree_, t, knots_);
  auto ders = basis_derivatives(span, t, degree_, d, knots_);
  std::vector<Vec3> A(d + 1, Vec3::Zero());
  std::vector<double> W(d + 1, 0.0);
  for (int k = 0; k <= std::min(d, degree_); ++k)
    for (int j = 0; j <= degree_; ++j) {
      int i = span - degree_ + j;
      A[k] += ders[k][j] * weights_[i] * points_[i];
      W[k] += ders[k][j] * weights_[i];
    }
  std::vector<Vec3> C(d + 1);
  for (int k = 0; k <= d; ++k) {
    Vec3 v = A[k];
    for (int i = 1; i <= k; ++i) v -= binomial(k, i) * W[i] * C[k - i];
    C[k] = v / W[0];
  }
  return C;
}

void NurbsCurve::jet(double t, int d, Vec3* out) const {
  if (d > 3) {
    Curve::jet(t, d, out);
    return;
  }
  // derivatives() without its allocations: A2.3's basis derivatives into a fixed table, then A4.2.
  int n = int(points_.size());
  int span = find_span(n, degree_, t, knots_);
  double ders[4 * (kMaxDegree + 1)];
  basis_derivatives(span, t, degree_, d, knots_, ders);
  const int w = degree_ + 1;
  Vec3 A[4];
  double W[4];
  for (int k = 0; k <= d; ++k) {
    A[k] = Vec3::Zero();
    W[k] = 0;
    if (k > degree_) continue;
    for (int j = 0; j <= degree_; ++j) {
      int i = span - degree_ + j;
      A[k] += ders[k * w + j] * weights_[i] * points_[i];
      W[k] += ders[k * w + j] * weights_[i];
    }
  }
  for (int k = 0; k <= d; ++k) {
    Vec3 v = A[k];
    for (int i = 1; i <= k; ++i) v -= binomial(k, i) * W[i] * out[k - i];
    out[k] = v / W[0];
  }
}

Vec3 NurbsCurve::derivative(double t, int k) const {
  if (k < 0) fail("derivative order must be >= 0, got ", k);
  if (k <= 3) {
    Vec3 out[4];
    jet(t, k, out);
    return out[k];
  }
  // Rational curves have non-zero derivatives of every order; the recurrence needs k + 1 terms.
  // Orders far beyond any use are refused rather than allocated.
  if (k > 64) fail("derivative order must be at most 64, got ", k);
  return derivatives(t, k)[k];
}

NurbsCurve NurbsCurve::with_knot(double u, int times) const {
  auto [a, b] = domain();
  if (!std::isfinite(u) || u < a || u > b) fail("knot to insert (", u, ") must lie in the domain [", a, ", ", b, "]");
  int p = degree_;
  int s = int(std::count(knots_.begin(), knots_.end(), u));
  times = std::min(times, p - s);
  if (times <= 0) return *this;
  std::vector<Vec4> Pw(points_.size());
  for (std::size_t i = 0; i < Pw.size(); ++i) Pw[i] << weights_[i] * points_[i], weights_[i];
  std::vector<double> U = knots_;
  for (int r = 0; r < times; ++r) {
    // Boehm: Q_i = a_i P_i + (1 - a_i) P_{i-1}, a_i = (u - u_i) / (u_{i+p} - u_i) on the p affected
    // points of the span k with u_k <= u <= u_{k+1}.
    int np = int(Pw.size());
    int k = p;
    while (k + 1 < np && U[k + 1] <= u) ++k;
    std::vector<Vec4> Q(np + 1);
    for (int i = 0; i <= np; ++i) {
      if (i <= k - p) Q[i] = Pw[i];
      else if (i > k) Q[i] = Pw[i - 1];
      else {
        double alpha = (u - U[i]) / (U[i + p] - U[i]);
        Q[i] = alpha * Pw[i] + (1 - alpha) * Pw[i - 1];
      }
    }
    U.insert(U.begin() + k + 1, u);
    Pw = std::move(Q);
  }
  std::vector<Point3> P(Pw.size());
  std::vector<double> w(Pw.size());
  for (std::size_t i = 0; i < Pw.size(); ++i) {
    w[i] = Pw[i][3];
    P[i] = Pw[i].head<3>() / w[i];
  }
  return NurbsCurve(p, std::move(P), std::move(U), std::move(w));
}

std::vector<NurbsCurve> NurbsCurve::bezier_segments() const {
  NurbsCurve c = *this;
  for (double u : breaks()) c = c.with_knot(u, degree_);
  std::vector<NurbsCurve> out;
  const auto& U = c.knots_;
  int p = degree_;
  auto [a, b] = domain();
  for (std::size_t i = p; i + 1 < U.size(); ++i) {
    if (!(U[i] < U[i + 1]) || U[i] < a || U[i + 1] > b) continue;
    std::vector<Point3> P(c.points_.begin() + (i - p), c.points_.begin() + i + 1);
    std::vector<double> w(c.weights_.begin() + (i - p), c.weights_.begin() + i + 1);
    std::vector<double> K(p + 1, U[i]);
    K.insert(K.end(), p + 1, U[i + 1]);
    out.emplace_back(p, std::move(P), std::move(K), std::move(w));
  }
  return out;
}

namespace {

// One removal of the knot at index r (its last copy; multiplicity s) from Pw/U, A5.8 with num = 1.
bool remove_once(std::vector<Vec4>& Pw, std::vector<double>& U, int p, int r, int s, double tol) {
  double u = U[r];
  int ord = p + 1, first = r - p, last = r - s, off = first - 1;
  std::vector<Vec4> temp(last - off + 2);
  temp[0] = Pw[off];
  temp[last + 1 - off] = Pw[last + 1];
  int i = first, j = last, ii = 1, jj = last - off;
  while (j - i > 0) {
    double ai = (u - U[i]) / (U[i + ord] - U[i]);
    double aj = (u - U[j]) / (U[j + ord] - U[j]);
    temp[ii] = (Pw[i] - (1 - ai) * temp[ii - 1]) / ai;
    temp[jj] = (Pw[j] - aj * temp[jj + 1]) / (1 - aj);
    ++i, ++ii, --j, --jj;
  }
  bool ok;
  if (j - i < 0) {
    ok = (temp[ii - 1] - temp[jj + 1]).norm() <= tol;
  } else {
    double ai = (u - U[i]) / (U[i + ord] - U[i]);
    ok = (Pw[i] - (ai * temp[ii + 1] + (1 - ai) * temp[ii - 1])).norm() <= tol;
  }
  if (!ok) return false;
  for (i = first, j = last; j - i > 0; ++i, --j) {
    Pw[i] = temp[i - off];
    Pw[j] = temp[j - off];
  }
  U.erase(U.begin() + r);
  Pw.erase(Pw.begin() + (2 * r - s - p) / 2);
  return true;
}

}  // namespace

NurbsCurve NurbsCurve::without_knot(double u, int times, double tolerance) const {
  auto [a, b] = domain();
  if (!std::isfinite(u) || !(u > a && u < b)) fail("knot to remove (", u, ") must lie inside the domain (", a, ", ", b, ")");
  std::vector<Vec4> Pw(points_.size());
  for (std::size_t i = 0; i < Pw.size(); ++i) Pw[i] << weights_[i] * points_[i], weights_[i];
  std::vector<double> U = knots_;
  for (int k = 0; k < times; ++k) {
    auto it = std::upper_bound(U.begin(), U.end(), u);
    int s = int(std::count(U.begin(), U.end(), u));
    if (s == 0) break;
    int r = int(it - U.begin()) - 1;
    if (!remove_once(Pw, U, degree_, r, s, tolerance)) break;
  }
  std::vector<Point3> P(Pw.size());
  std::vector<double> w(Pw.size());
  for (std::size_t i = 0; i < Pw.size(); ++i) {
    w[i] = Pw[i][3];
    P[i] = Pw[i].head<3>() / w[i];
  }
  return NurbsCurve(degree_, std::move(P), std::move(U), std::move(w));
}

NurbsCurve NurbsCurve::elevated() const {
  int p = degree_, q = p + 1;
  if (q > kMaxDegree) fail("degree must be at most ", kMaxDegree);
  std::vector<Point3> P;
  std::vector<double> W, K;
  bool first = true;
  for (const NurbsCurve& seg : bezier_segments()) {
    std::vector<Vec4> Pw(p + 1), Qw(q + 1);
    for (int i = 0; i <= p; ++i) Pw[i] << seg.weights_[i] * seg.points_[i], seg.weights_[i];
    Qw[0] = Pw[0];
    Qw[q] = Pw[p];
    for (int i = 1; i < q; ++i) {
      double a = double(i) / q;
      Qw[i] = a * Pw[i - 1] + (1 - a) * Pw[i];
    }
    auto [a, b] = seg.domain();
    if (first) K.insert(K.end(), q + 1, a);
    K.insert(K.end(), first ? 0 : q, a);
    for (int i = first ? 0 : 1; i <= q; ++i) {
      W.push_back(Qw[i][3]);
      P.push_back(Qw[i].head<3>() / Qw[i][3]);
    }
    first = false;
  }
  K.insert(K.end(), q + 1, domain().second);
  NurbsCurve out(q, std::move(P), std::move(K), std::move(W));
  // Each interior knot of multiplicity m now has q = p + 1 copies; the elevated curve needs m + 1.
  double scale = 1;
  for (std::size_t i = 0; i < points_.size(); ++i) scale = std::max(scale, (weights_[i] * points_[i]).norm() + weights_[i]);
  for (double u : breaks()) {
    if (u == domain().first || u == domain().second) continue;
    int m = int(std::count(knots_.begin(), knots_.end(), u));
    out = out.without_knot(u, p - m, 1e-10 * scale);
  }
  return out;
}

// --- conics ---

namespace {

NurbsCurve conic_arc(const Point3& O, const Vec3& X, const Vec3& Y, double rx, double ry, double start, double end) {
  require_finite(start, "start angle");
  require_finite(end, "end angle");
  require_positive(rx, "radius");
  require_positive(ry, "radius");
  double theta = end - start;
  if (!(theta > 0) || theta > 2 * kPi + 1e-12) fail("arc angle must be in (0, 360] degrees, got ", degrees(theta));
  int narcs = std::clamp(int(std::ceil(theta / (kPi / 2) - 1e-9)), 1, 4);
  double d = theta / narcs, w1 = std::cos(d / 2);
  auto at = [&](double ang, double scale) {
    double c, s;
    cos_sin(ang, c, s);
    return Point3(O + scale * (rx * c * X + ry * s * Y));
  };
  std::vector<Point3> P;
  std::vector<double> W;
  std::vector<double> K{0, 0, 0};
  P.push_back(at(start, 1));
  W.push_back(1);
  for (int i = 1; i <= narcs; ++i) {
    double mid = start + (i - 0.5) * d;
    double ang = i == narcs ? end : start + i * d;
    P.push_back(at(mid, 1 / w1));
    W.push_back(w1);
    P.push_back(at(ang, 1));
    W.push_back(1);
    if (i < narcs) K.insert(K.end(), 2, double(i) / narcs);
  }
  if (theta >= 2 * kPi - 1e-15) P.back() = P.front();  // a full turn closes exactly
  K.insert(K.end(), 3, 1.0);
  return NurbsCurve(2, std::move(P), std::move(K), std::move(W));
}

std::pair<Vec3, Vec3> plane_axes(const Vec3& normal) {
  Vec3 n = normal.normalized();
  Vec3 x = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  x = (x - x.dot(n) * n).normalized();
  if (n == Vec3::UnitZ()) x = Vec3::UnitX();
  return {x, n.cross(x)};
}

}  // namespace

NurbsCurve nurbs_arc(const Point3& center, const Vec3& x_axis, const Vec3& y_axis, double radius, double start,
                     double end) {
  if (!(x_axis.norm() > 0) || !(y_axis.norm() > 0) || std::abs(x_axis.normalized().dot(y_axis.normalized())) > 1e-12)
    fail("arc axes must be non-zero and perpendicular");
  return conic_arc(center, x_axis.normalized(), y_axis.normalized(), radius, radius, start, end);
}

NurbsCurve nurbs_circle(const Point3& center, double radius, const Vec3& normal) {
  if (!(normal.norm() > 0) || !normal.allFinite()) fail("circle normal must be a non-zero vector");
  auto [x, y] = plane_axes(normal);
  return conic_arc(center, x, y, radius, radius, 0, 2 * kPi);
}

NurbsCurve nurbs_ellipse(const Point3& center, const Vec3& x_axis, const Vec3& y_axis, double rx, double ry) {
  if (!(x_axis.norm() > 0) || !(y_axis.norm() > 0) || std::abs(x_axis.normalized().dot(y_axis.normalized())) > 1e-12)
    fail("ellipse axes must be non-zero and perpendicular");
  return conic_arc(center, x_axis.normalized(), y_axis.normalized(), rx, ry, 0, 2 * kPi);
}

NurbsCurve to_nurbs(const BezierCurve& c) {
  int p = c.degree();
  std::vector<double> K(p + 1, 0.0);
  K.insert(K.end(), p + 1, 1.0);
  return NurbsCurve(p, c.control_points(), std::move(K));
}

NurbsCurve to_nurbs(const LineSegment& c) { return NurbsCurve(1, {c.a, c.b}, {0, 0, 1, 1}); }

NurbsCurve interpolate_nurbs(const std::vector<Point3>& Q, int degree) {
  std::size_t n = Q.size();
  if (degree < 1) fail("degree must be at least 1, got ", degree);
  if (degree > kMaxDegree) fail("degree must be at most ", kMaxDegree, ", got ", degree);
  if (n < std::size_t(degree) + 1)
    fail("interpolation of degree ", degree, " needs at least ", degree + 1, " points, got ", n);
  require_points_finite(Q, "points");
  std::vector<double> chord(n, 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    double d = (Q[i] - Q[i - 1]).norm();
    if (d == 0) fail("points ", i, " and ", i + 1, " coincide: interpolation needs distinct consecutive points");
    chord[i] = chord[i - 1] + d;
  }
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i) t[i] = chord[i] / chord[n - 1];
  t[n - 1] = 1.0;
  int p = degree;
  std::vector<double> U(n + p + 1, 0.0);
  for (std::size_t i = n; i < U.size(); ++i) U[i] = 1.0;
  for (std::size_t j = 1; j + p < n; ++j) {  // averaging (9.8)
    double s = 0;
    for (std::size_t i = j; i < j + p; ++i) s += t[i];
    U[j + p] = s / p;
  }
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  double N[kMaxDegree + 1];
  for (std::size_t i = 0; i < n; ++i) {
    int span = find_span(int(n), p, t[i], U);
    basis_functions(span, t[i], p, U, N);
    for (int j = 0; j <= p; ++j) A(i, span - p + j) = N[j];
  }
  Eigen::MatrixXd B(n, 3);
  for (std::size_t i = 0; i < n; ++i) B.row(i) = Q[i].transpose();
  Eigen::MatrixXd X = A.partialPivLu().solve(B);
  std::vector<Point3> P(n);
  for (std::size_t i = 0; i < n; ++i) P[i] = X.row(i).transpose();
  return NurbsCurve(p, std::move(P), std::move(U));
}

}  // namespace wedge
