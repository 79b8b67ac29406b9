// validate(): the structural and geometric rules of a winged-edge solid, checked from the stored
// pointers alone (never from the counters), each failure reported in words with the element ids.
//
// Order of the rules: wings present and pointing back (the "broken wing" and "open loop" cases),
// each loop a closed cycle of sides that name it, every side in exactly one loop (a side no loop
// reaches is a dangling edge), every vertex a single fan of edges (2-manifold), faces and loops
// naming each other, shells as connected components found by traversal, and the genus of each
// shell from its Euler characteristic V − E + F − R = 2 − 2g, summed against H. Geometry: plane
// faces flat and their loops simple (segment tests with the exact orient2d of kernel/predicates),
// outer loops counter-clockwise about the outward normal and rings clockwise (Newell normals),
// and a positive enclosed volume.
#include <array>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "brep/brep.h"
#include "kernel/scaled.h"

namespace wedge {

namespace {
std::string side_name(EdgeSide s) {
  std::ostringstream o;
  o << "edge " << s.edge.value << " side " << s.side;
  return o.str();
}
Validation bad(const std::string& m) { return Validation{false, m}; }

// A floating-point filter before the exact segment test: false only when one segment lies
// clearly on one side of the other's line (by a margin far above the rounding error).
bool may_cross(const Point2& p, const Point2& q, const Point2& a, const Point2& b) {
  auto side = [](const Point2& o, const Point2& d, const Point2& x) {
    double det = (d.x() - o.x()) * (x.y() - o.y()) - (d.y() - o.y()) * (x.x() - o.x());
    double mag = (std::abs(d.x() - o.x()) + std::abs(d.y() - o.y())) * (std::abs(x.x() - o.x()) + std::abs(x.y() - o.y()));
    return det > 1e-12 * mag ? 1 : det < -1e-12 * mag ? -1 : 0;
  };
  int sa = side(p, q, a), sb = side(p, q, b);
  if (sa != 0 && sa == sb) return false;
  int sp = side(a, b, p), sq = side(a, b, q);
  if (sp != 0 && sp == sq) return false;
  return true;
}

// The first pair (i, j), i < j, in that order, of segments q[i] - q[i + 1] and q[j] - q[j + 1]
// (closing the loop) that meet and are not neighbours, or (0, 0) where the loop is simple. The
// segments are swept by their least x, each tested against those whose x ranges reach it and
// whose y ranges meet its own (every pair was tested before: a face of 20,000 corners, a cone's
// base, took 1.4 s to validate).
std::pair<std::size_t, std::size_t> first_crossing(const std::vector<Point2>& q) {
  const std::size_t m = q.size();
  struct Range {
    double xlo, xhi, ylo, yhi;
  };
  std::vector<Range> r(m);
  std::vector<std::size_t> order(m);
  for (std::size_t i = 0; i < m; ++i) {
    const Point2 &a = q[i], &b = q[(i + 1) % m];
    r[i] = {std::min(a.x(), b.x()), std::max(a.x(), b.x()), std::min(a.y(), b.y()), std::max(a.y(), b.y())};
    order[i] = i;
  }
  // (A coordinate that is not a number orders nothing: then every pair.)
  const bool finite = std::all_of(r.begin(), r.end(), [](const Range& x) { return std::isfinite(x.xlo + x.xhi + x.ylo + x.yhi); });
  if (finite)
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return r[a].xlo < r[b].xlo || (r[a].xlo == r[b].xlo && a < b); });
  std::pair<std::size_t, std::size_t> first{0, 0};
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t a = order[k];
    for (std::size_t l = k + 1; l < m && (!finite || r[order[l]].xlo <= r[a].xhi); ++l) {
      const std::size_t b = order[l];
      if (finite && (r[b].ylo > r[a].yhi || r[a].ylo > r[b].yhi)) continue;
      const std::size_t i = std::min(a, b), j = std::max(a, b);
      if (j == i + 1 || (i == 0 && j == m - 1)) continue;  // neighbours share a corner
      if (first.first != first.second && std::make_pair(i, j) >= first) continue;
      if (may_cross(q[i], q[(i + 1) % m], q[j], q[(j + 1) % m]) && segments_intersect_2d(q[i], q[(i + 1) % m], q[j], q[(j + 1) % m]))
        first = {i, j};
    }
  }
  return first;
}

}  // namespace

void Model::append_arc_interior(EdgeSide s, int arc_segments, std::vector<Point3>& out) const {
  if (!curves_[s.edge]) return;
  for (int k = 1; k < arc_segments; ++k) out.push_back(edge_point(s.edge, double(s.side == 0 ? k : arc_segments - k) / arc_segments));
}

