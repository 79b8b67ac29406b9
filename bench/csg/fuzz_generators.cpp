// The boolean fuzzer's cases (see fuzz_boolean.cpp): seeded generators of adversarial operands,
// each a function of the random stream only, so that `--gen NAME --seed N --cases 1` makes the
// same case again with the same build (several draws in one call's arguments, such as
// Vec3(uni(r, ..), uni(r, ..), ..), are made in the compiler's order). Operands come from the
// tests' support library (boxes, spheres, cylinders, grid boxes), the shapes below (tetrahedra,
// prisms, tori) and the tessellator (curved B-Rep solids), moved by exact and inexact transforms.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "bench/csg/fuzz_boolean.h"
#include "brep/brep.h"
#include "kernel/transform.h"
#include "tessellate/brep_mesh.h"
#include "tests/support/boolean_cases.h"

namespace wedge::fuzz {

using namespace wedge::testing;

// ---------------------------------------------------------------- mesh helpers
Vec3 rand_dir(Rng& r) {
  for (;;) {  // uniform in a spherical shell, so uniform in direction
    const Vec3 v(uni(r, -1, 1), uni(r, -1, 1), uni(r, -1, 1));
    if (v.norm() > 0.1 && v.norm() <= 1) return v.normalized();
  }
}
Mesh rot(const Mesh& m, double deg, const Vec3& axis, const Point3& pivot) { return m.transformed(rotate(deg, axis, pivot)); }
Mesh moved(const Mesh& m, const Vec3& d) {
  Mesh o = m;
  for (auto& p : o.positions) p += d;
  return o;
}
Mesh scaled_pow2(const Mesh& m, int e) {
  Mesh o = m;
  for (auto& p : o.positions) p = Vec3(std::ldexp(p.x(), e), std::ldexp(p.y(), e), std::ldexp(p.z(), e));
  return o;
}
Mesh flipped(const Mesh& m) {
  Mesh o = m;
  for (auto& t : o.triangles) std::swap(t[1], t[2]);
  return o;
}
Vec3 vertex_mean(const Mesh& m) {
  Vec3 c = Vec3::Zero();
  for (const auto& p : m.positions) c += p;
  return m.positions.empty() ? c : Vec3(c / static_cast<double>(m.positions.size()));
}

namespace {

constexpr double kPi = std::numbers::pi;

Mesh ulp_shift(const Mesh& m, int k, const Vec3& dir) {  // each coordinate k ulps toward sign(dir)
  Mesh o = m;
  for (auto& p : o.positions)
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < k; ++i)
        if (dir[c] != 0) p[c] = std::nextafter(p[c], dir[c] > 0 ? INFINITY : -INFINITY);
  return o;
}
Mesh jitter_ulps(const Mesh& m, int k, Rng& r) {  // each coordinate up to k ulps either way
  Mesh o = m;
  for (auto& p : o.positions)
    for (int c = 0; c < 3; ++c) {
      const int n = irand(r, -k, k);
      for (int i = 0; i < std::abs(n); ++i) p[c] = std::nextafter(p[c], n > 0 ? INFINITY : -INFINITY);
    }
  return o;
}
Mesh snapped(const Mesh& m, double grid) {
  Mesh o = m;
  for (auto& p : o.positions)
    for (int c = 0; c < 3; ++c) p[c] = std::round(p[c] / grid) * grid;
  return o;
}
// A tetrahedron, outward whatever the order of the corners (none coplanar).
Mesh tetra(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  if ((b - a).cross(c - a).dot(d - a) > 0) std::swap(b, c);
  Mesh m;
  m.add_vertex(a), m.add_vertex(b), m.add_vertex(c), m.add_vertex(d);
  m.add_triangle(0, 1, 2), m.add_triangle(0, 3, 1), m.add_triangle(1, 3, 2), m.add_triangle(0, 2, 3);
  return m;
}
// A prism over a convex polygon (counter-clockwise in xy) from z0 to z1, caps fanned from vertex 0
// (skinny triangles for many nearly collinear points) or from a centre vertex.
Mesh prism(const std::vector<Vec2>& poly, double z0, double z1, bool centre_fan) {
  Mesh m;
  const std::uint32_t n = static_cast<std::uint32_t>(poly.size());
  for (const auto& p : poly) m.add_vertex({p.x(), p.y(), z0});
  for (const auto& p : poly) m.add_vertex({p.x(), p.y(), z1});
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.add_triangle(i, j, n + j), m.add_triangle(i, n + j, n + i);
  }
  if (centre_fan) {
    Vec2 c(0, 0);
    for (const auto& p : poly) c += p;
    c /= static_cast<double>(n);
    const auto b = m.add_vertex({c.x(), c.y(), z0}), t = m.add_vertex({c.x(), c.y(), z1});
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t j = (i + 1) % n;
      m.add_triangle(b, j, i), m.add_triangle(t, n + i, n + j);
    }
  } else {
    for (std::uint32_t i = 1; i + 1 < n; ++i) m.add_triangle(0, i + 1, i), m.add_triangle(n, n + i, n + i + 1);
  }
  return m;
}
// The regular n-gon of radius `radius` about the origin, counter-clockwise.
std::vector<Vec2> regular_polygon(int n, double radius) {
  std::vector<Vec2> poly;
  for (int i = 0; i < n; ++i) poly.push_back(radius * Vec2(std::cos(2 * kPi * i / n), std::sin(2 * kPi * i / n)));
  return poly;
}

