// Mass properties from the exact geometry, never from triangles.
//
// Method: the divergence theorem turns each volume integral into a surface integral,
//   V = 1/3 ∮ x·n dA,  ∫ x_i dV = 1/2 ∮ x_i² n_i dA,  ∫ x_i² dV = 1/3 ∮ x_i³ n_i dA,
//   ∫ x_i x_j dV = 1/2 ∮ x_i² x_j n_i dA (i ≠ j),
// with x measured from a reference point near the solid (less cancellation). A parametric
// face covers its whole parameter rectangle, so its integral is a tensor Gauss-Legendre
// rule over the rectangle (split at the surface's breaks, then into panels), with n dA = ±Su x Sv
// du dv. A planar face is any region bounded by its edges' curves: Green's theorem in the plane's
// frame (s, t), ∫∫ h ds dt = ∮ P dt with P(s, t) = ∫_0^s h(σ, t) dσ, and P itself is a 3-point
// Gauss rule in σ (exact: h is a polynomial of degree <= 3), integrated along every edge curve.
// The integrands are smooth (polynomials and trigonometric polynomials for the quadrics), so the
// rule converges to rounding error: a sphere's volume agrees with 4/3 pi r^3 to about 1e-15.
#include <algorithm>
#include <cmath>

#include "brep/brep.h"
#include "kernel/scaled.h"

namespace wedge {

namespace {

// Gauss-Legendre nodes and weights on [-1, 1], by Newton's method on P_n (Golub-Welsch is not
// needed for n this small).
struct Gauss {
  std::vector<double> x, w;
  explicit Gauss(int n) {
    x.resize(static_cast<std::size_t>(n));
    w.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = 0;
        for (int k = 1; k <= n; ++k) {
          double p2 = p1;
          p1 = p0;
          p0 = ((2 * k - 1) * z * p1 - (k - 1) * p2) / k;
        }
        dp = n * (z * p0 - p1) / (z * z - 1);
        double dz = p0 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-16) break;
      }
      x[static_cast<std::size_t>(i)] = z;
      w[static_cast<std::size_t>(i)] = 2 / ((1 - z * z) * dp * dp);
    }
  }
};

const Gauss& gauss16() {
  static const Gauss g(16);
  return g;
}

const Gauss& gauss3() {
  static const Gauss g(3);
  return g;
}

const Gauss& gauss4() {
  static const Gauss g(4);
  return g;
}

// Accumulated surface integrals (the divergence-theorem forms above).
struct Moments {
  double area = 0, vol = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  // One quadrature point: x relative to the reference, N the area-weighted outward normal times
  // the weight, `da` the weighted area element.
  void add(const Vec3& x, const Vec3& N, double da) {
    area += da;
    vol += x.dot(N) / 3;
    for (int i = 0; i < 3; ++i) {
      first[i] += x[i] * x[i] * N[i] / 2;
      second(i, i) += x[i] * x[i] * x[i] * N[i] / 3;
      for (int j = i + 1; j < 3; ++j) second(i, j) += x[i] * x[i] * x[j] * N[i] / 2;
    }
  }
};

// Panels of [a, b] split at the breaks, each break interval into `per` equal pieces.
std::vector<double> panels(std::vector<double> breaks, double a, double b, int per) {
  std::vector<double> cuts{a};
  std::sort(breaks.begin(), breaks.end());
  for (double t : breaks)
    if (t > a + 1e-14 * (b - a) && t < b - 1e-14 * (b - a)) cuts.push_back(t);
  cuts.push_back(b);
  std::vector<double> out{a};
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i)
    for (int k = 1; k <= per; ++k) out.push_back(cuts[i] + (cuts[i + 1] - cuts[i]) * k / per);
  return out;
}

}  // namespace