std::vector<Point3> Model::side_polyline(EdgeSide s, int arc_segments) const {
  std::vector<Point3> out{point(origin(s))};
  append_arc_interior(s, arc_segments, out);
  out.push_back(point(dest(s)));
  return out;
}

std::vector<Point3> Model::loop_polyline(LoopId l, int arc_segments) const {
  const BrepLoop& lp = loops_[l];
  if (!lp.first.valid()) return {point(lp.lone)};
  std::vector<Point3> out;
  EdgeSide s = lp.first;
  std::size_t guard = 2 * edges_.capacity() + 2, n = 0;
  do {
    out.push_back(point(origin(s)));
    append_arc_interior(s, arc_segments, out);
    s = side(s).next;
    if (++n > guard) fail("loop ", l.value, " is not a closed cycle");
  } while (!(s == lp.first));
  return out;
}

Vec3 Model::face_normal(FaceId f) const {
  if (const Plane* pl = surface(f).plane()) return pl->unit_normal();
  return unit_vector(newell_normal(loop_polyline(faces_[f].outer)));
}

namespace {

// The extremes of a curve or face along each axis, both ways: the best of a grid of samples,
// refined by a pattern search (a step each way along each parameter, moved while it gains, halved
// while it does not): sampled alone, a sphere of radius 5 turned by 10 degrees about z had its box
// 4.9952 wide each way, and a point inside it lay outside its box. A grid of (n + 1)^dims points
// over the parameters' ranges, each [lo, hi].
template <int dims>
struct Extremes {
  using P = std::array<double, dims>;
  std::array<std::pair<double, double>, dims> range;
  int n = 0;
  P best[3][2];      // the best sample for each of the six extremes
  double top[3][2];  // its value (the coordinate, negated for the low side)
  double jump[3];    // the largest change of each coordinate between neighbouring samples

  // `grid`: the points, the last parameter's index varying fastest.
  void sample(Box3& b, const std::vector<Point3>& grid) {
    for (auto& t : top) t[0] = t[1] = -INFINITY;
    jump[0] = jump[1] = jump[2] = 0;
    const int m = n + 1;
    std::array<std::size_t, dims> stride;
    for (int d = dims - 1, size = 1; d >= 0; --d) stride[d] = static_cast<std::size_t>(size), size *= m;
    std::array<int, dims> idx{};
    for (std::size_t k = 0; k < grid.size(); ++k) {
      const Point3& x = grid[k];
      b.extend(x);
      // The neighbour one step back along each parameter.
      for (int d = 0; d < dims; ++d)
        if (idx[d] > 0) {
          const Point3& y = grid[k - stride[d]];
          for (int axis = 0; axis < 3; ++axis) jump[axis] = std::max(jump[axis], std::abs(x[axis] - y[axis]));
        }
      for (int axis = 0; axis < 3; ++axis)
        for (int w = 0; w < 2; ++w)
          if (const double v = w ? -x[axis] : x[axis]; v > top[axis][w]) {
            top[axis][w] = v;
            for (int d = 0; d < dims; ++d) best[axis][w][d] = range[d].first + (range[d].second - range[d].first) * idx[d] / n;
          }
      for (int d = dims - 1; d >= 0 && ++idx[d] == m; --d) idx[d] = 0;
    }
  }

