// Rounding repair: the rounded result checked exactly and mended where rounding broke it
// (boolean_output.cpp's assemble rounds it). Defects are triangles turned over in their source's
// projection or meeting another beyond what they share; they are mended by collapsing short
// edges and folds, flipping caps, moving rounded vertices by an ulp (boolean_snap.cpp) and, last,
// collapsing a rounded vertex across a flat edge. Shells thinner than rounding are left out.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>
#include <unordered_map>

#include "csg/boolean_impl.h"
#include "kernel/error.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

namespace {



// Removes triangles with a repeated vertex and positions no triangle uses (keeping the
// per-triangle arrays in step, and the rounding's, if given).
void compact(BooleanResult& r, Rounding* rd) {
  std::size_t w = 0;
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    const auto& T = r.mesh.triangles[t];
    if (T[0] == T[1] || T[1] == T[2] || T[2] == T[0]) continue;
    r.mesh.triangles[w] = T;
    r.operand[w] = r.operand[t];
    r.source[w] = r.source[t];
    r.mesh.face_ids[w] = r.mesh.face_ids[t];
    if (rd) {
      rd->src[w] = rd->src[t];
      rd->sign[w] = rd->sign[t];
      rd->recheck[w] = rd->recheck[t];
    }
    ++w;
  }
  r.mesh.triangles.resize(w);
  r.operand.resize(w);
  r.source.resize(w);
  r.mesh.face_ids.resize(w);
  if (rd) {
    rd->src.resize(w);
    rd->sign.resize(w);
    rd->recheck.resize(w);
  }
  std::vector<u32> index(r.mesh.positions.size(), kNone);
  std::vector<Vec3> pos;
  std::vector<char> mv, alt;
  const bool altered = rd && !rd->altered.empty();
  for (auto& T : r.mesh.triangles)
    for (auto& v : T) {
      if (index[v] == kNone) {
        index[v] = static_cast<u32>(pos.size());
        pos.push_back(r.mesh.positions[v]);
        if (rd) mv.push_back(rd->moved[v]);
        if (altered) alt.push_back(rd->altered[v]);
      }
      v = index[v];
    }
  r.mesh.positions.swap(pos);
  if (rd) rd->moved.swap(mv);
  if (altered) rd->altered.swap(alt);
}


}  // namespace

// The orientation of mesh triangle t in the projection along axis k (exact).
int projected_orientation(const Mesh& m, std::size_t t, int k) {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  const auto& T = m.triangles[t];
  auto p2 = [&](int c) { return Point2(m.positions[T[c]][i], m.positions[T[c]][j]); };
  return orient2d(p2(0), p2(1), p2(2));
}


namespace {

// The link condition of an edge a - b, for its collapse: the vertices neighbouring both a and b
// are just the two opposite the edge. around[v] lists the triangles at v (for a and b), of which
// those `live` rejects are passed over. Afterwards `na` holds a's neighbours. The lists are
// kept between calls (nothing allocated per edge).
struct LinkTest {
  std::vector<u32> na, nb, common, opposite;

  template <class Live>
  bool operator()(const std::vector<std::array<u32, 3>>& tris, const std::vector<std::vector<u32>>& around, u32 a,
                  u32 b, Live&& live) {
    neighbours(tris, around, a, live, na);
    neighbours(tris, around, b, live, nb);
    common.clear();
    opposite.clear();
    std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
    for (u32 x : around[a]) {
      const auto& X = tris[x];
      if (live(x) && (X[0] == b || X[1] == b || X[2] == b))
        for (u32 v : X)
          if (v != a && v != b) opposite.push_back(v);
    }
    std::sort(opposite.begin(), opposite.end());
    return opposite.size() == 2 && common == opposite;
  }

