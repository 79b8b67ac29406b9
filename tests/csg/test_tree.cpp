// The CSG tree evaluated: boolean results rebuilt as winged-edge solids (Euler counts worked by
// hand, faces that keep their source surface, areas against closed forms), shared subtrees once,
// pruning, the same bits at 1 and 2 threads, progress and cancel.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <map>

#include <tbb/global_control.h>

#include "csg/brep_leaf.h"
#include "csg/csg.h"

using namespace wedge;

namespace {
Solid box_solid(const Vec3& size, const Point3& corner = Point3::Zero()) { return brep_solid(box(size, corner)); }

std::map<std::string, int> kinds(const std::vector<SolidFace>& faces) {
  std::map<std::string, int> k;
  for (const auto& f : faces) ++k[f.surface];
  return k;
}

// A control installed for one scope.
struct Installed {
  explicit Installed(const EvalControl& c) { set_eval_control(&c); }
  ~Installed() { set_eval_control(nullptr); }
};
}  // namespace

TEST_CASE("rebuild: a plate with a square hole is one solid with two rings and one through-hole", "[tree][rebuild]") {
  // [0,4]x[0,4]x[0,1] minus [1,3]x[1,3]x[-1,2]: 10 faces (6 of the plate, 4 walls of the hole),
  // rings in top and bottom, H = 1; 16 corners and 24 edges (points where the plate's
  // triangulation crossed the hole's edges are joined away by jekv).
  Solid d = Solid::boolean(BooleanOp::Difference, {box_solid(Vec3(4, 4, 1)), box_solid(Vec3(2, 2, 3), Point3(1, 1, -1))});
  Tolerance tol;
  EulerCounts c = d.euler(tol);
  CHECK(c.F == 10);
  CHECK(c.R == 2);
  CHECK(c.H == 1);
  CHECK(c.S == 1);
  CHECK(c.V == 16);
  CHECK(c.E == 24);
  CHECK(c.characteristic() == 0);
  CHECK(d.validate(tol) == "");
  auto faces = d.faces(tol);
  CHECK(kinds(faces) == std::map<std::string, int>{{"plane", 10}});
  double area = 0;
  int ringed = 0;
  for (const auto& f : faces) {
    area += f.area;
    ringed += f.loops == 2;
  }
  CHECK(ringed == 2);
  // 2 * (16 - 4) + 4 * 4 (outer walls) + 4 * 2 (hole walls)
  CHECK(area == Approx(24 + 16 + 8).epsilon(1e-12));
}

TEST_CASE("rebuild: a sphere minus a cube keeps one spherical face and three planar ones", "[tree][rebuild]") {
  Tolerance tol;
  tol.chordal = 1e-3;
  Solid d = Solid::boolean(BooleanOp::Difference, {brep_solid(sphere(1)), box_solid(Vec3(2, 2, 2))});
  auto faces = d.faces(tol);
  CHECK(kinds(faces) == std::map<std::string, int>{{"plane", 3}, {"sphere", 1}});
  EulerCounts c = d.euler(tol);
  CHECK(c.V == 4);  // the centre and the three points on the axes
  CHECK(c.E == 6);  // three arcs, three straight edges
  CHECK(c.F == 4);
  CHECK(c.R == 0);
  CHECK(c.H == 0);
  CHECK(c.S == 1);
  CHECK(d.validate(tol) == "");
  // Seven eighths of the sphere's area; each cut is a quarter disc.
  for (const auto& f : faces) {
    if (f.surface == "sphere") CHECK(f.area == Approx(3.5 * kPi).epsilon(2e-3));
    else CHECK(f.area == Approx(kPi / 4).epsilon(2e-3));
    CHECK(f.loops == 1);
  }
}

TEST_CASE("rebuild: a sphere drilled through keeps an annular spherical face", "[tree][rebuild]") {
  Tolerance tol;
  tol.chordal = 2e-3;
  Solid d = Solid::boolean(BooleanOp::Difference, {brep_solid(sphere(1)), brep_solid(cylinder(0.4, 4, Point3(0, 0, -2)))});
  EulerCounts c = d.euler(tol);
  // The drill's two half-cylinder faces meet along two seams: 2 vertices on each circle, 2 arcs
  // on each, 2 seam edges; the sphere's face is an annulus (one ring).
  CHECK(c.V == 4);
  CHECK(c.E == 6);
  CHECK(c.F == 3);
  CHECK(c.R == 1);
  CHECK(c.H == 1);
  CHECK(c.S == 1);
  CHECK(c.characteristic() == 0);
  CHECK(d.validate(tol) == "");
  auto k = kinds(d.faces(tol));
  CHECK(k["sphere"] == 1);
  CHECK(k["cylinder"] == 2);  // the drill's two half-cylinder faces
  CHECK(k.size() == 2);
}

