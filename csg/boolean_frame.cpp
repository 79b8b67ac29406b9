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
#include <algorithm>
#include <cmath>
#include <exception>
#include <numeric>
#include <optional>
#include <unordered_map>

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

// Operands with vertices a rounding apart (a solid and its copy turned by 1e-14 degrees, or a
// result and a mirrored, moved copy of it whose sheets nearly coincide) can leave a result that no
// re-resolution rounds: each pass's rounded intersection points cross the sheet beside them
// again. Welded, those vertices coincide and the sheets are the same exactly, which the engine
// decides as it decides any coplanar overlap. Each vertex of a later operand within kWeld steps of
// the largest coordinate's rounding (2^-46 of it: 64 ulps) of an earlier operand's vertex moves
// onto the nearest such vertex. False when nothing moved.
constexpr int kWeld = 64;

bool weld_operands(const std::vector<const Mesh*>& operands, std::vector<Mesh>& welded) {
  double reach = 0;
  for (const Mesh* m : operands)
    for (const Point3& p : m->positions) reach = std::max(reach, p.cwiseAbs().maxCoeff());
  if (!(reach > 0) || !std::isfinite(reach)) return false;
  const double delta = kWeld * std::ldexp(1.0, std::ilogb(reach) - 52);
  // Earlier operands' vertices in a grid of cells 2 delta wide: a vertex's partners are in the
  // 27 cells around its own.
  const double cell = 2 * delta;
  auto key = [&](long long x, long long y, long long z) {
    return static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
           static_cast<std::uint64_t>(z) * 0x165667B19E3779F9ull;
  };
  auto coord = [&](double v) { return static_cast<long long>(std::floor(v / cell)); };
  std::unordered_multimap<std::uint64_t, Point3> grid;
  welded.resize(operands.size());
  bool moved = false;
  for (std::size_t i = 0; i < operands.size(); ++i) {
    welded[i] = *operands[i];
    if (i > 0)
      for (Point3& p : welded[i].positions) {
        const long long cx = coord(p.x()), cy = coord(p.y()), cz = coord(p.z());
        const Point3* best = nullptr;
        double best_d = delta;
        for (long long dx = -1; dx <= 1; ++dx)
          for (long long dy = -1; dy <= 1; ++dy)
            for (long long dz = -1; dz <= 1; ++dz) {
              auto range = grid.equal_range(key(cx + dx, cy + dy, cz + dz));
              for (auto it = range.first; it != range.second; ++it) {
                const double d = (it->second - p).cwiseAbs().maxCoeff();
                if (best ? d < best_d : d <= best_d) best = &it->second, best_d = d;
              }
            }
        if (best && *best != p) {
          p = *best;
          moved = true;
        }
      }
    for (const Point3& p : operands[i]->positions) grid.emplace(key(coord(p.x()), coord(p.y()), coord(p.z())), p);
  }
  return moved;
}

// The engine in the frame (above), on the operands' own coordinates where framing does not apply.
BooleanResult in_frame(BooleanOp op, const std::vector<const Mesh*>& operands, BooleanStats* stats,
                       const CancelCheck* cancel, std::size_t max_crossings, const std::vector<std::string>* names) {
  using boolean_detail::boolean_as_given;
  for (const Mesh* m : operands)
    if (!m) return boolean_as_given(op, operands, stats, cancel, max_crossings, names);  // its error
  const double s = frame_scale(operands);
  if (s == 1) return boolean_as_given(op, operands, stats, cancel, max_crossings, names);
  std::vector<Mesh> framed(operands.size());
  std::vector<const Mesh*> ptrs(operands.size());
  for (std::size_t i = 0; i < operands.size(); ++i) {
    if (!scale_exactly(operands[i]->positions, 1 / s, framed[i].positions))
      return boolean_as_given(op, operands, stats, cancel, max_crossings, names);
    framed[i].triangles = operands[i]->triangles;
    framed[i].face_ids = operands[i]->face_ids;
    ptrs[i] = &framed[i];
  }
  BooleanResult r;
  try {
    r = boolean_as_given(op, ptrs, stats, cancel, max_crossings, names);
  } catch (const Cancelled&) {
    throw;
  } catch (const Error&) {
    // An operand's defect (or the work budget): said again on the operands as given, so that its
    // coordinates are the caller's.
    return boolean_as_given(op, operands, stats, cancel, max_crossings, names);
  }
  std::vector<Point3> back;
  if (!scale_exactly(r.mesh.positions, s, back)) return boolean_as_given(op, operands, stats, cancel, max_crossings, names);
  r.mesh.positions = std::move(back);
  // Fed to a boolean whose frame is the same, the result becomes the frame's result again, bit
  // for bit, which the engine remembers as verified: it is not checked again.
  return r;
}

}  // namespace

// The engine, and where its result cannot be rounded, the engine again on welded operands, then
// on the operands in other orders. The welded run is checked as any operands are (a weld that
// folds an operand is refused there); if every run fails, the first run's error is the one
// reported.
//
// The order changes nothing exact (the same solid, the same decisions), but the rounding repair
// visits triangles, and breaks ties, in the order the operands give them: on turned boxes with
// nearly flush faces, where about 1 boolean in 4,000 cannot be rounded, another order rounds half
// of those. Union and intersection take the operands turned by one place, up to 3 times (and
// fewer than their number); a difference keeps its first operand and turns the rest.
BooleanResult boolean(BooleanOp op, const std::vector<const Mesh*>& operands, BooleanStats* stats, const CancelCheck* cancel,
                      std::size_t max_crossings, const std::vector<std::string>* names) {
  if (names && names->size() != operands.size())
    fail("boolean: ", names->size(), " names for ", operands.size(), " operands");
  try {
    return in_frame(op, operands, stats, cancel, max_crossings, names);
  } catch (const boolean_detail::Unroundable&) {
    const std::exception_ptr first = std::current_exception();
    // Another run: its result, or nothing where it fails too (a cancel still ends it all).
    auto attempt = [&](const std::vector<const Mesh*>& ptrs) -> std::optional<BooleanResult> {
      try {
        return in_frame(op, ptrs, stats, cancel, max_crossings, nullptr);  // (its errors are not reported)
      } catch (const Cancelled&) {
        throw;
      } catch (const Error&) {
        return std::nullopt;
      }
    };
    std::vector<Mesh> welded;
    if (weld_operands(operands, welded)) {
      std::vector<const Mesh*> ptrs;
      for (const Mesh& m : welded) ptrs.push_back(&m);
      if (auto r = attempt(ptrs)) {
        if (stats) stats->welded = 1;
        return std::move(*r);
      }
    }
    const std::size_t fixed = op == BooleanOp::Difference ? 1 : 0;
    const std::size_t turning = operands.size() - fixed;
    std::vector<std::size_t> order(operands.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    for (std::size_t turn = 1; turn < turning && turn <= 3; ++turn) {
      std::rotate(order.begin() + fixed, order.begin() + fixed + 1, order.end());
      std::vector<const Mesh*> ptrs;
      for (std::size_t i : order) ptrs.push_back(operands[i]);
      if (auto r = attempt(ptrs)) {
        for (auto& o : r->operand) o = static_cast<std::int32_t>(order[o]);
        if (stats) stats->reorders = turn;
        return std::move(*r);
      }
    }
    std::rethrow_exception(first);
  }
}

}  // namespace wedge
