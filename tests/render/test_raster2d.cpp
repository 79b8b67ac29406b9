// The 2D clipping and raster algorithms, each checked against a direct definition.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <set>
#include <utility>

#include "render/raster2d.h"

using namespace wedge;
using namespace wedge::render;

namespace {

double polygon_area(const std::vector<Point2>& p) {
  double a = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point2& u = p[i];
    const Point2& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return a / 2;
}

// Winding number of the closed polygon around q (direct definition, for checking the fill).
int winding(const std::vector<Point2>& p, const Point2& q) {
  int w = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Point2& a = p[i];
    const Point2& b = p[(i + 1) % p.size()];
    double cross = (b.x() - a.x()) * (q.y() - a.y()) - (q.x() - a.x()) * (b.y() - a.y());
    if (a.y() <= q.y() && b.y() > q.y() && cross > 0) ++w;
    if (a.y() > q.y() && b.y() <= q.y() && cross < 0) --w;
  }
  return w;
}

bool on_boundary_or_inside(const Point2& p, const Box2& r) {
  return p.x() >= r.min.x() - 1e-9 && p.x() <= r.max.x() + 1e-9 && p.y() >= r.min.y() - 1e-9 && p.y() <= r.max.y() + 1e-9;
}

}  // namespace

TEST_CASE("Cohen-Sutherland and Liang-Barsky clip lines to the same segment", "[render][2d][clip]") {
  const Box2 r(Point2(-1, -0.5), Point2(2, 1.5));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  int accepted = 0, rejected = 0;
  for (int i = 0; i < 2000; ++i) {
    Point2 a(u(rng), u(rng)), b(u(rng), u(rng));
    Point2 a1 = a, b1 = b, a2 = a, b2 = b;
    bool k1 = clip_cohen_sutherland(a1, b1, r), k2 = clip_liang_barsky(a2, b2, r);
    // Ground truth: sample the segment densely for points inside the rectangle.
    bool any = false;
    for (int s = 0; s <= 2000 && !any; ++s) any = on_boundary_or_inside(a + (b - a) * (s / 2000.0), r);
    REQUIRE(k1 == k2);
    if (any) CHECK(k1);
    if (!k1) {
      ++rejected;
      continue;
    }
    ++accepted;
    CHECK((a1 - a2).norm() < 1e-9);
    CHECK((b1 - b2).norm() < 1e-9);
    CHECK(on_boundary_or_inside(a1, r));
    CHECK(on_boundary_or_inside(b1, r));
    // Still on the original line.
    const Vec2 d = b - a;
    CHECK(std::abs(d.x() * (a1.y() - a.y()) - d.y() * (a1.x() - a.x())) < 1e-9 * (1 + d.squaredNorm()));
  }
  CHECK(accepted > 200);
  CHECK(rejected > 200);
  Point2 a(0, 0), b(1, 1);
  CHECK(clip_liang_barsky(a, b, r));
  CHECK(a == Point2(0, 0));  // inside: unchanged
  CHECK(b == Point2(1, 1));
}

