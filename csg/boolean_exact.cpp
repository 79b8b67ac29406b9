// Exact points and predicates of the boolean engine.
//
// Every point is an input vertex or an implicit point (LPI: a segment cut by a plane; TPI: three
// planes), with homogeneous coordinates (X, Y, Z, W) that are polynomials in the input doubles.
// Each predicate is one polynomial sign, evaluated first in interval arithmetic on the cached
// interval coordinates of its points (CGAL::Interval_nt, rounding mode set upward for the
// duration of the filter), and, only when the interval contains zero, again in exact
// arithmetic (CGAL::Mpzf: exact sums and products of doubles). The filter decides almost every
// call; the exact path makes every answer the one exact real arithmetic would give. Between the
// two, double-double arithmetic with a proven error bound (boolean_dd.h) decides most of what
// the filter leaves (points within ulps of each other, cut points to be rounded) for a fraction
// of the exact path's cost, and gives the same answers, since it answers only where it is sure.
#include <CGAL/Interval_nt.h>
#include <CGAL/Gmpq.h>
#include <CGAL/Mpzf.h>

#include <atomic>
#include <cmath>
#include <limits>

#include "csg/boolean_dd.h"
#include "csg/boolean_impl.h"
#include "kernel/parallel.h"
#include "kernel/error.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

namespace {

using IA = CGAL::Interval_nt<false>;  // needs the rounding mode upward: see Filter
using EX = CGAL::Mpzf;

// Rounds toward +infinity while alive, as Interval_nt<false> requires.
using Filter = CGAL::Protect_FPU_rounding<true>;

template <class NT>
NT lift(double x) {
  return NT(x);
}

template <class NT>
struct H {
  NT c[4];  // X, Y, Z, W
};

// The normal n of plane P (its offset d = -n . a, a = its first vertex, in plane_eval below).
template <class NT>
void plane_normal(const Soup& s, const Plane& P, NT n[3]) {
  const Vec3& a = s.verts[P.a];
  const Vec3& b = s.verts[P.b];
  NT ax = lift<NT>(a.x()), ay = lift<NT>(a.y()), az = lift<NT>(a.z());
  NT ux = lift<NT>(b.x()) - ax, uy = lift<NT>(b.y()) - ay, uz = lift<NT>(b.z()) - az;
  if (P.axis < 0) {
    const Vec3& c = s.verts[P.c];
    NT vx = lift<NT>(c.x()) - ax, vy = lift<NT>(c.y()) - ay, vz = lift<NT>(c.z()) - az;
    n[0] = uy * vz - uz * vy;
    n[1] = uz * vx - ux * vz;
    n[2] = ux * vy - uy * vx;
  } else if (P.axis == 0) {  // u x e_x
    n[0] = lift<NT>(0);
    n[1] = uz;
    n[2] = -uy;
  } else if (P.axis == 1) {  // u x e_y
    n[0] = -uz;
    n[1] = lift<NT>(0);
    n[2] = ux;
  } else {  // u x e_z
    n[0] = uy;
    n[1] = -ux;
    n[2] = lift<NT>(0);
  }
}

template <class NT>
void plane_eval(const Soup& s, const Plane& P, NT n[3], NT& d) {
  plane_normal(s, P, n);
  const Vec3& a = s.verts[P.a];
  d = -(n[0] * lift<NT>(a.x()) + n[1] * lift<NT>(a.y()) + n[2] * lift<NT>(a.z()));
}

// Whether coordinate i of point d is a double known without arithmetic (then set): an input
// vertex's; on a plane x_i = c (a triangle whose three vertices share coordinate i, or a wall
// over a segment with a_i = b_i); or, for an LPI, on a segment with p_i = q_i.
bool known_coordinate(const Soup& s, const PointDef& d, int i, double& c) {
  if (d.kind == PointDef::Explicit || (d.kind == PointDef::Lpi && s.verts[d.p][i] == s.verts[d.q][i])) {
    c = s.verts[d.p][i];
    return true;
  }
  const int planes = d.kind == PointDef::Tpi ? 3 : 1;
  for (int k = 0; k < planes; ++k)
    if (fixes_coordinate(s, d.P[k], i, c)) return true;
  return false;
}

template <class NT>
H<NT> point_eval(const Soup& s, const PointDef& def) {
  H<NT> h;
  if (def.kind == PointDef::Explicit) {
    const Vec3& p = s.verts[def.p];
    h.c[0] = lift<NT>(p.x());
    h.c[1] = lift<NT>(p.y());
    h.c[2] = lift<NT>(p.z());
    h.c[3] = lift<NT>(1);
    return h;
  }
  if (def.kind == PointDef::Lpi) {
    const Vec3& p = s.verts[def.p];
    const Vec3& q = s.verts[def.q];
    double c = 0;
    for (int k = 0; k < 3; ++k)
      if (fixes_coordinate(s, def.P[0], k, c)) {
        // The plane x_k = c: p + t (q - p) with t = (c - p_k) / (q_k - p_k), scaled by W = q_k - p_k:
        // coordinates of degree 2 instead of 4 (the general plane's normal and offset), so that
        // the filter is tighter and the exact path works on shorter numbers.
        const NT pk = lift<NT>(p[k]) - lift<NT>(c), qk = lift<NT>(q[k]) - lift<NT>(c);
        for (int i = 0; i < 3; ++i) h.c[i] = i == k ? lift<NT>(c) * (qk - pk) : lift<NT>(p[i]) * qk - lift<NT>(q[i]) * pk;
        h.c[3] = qk - pk;
        return h;
      }
    // The end points' distances from the plane as n . (p - a), a its first vertex: the same
    // numbers as n . p + d, but without d's terms, which grow with the coordinates while the
    // distances grow with the scene. (In that form, a part 1e-8 of its coordinates wide had the
    // filter's intervals of its cut points as wide as the part, and a union of four nearly
    // coincident spheres at 1e8 spent 2 s in double-double arithmetic where 0.1 s did at 0.)
    NT n[3];
    plane_normal(s, def.P[0], n);
    const Vec3& a = s.verts[def.P[0].a];
    NT dp = lift<NT>(0), dq = lift<NT>(0);
    for (int i = 0; i < 3; ++i) {
      dp = dp + n[i] * (lift<NT>(p[i]) - lift<NT>(a[i]));
      dq = dq + n[i] * (lift<NT>(q[i]) - lift<NT>(a[i]));
    }
    for (int i = 0; i < 3; ++i) h.c[i] = dp * lift<NT>(q[i]) - dq * lift<NT>(p[i]);
    h.c[3] = dp - dq;
    return h;
  }
  // Three planes n_k . (x - a_k) = 0, solved for x - v with v the first plane's first vertex (so
  // that the right-hand sides n_k . (a_k - v) grow with the scene, not the coordinates, as above),
  // then moved back by v W.
  NT n1[3], n2[3], n3[3];
  plane_normal(s, def.P[0], n1);
  plane_normal(s, def.P[1], n2);
  plane_normal(s, def.P[2], n3);
  const Vec3& v = s.verts[def.P[0].a];
  const Vec3& a2 = s.verts[def.P[1].a];
  const Vec3& a3 = s.verts[def.P[2].a];
  NT e2 = lift<NT>(0), e3 = lift<NT>(0);  // n_k . (a_k - v); the first plane's is 0
  for (int i = 0; i < 3; ++i) {
    e2 = e2 + n2[i] * (lift<NT>(a2[i]) - lift<NT>(v[i]));
    e3 = e3 + n3[i] * (lift<NT>(a3[i]) - lift<NT>(v[i]));
  }
  NT c23[3] = {n2[1] * n3[2] - n2[2] * n3[1], n2[2] * n3[0] - n2[0] * n3[2], n2[0] * n3[1] - n2[1] * n3[0]};
  NT c31[3] = {n3[1] * n1[2] - n3[2] * n1[1], n3[2] * n1[0] - n3[0] * n1[2], n3[0] * n1[1] - n3[1] * n1[0]};
  NT c12[3] = {n1[1] * n2[2] - n1[2] * n2[1], n1[2] * n2[0] - n1[0] * n2[2], n1[0] * n2[1] - n1[1] * n2[0]};
  h.c[3] = n1[0] * c23[0] + n1[1] * c23[1] + n1[2] * c23[2];
  for (int i = 0; i < 3; ++i) h.c[i] = e2 * c31[i] + e3 * c12[i] + lift<NT>(v[i]) * h.c[3];
  return h;
}

template <class NT>
H<NT> centroid_of(const H<NT>& a, const H<NT>& b, const H<NT>& c) {
  H<NT> h;
  NT bc = b.c[3] * c.c[3], ac = a.c[3] * c.c[3], ab = a.c[3] * b.c[3];
  for (int i = 0; i < 3; ++i) h.c[i] = a.c[i] * bc + b.c[i] * ac + c.c[i] * ab;
  h.c[3] = lift<NT>(3) * a.c[3] * bc;
  return h;
}

// Signs: +1, -1, or 0; for intervals, 2 when the interval contains zero (undecided).
int sign_of(const EX& x) {
  auto s = x.sign();
  return s == CGAL::POSITIVE ? 1 : (s == CGAL::NEGATIVE ? -1 : 0);
}
int sign_of(const IA& x) {
  if (x.inf() > 0) return 1;
  if (x.sup() < 0) return -1;
  if (x.inf() == 0 && x.sup() == 0) return 0;
  return 2;
}

// Product of signs, undecided (2) if any is.
int mul(int a, int b) { return (a == 2 || b == 2) ? 2 : a * b; }

H<IA> to_ia(const IntervalH& ih) {
  H<IA> h;
  for (int i = 0; i < 4; ++i) h.c[i] = IA(ih.lo[i], ih.hi[i]);
  return h;
}

template <class NT>
NT det3(const NT& a, const NT& b, const NT& c, const NT& d, const NT& e, const NT& f, const NT& g,
        const NT& h, const NT& i) {
  return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
}

template <class NT>
int orient2d_sign(const H<NT>& a, const H<NT>& b, const H<NT>& c, int k) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  NT det = det3(a.c[i], a.c[j], a.c[3], b.c[i], b.c[j], b.c[3], c.c[i], c.c[j], c.c[3]);
  return mul(sign_of(det), mul(sign_of(a.c[3]), mul(sign_of(b.c[3]), sign_of(c.c[3]))));
}

