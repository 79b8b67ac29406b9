// Surfaces: exact quadrics, revolution of segments, derivatives vs central differences, swept
// frames, lofts through their sections, mesh chordal error measured on samples, trimming.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <memory>
#include <set>

#include "tessellate/surface_mesh.h"
#include "surfaces/surfaces.h"

using namespace wedge;

namespace {

void check_surface_derivatives(const Surface& s, double tol, int order = 2) {
  auto [u0, u1] = s.u_domain();
  auto [v0, v1] = s.v_domain();
  double hu = 1e-5 * (u1 - u0), hv = 1e-5 * (v1 - v0);
  for (int i = 1; i < 8; ++i)
    for (int j = 1; j < 8; ++j) {
      double u = u0 + (u1 - u0) * (i + 0.31) / 8.7, v = v0 + (v1 - v0) * (j + 0.17) / 8.5;
      for (int ku = 0; ku <= order; ++ku)
        for (int kv = 0; ku + kv <= order; ++kv) {
          Vec3 d = s.derivative(u, v, ku + 1, kv);
          Vec3 fd = (s.derivative(u + hu, v, ku, kv) - s.derivative(u - hu, v, ku, kv)) / (2 * hu);
          INFO("u=" << u << " v=" << v << " d/du of (" << ku << "," << kv << ")");
          CHECK((d - fd).norm() <= tol * (1 + d.norm()));
          d = s.derivative(u, v, ku, kv + 1);
          fd = (s.derivative(u, v + hv, ku, kv) - s.derivative(u, v - hv, ku, kv)) / (2 * hv);
          INFO("d/dv of (" << ku << "," << kv << ")");
          CHECK((d - fd).norm() <= tol * (1 + d.norm()));
        }
    }
}

// The largest distance between a mesh triangle and the surface at the same parameters, sampled at
// 15 barycentric points per triangle.
double chordal_error(const Surface& s, const Mesh& m) {
  double worst = 0;
  for (const auto& t : m.triangles)
    for (int a = 0; a <= 4; ++a)
      for (int b = 0; a + b <= 4; ++b) {
        double l0 = a / 4.0, l1 = b / 4.0, l2 = 1 - l0 - l1;
        Vec2 uv = l0 * m.uvs[t[0]] + l1 * m.uvs[t[1]] + l2 * m.uvs[t[2]];
        Point3 p = l0 * m.positions[t[0]] + l1 * m.positions[t[1]] + l2 * m.positions[t[2]];
        worst = std::max(worst, (s.eval(uv.x(), uv.y()) - p).norm());
      }
  return worst;
}

}  // namespace

TEST_CASE("NURBS sphere, cylinder, cone and torus are exact", "[quadrics]") {
  NurbsSurface sphere = nurbs_sphere(Point3(1, 2, 3), 2);
  NurbsSurface cyl = nurbs_cylinder(Point3(0, 0, 1), 1.5, 4);
  NurbsSurface cone = nurbs_cone(Point3(0, 0, 0), 2, 0.5, 3);
  NurbsSurface torus = nurbs_torus(Point3(0, 0, 0), 3, 1);
  for (int i = 0; i <= 40; ++i)
    for (int j = 0; j <= 40; ++j) {
      double u = i / 40.0, v = j / 40.0;
      Point3 p = sphere.eval(u, v);
      CHECK(std::abs((p - Point3(1, 2, 3)).norm() - 2) < 1e-14 * 4);
      p = cyl.eval(u, v);
      CHECK(std::abs(p.head<2>().norm() - 1.5) < 1e-14 * 2);
      CHECK(p.z() == Approx(1 + 4 * v).margin(1e-14));
      p = cone.eval(u, v);
      CHECK(std::abs(p.head<2>().norm() - (2 - 1.5 * p.z() / 3)) < 1e-14 * 3);
      p = torus.eval(u, v);
      CHECK(std::abs(Vec2(p.head<2>().norm() - 3, p.z()).norm() - 1) < 1e-14 * 4);
      // Outward normals.
      Vec3 n = sphere.normal(u, v);
      CHECK(n.dot(sphere.eval(u, v) - Point3(1, 2, 3)) > 1.99);
    }
  check_surface_derivatives(sphere, 1e-5);
  check_surface_derivatives(torus, 1e-5);
}

