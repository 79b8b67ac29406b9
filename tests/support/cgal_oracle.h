// The independent references the boolean engine is judged by: CGAL's corefinement with exact
// constructions (Epeck) for volumes, CGAL's exact self-intersection test for results, and a plain
// combinatorial check of closedness, manifoldness and orientation. CGAL stays inside
// cgal_oracle.cpp; this header is plain.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "csg/csg.h"
#include "kernel/mesh.h"

namespace wedge::testing {

struct OracleResult {
  bool ok = false;       // false: CGAL refused (non-manifold result, bad input) or threw
  double volume = 0;     // the exact volume of CGAL's exact result, rounded once to double
  std::size_t triangles = 0;
  std::string why;       // when !ok
};

// PMP::corefine_and_compute_union / _intersection / _difference on Surface_mesh<Epeck::Point_3>.
OracleResult oracle_boolean(BooleanOp op, const Mesh& a, const Mesh& b);
// first op1 m1 op2 m2 ..., each step on the exact result of the one before (no rounding between).
OracleResult oracle_sequence(const Mesh& first, const std::vector<std::pair<BooleanOp, const Mesh*>>& steps);
// The n-ary operation as the engine defines it: union or intersection of all, or the first minus
// the rest, folded left to right in exact arithmetic.
OracleResult oracle_nary(BooleanOp op, const std::vector<const Mesh*>& operands);

// The signed volume of the mesh's doubles computed exactly (Epeck), rounded once.
double exact_volume(const Mesh& m);

// The distance of p from the plane through a, b, c, computed exactly and rounded once (a sliver
// triangle's plane is too ill-conditioned for floating point, even long double).
double exact_plane_distance(const Point3& a, const Point3& b, const Point3& c, const Point3& p);

// "" when the mesh is closed, 2-manifold and consistently oriented outward, else the first defect
// with its place: an index out of range or a repeated index in a triangle, a border edge, an edge
// with more than two triangles, two triangles using an edge in the same direction, a vertex whose
// triangles form more than one fan, a non-positive volume. Judged by vertex index, so shells that
// touch at distinct vertices of equal position (how a non-manifold regularised result comes back)
// are fine. An empty mesh is fine (the empty solid).
std::string closed_manifold_outward(const Mesh& m);

// True when two triangles of the mesh (as its doubles say) meet anywhere but in a vertex or an
// edge they share, or a triangle is degenerate (zero area): PMP::self_intersections with Epeck,
// exact. Vertices are shared by position: two triangles of shells that touch at coincident but
// distinct vertices may meet exactly there, in those points or the segment between them, and
// nowhere else. `where`, if given, receives the first offending pair with coordinates.
bool exact_self_intersects(const Mesh& m, std::string* where = nullptr);

// Shells that touch along an edge (their vertices there distinct but of equal position) and
// overlap in the wedge between two of their triangles, though no two triangles cross: about
// such an edge the triangles, in exact order, do not run alternately to and from one end, or two
// lie in one half-plane. "" where there is none, else the edge.
std::string folded_touching_edge(const Mesh& m);

// Shells (components by vertex index) that overlap with no two triangles crossing: one inside
// another facing the same way, or a hollow (a shell facing inward) in no solid. Judged by the
// winding number of the other shells at a vertex of each that no other shell holds (exact, along
// a segment): 0 beside an outward shell, 1 beside an inward one. "" where there is none.
std::string nested_shells(const Mesh& m);

// "" for a valid result (closed_manifold_outward, no exact self-intersection, no folded touching
// edge, no nested shells), else the first defect with its place.
std::string result_defect(const Mesh& m);

}  // namespace wedge::testing
