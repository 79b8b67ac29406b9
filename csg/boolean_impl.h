// The engine's private header: its data and stages, by the file that defines them (its map).
//
// Notation and number representation
// - The input is a *soup*: every operand's triangles, on vertices merged by exactly equal position
//   across operands. Input coordinates are doubles and are exact.
// - A *point* is an input vertex or an implicit point, never a rounded construction:
//     LPI  the segment p q (input vertices) cut by a plane,
//     TPI  the meeting point of three planes,
//   where a *plane* is the plane of an input triangle (a, b, c) or the plane through the input
//   vertices a, b that contains the coordinate axis e_k (the "wall" over a segment when a triangle
//   is seen along e_k). Every point has exact homogeneous coordinates (X, Y, Z, W): polynomials in
//   the input doubles, evaluated in three number types:
//     double     approximate position (sorting hints, the final rounding);
//     Interval   CGAL::Interval_nt, the filter: most predicates are decided here;
//     Mpzf       CGAL's exact multi-precision float, for the rare ties the filter cannot decide.
//   W is never 0 for a point the engine makes (its planes are independent). Every predicate
//   (orientation in a projection, coordinate comparison, side of a plane) returns the sign exact
//   arithmetic would give.
// - T, U are input triangles; k(T) is the axis T is projected along (the largest component of its
//   normal, exactly non-zero), and (i, j) = (k+1, k+2) mod 3 its 2D coordinates, so that the
//   projection keeps T's orientation when n_k > 0.
// - A *segment* of T is a constraint of T's retriangulation: a piece of T's intersection with
//   another operand, given by its two end points and the plane that cuts T along it.
// - A *flat quadrilateral*: two cut triangles of one operand and face, coplanar and strictly
//   convex together, retriangulated as one (boolean_quads.cpp), named by the first.
// - A *patch* is a set of output candidate triangles of one operand joined across edges that no
//   other operand touches; a patch is all inside or all outside every other operand, but where it
//   lies strictly inside an operand that drops everything there (settling, boolean_settle.cpp:
//   the cuts there are left out, and the patch is dropped whatever it straddles).
// - w_j(P) is the winding number of point P with respect to operand j.
//
// Where rounding happens: only in output.cpp, once, when exact output vertices become doubles.
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <cmath>

#include "csg/boolean.h"
#include "csg/boolean_dsu_impl.h"  // Dsu: union-find, serial, shared and by blocks
#include "csg/boolean_sort_impl.h"  // radix_sort
#include "kernel/memory.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"
#include "kernel/types.h"

