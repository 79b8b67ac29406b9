// wedge::tessellate — every tessellation (B-Rep to Mesh, surface to Mesh), and mesh files.
#pragma once
#include "brep/brep.h"
#include "tessellate/mesh_io.h"
#include "tessellate/brep_mesh.h"
#include "tessellate/planar.h"
#include "tessellate/surface_mesh.h"
