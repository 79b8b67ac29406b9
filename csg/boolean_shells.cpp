// overlapping_shells: an operand whose shells overlap without any two triangles crossing (a shell
// inside another that faces the same way, or a shell turned inward outside every other). The
// pairwise checks cannot see it, and the engine, taking such an operand for a solid, counted the
// overlap twice (a box holding a smaller box: a union of volume 1008 for the 1000 of the
// solid) or failed with an internal error (its difference: "the result has an open edge").
//
// A set of closed shells bounds a solid where its winding number is 0 or 1 everywhere. Shells
// that do not cross each other (checked before) and touch only at vertices: each shell's surface
// off the vertices it shares is connected and lies wholly inside or wholly outside each other
// shell, so one vertex w of its own says where it lies. There the winding number of the others,
// W, must be 0 beside an outward shell (its solid side then has 1) and 1 beside an inward one
// (its hollow side then has 0). W is counted exactly along a segment from w to a point beyond
// the shells that may hold it (those whose box holds w): +1 where it leaves a shell's solid side,
// -1 where it enters, a segment through an edge or a vertex thrown away for another direction.
#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "csg/boolean_impl.h"
#include "csg/membership.h"
#include "kernel/predicates.h"

namespace wedge::boolean_detail {

namespace {

// Directions for the segments (none along an axis or a diagonal: boxes' faces and edges).
const std::array<Vec3, 6> kDirections = {Vec3(0.8630173, 0.3841259, 0.3280961), Vec3(-0.2894213, 0.9012347, 0.3227311),
                                         Vec3(0.1784529, -0.4410927, 0.8794353), Vec3(-0.7036117, -0.5148273, 0.4895519),
                                         Vec3(0.4417231, 0.7703391, -0.4598227), Vec3(-0.3322709, -0.2716559, -0.9032281)};

// The winding number at w of the triangles `tris` (closed shells) along segment w -> far, or 2^30
// where the segment passes through an edge or a vertex of one, or lies in its plane where it
// meets it.
constexpr int kAmbiguous = 1 << 30;
int winding_along(const Soup& s, const std::vector<u32>& tris, const Vec3& w, const Vec3& far) {
  int wn = 0;
  for (u32 t : tris) {
    const std::optional<int> c = segment_crossing(w, far, s.verts[s.tris[t][0]], s.verts[s.tris[t][1]], s.verts[s.tris[t][2]]);
    if (!c) return kAmbiguous;
    wn += *c;
  }
  return wn;
}

}  // namespace

std::string overlapping_shells(const Soup& s, const std::vector<u32>& first, std::int32_t o) {
  const u32 lo = first[static_cast<std::size_t>(o)], hi = first[static_cast<std::size_t>(o) + 1];
  const std::size_t n = hi - lo;
  if (n < 8) return "";  // (two shells need eight triangles)
  // The shells: triangles joined across edges of exactly two triangles. Where an edge has more
  // (shells that touch along it), the edge checks decide (folded_edges): not looked at here.
  struct Rec {
    std::uint64_t key;
    u32 t;
  };
  std::vector<Rec> rec(3 * n);
  for (u32 t = lo; t < hi; ++t)
    for (int k = 0; k < 3; ++k) {
      const u32 a = s.tris[t][k], b = s.tris[t][(k + 1) % 3];
      rec[3 * (t - lo) + k] = {static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b), t - lo};
    }
  std::sort(rec.begin(), rec.end(), [](const Rec& x, const Rec& y) { return x.key < y.key || (x.key == y.key && x.t < y.t); });
  std::vector<u32> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](u32 x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t i = 0; i < rec.size();) {
    std::size_t j = i;
    while (j < rec.size() && rec[j].key == rec[i].key) ++j;
    if (j - i != 2) return "";
    const u32 x = root(rec[i].t), y = root(rec[i + 1].t);
    if (x != y) parent[std::max(x, y)] = std::min(x, y);
    i = j;
  }
  // The shells numbered in the order of their first triangles; their triangles, boxes, vertices.
  std::vector<u32> shell_of(n), id(n, kNone);
  // (Shell j's triangles: tris[from[j] .. from[j + 1]), by a counting sort.)
  std::size_t shells = 0;
  for (u32 t = 0; t < n; ++t) {
    const u32 r = root(t);
    if (id[r] == kNone) id[r] = static_cast<u32>(shells++);
    shell_of[t] = id[r];
  }
  if (shells < 2) return "";
  std::vector<u32> from(shells + 1, 0), tris(n);
  for (u32 t = 0; t < n; ++t) ++from[shell_of[t] + 1];
  for (std::size_t j = 0; j < shells; ++j) from[j + 1] += from[j];
  {
    std::vector<u32> at(from.begin(), from.end() - 1);
    for (u32 t = 0; t < n; ++t) tris[at[shell_of[t]]++] = lo + t;
  }
  auto shell = [&](std::size_t j) { return std::span<const u32>(tris.data() + from[j], from[j + 1] - from[j]); };
  std::vector<std::array<double, 6>> box(shells, {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY});
  // Per vertex of the operand (soup ids from vmin to vmax: an operand's own are numbered together,
  // those it shares with an earlier operand are lower), its shell, or kNone - 1 where shells
  // share it.
  u32 vmin = kNone, vmax = 0;
  for (u32 t = lo; t < hi; ++t)
    for (u32 v : s.tris[t]) vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  auto index = [&](u32 v) { return static_cast<std::size_t>(v - vmin); };
  const std::size_t nv = static_cast<std::size_t>(vmax - vmin) + 1;
  std::vector<u32> owner(nv, kNone);
  for (u32 t = 0; t < n; ++t)
    for (u32 v : s.tris[lo + t]) {
      const u32 sh = shell_of[t];
      u32& ov = owner[index(v)];
      ov = ov == kNone || ov == sh ? sh : kNone - 1;
      for (int a = 0; a < 3; ++a) {
        box[sh][a] = std::min(box[sh][a], s.verts[v][a]);
        box[sh][a + 3] = std::max(box[sh][a + 3], s.verts[v][a]);
      }
    }
  // The shells whose box may hold a point: a grid over the operand's box (about a shell a cell),
  // each shell listed in the cells its box meets; a shell over more than 64 cells in a list of
  // its own, looked at for every point (the outer shell of a part with many hollows).
  double glo[3] = {INFINITY, INFINITY, INFINITY}, ghi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const auto& b : box)
    for (int a = 0; a < 3; ++a) glo[a] = std::min(glo[a], b[a]), ghi[a] = std::max(ghi[a], b[a + 3]);
  const int g = static_cast<int>(std::clamp(std::cbrt(static_cast<double>(shells)), 1.0, 64.0));
  auto cell = [&](double x, int a) {
    const double f = ghi[a] > glo[a] ? (x - glo[a]) / (ghi[a] - glo[a]) * g : 0;
    return f <= 0 ? 0 : f >= g - 1 ? g - 1 : static_cast<int>(f);
  };
  auto range = [&](std::size_t i, int r[6]) {
    std::size_t cells = 1;
    for (int a = 0; a < 3; ++a) {
      r[a] = cell(box[i][a], a);
      r[a + 3] = cell(box[i][a + 3], a);
      cells *= static_cast<std::size_t>(r[a + 3] - r[a] + 1);
    }
    return cells;
  };
  const std::size_t ncells = static_cast<std::size_t>(g) * g * g;
  std::vector<u32> big, start(ncells + 1, 0), listed;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<u32> at(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < shells; ++i) {
      int r[6];
      if (range(i, r) > 64) {
        if (pass == 0) big.push_back(static_cast<u32>(i));
        continue;
      }
      for (int x = r[0]; x <= r[3]; ++x)
        for (int y = r[1]; y <= r[4]; ++y)
          for (int z = r[2]; z <= r[5]; ++z) {
            const std::size_t c = (static_cast<std::size_t>(x) * g + y) * g + z;
            if (pass == 0) ++start[c + 1];
            else listed[at[c]++] = static_cast<u32>(i);
          }
    }
    if (pass == 0) {
      for (std::size_t c = 0; c < ncells; ++c) start[c + 1] += start[c];
      listed.resize(start[ncells]);
    }
  }
  std::vector<Point3> pos;
  std::vector<std::array<std::uint32_t, 3>> tri;
  std::vector<u32> local(nv, kNone);
  for (std::size_t j = 0; j < shells; ++j) {
    s.poll();
    u32 w = kNone;
    for (u32 t : shell(j))
      for (u32 v : s.tris[t])
        if (w == kNone && owner[index(v)] == j) w = v;
    if (w == kNone) continue;  // every vertex shared: nothing of its own to look at
    const Vec3& p = s.verts[w];
    std::vector<u32> around;  // the other shells' triangles whose shell's box holds p
    double reach = 0;
    const std::size_t c = (static_cast<std::size_t>(cell(p[0], 0)) * g + cell(p[1], 1)) * g + cell(p[2], 2);
    std::vector<u32> near(listed.begin() + start[c], listed.begin() + start[c + 1]);
    near.insert(near.end(), big.begin(), big.end());
    std::sort(near.begin(), near.end());  // (the shells in order: the sum the same whatever the grid)
    for (const std::size_t i : near) {
      if (i == j) continue;
      bool in = true;
      for (int a = 0; a < 3; ++a) in = in && box[i][a] <= p[a] && p[a] <= box[i][a + 3];
      if (!in) continue;
      around.insert(around.end(), shell(i).begin(), shell(i).end());
      for (int a = 0; a < 3; ++a) reach = std::max({reach, p[a] - box[i][a], box[i][a + 3] - p[a]});
    }
    int wn = 0;
    if (!around.empty()) {
      wn = kAmbiguous;
      for (std::size_t d = 0; d < kDirections.size() && wn == kAmbiguous; ++d) {
        const Vec3 far = p + kDirections[d] * (4 * reach + 1);
        if (far.allFinite()) wn = winding_along(s, around, p, far);  // (not past the doubles' range)
      }
      if (wn == kAmbiguous) continue;  // (every direction through an edge: not decided here)
    }
    // The shell's own arrays (volume_sign takes a mesh's), `local` left as it was after.
    pos.clear();
    tri.clear();
    for (u32 t : shell(j)) {
      std::array<std::uint32_t, 3> T;
      for (int k = 0; k < 3; ++k) {
        const u32 v = s.tris[t][k];
        u32& l = local[index(v)];
        if (l == kNone) {
          l = static_cast<u32>(pos.size());
          pos.push_back(s.verts[v]);
        }
        T[k] = l;
      }
      tri.push_back(T);
    }
    for (u32 t : shell(j))
      for (u32 v : s.tris[t]) local[index(v)] = kNone;
    const int sign = volume_sign(pos, tri);
    const int want = sign > 0 ? 0 : 1;
    if (wn != want) {
      const std::string at = "the shell through " + point_text(p);
      if (sign > 0 && wn > 0) return "has shells that overlap: " + at + " lies inside another of its shells that faces the same way";
      if (sign <= 0 && wn == 0) return "has shells that overlap: " + at + " faces inward but lies outside every other shell (a hollow in no solid)";
      return "has shells that overlap: " + at + " lies where its other shells wind " + std::to_string(wn) +
             " times (a solid's shells wind 0 or 1 times about a point)";
    }
  }
  return "";
}

}  // namespace wedge::boolean_detail