namespace wedge::boolean_detail {

// Filtered orientation predicates on input doubles: the determinant in double with a static
// error bound (Shewchuk's stage-A bounds for a 2x2 and a 3x3 determinant of differences); only
// when the bound cannot decide does the exact predicate (CGAL, kernel/predicates.cpp) run. What
// follows an undecided filter is out of line (boolean_exact.cpp), so that the filter inlines
// small into the hot loops.
int orient2d_undecided(double ax, double ay, double bx, double by, double cx, double cy);
int orient3d_undecided(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
// orient2d_fast's filter on its two products, l - r the determinant: its sign, or 0 where the
// bound does not decide it.
inline int orient2d_filter(double l, double r) {
  const double det = l - r;
  const double bound = 3.3306690738754716e-16 * (std::abs(l) + std::abs(r));
  if (bound > 1e-280) {  // far from underflow, where the bound holds
    if (det > bound) return 1;
    if (-det > bound) return -1;
  }
  return 0;
}
inline int orient2d_fast(double ax, double ay, double bx, double by, double cx, double cy) {
  if (const int s = orient2d_filter((bx - ax) * (cy - ay), (by - ay) * (cx - ax))) return s;
  return orient2d_undecided(ax, ay, bx, by, cx, cy);
}
// The first stages of the point predicates (Points::orient2d, Points::incircle_certain), on
// projected approximations (x, y) each at most w from its exact point: the sign where the error
// bound settles it, else 2. The triangulation runs them on its own copies of its points. (Their
// bounds assume each operation rounded on its own: the files that call them are compiled with
// -ffp-contract=off.)
struct Approx2 {
  double x, y, w;
  bool exact;  // x and y are the point's own (then w does not count)
};
// Where all three are exact, the filtered predicate on doubles (never undecided). Else Shewchuk's
// stage-A bound for the determinant, plus how far the exact points may be from the
// approximations: each difference moves by at most 2W (W the largest slack), so the determinant
// by at most 8 R' W, R' the largest difference plus 2W.
inline int orient2d_first(const Approx2& A, const Approx2& B, const Approx2& C) {
  if (A.exact && B.exact && C.exact) return orient2d_fast(A.x, A.y, B.x, B.y, C.x, C.y);
  const double W = std::max({A.w, B.w, C.w});
  const double bx = B.x - A.x, by = B.y - A.y, cx = C.x - A.x, cy = C.y - A.y;
  const double l = bx * cy, r = by * cx, det = l - r;
  const double R = std::max({std::abs(bx), std::abs(by), std::abs(cx), std::abs(cy)}) + 2 * W;
  const double bound = 3.3306690738754716e-16 * (std::abs(l) + std::abs(r)) + 16 * R * W;
  if (bound < INFINITY && bound > 1e-280) {
    if (det > bound) return 1;
    if (-det > bound) return -1;
  }
  return 2;
}
// The classic in-circle determinant relative to D, with Shewchuk's stage-A error bound, plus
// (where the points are not all exact) how far they may be: each difference moves by at most 2W
// (W the largest slack), so each of the three products of a squared length and a cross product
// by at most 32 R'^3 W (R' the largest difference plus 2W); 128 R'^3 W bounds the sum.
inline int incircle_first(const Approx2& A, const Approx2& B, const Approx2& C, const Approx2& D) {
  const double W = A.exact && B.exact && C.exact && D.exact ? 0.0 : std::max({A.w, B.w, C.w, D.w});
  const double adx = A.x - D.x, ady = A.y - D.y, bdx = B.x - D.x, bdy = B.y - D.y;
  const double cdx = C.x - D.x, cdy = C.y - D.y;
  const double bc = bdx * cdy, cb = cdx * bdy, ca = cdx * ady, ac = adx * cdy, ab = adx * bdy, ba = bdx * ady;
  const double al = adx * adx + ady * ady, bl = bdx * bdx + bdy * bdy, cl = cdx * cdx + cdy * cdy;
  const double det = al * (bc - cb) + bl * (ca - ac) + cl * (ab - ba);
  const double perm = (std::abs(bc) + std::abs(cb)) * al + (std::abs(ca) + std::abs(ac)) * bl +
                      (std::abs(ab) + std::abs(ba)) * cl;
  double bound = 1.1102230246251577e-15 * perm;
  if (W > 0) {
    const double R =
        std::max({std::abs(adx), std::abs(ady), std::abs(bdx), std::abs(bdy), std::abs(cdx), std::abs(cdy)}) + 2 * W;
    bound += 128 * R * R * R * W;
  }
  if (bound < INFINITY && bound > 1e-280 && std::abs(det) > bound) return det > 0 ? 1 : -1;
  return 2;
}
// The same in the metric of the quadratic form (q11, q12, q22) (the slacks count whether or not
// the points are exact), with a bound of 32 ulps of the
// permanent (the plain test's stage-A bound is 10; the form adds three products and a sum to
// each lifted term, and |q| <= 1), plus how far the exact points may be: with each difference
// off by at most 2W and R' the largest difference plus 2W, a lifted term is off by at most
// 16 R' W (and at most 4 R'^2), a 2x2 minor by 8 R' W (at most 2 R'^2): 192 R'^3 W in all,
// 256 here.
inline int incircle_first(const Approx2* p[4], double q11, double q12, double q22) {
  const Approx2& D = *p[3];
  double W = D.w, R = 0;
  double r[3][3], lift_abs[3];
  for (int n = 0; n < 3; ++n) {
    const double x = p[n]->x - D.x, y = p[n]->y - D.y;
    W = std::max(W, p[n]->w);
    R = std::max({R, std::abs(x), std::abs(y)});
    r[n][0] = x;
    r[n][1] = y;
    r[n][2] = q11 * x * x + 2 * q12 * x * y + q22 * y * y;
    lift_abs[n] = std::abs(q11) * x * x + 2 * std::abs(q12 * x * y) + std::abs(q22) * y * y;
  }
  const double m0 = r[1][0] * r[2][1] - r[2][0] * r[1][1], m1 = r[2][0] * r[0][1] - r[0][0] * r[2][1],
               m2 = r[0][0] * r[1][1] - r[1][0] * r[0][1];
  const double det = r[0][2] * m0 + r[1][2] * m1 + r[2][2] * m2;
  const double perm = lift_abs[0] * (std::abs(r[1][0] * r[2][1]) + std::abs(r[2][0] * r[1][1])) +
                      lift_abs[1] * (std::abs(r[2][0] * r[0][1]) + std::abs(r[0][0] * r[2][1])) +
                      lift_abs[2] * (std::abs(r[0][0] * r[1][1]) + std::abs(r[1][0] * r[0][1]));
  double bound = 3.5527136788005009e-15 * perm;
  if (W > 0) {
    R += 2 * W;
    bound += 256 * R * R * R * W;
  }
  if (bound < INFINITY && bound > 1e-280 && std::abs(det) > bound) return det > 0 ? 1 : -1;
  return 2;
}
// The smallest sine of the angles of triangle (a, b, c) seen in the coordinate plane (i, j),
// from approximate positions: 0 for a triangle that is degenerate there. It judges shapes only
// (how far a flip test may trust a rounded position), never a combinatorial decision.
inline double triangle_min_sine(const Vec3& a, const Vec3& b, const Vec3& c, int i, int j) {
  const Vec3* t[3] = {&a, &b, &c};
  double worst = 1;
  for (int k = 0; k < 3; ++k) {
    const Vec3 &o = *t[k], &u = *t[(k + 1) % 3], &v = *t[(k + 2) % 3];
    const double ux = u[i] - o[i], uy = u[j] - o[j], vx = v[i] - o[i], vy = v[j] - o[j];
    const double len = std::sqrt((ux * ux + uy * uy) * (vx * vx + vy * vy));
    if (!(len > 0)) return 0;
    worst = std::min(worst, std::abs(ux * vy - uy * vx) / len);
  }
  return worst;
}
// sign det[b - a, c - a, d - a], as wedge::orient3d.
inline int orient3d_fast(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double bx = b.x() - a.x(), by = b.y() - a.y(), bz = b.z() - a.z();
  const double cx = c.x() - a.x(), cy = c.y() - a.y(), cz = c.z() - a.z();
  const double dx = d.x() - a.x(), dy = d.y() - a.y(), dz = d.z() - a.z();
  const double cydz = cy * dz, czdy = cz * dy, czdx = cz * dx, cxdz = cx * dz, cxdy = cx * dy, cydx = cy * dx;
  const double det = bx * (cydz - czdy) + by * (czdx - cxdz) + bz * (cxdy - cydx);
  const double perm = std::abs(bx) * (std::abs(cydz) + std::abs(czdy)) + std::abs(by) * (std::abs(czdx) + std::abs(cxdz)) +
                      std::abs(bz) * (std::abs(cxdy) + std::abs(cydx));
  const double bound = 7.7715611723761027e-16 * perm;
  if (bound > 1e-280) {
    if (det > bound) return 1;
    if (-det > bound) return -1;
  }
  return orient3d_undecided(a, b, c, d);
}

using u32 = std::uint32_t;
constexpr u32 kNone = 0xffffffffu;

// A cancel request seen inside the stages: poll() is called in the stages' loops (by any of
// TBB's threads); it calls the caller's check at most every 2 ms and by one thread at a time,
// and throws Cancelled once the check has said stop (TBB carries the exception out of parallel
// loops to the caller). Nothing outlives a cancelled run: its state is all local to boolean().
class Interrupt {
 public:
  explicit Interrupt(const CancelCheck* check) : check_(check && *check ? check : nullptr) {}
  void poll() const;

 private:
  const CancelCheck* check_;
  mutable std::atomic<bool> stopped_{false};
  mutable std::atomic<std::int64_t> next_{0};
  mutable std::mutex mutex_;
};

// --- the input soup (boolean.cpp) ---
// An allocator whose vectors leave new elements of trivial types uninitialised (resize(n) and
// vector(n) do not zero them): for large arrays that are wholly written next, where zeroing them
// first (hundreds of megabytes on a million-triangle boolean) was a serial pass of its own.
template <class T>
struct NoInit : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = NoInit<U>;
  };
  NoInit() = default;
  template <class U>
  NoInit(const NoInit<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
};

// (The per-triangle arrays are written whole by make_soup: not zeroed first.)
struct Soup {
  std::vector<Vec3> verts;                                        // unique input positions
  std::vector<std::array<u32, 3>, NoInit<std::array<u32, 3>>> tris;  // vertex ids, counter-clockwise seen from outside
  std::vector<std::int32_t, NoInit<std::int32_t>> operand;        // per triangle
  std::vector<std::int32_t, NoInit<std::int32_t>> local;          // per triangle: its index in its operand
  std::vector<std::int32_t, NoInit<std::int32_t>> face_id;        // per triangle: the operand's face id, or -1
  std::vector<std::int8_t, NoInit<std::int8_t>> axis;             // per triangle: k(T)
  std::vector<std::int8_t, NoInit<std::int8_t>> axis_sign;        // per triangle: sign of n_k(T)
  int operands = 0;
  // Per operand: a box (lo, hi) that holds its triangles, over all its positions (with any its
  // triangles do not use); (inf, -inf) for an operand without triangles.
  std::vector<std::array<double, 6>> boxes;
  // Per vertex: the operand whose positions it holds, or -2 where it holds positions of several.
  std::vector<std::int32_t, NoInit<std::int32_t>> vertex_operand;
  // Per vertex (or empty: none): the input position is itself a rounded one (of a mesh moved by an
  // inexact transform, or of an earlier pass's output), which the rounding repair may move, as it
  // moves constructed points. An operand's own vertices never move.
  std::vector<char> movable;
  // Vertices where an operand's triangles make several fans (two of its shells touch there, their
  // vertices welded here; ascending): the output keeps one copy per fan (boolean_output.cpp).
  std::vector<u32> pinched;
  const Interrupt* interrupt = nullptr;   // the run's cancel request (null: none)
  void poll() const {
    if (interrupt) interrupt->poll();
  }
};

// What boolean_as_given throws when its result cannot be rounded to doubles without a
// self-intersection, after every re-resolution (boolean_frame.cpp then tries welded operands).
class Unroundable : public Error {
 public:
  using Error::Error;
};

// boolean() on the operands' own coordinates (boolean_frame.cpp runs it on copies scaled by a
// power of two where that is exact and the coordinates are far from 1).
BooleanResult boolean_as_given(BooleanOp op, const std::vector<const Mesh*>& operands, BooleanStats* stats,
                               const CancelCheck* cancel, std::size_t max_crossings,
                               const std::vector<std::string>* names = nullptr);

// Merges meshes into one soup (positions equal in value become one vertex; -0 is 0). The soup
// polls `interrupt` (if any), from here on.
Soup make_soup(const std::vector<const Mesh*>& meshes, const Interrupt* interrupt = nullptr);
// A hash of a position, every bit mixed (-0 hashes as 0).
std::uint64_t position_hash(const Vec3& at);
// "(x, y, z)" with 17 digits, for error messages.
std::string point_text(const Vec3& p);
// Spreads the low 21 bits of x to every third bit (a Morton code's one axis).
inline std::uint64_t morton_spread(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}
// Where each operand's triangles start in the soup (they come operand after operand): operand j's
// are first[j] .. first[j + 1] - 1.
std::vector<u32> operand_starts(const Soup& s);
// Each operand's box (lo, hi) over its triangles; an operand without triangles gets (inf, -inf).
std::vector<std::array<double, 6>> operand_boxes(const Soup& s);
// "" where operand o's shells (joined across edges of two triangles) nest as a solid's do, else
// the defect from "has shells that overlap": one inside another facing the same way, say. For
// shells that do not cross; `first` from operand_starts (boolean_shells.cpp).
std::string overlapping_shells(const Soup& s, const std::vector<u32>& first, std::int32_t o);
// Marks `owner` (an atomic or atomic_ref) held by operand op: -1 (none) becomes op, another op -2.
template <class Atomic>
inline void claim(Atomic&& owner, std::int32_t op) {
  using T = decltype(owner.load(std::memory_order_relaxed));
  T cur = owner.load(std::memory_order_relaxed);
  while (cur != T(op) && cur != T(-2))
    if (owner.compare_exchange_weak(cur, cur == T(-1) ? T(op) : T(-2), std::memory_order_relaxed)) break;
}
// Sets s.axis[t] and s.axis_sign[t] from triangle t's vertices (-1: zero area).
void set_axis(Soup& s, std::size_t t);
// Mends the zero-area triangles of the operands marked in `check` where no point moves (see
// boolean.cpp); what it cannot mend stays for the operand check to report.
void mend_flat_triangles(Soup& s, const std::vector<char>& check);
// Whether triangles t and u meet anywhere but in the vertices or edge they share (exact).
bool triangles_clash(const Soup& s, u32 t, u32 u);
// Whether triangles t and u (their corners) meet, where their planes cross: st[k] the side of
// t[k] of u's plane and su[k] of u[k] of t's plane (orient3d), none 0, neither all alike (exact).
bool crossing_triangles_meet(const Vec3* const t[3], const int st[3], const Vec3* const u[3], const int su[3]);

// The box of soup triangle t (exact: the min and max of its vertices).
inline void triangle_box(const Soup& s, u32 t, double lo[3], double hi[3]) {
  for (int d = 0; d < 3; ++d) {
    double a = s.verts[s.tris[t][0]][d], b = s.verts[s.tris[t][1]][d], c = s.verts[s.tris[t][2]][d];
    lo[d] = std::min(a, std::min(b, c));
    hi[d] = std::max(a, std::max(b, c));
  }
}

// The box of triangle t of mesh m (the min and max of its vertices).
inline void mesh_triangle_box(const Mesh& m, std::size_t t, double lo[3], double hi[3]) {
  for (int d = 0; d < 3; ++d) {
    lo[d] = hi[d] = m.positions[m.triangles[t][0]][d];
    for (int k = 1; k < 3; ++k) {
      lo[d] = std::min(lo[d], m.positions[m.triangles[t][k]][d]);
      hi[d] = std::max(hi[d], m.positions[m.triangles[t][k]][d]);
    }
  }
}


// Whether two short arrays are equal, compared element by element in line (operator== of a
// std::array of integers is a call to memcmp: one per piece in classify, 3.6 ms of two
// 1M-triangle spheres' union).
template <class T, std::size_t N>
inline bool same_array(const std::array<T, N>& a, const std::array<T, N>& b) {
  bool differ = false;
  for (std::size_t i = 0; i < N; ++i) differ |= a[i] != b[i];
  return !differ;
}

// An edge's record: key = a << 32 | b (vertex or point ids), and a value (a triangle, a corner).
struct EdgeRec {
  std::uint64_t key;
  u32 value;
};
using EdgeRecs = std::vector<EdgeRec, NoInit<EdgeRec>>;
// Sorts edge records by (key, value), every a (key >> 32) below n: a counting sort on a, then each
// vertex's few records (a comparison sort of millions was a tenth of a large boolean); with far
// fewer records than n, a radix sort of the keys (linear in the records alone).
void sort_edges(EdgeRecs& recs, std::size_t n, const Interrupt* interrupt = nullptr);

// Calls f(i, j) for each run recs[i .. j) of records with one key (recs sorted by key), in
// parallel over blocks of records: a run belongs to the block it starts in. Polls per block.
template <class F>
void for_each_run(const EdgeRecs& recs, const Interrupt* interrupt, F&& f) {
  constexpr std::size_t kBlock = 1 << 14;
  const std::size_t m = recs.size();
  parallel_for(0, (m + kBlock - 1) / kBlock, [&](std::size_t b) {
    if (interrupt) interrupt->poll();
    std::size_t i = b * kBlock;
    const std::size_t end = std::min(m, i + kBlock);
    while (i < end && i > 0 && recs[i].key == recs[i - 1].key) ++i;  // a run of the block before
    while (i < end) {
      std::size_t j = i + 1;
      while (j < m && recs[j].key == recs[i].key) ++j;
      f(i, j);
      i = j;
    }
  });
}

// --- exact points and predicates (boolean_exact.cpp) ---
struct Plane {
  std::int32_t axis;  // -1: the plane of triangle (a, b, c); 0..2: through a, b containing e_axis
  u32 a, b, c;
  static Plane of_triangle(const std::array<u32, 3>& t) { return {-1, t[0], t[1], t[2]}; }
  static Plane wall(u32 a, u32 b, int k) { return {k, a, b, kNone}; }
  bool operator==(const Plane& o) const { return axis == o.axis && a == o.a && b == o.b && c == o.c; }
};

// Whether plane P is x_i = c for a double c (then set; -0 as +0): a triangle whose corners share
// coordinate i, or a wall over a segment whose ends do, across e_i.
inline bool fixes_coordinate(const Soup& s, const Plane& P, int i, double& c) {
  const Vec3& a = s.verts[P.a];
  const Vec3& b = s.verts[P.b];
  if (a[i] != b[i]) return false;
  if (P.axis < 0) {
    if (s.verts[P.c][i] != a[i]) return false;
  } else if (P.axis == i) {
    return false;  // a wall contains e_axis, so it is never x_axis = c
  }
  c = a[i] == 0 ? 0.0 : a[i];
  return true;
}

struct PointDef {
  enum Kind : std::uint8_t { Explicit, Lpi, Tpi } kind = Explicit;
  u32 p = kNone, q = kNone;  // Explicit: vertex p; Lpi: segment p q
  Plane P[3] = {};           // Lpi: P[0]; Tpi: P[0], P[1], P[2]
};

struct IntervalH { double lo[4], hi[4]; };  // interval homogeneous coordinates (X, Y, Z, W)

// The table of every point of a run. Ids below soup.verts.size() are the input vertices.
struct ExactPoint;  // a point's exact homogeneous coordinates, kept once computed (boolean_exact.cpp)
struct DdPoint;     // the same in double-double arithmetic with an error bound (boolean_dd.h)

class Points {
 public:
  explicit Points(const Soup& soup);
  ~Points();
  Points(const Points&) = delete;
  Points& operator=(const Points&) = delete;
  // A new point (not thread-safe), with its filter data.
  u32 add(const PointDef& d);
  // A new point whose filter data waits for evaluate_added(): until then only its definition
  // may be read. (Many points added this way are evaluated in parallel.)
  u32 add_later(const PointDef& d);
  // Computes the filter data (approximation, intervals, box) of the points added since the last
  // call, in parallel.
  void evaluate_added();
  void reserve(std::size_t n);  // room for n points in all (no reallocation while interning)
  std::size_t size() const { return nin_ + defs_.size(); }
  PointDef def(u32 p) const {
    if (p >= nin_) return defs_[p - nin_];
    PointDef d;
    d.p = p;
    return d;
  }
  const Vec3& approx(u32 p) const { return p < nin_ ? soup_->verts[p] : approx_[p - nin_]; }
  IntervalH interval(u32 p) const;
  bool is_explicit(u32 p) const { return p < nin_ || defs_[p - nin_].kind == PointDef::Explicit; }
  // Whether approx(p) is the point exactly (an input vertex, or a point whose three coordinates
  // are each fixed by a segment or an axis-parallel plane through it); such a point does not
  // move when the result is rounded.
  bool is_double(u32 p) const { return fixed(p) == 7; }
  // Bit i set: coordinate i of approx(p) is exact.
  std::uint8_t fixed(u32 p) const { return p < nin_ ? 7 : fixed_[p - nin_]; }
  // approx(p) in the projection along e_k, with its slack and whether it is exact there: what
  // the predicates' first stages read.
  Approx2 projected(u32 p, int k) const {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const std::uint8_t m = static_cast<std::uint8_t>(1u << i | 1u << j);
    const Vec3& v = approx(p);
    return {v[i], v[j], slack(p), (fixed(p) & m) == m};
  }
  const Soup& soup() const { return *soup_; }

