// The engine's filtered predicates and its table of constructed points (Points,
// boolean_exact.cpp), against exact arithmetic: the fast orientation tests, points fixed by their
// definitions, cut points rounded within an ulp, collinearity by definition, and one definition
// per crossing of two edges. Where the interval filter bounds a point only loosely, its box must
// still be the two doubles around its exact coordinate.
#include <CGAL/Gmpq.h>
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "csg/boolean_impl.h"
#include "kernel/predicates.h"

using namespace wedge;
using namespace wedge::boolean_detail;

namespace {
double ulps(double lo, double hi) {
  const double u = std::ldexp(1.0, std::ilogb(std::max(std::abs(lo), std::abs(hi))) - 52);
  return (hi - lo) / u;
}
}  // namespace

TEST_CASE("boolean points: a segment nearly parallel to a plane cuts it at a point boxed within an ulp", "[boolean][points]") {
  // Plane z = 0.1 x + 0.3 y tilted through rounded coordinates, and segments that cross it at a
  // grazing angle: their W (the segment's direction against the plane's normal) is a few
  // roundings, so the filter's quotient spans far more than 64 ulps, and the box was left that
  // wide (five spheres turned by 1e-13 degrees: 6,384 such points, each then compared exactly
  // with every other point of the run).
  int loose = 0;
  for (int k = 1; k <= 40; ++k) {
    const double eps = std::ldexp(1.0, -40 - k);
    Mesh m;
    m.positions = {{0.1, 0.2, 0.1 * 0.1 + 0.3 * 0.2}, {3.7, 0.3, 0.37 + 0.09}, {0.3, 2.9, 0.03 + 0.87},
                   {0.7, 0.9, 0.07 + 0.27 - eps}, {2.3, 1.3, 0.23 + 0.39 + eps}, {5, 5, 9}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}};
    std::vector<const Mesh*> one{&m};
    const Soup soup = make_soup(one);
    Points pts(soup);
    PointDef d;
    d.kind = PointDef::Lpi;
    d.p = 3;
    d.q = 4;
    d.P[0] = Plane::of_triangle(soup.tris[0]);
    if (pts.side(d.P[0], 3) * pts.side(d.P[0], 4) >= 0) continue;  // the segment does not cross
    const IntervalH h = pts.interval(pts.add(d));
    const u32 p = static_cast<u32>(pts.size() - 1);
    const auto box = pts.box(p);
    const Vec3& a = pts.approx(p);
    for (int i = 0; i < 3; ++i) {
      INFO("k " << k << " axis " << i);
      CHECK(ulps(box[i], box[i + 3]) <= 1);
      CHECK(box[i] <= a[i]);
      CHECK(a[i] <= box[i + 3]);
      // The filter's quotient, for the record of how loose it was.
      const double wlo = h.lo[3], whi = h.hi[3];
      if (wlo > 0 || whi < 0) {
        const double q[4] = {h.lo[i] / wlo, h.lo[i] / whi, h.hi[i] / wlo, h.hi[i] / whi};
        if (ulps(std::min({q[0], q[1], q[2], q[3]}), std::max({q[0], q[1], q[2], q[3]})) > 64) ++loose;
      } else {
        ++loose;
      }
    }
  }
  CHECK(loose > 10);  // the loose filter path is what is tested
}

