// Wireframe models from Lua: a solid's edges as polylines, exported as OBJ polylines and rendered.
#include <catch2/catch.hpp>

#include <filesystem>
#include <sstream>

#include "lua/wedge_lua.h"
#include "render/render.h"

using namespace wedge;

namespace {
struct Run {
  int status;
  std::string err;
};
Run run(const std::string& code, const std::string& chunk = "@wire.lua") {
  std::ostringstream err;
  int status = lua::run_string(code, chunk, err);
  return {status, err.str()};
}
const std::string kOut = std::string(WEDGE_BINARY_DIR) + "/wireframe-test";
}  // namespace

TEST_CASE("a wireframe holds a solid's edges: a box has 12 of total length 4(a+b+c)", "[lua][wireframe]") {
  std::filesystem::create_directories(kOut);
  auto r = run("local out = '" + kOut + "'\n" + R"LUA(
    local w = wireframe(box(1, 2, 3))
    assert(w:segments() == 12, w:segments())
    assert(math.abs(w:length() - 24) < 1e-12, w:length())
    assert(tostring(w):find("^Wireframe%("))
    -- a plate with a square hole: 12 outer and 12 inner edges
    local plate = extrude(polygon{outer = {{0, 0}, {6, 0}, {6, 4}, {0, 4}}, holes = {{{1, 1}, {3, 1}, {3, 3}, {1, 3}}}}, 1)
    local pw = wireframe(plate)
    assert(pw:segments() == 24, pw:segments())
    assert(math.abs(pw:length() - (2 * 20 + 4 + 2 * 8 + 4)) < 1e-12, pw:length())
    -- OBJ polylines: parse the file back and measure it independently
    assert(export(w, out .. "/box-wire.obj") == 12)
    local v, total, lines = {}, 0, 0
    for line in io.lines(out .. "/box-wire.obj") do
      local x, y, z = line:match("^v (%S+) (%S+) (%S+)")
      if x then v[#v + 1] = {tonumber(x), tonumber(y), tonumber(z)} end
      if line:match("^l ") then
        lines = lines + 1
        local prev
        for i in line:gmatch("%d+") do
          local p = v[tonumber(i)]
          assert(p, "index out of range")
          if prev then total = total + math.sqrt((p[1]-prev[1])^2 + (p[2]-prev[2])^2 + (p[3]-prev[3])^2) end
          prev = p
        end
      end
      assert(not line:match("^f "), "no faces")
    end
    assert(lines == #w and math.abs(total - 24) < 1e-12, total)
    render{w, out = out .. "/box-wire.png", size = {120, 120}, view = "iso"}
    render{wireframe(box(1, 1, 1), {color = {1, 0, 0}}), out = out .. "/red-wire.png", size = {60, 60}, view = "front"}
  )LUA");
  INFO(r.err);
  REQUIRE(r.status == 0);
  // The front view of a unit cube's wireframe is a square outline: red pixels on the border of
  // the picture's square, none at its centre.
  render::Image im = render::read_png(kOut + "/red-wire.png");
  int red = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      auto p = im.pixel(x, y);
      red += p[0] > 200 && p[1] < 60 && p[2] < 60;
    }
  CHECK(red > 4 * 40);
  auto c = im.pixel(30, 30);
  CHECK(int(c[1]) == 255);  // background at the centre
}

TEST_CASE("bad wireframe calls name the problem and the line", "[lua][wireframe][errors]") {
  struct Bad {
    const char* call;
    const char* message;
  } bad[] = {
      {"wireframe()", "bad argument #1 to 'wireframe' (Solid or mesh expected, got no value)"},
      {"wireframe(nil)", "bad argument #1 to 'wireframe' (Solid or mesh expected, got nil)"},
      {"wireframe(5)", "bad argument #1 to 'wireframe' (Solid or mesh expected, got number)"},
      {"wireframe(box(1, 1, 1), {crease = 0})", "wireframe: crease must be within 0..180 degrees, got 0"},
      {"wireframe(box(1, 1, 1), {color = {2, 0, 0}})", "wireframe: color[1] must be within 0..1, got 2"},
      {"wireframe(box(1, 1, 1), {colour = {1, 0, 0}})", "unknown field 'colour'"},
      {"export(wireframe(box(1, 1, 1)), 'w.stl')", "a wireframe has no faces; export it as .obj"},
      {"export(wireframe(box(1, 1, 1)), 'w.obj', {split = true})", "export: split needs a scene group to split, got Wireframe"},
      {"export(wireframe(box(1, 1, 1)), '/nonexistent/w.obj')", "export: cannot write '/nonexistent/w.obj': folder '/nonexistent' does not exist"},
  };
  for (const auto& b : bad) {
    auto r = run(std::string("local a = 1\n\n") + b.call + "\n", "@bad.lua");
    INFO(b.call << "\n  -> " << r.err);
    CHECK(r.status == 1);
    CHECK_THAT(r.err, Catch::StartsWith("bad.lua:3: "));
    CHECK_THAT(r.err, Catch::Contains(b.message));
  }
}
