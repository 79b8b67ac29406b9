#include "csg/shading.h"
#include "kernel/scaled.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace wedge {

namespace {
bool finite(const Vec2& uv) { return std::isfinite(uv.x()) && std::isfinite(uv.y()); }

// The unit normal Su x Sv at (u, v); at a pole (Su or Sv zero there) its limit, from the first
// order expansion Su(u, v + h) = h Suv (or Sv(u + h, v) = h Suv): the direction Suv x Sv (or
// Su x Suv), oriented as Surface::normal's step inside the domain says.
Vec3 surface_normal(const Surface& S, const Vec2& uv) {
  const Vec3 su = S.derivative(uv.x(), uv.y(), 1, 0), sv = S.derivative(uv.x(), uv.y(), 0, 1);
  const Vec3 n = su.cross(sv);
  const double scale = su.norm() * sv.norm();
  if (scaled_norm(n) > 1e-8 * scale && scale > 0) return unit_vector(n);
  const Vec3 approx = S.normal(uv.x(), uv.y());
  const Vec3 suv = S.derivative(uv.x(), uv.y(), 1, 1);
  const Vec3 m = unit_vector(su.norm() < sv.norm() ? suv.cross(sv) : su.cross(suv));
  if (m == Vec3::Zero()) return approx;
  return approx.dot(m) < 0 ? Vec3(-m) : m;
}
}  // namespace

Vec2 closest_parameters(const Surface& S, const Point3& p, const Vec2& guess) {
  auto [u0, u1] = S.u_domain();
  auto [v0, v1] = S.v_domain();
  Vec2 uv = guess;
  if (!finite(uv)) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 16; ++i)
      for (int j = 0; j <= 16; ++j) {
        const Vec2 c(u0 + (u1 - u0) * i / 16, v0 + (v1 - v0) * j / 16);
        const double d = (S.eval(c.x(), c.y()) - p).squaredNorm();
        if (d < best) best = d, uv = c;
      }
  }
  uv.x() = std::clamp(uv.x(), u0, u1);
  uv.y() = std::clamp(uv.y(), v0, v1);
  // Gauss-Newton on |S(u, v) - p|^2: (J^T J) d = -J^T r with J = [Su Sv]. Off the surface by the
  // tolerance at most, each step divides the error by about distance x curvature; a small ridge
  // on the diagonal keeps a pole (Su = 0) from dividing by zero.
  for (int it = 0; it < 12; ++it) {
    const Vec3 r = S.eval(uv.x(), uv.y()) - p;
    const Vec3 su = S.derivative(uv.x(), uv.y(), 1, 0), sv = S.derivative(uv.x(), uv.y(), 0, 1);
    // The system divided by the larger of |Su|, |Sv| squared: on a surface 1e90 wide the products
    // a c of its entries are beyond doubles (the step d is the same).
    const double k = std::max(su.cwiseAbs().maxCoeff(), sv.cwiseAbs().maxCoeff());
    if (!(k > 0) || !std::isfinite(k)) break;
    const Vec3 ku = su / k, kv = sv / k;
    double a = ku.squaredNorm(), b = ku.dot(kv), c = kv.squaredNorm();
    const double ridge = 1e-14 * (a + c);
    a += ridge;
    c += ridge;
    const double det = a * c - b * b;
    if (!(det > 0)) break;
    const double gu = ku.dot(r) / k, gv = kv.dot(r) / k;
    const Vec2 d((-c * gu + b * gv) / det, (b * gu - a * gv) / det);
    const Vec2 next(std::clamp(uv.x() + d.x(), u0, u1), std::clamp(uv.y() + d.y(), v0, v1));
    const bool done = std::abs(next.x() - uv.x()) <= 1e-15 * (u1 - u0 + std::abs(uv.x())) &&
                      std::abs(next.y() - uv.y()) <= 1e-15 * (v1 - v0 + std::abs(uv.y()));
    uv = next;
    if (done) break;
  }
  return uv;
}

unsigned pole_corners(const Surface& S, const std::array<Vec2, 3>& uv, int& free) {
  unsigned mask = 0;
  for (int k = 2; k >= 0; --k) {
    Vec3 J[3];
    S.jet(uv[static_cast<std::size_t>(k)].x(), uv[static_cast<std::size_t>(k)].y(), 1, J);
    const double su = J[1].norm(), sv = J[2].norm();
    if (su <= 1e-9 * sv) mask |= 1u << k, free = 0;
    else if (sv <= 1e-9 * su) mask |= 1u << k, free = 1;
  }
  return mask;
}

const Surface* parametric_surface(const Mesh& mesh, const std::vector<FaceSurface>& surfaces, std::size_t t) {
  if (t >= mesh.face_ids.size()) return nullptr;
  const std::int32_t id = mesh.face_ids[t];
  if (id < 0 || static_cast<std::size_t>(id) >= surfaces.size()) return nullptr;
  const FaceSurface& fs = surfaces[static_cast<std::size_t>(id)];
  return fs.parametric ? fs.surface.get() : nullptr;
}

