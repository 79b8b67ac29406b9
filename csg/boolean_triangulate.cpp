// Retriangulation: every input triangle that another operand touches is cut into pieces along
// its intersection segments, so that the pieces of all operands meet edge to edge.
//
// 1. Each candidate pair is intersected exactly (boolean_intersect.cpp), in parallel.
// 2. The implicit points are interned (one id per symbolic definition or exact position, with the
//    ids of a pass in pair order, in parallel runs: boolean_intern.cpp), and every
//    triangle's points are compared exactly with each other: equal points get one id (the
//    smallest, so an input vertex wins) through a union-find over the whole run. Two points
//    equal anywhere both lie on some triangle that lists both, so this finds every coincidence
//    that matters.
//    Then two cut triangles of one face that make a flat convex quadrilateral become one work,
//    and the cut points on their shared diagonal that only join two collinear segments go
//    (flat_quads, boolean_quads.cpp).
// 3. Within each triangle, segments that cross properly make a new point, the meeting of T's
//    plane with the two segments' cutting planes (a TPI); these are interned and merged the same
//    way, so the crossing of the same three surfaces gets one id in all three triangles.
// 4. Each segment is split at every point of its triangle that lies on it, and the triangle is
//    triangulated: chords from edge to edge directly (boundary_cuts), anything else by a
//    constrained Delaunay triangulation (boolean_cdt.cpp: the points are ids, and orientation is
//    the exact predicate of boolean_exact.cpp in the projection along the triangle's axis). The
//    in-circle test behind the Delaunay flips (Points::incircle_certain) flips only where it is
//    certain; where four points are too close to cocircular for its filter and both splits are
//    well shaped (a tessellated circle cut by a plane), the split in place stays without exact
//    arithmetic. Inside thin slivers it works in the metric that makes the sliver equilateral.
// Work is split per triangle and concatenated in triangle order, so the result does not depend
// on the number of threads.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include "csg/boolean_impl.h"
#include "kernel/error.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

