// Solids built only through the Euler operators.
//
// Lamina and translational sweep (Mäntylä 1988, ch. 12): a profile becomes a two-sided face
// (mvfs, a chain of mev, one mef; each hole by a strut mev, a chain, mef, kemr, and kfmrh of the
// hole's plug into the back face), then the front face is swept: one mev strut per corner and
// one mef per side wall. Features of the worked example (protrusion, pockets, hole) are the same
// steps on the top face of a block.
//
// polyhedron(): a face list becomes a winged-edge model by growing a spanning tree of the vertex
// graph with mev (each strut placed in the corner its vertex's face cycle dictates), then adding
// each remaining edge with mef when its two corners share a loop, or kfmrh + mekr (a handle)
// when they do not. Each mef relabels the shorter side of the loop it splits, found by walking
// both sides in step; the faces are closed in an order that keeps that side short (a face whose
// other edges are all there: its own corners), so the build costs O(E log d) for vertex degree d.
#include <algorithm>
#include <cmath>
#include <optional>

#include "brep/brep.h"
#include "brep/polyhedron_topology.h"
#include "kernel/scaled.h"

namespace wedge {

namespace {

// A closed polygon whose edge i runs pts[i] → pts[i+1]; mids[i] set makes that edge an arc.
struct Ring {
  std::vector<Point3> pts;
  std::vector<std::optional<Point3>> mids;
  Ring reversed() const {
    Ring r;
    std::size_t n = pts.size();
    for (std::size_t i = 0; i < n; ++i) {
      r.pts.push_back(pts[(n - i) % n]);
      r.mids.push_back(mids[(2 * n - i - 1) % n]);
    }
    return r;
  }
  CurvePtr curve(std::size_t i) const {
    if (!mids[i]) return nullptr;
    return std::make_shared<const CircularArc>(arc_through(pts[i], *mids[i], pts[(i + 1) % pts.size()]));
  }
  // Twice the signed area about +z of the straight polygon (arcs by their midpoints).
  double area_z() const {
    double a = 0;
    std::vector<Point3> p;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      p.push_back(pts[i]);
      if (mids[i]) p.push_back(*mids[i]);
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Point3& u = p[i];
      const Point3& w = p[(i + 1) % p.size()];
      a += u.x() * w.y() - w.x() * u.y();
    }
    return a;
  }
};

Ring polygon_ring(const std::vector<Vec2>& pts, double z) {
  Ring r;
  for (const Vec2& p : pts) {
    r.pts.emplace_back(p.x(), p.y(), z);
    r.mids.emplace_back();
  }
  return r;
}

// mev from the tip of a chain, the new vertex at the end of edge `last` (from e.v[0]): its one
// corner is the side of `last` leaving it, taken without a walk along the face's loop (mev(f, v,
// p) looks for v's corner there: a profile of 20,000 points took seconds to become a lamina).
Model::Mev mev_from_tip(Model& m, EdgeId last, const Point3& p, CurvePtr curve = nullptr) {
  const EdgeSide out{last, 1};
  return m.mev_at(Corner{m.side(out).loop, out, m.origin(out)}, p, std::move(curve));
}

// Adds ring `r` (clockwise about the face normal) as a ring of face f, starting with a strut from
// `anchor` (a vertex on f's outer loop). Returns the plug face (the polygon's own face, facing
// the same way as f) and the ring loop.
std::pair<FaceId, LoopId> add_ring(Model& m, FaceId f, VertexId anchor, const Ring& r) {
  std::size_t n = r.pts.size();
  auto strut = m.mev(f, anchor, r.pts[0]);
  EdgeId last_edge = strut.e;
  for (std::size_t i = 1; i < n; ++i) last_edge = mev_from_tip(m, last_edge, r.pts[i], r.curve(i - 1)).e;
  // Close the polygon: from the chain's end back to its start, the new face taking the chain.
  EdgeSide c1{last_edge, 1};          // leaves the chain's last vertex (a leaf)
  EdgeSide c2{strut.e, 1};            // leaves the chain's first vertex along the strut
  auto closing = m.mef_at(c1, c2, r.curve(n - 1));
  LoopId ring = m.kemr(strut.e);
  m.set_surface(closing.f, m.surface(f));
  return {closing.f, ring};
}

// The outward normal of the side wall swept from side s (running a→b) of a face moved by d.
FaceSurface wall_surface(const Model& m, EdgeSide s, const Vec3& d, const Point3& a, const Point3& b) {
  if (auto* arc = dynamic_cast<const CircularArc*>(m.curve(s.edge).get())) {
    Vec3 ax = unit_vector(d);
    const Vec3 axis = arc->normal();
    if (std::abs(std::abs(axis.dot(ax)) - 1) > 1e-9) fail("sweep: an arc's plane is not perpendicular to the sweep direction");
    double sign_side = s.side == 0 ? 1.0 : -1.0;
    // The arc runs counter-clockwise about its normal from v[0] to v[1]: its tangent at the
    // middle, in the side's direction, crossed with d points out of the wall's solid side.
    auto [t0, t1] = arc->domain();
    Vec3 mid = unit_vector(arc->eval((t0 + t1) / 2) - arc->center());
    Vec3 tangent = sign_side * axis.cross(mid);
    Vec3 out = tangent.cross(d);
    return cylinder_face(arc->center(), ax, arc->radius(), !(out.dot(mid) > 0));
  }
  return plane_face(a, unit_vector((b - a).cross(d)));
}

}  // namespace

