// Broad phase: a bounding-volume hierarchy over triangle boxes (float boxes rounded outward, so
// no pair that meets is ever missed), built by halving the Morton order of the boxes' centres, and
// the candidate pairs of triangles of different operands whose boxes overlap, found by one
// self-join of the tree. The join is split into fixed tasks whose results are concatenated in
// order (and the candidates sorted), so the pairs come out the same at any thread count.
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
    if ((i & 0xffff) == 0) soup.poll();
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
  soup.poll();
  std::sort(order.begin(), order.end());
  soup.poll();
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

namespace {

// The tree's self-join: every unordered pair of distinct items whose float boxes overlap, at least
// one of them active, handed to visit(task, t, u) (triangle ids, in no particular order) as the
// walk meets it; nothing is collected here, so a join of millions of neighbouring pairs (an
// operand's self-check) costs no memory. The walk is split into fixed tasks (breadth first to
// about 512 independent node pairs, then one depth-first walk each); start(number of tasks) is
// called before the tasks run, in parallel. What a task visits, and in which order, does not
// depend on the number of threads. poll() is called every few thousand leaf pairs.
template <class Start, class Visit, class Poll>
void self_join(const Bvh& bvh, const std::vector<char>* active, Start&& start, Visit&& visit, Poll&& poll) {
  const auto& nodes = bvh.nodes;
  const auto& items = bvh.items;
  const auto& boxes = bvh.boxes;
  if (nodes.empty()) {
    start(std::size_t(0));
    return;
  }
  // Whether a subtree holds an active triangle (children follow their parent).
  std::vector<char> act(nodes.size(), 1);
  if (active)
    for (std::size_t i = nodes.size(); i-- > 0;) {
      const Bvh::Node& nd = nodes[i];
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
    const Bvh::Node &A = nodes[p[0]], &B = nodes[p[1]];
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
  if (act[0]) tasks.push_back({0, 0});
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
    auto emit = [&](u32 i, u32 j) {
      const u32 t = items[i], u = items[j];
      if (active && !(*active)[t] && !(*active)[u]) return;
      if (!meet(boxes[i].data(), boxes[i].data() + 3, boxes[j].data(), boxes[j].data() + 3)) return;
      visit(k, t, u);
    };
    while (!stack.empty()) {
      const Pair p = stack.back();
      stack.pop_back();
      const Bvh::Node &A = nodes[p[0]], &B = nodes[p[1]];
      if (p[0] == p[1] && A.count) {
        for (u32 i = A.first; i < A.first + A.count; ++i)
          for (u32 j = i + 1; j < A.first + A.count; ++j) emit(i, j);
      } else if (p[0] != p[1] && A.count && B.count) {
        for (u32 i = A.first; i < A.first + A.count; ++i)
          for (u32 j = B.first; j < B.first + B.count; ++j) emit(i, j);
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

std::vector<std::array<u32, 2>> Bvh::self_pairs(const std::vector<char>* active, const Soup* soup) const {
  std::vector<std::vector<std::array<u32, 2>>> found;
  self_join(
      *this, active, [&](std::size_t n) { found.resize(n); },
      [&](std::size_t k, u32 t, u32 u) { found[k].push_back({std::min(t, u), std::max(t, u)}); },
      [&] {
        if (soup) soup->poll();
      });
  return concatenate(found);
}

// The tree's self-join visits the pairs of overlapping float boxes; each is tested on double boxes
// and kept if its triangles belong to different operands; a pair of one operand is checked for a
// clash (exactly) where asked. No list of all overlapping pairs is made: on two 1M-triangle
// spheres it would hold some 30 million pairs of neighbours, nearly all of one operand. The first
// clash is the first one met by the first task that meets one, the same at any thread count.
std::vector<std::array<u32, 2>> candidate_pairs(const Soup& soup, std::array<u32, 2>* clash, bool self,
                                                const std::vector<char>* trusted) {
  std::size_t n = soup.tris.size();
  std::vector<u32> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<u32>(i);
  const Bvh tree(soup, std::move(all), 3);
  std::vector<std::vector<std::array<u32, 2>>> out;
  std::vector<std::array<u32, 2>> clashes;
  self_join(
      tree, nullptr,
      [&](std::size_t tasks) {
        out.resize(tasks);
        clashes.assign(tasks, {kNone, kNone});
      },
      [&](std::size_t k, u32 t, u32 u) {
        if (t > u) std::swap(t, u);
        double lo[3], hi[3], ulo[3], uhi[3];
        tri_box(soup, t, lo, hi);
        tri_box(soup, u, ulo, uhi);
        for (int a = 0; a < 3; ++a)
          if (ulo[a] > hi[a] || uhi[a] < lo[a]) return;
        if (soup.operand[u] != soup.operand[t] || (self && triangles_clash(soup, t, u))) {
          out[k].push_back({t, u});
        } else if (clash && clashes[k][0] == kNone && !(trusted && (*trusted)[soup.operand[t]]) &&
                   triangles_clash(soup, t, u)) {
          clashes[k] = {t, u};
        }
      },
      [&] { soup.poll(); });
  if (clash) {
    *clash = {kNone, kNone};
    for (const auto& c : clashes)
      if (c[0] != kNone) {
        *clash = c;
        break;
      }
  }
  soup.poll();
  std::vector<std::array<u32, 2>> pairs = concatenate(out);
  std::sort(pairs.begin(), pairs.end());
  soup.poll();
  return pairs;
}

}  // namespace wedge::boolean_detail
