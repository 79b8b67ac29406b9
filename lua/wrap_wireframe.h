// The Lua Wireframe value: a wireframe model, polylines and no faces (wrap_wireframe.cpp).
#pragma once
#include <lua.hpp>

#include <string>
#include <vector>

#include "render/render.h"

namespace wedge::lua {

struct Wireframe {
  std::vector<std::vector<Point3>> lines;
  render::Vec4f color;
};

const Wireframe* test_wireframe(lua_State* L, int idx);  // nullptr if not a Wireframe
// Writes the polylines as an OBJ file ("v" and "l" records), whole or not at all; throws
// wedge::Error naming the path (also for an extension other than .obj).
void write_wireframe_obj(const Wireframe& w, const std::string& path);

}  // namespace wedge::lua
