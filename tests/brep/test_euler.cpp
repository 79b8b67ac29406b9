#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <unordered_map>
#include <random>

#include "brep_helpers.h"

using namespace wedge;
using wedge::test::face_facing;
using wedge::test::first_vertex;
using wedge::test::signature;

namespace {
struct State {
  EulerCounts counts;
  bool ok;
  std::string message, sig;
};
State state(const Model& m, bool geometry = true) {
  Validation v = m.validate(geometry);
  return {m.counts(), v.ok, v.message, signature(m)};
}
void require_same(const State& a, const State& b) {
  CHECK(a.counts == b.counts);
  CHECK(a.ok == b.ok);
  CHECK(a.message == b.message);
  CHECK(a.sig == b.sig);
}
}  // namespace

TEST_CASE("a box built by Euler operators has 8/12/6 and is valid", "[brep]") {
  Model m = box(Vec3(2, 3, 4));
  CHECK(m.counts() == EulerCounts{8, 12, 6, 0, 0, 1});
  CHECK(m.counts().characteristic() == 0);
  Validation v = m.validate();
  INFO(v.message);
  CHECK(v.ok);
}

TEST_CASE("mvfs and kvfs are inverses", "[brep][euler]") {
  Model m = box(Vec3(1, 1, 1));
  State before = state(m);
  auto r = m.mvfs(Point3(5, 5, 5));
  CHECK(m.counts() - before.counts == EulerCounts{1, 0, 1, 0, 0, 1});
  CHECK(m.validate(false).ok);
  m.kvfs(r.v);
  require_same(before, state(m));
}

TEST_CASE("mev and kev are inverses", "[brep][euler]") {
  Model m = box(Vec3(1, 1, 1));
  FaceId top = face_facing(m, Vec3::UnitZ());
  State before = state(m);
  auto r = m.mev(top, first_vertex(m, top), Point3(0.5, 0.5, 1));
  CHECK(m.counts() - before.counts == EulerCounts{1, 1, 0, 0, 0, 0});
  CHECK(m.counts().characteristic() == 0);
  CHECK(m.validate(false).ok);
  m.kev(r.e, r.v);
  require_same(before, state(m));
}

TEST_CASE("mef and kef are inverses, and a diagonal split keeps the box valid", "[brep][euler]") {
  Model m = box(Vec3(1, 1, 1));
  FaceId top = face_facing(m, Vec3::UnitZ());
  State before = state(m);
  auto vs = m.loop_vertices(m.faces()[top].outer);
  auto r = m.mef(top, vs[0], vs[2]);
  CHECK(m.counts() - before.counts == EulerCounts{0, 1, 1, 0, 0, 0});
  Validation v = m.validate();
  INFO(v.message);
  CHECK(v.ok);
  CHECK(m.mass_properties().volume == Approx(1.0));
  m.kef(r.e, r.f);
  require_same(before, state(m));
}

TEST_CASE("kemr and mekr are inverses", "[brep][euler]") {
  Model m = box(Vec3(1, 1, 1));
  FaceId top = face_facing(m, Vec3::UnitZ());
  auto strut = m.mev(top, first_vertex(m, top), Point3(0.3, 0.3, 1));
  auto a = m.mev(top, strut.v, Point3(0.6, 0.3, 1));
  auto b = m.mev(top, a.v, Point3(0.5, 0.6, 1));
  m.mef(top, b.v, strut.v);
  top = m.loops()[m.edges()[strut.e].side[0].loop].face;  // the face that kept the strut
  State before = state(m, false);
  LoopId ring = m.kemr(strut.e);
  CHECK(m.counts() - before.counts == EulerCounts{0, -1, 0, 1, 0, 0});
  CHECK(std::find(m.faces()[top].rings.begin(), m.faces()[top].rings.end(), ring) != m.faces()[top].rings.end());
  CHECK(m.validate(false).ok);
  m.mekr(first_vertex(m, top), strut.v);
  require_same(before, state(m, false));
}

