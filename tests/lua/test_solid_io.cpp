#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "lua/wedge_lua.h"

namespace fs = std::filesystem;

namespace {
struct Run {
  int status;
  std::string err;
};
Run run(const std::string& code, const std::string& chunk = "@io.lua") {
  std::ostringstream err;
  int status = wedge::lua::run_string(code, chunk, err);
  return {status, err.str()};
}

// A unit tetrahedron as an OFF file, and a directory for the test.
struct Fixture {
  fs::path dir = fs::temp_directory_path() / ("wedge-lua-io-" + std::to_string(::getpid()));
  Fixture() {
    fs::create_directories(dir);
    std::ofstream(dir / "tet.off") << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    std::ofstream(dir / "open.off") << "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n";
  }
  ~Fixture() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string lua_dir() const { return "local dir = '" + dir.string() + "'\n"; }
};
}  // namespace

TEST_CASE("import gives a Solid whose queries, transforms and export work", "[lua][solid][io]") {
  Fixture f;
  auto r = run(f.lua_dir() + R"(
    local t = import(dir .. "/tet.off")
    assert(math.abs(t:volume() - 1/6) < 1e-15, t:volume())
    local e = t:euler()
    assert(e.V == 4 and e.E == 6 and e.F == 4 and e.S == 1 and e.H == 0)
    assert(t:is_valid())
    local b = t:translate(1, 2, 3):bounds()
    assert(b.min[1] == 1 and b.max[3] == 4)
    local big = t:scale(2)
    assert(math.abs(big:volume() - 8/6) < 1e-14)
    local c = t:centroid()
    assert(math.abs(c[1] - 0.25) < 1e-15 and math.abs(c[3] - 0.25) < 1e-15)
    assert(math.abs(t:mirror({1, 0, 0}):volume() - 1/6) < 1e-15)
    assert(t:triangles() == 4)
    local n = export(t:rotate(30, {0, 0, 1}, {1, 1, 1}), dir .. "/out.stl")
    assert(n == 4)
    local back = import(dir .. "/out.stl")
    assert(math.abs(back:volume() - 1/6) < 1e-6)
    export(t, dir .. "/out.obj", {ascii = true})
    assert(tostring(t):find("^Solid"))
    local m = t:material{diffuse = {1, 0, 0}, shininess = 20}
    assert(m:translate(1, 0, 0):volume() > 0)
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("a result whose parts touch at a point is exported and imported back", "[lua][solid][io]") {
  // The union of two cubes that share one corner is written with that corner once per cube; read
  // back (and welded for its checks) the two fans there stay apart: the same solid, two shells.
  // STL keeps no vertices: its facets' corners are welded by position when read, and the weld
  // keeps the two closed fans at the shared corner apart. A bowtie of one vertex index in an
  // indexed file is still refused (tests/tessellate/bad_files).
  Fixture f;
  auto r = run(f.lua_dir() + R"(
    local b = cube(1) + cube(1):translate(1, 1, 1)
    for _, ext in ipairs({"off", "obj", "ply", "stl"}) do
      export(b, dir .. "/touch." .. ext)
      local c = import(dir .. "/touch." .. ext)
      assert(c:is_valid() and math.abs(c:volume() - 2) < 1e-14, ext)
      local e = c:euler()
      assert(e.S == 2 and e.V == 16, ext .. ": " .. e.S .. " shells, " .. e.V .. " vertices")
      assert(math.abs((c + cube(1):translate(5, 5, 5)):volume() - 3) < 1e-14, ext)
      assert(math.abs((c - cube(1):translate(0.5, 0.5, 0.5)):volume() - 1.75) < 1e-14, ext)
    end
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("bad files and bad export arguments are Lua errors naming what was wrong", "[lua][io][errors]") {
  Fixture f;
  auto open = run(f.lua_dir() + "local s = import(dir .. '/open.off')\n", "@imp.lua");
  CHECK_THAT(open.err, Catch::Contains("imp.lua:2: import:"));
  CHECK_THAT(open.err, Catch::Contains("open.off: mesh is not closed"));

  auto missing = run("import('/no/such/part.stl')\n", "@miss.lua");
  CHECK_THAT(missing.err, Catch::StartsWith("miss.lua:1: import: cannot read '/no/such/part.stl'"));

  auto ext = run(f.lua_dir() + "export(import(dir .. '/tet.off'), dir .. '/x.step')\n", "@ext.lua");
  CHECK_THAT(ext.err, Catch::Contains("unknown mesh format '.step'"));

  auto notsolid = run("export(42, 'x.stl')\n", "@ns.lua");
  CHECK_THAT(notsolid.err, Catch::StartsWith("ns.lua:1: bad argument #1 to 'export' (Solid or mesh expected, got number)"));

  auto field = run(f.lua_dir() + "export(import(dir .. '/tet.off'), dir .. '/x.stl', {asci = true})\n", "@f.lua");
  CHECK_THAT(field.err, Catch::Contains("unknown field 'asci'"));

  auto mat = run(f.lua_dir() + "import(dir .. '/tet.off'):material{shininess = 500}\n", "@mat.lua");
  CHECK_THAT(mat.err, Catch::Contains("shininess"));

  auto tol = run("tolerance(-1)\n", "@tol.lua");
  CHECK_THAT(tol.err, Catch::StartsWith("tol.lua:1: bad argument #1 to 'tolerance' (tolerance must be positive"));
  // No stray files from the failed exports.
  CHECK_FALSE(fs::exists(f.dir / "x.stl"));
  CHECK_FALSE(fs::exists(f.dir / "x.step"));
}

TEST_CASE("free-form surfaces export as their meshes", "[lua][io]") {
  Fixture f;
  auto r = run(f.lua_dir() + R"(
    local n = export(teapot(), dir .. "/teapot.ply", {tolerance = 0.05})
    assert(n > 500, n)
    local s = bezier_surface{{{0,0,0},{1,0,0}},{{0,1,0},{1,1,1}}}
    assert(export(s, dir .. "/patch.obj") >= 2)
    -- A closed surface exports closed: the file imports as a solid (import rejects open meshes).
    local ball = revolved_surface(circle{r = 1, center = {2, 0}})
    export(ball, dir .. "/ring.stl", {tolerance = 0.01})
    local ring = import(dir .. "/ring.stl")
    local e = ring:euler()
    assert(e.H == 1 and e.S == 1, "a revolved circle is a torus")
    assert(math.abs(ring:volume() - 2 * math.pi^2 * 2) < 0.02 * 2 * math.pi^2 * 2, ring:volume())
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

#include "render/render.h"

TEST_CASE("a rendered box shades each planar face in one colour (normals split per face)", "[lua][render]") {
  Fixture f;
  auto r = run(f.lua_dir() + R"(
    render{extrude(rect(2, 2, true), 1), out = dir .. "/box.png", size = {64, 64}, shading = "gouraud",
           camera = {eye = {0, 0, 10}, center = {0, 0, 0}, up = {0, 1, 0}, fovy = 30},
           lights = {{type = "directional", direction = {0.3, 0.2, -1}}}}
  )");
  INFO(r.err);
  REQUIRE(r.status == 0);
  wedge::render::Image img = wedge::render::read_png((f.dir / "box.png").string());
  // Seen from above, the top face fills the middle of the picture. With normals shared across
  // the box's edges the colour would vary across it; with per-face normals it is constant.
  auto centre = img.pixel(32, 32);
  for (int y = 24; y <= 40; y += 4)
    for (int x = 24; x <= 40; x += 4) CHECK(img.pixel(x, y) == centre);
  CHECK(centre != img.pixel(1, 1));  // and it is not the background
}

TEST_CASE("render{} takes a named view at the top level or as camera=", "[lua][render]") {
  Fixture f;
  auto ok = run(f.lua_dir() + R"(
    local b = box(1, 2, 3)
    render{b, out = dir .. "/front.png", size = {64, 64}, view = "front"}
    render{b, out = dir .. "/top.png", size = {64, 64}, camera = "top"}
  )");
  INFO(ok.err);
  REQUIRE(ok.status == 0);
  // The images, not only the files: a 1 x 2 x 3 box seen along +Y (front: picture x = world X,
  // y = world Z) is a 1 x 3 rectangle, seen from above (top: x = X, y = Y) a 1 x 2 one. The
  // pixels unlike the background's corner span a box of those proportions, filling most of the
  // image along its longer side (the view is fitted around the part).
  auto extent = [](const fs::path& path) {
    const wedge::render::Image im = wedge::render::read_png(path.string());
    int x0 = im.width, x1 = -1, y0 = im.height, y1 = -1;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x)
        if (im.pixel(x, y) != im.pixel(0, 0)) x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    return std::pair<int, int>(x1 - x0 + 1, y1 - y0 + 1);
  };
  const auto [fw, fh] = extent(f.dir / "front.png");
  const auto [tw, th] = extent(f.dir / "top.png");
  INFO("front " << fw << " x " << fh << ", top " << tw << " x " << th);
  CHECK(fh >= 48);
  CHECK(th >= 48);
  CHECK(std::abs(3.0 * fw / fh - 1) < 0.12);
  CHECK(std::abs(2.0 * tw / th - 1) < 0.08);
  auto both = run(f.lua_dir() + "render{box(1,1,1), out = dir .. '/x.png', view = 'iso', camera = {eye = {1,1,1}}}\n", "@v.lua");
  CHECK_THAT(both.err, Catch::Contains("either camera={...} or view="));
  auto bad = run(f.lua_dir() + "render{box(1,1,1), out = dir .. '/x.png', camera = 42}\n", "@v.lua");
  CHECK_THAT(bad.err, Catch::Contains("render: camera must be a table or a view name, got number"));
  CHECK_FALSE(fs::exists(f.dir / "x.png"));
}
