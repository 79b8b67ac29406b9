// The B-Rep tessellator (tessellate/brep_mesh.h).
//
// Edges: the number of chords a smooth stretch needs is the integral of its curvature's need
// (chordal sagitta kappa h^2 / 8 and turn kappa h); the points go at equal steps of that integral,
// then each chord is checked at three interior samples (and the tangent's turn) and bisected while
// it is over the tolerance.
//
// Curved faces: the face's loops are mapped into (u, v) through the PCurves of their sides; where
// the image of one side ends away from the start of the next, the stretch between them is a pole
// (it maps to the one shared vertex) and gets points of its own that all carry that vertex. Each
// parameter is stretched, piecewise linearly, by the chords per unit parameter that the surface's
// normal curvature along it needs there, so that Delaunay's triangles in the stretched plane are
// about as long as the tolerance allows in each direction; the triangulation's plane stretches u
// further where a column needs fewer chords along v than the most (conformal on a surface of
// revolution). Seeding puts rows of points at that spacing inside the face (rows along v with the
// local need of each row). Refinement: each triangle inside the face is checked by the distance
// of its edges' midpoints from the surface (along the normal at their foot, to second order),
// the largest distance of the quadratic through those three over the triangle, and the angle
// between the surface normals at its corners; a triangle over the tolerance gets a new point at
// its worst place; repeat until none does. A triangle whose corners include one vertex twice (at
// a pole) is dropped: its neighbours close the fan.
#include "tessellate/brep_mesh.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/spatial_sort.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <numeric>
#include <functional>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

#include "kernel/distance.h"
#include "tessellate/brep_sampling.h"
#include "tessellate/planar.h"
#include "tessellate/progress.h"

