// Scenes: building, the depth-first traversal with a matrix stack, the instance table and the draw
// items (see scene.h for the model).
#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace wedge::scene {

namespace {
constexpr std::size_t kMaxLeaves = 1000000;
constexpr std::size_t kMaxDepth = 1000;
constexpr int kMaxCount = 100000;

// Whether `target` is `from` or lies under it.
bool reaches(const Node* from, const Node* target) {
  std::vector<const Node*> todo{from};
  std::unordered_set<const Node*> seen;
  while (!todo.empty()) {
    const Node* n = todo.back();
    todo.pop_back();
    if (n == target) return true;
    if (!seen.insert(n).second) continue;
    for (const auto& c : n->children) todo.push_back(c.get());
  }
  return false;
}

// The deepest level of `from` and its descendants with `from` at `level` (1 for a node without
// parents), or the first level found beyond kMaxDepth, by a traversal that visits each node again
// only when it is reached deeper than before.
std::size_t deepest(const Node* from, std::size_t level) {
  std::vector<std::pair<const Node*, std::size_t>> todo{{from, level}};
  std::unordered_map<const Node*, std::size_t> seen;
  std::size_t out = level;
  while (!todo.empty()) {
    auto [n, depth] = todo.back();
    todo.pop_back();
    out = std::max(out, depth);
    if (depth > kMaxDepth) return depth;
    auto [it, fresh] = seen.try_emplace(n, depth);
    if (!fresh) {
      if (it->second >= depth) continue;
      it->second = depth;
    }
    for (const auto& c : n->children) todo.emplace_back(c.get(), depth + 1);
  }
  return out;
}

// Records that `child` now has `above` levels over it (at least), and so its descendants one more
// each: Node::above grows where a path is longer than those seen, and the walk stops where it
// does not (every child already has more levels above it than its parent).
void lower(Node& child, std::size_t above) {
  std::vector<std::pair<Node*, std::size_t>> todo{{&child, above}};
  while (!todo.empty()) {
    auto [n, a] = todo.back();
    todo.pop_back();
    if (n->above >= a) continue;
    n->above = a;
    for (const auto& c : n->children) todo.emplace_back(c.get(), a + 1);
  }
}

// Refuses a prototype that would sit at `level` (array: level 3, under the array and a copy) with
// its deepest level beyond kMaxDepth.
void check_prototype_depth(const NodePtr& prototype, std::size_t level, const char* fn) {
  if (const std::size_t d = deepest(prototype.get(), level); d > kMaxDepth)
    fail(fn, ": the scene would be deeper than ", kMaxDepth, " levels: ", describe(*prototype), " would reach level ", d,
         " under the copies");
}

void check_count(int count, const char* fn) {
  if (count < 1 || count > kMaxCount) fail(fn, ": count must be within 1..", kMaxCount, ", got ", count);
}

// A part is placed by the product of the transforms on the way down to it, each checked alone
// when it was set; the product is checked here by the rule a solid's transform is: within the
// coordinates a solid may have (+-1e100), not singular, not shrinking volumes below 1e-300.
// (group{transform=matrix.translate(1e300, 0, 0)} placed a box of zero width there, and two nested
// scale(1e200) gave a world matrix of infinities: table() said scale nan, render "singular".)
void check_world(const Occurrence& o, std::size_t k, std::unordered_map<const Leaf*, Box3>& boxes) {
  auto [it, fresh] = boxes.try_emplace(o.leaf);
  if (fresh) it->second = o.leaf->solid ? o.leaf->solid->loose_bounds() : o.leaf->mesh.bounds();
  try {
    check_transform(o.world, it->second, "its world matrix (the product of the transforms above it)");
  } catch (const Error& e) {
    fail("part ", k, " of the scene ('", o.path.empty() ? o.symbol : o.path, "'): ", e.what());
  }
}

// `depth` counts from 1 at the root, as flatten() does (from 0, a scene of 1001 levels was
// copied and then refused by every other use).
NodePtr deep_copy(const NodePtr& n, std::size_t depth) {
  if (depth > kMaxDepth) fail("copy: the scene is deeper than ", kMaxDepth, " levels");
  auto c = std::make_shared<Node>(*n);
  c->above = depth - 1;  // the copy is a tree: one path down to each node
  for (auto& child : c->children) child = deep_copy(child, depth + 1);
  return c;
}
}  // namespace

