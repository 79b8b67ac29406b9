// render{} from Lua: a mesh table drawn to a PNG, and its argument errors.
#include <catch2/catch.hpp>

#include <filesystem>
#include <algorithm>
#include <fstream>
#include <map>
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

TEST_CASE("render{} and drawing{} name a bad option by its field path, not by an argument number", "[lua][render][errors]") {
  // render{} takes one table: "bad argument #1 to 'render'" says nothing the reader can use, the
  // field's path does (issue 14). Each message is checked whole after the script's file:line.
  struct Bad {
    const char* call;
    const char* message;
  };
  const Bad bad[] = {
      {"render{s, out = 'x.png', lights = {{type = 'point'}, {type = 'point', position = 'up'}}}",
       "render: lights[2].position must be a point {x, y, z}, got string"},
      {"render{s, out = 'x.png', lights = {{type = 'point', position = {1, 2}}}}",
       "render: lights[1].position must have 3 coordinates, got 2"},
      {"render{s, out = 'x.png', lights = {{type = 'spot', position = {0, 0, 5}, exponent = 200}}}",
       "render: lights[1].exponent must be within 0..128 (OpenGL's range), got 200"},
      {"render{s, out = 'x.png', lights = {{specular = {1, 0/0, 1}}}}",
       "render: lights[1].specular[2] must be within 0..1, got nan"},
      {"render{s, out = 'x.png', camera = {eye = {5, 5, 5}, near = 10, far = 1}}",
       "render: camera.near must be below camera.far, got 10 and 1"},
      {"render{s, out = 'x.png', camera = {eye = {1, 1, 1/0}}}", "render: camera.eye[3] must be finite, got inf"},
      {"render{s, out = 'x.png', camera = {projection = 'ortho', left = 1, right = 1}}",
       "render: camera.left must be below camera.right, got 1 and 1"},
      {"render{s, out = 'x.png', fog = {start = 'near'}}", "render: fog.start must be a number, got string"},
      {"render{s, out = 'x.png', fog = {start = 1, stop = 2, colour = {1, 1, 1}}}",
       "render: unknown field 'fog.colour' (known: mode, start, stop, density, color)"},
      {"render{s, out = 'x.png', view = {'cabinet', angle = 'steep'}}", "render: view.angle must be a number, got string"},
      {"render{s, out = 'x.png', size = {64, 'tall'}}", "render: size[2] must be a number, got string"},
      {"render{s, out = 3}", "render: out must be a string, got number"},
      {"render{s}", "render: out is missing (the .png file to write)"},
      {"render{out = 'x.png'}", "render: needs the thing to draw as its first element, as render{s, out=...}"},
      {"render{{vertices = {{0, 0, 0}, {1, 0}}, triangles = {{1, 2, 3}}}, out = 'x.png'}",
       "render: vertex 2 must have 3 coordinates, got 2"},
      {"render{{vertices = {{0, 0, 0}}, triangles = {{1, 2, 3}}, material = {diffuse = {2, 0, 0}}}, out = 'x.png'}",
       "render: triangle 1 refers to vertex 2, not in 1..1"},
      {"drawing{s, out = 'x.png', views = {'front', 'sideways'}}", "drawing: views[2]: unknown view 'sideways'"},
      {"drawing{s, out = 'x.png', views = {'front', {'cabinet', angle = 0/0}}}", "drawing: views[2].angle must be finite, got nan"},
      {"drawing{s, out = 'x.png', hidden = 'dotted'}", "drawing: hidden must be \"removed\" or \"dashed\", got 'dotted'"},
      {"drawing{s, out = 'x.png', titles = 'front'}", "drawing: titles must be a list of strings, got string"},
  };
  for (const Bad& b : bad) {
    std::string err;
    const int status = run(std::string("local s = box(1, 1, 1)\n") + b.call + "\n", err);
    INFO(b.call << "\n  -> " << err);
    CHECK(status == 1);
    CHECK_THAT(err, Catch::StartsWith(std::string("render_test.lua:2: ") + b.message));
    CHECK(err.find("bad argument") == std::string::npos);
  }
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

TEST_CASE("drawing{} writes a multi-view sheet of a box, the front view showing its x/z extent", "[lua][render][drawing]") {
  std::string out = std::string(WEDGE_BINARY_DIR) + "/lua_drawing_box.png";
  std::filesystem::remove(out);
  std::string err;
  int status = run("drawing{box(4, 2, 1):material{diffuse={0.9, 0.5, 0.2}}, out='" + out + "', size={300, 200}, views={'front', 'top', 'side', 'iso'}}", err);
  INFO(err);
  REQUIRE(status == 0);
  render::Image im = render::read_png(out);
  REQUIRE(im.width == 300);
  REQUIRE(im.height == 200);
  // Cells of 150 x 100; the object's tinted pixels (background, border and label ink are grey).
  auto extent = [&](int cx, int cy, int& w, int& h) {
    int x0 = 1 << 30, x1 = -1, y0 = 1 << 30, y1 = -1, n = 0;
    for (int y = cy + 14; y < cy + 99; ++y)  // below the label band
      for (int x = cx + 1; x < cx + 149; ++x) {
        auto p = im.pixel(x, y);
        if (p[0] == p[1] && p[1] == p[2]) continue;
        ++n, x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      }
    w = x1 - x0 + 1, h = y1 - y0 + 1;
    return n;
  };
  int w = 0, h = 0;
  for (int v = 0; v < 4; ++v) CHECK(extent((v % 2) * 150, (v / 2) * 100, w, h) > 300);
  extent(0, 0, w, h);
  CHECK(double(w) / h == Approx(4.0).epsilon(0.1));
  CHECK(w > 110);
  // Errors name the function and the bad value.
  status = run("\ndrawing{box(1, 1, 1), out='x.png', views={'front', 'sideways'}}", err);
  CHECK(status != 0);
  CHECK(err.find("render_test.lua:2:") != std::string::npos);
  CHECK(err.find("drawing") != std::string::npos);
  CHECK(err.find("sideways") != std::string::npos);
  status = run("drawing{box(1, 1, 1)}", err);
  CHECK(err.find("drawing: out is missing (the .png file to write)") != std::string::npos);
}

TEST_CASE("import() of a seamed, faceted, textured cube OBJ gives a Solid that renders with the file's normals and uvs",
          "[lua][render][io]") {
  // One `vn` per face and the whole texture on each face: every position is split by its uv seams
  // and normal creases, yet the surface is closed, so import() accepts it.
  std::string dir = std::string(WEDGE_BINARY_DIR) + "/";
  {
    std::ofstream obj(dir + "seamed_cube.obj");
    obj << "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n"
           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
           "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n"
           "f 1/1/1 3/2/1 4/3/1 2/4/1\nf 5/1/2 6/2/2 8/3/2 7/4/2\nf 1/1/3 2/2/3 6/3/3 5/4/3\n"
           "f 3/1/4 7/2/4 8/3/4 4/4/4\nf 1/1/5 5/2/5 7/3/5 3/4/5\nf 2/1/6 4/2/6 8/3/6 6/4/6\n";
  }
  std::string err;
  int status = run("local s = import('" + dir + "seamed_cube.obj')\n" + R"(
    assert(math.abs(s:volume() - 8) < 1e-12, 'volume ' .. s:volume())
    assert(s:triangles() == 12)
    local e = s:euler()
    assert(e.V == 8 and e.E == 18 and e.F == 12, 'euler')
    local lit = {{type='directional', direction={-1, 2, -3}}}
    render{s:material{diffuse={0.8, 0.8, 0.8}}, out=')" + dir + R"(lua_seamed_gouraud.png', size={96, 72},
           camera={view='iso'}, background={0, 0, 0}, lights=lit, shading='gouraud'}
    render{s:material{diffuse={1, 1, 1}, texture=checker{n=2, colors={{1, 1, 0}, {0, 0, 1}}}},
           out=')" + dir + R"(lua_seamed_tex.png', size={96, 72}, camera={view='iso'}, background={0, 0, 0},
           lights=lit, shading='gouraud'})",
                   err);
  INFO(err);
  REQUIRE(status == 0);
  // Gouraud with the file's per-face normals and a directional light: each visible face is one
  // colour (smeared normals would shade a gradient across every face).
  render::Image g = render::read_png(dir + "lua_seamed_gouraud.png");
  std::map<std::array<std::uint8_t, 4>, int> hist;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) ++hist[g.pixel(x, y)];
  std::vector<std::pair<int, std::array<std::uint8_t, 4>>> by_count;
  for (const auto& [c, n] : hist) by_count.push_back({n, c});
  std::sort(by_count.rbegin(), by_count.rend());
  REQUIRE(by_count.size() >= 4);
  const int total = g.width * g.height, background = hist[{0, 0, 0, 255}];
  std::vector<std::array<std::uint8_t, 4>> faces;  // the three most common non-background colours
  for (const auto& [n, c] : by_count)
    if (c != std::array<std::uint8_t, 4>{0, 0, 0, 255} && faces.size() < 3) faces.push_back(c);
  int near_face = 0;
  for (const auto& [c, n] : hist)
    for (const auto& f : faces)
      if (std::abs(c[0] - f[0]) <= 1 && std::abs(c[1] - f[1]) <= 1 && std::abs(c[2] - f[2]) <= 1) {
        near_face += n;
        break;
      }
  INFO(hist.size() << " colours; background " << background << ", near a face colour " << near_face << " of " << total);
  CHECK(total - background > 2000);
  CHECK(near_face >= (total - background) * 99 / 100);
  // The three faces differ (three normals): 0.8 x the light's cosine on each.
  CHECK(faces.size() == 3);
  if (faces.size() == 3) CHECK((faces[0] != faces[1] && faces[1] != faces[2] && faces[0] != faces[2]));
  // Textured through the file's uvs: each face carries the whole 2x2 checker, so both colours
  // show in about equal measure (box mapping or lost uvs would not split every face in four).
  render::Image t = render::read_png(dir + "lua_seamed_tex.png");
  int yellowish = 0, blueish = 0;
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      auto p = t.pixel(x, y);
      yellowish += p[0] > 40 && p[2] < p[0] / 2;
      blueish += p[2] > 40 && p[0] < p[2] / 2;
    }
  INFO("yellow " << yellowish << ", blue " << blueish);
  CHECK(yellowish > 1000);
  CHECK(blueish > 1000);
  CHECK(std::abs(yellowish - blueish) < (yellowish + blueish) / 4);
}

