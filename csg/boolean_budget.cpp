// The work budget of an n-ary boolean (candidate_triples): the points where three operands'
// surfaces would cross, counted from the candidate pairs before the arrangement, so that
// operands that nearly coincide are refused in a fraction of a second instead of minutes of
// exact work. (Split from the broad phase, boolean_broad.cpp, whose pairs it counts.)
#include <algorithm>
#include <cmath>

#include "csg/boolean_impl.h"
#include "kernel/parallel.h"

namespace wedge::boolean_detail {

namespace {

// How triangles t and u lie to each other's planes, as double arithmetic sees it: 1 each crosses
// the other's plane (vertices strictly on both sides: the three pairs of a crossing point inside
// three triangles all do), 3 both lie in one plane, 2 neither. ht gets the heights of t's vertices
// over u's plane, hu those of u's over t's (each times its normal's length; 0 where within the
// tolerance the kind was judged by).
std::uint8_t pair_kind(const Soup& s, const std::vector<std::array<double, 4>>& plane, u32 t, u32 u, double ht[3],
                       double hu[3]) {
  auto side = [&](u32 a, u32 b, double h[3]) {  // 1 across, 3 within a's plane, 2 otherwise
    const auto& A = s.tris[a];
    const auto& B = s.tris[b];
    const Vec3 n(plane[a][0], plane[a][1], plane[a][2]);
    const Vec3& o = s.verts[A[0]];
    double lo = 0, hi = 0, size = 0;
    for (int c = 0; c < 3; ++c) {
      const Vec3 d = s.verts[B[c]] - o;
      h[c] = n.dot(d);
      lo = std::min(lo, h[c]), hi = std::max(hi, h[c]);
      size = std::max(size, d.norm());
    }
    const double eps = 1e-12 * n.norm() * size;
    for (int c = 0; c < 3; ++c)
      if (std::abs(h[c]) <= eps) h[c] = 0;
    return lo < -eps && hi > eps ? 1 : lo >= -eps && hi <= eps ? 3 : 2;
  };
  const int a = side(t, u, hu);
  if (a == 2) return 2;
  return static_cast<std::uint8_t>(a == side(u, t, ht) ? a : 2);
}

// The two points where triangle t, its vertices at heights h over a plane (some above, some
// below), meets that plane: a vertex on it, or a point on an edge across it.
void plane_cut(const Soup& s, u32 t, const double h[3], Vec3 out[2]) {
  int n = 0;
  const auto& T = s.tris[t];
  for (int e = 0; e < 3 && n < 2; ++e) {
    const double ha = h[e], hb = h[(e + 1) % 3];
    const Vec3& a = s.verts[T[e]];
    if (ha == 0) out[n++] = a;
    else if ((ha < 0 && hb > 0) || (ha > 0 && hb < 0)) out[n++] = a + (s.verts[T[(e + 1) % 3]] - a) * (ha / (ha - hb));
  }
  if (n < 2) out[1] = out[0];
}

// The segment where triangles t and u (kind 1) meet, in doubles: the pieces of their planes'
// line in each triangle, overlapped along the line's main axis; false where they do not overlap.
bool meet_segment(const Soup& s, const std::vector<std::array<double, 4>>& plane, u32 t, u32 u, const double ht[3],
                  const double hu[3], Vec3& p, Vec3& q) {
  Vec3 a[2], b[2];
  plane_cut(s, t, ht, a);
  plane_cut(s, u, hu, b);
  const Vec3 nt(plane[t][0], plane[t][1], plane[t][2]), nu(plane[u][0], plane[u][1], plane[u][2]);
  const Vec3 dir = nt.cross(nu);
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(dir[i]) > std::abs(dir[k])) k = i;
  if (a[0][k] > a[1][k]) std::swap(a[0], a[1]);
  if (b[0][k] > b[1][k]) std::swap(b[0], b[1]);
  p = a[0][k] >= b[0][k] ? a[0] : b[0];
  q = a[1][k] <= b[1][k] ? a[1] : b[1];
  return p[k] < q[k];
}

// For three triangles in one plane: the crossings of two triangles' edges strictly inside the
// third, each of the three in turn (the arrangement of each triangle holds its own). Copies of a
// face turned by a hair cross everywhere: n such copies make n^3 of these.
std::size_t coplanar_crossings(const Soup& s, u32 t, u32 u, u32 w) {
  const u32 ids[3] = {t, u, w};
  const auto& T = s.tris[t];
  const Vec3 n = (s.verts[T[1]] - s.verts[T[0]]).cross(s.verts[T[2]] - s.verts[T[0]]);
  int k = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) > std::abs(n[k])) k = i;
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  Vec2 p[3][3];
  double size = 0;
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) {
      const Vec3& v = s.verts[s.tris[ids[a]][c]];
      p[a][c] = Vec2(v[i], v[j]);
      size = std::max(size, p[a][c].cwiseAbs().maxCoeff());
    }
  const double eps = 1e-12 * size * size;
  auto cross2 = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::size_t count = 0;
  for (int h = 0; h < 3; ++h) {
    const int x = (h + 1) % 3, y = (h + 2) % 3;
    const double orient = cross2(p[h][0], p[h][1], p[h][2]) > 0 ? 1 : -1;
    for (int e = 0; e < 3; ++e)
      for (int f = 0; f < 3; ++f) {
        const Vec2 &a = p[x][e], &b = p[x][(e + 1) % 3], &c = p[y][f], &d = p[y][(f + 1) % 3];
        const double ca = cross2(c, d, a), cb = cross2(c, d, b), cc = cross2(a, b, c), cd = cross2(a, b, d);
        if (!((ca > eps && cb < -eps) || (ca < -eps && cb > eps))) continue;
        if (!((cc > eps && cd < -eps) || (cc < -eps && cd > eps))) continue;
        const Vec2 q = a + (b - a) * (ca / (ca - cb));
        bool inside = true;
        for (int g = 0; g < 3 && inside; ++g) inside = orient * cross2(p[h][g], p[h][(g + 1) % 3], q) > eps;
        count += inside;
      }
  }
  return count;
}

