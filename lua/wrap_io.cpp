// Lua bindings of mesh files: export(value, path [, {ascii=, tolerance=}]) and import(path).
#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_curve.h"
#include "lua/wrap_solid.h"
#include "tessellate/mesh_io.h"

namespace wedge::lua {

namespace {

int export_fn(lua_State* L) {
  return guarded(L, [&] {
    std::string path = check_string(L, 2);
    Tolerance tol = current_tolerance(L);
    MeshWriteOptions options;
    if (!lua_isnoneornil(L, 3)) {
      Options o(L, 3);
      options.ascii = o.boolean("ascii", false);
      tol.chordal = o.positive("tolerance", tol.chordal);
      o.finish();
    }
    mesh_format(path);  // an unknown extension is an error before any tessellation work
    // A single surface is exported welded (closed seams merged, poles collapsed), so a closed
    // surface such as a sphere or torus makes a closed file; several patches are exported as
    // they are (patches are not welded to each other).
    const LuaSurface* surface = test_surface(L, 1);
    Mesh mesh = surface && surface->patches.size() == 1 ? surface_mesh(*surface, tol.chordal, true) : to_mesh(L, 1, 1, tol);
    write_mesh(mesh, path, options);
    lua_pushinteger(L, static_cast<lua_Integer>(mesh.triangle_count()));
    return 1;
  });
}

int import_fn(lua_State* L) {
  return guarded(L, [&] {
    std::string path = check_string(L, 1);
    push_solid(L, Solid::from_mesh(read_mesh(path), path));
    return 1;
  });
}

// Free-form surfaces (and the teapot's patches) export and render as their meshes.
std::optional<Mesh> surface_to_mesh(lua_State* L, int idx, const Tolerance& tol) {
  if (const LuaSurface* s = test_surface(L, idx)) return surface_mesh(*s, tol.chordal);
  return std::nullopt;
}

const luaL_Reg kFunctions[] = {{"export", export_fn}, {"import", import_fn}, {nullptr, nullptr}};

}  // namespace

void register_io(lua_State* L) {
  set_functions(L, kFunctions);
  add_mesh_converter(L, surface_to_mesh);
}

}  // namespace wedge::lua
