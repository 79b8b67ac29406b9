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
  boxes.swap(sbox);
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
          nd.lo[a] = std::min(nd.lo[a], boxes[i][a]);
          nd.hi[a] = std::max(nd.hi[a], boxes[i][a + 3]);
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

std::vector<std::array<u32, 2>> Bvh::self_pairs(const std::vector<char>* active) const {
  if (nodes.empty()) return {};
  // Whether a subtree holds an active triangle (children follow their parent).
  std::vector<char> act(nodes.size(), 1);
  if (active)
    for (std::size_t i = nodes.size(); i-- > 0;) {
      const Node& nd = nodes[i];
      if (!nd.count) {
        act[i] = act[nd.left] | act[nd.right];
        continue;
      }
      act[i] = 0;
      for (u32 k = nd.first; k < nd.first + nd.count; ++k) act[i] |= (*active)[items[k]];
    }
  auto meet = [](const float* alo, const float* ahi, const float* blo, const float* bhi) {
    return alo[0] <= bhi[0] && blo[0] <= ahi[0] && alo[1] <= bhi[1] && blo[1] <= ahi[1] && alo[2] <= bhi[2] &&
           blo[2] <= ahi[2];
  };
  using Pair = std::array<u32, 2>;  // node ids; a == b: pairs within one subtree
  // The node pairs one step below (a, b), those worth a look.
  auto expand = [&](Pair p, std::vector<Pair>& out) {
    const Node &A = nodes[p[0]], &B = nodes[p[1]];
    auto push = [&](u32 a, u32 b) {
      if (a == b ? act[a] : (act[a] | act[b]) && meet(nodes[a].lo, nodes[a].hi, nodes[b].lo, nodes[b].hi))
        out.push_back({a, b});
    };
    if (p[0] == p[1]) {
      push(A.left, A.left);
      push(A.right, A.right);
      push(A.left, A.right);
      return;
    }
    auto size = [](const Node& n) { return (n.hi[0] - n.lo[0]) + (n.hi[1] - n.lo[1]) + (n.hi[2] - n.lo[2]); };
    if (B.count || (!A.count && size(A) >= size(B))) {
      push(A.left, p[1]);
      push(A.right, p[1]);
    } else {
      push(p[0], B.left);
      push(p[0], B.right);
    }
  };
  auto leaves = [&](Pair p) { return nodes[p[0]].count && nodes[p[1]].count; };
  // Breadth first to enough independent node pairs for the threads, then one depth-first walk each.
  std::vector<Pair> tasks;
  if (act[0]) tasks.push_back({0, 0});
  for (int round = 0; round < 12 && !tasks.empty() && tasks.size() < 512; ++round) {
    std::vector<Pair> next;
    for (Pair p : tasks) {
      if (leaves(p) || (p[0] == p[1] && nodes[p[0]].count)) next.push_back(p);
      else expand(p, next);
    }
    tasks.swap(next);
  }
  std::vector<std::vector<std::array<u32, 2>>> found(tasks.size());
  parallel_for(0, tasks.size(), [&](std::size_t k) {
    auto& res = found[k];
    std::vector<Pair> stack{tasks[k]};
    auto emit = [&](u32 i, u32 j) {
      const u32 t = items[i], u = items[j];
      if (active && !(*active)[t] && !(*active)[u]) return;
      if (!meet(boxes[i].data(), boxes[i].data() + 3, boxes[j].data(), boxes[j].data() + 3)) return;
      res.push_back({std::min(t, u), std::max(t, u)});
    };
    while (!stack.empty()) {
      const Pair p = stack.back();
      stack.pop_back();
      const Node &A = nodes[p[0]], &B = nodes[p[1]];
      if (p[0] == p[1] && A.count) {
        for (u32 i = A.first; i < A.first + A.count; ++i)
          for (u32 j = i + 1; j < A.first + A.count; ++j) emit(i, j);
      } else if (p[0] != p[1] && A.count && B.count) {
        for (u32 i = A.first; i < A.first + A.count; ++i)
          for (u32 j = B.first; j < B.first + B.count; ++j) emit(i, j);
      } else {
        expand(p, stack);
      }
    }
  });
  std::size_t total = 0;
  for (const auto& f : found) total += f.size();
  std::vector<std::array<u32, 2>> pairs;
  pairs.reserve(total);
  for (const auto& f : found) pairs.insert(pairs.end(), f.begin(), f.end());
  return pairs;
}

// The tree's self-join gives the pairs of overlapping float boxes; they are then tested on double
// boxes (and exactly, where asked) in fixed blocks, so the result is the same at any thread count.
std::vector<std::array<u32, 2>> candidate_pairs(const Soup& soup, std::array<u32, 2>* clash, bool self,
                                                const std::vector<char>* trusted) {
  std::size_t n = soup.tris.size();
  std::vector<u32> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<u32>(i);
  const auto near = Bvh(soup, all, 3).self_pairs();
  constexpr std::size_t kBlock = 4096;
  std::size_t blocks = (near.size() + kBlock - 1) / kBlock;
  std::vector<std::vector<std::array<u32, 2>>> out(blocks);
  std::vector<std::array<u32, 2>> clashes(blocks, {kNone, kNone});
  parallel_for(0, blocks, [&](std::size_t b) {
    soup.poll();
    auto& res = out[b];
    for (std::size_t k = b * kBlock; k < std::min(near.size(), (b + 1) * kBlock); ++k) {
      const u32 t = near[k][0], u = near[k][1];
      double lo[3], hi[3], ulo[3], uhi[3];
      tri_box(soup, t, lo, hi);
      tri_box(soup, u, ulo, uhi);
      bool apart = false;
      for (int a = 0; a < 3; ++a)
        if (ulo[a] > hi[a] || uhi[a] < lo[a]) apart = true;
      if (apart) continue;
      if (soup.operand[u] != soup.operand[t] || (self && triangles_clash(soup, t, u))) {
        res.push_back({t, u});
      } else if (clash && clashes[b][0] == kNone && !(trusted && (*trusted)[soup.operand[t]]) &&
                 triangles_clash(soup, t, u)) {
        clashes[b] = {t, u};
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
