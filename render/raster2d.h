// The classic 2D raster and clipping algorithms as library functions (Foley, van Dam, Feiner &
// Hughes, "Computer Graphics: Principles and Practice", 2nd ed., chapters 3 and 19):
// Cohen-Sutherland and Liang-Barsky line clipping, Sutherland-Hodgman polygon clipping,
// Bresenham and DDA lines, the midpoint circle with 8-way symmetry, scan-line polygon fill with
// the even-odd and non-zero winding rules, and a 4-connected flood fill.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "kernel/kernel.h"

namespace wedge::render {

struct Pixel {
  int x, y;
  bool operator==(const Pixel& o) const { return x == o.x && y == o.y; }
  bool operator<(const Pixel& o) const { return y < o.y || (y == o.y && x < o.x); }
};

// Clips segment a-b to the rectangle in place; false if nothing is left.
bool clip_cohen_sutherland(Point2& a, Point2& b, const Box2& rect);
bool clip_liang_barsky(Point2& a, Point2& b, const Box2& rect);

// Clips `subject` (any simple polygon) against a convex polygon `clip` given counter-clockwise.
std::vector<Point2> clip_sutherland_hodgman(const std::vector<Point2>& subject, const std::vector<Point2>& clip);

// The pixels of the segment between two pixel positions, both endpoints included, in order from
// (x0, y0). A minor coordinate exactly halfway between two pixels rounds up, so a segment has the
// same pixels drawn from either end, and the two algorithms give the same pixels.
std::vector<Pixel> line_bresenham(int x0, int y0, int x1, int y1);
std::vector<Pixel> line_dda(int x0, int y0, int x1, int y1);

// The pixels of a circle of integer radius r >= 0 about (cx, cy), without duplicates.
std::vector<Pixel> circle_midpoint(int cx, int cy, int r);

enum class FillRule { EvenOdd, NonZero };

// A grid of labels, row 0 at the bottom.
struct Grid {
  int width = 0, height = 0;
  std::vector<std::int32_t> cells;
  Grid(int w, int h, std::int32_t value = 0) : width(w), height(h), cells(std::size_t(w) * h, value) {}
  std::int32_t& at(int x, int y) { return cells[std::size_t(y) * width + x]; }
  std::int32_t at(int x, int y) const { return cells[std::size_t(y) * width + x]; }
  bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

// The cells x0..x1 by y0..y1, both ends included: where a fill may set cells (a clip window).
struct CellRect {
  int x0, y0, x1, y1;
};

// Sets to `value` every cell (within `cells`, if given) whose centre (x + 1/2, y + 1/2) is inside
// the polygon under `rule` (an edge-table / active-edge-table scan conversion; a centre exactly on
// a left edge is in, on a right edge is out).
void fill_polygon(Grid& grid, const std::vector<Point2>& polygon, FillRule rule, std::int32_t value,
                  std::optional<CellRect> cells = std::nullopt);

// Replaces the 4-connected region of cells equal to the seed's value (and within `cells`, if
// given) with `value` (scan-line seed fill with an explicit stack: no recursion depth limit).
// Returns the number of cells set: 0 for a seed outside `cells`.
std::size_t flood_fill(Grid& grid, int x, int y, std::int32_t value, std::optional<CellRect> cells = std::nullopt);

}  // namespace wedge::render
