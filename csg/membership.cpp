#include "csg/membership.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "kernel/error.h"
#include "kernel/predicates.h"
#include "kernel/scaled.h"

namespace wedge {

const char* membership_name(Membership m) {
  switch (m) {
    case Membership::Inside: return "inside";
    case Membership::Boundary: return "boundary";
    case Membership::Outside: break;
  }
  return "outside";
}

namespace {

using TriList = std::vector<std::uint32_t>;

struct Tri {
  const Point3 *a, *b, *c;
};

Tri tri(const Mesh& m, std::uint32_t t) {
  const auto& f = m.triangles[t];
  return {&m.positions[f[0]], &m.positions[f[1]], &m.positions[f[2]]};
}

}  // namespace

std::optional<int> segment_crossing(const Point3& p, const Point3& q, const Point3& a, const Point3& b, const Point3& c) {
  const int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
  if (sp != 0 && sp == sq) return 0;
  if (sp == 0 || sq == 0) {
    if (segment_triangle_intersect(p, q, a, b, c)) return std::nullopt;
    return 0;
  }
  int o1 = orient3d(p, q, a, b), o2 = orient3d(p, q, b, c), o3 = orient3d(p, q, c, a);
  bool pos = o1 > 0 || o2 > 0 || o3 > 0, neg = o1 < 0 || o2 < 0 || o3 < 0;
  if (pos && neg) return 0;
  if (o1 == 0 || o2 == 0 || o3 == 0) return std::nullopt;
  return sp < 0 ? 1 : -1;
}

namespace {

// The crossings of segment s-t with one triangle: 1 for a proper crossing through its interior,
// 0 for none, nullopt when the segment touches an edge, a vertex or lies in its plane where it
// meets it (the count would be ambiguous).
std::optional<int> crossing(const Point3& s, const Point3& t, const Tri& x) {
  const std::optional<int> c = segment_crossing(s, t, *x.a, *x.b, *x.c);
  if (!c) return std::nullopt;
  return *c != 0 ? 1 : 0;
}

// The parity of the crossings of s-t with the listed triangles (all triangles if list is null),
// or nullopt if some crossing is ambiguous.
std::optional<int> parity(const Mesh& m, const Point3& s, const Point3& t, const TriList* list) {
  int count = 0;
  Box3 seg;
  seg.extend(s);
  seg.extend(t);
  auto one = [&](std::uint32_t i) -> bool {
    Tri x = tri(m, i);
    Box3 tb;
    tb.extend(*x.a);
    tb.extend(*x.b);
    tb.extend(*x.c);
    if (!tb.intersects(seg)) return true;
    auto c = crossing(s, t, x);
    if (!c) return false;
    count += *c;
    return true;
  };
  if (list) {
    for (std::uint32_t i : *list)
      if (!one(i)) return std::nullopt;
  } else {
    for (std::uint32_t i = 0; i < m.triangles.size(); ++i)
      if (!one(i)) return std::nullopt;
  }
  return count & 1;
}

// Distance from p to triangle abc (Ericson, "Real-Time Collision Detection", 5.1.5).
double point_triangle_distance(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
  Vec3 ab = b - a, ac = c - a, ap = p - a;
  double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  Vec3 bp = p - b;
  double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  Vec3 cp = p - c;
  double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  double den = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * den) + ac * (vc * den))).norm();
}

// Separating-axis test of a box and a triangle (Akenine-Möller 2001), in doubles with a relative
// slack so that rounding can only turn a near miss into a touch, never the other way.
bool box_touches_triangle(const Box3& box, const Tri& x) {
  Vec3 c = box.center(), h = 0.5 * box.size();
  Vec3 v[3] = {*x.a - c, *x.b - c, *x.c - c};
  double scale = h.maxCoeff() + std::max({v[0].cwiseAbs().maxCoeff(), v[1].cwiseAbs().maxCoeff(), v[2].cwiseAbs().maxCoeff()});
  const double slack = 1e-12 * scale;
  auto separated = [&](const Vec3& axis) {
    double p0 = axis.dot(v[0]), p1 = axis.dot(v[1]), p2 = axis.dot(v[2]);
    double r = h.x() * std::abs(axis.x()) + h.y() * std::abs(axis.y()) + h.z() * std::abs(axis.z());
    double s = slack * axis.cwiseAbs().sum();
    return std::min({p0, p1, p2}) > r + s || std::max({p0, p1, p2}) < -r - s;
  };
  for (int i = 0; i < 3; ++i) {
    if (std::min({v[0][i], v[1][i], v[2][i]}) > h[i] + slack) return false;
    if (std::max({v[0][i], v[1][i], v[2][i]}) < -h[i] - slack) return false;
  }
  Vec3 e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  if (separated(e[0].cross(e[1]))) return false;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      Vec3 axis = Vec3::Unit(i).cross(e[k]);
      if (axis.squaredNorm() > 0 && separated(axis)) return false;
    }
  return true;
}

