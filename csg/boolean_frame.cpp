// The engine in a frame of unit size: operands whose coordinates are far from 1 (a part 1e-90 or
// 1e90 wide) are scaled by a power of two first, and the result back.
//
// Every decision is exact at any scale, but the fast paths are not scale-invariant: the static
// filters of the double predicates give up where products of coordinates underflow toward
// subnormals (a cube's orient3d is of degree 3: 1e-270 at size 1e-90) or overflow, and so do the
// interval filters of the implicit points (a TPI's coordinates are of degree 7 in the input), so
// that at such sizes almost every predicate took the exact path: a box and a 20k-triangle sphere
// took 10 ms at size 1, 0.7 s at 1e-90, 7 s at 1e-120 and 0.8 s at 1e120. Scaling by a power of
// two changes no sign and no comparison, so the frame's result is the same arrangement, and its
// rounding (faithful, toward zero) scales back exactly where it stays among the normal doubles.
// Both steps are checked: a coordinate that would not survive the round trip (a vertex near zero
// whose scaled value is subnormal) leaves the operands as given.
#include <cmath>

#include "csg/boolean_impl.h"

namespace wedge {

namespace {

// Largest coordinates within 2^-kNear .. 2^kNear are left as they are: there the filters work.
constexpr int kNear = 20;

// The power of two s with the largest absolute coordinate of the operands in [1, 2) after
// dividing by s; 1 when that is near 1 already (or there is nothing to scale).
double frame_scale(const std::vector<const Mesh*>& operands) {
  double big = 0;
  for (const Mesh* m : operands)
    for (const Point3& p : m->positions) big = std::max(big, p.cwiseAbs().maxCoeff());
  if (!(big > 0) || !std::isfinite(big)) return 1;
  const int e = std::ilogb(big);
  return std::abs(e) <= kNear ? 1.0 : std::ldexp(1.0, e);
}

// positions times `factor`, false (and `out` unspecified) if a coordinate does not come back
// exactly when divided by it.
bool scale_exactly(const std::vector<Point3>& in, double factor, std::vector<Point3>& out) {
  out.resize(in.size());
  for (std::size_t v = 0; v < in.size(); ++v) {
    out[v] = in[v] * factor;
    if (out[v] / factor != in[v]) return false;
  }
  return true;
}

}  // namespace

BooleanResult boolean(BooleanOp op, const std::vector<const Mesh*>& operands, BooleanStats* stats, const CancelCheck* cancel,
                      std::size_t max_crossings) {
  using boolean_detail::boolean_as_given;
  for (const Mesh* m : operands)
    if (!m) return boolean_as_given(op, operands, stats, cancel, max_crossings);  // its error
  const double s = frame_scale(operands);
  if (s == 1) return boolean_as_given(op, operands, stats, cancel, max_crossings);
  std::vector<Mesh> framed(operands.size());
  std::vector<const Mesh*> ptrs(operands.size());
  for (std::size_t i = 0; i < operands.size(); ++i) {
    if (!scale_exactly(operands[i]->positions, 1 / s, framed[i].positions))
      return boolean_as_given(op, operands, stats, cancel, max_crossings);
    framed[i].triangles = operands[i]->triangles;
    framed[i].face_ids = operands[i]->face_ids;
    ptrs[i] = &framed[i];
  }
  BooleanResult r;
  try {
    r = boolean_as_given(op, ptrs, stats, cancel, max_crossings);
  } catch (const Cancelled&) {
    throw;
  } catch (const Error&) {
    // An operand's defect (or the work budget): said again on the operands as given, so that its
    // coordinates are the caller's.
    return boolean_as_given(op, operands, stats, cancel, max_crossings);
  }
  std::vector<Point3> back;
  if (!scale_exactly(r.mesh.positions, s, back)) return boolean_as_given(op, operands, stats, cancel, max_crossings);
  r.mesh.positions = std::move(back);
  // Fed to a boolean whose frame is the same, the result becomes the frame's result again, bit
  // for bit, which the engine remembers as verified: it is not checked again.
  return r;
}

}  // namespace wedge
