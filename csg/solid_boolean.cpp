// A boolean node of the CSG tree evaluated (csg/solid_impl.h): its operands evaluated (in parallel),
// repeats of one mesh dropped, operands pruned by their boxes, unions grouped by overlapping boxes
// (groups apart are put side by side as shells, with no engine pass), large n-ary nodes balanced
// by the fan-in, and the engine called once per group, its result's faces numbered after the
// operands' faces. The tree's walk, its cache and the queries are solid.cpp's.
#include <algorithm>
#include <cstring>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>

#include "csg/mesh_leaf.h"
#include "csg/solid_impl.h"
#include "kernel/parallel.h"

namespace wedge::tree_detail {

namespace {

Box3 mesh_box(const Mesh& m) { return m.empty() ? Box3() : m.bounds(); }

bool boxes_apart(const Box3& a, const Box3& b) {
  if (a.empty() || b.empty()) return true;
  for (int i = 0; i < 3; ++i)
    if (a.max[i] < b.min[i] || b.max[i] < a.min[i]) return true;
  return false;
}

// True when the boxes have a point in common: when they meet pairwise (intervals on a line that
// meet pairwise share a point), found in one pass, not one per pair (a chain s = s * b is long).
bool boxes_meet(const std::vector<Box3>& boxes) {
  const double inf = std::numeric_limits<double>::infinity();
  Box3 common(Vec3::Constant(-inf), Vec3::Constant(inf));
  for (const Box3& b : boxes) {
    if (b.empty()) return false;
    common.min = common.min.cwiseMax(b.min);
    common.max = common.max.cwiseMin(b.max);
  }
  return !common.empty();
}

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
const std::array<Vec2, 3> kNoUv{Vec2(kNan, kNan), Vec2(kNan, kNan), Vec2(kNan, kNan)};

// Appends b's mesh and faces to a (face ids of b offset past a's).
void append_evaluated(Evaluated& a, const Evaluated& b) {
  const std::int32_t offset = static_cast<std::int32_t>(a.kinds.size());
  const std::size_t t0 = a.mesh.triangles.size();
  if (!a.corner_uv.empty() || !b.corner_uv.empty()) {
    a.corner_uv.resize(t0, kNoUv);
    if (b.corner_uv.empty()) a.corner_uv.resize(t0 + b.mesh.triangles.size(), kNoUv);
    else a.corner_uv.insert(a.corner_uv.end(), b.corner_uv.begin(), b.corner_uv.end());
  }
  a.mesh.append(b.mesh);
  for (std::size_t t = t0; t < a.mesh.face_ids.size(); ++t) a.mesh.face_ids[t] += offset;
  a.kinds.insert(a.kinds.end(), b.kinds.begin(), b.kinds.end());
  a.tags.insert(a.tags.end(), b.tags.begin(), b.tags.end());
  a.surfaces.insert(a.surfaces.end(), b.surfaces.begin(), b.surfaces.end());
}

// How deep the boxes lie on one another: the most of them whose middle halves (a quarter of the
// box in from each side) hold one box's centre, found by a sweep along x; the count stops above
// `enough`. Operands that only meet at their ends (a lattice's struts at a node, each node's box
// corner) are no pile: their one pass costs no more than passes would, and leaves fewer triangles.
// Boxes within a hundredth of the centre's box (its diagonal) count as that box: copies of one
// shape turned or shifted a little are one in a pile. (Their surfaces cross everywhere; passes of a
// few do not make their union cheaper, and in one pass the engine's work budget refuses them at once:
// 17 copies of a sphere turned by a degree each went past 25 s in passes of 4 before failing.)
std::size_t stack_depth(const std::vector<Box3>& box, std::size_t enough) {
  // A sweep along x: the centres in order, each against the boxes begun before it and not yet
  // ended (the others cannot hold it, nor any later centre).
  std::vector<std::size_t> by_min, by_centre;
  for (std::size_t i = 0; i < box.size(); ++i)
    if (!box[i].empty()) by_min.push_back(i);
  by_centre = by_min;
  auto centre = [&](std::size_t i) { return 0.5 * (box[i].min + box[i].max); };
  std::stable_sort(by_min.begin(), by_min.end(), [&](std::size_t a, std::size_t b) { return box[a].min.x() < box[b].min.x(); });
  std::stable_sort(by_centre.begin(), by_centre.end(), [&](std::size_t a, std::size_t b) { return centre(a).x() < centre(b).x(); });
  std::vector<std::size_t> active;
  std::size_t next = 0, deepest = 0;
  for (std::size_t i : by_centre) {
    const Vec3 c = centre(i);
    while (next < by_min.size() && box[by_min[next]].min.x() <= c.x()) active.push_back(by_min[next++]);
    const double near = 0.01 * (box[i].max - box[i].min).norm();
    std::size_t n = 1, kept = 0;
    for (std::size_t j : active) {
      if (box[j].max.x() < c.x()) continue;  // ended: dropped
      active[kept++] = j;
      if (j == i || ((box[j].min - box[i].min).cwiseAbs().maxCoeff() <= near &&
                     (box[j].max - box[i].max).cwiseAbs().maxCoeff() <= near))
        continue;
      const Vec3 quarter = 0.25 * (box[j].max - box[j].min);
      n += (box[j].min.array() + quarter.array() <= c.array()).all() &&
           (c.array() <= box[j].max.array() - quarter.array()).all();
    }
    active.resize(kept);
    deepest = std::max(deepest, n);
    if (deepest > enough) break;
  }
  return deepest;
}

// The fan-in for a group of operands: union_fan_in, or stack_fan_in where more of their boxes
// than that hold one point (EvalOptions).
std::size_t fan_in(const std::vector<std::shared_ptr<Evaluated>>& group, const Run& run) {
  const std::size_t k = run.options.union_fan_in, s = run.options.stack_fan_in;
  if (k < 2 || s < 2 || s >= k || group.size() <= s) return k;
  std::vector<Box3> box(group.size());
  for (std::size_t i = 0; i < group.size(); ++i) box[i] = mesh_box(group[i]->mesh);
  return stack_depth(box, s) > s ? s : k;
}

// The operands of the node being evaluated, as the script gave them, for the engine's errors: a
// union's operands reach the engine grouped and ordered by their boxes, a difference's pruned, so
// the engine's own numbering ("the first operand") would name the wrong one.
struct Origin {
  BooleanOp op;
  std::unordered_map<const Evaluated*, std::size_t> place;  // each operand's first place in the node
  const std::string* where;                                  // where the script made the node, or empty
};

// "the third operand of the union"; an engine operand that is none of the node's own (a union of
// some of them, made on the way) is "a partial union of the operands of the union". (Looked up,
// not searched: a chain s = s + b of n links is one node of n operands.)
std::string origin_name(const Origin& origin, const std::shared_ptr<Evaluated>& e, BooleanOp partial) {
  static const char* const ordinal[] = {"first", "second", "third", "fourth", "fifth",
                                        "sixth", "seventh", "eighth", "ninth", "tenth"};
  // (A script's node is named by its line: the error comes from the query that evaluates it, often
  // lines later.)
  const std::string node = std::string(boolean_op_name(origin.op)) + (origin.where->empty() ? "" : " at " + *origin.where);
  if (const auto it = origin.place.find(e.get()); it != origin.place.end()) {
    const std::size_t j = it->second;
    return (j < 10 ? std::string("the ") + ordinal[j] + " operand" : "operand " + std::to_string(j + 1)) + " of the " + node;
  }
  return std::string("a partial ") + boolean_op_name(partial) + " of the operands of the " + node;
}

// The engine on some operands; the result's face ids number the operands' faces in turn.
std::shared_ptr<Evaluated> engine(BooleanOp op, const std::vector<std::shared_ptr<Evaluated>>& in, Run& run, const Origin& origin) {
  auto out = std::make_shared<Evaluated>();
  if (in.size() == 1) {
    out->mesh = in[0]->mesh;
    out->kinds = in[0]->kinds;
    out->tags = in[0]->tags;
    out->surfaces = in[0]->surfaces;
    out->corner_uv = in[0]->corner_uv;
    return out;
  }
  std::vector<const Mesh*> ptrs;
  std::vector<std::int32_t> offset;
  for (const auto& e : in) {
    ptrs.push_back(&e->mesh);
    offset.push_back(static_cast<std::int32_t>(out->kinds.size()));
    out->kinds.insert(out->kinds.end(), e->kinds.begin(), e->kinds.end());
    out->tags.insert(out->tags.end(), e->tags.begin(), e->tags.end());
    // A difference keeps the later operands' faces turned inside out (they bound the hole): their
    // surfaces' outward side flips with them.
    for (const FaceSurface& f : e->surfaces)
      out->surfaces.push_back(op == BooleanOp::Difference && ptrs.size() > 1 ? flipped_surface(f) : f);
  }
  check_boolean_budget(op, ptrs, run.max_triangles);
  std::vector<std::string> names;
  for (const auto& e : in) names.push_back(origin_name(origin, e, op == BooleanOp::Difference ? BooleanOp::Union : op));
  BooleanStats st;
  BooleanResult r = wedge::boolean(op, ptrs, &st, &run.cancel, run.max_crossings, &names);
  run.add(&EvalStats::check, st.check);
  run.add(&EvalStats::broad, st.broad);
  run.add(&EvalStats::arrange, st.arrange);
  run.add(&EvalStats::classify, st.classify);
  run.add(&EvalStats::output, st.output);
  run.count(&EvalStats::booleans);
  run.widest(static_cast<long>(in.size()));
  out->mesh = std::move(r.mesh);
  out->mesh.face_ids.resize(out->mesh.triangles.size());
  bool any_uv = false;
  for (const auto& e : in) any_uv = any_uv || !e->corner_uv.empty();
  if (any_uv) out->corner_uv.assign(out->mesh.triangles.size(), kNoUv);
  for (std::size_t t = 0; t < out->mesh.triangles.size(); ++t) {
    const std::size_t o = static_cast<std::size_t>(r.operand[t]);
    out->mesh.face_ids[t] = offset[o] + in[o]->mesh.face_ids[static_cast<std::size_t>(r.source[t])];
    // Where the triangle lies in its source triangle: the guess for its corners' parameters.
    if (!in[o]->corner_uv.empty()) {
      const auto source = static_cast<std::size_t>(r.source[t]);
      out->corner_uv[t] = interpolated_uv(in[o]->mesh, in[o]->corner_uv, source, out->mesh, t,
                                          parametric_surface(in[o]->mesh, in[o]->surfaces, source));
    }
  }
  return out;
}

std::shared_ptr<Evaluated> union_of(const std::vector<std::shared_ptr<Evaluated>>& in, Run& run, const Origin& origin);

// The union of operands whose boxes overlap one another (transitively). Up to the fan-in, one
// engine pass over all of them (the engine is n-ary); beyond it, a balanced tree: the operands
// (in the order of their boxes along x, so that neighbours are near) are cut into fan-in runs of
// near-equal length, each run's union is made the same way (in parallel), and one engine pass
// joins the runs' results. Each engine call then stays small, so a cancel is seen soon and the
// two threads have independent work; the depth grows as log(n) / log(fan-in).
//
// First, with pruning on, the hubs: operands whose boxes meet more than fan-in others (a plate under
// its 400 bosses). The others are unioned without them (grouped by their boxes again: bosses apart
// from one another are put side by side with no engine pass), and one pass joins the hubs and that
// union. Cut into runs instead, the plate met one run of bosses in one pass and everything else
// in the next, its triangles cut twice (1.56 s against 1.17 s in one pass, bench_tree at one
// thread); with the hubs apart it is one pass of two operands.
//
// Before either, a group whose boxes are sparse (no point in more than fan-in of them, by the bound
// of overlaps() below: the plate and its bosses, at most two) is one pass however many operands it
// has: the fan-in bounds the operands that lie on one another, which is where an engine pass grows
// faster than its input. One pass of the plate and 400 bosses took 1.13 s of the 400-boss plate's
// evaluation against 1.21 s with the bosses put side by side as one operand first.
//
// The fan-in is the smaller stack fan-in (4) where more operands than that pile on one point
// (fan_in(): spokes through one hub, a shape's copies shifted a little): one pass over 24 spokes
// through one point took 1.6 s, passes of 4 take 0.2 s; 32 boxes shifted by 1/1024 went past the
// engine's work budget in one pass.
struct Overlaps {
  std::vector<std::size_t> degree;  // per operand, the others its box meets
  bool sparse = false;              // no point in more than the k asked of their boxes
};
Overlaps overlaps(const std::vector<std::shared_ptr<Evaluated>>& in, std::size_t k);
std::shared_ptr<Evaluated> balanced_union(const std::vector<std::shared_ptr<Evaluated>>& group, Run& run, const Origin& origin) {
  const std::size_t k = fan_in(group, run);
  if (k < 2 || group.size() <= k) return engine(BooleanOp::Union, group, run, origin);
  if (run.options.prune) {
    const Overlaps o = overlaps(group, k);
    if (o.sparse) return engine(BooleanOp::Union, group, run, origin);
    const std::vector<std::size_t>& degree = o.degree;
    std::vector<std::shared_ptr<Evaluated>> hubs, rest;
    for (std::size_t i = 0; i < group.size(); ++i) (degree[i] > k ? hubs : rest).push_back(group[i]);
    // Two or more others, so that the group below is smaller than this one.
    if (!hubs.empty() && rest.size() >= 2) {
      auto others = union_of(rest, run, origin);
      run.check();
      if (!others->mesh.empty()) hubs.push_back(others);
      return balanced_union(hubs, run, origin);
    }
  }
  std::vector<std::vector<std::shared_ptr<Evaluated>>> runs(k);
  for (std::size_t i = 0; i < k; ++i)
    runs[i].assign(group.begin() + long(group.size() * i / k), group.begin() + long(group.size() * (i + 1) / k));
  std::vector<std::shared_ptr<Evaluated>> parts(k);
  auto one = [&](std::size_t i) {
    run.check();
    parts[i] = run.options.prune ? union_of(runs[i], run, origin) : balanced_union(runs[i], run, origin);
  };
  if (run.options.parallel) parallel_for(0, k, one);
  else
    for (std::size_t i = 0; i < k; ++i) one(i);
  run.check();
  parts.erase(std::remove_if(parts.begin(), parts.end(), [](const auto& p) { return p->mesh.empty(); }), parts.end());
  if (parts.empty()) return std::make_shared<Evaluated>();
  return engine(BooleanOp::Union, parts, run, origin);
}

// For each operand, how many others its box meets (a sweep along x, as union_of's), and whether
// at most k boxes can share a point: the operands that meet k or more others all, plus one other
// and those of its neighbours that are not among them.
Overlaps overlaps(const std::vector<std::shared_ptr<Evaluated>>& in, std::size_t k) {
  std::vector<Box3> box(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) box[i] = mesh_box(in[i]->mesh);
  std::vector<std::size_t> order(in.size());
  Overlaps out;
  out.degree.assign(in.size(), 0);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return box[a].min.x() < box[b].min.x(); });
  // Two sweeps, the pairs not kept (a thousand operands on one another are half a million pairs).
  auto sweep = [&](const auto& pair) {
    for (std::size_t a = 0; a < order.size(); ++a)
      for (std::size_t b = a + 1; b < order.size() && box[order[b]].min.x() <= box[order[a]].max.x(); ++b)
        if (!boxes_apart(box[order[a]], box[order[b]])) pair(order[a], order[b]);
  };
  sweep([&](std::size_t a, std::size_t b) { ++out.degree[a], ++out.degree[b]; });
  std::size_t hubs = 0;
  for (std::size_t d : out.degree) hubs += d >= k;
  if (hubs + 1 > k) return out;
  std::vector<std::size_t> among(in.size(), 0);  // neighbours that are no hubs
  sweep([&](std::size_t a, std::size_t b) {
    if (out.degree[a] < k && out.degree[b] < k) ++among[a], ++among[b];
  });
  const std::size_t widest = among.empty() ? 0 : *std::max_element(among.begin(), among.end());
  out.sparse = hubs + 1 + widest <= k;
  return out;
}