void sweep(Model& m, FaceId f, const Vec3& d) {
  if (!m.faces().contains(f)) fail("sweep: ", f.value, " is not a face of this model");
  if (!d.allFinite() || d.norm() == 0) fail("sweep: the direction must be finite and non-zero");
  const BrepFace& face = m.faces()[f];
  std::vector<LoopId> ls{face.outer};
  ls.insert(ls.end(), face.rings.begin(), face.rings.end());
  for (LoopId l : ls) {
    std::vector<EdgeSide> sides = m.loop_sides(l);
    std::size_t n = sides.size();
    if (n < 2) fail("sweep: loop ", l.value, " of face ", f.value, " has fewer than two edges");
    std::vector<Point3> base(n);
    std::vector<CurvePtr> curves(n);
    for (std::size_t i = 0; i < n; ++i) {
      base[i] = m.point(m.origin(sides[i]));
      curves[i] = m.curve(sides[i].edge);
    }
    std::vector<EdgeId> struts(n);
    for (std::size_t i = 0; i < n; ++i) struts[i] = m.mev_at(Corner{l, sides[i], m.origin(sides[i])}, base[i] + d).e;
    EdgeSide first_top;
    for (std::size_t i = 0; i < n; ++i) {
      EdgeSide c1{struts[i], 1};
      EdgeSide c2 = i + 1 < n ? EdgeSide{struts[i + 1], 1} : first_top;
      // The top edge copies the side's curve, moved by d and run in the loop's direction.
      CurvePtr top = curves[i];
      if (top) {
        top = transformed_curve(top, translate(d));
        if (sides[i].side == 1) top = reversed_curve(top);
      }
      auto wall = m.mef_at(c1, c2, top);
      if (i == 0) first_top = EdgeSide{wall.e, 0};
      m.set_surface(wall.f, wall_surface(m, sides[i], d, base[i], base[(i + 1) % n]));
    }
  }
  if (const Plane* pl = m.surface(f).plane()) m.set_surface(f, plane_face(pl->origin() + d, pl->unit_normal()));
}

namespace {

// A lamina: face `top` facing +z bounded by `outer` (counter-clockwise about +z) with the given
// holes, face `bottom` facing -z. Holes are reoriented as needed.
struct Lamina {
  Model m;
  FaceId top, bottom;
};
Lamina lamina(const Ring& outer_in, const std::vector<Ring>& holes_in, double z) {
  Lamina L;
  Ring outer = outer_in.area_z() < 0 ? outer_in.reversed() : outer_in;
  std::size_t n = outer.pts.size();
  if (n < 3) fail("lamina: a profile needs at least three points, not ", n);
  auto s = L.m.mvfs(outer.pts[0]);
  VertexId first = s.v;
  auto tip = L.m.mev(s.f, first, outer.pts[1], outer.curve(0));
  for (std::size_t i = 2; i < n; ++i) tip = mev_from_tip(L.m, tip.e, outer.pts[i], outer.curve(i - 1));
  auto back = L.m.mef(s.f, tip.v, first, outer.curve(n - 1));
  L.top = s.f;
  L.bottom = back.f;
  L.m.set_surface(L.top, plane_face(Point3(0, 0, z), Vec3::UnitZ()));
  L.m.set_surface(L.bottom, plane_face(Point3(0, 0, z), -Vec3::UnitZ()));
  for (const Ring& h : holes_in) {
    Ring cw = h.area_z() > 0 ? h.reversed() : h;
    auto [plug, ring] = add_ring(L.m, L.top, first, cw);
    (void)ring;
    L.m.kfmrh(plug, L.bottom);
  }
  return L;
}

void require_polygon(const std::vector<Vec2>& p, const char* what) {
  if (p.size() < 3) fail(what, " needs at least 3 points, got ", p.size());
  for (const Vec2& q : p)
    if (!q.allFinite()) fail(what, " has a point that is not finite");
}

void require_size(double x, const char* what) {
  require_positive(x, what);
  if (x > kMaxCoordinate) fail(what, " ", x, " is beyond ", kMaxCoordinate, " (volumes and normals would overflow)");
  if (x < 1 / kMaxCoordinate) fail(what, " ", x, " is below ", 1 / kMaxCoordinate, " (areas and volumes would underflow to zero)");
}

}  // namespace

