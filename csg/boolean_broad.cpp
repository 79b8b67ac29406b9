// Broad phase: a bounding-volume hierarchy over triangle boxes (float boxes rounded outward, so
// no pair that meets is ever missed), built by splitting the Morton order of the boxes' centres
// at its cells' boundaries, and
// the candidate pairs of triangles of different operands whose boxes overlap, found by one
// self-join of the tree. The join is split into fixed tasks whose results are concatenated in
// order (and the candidates sorted), so the pairs come out the same at any thread count.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <tbb/task_arena.h>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

namespace {

// The floats next to f (not NaN) below and above it, by their bits (std::nextafter is a call into
// the maths library, and a tree over a million triangles takes six of these each).
float float_below(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  b = f > 0 ? b - 1 : (f < 0 ? b + 1 : 0x80000001u);  // below +-0: the least negative float
  std::memcpy(&f, &b, 4);
  return f;
}
float float_above(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  b = f < 0 ? b - 1 : (f > 0 ? b + 1 : 0x00000001u);
  std::memcpy(&f, &b, 4);
  return f;
}
// (Both neighbours made, one taken by a mask: whether rounding went up or down is a coin toss,
// and as a branch it was mispredicted half the time, six times a box: a third of a tree's build.)
float pick(bool take_g, float f, float g) {
  std::uint32_t a, b;
  std::memcpy(&a, &f, 4);
  std::memcpy(&b, &g, 4);
  const std::uint32_t m = 0u - static_cast<std::uint32_t>(take_g);
  a = (a & ~m) | (b & m);
  std::memcpy(&f, &a, 4);
  return f;
}
float down(double x) {
  const float f = static_cast<float>(x);
  return pick(static_cast<double>(f) > x, f, float_below(f));
}
float up(double x) {
  const float f = static_cast<float>(x);
  return pick(static_cast<double>(f) < x, f, float_above(f));
}

void tri_box(const Soup& s, u32 t, double lo[3], double hi[3]) { triangle_box(s, t, lo, hi); }

// How many slabs triangle t is worth cutting into across the longest axis of its box (returned
// in `axis`): 1 for most, up to 8 for one whose box's faces are far larger than the triangle (a
// long thin triangle lying diagonally across its box), about the square root of the ratio.
int slab_count(const Soup& s, u32 t, int& axis) {
  const Vec3 &p = s.verts[s.tris[t][0]], &q = s.verts[s.tris[t][1]], &r = s.verts[s.tris[t][2]];
  double lo[3], hi[3];
  triangle_box(s, t, lo, hi);
  const Vec3 e(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  if (!std::isfinite(e.sum())) return 1;
  const double faces = e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  const double area2 = (q - p).cross(r - p).norm();  // (twice the area)
  if (!(faces > 16 * area2)) return 1;               // (and 0 for a point)
  axis = e[0] >= e[1] ? (e[0] >= e[2] ? 0 : 2) : (e[1] >= e[2] ? 1 : 2);
  const double ratio = area2 > 0 ? faces / area2 : 64.0;
  return static_cast<int>(std::min(8.0, std::floor(std::sqrt(ratio))));
}

// The boxes of triangle t's k slabs across `axis`: slab m holds the points of t whose coordinate
// along the axis lies between the m-th and (m+1)-th of k + 1 cuts spread over the box's range
// (the first and last its ends), and its box those bounds along the axis and, along the others,
// the range of the slab's polygon (t's corners in the slab and its edges' crossings of the two
// cuts), widened by far more than the crossings' rounding and kept within t's box. Every point
// of t lies in a slab whose box holds it.
void slab_boxes_of(const Soup& s, u32 t, int k, int axis, std::array<double, 6>* out) {
  const Vec3* c[3] = {&s.verts[s.tris[t][0]], &s.verts[s.tris[t][1]], &s.verts[s.tris[t][2]]};
  double lo[3], hi[3];
  triangle_box(s, t, lo, hi);
  double cut[9];
  cut[0] = lo[axis];
  cut[k] = hi[axis];
  for (int m = 1; m < k; ++m) cut[m] = std::clamp(lo[axis] + (hi[axis] - lo[axis]) * m / k, lo[axis], hi[axis]);
  double slack[3];
  for (int d = 0; d < 3; ++d) slack[d] = std::ldexp(std::max(std::abs(lo[d]), std::abs(hi[d])), -44);
  for (int m = 0; m < k; ++m) {
    const double a0 = cut[m], a1 = cut[m + 1];
    double blo[3] = {INFINITY, INFINITY, INFINITY}, bhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    auto take = [&](const Vec3& x) {
      for (int d = 0; d < 3; ++d) {
        blo[d] = std::min(blo[d], x[d]);
        bhi[d] = std::max(bhi[d], x[d]);
      }
    };
    for (int i = 0; i < 3; ++i) {
      const Vec3 &p = *c[i], &q = *c[(i + 1) % 3];
      if (p[axis] >= a0 && p[axis] <= a1) take(p);
      const double pa = p[axis], qa = q[axis];
      for (double a : {a0, a1})
        if ((pa < a && a < qa) || (qa < a && a < pa)) take(p + (q - p) * ((a - pa) / (qa - pa)));
    }
    std::array<double, 6>& b = out[m];
    for (int d = 0; d < 3; ++d) {
      if (d == axis) {
        b[d] = a0;
        b[d + 3] = a1;
      } else if (blo[d] <= bhi[d]) {
        b[d] = std::max(lo[d], blo[d] - slack[d]);
        b[d + 3] = std::min(hi[d], bhi[d] + slack[d]);
      } else {
        b[d] = lo[d];
        b[d + 3] = hi[d];
      }
    }
  }
}

}  // namespace


// Built in linear time after one sort: triangles in Morton order of their box centres, the tree
// that order split where the codes' highest differing bit changes (leaves of up to 8), boxes
// computed bottom-up.
Bvh::Bvh(const Soup& soup, std::vector<u32> ids, int d, bool by_operand, bool slice) : items(std::move(ids)), dims(d) {
  if (items.empty()) return;
  // Long thin triangles across their boxes: an item per slab, each with its own box (below).
  std::vector<std::array<double, 6>> slab_box;  // per item, where any triangle is sliced
  if (slice && dims == 3) {
    std::vector<std::uint8_t> count(items.size()), along(items.size());
    parallel_for(0, items.size(), [&](std::size_t i) {
      int a = 0;
      count[i] = static_cast<std::uint8_t>(slab_count(soup, items[i], a));
      along[i] = static_cast<std::uint8_t>(a);
    });
    std::vector<std::size_t> at(items.size() + 1, 0);
    std::size_t sliced = 0;
    for (std::size_t i = 0; i < items.size(); ++i) {
      at[i + 1] = at[i] + count[i];
      sliced += count[i] > 1 ? count[i] : 0;
    }
    if (at.back() > items.size()) {
      std::vector<u32> all(at.back());
      slabs.resize(at.back());
      slab_box.resize(at.back());
      slab_boxes.resize(sliced);
      std::vector<u32> first(items.size(), kNone);
      for (std::size_t i = 0, f = 0; i < items.size(); ++i)
        if (count[i] > 1) {
          first[i] = static_cast<u32>(f);
          f += count[i];
        }
      parallel_for(0, items.size(), [&](std::size_t i) {
        const u32 t = items[i];
        if (count[i] > 1) slab_boxes_of(soup, t, count[i], along[i], slab_box.data() + at[i]);
        else triangle_box(soup, t, slab_box[at[i]].data(), slab_box[at[i]].data() + 3);
        for (std::size_t k = 0; k < count[i]; ++k) {
          all[at[i] + k] = t;
          slabs[at[i] + k] = {first[i], static_cast<std::uint8_t>(k), count[i]};
        }
      });
      items.swap(all);
    }
  }
  const std::size_t n = items.size();
  // (The arrays below are written whole before they are read: not zeroed first, serially.)
  std::vector<std::array<float, 6>, NoInit<std::array<float, 6>>> box(n);
  // The boxes are kept as offsets from the operands' lowest corner (see `origin`).
  for (const auto& b : soup.boxes)
    for (int a = 0; a < 3; ++a)
      if (std::isfinite(b[a])) origin[a] = std::isfinite(origin[a]) ? std::min(origin[a], b[a]) : b[a];
  for (double& o : origin)
    if (!std::isfinite(o)) o = 0;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  {
    // Per block, then the blocks' bounds merged (min and max: the same at any thread count).
    constexpr std::size_t kBlock = 16384;
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    std::vector<std::array<double, 6>> bound(blocks);
    parallel_for(0, blocks, [&](std::size_t b) {
      soup.poll();
      std::array<double, 6> bb = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
      for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
        double blo[3], bhi[3];
        if (slab_box.empty()) {
          tri_box(soup, items[i], blo, bhi);
        } else {
          std::copy(slab_box[i].begin(), slab_box[i].begin() + 3, blo);
          std::copy(slab_box[i].begin() + 3, slab_box[i].end(), bhi);
        }
        for (int a = 0; a < 3; ++a) {
          blo[a] -= origin[a];
          bhi[a] -= origin[a];
          box[i][a] = down(blo[a]);
          box[i][a + 3] = up(bhi[a]);
          bb[a] = std::min(bb[a], blo[a]);
          bb[a + 3] = std::max(bb[a + 3], bhi[a]);
        }
      }
      bound[b] = bb;
    });
    for (const auto& bb : bound)
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], bb[a]);
        hi[a] = std::max(hi[a], bb[a + 3]);
      }
  }
  if (!slabs.empty()) {
    parallel_for(0, n, [&](std::size_t i) {
      if (slabs[i].first != kNone) slab_boxes[slabs[i].first + slabs[i].index] = box[i];
    });
    std::vector<std::array<double, 6>>().swap(slab_box);
  }
  auto morton = [&](const float* b) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      double ext = hi[a] - lo[a];
      double c = 0.5 * (static_cast<double>(b[a]) + b[a + 3]);
      double f = ext > 0 ? (c - lo[a]) / ext : 0.0;
      auto q = static_cast<std::uint64_t>(std::clamp(f, 0.0, 1.0) * 2097151.0);
      code |= morton_spread(q) << a;
    }
    return code;
  };
  // With by_operand, the operands come one after another (in the Morton order of their boxes'
  // centres) and each one's triangles in their own order: below the top levels every node holds
  // one operand, so the join can leave out an operand's own pairs whole subtrees at a time.
  std::vector<u32> rank;
  if (by_operand) {
    // Each operand's box: per block of items, then the blocks' merged (min and max: the same at
    // any thread count).
    constexpr std::array<float, 6> kNoBox = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    constexpr std::size_t kBlock = 16384;
    const std::size_t blocks = (n + kBlock - 1) / kBlock, nops = static_cast<std::size_t>(soup.operands);
    std::vector<std::array<float, 6>> part(blocks * nops, kNoBox);
    parallel_for(0, blocks, [&](std::size_t b) {
      std::array<float, 6>* pb = part.data() + b * nops;
      for (std::size_t i = b * kBlock; i < std::min(n, (b + 1) * kBlock); ++i) {
        auto& o = pb[soup.operand[items[i]]];
        for (int a = 0; a < 3; ++a) {
          o[a] = std::min(o[a], box[i][a]);
          o[a + 3] = std::max(o[a + 3], box[i][a + 3]);
        }
      }
    });
    std::vector<std::array<float, 6>> ob(nops, kNoBox);
    for (std::size_t b = 0; b < blocks; ++b)
      for (std::size_t o = 0; o < nops; ++o)
        for (int a = 0; a < 3; ++a) {
          ob[o][a] = std::min(ob[o][a], part[b * nops + o][a]);
          ob[o][a + 3] = std::max(ob[o][a + 3], part[b * nops + o][a + 3]);
        }
    std::vector<std::pair<std::uint64_t, u32>> ops;
    for (int o = 0; o < soup.operands; ++o)
      if (ob[o][0] <= ob[o][3]) ops.push_back({morton(ob[o].data()), static_cast<u32>(o)});
    std::sort(ops.begin(), ops.end());
    rank.assign(soup.operands, 0);
    for (std::size_t r = 0; r < ops.size(); ++r) rank[ops[r].second] = static_cast<u32>(r);
  }
  // Sorted by (rank, code, index): a stable radix sort, 11 bits of the code at a time from the
  // lowest, then (with by_operand) stably by rank (another radix pass).
  struct Key {
    std::uint64_t code;
    u32 i;
    u32 rank;  // the operand's, with by_operand (else 0)
  };
  std::vector<Key, NoInit<Key>> order(n);
  parallel_for(0, n, [&](std::size_t i) {
    order[i] = {morton(box[i].data()), static_cast<u32>(i), by_operand ? rank[soup.operand[items[i]]] : 0u};
  });
  soup.poll();
  radix_sort(order, [](const Key& k) { return k.code; });
  soup.poll();
  if (by_operand) {
    int bits = 1;  // (the ranks' width: one counting pass for a few operands, not six)
    while (bits < 64 && (std::uint64_t(1) << bits) < static_cast<std::uint64_t>(soup.operands)) ++bits;
    radix_sort(order, [](const Key& k) { return static_cast<std::uint64_t>(k.rank); }, bits);  // (stable)
  }
  soup.poll();
  std::vector<u32> sorted(n);
  const std::size_t stride = n + 8;
  boxes.resize(6 * stride);
  std::vector<std::uint64_t, NoInit<std::uint64_t>> scode(n);  // the sort keys in tree order: operand rank, then code
  std::vector<u32, NoInit<u32>> srank(n);
  std::vector<Slab> sorted_slabs(slabs.size());
  parallel_for(0, n, [&](std::size_t i) {
    sorted[i] = items[order[i].i];
    if (!slabs.empty()) sorted_slabs[i] = slabs[order[i].i];
    for (int k = 0; k < 6; ++k) boxes[k * stride + i] = box[order[i].i][k];
    scode[i] = order[i].code;
    srank[i] = order[i].rank;
  });
  for (std::size_t i = n; i < stride; ++i)
    for (int k = 0; k < 6; ++k) boxes[k * stride + i] = k < 3 ? INFINITY : -INFINITY;
  // Where a range splits: at the highest bit in which its first and last keys differ (the rank's
  // bits above the code's), so that each node is one cell of the Morton grid (or one run of
  // operands), whose box is that cell's; halving the range instead made nodes that straddle a
  // cell boundary, as large as their parent, and a self-join visited six times more leaf pairs
  // than overlap. Equal keys: halved.
  auto split_of = [&](u32 first, u32 count) -> u32 {
    const u32 last = first + count - 1;
    auto first_set = [&](auto&& bit_of) {  // the first position in the range with the bit set
      u32 lo = first, hi = last;
      while (lo < hi) {
        const u32 mid = lo + (hi - lo) / 2;
        if (bit_of(mid)) hi = mid;
        else lo = mid + 1;
      }
      return lo;
    };
    if (srank[first] != srank[last]) {
      const int b = 31 - __builtin_clz(srank[first] ^ srank[last]);
      return first_set([&](u32 i) { return (srank[i] >> b & 1u) != 0; }) - first;
    }
    if (scode[first] != scode[last]) {
      const int b = 63 - __builtin_clzll(scode[first] ^ scode[last]);
      return first_set([&](u32 i) { return (scode[i] >> b & 1u) != 0; }) - first;
    }
    return count / 2;
  };
  items.swap(sorted);
  slabs.swap(sorted_slabs);
  // Leaves of up to 8 triangles: a leaf's few extra boxes cost less than the node visits they
  // save (leaves of 4 before: the 512-sphere lattice's classification 158 -> 113 ms, its output
  // 338 -> 317, at one thread). At most 2n - 1 nodes.
  constexpr u32 leaf = 8;
  nodes.reserve(2 * n);
  // Build top-down by splitting ranges (split_of); fill boxes bottom-up afterwards (children follow
  // parents).
  struct Task { u32 node, first, count; };
  std::vector<Task> stack;
  nodes.push_back({});
  stack.push_back({0, 0, static_cast<u32>(n)});
  while (!stack.empty()) {
    Task t = stack.back();
    stack.pop_back();
    Node& nd = nodes[t.node];
    if (t.count <= leaf) {
      nd.first = t.first;
      nd.count = t.count;
      for (int a = 0; a < 3; ++a) {
        nd.lo[a] = INFINITY;
        nd.hi[a] = -INFINITY;
      }
      for (u32 i = t.first; i < t.first + t.count; ++i)
        for (int a = 0; a < 3; ++a) {
          nd.lo[a] = std::min(nd.lo[a], boxes[a * stride + i]);
          nd.hi[a] = std::max(nd.hi[a], boxes[(a + 3) * stride + i]);
        }
      continue;
    }
    const u32 half = split_of(t.first, t.count);
    u32 left = static_cast<u32>(nodes.size());
    nodes[t.node].count = 0;
    nodes[t.node].left = left;
    nodes[t.node].right = left + 1;
    nodes.push_back({});
    nodes.push_back({});
    stack.push_back({left, t.first, half});
    stack.push_back({left + 1, t.first + half, t.count - half});
  }
  for (std::size_t i = nodes.size(); i-- > 0;) {
    Node& nd = nodes[i];
    if (nd.count) continue;
    const Node& l = nodes[nd.left];
    const Node& r = nodes[nd.right];
    for (int a = 0; a < 3; ++a) {
      nd.lo[a] = std::min(l.lo[a], r.lo[a]);
      nd.hi[a] = std::max(l.hi[a], r.hi[a]);
    }
  }
}

