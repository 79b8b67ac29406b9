// Big-but-finite and tiny-but-positive geometry (sizes from 1e-90 to 1e100, inside the +-1e100
// range every builder accepts) measured against closed forms, and the triangle budget counted on
// every mesh: planar faces, boolean results, imported meshes. Each script asserts its values;
// the budget cases check the message (what, the estimate, the option to raise) and the line.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/lua/run_lua.h"

namespace fs = std::filesystem;

namespace {

using Run = LuaRun;
Run run(const std::string& code) { return run_lua(code, "@sizes.lua"); }

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("wedge-sizes-" + std::to_string(::getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string lua() const { return "local dir = '" + dir.string() + "'\n"; }
};

// close(a, b, rel): a within rel of b, relatively.
const char* kHelpers = R"(
local function close(a, b, rel, what)
  assert(math.abs(a - b) <= rel * math.abs(b), what .. ": " .. a .. " is not within " .. rel .. " of " .. b)
end
)";

}  // namespace

TEST_CASE("solids from 1e-90 to 1e100 wide: volume, area, centroid and tessellation as at size 1", "[lua][extreme]") {
  for (const char* size : {"1e-90", "1e-30", "1e30", "1e90", "1e100"}) {
    INFO(size);
    Run r = run(std::string(kHelpers) + "local S = " + size + R"(
tolerance(S * 1e-3)
local pi = math.pi
-- A box 1e90 wide failed with "plane: the normal must be non-zero" (its Newell normals' squared
-- lengths overflowed); its centroid was nan.
local b = box(S, S, S)
close(b:volume(), S^3, 1e-12, "box volume")
close(b:area(), 6 * S^2, 1e-12, "box area")
close(b:centroid()[1], S / 2, 1e-12, "box centroid")
assert(b:is_valid() and b:triangles() == 12)
close(box{size = {S, S, S}, center = true}:translate(S / 2, 0, 0):centroid()[1], S / 2, 1e-12, "centred box centroid")
close(sphere(S):volume(), 4 / 3 * pi * S^3, 1e-9, "sphere volume")
close(sphere(S):area(), 4 * pi * S^2, 1e-9, "sphere area")
close(cylinder(S, S):volume(), pi * S^3, 1e-9, "cylinder volume")
close(torus(S / 2, S / 4):volume(), 2 * pi^2 * (S / 2) * (S / 4)^2, 1e-9, "torus volume")
close(extrude(circle(S), S):volume(), pi * S^3, 1e-9, "extruded circle volume")
close(polyhedron{points = {{0,0,0},{S,0,0},{0,S,0},{0,0,S}}, faces = {{1,3,2},{1,2,4},{2,3,4},{1,4,3}}}:volume(), S^3 / 6, 1e-12, "tetrahedron")
-- The tessellation does not depend on the size at a tolerance in proportion (a sphere 1e-82 wide
-- came out with no triangles at all).
local n1 = (function() tolerance(1e-3) local n = sphere(1):triangles() tolerance(S * 1e-3) return n end)()
close(sphere(S):triangles(), n1, 0.01, "sphere triangles")
close(sphere(S / 2):rotate(30, {1, 1, 0}):volume(), pi / 6 * S^3, 1e-9, "rotated sphere")
-- A box less a box: the mesh's volume and area (they were inf for 1e90).
local d = box(S, S, S) - box(S / 2, S / 2, S / 2):translate(S / 4, S / 4, S / 4)
close(d:volume(), S^3 * 7 / 8, 1e-12, "difference volume")
close(d:area(), 6 * S^2 * 5 / 4, 1e-12, "difference area")
assert(d:contains{S / 2, S / 2, S / 2} == "outside" and d:contains{S / 8, S / 8, S / 8} == "inside")
local c = b:cells{size = S / 4}
assert(c.volume_min <= S^3 and S^3 <= c.volume_max, "cells bracket the volume")
-- An open path is open at any size (a path 1e-20 long was "closed", and the sweep failed).
assert(not bezier{{0, 0, 0}, {S, 0, S}, {2 * S, 0, 0}}:closed())
)");
    CHECK(r.err == "");
    CHECK(r.status == 0);
  }
}

