// Curves and surfaces made from others: reversal, pieces, iso-lines, affine images, and the two
// sweeps of OpenSCAD (revolve about +z of an XY profile, linear extrude with twist and scale).
// Derivatives are analytic: a rotation by an angle phi(v) = a v has d^k/dv^k R(a v) = a^k
// R(a v + k pi/2), and (1 + (s - 1) v) R(a v) differentiates by Leibniz's rule with one term of
// the linear factor.
#include <algorithm>
#include <cmath>

#include "surfaces/surfaces.h"

namespace wedge {

namespace {
// (x, y) rotated by angle a (the z part untouched).
Vec3 rot(const Vec3& p, double a) {
  double c, s;
  cos_sin(a, c, s);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z()};
}
}  // namespace

ReversedCurve::ReversedCurve(CurvePtr c) : curve_(std::move(c)) {
  if (!curve_) fail("ReversedCurve: no curve");
}
Point3 ReversedCurve::eval(double t) const {
  auto [a, b] = curve_->domain();
  return curve_->eval(a + b - t);
}
Vec3 ReversedCurve::derivative(double t, int k) const {
  auto [a, b] = curve_->domain();
  Vec3 d = curve_->derivative(a + b - t, k);
  return k % 2 ? Vec3(-d) : d;
}
void ReversedCurve::jet(double t, int d, Vec3* out) const {
  auto [a, b] = curve_->domain();
  curve_->jet(a + b - t, d, out);
  for (int k = 1; k <= d; k += 2) out[k] = -out[k];
}
std::vector<double> ReversedCurve::breaks() const {
  auto [a, b] = curve_->domain();
  std::vector<double> out;
  for (double t : curve_->breaks()) out.push_back(a + b - t);
  std::reverse(out.begin(), out.end());
  return out;
}

SubCurve::SubCurve(CurvePtr c, double a, double b) : curve_(std::move(c)), a_(a), b_(b) {
  if (!curve_) fail("SubCurve: no curve");
  auto [t0, t1] = curve_->domain();
  if (!(a < b) || a < t0 - 1e-12 || b > t1 + 1e-12) fail("SubCurve: [", a, ", ", b, "] is not inside the domain [", t0, ", ", t1, "]");
}
std::vector<double> SubCurve::breaks() const {
  std::vector<double> out{a_};
  for (double t : curve_->breaks())
    if (t > a_ && t < b_) out.push_back(t);
  out.push_back(b_);
  return out;
}

IsoCurve::IsoCurve(SurfacePtr s, bool along_u, double value, double a, double b)
    : surface_(std::move(s)), along_u_(along_u), value_(value), a_(a), b_(b) {
  if (!surface_) fail("IsoCurve: no surface");
  if (!(a < b)) fail("IsoCurve: empty interval [", a, ", ", b, "]");
}
Point3 IsoCurve::eval(double t) const { return along_u_ ? surface_->eval(t, value_) : surface_->eval(value_, t); }
Vec3 IsoCurve::derivative(double t, int k) const {
  return along_u_ ? surface_->derivative(t, value_, k, 0) : surface_->derivative(value_, t, 0, k);
}
std::vector<double> IsoCurve::breaks() const {
  std::vector<double> out{a_};
  for (double t : along_u_ ? surface_->u_breaks() : surface_->v_breaks())
    if (t > a_ && t < b_) out.push_back(t);
  out.push_back(b_);
  return out;
}

CurvePtr reversed_curve(const CurvePtr& c) {
  if (auto* arc = dynamic_cast<const CircularArc*>(c.get())) return std::make_shared<const CircularArc>(arc->reversed());
  return std::make_shared<const ReversedCurve>(c);
}

CurvePtr transformed_curve(const CurvePtr& c, const Mat4& m) {
  if (auto* arc = dynamic_cast<const CircularArc*>(c.get())) {
    const Mat3 lin = m.block<3, 3>(0, 0);
    const double s = std::cbrt(std::abs(lin.determinant()));
    if ((lin.transpose() * lin).isApprox(s * s * Mat3::Identity(), 1e-9))
      return std::make_shared<const CircularArc>(arc->transformed(m));
  }
  return std::make_shared<const TransformedCurve>(c, m);
}