TEST_CASE("Sutherland-Hodgman clips a polygon to a convex window", "[render][2d][clip]") {
  std::vector<Point2> square{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  std::vector<Point2> window{{1, 1}, {3, 1}, {3, 3}, {1, 3}};
  auto c = clip_sutherland_hodgman(square, window);
  CHECK(polygon_area(c) == Approx(1.0));
  std::vector<Point2> tri{{-1, -1}, {5, -1}, {-1, 5}};
  CHECK(polygon_area(clip_sutherland_hodgman(tri, square)) == Approx(4.0));  // square inside the triangle
  std::vector<Point2> far{{10, 10}, {11, 10}, {11, 11}};
  CHECK(clip_sutherland_hodgman(far, square).empty());
  CHECK_THROWS(clip_sutherland_hodgman(square, {{0, 0}, {1, 1}}));
}

TEST_CASE("Bresenham and DDA lines are connected, exact at endpoints and close to the line", "[render][2d][line]") {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> u(-40, 40);
  int same = 0;
  for (int i = 0; i < 500; ++i) {
    int x0 = u(rng), y0 = u(rng), x1 = u(rng), y1 = u(rng);
    for (auto line : {line_bresenham(x0, y0, x1, y1), line_dda(x0, y0, x1, y1)}) {
      REQUIRE(line.size() == std::size_t(std::max(std::abs(x1 - x0), std::abs(y1 - y0)) + 1));
      CHECK(line.front() == Pixel{x0, y0});
      CHECK(line.back() == Pixel{x1, y1});
      for (std::size_t k = 1; k < line.size(); ++k) {
        CHECK(std::abs(line[k].x - line[k - 1].x) <= 1);
        CHECK(std::abs(line[k].y - line[k - 1].y) <= 1);
      }
      // Each pixel is within half a pixel of the ideal line along the minor axis.
      double dx = x1 - x0, dy = y1 - y0;
      for (auto p : line) {
        double dist = std::abs(dy * (p.x - x0) - dx * (p.y - y0)) / std::max(std::abs(dx), std::abs(dy) + 1e-300);
        CHECK(dist <= 0.5 + 1e-9);
      }
    }
    same += line_bresenham(x0, y0, x1, y1) == line_dda(x0, y0, x1, y1);
  }
  CHECK(same > 400);  // they differ only where the line passes exactly between two pixels
  CHECK(line_bresenham(0, 0, 5, 0).size() == 6);
}

TEST_CASE("the midpoint circle is 8-way symmetric and within half a pixel of the circle", "[render][2d][circle]") {
  for (int r : {0, 1, 5, 17, 40}) {
    auto pts = circle_midpoint(3, -2, r);
    std::set<Pixel> s(pts.begin(), pts.end());
    CHECK(s.size() == pts.size());
    for (auto p : pts) {
      int x = p.x - 3, y = p.y + 2;
      for (auto q : {Pixel{x, -y}, Pixel{-x, y}, Pixel{y, x}, Pixel{-y, -x}}) CHECK(s.count({q.x + 3, q.y - 2}) == 1);
      CHECK(std::abs(std::hypot(x, y) - r) <= 0.5 + 1e-9);
    }
  }
  CHECK(circle_midpoint(0, 0, 1).size() == 4);
  CHECK_THROWS(circle_midpoint(0, 0, -1));
}

TEST_CASE("scan-line fill matches the even-odd and non-zero rules at every pixel centre", "[render][2d][fill]") {
  // A pentagram: its centre pentagon has winding number 2, in for non-zero, out for even-odd.
  std::vector<Point2> star;
  for (int i = 0; i < 5; ++i) {
    double a = radians(90 + 144.0 * i);
    star.push_back(Point2(32 + 28 * std::cos(a), 32 + 28 * std::sin(a)));
  }
  for (auto rule : {FillRule::EvenOdd, FillRule::NonZero}) {
    Grid g(64, 64);
    fill_polygon(g, star, rule, 1);
    int mismatches = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        int w = winding(star, Point2(x + 0.5, y + 0.5));
        bool in = rule == FillRule::EvenOdd ? (w % 2 != 0) : w != 0;
        mismatches += in != (g.at(x, y) == 1);
      }
    CHECK(mismatches == 0);
    CHECK(g.at(32, 32) == (rule == FillRule::NonZero ? 1 : 0));
  }
  // An axis-aligned rectangle covers exactly its pixels.
  Grid g(10, 10);
  fill_polygon(g, {{2, 3}, {7, 3}, {7, 8}, {2, 8}}, FillRule::EvenOdd, 5);
  int n = 0;
  for (auto v : g.cells) n += v == 5;
  CHECK(n == 25);
}

TEST_CASE("flood fill fills the 4-connected region inside a circle outline", "[render][2d][fill]") {
  Grid g(41, 41);
  for (auto p : circle_midpoint(20, 20, 15)) g.at(p.x, p.y) = 1;
  std::size_t filled = flood_fill(g, 20, 20, 2);
  std::size_t expected = 0;
  Grid ref(41, 41);
  for (auto p : circle_midpoint(20, 20, 15)) ref.at(p.x, p.y) = 1;
  // Count interior cells row by row: cells strictly between the outline's extremes.
  for (int y = 0; y < 41; ++y) {
    int l = -1, r = -1;
    for (int x = 0; x < 41; ++x)
      if (ref.at(x, y) == 1) {
        if (l < 0) l = x;
        r = x;
      }
    if (l < 0) continue;
    for (int x = l; x <= r; ++x) expected += ref.at(x, y) == 0 && x > l && x < r;
  }
  CHECK(filled == expected);
  CHECK(g.at(0, 0) == 0);  // the outside is untouched
  CHECK(flood_fill(g, 0, 0, 3) == 41 * 41 - filled - circle_midpoint(20, 20, 15).size());
  CHECK_THROWS(flood_fill(g, 50, 0, 1));
}

