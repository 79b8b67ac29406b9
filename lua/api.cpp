// Assembles the API table from every bound area. A new area adds its register_* function to
// wedge_lua.h and one line to kRegistrars below.
#include <cctype>
#include <cstring>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"

namespace wedge::lua {

// wrap_canvas.cpp (declared here rather than in wedge_lua.h, which every binding and Lua test
// includes: adding it there rebuilt them all).
void register_canvas(lua_State* L);

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
    register_scene,
    register_wireframe,
    register_boolean,
    register_canvas,
};

int version_fn(lua_State* L) {
  lua_pushstring(L, wedge::version());
  return 1;
}

bool is_name(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

}  // namespace

void push_api(lua_State* L) {
  lua_newtable(L);
  for (Registrar r : kRegistrars) r(L);
  lua_pushcfunction(L, version_fn);
  lua_setfield(L, -2, "version");
  name_functions(L, -1);
  lua_newtable(L);
  lua_setfield(L, -2, "params");
}

void fill_params(lua_State* L, int table_idx, const std::vector<std::string>& args) {
  table_idx = lua_absindex(L, table_idx);
  for (const std::string& a : args) {
    const std::size_t eq = a.find('=');
    if (eq == std::string::npos || !is_name(a.substr(0, eq))) continue;
    const std::string key = a.substr(0, eq), value = a.substr(eq + 1);
    if (value == "true" || value == "false") lua_pushboolean(L, value == "true");
    else if (value.empty() || lua_stringtonumber(L, value.c_str()) != value.size() + 1) lua_pushlstring(L, value.data(), value.size());
    lua_setfield(L, table_idx, key.c_str());
  }
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
  // The same functions, also as the table `wedge`, which is what `require "wedge"` returns inside
  // `wedge run` (as package.loaded holds Lua's own libraries).
  lua_getglobal(L, LUA_LOADLIBNAME);
  if (lua_istable(L, -1) && lua_getfield(L, -1, "loaded") == LUA_TTABLE) {
    lua_pushvalue(L, -3);
    lua_setfield(L, -2, "wedge");
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  lua_setglobal(L, "wedge");
}

lua_State* new_state() {
  lua_State* L = luaL_newstate();
  if (!L) fail("cannot create a Lua state: out of memory");
  luaL_openlibs(L);
  install_globals(L);
  return L;
}

}  // namespace wedge::lua