TEST_CASE("a surface of revolution of a segment is an exact cylinder or cone", "[revolution]") {
  auto side = std::make_shared<LineSegment>(Point3(2, 0, 0), Point3(2, 0, 5));
  RevolvedSurface cyl(side, Point3(0, 0, 0), Vec3::UnitZ(), 2 * kPi);
  auto slant = std::make_shared<LineSegment>(Point3(3, 0, 1), Point3(1, 0, 5));
  RevolvedSurface cone(slant, Point3(0, 0, 0), Vec3(0, 0, 2), 2 * kPi);
  // About an oblique axis: distance to the axis is linear along the segment.
  Vec3 axis = Vec3(1, 1, 1).normalized();
  Point3 base(0.5, -1, 0);
  auto seg = std::make_shared<LineSegment>(base + 2 * Vec3(1, -1, 0).normalized(), base + 2 * Vec3(1, -1, 0).normalized() + 3 * axis);
  RevolvedSurface oblique(seg, base, axis, kPi);
  for (int i = 0; i <= 50; ++i)
    for (int j = 0; j <= 50; ++j) {
      double u = 2 * kPi * i / 50, v = j / 50.0;
      Point3 p = cyl.eval(u, v);
      CHECK(std::abs(p.head<2>().norm() - 2) < 1e-14 * 2);
      CHECK(p.z() == Approx(5 * v).margin(1e-14));
      p = cone.eval(u, v);
      CHECK(std::abs(p.head<2>().norm() - (3 - 2 * v)) < 1e-14 * 3);
      CHECK(p.z() == Approx(1 + 4 * v).margin(1e-14));
      p = oblique.eval(u / 2, v);
      Vec3 d = p - base;
      CHECK(std::abs((d - d.dot(axis) * axis).norm() - 2) < 1e-14 * 4);
      CHECK(d.dot(axis) == Approx(3 * v).margin(1e-14));
    }
  check_surface_derivatives(cone, 1e-6);
  // The exact NURBS revolution of the same segment agrees with the trigonometric one in shape.
  NurbsSurface ncone = nurbs_revolve(to_nurbs(*slant), Point3(0, 0, 0), Vec3::UnitZ(), kPi / 3);
  for (int i = 0; i <= 20; ++i) {
    Point3 p = ncone.eval(i / 20.0, 0.25);
    CHECK(std::abs(p.head<2>().norm() - 2.5) < 1e-14 * 3);
    CHECK(std::atan2(p.y(), p.x()) >= -1e-15);
    CHECK(std::atan2(p.y(), p.x()) <= kPi / 3 + 1e-15);
  }
}

TEST_CASE("tensor-product surfaces: Bezier patch, bilinear, derivatives", "[nurbs]") {
  std::vector<std::vector<Point3>> grid(4, std::vector<Point3>(4));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) grid[i][j] = Point3(i, j, std::sin(i + 2.0 * j));
  NurbsSurface b = bezier_surface(grid);
  // Bernstein tensor formula at one point.
  auto B = [](int i, double t) {
    const double c[4] = {1, 3, 3, 1};
    return c[i] * std::pow(t, i) * std::pow(1 - t, 3 - i);
  };
  double u = 0.3, v = 0.8;
  Point3 expect = Point3::Zero();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) expect += B(i, u) * B(j, v) * grid[i][j];
  CHECK((b.eval(u, v) - expect).norm() < 1e-14);
  check_surface_derivatives(b, 1e-5);
  NurbsSurface bl = bilinear_surface(Point3(0, 0, 0), Point3(1, 0, 0), Point3(0, 1, 0), Point3(1, 1, 1));
  CHECK((bl.eval(0.5, 0.5) - Point3(0.5, 0.5, 0.25)).norm() < 1e-15);
  CHECK(bl.derivative(0.2, 0.7, 1, 1).isApprox(Vec3(0, 0, 1)));
  // A rational surface with uneven weights.
  std::vector<std::vector<double>> w(4, std::vector<double>(4, 1.0));
  w[1][2] = 3;
  w[2][1] = 0.4;
  NurbsSurface r(3, 3, grid, {0, 0, 0, 0, 1, 1, 1, 1}, {0, 0, 0, 0, 1, 1, 1, 1}, w);
  check_surface_derivatives(r, 1e-5);
  CHECK_THROWS_WITH(NurbsSurface(3, 3, grid, {0, 0, 0, 0, 1, 1, 1, 1}, {0, 0, 0, 1, 0.5, 1, 1, 1}),
                    Catch::Contains("vknots must be non-decreasing"));
  w[0][0] = 0;
  CHECK_THROWS_WITH(NurbsSurface(3, 3, grid, {0, 0, 0, 0, 1, 1, 1, 1}, {0, 0, 0, 0, 1, 1, 1, 1}, w),
                    Catch::Contains("weight [1][1]"));
}

TEST_CASE("swept frames stay orthonormal and do not flip", "[sweep]") {
  SECTION("helix") {
    // A helix as an interpolating spline through its points: a general 3D path.
    std::vector<Point3> pts;
    for (int i = 0; i <= 60; ++i) {
      double a = i * 0.25;
      pts.emplace_back(2 * std::cos(a), 2 * std::sin(a), 0.3 * a);
    }
    NurbsCurve helix = interpolate_nurbs(pts, 3);
    auto frames = rotation_minimizing_frames(helix, 400);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const Frame& f = frames[i];
      CHECK(std::abs(f.t.norm() - 1) < 1e-12);
      CHECK(std::abs(f.r.norm() - 1) < 1e-12);
      CHECK(std::abs(f.s.norm() - 1) < 1e-12);
      CHECK(std::abs(f.t.dot(f.r)) < 1e-12);
      CHECK(std::abs(f.r.dot(f.s)) < 1e-12);
      CHECK((f.r.cross(f.s) - f.t).norm() < 1e-12);
      if (i > 0) CHECK(f.r.dot(frames[i - 1].r) > 0.99);  // no flip between neighbours
    }
  }
  SECTION("planar S-curve: the frame stays put through the inflection") {
    BezierCurve s({{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {4, 4, 0}});
    auto frames = rotation_minimizing_frames(s, 300);
    // For a planar curve the RMF keeps the plane normal as one of its axes.
    for (const Frame& f : frames) {
      CHECK(std::abs(std::abs(f.s.z()) - 1) < 1e-9);
      CHECK(f.s.z() * frames[0].s.z() > 0);
      CHECK(std::abs(f.t.dot(f.r)) < 1e-12);
    }
    // The Frenet normal flips at the inflection; the RMF does not.
    auto swept = SweptSurface(std::make_shared<CircularArc>(Point3(0, 0, 0), 0.2, 0, 2 * kPi),
                              std::make_shared<BezierCurve>(s));
    for (int i = 0; i <= 100; ++i) {
      Frame a = swept.frame(i / 100.0), b = swept.frame(i / 100.0 + 0.0037);
      CHECK(a.r.dot(b.r) > 0.99);
      CHECK((swept.eval(0, i / 100.0) - a.origin).norm() == Approx(0.2).epsilon(1e-12));
    }
    check_surface_derivatives(swept, 1e-6, 1);  // analytic v-derivatives (orders 1, 2) vs differences
  }
}

