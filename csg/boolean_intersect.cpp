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

// Points with their coordinate bounds along one axis (evaluated once, compared many times).
struct Keyed {
  PointDef d;
  double b[2];
};
bool same_def(const PointDef& x, const PointDef& y) {
  return x.kind == y.kind && x.p == y.p && x.q == y.q && x.P[0] == y.P[0] && x.P[1] == y.P[1] && x.P[2] == y.P[2];
}
int cmp(const Points& pts, const Keyed& x, const Keyed& y, int axis) {
  if (same_def(x.d, y.d)) return 0;
  return pts.compare_def(x.d, x.b, y.d, y.b, axis);
}

// The points of triangle `tri` on the plane that `side` measures: its vertices with side 0 and
// its edges whose ends lie strictly on opposite sides, cut by `plane`, with their coordinate
// bounds on `axis`. Returns how many (at most 3).
int on_plane(const Points& pts, const std::array<u32, 3>& tri, const int side[3], const Plane& plane, int axis,
             Keyed out[3]) {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    if (side[i] == 0) out[n++].d = explicit_point(tri[i]);
    int j = (i + 1) % 3;
    if (side[i] * side[j] < 0 && n < 3) out[n++].d = lpi(tri[i], tri[j], plane);
  }
  for (int i = 0; i < n; ++i) pts.coord_bounds(out[i].d, axis, out[i].b[0], out[i].b[1]);
  return n;
}

int orient2d_v(const Soup& s, u32 a, u32 b, u32 c, int k) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  const Vec3 &A = s.verts[a], &B = s.verts[b], &C = s.verts[c];
  return orient2d_fast(A[i], A[j], B[i], B[j], C[i], C[j]);
}

// Where an edge of T crosses an edge of U (the two segments meet at a point inside both; input
// meshes placed symmetrically do this all along their intersection curves, as the spheres of a
// lattice do), the edge of T cut by U's plane, the edge of U cut by T's plane, and the same
// edges cut by the planes of their other triangles are one point under four definitions, which
// only exact arithmetic would find equal. It gets one definition instead, from the two edges
// alone: the lower edge (p, q) cut by the wall over the other (r, s) along the axis k on which
// the edges' common plane has its largest normal component (there the walls are proper planes
// and the lower edge crosses the wall over the other, checked exactly).
bool crossing_def(const Soup& s, u32 p, u32 q, u32 r, u32 t, PointDef& out) {
  if (std::make_pair(std::min(p, q), std::max(p, q)) > std::make_pair(std::min(r, t), std::max(r, t))) {
    std::swap(p, r);
    std::swap(q, t);
  }
  const Vec3 n = (s.verts[q] - s.verts[p]).cross(s.verts[t] - s.verts[r]).cwiseAbs();
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int x, int y) { return n[x] > n[y] || (n[x] == n[y] && x < y); });
  for (int k : order) {
    // p and q strictly on opposite sides of the line r t in the projection along k.
    if (orient2d_v(s, r, t, p, k) * orient2d_v(s, r, t, q, k) < 0) {
      out = lpi(p, q, Plane::wall(std::min(r, t), std::max(r, t), k));
      return true;
    }
  }
  return false;
}

