// Settling, between the broad phase and the arrangement: cuts that lie strictly inside an operand
// whose inside drops everything there leave the arrangement.
//
// In a union every point strictly inside an operand is dropped, whatever the other operands say;
// in a difference every point strictly inside a subtrahend. Call such an operand a settling one
// (for the points of the other operands). A cut that lies strictly inside a settling operand j
// separates pieces that are both dropped: a piece cannot cross j's surface, whose cuts are all
// kept (a pair of a triangle of j and another triangle is dropped only for a third operand's
// sake), so the pieces on both sides of the cut are inside j. Left out, the cut merges pieces
// that are dropped anyway, and no cut on the result's boundary goes.
//
// - Settled triangles: a triangle t that meets no triangle of a settling operand j (no candidate
//   pair: their boxes are apart, or apart() proved them apart) and has a vertex strictly inside j
//   (an exact ray) lies strictly inside j, all of it: every pair of t goes. A lattice truss's
//   struts end in caps at each node's centre, deep inside the node's ball, where the caps of the
//   node's struts cut one another: most of its pairs.
// - Pairs in a core: an operand's core is a ball certainly inside it (its centre strictly inside
//   by an exact ray, its radius the distance to its nearest triangle, shrunk far beyond that
//   distance's rounding). A pair of triangles of two other operands whose cut (bounded in double
//   arithmetic, with a margin far beyond its rounding) lies in the core of an operand settling
//   both goes: the struts' walls cross one another near each node, inside the node's ball.
//
// classify() drops settled triangles' pieces without a ray, and a piece whose centroid lies on a
// triangle whose cut with the piece's own triangle was left out: that centroid is on the cut,
// strictly inside the settling operand.
#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <memory>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

namespace {

// The winding number of point p with respect to one closed operand, along the vertical ray up from
// p moved by (eps, eps^2) in x and y, as classify()'s rays go: each triangle the ray crosses above
// p adds the sign of its normal's z. `each(f)` calls f(triangle) for the operand's triangles (at
// least those whose box meets the ray). INT_MIN where p lies on a triangle (not decided here).
template <class Each>
int winding_at(const Soup& s, const Vec3& p, Each&& each) {
  // orient2d(a, b, p) in xy, ties broken by the perturbation.
  auto side = [&](const Vec3& a, const Vec3& b) {
    const int o = orient2d_fast(a.x(), a.y(), b.x(), b.y(), p.x(), p.y());
    if (o != 0) return o;
    if (a.y() != b.y()) return a.y() > b.y() ? 1 : -1;
    return b.x() > a.x() ? 1 : (b.x() < a.x() ? -1 : 0);
  };
  int w = 0;
  bool on = false;
  each([&](u32 u) {
    const auto& U = s.tris[u];
    const Vec3 &A = s.verts[U[0]], &B = s.verts[U[1]], &C = s.verts[U[2]];
    const int o = orient2d_fast(A.x(), A.y(), B.x(), B.y(), C.x(), C.y());
    if (o == 0) return;  // vertical: the perturbed ray misses it
    if (side(A, B) != o || side(B, C) != o || side(C, A) != o) return;
    const int h = orient3d_fast(A, B, C, p);  // +1: p on the side the normal points to
    if (h == 0) on = true;
    else if (h * o < 0) w += o;  // the triangle is above p
  });
  return on ? INT_MIN : w;
}

// Lists of operands per cell of a grid over the scene: the operands whose box meets the cell.
struct Grid {
  double g0[3], g1[3];  // the extent
  int g = 1;            // cells per axis
  std::vector<std::vector<int>> cells;
  // Cell of coordinate x on axis d: monotone in x, so a box holding a point shares its cell.
  int cell(double x, int d) const {
    const double f = (x - g0[d]) / (g1[d] - g0[d]) * g;
    return f <= 0 ? 0 : (f >= g ? g - 1 : static_cast<int>(f));
  }
  const std::vector<int>& at(const double p[3]) const {
    return cells[(static_cast<std::size_t>(cell(p[0], 0)) * g + cell(p[1], 1)) * g + cell(p[2], 2)];
  }
};

// What both kinds of settling share: the operands' triangle ranges and boxes, and the scene's
// extent.
struct Scene {
  const Soup& soup;
  std::vector<u32> first;                  // operand_starts()
  std::vector<std::array<double, 6>> box;  // per operand (lo, hi)
  double g0[3], g1[3];                     // every operand's box

