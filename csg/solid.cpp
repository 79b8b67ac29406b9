#include "csg/solid.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <unordered_map>
#include <atomic>
#include <chrono>

#include <tbb/task_arena.h>

#include "csg/brep_leaf.h"
#include "csg/mesh_leaf.h"
#include "csg/solid_impl.h"
#include "kernel/parallel.h"
#include "kernel/predicates.h"
#include "tessellate/progress.h"
#include <limits>

#include <Eigen/Eigenvalues>

namespace wedge {

using tree_detail::child_tolerance;
using tree_detail::elapsed_ms;
using tree_detail::evaluate;
using tree_detail::evaluate_boolean;
using tree_detail::evaluate_root;
using tree_detail::transformed_box;
using tree_detail::NodePtr;
using tree_detail::Run;

// --- the CSG tree ---
//
// Evaluation. Every node keeps its evaluated result per tolerance (chordal, angular): the mesh, its
// face ids numbering the node's faces, and each face's surface kind; the winged-edge solid rebuilt
// from it is made on demand and kept beside it. A subtree shared by several parents is a shared
// node, so it is evaluated once. A boolean node evaluates its operands (in parallel on TBB's
// threads, each in an isolated task arena so that a thread waiting for a shared node never runs a
// task that waits for it too), prunes by bounding boxes, and calls the engine once per group of
// operands whose boxes overlap (solid_boolean.cpp). Cancel and progress go through the installed
// EvalControl.

namespace {
// The largest stretch a transform applies to any direction (its spectral norm, bounded above by
// the Frobenius norm of the linear part, which is cheap and safe for choosing tolerances).
double m_norm(const Mat4& m) {
  // sqrt of the largest eigenvalue of A^T A: exactly 1 for a rotation or a translation, so that a
  // moved copy of a shared subtree asks for it at the same tolerance and shares its cache entry.
  const Mat3 a = m.block<3, 3>(0, 0);
  const double s = std::sqrt(Eigen::SelfAdjointEigenSolver<Mat3>(a.transpose() * a, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff());
  return std::abs(s - 1) < 1e-9 ? 1.0 : s;
}

// A box that holds the solid under n, found without evaluating any boolean (for checks that must
// not force an evaluation).
Box3 loose_bounds(const std::shared_ptr<const Solid::Node>& n);

std::atomic<const EvalControl*> g_control{nullptr};
std::mutex g_options_mutex;
EvalOptions g_options;

EvalOptions options() {
  std::lock_guard<std::mutex> lock(g_options_mutex);
  return g_options;
}

}  // namespace

double tree_detail::elapsed_ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

const EvalControl* tree_detail::eval_control() { return g_control.load(); }

void set_eval_control(const EvalControl* control) { g_control.store(control); }

void set_eval_options(const EvalOptions& o) {
  std::lock_guard<std::mutex> lock(g_options_mutex);
  g_options = o;
}

namespace {
// Alternating unions and differences (s = s + a; s = s - b; ...) nest one level per operation; a
// tree 20000 levels deep overflowed the stack of the recursive evaluation.
constexpr int kMaxTreeDepth = 1000;
void check_tree_depth(int depth, const char* what) {
  if (depth > kMaxTreeDepth)
    fail(what, ": the CSG tree would be ", depth, " levels deep, beyond ", kMaxTreeDepth,
         " (alternating unions and differences nest; gather operands: union(a, b, c), s - union(h1, h2, ...))");
}
}  // namespace

namespace {

NodePtr moved_node(const NodePtr& n, const Mat4& m);
NodePtr moved_operands(const Solid::Node& b, const Mat4& m, bool leaves_only);

// True when m only swaps and negates axes (a mirror through a coordinate plane, a turn by a
// multiple of 90 degrees about an axis; no translation), but is not the identity: it moves every
// double exactly, and commutes with rounding, so the boolean of moved operands is the moved result.
bool swaps_axes(const Mat4& m) {
  if (m == Mat4::Identity() || m.block<3, 1>(0, 3) != Vec3::Zero()) return false;
  for (int r = 0; r < 3; ++r) {
    int ones = 0;
    for (int c = 0; c < 3; ++c)
      if (m(r, c) == 1 || m(r, c) == -1) ++ones;
      else if (m(r, c) != 0) return false;
    if (ones != 1) return false;
  }
  return true;
}

// True when the subtree under n is small (at most kRemade nodes, counted along every path, as a
// copy of it counts them) and has a leaf that places its copies by symmetry. (Unbounded, s = s +
// s:mirror{1, 0, 0} repeated copied the tree along every path: 14 times, 4.7 s and 1.2 GB.)
bool remade_when_moved(const NodePtr& n) {
  constexpr std::size_t kRemade = 64;
  std::vector<const Solid::Node*> stack{n.get()};
  std::size_t visits = 0;
  bool symmetric = false;
  while (!stack.empty()) {
    if (++visits > kRemade) return false;
    const Solid::Node* x = stack.back();
    stack.pop_back();
    switch (x->kind) {
      case Solid::Node::Kind::Empty: break;
      case Solid::Node::Kind::Leaf: symmetric = symmetric || x->leaf->symmetric(); break;
      case Solid::Node::Kind::Transform: stack.push_back(x->child.get()); break;
      case Solid::Node::Kind::Boolean:
        x->for_each_operand([&](const NodePtr& o) { stack.push_back(o.get()); });
        break;
    }
  }
  return symmetric;
}

// The node n moved by m (checked by Solid::transformed): a leaf that can move itself is a new leaf
// (its tag kept), consecutive transforms fold into one node, anything else gets a transform node.
// A boolean that holds a symmetric leaf, mirrored or turned by 90 degrees about an axis, is
// remade from its moved operands: a symmetric leaf's copy is then its source's own mesh, and a
// part symmetric about x = 0 united with its mirror image is itself (moved as a whole, its sphere's
// mesh, not symmetric, left 224 faces of slivers).
NodePtr moved_node(const NodePtr& n, const Mat4& m) {
  switch (n->kind) {
    case Solid::Node::Kind::Empty: return n;
    case Solid::Node::Kind::Leaf:
      if (auto t = n->leaf->transformed(m)) {
        auto out = std::make_shared<Solid::Node>();
        out->kind = Solid::Node::Kind::Leaf;
        out->leaf = std::move(t);
        out->tag = n->tag;
        return out;
      }
      break;
    case Solid::Node::Kind::Transform: {
      auto out = std::make_shared<Solid::Node>(*n);
      out->matrix = m * n->matrix;
      return out;
    }
    case Solid::Node::Kind::Boolean:
      if (swaps_axes(m) && remade_when_moved(n)) return moved_operands(*n, m, false);
      break;
  }
  auto out = std::make_shared<Solid::Node>();
  out->kind = Solid::Node::Kind::Transform;
  out->matrix = m;
  out->child = n;
  out->depth = n->depth + 1;
  check_tree_depth(out->depth, "transform");
  return out;
}

// True when m moves every vertex of mesh without rounding: each row of its linear part has one
// entry, a power of two (a translation, a mirror, a turn by 90 degrees, a scale by 2), and each
// product and sum is exact (Knuth's two-sum leaves no error).
bool moves_exactly(const Mesh& mesh, const Mat4& m) {
  std::array<int, 3> col{};
  for (int r = 0; r < 3; ++r) {
    int nonzero = 0;
    for (int c = 0; c < 3; ++c)
      if (m(r, c) != 0) ++nonzero, col[r] = c;
    int e = 0;
    if (nonzero != 1 || std::frexp(std::abs(m(r, col[r])), &e) != 0.5) return false;
  }
  for (const Point3& p : mesh.positions)
    for (int r = 0; r < 3; ++r) {
      const double a = m(r, col[r]), t = m(r, 3), q = a * p[col[r]];
      if (q / a != p[col[r]]) return false;  // under- or overflow
      const double s = q + t, bq = s - q;
      if ((q - (s - bq)) + (t - bq) != 0) return false;
    }
  return true;
}

// False when no triangle of `moved` has an edge or a height within 64 rounding steps of its
// coordinates: rounding each vertex (by at most one step) can then neither flatten nor turn over a
// triangle. Two sheets of fat triangles closer than that are not seen here; the engine's own
// operand check still refuses them if they cross.
bool thin_for_rounding(const Mesh& moved) {
  double reach = 0;
  for (const Point3& p : moved.positions) reach = std::max(reach, p.cwiseAbs().maxCoeff());
  if (reach == 0) return true;
  const double limit = 64 * std::ldexp(1.0, std::ilogb(reach) - 52);
  for (const auto& t : moved.triangles) {
    const Point3 &a = moved.positions[t[0]], &b = moved.positions[t[1]], &c = moved.positions[t[2]];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    if (!(longest > limit) || !((b - a).cross(c - a).norm() / longest > limit)) return true;
  }
  return false;
}

// The boolean node b with every operand moved by m: the same solid, moved, made by one engine call
// on moved operands (as costly as b's own) instead of by moving b's result. With `leaves_only`,
// nullptr unless each moved operand is a leaf: remaking operands that are booleans themselves
// nested, and a tree that shares a subtree under many moves (s = s + s:mirror("x"):translate(...),
// repeated) was remade at every level into one pass of near-coincident copies (a minute in the
// engine, then a failure, where the spoiled operand is reported at once).
NodePtr moved_operands(const Solid::Node& b, const Mat4& m, bool leaves_only) {
  auto out = std::make_shared<Solid::Node>();
  out->kind = Solid::Node::Kind::Boolean;
  out->op = b.op;
  out->tag = b.tag;
  out->where = b.where;
  for (const NodePtr& o : b.operands()) {
    NodePtr moved = moved_node(o, m);
    if (leaves_only && moved->kind != Solid::Node::Kind::Leaf) return nullptr;
    out->depth = std::max(out->depth, moved->depth + 1);
    out->parts.push_back({std::move(moved), false});
  }
  out->size = out->parts.size();
  return out;
}

static_assert(Tolerance{}.max_crossings == kDefaultMaxCrossings, "one default work budget");

}  // namespace

Tolerance tree_detail::child_tolerance(const Solid::Node& n, const Tolerance& tol) {
  Tolerance t = tol;
  double stretch = m_norm(n.matrix);
  if (stretch > 0) t.chordal = tol.chordal / std::max(1.0, stretch);
  return t;
}

namespace {

bool cached(const Solid::Node& n, const Tolerance& tol) {
  std::lock_guard<std::mutex> lock(n.cache_mutex);
  auto it = n.cache.find({tol.chordal, tol.angular});
  return it != n.cache.end() && it->second->value;
}

// The boolean nodes an evaluation at tol will compute (each shared node once).
void count_booleans(const NodePtr& n, const Tolerance& tol, std::set<const Solid::Node*>& seen) {
  if (!n || !seen.insert(n.get()).second) return;
  switch (n->kind) {
    case Solid::Node::Kind::Transform: count_booleans(n->child, child_tolerance(*n, tol), seen); break;
    case Solid::Node::Kind::Boolean:
      if (cached(*n, tol)) return;
      n->for_each_operand([&](const NodePtr& o) { count_booleans(o, tol, seen); });
      break;
    default: break;
  }
}

std::shared_ptr<Evaluated> compute_untagged(const Solid::Node& n, const Tolerance& tol, Run& run);

std::shared_ptr<Evaluated> compute(const Solid::Node& n, const Tolerance& tol, Run& run) {
  auto out = compute_untagged(n, tol, run);
  if (n.tag >= 0)
    for (int& t : out->tags)
      if (t < 0) t = n.tag;
  return out;
}

std::shared_ptr<Evaluated> compute_untagged(const Solid::Node& n, const Tolerance& tol, Run& run) {
  switch (n.kind) {
    case Solid::Node::Kind::Empty: return std::make_shared<Evaluated>();
    case Solid::Node::Kind::Leaf: {
      auto t0 = std::chrono::steady_clock::now();
      auto out = std::make_shared<Evaluated>();
      {
        // A cancel is seen inside a long tessellation too, not only when the leaf is done.
        const TessellatePoll poll = [&run] { run.check(); };
        const TessellatePoll* const outer = set_tessellate_poll(&poll);
        struct Restore {
          const TessellatePoll* outer;
          ~Restore() { set_tessellate_poll(outer); }
        } restore{outer};
        out->mesh = n.leaf->parametrised_mesh(tol, out->corner_uv);
      }
      out->kinds = n.leaf->face_kinds();
      if (out->kinds.empty()) {
        out->kinds.assign(planar_regions(out->mesh, out->surfaces), "plane");
      } else {
        out->surfaces = n.leaf->face_surfaces();
        if (out->surfaces.size() != out->kinds.size()) fail("a leaf gives ", out->surfaces.size(), " face surfaces for ", out->kinds.size(), " faces");
        for (auto& id : out->mesh.face_ids)
          if (id < 0 || static_cast<std::size_t>(id) >= out->kinds.size()) fail("a leaf's mesh names face ", id, ", which it has not");
      }
      out->tags.assign(out->kinds.size(), -1);
      run.add(&EvalStats::tessellate, elapsed_ms(t0));
      return out;
    }
    case Solid::Node::Kind::Transform: {
      auto c = evaluate(n.child, child_tolerance(n, tol), run);
      auto out = std::make_shared<Evaluated>();
      out->mesh = c->mesh.transformed(n.matrix);
      out->kinds = c->kinds;
      out->tags = c->tags;
      out->corner_uv = c->corner_uv;
      if (reverses_orientation(n.matrix))  // Mesh::transformed swapped corners 1 and 2
        for (auto& uv : out->corner_uv) std::swap(uv[1], uv[2]);
      const Box3 extent = c->mesh.empty() ? Box3() : c->mesh.bounds();
      out->surfaces.reserve(c->surfaces.size());
      for (const FaceSurface& f : c->surfaces) out->surfaces.push_back(transformed_surface(f, n.matrix, extent));
      // A boolean result has vertices far closer together than a double's rounding at another
      // place or scale (where a sphere's facet meets a cube's face, 1e-16 apart): moved, they can
      // round into triangles that cross or have no area ((sphere(1) - cube(1)):scale(3) crossed
      // itself, and a boolean refused it as an operand). Unless the move is exact or the mesh has
      // no triangle that thin, the moved mesh is checked exactly, and a defective one is made
      // again: the engine resolves the moved mesh where it crosses itself (the region of winding
      // number at least 1, rounded again). Made instead from the moved leaves, the leaves' shared
      // planes no longer coincide after an inexact move: cube(1) - cylinder(0.3, 3), turned, kept
      // a flap between the cube's face and the cylinder's cap, a film the next boolean could not
      // round (29 of 120 random booleans with it failed). The leaves remain the fallback.
      if (n.child->kind == Solid::Node::Kind::Boolean && !out->mesh.empty() && !moves_exactly(c->mesh, n.matrix) &&
          thin_for_rounding(out->mesh)) {
        const auto t0 = std::chrono::steady_clock::now();
        const bool defective = !mesh_solid_defect(out->mesh).empty();
        run.add(&EvalStats::check, elapsed_ms(t0));
        if (defective) {
          std::string unresolved;
          try {
            const auto t1 = std::chrono::steady_clock::now();
            BooleanResult r = resolve_self(out->mesh, &run.cancel);
            run.add(&EvalStats::output, elapsed_ms(t1));
            run.count(&EvalStats::remade);
            if (!out->corner_uv.empty()) {
              CornerUvs uv(r.mesh.triangles.size());
              for (std::size_t t = 0; t < uv.size(); ++t) {
                const auto source = static_cast<std::size_t>(r.source[t]);
                uv[t] = interpolated_uv(out->mesh, out->corner_uv, source, r.mesh, t,
                                        parametric_surface(out->mesh, out->surfaces, source));
              }
              out->corner_uv = std::move(uv);
            }
            out->mesh = std::move(r.mesh);
            return out;
          } catch (const Cancelled&) {
            throw;
          } catch (const Error& e) {
            unresolved = e.what();
          }
          if (NodePtr remade = moved_operands(*n.child, n.matrix, true)) {
            run.count(&EvalStats::remade);
            return evaluate(remade, tol, run);
          }
          // Returned as it is, the mesh would cross itself: an export would write it, and the next
          // boolean would refuse it as "the second operand" of a tree the script never wrote.
          fail("a boolean result, moved by a transform that is not exact, crosses itself where its vertices "
               "rounded, and could not be mended (", unresolved, ")");
        }
      }
      return out;
    }
    case Solid::Node::Kind::Boolean: {
      auto out = evaluate_boolean(n, tol, run);
      run.boolean_done();
      return out;
    }
  }
  return std::make_shared<Evaluated>();
}

}  // namespace

std::shared_ptr<Evaluated> tree_detail::evaluate(const NodePtr& n, const Tolerance& tol, Run& run) {
  run.check();
  if (!run.options.cache) return compute(*n, tol, run);
  std::shared_ptr<Solid::Node::Slot> slot;
  {
    std::lock_guard<std::mutex> lock(n->cache_mutex);
    auto& s = n->cache[{tol.chordal, tol.angular}];
    if (!s) s = std::make_shared<Solid::Node::Slot>();
    slot = s;
  }
  std::lock_guard<std::mutex> lock(slot->mutex);
  if (slot->value) {
    run.count(&EvalStats::cached);
    return slot->value;
  }
  std::shared_ptr<Evaluated> value;
  tbb::this_task_arena::isolate([&] { value = compute(*n, tol, run); });
  slot->value = value;
  return value;
}

namespace {

// A deep tree (a script alternating s = s * B and s = s - b nests a level per step) evaluated from
// its leaves up, one height at a time (a node's operands are all lower than it), so that
// evaluate() finds every operand done and recurses one level only: recursing through 1000
// levels (each a few TBB frames) overflowed the 8 MB main stack under AddressSanitizer. The walk
// keeps its own stack; each (node, tolerance) once; nodes done before are not entered.
constexpr int kRecursiveDepth = 32;  // shallower trees recurse: their subtrees in parallel
void evaluate_bottom_up(const NodePtr& root, const Tolerance& tol, Run& run) {
  std::vector<std::vector<std::pair<NodePtr, Tolerance>>> by_height(static_cast<std::size_t>(root->depth) + 1);
  std::set<std::tuple<const Solid::Node*, double, double>> seen;
  std::vector<std::pair<NodePtr, Tolerance>> stack{{root, tol}};
  while (!stack.empty()) {
    auto [n, t] = std::move(stack.back());
    stack.pop_back();
    if (!seen.insert({n.get(), t.chordal, t.angular}).second || cached(*n, t)) continue;
    if (n->kind == Solid::Node::Kind::Transform) stack.push_back({n->child, child_tolerance(*n, t)});
    if (n->kind == Solid::Node::Kind::Boolean)
      for (const NodePtr& o : n->operands()) stack.push_back({o, t});
    by_height[static_cast<std::size_t>(n->depth)].push_back({std::move(n), t});
  }
  for (const auto& level : by_height) {
    auto one = [&](std::size_t i) { evaluate(level[i].first, level[i].second, run); };
    if (run.options.parallel && level.size() > 1) parallel_for(0, level.size(), one);
    else
      for (std::size_t i = 0; i < level.size(); ++i) one(i);
  }
}

// Evaluates the tree under n at tol with the installed control.
}  // namespace

std::shared_ptr<Evaluated> tree_detail::evaluate_root(const NodePtr& n, const Tolerance& tol) {
  Run run;
  run.max_crossings = tol.max_crossings;
  run.max_triangles = tol.max_triangles;
  run.control = g_control.load();
  run.options = options();
  if (run.control && run.control->cancelled) run.cancel = run.control->cancelled;
  if (run.control && run.control->progress) {
    std::set<const Solid::Node*> seen;
    count_booleans(n, tol, seen);
    for (const auto* p : seen) run.total += p->kind == Solid::Node::Kind::Boolean && !cached(*p, tol);
  }
  if (n->depth > kRecursiveDepth && run.options.cache) evaluate_bottom_up(n, tol, run);
  auto out = evaluate(n, tol, run);
  check_triangle_budget(out->mesh.triangles.size(), tol);
  return out;
}

Box3 tree_detail::transformed_box(const Box3& b, const Mat4& m) {
  Box3 out;
  if (b.empty()) return out;
  for (int i = 0; i < 8; ++i)
    out.extend(apply_point(m, Vec3((i & 1) ? b.max.x() : b.min.x(), (i & 2) ? b.max.y() : b.min.y(), (i & 4) ? b.max.z() : b.min.z())));
  return out;
}

namespace {
// Each node once, however often the tree shares it (s = s + s, repeated, shares every level twice:
// walked path by path, that is 2^levels visits).
Box3 loose_bounds(const std::shared_ptr<const Solid::Node>& n, std::unordered_map<const Solid::Node*, Box3>& memo) {
  if (auto it = memo.find(n.get()); it != memo.end()) return it->second;
  Box3 out;
  switch (n->kind) {
    case Solid::Node::Kind::Empty: break;
    case Solid::Node::Kind::Leaf: out = n->leaf->bounds(); break;
    case Solid::Node::Kind::Transform: out = transformed_box(loose_bounds(n->child, memo), n->matrix); break;
    case Solid::Node::Kind::Boolean:
      if (n->op == BooleanOp::Difference) {
        const Solid::Node* first = n.get();
        while (first->parts[0].splice) first = first->parts[0].node.get();
        out = loose_bounds(first->parts[0].node, memo);
      } else {
        n->for_each_operand([&](const NodePtr& o) { out.extend(loose_bounds(o, memo)); });
      }
      break;
  }
  memo.emplace(n.get(), out);
  return out;
}

Box3 loose_bounds(const std::shared_ptr<const Solid::Node>& n) {
  std::unordered_map<const Solid::Node*, Box3> memo;
  return loose_bounds(n, memo);
}
}  // namespace

Solid Solid::boolean(BooleanOp op, std::vector<Solid> operands, std::string where) {
  if (operands.empty()) fail("boolean: no operands");
  auto n = std::make_shared<Node>();
  n->kind = Node::Kind::Boolean;
  n->op = op;
  n->where = std::move(where);
  // Chains become one n-ary node: a + b + c + ... one union (one engine pass over all operands,
  // grouped by their boxes, balanced when large), a * b * c one intersection, and a - b - c
  // (a script drilling holes one by one) a minus all of b, c, ...: never a chain of growing
  // intermediate results. A tagged node keeps its own (its tag colours its faces). One already
  // evaluated is spliced all the same: the tree's shape, and so the result's bits, must follow
  // from the script alone. Kept whole when evaluated (its result reused), c - s gave another
  // rounding than cube - cylinder - s whenever c:volume() (or any query of c) came first: a volume
  // 5e-13 apart, an OBJ whose every vertex moved, an export that failed or did not. The cost is
  // the cached result not reused: querying a chain after each link repeats the earlier links'
  // engine work (a plate drilled 100 times, its volume asked after every hole: 7.4 s of CPU where
  // reusing took 2.5 s; asked every 10 holes, or only at the end, no slower). An operand is
  // spliced, not copied (Node::parts),
  // so each link of a chain costs the same however long the chain is. The same node twice in one
  // call is spliced once (s + s, repeated, would otherwise double the list each time), and no
  // list grows past kMaxSpliced: beyond it an operand stays a node of its own.
  constexpr std::size_t kMaxSpliced = std::size_t(1) << 20;
  std::set<const Node*> spliced;
  for (std::size_t i = 0; i < operands.size(); ++i) {
    const NodePtr& o = operands[i].node_;
    // b - b with b = x - y spliced would be x - y - b: b's mesh, rounded, is not exactly x - y,
    // and slivers of it were left (36 triangles in 7 shells for b = sphere(1) - cube(1)). Kept whole,
    // the subtrahend is the first operand itself, and the result is empty.
    const auto subtracted_too = [&] {
      return std::any_of(operands.begin() + 1, operands.end(), [&](const Solid& later) { return later.node_ == o; });
    };
    bool splice = o->kind == Node::Kind::Boolean && o->op == op && o->tag < 0 &&
                  (op != BooleanOp::Difference || (i == 0 && !subtracted_too())) && n->size + o->size <= kMaxSpliced;
    if (splice) splice = spliced.insert(o.get()).second;
    n->parts.push_back({o, splice});
    n->size += splice ? o->size : 1;
    n->depth = std::max(n->depth, splice ? o->depth : o->depth + 1);
  }
  check_tree_depth(n->depth, op == BooleanOp::Union ? "union" : op == BooleanOp::Difference ? "difference" : "intersection");
  return Solid(std::shared_ptr<const Node>(n));
}

Solid::Solid() : node_(std::make_shared<Node>()) {}

Solid::Solid(std::shared_ptr<const SolidLeaf> leaf) {
  if (!leaf) fail("Solid: null leaf");
  auto n = std::make_shared<Node>();
  n->kind = Node::Kind::Leaf;
  n->leaf = std::move(leaf);
  node_ = n;
}

Solid::Solid(std::shared_ptr<const Node> node) : node_(std::move(node)) {}

Solid Solid::from_mesh(Mesh mesh, const std::string& what) {
  return Solid(std::make_shared<MeshLeaf>(std::move(mesh), what));
}

bool Solid::empty() const { return node_->kind == Node::Kind::Empty; }

bool Solid::evaluates_empty(const Tolerance& tol) const {
  if (node_->kind == Node::Kind::Empty) return true;
  // Leaves refuse to be made without triangles (MeshLeaf, the builders).
  if (node_->kind == Node::Kind::Leaf || (node_->kind == Node::Kind::Transform && node_->child->kind == Node::Kind::Leaf))
    return false;
  return mesh(tol).triangles.empty();
}

void check_transform(const Mat4& m, const Box3& box, const std::string& what) {
  if (!m.allFinite()) fail(what, " has non-finite entries");
  {
    // A determinant below 1e-300 is either a singular transform (it flattens the solid) or tiny
    // factors that are not singular (scale(1e-101)), whose volumes underflow: the determinant of
    // the linear part with its columns made unit length tells which. (An extreme shear has
    // determinant 1 and is left to the overflow check below.)
    const Mat3 a = m.block<3, 3>(0, 0);
    const double det = a.determinant();
    if (!(std::abs(det) >= 1e-300)) {
      // stableNorm: norm() of (1e-200, 0, 0) underflows to 0.
      const Vec3 len(a.col(0).stableNorm(), a.col(1).stableNorm(), a.col(2).stableNorm());
      const double shape = len.minCoeff() > 0 ? Mat3(a * len.cwiseInverse().asDiagonal()).determinant() : 0.0;
      if (!(std::abs(shape) >= 1e-12)) fail(what, " is singular: it would flatten the solid");
      std::ostringstream factor;  // 6 digits: 1e-303, not 1.0000000000000001e-303
      if (det != 0) factor << std::abs(det);
      else factor << "about 1e" << std::lround(std::log10(std::abs(shape)) + std::log10(len.x()) + std::log10(len.y()) + std::log10(len.z()));
      fail(what, " shrinks volumes by a factor of ", factor.str(),
           ", below 1e-300: the solid's volume and normals would underflow to zero");
    }
  }
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() != 0)
    fail(what, " is projective (last row not 0 0 0 1): solids take affine transforms only");
  // A result beyond the coordinates a solid may have is an error here, not a nan volume later.
  if (const Box3& b = box; !b.empty()) {
    double reach = 0;
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner((i & 1) ? b.max.x() : b.min.x(), (i & 2) ? b.max.y() : b.min.y(), (i & 4) ? b.max.z() : b.min.z());
      const Point3 p = apply_point(m, corner);
      reach = std::max(reach, p.cwiseAbs().maxCoeff());
    }
    if (!(reach <= kMaxCoordinate))
      fail(what, " overflows: the solid would reach coordinate ", reach, ", beyond +-", kMaxCoordinate,
           " (its volume and normals would not be finite numbers)");
    // Far from the origin doubles are far apart (16384 at 1e20): a solid whose size is below
    // 1e-12 of its distance from the origin spans too few of them to keep its shape (a unit sphere
    // moved to 1e20 had a volume of 2.79, a unit box moved to 1e16 crossed itself).
    // The solid's own size after the transform (its corners at `reach` may round together).
    Mat4 linear = m;
    linear.block<3, 1>(0, 3).setZero();
    const double size = transformed_box(b, linear).size().maxCoeff();
    if (size < 1e-12 * reach)
      fail(what, " moves the solid to coordinate ", reach, ", where doubles are ",
           std::nextafter(reach, 2 * reach) - reach, " apart: a solid of size ", size,
           " there would lose its shape (keep its size above 1e-12 of its distance from the origin)");
  }
}

