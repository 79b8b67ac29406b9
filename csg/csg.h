// wedge::csg — the CSG tree and its evaluator: the Solid value type and its leaves, and the exact
// mesh-boolean engine (csg/boolean.h).
#pragma once
#include "csg/boolean.h"
#include "csg/solid.h"
#include "tessellate/tessellate.h"
