// The broad phase's box tree (Bvh) far from the origin: its float boxes are offsets from the
// operands' corner, so which boxes overlap does not depend on where the model is. Before, a
// scene 1.2 wide at 1.5e8 had every float box overlap every other (an ulp of the coordinate is
// 16 there), and a fuzz case's rounding check tested 2 million pairs a round.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "csg/boolean.h"
#include "csg/boolean_impl.h"
#include "kernel/transform.h"
#include "tests/support/boolean_cases.h"

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

namespace {
// A cone of n sides about the z axis: its side a fan about the apex (0, 0, apex_z), its base a fan
// about the hub, the rim the unit circle at z = 0. Closed and outward where apex_z > 0 >= hub's z.
Mesh fan_cone(int n, double apex_z, const Point3& hub = Point3(0, 0, 0)) {
  Mesh m;
  m.positions.push_back(Point3(0, 0, apex_z));
  m.positions.push_back(hub);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    m.positions.push_back(Point3(std::cos(a), std::sin(a), 0));
  }
  for (int i = 0; i < n; ++i) {
    const u32 a = 2 + i, b = 2 + (i + 1) % n;
    m.triangles.push_back({a, b, 0});
    m.triangles.push_back({b, a, 1});
  }
  return m;
}
}  // namespace

TEST_CASE("boolean: slabs of long thin triangles keep every pair that meets and report it once", "[boolean][tree]") {
  // A fine cone's spokes lie across boxes far larger than themselves; the join over their slabs
  // must still report every pair of triangles that meet (here: each spoke against a sphere
  // through the cone), each once, and far fewer pairs than the join over whole boxes.
  const Mesh cone = fan_cone(800, 1.0);
  const Mesh ball = testing::icosphere(Point3(0.2, 0.1, 0.3), 0.45, 1280);
  const Soup soup = make_soup({&cone, &ball});
  std::vector<u32> ids(soup.tris.size());
  for (u32 i = 0; i < ids.size(); ++i) ids[i] = i;
  auto join = [&](bool slice) {
    const Bvh tree(soup, ids, 3, false, slice);
    std::mutex lock;
    std::vector<std::array<u32, 2>> pairs;
    tree.each_pair(nullptr, &soup, [&](u32 t, u32 u) {
      std::lock_guard<std::mutex> hold(lock);
      pairs.push_back({t, u});
    });
    std::sort(pairs.begin(), pairs.end());
    return std::make_pair(pairs, tree.items.size());
  };
  const auto [whole, whole_items] = join(false);
  const auto [sliced, sliced_items] = join(true);
  CHECK(whole_items == soup.tris.size());
  CHECK(sliced_items > soup.tris.size());  // (the spokes were sliced)
  CHECK(std::adjacent_find(sliced.begin(), sliced.end()) == sliced.end());
  CHECK(std::includes(whole.begin(), whole.end(), sliced.begin(), sliced.end()));
  auto across = [&](const std::vector<std::array<u32, 2>>& pairs) {
    return std::count_if(pairs.begin(), pairs.end(), [&](const auto& p) { return soup.operand[p[0]] != soup.operand[p[1]]; });
  };
  CHECK(sliced.size() * 2 < whole.size());
  CHECK(across(sliced) * 2 < across(whole));
  // Every pair of the cone's and the ball's triangles that meets, found by brute force.
  const Points pts(soup);
  std::size_t met = 0, missing = 0;
  for (u32 t = 0; t < soup.tris.size(); ++t) {
    if (soup.operand[t] != 0) continue;
    double lo[3], hi[3];
    triangle_box(soup, t, lo, hi);
    for (u32 u = 0; u < soup.tris.size(); ++u) {
      if (soup.operand[u] != 1) continue;
      double ulo[3], uhi[3];
      triangle_box(soup, u, ulo, uhi);
      if (!box_meets(lo, hi, ulo, uhi)) continue;
      const PairCut cut = intersect_pair(pts, t, u);
      if (cut.segs_t.empty() && cut.segs_u.empty() && cut.points.empty()) continue;
      ++met;
      missing += !std::binary_search(sliced.begin(), sliced.end(), std::array<u32, 2>{std::min(t, u), std::max(t, u)});
    }
  }
  CHECK(met > 100);
  CHECK(missing == 0);
}

