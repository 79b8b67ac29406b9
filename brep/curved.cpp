// Curved solids, built only through the Euler operators.
//
// build_from_loops(): a boundary given as faces (each one loop of edge sides) becomes a winged-edge
// model by the method of polyhedron() in build.cpp, with edges named by index instead of by their
// two vertices (so two edges may join the same vertices, and one loop may pass an edge both ways,
// as a seam does): the rotation of edge sides around each vertex is read off the loops (for a
// corner p -> q at vertex u, the side after reverse(p) around u is q); a spanning tree of the
// vertices grows by mev, each new side placed before the first present side that follows it in
// the rotation; each remaining edge closes with mef when its two corners share a loop, and with
// kfmrh + mekr (a handle) when they do not. A face with holes is given as one loop through
// "bridge" edges, which kemr turns into rings at the end.
//
// sweep_sides(): the generalised sweep (brep.h) as such a face list. Notation: loop k of the
// section, piece j, its side surface S_kj(u, v), u in [u0_kj, u1_kj] along the piece, v in
// [v0, v1] along the sweep. Vertices b_kj = S_kj(u0, v0) (start), t_kj = S_kj(u0, v1) (end of a
// capped sweep) or m_kj = S_kj(u0, vm) (half-way point of a closed one). Edges carry iso-parameter
// curves of the side surfaces and their images (PCurves) in the faces on both sides.
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "brep/brep.h"
#include "kernel/scaled.h"