TEST_CASE("an axis or a factor of extreme size is still the direction or factor it says", "[lua][extreme]") {
  // rotate(30, {1e308, 1e308, 0}) normalised its axis to zero and changed a box's volume to 0.6495;
  // inverse(scale(1e-200, 1, 1)) was "singular (rank 3 of 4)".
  Run r = run(std::string(kHelpers) + R"(
close(box(1, 1, 1):rotate(30, {1e308, 1e308, 0}):volume(), 1, 1e-12, "rotated box")
close(box(1, 1, 1):rotate(30, {5e-324, 0, 0}):bounds().max[2], box(1, 1, 1):rotate_x(30):bounds().max[2], 1e-15, "tiny axis")
close(box(1, 1, 1):mirror({1e300, 0, 0}):volume(), 1, 1e-12, "mirror")
close(matrix.scale(1e-200, 1, 1):inverse():get(1, 1), 1e200, 1e-15, "inverse")
close(extruded_surface(circle(1), {0, 0, 5e-324}):eval(0, 1)[3], 5e-324, 0, "tiny extrusion")
)");
  CHECK(r.err == "");
}

TEST_CASE("a sweep along a path 1e-20 long turns its frames as at size 1", "[lua][extreme]") {
  // Steps below an absolute 1e-12 were taken for rounding: the frames never turned and the volume
  // came out 0.0375 S^3 instead of 0.0721 S^3.
  Run r = run(std::string(kHelpers) + R"(
local function v(S) tolerance(S * 1e-3) return sweep(circle(S / 10), bezier{{0, 0, 0}, {S, 0, S}, {2 * S, 0, 0}}):volume() / S^3 end
close(v(1e-20), v(1), 1e-6, "swept volume")
close(v(1e90), v(1), 1e-6, "swept volume")
)");
  CHECK(r.err == "");
}

TEST_CASE("an inertia tensor beyond doubles is an error that says so, not inf or 0", "[lua][extreme]") {
  Run r = run("local _ = 1\nlocal i = box(1e90, 1e90, 1e90):inertia()\n");
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Catch::StartsWith("sizes.lua:2: inertia: the inertia tensor overflows: the solid's volume 1e+270 times its size squared"));
  r = run("local _ = 1\nlocal i = sphere(1e-90):inertia()\n");
  CHECK_THAT(r.err, Catch::StartsWith("sizes.lua:2: inertia: the inertia tensor underflows"));
  // Within range, about the centroid: a cube of side S has I = S^5 / 6 on the diagonal.
  r = run(std::string(kHelpers) + "local S = 1e60\nlocal I = box(S, S, S):translate(S, 0, 0):inertia()\nclose(I[1][1], S^5 / 6, 1e-12, 'I')\n");
  CHECK(r.err == "");
}

TEST_CASE("render, drawing and OBJ export of a part far from unit size", "[lua][extreme]") {
  Scratch s;
  // A view of a box 1e10 wide was "matrix is singular (rank 3 of 4)": LU of the view matrix judged
  // its rotation against its translation. The picture does not depend on the size.
  Run r = run(s.lua() + R"(
for i, S in ipairs{1, 1e10, 1e90} do
  tolerance(S * 1e-3)
  render{box(S, S, S), out = dir .. '/box' .. i .. '.png', size = {32, 32}, view = 'iso'}
  drawing{sphere(S), out = dir .. '/sheet' .. i .. '.png', size = {64, 64}}
end
tolerance(1e87)
assert(export(sphere(1e90), dir .. '/s.obj') > 1000)
)");
  CHECK(r.err == "");
  auto bytes = [&](const std::string& name) {
    std::ostringstream o;
    o << std::ifstream(s.dir / name, std::ios::binary).rdbuf();
    return o.str();
  };
  CHECK(bytes("box1.png").size() > 100);
  CHECK(bytes("box2.png") == bytes("box1.png"));
  CHECK(bytes("box3.png") == bytes("box1.png"));
  CHECK(fs::file_size(s.dir / "s.obj") > 1000);
}

TEST_CASE("STL refuses a part whose coordinates its 32-bit floats cannot hold", "[lua][extreme]") {
  Scratch s;
  Run r = run(s.lua() + "export(box(1e-90, 1e-90, 1e-90), dir .. '/tiny.stl')\n");
  CHECK_THAT(r.err, Catch::StartsWith("sizes.lua:2: export: cannot write '" + (s.dir / "tiny.stl").string() +
                                      "': the mesh's largest coordinate 9.9999999999999999e-91 is below"));
  CHECK_THAT(r.err, Catch::Contains("where STL's 32-bit floats lose their digits (scale the part up, or write .ply or .obj)"));
  CHECK_FALSE(fs::exists(s.dir / "tiny.stl"));
  r = run(s.lua() + "assert(export(box(1e-90, 1e-90, 1e-90), dir .. '/tiny.ply') == 12)\n");
  CHECK(r.err == "");
}

