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
// With few operands, patches linked across edges where exactly two flat surfaces cross take their
// winding numbers from one patch of their component, by the crossings between (see `carry`).
#include <algorithm>
#include <atomic>
#include <cmath>
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

std::vector<std::int8_t> classify(const Points& pts, const Arrangement& arr, BooleanOp op, bool self,
                                  const std::vector<std::array<u32, 3>>* adj, std::vector<std::array<u32, 3>>* piece_adj,
                                  const Settlement* settled) {
  // Triangles outside every other operand (the broad phase's, where it knows them): a patch with
  // a piece of one is outside every other operand, kept or dropped by its operand alone, without
  // a ray (two overlapping spheres: the patches outside the other sphere, two of four rays).
  const std::vector<char>* outside = settled && !settled->outside.empty() ? &settled->outside : nullptr;
  if (settled && settled->empty()) settled = nullptr;
  const Soup& soup = pts.soup();
  const auto& pieces = arr.pieces;
  const std::size_t np = pieces.size();
  const int nops = soup.operands;

  // Patches: union pieces of one operand across edges used by exactly those two pieces.
  Dsu dsu(np);
  // Most pieces of large operands are whole input triangles. Two whole triangles across an edge
  // (adj) whose end points no other operand's piece uses are the only pieces on that edge: they
  // are joined here, and that edge needs no record. Every other piece edge is sorted.
  std::vector<std::uint8_t> direct(np, 0);  // per piece: bit e, edge e joined here
  if (piece_adj) {
    if (np >> kAdjPieceBits) fail("boolean: more than 2^30 pieces");
    piece_adj->assign(adj || !arr.inner.empty() ? np : 0, {kNone, kNone, kNone});
  }
  if (adj) {
    const std::size_t nt = soup.tris.size(), nin = soup.verts.size();
    // Per input vertex: the one operand whose pieces use it, or -2 for several (or where positions
    // of several operands are welded in it). A whole triangle's piece uses its own corners only,
    // which hold its operand's positions (soup.vertex_operand: that operand or -2): only the
    // pieces of cut triangles claim theirs.
    std::vector<u32> whole(nt, kNone);
    std::vector<std::int32_t> owner(soup.vertex_operand.begin(), soup.vertex_operand.end());
    parallel_for(0, np, [&](std::size_t i) {
      const u32 t = pieces[i].tri;
      if ((i == 0 || pieces[i - 1].tri != t) && (i + 1 == np || pieces[i + 1].tri != t) && same_array(pieces[i].v, soup.tris[t])) {
        whole[t] = static_cast<u32>(i);
        return;
      }
      for (u32 v : pieces[i].v)
        if (v < nin) claim(std::atomic_ref<std::int32_t>(owner[v]), soup.operand[t]);
    });
    soup.poll();
    // (The first unions of the Dsu: by blocks of pieces, most of them within a block.)
    dsu.unite_blocks(np, 65536, [&](std::size_t lo, std::size_t hi, auto&& unite) {
      for (std::size_t i = lo; i < hi; ++i) {
        const u32 t = pieces[i].tri;
        if (whole[t] != i) continue;
        for (int e = 0; e < 3; ++e) {
          const u32 u = (*adj)[t][e];
          // Known from both sides (each side's vertex saw a disk), so both skip the edge's record.
          if (u == kNone || whole[u] == kNone) continue;
          const u32 f = (*adj)[u][0] == t ? 0 : (*adj)[u][1] == t ? 1 : (*adj)[u][2] == t ? 2 : 3;
          if (f == 3) continue;
          const u32 a = soup.tris[t][e], b = soup.tris[t][(e + 1) % 3];
          if (owner[a] == -2 || owner[b] == -2) continue;
          direct[i] |= static_cast<std::uint8_t>(1u << e);
          if (piece_adj) (*piece_adj)[i][e] = adj_entry(whole[u], f);
          if (t < u) unite(static_cast<u32>(i), whole[u]);
        }
      }
    });
  }
  // So are two pieces of one cut triangle across an edge inside it that is on no cut.
  parallel_for(0, arr.inner.size(), [&](std::size_t n) {
    const auto& [i, nb] = arr.inner[n];
    for (int e = 0; e < 3; ++e) {
      const u32 q = nb[e];
      if (q == kNone) continue;
      direct[i] |= static_cast<std::uint8_t>(1u << e);
      if (piece_adj) {
        // The edge b -> a of q (pieces of one triangle turn alike).
        const auto &V = pieces[i].v, &W = pieces[q].v;
        u32 f = 0;
        while (f < 3 && !(W[f] == V[(e + 1) % 3] && W[(f + 1) % 3] == V[e])) ++f;
        if (f == 3) fail("boolean: internal error: pieces joined across an edge one of them does not have");
        (*piece_adj)[i][e] = adj_entry(q, f);
      }
      if (i < q) dsu.unite_shared(i, q);
    }
  });
  // Where each piece's records start (its edges not joined directly; three bits counted by hand:
  // std::popcount was a libgcc call on this target).
  constexpr std::size_t kBlock = 65536;
  std::vector<u32, NoInit<u32>> first_rec;  // (every entry written by parallel_prefix)
  parallel_prefix(first_rec, np, kBlock, [&](std::size_t i) {
    return 3u - (direct[i] & 1u) - (direct[i] >> 1 & 1u) - (direct[i] >> 2 & 1u);
  });
  EdgeRecs half(first_rec[np]);
  parallel_for(0, np, [&](std::size_t i) {
    u32 r = first_rec[i];
    for (int e = 0; e < 3; ++e) {
      if (direct[i] >> e & 1) continue;
      u32 a = pieces[i].v[e], b = pieces[i].v[(e + 1) % 3];
      if (a > b) std::swap(a, b);
      half[r++] = {static_cast<std::uint64_t>(a) << 32 | b, static_cast<u32>(i)};
    }
  });
  soup.poll();
  sort_edges(half, pts.size(), soup.interrupt);
  for_each_run(half, soup.interrupt, [&](std::size_t i, std::size_t j) {
    if (j - i == 2 && soup.operand[pieces[half[i].value].tri] == soup.operand[pieces[half[i + 1].value].tri])
      dsu.unite_shared(half[i].value, half[i + 1].value);
  });
  std::vector<u32, NoInit<u32>> patch_of(np);  // (every entry written below)
  std::vector<char> patch_outside(outside ? np : 0, 0);  // per patch, whether a piece is outside
  const auto reps_from = block_starts(np, kBlock, [&](std::size_t lo, std::size_t hi) {
    std::size_t n = 0;
    u32 marked = kNone;  // (a block's pieces are mostly of one patch: marked once)
    for (std::size_t i = lo; i < hi; ++i) {
      patch_of[i] = dsu.root(static_cast<u32>(i));
      n += patch_of[i] == i;
      if (outside && (*outside)[pieces[i].tri] && patch_of[i] != marked) {
        marked = patch_of[i];
        std::atomic_ref<char>(patch_outside[marked]).store(1, std::memory_order_relaxed);
      }
    }
    return n;
  });
  soup.poll();
  std::vector<u32> reps(reps_from.total());  // representative piece per patch (its smallest piece), in order
  fill_blocks(reps_from, [&](std::size_t lo, std::size_t hi, std::size_t n) {
    for (std::size_t i = lo; i < hi; ++i)
      if (patch_of[i] == i) reps[n++] = static_cast<u32>(i);
  });

  // Winding numbers carried across cut edges instead of a ray per patch (nearly coincident
  // sheets: 217,122 patches, each of whose rays the exact stages decide). Where exactly two
  // operands' surfaces cross along an edge, each flat there (the edge inside one triangle of each,
  // neither triangle with a coplanar overlap) and no other surface on it (four pieces on the
  // edge), the two patches of one operand on either side of it lie on opposite sides of the
  // other's plane: their winding numbers of that operand differ by one, more on the side its
  // normal points away from, and of every other operand not at all. Patches so linked form
  // components; one patch per component (its smallest) gets the rays, for every operand, and the
  // others their winding numbers from it. With few operands, none settled, and not for one operand
  // crossing itself.
  const bool carry = !self && !settled && nops <= 32 && reps.size() > 64;
  std::vector<u32> comp_of;                // per patch (index in reps): its component's root (index)
  std::vector<std::int16_t> delta;         // per patch, per operand: its winding number less its root's
  std::vector<char> linked;                // per patch: in a component of more than one patch
  if (carry) {
    std::vector<u32> index_of(np);  // piece -> its patch's index in reps (roots only are read)
    parallel_for(0, reps.size(), [&](std::size_t r) { index_of[reps[r]] = static_cast<u32>(r); });
    struct Link {
      u32 a, b;  // patches (indices in reps): b's winding number of `op` is a's plus `step`
      int op, step;
    };
    std::vector<Link> links;
    // Patch b's side of triangle u's plane, from its piece q's corner off the edge (x, y).
    auto step_to = [&](u32 q, u32 x, u32 y, u32 u) {
      u32 c = kNone;
      for (u32 v : pieces[q].v)
        if (v != x && v != y) c = v;
      const int side = c == kNone ? 0 : pts.side(Plane::of_triangle(soup.tris[u]), c);
      return side > 0 ? -1 : side < 0 ? 1 : 0;  // in front of the other's surface: outside it there
    };
    for (std::size_t i = 0; i < half.size();) {
      std::size_t j = i + 1;
      while (j < half.size() && half[j].key == half[i].key) ++j;
      if (j - i == 4) {
        u32 p[4];
        for (int n = 0; n < 4; ++n) p[n] = half[i + n].value;
        // Two pieces of one triangle and two of another, of two operands (a run is in piece
        // order, and pieces are in triangle order).
        const u32 t[2] = {pieces[p[0]].tri, pieces[p[2]].tri};
        if (pieces[p[1]].tri == t[0] && pieces[p[3]].tri == t[1] && t[0] != t[1]) {
          const int o[2] = {soup.operand[t[0]], soup.operand[t[1]]};
          if (o[0] != o[1] && arr.coplanar(t[0]).empty() && arr.coplanar(t[1]).empty()) {
            const u32 x = static_cast<u32>(half[i].key >> 32), y = static_cast<u32>(half[i].key & 0xffffffffu);
            for (int g = 0; g < 2; ++g) {
              const u32 a = index_of[patch_of[p[2 * g]]], b = index_of[patch_of[p[2 * g + 1]]];
              const int step = a == b ? 0 : step_to(p[2 * g + 1], x, y, t[1 - g]);
              if (step != 0) links.push_back({a, b, o[1 - g], step});
            }
          }
        }
      }
      i = j;
    }
    soup.poll();
    // The components, in order of their smallest patch, each walked from it.
    const std::size_t nr = reps.size();
    std::vector<u32> from(nr + 1, 0);
    for (const auto& l : links) ++from[l.a + 1], ++from[l.b + 1];
    for (std::size_t r = 0; r < nr; ++r) from[r + 1] += from[r];
    struct Arc {
      u32 to;
      int op, step;
    };
    std::vector<Arc> arcs(2 * links.size());
    {
      std::vector<u32> at(from.begin(), from.end() - 1);
      for (const auto& l : links) {
        arcs[at[l.a]++] = {l.b, l.op, l.step};
        arcs[at[l.b]++] = {l.a, l.op, -l.step};
      }
    }
    comp_of.assign(nr, kNone);
    delta.assign(nr * nops, 0);
    linked.assign(nr, 0);
    std::vector<u32> queue;
    for (u32 root = 0; root < nr; ++root) {
      if (comp_of[root] != kNone || from[root] == from[root + 1]) continue;
      comp_of[root] = root;
      queue.assign(1, root);
      bool consistent = true;
      for (std::size_t n = 0; n < queue.size(); ++n) {
        const u32 x = queue[n];
        for (u32 e = from[x]; e < from[x + 1]; ++e) {
          const Arc& arc = arcs[e];
          const u32 y = arc.to;
          const std::int16_t* dx = &delta[static_cast<std::size_t>(x) * nops];
          std::int16_t* dy = &delta[static_cast<std::size_t>(y) * nops];
          if (comp_of[y] == kNone) {
            comp_of[y] = root;
            std::copy(dx, dx + nops, dy);
            dy[arc.op] = static_cast<std::int16_t>(dy[arc.op] + arc.step);
            queue.push_back(y);
          } else {
            // Around a cycle the steps add up to nothing (exactly); where they do not, the rays
            // decide every patch of the component.
            for (int j = 0; j < nops; ++j)
              if (dy[j] != dx[j] + (j == arc.op ? arc.step : 0)) consistent = false;
          }
        }
      }
      if (consistent && queue.size() > 1)
        for (u32 x : queue) linked[x] = 1;
    }
  }
  std::vector<std::int16_t> root_w(carry ? reps.size() * nops : 0, 0);  // per component root: its winding numbers

  // A tree per operand, for the vertical rays, and each operand's box: a point outside the box
  // has winding number 0 there, so the operand's tree need not be looked at (a ray through a
  // Menger sponge meets a few bars' boxes, not every bar above it).
  const std::vector<u32> first_tri = operand_starts(soup);
  // With a few patches (two spheres: four), a ray looks at every triangle of an operand (a box
  // test each) instead of a tree built for it: building trees over a million triangles for four
  // rays was a fifth of such a boolean.
  const bool scan = reps.size() <= 16;
  std::vector<Bvh> trees;
  if (!scan) {
    trees.resize(nops);
    parallel_for(0, nops, [&](std::size_t j) {
      std::vector<u32> ids(first_tri[j + 1] - first_tri[j]);
      std::iota(ids.begin(), ids.end(), first_tri[j]);
      trees[j] = Bvh(soup, std::move(ids), 3);
    });
  }
  auto query = [&](int j, const double qlo[3], const double qhi[3], auto&& f) {
    if (!scan) trees[j].query(qlo, qhi, f);
    else
      for (u32 u = first_tri[j]; u < first_tri[j + 1]; ++u) f(u);  // the callers' crossing() tests the box
  };
  soup.poll();
  // (Boxes over the operands' positions: a point outside one is outside the operand's triangles'.)
  const std::vector<std::array<double, 6>>& op_box = soup.boxes;

  // The operands whose boxes meet a vertical line, by a grid over the scene's xy extent: a piece
  // looks at the operands listed in the cell of its centroid, not at every operand (a sponge has
  // 274, and looping over them all was most of its classification).
  const int grid = nops > 8 ? std::min(64, static_cast<int>(2 * std::sqrt(static_cast<double>(nops)))) : 1;
  double gx0 = INFINITY, gy0 = INFINITY, gx1 = -INFINITY, gy1 = -INFINITY;
  for (const auto& b : op_box) {
    gx0 = std::min(gx0, b[0]);
    gy0 = std::min(gy0, b[1]);
    gx1 = std::max(gx1, b[3]);
    gy1 = std::max(gy1, b[4]);
  }
  const bool gridded = grid > 1 && gx0 < gx1 && gy0 < gy1 && std::isfinite(gx1 - gx0) && std::isfinite(gy1 - gy0);
  // Cell of coordinate v: monotone in v (correctly rounded operations), so an operand box and a
  // centroid box that share a point share a cell.
  auto cell = [&](double v, double v0, double v1) {
    const double f = (v - v0) / (v1 - v0) * grid;
    return f <= 0 ? 0 : (f >= grid ? grid - 1 : static_cast<int>(f));
  };
  std::vector<std::vector<int>> cells(gridded ? static_cast<std::size_t>(grid) * grid : 0);
  if (gridded)
    for (int j = 0; j < nops; ++j) {
      const auto& b = op_box[j];
      if (!(b[0] <= b[3])) continue;  // no triangles
      for (int x = cell(b[0], gx0, gx1); x <= cell(b[3], gx0, gx1); ++x)
        for (int y = cell(b[1], gy0, gy1); y <= cell(b[4], gy0, gy1); ++y) cells[x * grid + y].push_back(j);
    }
  std::vector<int> all_operands(nops);
  for (int j = 0; j < nops; ++j) all_operands[j] = j;

  // A piece with the operands' memberships behind it and in front: kept facing out where the
  // result holds the space behind it and not in front, kept reversed the other way round.
  auto keep_of = [&](const std::vector<char>& back, const std::vector<char>& front) -> std::int8_t {
    const bool fb = membership(op, back), ff = membership(op, front);
    return (fb && !ff) ? 1 : (!fb && ff) ? -1 : 0;
  };
  std::vector<std::int8_t> patch_keep(np, 0);
  parallel_for(0, reps.size(), [&](std::size_t ri) {
    soup.poll();
    if (carry && linked[ri] && comp_of[ri] != ri) return;  // carried from its component's root below
    const bool root = carry && linked[ri];  // (its component's root: every winding number wanted)
    u32 pi = reps[ri];
    const Piece& piece = pieces[pi];
    u32 t = piece.tri;
    int i = soup.operand[t];
    int k = soup.axis[t];
    if (settled && !settled->triangles.empty() && settled->triangles[t]) {  // inside an operand that drops it
      patch_keep[pi] = 0;
      return;
    }
    if (outside && patch_outside[pi]) {
      // Outside every other operand: behind the piece only its own, in front none.
      std::vector<char> in_front(nops, 0), behind(nops, 0);
      behind[i] = 1;
      patch_keep[pi] = keep_of(behind, in_front);
      return;  // (a root's winding numbers: all 0, as root_w has them)
    }
    // Set where the centroid lies on a triangle whose cut with t settle() left out: strictly inside
    // the operand that settled it, and so dropped.
    bool on_settled = false;
    // A tight box around the centroid decides most tests on doubles: the box wholly on one side
    // of a line or plane (its corners, exactly) puts the centroid there.
    const std::array<double, 6> cb = pts.centroid_box(piece.v);
    const bool cb_ok = std::isfinite(cb[0]) && std::isfinite(cb[1]) && std::isfinite(cb[2]) &&
                       std::isfinite(cb[3]) && std::isfinite(cb[4]) && std::isfinite(cb[5]);
    // Side of the centroid of line A B in the projection along e_k (0: undecided).
    auto edge_side = [&](const Vec3& A, const Vec3& B, int kk) {
      if (!cb_ok) return 0;
      const int x = (kk + 1) % 3, y = (kk + 2) % 3;
      const int s0 = orient2d_fast(A[x], A[y], B[x], B[y], cb[x], cb[y]);
      if (s0 == 0 || orient2d_fast(A[x], A[y], B[x], B[y], cb[x + 3], cb[y]) != s0 ||
          orient2d_fast(A[x], A[y], B[x], B[y], cb[x], cb[y + 3]) != s0 ||
          orient2d_fast(A[x], A[y], B[x], B[y], cb[x + 3], cb[y + 3]) != s0)
        return 0;
      return s0;
    };
    // Coplanar operands covering the piece: +1 same orientation, -1 opposite (few: a short list).
    // Per-thread lists, reused from patch to patch (a sponge has 120k patches).
    thread_local std::vector<std::pair<int, int>> coplanar, winding;
    thread_local std::vector<char> front, back;
    coplanar.clear();
    winding.clear();
    auto coplanar_with = [&](int j) -> const std::pair<int, int>* {
      for (const auto& c : coplanar)
        if (c.first == j) return &c;
      return nullptr;
    };
    // Coplanar triangle u over the centroid: +1 same orientation as the piece, -1 opposite; 0 if
    // the centroid is not strictly inside it.
    auto cover_sign = [&](u32 u) {
      const auto& U = soup.tris[u];
      if (cb_ok) {  // the centroid's box off U's box: not inside U (most of a long coplanar list)
        double ulo[3], uhi[3];
        triangle_box(soup, u, ulo, uhi);
        for (int d = 0; d < 3; ++d)
          if (d != k && (cb[d + 3] < ulo[d] || cb[d] > uhi[d])) return 0;
      }
      const int o = pts.orient2d(U[0], U[1], U[2], k);  // U's orientation seen along k
      auto side_of = [&](u32 a, u32 b) {
        const int f = edge_side(soup.verts[a], soup.verts[b], k);
        return f != 0 ? f : pts.orient2d_centroid(a, b, piece.v, k);
      };
      // U's other half across a diagonal whose cuts were erased (pieces of this triangle may
      // cross it): a centroid on the diagonal is inside the quadrilateral where it is strictly
      // inside the other half's two other edges.
      const u32 half = arr.quad_partner.empty() ? kNone : arr.quad_partner[u];
      int diagonal = -1;
      for (int e = 0; e < 3; ++e) {
        const int f = side_of(U[e], U[(e + 1) % 3]);
        if (f == 0 && half != kNone && diagonal < 0) {
          const auto& H = soup.tris[half];
          auto in_h = [&](u32 v) { return v == H[0] || v == H[1] || v == H[2]; };
          if (in_h(U[e]) && in_h(U[(e + 1) % 3])) {
            diagonal = e;
            continue;
          }
        }
        if (f * o <= 0) return 0;
      }
      if (diagonal >= 0) {
        // The other half, seen along k, turns as U does (one plane, one facing): its edges other
        // than the diagonal, with the centroid strictly on their inner side.
        const auto& H = soup.tris[half];
        for (int e = 0; e < 3; ++e) {
          const u32 a = H[e], b = H[(e + 1) % 3];
          if ((a == U[diagonal] || a == U[(diagonal + 1) % 3]) && (b == U[diagonal] || b == U[(diagonal + 1) % 3])) continue;
          if (side_of(a, b) * o <= 0) return 0;
        }
      }
      return (o > 0) == (soup.axis_sign[t] > 0) ? 1 : -1;
    };
    for (u32 u : arr.coplanar(t)) {
      const int j = soup.operand[u];
      if (j == i || coplanar_with(j)) continue;
      if (const int c = cover_sign(u)) coplanar.push_back({j, c});
    }
    std::sort(coplanar.begin(), coplanar.end());
    // Winding numbers of the centroid with respect to every other operand.
    // winding: (operand, winding number), the ones met
    // The box that holds the centroid: its tight box where the filter has one, else the piece's.
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      if (cb_ok) {
        lo[d] = cb[d];
        hi[d] = cb[d + 3];
        continue;
      }
      lo[d] = std::min({pts.box(piece.v[0])[d], pts.box(piece.v[1])[d], pts.box(piece.v[2])[d]});
      hi[d] = std::max({pts.box(piece.v[0])[d + 3], pts.box(piece.v[1])[d + 3], pts.box(piece.v[2])[d + 3]});
    }
    // Whether operand j's box may hold the centroid (the centroid's box meets it).
    const double clo[3] = {lo[0], lo[1], lo[2]}, chi[3] = {hi[0], hi[1], hi[2]};
    auto near = [&](int j) {
      for (int d = 0; d < 3; ++d)
        if (chi[d] < op_box[j][d] || clo[d] > op_box[j][d + 3]) return false;
      return true;
    };
    auto plane_side = [&](const Vec3& A, const Vec3& B, const Vec3& C) {  // 0: undecided
      int s0 = 0;
      for (int c = 0; c < 8; ++c) {
        const Vec3 q(cb[(c & 1) ? 3 : 0], cb[(c & 2) ? 4 : 1], cb[(c & 4) ? 5 : 2]);
        const int o = orient3d_fast(A, B, C, q);
        if (o == 0 || (s0 != 0 && o != s0)) return 0;
        s0 = o;
      }
      return s0;
    };
    // The ray goes up: triangles wholly below the centroid's box cannot be above it.
    hi[2] = INFINITY;
    // What triangle u adds to the winding number along the ray: +-1 where the ray crosses it
    // above the centroid, 0 where it misses.
    auto crossing = [&](u32 u) {
      // U's box against the ray's, an axis at a time (most triangles a scan meets are off in x).
      const auto& U = soup.tris[u];
      const Vec3 &A = soup.verts[U[0]], &B = soup.verts[U[1]], &C = soup.verts[U[2]];
      for (int d = 0; d < 2; ++d)
        if (std::max({A[d], B[d], C[d]}) < clo[d] || std::min({A[d], B[d], C[d]}) > chi[d]) return 0;
      if (std::max({A[2], B[2], C[2]}) < clo[2]) return 0;
      const int o = orient2d_xy(soup, U[0], U[1], U[2]);
      if (o == 0) return 0;  // vertical: the perturbed ray misses it
      for (int e = 0; e < 3; ++e) {
        const int f = edge_side(soup.verts[U[e]], soup.verts[U[(e + 1) % 3]], 2);
        if (f != 0 ? f != o : orient_sos(pts, U[e], U[(e + 1) % 3], piece.v) != o) return 0;
      }
      int side = cb_ok ? plane_side(soup.verts[U[0]], soup.verts[U[1]], soup.verts[U[2]]) : 0;
      if (side == 0) side = pts.side_centroid(Plane::of_triangle(U), piece.v);
      if (side == 0 && settled && settled->left_out(t, u)) {
        on_settled = true;
        return 0;
      }
      if (side == 0) fail("boolean: internal error: a piece's centroid lies on a triangle of operand ", soup.operand[u] + 1);
      return side * o < 0 ? o : 0;
    };
    if (self) {
      // One operand that may cross itself (a rounded result being re-resolved): the result is
      // where its winding number is at least 1. w counts every sheet but the piece's own and the
      // coplanar ones over it; those add 1 behind the piece (same orientation) or in front.
      std::vector<std::pair<u32, int>> cover;
      for (u32 u : arr.coplanar(t))
        if (const int c = cover_sign(u)) cover.push_back({u, c});
      int w = 0;
      query(0, lo, hi, [&](u32 u) {
        if (u == t || std::any_of(cover.begin(), cover.end(), [&](const auto& c) { return c.first == u; })) return;
        w += crossing(u);
      });
      // w is the winding number where the ray starts: just above the piece's plane, or, for a
      // vertical plane, on the side the perturbation (eps, eps^2) in x and y moves to. Crossing
      // the sheets in the plane from the piece's front to its back adds S.
      int S = 1;
      for (const auto& c : cover) S += c.second;
      const auto& T = soup.tris[t];
      int up = orient2d_xy(soup, T[0], T[1], T[2]);  // sign of the normal's z
      if (up == 0) {
        const Vec3 &A = soup.verts[T[0]], &B = soup.verts[T[1]], &C = soup.verts[T[2]];
        up = orient2d_fast(A.y(), A.z(), B.y(), B.z(), C.y(), C.z());  // sign of n_x
        if (up == 0) up = orient2d_fast(A.z(), A.x(), B.z(), B.x(), C.z(), C.x());  // sign of n_y
      }
      const int front = up > 0 ? w : w - S, back = up > 0 ? w + S : w;
      std::int8_t keep = (back >= 1 && front < 1) ? 1 : (front >= 1 && back < 1) ? -1 : 0;
      // Coplanar sheets kept here give the same triangle: the lowest one keeps it.
      for (const auto& c : cover)
        if (c.first < t) keep = 0;
      patch_keep[pi] = keep;
      return;
    }
    auto hit = [&](u32 u) {
      const int o = crossing(u);
      if (o == 0) return;
      const int j = soup.operand[u];
      auto w = std::find_if(winding.begin(), winding.end(), [&](const auto& x) { return x.first == j; });
      if (w == winding.end()) winding.push_back({j, o});
      else w->second += o;
    };
    // The operands to look at: those of the grid cell holding the centroid's xy box (all, where
    // that box is not within one cell).
    const std::vector<int>* candidates = &all_operands;
    if (gridded) {
      const int x0 = cell(clo[0], gx0, gx1), y0 = cell(clo[1], gy0, gy1);
      if (x0 == cell(chi[0], gx0, gx1) && y0 == cell(chi[1], gy0, gy1)) candidates = &cells[x0 * grid + y0];
    }
    // One operand can settle a piece by itself: inside another operand of a union, outside one of
    // an intersection, inside a subtrahend of a difference or outside its first operand, the piece
    // has the same membership on both sides and is dropped, whatever the other operands say (a
    // sponge drops most of its 120 thousand patches so, after a ray or two instead of one per bar
    // above them; nine nearly coincident spheres' intersection, most of its patches after two
    // rays instead of eight).
    auto settles = [&](int j) {
      int w = 0;
      for (const auto& x : winding)
        if (x.first == j) w = x.second;
      switch (op) {
        case BooleanOp::Union: return w > 0;
        case BooleanOp::Intersection: return w <= 0;
        case BooleanOp::Difference: return j == 0 ? w <= 0 : w > 0;
      }
      return false;
    };
    if (root) {
      // Every operand's winding number (no early stop: the component's other patches need them).
      if (!coplanar.empty()) fail("boolean: internal error: a linked patch lies on another operand's surface");
      for (int j : *candidates)
        if (j != i && near(j)) query(j, lo, hi, hit);
      for (const auto& [j, w] : winding) root_w[ri * nops + j] = static_cast<std::int16_t>(w);
    }
    if (!root && op == BooleanOp::Difference && i != 0 && !near(0) && !coplanar_with(0)) {
      patch_keep[pi] = 0;  // outside the first operand's box
      return;
    }
    if (!root && op == BooleanOp::Intersection)
      for (int j = 0; j < nops; ++j)
        if (j != i && !near(j) && !coplanar_with(j)) {
          patch_keep[pi] = 0;  // outside another operand's box
          return;
        }
    if (!root)
      for (int j : *candidates)
        if (j != i && near(j) && !coplanar_with(j)) {
          query(j, lo, hi, hit);
          if (on_settled || settles(j)) {
            patch_keep[pi] = 0;
            return;
          }
        }
    front.assign(nops, 0);
    back.assign(nops, 0);
    back[i] = 1;
    for (const auto& [j, w] : winding) front[j] = back[j] = w > 0;
    for (const auto& [j, c] : coplanar) {
      front[j] = c < 0;
      back[j] = c > 0;
    }
    std::int8_t keep = keep_of(back, front);
    if (keep && !coplanar.empty() && coplanar.front().first < i) keep = 0;
    patch_keep[pi] = keep;
  });
  if (carry)
    parallel_for(0, reps.size(), [&](std::size_t ri) {
      if (!linked[ri] || comp_of[ri] == ri) return;
      const std::int16_t* w0 = &root_w[static_cast<std::size_t>(comp_of[ri]) * nops];
      const std::int16_t* d = &delta[ri * nops];
      const int i = soup.operand[pieces[reps[ri]].tri];
      thread_local std::vector<char> front, back;
      front.assign(nops, 0);
      back.assign(nops, 0);
      for (int j = 0; j < nops; ++j) front[j] = back[j] = j != i && w0[j] + d[j] > 0;
      back[i] = 1;
      patch_keep[reps[ri]] = keep_of(back, front);
    });
  std::vector<std::int8_t> keep(np);
  parallel_blocks(np, kBlock, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t p = lo; p < hi; ++p) keep[p] = patch_keep[patch_of[p]];
  });
  return keep;
}

}  // namespace wedge::boolean_detail
