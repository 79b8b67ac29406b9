// The queries of a Solid (csg/solid.h) on its evaluated result: the rebuilt winged-edge solid and
// its faces, bounds, mass properties, Euler counts, validation, membership and cells. The tree's
// evaluation is in solid.cpp.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <unordered_map>

#include "csg/brep_leaf.h"
#include "csg/curved_mass.h"
#include "csg/mesh_leaf.h"
#include "csg/solid_impl.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge {

using tree_detail::child_tolerance;
using tree_detail::elapsed_ms;
using tree_detail::evaluate_root;
using tree_detail::NodePtr;
using tree_detail::transformed_box;

namespace {
// The face ids of a boolean result with the planar faces of different sources joined where they
// meet along an edge in one plane (exactly), facing the same way, with the same tag: cube(1) +
// cube(1):translate(1, 0, 0) is a 2 x 1 x 1 box of six faces, not ten (each 2 x 1 side two
// triangles, one from each cube's face). Each group takes its smallest source id; curved faces,
// and faces of different tags (colours), stay apart.
std::vector<std::int32_t> coplanar_faces_joined(const Mesh& mesh, const std::vector<std::string>& kinds, const std::vector<int>& tags) {
  std::vector<std::int32_t> ids = mesh.face_ids;
  const std::size_t nf = kinds.size();
  auto planar = [&](std::int32_t id) { return id >= 0 && static_cast<std::size_t>(id) < nf && kinds[static_cast<std::size_t>(id)] == "plane"; };
  // Each undirected edge's two triangles, by sorting (low vertex, high vertex, triangle).
  std::vector<std::array<std::uint32_t, 3>> sides;
  sides.reserve(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!planar(ids[t])) continue;
    const auto& T = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
      sides.push_back({std::min(T[k], T[(k + 1) % 3]), std::max(T[k], T[(k + 1) % 3]), static_cast<std::uint32_t>(t)});
  }
  std::sort(sides.begin(), sides.end());
  std::vector<std::int32_t> parent(nf);
  for (std::size_t i = 0; i < nf; ++i) parent[i] = static_cast<std::int32_t>(i);
  auto root = [&](std::int32_t x) {
    while (parent[static_cast<std::size_t>(x)] != x) x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  };
  bool joined = false;
  for (std::size_t i = 0, j = 0; i < sides.size(); i = j) {
    for (j = i + 1; j < sides.size() && sides[j][0] == sides[i][0] && sides[j][1] == sides[i][1];) ++j;
    if (j - i != 2) continue;  // an edge of more than two triangles (or an open one): left apart
    const auto &a = sides[i], &b = sides[i + 1];
    const std::int32_t fa = ids[a[2]], fb = ids[b[2]];
    if (fa == fb || root(fa) == root(fb)) continue;
    const int ta = static_cast<std::size_t>(fa) < tags.size() ? tags[static_cast<std::size_t>(fa)] : -1;
    const int tb = static_cast<std::size_t>(fb) < tags.size() ? tags[static_cast<std::size_t>(fb)] : -1;
    if (ta != tb) continue;
    const auto& A = mesh.triangles[a[2]];
    const auto& B = mesh.triangles[b[2]];
    const auto& P = mesh.positions;
    std::uint32_t apex = B[0];
    for (std::uint32_t v : B)
      if (v != a[0] && v != a[1]) apex = v;
    if (orient3d(P[A[0]], P[A[1]], P[A[2]], P[apex]) != 0) continue;
    const Vec3 na = (P[A[1]] - P[A[0]]).cross(P[A[2]] - P[A[0]]), nb = (P[B[1]] - P[B[0]]).cross(P[B[2]] - P[B[0]]);
    if (!(na.dot(nb) > 0)) continue;
    const std::int32_t ra = root(fa), rb = root(fb);
    parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    joined = true;
  }
  if (joined)
    for (auto& id : ids)
      if (planar(id)) id = root(id);
  return ids;
}
}  // namespace

