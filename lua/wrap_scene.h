// Scenes (hierarchical models, API.md "Scenes"): groups with a local transform, whose children are
// groups or geometry leaves. A node may sit under several parents (that is what an instance is:
// the prototype is shared, so changing it changes every instance); a copy is a new tree. Scenes
// are walked depth first with a matrix stack: entering a node pushes M_parent * M_local, leaving
// it pops, so each leaf is drawn with M_world = M_root * ... * M_parent * M_local.
#pragma once
#include <lua.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "csg/solid.h"
#include "render/render.h"

namespace wedge::lua {

// Geometry at the bottom of a scene: a Solid (tessellated when drawn, at the tolerance of the
// time) or a fixed mesh (a surface or mesh table, tessellated when added), with its material.
struct SceneLeaf {
  std::optional<Solid> solid;
  Mesh mesh;
  std::optional<render::Material> material;
  std::shared_ptr<const render::Texture> texture;
};

struct SceneNode {
  Mat4 transform = Mat4::Identity();
  std::string name;
  std::optional<render::Material> material;  // inherited by leaves without their own
  std::shared_ptr<const render::Texture> texture;
  std::vector<std::shared_ptr<SceneNode>> children;
  std::shared_ptr<const SceneLeaf> leaf;  // set on leaf nodes only (no children)
};

// One leaf as the traversal reaches it.
struct SceneOccurrence {
  const SceneLeaf* leaf = nullptr;
  Mat4 world = Mat4::Identity();
  std::string symbol;  // the nearest name on the way down to the leaf, or "solid"/"mesh"
  std::string path;    // the names on the way down, "/"-separated ("" for unnamed nodes)
  render::Material material;
  std::shared_ptr<const render::Texture> texture;
};

// The scene group at idx, or nullptr.
const SceneNode* test_scene(lua_State* L, int idx);
// Every leaf under `root`, depth first in child order. Throws wedge::Error for an empty scene or
// one of more than a million leaves.
std::vector<SceneOccurrence> flatten(const SceneNode& root);
// A leaf's mesh at `tol` in its own coordinates (a solid with per-face shading normals if
// `for_render`).
Mesh leaf_mesh(const SceneLeaf& leaf, const Tolerance& tol, bool for_render);

}  // namespace wedge::lua
