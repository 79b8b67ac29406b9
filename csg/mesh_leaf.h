// A closed triangle mesh as a leaf of the CSG tree (MeshLeaf, declared in csg/solid.h): its
// checks, and the faces a mesh without face ids is given.
#pragma once
#include <cstddef>
#include <vector>

#include "csg/solid.h"

namespace wedge {

// Face ids for a mesh without its own: the connected regions of exactly coplanar, like-facing
// triangles (orient3d of the neighbour's far corner is zero). Returns the region count; `planes`
// gets each region's plane (its first triangle's).
std::size_t planar_regions(Mesh& mesh, std::vector<FaceSurface>& planes);

}  // namespace wedge
