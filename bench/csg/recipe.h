// What a benchmark case computes: steps of n-ary booleans, each over operands of the case or the
// previous step's result, run the same way by every engine of bench_boolean.
#pragma once
#include <string>
#include <vector>

#include "csg/csg.h"
#include "kernel/mesh.h"

namespace wedge::bench {

struct Step {
  BooleanOp op;
  std::vector<int> inputs;  // operand indices; -1 is the previous step's result
};
using Recipe = std::vector<Step>;

// The result of one engine on one case: the output mesh rounded to doubles, or why there is none.
struct PeerRun {
  Mesh mesh;
  bool ok = false;
  std::string why;
};

enum class CgalKernel { Epick, Epeck };

// CGAL's corefinement (PMP::corefine_and_compute_*) on Surface_mesh<K::Point_3>. An n-ary union
// or intersection is reduced pairwise as a balanced tree; a difference is the first operand minus
// the balanced union of the rest. The output is rounded to doubles (for Epeck: exact until then).
PeerRun cgal_recipe(CgalKernel kernel, const std::vector<Mesh>& operands, const Recipe& recipe);

}  // namespace wedge::bench
