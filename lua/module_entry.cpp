// The entry point of the loadable module: `require "wedge"` from any Lua 5.4 host. The host's
// global `arg` (the stock interpreter's script arguments), if any, fills wedge.params as
// `wedge run` fills params, so `lua5.4 gear.lua teeth=24` works as `wedge run gear.lua teeth=24`.
#include "lua/wedge_lua.h"

extern "C" __attribute__((visibility("default"))) int luaopen_wedge(lua_State* L) {
  wedge::lua::push_api(L);
  std::vector<std::string> args;
  if (lua_getglobal(L, "arg") == LUA_TTABLE) {
    for (lua_Integer i = 1;; ++i) {
      if (lua_rawgeti(L, -1, i) != LUA_TSTRING) {
        lua_pop(L, 1);
        break;
      }
      args.emplace_back(lua_tostring(L, -1));
      lua_pop(L, 1);
    }
  }
  lua_pop(L, 1);
  lua_getfield(L, -1, "params");
  wedge::lua::fill_params(L, -1, args);
  lua_pop(L, 1);
  return 1;
}