namespace wedge {

namespace {

// A size of a curved primitive (radius, height): positive, and within 1e-100..kMaxCoordinate so
// that its areas and volumes (squares and cubes) neither overflow nor underflow to zero.
void require_extent(double x, const char* what) {
  require_positive(x, what);
  if (x > kMaxCoordinate) fail(what, " ", x, " is beyond ", kMaxCoordinate, " (volumes and normals would overflow)");
  if (x < 1 / kMaxCoordinate) fail(what, " ", x, " is below ", 1 / kMaxCoordinate, " (areas and volumes would underflow to zero)");
}

// The placement of a primitive of reach `extent` at `at`: every coordinate stays within kMaxCoordinate.
void require_placement(const Point3& at, double extent, const char* what) {
  if (!at.allFinite()) fail(what, ": the position (", at.x(), ", ", at.y(), ", ", at.z(), ") is not finite");
  if (!(at.cwiseAbs().maxCoeff() + extent <= kMaxCoordinate))
    fail(what, ": the solid at (", at.x(), ", ", at.y(), ", ", at.z(), ") would reach beyond +-", kMaxCoordinate,
         " (volumes and normals would overflow)");
}

struct LoopsSpec {
  std::vector<Point3> points;
  std::vector<std::array<int, 2>> edges;                 // v0, v1
  std::vector<std::vector<std::pair<int, int>>> faces;  // each: one loop of (edge, side)
};
struct Built {
  Model m;
  std::vector<EdgeId> edges;  // model edge of each spec edge, with v[0] = the spec's v0
  std::vector<FaceId> faces;
};

Built build_from_loops(const LoopsSpec& sp) {
  const int nv = static_cast<int>(sp.points.size()), ne = static_cast<int>(sp.edges.size());
  auto org = [&](int x) { return sp.edges[static_cast<std::size_t>(x / 2)][static_cast<std::size_t>(x % 2)]; };
  auto dst = [&](int x) { return sp.edges[static_cast<std::size_t>(x / 2)][static_cast<std::size_t>(1 - x % 2)]; };
  auto mate = [](int x) { return x ^ 1; };
  for (int e = 0; e < ne; ++e) {
    const auto& ed = sp.edges[static_cast<std::size_t>(e)];
    if (ed[0] == ed[1]) fail("build_from_loops: edge ", e, " starts and ends at vertex ", ed[0]);
    if (ed[0] < 0 || ed[1] < 0 || ed[0] >= nv || ed[1] >= nv) fail("build_from_loops: edge ", e, " names a missing vertex");
  }
  std::vector<int> used(static_cast<std::size_t>(2 * ne), 0), succ(static_cast<std::size_t>(2 * ne), -1);
  for (std::size_t f = 0; f < sp.faces.size(); ++f) {
    const auto& L = sp.faces[f];
    if (L.empty()) fail("build_from_loops: face ", f, " has no sides");
    for (std::size_t k = 0; k < L.size(); ++k) {
      int p = 2 * L[k].first + L[k].second, q = 2 * L[(k + 1) % L.size()].first + L[(k + 1) % L.size()].second;
      if (dst(p) != org(q)) fail("build_from_loops: face ", f, " is not a closed loop at its side ", k);
      if (used[static_cast<std::size_t>(p)]++) fail("build_from_loops: side ", p % 2, " of edge ", p / 2, " is used twice");
      if (succ[static_cast<std::size_t>(mate(p))] != -1) fail("build_from_loops: vertex ", dst(p), " is not 2-manifold");
      succ[static_cast<std::size_t>(mate(p))] = q;
    }
  }
  for (int x = 0; x < 2 * ne; ++x)
    if (!used[static_cast<std::size_t>(x)]) fail("build_from_loops: side ", x % 2, " of edge ", x / 2, " lies on no face");
  std::vector<std::vector<int>> outs(static_cast<std::size_t>(nv));
  for (int x = 0; x < 2 * ne; ++x) outs[static_cast<std::size_t>(org(x))].push_back(x);
  for (int u = 0; u < nv; ++u) {
    const auto& o = outs[static_cast<std::size_t>(u)];
    if (o.empty()) fail("build_from_loops: vertex ", u, " has no edges");
    int x = o[0];
    std::size_t n = 0;
    do {
      x = succ[static_cast<std::size_t>(x)];
      ++n;
    } while (x != o[0] && n <= o.size());
    if (n != o.size()) fail("build_from_loops: the faces around vertex ", u, " form more than one fan");
  }

  Built out;
  Model& m = out.m;
  std::vector<VertexId> vid(static_cast<std::size_t>(nv));
  std::vector<LoopId> lone(static_cast<std::size_t>(nv));
  std::vector<int> degree(static_cast<std::size_t>(nv), 0);
  std::vector<EdgeSide> ms(static_cast<std::size_t>(2 * ne));
  auto corner_at = [&](int u, int x) -> Corner {
    if (degree[static_cast<std::size_t>(u)] == 0) return Corner{lone[static_cast<std::size_t>(u)], {}, vid[static_cast<std::size_t>(u)]};
    int y = succ[static_cast<std::size_t>(x)];
    while (!ms[static_cast<std::size_t>(y)].valid()) y = succ[static_cast<std::size_t>(y)];
    EdgeSide s = ms[static_cast<std::size_t>(y)];
    return Corner{m.side(s).loop, s, vid[static_cast<std::size_t>(u)]};
  };
  std::vector<char> visited(static_cast<std::size_t>(nv), 0);
  for (int root = 0; root < nv; ++root) {
    if (visited[static_cast<std::size_t>(root)]) continue;
    visited[static_cast<std::size_t>(root)] = 1;
    auto s = m.mvfs(sp.points[static_cast<std::size_t>(root)]);
    vid[static_cast<std::size_t>(root)] = s.v;
    lone[static_cast<std::size_t>(root)] = m.faces()[s.f].outer;
    std::deque<int> queue{root};
    while (!queue.empty()) {
      int u = queue.front();
      queue.pop_front();
      for (int x : outs[static_cast<std::size_t>(u)]) {
        int w = dst(x);
        if (visited[static_cast<std::size_t>(w)]) continue;
        visited[static_cast<std::size_t>(w)] = 1;
        auto r = m.mev_at(corner_at(u, x), sp.points[static_cast<std::size_t>(w)]);
        vid[static_cast<std::size_t>(w)] = r.v;
        ms[static_cast<std::size_t>(x)] = EdgeSide{r.e, 0};
        ms[static_cast<std::size_t>(mate(x))] = EdgeSide{r.e, 1};
        degree[static_cast<std::size_t>(u)]++;
        degree[static_cast<std::size_t>(w)]++;
        queue.push_back(w);
      }
    }
  }
  for (int e = 0; e < ne; ++e) {
    int x0 = 2 * e, x1 = 2 * e + 1;
    if (ms[static_cast<std::size_t>(x0)].valid()) continue;
    Corner c1 = corner_at(org(x0), x0), c2 = corner_at(org(x1), x1);
    EdgeId id;
    if (c1.loop == c2.loop) {
      // The shorter side of the loop, found by walking both in step, becomes the new face (its
      // sides are relabelled: a revolved profile of 20,000 points closed each side face by
      // relabelling the rest of a loop of them all, quadratic). Which face is new does not
      // matter: faces are named by their loops below.
      EdgeSide a = c1.out, b = c2.out;
      bool first_shorter = false;
      while (true) {
        a = m.side(a).next;
        if (a == c2.out) {
          first_shorter = true;
          break;
        }
        b = m.side(b).next;
        if (b == c1.out) break;
      }
      id = first_shorter ? m.mef_at(c1.out, c2.out).e : m.mef_at(c2.out, c1.out).e;
      if (m.edges()[id].v[0] != vid[static_cast<std::size_t>(org(x0))]) m.reverse_edge(id);
    } else {
      FaceId f1 = m.loops()[c1.loop].face, f2 = m.loops()[c2.loop].face;
      if (f1 != f2) m.kfmrh(f2, f1);
      id = m.mekr_at(c1, c2);
      if (m.edges()[id].v[0] != vid[static_cast<std::size_t>(org(x0))]) m.reverse_edge(id);
    }
    ms[static_cast<std::size_t>(x0)] = EdgeSide{id, 0};
    ms[static_cast<std::size_t>(x1)] = EdgeSide{id, 1};
    degree[static_cast<std::size_t>(org(x0))]++;
    degree[static_cast<std::size_t>(org(x1))]++;
  }
  if (m.faces().size() != sp.faces.size())
    fail("build_from_loops: the loops give ", m.faces().size(), " faces, not ", sp.faces.size());
  // A tree edge grown along its side 1 runs backwards: turn it round (no topological change).
  for (int e = 0; e < ne; ++e) {
    EdgeSide s0 = ms[static_cast<std::size_t>(2 * e)];
    if (s0.side == 1) {
      m.reverse_edge(s0.edge);
      ms[static_cast<std::size_t>(2 * e)] = EdgeSide{s0.edge, 0};
      ms[static_cast<std::size_t>(2 * e + 1)] = EdgeSide{s0.edge, 1};
    }
    out.edges.push_back(s0.edge);
  }
  std::vector<char> taken(m.faces().capacity(), 0);
  for (std::size_t f = 0; f < sp.faces.size(); ++f) {
    const auto& L = sp.faces[f];
    EdgeSide s0 = ms[static_cast<std::size_t>(2 * L[0].first + L[0].second)];
    LoopId l = m.side(s0).loop;
    FaceId face = m.loops()[l].face;
    if (m.faces()[face].outer != l || m.loop_sides(l).size() != L.size() || taken[static_cast<std::size_t>(face.value)]++)
      fail("build_from_loops: face ", f, " does not close into a loop of its own");
    out.faces.push_back(face);
  }
  return out;
}

// --- the generalised sweep ---------------------------------------------------------------------

struct Geo {
  CurvePtr curve;
  // pcurve per side: the spec face of that side and its image
  std::optional<PCurve> pc[2];
};

Model sweep_raw(const std::vector<std::vector<SurfacePtr>>& sides, bool closed) {
  if (sides.empty() || sides[0].empty()) fail("sweep: the section has no pieces");
  const std::size_t K = sides.size();
  auto [v0, v1] = sides[0][0]->v_domain();
  double vm = (v0 + v1) / 2;
  // Size of the model, for the coincidence tolerance.
  Box3 box;
  for (const auto& loop : sides)
    for (const auto& S : loop) {
      auto [a, b] = S->u_domain();
      for (int i = 0; i <= 4; ++i)
        for (int j = 0; j <= 4; ++j) box.extend(S->eval(a + (b - a) * i / 4, v0 + (v1 - v0) * j / 4));
    }
  double eps = 1e-9 * std::max(box.diagonal(), 1e-300);
  auto ud = [&](std::size_t k, std::size_t j) { return sides[k][j]->u_domain(); };
  auto still = [&](std::size_t k, std::size_t j, double u) {  // S(u, v) does not move along v
    const Surface& S = *sides[k][j];
    Point3 p = S.eval(u, v0);
    for (int i = 1; i <= 6; ++i)
      if ((S.eval(u, v0 + (v1 - v0) * i / 6) - p).norm() > eps) return false;
    return true;
  };
  std::vector<std::vector<char>> pole(K), degenerate(K);
  for (std::size_t k = 0; k < K; ++k) {
    std::size_t n = sides[k].size();
    pole[k].resize(n);
    degenerate[k].resize(n);
    for (std::size_t j = 0; j < n; ++j) pole[k][j] = still(k, j, ud(k, j).first);
    for (std::size_t j = 0; j < n; ++j) {
      auto [a, b] = ud(k, j);
      degenerate[k][j] = pole[k][j] && pole[k][(j + 1) % n] && still(k, j, (a + b) / 2) && still(k, j, a + (b - a) / 3);
    }
  }
  // A capped sweep whose end section is one point ends in an apex.
  bool apex = false;
  Point3 apex_point;
  if (!closed) {
    apex_point = sides[0][0]->eval(ud(0, 0).first, v1);
    apex = true;
    for (std::size_t k = 0; k < K && apex; ++k)
      for (std::size_t j = 0; j < sides[k].size() && apex; ++j) {
        auto [a, b] = ud(k, j);
        for (int i = 0; i <= 4; ++i)
          if ((sides[k][j]->eval(a + (b - a) * i / 4, v1) - apex_point).norm() > eps) apex = false;
      }
    if (apex && K > 1) fail("sweep: a section with holes cannot shrink to an apex");
  }

  LoopsSpec sp;
  std::vector<Geo> geo;
  std::vector<FaceSurface> face_geo;
  std::vector<int> bridges;
  auto add_edge = [&](int a, int b, CurvePtr c) {
    sp.edges.push_back({a, b});
    geo.push_back(Geo{std::move(c), {}});
    return static_cast<int>(sp.edges.size()) - 1;
  };
  auto add_point = [&](const Point3& p) {
    sp.points.push_back(p);
    return static_cast<int>(sp.points.size()) - 1;
  };
  auto iso_u = [&](std::size_t k, std::size_t j, double v) {  // along the piece at v
    auto [a, b] = ud(k, j);
    return std::make_shared<const IsoCurve>(sides[k][j], true, v, a, b);
  };
  auto iso_v = [&](std::size_t k, std::size_t j, double a, double b) {  // along the sweep at u0
    return std::make_shared<const IsoCurve>(sides[k][j], false, ud(k, j).first, a, b);
  };
  int apex_v = apex ? add_point(apex_point) : -1;
  std::vector<std::vector<int>> bv(K), tv(K), bottom(K), top(K), strut(K), strut2(K), sidef(K);
  for (std::size_t k = 0; k < K; ++k) {
    std::size_t n = sides[k].size();
    bv[k].assign(n, -1);
    tv[k].assign(n, -1);
    bottom[k].assign(n, -1);
    top[k].assign(n, -1);
    strut[k].assign(n, -1);
    strut2[k].assign(n, -1);
    sidef[k].assign(n, -1);
    // Vertices: a pole whose both pieces are degenerate touches nothing and is left out.
    for (std::size_t j = 0; j < n; ++j) {
      bool lonely = closed && degenerate[k][j] && degenerate[k][(j + n - 1) % n];
      if (lonely) continue;
      bv[k][j] = add_point(sides[k][j]->eval(ud(k, j).first, v0));
      if (pole[k][j]) tv[k][j] = bv[k][j];
      else if (!closed) tv[k][j] = apex ? apex_v : add_point(sides[k][j]->eval(ud(k, j).first, v1));
      else tv[k][j] = add_point(sides[k][j]->eval(ud(k, j).first, vm));
    }
    for (std::size_t j = 0; j < n; ++j) {
      std::size_t jn = (j + 1) % n;
      if (closed && degenerate[k][j]) continue;
      bottom[k][j] = add_edge(bv[k][j], bv[k][jn], iso_u(k, j, v0));
      if (closed) continue;
      if (degenerate[k][j]) top[k][j] = bottom[k][j];
      else if (!apex) top[k][j] = add_edge(tv[k][j], tv[k][jn], iso_u(k, j, v1));
    }
    for (std::size_t j = 0; j < n; ++j) {
      if (pole[k][j]) continue;
      if (closed) {
        strut[k][j] = add_edge(bv[k][j], tv[k][j], iso_v(k, j, v0, vm));
        strut2[k][j] = add_edge(tv[k][j], bv[k][j], iso_v(k, j, vm, v1));
      } else {
        strut[k][j] = add_edge(bv[k][j], tv[k][j], iso_v(k, j, v0, v1));
      }
    }
    // Side faces and the pcurves of their sides.
    for (std::size_t j = 0; j < n; ++j) {
      if (degenerate[k][j]) continue;
      std::size_t jn = (j + 1) % n;
      auto [a, b] = ud(k, j);
      std::vector<std::pair<int, int>> L;
      auto put = [&](int e, int side, Vec2 s, Vec2 t) {
        L.emplace_back(e, side);
        geo[static_cast<std::size_t>(e)].pc[side] = PCurve{s, t};
      };
      put(bottom[k][j], 0, {a, v0}, {b, v0});
      if (closed) {
        if (!pole[k][jn]) {
          put(strut[k][jn], 0, {b, v0}, {b, vm});
          put(strut2[k][jn], 0, {b, vm}, {b, v1});
        }
        put(bottom[k][j], 1, {a, v1}, {b, v1});
        if (!pole[k][j]) {
          put(strut2[k][j], 1, {a, vm}, {a, v1});
          put(strut[k][j], 1, {a, v0}, {a, vm});
        }
      } else {
        if (!pole[k][jn]) put(strut[k][jn], 0, {b, v0}, {b, v1});
        if (!apex) put(top[k][j], 1, {a, v1}, {b, v1});
        if (!pole[k][j]) put(strut[k][j], 1, {a, v0}, {a, v1});
      }
      sidef[k][j] = static_cast<int>(sp.faces.size());
      sp.faces.push_back(std::move(L));
      face_geo.push_back(parametric_face(sides[k][j]));
    }
  }
  if (!closed) {
    // Caps: the bottom runs the section backwards (its outside faces -v), the top forwards. Holes
    // hang on bridges from the outer loop's first vertex.
    auto cap = [&](bool at_top) {
      std::vector<std::pair<int, int>> L;
      std::vector<Point3> pts;
      auto loop_sides = [&](std::size_t k) {
        std::size_t n = sides[k].size();
        for (std::size_t i = 0; i < n; ++i) {
          std::size_t j = at_top ? i : n - 1 - i;
          int e = at_top ? top[k][j] : bottom[k][j];
          L.emplace_back(e, at_top ? 0 : 1);
          if (k == 0)
            for (int s = 0; s < 8; ++s) {
              auto [a, b] = ud(k, j);
              double u = at_top ? a + (b - a) * s / 8 : b - (b - a) * s / 8;
              pts.push_back(sides[k][j]->eval(u, at_top ? v1 : v0));
            }
        }
      };
      loop_sides(0);
      const auto& vs = at_top ? tv : bv;
      for (std::size_t k = 1; k < K; ++k) {
        int br = add_edge(vs[0][0], vs[k][0], nullptr);
        bridges.push_back(br);
        L.emplace_back(br, 0);
        loop_sides(k);
        L.emplace_back(br, 1);
      }
      Vec3 nrm = unit_vector(newell_normal(pts));
      if (nrm == Vec3::Zero()) fail("sweep: an end section has no area");
      sp.faces.push_back(std::move(L));
      face_geo.push_back(plane_face(pts[0], nrm));
    };
    cap(false);
    if (!apex) cap(true);
  }
  Built B = build_from_loops(sp);
  Model& m = B.m;
  for (std::size_t e = 0; e < geo.size(); ++e) {
    EdgeId id = B.edges[e];
    if (geo[e].curve) m.set_curve(id, geo[e].curve);
    for (int s = 0; s < 2; ++s)
      if (geo[e].pc[s]) m.set_pcurve(EdgeSide{id, s}, *geo[e].pc[s]);
  }
  for (std::size_t f = 0; f < face_geo.size(); ++f) m.set_surface(B.faces[f], face_geo[f]);
  for (int br : bridges) m.kemr(B.edges[static_cast<std::size_t>(br)]);
  Validation v = m.validate(false);
  if (!v) fail("sweep: the swept boundary is not a valid solid: ", v.message);
  return m;
}

SectionLoop reversed(const SectionLoop& l) {
  SectionLoop out;
  for (auto it = l.rbegin(); it != l.rend(); ++it) out.push_back(std::make_shared<const ReversedCurve>(*it));
  return out;
}
Section reversed(const Section& s) {
  Section out{reversed(s.outer), {}};
  for (const auto& h : s.holes) out.holes.push_back(reversed(h));
  return out;
}
// Twice the signed area of a loop about +z (its pieces sampled).
double area2(const SectionLoop& l) {
  std::vector<Point3> p;
  for (const auto& c : l) {
    auto [a, b] = c->domain();
    for (int i = 0; i < 16; ++i) p.push_back(c->eval(a + (b - a) * i / 16));
  }
  double s = 0;
  for (std::size_t i = 0; i < p.size(); ++i) s += p[i].x() * p[(i + 1) % p.size()].y() - p[(i + 1) % p.size()].x() * p[i].y();
  return s;
}
// Outer counter-clockwise, holes clockwise; every piece joins the next.
Section normalised(const Section& s, const char* what) {
  auto check = [&](const SectionLoop& l, const char* which) {
    if (l.empty()) fail(what, ": the section's ", which, " loop has no pieces");
    for (std::size_t i = 0; i < l.size(); ++i) {
      if (!l[i]) fail(what, ": a piece of the section is missing");
      Point3 e = l[i]->eval(l[i]->domain().second), b = l[(i + 1) % l.size()]->eval(l[(i + 1) % l.size()]->domain().first);
      if ((e - b).norm() > 1e-9 * (1 + e.norm())) fail(what, ": the section's ", which, " loop is not closed (piece ", i + 1, " does not end where the next starts)");
      if (l.size() == 1) fail(what, ": a loop of one piece starts and ends at one point (split it: loop_of_curve)");
    }
    if (area2(l) == 0) fail(what, ": the section's ", which, " loop encloses no area");
  };
  check(s.outer, "outer");
  for (const auto& h : s.holes) check(h, "inner");
  Section out{area2(s.outer) > 0 ? s.outer : reversed(s.outer), {}};
  for (const auto& h : s.holes) out.holes.push_back(area2(h) < 0 ? h : reversed(h));
  return out;
}

// The cyclic shift of loop l (pieces in the same order) whose pieces lie nearest those of loop ref,
// by the sum of squared distances between points at the same fractions of corresponding pieces
// (the correspondence a loft's sides use): a loft from a square to the same square starting at
// another corner otherwise twisted into an hourglass pinched to a point.
SectionLoop aligned(const SectionLoop& l, const SectionLoop& ref) {
  const std::size_t n = l.size();
  constexpr int kSamples = 8;
  auto samples = [&](const SectionLoop& loop) {
    std::vector<Point3> p;
    for (const auto& c : loop) {
      auto [a, b] = c->domain();
      for (int i = 0; i < kSamples; ++i) p.push_back(c->eval(a + (b - a) * (i + 0.5) / kSamples));
    }
    return p;
  };
  const std::vector<Point3> p = samples(l), q = samples(ref);
  std::size_t best = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  for (std::size_t shift = 0; shift < n; ++shift) {
    double cost = 0;
    for (std::size_t j = 0; j < n; ++j)
      for (int i = 0; i < kSamples; ++i) {
        const Point3& a = p[((j + shift) % n) * kSamples + static_cast<std::size_t>(i)];
        const Point3& b = q[j * kSamples + static_cast<std::size_t>(i)];
        cost += (a.head<2>() - b.head<2>()).squaredNorm();
      }
    if (cost < best_cost) best_cost = cost, best = shift;
  }
  SectionLoop out;
  for (std::size_t j = 0; j < n; ++j) out.push_back(l[(j + best) % n]);
  return out;
}

// Builds from the section, and from its mirror image when the sweep turns it inside out (a
// revolve maps the XY plane's counter-clockwise onto clockwise seen from outside).
template <class MakeSide>
Model oriented_sweep(const Section& s0, bool closed, MakeSide make, const char* what) {
  Section s = normalised(s0, what);
  for (int attempt = 0; attempt < 2; ++attempt) {
    std::vector<std::vector<SurfacePtr>> sides;
    std::vector<const SectionLoop*> loops{&s.outer};
    for (const auto& h : s.holes) loops.push_back(&h);
    for (const SectionLoop* l : loops) {
      sides.emplace_back();
      for (const auto& piece : *l) sides.back().push_back(make(piece));
    }
    Model m = sweep_raw(sides, closed);
    double vol = m.approximate_volume();
    if (vol > 0) {
      Validation v = m.validate();
      if (!v) fail(what, ": the result is not a valid solid: ", v.message);
      return m;
    }
    s = reversed(s);
  }
  fail(what, ": the swept solid encloses no volume");
}

// Names every curved face of m as s:faces() reports it.
Model named(Model m, const char* kind) {
  for (FaceId f : m.faces().ids())
    if (m.surface(f).parametric) {
      FaceSurface named_surface = m.surface(f);
      named_surface.kind = kind;
      m.set_surface(f, named_surface);
    }
  return m;
}

}  // namespace

// --- a closed set of patches ---------------------------------------------------------------------
//
// patch_solid(): each patch's domain [u0, u1] x [v0, v1] has four boundary sides, counter-clockwise
// in (u, v): v = v0 (u rising), u = u1 (v rising), v = v1 (u falling), u = u0 (v falling). A side
// that maps to one point is a pole (no edge); a side whose two ends meet (a full circle) is split at
// its middle parameter. Corners closer than eps are one vertex. Two sides join into one edge when
// they run between the same two vertices in opposite directions and agree at interior samples (at
// the same fraction of their parameter segments); the sides left over form the open boundary, which
// is cut into loops, and each loop, if planar, is closed by a planar cap.

namespace {

struct PatchSide {
  std::size_t patch;
  Vec2 from, to;  // parameters, in the patch loop's direction
  int a = -1, b = -1;  // vertices at from and to
  int edge = -1, side = -1;
};

Model patch_solid_raw(const std::vector<SurfacePtr>& patches, const std::string& kind, bool flip, double eps) {
  const char* what = "patch_solid";
  std::vector<Point3> points;
  auto vertex = [&](const Point3& p) {
    for (std::size_t i = 0; i < points.size(); ++i)
      if ((points[i] - p).norm() <= eps) return static_cast<int>(i);
    points.push_back(p);
    return static_cast<int>(points.size()) - 1;
  };
  auto at = [&](const PatchSide& sd, double f) { return patches[sd.patch]->eval(sd.from.x() + f * (sd.to.x() - sd.from.x()), sd.from.y() + f * (sd.to.y() - sd.from.y())); };
  static const double kSamples[] = {0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875};
  std::vector<std::vector<PatchSide>> loops(patches.size());
  for (std::size_t i = 0; i < patches.size(); ++i) {
    auto [u0, u1] = patches[i]->u_domain();
    auto [v0, v1] = patches[i]->v_domain();
    Vec2 c[4] = {{u0, v0}, {u1, v0}, {u1, v1}, {u0, v1}};
    for (int k = 0; k < 4; ++k) {
      PatchSide sd{i, c[k], c[(k + 1) % 4]};
      Point3 pa = at(sd, 0), pb = at(sd, 1);
      bool pole = (pa - pb).norm() <= eps;
      for (double f : kSamples) pole = pole && (at(sd, f) - pa).norm() <= eps;
      if (pole) continue;
      if ((pa - pb).norm() <= eps) {  // a closed side: two halves
        Vec2 mid = 0.5 * (sd.from + sd.to);
        loops[i].push_back(PatchSide{i, sd.from, mid});
        loops[i].push_back(PatchSide{i, mid, sd.to});
      } else {
        loops[i].push_back(sd);
      }
    }
    if (loops[i].size() < 2) fail(what, ": patch ", i + 1, " has fewer than two sides that are not poles (it is a point or a curve)");
    if (flip) {
      std::reverse(loops[i].begin(), loops[i].end());
      for (auto& sd : loops[i]) std::swap(sd.from, sd.to);
    }
    for (auto& sd : loops[i]) {
      sd.a = vertex(at(sd, 0));
      sd.b = vertex(at(sd, 1));
    }
  }
  // Join the sides into edges.
  LoopsSpec sp;
  std::vector<Geo> geo;
  std::vector<PatchSide*> all;
  for (auto& l : loops)
    for (auto& sd : l) all.push_back(&sd);
  auto same_points = [&](const PatchSide& x, const PatchSide& y, bool reversed) {
    for (double f : kSamples)
      if ((at(x, f) - at(y, reversed ? 1 - f : f)).norm() > eps) return false;
    return true;
  };
  auto new_edge = [&](PatchSide& x) {  // an edge along x, v[0] at x's start, x on side 0
    sp.edges.push_back({x.a, x.b});
    bool along_u = x.from.y() == x.to.y();
    double lo = along_u ? x.from.x() : x.from.y(), hi = along_u ? x.to.x() : x.to.y();
    double value = along_u ? x.from.y() : x.from.x();
    CurvePtr c = std::make_shared<const IsoCurve>(patches[x.patch], along_u, value, std::min(lo, hi), std::max(lo, hi));
    if (hi < lo) c = std::make_shared<const ReversedCurve>(c);
    geo.push_back(Geo{c, {}});
    geo.back().pc[0] = PCurve{x.from, x.to};
    x.edge = static_cast<int>(sp.edges.size()) - 1;
    x.side = 0;
  };
  for (std::size_t i = 0; i < all.size(); ++i) {
    PatchSide& x = *all[i];
    if (x.edge >= 0) continue;
    new_edge(x);
    for (std::size_t j = i + 1; j < all.size(); ++j) {
      PatchSide& y = *all[j];
      if (y.edge >= 0) continue;
      if (y.a == x.a && y.b == x.b && same_points(x, y, false))
        fail(what, ": patches ", x.patch + 1, " and ", y.patch + 1,
             " share an edge that runs the same way in both (the patches are not oriented alike)");
      if (y.a == x.b && y.b == x.a && same_points(x, y, true)) {
        y.edge = x.edge;
        y.side = 1;
        geo[static_cast<std::size_t>(x.edge)].pc[1] = PCurve{y.to, y.from};
        break;
      }
    }
  }
  // Faces: the patches, then a cap per loop of the open boundary.
  std::vector<FaceSurface> face_geo;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    std::vector<std::pair<int, int>> L;
    for (const auto& sd : loops[i]) L.emplace_back(sd.edge, sd.side);
    sp.faces.push_back(std::move(L));
    face_geo.push_back(parametric_face(patches[i], flip, kind));
  }
  std::vector<PatchSide*> open;
  for (PatchSide* x : all)
    if (geo[static_cast<std::size_t>(x->edge)].pc[1] == std::nullopt) open.push_back(x);
  // A cap runs each open side backwards (b -> a); after x comes the open side that ends at x.a.
  std::vector<char> capped(open.size(), 0);
  for (std::size_t i = 0; i < open.size(); ++i) {
    if (capped[i]) continue;
    std::vector<std::pair<int, int>> L;
    std::vector<Point3> pts;
    for (std::size_t k = i;;) {
      capped[k] = 1;
      const PatchSide& x = *open[k];
      L.emplace_back(x.edge, 1);
      for (int s = 0; s < 8; ++s) pts.push_back(at(x, 1 - s / 8.0));
      std::size_t next = open.size();
      for (std::size_t j = 0; j < open.size(); ++j)
        if (open[j]->b == x.a) {
          if (next != open.size()) fail(what, ": the patches' open boundary branches at (", points[x.a].x(), ", ", points[x.a].y(), ", ", points[x.a].z(), ")");
          next = j;
        }
      if (next == open.size()) fail(what, ": the patches' open boundary stops at (", points[x.a].x(), ", ", points[x.a].y(), ", ", points[x.a].z(), ")");
      if (next == i) break;
      if (capped[next]) fail(what, ": the patches' open boundary crosses itself at (", points[x.a].x(), ", ", points[x.a].y(), ", ", points[x.a].z(), ")");
      k = next;
    }
    Vec3 n = unit_vector(newell_normal(pts));
    if (n == Vec3::Zero()) fail(what, ": a loop of the patches' open boundary encloses no area");
    double off = 0;
    for (const Point3& p : pts) off = std::max(off, std::abs((p - pts[0]).dot(n)));
    if (off > 1e3 * eps)
      fail(what, ": the patches leave an open boundary of ", L.size(), " edges that is not planar (", off,
           " off its plane), so it cannot be closed by a cap");
    sp.faces.push_back(std::move(L));
    face_geo.push_back(plane_face(pts[0], n));
  }
  sp.points = points;
  Built B;
  try {
    B = build_from_loops(sp);
  } catch (const Error& e) {
    fail(what, ": the patches and caps do not form a closed 2-manifold boundary (", e.what(), ")");
  }
  Model& m = B.m;
  for (std::size_t e = 0; e < geo.size(); ++e) {
    EdgeId id = B.edges[e];
    m.set_curve(id, geo[e].curve);
    for (int s = 0; s < 2; ++s)
      if (geo[e].pc[s]) m.set_pcurve(EdgeSide{id, s}, *geo[e].pc[s]);
  }
  for (std::size_t f = 0; f < face_geo.size(); ++f) m.set_surface(B.faces[f], face_geo[f]);
  return m;
}

}  // namespace

