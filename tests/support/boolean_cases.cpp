#include "tests/support/boolean_cases.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include "kernel/error.h"
#include "kernel/transform.h"

namespace wedge::testing {

namespace {
Mesh apply(const Mesh& m, const Mat4& t) { return t.isIdentity(0.0) ? m : m.transformed(t); }
}  // namespace

Mesh box_mesh(const Point3& lo, const Vec3& size, const Mat4& m, int face_id) {
  Mesh b;
  for (int i = 0; i < 8; ++i)
    b.add_vertex({(i & 1) ? lo.x() + size.x() : lo.x(), (i & 2) ? lo.y() + size.y() : lo.y(),
                  (i & 4) ? lo.z() + size.z() : lo.z()});
  // -z, +z, -y, +y, -x, +x; each quad counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int f = 0; f < 6; ++f) {
    const int* q = quads[f];
    b.add_triangle(q[0], q[1], q[2], face_id + f);
    b.add_triangle(q[0], q[2], q[3], face_id + f);
  }
  return apply(b, m);
}

Mesh uv_sphere(const Point3& center, double radius, int triangles, int face_id) {
  // 4 r (r - 1) triangles for r rings.
  int rings = std::max(3, static_cast<int>(std::lround(0.5 + std::sqrt(std::max(triangles, 24) / 4.0))));
  const int slices = 2 * rings;
  Mesh s;
  s.add_vertex(center + Vec3(0, 0, radius));
  for (int i = 1; i < rings; ++i) {
    const double theta = kPi * i / rings;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2 * kPi * j / slices;
      s.add_vertex(center + radius * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                          std::cos(theta)));
    }
  }
  const auto south = s.add_vertex(center - Vec3(0, 0, radius));
  auto v = [&](int ring, int j) { return static_cast<std::uint32_t>(1 + (ring - 1) * slices + (j % slices)); };
  for (int j = 0; j < slices; ++j) s.add_triangle(0, v(1, j), v(1, j + 1), face_id);
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < slices; ++j) {
      s.add_triangle(v(i, j), v(i + 1, j), v(i + 1, j + 1), face_id);
      s.add_triangle(v(i, j), v(i + 1, j + 1), v(i, j + 1), face_id);
    }
  for (int j = 0; j < slices; ++j) s.add_triangle(v(rings - 1, j), south, v(rings - 1, j + 1), face_id);
  return s;
}

