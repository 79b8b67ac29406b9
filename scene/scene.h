// Scenes (hierarchical models; API.md "Scenes", the Lua group{}/instance()/array{} of lua/): groups
// with a local transform whose children are groups or geometry leaves. A node may sit under several
// parents, which is what an instance is: the prototype is shared, so changing it changes every
// instance; copy() makes a new tree. A scene is walked depth first with a matrix stack: entering a
// node pushes M_parent * M_local, leaving it pops, so each leaf is placed by
// M_world = M_root * ... * M_parent * M_local.
//
//   auto arm = scene::group(rotate_z(30), "arm");          // (a Mat4{} would be uninitialised: use group("name"))
//   scene::add(*arm, scene::part(brep_solid(box(Vec3(1, 1, 4)))));
//   auto root = scene::group();
//   scene::add(*root, arm);
//   scene::add(*root, scene::array(arm, 3, Vec3(5, 0, 0)));
//   Box3 b = scene::bounds(*root, Tolerance{});  render::write_png("s.png", scene::picture(*root, ro, tol));
//
// Bad input (a cycle, a singular or projective transform, an empty scene, a count of 0) throws
// wedge::Error with a message naming it.
#pragma once
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "csg/solid.h"
#include "render/render.h"

namespace wedge::scene {

// Geometry at the bottom of a scene: a Solid (tessellated when drawn, at the tolerance of the
// time) or a fixed mesh, with its material (none: the nearest group's, or the default).
struct Leaf {
  std::optional<Solid> solid;
  Mesh mesh;
  std::optional<render::Material> material;
  std::shared_ptr<const render::Texture> texture;
};

struct Node {
  Mat4 transform = Mat4::Identity();
  std::string name;
  std::optional<render::Material> material;  // inherited by leaves without their own
  std::shared_ptr<const render::Texture> texture;
  std::vector<std::shared_ptr<Node>> children;
  std::shared_ptr<const Leaf> leaf;  // set on leaf nodes only (no children)
  // The most levels above this node on any path down to it from a node without parents, as add()
  // has seen them (kept by add(), array() and copy(); a parent that dies is not forgotten). It
  // lets add() see the depth of a chain built from the top, each new group added under the last.
  std::size_t above = 0;

  Node() = default;
  Node(const Node&) = default;
  Node& operator=(const Node&) = default;
  // Releases the children without recursion, so that a chain of a million nested groups (which
  // add() alone cannot see: it is built from the bottom) does not overflow the stack when it dies.
  ~Node();
};
using NodePtr = std::shared_ptr<Node>;

// --- building ---
// `transform` must be finite, affine (last row 0 0 0 1) and invertible; `what` names it in errors.
Mat4 checked_transform(const Mat4& m, const std::string& what = "transform");
NodePtr group(const Mat4& transform = Mat4::Identity(), std::string name = {});
NodePtr group(std::string name);  // a named group under the identity
// A leaf node holding a solid (not the empty one; the Lua bindings also refuse a boolean whose
// result is empty, which needs its evaluation) or a mesh with triangles.
NodePtr part(Solid solid, std::optional<render::Material> material = std::nullopt,
             std::shared_ptr<const render::Texture> texture = nullptr);
NodePtr part(Mesh mesh, std::optional<render::Material> material = std::nullopt,
             std::shared_ptr<const render::Texture> texture = nullptr);
// Adds `child` under `parent` (shared, not copied); a child that reaches `parent` would make a
// cycle and is refused, as is a child whose deepest level, counted from the top of the deepest
// path down to `parent`, would be beyond 1000.
void add(Node& parent, NodePtr child);
// A node as errors and Lua's tostring name it: "Group('arm', 2 children)", "Group(1 child)", "a part".
std::string describe(const Node& node);
// A node that shares `prototype` under a transform of its own.
NodePtr instance(NodePtr prototype, const Mat4& transform = Mat4::Identity(), std::string name = {});
// `count` instances of `prototype`, the k-th (from 0) translated by k * step. count in 1..100000.
NodePtr array(NodePtr prototype, int count, const Vec3& step);
// `count` instances of `prototype`, each moved `radius` out from the axis through `center` (towards
// x perpendicular to the axis, or y if the axis is x) and turned about it by k * angle / count
// (k * angle / (count - 1) when angle < 360, so that both ends are used). angle in (0, 360].
NodePtr radial_array(NodePtr prototype, int count, double radius, const Vec3& axis = Vec3(0, 0, 1),
                     const Point3& center = Point3(0, 0, 0), double angle = 360);
// A new tree equal to `root` now: later changes to `root` or its groups do not reach it (leaves,
// immutable geometry, are shared).
NodePtr copy(const NodePtr& root);

// --- traversal and queries ---
// One leaf as the traversal reaches it.
struct Occurrence {
  const Leaf* leaf = nullptr;
  Mat4 world = Mat4::Identity();
  std::string symbol;  // the nearest name on the way down to the leaf, or "solid"/"mesh"
  std::string path;    // the names on the way down, "/"-separated ("" for unnamed nodes)
  render::Material material;
  std::shared_ptr<const render::Texture> texture;
};
// Every leaf under `root`, depth first in child order. Throws for an empty scene, one of more
// than a million leaves, or one deeper than 1000 levels.
std::vector<Occurrence> flatten(const Node& root);
// A leaf's mesh at `tol` in its own coordinates (a solid with per-face shading normals if
// `for_render`).
Mesh leaf_mesh(const Leaf& leaf, const Tolerance& tol, bool for_render);
// Every leaf's mesh in world coordinates, merged (each leaf tessellated once).
Mesh mesh(const Node& root, const Tolerance& tol);
Box3 bounds(const Node& root, const Tolerance& tol);

// The course's instance table: one row per leaf, in traversal order, with the world matrix split
// as translation * rotation * scale (rotation in degrees in matrix.euler's order Rz * Ry * Rx,
// scale negative in x for a mirror, and whether a shear remains that the three do not show).
struct InstanceRow {
  std::string symbol, path;
  Vec3 translation, rotation, scale;
  bool shear = false;
  Mat4 world;
};
std::vector<InstanceRow> instance_table(const Node& root);

// --- drawing ---
// The draw items of a scene for render::render_scene / render_drawing: one per leaf occurrence,
// placed by its world matrix, each distinct leaf meshed once (textured leaves get box uvs if
// their mesh has none). The items point into `meshes`. `step` is called once per occurrence
// (a progress hook).
//
// A solid whose faces carry tags of several solids (Solid::tagged: a boolean of solids with
// materials of their own) is drawn in pieces, one per tag, each in tag_material(tag) where that
// gives one (else in the leaf's material), when `tag_material` is set.
struct Drawable {
  std::deque<Mesh> meshes;
  std::vector<render::DrawItem> items;
};
using OwnMaterial = std::pair<render::Material, std::shared_ptr<const render::Texture>>;
using TagMaterial = std::function<std::optional<OwnMaterial>(int tag)>;
Drawable draw_items(const Node& root, const Tolerance& tol, const std::function<void()>& step = {},
                    const TagMaterial& tag_material = {});
// A solid's shading mesh (Solid::shaded_mesh: normals from its faces' surfaces) split by face tag
// (Solid::face_tags): one mesh per tag, -1 for untagged faces, each with its own vertices.
std::map<int, Mesh> split_by_tags(const Solid& solid, const Tolerance& tol);
// The scene drawn with `options` (options.camera as given; render::named_view(..., bounds) fits one).
render::Image picture(const Node& root, const render::RenderOptions& options, const Tolerance& tol);

}  // namespace wedge::scene