TEST_CASE("boolean: the engine's filtered orientation tests agree with the exact ones on near-degenerate input",
          "[boolean]") {
  // Points on a line or a plane, each coordinate nudged by a few ulps, at several scales: the
  // float filter must either decide correctly or hand over to the exact predicate.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> nudge(-3, 3);
  auto jiggle = [&](double x) {
    for (int k = nudge(rng); k != 0; k += (k > 0 ? -1 : 1)) x = std::nextafter(x, k > 0 ? INFINITY : -INFINITY);
    return x;
  };
  std::uniform_int_distribution<int> small(-8, 8);
  int decided_zero = 0;
  // Powers of two keep the integer cases exactly degenerate after scaling.
  for (double scale : {std::ldexp(1.0, -490), std::ldexp(1.0, -10), 1.0, std::ldexp(1.0, 23), std::ldexp(1.0, 300)}) {
    for (int n = 0; n < 20000; ++n) {
      Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng)), d;
      double cx, cy;
      if (n % 4 == 0) {  // small integers: d exactly on the plane, (cx, cy) exactly on the line
        a = Vec3(small(rng), small(rng), small(rng));
        b = Vec3(small(rng), small(rng), small(rng));
        c = Vec3(small(rng), small(rng), small(rng));
        d = a + (b - a) * small(rng) + (c - a) * small(rng);
        const int m = small(rng);
        cx = a.x() + m * (b.x() - a.x());
        cy = a.y() + m * (b.y() - a.y());
      } else {
        const double s = u(rng), t = u(rng);
        d = a + s * (b - a) + t * (c - a);  // on the plane, up to rounding
        d = Vec3(jiggle(d.x()), jiggle(d.y()), jiggle(d.z()));
        cx = jiggle(a.x() + s * (b.x() - a.x()));
        cy = jiggle(a.y() + s * (b.y() - a.y()));
      }
      const Vec3 A = a * scale, B = b * scale, C = c * scale, D = d * scale;
      REQUIRE(boolean_detail::orient3d_fast(A, B, C, D) == orient3d(A, B, C, D));
      const int fast = boolean_detail::orient2d_fast(A.x(), A.y(), B.x(), B.y(), cx * scale, cy * scale);
      REQUIRE(fast == orient2d(Point2(A.x(), A.y()), Point2(B.x(), B.y()), Point2(cx * scale, cy * scale)));
      if (fast == 0) ++decided_zero;
    }
  }
  CHECK(decided_zero > 0);  // the cases include exact degeneracies, decided by the exact path
  // Side quads of extrusions: four points that are two points seen along an axis are coplanar
  // (answered without the exact predicate); nudged by an ulp off that, they are not.
  int extruded = 0, off = 0;
  for (int n = 0; n < 20000; ++n) {
    const int k = n % 3, i = (k + 1) % 3, j = (k + 2) % 3;
    Vec3 p, q, a, b, c, d;
    p[i] = u(rng), p[j] = u(rng), q[i] = u(rng), q[j] = u(rng);
    a = p, b = q, c = q, d = p;
    a[k] = u(rng), b[k] = u(rng), c[k] = u(rng), d[k] = u(rng);
    if (n % 5 == 4) {
      d[i] = std::nextafter(d[i], INFINITY);  // off the wall by an ulp
      ++off;
    }
    const int fast = boolean_detail::orient3d_fast(a, b, c, d);
    REQUIRE(fast == orient3d(a, b, c, d));
    if (n % 5 != 4) {
      REQUIRE(fast == 0);
      ++extruded;
    }
  }
  CHECK(extruded > 10000);
  CHECK(off > 1000);
}

