// render_scene (the path of Lua's render{}), image output and supersampling.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <thread>

#include "simd_skip.h"
#include "render/render.h"

using namespace wedge;
using namespace wedge::render;

namespace {

Mesh cube() {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.add_vertex(Point3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  const int f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (auto& t : f) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

RenderOptions options() {
  RenderOptions o;
  o.width = 64, o.height = 48;
  o.camera.eye = Point3(4, -5, 3);
  o.background = Vec4f(0, 0, 0, 1);
  LightSpec l;
  l.direction = Vec3(-1, 2, -3);
  o.lights.push_back(l);
  return o;
}

std::set<std::array<std::uint8_t, 4>> colours(const Image& im) {
  std::set<std::array<std::uint8_t, 4>> s;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) s.insert(im.pixel(x, y));
  return s;
}

}  // namespace

TEST_CASE("a flat-shaded cube shows one colour per visible face", "[render][scene]") {
  Mesh m = cube();
  CHECK(m.volume() > 0);
  DrawItem it;
  it.mesh = &m;
  RenderOptions o = options();
  o.shading = ShadeModel::Flat;
  Image im = render_scene({it}, o);
  // Background plus three visible faces, each uniformly lit with its geometric normal.
  CHECK(colours(im).size() == 4);
}

TEST_CASE("supersampling blends edge pixels, smooth shading varies across faces", "[render][scene]") {
  Mesh m = cube();
  DrawItem it;
  it.mesh = &m;
  RenderOptions o = options();
  o.shading = ShadeModel::Flat;
  o.antialias = 3;
  CHECK(colours(render_scene({it}, o)).size() > 10);
  o.antialias = 1;
  o.shading = ShadeModel::Phong;
  CHECK(colours(render_scene({it}, o)).size() > 10);
}

TEST_CASE("wireframe draws the outline only, culling both draws nothing", "[render][scene]") {
  Mesh m = cube();
  DrawItem it;
  it.mesh = &m;
  RenderOptions o = options();
  auto covered = [](const Image& im) {
    int n = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) n += im.pixel(x, y) != std::array<std::uint8_t, 4>{0, 0, 0, 255};
    return n;
  };
  int filled = covered(render_scene({it}, o));
  o.wireframe = true;
  int wire = covered(render_scene({it}, o));
  CHECK(wire > 20);
  CHECK(wire < filled / 2);
  o.wireframe = false;
  o.cull = "both";
  CHECK(covered(render_scene({it}, o)) == 0);
}

TEST_CASE("PNG output round-trips and leaves no temporary file", "[render][io]") {
  Context c(20, 10);
  c.clear_color(0.2f, 0.4f, 0.6f, 1);
  c.clear();
  auto dir = std::filesystem::path(WEDGE_BINARY_DIR) / "png_roundtrip";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  c.write_png((dir / "a.png").string());
  Image im = read_png((dir / "a.png").string());
  CHECK(im.width == 20);
  CHECK(im.height == 10);
  CHECK(im.pixel(5, 5) == std::array<std::uint8_t, 4>{51, 102, 153, 255});
  c.write_depth_pfm((dir / "d.pfm").string());
  CHECK(std::filesystem::file_size(dir / "d.pfm") > 20 * 10 * 4);
  int files = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
  CHECK(files == 2);
  CHECK_THROWS_WITH(write_png((dir / "no/such/dir/x.png").string(), im), Catch::Contains("cannot write"));
  CHECK_THROWS_WITH(read_png((dir / "missing.png").string()), Catch::Contains("missing.png"));
}

TEST_CASE("matrix stacks have GL's depths and report overflow and underflow", "[render][matrix]") {
  Context c(4, 4);
  c.matrix_mode(MatrixMode::Projection);
  c.push_matrix();
  CHECK_THROWS_WITH(c.push_matrix(), Catch::Contains("overflow"));
  c.pop_matrix();
  CHECK_THROWS_WITH(c.pop_matrix(), Catch::Contains("underflow"));
  c.matrix_mode(MatrixMode::ModelView);
  for (int i = 0; i < 31; ++i) c.push_matrix();
  CHECK_THROWS(c.push_matrix());
  c.translate(1, 2, 3);
  CHECK(c.matrix(MatrixMode::ModelView)(0, 3) == 1);
  c.pop_matrix();
  CHECK(c.matrix(MatrixMode::ModelView)(0, 3) == 0);
}

TEST_CASE("scissor and depth range shape what reaches the framebuffer", "[render][framebuffer]") {
  Context c(16, 16);
  c.clear_color(0, 0, 0, 1);
  c.clear();
  c.enable(Cap::ScissorTest);
  c.scissor(4, 4, 8, 8);
  c.enable(Cap::DepthTest);
  c.depth_range(0.25, 0.75);
  c.begin(Primitive::Quads);
  c.color(1, 1, 1);
  c.vertex(-1, -1, 0), c.vertex(1, -1, 0), c.vertex(1, 1, 0), c.vertex(-1, 1, 0);
  c.end();
  CHECK(c.read_pixel(3, 8)[0] == 0);
  CHECK(c.read_pixel(4, 8)[0] == 255);
  CHECK(c.read_pixel(11, 11)[0] == 255);
  CHECK(c.read_pixel(12, 11)[0] == 0);
  CHECK(c.read_depth(8, 8) == Approx(0.5).margin(1e-6));
  CHECK(c.read_depth(0, 0) == 1.0f);
}

