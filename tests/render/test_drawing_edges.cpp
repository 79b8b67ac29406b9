// Drawing sheets' edges: feature edges of a mesh, polylines joined from segments, and edges drawn
// over the shaded faces with the hidden ones left out or dashed.
#include <catch2/catch.hpp>

#include "render/render.h"

using namespace wedge;
using namespace wedge::render;

namespace {

// An axis-aligned box from lo to hi, 12 triangles, no face ids.
Mesh box_mesh(const Point3& lo, const Point3& hi) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.add_vertex(Point3(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()));
  const int f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (auto& t : f) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

int count(const Image& im, std::array<std::uint8_t, 3> rgb, int x0 = 0, int x1 = 1 << 30) {
  int n = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = std::max(0, x0); x < std::min(im.width, x1); ++x) {
      auto p = im.pixel(x, y);
      n += p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2];
    }
  return n;
}

}  // namespace

TEST_CASE("a box's feature edges are its 12 edges, the face diagonals are not", "[render][drawing][edges]") {
  const Mesh m = box_mesh(Point3(0, 0, 0), Point3(1, 2, 3));
  const auto e = feature_edges(m, 30);
  REQUIRE(e.size() == 12);
  double length = 0;
  for (const auto& s : e) length += (s[1] - s[0]).norm();
  CHECK(length == Approx(4 * (1 + 2 + 3)));
  // Joined into polylines, every segment is used once.
  const auto lines = polylines(e);
  std::size_t segments = 0;
  for (const auto& l : lines) segments += l.size() - 1;
  CHECK(segments == 12);
  // With face ids, edges between triangles of one face are not features, whatever their angle:
  // a two-triangle "face" folded at 90 degrees gives only its outline.
  Mesh fold;
  for (const Point3& p : {Point3(0, 0, 0), Point3(1, 0, 0), Point3(1, 1, 0), Point3(1, 1, 1)}) fold.add_vertex(p);
  fold.add_triangle(0, 1, 2, 7);
  fold.add_triangle(2, 1, 3, 7);
  CHECK(feature_edges(fold, 30).size() == 4);  // the outline; the shared edge 1-2 is not a feature
  fold.face_ids = {7, 8};
  CHECK(feature_edges(fold, 30).size() == 5);
}

TEST_CASE("a drawing draws visible edges and leaves out or dashes the hidden ones", "[render][drawing][edges]") {
  // A wide box in front and a small one straight behind it: in the front view the small box is
  // wholly hidden, its outline only a hidden edge.
  const Mesh front = box_mesh(Point3(0, 0, 0), Point3(4, 1, 2));
  const Mesh back = box_mesh(Point3(1.5, 3, 0.5), Point3(2.5, 4, 1.5));
  std::vector<DrawItem> items(2);
  items[0].mesh = &front, items[1].mesh = &back;
  for (auto& it : items) it.material.diffuse = it.material.ambient = Vec4f(0.2f, 0.6f, 0.3f, 1);
  DrawingOptions o;
  o.views = {"front"};
  o.width = 300, o.height = 200;
  o.labels = false, o.border = false;
  const std::array<std::uint8_t, 3> ink{20, 20, 20}, hidden{150, 150, 150};

  Image removed = render_drawing(items, o);
  CHECK(count(removed, hidden) == 0);
  const int outline = count(removed, ink);
  // The front box's outline: its 4 x 2 rectangle, drawn all round (the window fits it to about
  // 88% of the 300-pixel width, so its perimeter is some 790 pixels).
  CHECK(outline > 600);
  CHECK(outline < 1000);

  o.hidden_dashed = true;
  Image dashed = render_drawing(items, o);
  CHECK(count(dashed, ink) == outline);  // the visible edges do not change
  // The hidden square (1 x 1 in a 4-wide picture: some 66 pixels a side) is dashed: 4 on, 3 off,
  // so about 4/7 of its perimeter, all of it in the middle quarter of the picture's width.
  const int h = count(dashed, hidden);
  CHECK(h > 0.4 * 4 * 60);
  CHECK(h < 0.7 * 4 * 75);
  CHECK(count(dashed, hidden, 0, 100) == 0);
  CHECK(count(dashed, hidden, 200, 300) == 0);

  o.edges = false;
  Image none = render_drawing(items, o);
  CHECK(count(none, ink) == 0);
  CHECK(count(none, hidden) == 0);
}

