// The script runner, modelled on lua.c: load, pcall with a traceback handler, report
// "file:line: message" and a non-zero exit on error.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <ostream>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"

namespace wedge::lua {

namespace {

struct StateCloser {
  void operator()(lua_State* L) const { lua_close(L); }
};

using StatePtr = std::unique_ptr<lua_State, StateCloser>;

// A fresh state with the API, or null after reporting why to `err`.
StatePtr open_state(std::ostream& err) {
  try {
    return StatePtr(new_state());
  } catch (const std::exception& e) {
    err << "wedge: " << e.what() << "\n";
    return nullptr;
  }
}

int traceback_handler(lua_State* L) {
  const char* msg = lua_tostring(L, 1);
  if (!msg) {
    if (luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING) return 1;
    msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
  }
  luaL_traceback(L, L, msg, 1);
  return 1;
}

int call_chunk(lua_State* L, int nargs, std::ostream& err) {
  // Stack: chunk, args... ; put the handler beneath the chunk.
  int base = lua_gettop(L) - nargs;
  lua_pushcfunction(L, traceback_handler);
  lua_insert(L, base);
  int status = lua_pcall(L, nargs, 0, base);
  lua_remove(L, base);
  if (status != LUA_OK) {
    const char* msg = lua_tostring(L, -1);
    err << (msg ? msg : "(error object is not a string)") << "\n";
    lua_pop(L, 1);
    return 1;
  }
  return 0;
}

int print_nothing(lua_State*) { return 0; }

void report_stats(const RunStats& stats, double total, const std::string& path, std::ostream& err) {
  char line[160];
  err << "wedge: time per stage for " << path << " (each stage's own share of the wall time)\n";
  for (const auto& e : stats.entries) {
    std::snprintf(line, sizeof line, "  %-10s %10.1f ms", e.name.c_str(), e.seconds * 1e3);
    err << line;
    if (e.name != "load" && e.name != "lua") err << "  (" << e.calls << (e.calls == 1 ? " call)" : " calls)");
    err << "\n";
  }
  std::snprintf(line, sizeof line, "  %-10s %10.1f ms\n", "total", total * 1e3);
  err << line;
}

}  // namespace

int run_file(const std::string& path, const std::vector<std::string>& args, std::ostream& err,
             const RunOptions& options) {
  {
    std::ifstream probe(path);
    if (!probe) {
      err << "wedge: cannot open script '" << path << "': " << std::strerror(errno) << "\n";
      return 1;
    }
  }
  StatePtr state = open_state(err);
  if (!state) return 1;
  lua_State* L = state.get();

  // arg[0] = script, arg[1..n] = its arguments, as the lua interpreter does.
  lua_createtable(L, static_cast<int>(args.size()), 1);
  lua_pushlstring(L, path.data(), path.size());
  lua_rawseti(L, -2, 0);
  for (std::size_t i = 0; i < args.size(); ++i) {
    lua_pushlstring(L, args[i].data(), args[i].size());
    lua_rawseti(L, -2, static_cast<lua_Integer>(i + 1));
  }
  lua_setglobal(L, "arg");
  // params.key for each key=value argument.
  lua_getglobal(L, "params");
  fill_params(L, -1, args);
  lua_pop(L, 1);

  if (options.quiet) {
    lua_pushcfunction(L, print_nothing);
    lua_setglobal(L, "print");
    set_quiet(L, true);
  }
  if (options.sandbox) {
    try {
      apply_sandbox(L, path);
    } catch (const std::exception& e) {
      err << "wedge: " << e.what() << "\n";
      return 1;
    }
  }

  RunStats stats;
  if (options.stats) install_stats(L, &stats);
  const double start = RunStats::now();
  int status = 0;
  {
    Stage load(L, "load");
    if (luaL_loadfilex(L, path.c_str(), "t") != LUA_OK) {
      const char* msg = lua_tostring(L, -1);
      err << (msg ? msg : "cannot load script") << "\n";
      status = 1;
    }
  }
  if (status == 0) {
    for (const auto& a : args) lua_pushlstring(L, a.data(), a.size());
    Stage run(L, "lua");
    status = call_chunk(L, static_cast<int>(args.size()), err);
  }
  if (options.stats) {
    install_stats(L, nullptr);
    report_stats(stats, RunStats::now() - start, path, err);
  }
  return status;
}

int run_string(const std::string& code, const std::string& chunkname, std::ostream& err) {
  StatePtr state = open_state(err);
  if (!state) return 1;
  lua_State* L = state.get();
  if (luaL_loadbufferx(L, code.data(), code.size(), chunkname.c_str(), "t") != LUA_OK) {
    const char* msg = lua_tostring(L, -1);
    err << (msg ? msg : "cannot load chunk") << "\n";
    return 1;
  }
  return call_chunk(L, 0, err);
}

}  // namespace wedge::lua
