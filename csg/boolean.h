// wedge's exact mesh-boolean engine: regularised union, intersection and difference of closed,
// consistently oriented triangle meshes. Every decision (which triangles meet, where, how a cut
// triangle is retriangulated, what is inside what) is made exactly on the input doubles; the
// output is rounded to doubles once, at the end. The stages live in csg/boolean_*.cpp and share
// csg/boolean_impl.h, which opens with the notation.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "kernel/error.h"
#include "kernel/mesh.h"

namespace wedge {

// Regularised boolean operations; union and intersection are n-ary, difference subtracts
// every later operand from the first.
enum class BooleanOp { Union, Difference, Intersection };
// "union", "difference" or "intersection": the word scripts, messages and reports use.
const char* boolean_op_name(BooleanOp op);

struct BooleanResult {
  // Closed, 2-manifold, outward-oriented. Where the regularised result is not a manifold (two
  // cubes sharing only an edge) it comes back as shells that touch, each 2-manifold, with their
  // coincident vertices kept apart. face_ids: the source triangle's face id in its operand
  // (-1 where that operand has none).
  Mesh mesh;
  std::vector<std::int32_t> operand;  // per output triangle: the operand it came from (0-based)
  std::vector<std::int32_t> source;   // per output triangle: its input triangle in that operand
};

// Wall time per stage of one boolean (milliseconds), for --stats and the benchmark.
struct BooleanStats {
  double check = 0, broad = 0, arrange = 0, classify = 0, output = 0;
  std::size_t pairs = 0, pieces = 0;
  std::size_t collapses = 0;  // edges the rounding repair collapsed or split (0 on most inputs)
  std::size_t flat_shells = 0;  // shells thinner than rounding, left out (0 on most inputs)
  std::size_t resolutions = 0;  // passes that re-resolved a rounded result crossing itself (0 on most)
  std::size_t welded = 0;  // 1 where the result is of operands welded after the first run could not be rounded
  std::size_t reorders = 0;  // other orders of the operands tried after the result could not be rounded
  std::size_t trusted = 0;  // operands known as results of earlier booleans, not checked again
  std::size_t settled = 0;  // triangles buried in an operand that drops them, left out of the arrangement
  std::size_t in_cores = 0;  // of those, the ones settled before the broad phase (inside an operand's core)
  std::size_t settled_pairs = 0;  // other pairs whose cut lies deep inside such an operand, left out
  std::size_t quads = 0;  // pairs of cut triangles of one face retriangulated as one quadrilateral
  std::size_t quad_points = 0;  // cut points on those quadrilaterals' diagonals left out
};

// Thrown when an evaluation is cancelled (boolean()'s `cancel`, Solid evaluation's EvalControl).
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};
using CancelCheck = std::function<bool()>;

// The work budget of one boolean (Tolerance::max_crossings has the same default): the most points
// where three operands' surfaces cross. Each such point is a crossing of two cut lines inside a
// triangle, which the exact arithmetic decides slowly where surfaces nearly coincide. Ordinary
// booleans have none or a few hundred (the bench's spheres, lattice, plate and sponge); 17 copies
// of a sphere turned by 1 .. 16 degrees have about 650,000 and would take minutes. The estimate is
// made after the broad phase, before the exact work; above the budget boolean() throws
// wedge::Error giving the estimate.
constexpr std::size_t kDefaultMaxCrossings = 50'000;

// The boolean of `operands` (union and intersection of all of them in one pass; difference is
// operands[0] minus all the others). Throws wedge::Error naming the operand and the first
// offending spot if an operand is not closed, not 2-manifold, inside out, has a zero-area triangle
// that cannot be mended without moving a point (those that can are mended, and the operand
// accepted: boolean_impl.h, mend_flat_triangles) or intersects itself. Shells of an
// operand that touch at a vertex or an edge are accepted. Runs on TBB's threads; the result is
// the same bits at any thread count.
// `cancel`, if given, is polled between the stages and inside them (at most every 2 ms, from any of
// TBB's threads, one at a time); when it returns true, boolean() throws Cancelled.
// An operand that is bit for bit a mesh an earlier boolean() returned is known to be valid and is
// not checked again (results are remembered by a 128-bit hash; the last 256 of them).
// `max_crossings`: the work budget above.
// `names`, if given (one per operand), names the operands in errors, as a CSG tree names its node's
// operands in the script's order ("the third operand of the union"); otherwise they are "the first
// operand" and "the second operand" (two of them) or "operand 3".
BooleanResult boolean(BooleanOp op, const std::vector<const Mesh*>& operands, BooleanStats* stats = nullptr,
                      const CancelCheck* cancel = nullptr, std::size_t max_crossings = kDefaultMaxCrossings,
                      const std::vector<std::string>* names = nullptr);
// The two-operand shorthand: boolean(op, {&a, &b}).mesh.
Mesh boolean(BooleanOp op, const Mesh& a, const Mesh& b);

// The solid a closed, consistently oriented mesh that crosses itself only by rounding bounds (a
// boolean result moved by an inexact transform, its thinnest triangles folded over): the region
// where its winding number is at least 1, resolved exactly and rounded to doubles again, closed,
// 2-manifold and free of self-intersections. operand is 0 and source the mesh's triangle each
// result triangle lies in; face ids are kept. Throws wedge::Error where rounding cannot be made
// valid. `cancel` as for boolean().
BooleanResult resolve_self(const Mesh& mesh, const CancelCheck* cancel = nullptr);

// "" if `mesh` is closed, 2-manifold (touching shells allowed only at distinct vertex indices),
// consistently oriented with positive volume and free of self-intersections, all decided exactly;
// otherwise the first defect in words, with the offending spot. `name` starts the message.
std::string mesh_solid_defect(const Mesh& mesh, const std::string& name = "mesh");

}  // namespace wedge
