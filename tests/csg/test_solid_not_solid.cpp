// Leaves whose surface is closed and consistently oriented but bounds no solid as it is: it
// crosses itself, or holds a shell inside another facing the same way. An imported mesh is the
// region it winds around at least once; a polyhedron (a B-Rep of the user's faces) is refused by
// the queries that need a solid, and is_valid() says why. (Both were taken as solids: two
// overlapping cubes had volume 2 where they bound 1.875, and a point inside both was "outside".)
#include <catch2/catch.hpp>

#include "brep/brep.h"
#include "csg/brep_leaf.h"
#include "csg/csg.h"
#include "tessellate/tessellate.h"

#include <filesystem>
#include <unistd.h>
#include "tests/support/boolean_cases.h"

using namespace wedge;
using wedge::testing::box_mesh;

namespace {

Mesh two_boxes(const Point3& lo1, double s1, const Point3& lo2, double s2) {
  Mesh m = box_mesh(lo1, Vec3(s1, s1, s1));
  m.append(box_mesh(lo2, Vec3(s2, s2, s2)));
  return m;
}

Solid as_polyhedron(const Mesh& m) {
  std::vector<std::vector<int>> faces;
  for (const auto& t : m.triangles) faces.push_back({int(t[0]), int(t[1]), int(t[2])});
  return brep_solid(polyhedron(m.positions, faces));
}

}  // namespace

TEST_CASE("an imported mesh that crosses itself is the region it winds around", "[solid][mesh]") {
  Tolerance tol;
  const Solid s = Solid::from_mesh(two_boxes({0, 0, 0}, 1, {0.5, 0.5, 0.5}, 1), "overlap.obj");
  CHECK(s.validate(tol).empty());
  CHECK(s.mass_properties(tol).volume == Approx(1.875).epsilon(1e-12));
  CHECK(s.contains({0.75, 0.75, 0.75}, tol) == Membership::Inside);
  CHECK(s.contains({1.25, 1.25, 1.25}, tol) == Membership::Inside);
  CHECK(s.contains({1.25, 0.25, 0.25}, tol) == Membership::Outside);
  CHECK(mesh_solid_defect(s.mesh(tol)).empty());
  const Solid u = Solid::boolean(BooleanOp::Union, {s, Solid::from_mesh(box_mesh({1, 1, 1}, Vec3(1, 1, 1)))});
  CHECK(u.mass_properties(tol).volume == Approx(1.875 + 1 - 0.125).epsilon(1e-12));
  // A shell inside another that faces the same way: the outer box.
  const Solid nested = Solid::from_mesh(two_boxes({0, 0, 0}, 3, {1, 1, 1}, 1), "nested.obj");
  CHECK(nested.validate(tol).empty());
  CHECK(nested.mass_properties(tol).volume == Approx(27).epsilon(1e-12));
  CHECK(nested.contains({1.5, 1.5, 1.5}, tol) == Membership::Inside);
  // Valid meshes are kept as given (a box beside a box: two shells apart).
  const Mesh apart = two_boxes({0, 0, 0}, 1, {2, 0, 0}, 1);
  CHECK(Solid::from_mesh(apart).mesh(tol).triangles == apart.triangles);
}

