// The boolean engine's broad phase and work budget (csg/boolean.h, kDefaultMaxCrossings): operands that nearly
// coincide cross everywhere and are refused after the broad phase, before minutes of exact work,
// with the estimate; ordinary heavy inputs are far below it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <ctime>
#include <iterator>

#include "csg/boolean.h"
#include "csg/boolean_impl.h"
#include "kernel/transform.h"
#include "tests/support/boolean_cases.h"

using namespace wedge;
using Catch::Matchers::Contains;

namespace {

std::vector<const Mesh*> pointers(const std::vector<Mesh>& meshes) {
  std::vector<const Mesh*> out;
  for (const Mesh& m : meshes) out.push_back(&m);
  return out;
}

std::size_t triples(const std::vector<Mesh>& meshes) {
  using namespace boolean_detail;
  Soup soup = make_soup(pointers(meshes));
  return candidate_triples(soup, candidate_pairs(soup));
}

}  // namespace

TEST_CASE("boolean: copies of a sphere turned by 1 .. 16 degrees are refused fast with the estimate", "[boolean]") {
  std::vector<Mesh> copies;
  for (int i = 0; i <= 16; ++i) copies.push_back(testing::uv_sphere(Point3(0, 0, 0), 1, 4000).transformed(rotate_x(i)));
  const std::clock_t t0 = std::clock();  // CPU time of the process (all threads): not the machine's load
  REQUIRE_THROWS_WITH(boolean(BooleanOp::Union, pointers(copies)),
                      Contains("boolean: the union of 17 operands: their surfaces would cross three at a time at about ") &&
                          Contains(" points, more than the budget of 50000 (operands that nearly coincide") &&
                          Contains("raise the budget with tolerance{max_crossings=N}"));
  // Before: minutes of exact arithmetic (past 120 s). Now the checks, the broad phase and the
  // estimate: about 1 s of CPU in the release build; the bound leaves room for the sanitizers.
  CHECK(double(std::clock() - t0) / CLOCKS_PER_SEC < 30);
  // The estimate is close to the crossings the arrangement would find (each found once in each of
  // the three triangles): about 1 per 3 of them, not the loose count of meeting boxes.
  const std::vector<Mesh> three(copies.begin(), copies.begin() + 3);
  const std::size_t estimate = triples(three);
  CHECK(estimate > 100);
  CHECK(estimate < 50000);
  // A moderate case: refused under a small budget, through under the default (or a raised one).
  REQUIRE_THROWS_WITH(boolean(BooleanOp::Union, pointers(three), nullptr, nullptr, 100),
                      Contains("the union of 3 operands") && Contains("more than the budget of 100 "));
  const BooleanResult r = boolean(BooleanOp::Union, pointers(three), nullptr, nullptr, estimate);
  CHECK(mesh_solid_defect(r.mesh) == "");
  // Two operands have no point where three surfaces meet: never refused by this budget.
  const std::vector<Mesh> two(copies.begin(), copies.begin() + 2);
  CHECK(boolean(BooleanOp::Union, pointers(two), nullptr, nullptr, 1).mesh.triangle_count() > 0);
}

TEST_CASE("boolean: the bench's heavy inputs are far below the work budget", "[boolean]") {
  CHECK(triples(testing::plate_and_cylinders(20, 32)) == 0);
  CHECK(triples(testing::menger_operands(3)) < 1000);
  CHECK(triples(testing::sphere_lattice(4, 1280)) == 0);
  CHECK(triples(testing::overlapping_spheres(65536)) == 0);
}

TEST_CASE("boolean: copies of a box turned by a hair count their faces' crossings in one plane", "[boolean]") {
  // Turned about the z axis, the copies' tops and bottoms stay in two planes, where each copy's
  // edges cross the others' inside every other copy's face: n^3 crossings, none of them where
  // three planes meet across each other (the count of those alone is 0 here). 40 copies took 13 s
  // before this count and are now refused in milliseconds; 10 copies are answered.
  auto copies = [](int n) {
    std::vector<Mesh> out;
    for (int i = 1; i <= n; ++i) out.push_back(testing::box_mesh(Point3(0, 0, 0), Vec3(1, 1, 1), rotate(i * 1e-7, Vec3(0, 0, 1))));
    return out;
  };
  const std::vector<Mesh> ten = copies(10), forty = copies(40);
  const std::size_t small = triples(ten), large = triples(forty);
  CHECK(small > 500);  // 2 faces x 2 triangles x C(10, 2) pairs of other copies, a crossing or two each
  CHECK(small < 50000);
  CHECK(large > 50000);
  const std::clock_t t0 = std::clock();
  REQUIRE_THROWS_WITH(boolean(BooleanOp::Union, pointers(forty)),
                      Contains("the union of 40 operands") && Contains("more than the budget of 50000"));
  CHECK(double(std::clock() - t0) / CLOCKS_PER_SEC < 10);
  const BooleanResult r = boolean(BooleanOp::Union, pointers(ten));
  CHECK(mesh_solid_defect(r.mesh) == "");
  CHECK(r.mesh.volume() == Approx(1.0).epsilon(1e-6));
}