// A convex operand in general position near the origin: a turned box, an icosphere, a turned
// cylinder, a UV sphere, a grid box or a tetrahedron, about `size` across.
Mesh random_primitive(Rng& r, double size = 1) {
  const Vec3 c(uni(r, -0.5, 0.5) * size, uni(r, -0.5, 0.5) * size, uni(r, -0.5, 0.5) * size);
  switch (irand(r, 0, 5)) {
    case 0: return box_mesh(c, Vec3(uni(r, 0.3, 1.2), uni(r, 0.3, 1.2), uni(r, 0.3, 1.2)) * size,
                            rotate(uni(r, 0, 360), rand_dir(r), c));
    case 1: return icosphere(c, uni(r, 0.3, 0.9) * size, coin(r) ? 80 : 320);
    case 2: return cylinder_mesh(uni(r, 0.2, 0.7) * size, -0.6 * size, 0.6 * size, irand(r, 3, 8),
                                 translate(c) * rotate(uni(r, 0, 360), rand_dir(r)));
    case 3: return uv_sphere(c, uni(r, 0.3, 0.9) * size, irand(r, 24, 200));
    case 4: return grid_box(c, c + Vec3(uni(r, 0.3, 1), uni(r, 0.3, 1), uni(r, 0.3, 1)) * size, irand(r, 1, 4));
    default: {
      Vec3 a = c, b = c + rand_dir(r) * size, d = c + rand_dir(r) * size, e = c + rand_dir(r) * size;
      if (std::abs((b - a).cross(d - a).dot(e - a)) < 0.05 * size * size * size) return box_mesh(c, Vec3(size, size, size));
      return tetra(a, b, d, e);
    }
  }
}

