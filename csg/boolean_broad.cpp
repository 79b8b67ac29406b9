// Broad phase: a bounding-volume hierarchy over triangle boxes (float boxes rounded outward, so
// no pair that meets is ever missed), built by median splits on the longest axis, and the
// candidate pairs of triangles of different operands whose boxes overlap. Work is split into
// fixed blocks and the blocks' results concatenated in order, so the pairs come out the same at
// any thread count.
#include <algorithm>
#include <cmath>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

namespace {

float down(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -INFINITY) : f;
}
float up(double x) {
  float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, INFINITY) : f;
}

void tri_box(const Soup& s, u32 t, double lo[3], double hi[3]) { triangle_box(s, t, lo, hi); }

}  // namespace

namespace {

// Spreads the low 21 bits of x to every third bit (Morton code).
std::uint64_t spread(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

}  // namespace

// Built in linear time after one sort: triangles in Morton order of their box centres, the tree
// the halving of that order (leaves of up to 4), boxes computed bottom-up.
Bvh::Bvh(const Soup& soup, std::vector<u32> ids, int d) : items(std::move(ids)), dims(d) {
  if (items.empty()) return;
  const std::size_t n = items.size();
  std::vector<std::array<float, 6>> box(n);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < n; ++i) {
    double blo[3], bhi[3];
    tri_box(soup, items[i], blo, bhi);
    for (int a = 0; a < 3; ++a) {
      box[i][a] = down(blo[a]);
      box[i][a + 3] = up(bhi[a]);
      lo[a] = std::min(lo[a], blo[a]);
      hi[a] = std::max(hi[a], bhi[a]);
    }
  }
  std::vector<std::pair<std::uint64_t, u32>> order(n);
  parallel_for(0, n, [&](std::size_t i) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      double ext = hi[a] - lo[a];
      double c = 0.5 * (static_cast<double>(box[i][a]) + box[i][a + 3]);
      double f = ext > 0 ? (c - lo[a]) / ext : 0.0;
      auto q = static_cast<std::uint64_t>(std::clamp(f, 0.0, 1.0) * 2097151.0);
      code |= spread(q) << a;
    }
    order[i] = {code, static_cast<u32>(i)};
  });
  std::sort(order.begin(), order.end());
  std::vector<u32> sorted(n);
  std::vector<std::array<float, 6>> sbox(n);
  for (std::size_t i = 0; i < n; ++i) {
    sorted[i] = items[order[i].second];
    sbox[i] = box[order[i].second];
  }
  items.swap(sorted);
  nodes.reserve(2 * (n / 4 + 1) + 1);
  // Build top-down by halving ranges; fill boxes bottom-up afterwards (children follow parents).
  struct Task { u32 node, first, count; };
  std::vector<Task> stack;
  nodes.push_back({});
  stack.push_back({0, 0, static_cast<u32>(n)});
  while (!stack.empty()) {
    Task t = stack.back();
    stack.pop_back();
    Node& nd = nodes[t.node];
    if (t.count <= 4) {
      nd.first = t.first;
      nd.count = t.count;
      for (int a = 0; a < 3; ++a) {
        nd.lo[a] = INFINITY;
        nd.hi[a] = -INFINITY;
      }
      for (u32 i = t.first; i < t.first + t.count; ++i)
        for (int a = 0; a < 3; ++a) {
          nd.lo[a] = std::min(nd.lo[a], sbox[i][a]);
          nd.hi[a] = std::max(nd.hi[a], sbox[i][a + 3]);
        }
      continue;
    }
    u32 half = t.count / 2;
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

// Each pair is found once: the triangles are visited in the tree's (Morton) order, and a visit
// from position p skips every subtree whose items all sit at positions <= p (a node covers a
// contiguous range of positions). Pairs are sorted at the end, so the order is the same at any
// thread count.
std::vector<std::array<u32, 2>> candidate_pairs(const Soup& soup, std::array<u32, 2>* clash, bool self) {
  std::size_t n = soup.tris.size();
  std::vector<u32> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<u32>(i);
  Bvh bvh(soup, all, 3);
  // One past the last item position under each node (children follow their parent).
  std::vector<u32> end(bvh.nodes.size());
  for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
    const Bvh::Node& nd = bvh.nodes[i];
    end[i] = nd.count ? nd.first + nd.count : end[nd.right];
  }
  constexpr std::size_t kBlock = 2048;
  std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<std::array<u32, 2>>> out(blocks);
  std::vector<std::array<u32, 2>> clashes(blocks, {kNone, kNone});
  parallel_for(0, blocks, [&](std::size_t b) {
    auto& res = out[b];
    u32 stack[128];
    for (std::size_t p = b * kBlock; p < std::min(n, (b + 1) * kBlock); ++p) {
      const u32 t = bvh.items[p];
      double lo[3], hi[3];
      tri_box(soup, t, lo, hi);
      int top = 0;
      stack[top++] = 0;
      while (top) {
        const u32 id = stack[--top];
        if (end[id] <= p + 1) continue;  // every item below sits at or before p
        const Bvh::Node& nd = bvh.nodes[id];
        bool miss = false;
        for (int d = 0; d < 3; ++d)
          if (nd.lo[d] > hi[d] || nd.hi[d] < lo[d]) miss = true;
        if (miss) continue;
        if (!nd.count) {
          stack[top++] = nd.left;
          stack[top++] = nd.right;
          continue;
        }
        for (u32 i = std::max<u32>(nd.first, static_cast<u32>(p + 1)); i < nd.first + nd.count; ++i) {
          const u32 u = bvh.items[i];
          double ulo[3], uhi[3];
          tri_box(soup, u, ulo, uhi);
          bool apart = false;
          for (int a = 0; a < 3; ++a)
            if (ulo[a] > hi[a] || uhi[a] < lo[a]) apart = true;
          if (apart) continue;
          if (soup.operand[u] != soup.operand[t] || (self && triangles_clash(soup, t, u))) {
            res.push_back({std::min(t, u), std::max(t, u)});
          } else if (clash && clashes[b][0] == kNone && triangles_clash(soup, t, u)) {
            clashes[b] = {std::min(t, u), std::max(t, u)};
          }
        }
      }
    }
  });
  if (clash) {
    *clash = {kNone, kNone};
    for (const auto& c : clashes)
      if (c[0] != kNone) {
        *clash = c;
        break;
      }
  }
  std::vector<std::array<u32, 2>> pairs;
  std::size_t total = 0;
  for (auto& v : out) total += v.size();
  pairs.reserve(total);
  for (auto& v : out) pairs.insert(pairs.end(), v.begin(), v.end());
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace wedge::boolean_detail
