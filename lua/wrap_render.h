// What the scene bindings share with render{}: materials read from Lua tables.
#pragma once
#include <lua.hpp>

#include <memory>

#include "render/render.h"

namespace wedge::lua {

// A material table {ambient=, diffuse=, specular=, emission=, shininess=, color=, texture=} at
// stack index idx, part of argument `arg`.
render::Material read_material(lua_State* L, int idx, int arg, std::shared_ptr<const render::Texture>& texture);

}  // namespace wedge::lua
