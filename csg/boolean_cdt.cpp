// The constrained Delaunay triangulation of one cut triangle (step 4 of the retriangulation).
//
// Everything happens inside the triangle T being cut: its three corners are the first
// triangle, and every other point lies inside T or on its boundary, so there is no convex hull
// to grow and no infinite vertex. Points go in one at a time (a walk from the last insertion
// finds the triangle, which splits in three, or two pairs split in two where the point is on an
// edge), followed by Lawson's flips; then each constraint is recovered by Sloan's flips of the
// edges it crosses (only orientation decides a flip there, so the mesh stays a triangulation
// whatever the in-circle test says), and the flipped edges are made Delaunay again.
//
// The only geometry is Points::orient2d (exact) and Points::incircle_certain, which says "flip"
// only where exact arithmetic would: every flip lowers the lifted surface, so the flips end.
// The walk picks its first edge from a generator seeded the same way every time, so the result
// does not depend on threads or timing.
//
// Compared with CGAL's constrained Delaunay triangulation on the same predicates (which this
// replaces), there are no handles, no hash map from ids to vertices, no infinite faces and no
// per-triangulation allocation beyond a few flat arrays, reused by each thread.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "csg/boolean_impl.h"
#include "kernel/error.h"

namespace wedge::boolean_detail {

namespace {

constexpr int kNo = -1;

struct Tri {
  int v[3];       // local vertices, counter-clockwise in the projection
  int n[3];       // n[j]: the triangle across the edge opposite v[j] (v[j+1] -> v[j+2]), or kNo
  std::uint8_t c; // bit j: the edge opposite v[j] is a constraint
};

inline int nx(int j) { return j == 2 ? 0 : j + 1; }
inline int pv(int j) { return j == 0 ? 2 : j - 1; }

class Triangulator {
 public:
  // corners: nc = 3 (a triangle) or 4 (a convex quadrilateral), counter-clockwise.
  void run(const Points& pts, int k, double well, const u32* corners, int nc, const std::vector<u32>& points,
           const std::vector<std::array<u32, 2>>& constraints, std::vector<std::array<u32, 3>>& out,
           std::vector<std::array<u32, 3>>* inner, const Points::Metric* metric) {
    pts_ = &pts;
    metric_ = metric;
    k_ = k;
    well_ = well;
    rng_ = 0x9e3779b9u;
    ids_.clear();
    lv_.clear();
    tris_.clear();
    vt_.clear();
    for (int i = 0; i < nc; ++i) add_vertex(corners[i]);
    if (nc == 3) {
      if (orient(0, 1, 2) <= 0) fail("the triangle's corners are not counter-clockwise");
      tris_.push_back({{0, 1, 2}, {kNo, kNo, kNo}, 0});
      vt_ = {0, 0, 0};
    } else {
      // Two triangles across the diagonal 0-2, which is no constraint.
      if (orient(0, 1, 2) <= 0 || orient(2, 3, 0) <= 0 || orient(1, 2, 3) <= 0 || orient(3, 0, 1) <= 0)
        fail("the quadrilateral's corners are not convex and counter-clockwise");
      tris_.push_back({{0, 1, 2}, {kNo, 1, kNo}, 0});
      tris_.push_back({{2, 3, 0}, {kNo, 0, kNo}, 0});
      vt_ = {0, 0, 0, 1};
    }
    // Local numbers by id, for the constraints: (id, local), sorted.
    std::vector<std::pair<u32, int>>& local = local_;
    local.clear();
    for (int i = 0; i < nc; ++i) local.push_back({corners[i], i});
    int hint = 0;
    std::size_t polled = 0;
    for (u32 p : points) {
      if (std::find(corners, corners + nc, p) != corners + nc) continue;
      if ((++polled & 0xff) == 0) pts_->soup().poll();
      const int v = add_vertex(p);
      const int at = insert(v, hint);
      local.push_back({p, at});  // at: v, or an earlier vertex at the same point
      hint = vt_[at];
    }
    std::sort(local.begin(), local.end());
    auto find_local = [&](u32 id) {
      auto it = std::lower_bound(local.begin(), local.end(), std::make_pair(id, -1));
      if (it == local.end() || it->first != id) fail("a constraint's end point is not among the points");
      return it->second;
    };
    for (const auto& c : constraints) {
      if ((++polled & 0xff) == 0) pts_->soup().poll();
      const int a = find_local(c[0]), b = find_local(c[1]);
      if (a != b) constrain(a, b, 0);
    }
    out.reserve(out.size() + tris_.size());
    for (const Tri& t : tris_) out.push_back({ids_[t.v[0]], ids_[t.v[1]], ids_[t.v[2]]});
    if (inner) {
      // Edge e (v[e] -> v[e+1]) is the one opposite v[e+2].
      inner->reserve(inner->size() + tris_.size());
      for (const Tri& t : tris_) {
        std::array<u32, 3> nb;
        for (int e = 0; e < 3; ++e) {
          const int j = pv(e);
          nb[e] = t.n[j] == kNo || cons(t, j) ? kNone : static_cast<u32>(t.n[j]);
        }
        inner->push_back(nb);
      }
    }
  }

