// The broad phase's boxes and box tree (built in boolean_broad.cpp), split from boolean_impl.h
// (which includes this header at its end, so every stage sees the tree as before).
#pragma once

#include "csg/boolean_impl.h"

namespace wedge::boolean_detail {

// Whether the boxes [alo, ahi] and [blo, bhi] share a point on the first `dims` axes.
template <class A, class B>
inline bool box_meets(const A* alo, const A* ahi, const B* blo, const B* bhi, int dims = 3) {
  for (int d = 0; d < dims; ++d)
    if (alo[d] > bhi[d] || ahi[d] < blo[d]) return false;
  return true;
}

// Where point p lies off the box [lo, hi]: bit a below it along axis a, bit a + 3 above. ANDed
// over a triangle's corners, not zero exactly where the triangle's box misses the box (a byte
// per corner read instead of its position, for the many triangles far from a small box).
template <class B>
inline std::uint8_t off_box(const Vec3& p, const B* lo, const B* hi) {
  std::uint8_t c = 0;
  for (int a = 0; a < 3; ++a) c |= static_cast<std::uint8_t>((p[a] < lo[a]) << a | (p[a] > hi[a]) << (a + 3));
  return c;
}

// An axis-aligned box tree over triangles, for point and vertical-line queries.
class Bvh {
 public:
  // Over the triangles `ids` of the soup; boxes of `dims` axes (2: xy only, for vertical rays).
  // With `by_operand`, each operand's triangles are kept together (see boolean_broad.cpp).
  // With `slice` (for each_pair() and the broad phase's join only: a query would meet a triangle
  // once per slab), a long thin triangle lying across its box (a spoke of a fan over a disk, a
  // cut cone's side) is an item per slab of it along its box's longest axis, each slab's box
  // holding just the part of the triangle in it: the spokes of a disk's fan met each other's
  // boxes and those of every triangle along the disk's rim. A join's visit of items i, j counts
  // only where canonical(i, j).
  Bvh(const Soup& soup, std::vector<u32> ids, int dims, bool by_operand = false, bool slice = false);
  Bvh() = default;  // empty: no triangles
  // Calls f(triangle id) for every triangle whose box meets the box [lo, hi].
  template <class F>
  void query(const double lo[3], const double hi[3], F&& f) const;
  // Whether some triangle's box meets the box [lo, hi] (the walk stops at the first).
  bool meets(const double lo[3], const double hi[3]) const;
  // As query(), descending only into nodes whose (float) box `enter(lo, hi)` accepts; f(triangle
  // id) for every triangle of an accepted leaf.
  template <class Enter, class F>
  void query_if(Enter&& enter, F&& f) const;
  // Calls f(t, u), t < u, for every unordered pair of distinct triangles whose boxes (float,
  // rounded outward) overlap, of which at least one is active (active[triangle id] != 0; every
  // triangle when `active` is null). One traversal of the tree against itself instead of a query
  // per triangle: each pair of subtrees is looked at once. f is called from several threads at
  // once, in no fixed order, and nothing is collected (a self-check meets millions of
  // neighbouring pairs). `soup`, if given, is polled for a cancel request. With `cert` (and
  // `soup`: star_certificates() of that soup), pairs that shares_certified() clears are left out
  // inside the walk. With `group` (per triangle of `soup`: embedded_groups() of it), pairs within
  // one certified group are left out, and pairs of subtrees within one are not looked into.
  void each_pair(const std::vector<char>* active, const Soup* soup, const std::function<void(u32, u32)>& f,
                 const std::vector<std::uint8_t>* cert = nullptr, const std::vector<u32>* group = nullptr) const;
  struct Node { float lo[3], hi[3]; u32 first, count; u32 left, right; };  // leaf: count > 0
  std::vector<Node> nodes;
  std::vector<u32> items;
  // Where triangles were sliced, per item: its triangle's slabs (their boxes from slab_boxes[first],
  // as in `boxes`; kNone where the triangle is one item), which of them it is, and how many.
  // Empty where nothing was sliced.
  struct Slab { u32 first; std::uint8_t index, count; };
  std::vector<Slab> slabs;
  std::vector<std::array<float, 6>> slab_boxes;
  // Whether the join's visit of items i and j (boxes that meet) is the one that counts for their
  // triangles: not one triangle's two slabs, and the first of their slabs' pairs (in the order
  // of slab indices, the lower triangle id's first) whose boxes meet.
  bool canonical(u32 i, u32 j) const {
    if (slabs.empty()) return true;
    const Slab *I = &slabs[i], *J = &slabs[j];
    if (I->count == 1 && J->count == 1) return true;  // (two triangles of one item each)
    if (items[i] == items[j]) return false;
    if (items[i] > items[j]) {
      std::swap(I, J);
      std::swap(i, j);
    }
    auto box = [&](const Slab* s, u32 at, int k, float b[6]) {
      if (s->first == kNone)
        for (int r = 0; r < 6; ++r) b[r] = box_row(r)[at];
      else
        for (int r = 0; r < 6; ++r) b[r] = slab_boxes[s->first + k][r];
    };
    float a[6], b[6];
    for (int x = 0; x <= I->index; ++x) {
      box(I, i, x, a);
      for (int y = 0; y < J->count; ++y) {
        if (x == I->index && y == J->index) return true;
        box(J, j, y, b);
        if (a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5]) return false;
      }
    }
    return true;
  }
  // items[i]'s box by position i: six rows of `stride` floats (lo x, y, z, hi x, y, z), 8 boxes
  // past the items' that meet nothing (the join compares a leaf's boxes four at a time).
  std::vector<float, NoInit<float>> boxes;  // (every entry written by the constructor)
  const float* box_row(int k) const { return boxes.data() + static_cast<std::size_t>(k) * (boxes.size() / 6); }
  int dims = 3;
  // The boxes (the items' and the nodes') are of x - origin (rounded to double, then outward to
  // float), origin being the soup's operands' lowest corner: a float box at the coordinates
  // themselves is at least an ulp of the coordinate wide, and a model far from the origin (a
  // scene 1.2 wide at 1.5e8, framed to 9e-9 at 1.1) had every box overlap every other. The
  // subtraction, correctly rounded, never decreases as x grows, so boxes that overlap still do.
  // A box from outside goes through local() first.
  double origin[3] = {NAN, NAN, NAN};
  void local(const double lo[3], const double hi[3], double tlo[3], double thi[3]) const {
    for (int a = 0; a < 3; ++a) {
      tlo[a] = lo[a] - origin[a];
      thi[a] = hi[a] - origin[a];
    }
  }
};

template <class F>
void Bvh::query(const double lo[3], const double hi[3], F&& f) const {
  double tlo[3], thi[3];
  local(lo, hi, tlo, thi);
  query_if([&](const float nlo[3], const float nhi[3]) { return box_meets(nlo, nhi, tlo, thi, dims); }, f);
}

inline bool Bvh::meets(const double lo[3], const double hi[3]) const {
  bool met = false;
  double tlo[3], thi[3];
  local(lo, hi, tlo, thi);
  query_if([&](const float nlo[3], const float nhi[3]) { return !met && box_meets(nlo, nhi, tlo, thi, dims); },
           [&](u32) { met = true; });
  return met;
}

template <class Enter, class F>
void Bvh::query_if(Enter&& enter, F&& f) const {
  if (nodes.empty()) return;
  u32 stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top) {
    const Node& n = nodes[stack[--top]];
    if (!enter(n.lo, n.hi)) continue;
    if (n.count) {
      for (u32 i = n.first; i < n.first + n.count; ++i) f(items[i]);
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
}

}  // namespace wedge::boolean_detail
