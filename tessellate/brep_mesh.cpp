// The B-Rep tessellator (tessellate/brep_mesh.h).
//
// Edges: recursive bisection of the parameter interval from the curve's breaks, until the
// polyline's chord stays within the chordal tolerance of the curve at three interior samples and
// the tangent turns by less than the angular tolerance over each segment.
//
// Curved faces: the face's loops are mapped into (u, v) through the PCurves of their sides; where
// the image of one side ends away from the start of the next, the stretch between them is a pole
// (it maps to the one shared vertex) and gets points of its own that all carry that vertex. The
// (u, v) plane is scaled by the surface's mean |Su| and |Sv| so that Delaunay's angles mean
// something in 3D. Refinement: each triangle inside the face is checked at its centroid and at the
// midpoints of its free edges (distance between the surface at those parameters and the flat
// triangle's point) and by the angle between the surface normals at its corners; the worst place
// of a triangle over the tolerance gets a new point; repeat until none does. A triangle whose
// corners include one vertex twice (at a pole) is dropped: its neighbours close the fan.
#include "tessellate/brep_mesh.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <unordered_map>

#include "tessellate/planar.h"

namespace wedge {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VInfo {
  std::uint32_t index = 0;
  Vec2 uv = Vec2::Zero();
  int free_axis = -1;  // on a pole: the parameter (0: u, 1: v) along which the point does not move
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VInfo, K>;
struct FInfo {
  int depth = -1;   // nesting depth: odd inside the face
  // The corners it had when it was found within the tolerances (a flip reuses a face with new
  // corners: then they differ and it is checked again).
  const void* ok[3] = {nullptr, nullptr, nullptr};
};
using Fbi = CGAL::Triangulation_face_base_with_info_2<FInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Itag = CGAL::Exact_predicates_tag;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, Itag>;

double angle_between(const Vec3& a, const Vec3& b) {
  double na = a.norm(), nb = b.norm();
  if (na == 0 || nb == 0) return 0;
  return std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0));
}

double seg_distance(const Point3& p, const Point3& a, const Point3& b) {
  Vec3 d = b - a;
  double l2 = d.squaredNorm();
  double t = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

void mark_depth(CDT& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info().depth = -1;
  std::deque<std::pair<CDT::Face_handle, int>> queue{{cdt.infinite_face(), 0}};
  while (!queue.empty()) {
    auto [f, depth] = queue.front();
    queue.pop_front();
    if (f->info().depth != -1) continue;
    f->info().depth = depth;
    for (int i = 0; i < 3; ++i) {
      auto g = f->neighbor(i);
      if (g->info().depth != -1) continue;
      if (cdt.is_constrained(CDT::Edge(f, i))) queue.emplace_back(g, depth + 1);
      else queue.emplace_front(g, depth);
    }
  }
}

struct EdgeSamples {
  std::vector<double> s;              // interior fractions of the parameter range, increasing
  std::vector<std::uint32_t> index;   // their mesh vertices
};

}  // namespace

std::vector<double> curve_parameters(const Curve& c, const Tolerance& tol) {
  auto [t0, t1] = c.domain();
  std::vector<double> cuts{t0};
  for (double t : c.breaks())
    if (t > t0 && t < t1) cuts.push_back(t);
  cuts.push_back(t1);
  std::sort(cuts.begin(), cuts.end());
  double ang = radians(tol.angular);
  std::vector<double> out{t0};
  std::function<void(double, double, const Point3&, const Point3&, int)> rec = [&](double a, double b, const Point3& pa,
                                                                                 const Point3& pb, int depth) {
    double m = (a + b) / 2;
    Point3 pm = c.eval(m);
    bool split = false;
    if (depth < 24) {
      for (double f : {0.25, 0.5, 0.75}) {
        Point3 q = f == 0.5 ? pm : c.eval(a + f * (b - a));
        if (seg_distance(q, pa, pb) > tol.chordal) split = true;
      }
      if (!split && angle_between(c.derivative(a, 1), c.derivative(b, 1)) > ang) split = true;
    }
    if (split) {
      rec(a, m, pa, pm, depth + 1);
      rec(m, b, pm, pb, depth + 1);
    } else {
      out.push_back(b);
    }
  };
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    if (!(cuts[i + 1] > cuts[i])) continue;
    // At least two pieces per smooth stretch, so a half circle never becomes one chord.
    double m = (cuts[i] + cuts[i + 1]) / 2;
    Point3 a = c.eval(cuts[i]), pm = c.eval(m), b = c.eval(cuts[i + 1]);
    bool straight = seg_distance(pm, a, b) <= 1e-12 * (a - b).norm() &&
                    seg_distance(c.eval(cuts[i] + 0.25 * (cuts[i + 1] - cuts[i])), a, b) <= 1e-12 * (a - b).norm();
    if (straight) {
      out.push_back(cuts[i + 1]);
      continue;
    }
    rec(cuts[i], m, a, pm, 1);
    rec(m, cuts[i + 1], pm, b, 1);
  }
  return out;
}