double closest_parameter(const Curve& c, const Point3& p) {
  std::vector<double> br = c.breaks();
  double best = br.front(), best_d = (c.eval(best) - p).squaredNorm(), step = 0;
  for (std::size_t i = 0; i + 1 < br.size(); ++i) {
    const int n = 32;
    for (int k = 0; k <= n; ++k) {
      double t = br[i] + (br[i + 1] - br[i]) * k / n;
      double d = (c.eval(t) - p).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = t;
        step = (br[i + 1] - br[i]) / n;
      }
    }
  }
  if (step == 0) return best;
  auto [t0, t1] = c.domain();
  double a = std::max(t0, best - step), b = std::min(t1, best + step);
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 80 && b - a > 1e-15 * std::max(1.0, std::abs(a)); ++it) {
    double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if ((c.eval(x1) - p).squaredNorm() < (c.eval(x2) - p).squaredNorm()) b = x2;
    else a = x1;
  }
  return (a + b) / 2;
}

std::pair<CurvePtr, CurvePtr> split_curve(const CurvePtr& c, double t) {
  auto [t0, t1] = c->domain();
  if (!(t > t0 && t < t1)) fail("split_curve: parameter ", t, " is not inside the domain [", t0, ", ", t1, "]");
  if (auto* arc = dynamic_cast<const CircularArc*>(c.get()))
    return {std::make_shared<const CircularArc>(arc->center(), arc->radius(), t0, t, arc->normal(), arc->x_axis()),
            std::make_shared<const CircularArc>(arc->center(), arc->radius(), t, t1, arc->normal(), arc->x_axis())};
  CurvePtr base = c;
  if (auto* sub = dynamic_cast<const SubCurve*>(c.get())) base = sub->source();
  return {std::make_shared<const SubCurve>(base, t0, t), std::make_shared<const SubCurve>(base, t, t1)};
}

CurvePtr joined_curve(const CurvePtr& a, const CurvePtr& b) {
  if (!a || !b) return nullptr;
  auto [a0, a1] = a->domain();
  auto [b0, b1] = b->domain();
  if ((a->eval(a1) - b->eval(b0)).norm() > 1e-9 * (1 + a->eval(a1).norm())) return nullptr;
  auto* p = dynamic_cast<const CircularArc*>(a.get());
  auto* q = dynamic_cast<const CircularArc*>(b.get());
  if (p && q) {
    double r = p->radius();
    if ((p->center() - q->center()).norm() > 1e-9 * r || std::abs(p->radius() - q->radius()) > 1e-9 * r ||
        (p->normal() - q->normal()).norm() > 1e-9)
      return nullptr;
    return std::make_shared<const CircularArc>(p->center(), r, a0, a1 + (b1 - b0), p->normal(), p->x_axis());
  }
  auto* sa = dynamic_cast<const SubCurve*>(a.get());
  auto* sb = dynamic_cast<const SubCurve*>(b.get());
  const Curve* base_a = sa ? sa->source().get() : a.get();
  const Curve* base_b = sb ? sb->source().get() : b.get();
  if (base_a != base_b || a1 != b0) return nullptr;
  CurvePtr base = sa ? sa->source() : a;
  auto [t0, t1] = base->domain();
  if (a0 == t0 && b1 == t1) return base;
  return std::make_shared<const SubCurve>(base, a0, b1);
}

TransformedCurve::TransformedCurve(CurvePtr c, const Mat4& m) : curve_(std::move(c)), m_(m) {
  if (!curve_) fail("TransformedCurve: no curve");
}
Point3 TransformedCurve::eval(double t) const { return apply_point(m_, curve_->eval(t)); }
Vec3 TransformedCurve::derivative(double t, int k) const {
  return k == 0 ? eval(t) : Vec3(m_.block<3, 3>(0, 0) * curve_->derivative(t, k));
}

TransformedSurface::TransformedSurface(SurfacePtr s, const Mat4& m) : surface_(std::move(s)), m_(m) {
  if (!surface_) fail("TransformedSurface: no surface");
}
Point3 TransformedSurface::eval(double u, double v) const { return apply_point(m_, surface_->eval(u, v)); }
Vec3 TransformedSurface::derivative(double u, double v, int ku, int kv) const {
  return ku + kv == 0 ? eval(u, v) : Vec3(m_.block<3, 3>(0, 0) * surface_->derivative(u, v, ku, kv));
}

