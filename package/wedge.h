// wedge's C++ API in one include: #include <wedge/wedge.h>. The same operations as the Lua API,
// with C++ types: wedge::Solid (csg/solid.h) and its builders (brep/brep.h, csg/brep_leaf.h),
// transforms (kernel/transform.h), curves and surfaces (surfaces/surfaces.h), tessellation and
// mesh files (tessellate/), the software renderer (render/render.h) and scenes of solids
// (scene/scene.h: groups, instances, arrays, the instance table, drawing).
#pragma once
#include "brep/brep.h"
#include "csg/brep_leaf.h"
#include "csg/csg.h"
#include "csg/solid.h"
#include "kernel/kernel.h"
#include "render/render.h"
#include "scene/scene.h"
#include "surfaces/surfaces.h"
#include "tessellate/mesh_io.h"
#include "tessellate/tessellate.h"
