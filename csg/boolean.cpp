// The boolean engine's driver: operand checks, the input soup, and the stages in order
// (broad phase, exact intersection and retriangulation, classification, output).
#include "csg/boolean.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include <tbb/task_arena.h>

#include "csg/boolean_impl.h"
#include "kernel/error.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"

namespace wedge {

using namespace boolean_detail;

std::string boolean_detail::point_text(const Vec3& p) {
  std::ostringstream o;
  o.precision(17);
  o << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return o.str();
}

namespace {

// Meshes this engine has returned: closed, 2-manifold, outward and free of self-intersections
// after rounding, all checked exactly before they were returned. An operand equal to one of them
// bit for bit (a result fed to the next boolean, as a CSG tree or a chain of booleans does) is
// not checked again. A mesh is known by a 128-bit hash of its positions and triangles; the last
// 256 results are remembered.
struct Fingerprint {
  std::uint64_t a = 0, b = 0;
  std::uint64_t positions = 0, triangles = 0;  // the mesh's sizes
  bool operator==(const Fingerprint& o) const {
    return a == o.a && b == o.b && positions == o.positions && triangles == o.triangles;
  }
};

// Per block of 4096 positions and triangles, independent hash lanes (a hash is a chain of
// dependent multiplies: several chains keep the multiplier busy; the triangles' words go to four,
// which were one chain of two multiplies a triangle, 4.5 of the 5.9 ms a 1M union's result took),
// blocks in parallel, their hashes combined in block order: the same value at any thread count.
Fingerprint fingerprint(const Mesh& m) {
  const std::size_t np = m.positions.size(), nt = m.triangles.size();
  const std::size_t blocks = std::max((np + 4095) / 4096, (nt + 4095) / 4096);
  std::vector<std::array<std::uint64_t, 2>> part(blocks);
  parallel_for(0, blocks, [&](std::size_t k) {
    std::uint64_t lane[7] = {0x243f6a8885a308d3ull ^ k, 0x13198a2e03707344ull, 0xa4093822299f31d0ull, 0x082efa98ec4e6c89ull,
                             0x452821e638d01377ull, 0xbe5466cf34e90c6cull, 0xc0ac29b7c97c50ddull};
    auto mix = [](std::uint64_t& h, std::uint64_t x) {
      h = (h ^ x) * 0x9e3779b97f4a7c15ull;
      h ^= h >> 29;
    };
    for (std::size_t v = k * 4096; v < std::min(np, (k + 1) * 4096); ++v) {
      std::uint64_t x[3];
      std::memcpy(x, m.positions[v].data(), sizeof x);
      mix(lane[0], x[0]);
      mix(lane[1], x[1]);
      mix(lane[2], x[2]);
    }
    for (std::size_t t = k * 4096; t < std::min(nt, (k + 1) * 4096); ++t) {
      const auto& T = m.triangles[t];
      const std::size_t odd = 2 * (t & 1);
      mix(lane[3 + odd], static_cast<std::uint64_t>(T[0]) << 32 | T[1]);
      mix(lane[4 + odd], T[2]);
    }
    std::uint64_t a = lane[0], b = lane[3];
    for (std::uint64_t l : {lane[1], lane[2], lane[3], lane[4], lane[5], lane[6]}) mix(a, l);
    for (std::uint64_t l : {lane[0], lane[1], lane[2], lane[4], lane[5], lane[6]}) b = (b + l) * 0xff51afd7ed558ccdull, b ^= b >> 31;
    part[k] = {a, b};
  });
  Fingerprint f{0x243f6a8885a308d3ull, 0x13198a2e03707344ull, np, nt};
  for (const auto& p : part) {
    f.a = (f.a ^ p[0]) * 0x9e3779b97f4a7c15ull;
    f.a ^= f.a >> 29;
    f.b = (f.b + p[1]) * 0xff51afd7ed558ccdull;
    f.b ^= f.b >> 31;
  }
  return f;
}

class VerifiedResults {
 public:
  // Whether m is one of the results (the hash is made only where a result has m's sizes).
  bool contains(const Mesh& m) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (std::none_of(ring_.begin(), ring_.end(), [&](const Fingerprint& f) {
            return f.positions == m.positions.size() && f.triangles == m.triangles.size();
          }))
        return false;
    }
    const Fingerprint f = fingerprint(m);
    std::lock_guard<std::mutex> lock(mutex_);
    return std::find(ring_.begin(), ring_.end(), f) != ring_.end();
  }
  void add(const Fingerprint& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    ring_[next_++ % ring_.size()] = f;
  }

 private:
  std::mutex mutex_;
  std::array<Fingerprint, 256> ring_{};
  std::size_t next_ = 0;
};
VerifiedResults& verified_results() {
  static VerifiedResults v;
  return v;
}

std::string at(const Vec3& p) { return point_text(p); }