template <class NT>
int compare_sign(const H<NT>& a, const H<NT>& b, int axis) {
  NT d = a.c[axis] * b.c[3] - b.c[axis] * a.c[3];
  return mul(sign_of(d), mul(sign_of(a.c[3]), sign_of(b.c[3])));
}

template <class NT>
int side_sign(const Soup& s, const Plane& P, const H<NT>& p) {
  NT n[3], d;
  plane_eval(s, P, n, d);
  NT v = n[0] * p.c[0] + n[1] * p.c[1] + n[2] * p.c[2] + d * p.c[3];
  return mul(sign_of(v), sign_of(p.c[3]));
}

// Rows (x W^2, y W^2, (x^2 + y^2) W^2, W^2) = (X W, Y W, X^2 + Y^2, W^2): the affine rows of the
// classic 4x4 determinant times W^2 > 0, so the sign is the classic one. With a quadratic form q,
// its lifting q(X, Y) instead of X^2 + Y^2.
template <class NT>
int incircle_sign(const H<NT>& a, const H<NT>& b, const H<NT>& c, const H<NT>& d, int k,
                  const Points::Metric* q = nullptr) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  const H<NT>* p[4] = {&a, &b, &c, &d};
  NT m[4][4];
  for (int r = 0; r < 4; ++r) {
    const NT& X = p[r]->c[i];
    const NT& Y = p[r]->c[j];
    const NT& W = p[r]->c[3];
    m[r][0] = X * W;
    m[r][1] = Y * W;
    m[r][2] = q ? lift<NT>(q->q11) * X * X + lift<NT>(2 * q->q12) * X * Y + lift<NT>(q->q22) * Y * Y : X * X + Y * Y;
    m[r][3] = W * W;
  }
  // Laplace expansion along the last column.
  NT det = -m[0][3] * det3(m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2], m[3][0], m[3][1], m[3][2]) +
           m[1][3] * det3(m[0][0], m[0][1], m[0][2], m[2][0], m[2][1], m[2][2], m[3][0], m[3][1], m[3][2]) -
           m[2][3] * det3(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[3][0], m[3][1], m[3][2]) +
           m[3][3] * det3(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
  return sign_of(det);
}

