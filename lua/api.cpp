// Assembles the API table from every bound area. A new area adds its register_* function to
// wedge_lua.h and one line to kRegistrars below.
#include <cstring>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"

namespace wedge::lua {

namespace {

using Registrar = void (*)(lua_State*);

const Registrar kRegistrars[] = {
    register_matrix,
    register_solid,
    register_io,
    register_profiles,
    register_curves,
    register_surfaces,
    register_brep,
    register_render,
};

int version_fn(lua_State* L) {
  lua_pushstring(L, wedge::version());
  return 1;
}

}  // namespace

void push_api(lua_State* L) {
  lua_newtable(L);
  for (Registrar r : kRegistrars) r(L);
  lua_pushcfunction(L, version_fn);
  lua_setfield(L, -2, "version");
}

void install_globals(lua_State* L) {
  push_api(L);
  lua_pushnil(L);
  while (lua_next(L, -2)) {
    // key at -2, value at -1: _G[key] = value
    lua_pushvalue(L, -2);
    lua_insert(L, -2);
    lua_setglobal(L, lua_tostring(L, -2));
    lua_pop(L, 1);
  }
  lua_setglobal(L, "wedge");  // the same functions, also as the table `wedge`
}

lua_State* new_state() {
  lua_State* L = luaL_newstate();
  if (!L) fail("cannot create a Lua state: out of memory");
  luaL_openlibs(L);
  install_globals(L);
  return L;
}

}  // namespace wedge::lua