std::shared_ptr<const RebuiltSolid> Solid::rebuilt(const Tolerance& tol) const {
  auto e = evaluate_root(node_, tol);
  std::lock_guard<std::mutex> lock(e->rebuild_mutex);
  if (!e->rebuilt) {
    auto t0 = std::chrono::steady_clock::now();
    // A boolean result is closed by its own indices, and where two of its solids share only an
    // edge or a vertex it holds one copy of each shared vertex per shell: welded by position, the
    // copies made the edge non-manifold and the rebuild failed (cube(1) + cube(1):translate(1, 1, 0)
    // was not valid, and faces() was an error). A mesh whose faces have vertices of their own (a
    // moved leaf's) is welded to be closed.
    bool closed = true;
    try {
      euler_counts(e->mesh);
    } catch (const Error&) {
      closed = false;
    }
    Mesh joined = closed ? e->mesh : e->mesh.welded();
    joined.face_ids = coplanar_faces_joined(joined, e->kinds, e->tags);
    auto r = std::make_shared<RebuiltSolid>(rebuild_brep(joined));
    // Each face carries the surface of the source face its triangles came from.
    r->model.faces().for_each([&](FaceId f, const BrepFace&) {
      const std::int32_t src = r->source.at(f.value);
      if (src >= 0 && static_cast<std::size_t>(src) < e->surfaces.size()) r->model.set_surface(f, e->surfaces[static_cast<std::size_t>(src)]);
    });
    e->rebuilt = std::move(r);
    if (const EvalControl* c = tree_detail::eval_control(); c && c->stats) c->stats->rebuild += elapsed_ms(t0);
  }
  return e->rebuilt;
}

namespace {
// An evaluated curved solid's mass properties and each triangle's share of its area
// (csg/curved_mass.h), made once and kept with it.
const MassProperties& curved_mass(Evaluated& e, const Tolerance& tol) {
  std::lock_guard<std::mutex> lock(e.mass_mutex);
  if (!e.mass) e.mass = curved_mass_properties(e.mesh, e.surfaces, e.corner_uv, tol.chordal, &e.triangle_area);
  return *e.mass;
}
}  // namespace

namespace {
// The exact area of a planar face bounded by any curves (circular arcs, splines): Green's theorem
// in the plane's frame (s, t), A = sum over its loops' sides of the integral of s dt, by a 5-point
// Gauss rule on 32 panels per curved side (a straight side's integrand is linear: one panel). Its
// triangles' area was the chord polygon's: a cylinder's cap was short of pi by 9e-5 at 0.01, and
// s:faces() did not sum to s:area(). NaN where the face has no plane.
double planar_face_area(const Model& m, FaceId f, const BrepFace& face) {
  const Plane* pl = m.surface(f).plane();
  if (!pl) return std::numeric_limits<double>::quiet_NaN();
  const Vec3 n = m.face_normal(f);
  const Point3 o = pl->origin();
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = n.cross(helper.cross(n).normalized()).cross(n).normalized(), e2 = n.cross(e1);
  static const double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  static const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                               0.2369268850561891};
  std::vector<LoopId> loops{face.outer};
  loops.insert(loops.end(), face.rings.begin(), face.rings.end());
  double area = 0;
  for (LoopId l : loops)
    for (EdgeSide sd : m.loop_sides(l)) {
      const CurvePtr c = m.edge_curve(sd.edge);
      const auto [t0, t1] = c->domain();
      const int panels = m.curve(sd.edge) ? 32 : 1;
      const double dir = sd.side == 0 ? 1.0 : -1.0, h = (t1 - t0) / panels / 2;
      for (int i = 0; i < panels; ++i) {
        const double mid = t0 + (2 * i + 1) * h;
        for (int k = 0; k < 5; ++k) {
          const double t = mid + h * gx[k];
          area += dir * gw[k] * h * (c->eval(t) - o).dot(e1) * c->derivative(t, 1).dot(e2);
        }
      }
    }
  return area;
}
}  // namespace