  // Refines the extremes that may reach past `reach` (the box of every sample): those whose best
  // sample is within a neighbour's change of it. (Between samples a smooth coordinate passes its
  // best sample by an eighth of such a change where it is about quadratic.) Refining the rest
  // changed nothing and was most of a revolve's validate(): 20,000 faces, each 49 x 49 samples
  // and six searches.
  template <class Eval>
  void refine(Box3& b, const Box3& reach, Eval&& eval) const {
    for (int axis = 0; axis < 3; ++axis)
      for (int w = 0; w < 2; ++w) {
        const double edge = w ? -reach.min[axis] : reach.max[axis];
        if (!(top[axis][w] + jump[axis] >= edge)) continue;
        P at = best[axis][w];
        double value = top[axis][w];
        P step;
        for (int d = 0; d < dims; ++d) step[d] = (range[d].second - range[d].first) / n;
        for (int round = 0; round < 200; ++round) {
          bool moved = false, any = false;
          for (int d = 0; d < dims; ++d) {
            if (!(step[d] > 1e-12 * (range[d].second - range[d].first))) continue;
            any = true;
            for (double way : {1.0, -1.0}) {
              P q = at;
              q[d] = std::clamp(at[d] + way * step[d], range[d].first, range[d].second);
              const Point3 x = eval(q);
              if (const double v = w ? -x[axis] : x[axis]; v > value) value = v, at = q, moved = true;
            }
          }
          if (!any) break;
          if (!moved)
            for (int d = 0; d < dims; ++d) step[d] /= 2;
        }
        b.extend(eval(at));
      }
  }
};

// n + 1 parameters spread evenly over [lo, hi].
std::vector<double> spread(std::pair<double, double> range, int n) {
  std::vector<double> t(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) t[static_cast<std::size_t>(i)] = range.first + (range.second - range.first) * i / n;
  return t;
}

// The box of a model's vertices and of a grid of 9 points on each curve, 9 x 9 on each face: the
// size of its box to within a few percent, for tolerances.
Box3 coarse_box(const Model& m) {
  Box3 b;
  m.vertices().for_each([&](VertexId v, const BrepVertex&) { b.extend(m.point(v)); });
  m.edges().for_each([&](EdgeId e, const BrepEdge&) {
    if (const CurvePtr& c = m.curve(e))
      for (double t : spread(c->domain(), 8)) b.extend(c->eval(t));
  });
  std::array<Point3, 81> grid;
  m.faces().for_each([&](FaceId f, const BrepFace&) {
    const FaceSurface& fs = m.surface(f);
    if (!fs.parametric) return;
    const std::vector<double> us = spread(fs.surface->u_domain(), 8), vs = spread(fs.surface->v_domain(), 8);
    fs.surface->eval_grid(us.data(), 9, vs.data(), 9, grid.data());
    for (const Point3& p : grid) b.extend(p);
  });
  return b;
}

}  // namespace

Box3 Model::bounds() const {
  Box3 b;
  vertices_.for_each([&](VertexId v, const BrepVertex&) { b.extend(point(v)); });
  // Arcs bulge past their ends, curved faces past their edges: their extremes along each axis,
  // sampled first, then refined where they may reach past every sample.
  std::vector<std::pair<const Curve*, Extremes<1>>> curves;
  std::vector<std::pair<const Surface*, Extremes<2>>> faces;
  std::vector<Point3> grid;
  edges_.for_each([&](EdgeId e, const BrepEdge&) {
    const CurvePtr& c = curve(e);
    if (!c) return;
    Extremes<1> x;
    x.range = {c->domain()};
    x.n = 64;
    grid.clear();
    for (double t : spread(x.range[0], x.n)) grid.push_back(c->eval(t));
    x.sample(b, grid);
    curves.push_back({c.get(), x});
  });
  faces_.for_each([&](FaceId f, const BrepFace&) {
    const FaceSurface* ps = &surface(f);
    if (!ps->parametric) return;
    const Surface& s = *ps->surface;
    Extremes<2> x;
    x.range = {s.u_domain(), s.v_domain()};
    x.n = 48;
    const std::vector<double> us = spread(x.range[0], x.n), vs = spread(x.range[1], x.n);
    grid.resize(us.size() * vs.size());
    s.eval_grid(us.data(), static_cast<int>(us.size()), vs.data(), static_cast<int>(vs.size()), grid.data());
    x.sample(b, grid);
    faces.push_back({&s, x});
  });
  const Box3 reach = b;
  for (const auto& [c, x] : curves) x.refine(b, reach, [&](const std::array<double, 1>& t) { return c->eval(t[0]); });
  for (const auto& [s, x] : faces) x.refine(b, reach, [&](const std::array<double, 2>& uv) { return s->eval(uv[0], uv[1]); });
  return b;
}

bool Model::all_planar() const {
  bool ok = true;
  faces_.for_each([&](FaceId f, const BrepFace&) {
    if (surface(f).surface && !surface(f).plane()) ok = false;
  });
  edges_.for_each([&](EdgeId e, const BrepEdge&) {
    if (curve(e)) ok = false;
  });
  return ok;
}

double Model::approximate_volume() const {
  if (has_param_faces()) return exact_mass(true).volume;
  Point3 ref = bounds().center();
  double vol = 0;
  auto tri = [&](const Point3& a, const Point3& b, const Point3& c) { vol += (a - ref).dot((b - ref).cross(c - ref)) / 6.0; };
  faces_.for_each([&](FaceId f, const BrepFace& face) {
    // A cylinder patch bounded by arc, line, arc, line: a strip of quads between the two arcs.
    if (surface(f).cylinder() && face.rings.empty()) {
      std::vector<EdgeSide> sides = loop_sides(face.outer);
      if (sides.size() == 4) {
        int k = curve(sides[0].edge) ? 0 : 1;
        std::vector<Point3> a = side_polyline(sides[static_cast<std::size_t>(k)]);
        std::vector<Point3> b = side_polyline(sides[static_cast<std::size_t>(k + 2)]);
        if (a.size() == b.size()) {
          std::reverse(b.begin(), b.end());
          for (std::size_t i = 0; i + 1 < a.size(); ++i) {
            tri(a[i], a[i + 1], b[i + 1]);
            tri(a[i], b[i + 1], b[i]);
          }
          return;
        }
      }
    }
    std::vector<LoopId> ls{face.outer};
    ls.insert(ls.end(), face.rings.begin(), face.rings.end());
    for (LoopId l : ls) {
      std::vector<Point3> p = loop_polyline(l);
      for (std::size_t i = 1; i + 1 < p.size(); ++i) tri(p[0], p[i], p[i + 1]);
    }
  });
  return vol;
}

