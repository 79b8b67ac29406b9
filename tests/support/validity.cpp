// closed_manifold_outward: combinatorial checks on vertex indices, no geometry but the volume.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>

#include "kernel/predicates.h"
#include "tests/support/boolean_cases.h"
#include "tests/support/cgal_oracle.h"

namespace wedge::testing {

namespace {
std::string where(const Mesh& m, std::uint32_t u, std::uint32_t v) {
  std::ostringstream s;
  s.precision(17);
  const auto& p = m.positions[u];
  const auto& q = m.positions[v];
  s << "edge " << u << "-" << v << " (" << p.x() << ", " << p.y() << ", " << p.z() << ")-(" << q.x() << ", " << q.y()
    << ", " << q.z() << ")";
  return s.str();
}
}  // namespace

std::string closed_manifold_outward(const Mesh& m) {
  const std::size_t nv = m.positions.size(), nt = m.triangles.size();
  for (std::size_t i = 0; i < nv; ++i)
    if (!m.positions[i].allFinite()) return "vertex " + std::to_string(i) + " is not finite";
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = m.triangles[t];
    if (tri[0] >= nv || tri[1] >= nv || tri[2] >= nv) return "triangle " + std::to_string(t) + ": index out of range";
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0])
      return "triangle " + std::to_string(t) + ": repeated vertex index";
  }
  // Directed edges sorted by undirected key: each undirected edge must hold u->v and v->u once.
  struct Half {
    std::uint32_t lo, hi;
    bool forward;  // u < v
  };
  std::vector<Half> half;
  half.reserve(3 * nt);
  for (const auto& tri : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = tri[k], v = tri[(k + 1) % 3];
      half.push_back({std::min(u, v), std::max(u, v), u < v});
    }
  std::sort(half.begin(), half.end(), [](const Half& a, const Half& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.hi != b.hi ? a.hi < b.hi : a.forward < b.forward;
  });
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) ++j;
    const std::size_t n = j - i;
    if (n == 1) return "border " + where(m, half[i].lo, half[i].hi);
    if (n > 2) return "non-manifold " + where(m, half[i].lo, half[i].hi) + " has " + std::to_string(n) + " triangles";
    if (half[i].forward == half[i + 1].forward)
      return "inconsistent orientation at " + where(m, half[i].lo, half[i].hi);
    i = j;
  }
  // Around each vertex the wedges (b, c) of its triangles (v, b, c) must chain into one cycle.
  std::vector<std::uint32_t> start(nv + 1, 0);
  for (const auto& tri : m.triangles)
    for (int k = 0; k < 3; ++k) ++start[tri[k] + 1];
  for (std::size_t i = 0; i < nv; ++i) start[i + 1] += start[i];
  std::vector<std::pair<std::uint32_t, std::uint32_t>> wedge(3 * nt);
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (const auto& tri : m.triangles)
    for (int k = 0; k < 3; ++k) wedge[fill[tri[k]]++] = {tri[(k + 1) % 3], tri[(k + 2) % 3]};
  for (std::size_t v = 0; v < nv; ++v) {
    auto first = wedge.begin() + start[v], last = wedge.begin() + start[v + 1];
    if (first == last) continue;
    std::sort(first, last);
    // Follow b -> c from the first wedge; every wedge must be reached.
    std::size_t steps = 0, n = static_cast<std::size_t>(last - first);
    std::uint32_t b = first->first;
    do {
      auto it = std::lower_bound(first, last, std::make_pair(b, std::uint32_t(0)));
      if (it == last || it->first != b) break;
      b = it->second;
      ++steps;
    } while (b != first->first && steps <= n);
    if (steps != n) {
      std::ostringstream s;
      s.precision(17);
      const auto& p = m.positions[v];
      s << "non-manifold vertex " << v << " (" << p.x() << ", " << p.y() << ", " << p.z()
        << "): its triangles form more than one fan";
      return s.str();
    }
  }
  if (nt > 0) {
    // In units of the mesh's size (a power of two: exact) where that is far from 1: a solid 1e-150
    // wide has a volume below the doubles.
    const int e = m.bounds().empty() ? 0 : -std::ilogb(m.bounds().size().maxCoeff());
    double vol = 0;
    if (std::abs(e) <= 100) {
      vol = polyhedron_volume(m);
    } else {
      Mesh unit = m;
      for (Point3& p : unit.positions) p = Point3(std::ldexp(p.x(), e), std::ldexp(p.y(), e), std::ldexp(p.z(), e));
      vol = polyhedron_volume(unit);
    }
    // The sign exactly (the doubles' sum errs by about an ulp of the coordinates' cube: a sliver
    // 1e-11 x 1e-10 x 1e-7 at a unit box's corner summed to -1e-17 though its volume is 3e-28).
    if (volume_sign(m.positions, m.triangles) <= 0) {
      std::ostringstream s;
      s.precision(17);
      s << "volume " << vol << " is not positive (inward orientation)";
      return s.str();
    }
  }
  return "";
}

