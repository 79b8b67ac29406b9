// wedge::surfaces — curves and surfaces. The interfaces every curve and surface implements;
// the concrete kinds (Bezier, B-spline, NURBS, interpolating splines, swept surfaces) build on them.
#pragma once
#include <utility>

#include "kernel/kernel.h"

namespace wedge {

// A parametric curve C(t) in 3D (2D curves have z = 0) over the interval [t0, t1].
class Curve {
 public:
  virtual ~Curve() = default;
  virtual std::pair<double, double> domain() const = 0;
  virtual Point3 eval(double t) const = 0;
  // The k-th derivative at t (k = 0 is the point itself).
  virtual Vec3 derivative(double t, int k) const = 0;
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
  // The unit normal Su x Sv (zero where the surface is degenerate).
  Vec3 normal(double u, double v) const {
    Vec3 n = derivative(u, v, 1, 0).cross(derivative(u, v, 0, 1));
    double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
  }
};

}  // namespace wedge