std::vector<SolidFace> Solid::faces(const Tolerance& tol) const {
  std::vector<SolidFace> out;
  if (empty()) return out;
  // A curved solid's faces: the areas of their surfaces (csg/curved_mass.h), summed over the
  // triangles each face has in the evaluated mesh (the flat triangles' were first-order: a
  // sphere's 2e-3 short at tolerance 1e-2).
  std::shared_ptr<Evaluated> curved;
  auto curved_areas = [&]() -> const std::vector<double>& {
    curved = evaluate_root(node_, tol);
    curved_mass(*curved, tol);
    return curved->triangle_area;
  };
  if (node_->kind == Node::Kind::Leaf)
    if (auto* b = dynamic_cast<const BrepLeaf*>(node_->leaf.get())) {
      const Model& m = b->model();
      Mesh mesh = b->mesh(tol);
      std::unordered_map<std::int32_t, double> area;
      std::unordered_map<std::int32_t, Box3> box;
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& T = mesh.triangles[t];
        area[mesh.face_ids[t]] +=
            0.5 * (mesh.positions[T[1]] - mesh.positions[T[0]]).cross(mesh.positions[T[2]] - mesh.positions[T[0]]).norm();
        for (int k = 0; k < 3; ++k) box[mesh.face_ids[t]].extend(mesh.positions[T[k]]);
      }
      if (!polyhedral()) {
        const std::vector<double>& share = curved_areas();
        if (curved->mesh.face_ids.size() == share.size()) {
          area.clear();
          for (std::size_t t = 0; t < share.size(); ++t) area[curved->mesh.face_ids[t]] += share[t];
        }
      }
      m.faces().for_each([&](FaceId f, const BrepFace& face) {
        // A plane face's area exact, as area() has it, so that the faces' areas sum to it.
        if (const double exact = planar_face_area(m, f, face); exact > 0) area[f.value] = exact;
        out.push_back({surface_kind(m.surface(f)), area[f.value], 1 + static_cast<int>(face.rings.size()), face_surface(m, f), box[f.value]});
      });
      return out;
    }
  auto e = evaluate_root(node_, tol);
  auto r = rebuilt(tol);
  std::unordered_map<std::int32_t, double> area;
  if (!polyhedral()) {
    const std::vector<double>& share = curved_areas();
    if (curved->mesh.triangles.size() == share.size() && r->triangle_face.size() == share.size())
      for (std::size_t t = 0; t < share.size(); ++t) area[r->triangle_face[t]] += share[t];
  }
  r->model.faces().for_each([&](FaceId f, const BrepFace& face) {
    std::int32_t src = r->source.at(f.value);
    std::string kind = src >= 0 && static_cast<std::size_t>(src) < e->kinds.size() ? e->kinds[static_cast<std::size_t>(src)] : "plane";
    Box3 box;
    for (VertexId v : r->model.loop_vertices(face.outer)) box.extend(r->model.point(v));
    FaceSurface geometry = r->model.surface(f);
    if (!geometry.surface) geometry = face_surface(r->model, f);
    const auto curved_area = area.find(f.value);
    out.push_back({kind, curved_area != area.end() ? curved_area->second : r->area.at(f.value), 1 + static_cast<int>(face.rings.size()),
                   std::move(geometry), box});
  });
  return out;
}

// A difference's or intersection's evaluated mesh (at the default tolerance) as bounds need it:
// its vertices, those on curved faces with the bulge of the surface past them (a triangle's
// corners lie on the surface, which bulges past it by up to the tolerance along its normal: a
// ball minus a box reached x = -0.99658 where the ball reaches -1).
struct BoundPoints {
  std::vector<Point3> flat;
  // A vertex of curved faces, and how far the surface may bulge past it along each axis (the
  // tolerance times the largest |normal| component of its triangles there): one entry a vertex,
  // not one a corner, so that a scene's turned copies each move as few points as can be.
  std::vector<std::pair<Point3, Vec3>> curved;
};

namespace {
std::shared_ptr<const BoundPoints> bound_points(const NodePtr& n) {
  {
    std::lock_guard<std::mutex> lock(n->bound_points_mutex);
    if (n->bound_points) return n->bound_points;
  }
  // Made without the lock (the evaluation may ask other nodes' bounds); two callers at once make
  // it twice, the same.
  const Tolerance tol;
  const auto e = evaluate_root(n, tol);
  const Mesh& m = e->mesh;
  auto out = std::make_shared<BoundPoints>();
  std::vector<bool> used(m.positions.size(), false);
  std::vector<Vec3> bulge(m.positions.size(), Vec3::Zero());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const std::int32_t id = t < m.face_ids.size() ? m.face_ids[t] : -1;
    const FaceSurface* fs = id >= 0 && static_cast<std::size_t>(id) < e->surfaces.size() ? &e->surfaces[static_cast<std::size_t>(id)] : nullptr;
    const bool flat = !fs || !fs->surface || fs->plane();
    const Vec3 grow = flat ? Vec3::Zero() : Vec3(tol.chordal * m.triangle_normal(t).cwiseAbs());
    for (std::uint32_t v : m.triangles[t]) {
      used[v] = true;
      bulge[v] = bulge[v].cwiseMax(grow);
    }
  }
  for (std::size_t v = 0; v < m.positions.size(); ++v) {
    if (!used[v]) continue;
    if (bulge[v].isZero(0)) out->flat.push_back(m.positions[v]);
    else out->curved.emplace_back(m.positions[v], bulge[v]);
  }
  std::lock_guard<std::mutex> lock(n->bound_points_mutex);
  if (!n->bound_points) n->bound_points = std::move(out);
  return n->bound_points;
}