namespace {

// A cylinder of radius 1 from z = 0 to 2 made as a solid's shading mesh is: two half-cylinder
// faces (ids 0 and 1, seams at (1, 0) and (-1, 0)) and two caps (ids 2 and 3), each face with its
// own vertices and its surface's normals, `n` segments round.
Mesh split_cylinder(int n) {
  Mesh m;
  auto ring = [&](int i) { const double a = 2 * 3.14159265358979323846 * (i % n) / n; return Vec2(std::cos(a), std::sin(a)); };
  auto vertex = [&](const Vec2& xy, double z, const Vec3& normal) {
    m.normals.push_back(normal);
    return m.add_vertex(Point3(xy.x(), xy.y(), z));
  };
  for (int face = 0; face < 2; ++face)
    for (int i = face * n / 2; i < (face + 1) * n / 2; ++i) {
      const Vec2 p = ring(i), q = ring(i + 1);
      const Vec3 np(p.x(), p.y(), 0), nq(q.x(), q.y(), 0);
      const auto b0 = vertex(p, 0, np), b1 = vertex(q, 0, nq), t0 = vertex(p, 2, np), t1 = vertex(q, 2, nq);
      m.add_triangle(b0, b1, t1, face);
      m.add_triangle(b0, t1, t0, face);
    }
  for (int cap = 0; cap < 2; ++cap) {
    const double z = cap == 0 ? 2 : 0;
    const Vec3 normal(0, 0, cap == 0 ? 1 : -1);
    const auto c = vertex(Vec2(0, 0), z, normal);
    for (int i = 0; i < n; ++i) {
      const auto a = vertex(ring(i), z, normal), b = vertex(ring(i + 1), z, normal);
      if (cap == 0) m.add_triangle(c, a, b, 2);
      else m.add_triangle(c, b, a, 3);
    }
  }
  return m;
}

}  // namespace

TEST_CASE("a drawing leaves out the seam between two faces that meet tangentially", "[render][drawing][edges]") {
  const Mesh cyl = split_cylinder(32);
  // The two cap circles are the only sharp edges; the two seams down the side join faces whose
  // normals are the same along them. A wireframe keeps the seams (edges of the solid's faces).
  CHECK(feature_edges(cyl, 30).size() == 2 * 32 + 2);
  CHECK(feature_edges(cyl, 30, false).size() == 2 * 32);
  // A box made the same way (each face its own vertices and its plane's normal) keeps all 12
  // edges: its faces meet at 90 degrees.
  Mesh box = box_mesh(Point3(0, 0, 0), Point3(1, 2, 3));
  Mesh split;
  for (std::size_t t = 0; t < box.triangles.size(); ++t) {
    const Vec3 normal = box.triangle_normal(t).normalized();
    std::uint32_t v[3];
    for (int k = 0; k < 3; ++k) v[k] = split.add_vertex(box.positions[box.triangles[t][k]]), split.normals.push_back(normal);
    split.add_triangle(v[0], v[1], v[2], std::int32_t(t / 2));
  }
  CHECK(feature_edges(split, 30, false).size() == 12);

  // The side view looks along x, so the seam at (1, 0) runs down the middle of the picture: it
  // drew a line of ink from top to bottom there. Now the middle columns hold only the caps'
  // edges (the picture's top and bottom lines).
  std::vector<DrawItem> items(1);
  items[0].mesh = &cyl;
  DrawingOptions o;
  o.views = {"side"};
  o.width = 200, o.height = 200;
  o.labels = false, o.border = false;
  const Image im = render_drawing(items, o);
  const std::array<std::uint8_t, 3> ink{20, 20, 20};
  REQUIRE(count(im, ink) > 200);  // the outline is drawn
  int rows = 0;  // rows with ink in the middle ten columns: some 150 with the seam, a few without
  for (int y = 0; y < im.height; ++y) {
    bool inked = false;
    for (int x = 95; x < 105; ++x) {
      auto p = im.pixel(x, y);
      inked = inked || (p[0] == 20 && p[1] == 20 && p[2] == 20);
    }
    rows += inked;
  }
  CHECK(rows < 8);
}
