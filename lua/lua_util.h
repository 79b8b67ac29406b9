// Helpers every binding uses. The rule they enforce: no Lua error (a longjmp) is ever raised while
// a C++ frame with a destructor is live. Bindings run their body inside guarded(); argument checks
// throw ArgError, kernel code throws wedge::Error, and guarded() turns either into a Lua error
// only after the catch block has ended and the C++ objects are gone. The messages follow Lua's
// own: "bad argument #2 to 'translate' (number expected, got string)", at the caller's file:line.
#pragma once
#include <lua.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "kernel/kernel.h"

namespace wedge::lua {

// An error in argument `arg` of the running function; `message` goes inside the parentheses.
struct ArgError {
  int arg;
  std::string message;
};

// Raises the error whose message is on top of the Lua stack: as an argument error when arg > 0.
// Never returns. It runs after every C++ object of the failed call has been destroyed.
// The function is named as Lua names it at the call site (`box(...)`, `matrix.rotate(...)`,
// `s:translate(...)`); where the call site gives no name (called as a value: `pcall(matrix.rotate,
// "x")`, or through a local or upvalue) the API's own name is used ("matrix.rotate",
// "Solid:translate"; for a method the object counts as argument #0, as in a method call).
int raise_pending(lua_State* L, int arg);

// The name raise_pending would give the running C function ("" if it has none).
std::string running_function_name(lua_State* L);
// Records the API's name of every function in the table at api_idx (and one level of sub-tables:
// "matrix.rotate") for raise_pending. Names recorded by register_class stay unless the API table
// holds the same function.
void name_functions(lua_State* L, int api_idx);

// A progress bar on stderr for long work ("\r[#####     ] drawing views 3/8"), shown only when
// stderr is a terminal, the run is not --quiet, and the work has run for half a second; the line
// is erased when the work ends. WEDGE_PROGRESS=always shows it from the first step (for tests),
// WEDGE_PROGRESS=never never.
class Progress {
 public:
  Progress(lua_State* L, std::string what, std::size_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  void step();  // one more of `total` done

 private:
  std::string what_;
  std::size_t total_, done_ = 0;
  double start_;
  bool enabled_, shown_ = false, always_ = false;
};
// Marks the state as --quiet (no progress bars).
void set_quiet(lua_State* L, bool quiet);

// Time per stage for `wedge run --stats`. A binding opens a Stage around its work; nothing is
// recorded unless the runner has installed a RunStats in this state. Stages nest; each stage is
// charged its own time, not that of the stages inside it.
struct RunStats {
  struct Entry {
    std::string name;
    double seconds = 0;
    long calls = 0;
  };
  std::vector<Entry> entries;  // in order of first use
  struct Open {
    double start, inner;
  };
  std::vector<Open> open;
  void add(const std::string& name, double seconds);
  static double now();
};
void install_stats(lua_State* L, RunStats* stats);  // nullptr removes it
class Stage {
 public:
  Stage(lua_State* L, const char* name);
  ~Stage();
  Stage(const Stage&) = delete;
  Stage& operator=(const Stage&) = delete;

