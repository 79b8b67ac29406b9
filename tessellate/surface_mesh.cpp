// Surface -> Mesh: a parameter grid, uniform within each knot interval, refined where a cell's edge
// midpoints, diagonal midpoint or triangle centroids leave the surface by more than half the
// tolerance (the error of a linear interpolant of a smooth surface is quadratic over the triangle,
// so bounding these samples by tol/2 keeps the whole triangle within about 2/3 tol); an interval's
// count grows by the square root of its worst error ratio.
#include "tessellate/surface_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernel/error.h"

namespace wedge {

namespace {

std::vector<double> unique_sorted(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

[[noreturn]] void over_budget(std::size_t triangles, double tolerance, std::size_t max_triangles) {
  fail("tessellate: the surface needs about ", triangles, " triangles at tolerance ", tolerance, ", more than the budget of ",
       max_triangles, ": use a larger tolerance or raise the budget with tolerance{max_triangles=N}");
}

// The refined parameter grid of tessellate() and its evaluated points (row-major, us outer).
void refine_grid(const Surface& s, double tolerance, std::vector<double>& us, std::vector<double>& vs,
                 std::vector<Point3>& grid, std::size_t max_triangles) {
  if (!(tolerance > 0) || !std::isfinite(tolerance)) fail("tolerance must be a positive number, got ", tolerance);
  std::vector<double> ub = unique_sorted(s.u_breaks()), vb = unique_sorted(s.v_breaks());
  std::vector<int> cu(ub.size() - 1, 2), cv(vb.size() - 1, 2);
  auto params = [](const std::vector<double>& br, const std::vector<int>& count, std::vector<int>& owner) {
    std::vector<double> t;
    owner.clear();
    for (std::size_t i = 0; i + 1 < br.size(); ++i)
      for (int j = 0; j < count[i]; ++j) {
        t.push_back(br[i] + (br[i + 1] - br[i]) * j / count[i]);
        owner.push_back(int(i));
      }
    t.push_back(br.back());
    return t;
  };
  const double limit = 0.5 * tolerance;
  const std::size_t max_vertices = std::size_t(1) << 22;
  // The budget is checked on each grid before it is evaluated: teapot():mesh{tolerance=1e-5}
  // ignored tolerance{max_triangles=} and grew to 9.5 GB (4M vertices a patch, 32 patches).
  auto require_budget = [&](std::size_t nu, std::size_t nv) {
    if (2 * (nu - 1) * (nv - 1) > max_triangles) over_budget(2 * (nu - 1) * (nv - 1), tolerance, max_triangles);
  };
  std::vector<int> uo, vo;
  for (int round = 0;; ++round) {
    us = params(ub, cu, uo);
    vs = params(vb, cv, vo);
    std::size_t nu = us.size(), nv = vs.size();
    grid.resize(nu * nv);
    for (std::size_t a = 0; a < nu; ++a)
      for (std::size_t b = 0; b < nv; ++b) grid[a * nv + b] = s.eval(us[a], vs[b]);
    // Worst error / limit per knot interval, in each direction.
    std::vector<double> ratio_u(cu.size(), 0.0), ratio_v(cv.size(), 0.0);
    for (std::size_t a = 0; a + 1 < nu; ++a)
      for (std::size_t b = 0; b + 1 < nv; ++b) {
        const Point3 &p00 = grid[a * nv + b], &p10 = grid[(a + 1) * nv + b], &p01 = grid[a * nv + b + 1],
                     &p11 = grid[(a + 1) * nv + b + 1];
        double um = 0.5 * (us[a] + us[a + 1]), vm = 0.5 * (vs[b] + vs[b + 1]);
        double eu = std::max((s.eval(um, vs[b]) - 0.5 * (p00 + p10)).norm(), (s.eval(um, vs[b + 1]) - 0.5 * (p01 + p11)).norm());
        double ev = std::max((s.eval(us[a], vm) - 0.5 * (p00 + p01)).norm(), (s.eval(us[a + 1], vm) - 0.5 * (p10 + p11)).norm());
        double ed = (s.eval(um, vm) - 0.5 * (p00 + p11)).norm();
        ed = std::max(ed, (s.eval((us[a] + 2 * us[a + 1]) / 3, (2 * vs[b] + vs[b + 1]) / 3) - (p00 + p10 + p11) / 3).norm());
        ed = std::max(ed, (s.eval((2 * us[a] + us[a + 1]) / 3, (vs[b] + 2 * vs[b + 1]) / 3) - (p00 + p11 + p01) / 3).norm());
        ratio_u[uo[a]] = std::max(ratio_u[uo[a]], std::max(eu, ed) / limit);
        ratio_v[vo[b]] = std::max(ratio_v[vo[b]], std::max(ev, ed) / limit);
      }
    // The chordal error falls with the square of the step: scale each interval's count by the
    // square root of its worst ratio (a little more, and at least one more cell).
    auto grow = [](std::vector<int>& count, const std::vector<double>& ratio) {
      bool changed = false;
      for (std::size_t i = 0; i < count.size(); ++i)
        if (ratio[i] > 1) {
          double target = std::ceil(count[i] * std::sqrt(ratio[i]) * 1.1);
          count[i] = int(std::min(target, 1e7));
          changed = true;
        }
      return changed;
    };
    bool any = grow(cu, ratio_u);
    any = grow(cv, ratio_v) || any;
    if (!any) break;
    std::size_t next_u = 1, next_v = 1;
    for (int c : cu) next_u += std::size_t(c);
    for (int c : cv) next_v += std::size_t(c);
    require_budget(next_u, next_v);
    if (next_u * next_v > max_vertices || round > 30)
      fail("tolerance ", tolerance, " would need more than ", max_vertices, " mesh vertices on this surface: use a larger tolerance");
  }
  if (s.trims.empty()) return;
  // A trimmed surface keeps the grid triangles whose centroid lies inside the trim region, so
  // its boundary follows the trim loops to within one cell: refine until every cell edge is at
  // most the tolerance long in model space (the mesh boundary is then within about 1.5 times
  // the tolerance of the trim curve's image).
  const std::size_t nu = us.size(), nv = vs.size();
  std::vector<double> len_u(cu.size(), 0.0), len_v(cv.size(), 0.0);
  for (std::size_t a = 0; a < nu; ++a)
    for (std::size_t b = 0; b < nv; ++b) {
      if (a + 1 < nu) len_u[uo[a]] = std::max(len_u[uo[a]], (grid[(a + 1) * nv + b] - grid[a * nv + b]).norm());
      if (b + 1 < nv) len_v[vo[b]] = std::max(len_v[vo[b]], (grid[a * nv + b + 1] - grid[a * nv + b]).norm());
    }
  bool finer = false;
  std::size_t next_u = 1, next_v = 1;
  for (std::size_t i = 0; i < cu.size(); ++i) {
    if (len_u[i] > tolerance) cu[i] = int(std::min(1e7, std::ceil(cu[i] * len_u[i] / tolerance))), finer = true;
    next_u += std::size_t(cu[i]);
  }
  for (std::size_t i = 0; i < cv.size(); ++i) {
    if (len_v[i] > tolerance) cv[i] = int(std::min(1e7, std::ceil(cv[i] * len_v[i] / tolerance))), finer = true;
    next_v += std::size_t(cv[i]);
  }
  if (!finer) return;
  require_budget(next_u, next_v);
  if (next_u * next_v > max_vertices)
    fail("tolerance ", tolerance, " would need more than ", max_vertices,
         " mesh vertices to follow this surface's trim loops: use a larger tolerance");
  us = params(ub, cu, uo);
  vs = params(vb, cv, vo);
  grid.resize(us.size() * vs.size());
  for (std::size_t a = 0; a < us.size(); ++a)
    for (std::size_t b = 0; b < vs.size(); ++b) grid[a * vs.size() + b] = s.eval(us[a], vs[b]);
}

}  // namespace

Mesh tessellate(const Surface& s, double tolerance, int face_id, std::size_t max_triangles) {
  std::vector<double> us, vs;
  std::vector<Point3> grid;
  refine_grid(s, tolerance, us, vs, grid, max_triangles);
  return tessellate_grid(s, us, vs, face_id, &grid);
}

Mesh tessellate_welded(const Surface& s, double tolerance, int face_id, std::size_t max_triangles) {
  std::vector<double> us, vs;
  std::vector<Point3> grid;
  refine_grid(s, tolerance, us, vs, grid, max_triangles);
  return tessellate_grid_welded(s, us, vs, face_id, &grid);
}

Mesh tessellate_grid(const Surface& s, const std::vector<double>& us, const std::vector<double>& vs, int face_id,
                     const std::vector<Point3>* points) {
  if (us.size() < 2 || vs.size() < 2) fail("tessellate_grid: need at least two parameters in each direction");
  Mesh m;
  std::size_t nu = us.size(), nv = vs.size();
  if (points && points->size() == nu * nv) m.positions = *points;
  else {
    m.positions.resize(nu * nv);
    for (std::size_t a = 0; a < nu; ++a)
      for (std::size_t b = 0; b < nv; ++b) m.positions[a * nv + b] = s.eval(us[a], vs[b]);
  }
  m.normals.resize(nu * nv);
  m.uvs.resize(nu * nv);
  for (std::size_t a = 0; a < nu; ++a)
    for (std::size_t b = 0; b < nv; ++b) {
      m.normals[a * nv + b] = s.normal(us[a], vs[b]);
      m.uvs[a * nv + b] = Vec2(us[a], vs[b]);
    }
  auto idx = [&](std::size_t a, std::size_t b) { return std::uint32_t(a * nv + b); };
  auto keep = [&](double u, double v) { return s.inside_trim(u, v); };
  for (std::size_t a = 0; a + 1 < nu; ++a)
    for (std::size_t b = 0; b + 1 < nv; ++b) {
      if (keep((us[a] + 2 * us[a + 1]) / 3, (2 * vs[b] + vs[b + 1]) / 3))
        m.add_triangle(idx(a, b), idx(a + 1, b), idx(a + 1, b + 1), face_id);
      if (keep((2 * us[a] + us[a + 1]) / 3, (vs[b] + 2 * vs[b + 1]) / 3))
        m.add_triangle(idx(a, b), idx(a + 1, b + 1), idx(a, b + 1), face_id);
    }
  return m;
}

Mesh tessellate_grid_welded(const Surface& s, const std::vector<double>& us, const std::vector<double>& vs,
                            int face_id, const std::vector<Point3>* points) {
  if (us.size() < 2 || vs.size() < 2) fail("welded mesh: need at least two parameters in each direction");
  const std::size_t nu = us.size(), nv = vs.size();
  std::vector<Point3> grid;
  if (points && points->size() == nu * nv) grid = *points;
  else {
    grid.resize(nu * nv);
    for (std::size_t a = 0; a < nu; ++a)
      for (std::size_t b = 0; b < nv; ++b) grid[a * nv + b] = s.eval(us[a], vs[b]);
  }
  auto at = [&](std::size_t a, std::size_t b) -> const Point3& { return grid[a * nv + b]; };
  // Coincidence is judged relative to the surface's size: its grid's bounding-box diagonal.
  Box3 box;
  for (const Point3& p : grid) box.extend(p);
  const double eps = 1e-9 * std::max(box.diagonal(), 1e-300);
  auto same = [&](const Point3& p, const Point3& q) { return (p - q).norm() <= eps; };
  bool u_seam = true, v_seam = true;
  for (std::size_t b = 0; b < nv && u_seam; ++b) u_seam = same(at(0, b), at(nu - 1, b));
  for (std::size_t a = 0; a < nu && v_seam; ++a) v_seam = same(at(a, 0), at(a, nv - 1));
  // A pole: a whole row of constant u (u_pole[a]) or column of constant v (v_pole[b]) at one point.
  std::vector<char> u_pole(nu, 1), v_pole(nv, 1);
  for (std::size_t a = 0; a < nu; ++a)
    for (std::size_t b = 1; b < nv && u_pole[a]; ++b) u_pole[a] = same(at(a, b), at(a, 0));
  for (std::size_t b = 0; b < nv; ++b)
    for (std::size_t a = 1; a < nu && v_pole[b]; ++a) v_pole[b] = same(at(a, b), at(0, b));
  // The grid point that stands for (a, b): across a seam the first row, on a pole its first point.
  auto canonical = [&](std::size_t a, std::size_t b) {
    if (u_seam && a == nu - 1) a = 0;
    if (v_seam && b == nv - 1) b = 0;
    if (v_pole[b]) a = 0;
    if (u_pole[a]) b = 0;
    return a * nv + b;
  };
  Mesh m;
  std::vector<std::uint32_t> index(nu * nv, UINT32_MAX);
  for (std::size_t a = 0; a < nu; ++a)
    for (std::size_t b = 0; b < nv; ++b) {
      std::size_t c = canonical(a, b);
      if (index[c] == UINT32_MAX) {
        index[c] = m.add_vertex(grid[c]);
        std::size_t ca = c / nv, cb = c % nv;
        Vec3 n = s.normal(us[ca], vs[cb]);
        Vec2 uv(us[ca], vs[cb]);
        // A pole's limit normal: the mean of the normals found stepping in from each point of the
        // collapsed row (all equal on a smooth pole; the axis direction at a cone's apex).
        if (v_pole[cb] || u_pole[ca]) {
          Vec3 sum = Vec3::Zero();
          if (v_pole[cb])
            for (std::size_t k = 0; k + 1 < nu; ++k) sum += s.normal(us[k], vs[cb]);
          else
            for (std::size_t k = 0; k + 1 < nv; ++k) sum += s.normal(us[ca], vs[k]);
          if (sum.norm() > 1e-12) n = sum.normalized();
          if (v_pole[cb]) uv.x() = 0.5 * (us.front() + us.back());
          else uv.y() = 0.5 * (vs.front() + vs.back());
        }
        m.normals.push_back(n);
        m.uvs.push_back(uv);
      }
      index[a * nv + b] = index[c];
    }
  auto keep = [&](double u, double v) { return s.inside_trim(u, v); };
  auto add = [&](std::size_t i, std::size_t j, std::size_t k) {
    std::uint32_t x = index[i], y = index[j], z = index[k];
    if (x != y && y != z && z != x) m.add_triangle(x, y, z, face_id);  // no slivers at a pole
  };
  for (std::size_t a = 0; a + 1 < nu; ++a)
    for (std::size_t b = 0; b + 1 < nv; ++b) {
      if (keep((us[a] + 2 * us[a + 1]) / 3, (2 * vs[b] + vs[b + 1]) / 3))
        add(a * nv + b, (a + 1) * nv + b, (a + 1) * nv + b + 1);
      if (keep((2 * us[a] + us[a + 1]) / 3, (vs[b] + 2 * vs[b + 1]) / 3))
        add(a * nv + b, (a + 1) * nv + b + 1, a * nv + b + 1);
    }
  // A closed result faces outward: if Su x Sv points in (a profile drawn the other way round),
  // reverse the triangles and the normals so the mesh is a solid's boundary.
  bool closed = s.trims.empty() && (u_seam || (u_pole[0] && u_pole[nu - 1])) && (v_seam || (v_pole[0] && v_pole[nv - 1]));
  if (closed && m.volume() < 0) {
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
    for (auto& n : m.normals) n = -n;
  }
  return m;
}

Mesh tessellate_patches(const std::vector<SurfacePtr>& patches, double tolerance, std::size_t max_triangles) {
  if (patches.empty()) return Mesh();
  if (patches.size() == 1) return tessellate(*patches[0], tolerance, 0, max_triangles);
  // Patches meshed independently would sample a shared edge at different points and leave cracks
  // (T-junctions). Instead every patch gets the same uniform grid, as fine as the most demanding
  // patch needs, so shared edges get the same points.
  std::size_t n = 1;
  bool trimmed = false;
  for (const auto& p : patches) {
    trimmed = trimmed || !p->trims.empty();
    Mesh m = tessellate(*p, tolerance, -1, max_triangles);
    std::vector<double> us, vs;
    for (const auto& uv : m.uvs) {
      us.push_back(uv.x());
      vs.push_back(uv.y());
    }
    for (auto* t : {&us, &vs}) {
      std::sort(t->begin(), t->end());
      n = std::max(n, std::size_t(std::unique(t->begin(), t->end()) - t->begin()) - 1);
    }
  }
  // Every untrimmed patch gets the n x n grid: the whole is known before any of it is made.
  if (!trimmed && 2 * n * n * patches.size() > max_triangles) over_budget(2 * n * n * patches.size(), tolerance, max_triangles);
  Mesh all;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    const Surface& p = *patches[i];
    Mesh m;
    if (trimmed) {
      m = tessellate(p, tolerance, int(i), max_triangles - std::min(max_triangles, all.triangle_count()));
    } else {
      auto [u0, u1] = p.u_domain();
      auto [v0, v1] = p.v_domain();
      std::vector<double> us(n + 1), vs(n + 1);
      for (std::size_t k = 0; k <= n; ++k) {
        us[k] = k == n ? u1 : u0 + (u1 - u0) * double(k) / double(n);
        vs[k] = k == n ? v1 : v0 + (v1 - v0) * double(k) / double(n);
      }
      m = tessellate_grid(p, us, vs, int(i));
    }
    if (i == 0) all = std::move(m);
    else all.append(m);
  }
  return all;
}

}  // namespace wedge
