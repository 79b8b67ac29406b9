// B-Rep -> Mesh: the one tessellator of solids. Every edge is discretised once, to the chordal
// and angular tolerance, and both of its faces use exactly those points, so the mesh is watertight
// by construction. Planar faces are triangulated in their plane; parametric faces in their
// (u, v) domain by CGAL's constrained Delaunay triangulation (loops, seams and poles as
// constraints), refined until the chordal and angular tolerances hold inside the face. Triangles
// carry their source face id; a pole is one vertex, and no triangle has zero area from it.
#pragma once
#include <array>
#include <vector>

#include "brep/brep.h"

namespace wedge {

// `corner_uv`, if given, gets for each triangle the (u, v) of its three corners on its face's
// parametric face (NaN on planar and cylinder faces): a seam's point has the parameters of the side
// the triangle lies on, a pole's those in the middle of the triangle's other corners.
Mesh tessellate(const Model& m, const Tolerance& tol, std::vector<std::array<Vec2, 3>>* corner_uv = nullptr);

// The parameters along a curve at which its polyline stays within tol.chordal of it and turns by
// at most tol.angular degrees per segment (the curve's breaks always included).
std::vector<double> curve_parameters(const Curve& c, const Tolerance& tol);

}  // namespace wedge
