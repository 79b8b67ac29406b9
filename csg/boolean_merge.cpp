// merge_flat: the cut points the retriangulation put inside a flat region of the result, or on a
// straight crease between two, merged into a neighbour before the output is rounded.
#include <algorithm>
#include <atomic>
#include <map>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

// Merges the pieces of one flat region or one straight crease where a point between them need
// not be a vertex: a vertex of a cut piece (a cut point, or an operand's vertex that another
// operand's face or edge runs through), whose triangles form one closed fan lying in one plane,
// or in two planes that meet along a line through it, is collapsed into a neighbour (on that
// line, for two planes). The surface is unchanged as a set
// of points: the vertex lay inside a flat region or on a straight crease between the two
// neighbours it had there. A collapse is made only where every triangle that remains keeps its
// exact orientation in its source's projection, and where the link condition holds, so the
// mesh stays closed, manifold and free of crossings. Triangles keep their sources. Cut points
// that are not doubles (rounded when output) are the ones a plate's holes have in the middle of
// their edges; without them nothing of the output needs rounding there.
// Returns the number of vertices removed.
std::size_t merge_flat(const Points& pts, std::vector<std::array<u32, 3>>& tris, std::vector<u32>& src,
                       std::vector<char>& flipped, std::vector<u32>& piece) {
  const Soup& soup = pts.soup();
  const std::size_t np = pts.size();
  // The candidates: the vertices of pieces that are not their whole source triangle (the rest of
  // an operand is left as it came).
  // (The passes over every triangle run in parallel blocks, flags set by relaxed atomic stores:
  // on two 1M-triangle spheres they were most of this function.)
  constexpr std::size_t kBlock = 16384;
  auto mark = [](std::vector<char>& flag, const std::array<u32, 3>& T) {
    for (u32 v : T) std::atomic_ref<char>(flag[v]).store(1, std::memory_order_relaxed);
  };
  std::vector<char> candidate(np, 0);
  parallel_blocks(tris.size(), kBlock, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t t = lo; t < hi; ++t) {
      const auto& T = tris[t];
      const auto& S = soup.tris[src[t]];
      for (u32 v : T)
        if (v != S[0] && v != S[1] && v != S[2]) {
          mark(candidate, T);
          break;
        }
    }
  });
  std::vector<u32> cands;
  for (std::size_t v = 0; v < np; ++v)
    if (candidate[v]) cands.push_back(static_cast<u32>(v));
  if (cands.empty()) return 0;
  std::size_t removed = 0;
  // Whether source triangles s and u lie in one plane facing one way (with their flips).
  auto same_side = [&](u32 s, bool fs, u32 u, bool fu) {
    if (s == u) return fs == fu;
    const auto& S = soup.tris[s];
    for (u32 v : soup.tris[u])
      if (orient3d_v(soup, S[0], S[1], S[2], v) != 0) return false;
    const int k = soup.axis[s];
    const auto& U = soup.tris[u];
    const int o = pts.orient2d(U[0], U[1], U[2], k);  // non-zero: U is in S's plane
    return (o * (fu ? -1 : 1)) == (soup.axis_sign[s] * (fs ? -1 : 1));
  };
  // Whether a fan's triangles lie in at most two oriented planes (the cheap rejection on curved
  // surfaces, where a cut point's triangles come from three or more source planes): each
  // triangle's plane in `group` (0 or 1), their count in `groups`.
  auto two_planes = [&](const std::vector<u32>& fan, std::vector<char>& group, int& groups) {
    const std::size_t n = fan.size();
    group.assign(n, 0);
    groups = 1;
    std::size_t rep[2] = {0, 0};
    for (std::size_t y = 1; y < n; ++y) {
      const u32 ty = fan[y];
      if (same_side(src[fan[rep[0]]], flipped[fan[rep[0]]], src[ty], flipped[ty])) continue;
      if (groups == 2 && same_side(src[fan[rep[1]]], flipped[fan[rep[1]]], src[ty], flipped[ty])) {
        group[y] = 1;
      } else if (groups == 1) {
        rep[1] = y;
        group[y] = 1;
        groups = 2;
      } else {
        return false;
      }
    }
    return true;
  };
  // A source face (operand, face id) is flat when all its triangles lie in the plane of its first
  // with an area (exact; looked at once each, on demand: an operand's triangles are one run of the soup). A
  // triangle without a face id is taken as flat: nothing says what surface it stands for.
  const std::vector<u32> op_first = operand_starts(soup);
  auto source_key = [&](u32 s) { return std::int64_t(soup.operand[s]) << 32 | std::uint32_t(soup.face_id[s]); };
  std::map<std::int64_t, bool> flat_faces;
  auto flat_source = [&](u32 s) {
    if (soup.face_id[s] < 0) return true;
    const std::int64_t key = source_key(s);
    auto [it, inserted] = flat_faces.emplace(key, true);
    if (!inserted) return it->second;
    const auto o = static_cast<std::size_t>(soup.operand[s]);
    u32 ref = kNone;
    for (u32 t = op_first[o]; t < op_first[o + 1] && it->second; ++t) {
      if (soup.face_id[t] != soup.face_id[s] || soup.axis[t] < 0) continue;  // (zero area: no plane)
      if (ref == kNone) {
        ref = t;
        continue;
      }
      const auto& R = soup.tris[ref];
      for (u32 v : soup.tris[t])
        if (orient3d_v(soup, R[0], R[1], R[2], v) != 0) it->second = false;
    }
    return it->second;
  };
  for (int pass = 0; pass < 16; ++pass) {
    soup.poll();
    const std::size_t nt = tris.size();
    // Triangles around each point (counting sort), per pass: for the points whose lists are
    // read, the candidates and their neighbours (on a million-triangle result most points are
    // neither, and listing every point's triangles was most of this function).
    std::vector<char> near(np, 0);
    parallel_blocks(nt, kBlock, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t t = lo; t < hi; ++t) {
        const auto& T = tris[t];
        if (candidate[T[0]] || candidate[T[1]] || candidate[T[2]]) mark(near, T);
      }
    });
    // The triangles with a point whose list is made (the only ones in a list), in order.
    auto is_near = [&](std::size_t t) { return near[tris[t][0]] || near[tris[t][1]] || near[tris[t][2]]; };
    const auto listed_from = block_starts(nt, kBlock, [&](std::size_t lo, std::size_t hi) {
      std::size_t n = 0;
      for (std::size_t t = lo; t < hi; ++t) n += is_near(t);
      return n;
    });
    std::vector<u32> listed(listed_from.total());
    fill_blocks(listed_from, [&](std::size_t lo, std::size_t hi, std::size_t n) {
      for (std::size_t t = lo; t < hi; ++t)
        if (is_near(t)) listed[n++] = static_cast<u32>(t);
    });
    std::vector<u32> off(np + 1, 0);
    for (u32 t : listed)
      for (u32 v : tris[t]) off[v + 1] += near[v];
    for (std::size_t v = 0; v < np; ++v) off[v + 1] += off[v];
    std::vector<u32> around(off[np]);
    {
      std::vector<u32> next(off.begin(), off.end() - 1);
      for (u32 t : listed)
        for (u32 v : tris[t])
          if (near[v]) around[next[v]++] = t;
    }
    // The plane test of every candidate's fan as the pass finds it, in parallel (exact, and most of
    // the work where nothing merges: a curved result's cut points). A collapse changes only the
    // fans of the points it marks `changed`, which the loop below tests again.
    std::vector<char> planes_ok(cands.size(), 0);
    parallel_blocks(cands.size(), 512, [&](std::size_t lo, std::size_t hi) {
      std::vector<u32> fan_;
      std::vector<char> group_;
      for (std::size_t ci = lo; ci < hi; ++ci) {
        const u32 v = cands[ci];
        if (off[v + 1] - off[v] < 3) continue;
        fan_.assign(around.begin() + off[v], around.begin() + off[v + 1]);
        int groups = 0;
        planes_ok[ci] = two_planes(fan_, group_, groups);
      }
    });
    std::vector<char> locked(np, 0), gone(nt, 0), changed(np, 0);  // changed: in a triangle changed
    std::size_t collapsed = 0;
    std::vector<u32> fan, order, targets, nbx, opposite;
    std::vector<std::array<u32, 2>> ab;
    std::vector<char> group, used;
    for (std::size_t ci = 0; ci < cands.size(); ++ci) {
      const u32 v = cands[ci];
      if ((ci & 0xffff) == 0) soup.poll();
      if (locked[v] || off[v + 1] - off[v] < 3) continue;
      if (!changed[v] && !planes_ok[ci]) continue;  // its fan as it was, and that failed
      fan.clear();
      for (u32 i = off[v]; i < off[v + 1]; ++i)
        if (!gone[around[i]]) fan.push_back(around[i]);
      const std::size_t n = fan.size();
      if (n < 3) continue;
      int groups = 0;
      if (!two_planes(fan, group, groups)) continue;
      // A plane's triangles of two source faces (operand and face id) merge only where those
      // faces are flat: a merged triangle keeps one source, and one that spanned two curved faces
      // (stacked coaxial cylinders, whose rims met: merged along the sides' creases) took the
      // other's region for its own; the curved volume and area from its own surface, clamped to
      // that face's extent, lost a third of the sides' area.
      bool ok = true;
      {
        std::int64_t first[2] = {-1, -1};
        bool mixed = false;
        for (std::size_t x = 0; x < n; ++x) {
          const std::int64_t key = source_key(src[fan[x]]);
          std::int64_t& f = first[static_cast<std::size_t>(group[x])];
          if (f < 0) f = key;
          else mixed = mixed || f != key;
        }
        for (std::size_t x = 0; x < n && mixed && ok; ++x) ok = flat_source(src[fan[x]]);
      }
      if (!ok) continue;
      // The fan: each triangle (v, a, b) turned so that v is first; a closed fan has each
      // neighbour once as a and once as b, and following a -> b visits every triangle once.
      ab.resize(n);
      for (std::size_t x = 0; x < n; ++x) {
        const auto& T = tris[fan[x]];
        const int c = T[0] == v ? 0 : T[1] == v ? 1 : 2;
        ab[x] = {T[(c + 1) % 3], T[(c + 2) % 3]};
      }
      order.assign(1, 0);
      used.assign(n, 0);
      used[0] = 1;
      for (std::size_t step = 1; step < n && ok; ++step) {
        const u32 b = ab[order.back()][1];
        std::size_t found = n;
        for (std::size_t y = 0; y < n; ++y)
          if (!used[y] && ab[y][0] == b) {
            if (found != n) ok = false;  // two triangles leave through one edge: not a fan
            found = y;
          }
        if (found == n) ok = false;
        if (!ok) break;
        used[found] = 1;
        order.push_back(static_cast<u32>(found));
      }
      if (!ok || ab[order.back()][1] != ab[order[0]][0]) continue;
      // Candidate targets: for one plane any neighbour; for two, the two ends of the crease (the
      // neighbours where the ring passes from one plane to the other), with v strictly between.
      targets.clear();
      if (groups == 1) {
        for (std::size_t x = 0; x < n; ++x) targets.push_back(ab[order[x]][0]);
      } else {
        for (std::size_t x = 0; x < n; ++x) {
          const u32 y = order[x], z = order[(x + 1) % n];
          if (group[y] != group[z]) targets.push_back(ab[z][0]);  // shared edge v -> ab[z][0]
        }
        if (targets.size() != 2) continue;
        const u32 x1 = targets[0], x2 = targets[1];
        int axis = -1;
        for (int k = 0; k < 3 && axis < 0; ++k)
          if (pts.compare(x1, x2, k) != 0) axis = k;
        if (axis < 0 || pts.compare(x1, v, axis) * pts.compare(v, x2, axis) <= 0) continue;
      }
      for (u32 x : targets) {
        // Link condition: the neighbours v and x share are the third vertices of the two
        // triangles on edge v x. (v's neighbours are each once in ab[.][0], the fan being closed;
        // a few of each, so looked up by scanning.)
        if (locked[x]) continue;  // x has taken triangles this pass: its list is not complete
        opposite.clear();
        for (std::size_t y = 0; y < n; ++y) {
          if (ab[y][0] == x) opposite.push_back(ab[y][1]);
          if (ab[y][1] == x) opposite.push_back(ab[y][0]);
        }
        if (opposite.size() != 2 || opposite[0] == opposite[1]) continue;
        nbx.clear();
        for (u32 i = off[x]; i < off[x + 1]; ++i)
          if (!gone[around[i]])
            for (u32 w : tris[around[i]])
              if (w != x) nbx.push_back(w);
        int shared = 0;
        bool link = true;
        for (const auto& e : ab) {
          const u32 w = e[0];
          if (std::find(nbx.begin(), nbx.end(), w) == nbx.end()) continue;
          if (w != opposite[0] && w != opposite[1]) {
            link = false;
            break;
          }
          ++shared;
        }
        if (!link || shared != 2) continue;
        // Every remaining triangle keeps its orientation in its source's projection.
        bool keeps = true;
        for (std::size_t y = 0; y < n && keeps; ++y) {
          if (ab[y][0] == x || ab[y][1] == x) continue;
          const u32 t = fan[y];
          const int k = soup.axis[src[t]];
          const int want = soup.axis_sign[src[t]] * (flipped[t] ? -1 : 1);
          keeps = pts.orient2d(x, ab[y][0], ab[y][1], k) == want;
          // A triangle with a vertex that rounding will move must not be so thin that the move
          // could turn it over (rounding moves a point by an ulp; here the height is at least a
          // billionth of the longest edge).
          if (keeps && !(pts.is_double(x) && pts.is_double(ab[y][0]) && pts.is_double(ab[y][1]))) {
            const Vec3 &P = pts.approx(x), &Q = pts.approx(ab[y][0]), &R = pts.approx(ab[y][1]);
            const double area2 = (Q - P).cross(R - P).norm();
            const double longest = std::max({(Q - P).squaredNorm(), (R - P).squaredNorm(), (R - Q).squaredNorm()});
            keeps = area2 > 1e-9 * longest;
          }
        }
        if (!keeps) continue;
        for (std::size_t y = 0; y < n; ++y) {
          const u32 t = fan[y];
          for (u32 w : tris[t]) changed[w] = 1;
          if (ab[y][0] == x || ab[y][1] == x) {
            gone[t] = 1;
            continue;
          }
          for (u32& w : tris[t])
            if (w == v) w = x;
        }
        // v is gone and x has taken its triangles (x's list is stale until the next pass); v's
        // other neighbours keep their lists, which hold the triangles they are in (gone ones
        // marked), read afresh.
        locked[v] = locked[x] = 1;
        ++collapsed;
        break;
      }
    }
    if (!collapsed) break;
    removed += collapsed;
    // The triangles that stay, in order (into new arrays: blocks are copied in parallel).
    const auto kept_from = block_starts(nt, kBlock, [&](std::size_t lo, std::size_t hi) {
      std::size_t n = 0;
      for (std::size_t t = lo; t < hi; ++t) n += !gone[t];
      return n;
    });
    {
      const std::size_t w = kept_from.total();
      std::vector<std::array<u32, 3>> tris2(w);
      std::vector<u32> src2(w), piece2(w);
      std::vector<char> flipped2(w);
      fill_blocks(kept_from, [&](std::size_t lo, std::size_t hi, std::size_t n) {
        for (std::size_t t = lo; t < hi; ++t) {
          if (gone[t]) continue;
          tris2[n] = tris[t];
          src2[n] = src[t];
          flipped2[n] = flipped[t];
          piece2[n] = piece[t];
          ++n;
        }
      });
      tris.swap(tris2);
      src.swap(src2);
      flipped.swap(flipped2);
      piece.swap(piece2);
    }
    // The next pass looks again only at the candidates with a changed triangle around them or
    // around a neighbour: a candidate's decision reads its own triangles and its target's (a
    // neighbour), so the others would fail again (plate: 51 thousand candidates looked at in each
    // later pass for 10 collapses).
    std::vector<char> reach(np, 0);
    parallel_blocks(tris.size(), kBlock, [&](std::size_t lo, std::size_t hi) {
      for (std::size_t t = lo; t < hi; ++t) {
        const auto& T = tris[t];
        if (changed[T[0]] || changed[T[1]] || changed[T[2]]) mark(reach, T);
      }
    });
    std::size_t kept = 0;
    for (u32 v : cands) {
      candidate[v] = reach[v];
      if (reach[v]) cands[kept++] = v;
    }
    cands.resize(kept);
    if (cands.empty()) break;
  }
  return removed;
}

}  // namespace wedge::boolean_detail
