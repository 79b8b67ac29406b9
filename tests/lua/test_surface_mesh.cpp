#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "lua/wrap_curve.h"

using namespace wedge;

namespace {
using Key = std::tuple<double, double, double>;
// Points within about 1e-8 are one point: patches that run along a shared edge in opposite
// directions evaluate it at u and 1 - u, equal in exact arithmetic, a few ulps apart in doubles.
Key key(const Point3& p) {
  auto q = [](double x) { return std::round(x * 1e8) / 1e8; };
  return {q(p.x()), q(p.y()), q(p.z())};
}
}  // namespace

TEST_CASE("the teapot's patches are meshed without T-junctions along shared edges", "[surfaces][mesh]") {
  lua::LuaSurface pot;
  for (auto& patch : teapot()) pot.patches.push_back(std::make_shared<NurbsSurface>(patch));
  Mesh m = lua::surface_mesh(pot, 0.02);
  // Merge coincident points, then collect edges used by one triangle only: the patch boundaries
  // that found no partner, and the teapot's real openings.
  std::map<Key, int> id;
  std::vector<Point3> pts;
  auto vid = [&](const Point3& p) {
    auto [it, fresh] = id.emplace(key(p), int(pts.size()));
    if (fresh) pts.push_back(p);
    return it->second;
  };
  std::map<std::pair<int, int>, int> uses;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      int a = vid(m.positions[t[k]]), b = vid(m.positions[t[(k + 1) % 3]]);
      if (a == b) continue;  // a collapsed edge at a pole
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  std::vector<std::pair<int, int>> boundary;
  std::set<int> boundary_vertices;
  for (const auto& [e, n] : uses)
    if (n == 1) {
      boundary.push_back(e);
      boundary_vertices.insert(e.first);
      boundary_vertices.insert(e.second);
    }
  // A T-junction is a vertex lying inside another boundary edge: that is where a crack opens.
  int t_junctions = 0;
  for (const auto& [a, b] : boundary) {
    const Point3 &p = pts[a], &q = pts[b];
    double len2 = (q - p).squaredNorm();
    for (int v : boundary_vertices) {
      if (v == a || v == b) continue;
      double t = (pts[v] - p).dot(q - p) / len2;
      if (t <= 1e-9 || t >= 1 - 1e-9) continue;
      if ((p + t * (q - p) - pts[v]).norm() < 1e-9) ++t_junctions;
    }
  }
  CHECK(t_junctions == 0);
  // The remaining boundary must be the teapot's real openings, as closed loops: every boundary
  // vertex has two boundary edges. Cracks along seams would add loops, one per unmatched seam.
  std::map<int, std::vector<int>> adjacent;
  for (const auto& [a, b] : boundary) {
    adjacent[a].push_back(b);
    adjacent[b].push_back(a);
  }
  int odd = 0;
  for (const auto& [v, next] : adjacent) odd += next.size() != 2;
  std::set<int> seen;
  int loops = 0;
  for (const auto& [v, next] : adjacent) {
    if (seen.count(v)) continue;
    ++loops;
    std::vector<int> stack{v};
    while (!stack.empty()) {
      int x = stack.back();
      stack.pop_back();
      if (!seen.insert(x).second) continue;
      for (int y : adjacent[x]) stack.push_back(y);
    }
  }
  CHECK(odd == 0);
  // Newell's data is open in six places (among them the spout's tip, the handle's two ends where
  // they meet the body, and the rims of lid and body). Patches meshed independently instead
  // leave 48 boundary vertices of odd degree along the seams.
  CHECK(loops == 6);
  CHECK(m.triangle_count() > 1000);
}
