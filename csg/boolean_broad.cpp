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

void tri_box(const Soup& s, u32 t, double lo[3], double hi[3]) {
  for (int d = 0; d < 3; ++d) {
    double a = s.verts[s.tris[t][0]][d], b = s.verts[s.tris[t][1]][d], c = s.verts[s.tris[t][2]][d];
    lo[d] = std::min({a, b, c});
    hi[d] = std::max({a, b, c});
  }
}

}  // namespace

Bvh::Bvh(const Soup& soup, std::vector<u32> ids, int d) : items(std::move(ids)), dims(d) {
  if (items.empty()) return;
  std::size_t n = items.size();
  std::vector<float> blo(n * 3), bhi(n * 3), ctr(n * 3);
  for (std::size_t i = 0; i < n; ++i) {
    double lo[3], hi[3];
    tri_box(soup, items[i], lo, hi);
    for (int a = 0; a < 3; ++a) {
      blo[i * 3 + a] = down(lo[a]);
      bhi[i * 3 + a] = up(hi[a]);
      ctr[i * 3 + a] = static_cast<float>(0.5 * (lo[a] + hi[a]));
    }
  }
  // Build over positions in a permutation; items are permuted at the end.
  std::vector<u32> perm(n);
  for (std::size_t i = 0; i < n; ++i) perm[i] = static_cast<u32>(i);
  nodes.reserve(2 * n / 2 + 1);
  struct Task { u32 node, first, count; };
  std::vector<Task> stack;
  nodes.push_back({});
  stack.push_back({0, 0, static_cast<u32>(n)});
  while (!stack.empty()) {
    Task t = stack.back();
    stack.pop_back();
    Node nd{};
    for (int a = 0; a < 3; ++a) {
      nd.lo[a] = INFINITY;
      nd.hi[a] = -INFINITY;
    }
    float clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (u32 i = t.first; i < t.first + t.count; ++i) {
      u32 p = perm[i];
      for (int a = 0; a < 3; ++a) {
        nd.lo[a] = std::min(nd.lo[a], blo[p * 3 + a]);
        nd.hi[a] = std::max(nd.hi[a], bhi[p * 3 + a]);
        clo[a] = std::min(clo[a], ctr[p * 3 + a]);
        chi[a] = std::max(chi[a], ctr[p * 3 + a]);
      }
    }
    if (t.count <= 4) {
      nd.first = t.first;
      nd.count = t.count;
      nodes[t.node] = nd;
      continue;
    }
    int axis = 0;
    for (int a = 1; a < dims; ++a)
      if (chi[a] - clo[a] > chi[axis] - clo[axis]) axis = a;
    u32 mid = t.first + t.count / 2;
    std::nth_element(perm.begin() + t.first, perm.begin() + mid, perm.begin() + t.first + t.count,
                     [&](u32 x, u32 y) {
                       float cx = ctr[x * 3 + axis], cy = ctr[y * 3 + axis];
                       return cx < cy || (cx == cy && x < y);
                     });
    nd.count = 0;
    nd.left = static_cast<u32>(nodes.size());
    nd.right = nd.left + 1;
    nodes[t.node] = nd;
    nodes.push_back({});
    nodes.push_back({});
    stack.push_back({nd.left, t.first, mid - t.first});
    stack.push_back({nd.right, mid, t.first + t.count - mid});
  }
  std::vector<u32> permuted(n);
  for (std::size_t i = 0; i < n; ++i) permuted[i] = items[perm[i]];
  items.swap(permuted);
}

std::vector<std::array<u32, 2>> candidate_pairs(const Soup& soup) {
  std::size_t n = soup.tris.size();
  std::vector<u32> all(n);
  for (std::size_t i = 0; i < n; ++i) all[i] = static_cast<u32>(i);
  Bvh bvh(soup, all, 3);
  constexpr std::size_t kBlock = 2048;
  std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<std::array<u32, 2>>> out(blocks);
  parallel_for(0, blocks, [&](std::size_t b) {
    auto& res = out[b];
    std::vector<u32> hits;
    for (std::size_t t = b * kBlock; t < std::min(n, (b + 1) * kBlock); ++t) {
      double lo[3], hi[3];
      tri_box(soup, static_cast<u32>(t), lo, hi);
      hits.clear();
      bvh.query(lo, hi, [&](u32 u) {
        if (u > t && soup.operand[u] != soup.operand[t]) {
          double ulo[3], uhi[3];
          tri_box(soup, u, ulo, uhi);
          for (int a = 0; a < 3; ++a)
            if (ulo[a] > hi[a] || uhi[a] < lo[a]) return;
          hits.push_back(u);
        }
      });
      std::sort(hits.begin(), hits.end());
      for (u32 u : hits) res.push_back({static_cast<u32>(t), u});
    }
  });
  std::vector<std::array<u32, 2>> pairs;
  std::size_t total = 0;
  for (auto& v : out) total += v.size();
  pairs.reserve(total);
  for (auto& v : out) pairs.insert(pairs.end(), v.begin(), v.end());
  return pairs;
}

}  // namespace wedge::boolean_detail
