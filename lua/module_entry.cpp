// The entry point of the loadable module: `require "wedge"` from any Lua 5.4 host.
#include "lua/wedge_lua.h"

extern "C" __attribute__((visibility("default"))) int luaopen_wedge(lua_State* L) {
  wedge::lua::push_api(L);
  return 1;
}
