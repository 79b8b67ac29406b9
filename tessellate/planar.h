// Triangulation of planar faces with holes, for tessellating B-Rep faces. Vertices are given as
// indices into a shared position array, and the triangles use those same indices: two faces that
// share an edge share its vertices, so a solid tessellated face by face is watertight by
// construction (no new points are inserted).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "kernel/mesh.h"
#include "kernel/types.h"

namespace wedge {

using Triangle = std::array<std::uint32_t, 3>;

// loops[0] is the outer boundary (counter-clockwise seen from the side `normal` points to), the
// others are holes (clockwise). Returns triangles counter-clockwise about `normal`, covering the
// region inside the outer loop and outside every hole. Uses a constrained Delaunay triangulation
// of the loops projected onto the face's plane. Throws wedge::Error if a loop has fewer than three
// vertices, the loops cross each other, or the normal is zero.
std::vector<Triangle> triangulate_face(const std::vector<Point3>& positions,
                                       const std::vector<std::vector<std::uint32_t>>& loops, const Vec3& normal);

// (Newell's normal of a loop, newell_normal, is in kernel/mesh.h.)

}  // namespace wedge
