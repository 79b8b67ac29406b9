// Runs a chunk of Lua the way `wedge run` does, keeping its exit status and what it printed on
// stderr (the error message with its file:line, and the traceback).
#pragma once
#include <sstream>
#include <string>

#include "lua/wedge_lua.h"

struct LuaRun {
  int status;
  std::string err;
};

inline LuaRun run_lua(const std::string& code, const std::string& chunk) {
  std::ostringstream err;
  const int status = wedge::lua::run_string(code, chunk, err);
  return {status, err.str()};
}