 private:
  const Points* pts_ = nullptr;
  const Points::Metric* metric_ = nullptr;
  int k_ = 2;
  double well_ = 0.01;
  std::uint32_t rng_ = 0x9e3779b9u;
  std::vector<u32> ids_;               // local vertex -> point id
  std::vector<Approx2> lv_;            // local vertex -> its point projected (Points::projected)
  std::vector<Tri> tris_;
  std::vector<int> vt_;                // local vertex -> a triangle that has it
  std::vector<std::pair<u32, int>> local_;
  std::vector<std::pair<int, int>> stack_;
  std::vector<std::array<int, 2>> crossed_, made_;

  [[noreturn]] static void fail(const char* what) { wedge::fail("boolean: internal error: ", what); }

  int add_vertex(u32 id) {
    ids_.push_back(id);
    vt_.push_back(kNo);
    lv_.push_back(pts_->projected(id, k_));
    return static_cast<int>(ids_.size()) - 1;
  }
  // The predicates' first stages (orient2d_first, incircle_first) on the local copies, as
  // Points::orient2d and Points::incircle_certain run them (so they decide exactly where those
  // would); the rest there.
  int orient(int a, int b, int c) const {
    if (const int s = orient2d_first(lv_[a], lv_[b], lv_[c]); s != 2) return s;
    return pts_->orient2d(ids_[a], ids_[b], ids_[c], k_);
  }
  // +1 where d is certainly inside the circle through a, b, c (counter-clockwise).
  bool in_circle(int a, int b, int c, int d) const {
    if (metric_) {
      const Approx2* p[4] = {&lv_[a], &lv_[b], &lv_[c], &lv_[d]};
      if (const int s = incircle_first(p, metric_->q11, metric_->q12, metric_->q22); s != 2) return s > 0;
      return pts_->incircle_certain(ids_[a], ids_[b], ids_[c], ids_[d], k_, well_, *metric_) > 0;
    }
    if (const int s = incircle_first(lv_[a], lv_[b], lv_[c], lv_[d]); s != 2) return s > 0;
    return pts_->incircle_certain(ids_[a], ids_[b], ids_[c], ids_[d], k_, well_) > 0;
  }
  std::uint32_t next_random() {
    rng_ ^= rng_ << 13;
    rng_ ^= rng_ >> 17;
    rng_ ^= rng_ << 5;
    return rng_;
  }
  static int index_of(const Tri& t, int v) { return t.v[0] == v ? 0 : (t.v[1] == v ? 1 : (t.v[2] == v ? 2 : kNo)); }
  // Triangle t's link to old_nb now goes to new_nb.
  void relink(int t, int old_nb, int new_nb) {
    if (t == kNo) return;
    Tri& x = tris_[t];
    for (int j = 0; j < 3; ++j)
      if (x.n[j] == old_nb) {
        x.n[j] = new_nb;
        return;
      }
  }
  static bool cons(const Tri& t, int j) { return (t.c >> j) & 1; }
  static void set_cons(Tri& t, int j, bool on) {
    t.c = static_cast<std::uint8_t>(on ? (t.c | (1u << j)) : (t.c & ~(1u << j)));
  }