namespace {

// --- union-find over point ids (the representative is the smallest id) ---

class Merge {
 public:
  u32 find(u32 x) {
    grow(x);
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(u32 a, u32 b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (a < b) parent_[b] = a;
    else parent_[a] = b;
  }
  u32 rep(u32 x) const {  // read-only find (after all unions)
    if (x >= parent_.size()) return x;
    while (parent_[x] != x) x = parent_[x];
    return x;
  }

 private:
  void grow(u32 x) {
    while (parent_.size() <= x) parent_.push_back(static_cast<u32>(parent_.size()));
  }
  std::vector<u32> parent_;
};

bool boxes_overlap(const std::array<double, 6>& a, const std::array<double, 6>& b) {
  for (int i = 0; i < 3; ++i)
    if (a[i] > b[i + 3] || b[i] > a[i + 3]) return false;
  return true;
}

std::array<double, 6> seg_box(const Points& pts, u32 a, u32 b) {
  const auto& x = pts.box(a);
  const auto& y = pts.box(b);
  return {std::min(x[0], y[0]), std::min(x[1], y[1]), std::min(x[2], y[2]),
          std::max(x[3], y[3]), std::max(x[4], y[4]), std::max(x[5], y[5])};
}

// Pairs (i, j), i < j, of boxes that overlap: a sweep along x.
template <class F>
void overlapping(const std::vector<std::array<double, 6>>& boxes, F&& f) {
  std::vector<u32> order(boxes.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](u32 a, u32 b) {
    return boxes[a][0] < boxes[b][0] || (boxes[a][0] == boxes[b][0] && a < b);
  });
  for (std::size_t x = 0; x < order.size(); ++x)
    for (std::size_t y = x + 1; y < order.size() && boxes[order[y]][0] <= boxes[order[x]][3]; ++y)
      if (boxes_overlap(boxes[order[x]], boxes[order[y]])) f(std::min(order[x], order[y]), std::max(order[x], order[y]));
}

// Unites every two equal points among `ids` (exact) in `merge`. Points whose coordinates are doubles (input
// vertices, and the points interned by their exact position) are equal where their coordinates
// are: grouped by a hash of them. The others ("loose") go through a grid: each into every cell
// its box meets, each double point into the cell of its position, all sorted by cell (radix), and
// in each cell that holds a loose point two points whose boxes overlap are compared exactly. Equal points share the cell of
// their exact position, so none is missed. Points already united (the same point met by several
// definitions, a sponge's cut of one diagonal by a dozen faces on one plane) are not compared
// again: a class of m points costs about m exact tests rather than m^2 / 2.
void equal_points(const Points& pts, const std::vector<u32>& ids, Merge& merge) {
  if (ids.size() < 2) return;
  const Soup& soup = pts.soup();
  auto known = [&](u32 x, u32 y) { return merge.find(x) == merge.find(y); };
  std::vector<u32> loose, doubles;
  for (u32 p : ids) (pts.is_double(p) ? doubles : loose).push_back(p);
  {
    // Equal doubles: an open-addressing table of positions (-0 and +0 hash alike).
    std::size_t size = 16;
    while (size < 2 * doubles.size()) size *= 2;
    std::vector<u32> table(size, kNone);
    for (std::size_t n = 0; n < doubles.size(); ++n) {
      if ((n & 0xffff) == 0) soup.poll();
      const u32 p = doubles[n];
      const Vec3& at = pts.approx(p);
      std::size_t slot = position_hash(at) & (size - 1);
      for (; table[slot] != kNone; slot = (slot + 1) & (size - 1))
        if (pts.approx(table[slot]) == at) {
          merge.unite(p, table[slot]);
          break;
        }
      if (table[slot] == kNone) table[slot] = p;
    }
  }
  if (loose.empty()) return;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (u32 p : loose)
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], pts.approx(p)[i]);
      hi[i] = std::max(hi[i], pts.approx(p)[i]);
    }
  double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  double cell = size > 0 ? size / std::max(1.0, std::cbrt(static_cast<double>(loose.size()))) : 1.0;
  struct Entry {
    std::uint64_t key;
    u32 id;
    u32 loose;  // 1 for a loose point's entry, 0 for a double's
  };
  std::vector<Entry> entries;
  std::vector<u32> wide;  // boxes too wide for the grid (exact fallbacks): compared with all
  entries.reserve(loose.size() + doubles.size());
  // Cell numbers are clamped in double before they become integers: an exact fallback's box can
  // be far wider than the whole scene at extreme scales, and converted as it was, its cell number
  // overflowed, the box visited no cell, and its point was never compared (two equal points left
  // apart: "Unauthorized intersections of constraints" at 1e-90). Cells -8 and beyond the far
  // side hold no loose point.
  // (A product by the inverse rather than a quotient: any rounding serves that keeps the cell
  // number monotone in x, as both do.)
  const double inv = 1.0 / cell;
  const double top[3] = {(hi[0] - lo[0]) * inv, (hi[1] - lo[1]) * inv, (hi[2] - lo[2]) * inv};
  auto cell_of = [&](double x, int i) {
    const double f = std::floor((x - lo[i]) * inv);
    return f >= -4 && f <= top[i] + 4 ? f : -8.0;  // NaN too
  };
  // A loose box's cells along axis i, or false where it spans more than three (then it is
  // compared with every point).
  auto cells = [&](double b0, double b1, int i, std::int64_t& c0, std::int64_t& c1) {
    const double f0 = cell_of(b0, i), f1 = cell_of(b1, i);
    if (!(f0 > -8 && f1 > -8 && f1 - f0 <= 2)) return false;
    c0 = static_cast<std::int64_t>(f0);
    c1 = static_cast<std::int64_t>(f1);
    return true;
  };
  // Cells are numbered densely (cell -4 of each axis first): the keys span about as many values
  // as there are loose points, so a radix sort orders them in two or three passes. (cell is at
  // least the largest extent / cbrt(loose points): top[i] + 9 cells per axis fit in 21 bits.)
  std::uint64_t dim[3];
  for (int i = 0; i < 3; ++i) dim[i] = static_cast<std::uint64_t>(top[i] >= 0 && top[i] < 4e6 ? top[i] : 0.0) + 10;
  auto key_of = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(z + 4) * dim[1] + static_cast<std::uint64_t>(y + 4)) * dim[0] +
           static_cast<std::uint64_t>(x + 4);
  };
  std::size_t polled = 0;
  for (u32 p : loose) {
    if ((++polled & 0xffff) == 0) soup.poll();
    const auto b = pts.box(p);
    std::int64_t c0[3], c1[3];
    bool ok = true;
    for (int i = 0; i < 3 && ok; ++i) ok = cells(b[i], b[i + 3], i, c0[i], c1[i]);
    if (!ok) {
      wide.push_back(p);
      continue;
    }
    for (std::int64_t x = c0[0]; x <= c1[0]; ++x)
      for (std::int64_t y = c0[1]; y <= c1[1]; ++y)
        for (std::int64_t z = c0[2]; z <= c1[2]; ++z) entries.push_back({key_of(x, y, z), p, 1});
  }
  // The double points, each in the cell of its position (a double's box is its point; one
  // outside every loose point's cells is in none); cells without a loose point are passed over
  // below.
  for (u32 p : doubles) {
    if ((++polled & 0xffff) == 0) soup.poll();
    const Vec3& at = pts.approx(p);
    const double f[3] = {cell_of(at[0], 0), cell_of(at[1], 1), cell_of(at[2], 2)};
    if (f[0] > -8 && f[1] > -8 && f[2] > -8)
      entries.push_back({key_of(static_cast<std::int64_t>(f[0]), static_cast<std::int64_t>(f[1]), static_cast<std::int64_t>(f[2])), p, 0});
  }
  soup.poll();
  // (The order within a cell does not matter: the classes, and their representatives, the
  // smallest ids, are the same in any order of comparison.)
  radix_sort(entries, [](const Entry& e) { return e.key; });
  soup.poll();
  // Two doubles were paired above: a pair is compared here where one of them is loose.
  for (std::size_t i = 0; i < entries.size();) {
    if ((++polled & 0xffff) == 0) soup.poll();
    std::size_t j = i;
    u32 loose_here = 0;
    while (j < entries.size() && entries[j].key == entries[i].key) loose_here |= entries[j++].loose;
    if (!loose_here) {  // doubles only
      i = j;
      continue;
    }
    if (j - i <= 16) {
      // Each point against one point of each class met so far in the cell (at most one test
      // per class: equality is transitive, and two equal points' boxes both hold their exact
      // position); boxes that meet are checked for a union already made before the exact test.
      u32 reps[16];
      std::array<double, 6> rep_box[16];
      std::size_t nr = 0;
      for (std::size_t a = i; a < j; ++a) {
        const Entry& x = entries[a];
        const std::array<double, 6> xb = pts.box(x.id);
        bool found = false;
        for (std::size_t r = 0; r < nr && !found; ++r) {
          const Entry& y = entries[reps[r]];
          found = x.id != y.id && (x.loose | y.loose) && boxes_overlap(xb, rep_box[r]) &&
                  (known(x.id, y.id) || pts.equal(x.id, y.id));
          if (found) merge.unite(x.id, y.id);
        }
        if (!found) {
          rep_box[nr] = xb;
          reps[nr++] = static_cast<u32>(a);
        }
      }
    } else {
      // A crowded cell (nearly coincident operands put all their points near a few corners):
      // a sweep along x compares only the points whose boxes overlap there.
      std::vector<u32> crowd;
      std::vector<std::array<double, 6>> boxes;
      for (std::size_t a = i; a < j; ++a) {
        crowd.push_back(static_cast<u32>(a));
        boxes.push_back(pts.box(entries[a].id));
      }
      overlapping(boxes, [&](u32 a, u32 b) {
        if ((++polled & 0xfff) == 0) soup.poll();
        const Entry &x = entries[crowd[a]], &y = entries[crowd[b]];
        if (x.id != y.id && (x.loose | y.loose) && !known(x.id, y.id) && pts.equal(x.id, y.id)) merge.unite(x.id, y.id);
      });
    }
    i = j;
  }
  for (u32 w : wide) {
    soup.poll();
    for (u32 p : ids)
      if (p != w && boxes_overlap(pts.box(w), pts.box(p)) && !known(w, p) && pts.equal(w, p)) merge.unite(w, p);
  }
}

