// canvas{width=, height=, background=}: a pixel grid for the classic 2D raster algorithms of
// render/raster2d.h (Foley et al., chapters 3 and 19), each reachable by name:
//   c:line{{x0,y0}, {x1,y1}, algorithm="bresenham"|"dda", color=}
//   c:circle{center={x,y}, radius=, color=}                     midpoint circle
//   c:polygon{{x,y}, ..., fill="even-odd"|"nonzero", color=}    scan-line fill
//   c:flood_fill{{x,y}, color=}                                 4-connected seed fill
//   c:clip{window={xmin,ymin,xmax,ymax}, algorithm=}            clip what is drawn next
//   c:pixel(x, y) -> {r,g,b}     c:save("out.png")
// Pixel (x, y) is the unit square [x, x+1] x [y, y+1], y up from the bottom row (as raster2d's
// Grid and a GL window); save() writes the top row first, as PNG files hold it, whole or not at all
// (render::write_png goes through an AtomicFile). Colours are
// {r, g, b} or {r, g, b, a} in [0, 1]. After c:clip{window={xmin, ymin, xmax, ymax}}, every
// primitive draws only the pixels whose position (x, y) is in the window, its edges included
// (xmin <= x <= xmax, ymin <= y <= ymax), and otherwise the pixels it draws unclipped: a line (the
// chosen algorithm, "cohen_sutherland", the default, or "liang_barsky", finds the part of the
// line to walk), a polygon (clipped by Sutherland-Hodgman before it is filled), a circle, and a
// flood fill, which spreads only through the window. c:clip{} (no window) ends clipping.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "render/raster2d.h"
#include "render/render.h"

