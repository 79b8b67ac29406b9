// CGAL, exact constructions (Epeck: lazy exact numbers over a filtered interval), for the oracle.
// Every quantity here is exact until the one rounding of a volume to double at the end.
#include "tests/support/cgal_oracle.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace wedge::testing {

namespace {
using K = CGAL::Exact_predicates_exact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

// The mesh's vertices and triangles as given (vertex i of the mesh is vertex i of the result).
// Fails with a reason when Surface_mesh cannot hold it (a non-manifold vertex or edge).
bool to_surface_mesh(const Mesh& m, SM& out, std::string* why) {
  out.clear();
  out.reserve(static_cast<SM::size_type>(m.positions.size()), static_cast<SM::size_type>(3 * m.triangles.size() / 2),
              static_cast<SM::size_type>(m.triangles.size()));
  for (const auto& p : m.positions) out.add_vertex(K::Point_3(p.x(), p.y(), p.z()));
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    if (tri[0] >= m.positions.size() || tri[1] >= m.positions.size() || tri[2] >= m.positions.size()) {
      if (why) *why = "triangle " + std::to_string(t) + " has a vertex index out of range";
      return false;
    }
    const auto f = out.add_face(SM::Vertex_index(tri[0]), SM::Vertex_index(tri[1]), SM::Vertex_index(tri[2]));
    if (f == SM::null_face()) {
      if (why) *why = "triangle " + std::to_string(t) + " cannot join the surface (non-manifold edge or vertex)";
      return false;
    }
  }
  return true;
}

bool apply(BooleanOp op, SM& a, SM& b, SM& out) {
  switch (op) {
    case BooleanOp::Union: return PMP::corefine_and_compute_union(a, b, out);
    case BooleanOp::Intersection: return PMP::corefine_and_compute_intersection(a, b, out);
    case BooleanOp::Difference: return PMP::corefine_and_compute_difference(a, b, out);
  }
  return false;
}

// Volumes are summed in the exact number type itself (Epeck's FT::ET, a rational), not in lazy
// numbers: a sum of a million lazy terms is a DAG a million deep, and evaluating it overflows the
// stack; and a lazy number's to_double is its interval's estimate, not the exact value rounded.
using ET = K::FT::ET;

ET det(const ET& ax, const ET& ay, const ET& az, const ET& bx, const ET& by, const ET& bz, const ET& cx,
       const ET& cy, const ET& cz) {
  return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

double exact_volume_of(const SM& sm) {
  ET v = 0;
  for (auto f : sm.faces()) {
    const auto h = sm.halfedge(f);
    const auto& a = sm.point(sm.target(h));
    const auto& b = sm.point(sm.target(sm.next(h)));
    const auto& c = sm.point(sm.target(sm.next(sm.next(h))));
    v += det(CGAL::exact(a.x()), CGAL::exact(a.y()), CGAL::exact(a.z()), CGAL::exact(b.x()), CGAL::exact(b.y()),
             CGAL::exact(b.z()), CGAL::exact(c.x()), CGAL::exact(c.y()), CGAL::exact(c.z()));
  }
  return CGAL::to_double(v / 6);
}

OracleResult run(const Mesh& first, const std::vector<std::pair<BooleanOp, const Mesh*>>& steps) {
  OracleResult r;
  try {
    SM current;
    std::string why;
    if (!to_surface_mesh(first, current, &why)) {
      r.why = "operand 0: " + why;
      return r;
    }
    for (std::size_t k = 0; k < steps.size(); ++k) {
      SM b, out;
      if (!to_surface_mesh(*steps[k].second, b, &why)) {
        r.why = "operand " + std::to_string(k + 1) + ": " + why;
        return r;
      }
      if (!apply(steps[k].first, current, b, out)) {
        r.why = std::string("CGAL refused step ") + std::to_string(k + 1) + " (" + boolean_op_name(steps[k].first) +
                "): the result is not a 2-manifold";
        return r;
      }
      current = std::move(out);
    }
    r.volume = exact_volume_of(current);
    r.triangles = current.number_of_faces();
    r.ok = true;
  } catch (const std::exception& e) {
    r.why = std::string("CGAL threw: ") + e.what();
  }
  return r;
}

std::string point_text(const K::Point_3& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << CGAL::to_double(p.x()) << ", " << CGAL::to_double(p.y()) << ", " << CGAL::to_double(p.z()) << ")";
  return s.str();
}
}  // namespace