// Whether m moves a box to a box (each row of its linear part has at most one non-zero entry:
// translations, scales, mirrors and quarter turns about the axes), so that the moved box is tight.
bool keeps_boxes(const Mat4& m) {
  for (int r = 0; r < 3; ++r)
    if ((m(r, 0) != 0) + (m(r, 1) != 0) + (m(r, 2) != 0) > 1) return false;
  return true;
}
}  // namespace

Box3 Solid::bounds() const { return bounds(Mat4::Identity()); }

Box3 Solid::bounds(const Mat4& placement) const {
  // Each (node, placement) once (see loose_bounds). A placement that keeps boxes is applied to the
  // node's own box; any other is carried down to the leaves and the evaluated booleans, whose
  // points it moves: a turned box of a boolean result was 41-65 % too large (a torus cut by a box
  // and turned 45 degrees reached 3.54 where its mesh reaches 2.5).
  std::map<std::pair<const Node*, std::array<double, 12>>, Box3> memo;
  std::function<Box3(const NodePtr&, const Mat4&)> of = [&](const NodePtr& n, const Mat4& m) -> Box3 {
    const bool boxes = keeps_boxes(m);
    if (boxes && !m.isIdentity(0)) return transformed_box(of(n, Mat4::Identity()), m);
    std::array<double, 12> key;
    for (int i = 0; i < 12; ++i) key[static_cast<std::size_t>(i)] = m(i / 4, i % 4);
    if (auto it = memo.find({n.get(), key}); it != memo.end()) return it->second;
    Box3 out;
    switch (n->kind) {
      case Node::Kind::Empty: break;
      case Node::Kind::Leaf:
        // A leaf moved exactly where it can move itself (a turned sphere: its own box); else a
        // polyhedral one by its moved vertices, and the rest by its moved box.
        if (boxes) out = n->leaf->bounds();
        else if (const auto moved = n->leaf->transformed(m)) out = moved->bounds();
        else if (n->leaf->polyhedral())
          for (const Point3& p : n->leaf->mesh(Tolerance{}).positions) out.extend(apply_point(m, p));
        else out = transformed_box(n->leaf->bounds(), m);
        break;
      case Node::Kind::Transform: out = of(n->child, Mat4(m * n->matrix)); break;
      case Node::Kind::Boolean: {
        // Bounds of the operands that can contribute (exact bounds need the evaluated mesh).
        if (n->op == BooleanOp::Union) {
          n->for_each_operand([&](const NodePtr& o) { out.extend(of(o, m)); });
          break;
        }
        // The evaluated mesh's points, moved, each on a curved face grown by its bulge; then, on
        // the axes, cut to what bounds the result: the first operand of a difference, every
        // operand of an intersection. (Turned, the cut would move every operand: a turned copy of
        // a sphere's B-Rep is bounded by sampling its curves, which took most of the time of a
        // radial array's bounds; the points alone are within the tolerance.)
        const auto points = bound_points(n);
        // |A| times the bulge along the axes bounds the bulge moved by A (on the axes: itself).
        const Mat3 abs_a = m.block<3, 3>(0, 0).cwiseAbs();
        for (const Point3& p : points->flat) out.extend(apply_point(m, p));
        for (const auto& [p, bulge] : points->curved) {
          const Point3 q = apply_point(m, p);
          const Vec3 grow = abs_a * bulge;
          out.extend(Vec3(q - grow));
          out.extend(Vec3(q + grow));
        }
        bool first = true;
        if (boxes)
          n->for_each_operand([&](const NodePtr& o) {
            if (!first && n->op == BooleanOp::Difference) return;
            first = false;
            const Box3 b = of(o, m);
            out.min = out.min.cwiseMax(b.min);
            out.max = out.max.cwiseMin(b.max);
          });
        if (out.empty()) out = Box3();
        break;
      }
    }
    memo.emplace(std::make_pair(n.get(), key), out);
    return out;
  };
  return of(node_, placement);
}