Model patch_solid(const std::vector<SurfacePtr>& patches, const std::string& kind) {
  if (patches.empty()) fail("patch_solid: no patches");
  Box3 box;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    if (!patches[i]) fail("patch_solid: patch ", i + 1, " is missing");
    if (!patches[i]->trims.empty()) fail("patch_solid: patch ", i + 1, " is trimmed (only whole patches can bound a solid yet)");
    auto [u0, u1] = patches[i]->u_domain();
    auto [v0, v1] = patches[i]->v_domain();
    for (int a = 0; a <= 4; ++a)
      for (int b = 0; b <= 4; ++b) {
        Point3 p = patches[i]->eval(u0 + (u1 - u0) * a / 4, v0 + (v1 - v0) * b / 4);
        if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate)
          fail("patch_solid: patch ", i + 1, " has a point that is not finite or beyond +-", kMaxCoordinate);
        box.extend(p);
      }
  }
  double eps = 1e-9 * std::max(box.diagonal(), 1e-300);
  for (bool flip : {false, true}) {
    Model m = patch_solid_raw(patches, kind, flip, eps);
    if (m.approximate_volume() > 0) {
      Validation v = m.validate();
      if (!v) fail("patch_solid: the patches do not bound a valid solid: ", v.message);
      return m;
    }
  }
  fail("patch_solid: the patches enclose no volume");
}