TEST_CASE("rebuild: a plate minus 400 through-cylinders has H = 400", "[tree][rebuild]") {
  Tolerance tol;
  tol.chordal = 0.05;
  std::vector<Solid> ops{box_solid(Vec3(21, 21, 1))};
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) ops.push_back(brep_solid(cylinder(0.3, 3, Point3(1 + i, 1 + j, -1))));
  Solid d = Solid::boolean(BooleanOp::Difference, ops);
  EulerCounts c = d.euler(tol);
  CHECK(c.V == 8 + 400 * 4);
  CHECK(c.E == 12 + 400 * 6);
  CHECK(c.H == 400);
  CHECK(c.R == 800);
  CHECK(c.F == 6 + 800);
  CHECK(c.S == 1);
  CHECK(d.validate(tol) == "");
}

TEST_CASE("tree: disjoint operands are pruned; shells and empty results come out right", "[tree]") {
  Tolerance tol;
  EvalStats stats;
  EvalControl control;
  control.stats = &stats;
  Installed on(control);
  Solid a = box_solid(Vec3(1, 1, 1)), b = box_solid(Vec3(1, 1, 1), Point3(3, 0, 0));
  Solid u = Solid::boolean(BooleanOp::Union, {a, b});
  EulerCounts c = u.euler(tol);
  CHECK(c.S == 2);
  CHECK(c.F == 12);
  CHECK(u.mass_properties(tol).volume == 2);
  CHECK(stats.booleans == 0);  // no engine call for a union of parts far apart
  Solid i = Solid::boolean(BooleanOp::Intersection, {a, b});
  CHECK(i.mesh(tol).empty());
  Solid d = Solid::boolean(BooleanOp::Difference, {a, b});
  CHECK(d.mass_properties(tol).volume == Approx(1).epsilon(1e-12));
  CHECK(stats.booleans == 0);
  CHECK(stats.pruned >= 3);
}

TEST_CASE("tree: a shared subtree is evaluated once", "[tree]") {
  Tolerance tol;
  tol.chordal = 0.02;
  Solid s = Solid::boolean(BooleanOp::Difference, {box_solid(Vec3(2, 2, 2)), brep_solid(sphere(0.7, Point3(1, 1, 1)))});
  auto build = [&] {
    return Solid::boolean(BooleanOp::Union, {s, s.transformed(translate(Vec3(1.3, 0.2, 0.1))), s.transformed(translate(Vec3(0.3, 1.1, 0.2)))});
  };
  EvalStats stats;
  EvalControl control;
  control.stats = &stats;
  Installed on(control);
  double v = build().mass_properties(tol).volume;
  CHECK(stats.booleans == 2);  // s once, the union once
  // Without the cache the shared s is computed three times.
  set_eval_options({false, true, true});
  EvalStats off;
  control.stats = &off;
  Solid s2 = Solid::boolean(BooleanOp::Difference, {box_solid(Vec3(2, 2, 2)), brep_solid(sphere(0.7, Point3(1, 1, 1)))});
  Solid u2 = Solid::boolean(BooleanOp::Union, {s2, s2.transformed(translate(Vec3(1.3, 0.2, 0.1))), s2.transformed(translate(Vec3(0.3, 1.1, 0.2)))});
  double v2 = u2.mass_properties(tol).volume;
  set_eval_options({});
  CHECK(off.booleans == 4);
  CHECK(v == v2);
}

TEST_CASE("tree: the same result at 1 and 2 threads", "[tree]") {
  Tolerance tol;
  tol.chordal = 5e-3;
  auto build = [] {
    std::vector<Solid> parts;
    for (int i = 0; i < 6; ++i) parts.push_back(brep_solid(sphere(0.6, Point3(i * 0.7, 0, 0))));
    Solid u = Solid::boolean(BooleanOp::Union, parts);
    return Solid::boolean(BooleanOp::Difference, {u, brep_solid(cylinder(0.2, 4, Point3(1.4, 0, -2)))});
  };
  Mesh one, two;
  {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, 1);
    one = build().mesh(tol);
  }
  {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, 2);
    two = build().mesh(tol);
  }
  REQUIRE(one.triangles.size() == two.triangles.size());
  CHECK(one.positions == two.positions);
  CHECK(one.triangles == two.triangles);
  CHECK(one.face_ids == two.face_ids);
}

