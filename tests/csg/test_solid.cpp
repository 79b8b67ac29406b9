#include <catch2/catch.hpp>

#include <cmath>

#include "csg/csg.h"

using namespace wedge;

namespace {
// An axis-aligned box [0,a]x[0,b]x[0,c] as 12 outward triangles.
Mesh box_mesh(double a, double b, double c) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.add_vertex({(i & 1) ? a : 0, (i & 2) ? b : 0, (i & 4) ? c : 0});
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int f = 0; f < 6; ++f) {
    const int* q = quads[f];
    m.add_triangle(q[0], q[1], q[2], f);
    m.add_triangle(q[0], q[2], q[3], f);
  }
  return m;
}

// A square torus: a 4x4 grid of quads on a ring, the simplest closed genus-1 mesh.
Mesh square_torus() {
  Mesh m;
  const int n = 4, k = 4;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      double u = 2 * kPi * i / n, v = 2 * kPi * j / k;
      m.add_vertex({(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + n) % n) * k + (j + k) % k); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < k; ++j) {
      m.add_triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.add_triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return m;
}
}  // namespace

TEST_CASE("mass properties of a box mesh are exact", "[solid][mass]") {
  MassProperties mp = mass_properties(box_mesh(2, 3, 4));
  CHECK(mp.volume == Approx(24).epsilon(1e-14));
  CHECK(mp.area == Approx(2 * (6 + 8 + 12)).epsilon(1e-14));
  CHECK((mp.centroid - Vec3(1, 1.5, 2)).norm() < 1e-14);
  // Box about its centroid: Ixx = m (b^2 + c^2) / 12 etc., products zero.
  CHECK(mp.inertia(0, 0) == Approx(24 * (9 + 16) / 12.0).epsilon(1e-13));
  CHECK(mp.inertia(1, 1) == Approx(24 * (4 + 16) / 12.0).epsilon(1e-13));
  CHECK(mp.inertia(2, 2) == Approx(24 * (4 + 9) / 12.0).epsilon(1e-13));
  CHECK(std::abs(mp.inertia(0, 1)) < 1e-12);
  CHECK(std::abs(mp.inertia(1, 2)) < 1e-12);
  // Moving the box moves the centroid but not the inertia about it.
  MassProperties moved = mass_properties(box_mesh(2, 3, 4).transformed(translate({10, -5, 7})));
  CHECK((moved.centroid - Vec3(11, -3.5, 9)).norm() < 1e-12);
  CHECK((moved.inertia - mp.inertia).cwiseAbs().maxCoeff() < 1e-10);
}

TEST_CASE("Euler counts of closed meshes: a box is a sphere, a ring a torus, two boxes two shells", "[solid][euler]") {
  EulerCounts box = euler_counts(box_mesh(1, 1, 1));
  CHECK(box == EulerCounts{8, 18, 12, 0, 0, 1});
  EulerCounts torus = euler_counts(square_torus());
  CHECK(torus.H == 1);
  CHECK(torus.S == 1);
  CHECK(torus.characteristic() == 0);
  Mesh two = box_mesh(1, 1, 1);
  two.append(box_mesh(1, 1, 1).transformed(translate({3, 0, 0})));
  CHECK(euler_counts(two) == EulerCounts{16, 36, 24, 0, 0, 2});
}

TEST_CASE("a mesh leaf rejects open, non-manifold and inside-out meshes with a clear message", "[solid][errors]") {
  Mesh open = box_mesh(1, 1, 1);
  open.triangles.pop_back();
  open.face_ids.pop_back();
  CHECK_THROWS_WITH(Solid::from_mesh(open, "part.stl"), Catch::StartsWith("part.stl: mesh is not closed"));
  Mesh twice = box_mesh(1, 1, 1);
  twice.add_triangle(twice.triangles[0][0], twice.triangles[0][1], twice.triangles[0][2]);
  CHECK_THROWS_WITH(Solid::from_mesh(twice), Catch::Contains("not 2-manifold"));
  Mesh inside_out = box_mesh(1, 1, 1);
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  CHECK_THROWS_WITH(Solid::from_mesh(inside_out), Catch::Contains("inside out"));
  CHECK_THROWS_WITH(Solid::from_mesh(Mesh()), Catch::Contains("no triangles"));
}

TEST_CASE("transformed solids: queries follow the transform, mirrors keep outward orientation", "[solid]") {
  Solid s = Solid::from_mesh(box_mesh(1, 2, 3));
  Tolerance tol;
  Solid t = s.transformed(translate({1, 1, 1})).transformed(scale({2, 2, 2}));
  CHECK(t.mass_properties(tol).volume == Approx(48));
  CHECK(t.bounds().min == Vec3(2, 2, 2));
  CHECK(t.bounds().max == Vec3(4, 6, 8));
  Solid m = s.transformed(reflect({1, 0, 0}));
  CHECK(m.mass_properties(tol).volume == Approx(6));
  CHECK(m.validate(tol).empty());
  CHECK(m.euler(tol) == EulerCounts{8, 18, 12, 0, 0, 1});
  CHECK_THROWS_WITH(s.transformed(scale({1, 0, 1})), Catch::Contains("singular"));
  CHECK_THROWS_WITH(s.transformed(perspective(60, 1, 1, 10)), Catch::Contains("projective"));
  CHECK(Solid().empty());
  CHECK(Solid().mesh(tol).empty());
}

TEST_CASE("a mesh split at its uv seams and normal creases is still a closed solid", "[solid][euler]") {
  // The box with every face's corners as vertices of their own (24 vertices, as a textured,
  // faceted cube is rendered): welded by position it is the closed 8-vertex box.
  Mesh welded = box_mesh(1, 2, 3), split;
  for (const auto& t : welded.triangles) {
    std::uint32_t v[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = split.add_vertex(welded.positions[t[k]]);
      split.normals.push_back(welded.triangle_normal(&t - welded.triangles.data()));
      split.uvs.emplace_back(k == 1, k == 2);
    }
    split.add_triangle(v[0], v[1], v[2]);
  }
  CHECK_THROWS_WITH(euler_counts(split), Catch::Contains("not closed"));  // by index it is open
  Solid s = Solid::from_mesh(split, "split box");
  Tolerance tol;
  CHECK(s.euler(tol) == EulerCounts{8, 18, 12, 0, 0, 1});
  CHECK(s.mass_properties(tol).volume == Approx(6));
  // The solid keeps the mesh as given: split vertices, their normals and uvs.
  Mesh back = s.mesh(tol);
  CHECK(back.vertex_count() == 36);
  CHECK(back.normals.size() == 36);
  CHECK(back.uvs.size() == 36);
  // An open mesh is still refused, split or not.
  Mesh open = split;
  open.triangles.pop_back();
  CHECK_THROWS_WITH(Solid::from_mesh(open, "open box"), Catch::Contains("not closed"));
}
