// Multi-view orthographic sheets (drawing{} in API.md): the views of a set of items rendered
// side by side on a grid, as the first-angle/third-angle sheets of technical drawing show them.
// Each view is an orthographic camera from named_view() whose box is fitted to the items'
// bounding box projected onto the view plane (the eight corners in eye space), plus a margin;
// cells are optionally framed by a one-pixel border and labelled with the view's name in a
// small 5x7 bitmap font defined here (capital letters, digits and a few signs; other characters
// are drawn blank).
#include <algorithm>
#include <cctype>
#include <cmath>

#include "kernel/transform.h"
#include "render/render.h"

namespace wedge::render {

namespace {

// 5x7 glyphs, one byte per row from the top, bit 4 the leftmost column.
struct Glyph {
  char c;
  std::uint8_t rows[7];
};
constexpr Glyph kFont[] = {
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}}, {'D', {0x1E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1E}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}}, {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}}, {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}}, {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04}}, {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}}, {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}}, {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
};

const Glyph* glyph(char c) {
  c = char(std::toupper(static_cast<unsigned char>(c)));
  for (const Glyph& g : kFont)
    if (g.c == c) return &g;
  return nullptr;
}

void put(Image& im, int x, int y, const std::array<std::uint8_t, 4>& c) {
  if (x < 0 || y < 0 || x >= im.width || y >= im.height) return;
  std::copy(c.begin(), c.end(), &im.rgba[(std::size_t(y) * im.width + x) * 4]);
}

// The orthographic camera of view `name`, its box fitted to `bounds` seen along the view.
Camera fitted_view(const std::string& name, const Box3& bounds) {
  Camera c = named_view(name, bounds);
  const Mat4 view = look_at(c.eye, c.center, c.up);
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (int i = 0; i < 8; ++i) {
    Point3 corner((i & 1) ? bounds.max.x() : bounds.min.x(), (i & 2) ? bounds.max.y() : bounds.min.y(),
                  (i & 4) ? bounds.max.z() : bounds.min.z());
    Vec4 e = view * corner.homogeneous();
    x0 = std::min(x0, e.x()), x1 = std::max(x1, e.x()), y0 = std::min(y0, e.y()), y1 = std::max(y1, e.y());
  }
  // A margin of 6% of the larger extent on every side (and some size for a flat or point-like
  // object seen edge-on).
  const double m = std::max({0.06 * std::max(x1 - x0, y1 - y0), 1e-6 * bounds.diagonal(), 1e-9});
  c.left = x0 - m, c.right = x1 + m, c.bottom = y0 - m, c.top = y1 + m;
  c.fit = true;
  return c;
}

}  // namespace

int text_width(const std::string& text, int scale) {
  return text.empty() ? 0 : int(text.size()) * 6 * scale - scale;
}

void draw_text(Image& im, int x, int y, const std::string& text, const std::array<std::uint8_t, 4>& color, int scale) {
  if (scale < 1) fail("draw_text: scale ", scale, " must be at least 1");
  for (std::size_t k = 0; k < text.size(); ++k) {
    const Glyph* g = glyph(text[k]);
    if (!g) continue;
    const int gx = x + int(k) * 6 * scale;
    for (int r = 0; r < 7; ++r)
      for (int col = 0; col < 5; ++col)
        if (g->rows[r] & (0x10 >> col))
          for (int dy = 0; dy < scale; ++dy)
            for (int dx = 0; dx < scale; ++dx) put(im, gx + col * scale + dx, y + r * scale + dy, color);
  }
}

Image render_drawing(const std::vector<DrawItem>& items, const DrawingOptions& o) {
  const int n = int(o.views.size());
  if (n < 1 || n > 16) fail("drawing: ", n, " views given, expected 1 to 16");
  if (o.width < 1 || o.height < 1 || o.width > 8192 || o.height > 8192)
    fail("drawing: size ", o.width, "x", o.height, " must be within 1..8192");
  if (o.columns < 0 || o.columns > n) fail("drawing: columns ", o.columns, " must be within 0..", n, " (0: automatic)");
  Box3 bounds;
  for (const auto& it : items)
    if (it.mesh)
      for (const auto& p : it.mesh->positions) bounds.extend(apply_point(it.transform, p));
  if (bounds.empty()) fail("drawing: nothing to draw (no vertices)");
  for (const auto& v : o.views) named_view(v, bounds);  // unknown names fail before any rendering

  const int cols = o.columns > 0 ? o.columns : int(std::ceil(std::sqrt(double(n))));
  const int rows = (n + cols - 1) / cols;
  const int cw = o.width / cols, ch = o.height / rows;
  const int scale = ch >= 300 ? 2 : 1;
  const int band = o.labels ? 7 * scale + 4 * scale : 0;  // label height plus padding
  const int frame = o.border ? 1 : 0;
  const int rw = cw - 2 * frame, rh = ch - 2 * frame - band;
  if (rw < 8 || rh < 8)
    fail("drawing: size ", o.width, "x", o.height, " leaves cells of ", cw, "x", ch, " pixels for ", n,
         " views: too small");

  const Vec4f& bg = o.render.background;
  // As Context::clear converts the cells' background (ties to even), so sheet and cells agree.
  auto to8 = [](float v) { return !(v > 0.0f) ? std::uint8_t(0) : v >= 1.0f ? std::uint8_t(255) : std::uint8_t(std::lrint(v * 255.0f)); };
  Image sheet;
  sheet.width = o.width, sheet.height = o.height;
  sheet.rgba.resize(std::size_t(o.width) * o.height * 4);
  for (std::size_t i = 0; i < sheet.rgba.size(); i += 4)
    for (int k = 0; k < 4; ++k) sheet.rgba[i + k] = to8(bg[k]);
  const bool light_bg = 0.3f * bg[0] + 0.59f * bg[1] + 0.11f * bg[2] > 0.5f;
  const std::array<std::uint8_t, 4> ink = light_bg ? std::array<std::uint8_t, 4>{40, 40, 40, 255}
                                                   : std::array<std::uint8_t, 4>{220, 220, 220, 255};
  const std::array<std::uint8_t, 4> rule{128, 128, 128, 255};

  for (int v = 0; v < n; ++v) {
    const int cx = (v % cols) * cw, cy = (v / cols) * ch;
    RenderOptions ro = o.render;
    ro.width = rw, ro.height = rh;
    ro.camera = fitted_view(o.views[v], bounds);
    Image im = render_scene(items, ro);
    for (int y = 0; y < rh; ++y)
      std::copy_n(&im.rgba[std::size_t(y) * rw * 4], std::size_t(rw) * 4,
                  &sheet.rgba[(std::size_t(cy + frame + band + y) * o.width + cx + frame) * 4]);
    if (o.border) {
      for (int x = cx; x < cx + cw; ++x) put(sheet, x, cy, rule), put(sheet, x, cy + ch - 1, rule);
      for (int y = cy; y < cy + ch; ++y) put(sheet, cx, y, rule), put(sheet, cx + cw - 1, y, rule);
    }
    if (o.labels) draw_text(sheet, cx + frame + 2 * scale, cy + frame + 2 * scale, o.views[v], ink, scale);
  }
  return sheet;
}

}  // namespace wedge::render