// ---------------------------------------------------------------- generators
// Axis-parallel boxes with integer corners in [0, 4]: shared faces, edges, vertices, T-junctions.
Case gen_grid_boxes(Rng& r) {
  Case c;
  c.axis_boxes = true;
  const int n = irand(r, 2, 5);
  for (int i = 0; i < n; ++i) {
    Vec3 lo(irand(r, 0, 3), irand(r, 0, 3), irand(r, 0, 3));
    Vec3 hi = lo + Vec3(ir(r, 1, 3), ir(r, 1, 3), ir(r, 1, 3));
    if (coin(r, 0.3)) lo *= 0.5, hi *= 0.5;  // half grid: more partial coincidence
    c.boxes.push_back({lo, hi});
    c.ops.push_back(coin(r, 0.4) ? grid_box(lo, hi, irand(r, 2, 4)) : box_mesh(lo, hi - lo));
  }
  return c;
}
// Grid shapes that are not boxes: snapped low-poly spheres and cylinders, boxes turned 90 / 45
// degrees about grid points, tetrahedra and prisms on integer corners (sloped exact coplanarity).
Case gen_grid_mixed(Rng& r) {
  Case c;
  const int n = irand(r, 2, 4);
  for (int i = 0; i < n; ++i) {
    const Vec3 g(irand(r, 0, 3), irand(r, 0, 3), irand(r, 0, 3));
    switch (irand(r, 0, 4)) {
      case 0: c.ops.push_back(snapped(icosphere(g, irand(r, 2, 4), 80), coin(r) ? 1.0 : 0.5)); break;
      case 1: c.ops.push_back(snapped(cylinder_mesh(irand(r, 1, 3), 0, irand(r, 1, 4), irand(r, 3, 8),
                                                    translate(g) * rotate(90.0 * irand(r, 0, 3), Vec3::UnitX())), 0.5));
        break;
      case 2: c.ops.push_back(box_mesh(g, Vec3(ir(r, 1, 3), ir(r, 1, 3), ir(r, 1, 3)),
                                       rotate(coin(r) ? 45.0 : 90.0, Vec3::Unit(irand(r, 0, 2)), g)));
        break;
      case 3: {
        Vec3 p[4];
        for (auto& q : p) q = g + Vec3(ir(r, -2, 2), ir(r, -2, 2), ir(r, -2, 2));
        if ((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) == 0) p[3] += Vec3(1, 1, 1);
        if ((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) == 0) p[3] = p[0] + Vec3(0, 0, 1), p[1] = p[0] + Vec3(1, 0, 0), p[2] = p[0] + Vec3(0, 1, 0);
        c.ops.push_back(tetra(p[0], p[1], p[2], p[3]));
        break;
      }
      default: {
        std::vector<Vec2> poly = {{0, 0}, {2, 0}, {3, 1}, {2, 2}, {0, 2}};
        for (auto& q : poly) q += Vec2(g.x(), g.y());
        c.ops.push_back(prism(poly, g.z(), g.z() + irand(r, 1, 3), coin(r)));
      }
    }
  }
  return c;
}
// A mesh (sometimes 1e3 from the origin) and one to four copies that nearly coincide with it:
// moved by 1-3 ulps per coordinate, by 1e-12, by 2^-40 .. 2^-52 along x, turned by 1e-9 .. 3e-9
// rad or up to 1e-6 degrees, vertices jittered by up to 3 ulps, or mirrored in a plane through
// its centre.
Case gen_near_copy(Rng& r) {
  Case c;
  Mesh a = random_primitive(r);
  if (coin(r, 0.3)) a = moved(a, Vec3(uni(r, -1e3, 1e3), uni(r, -1e3, 1e3), 0));
  c.ops.push_back(a);
  const int k = irand(r, 1, 3);
  const int nc = coin(r, 0.3) ? irand(r, 2, 4) : 1;
  const Vec3 ctr = vertex_mean(a);
  for (int i = 0; i < nc; ++i) {
    const int how = irand(r, 0, 6);
    c.note += std::to_string(how);
    switch (how) {
      case 0: c.ops.push_back(ulp_shift(a, k, Vec3(ir(r, -1, 1), ir(r, -1, 1), ir(r, -1, 1)))); break;
      case 1: c.ops.push_back(moved(a, rand_dir(r) * 1e-12)); break;
      case 2: c.ops.push_back(rot(a, 1e-9 * 180 / kPi * irand(r, 1, 3), rand_dir(r), coin(r) ? ctr : a.positions[0])); break;
      case 3: c.ops.push_back(jitter_ulps(a, k, r)); break;
      case 4: c.ops.push_back(a.transformed(reflect(rand_dir(r), ctr))); break;
      case 5: c.ops.push_back(rot(a, uni(r, -1e-6, 1e-6), rand_dir(r), ctr)); break;
      default: c.ops.push_back(moved(a, Vec3(std::ldexp(1.0, -irand(r, 40, 52)), 0, 0))); break;
    }
  }
  if (c.ops.size() == 2 && coin(r, 0.3)) std::swap(c.ops[0], c.ops[1]);
  return c;
}
// Exact contact: shared faces, flush pockets, nesting that touches at a vertex or an edge, shared
// edges or vertices only, a sphere's vertex on a box's corner, stacked grid boxes; built on
// integers, sometimes with a third box on the grid, then moved by an exact transform (an integer
// shift with a power-of-two scale, a mirror) or one inexact rotation for all.
Case gen_touching(Rng& r) {
  Case c;
  const int kind = irand(r, 0, 7);
  c.note = std::to_string(kind);
  Mesh a, b;
  switch (kind) {
    case 0: a = box_mesh({0, 0, 0}, {2, 2, 2}), b = box_mesh({2, ir(r, -1, 1), ir(r, -1, 1)}, {2, 2, 2}); break;  // faces
    case 1: a = box_mesh({0, 0, 0}, {4, 4, 4}), b = box_mesh({1, 1, ir(r, 2, 3)}, {2, 2, ir(r, 1, 3)}); break;   // pocket
    case 2: a = box_mesh({0, 0, 0}, {4, 4, 4}), b = tetra({0, 0, 0}, {1, 1, 2}, {2, 1, 1}, {1, 2, 1}); break;        // inside at vertex
    case 3: a = box_mesh({0, 0, 0}, {4, 4, 4}), b = tetra({0, 0, 0}, {2, 0, 0}, {1, 1, 1}, {1, 2, 1}); break;        // inside at edge
    case 4: a = box_mesh({0, 0, 0}, {2, 2, 2}), b = box_mesh({2, 2, ir(r, -1, 1)}, {2, 2, 2}); break;              // edge
    case 5: a = box_mesh({0, 0, 0}, {2, 2, 2}), b = box_mesh({2, 2, 2}, {2, 2, 2}); break;                            // vertex
    case 6: {  // a unit box on the far side of a sphere's vertex in every coordinate: vertex-vertex contact
      a = icosphere({0, 0, 0}, 2, 80);
      const Vec3 v = a.positions[irand(r, 0, static_cast<int>(a.positions.size()) - 1)];
      b = box_mesh(v - Vec3(v.x() >= 0 ? 0 : 1, v.y() >= 0 ? 0 : 1, v.z() >= 0 ? 0 : 1), {1, 1, 1});
      break;
    }
    default: a = grid_box({0, 0, 0}, {4, 4, 4}, irand(r, 2, 4)), b = grid_box({ir(r, 0, 2), ir(r, 0, 2), 4}, {4, 4, 6}, irand(r, 1, 3)); break;
  }
  std::vector<Mesh> ms = {a, b};
  if (coin(r, 0.3)) ms.push_back(box_mesh({ir(r, -1, 3), ir(r, -1, 3), ir(r, -1, 3)}, {2, 2, 2}));
  Mat4 t = Mat4::Identity();
  switch (irand(r, 0, 3)) {
    case 0: break;
    case 1: t = translate(Vec3(ir(r, -5, 5), ir(r, -5, 5), ir(r, -5, 5))) * scale(Vec3(1, 1, 1) * std::ldexp(1.0, irand(r, -3, 3)));
      break;
    case 2: t = reflect(Vec3::Unit(irand(r, 0, 2))); break;
    default: t = rotate(uni(r, 0, 360), rand_dir(r)); break;  // inexact, same for all: contacts stay near
  }
  for (auto& m : ms) c.ops.push_back(m.transformed(t));
  if (coin(r)) std::reverse(c.ops.begin(), c.ops.end());
  return c;
}
// Two or three identical operands, or one solid triangulated two ways (a box and a grid box; a
// prism capped by centre fans and by corner fans).
Case gen_identical(Rng& r) {
  Case c;
  Mesh a = random_primitive(r);
  const int how = irand(r, 0, 3);
  c.note = std::to_string(how);
  if (how == 0) c.ops = {a, a};
  else if (how == 1) c.ops = {a, a, a};
  else if (how == 2) {
    const Vec3 lo(uni(r, -1, 0), uni(r, -1, 0), uni(r, -1, 0));
    const Vec3 hi = lo + Vec3(ir(r, 1, 2), ir(r, 1, 2), ir(r, 1, 2));
    c.ops = {box_mesh(lo, hi - lo), grid_box(lo, hi, irand(r, 2, 5))};
  } else {
    // the same polygon prism, its caps fanned two ways
    const std::vector<Vec2> poly = regular_polygon(irand(r, 5, 12), 1);
    c.ops = {prism(poly, 0, 1, true), prism(poly, 0, 1, false)};
  }
  return c;
}
// 3 to 10 operands through one point (the origin, exactly): boxes with a corner there, turned
// about it; tetrahedra with an apex there; cylinders whose cap centre is there.
Case gen_nary_point(Rng& r) {
  Case c;
  const int n = irand(r, 3, 10);
  const bool exact = coin(r, 0.4);
  for (int i = 0; i < n; ++i) {
    Mesh m;
    switch (irand(r, 0, 2)) {
      case 0: m = box_mesh({0, 0, 0}, {uni(r, 0.5, 1.5), uni(r, 0.5, 1.5), uni(r, 0.5, 1.5)}); break;
      case 1: m = tetra({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}); break;
      default: m = cylinder_mesh(uni(r, 0.3, 1), 0, uni(r, 0.5, 1.5), irand(r, 3, 8)); break;
    }
    if (exact) {  // octant mirrors and quarter turns: many coincident faces
      Mat4 t = Mat4::Identity();
      for (int k = 0; k < 3; ++k)
        if (coin(r)) t = reflect(Vec3::Unit(k)) * t;
      if (coin(r)) t = rotate(90.0 * irand(r, 1, 3), Vec3::Unit(irand(r, 0, 2))) * t;
      m = m.transformed(t);
      for (auto& p : m.positions)
        for (int k = 0; k < 3; ++k) p[k] = std::round(p[k] * 1e12) / 1e12;  // clean the 90-degree turns' noise
      for (auto& p : m.positions)
        for (int k = 0; k < 3; ++k)
          if (std::abs(p[k]) < 1e-9) p[k] = 0;
    } else {
      m = rot(m, uni(r, 0, 360), rand_dir(r), Vec3::Zero());
    }
    c.ops.push_back(m);
  }
  return c;
}
// Turned low-side cylinders and icospheres, near one another.
Case gen_cyl_ico(Rng& r) {
  Case c;
  const int n = irand(r, 2, 4);
  for (int i = 0; i < n; ++i) {
    const Vec3 p(uni(r, -0.3, 0.3), uni(r, -0.3, 0.3), uni(r, -0.3, 0.3));
    if (coin(r)) c.ops.push_back(cylinder_mesh(uni(r, 0.2, 0.8), uni(r, -1, 0), uni(r, 0.1, 1), irand(r, 3, 8),
                                               translate(p) * rotate(uni(r, 0, 360), rand_dir(r))));
    else c.ops.push_back(icosphere(p, uni(r, 0.2, 0.8), coin(r) ? 20 : 80));
  }
  return c;
}
// Slivers: boxes 1e-9 or 2^-30 .. 2^-50 thick crossing a box or a sphere (some turned by up to
// 1e-3 degrees, some flush with its top), a tetrahedron that thin, a wedge whose top tilts that much.
Case gen_sliver(Rng& r) {
  Case c;
  const double th = coin(r) ? 1e-9 : std::ldexp(1.0, -irand(r, 30, 50));
  c.ops.push_back(coin(r) ? box_mesh({0, 0, 0}, {1, 1, 1}) : icosphere({0.5, 0.5, 0.5}, 0.6, 80));
  const int n = irand(r, 1, 3);
  for (int i = 0; i < n; ++i) {
    switch (irand(r, 0, 3)) {
      case 0: c.ops.push_back(box_mesh({-0.5, -0.5, uni(r, 0, 1)}, {2, 2, th}, rotate(uni(r, 0, 1e-3), rand_dir(r), {0.5, 0.5, 0.5}))); break;
      case 1: c.ops.push_back(box_mesh({-0.5, -0.5, coin(r) ? 1.0 : 1.0 - th}, {2, 2, th})); break;  // flush sliver
      case 2: c.ops.push_back(tetra({-0.5, -0.5, 0.5}, {1.5, -0.5, 0.5}, {0.5, 1.5, 0.5}, {0.5, 0.5, 0.5 + th})); break;
      default: {  // a wedge whose top face tilts by th over the unit
        std::vector<Vec2> tri = {{-0.5, -0.5}, {1.5, 0.2}, {0.2, 1.5}};
        Mesh w = prism(tri, 0.3, 0.7, false);
        for (auto& p : w.positions)
          if (p.z() > 0.5) p.z() += th * p.x();
        c.ops.push_back(w);
      }
    }
  }
  return c;
}
// Extreme coordinates: a unit case (touching, cyl_ico or near_copy) scaled by 2^e (e from -1060,
// subnormal, which the engine refuses, to 1018), or moved to around 1e8 with unit features, or a
// box up to 2^401 across with that case shrunk by up to 2^-600 near its centre.
Case gen_scale(Rng& r) {
  Case c;
  Rng r2(r());
  Case base;
  switch (irand(r, 0, 2)) {
    case 0: base = gen_touching(r2); break;
    case 1: base = gen_cyl_ico(r2); break;
    default: base = gen_near_copy(r2); break;
  }
  const int kind = irand(r, 0, 3);
  c.note = std::to_string(kind);
  if (kind <= 1) {
    static const int es[] = {-1060, -1000, -900, -600, -333, -100, 100, 333, 600, 900, 1000, 1018};
    c.pow2 = es[irand(r, 0, 11)];
    for (auto& m : base.ops) c.ops.push_back(scaled_pow2(m, c.pow2));
    c.note += " 2^" + std::to_string(c.pow2);
  } else if (kind == 2) {
    const Vec3 off(uni(r, 0.5, 2) * 1e8, uni(r, -2, 2) * 1e8, std::ldexp(1.0, 27));
    for (auto& m : base.ops) c.ops.push_back(moved(m, off));
  } else {  // mixed: a big box and small features near the origin
    const int e = irand(r, 40, 400);
    c.ops.push_back(box_mesh(Vec3(-1, -1, -1) * std::ldexp(1.0, e), Vec3(2, 2, 2) * std::ldexp(1.0, e)));
    for (auto& m : base.ops) c.ops.push_back(scaled_pow2(m, -irand(r, 0, 600)));
    if (coin(r)) c.ops.push_back(box_mesh({0, 0, 0}, Vec3(1, 1, 1) * std::ldexp(1.0, e)));  // shares the big box's corner region
    c.note += " mixed 2^" + std::to_string(e);
  }
  return c;
}
// Skinny triangles: fans of 300-1000 around one vertex (prisms over many-sided polygons fanned
// from a corner, nearly collinear points), crossed by a box or a cylinder.
Case gen_fan(Rng& r) {
  Case c;
  const int n = irand(r, 300, 1000);
  std::vector<Vec2> poly;
  if (coin(r)) {
    poly = regular_polygon(n, 1);
  } else {  // a very flat arc: points nearly collinear
    for (int i = 0; i < n; ++i) {
      const double t = static_cast<double>(i) / (n - 1);
      poly.push_back({2 * t - 1, -1e-3 * 4 * t * (1 - t)});
    }
    poly.push_back({0, 1});
  }
  c.ops.push_back(prism(poly, 0, 1, coin(r, 0.3)));
  if (coin(r)) c.ops.push_back(box_mesh({0, -0.5, 0.5}, {1, 1, 1}, rotate(uni(r, 0, 90), Vec3::UnitZ(), {0, 0, 0})));
  else c.ops.push_back(cylinder_mesh(0.5, 0.25, 2, irand(r, 3, 64), rotate(uni(r, 0, 30), rand_dir(r), {0, 0, 0.5})));
  if (coin(r, 0.3)) c.ops.push_back(box_mesh({-1, -1e-3, -1}, {2, 1e-3, 3}));  // the arc's chord region
  return c;
}
// Disjoint operands in a row along x (each within 1.6 of its place, 3.5 apart), some also moved
// by 1e-300 in y (which moves only their zero coordinates).
Case gen_disjoint(Rng& r) {
  Case c;
  const int n = irand(r, 2, 5);
  for (int i = 0; i < n; ++i) c.ops.push_back(moved(random_primitive(r), Vec3(3.5 * i, coin(r) ? 0 : 1e-300, 0)));
  return c;
}
// General position: random primitives overlapping (the baseline).
Case gen_random(Rng& r) {
  Case c;
  const int n = irand(r, 2, 4);
  for (int i = 0; i < n; ++i) c.ops.push_back(random_primitive(r));
  return c;
}
// Chains: a start and 10-20 further operands; each step's three results are checked, one goes on.
Case gen_chain(Rng& r) {
  Case c;
  c.chain = true;
  c.ops.push_back(random_primitive(r));
  const int n = irand(r, 10, 20);
  for (int i = 0; i < n; ++i) {
    switch (irand(r, 0, 5)) {
      case 0: c.ops.push_back(gen_grid_mixed(r).ops[0]); break;
      case 1: c.ops.push_back(snapped(random_primitive(r), 0.25)); break;
      default: c.ops.push_back(random_primitive(r)); break;
    }
  }
  return c;
}
// One bad operand among valid ones: open, inside out, two crossing shells, a NaN or infinite
// coordinate, an index out of range, a triangle repeated (three at its edges), two coincident
// shells, a collapsed edge, a shell with its inside-out copy. Every op must throw wedge::Error
// naming that operand, but for the collapsed edge, which the engine may mend (boolean.h).
Case gen_bad(Rng& r) {
  Case c;
  const int n = irand(r, 2, 4);
  for (int i = 0; i < n; ++i) c.ops.push_back(random_primitive(r));
  const int bi = irand(r, 0, n - 1);
  Mesh& m = c.ops[bi];
  c.bad = true;
  c.bad_index = bi;
  const int kind = irand(r, 0, 9);
  c.note = std::to_string(kind);
  c.mendable = kind == 8;
  switch (kind) {
    case 0: m.triangles.pop_back(); if (!m.face_ids.empty()) m.face_ids.pop_back(); break;  // open
    case 1: m = flipped(m); break;                                                            // inside out
    case 2: {  // two crossing shells: a convex operand moved by less than the way from a vertex to its centre
      const Vec3 d = 0.3 * (vertex_mean(m) - m.positions[m.triangles[0][0]]);
      m.append(moved(m, d));
      break;
    }
    case 3: m.positions[irand(r, 0, static_cast<int>(m.positions.size()) - 1)].x() = NAN; break;
    case 4: m.positions[irand(r, 0, static_cast<int>(m.positions.size()) - 1)].y() = -INFINITY; break;
    case 5: m.triangles[0][1] = static_cast<std::uint32_t>(m.positions.size() + 5); break;
    case 6: { m.triangles.push_back(m.triangles[0]); if (!m.face_ids.empty()) m.face_ids.push_back(-1); break; }  // 3 at an edge
    case 7: { Mesh o = m; m.append(o); break; }  // two coincident shells
    case 8: { auto& t = m.triangles[0]; m.positions[t[1]] = m.positions[t[0]]; break; }  // collapsed edge
    default: { Mesh o = flipped(m); m.append(o); break; }  // a shell and its inside-out copy
  }
  return c;
}

