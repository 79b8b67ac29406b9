// The Lua Solid value: a userdata holding a wedge::Solid (csg/solid.h), plus, in its first user
// value, the material table given to s:material{...} (or nil). Every binding that makes or takes
// solids uses these functions.
#pragma once
#include <lua.hpp>

#include <optional>

#include "csg/solid.h"

namespace wedge::lua {

// Pushes a new Solid userdata. If material_from != 0, the new value carries the material of the
// Solid at that stack index (transforms keep the material).
void push_solid(lua_State* L, Solid s, int material_from = 0);
const Solid* test_solid(lua_State* L, int idx);   // nullptr if not a Solid
const Solid& check_solid(lua_State* L, int idx);  // throws ArgError if not a Solid
// Pushes the material table of the Solid at idx (nil when it has none); returns its Lua type.
int push_material(lua_State* L, int idx);
// Pushes the material table of a face tag (Solid::face_tags; made by s:material{}), or nil.
int push_tag_material(lua_State* L, int tag);

// The chordal tolerance set by tolerance(t) in this Lua state (default 0.01 model units).
Tolerance current_tolerance(lua_State* L);
// A triangle budget given as field 'max_triangles' of argument `arg`: a whole number in 1..1e12.
double check_max_triangles(double n, int arg);
// A budget given as field `field` of argument `arg` (max_triangles, max_crossings): a whole number
// in 1..1e12.
double check_budget(const char* field, double n, int arg);

// The triangle mesh of a value that can be drawn or exported: a Solid (tessellated at `tol`), or
// anything a registered converter accepts (free-form surfaces, scenes). Throws ArgError naming
// argument `arg` otherwise.
Mesh to_mesh(lua_State* L, int idx, int arg, const Tolerance& tol);
// A converter returns nullopt when the value at idx is not its kind.
using MeshConverter = std::optional<Mesh> (*)(lua_State* L, int idx, const Tolerance& tol);
void add_mesh_converter(lua_State* L, MeshConverter converter);

}  // namespace wedge::lua