TEST_CASE("painter's algorithm and the BSP tree give the z-buffer's image", "[render][visibility]") {
  // Cubes that overlap on screen but not cyclically, including one rotated so that BSP planes
  // cut other cubes' triangles.
  Mesh m = cube();
  std::vector<DrawItem> items(4);
  const Mat4 xf[4] = {translate(Vec3(0, 0, 0)), translate(Vec3(1.2, 2.5, 0.3)) * rotate(30, Vec3(1, 1, 0)),
                      translate(Vec3(-2.2, 1, -0.5)), translate(Vec3(2.5, -1, 1)) * scale(Vec3(0.5, 0.5, 0.5))};
  const Vec4f col[4] = {{0.9f, 0.2f, 0.2f, 1}, {0.2f, 0.9f, 0.2f, 1}, {0.2f, 0.2f, 0.9f, 1}, {0.9f, 0.9f, 0.2f, 1}};
  for (int i = 0; i < 4; ++i) items[i].mesh = &m, items[i].transform = xf[i], items[i].material.diffuse = col[i];
  RenderOptions o = options();
  o.width = 128, o.height = 96;
  o.camera.eye = Point3(6, -9, 5);
  o.shading = ShadeModel::Flat;
  Image z = render_scene(items, o);
  for (auto v : {Visibility::Painter, Visibility::Bsp}) {
    o.visibility = v;
    Image im = render_scene(items, o);
    int covered = 0, diff = 0;
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        auto a = z.pixel(x, y), b = im.pixel(x, y);
        covered += a != std::array<std::uint8_t, 4>{0, 0, 0, 255};
        int d = 0;
        for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a[k]) - int(b[k])));
        diff += d > 2;
      }
    INFO("visibility " << int(v) << ": " << diff << " of " << covered << " pixels differ");
    CHECK(covered > 1000);
    CHECK(diff <= covered / 1000);
  }
  // Without culling both must still hide back faces behind front ones.
  o.cull = "none";
  o.visibility = Visibility::ZBuffer;
  Image z2 = render_scene(items, o);
  for (auto v : {Visibility::Painter, Visibility::Bsp}) {
    o.visibility = v;
    Image b2 = render_scene(items, o);
    int diff = 0;
    for (std::size_t i = 0; i < z2.rgba.size(); ++i) diff += std::abs(int(z2.rgba[i]) - int(b2.rgba[i])) > 2;
    INFO("visibility " << int(v));
    CHECK(diff <= 10);
  }
}

namespace {
// Pixels whose colour differs by more than 2 levels in a channel, and pixels not background.
std::pair<int, int> differing(const Image& z, const Image& im, std::array<std::uint8_t, 4> bg = {0, 0, 0, 255}) {
  int covered = 0, diff = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      auto a = z.pixel(x, y), b = im.pixel(x, y);
      covered += a != bg;
      int d = 0;
      for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a[k]) - int(b[k])));
      diff += d > 2;
    }
  return {diff, covered};
}

// With WEDGE_KEEP_IMAGES set, writes the image to the build directory for a look.
void keep(const std::string& name, const Image& im) {
  if (std::getenv("WEDGE_KEEP_IMAGES")) write_png(std::string(WEDGE_BINARY_DIR) + "/" + name + ".png", im);
}

Mesh triangle(const Point3& a, const Point3& b, const Point3& c) {
  Mesh m;
  m.add_vertex(a), m.add_vertex(b), m.add_vertex(c);
  m.add_triangle(0, 1, 2);
  return m;
}
}  // namespace

TEST_CASE("the painter's overlap tests order what the farthest-depth sort gets wrong, culling off", "[render][visibility]") {
  // A slanted triangle A reaching from depth 2 to depth 10 lies in front of a small triangle B at
  // depth 6 over all of B's image: sorted by farthest depth A would be drawn first and B painted
  // over it; the z-buffer shows no B at all. No cyclic overlap, no interpenetration.
  Mesh a = triangle(Point3(-1, -1, 3), Point3(1, -1, 3), Point3(0, 3, -5));
  Mesh b = triangle(Point3(-0.5, -0.5, -1), Point3(0.5, -0.5, -1), Point3(0, 0.5, -1));
  std::vector<DrawItem> items(2);
  items[0].mesh = &a, items[0].material.diffuse = Vec4f(0.9f, 0.2f, 0.2f, 1);
  items[1].mesh = &b, items[1].material.diffuse = Vec4f(0.2f, 0.2f, 0.9f, 1);
  for (bool ortho : {false, true}) {
    for (bool b_first : {false, true}) {
      INFO((ortho ? "orthographic" : "perspective") << (b_first ? ", B listed first" : ", A listed first"));
      std::vector<DrawItem> list = items;
      if (b_first) std::swap(list[0], list[1]);
      RenderOptions o = options();
      o.width = 96, o.height = 96;
      o.cull = "none";
      o.two_side = true;
      o.lights[0].direction = Vec3(0.2, -0.3, -1);
      o.shading = ShadeModel::Flat;
      o.camera.eye = Point3(0, 0, 5), o.camera.center = Point3(0, 0, 0), o.camera.up = Vec3(0, 1, 0);
      o.camera.orthographic = ortho;
      o.camera.left = -2, o.camera.right = 2, o.camera.bottom = -2, o.camera.top = 2;
      Image z = render_scene(list, o);
      const std::string name = std::string("painter_ab_") + (ortho ? "ortho" : "persp") + (b_first ? "_b" : "_a");
      keep(name + "_z", z);
      int blue = 0, red = 0;
      for (int y = 0; y < z.height; ++y)
        for (int x = 0; x < z.width; ++x) {
          auto p = z.pixel(x, y);
          blue += p[2] > p[0] + 20, red += p[0] > p[2] + 20;
        }
      REQUIRE(blue == 0);  // the scene is as described: A hides B
      REQUIRE(red > 500);
      o.visibility = Visibility::Painter;
      Image im = render_scene(list, o);
      keep(name + "_painter", im);
      auto [diff, covered] = differing(z, im);
      INFO(diff << " of " << covered << " pixels differ");
      CHECK(diff <= covered / 1000);
    }
  }
}