template <class T>
void unique_sorted(std::vector<T>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

// A uniform grid over a cut triangle's projection (axes u, v), about one cell a point, each point
// in every cell its box meets. A plate's face cut by 200 holes holds 12,800 points and as many
// segments; a slab along one axis holds every hole in its column, a cell a few points (the
// points on each segment: 8 -> 3 ms a face).
class PointGrid {
 public:
  static constexpr std::size_t kFrom = 512;  // points from which a triangle's are gridded

  void build(const std::vector<std::array<double, 6>>& boxes, int u, int v) {
    axis_[0] = u;
    axis_[1] = v;
    double hi[2] = {-INFINITY, -INFINITY};
    lo_[0] = lo_[1] = INFINITY;
    for (const auto& b : boxes)
      for (int d = 0; d < 2; ++d) {
        lo_[d] = std::min(lo_[d], b[axis_[d]]);
        hi[d] = std::max(hi[d], b[axis_[d] + 3]);
      }
    const double eu = hi[0] - lo_[0], ev = hi[1] - lo_[1], n = static_cast<double>(boxes.size());
    const double nu = eu > 0 && ev > 0 ? std::sqrt(n * eu / ev) : 1.0;
    n_[0] = static_cast<std::size_t>(std::clamp(nu, 1.0, 4096.0));
    n_[1] = static_cast<std::size_t>(std::clamp(n / static_cast<double>(n_[0]), 1.0, 4096.0));
    scale_[0] = eu > 0 ? static_cast<double>(n_[0]) / eu : 0.0;  // (infinite or NaN boxes: cell 0)
    scale_[1] = ev > 0 ? static_cast<double>(n_[1]) / ev : 0.0;
    // Counts per cell, their prefix, then each point at its cells' next free places.
    start_.assign(n_[0] * n_[1] + 1, 0);
    for (const auto& b : boxes) cells(b, [&](std::size_t c) { ++start_[c + 1]; });
    for (std::size_t c = 0; c + 1 < start_.size(); ++c) start_[c + 1] += start_[c];
    points_.resize(start_.back());
    next_.assign(start_.begin(), start_.end() - 1);
    for (std::size_t q = 0; q < boxes.size(); ++q)
      cells(boxes[q], [&](std::size_t c) { points_[next_[c]++] = static_cast<u32>(q); });
    stamp_.assign(boxes.size(), 0);
    mark_ = 0;
  }

  // Calls f(i) once for each point i in the cells that box b meets.
  template <class F>
  void near(const std::array<double, 6>& b, F&& f) {
    ++mark_;
    cells(b, [&](std::size_t c) {
      for (std::size_t x = start_[c]; x < start_[c + 1]; ++x) {
        const u32 i = points_[x];
        if (stamp_[i] == mark_) continue;  // (a box over several cells)
        stamp_[i] = mark_;
        f(i);
      }
    });
  }

 private:
  int axis_[2] = {0, 1};
  double lo_[2] = {0, 0}, scale_[2] = {0, 0};
  std::size_t n_[2] = {1, 1};
  std::vector<u32> start_, points_, next_, stamp_;
  u32 mark_ = 0;

  std::size_t cell(double x, int d) const {
    const double f = std::floor((x - lo_[d]) * scale_[d]);
    return f > 0 ? (f < static_cast<double>(n_[d] - 1) ? static_cast<std::size_t>(f) : n_[d] - 1) : 0;  // NaN: 0
  }
  template <class F>
  void cells(const std::array<double, 6>& b, F&& f) const {
    const std::size_t u0 = cell(b[axis_[0]], 0), u1 = cell(b[axis_[0] + 3], 0);
    const std::size_t v0 = cell(b[axis_[1]], 1), v1 = cell(b[axis_[1] + 3], 1);
    for (std::size_t v = v0; v <= v1; ++v)
      for (std::size_t u = u0; u <= u1; ++u) f(v * n_[0] + u);
  }
};

// An axis along which a != b, preferring the longest approximate extent.
int split_axis(const Points& pts, u32 a, u32 b) {
  Vec3 d = (pts.approx(b) - pts.approx(a)).cwiseAbs();
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int x, int y) { return d[x] > d[y]; });
  for (int i : order)
    if (pts.compare(a, b, i) != 0) return i;
  return -1;
}