std::string folded_touching_edge(const Mesh& m) {
  // Vertices welded by position (w), and whether a position has several.
  const std::size_t nv = m.positions.size();
  std::vector<std::uint32_t> order(nv), w(nv);
  for (std::size_t v = 0; v < nv; ++v) order[v] = static_cast<std::uint32_t>(v);
  auto key = [&](std::uint32_t v) { return std::array<double, 3>{m.positions[v].x(), m.positions[v].y(), m.positions[v].z()}; };
  std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return key(x) < key(y); });
  std::vector<char> several(nv, 0);
  bool any = false;
  for (std::size_t i = 0; i < nv; ++i) {
    w[order[i]] = i > 0 && key(order[i]) == key(order[i - 1]) ? w[order[i - 1]] : order[i];
    if (w[order[i]] != order[i]) several[w[order[i]]] = 1, any = true;
  }
  if (!any) return "";
  // Per welded edge at such a position: its triangles' third corners and directions (lo -> hi).
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<Point3, bool>>> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = w[t[k]], v = w[t[(k + 1) % 3]];
      if (several[u] || several[v]) edges[{std::min(u, v), std::max(u, v)}].push_back({m.positions[t[(k + 2) % 3]], u < v});
    }
  const std::vector<Vec3>& at = m.positions;
  for (auto& [e, sheets] : edges) {
    if (sheets.size() < 3) continue;
    const Point3 &a = at[e.first], &b = at[e.second];
    // Half-turns about a -> b from the first sheet, then the order within each (exact).
    const Point3 c0 = sheets[0].first;
    auto half = [&](const Point3& c) {
      const int o = orient3d(a, b, c0, c);
      if (o != 0) return o > 0 ? 0 : 1;
      // In the first sheet's plane: the same half-plane where c and c0 lie on one side of a b
      // seen along the plane's normal's largest axis.
      const Vec3 n = (b - a).cross(c0 - a);
      int k = 0;
      for (int d = 1; d < 3; ++d)
        if (std::abs(n[d]) > std::abs(n[k])) k = d;
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      auto side = [&](const Point3& q) { return orient2d(Point2(a[i], a[j]), Point2(b[i], b[j]), Point2(q[i], q[j])); };
      return side(c) == side(c0) ? 0 : 1;
    };
    std::sort(sheets.begin(), sheets.end(), [&](const auto& x, const auto& y) {
      const int hx = half(x.first), hy = half(y.first);
      return hx != hy ? hx < hy : orient3d(a, b, x.first, y.first) > 0;
    });
    for (std::size_t x = 0; x < sheets.size(); ++x) {
      const auto &p = sheets[x], &q = sheets[(x + 1) % sheets.size()];
      if (p.second == q.second || (half(p.first) == half(q.first) && orient3d(a, b, p.first, q.first) == 0)) {
        std::ostringstream s;
        s.precision(17);
        s << "shells touching along the edge (" << a.x() << ", " << a.y() << ", " << a.z() << ")-(" << b.x() << ", " << b.y()
          << ", " << b.z() << ") overlap there (its " << sheets.size() << " triangles do not alternate about it)";
        return s.str();
      }
    }
  }
  return "";
}