void validate_profile(const Profile& profile) {
  struct Seg {
    Vec2 a, b;
    std::size_t ring, index, ring_size;
  };
  std::vector<const std::vector<Vec2>*> rings{&profile.outer};
  for (const auto& h : profile.holes) rings.push_back(&h);
  auto ring_name = [](std::size_t r) { return r == 0 ? std::string("the outer ring") : "hole " + std::to_string(r); };
  std::vector<Seg> segs;
  for (std::size_t r = 0; r < rings.size(); ++r) {
    const auto& ring = *rings[r];
    if (ring.size() < 3) fail(ring_name(r), " needs at least 3 points, got ", ring.size());
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Vec2& p = ring[i];
      if (!p.allFinite()) fail(ring_name(r), " point ", i + 1, " is not finite");
      if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
        fail(ring_name(r), " point ", i + 1, " (", p.x(), ", ", p.y(), ") is beyond +-", kMaxCoordinate,
             " (areas and normals would overflow)");
      const Vec2& q = ring[(i + 1) % ring.size()];
      if (p == q) fail(ring_name(r), " point ", (i + 1) % ring.size() + 1, " repeats point ", i + 1, " (", p.x(), ", ", p.y(), ")");
      segs.push_back({p, q, r, i, ring.size()});
    }
  }
  // Every pair of segments whose x ranges overlap (sorted by their left end): none may meet, but
  // for neighbours in one ring at their shared point.
  std::sort(segs.begin(), segs.end(), [](const Seg& s, const Seg& t) { return std::min(s.a.x(), s.b.x()) < std::min(t.a.x(), t.b.x()); });
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const Seg& s = segs[i];
    const double right = std::max(s.a.x(), s.b.x());
    for (std::size_t j = i + 1; j < segs.size() && std::min(segs[j].a.x(), segs[j].b.x()) <= right; ++j) {
      const Seg& t = segs[j];
      if (s.ring == t.ring) {
        const std::size_t n = s.ring_size;
        const bool adjacent = (s.index + 1) % n == t.index || (t.index + 1) % n == s.index;
        if (adjacent) continue;
        if (segments_intersect_2d(Point2(s.a), Point2(s.b), Point2(t.a), Point2(t.b)))
          fail(ring_name(s.ring), " crosses or touches itself (edges ", std::min(s.index, t.index) + 1, " and ",
               std::max(s.index, t.index) + 1, ")");
      } else if (segments_intersect_2d(Point2(s.a), Point2(s.b), Point2(t.a), Point2(t.b))) {
        const std::size_t lo = std::min(s.ring, t.ring), hi = std::max(s.ring, t.ring);
        if (lo == 0) fail("hole ", hi, " touches or crosses the outer ring (a hole must lie strictly inside it)");
        fail("holes ", lo, " and ", hi, " touch or cross each other");
      }
    }
  }
  // No crossings: a hole is inside a ring exactly when its first point is.
  auto inside = [](const Vec2& p, const std::vector<Vec2>& ring) {
    bool in = false;
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++)
      if ((ring[i].y() > p.y()) != (ring[j].y() > p.y()) &&
          p.x() < (ring[j].x() - ring[i].x()) * (p.y() - ring[i].y()) / (ring[j].y() - ring[i].y()) + ring[i].x())
        in = !in;
    return in;
  };
  for (std::size_t h = 1; h < rings.size(); ++h) {
    if (!inside(rings[h]->front(), profile.outer)) fail("hole ", h, " lies outside the outer ring");
    for (std::size_t k = 1; k < rings.size(); ++k)
      if (k != h && inside(rings[h]->front(), *rings[k])) fail("hole ", h, " lies inside hole ", k, " (holes may not overlap)");
  }
}