Mesh tessellate(const Model& m, const Tolerance& tol_in) {
  Tolerance tol = tol_in;
  if (!(tol.chordal > 0)) fail("tessellate: the chordal tolerance must be positive");
  if (!(tol.angular > 0)) tol.angular = 180;
  Mesh out;
  std::unordered_map<std::int32_t, std::uint32_t> vindex;
  m.vertices().for_each([&](VertexId v, const BrepVertex&) { vindex[v.value] = out.add_vertex(m.point(v)); });
  std::unordered_map<std::int32_t, EdgeSamples> samples;
  m.edges().for_each([&](EdgeId e, const BrepEdge&) {
    if (std::holds_alternative<LineCurve>(m.curve(e))) return;
    CurvePtr c = m.edge_curve(e);
    auto [t0, t1] = c->domain();
    std::vector<double> ts = curve_parameters(*c, tol);
    EdgeSamples& es = samples[e.value];
    for (std::size_t i = 1; i + 1 < ts.size(); ++i) {
      es.s.push_back((ts[i] - t0) / (t1 - t0));
      es.index.push_back(out.add_vertex(c->eval(ts[i])));
    }
  });
  // A side's points from its start (included) to its end (excluded), with their fractions s of
  // the edge's parameter range.
  auto side_points = [&](EdgeSide s, std::vector<std::uint32_t>& idx, std::vector<double>& fr) {
    const BrepEdge& ed = m.edges()[s.edge];
    idx.clear();
    fr.clear();
    auto it = samples.find(s.edge.value);
    if (s.side == 0) {
      idx.push_back(vindex.at(ed.v[0].value));
      fr.push_back(0);
      if (it != samples.end())
        for (std::size_t i = 0; i < it->second.s.size(); ++i) {
          idx.push_back(it->second.index[i]);
          fr.push_back(it->second.s[i]);
        }
    } else {
      idx.push_back(vindex.at(ed.v[1].value));
      fr.push_back(1);
      if (it != samples.end())
        for (std::size_t i = it->second.s.size(); i-- > 0;) {
          idx.push_back(it->second.index[i]);
          fr.push_back(it->second.s[i]);
        }
    }
  };

  std::vector<std::uint32_t> idx;
  std::vector<double> fr;
  m.faces().for_each([&](FaceId f, const BrepFace& face) {
    std::vector<LoopId> ls{face.outer};
    ls.insert(ls.end(), face.rings.begin(), face.rings.end());
    const FaceSurface& fs = m.surface(f);
    if (auto* cyl = std::get_if<CylinderSurface>(&fs)) {
      (void)cyl;
      // The planar builders' cylinder patch: arc, line, arc, line, as a strip between the arcs.
      auto sides = m.loop_sides(face.outer);
      if (sides.size() != 4 || !face.rings.empty()) fail("tessellate: cylinder face ", f.value, " is not bounded by two arcs and two lines");
      int k = std::holds_alternative<ArcCurve>(m.curve(sides[0].edge)) ? 0 : 1;
      std::vector<std::uint32_t> a, b;
      side_points(sides[static_cast<std::size_t>(k)], a, fr);
      a.push_back(vindex.at(m.dest(sides[static_cast<std::size_t>(k)]).value));
      side_points(sides[static_cast<std::size_t>(k + 2)], b, fr);
      b.push_back(vindex.at(m.dest(sides[static_cast<std::size_t>(k + 2)]).value));
      if (a.size() != b.size()) fail("tessellate: cylinder face ", f.value, " has arcs of different lengths");
      std::reverse(b.begin(), b.end());
      for (std::size_t i = 0; i + 1 < a.size(); ++i) {
        out.add_triangle(a[i], a[i + 1], b[i + 1], f.value);
        out.add_triangle(a[i], b[i + 1], b[i], f.value);
      }
      return;
    }
    auto* ps = std::get_if<ParamSurface>(&fs);
    if (!ps) {
      std::vector<std::vector<std::uint32_t>> loops;
      for (LoopId l : ls) {
        std::vector<std::uint32_t> loop;
        for (EdgeSide s : m.loop_sides(l)) {
          side_points(s, idx, fr);
          loop.insert(loop.end(), idx.begin(), idx.end());
        }
        loops.push_back(std::move(loop));
      }
      for (const auto& t : triangulate_face(out.positions, loops, m.face_normal(f))) out.add_triangle(t[0], t[1], t[2], f.value);
      return;
    }
    const Surface& S = *ps->surface;
    auto [u0, u1] = S.u_domain();
    auto [v0, v1] = S.v_domain();
    // Scale of (u, v): the mean speeds of the surface along u and v.
    double su = 0, sv = 0;
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j) {
        double u = u0 + (u1 - u0) * (i + 0.5) / 9.0, v = v0 + (v1 - v0) * (j + 0.5) / 9.0;
        su += S.derivative(u, v, 1, 0).norm();
        sv += S.derivative(u, v, 0, 1).norm();
      }
    su = su > 0 ? su / 81 : 1;
    sv = sv > 0 ? sv / 81 : 1;
    auto to_plane = [&](const Vec2& uv) { return K::Point_2(uv.x() * su, uv.y() * sv); };

    CDT cdt;
    struct LoopPt {
      std::uint32_t index;
      Vec2 uv;
      int free_axis = -1;
    };
    for (LoopId l : ls) {
      std::vector<LoopPt> pts;
      std::vector<std::pair<Vec2, Vec2>> ends;  // each side's first and last uv
      std::vector<std::vector<LoopPt>> per_side;
      for (EdgeSide s : m.loop_sides(l)) {
        const PCurve* pc = m.pcurve(s);
        if (!pc) fail("tessellate: face ", f.value, ": edge ", s.edge.value, " has no parameter-space curve on it");
        side_points(s, idx, fr);
        std::vector<LoopPt> sp;
        for (std::size_t i = 0; i < idx.size(); ++i) sp.push_back({idx[i], pc->at(fr[i])});
        per_side.push_back(std::move(sp));
        ends.emplace_back(pc->at(s.side == 0 ? 0.0 : 1.0), pc->at(s.side == 0 ? 1.0 : 0.0));
      }
      // Typical spacing of the real sides, in the scaled plane, for the points along poles.
      double spacing = 0;
      std::size_t count = 0;
      for (std::size_t i = 0; i < per_side.size(); ++i) {
        const auto& sp = per_side[i];
        for (std::size_t k = 0; k < sp.size(); ++k) {
          Vec2 a = sp[k].uv, b = k + 1 < sp.size() ? sp[k + 1].uv : ends[i].second;
          spacing += Vec2((b - a).x() * su, (b - a).y() * sv).norm();
          ++count;
        }
      }
      spacing = count ? spacing / static_cast<double>(count) : 1;
      for (std::size_t i = 0; i < per_side.size(); ++i) {
        pts.insert(pts.end(), per_side[i].begin(), per_side[i].end());
        Vec2 a = ends[i].second, b = ends[(i + 1) % ends.size()].first;
        Vec2 d(( b - a).x() * su, (b - a).y() * sv);
        if (d.norm() > 1e-12 * (1 + spacing)) {
          // A pole: the vertex between the two sides, along the domain's border.
          std::uint32_t pole = per_side[(i + 1) % per_side.size()][0].index;
          int n = std::max(2, static_cast<int>(std::ceil(d.norm() / std::max(spacing, 1e-300))));
          n = std::min(n, 4096);
          int axis = std::abs(d.x()) >= std::abs(d.y()) ? 0 : 1;
          // The pole's corners at both ends of the stretch are the sides' own points; mark the
          // stretch's points, whose one parameter is free.
          for (int k = 1; k < n; ++k) pts.push_back({pole, a + (b - a) * (double(k) / n), axis});
        }
      }
      std::vector<CDT::Vertex_handle> hs;
      for (const LoopPt& p : pts) {
        auto h = cdt.insert(to_plane(p.uv));
        h->info() = VInfo{p.index, p.uv, p.free_axis};
        hs.push_back(h);
      }
      for (std::size_t i = 0; i < hs.size(); ++i)
        if (hs[i] != hs[(i + 1) % hs.size()]) cdt.insert_constraint(hs[i], hs[(i + 1) % hs.size()]);
    }
    double sign = ps->reversed ? -1.0 : 1.0;
    auto pos = [&](std::uint32_t i) -> const Point3& { return out.positions[i]; };
    double ang = radians(tol.angular);
    std::size_t budget = 4'000'000;
    for (int round = 0; round < 400; ++round) {
      mark_depth(cdt);
      std::vector<Vec2> add;
      for (auto fh = cdt.finite_faces_begin(); fh != cdt.finite_faces_end(); ++fh) {
        if (fh->info().depth % 2 != 1) continue;
        const void* corners[3] = {&*fh->vertex(0), &*fh->vertex(1), &*fh->vertex(2)};
        if (std::equal(corners, corners + 3, fh->info().ok)) continue;
        VInfo e[3] = {fh->vertex(0)->info(), fh->vertex(1)->info(), fh->vertex(2)->info()};
        if (e[0].index == e[1].index || e[1].index == e[2].index || e[0].index == e[2].index) continue;
        // A corner on a pole stands for the whole stretch: give it the others' mean along the
        // free parameter, so that the triangle's parameters follow its fan in 3D.
        for (int k = 0; k < 3; ++k) {
          int ax = e[k].free_axis;
          if (ax < 0) {
            // The pole's own vertex at the stretch's ends: free along the axis of a pole it
            // belongs to, if any corner of this triangle is on such a stretch.
            continue;
          }
          double sum = 0;
          int cnt = 0;
          for (int j = 0; j < 3; ++j)
            if (j != k && e[j].index != e[k].index) sum += e[j].uv[ax], ++cnt;
          if (cnt) e[k].uv[ax] = sum / cnt;
        }
        const VInfo* c[3] = {&e[0], &e[1], &e[2]};
        double worst = 0;
        Vec2 at = Vec2::Zero();
        Vec2 uvc = (c[0]->uv + c[1]->uv + c[2]->uv) / 3;
        Point3 pc = (pos(c[0]->index) + pos(c[1]->index) + pos(c[2]->index)) / 3;
        double dc = (S.eval(uvc.x(), uvc.y()) - pc).norm();
        if (dc > worst) worst = dc, at = uvc;
        for (int k = 0; k < 3; ++k) {
          if (cdt.is_constrained(CDT::Edge(fh, k))) continue;
          const VInfo* a = c[(k + 1) % 3];
          const VInfo* b = c[(k + 2) % 3];
          Vec2 uvm = (a->uv + b->uv) / 2;
          double de = (S.eval(uvm.x(), uvm.y()) - (pos(a->index) + pos(b->index)) / 2).norm();
          if (de > worst) worst = de, at = uvm;
        }
        // The flat triangle's largest distance lies between the sampled points (at the
        // circumcentre on a sphere): hold the samples to a margin below the tolerance.
        bool over = worst > 0.8 * tol.chordal;
        if (!over) {
          Vec3 n0 = S.normal(c[0]->uv.x(), c[0]->uv.y()), n1 = S.normal(c[1]->uv.x(), c[1]->uv.y()),
               n2 = S.normal(c[2]->uv.x(), c[2]->uv.y());
          if (std::max({angle_between(n0, n1), angle_between(n1, n2), angle_between(n0, n2)}) > ang) {
            over = true;
            at = uvc;
          }
        }
        if (over) add.push_back(at);
        else std::copy(corners, corners + 3, fh->info().ok);
      }
      if (add.empty()) break;
      if (out.positions.size() + add.size() > budget)
        fail("tessellate: face ", f.value, " needs more than ", budget, " points at tolerance ", tol.chordal);
      for (const Vec2& uv : add) {
        auto loc = to_plane(uv);
        CDT::Locate_type lt;
        int li;
        auto fh = cdt.locate(loc, lt, li);
        if (lt == CDT::VERTEX) continue;
        if (lt == CDT::EDGE && cdt.is_constrained(CDT::Edge(fh, li))) continue;
        auto h = cdt.insert(loc, fh);
        h->info() = VInfo{out.add_vertex(S.eval(uv.x(), uv.y())), uv};
      }
    }
    mark_depth(cdt);
    for (auto fh = cdt.finite_faces_begin(); fh != cdt.finite_faces_end(); ++fh) {
      if (fh->info().depth % 2 != 1) continue;
      std::uint32_t a = fh->vertex(0)->info().index, b = fh->vertex(1)->info().index, c = fh->vertex(2)->info().index;
      if (a == b || b == c || a == c) continue;
      if (sign > 0) out.add_triangle(a, b, c, f.value);
      else out.add_triangle(a, c, b, f.value);
    }
  });
  return out;
}

}  // namespace wedge
