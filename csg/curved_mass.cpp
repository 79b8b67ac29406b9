#include "csg/curved_mass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "kernel/parallel.h"
#include "surfaces/surfaces.h"

namespace wedge {

namespace {

// Integrals about a reference point: volume, area, first and second moments.
struct Sums {
  double volume = 0, area = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  void add(const Sums& o) {
    volume += o.volume;
    area += o.area;
    first += o.first;
    second += o.second;
  }
};

// Dunavant's 6-point rule, degree 4, on the triangle b0 + b1 + b2 = 1 (weights sum to 1).
struct TriPoint {
  double b1, b2, w;
};
constexpr double kA1 = 0.445948490915965, kB1 = 0.108103018168070, kW1 = 0.223381589678011;
constexpr double kA2 = 0.091576213509771, kB2 = 0.816847572980459, kW2 = 0.109951743655322;
constexpr std::array<TriPoint, 6> kTri{{{kA1, kA1, kW1}, {kA1, kB1, kW1}, {kB1, kA1, kW1},
                                        {kA2, kA2, kW2}, {kA2, kB2, kW2}, {kB2, kA2, kW2}}};
// Gauss-Legendre, 3 points on [0, 1].
constexpr std::array<double, 3> kL{0.1127016653792583, 0.5, 0.8872983346207417};
constexpr std::array<double, 3> kLw{5.0 / 18, 8.0 / 18, 5.0 / 18};

// The surface point over q and its derivatives along the triangle's two sides a1, a2.
struct OnSurface {
  Vec3 s, s1, s2;
  Vec3 n = Vec3::Zero();  // the surface's normal there (either sign, any length; zero at a pole)
};

// The closest point of a cylinder (the planar builders' faces) and its derivative along a.
OnSurface on_cylinder(const Cylinder& c, const Point3& q, const Vec3& a1, const Vec3& a2) {
  const Vec3 ax = c.axis();
  const Vec3 d = q - c.origin();
  const Vec3 perp = d - d.dot(ax) * ax;
  const double rho = perp.norm();
  const Vec3 e = perp / rho;
  auto along = [&](const Vec3& a) {
    const Vec3 ap = a - a.dot(ax) * ax;
    return Vec3(a.dot(ax) * ax + c.radius() / rho * (ap - e.dot(ap) * e));
  };
  return {c.origin() + d.dot(ax) * ax + c.radius() * e, along(a1), along(a2), e};
}

// The map from triangle t's points to its surface: s(b) at barycentric b (see the header).
struct Patch {
  Point3 q0;
  Vec3 a1, a2;
  const Cylinder* cyl = nullptr;
  const Surface* S = nullptr;
  std::array<Vec2, 3> uv;
  unsigned poles = 0;
  int pole = -1, free = -1;

  // False where the triangle has no map: a plane, or a parametric face without finite corner
  // parameters, or all three corners on a pole. `known`: the pole corners as code() gave them
  // (the cut edges' pass reuses the caps' finding: each test evaluates the surface three times).
  bool make(const Mesh& mesh, std::size_t t, const FaceSurface& fs, const CornerUvs& corner_uv, int known = -1) {
    const auto& T = mesh.triangles[t];
    q0 = mesh.positions[T[0]];
    a1 = mesh.positions[T[1]] - q0, a2 = mesh.positions[T[2]] - q0;
    cyl = fs.cylinder();
    if (cyl) return true;
    if (!fs.parametric || !fs.surface || corner_uv.size() <= t) return false;
    S = fs.surface.get();
    uv = corner_uv[t];
    for (const Vec2& p : uv)
      if (!p.allFinite()) return false;
    // A corner on a pole (a cone's apex, a sphere's pole: Su or Sv zero there) stands for the
    // whole collapsed row, as in the tessellator: at barycentric b its free parameter is the other
    // corners' mean weighted by b, so the edge from it to a corner follows that corner's generator
    // line, the same line for both triangles on the edge (a fixed parameter per triangle made
    // neighbours' walls differ: a first-order error along a cone's apex fan). Two corners on the
    // pole (a piece between the poles of two operands 1e-13 apart and a corner below them) leave
    // the third's generator line: the patch is that line, not a lune.
    if (known >= 0) poles = static_cast<unsigned>(known) & 7u, free = known >> 3 & 1;
    else poles = pole_corners(*S, uv, free);
    if (poles == 7u) return false;
    for (int k = 0; k < 3 && pole < 0; ++k)
      if (poles >> k & 1u) pole = k;
    return true;
  }

