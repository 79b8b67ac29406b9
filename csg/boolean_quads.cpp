// Flat quadrilaterals: two cut triangles of one face retriangulated as one, and the cut points on
// their shared diagonal left out (boolean_impl.h, FlatQuads). A step of arrange()
// (boolean_triangulate.cpp), between the first canonical works and the crossings.
//
// Every decision is exact: coplanarity and convexity by orientation tests on input vertices,
// whether a point joins two collinear segments by orient2d and comparisons on its exact
// definition. Groups are chosen in the order of the shared edges' keys, points in id order: the
// result does not depend on the number of threads.
#include <algorithm>
#include <atomic>
#include <iterator>
#include <numeric>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

FlatQuads flat_quads(const Points& pts, const std::vector<u32>& touched, Works& work,
                     const std::vector<char>* fixed) {
  const Soup& soup = pts.soup();
  const std::size_t nw = work.size();
  FlatQuads fq;
  fq.quad.assign(nw, {kNone, kNone, kNone, kNone});
  fq.absorbed.assign(nw, 0);

  // 1. The edges two cut triangles share, and of those the pairs that make a flat quadrilateral.
  struct Rec {
    std::uint64_t key;
    u32 wi;
    int e;
  };
  // (Made in parallel, each work's three in its place; the others last, with the largest key.)
  std::vector<Rec> recs(3 * nw);
  parallel_for(0, nw, [&](std::size_t wi) {
    const u32 t = touched[wi];
    const bool can = !(fixed && (*fixed)[t]) && soup.axis[t] >= 0;
    const auto& T = soup.tris[t];
    for (int e = 0; e < 3; ++e) {
      const u32 a = T[e], b = T[(e + 1) % 3];
      recs[3 * wi + e] = {can ? static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b) : ~std::uint64_t(0),
                          static_cast<u32>(wi), e};
    }
  });
  // By key, then work (the order they were made in: the sort is stable).
  radix_sort(recs, [](const Rec& r) { return r.key; });
  while (!recs.empty() && recs.back().key == ~std::uint64_t(0)) recs.pop_back();
  soup.poll();
  // Whether the two triangles of the edge at recs[i] (an edge of exactly two cut triangles) make a
  // flat quadrilateral, and its corners; decided for every such edge in parallel, then taken in
  // order where neither triangle is taken yet.
  std::vector<std::array<u32, 4>> quad_at(recs.size(), {kNone, kNone, kNone, kNone});
  parallel_for(0, recs.size(), [&](std::size_t i) {
    if (i + 1 >= recs.size() || recs[i].key != recs[i + 1].key || (i + 2 < recs.size() && recs[i + 2].key == recs[i].key) ||
        (i > 0 && recs[i - 1].key == recs[i].key))
      return;  // an edge of one cut triangle, or of more than two
    const u32 t = touched[recs[i].wi], u = touched[recs[i + 1].wi];
    if (soup.operand[t] != soup.operand[u] || soup.face_id[t] != soup.face_id[u] || soup.axis[t] != soup.axis[u] ||
        soup.axis_sign[t] != soup.axis_sign[u])
      return;
    const auto& T = soup.tris[t];
    const auto& U = soup.tris[u];
    const int e = recs[i].e;
    const u32 p = T[e], q = T[(e + 1) % 3], a = T[(e + 2) % 3];
    int f = 0;
    while (f < 3 && !(U[f] == q && U[(f + 1) % 3] == p)) ++f;
    if (f == 3) return;  // not the edge q -> p in u: the two are not oriented alike
    const u32 b = U[(f + 2) % 3];
    if (orient3d_v(soup, T[0], T[1], T[2], b) != 0) return;
    // Strictly convex: a and b on either side of p q, and p and q on either side of a b.
    const int k = soup.axis[t];
    if (pts.orient2d(p, q, a, k) * pts.orient2d(p, q, b, k) >= 0) return;
    if (pts.orient2d(a, b, p, k) * pts.orient2d(a, b, q, k) >= 0) return;
    // The boundary p -> b -> q -> a -> p runs as t's and u's edges do.
    quad_at[i] = {p, b, q, a};
  });
  std::vector<char> taken(nw, 0);
  struct Group {
    u32 first, second;  // works: the first's triangle has the smaller index
  };
  std::vector<Group> groups;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    if (quad_at[i][0] == kNone) continue;
    const u32 wi = recs[i].wi, wj = recs[i + 1].wi;
    if (taken[wi] || taken[wj]) continue;
    taken[wi] = taken[wj] = 1;
    const bool t_first = touched[wi] < touched[wj];
    groups.push_back({t_first ? wi : wj, t_first ? wj : wi});
    fq.quad[t_first ? wi : wj] = quad_at[i];
  }
  fq.groups = groups.size();
  if (groups.empty()) return fq;

  // 2. The points on the diagonals (in both works: t and u meet only there; not its ends), then
  //    each group's works in one. A group whose diagonal is itself a cut somewhere keeps its
  //    points: there a crossing found later (step 3 of arrange) would make them again, in that
  //    work alone. Such a diagonal lies in a plane of another operand: one through the diagonal
  //    (then a cut in the quadrilateral runs along it, checked once merged), or a coplanar
  //    triangle over a half that the diagonal crosses (the halves' edges clipped to it cut it,
  //    the diagonal among them: a segment on the wall over the diagonal). The latter cuts are
  //    erased instead where they can be (below): a sponge's flush bars cut each other's
  //    diagonals so.
  std::vector<char> on_diagonal(pts.size(), 0);
  std::vector<std::vector<u32>> on(groups.size());
  std::vector<char> veto(groups.size(), 0), over(groups.size(), 0);
  std::vector<u32> work_of;  // triangle -> its work, for the coplanar triangles' works
  auto diagonal_cut_over = [&](const Group& g) {
    const auto& quad = fq.quad[g.first];
    const u32 p = quad[0], q = quad[2];
    // (A wall over the diagonal along whichever axis the pair's first triangle projects.)
    auto over = [&](const Plane& c) { return c.axis >= 0 && ((c.a == p && c.b == q) || (c.a == q && c.b == p)); };
    for (u32 wi : {g.first, g.second})
      for (u32 f : work[wi].coplanar) {
        if (work_of[f] == kNone) continue;
        for (const Plane& c : work[work_of[f]].cuts)
          if (over(c)) return true;
      }
    return false;
  };
  for (const Group& g : groups)
    if (!work[g.first].coplanar.empty() || !work[g.second].coplanar.empty()) {
      work_of.assign(soup.tris.size(), kNone);
      for (std::size_t x = 0; x < nw; ++x) work_of[touched[x]] = static_cast<u32>(x);
      break;
    }
  // (Every group looked at before any is merged: a veto reads other works.)
  parallel_for(0, groups.size(), [&](std::size_t gi) {
    const Group& g = groups[gi];
    over[gi] = diagonal_cut_over(g);
    const auto& A = work[g.first].points;
    const auto& B = work[g.second].points;
    std::size_t x = 0, y = 0;
    while (x < A.size() && y < B.size()) {
      if (A[x] < B[y]) ++x;
      else if (B[y] < A[x]) ++y;
      else {
        // (An operand's vertex there stays: the whole triangles around it use it.)
        if (A[x] >= soup.verts.size()) on[gi].push_back(A[x]);
        ++x, ++y;
      }
    }
  });
  // (The first works' arrays as they were are freed after the loop, on this thread, and the
  // second works' are emptied, not freed: a block freed by a thread other than the one that made
  // it costs glibc its arena's lock and the other core's cache lines. Freed in the loop, the
  // sponge's merge took 7.4-9.6 ms at two threads against 3.9 at one; so, 3.4 ms.)
  std::vector<TriWork> before(groups.size());
  parallel_for(0, groups.size(), [&](std::size_t gi) {
    TriWork& w = work[groups[gi].first];
    TriWork& o = work[groups[gi].second];
    // Both canonical: merged in order, a segment in both once (the first work's cut plane kept).
    std::vector<u32> points;
    points.reserve(w.points.size() + o.points.size());
    std::set_union(w.points.begin(), w.points.end(), o.points.begin(), o.points.end(), std::back_inserter(points));
    std::vector<std::array<u32, 2>> segs;
    std::vector<Plane> cuts;
    segs.reserve(w.segs.size() + o.segs.size());
    cuts.reserve(w.segs.size() + o.segs.size());
    std::size_t x = 0, y = 0;
    while (x < w.segs.size() || y < o.segs.size()) {
      if (y == o.segs.size() || (x < w.segs.size() && !(o.segs[y] < w.segs[x]))) {
        if (y < o.segs.size() && o.segs[y] == w.segs[x]) ++y;
        segs.push_back(w.segs[x]);
        cuts.push_back(w.cuts[x++]);
      } else {
        segs.push_back(o.segs[y]);
        cuts.push_back(o.cuts[y++]);
      }
    }
    w.points.swap(points);
    w.segs.swap(segs);
    w.cuts.swap(cuts);
    before[gi].points.swap(points);
    before[gi].segs.swap(segs);
    before[gi].cuts.swap(cuts);
    // Coplanar triangles of other operands over either half (classify tests each for covering a
    // piece's centroid: one over the other half covers none of this half's pieces).
    w.coplanar.insert(w.coplanar.end(), o.coplanar.begin(), o.coplanar.end());
    o.segs.clear();
    o.cuts.clear();
    o.points.clear();
    o.coplanar.clear();
    fq.absorbed[groups[gi].second] = 1;
    // A cut along the diagonal: both its ends on it (the diagonal's own ends are vertices, never
    // in `on`; nor is another operand's vertex on the diagonal, the end of a cut along it: an
    // edge of a flush face lying on the line; a point of the work on the diagonal's line is on
    // the diagonal, the quadrilateral being convex).
    const auto& quad = fq.quad[groups[gi].first];
    const int k = soup.axis[touched[groups[gi].first]];
    auto on_it = [&](u32 v) {
      return v == quad[0] || v == quad[2] || std::binary_search(on[gi].begin(), on[gi].end(), v) ||
             (v < soup.verts.size() && pts.orient2d(quad[0], quad[2], v, k) == 0);
    };
    for (const auto& sg : w.segs)
      if (on_it(sg[0]) && on_it(sg[1])) veto[gi] = 1;
  });
  std::vector<TriWork>().swap(before);
  // A group whose diagonal only coplanar triangles over it cut (not a cut along it in the
  // quadrilateral) may instead erase those cuts, the walls over its diagonal in their works: their
  // pieces then cross the diagonal as the group's own do, and classify tests their centroids
  // against the quadrilateral (Arrangement::quad_partner). Erased only where every point of the
  // diagonal goes (below): a crossing of the diagonal with another cut in such a work would make
  // a point there that no other work has.
  auto diagonal_key = [](u32 a, u32 b) { return static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b); };
  std::vector<char> erase(groups.size(), 0);
  for (std::size_t gi = 0; gi < groups.size(); ++gi)
    if (over[gi] && !veto[gi]) {
      // (Not where a coplanar triangle's cuts settling left out: classify asks about those per
      // triangle.)
      const auto& cop = work[groups[gi].first].coplanar;
      if (fixed && std::any_of(cop.begin(), cop.end(), [&](u32 f) { return (*fixed)[f] != 0; })) {
        veto[gi] = 1;
        continue;
      }
      erase[gi] = 1;
    }
  // The cuts to erase: per (work, diagonal), in the works of the groups' coplanar triangles only
  // (after the merge a group's second half's work is its first's). (Positions are welded across
  // operands, so another operand's edge may join the same two vertices; its walls are not the
  // group's business elsewhere.)
  std::vector<u32> owner(nw);
  std::iota(owner.begin(), owner.end(), 0u);
  for (const Group& g : groups) owner[g.second] = g.first;
  struct Erasable {
    u32 work;
    std::uint64_t diagonal;
    bool operator<(const Erasable& o) const { return work < o.work || (work == o.work && diagonal < o.diagonal); }
  };
  std::vector<Erasable> erasable;  // sorted
  auto list_erasable = [&] {
    erasable.clear();
    for (std::size_t gi = 0; gi < groups.size(); ++gi) {
      if (!erase[gi]) continue;
      const auto& quad = fq.quad[groups[gi].first];
      for (u32 f : work[groups[gi].first].coplanar)
        if (work_of[f] != kNone) erasable.push_back({owner[work_of[f]], diagonal_key(quad[0], quad[2])});
    }
    std::sort(erasable.begin(), erasable.end());
  };
  list_erasable();
  auto erasable_cut = [&](std::size_t wi, const Plane& c) {
    return c.axis >= 0 && !erasable.empty() &&
           std::binary_search(erasable.begin(), erasable.end(), Erasable{static_cast<u32>(wi), diagonal_key(c.a, c.b)});
  };
  // (A point on two diagonals, two faces' diagonals crossing there, goes only where neither
  // vetoes.)
  std::vector<char> vetoed(pts.size(), 0);
  for (std::size_t gi = 0; gi < groups.size(); ++gi)
    if (veto[gi])
      for (u32 m : on[gi]) vetoed[m] = 1;
  std::vector<u32> candidates;
  for (std::size_t gi = 0; gi < groups.size(); ++gi)
    if (!veto[gi])
      for (u32 m : on[gi])
        if (!vetoed[m] && !on_diagonal[m]) {
          on_diagonal[m] = 1;
          candidates.push_back(m);
        }
  std::sort(candidates.begin(), candidates.end());
  soup.poll();
  if (candidates.empty()) return fq;

  // 3. Whether segments s1 and s2 of a work (on its triangle's plane) lie on one line: their
  //    cut planes are one plane (the same, one axis plane x_i = c, or the two halves of a group),
  //    else exactly by orient2d through the far ends e1, e2 and the point m they share.
  std::vector<std::pair<std::array<u32, 3>, std::array<u32, 3>>> halves;  // both ways round, sorted
  for (const Group& g : groups) {
    const auto& A = soup.tris[touched[g.first]];
    const auto& B = soup.tris[touched[g.second]];
    halves.push_back({A, B});
    halves.push_back({B, A});
  }
  std::sort(halves.begin(), halves.end());
  auto one_plane = [&](const Plane& P, const Plane& Q) {
    if (P == Q) return true;
    double c = 0, d = 0;
    for (int i = 0; i < 3; ++i)
      if (fixes_coordinate(soup, P, i, c) && fixes_coordinate(soup, Q, i, d) && c == d) return true;
    if (P.axis >= 0 || Q.axis >= 0) return false;
    const std::pair<std::array<u32, 3>, std::array<u32, 3>> key{{P.a, P.b, P.c}, {Q.a, Q.b, Q.c}};
    return std::binary_search(halves.begin(), halves.end(), key);
  };
  // Points::compare, its boxes first (most of these points are far apart on every axis).
  auto compare = [&](u32 a, u32 b, int axis) {
    const auto A = pts.box(a), B = pts.box(b);
    if (A[axis + 3] < B[axis]) return -1;
    if (A[axis] > B[axis + 3]) return 1;
    return pts.compare(a, b, axis);
  };
  // 4. A point goes where, in every work that holds it, the segments that end at it (two or more)
  //    lie on one line, some on either side of it, or (a point where erasable cuts end) none but
  //    erasable ones end there: each work clears the points it holds that fail that there.
  //    (Overlapping collinear segments of different planes, two flush faces' cuts along one line,
  //    are not merged yet: a line through m may be several segments on one side.)
  std::vector<char> keep(pts.size(), 0);
  auto keep_points = [&] {
    parallel_for(0, nw, [&](std::size_t wi) {
      if ((wi & 0xfff) == 0) soup.poll();
      const TriWork& w = work[wi];
      bool held = false;
      for (u32 m : w.points) held = held || on_diagonal[m];
      if (!held) return;
      // The segments ending at each point on a diagonal (by its place in the sorted points).
      thread_local std::vector<std::array<u32, 2>> ends;  // (place, segment)
      thread_local std::vector<char> erased_end;
      ends.clear();
      erased_end.assign(w.points.size(), 0);
      for (std::size_t s = 0; s < w.segs.size(); ++s) {
        const bool erased = erasable_cut(wi, w.cuts[s]);
        for (u32 m : w.segs[s])
          if (on_diagonal[m]) {
            const auto i = static_cast<u32>(std::lower_bound(w.points.begin(), w.points.end(), m) - w.points.begin());
            if (erased) erased_end[i] = 1;
            else ends.push_back({i, static_cast<u32>(s)});
          }
      }
      std::sort(ends.begin(), ends.end());
      const int k = soup.axis[touched[wi]];
      std::size_t r = 0;
      for (u32 i = 0; i < w.points.size(); ++i) {
        const u32 m = w.points[i];
        const std::size_t r0 = r;
        while (r < ends.size() && ends[r][0] == i) ++r;
        if (!on_diagonal[m]) continue;
        const std::size_t n = r - r0;
        bool ok = n == 0 ? erased_end[i] != 0 : n >= 2;
        if (n >= 2) {
          auto far_end = [&](std::size_t x) {
            const auto& sg = w.segs[ends[x][1]];
            return sg[0] == m ? sg[1] : sg[0];
          };
          const u32 s1 = ends[r0][1], e1 = far_end(r0);
          int axis = 0;  // one along which the line through m and e1 varies
          while (axis < 3 && compare(e1, m, axis) == 0) ++axis;
          bool before = false, after = false;
          for (std::size_t x = r0; x < r && ok; ++x) {
            const u32 e = far_end(x);
            ok = axis < 3 && (x == r0 || one_plane(w.cuts[s1], w.cuts[ends[x][1]]) || pts.orient2d(e1, m, e, k) == 0);
            if (!ok) break;
            const int o = compare(e, m, axis);
            before = before || o < 0;
            after = after || o > 0;
          }
          ok = ok && before && after;
        }
        if (!ok) std::atomic_ref<char>(keep[m]).store(1, std::memory_order_relaxed);
      }
    });
  };
  keep_points();
  soup.poll();
  // A group that erases its diagonal's cuts keeps none of its points. Where one stays, the cuts
  // stay, and so do all its points: the others' decisions are made again without those cuts
  // erased (a point on two diagonals may hold another such group back in turn).
  if (!erasable.empty()) {
    std::vector<char> held_back(groups.size(), 0);
    for (bool again = true; again;) {
      again = false;
      for (std::size_t gi = 0; gi < groups.size(); ++gi) {
        if (!erase[gi] || std::none_of(on[gi].begin(), on[gi].end(), [&](u32 m) { return keep[m] || vetoed[m]; }))
          continue;
        erase[gi] = 0;
        held_back[gi] = 1;
        again = true;
      }
      list_erasable();
      if (!again) break;
      std::fill(keep.begin(), keep.end(), 0);
      keep_points();
      for (std::size_t gi = 0; gi < groups.size(); ++gi)
        if (held_back[gi])
          for (u32 m : on[gi]) keep[m] = 1;
      soup.poll();
    }
    for (std::size_t gi = 0; gi < groups.size(); ++gi)
      if (erase[gi]) fq.erased.push_back({touched[groups[gi].first], touched[groups[gi].second]});
    if (!erasable.empty())
      parallel_for(0, nw, [&](std::size_t wi) {
        TriWork& w = work[wi];
        std::size_t n = 0;
        for (std::size_t s = 0; s < w.segs.size(); ++s)
          if (!erasable_cut(wi, w.cuts[s])) {
            w.segs[n] = w.segs[s];
            w.cuts[n++] = w.cuts[s];
          }
        w.segs.resize(n);
        w.cuts.resize(n);
      });
  }
  std::vector<char> drop(pts.size(), 0);
  std::vector<u32> dropped;
  for (u32 m : candidates)
    if (!keep[m]) {
      drop[m] = 1;
      dropped.push_back(m);
    }
  fq.dropped = dropped.size();
  if (dropped.empty()) return fq;

  // 5. In each work, the chains of segments through dropped points (each on one line) become one
  //    segment each, between the chain's farthest ends (the cut plane of its first: every
  //    segment's plane holds the whole line; nearer ends stay as points on it), and the points go.
  parallel_for(0, nw, [&](std::size_t wi) {
    TriWork& w = work[wi];
    bool any = false;
    for (u32 m : w.points) any = any || drop[m];
    if (!any) return;
    const std::size_t ns = w.segs.size();
    thread_local std::vector<u32> parent, first_at;
    thread_local std::vector<std::array<u32, 2>> chain_ends;
    thread_local std::vector<int> chain_axis;
    parent.resize(ns);
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](u32 x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    // The segments at each dropped point (by its place in the sorted points) are joined.
    first_at.assign(w.points.size(), kNone);
    for (std::size_t s = 0; s < ns; ++s)
      for (u32 m : w.segs[s]) {
        if (!drop[m]) continue;
        u32& f = first_at[static_cast<std::size_t>(std::lower_bound(w.points.begin(), w.points.end(), m) - w.points.begin())];
        if (f == kNone) {
          f = static_cast<u32>(s);
          continue;
        }
        const u32 a = root(f), b = root(static_cast<u32>(s));
        parent[std::max(a, b)] = std::min(a, b);
      }
    // (Made in this thread's arrays and copied back into the work's, which hold them, there being
    // no more segments than before: the work's arrays were made by another thread, which a free
    // here would make wait; see the merge above.)
    thread_local std::vector<std::array<u32, 2>> segs;
    thread_local std::vector<Plane> cuts;
    segs.clear();
    cuts.clear();
    chain_ends.assign(ns, {kNone, kNone});
    chain_axis.assign(ns, -1);
    for (std::size_t s = 0; s < ns; ++s) {
      const u32 r = root(static_cast<u32>(s));
      if (chain_axis[r] < 0) {  // an axis along which the chain's line varies
        int axis = 0;
        while (axis < 3 && compare(w.segs[r][0], w.segs[r][1], axis) == 0) ++axis;
        if (axis == 3) fail("boolean: internal error: a joined cut has one point for both ends");
        chain_axis[r] = axis;
      }
      auto& c = chain_ends[r];
      for (u32 v : w.segs[s]) {
        if (drop[v]) continue;
        if (c[0] == kNone || compare(v, c[0], chain_axis[r]) < 0) c[0] = v;
        if (c[1] == kNone || compare(v, c[1], chain_axis[r]) > 0) c[1] = v;
      }
    }
    for (std::size_t s = 0; s < ns; ++s) {
      if (root(static_cast<u32>(s)) != s) continue;
      const auto& c = chain_ends[s];
      if (c[0] == kNone || c[1] == kNone || c[0] == c[1]) fail("boolean: internal error: a chain of joined cuts has no two ends");
      segs.push_back({std::min(c[0], c[1]), std::max(c[0], c[1])});
      cuts.push_back(w.cuts[s]);
    }
    w.segs.assign(segs.begin(), segs.end());
    w.cuts.assign(cuts.begin(), cuts.end());
    // (A joined segment may repeat one the work has: the retriangulation takes each once.)
    w.points.erase(std::remove_if(w.points.begin(), w.points.end(), [&](u32 m) { return drop[m] != 0; }), w.points.end());
  });
  return fq;
}

}  // namespace wedge::boolean_detail
