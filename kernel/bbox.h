// Axis-aligned bounding boxes. An empty box has min = +inf, max = -inf, so extend() needs no
// special first case.
#pragma once
#include <algorithm>
#include <limits>

#include "kernel/types.h"

namespace wedge {

template <class V>
struct BoxT {
  V min = V::Constant(std::numeric_limits<double>::infinity());
  V max = V::Constant(-std::numeric_limits<double>::infinity());

  BoxT() = default;
  BoxT(const V& lo, const V& hi) : min(lo), max(hi) {}

  bool empty() const { return (min.array() > max.array()).any(); }
  void extend(const V& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void extend(const BoxT& b) {
    if (b.empty()) return;
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  V size() const { return empty() ? V::Zero().eval() : (max - min).eval(); }
  V center() const { return (0.5 * (min + max)).eval(); }
  double diagonal() const { return empty() ? 0.0 : (max - min).norm(); }
  bool contains(const V& p, double tol = 0.0) const {
    return ((p.array() >= min.array() - tol).all() && (p.array() <= max.array() + tol).all());
  }
  bool intersects(const BoxT& b, double tol = 0.0) const {
    if (empty() || b.empty()) return false;
    return ((min.array() <= b.max.array() + tol).all() && (b.min.array() <= max.array() + tol).all());
  }
  BoxT inflated(double d) const { return empty() ? *this : BoxT(min - V::Constant(d), max + V::Constant(d)); }
};

using Box2 = BoxT<Vec2>;
using Box3 = BoxT<Vec3>;

}  // namespace wedge
