#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <random>

#include "kernel/kernel.h"

using namespace wedge;

namespace {
// The textbook floating-point determinant, to show where it fails.
double naive_orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
}
int sgn(double x) { return (x > 0) - (x < 0); }
}  // namespace

TEST_CASE("orient2d on easy cases", "[predicates]") {
  CHECK(orient2d({0, 0}, {1, 0}, {0, 1}) == 1);
  CHECK(orient2d({0, 0}, {0, 1}, {1, 0}) == -1);
  CHECK(orient2d({0, 0}, {1, 1}, {2, 2}) == 0);
}

TEST_CASE("orient2d is exact where naive double arithmetic gets the sign wrong", "[predicates]") {
  // Points a within a few ulps of (0.5, 0.5), tested against the line through (12,12) and
  // (24,24), which is y = x (after Kettner et al., "Classroom examples of robustness problems").
  // The exact sign is sign(ay - ax); the naive determinant rounds a - b and loses it.
  Vec2 b(12, 12), c(24, 24);
  int naive_wrong = 0;
  for (int i = 0; i < 64; ++i) {
    for (int j = 0; j < 64; ++j) {
      Vec2 a(0.5 + i * std::ldexp(1.0, -53), 0.5 + j * std::ldexp(1.0, -53));
      // Exact truth: a is on the line y = x iff ax == ay; left of b->c (above) iff ay > ax.
      int truth = sgn(a.y() - a.x());
      // Orientation (b, c, a): c - b = (12, 12), a - b: sign of 12*(ay - by) - 12*(ax - bx) = sign(ay - ax).
      CHECK(orient2d(b, c, a) == truth);
      if (sgn(naive_orient2d(b, c, a)) != truth) ++naive_wrong;
    }
  }
  // The naive formula is wrong on many of these inputs; the exact one on none.
  CHECK(naive_wrong > 100);
}

TEST_CASE("orient3d is exact on nearly coplanar points", "[predicates]") {
  Point3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK(orient3d(a, b, c, {0.3, 0.3, 1}) == 1);
  CHECK(orient3d(a, b, c, {0.3, 0.3, -1}) == -1);
  CHECK(orient3d(a, b, c, {0.3, 0.3, 0}) == 0);
  CHECK(orient3d(a, b, c, {5, 7, 1e-300}) == 1);  // far below any float tolerance
  // A plane that is not axis-aligned, and points placed on it by construction whose
  // coordinates are rounded: the exact predicate agrees with exact reasoning about a
  // case we can decide by hand, x + y + z = 1.5 with dyadic coordinates (exactly on it).
  Point3 p(0.5, 0.5, 0.5), q(1.5, 0, 0), r(0, 1.5, 0);
  CHECK(orient3d(p, q, r, {0.25, 0.25, 1.0}) == 0);
  CHECK(orient3d(p, q, r, {0.25, 0.25, std::nextafter(1.0, 2.0)}) != 0);
  CHECK(coplanar(p, q, r, {0.25, 0.25, 1.0}));
  CHECK_FALSE(coplanar(p, q, r, {0.25, 0.25, std::nextafter(1.0, 0.0)}));
}

TEST_CASE("orient3d agrees with exact integer arithmetic where the naive determinant does not", "[predicates]") {
  // Integer coordinates below 2^40: the determinant fits in a 128-bit integer, which gives the
  // true sign. d = a + s(b-a) + t(c-a) with small integers s, t lies exactly on the plane of a, b,
  // c (true sign 0), but the naive double determinant rounds its 2^80-sized products and
  // usually returns a non-zero sign; half of the cases nudge d off the plane by one unit.
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<std::int64_t> coord(0, (std::int64_t(1) << 40) - 1);
  std::uniform_int_distribution<int> param(-2, 2), nudge(0, 1);
  int naive_wrong = 0, cases = 2000;
  for (int i = 0; i < cases; ++i) {
    std::int64_t P[4][3];
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j) P[k][j] = coord(rng);
    std::int64_t s = param(rng), t = param(rng);
    for (int j = 0; j < 3; ++j) P[3][j] = P[0][j] + s * (P[1][j] - P[0][j]) + t * (P[2][j] - P[0][j]);
    P[3][2] += nudge(rng);
    __int128 u[3], v[3], w[3];
    for (int j = 0; j < 3; ++j) {
      u[j] = P[1][j] - P[0][j];
      v[j] = P[2][j] - P[0][j];
      w[j] = P[3][j] - P[0][j];
    }
    __int128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
    int truth = (det > 0) - (det < 0);
    Point3 p[4];
    for (int k = 0; k < 4; ++k) p[k] = Point3(double(P[k][0]), double(P[k][1]), double(P[k][2]));
    REQUIRE(orient3d(p[0], p[1], p[2], p[3]) == truth);
    int naive = sgn((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]));
    if (naive != truth) ++naive_wrong;
  }
  CHECK(naive_wrong > cases / 10);  // the naive sign is wrong on a good share of these inputs
}