// For triangles t and u sharing no vertex, one of them in a plane x_k = c and the other not:
// 1 where they meet, 0 where they do not, 2 where it is not decided here (neither lies in such a
// plane, both do, or the other touches the plane along an edge or crosses it).
int on_axis_plane(const Soup& s, u32 t, u32 u) {
  for (int swap = 0; swap < 2; ++swap) {
    const auto& P = s.tris[swap ? u : t];  // the one in the plane
    const auto& Q = s.tris[swap ? t : u];
    const Vec3 &a = s.verts[P[0]], &b = s.verts[P[1]], &c = s.verts[P[2]];
    for (int k = 0; k < 3; ++k) {
      const double h = a[k];
      if (b[k] != h || c[k] != h) continue;
      int above = 0, below = 0, on = -1, ons = 0;
      for (int m = 0; m < 3; ++m) {
        const double z = s.verts[Q[m]][k];
        if (z > h) ++above;
        else if (z < h) ++below;
        else on = m, ++ons;
      }
      if (ons == 0) return above == 3 || below == 3 ? 0 : 2;
      if (ons != 1 || (above != 2 && below != 2)) return 2;
      // Q meets the plane in its corner q alone: they meet where q is in P (closed).
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const Vec3& q = s.verts[Q[on]];
      const int o = orient2d_fast(a[i], a[j], b[i], b[j], c[i], c[j]);
      if (o == 0) return 2;
      const int s0 = orient2d_fast(a[i], a[j], b[i], b[j], q[i], q[j]);
      const int s1 = orient2d_fast(b[i], b[j], c[i], c[j], q[i], q[j]);
      const int s2 = orient2d_fast(c[i], c[j], a[i], a[j], q[i], q[j]);
      return s0 != -o && s1 != -o && s2 != -o ? 1 : 0;
    }
  }
  return 2;
}

}  // namespace

// Whether triangles t = (a, b, c) and u = (d, e, f), whose planes cross, meet (closed): st[k] is
// the side of t's corner k of u's plane, su[k] of u's corner k of t's plane (orient3d), none 0
// and neither all alike. Each triangle has one corner alone on its side: turned (cyclically, the
// orientation kept) to be its first, a and d. Where a is on the negative side of u's plane, u is
// taken the other way round (e and f swapped: the plane's sides swap), and likewise t for d. Then
// t meets the planes' line L in a segment from its edge ab to its edge ac and u in one from de to
// df; along L (its direction n_t x n_u) the first runs from ac's point to ab's, the second from
// de's to df's, and they overlap where de's point is not past ab's and ac's not past df's. Each
// comparison is the orientation of the two edges' lines (zero where they meet, which is where the
// points coincide): orient3d(a, b, d, e) <= 0 and orient3d(a, c, f, d) <= 0 (Guigue and
// Devillers' test; the signs checked on a worked example and against CGAL's do_intersect in
// tests/csg/test_boolean_clash.cpp).
bool boolean_detail::crossing_triangles_meet(const Vec3* const t[3], const int st[3], const Vec3* const u[3], const int su[3]) {
  auto alone = [](const int s[3]) { return s[0] == s[1] ? 2 : s[0] == s[2] ? 1 : 0; };
  const int i = alone(st), j = alone(su);
  const Vec3 *a = t[i], *b = t[(i + 1) % 3], *c = t[(i + 2) % 3];
  const Vec3 *d = u[j], *e = u[(j + 1) % 3], *f = u[(j + 2) % 3];
  if (st[i] < 0) std::swap(e, f);
  if (su[j] < 0) std::swap(b, c);
  return orient3d_fast(*a, *b, *d, *e) <= 0 && orient3d_fast(*a, *c, *f, *d) <= 0;
}

