// The course's views, checked by where known points land: the world axes' images under each
// projection against the closed forms (foreshortening of axonometric views, the receding axis of
// oblique views), vanishing points of perspective views, and rendered pictures of small cubes
// placed on the axes.
#include <catch2/catch.hpp>

#include <cmath>

#include "render/render.h"

using namespace wedge;
using namespace wedge::render;

namespace {


double rad(double d) { return d * kPi / 180; }

// A box [0,2]^3: the axes' unit vectors start at its corner.
Box3 cube_bounds() {
  Box3 b;
  b.extend(Point3(0, 0, 0));
  b.extend(Point3(2, 2, 2));
  return b;
}

struct Projector {
  Mat4 pv;
  explicit Projector(const Camera& c, const Box3& b, double aspect = 1) {
    CameraMatrices m = camera_matrices(c, b, aspect);
    pv = m.projection * m.view;
  }
  // Normalised device x, y of a point.
  Vec2 operator()(const Point3& p) const {
    Vec4 h = pv * p.homogeneous();
    return h.head<2>() / h.w();
  }
  // The image of the point at infinity in direction d: (x, y, w); w == 0 means no vanishing point.
  Vec3 direction(const Vec3& d) const {
    Vec4 h = pv * Vec4(d.x(), d.y(), d.z(), 0);
    return Vec3(h.x(), h.y(), h.w());
  }
  // The image of a unit step along world axis k from point p.
  Vec2 axis(int k, const Point3& p = Point3(1, 1, 1)) const { return (*this)(p + Vec3::Unit(k)) - (*this)(p); }
};

double angle_deg(const Vec2& v) { return std::atan2(v.y(), v.x()) * 180 / kPi; }

// The foreshortening of the world axes under axonometric(rx, ry), from the closed forms (in the
// front view's frame: world X is the view's x, world Z its y, world Y its -z).
Vec3 axonometric_lengths(double rx, double ry) {
  const double cx = std::cos(rad(rx)), sx = std::sin(rad(rx)), cy = std::cos(rad(ry)), sy = std::sin(rad(ry));
  return Vec3(std::sqrt(cy * cy + sx * sx * sy * sy), std::sqrt(sy * sy + cy * cy * sx * sx), cx);
}

}  // namespace

TEST_CASE("multiview views show two axes at full length and hide the third", "[render][views]") {
  const Box3 b = cube_bounds();
  struct Case {
    const char* name;
    int right, up, depth;  // world axes along the picture's +x, +y, and along the view
  } cases[] = {{"front", 0, 2, 1}, {"top", 0, 1, 2}, {"side", 1, 2, 0}};
  for (const auto& c : cases) {
    INFO(c.name);
    Projector P(named_view(c.name, b), b);
    const Vec2 r = P.axis(c.right), u = P.axis(c.up), d = P.axis(c.depth);
    CHECK(r.x() > 0);
    CHECK(std::abs(r.y()) < 1e-12);
    CHECK(u.y() > 0);
    CHECK(std::abs(u.x()) < 1e-12);
    CHECK(r.x() == Approx(u.y()).epsilon(1e-12));  // square pixels, aspect 1: equal scale
    CHECK(d.norm() < 1e-12);
  }
}

TEST_CASE("an isometric view foreshortens the three axes equally, their lines 120 degrees apart", "[render][views]") {
  const Box3 b = cube_bounds();
  for (const char* name : {"iso", "isometric"}) {
    Projector P(named_view(name, b), b);
    const Vec2 x = P.axis(0), y = P.axis(1), z = P.axis(2);
    CHECK(x.norm() == Approx(y.norm()).epsilon(1e-12));
    CHECK(x.norm() == Approx(z.norm()).epsilon(1e-12));
    CHECK(std::abs(z.x()) < 1e-12);  // vertical stays vertical
    CHECK(z.y() > 0);
    // The axis lines meet at 120 degrees: +X at -30, +Y (receding) at +30, +Z at 90 degrees.
    CHECK(x.dot(z) / (x.norm() * z.norm()) == Approx(-0.5).epsilon(1e-12));
    CHECK(y.dot(z) / (y.norm() * z.norm()) == Approx(0.5).epsilon(1e-12));
    CHECK(x.dot(y) / (x.norm() * y.norm()) == Approx(0.5).epsilon(1e-12));
    // The right-hand face (+X) turns towards the viewer: X runs down to the right, Y up to the right.
    CHECK(x.x() > 0);
    CHECK(x.y() < 0);
    CHECK(y.x() > 0);
    CHECK(y.y() > 0);
    // The matrix alone: each world axis (in the front view's frame) has length sqrt(2/3).
    const Mat4 m = axonometric(std::asin(std::tan(rad(30))) * 180 / kPi, -45);
    for (const Vec3& a : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)})
      CHECK((m.block<3, 3>(0, 0) * a).head<2>().norm() == Approx(std::sqrt(2.0 / 3)).epsilon(1e-12));
  }
}