TEST_CASE("render{} draws each face of a boolean in the material of the solid it came from", "[lua][render][tree]") {
  std::string out = std::string(WEDGE_BINARY_DIR) + "/lua_render_colours.png";
  std::filesystem::remove(out);
  std::string err;
  int status = run(R"(
      local red = sphere(1):material{diffuse = {0.9, 0.1, 0.1}}
      local blue = cube(2):material{diffuse = {0.1, 0.1, 0.9}}
      render{red - blue, out = ')" + out + R"(', size = {80, 80}, background = {1, 1, 1},
        camera = {eye = {4, 4, 4}, center = {0, 0, 0}, up = {0, 0, 1}, fovy = 40},
        lights = {{type = 'directional', direction = {-1, -1, -1}}}})",
                   err);
  INFO(err);
  REQUIRE(status == 0);
  render::Image im = render::read_png(out);
  int reds = 0, blues = 0;
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      auto p = im.pixel(x, y);
      if (p[0] > p[2] + 60 && p[0] > 60) ++reds;
      if (p[2] > p[0] + 60 && p[2] > 60) ++blues;
    }
  // The cut corner (the cube's three quarter discs) faces the eye: blue in the middle, the rest
  // of the sphere red around it.
  auto mid = im.pixel(40, 40);
  CHECK(mid[2] > mid[0] + 60);
  CHECK(reds > 300);
  CHECK(blues > 100);
}