// orient2d_sign and incircle_sign with the points' differences to the last one formed first: the
// same signs, for the double-double stage, whose error bound grows with the size of the terms it
// adds. Points a few ulps apart cancel here at low degree, where the bound is still tight, and
// not in the full determinant's terms (in-circle tests in a sliver's metric on points where
// three cylinders cross: 133 of 934 undecided in the 4x4 form). Rows are scaled by positive
// factors: (W_r W_last)^2 for the in-circle test; for orient2d the sign of W_a W_b remains.
template <class NT>
void differences(const H<NT>& p, const H<NT>& o, int i, int j, NT& dx, NT& dy) {
  dx = p.c[i] * o.c[3] - o.c[i] * p.c[3];  // (x_p - x_o) W_p W_o
  dy = p.c[j] * o.c[3] - o.c[j] * p.c[3];
}

template <class NT>
int orient2d_sign_rel(const H<NT>& a, const H<NT>& b, const H<NT>& c, int k) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  NT ax, ay, bx, by;
  differences(a, c, i, j, ax, ay);
  differences(b, c, i, j, bx, by);
  return mul(sign_of(ax * by - ay * bx), mul(sign_of(a.c[3]), sign_of(b.c[3])));
}

template <class NT>
int incircle_sign_rel(const H<NT>& a, const H<NT>& b, const H<NT>& c, const H<NT>& d, int k,
                      const Points::Metric* q = nullptr) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const H<NT>* p[3] = {&a, &b, &c};
  NT m[3][3];
  for (int r = 0; r < 3; ++r) {
    NT dx, dy;
    differences(*p[r], d, i, j, dx, dy);
    const NT w = p[r]->c[3] * d.c[3];
    m[r][0] = dx * w;
    m[r][1] = dy * w;
    m[r][2] = q ? lift<NT>(q->q11) * dx * dx + lift<NT>(2 * q->q12) * dx * dy + lift<NT>(q->q22) * dy * dy : dx * dx + dy * dy;
  }
  return sign_of(det3(m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]));
}

// A point's coordinate box on axes i and j as intervals; false if the box is unbounded (a point
// whose rounding fell back to the rational quotient outside its filter's interval).
bool box_ia(const std::array<double, 6>& b, int i, int j, IA& x, IA& y) {
  if (!(std::isfinite(b[i]) && std::isfinite(b[i + 3]) && std::isfinite(b[j]) && std::isfinite(b[j + 3]))) return false;
  x = IA(b[i], b[i + 3]);
  y = IA(b[j], b[j + 3]);
  return true;
}

// From a double guess g, the pair of adjacent doubles lo <= x <= hi around a number x (lo == hi
// where x is a double), stepping an ulp at a time; above(y) is the sign of x - y, or 2 where it is
// not known (then false). False too after `steps` steps or at an infinity.
template <class Above>
bool bracket(double g, int steps, Above&& above, double& lo, double& hi) {
  const int s = above(g);
  if (s == 2) return false;
  if (s == 0) {
    lo = hi = g;
    return true;
  }
  const double dir = s > 0 ? INFINITY : -INFINITY;
  for (int step = 0; step < steps; ++step) {
    const double h = std::nextafter(g, dir);
    if (!std::isfinite(h)) return false;
    const int t = above(h);
    if (t == 2) return false;
    if (t == 0) {
      lo = hi = h;
      return true;
    }
    if (t != s) {
      lo = std::min(g, h);
      hi = std::max(g, h);
      return true;
    }
    g = h;
  }
  return false;
}

// The exact quotient x = X / W (W of sign ws) between two adjacent doubles: lo <= x <= hi, with
// lo == hi when x is a double. Found from a double guess (the filter's interval midpoint, or
// the doubles' quotient) by the exact sign of X - g W (a double times an Mpzf is exact), stepping
// an ulp at a time. False if the guess is not finite or more than a few ulps off.
bool faithful(const EX& X, const EX& W, int ws, double mid, double ilo, double ihi, double& lo, double& hi) {
  double g = mid;
  if (!(std::isfinite(ilo) && std::isfinite(ihi) && std::isfinite(g))) g = CGAL::to_double(X) / CGAL::to_double(W);
  if (!std::isfinite(g)) return false;
  return bracket(g, 64, [&](double y) { return sign_of(X - EX(y) * W) * ws; }, lo, hi);
}

// faithful() in double-double arithmetic: false where a sign it needs is not decided (among them
// every x that is itself a double, unless X and W are exact), or the doubles' quotient is more
// than a few ulps off. The answer, where there is one, is faithful()'s: the pair of adjacent
// doubles around x, or x twice, is unique.
bool faithful_dd(const DD& X, const DD& W, int ws, double& lo, double& hi) {
  const double g = X.hi / W.hi;
  if (!std::isfinite(g)) return false;
  return bracket(g, 8, [&](double y) {
    const int s = sign_of(X - DD(y) * W);
    return s == 2 ? 2 : s * ws;
  }, lo, hi);
}