// T's points on U's plane (a) and U's points on T's plane (b): an edge of T and an edge of U that
// cross are given their one shared definition (crossing_def) in both lists.
void share_crossings(const Points& pts, Keyed a[3], int na, Keyed b[3], int nb) {
  const Soup& s = pts.soup();
  for (int i = 0; i < na; ++i) {
    if (a[i].d.kind != PointDef::Lpi) continue;
    for (int j = 0; j < nb; ++j) {
      if (b[j].d.kind != PointDef::Lpi || a[i].b[1] < b[j].b[0] || b[j].b[1] < a[i].b[0]) continue;
      const u32 p = a[i].d.p, q = a[i].d.q, r = b[j].d.p, t = b[j].d.q;
      if (orient3d_v(s, p, q, r, t) != 0) continue;  // the lines are skew: the points differ
      // Coplanar edges, each crossing the other's triangle's plane properly: the lines are not
      // parallel, and they meet where each crosses the other's plane.
      PointDef c;
      if (!crossing_def(s, p, q, r, t, c)) continue;
      const double lo = std::max(a[i].b[0], b[j].b[0]), hi = std::min(a[i].b[1], b[j].b[1]);
      a[i].d = b[j].d = c;
      a[i].b[0] = b[j].b[0] = lo;
      a[i].b[1] = b[j].b[1] = hi;
    }
  }
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
// 1 or 2 points (2: a segment p'..q' along the edge), in out[0..n).
int clip_edge(const Points& pts, u32 p, u32 q, const std::array<u32, 3>& tri, int k, PointDef out[2]) {
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
    if (sp[e] < 0 && sq[e] < 0) return 0;
  Keyed kc[8];  // p, q, and per edge of tri a vertex and a crossing: at most 8
  int n = 0;
  if (sp[0] >= 0 && sp[1] >= 0 && sp[2] >= 0) kc[n++].d = explicit_point(p);
  if (sq[0] >= 0 && sq[1] >= 0 && sq[2] >= 0) kc[n++].d = explicit_point(q);
  int axis = segment_axis(s, p, q);
  auto strictly_between = [&](u32 v) {
    double a = s.verts[p][axis], b = s.verts[q][axis], x = s.verts[v][axis];
    return (a < x && x < b) || (b < x && x < a);
  };
  for (int e = 0; e < 3; ++e) {
    u32 a = t[e], b = t[(e + 1) % 3];
    int ra = orient2d_v(s, p, q, a, k);
    if (ra == 0 && strictly_between(a)) kc[n++].d = explicit_point(a);
    int rb = orient2d_v(s, p, q, b, k);
    if (sp[e] * sq[e] < 0 && ra * rb < 0) {
      // Two edges crossing properly: the one definition the other triangle's clip gives it too.
      PointDef& d = kc[n++].d;
      if (!crossing_def(s, p, q, a, b, d)) d = lpi(p, q, Plane::wall(a, b, k));
    }
  }
  if (n == 0) return 0;
  // The extreme two along the edge.
  for (int i = 0; i < n; ++i) pts.coord_bounds(kc[i].d, axis, kc[i].b[0], kc[i].b[1]);
  int lo = 0, hi = 0;
  for (int i = 1; i < n; ++i) {
    if (cmp(pts, kc[i], kc[lo], axis) < 0) lo = i;
    if (cmp(pts, kc[i], kc[hi], axis) > 0) hi = i;
  }
  out[0] = kc[lo].d;
  if (cmp(pts, kc[lo], kc[hi], axis) == 0) return 1;
  out[1] = kc[hi].d;
  return 2;
}

void add_clip(PairCut& cut, std::vector<Segment>& segs, const PointDef c[2], int n, u32 p, u32 q, int k) {
  if (n == 2)
    segs.push_back({c[0], c[1], Plane::wall(p, q, k)});
  else if (n == 1)
    cut.points.push_back(c[0]);
}

void coplanar_cut(const Points& pts, u32 t, u32 u, PairCut& cut) {
  const Soup& s = pts.soup();
  cut.coplanar = true;
  int k = s.axis[t];
  const auto& T = s.tris[t];
  const auto& U = s.tris[u];
  PointDef c[2];
  for (int e = 0; e < 3; ++e) {
    u32 p = U[e], q = U[(e + 1) % 3];
    add_clip(cut, cut.segs_t, c, clip_edge(pts, p, q, T, k, c), p, q, k);
    p = T[e];
    q = T[(e + 1) % 3];
    add_clip(cut, cut.segs_u, c, clip_edge(pts, p, q, U, k, c), p, q, k);
  }
}

}  // namespace

PairCut intersect_pair(const Points& pts, u32 t, u32 u) {
  PairCut cut;
  intersect_pair(pts, t, u, cut);
  return cut;
}

void intersect_pair(const Points& pts, u32 t, u32 u, PairCut& cut) {
  cut.segs_t.clear();
  cut.segs_u.clear();
  cut.points.clear();
  cut.coplanar = false;
  const Soup& s = pts.soup();
  const auto& T = s.tris[t];
  const auto& U = s.tris[u];
  int su[3], st[3];
  for (int i = 0; i < 3; ++i) su[i] = orient3d_v(s, T[0], T[1], T[2], U[i]);
  if ((su[0] > 0 && su[1] > 0 && su[2] > 0) || (su[0] < 0 && su[1] < 0 && su[2] < 0)) return;
  if (su[0] == 0 && su[1] == 0 && su[2] == 0) return coplanar_cut(pts, t, u, cut);
  for (int i = 0; i < 3; ++i) st[i] = orient3d_v(s, U[0], U[1], U[2], T[i]);
  if ((st[0] > 0 && st[1] > 0 && st[2] > 0) || (st[0] < 0 && st[1] < 0 && st[2] < 0)) return;
  if (apart(s, t, u, true)) return;  // (the normals were tried in the broad phase)

  Plane pt = Plane::of_triangle(T), pu = Plane::of_triangle(U);
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
  if (axis < 0) return;  // parallel planes that are not the same: cannot meet
  Keyed a[3], b[3];
  const int na = on_plane(pts, T, st, pu, axis, a);  // T ∩ plane(U)
  const int nb = on_plane(pts, U, su, pt, axis, b);  // U ∩ plane(T)
  if (na == 0 || nb == 0) return;
  share_crossings(pts, a, na, b, nb);
  // Each is a point or a segment: its ends in order along the axis.
  if (na == 2 && cmp(pts, a[0], a[1], axis) > 0) std::swap(a[0], a[1]);
  if (nb == 2 && cmp(pts, b[0], b[1], axis) > 0) std::swap(b[0], b[1]);
  // Overlap [max(lo), min(hi)].
  const Keyed& lo = cmp(pts, a[0], b[0], axis) >= 0 ? a[0] : b[0];
  const Keyed& hi = cmp(pts, a[na - 1], b[nb - 1], axis) <= 0 ? a[na - 1] : b[nb - 1];
  int c = cmp(pts, lo, hi, axis);
  if (c > 0) return;
  if (c == 0) {
    cut.points.push_back(lo.d);
    return;
  }
  cut.segs_t.push_back({lo.d, hi.d, pu});
  cut.segs_u.push_back({lo.d, hi.d, pt});
}

}  // namespace wedge::boolean_detail
