// Boolean results through files whose numbers are coarser than the mesh's: STL's 32-bit floats,
// and doubles far from the origin. A boolean leaves vertices far closer together than its
// tolerance (where a sphere's facet meets a cube's face); rounded to a file's numbers they meet,
// and a reader (which welds by position) saw triangles with two corners at one point. Each file
// must read back as a closed, consistently oriented surface (counted here, independently of
// euler_counts), a valid solid, with a volume within the bound that rounding allows: each vertex
// moves at most d = sqrt(3)/2 ulp(reach) (to its own rounded position, or to a merged neighbour's,
// which is the same point), so the volume moves at most about area * d.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <filesystem>
#include <limits>
#include <map>

#include "csg/brep_leaf.h"
#include "csg/csg.h"
#include "kernel/predicates.h"
#include "kernel/transform.h"
#include "tessellate/mesh_io.h"
#include "closed_surface.h"

using namespace wedge;
namespace fs = std::filesystem;

namespace {

double reach(const Mesh& m) {
  double r = 0;
  for (const auto& p : m.positions) r = std::max(r, p.cwiseAbs().maxCoeff());
  return r;
}

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("wedge-rounded-" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// Triangles whose three corners are exactly collinear (zero area), by kernel/predicates.h.
std::size_t flat_triangles(const Mesh& m) {
  std::size_t n = 0;
  for (const auto& t : m.triangles) n += collinear(m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]);
  return n;
}

// The octant starts `gap` from the origin, so the result keeps edges that short where the sphere's
// points on the axes lie just outside its faces (tiny edges that rounding brings together). Edges
// of a few ulps whose short side an end can be moved onto within an ulp of its planes are collapsed
// where the boolean rounds (1e-17 goes that way); 1e-15 is kept.
Solid sphere_minus_cube(double gap = 1e-17) {
  return Solid::boolean(BooleanOp::Difference, {brep_solid(sphere(1)), brep_solid(box(Vec3(1, 1, 1), Point3(gap, gap, gap)))});
}
}  // namespace

TEST_CASE("boolean results round-trip through STL (32-bit floats) as closed valid solids at fine tolerances", "[mesh_io][rounding]") {
  TempDir dir;
  const std::vector<std::pair<const char*, Solid>> models = {
      {"sphere - cube", sphere_minus_cube()},
      {"sphere + cylinder", Solid::boolean(BooleanOp::Union, {brep_solid(sphere(1)), brep_solid(cylinder(0.5, 2))})},
      {"sphere - cube, at (1000, 2000, 0)", sphere_minus_cube().transformed(translate({1000, 2000, 0}))},
      // (Edges 1e-15 long are kept where the boolean rounds: rounding to floats merges their
      // ends. Before a circle's points were snapped to 2^-44 of a turn, the models above had such
      // vertices too.)
      {"sphere - cube, gap 1e-15", sphere_minus_cube(1e-15)},
  };
  bool any_rounded_together = false;
  for (const auto& [name, solid] : models)
    for (double chordal : {0.01, 0.003, 0.001}) {
      Tolerance tol;
      tol.chordal = chordal;
      const Mesh mesh = solid.mesh(tol);
      const FileMesh as_floats = file_mesh(mesh, true);
      any_rounded_together |= as_floats.merged > 0;
      const double d = std::sqrt(3.0) / 2 * std::ldexp(1.0, std::ilogb(reach(mesh)) - 23);
      for (bool ascii : {false, true}) {
        INFO(name << " at tolerance " << chordal << (ascii ? " ascii" : " binary") << ": " << as_floats.merged
                  << " vertices merged, " << as_floats.dropped << " triangles dropped");
        const std::string path = (dir.path / "part.stl").string();
        MeshWriteOptions options;
        options.ascii = ascii;
        write_mesh(mesh, path, options);
        const Mesh back = read_mesh(path);
        CHECK(closed_and_oriented(back));
        CHECK(flat_triangles(back) == 0);
        CHECK(back.triangle_count() == mesh.triangle_count() - as_floats.dropped);
        const Solid s = Solid::from_mesh(back, "part.stl");
        CHECK(s.validate(tol).empty());
        CHECK(std::abs(back.volume() - mesh.volume()) <= mesh.area() * d);
      }
    }
  // The reason for this test: at these tolerances rounding to floats does bring vertices together.
  CHECK(any_rounded_together);
}