MassProperties Model::exact_mass(bool rough) const {
  // Measured in the frame of the vertices' box (kernel/mesh.h), or of the sampled bounds where the
  // vertices span nothing (a torus's one vertex): x and areas divided by its scale, so that the
  // moments of a part 1e90 (or 1e-90) wide neither overflow nor underflow.
  Box3 box;
  vertices_.for_each([&](VertexId v, const BrepVertex&) { box.extend(point(v)); });
  if (!(box.size().maxCoeff() > 0)) box = bounds();
  const MomentFrame frame(box);
  const double per_area = 1 / (frame.scale * frame.scale);
  // `rough` (approximate_volume, for validate()'s sign check): 4 points and half the panels per
  // break, 64 times fewer surface evaluations per face; still within about 1e-6 of the volume
  // for the quadrics.
  const Gauss& g = rough ? gauss4() : gauss16();
  const int per = rough ? 2 : 4;
  Moments mo;
  faces_.for_each([&](FaceId f, const BrepFace& face) {
    const FaceSurface& fs = surface(f);
    std::vector<LoopId> ls{face.outer};
    ls.insert(ls.end(), face.rings.begin(), face.rings.end());
    if (const FaceSurface* ps = &fs; ps->parametric) {
      const Surface& S = *ps->surface;
      auto [u0, u1] = S.u_domain();
      auto [v0, v1] = S.v_domain();
      // The face must cover its rectangle: its loops' images in (u, v) (poles joined straight)
      // enclose the rectangle's area.
      double a2 = 0;
      for (LoopId l : ls) {
        std::vector<Vec2> poly;
        for (EdgeSide sd : loop_sides(l)) {
          const PCurve* pc = pcurve(sd);
          if (!pc) fail("mass properties: face ", f.value, " has a side without a parameter-space curve");
          poly.push_back(sd.side == 0 ? pc->start : pc->end);
          poly.push_back(sd.side == 0 ? pc->end : pc->start);
        }
        for (std::size_t i = 0; i < poly.size(); ++i) {
          const Vec2& p = poly[i];
          const Vec2& q = poly[(i + 1) % poly.size()];
          a2 += p.x() * q.y() - q.x() * p.y();
        }
      }
      double rect = (u1 - u0) * (v1 - v0);
      if (std::abs(std::abs(a2 / 2) - rect) > 1e-9 * rect)
        fail("mass properties: face ", f.value, " is a trimmed piece of its surface (not supported yet)");
      double sign = ps->reversed ? -1.0 : 1.0;
      // Where the integrands are polynomials of degree <= 4 in u (a revolved straight piece), one
      // panel per break interval and 3 points along u are exact (a revolve's volume() over
      // 20,000 profile points: 1.0 -> 0.1 s).
      const bool affine_u = S.affine_area_in_u();
      const Gauss& gu_rule = affine_u ? gauss3() : g;
      std::vector<double> us = panels(S.u_breaks(), u0, u1, affine_u ? 1 : per), vs = panels(S.v_breaks(), v0, v1, per);
      // Each panel's points as one grid (jet_grid: a surface of revolution turns each profile
      // point by one sine and cosine per column; point by point, sincos was a third of a
      // revolve's volume() over 2,000 profile points).
      const std::size_t nu = gu_rule.x.size(), nv = g.x.size();
      std::vector<double> gu(nu), gv(nv);
      std::vector<Vec3> jets(nu * nv * 6);
      for (std::size_t i = 0; i + 1 < us.size(); ++i)
        for (std::size_t j = 0; j + 1 < vs.size(); ++j) {
          double hu = (us[i + 1] - us[i]) / 2, hv = (vs[j + 1] - vs[j]) / 2;
          double mu = (us[i + 1] + us[i]) / 2, mv = (vs[j + 1] + vs[j]) / 2;
          for (std::size_t a = 0; a < nu; ++a) gu[a] = mu + hu * gu_rule.x[a];
          for (std::size_t b = 0; b < nv; ++b) gv[b] = mv + hv * g.x[b];
          S.jet_grid(gu.data(), static_cast<int>(nu), gv.data(), static_cast<int>(nv), 1, jets.data());
          for (std::size_t a = 0; a < nu; ++a)
            for (std::size_t b = 0; b < nv; ++b) {
              const Vec3* J = &jets[(a * nv + b) * 6];
              double w = gu_rule.w[a] * g.w[b] * hu * hv;
              Vec3 N = sign * per_area * J[1].cross(J[2]);
              mo.add(frame.local(J[0]), w * N, w * N.norm());
            }
        }
      return;
    }
    if (fs.cylinder())
      fail("mass properties: face ", f.value, " is a cylinder patch of the planar builders (not integrated exactly)");
    // A planar face: frame (o; e1, e2, n) with e1 x e2 = n outward.
    Vec3 n = face_normal(f);
    Point3 o = point(loops_[face.outer].first.valid() ? origin(loops_[face.outer].first) : loops_[face.outer].lone);
    if (const Plane* pl = fs.plane()) o = pl->origin();
    Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    Vec3 e1 = helper.cross(n).normalized();
    e1 = n.cross(e1).cross(n).normalized();
    Vec3 e2 = n.cross(e1);
    static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
    static const double gw[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    for (LoopId l : ls)
      for (EdgeSide sd : loop_sides(l)) {
        CurvePtr C = edge_curve(sd.edge);
        auto [t0, t1] = C->domain();
        bool straight = !curve(sd.edge);
        std::vector<double> ts = panels(C->breaks(), t0, t1, straight ? 1 : 2 * per);
        double dir = sd.side == 0 ? 1.0 : -1.0;
        for (std::size_t i = 0; i + 1 < ts.size(); ++i) {
          double h = (ts[i + 1] - ts[i]) / 2, m = (ts[i + 1] + ts[i]) / 2;
          for (std::size_t a = 0; a < g.x.size(); ++a) {
            double t = m + h * g.x[a];
            Vec3 p = C->eval(t) - o;
            double s = p.dot(e1), tt = p.dot(e2), dt = dir * C->derivative(t, 1).dot(e2) * g.w[a] * h;
            // P(s, tt) dt = s ∫_0^1 h(τ s, tt) dτ dt, the inner integral by 3-point Gauss.
            for (int k = 0; k < 3; ++k) {
              double sk = s * (gx[k] + 1) / 2, wk = gw[k] / 2 * s * dt * per_area;
              mo.add(frame.local(o + sk * e1 + tt * e2), wk * n, wk);
            }
          }
        }
      }
  });
  Mat3 second = mo.second;
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) second(j, i) = second(i, j);
  MassProperties mp = frame.from_frame(mo.vol, mo.area, mo.first, second);
  if (!(mp.volume > 0)) return {mp.volume, mp.area, Point3::Zero(), Mat3::Zero()};  // inside out or flat: mass_properties() reports it
  return mp;
}

}  // namespace wedge
