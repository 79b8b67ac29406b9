// Exact triangle-triangle intersection.
//
// For triangles T and U the signs of U's vertices against T's plane and of T's against U's
// (orient3d on input doubles, exact) decide whether they can meet. If they are not coplanar, the
// points of T on U's plane form a segment (or a point) on the line L = plane(T) ∩ plane(U), and
// so do the points of U on T's plane; their end points are vertices or LPIs (an edge cut by the
// other plane). T ∩ U is the overlap of the two segments, found by comparing the end points'
// coordinates on an axis along which L is not constant (exact comparisons of implicit points).
// The result is one segment, one point or nothing, cutting T along plane(U) and U along plane(T).
//
// Coplanar triangles are compared in the projection along T's axis k: each edge of U clipped to
// T becomes a constraint of T (cut by the wall over that edge), and each edge of T clipped to U a
// constraint of U. Clipping collects the candidate end points (the edge's own end points inside
// the triangle, proper crossings with the triangle's edges as LPIs of the edge and a wall, the
// triangle's vertices on the edge) and keeps the extreme two along the edge.
#include <algorithm>
#include <cmath>

#include "csg/boolean_impl.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

namespace {

PointDef explicit_point(u32 v) {
  PointDef d;
  d.kind = PointDef::Explicit;
  d.p = v;
  return d;
}

PointDef lpi(u32 p, u32 q, const Plane& P) {
  PointDef d;
  d.kind = PointDef::Lpi;
  d.p = std::min(p, q);
  d.q = std::max(p, q);
  d.P[0] = P;
  return d;
}

bool same_def(const PointDef& a, const PointDef& b) {
  if (a.kind != b.kind || a.p != b.p || a.q != b.q) return false;
  if (a.kind == PointDef::Explicit) return true;
  if (a.kind == PointDef::Lpi) return a.P[0] == b.P[0];
  return a.P[0] == b.P[0] && a.P[1] == b.P[1] && a.P[2] == b.P[2];
}

// The points of triangle `tri` on the plane that `side` measures: its vertices with side 0 and
// its edges whose ends lie strictly on opposite sides, cut by `plane`.
std::vector<PointDef> on_plane(const std::array<u32, 3>& tri, const int side[3], const Plane& plane) {
  std::vector<PointDef> out;
  for (int i = 0; i < 3; ++i) {
    if (side[i] == 0) out.push_back(explicit_point(tri[i]));
    int j = (i + 1) % 3;
    if (side[i] * side[j] < 0) out.push_back(lpi(tri[i], tri[j], plane));
  }
  return out;
}

// Points with their coordinate bounds along one axis (evaluated once, compared many times).
struct Keyed {
  PointDef d;
  double b[2];
};
std::vector<Keyed> keyed(const Points& pts, const std::vector<PointDef>& v, int axis) {
  std::vector<Keyed> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    out[i].d = v[i];
    pts.coord_bounds(v[i], axis, out[i].b[0], out[i].b[1]);
  }
  return out;
}
int cmp(const Points& pts, const Keyed& x, const Keyed& y, int axis) {
  return pts.compare_def(x.d, x.b, y.d, y.b, axis);
}

// Sorts two points along `axis` (exact).
void order2(const Points& pts, std::vector<Keyed>& s, int axis) {
  if (s.size() == 2 && cmp(pts, s[0], s[1], axis) > 0) std::swap(s[0], s[1]);
}

int orient2d_v(const Soup& s, u32 a, u32 b, u32 c, int k) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  const Vec3 &A = s.verts[a], &B = s.verts[b], &C = s.verts[c];
  return orient2d_fast(A[i], A[j], B[i], B[j], C[i], C[j]);
}

// An axis along which p != q (exactly), preferring the longest extent.
int segment_axis(const Soup& s, u32 p, u32 q) {
  Vec3 d = (s.verts[q] - s.verts[p]).cwiseAbs();
  int a = 0;
  for (int i = 1; i < 3; ++i)
    if (d[i] > d[a]) a = i;
  return a;
}