namespace {

// The tree's self-join: every unordered pair of distinct items whose float boxes overlap, at least
// one of them active, handed to visit(task, i, j) (positions in the tree's items) as the
// walk meets it; nothing is collected here, so a join of millions of neighbouring pairs (an
// operand's self-check) costs no memory. The walk is split into fixed tasks (breadth first to
// about 512 independent node pairs, then one depth-first walk each); start(number of tasks) is
// called before the tasks run, in parallel. What a task visits, and in which order, does not
// depend on the number of threads. poll() is called every few thousand leaf pairs. A node pair
// (a, b) (a == b: the pairs within one subtree) for which skip(a, b) holds is not looked into.
template <class Start, class Visit, class Poll, class Skip>
void self_join(const Bvh& bvh, const std::vector<char>* active, Start&& start, Visit&& visit, Poll&& poll,
               Skip&& skip) {
  const auto& nodes = bvh.nodes;
  const auto& items = bvh.items;
  const float *lox = bvh.box_row(0), *loy = bvh.box_row(1), *loz = bvh.box_row(2);
  const float *hix = bvh.box_row(3), *hiy = bvh.box_row(4), *hiz = bvh.box_row(5);
  if (nodes.empty()) {
    start(std::size_t(0));
    return;
  }
  // Whether each item (in tree order) is active, and whether a subtree holds an active triangle
  // (children follow their parent).
  std::vector<char> item_act;
  if (active) {
    item_act.resize(items.size());
    parallel_for(0, items.size(), [&](std::size_t i) { item_act[i] = (*active)[items[i]]; });
  }
  std::vector<char> act(nodes.size(), 1);
  if (active)
    for (std::size_t i = nodes.size(); i-- > 0;) {
      const Bvh::Node& nd = nodes[i];
      if (!nd.count) {
        act[i] = act[nd.left] | act[nd.right];
        continue;
      }
      act[i] = 0;
      for (u32 k = nd.first; k < nd.first + nd.count; ++k) act[i] |= item_act[k];
    }
  auto meet = [](const float* alo, const float* ahi, const float* blo, const float* bhi) {
    return alo[0] <= bhi[0] && blo[0] <= ahi[0] && alo[1] <= bhi[1] && blo[1] <= ahi[1] && alo[2] <= bhi[2] &&
           blo[2] <= ahi[2];
  };
  using Pair = std::array<u32, 2>;  // node ids; a == b: pairs within one subtree
  // The node pairs one step below (a, b), those worth a look.
  auto expand = [&](Pair p, std::vector<Pair>& out) {
    const Bvh::Node &A = nodes[p[0]], &B = nodes[p[1]];
    auto push = [&](u32 a, u32 b) {
      if ((a == b ? act[a] : (act[a] | act[b]) && meet(nodes[a].lo, nodes[a].hi, nodes[b].lo, nodes[b].hi)) &&
          !skip(a, b))
        out.push_back({a, b});
    };
    if (p[0] == p[1]) {
      push(A.left, A.left);
      push(A.right, A.right);
      push(A.left, A.right);
      return;
    }
    auto size = [](const Bvh::Node& n) { return (n.hi[0] - n.lo[0]) + (n.hi[1] - n.lo[1]) + (n.hi[2] - n.lo[2]); };
    if (B.count || (!A.count && size(A) >= size(B))) {
      push(A.left, p[1]);
      push(A.right, p[1]);
    } else {
      push(p[0], B.left);
      push(p[0], B.right);
    }
  };
  auto leaves = [&](Pair p) { return nodes[p[0]].count && nodes[p[1]].count; };
  std::vector<Pair> tasks;
  if (act[0] && !skip(0u, 0u)) tasks.push_back({0, 0});
  for (int round = 0; round < 12 && !tasks.empty() && tasks.size() < 512; ++round) {
    std::vector<Pair> next;
    for (Pair p : tasks) {
      if (leaves(p) || (p[0] == p[1] && nodes[p[0]].count)) next.push_back(p);
      else expand(p, next);
    }
    tasks.swap(next);
  }
  start(tasks.size());
  parallel_for(0, tasks.size(), [&](std::size_t k) {
    poll();
    std::vector<Pair> stack{tasks[k]};
    std::size_t since_poll = 0;
    // Item i against items [from, to) (at most 8, in a leaf): those whose boxes meet i's, in
    // order. Four boxes at a time where SSE is there (the rows run 8 past the last item).
    auto against = [&](u32 i, u32 from, u32 to) {
      const bool i_act = !active || item_act[i];
#if defined(__SSE2__)
      const __m128 ilx = _mm_set1_ps(lox[i]), ily = _mm_set1_ps(loy[i]), ilz = _mm_set1_ps(loz[i]);
      const __m128 ihx = _mm_set1_ps(hix[i]), ihy = _mm_set1_ps(hiy[i]), ihz = _mm_set1_ps(hiz[i]);
      for (u32 j0 = from; j0 < to; j0 += 4) {
        __m128 m = _mm_and_ps(_mm_cmple_ps(ilx, _mm_loadu_ps(hix + j0)), _mm_cmple_ps(_mm_loadu_ps(lox + j0), ihx));
        m = _mm_and_ps(m, _mm_and_ps(_mm_cmple_ps(ily, _mm_loadu_ps(hiy + j0)), _mm_cmple_ps(_mm_loadu_ps(loy + j0), ihy)));
        m = _mm_and_ps(m, _mm_and_ps(_mm_cmple_ps(ilz, _mm_loadu_ps(hiz + j0)), _mm_cmple_ps(_mm_loadu_ps(loz + j0), ihz)));
        unsigned bits = static_cast<unsigned>(_mm_movemask_ps(m));
        if (to - j0 < 4) bits &= (1u << (to - j0)) - 1;
        while (bits) {
          const u32 j = j0 + static_cast<u32>(__builtin_ctz(bits));
          bits &= bits - 1;
          if (i_act || item_act[j]) visit(k, i, j);
        }
      }
#else
      for (u32 j = from; j < to; ++j)
        if ((i_act || item_act[j]) && lox[i] <= hix[j] && lox[j] <= hix[i] && loy[i] <= hiy[j] && loy[j] <= hiy[i] &&
            loz[i] <= hiz[j] && loz[j] <= hiz[i])
          visit(k, i, j);
#endif
    };
    while (!stack.empty()) {
      const Pair p = stack.back();
      stack.pop_back();
      const Bvh::Node &A = nodes[p[0]], &B = nodes[p[1]];
      if (p[0] == p[1] && A.count) {
        for (u32 i = A.first; i + 1 < A.first + A.count; ++i) against(i, i + 1, A.first + A.count);
      } else if (p[0] != p[1] && A.count && B.count) {
        for (u32 i = A.first; i < A.first + A.count; ++i) {
          const float ilo[3] = {lox[i], loy[i], loz[i]}, ihi[3] = {hix[i], hiy[i], hiz[i]};
          if (!meet(ilo, ihi, B.lo, B.hi)) continue;  // misses all of B
          against(i, B.first, B.first + B.count);
        }
      } else {
        expand(p, stack);
        continue;
      }
      if (++since_poll == 4096) {
        since_poll = 0;
        poll();
      }
    }
  });
}

template <class T>
std::vector<T> concatenate(std::vector<std::vector<T>>& parts) {
  std::size_t total = 0;
  for (const auto& p : parts) total += p.size();
  std::vector<T> all;
  all.reserve(total);
  for (auto& p : parts) {
    all.insert(all.end(), p.begin(), p.end());
    std::vector<T>().swap(p);
  }
  return all;
}

}  // namespace