RevolutionSurface::RevolutionSurface(CurvePtr profile, double angle) : profile_(std::move(profile)), angle_(angle) {
  if (!profile_) fail("RevolutionSurface: no profile");
  if (!(angle > 0) || angle > 2 * kPi + 1e-12) fail("RevolutionSurface: the angle must be in (0, 2 pi], got ", angle);
}
Point3 RevolutionSurface::eval(double u, double v) const { return derivative(u, v, 0, 0); }
Vec3 RevolutionSurface::derivative(double u, double v, int ku, int kv) const {
  Vec3 p = ku == 0 ? profile_->eval(u) : profile_->derivative(u, ku);
  // (x cos v, x sin v, y): the k-th v derivative rotates (x, 0) by v + k pi/2; y only for k = 0.
  Vec3 r = rot(Vec3(p.x(), 0, 0), v + kv * kPi / 2);
  return {r.x(), r.y(), kv == 0 ? p.y() : 0.0};
}

void RevolutionSurface::jet(double u, double v, int d, Vec3* out) const {
  if (d > 2) {
    Surface::jet(u, v, d, out);
    return;
  }
  // The profile's point and derivatives once, one sine and cosine: the v derivatives turn (x, 0)
  // by pi/2 each, (x cos v, x sin v) -> (-x sin v, x cos v) -> (-x cos v, -x sin v).
  Vec3 c[3];
  profile_->jet(u, d, c);
  double cv, sv;
  cos_sin(v, cv, sv);
  out[0] = Vec3(c[0].x() * cv, c[0].x() * sv, c[0].y());
  out[1] = Vec3(c[1].x() * cv, c[1].x() * sv, c[1].y());
  out[2] = Vec3(-c[0].x() * sv, c[0].x() * cv, 0);
  if (d == 2) {
    out[3] = Vec3(c[2].x() * cv, c[2].x() * sv, c[2].y());
    out[4] = Vec3(-c[1].x() * sv, c[1].x() * cv, 0);
    out[5] = Vec3(-c[0].x() * cv, -c[0].x() * sv, 0);
  }
}

void RevolutionSurface::jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const {
  if (d > 2) {
    Surface::jet_grid(u, nu, v, nv, d, out);
    return;
  }
  // As jet(), with each column's sine and cosine and each row's profile jet computed once.
  std::vector<double> cvs(static_cast<std::size_t>(nv)), svs(static_cast<std::size_t>(nv));
  for (int j = 0; j < nv; ++j) {
    cos_sin(v[j], cvs[static_cast<std::size_t>(j)], svs[static_cast<std::size_t>(j)]);
  }
  for (int i = 0; i < nu; ++i) {
    Vec3 c[3];
    profile_->jet(u[i], d, c);
    for (int j = 0; j < nv; ++j) {
      const double cv = cvs[static_cast<std::size_t>(j)], sv = svs[static_cast<std::size_t>(j)];
      Vec3* o = out + (static_cast<std::ptrdiff_t>(i) * nv + j) * 6;
      o[0] = Vec3(c[0].x() * cv, c[0].x() * sv, c[0].y());
      o[1] = Vec3(c[1].x() * cv, c[1].x() * sv, c[1].y());
      o[2] = Vec3(-c[0].x() * sv, c[0].x() * cv, 0);
      if (d == 2) {
        o[3] = Vec3(c[2].x() * cv, c[2].x() * sv, c[2].y());
        o[4] = Vec3(-c[1].x() * sv, c[1].x() * cv, 0);
        o[5] = Vec3(-c[0].x() * cv, -c[0].x() * sv, 0);
      }
    }
  }
}

bool RevolutionSurface::affine_area_in_u() const {
  if (!profile_->affine()) return false;
  const auto [a, b] = profile_->domain();
  return !(profile_->eval(a).x() * profile_->eval(b).x() < 0);
}

void RevolutionSurface::eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const {
  // As eval(), with each column's sine and cosine and each row's profile point computed once.
  std::vector<double> cvs(static_cast<std::size_t>(nv)), svs(static_cast<std::size_t>(nv));
  for (int j = 0; j < nv; ++j) cos_sin(v[j], cvs[static_cast<std::size_t>(j)], svs[static_cast<std::size_t>(j)]);
  for (int i = 0; i < nu; ++i) {
    const Point3 c = profile_->eval(u[i]);
    for (int j = 0; j < nv; ++j)
      out[static_cast<std::ptrdiff_t>(i) * nv + j] =
          Point3(c.x() * cvs[static_cast<std::size_t>(j)], c.x() * svs[static_cast<std::size_t>(j)], c.y());
  }
}