TEST_CASE("dimetric and trimetric views foreshorten the axes as the closed forms say", "[render][views]") {
  const Box3 b = cube_bounds();
  {
    // The default dimetric: X and Z whole, the receding Y at half.
    Projector P(named_view("dimetric", b), b);
    const double x = P.axis(0).norm(), y = P.axis(1).norm(), z = P.axis(2).norm();
    CHECK(x == Approx(z).epsilon(1e-12));
    CHECK(y == Approx(0.5 * x).epsilon(1e-12));
  }
  {
    // dimetric with rx given: ry = -45 makes X and Y equal, Z as cos rx says.
    ViewParams p;
    p.rx = 25;
    Projector P(named_view("dimetric", b, p), b);
    const Vec3 L = axonometric_lengths(25, -45);
    CHECK(P.axis(0).norm() == Approx(P.axis(1).norm()).epsilon(1e-12));
    CHECK(P.axis(2).norm() / P.axis(0).norm() == Approx(L.z() / L.x()).epsilon(1e-12));
  }
  for (auto [rx, ry] : {std::pair{20.0, -30.0}, std::pair{10.0, -60.0}, std::pair{40.0, 15.0}}) {
    ViewParams p;
    p.rx = rx, p.ry = ry;
    Projector P(named_view("trimetric", b, p), b);
    const Vec3 L = axonometric_lengths(rx, ry);
    INFO("rx " << rx << " ry " << ry);
    CHECK(P.axis(0).norm() / P.axis(2).norm() == Approx(L.x() / L.z()).epsilon(1e-12));
    CHECK(P.axis(1).norm() / P.axis(2).norm() == Approx(L.y() / L.z()).epsilon(1e-12));
    // the three differ: a trimetric view
    CHECK(std::abs(L.x() - L.y()) > 0.01);
    CHECK(std::abs(L.y() - L.z()) > 0.01);
  }
}

TEST_CASE("a cabinet view draws the receding axis at half length and at the given angle", "[render][views]") {
  const Box3 b = cube_bounds();
  for (double angle : {45.0, 30.0, 60.0}) {
    ViewParams p;
    p.angle = angle;
    for (auto [name, ratio] : {std::pair{"cabinet", 0.5}, std::pair{"cavalier", 1.0}}) {
      INFO(name << " angle " << angle);
      Projector P(named_view(name, b, p), b);
      const Vec2 x = P.axis(0), y = P.axis(1), z = P.axis(2);
      // The picture plane's axes at full length, undistorted.
      CHECK(std::abs(x.y()) < 1e-12);
      CHECK(std::abs(z.x()) < 1e-12);
      CHECK(x.x() == Approx(z.y()).epsilon(1e-12));
      // The receding axis: `ratio` of the full length, at `angle` from the picture's x axis.
      CHECK(y.norm() / x.norm() == Approx(ratio).epsilon(1e-12));
      CHECK(angle_deg(y) == Approx(angle).epsilon(1e-12));
      // The same point lands at the same place wherever the step starts (a parallel projection).
      CHECK((P.axis(1, Point3(0, 0, 0)) - y).norm() < 1e-12);
    }
  }
  // "oblique" takes its ratio, by default the cabinet's; the shear matrix itself moves a point one
  // unit deep by ratio * (cos, sin) of the angle.
  ViewParams p;
  p.ratio = 0.75, p.angle = 45;
  Projector P(named_view("oblique", b, p), b);
  CHECK(P.axis(1).norm() / P.axis(0).norm() == Approx(0.75).epsilon(1e-12));
  const Vec4 q = oblique(30, 0.5) * Vec4(0, 0, -1, 1);
  CHECK(q.x() == Approx(0.5 * std::cos(rad(30))).epsilon(1e-15));
  CHECK(q.y() == Approx(0.5 * std::sin(rad(30))).epsilon(1e-15));
  CHECK(q.z() == -1);
}