TEST_CASE("a boolean result moved far from the origin writes OBJ, PLY and OFF that read back closed", "[mesh_io][rounding]") {
  // Moved to (1000, 2000, 0), the sphere-minus-cube's tiny edges round to one double: the mesh
  // holds triangles with two corners at one position (distinct indices), which every reader welds.
  TempDir dir;
  Tolerance tol;
  // The mesh itself moved: a Solid's moved result is made again where rounding spoils it
  // (csg/solid.cpp), but a mesh moved as it is (by a script's own code, or another program's) is not.
  const Mesh mesh = sphere_minus_cube(1e-15).mesh(tol).transformed(translate({1000, 2000, 0}));
  const FileMesh as_doubles = file_mesh(mesh, false);
  CHECK(as_doubles.merged > 0);
  const double d = std::sqrt(3.0) / 2 * std::ldexp(1.0, std::ilogb(reach(mesh)) - 52);
  for (const char* name : {"far.obj", "far.ply", "far.off"}) {
    INFO(name);
    const std::string path = (dir.path / name).string();
    write_mesh(mesh, path);
    const Mesh back = read_mesh(path);
    CHECK(closed_and_oriented(back));
    CHECK(flat_triangles(back) == 0);
    CHECK(back.triangle_count() == mesh.triangle_count() - as_doubles.dropped);
    INFO(Solid::from_mesh(back, name).validate(tol));
    CHECK(Solid::from_mesh(back, name).validate(tol).empty());
    CHECK(std::abs(back.volume() - mesh.volume()) <= mesh.area() * d + 1e-9 * std::abs(mesh.volume()));
  }
}

TEST_CASE("a drilled cylinder moved to 1e5 writes OBJ, PLY and OFF without zero-area triangles", "[mesh_io][rounding]") {
  // Moved to x = 1e5 (doubles 1.5e-11 apart), the drill's seam rounds four vertices onto one
  // line as two flat triangles sharing an edge; mending the first leaves a half that is the reverse
  // of a neighbour, and the two cancel. The files read back closed, with no flat triangle. The
  // mesh is cylinder(1, 2) - cylinder(0.5, 3):rotate_x(90) at tolerance 0.003 as wedge made it
  // before a circle's points were snapped to 2^-44 of a turn (tests/data/tessellate): its seam's
  // points are those that round onto one line.
  TempDir dir;
  Mesh drilled;
  {
    std::ifstream in(std::string(WEDGE_SOURCE_DIR) + "/tests/data/tessellate/drilled_cylinder.off");
    std::string magic;
    std::size_t nv = 0, nf = 0, ne = 0;
    in >> magic >> nv >> nf >> ne;
    for (std::size_t i = 0; i < nv; ++i) {
      double x, y, z;
      in >> x >> y >> z;
      drilled.add_vertex(Point3(x, y, z));
    }
    for (std::size_t i = 0; i < nf; ++i) {
      std::uint32_t k, a, b, c;
      in >> k >> a >> b >> c;
      drilled.add_triangle(a, b, c);
    }
    REQUIRE(in);
    REQUIRE(drilled.triangles.size() == 234);
  }
  const Mesh mesh = drilled.transformed(translate({1e5, 0, 0}));  // the mesh itself moved, as above
  const FileMesh as_doubles = file_mesh(mesh, false);
  CHECK(as_doubles.mended > 0);
  CHECK(as_doubles.flat == 0);
  for (const char* name : {"far.obj", "far.ply", "far.off"}) {
    INFO(name);
    const std::string path = (dir.path / name).string();
    write_mesh(mesh, path);
    const Mesh back = read_mesh(path);
    CHECK(flat_triangles(back) == 0);
    CHECK(closed_and_oriented(back));
    CHECK(std::abs(back.volume() - mesh.volume()) <= 1e-9 * std::abs(mesh.volume()));
  }
}

