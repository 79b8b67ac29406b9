// Curved solids through every mesh file format: the tessellation of each primitive and builder,
// written and read back, has the same vertex, edge and triangle counts, the same genus, and every
// edge used exactly twice in opposite directions (checked here by counting, independently of
// euler_counts). OBJ is judged this way only: Debian's meshlabserver aborts on every OBJ file
// (tests/meshlab judges STL, PLY and OFF).
#include <catch2/catch.hpp>

#include <filesystem>
#include <map>

#include "csg/solid.h"
#include "tessellate/brep_mesh.h"
#include "tessellate/tessellate.h"
#include "closed_surface.h"

using namespace wedge;
namespace fs = std::filesystem;

TEST_CASE("curved solids round-trip through OBJ, STL, PLY and OFF with identical topology", "[mesh_io][curved]") {
  fs::path dir = fs::temp_directory_path() / ("wedge-curved-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Section square = section_of(Profile{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}, {}});
  std::vector<std::pair<const char*, Model>> solids = {
      {"sphere", sphere(1)},
      {"cylinder", cylinder(1, 2)},
      {"cone", cone(1, 0, 2)},
      {"frustum", cone(1.5, 0.5, 2)},
      {"torus", torus(2, 0.5)},
      {"tube", tube(2, 1, 1)},
      {"twisted", extrude(square, 2, radians(90), 0.5)},
      {"revolved", revolve(section_of(Profile{{{1, 0}, {2, 0}, {2, 1}, {1, 1}}, {}}), 2 * kPi)},
      {"swept", sweep_along(Section{circle_loop(Vec2::Zero(), 0.5), {}}, std::make_shared<const CircularArc>(Point3::Zero(), 2, 0.0, 2 * kPi))},
      {"lofted", loft({Section{circle_loop(Vec2::Zero(), 1), {}}, Section{circle_loop(Vec2::Zero(), 2), {}}, Section{circle_loop(Vec2::Zero(), 1), {}}}, {0, 1, 2})},
  };
  Tolerance tol;
  tol.chordal = 1e-3;
  for (const auto& [name, model] : solids) {
    Mesh mesh = tessellate(model, tol);
    std::size_t V0 = 0, E0 = 0;
    REQUIRE(closed_and_oriented(mesh, &V0, &E0));
    EulerCounts ec0 = euler_counts(mesh);
    for (const char* ext : {".obj", ".stl", ".ply", ".off"})
      for (bool ascii : {false, true}) {
        INFO(name << ext << (ascii ? " ascii" : " binary"));
        std::string path = (dir / (std::string(name) + ext)).string();
        write_mesh(mesh, path, {ascii});
        Mesh back = read_mesh(path);
        std::size_t V = 0, E = 0;
        CHECK(closed_and_oriented(back, &V, &E));
        CHECK(V == V0);
        CHECK(E == E0);
        CHECK(back.triangle_count() == mesh.triangle_count());
        CHECK(euler_counts(back) == ec0);
        CHECK(back.volume() == Approx(mesh.volume()).epsilon(1e-6));
      }
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}