  explicit Scene(const Soup& s) : soup(s), first(operand_starts(s)), box(operand_boxes(s)) {
    for (int d = 0; d < 3; ++d) g0[d] = INFINITY, g1[d] = -INFINITY;
    for (const auto& b : box)
      for (int d = 0; d < 3; ++d) g0[d] = std::min(g0[d], b[d]), g1[d] = std::max(g1[d], b[d + 3]);
  }
  // Whether the scene has an extent (finite, not flat).
  bool usable() const {
    for (int d = 0; d < 3; ++d)
      if (!(g0[d] < g1[d]) || !std::isfinite(g1[d] - g0[d])) return false;
    return true;
  }
  // A grid of g^3 cells over the scene listing the `boxes` (per operand; empty ones nowhere).
  Grid grid(const std::vector<std::array<double, 6>>& boxes, int g) const {
    Grid r;
    for (int d = 0; d < 3; ++d) r.g0[d] = g0[d], r.g1[d] = g1[d];
    r.g = g;
    r.cells.resize(static_cast<std::size_t>(g) * g * g);
    for (int j = 0; j < static_cast<int>(boxes.size()); ++j) {
      const auto& b = boxes[j];
      if (!(b[0] <= b[3])) continue;
      for (int x = r.cell(b[0], 0); x <= r.cell(b[3], 0); ++x)
        for (int y = r.cell(b[1], 1); y <= r.cell(b[4], 1); ++y)
          for (int z = r.cell(b[2], 2); z <= r.cell(b[5], 2); ++z) r.cells[(x * g + y) * g + z].push_back(j);
    }
    return r;
  }
};

// Settling looks at triangles with at least kMinPairs pairs, and at pairs with such a triangle:
// a ray (and the tree it needs), or a look at the cores around a pair, costs about what the exact
// work on a few pairs does, and the arrangement's work in a triangle grows faster than its cuts
// (their crossings). The 512-sphere lattice has tens of thousands of triangles with 1 to 7 pairs,
// none of them buried and no cut of theirs in a third sphere's core: looking at them all took
// 130 ms and 45 ms, 6% and 2% of that union. A truss's caps have 100 pairs each, the walls of its
// struts near a node dozens.
constexpr u32 kMinPairs = 8;

// The triangles settled by the operands' boxes and exact rays (see the top of the file); their
// pairs leave `pairs`. Empty where none is. `degree`: per triangle, its pairs.
template <class Settles>
std::vector<char> settle_triangles(const Scene& sc, const std::vector<u32>& degree, std::vector<std::array<u32, 2>>& pairs,
                                   Settles&& settles) {
  const Soup& soup = sc.soup;
  const int nops = soup.operands;
  const std::vector<u32>& first = sc.first;
  const auto& box = sc.box;
  const std::size_t nt = soup.tris.size(), np = pairs.size();
  // Per triangle, where its run of pairs (t, u) starts.
  std::vector<u32> run(nt + 1, 0);
  for (const auto& p : pairs) ++run[p[0] + 1];
  for (std::size_t t = 0; t < nt; ++t) run[t + 1] += run[t];
  // The operands whose box may hold a box starting in a cell, per cell.
  const int per_axis = std::clamp(static_cast<int>(std::cbrt(static_cast<double>(nops))), 1, 16);
  const Grid cells = sc.grid(box, per_axis);
  // Per triangle with at least kMinPairs pairs, the operands that may settle it (their box holds
  // its box), the smallest box first (the one most likely to hold it closely: a node's ball
  // before the struts through it).
  constexpr std::size_t kBlock = 16384;
  auto holders = [&](u32 t, auto&& f) {
    double lo[3], hi[3];
    triangle_box(soup, t, lo, hi);
    const int i = soup.operand[t];
    for (int j : cells.at(lo)) {
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
  // Per held triangle, the first holder it has no pair with (-1: none). A triangle with a
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
    const Vec3& p = soup.verts[soup.tris[t][0]];
    const int w = winding_at(soup, p, [&](auto&& f) {
      const double lo[3] = {p.x(), p.y(), p.z()}, hi[3] = {p.x(), p.y(), INFINITY};
      trees[candidate[t]].query(lo, hi, f);
    });
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


// An operand's core: a ball strictly inside it (see the top of the file). r <= 0: none.
struct Core {
  Vec3 c = Vec3::Zero();
  double r = 0;
};

// A lower bound on the distance from p to triangle abc: the larger of the distances to its box
// and to its plane (the plane's only where the normal is not a small difference of large
// products, so that its rounding stays below a millionth).
double distance_below(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  double box2 = 0;
  for (int d = 0; d < 3; ++d) {
    const double lo = std::min({a[d], b[d], c[d]}), hi = std::max({a[d], b[d], c[d]});
    const double out = p[d] < lo ? lo - p[d] : (p[d] > hi ? p[d] - hi : 0);
    box2 += out * out;
  }
  double best = std::sqrt(box2);
  const Vec3 n = (b - a).cross(c - a);
  const double nn = n.norm();
  if (nn > 1e-6 * (b - a).norm() * (c - a).norm()) best = std::max(best, std::abs(n.dot(p - a)) / nn);
  return best;
}

// Operand j's core: its centre the mean of its triangles' centroids, where an exact ray puts that
// strictly inside; its radius the smallest distance_below() to its triangles, shrunk by a ten
// millionth of itself and by 1e-12 of the operand's extent (the bounds' rounding is some 1e-15 of
// those).
Core core_of(const Scene& sc, int j) {
  const Soup& s = sc.soup;
  const u32 a = sc.first[j], b = sc.first[j + 1];
  if (a == b) return {};
  Vec3 sum = Vec3::Zero();
  for (u32 t = a; t < b; ++t) sum += s.verts[s.tris[t][0]] + s.verts[s.tris[t][1]] + s.verts[s.tris[t][2]];
  Core k;
  k.c = sum / (3.0 * (b - a));
  if (!k.c.allFinite()) return {};
  const int w = winding_at(s, k.c, [&](auto&& f) {
    for (u32 t = a; t < b; ++t) f(t);
  });
  if (w == INT_MIN || w <= 0) return {};
  double r = INFINITY, extent = k.c.cwiseAbs().maxCoeff();
  for (u32 t = a; t < b; ++t) {
    const auto& T = s.tris[t];
    r = std::min(r, distance_below(k.c, s.verts[T[0]], s.verts[T[1]], s.verts[T[2]]));
    for (u32 v : T) extent = std::max(extent, s.verts[v].cwiseAbs().maxCoeff());
  }
  k.r = r * (1 - 1e-7) - 1e-12 * extent;
  if (!(k.r > 0) || !std::isfinite(k.r)) return {};
  return k;
}

// The operands' cores (none for an operand that settles nothing: the first operand of a
// difference), their boxes, and a grid listing the boxes, finer than the operands' grid: a pair
// or triangle looks at the cores listed in its cell (a lattice of spheres, whose cores reach past
// their neighbours' centres, listed some 14 per cell in a grid of one cell per operand, a third of
// the pairs' time).
struct Cores {
  std::vector<Core> core;
  std::vector<std::array<double, 6>> box;
  Grid cells;
  bool any = false;
};

Cores cores_of(const Scene& sc, BooleanOp op) {
  const int nops = sc.soup.operands;
  Cores k;
  k.core.resize(nops);
  parallel_for(0, static_cast<std::size_t>(nops), [&](std::size_t j) {
    if (op == BooleanOp::Difference && j == 0) return;
    k.core[j] = core_of(sc, static_cast<int>(j));
  });
  k.box.assign(nops, {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY});
  for (int j = 0; j < nops; ++j)
    if (k.core[j].r > 0) {
      k.any = true;
      for (int d = 0; d < 3; ++d) k.box[j][d] = k.core[j].c[d] - k.core[j].r, k.box[j][d + 3] = k.core[j].c[d] + k.core[j].r;
    }
  if (k.any) k.cells = sc.grid(k.box, std::clamp(static_cast<int>(2 * std::cbrt(static_cast<double>(nops))), 1, 32));
  return k;
}

// Points whose convex hull holds triangle a's part in the plane of triangle b (its chord there),
// each within `slop` of where exact arithmetic puts it; n of them (at most 6). False where a
// certainly does not meet that plane, or its coordinates are outside 1e-100 .. 1e100.
bool chord(const Vec3 a[3], const Vec3 b[3], Vec3 out[6], int& n, double& slop) {
  const Vec3 e1 = b[1] - b[0], e2 = b[2] - b[0];
  const Vec3 nb = e1.cross(e2);
  // A bound on each signed distance's rounding: about ten units in the last place of
  // |e1|_1 |e2|_1 |a - b0|_1 (the differences, the cross product, the dot product), taken as 90.
  const double scale = 1e-14 * e1.cwiseAbs().sum() * e2.cwiseAbs().sum();
  if (!(scale > 1e-250 && scale < 1e250)) return false;
  double d[3], err[3];
  for (int m = 0; m < 3; ++m) {
    d[m] = nb.dot(a[m] - b[0]);
    err[m] = scale * (a[m] - b[0]).cwiseAbs().sum();
  }
  n = 0;
  slop = 0;
  for (int m = 0; m < 3; ++m) {
    const int q = (m + 1) % 3;
    if ((d[m] > err[m] && d[q] > err[q]) || (d[m] < -err[m] && d[q] < -err[q])) continue;  // apart
    const double D = std::abs(d[m] - d[q]);
    if (D <= err[m] + err[q]) {  // the edge may lie in the plane: all of it
      out[n++] = a[m];
      out[n++] = a[q];
      continue;
    }
    // The crossing at s = d_m / (d_m - d_q): a change of the distances by their errors moves s by
    // at most (err_m + err_q) max|d| / D^2 (taken twice).
    const double s = std::clamp(d[m] / (d[m] - d[q]), 0.0, 1.0);
    out[n++] = a[m] + (a[q] - a[m]) * s;
    slop = std::max(slop, (a[q] - a[m]).norm() * 2 * (err[m] + err[q]) * std::max(std::abs(d[m]), std::abs(d[q])) / (D * D));
  }
  return n > 0;
}

// Whether the cut of triangles t and u certainly lies within distance `reach` of point c: all
// the points bounding it (one triangle's chord in the other's plane, clipped to the other's
// chord along their planes' common line where both are segments), with their errors to spare.
bool cut_within(const Vec3 t[3], const Vec3 u[3], const Vec3& c, double reach) {
  Vec3 p[6], q[6];
  int np = 0, nq = 0;
  double sp = 0, sq = 0;
  if (!chord(t, u, p, np, sp) || !chord(u, t, q, nq, sq)) return false;
  double extent = c.cwiseAbs().maxCoeff();
  for (int m = 0; m < 3; ++m) extent = std::max({extent, t[m].cwiseAbs().maxCoeff(), u[m].cwiseAbs().maxCoeff()});
  // The points' errors; clipping along a direction within 60 degrees of the chord at most doubles
  // them; the rest is the arithmetic's rounding on the coordinates.
  const double r = reach - 4 * (sp + sq) - 1e-12 * extent;
  if (!(r > 0)) return false;
  auto inside = [&](const Vec3& x) { return (x - c).squaredNorm() <= r * r; };
  if (np == 2 && nq == 2) {
    const Vec3 L = (t[1] - t[0]).cross(t[2] - t[0]).cross((u[1] - u[0]).cross(u[2] - u[0]));
    const double sp0 = L.dot(p[0]), sp1 = L.dot(p[1]), sq0 = L.dot(q[0]), sq1 = L.dot(q[1]);
    const double lo = std::max(std::min(sp0, sp1), std::min(sq0, sq1));
    const double hi = std::min(std::max(sp0, sp1), std::max(sq0, sq1));
    // p's chord clipped to [lo, hi] along L, where L runs within 60 degrees of it.
    const double span = sp1 - sp0;
    if (lo <= hi && std::abs(span) > 0.5 * L.norm() * (p[1] - p[0]).norm()) {
      auto at = [&](double x) { return p[0] + (p[1] - p[0]) * std::clamp((x - sp0) / span, 0.0, 1.0); };
      if (inside(at(lo)) && inside(at(hi))) return true;
    }
  }
  return std::all_of(p, p + np, inside) || std::all_of(q, q + nq, inside);
}

// The pairs with a triangle of kMinPairs pairs or more (`degree`) whose cut lies in the core of an
// operand that settles both their triangles; they leave `pairs`, and are returned (sorted).
template <class Settles>
std::vector<std::array<u32, 2>> drop_core_pairs(const Scene& sc, const std::vector<u32>& degree,
                                                std::vector<std::array<u32, 2>>& pairs, Settles&& settles,
                                                const Cores& cores) {
  const Soup& soup = sc.soup;
  if (!cores.any || std::none_of(pairs.begin(), pairs.end(), [&](const auto& p) {
        return degree[p[0]] >= kMinPairs || degree[p[1]] >= kMinPairs;
      }))
    return {};
  const std::vector<Core>& core = cores.core;
  const auto& core_box = cores.box;
  const Grid& cells = cores.cells;
  soup.poll();
  const std::size_t np = pairs.size();
  std::vector<char> drop(np, 0);
  parallel_blocks(np, 16384, [&](std::size_t from, std::size_t to) {
    soup.poll();
    for (std::size_t k_ = from; k_ < to; ++k_) {
      const u32 t = pairs[k_][0], u = pairs[k_][1];
      if (degree[t] < kMinPairs && degree[u] < kMinPairs) continue;
      double lo[3], hi[3], ulo[3], uhi[3], mid[3];
      triangle_box(soup, t, lo, hi);
      triangle_box(soup, u, ulo, uhi);
      for (int d = 0; d < 3; ++d) {
        lo[d] = std::max(lo[d], ulo[d]);
        hi[d] = std::min(hi[d], uhi[d]);
        mid[d] = lo[d] + (hi[d] - lo[d]) / 2;
      }
      const int i = soup.operand[t], m = soup.operand[u];
      for (int j : cells.at(mid)) {
        const auto& b = core_box[j];
        if (!settles(i, j) || !settles(m, j) || b[0] > hi[0] || b[1] > hi[1] || b[2] > hi[2] || b[3] < lo[0] ||
            b[4] < lo[1] || b[5] < lo[2])
          continue;
        // The cut lies in the boxes' overlap: not in the core where that is farther from the centre
        // than the radius (with a margin for the rounding), in it where all of it is nearer.
        const Core& k = core[j];
        double near2 = 0, far2 = 0;
        for (int d = 0; d < 3; ++d) {
          const double a = lo[d] - k.c[d], b = hi[d] - k.c[d];
          const double n = a > 0 ? a : (b < 0 ? -b : 0), f = std::max(std::abs(a), std::abs(b));
          near2 += n * n;
          far2 += f * f;
        }
        if (near2 > k.r * k.r * (1 + 1e-9)) continue;
        if (far2 < k.r * k.r * (1 - 1e-9)) {
          drop[k_] = 1;
          break;
        }
        const Vec3 T[3] = {soup.verts[soup.tris[t][0]], soup.verts[soup.tris[t][1]], soup.verts[soup.tris[t][2]]};
        const Vec3 U[3] = {soup.verts[soup.tris[u][0]], soup.verts[soup.tris[u][1]], soup.verts[soup.tris[u][2]]};
        // Nor where the line both planes hold passes farther from the centre than the radius
        // (a look that only rejects needs no care for rounding: spheres of a lattice, cut where
        // two of them meet, pass a third's core there by a few percent of its radius).
        {
          const Vec3 nt = (T[1] - T[0]).cross(T[2] - T[0]), nu = (U[1] - U[0]).cross(U[2] - U[0]);
          const Vec3 L = nt.cross(nu);
          const double LL = L.squaredNorm();
          if (LL > 0) {
            // The point of the line nearest the centre, from the centre.
            const Vec3 x = (nt.dot(T[0] - k.c) * nu.cross(L) + nu.dot(U[0] - k.c) * L.cross(nt)) / LL;
            if (x.squaredNorm() > k.r * k.r) continue;
          }
        }
        if (cut_within(T, U, k.c, k.r)) {
          drop[k_] = 1;
          break;
        }
      }
    }
  });
  const auto from = block_starts(np, 65536, [&](std::size_t lo, std::size_t hi) {
    return static_cast<std::size_t>(std::count(drop.begin() + lo, drop.begin() + hi, 1));
  });
  if (from.total() == 0) return {};
  std::vector<std::array<u32, 2>> dropped(from.total()), kept(np - from.total());
  fill_blocks(from, [&](std::size_t lo, std::size_t hi, std::size_t n) {
    for (std::size_t k = lo, x = lo - n; k < hi; ++k) (drop[k] ? dropped[n++] : kept[x++]) = pairs[k];
  });
  pairs.swap(kept);
  return dropped;
}

}  // namespace

namespace {

// Whether the inside of operand j drops the points of operand i there, whatever else holds them
// (in a union or a difference).
auto settles_for(BooleanOp op) {
  return [op](int i, int j) { return j != i && (op == BooleanOp::Union || j != 0); };
}

// Runs f(scene, degree, settles) where settling can do anything (three operands or more, a union
// or a difference, a scene with an extent).
template <class F>
void with_scene(const Soup& soup, const std::vector<std::array<u32, 2>>& pairs, BooleanOp op, F&& f) {
  // With two operands every pair is with the other one: nothing to settle.
  if (soup.operands < 3 || op == BooleanOp::Intersection || pairs.empty()) return;
  const auto settles = settles_for(op);
  const Scene sc(soup);
  if (!sc.usable()) return;
  // Per triangle, its pairs (one pass: the pairs of a neighbourhood sit together, and plain
  // increments beat atomic ones threefold here).
  std::vector<u32> degree(soup.tris.size(), 0);
  for (const auto& p : pairs) ++degree[p[0]], ++degree[p[1]];
  f(sc, degree, settles);
}

}  // namespace

// What settle_in_cores() made for settle_pairs() to use again.
struct SettleCores {
  Cores k;
};

namespace {

const Cores& cores_for(const Scene& sc, BooleanOp op, Settlement& s) {
  if (!s.cores) s.cores = std::make_shared<SettleCores>(SettleCores{cores_of(sc, op)});
  return s.cores->k;
}

}  // namespace

Settlement settle_in_cores(const Soup& soup, BooleanOp op, const std::vector<char>& checked) {
  Settlement s;
  if (soup.operands < 3 || op == BooleanOp::Intersection) return s;
  if (std::none_of(checked.begin(), checked.end(), [](char c) { return c != 0; })) return s;
  const auto settles = settles_for(op);
  const Scene sc(soup);
  if (!sc.usable()) return s;
  const Cores& cores = cores_for(sc, op, s);
  if (!cores.any) return s;
  soup.poll();
  const std::size_t nt = soup.tris.size();
  std::vector<char> in(nt, 0);
  std::atomic<bool> found{false};
  parallel_blocks(nt, 16384, [&](std::size_t lo, std::size_t hi) {
    soup.poll();
    for (std::size_t t = lo; t < hi; ++t) {
      const int i = soup.operand[t];
      if (!checked[i]) continue;
      const auto& T = soup.tris[t];
      const Vec3 *a = &soup.verts[T[0]], *b = &soup.verts[T[1]], *c = &soup.verts[T[2]];
      // A core holding the triangle holds its first vertex, and so is listed in that one's cell.
      for (int j : cores.cells.at(a->data())) {
        const Core& k = cores.core[j];
        if (!settles(i, j) || !(k.r > 0)) continue;
        const double r2 = k.r * k.r * (1 - 1e-9);
        if ((*a - k.c).squaredNorm() < r2 && (*b - k.c).squaredNorm() < r2 && (*c - k.c).squaredNorm() < r2) {
          in[t] = 1;
          found.store(true, std::memory_order_relaxed);
          break;
        }
      }
    }
  });
  if (found.load()) s.triangles.swap(in);
  return s;
}

void settle(const Soup& soup, std::vector<std::array<u32, 2>>& pairs, BooleanOp op, Settlement& s) {
  with_scene(soup, pairs, op, [&](const Scene& sc, const std::vector<u32>& degree, auto&& settles) {
    std::vector<char> more = settle_triangles(sc, degree, pairs, settles);
    if (s.triangles.empty()) s.triangles.swap(more);
    else
      for (std::size_t t = 0; t < more.size(); ++t) s.triangles[t] |= more[t];
  });
}

void settle_pairs(const Soup& soup, std::vector<std::array<u32, 2>>& pairs, BooleanOp op, Settlement& s) {
  with_scene(soup, pairs, op, [&](const Scene& sc, const std::vector<u32>& degree, auto&& settles) {
    s.pairs = drop_core_pairs(sc, degree, pairs, settles, cores_for(sc, op, s));
  });
}

}  // namespace wedge::boolean_detail
