// wedge::kernel — the public header of the kernel layer: vectors and transforms, bounding
// boxes, tolerances, exact predicates, typed ids and arenas, the triangle Mesh, errors.
#pragma once
#include "kernel/bbox.h"
#include "kernel/error.h"
#include "kernel/ids.h"
#include "kernel/mesh.h"
#include "kernel/predicates.h"
#include "kernel/tolerance.h"
#include "kernel/transform.h"
#include "kernel/types.h"

namespace wedge {
// The version of the library, "MAJOR.MINOR.PATCH".
const char* version();
}  // namespace wedge
