#include "csg/curved_mass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "kernel/parallel.h"
#include "surfaces/surfaces.h"

namespace wedge {

namespace {

// Integrals about a reference point: volume, area, first and second moments.
struct Sums {
  double volume = 0, area = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  void add(const Sums& o) {
    volume += o.volume;
    area += o.area;
    first += o.first;
    second += o.second;
  }
};

// Dunavant's 6-point rule, degree 4, on the triangle b0 + b1 + b2 = 1 (weights sum to 1).
struct TriPoint {
  double b1, b2, w;
};
constexpr double kA1 = 0.445948490915965, kB1 = 0.108103018168070, kW1 = 0.223381589678011;
constexpr double kA2 = 0.091576213509771, kB2 = 0.816847572980459, kW2 = 0.109951743655322;
constexpr std::array<TriPoint, 6> kTri{{{kA1, kA1, kW1}, {kA1, kB1, kW1}, {kB1, kA1, kW1},
                                        {kA2, kA2, kW2}, {kA2, kB2, kW2}, {kB2, kA2, kW2}}};
// Gauss-Legendre, 3 points on [0, 1].
constexpr std::array<double, 3> kL{0.1127016653792583, 0.5, 0.8872983346207417};
constexpr std::array<double, 3> kLw{5.0 / 18, 8.0 / 18, 5.0 / 18};

// The surface point over q and its derivatives along the triangle's two sides a1, a2.
struct OnSurface {
  Vec3 s, s1, s2;
};

// The closest point of a cylinder (the planar builders' faces) and its derivative along a.
OnSurface on_cylinder(const Cylinder& c, const Point3& q, const Vec3& a1, const Vec3& a2) {
  const Vec3 ax = c.axis();
  const Vec3 d = q - c.origin();
  const Vec3 perp = d - d.dot(ax) * ax;
  const double rho = perp.norm();
  const Vec3 e = perp / rho;
  auto along = [&](const Vec3& a) {
    const Vec3 ap = a - a.dot(ax) * ax;
    return Vec3(a.dot(ax) * ax + c.radius() / rho * (ap - e.dot(ap) * e));
  };
  return {c.origin() + d.dot(ax) * ax + c.radius() * e, along(a1), along(a2)};
}

// The cap of triangle t into `out`; false (nothing added) when its surface points are not near it.
bool cap(const Mesh& mesh, std::size_t t, const FaceSurface& fs, const CornerUvs& corner_uv, double far, const Point3& ref,
         Sums& out) {
  const auto& T = mesh.triangles[t];
  const Point3 &q0 = mesh.positions[T[0]], &q1 = mesh.positions[T[1]], &q2 = mesh.positions[T[2]];
  const Vec3 a1 = q1 - q0, a2 = q2 - q0;
  const Cylinder* cyl = fs.cylinder();
  const std::array<Vec2, 3>* uv = nullptr;
  if (!cyl) {
    if (!fs.parametric || !fs.surface || corner_uv.size() <= t) return false;
    uv = &corner_uv[t];
    for (const Vec2& p : *uv)
      if (!p.allFinite()) return false;
  }
  const Vec3 normal = a1.cross(a2).normalized();
  const double side = std::max({a1.norm(), a2.norm(), (q2 - q1).norm()});
  // A corner on a pole (a cone's apex, a sphere's pole: Su or Sv zero there) stands for the whole
  // collapsed row, as in the tessellator: at barycentric b its free parameter is the other
  // corners' mean weighted by b, so the edge from it to a corner follows that corner's generator
  // line, the same line for both triangles on the edge (a fixed parameter per triangle made
  // neighbours' walls differ: a first-order error along a cone's apex fan).
  // Two corners on the pole (a piece between the poles of two operands 1e-13 apart and a corner
  // below them) leave the third's generator line: the patch is that line, not a lune.
  int free = -1;
  const unsigned poles = uv ? pole_corners(*fs.surface, *uv, free) : 0u;
  if (poles == 7u) return true;  // all three on the pole: no patch
  int pole = -1;
  for (int k = 0; k < 3 && pole < 0; ++k)
    if (poles >> k & 1u) pole = k;
  // The rule: Dunavant's; on a triangle with a pole corner, whose parameters are a ratio that is
  // not smooth at the pole (a polynomial rule on it left a first-order error along a cone's apex
  // fan), 3 x 3 Gauss points in the collapsed square: t from the pole to the opposite side, s
  // along it, b = (1 - t at the pole, t s, t (1 - s)), area element t.
  std::vector<TriPoint> rule(kTri.begin(), kTri.end());
  if (pole >= 0) {
    rule.clear();
    const int j = (pole + 1) % 3, l = (pole + 2) % 3;
    for (std::size_t a = 0; a < kL.size(); ++a)
      for (std::size_t c = 0; c < kL.size(); ++c) {
        const double t = kL[a], sv = kL[c];
        double b[3];
        b[pole] = 1 - t, b[j] = t * sv, b[l] = t * (1 - sv);
        rule.push_back({b[1], b[2], 2 * kLw[a] * kLw[c] * t});  // weights of kTri's kind: sum 1
      }
  }
  Sums local;
  for (const TriPoint& tp : rule) {
    const Point3 q = q0 + tp.b1 * a1 + tp.b2 * a2;
    OnSurface os;
    if (cyl) {
      os = on_cylinder(*cyl, q, a1, a2);
    } else {
      Vec2 d1 = (*uv)[1] - (*uv)[0], d2 = (*uv)[2] - (*uv)[0];
      Vec2 p = (*uv)[0] + tp.b1 * d1 + tp.b2 * d2;
      if (pole >= 0) {
        // p[free] = N / D, N = sum over the other corners of b_j x_j, D = sum of their b_j.
        const double b[3] = {1 - tp.b1 - tp.b2, tp.b1, tp.b2};
        const double db1[3] = {-1, 1, 0}, db2[3] = {-1, 0, 1};
        double N = 0, D = 0, N1 = 0, D1 = 0, N2 = 0, D2 = 0;
        for (int j = 0; j < 3; ++j) {
          if (poles >> j & 1u) continue;
          const double x = (*uv)[static_cast<std::size_t>(j)][free];
          N += b[j] * x, D += b[j];
          N1 += db1[j] * x, D1 += db1[j];
          N2 += db2[j] * x, D2 += db2[j];
        }
        p[free] = N / D;
        d1[free] = (N1 * D - N * D1) / (D * D);
        d2[free] = (N2 * D - N * D2) / (D * D);
      }
      Vec3 J[3];
      fs.surface->jet(p.x(), p.y(), 1, J);
      os = {J[0], d1.x() * J[1] + d1.y() * J[2], d2.x() * J[1] + d2.y() * J[2]};
    }
    const Vec3 w = os.s - q;
    // Off the triangle's plane by about the tolerance; along it the surface point may lie a
    // fraction of a side away (interpolated parameters on a ruled face: a cone's long triangles
    // reach from one parameter to another and its generator lines twist), but not a turn away
    // (parameters across a seam).
    if (!(std::abs(w.dot(normal)) <= far && w.norm() <= far + side)) return false;
    const Vec3 c1 = os.s1 - a1, c2 = os.s2 - a2;
    const double wt = tp.w / 2;  // the reference triangle's area is 1/2
    for (std::size_t j = 0; j < kL.size(); ++j) {
      const double l = kL[j];
      const double jac = (a1 + l * c1).cross(a2 + l * c2).dot(w);
      const Vec3 x = q + l * w - ref;
      const double dv = wt * kLw[j] * jac;
      local.volume += dv;
      local.first += dv * x;
      local.second += dv * x * x.transpose();
    }
    // The surface's area element in place of the flat triangle's.
    local.area += wt * os.s1.cross(os.s2).norm();
  }
  local.area -= 0.5 * a1.cross(a2).norm();
  out.add(local);
  return true;
}

}  // namespace

MassProperties curved_mass_properties(const Mesh& mesh, const std::vector<FaceSurface>& surfaces, const CornerUvs& corner_uv,
                                      double chordal) {
  MassProperties mp;
  if (mesh.triangles.empty()) return mp;
  const Point3 ref = mesh.bounds().center();
  const double far = 16 * chordal + 1e-12 * mesh.bounds().diagonal();
  // Blocks summed in order: the same bits at any number of threads.
  const std::size_t n = mesh.triangles.size(), block = 4096, blocks = (n + block - 1) / block;
  std::vector<Sums> part(blocks);
  parallel_for(0, blocks, [&](std::size_t b) {
    Sums& s = part[b];
    for (std::size_t t = b * block; t < std::min(n, (b + 1) * block); ++t) {
      const auto& T = mesh.triangles[t];
      const Vec3 a = mesh.positions[T[0]] - ref, p = mesh.positions[T[1]] - ref, c = mesh.positions[T[2]] - ref;
      // The flat tetrahedron (ref, a, p, c) (as kernel/mesh.cpp's mass_properties).
      const double v = a.dot(p.cross(c)) / 6.0;
      const Vec3 sum = a + p + c;
      s.volume += v;
      s.area += 0.5 * (p - a).cross(c - a).norm();
      s.first += v * sum / 4.0;
      s.second += v / 20.0 * (a * a.transpose() + p * p.transpose() + c * c.transpose() + sum * sum.transpose());
      const std::int32_t id = t < mesh.face_ids.size() ? mesh.face_ids[t] : -1;
      if (id < 0 || static_cast<std::size_t>(id) >= surfaces.size()) continue;
      const FaceSurface& fs = surfaces[static_cast<std::size_t>(id)];
      if (fs.plane() || !fs.surface) continue;
      cap(mesh, t, fs, corner_uv, far, ref, s);
    }
  });
  Sums total;
  for (const Sums& s : part) total.add(s);
  mp.volume = total.volume;
  mp.area = total.area;
  if (total.volume == 0) return mp;
  const Vec3 cl = total.first / total.volume;
  mp.centroid = ref + cl;
  const Mat3 cov = total.second - total.volume * cl * cl.transpose();
  mp.inertia = cov.trace() * Mat3::Identity() - cov;
  return mp;
}

}  // namespace wedge