TEST_CASE("perspective views have one, two and three vanishing points", "[render][views]") {
  const Box3 b = cube_bounds();
  auto finite = [](const Vec3& h) { return std::abs(h.z()) > 1e-9; };
  {
    // One-point: X and Z edges stay parallel to the image axes, Y edges converge to one point.
    Projector P(named_view("one_point", b), b);
    CHECK_FALSE(finite(P.direction(Vec3::UnitX())));
    CHECK_FALSE(finite(P.direction(Vec3::UnitZ())));
    REQUIRE(finite(P.direction(Vec3::UnitY())));
    for (const Point3& p : {Point3(0, 0, 0), Point3(0, 2, 0), Point3(2, 2, 2), Point3(0, 0, 2)}) {
      const Vec2 x = P(p + Vec3(2, 0, 0)) - P(p), z = P(p + Vec3(0, 0, 2)) - P(p);
      CHECK(std::abs(x.y()) < 1e-12 * x.norm());  // horizontal
      CHECK(std::abs(z.x()) < 1e-12 * z.norm());  // vertical
    }
    // The four Y edges of the cube meet at the vanishing point.
    const Vec3 h = P.direction(Vec3::UnitY());
    const Vec2 vp = h.head<2>() / h.z();
    for (const Point3& p : {Point3(0, 0, 0), Point3(2, 0, 0), Point3(0, 0, 2), Point3(2, 0, 2)}) {
      const Vec2 a = P(p), e = P(p + Vec3(0, 2, 0));
      const Vec2 u = e - a, w = vp - a;
      CHECK(std::abs(u.x() * w.y() - u.y() * w.x()) < 1e-12 * u.norm() * w.norm());  // collinear
      CHECK(u.dot(w) > 0);  // towards it
    }
    // The top and the right-hand side show: the eye is above and to the right of the cube.
    CHECK(P(Point3(2, 2, 2)).y() > P(Point3(2, 0, 2)).y());
  }
  {
    // Two-point: verticals stay vertical; X and Y each have a vanishing point, both on the horizon.
    Projector P(named_view("two_point", b), b);
    CHECK_FALSE(finite(P.direction(Vec3::UnitZ())));
    const Vec3 hx = P.direction(Vec3::UnitX()), hy = P.direction(Vec3::UnitY());
    REQUIRE(finite(hx));
    REQUIRE(finite(hy));
    CHECK(hx.y() / hx.z() == Approx(hy.y() / hy.z()).epsilon(1e-9));
    for (const Point3& p : {Point3(0, 0, 0), Point3(2, 2, 0), Point3(2, 0, 0)}) {
      const Vec2 z = P(p + Vec3(0, 0, 2)) - P(p);
      CHECK(std::abs(z.x()) < 1e-12 * z.norm());
    }
    // angle= turns the view: at 45 degrees the two vanishing points are symmetric about the centre line.
    ViewParams q;
    q.angle = 45;
    Projector Q(named_view("two_point", b, q), b);
    const Vec3 qx = Q.direction(Vec3::UnitX()), qy = Q.direction(Vec3::UnitY());
    const Vec3 c = Q.direction(Vec3(-1, 1, 0).normalized());  // the view direction: the principal point
    CHECK(qx.x() / qx.z() - c.x() / c.z() == Approx(c.x() / c.z() - qy.x() / qy.z()).epsilon(1e-9));
  }
  {
    // Three-point: no principal axis is parallel to the picture.
    Projector P(named_view("three_point", b), b);
    for (int k = 0; k < 3; ++k) CHECK(finite(P.direction(Vec3::Unit(k))));
    const Vec2 z0 = P(Point3(0, 0, 2)) - P(Point3(0, 0, 0)), z1 = P(Point3(2, 2, 2)) - P(Point3(2, 2, 0));
    CHECK(std::abs(z0.x() * z1.y() - z0.y() * z1.x()) > 1e-6 * z0.norm() * z1.norm());  // verticals converge
  }
}

TEST_CASE("a view's options are checked", "[render][views]") {
  const Box3 b = cube_bounds();
  ViewParams angle;
  angle.angle = 30;
  CHECK_THROWS_WITH(named_view("iso", b, angle), Catch::Contains("view 'iso' takes no angle"));
  CHECK_THROWS_WITH(named_view("perspective", b), Catch::Contains("unknown view 'perspective'"));
  ViewParams steep;
  steep.rx = 95;
  CHECK_THROWS_WITH(named_view("trimetric", b, steep), Catch::Contains("rx must be within -89..89"));
  ViewParams flat;
  flat.ratio = 0;
  CHECK_THROWS_WITH(named_view("oblique", b, flat), Catch::Contains("ratio"));
  ViewParams near;
  near.distance = 1;
  CHECK_THROWS_WITH(named_view("one_point", b, near), Catch::Contains("distance must be within"));
}