std::shared_ptr<Evaluated> union_of(const std::vector<std::shared_ptr<Evaluated>>& in, Run& run, const Origin& origin) {
  // Operands in groups whose boxes overlap (transitively); a group of one needs no engine, and
  // groups far apart are put side by side as separate shells.
  std::vector<Box3> box(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) box[i] = mesh_box(in[i]->mesh);
  std::vector<std::size_t> parent(in.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < in.size(); ++i)
    if (!in[i]->mesh.empty()) order.push_back(i);
  // Sweep along x: only boxes whose x-ranges overlap can touch.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return box[a].min.x() < box[b].min.x(); });
  for (std::size_t a = 0; a < order.size(); ++a)
    for (std::size_t b = a + 1; b < order.size() && box[order[b]].min.x() <= box[order[a]].max.x(); ++b)
      if (!boxes_apart(box[order[a]], box[order[b]])) parent[find(order[a])] = find(order[b]);
  std::map<std::size_t, std::vector<std::shared_ptr<Evaluated>>> groups;
  for (std::size_t i : order) groups[find(i)].push_back(in[i]);
  std::vector<std::vector<std::shared_ptr<Evaluated>>> list;
  for (auto& [root, g] : groups) list.push_back(std::move(g));
  if (list.empty()) return std::make_shared<Evaluated>();
  if (list.size() > 1) run.count(&EvalStats::pruned);
  std::vector<std::shared_ptr<Evaluated>> parts(list.size());
  auto part = [&](std::size_t i) { parts[i] = balanced_union(list[i], run, origin); };
  if (run.options.parallel && list.size() > 1) parallel_for(0, list.size(), part);
  else
    for (std::size_t i = 0; i < list.size(); ++i) part(i);
  if (parts.size() == 1) return parts[0];
  auto out = std::make_shared<Evaluated>();
  for (const auto& p : parts) append_evaluated(*out, *p);
  return out;
}