TEST_CASE("boolean: points with coordinates fixed by their definition are exact doubles, and the fast predicates on "
          "them agree with exact ones",
          "[boolean]") {
  // Random segments and planes, some axis-parallel (their points have coordinates known without
  // arithmetic), some generic. A point the engine calls a double must lie exactly on every plane
  // and segment that defines it (checked with the kernel's exact predicates); side() must agree
  // with orient3d on the plane's vertices (walls: a, b, a + e_k).
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> small(-6, 6);
  std::uniform_real_distribution<double> u(-3, 3);
  Mesh m;
  auto coord = [&](int i) { return i % 3 == 0 ? double(small(rng)) : u(rng); };
  for (int i = 0; i < 60; ++i) m.add_vertex(Vec3(coord(i), coord(i + 1), coord(i + 2)));
  // Axis-parallel vertex pairs and triples: shared coordinates.
  for (int i = 0; i < 60; ++i) {
    Vec3 p = m.positions[i];
    const int k = i % 3;
    Vec3 q = p, r = p;
    q[(k + 1) % 3] = u(rng);
    r[(k + 2) % 3] = u(rng);
    q[(k + 2) % 3] = small(rng);
    m.add_vertex(q);
    m.add_vertex(r);
  }
  std::vector<const Mesh*> one{&m};
  boolean_detail::Soup soup = boolean_detail::make_soup(one);
  REQUIRE(soup.verts.size() == m.positions.size());  // no two positions merged: ids are the mesh's
  boolean_detail::Points pts(soup);
  using boolean_detail::u32;
  const auto nv = static_cast<u32>(soup.verts.size());
  std::uniform_int_distribution<u32> pick(0, nv - 1), base(0, 59);
  // Vertex i < 60 and its two companions q = 60 + 2i (coordinate i % 3 kept) and r = 61 + 2i (only
  // coordinate (i + 2) % 3 changed): (i, r) is an axis-parallel segment, (i, q, r) lies in the
  // plane x_{i % 3} = const.
  auto plane = [&]() {
    const u32 i = base(rng);
    switch (rng() % 3) {
      case 0: return boolean_detail::Plane::of_triangle({i, 60 + 2 * i, 61 + 2 * i});
      case 1: return boolean_detail::Plane::wall(pick(rng), pick(rng), static_cast<int>(rng() % 3));
      default: return boolean_detail::Plane::of_triangle({pick(rng), pick(rng), pick(rng)});
    }
  };
  auto vert = [&](boolean_detail::u32 v) { return soup.verts[v]; };
  auto on_plane = [&](const boolean_detail::Plane& P, const Vec3& x) {
    if (P.axis < 0) return orient3d(vert(P.a), vert(P.b), vert(P.c), x) == 0;
    const int i = (P.axis + 1) % 3, j = (P.axis + 2) % 3;
    return orient2d(Point2(vert(P.a)[i], vert(P.a)[j]), Point2(vert(P.b)[i], vert(P.b)[j]), Point2(x[i], x[j])) == 0;
  };
  auto degenerate = [&](const boolean_detail::Plane& P) {
    if (P.axis < 0) return collinear(vert(P.a), vert(P.b), vert(P.c));
    const int i = (P.axis + 1) % 3, j = (P.axis + 2) % 3;
    return vert(P.a)[i] == vert(P.b)[i] && vert(P.a)[j] == vert(P.b)[j];
  };
  int doubles = 0, sides = 0;
  for (int n = 0; n < 12000; ++n) {
    boolean_detail::PointDef d;
    if (n % 2 == 0) {
      d.kind = boolean_detail::PointDef::Lpi;
      if (rng() % 2) {
        d.p = base(rng);
        d.q = 61 + 2 * d.p;
      } else {
        d.p = pick(rng);
        d.q = pick(rng);
      }
      if (d.q == d.p) continue;
      d.P[0] = plane();
      if (degenerate(d.P[0])) continue;
      // The segment must cross the plane (W != 0): p and q on strictly opposite sides.
      if (pts.side(d.P[0], d.p) * pts.side(d.P[0], d.q) >= 0) continue;
    } else {
      d.kind = boolean_detail::PointDef::Tpi;
      for (auto& P : d.P) P = plane();
      if (degenerate(d.P[0]) || degenerate(d.P[1]) || degenerate(d.P[2])) continue;
      bool independent = false;
      for (int k = 0; k < 3 && !independent; ++k)
        if (pts.cross_sign(d.P[1], d.P[2], k) != 0) independent = true;
      if (!independent) continue;
      // Three independent planes: det of the normals != 0 (checked on doubles far from zero).
      Vec3 nn[3];
      for (int k = 0; k < 3; ++k) {
        const auto& P = d.P[k];
        nn[k] = P.axis < 0 ? (vert(P.b) - vert(P.a)).cross(vert(P.c) - vert(P.a))
                           : (vert(P.b) - vert(P.a)).cross(Vec3::Unit(P.axis));
      }
      const double det = nn[0].dot(nn[1].cross(nn[2]));
      if (!(std::abs(det) > 1e-6 * nn[0].norm() * nn[1].norm() * nn[2].norm())) continue;
    }
    const u32 id = pts.add(d);
    const Vec3 x = pts.approx(id);
    if (pts.is_double(id)) {
      ++doubles;
      if (d.kind == boolean_detail::PointDef::Lpi) {
        REQUIRE(on_plane(d.P[0], x));
        REQUIRE(collinear(vert(d.p), vert(d.q), x));
      } else {
        REQUIRE(on_plane(d.P[0], x));
        REQUIRE(on_plane(d.P[1], x));
        REQUIRE(on_plane(d.P[2], x));
      }
      for (int k = 0; k < 20; ++k) {
        const u32 a = pick(rng), b = pick(rng), c = pick(rng);
        const int axis = static_cast<int>(rng() % 3);
        if (!collinear(vert(a), vert(b), vert(c)))
          REQUIRE(pts.side(boolean_detail::Plane::of_triangle({a, b, c}), id) == orient3d(vert(a), vert(b), vert(c), x));
        const Vec3 a1 = vert(a) + Vec3::Unit(axis);
        if (a1 - Vec3::Unit(axis) == vert(a) && !(vert(a) - vert(b)).isZero())
          REQUIRE(pts.side(boolean_detail::Plane::wall(a, b, axis), id) == orient3d(vert(a), vert(b), a1, x));
        REQUIRE(pts.compare(id, a, axis) == (x[axis] < vert(a)[axis] ? -1 : x[axis] > vert(a)[axis] ? 1 : 0));
        ++sides;
      }
    }
  }
  CHECK(doubles > 150);
  CHECK(sides > 3000);
}