TwistedExtrusionSurface::TwistedExtrusionSurface(CurvePtr profile, double height, double twist, double scale)
    : profile_(std::move(profile)), height_(height), twist_(twist), scale_(scale) {
  if (!profile_) fail("TwistedExtrusionSurface: no profile");
  if (!(height > 0) || !std::isfinite(height)) fail("TwistedExtrusionSurface: the height must be positive, got ", height);
  if (!std::isfinite(twist)) fail("TwistedExtrusionSurface: the twist is not finite");
  if (!(scale >= 0) || !std::isfinite(scale)) fail("TwistedExtrusionSurface: the scale must be >= 0, got ", scale);
}
Point3 TwistedExtrusionSurface::eval(double u, double v) const { return derivative(u, v, 0, 0); }

void TwistedExtrusionSurface::eval_grid(const double* u, int nu, const double* v, int nv, Point3* out) const {
  std::vector<Vec3> j(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv) * 6);
  grid(u, nu, v, nv, 0, j.data());
  for (std::size_t k = 0; k < static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv); ++k) out[k] = j[k * 6];
}

void TwistedExtrusionSurface::jet_grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const {
  if (d != 1) {
    Surface::jet_grid(u, nu, v, nv, d, out);
    return;
  }
  grid(u, nu, v, nv, 1, out);
}

// derivative()'s values at every grid point (S, and with d = 1 Su and Sv), each column's turns
// (a v and a v + pi/2, one sine and cosine each) and each row's profile point once.
void TwistedExtrusionSurface::grid(const double* u, int nu, const double* v, int nv, int d, Vec3* out) const {
  const double a = twist_, dk = scale_ - 1;
  struct Column {
    double k, c0, s0, c1, s1;
  };
  std::vector<Column> cols(static_cast<std::size_t>(nv));
  for (int j = 0; j < nv; ++j) {
    Column& c = cols[static_cast<std::size_t>(j)];
    c.k = 1 + (scale_ - 1) * v[j];
    cos_sin(a * v[j] + 0 * kPi / 2, c.c0, c.s0);
    if (d) cos_sin(a * v[j] + 1 * kPi / 2, c.c1, c.s1);
  }
  auto turn = [](const Vec3& p, double c, double s) { return Vec3(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z()); };
  for (int i = 0; i < nu; ++i) {
    Vec3 p0 = profile_->eval(u[i]), p1 = Vec3::Zero();
    p0.z() = 0;
    if (d) {
      p1 = profile_->derivative(u[i], 1);
      p1.z() = 0;
    }
    for (int j = 0; j < nv; ++j) {
      const Column& c = cols[static_cast<std::size_t>(j)];
      Vec3* o = out + (static_cast<std::ptrdiff_t>(i) * nv + j) * 6;
      o[0] = c.k * std::pow(a, 0) * turn(p0, c.c0, c.s0);
      o[0].z() = height_ * v[j];
      if (!d) continue;
      o[1] = c.k * std::pow(a, 0) * turn(p1, c.c0, c.s0);
      o[1].z() = 0;
      o[2] = c.k * std::pow(a, 1) * turn(p0, c.c1, c.s1);
      o[2] += 1 * dk * std::pow(a, 1 - 1) * turn(p0, c.c0, c.s0);
      o[2].z() = height_;
    }
  }
}
Vec3 TwistedExtrusionSurface::derivative(double u, double v, int ku, int kv) const {
  Vec3 p = ku == 0 ? profile_->eval(u) : profile_->derivative(u, ku);
  p.z() = 0;
  double a = twist_, k = 1 + (scale_ - 1) * v, dk = scale_ - 1;
  // d^n/dv^n [k(v) R(a v)] = k a^n R(a v + n pi/2) + n k' a^(n-1) R(a v + (n-1) pi/2).
  Vec3 out = k * std::pow(a, kv) * rot(p, a * v + kv * kPi / 2);
  if (kv >= 1) out += kv * dk * std::pow(a, kv - 1) * rot(p, a * v + (kv - 1) * kPi / 2);
  out.z() = 0;
  if (ku == 0) {
    if (kv == 0) out.z() = height_ * v;
    if (kv == 1) out.z() = height_;
  }
  return out;
}

}  // namespace wedge