Mesh icosphere(const Point3& center, double radius, int triangles, int face_id) {
  int levels = 0;
  while (levels < 10 && std::abs(std::log(20.0 * std::pow(4.0, levels + 1) / triangles)) <
                            std::abs(std::log(20.0 * std::pow(4.0, levels) / triangles)))
    ++levels;
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& q : p) q.normalize();
  std::vector<Mesh::Triangle> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      auto key = std::minmax(a, b);
      auto [it, inserted] = mid.emplace(key, static_cast<std::uint32_t>(p.size()));
      if (inserted) p.push_back((p[a] + p[b]).normalized());
      return it->second;
    };
    std::vector<Mesh::Triangle> g;
    g.reserve(4 * f.size());
    for (const auto& tri : f) {
      const auto ab = midpoint(tri[0], tri[1]), bc = midpoint(tri[1], tri[2]), ca = midpoint(tri[2], tri[0]);
      g.push_back({tri[0], ab, ca});
      g.push_back({tri[1], bc, ab});
      g.push_back({tri[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  Mesh s;
  for (const auto& q : p) s.add_vertex(center + radius * q);
  for (const auto& tri : f) s.add_triangle(tri[0], tri[1], tri[2], face_id);
  return s;
}

Mesh cylinder_mesh(double radius, double z0, double z1, int sides, const Mat4& m, int face_id) {
  if (sides < 3) fail("cylinder_mesh: sides must be at least 3, got ", sides);
  Mesh c;
  for (int j = 0; j < sides; ++j) {
    const double a = 2 * kPi * j / sides;
    c.add_vertex({radius * std::cos(a), radius * std::sin(a), z0});
    c.add_vertex({radius * std::cos(a), radius * std::sin(a), z1});
  }
  const auto bottom = c.add_vertex({0, 0, z0}), top = c.add_vertex({0, 0, z1});
  for (int j = 0; j < sides; ++j) {
    const std::uint32_t b0 = 2 * j, t0 = 2 * j + 1, b1 = 2 * ((j + 1) % sides), t1 = b1 + 1;
    c.add_triangle(b0, b1, t1, face_id);
    c.add_triangle(b0, t1, t0, face_id);
    c.add_triangle(bottom, b1, b0, face_id + 1);
    c.add_triangle(top, t0, t1, face_id + 2);
  }
  return apply(c, m);
}

double polyhedron_volume(const Mesh& m) {
  if (m.positions.empty()) return 0;
  const Point3 o = m.positions[0];
  long double sum = 0, carry = 0;  // Kahan summation of the tetrahedra on o
  for (const auto& t : m.triangles) {
    const long double ax = m.positions[t[0]].x() - (long double)o.x(), ay = m.positions[t[0]].y() - (long double)o.y(),
                      az = m.positions[t[0]].z() - (long double)o.z();
    const long double bx = m.positions[t[1]].x() - (long double)o.x(), by = m.positions[t[1]].y() - (long double)o.y(),
                      bz = m.positions[t[1]].z() - (long double)o.z();
    const long double cx = m.positions[t[2]].x() - (long double)o.x(), cy = m.positions[t[2]].y() - (long double)o.y(),
                      cz = m.positions[t[2]].z() - (long double)o.z();
    const long double det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    const long double y = det - carry, s = sum + y;
    carry = (s - sum) - y;
    sum = s;
  }
  return static_cast<double>(sum / 6);
}

std::optional<double> BooleanCase::expected(BooleanOp op) const {
  switch (op) {
    case BooleanOp::Union: return union_volume;
    case BooleanOp::Intersection: return intersection_volume;
    case BooleanOp::Difference: return difference_volume;
  }
  return std::nullopt;
}

namespace {
BooleanCase two(std::string name, Mesh a, Mesh b, std::optional<double> u, std::optional<double> i,
                std::optional<double> d, bool nonmanifold_union = false) {
  BooleanCase c;
  c.name = std::move(name);
  c.operands.push_back(std::move(a));
  c.operands.push_back(std::move(b));
  c.union_volume = u;
  c.intersection_volume = i;
  c.difference_volume = d;
  c.nonmanifold_union = nonmanifold_union;
  return c;
}

// A triangular prism along x from x0 to x1 over the triangle (y, z) = p, q, r (counter-clockwise
// seen from +x).
Mesh prism_x(double x0, double x1, Vec2 p, Vec2 q, Vec2 r) {
  Mesh m;
  const Vec2 t[3] = {p, q, r};
  for (int k = 0; k < 3; ++k) {
    m.add_vertex({x0, t[k].x(), t[k].y()});
    m.add_vertex({x1, t[k].x(), t[k].y()});
  }
  m.add_triangle(1, 3, 5, 0);  // +x end
  m.add_triangle(0, 4, 2, 1);  // -x end
  for (int k = 0; k < 3; ++k) {
    const std::uint32_t a0 = 2 * k, a1 = a0 + 1, b0 = 2 * ((k + 1) % 3), b1 = b0 + 1;
    m.add_triangle(a0, b0, b1, 2 + k);
    m.add_triangle(a0, b1, a1, 2 + k);
  }
  return m;
}

// A square pyramid: base [x0,x1]x[y0,y1] at height zb, apex at `apex` (below the base), so the
// outward base normal is +z.
Mesh pyramid_down(double x0, double x1, double y0, double y1, double zb, const Point3& apex) {
  Mesh m;
  m.add_vertex({x0, y0, zb});
  m.add_vertex({x1, y0, zb});
  m.add_vertex({x1, y1, zb});
  m.add_vertex({x0, y1, zb});
  const auto a = m.add_vertex(apex);
  m.add_triangle(0, 1, 2, 0);
  m.add_triangle(0, 2, 3, 0);
  for (std::uint32_t k = 0; k < 4; ++k) m.add_triangle(a, (k + 1) % 4, k, 1 + k);
  return m;
}
}  // namespace

std::vector<BooleanCase> degenerate_cases() {
  std::vector<BooleanCase> cases;
  const Vec3 one(1, 1, 1);
  {
    const Mesh s = uv_sphere({0.25, -0.5, 1}, 1.5, 1200);
    const double v = polyhedron_volume(s);
    cases.push_back(two("identical operands", s, s, v, v, 0.0));
  }
  {
    const Mesh b = box_mesh({-0.5, -0.5, -0.5}, one, rotate(37, Vec3(1, 2, 3)));
    const double v = polyhedron_volume(b);
    cases.push_back(two("A - A (rotated box)", b, b, v, v, 0.0));
  }
  cases.push_back(two("coplanar faces, same orientation", box_mesh({0, 0, 0}, {2, 2, 1}), box_mesh({1, 1, 0}, {2, 2, 1}),
                      7.0, 1.0, 3.0));
  cases.push_back(two("coplanar faces, opposite orientation", box_mesh({0, 0, 0}, {2, 2, 1}), box_mesh({1, 1, 1}, {2, 2, 1}),
                      8.0, 0.0, 4.0));
  cases.push_back(two("cubes sharing a face", box_mesh({0, 0, 0}, one), box_mesh({1, 0, 0}, one), 2.0, 0.0, 1.0));
  {
    // A prism whose lowest edge (x from 0.25 to 0.75 at y 0.5) lies on the cube's top face.
    const Mesh p = prism_x(0.25, 0.75, {0.5, 1}, {1, 2}, {0, 2});
    const double v = polyhedron_volume(p);
    cases.push_back(two("edge lying on a face", box_mesh({0, 0, 0}, one), p, 1 + v, 0.0, 1.0, true));
  }
  {
    const Mesh p = pyramid_down(0, 1, 0, 1, 2, {0.5, 0.5, 1});
    const double v = polyhedron_volume(p);
    cases.push_back(two("vertex touching a face", box_mesh({0, 0, 0}, one), p, 1 + v, 0.0, 1.0, true));
  }
  cases.push_back(two("cubes sharing only an edge", box_mesh({0, 0, 0}, one), box_mesh({1, 1, 0}, one), 2.0, 0.0, 1.0, true));
  cases.push_back(two("cubes sharing only a vertex", box_mesh({0, 0, 0}, one), box_mesh({1, 1, 1}, one), 2.0, 0.0, 1.0, true));
  cases.push_back(two("flush pocket", box_mesh({0, 0, 0}, {4, 4, 2}), box_mesh({1, 1, 1}, {2, 2, 1}), 32.0, 4.0, 28.0));
  {
    const Mesh s = icosphere({0.1, 0.2, -0.3}, 1, 1280);
    const double v = polyhedron_volume(s);
    cases.push_back(two("nested (sphere inside a box)", box_mesh({-2, -2, -2}, {4, 4, 4}), s, 64.0, v, 64.0 - v));
  }
  {
    const Mesh s = icosphere({3, 0.5, 0.5}, 1, 1280);
    const double v = polyhedron_volume(s);
    cases.push_back(two("disjoint", box_mesh({0, 0, 0}, one), s, 1 + v, 0.0, 1.0));
  }
  cases.push_back(two("T-junctions between operands", box_mesh({0, 0, 0}, {2, 2, 2}), box_mesh({1, 0, 0}, {2, 2, 2}), 12.0,
                      4.0, 4.0));
  cases.push_back(
      two("T-junctions, stacked boxes", box_mesh({0, 0, 0}, {2, 1, 1}), box_mesh({0, 0, 1}, {1, 1, 1}), 3.0, 0.0, 2.0));
  // Faces 1e-6 radians from parallel: long thin intersection polygons (slivers). No closed form.
  cases.push_back(two("nearly parallel faces (slivers)", box_mesh({0, 0, 0}, one),
                      box_mesh({0, 0, 0}, one, rotate(1e-6 * 180 / kPi, Vec3(1, 2, 3), Point3(0.3, 0.4, 0.5))),
                      std::nullopt, std::nullopt, std::nullopt));
  {
    // A 1e6 cube and a 1e-6 cube straddling its corner; and one straddling the middle of its top.
    const Mesh big = box_mesh({0, 0, 0}, {1e6, 1e6, 1e6});
    const Mesh small = box_mesh({-5e-7, -5e-7, -5e-7}, {1e-6, 1e-6, 1e-6});
    const double hi = -5e-7 + 1e-6, vs = polyhedron_volume(small), inside = hi * hi * hi;
    cases.push_back(two("1e-6 and 1e6 coordinates (corner)", big, small, 1e18 + vs - inside, inside, 1e18 - inside));
    const Mesh top = box_mesh({5e5, 5e5, 1e6 - 5e-7}, {1e-6, 1e-6, 1e-6});
    const double d = polyhedron_volume(top);  // its box's true extents, after rounding
    const Point3 lo = top.positions[0], up = top.positions[7];
    const double in = (up.x() - lo.x()) * (up.y() - lo.y()) * (1e6 - lo.z());
    cases.push_back(two("1e-6 and 1e6 coordinates (top face)", big, top, 1e18 + d - in, in, 1e18 - in));
  }
  return cases;
}

BooleanCase degenerate_case(const std::string& name) {
  for (auto& c : degenerate_cases())
    if (c.name == name) return c;
  fail("degenerate_case: no case named '", name, "'");
}

std::vector<Mesh> overlapping_spheres(int triangles) {
  const double d = 0.6 / std::sqrt(3.0);
  return {uv_sphere({0, 0, 0}, 1, triangles, 0),
          uv_sphere({0, 0, 0}, 1, triangles, 1).transformed(compose(translate({d, d, d}), rotate(17, Vec3(1, -2, 0.5))))};
}

std::vector<Mesh> classic_figure_operands(int sphere_triangles, int sides) {
  return {box_mesh({-1, -1, -1}, {2, 2, 2}, Mat4::Identity(), 0), uv_sphere({0, 0, 0}, 1.35, sphere_triangles, 10),
          cylinder_mesh(0.7, -2, 2, sides, rotate_y(90), 20), cylinder_mesh(0.7, -2, 2, sides, rotate_x(90), 30),
          cylinder_mesh(0.7, -2, 2, sides, Mat4::Identity(), 40)};
}

std::vector<Mesh> sphere_lattice(int n, int triangles) {
  std::vector<Mesh> out;
  const Mesh unit = icosphere({0, 0, 0}, 1, triangles);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        Mesh s = unit;
        for (auto& p : s.positions) p += Vec3(1.5 * i, 1.5 * j, 1.5 * k);
        std::fill(s.face_ids.begin(), s.face_ids.end(), static_cast<std::int32_t>(out.size()));
        out.push_back(std::move(s));
      }
  return out;
}

std::vector<Mesh> octet_truss(int n, double r, int sides, int ball_triangles) {
  std::vector<Mesh> out;
  const int dirs[9][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, -1, 0}, {1, 0, -1}, {0, 1, -1}};
  for (int x = 0; x <= n; ++x)
    for (int y = 0; y <= n; ++y)
      for (int z = 0; z <= n; ++z)
        for (const auto& d : dirs) {
          const int q[3] = {x + d[0], y + d[1], z + d[2]};
          if (q[0] > n || q[1] < 0 || q[1] > n || q[2] < 0 || q[2] > n) continue;
          const Vec3 dir(d[0], d[1], d[2]);
          const double length = dir.norm();
          // The z axis turned onto dir (about z x dir; dir is never -z here).
          const Vec3 axis = Vec3(0, 0, 1).cross(dir);
          const double angle = std::acos(dir.z() / length) * 180 / kPi;
          const Mat4 turn = axis.norm() > 0 ? rotate(angle, axis) : Mat4::Identity();
          out.push_back(cylinder_mesh(r, 0, length, sides, translate(Vec3(x, y, z)) * turn, static_cast<int>(out.size())));
        }
  for (int x = 0; x <= n; ++x)
    for (int y = 0; y <= n; ++y)
      for (int z = 0; z <= n; ++z) {
        Mesh b = icosphere(Point3(x, y, z), 1.5 * r, ball_triangles);
        std::fill(b.face_ids.begin(), b.face_ids.end(), static_cast<std::int32_t>(out.size()));
        out.push_back(std::move(b));
      }
  return out;
}

std::vector<Mesh> plate_and_cylinders(int n, int sides) {
  std::vector<Mesh> out = {box_mesh({0, 0, 0}, {double(n), double(n), 1})};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      out.push_back(cylinder_mesh(0.3, -0.5, 1.5, sides, translate({i + 0.5, j + 0.5, 0}), 6 + 3 * (i * n + j)));
  return out;
}

double plate_with_holes_volume(const std::vector<Mesh>& pc) {
  // Each cylinder is a prism of height 2 of which the plate holds height 1 (exact: z is not moved).
  double v = polyhedron_volume(pc[0]);
  for (std::size_t k = 1; k < pc.size(); ++k) v -= polyhedron_volume(pc[k]) / 2;
  return v;
}

std::vector<Mesh> menger_operands(int level) {
  int side = 1;
  for (int l = 0; l < level; ++l) side *= 3;
  const double s = side;
  std::vector<Mesh> out = {box_mesh({0, 0, 0}, {s, s, s})};
  // Level k removes the points where two coordinates both have base-3 digit k equal to 1: for each
  // pair of axes, bars over [3^(level-k) (3m+1), 3^(level-k) (3m+2)] in both.
  int cell = side;
  for (int k = 1; k <= level; ++k) {
    cell /= 3;
    const int count = side / (3 * cell);
    for (int axis = 0; axis < 3; ++axis)
      for (int a = 0; a < count; ++a)
        for (int b = 0; b < count; ++b) {
          Vec3 lo, size;
          const int u = (axis + 1) % 3, v = (axis + 2) % 3;
          lo[axis] = -1;
          size[axis] = s + 2;
          lo[u] = cell * (3 * a + 1);
          lo[v] = cell * (3 * b + 1);
          size[u] = size[v] = cell;
          out.push_back(box_mesh(lo, size, Mat4::Identity(), static_cast<int>(6 * out.size())));
        }
  }
  return out;
}

double menger_volume(int level) { return std::pow(20.0, level); }

// The box [lo, hi] with each side cut into n x n squares of two triangles: a triangle of a coarse
// operand crossing it meets many of them (settle() looks only at triangles with 8 pairs or more).
Mesh grid_box(const Vec3& lo, const Vec3& hi, int n) {
  Mesh m;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const std::uint32_t base = static_cast<std::uint32_t>(m.positions.size());
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Vec3 p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[u] = i == n ? hi[u] : lo[u] + (hi[u] - lo[u]) * i / n;
          p[v] = j == n ? hi[v] : lo[v] + (hi[v] - lo[v]) * j / n;
          m.add_vertex(p);
        }
      auto id = [&](int i, int j) { return base + static_cast<std::uint32_t>(i * (n + 1) + j); };
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          // Counter-clockwise seen from outside: (u, v, axis) is right-handed, so the far side
          // (side 1) turns u to v, the near side v to u.
          if (side) {
            m.add_triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1));
            m.add_triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1));
          } else {
            m.add_triangle(id(i, j), id(i + 1, j + 1), id(i + 1, j));
            m.add_triangle(id(i, j), id(i, j + 1), id(i + 1, j + 1));
          }
        }
    }
  // The sides share their edges' positions; weld them into one closed mesh.
  return m.welded();
}


