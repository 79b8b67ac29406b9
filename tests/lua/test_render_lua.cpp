// render{} from Lua: a mesh table drawn to a PNG, and its argument errors.
#include <catch2/catch.hpp>

#include <filesystem>
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