OracleResult oracle_boolean(BooleanOp op, const Mesh& a, const Mesh& b) { return run(a, {{op, &b}}); }

OracleResult oracle_sequence(const Mesh& first, const std::vector<std::pair<BooleanOp, const Mesh*>>& steps) {
  return run(first, steps);
}

OracleResult oracle_nary(BooleanOp op, const std::vector<const Mesh*>& operands) {
  std::vector<std::pair<BooleanOp, const Mesh*>> steps;
  for (std::size_t k = 1; k < operands.size(); ++k) steps.push_back({op, operands[k]});
  return run(*operands.at(0), steps);
}

double exact_volume(const Mesh& m) {
  ET v = 0;
  for (const auto& t : m.triangles) {
    const auto& a = m.positions[t[0]];
    const auto& b = m.positions[t[1]];
    const auto& c = m.positions[t[2]];
    v += det(ET(a.x()), ET(a.y()), ET(a.z()), ET(b.x()), ET(b.y()), ET(b.z()), ET(c.x()), ET(c.y()), ET(c.z()));
  }
  return CGAL::to_double(v / 6);
}

double exact_plane_distance(const Point3& a, const Point3& b, const Point3& c, const Point3& p) {
  auto v = [](const Point3& x, const Point3& o) {
    return std::array<ET, 3>{ET(x.x()) - ET(o.x()), ET(x.y()) - ET(o.y()), ET(x.z()) - ET(o.z())};
  };
  const auto u = v(b, a), w = v(c, a), q = v(p, a);
  const std::array<ET, 3> n{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  const ET d = n[0] * q[0] + n[1] * q[1] + n[2] * q[2];
  const ET nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  if (nn == 0) return 0;
  return std::sqrt(CGAL::to_double(d * d / nn));
}

bool exact_self_intersects(const Mesh& m, std::string* where) {
  SM sm;
  std::string why;
  if (!to_surface_mesh(m, sm, &why)) {
    if (where) *where = why;
    return true;
  }
  std::vector<std::pair<SM::Face_index, SM::Face_index>> pairs;
  PMP::self_intersections(sm, std::back_inserter(pairs));
  auto triangle = [&](SM::Face_index f) {
    const auto h = sm.halfedge(f);
    return K::Triangle_3(sm.point(sm.target(h)), sm.point(sm.target(sm.next(h))),
                         sm.point(sm.target(sm.next(sm.next(h)))));
  };
  auto describe = [&](SM::Face_index f) {
    const auto t = triangle(f);
    return "triangle " + std::to_string(static_cast<std::size_t>(f)) + " " + point_text(t[0]) + " " +
           point_text(t[1]) + " " + point_text(t[2]);
  };
  for (const auto& [f, g] : pairs) {
    if (f == g) {
      if (where) *where = "degenerate " + describe(f);
      return true;
    }
    const K::Triangle_3 tf = triangle(f), tg = triangle(g);
    // The positions the two triangles have in common.
    std::vector<K::Point_3> shared;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (tf[i] == tg[j] && std::find(shared.begin(), shared.end(), tf[i]) == shared.end()) shared.push_back(tf[i]);
    bool fine = false;
    if (!shared.empty() && shared.size() < 3) {
      const auto inter = CGAL::intersection(tf, tg);
      auto is_shared = [&](const K::Point_3& p) { return std::find(shared.begin(), shared.end(), p) != shared.end(); };
      if (!inter) {
        fine = true;
      } else if (const K::Point_3* p = boost::get<K::Point_3>(&*inter)) {
        fine = is_shared(*p);
      } else if (const K::Segment_3* s = boost::get<K::Segment_3>(&*inter)) {
        fine = is_shared(s->source()) && is_shared(s->target());
      }
    }
    if (!fine) {
      if (where) *where = describe(f) + " meets " + describe(g);
      return true;
    }
  }
  return false;
}

}  // namespace wedge::testing
