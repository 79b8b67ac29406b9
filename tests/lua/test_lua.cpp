#include <catch2/catch.hpp>

#include <sstream>

#include "lua/wedge_lua.h"

using namespace wedge::lua;

namespace {
struct Run {
  int status;
  std::string err;
};
Run run(const std::string& code, const std::string& chunk = "@test.lua") {
  std::ostringstream err;
  int status = run_string(code, chunk, err);
  return {status, err.str()};
}
}  // namespace

TEST_CASE("matrix bindings compute what the kernel computes", "[lua][matrix]") {
  auto r = run(R"(
    local p = matrix.translate(1, 2, 3):apply({1, 1, 1})
    assert(p[1] == 2 and p[2] == 3 and p[3] == 4)
    local m = matrix.rotate(30, {0, 0, 1}, {1, 2, 3})
    local q = m:apply({1, 2, 3})
    assert(math.abs(q[1] - 1) < 1e-15 and math.abs(q[2] - 2) < 1e-15 and q[3] == 3)
    local id = m * m:inverse()
    for i = 1, 4 do for j = 1, 4 do
      assert(math.abs(id:get(i, j) - (i == j and 1 or 0)) < 1e-12)
    end end
    local s = matrix.scale(2, 3, 4, {1, 1, 1}):apply({2, 2, 2})
    assert(s[1] == 3 and s[2] == 4 and s[3] == 5)
    assert(matrix.identity() == matrix.scale(1))
    assert(tostring(matrix.identity()):find("^Matrix{"))
    local t = matrix.rotate(90, "z"):apply({1, 0})
    assert(#t == 2 and t[1] == 0 and t[2] == 1)
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("an error on line 7 of a script is reported at line 7", "[lua][errors]") {
  auto r = run("local a = 1\nlocal b = 2\n\n\n\n-- six\nerror('broken here')\n", "@model.lua");
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Catch::StartsWith("model.lua:7: broken here"));
  CHECK_THAT(r.err, Catch::Contains("stack traceback"));
}

TEST_CASE("a bad argument type names the function, the argument number and the type received", "[lua][errors]") {
  auto r = run("\n\nlocal m = matrix.translate(1, {}, 3)\n", "@bad.lua");
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Catch::StartsWith("bad.lua:3: bad argument #2 to 'translate' (number expected, got table)"));

  auto m = run("local m = matrix.identity()\nlocal p = m:apply('here')\n", "@meth.lua");
  CHECK_THAT(m.err, Catch::StartsWith("meth.lua:2: bad argument #1 to 'apply' (point {x, y, z} expected, got string)"));

  auto u = run("local x = matrix.translate(1,2,3) * 5\n", "@mul.lua");
  CHECK_THAT(u.err, Catch::Contains("mul.lua:1:"));
  CHECK_THAT(u.err, Catch::Contains("Matrix expected, got number"));
}

TEST_CASE("NaN, unknown fields and kernel errors become Lua errors with a line number", "[lua][errors]") {
  auto nan = run("local m = matrix.rotate(0/0, {0,0,1})\n", "@nan.lua");
  CHECK_THAT(nan.err, Catch::StartsWith("nan.lua:1: bad argument #1 to 'rotate' (finite number expected, got"));

  auto field = run("x = 1\nlocal m = matrix.shear{xy = 1, yz = 2, qq = 3}\n", "@field.lua");
  CHECK_THAT(field.err, Catch::StartsWith("field.lua:2: shear: unknown field 'qq'"));

  auto sing = run("local m = matrix.scale(0, 1, 1):inverse()\n", "@sing.lua");
  CHECK_THAT(sing.err, Catch::StartsWith("sing.lua:1: inverse: matrix is singular"));

  auto axis = run("local m = matrix.rotate(30, {0, 0, 0})\n", "@axis.lua");
  CHECK_THAT(axis.err, Catch::StartsWith("axis.lua:1: bad argument #2 to 'rotate' (axis must be non-zero)"));

  auto pt = run("local m = matrix.identity():apply({1, 'a', 3})\n", "@pt.lua");
  CHECK_THAT(pt.err, Catch::Contains("point coordinate 2 must be a number"));
}

TEST_CASE("errors raised by C++ leave the state usable: pcall recovers and the script goes on", "[lua][errors]") {
  auto r = run(R"(
    for i = 1, 1000 do
      local ok, err = pcall(function() return matrix.scale(0, 0, 0):inverse() end)
      assert(not ok and err:find("singular"))
    end
    assert(matrix.translate(1, 0, 0):apply({0, 0, 0})[1] == 1)
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("run_file reports a missing script by path", "[lua][errors]") {
  std::ostringstream err;
  CHECK(run_file("/nonexistent/dir/model.lua", {}, err) == 1);
  CHECK_THAT(err.str(), Catch::Contains("cannot open script '/nonexistent/dir/model.lua'"));
}

TEST_CASE("a syntax error names the file and line", "[lua][errors]") {
  auto r = run("local a = 1\nlocal b = = 2\n", "@syntax.lua");
  CHECK(r.status == 1);
  CHECK_THAT(r.err, Catch::StartsWith("syntax.lua:2:"));
}