TEST_CASE("file_mesh keeps copies at one position that share no edge, and leaves a clean mesh unchanged", "[mesh_io][rounding]") {
  // Two tetrahedra touching at one vertex, each with its own copy of it (how a non-manifold
  // boolean result keeps its shells apart): nothing shares an edge at one point, nothing merges.
  Mesh m;
  for (const Point3& p : {Point3(0, 0, 0), Point3(1, 0, 0), Point3(0, 1, 0), Point3(0, 0, 1)}) m.add_vertex(p);
  for (const Point3& p : {Point3(0, 0, 0), Point3(-1, 0, 0), Point3(0, -1, 0), Point3(0, 0, -1)}) m.add_vertex(p);
  for (std::uint32_t o : {0u, 4u}) {
    m.add_triangle(o + 0, o + 2, o + 1);
    m.add_triangle(o + 0, o + 1, o + 3);
    m.add_triangle(o + 0, o + 3, o + 2);
    m.add_triangle(o + 1, o + 2, o + 3);
  }
  const FileMesh doubles = file_mesh(m, false);
  CHECK(doubles.merged == 0);
  CHECK(doubles.dropped == 0);
  CHECK(doubles.mesh.triangles == m.triangles);
  const FileMesh floats = file_mesh(m, true);
  CHECK(floats.merged == 0);
  CHECK(floats.mesh.triangle_count() == 8);

  // A tetrahedron whose edge 0-3 is split by vertex 4 at 1e-12 from vertex 3: as floats the
  // edge 4-3 collapses, its two triangles go, the tetrahedron is left.
  Mesh t;
  for (const Point3& p : {Point3(0, 0, 0), Point3(1, 0, 0), Point3(0, 1, 0), Point3(0, 0, 1), Point3(0, 0, 1 - 1e-12)}) t.add_vertex(p);
  t.add_triangle(0, 2, 1);
  t.add_triangle(0, 1, 4);
  t.add_triangle(4, 1, 3);
  t.add_triangle(0, 4, 2);
  t.add_triangle(4, 3, 2);
  t.add_triangle(1, 2, 3);
  REQUIRE(closed_and_oriented(t));
  const FileMesh r = file_mesh(t, true);
  CHECK(r.merged == 1);
  CHECK(r.dropped == 2);
  CHECK(r.mesh.vertex_count() == 4);
  CHECK(closed_and_oriented(r.mesh));
  CHECK(r.mesh.volume() == Approx(1.0 / 6));
  CHECK(file_mesh(t, false).dropped == 0);  // as doubles nothing meets
  // Two triangles on 0, 1 and two points 1e-12 apart that floats cannot tell apart: merged, they
  // are one triangle and its reverse (a fin of no volume), and both go.
  Mesh f;
  for (const Point3& p : {Point3(0, 0, 0), Point3(1, 0, 0), Point3(0.5, 0.5, 0), Point3(0.5, 0.5 + 1e-12, 0)}) f.add_vertex(p);
  f.add_triangle(0, 1, 2);
  f.add_triangle(0, 3, 1);
  const FileMesh fin = file_mesh(f, true);
  CHECK(fin.merged == 1);
  CHECK(fin.dropped == 2);
  CHECK(fin.mesh.triangles.empty());
  CHECK(file_mesh(f, false).dropped == 0);  // as doubles the two points differ
}

