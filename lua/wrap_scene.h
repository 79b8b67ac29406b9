// Lua bindings of scenes (API.md "Scenes"); the model and its traversal are scene/scene.h's, which
// the C++ API shares.
#pragma once
#include <lua.hpp>

#include "scene/scene.h"

namespace wedge::lua {

using SceneNode = scene::Node;
using SceneLeaf = scene::Leaf;
using SceneOccurrence = scene::Occurrence;

// The scene group at idx, or nullptr.
const SceneNode* test_scene(lua_State* L, int idx);

}  // namespace wedge::lua