// A grid case (boxes or mixed) turned as a whole by one inexact rotation: faces that were exactly
// flush are now flush within ulps (nearly coincident planes, nearly shared edges and vertices).
Case gen_grid_rot(Rng& r) {
  Case c = coin(r) ? gen_grid_boxes(r) : gen_grid_mixed(r);
  c.axis_boxes = false;
  const Mat4 t = rotate(uni(r, 0, 360), rand_dir(r), Vec3(uni(r, -2, 2), uni(r, -2, 2), uni(r, -2, 2)));
  for (auto& m : c.ops) m = m.transformed(t);
  if (coin(r, 0.3)) {  // and one operand turned again by a hair
    auto& m = c.ops[irand(r, 0, static_cast<int>(c.ops.size()) - 1)];
    m = rot(m, uni(r, 1e-12, 1e-6), rand_dir(r), m.positions[0]);
  }
  return c;
}
// 2-10 boxes and prisms standing on the plane z = 0 (or hanging from it) with tops at z = 1 (or
// 0.5 or 2), each turned about the z axis, which leaves z exact: exactly coplanar overlapping
// faces of many operands at once.
Case gen_coplanar_stack(Rng& r) {
  Case c;
  const int n = irand(r, 2, 10);
  for (int i = 0; i < n; ++i) {
    Mesh m;
    const double top = coin(r, 0.7) ? 1.0 : (coin(r) ? 0.5 : 2.0);
    if (coin(r)) m = box_mesh({-0.5, -0.5, 0}, {1, uni(r, 0.2, 1), top});
    else {
      const std::vector<Vec2> poly = regular_polygon(irand(r, 3, 8), 0.6);
      m = prism(poly, 0, top, coin(r));
    }
    const Vec2 d(uni(r, -0.4, 0.4), uni(r, -0.4, 0.4));
    const double a = coin(r, 0.2) ? 90.0 * irand(r, 0, 3) : uni(r, 0, 360);
    for (auto& p : m.positions) {  // a turn about z, z untouched
      const double ca = std::cos(a * kPi / 180), sa = std::sin(a * kPi / 180);
      p = Vec3(ca * p.x() - sa * p.y() + d.x(), sa * p.x() + ca * p.y() + d.y(), p.z());
    }
    if (coin(r, 0.2)) for (auto& p : m.positions) p.z() = -p.z();  // hangs below instead
    if (coin(r, 0.2)) m = flipped(m);
    c.ops.push_back(m);
  }
  // The mirror in z and the flip each turn a solid inside out (both together do not): orient
  // every operand by its volume.
  for (auto& m : c.ops)
    if (m.volume() < 0) m = flipped(m);
  return c;
}
// A result with touching shells (the engine's union of two cubes sharing an edge or a vertex),
// perhaps turned, and an operand at the contact: a sphere, a box or a cylinder across it, or a
// third cube touching there.
Case gen_nonmanifold_ops(Rng& r) {
  Case c;
  const Mesh a = box_mesh({0, 0, 0}, {1, 1, 1});
  const Mesh b = coin(r) ? box_mesh({1, 1, 0}, {1, 1, 1}) : box_mesh({1, 1, 1}, {1, 1, 1});
  Mesh u = boolean(BooleanOp::Union, {&a, &b}).mesh;
  const Mat4 t = coin(r) ? Mat4::Identity() : rotate(uni(r, 0, 360), rand_dir(r));
  u = u.transformed(t);
  c.ops.push_back(u);
  const Vec3 at = apply_point(t, Vec3(1, 1, 1));
  switch (irand(r, 0, 3)) {
    case 0: c.ops.push_back(icosphere(at + rand_dir(r) * uni(r, 0, 0.3), uni(r, 0.1, 0.6), 80)); break;
    case 1: c.ops.push_back(box_mesh(at - Vec3(0.25, 0.25, 0.25), {0.5, 0.5, 0.5})); break;
    case 2: c.ops.push_back(cylinder_mesh(0.3, -1, 1, irand(r, 3, 8), translate(at) * rotate(uni(r, 0, 360), rand_dir(r)))); break;
    default: c.ops.push_back(box_mesh(at, {1, 1, 1})); break;  // a third cube at the contact point
  }
  return c;
}
// Near copies at higher resolution, where rounding repair has more to do: a UV sphere of
// 1000-4000 triangles or a 64-400-sided cylinder, and a copy turned by 1e-14 .. 1e-6 degrees,
// moved by 1e-15 .. 1e-9, mirrored in a plane through its centre or scaled by 1 - 1e-15 .. 1e-8;
// sometimes a third copy turned by up to 1e-4 degrees.
Case gen_hires_near(Rng& r) {
  Case c;
  Mesh a = coin(r) ? uv_sphere({0, 0, 0}, 1, irand(r, 1000, 4000)) : cylinder_mesh(1, -1, 1, irand(r, 64, 400));
  c.ops.push_back(a);
  switch (irand(r, 0, 3)) {
    case 0: c.ops.push_back(rot(a, std::pow(10.0, -uni(r, 6, 14)), rand_dir(r), {0, 0, 0})); break;
    case 1: c.ops.push_back(moved(a, rand_dir(r) * std::pow(10.0, -uni(r, 9, 15)))); break;
    case 2: c.ops.push_back(a.transformed(reflect(rand_dir(r), {0, 0, 0}))); break;
    default: c.ops.push_back(a.transformed(scale(Vec3(1, 1, 1) * (1 - std::pow(10.0, -uni(r, 8, 15)))))); break;
  }
  if (coin(r, 0.3)) c.ops.push_back(rot(a, uni(r, 1e-9, 1e-4), rand_dir(r), {0, 0, 0}));
  return c;
}