 private:
  template <class Live>
  static void neighbours(const std::vector<std::array<u32, 3>>& tris, const std::vector<std::vector<u32>>& around,
                         u32 a, Live& live, std::vector<u32>& n) {
    n.clear();
    for (u32 x : around[a])
      if (live(x))
        for (u32 v : tris[x])
          if (v != a) n.push_back(v);
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
};

// How far (approximately) position p is from the plane of soup triangle t.
double plane_gap(const Soup& s, u32 t, const Vec3& p) {
  const Vec3 &a = s.verts[s.tris[t][0]], &b = s.verts[s.tris[t][1]], &c = s.verts[s.tris[t][2]];
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  return len > 0 ? std::abs(n.dot(p - a)) / len : 0.0;
}

// Whether the triangles `star` (each holding v) close around v as one disk: each link edge x -> y
// (for the triangle v, x, y in turn) starts at a different x, and they join into one cycle.
bool one_disk(u32 v, const std::vector<std::array<u32, 3>>& star) {
  if (star.empty()) return false;
  std::vector<std::pair<u32, u32>> link;
  for (const auto& T : star) {
    const int k = T[0] == v ? 0 : (T[1] == v ? 1 : 2);
    link.push_back({T[(k + 1) % 3], T[(k + 2) % 3]});
  }
  std::sort(link.begin(), link.end());
  for (std::size_t i = 1; i < link.size(); ++i)
    if (link[i].first == link[i - 1].first) return false;
  u32 at = link[0].first;
  for (std::size_t steps = 0; steps < link.size(); ++steps) {
    auto it = std::lower_bound(link.begin(), link.end(), std::make_pair(at, u32(0)));
    if (it == link.end() || it->first != at) return false;
    at = it->second;
    if (at == link[0].first) return steps + 1 == link.size();
  }
  return false;
}

// The disks the triangles `star` (each holding v) make around v: each link edge x -> y starts at
// a different x, and they join into cycles. Returns each cycle's indices into star, or nothing
// where they are no union of disks (a link vertex met twice, a chain that does not close).
std::vector<std::vector<u32>> disks(u32 v, const std::vector<std::array<u32, 3>>& star) {
  std::vector<std::array<u32, 3>> link;  // x, y, index in star
  for (u32 i = 0; i < star.size(); ++i) {
    const auto& T = star[i];
    const int k = T[0] == v ? 0 : (T[1] == v ? 1 : 2);
    link.push_back({T[(k + 1) % 3], T[(k + 2) % 3], i});
  }
  std::sort(link.begin(), link.end());
  for (std::size_t i = 1; i < link.size(); ++i)
    if (link[i][0] == link[i - 1][0]) return {};
  std::vector<char> used(link.size(), 0);
  std::vector<std::vector<u32>> out;
  for (std::size_t s = 0; s < link.size(); ++s) {
    if (used[s]) continue;
    std::vector<u32> cycle;
    std::size_t at = s;
    while (!used[at]) {
      used[at] = 1;
      cycle.push_back(link[at][2]);
      auto it = std::lower_bound(link.begin(), link.end(), std::array<u32, 3>{link[at][1], 0, 0});
      if (it == link.end() || (*it)[0] != link[at][1]) return {};
      at = static_cast<std::size_t>(it - link.begin());
    }
    if (at != s) return {};
    out.push_back(std::move(cycle));
  }
  return out;
}

// An edge collapse a -> b where the link condition fails can still leave a closed manifold: the
// two triangles of a fold (a, c, d) and (b, d, c) become one triangle both ways round, a film of
// no volume, and go. (A wall thinner than rounding, turned, folds so: a short edge's ends had a
// common neighbour beyond the two opposite vertices, and no pass could collapse it.) The collapse
// is made where every vertex it changes keeps one disk of triangles around it, and none of them
// is `touched` (changed earlier in the same sweep, which the stars, made once, do not know).
// Triangles that go become {b, b, b}. With `pinch`, a vertex left with several disks around it
// (two sheets nearer than rounding, met at one point: a thin wedge's vertices a few ulps apart)
// is allowed: `pinches` then lists, per extra disk, the vertex and its triangles there, which the
// caller gives a copy of the vertex (shells touching at a point, each kept a manifold, as the
// output keeps touching operands).
class FoldCollapse {
 public:
  FoldCollapse(std::vector<std::array<u32, 3>>& tris, std::size_t nv, std::vector<char>& touched, bool pinch = false)
      : tris_(tris), nv_(nv), touched_(touched), pinch_(pinch) {}
  std::vector<u32> changed;  // the triangles the last collapse changed
  std::vector<std::pair<u32, std::vector<u32>>> pinches;  // (vertex, triangles of one extra disk)

  bool operator()(u32 a, u32 b) {
    stars();
    changed.clear();
    pinches.clear();
    std::vector<u32> set(star_tri_.begin() + star_first_[a], star_tri_.begin() + star_first_[a + 1]);
    set.insert(set.end(), star_tri_.begin() + star_first_[b], star_tri_.begin() + star_first_[b + 1]);
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    std::vector<std::array<u32, 3>> now(set.size());
    std::vector<char> gone(set.size(), 0);
    std::vector<u32> affected;
    for (std::size_t i = 0; i < set.size(); ++i) {
      now[i] = tris_[set[i]];
      for (u32& v : now[i]) {
        affected.push_back(v);
        if (v == a) v = b;
      }
      gone[i] = now[i][0] == now[i][1] || now[i][1] == now[i][2] || now[i][2] == now[i][0];
    }
    // A triangle and its reverse cancel; the same triangle twice is no manifold.
    auto canon = [](std::array<u32, 3> T) {
      while (T[0] > T[1] || T[0] > T[2]) T = {T[1], T[2], T[0]};
      return T;
    };
    for (std::size_t i = 0; i < set.size(); ++i)
      for (std::size_t j = i + 1; j < set.size() && !gone[i]; ++j) {
        if (gone[j]) continue;
        const auto x = canon(now[i]), y = canon(now[j]);
        if (x == y) return false;
        if (x == canon({now[j][0], now[j][2], now[j][1]})) gone[i] = gone[j] = 1;
      }
    std::sort(affected.begin(), affected.end());
    affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
    for (u32 w : affected) {
      if (touched_[w]) return false;
      if (w == a) continue;
      std::vector<std::array<u32, 3>> star;
      std::vector<u32> ids;  // star's triangles' indices
      for (u32 k = star_first_[w]; k < star_first_[w + 1]; ++k)
        if (!std::binary_search(set.begin(), set.end(), star_tri_[k])) {
          star.push_back(tris_[star_tri_[k]]);
          ids.push_back(star_tri_[k]);
        }
      for (std::size_t i = 0; i < set.size(); ++i)
        if (!gone[i] && (now[i][0] == w || now[i][1] == w || now[i][2] == w)) {
          star.push_back(now[i]);
          ids.push_back(set[i]);
        }
      if (star.empty()) {
        if (w == b) return false;
        continue;
      }
      if (one_disk(w, star)) continue;
      if (!pinch_) return false;
      const auto cycles = disks(w, star);
      if (cycles.size() < 2) return false;
      for (std::size_t c = 1; c < cycles.size(); ++c) {
        std::vector<u32> in;
        for (u32 i : cycles[c]) in.push_back(ids[i]);
        pinches.push_back({w, std::move(in)});
      }
    }
    for (std::size_t i = 0; i < set.size(); ++i) {
      tris_[set[i]] = gone[i] ? std::array<u32, 3>{b, b, b} : now[i];
      changed.push_back(set[i]);
    }
    for (u32 w : affected) touched_[w] = 1;
    return true;
  }

