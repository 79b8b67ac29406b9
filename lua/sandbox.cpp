// `wedge run --sandbox`: a stranger's script runs without process, library or file access beyond
// two folders: the script's own and the output folder (params.out, when the command line gives
// out=DIR). What is taken away and why:
//  - os.execute, io.popen: run programs. package.loadlib and the C searchers of require: load
//    native code. os.tmpname, os.getenv: touch /tmp, read the environment (tokens, keys).
//    Each is replaced by a function that raises "... is not available under --sandbox", so the
//    script's author reads why, not "attempt to call a nil value".
//  - debug: getregistry, getupvalue and setupvalue reach the originals kept below (and the list of
//    allowed folders); only debug.traceback stays, and each other debug function raises the same
//    "... is not available under --sandbox".
//  - load, loadfile, dofile take text chunks only: crafted bytecode can break out of any Lua.
// What stays, but checked against the two folders (resolved through symbolic links and ".."):
// io.open, io.lines, io.input, io.output, os.remove, os.rename, loadfile, dofile, require (Lua files
// in the script's folder only), and wedge's own files: export, import, render/drawing out=,
// textures (sandbox_check_path, called by those bindings).
#include <sys/stat.h>

#include <cstring>
#include <filesystem>

#include "kernel/kernel.h"
#include "lua/wedge_lua.h"

