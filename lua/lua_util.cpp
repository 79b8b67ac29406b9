#include "lua/lua_util.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <unistd.h>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string_view>

namespace wedge::lua {

namespace {
std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}
}  // namespace

namespace {
// Argument n + 1 where none is expected: `takes` arguments are (`what`: "function" or "method"),
// and `after` follows the value shown.
[[noreturn]] void extra_argument(lua_State* L, int n, const char* what, int takes, const std::string& after = "") {
  throw ArgError{n + 1, "no argument expected here (the " + std::string(what) + " takes " + std::to_string(takes) + "), got " +
                            describe(L, n + 1) + after};
}
}  // namespace

void check_no_more(lua_State* L, int n) {
  if (lua_gettop(L) > n) extra_argument(L, n, "function", n);
}

void check_no_more_method(lua_State* L, int n) {
  if (lua_gettop(L) > n) extra_argument(L, n, "method", n - 1);
}

void check_no_more(lua_State* L, int n, const char* table_form) {
  if (lua_gettop(L) > n)
    extra_argument(L, n, "function", n, lua_type(L, n + 1) == LUA_TBOOLEAN ? std::string(": a centred solid is ") + table_form : "");
}

std::string number_text(double x) {
  if (std::isnan(x)) return "nan";
  std::ostringstream out;
  out.precision(10);
  out << x;
  return out.str();
}

namespace {

constexpr const char* kNamesKey = "wedge.function_names";
constexpr const char* kStatsKey = "wedge.run_stats";

// The table of API names in the registry (created on first use), pushed.
void push_names(lua_State* L) {
  if (lua_getfield(L, LUA_REGISTRYINDEX, kNamesKey) != LUA_TTABLE) {
    lua_pop(L, 1);
    lua_newtable(L);
    lua_pushvalue(L, -1);
    lua_setfield(L, LUA_REGISTRYINDEX, kNamesKey);
  }
}

struct FunctionName {
  std::string name;
  bool method = false;    // a method named by the API: the object is argument #0
  bool operator_ = false;  // an operator's metamethod: named "operator '+'", not quoted again
};

// The operator a metamethod implements, by Lua's name for it ("add" for __add), or null. A
// message names the operator the script wrote, not "add" or "mul", which the script never says.
const char* operator_symbol(const char* metamethod) {
  static const char* const kOperators[][2] = {
      {"add", "+"}, {"sub", "-"}, {"mul", "*"},  {"div", "/"},   {"mod", "%"}, {"pow", "^"},
      {"unm", "-"}, {"idiv", "//"}, {"band", "&"}, {"bor", "|"}, {"bxor", "~"}, {"shl", "<<"},
      {"shr", ">>"}, {"bnot", "~"}, {"concat", ".."}, {"len", "#"}, {"eq", "=="}, {"lt", "<"},
      {"le", "<="}};
  for (const auto& op : kOperators)
    if (std::strcmp(metamethod, op[0]) == 0) return op[1];
  return nullptr;
}

// luaL_argerror's rule, with the API's own name where the call site has none.
FunctionName function_name(lua_State* L) {
  lua_Debug ar;
  if (!lua_getstack(L, 0, &ar) || !lua_getinfo(L, "nf", &ar)) return {};
  // Stack: ..., function
  std::string what = ar.namewhat ? ar.namewhat : "";
  // A call through a computed key names no function: Lua says "?" (e[q](e)) or "integer index"
  // (({e.bounds})[1](e)), and the message began "?: the solid is empty". The API's name instead.
  if (ar.name && (std::strcmp(ar.name, "?") == 0 || std::strcmp(ar.name, "integer index") == 0)) ar.name = nullptr;
  FunctionName out;
  if (what == "metamethod" && ar.name && (std::strcmp(ar.name, "index") == 0 || std::strcmp(ar.name, "newindex") == 0)) {
    // g.field / g.field = v: the message names the field; "index" would only puzzle.
  } else if (const char* op = what == "metamethod" && ar.name ? operator_symbol(ar.name) : nullptr) {
    out.name = std::string("operator '") + op + "'";
    out.operator_ = true;
  } else if (ar.name && (what == "global" || what == "field" || what == "method" || what == "metamethod")) {
    out.name = ar.name;
    out.method = what == "method";
  } else {
    push_names(L);
    lua_pushvalue(L, -2);
    if (lua_rawget(L, -2) == LUA_TSTRING) {
      out.name = lua_tostring(L, -1);
      out.method = out.name.find(':') != std::string::npos;
    } else if (ar.name) {
      out.name = ar.name;
    }
    lua_pop(L, 2);
  }
  lua_pop(L, 1);
  return out;
}

}  // namespace