Model sweep_sides(const std::vector<std::vector<SurfacePtr>>& sides, bool closed) {
  Model m = sweep_raw(sides, closed);
  Validation v = m.validate();
  if (!v) fail("sweep: ", v.message);
  return m;
}

SectionLoop circle_loop(const Vec2& c, double r) {
  require_extent(r, "circle radius");
  Point3 center(c.x(), c.y(), 0);
  return {std::make_shared<const CircularArc>(center, r, 0.0, kPi), std::make_shared<const CircularArc>(center, r, kPi, 2 * kPi)};
}

SectionLoop loop_of_curve(const CurvePtr& c) {
  if (!c || !c->closed()) fail("profile: the curve is not closed");
  auto [a, b] = c->domain();
  double m = (a + b) / 2;
  return {std::make_shared<const SubCurve>(c, a, m), std::make_shared<const SubCurve>(c, m, b)};
}

Section section_of(const Profile& p) {
  auto loop = [](const std::vector<Vec2>& pts) {
    if (pts.size() < 3) fail("profile: a polygon needs at least 3 points, got ", pts.size());
    SectionLoop l;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec2& a = pts[i];
      const Vec2& b = pts[(i + 1) % pts.size()];
      if (a == b) fail("profile: polygon point ", i + 1, " repeats the next one");
      l.push_back(std::make_shared<const LineSegment>(Point3(a.x(), a.y(), 0), Point3(b.x(), b.y(), 0)));
    }
    return l;
  };
  Section s{loop(p.outer), {}};
  for (const auto& h : p.holes) s.holes.push_back(loop(h));
  return s;
}