namespace {

// A small cube of half-size h centred at c.
Mesh small_cube(const Point3& c, double h) {
  Mesh m;
  for (int i = 0; i < 8; ++i) m.add_vertex(c + Vec3(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h));
  const int f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (auto& t : f) m.add_triangle(t[0], t[1], t[2]);
  return m;
}

// The centroid (x right, y up) of the pixels of exactly this colour.
Vec2 centroid(const Image& im, std::array<std::uint8_t, 3> rgb) {
  double sx = 0, sy = 0;
  long n = 0;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      auto p = im.pixel(x, y);
      if (p[0] == rgb[0] && p[1] == rgb[1] && p[2] == rgb[2]) sx += x, sy += im.height - 1 - y, ++n;
    }
  REQUIRE(n > 0);
  return Vec2(sx / n, sy / n);
}

// Cubes at the origin and two units along X, Y and Z, each emitting its own colour, drawn with
// the named view; returns the images of the three axis steps in pixels.
std::array<Vec2, 3> rendered_axes(const std::string& view, const ViewParams& p = {}) {
  const Point3 at[4] = {Point3(0, 0, 0), Point3(2, 0, 0), Point3(0, 2, 0), Point3(0, 0, 2)};
  const std::array<std::uint8_t, 3> colour[4] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 0, 255}};
  std::vector<Mesh> meshes;
  for (const auto& c : at) meshes.push_back(small_cube(c, 0.08));
  std::vector<DrawItem> items(4);
  Box3 bounds;
  for (int i = 0; i < 4; ++i) {
    items[i].mesh = &meshes[i];
    items[i].material.ambient = items[i].material.diffuse = Vec4f(0, 0, 0, 1);
    items[i].material.emission = Vec4f(colour[i][0] / 255.f, colour[i][1] / 255.f, colour[i][2] / 255.f, 1);
    for (const auto& q : meshes[i].positions) bounds.extend(q);
  }
  RenderOptions o;
  o.width = 400, o.height = 400;
  o.camera = named_view(view, bounds, p);
  o.threads = 1;
  Image im = render_scene(items, o);
  const Vec2 origin = centroid(im, colour[0]);
  return {centroid(im, colour[1]) - origin, centroid(im, colour[2]) - origin, centroid(im, colour[3]) - origin};
}

}  // namespace

TEST_CASE("rendered pictures put points where the projections say", "[render][views]") {
  // Each small cube's picture is centrally symmetric about the image of its centre under a
  // parallel projection, so the pixel centroids measure the axes' images to a fraction of a pixel.
  {
    auto [x, y, z] = rendered_axes("cabinet");
    CHECK(std::abs(x.y()) < 0.5);
    CHECK(std::abs(z.x()) < 0.5);
    CHECK(x.x() == Approx(z.y()).epsilon(0.01));
    CHECK(y.norm() / x.norm() == Approx(0.5).epsilon(0.01));
    CHECK(angle_deg(y) == Approx(45).margin(0.5));
  }
  {
    ViewParams p;
    p.angle = 30;
    auto [x, y, z] = rendered_axes("cavalier", p);
    CHECK(y.norm() / x.norm() == Approx(1.0).epsilon(0.01));
    CHECK(angle_deg(y) == Approx(30).margin(0.5));
  }
  {
    auto [x, y, z] = rendered_axes("iso");
    CHECK(x.norm() == Approx(z.norm()).epsilon(0.01));
    CHECK(y.norm() == Approx(z.norm()).epsilon(0.01));
    CHECK(angle_deg(z) == Approx(90).margin(0.5));
    CHECK(angle_deg(x) == Approx(-30).margin(0.5));
    CHECK(angle_deg(y) == Approx(30).margin(0.5));
  }
  {
    // One-point perspective: the cubes on X and Z sit level with and straight above the origin's.
    auto [x, y, z] = rendered_axes("one_point");
    CHECK(std::abs(x.y()) < 0.5);
    CHECK(std::abs(z.x()) < 0.5);
    CHECK(y.norm() > 5);  // depth shows
  }
}
