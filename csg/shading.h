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

// The corners of a triangle with parameters `uv` that lie on a pole of S (Su or Sv zero there: a
// cone's apex, a sphere's pole), as a mask (bit k: corner k); `free` is then the parameter (0: u,
// 1: v) that the first such pole leaves free. A corner on a pole stands for the whole collapsed
// row: at barycentric b in the triangle, the free parameter is the other corners' mean weighted
// by b, so that the edge from the pole to a corner follows that corner's generator line.
unsigned pole_corners(const Surface& S, const std::array<Vec2, 3>& uv, int& free);

// The parametric surface triangle t of `mesh` lies on (its face id indexing `surfaces`), or nullptr.
const Surface* parametric_surface(const Mesh& mesh, const std::vector<FaceSurface>& surfaces, std::size_t t);

// The guesses for a boolean's output triangles: corner k of output triangle t lies in triangle
// source[t] of the operand mesh `in` (whose corners have the parameters in_uv), and gets the
// parameters interpolated there by its barycentric coordinates (a source corner, its own). With
// the source's surface S given and source corners on a pole of S, the free parameter is
// interpolated as pole_corners says, so that the pieces of a pole triangle follow its generator
// lines as the whole triangle does (the pieces of sphere(1) and of a copy moved by 1e-13 differed
// by 7e-7 in volume near the poles); that guess is then refined to the parameters of the corner's
// closest point of S. So a vertex has one pair of parameters on a face whichever triangle it is a
// corner of, also where the engine made one triangle of two cut triangles of a flat quadrilateral
// (a frustum's side: extrapolated from one of the two, a corner's parameters were up to a
// segment off), and the cut vertices of two operands on one surface (a torus and its copy turned
// about the axis) have the same surface point on both.
std::array<Vec2, 3> interpolated_uv(const Mesh& in, const CornerUvs& in_uv, std::size_t source, const Mesh& out,
                                    std::size_t t, const Surface* S = nullptr);

}  // namespace wedge