// Whether triangles t and u of a soup meet anywhere but in the vertices (or edge) they share,
// decided exactly.
bool boolean_detail::triangles_clash(const Soup& s, u32 t, u32 u) {
  const auto& T = s.tris[t];
  const auto& U = s.tris[u];
  int shared = 0, ti = -1, ui = -1;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      if (T[a] == U[b]) {
        ++shared;
        ti = a;
        ui = b;
      }
  const Vec3 *A = &s.verts[T[0]], *B = &s.verts[T[1]], *C = &s.verts[T[2]];
  const Vec3 *D = &s.verts[U[0]], *E = &s.verts[U[1]], *F = &s.verts[U[2]];
  if (shared == 0) {
    // One triangle in a plane x_k = c (a box's face, a cut face's fan) and the other not: decided
    // by comparisons, and by one point-in-triangle test where the other touches the plane at one
    // corner (a sphere's facet ending on the face), without the general test's predicates.
    const int flat = on_axis_plane(s, t, u);
    if (flat != 2) return flat != 0;
  }
  bool hit = false;
  // Both on one plane x_k = c (faces of boxes, plates, cylinder caps): certainly coplanar, and the
  // side tests below would each take the exact predicate's slowest path to say so.
  bool flat = false;
  for (int k = 0; k < 3 && !flat; ++k) {
    const double c = (*A)[k];
    flat = (*B)[k] == c && (*C)[k] == c && (*D)[k] == c && (*E)[k] == c && (*F)[k] == c;
  }
  // Quick exact rejection: one triangle strictly on one side of the other's plane (shared
  // vertices aside). sides(P, Q) puts the side of P's plane of each corner of Q it does not share
  // in `side`: 1 where all are on one side, 0 where one is on the plane or (without `all`) they
  // are on both sides (the rest not looked at), 2 where they are on both sides and none on it.
  auto sides = [&](const std::array<u32, 3>& P, const std::array<u32, 3>& Q, bool all, int side[3]) {
    int seen = 0;  // bit 0: a corner in front, bit 1: one behind
    for (int k = 0; k < 3; ++k) {
      const u32 q = Q[k];
      if (q == P[0] || q == P[1] || q == P[2]) continue;
      const int o = orient3d_fast(s.verts[P[0]], s.verts[P[1]], s.verts[P[2]], s.verts[q]);
      if (o == 0) return 0;
      side[k] = o;
      seen |= o > 0 ? 1 : 2;
      if (seen == 3 && !all) return 0;
    }
    return seen == 3 ? 2 : 1;
  };
  if (shared < 3 && !flat) {
    // Sharing no vertex, where no corner is on the other's plane and neither is apart, the planes
    // cross: each triangle meets their line in a segment, and two more orientations compare the
    // segments (crossing_triangles_meet). The pairs along a concave crease of a result (the
    // lattice's, 236,544 of them, none meeting) took CGAL's general test after the tests below.
    int su[3], st[3];
    const int a = sides(T, U, shared == 0, su);
    if (a == 1) return false;
    const int b = sides(U, T, shared == 0, st);
    if (b == 1) return false;
    if (a == 2 && b == 2) {
      const Vec3* TV[3] = {A, B, C};
      const Vec3* UV[3] = {D, E, F};
      return crossing_triangles_meet(TV, st, UV, su);
    }
  }
  // Quick exact rejection in a projection (along t's axis): an edge line of one triangle with the
  // other triangle strictly on its far side, shared vertices aside (on the line they span only
  // what the two triangles share). Decides most coplanar pairs, where the test above cannot.
  if (shared < 3 && s.axis[t] >= 0) {
    const int k = s.axis[t], i = (k + 1) % 3, j = (k + 2) % 3;
    auto separated = [&](const std::array<u32, 3>& P, const std::array<u32, 3>& Q) {
      for (int e = 0; e < 3; ++e) {
        const Vec3 &a = s.verts[P[e]], &b = s.verts[P[(e + 1) % 3]], &c = s.verts[P[(e + 2) % 3]];
        const int o = orient2d_fast(a[i], a[j], b[i], b[j], c[i], c[j]);
        if (o == 0) return false;
        bool all = true;
        for (u32 q : Q) {
          if (q == P[e] || q == P[(e + 1) % 3]) continue;
          const Vec3& w = s.verts[q];
          if (orient2d_fast(a[i], a[j], b[i], b[j], w[i], w[j]) != -o) {
            all = false;
            break;
          }
        }
        if (all) return true;
      }
      return false;
    };
    if (separated(T, U) || separated(U, T)) return false;
  }
  if (shared == 0) {
    hit = triangles_intersect(*A, *B, *C, *D, *E, *F);
  } else if (shared == 1) {
    // Beyond the shared vertex: the opposite edge of one meets the other, or (coplanar) an
    // edge from the shared vertex runs inside the other.
    const Vec3& ta = s.verts[T[(ti + 1) % 3]];
    const Vec3& tb = s.verts[T[(ti + 2) % 3]];
    const Vec3& ua = s.verts[U[(ui + 1) % 3]];
    const Vec3& ub = s.verts[U[(ui + 2) % 3]];
    hit = segment_triangle_intersect(ta, tb, *D, *E, *F) || segment_triangle_intersect(ua, ub, *A, *B, *C);
    if (!hit && orient3d_fast(*A, *B, *C, ua) == 0 && orient3d_fast(*A, *B, *C, ub) == 0) {
      // Coplanar fans around one vertex: they overlap if an edge of one runs into the other.
      const Vec3& v = s.verts[T[ti]];
      auto inside_open = [&](const Vec3& q, const Vec3& r, const Vec3& x) {
        // x strictly inside the angle at v spanned by q and r (projection along T's axis).
        int k = s.axis[t], i = (k + 1) % 3, j = (k + 2) % 3;
        Point2 Q(q[i], q[j]), R(r[i], r[j]), X(x[i], x[j]), V(v[i], v[j]);
        int o = orient2d(V, Q, R);
        return orient2d(V, Q, X) * o > 0 && orient2d(V, X, R) * o > 0;
      };
      hit = inside_open(ta, tb, ua) || inside_open(ta, tb, ub) || inside_open(ua, ub, ta) ||
            inside_open(ua, ub, tb);
    }
  } else if (shared == 2) {
    // Sharing an edge: they overlap only if folded flat onto each other.
    u32 t3 = 0, u3 = 0;
    for (int a = 0; a < 3; ++a) {
      if (T[a] != U[0] && T[a] != U[1] && T[a] != U[2]) t3 = T[a];
      if (U[a] != T[0] && U[a] != T[1] && U[a] != T[2]) u3 = U[a];
    }
    if (orient3d_fast(*A, *B, *C, s.verts[u3]) == 0) {
      // Coplanar: overlap if u3 is on the same side of the shared edge as t3.
      u32 e0 = kNone, e1 = kNone;
      for (int a = 0; a < 3; ++a)
        if (T[a] != t3) (e0 == kNone ? e0 : e1) = T[a];
      int k = s.axis[t], i = (k + 1) % 3, j = (k + 2) % 3;
      auto p2 = [&](u32 v) { return Point2(s.verts[v][i], s.verts[v][j]); };
      hit = orient2d(p2(e0), p2(e1), p2(t3)) * orient2d(p2(e0), p2(e1), p2(u3)) > 0;
    }
  } else {
    hit = true;  // the same three vertices twice
  }
  return hit;
}

