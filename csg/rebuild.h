// A boolean result (a closed triangle mesh whose triangles know their source face) rebuilt as a
// winged-edge solid through the Euler operators.
//
// Method. The triangles become a model by polyhedron() (brep/build.cpp: mvfs, mev, mef, and
// kfmrh + mekr for handles), one face per triangle. Then every edge whose two triangles have the
// same source face is removed: by kef while its sides lie in two faces (the smaller face is
// merged into the larger); then, for the edges left with one face on both sides, by kev when
// one end hangs on that edge alone (a strut to a vertex inside the face) and by kemr otherwise
// (a bridge between the outer boundary and a hole: the ring is made of the part of the loop
// with the smaller projected area about the face's mean normal). What remains are the faces of
// the result, one per connected region of one source face, with their rings; the edges left are
// the polylines where source faces meet, the intersection curves among them.
#pragma once
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "brep/brep.h"
#include "kernel/mesh.h"

namespace wedge {

struct RebuiltSolid {
  Model model;
  // Per model face (by id value): the source face id its triangles carry, and their total area.
  std::unordered_map<std::int32_t, std::int32_t> source;
  std::unordered_map<std::int32_t, double> area;
  // Per triangle of the mesh, the model face (id value) it became part of.
  std::vector<std::int32_t> triangle_face;
};

// `mesh`: closed, 2-manifold, outward-oriented, one face id per triangle (welded: a vertex is one
// index). Throws wedge::Error if it is not.
RebuiltSolid rebuild_brep(const Mesh& mesh);

}  // namespace wedge