std::string nested_shells(const Mesh& m) {
  // Shells: the components of the triangles joined through vertex indices (touching shells have
  // copies of their common vertices).
  const std::size_t nv = m.positions.size();
  std::vector<std::uint32_t> up(nv);
  for (std::size_t v = 0; v < nv; ++v) up[v] = static_cast<std::uint32_t>(v);
  auto find = [&](std::uint32_t x) {
    while (up[x] != x) x = up[x] = up[up[x]];
    return x;
  };
  for (const auto& t : m.triangles)
    for (int k = 1; k < 3; ++k) {
      const std::uint32_t a = find(t[0]), b = find(t[k]);
      if (a != b) up[std::max(a, b)] = std::min(a, b);
    }
  std::map<std::uint32_t, std::vector<std::array<std::uint32_t, 3>>> shells;
  for (const auto& t : m.triangles) shells[find(t[0])].push_back(t);
  if (shells.size() < 2) return "";
  // How many shells hold each position.
  std::map<std::array<double, 3>, std::vector<std::uint32_t>> holders;
  for (std::size_t v = 0; v < nv; ++v) {
    auto& h = holders[{m.positions[v].x(), m.positions[v].y(), m.positions[v].z()}];
    if (std::find(h.begin(), h.end(), find(static_cast<std::uint32_t>(v))) == h.end()) h.push_back(find(static_cast<std::uint32_t>(v)));
  }
  // The winding number at w of the shells but `skip`, along the segment w -> far: +1 where it
  // leaves a shell's solid side, -1 where it enters; 1 << 30 where it meets an edge or a vertex.
  auto winding = [&](std::uint32_t skip, const Point3& w, const Point3& far) {
    int n = 0;
    for (const auto& [root, tris] : shells) {
      if (root == skip) continue;
      for (const auto& t : tris) {
        const Point3 &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
        const int sw = orient3d(a, b, c, w), sf = orient3d(a, b, c, far);
        if (sw == sf && sw != 0) continue;
        if (sw == 0 || sf == 0) {
          if (segment_triangle_intersect(w, far, a, b, c)) return 1 << 30;
          continue;
        }
        const int e0 = orient3d(w, far, a, b), e1 = orient3d(w, far, b, c), e2 = orient3d(w, far, c, a);
        if ((e0 > 0 || e1 > 0 || e2 > 0) && (e0 < 0 || e1 < 0 || e2 < 0)) continue;
        if (e0 == 0 || e1 == 0 || e2 == 0) return 1 << 30;
        n += sw < 0 ? 1 : -1;
      }
    }
    return n;
  };
  Box3 all = m.bounds();
  const double size = (all.max - all.min).norm() + 1;
  for (const auto& [root, tris] : shells) {
    // A vertex of this shell's at a position no other shell holds.
    const Point3* w = nullptr;
    for (const auto& t : tris)
      for (std::uint32_t v : t)
        if (!w && holders[{m.positions[v].x(), m.positions[v].y(), m.positions[v].z()}].size() == 1) w = &m.positions[v];
    if (!w) continue;
    int n = 1 << 30;
    for (int d = 0; d < 8 && n == (1 << 30); ++d) {
      const Vec3 dir = Vec3(std::sin(1.3 * d + 0.4), std::cos(2.1 * d + 0.7), std::sin(0.9 * d + 1.9)).normalized();
      const Point3 far = *w + 4 * size * dir;
      if (far.allFinite()) n = winding(root, *w, far);  // (a model near the doubles' range: not judged)
    }
    if (n == (1 << 30)) continue;
    const int want = volume_sign(m.positions, tris) > 0 ? 0 : 1;
    if (n != want) {
      std::ostringstream s;
      s.precision(17);
      s << "shells overlap: the shell through (" << w->x() << ", " << w->y() << ", " << w->z() << ") lies where the others wind "
        << n << " times (" << want << " for a solid's)";
      return s.str();
    }
  }
  return "";
}

std::string result_defect(const Mesh& m) {
  std::string d = closed_manifold_outward(m);
  if (d.empty() && exact_self_intersects(m, &d) && d.empty()) d = "self-intersection";
  if (d.empty()) d = folded_touching_edge(m);
  if (d.empty()) d = nested_shells(m);
  return d;
}

}  // namespace wedge::testing
