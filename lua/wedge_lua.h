// wedge::lua — the Lua 5.4 front end: the bindings of every module, and the script runner that
// the `wedge` executable and the tests share.
#pragma once
#include <lua.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace wedge::lua {

// Pushes a table holding the whole API (what `require "wedge"` returns).
void push_api(lua_State* L);
// Sets every API name as a global (what `wedge run` does before running a script).
void install_globals(lua_State* L);
// A fresh state with the standard libraries and the API as globals. Never returns null: throws
// wedge::Error if Lua cannot allocate a state.
lua_State* new_state();

// Runs a script file with `args` as arg[1..] (arg[0] is the path). Errors (a missing or
// unreadable file, a syntax error, a runtime error) are written to `err` as
// "path:LINE: message" followed by a traceback. Returns the process exit code: 0 or 1.
int run_file(const std::string& path, const std::vector<std::string>& args, std::ostream& err);
// Runs a chunk of code under `chunkname` (e.g. "@test.lua"), reporting errors the same way.
int run_string(const std::string& code, const std::string& chunkname, std::ostream& err);

// --- the registration functions of each bound area (one wrap_<type>.cpp each) ---
// Each adds its functions to the API table at the top of the stack and registers its classes.
void register_matrix(lua_State* L);
void register_solid(lua_State* L);
void register_io(lua_State* L);
void register_profiles(lua_State* L);  // wrap_profile.cpp
void register_curves(lua_State* L);    // wrap_curve.cpp
void register_surfaces(lua_State* L);  // wrap_surface.cpp
void register_brep(lua_State* L);      // wrap_brep.cpp
void register_render(lua_State* L);

}  // namespace wedge::lua