TEST_CASE("incircle and insphere", "[predicates]") {
  CHECK(incircle({0, 0}, {1, 0}, {0, 1}, {0.5, 0.5}) == 1);
  CHECK(incircle({0, 0}, {1, 0}, {0, 1}, {2, 2}) == -1);
  CHECK(incircle({0, 0}, {1, 0}, {0, 1}, {1, 1}) == 0);  // cocircular: exact zero
  CHECK(incircle({0, 0}, {1, 0}, {0, 1}, {1, std::nextafter(1.0, 2.0)}) == -1);
  Point3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(0, 0, 1);
  REQUIRE(orient3d(a, b, c, d) == 1);
  CHECK(insphere(a, b, c, d, {0.25, 0.25, 0.25}) == 1);
  CHECK(insphere(a, b, c, d, {3, 3, 3}) == -1);
  CHECK(insphere(a, b, c, d, {1, 1, 1}) == 0);  // the cube's far corner lies on the sphere
}

TEST_CASE("segment and triangle intersection tests, including touching and degenerate", "[predicates]") {
  Point3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  CHECK(segment_triangle_intersect({0.2, 0.2, -1}, {0.2, 0.2, 1}, a, b, c));
  CHECK_FALSE(segment_triangle_intersect({0.8, 0.8, -1}, {0.8, 0.8, 1}, a, b, c));
  CHECK(segment_triangle_intersect({0.5, 0.5, -1}, {0.5, 0.5, 1}, a, b, c));  // through the edge
  CHECK(segment_triangle_intersect({0.2, 0.2, 0}, {0.2, 0.2, 1}, a, b, c));   // touches at an end
  CHECK_FALSE(segment_triangle_intersect({0.2, 0.2, 1e-300}, {0.2, 0.2, 1}, a, b, c));
  // Degenerate triangle (a segment) crossed by a segment.
  CHECK(segment_triangle_intersect({0.5, -1, 0}, {0.5, 1, 0}, a, b, {2, 0, 0}));
  CHECK(segments_intersect_2d({0, 0}, {2, 2}, {0, 2}, {2, 0}));
  CHECK_FALSE(segments_intersect_2d({0, 0}, {1, 1}, {0, 2}, {0.9, 1.1}));
  CHECK(segments_intersect_2d({0, 0}, {1, 1}, {1, 1}, {2, 0}));  // shared endpoint
  CHECK(triangles_intersect(a, b, c, {0.2, 0.2, -1}, {0.2, 0.2, 1}, {5, 5, 1}));
  CHECK_FALSE(triangles_intersect(a, b, c, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}));
}

TEST_CASE("predicates reject non-finite input with a clear error", "[predicates][errors]") {
  CHECK_THROWS_WITH(orient2d({0, 0}, {1, 0}, {std::nan(""), 1}), Catch::Contains("finite"));
}

namespace {
// Integer points on the circle x^2 + y^2 = r^2 (r = 5^8 has many: 5 splits in the Gaussian
// integers), found by brute force.
std::vector<std::pair<std::int64_t, std::int64_t>> circle_points(std::int64_t r) {
  std::vector<std::pair<std::int64_t, std::int64_t>> out;
  for (std::int64_t x = -r; x <= r; ++x) {
    std::int64_t y2 = r * r - x * x;
    auto y = std::int64_t(std::llround(std::sqrt(double(y2))));
    for (std::int64_t yy : {y - 1, y, y + 1})
      if (yy >= 0 && yy * yy == y2) {
        out.push_back({x, yy});
        if (yy) out.push_back({x, -yy});
      }
  }
  return out;
}
}  // namespace