namespace {

// Per node of the tree: the group (embedded_groups) of all its triangles, kNone where they are in
// none or several; empty without groups.
std::vector<u32> node_groups(const Bvh& tree, const std::vector<u32>& group) {
  std::vector<u32> node_group;
  if (group.empty()) return node_group;
  const std::size_t nn = tree.nodes.size();
  node_group.assign(nn, kNone);
  for (std::size_t i = nn; i-- > 0;) {
    const Bvh::Node& nd = tree.nodes[i];
    if (!nd.count) {
      if (node_group[nd.left] == node_group[nd.right]) node_group[i] = node_group[nd.left];
      continue;
    }
    u32 g = group[tree.items[nd.first]];
    for (u32 k = nd.first + 1; k < nd.first + nd.count && g != kNone; ++k)
      if (group[tree.items[k]] != g) g = kNone;
    node_group[i] = g;
  }
  return node_group;
}

}  // namespace

void Bvh::each_pair(const std::vector<char>* active, const Soup* soup, const std::function<void(u32, u32)>& f,
                    const std::vector<std::uint8_t>* cert, const std::vector<u32>* group) const {
  // What a visit reads, copied in tree order (the soup's order is not the walk's): the
  // triangle's vertices and certified corners.
  struct Item {
    std::array<u32, 3> v;
    std::uint8_t cert;
  };
  std::vector<Item> item;
  if (cert && soup) {
    item.resize(items.size());
    parallel_for(0, items.size(), [&](std::size_t i) { item[i] = {soup->tris[items[i]], (*cert)[items[i]]}; });
  }
  // Node pairs within one certified group are not looked into; item pairs within one are left out.
  const std::vector<u32> node_group = group ? node_groups(*this, *group) : std::vector<u32>();
  self_join(
      *this, active, [](std::size_t) {},
      [&](std::size_t, u32 i, u32 j) {
        if (!canonical(i, j) || (!item.empty() && shares_certified(item[i].v, item[i].cert, item[j].v))) return;
        const u32 t = items[i], u = items[j];
        if (!node_group.empty() && (*group)[t] != kNone && (*group)[t] == (*group)[u]) return;
        f(std::min(t, u), std::max(t, u));
      },
      [&] {
        if (soup) soup->poll();
      },
      [&](u32 a, u32 b) { return !node_group.empty() && node_group[a] != kNone && node_group[a] == node_group[b]; });
}