  // Exact predicates.
  // In the projection along e_k, (i, j) = (k+1, k+2). With `line`: a, b and c lie on one plane
  // (a triangle's) and `line` is another plane through a and b: c on it is collinear with them.
  int orient2d(u32 a, u32 b, u32 c, int k, const Plane* line = nullptr) const;
  int compare(u32 a, u32 b, int axis) const;       // sign(a_axis - b_axis)
  bool equal(u32 a, u32 b) const;
  int side(const Plane& P, u32 p) const;           // sign(n . p + d): + on the side n points to
  // For the retriangulation's Delaunay flips: +1 if d is inside the circle through a, b, c
  // (counter-clockwise in projection k), -1 if outside or on it, as exact arithmetic says; except
  // where the filter cannot tell and every triangle that either split of the four points would
  // make is well shaped: then -1 (no flip) without exact arithmetic. A flip is made only where it
  // is certain, so flipping ends; points cocircular to within the inputs' rounding (a tessellated
  // circle cut by a plane) leave their split as it is, and slivers are still flipped away.
  // "Well shaped": no angle with a sine under `well` (0.01, about half a degree; the
  // retriangulation of an input triangle that is itself a sliver passes half its own smallest
  // sine, since every piece of it is as thin).
  int incircle_certain(u32 a, u32 b, u32 c, u32 d, int k, double well = 0.01) const;
  // The same in the metric of a positive definite quadratic form q(x, y) = q11 x^2 + 2 q12 x y +
  // q22 y^2 on the projection (the circles are its ellipses): the Delaunay test of the plane that
  // the form's square root maps the points to. Inside a sliver, the map that makes the sliver
  // equilateral spreads its points, so the filter decides where the plain test would need exact
  // arithmetic, and "well shaped" is judged there.
  struct Metric {
    double q11, q12, q22;
  };
  int incircle_certain(u32 a, u32 b, u32 c, u32 d, int k, double well, const Metric& q) const;
  int incircle_interval(u32 a, u32 b, u32 c, u32 d, int k, const Metric* q) const;  // 2: undecided
  // For the centroid of triangle (a, b, c): sign of orient2d(u, v, centroid) in projection k, with
  // u, v input vertices; and the side of a plane.
  int orient2d_centroid(u32 u, u32 v, const std::array<u32, 3>& t, int k) const;
  int side_centroid(const Plane& P, const std::array<u32, 3>& t) const;
  // A box that holds the centroid of triangle (a, b, c) exactly: lo[0..2], hi[0..2] (infinite
  // where the filter cannot bound it).
  std::array<double, 6> centroid_box(const std::array<u32, 3>& t) const;
  // Whether two planes are parallel or the same (cross product of normals exactly zero) — and
  // the sign of a component of that cross product.
  int cross_sign(const Plane& P, const Plane& Q, int axis) const;
  // compare() on points not (yet) in the table.
  int compare_def(const PointDef& a, const PointDef& b, int axis) const;
  // An interval [lo, hi] that holds coordinate `axis` of the point d (lo == hi: exactly that
  // double), for ordering points not in the table without evaluating them again per comparison.
  void coord_bounds(const PointDef& d, int axis, double& lo, double& hi) const;
  // compare_def() given the two points' coord_bounds() on `axis`.
  int compare_def(const PointDef& a, const double ab[2], const PointDef& b, const double bb[2], int axis) const {
    if (ab[1] < bb[0]) return -1;
    if (ab[0] > bb[1]) return 1;
    if (ab[0] == ab[1] && bb[0] == bb[1]) return 0;  // both exact and equal
    return compare_def(a, b, axis);
  }
  // A box that holds the point exactly: lo[0..2], hi[0..2].
  std::array<double, 6> box(u32 p) const {
    if (p >= nin_) return box_[p - nin_];
    const Vec3& v = soup_->verts[p];
    return {v.x(), v.y(), v.z(), v.x(), v.y(), v.z()};
  }
  bool on_one_segment(u32 a, u32 b, u32 c) const;
  // Whether each coordinate of the point d is a double fixed by its definition (an axis-parallel
  // segment or axis plane: every point of a sponge of boxes); if so, *out is the point. It reads
  // the soup only: the interning's runs call it while the first of them adds points.
  bool exact_position(const PointDef& d, Vec3& out) const;
  // Whether a, b, c certainly lie on one line, from their definitions: on one cutting plane, with
  // their segments' end points on one other plane (exact tests on input vertices only). With
  // k >= 0, also whether they lie on one line seen along e_k: on one plane containing e_k.
  bool collinear_by_definition(u32 a, u32 b, u32 c, int k = -1) const;
  // Whether point p certainly lies on plane P, from its definition (exact tests on input
  // vertices only; false where that does not settle it).
  bool on_plane(u32 p, const Plane& P) const;