Model extrude(const Section& s, double h, double twist, double scale) {
  require_extent(h, "extrude height");
  if (scale > kMaxCoordinate) fail("extrude: scale ", scale, " is beyond ", kMaxCoordinate);
  if (!std::isfinite(twist)) fail("extrude: twist is not finite");
  // Beyond a hundred turns the twisted surface's tessellation (and its arc lengths) lose their
  // precision: a rectangle twisted 1e300 degrees had a volume of 1.7e281.
  if (!(std::abs(twist) <= 200 * kPi)) fail("extrude: twist ", degrees(twist), " degrees is beyond +-36000 (100 turns)");
  if (!(scale >= 0) || !std::isfinite(scale)) fail("extrude: scale must be >= 0, got ", scale);
  return named(oriented_sweep(s, false, [&](const CurvePtr& c) -> SurfacePtr {
    return std::make_shared<const TwistedExtrusionSurface>(c, h, twist, scale);
  }, "extrude"), "extruded");
}

Model revolve(const Section& s, double angle) {
  if (!(angle > 0) || angle > 2 * kPi * (1 + 1e-12)) fail("revolve: angle must be in (0, 360] degrees, got ", degrees(angle));
  auto check_x = [](const SectionLoop& l) {
    for (const auto& c : l) {
      auto [a, b] = c->domain();
      for (int i = 0; i <= 32; ++i)
        if (c->eval(a + (b - a) * i / 32).x() < -1e-12) fail("revolve: the profile crosses the axis (x < 0): every x must be >= 0");
    }
  };
  check_x(s.outer);
  for (const auto& h : s.holes) check_x(h);
  // A corner of the profile on the axis whose pieces both leave it (a triangle with one corner at
  // x = 0) revolves into a solid pinched to a point there: "build_from_loops: the faces around
  // vertex 0 form more than one fan" said nothing a script could act on. On the axis, a corner
  // needs a piece along it (a half disk's diameter, for a sphere).
  auto check_pinch = [](const SectionLoop& l) {
    double size = 0;
    for (const auto& c : l) {
      auto [a, b] = c->domain();
      for (int i = 0; i <= 8; ++i) size = std::max(size, c->eval(a + (b - a) * i / 8).head<2>().cwiseAbs().maxCoeff());
    }
    const double tol = 1e-12 * size;
    auto along_axis = [&](const CurvePtr& c) {
      auto [a, b] = c->domain();
      for (int i = 0; i <= 8; ++i)
        if (std::abs(c->eval(a + (b - a) * i / 8).x()) > tol) return false;
      return true;
    };
    for (std::size_t i = 0; i < l.size(); ++i) {
      const Point3 p = l[i]->eval(l[i]->domain().second);
      if (std::abs(p.x()) <= tol && !along_axis(l[i]) && !along_axis(l[(i + 1) % l.size()]))
        fail("revolve: the profile touches the axis at (0, ", p.y(), ") at a corner only: the solid would pinch to a point "
             "there (give the profile an edge along the axis there, or keep it off the axis)");
    }
  };
  check_pinch(s.outer);
  for (const auto& h : s.holes) check_pinch(h);
  bool full = angle >= 2 * kPi * (1 - 1e-12);
  double a = full ? 2 * kPi : angle;
  Model m = oriented_sweep(s, full, [&](const CurvePtr& c) -> SurfacePtr { return std::make_shared<const RevolutionSurface>(c, a); },
                           "revolve");
  // A profile point on the axis gives a pole; its position comes from the profile, where it may
  // miss the axis by a rounding (a sphere's arc ends at r cos(pi/2) = 6e-17 r): put it on the axis
  // exactly, so that the pole lies on every plane through the axis (a boolean cutting a sphere
  // there otherwise sees the pole a rounding across the cut).
  double size = 0;
  m.vertices().for_each([&](VertexId v, const BrepVertex&) { size = std::max(size, m.point(v).cwiseAbs().maxCoeff()); });
  m.vertices().for_each([&](VertexId v, const BrepVertex&) {
    const Point3 p = m.point(v);
    if ((p.x() != 0 || p.y() != 0) && std::hypot(p.x(), p.y()) <= 1e-12 * size) m.set_point(v, Point3(0, 0, p.z()));
  });
  return named(std::move(m), "revolved");
}

