// Shading attributes from the exact geometry: a solid's triangle mesh made ready for rendering and
// export, with each vertex's normal taken from the surface of the face it lies on (the source
// surface of a boolean result's face), never averaged from the triangles, and its uv from that
// surface's parameters.
//
// Method. Vertices are split per face (a box's corner is three vertices, one per face), and on a
// parametric face also where the parameters jump (a seam, a pole). The parameters of a vertex on a
// parametric face start from a guess (the tessellator's own (u, v) for a leaf's vertex; for a vertex
// a boolean made, the guess interpolated in the source triangle it lies in) and are refined by
// Gauss-Newton steps to the closest point of the surface: a boolean's new vertex lies on a facet,
// within the tolerance of the surface, and the normal at its closest point is the exact one (for a
// sphere, the radial direction through it). Planes and the planar builders' cylinders have their
// normals in closed form; their uv are coordinates in the plane and (angle, height).
#pragma once
#include <array>
#include <vector>

#include "brep/brep.h"
#include "kernel/mesh.h"

namespace wedge {

// Per triangle, the (u, v) of its three corners on its parametric face's surface; NaN where unknown.
using CornerUvs = std::vector<std::array<Vec2, 3>>;

// The parameters of the point of S closest to p, from `guess` (clamped to the domain); without a
// finite guess, from the nearest point of a 16 x 16 grid of samples.
Vec2 closest_parameters(const Surface& S, const Point3& p, const Vec2& guess);

// `mesh` (face ids indexing `surfaces`) split per face, with outward unit normals from the
// surfaces and uvs from their parameters; face ids kept. `corner_uv`: empty, or one per triangle.
Mesh shaded_mesh(const Mesh& mesh, const std::vector<FaceSurface>& surfaces, const CornerUvs& corner_uv);

// The guesses for a boolean's output triangles: corner k of output triangle t lies in triangle
// source[t] of the operand mesh `in` (whose corners have the parameters in_uv), and gets the
// parameters interpolated there by its barycentric coordinates.
std::array<Vec2, 3> interpolated_uv(const Mesh& in, const CornerUvs& in_uv, std::size_t source, const Mesh& out,
                                    std::size_t t);

}  // namespace wedge
