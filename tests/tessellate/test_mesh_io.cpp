#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "csg/solid.h"
#include "tessellate/tessellate.h"

using namespace wedge;
namespace fs = std::filesystem;

namespace {
Mesh box_mesh(double a, double b, double c) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.add_vertex({(i & 1) ? a : 0, (i & 2) ? b : 0, (i & 4) ? c : 0});
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.add_triangle(q[0], q[1], q[2]);
    m.add_triangle(q[0], q[2], q[3]);
  }
  return m;
}

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("wedge-test-" + std::to_string(::getpid()) + "-" + std::to_string(rand()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::size_t count() const { return static_cast<std::size_t>(std::distance(fs::directory_iterator(path), fs::directory_iterator())); }
};
}  // namespace

TEST_CASE("meshes round-trip through every format and stay closed", "[mesh_io]") {
  TempDir dir;
  Mesh box = box_mesh(1.5, 2.25, 3.125).transformed(translate({0.1, -0.2, 0.3}));
  for (std::string name : {"a.obj", "b.stl", "c.ply", "d.off", "E.STL"}) {
    for (bool ascii : {false, true}) {
      INFO(name << " ascii=" << ascii);
      write_mesh(box, dir.file(name), {ascii});
      Mesh back = read_mesh(dir.file(name));
      CHECK(back.triangle_count() == 12);
      CHECK(back.vertex_count() == 8);  // STL's repeated corners are merged back into vertices
      // STL stores floats; the others keep doubles.
      CHECK(back.volume() == Approx(box.volume()).epsilon(1e-6));
      CHECK(euler_counts(back) == EulerCounts{8, 18, 12, 0, 0, 1});
      CHECK(back.face_ids.empty());  // a file's triangles belong to no B-Rep face
    }
  }
  CHECK(dir.count() == 5);  // no temporary files left behind
}

TEST_CASE("OBJ keeps its own normals and per-corner texture coordinates", "[mesh_io]") {
  TempDir dir;
  std::ofstream(dir.file("quad.obj")) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
                                         "vn 0 0 1\n"
                                         "f 1/1/1 2/2/1 3/3/1\nf 1/5/1 3/3/1 4/4/1\n";
  Mesh m = read_mesh(dir.file("quad.obj"));
  REQUIRE(m.triangle_count() == 2);
  REQUIRE(m.uvs.size() == m.vertex_count());
  // Vertex 1 is used with two different uvs, so it is split: 5 vertices.
  CHECK(m.vertex_count() == 5);
  CHECK(m.uvs[m.triangles[1][0]] == Vec2(0.5, 0.5));
  CHECK(m.uvs[m.triangles[0][0]] == Vec2(0, 0));
  REQUIRE(m.normals.size() == m.vertex_count());
  for (const auto& n : m.normals) CHECK(n == Vec3(0, 0, 1));
}

namespace {
// A faceted, textured cube as modellers write it: 8 positions, each face a quad with its own
// normal (one `vn` per face) and the whole texture (vt 1-4), so every position is used with three
// normals and several uvs: the uv seams and normal creases split it into 24 render vertices.
const char* kSeamedCube =
    "# seamed, faceted, textured cube\n"
    "o cube\n"
    "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n"
    "s off\n"
    "f 1/1/1 3/2/1 4/3/1 2/4/1\n"
    "f 5/1/2 6/2/2 8/3/2 7/4/2\n"
    "f 1/1/3 2/2/3 6/3/3 5/4/3\n"
    "f 3/1/4 7/2/4 8/3/4 4/4/4\n"
    "f 1/1/5 5/2/5 7/3/5 3/4/5\n"
    "f 2/1/6 4/2/6 8/3/6 6/4/6\n";
}  // namespace