 private:
  // Every vertex's triangles, made when first needed.
  void stars() {
    if (!star_first_.empty()) return;
    star_first_.assign(nv_ + 1, 0);
    for (const auto& T : tris_)
      for (u32 v : T) ++star_first_[v + 1];
    for (std::size_t v = 0; v < nv_; ++v) star_first_[v + 1] += star_first_[v];
    star_tri_.resize(star_first_.back());
    std::vector<u32> fill(star_first_.begin(), star_first_.end() - 1);
    for (std::size_t t = 0; t < tris_.size(); ++t)
      for (u32 v : tris_[t]) star_tri_[fill[v]++] = static_cast<u32>(t);
  }

  std::vector<std::array<u32, 3>>& tris_;
  std::size_t nv_;
  std::vector<char>& touched_;
  bool pinch_;
  std::vector<u32> star_first_, star_tri_;
};

}  // namespace

std::size_t collapse_short_edges(BooleanResult& r, double tau) {
  auto& tris = r.mesh.triangles;
  std::size_t total = 0;
  for (int sweep = 0; sweep < 8; ++sweep) {
    struct Edge {
      double len2;
      u32 a, b;
    };
    std::vector<Edge> edges;
    for (const auto& T : tris)
      for (int e = 0; e < 3; ++e) {
        const u32 a = T[e], b = T[(e + 1) % 3];
        const double l2 = (r.mesh.positions[a] - r.mesh.positions[b]).squaredNorm();
        if (a < b && l2 < tau * tau) edges.push_back({l2, a, b});
      }
    if (edges.empty()) break;
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
      return x.len2 != y.len2 ? x.len2 < y.len2 : (x.a != y.a ? x.a < y.a : x.b < y.b);
    });
    std::vector<char> touched(r.mesh.positions.size(), 0);
    FoldCollapse fold(tris, r.mesh.positions.size(), touched);
    std::size_t made = 0;
    for (const Edge& e : edges) made += fold(e.b, e.a) || fold(e.a, e.b);  // the larger index goes, if it may
    if (!made) break;
    total += made;
    compact(r, nullptr);
  }
  return total;
}