std::string running_function_name(lua_State* L) { return function_name(L).name; }

int raise_pending(lua_State* L, int arg) {
  // lua_error longjmps (liblua is C): no C++ object may be alive when it is called, or its
  // destructor never runs (a function name longer than the short-string buffer leaked). The
  // message is built and pushed in this block; only the Lua string outlives it.
  {
    const char* message = lua_tostring(L, -1);  // stays valid: the string stays on the stack
    const FunctionName f = function_name(L);
    std::string text;
    if (arg) {
      if (f.name.empty()) {
        text = "bad argument #" + std::to_string(arg) + " (" + message + ")";
      } else if (f.method && --arg == 0) {
        text = "calling '" + f.name + "' on bad self (" + message + ")";
      } else {
        const std::string name = f.operator_ ? f.name : "'" + f.name + "'";
        text = "bad argument #" + std::to_string(arg) + " to " + name + " (" + message + ")";
      }
    } else if (!f.name.empty()) {
      // Name the running function, as luaL_argerror does, so the message says where it came
      // from; once: a message that starts with that name already ("perspective: aspect must be
      // ...", from the kernel) keeps its own.
      const std::string_view m(message);
      const std::size_t cut = f.operator_ ? std::string::npos : f.name.find_last_of(".:");
      const std::string last = cut == std::string::npos ? f.name : f.name.substr(cut + 1);
      if (m.rfind(f.name + ": ", 0) == 0 || m.rfind(last + ": ", 0) == 0 || (f.operator_ && m.rfind(f.name + " (", 0) == 0)) {
        text = message;
      } else {
        text = f.name + ": " + message;
      }
    } else {
      text = message;
    }
    luaL_where(L, 1);  // "script.lua:7: ", as luaL_error puts it
    lua_pushlstring(L, text.data(), text.size());
    lua_concat(L, 2);
  }
  return lua_error(L);
}

namespace {
// names[function at the top] = name, unless it already has an API name that sorts first (one
// function under two names, as nurbs and bspline, gets the same name in every run).
void set_name(lua_State* L, int names, const std::string& name) {
  lua_pushvalue(L, -1);
  if (lua_rawget(L, names) == LUA_TSTRING) {
    std::string old = lua_tostring(L, -1);
    if (old.find(':') == std::string::npos && old <= name) {
      lua_pop(L, 1);
      return;
    }
  }
  lua_pop(L, 1);
  lua_pushvalue(L, -1);
  lua_pushlstring(L, name.data(), name.size());
  lua_rawset(L, names);
}
}  // namespace

