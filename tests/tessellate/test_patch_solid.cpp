// Free-form solids: a closed set of Bezier / NURBS patches becomes a B-Rep solid (Newell's teapot
// body and lid, closed by planar caps). The exact volume (Gauss quadrature over the patches, Green's
// theorem on the caps) is checked against an independent estimate written here: the polyhedron of
// a uniform parameter grid on every patch, closed by the polygon of its boundary points, whose
// divergence-theorem volume converges as O(h^2); two grid sizes and Richardson extrapolation give
// the limit to about 1e-9.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "brep/brep.h"
#include "tessellate/brep_mesh.h"

using namespace wedge;

namespace {

std::vector<SurfacePtr> teapot_patches(std::initializer_list<std::pair<int, int>> ranges) {
  std::vector<NurbsSurface> pot = teapot();
  std::vector<SurfacePtr> out;
  for (auto [a, b] : ranges)
    for (int i = a; i <= b; ++i) out.push_back(std::make_shared<const NurbsSurface>(pot[static_cast<std::size_t>(i)]));
  return out;
}

// The volume of the polyhedron made of an n x n grid of triangles on every patch and, for the one
// open loop at height z0 (the teapot's rims lie in planes z = const), the polygon of the grid
// points on it: sum over triangles of det(a, b, c) / 6, plus z0 / 3 times the polygon's area
// (the cap's normal is +-z). `up`: the cap faces +z (the body's) or -z (the lid's).
double grid_volume(const std::vector<SurfacePtr>& patches, int n, double z0, bool up) {
  double vol = 0;
  // Grid edges on the patches' borders that lie in the plane z = z0, each run the way its patch's
  // loop runs (counter-clockwise in (u, v)). Where two patches meet in that plane their edges come
  // in both directions and cancel; what is left is the open loop that the cap closes.
  std::vector<std::pair<Point3, Point3>> seg;
  for (const auto& s : patches) {
    auto [u0, u1] = s->u_domain();
    auto [v0, v1] = s->v_domain();
    std::vector<Point3> g((n + 1) * (n + 1));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) g[i * (n + 1) + j] = s->eval(u0 + (u1 - u0) * i / n, v0 + (v1 - v0) * j / n);
    auto P = [&](int i, int j) { return g[i * (n + 1) + j]; };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        Point3 a = P(i, j), b = P(i + 1, j), c = P(i + 1, j + 1), d = P(i, j + 1);
        vol += a.dot(b.cross(c)) / 6 + a.dot(c.cross(d)) / 6;
      }
    auto add = [&](const Point3& a, const Point3& b) {
      if (std::abs(a.z() - z0) < 1e-12 && std::abs(b.z() - z0) < 1e-12) seg.emplace_back(a, b);
    };
    for (int k = 0; k < n; ++k) {
      add(P(k, 0), P(k + 1, 0));          // v = v0, u rising
      add(P(n, k), P(n, k + 1));          // u = u1, v rising
      add(P(k + 1, n), P(k, n));          // v = v1, u falling
      add(P(0, k + 1), P(0, k));          // u = u0, v falling
    }
  }
  // The cap polygon's area: the shoelace sum over the segments (the cancelling pairs add nothing).
  double area2 = 0;
  for (const auto& [a, b] : seg) area2 += a.x() * b.y() - b.x() * a.y();
  double area = std::abs(area2) / 2;
  return vol + (up ? 1 : -1) * z0 * area / 3;
}

double extrapolated_volume(const std::vector<SurfacePtr>& patches, double z0, bool up) {
  double a = grid_volume(patches, 200, z0, up), b = grid_volume(patches, 400, z0, up);
  return b + (b - a) / 3;
}

}  // namespace