// Whether one of a box's three intervals holds a double whose significand ends in 26 zero bits or
// more (0 and the integers among them; 1 in 2^26 doubles otherwise). Infinite bounds: true.
bool holds_round_double(const std::array<double, 6>& b, std::uint8_t skip) {
  for (int i = 0; i < 3; ++i) {
    if (skip >> i & 1) continue;
    const double lo = b[i], hi = b[i + 3];
    if (!(std::isfinite(lo) && std::isfinite(hi))) return true;
    if (lo <= 0 && hi >= 0) return true;
    // The round doubles near x are the multiples of q = 2^(e - 26) (x in [2^e, 2^(e+1))): one lies
    // in [lo, hi] where the multiples of q next to lo and hi differ. (lo and hi share a sign and,
    // the box being a few ulps wide, nearly always an exponent; where not, q of the smaller.)
    const double m = std::min(std::abs(lo), std::abs(hi));
    int e = 0;
    std::frexp(m, &e);  // m in [2^(e-1), 2^e)
    const double q = std::ldexp(1.0, e - 1 - 26);
    if (std::floor(lo / q) != std::floor(hi / q) || lo / q == std::floor(lo / q)) return true;
  }
  return false;
}

}  // namespace

struct ExactPoint {
  H<EX> h;
};
struct DdPoint {
  H<DD> h;
};

Points::~Points() {
  for (ExactPoint* e : exact_) delete e;
  for (DdPoint* e : dd_) delete e;
}

namespace {

// The coordinates of point p kept in `cache` (made once, by whichever thread is first), or, for an
// input vertex, made in `scratch`.
template <class Kept, class A, class Eval>
const Kept& kept_point(std::vector<Kept*, A>& cache, u32 nin, u32 p, Kept& scratch, Eval&& eval) {
  if (p < nin) {
    scratch.h = eval();
    return scratch;
  }
  std::atomic_ref<Kept*> slot(cache[p - nin]);
  Kept* e = slot.load(std::memory_order_acquire);
  if (!e) {
    auto* made = new Kept{eval()};
    if (slot.compare_exchange_strong(e, made, std::memory_order_acq_rel)) e = made;
    else delete made;  // another thread was first: e holds its result
  }
  return *e;
}

}  // namespace

const ExactPoint& Points::exact(u32 p, ExactPoint& scratch) const {
  return kept_point(exact_, nin_, p, scratch, [&] { return point_eval<EX>(*soup_, def(p)); });
}

const DdPoint& Points::dd(u32 p, DdPoint& scratch) const {
  return kept_point(dd_, nin_, p, scratch, [&] { return point_eval<DD>(*soup_, def(p)); });
}

Points::Points(const Soup& soup) : soup_(&soup), nin_(static_cast<u32>(soup.verts.size())) {}

IntervalH Points::interval(u32 p) const {
  if (p >= nin_) return ih_[p - nin_];
  IntervalH ih;
  for (int i = 0; i < 3; ++i) ih.lo[i] = ih.hi[i] = soup_->verts[p][i];
  ih.lo[3] = ih.hi[3] = 1;
  return ih;
}

void Points::reserve(std::size_t n) {
  n = n > nin_ ? n - nin_ : 0;
  defs_.reserve(n);
  fixed_.reserve(n);
  approx_.reserve(n);
  ih_.reserve(n);
  box_.reserve(n);
  slack_.reserve(n);
  exact_.reserve(n);
  dd_.reserve(n);
}

u32 Points::add(const PointDef& d) {
  const u32 id = add_later(d);
  evaluate_added();
  return id;
}

u32 Points::add_later(const PointDef& d) {
  defs_.push_back(d);
  return static_cast<u32>(size() - 1);
}

void Points::evaluate_added() {
  const std::size_t from = fixed_.size(), to = defs_.size();
  if (from == to) return;
  fixed_.resize(to);
  approx_.resize(to);
  ih_.resize(to);
  box_.resize(to);
  slack_.resize(to);
  exact_.resize(to, nullptr);
  dd_.resize(to, nullptr);
  parallel_for(from, to, [&](std::size_t n) {
    if ((n & 0xfff) == 0) soup_->poll();
    evaluate(n);
  });
}

