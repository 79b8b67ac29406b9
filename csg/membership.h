// Point-membership classification and octree cell decomposition of a closed triangle mesh
// (Requicha's point membership and the course's cell-decomposition scheme).
//
// Method. A point on a triangle (exact point-in-closed-triangle test) is on the boundary.
// Otherwise a ray from the point to a far point beyond the bounds is cast and its proper
// crossings counted: with s_p, s_q the orient3d signs of the ray's ends against the triangle's
// plane and o_ab, o_bc, o_ca the signs of the ray against its edges, a crossing is
// s_p = -s_q != 0 with o_ab = o_bc = o_ca != 0, all decided exactly (kernel/predicates.h). A
// ray through an edge or a vertex (some sign zero where it matters) is thrown away and another
// direction tried, so the parity decides exactly for the polyhedron the mesh describes.
//
// The octree splits the mesh's bounds (inflated by a margin) until a cell's longest side is at
// most `size`; a cell that no triangle touches (box-triangle separating-axis test on the cell
// inflated by the margin, so a near miss counts as a touch) is wholly inside or wholly outside,
// decided at its centre by a segment from its parent's centre, whose crossings can only be with
// the parent's triangles. volume_min (inside cells) and volume_max (inside + boundary cells)
// then bracket the volume of any surface within `margin` of the mesh.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "kernel/mesh.h"

namespace wedge {

// How segment p-q meets triangle (a, b, c), decided exactly: +1 where it passes through the
// triangle's interior from behind (orient3d(a, b, c, p) < 0: the solid side of an outward
// triangle) to in front, -1 the other way, 0 where it misses, nullopt where it touches an edge or
// a vertex or lies in the plane where it meets it. (Summed over a closed surface from p: the
// winding number at p.)
std::optional<int> segment_crossing(const Point3& p, const Point3& q, const Point3& a, const Point3& b, const Point3& c);

enum class Membership { Outside, Inside, Boundary };
const char* membership_name(Membership m);  // "outside" | "inside" | "boundary"

// Where p lies with respect to the closed, outward-oriented mesh. `boundary_distance` > 0 also
// calls a point boundary when it is that close to a triangle (for a mesh that stands for a
// curved surface within that distance); 0 gives the exact answer for the mesh itself.
Membership classify_point(const Mesh& mesh, const Point3& p, double boundary_distance = 0);

struct Cell {
  Box3 box;
  Membership state = Membership::Outside;
};

struct CellDecomposition {
  long inside = 0, boundary = 0, outside = 0;  // counts of leaf cells of the octree
  double volume_min = 0;                       // total volume of the inside cells
  double volume_max = 0;                       // inside + boundary cells
  std::vector<Cell> cells;                     // every leaf cell
};

// The octree decomposition down to cells of longest side <= size. `margin` >= 0 widens what
// counts as touching the boundary (the chordal tolerance of a curved solid's mesh). Throws if
// size is not positive or the decomposition would exceed `max_cells` leaf cells.
CellDecomposition decompose_cells(const Mesh& mesh, double size, double margin = 0,
                                  std::size_t max_cells = 4'000'000);

}  // namespace wedge
