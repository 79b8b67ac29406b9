// The CSG tree's node and a node's evaluated result: private to csg/ (solid.cpp evaluates the
// tree, solid_boolean.cpp its boolean nodes, solid_queries.cpp answers the queries on results;
// solid_node.cpp holds the node's own functions).
// Not installed (named *_impl.h).
#pragma once
#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "csg/solid.h"

namespace wedge {

// A node's result at one tolerance.
struct Evaluated {
  Mesh mesh;                       // face_ids index kinds
  std::vector<std::string> kinds;  // surface kind per face id
  std::vector<int> tags;           // tag per face id (-1: none)
  std::vector<FaceSurface> surfaces;  // surface per face id, in this node's coordinates
  CornerUvs corner_uv;                // per triangle: its corners' parameters (or empty)
  std::mutex rebuild_mutex;
  std::shared_ptr<const RebuiltSolid> rebuilt;
  std::mutex shaded_mutex;
  std::shared_ptr<const Mesh> shaded;
  std::mutex mass_mutex;
  std::optional<MassProperties> mass;  // of a curved result (csg/curved_mass.h)
  std::vector<double> triangle_area;   // with it: each triangle's share of the area
};

struct BoundPoints;

struct Solid::Node {
  enum class Kind { Empty, Leaf, Transform, Boolean } kind = Kind::Empty;
  std::shared_ptr<const SolidLeaf> leaf;
  Mat4 matrix = Mat4::Identity();
  std::shared_ptr<const Node> child;
  BooleanOp op = BooleanOp::Union;
  // A boolean node's operands, in order. A part marked `splice` is a boolean node of the same op
  // whose own operands stand in its place: a chain s = s + b (repeated thousands of times by a
  // script) links each new node to the previous one in O(1) instead of copying the whole operand
  // list (which made building the chain quadratic in time and memory). operands() is the flat list,
  // made once, when the node is first evaluated or measured.
  struct Part {
    std::shared_ptr<const Node> node;
    bool splice = false;
  };
  std::vector<Part> parts;
  std::size_t size = 0;  // the length of operands()
  // The flat list, kept: for evaluation, which takes it many times.
  const std::vector<std::shared_ptr<const Node>>& operands() const;
  // The same list walked without keeping it (bounds and checks of an intermediate node of a chain
  // would otherwise each keep a copy).
  void for_each_operand(const std::function<void(const std::shared_ptr<const Node>&)>& f) const;
  int tag = -1;  // Solid::tagged
  std::string where;  // a boolean node: where a script made it ("model.lua:12"), for its errors
  // Levels from this node down to its deepest leaf (1 for a leaf). Evaluation, bounds and the
  // traversals recurse over the tree, so its depth is bounded where the tree is made.
  int depth = 1;
  // The evaluated results by (chordal, angular) tolerance. A slot's own mutex is held while it is
  // computed, so a second caller waits for the first instead of computing it again.
  struct Slot {
    std::mutex mutex;
    std::shared_ptr<Evaluated> value;
  };
  mutable std::mutex cache_mutex;
  mutable std::map<std::pair<double, double>, std::shared_ptr<Slot>> cache;
  mutable std::mutex flat_mutex;
  mutable std::shared_ptr<const std::vector<std::shared_ptr<const Node>>> flat;  // operands(), once made
  // A difference's or intersection's evaluated mesh as bounds need it (Solid::bounds, solid.cpp),
  // once made.
  mutable std::mutex bound_points_mutex;
  mutable std::shared_ptr<const BoundPoints> bound_points;

  Node() = default;
  Node(const Node& o)
      : kind(o.kind), leaf(o.leaf), matrix(o.matrix), child(o.child), op(o.op), parts(o.parts), size(o.size), tag(o.tag),
        where(o.where), depth(o.depth) {}
  ~Node();
};

// The tree's evaluation, shared by its two files.
namespace tree_detail {

using NodePtr = std::shared_ptr<const Solid::Node>;

// One evaluation from a public entry point: the control, and the count of boolean nodes for the
// progress callback.
struct Run {
  const EvalControl* control = nullptr;
  EvalOptions options;
  std::size_t total = 0;
  std::atomic<std::size_t> done{0};
  std::mutex stats_mutex;
  CancelCheck cancel;
  std::size_t max_crossings = kDefaultMaxCrossings;  // the engine's work budget (Tolerance::max_crossings)
  std::size_t max_triangles = Tolerance{}.max_triangles;  // the triangle budget of any mesh made

  void check() const {
    if (control && control->cancelled && control->cancelled()) throw Cancelled();
  }
  void add(double EvalStats::*field, double ms) {
    if (!control || !control->stats) return;
    std::lock_guard<std::mutex> lock(stats_mutex);
    control->stats->*field += ms;
  }
  void count(long EvalStats::*field) {
    if (!control || !control->stats) return;
    std::lock_guard<std::mutex> lock(stats_mutex);
    ++(control->stats->*field);
  }
  void widest(long operands) {
    if (!control || !control->stats) return;
    std::lock_guard<std::mutex> lock(stats_mutex);
    control->stats->widest = std::max(control->stats->widest, operands);
  }
  void boolean_done() {
    std::size_t d = ++done;
    if (control && control->progress) control->progress(std::min(d, total), total);
  }
};

// solid.cpp: the node's result at tol, from its cache slot or computed (once, however many callers).
std::shared_ptr<Evaluated> evaluate(const NodePtr& n, const Tolerance& tol, Run& run);
// solid.cpp: the result of the tree under n at tol, one evaluation from a public entry point
// (the installed control, the budgets of tol); the queries (solid_queries.cpp) start here.
std::shared_ptr<Evaluated> evaluate_root(const NodePtr& n, const Tolerance& tol);
// The tolerance a transform node asks of its child: finer by the largest stretch it applies.
Tolerance child_tolerance(const Solid::Node& n, const Tolerance& tol);
// The box around b's eight corners moved by m.
Box3 transformed_box(const Box3& b, const Mat4& m);
// The installed EvalControl (set_eval_control), or nullptr.
const EvalControl* eval_control();
double elapsed_ms(std::chrono::steady_clock::time_point t0);

// solid_boolean.cpp: a boolean node's result from its operands' (pruned, grouped, balanced).
std::shared_ptr<Evaluated> evaluate_boolean(const Solid::Node& n, const Tolerance& tol, Run& run);

}  // namespace tree_detail

}  // namespace wedge