TEST_CASE("boolean: the self-check over slabs finds a fine cone pushed through itself", "[boolean][tree]") {
  // The base's hub pushed up and out through the side (the volume still positive): the base's
  // spokes cross the side's.
  CHECK(mesh_solid_defect(fan_cone(3000, 1.0)) == "");
  const std::string defect = mesh_solid_defect(fan_cone(3000, 0.6, Point3(0.5, 0, 0.5)));
  INFO(defect);
  CHECK_THAT(defect, Catch::Contains("intersects itself"));
}

TEST_CASE("boolean: the closedness check at a hub of thousands of corners", "[boolean]") {
  // A cone's hub and apex have 2000 corners each (counted by sorted keys there: a scan per corner
  // was quadratic). Closed; one base triangle left out; one turned over.
  Mesh cone = fan_cone(2000, 1.0);
  CHECK(mesh_solid_defect(cone) == "");
  Mesh open = cone;
  open.triangles.erase(open.triangles.begin() + 1001);
  CHECK_THAT(mesh_solid_defect(open), Catch::Contains("is not closed: edge") && Catch::Contains("has no neighbour"));
  Mesh turned = cone;
  std::swap(turned.triangles[1001][0], turned.triangles[1001][1]);
  CHECK_THAT(mesh_solid_defect(turned), Catch::Contains("is not consistently oriented: edge") &&
                                            Catch::Contains("is used 2 times in one direction"));
}

namespace {
// A disk of n points about (cx, cy) in the plane z = 0, as a fan of slivers from its first point,
// counter-clockwise seen from +z, face id `id`.
void add_disk(Mesh& m, double cx, double cy, double r, int n, int id) {
  const u32 b = static_cast<u32>(m.positions.size());
  for (int i = 0; i < n; ++i) m.positions.push_back(Point3(cx + r * std::cos(2 * M_PI * i / n), cy + r * std::sin(2 * M_PI * i / n), 0));
  for (int i = 1; i + 1 < n; ++i) m.add_triangle(b, b + i, b + i + 1, id);
}
// An annulus between radii r0 < r1 about the origin, n points on each circle, face id `id`.
void add_annulus(Mesh& m, double r0, double r1, int n, int id) {
  const u32 b = static_cast<u32>(m.positions.size());
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    m.positions.push_back(Point3(r0 * std::cos(a), r0 * std::sin(a), 0));
    m.positions.push_back(Point3(r1 * std::cos(a), r1 * std::sin(a), 0));
  }
  for (int i = 0; i < n; ++i) {
    const u32 in0 = b + 2 * i, out0 = in0 + 1, in1 = b + 2 * ((i + 1) % n), out1 = in1 + 1;
    m.add_triangle(in0, out0, out1, id);
    m.add_triangle(in0, out1, in1, id);
  }
}
bool certified(const Mesh& m) {
  const Soup soup = make_soup({&m});
  const std::vector<u32> g = embedded_groups(soup, nullptr, 1);
  return !g.empty() && std::all_of(g.begin(), g.end(), [&](u32 x) { return x == g[0] && x != kNone; });
}
}  // namespace

