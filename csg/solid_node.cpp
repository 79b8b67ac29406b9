// The CSG tree node's own functions (csg/solid_impl.h): its flat operand list and its release.
#include "csg/solid_impl.h"

namespace wedge {

Solid::Node::~Node() {
  // A chain s = s + b, thousands of links long, holds each link by the next: released by the
  // destructors' recursion it would overflow the stack. The links this node holds alone are taken
  // over and released one by one here instead.
  // So are the children of transforms (a chain s = (s - b):translate(...)).
  std::vector<std::shared_ptr<const Node>> pending;
  auto take = [&](Node& from) {
    for (Part& p : from.parts)
      if (p.node && p.node.use_count() == 1) pending.push_back(std::move(p.node));
    if (from.child && from.child.use_count() == 1) pending.push_back(std::move(from.child));
  };
  take(*this);
  while (!pending.empty()) {
    std::shared_ptr<const Node> n = std::move(pending.back());
    pending.pop_back();
    if (n.use_count() == 1) take(const_cast<Node&>(*n));  // ours alone: nobody else sees it
  }
}

void Solid::Node::for_each_operand(const std::function<void(const std::shared_ptr<const Node>&)>& f) const {
  {
    std::shared_ptr<const std::vector<std::shared_ptr<const Node>>> made;
    {
      std::lock_guard<std::mutex> lock(flat_mutex);
      made = flat;
    }
    if (made) {
      for (const auto& o : *made) f(o);
      return;
    }
  }
  // Depth first through the spliced parts, with a stack of our own: a chain is as long as the
  // script's loop. A spliced node whose list is already made gives it whole.
  std::vector<std::pair<const Node*, std::size_t>> stack{{this, 0}};
  while (!stack.empty()) {
    const Node* n = stack.back().first;
    const std::size_t i = stack.back().second++;
    if (i == n->parts.size()) {
      stack.pop_back();
      continue;
    }
    const Part& p = n->parts[i];
    if (!p.splice) {
      f(p.node);
      continue;
    }
    std::shared_ptr<const std::vector<std::shared_ptr<const Node>>> made;
    {
      std::lock_guard<std::mutex> lock(p.node->flat_mutex);
      made = p.node->flat;
    }
    if (made)
      for (const auto& o : *made) f(o);
    else
      stack.push_back({p.node.get(), 0});
  }
}

const std::vector<std::shared_ptr<const Solid::Node>>& Solid::Node::operands() const {
  std::lock_guard<std::mutex> lock(flat_mutex);
  if (!flat) {
    auto out = std::make_shared<std::vector<std::shared_ptr<const Node>>>();
    out->reserve(size);
    for (const Part& p : parts) {
      if (!p.splice) out->push_back(p.node);
      else p.node->for_each_operand([&](const std::shared_ptr<const Node>& o) { out->push_back(o); });
    }
    // A leaf copy placed otherwise than by its symmetry stands here as its canonical twin (the
    // same solid: csg/brep_leaf.h), made once with this list.
    for (auto& o : *out)
      if (o->kind == Kind::Leaf)
        if (auto c = o->leaf->canonical()) {
          auto twin = std::make_shared<Node>();
          twin->kind = Kind::Leaf;
          twin->leaf = std::move(c);
          twin->tag = o->tag;
          o = std::move(twin);
        }
    flat = std::move(out);
  }
  return *flat;
}

}  // namespace wedge