Model sweep_along(const Section& s, const CurvePtr& path) {
  if (!path) fail("sweep: no path");
  // A closed path gives a ring: the frames' holonomy is spread along it (SweptSurface), and the
  // sweep closes on itself with no caps.
  bool closed = path->closed();
  const std::shared_ptr<const SweepFrames> frames = sweep_frames(path, 512, closed);
  return named(oriented_sweep(s, closed, [&](const CurvePtr& c) -> SurfacePtr {
    return std::make_shared<const SweptSurface>(c, frames);
  }, "sweep"), "swept");
}

namespace {

// Refuses a loft whose blend turns a section over. The sides blend the sections with the cardinal
// natural cubic splines N_i(v) (LoftedSurface), which can overshoot: through half-widths 1, 0.1, 1
// at heights 0, 1, 1.05 a square's half-width followed the cubic down to -2.996, so the square
// shrank to a point and turned over. That solid passed validate() (its faces are parametric and
// the pinch is inside one), and tessellating it ran 33 s and 2.6 GB into the point budget.
//
// The test is exact up to the sampling in v: the section of a loop at v is sum_i N_i(v) C_i(u), so
// the mixed area of the sections at v and w, 1/2 of the integral of x_v y_w' - y_v x_w', is the
// bilinear form N(v)^T B N(w) with B_ij the mixed areas of the profiles' loops (each piece taken
// over [0, 1], as LoftedSurface does). A section that turns over between two samples v < w has a
// mixed area of the opposite sign to the loop's own (a square scaled by s and by s' < 0: s s' times
// its area), and one that pinches to a point or a line there has none. Sampling each pair of
// heights 64 times costs n^2 products per sample; B costs one quadrature per piece and profile.
void require_no_turnover(const std::vector<SectionLoop>& loops, const std::vector<double>& params,
                         const std::vector<double>& heights, const char* which) {
  const std::size_t n = loops.size();
  // Points and derivatives at Gauss-Legendre nodes (8 per sixteenth of each piece's domain).
  static const double kX[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
  static const double kW[4] = {0.3626837833783620, 0.3137066708834664, 0.2223810344533745, 0.1012285362903763};
  constexpr int kPanels = 16;
  std::vector<std::vector<Vec3>> p(n), d(n);
  std::vector<double> weight;
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& c : loops[i]) {
      auto [a, b] = c->domain();
      for (int k = 0; k < kPanels; ++k)
        for (int g = 0; g < 8; ++g) {
          const double x = g < 4 ? -kX[g] : kX[g - 4], u = (k + 0.5 + 0.5 * x) / kPanels;
          p[i].push_back(c->derivative(a + u * (b - a), 0));
          d[i].push_back((b - a) * c->derivative(a + u * (b - a), 1));
          if (i == 0) weight.push_back(kW[g % 4] / (2 * kPanels));
        }
    }
  Eigen::MatrixXd B(n, n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      double s = 0;
      for (std::size_t q = 0; q < weight.size(); ++q) s += weight[q] * (p[i][q].x() * d[j][q].y() - p[i][q].y() * d[j][q].x());
      B(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = s / 2;
    }
  // Symmetric in exact arithmetic (integration by parts); the mean of the two quadratures.
  B = (0.5 * (B + B.transpose())).eval();
  std::vector<HermiteSpline> cardinal;
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<Point3> e(n, Point3::Zero());
    e[i] = Point3(1, 0, 0);
    cardinal.push_back(natural_spline(params, e));
  }
  auto blend = [&](double v) {
    Eigen::VectorXd N(n);
    for (std::size_t i = 0; i < n; ++i) N(static_cast<Eigen::Index>(i)) = cardinal[i].derivative(v, 0).x();
    return N;
  };
  const double sign = B(0, 0) > 0 ? 1 : -1;  // outer loops counter-clockwise, holes clockwise
  constexpr int kSteps = 64;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    Eigen::VectorXd prev = blend(params[i]);
    for (int s = 1; s <= kSteps; ++s) {
      const double v = s == kSteps ? params[i + 1] : params[i] + (params[i + 1] - params[i]) * s / kSteps;
      const Eigen::VectorXd N = blend(v);
      if (!(sign * prev.dot(B * N) > 0) || !(sign * N.dot(B * N) > 0)) {
        const double z = heights[i] + (heights[i + 1] - heights[i]) * (s - 0.5) / kSteps;
        fail("loft: between profiles ", i + 1, " and ", i + 2, " (heights ", heights[i], " and ", heights[i + 1],
             ") the spline through the profiles shrinks ", which, " to nothing and turns it over near height ",
             z, ": space the heights more evenly, or add profiles where the shape changes fast");
      }
      prev = N;
    }
  }
}

}  // namespace