TEST_CASE("a boolean placed in a scene keeps the material of the solid each face came from", "[lua][render][scene]") {
  // The same picture as above, with the boolean as an instance in a group that has a material of
  // its own (green): the faces keep red and blue, the group's green reaches none of them.
  std::string out = std::string(WEDGE_BINARY_DIR) + "/lua_render_scene_colours.png";
  std::filesystem::remove(out);
  std::string err;
  int status = run(R"(
      local red = sphere(1):material{diffuse = {0.9, 0.1, 0.1}}
      local blue = cube(2):material{diffuse = {0.1, 0.1, 0.9}}
      local scene = group{material = {diffuse = {0.1, 0.9, 0.1}}}
      scene:add(instance(red - blue, {transform = matrix.translate(0, 0, 0)}))
      render{scene, out = ')" + out + R"(', size = {80, 80}, background = {1, 1, 1},
        camera = {eye = {4, 4, 4}, center = {0, 0, 0}, up = {0, 0, 1}, fovy = 40},
        lights = {{type = 'directional', direction = {-1, -1, -1}}}})",
                   err);
  INFO(err);
  REQUIRE(status == 0);
  render::Image im = render::read_png(out);
  int reds = 0, blues = 0, greens = 0;
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      auto p = im.pixel(x, y);
      if (p[0] > p[2] + 60 && p[0] > 60) ++reds;
      if (p[2] > p[0] + 60 && p[2] > 60) ++blues;
      if (p[1] > p[0] + 60 && p[1] > p[2] + 60) ++greens;
    }
  auto mid = im.pixel(40, 40);
  CHECK(mid[2] > mid[0] + 60);
  CHECK(reds > 300);
  CHECK(blues > 100);
  CHECK(greens == 0);
}