MassProperties Model::mass_properties() const {
  if (!all_planar()) {
    MassProperties e = exact_mass();
    if (!(e.volume > 0)) fail("mass properties: the model encloses no positive volume (", e.volume, ")");
    return e;
  }
  const MomentFrame frame(bounds());
  double volume = 0, area = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  faces_.for_each([&](FaceId f, const BrepFace& face) {
    Vec3 n = face_normal(f);
    auto add_loop = [&](LoopId l) {
      std::vector<Point3> p = loop_polyline(l);
      for (std::size_t i = 1; i + 1 < p.size(); ++i) {
        Vec3 a = frame.local(p[0]), b = frame.local(p[i]), c = frame.local(p[i + 1]);
        area += 0.5 * (b - a).cross(c - a).dot(n);
        // Signed tetrahedron (ref, a, b, c): volume, first and second moments (the covariance of
        // the canonical tetrahedron mapped by [a b c], Blow & Binstock 2004).
        double det = a.dot(b.cross(c));
        volume += det / 6.0;
        first += det / 24.0 * (a + b + c);
        Vec3 s = a + b + c;
        second += det / 120.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
      }
    };
    add_loop(face.outer);
    for (LoopId r : face.rings) add_loop(r);
  });
  MassProperties mp = frame.from_frame(volume, area, first, second);
  if (!(mp.volume > 0)) fail("mass properties: the model encloses no positive volume (", mp.volume, ")");
  return mp;
}

void Model::transform(const Mat4& m) {
  Mat3 lin = m.block<3, 3>(0, 0);
  double det = lin.determinant();
  if (!std::isfinite(det) || std::abs(det) < 1e-300) fail("transform: the matrix is singular");
  if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) fail("transform: a projective matrix cannot move a solid");
  double s = std::cbrt(std::abs(det));
  bool cylinders = false;  // the planar builders' cylinder faces stay circular only under similarities
  for (auto [f, c] : surfaces_) cylinders = cylinders || (faces_.contains(f) && c.cylinder());
  if (cylinders && !(lin.transpose() * lin).isApprox(s * s * Mat3::Identity(), 1e-9))
    fail("transform: a non-uniform scale or shear would turn arcs into ellipses; this model has circular edges");
  for (auto [v, p] : points_) p = apply_point(m, p);
  for (auto [e, c] : curves_)
    if (c) {
      c = transformed_curve(c, m);
      // A mirror swaps every edge's ends below: the curve then runs the other way.
      if (det < 0) c = reversed_curve(c);
      if (det < 0 && pcurves_.contains(e))
        for (auto& pcv : pcurves_[e])
          if (pcv) std::swap(pcv->start, pcv->end);
    }
  for (auto [id, f] : surfaces_) f = transformed_surface(f, m);
  if (det < 0) {
    // A mirror: reverse every loop so outer loops stay counter-clockwise seen from outside.
    edges_.for_each([&](EdgeId e, const BrepEdge&) {
      BrepEdge& ed = edges_[e];
      std::swap(ed.v[0], ed.v[1]);
      for (auto& sd : ed.side) std::swap(sd.next, sd.prev);
    });
    vertices_.for_each([&](VertexId v, const BrepVertex&) {
      BrepVertex& vx = vertices_[v];
      if (vx.out.valid()) vx.out = vx.out.mate();
    });
  }
}

const Plane* FaceSurface::plane() const { return parametric ? nullptr : dynamic_cast<const Plane*>(surface.get()); }
const Cylinder* FaceSurface::cylinder() const { return parametric ? nullptr : dynamic_cast<const Cylinder*>(surface.get()); }

FaceSurface plane_face(const Point3& point, const Vec3& unit_outward_normal) {
  return FaceSurface{std::make_shared<const Plane>(point, unit_outward_normal), false, false, "plane"};
}
FaceSurface cylinder_face(const Point3& origin, const Vec3& unit_axis, double radius, bool solid_outside) {
  return FaceSurface{std::make_shared<const Cylinder>(origin, unit_axis, radius), solid_outside, false, "cylinder"};
}
FaceSurface parametric_face(SurfacePtr surface, bool reversed, std::string kind) {
  return FaceSurface{std::move(surface), reversed, true, std::move(kind)};
}