TEST_CASE("the teapot's body closed by a cap over its rim is a valid solid with its exact volume", "[tessellate][patches]") {
  // Rim (patches 1-4), body (5-12) and bottom (29-32): open only along the rim's inner edge, a
  // closed curve of four cubic arcs in the plane z = 2.4.
  auto body = teapot_patches({{0, 11}, {28, 31}});
  Model m = patch_solid(body, "nurbs");
  REQUIRE(m.validate().ok);
  // Vertices: 4 corners on each of the rings at z = 2.4 (r 1.4 and 1.5), 0.9 and 0.15, and the
  // bottom's pole. Edges: 4 arcs on each ring and 4 sides down each of the 4 rows. Faces: 16 + cap.
  CHECK(m.counts() == EulerCounts{17, 32, 17, 0, 0, 1});
  MassProperties mp = m.mass_properties();
  double reference = extrapolated_volume(body, 2.4, true);
  CHECK(mp.volume == Approx(reference).epsilon(1e-8));
  // The pot is symmetric about x = 0 and y = 0 (its quarter patches are mirror images).
  CHECK(std::abs(mp.centroid.x()) < 1e-9);
  CHECK(std::abs(mp.centroid.y()) < 1e-9);
}

TEST_CASE("the teapot's lid closed by a cap is a valid solid with its exact volume", "[tessellate][patches]") {
  auto lid = teapot_patches({{20, 27}});
  Model m = patch_solid(lid, "nurbs");
  REQUIRE(m.validate().ok);
  CHECK(m.counts() == EulerCounts{9, 16, 9, 0, 0, 1});
  CHECK(m.mass_properties().volume == Approx(extrapolated_volume(lid, 2.4, false)).epsilon(1e-8));
}

TEST_CASE("patch solids tessellate closed and converge to their exact volume", "[tessellate][patches]") {
  for (bool lid : {false, true}) {
    Model m = patch_solid(lid ? teapot_patches({{20, 27}}) : teapot_patches({{0, 11}, {28, 31}}));
    double exact = m.mass_properties().volume, area = m.mass_properties().area;
    for (double tol : {1e-2, 1e-3}) {
      INFO((lid ? "lid" : "body") << " at tolerance " << tol);
      Tolerance t;
      t.chordal = tol;
      Mesh mesh = tessellate(m, t);
      EulerCounts ec = euler_counts(mesh);  // throws unless closed and 2-manifold
      CHECK(ec.S == 1);
      CHECK(ec.H == 0);
      // Every triangle is within tol of the surface, so the volumes differ by at most area * tol.
      CHECK(std::abs(mesh.volume() - exact) <= area * tol);
    }
  }
}

TEST_CASE("the body without its bottom gets two caps, a closed NURBS sphere needs none", "[tessellate][patches]") {
  Model open_bottom = patch_solid(teapot_patches({{0, 11}}));
  REQUIRE(open_bottom.validate().ok);
  CHECK(open_bottom.counts() == EulerCounts{16, 28, 14, 0, 0, 1});
  CHECK(open_bottom.mass_properties().volume > 0);

  double r = 1.25;
  Model s = patch_solid({std::make_shared<const NurbsSurface>(nurbs_sphere(Point3(1, 0, 0), r))});
  REQUIRE(s.validate().ok);
  MassProperties mp = s.mass_properties();
  CHECK(mp.volume == Approx(4.0 / 3 * kPi * r * r * r).epsilon(1e-9));
  CHECK((mp.centroid - Point3(1, 0, 0)).norm() < 1e-9);
}

TEST_CASE("patches that do not close into a solid are errors that say where", "[tessellate][patches][errors]") {
  // The whole teapot: the handle and spout end in open, non-planar loops.
  CHECK_THROWS_WITH(patch_solid(teapot_patches({{0, 31}})), Catch::Contains("patch_solid"));
  // A patch turned over (its u and v swapped) against its neighbours.
  auto body = teapot_patches({{0, 11}, {28, 31}});
  const auto& p = dynamic_cast<const NurbsSurface&>(*body[5]);
  std::vector<std::vector<Point3>> grid(4, std::vector<Point3>(4));
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) grid[i][j] = p.control_points()[j][i];
  body[5] = std::make_shared<const NurbsSurface>(bezier_surface(grid));
  CHECK_THROWS_WITH(patch_solid(body), Catch::Contains("not oriented alike"));
  CHECK_THROWS_WITH(patch_solid({}), Catch::Contains("no patches"));
}