TEST_CASE("extruded and lofted surfaces", "[loft]") {
  auto arc = std::make_shared<NurbsCurve>(nurbs_circle(Point3(0, 0, 0), 1));
  ExtrudedSurface e(arc, Vec3(0, 0, 3));
  CHECK((e.eval(0.3, 0.5) - (arc->eval(0.3) + Vec3(0, 0, 1.5))).norm() < 1e-15);
  check_surface_derivatives(e, 1e-5);
  std::vector<CurvePtr> sections{
      std::make_shared<NurbsCurve>(nurbs_circle(Point3(0, 0, 0), 1)),
      std::make_shared<NurbsCurve>(nurbs_circle(Point3(0, 0, 1), 2)),
      std::make_shared<CircularArc>(Point3(0, 0, 2), 1.5, 0, 2 * kPi),
      std::make_shared<NurbsCurve>(nurbs_circle(Point3(0.5, 0, 3), 1)),
  };
  LoftedSurface loft(sections);
  for (std::size_t i = 0; i < sections.size(); ++i)
    for (int j = 0; j <= 20; ++j) {
      double u = j / 20.0;
      auto [a, b] = sections[i]->domain();
      CHECK((loft.eval(u, i / 3.0) - sections[i]->eval(a + u * (b - a))).norm() < 1e-14);
    }
  check_surface_derivatives(loft, 1e-5);
  CHECK_THROWS_WITH(LoftedSurface({sections[0]}), Catch::Contains("at least 2 sections"));
}

TEST_CASE("mesh chordal error is below the requested tolerance", "[mesh]") {
  auto slant = std::make_shared<NurbsCurve>(interpolate_nurbs({{1, 0, 0}, {2, 0, 1}, {1.5, 0, 2}, {2.5, 0, 3}}, 3));
  std::vector<std::unique_ptr<Surface>> surfaces;
  surfaces.push_back(std::make_unique<NurbsSurface>(nurbs_sphere(Point3(0, 0, 0), 2)));
  surfaces.push_back(std::make_unique<NurbsSurface>(nurbs_torus(Point3(0, 0, 0), 3, 1)));
  surfaces.push_back(std::make_unique<RevolvedSurface>(slant, Point3(0, 0, 0), Vec3::UnitZ(), 2 * kPi));
  surfaces.push_back(std::make_unique<Plane>(Point3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY()));
  for (const auto& s : surfaces)
    for (double tol : {0.05, 0.005}) {
      Mesh m = tessellate(*s, tol, 7);
      REQUIRE_NOTHROW(m.check());
      REQUIRE(m.uvs.size() == m.positions.size());
      REQUIRE(m.normals.size() == m.positions.size());
      CHECK(m.face_ids.front() == 7);
      double err = chordal_error(*s, m);
      CHECK(err <= tol);
      if (s.get() != surfaces[3].get()) CHECK(err > tol / 50);  // and not absurdly fine (a plane is exact)
    }
  Mesh plane = tessellate(*surfaces[3], 0.01);
  CHECK(plane.area() == Approx(1).epsilon(1e-14));
  Mesh sphere = tessellate(*surfaces[0], 0.001);
  CHECK(sphere.area() == Approx(16 * kPi).epsilon(2e-3));
  CHECK(std::abs(sphere.volume()) == Approx(32 * kPi / 3).epsilon(3e-3));
  CHECK(sphere.volume() > 0);  // outward orientation
  for (std::size_t i = 0; i < sphere.positions.size(); ++i) CHECK(sphere.normals[i].dot(sphere.positions[i]) > 1.99);
}