SurfacePtr surface_patch(const FaceSurface& fs, const Box3& extent, bool& reversed) {
  reversed = false;
  if (fs.parametric) {
    reversed = fs.reversed;
    return fs.surface;
  }
  if (extent.empty()) return nullptr;
  auto range = [&](const Point3& o, const Vec3& d) {
    double lo = 1e300, hi = -1e300;
    for (int i = 0; i < 8; ++i) {
      const Vec3 c((i & 1) ? extent.max.x() : extent.min.x(), (i & 2) ? extent.max.y() : extent.min.y(),
                   (i & 4) ? extent.max.z() : extent.min.z());
      const double t = (c - o).dot(d);
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
    if (!(hi > lo)) hi = lo + 1;  // a flat box along d: any positive range
    return std::make_pair(lo, hi);
  };
  if (const Plane* pl = fs.plane()) {
    // x cross y = n: the plane's parameters run so that Su x Sv is the outward normal.
    auto [u0, u1] = range(pl->origin(), pl->x_axis());
    auto [v0, v1] = range(pl->origin(), pl->y_axis());
    return std::make_shared<const Plane>(pl->origin(), pl->x_axis(), pl->y_axis(), u0, u1, v0, v1);
  }
  if (const Cylinder* cy = fs.cylinder()) {
    // The circle runs counter-clockwise about the axis and is extruded along it: Su x Sv points
    // away from the axis.
    reversed = fs.reversed;
    auto [h0, h1] = range(cy->origin(), cy->axis());
    auto circle = std::make_shared<const CircularArc>(Point3(cy->origin() + h0 * cy->axis()), cy->radius(), 0.0, 2 * kPi,
                                                      cy->axis(), perpendicular(cy->axis()));
    return std::make_shared<const ExtrudedSurface>(circle, (h1 - h0) * cy->axis());
  }
  return nullptr;
}

FaceSurface flipped_surface(const FaceSurface& fs) {
  FaceSurface f = fs;
  if (const Plane* p = fs.plane()) f.surface = std::make_shared<const Plane>(p->origin(), Vec3(-p->unit_normal()));
  else if (f.surface) f.reversed = !f.reversed;
  return f;
}

FaceSurface transformed_surface(const FaceSurface& fs, const Mat4& m, const Box3& extent) {
  const Mat3 lin = m.block<3, 3>(0, 0);
  const double det = lin.determinant();
  FaceSurface f = fs;
  if (const Cylinder* c = fs.cylinder()) {
    const double s = std::cbrt(std::abs(det));
    if (!(lin.transpose() * lin).isApprox(s * s * Mat3::Identity(), 1e-9)) {
      bool reversed = false;
      SurfacePtr patch = surface_patch(fs, extent, reversed);
      if (!patch) fail("transform: a cylinder face under a non-uniform scale needs the box that holds it");
      f = parametric_face(patch, reversed, "cylinder");
    } else {
      f.surface = std::make_shared<const Cylinder>(apply_point(m, c->origin()), unit_vector(apply_vector(m, c->axis())),
                                                   c->radius() * s);
      return f;
    }
  }
  if (f.parametric) {
    f.surface = std::make_shared<const TransformedSurface>(f.surface, m);
    if (det < 0) f.reversed = !f.reversed;  // a mirror turns Su x Sv inward
  } else if (const Plane* p = f.plane()) {
    f.surface = std::make_shared<const Plane>(apply_point(m, p->origin()), apply_normal(m, p->unit_normal()));
  }
  return f;
}

Validation Model::validate(bool geometry) const {
  // 1. Wings: present, alive, pointing back, meeting end to end.
  Validation verdict;
  bool stop = false;
  edges_.for_each([&](EdgeId e, const BrepEdge& ed) {
    if (stop) return;
    for (int k = 0; k < 2; ++k)
      if (!vertices_.contains(ed.v[k])) {
        verdict = bad("edge " + std::to_string(e.value) + " names a missing vertex " + std::to_string(ed.v[k].value));
        stop = true;
        return;
      }
    if (ed.v[0] == ed.v[1]) {
      verdict = bad("edge " + std::to_string(e.value) + " starts and ends at vertex " + std::to_string(ed.v[0].value));
      stop = true;
      return;
    }
    for (int k = 0; k < 2 && !stop; ++k) {
      EdgeSide s{e, k};
      const BrepSide& sd = ed.side[k];
      if (!loops_.contains(sd.loop)) {
        verdict = bad(side_name(s) + " names no live loop (" + std::to_string(sd.loop.value) + ")");
        stop = true;
      } else if (!sd.next.valid() || !edges_.contains(sd.next.edge) || !sd.prev.valid() || !edges_.contains(sd.prev.edge)) {
        verdict = bad("loop " + std::to_string(sd.loop.value) + " is not closed: " + side_name(s) + " has no " +
                      (!sd.next.valid() || !edges_.contains(sd.next.edge) ? "successor" : "predecessor"));
        stop = true;
      }
    }
  });
  if (!verdict) return verdict;
  edges_.for_each([&](EdgeId e, const BrepEdge& ed) {
    for (int k = 0; k < 2 && !stop; ++k) {
      EdgeSide s{e, k};
      const BrepSide& sd = ed.side[k];
      if (!(side(sd.next).prev == s)) {
        verdict = bad("broken wing: the successor of " + side_name(s) + " is " + side_name(sd.next) +
                      ", whose predecessor is " + side_name(side(sd.next).prev) + ", not it");
        stop = true;
      } else if (!(side(sd.prev).next == s)) {
        verdict = bad("broken wing: the predecessor of " + side_name(s) + " is " + side_name(sd.prev) +
                      ", whose successor is " + side_name(side(sd.prev).next) + ", not it");
        stop = true;
      } else if (dest(s) != origin(sd.next)) {
        verdict = bad("broken wing: " + side_name(s) + " ends at vertex " + std::to_string(dest(s).value) + " but its successor " +
                      side_name(sd.next) + " starts at vertex " + std::to_string(origin(sd.next).value));
        stop = true;
      } else if (side(sd.next).loop != sd.loop) {
        verdict = bad(side_name(s) + " is in loop " + std::to_string(sd.loop.value) + " but its successor " +
                      side_name(sd.next) + " is in loop " + std::to_string(side(sd.next).loop.value));
        stop = true;
      }
    }
  });
  if (!verdict) return verdict;

  // 2. Loops: closed cycles from their first side; every side reached exactly once.
  std::vector<char> seen(2 * edges_.capacity(), 0);
  auto slot = [](EdgeSide s) { return 2 * static_cast<std::size_t>(s.edge.value) + static_cast<std::size_t>(s.side); };
  loops_.for_each([&](LoopId l, const BrepLoop& lp) {
    if (stop) return;
    if (!faces_.contains(lp.face)) {
      verdict = bad("loop " + std::to_string(l.value) + " names no live face");
      stop = true;
      return;
    }
    if (!lp.first.valid()) {
      if (!vertices_.contains(lp.lone)) {
        verdict = bad("loop " + std::to_string(l.value) + " has neither edges nor a lone vertex");
        stop = true;
      } else if (vertices_[lp.lone].out.valid()) {
        verdict = bad("vertex " + std::to_string(lp.lone.value) + " is the lone vertex of loop " + std::to_string(l.value) + " but has edges");
        stop = true;
      }
      return;
    }
    if (!edges_.contains(lp.first.edge) || side(lp.first).loop != l) {
      verdict = bad("loop " + std::to_string(l.value) + " starts at a side that is not in it");
      stop = true;
      return;
    }
    EdgeSide s = lp.first;
    do {
      if (seen[slot(s)]++) {
        verdict = bad("loop " + std::to_string(l.value) + " is not a closed cycle: it passes " + side_name(s) + " twice");
        stop = true;
        return;
      }
      s = side(s).next;
    } while (!(s == lp.first));
  });
  if (!verdict) return verdict;
  edges_.for_each([&](EdgeId e, const BrepEdge& ed) {
    if (stop) return;
    for (int k = 0; k < 2; ++k)
      if (!seen[slot({e, k})]) {
        verdict = bad("edge " + std::to_string(e.value) + " is dangling: its side " + std::to_string(k) + " lies on no loop's cycle (loop " +
                      std::to_string(ed.side[k].loop.value) + " does not pass through it)");
        stop = true;
        return;
      }
  });
  if (!verdict) return verdict;

  // 3. Vertices: `out` leaves the vertex, and the sides leaving it form one fan (2-manifold).
  std::vector<int> degree(vertices_.capacity(), 0);
  edges_.for_each([&](EdgeId, const BrepEdge& ed) {
    degree[static_cast<std::size_t>(ed.v[0].value)]++;
    degree[static_cast<std::size_t>(ed.v[1].value)]++;
  });
  vertices_.for_each([&](VertexId v, const BrepVertex& vx) {
    if (stop) return;
    int deg = degree[static_cast<std::size_t>(v.value)];
    std::string name = "vertex " + std::to_string(v.value);
    if (!vx.out.valid()) {
      if (deg) verdict = bad(name + " has edges but no outgoing side recorded");
      stop = !verdict.ok;
      return;
    }
    if (!edges_.contains(vx.out.edge) || origin(vx.out) != v) {
      verdict = bad(name + " records an outgoing side that does not start at it");
      stop = true;
      return;
    }
    int n = 0;
    EdgeSide s = vx.out;
    do {
      ++n;
      s = side(s).prev.mate();
    } while (!(s == vx.out) && n <= deg);
    if (n != deg) {
      verdict = bad(name + " is not 2-manifold: its " + std::to_string(deg) + " edges do not form a single fan (" +
                    std::to_string(n) + " reached around it)");
      stop = true;
    }
  });
  if (!verdict) return verdict;

  // 4. Faces and loops name each other; every loop belongs to exactly one face.
  std::vector<int> owners(loops_.capacity(), 0);
  faces_.for_each([&](FaceId f, const BrepFace& face) {
    if (stop) return;
    std::string name = "face " + std::to_string(f.value);
    if (!shells_.contains(face.shell)) {
      verdict = bad(name + " names no live shell");
      stop = true;
      return;
    }
    auto check = [&](LoopId l, const char* what) {
      if (!loops_.contains(l) || loops_[l].face != f) {
        verdict = bad(name + "'s " + what + " loop " + std::to_string(l.value) + " does not name the face back");
        stop = true;
        return;
      }
      owners[static_cast<std::size_t>(l.value)]++;
    };
    check(face.outer, "outer");
    for (LoopId r : face.rings)
      if (!stop) check(r, "inner");
  });
  if (!verdict) return verdict;
  loops_.for_each([&](LoopId l, const BrepLoop&) {
    if (!stop && owners[static_cast<std::size_t>(l.value)] != 1) {
      verdict = bad("loop " + std::to_string(l.value) + " is listed by " + std::to_string(owners[static_cast<std::size_t>(l.value)]) + " faces, not one");
      stop = true;
    }
  });
  if (!verdict) return verdict;

  // 5. Shells by traversal, then the genus of each.
  std::vector<int> comp(faces_.capacity(), -1);
  int ncomp = 0;
  long genus_total = 0;
  std::vector<char> vseen(vertices_.capacity(), 0);
  for (FaceId start : faces_.ids()) {
    if (comp[static_cast<std::size_t>(start.value)] >= 0) continue;
    int c = ncomp++;
    std::vector<FaceId> queue{start};
    comp[static_cast<std::size_t>(start.value)] = c;
    long V = 0, E2 = 0, F = 0, R = 0;
    for (std::size_t qi = 0; qi < queue.size(); ++qi) {
      FaceId f = queue[qi];
      const BrepFace& face = faces_[f];
      if (face.shell != faces_[start].shell) {
        verdict = bad("faces " + std::to_string(start.value) + " and " + std::to_string(f.value) +
                      " are connected but name different shells " + std::to_string(faces_[start].shell.value) + " and " +
                      std::to_string(face.shell.value));
        return verdict;
      }
      ++F;
      R += static_cast<long>(face.rings.size());
      for (std::size_t li = 0; li <= face.rings.size(); ++li) {
        LoopId l = li == 0 ? face.outer : face.rings[li - 1];
        const BrepLoop& lp = loops_[l];
        if (!lp.first.valid()) {
          if (!vseen[static_cast<std::size_t>(lp.lone.value)]) vseen[static_cast<std::size_t>(lp.lone.value)] = 1, ++V;
          continue;
        }
        EdgeSide s = lp.first;
        do {
          // (a flag, not a count: a char counted past 255 sides from one vertex wrapped to 0 and
          // counted the vertex again, so a cone of 500 sides as a polyhedron was refused)
          if (!vseen[static_cast<std::size_t>(origin(s).value)]) vseen[static_cast<std::size_t>(origin(s).value)] = 1, ++V;
          ++E2;
          FaceId g = loops_[side(s.mate()).loop].face;
          if (comp[static_cast<std::size_t>(g.value)] < 0) {
            comp[static_cast<std::size_t>(g.value)] = c;
            queue.push_back(g);
          }
          s = side(s).next;
        } while (!(s == lp.first));
      }
    }
    if (shells_[faces_[start].shell].faces != F) {
      verdict = bad("shell " + std::to_string(faces_[start].shell.value) + " is not connected: face " + std::to_string(start.value) +
                    " reaches " + std::to_string(F) + " of its " + std::to_string(shells_[faces_[start].shell].faces) + " faces");
      return verdict;
    }
    long chi = V - E2 / 2 + F - R;
    if ((2 - chi) % 2 != 0 || chi > 2) {
      verdict = bad("shell " + std::to_string(faces_[start].shell.value) + " has Euler characteristic V - E + F - R = " +
                    std::to_string(chi) + ", which gives no integer genus >= 0");
      return verdict;
    }
    genus_total += (2 - chi) / 2;
  }
  if (static_cast<std::size_t>(ncomp) != shells_.size())
    return bad("the faces form " + std::to_string(ncomp) + " connected shells but the model records " + std::to_string(shells_.size()));
  if (genus_total != holes_)
    return bad("the shells' genus totals " + std::to_string(genus_total) + " through-holes but the model records H = " + std::to_string(holes_));

  if (!geometry) return verdict;

  // 6. Geometry.
  // (The tolerances' scale: the box of the vertices and a coarse grid on each curve and face, no
  // refinement; bounds() made two thirds of a 20,000-face revolve's validate().)
  double scale = std::max(coarse_box(*this).diagonal(), 1e-300);
  double tol = 1e-7 * scale;
  for (FaceId f : faces_.ids()) {
    const BrepFace& face = faces_[f];
    std::string name = "face " + std::to_string(f.value);
    if (surface(f).cylinder()) continue;
    if (const FaceSurface* ps = &surface(f); ps->parametric) {
      // Every side carries its image in the face's domain, the images of consecutive sides meet
      // or are joined by a pole (a stretch of the domain's border that maps to the shared
      // vertex), and the ends of each image map onto the side's vertices.
      std::vector<LoopId> ls{face.outer};
      ls.insert(ls.end(), face.rings.begin(), face.rings.end());
      for (LoopId l : ls)
        for (EdgeSide sd : loop_sides(l)) {
          const PCurve* pc = pcurve(sd);
          if (!pc) return bad(name + ": " + side_name(sd) + " has no curve in the face's parameter domain");
          Point3 a = ps->surface->eval(pc->start.x(), pc->start.y());
          Point3 b = ps->surface->eval(pc->end.x(), pc->end.y());
          const BrepEdge& ed = edges_[sd.edge];
          if ((a - point(ed.v[0])).norm() > tol || (b - point(ed.v[1])).norm() > tol)
            return bad(name + ": the ends of " + side_name(sd) + " are not where the face's surface puts them");
          Point3 m = ps->surface->eval(pc->at(0.5).x(), pc->at(0.5).y());
          if ((m - edge_point(sd.edge, 0.5)).norm() > tol)
            return bad(name + ": " + side_name(sd) + " leaves the face's surface");
        }
      continue;
    }
    Vec3 n = face_normal(f);
    if (n.norm() < 0.5) return bad(name + " has no normal: its outer loop encloses no area");
    const BrepLoop& outer_loop = loops_[face.outer];
    Point3 p0 = point(outer_loop.first.valid() ? origin(outer_loop.first) : outer_loop.lone);
    if (const Plane* pl = surface(f).plane()) p0 = pl->origin();
    std::vector<LoopId> ls{face.outer};
    ls.insert(ls.end(), face.rings.begin(), face.rings.end());
    // 2D projection: drop the dominant axis of n, keeping counter-clockwise about n.
    int ax = 0;
    n.cwiseAbs().maxCoeff(&ax);
    int i0 = (ax + 1) % 3, i1 = (ax + 2) % 3;
    if (n[ax] < 0) std::swap(i0, i1);
    for (LoopId l : ls) {
      std::vector<Point3> pts = loop_polyline(l);
      for (const Point3& p : pts)
        if (std::abs((p - p0).dot(n)) > tol)
          return bad(name + " is not planar: loop " + std::to_string(l.value) + " has a point " + std::to_string((p - p0).dot(n)) +
                     " off its plane");
      if (pts.size() < 3) return bad(name + "'s loop " + std::to_string(l.value) + " has fewer than three corners");
      std::vector<Point2> q;
      for (const Point3& p : pts) q.emplace_back(p[i0], p[i1]);
      if (auto [i, j] = first_crossing(q); i != j)
        return bad(name + "'s loop " + std::to_string(l.value) + " intersects itself (segments " + std::to_string(i) + " and " +
                   std::to_string(j) + ")");
      Vec3 nl = newell_normal(pts);
      bool outer = l == face.outer;
      if (outer && nl.dot(n) <= 0) return bad(name + "'s outer loop " + std::to_string(l.value) + " is not counter-clockwise seen from outside");
      if (!outer && nl.dot(n) >= 0) return bad(name + "'s inner loop " + std::to_string(l.value) + " is not clockwise seen from outside");
    }
  }
  double vol = approximate_volume();
  if (!(vol > 0)) return bad("the solid does not enclose a positive volume (" + std::to_string(vol) + "): its faces point inwards or it is flat");
  return verdict;
}

}  // namespace wedge