void Points::evaluate(std::size_t n) {
  const PointDef& d = defs_[n];
  IntervalH ih;
  Vec3 ap;
  std::array<double, 6> bx;
  {
    Filter guard;
    H<IA> h = point_eval<IA>(*soup_, d);
    for (int i = 0; i < 4; ++i) {
      ih.lo[i] = h.c[i].inf();
      ih.hi[i] = h.c[i].sup();
    }
    for (int i = 0; i < 3; ++i) {
      IA q = h.c[i] / h.c[3];
      ap[i] = q.inf() * 0.5 + q.sup() * 0.5;
      bx[i] = q.inf();
      bx[i + 3] = q.sup();
    }
  }
  // The approximation must be faithful (within an ulp of the exact coordinate): where the filter's
  // quotient is wider than that (a W near zero: a segment nearly parallel to its cutting plane),
  // the exact rational quotient is rounded instead.
  // Coordinates known without arithmetic (the c of an axis plane x_k = c that defines the point)
  // are set to c below: only the others need a faithful value here. (Left in, a known coordinate
  // that is a round double sent a point to the exact path: 1,226 of the classic figure's first
  // 4,096 cut points, each cut from a cube's face.)
  std::uint8_t known = 0;
  double known_c[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i)
    if (known_coordinate(*soup_, d, i, known_c[i])) known |= static_cast<std::uint8_t>(1u << i);
  bool tight = ap.allFinite() && (ih.lo[3] > 0 || ih.hi[3] < 0);
  for (int i = 0; i < 3 && tight; ++i)
    if (!(known >> i & 1) &&
        bx[i + 3] - bx[i] > 2 * std::numeric_limits<double>::epsilon() * std::max(std::abs(bx[i]), std::abs(bx[i + 3])))
      tight = false;
  // In double-double arithmetic next: it rounds every point it can decide, but not one with a
  // coordinate that is itself a double (it cannot prove a difference zero), which is nearly always
  // a round one (the plane of symmetry y = 0.75 between two spheres of a lattice, a cube's face
  // x = 1 met by a sphere's edge on it): where the box holds a double with 26 or more trailing
  // zero bits, the exact path is taken at once. Either way the answer is the same.
  if (!tight && ap.allFinite() && !holds_round_double(bx, known)) {
    const H<DD> dd = point_eval<DD>(*soup_, d);
    const int ws = sign_of(dd.c[3]);
    double lo[3], hi[3];
    tight = ws == 1 || ws == -1;
    for (int i = 0; i < 3 && tight; ++i)
      if (!(known >> i & 1)) tight = faithful_dd(dd.c[i], dd.c[3], ws, lo[i], hi[i]);
    if (tight)
      for (int i = 0; i < 3; ++i) {
        if (known >> i & 1) continue;
        ap[i] = lo[i] >= 0 ? lo[i] : hi[i];  // toward zero, as below
        bx[i] = lo[i];
        bx[i + 3] = hi[i];
      }
  }
  if (!tight) {
    H<EX> e = point_eval<EX>(*soup_, d);
    const int ws = sign_of(e.c[3]);
    if (ws == 0) fail("boolean: internal error: a constructed point has W = 0");
    for (int i = 0; i < 3; ++i) {
      if (known >> i & 1) continue;
      double lo = 0, hi = 0;
      if (faithful(e.c[i], e.c[3], ws, ap[i], bx[i], bx[i + 3], lo, hi)) {
        // Toward zero, as the exact rational quotient's conversion (mpq_get_d) rounded before:
        // the engine's results on near-coincident input depend on it (test_boolean_oracle's
        // sheets an ulp apart resolve with it, and not with round-to-nearest).
        ap[i] = lo >= 0 ? lo : hi;
        bx[i] = lo;
        bx[i + 3] = hi;
        continue;
      }
      // Far from any double guess (huge or tiny magnitudes, or a filter interval hundreds of ulps
      // wide): the exact rational quotient, and from it as the guess, the box of two doubles.
      // (Left as the filter's interval, the box of a point where nearly coincident operands cross
      // spanned the scene: 6,384 such points of five spheres turned by 1e-13 degrees were compared
      // exactly with every other point when merging equal points, three minutes.)
      const CGAL::Gmpq w = static_cast<CGAL::Gmpq>(e.c[3]);
      ap[i] = CGAL::to_double(static_cast<CGAL::Gmpq>(e.c[i]) / w);
      if (std::isfinite(ap[i]) && faithful(e.c[i], e.c[3], ws, ap[i], ap[i], ap[i], lo, hi)) {
        ap[i] = lo >= 0 ? lo : hi;
        bx[i] = lo;
        bx[i + 3] = hi;
        continue;
      }
      if (!std::isfinite(bx[i]) || !std::isfinite(bx[i + 3]) || !(bx[i] <= ap[i] && ap[i] <= bx[i + 3])) {
        bx[i] = -INFINITY;
        bx[i + 3] = INFINITY;
      }
    }
  }
  // Coordinates known exactly without arithmetic are the double c itself, so the point need not
  // move there when it is rounded.
  // So are coordinates whose box is one double: the arithmetic above was exact (a segment between
  // integer points cut by a diagonal wall through others, all over a sponge of boxes).
  std::uint8_t fixed = 0;
  for (int i = 0; i < 3; ++i) {
    if (known >> i & 1) {
      const double c = known_c[i];
      ap[i] = bx[i] = bx[i + 3] = c;
      fixed |= static_cast<std::uint8_t>(1u << i);
    } else if (bx[i] == bx[i + 3] && std::isfinite(bx[i])) {
      ap[i] = bx[i] == 0 ? 0.0 : bx[i];
      fixed |= static_cast<std::uint8_t>(1u << i);
    }
  }
  double w = 0;
  for (int i = 0; i < 3; ++i) w = std::max({w, ap[i] - bx[i], bx[i + 3] - ap[i]});
  fixed_[n] = fixed;
  approx_[n] = ap;
  ih_[n] = ih;
  box_[n] = bx;
  slack_[n] = w == w ? w : INFINITY;
}

// Fast paths: where every coordinate a predicate reads is known exactly (fixed), the predicate
// is the double one on approx(), itself exact (static filter, then CGAL's exact arithmetic).

// Whether three points are known to lie on one line without arithmetic: each is a cut point of
// the same segment p q (an LPI) or one of its end points, and at least one is a cut point.
bool Points::exact_position(const PointDef& d, Vec3& out) const {
  for (int i = 0; i < 3; ++i)
    if (!known_coordinate(*soup_, d, i, out[i])) return false;
  return true;
}

int Points::orient2d(u32 a, u32 b, u32 c, int k, const Plane* line) const {
  if (a == b || b == c || a == c) return 0;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  if (const int s = orient2d_first(projected(a, k), projected(b, k), projected(c, k)); s != 2) return s;
  {
    Filter guard;
    // First on the coordinate boxes (each an ulp or two wide), then on the homogeneous intervals.
    IA x[3], y[3];
    if (box_ia(box(a), i, j, x[0], y[0]) && box_ia(box(b), i, j, x[1], y[1]) && box_ia(box(c), i, j, x[2], y[2])) {
      int s = sign_of((x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]));
      if (s != 2) return s;
    }
    int s = orient2d_sign(to_ia(interval(a)), to_ia(interval(b)), to_ia(interval(c)), k);
    if (s != 2) return s;
  }
  if (on_one_segment(a, b, c) || (line && on_plane(c, *line)) || collinear_by_definition(a, b, c, k)) return 0;
  DdPoint ds[5];
  if (const int s = orient2d_sign_rel(dd(a, ds[0]).h, dd(b, ds[1]).h, dd(c, ds[2]).h, k); s != 2) return s;
  ExactPoint scratch[4];
  return orient2d_sign(exact(a, scratch[0]).h, exact(b, scratch[1]).h,
                       exact(c, scratch[2]).h, k);
}