TEST_CASE("the painter's algorithm gives the z-buffer's image on overlapping parallel slats, culling off", "[render][visibility]") {
  // Venetian blinds: eight slanted strips, each hiding part of the one above and behind it. Their
  // depth ranges all overlap and the farthest-depth order is exactly backwards; the slats are
  // parallel, so there is no cyclic overlap. Seen from the front (their lit side) and from behind.
  Mesh slat;
  slat.add_vertex(Point3(-2, 0, -1.5)), slat.add_vertex(Point3(2, 0, -1.5));
  slat.add_vertex(Point3(2, 1, 0)), slat.add_vertex(Point3(-2, 1, 0));
  slat.add_triangle(0, 1, 2), slat.add_triangle(0, 2, 3);
  std::vector<DrawItem> items(8);
  for (int i = 0; i < 8; ++i) {
    items[i].mesh = &slat;
    items[i].transform = translate(Vec3(0.1 * i, 0.3 * i, 0));
    items[i].material.diffuse = Vec4f(0.2f + 0.1f * i, 0.9f - 0.1f * i, i % 2 ? 0.8f : 0.2f, 1);
  }
  for (bool ortho : {false, true})
    for (double side : {1.0, -1.0}) {
      INFO((ortho ? "orthographic" : "perspective") << (side > 0 ? ", from the front" : ", from behind"));
      RenderOptions o = options();
      o.width = 128, o.height = 96;
      o.cull = "none";
      o.two_side = true;
      o.lights.push_back(o.lights[0]);
      o.lights[1].direction = Vec3(0.2, 0.3, 1);  // lights the slats' backs
      o.shading = ShadeModel::Smooth;
      o.camera.eye = side > 0 ? Point3(0.5, 2, 6) : Point3(0.5, 1, -6);
      o.camera.center = Point3(0.35, 1.5, -0.75), o.camera.up = Vec3(0, 1, 0);
      o.camera.orthographic = ortho;
      o.camera.left = -3, o.camera.right = 3, o.camera.bottom = -2.5, o.camera.top = 2.5;
      Image z = render_scene(items, o);
      const std::string name = std::string("slats_") + (ortho ? "ortho" : "persp") + (side > 0 ? "_front" : "_back");
      keep(name + "_z", z);
      REQUIRE(colours(z).size() >= 9);  // every slat shows
      for (auto v : {Visibility::Painter, Visibility::Bsp}) {
        o.visibility = v;
        Image im = render_scene(items, o);
        keep(name + "_" + std::to_string(int(v)), im);
        auto [diff, covered] = differing(z, im);
        INFO("visibility " << int(v) << ": " << diff << " of " << covered << " pixels differ");
        CHECK(covered > 3000);
        CHECK(diff <= covered / 1000);
      }
      o.visibility = Visibility::ZBuffer;
    }
}

TEST_CASE("two-step cylinder, sphere and box mappings give the intermediate surface's (u, v)", "[render][texture]") {
  Mesh m;
  // Points on a cylinder of radius 1 about z, heights 0..2 (centre at z = 1).
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k <= 2; ++k) m.add_vertex(Point3(std::cos(i * kPi / 4), std::sin(i * kPi / 4), k));
  m.add_triangle(0, 3, 1);
  Mesh c = with_uv_mapping(m, UvMapping::Cylinder);
  REQUIRE(c.uvs.size() == m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    CHECK(c.uvs[i].y() == Approx(m.positions[i].z() / 2).margin(1e-12));
    CHECK(c.uvs[i].x() >= 0);
    CHECK(c.uvs[i].x() <= 1);
  }
  // Around the axis u grows by 1/8 per step (up to the seam).
  double du = c.uvs[3].x() - c.uvs[0].x();
  CHECK(std::abs(std::abs(du) - 0.125) < 1e-9);
  Mesh s = with_uv_mapping(m, UvMapping::Sphere);
  CHECK(s.uvs[1].y() == Approx(0.5).margin(1e-12));  // the equator (z = 1 is the centre)
  CHECK(s.uvs[2].y() > 0.5);                          // above it
  Mesh b = with_uv_mapping(cube(), UvMapping::Box);
  for (const auto& uv : b.uvs) {
    CHECK(uv.x() >= -1e-12);
    CHECK(uv.x() <= 1 + 1e-12);
  }
  CHECK_THROWS(with_uv_mapping(m, UvMapping::Cylinder, Vec3(0, 0, 0)));
}