Model prism(const Profile& profile, double height) {
  require_size(height, "prism height");
  require_polygon(profile.outer, "prism profile");
  validate_profile(profile);
  std::vector<Ring> holes;
  for (const auto& h : profile.holes) {
    require_polygon(h, "prism hole");
    holes.push_back(polygon_ring(h, 0));
  }
  Lamina L = lamina(polygon_ring(profile.outer, 0), holes, 0);
  sweep(L.m, L.top, Vec3(0, 0, height));
  Validation v = L.m.validate();
  if (!v) fail("prism: the profile does not give a valid solid: ", v.message);
  return std::move(L.m);
}

Model box(const Vec3& size, const Point3& corner) {
  for (int i = 0; i < 3; ++i) require_size(size[i], "box size");
  if (!corner.allFinite()) fail("box: the corner is not finite");
  if ((corner + size).cwiseAbs().maxCoeff() > kMaxCoordinate || corner.cwiseAbs().maxCoeff() > kMaxCoordinate)
    fail("box: a corner is beyond +-", kMaxCoordinate, " (volumes and normals would overflow)");
  Lamina L = lamina(polygon_ring({{corner.x(), corner.y()}, {corner.x() + size.x(), corner.y()},
                                  {corner.x() + size.x(), corner.y() + size.y()}, {corner.x(), corner.y() + size.y()}},
                                 corner.z()),
                    {}, corner.z());
  sweep(L.m, L.top, Vec3(0, 0, size.z()));
  return std::move(L.m);
}

Model frustum(const std::vector<Vec2>& base_in, double height, double top_scale, const Vec2& apex_xy) {
  require_polygon(base_in, "frustum base");
  require_positive(height, "frustum height");
  if (!std::isfinite(top_scale) || top_scale < 0) fail("frustum: top scale must be >= 0, got ", top_scale);
  std::vector<Vec2> base = base_in;
  double a2 = 0;
  for (std::size_t i = 0; i < base.size(); ++i) {
    const Vec2& u = base[i];
    const Vec2& w = base[(i + 1) % base.size()];
    a2 += u.x() * w.y() - w.x() * u.y();
  }
  if (a2 < 0) std::reverse(base.begin(), base.end());
  int n = static_cast<int>(base.size());
  std::vector<Point3> pts;
  for (const Vec2& p : base) pts.emplace_back(p.x(), p.y(), 0);
  std::vector<std::vector<int>> faces;
  std::vector<int> bottom;
  for (int i = n - 1; i >= 0; --i) bottom.push_back(i);
  faces.push_back(bottom);
  if (top_scale == 0) {
    pts.emplace_back(apex_xy.x(), apex_xy.y(), height);
    for (int i = 0; i < n; ++i) faces.push_back({i, (i + 1) % n, n});
  } else {
    for (const Vec2& p : base) {
      Vec2 q = apex_xy + top_scale * (p - apex_xy);
      pts.emplace_back(q.x(), q.y(), height);
    }
    std::vector<int> top;
    for (int i = 0; i < n; ++i) top.push_back(n + i);
    faces.push_back(top);
    for (int i = 0; i < n; ++i) faces.push_back({i, (i + 1) % n, n + (i + 1) % n, n + i});
  }
  return polyhedron(pts, faces);
}

namespace {
Model build_polyhedron(const std::vector<Point3>& points, const std::vector<std::vector<int>>& faces, std::vector<FaceId>* face_of,
                       bool geometry);
}  // namespace

Model polyhedron(const std::vector<Point3>& points, const std::vector<std::vector<int>>& faces, std::vector<FaceId>* face_of) {
  return build_polyhedron(points, faces, face_of, true);
}

Model polyhedron_topology(const std::vector<Point3>& points, const std::vector<std::vector<int>>& faces, std::vector<FaceId>* face_of) {
  return build_polyhedron(points, faces, face_of, false);
}