namespace wedge::lua {

namespace {

namespace fs = std::filesystem;
constexpr const char* kRootsKey = "wedge.sandbox_roots";

fs::path resolved(const std::string& path) {
  std::error_code ec;
  fs::path abs = fs::absolute(path, ec);
  if (ec) fail("sandbox: cannot resolve '", path, "': ", ec.message());
  fs::path canon = fs::weakly_canonical(abs, ec);
  if (ec) fail("sandbox: cannot resolve '", path, "': ", ec.message());
  return canon;
}

bool within(const fs::path& root, const fs::path& p) {
  auto r = root.begin(), q = p.begin();
  for (; r != root.end(); ++r, ++q) {
    if (r->empty()) continue;  // a trailing separator
    if (q == p.end() || *r != *q) return false;
  }
  return true;
}

// Pushes the reason and returns true if the path is refused. The caller raises the error with
// lua_error after this returns, when no C++ object is alive to be skipped by the longjmp. The
// reason starts with the calling script's file:line and the function's name (`fn`), as export's
// refusal does ("loc.lua:2: io.open: sandbox: cannot read ..."): it had neither.
bool refused(lua_State* L, const char* path, bool write, const char* fn) {
  std::string why;
  try {
    sandbox_check_path(L, path, write);
  } catch (const std::exception& e) {
    why = e.what();
  }
  if (why.empty()) return false;
  luaL_where(L, 1);
  lua_pushfstring(L, "%s: ", fn);
  lua_pushlstring(L, why.data(), why.size());
  lua_concat(L, 3);
  return true;
}

bool is_regular(const char* path) {
  struct stat st {};
  return ::stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int unavailable(lua_State* L) {
  return luaL_error(L, "%s is not available under --sandbox", lua_tostring(L, lua_upvalueindex(1)));
}

// Calls the original function (upvalue 1) with all arguments after checking argument `arg`
// (upvalue 2) as a path, for writing if upvalue 3 says so (or, for io.open, if its mode writes).
// Upvalue 4 is the function's name, for the message.
int checked_call(lua_State* L) {
  const int arg = static_cast<int>(lua_tointeger(L, lua_upvalueindex(2)));
  // 0 read, 1 write, 2 as io.open's mode says, 3 this argument and the next for writing
  const int rule = static_cast<int>(lua_tointeger(L, lua_upvalueindex(3)));
  for (int a = arg; a <= (rule == 3 ? arg + 1 : arg); ++a) {
    if (lua_type(L, a) != LUA_TSTRING) continue;  // a file handle, or nothing: no path to check
    bool write = rule == 1 || rule == 3;
    if (rule == 2 && lua_type(L, 2) == LUA_TSTRING) write = std::strpbrk(lua_tostring(L, 2), "wa+") != nullptr;
    if (refused(L, lua_tostring(L, a), write, lua_tostring(L, lua_upvalueindex(4)))) return lua_error(L);
  }
  const int n = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, n, LUA_MULTRET);
  return lua_gettop(L);
}

// load(chunk [, name [, mode [, env]]]) and loadfile(path [, mode [, env]]) with mode "t" forced.
int text_only(lua_State* L) {
  const int mode_arg = static_cast<int>(lua_tointeger(L, lua_upvalueindex(2)));
  if (mode_arg == 2 && refused(L, luaL_checkstring(L, 1), false, "loadfile")) return lua_error(L);
  if (lua_gettop(L) < mode_arg) lua_settop(L, mode_arg);
  lua_pushliteral(L, "t");
  lua_replace(L, mode_arg);
  const int n = lua_gettop(L);
  lua_pushvalue(L, lua_upvalueindex(1));
  lua_insert(L, 1);
  lua_call(L, n, LUA_MULTRET);
  return lua_gettop(L);
}

// dofile(path): loadfile in text mode, then call.
int dofile_checked(lua_State* L) {
  const char* path = luaL_checkstring(L, 1);
  if (refused(L, path, false, "dofile")) return lua_error(L);
  lua_settop(L, 1);
  if (luaL_loadfilex(L, path, "t") != LUA_OK) return lua_error(L);
  lua_call(L, 0, LUA_MULTRET);
  return lua_gettop(L) - 1;
}

// require's searcher for Lua files in the script's folder only (upvalue 1: the folder).
int searcher(lua_State* L) {
  const char* name = luaL_checkstring(L, 1);
  const char* dir = lua_tostring(L, lua_upvalueindex(1));
  const char* base = luaL_gsub(L, name, ".", "/");
  const char* candidates[2] = {lua_pushfstring(L, "%s/%s.lua", dir, base), lua_pushfstring(L, "%s/%s/init.lua", dir, base)};
  for (const char* file : candidates) {
    if (!is_regular(file)) continue;
    if (refused(L, file, false, "require")) return lua_error(L);
    if (luaL_loadfilex(L, file, "t") != LUA_OK) return lua_error(L);
    lua_pushstring(L, file);
    return 2;
  }
  lua_pushfstring(L, "no file '%s' (under --sandbox only the script's folder is searched)", candidates[0]);
  return 1;
}

// table[name] = f(upvalues...) on the table at `t`, named `table.name` in its messages.
void wrap(lua_State* L, int t, const char* table, const char* name, lua_CFunction f, int arg, int rule) {
  lua_getfield(L, t, name);
  lua_pushinteger(L, arg);
  lua_pushinteger(L, rule);
  lua_pushfstring(L, "%s.%s", table, name);
  lua_pushcclosure(L, f, 4);
  lua_setfield(L, t, name);
}

void disable(lua_State* L, int t, const char* table, const char* name) {
  lua_pushfstring(L, "%s%s%s", table, *table ? "." : "", name);
  lua_pushcclosure(L, unavailable, 1);
  lua_setfield(L, t, name);
}

}  // namespace

void sandbox_check_path(lua_State* L, const std::string& path, bool write) {
  // A Lua string may hold a NUL byte; the file functions would stop there and use another file
  // than the one named (export(s, "a\0b.stl") wrote "a"), and than the one checked below.
  if (const std::size_t nul = path.find('\0'); nul != std::string::npos)
    fail("cannot ", write ? "write" : "read", " '", path.substr(0, nul), "\\0", path.substr(nul + 1),
         "': a file name cannot hold a NUL byte");
  if (lua_getfield(L, LUA_REGISTRYINDEX, kRootsKey) != LUA_TTABLE) {
    lua_pop(L, 1);
    return;  // not sandboxed
  }
  const fs::path p = resolved(path);  // may throw: the table is on the stack, guarded() drops it
  std::string roots;
  for (lua_Integer i = 1; lua_rawgeti(L, -1, i) == LUA_TSTRING; ++i) {
    const std::string root = lua_tostring(L, -1);
    lua_pop(L, 1);
    if (within(root, p)) {
      lua_pop(L, 1);
      return;
    }
    roots += (roots.empty() ? "'" : " or '") + root + "'";
  }
  lua_pop(L, 2);
  fail("sandbox: cannot ", write ? "write" : "read", " '", path, "': under --sandbox a script may use files in ", roots,
       " only");
}

void apply_sandbox(lua_State* L, const std::string& script_path) {
  const fs::path script_dir = resolved(script_path).parent_path();
  // The allowed folders: the script's, and params.out when the command line names one.
  lua_createtable(L, 2, 0);
  lua_pushstring(L, script_dir.string().c_str());
  lua_rawseti(L, -2, 1);
  // Without out= the params table stayed on the stack and became the list of allowed folders (an
  // empty one: a sandboxed script could write nowhere, not even beside itself).
  const bool has_params = lua_getglobal(L, "params") == LUA_TTABLE;
  if (has_params && lua_getfield(L, -1, "out") == LUA_TSTRING) {
    const fs::path out = resolved(lua_tostring(L, -1));
    lua_pop(L, 2);
    lua_pushstring(L, out.string().c_str());
    lua_rawseti(L, -2, 2);
  } else {
    lua_pop(L, has_params ? 2 : 1);
  }
  lua_setfield(L, LUA_REGISTRYINDEX, kRootsKey);

  lua_pushglobaltable(L);
  const int g = lua_gettop(L);
  lua_getfield(L, g, "os");
  const int os = lua_gettop(L);
  for (const char* name : {"execute", "tmpname", "getenv"}) disable(L, os, "os", name);
  wrap(L, os, "os", "remove", checked_call, 1, 1);
  wrap(L, os, "os", "rename", checked_call, 1, 3);  // both names are checked for writing
  lua_getfield(L, g, "io");
  const int io = lua_gettop(L);
  disable(L, io, "io", "popen");
  wrap(L, io, "io", "open", checked_call, 1, 2);
  wrap(L, io, "io", "lines", checked_call, 1, 0);
  wrap(L, io, "io", "input", checked_call, 1, 0);
  wrap(L, io, "io", "output", checked_call, 1, 1);
  // load's mode is its 3rd argument, loadfile's its 2nd.
  lua_getfield(L, g, "load");
  lua_pushinteger(L, 3);
  lua_pushcclosure(L, text_only, 2);
  lua_setfield(L, g, "load");
  lua_getfield(L, g, "loadfile");
  lua_pushinteger(L, 2);
  lua_pushcclosure(L, text_only, 2);
  lua_setfield(L, g, "loadfile");
  lua_pushcfunction(L, dofile_checked);
  lua_setfield(L, g, "dofile");
  // debug: only the traceback; each other function raises "debug.getregistry is not available
  // under --sandbox" (it was removed, and a call said "attempt to call a nil value").
  lua_getfield(L, g, "debug");
  const int original_debug = lua_gettop(L);
  lua_createtable(L, 0, 1);
  const int debug = lua_gettop(L);
  lua_pushnil(L);
  while (lua_next(L, original_debug)) {
    lua_pop(L, 1);
    if (lua_type(L, -1) == LUA_TSTRING && std::strcmp(lua_tostring(L, -1), "traceback") != 0)
      disable(L, debug, "debug", lua_tostring(L, -1));
  }
  lua_getfield(L, original_debug, "traceback");
  lua_setfield(L, debug, "traceback");
  lua_setfield(L, g, "debug");
  lua_pop(L, 1);
  // package: no native code; require finds preloaded modules and Lua files beside the script.
  lua_getfield(L, g, "package");
  const int pkg = lua_gettop(L);
  disable(L, pkg, "package", "loadlib");
  lua_pushliteral(L, "");
  lua_setfield(L, pkg, "cpath");
  lua_pushstring(L, (script_dir.string() + "/?.lua").c_str());
  lua_setfield(L, pkg, "path");
  lua_getfield(L, pkg, "searchers");
  const int searchers = lua_gettop(L);
  lua_rawgeti(L, searchers, 1);  // the preload searcher
  lua_createtable(L, 2, 0);
  lua_insert(L, -2);
  lua_rawseti(L, -2, 1);
  lua_pushstring(L, script_dir.string().c_str());
  lua_pushcclosure(L, searcher, 1);
  lua_rawseti(L, -2, 2);
  lua_setfield(L, pkg, "searchers");
  lua_settop(L, g - 1);
}

}  // namespace wedge::lua