std::array<Vec2, 3> interpolated_uv(const Mesh& in, const CornerUvs& in_uv, std::size_t source, const Mesh& out,
                                    std::size_t t, const Surface* S) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::array<Vec2, 3> res{Vec2(nan, nan), Vec2(nan, nan), Vec2(nan, nan)};
  if (source >= in_uv.size()) return res;
  const auto& uv = in_uv[source];
  if (!finite(uv[0]) || !finite(uv[1]) || !finite(uv[2])) return res;
  const auto& T = in.triangles[source];
  const Point3 &a = in.positions[T[0]], &b = in.positions[T[1]], &c = in.positions[T[2]];
  // Measured in units of the triangle's size (a power of two: exact): the products below are of
  // degree 4 in its coordinates, and at size 1e80 (1e-85) they overflowed (underflowed), every
  // corner got the source's first uv, and the curved volume lost its caps.
  const double unit = std::ldexp(1.0, std::ilogb(std::max((b - a).cwiseAbs().maxCoeff(), (c - a).cwiseAbs().maxCoeff())));
  if (!(unit > 0) || !std::isfinite(unit)) return res;
  const Vec3 e1 = (b - a) / unit, e2 = (c - a) / unit;
  const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), det = d11 * d22 - d12 * d12;
  // The poles are looked for only when a corner is not one of the source's: most output
  // triangles of a boolean are whole operand triangles, and each test evaluates S three times.
  int free = -1;
  unsigned poles = 0;
  bool looked = false;
  for (int k = 0; k < 3; ++k) {
    const Point3& p = out.positions[out.triangles[t][static_cast<std::size_t>(k)]];
    Vec2& r = res[static_cast<std::size_t>(k)];
    const int at = p == a ? 0 : p == b ? 1 : p == c ? 2 : -1;
    if (at >= 0) {
      r = uv[static_cast<std::size_t>(at)];
      continue;
    }
    // Barycentric coordinates of p's projection into the source triangle's plane.
    const Vec3 w = (p - a) / unit;
    const double w1 = w.dot(e1), w2 = w.dot(e2);
    double l1 = det > 0 ? (d22 * w1 - d12 * w2) / det : 0, l2 = det > 0 ? (d11 * w2 - d12 * w1) / det : 0;
    r = uv[0] + l1 * (uv[1] - uv[0]) + l2 * (uv[2] - uv[0]);
    if (S && !looked) poles = pole_corners(*S, uv, free), looked = true;
    if (poles != 0u && poles != 7u) {
      // The free parameter as the mean of the corners off the pole, weighted by their barycentric
      // coordinates; a corner at the pole (those weights about zero) keeps the linear value.
      const double bc[3] = {std::max(1 - l1 - l2, 0.0), std::max(l1, 0.0), std::max(l2, 0.0)};
      double num = 0, den = 0;
      for (int j = 0; j < 3; ++j)
        if (!(poles >> j & 1u)) num += bc[j] * uv[static_cast<std::size_t>(j)][free], den += bc[j];
      if (den > 1e-12) r[free] = num / den;
    }
    if (S) r = closest_parameters(*S, p, r);
  }
  return res;
}

Mesh shaded_mesh(const Mesh& mesh, const std::vector<FaceSurface>& surfaces, const CornerUvs& corner_uv) {
  Mesh out;
  out.positions.reserve(mesh.positions.size());
  out.triangles.reserve(mesh.triangles.size());
  // (vertex, face) -> the vertices made for it, each with its parameters (several on a seam or at
  // a pole, where one point has several (u, v)).
  std::map<std::pair<std::uint32_t, std::int32_t>, std::vector<std::uint32_t>> made;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const std::int32_t f = mesh.face_ids.empty() ? -1 : mesh.face_ids[t];
    const FaceSurface* fs =
        f >= 0 && static_cast<std::size_t>(f) < surfaces.size() ? &surfaces[static_cast<std::size_t>(f)] : nullptr;
    const FaceSurface* ps = fs && fs->parametric ? fs : nullptr;
    double su = 1, sv = 1;  // the parameter ranges, for comparing (u, v)
    if (ps) {
      auto [u0, u1] = ps->surface->u_domain();
      auto [v0, v1] = ps->surface->v_domain();
      su = u1 - u0;
      sv = v1 - v0;
    }
    std::array<std::uint32_t, 3> v;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = mesh.triangles[t][static_cast<std::size_t>(k)];
      const Point3& p = mesh.positions[i];
      Vec3 n = Vec3::Zero();
      Vec2 uv = Vec2::Zero();
      if (ps) {
        const Vec2 guess = t < corner_uv.size() ? corner_uv[t][static_cast<std::size_t>(k)] : Vec2(NAN, NAN);
        uv = closest_parameters(*ps->surface, p, guess);
        n = surface_normal(*ps->surface, uv);
        if (ps->reversed) n = -n;
      } else if (const Plane* pl = fs ? fs->plane() : nullptr) {
        n = pl->unit_normal();
        const Vec3 &x = pl->x_axis(), &y = pl->y_axis();
        uv = Vec2((p - pl->origin()).dot(x), (p - pl->origin()).dot(y));
      } else if (const Cylinder* cy = fs ? fs->cylinder() : nullptr) {
        const Vec3 d = p - cy->origin(), x = perpendicular(cy->axis()), y = cy->axis().cross(x);
        const double h = d.dot(cy->axis());
        n = unit_vector(d - h * cy->axis());
        if (fs->reversed) n = -n;
        uv = Vec2(std::atan2(d.dot(y), d.dot(x)), h);
      } else {
        n = mesh.triangle_normal(t);
      }
      auto& list = made[{i, f}];
      std::uint32_t found = UINT32_MAX;
      for (std::uint32_t j : list) {
        const Vec2& o = out.uvs[j];
        if (std::abs(o.x() - uv.x()) <= 1e-9 * su && std::abs(o.y() - uv.y()) <= 1e-9 * sv && out.normals[j].dot(n) > 1 - 1e-12) {
          found = j;
          break;
        }
      }
      if (found == UINT32_MAX) {
        found = static_cast<std::uint32_t>(out.positions.size());
        out.positions.push_back(p);
        out.normals.push_back(n);
        out.uvs.push_back(uv);
        list.push_back(found);
      }
      v[static_cast<std::size_t>(k)] = found;
    }
    out.add_triangle(v[0], v[1], v[2], f);
  }
  return out;
}

}  // namespace wedge
