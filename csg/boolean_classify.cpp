// Classification: which pieces bound the result, and which way they face.
//
// Pieces of one operand joined across an edge that no other operand's piece uses form a patch;
// a patch cannot cross another operand's surface, so it is all inside or all outside it. Per
// patch one piece is tested:
// - against an operand with a triangle coplanar with it and covering it (the piece's centroid
//   strictly inside that triangle, exactly): the piece lies on that operand's boundary, with the
//   same or the opposite orientation;
// - against every other operand, by the winding number of the piece's centroid (an implicit
//   point) along a vertical ray: each triangle whose xy-projection holds the centroid and whose
//   plane passes above it adds the sign of its normal's z. Ties (the ray through an edge or a
//   vertex) are broken by Simulation of Simplicity: the centroid moves by (eps, eps^2) in x and
//   y, so a ray never hits an edge; vertical triangles are then never hit.
// With the membership m_j of both sides of the piece (m_i = 1 behind it, 0 in front; coplanar
// operands as their orientation says), the piece is kept facing out if the result holds the
// space behind it and not in front, kept reversed if the other way round, and dropped otherwise.
// Coplanar pieces of several operands that are kept are kept once: by the lowest operand.
#include <algorithm>
#include <map>
#include <numeric>

#include "csg/boolean_impl.h"
#include "kernel/error.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

namespace {

int orient2d_xy(const Soup& s, u32 a, u32 b, u32 c) {
  const Vec3 &A = s.verts[a], &B = s.verts[b], &C = s.verts[c];
  return orient2d_fast(A.x(), A.y(), B.x(), B.y(), C.x(), C.y());
}

// orient2d(a, b, centroid) in xy with the Simulation-of-Simplicity tie break.
int orient_sos(const Points& pts, u32 a, u32 b, const std::array<u32, 3>& piece) {
  int s = pts.orient2d_centroid(a, b, piece, 2);
  if (s != 0) return s;
  const Vec3& A = pts.soup().verts[a];
  const Vec3& B = pts.soup().verts[b];
  if (A.y() != B.y()) return A.y() > B.y() ? 1 : -1;
  return B.x() > A.x() ? 1 : (B.x() < A.x() ? -1 : 0);
}

bool membership(BooleanOp op, const std::vector<char>& m) {
  switch (op) {
    case BooleanOp::Union:
      return std::any_of(m.begin(), m.end(), [](char x) { return x != 0; });
    case BooleanOp::Intersection:
      return std::all_of(m.begin(), m.end(), [](char x) { return x != 0; });
    case BooleanOp::Difference:
      return m[0] && std::none_of(m.begin() + 1, m.end(), [](char x) { return x != 0; });
  }
  return false;
}

}  // namespace

std::vector<std::int8_t> classify(const Points& pts, const Arrangement& arr, BooleanOp op) {
  const Soup& soup = pts.soup();
  const auto& pieces = arr.pieces;
  const std::size_t np = pieces.size();
  const int nops = soup.operands;

  // Patches: union pieces of one operand across edges used by exactly those two pieces.
  struct Half {
    std::uint64_t key;
    u32 piece;
  };
  std::vector<Half> half(np * 3);
  parallel_for(0, np, [&](std::size_t i) {
    for (int e = 0; e < 3; ++e) {
      u32 a = pieces[i].v[e], b = pieces[i].v[(e + 1) % 3];
      if (a > b) std::swap(a, b);
      half[i * 3 + e] = {static_cast<std::uint64_t>(a) << 32 | b, static_cast<u32>(i)};
    }
  });
  std::sort(half.begin(), half.end(), [](const Half& x, const Half& y) {
    return x.key < y.key || (x.key == y.key && x.piece < y.piece);
  });
  Dsu dsu(np);
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    while (j < half.size() && half[j].key == half[i].key) ++j;
    if (j - i == 2 && soup.operand[pieces[half[i].piece].tri] == soup.operand[pieces[half[i + 1].piece].tri])
      dsu.unite(half[i].piece, half[i + 1].piece);
    i = j;
  }
  std::vector<u32> patch_of(np);
  std::vector<u32> reps;  // representative piece per patch (its smallest piece)
  for (std::size_t i = 0; i < np; ++i) {
    u32 r = dsu.find(static_cast<u32>(i));
    if (r == i) reps.push_back(static_cast<u32>(i));
    patch_of[i] = r;
  }

  // A vertical-ray tree over all triangles.
  std::vector<u32> all(soup.tris.size());
  std::iota(all.begin(), all.end(), 0u);
  Bvh bvh(soup, all, 2);

  std::vector<std::int8_t> patch_keep(np, 0);
  parallel_for(0, reps.size(), [&](std::size_t ri) {
    u32 pi = reps[ri];
    const Piece& piece = pieces[pi];
    u32 t = piece.tri;
    int i = soup.operand[t];
    int k = soup.axis[t];
    // Coplanar operands covering the piece: +1 same orientation, -1 opposite.
    std::map<int, int> coplanar;
    for (u32 u : arr.coplanar[t]) {
      int j = soup.operand[u];
      if (j == i || coplanar.count(j)) continue;
      const auto& U = soup.tris[u];
      int o = pts.orient2d(U[0], U[1], U[2], k);  // U's orientation seen along k
      bool inside = true;
      for (int e = 0; e < 3 && inside; ++e)
        if (pts.orient2d_centroid(U[e], U[(e + 1) % 3], piece.v, k) * o <= 0) inside = false;
      if (inside) coplanar[j] = (o > 0) == (soup.axis_sign[t] > 0) ? 1 : -1;
    }
    // Winding numbers of the centroid with respect to every other operand.
    std::map<int, int> winding;
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min({pts.box(piece.v[0])[d], pts.box(piece.v[1])[d], pts.box(piece.v[2])[d]});
      hi[d] = std::max({pts.box(piece.v[0])[d + 3], pts.box(piece.v[1])[d + 3], pts.box(piece.v[2])[d + 3]});
    }
    bvh.query(lo, hi, [&](u32 u) {
      int j = soup.operand[u];
      if (j == i || coplanar.count(j)) return;
      const auto& U = soup.tris[u];
      int o = orient2d_xy(soup, U[0], U[1], U[2]);
      if (o == 0) return;  // vertical: the perturbed ray misses it
      for (int e = 0; e < 3; ++e)
        if (orient_sos(pts, U[e], U[(e + 1) % 3], piece.v) != o) return;
      int side = pts.side_centroid(Plane::of_triangle(U), piece.v);
      if (side == 0) fail("boolean: internal error: a piece's centroid lies on a triangle of operand ", j + 1);
      if (side * o < 0) winding[j] += o;
    });
    std::vector<char> front(nops, 0), back(nops, 0);
    back[i] = 1;
    for (int j = 0; j < nops; ++j) {
      if (j == i) continue;
      auto c = coplanar.find(j);
      if (c != coplanar.end()) {
        front[j] = c->second < 0;
        back[j] = c->second > 0;
      } else {
        auto w = winding.find(j);
        front[j] = back[j] = (w != winding.end() && w->second > 0);
      }
    }
    bool fb = membership(op, back), ff = membership(op, front);
    std::int8_t keep = (fb && !ff) ? 1 : (!fb && ff) ? -1 : 0;
    if (keep && !coplanar.empty() && coplanar.begin()->first < i) keep = 0;
    patch_keep[pi] = keep;
  });
  std::vector<std::int8_t> keep(np);
  for (std::size_t p = 0; p < np; ++p) keep[p] = patch_keep[patch_of[p]];
  return keep;
}

}  // namespace wedge::boolean_detail
