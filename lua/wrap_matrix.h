// The Matrix userdata, for other bindings that take or return 4x4 transforms (s:transform(m)).
#pragma once
#include <lua.hpp>

#include "kernel/transform.h"

namespace wedge::lua {
const Mat4* test_matrix(lua_State* L, int idx);   // nullptr if not a Matrix
const Mat4& check_matrix(lua_State* L, int idx);  // throws ArgError if not a Matrix
void push_matrix_value(lua_State* L, const Mat4& m);
// An axis given as {x, y, z} (non-zero) or as one of the strings "x", "y", "z"; throws ArgError.
Vec3 check_axis(lua_State* L, int idx);
// The options table {xy=, xz=, yx=, yz=, zx=, zy=} of a shear; throws ArgError.
Shear check_shear(lua_State* L, int arg);
}  // namespace wedge::lua