TEST_CASE("tree: progress reaches the total, and a cancel leaves nothing behind", "[tree]") {
  Tolerance tol;
  tol.chordal = 5e-3;
  auto build = [] {
    Solid a = Solid::boolean(BooleanOp::Difference, {box_solid(Vec3(2, 2, 2)), brep_solid(sphere(0.5, Point3(1, 1, 2)))});
    Solid b = Solid::boolean(BooleanOp::Difference, {box_solid(Vec3(2, 2, 2), Point3(1, 1, 1)), brep_solid(sphere(0.5, Point3(2, 2, 3)))});
    return Solid::boolean(BooleanOp::Union, {a, b});
  };
  std::vector<std::pair<std::size_t, std::size_t>> seen;
  std::mutex m;
  EvalControl control;
  control.progress = [&](std::size_t done, std::size_t total) {
    std::lock_guard<std::mutex> lock(m);
    seen.emplace_back(done, total);
  };
  double v = 0;
  {
    Installed on(control);
    v = build().mass_properties(tol).volume;
  }
  REQUIRE(seen.size() == 3);
  CHECK(seen.back() == std::pair<std::size_t, std::size_t>{3, 3});

  std::atomic<int> polls{0};
  EvalControl stop;
  stop.cancelled = [&] { return ++polls > 3; };
  Solid s = build();
  {
    Installed on(stop);
    CHECK_THROWS_AS(s.mass_properties(tol), Cancelled);
  }
  // Nothing half-done was kept: the same solid evaluates in full afterwards.
  CHECK(s.mass_properties(tol).volume == v);
}

TEST_CASE("tree: each face of a result keeps the tag of the solid it came from", "[tree]") {
  Tolerance tol;
  tol.chordal = 5e-3;
  Solid red = brep_solid(sphere(1)).tagged(1), blue = box_solid(Vec3(2, 2, 2)).tagged(2);
  Solid d = Solid::boolean(BooleanOp::Difference, {red, blue.transformed(translate(Vec3(0, 0, 0)))}).tagged(7);
  Mesh m = d.tagged_mesh(tol);
  std::vector<std::string> kinds = d.face_kinds(tol);
  std::vector<int> tags = d.face_tags(tol);
  REQUIRE(kinds.size() == tags.size());
  std::map<int, double> area;  // by tag
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& T = m.triangles[t];
    int id = m.face_ids[t];
    double a = 0.5 * (m.positions[T[1]] - m.positions[T[0]]).cross(m.positions[T[2]] - m.positions[T[0]]).norm();
    area[tags[static_cast<std::size_t>(id)]] += a;
    CHECK((kinds[static_cast<std::size_t>(id)] == "sphere") == (tags[static_cast<std::size_t>(id)] == 1));
  }
  // The sphere keeps 7/8 of its area in red; the three quarter discs cut by the cube are blue;
  // the outer tag 7 reaches no face (every face had a tag already).
  CHECK(area.size() == 2);
  CHECK(area[1] == Approx(3.5 * kPi).epsilon(5e-3));
  CHECK(area[2] == Approx(0.75 * kPi).epsilon(5e-3));
  // An untagged operand's faces take the outer tag.
  Solid e = Solid::boolean(BooleanOp::Difference, {brep_solid(sphere(1)), blue}).tagged(7);
  std::vector<int> te = e.face_tags(tol);
  std::vector<std::string> ke = e.face_kinds(tol);
  for (std::size_t i = 0; i < te.size(); ++i)
    if (ke[i] == "sphere") CHECK(te[i] == 7);
}

TEST_CASE("tree: a finer tolerance re-evaluates the boolean from the tree and converges", "[tree]") {
  // Sphere r = 1 minus the octant cube: 7/8 of the ball. A finer tolerance tessellates the leaves
  // again (more triangles, not the coarse facets subdivided) and the volume error shrinks.
  Solid d = Solid::boolean(BooleanOp::Difference, {brep_solid(sphere(1)), box_solid(Vec3(2, 2, 2))});
  const double exact = 7.0 / 8.0 * 4.0 / 3.0 * kPi;
  double last_error = 1e300;
  std::size_t last_count = 0;
  for (double t : {1e-2, 1e-3, 1e-4}) {
    Tolerance tol;
    tol.chordal = t;
    Mesh m = d.mesh(tol);
    double error = std::abs(mass_properties(m).volume - exact);
    INFO("tolerance " << t << " error " << error);
    CHECK(m.triangles.size() > last_count);
    CHECK(error < last_error);
    CHECK(error < 13.4 * t);  // a chordal error t costs at most the area (4.25 pi) times t
    last_error = error;
    last_count = m.triangles.size();
  }
}