// An operand with a cavity (an outer shell and an inside-out inner shell in one mesh; sometimes
// an island in the cavity) and one that fills the cavity exactly or nearly (2^-52 .. 2^-30 off),
// sits in it or flush in its corner, crosses everything, or is the hollow operand turned.
Case gen_hollow(Rng& r) {
  Case c;
  const bool boxy = coin(r);
  Mesh outer = boxy ? box_mesh({-2, -2, -2}, {4, 4, 4}) : icosphere({0, 0, 0}, 2, 320);
  Mesh inner = boxy ? box_mesh({-1, -1, -1}, {2, 2, 2}) : icosphere({0, 0, 0}, 1, coin(r) ? 80 : 320);
  if (!boxy && coin(r)) inner = inner.transformed(rotate(uni(r, 0, 360), rand_dir(r)));
  Mesh a = outer;
  a.append(flipped(inner));
  if (coin(r, 0.3)) a.append(box_mesh({-0.5, -0.5, -0.5}, {1, 1, 1}));  // an island in the cavity
  c.ops.push_back(a);
  switch (irand(r, 0, 5)) {
    case 0: c.ops.push_back(inner); break;                                         // fills the cavity exactly
    case 1: c.ops.push_back(box_mesh({-0.5, -0.5, -0.5}, {1, 1, 1})); break;       // inside the cavity (or = island)
    case 2: c.ops.push_back(box_mesh({-3, -0.5, -0.5}, {6, 1, 1})); break;         // a bar through everything
    case 3: c.ops.push_back(box_mesh({-1, -1, -1}, {1, 1, 1})); break;             // flush in the cavity's corner
    case 4: c.ops.push_back(a.transformed(rotate(uni(r, 0, 90), rand_dir(r)))); break;    // another hollow one
    default: c.ops.push_back(moved(inner, Vec3(std::ldexp(1.0, -irand(r, 30, 52)), 0, 0))); break;
  }
  if (coin(r, 0.3)) std::swap(c.ops[0], c.ops[1]);
  return c;
}
// Unreferenced vertices (allowed by Mesh) placed on the other operands' vertices, edges and faces,
// and an empty operand now and then.
Case gen_unused_verts(Rng& r) {
  Case c = coin(r) ? gen_touching(r) : gen_random(r);
  std::vector<Vec3> spots;
  for (auto& m : c.ops)
    for (const auto& t : m.triangles) {
      const Vec3 &a = m.positions[t[0]], &b = m.positions[t[1]], &d = m.positions[t[2]];
      spots.push_back(a), spots.push_back((a + b) / 2), spots.push_back((a + b + d) / 3);
    }
  for (auto& m : c.ops)
    for (int k = irand(r, 1, 20); k > 0; --k) m.positions.push_back(spots[irand(r, 0, static_cast<int>(spots.size()) - 1)]);
  if (coin(r, 0.3)) c.ops.insert(c.ops.begin() + irand(r, 0, static_cast<int>(c.ops.size())), Mesh());
  return c;
}