TEST_CASE("boolean: the broad phase over only the triangles near other operands finds every pair", "[boolean]") {
  // With every operand known valid, the tree holds only the triangles whose grid cells another
  // operand's triangles also touch; the pairs must be those of the tree over all triangles (which
  // is what a check of the operands' own pairs builds), but for the pairs that tree, slicing long
  // thin triangles (a uv sphere's near its poles), found apart: those must not meet.
  using namespace boolean_detail;
  auto both = [](const std::vector<Mesh>& meshes) {
    Soup soup = make_soup(pointers(meshes));
    std::array<u32, 2> clash;
    const std::vector<char> none(meshes.size(), 0), all(meshes.size(), 1);
    auto full = candidate_pairs(soup, &clash, false, &none);
    CHECK(clash[0] == kNone);
    auto near = candidate_pairs(soup, &clash, false, &all);
    CHECK(near.size() > 0);
    CHECK(std::includes(near.begin(), near.end(), full.begin(), full.end()));
    std::vector<std::array<u32, 2>> dropped;
    std::set_difference(near.begin(), near.end(), full.begin(), full.end(), std::back_inserter(dropped));
    const Points pts(soup);
    int meet = 0;
    for (const auto& p : dropped) {
      const PairCut cut = intersect_pair(pts, p[0], p[1]);
      meet += !cut.segs_t.empty() || !cut.segs_u.empty() || !cut.points.empty();
    }
    CHECK(meet == 0);
  };
  both(testing::overlapping_spheres(16384));
  both(testing::sphere_lattice(3, 1280));
  both(testing::plate_and_cylinders(6, 32));
  both(testing::menger_operands(2));
  // Boxes that overlap in a corner: each operand's triangles off the other's box are left out
  // before the grid (those crossing into it, or touching it, are kept).
  both({testing::icosphere(Point3(0, 0, 0), 1, 20000), testing::box_mesh(Point3(0.5, 0.5, 0.5), Vec3(2, 2, 2)),
        testing::uv_sphere(Point3(1.6, 1.6, 1.6), 0.7, 6000)});
  // Touching only: boxes side by side share faces, edges and corners (boxes that touch overlap).
  std::vector<Mesh> boxes;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) boxes.push_back(testing::box_mesh(Point3(i, j, 0), Vec3(1, 1, 1 + 0.5 * ((i + j) % 2))));
  boxes.push_back(testing::uv_sphere(Point3(3, 3, 1), 2.5, 8000));
  both(boxes);
}

TEST_CASE("boolean: triangles the broad phase finds outside the other operands are outside their boxes", "[boolean]") {
  // candidate_pairs' `outside`: a triangle is marked where its box is off every other operand's
  // box (classify keeps or drops it, and its patch, by its operand alone). Every marked triangle
  // must be off them all; and on two overlapping spheres about half are marked.
  using namespace boolean_detail;
  auto check = [](const std::vector<Mesh>& meshes, double least) {
    const Soup soup = make_soup(pointers(meshes));
    std::array<u32, 2> clash;
    const std::vector<char> all(meshes.size(), 1);
    std::vector<char> outside;
    candidate_pairs(soup, &clash, false, &all, nullptr, nullptr, &outside);
    REQUIRE(outside.size() == soup.tris.size());
    std::size_t marked = 0;
    for (std::size_t t = 0; t < outside.size(); ++t) {
      if (!outside[t]) continue;
      ++marked;
      double lo[3], hi[3];
      triangle_box(soup, static_cast<u32>(t), lo, hi);
      for (int o = 0; o < soup.operands; ++o) {
        if (o == soup.operand[t]) continue;
        const auto& b = soup.boxes[o];
        const bool meets = lo[0] <= b[3] && b[0] <= hi[0] && lo[1] <= b[4] && b[1] <= hi[1] && lo[2] <= b[5] && b[2] <= hi[2];
        CHECK_FALSE(meets);
      }
    }
    CHECK(marked >= least * static_cast<double>(soup.tris.size()));
  };
  check(testing::overlapping_spheres(16384), 0.3);
  check({testing::icosphere(Point3(0, 0, 0), 1, 20000), testing::box_mesh(Point3(0.5, 0.5, 0.5), Vec3(2, 2, 2)),
         testing::uv_sphere(Point3(1.6, 1.6, 1.6), 0.7, 6000)},
        0.5);
  // Boxes side by side touch: none of their triangles is off the others' boxes but where a box
  // has no neighbour on that side.
  std::vector<Mesh> boxes;
  for (int i = 0; i < 4; ++i) boxes.push_back(testing::box_mesh(Point3(i, 0, 0), Vec3(1, 1, 1)));
  boxes.push_back(testing::uv_sphere(Point3(2, 0.5, 0.5), 0.4, 8000));
  check(boxes, 0.0);
}
