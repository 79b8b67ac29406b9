// The CSG tree's node and a node's evaluated result: private to csg/ (solid.cpp evaluates the
// tree; solid_node.cpp holds the node's own functions). Not installed (named *_impl.h).
#pragma once
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
};

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

  Node() = default;
  Node(const Node& o)
      : kind(o.kind), leaf(o.leaf), matrix(o.matrix), child(o.child), op(o.op), parts(o.parts), size(o.size), tag(o.tag),
        depth(o.depth) {}
  ~Node();
};

}  // namespace wedge
