// Planar face triangulation by constrained Delaunay triangulation (CGAL's CDT_2 with exact
// predicates), after projecting the face onto the plane perpendicular to its normal. The region
// inside the face is found by the nesting-depth flood fill usual for polygons with holes: starting
// from the infinite face (depth 0), crossing a constrained edge adds one; triangles at odd depth
// are inside. No Steiner points: loops that cross make CGAL throw, reported as wedge::Error.
#include "tessellate/planar.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <deque>
#include <numeric>

#include "kernel/error.h"
#include "kernel/scaled.h"

namespace wedge {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<int, K>;  // nesting depth, -1 = unvisited
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Itag = CGAL::No_constraint_intersection_requiring_constructions_tag;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, Itag>;

}  // namespace

std::vector<Triangle> triangulate_face(const std::vector<Point3>& positions,
                                       const std::vector<std::vector<std::uint32_t>>& loops, const Vec3& normal) {
  if (!normal.allFinite() || !(normal.norm() > 0)) fail("triangulate_face: the face normal is zero or not finite");
  if (loops.empty()) fail("triangulate_face: the face has no loops");
  for (std::size_t l = 0; l < loops.size(); ++l) {
    if (loops[l].size() < 3) fail("triangulate_face: loop ", l, " has ", loops[l].size(), " vertices (3 or more needed)");
    for (auto v : loops[l])
      if (v >= positions.size()) fail("triangulate_face: loop ", l, " refers to vertex ", v, " of ", positions.size());
  }
  // Fast path: a convex-looking triangle needs no CDT.
  if (loops.size() == 1 && loops[0].size() == 3) return {Triangle{loops[0][0], loops[0][1], loops[0][2]}};

  // An orthonormal frame (u, v, n) so that (u, v) is counter-clockwise seen from n.
  Vec3 n = unit_vector(normal);
  Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  Vec3 u = n.cross(helper).normalized();
  Vec3 v = n.cross(u);

  CDT cdt;
  try {
    // Every loop's points first, in the spatial sort's order (along a loop, each new point on the
    // hull of the last ones flipped edges back to most of them: a loop of 20,000 points took a
    // second), each located from the last one's face; then the loops' edges as constraints. Where
    // points coincide, the vertex names the last of them in loop order, as when they were
    // inserted loop by loop.
    std::vector<K::Point_2> pts;
    for (const auto& loop : loops)
      for (auto idx : loop) {
        const Point3& p = positions[idx];
        pts.emplace_back(p.dot(u), p.dot(v));
      }
    std::vector<std::size_t> order(pts.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    using Traits = CGAL::Spatial_sort_traits_adapter_2<K, CGAL::Pointer_property_map<K::Point_2>::const_type>;
    CGAL::spatial_sort(order.begin(), order.end(), Traits(CGAL::make_property_map(static_cast<const std::vector<K::Point_2>&>(pts))));
    std::vector<CDT::Vertex_handle> handles(pts.size());
    CDT::Face_handle near;
    for (std::size_t i : order) {
      handles[i] = cdt.insert(pts[i], near);
      near = handles[i]->face();
    }
    std::size_t at = 0;
    for (const auto& loop : loops) {
      for (std::size_t k = 0; k < loop.size(); ++k) handles[at + k]->info() = loop[k];
      for (std::size_t k = 0; k < loop.size(); ++k) {
        auto a = handles[at + k], b = handles[at + (k + 1) % loop.size()];
        if (a != b) cdt.insert_constraint(a, b);
      }
      at += loop.size();
    }
  } catch (const std::exception&) {  // CGAL's Intersection_of_constraints_exception
    fail("triangulate_face: the face's loops cross each other or themselves");
  }

  // Nesting depth: the least number of constraints crossed to reach a face from outside.
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::deque<std::pair<CDT::Face_handle, int>> queue{{cdt.infinite_face(), 0}};
  while (!queue.empty()) {
    auto [f, depth] = queue.front();
    queue.pop_front();
    if (f->info() != -1) continue;
    f->info() = depth;
    for (int i = 0; i < 3; ++i) {
      auto g = f->neighbor(i);
      if (g->info() != -1) continue;
      // 0-1 breadth-first search: same-depth neighbours first, so each face gets its least depth.
      if (cdt.is_constrained(CDT::Edge(f, i))) queue.emplace_back(g, depth + 1);
      else queue.emplace_front(g, depth);
    }
  }
  std::vector<Triangle> out;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 != 1) continue;
    // CGAL's faces are counter-clockwise in (u, v), i.e. about n.
    out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return out;
}

}  // namespace wedge