TEST_CASE("boolean: cut points round within an ulp, and the predicates on them (collinear, "
          "near-cocircular) agree with exact rational arithmetic, and the flip test is never wrong",
          "[boolean]") {
  // Segments cut by axis planes (z = c: the short formula) and by generic triangle planes; their
  // points' exact coordinates computed here in rationals (GMP), independently of the engine.
  // Several cuts of one segment are collinear with its end points (answered without arithmetic
  // by the engine); cuts of a polygon's chords by one plane are nearly cocircular.
  using Q = CGAL::Gmpq;
  using boolean_detail::u32;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  Mesh m;
  for (int i = 0; i < 24; ++i) {  // a 24-gon's vertical edges, bottom and top turned by a step
    const double a = 2 * kPi * i / 24, b = 2 * kPi * (i + 1) / 24;
    m.add_vertex(Vec3(0.6 * std::cos(a) + 3, 0.6 * std::sin(a) - 1, -1.25));
    m.add_vertex(Vec3(0.6 * std::cos(b) + 3, 0.6 * std::sin(b) - 1, 2.5));
  }
  for (int i = 0; i < 30; ++i) m.add_vertex(Vec3(3 + u(rng), u(rng) - 1, 0.6 + u(rng)));
  m.add_vertex(Vec3(-5, -5, 0.7));  // an axis plane z = 0.7 (a triangle whose vertices share z)
  m.add_vertex(Vec3(5, -5, 0.7));
  m.add_vertex(Vec3(0, 5, 0.7));
  std::vector<const Mesh*> one{&m};
  boolean_detail::Soup soup = boolean_detail::make_soup(one);
  REQUIRE(soup.verts.size() == m.positions.size());
  boolean_detail::Points pts(soup);
  const auto nv = static_cast<u32>(soup.verts.size());
  const boolean_detail::Plane zplane = boolean_detail::Plane::of_triangle({nv - 3, nv - 2, nv - 1});
  auto qv = [&](u32 v) { return std::array<Q, 3>{Q(soup.verts[v].x()), Q(soup.verts[v].y()), Q(soup.verts[v].z())}; };
  std::vector<u32> ids;
  std::vector<std::array<Q, 3>> exact;
  std::vector<std::size_t> zcuts;
  auto add_cut = [&](u32 p, u32 q, const boolean_detail::Plane& P) {
    if (pts.side(P, p) * pts.side(P, q) >= 0) return false;
    boolean_detail::PointDef d;
    d.kind = boolean_detail::PointDef::Lpi;
    d.p = p;
    d.q = q;
    d.P[0] = P;
    const auto A = qv(P.a), B = qv(P.b), C = qv(P.c), X = qv(p), Y = qv(q);
    std::array<Q, 3> e1, e2, n;
    for (int i = 0; i < 3; ++i) e1[i] = B[i] - A[i], e2[i] = C[i] - A[i];
    n = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    Q num = 0, den = 0;
    for (int i = 0; i < 3; ++i) num += n[i] * (A[i] - X[i]), den += n[i] * (Y[i] - X[i]);
    const Q t = num / den;
    std::array<Q, 3> x;
    for (int i = 0; i < 3; ++i) x[i] = X[i] + t * (Y[i] - X[i]);
    ids.push_back(pts.add(d));
    exact.push_back(x);
    return true;
  };
  for (u32 i = 0; i < 24; ++i) {
    REQUIRE(add_cut(2 * i, 2 * i + 1, zplane));  // the chords' cuts by z = 0.7: nearly cocircular
    zcuts.push_back(ids.size() - 1);
    for (int k = 0; k < 3; ++k) {  // the same segment cut by generic planes: collinear cuts
      const u32 a = 48 + static_cast<u32>(rng() % 30), b = 48 + static_cast<u32>(rng() % 30), c = 48 + static_cast<u32>(rng() % 30);
      if (a != b && b != c && a != c && !collinear(soup.verts[a], soup.verts[b], soup.verts[c]))
        add_cut(2 * i, 2 * i + 1, boolean_detail::Plane::of_triangle({a, b, c}));
    }
  }
  REQUIRE(ids.size() > 50);
  // Rounding: within an ulp; the box holds the exact coordinate.
  for (std::size_t n = 0; n < ids.size(); ++n)
    for (int i = 0; i < 3; ++i) {
      const double x = pts.approx(ids[n])[i];
      const Q& e = exact[n][i];
      INFO("point " << n << " coordinate " << i);
      REQUIRE(Q(pts.box(ids[n])[i]) <= e);
      REQUIRE(e <= Q(pts.box(ids[n])[i + 3]));
      REQUIRE((Q(std::nextafter(x, -INFINITY)) < e && e < Q(std::nextafter(x, INFINITY))));
    }
  // Every point: the cuts, then the segments' end points.
  std::vector<u32> all = ids;
  std::vector<std::array<Q, 3>> ex = exact;
  for (u32 v = 0; v < 48; ++v) {
    all.push_back(v);
    ex.push_back(qv(v));
  }
  auto sgn = [](const Q& x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); };
  std::uniform_int_distribution<std::size_t> pick(0, all.size() - 1);
  int zeros = 0, near_cocircular = 0, inside = 0, found = 0;
  for (int n = 0; n < 20000; ++n) {
    int k = static_cast<int>(rng() % 3);
    std::size_t a = pick(rng), b = pick(rng), c = pick(rng), d = pick(rng);
    if (n % 4 == 0) {  // two cuts of one segment and an end point, or three cuts of it
      const u32 seg = static_cast<u32>(rng() % 24);
      std::vector<std::size_t> on;
      for (std::size_t x = 0; x < all.size(); ++x) {
        const auto& D = pts.def(all[x]);
        if ((D.kind == boolean_detail::PointDef::Lpi && D.p == 2 * seg) || all[x] == 2 * seg || all[x] == 2 * seg + 1)
          on.push_back(x);
      }
      a = on[rng() % on.size()], b = on[rng() % on.size()], c = on[rng() % on.size()];
    }
    if (n % 4 == 1) {  // four cuts of the chords by z = 0.7, seen along z
      a = zcuts[rng() % 24], b = zcuts[rng() % 24], c = zcuts[rng() % 24], d = zcuts[rng() % 24];
      k = 2;
    }
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    const auto &A = ex[a], &B = ex[b], &C = ex[c], &D = ex[d];
    const int o = sgn((B[i] - A[i]) * (C[j] - A[j]) - (B[j] - A[j]) * (C[i] - A[i]));
    zeros += o == 0 && a != b && b != c && a != c;
    REQUIRE(pts.orient2d(all[a], all[b], all[c], k) == o);
    Q r[3][3];
    const std::array<Q, 3>* P3[3] = {&A, &B, &C};
    for (int q = 0; q < 3; ++q) {
      r[q][0] = (*P3[q])[i] - D[i];
      r[q][1] = (*P3[q])[j] - D[j];
      r[q][2] = r[q][0] * r[q][0] + r[q][1] * r[q][1];
    }
    const Q det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                  r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    near_cocircular += n % 4 == 1 && a != b && a != c && a != d && b != c && b != d && c != d;
    // The retriangulation's flip test: "inside" only where exactly inside, and (on quadruples
    // not chosen near-cocircular) it finds nearly every one that is.
    const int certain = pts.incircle_certain(all[a], all[b], all[c], all[d], k);
    REQUIRE((certain == 1 || certain == -1));
    if (certain == 1) REQUIRE(sgn(det) == 1);
    if (n % 4 != 1 && sgn(det) == 1) {
      ++inside;
      found += certain == 1;
    }
  }
  CHECK(zeros > 1000);
  CHECK(near_cocircular > 1000);
  CHECK(inside > 1000);
  CHECK(found >= inside * 95 / 100);
}

