// Faces certified embedded by their projection (embedded_groups, boolean_impl.h): the broad
// phase's self-check then leaves out the pairs of each such face's triangles.
#include <algorithm>
#include <cmath>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

namespace {

// Whether the triangles `g` (of one operand) are embedded, certified by their projection along
// the dominant axis of the first one's normal (exact): (a) every triangle turns the same way as
// the first there; (b) the edges whose reverse is not among them (the group's boundary; no
// directed edge twice) meet only where consecutive ones share an end, each end having one edge in
// and one out: disjoint simple closed curves; (c) at most one of those curves turns the triangles'
// way. Then no point of the projection is covered twice: the number of triangles over a point is
// the winding number of the boundary around it (the triangles all positive), which (b) and (c)
// keep at most 1; two triangles that met beyond what they share would overlap in area, or put a
// boundary point on another boundary segment. And triangles whose projections meet only in what
// they share meet only there in space.
bool embedded_by_projection(const Soup& soup, const std::vector<u32>& g) {
  const int k = soup.axis[g[0]];
  if (k < 0) return false;
  const int want = soup.axis_sign[g[0]];
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  auto p2 = [&](u32 v) { return Point2(soup.verts[v][i], soup.verts[v][j]); };
  for (u32 t : g) {
    const auto& T = soup.tris[t];
    if (orient2d(p2(T[0]), p2(T[1]), p2(T[2])) != want) return false;
  }
  auto key = [](u32 a, u32 b) { return static_cast<std::uint64_t>(a) << 32 | b; };
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * g.size());
  for (u32 t : g)
    for (int c = 0; c < 3; ++c) edges.push_back(key(soup.tris[t][c], soup.tris[t][(c + 1) % 3]));
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
  // The boundary: a -> b with no b -> a; per end, one edge out (sorted by a) and one in.
  std::vector<std::array<u32, 2>> bound;
  for (std::uint64_t e : edges) {
    const u32 a = static_cast<u32>(e >> 32), b = static_cast<u32>(e);
    if (!std::binary_search(edges.begin(), edges.end(), key(b, a))) bound.push_back({a, b});
  }
  if (bound.empty()) return false;  // (a closed group: not the faces this is for)
  std::vector<std::array<u32, 2>> in(bound.size());
  for (std::size_t e = 0; e < bound.size(); ++e) in[e] = {bound[e][1], bound[e][0]};
  std::sort(in.begin(), in.end());
  for (std::size_t e = 0; e < bound.size(); ++e) {
    if (in[e][0] != bound[e][0]) return false;                                    // in- and out-degree 1 at every end
    if (e > 0 && bound[e][0] == bound[e - 1][0]) return false;
  }
  // (b): the segments swept by least x; a pair sharing an end must not overlap along a line.
  struct Seg {
    Point2 p, q;
    double xlo, xhi, ylo, yhi;
    u32 a, b;
  };
  std::vector<Seg> seg(bound.size());
  for (std::size_t e = 0; e < bound.size(); ++e) {
    const Point2 p = p2(bound[e][0]), q = p2(bound[e][1]);
    seg[e] = {p, q, std::min(p.x(), q.x()), std::max(p.x(), q.x()), std::min(p.y(), q.y()), std::max(p.y(), q.y()), bound[e][0], bound[e][1]};
    if (!std::isfinite(seg[e].xlo + seg[e].xhi + seg[e].ylo + seg[e].yhi)) return false;
  }
  std::sort(seg.begin(), seg.end(), [](const Seg& x, const Seg& y) { return x.xlo < y.xlo || (x.xlo == y.xlo && x.a < y.a); });
  auto sign = [](double x) { return (x > 0) - (x < 0); };
  for (std::size_t x = 0; x < seg.size(); ++x)
    for (std::size_t y = x + 1; y < seg.size() && seg[y].xlo <= seg[x].xhi; ++y) {
      const Seg &s1 = seg[x], &s2 = seg[y];
      if (s2.ylo > s1.yhi || s1.ylo > s2.yhi) continue;
      u32 v = kNone;
      Point2 o1, o2;  // the other ends, where they share v
      if (s1.b == s2.a) v = s1.b, o1 = s1.p, o2 = s2.q;
      else if (s2.b == s1.a) v = s2.b, o1 = s1.q, o2 = s2.p;
      if (v == kNone) {
        if (segments_intersect_2d(s1.p, s1.q, s2.p, s2.q)) return false;
        continue;
      }
      const Point2 c = p2(v);
      if (orient2d(c, o1, o2) == 0 && sign(o1.x() - c.x()) == sign(o2.x() - c.x()) && sign(o1.y() - c.y()) == sign(o2.y() - c.y()))
        return false;
    }
  // (c): each curve's turn at its least point (by x, then y).
  std::vector<char> seen(bound.size(), 0);
  auto next_of = [&](u32 b) {  // the boundary edge out of b
    const auto it = std::lower_bound(bound.begin(), bound.end(), std::array<u32, 2>{b, 0});
    return static_cast<std::size_t>(it - bound.begin());
  };
  int turning = 0;
  for (std::size_t e0 = 0; e0 < bound.size(); ++e0) {
    if (seen[e0]) continue;
    std::size_t least = e0;
    for (std::size_t e = e0; !seen[e]; e = next_of(bound[e][1])) {
      seen[e] = 1;
      const Point2 a = p2(bound[e][1]), l = p2(bound[least][1]);
      if (a.x() < l.x() || (a.x() == l.x() && a.y() < l.y())) least = e;
    }
    const std::size_t after = next_of(bound[least][1]);
    const int o = orient2d(p2(bound[least][0]), p2(bound[least][1]), p2(bound[after][1]));
    if (o == 0) return false;
    turning += o == want;
  }
  return turning <= 1;
}

}  // namespace