TEST_CASE("kfmrh and mfkrh are inverses, within a shell (H) and across shells (S)", "[brep][euler]") {
  SECTION("a hole") {
    Model m = prism({{{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {{{1, 1}, {2, 1}, {2, 2}, {1, 2}}}}, 1);
    CHECK(m.counts() == EulerCounts{16, 24, 10, 2, 1, 1});
    FaceId bottom = face_facing(m, -Vec3::UnitZ());
    REQUIRE(m.faces()[bottom].rings.size() == 1);
    State before = state(m);
    LoopId ring = m.faces()[bottom].rings[0];
    FaceId f = m.mfkrh(bottom, ring);
    CHECK(m.counts() - before.counts == EulerCounts{0, 0, 1, -1, -1, 0});
    CHECK(m.validate(false).ok);
    m.kfmrh(f, bottom);
    require_same(before, state(m));
  }
  SECTION("two shells") {
    Model m;
    auto a = m.mvfs(Point3(0, 0, 0));
    auto b = m.mvfs(Point3(1, 0, 0));
    m.mev(a.f, a.v, Point3(0, 1, 0));
    State before = state(m, false);
    LoopId ring = m.kfmrh(b.f, a.f);
    CHECK(m.counts() - before.counts == EulerCounts{0, 0, -1, 1, 0, -1});
    CHECK(m.validate(false).ok);
    m.mfkrh(a.f, ring);
    require_same(before, state(m, false));
  }
}

TEST_CASE("semv and jekv are inverses", "[brep][euler]") {
  Model m = box(Vec3(1, 1, 1));
  State before = state(m);
  EdgeId e = m.edges().ids()[3];
  Point3 mid = 0.5 * (m.point(m.edges()[e].v[0]) + m.point(m.edges()[e].v[1]));
  auto r = m.semv(e, mid);
  CHECK(m.counts() - before.counts == EulerCounts{1, 1, 0, 0, 0, 0});
  CHECK(m.validate().ok);
  m.jekv(r.e, r.v);
  require_same(before, state(m));
}

TEST_CASE("semv cuts an arc edge into two arcs of its circle and jekv joins them back", "[brep][euler]") {
  Model m = worked_example();
  State before = state(m);
  EdgeId e;
  for (EdgeId x : m.edges().ids())
    if (dynamic_cast<const CircularArc*>(m.curve(x).get())) e = x;
  REQUIRE(e.valid());
  const auto& arc = dynamic_cast<const CircularArc&>(*m.curve(e));
  const Point3 c = arc.center();
  const double r = arc.radius();
  std::vector<Point3> along;
  for (int i = 0; i <= 8; ++i) along.push_back(m.edge_point(e, i / 8.0));
  const Point3 mid = m.edge_point(e, 0.5);
  CHECK_THROWS_WITH(m.semv(e, Point3(mid + 0.1 * (mid - c))), Catch::Contains("not inside edge"));
  auto sv = m.semv(e, mid);
  CHECK(m.counts() - before.counts == EulerCounts{1, 1, 0, 0, 0, 0});
  CHECK(m.validate().ok);
  for (EdgeId half : {e, sv.e}) {
    auto* h = dynamic_cast<const CircularArc*>(m.curve(half).get());
    REQUIRE(h);
    CHECK((h->center() - c).norm() < 1e-12);
    CHECK(h->radius() == Approx(r).epsilon(1e-12));
    for (int i = 0; i <= 4; ++i) CHECK((m.edge_point(half, i / 4.0) - c).norm() == Approx(r).epsilon(1e-12));
  }
  CHECK((m.edge_point(e, 1) - mid).norm() < 1e-12);
  CHECK((m.edge_point(sv.e, 0) - mid).norm() < 1e-12);
  m.jekv(sv.e, sv.v);
  require_same(before, state(m));
  for (int i = 0; i <= 8; ++i) CHECK((m.edge_point(e, i / 8.0) - along[static_cast<std::size_t>(i)]).norm() < 1e-12);
}

TEST_CASE("jekv refuses to join the two edges of a two-edge loop", "[brep][euler]") {
  // Two edges between the same two vertices (a lamina split by mef): joining them at v1 would
  // leave an edge from v0 to itself.
  Model m;
  auto a = m.mvfs(Point3(0, 0, 0));
  auto b = m.mev(a.f, a.v, Point3(1, 0, 0));
  auto c = m.mef(a.f, a.v, b.v);
  REQUIRE(m.validate(false).ok);
  State before = state(m, false);
  CHECK_THROWS_WITH(m.jekv(c.e, b.v), Catch::Contains("join the same two vertices"));
  require_same(before, state(m, false));
}

TEST_CASE("an operator whose precondition fails says which and leaves the model as it was", "[brep][euler]") {
  Model m = box(Vec3(1, 1, 1));
  FaceId top = face_facing(m, Vec3::UnitZ());
  FaceId bottom = face_facing(m, -Vec3::UnitZ());
  State before = state(m);
  VertexId vt = first_vertex(m, top), vb = first_vertex(m, bottom);
  EdgeId e = m.edges().ids()[0];
  CHECK_THROWS_WITH(m.kev(e, m.edges()[e].v[0]), Catch::Contains("is not the only edge at vertex"));
  CHECK_THROWS_WITH(m.mev(top, vb, Point3(0, 0, 0)), Catch::Contains("is not on face"));
  CHECK_THROWS_WITH(m.mef(top, vt, vt), Catch::Contains("must differ"));
  CHECK_THROWS_WITH(m.mef(top, vt, vb), Catch::Contains("do not lie on one loop"));
  CHECK_THROWS_WITH(m.kemr(e), Catch::Contains("different loops on its two sides"));
  CHECK_THROWS_WITH(m.kef(e, FaceId(999)), Catch::Contains("is not a face"));
  FaceId fa = m.loops()[m.edges()[e].side[0].loop].face, fb = m.loops()[m.edges()[e].side[1].loop].face;
  FaceId away;
  for (FaceId f : m.faces().ids())
    if (f != fa && f != fb) away = f;
  CHECK_THROWS_WITH(m.kef(e, away), Catch::Contains("on neither side"));
  CHECK_THROWS_WITH(m.mekr(vt, vb), Catch::Contains("do not lie on two loops of one face"));
  CHECK_THROWS_WITH(m.kfmrh(top, top), Catch::Contains("must differ"));
  CHECK_THROWS_WITH(m.mfkrh(top, m.faces()[bottom].outer), Catch::Contains("is not a ring of face"));
  CHECK_THROWS_WITH(m.kvfs(vt), Catch::Contains("has edges"));
  CHECK_THROWS_WITH(m.jekv(e, m.edges()[e].v[0]), Catch::Contains("does not have exactly two edges"));
  CHECK_THROWS_WITH(m.mev(top, vt, Point3(0, 0, std::nan(""))), Catch::Contains("not finite"));
  require_same(before, state(m));
}

TEST_CASE("the seed's worked example: 44/66/27/5/1/1 with each feature's own row", "[brep][example]") {
  std::vector<FeatureRow> rows;
  Model m = worked_example(&rows);
  REQUIRE(rows.size() == 5);
  CHECK(rows[0].name == "Basic shape");
  CHECK(rows[0].counts == EulerCounts{8, 12, 6, 0, 0, 1});
  CHECK(rows[1].name == "Protrusion");
  CHECK(rows[1].counts == EulerCounts{8, 12, 5, 1, 0, 0});
  CHECK(rows[2].counts == EulerCounts{8, 12, 5, 1, 0, 0});
  CHECK(rows[3].counts == EulerCounts{16, 24, 9, 1, 0, 0});
  CHECK(rows[4].counts == EulerCounts{4, 6, 2, 2, 1, 0});
  CHECK(m.counts() == EulerCounts{44, 66, 27, 5, 1, 1});
  CHECK(m.counts().characteristic() == 0);
  Validation v = m.validate();
  INFO(v.message);
  CHECK(v.ok);
  // Four quarter cylinders and two half cylinders.
  int cylinders = 0;
  m.faces().for_each([&](FaceId f, const BrepFace&) { cylinders += m.surface(f).cylinder() != nullptr; });
  CHECK(cylinders == 6);
  // Block 320 + protrusion 8 - sharp pocket 4 - round pocket (10 - (4 - pi) r^2) - hole 4 pi.
  double expected = 320 + 8 - 4 - (4 * 2.5 - (4 - kPi) * 0.25) - 4 * kPi;
  CHECK(m.approximate_volume() == Approx(expected).epsilon(2e-3));
}

TEST_CASE("a block with two through holes has H = 2", "[brep]") {
  Model m = prism({{{0, 0}, {6, 0}, {6, 3}, {0, 3}}, {{{1, 1}, {2, 1}, {2, 2}, {1, 2}}, {{4, 1}, {5, 1}, {5, 2}, {4, 2}}}}, 2);
  CHECK(m.counts() == EulerCounts{24, 36, 14, 4, 2, 1});
  Validation v = m.validate();
  INFO(v.message);
  CHECK(v.ok);
  CHECK(m.mass_properties().volume == Approx((18 - 2) * 2.0));
}

TEST_CASE("two disjoint boxes are two shells", "[brep]") {
  std::vector<Point3> pts;
  std::vector<std::vector<int>> faces;
  for (int k = 0; k < 2; ++k) {
    int b = static_cast<int>(pts.size());
    for (int i = 0; i < 8; ++i) pts.emplace_back((i & 1) + 3 * k, (i >> 1) & 1, (i >> 2) & 1);
    std::vector<std::vector<int>> f = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (auto& q : f) {
      for (int& i : q) i += b;
      faces.push_back(q);
    }
  }
  Model m = polyhedron(pts, faces);
  CHECK(m.counts() == EulerCounts{16, 24, 12, 0, 0, 2});
  CHECK(m.validate().ok);
  CHECK(m.mass_properties().volume == Approx(2.0));
}

namespace wedge {
// Direct access past the Euler operators, to break a model on purpose (a friend of Model).
struct ModelCorruptor {
  static BrepEdge& edge(Model& m, EdgeId e) { return m.edges_[e]; }
  static EdgeId add_edge(Model& m, BrepEdge e) {
    EdgeId id = m.edges_.add(e);
    m.curves_[id] = nullptr;
    return id;
  }
};
}  // namespace wedge

TEST_CASE("validate() catches a broken wing, an open loop and a dangling edge", "[brep][validate]") {
  SECTION("broken wing") {
    Model m = box(Vec3(1, 1, 1));
    EdgeId e = m.edges().ids()[0];
    EdgeId other = m.edges().ids()[5];
    ModelCorruptor::edge(m, e).side[0].next = EdgeSide{other, 0};
    Validation v = m.validate();
    CHECK_FALSE(v.ok);
    CHECK_THAT(v.message, Catch::StartsWith("broken wing: the successor of edge 0 side 0"));
  }
  SECTION("open loop") {
    Model m = box(Vec3(1, 1, 1));
    EdgeId e = m.edges().ids()[2];
    LoopId l = m.edges()[e].side[1].loop;
    ModelCorruptor::edge(m, e).side[1].next = EdgeSide();
    Validation v = m.validate();
    CHECK_FALSE(v.ok);
    CHECK(v.message == "loop " + std::to_string(l.value) + " is not closed: edge 2 side 1 has no successor");
  }
  SECTION("dangling edge") {
    Model m = box(Vec3(1, 1, 1));
    FaceId top = face_facing(m, Vec3::UnitZ());
    BrepEdge d;
    auto vs = m.loop_vertices(m.faces()[top].outer);
    d.v[0] = vs[0];
    d.v[1] = vs[2];
    EdgeId id = ModelCorruptor::add_edge(m, d);
    // Its sides point at each other and claim the top face's loop, which never reaches them.
    BrepEdge& de = ModelCorruptor::edge(m, id);
    for (int k = 0; k < 2; ++k) {
      de.side[k].loop = m.faces()[top].outer;
      de.side[k].next = de.side[k].prev = EdgeSide{id, 1 - k};
    }
    Validation v = m.validate();
    CHECK_FALSE(v.ok);
    CHECK_THAT(v.message, Catch::StartsWith("edge " + std::to_string(id.value) + " is dangling"));
  }
}

namespace {
// Ids killed by a forward operator and re-created by an undo get new ids: the undo steps look
// every captured id up here.
struct Remap {
  std::unordered_map<std::int32_t, std::int32_t> v, e, l, f;
  template <class IdT>
  static IdT get(const std::unordered_map<std::int32_t, std::int32_t>& m, IdT id) {
    auto it = m.find(id.value);
    return it == m.end() ? id : IdT(it->second);
  }
  VertexId operator()(VertexId x) const { return get(v, x); }
  EdgeId operator()(EdgeId x) const { return get(e, x); }
  LoopId operator()(LoopId x) const { return get(l, x); }
  FaceId operator()(FaceId x) const { return get(f, x); }
  EdgeSide operator()(EdgeSide s) const { return s.valid() ? EdgeSide{(*this)(s.edge), s.side} : s; }
  // Edge `old` lives on as `now`; `flip` when `now` runs the other way: turn it back, so that
  // the sides captured by earlier steps keep their meaning.
  void edge(Model& m, EdgeId old, EdgeId now, bool flip) {
    if (flip) m.reverse_edge(now);
    e[old.value] = now.value;
  }
  Corner operator()(Corner c) const { return {(*this)(c.loop), (*this)(c.out), c.v.valid() ? (*this)(c.v) : c.v}; }
};
}  // namespace

TEST_CASE("random legal operator sequences, all undone, restore the model exactly", "[brep][random]") {
  // Each sequence starts from a box, applies random legal operators (recording the exact
  // inverse of each, at the corners it must use), checks the structure, then undoes them all.
  std::mt19937 rng(12345);
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng)); };
  auto rnd = [&]() { return std::uniform_real_distribution<double>(-10, 10)(rng); };
  const int sequences = 2000, length = 12;
  Model base = box(Vec3(1, 1, 1));
  const std::string base_sig = signature(base);
  long applied = 0;
  std::array<long, 8> per_op{};
  for (int seq = 0; seq < sequences; ++seq) {
    Model m = base;
    using Undo = std::function<void(Model&, Remap&)>;
    std::vector<Undo> undo;
    std::vector<int> trace;
    for (int step = 0; step < length; ++step) {
      auto faces = m.faces().ids();
      auto edges = m.edges().ids();
      int op = static_cast<int>(pick(8));
      if (op == 0) {  // mev at a random corner of a random loop
        FaceId f = faces[pick(faces.size())];
        auto ls = m.faces()[f].rings;
        ls.push_back(m.faces()[f].outer);
        LoopId l = ls[pick(ls.size())];
        auto sides = m.loop_sides(l);
        Corner c = sides.empty() ? Corner{l, {}, m.loops()[l].lone} : Corner{l, sides[pick(sides.size())], {}};
        if (c.out.valid()) c.v = m.origin(c.out);
        auto r = m.mev_at(c, Point3(rnd(), rnd(), rnd()));
        undo.push_back([r](Model& x, Remap& map) { x.kev(map(r.e), map(r.v)); });
      } else if (op == 1) {  // mef between two corners of one loop at different vertices
        FaceId f = faces[pick(faces.size())];
        auto sides = m.loop_sides(m.faces()[f].outer);
        if (sides.size() < 2) continue;
        EdgeSide a = sides[pick(sides.size())], b = sides[pick(sides.size())];
        if (m.origin(a) == m.origin(b)) continue;
        auto r = m.mef_at(a, b);
        undo.push_back([r](Model& x, Remap& map) { x.kef(map(r.e), map(r.f)); });
      } else if (op == 2) {  // kemr on an edge with one loop on both sides
        std::vector<EdgeId> ok;
        for (EdgeId e : edges)
          if (m.edges()[e].side[0].loop == m.edges()[e].side[1].loop) ok.push_back(e);
        if (ok.empty()) continue;
        EdgeId e = ok[pick(ok.size())];
        const BrepEdge& ed = m.edges()[e];
        EdgeSide s0{e, 0}, s1{e, 1};
        EdgeSide n0 = m.side(s0).next, n1 = m.side(s1).next;
        VertexId v0 = ed.v[0], v1 = ed.v[1];
        LoopId l = ed.side[0].loop;
        LoopId r = m.kemr(e);
        Corner a = n1 == s0 ? Corner{l, {}, v0} : Corner{l, n1, v0};
        Corner b = n0 == s1 ? Corner{r, {}, v1} : Corner{r, n0, v1};
        undo.push_back([a, b, e](Model& x, Remap& map) { map.edge(x, e, x.mekr_at(map(a), map(b)), false); });
      } else if (op == 3) {  // kev on an edge with a dangling end
        std::vector<std::pair<EdgeId, int>> ok;
        for (EdgeId e : edges)
          for (int k = 0; k < 2; ++k)
            if (m.side({e, k}).next == EdgeSide{e, 1 - k}) ok.emplace_back(e, k);
        if (ok.empty()) continue;
        auto [e, k] = ok[pick(ok.size())];
        VertexId v = m.edges()[e].v[1 - k];  // side k ends at v
        VertexId u = m.edges()[e].v[k];
        Point3 p = m.point(v);
        EdgeSide out = m.side({e, 1 - k}).next;
        LoopId l = m.edges()[e].side[k].loop;
        bool lone = out == EdgeSide{e, k};
        m.kev(e, v);
        Corner c = lone ? Corner{l, {}, u} : Corner{l, out, u};
        undo.push_back([c, p, e = e, k = k, v](Model& x, Remap& map) {
          auto r = x.mev_at(map(c), p);
          map.edge(x, e, r.e, k == 1);  // the new edge runs from u, the old edge's v[k]
          map.v[v.value] = r.v.value;
        });
      } else if (op == 4) {  // kef where the killed face has no rings
        if (edges.empty()) continue;
        EdgeId e = edges[pick(edges.size())];
        EdgeSide a{e, static_cast<int>(pick(2))};
        LoopId la = m.side(a).loop, lb = m.side(a.mate()).loop;
        FaceId f = m.loops()[la].face;
        if (m.loops()[lb].face == f || m.faces()[f].outer != la || !m.faces()[f].rings.empty()) continue;
        EdgeSide c1 = m.side(a).next, c2 = m.side(a.mate()).next;
        FaceSurface surf = m.surface(f);
        m.kef(e, f);
        bool flip = a.side == 0;  // the new edge runs from origin(c1) = the old v[1 - a.side]
        undo.push_back([c1, c2, e, f, la, surf, flip](Model& x, Remap& map) {
          auto r = x.mef_at(map(c1), map(c2));
          map.edge(x, e, r.e, flip);
          x.set_surface(r.f, surf);  // geometry is attached, not restored by topology
          map.f[f.value] = r.f.value;
          map.l[la.value] = x.faces()[r.f].outer.value;
        });
      } else if (op == 5) {  // semv
        if (edges.empty()) continue;
        auto r = m.semv(edges[pick(edges.size())], Point3(rnd(), rnd(), rnd()));
        undo.push_back([r](Model& x, Remap& map) { x.jekv(map(r.e), map(r.v)); });
      } else if (op == 6) {  // mfkrh on a random ring
        std::vector<std::pair<FaceId, LoopId>> ok;
        for (FaceId f : faces)
          for (LoopId r : m.faces()[f].rings) ok.emplace_back(f, r);
        if (ok.empty()) continue;
        auto [f, r] = ok[pick(ok.size())];
        bool connected_possible = m.holes() > 0;
        FaceId g;
        try {
          g = m.mfkrh(f, r);
        } catch (const Error&) {
          CHECK_FALSE(connected_possible);
          continue;
        }
        undo.push_back([g, f = f](Model& x, Remap& map) { x.kfmrh(map(g), map(f)); });
      } else {  // kfmrh of a one-loop face into another face
        FaceId h = faces[pick(faces.size())], f = faces[pick(faces.size())];
        if (h == f || !m.faces()[h].rings.empty()) continue;
        FaceSurface surf = m.surface(h);
        LoopId r = m.kfmrh(h, f);
        undo.push_back([f, r, h, surf](Model& x, Remap& map) {
          FaceId g = x.mfkrh(map(f), map(r));
          x.set_surface(g, surf);
          map.f[h.value] = g.value;
        });
      }
      ++applied;
      trace.push_back(op);
      ++per_op[static_cast<std::size_t>(op)];
      REQUIRE(m.counts().characteristic() == 0);
    }
    Validation v = m.validate(false);
    INFO(v.message);
    REQUIRE(v.ok);
    Remap map;
    std::string ops;
    for (int o : trace) ops += std::to_string(o) + " ";
    INFO("sequence " << seq << " ops " << ops);
    for (auto it = undo.rbegin(); it != undo.rend(); ++it) (*it)(m, map);
    REQUIRE(m.counts() == base.counts());
    REQUIRE(signature(m) == base_sig);
    Validation after = m.validate();
    INFO(after.message);
    REQUIRE(after.ok);
  }
  CHECK(applied > 10000);
  for (long n : per_op) CHECK(n > 200);  // every operator was exercised
}