TEST_CASE("boolean: a planar face's triangulation is certified embedded by its projection", "[boolean][tree]") {
  // Certified: a disk's fan of slivers, an annulus (its hole turning the other way), the same
  // turned about a slanted axis (projected along its dominant axis).
  Mesh disk;
  add_disk(disk, 0, 0, 1, 400, 7);
  CHECK(certified(disk));
  Mesh ring;
  add_annulus(ring, 0.5, 1, 300, 3);
  CHECK(certified(ring));
  Mesh tilted = ring;
  const Mat4 turn = rotate(40, Vec3(1, 2, 0.5));
  for (Point3& p : tilted.positions) p = apply_point(turn, p);
  CHECK(certified(tilted));
  // Not: two disks overlapping; a disk inside another (two curves turning one way); two disks
  // touching at a point; a fan whose first point is moved across the disk (triangles turned over).
  for (const auto& [cx, r] : std::vector<std::pair<double, double>>{{0.5, 1}, {0, 0.5}, {2, 1}}) {
    INFO("a second disk at x " << cx << " of radius " << r);
    Mesh two;
    add_disk(two, 0, 0, 1, 200, 1);
    add_disk(two, cx, 0, r, 200, 1);
    CHECK_FALSE(certified(two));
  }
  Mesh folded;
  add_disk(folded, 0, 0, 1, 200, 1);
  folded.positions[0] = Point3(-1.5, 0, 0);
  CHECK_FALSE(certified(folded));
  // A fan about a centre moved out of the disk: the boundary is still the circle, but the
  // triangles on the near side are turned over (covering it twice one way, once the other).
  Mesh hub;
  {
    const int n = 200;
    hub.positions.push_back(Point3(0, 0, 0));
    for (int i = 0; i < n; ++i) hub.positions.push_back(Point3(std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0));
    for (int i = 0; i < n; ++i) hub.add_triangle(0, 1 + i, 1 + (i + 1) % n, 5);
  }
  CHECK(certified(hub));
  hub.positions[0] = Point3(1.4, 0.3, 0);
  CHECK_FALSE(certified(hub));
  // A C whose lower arm has a spike up to the upper arm's edge, touching it at a point: one
  // boundary curve, every triangle turned the right way, but the spike's triangle and the upper
  // arm's meet at that point.
  Mesh c;
  for (auto [x, y] : std::vector<std::pair<double, double>>{{0, 0}, {6, 0}, {6, 1}, {4, 1}, {3.5, 3}, {3, 1}, {1, 1}, {1, 3}, {6, 3}, {6, 4}, {0, 4}})
    c.positions.push_back(Point3(x, y, 0));
  for (auto [a, b, d] : std::vector<std::array<u32, 3>>{{0, 1, 2}, {0, 2, 3}, {3, 4, 5}, {0, 3, 5}, {0, 5, 6}, {0, 6, 7}, {0, 7, 10}, {7, 8, 9}, {7, 9, 10}})
    c.add_triangle(a, b, d, 4);
  CHECK_FALSE(certified(c));
  c.positions[4] = Point3(3.5, 2.9, 0);  // (the spike short of the arm)
  CHECK(certified(c));
  // And the self-check still finds the overlap of the two disks' triangles, closed into a solid
  // (each disk a cap of its own drum, the drums' caps in one plane with one face id).
  auto drum = [](Mesh& m, double cx, int n) {
    const u32 b = static_cast<u32>(m.positions.size());
    for (int i = 0; i < n; ++i) m.positions.push_back(Point3(cx + std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 0));
    for (int i = 0; i < n; ++i) m.positions.push_back(Point3(cx + std::cos(2 * M_PI * i / n), std::sin(2 * M_PI * i / n), 1));
    for (int i = 1; i + 1 < n; ++i) {
      m.add_triangle(b, b + i + 1, b + i, 1);  // the bottom, facing -z
      m.add_triangle(b + n, b + n + i, b + n + i + 1, 2);
    }
    for (int i = 0; i < n; ++i) {
      const u32 a0 = b + i, a1 = b + (i + 1) % n, c0 = a0 + n, c1 = a1 + n;
      m.add_triangle(a0, a1, c1, 3);
      m.add_triangle(a0, c1, c0, 3);
    }
  };
  Mesh drums;
  drum(drums, 0, 100);
  drum(drums, 0.5, 100);
  CHECK_THAT(mesh_solid_defect(drums), Catch::Contains("intersects itself"));
}