TEST_CASE("the triangle budget counts planar faces, boolean results and imported meshes", "[lua][extreme][budget]") {
  Scratch s;
  const std::string file = (s.dir / "x.stl").string();
  // A box is 12 triangles at any tolerance; the budget counted only curved faces' triangles.
  Run r = run(s.lua() + "export(box(1, 1, 1), dir .. '/x.stl', {max_triangles = 11})\n");
  CHECK(r.err.rfind("sizes.lua:2: export: tessellate: the solid's planar faces make 12 triangles at any tolerance, "
                    "more than the budget of 11: raise the budget with tolerance{max_triangles=N}", 0) == 0);
  CHECK_FALSE(fs::exists(file));
  r = run(s.lua() + "assert(export(box(1, 1, 1), dir .. '/x.stl', {max_triangles = 12}) == 12)\n");
  CHECK(r.err == "");
  r = run("local _ = 1\ntolerance{max_triangles = 100}\nlocal n = polygon{{0,0},{1,0},{1,1},{0,1}}:area() + extrude(circle(1), 1):triangles()\n");
  CHECK_THAT(r.err, Catch::StartsWith("sizes.lua:3: triangles: "));
  CHECK_THAT(r.err, Catch::Contains("more than the budget of 100"));
  // A boolean: its operands' triangles together, before the engine runs.
  r = run(s.lua() + "export(box(2, 2, 2) - box(1, 1, 1):translate(0.5, 0.5, 0.5), dir .. '/x.stl', {max_triangles = 23})\n");
  CHECK(r.err.rfind("sizes.lua:2: export: boolean: the difference of 2 operands would make about 24 triangles "
                    "(its operands' together), more than the budget of 23: raise the budget with tolerance{max_triangles=N}", 0) == 0);
  // A result kept from an evaluation under the default budget is checked all the same, as is a
  // union of parts apart (no engine call).
  r = run(s.lua() + "local d = box(2, 2, 2) - box(1, 1, 1):translate(0.5, 0.5, 0.5)\nassert(math.abs(d:volume() - 7) < 1e-12)\n"
                    "export(d, dir .. '/x.stl', {max_triangles = 20})\n");
  CHECK(r.err.rfind("sizes.lua:4: export: the mesh has 24 triangles, more than the budget of 20: raise the budget with tolerance{max_triangles=N}", 0) == 0);
  r = run(s.lua() + "local u = box(1, 1, 1) + box(1, 1, 1):translate(5, 0, 0)\nexport(u, dir .. '/x.obj', {max_triangles = 20})\n");
  CHECK(r.err.rfind("sizes.lua:3: export: the mesh has 24 triangles, more than the budget of 20: raise the budget with tolerance{max_triangles=N}", 0) == 0);
  // An imported mesh.
  r = run(s.lua() + "export(box(1, 1, 1), dir .. '/b.off')\nlocal m = import(dir .. '/b.off')\ntolerance{max_triangles = 11}\nlocal n = m:triangles()\n");
  CHECK(r.err.rfind("sizes.lua:5: triangles: the mesh has 12 triangles, more than the budget of 11: raise the budget with tolerance{max_triangles=N}", 0) == 0);
}

TEST_CASE("the triangle budget refuses a scaled curved boolean at once from its estimate", "[lua][extreme][budget]") {
  // The estimate counted the ideal mesh, about half of what the refinement makes: scaled by 1e4
  // (its leaves at tolerance 1e-6), torus - cylinder passed the estimate and volume() refined for
  // 84 s and 3.2 GB before the refinement's own count refused it.
  Run r = run(std::string(kHelpers) + R"(
tolerance{max_triangles = 1000000}
local s = torus{R = 2, r = 0.5} - cylinder{r = 0.6, h = 2}:translate(2, 0, -1)
local t0 = os.clock()
local ok, err = pcall(function() return s:scale(1e3):volume() end)
assert(not ok and err:find("would need", 1, true) and err:find("tolerance{max_triangles=N}", 1, true), err)
assert(os.clock() - t0 < 1, "refused after " .. (os.clock() - t0) .. " s")
-- A mesh within the budget is not refused by its estimate (16,792 triangles).
assert(torus{R = 2, r = 0.5}:triangles{tolerance = 1e-3, max_triangles = 20000} > 16000)
)");
  CHECK(r.err == "");
}