void name_functions(lua_State* L, int api_idx) {
  api_idx = lua_absindex(L, api_idx);
  push_names(L);
  const int names = lua_gettop(L);
  lua_pushnil(L);
  while (lua_next(L, api_idx)) {
    if (lua_type(L, -2) == LUA_TSTRING) {
      std::string key = lua_tostring(L, -2);
      if (lua_iscfunction(L, -1)) {
        set_name(L, names, key);
      } else if (lua_istable(L, -1)) {
        const int sub = lua_gettop(L);
        lua_pushnil(L);
        while (lua_next(L, sub)) {
          if (lua_type(L, -2) == LUA_TSTRING && lua_iscfunction(L, -1)) {
            set_name(L, names, key + "." + lua_tostring(L, -2));
          }
          lua_pop(L, 1);
        }
      }
    }
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
}

// --- progress ---

namespace {
constexpr const char* kQuietKey = "wedge.quiet";
}

void set_quiet(lua_State* L, bool quiet) {
  lua_pushboolean(L, quiet);
  lua_setfield(L, LUA_REGISTRYINDEX, kQuietKey);
}

Progress::Progress(lua_State* L, std::string what, std::size_t total)
    : what_(std::move(what)), total_(total), start_(RunStats::now()) {
  lua_getfield(L, LUA_REGISTRYINDEX, kQuietKey);
  const bool quiet = lua_toboolean(L, -1);
  lua_pop(L, 1);
  const char* mode = std::getenv("WEDGE_PROGRESS");
  const std::string m = mode ? mode : "";
  always_ = m == "always";
  enabled_ = !quiet && total_ > 1 && m != "never" && (always_ || ::isatty(2));
}

void Progress::step() {
  ++done_;
  if (!enabled_ || done_ > total_) return;
  if (!always_ && RunStats::now() - start_ < 0.5) return;
  constexpr int kWidth = 30;
  const int filled = int(kWidth * done_ / total_);
  std::string bar = "\r[" + std::string(std::size_t(filled), '#') + std::string(std::size_t(kWidth - filled), ' ') + "] " +
                    what_ + " " + std::to_string(done_) + "/" + std::to_string(total_);
  std::fputs(bar.c_str(), stderr);
  std::fflush(stderr);
  shown_ = true;
}

Progress::~Progress() {
  if (!shown_) return;
  // Erase the line: carriage return, spaces over the longest line drawn, carriage return.
  const std::string blank(what_.size() + 40 + 2 * std::to_string(total_).size(), ' ');
  std::fprintf(stderr, "\r%s\r", blank.c_str());
  std::fflush(stderr);
}

// --- run statistics ---

double RunStats::now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void RunStats::add(const std::string& name, double seconds) {
  for (auto& e : entries)
    if (e.name == name) {
      e.seconds += seconds, ++e.calls;
      return;
    }
  entries.push_back({name, seconds, 1});
}

void install_stats(lua_State* L, RunStats* stats) {
  if (stats) lua_pushlightuserdata(L, stats);
  else lua_pushnil(L);
  lua_setfield(L, LUA_REGISTRYINDEX, kStatsKey);
}

Stage::Stage(lua_State* L, const char* name) : stats_(nullptr), name_(name) {
  lua_getfield(L, LUA_REGISTRYINDEX, kStatsKey);
  stats_ = static_cast<RunStats*>(lua_touserdata(L, -1));
  lua_pop(L, 1);
  if (!stats_) return;
  depth_ = stats_->open.size();
  stats_->open.push_back({RunStats::now(), 0.0});
}

Stage::~Stage() {
  if (!stats_) return;
  // A stage skipped by a Lua error (a longjmp past its destructor) is closed here with this one.
  if (stats_->open.size() <= depth_) return;
  const double elapsed = RunStats::now() - stats_->open[depth_].start;
  const double own = elapsed - stats_->open[depth_].inner;
  stats_->open.resize(depth_);
  if (!stats_->open.empty()) stats_->open.back().inner += elapsed;
  stats_->add(name_, own);
}

std::string type_name(lua_State* L, int idx) {
  if (luaL_getmetafield(L, idx, "__name") == LUA_TSTRING) {
    std::string name = lua_tostring(L, -1);
    lua_pop(L, 1);
    return name;
  }
  if (lua_type(L, idx) == LUA_TNONE) return "no value";
  return luaL_typename(L, idx);
}

std::string describe(lua_State* L, int idx) {
  switch (lua_type(L, idx)) {
    case LUA_TNUMBER: return "number " + format_number(lua_tonumber(L, idx));
    case LUA_TSTRING: return std::string("string '") + lua_tostring(L, idx) + "'";
    case LUA_TBOOLEAN: return lua_toboolean(L, idx) ? "true" : "false";
    default: return type_name(L, idx);
  }
}

double check_number(lua_State* L, int idx) {
  if (lua_type(L, idx) != LUA_TNUMBER) throw ArgError{idx, "number expected, got " + type_name(L, idx)};
  double v = lua_tonumber(L, idx);
  if (!std::isfinite(v)) throw ArgError{idx, "finite number expected, got " + format_number(v)};
  return v;
}

double opt_number(lua_State* L, int idx, double fallback) {
  return lua_isnoneornil(L, idx) ? fallback : check_number(L, idx);
}

bool check_boolean(lua_State* L, int idx) {
  if (lua_type(L, idx) != LUA_TBOOLEAN) throw ArgError{idx, "boolean expected, got " + type_name(L, idx)};
  return lua_toboolean(L, idx);
}

std::string check_string(lua_State* L, int idx) {
  if (lua_type(L, idx) != LUA_TSTRING) throw ArgError{idx, "string expected, got " + type_name(L, idx)};
  size_t len = 0;
  const char* s = lua_tolstring(L, idx, &len);
  return std::string(s, len);
}

int check_integer(lua_State* L, int idx) {
  double v = check_number(L, idx);
  if (v != std::floor(v) || std::fabs(v) > 2e9)
    throw ArgError{idx, "integer expected, got " + format_number(v)};
  return static_cast<int>(v);
}

void check_table(lua_State* L, int idx) {
  if (lua_type(L, idx) != LUA_TTABLE) throw ArgError{idx, "table expected, got " + type_name(L, idx)};
}

std::string element_name(const std::string& what, long long k, const char* noun) {
  static const std::string kField = "field '";
  if (what.size() > kField.size() && what.rfind(kField, 0) == 0 && what.back() == '\'')
    return what.substr(0, what.size() - 1) + "[" + std::to_string(k) + "]'";
  return what + " " + noun + " " + std::to_string(k);
}

std::string field_message(const std::string& m) {
  static const std::string kField = "field '";
  if (m.rfind(kField, 0) == 0) {
    const std::size_t end = m.find('\'', kField.size());
    if (end != std::string::npos) return m.substr(kField.size(), end - kField.size()) + m.substr(end + 1);
  }
  return m;
}

template <int N>
static Eigen::Matrix<double, N, 1> read_vector(lua_State* L, int idx, int arg, const std::string& what, bool allow_shorter) {
  idx = lua_absindex(L, idx);
  if (lua_type(L, idx) != LUA_TTABLE)
    throw ArgError{arg, what + (N == 3 ? " must be a point {x, y, z}" : " must be a point {x, y}") + ", got " +
                            type_name(L, idx)};
  lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, idx));
  if (n != N && !(allow_shorter && n == N - 1))
    // Where a 2D point is allowed too, say so: bezier{{0,0},{1}} said "must have 3 coordinates".
    throw ArgError{arg, what + " must have " + (allow_shorter ? std::to_string(N - 1) + " or " : std::string()) + std::to_string(N) +
                            " coordinates, got " + std::to_string(n)};
  Eigen::Matrix<double, N, 1> v = Eigen::Matrix<double, N, 1>::Zero();
  for (lua_Integer i = 1; i <= n; ++i) {
    int t = lua_rawgeti(L, idx, i);
    double x = lua_tonumber(L, -1);
    const std::string got = t == LUA_TNUMBER ? "" : type_name(L, -1);
    lua_pop(L, 1);
    if (t != LUA_TNUMBER) throw ArgError{arg, element_name(what, i, "coordinate") + " must be a number, got " + got};
    if (!std::isfinite(x))
      throw ArgError{arg, element_name(what, i, "coordinate") + " must be finite, got " + format_number(x)};
    v[static_cast<int>(i - 1)] = x;
  }
  return v;
}