namespace {
Model build_polyhedron(const std::vector<Point3>& points, const std::vector<std::vector<int>>& faces, std::vector<FaceId>* face_of,
                       bool geometry) {
  const int np = static_cast<int>(points.size());
  if (faces.empty()) fail("polyhedron: no faces");
  for (int i = 0; i < np; ++i)
    if (!points[static_cast<std::size_t>(i)].allFinite()) fail("polyhedron: point ", i + 1, " is not finite");
    else if (points[static_cast<std::size_t>(i)].cwiseAbs().maxCoeff() > kMaxCoordinate)
      fail("polyhedron: point ", i + 1, " is beyond +-", kMaxCoordinate, " (volumes and normals would overflow)");
  const auto un = [](int i) { return static_cast<std::size_t>(i); };
  std::vector<int> used(un(np), 0);
  std::vector<std::size_t> offset(faces.size() + 1, 0);  // face fi's corners: offset[fi] ..
  for (std::size_t fi = 0; fi < faces.size(); ++fi) {
    const auto& f = faces[fi];
    if (f.size() < 3) fail("polyhedron: face ", fi + 1, " has ", f.size(), " corners (at least 3 needed)");
    for (std::size_t k = 0; k < f.size(); ++k) {
      int a = f[k];
      if (a < 0 || a >= np) fail("polyhedron: face ", fi + 1, " names point ", a + 1, ", but there are ", np, " points");
      if (used[un(a)] == static_cast<int>(fi) + 2) fail("polyhedron: face ", fi + 1, " uses point ", a + 1, " twice");
      used[un(a)] = static_cast<int>(fi) + 2;  // this face's mark (nonzero: the point is used)
    }
    offset[fi + 1] = offset[fi] + f.size();
  }
  for (int i = 0; i < np; ++i)
    if (!used[un(i)]) fail("polyhedron: point ", i + 1, " is used by no face");

  // The rotation at each vertex u: one entry per corner x -> u -> y (sigma_u(x) = y), the
  // entries of u together and sorted by x, so that a neighbour is found by binary search (a
  // vertex may have thousands: the apex of a fine cone).
  struct Entry {
    int x, y;
    std::uint32_t face, k;  // the corner: face `face`, its corner k (at u)
  };
  std::vector<std::size_t> start(un(np) + 1, 0);
  for (const auto& f : faces)
    for (int a : f) start[un(a) + 1]++;
  for (int u = 0; u < np; ++u) start[un(u) + 1] += start[un(u)];
  std::vector<Entry> rot(offset.back());
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t fi = 0; fi < faces.size(); ++fi) {
      const auto& f = faces[fi];
      const std::size_t n = f.size();
      for (std::size_t k = 0; k < n; ++k)
        rot[fill[un(f[k])]++] = Entry{f[(k + n - 1) % n], f[(k + 1) % n], static_cast<std::uint32_t>(fi), static_cast<std::uint32_t>(k)};
    }
  }
  for (int u = 0; u < np; ++u)
    std::sort(rot.begin() + static_cast<std::ptrdiff_t>(start[un(u)]), rot.begin() + static_cast<std::ptrdiff_t>(start[un(u) + 1]),
              [](const Entry& a, const Entry& b) { return a.x != b.x ? a.x < b.x : a.face < b.face; });
  // The entry at u whose x is `x` (the corner after the edge x -> u), or npos.
  constexpr std::size_t npos = ~std::size_t(0);
  auto entry = [&](int u, int x) -> std::size_t {
    auto b = rot.begin() + static_cast<std::ptrdiff_t>(start[un(u)]), e = rot.begin() + static_cast<std::ptrdiff_t>(start[un(u) + 1]);
    auto it = std::lower_bound(b, e, x, [](const Entry& a, int v) { return a.x < v; });
    return (it != e && it->x == x) ? static_cast<std::size_t>(it - rot.begin()) : npos;
  };
  // Each directed edge x -> u once: two entries at u with one x use it twice. Reported where a
  // walk of the faces in order meets the second use first (as a scan of the faces would).
  {
    std::size_t best_face = npos, best_edge = 0, first_face = 0;
    int ba = 0, bb = 0;
    for (int u = 0; u < np; ++u)
      for (std::size_t j = start[un(u)]; j + 1 < start[un(u) + 1]; ++j) {
        if (rot[j].x != rot[j + 1].x) continue;
        // The uses of x -> u in scan order: (face, the edge's index in it), the edge ending at corner k.
        std::vector<std::pair<std::size_t, std::size_t>> uses;
        std::size_t i = j;
        for (; i < start[un(u) + 1] && rot[i].x == rot[j].x; ++i) {
          const std::size_t n = faces[rot[i].face].size();
          uses.emplace_back(rot[i].face, (rot[i].k + n - 1) % n);
        }
        std::sort(uses.begin(), uses.end());
        if (best_face == npos || uses[1] < std::make_pair(best_face, best_edge)) {
          best_face = uses[1].first;
          best_edge = uses[1].second;
          first_face = uses[0].first;
          ba = rot[j].x;
          bb = u;
        }
        j = i - 1;
      }
    if (best_face != npos)
      fail("polyhedron: edge ", ba + 1, "-", bb + 1, " is used in the same direction by faces ", first_face + 1, " and ", best_face + 1,
           " (non-manifold, or faces not all counter-clockwise seen from outside)");
  }
  // Each directed edge a -> b has its reverse: an entry at a whose x is b.
  for (std::size_t fi = 0; fi < faces.size(); ++fi) {
    const auto& f = faces[fi];
    for (std::size_t k = 0; k < f.size(); ++k) {
      int a = f[k], b = f[(k + 1) % f.size()];
      if (entry(a, b) == npos) fail("polyhedron: the surface is open: edge ", a + 1, "-", b + 1, " belongs to face ", fi + 1, " only");
    }
  }
  // nxt[j]: the entry whose x is entry j's y (sigma applied once); one fan: following it from
  // any entry of u visits all of u's.
  std::vector<std::size_t> nxt(rot.size());
  for (int u = 0; u < np; ++u)
    for (std::size_t j = start[un(u)]; j < start[un(u) + 1]; ++j) nxt[j] = entry(u, rot[j].y);
  for (int u = 0; u < np; ++u) {
    const std::size_t d = start[un(u) + 1] - start[un(u)];
    std::size_t j = start[un(u)], steps = 0;
    do {
      j = nxt[j];
      ++steps;
    } while (j != start[un(u)] && steps <= d);
    if (steps != d) fail("polyhedron: point ", u + 1, " is non-manifold: the faces around it form more than one fan");
  }
  // The entry of each face corner (face fi, corner k at f[k]).
  std::vector<std::size_t> corner_entry(rot.size());
  for (std::size_t j = 0; j < rot.size(); ++j) corner_entry[offset[rot[j].face] + rot[j].k] = j;

  Model m;
  // side[j]: the side running u -> x for entry j at u (its x), once that edge exists.
  std::vector<EdgeSide> side(rot.size());
  auto has = [&](std::size_t j) { return side[j].valid(); };
  std::vector<VertexId> vid(un(np));
  std::vector<LoopId> lone(un(np));
  std::vector<int> degree(un(np), 0);
  std::vector<int> point_of;  // vertex id -> point index
  // The corner at u where the edge to w goes: the side u -> y, y the first present neighbour
  // after w in sigma_u (lone vertex: no side). `jw` is u's entry whose x is w.
  auto corner_at = [&](int u, std::size_t jw) -> Corner {
    if (degree[un(u)] == 0) return Corner{lone[un(u)], {}, vid[un(u)]};
    std::size_t j = nxt[jw];
    while (!has(j)) j = nxt[j];
    const EdgeSide s = side[j];
    return Corner{m.side(s).loop, s, vid[un(u)]};
  };
  auto remember = [&](int p, VertexId v) {
    vid[un(p)] = v;
    if (point_of.size() <= static_cast<std::size_t>(v.value)) point_of.resize(static_cast<std::size_t>(v.value) + 1, -1);
    point_of[static_cast<std::size_t>(v.value)] = p;
  };
  // Each component gets its shell from the mvfs of its first point; the rest of its points
  // arrive by mev in breadth-first order.
  std::vector<char> reached(un(np), 0);
  std::vector<int> queue;
  for (int root = 0; root < np; ++root) {
    if (reached[un(root)]) continue;
    auto s = m.mvfs(points[un(root)]);
    remember(root, s.v);
    lone[un(root)] = m.faces()[s.f].outer;
    reached[un(root)] = 1;
    queue.assign(1, root);
    for (std::size_t qi = 0; qi < queue.size(); ++qi) {
      int u = queue[qi];
      for (std::size_t j = start[un(u)]; j < start[un(u) + 1]; ++j) {
        const int w = rot[j].x;
        if (reached[un(w)]) continue;
        reached[un(w)] = 1;
        Corner c = corner_at(u, j);
        auto r = m.mev_at(c, points[un(w)]);
        remember(w, r.v);
        side[j] = EdgeSide{r.e, 0};
        side[entry(w, u)] = EdgeSide{r.e, 1};
        degree[un(u)]++;
        degree[un(w)]++;
        queue.push_back(w);
      }
    }
  }
  // A remaining edge u - w (j: u's entry whose x is w): mef when its corners share a loop (the
  // shorter side of the loop, found by walking both in step, becomes the new face), or kfmrh +
  // mekr (a handle) when they do not.
  auto close = [&](int u, std::size_t j) {
    const int w = rot[j].x;
    const std::size_t jr = entry(w, u);
    Corner c1 = corner_at(u, j), c2 = corner_at(w, jr);
    EdgeId e;
    if (c1.loop == c2.loop) {
      EdgeSide a = c1.out, b = c2.out;
      bool first_shorter = false;
      while (true) {
        a = m.side(a).next;
        if (a == c2.out) { first_shorter = true; break; }
        b = m.side(b).next;
        if (b == c1.out) break;
      }
      e = first_shorter ? m.mef_at(c1.out, c2.out).e : m.mef_at(c2.out, c1.out).e;
    } else {
      m.kfmrh(m.loops()[c2.loop].face, m.loops()[c1.loop].face);
      e = m.mekr_at(c1, c2);
    }
    const BrepEdge& ed = m.edges()[e];
    const bool forward = point_of[static_cast<std::size_t>(ed.v[0].value)] == u;  // e runs u -> w
    side[j] = EdgeSide{e, forward ? 0 : 1};
    side[jr] = EdgeSide{e, forward ? 1 : 0};
  };
  // The remaining edges, first by peeling faces: a face with one edge missing is closed by it,
  // and that side of the loop is the face's few corners, so the walk is short (in any other
  // order the walks summed to O(E log E) and most of the build). Then the rest (around handles).
  {
    std::vector<std::uint32_t> missing(faces.size(), 0);
    for (std::size_t fi = 0; fi < faces.size(); ++fi)
      for (std::size_t k = 0; k < faces[fi].size(); ++k)
        if (!has(nxt[corner_entry[offset[fi] + k]])) missing[fi]++;  // the side f[k] -> f[k+1]
    std::vector<std::uint32_t> ready;
    for (std::size_t fi = 0; fi < faces.size(); ++fi)
      if (missing[fi] == 1) ready.push_back(static_cast<std::uint32_t>(fi));
    // Closing an edge counts down the faces on both sides; where none has one edge missing (the
    // edges left form cycles of faces: around the handles), the next edge in vertex order is
    // closed, which opens its cycle to peeling again.
    auto closed_one = [&](std::size_t j, std::uint32_t fi) {
      missing[fi]--;
      const std::uint32_t g = rot[j].face;  // the face across: it runs x -> u
      missing[g]--;
      if (missing[g] == 1) ready.push_back(g);
      if (missing[fi] == 1) ready.push_back(fi);
    };
    int cu = 0;
    std::size_t cj = 0;
    while (true) {
      if (!ready.empty()) {
        const std::uint32_t fi = ready.back();
        ready.pop_back();
        if (missing[fi] != 1) continue;
        const auto& f = faces[fi];
        for (std::size_t k = 0; k < f.size(); ++k) {
          const std::size_t j = nxt[corner_entry[offset[fi] + k]];  // at f[k], its x is f[k+1]
          if (has(j)) continue;
          close(f[k], j);
          closed_one(j, fi);
          break;
        }
        continue;
      }
      // The next edge u - x not yet there (u < x), in vertex order.
      while (cu < np && (cj >= start[un(cu) + 1] || cu >= rot[cj].x || has(cj))) {
        if (cj >= start[un(cu) + 1]) {
          if (++cu < np) cj = start[un(cu)];
        } else {
          ++cj;
        }
      }
      if (cu >= np) break;
      close(cu, cj);
      // (the face that runs u -> x: the corner at x after the edge from u)
      closed_one(cj, rot[entry(rot[cj].x, cu)].face);
    }
  }
  // Each input face is now one face; give it its plane (Newell normal, centroid).
  if (face_of) face_of->clear();
  if (m.faces().size() != faces.size())
    fail("polyhedron: the faces do not form closed 2-manifold surfaces (", m.faces().size(), " faces built from ", faces.size(), ")");
  std::vector<Point3> corners;
  for (std::size_t fi = 0; fi < faces.size(); ++fi) {
    const auto& f = faces[fi];
    const EdgeSide first = side[nxt[corner_entry[offset[fi]]]];  // f[0] -> f[1]
    LoopId l = m.side(first).loop;
    FaceId face = m.loops()[l].face;
    std::size_t length = 0;
    EdgeSide s = first;
    do {
      s = m.side(s).next;
      ++length;
    } while (!(s == first) && length <= f.size());
    if (m.faces()[face].outer != l || length != f.size()) fail("polyhedron: face ", fi + 1, " does not close into a single loop");
    if (geometry) {
      corners.clear();
      Point3 c = Point3::Zero();
      for (int k : f) {
        corners.push_back(points[un(k)]);
        c += corners.back();
      }
      Vec3 n = unit_vector(newell_normal(corners));
      if (n == Vec3::Zero()) fail("polyhedron: face ", fi + 1, " has zero area");
      m.set_surface(face, plane_face(c / static_cast<double>(f.size()), n));
    }
    if (face_of) face_of->push_back(face);
  }
  // (A topology alone is for a caller that changes it further and validates its own result.)
  if (geometry) {
    Validation v = m.validate(true);
    if (!v) fail("polyhedron: ", v.message);
  }
  return m;
}
}  // namespace