TEST_CASE("a texture loaded from PNG samples its texels, bottom row at t = 0", "[render][texture]") {
  Image im;
  im.width = 2, im.height = 2;
  im.rgba = {255, 0, 0, 255, 0, 255, 0, 255,   // top row: red, green
             0, 0, 255, 255, 255, 255, 255, 255};  // bottom row: blue, white
  std::string path = std::string(WEDGE_BINARY_DIR) + "/tex2x2.png";
  write_png(path, im);
  auto t = Texture::load_png(path, TexFormat::RGBA, false);
  t->mag_filter = TexFilter::Nearest;
  CHECK(t->sample(0.25f, 0.25f, -1).isApprox(Vec4f(0, 0, 1, 1)));  // bottom left: blue
  CHECK(t->sample(0.75f, 0.75f, -1).isApprox(Vec4f(0, 1, 0, 1)));  // top right: green
  auto l = Texture::load_png(path, TexFormat::Luminance, true);
  CHECK(l->levels.size() == 2);
  CHECK(l->sample(0.25f, 0.75f, -1)[1] == Approx(1.0f));  // luminance of red is its red channel
}

TEST_CASE("banded multi-threaded rasterisation gives the single-threaded image", "[render][threads]") {
  // Overlapping translucent, depth-tested, wireframe and filled triangles: order matters.
  std::vector<double> pos;
  std::vector<float> col;
  for (int i = 0; i < 1200; ++i) {  // enough for the parallel vertex stage and setup too
    double cx = std::sin(i * 1.3) * 0.8, cy = std::cos(i * 0.7) * 0.8, z = std::sin(i * 0.31);
    for (int k = 0; k < 3; ++k) {
      double a = i * 0.9 + k * 2.1;
      pos.insert(pos.end(), {cx + 0.3 * std::cos(a), cy + 0.3 * std::sin(a), z + 0.1 * k});
      col.insert(col.end(), {float(k == 0), float(k == 1), float(k == 2), 0.6f});
    }
  }
  auto draw = [&](int threads) {
    Context c(97, 83);
    c.threads(threads);
    c.clear_color(0, 0, 0, 1);
    c.clear();
    c.enable(Cap::DepthTest);
    c.depth_func(DepthFunc::LessEqual);
    c.enable(Cap::Blend);
    c.blend_func(BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha);
    VertexArrays a;
    a.positions = pos.data();
    a.colors = col.data();
    c.draw_arrays(Primitive::Triangles, a, 0, 3000);
    c.polygon_mode(Face::FrontAndBack, PolygonMode::Line);
    c.line_width(2);
    c.draw_arrays(Primitive::Triangles, a, 3000, 600);
    c.polygon_mode(Face::FrontAndBack, PolygonMode::Fill);  // culled triangles skip the vertex stage
    c.enable(Cap::CullFace);
    c.draw_arrays(Primitive::Triangles, a, 0, 3600);
    return c.image();
  };
  Image one = draw(1), two = draw(2);
  CHECK(one.rgba == two.rgba);
  CHECK_THROWS(Context(4, 4).threads(0));
}

TEST_CASE("bands give the single-threaded bits where a triangle spans several: planes from its own corner", "[render][threads]") {
  // A textured, fogged plane receding to the horizon (two triangles, one crossing the near plane)
  // and a smooth-shaded fan of long thin triangles, each over many bands of rows: the band that
  // draws a row must evaluate the same attribute, texture-coordinate and depth planes as one
  // thread does (taken at the triangle's first quad, not at the band's first row), or colours and
  // mipmap levels differ in the last bit. Scissored to an odd first row, at 1, 2 and 3 threads.
  std::vector<double> pos, tex;
  std::vector<float> col;
  const double p[4][3] = {{-20, -1, 5}, {20, -1, 5}, {20, -1, -60}, {-20, -1, -60}};
  const double t[4][2] = {{0, 0}, {20, 0}, {20, 32}, {0, 32}};
  for (int k : {0, 1, 2, 0, 2, 3}) {
    pos.insert(pos.end(), {p[k][0], p[k][1], p[k][2]});
    tex.insert(tex.end(), {t[k][0], t[k][1]});
    col.insert(col.end(), {1, 1, 1, 1});
  }
  for (int i = 0; i < 40; ++i) {  // a fan of slivers around (0, 0.2, -2), 2 to 4 bands tall
    const double a0 = i * 0.157, a1 = a0 + 0.05;
    pos.insert(pos.end(), {0, 0.2, -2, 3 * std::cos(a0), 0.2 + 3 * std::sin(a0), -2.5, 3 * std::cos(a1), 0.2 + 3 * std::sin(a1), -2.5});
    tex.insert(tex.end(), {0, 0, 0, 0, 0, 0});
    col.insert(col.end(), {1, 0.2f, 0.1f, 1, 0.1f, 0.9f, 0.3f, 1, 0.2f, 0.3f, 1, 1});
  }
  auto checker = Texture::checker(256, 16, Vec4f(1, 1, 1, 1), Vec4f(0.2f, 0.3f, 0.6f, 1));
  struct Frame {
    Image image;
    std::vector<float> depth;
  };
  checker->min_filter = TexFilter::LinearMipmapLinear;
  auto draw = [&](int threads, bool sse2, bool scissor) {
    Context c(400, 300);
    c.threads(threads);
    if (sse2) c.simd(Simd::Sse2);
    c.clear_color(0.7f, 0.7f, 0.75f, 1);
    c.clear();
    if (scissor) {
      c.enable(Cap::ScissorTest);
      c.scissor(3, 7, 390, 280);
    }
    c.matrix_mode(MatrixMode::Projection);
    c.perspective(45, 400.0 / 300, 0.5, 100);
    c.matrix_mode(MatrixMode::ModelView);
    c.look_at(Point3(0, 0.8, 3), Point3(0, 0, 0), Vec3(0, 1, 0));
    c.enable(Cap::DepthTest);
    VertexArrays va;
    va.positions = pos.data(), va.texcoords = tex.data(), va.colors = col.data();
    c.enable(Cap::Texture2D);
    c.bind_texture(checker);
    c.tex_env_mode(TexEnvMode::Modulate);
    c.enable(Cap::Fog);
    c.fog_mode(FogMode::Linear);
    c.fog_color(Vec4f(0.7f, 0.7f, 0.75f, 1));
    c.fog_start(2);
    c.fog_end(40);
    c.draw_arrays(Primitive::Triangles, va, 0, 6);
    c.disable(Cap::Texture2D);
    c.disable(Cap::Fog);
    c.draw_arrays(Primitive::Triangles, va, 6, int(pos.size() / 3) - 6);
    return Frame{c.image(), c.depth_buffer()};
  };
  for (bool sse2 : {false, true})
    for (bool scissor : {false, true}) {
      const Frame one = draw(1, sse2, scissor);
      for (int threads : {2, 3}) {
        const Frame more = draw(threads, sse2, scissor);
        INFO(threads << " threads" << (sse2 ? ", SSE2" : "") << (scissor ? ", scissored" : ""));
        std::size_t differ = 0;
        for (std::size_t i = 0; i < one.image.rgba.size(); i += 4)
          differ += std::memcmp(&one.image.rgba[i], &more.image.rgba[i], 4) != 0;
        CHECK(differ == 0);
        CHECK(std::memcmp(one.depth.data(), more.depth.data(), one.depth.size() * sizeof(float)) == 0);
      }
    }
}