int Points::compare(u32 a, u32 b, int axis) const {
  if (a == b) return 0;
  if (fixed(a) & fixed(b) & (1u << axis)) {
    const double x = approx(a)[axis], y = approx(b)[axis];
    return x < y ? -1 : (x > y ? 1 : 0);
  }
  {
    // The boxes hold the points exactly: apart on the axis, they decide (nearly every call).
    const auto ba = box(a), bb = box(b);
    if (ba[axis + 3] < bb[axis]) return -1;
    if (ba[axis] > bb[axis + 3]) return 1;
  }
  {
    Filter guard;
    int s = compare_sign(to_ia(interval(a)), to_ia(interval(b)), axis);
    if (s != 2) return s;
  }
  DdPoint ds[5];
  if (const int s = compare_sign(dd(a, ds[0]).h, dd(b, ds[1]).h, axis); s != 2) return s;
  ExactPoint scratch[4];
  return compare_sign(exact(a, scratch[0]).h, exact(b, scratch[1]).h, axis);
}

bool Points::equal(u32 a, u32 b) const {
  return a == b || (compare(a, b, 0) == 0 && compare(a, b, 1) == 0 && compare(a, b, 2) == 0);
}

int Points::compare_def(const PointDef& a, const PointDef& b, int axis) const {
  {
    Filter guard;
    int s = compare_sign(point_eval<IA>(*soup_, a), point_eval<IA>(*soup_, b), axis);
    if (s != 2) return s;
  }
  if (const int s = compare_sign(point_eval<DD>(*soup_, a), point_eval<DD>(*soup_, b), axis); s != 2) return s;
  return compare_sign(point_eval<EX>(*soup_, a), point_eval<EX>(*soup_, b), axis);
}

void Points::coord_bounds(const PointDef& d, int axis, double& lo, double& hi) const {
  const Soup& s = *soup_;
  double c = 0;
  if (known_coordinate(s, d, axis, c)) {
    lo = hi = c;
    return;
  }
  Filter guard;
  const H<IA> h = point_eval<IA>(s, d);
  if (h.c[3].inf() > 0 || h.c[3].sup() < 0) {
    const IA q = h.c[axis] / h.c[3];
    lo = q.inf();
    hi = q.sup();
  } else {
    lo = -INFINITY;
    hi = INFINITY;
  }
}

int Points::side(const Plane& P, u32 p) const {
  if (fixed(p) == 7) {
    const Vec3& a = soup_->verts[P.a];
    const Vec3& b = soup_->verts[P.b];
    const Vec3& q = approx(p);
    if (P.axis < 0) return orient3d_fast(a, b, soup_->verts[P.c], q);  // n . (q - a), n = (b - a) x (c - a)
    // A wall: n = (b - a) x e_k, and n . (q - a) = -orient2d(a, b, q) in the projection along e_k.
    const int i = (P.axis + 1) % 3, j = (P.axis + 2) % 3;
    return -orient2d_fast(a[i], a[j], b[i], b[j], q[i], q[j]);
  }
  {
    Filter guard;
    int s = side_sign(*soup_, P, to_ia(interval(p)));
    if (s != 2) return s;
  }
  DdPoint ds[5];
  if (const int s = side_sign(*soup_, P, dd(p, ds[0]).h); s != 2) return s;
  ExactPoint scratch[4];
  return side_sign(*soup_, P, exact(p, scratch[0]).h);
}

namespace {

// The smallest sine of an angle of the triangles any three of the four points make (from their
// approximate positions, in the plane (i, j)): where it is large, both ways of splitting the four
// points into two triangles are well shaped.
// Whether every triangle of three of the four points has no angle with a sine at most `well`
// (in the projection on axes i, j). A triangle's smallest sine is at the corner between its two
// longest edges: twice its area over their product, compared here squared (no roots).
bool well_shaped(const Vec3* p[4], int i, int j, double well) {
  double len[4][4];
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) {
      const double dx = (*p[b])[i] - (*p[a])[i], dy = (*p[b])[j] - (*p[a])[j];
      len[a][b] = len[b][a] = dx * dx + dy * dy;
    }
  const double w2 = well * well;
  for (int skip = 0; skip < 4; ++skip) {
    int t[3], n = 0;
    for (int q = 0; q < 4; ++q)
      if (q != skip) t[n++] = q;
    const Vec3 &o = *p[t[0]], &u = *p[t[1]], &v = *p[t[2]];
    const double cross = (u[i] - o[i]) * (v[j] - o[j]) - (u[j] - o[j]) * (v[i] - o[i]);
    const double e[3] = {len[t[0]][t[1]], len[t[1]][t[2]], len[t[0]][t[2]]};
    const double shortest = std::min({e[0], e[1], e[2]});
    const double product = shortest == e[0] ? e[1] * e[2] : (shortest == e[1] ? e[0] * e[2] : e[0] * e[1]);
    if (!(cross * cross > w2 * product)) return false;
  }
  return true;
}

}  // namespace

// The in-circle sign (in the metric q, if given) on the points' coordinate boxes, relative to d
// (the 3x3 form), then on their homogeneous intervals; 2 where neither decides.
int Points::incircle_interval(u32 a, u32 b, u32 c, u32 d, int k, const Metric* q) const {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  Filter guard;
  const u32 id[3] = {a, b, c};
  IA dx0, dy0, r[3][3];
  bool boxed = box_ia(box(d), i, j, dx0, dy0);
  for (int n = 0; n < 3 && boxed; ++n) {
    IA x, y;
    boxed = box_ia(box(id[n]), i, j, x, y);
    r[n][0] = x - dx0;
    r[n][1] = y - dy0;
    r[n][2] = q ? IA(q->q11) * CGAL::square(r[n][0]) + IA(2 * q->q12) * r[n][0] * r[n][1] + IA(q->q22) * CGAL::square(r[n][1])
                : r[n][0] * r[n][0] + r[n][1] * r[n][1];
  }
  int s = 2;
  if (boxed) s = sign_of(det3(r[0][0], r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1], r[2][2]));
  if (s == 2) s = incircle_sign(to_ia(interval(a)), to_ia(interval(b)), to_ia(interval(c)), to_ia(interval(d)), k, q);
  return s;
}