Model worked_example(std::vector<FeatureRow>* rows) {
  Model m = box(Vec3(10, 8, 4));
  if (rows) rows->push_back({"Basic shape", m.counts()});
  FaceId top, bottom;
  m.faces().for_each([&](FaceId f, const BrepFace&) {
    Vec3 n = m.face_normal(f);
    if (n.z() > 0.5) top = f;
    if (n.z() < -0.5) bottom = f;
  });
  VertexId anchor = m.loop_vertices(m.faces()[top].outer)[0];
  auto feature = [&](const char* name, const Ring& ccw, double depth, bool through) {
    EulerCounts before = m.counts();
    auto [plug, ring] = add_ring(m, top, anchor, ccw.reversed());
    (void)ring;
    sweep(m, plug, Vec3(0, 0, depth));
    if (through) m.kfmrh(plug, bottom);
    if (rows) rows->push_back({name, m.counts() - before});
  };
  // Protrusion: a 2 x 2 block, 2 high.
  feature("Protrusion", polygon_ring({{1, 1}, {3, 1}, {3, 3}, {1, 3}}, 4), 2, false);
  // Sharp-cornered depression, 1 deep.
  feature("Sharp corner depression", polygon_ring({{4, 1}, {6, 1}, {6, 3}, {4, 3}}, 4), -1, false);
  // Round-cornered depression: x in [1, 5], y in [4.5, 7], corner radius 0.5, 1 deep.
  {
    double a = 1, b = 5, c = 4.5, d = 7, r = 0.5, z = 4, h = r * (1 - std::sqrt(0.5));
    Ring q;
    auto add = [&](double x, double y, std::optional<Point3> mid) {
      q.pts.emplace_back(x, y, z);
      q.mids.push_back(mid);
    };
    add(a + r, c, std::nullopt);
    add(b - r, c, Point3(b - h, c + h, z));
    add(b, c + r, std::nullopt);
    add(b, d - r, Point3(b - h, d - h, z));
    add(b - r, d, std::nullopt);
    add(a + r, d, Point3(a + h, d - h, z));
    add(a, d - r, std::nullopt);
    add(a, c + r, Point3(a + h, c + h, z));
    feature("Round corner depression", q, -1, false);
  }
  // Round through-hole: radius 1 at (7.5, 5.5), its circle as two half arcs.
  {
    double cx = 7.5, cy = 5.5, r = 1, z = 4;
    Ring q;
    q.pts = {Point3(cx + r, cy, z), Point3(cx - r, cy, z)};
    q.mids = {Point3(cx, cy + r, z), Point3(cx, cy - r, z)};
    feature("Hole", q, -4, true);
  }
  return m;
}

}  // namespace wedge