TEST_CASE("boolean: points collinear by their definitions are found so without exact arithmetic, and only those",
          "[boolean]") {
  // A cylinder's side quad b0 b1 t1 t0 (planar; its diagonal b0 t1) cut by a plate's face z = 1:
  // the cuts of b0 t0, b0 t1 and b1 t1 lie on one line (the face's plane and the quad's), though
  // none is a double and no two share a segment. The same with t1 lifted off the quad's plane
  // (a quad that is not planar): not collinear, and orient2d says so.
  using boolean_detail::u32;
  Mesh m;
  const double a0 = 0.3, a1 = 0.5;
  m.add_vertex({std::cos(a0), std::sin(a0), -0.5});  // b0
  m.add_vertex({std::cos(a0), std::sin(a0), 1.5});   // t0
  m.add_vertex({std::cos(a1), std::sin(a1), -0.5});  // b1
  m.add_vertex({std::cos(a1), std::sin(a1), 1.5});   // t1
  m.add_vertex({std::cos(a1) + 1e-3, std::sin(a1) - 1e-3, 1.5});  // t1 off the quad's plane
  m.add_vertex({-5, -5, 1});
  m.add_vertex({5, -5, 1});
  m.add_vertex({0, 5, 1});
  std::vector<const Mesh*> one{&m};
  const boolean_detail::Soup soup = boolean_detail::make_soup(one);
  boolean_detail::Points pts(soup);
  const boolean_detail::Plane face = boolean_detail::Plane::of_triangle({5, 6, 7});
  auto lpi = [&](u32 p, u32 q) {
    boolean_detail::PointDef d;
    d.kind = boolean_detail::PointDef::Lpi;
    d.p = p;
    d.q = q;
    d.P[0] = face;
    return pts.add(d);
  };
  const u32 A = lpi(0, 1), M = lpi(0, 3), B = lpi(2, 3), M2 = lpi(0, 4), B2 = lpi(2, 4);
  for (u32 x : {M, M2, B2}) CHECK_FALSE(pts.is_double(x));  // the diagonal's cuts are not doubles
  CHECK(pts.collinear_by_definition(A, M, B));
  CHECK(pts.collinear_by_definition(B, A, M));
  CHECK(pts.orient2d(A, M, B, 2) == 0);
  CHECK(pts.orient2d(M, A, B, 2) == 0);
  CHECK_FALSE(pts.collinear_by_definition(A, M2, B2));
  CHECK(pts.orient2d(A, M2, B2, 2) != 0);
  CHECK(pts.orient2d(A, M2, B2, 2) == -pts.orient2d(M2, A, B2, 2));
  // On a plane by definition: the cuts lie on the face; A on every plane through its segment.
  CHECK(pts.on_plane(M, face));
  CHECK(pts.on_plane(A, boolean_detail::Plane::of_triangle({0, 1, 2})));
  CHECK_FALSE(pts.on_plane(M2, boolean_detail::Plane::of_triangle({0, 1, 2})));
  // Three TPIs on the face and on the quad's plane (each with a third plane of its own) are
  // collinear by two planes they all lie on; with the off-plane quad for one of them, not.
  auto tpi = [&](const boolean_detail::Plane& q, const boolean_detail::Plane& x) {
    boolean_detail::PointDef d;
    d.kind = boolean_detail::PointDef::Tpi;
    d.P[0] = face;
    d.P[1] = q;
    d.P[2] = x;
    return pts.add(d);
  };
  const auto quad = boolean_detail::Plane::of_triangle({0, 1, 3}), quad2 = boolean_detail::Plane::of_triangle({0, 1, 4});
  const u32 P1 = tpi(quad, boolean_detail::Plane::wall(5, 1, 2)), P2 = tpi(quad, boolean_detail::Plane::wall(6, 3, 2)),
            P3 = tpi(boolean_detail::Plane::of_triangle({2, 3, 0}), boolean_detail::Plane::wall(7, 0, 2)),
            P4 = tpi(quad2, boolean_detail::Plane::wall(7, 2, 2));
  CHECK(pts.collinear_by_definition(P1, P2, P3));  // {2, 3, 0} is the quad's plane too
  CHECK(pts.orient2d(P1, P2, P3, 2) == 0);
  CHECK_FALSE(pts.collinear_by_definition(P1, P2, P4));
  CHECK(pts.orient2d(P1, P2, P4, 2) != 0);
}