int Points::incircle_certain(u32 a, u32 b, u32 c, u32 d, int k, double well) const {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const std::uint8_t m = static_cast<std::uint8_t>(1u << i | 1u << j);
  const bool doubles = (fixed(a) & fixed(b) & fixed(c) & fixed(d) & m) == m;
  if (const int s = incircle_first(projected(a, k), projected(b, k), projected(c, k), projected(d, k)); s != 2)
    return s;
  if (!doubles) {
    const int s = incircle_interval(a, b, c, d, k, nullptr);
    if (s != 2) return s == 1 ? 1 : -1;
  }
  // Too close to cocircular for the filter. Where every triangle either split would make is well
  // shaped (no angle under about half a degree), the split in place stays: no exact arithmetic.
  // Where one would be a sliver, the exact test decides, so that slivers are flipped away as a
  // true Delaunay triangulation would.
  const Vec3* p[4] = {&approx(a), &approx(b), &approx(c), &approx(d)};
  if (well_shaped(p, i, j, well)) return -1;
  if (doubles) {
    auto p2 = [&](u32 x) { return Point2(approx(x)[i], approx(x)[j]); };
    return wedge::incircle(p2(a), p2(b), p2(c), p2(d)) == 1 ? 1 : -1;
  }
  DdPoint ds[5];
  if (const int s = incircle_sign_rel(dd(a, ds[0]).h, dd(b, ds[1]).h, dd(c, ds[2]).h, dd(d, ds[3]).h, k); s != 2)
    return s == 1 ? 1 : -1;
  ExactPoint scratch[4];
  return incircle_sign(exact(a, scratch[0]).h, exact(b, scratch[1]).h,
                       exact(c, scratch[2]).h, exact(d, scratch[3]).h, k) == 1
             ? 1
             : -1;
}

int Points::incircle_certain(u32 a, u32 b, u32 c, u32 d, int k, double well, const Metric& q) const {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const u32 id[4] = {a, b, c, d};
  {
    const Approx2 ap[4] = {projected(a, k), projected(b, k), projected(c, k), projected(d, k)};
    const Approx2* p[4] = {&ap[0], &ap[1], &ap[2], &ap[3]};
    if (const int s = incircle_first(p, q.q11, q.q12, q.q22); s != 2) return s;
  }
  if (const int s = incircle_interval(a, b, c, d, k, &q); s != 2) return s == 1 ? 1 : -1;
  // Shapes are judged where the form is the plain one: mapped by its square root (Cholesky).
  const double l11 = std::sqrt(q.q11), l12 = q.q12 / l11, l22 = std::sqrt(std::max(0.0, q.q22 - l12 * l12));
  Vec3 mapped[4];
  const Vec3* p[4];
  for (int n = 0; n < 4; ++n) {
    const Vec3& x = approx(id[n]);
    mapped[n] = Vec3(l11 * x[i] + l12 * x[j], l22 * x[j], 0);
    p[n] = &mapped[n];
  }
  if (well_shaped(p, 0, 1, well)) return -1;
  DdPoint ds[5];
  if (const int s = incircle_sign_rel(dd(a, ds[0]).h, dd(b, ds[1]).h, dd(c, ds[2]).h, dd(d, ds[3]).h, k, &q);
      s != 2)
    return s == 1 ? 1 : -1;
  ExactPoint scratch[4];
  return incircle_sign(exact(a, scratch[0]).h, exact(b, scratch[1]).h, exact(c, scratch[2]).h,
                       exact(d, scratch[3]).h, k, &q) == 1
             ? 1
             : -1;
}

int Points::orient2d_centroid(u32 u, u32 v, const std::array<u32, 3>& t, int k) const {
  {
    Filter guard;
    // First on the coordinate boxes, relative to u (three times the centroid's offset from it):
    // the homogeneous form's terms grow with the coordinates, the offsets with the scene.
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    IA x[5], y[5];
    const u32 id[5] = {u, v, t[0], t[1], t[2]};
    bool boxed = true;
    for (int n = 0; n < 5 && boxed; ++n) boxed = box_ia(box(id[n]), i, j, x[n], y[n]);
    if (boxed) {
      const IA sx = (x[2] - x[0]) + (x[3] - x[0]) + (x[4] - x[0]), sy = (y[2] - y[0]) + (y[3] - y[0]) + (y[4] - y[0]);
      if (const int s = sign_of((x[1] - x[0]) * sy - (y[1] - y[0]) * sx); s != 2) return s;
    }
    H<IA> c = centroid_of(to_ia(interval(t[0])), to_ia(interval(t[1])), to_ia(interval(t[2])));
    int s = orient2d_sign(to_ia(interval(u)), to_ia(interval(v)), c, k);
    if (s != 2) return s;
  }
  {
    DdPoint ds[5];
    const H<DD> c = centroid_of(dd(t[0], ds[0]).h, dd(t[1], ds[1]).h, dd(t[2], ds[2]).h);
    if (const int s = orient2d_sign_rel(dd(u, ds[3]).h, dd(v, ds[4]).h, c, k); s != 2) return s;
  }
  ExactPoint scratch[4];
  H<EX> c = centroid_of(exact(t[0], scratch[0]).h, exact(t[1], scratch[1]).h,
                        exact(t[2], scratch[2]).h);
  return orient2d_sign(exact(u, scratch[0]).h, exact(v, scratch[1]).h, c, k);
}