 private:
  // The input vertices (ids below nin_) are read from the soup: the tables below (blocks kept
  // for the next run: kernel/memory.h) hold the points added since, at id - nin_.
  const Soup* soup_;
  u32 nin_;
  KeptVector<PointDef> defs_;
  KeptVector<std::uint8_t> fixed_;
  KeptVector<Vec3> approx_;
  KeptVector<IntervalH> ih_;
  KeptVector<std::array<double, 6>> box_;
  KeptVector<double> slack_;  // how far approx(p) may be from the point in any coordinate (from its box)
  // Per added point, its exact coordinates once a predicate has needed them (null before): set by
  // any thread, once (an atomic compare-and-swap), freed with the table.
  mutable KeptVector<ExactPoint*> exact_;
  mutable KeptVector<DdPoint*> dd_;  // the same for the double-double coordinates
  void evaluate(std::size_t n);  // the filter data of added point n (at id nin_ + n)
  double slack(u32 p) const { return p < nin_ ? 0.0 : slack_[p - nin_]; }
  // The exact coordinates: an input vertex's are made in `scratch`, an added point's are kept.
  const ExactPoint& exact(u32 p, ExactPoint& scratch) const;
  const DdPoint& dd(u32 p, DdPoint& scratch) const;
};

// The constrained Delaunay triangulation of one cut triangle (boolean_cdt.cpp), in the
// projection along e_k: `corners` (counter-clockwise there) with `points` inside or on their
// triangle (inserted in this order; corners among them are skipped) and the `constraints`
// between them (none passing through a point, none crossing another). The triangles, counter-
// clockwise in the projection, are appended to `out`. `well` is incircle_certain's. With `inner`,
// per triangle made and edge e (v[e] -> v[e+1]), the triangle across it (counted from this call's
// first) where that edge is neither a constraint nor on the boundary, else kNone.
// With `metric`, the Delaunay test is in that metric (Points::incircle_certain).
void constrained_delaunay(const Points& pts, int k, double well, const std::array<u32, 3>& corners,
                          const std::vector<u32>& points, const std::vector<std::array<u32, 2>>& constraints,
                          std::vector<std::array<u32, 3>>& out, std::vector<std::array<u32, 3>>* inner = nullptr,
                          const Points::Metric* metric = nullptr);
// The same in a convex quadrilateral (two coplanar triangles of one face, flat_quads()): its
// corners counter-clockwise, their diagonal 0-2 no constraint.
void constrained_delaunay_quad(const Points& pts, int k, double well, const std::array<u32, 4>& corners,
                          const std::vector<u32>& points, const std::vector<std::array<u32, 2>>& constraints,
                          std::vector<std::array<u32, 3>>& out, std::vector<std::array<u32, 3>>* inner = nullptr);

// Exact sign of orient3d on input vertices.
int orient3d_v(const Soup& s, u32 a, u32 b, u32 c, u32 d);

// --- broad phase (boolean_broad.cpp) ---
// Pairs (T, U), T < U, of triangles of different operands whose boxes overlap, sorted. With
// `clash`, also checks the pairs of one operand exactly and reports the first two triangles that
// meet beyond their shared vertices (or {kNone, kNone}).
// With `self`, pairs of one operand that clash are candidates too (no clash is reported).
// With `trusted` (per operand), pairs of one trusted operand are not checked.
// With `active` (per triangle), only pairs with an active triangle are looked at.
// With `left_out` (per triangle), those triangles have no pairs (settle_in_cores()).
// With `outside`: per triangle, 1 where its box is off every other operand's box (so it lies
// outside all of them), as far as the broad phase saw (empty: not known; it is where every
// operand's own pairs are looked at, or the operands are few).
std::vector<std::array<u32, 2>> candidate_pairs(const Soup& soup, std::array<u32, 2>* clash = nullptr,
                                                bool self = false, const std::vector<char>* trusted = nullptr,
                                                const std::vector<char>* active = nullptr,
                                                const std::vector<char>* left_out = nullptr,
                                                std::vector<char>* outside = nullptr);

// Per triangle: the group (an operand's triangles of one face id, at least `least` of them) it
// belongs to where that group is certified embedded by its projection along one axis (exact:
// every triangle turned one way there, the group's boundary disjoint simple curves of which at
// most one turns that way; see boolean_faces.cpp), else kNone; empty where no group is. No two
// triangles of such a group meet beyond what they share: a planar face of a thousand corners,
// whose triangulation is a fan of slivers whose boxes all meet, needs no pair of it tested.
// Operands `trusted` marks are left out.
std::vector<u32> embedded_groups(const Soup& soup, const std::vector<char>* trusted, std::size_t least = 32);

// True where double arithmetic proves that triangles t and u are apart (so that their exact
// intersection is empty): an axis on which their projections are separated by more than the
// projections' rounding (a dot product of doubles is within 3 units in the last place of
// |v|_1 max|p|; 4 are allowed, on each side). The axes: either triangle's normal, and with
// `edges` the cross products of an edge of each (any vector serves, so its own rounding is
// harmless). Boxes of long thin triangles side by side (a lattice's struts, a cylinder's sides
// against a plate's fan) meet where the triangles do not: the normals settle 60% of the box
// pairs of the 512-sphere lattice and of a truss; the edges a further 18-40% of the lattice's,
// the plate's and the sponge's, where the exact test would go on to compare the cut's ends.
inline bool apart(const Soup& s, u32 ti, u32 ui, bool edges) {
  const auto& T = s.tris[ti];
  const auto& U = s.tris[ui];
  const Vec3 t[3] = {s.verts[T[0]], s.verts[T[1]], s.verts[T[2]]};
  const Vec3 u[3] = {s.verts[U[0]], s.verts[U[1]], s.verts[U[2]]};
  double m = 0;
  for (int i = 0; i < 3; ++i) m = std::max({m, t[i].cwiseAbs().maxCoeff(), u[i].cwiseAbs().maxCoeff()});
  if (!(m > 1e-100 && m < 1e100)) return false;  // (no underflow or overflow in the products)
  const double unit = 4 * std::ldexp(1.0, -53) * m;
  auto separates = [&](const Vec3& v) {
    const double err = unit * v.cwiseAbs().sum();
    if (!(err > 1e-200)) return false;  // (an axis so short that its products could underflow)
    const double a0 = v.dot(t[0]), a1 = v.dot(t[1]), a2 = v.dot(t[2]);
    const double b0 = v.dot(u[0]), b1 = v.dot(u[1]), b2 = v.dot(u[2]);
    const double alo = std::min({a0, a1, a2}), ahi = std::max({a0, a1, a2});
    const double blo = std::min({b0, b1, b2}), bhi = std::max({b0, b1, b2});
    return ahi + 2 * err < blo || bhi + 2 * err < alo;
  };
  if (!edges) return separates((t[1] - t[0]).cross(t[2] - t[0])) || separates((u[1] - u[0]).cross(u[2] - u[0]));
  for (int i = 0; i < 3; ++i) {
    const Vec3 e = t[(i + 1) % 3] - t[i];
    for (int j = 0; j < 3; ++j)
      if (separates(e.cross(u[(j + 1) % 3] - u[j]))) return true;
  }
  return false;
}

// --- the work budget (boolean_budget.cpp) ---
// An estimate of the points where three operands' surfaces cross (each found by the arrangement
// as a crossing of two segments in a triangle, once in each of the three): the triples of
// triangles of three operands whose planes meet, in doubles, at a point inside all three (in the
// lowest one's partners, two of its cut segments crossing strictly inside both). Ordinary
// booleans have few; nearly coincident operands very many, each slow to decide exactly (17 copies
// of a sphere turned by 1 .. 16 degrees: some 700,000, minutes of work). Three operands' triangles
// in one plane count two one's edges crossing inside the third (copies of a box turned by a hair:
// n^3). The count stops past `stop_above`, then scaled up from the share of the pairs looked at.
// `pairs` as candidate_pairs() returns them (sorted, of different operands).
std::size_t candidate_triples(const Soup& soup, const std::vector<std::array<u32, 2>>& pairs,
                              std::size_t stop_above = static_cast<std::size_t>(-1));

// Boxes and the box tree (Bvh): csg/boolean_bvh_impl.h, included at the end of this header.

// --- exact triangle-triangle intersection (boolean_intersect.cpp) ---
struct Segment {
  PointDef a, b;  // end points (before point ids are assigned)
  Plane cut;      // the plane that cuts the triangle along the segment
};
struct PairCut {       // what T ∩ U adds to T's and to U's retriangulation
  std::vector<Segment> segs_t, segs_u;
  std::vector<PointDef> points;  // isolated touching points (in both)
  bool coplanar = false;
};
// T ∩ U into `cut`, cleared first (its arrays keep their room: a caller that reuses one allocates
// nothing per pair).
void intersect_pair(const Points& pts, u32 t, u32 u, PairCut& cut);
PairCut intersect_pair(const Points& pts, u32 t, u32 u);
// A PairCut's lists where they are kept elsewhere (arrange() keeps every pair's in a few flat
// arrays).
struct PairCutView {
  std::span<const Segment> segs_t, segs_u;
  std::span<const PointDef> points;
  bool coplanar = false;
  PairCutView() = default;
  PairCutView(const PairCut& c) : segs_t(c.segs_t), segs_u(c.segs_u), points(c.points), coplanar(c.coplanar) {}
};

// --- interning of the retriangulation's points (boolean_intern.cpp) ---
// What one input triangle's retriangulation gathers from its pairs (point ids).
struct TriWork {
  std::vector<std::array<u32, 2>> segs;
  std::vector<Plane> cuts;  // per segment, the plane that cuts T along it
  std::vector<u32> points;
  std::vector<u32> coplanar;
};
using Works = KeptVector<TriWork>;  // (its block kept for the next run: kernel/memory.h)
// Flat quadrilaterals (boolean_quads.cpp): two cut triangles of one operand and one face id that
// share an edge, lie in one plane and make a strictly convex quadrilateral are retriangulated as
// one (the work of the first holds both; its pieces name it as their source), so their shared
// edge, a diagonal of a face the tessellator split, is no constraint. A cut point strictly inside
// such a diagonal, where in every work that holds it it joins collinear segments and nothing
// else (or, in a coplanar triangle's work, ends only cuts of the diagonal itself, which are then
// erased there), is then no point of the arrangement at all: its segments are joined. (A plane crossing a
// long box face or a cylinder's side cuts each diagonal it meets: two thirds of a Menger sponge's
// points and half a plate's were such points, rounded when output, and merged away afterwards.)
// Works must be canonical (sorted points, unique segments); `fixed` triangles are not grouped.
struct FlatQuads {
  // Per work: the corners (p, b, q, a) of its quadrilateral, in its triangles' orientation, where
  // it holds one (else kNone in [0]); and whether it was merged into its partner's (now empty).
  std::vector<std::array<u32, 4>> quad;
  std::vector<char> absorbed;
  // The groups (their two triangles) whose diagonal's cuts in coplanar triangles' works were
  // erased: those triangles' pieces may cross the diagonal.
  std::vector<std::array<u32, 2>> erased;
  std::size_t groups = 0, dropped = 0;
};
FlatQuads flat_quads(const Points& pts, const std::vector<u32>& touched, Works& work, const std::vector<char>* fixed);
// One id per point: per symbolic definition (canonical: the same planes in any order), or per
// position for a point whose definition fixes all three coordinates (the many definitions of one
// corner of a sponge get one id), where an input vertex at that position keeps its own id.
struct InternRun;
class Interner {
 public:
  explicit Interner(Points& pts);
  ~Interner();
  // Interns every point of `cuts` (per pair of `pairs`) and gathers each cut triangle's work, with
  // the ids a serial pass in pair order gives: new ids numbered in order of first occurrence, a
  // triangle's vertices seeded (by position) at its first cut. The pairs are cut into runs
  // interned in parallel, then joined; the ids do not depend on the number of runs. `touched`:
  // the triangles cut, in order of first cut; work[w] is touched[w]'s, slot[t] its index (kNone).
  // Called once, before any other point is interned.
  void intern_cuts(const std::vector<std::array<u32, 2>>& pairs, const std::vector<PairCutView>& cuts,
                   std::vector<u32>& slot, std::vector<u32>& touched, Works& work);
  // One more point (not thread-safe).
  u32 operator()(const PointDef& raw);

