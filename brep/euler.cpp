// The winged-edge store and its Euler operators.
//
// Method: Baumgart's winged edge (1975) with the operator set of Mäntylä, "An Introduction to
// Solid Modeling" (1988), ch. 9 (mvfs/kvfs, mev/kev, mef/kef, kemr/mekr, kfmrh/mfkrh, semv/jekv).
// Each operator is a handful of splices of the successor/predecessor wings ("link(a, b)": b
// follows a) plus a relabelling of the loop pointers of the sides that change loop. Every
// precondition is checked before the first write, so a failed operator leaves the model as it was.
#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_set>

#include "brep/brep.h"

namespace wedge {

// --- element helpers -------------------------------------------------------------------------
VertexId Model::new_vertex(const Point3& p) {
  VertexId v = vertices_.add({});
  points_[v] = p;
  return v;
}
EdgeId Model::new_edge(VertexId a, VertexId b, CurvePtr c) {
  BrepEdge e;
  e.v[0] = a;
  e.v[1] = b;
  EdgeId id = edges_.add(e);
  curves_[id] = std::move(c);
  return id;
}
FaceId Model::new_face(ShellId s) {
  BrepFace f;
  f.shell = s;
  FaceId id = faces_.add(f);
  surfaces_[id] = FaceSurface{};
  shells_[s].faces++;
  return id;
}
void Model::kill_face(FaceId f) {
  shells_[faces_[f].shell].faces--;
  faces_.remove(f);
}

void Model::link(EdgeSide a, EdgeSide b) {
  side_mut(a).next = b;
  side_mut(b).prev = a;
}
void Model::relabel(EdgeSide start, LoopId l) {
  EdgeSide s = start;
  do {
    side_mut(s).loop = l;
    s = side(s).next;
  } while (!(s == start));
}

const Point3& Model::point(VertexId v) const {
  if (!vertices_.contains(v)) fail("no vertex ", v.value);
  return points_[v];
}
const CurvePtr& Model::curve(EdgeId e) const {
  if (!edges_.contains(e)) fail("no edge ", e.value);
  return curves_[e];
}
const FaceSurface& Model::surface(FaceId f) const {
  if (!faces_.contains(f)) fail("no face ", f.value);
  return surfaces_[f];
}
void Model::set_point(VertexId v, const Point3& p) {
  if (!vertices_.contains(v)) fail("set_point: no vertex ", v.value);
  if (!p.allFinite()) fail("set_point: the point of vertex ", v.value, " is not finite");
  points_[v] = p;
}
void Model::set_curve(EdgeId e, CurvePtr c) {
  if (!edges_.contains(e)) fail("set_curve: no edge ", e.value);
  curves_[e] = std::move(c);
}
const PCurve* Model::pcurve(EdgeSide s) const {
  if (!pcurves_.contains(s.edge)) return nullptr;
  const auto& p = pcurves_[s.edge][s.side];
  return p ? &*p : nullptr;
}
void Model::set_pcurve(EdgeSide s, const PCurve& p) {
  if (!edges_.contains(s.edge)) fail("set_pcurve: no edge ", s.edge.value);
  pcurves_[s.edge][s.side] = p;
}
bool Model::has_param_faces() const {
  bool any = false;
  faces_.for_each([&](FaceId f, const BrepFace&) { any = any || surface(f).parametric; });
  return any;
}
CurvePtr Model::edge_curve(EdgeId e) const {
  if (const CurvePtr& c = curve(e)) return c;
  return std::make_shared<const LineSegment>(point(edges_[e].v[0]), point(edges_[e].v[1]));
}
Point3 Model::edge_point(EdgeId e, double s) const {
  const CurvePtr& c = curve(e);
  if (!c) {
    Point3 a = point(edges_[e].v[0]), b = point(edges_[e].v[1]);
    return a + s * (b - a);
  }
  auto [t0, t1] = c->domain();
  return c->eval(t0 + s * (t1 - t0));
}

void Model::set_surface(FaceId f, FaceSurface s) {
  if (!faces_.contains(f)) fail("set_surface: no face ", f.value);
  surfaces_[f] = std::move(s);
}

void Model::require_vertex(VertexId v, const char* op, const char* what) const {
  if (!vertices_.contains(v)) fail(op, ": ", what, " ", v.value, " is not a vertex of this model");
}
void Model::require_edge(EdgeId e, const char* op) const {
  if (!edges_.contains(e)) fail(op, ": ", e.value, " is not an edge of this model");
}
void Model::require_face(FaceId f, const char* op) const {
  if (!faces_.contains(f)) fail(op, ": ", f.value, " is not a face of this model");
}

std::vector<EdgeSide> Model::loop_sides(LoopId l) const {
  std::vector<EdgeSide> out;
  const BrepLoop& lp = loops_[l];
  if (!lp.first.valid()) return out;
  EdgeSide s = lp.first;
  std::size_t guard = 2 * edges_.capacity() + 2;
  do {
    out.push_back(s);
    s = side(s).next;
    if (out.size() > guard) fail("loop ", l.value, " is not a closed cycle");
  } while (!(s == lp.first));
  return out;
}
std::vector<VertexId> Model::loop_vertices(LoopId l) const {
  std::vector<VertexId> out;
  if (!loops_[l].first.valid()) return {loops_[l].lone};
  for (EdgeSide s : loop_sides(l)) out.push_back(origin(s));
  return out;
}

Corner Model::corner(LoopId l, VertexId v) const {
  if (!loops_.contains(l)) fail("no loop ", l.value);
  const BrepLoop& lp = loops_[l];
  if (!lp.first.valid()) {
    if (lp.lone == v) return {l, {}, v};
  } else {
    for (EdgeSide s : loop_sides(l))
      if (origin(s) == v) return {l, s, v};
  }
  fail("vertex ", v.value, " is not on loop ", l.value);
}

bool Model::find_corner(FaceId f, VertexId v, Corner* c) const {
  const BrepFace& face = faces_[f];
  auto try_loop = [&](LoopId l) {
    const BrepLoop& lp = loops_[l];
    if (!lp.first.valid()) {
      if (lp.lone == v) { *c = {l, {}, v}; return true; }
      return false;
    }
    for (EdgeSide s : loop_sides(l))
      if (origin(s) == v) { *c = {l, s, v}; return true; }
    return false;
  };
  if (try_loop(face.outer)) return true;
  for (LoopId r : face.rings)
    if (try_loop(r)) return true;
  return false;
}

// --- mvfs / kvfs -----------------------------------------------------------------------------
Model::Mvfs Model::mvfs(const Point3& p) {
  if (!p.allFinite()) fail("mvfs: the point is not finite");
  ShellId s = shells_.add({});
  FaceId f = new_face(s);
  VertexId v = new_vertex(p);
  BrepLoop l;
  l.face = f;
  l.lone = v;
  faces_[f].outer = loops_.add(l);
  return {v, f, s};
}

void Model::kvfs(VertexId v) {
  require_vertex(v, "kvfs", "vertex");
  if (vertices_[v].out.valid()) fail("kvfs: vertex ", v.value, " has edges (precondition: a lone vertex)");
  LoopId l;
  loops_.for_each([&](LoopId id, const BrepLoop& lp) {
    if (!lp.first.valid() && lp.lone == v) l = id;
  });
  if (!l.valid()) fail("kvfs: vertex ", v.value, " is on no loop");
  FaceId f = loops_[l].face;
  ShellId s = faces_[f].shell;
  if (faces_[f].outer != l || !faces_[f].rings.empty() || shells_[s].faces != 1)
    fail("kvfs: the shell of vertex ", v.value, " has more than one face or loop (precondition: a shell made by mvfs alone)");
  loops_.remove(l);
  kill_face(f);
  shells_.remove(s);
  vertices_.remove(v);
}

// --- mev / kev -------------------------------------------------------------------------------
Model::Mev Model::mev(FaceId f, VertexId v, const Point3& p, CurvePtr curve) {
  require_face(f, "mev");
  require_vertex(v, "mev", "vertex");
  Corner c;
  if (!find_corner(f, v, &c)) fail("mev: vertex ", v.value, " is not on face ", f.value);
  return mev_at(c, p, std::move(curve));
}

Model::Mev Model::mev_at(Corner c, const Point3& p, CurvePtr curve) {
  if (!p.allFinite()) fail("mev: the new point is not finite");
  if (!loops_.contains(c.loop)) fail("mev: ", c.loop.value, " is not a loop of this model");
  BrepLoop& lp0 = loops_[c.loop];
  if (c.out.valid()) {
    if (!edges_.contains(c.out.edge) || side(c.out).loop != c.loop)
      fail("mev: the corner's side is not in loop ", c.loop.value);
  } else if (lp0.first.valid() || lp0.lone != c.v) {
    fail("mev: vertex ", c.v.value, " is not the lone vertex of loop ", c.loop.value);
  }
  VertexId v = c.out.valid() ? origin(c.out) : c.v;
  VertexId w = new_vertex(p);
  EdgeId e = new_edge(v, w, std::move(curve));
  EdgeSide s0{e, 0}, s1{e, 1};
  side_mut(s0).loop = c.loop;
  side_mut(s1).loop = c.loop;
  if (c.out.valid()) {
    EdgeSide in = side(c.out).prev;
    link(in, s0);
    link(s0, s1);
    link(s1, c.out);
  } else {
    link(s0, s1);
    link(s1, s0);
    BrepLoop& lp = loops_[c.loop];
    lp.first = s0;
    lp.lone = VertexId();
    vertices_[v].out = s0;
  }
  vertices_[w].out = s1;
  return {e, w};
}

void Model::kev(EdgeId e, VertexId v) {
  require_edge(e, "kev");
  require_vertex(v, "kev", "vertex");
  const BrepEdge& ed = edges_[e];
  if (ed.v[0] != v && ed.v[1] != v) fail("kev: vertex ", v.value, " is not an end of edge ", e.value);
  EdgeSide in{e, ed.v[1] == v ? 0 : 1};  // ends at v
  EdgeSide out = in.mate();              // starts at v
  if (!(side(in).next == out))
    fail("kev: edge ", e.value, " is not the only edge at vertex ", v.value, " (precondition: v hangs on e alone)");
  VertexId u = ed.v[in.side];
  LoopId l = side(in).loop;
  if (side(in).prev == out) {  // the loop was just this edge
    BrepLoop& lp = loops_[l];
    lp.first = EdgeSide();
    lp.lone = u;
    vertices_[u].out = EdgeSide();
  } else {
    EdgeSide p = side(in).prev, n = side(out).next;
    link(p, n);
    BrepLoop& lp = loops_[l];
    if (lp.first == in || lp.first == out) lp.first = n;
    if (vertices_[u].out == in) vertices_[u].out = n;
  }
  edges_.remove(e);
  vertices_.remove(v);
}

// --- mef / kef -------------------------------------------------------------------------------
Model::Mef Model::mef(FaceId f, VertexId v1, VertexId v2, CurvePtr curve) {
  require_face(f, "mef");
  require_vertex(v1, "mef", "vertex");
  require_vertex(v2, "mef", "vertex");
  if (v1 == v2) fail("mef: the two vertices must differ (both are ", v1.value, ")");
  auto try_loop = [&](LoopId l, EdgeSide* c1, EdgeSide* c2) {
    *c1 = *c2 = EdgeSide();
    if (!loops_[l].first.valid()) return false;
    for (EdgeSide s : loop_sides(l)) {
      if (!c1->valid() && origin(s) == v1) *c1 = s;
      if (!c2->valid() && origin(s) == v2) *c2 = s;
    }
    return c1->valid() && c2->valid();
  };
  EdgeSide c1, c2;
  const BrepFace& face = faces_[f];
  bool found = try_loop(face.outer, &c1, &c2);
  for (std::size_t i = 0; !found && i < face.rings.size(); ++i) found = try_loop(face.rings[i], &c1, &c2);
  if (!found) fail("mef: vertices ", v1.value, " and ", v2.value, " do not lie on one loop of face ", f.value);
  return mef_at(c1, c2, std::move(curve));
}

Model::Mef Model::mef_at(EdgeSide c1, EdgeSide c2, CurvePtr curve) {
  if (!edges_.contains(c1.edge) || !edges_.contains(c2.edge)) fail("mef: a corner names no edge of this model");
  if (side(c1).loop != side(c2).loop) fail("mef: the two corners are not on one loop");
  VertexId v1 = origin(c1), v2 = origin(c2);
  if (v1 == v2) fail("mef: the two corners are at the same vertex ", v1.value);
  LoopId l = side(c1).loop;
  FaceId f = loops_[l].face;
  EdgeSide p1 = side(c1).prev, p2 = side(c2).prev;
  EdgeId e = new_edge(v1, v2, std::move(curve));
  EdgeSide s0{e, 0}, s1{e, 1};
  link(p1, s0);
  link(s0, c2);
  link(p2, s1);
  link(s1, c1);
  FaceId f2 = new_face(faces_[f].shell);
  BrepLoop nl;
  nl.face = f2;
  nl.first = s1;
  LoopId l2 = loops_.add(nl);
  faces_[f2].outer = l2;
  side_mut(s0).loop = l;
  relabel(s1, l2);
  loops_[l].first = s0;
  return {e, f2};
}

void Model::kef(EdgeId e, FaceId f) {
  require_edge(e, "kef");
  require_face(f, "kef");
  EdgeSide a{e, 0};
  LoopId la = side(a).loop, lb = side(a.mate()).loop;
  FaceId fa = loops_[la].face, fb = loops_[lb].face;
  if (fa == fb) fail("kef: edge ", e.value, " has face ", fa.value, " on both sides (precondition: two different faces; use kemr)");
  if (fa != f && fb != f) fail("kef: face ", f.value, " is on neither side of edge ", e.value);
  if (fb == f) {
    a = a.mate();
    std::swap(la, lb);
  }
  if (faces_[f].outer != la) fail("kef: edge ", e.value, " lies on a ring of face ", f.value, ", not on its outer loop");
  EdgeSide b = a.mate();
  FaceId g = loops_[lb].face;
  EdgeSide pa = side(a).prev, na = side(a).next, pb = side(b).prev, nb = side(b).next;
  VertexId x = origin(a), y = origin(b);
  link(pb, na);
  link(pa, nb);
  // Only f's sides change loop: na round to pa, then g's (nb) follow. (Relabelling the whole
  // merged loop made merging many faces into one quadratic: rebuild_brep's kef of a 262k-triangle
  // result.)
  for (EdgeSide s = na; side(s).loop != lb; s = side(s).next) side_mut(s).loop = lb;
  loops_[lb].first = nb;
  if (vertices_[x].out == a) vertices_[x].out = nb;
  if (vertices_[y].out == b) vertices_[y].out = na;
  for (LoopId r : faces_[f].rings) {
    loops_[r].face = g;
    faces_[g].rings.push_back(r);
  }
  loops_.remove(la);
  kill_face(f);
  edges_.remove(e);
}

// --- kemr / mekr -----------------------------------------------------------------------------
LoopId Model::kemr(EdgeId e) {
  require_edge(e, "kemr");
  EdgeSide s0{e, 0}, s1{e, 1};
  LoopId l = side(s0).loop;
  if (side(s1).loop != l)
    fail("kemr: edge ", e.value, " has different loops on its two sides (precondition: one loop on both sides; use kef)");
  VertexId v0 = edges_[e].v[0], v1 = edges_[e].v[1];
  EdgeSide n0 = side(s0).next, p1 = side(s1).prev, n1 = side(s1).next, p0 = side(s0).prev;
  FaceId f = loops_[l].face;
  BrepLoop ring;
  ring.face = f;
  LoopId r = loops_.add(ring);
  if (n0 == s1) {  // v1 hung on e alone
    loops_[r].lone = v1;
    vertices_[v1].out = EdgeSide();
  } else {
    link(p1, n0);
    loops_[r].first = n0;
    relabel(n0, r);
    if (vertices_[v1].out == s1) vertices_[v1].out = n0;
  }
  BrepLoop& lp = loops_[l];
  if (n1 == s0) {
    lp.first = EdgeSide();
    lp.lone = v0;
    vertices_[v0].out = EdgeSide();
  } else {
    link(p0, n1);
    lp.first = n1;
    if (vertices_[v0].out == s0) vertices_[v0].out = n1;
  }
  faces_[f].rings.push_back(r);
  edges_.remove(e);
  return r;
}

EdgeId Model::mekr(VertexId v1, VertexId v2, CurvePtr curve) {
  require_vertex(v1, "mekr", "vertex");
  require_vertex(v2, "mekr", "vertex");
  if (v1 == v2) fail("mekr: the two vertices must differ (both are ", v1.value, ")");
  // Find a face with v1 and v2 on two different loops.
  Corner c1, c2;
  bool found = false, same_loop = false;
  faces_.for_each([&](FaceId f, const BrepFace&) {
    if (found) return;
    Corner a, b;
    if (find_corner(f, v1, &a) && find_corner(f, v2, &b)) {
      if (a.loop == b.loop) {
        same_loop = true;
        return;
      }
      c1 = a;
      c2 = b;
      found = true;
    }
  });
  if (!found) {
    if (same_loop) fail("mekr: vertices ", v1.value, " and ", v2.value, " lie on the same loop (precondition: two different loops of one face; use mef)");
    fail("mekr: vertices ", v1.value, " and ", v2.value, " do not lie on two loops of one face");
  }
  return mekr_at(c1, c2, std::move(curve));
}

EdgeId Model::mekr_at(Corner a, Corner b, CurvePtr curve) {
  if (!loops_.contains(a.loop) || !loops_.contains(b.loop)) fail("mekr: a corner names no loop of this model");
  if (a.loop == b.loop) fail("mekr: both corners are on loop ", a.loop.value, " (precondition: two different loops; use mef)");
  FaceId f = loops_[a.loop].face;
  if (loops_[b.loop].face != f) fail("mekr: loops ", a.loop.value, " and ", b.loop.value, " belong to different faces");
  // The ring to kill: b's if it is a ring, else a's; the new edge runs from the survivor (v[0]).
  if (faces_[f].outer == b.loop) std::swap(a, b);
  if (faces_[f].outer == b.loop) fail("mekr: neither loop is a ring");
  auto check_corner = [&](const Corner& c) {
    if (c.out.valid()) {
      if (!edges_.contains(c.out.edge) || side(c.out).loop != c.loop) fail("mekr: a corner's side is not in its loop");
    } else if (loops_[c.loop].first.valid() || loops_[c.loop].lone != c.v) {
      fail("mekr: vertex ", c.v.value, " is not the lone vertex of loop ", c.loop.value);
    }
  };
  check_corner(a);
  check_corner(b);
  VertexId va = a.out.valid() ? origin(a.out) : a.v, vb = b.out.valid() ? origin(b.out) : b.v;
  EdgeSide pa = a.out.valid() ? side(a.out).prev : EdgeSide(), pb = b.out.valid() ? side(b.out).prev : EdgeSide();
  EdgeId e = new_edge(va, vb, std::move(curve));
  EdgeSide s0{e, 0}, s1{e, 1};
  if (b.out.valid()) {
    link(s0, b.out);
    link(pb, s1);
  } else {
    link(s0, s1);
  }
  if (a.out.valid()) {
    link(s1, a.out);
    link(pa, s0);
  } else {
    link(s1, s0);
  }
  if (!a.out.valid()) vertices_[va].out = s0;
  if (!b.out.valid()) vertices_[vb].out = s1;
  // Only b's sides and the new ones change loop: s0 round to s1, then a's follow (relabelling the
  // whole merged loop cost a polyhedron's handles a walk of most of its model each).
  {
    EdgeSide s = s0;
    do {
      side_mut(s).loop = a.loop;
      s = side(s).next;
    } while (!(s == s0) && side(s).loop != a.loop);
  }
  BrepLoop& keep = loops_[a.loop];
  keep.first = s0;
  keep.lone = VertexId();
  auto& rings = faces_[f].rings;
  rings.erase(std::find(rings.begin(), rings.end(), b.loop));
  loops_.remove(b.loop);
  return e;
}

// --- kfmrh / mfkrh ---------------------------------------------------------------------------
LoopId Model::kfmrh(FaceId hole, FaceId f) {
  require_face(hole, "kfmrh");
  require_face(f, "kfmrh");
  if (hole == f) fail("kfmrh: the two faces must differ (both are ", f.value, ")");
  if (!faces_[hole].rings.empty()) fail("kfmrh: face ", hole.value, " has rings (precondition: a face of one loop)");
  LoopId l = faces_[hole].outer;
  ShellId sh = faces_[hole].shell, sf = faces_[f].shell;
  if (sh == sf) {
    ++holes_;
  } else {
    for (FaceId g : faces_.ids())
      if (faces_[g].shell == sh) {
        faces_[g].shell = sf;
        shells_[sf].faces++;
      }
    shells_.remove(sh);
  }
  loops_[l].face = f;
  faces_[f].rings.push_back(l);
  // kill_face decrements the face count of the hole's (now merged) shell.
  shells_[faces_[hole].shell].faces--;
  faces_.remove(hole);
  return l;
}

bool Model::ring_stays_connected(FaceId f, LoopId ring, std::vector<FaceId>* component) const {
  // Breadth-first search over faces from the ring, with the ring standing for the new face: does
  // it reach face f through another loop?
  std::unordered_set<std::int32_t> seen;
  std::vector<LoopId> queue{ring};
  for (std::size_t qi = 0; qi < queue.size(); ++qi) {
    LoopId l = queue[qi];
    if (!loops_[l].first.valid()) continue;
    for (EdgeSide s : loop_sides(l)) {
      LoopId m = side(s.mate()).loop;
      if (m == ring) continue;
      FaceId g = loops_[m].face;
      if (g == f) return true;
      if (seen.insert(g.value).second) {
        if (component) component->push_back(g);
        queue.push_back(faces_[g].outer);
        for (LoopId r : faces_[g].rings) queue.push_back(r);
      }
    }
  }
  return false;
}

FaceId Model::mfkrh(FaceId f, LoopId ring) {
  require_face(f, "mfkrh");
  if (!loops_.contains(ring)) fail("mfkrh: ", ring.value, " is not a loop of this model");
  auto& rings = faces_[f].rings;
  auto it = std::find(rings.begin(), rings.end(), ring);
  if (it == rings.end()) fail("mfkrh: loop ", ring.value, " is not a ring of face ", f.value);
  std::vector<FaceId> comp;
  bool connected = ring_stays_connected(f, ring, &comp);
  if (connected && holes_ <= 0)
    fail("mfkrh: the model has no through-hole to kill (H = 0) and face ", f.value, " stays connected to loop ", ring.value);
  rings.erase(it);
  ShellId s = faces_[f].shell;
  if (!connected) {
    s = shells_.add({});
    for (FaceId g : comp) {
      shells_[faces_[g].shell].faces--;
      faces_[g].shell = s;
      shells_[s].faces++;
    }
  } else {
    --holes_;
  }
  FaceId f2 = new_face(s);
  faces_[f2].outer = ring;
  loops_[ring].face = f2;
  // The new face lies in the plane of f, facing the other way.
  if (const Plane* pl = surfaces_[f].plane()) surfaces_[f2] = plane_face(pl->origin(), -pl->unit_normal());
  return f2;
}

// --- semv / jekv -----------------------------------------------------------------------------
Model::Mev Model::semv(EdgeId e, const Point3& p) {
  require_edge(e, "semv");
  if (!p.allFinite()) fail("semv: the new point is not finite");
  // A curved edge is cut where its curve passes p (which must lie on it).
  CurvePtr first, second;
  if (const CurvePtr& c = curves_[e]) {
    double t = closest_parameter(*c, p);
    auto [t0, t1] = c->domain();
    double size = (c->eval(t0) - c->eval((t0 + t1) / 2)).norm() + (c->eval(t1) - c->eval((t0 + t1) / 2)).norm();
    if ((c->eval(t) - p).norm() > 1e-9 * std::max(size, 1e-300) || !(t > t0 && t < t1))
      fail("semv: the new point is not inside edge ", e.value, "'s curve (precondition: p on the curve, not at its ends)");
    std::tie(first, second) = split_curve(c, t);
  }
  VertexId v1 = edges_[e].v[1];
  VertexId w = new_vertex(p);
  EdgeId e2 = new_edge(w, v1, second);
  curves_[e] = first;
  edges_[e].v[1] = w;
  EdgeSide e0{e, 0}, e1{e, 1}, f0{e2, 0}, f1{e2, 1};
  side_mut(f0).loop = side(e0).loop;
  side_mut(f1).loop = side(e1).loop;
  EdgeSide n0 = side(e0).next, p1 = side(e1).prev;
  if (n0 == e1) {
    link(e0, f0);
    link(f0, f1);
    link(f1, e1);
  } else {
    link(e0, f0);
    link(f0, n0);
    link(p1, f1);
    link(f1, e1);
  }
  if (vertices_[v1].out == e1) vertices_[v1].out = f1;
  vertices_[w].out = f0;
  return {e2, w};
}

void Model::reverse_edge(EdgeId e) {
  BrepEdge& ed = edges_[e];
  auto sw = [e](EdgeSide s) { return s.edge == e ? s.mate() : s; };
  BrepSide old[2] = {ed.side[0], ed.side[1]};
  for (int k = 0; k < 2; ++k) {
    EdgeSide now{e, 1 - k};
    if (old[k].next.edge != e) side_mut(old[k].next).prev = now;
    if (old[k].prev.edge != e) side_mut(old[k].prev).next = now;
  }
  for (int k = 0; k < 2; ++k) {
    BrepSide& sd = edges_[e].side[1 - k];
    sd.loop = old[k].loop;
    sd.next = sw(old[k].next);
    sd.prev = sw(old[k].prev);
  }
  BrepEdge& ed2 = edges_[e];
  std::swap(ed2.v[0], ed2.v[1]);
  for (VertexId v : ed2.v)
    if (vertices_[v].out.edge == e) vertices_[v].out = vertices_[v].out.mate();
  for (const BrepSide& sd : ed2.side)
    if (loops_[sd.loop].first.edge == e) loops_[sd.loop].first = loops_[sd.loop].first.mate();
  if (CurvePtr& c = curves_[e]) c = reversed_curve(c);
  if (pcurves_.contains(e)) {
    // Side k (on face A) becomes side 1 - k; the curve's parameter now runs from the old end.
    auto old = pcurves_[e];
    for (int k = 0; k < 2; ++k) {
      pcurves_[e][1 - k].reset();
      if (old[k]) pcurves_[e][1 - k] = PCurve{old[k]->end, old[k]->start};
    }
  }
}

void Model::jekv(EdgeId e2, VertexId v) {
  require_edge(e2, "jekv");
  require_vertex(v, "jekv", "vertex");
  if (edges_[e2].v[0] != v && edges_[e2].v[1] != v) fail("jekv: vertex ", v.value, " is not an end of edge ", e2.value);
  // Run e2 away from v and the other edge e into v (flipping an edge changes no topology).
  EdgeSide f0{e2, edges_[e2].v[0] == v ? 0 : 1};
  EdgeSide in = side(f0).prev;  // ends at v
  EdgeSide f1 = f0.mate();
  if (in.edge == e2 || !(side(f1).next == in.mate()))
    fail("jekv: vertex ", v.value, " does not have exactly two edges (precondition: v of degree 2)");
  // Side s of an edge runs from v[s] to v[1 - s]. Joining two edges that connect the same pair
  // of vertices would leave one edge from a vertex to itself.
  if (edges_[in.edge].v[in.side] == edges_[e2].v[1 - f0.side])
    fail("jekv: edges ", in.edge.value, " and ", e2.value, " join the same two vertices; joining them would make an edge "
         "from a vertex to itself (precondition: the two edges at v lead to different vertices)");
  // The joined edge's curve: none for two straight edges, else the one curve of which the two are
  // consecutive pieces (semv's split undone).
  CurvePtr joined;
  {
    const CurvePtr& ci = curves_[in.edge];
    const CurvePtr& co = curves_[e2];
    if (ci || co) {
      joined = joined_curve(ci && in.side == 1 ? reversed_curve(ci) : ci, co && f0.side == 1 ? reversed_curve(co) : co);
      if (!joined)
        fail("jekv: edges ", in.edge.value, " and ", e2.value, " are not consecutive pieces of one curve (precondition: "
             "both straight, or cut from one curve by semv)");
    }
  }
  if (f0.side == 1) reverse_edge(e2);
  if (in.side == 1) reverse_edge(in.edge);
  EdgeId e = in.edge;
  EdgeSide e0{e, 0}, e1{e, 1};
  f0 = EdgeSide{e2, 0};
  f1 = EdgeSide{e2, 1};
  VertexId v1 = edges_[e2].v[1];
  EdgeSide n = side(f0).next, p = side(f1).prev;
  if (n == f1) {
    link(e0, e1);
  } else {
    link(e0, n);
    link(p, e1);
  }
  edges_[e].v[1] = v1;
  curves_[e] = joined;
  if (vertices_[v1].out == f1) vertices_[v1].out = e1;
  if (loops_[side(e0).loop].first == f0) loops_[side(e0).loop].first = e0;
  if (loops_[side(e1).loop].first == f1) loops_[side(e1).loop].first = e1;
  edges_.remove(e2);
  vertices_.remove(v);
}

EulerCounts Model::counts() const {
  EulerCounts c;
  c.V = static_cast<long>(vertices_.size());
  c.E = static_cast<long>(edges_.size());
  c.F = static_cast<long>(faces_.size());
  c.R = static_cast<long>(loops_.size()) - c.F;
  c.H = holes_;
  c.S = static_cast<long>(shells_.size());
  return c;
}

}  // namespace wedge