Mat4 checked_transform(const Mat4& m, const std::string& what) {
  if (!m.allFinite()) fail(what, " must be finite");
  if (m(3, 0) != 0 || m(3, 1) != 0 || m(3, 2) != 0 || m(3, 3) != 1)
    fail(what, " must be affine (last row 0 0 0 1); a projection cannot place a part");
  // Singular and underflowing volumes by the rule solids use (a uniform scale(1e-101) was called
  // singular here, with |det| > 1e-300 as the test); the box of each part is checked where the
  // scene is used (flatten), against its world matrix.
  check_transform(m, Box3(), what);
  const Vec3 t = m.block<3, 1>(0, 3);
  if (!(t.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
    std::ostringstream by;  // 6 digits: 1e+300, not 1.0000000000000001e+300
    by << "{" << t.x() << ", " << t.y() << ", " << t.z() << "}";
    fail(what, " moves by ", by.str(), ", beyond +-", kMaxCoordinate, " (the coordinates a solid may have)");
  }
  return m;
}

NodePtr group(const Mat4& transform, std::string name) {
  auto node = std::make_shared<Node>();
  node->transform = checked_transform(transform);
  node->name = std::move(name);
  return node;
}

NodePtr group(std::string name) { return group(Mat4::Identity(), std::move(name)); }

NodePtr part(Solid solid, std::optional<render::Material> material, std::shared_ptr<const render::Texture> texture) {
  if (solid.empty()) fail("the empty solid cannot be part of a scene");
  auto leaf = std::make_shared<Leaf>();
  leaf->solid = std::move(solid);
  leaf->material = std::move(material);
  leaf->texture = std::move(texture);
  auto node = std::make_shared<Node>();
  node->leaf = std::move(leaf);
  return node;
}

NodePtr part(Mesh mesh, std::optional<render::Material> material, std::shared_ptr<const render::Texture> texture) {
  if (mesh.empty()) fail("a scene part needs triangles; this mesh has none");
  auto leaf = std::make_shared<Leaf>();
  leaf->mesh = std::move(mesh);
  leaf->material = std::move(material);
  leaf->texture = std::move(texture);
  auto node = std::make_shared<Node>();
  node->leaf = std::move(leaf);
  return node;
}

std::string describe(const Node& node) {
  if (node.leaf) return "a part";
  const std::size_t n = node.children.size();
  return "Group(" + (node.name.empty() ? "" : "'" + node.name + "', ") + std::to_string(n) + (n == 1 ? " child)" : " children)");
}

void add(Node& parent, NodePtr child) {
  if (!child) fail("add: the child is null");
  if (parent.leaf) fail("add: a part (leaf) cannot hold children; put both in a group");
  if (child.get() == &parent)
    fail("the group would contain itself (a scene must have no cycle): ", describe(parent), " cannot be added to itself");
  if (reaches(child.get(), &parent))
    fail("the group would contain itself (a scene must have no cycle): ", describe(parent), " is already inside ",
         describe(*child), ", which cannot be added to it");
  // The levels above `parent` count as well as those below `child`: built from the top (a new
  // group added under the last one, a million times), the scene passed here and then every use
  // of it failed.
  if (const std::size_t d = deepest(child.get(), parent.above + 2); d > kMaxDepth)
    fail("the scene would be deeper than ", kMaxDepth, " levels: ", describe(*child), " added to ", describe(parent),
         " (at level ", parent.above + 1, ") would reach level ", d);
  lower(*child, parent.above + 1);
  parent.children.push_back(std::move(child));
}

Node::~Node() {
  std::vector<NodePtr> pending = std::move(children);
  while (!pending.empty()) {
    NodePtr n = std::move(pending.back());
    pending.pop_back();
    // The last owner of n takes its children over, so n dies with none.
    if (n.use_count() == 1)
      for (auto& c : n->children) pending.push_back(std::move(c));
  }
}

NodePtr instance(NodePtr prototype, const Mat4& transform, std::string name) {
  if (!prototype) fail("instance: the prototype is null");
  auto node = group(transform, std::move(name));
  add(*node, std::move(prototype));
  return node;
}

NodePtr array(NodePtr prototype, int count, const Vec3& step) {
  if (!prototype) fail("array: the prototype is null");
  check_prototype_depth(prototype, 3, "array");
  check_count(count, "array");
  if (!step.allFinite()) fail("array: step must be finite");
  if (!(double(count - 1) * step.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
    std::ostringstream by;
    by << "{" << step.x() << ", " << step.y() << ", " << step.z() << "}";
    fail("array: step ", by.str(), " puts copy ", count, " beyond +-", kMaxCoordinate);
  }
  lower(*prototype, 2);
  auto node = std::make_shared<Node>();
  for (int k = 0; k < count; ++k) {
    auto inst = std::make_shared<Node>();
    inst->above = 1;
    inst->transform = translate(double(k) * step);
    inst->children.push_back(prototype);
    node->children.push_back(std::move(inst));
  }
  return node;
}

NodePtr radial_array(NodePtr prototype, int count, double radius, const Vec3& axis, const Point3& center, double angle) {
  if (!prototype) fail("radial_array: the prototype is null");
  check_prototype_depth(prototype, 3, "radial_array");
  check_count(count, "radial_array");
  if (!(radius >= 0) || !std::isfinite(radius)) fail("radial_array: radius must be finite and not negative, got ", radius);
  if (!axis.allFinite() || axis.norm() == 0) fail("radial_array: axis must be finite and non-zero");
  if (!center.allFinite()) fail("radial_array: center must be finite");
  // Within the coordinates a solid may have, as array's step is (a radius of 1e300 put every
  // copy there, flattened).
  if (!(radius + center.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
    std::ostringstream where;
    where << "radius " << radius << " about center {" << center.x() << ", " << center.y() << ", " << center.z() << "}";
    fail("radial_array: ", where.str(), " puts the copies beyond +-", kMaxCoordinate);
  }
  if (!(angle > 0) || angle > 360) fail("radial_array: angle must be within 0..360 (above 0), got ", angle);
  const Vec3 a = axis.normalized();
  Vec3 out = Vec3::UnitX() - a.x() * a;
  if (out.norm() < 1e-9) out = Vec3::UnitY() - a.y() * a;
  out.normalize();
  const double step = angle >= 360 ? 360.0 / count : count > 1 ? angle / (count - 1) : 0;
  lower(*prototype, 2);
  auto node = std::make_shared<Node>();
  for (int k = 0; k < count; ++k) {
    auto inst = std::make_shared<Node>();
    inst->above = 1;
    inst->transform = rotate(k * step, a, center) * translate(Vec3(center) + radius * out);
    inst->children.push_back(prototype);
    node->children.push_back(std::move(inst));
  }
  return node;
}

NodePtr copy(const NodePtr& root) {
  if (!root) fail("copy: the scene is null");
  return deep_copy(root, 1);
}

std::vector<Occurrence> flatten(const Node& root) {
  std::vector<Occurrence> out;
  std::unordered_map<const Leaf*, Box3> boxes;  // check_world's, each leaf's once
  // The traversal's stacks, one entry per node on the way down: the node and the next child to
  // visit, its world matrix (the matrix stack), its material and its path.
  struct Frame {
    const Node* node;
    std::size_t next;
    Mat4 world;
    const render::Material* material;
    std::shared_ptr<const render::Texture> texture;
    std::string path, symbol;
  };
  auto enter = [](const Node& n, const Frame* parent) {
    Frame f{&n, 0, n.transform, nullptr, nullptr, "", ""};
    if (parent) f.world = parent->world * n.transform;  // M_world = M_parent * M_local
    f.material = n.material ? &*n.material : parent ? parent->material : nullptr;
    f.texture = n.material ? n.texture : parent ? parent->texture : nullptr;
    const std::string parent_path = parent ? parent->path : "";
    f.path = n.name.empty() ? parent_path : parent_path.empty() ? n.name : parent_path + "/" + n.name;
    f.symbol = n.name.empty() ? (parent ? parent->symbol : "") : n.name;
    return f;
  };
  std::vector<Frame> stack;
  stack.push_back(enter(root, nullptr));
  while (!stack.empty()) {
    Frame& top = stack.back();
    if (const Leaf* leaf = top.node->leaf.get()) {
      Occurrence o;
      o.leaf = leaf;
      o.world = top.world;
      o.path = top.path;
      o.symbol = !top.symbol.empty() ? top.symbol : leaf->solid ? "solid" : "mesh";
      check_world(o, out.size() + 1, boxes);
      if (leaf->material) o.material = *leaf->material, o.texture = leaf->texture;
      else if (top.material) o.material = *top.material, o.texture = top.texture;
      out.push_back(std::move(o));
      if (out.size() > kMaxLeaves) fail("the scene has more than ", kMaxLeaves, " parts");
      stack.pop_back();
      continue;
    }
    if (top.next == top.node->children.size()) {
      stack.pop_back();  // leaving the node: pop its matrix
      continue;
    }
    const Node& child = *top.node->children[top.next++];
    if (stack.size() >= kMaxDepth) fail("the scene is deeper than ", kMaxDepth, " levels");
    Frame f = enter(child, &stack.back());
    stack.push_back(std::move(f));
  }
  if (out.empty()) fail("the scene is empty: add a solid to a group first");
  return out;
}

Mesh leaf_mesh(const Leaf& leaf, const Tolerance& tol, bool for_render) {
  if (!leaf.solid) return leaf.mesh;
  Mesh m = leaf.solid->mesh(tol);
  return for_render ? m.with_face_normals() : m;
}

namespace {
// Each leaf's mesh once (a leaf placed 100000 times by an array is tessellated once), found by
// the leaf in a hash map: a scene of many distinct parts costs one lookup per part, not a scan.
class LeafMeshes {
 public:
  explicit LeafMeshes(const Tolerance& tol) : tol_(tol) {}
  const Mesh& of(const Leaf* leaf) {
    auto it = meshes_.find(leaf);
    if (it == meshes_.end()) it = meshes_.emplace(leaf, leaf_mesh(*leaf, tol_, false)).first;
    return it->second;
  }

 private:
  Tolerance tol_;
  std::unordered_map<const Leaf*, Mesh> meshes_;
};
}  // namespace

Mesh mesh(const Node& root, const Tolerance& tol) {
  const std::vector<Occurrence> parts = flatten(root);
  LeafMeshes meshes(tol);
  // The merged mesh holds every occurrence's triangles: within the triangle budget, checked
  // before anything is copied (array{sphere(1), count=100000} would be 2e8 triangles).
  double total = 0;
  for (const auto& occ : parts) total += double(meshes.of(occ.leaf).triangles.size());
  if (!(total <= double(tol.max_triangles)))
    fail("the scene would be one mesh of ", total, " triangles (", parts.size(), " parts), more than the budget of ",
         tol.max_triangles,
         ": use fewer copies, a larger tolerance, or raise the budget with tolerance{max_triangles=N}");
  Mesh all;
  for (const auto& occ : parts) all.append(meshes.of(occ.leaf).transformed(occ.world));
  return all;
}

Box3 bounds(const Node& root, const Tolerance& tol) {
  // A solid's own bounds, not its mesh's: a group holding sphere(1) reached x = 0.99271 at
  // tolerance 0.01 where the sphere reaches 1. Placed by its world matrix (Solid::bounds(m): a
  // turned solid's points are turned, not its box: a turned box of a sphere is too big, and one
  // of a boolean result was 41-65 % too big). A mesh part: its points moved by the transform.
  LeafMeshes meshes(tol);
  Box3 box;
  for (const auto& occ : flatten(root)) {
    if (occ.leaf->solid) {
      const Box3 b = occ.leaf->solid->bounds(occ.world);
      if (!b.empty()) box.extend(b.min), box.extend(b.max);
      continue;
    }
    for (const Point3& p : meshes.of(occ.leaf).positions) box.extend(apply_point(occ.world, p));
  }
  return box;
}

std::vector<InstanceRow> instance_table(const Node& root) {
  std::vector<InstanceRow> rows;
  for (const Occurrence& occ : flatten(root)) {
    InstanceRow row;
    row.symbol = occ.symbol;
    row.path = occ.path;
    row.world = occ.world;
    const Mat4& m = occ.world;
    row.translation = m.block<3, 1>(0, 3);
    const Mat3 a = m.block<3, 3>(0, 0);
    row.scale = Vec3(a.col(0).stableNorm(), a.col(1).stableNorm(), a.col(2).stableNorm());  // 1e-200 squared underflows
    if (a.determinant() < 0) row.scale.x() = -row.scale.x();
    Mat3 r = a;
    for (int k = 0; k < 3; ++k) r.col(k) /= row.scale[k];
    row.shear = (r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-9;
    constexpr double deg = 180.0 / 3.14159265358979323846;
    const double sy = std::clamp(-r(2, 0), -1.0, 1.0);
    if (std::abs(sy) < 1 - 1e-12) {
      row.rotation = Vec3(std::atan2(r(2, 1), r(2, 2)), std::asin(sy), std::atan2(r(1, 0), r(0, 0))) * deg;
    } else {  // gimbal lock: y = +-90; put the whole turn in x
      row.rotation = Vec3(std::atan2(-r(1, 2), r(1, 1)), std::asin(sy), 0) * deg;
    }
    for (int k = 0; k < 3; ++k)
      if (std::abs(row.rotation[k]) < 1e-12) row.rotation[k] = 0;
    rows.push_back(std::move(row));
  }
  return rows;
}

std::map<int, Mesh> split_by_tags(const Solid& solid, const Tolerance& tol) {
  // The shading mesh (normals from the faces' surfaces; face ids as tagged_mesh's).
  const Mesh mesh = solid.shaded_mesh(tol);
  const bool normals = mesh.normals.size() == mesh.positions.size();
  const std::vector<int> tags = solid.face_tags(tol);
  std::map<int, Mesh> parts;
  std::map<int, std::unordered_map<std::uint32_t, std::uint32_t>> index;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const int tag = tags.at(static_cast<std::size_t>(mesh.face_ids[t]));
    Mesh& part = parts[tag];
    auto& ix = index[tag];
    std::uint32_t v[3];
    for (int k = 0; k < 3; ++k) {
      auto [it, fresh] = ix.emplace(mesh.triangles[t][k], static_cast<std::uint32_t>(part.positions.size()));
      if (fresh) {
        part.positions.push_back(mesh.positions[mesh.triangles[t][k]]);
        if (normals) part.normals.push_back(mesh.normals[mesh.triangles[t][k]]);
      }
      v[k] = it->second;
    }
    part.add_triangle(v[0], v[1], v[2], mesh.face_ids[t]);
  }
  return parts;
}

Drawable draw_items(const Node& root, const Tolerance& tol, const std::function<void()>& step, const TagMaterial& tag_material) {
  Drawable d;
  // A leaf's pieces: its whole mesh, or one mesh per face tag with the tag's own material.
  struct Piece {
    const Mesh* mesh;
    const OwnMaterial* own;  // nullptr: the occurrence's material
  };
  struct Made {
    const Leaf* leaf;
    bool textured;
    std::vector<Piece> pieces;
  };
  std::deque<Made> made;
  std::map<std::pair<const Leaf*, bool>, std::size_t> made_index;  // (leaf, textured) -> made[i]: one lookup a part
  std::deque<OwnMaterial> owns;
  auto add_mesh = [&](Mesh m, bool textured) {
    if (textured && m.uvs.empty()) m = render::with_uv_mapping(m, render::UvMapping::Box);
    d.meshes.push_back(std::move(m));
    return &d.meshes.back();
  };
  for (const Occurrence& occ : flatten(root)) {
    if (step) step();
    const bool textured = occ.texture != nullptr;
    const Made* found = nullptr;
    if (auto it = made_index.find({occ.leaf, textured}); it != made_index.end()) found = &made[it->second];
    if (!found) {
      Made m{occ.leaf, textured, {}};
      std::map<int, Mesh> parts;
      if (occ.leaf->solid && tag_material) {
        parts = split_by_tags(*occ.leaf->solid, tol);
        if (parts.size() < 2) parts.clear();
      }
      for (auto& [tag, part] : parts) {
        const OwnMaterial* own = nullptr;
        if (tag >= 0)
          if (std::optional<OwnMaterial> o = tag_material(tag)) {
            owns.push_back(std::move(*o));
            own = &owns.back();
          }
        m.pieces.push_back({add_mesh(part.with_face_normals(), own ? own->second != nullptr : textured), own});
      }
      if (m.pieces.empty()) m.pieces.push_back({add_mesh(leaf_mesh(*occ.leaf, tol, true), textured), nullptr});
      made_index.emplace(std::make_pair(occ.leaf, textured), made.size());
      made.push_back(std::move(m));
      found = &made.back();
    }
    for (const Piece& p : found->pieces) {
      render::DrawItem item;
      item.mesh = p.mesh;
      item.material = p.own ? p.own->first : occ.material;
      item.texture = p.own ? p.own->second : occ.texture;
      item.transform = occ.world;
      d.items.push_back(std::move(item));
    }
  }
  // The renderer goes through every placed triangle: within the triangle budget, as one merged
  // mesh is (mesh()), or an array of 100000 spheres runs out of memory in the rasterizer.
  double total = 0;
  for (const render::DrawItem& item : d.items)
    if (item.mesh) total += double(item.mesh->triangles.size());
  if (!(total <= double(tol.max_triangles)))
    fail("the scene would draw ", total, " triangles (", d.items.size(), " placed meshes), more than the budget of ",
         tol.max_triangles,
         ": use fewer copies, a larger tolerance, or raise the budget with tolerance{max_triangles=N}");
  return d;
}

render::Image picture(const Node& root, const render::RenderOptions& options, const Tolerance& tol) {
  const Drawable d = draw_items(root, tol);
  return render::render_scene(d.items, options);
}

}  // namespace wedge::scene