 private:
  RunStats* stats_;
  const char* name_;
  std::size_t depth_ = 0;
};

template <class F>
int guarded(lua_State* L, F&& body) {
  int arg = 0;
  {
    std::string message;
    try {
      return body();
    } catch (const ArgError& e) {
      arg = e.arg;
      message = e.message;
    } catch (const std::exception& e) {
      message = e.what();
    } catch (...) {
      message = "unknown C++ exception";
    }
    // Hand the message to Lua; the std::string dies at the end of this block, before the longjmp.
    lua_pushlstring(L, message.data(), message.size());
  }
  return raise_pending(L, arg);
}

// "field 'size'" and element 2 -> "field 'size[2]'"; "point" -> "point coordinate 2" (noun).
std::string element_name(const std::string& what, long long k, const char* noun);
// "field 'camera.near' must be ..." -> "camera.near must be ..."; other messages unchanged.
std::string field_message(const std::string& m);

// For functions that take one table of options (box{...}, array{...}, s:material{...}, render{...}):
// like guarded(), but an error in that table (argument `arg`) is named by its field path and the
// function rather than by an argument number: "box: size[2] must be a number, got string".
template <class F>
int table_call(lua_State* L, int arg, F&& body) {
  return guarded(L, [&] {
    try {
      return body();
    } catch (const ArgError& e) {
      if (e.arg != arg || lua_type(L, arg) != LUA_TTABLE) throw;
      throw Error(field_message(e.message));
    }
  });
}

// Runs f, turning a wedge::Error it throws into an ArgError on argument `arg` (for kernel
// constructors whose message is about one argument).
template <class F>
auto as_arg(int arg, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Error& e) {
    throw ArgError{arg, e.what()};
  }
}

// A number as text for messages, with up to 10 significant digits.
std::string number_text(double x);

// The name Lua shows for the value at idx: its metatable's __name, or its type name.
std::string type_name(lua_State* L, int idx);
std::string describe(lua_State* L, int idx);  // "number 3", "string 'abc'", "nil", ...

// Argument checks (they throw ArgError). Numbers must be finite.
// For a function that takes exactly `n` arguments (no options table): an argument n+1 is an error
// ("sweep(profile, path, {twist = 5})" silently ignored its third argument).
void check_no_more(lua_State* L, int n);
// The same for a solid's constructor, whose positional form has no place for `center`: an extra
// true or false (OpenSCAD's cube(10, true)) is told where center goes, `table_form` ("cube{size=s,
// center=true}").
void check_no_more(lua_State* L, int n, const char* table_form);
// For a method (self at index 1, not counted in the message: s:translate(x, y, z) takes 3).
void check_no_more_method(lua_State* L, int n);
double check_number(lua_State* L, int idx);
double opt_number(lua_State* L, int idx, double fallback);
bool check_boolean(lua_State* L, int idx);
std::string check_string(lua_State* L, int idx);
int check_integer(lua_State* L, int idx);
void check_table(lua_State* L, int idx);
// A point {x, y, z}; a 2-element table is accepted as {x, y, 0} only if allow_2d.
Vec3 check_vec3(lua_State* L, int idx, bool allow_2d = false);
Vec2 check_vec2(lua_State* L, int idx);
// Reads the table at the top of the stack (not an argument slot) as a vector; `what` names it in
// errors ("field 'center'").
Vec3 to_vec3(lua_State* L, int idx, int arg, const std::string& what, bool allow_2d = false);
Vec2 to_vec2(lua_State* L, int idx, int arg, const std::string& what);

void push_vec3(lua_State* L, const Vec3& v);
void push_vec2(lua_State* L, const Vec2& v);

// A table of named options at argument `arg`. Each accessor records the field as known; finish()
// rejects any field that was never asked for ("unknown field 'raduis'").
class Options {
 public:
  Options(lua_State* L, int arg);
  // A table nested in argument `arg` (at stack index idx), named `field` in messages:
  // "field 'camera.near' must be a number".
  Options(lua_State* L, int idx, int arg, std::string name);
  bool has(const char* key);
  double number(const char* key, double fallback);
  std::optional<double> number(const char* key);
  double positive(const char* key, double fallback);  // > 0
  int integer(const char* key, int fallback);
  bool boolean(const char* key, bool fallback);
  std::string string(const char* key, const std::string& fallback);
  Vec3 vec3(const char* key, const Vec3& fallback, bool allow_2d = false);
  std::optional<Vec3> vec3(const char* key, bool allow_2d = false);
  Vec2 vec2(const char* key, const Vec2& fallback);
  // Pushes the field's value (possibly nil) and returns its Lua type; the caller pops it.
  int push(const char* key);
  // Also accept the array part (t[1], t[2], ...) without complaint.
  void allow_positional() { positional_ = true; }
  void finish();
  // The key as messages name it: "near", or "camera.near" in a nested table.
  std::string field(const std::string& key) const;
  int arg() const { return arg_; }
  lua_State* state() const { return L_; }

 private:
  void mark(const char* key);
  lua_State* L_;
  int arg_;
  int idx_;
  std::string prefix_;
  bool positional_ = false;
  std::vector<std::string> known_;
};

// --- userdata holding a C++ value -----------------------------------------------------------
// The userdata stores a pointer to a heap copy, so any alignment works (Eigen types included);
// __gc deletes it and clears the pointer, so running it twice is harmless.
void register_class(lua_State* L, const char* registry_key, const char* display_name, const luaL_Reg* methods,
                    const luaL_Reg* metamethods, lua_CFunction gc);

template <class T>
int gc_object(lua_State* L) {
  auto** p = static_cast<T**>(lua_touserdata(L, 1));
  if (p && *p) {
    delete *p;
    *p = nullptr;
  }
  return 0;
}

template <class T>
T& push_object(lua_State* L, const char* registry_key, T value) {
  auto** slot = static_cast<T**>(lua_newuserdatauv(L, sizeof(T*), 0));
  *slot = nullptr;
  luaL_setmetatable(L, registry_key);
  *slot = new T(std::move(value));
  return **slot;
}

// The object at idx, or nullptr if it is not of this class.
template <class T>
T* test_object(lua_State* L, int idx, const char* registry_key) {
  auto** p = static_cast<T**>(luaL_testudata(L, idx, registry_key));
  return p ? *p : nullptr;
}

template <class T>
T& check_object(lua_State* L, int idx, const char* registry_key, const char* display_name) {
  T* p = test_object<T>(L, idx, registry_key);
  if (!p) throw ArgError{idx, std::string(display_name) + " expected, got " + type_name(L, idx)};
  return *p;
}

// Sets table[name] = f for each entry, on the table at the top of the stack.
void set_functions(lua_State* L, const luaL_Reg* functions);

}  // namespace wedge::lua