TEST_CASE("a seamed, faceted, textured cube OBJ keeps each corner's normal and uv, and is a closed solid", "[mesh_io]") {
  TempDir dir;
  std::ofstream(dir.file("cube.obj")) << kSeamedCube;
  Mesh m = read_mesh(dir.file("cube.obj"));
  REQUIRE(m.triangle_count() == 12);    // each quad fanned into two: the file's own triangles
  CHECK(m.vertex_count() == 24);        // 6 faces x 4 corners, keyed by (position, uv, normal)
  REQUIRE(m.normals.size() == 24);
  REQUIRE(m.uvs.size() == 24);
  const Vec3 face_n[6] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}};
  const Vec2 quad_uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (std::size_t t = 0; t < 12; ++t) {
    INFO("triangle " << t);
    const auto& tri = m.triangles[t];
    const std::size_t f = t / 2;
    for (int k = 0; k < 3; ++k) CHECK(m.normals[tri[k]] == face_n[f]);  // not smeared across faces
    CHECK(m.triangle_normal(t).isApprox(face_n[f]));                     // counter-clockwise outside
    // Fanned from the first corner: (0, 1, 2) and (0, 2, 3) of the quad, with their uvs.
    const int corners[2][3] = {{0, 1, 2}, {0, 2, 3}};
    for (int k = 0; k < 3; ++k) CHECK(m.uvs[tri[k]] == quad_uv[corners[t % 2][k]]);
  }
  // By index the split mesh is open; the Solid checks the vertices welded by position.
  CHECK_THROWS_WITH(euler_counts(m), Catch::Contains("not closed"));
  Solid s = Solid::from_mesh(m, "cube.obj");
  Tolerance tol;
  CHECK(s.euler(tol) == EulerCounts{8, 18, 12, 0, 0, 1});
  CHECK(s.mass_properties(tol).volume == Approx(8));
  CHECK(s.mesh(tol).vertex_count() == 24);  // and renders the mesh as read
}

