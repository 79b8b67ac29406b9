#include "csg/brep_leaf.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "tessellate/planar.h"

namespace wedge {

BrepLeaf::BrepLeaf(Model model) {
  Validation v = model.validate();
  if (!v) fail("not a valid solid: ", v.message);
  model_ = std::make_shared<const Model>(std::move(model));
}

Solid brep_solid(Model model) { return Solid(std::make_shared<const BrepLeaf>(std::move(model))); }

std::optional<MassProperties> BrepLeaf::mass_properties() const {
  if (!model_->all_planar()) return std::nullopt;
  BrepMass b = model_->mass_properties();
  MassProperties mp;
  mp.volume = b.volume;
  mp.area = b.area;
  mp.centroid = b.centroid;
  mp.inertia = b.inertia;
  return mp;
}

std::shared_ptr<const SolidLeaf> BrepLeaf::transformed(const Mat4& m) const {
  Model copy = *model_;
  try {
    copy.transform(m);
  } catch (const Error&) {
    return nullptr;  // e.g. a non-uniform scale of arcs: the Solid transforms the mesh instead
  }
  return std::make_shared<const BrepLeaf>(std::move(copy));
}

Mesh BrepLeaf::mesh(const Tolerance& tol) const {
  const Model& m = *model_;
  Mesh out;
  std::unordered_map<std::int32_t, std::uint32_t> vindex;
  m.vertices().for_each([&](VertexId v, const BrepVertex&) { vindex[v.value] = out.add_vertex(m.point(v)); });
  // Arc samples per edge, shared by the two faces of the edge.
  std::unordered_map<std::int32_t, std::vector<std::uint32_t>> inner;  // from v[0] to v[1], exclusive
  auto segments = [&](EdgeId e) {
    const auto* arc = std::get_if<ArcCurve>(&m.curve(e));
    if (!arc) return 1;
    double r = arc->radius, c = std::max(tol.chordal, 1e-9 * r);
    double step = c >= r ? kPi / 2 : 2 * std::acos(1 - c / r);
    step = std::min(step, radians(tol.angular));
    Vec3 x = m.point(m.edges()[e].v[0]) - arc->center, y = m.point(m.edges()[e].v[1]) - arc->center;
    double sweep = std::atan2(arc->axis.dot(x.cross(y)), x.dot(y));
    if (sweep <= 1e-12) sweep += 2 * kPi;
    return std::clamp(static_cast<int>(std::ceil(sweep / step)), 2, 1024);
  };
  m.edges().for_each([&](EdgeId e, const BrepEdge&) {
    int n = segments(e);
    if (n == 1) return;
    std::vector<Point3> p = m.side_polyline(EdgeSide{e, 0}, n);
    auto& ids = inner[e.value];
    for (std::size_t i = 1; i + 1 < p.size(); ++i) ids.push_back(out.add_vertex(p[i]));
  });
  auto side_indices = [&](EdgeSide s) {  // start .. end inclusive
    const BrepEdge& ed = m.edges()[s.edge];
    std::vector<std::uint32_t> r{vindex.at(ed.v[0].value)};
    if (auto it = inner.find(s.edge.value); it != inner.end()) r.insert(r.end(), it->second.begin(), it->second.end());
    r.push_back(vindex.at(ed.v[1].value));
    if (s.side == 1) std::reverse(r.begin(), r.end());
    return r;
  };
  m.faces().for_each([&](FaceId f, const BrepFace& face) {
    if (std::holds_alternative<CylinderSurface>(m.surface(f))) {
      auto sides = m.loop_sides(face.outer);
      if (sides.size() != 4 || !face.rings.empty()) fail("mesh: cylinder face ", f.value, " is not bounded by two arcs and two lines");
      int k = std::holds_alternative<ArcCurve>(m.curve(sides[0].edge)) ? 0 : 1;
      auto a = side_indices(sides[static_cast<std::size_t>(k)]);
      auto b = side_indices(sides[static_cast<std::size_t>(k + 2)]);
      if (a.size() != b.size()) fail("mesh: cylinder face ", f.value, " has arcs of different lengths");
      std::reverse(b.begin(), b.end());
      for (std::size_t i = 0; i + 1 < a.size(); ++i) {
        out.add_triangle(a[i], a[i + 1], b[i + 1], f.value);
        out.add_triangle(a[i], b[i + 1], b[i], f.value);
      }
      return;
    }
    std::vector<std::vector<std::uint32_t>> loops;
    std::vector<LoopId> ls{face.outer};
    ls.insert(ls.end(), face.rings.begin(), face.rings.end());
    for (LoopId l : ls) {
      std::vector<std::uint32_t> idx;
      for (EdgeSide s : m.loop_sides(l)) {
        auto r = side_indices(s);
        idx.insert(idx.end(), r.begin(), r.end() - 1);
      }
      loops.push_back(std::move(idx));
    }
    for (const auto& t : triangulate_face(out.positions, loops, m.face_normal(f))) out.add_triangle(t[0], t[1], t[2], f.value);
  });
  return out;
}

}  // namespace wedge
