// 2D clipping and raster algorithms (Foley et al., "Computer Graphics: Principles and Practice",
// 2nd ed.): Cohen-Sutherland (3.12.3: outcodes, trivial accept/reject, clip against one
// violated edge at a time), Liang-Barsky (3.12.4: the parametric form, entering and leaving t
// per edge), Sutherland-Hodgman (3.14.1: the subject polygon clipped against each edge of the
// convex clip polygon in turn), Bresenham's midpoint line (3.2.2: integer decision variable),
// the DDA (3.2.1: step the major axis by one and round the minor, each taken from the start rather
// than accumulated), the midpoint circle (3.3.2: second-order differences in one octant, mirrored
// eight ways), scan-line polygon fill (3.6: an edge table bucketed by scan line, the active
// edges' crossings sorted in x, spans by the even-odd or non-zero winding rule) and a scan-line
// seed flood fill (19.5).
#include "render/raster2d.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace wedge::render {

namespace {
enum : int { kLeft = 1, kRight = 2, kBottom = 4, kTop = 8 };

int outcode(const Point2& p, const Box2& r) {
  int c = 0;
  if (p.x() < r.min.x()) c |= kLeft;
  else if (p.x() > r.max.x()) c |= kRight;
  if (p.y() < r.min.y()) c |= kBottom;
  else if (p.y() > r.max.y()) c |= kTop;
  return c;
}
}  // namespace

bool clip_cohen_sutherland(Point2& a, Point2& b, const Box2& r) {
  int ca = outcode(a, r), cb = outcode(b, r);
  for (int guard = 0; guard < 8; ++guard) {
    if (!(ca | cb)) return true;   // trivially accepted
    if (ca & cb) return false;     // trivially rejected: both outside one edge
    const int out = ca ? ca : cb;  // an endpoint outside: move it to the violated edge
    Point2 p;
    const Vec2 d = b - a;
    if (out & kTop) p = Point2(a.x() + d.x() * (r.max.y() - a.y()) / d.y(), r.max.y());
    else if (out & kBottom) p = Point2(a.x() + d.x() * (r.min.y() - a.y()) / d.y(), r.min.y());
    else if (out & kRight) p = Point2(r.max.x(), a.y() + d.y() * (r.max.x() - a.x()) / d.x());
    else p = Point2(r.min.x(), a.y() + d.y() * (r.min.x() - a.x()) / d.x());
    if (out == ca) a = p, ca = outcode(a, r);
    else b = p, cb = outcode(b, r);
  }
  return !(ca | cb);
}

bool clip_liang_barsky(Point2& a, Point2& b, const Box2& r) {
  const Vec2 d = b - a;
  double t0 = 0, t1 = 1;
  // For each edge: p t <= q, with p < 0 entering and p > 0 leaving.
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {a.x() - r.min.x(), r.max.x() - a.x(), a.y() - r.min.y(), r.max.y() - a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0) {
      if (q[i] < 0) return false;  // parallel to and outside this edge
      continue;
    }
    const double t = q[i] / p[i];
    if (p[i] < 0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
    if (t0 > t1) return false;
  }
  const Point2 a0 = a;
  if (t1 < 1) b = a0 + t1 * d;
  if (t0 > 0) a = a0 + t0 * d;
  return true;
}

std::vector<Point2> clip_sutherland_hodgman(const std::vector<Point2>& subject, const std::vector<Point2>& clip) {
  if (clip.size() < 3) fail("Sutherland-Hodgman: the clip polygon needs at least 3 vertices, got ", clip.size());
  std::vector<Point2> out = subject, in;
  for (std::size_t e = 0; e < clip.size() && !out.empty(); ++e) {
    const Point2& c0 = clip[e];
    const Point2& c1 = clip[(e + 1) % clip.size()];
    const Vec2 edge = c1 - c0;
    auto side = [&](const Point2& p) { return edge.x() * (p.y() - c0.y()) - edge.y() * (p.x() - c0.x()); };
    in.swap(out);
    out.clear();
    for (std::size_t i = 0; i < in.size(); ++i) {
      const Point2& s = in[i];
      const Point2& t = in[(i + 1) % in.size()];
      const double ds = side(s), dt = side(t);
      if (ds >= 0) out.push_back(s);
      if ((ds >= 0) != (dt >= 0)) out.push_back(s + (ds / (ds - dt)) * (t - s));
    }
  }
  return out;
}

