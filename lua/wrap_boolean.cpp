// Lua bindings of the boolean operations: a + b, a - b, a * b on Solids, and union(...),
// difference(...), intersection(...) with any number of operands (or one table of them). Each
// makes a lazy boolean node (csg/solid.h); the engine runs when a query needs the mesh.
#include <string>
#include <vector>

#include "lua/lua_util.h"
#include "lua/wedge_lua.h"
#include "lua/wrap_solid.h"

namespace wedge::lua {

namespace {

// Where the script made the node ("model.lua:12"): its errors come from a later query.
std::string caller_line(lua_State* L) {
  luaL_where(L, 1);
  std::string w = lua_tostring(L, -1);
  lua_pop(L, 1);
  while (!w.empty() && (w.back() == ' ' || w.back() == ':')) w.pop_back();
  return w;
}

// a + b, a - b, a * b: Lua calls the metamethod with the operands in order, whichever is the Solid.
template <BooleanOp Op>
int operator_m(lua_State* L) {
  return guarded(L, [&] {
    const char* sym = Op == BooleanOp::Union ? "+" : Op == BooleanOp::Difference ? "-" : "*";
    std::vector<Solid> ops;
    for (int i = 1; i <= 2; ++i) {
      const Solid* s = test_solid(L, i);
      if (!s)
        throw Error(std::string("operator '") + sym + "' (" + boolean_op_name(Op) + "): the " + (i == 1 ? "first" : "second") +
                    " operand is " + describe(L, i) + ", a Solid expected");
      ops.push_back(*s);
    }
    push_solid(L, Solid::boolean(Op, std::move(ops), caller_line(L)), 1);
    return 1;
  });
}

// union(a, b, ...) or union{a, b, ...}
template <BooleanOp Op>
int function_fn(lua_State* L) {
  return guarded(L, [&] {
    std::vector<Solid> ops;
    int first = 1;
    if (lua_gettop(L) == 1 && lua_type(L, 1) == LUA_TTABLE && !test_solid(L, 1)) {
      lua_Integer n = luaL_len(L, 1);
      for (lua_Integer i = 1; i <= n; ++i) {
        lua_geti(L, 1, i);
        const Solid* s = test_solid(L, -1);
        if (!s) {
          std::string what = describe(L, -1);
          lua_pop(L, 1);
          throw ArgError{1, "element " + std::to_string(i) + " is " + what + ", a Solid expected"};
        }
        ops.push_back(*s);
        lua_pop(L, 1);
      }
      if (ops.empty()) throw ArgError{1, std::string("no operands: ") + boolean_op_name(Op) + " needs at least one Solid"};
      lua_geti(L, 1, 1);
      first = lua_gettop(L);
    } else {
      int n = lua_gettop(L);
      if (n == 0) throw ArgError{1, std::string("no operands: ") + boolean_op_name(Op) + " needs at least one Solid"};
      for (int i = 1; i <= n; ++i) ops.push_back(check_solid(L, i));
    }
    push_solid(L, Solid::boolean(Op, std::move(ops), caller_line(L)), first);
    return 1;
  });
}

}  // namespace

void register_boolean(lua_State* L) {
  lua_pushcfunction(L, function_fn<BooleanOp::Union>);
  lua_setfield(L, -2, "union");
  lua_pushcfunction(L, function_fn<BooleanOp::Difference>);
  lua_setfield(L, -2, "difference");
  lua_pushcfunction(L, function_fn<BooleanOp::Intersection>);
  lua_setfield(L, -2, "intersection");
  // The operators live in the Solid metatable (registered by register_solid).
  luaL_getmetatable(L, "wedge.Solid");
  lua_pushcfunction(L, operator_m<BooleanOp::Union>);
  lua_setfield(L, -2, "__add");
  lua_pushcfunction(L, operator_m<BooleanOp::Difference>);
  lua_setfield(L, -2, "__sub");
  lua_pushcfunction(L, operator_m<BooleanOp::Intersection>);
  lua_setfield(L, -2, "__mul");
  lua_pop(L, 1);
}

}  // namespace wedge::lua