 private:
  u32 find(std::uint64_t h, bool by_position, const PointDef& raw, const Vec3& at);
  const Vec3& position(u32 id) const;
  Points& pts_;
  u32 base_ = 0;                  // the first id made here
  std::vector<InternRun> runs_;   // intern_cuts()'s runs, each key in the first run that has it
  std::vector<std::vector<u32>> map_;  // per run, per point it made: its id
  // The keys interned since (open addressing: (the hash's high 31 bits, 1 where by position) << 32
  // | id, ~0 where empty).
  KeptVector<std::uint64_t> table_;
  std::size_t keys_ = 0;
  KeptVector<Vec3> at_;  // per id made here (from base_): its position, where interned by it
};

// --- retriangulation (boolean_triangulate.cpp) ---
struct Piece {               // an output candidate triangle
  std::array<u32, 3> v;      // point ids, counter-clockwise seen from outside its operand
  u32 tri;                   // its input triangle
};
struct Arrangement {
  std::vector<Piece, NoInit<Piece>> pieces;  // every triangle cut into pieces, uncut ones whole
  // Per input triangle t, the overlapping coplanar triangles (offsets per triangle, empty where
  // none has any: a vector each was 48 MB for two 1M spheres, nearly all empty).
  std::vector<u32> coplanar_from, coplanar_ids;
  std::span<const u32> coplanar(u32 t) const {
    if (coplanar_from.empty()) return {};
    return std::span(coplanar_ids).subspan(coplanar_from[t], coplanar_from[t + 1] - coplanar_from[t]);
  }
  // For the pieces of triangulated triangles, in piece order: the piece, and per edge e (v[e] ->
  // v[e+1]) the other piece of the same input triangle across it, where the edge is inside that
  // triangle and on no cut (so these two are the only pieces on it), else kNone.
  std::vector<std::pair<u32, std::array<u32, 3>>, NoInit<std::pair<u32, std::array<u32, 3>>>> inner;
  std::size_t quads = 0, quad_points = 0;  // flat_quads()' groups and points left out
  std::vector<u32> quad_tris;  // the input triangles retriangulated in those groups
  // Per input triangle (empty: none), the other half of its flat quadrilateral where the cuts of
  // their diagonal were erased from coplanar triangles' works (FlatQuads::erased), else kNone: a
  // piece of such a coplanar triangle may have its centroid on the diagonal, in neither half.
  std::vector<u32> quad_partner;
};
struct Settlement;
// With `quads`, cut triangles are grouped into flat quadrilaterals (flat_quads), but for the
// triangles of cuts `settled` left out (classify asks about those per source triangle). Not for
// a mesh classified against itself (classify's `self`), whose rays must not meet the partner.
Arrangement arrange(Points& pts, const std::vector<std::array<u32, 2>>& pairs, bool quads = false,
                    const Settlement* settled = nullptr);

// --- settling (boolean_settle.cpp) ---
// The cuts left out of the arrangement because they lie strictly inside an operand whose inside
// drops every point of the other operands there (any other operand of a union, a subtrahend of a
// difference): no such cut reaches the result's boundary.
struct SettleCores;
struct Settlement {
  // Per triangle (empty: none), whether it lies strictly inside such an operand, met by none of
  // its triangles: every pair of it left out.
  std::vector<char> triangles;
  // The operands' cores, made once for both kinds of settling (boolean_settle.cpp).
  std::shared_ptr<const SettleCores> cores;
  // Pairs of unsettled triangles whose cut lies in the core of such an operand (sorted).
  std::vector<std::array<u32, 2>> pairs;
  // Per triangle (empty: not known), 1 where it lies outside every other operand (its box off
  // theirs: candidate_pairs' `outside`). Such a triangle is in no pair; classify() keeps or drops
  // it by its operand alone.
  std::vector<char> outside;
  std::size_t settled_triangles() const { return static_cast<std::size_t>(std::count(triangles.begin(), triangles.end(), 1)); }
  bool empty() const { return triangles.empty() && pairs.empty(); }
  // Whether the cut of triangles t and u was left out.
  bool left_out(u32 t, u32 u) const {
    if (!triangles.empty() && (triangles[t] || triangles[u])) return true;
    return std::binary_search(pairs.begin(), pairs.end(), std::array<u32, 2>{std::min(t, u), std::max(t, u)});
  }
};
// Before the broad phase: the triangles of operands in `checked` (whose own pairs need no look)
// that lie in the core of an operand settling them, all three vertices (s.triangles, empty:
// none). Such a triangle is settled without a pair (a truss's strut caps at each node's centre,
// inside the node's ball: two thirds of its candidate pairs); the broad phase leaves it out.
Settlement settle_in_cores(const Soup& soup, BooleanOp op, const std::vector<char>& checked);
// Then the settled triangles of a boolean's candidate pairs; their pairs are removed from `pairs`
// (the rest keep their order).
void settle(const Soup& soup, std::vector<std::array<u32, 2>>& pairs, BooleanOp op, Settlement& s);
// Then the pairs in cores (s.pairs), removed from `pairs` as well. Run after the work budget's
// count: on operands that nearly coincide (17 copies of a sphere turned by a degree each, 4.4M
// pairs, every core in every cell) the cores' look took 1.1 s where the count refuses in 0.1 s.
void settle_pairs(const Soup& soup, std::vector<std::array<u32, 2>>& pairs, BooleanOp op, Settlement& s);

// --- classification (boolean_classify.cpp) ---
// For each piece: 0 drop, +1 keep, -1 keep reversed.
// With `self`, the soup is one mesh that may cross itself, and the result is the region where its
// winding number is at least 1 (op is not used).
// `adj` (per soup triangle and edge, the triangle across it where known, else kNone), if given,
// joins whole triangles into patches without sorting their edges, as arr.inner joins the pieces
// of one cut triangle across edges on no cut; `piece_adj` (if given) then
// receives per piece and edge the piece so joined across it (the only other piece on that edge,
// in the same patch), else kNone: adj_piece() of the entry, and adj_edge() the edge of that
// piece it is (its edge f runs from v[f] to v[f + 1], the reverse of this one).
// `settled` (settle()'s, if given): the pieces of settled triangles are dropped, and so is a piece
// whose centroid lies on a triangle whose cut with the piece's own triangle was left out (the
// centroid is on that cut, strictly inside the operand that settled it).
constexpr u32 kAdjPieceBits = 30;
inline u32 adj_entry(u32 piece, u32 edge) { return piece | edge << kAdjPieceBits; }
inline u32 adj_piece(u32 entry) { return entry & ((1u << kAdjPieceBits) - 1); }
inline u32 adj_edge(u32 entry) { return entry >> kAdjPieceBits; }
std::vector<std::int8_t> classify(const Points& pts, const Arrangement& arr, BooleanOp op, bool self = false,
                                  const std::vector<std::array<u32, 3>>* adj = nullptr,
                                  std::vector<std::array<u32, 3>>* piece_adj = nullptr,
                                  const Settlement* settled = nullptr);

// --- output and rounding (boolean_output.cpp) ---
// `collapses` (if given) receives the number of edges the rounding repair collapsed or split,
// `flat_shells` (if given) the number of shells thinner than rounding it left out.
// Where rounding leaves crossings that collapsing short edges cannot remove: with `unresolved`,
// *unresolved is set and the rounded mesh returned as it is; without, an error is thrown.
// `crossing` (if given) receives the triangles of the returned mesh that still cross another:
// every crossing pair has one of them.
// `piece_adj` (classify's, if given) pairs the edges it names without sorting them.
// With `snap`, the repair may also move rounded vertices by an ulp (snap_rounded): only in a
// boolean's own rounding, not in a re-resolution's. There, on sheets that nearly coincide, moves
// that mended some crossings let a moved result's resolution succeed, and the next union of the
// tree then spent minutes in re-resolutions before failing in its own right.
// Collapses r's edges shorter than tau, shortest first, where the mesh stays closed and manifold
// (a fold whose two triangles come to lie on each other goes); triangles keep their provenance.
// Positions no triangle uses are dropped. Returns the number of collapses.
std::size_t collapse_short_edges(BooleanResult& r, double tau);
// The triangles `ids` of m (in that order) with the positions they use.
Mesh sub_mesh(const Mesh& m, const std::vector<u32>& ids);
// The orientation of mesh triangle t in the projection along axis k (exact; boolean_round.cpp).
int projected_orientation(const Mesh& m, std::size_t t, int k);
// Collapses the cut vertices that lie inside one flat region or on one straight crease of the
// kept pieces (tris, with their sources, flips and pieces), where the surface stays the same set
// of points and every triangle keeps its exact orientation (boolean_merge.cpp). Returns the
// number of vertices removed.
std::size_t merge_flat(const Points& pts, std::vector<std::array<u32, 3>>& tris, std::vector<u32>& src,
                       std::vector<char>& flipped, std::vector<u32>& piece);
// What the rounding check knows of each output triangle besides the mesh: its source triangle in
// the soup and the orientation its exact piece has in its source's projection.
struct Rounding {
  const Soup* soup;
  std::vector<char> moved;          // per vertex: its position was rounded (not an input vertex)
  std::vector<u32> src;             // per triangle: soup triangle
  std::vector<std::int8_t> sign;    // per triangle: exact orientation in the projection along k(src)
  std::vector<char> recheck;        // per triangle: to be checked (it has changed since the last check)
  std::size_t collapses = 0;
  std::vector<char> altered;        // per vertex: the repair changed its triangles (empty: none did)
};
// The triangles to recheck (rd.recheck) that are degenerate, turned over in their source's
// projection, or meet another beyond their shared vertices, and the triangles they meet (exact,
// on the rounded doubles) (boolean_round.cpp).
std::vector<u32> rounding_defects(const Mesh& m, const Rounding& rd);
// Mends rounding defects where it can (the bad ones left in `left`); true when none is left.
// With `flat_shells`: where the first check finds defects, the shells thinner than rounding are
// left out first (drop_flat_shells), their number added there.
bool repair_rounding(BooleanResult& r, Rounding& rd, std::vector<u32>* left, bool snap, std::size_t* flat_shells = nullptr);
// Before the repair: edges 8-16 ulps long with a rounded end (cut points apart only by the inputs'
// rounding) collapse into their other end where the link condition holds, orientations in the
// sources' projections stay, and that end lies within an ulp of every joined triangle's source
// plane; the changed triangles get rd.recheck. The result as it was goes to *saved, *saved_rd (the
// repair's fallback). Returns the number collapsed. Every triangle with a rounded vertex must
// have rd.recheck set (only those are looked at).
std::size_t collapse_ulp_edges(BooleanResult& r, Rounding& rd, BooleanResult* saved, Rounding* saved_rd);
// Leaves out the shells thinner than rounding; returns how many.
std::size_t drop_flat_shells(BooleanResult& r, Rounding& rd);
// A re-resolution takes the rounded result as it is: where the repair had collapsed a vertex
// across a flat edge and turned a triangle over in its plane (sheets a few ulps apart, one
// facing each way), the triangle can come out bounding the result the other way round from its
// source (the sheet facing that way is another operand's). Such triangles (exact orientation in
// their source's projection) are named after a source triangle that faces their way and whose
// plane they lie in (within a billionth of the model's size), one holding their centroid where
// there is one. `soup` is the boolean's own (the operands as given).
std::size_t rename_reversed(BooleanResult& r, const Soup& soup, BooleanOp op);
BooleanResult assemble(const Points& pts, const Arrangement& arr, const std::vector<std::int8_t>& keep,
                       std::size_t* collapses = nullptr, bool* unresolved = nullptr,
                       std::vector<u32>* crossing = nullptr,
                       const std::vector<std::array<u32, 3>>* piece_adj = nullptr, bool snap = false,
                       std::size_t* flat_shells = nullptr);

// --- moving rounded vertices (boolean_snap.cpp) ---
// Where collapsing short edges cannot mend the triangles `bad` of m (rounding turned them over in
// their source's projection or made them cross another), each of their vertices marked `movable`
// whose own triangles are not sound may move to a double next to it (an ulp or none in each
// coordinate; the nearest first) where every triangle around it has its orientation `sign` in the
// projection of its soup triangle `src` and meets no triangle near it beyond what they share
// (exact checks). The triangles of a moved vertex are marked in `recheck`. Returns the number of
// vertices moved (none where the bad triangles are too many for moves of an ulp to mend).
std::size_t snap_rounded(Mesh& m, const Soup& soup, const std::vector<u32>& src, const std::vector<std::int8_t>& sign,
                         const std::vector<char>& movable, const std::vector<u32>& bad, std::vector<char>& recheck);

}  // namespace wedge::boolean_detail

#include "csg/boolean_stars_impl.h"  // corner lists, star certificates, the radial check

// The box tree needs the soup above; it has a header of its own (boolean_broad.cpp builds it).
#include "csg/boolean_bvh_impl.h"
