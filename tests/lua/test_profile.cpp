#include <catch2/catch.hpp>

#include <sstream>

#include "lua/wedge_lua.h"

namespace {
struct Run {
  int status;
  std::string err;
};
Run run(const std::string& code, const std::string& chunk = "@profile.lua") {
  std::ostringstream err;
  int status = wedge::lua::run_string(code, chunk, err);
  return {status, err.str()};
}
}  // namespace

TEST_CASE("extrude builds prisms, frusta and pyramids from profiles", "[lua][profile]") {
  auto r = run(R"(
    local function near(a, b, tol) return math.abs(a - b) <= (tol or 1e-12) end
    local b = extrude(rect(2, 3), 4)
    assert(near(b:volume(), 24), b:volume())
    local e = b:euler()
    assert(e.V == 8 and e.E == 12 and e.F == 6 and e.S == 1)
    assert(b:is_valid())

    -- A square with a square hole: a through hole, H = 1, R = 2 (one ring on each end face).
    local frame = polygon{outer = {{0,0},{4,0},{4,4},{0,4}}, holes = {{{1,1},{3,1},{3,3},{1,3}}}}
    assert(near(frame:area(), 12))
    local f = extrude(frame, 2)
    assert(near(f:volume(), 24))
    e = f:euler()
    assert(e.V == 16 and e.E == 24 and e.F == 10 and e.R == 2 and e.H == 1 and e.S == 1)
    assert(e.V - e.E + e.F - e.R + 2 * e.H - 2 * e.S == 0)

    -- A clockwise outline is reoriented, not turned inside out.
    local cw = extrude(polygon{{0,0},{0,1},{1,1},{1,0}}, 1)
    assert(near(cw:volume(), 1))

    -- scale = 0 is a pyramid (area * h / 3), scale 0.5 a frustum.
    assert(near(extrude(rect(3, 3, true), 2, {scale = 0}):volume(), 6))
    assert(near(extrude(rect(2, 2, true), 3, {scale = 0.5}):volume(), 3 * (4 + 1 + 2) / 3))

    -- A closed curve extrudes exactly: its side lies on the swept curve, its volume is exact.
    local c = extrude(circle(1), 1)
    assert(near(c:volume(), math.pi, 1e-12), c:volume())
    local bb = c:bounds()
    assert(near(bb.max[1], 1, 1e-9) and near(bb.max[3], 1))
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("bad profiles and extrude arguments are errors naming the argument", "[lua][profile][errors]") {
  CHECK_THAT(run("rect(-1, 2)\n", "@r.lua").err, Catch::StartsWith("r.lua:1: bad argument #1 to 'rect' (width must be positive"));
  CHECK_THAT(run("polygon{{0,0},{1,1}}\n", "@p.lua").err, Catch::Contains("p.lua:1: polygon: the outer ring needs at least 3 points, got 2"));
  CHECK_THAT(run("polygon{{0,0},{1,1},{2,2}}\n", "@p.lua").err, Catch::Contains("zero area"));
  CHECK_THAT(run("polygon{{0,0},{1,'x'},{2,2}}\n", "@p.lua").err, Catch::Contains("p.lua:1: polygon: point 2 coordinate 2 must be a number, got string"));
  CHECK_THAT(run("extrude(42, 1)\n", "@e.lua").err,
             Catch::StartsWith("e.lua:1: bad argument #1 to 'extrude' (profile (polygon, rect or closed curve) expected, got number)"));
  CHECK_THAT(run("extrude(rect(1,1), 0)\n", "@e.lua").err, Catch::Contains("height must be positive"));
  CHECK_THAT(run("extrude(rect(1,1), 1, {scale = -1})\n", "@e.lua").err, Catch::Contains("e.lua:1: extrude: scale must be zero or positive, got -1"));
  CHECK_THAT(run("extrude(rect(1,1), 1, {scael = 2})\n", "@e.lua").err, Catch::Contains("unknown field 'scael'"));
  CHECK_THAT(run("extrude(bezier{{0,0},{1,1},{2,0}}, 1)\n", "@e.lua").err, Catch::Contains("the curve is open"));
  CHECK_THAT(run("polygon{outer={{0,0},{1,0},{1,1}}, holes=5}\n", "@h.lua").err, Catch::Contains("h.lua:1: polygon: holes must be a list of polygons or closed curves, got number"));
}

TEST_CASE("a curve hole is checked against the outer ring by the exact curve", "[lua][profile][errors]") {
  // The outer ring is the polyline of a circle 1.001 times the hole's radius: the hole's own
  // polyline at the tolerance 0.01 fits inside it, but the exact circle crosses every edge of the
  // ring by up to 0.009. It was accepted, is_valid() said true, and triangles{} then failed.
  auto r = run(R"(
    local pts = circle(1):points{tolerance = 0.01}
    local outer = {}
    for i = 1, #pts - 1 do outer[i] = {1.001 * pts[i][1], 1.001 * pts[i][2]} end
    local p = polygon{outer = outer, holes = {circle(1)}}
  )", "@hole.lua");
  CHECK(r.status != 0);
  CHECK_THAT(r.err, Catch::Contains("hole.lua:5: polygon: hole 1 touches or crosses the outer ring (a hole must lie strictly inside it)"));
  // One edge of a square 0.002 inside the circle, the polyline clear of it.
  auto e = run(R"(
    local a, d = math.rad(5.625), 0.998
    local n, t = {math.cos(a), math.sin(a)}, {-math.sin(a), math.cos(a)}
    local function P(s, u) return {n[1] * s + t[1] * u, n[2] * s + t[2] * u} end
    local p = polygon{outer = {P(-3, -3), P(d, -3), P(d, 3), P(-3, 3)}, holes = {circle(1)}}
  )", "@edge.lua");
  CHECK_THAT(e.err, Catch::Contains("edge.lua:5: polygon: hole 1 touches or crosses the outer ring"));
  // Two circles 1e-6 apart touch nothing; two that overlap by 1e-6 do.
  auto k = run(R"(
    local sq = {{-5, -5}, {5, -5}, {5, 5}, {-5, 5}}
    local p = polygon{outer = sq, holes = {circle(1), circle{r = 1, center = {2 + 1e-6, 0}}}}
    assert(math.abs(p:area() - (100 - 2 * math.pi)) < 0.1, p:area())  -- of the polylines
    assert(math.abs(extrude(p, 1):volume() - (100 - 2 * math.pi)) < 1e-9)
    local ok, err = pcall(polygon, {outer = sq, holes = {circle(1), circle{r = 1, center = {2 - 1e-6, 0}}}})
    assert(not ok and err:find("holes 1 and 2 touch or cross each other", 1, true), err)
  )");
  INFO(k.err);
  CHECK(k.status == 0);
}

TEST_CASE("a closed curve profile that crosses itself is refused by every builder", "[lua][profile][errors]") {
  // A closed Catmull-Rom figure eight: a full revolve has no caps to refuse it, and gave a valid
  // solid of volume 39.80, the lobes' 64.52 and -24.73 summed with their signs.
  auto r = run(R"(
    local c = catmull_rom{points = {{3, 0}, {4, 1}, {5, 0}, {4, -1}, {3, 0}, {2, 1}, {1.5, 0}, {2, -1}}, closed = true}
    local msg = "the curve intersects itself: a profile must be a simple closed curve"
    for name, f in pairs{
      revolve = function() return revolve(c) end,
      revolve90 = function() return revolve(c, {angle = 90}) end,
      extrude = function() return extrude(c, 1) end,
      twist = function() return extrude(c, 1, {twist = 30}) end,
      sweep = function() return sweep(c, bezier{{0, 0, 0}, {0, 0, 5}}) end,
      loft = function() return loft{profiles = {c, c}, heights = {0, 1}} end,
    } do
      local ok, err = pcall(f)
      assert(not ok and err:find(name == "loft" and "loft: profiles[1] curve intersects itself" or msg, 1, true), name .. ": " .. tostring(err))
    end
    -- a simple closed spline still revolves
    local d = catmull_rom{points = {{3, 0}, {4, 1}, {5, 0}, {4, -1}}, closed = true}
    assert(revolve(d):is_valid())
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}