// Calls f(a, b) once for each pair of boxes (x0, x1, y0, y1) that overlap. Few boxes, or boxes
// that a grid would hold many times over: a sweep along x (`boxes` is sorted by x0). Many (a
// plate's face crossed by 400 cylinders' sides: 12,800 segments in one triangle, 20 holes in
// every column): a grid of about one box per cell, each pair met in the cell of its overlap's
// low corner alone.
template <class Box, class F>
void each_overlap(std::vector<Box>& boxes, F&& f) {
  const std::size_t n = boxes.size();
  if (n < 2) return;
  auto overlap = [](const Box& A, const Box& B) { return !(B.x0 > A.x1 || B.x1 < A.x0 || B.y0 > A.y1 || B.y1 < A.y0); };
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const Box& g : boxes) x0 = std::min(x0, g.x0), y0 = std::min(y0, g.y0), x1 = std::max(x1, g.x1), y1 = std::max(y1, g.y1);
  const int g = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(n))), 1, 1024);
  const double ix = x1 > x0 ? g / (x1 - x0) : 0, iy = y1 > y0 ? g / (y1 - y0) : 0;
  auto cx = [&](double x) { return std::clamp(static_cast<int>((x - x0) * ix), 0, g - 1); };
  auto cy = [&](double y) { return std::clamp(static_cast<int>((y - y0) * iy), 0, g - 1); };
  std::size_t spans = 0;
  if (n > 64)
    for (const Box& a : boxes) spans += static_cast<std::size_t>(cx(a.x1) - cx(a.x0) + 1) * (cy(a.y1) - cy(a.y0) + 1);
  if (n <= 64 || spans > 8 * n) {
    std::sort(boxes.begin(), boxes.end(), [](const Box& a, const Box& b) { return a.x0 < b.x0; });
    for (std::size_t a = 0; a < n; ++a)
      for (std::size_t b = a + 1; b < n && boxes[b].x0 <= boxes[a].x1; ++b)
        if (overlap(boxes[a], boxes[b])) f(boxes[a], boxes[b]);
    return;
  }
  thread_local std::vector<u32> start, item;
  start.assign(static_cast<std::size_t>(g) * g + 1, 0);
  auto each_cell = [&](const Box& a, auto&& h) {
    for (int x = cx(a.x0); x <= cx(a.x1); ++x)
      for (int y = cy(a.y0); y <= cy(a.y1); ++y) h(static_cast<std::size_t>(x) * g + y);
  };
  for (const Box& a : boxes) each_cell(a, [&](std::size_t cell) { ++start[cell + 1]; });
  for (std::size_t k = 0; k + 1 < start.size(); ++k) start[k + 1] += start[k];
  item.resize(start.back());
  for (u32 a = 0; a < n; ++a) each_cell(boxes[a], [&](std::size_t cell) { item[start[cell]++] = a; });
  for (std::size_t k = start.size() - 1; k > 0; --k) start[k] = start[k - 1];
  start[0] = 0;
  for (std::size_t cell = 0; cell + 1 < start.size(); ++cell)
    for (u32 a = start[cell]; a < start[cell + 1]; ++a)
      for (u32 b = a + 1; b < start[cell + 1]; ++b) {
        const Box &A = boxes[item[a]], &B = boxes[item[b]];
        if (!overlap(A, B)) continue;
        if (static_cast<std::size_t>(cx(std::max(A.x0, B.x0))) * g + cy(std::max(A.y0, B.y0)) == cell) f(A, B);
      }
}

}  // namespace