TEST_CASE("render{} with the whole scene behind a perspective eye writes the background", "[lua][render][camera]") {
  // The fitted near and far came out negative (near=-0.00069, far=-6.9) and perspective() refused
  // them; with an explicit near and far the same camera drew the background, as it now does.
  const std::string out = std::string(WEDGE_BINARY_DIR) + "/lua_render_behind.png";
  for (const char* range : {"", ", near = 0.1, far = 100"}) {
    std::filesystem::remove(out);
    std::string err;
    const int status = run(std::string(kCube) + "render{cube, out='" + out +
                               "', size={50, 50}, background={0.2, 0.4, 0.6}, camera={eye={5, 5, 5}, center={10, 10, 10}" +
                               range + "}}",
                           err);
    INFO(range << ": " << err);
    REQUIRE(status == 0);
    const render::Image im = render::read_png(out);
    REQUIRE(im.width == 50);
    int other = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) other += im.pixel(x, y) != std::array<std::uint8_t, 4>{51, 102, 153, 255};
    CHECK(other == 0);
  }
}

TEST_CASE("render{} names vertices too large to view as the scene's bounds, not the eye", "[lua][render][errors]") {
  // The default camera fitted to bounds of +-1e300 had an eye of (inf, -inf, inf), and the error
  // was "render: eye must be finite", an eye the script never set.
  std::string err;
  const int status = run("\nrender{{vertices={{-1e300,0,0},{1e300,0,0},{0,1e300,0}}, triangles={{1,2,3}}}, out='x.png', size={10,10}}", err);
  CHECK(status != 0);
  INFO(err);
  CHECK(err.find("render_test.lua:2:") != std::string::npos);
  CHECK(err.find("the scene's bounds overflow") != std::string::npos);
  CHECK(err.find("1e+300") != std::string::npos);
  CHECK(err.find("eye") == std::string::npos);
}

TEST_CASE("render{} refuses an unknown field in a mesh table", "[lua][render][errors]") {
  // normals={} was silently ignored; a mesh table takes vertices, triangles and material only.
  std::string err;
  int status = run("\nrender{{vertices={{0,0,0},{1,0,0},{0,1,0}}, triangles={{1,2,3}}, normals={}}, out='x.png', size={10,10}}", err);
  CHECK(status != 0);
  INFO(err);
  CHECK(err.find("render_test.lua:2:") != std::string::npos);
  CHECK(err.find("unknown field 'normals'") != std::string::npos);
  CHECK(err.find("known: vertices, triangles, material") != std::string::npos);
  status = run("\ndrawing{{vertices={{0,0,0},{1,0,0},{0,1,0}}, triangles={{1,2,3}}, colour={1,0,0}}, out='x.png'}", err);
  CHECK(status != 0);
  CHECK(err.find("unknown field 'colour'") != std::string::npos);
}

TEST_CASE("render{} over the triangle budget says how to raise it", "[lua][render][errors]") {
  // The message said "raise max_triangles", and render{..., max_triangles=} is an unknown field;
  // the budget is tolerance{max_triangles=N}, and doing what the message says works.
  const std::string out = std::string(WEDGE_BINARY_DIR) + "/lua_render_budget.png";
  std::string err;
  int status = run("tolerance{max_triangles = 1000}\nrender{array{box(1, 1, 1), count = 100, step = {2, 0, 0}}, out = '" +
                       out + "', size = {20, 20}}",
                   err);
  CHECK(status != 0);
  INFO(err);
  CHECK(err.find("render_test.lua:2:") != std::string::npos);
  CHECK(err.find("more than the budget of 1000") != std::string::npos);
  CHECK(err.find("raise the budget with tolerance{max_triangles=N}") != std::string::npos);
  status = run("tolerance{max_triangles = 2000}\nrender{array{box(1, 1, 1), count = 100, step = {2, 0, 0}}, out = '" + out +
                   "', size = {20, 20}}",
               err);
  CHECK(status == 0);
}