// Both line algorithms set, at each whole position along the major axis, the exact line's minor
// coordinate rounded to the nearest whole number, a value exactly halfway rounded up (towards
// +infinity). The tie rule names a direction on the grid, not along the line, so a segment sets
// the same pixels whichever end it is drawn from: Bresenham's plain d > 0 settled ties in the
// direction of travel, and (0,0)-(2,1) took (1,0) one way and (1,1) the other.
std::vector<Pixel> line_bresenham(int x0, int y0, int x1, int y1) {
  std::vector<Pixel> out;
  const int dx = std::abs(x1 - x0), dy = std::abs(y1 - y0);
  const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
  const bool steep = dy > dx;
  const int major = steep ? dy : dx, minor = steep ? dx : dy;
  // At d == 0 the line passes through the midpoint: step only when the minor axis goes up.
  const bool step_on_tie = (steep ? sx : sy) > 0;
  out.reserve(major + 1);
  // d = 2 minor - major: the midpoint's side of the line, updated by integer increments.
  int d = 2 * minor - major, x = x0, y = y0;
  for (int i = 0; i <= major; ++i) {
    out.push_back({x, y});
    if (d > 0 || (d == 0 && step_on_tie)) {
      if (steep) x += sx;
      else y += sy;
      d -= 2 * major;
    }
    d += 2 * minor;
    if (steep) y += sy;
    else x += sx;
  }
  return out;
}

std::vector<Pixel> line_dda(int x0, int y0, int x1, int y1) {
  std::vector<Pixel> out;
  const int steps = std::max(std::abs(x1 - x0), std::abs(y1 - y0));
  if (steps == 0) return {{x0, y0}};
  out.reserve(steps + 1);
  // Each position from the start, x0 + i dx / steps, not by adding dx / steps i times: the sum
  // drifted off an exact half ((63,154)-(185,57) put (124,105) one way, (124,106) the other).
  // i dx is a whole number and the quotient is correctly rounded, so a true half stays a half and
  // anything else stays at least 1 / steps away from one.
  auto at = [steps](int v0, int dv, int i) { return int(std::floor(v0 + double(std::int64_t(i) * dv) / steps + 0.5)); };
  for (int i = 0; i <= steps; ++i) out.push_back({at(x0, x1 - x0, i), at(y0, y1 - y0, i)});
  return out;
}

std::vector<Pixel> circle_midpoint(int cx, int cy, int r) {
  if (r < 0) fail("circle radius must not be negative, got ", r);
  std::set<Pixel> pts;
  int x = 0, y = r, d = 1 - r, de = 3, dse = -2 * r + 5;
  while (x <= y) {
    for (int sx : {-1, 1})
      for (int sy : {-1, 1}) {
        pts.insert({cx + sx * x, cy + sy * y});
        pts.insert({cx + sx * y, cy + sy * x});
      }
    if (d < 0) d += de, de += 2, dse += 2;
    else d += dse, de += 2, dse += 4, --y;
    ++x;
  }
  return {pts.begin(), pts.end()};
}

namespace {
// v converted to an int clamped to [lo, hi] (NaN to lo). The conversion is done only on a value
// already in range: int(3e9) is undefined behaviour, and a polygon reaching x = 3e9 filled nothing.
int clamped_int(double v, int lo, int hi) {
  if (!(v > lo)) return lo;
  if (!(v < hi)) return hi;
  return int(v);
}
}  // namespace

namespace {
// `cells` cut to the grid (the whole grid if not given); x0 > x1 or y0 > y1 if nothing is left.
CellRect cells_on(const Grid& grid, const std::optional<CellRect>& cells) {
  CellRect r{0, 0, grid.width - 1, grid.height - 1};
  if (cells) r = {std::max(r.x0, cells->x0), std::max(r.y0, cells->y0), std::min(r.x1, cells->x1), std::min(r.y1, cells->y1)};
  return r;
}
}  // namespace