  // Inserts vertex p; returns p, or the earlier vertex at the same point.
  int insert(int p, int hint) {
    int t = hint;
    const std::size_t limit = 4 * tris_.size() + 64;
    int o[3] = {0, 0, 0};
    for (std::size_t step = 0;; ++step) {
      if (step > limit) fail("the walk to a point did not end");
      const Tri& x = tris_[t];
      const int r = static_cast<int>(next_random() % 3);
      int move = kNo;
      for (int q = 0; q < 3 && move == kNo; ++q) {
        const int j = (r + q) % 3;
        o[j] = orient(x.v[nx(j)], x.v[pv(j)], p);
        if (o[j] < 0) move = j;
      }
      if (move == kNo) break;
      t = x.n[move];
      if (t == kNo) fail("a point lies outside its triangle");
    }
    const Tri& x = tris_[t];
    int zeros = 0, zj = kNo;
    for (int j = 0; j < 3; ++j)
      if (o[j] == 0) ++zeros, zj = j;
    if (zeros >= 2) {
      // On two edges: at their shared vertex.
      for (int j = 0; j < 3; ++j)
        if (o[j] != 0) return x.v[j];
      fail("a triangle of zero area");
    }
    if (zeros == 1) split_edge(t, zj, p);
    else split_triangle(t, p);
    legalize();
    return p;
  }

  void split_triangle(int t, int p) {
    const Tri x = tris_[t];
    const int a = x.v[0], b = x.v[1], c = x.v[2];
    const int t1 = static_cast<int>(tris_.size()), t2 = t1 + 1;
    tris_[t] = {{p, b, c}, {x.n[0], t1, t2}, static_cast<std::uint8_t>(cons(x, 0) ? 1 : 0)};
    tris_.push_back({{p, c, a}, {x.n[1], t2, t}, static_cast<std::uint8_t>(cons(x, 1) ? 1 : 0)});
    tris_.push_back({{p, a, b}, {x.n[2], t, t1}, static_cast<std::uint8_t>(cons(x, 2) ? 1 : 0)});
    relink(x.n[1], t, t1);
    relink(x.n[2], t, t2);
    vt_[p] = t;
    vt_[b] = t;
    vt_[c] = t;
    vt_[a] = t1;
    stack_.push_back({t, 0});
    stack_.push_back({t1, 0});
    stack_.push_back({t2, 0});
  }

  // p on the edge of t opposite its vertex j.
  void split_edge(int t, int j, int p) {
    const Tri x = tris_[t];
    const int c = x.v[j], a = x.v[nx(j)], b = x.v[pv(j)];
    const int u = x.n[j];
    const bool ab = cons(x, j);
    const int ta = x.n[nx(j)], tb = x.n[pv(j)];  // across b -> c and c -> a
    const int tn = static_cast<int>(tris_.size());
    int un = kNo;
    if (u != kNo) un = tn + 1;
    // t: (c, a, p), tn: (c, p, b).
    tris_[t] = {{c, a, p}, {un, tn, tb}, static_cast<std::uint8_t>((ab ? 1 : 0) | (cons(x, pv(j)) ? 4 : 0))};
    tris_.push_back({{c, p, b}, {u, ta, t}, static_cast<std::uint8_t>((ab ? 1 : 0) | (cons(x, nx(j)) ? 2 : 0))});
    relink(ta, t, tn);
    vt_[c] = t;
    vt_[a] = t;
    vt_[p] = t;
    vt_[b] = tn;
    stack_.push_back({t, 2});
    stack_.push_back({tn, 1});
    if (u != kNo) {
      const Tri y = tris_[u];
      int m = 0;
      while (m < 3 && y.n[m] != t) ++m;
      if (m == 3) fail("a neighbour does not point back");
      const int d = y.v[m];  // y = (d, b, a)
      const int ua = y.n[pv(m)], ub = y.n[nx(m)];  // across d -> b and a -> d
      // u: (d, b, p), un: (d, p, a).
      tris_[u] = {{d, b, p}, {tn, un, ua}, static_cast<std::uint8_t>((ab ? 1 : 0) | (cons(y, pv(m)) ? 4 : 0))};
      tris_.push_back({{d, p, a}, {t, ub, u}, static_cast<std::uint8_t>((ab ? 1 : 0) | (cons(y, nx(m)) ? 2 : 0))});
      relink(ub, u, un);
      vt_[d] = u;
      stack_.push_back({u, 2});
      stack_.push_back({un, 1});
    }
  }