namespace {

// The defect of an operand (named `name`) with a negative volume.
std::string inside_out(const std::string& name) {
  return name + " is inside out (negative volume): triangles must be counter-clockwise seen from outside";
}
// "" where closed mesh m has a positive volume (or no triangles), else that defect (exact).
std::string volume_defect(const Mesh& m, const std::string& name) {
  return m.triangles.empty() || volume_sign(m.positions, m.triangles) > 0 ? "" : inside_out(name);
}

// The first defect of each operand of a soup that `check` marks (its Mesh `meshes[o]`, named
// names[o]), or "" (exact): a zero-area triangle, an edge that is not closed or not consistently
// oriented, a negative volume (not looked at without `volumes`). The operands' indices must be
// valid (Mesh::check) before the soup is made. One pass over the soup's vertices for all
// operands at once (a vertex that two operands share has both their edges, told apart by
// operand).
//
// With `adj` (sized to the soup's triangles, kNone), each triangle edge a -> b at a vertex a whose
// star is one disk of one operand (each edge out of a once, each edge in once) gets the triangle
// across it: the one with the edge b -> a.
std::vector<std::string> soup_defects(const Soup& s, CornerLists& corners, const std::vector<const Mesh*>& meshes,
                                      const std::vector<std::string>& names, const std::vector<char>& check,
                                      std::vector<std::array<u32, 3>>* adj = nullptr, bool volumes = true) {
  const std::size_t nops = meshes.size();
  std::vector<std::string> out(nops);
  // Each operand's first zero-area triangle.
  const std::vector<u32> first = operand_starts(s);
  parallel_for(0, nops, [&](std::size_t o) {
    if (!check[o]) return;
    for (std::size_t t = first[o]; t < first[o + 1]; ++t)
      if (s.axis[t] < 0) {
        const auto& T = s.tris[t];
        out[o] = names[o] + " has a zero-area triangle #" + std::to_string(s.local[t] + 1) + " at " + at(s.verts[T[0]]) +
                 ", " + at(s.verts[T[1]]) + ", " + at(s.verts[T[2]]);
        return;
      }
  });
  // Closed and 2-manifold: each directed edge once, and its reverse once, in each operand. Both
  // are seen from the edge's first vertex a: a -> b is a corner of a whose next vertex is b, and
  // b -> a one whose previous vertex is b. Per vertex, its corners' (next << 32 | triangle) and
  // (previous << 32 | triangle): the counts need no other vertex's list, and no order.
  const std::size_t nv = s.verts.size();
  const std::vector<u32>& off = corners.off;
  auto& outs = corners.next;
  auto& ins = corners.prev;
  auto op_of = [&](std::uint64_t x) { return s.operand[x & 0xffffffffu]; };
  // The first vertex (in soup order) at which each operand has an open or misoriented edge.
  std::vector<std::atomic<u32>> bad(nops);
  for (auto& b : bad) b.store(kNone, std::memory_order_relaxed);
  // How many of a's entries in `list` have vertex b in operand op (whose triangles are first[op]
  // .. first[op + 1]).
  auto count = [&](const auto& list, u32 a, u32 b, std::int32_t op) {
    const std::uint64_t lo = static_cast<std::uint64_t>(b) << 32 | first[op], hi = static_cast<std::uint64_t>(b) << 32 | first[op + 1];
    std::size_t n = 0;
    for (u32 k = off[a]; k < off[a + 1]; ++k) n += list[k] >= lo && list[k] < hi;
    return n;
  };
  // At a vertex of many corners (a fan's hub, a cone's apex), the counts come from the corners'
  // (vertex, operand) keys sorted: a count per corner by a scan of all was quadratic (a cone's hub
  // of 20,000 corners: 0.8 s).
  struct Keys {
    std::vector<std::uint64_t> out, in;
  };
  auto key = [&](std::uint64_t x) { return (x >> 32) << 32 | static_cast<u32>(op_of(x)); };
  auto sort_keys = [&](u32 a, Keys& keys) {
    keys.out.clear();
    keys.in.clear();
    for (u32 k = off[a]; k < off[a + 1]; ++k) {
      keys.out.push_back(key(outs[k]));
      keys.in.push_back(key(ins[k]));
    }
    std::sort(keys.out.begin(), keys.out.end());
    std::sort(keys.in.begin(), keys.in.end());
  };
  // Of out-edge k of a: 0 none, 1 misoriented, 2 open (`keys`: a's, sorted, or null).
  auto defect_at = [&](u32 a, u32 k, const Keys* keys = nullptr) -> int {
    std::size_t n, r;
    if (keys) {
      const std::uint64_t x = key(outs[k]);
      auto many = [&](const std::vector<std::uint64_t>& v) {
        const auto range = std::equal_range(v.begin(), v.end(), x);
        return static_cast<std::size_t>(range.second - range.first);
      };
      n = many(keys->out);
      r = many(keys->in);
    } else {
      const u32 b = static_cast<u32>(outs[k] >> 32);
      const std::int32_t op = op_of(outs[k]);
      n = count(outs, a, b, op);
      r = count(ins, a, b, op);
    }
    // Allowed only where shells touch: as many reverse uses as forward ones.
    if (n > 1 && n != r) return 1;
    return r == 0 ? 2 : 0;
  };
  parallel_for(0, (nv + 4095) / 4096, [&](std::size_t block) {
    s.poll();
    for (std::size_t v = block * 4096; v < std::min(nv, (block + 1) * 4096); ++v) {
      // The common case at once: the corners of one operand, whose next vertices are their
      // previous vertices reordered (each edge out of v has its reverse, as often).
      const u32 d = off[v + 1] - off[v];
      if (d == 0) continue;
      if (d <= 32) {
        // (The corners are in triangle order, so in operand order: all of one operand where the
        // first and the last are.)
        if (op_of(outs[off[v]]) == op_of(outs[off[v + 1] - 1])) {
          std::uint64_t o[32], i[32];  // (next or previous vertex, triangle)
          // Sorted by insertion as they are copied (a handful each: with std::sort, and the
          // operand of every corner looked at, this pass took 41 ms of two 1M-triangle spheres
          // at one thread, 32.5 so).
          auto insert = [](std::uint64_t* a, u32 n, std::uint64_t x) {
            u32 j = n;
            for (; j > 0 && a[j - 1] > x; --j) a[j] = a[j - 1];
            a[j] = x;
          };
          for (u32 k = 0; k < d; ++k) {
            insert(o, k, outs[off[v] + k]);
            insert(i, k, ins[off[v] + k]);
          }
          bool same = true, distinct = true;
          for (u32 k = 0; k < d; ++k) {
            same = same && (o[k] >> 32) == (i[k] >> 32);
            distinct = distinct && (k == 0 || (o[k] >> 32) != (o[k - 1] >> 32));
          }
          if (same) {
            if (adj && distinct)
              for (u32 k = 0; k < d; ++k) {
                const u32 t = static_cast<u32>(o[k]);
                const auto& T = s.tris[t];
                (*adj)[t][T[0] == v ? 0 : (T[1] == v ? 1 : 2)] = static_cast<u32>(i[k]);
              }
            continue;
          }
        }
      }
      thread_local Keys keys;
      if (d > 32) sort_keys(static_cast<u32>(v), keys);
      for (u32 k = off[v]; k < off[v + 1]; ++k)
        if (defect_at(static_cast<u32>(v), k, d > 32 ? &keys : nullptr)) {
          std::atomic<u32>& b = bad[op_of(outs[k])];
          u32 cur = b.load(std::memory_order_relaxed);
          while (v < cur && !b.compare_exchange_weak(cur, static_cast<u32>(v), std::memory_order_relaxed)) {
          }
        }
    }
  });
  auto edge_at = [&](u32 a, u32 b) { return at(s.verts[a]) + " - " + at(s.verts[b]); };
  for (std::size_t o = 0; o < nops; ++o) {
    const u32 a = bad[o].load(std::memory_order_relaxed);
    if (!check[o] || !out[o].empty() || a == kNone) continue;
    std::sort(outs.begin() + off[a], outs.begin() + off[a + 1]);  // the first defect in (b, triangle) order
    Keys keys;
    const bool many = off[a + 1] - off[a] > 32;
    if (many) sort_keys(a, keys);
    for (u32 k = off[a]; k < off[a + 1] && out[o].empty(); ++k) {
      if (op_of(outs[k]) != static_cast<std::int32_t>(o)) continue;
      const u32 b = static_cast<u32>(outs[k] >> 32);
      const int d = defect_at(a, k, many ? &keys : nullptr);
      if (d == 1)
        out[o] = names[o] + " is not consistently oriented: edge " + edge_at(a, b) + " is used " +
                 std::to_string(count(outs, a, b, static_cast<std::int32_t>(o))) + " times in one direction";
      else if (d == 2)
        out[o] = names[o] + " is not closed: edge " + edge_at(a, b) + " of triangle #" +
                 std::to_string(s.local[outs[k] & 0xffffffffu] + 1) + " has no neighbour";
    }
  }
  if (volumes)
    parallel_for(0, nops, [&](std::size_t o) {
      if (check[o] && out[o].empty()) out[o] = volume_defect(*meshes[o], names[o]);
    });
  return out;
}

// The first defect of one closed mesh, or "" (exact). `self` also checks self-intersections.
std::string defect(const Mesh& m, const std::string& name, bool self, const Interrupt* interrupt = nullptr) {
  try {
    m.check();
  } catch (const Error& e) {
    return name + ": " + e.what();
  }
  if (m.triangles.empty()) return "";
  std::vector<const Mesh*> one{&m};
  Soup s = make_soup(one, interrupt);
  CornerLists corners = corner_lists(s, nullptr);
  if (std::string d = soup_defects(s, corners, one, {name}, {1})[0]; !d.empty()) return d;
  if (!self) return "";
  // Self-intersection: triangle pairs whose boxes overlap meet only in their shared vertices/edge.
  // The broad phase's join, which skips the pairs of a certified star (a fan around one vertex, a
  // cone's apex: every pair of its triangles' boxes meet, and a plain join tested them all, 25
  // million pairs and 6 s for a cone of 10,000 sides), and finds shells folded onto each other
  // along an edge. All crossing pairs come back sorted: the first is named.
  std::array<u32, 2> folded{kNone, kNone};
  const std::vector<char> untrusted(1, 0);
  const auto crossing = candidate_pairs(s, &folded, true, &untrusted);
  if (folded[0] != kNone || !crossing.empty()) {
    const u32 t = folded[0] != kNone ? folded[0] : crossing[0][0], u = folded[0] != kNone ? folded[1] : crossing[0][1];
    const auto& T = s.tris[t];
    const auto& U = s.tris[u];
    return name + " intersects itself: triangles #" + std::to_string(s.local[t] + 1) + " " + at(s.verts[T[0]]) + " " +
           at(s.verts[T[1]]) + " " + at(s.verts[T[2]]) + " and #" + std::to_string(s.local[u] + 1) + " " + at(s.verts[U[0]]) +
           " " + at(s.verts[U[1]]) + " " + at(s.verts[U[2]]);
  }
  // Shells that cross nowhere but lie one inside another facing the same way (a box in a box,
  // both outward: a region counted twice), or a shell facing inward in no solid.
  if (std::string d = overlapping_shells(s, operand_starts(s), 0); !d.empty()) return name + " " + d;
  return "";
}

bool lex_less(const Vec3& p, const Vec3& q) {
  return p[0] != q[0] ? p[0] < q[0] : (p[1] != q[1] ? p[1] < q[1] : p[2] < q[2]);
}

// Re-resolves a rounded result that crosses itself: the exact arrangement of its own triangles,
// the region where its winding number is at least 1 kept, rounded again. Provenance (operand,
// source triangle, face id) is carried through from `prev`. The positions in `fixed` (sorted; the
// operands' own vertices) stay where they are; the others were rounded and may move again (all of
// them, without `fixed`).
BooleanResult resolve(const BooleanResult& prev, std::size_t* collapses, bool* unresolved,
                      const Interrupt* interrupt, std::vector<u32>& crossing, const std::vector<Vec3>* fixed,
                      std::size_t* flat_shells = nullptr) {
  // Zero-area triangles (rounding can flatten one) bound nothing and are left out; where their
  // vertices lie on a neighbour's edge the arrangement splits that edge.
  Mesh m;
  m.positions = prev.mesh.positions;
  std::vector<std::size_t> from;
  for (std::size_t t = 0; t < prev.mesh.triangles.size(); ++t) {
    const auto& T = prev.mesh.triangles[t];
    if (collinear(m.positions[T[0]], m.positions[T[1]], m.positions[T[2]])) continue;
    m.triangles.push_back(T);
    m.face_ids.push_back(prev.mesh.face_ids[t]);
    from.push_back(t);
  }
  std::vector<const Mesh*> one{&m};
  Soup soup = make_soup(one, interrupt);
  soup.movable.resize(soup.verts.size());
  for (std::size_t v = 0; v < soup.verts.size(); ++v)
    soup.movable[v] = !fixed || !std::binary_search(fixed->begin(), fixed->end(), soup.verts[v], lex_less);
  Points pts(soup);
  // Only around the triangles that still cross: every crossing pair has one of them, and the
  // triangles beside a flattened one (left out above) share a vertex with it.
  std::vector<char> near(prev.mesh.positions.size(), 0), active(m.triangles.size(), 0);
  for (u32 t : crossing)
    for (u32 v : prev.mesh.triangles[t]) near[v] = 1;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (u32 v : m.triangles[t]) active[t] |= near[v];
  auto pairs = candidate_pairs(soup, nullptr, true, nullptr, &active);
  Arrangement arr = arrange(pts, pairs);
  auto keep = classify(pts, arr, BooleanOp::Union, true);
  BooleanResult r = assemble(pts, arr, keep, collapses, unresolved, &crossing, nullptr, false, flat_shells);
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    const std::size_t orig = from[static_cast<std::size_t>(r.source[t])];
    r.operand[t] = prev.operand[orig];
    r.source[t] = prev.source[orig];
  }
  return r;
}