// The intersection of operands whose boxes all meet: up to the fan-in one engine pass, beyond it a
// balanced tree as for unions (balanced_union). An engine pass over n operands whose faces lie on
// one another's (a script intersecting nearly the same box again and again) meets every triangle's
// coplanar copies in all the others, and its time and memory grow much faster than n: 1001
// coincident boxes in one pass grew past 15 GB; 16 boxes shifted by 1/1024 took 0.1 s, 32 of
// them 1.8 s. Cut into runs of at most the fan-in, each pass stays bounded; an empty run ends it.
// (Exact copies never reach the engine: see distinct().)
std::shared_ptr<Evaluated> balanced_intersection(const std::vector<std::shared_ptr<Evaluated>>& group, Run& run, const Origin& origin) {
  const std::size_t k = fan_in(group, run);
  if (k < 2 || group.size() <= k) return engine(BooleanOp::Intersection, group, run, origin);
  std::vector<std::shared_ptr<Evaluated>> parts(k);
  auto one = [&](std::size_t i) {
    run.check();
    const std::vector<std::shared_ptr<Evaluated>> part(group.begin() + long(group.size() * i / k),
                                                       group.begin() + long(group.size() * (i + 1) / k));
    parts[i] = balanced_intersection(part, run, origin);
  };
  if (run.options.parallel) parallel_for(0, k, one);
  else
    for (std::size_t i = 0; i < k; ++i) one(i);
  run.check();
  for (const auto& p : parts)
    if (p->mesh.empty()) return std::make_shared<Evaluated>();
  std::vector<Box3> box;
  for (const auto& p : parts) box.push_back(mesh_box(p->mesh));
  if (run.options.prune && !boxes_meet(box)) return std::make_shared<Evaluated>();
  return engine(BooleanOp::Intersection, parts, run, origin);
}