TEST_CASE("trimming loops remove the outside of the parameter domain", "[trim]") {
  Plane p(Point3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY());
  p.trims.push_back({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  p.trims.push_back({{{0.25, 0.25}, {0.25, 0.75}, {0.75, 0.75}, {0.75, 0.25}}});  // a hole
  CHECK(p.inside_trim(0.1, 0.1));
  CHECK_FALSE(p.inside_trim(0.5, 0.5));
  Mesh m = tessellate(p, 0.01);
  CHECK(m.area() == Approx(0.75).epsilon(1e-12));
  // A hole off any grid line: the mesh follows the loop to within about the tolerance, so the
  // area converges to 1 - 0.4^2 as the tolerance falls (perimeter 1.6 x band of one cell).
  Plane q(Point3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY());
  q.trims.push_back({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}});
  q.trims.push_back({{{0.3, 0.3}, {0.3, 0.7}, {0.7, 0.7}, {0.7, 0.3}}});
  for (double tol : {0.02, 0.005}) {
    Mesh mq = tessellate(q, tol);
    INFO("tolerance " << tol << ", area " << mq.area());
    CHECK(std::abs(mq.area() - 0.84) <= 1.6 * tol);
    for (const auto& t : mq.triangles) {  // no triangle lies in the hole
      Point3 c = (mq.positions[t[0]] + mq.positions[t[1]] + mq.positions[t[2]]) / 3;
      CHECK_FALSE((c.x() > 0.3 + tol && c.x() < 0.7 - tol && c.y() > 0.3 + tol && c.y() < 0.7 - tol));
    }
  }
}

TEST_CASE("Newell's teapot: 32 patches, outward, watertight where patches meet", "[teapot]") {
  std::vector<NurbsSurface> pot = teapot();
  REQUIRE(pot.size() == 32);
  // Body and rim patches (0..11) face away from the z axis.
  for (int i = 0; i < 12; ++i) {
    Point3 p = pot[i].eval(0.5, 0.5);
    Vec3 n = pot[i].normal(0.5, 0.5);
    CHECK(n.head<2>().dot(p.head<2>()) > 0);
  }
  // The knob top faces up, the bottom faces down.
  CHECK(pot[20].normal(0.5, 0.1).z() > 0);  // the flat top of the knob
  CHECK(pot[28].normal(0.5, 0.1).z() < 0);
  // Neighbouring body patches share their boundary curves exactly.
  for (int i = 0; i < 12; ++i) {
    int next = (i % 4 == 3) ? i - 3 : i + 1;
    for (int k = 0; k <= 10; ++k) {
      double s = k / 10.0;
      CHECK((pot[i].eval(1, s) - pot[next].eval(0, s)).norm() < 1e-14);
    }
  }
  // The pot fits its classic bounding box.
  Mesh all;
  for (std::size_t i = 0; i < pot.size(); ++i) all.append(tessellate(pot[i], 0.01, int(i)));
  Box3 b = all.bounds();
  CHECK(b.min.z() == Approx(0).margin(1e-12));
  CHECK(b.max.z() == Approx(3.15).margin(1e-3));
  CHECK(b.max.x() == Approx(3.45).margin(0.03));  // spout tip
  CHECK(all.volume() > 0);
}

// --- Welded (closed) meshes ---

namespace {

// Every welded triangle is non-degenerate and its normal agrees with the vertex normals' side.
void check_welded(const Mesh& m) {
  REQUIRE_NOTHROW(m.check());
  std::size_t degenerate = 0, flipped = 0;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] || !(m.triangle_normal(t).norm() > 0.5)) {
      ++degenerate;
      continue;
    }
    double side = 0;
    for (auto i : tri) side += m.triangle_normal(t).dot(m.normals[i]);
    if (!(side > 0)) ++flipped;
  }
  CHECK(degenerate == 0);
  CHECK(flipped == 0);
}

}  // namespace

TEST_CASE("welded mesh of the NURBS sphere is a closed genus-0 surface with the right volume", "[surfaces][mesh]") {
  const double r = 2, tol = 1e-3;
  Point3 c(1, -2, 0.5);
  NurbsSurface s = nurbs_sphere(c, r);
  Mesh m = tessellate_welded(s, tol);
  check_welded(m);
  EulerCounts e = euler_counts(m);
  CHECK(e.V - e.E + e.F == 2);
  CHECK(e.S == 1);
  CHECK(e.H == 0);
  // Vertices on the sphere, so the mesh is inside it; the gap is at most area x tolerance.
  double exact = 4.0 / 3.0 * M_PI * r * r * r;
  CHECK(m.volume() > 0);
  CHECK(m.volume() <= exact);
  CHECK(exact - m.volume() <= 4 * M_PI * r * r * tol);
  // Pole vertices carry the limit normal (+-Z), every vertex normal is radial.
  int poles = 0;
  double worst = 1;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    Vec3 radial = (m.positions[i] - c).normalized();
    worst = std::min(worst, m.normals[i].dot(radial));
    if (std::abs(std::abs(radial.z()) - 1) < 1e-12) {
      ++poles;
      CHECK(m.normals[i].dot(radial) > 1 - 1e-9);
    }
  }
  CHECK(worst > 1 - 1e-6);
  CHECK(poles == 2);
  // The render mesh keeps the seam and pole rows: it has more vertices and is open.
  Mesh render = tessellate(s, tol);
  CHECK(render.positions.size() > m.positions.size());
  CHECK_THROWS_AS(euler_counts(render), Error);
}

TEST_CASE("welded mesh of the NURBS torus is closed with genus 1", "[surfaces][mesh]") {
  const double R = 3, r = 1, tol = 1e-3;
  Mesh m = tessellate_welded(nurbs_torus(Point3(0, 0, 1), R, r), tol);
  check_welded(m);
  EulerCounts e = euler_counts(m);
  CHECK(e.V - e.E + e.F == 0);
  CHECK(e.H == 1);
  double exact = 2 * M_PI * M_PI * R * r * r, area = 4 * M_PI * M_PI * R * r;
  CHECK(m.volume() > 0);
  CHECK(std::abs(exact - m.volume()) <= area * tol);
}