// 3-10 copies of one primitive, each turned by its own angle of 1e-12 .. 1e-4 degrees about its
// centre: many nearly coincident sheets in one n-ary pass (the work budget's territory; slow
// cases are reported).
Case gen_many_near(Rng& r) {
  Case c;
  Mesh a;
  switch (irand(r, 0, 2)) {
    case 0: a = icosphere({0, 0, 0}, 1, coin(r) ? 80 : 320); break;
    case 1: a = cylinder_mesh(1, -1, 1, irand(r, 3, 32)); break;
    default: a = box_mesh({-1, -1, -1}, {2, 2, 2}); break;
  }
  const int n = irand(r, 3, 10);
  c.ops.push_back(a);
  for (int i = 1; i < n; ++i) c.ops.push_back(rot(a, std::pow(10.0, -uni(r, 4, 12)), rand_dir(r), {0, 0, 0}));
  return c;
}

// A torus about z (radii R > r), n segments around the axis and m around the tube.
Mesh torus_mesh(double R, double rr, int n, int m) {
  Mesh t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * kPi * i / n, v = 2 * kPi * j / m;
      t.add_vertex(Vec3((R + rr * std::cos(v)) * std::cos(u), (R + rr * std::cos(v)) * std::sin(u), rr * std::sin(v)));
    }
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>((i % n) * m + j % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      t.add_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      t.add_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return t;
}

