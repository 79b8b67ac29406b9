// The Lua contract's frame (API.md, first paragraph): functions named in errors however they are
// called, `require "wedge"` inside `wedge run`, params.key from key=value arguments, the runner's
// flags.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "lua/wedge_lua.h"

using namespace wedge::lua;

namespace {
struct Run {
  int status;
  std::string err;
};
Run run(const std::string& code, const std::string& chunk = "@contract.lua") {
  std::ostringstream err;
  int status = run_string(code, chunk, err);
  return {status, err.str()};
}
// Writes `code` to a script file in the build tree and runs it with `args`.
Run run_script(const std::string& name, const std::string& code, const std::vector<std::string>& args,
               const RunOptions& options = {}) {
  const std::string path = std::string(WEDGE_BINARY_DIR) + "/" + name;
  {
    std::ofstream f(path);
    f << code;
  }
  std::ostringstream err;
  int status = run_file(path, args, err, options);
  return {status, err.str()};
}
}  // namespace

TEST_CASE("a function called as a value is named by its API name in argument errors", "[lua][errors][names]") {
  auto r = run(R"LUA(
    local ok, err = pcall(matrix.rotate, "x")
    assert(err == "bad argument #1 to 'matrix.rotate' (number expected, got string)", err)
    ok, err = pcall(box, "a", 1, 1)
    assert(err:find("^bad argument #1 to 'box' %("), err)
    ok, err = pcall(wedge.matrix.translate, 1, {}, 3)
    assert(err:find("^bad argument #2 to 'matrix.translate' %(number expected, got table%)"), err)
    -- through a local: the API's name, not the local's
    local rot = matrix.rotate
    ok, err = pcall(function() return rot("x") end)
    assert(err:find("^contract.lua:%d+: bad argument #1 to 'matrix.rotate'"), err)
    -- called the usual way, the name at the call site (as Lua's own libraries do)
    ok, err = pcall(function() return matrix.rotate("x") end)
    assert(err:find("^contract.lua:%d+: bad argument #1 to 'rotate'"), err)
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("a method called as a value is named Class:method, the object counting as #0", "[lua][errors][names]") {
  auto r = run(R"LUA(
    local s = box(1, 2, 3)
    local ok, err = pcall(s.translate, s, "a", 0, 0)
    assert(err:find("^bad argument #1 to 'Solid:translate' %(number expected, got string%)"), err)
    ok, err = pcall(s.translate, 5, 1, 2, 3)
    assert(err:find("^calling 'Solid:translate' on bad self %(Solid expected, got number%)"), err)
    local m = matrix.scale(0, 1, 1)
    ok, err = pcall(m.inverse, m)
    assert(err:find("^Matrix:inverse: matrix is singular"), err)
    local b = brep()
    ok, err = pcall(b.kemr, b, 99)
    assert(err:find("^bad argument #1 to 'Brep:kemr' %(99 is not an edge of this model%)"), err)
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("the first bad argument of a positional call is the one named, as the script reads", "[lua][errors][names]") {
  // box("x") once said "bad argument #3 to 'box' (number expected, got no value)": the three
  // numbers were read as one constructor's arguments, which C++ evaluates in no set order.
  struct Bad {
    const char* call;
    const char* message;
  } bad[] = {
      {"box('x')", "bad argument #1 to 'box' (number expected, got string)"},
      {"box(1, 'y')", "bad argument #2 to 'box' (number expected, got string)"},
      {"box(1, 2)", "bad argument #3 to 'box' (number expected, got no value)"},
      {"box(1, 1, 1):translate('a')", "bad argument #1 to 'translate' (number expected, got string)"},
      {"box(1, 1, 1):scale(2, 'b')", "bad argument #2 to 'scale' (number expected, got string)"},
      {"matrix.translate('a')", "bad argument #1 to 'translate' (number expected, got string)"},
      {"matrix.scale(2, 'b')", "bad argument #2 to 'scale' (number expected, got string)"},
      {"matrix.euler('a')", "bad argument #1 to 'euler' (number expected, got string)"},
      {"matrix.look_at('eye')", "bad argument #1 to 'look_at'"},
      {"matrix.perspective('wide')", "bad argument #1 to 'perspective' (number expected, got string)"},
      {"matrix.frustum('l')", "bad argument #1 to 'frustum' (number expected, got string)"},
      {"matrix.ortho(-1, 1, 'b')", "bad argument #3 to 'ortho' (number expected, got string)"},
  };
  for (const auto& b : bad) {
    auto r = run(std::string("local a = 1\nlocal x = ") + b.call + "\n", "@first.lua");
    INFO(b.call << "\n  -> " << r.err);
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::StartsWith(std::string("first.lua:2: ") + b.message));
  }
}

TEST_CASE("an operator's bad operand is named by the operator the script wrote, once", "[lua][errors][names]") {
  // Lua names a metamethod by its event ("add", "mul"), which the script never wrote: the
  // messages once read "add: operator '+' (union): ..." and "bad argument #2 to 'mul'".
  struct Bad {
    const char* call;
    const char* message;
  } bad[] = {
      {"box(1, 1, 1) + 3", "operator '+' (union): the second operand is number 3, a Solid expected"},
      {"box(1, 1, 1) - 'x'", "operator '-' (difference): the second operand is string 'x', a Solid expected"},
      {"2 * box(1, 1, 1)", "operator '*' (intersection): the first operand is number 2, a Solid expected"},
      {"box(1, 1, 1) * matrix.identity()", "operator '*' (intersection): the second operand is Matrix"},
      {"group():add(box(1, 1, 1) + {})", "operator '+' (union): the second operand is table"},
      {"matrix.identity() * 5", "bad argument #2 to operator '*' (Matrix expected, got number)"},
      {"5 * matrix.identity()", "bad argument #1 to operator '*' (Matrix expected, got number)"},
  };
  for (const auto& b : bad) {
    auto r = run(std::string("local a = 1\nlocal x = ") + b.call + "\n", "@op.lua");
    INFO(b.call << "\n  -> " << r.err);
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::StartsWith(std::string("op.lua:2: ") + b.message));
  }
}

TEST_CASE("an aliased function gets one name in every run", "[lua][errors][names]") {
  // nurbs and bspline are one C function: the name that sorts first is used.
  auto r = run(R"LUA(
    local ok, err = pcall(nurbs, 5)
    assert(err:find("to 'bspline'"), err)
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("require 'wedge' inside wedge run returns the API table the globals come from", "[lua][contract]") {
  auto r = run(R"LUA(
    local w = require "wedge"
    assert(w == wedge and w.box == box and w.matrix == matrix and w.render == render)
    assert(package.loaded.wedge == wedge)
    assert(type(params) == "table" and w.params == params)
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("key=value script arguments become params, numbers converted, arg keeps every argument", "[lua][contract][params]") {
  auto r = run_script("params_test.lua", R"LUA(
    assert(params.teeth == 24 and math.type(params.teeth) == "integer", tostring(params.teeth))
    assert(params.module == 1.5 and math.type(params.module) == "float")
    assert(params.small == 1e-3 and params.hex == 16 and params.neg == -2)
    assert(params.name == "spur gear")
    assert(params.fast == true and params.slow == false)
    assert(params.empty == "")
    assert(params.expr == "a=b", tostring(params.expr))
    assert(params["2x"] == nil and params["a.b"] == nil and params[""] == nil)
    assert(#arg == 13 and arg[1] == "teeth=24" and arg[10] == "plain" and arg[11] == "2x=1")
    assert(select("#", ...) == 13 and select(1, ...) == "teeth=24")
    print("params ok")
  )LUA",
                      {"teeth=24", "module=1.5", "small=1e-3", "hex=0x10", "neg=-2", "name=spur gear", "fast=true",
                       "slow=false", "empty=", "plain", "2x=1", "a.b=3", "expr=a=b"});
  INFO(r.err);
  CHECK(r.status == 0);
  // a key given twice: the last one wins, as on most command lines
  auto twice = run_script("params_twice.lua", "assert(params.n == 2)", {"n=1", "n=2"});
  INFO(twice.err);
  CHECK(twice.status == 0);
  auto none = run_script("params_none.lua", "assert(next(params) == nil)", {"just", "words"});
  INFO(none.err);
  CHECK(none.status == 0);
}

TEST_CASE("wedge run --stats reports the time per stage, --quiet silences print", "[lua][runner]") {
  RunOptions stats;
  stats.stats = true;
  auto r = run_script("stats_test.lua", R"LUA(
    local out = ...
    export(box(1, 1, 1), out .. "/stats_box.stl")
    render{box(1, 2, 3), out = out .. "/stats_box.png", size = {40, 30}}
  )LUA",
                      {WEDGE_BINARY_DIR}, stats);
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.err, Catch::Contains("wedge: time per stage for"));
  for (const char* stage : {"load", "mesh", "render", "write", "lua", "total"}) CHECK_THAT(r.err, Catch::Contains(std::string("  ") + stage));
  CHECK_THAT(r.err, Catch::Contains("(2 calls)"));  // mesh: once for export, once for render
  // The stages' own shares add up to the total (each printed to 0.1 ms).
  std::istringstream lines(r.err);
  std::string line;
  double sum = 0, total = -1;
  while (std::getline(lines, line)) {
    // The CSG block that follows has its own stages ("tessellation 1.2 ms"): not the run's.
    if (line.find("CSG evaluation") != std::string::npos) break;
    std::istringstream in(line);
    std::string name;
    double ms;
    if (!(in >> name >> ms)) continue;
    if (name == "total") total = ms;
    else sum += ms;
  }
  CHECK(total > 0);
  CHECK(std::abs(sum - total) < 0.1 * 7 + 0.01 * total);

  RunOptions quiet;
  quiet.quiet = true;
  auto q = run_script("quiet_test.lua", "print('should not appear')\nassert(print ~= nil)\n", {}, quiet);
  CHECK(q.status == 0);
}

TEST_CASE("wedge run --sandbox does not run a script it cannot confine", "[lua][runner][sandbox]") {
  const std::string marker = (std::filesystem::temp_directory_path() / "wedge_sandbox_marker.txt").string();
  std::filesystem::remove(marker);
  RunOptions sandbox;
  sandbox.sandbox = true;
  auto r = run_script("sandbox_test.lua", "local f = io.open('" + marker + "', 'w') f:write('ran') f:close()\n", {}, sandbox);
  // Either the sandbox (issue 14) confines the script, which may then not write outside its
  // folder, or the runner refuses; in no case does the script run unconfined.
  if (r.status != 0) {
    CHECK_THAT(r.err, Catch::Contains("sandbox"));
  }
  CHECK_FALSE(std::filesystem::exists(marker));
}

TEST_CASE("tolerance takes its positional and its table form", "[lua][contract]") {
  auto r = run(R"LUA(
    local c, a = tolerance()
    assert(c == 0.01 and a == 15, c .. " " .. a)
    c, a = tolerance(0.002)
    assert(c == 0.002 and a == 15)
    c, a = tolerance{chordal = 0.05, angle = 10}
    assert(c == 0.05 and a == 10)
    c, a = tolerance{angle = 20}
    assert(c == 0.05 and a == 20)
    local ok, err = pcall(tolerance, {angle = 0})
    assert(err:find("tolerance: angle must be within 0..90", 1, true), err)
    ok, err = pcall(tolerance, {chordal = -1})
    assert(err:find("tolerance: chordal must be positive, got -1", 1, true), err)
    ok, err = pcall(tolerance, {chord = 1})
    assert(err:find("tolerance: unknown field 'chord'", 1, true), err)
    -- the two budgets: triangles of one tessellation, crossings of one boolean
    local t, x
    c, a, t, x = tolerance()
    assert(t == 10000000 and x == 50000, t .. " " .. x)
    -- three copies of an extruded circle turned by a degree each (a copy of a cylinder would be
    -- placed by its symmetry, the same solid): about 5,000 points where three surfaces cross;
    -- refused under a budget of 100, through once it is raised again (nothing kept of the
    -- refused evaluation)
    local e = extrude(circle(1), 2)
    local s = e + e:rotate_z(1) + e:rotate_z(2)
    c, a, t, x = tolerance{max_crossings = 100}
    assert(x == 100)
    ok, err = pcall(s.volume, s)
    assert(not ok and err:find("more than the budget of 100 ", 1, true), err)
    assert(s:triangles{max_crossings = 5000} > 0)
    tolerance{max_crossings = 50000}
    assert(s:volume() > 6.2 and s:volume() < 6.4, s:volume())
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("tolerance changes nothing when one of its fields is refused", "[lua][contract]") {
  // {max_triangles = 1000, chordal = -1} raised its error about chordal but had already set the
  // budget to 1000.
  auto r = run(R"LUA(
    local ok, err = pcall(tolerance, {max_triangles = 1000, chordal = -1})
    assert(not ok and err:find("chordal must be positive, got -1", 1, true), err)
    ok, err = pcall(tolerance, {max_crossings = 100, angle = 0})
    assert(not ok and err:find("angle must be within 0..90", 1, true), err)
    local c, a, t, x = tolerance()
    assert(c == 0.01 and a == 15 and t == 10000000 and x == 50000, c .. " " .. a .. " " .. t .. " " .. x)
  )LUA");
  INFO(r.err);
  CHECK(r.status == 0);
}
