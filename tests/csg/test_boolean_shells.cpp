// Operands of several shells: a solid's shells nest alternately (a hollow inside a part, an
// island inside the hollow), and where they overlap without crossing (a box inside a box, both
// facing out; a box turned inward outside everything) no triangle pair says so. Such an operand
// is refused, naming its overlap; the engine took it for a solid before and counted the overlap
// twice (a union of volume 1008 for a solid of 1000) or failed with an internal error.
#include <catch2/catch.hpp>

#include <array>
#include <vector>

#include "csg/boolean.h"
#include "tests/support/cgal_oracle.h"

using namespace wedge;
using namespace wedge::testing;

namespace {

// The box [a, b]^3, facing out (or in).
void add_box(Mesh& m, double a, double b, bool inward = false) {
  const auto o = static_cast<std::uint32_t>(m.positions.size());
  for (double z : {a, b})
    for (auto [x, y] : {std::array<double, 2>{a, a}, {b, a}, {b, b}, {a, b}}) m.positions.push_back(Vec3(x, y, z));
  const std::array<std::array<std::uint32_t, 3>, 12> t = {{{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                                          {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}}};
  for (auto T : t) {
    if (inward) std::swap(T[1], T[2]);
    m.triangles.push_back({T[0] + o, T[1] + o, T[2] + o});
  }
}

// A tetrahedron with its apex at the origin and its other corners (-1, -2, -2) s, (-2, -1, -2) s,
// (-2, -2, -1) s (s = 1: out of the box [0, 10]^3 from its corner, s = -1: into it), facing out.
void add_tetra(Mesh& m, double s) {
  const auto o = static_cast<std::uint32_t>(m.positions.size());
  m.positions.push_back(Vec3(0, 0, 0));
  m.positions.push_back(Vec3(-1, -2, -2) * s);
  m.positions.push_back(Vec3(-2, -1, -2) * s);
  m.positions.push_back(Vec3(-2, -2, -1) * s);
  std::vector<std::array<std::uint32_t, 3>> t = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  for (auto T : t) {
    if (s > 0) std::swap(T[1], T[2]);
    m.triangles.push_back({T[0] + o, T[1] + o, T[2] + o});
  }
}

Mesh probe() {  // a unit cube across the big box's face x = 0
  Mesh m;
  add_box(m, 0, 1);
  for (auto& p : m.positions) p += Vec3(-0.5, 5, 5);
  return m;
}

}  // namespace

TEST_CASE("boolean: an operand whose shells overlap without crossing is refused", "[boolean][shells]") {
  const Mesh c = probe();
  auto refused = [&](const Mesh& m, const char* what) {
    CHECK(closed_manifold_outward(m).empty());
    CHECK_FALSE(exact_self_intersects(m));
    CHECK_THAT(nested_shells(m), Catch::Contains("shells overlap"));  // (the test support's own check)
    for (BooleanOp op : {BooleanOp::Union, BooleanOp::Difference, BooleanOp::Intersection})
      CHECK_THROWS_WITH(boolean(op, {&m, &c}), Catch::Contains("the first operand has shells that overlap") && Catch::Contains(what));
    CHECK_THROWS_WITH(boolean(BooleanOp::Union, {&c, &m}), Catch::Contains("the second operand has shells that overlap"));
  };
  Mesh nested;  // a box inside a box, both facing out
  add_box(nested, 0, 10);
  add_box(nested, 2, 4);
  refused(nested, "the shell through (2, 2, 2) lies inside another of its shells that faces the same way");
  Mesh hollow_nowhere;  // a box facing in, outside the other
  add_box(hollow_nowhere, 0, 10);
  add_box(hollow_nowhere, 20, 22, true);
  refused(hollow_nowhere, "faces inward but lies outside every other shell");
  Mesh in_island;  // a box inside the island inside the hollow of a box
  add_box(in_island, 0, 10);
  add_box(in_island, 2, 8, true);
  add_box(in_island, 4, 6);
  add_box(in_island, 4.5, 5.5);
  refused(in_island, "lies inside another of its shells");
  Mesh corner;  // a tetrahedron inside the box, touching it at its corner alone
  add_box(corner, 0, 10);
  add_tetra(corner, -1);
  refused(corner, "lies inside another of its shells");
}

TEST_CASE("boolean: operands whose shells nest as a solid's do are taken as they are", "[boolean][shells]") {
  const Mesh c = probe();  // volume 1, half of it inside the box [0, 10]^3
  struct Case {
    Mesh m;
    double volume;  // of the operand
    double inside;  // of the probe's half x > 0, inside the operand's solid
  };
  std::vector<Case> cases(4);
  add_box(cases[0].m, 0, 10);
  add_box(cases[0].m, 2, 4, true);  // a hollow
  cases[0].volume = 1000 - 8;
  cases[0].inside = 0.5;
  add_box(cases[1].m, 0, 10);
  add_box(cases[1].m, 2, 8, true);
  add_box(cases[1].m, 4, 6);  // an island in the hollow
  cases[1].volume = 1000 - 216 + 8;
  cases[1].inside = 0.5;
  add_box(cases[2].m, 0, 10);
  add_box(cases[2].m, 20, 22);  // apart
  cases[2].volume = 1000 + 8;
  cases[2].inside = 0.5;
  add_box(cases[3].m, 0, 10);
  add_tetra(cases[3].m, 1);  // outside, touching at the corner
  cases[3].volume = 1000 + 5.0 / 6;
  cases[3].inside = 0.5;
  for (const auto& k : cases) {
    CHECK(k.m.volume() == Approx(k.volume).epsilon(1e-12));
    CHECK(nested_shells(k.m).empty());
    BooleanResult u, d;
    REQUIRE_NOTHROW(u = boolean(BooleanOp::Union, {&k.m, &c}));
    CHECK(u.mesh.volume() == Approx(k.volume + 1 - k.inside).epsilon(1e-12));
    CHECK(result_defect(u.mesh).empty());
    REQUIRE_NOTHROW(d = boolean(BooleanOp::Difference, {&k.m, &c}));
    CHECK(d.mesh.volume() == Approx(k.volume - k.inside).epsilon(1e-12));
    CHECK(result_defect(d.mesh).empty());
  }
}