// first minus the subtrahends (those that can reach it). Up to the fan-in, one engine pass; beyond
// it the subtrahends' union first (grouped by their boxes and balanced: holes apart from one
// another are put side by side without the engine), then one pass of first minus that union, as
// a - b - c = a - (b + c). One pass over a thousand coincident subtrahends would grow as one
// intersection of them does (balanced_intersection).
std::shared_ptr<Evaluated> difference_of(const std::shared_ptr<Evaluated>& first,
                                         const std::vector<std::shared_ptr<Evaluated>>& subtrahends, Run& run, const Origin& origin) {
  std::vector<std::shared_ptr<Evaluated>> all{first};  // first, then the subtrahends
  all.insert(all.end(), subtrahends.begin(), subtrahends.end());
  const std::size_t k = fan_in(all, run);
  // Up to the fan-in, or subtrahends apart from one another (400 drills, as for a sparse union):
  // one pass.
  if (k < 2 || subtrahends.size() <= k || (run.options.prune && overlaps(subtrahends, k - 1).sparse))
    return engine(BooleanOp::Difference, all, run, origin);
  auto cut = run.options.prune ? union_of(subtrahends, run, origin) : balanced_union(subtrahends, run, origin);
  run.check();
  if (cut->mesh.empty()) return engine(BooleanOp::Difference, {first}, run, origin);
  return engine(BooleanOp::Difference, {first, cut}, run, origin);
}