namespace wedge::lua {

namespace {

constexpr const char* kKey = "wedge.Canvas";

struct Canvas {
  render::Grid grid;  // packed RGBA8 (r in the low byte), row 0 at the bottom
  std::optional<Box2> window;
  std::string line_clip = "cohen_sutherland";
};

Canvas& check_canvas(lua_State* L) { return check_object<Canvas>(L, 1, kKey, "Canvas"); }

std::int32_t pack(const Vec3& rgb, double a) {
  auto q = [](double c) { return std::uint32_t(std::lround(std::clamp(c, 0.0, 1.0) * 255)); };
  return std::int32_t(q(rgb.x()) | q(rgb.y()) << 8 | q(rgb.z()) << 16 | q(a) << 24);
}

// A colour field {r, g, b} or {r, g, b, a} (components in [0, 1]).
std::int32_t colour(Options& o, const char* key, std::int32_t fallback) {
  lua_State* L = o.state();
  if (o.push(key) == LUA_TNIL) {
    lua_pop(L, 1);
    return fallback;
  }
  const int idx = lua_gettop(L);
  const std::string what = std::string("field '") + key + "'";
  const int n = lua_istable(L, idx) ? int(lua_rawlen(L, idx)) : 0;
  if (n != 3 && n != 4) {
    const std::string got = describe(L, idx);
    lua_pop(L, 1);
    throw ArgError{o.arg(), what + " must be a colour {r, g, b} or {r, g, b, a}, got " + got};
  }
  double c[4] = {0, 0, 0, 1};
  for (int k = 0; k < n; ++k) {
    lua_rawgeti(L, idx, k + 1);
    const bool ok = lua_type(L, -1) == LUA_TNUMBER;
    const std::string got = ok ? "" : type_name(L, -1);
    c[k] = ok ? lua_tonumber(L, -1) : 0;
    lua_pop(L, 1);
    if (!ok || !(c[k] >= 0 && c[k] <= 1)) {
      lua_pop(L, 1);
      const std::string element = element_name(what, k + 1, "component");
      if (!ok) throw ArgError{o.arg(), element + " must be a number, got " + got};
      throw ArgError{o.arg(), element + " must be within 0..1, got " + number_text(c[k])};
    }
  }
  lua_pop(L, 1);
  return pack(Vec3(c[0], c[1], c[2]), c[3]);
}

// The positional points t[1], t[2], ... of an options table, each {x, y}.
std::vector<Point2> points(lua_State* L, int arg) {
  std::vector<Point2> pts;
  const int n = int(lua_rawlen(L, arg));
  for (int i = 1; i <= n; ++i) {
    lua_rawgeti(L, arg, i);
    try {
      pts.push_back(to_vec2(L, -1, arg, "point " + std::to_string(i)));
    } catch (...) {
      lua_pop(L, 1);
      throw;
    }
    lua_pop(L, 1);
  }
  return pts;
}

// A pixel position: a point whose coordinates are whole numbers.
// Positions and radii stay within +-32768 (twice the largest canvas): a line or circle is rasterised
// whole before the canvas drops what falls outside it, and a line from -1e9 to 1e9 asked for 16 GB.
constexpr double kMaxPixel = 32768;

int whole(double v, int arg, const std::string& what) {
  if (v != std::floor(v) || std::abs(v) > kMaxPixel)
    throw ArgError{arg, what + " must be a whole number within -32768..32768 (a pixel position), got " + number_text(v)};
  return int(v);
}

// Whether pixel position (x, y) is in the clip window, edges included (or there is no window). One
// rule for every primitive: polygons, clipped to the window itself and filled by pixel centres,
// lost the pixels on its right and top edges (a whole-canvas polygon in {10,10,20,20} covered
// [10..19] squared, a line x = 10..20), and flood fills ignored the window (all 1600 pixels).
bool in_window(const Canvas& c, int x, int y) {
  return !c.window || (x >= c.window->min.x() && x <= c.window->max.x() && y >= c.window->min.y() &&
                       y <= c.window->max.y());
}

// The window's pixels as cells for fill_polygon and flood_fill (the window's values may lie any
// distance off the canvas: clamped in double before they become ints).
render::CellRect window_cells(const Canvas& c) {
  auto cell = [&](double v) { return int(std::clamp(v, -1.0, double(std::max(c.grid.width, c.grid.height)))); };
  return {cell(std::ceil(c.window->min.x())), cell(std::ceil(c.window->min.y())), cell(std::floor(c.window->max.x())),
          cell(std::floor(c.window->max.y()))};
}

void set(Canvas& c, int x, int y, std::int32_t value) {
  if (c.grid.inside(x, y)) c.grid.at(x, y) = value;
}

// canvas{width=, height=, background=, max_pixels=}: a canvas of more than max_pixels pixels (by
// default 2^26, 256 MiB of RGBA8, as render{}'s sample budget) is an error giving its size.
int canvas_fn(lua_State* L) {
  return table_call(L, 1, [&] {
    Options o(L, 1);
    if (!o.has("width") || !o.has("height")) throw ArgError{1, "fields 'width' and 'height' are required (the size in pixels)"};
    const int w = o.integer("width", 0), h = o.integer("height", 0);
    if (w < 1 || h < 1 || w > 16384 || h > 16384)
      throw ArgError{1, "width and height must be whole numbers in 1..16384, got " + std::to_string(w) + " x " +
                            std::to_string(h)};
    const double budget = o.number("max_pixels").value_or(double(1 << 26));
    if (!(budget >= 1 && budget <= 1e12 && budget == std::floor(budget)))
      throw ArgError{1, "field 'max_pixels' must be a whole number in 1..1e12, got " + number_text(budget)};
    if (double(w) * h > budget)
      throw ArgError{1, "a canvas of " + std::to_string(w) + " x " + std::to_string(h) + " needs " +
                            number_text(double(w) * h) + " pixels, more than the budget of " + number_text(budget) +
                            " (raise it with max_pixels=)"};
    const std::int32_t bg = colour(o, "background", pack(Vec3(1, 1, 1), 1));
    o.finish();
    push_object(L, kKey, Canvas{render::Grid(w, h, bg), std::nullopt, "cohen_sutherland"});
    return 1;
  });
}

int line_m(lua_State* L) {
  return table_call(L, 2, [&] {
    Canvas& c = check_canvas(L);
    Options o(L, 2);
    o.allow_positional();
    const std::string algorithm = o.string("algorithm", "bresenham");
    if (algorithm != "bresenham" && algorithm != "dda")
      throw ArgError{2, "field 'algorithm' must be \"bresenham\" or \"dda\", got \"" + algorithm + "\""};
    const std::int32_t col = colour(o, "color", pack(Vec3(0, 0, 0), 1));
    o.finish();
    const std::vector<Point2> p = points(L, 2);
    if (p.size() != 2) throw ArgError{2, "a line needs two points {x0, y0}, {x1, y1}, got " + std::to_string(p.size())};
    Point2 a = p[0], b = p[1];
    const int x0 = whole(a.x(), 2, "point 1's x"), y0 = whole(a.y(), 2, "point 1's y");
    const int x1 = whole(b.x(), 2, "point 2's x"), y1 = whole(b.y(), 2, "point 2's y");
    const auto px = algorithm == "dda" ? render::line_dda(x0, y0, x1, y1) : render::line_bresenham(x0, y0, x1, y1);
    if (!c.window) {
      for (const render::Pixel& q : px) set(c, q.x, q.y, col);
      return 0;
    }
    // Clipping removes pixels and changes none: the visible part is the unclipped line's pixels
    // in the window. Rounding the clipped ends and drawing that shorter segment again had another
    // slope, so (25,19)-(1,28) in {10,10,30,30} rose by one pixel at x = 11, 13, 16 and 21, 144 of
    // 300 random lines changed inside the window, and the two clippers, whose ends differ in the
    // last bits, disagreed on 4 of 500. The clipper now gives the part of the segment to walk: the
    // pixels px[i], whose position along the major axis is i steps from the start, for i within
    // the clipped ends. It clips against the window grown by a pixel, because a pixel in the window
    // may have its exact line point up to half a pixel outside it; in_window() then keeps exactly
    // the pixels in the window, whatever last bits either clipper's ends have.
    const Box2& wnd = *c.window;
    const Box2 grown{wnd.min - Vec2(1, 1), wnd.max + Vec2(1, 1)};
    const bool kept = c.line_clip == "liang_barsky" ? render::clip_liang_barsky(a, b, grown)
                                                     : render::clip_cohen_sutherland(a, b, grown);
    if (!kept) return 0;
    const bool steep = std::abs(y1 - y0) > std::abs(x1 - x0);
    auto steps_from_start = [&](const Point2& q) { return steep ? std::abs(q.y() - y0) : std::abs(q.x() - x0); };
    const double s0 = std::min(steps_from_start(a), steps_from_start(b));
    const double s1 = std::max(steps_from_start(a), steps_from_start(b));
    const std::size_t first = std::size_t(std::max(0.0, std::floor(s0)));
    const std::size_t last = std::min(px.size() - 1, std::size_t(std::ceil(s1)));
    for (std::size_t i = first; i <= last; ++i)
      if (in_window(c, px[i].x, px[i].y)) set(c, px[i].x, px[i].y, col);
    return 0;
  });
}

int circle_m(lua_State* L) {
  return table_call(L, 2, [&] {
    Canvas& c = check_canvas(L);
    Options o(L, 2);
    const Vec2 centre = o.vec2("center", Vec2(0, 0));
    // Required: a default of -1 made a missing radius "got -1".
    if (!o.has("radius")) throw ArgError{2, "field 'radius' is missing (the circle's radius in pixels)"};
    const double r = o.number("radius", 0);
    const std::int32_t col = colour(o, "color", pack(Vec3(0, 0, 0), 1));
    o.finish();
    const int cx = whole(centre.x(), 2, "center's x"), cy = whole(centre.y(), 2, "center's y");
    if (r < 0 || r != std::floor(r) || r > kMaxPixel)
      throw ArgError{2, "field 'radius' must be a whole number within 0..32768, got " + number_text(r)};
    for (const render::Pixel& q : render::circle_midpoint(cx, cy, int(r))) {
      if (in_window(c, q.x, q.y)) set(c, q.x, q.y, col);
    }
    return 0;
  });
}

int polygon_m(lua_State* L) {
  return table_call(L, 2, [&] {
    Canvas& c = check_canvas(L);
    Options o(L, 2);
    o.allow_positional();
    const std::string fill = o.string("fill", "even-odd");
    if (fill != "even-odd" && fill != "nonzero")
      throw ArgError{2, "field 'fill' must be \"even-odd\" or \"nonzero\", got \"" + fill + "\""};
    const std::int32_t col = colour(o, "color", pack(Vec3(0, 0, 0), 1));
    o.finish();
    std::vector<Point2> p = points(L, 2);
    if (p.size() < 3) throw ArgError{2, "a polygon needs at least 3 points, got " + std::to_string(p.size())};
    std::optional<render::CellRect> cells;
    if (c.window) {
      // Clipped to the window grown by a pixel, which keeps the centres of the window's pixels
      // inside, and cut to the canvas grown by a pixel (a window of +-1e300 made the clipper's
      // products overflow); the fill then sets the window's pixels only.
      const Box2& wnd = *c.window;
      const Point2 lo = (wnd.min - Vec2(1, 1)).cwiseMax(Vec2(-1, -1));
      const Point2 hi = (wnd.max + Vec2(1, 1)).cwiseMin(Vec2(c.grid.width + 1, c.grid.height + 1));
      if (!(lo.x() < hi.x() && lo.y() < hi.y())) return 0;
      p = render::clip_sutherland_hodgman(p, {lo, Point2(hi.x(), lo.y()), hi, Point2(lo.x(), hi.y())});
      if (p.size() < 3) return 0;
      cells = window_cells(c);
    }
    render::fill_polygon(c.grid, p, fill == "nonzero" ? render::FillRule::NonZero : render::FillRule::EvenOdd, col, cells);
    return 0;
  });
}

int flood_fill_m(lua_State* L) {
  return table_call(L, 2, [&] {
    Canvas& c = check_canvas(L);
    Options o(L, 2);
    o.allow_positional();
    const std::int32_t col = colour(o, "color", pack(Vec3(0, 0, 0), 1));
    o.finish();
    const std::vector<Point2> p = points(L, 2);
    if (p.size() != 1) throw ArgError{2, "one seed point {x, y} expected, got " + std::to_string(p.size()) + " points"};
    const int x = whole(p[0].x(), 2, "the seed's x"), y = whole(p[0].y(), 2, "the seed's y");
    if (!c.grid.inside(x, y))
      throw ArgError{2, "the seed (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                            std::to_string(c.grid.width) + " x " + std::to_string(c.grid.height) + " canvas"};
    const std::optional<render::CellRect> cells = c.window ? std::optional(window_cells(c)) : std::nullopt;
    lua_pushinteger(L, lua_Integer(render::flood_fill(c.grid, x, y, col, cells)));
    return 1;
  });
}

int clip_m(lua_State* L) {
  return table_call(L, 2, [&] {
    Canvas& c = check_canvas(L);
    Options o(L, 2);
    const std::string algorithm = o.string("algorithm", "cohen_sutherland");
    if (algorithm != "cohen_sutherland" && algorithm != "liang_barsky" && algorithm != "sutherland_hodgman")
      throw ArgError{2, "field 'algorithm' must be \"cohen_sutherland\", \"liang_barsky\" or \"sutherland_hodgman\", got \"" +
                            algorithm + "\""};
    std::optional<Box2> window;
    if (o.push("window") != LUA_TNIL) {
      double v[4];
      const int idx = lua_gettop(L);
      std::string err;
      if (!lua_istable(L, idx) || lua_rawlen(L, idx) != 4) {
        err = "field 'window' must be {xmin, ymin, xmax, ymax}, got " +
              (lua_istable(L, idx) ? "a table of " + std::to_string(lua_rawlen(L, idx)) + " numbers" : describe(L, idx));
      }
      for (int k = 0; k < 4 && err.empty(); ++k) {
        const bool number = lua_rawgeti(L, idx, k + 1) == LUA_TNUMBER;
        v[k] = lua_tonumber(L, -1);
        const std::string element = element_name("field 'window'", k + 1, "");
        if (!number) err = element + " must be a number, got " + type_name(L, -1);
        else if (!std::isfinite(v[k])) err = element + " must be finite, got " + number_text(v[k]);
        lua_pop(L, 1);
      }
      lua_pop(L, 1);
      if (!err.empty()) throw ArgError{2, err};
      if (!(v[0] < v[2] && v[1] < v[3]))
        throw ArgError{2, "field 'window' must have xmin < xmax and ymin < ymax, got {" + number_text(v[0]) + ", " +
                              number_text(v[1]) + ", " + number_text(v[2]) + ", " + number_text(v[3]) + "}"};
      window = Box2{Point2(v[0], v[1]), Point2(v[2], v[3])};
    } else {
      lua_pop(L, 1);
    }
    o.finish();
    c.window = window;
    // Lines: the named line clipper (Sutherland-Hodgman names the polygon clipper, which
    // polygons always use: lines then keep Cohen-Sutherland).
    c.line_clip = algorithm == "liang_barsky" ? "liang_barsky" : "cohen_sutherland";
    return 0;
  });
}

int pixel_m(lua_State* L) {
  return guarded(L, [&] {
    Canvas& c = check_canvas(L);
    const int x = check_integer(L, 2), y = check_integer(L, 3);
    if (x < 0 || x >= c.grid.width) throw ArgError{2, "x must be in 0.." + std::to_string(c.grid.width - 1) + ", got " + std::to_string(x)};
    if (y < 0 || y >= c.grid.height) throw ArgError{3, "y must be in 0.." + std::to_string(c.grid.height - 1) + ", got " + std::to_string(y)};
    const std::uint32_t v = std::uint32_t(c.grid.at(x, y));
    lua_createtable(L, 3, 0);
    for (int k = 0; k < 3; ++k) {
      lua_pushnumber(L, double(v >> (8 * k) & 0xff) / 255);
      lua_rawseti(L, -2, k + 1);
    }
    return 1;
  });
}

int save_m(lua_State* L) {
  return guarded(L, [&] {
    Canvas& c = check_canvas(L);
    const std::string path = check_string(L, 2);
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    if (ext != ".png") throw ArgError{2, "the file must be a .png (the canvas is saved as PNG), got '" + path + "'"};
    sandbox_check_path(L, path, true);  // under --sandbox: the script's or the output folder only
    render::Image im;
    im.width = c.grid.width, im.height = c.grid.height;
    im.rgba.resize(std::size_t(im.width) * im.height * 4);
    for (int y = 0; y < im.height; ++y)
      for (int x = 0; x < im.width; ++x) {
        const std::uint32_t v = std::uint32_t(c.grid.at(x, y));
        std::uint8_t* p = &im.rgba[(std::size_t(im.height - 1 - y) * im.width + x) * 4];
        for (int k = 0; k < 4; ++k) p[k] = std::uint8_t(v >> (8 * k));
      }
    render::write_png(path, im);
    return 0;
  });
}

int size_m(lua_State* L) {
  return guarded(L, [&] {
    Canvas& c = check_canvas(L);
    lua_pushinteger(L, c.grid.width);
    lua_pushinteger(L, c.grid.height);
    return 2;
  });
}

const luaL_Reg kMethods[] = {{"line", line_m},     {"circle", circle_m}, {"polygon", polygon_m},
                             {"flood_fill", flood_fill_m}, {"clip", clip_m}, {"pixel", pixel_m},
                             {"save", save_m},     {"size", size_m},     {nullptr, nullptr}};

}  // namespace

void register_canvas(lua_State* L) {
  register_class(L, kKey, "Canvas", kMethods, nullptr, gc_object<Canvas>);
  static const luaL_Reg functions[] = {{"canvas", canvas_fn}, {nullptr, nullptr}};
  set_functions(L, functions);
}

}  // namespace wedge::lua