// T (soup triangle t, seen along e_k) cut by segments from boundary to boundary: every point of
// `points` is a corner of T or lies inside one of its edges, and the constraints are chords
// between them (or pieces of T's edges). The chords cut T into convex pieces; where each piece
// is a triangle or a quadrilateral (split by the diagonal the Delaunay test prefers, the one the
// triangulation would keep), they go to `out`, counter-clockwise seen from outside T's operand,
// and the answer is true; otherwise nothing is made and the answer is false.
bool boundary_cuts(const Points& pts, const Soup& soup, u32 t, int k, const std::vector<u32>& points,
                   const std::vector<std::array<u32, 2>>& constraints, double well, const Points::Metric* metric,
                   std::vector<Piece>& out) {
  const auto& T = soup.tris[t];
  const std::array<u32, 3> p = soup.axis_sign[t] > 0 ? T : std::array<u32, 3>{T[0], T[2], T[1]};  // ccw seen along k
  // Per-thread arrays, reused (this runs for most cut triangles, and allocating was much of it).
  thread_local std::array<std::vector<u32>, 3> on;
  thread_local std::vector<u32> ring;
  thread_local std::vector<std::array<int, 2>> chords, todo;
  thread_local std::vector<int> pool;
  thread_local std::vector<Piece> made;
  for (auto& e : on) e.clear();
  ring.clear();
  chords.clear();
  made.clear();
  // The boundary counter-clockwise: p0, the points inside edge p0 p1 in order, p1, ...
  for (u32 x : points) {
    if (x == p[0] || x == p[1] || x == p[2]) continue;
    int edge = -1;
    for (int i = 0; i < 3; ++i)
      if (pts.orient2d(p[i], p[(i + 1) % 3], x, k) == 0) {
        if (edge >= 0) return false;
        edge = i;
      }
    if (edge < 0) return false;  // inside T
    on[edge].push_back(x);
  }
  for (int i = 0; i < 3; ++i) {
    ring.push_back(p[i]);
    auto& e = on[i];
    if (e.size() > 1) {
      const int axis = split_axis(pts, p[i], p[(i + 1) % 3]);
      if (axis < 0) return false;
      const int dir = pts.compare(p[i], p[(i + 1) % 3], axis);
      std::sort(e.begin(), e.end(), [&](u32 x, u32 y) { return pts.compare(x, y, axis) == dir; });
    }
    ring.insert(ring.end(), e.begin(), e.end());
  }
  const int n = static_cast<int>(ring.size());
  auto pos = [&](u32 x) {
    for (int i = 0; i < n; ++i)
      if (ring[i] == x) return i;
    return -1;
  };
  for (const auto& c : constraints) {
    const int a = pos(c[0]), b = pos(c[1]);
    if (a < 0 || b < 0) return false;
    if ((a + 1) % n == b || (b + 1) % n == a) continue;  // a piece of T's boundary
    chords.push_back({a, b});
  }
  if (chords.empty()) return false;
  auto emit = [&](u32 x, u32 y, u32 z) {
    std::array<u32, 3> v = {x, y, z};
    if (soup.axis_sign[t] < 0) std::swap(v[1], v[2]);
    made.push_back({v, t});
  };
  // Split the polygon (ring positions, counter-clockwise) by the first chord between two of its
  // non-adjacent vertices; a polygon no chord splits is a piece. The polygons to do are ranges of
  // `pool`.
  pool.resize(static_cast<std::size_t>(n));
  pool.reserve(static_cast<std::size_t>(n) * (chords.size() + 2) * 2);  // every split fits: no reallocation
  for (int i = 0; i < n; ++i) pool[i] = i;
  todo.assign(1, {0, n});
  std::size_t used = 0;
  while (!todo.empty()) {
    const auto [b, e] = todo.back();
    todo.pop_back();
    const int* poly = pool.data() + b;
    const int m = e - b;
    int si = -1, sj = -1;
    for (const auto& c : chords) {
      int i = -1, j = -1;
      for (int q = 0; q < m; ++q) {
        if (poly[q] == c[0]) i = q;
        if (poly[q] == c[1]) j = q;
      }
      if (i < 0 || j < 0 || (i + 1) % m == j || (j + 1) % m == i) continue;
      si = std::min(i, j);
      sj = std::max(i, j);
      break;
    }
    if (si >= 0) {
      ++used;
      // The part from si to sj, then the rest: sj to the end and round to si.
      const int first = static_cast<int>(pool.size());
      for (int q = si; q <= sj; ++q) pool.push_back(pool[b + q]);
      todo.push_back({first, static_cast<int>(pool.size())});
      const int second = static_cast<int>(pool.size());
      for (int q = sj; q < m; ++q) pool.push_back(pool[b + q]);
      for (int q = 0; q <= si; ++q) pool.push_back(pool[b + q]);
      todo.push_back({second, static_cast<int>(pool.size())});
      continue;
    }
    if (m == 3) {
      emit(ring[poly[0]], ring[poly[1]], ring[poly[2]]);
    } else if (m == 4) {
      const u32 q0 = ring[poly[0]], q1 = ring[poly[1]], q2 = ring[poly[2]], q3 = ring[poly[3]];
      if ((metric ? pts.incircle_certain(q0, q1, q2, q3, k, well, *metric) : pts.incircle_certain(q0, q1, q2, q3, k, well)) ==
          1) {
        emit(q0, q1, q3);
        emit(q1, q2, q3);
      } else {
        emit(q0, q1, q2);
        emit(q0, q2, q3);
      }
    } else {
      return false;  // a larger piece: the triangulation below
    }
  }
  if (used != chords.size()) return false;  // a chord that split nothing: crossing or repeated
  out.insert(out.end(), made.begin(), made.end());
  return true;
}

}  // namespace