Vec3 to_vec3(lua_State* L, int idx, int arg, const std::string& what, bool allow_2d) {
  return read_vector<3>(L, idx, arg, what, allow_2d);
}
Vec2 to_vec2(lua_State* L, int idx, int arg, const std::string& what) { return read_vector<2>(L, idx, arg, what, false); }

Vec3 check_vec3(lua_State* L, int idx, bool allow_2d) {
  if (lua_type(L, idx) != LUA_TTABLE) throw ArgError{idx, "point {x, y, z} expected, got " + type_name(L, idx)};
  return to_vec3(L, idx, idx, "point", allow_2d);
}
Vec2 check_vec2(lua_State* L, int idx) {
  if (lua_type(L, idx) != LUA_TTABLE) throw ArgError{idx, "point {x, y} expected, got " + type_name(L, idx)};
  return to_vec2(L, idx, idx, "point");
}

void push_vec3(lua_State* L, const Vec3& v) {
  lua_createtable(L, 3, 0);
  for (int i = 0; i < 3; ++i) {
    lua_pushnumber(L, v[i]);
    lua_rawseti(L, -2, i + 1);
  }
}
void push_vec2(lua_State* L, const Vec2& v) {
  lua_createtable(L, 2, 0);
  for (int i = 0; i < 2; ++i) {
    lua_pushnumber(L, v[i]);
    lua_rawseti(L, -2, i + 1);
  }
}

// --- Options ---

Options::Options(lua_State* L, int arg) : L_(L), arg_(arg), idx_(lua_absindex(L, arg)) {
  if (lua_type(L, idx_) != LUA_TTABLE) throw ArgError{arg, "table of options expected, got " + type_name(L, idx_)};
}

Options::Options(lua_State* L, int idx, int arg, std::string name)
    : L_(L), arg_(arg), idx_(lua_absindex(L, idx)), prefix_(std::move(name)) {
  if (lua_type(L, idx_) != LUA_TTABLE) throw ArgError{arg, "field '" + prefix_ + "' must be a table, got " + type_name(L, idx_)};
}

std::string Options::field(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }

void Options::mark(const char* key) {
  if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
}