Box3 Solid::loose_bounds() const { return wedge::loose_bounds(node_); }

Solid Solid::transformed(const Mat4& m) const {
  check_transform(m, wedge::loose_bounds(node_));
  return Solid(moved_node(node_, m));
}

Mesh Solid::mesh(const Tolerance& tol) const {
  switch (node_->kind) {
    case Node::Kind::Empty: return Mesh();
    // A leaf's own mesh, attributes as the leaf gives them (an imported mesh's seams and normals).
    case Node::Kind::Leaf: return within_triangle_budget(node_->leaf->mesh(tol), tol);
    case Node::Kind::Transform:
      if (Solid(node_->child).node_->kind == Node::Kind::Leaf) return Solid(node_->child).mesh(child_tolerance(*node_, tol)).transformed(node_->matrix);
      break;
    case Node::Kind::Boolean: break;
  }
  return evaluate_root(node_, tol)->mesh;
}

Mesh Solid::tagged_mesh(const Tolerance& tol) const { return evaluate_root(node_, tol)->mesh; }

std::vector<std::string> Solid::face_kinds(const Tolerance& tol) const { return evaluate_root(node_, tol)->kinds; }

std::vector<int> Solid::face_tags(const Tolerance& tol) const { return evaluate_root(node_, tol)->tags; }

std::vector<FaceSurface> Solid::face_surfaces(const Tolerance& tol) const { return evaluate_root(node_, tol)->surfaces; }

Mesh Solid::shaded_mesh(const Tolerance& tol) const {
  if (empty()) return Mesh();
  if (node_->kind == Node::Kind::Leaf && node_->leaf->kind() == "mesh") {
    Mesh m = node_->leaf->mesh(tol);
    if (!m.normals.empty()) {
      m.face_ids = evaluate_root(node_, tol)->mesh.face_ids;  // the same triangles, in order
      return m;
    }
  }
  auto e = evaluate_root(node_, tol);
  std::lock_guard<std::mutex> lock(e->shaded_mutex);
  if (!e->shaded) e->shaded = std::make_shared<const Mesh>(wedge::shaded_mesh(e->mesh, e->surfaces, e->corner_uv));
  return *e->shaded;
}

Solid Solid::tagged(int tag) const {
  if (tag < 0) fail("tagged: a tag is a number >= 0, got ", tag);
  auto n = std::make_shared<Node>(*node_);
  n->tag = tag;
  return Solid(std::shared_ptr<const Node>(n));
}

}  // namespace wedge
