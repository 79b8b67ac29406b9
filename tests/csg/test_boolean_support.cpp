// The boolean engine's references, checked before they judge anything: the operand generators
// give closed outward meshes with the volumes they claim, the closed forms of the degenerate cases
// agree with CGAL's exact corefinement, and the validity checks catch each defect they name.
#include <catch2/catch.hpp>

#include <cmath>

#include "kernel/transform.h"
#include "tests/support/boolean_cases.h"
#include "tests/support/cgal_oracle.h"

using namespace wedge;
using namespace wedge::testing;

namespace {
void require_valid_operand(const Mesh& m) {
  INFO(closed_manifold_outward(m));
  REQUIRE(closed_manifold_outward(m).empty());
  std::string where;
  INFO(where);
  REQUIRE_FALSE(exact_self_intersects(m, &where));
  // The long-double volume is the exact one to far better than the tests' 1e-9.
  REQUIRE(polyhedron_volume(m) == Approx(exact_volume(m)).epsilon(1e-14));
}
}  // namespace

TEST_CASE("boolean support: generators give closed outward self-intersection-free meshes", "[boolean_support]") {
  const Mesh b = box_mesh({1, 2, 3}, {0.5, 2, 4});
  require_valid_operand(b);
  REQUIRE(polyhedron_volume(b) == 4.0);
  require_valid_operand(box_mesh({0, 0, 0}, {1, 2, 3}, rotate(33, Vec3(1, 1, 0))));

  const Mesh uv = uv_sphere({0.5, 0, 0}, 2, 4096);
  require_valid_operand(uv);
  CHECK(std::abs(int(uv.triangle_count()) - 4096) < 300);
  // The polyhedron is inscribed: a little less than the ball.
  CHECK(polyhedron_volume(uv) < 4 * kPi / 3 * 8);
  CHECK(polyhedron_volume(uv) > 0.99 * 4 * kPi / 3 * 8);

  const Mesh ico = icosphere({0, 0, 0}, 1, 5000);
  require_valid_operand(ico);
  CHECK(ico.triangle_count() == 5120);

  const Mesh cyl = cylinder_mesh(0.5, -1, 2, 40, rotate(20, Vec3(0, 1, 1)));
  require_valid_operand(cyl);
  // A regular 40-gon prism: (n/2) r^2 sin(2 pi / n) h.
  CHECK(polyhedron_volume(cyl) == Approx(20 * 0.25 * std::sin(2 * kPi / 40) * 3).epsilon(1e-12));

  for (const Mesh& m : classic_figure_operands(1000, 32)) require_valid_operand(m);
  for (const Mesh& m : overlapping_spheres(1000)) require_valid_operand(m);
  const auto lattice = sphere_lattice(2, 320);
  REQUIRE(lattice.size() == 8);
  for (const Mesh& m : lattice) require_valid_operand(m);
}

TEST_CASE("boolean support: triangle counts for the benchmark's sphere sizes", "[boolean_support]") {
  // About 4k, 65k and 1M triangles; 1M is only counted, not checked for intersections here.
  for (int n : {4096, 65536, 1048576}) {
    const Mesh s = uv_sphere({0, 0, 0}, 1, n);
    INFO(n);
    CHECK(std::abs(double(s.triangle_count()) / n - 1) < 0.05);
    CHECK(closed_manifold_outward(s).empty());
  }
}

TEST_CASE("boolean support: degenerate cases' operands are valid and their closed forms match CGAL",
          "[boolean_support]") {
  for (const BooleanCase& c : degenerate_cases()) {
    INFO(c.name);
    REQUIRE(c.operands.size() == 2);
    for (const Mesh& m : c.operands) require_valid_operand(m);
    for (BooleanOp op : {BooleanOp::Union, BooleanOp::Intersection, BooleanOp::Difference}) {
      INFO("op " << int(op));
      const OracleResult r = oracle_boolean(op, c.operands[0], c.operands[1]);
      if (op == BooleanOp::Union && c.nonmanifold_union) {
        // CGAL's corefinement returns only 2-manifold results; where it does answer, it must agree.
        if (!r.ok) continue;
      }
      INFO(r.why);
      REQUIRE(r.ok);
      if (const auto want = c.expected(op)) {
        const double scale = std::max(std::abs(*want), 1e-300);
        CHECK(std::abs(r.volume - *want) <= 1e-12 * scale);
      }
    }
  }
}