TEST_CASE("OBJ corners without normals get area-weighted smooth ones around their file vertex", "[mesh_io]") {
  TempDir dir;
  // The seamed cube with its normals stripped: uv seams split the vertices, but the shading must
  // not crease there: every copy of a file vertex gets the same area-weighted normal.
  std::string stripped = std::regex_replace(std::regex_replace(kSeamedCube, std::regex("vn [^\n]*\n"), ""),
                                            std::regex("(\\d+/\\d+)/\\d+"), "$1");  // "1/1/5" -> "1/1"
  REQUIRE(stripped.find("1/1/") == std::string::npos);
  std::ofstream(dir.file("smooth.obj")) << stripped;
  Mesh m = read_mesh(dir.file("smooth.obj"));
  REQUIRE(m.triangle_count() == 12);
  REQUIRE(m.normals.size() == m.vertex_count());
  for (std::size_t i = 0; i < m.vertex_count(); ++i) {
    // The corner (+-1, +-1, +-1): the faces around it are fanned so that the area-weighted
    // normal points out along the diagonal, within the fan's asymmetry.
    Vec3 diag = m.positions[i].normalized();
    CHECK(m.normals[i].norm() == Approx(1));
    CHECK(m.normals[i].dot(diag) > 0.9);
    for (std::size_t j = 0; j < m.vertex_count(); ++j)
      if (m.positions[j] == m.positions[i]) CHECK(m.normals[j] == m.normals[i]);
  }
  // Without normals and without splits the file gives no normals: the renderer computes them.
  std::ofstream(dir.file("plain.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  Mesh plain = read_mesh(dir.file("plain.obj"));
  CHECK(plain.vertex_count() == 4);
  CHECK(plain.normals.empty());
  CHECK(plain.uvs.empty());
}

TEST_CASE("OBJ keeps every triangle it gives, resolves relative indices and names bad lines", "[mesh_io]") {
  TempDir dir;
  // Three triangles on one edge (non-manifold: a half-edge reader drops or duplicates one), a
  // degenerate one, and relative (negative) indices.
  std::ofstream(dir.file("fan.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                                        "f 1 2 3\nf 2 1 4\nf -5 -4 -1\nf 1 1 2\n";
  Mesh m = read_mesh(dir.file("fan.obj"));
  REQUIRE(m.triangle_count() == 4);
  CHECK(m.vertex_count() == 5);
  CHECK(m.positions[m.triangles[2][2]] == Point3(0, 0, 1));
  std::ofstream(dir.file("far.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 7\n";
  CHECK_THROWS_WITH(read_mesh(dir.file("far.obj")), Catch::Contains("far.obj': line 5: face 1 corner 3: vertex index 7 is out of range (3 vertices in the file, numbered from 1)"));
  std::ofstream(dir.file("bad.obj")) << "v 0 0 zero\n";
  CHECK_THROWS_WITH(read_mesh(dir.file("bad.obj")), Catch::Contains("line 1: vertex 1: 'zero' is not a number"));
  std::ofstream(dir.file("none.obj")) << "# nothing\nv 0 0 0\n";
  CHECK_THROWS_WITH(read_mesh(dir.file("none.obj")), Catch::Contains("holds no triangles"));
}

TEST_CASE("unreadable, empty, unknown and broken files are errors naming the path", "[mesh_io][errors]") {
  TempDir dir;
  CHECK_THROWS_WITH(read_mesh(dir.file("missing.stl")), Catch::Contains("missing.stl': No such file"));
  CHECK_THROWS_WITH(read_mesh(dir.file("part.step")), Catch::Contains("unknown mesh format '.step'"));
  std::ofstream(dir.file("empty.obj")).flush();
  CHECK_THROWS_WITH(read_mesh(dir.file("empty.obj")), Catch::Contains("empty"));
  std::ofstream(dir.file("junk.off")) << "this is not an OFF file\n";
  CHECK_THROWS_WITH(read_mesh(dir.file("junk.off")), Catch::Contains("junk.off"));
}

TEST_CASE("a failed write leaves no file and never clobbers the old one", "[mesh_io][errors]") {
  TempDir dir;
  Mesh box = box_mesh(1, 1, 1);
  CHECK_THROWS_WITH(write_mesh(box, dir.file("no/such/dir/x.stl")), Catch::Contains("does not exist"));
  write_mesh(box, dir.file("keep.stl"));
  auto size_before = fs::file_size(dir.file("keep.stl"));
  Mesh bad = box;
  bad.triangles.push_back(bad.triangles[0]);  // a repeated triangle: non-manifold
  CHECK_THROWS_WITH(write_mesh(bad, dir.file("keep.stl")), Catch::Contains("non-manifold"));
  CHECK(fs::file_size(dir.file("keep.stl")) == size_before);
  CHECK(read_mesh(dir.file("keep.stl")).triangle_count() == 12);
  CHECK(dir.count() == 1);
  CHECK_THROWS_WITH(write_mesh(Mesh(), dir.file("empty.stl")), Catch::Contains("no triangles"));
}

TEST_CASE("concave polygon faces are triangulated inside themselves, in OBJ, OFF and PLY", "[mesh_io]") {
  // An L-shaped prism (the L: 2 x 2 less a 1 x 1 corner, 1 high) with each face one polygon, as
  // CAD exporters write it. Fanned from their first corner, the L's ends had triangles across the
  // missing corner: the solid crossed itself (a boolean refused it) though its volume looked right.
  TempDir dir;
  const char* points = "0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n0 0 1\n2 0 1\n2 1 1\n1 1 1\n1 2 1\n0 2 1\n";
  const std::vector<std::vector<int>> faces = {{5, 4, 3, 2, 1, 0}, {6, 7, 8, 9, 10, 11}, {0, 1, 7, 6}, {1, 2, 8, 7},
                                               {2, 3, 9, 8},       {3, 4, 10, 9},        {4, 5, 11, 10}, {5, 0, 6, 11}};
  {
    std::ofstream obj(dir.file("l.obj"));
    std::istringstream in(points);
    for (std::string line; std::getline(in, line);) obj << "v " << line << "\n";
    for (const auto& f : faces) {
      obj << "f";
      for (int i : f) obj << " " << i + 1;
      obj << "\n";
    }
  }
  {
    std::ofstream off(dir.file("l.off"));
    off << "OFF\n12 " << faces.size() << " 0\n" << points;
    for (const auto& f : faces) {
      off << f.size();
      for (int i : f) off << " " << i;
      off << "\n";
    }
  }
  {
    std::ofstream ply(dir.file("l.ply"));
    ply << "ply\nformat ascii 1.0\nelement vertex 12\nproperty double x\nproperty double y\nproperty double z\n"
           "element face " << faces.size() << "\nproperty list uchar int vertex_indices\nend_header\n" << points;
    for (const auto& f : faces) {
      ply << f.size();
      for (int i : f) ply << " " << i;
      ply << "\n";
    }
  }
  Tolerance tol;
  for (const char* name : {"l.obj", "l.off", "l.ply"}) {
    INFO(name);
    const Mesh m = read_mesh(dir.file(name));
    CHECK(m.triangle_count() == 20);  // 4 in each end, 2 in each of the 6 sides
    CHECK(mesh_solid_defect(m).empty());  // no triangle across the missing corner
    CHECK(m.volume() == Approx(3).epsilon(1e-12));
    CHECK(m.area() == Approx(14).epsilon(1e-12));
    const Solid s = Solid::from_mesh(m, name);
    CHECK(s.contains({1.5, 1.5, 0.5}, tol) == Membership::Outside);
    CHECK(s.contains({0.5, 1.5, 0.5}, tol) == Membership::Inside);
  }
  // A polygon whose edges cross (a star, winding twice) is an error naming its line.
  std::ofstream(dir.file("star.obj")) << "v 0 1 0\nv 0.588 -0.809 0\nv -0.951 0.309 0\nv 0.951 0.309 0\nv -0.588 -0.809 0\n"
                                         "f 1 2 3 4 5\n";
  CHECK_THROWS_WITH(read_mesh(dir.file("star.obj")), Catch::Contains("line 6: face 1: its edges cross each other"));
}

TEST_CASE("import errors number an OBJ's faces as the file does and name edges by their ends", "[mesh_io][errors]") {
  TempDir dir;
  // The first corner of the first face is "face 1 corner 1" (it was "face 0 corner 0" in a file
  // whose first vertex is 1).
  std::ofstream(dir.file("zero.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 0 1 2\n";
  CHECK_THROWS_WITH(read_mesh(dir.file("zero.obj")), Catch::Contains("line 5: face 2 corner 1 '0': vertex index 0"));
  // A tetrahedron with its last face missing, the vertices listed in another order than the faces
  // first use them: the error was "edge 3-7"-style mesh numbering, which is not the file's. Now
  // the edge is named by its ends.
  std::ofstream(dir.file("open.obj")) << "v 0 0 1\nv 0 1 0\nv 1 0 0\nv 0 0 0\nf 4 2 3\nf 4 3 1\nf 4 1 2\n";
  const Mesh open = read_mesh(dir.file("open.obj"));
  CHECK_THROWS_WITH(Solid::from_mesh(open, "open.obj"),
                    Catch::Contains("mesh is not closed: the edge from (") && Catch::Contains(") has only one triangle") &&
                        !Catch::Contains("edge 0-") && !Catch::Contains("edge 1-") && !Catch::Contains("edge 2-"));
  // An STL has no vertex numbers: its degenerate facet is given by its number from 1 and its point
  // (bad_files/degenerate.stl).
}

TEST_CASE("an ASCII STL with upper-case keywords is read as ASCII", "[mesh_io]") {
  // SOLID / FACET NORMAL / VERTEX (as some exporters write them) was taken for a binary STL:
  // "binary STL declares 824203333 triangles (41210166734 bytes) but the file has ... bytes".
  TempDir dir;
  std::string text = "SOLID X\n";
  const char* tris[4][3] = {{"0 0 0", "0 1 0", "1 0 0"}, {"0 0 0", "1 0 0", "0 0 1"}, {"0 0 0", "0 0 1", "0 1 0"}, {"1 0 0", "0 1 0", "0 0 1"}};
  for (const auto& t : tris)
    text += std::string("  Facet Normal 0 0 0\n    OUTER LOOP\n") + "      VERTEX " + t[0] + "\n      VERTEX " + t[1] +
            "\n      VERTEX " + t[2] + "\n    ENDLOOP\n  ENDFACET\n";
  text += "ENDSOLID X\n";
  std::ofstream(dir.file("upper.stl")) << text;
  const Mesh m = read_mesh(dir.file("upper.stl"));
  CHECK(m.triangle_count() == 4);
  CHECK(m.vertex_count() == 4);
  CHECK(m.volume() == Approx(1.0 / 6));
  CHECK_NOTHROW(Solid::from_mesh(m, "upper.stl"));
  // A keyword that is wrong in any case is still named.
  std::ofstream(dir.file("typo.stl")) << "SOLID X\nFACET NORMAL 0 0 0\nOUTER LOP\n";
  CHECK_THROWS_WITH(read_mesh(dir.file("typo.stl")), Catch::Contains("line 3: expected 'loop', got 'LOP'"));
}