TEST_CASE("a mesh's own normals are used, smooth normals are computed only when it has none", "[render][scene]") {
  Mesh m;
  m.add_vertex(Point3(-1, -1, 0)), m.add_vertex(Point3(1, -1, 0)), m.add_vertex(Point3(0, 1, 0));
  m.add_triangle(0, 1, 2);
  RenderOptions o;
  o.width = o.height = 32;
  o.camera.eye = Point3(0, 0, 5);
  o.camera.up = Vec3(0, 1, 0);
  o.background = Vec4f(0, 0, 0, 1);
  o.ambient = Vec4f(0, 0, 0, 1);
  LightSpec l;
  l.direction = Vec3(0, 0, -1);  // straight at the triangle
  l.specular = Vec4f(0, 0, 0, 1);
  o.lights.push_back(l);
  DrawItem it;
  it.mesh = &m;
  const int computed = render_scene({it}, o).pixel(16, 18)[0];
  CHECK(computed == Approx(0.8 * 255).margin(2));  // n = +z: full diffuse 0.8
  m.normals.assign(3, Vec3(1, 0, 0));               // the file's normals: perpendicular to the light
  const int own = render_scene({it}, o).pixel(16, 18)[0];
  CHECK(own == 0);
}

TEST_CASE("the BSP tree with an orthographic camera sorts along the view direction", "[render][visibility]") {
  // The eye point lies between two cubes; the orthographic view still shows the one behind the
  // eye point (nearer the viewer at infinity) in front. Sorting from the eye point would draw it
  // first and let the far cube cover it.
  Mesh m = cube();
  std::vector<DrawItem> items(2);
  items[0].mesh = &m, items[0].transform = scale(Vec3(0.5, 0.5, 0.5));  // near, small, red
  items[0].material.diffuse = Vec4f(0.9f, 0.2f, 0.2f, 1);
  items[1].mesh = &m, items[1].transform = translate(Vec3(0, 0, -4));  // far, large, blue
  items[1].material.diffuse = Vec4f(0.2f, 0.2f, 0.9f, 1);
  RenderOptions o = options();
  o.cull = "none";
  o.shading = ShadeModel::Flat;
  o.camera.orthographic = true;
  o.camera.eye = Point3(0.3, 0.2, -2), o.camera.center = Point3(0.3, 0.2, -10), o.camera.up = Vec3(0, 1, 0);
  o.camera.left = -2, o.camera.right = 2, o.camera.bottom = -1.5, o.camera.top = 1.5;
  Image z = render_scene(items, o);
  // The centre of the image shows the near cube.
  auto centre = z.pixel(z.width / 2, z.height / 2);
  REQUIRE(centre[0] > centre[2]);
  o.visibility = Visibility::Bsp;
  Image b = render_scene(items, o);
  int covered = 0, diff = 0;
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x) {
      auto p = z.pixel(x, y), q = b.pixel(x, y);
      covered += p != std::array<std::uint8_t, 4>{0, 0, 0, 255};
      int d = 0;
      for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(p[k]) - int(q[k])));
      diff += d > 2;
    }
  INFO(diff << " of " << covered << " pixels differ");
  CHECK(covered > 500);
  CHECK(diff <= covered / 1000);
}