TEST_CASE("boolean: two edges that cross get one point definition from all four pairs of their triangles",
          "[boolean]") {
  // Edge p q (of triangles T, T') crosses edge r s (of U, U') at the origin. Each of the four pairs
  // (T or T', U or U') meets there; the point must come out as one definition, so that it is
  // interned once instead of being found equal to three others by exact arithmetic.
  Mesh m;
  const auto p = m.add_vertex({-1, 0, 0}), q = m.add_vertex({1, 0, 0}), c = m.add_vertex({0, 1, 1});
  const auto c2 = m.add_vertex({0.2, -1, 0.5});
  const auto r = m.add_vertex({0, 0.5, -0.5}), s = m.add_vertex({0, -0.5, 0.5}), w = m.add_vertex({0.5, 0.3, 0.2});
  const auto w2 = m.add_vertex({-0.5, 0.4, 0.1});
  const auto T = m.add_triangle(p, q, c), T2 = m.add_triangle(q, p, c2);
  const auto U = m.add_triangle(r, s, w), U2 = m.add_triangle(s, r, w2);
  std::vector<const Mesh*> one{&m};
  boolean_detail::Soup soup = boolean_detail::make_soup(one);
  boolean_detail::Points pts(soup);
  std::vector<boolean_detail::PointDef> at_origin;
  for (auto t : {T, T2})
    for (auto u : {U, U2}) {
      const boolean_detail::PairCut cut = boolean_detail::intersect_pair(pts, t, u);
      std::vector<boolean_detail::PointDef> ends = cut.points;
      for (const auto& sg : cut.segs_t) {
        ends.push_back(sg.a);
        ends.push_back(sg.b);
      }
      int found = 0;
      for (const auto& d : ends) {
        const auto id = pts.add(d);
        if (pts.approx(id).norm() == 0) {
          at_origin.push_back(d);
          ++found;
        }
      }
      INFO("pair " << t << ", " << u);
      REQUIRE(found == 1);
    }
  REQUIRE(at_origin.size() == 4);
  for (const auto& d : at_origin) {
    REQUIRE(d.kind == at_origin[0].kind);
    REQUIRE(d.p == at_origin[0].p);
    REQUIRE(d.q == at_origin[0].q);
    REQUIRE(d.P[0] == at_origin[0].P[0]);
  }
}