// Rounding repair: each bad triangle loses its shortest edge that has a rounded end, one end
// collapsing into the other where the collapse keeps the surface a manifold (the link
// condition). Of the two directions the one that keeps the surviving triangles closest to their
// source planes is taken, and an input vertex never moves. Where no edge can go, and `snap` is
// set, rounded vertices of the bad triangles move to neighbouring doubles (snap_rounded,
// boolean_snap.cpp). Repeated until the exact check finds nothing.
bool repair_rounding(BooleanResult& r, Rounding& rd, std::vector<u32>* left, bool snap, std::size_t* flat_shells) {
  // Only edges that rounding itself could have made (a billionth of the model's size) are
  // collapsed: collapsing a longer one would move the surface by more than rounding did. (The
  // bounds once there is something to mend: a pass over a million positions otherwise.)
  double limit = 0, limit2 = 0, flat_tol = 0;
  int snaps = 0;
  // Each round changes a triangle's neighbourhood once: a cluster of defects (a strip of caps
  // along a wall thinner than rounding) takes many rounds. The repair goes on while the number of
  // defects keeps reaching new lows, and stops 16 rounds after the last one.
  std::size_t fewest = SIZE_MAX;
  for (int round = 0, since = 0; round < 1024 && since < 16; ++round, ++since) {
    rd.soup->poll();
    std::vector<u32> bad = rounding_defects(r.mesh, rd);
    if (bad.empty()) return true;
    if (round == 0) {
      const Box3 bounds = r.mesh.bounds();
      limit = 1e-9 * (bounds.max - bounds.min).norm();
      limit2 = limit * limit;
      flat_tol = 0x1p-46 * std::max(bounds.max.cwiseAbs().maxCoeff(), bounds.min.cwiseAbs().maxCoeff());
      // Shells thinner than rounding go first (they would be left out after the repair anyway):
      // where rounding has turned thousands of slivers between nearly coincident sheets inside
      // out, the repair worked round them for seconds and failed (a difference of three such
      // spheres: 3.1 s, then 9 ms without them), and the next check sees what is left.
      if (flat_shells)
        if (const std::size_t n = drop_flat_shells(r, rd)) {
          *flat_shells += n;
          continue;
        }
    }
    if (bad.size() < fewest) fewest = bad.size(), since = 0;
    // What the next round checks: the triangles still bad and those a collapse changes.
    std::fill(rd.recheck.begin(), rd.recheck.end(), 0);
    for (u32 t : bad) rd.recheck[t] = 1;
    auto& tris = r.mesh.triangles;
    // The triangles around each vertex of a bad triangle (the only vertices a collapse moves).
    std::vector<char> wanted(r.mesh.positions.size(), 0);
    for (u32 t : bad)
      for (u32 v : tris[t]) wanted[v] = 1;
    std::vector<std::vector<u32>> around(r.mesh.positions.size());
    for (std::size_t t = 0; t < tris.size(); ++t)
      for (u32 v : tris[t])
        if (wanted[v]) around[v].push_back(static_cast<u32>(t));
    std::vector<char> touched(r.mesh.positions.size(), 0);
    bool changed = false;
    LinkTest link;
    // The largest distance of b from the source planes of a's triangles that survive a -> b.
    auto cost = [&](u32 a, u32 b) {
      double worst = 0;
      for (u32 x : around[a]) {
        const auto& X = tris[x];
        if (X[0] == b || X[1] == b || X[2] == b) continue;
        worst = std::max(worst, plane_gap(*rd.soup, rd.src[x], r.mesh.positions[b]));
      }
      return worst;
    };
    // A cap: t's vertex v lies within rounding of its longest edge a -> b (a wall thinner than
    // rounding, met by a face of another copy, leaves these with every edge long: no collapse
    // removes them). The edge is flipped: t and its neighbour (b, a, w) become (a, w, v) and
    // (w, b, v), which cover the neighbour's part of the surface to within t's height. The
    // neighbour's source and orientation go to both; the next check decides if they hold.
    auto flip_cap = [&](u32 t) {
      const auto T = tris[t];
      int e = 0;
      double longest = -1;
      for (int k = 0; k < 3; ++k) {
        const double l = (r.mesh.positions[T[k]] - r.mesh.positions[T[(k + 1) % 3]]).squaredNorm();
        if (l > longest) longest = l, e = k;
      }
      const u32 a = T[e], b = T[(e + 1) % 3], v = T[(e + 2) % 3];
      if (touched[a] || touched[b] || touched[v]) return false;
      const Vec3 &pa = r.mesh.positions[a], &pb = r.mesh.positions[b], &pv = r.mesh.positions[v];
      const double height = (pb - pa).cross(pv - pa).norm() / std::sqrt(longest);
      if (!(height <= limit)) return false;
      u32 u = kNone, w = kNone;
      for (u32 x : around[a]) {
        const auto& X = tris[x];
        for (int k = 0; k < 3; ++k)
          if (X[k] == b && X[(k + 1) % 3] == a) {
            if (u != kNone) return false;  // not a manifold edge
            u = x, w = X[(k + 2) % 3];
          }
      }
      if (u == kNone || w == v || touched[w]) return false;
      for (u32 x : around[v])
        for (u32 y : tris[x])
          if (y == w) return false;  // v - w is an edge already
      tris[t] = {a, w, v};
      tris[u] = {w, b, v};
      rd.src[t] = rd.src[u];
      rd.sign[t] = rd.sign[u];
      r.operand[t] = r.operand[u];
      r.source[t] = r.source[u];
      r.mesh.face_ids[t] = r.mesh.face_ids[u];
      rd.recheck[t] = rd.recheck[u] = 1;
      touched[a] = touched[b] = touched[v] = touched[w] = 1;
      ++rd.collapses;
      return true;
    };
    FoldCollapse folds(tris, r.mesh.positions.size(), touched, true);
    // a -> b: a goes, its triangles take b, where the link condition holds (the common
    // neighbours of a and b are the two opposite vertices), or else (with `fold`) where a fold's
    // two triangles come to lie on each other and both go.
    auto collapse = [&](u32 a, u32 b, bool fold) {
      if (!link(tris, around, a, b, [](u32) { return true; })) {
        if (!fold || !folds(a, b)) return false;
        for (u32 x : folds.changed) rd.recheck[x] = 1;
        // A vertex left with several disks: a copy of it for each disk after the first.
        for (const auto& [w, in] : folds.pinches) {
          const u32 copy = static_cast<u32>(r.mesh.positions.size());
          r.mesh.positions.push_back(r.mesh.positions[w]);
          rd.moved.push_back(rd.moved[w]);
          if (!rd.altered.empty()) rd.altered.push_back(1);
          touched.push_back(1);
          around.emplace_back();
          for (u32 x : in) {
            for (u32& v : tris[x])
              if (v == w) v = copy;
            rd.recheck[x] = 1;
          }
        }
        ++rd.collapses;
        return true;
      }
      for (u32 x : around[a]) {
        for (u32& v : tris[x])
          if (v == a) v = b;
        rd.recheck[x] = 1;
      }
      for (u32 v : link.na) touched[v] = 1;
      touched[a] = touched[b] = 1;
      ++rd.collapses;
      return true;
    };
    for (u32 t : bad) {
      const auto T = tris[t];
      if (touched[T[0]] || touched[T[1]] || touched[T[2]]) continue;
      // Candidate edges, shortest first.
      std::array<int, 3> order = {0, 1, 2};
      auto len = [&](int e) { return (r.mesh.positions[T[e]] - r.mesh.positions[T[(e + 1) % 3]]).squaredNorm(); };
      std::sort(order.begin(), order.end(), [&](int x, int y) { return len(x) < len(y); });
      bool done = false;
      for (int e : order) {
        u32 a = T[e], b = T[(e + 1) % 3];
        if (!rd.moved[a] && !rd.moved[b]) continue;
        if (len(e) > limit2) break;  // sorted: every later edge is longer
        if (!rd.moved[a]) std::swap(a, b);  // a is removed, b kept
        else if (rd.moved[b]) {
          const double ab = cost(a, b), ba = cost(b, a);
          if (ba < ab || (ba == ab && b > a)) std::swap(a, b);
        }
        if (collapse(a, b, true)) {
          changed = done = true;
          break;
        }
      }
      // Flips can undo each other round after round (a cap flipped, a cap beside it flipped
      // back): after 4 rounds without a new low they stop, and the means below get their turn.
      if (!done && since < 4 && flip_cap(t)) changed = true;
    }
    if (!changed) {
      // No short edge to collapse: rounded vertices of the bad triangles may move by a few ulps.
      if (snap && snaps < 4 && (++snaps, snap_rounded(r.mesh, *rd.soup, rd.src, rd.sign, rd.moved, bad, rd.recheck) > 0))
        continue;
      // Last, a bad triangle's rounded vertex goes into a neighbour across an edge of any
      // length where every triangle around it stays within flat_tol of its source's plane:
      // sheets a few ulps apart (nearly flush faces, one of them split off its plane by its own
      // rounding) whose pieces rounding made overlap; the surface moves by no more than that.
      // A vertex with a copy at its position (sheets touching there) stays: collapsed into a
      // neighbour, it would leave the two sheets' edges crossing with no vertex between them.
      std::vector<char> twin(r.mesh.positions.size(), 0);
      {
        std::vector<u32> at;
        for (u32 t : bad)
          for (u32 v : tris[t])
            if (rd.moved[v]) at.push_back(v);
        std::sort(at.begin(), at.end());
        at.erase(std::unique(at.begin(), at.end()), at.end());
        if (!at.empty()) {
          std::vector<u32> order(r.mesh.positions.size());
          std::iota(order.begin(), order.end(), 0u);
          auto less = [&](u32 x, u32 y) {
            const Vec3 &p = r.mesh.positions[x], &q = r.mesh.positions[y];
            return p.x() != q.x() ? p.x() < q.x() : p.y() != q.y() ? p.y() < q.y() : p.z() < q.z();
          };
          std::sort(order.begin(), order.end(), less);
          for (u32 v : at) {
            auto range = std::equal_range(order.begin(), order.end(), v, less);
            twin[v] = range.second - range.first > 1;
          }
        }
      }
      for (u32 t : bad) {
        const auto T = tris[t];
        if (touched[T[0]] || touched[T[1]] || touched[T[2]]) continue;
        std::array<std::pair<double, std::array<u32, 2>>, 6> ways;
        int n = 0;
        for (int e = 0; e < 3; ++e)
          for (int d = 0; d < 2; ++d) {
            const u32 a = d ? T[(e + 1) % 3] : T[e], b = d ? T[e] : T[(e + 1) % 3];
            if (!rd.moved[a] || twin[a]) continue;
            const double c = cost(a, b);
            if (c <= flat_tol) ways[n++] = {c, {a, b}};
          }
        std::sort(ways.begin(), ways.begin() + n);
        for (int i = 0; i < n; ++i)
          if (collapse(ways[i].second[0], ways[i].second[1], false)) {
            changed = true;
            break;
          }
      }
      if (!changed) break;
    }
    // The vertices whose triangles changed: their shells are no longer as classification made
    // them (drop_flat_shells looks at those too).
    rd.altered.resize(r.mesh.positions.size(), 0);
    for (std::size_t t = 0; t < tris.size(); ++t)
      if (rd.recheck[t])
        for (u32 v : tris[t]) rd.altered[v] = 1;
    compact(r, &rd);
  }
  std::vector<u32> bad = rounding_defects(r.mesh, rd);
  const bool ok = bad.empty();
  if (left) *left = std::move(bad);
  return ok;
}

