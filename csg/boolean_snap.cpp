// Rounding repair, second means: a rounded vertex moves to a neighbouring double.
//
// The rounding repair (boolean_output.cpp) collapses short edges. Where a bad triangle has none, a
// few ulps can still decide: a cut point on an edge that is nearly straight through a vertex (a
// sliver of an operand's own rounding, a cube's edge with a vertex 1e-17 off it) is rounded to
// the wrong side of that edge's line, and the triangle beyond the edge crosses every triangle of
// the fan around the vertex. Each rounded vertex of a bad triangle may take one of the 26 doubles
// next to its position (an ulp or none in each coordinate), nearest first, where every triangle
// around it keeps its exact orientation in its source's projection and meets no triangle near it
// but in the vertices and edges they share: exact checks on the doubles decide. The mesh keeps its
// triangles; only positions change, by an ulp (as rounding moved them).
#include <algorithm>
#include <cmath>
#include <numeric>

#include "csg/boolean_impl.h"

namespace wedge::boolean_detail {

std::size_t snap_rounded(Mesh& m, const Soup& soup, const std::vector<u32>& src, const std::vector<std::int8_t>& sign,
                         const std::vector<char>& movable, const std::vector<u32>& bad, std::vector<char>& recheck) {
  constexpr int kReach = 1;  // ulps in each coordinate (every move the stress runs made was one)
  // The work allowed: the clash tests of one look at every candidate's star (each may take 27).
  // A few bad triangles, as a cut point on a sliver makes, take a few thousand; where thousands
  // of triangles are bad (sheets that coincide) moves of an ulp mend too little, and the
  // re-resolution is left to do it.
  constexpr std::size_t kBudget = 50000;
  const std::size_t nt = m.triangles.size();
  // The candidates: the movable vertices of bad triangles, those in the most bad triangles first.
  std::vector<u32> count(m.positions.size(), 0);
  for (u32 t : bad)
    for (u32 v : m.triangles[t])
      if (movable[v]) ++count[v];
  std::vector<u32> cands;
  for (std::size_t v = 0; v < count.size(); ++v)
    if (count[v]) cands.push_back(static_cast<u32>(v));
  if (cands.empty() || cands.size() * 50 > kBudget) return 0;
  std::stable_sort(cands.begin(), cands.end(), [&](u32 a, u32 b) { return count[a] > count[b]; });
  std::vector<u32> slot(m.positions.size(), kNone);  // candidate vertex -> its index in cands
  for (std::size_t i = 0; i < cands.size(); ++i) slot[cands[i]] = static_cast<u32>(i);
  std::vector<std::vector<u32>> star(cands.size()), near(cands.size());
  std::vector<u32> star_tris;
  for (std::size_t t = 0; t < nt; ++t) {
    bool in = false;
    for (u32 v : m.triangles[t])
      if (slot[v] != kNone) {
        star[slot[v]].push_back(static_cast<u32>(t));
        in = true;
      }
    if (in) star_tris.push_back(static_cast<u32>(t));
  }
  // The triangles near each star: boxes within the reach of a move (a few ulps of the largest
  // coordinate, generously) of one of its triangles' boxes.
  double big = 0;
  for (u32 v : cands) big = std::max(big, m.positions[v].cwiseAbs().maxCoeff());
  const double margin = 8 * kReach * (std::nextafter(big, INFINITY) - big);
  {
    const Mesh few = sub_mesh(m, star_tris);
    std::vector<const Mesh*> one{&few};
    const Soup fs = make_soup(one, soup.interrupt);
    std::vector<u32> ids(star_tris.size());
    std::iota(ids.begin(), ids.end(), 0u);
    const Bvh tree(fs, std::move(ids), 3);
    std::vector<u32> hit;
    for (std::size_t u = 0; u < nt; ++u) {
      double lo[3], hi[3];
      mesh_triangle_box(m, u, lo, hi);
      for (int d = 0; d < 3; ++d) {
        lo[d] -= margin;
        hi[d] += margin;
      }
      hit.clear();
      tree.query(lo, hi, [&](u32 i) {
        for (u32 v : m.triangles[star_tris[i]])
          if (slot[v] != kNone) hit.push_back(slot[v]);
      });
      std::sort(hit.begin(), hit.end());
      hit.erase(std::unique(hit.begin(), hit.end()), hit.end());
      for (u32 c : hit) near[c].push_back(static_cast<u32>(u));
    }
  }
  std::size_t work = 0;
  for (std::size_t c = 0; c < cands.size(); ++c) work += star[c].size() * (star[c].size() + near[c].size());
  if (work > kBudget) return 0;
  // The moves, nearest first: offsets of up to kReach ulps in each coordinate.
  std::vector<std::array<int, 3>> offsets;
  for (int x = -kReach; x <= kReach; ++x)
    for (int y = -kReach; y <= kReach; ++y)
      for (int z = -kReach; z <= kReach; ++z)
        if (x || y || z) offsets.push_back({x, y, z});
  std::stable_sort(offsets.begin(), offsets.end(), [](const auto& a, const auto& b) {
    return a[0] * a[0] + a[1] * a[1] + a[2] * a[2] < b[0] * b[0] + b[1] * b[1] + b[2] * b[2];
  });
  auto step = [](double x, int n) {
    for (; n > 0; --n) x = std::nextafter(x, INFINITY);
    for (; n < 0; ++n) x = std::nextafter(x, -INFINITY);
    return x;
  };
  std::size_t moved = 0;
  for (std::size_t c = 0; c < cands.size(); ++c) {
    soup.poll();
    const u32 v = cands[c];
    // The star's triangles first, then the others near it, with the positions as they are now
    // (earlier moves included).
    std::vector<u32> local = star[c];
    const std::size_t ns = local.size();
    for (u32 u : near[c])
      if (!std::binary_search(star[c].begin(), star[c].end(), u)) local.push_back(u);
    Mesh lm = sub_mesh(m, local);
    std::vector<const Mesh*> one{&lm};
    Soup ls = make_soup(one, soup.interrupt);
    // v's vertex in the local soup and in the local mesh.
    const auto& T0 = m.triangles[local[0]];
    const int k0 = T0[0] == v ? 0 : (T0[1] == v ? 1 : 2);
    const u32 lv = ls.tris[0][k0], mv = lm.triangles[0][k0];
    // A copy of v at its position (two sheets touching at a point, kept apart; rounded, they may
    // cross there): the soup, which merges equal positions, is made again for each move, so that
    // v leaves its copy rather than taking it along.
    bool copy = false;
    if (ls.verts.size() != lm.positions.size()) {
      std::size_t same = 0;
      for (const Vec3& p : lm.positions) same += p == m.positions[v];
      copy = same > 1;
    }
    // Whether the star is sound with v where it is now: each triangle of it has its orientation
    // in its source's projection and meets no local triangle beyond what they share.
    auto sound = [&]() {
      for (std::size_t s = 0; s < ns; ++s) {
        const u32 t = local[s];
        const int k = soup.axis[src[t]], i = (k + 1) % 3, j = (k + 2) % 3;
        const auto& T = ls.tris[s];
        auto p2 = [&](int q) { return Point2(ls.verts[T[q]][i], ls.verts[T[q]][j]); };
        if (orient2d(p2(0), p2(1), p2(2)) != sign[t]) return false;
      }
      for (std::size_t s = 0; s < ns; ++s)
        for (std::size_t u = 0; u < local.size(); ++u)
          if ((u >= ns || u > s) && triangles_clash(ls, static_cast<u32>(s), static_cast<u32>(u))) return false;
      return true;
    };
    if (sound()) continue;  // v's triangles are not what is wrong here
    const Vec3 at = m.positions[v];
    bool found = false;
    for (const auto& o : offsets) {
      const Vec3 q(step(at.x(), o[0]), step(at.y(), o[1]), step(at.z(), o[2]));
      if (copy) {
        lm.positions[mv] = q;
        ls = make_soup(one, soup.interrupt);
      } else {
        ls.verts[lv] = q;
        for (std::size_t s = 0; s < ns; ++s) set_axis(ls, s);
      }
      if (sound()) {
        found = true;
        m.positions[v] = q;
        break;
      }
    }
    if (!found) continue;
    for (u32 t : star[c]) recheck[t] = 1;
    ++moved;
  }
  return moved;
}

}  // namespace wedge::boolean_detail
