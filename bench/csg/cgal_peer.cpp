// CGAL corefinement as bench_boolean's peer, with the inexact-constructions kernel (Epick: filtered
// predicates, double constructions) and the exact one (Epeck), in the same process as wedge.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Surface_mesh.h>

#include "bench/csg/recipe.h"

namespace wedge::bench {

namespace {
namespace PMP = CGAL::Polygon_mesh_processing;

template <class K>
struct Cgal {
  using SM = CGAL::Surface_mesh<typename K::Point_3>;

  static SM from(const Mesh& m) {
    SM sm;
    sm.reserve(static_cast<typename SM::size_type>(m.positions.size()),
               static_cast<typename SM::size_type>(3 * m.triangles.size() / 2),
               static_cast<typename SM::size_type>(m.triangles.size()));
    for (const auto& p : m.positions) sm.add_vertex(typename K::Point_3(p.x(), p.y(), p.z()));
    for (const auto& t : m.triangles)
      if (sm.add_face(typename SM::Vertex_index(t[0]), typename SM::Vertex_index(t[1]),
                      typename SM::Vertex_index(t[2])) == SM::null_face())
        throw std::runtime_error("an operand is not a 2-manifold surface");
    return sm;
  }

  static Mesh to(SM& sm) {
    sm.collect_garbage();
    Mesh m;
    m.positions.reserve(sm.number_of_vertices());
    for (auto v : sm.vertices()) {
      const auto& p = sm.point(v);
      m.positions.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    }
    m.triangles.reserve(sm.number_of_faces());
    for (auto f : sm.faces()) {
      auto h = sm.halfedge(f);
      m.triangles.push_back({static_cast<std::uint32_t>(sm.target(h)), static_cast<std::uint32_t>(sm.target(sm.next(h))),
                             static_cast<std::uint32_t>(sm.target(sm.next(sm.next(h))))});
    }
    return m;
  }

  static bool apply(BooleanOp op, SM& a, SM& b, SM& out) {
    switch (op) {
      case BooleanOp::Union: return PMP::corefine_and_compute_union(a, b, out);
      case BooleanOp::Intersection: return PMP::corefine_and_compute_intersection(a, b, out);
      case BooleanOp::Difference: return PMP::corefine_and_compute_difference(a, b, out);
    }
    return false;
  }

  // Pairwise, as a balanced tree.
  static SM reduce(BooleanOp op, std::vector<SM> items) {
    while (items.size() > 1) {
      std::vector<SM> next;
      for (std::size_t i = 0; i + 1 < items.size(); i += 2) {
        SM out;
        if (!apply(op, items[i], items[i + 1], out)) throw std::runtime_error("CGAL refused (non-manifold result)");
        next.push_back(std::move(out));
      }
      if (items.size() % 2) next.push_back(std::move(items.back()));
      items = std::move(next);
    }
    return std::move(items.front());
  }

  static PeerRun run(const std::vector<Mesh>& operands, const Recipe& recipe) {
    PeerRun r;
    try {
      SM previous;
      for (const Step& s : recipe) {
        std::vector<SM> in;
        for (int i : s.inputs) in.push_back(i < 0 ? previous : from(operands.at(i)));
        if (s.op == BooleanOp::Difference && in.size() > 2) {
          SM first = std::move(in.front());
          in.erase(in.begin());
          SM rest = reduce(BooleanOp::Union, std::move(in));
          in.clear();
          in.push_back(std::move(first));
          in.push_back(std::move(rest));
        }
        previous = reduce(s.op, std::move(in));
      }
      r.mesh = to(previous);
      r.ok = true;
    } catch (const std::exception& e) {
      r.why = e.what();
    }
    return r;
  }
};
}  // namespace

PeerRun cgal_recipe(CgalKernel kernel, const std::vector<Mesh>& operands, const Recipe& recipe) {
  if (kernel == CgalKernel::Epick) return Cgal<CGAL::Exact_predicates_inexact_constructions_kernel>::run(operands, recipe);
  return Cgal<CGAL::Exact_predicates_exact_constructions_kernel>::run(operands, recipe);
}

}  // namespace wedge::bench