TEST_CASE("a polyhedron that crosses itself or nests a shell facing the same way is not a solid", "[solid][brep]") {
  Tolerance tol;
  const Solid crossed = as_polyhedron(two_boxes({0, 0, 0}, 2, {1, 1, 1}, 2));
  CHECK_THAT(crossed.validate(tol), Catch::Contains("intersects itself"));
  CHECK_THROWS_WITH(crossed.mass_properties(tol), Catch::StartsWith("not a solid: the solid intersects itself"));
  CHECK_THROWS_WITH(crossed.contains({1.5, 1.5, 1.5}, tol), Catch::Contains("not a solid"));
  CHECK_THROWS_WITH(crossed.cells(0.5, tol), Catch::Contains("not a solid"));
  const Solid nested = as_polyhedron(two_boxes({0, 0, 0}, 3, {1, 1, 1}, 1));
  CHECK_THAT(nested.validate(tol), Catch::Contains("has shells that overlap"));
  CHECK_THROWS_WITH(nested.mass_properties(tol), Catch::Contains("lies inside another of its shells that faces the same way"));
  // Moved, the copy asks its source.
  CHECK_THROWS_WITH(nested.transformed(translate({1, 0, 0})).mass_properties(tol), Catch::Contains("not a solid"));
  // A hollow (the inner box facing in) and boxes apart are solids.
  Mesh hollow = two_boxes({0, 0, 0}, 3, {1, 1, 1}, 1);
  for (std::size_t t = 12; t < 24; ++t) std::swap(hollow.triangles[t][1], hollow.triangles[t][2]);
  const Solid h = as_polyhedron(hollow);
  CHECK(h.validate(tol).empty());
  CHECK(h.mass_properties(tol).volume == Approx(26).epsilon(1e-12));
  CHECK(h.contains({1.5, 1.5, 1.5}, tol) == Membership::Outside);
  CHECK(as_polyhedron(two_boxes({0, 0, 0}, 1, {2, 0, 0}, 1)).mass_properties(tol).volume == Approx(2).epsilon(1e-12));
}

TEST_CASE("a boolean refuses a polyhedron that crosses itself even where the engine is not needed", "[solid][brep]") {
  // One operand, a repeat, operands whose boxes are apart: each way around the engine passed the
  // leaf's mesh on unchecked (union with a far cube: volume 3 where the region is 2.875).
  Tolerance tol;
  const Solid crossed = as_polyhedron(two_boxes({0, 0, 0}, 1, {0.5, 0.5, 0.5}, 1));
  const Solid far = as_polyhedron(box_mesh({10, 0, 0}, Vec3(1, 1, 1)));
  const std::vector<std::pair<BooleanOp, std::vector<Solid>>> cases = {
      {BooleanOp::Union, {crossed, far}},        {BooleanOp::Union, {far, crossed.transformed(translate({0, 5, 0}))}},
      {BooleanOp::Union, {crossed}},             {BooleanOp::Union, {crossed, crossed}},
      {BooleanOp::Intersection, {crossed, crossed}}, {BooleanOp::Intersection, {crossed, far}},
      {BooleanOp::Difference, {crossed, far}},   {BooleanOp::Difference, {far, crossed}},
      {BooleanOp::Difference, {crossed}}};
  for (const auto& [op, operands] : cases) {
    const Solid r = Solid::boolean(op, operands, "model.lua:7");
    CHECK_THROWS_WITH(r.mass_properties(tol), Catch::Contains("is not a solid: the solid intersects itself") &&
                                                  Catch::Contains("operand of the") && Catch::Contains("at model.lua:7"));
  }
  // Named by the operand's place in the node, not the engine's order (a union's operands reach
  // the engine sorted by their boxes and grouped, a difference's pruned).
  const Solid near = as_polyhedron(box_mesh({0.5, 0.5, 0.5}, Vec3(1, 1, 1)));
  const std::vector<std::tuple<BooleanOp, std::vector<Solid>, std::string>> named = {
      {BooleanOp::Union, {far, near, crossed}, "boolean: the third operand of the union at model.lua:7 is not a solid"},
      {BooleanOp::Union, {crossed, far, near}, "boolean: the first operand of the union at model.lua:7 is not a solid"},
      {BooleanOp::Difference, {near, far, crossed}, "boolean: the third operand of the difference at model.lua:7 is not a solid"},
      {BooleanOp::Intersection, {near, crossed}, "boolean: the second operand of the intersection at model.lua:7 is not a solid"}};
  for (const auto& [op, operands, expect] : named)
    CHECK_THROWS_WITH(Solid::boolean(op, operands, "model.lua:7").mass_properties(tol), Catch::StartsWith(expect));
  // Sound operands apart are still put side by side without the engine.
  CHECK(Solid::boolean(BooleanOp::Union, {as_polyhedron(box_mesh({0, 0, 0}, Vec3(1, 1, 1))), far}).mass_properties(tol).volume ==
        Approx(2).epsilon(1e-12));
}