int Points::side_centroid(const Plane& P, const std::array<u32, 3>& t) const {
  {
    Filter guard;
    // First on the coordinate boxes, relative to the plane's first vertex (as orient2d_centroid).
    IA n[3], r[3] = {IA(0), IA(0), IA(0)};
    bool boxed = true;
    for (int m = 0; m < 3 && boxed; ++m) {
      const auto b = box(t[m]);
      for (int i = 0; i < 3 && boxed; ++i) {
        boxed = std::isfinite(b[i]) && std::isfinite(b[i + 3]);
        if (boxed) r[i] += IA(b[i], b[i + 3]) - IA(soup_->verts[P.a][i]);
      }
    }
    if (boxed) {
      plane_normal(*soup_, P, n);
      if (const int s = sign_of(n[0] * r[0] + n[1] * r[1] + n[2] * r[2]); s != 2) return s;
    }
    H<IA> c = centroid_of(to_ia(interval(t[0])), to_ia(interval(t[1])), to_ia(interval(t[2])));
    int s = side_sign(*soup_, P, c);
    if (s != 2) return s;
  }
  {
    DdPoint ds[5];
    const H<DD> c = centroid_of(dd(t[0], ds[0]).h, dd(t[1], ds[1]).h, dd(t[2], ds[2]).h);
    if (const int s = side_sign(*soup_, P, c); s != 2) return s;
  }
  ExactPoint scratch[4];
  H<EX> c = centroid_of(exact(t[0], scratch[0]).h, exact(t[1], scratch[1]).h,
                        exact(t[2], scratch[2]).h);
  return side_sign(*soup_, P, c);
}

std::array<double, 6> Points::centroid_box(const std::array<u32, 3>& t) const {
  std::array<double, 6> b;
  Filter guard;
  H<IA> c = centroid_of(to_ia(interval(t[0])), to_ia(interval(t[1])), to_ia(interval(t[2])));
  const bool w_sign = c.c[3].inf() > 0 || c.c[3].sup() < 0;
  for (int i = 0; i < 3; ++i) {
    IA q = c.c[i] / c.c[3];
    const bool ok = w_sign && std::isfinite(q.inf()) && std::isfinite(q.sup());
    b[i] = ok ? q.inf() : -INFINITY;
    b[i + 3] = ok ? q.sup() : INFINITY;
  }
  return b;
}

int Points::cross_sign(const Plane& P, const Plane& Q, int axis) const {
  int i = (axis + 1) % 3, j = (axis + 2) % 3;
  {
    Filter guard;
    IA n[3], m[3], d, e;
    plane_eval(*soup_, P, n, d);
    plane_eval(*soup_, Q, m, e);
    int s = sign_of(n[i] * m[j] - n[j] * m[i]);
    if (s != 2) return s;
  }
  {
    DD n[3], m[3], d, e;
    plane_eval(*soup_, P, n, d);
    plane_eval(*soup_, Q, m, e);
    if (const int s = sign_of(n[i] * m[j] - n[j] * m[i]); s != 2) return s;
  }
  EX n[3], m[3], d, e;
  plane_eval(*soup_, P, n, d);
  plane_eval(*soup_, Q, m, e);
  return sign_of(n[i] * m[j] - n[j] * m[i]);
}

int orient2d_undecided(double ax, double ay, double bx, double by, double cx, double cy) {
  // Three points on one axis-parallel line (common in CAD input), or two equal, are exactly
  // collinear.
  if ((ax == bx && bx == cx) || (ay == by && by == cy)) return 0;
  if ((ax == bx && ay == by) || (ax == cx && ay == cy) || (bx == cx && by == cy)) return 0;
  {  // double-double first, as in orient3d_undecided
    const DD ux = DD(bx) - DD(ax), uy = DD(by) - DD(ay), vx = DD(cx) - DD(ax), vy = DD(cy) - DD(ay);
    if (const int s = sign_of(ux * vy - uy * vx); s != 2) return s;
  }
  return wedge::orient2d(Point2(ax, ay), Point2(bx, by), Point2(cx, cy));
}

int orient3d_undecided(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Two of the points equal (a neighbouring triangle's corner tested against a triangle's plane),
  // or four points on one axis-parallel plane (the faces of boxes, plates and cylinder caps): they
  // are exactly coplanar, and the exact predicate would take its slowest path to say so. So are four
  // points that, seen along an axis, are at most two points (the quads of a cylinder's or an
  // extrusion's side: they lie in the wall over the segment between those two).
  if (d == a || d == b || d == c || a == b || a == c || b == c) return 0;
  for (int k = 0; k < 3; ++k) {
    if (a[k] == b[k] && b[k] == c[k] && c[k] == d[k]) return 0;
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const Vec3* other = nullptr;
    bool two = true;
    for (const Vec3* p : {&b, &c, &d}) {
      if ((*p)[i] == a[i] && (*p)[j] == a[j]) continue;
      if (!other) other = p;
      else if ((*p)[i] != (*other)[i] || (*p)[j] != (*other)[j]) {
        two = false;
        break;
      }
    }
    if (two) return 0;
  }
  // Double-double with its error bound next: nearly coplanar points (sheets turned by 1e-12
  // degrees) are decided here, and only exact zeros and the like go on to CGAL's exact
  // arithmetic (a union of two such 87k-triangle results asked the exact predicate 12.7 million
  // times, and this stage decided all but 1,118 of them). The differences are exact double-words.
  {
    const DD bx = DD(b.x()) - DD(a.x()), by = DD(b.y()) - DD(a.y()), bz = DD(b.z()) - DD(a.z());
    const DD cx = DD(c.x()) - DD(a.x()), cy = DD(c.y()) - DD(a.y()), cz = DD(c.z()) - DD(a.z());
    const DD dx = DD(d.x()) - DD(a.x()), dy = DD(d.y()) - DD(a.y()), dz = DD(d.z()) - DD(a.z());
    if (const int s = sign_of(det3(bx, by, bz, cx, cy, cz, dx, dy, dz)); s != 2) return s;
  }
  return wedge::orient3d(a, b, c, d);
}

int orient3d_v(const Soup& s, u32 a, u32 b, u32 c, u32 d) {
  return orient3d_fast(s.verts[a], s.verts[b], s.verts[c], s.verts[d]);
}

}  // namespace wedge::boolean_detail