// Ray directions tried in turn (irrational-looking, so an edge or vertex is rarely hit twice).
const std::array<Vec3, 8> kDirections = {Vec3(0.8630173, 0.3841259, 0.3280961), Vec3(-0.2894213, 0.9012347, 0.3227311),
                                         Vec3(0.1937441, -0.4125523, 0.8901231), Vec3(-0.7713019, -0.5312741, 0.3505117),
                                         Vec3(0.4221877, 0.6618903, -0.6194321), Vec3(-0.3311937, 0.2479113, -0.9104447),
                                         Vec3(0.6972117, -0.7012391, -0.1491077), Vec3(-0.9123311, 0.1318879, -0.3877701)};

Membership classify_by_ray(const Mesh& m, const Point3& p, const Box3& bounds) {
  double reach = 2 * (bounds.diagonal() + (p - bounds.center()).norm()) + 1;
  for (int attempt = 0; attempt < 64; ++attempt) {
    Vec3 d = kDirections[attempt % kDirections.size()];
    if (attempt >= int(kDirections.size())) {
      // Further directions: a fixed scramble of the first ones.
      d = (d + 0.37 * kDirections[(attempt * 5 + 3) % kDirections.size()] * (1 + attempt * 0.01)).normalized();
    }
    Point3 q = p + reach * d;
    if (auto par = parity(m, p, q, nullptr)) return *par ? Membership::Inside : Membership::Outside;
  }
  fail("contains: every ray from (", p.x(), ", ", p.y(), ", ", p.z(), ") passed through an edge or a vertex of the mesh");
}

struct Decomposer {
  const Mesh& mesh;
  double size, margin;
  std::size_t max_cells;
  Box3 bounds;
  CellDecomposition out;

  void leaf(const Box3& b, Membership s) {
    if (out.cells.size() >= max_cells)
      fail("cells: more than ", max_cells, " cells at size ", size, " (choose a larger size)");
    out.cells.push_back({b, s});
    double v = b.size().prod();
    if (s == Membership::Inside) {
      ++out.inside;
      out.volume_min += v;
      out.volume_max += v;
    } else if (s == Membership::Boundary) {
      ++out.boundary;
      out.volume_max += v;
    } else {
      ++out.outside;
    }
  }

  // The state of point c, from the reference point r (state rs, not boundary) by the crossings
  // of r-c with `list`, which holds every triangle the segment can meet; a full ray otherwise.
  Membership state(const Point3& c, const Point3* r, Membership rs, const TriList& list) {
    if (r && rs != Membership::Boundary) {
      if (auto par = parity(mesh, *r, c, &list)) {
        if (*par == 0) return rs;
        return rs == Membership::Inside ? Membership::Outside : Membership::Inside;
      }
    }
    return classify_point(mesh, c, 0);
  }

  void split(const Box3& b, const TriList& parent, const Point3* r, Membership rs) {
    TriList mine;
    Box3 wide = b.inflated(margin);
    for (std::uint32_t t : parent)
      if (box_touches_triangle(wide, tri(mesh, t))) mine.push_back(t);
    Point3 c = b.center();
    if (mine.empty()) {
      leaf(b, state(c, r, rs, parent));
      return;
    }
    Vec3 sz = b.size();
    // A side too short for its centre to differ from its ends in doubles cannot be halved.
    const bool halvable = (c.array() > b.min.array() && c.array() < b.max.array()).all();
    if (sz.maxCoeff() <= size || !halvable) {
      leaf(b, Membership::Boundary);
      return;
    }
    // Every point of b within the margin of one triangle: each box below touches that triangle
    // through its margin, so every leaf is boundary, and they are made without the tests (a part
    // far smaller than the margin, sphere(1e-3) at tolerance 0.01 in cells of 2e-4: 1.3 million
    // leaves, each testing all 576 triangles, ran past a minute).
    const double reach = 0.5 * sz.norm();
    for (std::uint32_t t : mine) {
      const Tri x = tri(mesh, t);
      if (point_triangle_distance(c, *x.a, *x.b, *x.c) + reach <= 0.999 * margin) {
        boundary(b);
        return;
      }
    }
    Membership cs = state(c, r, rs, parent);
    halve(b, [&](const Box3& child) { split(child, mine, &c, cs); });
  }