TEST_CASE("a result whose parts touch along an edge reads back from OFF, PLY, STL and OBJ as a solid", "[solid][mesh]") {
  // The engine keeps a vertex per part where parts touch; OFF and PLY keep the indices. The leaf
  // checked only the welded copy, where four triangles met at the edge: "edge 6-2 is used twice
  // in the same direction", the file refused. OBJ's per-face normals split every vertex (only the
  // welded copy is closed) and STL welds as it reads: there the edge's triangles are paired again
  // by angle (split_touching), which refused both files before.
  Tolerance tol;
  const Solid two = Solid::boolean(BooleanOp::Union, {Solid::from_mesh(box_mesh({0, 0, 0}, Vec3(1, 1, 1))),
                                                      Solid::from_mesh(box_mesh({1, 1, 0}, Vec3(1, 1, 1)))});
  const Mesh m = two.mesh(tol);
  REQUIRE(m.positions.size() == 16);  // the edge's two points once per part
  const auto dir = std::filesystem::temp_directory_path() / ("wedge-edge-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const char* name : {"two.off", "two.ply", "two.stl", "two.obj"}) {
    INFO(name);
    const std::string path = (dir / name).string();
    write_mesh(m, path);
    const Solid back = Solid::from_mesh(read_mesh(path), name);
    CHECK(back.validate(tol).empty());
    CHECK(back.euler(tol) == EulerCounts{16, 36, 24, 0, 0, 2});
    CHECK(back.mass_properties(tol).volume == Approx(2).epsilon(1e-12));
    CHECK(Solid::boolean(BooleanOp::Union, {back, Solid::from_mesh(box_mesh({0.5, 0.5, 0.5}, Vec3(1, 1, 1)))})
              .mass_properties(tol)
              .volume == Approx(2 + 1 - 0.125 - 0.125).epsilon(1e-12));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("an OBJ of parts touching along an edge keeps its normals and uvs when read", "[solid][mesh]") {
  // Read back, the edge's triangles are paired by angle on the welded copy (split_touching); the
  // welded copy has no normals or uvs, and the leaf's mesh lost the file's: a textured part
  // rendered untextured, a faceted one with one normal per point.
  Tolerance tol;
  const Mesh m = Solid::boolean(BooleanOp::Union, {Solid::from_mesh(box_mesh({0, 0, 0}, Vec3(1, 1, 1))),
                                                   Solid::from_mesh(box_mesh({1, 1, 0}, Vec3(1, 1, 1)))})
                     .mesh(tol);
  // Faceted: each triangle its own corners, with its normal and uvs from its corners' x and y.
  Mesh faceted;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const Vec3 n = m.triangle_normal(t);
    const auto base = static_cast<std::uint32_t>(faceted.positions.size());
    for (std::uint32_t v : m.triangles[t]) {
      faceted.positions.push_back(m.positions[v]);
      faceted.normals.push_back(n);
      faceted.uvs.push_back(Vec2(m.positions[v].x() / 2 + 0.01 * double(t), m.positions[v].y() / 2));
    }
    faceted.triangles.push_back({base, base + 1, base + 2});
  }
  const auto dir = std::filesystem::temp_directory_path() / ("wedge-edge-uv-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "two.obj").string();
  write_mesh(faceted, path);
  const Mesh read = read_mesh(path);
  REQUIRE(read.triangles.size() == faceted.triangles.size());
  const Solid back = Solid::from_mesh(read, "two.obj");
  CHECK(back.validate(tol).empty());
  CHECK(back.euler(tol) == EulerCounts{16, 36, 24, 0, 0, 2});
  CHECK(back.mass_properties(tol).volume == Approx(2).epsilon(1e-12));
  const Mesh kept = back.mesh(tol);
  REQUIRE(kept.triangles.size() == read.triangles.size());
  REQUIRE(kept.normals.size() == kept.positions.size());
  REQUIRE(kept.uvs.size() == kept.positions.size());
  for (std::size_t t = 0; t < kept.triangles.size(); ++t)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::uint32_t v = kept.triangles[t][k], o = read.triangles[t][k];
      CHECK(kept.positions[v] == read.positions[o]);
      CHECK(kept.normals[v] == read.normals[o]);
      CHECK(kept.uvs[v] == read.uvs[o]);
    }
  std::filesystem::remove_all(dir);
}