std::string operand_name(std::size_t i, std::size_t n) {
  if (n == 2) return i == 0 ? "the first operand" : "the second operand";
  return "operand " + std::to_string(i + 1);
}

}  // namespace

std::string mesh_solid_defect(const Mesh& mesh, const std::string& name) { return defect(mesh, name, true); }

BooleanResult boolean_detail::boolean_as_given(BooleanOp op, const std::vector<const Mesh*>& operands, BooleanStats* stats,
                                               const CancelCheck* cancel, std::size_t max_crossings,
                                               const std::vector<std::string>* given_names) {
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  auto lap = [&](double BooleanStats::*field) {
    auto t = Clock::now();
    if (stats) stats->*field = std::chrono::duration<double, std::milli>(t - t0).count();
    t0 = t;
    if (cancel && *cancel && (*cancel)()) throw Cancelled();
  };
  if (operands.empty()) fail("boolean: no operands");
  std::vector<std::string> defects(operands.size()), names(operands.size());
  for (std::size_t i = 0; i < operands.size(); ++i) names[i] = given_names ? (*given_names)[i] : operand_name(i, operands.size());
  for (std::size_t i = 0; i < operands.size(); ++i)
    if (!operands[i]) fail("boolean: ", names[i], " is null");
  const Interrupt interrupt(cancel);
  std::vector<char> trusted(operands.size(), 0), untrusted(operands.size(), 0);
  parallel_for(0, operands.size(), [&](std::size_t i) {
    // A result of this engine was closed, manifold and outward when it was returned.
    trusted[i] = verified_results().contains(*operands[i]);
    untrusted[i] = !trusted[i];
    if (!trusted[i]) try {
        operands[i]->check();
      } catch (const Error& e) {
        defects[i] = names[i] + ": " + e.what();
      }
    // A subnormal coordinate (below 2^-1022 but not 0): products of such numbers lose bits, and
    // with them the exact arithmetic's guarantee (a union of three solids 2^-1060 wide came out
    // 1.7% off the pairwise one). boolean() frames a model of normal size but tiny first; what is
    // left is refused.
    if (defects[i].empty())
      for (std::size_t v = 0; v < operands[i]->positions.size(); ++v) {
        const Point3& p = operands[i]->positions[v];
        if (std::fpclassify(p.x()) == FP_SUBNORMAL || std::fpclassify(p.y()) == FP_SUBNORMAL || std::fpclassify(p.z()) == FP_SUBNORMAL) {
          defects[i] = names[i] + ": vertex " + std::to_string(v + 1) + " " + at(p) +
                       " has a subnormal coordinate (nonzero, below 2.2e-308), where exact decisions are not possible: "
                       "scale the model up";
          break;
        }
      }
  });
  for (const auto& d : defects)
    if (!d.empty()) fail("boolean: ", d);
  // The soup of all operands, and the checks of those not known valid on it.
  Soup soup = make_soup(operands, &interrupt);
  mend_flat_triangles(soup, untrusted);
  CornerLists corners = corner_lists(soup, &untrusted);
  // Triangles across edges, where the check sees them (for classify's patches).
  std::vector<std::array<u32, 3>> adj(soup.tris.size(), {kNone, kNone, kNone});
  defects = soup_defects(soup, corners, operands, names, untrusted, &adj, false);
  // The volumes' signs, but where the radial check below sees every triangle of an operand face
  // away from one point (a positive sum of tetrahedra: nearly every primitive), or toward it.
  std::vector<std::int8_t> facing(operands.size(), 0);
  const bool closed = std::all_of(defects.begin(), defects.end(), [](const std::string& d) { return d.empty(); });
  // (Closed and oriented operands only: the ray and the sum rest on it.)
  std::vector<char> checked = closed ? radially_embedded(soup, &trusted, corners, &facing) : std::vector<char>(operands.size(), 0);
  parallel_for(0, operands.size(), [&](std::size_t o) {
    if (!untrusted[o] || !defects[o].empty()) return;
    if (facing[o] < 0) defects[o] = inside_out(names[o]);
    else if (facing[o] == 0) defects[o] = volume_defect(*operands[o], names[o]);
  });
  for (const auto& d : defects)
    if (!d.empty()) fail("boolean: ", d);
  if (stats) stats->trusted = static_cast<std::size_t>(std::count(trusted.begin(), trusted.end(), 1));
  lap(&BooleanStats::check);
  Points pts(soup);
  // The broad phase also checks each operand for self-intersections, but for the operands known
  // valid: results of earlier booleans, and those one-to-one on the sphere around their centre.
  std::array<u32, 2> clash;
  {
    // Operands seen one-to-one from their centre have no pinched vertex; results of earlier
    // booleans have no adjacency here (their edges are all sorted in the output).
    std::vector<char> look(operands.size(), 0);
    for (std::size_t i = 0; i < operands.size(); ++i) look[i] = untrusted[i] && !checked[i];
    if (std::count(look.begin(), look.end(), 1) > 0) soup.pinched = pinched_vertices(soup, corners, look);
  }
  corners = {};
  for (std::size_t i = 0; i < operands.size(); ++i) checked[i] |= trusted[i];
  // Triangles inside the core of an operand that drops them (a strut's cap inside a node's ball)
  // are settled before the broad phase, which leaves them out.
  Settlement settled = settle_in_cores(soup, op, checked);
  const std::size_t in_cores = settled.settled_triangles();
  auto pairs = candidate_pairs(soup, &clash, false, &checked, nullptr, settled.triangles.empty() ? nullptr : &settled.triangles,
                               &settled.outside);
  if (clash[0] != kNone) {
    u32 t = clash[0], u = clash[1];
    auto tri = [&](u32 x) {
      const auto& T = soup.tris[x];
      return "#" + std::to_string(soup.local[x] + 1) + " " + at(soup.verts[T[0]]) + " " + at(soup.verts[T[1]]) + " " +
             at(soup.verts[T[2]]);
    };
    fail("boolean: ", names[static_cast<std::size_t>(soup.operand[t])], " intersects itself: triangles ", tri(t), " and ",
         tri(u));
  }
  // Shells of one operand that overlap with no crossing (nested facing the same way), but where
  // the operand is known valid.
  {
    std::vector<std::string> overlap(operands.size());
    const std::vector<u32> first = operand_starts(soup);
    parallel_for(0, operands.size(), [&](std::size_t i) {
      if (!checked[i]) overlap[i] = overlapping_shells(soup, first, static_cast<std::int32_t>(i));
    });
    for (std::size_t i = 0; i < operands.size(); ++i)
      if (!overlap[i].empty()) fail("boolean: ", names[i], " ", overlap[i]);
  }
  // Cuts buried in an operand that drops everything there leave the arrangement: settled
  // triangles now, pairs in cores after the budget.
  settle(soup, pairs, op, settled);
  // The work budget, before the exact work (the arrangement) that would take minutes above it.
  if (operands.size() >= 3) {
    const std::size_t crossings = candidate_triples(soup, pairs, max_crossings);
    if (crossings > max_crossings)
      fail("boolean: the ", boolean_op_name(op), " of ", operands.size(), " operands: their surfaces would cross three at a "
           "time at about ", crossings, " points, more than the budget of ", max_crossings,
           " (operands that nearly coincide, such as copies turned by a degree, cross everywhere): use fewer such "
           "operands or raise the budget with tolerance{max_crossings=N}");
  }
  settle_pairs(soup, pairs, op, settled);
  if (stats) {
    stats->settled = settled.settled_triangles();
    stats->in_cores = in_cores;
    stats->settled_pairs = settled.pairs.size();
  }
  lap(&BooleanStats::broad);
  std::size_t collapses = 0, resolutions = 0, flat_shells = 0;
  bool unresolved = false;
  std::vector<Vec3> fixed;  // the operands' vertices, which a re-resolution keeps where they are
  Arrangement arr;
  std::vector<u32> crossing_left;  // the triangles of solve()'s result that still cross (if unresolved)
  // The arrangement, its classification and the rounded result, resolved again where rounding
  // leaves crossings (sheets a few ulps apart), exactly, on the rounded result; each pass works
  // at a finer scale than the one before.
  auto solve = [&](Points& at, bool quads, std::vector<std::array<u32, 3>>* joined) {
    arr = arrange(at, pairs, quads, &settled);
    lap(&BooleanStats::arrange);
    std::vector<std::array<u32, 3>> piece_adj;
    auto keep = classify(at, arr, op, false, joined, &piece_adj, &settled);
    if (joined) std::vector<std::array<u32, 3>>().swap(*joined);
    lap(&BooleanStats::classify);
    std::vector<u32> crossing;
    BooleanResult out = assemble(at, arr, keep, &collapses, &unresolved, &crossing, &piece_adj, true, &flat_shells);
    std::vector<std::array<u32, 3>>().swap(piece_adj);
    if (unresolved && fixed.empty()) {
      fixed = soup.verts;
      std::sort(fixed.begin(), fixed.end(), lex_less);
    }
    for (std::size_t fewest = crossing.size(), tried = 0; unresolved && tried < 4; ++tried) {
      if (cancel && *cancel && (*cancel)()) throw Cancelled();
      out = resolve(out, &collapses, &unresolved, &interrupt, crossing, &fixed, &flat_shells);
      ++resolutions;
      if (unresolved && crossing.size() > 4 * fewest + 64) break;  // diverging, as in resolve_self
      fewest = std::min(fewest, crossing.size());
    }
    crossing_left = std::move(crossing);
    return out;
  };
  BooleanResult r = solve(pts, true, &adj);
  // Whether a triangle that still crosses comes from a flat quadrilateral's triangles.
  // (Compared as (operand, source triangle), which is what the result keeps of a piece's triangle.)
  auto crossing_in_quads = [&] {
    auto key = [](std::int32_t o, std::int32_t t) {
      return static_cast<std::uint64_t>(static_cast<std::uint32_t>(o)) << 32 | static_cast<std::uint32_t>(t);
    };
    std::vector<std::uint64_t> quads;
    for (u32 q : arr.quad_tris) quads.push_back(key(soup.operand[q], soup.local[q]));
    std::sort(quads.begin(), quads.end());
    for (u32 t : crossing_left)
      if (std::binary_search(quads.begin(), quads.end(), key(r.operand[t], r.source[t]))) return true;
    return false;
  };
  if (unresolved && crossing_in_quads()) {
    // Once more without the flat quadrilaterals (an optimization; the result is the same solid):
    // a quadrilateral's triangulation across its diagonal has left pieces that rounding folds
    // where the two triangles' own would not (flush boxes on planes such as x + y = c). Where no
    // triangle still crossing comes from one (or there is none), the pieces where it fails are
    // made again as they were, and fail again: not tried (a union of two results of nine nearly
    // coincident spheres spent 2.5 s of its 7.4 so, with no quadrilateral near its crossings).
    Points again(soup);
    r = solve(again, false, nullptr);
  }
  if (!unresolved && resolutions > 0) rename_reversed(r, soup, op);
  if (unresolved) {
    const Vec3& p = r.mesh.positions.empty() ? Vec3(0, 0, 0) : r.mesh.positions[0];
    // fail()'s message, thrown as the kind boolean() retries on welded operands.
    try {
      fail("boolean: the result cannot be rounded to doubles without a self-intersection (", resolutions,
           " re-resolutions tried; first vertex (", p.x(), ", ", p.y(), ", ", p.z(), "))");
    } catch (const Error& e) {
      throw Unroundable(e.what());
    }
  }
  verified_results().add(fingerprint(r.mesh));
  lap(&BooleanStats::output);
  if (stats) {
    stats->pairs = pairs.size();
    stats->collapses = collapses;
    stats->flat_shells = flat_shells;
    stats->resolutions = resolutions;
    stats->pieces = arr.pieces.size();
    stats->quads = arr.quads;
    stats->quad_points = arr.quad_points;
  }
  return r;
}