namespace {
// A leaf whose surface crosses itself or holds shells that overlap (SolidLeaf::solid_defect) has
// no volume or inside to speak of: an imported pair of overlapping cubes summed to 2 where the
// region they bound is 1.875, and a point inside both was "outside".
void require_solid(const Solid::Node& n) {
  if (n.kind == Solid::Node::Kind::Leaf)
    if (std::string d = n.leaf->solid_defect(); !d.empty()) fail("not a solid: ", d);
}
}  // namespace

MassProperties Solid::mass_properties(const Tolerance& tol) const {
  require_solid(*node_);
  if (node_->kind == Node::Kind::Leaf)
    if (auto mp = node_->leaf->mass_properties()) return *mp;
  if (empty() || polyhedral()) return wedge::mass_properties(mesh(tol));
  // Curved: the mesh and, under each curved triangle, the region up to its surface (csg/curved_mass.h).
  return curved_mass(*evaluate_root(node_, tol), tol);
}

EulerCounts Solid::euler(const Tolerance& tol) const {
  if (node_->kind == Node::Kind::Empty) return EulerCounts();
  if (node_->kind == Node::Kind::Leaf) {
    if (auto c = node_->leaf->euler()) return *c;
    return euler_counts(mesh(tol));
  }
  if (node_->kind == Node::Kind::Transform) return Solid(node_->child).euler(child_tolerance(*node_, tol));
  // A boolean: the counts of its rebuilt winged-edge solid (faces merged back by source face).
  auto r = rebuilt(tol);
  return r->model.counts();
}

std::string Solid::validate(const Tolerance& tol) const {
  switch (node_->kind) {
    case Node::Kind::Empty: return "";
    case Node::Kind::Leaf: return node_->leaf->validate();
    case Node::Kind::Transform: return Solid(node_->child).validate(child_tolerance(*node_, tol));
    case Node::Kind::Boolean: {
      auto e = evaluate_root(node_, tol);
      if (e->mesh.empty()) return "";
      std::string d = mesh_solid_defect(e->mesh, "boolean result");
      if (!d.empty()) return d;
      try {
        auto r = rebuilt(tol);
        Validation v = r->model.validate(false);
        if (!v) return "boolean result's rebuilt B-Rep: " + v.message;
      } catch (const Error& err) {
        return std::string("boolean result: ") + err.what();
      }
      return "";
    }
  }
  return "";
}

bool Solid::polyhedral() const {
  std::unordered_map<const Node*, bool> memo;  // each node once (see loose_bounds)
  std::function<bool(const NodePtr&)> of = [&](const NodePtr& n) {
    if (auto it = memo.find(n.get()); it != memo.end()) return it->second;
    bool out = true;
    switch (n->kind) {
      case Node::Kind::Empty: break;
      case Node::Kind::Leaf: out = n->leaf->polyhedral(); break;
      case Node::Kind::Transform: out = of(n->child); break;
      case Node::Kind::Boolean: n->for_each_operand([&](const NodePtr& o) { out = out && of(o); }); break;
    }
    memo.emplace(n.get(), out);
    return out;
  };
  return of(node_);
}

Membership Solid::contains(const Point3& p, const Tolerance& tol) const {
  if (!p.allFinite()) fail("contains: the point (", p.x(), ", ", p.y(), ", ", p.z(), ") is not finite");
  if (empty()) return Membership::Outside;
  require_solid(*node_);
  // The evaluated mesh, kept per tolerance like every other query's: mesh() tessellates a leaf
  // afresh, and sphere(1000) at tolerance 0.001 spent 15 s and 2 GB on each contains() call.
  return classify_point(evaluate_root(node_, tol)->mesh, p, polyhedral() ? 0.0 : tol.chordal);
}

CellDecomposition Solid::cells(double size, const Tolerance& tol) const {
  if (!(size > 0) || !std::isfinite(size)) fail("cells: size must be a positive number, got ", size);
  if (empty()) return CellDecomposition();
  require_solid(*node_);
  return decompose_cells(evaluate_root(node_, tol)->mesh, size, polyhedral() ? 0.0 : tol.chordal);
}

}  // namespace wedge