// The tree's self-join visits the pairs of overlapping float boxes; each is tested on double boxes
// and kept if its triangles belong to different operands; a pair of one operand is checked for a
// clash (exactly) where asked. No list of all overlapping pairs is made: on two 1M-triangle
// spheres it would hold some 30 million pairs of neighbours, nearly all of one operand. The first
// clash is the first one met by the first task that meets one, the same at any thread count.
namespace {

// The triangles that may meet a triangle of another operand: those whose box touches a cell of a
// coarse grid that a triangle of another operand also touches (two boxes that overlap share a
// point, and its cell is in both boxes' ranges: the cell of a coordinate is monotone in it). Two
// big spheres that overlap at a cap keep only the triangles near the cap. Everything, where the
// grid would be too coarse or too busy to tell (huge triangles, one operand).
std::vector<u32> near_other_operands(const Soup& soup, std::vector<char>* outside) {
  const std::size_t n = soup.tris.size();
  constexpr std::size_t kBlock = 65536;
  auto every = [&] {
    std::vector<u32> all(n);
    parallel_blocks(n, kBlock, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t i = lo; i < hi; ++i) all[i] = static_cast<u32>(i);
    });
    return all;
  };
  if (soup.operands < 2 || n < 4096) return every();
  // Per operand, the part of its box that another operand's box may reach: its box and the box
  // around the others'. A triangle whose box is off it (every vertex on one side of it along one
  // axis) meets no other operand's triangle, and claims no cell: two overlapping spheres' grid
  // pass sees half their triangles. (A triangle of another operand whose box meets a triangle's
  // is within this box, and so claims the cells they share: no pair is lost.)
  // (The others' box from the boxes before o and those after it: linear in the operands.)
  const int nops = soup.operands;
  constexpr std::array<double, 6> kNone6 = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
  auto hull = [](std::array<double, 6> x, const std::array<double, 6>& y) {
    for (int a = 0; a < 3; ++a) x[a] = std::min(x[a], y[a]), x[a + 3] = std::max(x[a + 3], y[a + 3]);
    return x;
  };
  std::vector<std::array<double, 6>> reach(nops), after(nops + 1, kNone6);
  for (int o = nops; o-- > 0;) after[o] = hull(after[o + 1], soup.boxes[o]);
  std::array<double, 6> before = kNone6;
  for (int o = 0; o < nops; ++o) {
    const std::array<double, 6> others = hull(before, after[o + 1]);
    for (int a = 0; a < 3; ++a) {
      reach[o][a] = std::max(soup.boxes[o][a], others[a]);
      reach[o][a + 3] = std::min(soup.boxes[o][a + 3], others[a + 3]);
    }
    before = hull(before, soup.boxes[o]);
  }
  // The scene's box: the operands' (make_soup's, over their positions). (A grid over the
  // reaches alone, finer, was slower: 59 -> 63 ms on two 1M-triangle spheres.)
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const auto& bb : soup.boxes)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], bb[a]), hi[a] = std::max(hi[a], bb[a + 3]);
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!(extent > 0) || !std::isfinite(extent)) return every();
  const int g = static_cast<int>(std::clamp(1.5 * std::cbrt(static_cast<double>(n)), 8.0, 160.0));
  const double inv = g / extent;
  int dim[3];
  for (int a = 0; a < 3; ++a) dim[a] = std::clamp(static_cast<int>((hi[a] - lo[a]) * inv) + 1, 1, g);
  // (Clamped before it is made an integer: a position no triangle uses, of an operand without
  // triangles, may lie far outside the box.)
  auto cell = [&](double x, int a) {
    const double f = (x - lo[a]) * inv;
    return f <= 0 ? 0 : f >= dim[a] - 1 ? dim[a] - 1 : static_cast<int>(f);
  };
  // Cell ranges of every triangle; give up when they would visit too many cells. A cell number
  // is monotone in its coordinate, so a triangle's range is its corners' cells' least and
  // greatest: each vertex's cells are found once (half as many as the triangles' box corners,
  // and a triangle then reads 18 bytes of them instead of 72 of positions; two 1M-triangle
  // spheres' ranges took 37 ms at one thread from the boxes, 20 so).
  const std::size_t nv = soup.verts.size();
  // Per vertex: its cells (a byte per axis: at most 160 cells along each), and where it lies
  // off its operand's reach (off_box; none for a vertex that several operands share).
  std::vector<std::array<std::uint8_t, 4>> vertex_cell(nv);
  parallel_blocks(nv, 4096, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t v = lo; v < hi; ++v) {
      const Vec3& p = soup.verts[v];
      const std::int32_t op = v < soup.vertex_operand.size() ? soup.vertex_operand[v] : -1;
      for (int a = 0; a < 3; ++a) vertex_cell[v][a] = static_cast<std::uint8_t>(cell(p[a], a));
      vertex_cell[v][3] = op >= 0 ? off_box(p, reach[op].data(), reach[op].data() + 3) : 0;
    }
  });
  // A triangle off its reach gets no cells (an empty range).
  constexpr std::array<std::uint8_t, 6> kNoCells = {1, 1, 1, 0, 0, 0};
  std::vector<std::array<std::uint8_t, 6>> range(n);
  if (outside) outside->assign(n, 0);
  std::atomic<std::size_t> visits{0};
  parallel_blocks(n, 4096, [&](std::size_t lo, std::size_t hi) {
    std::size_t local = 0;
    for (std::size_t t = lo; t < hi; ++t) {
      const auto& p = vertex_cell[soup.tris[t][0]];
      const auto& q = vertex_cell[soup.tris[t][1]];
      const auto& r = vertex_cell[soup.tris[t][2]];
      if (p[3] & q[3] & r[3]) {
        range[t] = kNoCells;
        if (outside) (*outside)[t] = 1;
        continue;
      }
      std::size_t cells = 1;
      for (int a = 0; a < 3; ++a) {
        range[t][a] = std::min({p[a], q[a], r[a]});
        range[t][a + 3] = std::max({p[a], q[a], r[a]});
        cells *= static_cast<std::size_t>(range[t][a + 3] - range[t][a] + 1);
      }
      local += cells;
    }
    visits += local;
  });
  if (visits.load() > 8 * n + 1000000) {
    if (outside) outside->clear();
    return every();
  }
  soup.poll();
  // Per cell: -1 untouched, the one operand that touches it, or -2 for several (the same at any
  // thread count: only the set of operands matters). A byte a cell where the operands are few
  // (4 MB for the 160^3 cells of two 1M-triangle spheres, against 16 for a word each: the claims
  // and the look-ups after them 20 + 20 -> 18 + 17 ms at one thread). The cells are stored in
  // tiles of 4 x 4 x 4 (a cache line of bytes): a triangle's few cells, and its neighbours', are
  // then mostly in one line, where rows of 160 cells put a step along x or y 160 or 25,600
  // bytes away.
  std::vector<char> keep(n);
  const std::size_t ty = (dim[1] + 3) / 4, tz = (dim[2] + 3) / 4;
  auto at = [&](int x, int y, int z) {
    return (((static_cast<std::size_t>(x) >> 2) * ty + (y >> 2)) * tz + (z >> 2)) * 64 + ((x & 3) << 4 | (y & 3) << 2 | (z & 3));
  };
  auto mark = [&](auto zero) {
    using T = decltype(zero);
    std::vector<T, NoInit<T>> owner(static_cast<std::size_t>((dim[0] + 3) / 4) * ty * tz * 64);
    parallel_blocks(owner.size(), kBlock, [&](std::size_t lo, std::size_t hi) {
      std::fill(owner.begin() + static_cast<std::ptrdiff_t>(lo), owner.begin() + static_cast<std::ptrdiff_t>(hi), T(-1));
    });
    auto for_cells = [&](const std::array<std::uint8_t, 6>& r, auto&& f) {
      for (int x = r[0]; x <= r[3]; ++x)
        for (int y = r[1]; y <= r[4]; ++y)
          for (int z = r[2]; z <= r[5]; ++z)
            if (!f(std::atomic_ref<T>(owner[at(x, y, z)]))) return false;
      return true;
    };
    // A range the same as the last triangle's (of the same operand: neighbours in the soup's
    // order are mostly neighbours in space) is claimed once, and looked up once.
    parallel_blocks(n, 4096, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t t = lo; t < hi; ++t) {
        if (t > lo && range[t] == range[t - 1] && soup.operand[t] == soup.operand[t - 1]) continue;
        for_cells(range[t], [&](std::atomic_ref<T> o) {
          claim(o, soup.operand[t]);
          return true;
        });
      }
    });
    soup.poll();
    parallel_blocks(n, 4096, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t t = lo; t < hi; ++t)
        keep[t] = t > lo && range[t] == range[t - 1]
                      ? keep[t - 1]
                      : !for_cells(range[t], [](std::atomic_ref<T> o) { return o.load(std::memory_order_relaxed) != T(-2); });
    });
  };
  if (soup.operands <= 100) mark(std::int8_t(0));
  else mark(std::int32_t(0));
  // The kept triangles in order: per-block counts, then each block's ids in parallel.
  const auto from = block_starts(n, kBlock, [&](std::size_t lo, std::size_t hi) {
    std::size_t k = 0;
    for (std::size_t t = lo; t < hi; ++t) k += keep[t] != 0;
    return k;
  });
  std::vector<u32> out(from.total());
  fill_blocks(from, [&](std::size_t lo, std::size_t hi, std::size_t w) {
    for (std::size_t t = lo; t < hi; ++t)
      if (keep[t]) out[w++] = static_cast<u32>(t);
  });
  return out;
}

}  // namespace