TEST_CASE("validate() finds the first crossing of a loop of thousands of corners", "[brep][validate]") {
  // A face of 3000 corners (validate swept its segments; it tested every pair, 1.4 s at 20,000),
  // simple, then with two far corners swapped: the crossing named is the first pair (i, j) of the
  // loop's segments that a test of every pair finds.
  std::vector<Point2> ring;
  for (int i = 0; i < 3000; ++i) ring.emplace_back(std::cos(2 * M_PI * i / 3000), std::sin(2 * M_PI * i / 3000));
  Model m = prism({ring, {}}, 1);
  Validation ok = m.validate();
  INFO(ok.message);
  REQUIRE(ok.ok);
  FaceId top = face_facing(m, Vec3::UnitZ());
  auto vs = m.loop_vertices(m.faces()[top].outer);
  REQUIRE(vs.size() == 3000);
  const Point3 a = m.point(vs[700]), b = m.point(vs[2100]);
  m.set_point(vs[700], b);
  m.set_point(vs[2100], a);
  std::vector<Point2> q;
  for (const Point3& p : m.loop_polyline(m.faces()[top].outer)) q.emplace_back(p.x(), p.y());
  std::string first;
  const std::size_t n = q.size();
  for (std::size_t i = 0; i < n && first.empty(); ++i)
    for (std::size_t j = i + 2; j < n && first.empty(); ++j)
      if (!(i == 0 && j == n - 1) && segments_intersect_2d(q[i], q[(i + 1) % n], q[j], q[(j + 1) % n]))
        first = "(segments " + std::to_string(i) + " and " + std::to_string(j) + ")";
  REQUIRE(!first.empty());
  const Validation v = m.validate();
  CHECK_THAT(v.message, Catch::Contains("face " + std::to_string(top.value) + "'s loop") && Catch::Contains("intersects itself " + first));
}