bool same_mesh(const Mesh& a, const Mesh& b) { return a.positions == b.positions && a.triangles == b.triangles; }

// The operands of an n-ary node without the repeats of one mesh (the same points and the same
// triangles, as a script that adds, intersects or subtracts one shape again and again makes):
// A + A = A * A = A and A - B - B = A - B. The first of each kept, as the engine keeps the
// lowest operand's copy of coincident faces, so the faces and their tags are the same as the
// engine's; the engine would find the same result through every pair of coincident triangles.
// Operands [0, from) are kept as they are (a difference's first operand).
std::vector<std::shared_ptr<Evaluated>> distinct(const std::vector<std::shared_ptr<Evaluated>>& in, std::size_t from) {
  if (in.size() < from + 2) return in;
  auto hash = [](const Mesh& m) {
    std::size_t h = m.positions.size() * 1000003u ^ m.triangles.size();
    auto mix = [&](double x) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      h ^= std::hash<std::uint64_t>()(bits) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
    };
    for (const Point3& p : m.positions) mix(p.x()), mix(p.y()), mix(p.z());
    return h;
  };
  std::vector<std::shared_ptr<Evaluated>> out(in.begin(), in.begin() + long(from));
  std::unordered_multimap<std::size_t, std::size_t> seen;  // hash -> index in out
  for (std::size_t i = from; i < in.size(); ++i) {
    const Mesh& m = in[i]->mesh;
    const std::size_t h = hash(m);
    bool repeat = false;
    for (auto [it, end] = seen.equal_range(h); it != end && !repeat; ++it)
      repeat = out[it->second] == in[i] || same_mesh(out[it->second]->mesh, m);
    if (repeat) continue;
    seen.emplace(h, out.size());
    out.push_back(in[i]);
  }
  return out;
}

}  // namespace