std::size_t collapse_ulp_edges(BooleanResult& r, Rounding& rd, BooleanResult* saved, Rounding* saved_rd) {
  auto& tris = r.mesh.triangles;
  const auto& P = r.mesh.positions;
  const std::size_t nt = tris.size(), nv = P.size();
  // 8 to 16 ulps of the larger end's largest coordinate (an ulp of m is within m 2^-53 .. m 2^-52).
  auto ulp_short = [&](u32 a, u32 b) {
    const double m = std::max(P[a].cwiseAbs().maxCoeff(), P[b].cwiseAbs().maxCoeff());
    const double d = (P[a] - P[b]).cwiseAbs().maxCoeff();
    return d > 0 && d <= m * 0x1p-49;
  };
  // The edges with an end that rounding moved: only in triangles to recheck (a triangle with a
  // moved vertex is one), except in a re-resolution, whose earlier passes' rounded points may
  // move but are in triangles rechecked only where this pass rounded a point. Found per block in
  // parallel; sorted below, so in no order here.
  using Edge = std::pair<double, std::array<u32, 2>>;
  constexpr std::size_t kBlock = 65536;
  std::vector<std::vector<Edge>> found((nt + kBlock - 1) / kBlock);
  const bool every = !rd.soup->movable.empty();
  parallel_blocks(nt, kBlock, [&](std::size_t lo, std::size_t hi) {
    auto& out = found[lo / kBlock];
    for (std::size_t t = lo; t < hi; ++t) {
      if (!every && !rd.recheck[t]) continue;
      for (int e = 0; e < 3; ++e) {
        const u32 a = tris[t][e], b = tris[t][(e + 1) % 3];
        if (a < b && (rd.moved[a] || rd.moved[b]) && ulp_short(a, b))
          out.push_back({(P[a] - P[b]).squaredNorm(), {a, b}});
      }
    }
  });
  std::vector<Edge> edges;
  for (const auto& f : found) edges.insert(edges.end(), f.begin(), f.end());
  if (edges.empty()) return 0;
  std::sort(edges.begin(), edges.end());
  *saved = r;
  *saved_rd = rd;
  std::vector<char> wanted(nv, 0);
  for (const auto& e : edges) wanted[e.second[0]] = wanted[e.second[1]] = 1;
  std::vector<std::vector<u32>> around(nv);  // may list triangles gone (a repeated vertex)
  for (std::size_t t = 0; t < nt; ++t)
    for (u32 v : tris[t])
      if (wanted[v]) around[v].push_back(static_cast<u32>(t));
  auto gone = [&](u32 x) { const auto& X = tris[x]; return X[0] == X[1] || X[1] == X[2] || X[2] == X[0]; };
  std::vector<char> changed(nt, 0);
  std::vector<u32> into(nv);  // where each vertex went (itself while it stays)
  std::iota(into.begin(), into.end(), 0u);
  LinkTest link;
  std::size_t done = 0;
  // A collapse changes its neighbourhood: one per neighbourhood in a sweep, a few sweeps (a
  // cluster of such points).
  for (int sweep = 0; sweep < 4; ++sweep) {
    std::vector<char> touched(nv, 0);
    const std::size_t done_before = done;
    for (const auto& [len, ab] : edges) {
      u32 a = ab[0], b = ab[1];
      if (into[a] != a || into[b] != b || touched[a] || touched[b]) continue;
      if (!rd.moved[a]) std::swap(a, b);  // a goes, b stays
      if (!link(tris, around, a, b, [&](u32 x) { return !gone(x); })) continue;
      // Every triangle that stays keeps its orientation in its source's projection.
      bool keeps = true;
      for (u32 x : around[a]) {
        auto X = tris[x];
        if (gone(x) || X[0] == b || X[1] == b || X[2] == b) continue;
        for (u32& v : X)
          if (v == a) v = b;
        const int k = rd.soup->axis[rd.src[x]], i = (k + 1) % 3, j = (k + 2) % 3;
        if (k < 0 || orient2d_fast(P[X[0]][i], P[X[0]][j], P[X[1]][i], P[X[1]][j], P[X[2]][i], P[X[2]][j]) != rd.sign[x]) {
          keeps = false;
          break;
        }
      }
      if (!keeps) continue;
      // b stays within rounding of the source plane of every triangle it joins (as each rounded
      // vertex is of its own).
      {
        const double m = P[b].cwiseAbs().maxCoeff(), ulp = std::nextafter(m, INFINITY) - m;
        for (u32 x : around[a])
          if (!gone(x) && plane_gap(*rd.soup, rd.src[x], P[b]) > ulp) keeps = false;
      }
      if (!keeps) continue;
      for (u32 x : around[a]) {
        if (gone(x)) continue;
        for (u32& v : tris[x])
          if (v == a) v = b;
        rd.recheck[x] = changed[x] = 1;
        around[b].push_back(x);
      }
      into[a] = b;
      for (u32 v : link.na) touched[v] = 1;
      touched[a] = touched[b] = 1;
      ++done;
    }
    if (done == done_before) break;
    for (auto& l : around) {
      std::sort(l.begin(), l.end());
      l.erase(std::unique(l.begin(), l.end()), l.end());
    }
  }
  if (done == 0) return 0;
  rd.altered.resize(nv, 0);
  for (std::size_t t = 0; t < nt; ++t)
    if (changed[t])
      for (u32 v : tris[t]) rd.altered[v] = 1;
  compact(r, &rd);
  return done;
}