TEST_CASE("boolean points: a small part far from the origin gets cut points boxed tightly, and centroid tests that "
          "agree with exact arithmetic", "[boolean][points]") {
  // A part 1 wide at 1e8 (or -3e9): the distances of a segment's ends from a plane, computed as
  // n . p + d, cancel d's terms of the coordinates' size, and the filter's interval of the cut
  // point was as wide as the part (a union of four nearly coincident spheres at 1e8: 2 s in
  // double-double arithmetic, 0.1 s at the origin). As n . (p - a) they are as tight as at 0.
  std::mt19937_64 rng(40);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (double at : {0.0, 1e8, -3e9}) {
    INFO("at " << at);
    auto point = [&] { return Point3(at + u(rng), at + u(rng), at + u(rng)); };
    int lpi = 0, tpi = 0, centroid_tests = 0;
    for (int trial = 0; trial < 200; ++trial) {
      Mesh m;
      for (int i = 0; i < 9; ++i) m.positions.push_back(point());
      // Three triangles; the third's corners nearly on the line through the first two vertices
      // (for the centroid tests), a few ulps off it.
      m.positions[6] = m.positions[0] + (m.positions[1] - m.positions[0]) * 0.25;
      m.positions[7] = m.positions[0] + (m.positions[1] - m.positions[0]) * 0.5;
      m.positions[8] = m.positions[0] + (m.positions[1] - m.positions[0]) * 0.75;
      for (int k = 0; k < 3; ++k) m.positions[6 + k].z() = std::nextafter(m.positions[6 + k].z(), (k & 1) ? INFINITY : -INFINITY);
      m.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
      std::vector<const Mesh*> one{&m};
      const Soup soup = make_soup(one);
      Points pts(soup);
      auto tight = [&](u32 p) {
        const IntervalH h = pts.interval(p);
        REQUIRE((h.lo[3] > 0 || h.hi[3] < 0));
        // In ulps of the part's place (coordinates near 0 have ulps far finer than the part's): at
        // most 300 or so at every place; before, 1.6e10 at 1e8 and 4.4e11 at -3e9.
        const double ulp = std::ldexp(1.0, std::ilogb(std::max(std::abs(at), 1.0)) - 52);
        for (int i = 0; i < 3; ++i) {
          const double q[4] = {h.lo[i] / h.lo[3], h.lo[i] / h.hi[3], h.hi[i] / h.lo[3], h.hi[i] / h.hi[3]};
          const double width = (std::max({q[0], q[1], q[2], q[3]}) - std::min({q[0], q[1], q[2], q[3]})) / ulp;
          CHECK(width <= 1024);
        }
      };
      // A segment of the second triangle across the first's plane.
      const Plane P = Plane::of_triangle(soup.tris[0]);
      for (u32 a = 3; a < 6; ++a) {
        const u32 b = a == 5 ? 3 : a + 1;
        const int sa = pts.side(P, a), sb = pts.side(P, b);
        if (sa * sb >= 0) continue;
        // Not grazing: the ends well away from the plane, for a filter to be tight at all.
        const Vec3 n = (m.positions[1] - m.positions[0]).cross(m.positions[2] - m.positions[0]).normalized();
        if (std::abs(n.dot(m.positions[a] - m.positions[0])) < 0.05 || std::abs(n.dot(m.positions[b] - m.positions[0])) < 0.05)
          continue;
        PointDef d;
        d.kind = PointDef::Lpi;
        d.p = a;
        d.q = b;
        d.P[0] = P;
        tight(pts.add(d));
        ++lpi;
      }
      // The three triangles' planes meet in a point (where they are not nearly parallel).
      {
        PointDef d;
        d.kind = PointDef::Tpi;
        d.P[0] = P;
        d.P[1] = Plane::of_triangle(soup.tris[1]);
        d.P[2] = Plane::wall(0, 2, 2);
        const Vec3 n0 = (m.positions[1] - m.positions[0]).cross(m.positions[2] - m.positions[0]);
        const Vec3 n1 = (m.positions[4] - m.positions[3]).cross(m.positions[5] - m.positions[3]);
        const Vec3 n2 = (m.positions[2] - m.positions[0]).cross(Vec3(0, 0, 1));
        if (std::abs(n0.dot(n1.cross(n2))) > 0.1 * n0.norm() * n1.norm() * n2.norm()) {
          tight(pts.add(d));
          ++tpi;
        }
      }
      // orient2d(0, 1, centroid of 6 7 8) seen along z and side of the first plane of that
      // centroid, against exact rational arithmetic on the doubles.
      using Q = CGAL::Gmpq;
      auto q = [&](u32 v, int i) { return Q(m.positions[v][i]); };
      const std::array<u32, 3> t{6, 7, 8};
      {
        const Q cx = (q(6, 0) + q(7, 0) + q(8, 0)) / 3, cy = (q(6, 1) + q(7, 1) + q(8, 1)) / 3;
        const Q det = (q(1, 0) - q(0, 0)) * (cy - q(0, 1)) - (q(1, 1) - q(0, 1)) * (cx - q(0, 0));
        CHECK(pts.orient2d_centroid(0, 1, t, 2) == CGAL::sign(det));
      }
      {
        Q c[3], e1[3], e2[3];
        for (int i = 0; i < 3; ++i) {
          c[i] = (q(6, i) + q(7, i) + q(8, i)) / 3 - q(0, i);
          e1[i] = q(1, i) - q(0, i);
          e2[i] = q(2, i) - q(0, i);
        }
        const Q n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        CHECK(pts.side_centroid(P, t) == CGAL::sign(n[0] * c[0] + n[1] * c[1] + n[2] * c[2]));
      }
      ++centroid_tests;
    }
    CHECK(lpi > 100);
    CHECK(tpi > 100);
    CHECK(centroid_tests == 200);
  }
}
