#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
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