// One smooth surface (torus, sphere, cylinder) tessellated twice: the copy at another resolution
// or turned about the symmetry axis by an angle that is no multiple of a segment's, so its facets
// lie a tessellation error apart from the first's everywhere, and perhaps also tilted by a small
// angle about another axis (the near-coincident sheets cross in long thin slivers; rounding them
// once left vertices a few ulps apart with no collapse that kept a manifold).
Case gen_same_surface(Rng& r) {
  Case c;
  const int kind = irand(r, 0, 2);
  auto make = [&] {
    switch (kind) {
      case 0: return torus_mesh(2, uni(r, 0.3, 0.9), irand(r, 12, 72), irand(r, 6, 32));
      case 1: return uv_sphere({0, 0, 0}, 1, irand(r, 200, 3000));
      default: return cylinder_mesh(1, -1, 1, irand(r, 12, 200));
    }
  };
  const Mesh a = make();
  c.ops.push_back(a);
  Mesh b = coin(r) ? make() : a;
  b = rot(b, uni(r, 0, 360), Vec3(0, 0, 1), {0, 0, 0});
  switch (irand(r, 0, 2)) {
    case 0: break;
    case 1: b = rot(b, std::pow(10.0, -uni(r, 1, 9)), rand_dir(r), {0, 0, 0}); break;
    default: b = rot(b, uni(r, 1, 20), rand_dir(r), {0, 0, 0}); break;
  }
  c.ops.push_back(b);
  if (coin(r, 0.2)) c.ops.push_back(rot(a, uni(r, 0, 360), Vec3(0, 0, 1), {0, 0, 0}));
  c.no_oracle = true;  // (CGAL's corefinement of such copies ran past the fuzzer's 30 s)
  return c;
}

