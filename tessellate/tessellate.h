// wedge::tessellate — B-Rep to Mesh (planar faces with holes), and mesh files.
#pragma once
#include "brep/brep.h"
#include "tessellate/mesh_io.h"
#include "tessellate/brep_mesh.h"
#include "tessellate/planar.h"