  // f(child) for the halves of b along its sides longer than `size` (a flat part is not split
  // along its thin side).
  template <class F>
  void halve(const Box3& b, F&& f) {
    const Vec3 sz = b.size(), c = b.center();
    int nx = sz.x() > size ? 2 : 1, ny = sz.y() > size ? 2 : 1, nz = sz.z() > size ? 2 : 1;
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j)
        for (int k = 0; k < nz; ++k) {
          Vec3 lo(nx == 1 ? b.min.x() : (i ? c.x() : b.min.x()), ny == 1 ? b.min.y() : (j ? c.y() : b.min.y()),
                  nz == 1 ? b.min.z() : (k ? c.z() : b.min.z()));
          Vec3 hi(nx == 1 ? b.max.x() : (i ? b.max.x() : c.x()), ny == 1 ? b.max.y() : (j ? b.max.y() : c.y()),
                  nz == 1 ? b.max.z() : (k ? b.max.z() : c.z()));
          f(Box3(lo, hi));
        }
  }

  // The leaves split() makes of a box every point of which is within the margin of the surface.
  void boundary(const Box3& b) {
    const Vec3 c = b.center();
    const bool halvable = (c.array() > b.min.array() && c.array() < b.max.array()).all();
    if (b.size().maxCoeff() <= size || !halvable) {
      leaf(b, Membership::Boundary);
      return;
    }
    halve(b, [&](const Box3& child) { boundary(child); });
  }
};

}  // namespace

Membership classify_point(const Mesh& mesh, const Point3& p, double boundary_distance) {
  if (!p.allFinite()) fail("contains: the point (", p.x(), ", ", p.y(), ", ", p.z(), ") is not finite");
  if (mesh.triangles.empty()) return Membership::Outside;
  Box3 bounds = mesh.bounds();
  if (!bounds.contains(p, boundary_distance)) return Membership::Outside;
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    Tri x = tri(mesh, t);
    Box3 tb;
    tb.extend(*x.a);
    tb.extend(*x.b);
    tb.extend(*x.c);
    if (!tb.contains(p, boundary_distance)) continue;
    if (segment_triangle_intersect(p, p, *x.a, *x.b, *x.c)) return Membership::Boundary;
    if (boundary_distance > 0 && point_triangle_distance(p, *x.a, *x.b, *x.c) <= boundary_distance) return Membership::Boundary;
  }
  return classify_by_ray(mesh, p, bounds);
}

CellDecomposition decompose_cells(const Mesh& mesh, double size, double margin, std::size_t max_cells) {
  if (!(size > 0) || !std::isfinite(size)) fail("cells: size must be a positive number, got ", size);
  if (!(margin >= 0)) fail("cells: margin must be >= 0, got ", margin);
  Decomposer d{mesh, size, margin, max_cells, mesh.bounds(), {}};
  if (mesh.triangles.empty()) return d.out;
  // The root is the bounds widened a little, so that no boundary lies on the root's faces; by a
  // part of the cell size, or of the bounds when the size is larger (a size of 1e300 made the one
  // root cell 1e297 wide, and volume_max infinite).
  double pad = std::max(margin, 1e-9 * d.bounds.diagonal()) + 1e-3 * std::min(size, d.bounds.diagonal());
  // A relative floor on the margin keeps the double-precision touch test conservative.
  d.margin = std::max(margin, 1e-9 * d.bounds.diagonal());
  // Every leaf has its sides within (size/2, size] and the surface meets at least area / (sqrt 2
  // size^2) of them (a plane cuts at most sqrt 2 size^2 from a cube; a surface folded within one
  // cell meets fewer, hence the further factor 2): refused before the work when that is too many.
  double area = 0;
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    Tri x = tri(mesh, t);
    area += 0.5 * scaled_norm((*x.b - *x.a).cross(*x.c - *x.a));
  }
  const double estimate = area / size / size / (2 * std::sqrt(2.0));
  if (!std::isfinite(estimate))
    fail("cells: size ", size, " would need more than 1e308 cells on the surface (its area ", area, " / size^2), more than ",
         max_cells, " (choose a larger size)");
  if (!(estimate <= double(max_cells)))
    fail("cells: size ", size, " would need about ", estimate, " cells on the surface (its area ", area,
         " / size^2), more than ", max_cells, " (choose a larger size)");
  TriList all(mesh.triangles.size());
  for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
  d.split(d.bounds.inflated(pad), all, nullptr, Membership::Outside);
  return std::move(d.out);
}

}  // namespace wedge