// Curved solids as the Lua front end makes them: a torus, sphere, cylinder or cone (B-Rep) and a
// copy turned (by a hair, a few degrees or more, about any axis) before the tessellator meshes
// each at one chordal tolerance: the copy's vertices are its own surface's points, not the first
// mesh's turned, so the sheets lie a tessellation error apart where the surfaces (nearly)
// coincide. (A torus minus its copy turned 13 degrees about x, at tolerance 0.05, once could not be
// rounded.)
Case gen_tess_near(Rng& r) {
  Case c;
  const int kind = irand(r, 0, 3);
  const double a = uni(r, 0.3, 0.9);
  auto make = [&] {
    switch (kind) {
      case 0: return torus(2, a);
      case 1: return sphere(1.5);
      case 2: return cylinder(1, 2, Point3(0, 0, -1));
      default: return cone(1, a * 0.5, 2, Point3(0, 0, -1));
    }
  };
  Tolerance tol;
  tol.chordal = std::pow(10.0, -uni(r, 1, 2.7));
  const Model m = make();
  c.ops.push_back(tessellate(m, tol));
  const int n = coin(r, 0.2) ? 2 : 1;
  for (int i = 0; i < n; ++i) {
    Model b = make();
    double deg = 0;
    switch (irand(r, 0, 2)) {
      case 0: deg = std::pow(10.0, -uni(r, 1, 9)); break;
      case 1: deg = uni(r, 0.5, 20); break;
      default: deg = uni(r, 0, 360); break;
    }
    const Vec3 axis = coin(r, 0.3) ? Vec3(0, 0, 1) : coin(r) ? Vec3::Unit(irand(r, 0, 1)) : rand_dir(r);
    b.transform(rotate(deg, axis, Point3(0, 0, 0)));
    c.ops.push_back(tessellate(b, tol));
    c.note += std::to_string(kind) + "/" + std::to_string(deg) + " ";
  }
  c.no_oracle = true;  // (CGAL's corefinement of such copies ran past the fuzzer's 30 s)
  return c;
}

// A prism between two triangles (a0 b0 c0) and (a1 b1 c1), outward whatever their order.
Mesh prism6(const Vec3& a0, const Vec3& b0, const Vec3& c0, const Vec3& a1, const Vec3& b1, const Vec3& c1) {
  Mesh m;
  for (const Vec3& p : {a0, b0, c0, a1, b1, c1}) m.add_vertex(p);
  m.add_triangle(0, 2, 1), m.add_triangle(3, 4, 5);
  const int q[3][4] = {{0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}};
  for (auto& f : q) m.add_triangle(f[0], f[1], f[2]), m.add_triangle(f[0], f[2], f[3]);
  if (m.volume() < 0) m = flipped(m);
  return m;
}
// Operands that touch at one point only, exactly: an edge crossing an edge (a point inside both
// edges, a vertex of neither), a vertex on a face, a vertex inside an edge, apex to apex; the
// regularised union is non-manifold there and its shells must come back apart. Then all moved by
// an exact transform or one rotation.
Case gen_point_contact(Rng& r) {
  Case c;
  const Mesh a = box_mesh({0, 0, 0}, {1, 1, 1});
  c.ops.push_back(a);
  const int n = irand(r, 1, 3);
  for (int i = 0; i < n; ++i) {
    const int kind = irand(r, 0, 3);
    c.note += std::to_string(kind);
    const double x = irand(r, 1, 3) * 0.25;
    Mesh b;
    if (kind == 0) {  // its edge along (0, 1, -1) crosses the cube's edge y = z = 1 at (x, 1, 1)
      const Vec3 p(x, 1, 1), e(0, 1, -1), u(-0.5, 1, 1), v(0.5, 1, 1);
      b = prism6(p - 0.5 * e, p - 0.5 * e + u, p - 0.5 * e + v, p + 0.5 * e, p + 0.5 * e + u, p + 0.5 * e + v);
    } else if (kind == 1) {  // a tetrahedron's vertex on the top face
      const Vec3 p(x, irand(r, 1, 3) * 0.25, 1);
      b = tetra(p, p + Vec3(-0.5, -0.5, 1), p + Vec3(0.5, -0.5, 1), p + Vec3(0, 0.5, 1));
    } else if (kind == 2) {  // a tetrahedron's vertex inside the edge y = z = 1
      const Vec3 p(x, 1, 1);
      b = tetra(p, p + Vec3(-0.25, 0.5, 0.5), p + Vec3(0.25, 0.5, 0.5), p + Vec3(0, 1, 0.25));
    } else {  // vertex to vertex: a tetrahedron on the corner (1, 1, 1)
      const Vec3 p(1, 1, 1);
      b = tetra(p, p + Vec3(1, 0.5, 0.5), p + Vec3(0.5, 1, 0.5), p + Vec3(0.5, 0.5, 1));
    }
    c.ops.push_back(b);
  }
  Mat4 t = Mat4::Identity();
  switch (irand(r, 0, 4)) {
    case 0: case 1: break;
    case 2: t = translate(Vec3(ir(r, -3, 3), ir(r, -3, 3), ir(r, -3, 3))) * reflect(Vec3::Unit(irand(r, 0, 2))); break;
    case 3: t = scale(Vec3(1, 1, 1) * std::ldexp(1.0, irand(r, -20, 20))); break;
    default: t = rotate(uni(r, 0, 360), rand_dir(r)); break;
  }
  for (auto& m : c.ops) m = m.transformed(t);
  if (coin(r)) std::reverse(c.ops.begin(), c.ops.end());
  return c;
}

}  // namespace

const std::vector<Gen>& generators() {
  static const std::vector<Gen> g = {
      {"grid_boxes", gen_grid_boxes},         {"grid_mixed", gen_grid_mixed},
      {"near_copy", gen_near_copy},           {"touching", gen_touching},
      {"identical", gen_identical},           {"nary_point", gen_nary_point},
      {"cyl_ico", gen_cyl_ico},               {"sliver", gen_sliver},
      {"scale", gen_scale},                   {"fan", gen_fan},
      {"disjoint", gen_disjoint},             {"random", gen_random},
      {"chain", gen_chain},                   {"bad", gen_bad},
      {"grid_rot", gen_grid_rot},             {"coplanar_stack", gen_coplanar_stack},
      {"nonmanifold_ops", gen_nonmanifold_ops}, {"hires_near", gen_hires_near},
      {"hollow", gen_hollow},                 {"unused_verts", gen_unused_verts},
      {"many_near", gen_many_near},           {"point_contact", gen_point_contact},
      {"same_surface", gen_same_surface},     {"tess_near", gen_tess_near}};
  return g;
}

}  // namespace wedge::fuzz
