// Output: the kept pieces become a triangle mesh of doubles.
//
// First, cut points that lie inside a flat region of the result, or on a straight crease between
// two, are merged into a neighbour (merge_flat): the retriangulation put them there, the result
// does not need them (a plate's holes lose the cuts of their cylinders' side diagonals, and the
// plate minus 400 cylinders has 52,812 triangles instead of 104,012).
//
// Exact until here: every vertex is a point id, and two pieces share a vertex exactly when their
// points are equal. Where the result is not a manifold (two solids that share only an edge or a
// vertex) its shells are kept apart: around an edge used by more than two triangles, each
// triangle is paired with its neighbour on its back side (the side its solid is on), and each
// vertex gets one copy per fan of triangles joined through such pairs; the copies have the same
// position and different indices.
// Rounding happens here, once: each vertex becomes the double nearest (within an ulp) to its
// exact position; the rounding check and its repair are in boolean_round.cpp.
#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <mutex>
#include <numeric>

#include "csg/boolean_impl.h"
#include "kernel/error.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

BooleanResult assemble(const Points& pts, const Arrangement& arr, const std::vector<std::int8_t>& keep,
                       std::size_t* collapses, bool* unresolved, std::vector<u32>* crossing,
                       const std::vector<std::array<u32, 3>>* piece_adj, bool snap, std::size_t* flat_shells) {
  const Soup& soup = pts.soup();
  // The kept pieces, in order (per-block counts, then each block copied in parallel).
  constexpr std::size_t kBlock = 65536;
  const std::size_t npieces = arr.pieces.size();
  const auto kept_from = block_starts(npieces, kBlock, [&](std::size_t lo, std::size_t hi) {
    std::size_t n = 0;
    for (std::size_t p = lo; p < hi; ++p) n += keep[p] != 0;
    return n;
  });
  std::vector<std::array<u32, 3>> tris(kept_from.total());
  std::vector<u32> src(tris.size()), piece(tris.size());
  std::vector<char> flipped(tris.size());
  // Per piece, its output triangle (kNone: dropped, or changed by merge_flat), where classify
  // joined pieces directly.
  const bool joined = piece_adj && !piece_adj->empty();
  std::vector<u32, NoInit<u32>> out_of(joined ? npieces : 0);
  fill_blocks(kept_from, [&](std::size_t lo, std::size_t hi, std::size_t w) {
    for (std::size_t p = lo; p < hi; ++p) {
      if (joined) out_of[p] = keep[p] ? static_cast<u32>(w) : kNone;
      if (!keep[p]) continue;
      auto v = arr.pieces[p].v;
      if (keep[p] < 0) std::swap(v[1], v[2]);
      tris[w] = v;
      src[w] = arr.pieces[p].tri;
      flipped[w] = keep[p] < 0;
      piece[w] = static_cast<u32>(p);
      ++w;
    }
  });
  const std::size_t merged = merge_flat(pts, tris, src, flipped, piece);
  const std::size_t nt = tris.size();

  // Directed edges; partner[c] for corner-edge c = 3*t+e (edge v[e] -> v[e+1]).
  std::vector<u32> partner(nt * 3, kNone);
  // Edges classify joined directly (two whole triangles, the only pieces on their edge, kept
  // together) are paired here where merge_flat left both triangles as their pieces; the rest
  // are sorted.
  if (joined) {
    if (merged) {
      // merge_flat removed triangles (the others moved down) and changed some.
      parallel_blocks(npieces, kBlock, [&](std::size_t lo, std::size_t hi) {
        std::fill(out_of.begin() + static_cast<std::ptrdiff_t>(lo), out_of.begin() + static_cast<std::ptrdiff_t>(hi), kNone);
      });
      parallel_for(0, nt, [&](std::size_t t) {
        auto v = arr.pieces[piece[t]].v;
        if (flipped[t]) std::swap(v[1], v[2]);
        if (same_array(v, tris[t])) out_of[piece[t]] = static_cast<u32>(t);
      });
    }
    parallel_for(0, nt, [&](std::size_t t) {
      const u32 p = piece[t];
      if (out_of[p] != t) return;
      for (u32 e = 0; e < 3; ++e) {
        const u32 x = (*piece_adj)[p][e];
        if (x == kNone) continue;
        const u32 u = out_of[adj_piece(x)];
        // (Turned alike: one patch's pieces are. Kept so, a piece's edge e is output edge e, or
        // 2 - e where the triangle was turned over.)
        if (u == kNone || flipped[u] != flipped[t]) continue;
        const u32 eo = flipped[t] ? 2 - e : e, f = adj_edge(x), fo = flipped[t] ? 2 - f : f;
        assert(tris[u][fo] == tris[t][(eo + 1) % 3] && tris[u][(fo + 1) % 3] == tris[t][eo]);
        partner[t * 3 + eo] = u * 3 + fo;
      }
    });
  }
  // Where each triangle's records start (its edges not paired directly).
  std::vector<u32, NoInit<u32>> first_rec;  // (every entry written by parallel_prefix)
  parallel_prefix(first_rec, nt, kBlock, [&](std::size_t t) {
    return u32(partner[t * 3] == kNone) + (partner[t * 3 + 1] == kNone) + (partner[t * 3 + 2] == kNone);
  });
  EdgeRecs half(first_rec[nt]);  // undirected key; value: corner-edge 3*t+e
  parallel_for(0, nt, [&](std::size_t t) {
    u32 r = first_rec[t];
    for (int e = 0; e < 3; ++e) {
      if (partner[t * 3 + e] != kNone) continue;
      u32 a = tris[t][e], b = tris[t][(e + 1) % 3];
      half[r++] = {static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b), static_cast<u32>(t * 3 + e)};
    }
  });
  soup.poll();
  sort_edges(half, pts.size(), soup.interrupt);
  // The edges of more than two triangles: their corner-edges in order about the edge, and the
  // edge's smaller end (a triangle running from it faces increasing angle).
  struct Sheets {
    std::vector<u32> ce;
    u32 a;
  };
  std::vector<Sheets> sheets;
  std::mutex sheets_mutex;
  // Pairs each triangle about such an edge with its neighbour behind it (the side its solid is
  // on), or in front of it (its empty side).
  auto pair_about = [&](const Sheets& s, bool in_front) {
    const std::size_t n = s.ce.size();
    auto fwd = [&](std::size_t x) { return tris[s.ce[x] / 3][s.ce[x] % 3] == s.a; };
    for (std::size_t x = 0; x < n; ++x) {
      if (!fwd(x)) continue;
      const std::size_t y = in_front ? (x + 1) % n : (x + n - 1) % n;
      if (fwd(y)) continue;
      partner[s.ce[x]] = s.ce[y];
      partner[s.ce[y]] = s.ce[x];
    }
  };
  // Each run of records (one undirected edge) writes only its own corners' partners.
  for_each_run(half, soup.interrupt, [&](std::size_t i, std::size_t j) {
    if (j - i == 2) {
      partner[half[i].value] = half[i + 1].value;
      partner[half[i + 1].value] = half[i].value;
    } else {
      // Several sheets through one edge: sort them around it and pair each triangle with its
      // neighbour behind it. Sorted exactly: sheet i leaves the edge e = b - a in direction
      // d_i = s_i (n_i x e), with n_i its source triangle's normal and s_i = +-1 (its
      // direction along the edge, and whether it was kept reversed). Then
      //   (d_i x d_j) . e = s_i s_j (e . (n_i x n_j)) |e|^2,
      // and as n_i x n_j is parallel to e, its sign is that of e_k (n_i x n_j)_k on an axis k
      // with e_k != 0: exact signs of input-vertex polynomials and one coordinate comparison.
      u32 a = static_cast<u32>(half[i].key >> 32), b = static_cast<u32>(half[i].key & 0xffffffffu);
      const Vec3 approx_e = pts.approx(b) - pts.approx(a);
      int k = 0, ek = 0;
      for (int tries = 0; tries < 3 && ek == 0; ++tries) {
        int order[3] = {0, 1, 2};
        std::sort(order, order + 3, [&](int x, int y) { return std::abs(approx_e[x]) > std::abs(approx_e[y]); });
        k = order[tries];
        ek = pts.compare(b, a, k);
      }
      struct Sheet {
        u32 ce;
        int s;        // s_i
        Plane plane;  // the source triangle's plane
        u32 tri;      // the source triangle
        int half = 0;
      };
      std::vector<Sheet> sh;
      for (std::size_t x = i; x < j; ++x) {
        u32 t = half[x].value / 3, ei = half[x].value % 3;
        const int s_i = (tris[t][ei] == a ? 1 : -1) * (flipped[t] ? -1 : 1);
        sh.push_back({half[x].value, s_i, Plane::of_triangle(soup.tris[src[t]]), src[t]});
      }
      // Whether parallel normals n_x, n_y point the same way (exact): n_y's component along x's
      // axis has the sign of n_x's there. (The dot product of the normals in doubles underflowed
      // to 0 at size 1e-91, and two cubes sharing an edge came out with "an open edge".)
      auto same_way = [&](const Sheet& x, const Sheet& y) {
        const int k = soup.axis[x.tri], i = (k + 1) % 3, j = (k + 2) % 3;
        const auto& U = soup.tris[y.tri];
        const Vec3 &p = soup.verts[U[0]], &q = soup.verts[U[1]], &r = soup.verts[U[2]];
        return soup.axis_sign[x.tri] * orient2d_fast(p[i], p[j], q[i], q[j], r[i], r[j]) > 0;
      };
      // ccw(x, y) > 0: y lies less than a half-turn counter-clockwise of x about e.
      auto ccw = [&](const Sheet& x, const Sheet& y) { return x.s * y.s * ek * pts.cross_sign(x.plane, y.plane, k); };
      for (Sheet& y : sh) {
        const int c = ccw(sh[0], y);
        if (c != 0) y.half = c > 0 ? 0 : 1;
        else y.half = (y.s * (same_way(sh[0], y) ? 1 : -1) == sh[0].s) ? 0 : 1;  // same or opposite direction
      }
      std::sort(sh.begin(), sh.end(), [&](const Sheet& x, const Sheet& y) {
        if (x.half != y.half) return x.half < y.half;
        const int c = ccw(x, y);
        return c != 0 ? c > 0 : x.ce < y.ce;
      });
      // A triangle with edge a->b has its front towards increasing angle about a->b; its solid is
      // behind it, towards decreasing angle. For b->a the other way round.
      Sheets around{{}, a};
      for (const Sheet& x : sh) around.ce.push_back(x.ce);
      pair_about(around, false);
      std::lock_guard<std::mutex> lock(sheets_mutex);
      sheets.push_back(std::move(around));
    }
  });
  {
    std::atomic<bool> open{false};
    parallel_blocks(partner.size(), kBlock, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t c = lo; c < hi; ++c)
        if (partner[c] == kNone) open.store(true, std::memory_order_relaxed);
    });
    if (open.load()) {  // (the first such corner-edge names the edge)
      const std::size_t c = static_cast<std::size_t>(std::find(partner.begin(), partner.end(), kNone) - partner.begin());
      const u32 a = tris[c / 3][c % 3], b = tris[c / 3][(c % 3 + 1) % 3];
      fail("boolean: internal error: the result has an open edge, ", point_text(pts.approx(a)), " - ", point_text(pts.approx(b)));
    }
  }

  // Vertex copies: corners (3*t+k) at the same point joined across paired edges. A point none
  // of whose edges was sorted (all paired directly: whole triangles of one disk around an input
  // vertex, not a pinched one) has one copy, its smallest corner; the other points' corners are
  // joined.
  soup.poll();
  std::vector<char> sorted_at(pts.size(), 0);
  parallel_blocks(half.size(), 65536, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      std::atomic_ref<char>(sorted_at[half[i].key >> 32]).store(1, std::memory_order_relaxed);
      std::atomic_ref<char>(sorted_at[half[i].key & 0xffffffffu]).store(1, std::memory_order_relaxed);
    }
  });
  for (u32 v : soup.pinched) sorted_at[v] = 1;  // several fans: their corners are joined by edges
  std::vector<u32> least(pts.size(), kNone);  // per point with one copy: its smallest corner
  parallel_blocks(nt, 16384, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t c = lo * 3; c < hi * 3; ++c) {
      const u32 v = tris[c / 3][c % 3];
      if (sorted_at[v]) continue;
      std::atomic_ref<u32> at(least[v]);
      u32 cur = at.load(std::memory_order_relaxed);
      while (c < cur && !at.compare_exchange_weak(cur, static_cast<u32>(c), std::memory_order_relaxed)) {
      }
    }
  });
  auto join_corners = [&](Dsu& corners) {
    corners.unite_each(nt, 16384, [&](std::size_t lo, std::size_t hi, auto&& unite) {
      soup.poll();
      for (std::size_t t = lo; t < hi; ++t)
        for (u32 e = 0; e < 3; ++e) {
          u32 c = partner[t * 3 + e];
          if (c < t * 3 + e) continue;  // the pair's other side joins the same corners
          u32 t2 = c / 3, e2 = c % 3;
          // Edge v[e] -> v[e+1] of t is v[e2+1] -> v[e2] of t2.
          if (sorted_at[tris[t][e]]) unite(static_cast<u32>(t * 3 + e), t2 * 3 + (e2 + 1) % 3);
          if (sorted_at[tris[t][(e + 1) % 3]]) unite(static_cast<u32>(t * 3 + (e + 1) % 3), t2 * 3 + e2);
        }
    });
  };
  Dsu corners(nt * 3);
  join_corners(corners);
  // Pairing each triangle with its neighbour behind it about an edge of more than two keeps the
  // solids apart there (two cubes that share an edge: two shells). Where the solid is one
  // around both ends of that edge (a third solid joins the two near each end), the pairs get the
  // same copies of both ends, and the edge would have four triangles: there the neighbours in
  // front are paired instead (the empty wedges kept apart; around each end they are apart, the
  // solid being one), which gives each end one copy per wedge. (Where two solids meet at an
  // edge, the solid wedges are joined elsewhere around a vertex or the empty ones are, not both;
  // with three or more, both can be: see below. Decided edge by edge in the order of their first
  // corners; a few rounds at most.)
  std::sort(sheets.begin(), sheets.end(), [](const Sheets& x, const Sheets& y) { return x.ce[0] < y.ce[0]; });
  std::vector<char> in_front(sheets.size(), 0);
  // The copies of an edge's two ends in a triangle on it (corner-edge c).
  auto ends = [&](u32 c) {
    const u32 t = c / 3, e = c % 3;
    const u32 x = corners.find_shared(t * 3 + e), y = corners.find_shared(t * 3 + (e + 1) % 3);
    const bool forward = tris[t][e] < tris[t][(e + 1) % 3];
    return forward ? std::array<u32, 2>{x, y} : std::array<u32, 2>{y, x};
  };
  for (int round = 0; round < 4 && !sheets.empty(); ++round) {
    bool switched = false;
    for (std::size_t k = 0; k < sheets.size(); ++k) {
      if (in_front[k]) continue;
      const auto& ce = sheets[k].ce;
      // Each pair's two triangles have the same copies; two pairs with the same copies conflict.
      std::vector<std::array<u32, 2>> copies;
      for (u32 c : ce) copies.push_back(ends(c));
      std::sort(copies.begin(), copies.end());
      if (static_cast<std::size_t>(std::unique(copies.begin(), copies.end()) - copies.begin()) * 2 >= ce.size()) continue;
      for (u32 c : ce) partner[c] = kNone;
      pair_about(sheets[k], true);
      in_front[k] = 1;
      switched = true;
    }
    if (!switched) break;
    corners = Dsu(nt * 3);
    join_corners(corners);
  }
  // Where the empty wedges conflict too, no pairing of neighbours keeps the copies apart: three
  // solids at an edge, two of them joined around both its ends and two of the empty wedges as
  // well (around a vertex both can hold once three solids meet: the two solids' joining path
  // closes a loop that leaves the third solid and both empty wedges beside it on one side).
  // There each pair but the first with the same copies gets its own copy of the edge's midpoint:
  // its two triangles are split there (below), and no edge has more than two triangles.
  std::vector<u32> split;  // corner-edges of pairs to split (the forward one of each)
  for (std::size_t k = 0; k < sheets.size(); ++k) {
    if (!in_front[k]) continue;
    std::vector<std::pair<std::array<u32, 2>, u32>> pairs;  // (copies, forward corner-edge)
    for (u32 c : sheets[k].ce)
      if (tris[c / 3][c % 3] == sheets[k].a) pairs.push_back({ends(c), c});
    std::stable_sort(pairs.begin(), pairs.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t x = 1; x < pairs.size(); ++x)
      if (pairs[x].first == pairs[x - 1].first) split.push_back(pairs[x].second);
  }
  // A copy's root is its smallest corner, the first met in corner order: copies are numbered in
  // the order of their roots (a count per block of corners, then the blocks' offsets).
  BooleanResult r;
  soup.poll();
  const std::size_t nc = nt * 3;
  std::vector<u32, NoInit<u32>> root(nc), index(nc);  // index: of roots only
  const auto first = block_starts(nc, 65536, [&](std::size_t lo, std::size_t hi) {
    std::size_t n = 0;
    for (std::size_t c = lo; c < hi; ++c) {
      const u32 v = tris[c / 3][c % 3];
      root[c] = sorted_at[v] ? corners.root(static_cast<u32>(c)) : least[v];
      n += root[c] == c;
    }
    return n;
  });
  r.mesh.positions.resize(first.total());
  // The copies whose point rounding moved (or, in a re-resolution, may move again: the rounded
  // points of earlier passes), and of those the ones rounded now: only those can make a crossing
  // that was not there, and only their triangles are checked (a re-resolution's input was
  // checked, and the crossings it had are resolved exactly).
  std::vector<char> moved(first.total());
  std::vector<char> rounded_now(soup.movable.empty() ? 0 : first.total());
  fill_blocks(first, [&](std::size_t lo, std::size_t hi, std::size_t n) {
    for (std::size_t c = lo; c < hi; ++c)
      if (root[c] == c) {
        index[c] = static_cast<u32>(n);
        r.mesh.positions[n] = pts.approx(tris[c / 3][c % 3]);
        const u32 p = tris[c / 3][c % 3];
        const bool now = !pts.is_double(p);
        if (!rounded_now.empty()) rounded_now[n] = now;
        moved[n++] = now || (p < soup.movable.size() && soup.movable[p]);
      }
  });
  const std::vector<char>& changed = rounded_now.empty() ? moved : rounded_now;
  r.mesh.triangles.resize(nt);
  r.operand.resize(nt);
  r.source.resize(nt);
  r.mesh.face_ids.resize(nt);
  std::vector<std::int8_t> sign(nt);
  std::vector<char> recheck(nt);
  parallel_for(0, nt, [&](std::size_t t) {
    // The exact result is free of crossings: only triangles with a vertex that rounding moved
    // can meet another one after it.
    char any = 0;
    for (int k = 0; k < 3; ++k) {
      const u32 v = index[root[t * 3 + k]];
      r.mesh.triangles[t][k] = v;
      any |= changed[v];
    }
    recheck[t] = any != 0;
    u32 s = src[t];
    r.operand[t] = soup.operand[s];
    r.source[t] = soup.local[s];
    r.mesh.face_ids[t] = soup.face_id[s];
    // A piece keeps its source's orientation in the source's projection, reversed if flipped.
    sign[t] = static_cast<std::int8_t>(soup.axis_sign[s] * (flipped[t] ? -1 : 1));
  });
  Rounding rd{&soup, std::move(moved), std::move(src), std::move(sign), std::move(recheck), 0, {}};
  if (!split.empty()) {
    // The split: each triangle (p, q, w) of a pair on edge p -> q becomes (p, m, w) and
    // (m, q, w), m a new copy at the edge's midpoint (rounded: it moved); the halves keep the
    // triangle's source and orientation. A triangle split before is looked for among its halves.
    std::vector<std::vector<u32>> halves(nt);
    auto& T = r.mesh.triangles;
    auto split_at = [&](u32 t, u32 p, u32 q, u32 m) {
      for (u32 x : halves[t].empty() ? std::vector<u32>{t} : halves[t])
        for (int e = 0; e < 3; ++e)
          if (T[x][e] == p && T[x][(e + 1) % 3] == q) {
            const u32 w = T[x][(e + 2) % 3], y = static_cast<u32>(T.size());
            T[x] = {p, m, w};
            T.push_back({m, q, w});
            r.operand.push_back(r.operand[x]);
            r.source.push_back(r.source[x]);
            r.mesh.face_ids.push_back(r.mesh.face_ids[x]);
            rd.src.push_back(rd.src[x]);
            rd.sign.push_back(rd.sign[x]);
            rd.recheck[x] = 1;
            rd.recheck.push_back(1);
            if (halves[t].empty()) halves[t].push_back(t);
            halves[t].push_back(y);
            return;
          }
      fail("boolean: internal error: an edge to split is not in its triangle");
    };
    for (u32 c : split) {
      const u32 t = c / 3, e = c % 3, u = partner[c] / 3;
      const u32 p = T[t][e], q = T[t][(e + 1) % 3];
      const u32 m = static_cast<u32>(r.mesh.positions.size());
      r.mesh.positions.push_back(0.5 * (r.mesh.positions[p] + r.mesh.positions[q]));
      rd.moved.push_back(1);
      if (!rd.altered.empty()) rd.altered.push_back(1);
      split_at(t, p, q, m);
      split_at(u, q, p, m);
    }
    rd.collapses += split.size();
  }
  std::size_t flat = 0;
  soup.poll();
  // Edges a few ulps long go first (their triangles are rechecked with the rest); where the
  // repair then fails, it runs again on the result as it was.
  BooleanResult saved;
  Rounding saved_rd;
  const std::size_t ulp_collapses = collapse_ulp_edges(r, rd, &saved, &saved_rd);
  bool ok = repair_rounding(r, rd, crossing, snap, &flat);
  if (!ok && ulp_collapses > 0) {
    r = std::move(saved);
    rd = std::move(saved_rd);
    flat = 0;  // (its flat shells are back)
    ok = repair_rounding(r, rd, crossing, snap, &flat);
  } else {
    rd.collapses += ulp_collapses;
  }
  if (!ok) {
    // Shells thinner than rounding, left out, may have been all that was wrong (or be what keeps
    // the repair from mending the rest).
    const std::size_t n = drop_flat_shells(r, rd);
    flat += n;
    if (n) ok = repair_rounding(r, rd, crossing, snap);
  }
  if (ok) flat += drop_flat_shells(r, rd);
  if (collapses) *collapses += rd.collapses;
  if (flat_shells) *flat_shells += flat;
  if (unresolved) *unresolved = !ok;
  if (!ok && !unresolved) {
    std::vector<u32> bad = rounding_defects(r.mesh, rd);
    const Vec3& p = r.mesh.positions[r.mesh.triangles[bad.empty() ? 0 : bad[0]][0]];
    fail("boolean: the result cannot be rounded to doubles without a self-intersection near (", p.x(), ", ", p.y(),
         ", ", p.z(), ")");
  }
  return r;
}

}  // namespace wedge::boolean_detail
