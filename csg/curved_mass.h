// Mass properties of a curved solid from its mesh and the surfaces its triangles lie on: convergent
// with the tolerance to second order at least (third where faces cross at a wide angle), not first.
//
// Method. The mesh's own integrals (signed tetrahedra) miss, under each triangle on a curved face,
// the thin region between the flat triangle and the surface over it: about two thirds of the
// tolerance times the face's area, relatively a few times the tolerance (the classic figure at
// 1e-4: 9e-5). That region is added, triangle by triangle, as the volume swept by the segments
// from each point q(b) of the triangle to its point s(b) on the surface,
//   F(b, l) = q(b) + l (s(b) - q(b)),  b in the triangle, l in [0, 1],
// whose integrals (volume, first and second moments) are det(F_b1, F_b2, F_l) times 1, x, x x^T
// over b and l: a 6-point degree-4 rule on the triangle (on a triangle with a pole corner, 3 x 3
// Gauss points in the square collapsed onto the pole) and 3-point Gauss in l. s(b) is the
// surface at the triangle's corner parameters interpolated (a parametric face: the tessellator's
// (u, v), and for a vertex a boolean made, those of its closest surface point (csg/shading.h's
// interpolated_uv), one pair per vertex on each face; a corner on a pole takes the others' free
// parameter), or the closest point (a planar builder's cylinder). Two
// triangles of one face that share an edge give it the same segments, so the side walls of
// neighbouring regions cancel. Where two faces meet (a boolean's cut, or an edge of a leaf), the
// walls left over, from the mesh's edge to each face's surface, and the surfaces' common curve
// bound a region whose section is the tolerance squared; it is added as the quadrilateral from the
// edge point to the two surface points and the point where the surfaces' tangent planes there
// meet, swept along the edge. What remains is third order (two unit balls 1 apart: 5e-10 at
// 1e-3, where the walls alone left 1.3e-6). Not where two surfaces cross at a grazing angle:
// there the meshes cross up to the tolerance over the angle away from the surfaces' curve, and
// between the two curves a piece is capped toward its own surface where the other bounds the
// solid (two balls 1e-3 apart: 8e-8 at 1e-4, relatively 2e-8 of the ball). The area is the
// surfaces' over the curved triangles (the caps' area elements) and, along each edge between two
// faces, the strips between the caps' ends and the faces' common curve C (a cylinder's cap disc
// beyond its chords), their widths measured in the tangent planes: second order (a sphere minus
// a cube: 4.5e-6 at 1e-2, 5e-8 at 1e-3, where the caps alone left 1.7e-3 and 1.7e-4).
#pragma once
#include <vector>

#include "brep/brep.h"
#include "csg/shading.h"
#include "kernel/mesh.h"

namespace wedge {

// `mesh`: closed and outward, face ids indexing `surfaces` (a face without a curved surface, or
// a triangle without finite corner parameters on a parametric face, counts as flat); `corner_uv`
// empty or one per triangle; `chordal` the tolerance the mesh was made at (a triangle whose surface
// points lie farther than 16 times it off the triangle's plane, or farther along it than its
// longest side, keeps its flat value). Every face tried converges at second order (the classic
// figure: 9e-9 at 1e-4; a pointed cone less a quadrant, its apex a pole: 1e-12 at 1e-3).
// `triangle_area`, where given: per triangle, its share of the area (its surface's over it and the
// strips along its edges between faces), for the areas of single faces.
MassProperties curved_mass_properties(const Mesh& mesh, const std::vector<FaceSurface>& surfaces, const CornerUvs& corner_uv,
                                      double chordal, std::vector<double>* triangle_area = nullptr);

}  // namespace wedge