Model loft(const std::vector<Section>& sections, const std::vector<double>& heights) {
  if (sections.size() < 2) fail("loft: needs at least two profiles, got ", sections.size());
  if (heights.size() != sections.size()) fail("loft: ", sections.size(), " profiles but ", heights.size(), " heights");
  for (std::size_t i = 1; i < heights.size(); ++i)
    if (!(heights[i] > heights[i - 1])) fail("loft: heights must increase (height ", i + 1, " is ", heights[i], ")");
  std::vector<Section> ns;
  for (const auto& s : sections) ns.push_back(normalised(s, "loft"));
  for (std::size_t i = 1; i < ns.size(); ++i) {
    if (ns[i].holes.size() != ns[0].holes.size()) fail("loft: profile ", i + 1, " has a different number of holes than profile 1");
    if (ns[i].outer.size() != ns[0].outer.size())
      fail("loft: profile ", i + 1, " has ", ns[i].outer.size(), " pieces, profile 1 has ", ns[0].outer.size(), " (they must match)");
    for (std::size_t k = 0; k < ns[0].holes.size(); ++k)
      if (ns[i].holes[k].size() != ns[0].holes[k].size()) fail("loft: hole ", k + 1, " of profile ", i + 1, " has a different number of pieces");
  }
  // Each loop starts where it best matches the same loop of the profile below (ns[0] as given).
  for (std::size_t i = 1; i < ns.size(); ++i) {
    ns[i].outer = aligned(ns[i].outer, ns[i - 1].outer);
    for (std::size_t k = 0; k < ns[i].holes.size(); ++k) ns[i].holes[k] = aligned(ns[i].holes[k], ns[i - 1].holes[k]);
  }
  // The sections' parameters in proportion to their heights: z is then linear along the side
  // (LoftedSurface), never outside [heights.front(), heights.back()].
  std::vector<double> params(heights.size());
  for (std::size_t i = 0; i < heights.size(); ++i) params[i] = (heights[i] - heights[0]) / (heights.back() - heights[0]);
  params.back() = 1;
  if (ns.size() > 2) {
    // Two profiles blend linearly: between two sections of positive area the mixed area can
    // still reach zero only where the loft would cross itself, which validate() sees on its caps.
    std::vector<SectionLoop> outer;
    for (const auto& s : ns) outer.push_back(s.outer);
    require_no_turnover(outer, params, heights, "the outer loop");
    for (std::size_t k = 0; k < ns[0].holes.size(); ++k) {
      std::vector<SectionLoop> hole;
      for (const auto& s : ns) hole.push_back(s.holes[k]);
      require_no_turnover(hole, params, heights, ("hole " + std::to_string(k + 1)).c_str());
    }
  }
  // Pieces of every section at their heights; the side of piece j lofts piece j of each.
  std::vector<std::vector<SurfacePtr>> sides;
  std::size_t K = 1 + ns[0].holes.size();
  for (std::size_t k = 0; k < K; ++k) {
    sides.emplace_back();
    std::size_t n = (k == 0 ? ns[0].outer : ns[0].holes[k - 1]).size();
    for (std::size_t j = 0; j < n; ++j) {
      std::vector<CurvePtr> secs;
      for (std::size_t i = 0; i < ns.size(); ++i) {
        const SectionLoop& l = k == 0 ? ns[i].outer : ns[i].holes[k - 1];
        secs.push_back(std::make_shared<const TransformedCurve>(l[j], translate(Vec3(0, 0, heights[i]))));
      }
      sides.back().push_back(std::make_shared<const LoftedSurface>(secs, params));
    }
  }
  Model m = sweep_raw(sides, false);
  Validation v = m.validate();
  if (!v) fail("loft: the result is not a valid solid: ", v.message);
  return named(std::move(m), "lofted");
}