  // Flips the edge of t opposite its vertex j (shared with u = t.n[j]). Afterwards t is
  // (q1, x, q2) and u is (q2, y, q1), where t was (q1, x, y) and u (q2, y, x).
  void flip(int t, int j) {
    const Tri x = tris_[t];
    const int u = x.n[j];
    const Tri y = tris_[u];
    int m = 0;
    while (y.n[m] != t) ++m;
    const int q1 = x.v[j], a = x.v[nx(j)], b = x.v[pv(j)], q2 = y.v[m];
    const int A = x.n[nx(j)], B = x.n[pv(j)];  // across b -> q1 and q1 -> a
    const int C = y.n[nx(m)], D = y.n[pv(m)];  // across a -> q2 (y is (q2, b, a)) and q2 -> b
    const bool cA = cons(x, nx(j)), cB = cons(x, pv(j)), cC = cons(y, nx(m)), cD = cons(y, pv(m));
    tris_[t] = {{q1, a, q2}, {C, u, B}, static_cast<std::uint8_t>((cC ? 1 : 0) | (cB ? 4 : 0))};
    tris_[u] = {{q2, b, q1}, {A, t, D}, static_cast<std::uint8_t>((cA ? 1 : 0) | (cD ? 4 : 0))};
    relink(A, t, u);
    relink(C, u, t);
    vt_[q1] = t;
    vt_[a] = t;
    vt_[q2] = t;
    vt_[b] = u;
  }

  // Lawson's flips of the edges on the stack (each given as a triangle and the vertex opposite).
  void legalize() {
    while (!stack_.empty()) {
      auto [t, j] = stack_.back();
      stack_.pop_back();
      const Tri& x = tris_[t];
      const int u = x.n[j];
      if (u == kNo || cons(x, j)) continue;
      const Tri& y = tris_[u];
      int m = 0;
      while (y.n[m] != t) ++m;
      if (!in_circle(x.v[j], x.v[nx(j)], x.v[pv(j)], y.v[m])) continue;
      flip(t, j);
      // t is (p, a, q2), u is (q2, b, p): their edges away from p.
      stack_.push_back({t, 0});
      stack_.push_back({u, 2});
    }
  }

  // One step at a time around vertex v: counter-clockwise from the triangle vt_ names until the
  // fan closes or ends, then (an open fan) clockwise from it. next() gives the next triangle (and
  // v's index in it), or false when all were given.
  struct Cursor {
    const std::vector<Tri>* tris;
    int v, t0, t, phase;  // phase 0: counter-clockwise from t0; 1: clockwise; 2: done
    Cursor(const std::vector<Tri>& tr, int vertex, int start) : tris(&tr), v(vertex), t0(start), t(start), phase(0) {}
    bool next(int& x, int& i) {
      const std::vector<Tri>& tr = *tris;
      if (phase == 0) {
        x = t;
        i = index_of(tr[x], v);
        const int n = tr[x].n[nx(i)];
        if (n == t0) phase = 2;
        else if (n != kNo) t = n;
        else {
          t = tr[t0].n[pv(index_of(tr[t0], v))];
          phase = t == kNo ? 2 : 1;
        }
        return true;
      }
      if (phase == 1) {
        x = t;
        i = index_of(tr[x], v);
        t = tr[x].n[pv(i)];
        if (t == kNo) phase = 2;
        return true;
      }
      return false;
    }
  };