TEST_CASE("boolean support: plate, Menger sponge and classic figure closed forms match CGAL", "[boolean_support]") {
  const auto plate = plate_and_cylinders(2, 16);
  REQUIRE(plate.size() == 5);
  std::vector<const Mesh*> ops;
  for (const Mesh& m : plate) ops.push_back(&m);
  const OracleResult p = oracle_nary(BooleanOp::Difference, ops);
  REQUIRE(p.ok);
  CHECK(p.volume == Approx(plate_with_holes_volume(plate)).epsilon(1e-13));

  for (int level : {1, 2}) {
    const auto menger = menger_operands(level);
    REQUIRE(menger.size() == (level == 1 ? 4u : 31u));
    ops.clear();
    for (const Mesh& m : menger) ops.push_back(&m);
    const OracleResult r = oracle_nary(BooleanOp::Difference, ops);
    INFO(r.why);
    REQUIRE(r.ok);
    CHECK(r.volume == menger_volume(level));
  }
  REQUIRE(menger_operands(3).size() == 1 + 3 * (1 + 9 + 81));

  // The figure is a proper solid strictly smaller than cube n sphere.
  const auto fig = classic_figure_operands(1000, 32);
  const OracleResult f = oracle_sequence(fig[0], {{BooleanOp::Intersection, &fig[1]},
                                                  {BooleanOp::Difference, &fig[2]},
                                                  {BooleanOp::Difference, &fig[3]},
                                                  {BooleanOp::Difference, &fig[4]}});
  REQUIRE(f.ok);
  const OracleResult cs = oracle_boolean(BooleanOp::Intersection, fig[0], fig[1]);
  REQUIRE(cs.ok);
  CHECK(f.volume > 0.2 * cs.volume);
  CHECK(f.volume < cs.volume);
}