std::shared_ptr<Evaluated> evaluate_boolean(const Solid::Node& n, const Tolerance& tol, Run& run) {
  const auto& operands = n.operands();
  std::vector<std::shared_ptr<Evaluated>> in(operands.size());
  auto one = [&](std::size_t i) { in[i] = evaluate(operands[i], tol, run); };
  if (run.options.parallel && in.size() > 1) parallel_for(0, in.size(), one);
  else
    for (std::size_t i = 0; i < in.size(); ++i) one(i);
  run.check();
  Origin origin{n.op, {}, &n.where};
  origin.place.reserve(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) origin.place.emplace(in[i].get(), i);  // (a repeat keeps its first place)
  // A leaf that bounds no solid (a polyhedron whose faces cross) is refused here, as its own
  // queries refuse it: the ways around the engine below (one operand, repeats, operands apart)
  // would otherwise pass its mesh on unchecked. Two overlapping cubes in one polyhedron, united
  // with a cube far away, had volume 3 where the region they bound is 1.875 + 1, and a point
  // inside both was "outside".
  for (std::size_t i = 0; i < operands.size(); ++i) {
    const Solid::Node* o = operands[i].get();
    while (o->kind == Solid::Node::Kind::Transform) o = o->child.get();
    if (o->kind == Solid::Node::Kind::Leaf)
      if (std::string d = o->leaf->solid_defect(); !d.empty())
        fail("boolean: ", origin_name(origin, in[i], n.op), " is not a solid: ", d);
  }
  in = distinct(in, n.op == BooleanOp::Difference ? 1 : 0);
  if (n.op == BooleanOp::Difference)  // A - A - ... is empty
    for (std::size_t i = 1; i < in.size(); ++i)
      if (!in[0]->mesh.empty() && same_mesh(in[0]->mesh, in[i]->mesh)) return std::make_shared<Evaluated>();
  std::vector<Box3> box(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) box[i] = mesh_box(in[i]->mesh);

  if (!run.options.prune) {
    std::vector<std::shared_ptr<Evaluated>> all;
    for (auto& e : in)
      if (!e->mesh.empty()) all.push_back(e);
    if (all.empty() || (n.op == BooleanOp::Difference && in[0]->mesh.empty()) ||
        (n.op == BooleanOp::Intersection && all.size() != in.size()))
      return std::make_shared<Evaluated>();
    switch (n.op) {
      case BooleanOp::Union: return balanced_union(all, run, origin);
      case BooleanOp::Intersection: return balanced_intersection(all, run, origin);
      case BooleanOp::Difference: return difference_of(all[0], {all.begin() + 1, all.end()}, run, origin);
    }
  }
  switch (n.op) {
    case BooleanOp::Difference: {
      // Only the operands whose boxes meet the first can take anything away.
      if (in[0]->mesh.empty()) return std::make_shared<Evaluated>();
      std::vector<std::shared_ptr<Evaluated>> use;
      for (std::size_t i = 1; i < in.size(); ++i)
        if (!boxes_apart(box[0], box[i])) use.push_back(in[i]);
        else run.count(&EvalStats::pruned);
      return difference_of(in[0], use, run, origin);
    }
    case BooleanOp::Intersection: {
      if (!boxes_meet(box)) {
        run.count(&EvalStats::pruned);
        return std::make_shared<Evaluated>();
      }
      return balanced_intersection(in, run, origin);
    }
    case BooleanOp::Union: return union_of(in, run, origin);
  }
  return std::make_shared<Evaluated>();
}

}  // namespace wedge::tree_detail
