// wedge::csg — the CSG tree and its evaluator: the Solid value type and its leaves.
#pragma once
#include "csg/solid.h"
#include "tessellate/tessellate.h"

namespace wedge {

// Regularised boolean operations; union and intersection are n-ary, difference subtracts
// every later operand from the first.
enum class BooleanOp { Union, Difference, Intersection };

}  // namespace wedge
