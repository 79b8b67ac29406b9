// drawing{}: the multi-view orthographic sheet, and the bitmap font its labels use.
#include <catch2/catch.hpp>

#include "render/render.h"

using namespace wedge;
using namespace wedge::render;

namespace {

// A box [0,4] x [0,2] x [0,1].
Mesh box_mesh() {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.add_vertex(Point3(i & 1 ? 4 : 0, i & 2 ? 2 : 0, i & 4 ? 1 : 0));
  const int f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (auto& t : f) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

struct Extent {
  int x0 = 1 << 30, x1 = -1, y0 = 1 << 30, y1 = -1, count = 0;
};

// Pixels of the cell [cx, cx + w) x [cy, cy + h) that are neither background (white) nor the
// grey of the border and labels.
Extent object_pixels(const Image& im, int cx, int cy, int w, int h) {
  Extent e;
  for (int y = cy; y < cy + h; ++y)
    for (int x = cx; x < cx + w; ++x) {
      auto p = im.pixel(x, y);
      const bool grey = p[0] == p[1] && p[1] == p[2];
      if (grey) continue;  // background, border, label ink (the object is tinted)
      ++e.count;
      e.x0 = std::min(e.x0, x), e.x1 = std::max(e.x1, x), e.y0 = std::min(e.y0, y), e.y1 = std::max(e.y1, y);
    }
  return e;
}

}  // namespace

TEST_CASE("a drawing sheet shows every view of the object in its own cell", "[render][drawing]") {
  Mesh m = box_mesh();
  std::vector<DrawItem> items(1);
  items[0].mesh = &m;
  items[0].material.diffuse = Vec4f(0.9f, 0.5f, 0.2f, 1);
  items[0].material.ambient = Vec4f(0.9f, 0.5f, 0.2f, 1);
  DrawingOptions o;
  o.width = 400, o.height = 300;
  Image im = render_drawing(items, o);
  REQUIRE(im.width == 400);
  REQUIRE(im.height == 300);
  // 2 x 2 cells of 200 x 150; each holds the object.
  for (int v = 0; v < 4; ++v) {
    Extent e = object_pixels(im, (v % 2) * 200, (v / 2) * 150, 200, 150);
    INFO("view " << o.views[v]);
    CHECK(e.count > 500);
  }
  // The front view (cell 0) looks along +y with z up: its silhouette is the box's x/z extent,
  // 4 x 1, fitted to the cell's width (the larger extent spans most of it) and centred.
  Extent f = object_pixels(im, 0, 0, 200, 150);
  const int fw = f.x1 - f.x0 + 1, fh = f.y1 - f.y0 + 1;
  CHECK(fw > 150);
  CHECK(fw < 200);
  CHECK(double(fw) / fh == Approx(4.0).epsilon(0.08));
  CHECK(f.count >= 0.95 * fw * fh);  // a filled rectangle
  CHECK(std::abs((f.x0 + f.x1) / 2.0 - 100) <= 2);
  // The top view (cell 1) shows the x/y extent, 4 x 2.
  Extent t = object_pixels(im, 200, 0, 200, 150);
  CHECK(double(t.x1 - t.x0 + 1) / (t.y1 - t.y0 + 1) == Approx(2.0).epsilon(0.08));
  // The side view (cell 2) looks along -x: y/z extent, 2 x 1.
  Extent s = object_pixels(im, 0, 150, 200, 150);
  CHECK(double(s.x1 - s.x0 + 1) / (s.y1 - s.y0 + 1) == Approx(2.0).epsilon(0.08));
  // One scale for the three multiview views, as an engineering drawing has them: the box's x is
  // as wide in the top view as in the front, its y as wide in the side view as it is tall in the
  // top (each view fitted alone, the top's x was half again as wide as the front's).
  CHECK(std::abs((t.x1 - t.x0) - (f.x1 - f.x0)) <= 1);
  CHECK(std::abs((s.x1 - s.x0) - (t.y1 - t.y0)) <= 1);
  CHECK(std::abs((s.y1 - s.y0) - (f.y1 - f.y0)) <= 1);
  // Borders and labels: the cell's corner pixel is the border grey, and the label band above
  // the front view holds dark ink.
  CHECK(im.pixel(0, 0) == std::array<std::uint8_t, 4>{128, 128, 128, 255});
  int ink = 0;
  for (int y = 1; y < 12; ++y)
    for (int x = 1; x < 60; ++x) ink += im.pixel(x, y)[0] < 100;
  CHECK(ink > 20);
}

TEST_CASE("the bitmap font draws its glyphs and skips unknown characters", "[render][drawing]") {
  Image im;
  im.width = 20, im.height = 9;
  im.rgba.assign(std::size_t(im.width) * im.height * 4, 0);
  draw_text(im, 1, 1, "T?", {255, 255, 255, 255});
  // T: the top row of five pixels, then the middle column.
  for (int x = 1; x <= 5; ++x) CHECK(im.pixel(x, 1)[0] == 255);
  CHECK(im.pixel(3, 7)[0] == 255);
  CHECK(im.pixel(1, 7)[0] == 0);
  int lit = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 7; x < im.width; ++x) lit += im.pixel(x, y)[0] != 0;
  CHECK(lit == 0);  // '?' has no glyph
  CHECK(text_width("TOP") == 17);
}

TEST_CASE("drawing rejects bad views and sizes", "[render][drawing]") {
  Mesh m = box_mesh();
  std::vector<DrawItem> items(1);
  items[0].mesh = &m;
  DrawingOptions o;
  o.views = {"front", "sideways"};
  CHECK_THROWS_WITH(render_drawing(items, o), Catch::Contains("sideways"));
  o.views = {};
  CHECK_THROWS_WITH(render_drawing(items, o), Catch::Contains("views"));
  o.views = {"front"};
  o.width = 10, o.height = 10;
  CHECK_THROWS_WITH(render_drawing(items, o), Catch::Contains("too small"));
  o.width = 100, o.height = 100;
  CHECK_THROWS_WITH(render_drawing({}, o), Catch::Contains("nothing to draw"));
}