std::vector<u32> embedded_groups(const Soup& soup, const std::vector<char>* trusted, std::size_t least) {
  std::vector<u32> group;
  const std::vector<u32> first = operand_starts(soup);
  std::vector<std::vector<u32>> groups;  // the candidates' triangles
  for (int o = 0; o < soup.operands; ++o) {
    if (trusted && (*trusted)[o]) continue;
    const u32 t0 = first[o], t1 = first[o + 1];
    std::int32_t top = -1;
    for (u32 t = t0; t < t1; ++t) top = std::max(top, soup.face_id[t]);
    if (top < 0 || static_cast<std::size_t>(top) > 4 * static_cast<std::size_t>(t1 - t0) + 1024) continue;
    std::vector<u32> count(static_cast<std::size_t>(top) + 1, 0);
    for (u32 t = t0; t < t1; ++t)
      if (soup.face_id[t] >= 0) ++count[static_cast<std::size_t>(soup.face_id[t])];
    std::vector<u32> slot(count.size(), kNone);
    for (std::size_t f = 0; f < count.size(); ++f)
      if (count[f] >= least) {
        slot[f] = static_cast<u32>(groups.size());
        groups.emplace_back();
        groups.back().reserve(count[f]);
      }
    for (u32 t = t0; t < t1; ++t)
      if (soup.face_id[t] >= 0 && slot[static_cast<std::size_t>(soup.face_id[t])] != kNone)
        groups[slot[static_cast<std::size_t>(soup.face_id[t])]].push_back(t);
  }
  if (groups.empty()) return group;
  std::vector<char> ok(groups.size(), 0);
  parallel_for(0, groups.size(), [&](std::size_t k) { ok[k] = embedded_by_projection(soup, groups[k]); });
  for (std::size_t k = 0; k < groups.size(); ++k)
    if (ok[k]) {
      if (group.empty()) group.assign(soup.tris.size(), kNone);
      for (u32 t : groups[k]) group[t] = static_cast<u32>(k);
    }
  return group;
}

}  // namespace wedge::boolean_detail