TEST_CASE("several contexts render at once on different threads, each exactly as it renders alone", "[render][threads]") {
  // Four different scenes - lit smooth sphere, mipmapped texture with fog, blended vertex arrays
  // on banded threads, render_scene with supersampling and the painter's sort - each in its own
  // Context on its own std::thread, all at once and several rounds; every image must equal the
  // same scene rendered serially, bit for bit. One texture is shared by two of them.
  auto tex = Texture::checker(64, 8, Vec4f(1, 0.9f, 0.2f, 1), Vec4f(0.1f, 0.3f, 0.8f, 1), true);
  tex->min_filter = TexFilter::LinearMipmapLinear;
  std::shared_ptr<const Texture> shared = tex;
  auto sphere = [](Context& c, int slices, int stacks) {
    for (int i = 0; i < stacks; ++i) {
      c.begin(Primitive::QuadStrip);
      for (int j = 0; j <= slices; ++j)
        for (int k : {i + 1, i}) {
          double t = kPi * k / stacks - kPi / 2, p = 2 * kPi * j / slices;
          double x = std::cos(t) * std::cos(p), y = std::cos(t) * std::sin(p), z = std::sin(t);
          c.normal(x, y, z);
          c.tex_coord(2.0 * j / slices, double(k) / stacks);
          c.vertex(1.2 * x, 1.2 * y, 1.2 * z);
        }
      c.end();
    }
  };
  auto camera = [](Context& c) {
    c.matrix_mode(MatrixMode::Projection);
    c.load_identity();
    c.perspective(40, double(c.width()) / c.height(), 1, 20);
    c.matrix_mode(MatrixMode::ModelView);
    c.load_identity();
    c.look_at(Point3(0.5, 1.5, 5), Point3(0, 0, 0), Vec3(0, 1, 0));
  };
  std::vector<double> pos;
  std::vector<float> col;
  for (int i = 0; i < 2000; ++i) {
    double cx = std::sin(i * 1.3) * 0.8, cy = std::cos(i * 0.7) * 0.8, z = std::sin(i * 0.31);
    for (int k = 0; k < 3; ++k) {
      double a = i * 0.9 + k * 2.1;
      pos.insert(pos.end(), {cx + 0.3 * std::cos(a), cy + 0.3 * std::sin(a), z + 0.1 * k});
      col.insert(col.end(), {float(k == 0), float(k == 1), float(k == 2), 0.6f});
    }
  }
  Mesh cube_mesh = cube();
  std::vector<std::function<Image()>> scenes = {
      [&] {
        Context c(160, 120);
        c.clear_color(0.1f, 0.1f, 0.15f, 1);
        c.clear();
        camera(c);
        c.enable(Cap::DepthTest), c.enable(Cap::Lighting), c.enable(Cap::Light0);
        c.light_position(0, Vec4f(2, 1, 2, 1));
        c.light_attenuation(0, 0.5f, 0.2f, 0.05f);
        c.material_specular(Face::FrontAndBack, Vec4f(0.6f, 0.6f, 0.6f, 1));
        c.material_shininess(Face::FrontAndBack, 20);
        sphere(c, 48, 32);
        return c.image();
      },
      [&] {
        Context c(128, 128);
        c.threads(2);
        c.clear_color(0.3f, 0.3f, 0.3f, 1);
        c.clear();
        camera(c);
        c.enable(Cap::DepthTest), c.enable(Cap::Texture2D), c.enable(Cap::Fog);
        c.bind_texture(shared);
        c.tex_env_mode(TexEnvMode::Replace);
        c.fog_mode(FogMode::Exp2), c.fog_density(0.2f), c.fog_color(Vec4f(0.7f, 0.7f, 0.8f, 1));
        sphere(c, 32, 24);
        return c.image();
      },
      [&] {
        Context c(97, 83);
        c.threads(2);
        c.clear_color(0, 0, 0, 1);
        c.clear();
        c.enable(Cap::DepthTest);
        c.depth_func(DepthFunc::LessEqual);
        c.enable(Cap::Blend);
        c.blend_func(BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha);
        VertexArrays a;
        a.positions = pos.data();
        a.colors = col.data();
        c.draw_arrays(Primitive::Triangles, a, 0, 6000);
        return c.image();
      },
      [&] {
        std::vector<DrawItem> items(3);
        for (int i = 0; i < 3; ++i) {
          items[i].mesh = &cube_mesh;
          items[i].transform = translate(Vec3(1.6 * i - 1.6, 0.3 * i, -0.4 * i)) * rotate(25.0 * i, Vec3(1, 1, 0));
          items[i].material.diffuse = Vec4f(0.9f - 0.3f * i, 0.3f + 0.3f * i, 0.4f, 1);
        }
        items[1].texture = shared;
        RenderOptions o = options();
        o.width = 90, o.height = 70, o.antialias = 2, o.threads = 1;
        o.cull = "none";
        o.visibility = Visibility::Painter;
        return render_scene(items, o);
      }};
  std::vector<Image> serial;
  for (auto& s : scenes) serial.push_back(s());
  for (int round = 0; round < 3; ++round) {
    std::vector<Image> got(scenes.size());
    std::vector<std::thread> workers;
    for (std::size_t i = 0; i < scenes.size(); ++i) workers.emplace_back([&, i] { got[i] = scenes[i](); });
    for (auto& w : workers) w.join();
    for (std::size_t i = 0; i < scenes.size(); ++i) {
      INFO("round " << round << ", scene " << i);
      CHECK(got[i].width == serial[i].width);
      CHECK(got[i].rgba == serial[i].rgba);
    }
  }
}