  // Calls f(t, i) for each triangle t around vertex v (v = t.v[i]) until f returns true; true if
  // one did.
  template <class F>
  bool around(int v, F&& f) {
    Cursor c(tris_, v, vt_[v]);
    int t, i;
    while (c.next(t, i))
      if (f(t, i)) return true;
    return false;
  }

  // The triangle with the directed edge a -> b, and the index of the vertex opposite it. Looked
  // for around a and around b in turns, so the cost is that of the end with fewer triangles (a
  // cut triangle crossed by a fan's 1,250 edges through one point: walking its hub for each of
  // the Delaunay restoration's 3.7 million edge lookups took a billion steps).
  bool find_edge(int a, int b, int& t, int& j) {
    Cursor ca(tris_, a, vt_[a]), cb(tris_, b, vt_[b]);
    bool more_a = true, more_b = true;
    int x, i;
    while (more_a || more_b) {
      if (more_a && (more_a = ca.next(x, i)) && tris_[x].v[nx(i)] == b) {
        t = x;
        j = pv(i);  // (a, b, c): c
        return true;
      }
      if (more_b && (more_b = cb.next(x, i)) && tris_[x].v[pv(i)] == a) {
        t = x;
        j = nx(i);  // (b, c, a): c
        return true;
      }
    }
    return false;
  }

  // Whether c lies strictly between a and b on their line (a, b, c collinear).
  bool between(int a, int b, int c) const {
    for (int axis = 0; axis < 3; ++axis) {
      const int ab = pts_->compare(ids_[a], ids_[b], axis);
      if (ab != 0) return pts_->compare(ids_[a], ids_[c], axis) == ab && pts_->compare(ids_[c], ids_[b], axis) == ab;
    }
    return false;
  }

  void mark(int t, int j) {
    Tri& x = tris_[t];
    set_cons(x, j, true);
    const int u = x.n[j];
    if (u == kNo) return;
    Tri& y = tris_[u];
    for (int m = 0; m < 3; ++m)
      if (y.n[m] == t) set_cons(y, m, true);
  }

  // Makes a -> b an edge of the triangulation, marked as a constraint.
  void constrain(int a, int b, int depth) {
    if (depth > 64) fail("a constraint passes through too many points");
    int t = kNo, j = kNo;
    if (find_edge(a, b, t, j) || find_edge(b, a, t, j)) {
      mark(t, j);
      return;
    }
    // The triangle at a whose corner holds the direction to b: (a, x, y) with x right of a -> b
    // and y left of it. A vertex on the open segment splits the constraint there.
    int split = kNo, x = kNo, y = kNo, start = kNo;
    around(a, [&](int s, int i) {
      const Tri& T = tris_[s];
      const int p = T.v[nx(i)], q = T.v[pv(i)];
      const int op = orient(a, b, p), oq = orient(a, b, q);
      if (op == 0 && between(a, b, p)) return split = p, true;
      if (oq == 0 && between(a, b, q)) return split = q, true;
      if (op < 0 && oq > 0) {
        x = p, y = q, start = s;
        return true;
      }
      return false;
    });
    if (split != kNo) {
      constrain(a, split, depth + 1);
      constrain(split, b, depth + 1);
      return;
    }
    if (start == kNo) fail("no triangle at a constraint's end point faces the other end");
    // The edges crossed, from a to b.
    crossed_.clear();
    int cur = start, end = b;
    for (std::size_t steps = 0;; ++steps) {
      if (steps > tris_.size()) fail("the walk along a constraint did not end");
      crossed_.push_back({x, y});
      const Tri& T = tris_[cur];
      const int i = index_of(T, x);
      const int nb = T.n[pv(i)];  // across x -> y (T is (x, y, ...))
      if (nb == kNo) fail("a constraint leaves its triangle");
      if (cons(T, pv(i))) fail("two constraints cross");
      const Tri& N = tris_[nb];
      const int z = N.v[nx(index_of(N, x))];  // N is (y, x, z)
      if (z == b) break;
      const int oz = orient(a, b, z);
      if (oz == 0) {
        end = z;  // a vertex on the segment: recover a -> z here, z -> b after
        break;
      }
      if (oz > 0) y = z;
      else x = z;
      cur = nb;
    }
    recover(a, end);
    if (end != b) constrain(end, b, depth + 1);
  }

