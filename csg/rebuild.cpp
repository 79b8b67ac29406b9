#include "csg/rebuild.h"

#include <deque>

#include "brep/polyhedron_topology.h"

#include "kernel/error.h"

namespace wedge {

namespace {

// Newell's vector of the closed polygon through the origins of `sides`.
Vec3 newell(const Model& m, const std::vector<EdgeSide>& sides) {
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < sides.size(); ++i) {
    const Point3& a = m.point(m.origin(sides[i]));
    const Point3& b = m.point(m.origin(sides[(i + 1) % sides.size()]));
    n += a.cross(b);
  }
  return n;
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
  std::unordered_map<std::int32_t, FaceData> data;
  data.reserve(face_of.size());
  for (std::size_t t = 0; t < face_of.size(); ++t) {
    const auto& f = faces[t];
    Vec3 c = (points[static_cast<std::size_t>(f[1])] - points[static_cast<std::size_t>(f[0])])
                 .cross(points[static_cast<std::size_t>(f[2])] - points[static_cast<std::size_t>(f[0])]);
    data[face_of[t].value] = FaceData{mesh.face_ids[t], 0.5 * c.norm(), c, 1};
  }
  auto face = [&](EdgeSide s) { return m.loops()[m.side(s).loop].face; };

  // 1. kef across every edge between two faces of one source face.
  std::vector<EdgeId> same;  // edges with one face on both sides, for step 2
  for (EdgeId e : m.edges().ids()) {
    FaceId a = face({e, 0}), b = face({e, 1});
    FaceData& da = data.at(a.value);
    FaceData& db = data.at(b.value);
    if (da.source != db.source) continue;
    if (a == b) {
      same.push_back(e);
      continue;
    }
    bool a_smaller = da.triangles < db.triangles;
    FaceId f = a_smaller ? a : b, g = a_smaller ? b : a;
    m.kef(e, f);
    FaceData& dg = data.at(g.value);
    const FaceData& df = data.at(f.value);
    dg.area += df.area;
    dg.normal += df.normal;
    dg.triangles += df.triangles;
    data.erase(f.value);
  }

  // 2. The edges left inside a face: struts by kev (repeatedly: killing one may leave another
  // hanging), then bridges by kemr.
  std::unordered_map<std::int32_t, std::vector<EdgeId>> at;  // vertex -> its edges in `same`
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
      const Vec3& n = data.at(f.value).normal;
      if (newell(m, part1).dot(n) > newell(m, part0).dot(n)) m.reverse_edge(e);
    }
    m.kemr(e);  // leaves no strut behind: both ends keep other edges
  }

  for (const auto& [id, d] : data) {
    FaceId f(id);
    m.set_surface(f, NoSurface{});
    r.source[id] = d.source;
    r.area[id] = d.area;
  }
  Validation v = m.validate(false);
  if (!v) fail("rebuild: the rebuilt solid is not valid: ", v.message);
  return r;
}

}  // namespace wedge