TEST_CASE("painter and BSP draw a closed 8k-triangle sphere with culling off as the z-buffer", "[render][visibility]") {
  // Back faces everywhere behind front faces, thousands of overlapping depth ranges; the BSP tree
  // of a convex mesh is a chain as deep as the mesh has triangles (once a stack overflow).
  Mesh m;
  const int S = 96, T = 44;
  for (int i = 0; i <= T; ++i)
    for (int j = 0; j <= S; ++j) {
      double th = kPi * i / T - kPi / 2, ph = 2 * kPi * j / S;
      m.add_vertex(Point3(std::cos(th) * std::cos(ph), std::cos(th) * std::sin(ph), std::sin(th)));
    }
  for (int i = 0; i < T; ++i)
    for (int j = 0; j < S; ++j) {
      const std::uint32_t a = i * (S + 1) + j, b = a + 1, c = a + S + 1, d = c + 1;
      if (i > 0) m.add_triangle(a, b, d);  // no zero-area triangles at the poles
      if (i < T - 1) m.add_triangle(a, d, c);
    }
  std::vector<DrawItem> items(1);
  items[0].mesh = &m;
  items[0].material.diffuse = Vec4f(0.3f, 0.7f, 0.9f, 1);
  RenderOptions o = options();
  o.width = 160, o.height = 120, o.cull = "none", o.two_side = true;
  o.camera.eye = Point3(1.6, -2, 1.2);
  Image z = render_scene(items, o);
  for (auto v : {Visibility::Painter, Visibility::Bsp}) {
    o.visibility = v;
    auto [diff, covered] = differing(z, render_scene(items, o));
    INFO("visibility " << int(v) << ": " << diff << " of " << covered << " pixels differ");
    CHECK(covered > 5000);
    CHECK(diff <= covered / 1000);
  }
}

TEST_CASE("vertex arrays, indexed arrays and begin/end draw independent triangles alike", "[render][threads]") {
  // An indexed UV sphere (normals, colours, texture coordinates) through the near plane, lit two-sided
  // with colour material and fog: every attribute the triangle path fetches, clipped and unclipped.
  const int st = 24, sl = 32;
  std::vector<double> pos, nrm, tex;
  std::vector<float> col;
  for (int i = 0; i <= st; ++i)
    for (int j = 0; j <= sl; ++j) {
      const double t = kPi * i / st - kPi / 2, p = 2 * kPi * j / sl;
      const double x = std::cos(t) * std::cos(p), y = std::cos(t) * std::sin(p), z = std::sin(t);
      pos.insert(pos.end(), {x, y, z});
      nrm.insert(nrm.end(), {x, y, z});
      tex.insert(tex.end(), {double(j) / sl, double(i) / st});
      col.insert(col.end(), {float(0.5 + 0.5 * x), float(0.5 + 0.5 * y), float(0.5 + 0.5 * z), 1.0f});
    }
  std::vector<std::uint32_t> idx;
  for (int i = 0; i < st; ++i)
    for (int j = 0; j < sl; ++j) {
      const std::uint32_t a = i * (sl + 1) + j, b = a + 1, c = a + sl + 1, d = c + 1;
      idx.insert(idx.end(), {a, b, d, a, d, c});
    }
  VertexArrays va;
  va.positions = pos.data(), va.normals = nrm.data(), va.colors = col.data(), va.texcoords = tex.data();
  auto tex_img = Texture::checker(16, 4, Vec4f(1, 1, 1, 1), Vec4f(0.3f, 0.5f, 0.9f, 1));
  auto draw = [&](int how, int threads, bool cull) {
    Context c(90, 70);
    c.threads(threads);
    c.clear_color(0.1f, 0.1f, 0.1f, 1);
    c.clear();
    c.matrix_mode(MatrixMode::Projection);
    c.perspective(50, 90.0 / 70, 0.9, 10);
    c.matrix_mode(MatrixMode::ModelView);
    c.look_at(Point3(0.4, 0.3, 1.6), Point3(0, 0, 0), Vec3(0, 1, 0));
    c.enable(Cap::DepthTest);
    if (cull) c.enable(Cap::CullFace);
    c.enable(Cap::Lighting);
    c.enable(Cap::Light0);
    c.enable(Cap::ColorMaterial);
    c.light_model_two_side(true);
    c.light_position(0, Vec4f(1, 2, 3, 1));
    c.material_specular(Face::FrontAndBack, Vec4f(0.5f, 0.5f, 0.5f, 1));
    c.material_shininess(Face::FrontAndBack, 20);
    c.enable(Cap::Texture2D);
    c.bind_texture(tex_img);
    c.enable(Cap::Fog);
    c.fog_mode(FogMode::Linear);
    c.fog_start(1);
    c.fog_end(4);
    if (how == 0) {
      c.draw_elements(Primitive::Triangles, va, idx.data(), int(idx.size()));
    } else if (how == 1) {
      std::vector<double> p2, n2, t2;
      std::vector<float> c2;
      for (std::uint32_t i : idx) {
        p2.insert(p2.end(), {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]});
        n2.insert(n2.end(), {nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]});
        t2.insert(t2.end(), {tex[2 * i], tex[2 * i + 1]});
        c2.insert(c2.end(), {col[4 * i], col[4 * i + 1], col[4 * i + 2], col[4 * i + 3]});
      }
      VertexArrays flat;
      flat.positions = p2.data(), flat.normals = n2.data(), flat.colors = c2.data(), flat.texcoords = t2.data();
      c.draw_arrays(Primitive::Triangles, flat, 0, int(idx.size()));
    } else {
      c.begin(Primitive::Triangles);
      for (std::uint32_t i : idx) {
        c.normal(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
        c.color(col[4 * i], col[4 * i + 1], col[4 * i + 2], col[4 * i + 3]);
        c.tex_coord(tex[2 * i], tex[2 * i + 1]);
        c.vertex(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
      }
      c.end();
    }
    return c.image();
  };
  for (bool cull : {false, true}) {
    const Image ref = draw(2, 1, cull);
    std::set<std::array<std::uint8_t, 4>> seen;
    for (int y = 0; y < ref.height; ++y)
      for (int x = 0; x < ref.width; ++x) seen.insert(ref.pixel(x, y));
    CHECK(seen.size() > 50);  // lit, textured, fogged: not a flat image
    for (int how : {0, 1, 2})
      for (int threads : {1, 2}) {
        INFO("path " << how << ", threads " << threads << ", cull " << cull);
        CHECK(draw(how, threads, cull).rgba == ref.rgba);
      }
  }
}