TEST_CASE("boolean support: the validity checks name each defect", "[boolean_support]") {
  const Mesh b = box_mesh({0, 0, 0}, {1, 1, 1});
  REQUIRE(closed_manifold_outward(b).empty());

  Mesh open = b;
  open.triangles.pop_back();
  open.face_ids.pop_back();
  CHECK_THAT(closed_manifold_outward(open), Catch::Contains("border edge"));

  Mesh flipped = b;
  std::swap(flipped.triangles[3][0], flipped.triangles[3][1]);
  CHECK_THAT(closed_manifold_outward(flipped), Catch::Contains("orientation"));

  Mesh inward = b;
  for (auto& t : inward.triangles) std::swap(t[0], t[1]);
  CHECK_THAT(closed_manifold_outward(inward), Catch::Contains("not positive"));
  // The result of a unit box minus five copies turned by 1e-7 or less (found by a fuzz run): two
  // slivers at opposite corners, each of volume 2.9e-28, far below the error of a sum of terms
  // near 1 (in doubles the total was not positive), so the orientation is judged by the exact sign.
  Mesh sliver;
  for (const Point3& p : {Point3(1, 0.999999999718162, -1),
                          Point3(0.99999999998759659, 1, -1),
                          Point3(1, 1, -1),
                          Point3(0.99999999998759659, 0.999999999718162, -1),
                          Point3(-1, -0.999999999718162, 1),
                          Point3(-1, -1, 1),
                          Point3(-0.99999999998759659, -1, 1),
                          Point3(-0.99999999998759659, -0.999999999718162, 1),
                          Point3(-0.99999999999172073, -1, 0.99999999999293421),
                          Point3(-1, -1, 0.99999987567346382),
                          Point3(-0.99999999999172051, -1, 0.99999987567346382),
                          Point3(-0.99999999998759659, -1, 0.9999999999929341),
                          Point3(0.99999999999172073, 1, -0.99999999999293421),
                          Point3(1, 1, -0.99999987567346382),
                          Point3(0.99999999998759659, 1, -0.9999999999929341),
                          Point3(0.99999999999172051, 1, -0.99999987567346382),
                          Point3(-1, -0.999999999718162, 0.99999987567346393),
                          Point3(1, 0.999999999718162, -0.99999987567346393),
                          Point3(-0.99999999998759659, -0.999999999718162, 0.9999999999929341),
                          Point3(0.99999999998759659, 0.999999999718162, -0.9999999999929341),
                          Point3(0.99999999999172051, 0.999999999718162, -0.99999987567346393),
                          Point3(-0.99999999999172051, -0.999999999718162, 0.99999987567346393),
                          Point3(0.99999999999172062, 0.999999999718162, -0.9999999999929341),
                          Point3(-0.99999999999172062, -0.999999999718162, 0.9999999999929341)})
    sliver.add_vertex(p);
  const std::uint32_t faces[40][3] = {{0, 1, 2}, {3, 1, 0}, {4, 5, 6}, {7, 4, 6}, {8, 6, 5}, {8, 5, 9},
                                      {8, 9, 10}, {11, 6, 8}, {12, 2, 1}, {12, 13, 2}, {14, 12, 1}, {12, 15, 13},
                                      {5, 16, 9}, {16, 5, 4}, {17, 0, 2}, {2, 13, 17}, {11, 7, 6}, {11, 18, 7},
                                      {14, 1, 3}, {14, 3, 19}, {20, 13, 15}, {13, 20, 17}, {9, 21, 10}, {9, 16, 21},
                                      {19, 22, 14}, {14, 22, 12}, {18, 11, 23}, {11, 8, 23}, {21, 23, 8}, {8, 10, 21},
                                      {20, 12, 22}, {12, 20, 15}, {4, 23, 16}, {23, 21, 16}, {7, 23, 4}, {18, 23, 7},
                                      {0, 17, 22}, {3, 0, 22}, {19, 3, 22}, {22, 17, 20}};
  for (const auto& f : faces) sliver.add_triangle(f[0], f[1], f[2]);
  REQUIRE_FALSE(polyhedron_volume(sliver) > 0);  // in doubles, not positive
  CHECK(closed_manifold_outward(sliver).empty());
  Mesh turned = sliver;
  for (auto& t : turned.triangles) std::swap(t[0], t[1]);
  CHECK_THAT(closed_manifold_outward(turned), Catch::Contains("not positive"));

  // Two cubes sharing one vertex index: closed, but the vertex has two fans.
  Mesh pinched = b;
  Mesh other = box_mesh({1, 1, 1}, {1, 1, 1});
  const auto offset = static_cast<std::uint32_t>(pinched.positions.size());
  pinched.positions.insert(pinched.positions.end(), other.positions.begin(), other.positions.end());
  for (auto t : other.triangles) {
    for (auto& v : t) v = (v == 0) ? 7 : v + offset;  // other's corner (1,1,1) is b's vertex 7
    pinched.triangles.push_back(t);
  }
  pinched.face_ids.clear();
  CHECK_THAT(closed_manifold_outward(pinched), Catch::Contains("non-manifold vertex"));

  // Three triangles on one edge.
  Mesh fin = b;
  const auto apex = fin.add_vertex({0.5, -1, 0.5});
  fin.add_triangle(fin.triangles[0][0], fin.triangles[0][1], apex);
  CHECK_THAT(closed_manifold_outward(fin), Catch::Contains("non-manifold edge"));

  // The same two cubes with the corner kept as two vertices: valid, and they meet only there.
  Mesh touching = b;
  touching.append(other);
  CHECK(closed_manifold_outward(touching).empty());
  CHECK_FALSE(exact_self_intersects(touching));
  // Sharing an edge (two coincident vertex pairs) is fine too; sharing part of a face is not.
  Mesh edge = b;
  edge.append(box_mesh({1, 1, 0}, {1, 1, 1}));
  CHECK_FALSE(exact_self_intersects(edge));
  Mesh face = b;
  face.append(box_mesh({1, 0.5, 0}, {1, 1, 1}));
  std::string where;
  CHECK(exact_self_intersects(face, &where));
  CHECK_THAT(where, Catch::Contains("meets"));

  Mesh crossing = b;
  crossing.append(box_mesh({0.5, 0.5, 0.5}, {1, 1, 1}));
  CHECK(exact_self_intersects(crossing));
  // Overlap by one ulp is found (exact arithmetic, no tolerance).
  Mesh ulp = b;
  ulp.append(box_mesh({std::nextafter(1.0, 0.0), 0, 0}, {1, 1, 1}));
  CHECK(exact_self_intersects(ulp));
  Mesh flat = b;
  flat.add_triangle(0, 1, 1);  // a repeated index is caught by the combinatorial check
  CHECK_FALSE(closed_manifold_outward(flat).empty());
  Mesh degenerate = b;
  const auto mid = degenerate.add_vertex({0.5, 0, 0});
  degenerate.triangles[4] = {0, mid, 1};  // zero area, on the -y face's edge
  where.clear();
  CHECK(exact_self_intersects(degenerate, &where));
}
