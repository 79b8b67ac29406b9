#include "csg/rebuild.h"

#include <algorithm>
#include <deque>

#include "brep/polyhedron_topology.h"

#include "kernel/error.h"

namespace wedge {

namespace {

// Newell's normal of the closed polygon through the origins of `sides`.
Vec3 newell(const Model& m, const std::vector<EdgeSide>& sides) {
  std::vector<Point3> pts;
  pts.reserve(sides.size());
  for (const EdgeSide& s : sides) pts.push_back(m.point(m.origin(s)));
  return newell_normal(pts);
}

}  // namespace

RebuiltSolid rebuild_brep(const Mesh& mesh) {
  if (mesh.face_ids.size() != mesh.triangles.size())
    fail("rebuild: the mesh has ", mesh.face_ids.size(), " face ids for ", mesh.triangles.size(), " triangles");
  if (mesh.triangles.empty()) return {};
  // The vertices in use, renumbered.
  std::vector<int> index(mesh.positions.size(), -1);
  std::vector<Point3> points;
  std::vector<std::vector<int>> faces;
  faces.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    std::vector<int> f(3);
    for (int k = 0; k < 3; ++k) {
      int& i = index[t[k]];
      if (i < 0) {
        i = static_cast<int>(points.size());
        points.push_back(mesh.positions[t[k]]);
      }
      f[k] = i;
    }
    faces.push_back(std::move(f));
  }
  std::vector<FaceId> face_of;
  RebuiltSolid r;
  r.model = polyhedron_topology(points, faces, &face_of);
  Model& m = r.model;

  struct FaceData {
    std::int32_t source = -1;
    double area = 0;
    Vec3 normal = Vec3::Zero();  // sum of the triangles' cross products
    long triangles = 0;
  };
  // Per face id value (arrays, where hash maps took a fifth of the rebuild of 262k triangles).
  const std::size_t nf = m.faces().capacity();
  std::vector<FaceData> data(nf);
  for (std::size_t t = 0; t < face_of.size(); ++t) {
    const auto& f = faces[t];
    Vec3 c = (points[static_cast<std::size_t>(f[1])] - points[static_cast<std::size_t>(f[0])])
                 .cross(points[static_cast<std::size_t>(f[2])] - points[static_cast<std::size_t>(f[0])]);
    data[static_cast<std::size_t>(face_of[t].value)] = FaceData{mesh.face_ids[t], 0.5 * c.norm(), c, 1};
  }
  auto face = [&](EdgeSide s) { return m.loops()[m.side(s).loop].face; };
  auto of = [&](FaceId f) -> FaceData& { return data[static_cast<std::size_t>(f.value)]; };

  // 1. kef across every edge between two faces of one source face.
  std::vector<EdgeId> same;  // edges with one face on both sides, for step 2
  std::vector<std::int32_t> into(nf, -1);  // a face killed -> the face that took it in
  for (EdgeId e : m.edges().ids()) {
    FaceId a = face({e, 0}), b = face({e, 1});
    FaceData& da = of(a);
    FaceData& db = of(b);
    if (da.source != db.source) continue;
    if (a == b) {
      same.push_back(e);
      continue;
    }
    bool a_smaller = da.triangles < db.triangles;
    FaceId f = a_smaller ? a : b, g = a_smaller ? b : a;
    m.kef(e, f);
    into[static_cast<std::size_t>(f.value)] = g.value;
    FaceData& dg = of(g);
    const FaceData& df = of(f);
    dg.area += df.area;
    dg.normal += df.normal;
    dg.triangles += df.triangles;
  }

  // 2. The edges left inside a face: struts by kev (repeatedly: killing one may leave another
  // hanging), then bridges by kemr.
  std::unordered_map<std::int32_t, std::vector<EdgeId>> at;  // vertex -> its edges in `same` (few)
  for (EdgeId e : same)
    for (int k = 0; k < 2; ++k) at[m.edges()[e].v[k].value].push_back(e);
  auto strut_end = [&](EdgeId e) -> int {  // the end that hangs on e alone, or -1
    if (m.side({e, 0}).next == EdgeSide{e, 1}) return 1;
    if (m.side({e, 1}).next == EdgeSide{e, 0}) return 0;
    return -1;
  };
  std::deque<EdgeId> work(same.begin(), same.end());
  auto kill_struts = [&] {
    while (!work.empty()) {
      EdgeId e = work.front();
      work.pop_front();
      if (!m.edges().contains(e)) continue;
      int end = strut_end(e);
      if (end < 0) continue;
      VertexId hang = m.edges()[e].v[end], other = m.edges()[e].v[1 - end];
      m.kev(e, hang);
      for (EdgeId n : at[other.value])
        if (m.edges().contains(n)) work.push_back(n);
    }
  };
  kill_struts();
  for (EdgeId e : same) {
    if (!m.edges().contains(e)) continue;
    EdgeSide s0{e, 0}, s1{e, 1};
    LoopId l = m.side(s0).loop;
    if (m.side(s1).loop != l)
      fail("rebuild: edge ", e.value, " lies inside one face but between two of its loops");
    FaceId f = m.loops()[l].face;
    if (m.faces()[f].outer == l) {
      // The two loops kemr will leave: the part at v[1] runs from s0's successor to s1, the part
      // at v[0] from s1's successor to s0. kemr keeps the part at v[0] as the outer loop.
      std::vector<EdgeSide> part0, part1;
      for (EdgeSide s = m.side(s0).next; s != s1; s = m.side(s).next) part1.push_back(s);
      for (EdgeSide s = m.side(s1).next; s != s0; s = m.side(s).next) part0.push_back(s);
      const Vec3& n = of(f).normal;
      if (newell(m, part1).dot(n) > newell(m, part0).dot(n)) m.reverse_edge(e);
    }
    const VertexId ends[2] = {m.edges()[e].v[0], m.edges()[e].v[1]};
    m.kemr(e);
    // A bridge of several edges: what remains of it now hangs into the ring or the outer loop.
    for (VertexId x : ends)
      for (EdgeId n : at[x.value])
        if (m.edges().contains(n)) work.push_back(n);
    kill_struts();
  }