void fill_polygon(Grid& grid, const std::vector<Point2>& poly, FillRule rule, std::int32_t value,
                  std::optional<CellRect> cells) {
  const std::size_t n = poly.size();
  const CellRect within = cells_on(grid, cells);
  if (n < 3 || within.x0 > within.x1 || within.y0 > within.y1) return;
  struct Edge {
    Point2 lo, hi;  // the end with the smaller y, the end with the larger
    int dir;        // +1 upward, -1 downward (for the winding number)
    // The edge's x at height y, for lo.y() <= y <= hi.y(). Halved terms and std::lerp keep every
    // intermediate finite for any finite ends (1e308 - -1e308 overflows), and each row's
    // crossing is found from the ends rather than by adding the slope once per row.
    double x_at(double y) const {
      const double t = (0.5 * y - 0.5 * lo.y()) / (0.5 * hi.y() - 0.5 * lo.y());
      return std::lerp(lo.x(), hi.x(), t);
    }
  };
  // Edge table: each non-horizontal edge in the bucket of the first scan line (pixel row whose
  // centre y + 1/2 >= ymin) it crosses.
  std::vector<std::vector<Edge>> table(grid.height);
  for (std::size_t i = 0; i < n; ++i) {
    Point2 a = poly[i], b = poly[(i + 1) % n];
    if (!std::isfinite(a.x()) || !std::isfinite(a.y()) || !std::isfinite(b.x()) || !std::isfinite(b.y())) continue;
    if (a.y() == b.y()) continue;
    int dir = b.y() > a.y() ? 1 : -1;
    if (a.y() > b.y()) std::swap(a, b);
    // The row in double first: a vertex may lie any distance off the canvas.
    const double first = std::ceil(a.y() - 0.5);
    if (first >= grid.height || b.y() <= std::max(first, 0.0) + 0.5) continue;
    table[clamped_int(first, 0, grid.height - 1)].push_back(Edge{a, b, dir});
  }
  std::vector<Edge> active;
  std::vector<std::pair<double, int>> xs;
  for (int y = 0; y < grid.height; ++y) {
    const double yc = y + 0.5;
    for (auto& e : table[y]) active.push_back(e);
    // Half-open in y: an edge covers centres with ymin <= yc < ymax.
    active.erase(std::remove_if(active.begin(), active.end(), [&](const Edge& e) { return e.hi.y() <= yc; }),
                 active.end());
    xs.clear();
    for (auto& e : active) xs.push_back({e.x_at(yc), e.dir});
    std::sort(xs.begin(), xs.end());
    if (y < within.y0 || y > within.y1) continue;
    int winding = 0;
    for (std::size_t k = 0; k + 1 < xs.size(); ++k) {
      winding += xs[k].second;
      bool in = rule == FillRule::EvenOdd ? (k % 2 == 0) : winding != 0;
      if (!in) continue;
      // Centres x + 1/2 in [xs[k], xs[k+1]), clamped to the row in double before becoming ints.
      const int x0 = clamped_int(std::ceil(xs[k].first - 0.5), within.x0, within.x1 + 1);
      const int x1 = clamped_int(std::ceil(xs[k + 1].first - 0.5), within.x0, within.x1 + 1);
      for (int x = x0; x < x1; ++x) grid.at(x, y) = value;
    }
  }
}

std::size_t flood_fill(Grid& grid, int x, int y, std::int32_t value, std::optional<CellRect> cells) {
  if (!grid.inside(x, y)) fail("flood fill seed (", x, ", ", y, ") is outside the ", grid.width, "x", grid.height, " grid");
  const CellRect within = cells_on(grid, cells);
  if (x < within.x0 || x > within.x1 || y < within.y0 || y > within.y1) return 0;
  const std::int32_t target = grid.at(x, y);
  if (target == value) return 0;
  std::size_t count = 0;
  std::vector<Pixel> stack{{x, y}};
  while (!stack.empty()) {
    Pixel p = stack.back();
    stack.pop_back();
    if (grid.at(p.x, p.y) != target) continue;
    // Fill the whole span of this row, then seed the rows above and below once per run.
    int l = p.x, r = p.x;
    while (l > within.x0 && grid.at(l - 1, p.y) == target) --l;
    while (r < within.x1 && grid.at(r + 1, p.y) == target) ++r;
    for (int i = l; i <= r; ++i) grid.at(i, p.y) = value, ++count;
    for (int ny : {p.y - 1, p.y + 1}) {
      if (ny < within.y0 || ny > within.y1) continue;
      bool run = false;
      for (int i = l; i <= r; ++i) {
        bool t = grid.at(i, ny) == target;
        if (t && !run) stack.push_back({i, ny});
        run = t;
      }
    }
  }
  return count;
}

}  // namespace wedge::render