std::vector<std::array<u32, 2>> candidate_pairs(const Soup& soup, std::array<u32, 2>* clash, bool self,
                                                const std::vector<char>* trusted, const std::vector<char>* active,
                                                const std::vector<char>* left_out, std::vector<char>* outside) {
  if (outside) outside->clear();
  // Where no operand's own pairs are looked at, the tree holds only the triangles near others.
  bool own = self;
  for (int op = 0; op < soup.operands && !own; ++op) own = clash && !(trusted && (*trusted)[op]);
  std::vector<u32> all;
  if (own) {
    all.resize(soup.tris.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<u32>(i);
  } else {
    all = near_other_operands(soup, outside);
  }
  if (left_out) all.erase(std::remove_if(all.begin(), all.end(), [&](u32 t) { return (*left_out)[t] != 0; }), all.end());
  // Where an operand's own pairs are checked, long thin triangles are sliced (Bvh's `slice`): an
  // imported cone of 20,000 sides (its apex's and its base's spokes, whose boxes met pairwise)
  // took 1.7 s to check, 0.24 s so. (Not in the rounding check's join: where the thin triangles
  // lie side by side, as on the classic figure's disks or near a cut apex, their slabs meet as
  // often as their boxes did, and that check took 1.5-2.4 times as long.)
  const Bvh tree(soup, std::move(all), 3, true, own);
  const std::size_t n = tree.items.size();
  std::vector<std::uint8_t> cert;
  std::vector<u32> group;
  // (Only for the pairs of one operand that are checked: none where every operand is known valid.)
  if (own) {
    cert = star_certificates(soup, trusted, active);
    group = embedded_groups(soup, trusted);
  }
  // Shells of one checked operand that touch along an edge and overlap in the wedge between two
  // of their triangles there: no pair of triangles below crosses (they share the edge).
  std::array<u32, 2> folded = {kNone, kNone};
  if (own && clash) {
    std::vector<char> checked(soup.tris.size(), 1);
    if (trusted)
      for (std::size_t t = 0; t < checked.size(); ++t) checked[t] = !(*trusted)[soup.operand[t]];
    const std::vector<u32> f = folded_edges(soup, cert, &checked);
    if (!f.empty()) folded = {f[0], f[1]};
  }
  // Per node: the operand of all its triangles (-1: several), and a vertex all its triangles
  // share with a certified star there (kNone: none). Pairs of one operand need no look unless
  // that operand is checked, and then not where both nodes hang on one certified vertex (the
  // fans of a cylinder's caps: otherwise some 600 thousand pairs for a plate's 400 cylinders).
  const std::size_t nn = tree.nodes.size();
  std::vector<std::int32_t> node_op(nn, -1);
  std::vector<u32> hub(nn, kNone);
  // Per node: the certified group of all its triangles (kNone: none, or several).
  const std::vector<u32> node_group = node_groups(tree, group);
  std::vector<u32> degree;
  if (!cert.empty()) {
    degree.assign(soup.verts.size(), 0);
    for (const auto& T : soup.tris)
      for (u32 v : T) ++degree[v];
  }
  for (std::size_t i = nn; i-- > 0;) {
    const Bvh::Node& nd = tree.nodes[i];
    if (!nd.count) {
      if (node_op[nd.left] == node_op[nd.right]) node_op[i] = node_op[nd.left];
      if (hub[nd.left] == hub[nd.right]) hub[i] = hub[nd.left];
      continue;
    }
    const u32 t0 = tree.items[nd.first];
    node_op[i] = soup.operand[t0];
    for (u32 k = nd.first + 1; k < nd.first + nd.count; ++k)
      if (soup.operand[tree.items[k]] != node_op[i]) node_op[i] = -1;
    if (cert.empty() || node_op[i] < 0) continue;
    for (int c = 0; c < 3; ++c) {
      const u32 v = soup.tris[t0][c];
      if (!(cert[t0] >> c & 1) || (hub[i] != kNone && degree[hub[i]] >= degree[v])) continue;
      bool all = true;
      for (u32 k = nd.first + 1; k < nd.first + nd.count && all; ++k) {
        const u32 t = tree.items[k];
        const auto& T = soup.tris[t];
        const int ci = T[0] == v ? 0 : T[1] == v ? 1 : T[2] == v ? 2 : -1;
        all = ci >= 0 && (cert[t] >> ci & 1);
      }
      if (all) hub[i] = v;
    }
  }
  // Per position in the tree: what the join's visit needs, in the order it walks.
  struct Item {
    std::array<u32, 3> v;
    std::int32_t op;
    u32 group;
    std::uint8_t cert;
  };
  std::vector<Item> item(n);
  parallel_for(0, n, [&](std::size_t i) {
    const u32 t = tree.items[i];
    item[i] = {soup.tris[t], soup.operand[t], group.empty() ? kNone : group[t], cert.empty() ? std::uint8_t(0) : cert[t]};
  });
  auto skip = [&](u32 a, u32 b) {
    const std::int32_t op = node_op[a];
    if (op < 0 || op != node_op[b]) return false;
    if (!self && (!clash || (trusted && (*trusted)[op]))) return true;
    if (!node_group.empty() && node_group[a] != kNone && node_group[a] == node_group[b]) return true;
    return hub[a] != kNone && hub[a] == hub[b];
  };
  std::vector<std::vector<std::array<u32, 2>>> out;
  std::vector<std::array<u32, 2>> clashes;
  self_join(
      tree, active,
      [&](std::size_t tasks) {
        out.resize(tasks);
        clashes.assign(tasks, {kNone, kNone});
      },
      [&](std::size_t k, u32 i, u32 j) {
        // A pair of one operand matters only to a check, and not where a certified star holds
        // both; decided on the items' copies in tree order (no look at the soup's tables).
        const Item &I = item[i], &J = item[j];
        const bool same = I.op == J.op;
        if (same && (self ? false : !clash || clashes[k][0] != kNone || (trusted && (*trusted)[I.op]))) return;
        if (same && (shares_certified(I.v, I.cert, J.v) || (I.group != kNone && I.group == J.group))) return;
        if (!tree.canonical(i, j)) return;
        u32 t = tree.items[i], u = tree.items[j];
        if (t > u) std::swap(t, u);
        double lo[3], hi[3], ulo[3], uhi[3];
        tri_box(soup, t, lo, hi);
        tri_box(soup, u, ulo, uhi);
        for (int a = 0; a < 3; ++a)
          if (ulo[a] > hi[a] || uhi[a] < lo[a]) return;
        // (A pair of one operand proved apart by doubles needs no exact test: a cone's fan.)
        if (!same ? !apart(soup, t, u, false) : (self && !apart(soup, t, u, false) && triangles_clash(soup, t, u))) {
          out[k].push_back({t, u});
        } else if (!self && !apart(soup, t, u, false) && triangles_clash(soup, t, u)) {
          clashes[k] = {t, u};
        }
      },
      [&] { soup.poll(); }, skip);
  if (clash) {
    *clash = folded;
    for (const auto& c : clashes)
      if (c[0] != kNone && folded[0] == kNone) {
        *clash = c;
        break;
      }
  }
  soup.poll();
  std::vector<std::array<u32, 2>> pairs = concatenate(out);
  radix_sort(pairs, [](const std::array<u32, 2>& p) { return static_cast<std::uint64_t>(p[0]) << 32 | p[1]; });
  soup.poll();
  return pairs;
}

}  // namespace wedge::boolean_detail