int Options::push(const char* key) {
  mark(key);
  lua_pushstring(L_, key);
  return lua_rawget(L_, idx_);
}

bool Options::has(const char* key) {
  int t = push(key);
  lua_pop(L_, 1);
  return t != LUA_TNIL;
}

std::optional<double> Options::number(const char* key) {
  int t = push(key);
  double v = lua_tonumber(L_, -1);
  lua_pop(L_, 1);
  if (t == LUA_TNIL) return std::nullopt;
  if (t != LUA_TNUMBER) {
    push(key);
    std::string got = type_name(L_, -1);
    lua_pop(L_, 1);
    throw ArgError{arg_, "field '" + field(key) + "' must be a number, got " + got};
  }
  if (!std::isfinite(v)) throw ArgError{arg_, "field '" + field(key) + "' must be finite, got " + format_number(v)};
  return v;
}

double Options::number(const char* key, double fallback) { return number(key).value_or(fallback); }

double Options::positive(const char* key, double fallback) {
  double v = number(key, fallback);
  if (!(v > 0)) throw ArgError{arg_, "field '" + field(key) + "' must be positive, got " + format_number(v)};
  return v;
}

int Options::integer(const char* key, int fallback) {
  auto v = number(key);
  if (!v) return fallback;
  if (*v != std::floor(*v) || std::fabs(*v) > 2e9)
    throw ArgError{arg_, "field '" + field(key) + "' must be an integer, got " + format_number(*v)};
  return static_cast<int>(*v);
}

bool Options::boolean(const char* key, bool fallback) {
  int t = push(key);
  bool v = lua_toboolean(L_, -1);
  std::string got = t == LUA_TNIL || t == LUA_TBOOLEAN ? "" : type_name(L_, -1);
  lua_pop(L_, 1);
  if (t == LUA_TNIL) return fallback;
  if (t != LUA_TBOOLEAN) throw ArgError{arg_, "field '" + field(key) + "' must be a boolean, got " + got};
  return v;
}

std::string Options::string(const char* key, const std::string& fallback) {
  int t = push(key);
  std::string v = t == LUA_TSTRING ? lua_tostring(L_, -1) : "";
  std::string got = t == LUA_TNIL || t == LUA_TSTRING ? "" : type_name(L_, -1);
  lua_pop(L_, 1);
  if (t == LUA_TNIL) return fallback;
  if (t != LUA_TSTRING) throw ArgError{arg_, "field '" + field(key) + "' must be a string, got " + got};
  return v;
}

namespace {
// Reads the value on top of the stack with `read`, then pops it, also when `read` throws.
template <class T, class F>
T read_and_pop(lua_State* L, F&& read) {
  std::optional<T> v;
  std::optional<ArgError> err;
  try {
    v = read();
  } catch (const ArgError& e) {
    err = e;
  }
  lua_pop(L, 1);
  if (err) throw *err;
  return *v;
}
}  // namespace

std::optional<Vec3> Options::vec3(const char* key, bool allow_2d) {
  if (push(key) == LUA_TNIL) {
    lua_pop(L_, 1);
    return std::nullopt;
  }
  return read_and_pop<Vec3>(L_, [&] { return to_vec3(L_, -1, arg_, "field '" + field(key) + "'", allow_2d); });
}

Vec3 Options::vec3(const char* key, const Vec3& fallback, bool allow_2d) { return vec3(key, allow_2d).value_or(fallback); }

Vec2 Options::vec2(const char* key, const Vec2& fallback) {
  if (push(key) == LUA_TNIL) {
    lua_pop(L_, 1);
    return fallback;
  }
  return read_and_pop<Vec2>(L_, [&] { return to_vec2(L_, -1, arg_, "field '" + field(key) + "'"); });
}

namespace {
// Whether the key at `key` is one of the elements 1..#t of the table at `table`.
// (A float key with an integer value, [2.0], is stored as the integer 2.)
bool is_element_key(lua_State* L, int key, int table) {
  if (!lua_isinteger(L, key)) return false;
  const lua_Integer k = lua_tointeger(L, key);
  return k >= 1 && static_cast<lua_Unsigned>(k) <= lua_rawlen(L, table);
}
}  // namespace