void boolean_detail::Interrupt::poll() const {
  if (!check_) return;
  if (stopped_.load(std::memory_order_relaxed)) throw Cancelled();
  const std::int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               std::chrono::steady_clock::now().time_since_epoch())
                               .count();
  if (now < next_.load(std::memory_order_relaxed)) return;
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  next_.store(now + 2'000'000, std::memory_order_relaxed);
  if ((*check_)()) {
    stopped_.store(true, std::memory_order_relaxed);
    throw Cancelled();
  }
}

const char* boolean_op_name(BooleanOp op) {
  switch (op) {
    case BooleanOp::Union: return "union";
    case BooleanOp::Difference: return "difference";
    case BooleanOp::Intersection: return "intersection";
  }
  return "?";
}

Mesh boolean(BooleanOp op, const Mesh& a, const Mesh& b) { return boolean(op, {&a, &b}).mesh; }

BooleanResult resolve_self(const Mesh& mesh, const CancelCheck* cancel) {
  mesh.check();
  const boolean_detail::Interrupt interrupt(cancel);
  BooleanResult r;
  r.mesh = mesh;
  if (r.mesh.face_ids.size() != r.mesh.triangles.size()) r.mesh.face_ids.assign(r.mesh.triangles.size(), -1);
  const std::size_t n = mesh.triangles.size();
  r.operand.assign(n, 0);
  r.source.resize(n);
  for (std::size_t t = 0; t < n; ++t) r.source[t] = static_cast<std::int32_t>(t);
  // Edges far shorter than the rounding the move made (a wall 1e-17 wide, turned) are noise: they
  // go first, where the mesh stays a manifold. Left in, each pass's resolution and rounding around
  // them made more crossings than it removed.
  double reach = 0;
  for (const Vec3& p : mesh.positions) reach = std::max(reach, p.cwiseAbs().maxCoeff());
  std::size_t collapses = collapse_short_edges(r, std::ldexp(reach, -40));
  // Where it crosses itself is not known: anywhere (the triangles the collapses left).
  std::vector<boolean_detail::u32> crossing(r.mesh.triangles.size());
  std::iota(crossing.begin(), crossing.end(), boolean_detail::u32(0));
  bool unresolved = true;
  std::size_t fewest = crossing.size();
  for (int pass = 0; unresolved && pass < 5; ++pass) {
    if (cancel && *cancel && (*cancel)()) throw Cancelled();
    r = resolve(r, &collapses, &unresolved, &interrupt, crossing, nullptr);
    // Diverging (each pass's rounding crossing more than the last resolved: 146, 1,377, then
    // 28,257 crossings over 40,000 triangles, a minute a pass), it stops.
    if (unresolved && crossing.size() > 4 * fewest + 64) break;
    fewest = std::min(fewest, crossing.size());
  }
  if (unresolved) fail("boolean: a mesh crossing itself could not be resolved and rounded to doubles without a self-intersection");
  verified_results().add(fingerprint(r.mesh));
  return r;
}

}  // namespace wedge
