// wedge::csg — the CSG tree and its evaluator. The operations of its inner nodes.
#pragma once
#include "tessellate/tessellate.h"

namespace wedge {

// Regularised boolean operations; union and intersection are n-ary, difference subtracts
// every later operand from the first.
enum class BooleanOp { Union, Difference, Intersection };

}  // namespace wedge