Arrangement arrange(Points& pts, const std::vector<std::array<u32, 2>>& pairs, bool group_quads,
                    const Settlement* settled) {
  const Soup& soup = pts.soup();
  const std::size_t nt = soup.tris.size();

  // 1. Exact pair intersections, in parallel per block of pairs, kept in the block's flat arrays
  // (one PairCut per thread is reused: nothing is allocated per pair). Blocks of 128: the 839 pairs
  // of two 4k-triangle spheres were one block of 1024, on one thread.
  constexpr std::size_t kCutBlock = 128;
  const std::size_t cut_blocks = (pairs.size() + kCutBlock - 1) / kCutBlock;
  std::vector<std::vector<Segment>> block_segs(cut_blocks);
  std::vector<std::vector<PointDef>> block_points(cut_blocks);
  std::vector<PairCutView> cuts(pairs.size());
  parallel_for(0, cut_blocks, [&](std::size_t b) {
    thread_local PairCut cut;
    struct Where {
      u32 t0, nt, u0, nu, p0, np;
      bool coplanar;
    };
    std::array<Where, kCutBlock> where;
    const std::size_t lo = b * kCutBlock, hi = std::min(pairs.size(), lo + kCutBlock);
    auto& segs = block_segs[b];
    auto& points = block_points[b];
    for (std::size_t i = lo; i < hi; ++i) {
      if ((i & 63) == 0) soup.poll();
      intersect_pair(pts, pairs[i][0], pairs[i][1], cut);
      Where& w = where[i - lo];
      w.t0 = static_cast<u32>(segs.size());
      segs.insert(segs.end(), cut.segs_t.begin(), cut.segs_t.end());
      w.u0 = static_cast<u32>(segs.size());
      segs.insert(segs.end(), cut.segs_u.begin(), cut.segs_u.end());
      w.p0 = static_cast<u32>(points.size());
      points.insert(points.end(), cut.points.begin(), cut.points.end());
      w.nt = static_cast<u32>(cut.segs_t.size());
      w.nu = static_cast<u32>(cut.segs_u.size());
      w.np = static_cast<u32>(cut.points.size());
      w.coplanar = cut.coplanar;
    }
    for (std::size_t i = lo; i < hi; ++i) {  // the arrays are complete: their views
      const Where& w = where[i - lo];
      PairCutView& v = cuts[i];
      v.segs_t = std::span<const Segment>(segs.data() + w.t0, w.nt);
      v.segs_u = std::span<const Segment>(segs.data() + w.u0, w.nu);
      v.points = std::span<const PointDef>(points.data() + w.p0, w.np);
      v.coplanar = w.coplanar;
    }
  });

  // 2. Interning (boolean_intern.cpp): per triangle cut, its segments and points as ids.
  std::vector<u32> slot, touched;
  Works work;
  Interner intern(pts);
  intern.intern_cuts(pairs, cuts, slot, touched, work);
  std::vector<PairCutView>().swap(cuts);
  std::vector<std::vector<Segment>>().swap(block_segs);
  std::vector<std::vector<PointDef>>().swap(block_points);
  pts.evaluate_added();

  Merge merge;
  // With `near` (a box), only the points whose boxes meet it.
  auto merge_round = [&](const std::array<double, 6>* near) {
    // Each point once, in the order first met (a mark per point instead of sorting them all).
    std::vector<u32> ids;
    std::vector<char> seen(pts.size(), 0);
    auto take = [&](u32 p) {
      if (!seen[p]) {
        seen[p] = 1;
        if (near && !boxes_overlap(pts.box(p), *near)) return;
        ids.push_back(p);
      }
    };
    for (std::size_t w = 0; w < work.size(); ++w) {
      if ((w & 0xfff) == 0) soup.poll();
      for (u32 p : work[w].points) take(p);
      for (u32 v : soup.tris[touched[w]]) take(v);
    }
    soup.poll();
    equal_points(pts, ids, merge);
  };
  merge_round(nullptr);

  // 3. Proper crossings of segments within each triangle.
  auto canon_work = [&](TriWork& w) {
    for (auto& p : w.points) p = merge.rep(p);
    unique_sorted(w.points);
    // Drop repeated segments (same end points), keeping the first cut plane: sorted by end
    // points, then by place. (Per-thread scratch: nothing allocated per triangle.)
    thread_local std::vector<std::pair<std::array<u32, 2>, u32>> keyed;
    thread_local std::vector<Plane> planes;
    keyed.clear();
    for (std::size_t i = 0; i < w.segs.size(); ++i) {
      u32 a = merge.rep(w.segs[i][0]), b = merge.rep(w.segs[i][1]);
      if (a == b) continue;
      if (a > b) std::swap(a, b);
      keyed.push_back({{a, b}, static_cast<u32>(i)});
    }
    std::sort(keyed.begin(), keyed.end());
    planes.assign(w.cuts.begin(), w.cuts.end());
    w.segs.clear();
    w.cuts.clear();
    for (std::size_t i = 0; i < keyed.size(); ++i) {
      if (i > 0 && keyed[i].first == keyed[i - 1].first) continue;
      w.segs.push_back(keyed[i].first);
      w.cuts.push_back(planes[keyed[i].second]);
    }
  };
  auto canon_all = [&] {
    parallel_for(0, work.size(), [&](std::size_t w) {
      if ((w & 0xfff) == 0) soup.poll();
      canon_work(work[w]);
    });
  };
  canon_all();
  // Flat quadrilaterals: two cut triangles of one face in one work, the cut points on their
  // diagonal left out (boolean_quads.cpp). Not where classify asks about left-out cuts per triangle.
  FlatQuads quads;
  quads.quad.assign(work.size(), {kNone, kNone, kNone, kNone});
  quads.absorbed.assign(work.size(), 0);
  if (group_quads) {
    std::vector<char> fixed;
    if (settled && !settled->empty()) {
      fixed.assign(nt, 0);
      if (!settled->triangles.empty())
        for (std::size_t t = 0; t < nt; ++t) fixed[t] = settled->triangles[t];
      for (const auto& p : settled->pairs) fixed[p[0]] = fixed[p[1]] = 1;
    }
    quads = flat_quads(pts, touched, work, fixed.empty() ? nullptr : &fixed);
  }
  {
    std::vector<std::vector<PointDef>> crossings(work.size());
    parallel_for(0, work.size(), [&](std::size_t wi) {
      soup.poll();
      const TriWork& w = work[wi];
      u32 t = touched[wi];
      int k = soup.axis[t];
      std::vector<std::array<double, 6>> boxes(w.segs.size());
      for (std::size_t i = 0; i < w.segs.size(); ++i) boxes[i] = seg_box(pts, w.segs[i][0], w.segs[i][1]);
      std::size_t polled = 0;
      overlapping(boxes, [&](u32 x, u32 y) {
        if ((++polled & 0x3ff) == 0) soup.poll();
        auto [a, b] = w.segs[x];
        auto [c, d] = w.segs[y];
        if (a == c || a == d || b == c || b == d) return;
        int o1 = pts.orient2d(a, b, c, k), o2 = pts.orient2d(a, b, d, k);
        if (o1 * o2 >= 0) return;
        int o3 = pts.orient2d(c, d, a, k), o4 = pts.orient2d(c, d, b, k);
        if (o3 * o4 >= 0) return;
        PointDef p;
        p.kind = PointDef::Tpi;
        p.P[0] = Plane::of_triangle(soup.tris[t]);
        p.P[1] = w.cuts[x];
        p.P[2] = w.cuts[y];
        crossings[wi].push_back(p);
      });
    });
    std::vector<u32> added;
    soup.poll();
    for (std::size_t wi = 0; wi < work.size(); ++wi)
      for (const auto& p : crossings[wi]) {
        added.push_back(intern(p));
        work[wi].points.push_back(added.back());
      }
    if (!added.empty()) {
      pts.evaluate_added();
      // The points met before were merged among themselves: a crossing's point can equal only
      // points whose boxes meet its own, all inside the crossings' box (the classic figure's
      // three cylinders cross in a few places: 0.5 ms for all the points again, serial).
      std::array<double, 6> near = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
      for (u32 p : added) {
        const auto b = pts.box(p);
        for (int i = 0; i < 3; ++i) near[i] = std::min(near[i], b[i]), near[i + 3] = std::max(near[i + 3], b[i + 3]);
      }
      merge_round(&near);
      canon_all();
    }
  }

  // 4. Split segments at the points on them, and triangulate.
  std::vector<std::vector<Piece>> cut_pieces(work.size());
  std::vector<std::vector<std::array<u32, 3>>> cut_inner(work.size());  // empty: none known
  auto triangulate_one = [&](std::size_t wi) {
    soup.poll();
    if (quads.absorbed[wi]) return;  // its triangle's pieces are its partner's
    TriWork& w = work[wi];
    u32 t = touched[wi];
    int k = soup.axis[t];
    const auto& T = soup.tris[t];
    const std::array<u32, 4>& quad = quads.quad[wi];
    const bool is_quad = quad[0] != kNone;

    // Per-thread arrays, reused from triangle to triangle (most triangles are small, and their
    // allocations were a good part of their time).
    thread_local std::vector<u32> points, by_lo, on;
    thread_local PointGrid grid;
    thread_local std::vector<std::array<double, 6>> pboxes;
    thread_local std::vector<std::array<u32, 2>> constraints;
    points.assign(w.points.begin(), w.points.end());
    for (u32 v : T) points.push_back(v);
    if (is_quad) points.push_back(quad[1]);  // the partner's far corner
    unique_sorted(points);
    pboxes.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) pboxes[i] = pts.box(points[i]);
    // The points that may lie on a segment. Many (a plate's face cut by hundreds of holes) go in
    // a grid over T's projection; few are sorted along T's longer projected axis, so each segment
    // looks only at the points in its own slab.
    const bool gridded = points.size() >= PointGrid::kFrom;
    int sweep = (k + 1) % 3;
    double widest = 0;
    if (gridded) {
      grid.build(pboxes, (k + 1) % 3, (k + 2) % 3);
    } else {
      const Vec3 &A = soup.verts[T[0]], &B = soup.verts[T[1]], &C = soup.verts[T[2]];
      const int other = (k + 2) % 3;
      auto extent = [&](int d) { return std::max({A[d], B[d], C[d]}) - std::min({A[d], B[d], C[d]}); };
      if (extent(other) > extent(sweep)) sweep = other;
      by_lo.resize(points.size());
      std::iota(by_lo.begin(), by_lo.end(), 0u);
      std::sort(by_lo.begin(), by_lo.end(), [&](u32 x, u32 y) { return pboxes[x][sweep] < pboxes[y][sweep]; });
      for (const auto& b : pboxes) widest = std::max(widest, b[sweep + 3] - b[sweep]);
    }
    constraints.clear();
    std::size_t polled = 0;  // a large triangle (a plate's face) is long work: poll within it
    for (std::size_t si = 0; si < w.segs.size(); ++si) {
      const auto& s = w.segs[si];
      if ((++polled & 0xff) == 0) soup.poll();
      u32 a = s[0], b = s[1];
      auto sb = seg_box(pts, a, b);
      int axis = split_axis(pts, a, b);
      if (axis < 0) continue;
      on.clear();
      auto consider = [&](std::size_t i) {
        const u32 p = points[i];
        if (p == a || p == b || !boxes_overlap(sb, pboxes[i])) return;
        // The segment is T's plane cut by w.cuts[si]: a point on that plane is on its line.
        if (pts.orient2d(a, b, p, k, &w.cuts[si]) != 0) return;
        if (pts.compare(a, p, axis) * pts.compare(p, b, axis) > 0) on.push_back(p);
      };
      if (gridded) {
        grid.near(sb, consider);
      } else {
        auto first = std::partition_point(by_lo.begin(), by_lo.end(),
                                          [&](u32 x) { return pboxes[x][sweep] < sb[sweep] - widest; });
        for (auto it = first; it != by_lo.end() && pboxes[*it][sweep] <= sb[sweep + 3]; ++it) consider(*it);
      }
      int dir = pts.compare(a, b, axis);
      std::sort(on.begin(), on.end(), [&](u32 x, u32 y) { return pts.compare(x, y, axis) == dir; });
      u32 prev = a;
      for (u32 p : on) {
        constraints.push_back({prev, p});
        prev = p;
      }
      constraints.push_back({prev, b});
    }
    // Overlapping segments (an edge of T cut by two operands, say) split into the same pieces;
    // each piece is one constraint.
    for (auto& c : constraints)
      if (c[0] > c[1]) std::swap(c[0], c[1]);
    unique_sorted(constraints);
    // Inside a sliver (a long cylinder's side triangle) every piece is a sliver too. Where T is
    // thin (a smallest sine under 0.02: a side of a cylinder of 128 sides has 0.009) and its
    // points are constructed (not all exact doubles in the projection), the Delaunay test works in
    // the metric of the linear map that makes T equilateral: its pieces are as well shaped there
    // as any triangle's, and the filter decides where the plain test needed exact arithmetic for
    // most of its calls (the classic figure's cylinders crossing each other: 47 -> 38 ms, and its
    // result rounds without a re-resolution). Elsewhere the plain test, on doubles where the
    // points are, settles for half of T's own smallest sine: on a sponge's bars (0.037) the
    // metric made recovering the constraints costlier than the filter saved, and a map too far
    // from a rotation (a sine under 1e-3) cannot be held in doubles.
    const int ti = (k + 1) % 3, tj = (k + 2) % 3;
    double sine = triangle_min_sine(soup.verts[T[0]], soup.verts[T[1]], soup.verts[T[2]], ti, tj);
    if (is_quad)
      sine = std::min(sine, triangle_min_sine(soup.verts[quad[0]], soup.verts[quad[1]], soup.verts[quad[2]], ti, tj));
    double well = std::min(0.01, 0.5 * sine);
    Points::Metric metric{1, 0, 1};
    bool stretched = false;
    const bool doubles = std::all_of(points.begin(), points.end(),
                                     [&](u32 p) { return (pts.fixed(p) >> ti & 1) && (pts.fixed(p) >> tj & 1); });
    if (!is_quad && sine < 0.02 && sine >= 1e-3 && !doubles) {
      const std::array<u32, 3> c = soup.axis_sign[t] > 0 ? T : std::array<u32, 3>{T[0], T[2], T[1]};
      const Vec3 &p0 = soup.verts[c[0]], &p1 = soup.verts[c[1]], &p2 = soup.verts[c[2]];
      const double ax = p1[ti] - p0[ti], ay = p1[tj] - p0[tj], bx = p2[ti] - p0[ti], by = p2[tj] - p0[tj];
      const double det = ax * by - bx * ay;
      // M = F E^-1, with E the edge vectors as columns and F those of the unit equilateral
      // triangle; q = M^T M, scaled to its largest entry (a positive factor: the same test).
      const double h = std::sqrt(3.0) / 2;
      const double m11 = (by - 0.5 * ay) / det, m12 = (0.5 * ax - bx) / det;
      const double m21 = -h * ay / det, m22 = h * ax / det;
      double q11 = m11 * m11 + m21 * m21, q12 = m11 * m12 + m21 * m22, q22 = m12 * m12 + m22 * m22;
      const double scale = std::max(q11, q22);
      q11 /= scale, q12 /= scale, q22 /= scale;
      // Positive definite with room to spare, so the doubles held are too.
      if (std::isfinite(scale) && scale > 0 && q11 > 0 && q22 > 0 && q11 * q22 - q12 * q12 > 1e-9 * q11 * q22) {
        metric = {q11, q12, q22};
        stretched = true;
        well = 0.01;
      }
    }
    // The commonest cuts, chords from edge to edge and nothing inside T, without building a
    // triangulation.
    if (!is_quad && constraints.size() <= 4 && points.size() <= 9 &&
        boundary_cuts(pts, soup, t, k, points, constraints, well, stretched ? &metric : nullptr, cut_pieces[wi]))
      return;
    // Many points (a plate's face) go in along a Morton curve over their projection, so each
    // insertion starts its walk beside the last one's triangle.
    std::vector<u32> order;
    if (points.size() >= 512) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
      for (u32 p : points) {
        const Vec3& a = pts.approx(p);
        lo[0] = std::min(lo[0], a[i]), hi[0] = std::max(hi[0], a[i]);
        lo[1] = std::min(lo[1], a[j]), hi[1] = std::max(hi[1], a[j]);
      }
      std::vector<std::pair<std::uint64_t, u32>> keyed(points.size());
      for (std::size_t q = 0; q < points.size(); ++q) {
        const Vec3& a = pts.approx(points[q]);
        auto cell = [&](double v, int d) {
          const double f = hi[d] > lo[d] ? (v - lo[d]) / (hi[d] - lo[d]) : 0.0;
          return static_cast<std::uint64_t>((f > 0 ? (f < 1 ? f : 1.0) : 0.0) * 2097151.0);  // NaN: 0
        };
        keyed[q] = {morton_spread(cell(a[i], 0)) | morton_spread(cell(a[j], 1)) << 1, points[q]};
      }
      std::sort(keyed.begin(), keyed.end());
      order.reserve(points.size());
      for (const auto& x : keyed) order.push_back(x.second);
    }
    const std::array<u32, 3> ccw = soup.axis_sign[t] > 0 ? T : std::array<u32, 3>{T[0], T[2], T[1]};
    std::vector<std::array<u32, 3>> made;
    auto& inner = cut_inner[wi];
    try {
      if (is_quad) {
        const std::array<u32, 4> ccw4 = soup.axis_sign[t] > 0 ? quad : std::array<u32, 4>{quad[0], quad[3], quad[2], quad[1]};
        constrained_delaunay_quad(pts, k, well, ccw4, order.empty() ? points : order, constraints, made, &inner);
      } else {
        constrained_delaunay(pts, k, well, ccw, order.empty() ? points : order, constraints, made, &inner,
                             stretched ? &metric : nullptr);
      }
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& e) {
      // Cannot happen when the constraints are split right; say where if it does.
      fail("boolean: internal error retriangulating triangle #", soup.local[t] + 1, " of operand ", soup.operand[t] + 1,
           ": ", e.what());
    }
    auto& out = cut_pieces[wi];
    out.reserve(made.size());
    for (auto v : made) {
      if (soup.axis_sign[t] < 0) std::swap(v[1], v[2]);
      out.push_back({v, t});
    }
    // Turned over, edge e of a piece is edge 2 - e of the triangle made.
    if (soup.axis_sign[t] < 0)
      for (auto& nb : inner) std::swap(nb[0], nb[2]);
  };
  // A few large triangles (a plate's face cut by hundreds of holes) can be most of this step,
  // each on one thread. Every thread takes the next item from one counter: the large triangles
  // one at a time, largest first, then the rest in blocks; so the large ones start at once, side
  // by side, and the rest fill in around them. (Run as tasks, a task group's own thread took the
  // blocks first and the plate's second face waited for them: 25 ms of 37 at two threads where
  // 19 would do.) Each triangle's pieces are its own, whichever thread makes them.
  auto size = [&](u32 wi) { return work[wi].points.size() + work[wi].segs.size(); };
  std::vector<u32> order(work.size());
  std::iota(order.begin(), order.end(), 0u);
  const std::size_t heavy = static_cast<std::size_t>(
      std::stable_partition(order.begin(), order.end(), [&](u32 wi) { return size(wi) >= 512; }) - order.begin());
  std::stable_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(heavy),
                   [&](u32 a, u32 b) { return size(a) > size(b); });
  constexpr std::size_t kBlock = 64;
  const std::size_t items = heavy + (order.size() - heavy + kBlock - 1) / kBlock;
  std::atomic<std::size_t> next{0};
  const std::size_t threads = thread_count();
  parallel_for(0, std::min(threads, items), [&](std::size_t) {
    for (std::size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < items;) {
      const std::size_t lo = i < heavy ? i : heavy + (i - heavy) * kBlock;
      const std::size_t hi = i < heavy ? i + 1 : std::min(order.size(), lo + kBlock);
      for (std::size_t k = lo; k < hi; ++k) triangulate_one(order[k]);
    }
  });

  Arrangement arr;
  arr.quads = quads.groups;
  arr.quad_points = quads.dropped;
  if (quads.groups > 0)
    for (std::size_t wi = 0; wi < work.size(); ++wi)
      if (quads.quad[wi][0] != kNone || quads.absorbed[wi]) arr.quad_tris.push_back(touched[wi]);
  if (!quads.erased.empty()) {
    arr.quad_partner.assign(nt, kNone);
    for (const auto& e : quads.erased) {
      arr.quad_partner[e[0]] = e[1];
      arr.quad_partner[e[1]] = e[0];
    }
  }
  // The pieces in triangle order, with the triangulated ones' inner neighbours and coplanar
  // triangles: counted per block of triangles, then each block written from its starts.
  constexpr std::size_t kTris = 16384;
  const std::size_t blocks = (nt + kTris - 1) / kTris;
  std::vector<std::array<std::size_t, 3>> from(blocks + 1, {0, 0, 0});  // pieces, inner, coplanar
  parallel_for(0, blocks, [&](std::size_t b) {
    soup.poll();
    std::array<std::size_t, 3> n{0, 0, 0};
    for (std::size_t t = b * kTris, e = std::min(nt, t + kTris); t < e; ++t) {
      if (slot[t] == kNone) {
        ++n[0];
      } else if (!quads.absorbed[slot[t]]) {  // (else in its partner's pieces)
        unique_sorted(work[slot[t]].coplanar);
        n[0] += cut_pieces[slot[t]].size();
        n[1] += cut_inner[slot[t]].size();
        n[2] += work[slot[t]].coplanar.size();
      }
    }
    from[b + 1] = n;
  });
  for (std::size_t b = 0; b < blocks; ++b)
    for (int k = 0; k < 3; ++k) from[b + 1][k] += from[b][k];
  arr.pieces.resize(from[blocks][0]);
  arr.inner.resize(from[blocks][1]);
  if (from[blocks][2] > 0) {
    arr.coplanar_from.resize(nt + 1);
    arr.coplanar_ids.resize(from[blocks][2]);
    arr.coplanar_from[nt] = static_cast<u32>(from[blocks][2]);
  }
  parallel_for(0, blocks, [&](std::size_t b) {
    auto [np, ni, nc] = from[b];
    for (std::size_t t = b * kTris, e = std::min(nt, t + kTris); t < e; ++t) {
      if (!arr.coplanar_from.empty()) arr.coplanar_from[t] = static_cast<u32>(nc);
      if (slot[t] == kNone) {
        arr.pieces[np++] = {soup.tris[t], static_cast<u32>(t)};
        continue;
      }
      if (quads.absorbed[slot[t]]) continue;
      const u32 base = static_cast<u32>(np);
      for (std::size_t q = 0; q < cut_inner[slot[t]].size(); ++q) {
        const auto& nb = cut_inner[slot[t]][q];
        arr.inner[ni++] = {base + static_cast<u32>(q),
                           {nb[0] == kNone ? kNone : base + nb[0], nb[1] == kNone ? kNone : base + nb[1],
                            nb[2] == kNone ? kNone : base + nb[2]}};
      }
      for (const auto& p : cut_pieces[slot[t]]) arr.pieces[np++] = p;
      for (u32 u : work[slot[t]].coplanar) arr.coplanar_ids[nc++] = u;
    }
  });
  return arr;
}

}  // namespace wedge::boolean_detail