std::size_t candidate_triples(const Soup& soup, const std::vector<std::array<u32, 2>>& pairs, std::size_t stop_above) {
  // N+(t): the partners u > t of t, pairs[off[t] .. off[t + 1])[1], ascending (pairs are sorted).
  const std::size_t nt = soup.tris.size(), np = pairs.size();
  std::vector<std::size_t> off(nt + 1, 0);
  for (const auto& p : pairs) ++off[p[0] + 1];
  for (std::size_t t = 0; t < nt; ++t) off[t + 1] += off[t];
  // Each triangle's plane n . x = d, made once: a triangle of a truss's node is in hundreds of
  // pairs.
  std::vector<std::array<double, 4>> plane(nt);
  parallel_for(0, nt, [&](std::size_t t) {
    const auto& T = soup.tris[t];
    const Vec3 n = (soup.verts[T[1]] - soup.verts[T[0]]).cross(soup.verts[T[2]] - soup.verts[T[0]]);
    plane[t] = {n.x(), n.y(), n.z(), n.dot(soup.verts[T[0]])};
  });
  // Per pair, how its triangles lie (pair_kind; 0: not looked at yet), made where first needed.
  std::vector<std::atomic<std::uint8_t>> kinds(np);
  auto kind_at = [&](std::size_t i, double ht[3], double hu[3]) {
    const std::uint8_t k = pair_kind(soup, plane, pairs[i][0], pairs[i][1], ht, hu);
    kinds[i].store(k, std::memory_order_relaxed);
    return k;
  };
  // Blocks of about kBlock pairs (each triangle's list whole, in the block where it starts), in a
  // shuffled order, so that a count stopped early (above stop_above) scales up to an estimate of
  // the whole.
  constexpr std::size_t kBlock = 1024, kPrime = 1000003;
  auto count_blocks = [&](std::size_t n, std::size_t stop, auto&& block) {
    const std::size_t blocks = (n + kBlock - 1) / kBlock;
    std::atomic<std::size_t> found{0}, done{0};
    parallel_for(0, blocks, [&](std::size_t k) {
      if (found.load(std::memory_order_relaxed) > stop) return;
      soup.poll();
      const std::size_t b = blocks % kPrime != 0 ? k * kPrime % blocks : k;
      const auto [c, d] = block(b * kBlock, std::min(n, (b + 1) * kBlock));
      found += c;
      done += d;
    });
    const std::size_t f = found.load(), seen = done.load();
    if (seen == n || seen == 0) return f;
    return static_cast<std::size_t>(double(f) * double(n) / double(seen));
  };
  // The first pair of the first triangle whose list starts at or after pair i.
  auto list_start = [&](std::size_t i) {
    if (i >= np) return np;
    const u32 t = pairs[i][0];
    return off[t] == i ? i : off[t + 1];
  };
  // Triangles that cross each other's planes: a triple t < u < w crosses (the planes meet at a
  // point inside all three) exactly where the segments t n u and t n w cross inside t, counted in
  // t's list alone, in t's projection along its normal's main axis. Only partners of t whose
  // operand's partners' projected boxes overlap another operand's can be in a triple (a plate's
  // face is crossed by every cylinder's sides, each hole apart from the others): their kinds and
  // segments are made, and a crossing counts where each segment's ends lie off the other's line by more
  // than 1e-9 of their length (segments that meet end to end, as the Menger sponge's tunnels do,
  // do not count).
  struct Box {
    double x0, x1, y0, y1;
    std::int32_t op;
    u32 j;  // the run
  };
  struct Seg {
    double x0, x1, y0, y1;  // the box
    std::int32_t op;
    Vec2 p, q;
  };
  const std::size_t crossing = count_blocks(np, stop_above, [&](std::size_t lo, std::size_t hi) {
    thread_local std::vector<Box> boxes;
    thread_local std::vector<Seg> segs;
    thread_local std::vector<char> need;
    std::size_t c = 0, d = 0;
    auto cross2 = [](const Vec2& o, const Vec2& a, const Vec2& b) {
      return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
    };
    for (std::size_t i = list_start(lo); i < hi; i = off[pairs[i][0] + 1]) {
      const u32 t = pairs[i][0];
      const std::size_t end = off[t + 1];
      d += end - i;
      if (end - i < 2) continue;
      const Vec3 n(plane[t][0], plane[t][1], plane[t][2]);
      int k = 0;
      for (int a = 1; a < 3; ++a)
        if (std::abs(n[a]) > std::abs(n[k])) k = a;
      const int x = (k + 1) % 3, y = (k + 2) % 3;
      // The partners of one operand are a run of the list (an operand's triangles are a run of
      // the soup's): one box per run, the union of its triangles' boxes in t's projection.
      boxes.clear();
      for (std::size_t j = i; j < end;) {
        const std::int32_t op = soup.operand[pairs[j][1]];
        Box b{INFINITY, -INFINITY, INFINITY, -INFINITY, op, static_cast<u32>(boxes.size())};
        for (; j < end && soup.operand[pairs[j][1]] == op; ++j) {
          double blo[3], bhi[3];
          triangle_box(soup, pairs[j][1], blo, bhi);
          b.x0 = std::min(b.x0, blo[x]), b.x1 = std::max(b.x1, bhi[x]);
          b.y0 = std::min(b.y0, blo[y]), b.y1 = std::max(b.y1, bhi[y]);
        }
        boxes.push_back(b);
      }
      if (boxes.size() < 2) continue;
      need.assign(boxes.size(), 0);
      each_overlap(boxes, [&](const Box& a, const Box& b) { need[a.j] = need[b.j] = 1; });
      std::size_t run = 0;
      segs.clear();
      for (std::size_t j = i; j < end; ++j) {
        if (j > i && soup.operand[pairs[j][1]] != soup.operand[pairs[j - 1][1]]) ++run;
        if (!need[run]) continue;
        double ht[3], hu[3];
        Vec3 p, q;
        if (kind_at(j, ht, hu) != 1 || !meet_segment(soup, plane, t, pairs[j][1], ht, hu, p, q)) continue;
        const Vec2 p2(p[x], p[y]), q2(q[x], q[y]);
        segs.push_back({std::min(p2.x(), q2.x()), std::max(p2.x(), q2.x()), std::min(p2.y(), q2.y()),
                        std::max(p2.y(), q2.y()), soup.operand[pairs[j][1]], p2, q2});
      }
      each_overlap(segs, [&](const Seg& A, const Seg& B) {
        if (A.op == B.op) return;
        const double eps = 1e-9 * (A.q - A.p).norm() * (B.q - B.p).norm();
        const double o1 = cross2(A.p, A.q, B.p), o2 = cross2(A.p, A.q, B.q);
        if (!((o1 > eps && o2 < -eps) || (o1 < -eps && o2 > eps))) return;
        const double o3 = cross2(B.p, B.q, A.p), o4 = cross2(B.p, B.q, A.q);
        c += (o3 > eps && o4 < -eps) || (o3 < -eps && o4 > eps);
      });
    }
    return std::pair<std::size_t, std::size_t>{c, d};
  });
  if (crossing > stop_above) return crossing;
  // Triangles in one plane: each triple t < u < w of coplanar pairs, from (t, u) and (t, w) both
  // in t's list (looked at above, as t's partners of other operands overlapping there), and
  // (u, w) in u's list (its kind made here where not yet).
  std::vector<std::size_t> flat;
  for (std::size_t i = 0; i < np; ++i)
    if (kinds[i].load(std::memory_order_relaxed) == 3) flat.push_back(i);
  if (flat.size() < 2) return crossing;
  const std::size_t coplanar = count_blocks(flat.size(), stop_above - crossing, [&](std::size_t lo, std::size_t hi) {
    std::size_t c = 0;
    for (std::size_t a = lo; a < hi; ++a) {
      const std::size_t i = flat[a];
      const u32 t = pairs[i][0], u = pairs[i][1];
      for (std::size_t b = a + 1; b < flat.size() && pairs[flat[b]][0] == t; ++b) {
        const u32 w = pairs[flat[b]][1];
        if (soup.operand[w] == soup.operand[u]) continue;
        const auto at = std::lower_bound(pairs.begin() + static_cast<std::ptrdiff_t>(off[u]),
                                         pairs.begin() + static_cast<std::ptrdiff_t>(off[u + 1]), w,
                                         [](const std::array<u32, 2>& p, u32 x) { return p[1] < x; });
        if (at == pairs.begin() + static_cast<std::ptrdiff_t>(off[u + 1]) || (*at)[1] != w) continue;
        const std::size_t uw = static_cast<std::size_t>(at - pairs.begin());
        std::uint8_t k = kinds[uw].load(std::memory_order_relaxed);
        double ht[3], hu[3];
        if (k == 0) k = kind_at(uw, ht, hu);
        if (k == 3) c += coplanar_crossings(soup, t, u, w);
      }
    }
    return std::pair<std::size_t, std::size_t>{c, hi - lo};
  });
  return crossing + coplanar;
}

}  // namespace wedge::boolean_detail