// The volume of a union (or of the first box minus the others) of axis-parallel boxes, exactly
// as their doubles say: per cell of the grid of all their coordinates, the cell's centre in or out.
double boxes_volume(BooleanOp op, const std::vector<std::array<Vec3, 2>>& boxes) {
  std::vector<double> c[3];
  for (const auto& b : boxes)
    for (int d = 0; d < 3; ++d) c[d].push_back(b[0][d]), c[d].push_back(b[1][d]);
  for (auto& v : c) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  long double total = 0;
  for (std::size_t i = 0; i + 1 < c[0].size(); ++i)
    for (std::size_t j = 0; j + 1 < c[1].size(); ++j)
      for (std::size_t k = 0; k + 1 < c[2].size(); ++k) {
        const Vec3 m((c[0][i] + c[0][i + 1]) / 2, (c[1][j] + c[1][j + 1]) / 2, (c[2][k] + c[2][k + 1]) / 2);
        auto in = [&](const std::array<Vec3, 2>& b) {
          return (m.array() > b[0].array()).all() && (m.array() < b[1].array()).all();
        };
        const bool inside = op == BooleanOp::Union ? std::any_of(boxes.begin(), boxes.end(), in)
                                                   : in(boxes[0]) && std::none_of(boxes.begin() + 1, boxes.end(), in);
        if (inside)
          total += static_cast<long double>(c[0][i + 1] - c[0][i]) * (c[1][j + 1] - c[1][j]) * (c[2][k + 1] - c[2][k]);
      }
  return static_cast<double>(total);
}

}  // namespace wedge::testing