TEST_CASE("an STL of sphere - cube has no zero-area triangle and reads back as a boolean operand", "[mesh_io][rounding]") {
  // Rounded to floats, one thin triangle of sphere(1) - cube(1) (at tolerance 0.01) has its three
  // distinct corners exactly on one line: a reader, and the boolean's own operand check, saw a
  // zero-area triangle. The writer mends it on the same points.
  TempDir dir;
  Tolerance tol;
  tol.chordal = 0.01;
  const Mesh mesh =
      Solid::boolean(BooleanOp::Difference, {brep_solid(sphere(1)), brep_solid(box(Vec3(1, 1, 1), Point3::Zero()))}).mesh(tol);
  const FileMesh as_floats = file_mesh(mesh, true);
  CHECK(as_floats.mended > 0);  // the reason for this test: rounding does make a flat triangle here
  CHECK(as_floats.flat == 0);
  const Solid cube = brep_solid(box(Vec3(0.5, 0.5, 0.5), Point3::Zero()));
  for (bool ascii : {false, true}) {
    INFO((ascii ? "ascii" : "binary"));
    const std::string path = (dir.path / "part.stl").string();
    MeshWriteOptions options;
    options.ascii = ascii;
    write_mesh(mesh, path, options);
    const Mesh back = read_mesh(path);
    CHECK(flat_triangles(back) == 0);
    CHECK(closed_and_oriented(back));
    CHECK(back.triangle_count() == mesh.triangle_count() - as_floats.dropped);
    const Solid part = Solid::from_mesh(back, "part.stl");
    CHECK(part.validate(tol).empty());
    // The cube [0, 0.5]^3 lies in the cube [0, 1]^3 that was taken away: nothing changes.
    const Solid cut = Solid::boolean(BooleanOp::Difference, {part, cube.transformed(translate({-0.25, -0.25, -0.25}))});
    double v = 0;
    REQUIRE_NOTHROW(v = cut.mass_properties(tol).volume);
    CHECK(v == Approx(back.volume() - 0.125 + 0.125 / 8).epsilon(1e-6));
  }
}

TEST_CASE("file_mesh mends a triangle that floats make flat by splitting its neighbour", "[mesh_io][rounding]") {
  // A tetrahedron x, y, d, a whose edge x-y carries a sliver x, y, m: m is 1e-12 off the
  // midpoint of x-y as doubles and on it as floats. Mended, the sliver goes and the base y, x, d
  // becomes y, m, d and m, x, d: six triangles again, none flat, the tetrahedron's volume 4/3.
  Mesh t;
  const std::uint32_t x = t.add_vertex({1, 1, 1}), y = t.add_vertex({3, 1, 1}), d = t.add_vertex({2, 3, 1}),
                      a = t.add_vertex({2, 2, 3}), m = t.add_vertex({2, 1 - 1e-12, 1 - 0.6e-12});
  t.add_triangle(x, d, y);
  t.add_triangle(x, y, m);
  t.add_triangle(x, m, a);
  t.add_triangle(m, y, a);
  t.add_triangle(y, d, a);
  t.add_triangle(d, x, a);
  REQUIRE(closed_and_oriented(t));
  REQUIRE(flat_triangles(t) == 0);
  const FileMesh r = file_mesh(t, true);
  CHECK(r.merged == 0);
  CHECK(r.dropped == 0);
  CHECK(r.mended == 1);
  CHECK(r.flat == 0);
  CHECK(r.mesh.triangle_count() == 6);
  CHECK(flat_triangles(r.mesh) == 0);
  CHECK(closed_and_oriented(r.mesh));
  CHECK(r.mesh.volume() == Approx(4.0 / 3));
  CHECK(std::count(r.source.begin(), r.source.end(), std::size_t(0)) == 2);  // both halves from the base
  CHECK(file_mesh(t, false).mended == 0);  // as doubles nothing is flat

  // With the base gone the sliver's long edge x-y is an open border: the sliver just goes.
  Mesh open = t;
  open.triangles.erase(open.triangles.begin());
  const FileMesh o = file_mesh(open, true);
  CHECK(o.mended == 1);
  CHECK(o.flat == 0);
  CHECK(o.mesh.triangle_count() == 4);
  CHECK(flat_triangles(o.mesh) == 0);
}
