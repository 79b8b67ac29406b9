// canvas{}: the 2D raster algorithms reached from Lua. Each check is a hand-worked value: the
// pixels of a Bresenham line and of a midpoint circle worked step by step, the pixel centres
// inside a rectangle, the even-odd and non-zero rules on a pentagram's centre, a flood fill's
// cell count, and what clipping keeps; bad arguments are errors that name them.
#include <catch2/catch.hpp>

#include <cstdio>
#include <sstream>

#include "lua/wedge_lua.h"
#include "render/render.h"

using namespace wedge::lua;

namespace {
struct Result {
  int status;
  std::string err;
};
Result run_lua(const std::string& code) {
  std::ostringstream err;
  int status = run_string(code, "@canvas.lua", err);
  return {status, err.str()};
}
// Lua helpers: black(c, x, y) and a count of the black pixels.
const char* kHelpers = R"LUA(
  local function black(c, x, y) local p = c:pixel(x, y) return p[1] == 0 and p[2] == 0 and p[3] == 0 end
  local function count(c)
    local w, h = c:size()
    local n = 0
    for y = 0, h - 1 do for x = 0, w - 1 do if black(c, x, y) then n = n + 1 end end end
    return n
  end
)LUA";
}  // namespace

TEST_CASE("canvas lines: Bresenham and DDA give the worked pixels", "[lua][canvas]") {
  auto r = run_lua(std::string(kHelpers) + R"LUA(
    -- (0,0) to (5,2): y = 0.4 x rounds to 0 0 1 1 2 2 (no ties), by either algorithm.
    for _, alg in ipairs{"bresenham", "dda"} do
      local c = canvas{width = 8, height = 4}
      c:line{{0, 0}, {5, 2}, algorithm = alg}
      local want = {{0, 0}, {1, 0}, {2, 1}, {3, 1}, {4, 2}, {5, 2}}
      for _, p in ipairs(want) do assert(black(c, p[1], p[2]), alg .. " misses " .. p[1] .. "," .. p[2]) end
      assert(count(c) == 6, alg .. ": " .. count(c) .. " pixels")
    end
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("canvas circle: the midpoint circle of radius 3 has 16 pixels", "[lua][canvas]") {
  // Foley's MidpointCircle for r = 3: d = -2, (0,3); d -> 1, (1,3); d -> 2, (2,2); stop. Eight-way
  // symmetry: 4 + 8 + 4 = 16 pixels.
  auto r = run_lua(std::string(kHelpers) + R"LUA(
    local c = canvas{width = 11, height = 11, background = {1, 1, 1}}
    c:circle{center = {5, 5}, radius = 3, color = {0, 0, 0}}
    assert(count(c) == 16, count(c))
    for _, p in ipairs{{5, 8}, {6, 8}, {7, 7}, {8, 5}, {8, 4}, {3, 3}, {4, 2}, {5, 2}} do
      assert(black(c, p[1], p[2]), p[1] .. "," .. p[2])
    end
    assert(not black(c, 5, 5) and not black(c, 8, 8))
    local p = c:pixel(0, 0)
    assert(p[1] == 1 and p[2] == 1 and p[3] == 1)
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("canvas polygons: pixel centres inside, even-odd and non-zero", "[lua][canvas]") {
  auto r = run_lua(std::string(kHelpers) + R"LUA(
    -- Centres (x + 1/2, y + 1/2) in [1, 6) x [1, 4): x = 1..5, y = 1..3.
    local c = canvas{width = 8, height = 6}
    c:polygon{{1, 1}, {6, 1}, {6, 4}, {1, 4}}
    assert(count(c) == 15, count(c))
    assert(black(c, 1, 1) and black(c, 5, 3) and not black(c, 6, 1) and not black(c, 1, 4))
    -- A pentagram about the centre of pixel (25, 25): winding number 2 in its inner pentagon, so
    -- even-odd leaves the centre empty and non-zero fills it; a point tip is filled by both.
    local star = {}
    for k = 0, 4 do
      local a = math.pi / 2 + k * 4 * math.pi / 5
      star[#star + 1] = {25.5 + 20 * math.cos(a), 25.5 + 20 * math.sin(a)}
    end
    local eo, nz = canvas{width = 51, height = 51}, canvas{width = 51, height = 51}
    star.fill = "even-odd"; eo:polygon(star)
    star.fill = "nonzero"; nz:polygon(star)
    assert(not black(eo, 25, 25) and black(nz, 25, 25))
    assert(black(eo, 25, 42) and black(nz, 25, 42))
    assert(count(nz) > count(eo))
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("canvas flood fill fills the 4-connected region inside a border", "[lua][canvas]") {
  auto r = run_lua(std::string(kHelpers) + R"LUA(
    local c = canvas{width = 12, height = 12}
    c:line{{0, 0}, {9, 0}} c:line{{9, 0}, {9, 9}} c:line{{9, 9}, {0, 9}} c:line{{0, 9}, {0, 0}}
    local red = {1, 0, 0}
    local n = c:flood_fill{{5, 5}, color = red}
    assert(n == 64, n)  -- the 8 x 8 interior
    local p = c:pixel(1, 1)
    assert(p[1] == 1 and p[2] == 0 and p[3] == 0)
    p = c:pixel(10, 10)
    assert(p[1] == 1 and p[2] == 1 and p[3] == 1)  -- outside the border: untouched
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("canvas clipping keeps what lies in the window", "[lua][canvas]") {
  auto r = run_lua(std::string(kHelpers) + R"LUA(
    for _, alg in ipairs{"cohen_sutherland", "liang_barsky"} do
      local c = canvas{width = 10, height = 10}
      c:clip{window = {2, 2, 7, 7}, algorithm = alg}
      c:line{{0, 4}, {9, 4}}
      for x = 0, 9 do assert(black(c, x, 4) == (x >= 2 and x <= 7), alg .. " x=" .. x) end
      c:line{{0, 9}, {9, 9}}  -- wholly outside
      assert(count(c) == 6, alg .. ": " .. count(c))
    end
    -- Sutherland-Hodgman: a square around the origin keeps its quarter in the window.
    local c = canvas{width = 10, height = 10}
    c:clip{window = {0, 0, 5, 5}, algorithm = "sutherland_hodgman"}
    c:polygon{{-3, -3}, {3, -3}, {3, 3}, {-3, 3}}
    assert(count(c) == 9, count(c))
    c:clip{}  -- no window: nothing clipped
    c:line{{0, 9}, {9, 9}}
    assert(count(c) == 19, count(c))
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("canvas save writes the picture top row first", "[lua][canvas]") {
  const std::string path = std::string(WEDGE_BINARY_DIR) + "/canvas_test.png";
  std::remove(path.c_str());
  auto r = run_lua("local c = canvas{width = 4, height = 3}\nc:line{{0, 0}, {0, 0}, color = {1, 0, 0}}\nc:save('" +
                   path + "')\n");
  INFO(r.err);
  REQUIRE(r.status == 0);
  const wedge::render::Image im = wedge::render::read_png(path);
  REQUIRE(im.width == 4);
  REQUIRE(im.height == 3);
  CHECK(im.pixel(0, 2) == std::array<std::uint8_t, 4>{255, 0, 0, 255});  // canvas (0, 0): bottom left
  CHECK(im.pixel(0, 0) == std::array<std::uint8_t, 4>{255, 255, 255, 255});
}

TEST_CASE("canvas errors name the function, the argument and the value", "[lua][canvas]") {
  auto r = run_lua("local c = canvas{width = 4, height = 4}\nc:line{{0, 0}, {3, 3}, algorithm = 'wu'}\n");
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Catch::Contains("canvas.lua:2:"));
  CHECK_THAT(r.err, Catch::Contains("'line'"));
  CHECK_THAT(r.err, Catch::Contains("\"wu\""));
  r = run_lua("local c = canvas{width = 0, height = 4}\n");
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Catch::Contains("width and height"));
  r = run_lua("local c = canvas{width = 4, height = 4}\nc:polygon{{0, 0}, {3, 0}, {3, 3}, fill = 'winding'}\n");
  CHECK_THAT(r.err, Catch::Contains("\"even-odd\" or \"nonzero\""));
  r = run_lua("local c = canvas{width = 4, height = 4}\nc:line{{0.5, 0}, {3, 3}}\n");
  CHECK_THAT(r.err, Catch::Contains("whole number"));
  r = run_lua("local c = canvas{width = 4, height = 4}\nlocal p = c:pixel(4, 0)\n");
  CHECK_THAT(r.err, Catch::Contains("x must be in 0..3, got 4"));
  r = run_lua("local c = canvas{width = 4, height = 4}\nc:flood_fill{{9, 9}}\n");
  CHECK_THAT(r.err, Catch::Contains("outside"));
  r = run_lua("local c = canvas{width = 4, height = 4}\nc:clip{window = {3, 0, 1, 4}}\n");
  CHECK_THAT(r.err, Catch::Contains("xmin < xmax"));
}

TEST_CASE("canvas polygons with vertices far off the canvas fill the part on it", "[lua][canvas]") {
  // A rectangle over rows 0..9 reaching x = 3e9 (beyond 2^31) or further covers the whole width
  // of those rows: 40 x 10 = 400 pixels. Converting 3e9 to int had filled nothing.
  auto r = run_lua(std::string(kHelpers) + R"LUA(
    for _, far in ipairs{1e9, 3e9, 1e10, 1e20, 1e300} do
      local c = canvas{width = 40, height = 40}
      c:polygon{{0, 0}, {far, 0}, {far, 10}, {0, 10}}
      assert(count(c) == 400, far .. ": " .. count(c))
      assert(black(c, 39, 9) and black(c, 0, 0) and not black(c, 0, 10))
      c = canvas{width = 40, height = 40}
      c:polygon{{-far, 0}, {10, 0}, {10, far}, {-far, far}}  -- columns 0..9, every row
      assert(count(c) == 400, -far .. ": " .. count(c))
      assert(black(c, 9, 39) and not black(c, 10, 0))
    end
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("canvas clipping only removes the pixels outside the window", "[lua][canvas]") {
  // Inside the window a clipped line has exactly the unclipped line's pixels. Rounding the clipped
  // ends and drawing again moved (25,19)-(1,28) up by one at x = 11, 13, 16 and 21, and changed
  // 144 of 300 random lines; Cohen-Sutherland and Liang-Barsky differed on fractional windows.
  auto r = run_lua(std::string(kHelpers) + R"LUA(
    local function check(a, b, window, alg)
      local full = canvas{width = 40, height = 40}
      full:line{a, b}
      local cut = canvas{width = 40, height = 40}
      cut:clip{window = window, algorithm = alg}
      cut:line{a, b}
      for y = 0, 39 do
        for x = 0, 39 do
          local inside = x >= window[1] and x <= window[3] and y >= window[2] and y <= window[4]
          local want = inside and black(full, x, y)
          if black(cut, x, y) ~= want then
            error(string.format("%s, window {%g,%g,%g,%g}, line {%d,%d}-{%d,%d}: pixel (%d,%d) is %s",
              alg, window[1], window[2], window[3], window[4], a[1], a[2], b[1], b[2], x, y,
              want and "missing" or "extra"))
          end
        end
      end
    end
    for _, alg in ipairs{"cohen_sutherland", "liang_barsky"} do
      check({25, 19}, {1, 28}, {10, 10, 30, 30}, alg)
      math.randomseed(5)
      for i = 1, 300 do
        local a = {math.random(-10, 49), math.random(-10, 49)}
        local b = {math.random(-10, 49), math.random(-10, 49)}
        check(a, b, {10, 10, 30, 30}, alg)
        check(a, b, {10.5, 9.25, 30.75, 29.5}, alg)
      end
    end
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("canvas clip: every primitive keeps the pixels whose position is in the window, edges included", "[lua][canvas]") {
  // With window {10,10,20,20} a line kept x = 10..20 but a whole-canvas polygon [10..19] squared,
  // and a flood fill ignored the window and filled all 1600 pixels.
  auto r = run_lua(std::string(kHelpers) + R"LUA(
    local function only_window(c, x0, y0, x1, y1, what)
      for y = 0, 39 do for x = 0, 39 do
        local inside = x >= x0 and x <= x1 and y >= y0 and y <= y1
        if black(c, x, y) and not inside then error(what .. ": (" .. x .. "," .. y .. ") outside the window") end
      end end
    end
    local c = canvas{width = 40, height = 40}
    c:clip{window = {10, 10, 20, 20}}
    c:polygon{{0, 0}, {40, 0}, {40, 40}, {0, 40}}
    assert(count(c) == 121, "polygon: " .. count(c))
    assert(black(c, 20, 20) and black(c, 10, 10))
    only_window(c, 10, 10, 20, 20, "polygon")
    c = canvas{width = 40, height = 40}
    c:clip{window = {10, 10, 20, 20}}
    c:line{{0, 20}, {39, 20}}  -- along the window's top edge
    assert(count(c) == 11, "line: " .. count(c))
    local n = c:flood_fill{{12, 12}}
    assert(n == 121 - 11, "flood fill: " .. n)
    assert(count(c) == 121, count(c))
    only_window(c, 10, 10, 20, 20, "flood fill")
    assert(c:flood_fill{{5, 5}} == 0)  -- a seed outside the window fills nothing
    assert(count(c) == 121)
    -- A fractional window: pixel positions 11..20 in x, 10..19 in y.
    c = canvas{width = 40, height = 40}
    c:clip{window = {10.5, 9.5, 20.5, 19.5}}
    c:polygon{{0, 0}, {40, 0}, {40, 40}, {0, 40}}
    assert(count(c) == 100, "fractional polygon: " .. count(c))
    only_window(c, 11, 10, 20, 19, "fractional polygon")
    c = canvas{width = 40, height = 40}
    c:clip{window = {10.5, 9.5, 20.5, 19.5}}
    assert(c:flood_fill{{15, 15}} == 100)
    -- A window reaching far off the canvas.
    c = canvas{width = 40, height = 40}
    c:clip{window = {-1e300, -1e300, 1e300, 1e300}}
    c:polygon{{0, 0}, {40, 0}, {40, 40}, {0, 40}}
    assert(count(c) == 1600, count(c))
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}
