// polyhedron() without its geometry, for meshes whose faces may be slivers too thin for a
// double-precision normal (the boolean engine's output, rebuilt by csg/rebuild.cpp): the same
// Euler-operator construction and input checks (closed, 2-manifold, one fan per vertex), but the
// faces get no planes and the model is not validated here: the caller changes it further (kef,
// kev, kemr) and validates what it keeps.
#pragma once
#include <vector>

#include "brep/brep.h"

namespace wedge {

Model polyhedron_topology(const std::vector<Point3>& points, const std::vector<std::vector<int>>& faces,
                          std::vector<FaceId>* face_of = nullptr);

}  // namespace wedge