// Edge (p, q) of one triangle clipped to the closed triangle `tri` (coplanar, projection k): 0,
// 1 or 2 points (2: a segment p'..q' along the edge).
std::vector<PointDef> clip_edge(const Points& pts, u32 p, u32 q, const std::array<u32, 3>& tri, int k) {
  const Soup& s = pts.soup();
  std::array<u32, 3> t = tri;
  if (orient2d_v(s, t[0], t[1], t[2], k) < 0) std::swap(t[1], t[2]);
  int sp[3], sq[3];
  for (int e = 0; e < 3; ++e) {
    sp[e] = orient2d_v(s, t[e], t[(e + 1) % 3], p, k);
    sq[e] = orient2d_v(s, t[e], t[(e + 1) % 3], q, k);
  }
  // Quick rejection: both ends strictly outside one edge.
  for (int e = 0; e < 3; ++e)
    if (sp[e] < 0 && sq[e] < 0) return {};
  std::vector<PointDef> cand;
  if (sp[0] >= 0 && sp[1] >= 0 && sp[2] >= 0) cand.push_back(explicit_point(p));
  if (sq[0] >= 0 && sq[1] >= 0 && sq[2] >= 0) cand.push_back(explicit_point(q));
  int axis = segment_axis(s, p, q);
  auto strictly_between = [&](u32 v) {
    double a = s.verts[p][axis], b = s.verts[q][axis], x = s.verts[v][axis];
    return (a < x && x < b) || (b < x && x < a);
  };
  for (int e = 0; e < 3; ++e) {
    u32 a = t[e], b = t[(e + 1) % 3];
    int ra = orient2d_v(s, p, q, a, k);
    if (ra == 0 && strictly_between(a)) cand.push_back(explicit_point(a));
    int rb = orient2d_v(s, p, q, b, k);
    if (sp[e] * sq[e] < 0 && ra * rb < 0) cand.push_back(lpi(p, q, Plane::wall(a, b, k)));
  }
  if (cand.empty()) return {};
  // The extreme two along the edge.
  const std::vector<Keyed> kc = keyed(pts, cand, axis);
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 1; i < kc.size(); ++i) {
    if (cmp(pts, kc[i], kc[lo], axis) < 0) lo = i;
    if (cmp(pts, kc[i], kc[hi], axis) > 0) hi = i;
  }
  if (cmp(pts, kc[lo], kc[hi], axis) == 0) return {cand[lo]};
  return {cand[lo], cand[hi]};
}

void add_clip(PairCut& cut, std::vector<Segment>& segs, const std::vector<PointDef>& c, u32 p, u32 q, int k) {
  if (c.size() == 2)
    segs.push_back({c[0], c[1], Plane::wall(p, q, k)});
  else if (c.size() == 1)
    cut.points.push_back(c[0]);
}

PairCut coplanar_cut(const Points& pts, u32 t, u32 u) {
  const Soup& s = pts.soup();
  PairCut cut;
  cut.coplanar = true;
  int k = s.axis[t];
  const auto& T = s.tris[t];
  const auto& U = s.tris[u];
  for (int e = 0; e < 3; ++e) {
    u32 p = U[e], q = U[(e + 1) % 3];
    add_clip(cut, cut.segs_t, clip_edge(pts, p, q, T, k), p, q, k);
    p = T[e];
    q = T[(e + 1) % 3];
    add_clip(cut, cut.segs_u, clip_edge(pts, p, q, U, k), p, q, k);
  }
  return cut;
}

}  // namespace

PairCut intersect_pair(const Points& pts, u32 t, u32 u) {
  const Soup& s = pts.soup();
  const auto& T = s.tris[t];
  const auto& U = s.tris[u];
  int su[3], st[3];
  for (int i = 0; i < 3; ++i) su[i] = orient3d_v(s, T[0], T[1], T[2], U[i]);
  if ((su[0] > 0 && su[1] > 0 && su[2] > 0) || (su[0] < 0 && su[1] < 0 && su[2] < 0)) return {};
  if (su[0] == 0 && su[1] == 0 && su[2] == 0) return coplanar_cut(pts, t, u);
  for (int i = 0; i < 3; ++i) st[i] = orient3d_v(s, U[0], U[1], U[2], T[i]);
  if ((st[0] > 0 && st[1] > 0 && st[2] > 0) || (st[0] < 0 && st[1] < 0 && st[2] < 0)) return {};

  Plane pt = Plane::of_triangle(T), pu = Plane::of_triangle(U);
  std::vector<PointDef> a = on_plane(T, st, pu);  // T ∩ plane(U)
  std::vector<PointDef> b = on_plane(U, su, pt);  // U ∩ plane(T)
  if (a.empty() || b.empty()) return {};
  // An axis along which L varies: a non-zero component of n_T x n_U.
  int axis = -1;
  {
    Vec3 nt = (s.verts[T[1]] - s.verts[T[0]]).cross(s.verts[T[2]] - s.verts[T[0]]);
    Vec3 nu = (s.verts[U[1]] - s.verts[U[0]]).cross(s.verts[U[2]] - s.verts[U[0]]);
    Vec3 d = nt.cross(nu).cwiseAbs();
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int x, int y) { return d[x] > d[y]; });
    for (int i : order)
      if (pts.cross_sign(pt, pu, i) != 0) {
        axis = i;
        break;
      }
  }
  if (axis < 0) return {};  // parallel planes that are not the same: cannot meet
  std::vector<Keyed> ka = keyed(pts, a, axis), kb = keyed(pts, b, axis);
  order2(pts, ka, axis);
  order2(pts, kb, axis);
  // Overlap [max(lo), min(hi)].
  const Keyed& lo = cmp(pts, ka.front(), kb.front(), axis) >= 0 ? ka.front() : kb.front();
  const Keyed& hi = cmp(pts, ka.back(), kb.back(), axis) <= 0 ? ka.back() : kb.back();
  int c = cmp(pts, lo, hi, axis);
  PairCut cut;
  if (c > 0) return cut;
  if (c == 0) {
    cut.points.push_back(lo.d);
    return cut;
  }
  cut.segs_t.push_back({lo.d, hi.d, pu});
  cut.segs_u.push_back({lo.d, hi.d, pt});
  (void)same_def;
  return cut;
}

}  // namespace wedge::boolean_detail
