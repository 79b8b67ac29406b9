// wedge::tessellate — B-Rep to Mesh, and mesh files. The file formats it reads and writes.
#pragma once
#include <string_view>

#include "brep/brep.h"

namespace wedge {

enum class MeshFormat { Obj, StlAscii, StlBinary, Ply, Off };

}  // namespace wedge