namespace wedge {

using brep_sampling::angle_between;
using brep_sampling::chords_needed;
using brep_sampling::edge_parameters;
using brep_sampling::tilt_tangent;
using brep_sampling::width_across;
using brep_sampling::estimate_triangles;
using brep_sampling::planar_triangles;
using brep_sampling::StraightAxes;

namespace {

// A triangle estimate in words: a whole number while it is one, else in powers of ten (a sphere
// 1e90 wide at tolerance 0.01 needs about 1e+186; llround of it was LLONG_MIN).
std::string triangle_count_text(double n) {
  if (n < 1e15) return "about " + std::to_string(std::llround(n));
  if (!std::isfinite(n)) return "more than 1e308";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", n);
  return std::string("about ") + buf;
}

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VInfo {
  std::uint32_t index = 0;
  Vec2 uv = Vec2::Zero();
  int free_axis = -1;  // on a pole: the parameter (0: u, 1: v) along which the point does not move
  Vec3 normal = Vec3::Zero();  // the surface's unit normal at uv (not used at poles)
  int pole_axis = -1;  // a pole's vertex (any of its points): the axis of its stretch, else -1
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VInfo, K>;
struct FInfo {
  int depth = -1;   // nesting depth: odd inside the face
  int blocked = -1;  // the refinement round in which a neighbour got a point
  int seen = -1;     // the last round that queued it
  // The corners it had when it was found within the tolerances (a flip reuses a face with new
  // corners: then they differ and it is checked again).
  const void* ok[3] = {nullptr, nullptr, nullptr};
  // Each edge's midpoint distance from the surface (the refinement's m[k]) and the two corners it
  // was found for: the triangle across the edge, or this one in a later round, takes it from here
  // instead of evaluating the surface again.
  double mid_off[3] = {0, 0, 0};
  const void* mid_ends[3][2] = {{nullptr, nullptr}, {nullptr, nullptr}, {nullptr, nullptr}};
};
using Fbi = CGAL::Triangulation_face_base_with_info_2<FInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Itag = CGAL::Exact_predicates_tag;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, Itag>;


// True when unit vectors a and b (either may be zero: never) differ by more than the angle whose
// cosine is cos_limit.
bool turned_more(const Vec3& a, const Vec3& b, double cos_limit) {
  if (a.squaredNorm() == 0 || b.squaredNorm() == 0) return false;
  return a.dot(b) < cos_limit;
}

// The unit normal at uv from the surface's jet J = (S, Su, Sv) there, as Surface::normal gives it
// (where Su x Sv vanishes, at a pole, that steps inside the domain).
Vec3 unit_normal(const Surface& S, const Vec2& uv, const Vec3* J) {
  Vec3 n = J[1].cross(J[2]);
  double size = 1e-9 * (1 + J[0].norm()), lu = J[1].norm(), lv = J[2].norm(), ln = n.norm();
  if (lu <= size || lv <= size || !(ln > 1e-9 * lu * lv)) return S.normal(uv.x(), uv.y());
  return n / ln;
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


namespace {
thread_local const TessellateProgress* t_progress = nullptr;
thread_local const TessellatePoll* t_poll = nullptr;

// Reports the points made against the estimate, and the end when it goes out of scope (also when
// the tessellation fails; `out` may then be moved from, which only makes the last count wrong).
class ProgressReport {
 public:
  // Only a tessellation the estimate calls large reports (fewer points take well under a second).
  static constexpr std::size_t kLarge = 10000;
  ProgressReport(const Mesh& out, double estimated_triangles)
      : progress_(t_progress), poll_(t_poll), out_(out),
        expected_(std::max<std::size_t>(1, std::size_t(std::min(estimated_triangles, 1e15) / 2))) {
    if (expected_ < kLarge) progress_ = nullptr;
  }
  ~ProgressReport() {
    if (progress_) (*progress_)(out_.positions.size(), expected_, true);
  }
  ProgressReport(const ProgressReport&) = delete;
  ProgressReport& operator=(const ProgressReport&) = delete;
  void operator()() const {
    if (poll_) (*poll_)();
    if (progress_) (*progress_)(out_.positions.size(), expected_, false);
  }
  // In the inner loops: the cancel poll every 1024 calls.
  void tick() const {
    if (poll_ && (++ticks_ & 1023) == 0) (*poll_)();
  }
  // Before a long step with no poll inside.
  void tick_now() const {
    if (poll_) (*poll_)();
  }

 private:
  const TessellateProgress* progress_;
  const TessellatePoll* poll_;
  mutable std::size_t ticks_ = 0;
  const Mesh& out_;
  std::size_t expected_;
};
}  // namespace

void set_tessellate_progress(const TessellateProgress* progress) { t_progress = progress; }

const TessellatePoll* set_tessellate_poll(const TessellatePoll* poll) { return std::exchange(t_poll, poll); }
const TessellatePoll* tessellate_poll() { return t_poll; }

static Mesh tessellate_at_scale(const Model& m, const Tolerance& tol_in, std::vector<std::array<Vec2, 3>>* corner_uv);

// A curved solid far from unit size is tessellated as a copy scaled by a power of two (exact) to
// about size 1, at the tolerance scaled alike, and its points scaled back: the refinement's
// thresholds (a determinant of squared lengths above 1e-300, a tangent longer than 1e-9) would
// otherwise drop every triangle of a sphere 1e-82 wide, and overflow for one 1e90 wide. Parametric
// faces keep their parameters under the scale, so the corners' (u, v) stay those of `m`.
Mesh tessellate(const Model& m, const Tolerance& tol, std::vector<std::array<Vec2, 3>>* corner_uv) {
  if (m.all_planar()) return tessellate_at_scale(m, tol, corner_uv);
  Box3 box;
  m.vertices().for_each([&](VertexId v, const BrepVertex&) { box.extend(m.point(v)); });
  if (!(box.size().maxCoeff() > 0)) box = m.bounds();  // a torus's one vertex
  const double size = box.size().maxCoeff();
  if (!(size > 0) || !std::isfinite(size) || (size >= 0x1p-20 && size <= 0x1p20)) return tessellate_at_scale(m, tol, corner_uv);
  const int k = std::ilogb(size);
  Model unit = m;
  // In steps of at most 2^64, so that no step's determinant leaves the range Model::transform takes.
  for (int left = -k; left != 0;) {
    const int step = std::clamp(left, -64, 64);
    unit.transform(scale(Vec3::Constant(std::ldexp(1.0, step))));
    left -= step;
  }
  Tolerance t = tol;
  t.chordal = std::ldexp(tol.chordal, -k);
  Mesh out = tessellate_at_scale(unit, t, corner_uv);
  for (Point3& p : out.positions) p *= std::ldexp(1.0, k);
  return out;
}

static Mesh tessellate_at_scale(const Model& m, const Tolerance& tol_in, std::vector<std::array<Vec2, 3>>* corner_uv) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::array<Vec2, 3> no_uv{Vec2(nan, nan), Vec2(nan, nan), Vec2(nan, nan)};
  if (corner_uv) corner_uv->clear();
  Tolerance tol = tol_in;
  if (!(tol.chordal > 0)) fail("tessellate: the chordal tolerance must be positive");
  if (!(tol.angular > 0)) tol.angular = 180;
  // The budget is checked on an estimate first, so that a tolerance far too fine fails at once
  // instead of after minutes of refinement (and gigabytes); the refinement below checks it again.
  StraightAxes straight_axis;
  const double planar = planar_triangles(m), estimate = estimate_triangles(m, tol, straight_axis) + planar;
  if (!(estimate <= double(tol.max_triangles))) {
    if (estimate == planar)  // the count of a polyhedron, whatever the tolerance
      fail("tessellate: the solid's planar faces make ", estimate, " triangles at any tolerance, more than the budget of ",
           tol.max_triangles, ": raise the budget with tolerance{max_triangles=N}");
    // Where the chordal tolerance alone stays within the budget, the angle is what asks too much
    // (tolerance{angle=1e-6} was reported as "tolerance 0.01 would need ...").
    Tolerance chordal_only = tol;
    chordal_only.angular = 180;
    StraightAxes unused;
    if (tol.angular < 180 && estimate_triangles(m, chordal_only, unused) + planar <= double(tol.max_triangles))
      fail("tessellate: the angle tolerance of ", tol.angular, " degrees would need ", triangle_count_text(estimate),
           " triangles, more than the budget of ", tol.max_triangles,
           ": use a larger angle or raise the budget with tolerance{max_triangles=N}");
    fail("tessellate: tolerance ", tol.chordal, " would need ", triangle_count_text(estimate),
         " triangles, more than the budget of ", tol.max_triangles,
         ": use a larger tolerance or raise the budget with tolerance{max_triangles=N}");
  }
  Mesh out;
  const ProgressReport report(out, estimate);
  std::unordered_map<std::int32_t, std::uint32_t> vindex;
  m.vertices().for_each([&](VertexId v, const BrepVertex&) { vindex[v.value] = out.add_vertex(m.point(v)); });
  std::unordered_map<std::int32_t, EdgeSamples> samples;
  std::unordered_map<std::int32_t, std::vector<double>> fractions;  // interior points of curved edges
  m.edges().for_each([&](EdgeId e, const BrepEdge&) {
    if (!m.curve(e)) return;
    CurvePtr c = m.edge_curve(e);
    auto [t0, t1] = c->domain();
    // The faces on a parametric surface along the edge: their normals must not turn by more than the
    // angular tolerance between neighbouring points (a twisted face turns along a straight edge).
    std::vector<std::pair<const FaceSurface*, const PCurve*>> along;
    for (int side = 0; side < 2; ++side) {
      EdgeSide es{e, side};
      FaceId f = m.loops()[m.side(es).loop].face;
      const PCurve* pc = m.pcurve(es);
      if (const FaceSurface* ps = &m.surface(f); ps->parametric && pc) along.emplace_back(ps, pc);
    }
    double ang = radians(tol.angular);
    const double tan_tilt = tilt_tangent(tol);
    auto turns = [&](double a, double b) {
      double bow = -1;  // the chord's, measured once for both faces
      for (const auto& [ps, pc] : along) {
        Vec2 pa = pc->at((a - t0) / (t1 - t0)), pb = pc->at((b - t0) / (t1 - t0));
        const Surface& S = *ps->surface;
        if (angle_between(S.normal(pa.x(), pa.y()), S.normal(pb.x(), pb.y())) > ang) return true;
        // The chord's bow against the width of the face's triangles across the edge: where the
        // face is narrow across (a thin tube's seam), a chord bowing by more than the tilt
        // tolerance times that width tilts the triangles on it past the angle, and turns over
        // those the refinement puts nearer (which it then splits without end: a tube of radius
        // 0.05 swept along a bend of radius 1 at 0.1 ran past the point budget).
        const double width = width_across(S, (pa + pb) / 2, pb - pa, tol);
        if (!std::isfinite(width)) continue;
        if (bow < 0) bow = point_segment_distance(c->eval((a + b) / 2), c->eval(a), c->eval(b));
        if (bow > tan_tilt * width) return true;
      }
      return false;
    };
    std::vector<double> ts = along.empty() ? curve_parameters(*c, tol) : edge_parameters(*c, tol, turns);
    std::vector<double>& fr = fractions[e.value];
    for (std::size_t i = 1; i + 1 < ts.size(); ++i) fr.push_back((ts[i] - t0) / (t1 - t0));
  });
  // A face that is straight along one parameter (a cone frustum, a scaled extrusion, a ruled
  // loft): its two curved borders get each other's points too, so that the triangles between
  // them follow the rulings and need no points inside (otherwise a chord between points at
  // different u cuts across the face and the refinement fills the face).
  m.faces().for_each([&](FaceId f, const BrepFace& face) {
    const FaceSurface* ps = &m.surface(f);
    if (!ps->parametric || !face.rings.empty()) return;
    int straight = straight_axis(*ps->surface);
    if (straight < 0) return;
    int along = 1 - straight;  // the curved borders run along this parameter
    std::vector<std::pair<EdgeSide, const PCurve*>> borders;
    for (EdgeSide es : m.loop_sides(face.outer)) {
      const PCurve* pc = m.pcurve(es);
      if (pc && pc->start[straight] == pc->end[straight] && pc->start[along] != pc->end[along] && fractions.count(es.edge.value))
        borders.emplace_back(es, pc);
    }
    if (borders.size() != 2) return;
    std::vector<double> ps_all;
    for (const auto& [es, pc] : borders)
      for (double x : fractions[es.edge.value]) ps_all.push_back(pc->at(x)[along]);
    for (const auto& [es, pc] : borders) {
      std::vector<double>& fr = fractions[es.edge.value];
      double a = pc->start[along], b = pc->end[along];
      for (double x : ps_all) {
        double t = (x - a) / (b - a);
        if (t > 1e-9 && t < 1 - 1e-9) fr.push_back(t);
      }
      std::sort(fr.begin(), fr.end());
      fr.erase(std::unique(fr.begin(), fr.end(), [](double p, double q) { return q - p < 1e-9; }), fr.end());
    }
  });
  m.edges().for_each([&](EdgeId e, const BrepEdge&) {
    auto it = fractions.find(e.value);
    if (it == fractions.end()) return;
    CurvePtr c = m.edge_curve(e);
    auto [t0, t1] = c->domain();
    EdgeSamples& es = samples[e.value];
    for (double x : it->second) {
      es.s.push_back(x);
      es.index.push_back(out.add_vertex(c->eval(t0 + x * (t1 - t0))));
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
    report();
    std::vector<LoopId> ls{face.outer};
    ls.insert(ls.end(), face.rings.begin(), face.rings.end());
    const FaceSurface& fs = m.surface(f);
    if (fs.cylinder()) {
      // The planar builders' cylinder patch: arc, line, arc, line, as a strip between the arcs.
      auto sides = m.loop_sides(face.outer);
      if (sides.size() != 4 || !face.rings.empty()) fail("tessellate: cylinder face ", f.value, " is not bounded by two arcs and two lines");
      int k = m.curve(sides[0].edge) ? 0 : 1;
      std::vector<std::uint32_t> a, b;
      side_points(sides[static_cast<std::size_t>(k)], a, fr);
      a.push_back(vindex.at(m.dest(sides[static_cast<std::size_t>(k)]).value));
      side_points(sides[static_cast<std::size_t>(k + 2)], b, fr);
      b.push_back(vindex.at(m.dest(sides[static_cast<std::size_t>(k + 2)]).value));
      std::reverse(b.begin(), b.end());
      // The two arcs are sampled each on its own (an edge's points follow the faces along it as
      // well as its curvature), so they may have different numbers of points: zip them by their
      // position along each arc (cumulative chord length, 0 at the start, 1 at the end), always
      // advancing on the side whose next point comes first. Equal counts at equal places give
      // the two triangles per quad of a plain strip.
      auto positions = [&](const std::vector<std::uint32_t>& p) {
        std::vector<double> s(p.size(), 0.0);
        for (std::size_t i = 1; i < p.size(); ++i) s[i] = s[i - 1] + (out.positions[p[i]] - out.positions[p[i - 1]]).norm();
        if (s.back() > 0)
          for (double& x : s) x /= s.back();
        return s;
      };
      const std::vector<double> sa = positions(a), sb = positions(b);
      std::size_t i = 0, j = 0;
      while (i + 1 < a.size() || j + 1 < b.size()) {
        if (j + 1 >= b.size() || (i + 1 < a.size() && sa[i + 1] <= sb[j + 1])) {
          out.add_triangle(a[i], a[i + 1], b[j], f.value);
          ++i;
        } else {
          out.add_triangle(a[i], b[j + 1], b[j], f.value);
          ++j;
        }
      }
      return;
    }
    const FaceSurface* ps = &fs;
    if (!ps->parametric) {
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
    // The metric of (u, v): each parameter is stretched by the number of chords per unit parameter
    // that the tolerance needs along it, sqrt(k / (8 tol)) with k the largest normal curvature
    // term (|Suu.n|, |Svv.n|, and |Suv.n| for twisted patches): a chord of parameter length d then
    // deviates by about k d^2 / 8. The stretch varies along each parameter (k is the largest over
    // a column of samples across it, for each of kCells columns), so that where a revolved
    // profile is nearly flat the triangles grow long along it instead of staying as short as at
    // its tightest bend. A straight direction (a cylinder's or cone's rulings) needs no points
    // inside, so its stretch falls to the floor (one chord over the face's size) and Delaunay
    // gives long triangles across it: counts then grow as 1/sqrt(tol) per curved edge, not 1/tol.
    // Where neither direction bends (a flat patch), the mean speeds |Su|, |Sv| keep the plane
    // isometric.
    auto needs = [&](const Vec3* J, const Vec3& n) { return chords_needed(J, n, tol); };
    constexpr int kCells = 16;
    double su = 0, sv = 0;
    std::array<double, kCells> ku{}, kv{};  // per column: the chords per unit u (v) needed
    std::array<double, kCells> gv{};  // per u column: the largest chords per unit v needed in it
    Box3 fbox;
    std::vector<Vec3> grid(kCells * kCells * 6);
    {
      double us[kCells], vs[kCells];
      for (int i = 0; i < kCells; ++i) us[i] = u0 + (u1 - u0) * (i + 0.5) / kCells, vs[i] = v0 + (v1 - v0) * (i + 0.5) / kCells;
      S.jet_grid(us, kCells, vs, kCells, 2, grid.data());
    }
    for (int i = 0; i < kCells; ++i)
      for (int j = 0; j < kCells; ++j) {
        const Vec3* J = &grid[static_cast<std::size_t>(i * kCells + j) * 6];
        const Vec3 &Su = J[1], &Sv = J[2];
        su += Su.norm();
        sv += Sv.norm();
        fbox.extend(Point3(J[0]));
        Vec3 n = Su.cross(Sv);
        if (!(n.norm() > 0)) continue;
        n.normalize();
        const auto [nu, nv] = needs(J, n);
        ku[i] = std::max(ku[i], nu);
        kv[j] = std::max(kv[j], nv);
        gv[i] = std::max(gv[i], nv);
      }
    su = su > 0 ? su / (kCells * kCells) : 1;
    sv = sv > 0 ? sv / (kCells * kCells) : 1;
    // The stretched coordinate of each parameter: piecewise linear over the cells, slope = the
    // cell's chords per unit parameter.
    struct Stretch {
      double p0 = 0, step = 1;
      std::array<double, kCells> slope{};
      std::array<double, kCells + 1> at{};
      double operator()(double p) const {
        int i = std::clamp(static_cast<int>(std::floor((p - p0) / step)), 0, kCells - 1);
        return at[static_cast<std::size_t>(i)] + slope[static_cast<std::size_t>(i)] * (p - (p0 + step * i));
      }
      // The parameter whose stretched coordinate is x (inside the range).
      double inverse(double x) const {
        std::size_t i = 0;
        while (i + 1 < kCells && at[i + 1] < x) ++i;
        return p0 + step * (static_cast<double>(i) + (slope[i] > 0 ? (x - at[i]) / (slope[i] * step) : 0.5));
      }
    } stretch_u, stretch_v;
    {
      double size = std::max(fbox.diagonal(), 1e-300);
      double kmax = std::max(*std::max_element(ku.begin(), ku.end()), *std::max_element(kv.begin(), kv.end()));
      auto fill = [&](Stretch& st, double p0, double p1, const std::array<double, kCells>& k, double speed) {
        st.p0 = p0;
        st.step = (p1 - p0) / kCells;
        for (int i = 0; i < kCells; ++i) {
          st.slope[static_cast<std::size_t>(i)] =
              kmax > 0 ? std::max(k[static_cast<std::size_t>(i)], speed / size) : speed;
          st.at[static_cast<std::size_t>(i) + 1] = st.at[static_cast<std::size_t>(i)] + st.slope[static_cast<std::size_t>(i)] * st.step;
        }
      };
      fill(stretch_u, u0, u1, ku, su);
      fill(stretch_v, v0, v1, kv, sv);
    }
    // The plane of the triangulation. The v stretch is one function of v, the largest need over
    // each v column, but where a u column needs fewer chords along v (a sphere's rows shrink as
    // cos(latitude) toward its poles) the seeds and refinement points lie farther apart along v,
    // in the stretched plane, than along u: Delaunay's triangles there reach across rows. So in
    // the plane each u column is stretched further by the ratio f of the largest need along v to
    // its own (capped; 1 where it needs as much), which makes the plane conformal to the
    // tolerance's metric on a surface of revolution (Mercator's projection on a sphere): Delaunay
    // in it is Delaunay on the surface. Faces straight along one parameter keep the plain stretch
    // (their triangles run between the borders).
    Stretch plane_u = stretch_u;
    std::array<double, kCells> conformal{};
    conformal.fill(1.0);
    if (straight_axis(S) < 0) {
      const double gmax = *std::max_element(gv.begin(), gv.end());
      constexpr double cap = 8.0;
      for (int i = 0; i < kCells; ++i) {
        const auto k = static_cast<std::size_t>(i);
        conformal[k] = gmax > 0 ? std::clamp(gmax / std::max(gv[k], 1e-300), 1.0, cap) : 1.0;
        plane_u.slope[k] = stretch_u.slope[k] * conformal[k];
        plane_u.at[k + 1] = plane_u.at[k] + plane_u.slope[k] * plane_u.step;
      }
    }
    auto conformal_at = [&](double u) {
      return conformal[static_cast<std::size_t>(std::clamp(static_cast<int>(std::floor((u - u0) / stretch_u.step)), 0, kCells - 1))];
    };
    auto stretched = [&](const Vec2& uv) { return Vec2(stretch_u(uv.x()), stretch_v(uv.y())); };
    auto to_plane = [&](const Vec2& uv) { return K::Point_2(plane_u(uv.x()), stretch_v(uv.y())); };

    CDT cdt;
    // The mesh vertices that are poles of this face, and the parameter along which each does not
    // move: a pole's (u, v) stands for a whole stretch of the border.
    std::unordered_map<std::uint32_t, int> pole_axis;
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
          spacing += (stretched(b) - stretched(a)).norm();
          ++count;
        }
      }
      spacing = count ? spacing / static_cast<double>(count) : 1;
      for (std::size_t i = 0; i < per_side.size(); ++i) {
        pts.insert(pts.end(), per_side[i].begin(), per_side[i].end());
        Vec2 a = ends[i].second, b = ends[(i + 1) % ends.size()].first;
        Vec2 d = stretched(b) - stretched(a);
        if (d.norm() > 1e-12 * (1 + spacing)) {
          // A pole: the vertex between the two sides, along the domain's border.
          std::uint32_t pole = per_side[(i + 1) % per_side.size()][0].index;
          int n = std::max(2, static_cast<int>(std::ceil(d.norm() / std::max(spacing, 1e-300))));
          n = std::min(n, 4096);
          int axis = std::abs(d.x()) >= std::abs(d.y()) ? 0 : 1;
          pole_axis[pole] = axis;
          // The pole's corners at both ends of the stretch are the sides' own points; mark the
          // stretch's points, whose one parameter is free.
          for (int k = 1; k < n; ++k) pts.push_back({pole, a + (b - a) * (double(k) / n), axis});
        }
      }
      // The loop's points in the spatial sort's order, each located from the last one's face (in
      // loop order, along a side's straight run in the plane, each new point on the hull of the
      // last ones flipped edges back to most of them: a cylinder at tolerance 1e-8, 22,800 points
      // on each rim, took 10 s); then the infos in loop order (where points coincide, the vertex
      // names the last of them, as when they went in in loop order), then the sides.
      std::vector<K::Point_2> at(pts.size());
      for (std::size_t i = 0; i < pts.size(); ++i) at[i] = to_plane(pts[i].uv);
      std::vector<std::size_t> order(pts.size());
      std::iota(order.begin(), order.end(), std::size_t(0));
      const std::vector<K::Point_2>& sorted_at = at;
      CGAL::spatial_sort(order.begin(), order.end(),
                         CGAL::Spatial_sort_traits_adapter_2<K, CGAL::Pointer_property_map<K::Point_2>::const_type>(
                             CGAL::make_property_map(sorted_at), K()));
      std::vector<CDT::Vertex_handle> hs(pts.size());
      CDT::Face_handle near;
      for (std::size_t i : order) {
        hs[i] = cdt.insert(at[i], near);
        near = hs[i]->face();
      }
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const LoopPt& p = pts[i];
        hs[i]->info() = VInfo{p.index, p.uv, p.free_axis, S.normal(p.uv.x(), p.uv.y())};
      }
      for (std::size_t i = 0; i < hs.size(); ++i)
        if (hs[i] != hs[(i + 1) % hs.size()]) cdt.insert_constraint(hs[i], hs[(i + 1) % hs.size()]);
    }
    // Every point of a pole's vertex knows its axis (the corners at both ends of its stretch too).
    if (!pole_axis.empty())
      for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
        auto it = pole_axis.find(v->info().index);
        if (it != pole_axis.end()) v->info().pole_axis = it->second;
      }
    // Seeding: rows of points across the face, so that refinement starts from nearly the
    // triangles the tolerance needs instead of growing them one worst point at a time (which
    // leaves most triangles well below the tolerance: about twice the count). Rows run along v at
    // steps of the u-stretch of sqrt(3)/2 kSeed; along each row the points are kSeed apart in the
    // row's own need (the local |Svv.n| and |Suv.n|, so that rows near a pole get few points),
    // shifted by half a step on every other row: Delaunay then gives nearly equilateral triangles
    // in the stretched plane, whose flat centroid lies (4/3) kSeed^2 tol from a quadric's surface
    // (0.69 tol: below the refinement's 0.93, which the rows' uneven counts and the borders use
    // up; larger seeds made the bench's shapes need more points, not fewer).
    // A face straight along one parameter needs no points inside.
    mark_depth(cdt);
    if (straight_axis(S) < 0) {
      constexpr double kSeed = 0.72;
      const double a0 = stretch_u(u0), a1 = stretch_u(u1);
      const int rows = static_cast<int>(std::floor((a1 - a0) / (kSeed * std::sqrt(3.0) / 2)));
      const double b0 = stretch_v(v0), b1 = stretch_v(v1);
      const double size = std::max(fbox.diagonal(), 1e-300);
      constexpr int kRow = 2 * kCells;
      std::array<double, kRow + 1> cum{};
      CDT::Face_handle hint;
      struct Seed {
        K::Point_2 loc;
        VInfo info;
        int depth;
      };
      std::vector<Seed> seeds;
      std::vector<K::Point_2> row, last_row;  // the plane points of the seeds taken in this row and the one before
      std::size_t before = 0;  // the first of last_row that may lie within reach
      // The jets along every row at once (the rows share their v samples).
      std::vector<double> row_u, row_v;
      for (int r = 1; r < rows; ++r) row_u.push_back(stretch_u.inverse(a0 + (a1 - a0) * r / rows));
      for (int j = 0; j <= kRow; ++j) row_v.push_back(v0 + (v1 - v0) * j / kRow);
      std::vector<Vec3> row_jets(row_u.size() * row_v.size() * 6);
      if (!row_u.empty()) S.jet_grid(row_u.data(), static_cast<int>(row_u.size()), row_v.data(), kRow + 1, 2, row_jets.data());
      for (int r = 1; r < rows; ++r) {
        const double u = row_u[static_cast<std::size_t>(r - 1)];
        double prev = 0;
        for (int j = 0; j <= kRow; ++j) {
          const Vec3* J = &row_jets[(static_cast<std::size_t>(r - 1) * (kRow + 1) + static_cast<std::size_t>(j)) * 6];
          const Vec3 &Su = J[1], &Sv = J[2];
          Vec3 n = Su.cross(Sv);
          double d = sv / size;
          if (n.norm() > 0) {
            n.normalize();
            d = std::max(d, needs(J, n)[1]);
          }
          if (j > 0) cum[static_cast<std::size_t>(j)] = cum[static_cast<std::size_t>(j) - 1] + 0.5 * (prev + d) * (v1 - v0) / kRow;
          prev = d;
        }
        const int count = static_cast<int>(std::lround(cum[kRow] / kSeed));
        if (count < 2) continue;
        const double shift = r % 2 ? 0.5 : 0.0;
        std::size_t piece = 0;
        for (int k = 0; k < count; ++k) {
          report.tick();
          const double target = cum[kRow] * (k + shift) / count;
          if (k == 0 && shift == 0) continue;
          while (piece + 1 < kRow && cum[piece + 1] < target) ++piece;
          const double c0 = cum[piece], c1 = cum[piece + 1];
          const double v = v0 + (v1 - v0) * (static_cast<double>(piece) + (c1 > c0 ? (target - c0) / (c1 - c0) : 0.5)) / kRow;
          const Vec2 uv(u, v);
          const Vec2 at = stretched(uv);
          // Half a step clear of the domain's border (where the loops' own points are).
          if (at.y() - b0 < 0.5 * kSeed || b1 - at.y() < 0.5 * kSeed) continue;
          const auto loc = to_plane(uv);
          CDT::Locate_type lt;
          int li;
          auto fh = cdt.locate(loc, lt, li, hint);
          // On an edge of the loops' triangulation (a row at the parameter of a border point, where
          // an edge runs straight across the face): inside all the same, unless it is a border.
          if (lt != CDT::FACE && !(lt == CDT::EDGE && !cdt.is_constrained(CDT::Edge(fh, li)))) continue;
          if (fh->info().depth % 2 != 1) continue;
          hint = fh;
          // Not within half a step of a loop's point (a corner of the loops' triangle it falls in)
          // or of a seed already taken (the one before it in its row, or one of the row before).
          const double clear = 0.25 * kSeed * kSeed * conformal_at(u) * conformal_at(u);
          double nearest = 1e300;
          for (int q = 0; q < 3; ++q) nearest = std::min(nearest, CGAL::squared_distance(loc, fh->vertex(q)->point()));
          if (!row.empty()) nearest = std::min(nearest, CGAL::squared_distance(loc, row.back()));
          const double reach = std::sqrt(clear);
          while (before < last_row.size() && last_row[before].y() < loc.y() - reach) ++before;
          for (std::size_t q = before; q < last_row.size() && last_row[q].y() <= loc.y() + reach; ++q)
            nearest = std::min(nearest, CGAL::squared_distance(loc, last_row[q]));
          if (nearest < clear) continue;
          row.push_back(loc);
          Vec3 J[3];
          S.jet(u, v, 1, J);
          seeds.push_back({loc, VInfo{out.add_vertex(Point3(J[0])), uv, -1, unit_normal(S, uv, J)}, fh->info().depth});
        }
        last_row.swap(row);
        row.clear();
        before = 0;
      }
      // Then all at once, in CGAL's spatial (Hilbert) order. Inserted one by one in row order,
      // each seed's conflicts reached across the long triangles between the rows done and the far
      // side of the loops: about a tenth of the sphere's time at 1e-2 went to those flips.
      std::vector<std::size_t> order(seeds.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::vector<K::Point_2> at(seeds.size());
      for (std::size_t i = 0; i < seeds.size(); ++i) at[i] = seeds[i].loc;
      const std::vector<K::Point_2>& sorted_at = at;
      // (make_property_map takes the address of the first point: none when there are no seeds.)
      // Beyond kBand seeds, band by band of kBand in row order (bands of neighbouring rows), with
      // a cancel poll between them: one sort of 1.7 million seeds ran 0.4 s without a poll.
      constexpr std::size_t kBand = std::size_t(1) << 17;
      for (std::size_t from = 0; from < order.size(); from += kBand) {
        report.tick_now();
        const auto to = order.begin() + long(std::min(order.size(), from + kBand));
        CGAL::spatial_sort(order.begin() + long(from), to,
                           CGAL::Spatial_sort_traits_adapter_2<K, CGAL::Pointer_property_map<K::Point_2>::const_type>(
                               CGAL::make_property_map(sorted_at), K()));
      }
      CDT::Face_handle near;
      for (std::size_t i : order) {
        report.tick();
        auto h = cdt.insert(seeds[i].loc, near);
        h->info() = seeds[i].info;
        auto fc = cdt.incident_faces(h), done = fc;
        do {
          fc->info().depth = seeds[i].depth;
        } while (++fc != done);
        near = fc;
      }
    }
    double sign = ps->reversed ? -1.0 : 1.0;
    const double margin = straight_axis(S) >= 0 ? 1.0 : 0.93;
    // How far the flat point p lies off the surface near S(uv), signed (+ on the normal's side).
    // p need not lie over S(uv) (a chord's midpoint is not over its parameters' midpoint where
    // the speed varies, or where the line bends sideways in the surface): its offset along the
    // surface, (du, dv) from the first fundamental form, is taken back by the second:
    // d.n - II(du, dv) / 2 is the distance from the surface at p's foot, to second order.
    auto off_surface = [&](const Vec2& uv, const Point3& p) {
      Vec3 J[6];
      S.jet(uv.x(), uv.y(), 2, J);
      Vec3 d = p - J[0];
      Vec3 n = unit_normal(S, uv, J);
      if (!(n.squaredNorm() > 0)) return d.norm();
      double h = d.dot(n);
      {
        const double E = J[1].squaredNorm(), F = J[1].dot(J[2]), G = J[2].squaredNorm(), det = E * G - F * F;
        if (det > 1e-300) {
          const double a = d.dot(J[1]), b = d.dot(J[2]);
          const double du = (G * a - F * b) / det, dv = (E * b - F * a) / det;
          h -= 0.5 * (J[3].dot(n) * du * du + 2 * J[4].dot(n) * du * dv + J[5].dot(n) * dv * dv);
        }
      }
      return h;
    };
    auto pos = [&](std::uint32_t i) -> const Point3& { return out.positions[i]; };
    const double cos_ang = std::cos(radians(tol.angular));
    std::size_t budget = std::max<std::size_t>(tol.max_triangles / 2, 1000);
    // The faces to look at in a round: all of them first, then those around the points the last
    // round added and around the triangles it held back. An insertion changes only triangles
    // around the new point (Delaunay's flips never cross a constraint), and they inherit the
    // depth of the triangle it fell in: the depths marked before seeding stay right through the
    // seeding and the refinement, with no second or third pass.
    std::vector<CDT::Face_handle> todo;
    for (auto fh = cdt.finite_faces_begin(); fh != cdt.finite_faces_end(); ++fh) todo.push_back(fh);
    std::vector<CDT::Vertex_handle> touched;
    for (int round = 0; !todo.empty(); ++round) {
      struct Add {
        Vec2 at, centroid;  // the worst place, and the triangle's own centroid in (u, v)
        CDT::Vertex_handle near;  // a corner, where the search for the place starts
      };
      std::vector<Add> add;
      touched.clear();
      // One point per neighbourhood and round: a triangle next to one that gets a point this
      // round waits for the next round (the new point often fixes it too). Without this, the
      // neighbours of one long edge each add a point beside it and the mesh ends up several times
      // denser than the tolerance needs.
      for (CDT::Face_handle fh : todo) {
        report.tick();
        if (cdt.is_infinite(fh)) continue;
        if (fh->info().depth % 2 != 1) continue;
        if (fh->info().blocked == round) {
          for (int k = 0; k < 3; ++k) touched.push_back(fh->vertex(k));
          continue;
        }
        const void* corners[3] = {&*fh->vertex(0), &*fh->vertex(1), &*fh->vertex(2)};
        if (std::equal(corners, corners + 3, fh->info().ok)) continue;
        VInfo e[3] = {fh->vertex(0)->info(), fh->vertex(1)->info(), fh->vertex(2)->info()};
        if (e[0].index == e[1].index || e[1].index == e[2].index || e[0].index == e[2].index) continue;
        auto axis_of = [](const VInfo& x) { return x.pole_axis; };
        // A corner on a pole stands for the whole stretch: the straight segment from it to another
        // corner is the image of the segment from that corner's own free parameter, and at the
        // place with barycentric coordinates lam its free parameter is the others' weighted mean.
        auto place = [&](const double* lam) {
          Vec2 uv = Vec2::Zero();
          for (int k = 0; k < 3; ++k) {
            Vec2 c = e[k].uv;
            int ax = axis_of(e[k]);
            double w = lam[(k + 1) % 3] + lam[(k + 2) % 3];
            if (ax >= 0 && w > 0) c[ax] = (lam[(k + 1) % 3] * e[(k + 1) % 3].uv[ax] + lam[(k + 2) % 3] * e[(k + 2) % 3].uv[ax]) / w;
            uv += lam[k] * c;
          }
          return uv;
        };
        const double third[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
        const Vec2 uvc = place(third);
        // m[k]: the signed distance from the surface to the midpoint of the edge opposite corner k.
        double m[3];
        Vec2 mid[3];
        bool border[3];
        bool angle_over = false;
        for (int k = 0; k < 3; ++k) {
          // Constrained edges lie on the face's border: their points come from the edge's own
          // discretisation (which holds both tolerances), and no point inside improves them; their
          // midpoints still shape the error inside the triangle.
          border[k] = cdt.is_constrained(CDT::Edge(fh, k));
          Vec2 a = e[(k + 1) % 3].uv, b = e[(k + 2) % 3].uv;
          int axa = axis_of(e[(k + 1) % 3]), axb = axis_of(e[(k + 2) % 3]);
          if (axa >= 0) a[axa] = b[axa];
          if (axb >= 0) b[axb] = a[axb];
          mid[k] = (a + b) / 2;
          // The distance depends on the edge's two corners alone, in either order (except between
          // two pole points, where the order of the adjustments above matters: not kept).
          const void *ea = corners[(k + 1) % 3], *eb = corners[(k + 2) % 3];
          auto cached = [&](const FInfo& fi, int j) {
            const void* const* ends = fi.mid_ends[j];
            return (ends[0] == ea && ends[1] == eb) || (ends[0] == eb && ends[1] == ea);
          };
          const bool keep = axa < 0 || axb < 0;
          const CDT::Face_handle across = fh->neighbor(k);
          const int back = keep ? across->index(fh) : 0;
          if (keep && cached(fh->info(), k)) {
            m[k] = fh->info().mid_off[k];
          } else if (keep && cached(across->info(), back)) {
            m[k] = across->info().mid_off[back];
          } else {
            m[k] = off_surface(mid[k], (pos(e[(k + 1) % 3].index) + pos(e[(k + 2) % 3].index)) / 2);
            if (keep) {
              fh->info().mid_off[k] = m[k];
              fh->info().mid_ends[k][0] = ea;
              fh->info().mid_ends[k][1] = eb;
            }
          }
          if (!angle_over && !border[k]) {
            // The corners' own normals, except at a pole (whose normal depends on the side).
            Vec3 na = axa >= 0 ? S.normal(a.x(), a.y()) : e[(k + 1) % 3].normal;
            Vec3 nb = axb >= 0 ? S.normal(b.x(), b.y()) : e[(k + 2) % 3].normal;
            if (turned_more(na, nb, cos_ang)) angle_over = true;
          }
        }
        // Where the surface is about quadratic over the triangle, the flat triangle's distance from
        // it is q(lam) = 4 sum_k lam_{k+1} lam_{k+2} m[k] (a quadratic in the barycentric
        // coordinates that is m[k] at each edge's midpoint): its largest |q| is at an edge's
        // midpoint or at q's critical point inside (the circumcentre on a sphere, 4/3 of the
        // midpoints' distance for an equilateral triangle). With lam = (x, y, 1 - x - y),
        // a = m[2], b = m[0], c = m[1], the critical point solves
        // [-2c, s; s, -2b] (x, y) = (-c, -b), s = a - b - c.
        double worst = 0;
        Vec2 at = uvc;
        for (int k = 0; k < 3; ++k)
          if (!border[k] && std::abs(m[k]) > worst) worst = std::abs(m[k]), at = mid[k];
        {
          const double a = m[2], b = m[0], c = m[1], sab = a - b - c, det = 4 * b * c - sab * sab;
          if (std::abs(det) > 1e-12 * (a * a + b * b + c * c)) {
            const double x = (2 * b * c + sab * b) / det, y = (2 * b * c + sab * c) / det, z = 1 - x - y;
            if (x >= 0 && y >= 0 && z >= 0) {
              const double q = std::abs(4 * (a * x * y + b * y * z + c * x * z));
              const double lam[3] = {x, y, z};
              if (q > worst) worst = q, at = place(lam);
            }
          }
        }
        // The quadratic model misses the surface's higher terms: hold it to a margin below the
        // tolerance. On a face straight along one parameter the largest distance is that of the
        // chords across the rulings, which the border's points (within the tolerance) already
        // bound: no margin.
        bool over = worst > margin * tol.chordal;
        if (!over && angle_over) {
          over = true;
          at = uvc;
        }
        // A triangle with a corner on a pole is flat, or turned over, where its other two corners
        // lie on one line of the free parameter (one meridian through the axis), or in the wrong
        // order along it: the pole's point in the plane stands anywhere on its stretch, so the
        // plane's orientation says nothing (a revolved rectangle's flat ends had triangles of zero
        // area, and folds, there, which booleans and STL refuse). It takes a point at its
        // centroid in the plane (the place above moves the pole corner onto the others' line).
        if (!over && (e[0].free_axis >= 0 || e[1].free_axis >= 0 || e[2].free_axis >= 0)) {
          const Vec3 n3 = (pos(e[1].index) - pos(e[0].index)).cross(pos(e[2].index) - pos(e[0].index));
          if (!(n3.dot(S.normal(uvc.x(), uvc.y())) > 0)) {
            over = true;
            at = (e[0].uv + e[1].uv + e[2].uv) / 3;
          }
        }
        // A triangle turned over against the surface (a thin one along a bend, its middle corner
        // past the chord of the other two: a swept tube's side at 0.01) folds the mesh onto itself
        // although every point is within the tolerance, and a boolean refuses it as crossing
        // itself: it takes a point too. (Corners on a pole have no normal of their own.)
        // (Not where the triangle is far below the tolerance: there its turn is a fold far below it
        // too, and a sliver's sign is noise; a sweep along a Catmull-Rom path at tolerance 0.3
        // split such slivers without end, down to edges 1e-8 long.)
        double len[3] = {0, 0, 0};  // squared, of the edge opposite each corner
        if (!over && e[0].free_axis < 0 && e[1].free_axis < 0 && e[2].free_axis < 0)
          for (int k = 0; k < 3; ++k) len[k] = (pos(e[(k + 1) % 3].index) - pos(e[(k + 2) % 3].index)).squaredNorm();
        if (std::max({len[0], len[1], len[2]}) > 1e-6 * tol.chordal * tol.chordal) {
          const Vec3 n3 = (pos(e[1].index) - pos(e[0].index)).cross(pos(e[2].index) - pos(e[0].index));
          if (n3.dot(e[0].normal + e[1].normal + e[2].normal) < 0) {
            over = true;
            // At the middle of its longest edge inside the face, which halves it: at the centroid,
            // a long thin one along a tight bend at a coarse tolerance (a tube of radius 0.12
            // swept along an arc of radius 2 at 0.1) left long thin ones turned over again, point
            // after point, until the budget (minutes, gigabytes).
            at = uvc;
            double inner = 0;
            for (int k = 0; k < 3; ++k)
              if (!border[k] && len[k] > inner) inner = len[k], at = mid[k];
          }
        }
        if (over) {
          add.push_back({at, (e[0].uv + e[1].uv + e[2].uv) / 3, fh->vertex(0)});
          for (int k = 0; k < 3; ++k) fh->neighbor(k)->info().blocked = round;
        } else {
          std::copy(corners, corners + 3, fh->info().ok);
        }
      }
      if (add.empty()) break;
      report();
      if (out.positions.size() + add.size() > budget)
        fail("tessellate: face ", f.value, " needs more than ", budget, " points at tolerance ", tol.chordal,
             ", more than the budget of ", tol.max_triangles,
             " triangles allows: use a larger tolerance or raise the budget with tolerance{max_triangles=N}");
      std::size_t inserted = 0;
      const double eu = 1e-12 * (u1 - u0), ev = 1e-12 * (v1 - v0);
      for (const Add& a : add) {
        report.tick();
        // A place on the border, on a vertex or outside the face cannot take a point: try the
        // triangle's centroid in the plane instead (strictly inside it).
        for (const Vec2& uv : {a.at, a.centroid}) {
          if (!(uv.x() > u0 + eu && uv.x() < u1 - eu && uv.y() > v0 + ev && uv.y() < v1 - ev)) continue;
          auto loc = to_plane(uv);
          CDT::Locate_type lt;
          int li;
          auto fh = cdt.locate(loc, lt, li, a.near->face());
          if (lt == CDT::VERTEX || lt == CDT::OUTSIDE_CONVEX_HULL || lt == CDT::OUTSIDE_AFFINE_HULL) continue;
          if (lt == CDT::EDGE && cdt.is_constrained(CDT::Edge(fh, li))) continue;
          int depth = fh->info().depth;
          if (depth % 2 != 1) continue;
          // Two places a rounding apart (the same midpoint reached from two triangles at a pole)
          // would give a zero-area triangle: the second is not a new point.
          double shortest = 1e300, nearest = 1e300;
          for (int k = 0; k < 3; ++k) {
            nearest = std::min(nearest, CGAL::squared_distance(loc, fh->vertex(k)->point()));
            shortest = std::min(shortest, CGAL::squared_distance(fh->vertex(k)->point(), fh->vertex((k + 1) % 3)->point()));
          }
          if (nearest <= 1e-12 * shortest) continue;
          auto h = cdt.insert(loc, fh);
          Vec3 J[3];
          S.jet(uv.x(), uv.y(), 1, J);
          h->info() = VInfo{out.add_vertex(Point3(J[0])), uv, -1, unit_normal(S, uv, J)};
          auto fc = cdt.incident_faces(h), done = fc;
          do {
            fc->info().depth = depth;
          } while (++fc != done);
          touched.push_back(h);
          ++inserted;
          break;
        }
      }
      if (!inserted) break;  // nothing more can be placed (see the measured-error tests)
      todo.clear();
      for (CDT::Vertex_handle v : touched) {
        auto fc = cdt.incident_faces(v), done = fc;
        if (fc != nullptr) do {
            if (fc->info().seen != round) {
              fc->info().seen = round;
              todo.push_back(fc);
            }
          } while (++fc != done);
      }
    }
    for (auto fh = cdt.finite_faces_begin(); fh != cdt.finite_faces_end(); ++fh) {
      if (fh->info().depth % 2 != 1) continue;
      std::uint32_t a = fh->vertex(0)->info().index, b = fh->vertex(1)->info().index, c = fh->vertex(2)->info().index;
      if (a == b || b == c || a == c) continue;
      if (sign > 0) out.add_triangle(a, b, c, f.value);
      else out.add_triangle(a, c, b, f.value);
      if (corner_uv) {
        // A pole's point stands for the whole collapsed row: each triangle takes it at the middle
        // of its other corners along the free axis (where its own limit normal is).
        std::array<Vec2, 3> uv;
        for (int k = 0; k < 3; ++k) {
          const VInfo& vi = fh->vertex(k)->info();
          uv[static_cast<std::size_t>(k)] = vi.uv;
          if (vi.free_axis >= 0)
            uv[static_cast<std::size_t>(k)][vi.free_axis] =
                (fh->vertex((k + 1) % 3)->info().uv[vi.free_axis] + fh->vertex((k + 2) % 3)->info().uv[vi.free_axis]) / 2;
        }
        if (sign <= 0) std::swap(uv[1], uv[2]);
        corner_uv->resize(out.triangles.size(), no_uv);
        corner_uv->back() = uv;
      }
    }
  });
  if (corner_uv) corner_uv->resize(out.triangles.size(), no_uv);
  return out;
}

}  // namespace wedge