TEST_CASE("incircle and insphere are exact where the textbook determinants get the sign wrong", "[predicates]") {
  // Points on one circle (or sphere) far from the origin, with integer coordinates, so the
  // truth is decided by 128-bit integer arithmetic; half of the cases move the last point by
  // one unit. The textbook determinants (Shewchuk's, without adaptivity) round their 2^80-sized
  // products and usually miss the exact zero.
  const std::int64_t r = 390625, ox = (std::int64_t(1) << 25) + 12345, oy = (std::int64_t(1) << 24) + 6789,
                     oz = (std::int64_t(1) << 23) + 4321;
  auto pts = circle_points(r);
  REQUIRE(pts.size() > 50);
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, pts.size() - 1);
  std::uniform_int_distribution<int> nudge(-1, 1);
  int cases = 0, naive2 = 0, naive3 = 0, exact_zero = 0;
  for (int i = 0; i < 1000; ++i) {
    std::int64_t P[4][2];
    for (auto& p : P) {
      auto q = pts[pick(rng)];
      p[0] = ox + q.first, p[1] = oy + q.second;
    }
    P[3][0] += nudge(rng);
    __int128 d[3][2];
    for (int k = 0; k < 3; ++k) d[k][0] = P[k][0] - P[3][0], d[k][1] = P[k][1] - P[3][1];
    auto lift = [&](int k) { return d[k][0] * d[k][0] + d[k][1] * d[k][1]; };
    auto cr = [&](int a, int b) { return d[a][0] * d[b][1] - d[b][0] * d[a][1]; };
    __int128 det = lift(0) * cr(1, 2) + lift(1) * cr(2, 0) + lift(2) * cr(0, 1);
    __int128 orient = (P[1][0] - P[0][0]) * __int128(P[2][1] - P[0][1]) - (P[1][1] - P[0][1]) * __int128(P[2][0] - P[0][0]);
    if (orient == 0) continue;
    ++cases;
    int truth = (det > 0) - (det < 0);
    exact_zero += truth == 0;
    Point2 p[4];
    for (int k = 0; k < 4; ++k) p[k] = Point2(double(P[k][0]), double(P[k][1]));
    REQUIRE(incircle(p[0], p[1], p[2], p[3]) == truth);
    double f[3][2];
    for (int k = 0; k < 3; ++k) f[k][0] = p[k].x() - p[3].x(), f[k][1] = p[k].y() - p[3].y();
    auto fl = [&](int k) { return f[k][0] * f[k][0] + f[k][1] * f[k][1]; };
    auto fc = [&](int a, int b) { return f[a][0] * f[b][1] - f[b][0] * f[a][1]; };
    if (sgn(fl(0) * fc(1, 2) + fl(1) * fc(2, 0) + fl(2) * fc(0, 1)) != truth) ++naive2;

    // The same on a sphere: circle points placed in the three coordinate planes through the
    // centre, which all lie on the sphere of radius r.
    std::int64_t Q[5][3];
    for (int k = 0; k < 5; ++k) {
      auto q = pts[pick(rng)];
      std::int64_t c[3] = {0, 0, 0};
      c[k % 3] = q.first, c[(k + 1) % 3] = q.second;
      Q[k][0] = ox + c[0], Q[k][1] = oy + c[1], Q[k][2] = oz + c[2];
    }
    Q[4][2] += nudge(rng);
    // 4x4 determinant expanded along the lifted column; its sign convention is fixed by an easy
    // case (the centre of a positive tetrahedron is inside: insphere = +1).
    auto sphere_det = [](const std::int64_t (&R)[5][3]) {
      __int128 e[4][3];
      for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j) e[k][j] = R[k][j] - R[4][j];
      auto det3 = [&](int a, int b, int c) {
        return e[a][0] * (e[b][1] * e[c][2] - e[b][2] * e[c][1]) - e[a][1] * (e[b][0] * e[c][2] - e[b][2] * e[c][0]) +
               e[a][2] * (e[b][0] * e[c][1] - e[b][1] * e[c][0]);
      };
      auto lift3 = [&](int k) { return e[k][0] * e[k][0] + e[k][1] * e[k][1] + e[k][2] * e[k][2]; };
      __int128 v = -lift3(0) * det3(1, 2, 3) + lift3(1) * det3(0, 2, 3) - lift3(2) * det3(0, 1, 3) + lift3(3) * det3(0, 1, 2);
      return (v > 0) - (v < 0);
    };
    const std::int64_t easy[5][3] = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {1, 1, 1}};
    const int convention = sphere_det(easy);  // +1 or -1: the formula's sign for "inside"
    REQUIRE(convention != 0);
    Point3 s[5];
    for (int k = 0; k < 5; ++k) s[k] = Point3(double(Q[k][0]), double(Q[k][1]), double(Q[k][2]));
    if (orient3d(s[0], s[1], s[2], s[3]) != 1) continue;  // insphere is stated for positive tetrahedra
    const int truth3 = convention * sphere_det(Q);
    const int got = insphere(s[0], s[1], s[2], s[3], s[4]);
    REQUIRE(got == truth3);
    double g[4][3];
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j < 3; ++j) g[k][j] = s[k][j] - s[4][j];
    auto gd = [&](int a, int b, int c) {
      return g[a][0] * (g[b][1] * g[c][2] - g[b][2] * g[c][1]) - g[a][1] * (g[b][0] * g[c][2] - g[b][2] * g[c][0]) +
             g[a][2] * (g[b][0] * g[c][1] - g[b][1] * g[c][0]);
    };
    auto gl = [&](int k) { return g[k][0] * g[k][0] + g[k][1] * g[k][1] + g[k][2] * g[k][2]; };
    double naive_sph = -gl(0) * gd(1, 2, 3) + gl(1) * gd(0, 2, 3) - gl(2) * gd(0, 1, 3) + gl(3) * gd(0, 1, 2);
    if (sgn(naive_sph) * convention != truth3) ++naive3;
  }
  INFO("cases " << cases << ", exact zeros " << exact_zero << ", naive incircle wrong " << naive2 << ", naive insphere wrong " << naive3);
  CHECK(exact_zero > cases / 5);
  CHECK(naive2 > cases / 20);
  CHECK(naive3 > cases / 20);
}