TEST_CASE("the default build's vertex code draws what the run-time-selected (AVX2) code draws", "[render][threads]") {
  if (test::avx2_missing("the vertex code's AVX2 build")) return;
  // A lit sphere (independent triangles through vertex arrays), some of it beyond the near plane.
  std::vector<double> pos;
  const int st = 40, sl = 60;
  auto vert = [&](int i, int j) {
    const double t = kPi * i / st - kPi / 2, p = 2 * kPi * j / sl;
    pos.insert(pos.end(), {std::cos(t) * std::cos(p), std::cos(t) * std::sin(p), std::sin(t)});
  };
  for (int i = 0; i < st; ++i)
    for (int j = 0; j < sl; ++j) vert(i, j), vert(i, j + 1), vert(i + 1, j + 1), vert(i, j), vert(i + 1, j + 1), vert(i + 1, j);
  VertexArrays va;
  va.positions = pos.data(), va.normals = pos.data();
  auto draw = [&](bool fallback, int threads) {
    Context c(120, 90);
    if (fallback) c.simd(Simd::Sse2);
    c.threads(threads);
    c.clear();
    c.matrix_mode(MatrixMode::Projection);
    c.perspective(45, 120.0 / 90, 1.1, 10);
    c.matrix_mode(MatrixMode::ModelView);
    c.look_at(Point3(0.3, 0.5, 2.0), Point3(0, 0, 0), Vec3(0, 1, 0));
    c.enable(Cap::DepthTest);
    c.enable(Cap::CullFace);
    c.enable(Cap::Lighting);
    c.enable(Cap::Light0);
    c.light_position(0, Vec4f(2, 2, 3, 1));
    c.material_specular(Face::FrontAndBack, Vec4f(0.5f, 0.5f, 0.5f, 1));
    c.material_shininess(Face::FrontAndBack, 30);
    c.draw_arrays(Primitive::Triangles, va, 0, int(pos.size() / 3));
    return c.image();
  };
  const Image ref = draw(false, 1);
  CHECK(draw(true, 1).rgba == ref.rgba);
  CHECK(draw(true, 2).rgba == ref.rgba);
}

TEST_CASE("batches of every small size draw alike in the default and the AVX2 vertex code", "[render][threads]") {
  if (test::avx2_missing("the vertex code's AVX2 build")) return;
  // Chunks whose vertex counts leave partial vector groups (and, with two lanes, groups wholly
  // past the end): 1 to 9 triangles and one more than a chunk, through packed client arrays.
  for (int tris : {1, 2, 3, 4, 5, 6, 7, 8, 9, 257}) {
    std::vector<double> pos;
    for (int t = 0; t < tris; ++t) {
      const double a = 0.7 * t, x = 0.6 * std::cos(a), y = 0.6 * std::sin(a);
      pos.insert(pos.end(), {x - 0.3, y - 0.2, 0.1 * t / tris, x + 0.3, y - 0.25, 0.0, x, y + 0.35, -0.1});
    }
    VertexArrays va;
    va.positions = pos.data();
    auto draw = [&](bool fallback) {
      Context c(64, 48);
      if (fallback) c.simd(Simd::Sse2);
      c.clear();
      c.matrix_mode(MatrixMode::Projection);
      c.perspective(50, 64.0 / 48, 0.5, 10);
      c.matrix_mode(MatrixMode::ModelView);
      c.look_at(Point3(0, 0, 2), Point3(0, 0, 0), Vec3(0, 1, 0));
      c.enable(Cap::DepthTest);
      c.color(0.2f, 0.7f, 0.4f);
      c.draw_arrays(Primitive::Triangles, va, 0, 3 * tris);
      return c.image();
    };
    const Image a = draw(false), b = draw(true);
    INFO(tris << " triangle(s)");
    CHECK(a.rgba == b.rgba);
    std::size_t lit = 0;
    for (std::size_t i = 0; i < a.rgba.size(); i += 4) lit += a.rgba[i + 1] > 100;
    CHECK(lit > 20);
  }
}