void Options::finish() {
  lua_pushnil(L_);
  while (lua_next(L_, idx_)) {
    lua_pop(L_, 1);  // the value; the key stays for lua_next
    if (lua_type(L_, -1) == LUA_TSTRING) {
      std::string key = lua_tostring(L_, -1);
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
        lua_pop(L_, 1);
        std::string names;
        for (const auto& k : known_) names += (names.empty() ? "" : ", ") + k;
        throw ArgError{arg_, "unknown field '" + field(key) + "'" + (names.empty() ? "" : " (known: " + names + ")")};
      }
    } else if (!positional_ || !is_element_key(L_, -1, idx_)) {
      // A number key outside 1..#t (group{s, [10] = s}, [1.5] = s) is no element either: it was
      // dropped without a word, where [true] = s was refused.
      const bool number = lua_type(L_, -1) == LUA_TNUMBER;
      std::string what = describe(L_, -1);
      lua_pop(L_, 1);
      throw ArgError{arg_, "unexpected key " + what + " in " + (prefix_.empty() ? std::string("options table") : "field '" + prefix_ + "'") +
                               (positional_ && number ? " (the elements are numbered 1.." + std::to_string(lua_rawlen(L_, idx_)) + ", without gaps)" : "")};
    }
  }
}

// --- classes ---

namespace {
// The __index of a class's table of methods: a name that is no method (s.foo, s.volum) is an
// error naming it and the class's methods, not a silent nil that fails later, further away
// ("attempt to call a nil value"). Upvalue 1: the class's name; argument 1: the methods.
int unknown_member(lua_State* L) {
  return guarded(L, [&] {
    const std::string cls = lua_tostring(L, lua_upvalueindex(1));
    std::vector<std::string> names;
    lua_pushnil(L);
    while (lua_next(L, 1)) {
      if (lua_type(L, -2) == LUA_TSTRING) names.emplace_back(lua_tostring(L, -2));
      lua_pop(L, 1);
    }
    std::sort(names.begin(), names.end());
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    const std::string known = names.empty() ? " (it has none)" : " (it has " + list + ")";
    if (lua_type(L, 2) != LUA_TSTRING) throw Error(cls + " has no field " + describe(L, 2) + known);
    throw Error(cls + " has no field or method '" + std::string(lua_tostring(L, 2)) + "'" + known);
    return 0;
  });
}

// The __newindex of a class without one of its own: s.foo = 1 says what cannot be done, not Lua's
// "attempt to index a Solid value". Upvalue 1: the class's name.
int no_field_to_set(lua_State* L) {
  return guarded(L, [&] {
    const std::string cls = lua_tostring(L, lua_upvalueindex(1));
    const std::string key = lua_type(L, 2) == LUA_TSTRING ? "'" + std::string(lua_tostring(L, 2)) + "'" : describe(L, 2);
    throw Error("cannot set field " + key + " of a " + cls + ": it has no fields to set (use its methods)");
    return 0;
  });
}
}  // namespace

void register_class(lua_State* L, const char* registry_key, const char* display_name, const luaL_Reg* methods,
                    const luaL_Reg* metamethods, lua_CFunction gc) {
  // Methods are named "Class:method" where the call site gives no name (see raise_pending).
  if (methods) {
    push_names(L);
    for (const luaL_Reg* m = methods; m->name; ++m) {
      lua_pushcfunction(L, m->func);
      if (lua_rawget(L, -2) == LUA_TNIL) {
        lua_pushcfunction(L, m->func);
        lua_pushfstring(L, "%s:%s", display_name, m->name);
        lua_rawset(L, -4);
      }
      lua_pop(L, 1);
    }
    lua_pop(L, 1);
  }
  luaL_newmetatable(L, registry_key);
  lua_pushstring(L, display_name);
  lua_setfield(L, -2, "__name");
  lua_newtable(L);
  if (methods) luaL_setfuncs(L, methods, 0);
  lua_createtable(L, 0, 1);
  lua_pushstring(L, display_name);
  lua_pushcclosure(L, unknown_member, 1);
  lua_setfield(L, -2, "__index");
  lua_setmetatable(L, -2);
  lua_setfield(L, -2, "__index");
  lua_pushstring(L, display_name);
  lua_pushcclosure(L, no_field_to_set, 1);
  lua_setfield(L, -2, "__newindex");
  if (metamethods) luaL_setfuncs(L, metamethods, 0);  // a class's own __index / __newindex wins
  lua_pushcfunction(L, gc);
  lua_setfield(L, -2, "__gc");
  lua_pop(L, 1);
}

void set_functions(lua_State* L, const luaL_Reg* functions) { luaL_setfuncs(L, functions, 0); }

}  // namespace wedge::lua