Model sphere(double r, const Point3& c) {
  require_extent(r, "sphere radius");
  require_placement(c, r, "sphere");
  Section s{{std::make_shared<const CircularArc>(Point3::Zero(), r, -kPi / 2, kPi / 2),
             std::make_shared<const LineSegment>(Point3(0, r, 0), Point3(0, -r, 0))},
            {}};
  Model m = revolve(s, 2 * kPi);
  if (c != Point3::Zero()) m.transform(translate(c));
  return named(std::move(m), "sphere");
}

Model cylinder(double r, double h, const Point3& base) {
  require_extent(r, "cylinder radius");
  require_extent(h, "cylinder height");
  require_placement(base, std::max(r, h), "cylinder");
  Model m = extrude(Section{circle_loop(Vec2::Zero(), r), {}}, h);
  if (base != Point3::Zero()) m.transform(translate(base));
  return named(std::move(m), "cylinder");
}

Model cone(double r1, double r2, double h, const Point3& base) {
  require_positive(h, "cone height");
  if (!(r1 >= 0) || !(r2 >= 0) || !std::isfinite(r1) || !std::isfinite(r2)) fail("cone: radii must be >= 0, got ", r1, " and ", r2);
  if (r1 == 0 && r2 == 0) fail("cone: r1 and r2 are both 0 (no volume)");
  require_extent(h, "cone height");
  if (r1 > 0) require_extent(r1, "cone radius r1");
  if (r2 > 0) require_extent(r2, "cone radius r2");
  require_placement(base, std::max({r1, r2, h}), "cone");
  Model m;
  if (r1 > 0) {
    m = extrude(Section{circle_loop(Vec2::Zero(), r1), {}}, h, 0, r2 / r1);
  } else {
    // Apex at the bottom: the apex-up cone of radius r2, turned over about x.
    m = extrude(Section{circle_loop(Vec2::Zero(), r2), {}}, h, 0, 0);
    m.transform(translate(Vec3(0, 0, h)) * rotate_x(180));
  }
  if (base != Point3::Zero()) m.transform(translate(base));
  return named(std::move(m), "cone");
}

Model torus(double R, double r, const Point3& c) {
  require_extent(R, "torus major radius R");
  require_extent(r, "torus minor radius r");
  require_placement(c, R + r, "torus");
  if (!(r < R)) fail("torus: the minor radius r (", r, ") must be less than the major radius R (", R, ")");
  Model m = revolve(Section{circle_loop(Vec2(R, 0), r), {}}, 2 * kPi);
  if (c != Point3::Zero()) m.transform(translate(c));
  return named(std::move(m), "torus");
}

Model tube(double ro, double ri, double h, const Point3& base) {
  require_extent(ro, "tube outer radius");
  require_extent(ri, "tube inner radius");
  require_extent(h, "tube height");
  require_placement(base, std::max(ro, h), "tube");
  if (!(ri < ro)) fail("tube: the inner radius (", ri, ") must be less than the outer radius (", ro, ")");
  Model m = extrude(Section{circle_loop(Vec2::Zero(), ro), {circle_loop(Vec2::Zero(), ri)}}, h);
  if (base != Point3::Zero()) m.transform(translate(base));
  return named(std::move(m), "cylinder");
}

}  // namespace wedge