  // What make() found, for make()'s `known`.
  std::uint8_t code() const { return static_cast<std::uint8_t>(poles | (free == 1 ? 8u : 0u)); }

  OnSurface at(double b1, double b2) const {
    const Point3 q = q0 + b1 * a1 + b2 * a2;
    if (cyl) return on_cylinder(*cyl, q, a1, a2);
    Vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    Vec2 p = uv[0] + b1 * d1 + b2 * d2;
    if (pole >= 0) {
      // p[free] = N / D, N = sum over the corners off the pole of b_j x_j, D = sum of their b_j.
      const double b[3] = {1 - b1 - b2, b1, b2};
      const double db1[3] = {-1, 1, 0}, db2[3] = {-1, 0, 1};
      double N = 0, D = 0, N1 = 0, D1 = 0, N2 = 0, D2 = 0;
      for (int j = 0; j < 3; ++j) {
        if (poles >> j & 1u) continue;
        const double x = uv[static_cast<std::size_t>(j)][free];
        N += b[j] * x, D += b[j];
        N1 += db1[j] * x, D1 += db1[j];
        N2 += db2[j] * x, D2 += db2[j];
      }
      p[free] = N / D;
      d1[free] = (N1 * D - N * D1) / (D * D);
      d2[free] = (N2 * D - N * D2) / (D * D);
    }
    Vec3 J[3];
    S->jet(p.x(), p.y(), 1, J);
    return {J[0], d1.x() * J[1] + d1.y() * J[2], d2.x() * J[1] + d2.y() * J[2], J[1].cross(J[2])};
  }
};

// The cap of triangle t into `out`; false (nothing added) when its surface points are not near it.
// `code`: the patch's Patch::code().
// `area`: the cap's surface area less the triangle's.
bool cap(const Mesh& mesh, std::size_t t, const FaceSurface& fs, const CornerUvs& corner_uv, double far, const Point3& ref,
         Sums& out, std::uint8_t& code, double& area) {
  Patch patch;
  if (!patch.make(mesh, t, fs, corner_uv)) return false;
  code = patch.code();
  const Vec3 &a1 = patch.a1, &a2 = patch.a2;
  const Vec3 normal = a1.cross(a2).normalized();
  const double side = std::max({a1.norm(), a2.norm(), (a2 - a1).norm()});
  // The rule: Dunavant's; on a triangle with a pole corner, whose parameters are a ratio that is
  // not smooth at the pole (a polynomial rule on it left a first-order error along a cone's apex
  // fan), 3 x 3 Gauss points in the collapsed square: t from the pole to the opposite side, s
  // along it, b = (1 - t at the pole, t s, t (1 - s)), area element t.
  std::vector<TriPoint> rule(kTri.begin(), kTri.end());
  if (patch.pole >= 0) {
    rule.clear();
    const int pole = patch.pole, j = (pole + 1) % 3, l = (pole + 2) % 3;
    for (std::size_t a = 0; a < kL.size(); ++a)
      for (std::size_t c = 0; c < kL.size(); ++c) {
        const double t = kL[a], sv = kL[c];
        double b[3];
        b[pole] = 1 - t, b[j] = t * sv, b[l] = t * (1 - sv);
        rule.push_back({b[1], b[2], 2 * kLw[a] * kLw[c] * t});  // weights of kTri's kind: sum 1
      }
  }
  Sums local;
  for (const TriPoint& tp : rule) {
    const Point3 q = patch.q0 + tp.b1 * a1 + tp.b2 * a2;
    const OnSurface os = patch.at(tp.b1, tp.b2);
    const Vec3 w = os.s - q;
    // Off the triangle's plane by about the tolerance; along it the surface point may lie a
    // fraction of a side away (interpolated parameters on a ruled face: a cone's long triangles
    // reach from one parameter to another and its generator lines twist), but not a turn away
    // (parameters across a seam).
    if (!(std::abs(w.dot(normal)) <= far && w.norm() <= far + side)) return false;
    const Vec3 c1 = os.s1 - a1, c2 = os.s2 - a2;
    const double wt = tp.w / 2;  // the reference triangle's area is 1/2
    for (std::size_t j = 0; j < kL.size(); ++j) {
      const double l = kL[j];
      const double jac = (a1 + l * c1).cross(a2 + l * c2).dot(w);
      const Vec3 x = q + l * w - ref;
      const double dv = wt * kLw[j] * jac;
      local.volume += dv;
      local.first += dv * x;
      local.second += dv * x * x.transpose();
    }
    // The surface's area element in place of the flat triangle's, signed as the volume's is: where
    // the map folds a piece over (its image turned against the triangle), the two layers cancel.
    const Vec3 element = os.s1.cross(os.s2);
    local.area += element.dot(normal) < 0 ? -wt * element.norm() : wt * element.norm();
  }
  local.area -= 0.5 * a1.cross(a2).norm();
  out.add(local);
  area = local.area;
  return true;
}

// Where two faces meet at a mesh edge E (a cut a boolean made, or an edge between two faces of a
// leaf), each side's cap ends in a wall: the segments from E's points e to that side's surface
// points s_A(e), s_B(e). The solid's boundary there is the two surfaces meeting at their common
// curve C, so the caps leave out (or count twice) the region bounded by e, s_A, C and s_B: its
// section is about the tolerance squared (tangentially the two maps may differ by the tolerance),
// and along the cut curves of a boolean of two balls it was the volume's largest error (3e-5 at
// tolerance 1e-2). It is added here, per edge, as the quadrilateral (e, s_A, C, s_B) swept along
// E, with C the point nearest e on the line where the tangent planes at s_A and s_B meet: the
// surfaces depart from those planes by the curvature times the tolerance squared, so what is left
// is third order. Where the tangent planes meet far from e (surfaces crossing at a grazing angle,
// or one surface twice), C is taken halfway between s_A and s_B: the region is then the triangle
// (e, s_A, s_B). A side without a cap (a plane) has s = e and its triangle's plane.
struct CutSide {
  Patch patch;
  bool curved = false;  // has a cap (else flat: s = e)
  // The side's outward unit normal where its surface gives one: a plane's, else (when `curved`)
  // the surface's own normal turned outward by the face's `reversed`; the triangle's normal only
  // where neither does. A sliver triangle's own normal (two corners a rounding apart, as a cut
  // leaves beside a vertex it nearly meets) points anywhere, and so did the tangent planes'
  // line through it: a sphere cut by a plane through its centre gained 6.5e-7 on one such edge.
  Vec3 normal;
  bool reversed = false;
  int at1 = 0, at2 = 0;  // the triangle's corners at the edge's first and second end
};

// Adds the edge's terms to `out`; `area_a`, `area_b`: the strips' areas on A's and on B's side.
void cut_edge(const CutSide& A, const CutSide& B, const Point3& v1, const Point3& v2, double far, const Point3& ref, Sums& out,
              double& area_a, double& area_b) {
  const Vec3 d = v2 - v1;  // v1 -> v2: the edge as A's triangle runs it
  // The quadrilateral's vector area along d at edge parameter l, with the point, and the strips'
  // widths on each side (below); 0 where a wall is longer than `far` or a side has no normal.
  auto term = [&](double l, Point3& e, double& strip_a, double& strip_b) {
    e = v1 + l * d;
    auto on = [&](const CutSide& S, Point3& s, Vec3& n) {
      s = e, n = S.normal;
      if (!S.curved) return;
      double b[3] = {0, 0, 0};
      b[S.at1] = 1 - l, b[S.at2] = l;
      const OnSurface os = S.patch.at(b[1], b[2]);
      s = os.s;
      // The surface's own normal, turned outward by the face's `reversed` (Su x Sv, or a
      // cylinder's radial direction, is outward where the face is not reversed): the map's
      // s1 x s2 on a sliver piece (its sides nearly parallel) points anywhere, and so did the
      // strips' widths across it (two balls 0.5 apart: 6e-7 of the area at 1e-4).
      if (os.n.norm() > 0) n = S.reversed ? Vec3(-os.n.normalized()) : Vec3(os.n.normalized());
      else if (const Vec3 m = os.s1.cross(os.s2); m.norm() > 0) n = m.normalized();
    };
    Point3 sa, sb;
    Vec3 na, nb;
    on(A, sa, na);
    on(B, sb, nb);
    strip_a = strip_b = 0;
    const double wall = std::max((sa - e).norm(), (sb - e).norm());
    if (!(wall > 0) || !(wall <= far)) return 0.0;
    // C = e + alpha na + beta nb on both tangent planes: na.(C - sa) = 0, nb.(C - sb) = 0.
    Point3 c = sa + 0.5 * (sb - sa);
    const double cos_ab = na.dot(nb), det = 1 - cos_ab * cos_ab;
    if (det > 1e-12) {
      const double ra = na.dot(sa - e), rb = nb.dot(sb - e);
      const double alpha = (ra - cos_ab * rb) / det, beta = (rb - cos_ab * ra) / det;
      const Point3 meet = e + alpha * na + beta * nb;
      if ((meet - e).norm() <= 4 * wall) c = meet;
    }
    // The surfaces' area the caps leave out (or count twice) along the edge: from each cap's end
    // (sa, sb) to the faces' common curve (c), across the edge and away from that side's
    // triangle (d x na for A, whose triangle runs the edge along d; -d x nb for B), in the tangent
    // planes: a strip of the tolerance's width (a cylinder's cap disc beyond its chords), whose
    // error is of second order.
    const Vec3 ma = d.cross(na), mb = nb.cross(d);
    const double wa = ma.norm() > 0 ? (c - sa).dot(ma.normalized()) : 0.0, wb = mb.norm() > 0 ? (c - sb).dot(mb.normalized()) : 0.0;
    if (std::isfinite(wa) && std::isfinite(wb)) strip_a = wa, strip_b = wb;
    // The quadrilateral (e, sa, c, sb): vector area (c - e) x (sb - sa) / 2, swept along d.
    const double a = 0.5 * (c - e).cross(sb - sa).dot(d);
    return std::isfinite(a) ? a : 0.0;  // not finite: a side's triangle without area
  };
  auto add = [&](double dv, const Point3& e) {
    const Vec3 x = e - ref;
    out.volume += dv;
    out.first += dv * x;
    out.second += dv * x * x.transpose();
  };
  const double length = d.norm();
  area_a = area_b = 0;
  for (std::size_t j = 0; j < kL.size(); ++j) {
    Point3 e;
    double strip_a = 0, strip_b = 0;
    const double a = term(kL[j], e, strip_a, strip_b);
    add(kLw[j] * a, e);
    area_a += kLw[j] * strip_a * length;
    area_b += kLw[j] * strip_b * length;
  }
  out.area += area_a + area_b;
}

// The edges between two faces (one of them curved) and their cut_edge terms, summed in edge order;
// each side's strip also added to its triangle's entry of `triangle_area` where given.
Sums cut_edges(const Mesh& mesh, const std::vector<FaceSurface>& surfaces, const CornerUvs& corner_uv,
               const std::vector<char>& capped, const std::vector<std::uint8_t>& codes, double far, const Point3& ref,
               std::vector<double>* triangle_area) {
  const std::size_t n = mesh.triangles.size();
  auto face = [&](std::size_t t) { return t < mesh.face_ids.size() ? mesh.face_ids[t] : -1; };
  // Vertices where two faces meet; only edges between two of them can be such an edge.
  constexpr std::int32_t kUnseen = std::numeric_limits<std::int32_t>::min();
  std::vector<std::int32_t> first(mesh.positions.size(), kUnseen);
  std::vector<char> mixed(mesh.positions.size(), 0);
  bool any_cap = false;
  for (std::size_t t = 0; t < n; ++t) {
    any_cap = any_cap || capped[t];
    for (const std::uint32_t v : mesh.triangles[t]) {
      if (first[v] == kUnseen) first[v] = face(t);
      else if (first[v] != face(t)) mixed[v] = 1;
    }
  }
  Sums total;
  if (!any_cap) return total;
  struct HalfEdge {
    std::uint32_t lo, hi;
    std::uint32_t t;
    int k;  // the edge from corner k to corner k + 1
  };
  // Bucketed by their lower vertex (a counting sort), then each small bucket sorted by the other.
  std::vector<std::uint32_t> start(mesh.positions.size() + 1, 0);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.triangles[t][static_cast<std::size_t>(k)], b = mesh.triangles[t][static_cast<std::size_t>((k + 1) % 3)];
      if (mixed[a] && mixed[b]) ++start[std::min(a, b) + 1];
    }
  for (std::size_t v = 0; v + 1 < start.size(); ++v) start[v + 1] += start[v];
  std::vector<HalfEdge> half(start.back());
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < n; ++t)
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = mesh.triangles[t][static_cast<std::size_t>(k)], b = mesh.triangles[t][static_cast<std::size_t>((k + 1) % 3)];
        if (mixed[a] && mixed[b]) half[fill[std::min(a, b)]++] = {std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(t), k};
      }
  }
  for (std::size_t v = 0; v + 1 < start.size(); ++v)
    if (start[v + 1] - start[v] > 1)
      std::sort(half.begin() + start[v], half.begin() + start[v + 1],
                [](const HalfEdge& x, const HalfEdge& y) { return x.hi != y.hi ? x.hi < y.hi : x.t < y.t; });
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // indices into half: a cut edge's two sides
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i;
    while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) ++j;
    // Two sides of different faces, one of them capped; an edge of touching shells (four sides)
    // is left alone.
    if (j == i + 2 && face(half[i].t) != face(half[i + 1].t) && (capped[half[i].t] || capped[half[i + 1].t]))
      pairs.push_back({i, i + 1});
    i = j;
  }
  auto side = [&](const HalfEdge& h, std::uint32_t v1, CutSide& S) {
    const auto& T = mesh.triangles[h.t];
    const Point3 &q0 = mesh.positions[T[0]], &q1 = mesh.positions[T[1]], &q2 = mesh.positions[T[2]];
    const std::int32_t f = face(h.t);
    const FaceSurface* fs = f >= 0 && static_cast<std::size_t>(f) < surfaces.size() ? &surfaces[static_cast<std::size_t>(f)] : nullptr;
    const Plane* plane = fs ? fs->plane() : nullptr;
    S.normal = plane ? plane->unit_normal() : Vec3((q1 - q0).cross(q2 - q0).normalized());
    S.reversed = fs && fs->reversed;
    const int a = h.k, b = (h.k + 1) % 3;
    S.at1 = T[static_cast<std::size_t>(a)] == v1 ? a : b;
    S.at2 = S.at1 == a ? b : a;
    S.curved = capped[h.t] && S.patch.make(mesh, h.t, surfaces[static_cast<std::size_t>(face(h.t))], corner_uv, codes[h.t]);
  };
  const std::size_t block = 1024, blocks = (pairs.size() + block - 1) / block;
  std::vector<Sums> part(blocks);
  std::vector<std::array<double, 2>> strips(triangle_area ? pairs.size() : 0);
  parallel_for(0, blocks, [&](std::size_t bi) {
    for (std::size_t i = bi * block; i < std::min(pairs.size(), (bi + 1) * block); ++i) {
      const HalfEdge &h = half[pairs[i].first], &g = half[pairs[i].second];
      // The edge as h's triangle runs it: v1 -> v2.
      const std::uint32_t v1 = mesh.triangles[h.t][static_cast<std::size_t>(h.k)];
      const std::uint32_t v2 = mesh.triangles[h.t][static_cast<std::size_t>((h.k + 1) % 3)];
      CutSide A, B;
      side(h, v1, A);
      side(g, v1, B);
      double area_a = 0, area_b = 0;
      cut_edge(A, B, mesh.positions[v1], mesh.positions[v2], far, ref, part[bi], area_a, area_b);
      if (triangle_area) strips[i] = {area_a, area_b};
    }
  });
  for (const Sums& p : part) total.add(p);
  // In edge order: the same bits at any number of threads.
  for (std::size_t i = 0; i < strips.size(); ++i) {
    (*triangle_area)[half[pairs[i].first].t] += strips[i][0];
    (*triangle_area)[half[pairs[i].second].t] += strips[i][1];
  }
  return total;
}

}  // namespace

