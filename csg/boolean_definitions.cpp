// Facts about points read from their definitions, without arithmetic on the points: on one cut
// segment, on a plane of their definition, collinear by construction (exact tests on input
// vertices only).
#include <algorithm>

#include "csg/boolean_impl.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

bool Points::on_one_segment(u32 a, u32 b, u32 c) const {
  std::uint64_t line = 0;
  for (u32 x : {a, b, c}) {
    const PointDef& d = def(x);
    if (d.kind == PointDef::Lpi) line = static_cast<std::uint64_t>(std::min(d.p, d.q)) << 32 | std::max(d.p, d.q);
  }
  if (!line) return false;
  const u32 p = static_cast<u32>(line >> 32), q = static_cast<u32>(line);
  for (u32 x : {a, b, c}) {
    const PointDef& d = def(x);
    if (d.kind == PointDef::Tpi) return false;
    if (d.kind == PointDef::Explicit ? (d.p != p && d.p != q) : (std::min(d.p, d.q) != p || std::max(d.p, d.q) != q))
      return false;
  }
  return true;
}

namespace {

// Whether the point x (doubles) lies on plane P (exact; a wall through a, b containing e_k holds
// x when a, b, x are collinear seen along e_k).
bool point_on(const Soup& s, const Plane& P, const Vec3& x) {
  if (P.axis < 0) return orient3d_fast(s.verts[P.a], s.verts[P.b], s.verts[P.c], x) == 0;
  const int i = (P.axis + 1) % 3, j = (P.axis + 2) % 3;
  const Vec3 &a = s.verts[P.a], &b = s.verts[P.b];
  return orient2d_fast(a[i], a[j], b[i], b[j], x[i], x[j]) == 0;
}

// Whether plane P contains the direction e_k (exact on input vertices): a wall along e_k; a wall
// along another axis over a segment whose ends share the third coordinate; a triangle whose
// projection along e_k is degenerate.
bool contains_axis(const Soup& s, const Plane& P, int k) {
  const Vec3 &a = s.verts[P.a], &b = s.verts[P.b];
  if (P.axis == k) return true;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  if (P.axis >= 0) return a[3 - k - P.axis] == b[3 - k - P.axis];
  const Vec3& c = s.verts[P.c];
  return orient2d_fast(a[i], a[j], b[i], b[j], c[i], c[j]) == 0;
}

// Whether input vertex v lies on plane P.
bool vertex_on(const Soup& s, const Plane& P, u32 v) {
  return v == P.a || v == P.b || (P.axis < 0 && v == P.c) || point_on(s, P, s.verts[v]);
}

// Whether planes X and P are the same plane (exact): X's points lie on P and, where X is a wall,
// P holds its direction too. (Two walls over one plane through different pairs of vertices used
// to count as different planes: collinear_by_definition then put three points on "their line"
// that were not collinear, one of them a few ulps off it.)
bool same_plane(const Soup& s, const Plane& X, const Plane& P) {
  if (X == P) return true;
  if (X.axis < 0) return vertex_on(s, P, X.a) && vertex_on(s, P, X.b) && vertex_on(s, P, X.c);
  return vertex_on(s, P, X.a) && vertex_on(s, P, X.b) && contains_axis(s, P, X.axis);
}

}  // namespace

bool Points::on_plane(u32 p, const Plane& P) const {
  const PointDef& d = def(p);
  switch (d.kind) {
    case PointDef::Explicit:
      return vertex_on(*soup_, P, d.p);
    case PointDef::Lpi:
      if (same_plane(*soup_, d.P[0], P) || (vertex_on(*soup_, P, d.p) && vertex_on(*soup_, P, d.q))) return true;
      break;
    case PointDef::Tpi:
      if (same_plane(*soup_, d.P[0], P) || same_plane(*soup_, d.P[1], P) || same_plane(*soup_, d.P[2], P)) return true;
      break;
  }
  // A point whose coordinates are all doubles (a cut of two axis-parallel segments' planes, as
  // where two cylinders sampled at the same angles cross): the exact test on them.
  return fixed(p) == 7 && point_on(*soup_, P, approx(p));
}

bool Points::collinear_by_definition(u32 a, u32 b, u32 c, int k) const {
  // The definitions held here: planes found below are kept by address.
  const PointDef defs[3] = {def(a), def(b), def(c)};
  const u32 ids[3] = {a, b, c};
  // Points that lie on two different planes of their definitions lie on their line: the
  // crossings of one cut segment with others (each a TPI of T's plane, the segment's plane and
  // another), end points of the segment.
  {
    const Plane* found[2] = {nullptr, nullptr};
    int nf = 0;
    for (int xi = 0; xi < 3; ++xi) {
      const u32 x = ids[xi];
      const PointDef& d = defs[xi];
      const int np = d.kind == PointDef::Tpi ? 3 : d.kind == PointDef::Lpi ? 1 : 0;
      for (int i = 0; i < np && nf < 2; ++i) {
        const Plane& P = d.P[i];
        if (nf == 1 && same_plane(*soup_, *found[0], P)) continue;
        bool all = true;
        for (u32 y : {a, b, c})
          if (y != x && !on_plane(y, P)) {
            all = false;
            break;
          }
        if (!all) continue;
        // On one plane that contains e_k: on its trace, seen along e_k (a sphere's triangle cut
        // by the side of a cylinder along e_k, the cut seen along the cylinder's axis).
        if (k >= 0 && contains_axis(*soup_, P, k)) return true;
        found[nf++] = &P;
      }
    }
    if (nf == 2) return true;
  }
  // Points on one cutting plane X (segments cut by X, or input vertices on X) whose segments'
  // end points all lie on one other plane Q lie on the line X n Q: the halves of a cylinder's
  // side quad cut by a plate's face, the quad's diagonal between them.
  const Plane* X = nullptr;
  u32 ends[6];
  int n = 0;
  for (const PointDef& d : defs) {
    if (d.kind == PointDef::Tpi) return false;
    if (d.kind == PointDef::Lpi) {
      if (!X) X = &d.P[0];
      else if (!same_plane(*soup_, d.P[0], *X)) return false;
      ends[n++] = d.p;
      ends[n++] = d.q;
    } else {
      ends[n++] = d.p;
    }
  }
  if (!X) return false;
  for (const PointDef& d : defs)
    if (d.kind == PointDef::Explicit && !vertex_on(*soup_, *X, d.p)) return false;
  // Q: through the first segment and the first end point off its line.
  const u32 p = ends[0], q = ends[1];
  const Vec3 &P = soup_->verts[p], &Qv = soup_->verts[q];
  int r = -1;
  for (int e = 2; e < n && r < 0; ++e) {
    const Vec3& R = soup_->verts[ends[e]];
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      if (orient2d_fast(P[i], P[j], Qv[i], Qv[j], R[i], R[j]) != 0) {
        r = e;
        break;
      }
    }
  }
  if (r < 0) return false;
  const Plane Qp = Plane::of_triangle({p, q, ends[r]});
  for (int e = 2; e < n; ++e)
    if (!vertex_on(*soup_, Qp, ends[e])) return false;
  return true;
}

}  // namespace wedge::boolean_detail