TEST_CASE("welded meshes of revolved closed profiles are closed and outward", "[surfaces][mesh]") {
  const double tol = 1e-3;
  SECTION("a circle revolved about Z (a torus), either direction of the profile") {
    for (double sign : {1.0, -1.0}) {
      auto circle = std::make_shared<CircularArc>(Point3(2.5, 0, 0), 0.75, 0, 2 * M_PI, sign * Vec3::UnitY());
      RevolvedSurface s(circle, Point3(0, 0, 0), Vec3::UnitZ(), 2 * M_PI);
      Mesh m = tessellate_welded(s, tol);
      check_welded(m);
      EulerCounts e = euler_counts(m);
      CHECK(e.V - e.E + e.F == 0);
      CHECK(e.H == 1);
      double exact = 2 * M_PI * M_PI * 2.5 * 0.75 * 0.75, area = 4 * M_PI * M_PI * 2.5 * 0.75;
      CHECK(m.volume() > 0);
      CHECK(std::abs(exact - m.volume()) <= area * tol);
    }
  }
  SECTION("a profile from the axis to the axis (poles at both ends)") {
    // A spline bulb: starts and ends on the Z axis.
    auto profile = std::make_shared<NurbsCurve>(interpolate_nurbs(
        {Point3(0, 0, 0), Point3(1, 0, 0.3), Point3(1.2, 0, 1), Point3(0.6, 0, 1.8), Point3(0, 0, 2)}, 3));
    RevolvedSurface s(profile, Point3(0, 0, 0), Vec3::UnitZ(), 2 * M_PI);
    Mesh m = tessellate_welded(s, tol);
    check_welded(m);
    EulerCounts e = euler_counts(m);
    CHECK(e.V - e.E + e.F == 2);
    CHECK(m.volume() > 0);
    // Pappus by quadrature: V = pi * integral x^2 dz over the profile.
    double exact = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
      double t = (i + 0.5) / n;
      Point3 p = profile->eval(t);
      exact += M_PI * p.x() * p.x() * profile->derivative(t, 1).z() / n;
    }
    exact = std::abs(exact);
    CHECK(std::abs(exact - m.volume()) <= 2 * M_PI * 1.2 * 2.5 * tol);
  }
}

TEST_CASE("welded mesh leaves an open surface open and merges nothing on a plane", "[surfaces][mesh]") {
  Plane p(Point3(0, 0, 0), Vec3::UnitX(), Vec3::UnitY());
  Mesh a = tessellate(p, 0.01), b = tessellate_welded(p, 0.01);
  CHECK(a.positions.size() == b.positions.size());
  CHECK(a.triangles.size() == b.triangles.size());
  // A half cylinder (open in u): no seam, the ends stay open.
  auto half = std::make_shared<CircularArc>(Point3(0, 0, 0), 1, 0, M_PI);
  ExtrudedSurface e(half, Vec3(0, 0, 1));
  CHECK_THROWS_AS(euler_counts(tessellate_welded(e, 1e-3)), Error);
}

TEST_CASE("swept surface v-derivatives are analytic and agree with differences of eval", "[swept]") {
  // A helix path (constant curvature and torsion) and a profile off-centre with a z component, so
  // every term of S = O + x r + y s + z t is exercised.
  struct Helix : Curve {
    std::pair<double, double> domain() const override { return {0.0, 4 * M_PI}; }
    Point3 eval(double t) const override { return Point3(2 * std::cos(t), 2 * std::sin(t), 0.5 * t); }
    Vec3 derivative(double t, int k) const override {
      if (k == 0) return eval(t);
      double c = std::cos(t + k * M_PI / 2), s = std::sin(t + k * M_PI / 2);
      return Vec3(2 * c, 2 * s, k == 1 ? 0.5 : 0.0);
    }
  };
  auto profile = std::make_shared<BezierCurve>(std::vector<Point3>{{0.3, 0, 0.1}, {0, 0.4, 0}, {-0.3, 0.1, -0.1}});
  for (CurvePtr path : {CurvePtr(std::make_shared<Helix>()),
                        CurvePtr(std::make_shared<BezierCurve>(std::vector<Point3>{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {4, 4, 0}}))}) {
    SweptSurface s(profile, path);
    auto [v0, v1] = s.v_domain();
    const double h = 1e-4 * (v1 - v0), k = 1e-6 * (v1 - v0);  // k: first differences
    double worst1 = 0, worst2 = 0, worst_mixed = 0;
    for (int i = 1; i < 40; ++i)
      for (double u : {0.0, 0.37, 1.0}) {
        double v = v0 + (v1 - v0) * (i + 0.13) / 40.0;
        Vec3 p = s.eval(u, v), pp = s.eval(u, v + h), pm = s.eval(u, v - h);
        Vec3 fd1 = (s.eval(u, v + k) - s.eval(u, v - k)) / (2 * k), fd2 = (pp - 2 * p + pm) / (h * h);
        Vec3 d1 = s.derivative(u, v, 0, 1), d2 = s.derivative(u, v, 0, 2);
        worst1 = std::max(worst1, (d1 - fd1).norm() / (1 + d1.norm()));
        worst2 = std::max(worst2, (d2 - fd2).norm() / (1 + d2.norm()));
        Vec3 fdm = (s.derivative(u, v + k, 1, 0) - s.derivative(u, v - k, 1, 0)) / (2 * k);
        worst_mixed = std::max(worst_mixed, (s.derivative(u, v, 1, 1) - fdm).norm() / (1 + fdm.norm()));
      }
    CHECK(worst1 < 1e-7);
    CHECK(worst2 < 1e-4);  // the second difference of eval loses half the digits
    CHECK(worst_mixed < 1e-7);
  }
}