MassProperties curved_mass_properties(const Mesh& mesh, const std::vector<FaceSurface>& surfaces, const CornerUvs& corner_uv,
                                      double chordal, std::vector<double>* triangle_area) {
  MassProperties mp;
  if (triangle_area) triangle_area->assign(mesh.triangles.size(), 0.0);
  if (mesh.triangles.empty()) return mp;
  const Point3 ref = mesh.bounds().center();
  const double far = 16 * chordal + 1e-12 * mesh.bounds().diagonal();
  // Blocks summed in order: the same bits at any number of threads.
  const std::size_t n = mesh.triangles.size(), block = 4096, blocks = (n + block - 1) / block;
  std::vector<Sums> part(blocks);
  std::vector<char> capped(n, 0);
  std::vector<std::uint8_t> codes(n, 0);
  parallel_for(0, blocks, [&](std::size_t b) {
    Sums& s = part[b];
    for (std::size_t t = b * block; t < std::min(n, (b + 1) * block); ++t) {
      const auto& T = mesh.triangles[t];
      const Vec3 a = mesh.positions[T[0]] - ref, p = mesh.positions[T[1]] - ref, c = mesh.positions[T[2]] - ref;
      // The flat tetrahedron (ref, a, p, c) (as kernel/mesh.cpp's mass_properties).
      const double v = a.dot(p.cross(c)) / 6.0;
      const Vec3 sum = a + p + c;
      s.volume += v;
      const double flat = 0.5 * (p - a).cross(c - a).norm();
      s.area += flat;
      if (triangle_area) (*triangle_area)[t] = flat;
      s.first += v * sum / 4.0;
      s.second += v / 20.0 * (a * a.transpose() + p * p.transpose() + c * c.transpose() + sum * sum.transpose());
      const std::int32_t id = t < mesh.face_ids.size() ? mesh.face_ids[t] : -1;
      if (id < 0 || static_cast<std::size_t>(id) >= surfaces.size()) continue;
      const FaceSurface& fs = surfaces[static_cast<std::size_t>(id)];
      if (fs.plane() || !fs.surface) continue;
      double capped_area = 0;
      capped[t] = cap(mesh, t, fs, corner_uv, far, ref, s, codes[t], capped_area);
      if (triangle_area) (*triangle_area)[t] += capped_area;
    }
  });
  Sums total;
  for (const Sums& s : part) total.add(s);
  total.add(cut_edges(mesh, surfaces, corner_uv, capped, codes, far, ref, triangle_area));
  mp.volume = total.volume;
  mp.area = total.area;
  if (total.volume == 0) return mp;
  const Vec3 cl = total.first / total.volume;
  mp.centroid = ref + cl;
  const Mat3 cov = total.second - total.volume * cl * cl.transpose();
  mp.inertia = cov.trace() * Mat3::Identity() - cov;
  return mp;
}

}  // namespace wedge