// Removes the shells thinner than rounding: a shell with a vertex that rounding moved whose
// volume is within what moving its vertices by a few ulps could change (and the error of
// computing it). Rounding can turn such a shell inside out without any triangle crossing another
// or turning over in its source's projection (a sliver tetrahedron between nearly coincident
// faces, three of its corners nearly on one line: the checks above find nothing), and its exact
// volume is below what doubles hold at its size. Shells are the components joined through shared
// vertices (touching solids have their own copies). Returns the number removed.
std::size_t drop_flat_shells(BooleanResult& r, Rounding& rd) {
  const auto& P = r.mesh.positions;
  auto& tris = r.mesh.triangles;
  const std::size_t nv = P.size(), nt = tris.size();
  if (nt == 0) return 0;
  Dsu shell(nv);
  shell.unite_each(nt, 16384, [&](std::size_t lo, std::size_t hi, auto&& unite) {
    for (std::size_t t = lo; t < hi; ++t) {
      unite(tris[t][0], tris[t][1]);
      unite(tris[t][0], tris[t][2]);
    }
  });
  std::vector<u32> root(nv);
  parallel_for(0, nv, [&](std::size_t v) { root[v] = shell.root(static_cast<u32>(v)); });
  // Per shell (by root, its smallest vertex: the origin of its sums, so that their error scales
  // with the shell's size and not its place): whether a vertex moved, the largest coordinate,
  // six times the volume (Kahan sums), twice the area, and what bounds the sums' errors. Summed
  // per block of triangles in order, and the blocks in order: the same bits at any thread count.
  struct Sums {
    u32 root;
    bool moved = false;
    double reach = 0, vol = 0, comp = 0, area = 0, size = 0, magnitude = 0;
  };
  constexpr std::size_t kBlock = 16384;
  std::vector<double> bigs((nv + kBlock - 1) / kBlock, 0);
  parallel_for(0, bigs.size(), [&](std::size_t b) {
    for (std::size_t v = b * kBlock; v < std::min(nv, (b + 1) * kBlock); ++v)
      bigs[b] = std::max(bigs[b], P[v].cwiseAbs().maxCoeff());
  });
  const double big = *std::max_element(bigs.begin(), bigs.end());
  if (!(big > 0) || !std::isfinite(big)) return 0;
  const double scale = std::ldexp(1.0, -std::ilogb(big));
  const std::size_t nb = (nt + kBlock - 1) / kBlock;
  // With `screen`: the area and size terms by L1 norms (no smaller than the lengths; no square
  // roots) and no reach (the model's is no smaller than a shell's).
  auto shell_sums = [&](bool screen) {
    std::vector<std::vector<Sums>> blocks(nb);
    parallel_for(0, nb, [&](std::size_t b) {
      auto& out = blocks[b];
      for (std::size_t t = b * kBlock; t < std::min(nt, (b + 1) * kBlock); ++t) {
        const auto& T = tris[t];
        const u32 s = root[T[0]];
        if (out.empty() || out.back().root != s) {
          auto it = std::find_if(out.begin(), out.end(), [&](const Sums& x) { return x.root == s; });
          if (it == out.end()) out.push_back({s});
          else std::rotate(it, it + 1, out.end());  // the last one used goes last
        }
        Sums& x = out.back();
        const Vec3& o = P[s];
        // Scaled by a power of two (exact) to the model's size: no underflow at 1e-150.
        const Vec3 a = (P[T[0]] - o) * scale, e1 = (P[T[1]] - P[T[0]]) * scale, e2 = (P[T[2]] - P[T[0]]) * scale;
        const Vec3 n = e1.cross(e2);
        const double det = a.dot(n);
        const double y = det - x.comp, sum = x.vol + y;
        x.comp = (sum - x.vol) - y;
        x.vol = sum;
        x.magnitude += std::abs(det);
        for (u32 v : T) x.moved |= rd.moved[v] != 0 || (!rd.altered.empty() && rd.altered[v] != 0);
        if (screen) {
          x.area += n.cwiseAbs().sum();
          x.size += a.cwiseAbs().sum() * e1.cwiseAbs().sum() * e2.cwiseAbs().sum();
          continue;
        }
        x.area += n.norm();
        x.size += a.norm() * e1.norm() * e2.norm();
        for (u32 v : T) x.reach = std::max(x.reach, P[v].cwiseAbs().maxCoeff());
      }
      std::sort(out.begin(), out.end(), [](const Sums& x, const Sums& y) { return x.root < y.root; });
    });
    // The blocks' sums of each shell, in block order (a stable sort), folded into the first.
    std::vector<Sums> parts, all;
    for (const auto& out : blocks) parts.insert(parts.end(), out.begin(), out.end());
    std::stable_sort(parts.begin(), parts.end(), [](const Sums& x, const Sums& y) { return x.root < y.root; });
    for (const Sums& x : parts) {
      if (all.empty() || all.back().root != x.root) {
        all.push_back(x);
        continue;
      }
      Sums& a = all.back();
      a.moved |= x.moved;
      a.reach = std::max(a.reach, x.reach);
      const double y = x.vol - a.comp, sum = a.vol + y;
      a.comp = (sum - a.vol) - y + x.comp;
      a.vol = sum;
      a.area += x.area;
      a.size += x.size;
      a.magnitude += x.magnitude;
    }
    return all;
  };
  constexpr double eps = 0x1p-53;
  // The test below on the screen's sums first: the same volumes (the same sums in the same order),
  // larger bounds (by a margin past their rounding): a shell flat by the test below is within
  // them. Where none is (nearly always), nothing is dropped, and the square roots are not taken.
  {
    const double delta = 0x1p-52 * big * scale;
    const std::vector<Sums> screened = shell_sums(true);
    if (std::none_of(screened.begin(), screened.end(), [&](const Sums& x) {
          const double bound = 4 * 3 * delta * x.area + 16 * eps * x.size + 4 * eps * x.magnitude;
          return x.moved && std::abs(x.vol) <= 1.0001 * bound;
        }))
      return 0;
  }
  const std::vector<Sums> all = shell_sums(false);
  std::vector<u32> flat;
  for (const Sums& x : all) {
    if (!x.moved) continue;  // exact and untouched: its volume has the sign classification gave it
    // Each vertex within delta of its exact place (sqrt(3) / 2 ulps). Moving vertex v by d
    // changes six times the volume by d . sum over v's triangles of (b - v) x (c - v): at most
    // 3 delta times the sum of |(b - a) x (c - a)| (first order; taken four times over). Each
    // term (a - o) . ((b - a) x (c - a)) is within about 10 eps |a - o| |b - a| |c - a| of the
    // computed one (its differences and products rounded), the Kahan sum within 2 eps of the sum
    // of their sizes.
    const double delta = 0x1p-52 * x.reach * scale;
    const double moves = 4 * 3 * delta * x.area;
    const double error = 16 * eps * x.size + 4 * eps * x.magnitude;
    if (std::abs(x.vol) <= moves + error) flat.push_back(x.root);
  }
  if (flat.empty()) return 0;
  parallel_for(0, nt, [&](std::size_t t) {
    auto& T = tris[t];
    if (std::binary_search(flat.begin(), flat.end(), root[T[0]])) T = {T[0], T[0], T[0]};  // compact() drops it
  });
  compact(r, &rd);
  return flat.size();
}