TEST_CASE("welded mesh of a swept tube merges the profile's seam and leaves the ends open", "[surfaces][mesh]") {
  // A circle swept along a planar S-curve: closed in u (the profile), open in v (the path).
  auto circle = std::make_shared<CircularArc>(Point3(0, 0, 0), 0.3, 0, 2 * M_PI);
  auto path = std::make_shared<BezierCurve>(std::vector<Point3>{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {4, 4, 0}});
  SweptSurface tube(circle, path);
  Mesh m = tessellate_welded(tube, 2e-3);
  check_welded(m);
  // Every edge has two triangles except those of the two end circles: one boundary loop per end.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  std::set<std::uint32_t> boundary_vertices;
  std::size_t boundary = 0, over = 0;
  for (const auto& [e, n] : edges) {
    if (n == 1) {
      ++boundary;
      boundary_vertices.insert(e.first);
      boundary_vertices.insert(e.second);
    }
    if (n > 2) ++over;
  }
  CHECK(over == 0);
  CHECK(boundary > 0);
  CHECK(boundary == boundary_vertices.size());  // closed loops: as many edges as vertices
  for (auto v : boundary_vertices) {
    double d0 = (m.positions[v] - path->eval(0)).norm(), d1 = (m.positions[v] - path->eval(1)).norm();
    CHECK(std::min(d0, d1) == Approx(0.3).epsilon(1e-9));
  }
  CHECK(m.positions.size() < tessellate(tube, 2e-3).positions.size());
}

TEST_CASE("the cylinder: points at its radius, Su x Sv away from the axis, derivatives", "[quadrics][cylinder]") {
  const Point3 o(1, -2, 0.5);
  const Vec3 axis = Vec3(1, 2, 2) / 3;
  Cylinder c(o, axis, 0.75, -1, 2);
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 5; ++j) {
      const double u = 2 * kPi * (i + 0.3) / 12, v = -1 + 3.0 * j / 4;
      const Vec3 d = c.eval(u, v) - o;
      const Vec3 radial = d - d.dot(axis) * axis;
      CHECK(radial.norm() == Approx(0.75).epsilon(1e-14));
      CHECK(d.dot(axis) == Approx(v).margin(1e-14));
      CHECK((c.normal(u, v) - radial / 0.75).norm() < 1e-14);
    }
  check_surface_derivatives(c, 1e-6, 3);
}

TEST_CASE("the plane of a face: its normal as given, axes from it", "[plane]") {
  const Vec3 n = Vec3(0.2, -0.4, 1).normalized();
  Plane p(Point3(1, 2, 3), n);
  CHECK(p.unit_normal() == n);  // bit for bit: the B-Rep keeps a face's normal as it was given
  CHECK(std::abs(p.x_axis().dot(n)) < 1e-15);
  CHECK((p.x_axis().cross(p.y_axis()) - n).norm() < 1e-15);
  CHECK((p.normal(0.3, 0.7) - n).norm() < 1e-15);
}

TEST_CASE("the plane of a face of a tiny solid: a normal whose squared length underflows", "[plane]") {
  // A face of box(1e-90, 1e-90, 1e-90) has a Newell normal near 1e-180; its squared length
  // underflowed to 0 and the box failed with "plane: the normal must be non-zero".
  Plane p(Point3(0, 0, 0), Vec3(0, 0, 2e-180));
  CHECK(p.unit_normal() == Vec3(0, 0, 1));
  Plane q(Point3(0, 0, 0), Vec3(1e-90, 0, 0), Vec3(0, 1e-90, 0), 0, 1, 0, 1);
  CHECK(q.unit_normal() == Vec3(0, 0, 1));
  CHECK_THROWS_WITH(Plane(Point3(0, 0, 0), Vec3(0, 0, 0)), "plane: the normal must be non-zero");
}

TEST_CASE("arcs stay arcs: through three points, reversed, moved, split and joined", "[curves][arc]") {
  const Point3 a(2, 0, 1), m(0, 2, 1), b(-2, 0, 1);  // half of the circle of radius 2 about (0, 0, 1)
  CircularArc arc = arc_through(a, m, b);
  CHECK((arc.center() - Point3(0, 0, 1)).norm() < 1e-14);
  CHECK(arc.radius() == Approx(2).epsilon(1e-15));
  auto [t0, t1] = arc.domain();
  CHECK((arc.eval(t0) - a).norm() < 1e-14);
  CHECK((arc.eval((t0 + t1) / 2) - m).norm() < 1e-14);
  CHECK((arc.eval(t1) - b).norm() < 1e-14);

  CircularArc rev = arc.reversed();
  auto [r0, r1] = rev.domain();
  for (int i = 0; i <= 8; ++i) {
    const double s = i / 8.0;
    CHECK((rev.eval(r0 + s * (r1 - r0)) - arc.eval(t1 - s * (t1 - t0))).norm() < 1e-14);
  }
  // A mirror with scale 3 and a shift: the image runs the same way, still a circle.
  const Mat4 mm = translate(Vec3(1, 1, 1)) * scale(Vec3(3, 3, 3)) * reflect(Vec3(1, 1, 0).normalized());
  CircularArc moved = arc.transformed(mm);
  CHECK(moved.radius() == Approx(6).epsilon(1e-14));
  for (int i = 0; i <= 8; ++i) {
    const double t = t0 + (t1 - t0) * i / 8;
    CHECK((moved.eval(t) - apply_point(mm, arc.eval(t))).norm() < 1e-13);
  }
  CurvePtr stretched = transformed_curve(std::make_shared<const CircularArc>(arc), scale(Vec3(2, 1, 1)));
  CHECK(dynamic_cast<const CircularArc*>(stretched.get()) == nullptr);  // an ellipse now
  CHECK((stretched->eval(t0) - Point3(4, 0, 1)).norm() < 1e-14);

  CurvePtr whole = std::make_shared<const CircularArc>(arc);
  auto [p, q] = split_curve(whole, 1.0);
  REQUIRE(dynamic_cast<const CircularArc*>(p.get()));
  REQUIRE(dynamic_cast<const CircularArc*>(q.get()));
  CHECK((p->eval(p->domain().second) - arc.eval(1.0)).norm() < 1e-14);
  CHECK((q->eval(q->domain().first) - arc.eval(1.0)).norm() < 1e-14);
  CurvePtr back = joined_curve(p, q);
  REQUIRE(back);
  CHECK(back->domain() == arc.domain());
  for (int i = 0; i <= 8; ++i) {
    const double t = t0 + (t1 - t0) * i / 8;
    CHECK((back->eval(t) - arc.eval(t)).norm() < 1e-14);
  }
  CHECK_FALSE(joined_curve(q, p));  // not in that order
}

