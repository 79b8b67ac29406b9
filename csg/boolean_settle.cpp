// Settling, between the broad phase and the arrangement: triangles that lie wholly inside another
// operand, where that alone drops them from the result, leave the arrangement with their pairs.
//
// A triangle t of operand i that meets no triangle of operand j (no candidate pair: their boxes
// are apart, or apart() proved them apart) and has a vertex strictly inside j lies strictly inside
// j, all of it. In a union, and in a difference where j is a subtrahend, every point strictly
// inside j is dropped whatever the other operands say. So t's pieces are all dropped, and the cuts
// t would make in its partners lie strictly inside j too: the pieces of a partner on both sides of
// such a cut are both dropped (a piece cannot cross j's surface, whose cuts are all kept: a pair
// of a triangle of j and an unsettled triangle stays). Only the region where the result's boundary
// is decided needs its cuts, and no cut that is left out reaches it.
//
// The lattice truss's struts end in caps at each node's centre, deep inside the node's ball, where
// the caps of the 18 struts of a node cut one another: most of its pairs, and none of them on the
// result. classify() drops the pieces of settled triangles without a ray, and a piece whose
// centroid lies on a settled triangle (it may now straddle one) as well: that centroid is strictly
// inside the settling operand.
#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

namespace {

// The winding number of input vertex v with respect to one closed operand (the triangles in
// `tree`), along the vertical ray up from v moved by (eps, eps^2) in x and y, as classify()'s rays
// go: each triangle the ray crosses above v adds the sign of its normal's z. INT_MIN where v lies
// on one of the triangles (not decided here).
int vertex_winding(const Soup& s, const Bvh& tree, u32 v) {
  const Vec3& p = s.verts[v];
  const double lo[3] = {p.x(), p.y(), p.z()}, hi[3] = {p.x(), p.y(), INFINITY};
  // orient2d(a, b, p) in xy, ties broken by the perturbation.
  auto side = [&](const Vec3& a, const Vec3& b) {
    const int o = orient2d_fast(a.x(), a.y(), b.x(), b.y(), p.x(), p.y());
    if (o != 0) return o;
    if (a.y() != b.y()) return a.y() > b.y() ? 1 : -1;
    return b.x() > a.x() ? 1 : (b.x() < a.x() ? -1 : 0);
  };
  int w = 0;
  bool on = false;
  tree.query(lo, hi, [&](u32 u) {
    const auto& U = s.tris[u];
    const Vec3 &A = s.verts[U[0]], &B = s.verts[U[1]], &C = s.verts[U[2]];
    const int o = orient2d_fast(A.x(), A.y(), B.x(), B.y(), C.x(), C.y());
    if (o == 0) return;  // vertical: the perturbed ray misses it
    if (side(A, B) != o || side(B, C) != o || side(C, A) != o) return;
    const int h = orient3d_fast(A, B, C, p);  // +1: v on the side the normal points to
    if (h == 0) on = true;
    else if (h * o < 0) w += o;  // the triangle is above v
  });
  return on ? INT_MIN : w;
}

}  // namespace