  // Sloan's recovery of a -> b from the crossed edges, then Delaunay flips of the new edges.
  void recover(int a, int b) {
    made_.clear();
    std::size_t head = 0, guard = 0;
    const std::size_t limit = 64 * (crossed_.size() + 4) * (crossed_.size() + 4);
    while (head < crossed_.size()) {
      if (++guard > limit) fail("recovering a constraint did not end");
      const auto e = crossed_[head++];
      int t, j;
      if (!find_edge(e[0], e[1], t, j)) fail("a crossed edge is missing");
      const Tri& T = tris_[t];
      const int u = T.n[j];
      const Tri& U = tris_[u];
      int m = 0;
      while (U.n[m] != t) ++m;
      const int q1 = T.v[j], q2 = U.v[m], p = T.v[nx(j)], q = T.v[pv(j)];
      // Convex quadrilateral: the new diagonal q1 q2 has p and q strictly on either side.
      if (orient(q1, p, q2) <= 0 || orient(q2, q, q1) <= 0) {
        crossed_.push_back(e);
        continue;
      }
      flip(t, j);
      const bool ends = (q1 == a && q2 == b) || (q1 == b && q2 == a);
      const int s1 = orient(a, b, q1), s2 = orient(a, b, q2);
      if (!ends && s1 * s2 < 0) crossed_.push_back({q1, q2});
      else made_.push_back({q1, q2});
    }
    int t, j;
    if (!find_edge(a, b, t, j) && !find_edge(b, a, t, j)) fail("a constraint was not recovered");
    mark(t, j);
    // Restore the Delaunay property on the new edges (the constraint stays).
    for (bool changed = true; changed;) {
      changed = false;
      for (auto& e : made_) {
        if ((e[0] == a && e[1] == b) || (e[0] == b && e[1] == a)) continue;
        if (!find_edge(e[0], e[1], t, j)) continue;
        const Tri& T = tris_[t];
        const int u = T.n[j];
        if (u == kNo || cons(T, j)) continue;
        const Tri& U = tris_[u];
        int m = 0;
        while (U.n[m] != t) ++m;
        const int q1 = T.v[j], q2 = U.v[m];
        if (!in_circle(q1, T.v[nx(j)], T.v[pv(j)], q2)) continue;
        if (orient(q1, T.v[nx(j)], q2) <= 0 || orient(q2, T.v[pv(j)], q1) <= 0) continue;
        flip(t, j);
        e = {q1, q2};
        changed = true;
        if (++guard > limit) fail("restoring a constraint's neighbourhood did not end");
      }
    }
  }
};

// One per thread, for triangles and quadrilaterals alike: its arrays are kept for the thread's
// next one.
Triangulator& local_triangulator() {
  thread_local Triangulator tr;
  return tr;
}

}  // namespace

void constrained_delaunay(const Points& pts, int k, double well, const std::array<u32, 3>& corners,
                          const std::vector<u32>& points, const std::vector<std::array<u32, 2>>& constraints,
                          std::vector<std::array<u32, 3>>& out, std::vector<std::array<u32, 3>>* inner,
                          const Points::Metric* metric) {
  local_triangulator().run(pts, k, well, corners.data(), 3, points, constraints, out, inner, metric);
}

void constrained_delaunay_quad(const Points& pts, int k, double well, const std::array<u32, 4>& corners,
                          const std::vector<u32>& points, const std::vector<std::array<u32, 2>>& constraints,
                          std::vector<std::array<u32, 3>>& out, std::vector<std::array<u32, 3>>* inner) {
  local_triangulator().run(pts, k, well, corners.data(), 4, points, constraints, out, inner, nullptr);
}

}  // namespace wedge::boolean_detail
