// The Curve and Surface userdata, for other bindings: a closed Curve is a 2D profile (extrude,
// revolve, sweep), and a Surface's patches can be tessellated into a Mesh for render/export.
#pragma once
#include <lua.hpp>

#include <vector>

#include "surfaces/surfaces.h"

namespace wedge::lua {

struct LuaCurve {
  CurvePtr curve;
  bool planar = true;  // every input point was 2D (or had z = 0): eval returns {x, y}
};

// One surface or a set of patches (the teapot).
struct LuaSurface {
  std::vector<SurfacePtr> patches;
};

const LuaCurve* test_curve(lua_State* L, int idx);    // nullptr if not a Curve
const LuaCurve& check_curve(lua_State* L, int idx);   // throws ArgError if not a Curve
void push_curve(lua_State* L, LuaCurve c);
const LuaSurface* test_surface(lua_State* L, int idx);
const LuaSurface& check_surface(lua_State* L, int idx);
void push_surface(lua_State* L, LuaSurface s);
// All patches meshed to `tolerance`; face_ids are the 0-based patch numbers.
// welded: tessellate_welded (seams merged, poles collapsed); single-patch surfaces only.
Mesh surface_mesh(const LuaSurface& s, double tolerance, bool welded = false, std::size_t max_triangles = SIZE_MAX);

}  // namespace wedge::lua
