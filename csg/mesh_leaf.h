// A closed triangle mesh as a leaf of the CSG tree (MeshLeaf, declared in csg/solid.h): its
// checks, the faces a mesh without face ids is given, and the triangle budget of meshes made.
#pragma once
#include <cstddef>
#include <vector>

#include "csg/solid.h"

namespace wedge {

// Face ids for a mesh without its own: the connected regions of exactly coplanar, like-facing
// triangles (orient3d of the neighbour's far corner is zero). Returns the region count; `planes`
// gets each region's plane (its first triangle's).
std::size_t planar_regions(Mesh& mesh, std::vector<FaceSurface>& planes);

// The triangle budget (Tolerance::max_triangles) on a mesh handed out: also a result kept from an
// evaluation under a larger budget, an imported mesh, a tessellation above its estimate.
void check_triangle_budget(std::size_t triangles, const Tolerance& tol);
inline Mesh within_triangle_budget(Mesh mesh, const Tolerance& tol) {
  check_triangle_budget(mesh.triangles.size(), tol);
  return mesh;
}
// Before a boolean runs: its result holds about its operands' triangles (more where their surfaces
// cross, fewer where parts fall away), so their sum is the estimate checked against the budget.
void check_boolean_budget(BooleanOp op, const std::vector<const Mesh*>& operands, std::size_t max_triangles);

}  // namespace wedge
