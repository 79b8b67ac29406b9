// polyhedron() without its geometric checks, for meshes whose faces may be slivers too thin for a
// double-precision normal (the boolean engine's output, rebuilt by csg/rebuild.cpp): the same
// Euler-operator construction and the structural validation (closed, 2-manifold, oriented,
// Euler-Poincare), but a face whose normal rounds to zero gets no plane instead of an error.
#pragma once
#include <vector>

#include "brep/brep.h"

namespace wedge {

Model polyhedron_topology(const std::vector<Point3>& points, const std::vector<std::vector<int>>& faces,
                          std::vector<FaceId>* face_of = nullptr);

}  // namespace wedge