std::vector<char> settle(const Soup& soup, std::vector<std::array<u32, 2>>& pairs, BooleanOp op) {
  const int nops = soup.operands;
  // With two operands every pair is with the other one: nothing to settle.
  if (nops < 3 || op == BooleanOp::Intersection || pairs.empty()) return {};
  const std::size_t nt = soup.tris.size(), np = pairs.size();
  const std::vector<u32> first = operand_starts(soup);
  // Whether a triangle strictly inside operand j is dropped whatever else holds it.
  auto settles = [&](int i, int j) { return j != i && (op == BooleanOp::Union || j != 0); };

  // The triangles with pairs (the others cost the arrangement nothing).
  // Per triangle, its pairs, and where its run of pairs (t, u) starts (one pass: the pairs of a
  // neighbourhood sit together, and plain increments beat atomic ones threefold here).
  std::vector<u32> degree(nt, 0), run(nt + 1, 0);
  for (const auto& p : pairs) ++degree[p[0]], ++degree[p[1]], ++run[p[0] + 1];
  for (std::size_t t = 0; t < nt; ++t) run[t + 1] += run[t];
  // Each operand's box, and a grid over them: the operands whose box may hold a box that starts
  // in a cell are listed in that cell.
  std::vector<std::array<double, 6>> box(nops);
  parallel_for(0, static_cast<std::size_t>(nops), [&](std::size_t j) {
    auto& b = box[j];
    b = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (u32 t = first[j]; t < first[j + 1]; ++t) {
      double lo[3], hi[3];
      triangle_box(soup, t, lo, hi);
      for (int d = 0; d < 3; ++d) b[d] = std::min(b[d], lo[d]), b[d + 3] = std::max(b[d + 3], hi[d]);
    }
  });
  double g0[3] = {INFINITY, INFINITY, INFINITY}, g1[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const auto& b : box)
    for (int d = 0; d < 3; ++d) g0[d] = std::min(g0[d], b[d]), g1[d] = std::max(g1[d], b[d + 3]);
  for (int d = 0; d < 3; ++d)
    if (!(g0[d] < g1[d]) || !std::isfinite(g1[d] - g0[d])) return {};
  const int g = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(nops))), 1, 16);
  // Cell of coordinate x on axis d: monotone in x, so a box holding a point shares its cell.
  auto cell = [&](double x, int d) {
    const double f = (x - g0[d]) / (g1[d] - g0[d]) * g;
    return f <= 0 ? 0 : (f >= g ? g - 1 : static_cast<int>(f));
  };
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(g) * g * g);
  for (int j = 0; j < nops; ++j) {
    const auto& b = box[j];
    if (!(b[0] <= b[3])) continue;
    for (int x = cell(b[0], 0); x <= cell(b[3], 0); ++x)
      for (int y = cell(b[1], 1); y <= cell(b[4], 1); ++y)
        for (int z = cell(b[2], 2); z <= cell(b[5], 2); ++z) cells[(x * g + y) * g + z].push_back(j);
  }
  // Per triangle with at least kMinPairs pairs, the operands that may settle it (their box holds its box), the smallest
  // box first (the one most likely to hold it closely: a node's ball before the struts through it).
  constexpr std::size_t kBlock = 16384;
  // A ray (and the tree it needs) costs about what the exact work on a few pairs does: triangles
  // with fewer pairs are left as they are. (The 512-sphere lattice has tens of thousands with 1 to
  // 7 pairs, none of them buried: looking at them all took 130 ms, 6% of that union. A truss's
  // caps have 100 pairs each.)
  constexpr u32 kMinPairs = 8;
  auto holders = [&](u32 t, auto&& f) {
    double lo[3], hi[3];
    triangle_box(soup, t, lo, hi);
    const int i = soup.operand[t];
    for (int j : cells[(cell(lo[0], 0) * g + cell(lo[1], 1)) * g + cell(lo[2], 2)]) {
      const auto& b = box[j];
      if (settles(i, j) && b[0] <= lo[0] && b[1] <= lo[1] && b[2] <= lo[2] && hi[0] <= b[3] && hi[1] <= b[4] &&
          hi[2] <= b[5])
        f(j);
    }
  };
  std::vector<u32> off;
  parallel_prefix(off, nt, kBlock, [&](std::size_t t) {
    u32 n = 0;
    if (degree[t] >= kMinPairs) holders(static_cast<u32>(t), [&](int) { ++n; });
    return n;
  });
  if (off[nt] == 0) return {};
  std::vector<std::int32_t> held(off[nt]);
  auto volume = [&](int j) { return (box[j][3] - box[j][0]) * (box[j][4] - box[j][1]) * (box[j][5] - box[j][2]); };
  parallel_for(0, nt, [&](std::size_t t) {
    if (off[t] == off[t + 1]) return;
    u32 n = off[t];
    holders(static_cast<u32>(t), [&](int j) { held[n++] = j; });
    std::sort(held.begin() + off[t], held.begin() + off[t + 1],
              [&](int a, int b) { return volume(a) != volume(b) ? volume(a) < volume(b) : a < b; });
  });
  soup.poll();
  // Pairs (u, t) with u < t, per held triangle t: its partners below it, in ascending order (its
  // partners above it are the run of pairs that starts with t).
  std::vector<u32> roff(nt + 1, 0);
  for (const auto& p : pairs)
    if (off[p[1]] != off[p[1] + 1]) ++roff[p[1] + 1];
  for (std::size_t t = 0; t < nt; ++t) roff[t + 1] += roff[t];
  std::vector<u32> below(roff[nt]);
  {
    std::vector<u32> at(roff.begin(), roff.end() - 1);
    for (const auto& p : pairs)
      if (off[p[1]] != off[p[1] + 1]) below[at[p[1]]++] = p[0];
  }
  soup.poll();
  // Per held triangle, the first holder it has no pair with (kNone: none). A triangle with a
  // partner in the holder meets its surface, or may.
  std::vector<std::int32_t> candidate(nt, -1);
  parallel_for(0, nt, [&](std::size_t ti) {
    const u32 t = static_cast<u32>(ti);
    if (off[t] == off[t + 1]) return;
    const auto run0 = pairs.begin() + run[t], run1 = pairs.begin() + run[t + 1];
    for (u32 k = off[t]; k < off[t + 1]; ++k) {
      const int j = held[k];
      const u32 a = first[j], b = first[j + 1];
      bool met;
      if (j > soup.operand[t]) {
        const auto x = std::lower_bound(run0, run1, std::array<u32, 2>{t, a});
        met = x != run1 && (*x)[1] < b;
      } else {
        const auto x = std::lower_bound(below.begin() + roff[t], below.begin() + roff[t + 1], a);
        met = x != below.begin() + roff[t + 1] && *x < b;
      }
      if (!met) {
        candidate[t] = j;
        return;
      }
    }
  });
  // One tree per operand a ray goes through.
  std::vector<char> needed(nops, 0);
  for (std::size_t t = 0; t < nt; ++t)
    if (candidate[t] >= 0) needed[candidate[t]] = 1;
  std::vector<Bvh> trees(nops);
  parallel_for(0, static_cast<std::size_t>(nops), [&](std::size_t j) {
    if (!needed[j]) return;
    std::vector<u32> ids(first[j + 1] - first[j]);
    for (u32 t = first[j]; t < first[j + 1]; ++t) ids[t - first[j]] = t;
    trees[j] = Bvh(soup, std::move(ids), 3);
  });
  soup.poll();
  std::vector<char> settled(nt, 0);
  std::atomic<bool> any{false};
  parallel_for(0, nt, [&](std::size_t t) {
    if (candidate[t] < 0) return;
    const int w = vertex_winding(soup, trees[candidate[t]], soup.tris[t][0]);
    if (w != INT_MIN && w > 0) {
      settled[t] = 1;
      any.store(true, std::memory_order_relaxed);
    }
  });
  if (!any.load()) return {};
  // The pairs of settled triangles go, the rest keep their order.
  const auto from = block_starts(np, 65536, [&](std::size_t lo, std::size_t hi) {
    std::size_t n = 0;
    for (std::size_t k = lo; k < hi; ++k) n += !settled[pairs[k][0]] && !settled[pairs[k][1]];
    return n;
  });
  std::vector<std::array<u32, 2>> kept(from.total());
  fill_blocks(from, [&](std::size_t lo, std::size_t hi, std::size_t n) {
    for (std::size_t k = lo; k < hi; ++k)
      if (!settled[pairs[k][0]] && !settled[pairs[k][1]]) kept[n++] = pairs[k];
  });
  pairs.swap(kept);
  return settled;
}

}  // namespace wedge::boolean_detail