TEST_CASE("a free-form curve split and joined again is the same curve", "[curves]") {
  std::vector<Point3> P{{0, 0, 0}, {1, 2, 0}, {3, 3, 1}, {4, 0, 2}, {6, 1, 0}};
  CurvePtr c = std::make_shared<const NurbsCurve>(interpolate_nurbs(P, 3));
  const Point3 x = c->eval(0.37);
  const double t = closest_parameter(*c, x);
  CHECK(t == Approx(0.37).margin(1e-9));
  auto [a, b] = split_curve(c, t);
  auto [a1, a2] = split_curve(a, 0.2);  // a piece of a piece is a piece of the curve
  CHECK(joined_curve(a1, a2)->domain() == a->domain());
  CHECK(joined_curve(joined_curve(a1, a2), b) == c);
  CHECK_FALSE(joined_curve(b, a));
}

TEST_CASE("a jet (the point and its derivatives at once) agrees with eval() and derivative() and with differences", "[jet]") {
  // Curves: a rational NURBS (a circle: weights not 1), a cubic Bezier, an arc, and a piece of a
  // NURBS run backwards (what revolve() makes of a profile).
  auto circle = std::make_shared<const NurbsCurve>(nurbs_circle(Point3(0.5, 0.2, 0), 1.3));
  auto cubic = std::make_shared<const NurbsCurve>(3, std::vector<Point3>{{1.5, 0, 0}, {2, 0, 0}, {2.2, 0.5, 0}, {1.8, 1, 0}, {1.2, 1.1, 0}},
                                                  std::vector<double>{0, 0, 0, 0, 0.4, 1, 1, 1, 1});
  auto bezier = std::make_shared<const BezierCurve>(std::vector<Point3>{{0, 0, 0}, {1, 0, 1}, {2, 1, 1}, {3, 1, 2}, {3, 3, 3}});
  auto arc = std::make_shared<const CircularArc>(Point3(1, 2, 3), 0.7, -1.0, 2.0, Vec3(1, 1, 0));
  auto piece = std::make_shared<const ReversedCurve>(std::make_shared<const SubCurve>(cubic, 0.1, 0.9));
  for (CurvePtr c : {CurvePtr(circle), CurvePtr(cubic), CurvePtr(bezier), CurvePtr(arc), CurvePtr(piece)}) {
    auto [a, b] = c->domain();
    const double h = 1e-6 * (b - a);
    for (int i = 1; i < 20; ++i) {
      const double t = a + (b - a) * (i + 0.21) / 20.0;
      for (int d = 0; d <= 3; ++d) {
        Vec3 j[4];
        c->jet(t, d, j);
        CHECK((j[0] - c->eval(t)).norm() <= 1e-12 * (1 + j[0].norm()));
        for (int k = 1; k <= d; ++k) CHECK((j[k] - c->derivative(t, k)).norm() <= 1e-9 * (1 + j[k].norm()));
        if (d >= 1) {
          Vec3 fd = (c->eval(t + h) - c->eval(t - h)) / (2 * h);
          CHECK((j[1] - fd).norm() <= 1e-6 * (1 + j[1].norm()));
        }
      }
    }
  }
  // Surfaces: a revolved NURBS profile and swept tubes (an open Bezier path, and a closed circle
  // path whose frames get the closing twist), a NURBS patch (the default jet), a loft through
  // three sections and a twisted, scaled extrusion.
  // A closed saddle-shaped path: not planar, so its rotation-minimising frames come back turned.
  struct Saddle : Curve {
    std::pair<double, double> domain() const override { return {0.0, 2 * M_PI}; }
    Point3 eval(double t) const override { return Point3(2 * std::cos(t), 2 * std::sin(t), 0.8 * std::sin(2 * t)); }
    Vec3 derivative(double t, int k) const override {
      if (k == 0) return eval(t);
      const double a = t + k * M_PI / 2, b = 2 * t + k * M_PI / 2;
      return Vec3(2 * std::cos(a), 2 * std::sin(a), 0.8 * std::pow(2.0, k) * std::sin(b));
    }
  };
  auto circle_path = std::make_shared<const Saddle>();
  auto profile = std::make_shared<const CircularArc>(Point3(0.1, 0, 0), 0.3, 0, 2 * M_PI);
  auto twisted_path = std::make_shared<const BezierCurve>(std::vector<Point3>{{0, 0, 0}, {4, 0, 1}, {0, 4, -1}, {4, 4, 0}});
  std::vector<std::shared_ptr<const Surface>> surfaces{
      std::make_shared<const RevolutionSurface>(piece, 5.0),
      std::make_shared<const SweptSurface>(profile, bezier),
      std::make_shared<const SweptSurface>(profile, twisted_path),
      std::make_shared<const SweptSurface>(profile, circle_path, 512, true),
      std::make_shared<const NurbsSurface>(nurbs_sphere(Point3(1, 0, 0), 2)),
      std::make_shared<const LoftedSurface>(std::vector<CurvePtr>{
          std::make_shared<const BezierCurve>(std::vector<Point3>{{0, 0, 0}, {1, 2, 0}, {3, 0, 0}}),
          std::make_shared<const CircularArc>(Point3(1, 0, 1), 1.5, 0.0, 3.0),
          std::make_shared<const BezierCurve>(std::vector<Point3>{{0, 1, 2}, {2, 3, 2}, {3, 1, 2}, {4, 0, 2}})}),
      std::make_shared<const TwistedExtrusionSurface>(
          std::make_shared<const BezierCurve>(std::vector<Point3>{{1, 0, 0}, {2, 1, 0}, {0.5, 2, 0}}), 3.0, 1.3, 0.4),
  };
  REQUIRE(dynamic_cast<const SweptSurface&>(*surfaces[3]).twist_rate() != 0);
  for (const auto& s : surfaces) {
    auto [u0, u1] = s->u_domain();
    auto [v0, v1] = s->v_domain();
    for (int i = 1; i < 9; ++i)
      for (int k = 1; k < 9; ++k) {
        const double u = u0 + (u1 - u0) * (i + 0.3) / 9, v = v0 + (v1 - v0) * (k + 0.6) / 9;
        Vec3 j[6];
        s->jet(u, v, 2, j);
        CHECK((j[0] - s->eval(u, v)).norm() <= 1e-12 * (1 + j[0].norm()));
        const int order[6][2] = {{0, 0}, {1, 0}, {0, 1}, {2, 0}, {1, 1}, {0, 2}};
        for (int q = 1; q < 6; ++q) {
          Vec3 d = s->derivative(u, v, order[q][0], order[q][1]);
          CHECK((j[q] - d).norm() <= 1e-9 * (1 + d.norm()));
        }
        const double hu = 1e-6 * (u1 - u0), hv = 1e-6 * (v1 - v0);
        Vec3 fu = (s->eval(u + hu, v) - s->eval(u - hu, v)) / (2 * hu), fv = (s->eval(u, v + hv) - s->eval(u, v - hv)) / (2 * hv);
        CHECK((j[1] - fu).norm() <= 1e-5 * (1 + fu.norm()));
        CHECK((j[2] - fv).norm() <= 1e-5 * (1 + fv.norm()));
        Vec3 j1[3];
        s->jet(u, v, 1, j1);
        CHECK((j1[2] - j[2]).norm() <= 1e-12 * (1 + j[2].norm()));
      }
    // The grids (jet_grid at order 1, eval_grid: a revolution's, a sweep's and a loft's share each
    // column's angle, frame or blending weights and each row's profile or section points) give
    // jet()'s and eval()'s values, bit for bit.
    std::vector<double> us, vs;
    for (int i = 0; i <= 6; ++i) us.push_back(u0 + (u1 - u0) * (i + 0.25 * (i % 2)) / 6.5);
    for (int k = 0; k <= 7; ++k) vs.push_back(v0 + (v1 - v0) * (k + 0.4 * (k % 3)) / 7.8);
    vs.push_back(v1);
    const int nu = static_cast<int>(us.size()), nv = static_cast<int>(vs.size());
    std::vector<Vec3> grid(us.size() * vs.size() * 6);
    std::vector<Point3> points(us.size() * vs.size());
    s->jet_grid(us.data(), nu, vs.data(), nv, 1, grid.data());
    s->eval_grid(us.data(), nu, vs.data(), nv, points.data());
    int same = 0;
    for (int i = 0; i < nu; ++i)
      for (int k = 0; k < nv; ++k) {
        Vec3 j[3];
        s->jet(us[static_cast<std::size_t>(i)], vs[static_cast<std::size_t>(k)], 1, j);
        const Vec3* g = &grid[static_cast<std::size_t>((i * nv + k) * 6)];
        same += g[0] == j[0] && g[1] == j[1] && g[2] == j[2] &&
                points[static_cast<std::size_t>(i * nv + k)] == s->eval(us[static_cast<std::size_t>(i)], vs[static_cast<std::size_t>(k)]);
      }
    CHECK(same == nu * nv);
  }
}

TEST_CASE("a swept surface is continuous across its stored frames, an ulp to either side", "[swept]") {
  // The frame at v is the double-reflection step from the stored frame before it; at a v an ulp
  // past a stored frame's parameter the step is rounding noise, and a reflection across it used
  // to turn the frame anywhere (the profile came out mirrored, 1.0 away on this torus).
  auto path = std::make_shared<const CircularArc>(Point3::Zero(), 2, 0.0, 2 * M_PI);
  auto profile = std::make_shared<const CircularArc>(Point3::Zero(), 0.5, 0.0, 2 * M_PI);
  SweptSurface s(profile, path, 512, true);
  double worst = 0;
  for (int i = 1; i < 511; ++i) {
    const double v = 2 * M_PI * i / 511;
    const Point3 p = s.eval(1.0, v);
    for (double w : {std::nextafter(v, 0.0), std::nextafter(v, 7.0), std::nextafter(std::nextafter(v, 7.0), 7.0)}) {
      Vec3 j[3];
      s.jet(1.0, w, 1, j);
      worst = std::max({worst, (s.eval(1.0, w) - p).norm(), (Point3(j[0]) - p).norm()});
    }
  }
  CHECK(worst < 1e-9);
}
