// The broad phase's box tree (Bvh) far from the origin: its float boxes are offsets from the
// operands' corner, so which boxes overlap does not depend on where the model is. Before, a
// scene 1.2 wide at 1.5e8 had every float box overlap every other (an ulp of the coordinate is
// 16 there), and a fuzz case's rounding check tested 2 million pairs a round.
#include <catch2/catch.hpp>

#include <atomic>

#include "csg/boolean_impl.h"

using namespace wedge;
using namespace wedge::boolean_detail;

namespace {
// n x n small triangles (0.1 wide) one apart in the plane z = 0, moved by `at`.
Mesh scattered(int n, const Vec3& at) {
  Mesh m;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const u32 b = static_cast<u32>(m.positions.size());
      m.positions.push_back(at + Vec3(i, j, 0));
      m.positions.push_back(at + Vec3(i + 0.1, j, 0));
      m.positions.push_back(at + Vec3(i, j + 0.1, 0.05));
      m.triangles.push_back({b, b + 1, b + 2});
    }
  return m;
}
}  // namespace

TEST_CASE("boolean: the box tree finds the same overlaps at the origin and 1.5e8 away from it", "[boolean][tree]") {
  for (const double far : {0.0, 1.5e8, -3.0e9}) {
    INFO("offset " << far);
    const Mesh m = scattered(40, Vec3(far, far / 2, -far));
    const Soup soup = make_soup({&m});
    std::vector<u32> ids(soup.tris.size());
    for (u32 i = 0; i < ids.size(); ++i) ids[i] = i;
    const Bvh tree(soup, ids, 3);
    // No two triangles' boxes overlap: the join reports no pair.
    std::atomic<int> pairs{0};
    tree.each_pair(nullptr, &soup, [&](u32, u32) { ++pairs; });
    CHECK(pairs.load() == 0);
    // A box around one triangle meets that triangle's box alone.
    int wrong = 0;
    for (u32 t = 0; t < soup.tris.size(); t += 37) {
      double lo[3], hi[3];
      triangle_box(soup, t, lo, hi);
      std::vector<u32> met;
      tree.query(lo, hi, [&](u32 u) { met.push_back(u); });
      // (query() reports the triangles of a leaf whose box meets; each is then told apart by its
      // own box, as the callers do.)
      int own = 0;
      for (u32 u : met) {
        double ulo[3], uhi[3];
        triangle_box(soup, u, ulo, uhi);
        if (box_meets(lo, hi, ulo, uhi)) own += u == t ? 1 : 100;
      }
      wrong += own != 1;
      CHECK(tree.meets(lo, hi));
    }
    CHECK(wrong == 0);
    // Leaves stay small: a leaf's box spans a few triangles, not the scene.
    const Bvh::Node& root = tree.nodes[0];
    CHECK(root.hi[0] - root.lo[0] < 40.0f);
    CHECK(root.hi[0] - root.lo[0] > 38.0f);
  }
}