TEST_CASE("volume_sign is the exact sign of a closed mesh's volume", "[predicates]") {
  using Tris = std::vector<std::array<std::uint32_t, 3>>;
  // A tetrahedron between two triangulations of one nearly flat quadrilateral (a face split along
  // one diagonal, its twin along the other; corners of turned boxes): its volume is 1.5e-17, and
  // summed in doubles, from the origin or from its box's centre, it comes out 0 or less.
  const std::vector<Point3> sliver = {{0.67193116189064517, 3.5414445183363314, 0.081726600478897321},
                                      {2.4445844911156231, 4.3452121183361498, -0.37833624259597431},
                                      {2.7270805289857565, 4.2695448698169551, 0.57794324379344464},
                                      {0.95442719976077828, 3.4657772698171367, 1.0380060868683161}};
  const Tris out = {{0, 1, 2}, {0, 2, 3}, {1, 3, 2}, {1, 0, 3}};
  Tris in = out;
  for (auto& t : in) std::swap(t[1], t[2]);
  double naive = 0;
  for (const auto& t : out) naive += sliver[t[0]].dot(sliver[t[1]].cross(sliver[t[2]]));
  CHECK_FALSE(naive > 0);
  CHECK(volume_sign(sliver, out) == 1);
  CHECK(volume_sign(sliver, in) == -1);
  // The unit cube, far from the origin and at 1e-150: the sign of its volume either way round.
  const Tris cube = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                     {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  for (double at : {0.0, 1e8, -3e15})
    for (double size : {1.0, 1e-150}) {
      std::vector<Point3> p;
      for (int k = 0; k < 8; ++k) {
        const double x = (k == 1 || k == 2 || k == 5 || k == 6), y = (k == 2 || k == 3 || k == 6 || k == 7), z = k >= 4;
        p.push_back(Point3(at + x * size, at + y * size, at + z * size));
      }
      INFO("at " << at << " size " << size);
      CHECK(volume_sign(p, cube) == (at + size == at ? 0 : 1));
      Tris turned = cube;
      for (auto& t : turned) std::swap(t[1], t[2]);
      CHECK(volume_sign(p, turned) == (at + size == at ? 0 : -1));
    }
  // Two triangles back to back bound nothing.
  CHECK(volume_sign({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 1}}) == 0);
  CHECK(volume_sign({}, {}) == 0);
}