  // 3. A vertex where only two edges meet lies inside one intersection curve (or one source
  // edge): jekv joins its two edges into one edge on the polyline through it, so the counts are
  // those of the result's faces and curves, not of its triangles. A closed curve keeps two edges.
  // (Per edge and vertex id value.)
  std::vector<std::vector<Point3>> poly(m.edges().capacity());  // edge -> its points, v[0] to v[1]
  std::vector<std::vector<EdgeId>> incident(m.vertices().capacity());
  const std::vector<EdgeId> edges = m.edges().ids();
  for (EdgeId e : edges) {
    const BrepEdge& ed = m.edges()[e];
    poly[static_cast<std::size_t>(e.value)] = {m.point(ed.v[0]), m.point(ed.v[1])};
    for (int k = 0; k < 2; ++k) incident[static_cast<std::size_t>(ed.v[k].value)].push_back(e);
  }
  auto far_end = [&](EdgeId e, VertexId v) { return m.edges()[e].v[m.edges()[e].v[0] == v ? 1 : 0]; };
  auto from = [&](EdgeId e, VertexId v) {  // e's points starting at its end v
    std::vector<Point3> p = poly[static_cast<std::size_t>(e.value)];
    if (m.edges()[e].v[0] != v) std::reverse(p.begin(), p.end());
    return p;
  };
  for (VertexId v : m.vertices().ids()) {
    auto& inc = incident[static_cast<std::size_t>(v.value)];
    if (inc.size() != 2 || inc[0] == inc[1]) continue;
    EdgeId eo = inc[0], e2 = inc[1];
    VertexId a = far_end(eo, v), b = far_end(e2, v);
    if (a == b) continue;  // the last two edges of a closed curve
    std::vector<Point3> pts = from(eo, a);  // a ... v
    std::vector<Point3> rest = from(e2, v);  // v ... b
    pts.insert(pts.end(), rest.begin() + 1, rest.end());
    try {
      m.jekv(e2, v);
    } catch (const Error&) {
      continue;  // a precondition failed; the model is as it was
    }
    // eo now runs between a and b, one way or the other.
    if (m.edges()[eo].v[0] != a) std::reverse(pts.begin(), pts.end());
    poly[static_cast<std::size_t>(eo.value)] = std::move(pts);
    poly[static_cast<std::size_t>(e2.value)].clear();
    inc.clear();
    for (EdgeId& x : incident[static_cast<std::size_t>(b.value)])
      if (x == e2) x = eo;
  }
  // Each joined edge lies on its polyline: a degree-1 NURBS curve through its points, by chord
  // length (left a straight edge if two of its parameters would coincide).
  for (EdgeId e : m.edges().ids()) {
    auto& pts = poly[static_cast<std::size_t>(e.value)];
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    if (pts.size() <= 2) continue;
    std::vector<double> knots{0, 0};
    double total = 0;
    std::vector<double> len{0};
    for (std::size_t i = 1; i < pts.size(); ++i) len.push_back(total += (pts[i] - pts[i - 1]).norm());
    for (std::size_t i = 1; i + 1 < pts.size(); ++i) knots.push_back(total > 0 ? len[i] / total : double(i) / double(pts.size() - 1));
    knots.push_back(1);
    knots.push_back(1);
    if (std::adjacent_find(knots.begin() + 1, knots.end() - 1, std::greater_equal<double>()) != knots.end() - 1) continue;
    m.set_curve(e, std::make_shared<const NurbsCurve>(1, pts, knots));
  }

  for (FaceId f : m.faces().ids()) {
    const FaceData& d = of(f);
    m.set_surface(f, FaceSurface{});
    r.source[f.value] = d.source;
    r.area[f.value] = d.area;
  }
  // Each triangle's face: the chain of faces that took its face in, shortened as it is followed.
  r.triangle_face.resize(face_of.size());
  auto last = [&](std::int32_t id) {
    std::int32_t root = id;
    while (into[static_cast<std::size_t>(root)] >= 0) root = into[static_cast<std::size_t>(root)];
    while (into[static_cast<std::size_t>(id)] >= 0) {
      const std::int32_t next = into[static_cast<std::size_t>(id)];
      into[static_cast<std::size_t>(id)] = root;
      id = next;
    }
    return root;
  };
  for (std::size_t t = 0; t < face_of.size(); ++t) r.triangle_face[t] = last(face_of[t].value);
  Validation v = m.validate(false);
  if (!v) fail("rebuild: the rebuilt solid is not valid: ", v.message);
  return r;
}

}  // namespace wedge
