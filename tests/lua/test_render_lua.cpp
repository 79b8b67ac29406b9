// render{} from Lua: a mesh table drawn to a PNG, and its argument errors.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "lua/wedge_lua.h"
#include "render/render.h"

using namespace wedge;

namespace {
int run(const std::string& code, std::string& err) {
  std::ostringstream e;
  int status = lua::run_string(code, "@render_test.lua", e);
  err = e.str();
  return status;
}
const char* kCube = R"(
local cube = {vertices = {{-1,-1,-1},{1,-1,-1},{1,1,-1},{-1,1,-1},{-1,-1,1},{1,-1,1},{1,1,1},{-1,1,1}},
  triangles = {{1,3,2},{1,4,3},{5,6,7},{5,7,8},{1,2,6},{1,6,5},{2,3,7},{2,7,6},{3,4,8},{3,8,7},{4,1,5},{4,5,8}},
  material = {diffuse = {0.9, 0.2, 0.1}}}
)";
}  // namespace

TEST_CASE("render{} draws a mesh table with camera and lights into a PNG", "[lua][render]") {
  std::string out = std::string(WEDGE_BINARY_DIR) + "/lua_render_cube.png";
  std::filesystem::remove(out);
  std::string err;
  int status = run(std::string(kCube) + "render{cube, out='" + out + R"(', size={80, 60},
      camera={eye={4, -5, 3}, center={0, 0, 0}, up={0, 0, 1}, fovy=40},
      lights={{type='directional', direction={-1, 1, -1}}}, shading='flat', background={1, 1, 1}})",
                   err);
  INFO(err);
  REQUIRE(status == 0);
  render::Image im = render::read_png(out);
  CHECK(im.width == 80);
  CHECK(im.height == 60);
  auto corner = im.pixel(0, 0);
  CHECK(corner[0] == 255);
  CHECK(corner[1] == 255);
  auto mid = im.pixel(40, 30);
  CHECK(mid[0] > mid[2]);  // the red material, lit
  CHECK(mid[1] < 200);
}

TEST_CASE("render{} names a bad option and the script line", "[lua][render]") {
  std::string err;
  int status = run(std::string(kCube) + "\nrender{cube, out='x.png', shading='glossy'}", err);
  CHECK(status != 0);
  CHECK(err.find("render_test.lua:6:") != std::string::npos);
  CHECK(err.find("shading") != std::string::npos);
  status = run(std::string(kCube) + "\nrender{cube, out='x.png', colour={1,0,0}}", err);
  CHECK(status != 0);
  CHECK(err.find("colour") != std::string::npos);
  status = run("render{{vertices={{0,0,0}}, triangles={{1,2,3}}}, out='x.png'}", err);
  CHECK(status != 0);
  CHECK(err.find("vertex") != std::string::npos);
}

TEST_CASE("render{} draws an imported Solid with its s:material, textured by checker{}", "[lua][render]") {
  std::string dir = std::string(WEDGE_BINARY_DIR) + "/";
  {
    std::ofstream obj(dir + "render_cube.obj");
    obj << "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
           "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
  }
  std::string out = dir + "lua_render_solid.png";
  std::string err;
  int status = run("local s = import('" + dir + "render_cube.obj')\n" + R"(
    local red = s:material{diffuse={0.9, 0.1, 0.1}}
    render{red, out=')" + out + R"(', size={64, 48}, camera={view='iso'}, background={0, 0, 0}}
    local t = s:material{diffuse={1, 1, 1}, texture=checker{n=4, colors={{1, 1, 0}, {0, 0, 1}}}}
    render{t, out=')" + dir + R"(lua_render_tex.png', size={64, 48}, camera={view='iso'}, background={0, 0, 0},
           shading='phong', antialias=2})",
                   err);
  INFO(err);
  REQUIRE(status == 0);
  render::Image im = render::read_png(out);
  auto mid = im.pixel(32, 24);
  CHECK(int(mid[0]) > 3 * int(mid[1]));  // the red material
  render::Image tex = render::read_png(dir + "lua_render_tex.png");
  int yellowish = 0, blueish = 0;
  for (int y = 0; y < tex.height; ++y)
    for (int x = 0; x < tex.width; ++x) {
      auto p = tex.pixel(x, y);
      yellowish += p[0] > 60 && p[2] < p[0] / 2;
      blueish += p[2] > 60 && p[0] < p[2] / 2;
    }
  CHECK(yellowish > 50);
  CHECK(blueish > 50);
}
