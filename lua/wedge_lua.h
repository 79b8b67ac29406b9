// wedge::lua — the Lua 5.4 front end: the bindings of every module, and the script runner that
// the `wedge` executable and the tests share.
#pragma once
#include <lua.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace wedge::lua {

// Pushes a table holding the whole API (what `require "wedge"` returns), with an empty `params`.
void push_api(lua_State* L);
// Sets table[key] = value for every argument "key=value" whose key is a Lua name: numbers become
// numbers (lua_stringtonumber's syntax: 24, 0.5, 1e-3, 0x10), true and false booleans, anything
// else (an empty value too) stays a string. Other arguments are left alone.
void fill_params(lua_State* L, int table_idx, const std::vector<std::string>& args);
// Sets every API name as a global (what `wedge run` does before running a script).
void install_globals(lua_State* L);
// A fresh state with the standard libraries and the API as globals. Never returns null: throws
// wedge::Error if Lua cannot allocate a state.
lua_State* new_state();

// How `wedge run` runs a script (its flags).
struct RunOptions {
  bool quiet = false;    // the script's print() writes nothing; wedge itself writes only errors
  bool stats = false;    // after the run, the time spent per stage, on `err`
  bool sandbox = false;  // a stranger's script: see apply_sandbox
};

// Runs a script file with `args` as arg[1..] (arg[0] is the path) and each "key=value" among them
// also as params.key (fill_params). Errors (a missing or unreadable file, a syntax error, a
// runtime error) are written to `err` as "path:LINE: message" followed by a traceback. Returns the
// process exit code: 0 or 1.
int run_file(const std::string& path, const std::vector<std::string>& args, std::ostream& err,
             const RunOptions& options = {});

// The hook of `wedge run --sandbox` (sandbox.cpp, issue 14): restricts the fresh state L, in which
// the script at `script_path` is about to run, to what a stranger's script may do. Throws
// wedge::Error when the restriction cannot be made; the runner then does not run the script.
void apply_sandbox(lua_State* L, const std::string& script_path);
// Under --sandbox, throws wedge::Error unless `path` lies in the script's folder or the output
// folder (resolved through symbolic links and ".."); does nothing otherwise. Every binding that
// opens a file by name calls it first (export, import, render and drawing out=, textures).
void sandbox_check_path(lua_State* L, const std::string& path, bool write);
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
void register_scene(lua_State* L);     // wrap_scene.cpp
void register_wireframe(lua_State* L); // wrap_wireframe.cpp
void register_boolean(lua_State* L);  // wrap_boolean.cpp (after register_solid)

}  // namespace wedge::lua