namespace {

// Floor division for a positive divisor.
long floor_div(long n, long d) { return n >= 0 ? n / d : -((-n + d - 1) / d); }

// The pixels of a line by its definition: along the major axis every whole position from one end
// to the other, and on the minor axis the exact line's value rounded to the nearest whole number,
// a value exactly halfway rounded up (towards +infinity), in integer arithmetic.
std::set<Pixel> line_definition(int x0, int y0, int x1, int y1) {
  std::set<Pixel> s;
  const bool steep = std::abs(y1 - y0) > std::abs(x1 - x0);
  const long m0 = steep ? y0 : x0, m1 = steep ? y1 : x1, n0 = steep ? x0 : y0, n1 = steep ? x1 : y1;
  if (m0 == m1) return {{x0, y0}};
  const long dm = m1 - m0, dn = n1 - n0;
  for (long m = std::min(m0, m1); m <= std::max(m0, m1); ++m) {
    // n = n0 + (m - m0) dn / dm, rounded half up: floor((2 num + den) / (2 den)) with den > 0.
    long num = n0 * dm + (m - m0) * dn, den = dm;
    if (den < 0) num = -num, den = -den;
    const long n = floor_div(2 * num + den, 2 * den);
    s.insert(steep ? Pixel{int(n), int(m)} : Pixel{int(m), int(n)});
  }
  return s;
}

std::set<Pixel> as_set(const std::vector<Pixel>& v) { return {v.begin(), v.end()}; }

}  // namespace

TEST_CASE("a line sets the same pixels from either end", "[render][2d][line]") {
  // (0,0)-(2,1) passes through (1, 1/2), midway between pixels (1,0) and (1,1). Bresenham's d > 0
  // took (1,0) from (0,0) but (1,1) from (2,1); a half rounds up from either end.
  const std::set<Pixel> worked{{0, 0}, {1, 1}, {2, 1}};
  CHECK(as_set(line_bresenham(0, 0, 2, 1)) == worked);
  CHECK(as_set(line_bresenham(2, 1, 0, 0)) == worked);
  CHECK(as_set(line_dda(0, 0, 2, 1)) == worked);
  CHECK(as_set(line_dda(2, 1, 0, 0)) == worked);
  // The DDA's accumulated x += ix put (124,105) going one way and (124,106) the other: at x = 124
  // y = 154 - 61 * 97 / 122 = 105.5 exactly, which rounds up to 106.
  for (auto line : {line_dda(63, 154, 185, 57), line_dda(185, 57, 63, 154), line_bresenham(63, 154, 185, 57),
                    line_bresenham(185, 57, 63, 154)}) {
    CHECK(as_set(line).count({124, 106}) == 1);
    CHECK(as_set(line).count({124, 105}) == 0);
  }
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> u(-200, 200);
  for (int i = 0; i < 3000; ++i) {
    const int x0 = u(rng), y0 = u(rng), x1 = u(rng), y1 = u(rng);
    const std::set<Pixel> want = line_definition(x0, y0, x1, y1);
    INFO(x0 << "," << y0 << " -> " << x1 << "," << y1);
    REQUIRE(as_set(line_bresenham(x0, y0, x1, y1)) == want);
    REQUIRE(as_set(line_bresenham(x1, y1, x0, y0)) == want);
    REQUIRE(as_set(line_dda(x0, y0, x1, y1)) == want);
    REQUIRE(as_set(line_dda(x1, y1, x0, y0)) == want);
  }
  // Lines with many ties: slopes 1/2 and 2 in all four directions.
  for (auto [x1, y1] : {std::pair{10, 5}, {-10, 5}, {10, -5}, {-10, -5}, {5, 10}, {-5, 10}, {5, -10}, {-5, -10}}) {
    INFO(x1 << "," << y1);
    CHECK(as_set(line_bresenham(0, 0, x1, y1)) == line_definition(0, 0, x1, y1));
    CHECK(as_set(line_bresenham(x1, y1, 0, 0)) == line_definition(0, 0, x1, y1));
    CHECK(as_set(line_dda(x1, y1, 0, 0)) == line_definition(0, 0, x1, y1));
  }
}