// Sources named again where a re-resolution left a triangle facing against its source (see
// boolean_impl.h). Returns the number renamed.
std::size_t rename_reversed(BooleanResult& r, const Soup& soup, BooleanOp op) {
  const auto& P = r.mesh.positions;
  const std::size_t nt = r.mesh.triangles.size();
  auto key = [](std::int32_t o, std::int32_t l) {
    return static_cast<std::uint64_t>(static_cast<std::uint32_t>(o)) << 32 | static_cast<std::uint32_t>(l);
  };
  std::unordered_map<std::uint64_t, u32> of;
  of.reserve(soup.tris.size());
  for (u32 u = 0; u < soup.tris.size(); ++u) of.emplace(key(soup.operand[u], soup.local[u]), u);
  // The way soup triangle u's pieces face in the result, in its axis's projection.
  auto facing = [&](u32 u) { return soup.axis_sign[u] * (op == BooleanOp::Difference && soup.operand[u] > 0 ? -1 : 1); };
  auto projected = [&](std::size_t t, u32 u) { return projected_orientation(r.mesh, t, soup.axis[u]); };
  std::vector<u32> wrong;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto it = of.find(key(r.operand[t], r.source[t]));
    if (it == of.end() || soup.axis[it->second] < 0) continue;
    const int o = projected(t, it->second);
    if (o != 0 && o != facing(it->second)) wrong.push_back(static_cast<u32>(t));
  }
  if (wrong.empty()) return 0;
  Box3 bounds = r.mesh.bounds();
  const double tol = 1e-9 * (bounds.max - bounds.min).norm();
  std::vector<u32> ids(soup.tris.size());
  std::iota(ids.begin(), ids.end(), 0u);
  const Bvh tree(soup, std::move(ids), 3);
  std::size_t renamed = 0;
  for (u32 t : wrong) {
    const auto& T = r.mesh.triangles[t];
    double lo[3], hi[3];
    mesh_triangle_box(r.mesh, t, lo, hi);
    for (int d = 0; d < 3; ++d) lo[d] -= tol, hi[d] += tol;
    const Vec3 c = (P[T[0]] + P[T[1]] + P[T[2]]) / 3;
    u32 best = kNone;
    double best_gap = tol;
    bool best_holds = false;
    tree.query(lo, hi, [&](u32 u) {
      if (soup.axis[u] < 0 || projected(t, u) != facing(u)) return;
      const auto& U = soup.tris[u];
      const Vec3 &a = soup.verts[U[0]], &b = soup.verts[U[1]], &e = soup.verts[U[2]];
      const Vec3 n = (b - a).cross(e - a).normalized();
      double gap = 0;
      for (u32 v : T) gap = std::max(gap, std::abs(n.dot(P[v] - a)));
      if (!(gap <= tol)) return;
      // Whether u holds the centroid (in its projection): such a source is preferred.
      const int k = soup.axis[u], i = (k + 1) % 3, j = (k + 2) % 3;
      auto side = [&](const Vec3& p, const Vec3& q) {
        return orient2d(Point2(p[i], p[j]), Point2(q[i], q[j]), Point2(c[i], c[j])) * soup.axis_sign[u];
      };
      const bool holds = side(a, b) >= 0 && side(b, e) >= 0 && side(e, a) >= 0;
      if ((holds && !best_holds) || (holds == best_holds && (gap < best_gap || (gap == best_gap && u < best)))) {
        best = u, best_gap = gap, best_holds = holds;
      }
    });
    if (best == kNone) continue;
    r.operand[t] = soup.operand[best];
    r.source[t] = soup.local[best];
    r.mesh.face_ids[t] = soup.face_id[best];
    ++renamed;
  }
  return renamed;
}

}  // namespace wedge::boolean_detail