TEST_CASE("validate() checks the geometry of plane faces", "[brep][validate]") {
  Model m = prism({{{0, 0}, {2, 0}, {2, 2}, {0, 2}}, {}}, 1);
  FaceId top = face_facing(m, Vec3::UnitZ());
  SECTION("a loop crossing itself") {
    auto vs = m.loop_vertices(m.faces()[top].outer);
    Point3 a = m.point(vs[0]), b = m.point(vs[1]);
    m.set_point(vs[0], b);
    m.set_point(vs[1], a);
    Validation v = m.validate();
    CHECK_THAT(v.message, Catch::Contains("face " + std::to_string(top.value) + "'s loop") && Catch::Contains("intersects itself"));
  }
  SECTION("an outer loop clockwise seen from outside") {
    m.set_surface(top, plane_face(Point3(0, 0, 1), -Vec3::UnitZ()));
    CHECK_THAT(m.validate().message, Catch::EndsWith("is not counter-clockwise seen from outside"));
  }
  SECTION("a face that is not flat") {
    m.set_point(m.loop_vertices(m.faces()[top].outer)[0], Point3(0, 0, 1.5));
    CHECK_THAT(m.validate().message, Catch::Contains("is not planar"));
  }
  SECTION("a ring counter-clockwise seen from outside") {
    auto strut = m.mev(top, first_vertex(m, top), Point3(0.5, 0.5, 1));
    auto a = m.mev(top, strut.v, Point3(1.5, 0.5, 1));
    auto b = m.mev(top, a.v, Point3(1.5, 1.5, 1));  // counter-clockwise about +z: wrong for a ring
    m.mef_at(EdgeSide{b.e, 1}, EdgeSide{strut.e, 1});
    LoopId ring = m.kemr(strut.e);
    CHECK(m.validate(false).ok);
    CHECK(m.validate().message == "face " + std::to_string(top.value) + "'s inner loop " + std::to_string(ring.value) +
                                      " is not clockwise seen from outside");
  }
}
