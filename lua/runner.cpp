// The script runner, modelled on lua.c: load, pcall with a traceback handler, report
// "file:line: message" and a non-zero exit on error.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <ostream>
#include <sstream>

#include "csg/solid.h"
#include "tessellate/progress.h"

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

// Ctrl-C, as lua.c does it: the handler sets a flag and a hook that stops the script at its next
// instruction; an evaluation of the CSG tree polls the flag between nodes and engine stages.
std::atomic<bool> g_interrupted{false};
lua_State* g_state = nullptr;

void interrupt_hook(lua_State* L, lua_Debug*) {
  lua_sethook(L, nullptr, 0, 0);
  luaL_error(L, "interrupted");
}

extern "C" void on_sigint(int) {
  g_interrupted = true;
  if (g_state) lua_sethook(g_state, interrupt_hook, LUA_MASKCALL | LUA_MASKRET | LUA_MASKCOUNT, 1);
}

// A progress bar on stderr ("\r[#####     ] evaluating the CSG tree 3/8"): shown when stderr is a
// terminal (or WEDGE_PROGRESS=always) and not --quiet, after half a second of work (at once with
// WEDGE_PROGRESS=always), erased when the work ends. Called from any of TBB's threads.
class EvalBar {
 public:
  EvalBar(bool quiet, std::string what) : what_(std::move(what)) {
    const char* mode = std::getenv("WEDGE_PROGRESS");
    const std::string m = mode ? mode : "";
    always_ = m == "always";
    enabled_ = !quiet && m != "never" && (always_ || ::isatty(2));
  }
  // `done` of `total` steps; the bar is erased when done reaches total.
  void update(std::size_t done, std::size_t total) {
    if (!enabled_ || total == 0) return;
    if (done >= total) return clear();
    {
      // Reports from several threads may arrive out of order: the bar never goes back.
      std::lock_guard<std::mutex> lock(mutex_);
      if (done < last_done_) return;
      last_done_ = done;
    }
    draw(double(done) / double(total), what_ + " " + std::to_string(done) + "/" + std::to_string(total));
  }
  // A fraction done (0..1) and the text after the bar.
  void draw(double fraction, const std::string& text) {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (start_ == 0) start_ = RunStats::now();
    if (!always_ && RunStats::now() - start_ < 0.5) return;
    constexpr int kWidth = 30;
    const int filled = std::clamp(int(kWidth * fraction), 0, kWidth);
    std::fprintf(stderr, "\r[%s%s] %s", std::string(std::size_t(filled), '#').c_str(),
                 std::string(std::size_t(kWidth - filled), ' ').c_str(), text.c_str());
    std::fflush(stderr);
    shown_ = true;
  }
  void clear() {
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    if (shown_) std::fprintf(stderr, "\r%80s\r", "");
    std::fflush(stderr);
    shown_ = false;
    start_ = 0;
    last_done_ = 0;
  }
  ~EvalBar() {
    if (shown_) std::fprintf(stderr, "\r%80s\r", "");
  }

 private:
  std::string what_;
  std::mutex mutex_;
  bool enabled_ = false, always_ = false, shown_ = false;
  double start_ = 0;
  std::size_t last_done_ = 0;
};

void report_eval_stats(const EvalStats& s, std::ostream& err) {
  if (s.booleans == 0 && s.tessellate == 0 && s.rebuild == 0) return;
  char line[160];
  err << "wedge: CSG evaluation by stage (summed over the booleans; they may run in parallel)\n";
  const std::pair<const char*, double> rows[] = {{"tessellation", s.tessellate}, {"checks", s.check},
                                                 {"broad phase", s.broad},       {"intersection", s.arrange},
                                                 {"classification", s.classify}, {"output", s.output},
                                                 {"rebuild", s.rebuild}};
  for (const auto& [name, ms] : rows) {
    std::snprintf(line, sizeof line, "  %-14s %10.1f ms\n", name, ms);
    err << line;
  }
  err << "  " << s.booleans << " engine calls, " << s.pruned << " pruned by bounding boxes, " << s.cached
      << " answered from the cache\n";
  if (s.remade > 0)
    err << "  " << s.remade << " moved results made again from moved operands (rounding spoiled the moved mesh)\n";
}

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
  // CSG evaluations of this run: progress bar, Ctrl-C, time per stage.
  EvalStats eval_stats;
  EvalBar bar(options.quiet, "evaluating the CSG tree");
  // A tessellation at a fine tolerance shows the points made against the size estimate's count
  // (those of this thread only: a CSG tree's operands tessellated in parallel do not report).
  EvalBar mesh_bar(options.quiet, "tessellating");
  const TessellateProgress mesh_progress = [&mesh_bar](std::size_t done, std::size_t expected, bool finished) {
    if (finished) return mesh_bar.clear();
    // The estimate is a guide (within about 1/8 to 4 times the real count): the bar stops short
    // of full when the count passes it, and the text says both.
    mesh_bar.draw(std::min(0.99, double(done) / double(expected)),
                  "tessellating: " + std::to_string(done) + " points, about " + std::to_string(expected) + " expected");
  };
  set_tessellate_progress(&mesh_progress);
  // Ctrl-C inside a long tessellation of this thread (s:triangles{tolerance = 1e-6}, an export)
  // stops it at once; a CSG tree's own leaves poll its cancel (csg/solid.cpp).
  const TessellatePoll mesh_poll = [] {
    if (g_interrupted.load()) throw Cancelled();
  };
  set_tessellate_poll(&mesh_poll);
  EvalControl control;
  control.progress = [&bar](std::size_t done, std::size_t total) { bar.update(done, total); };
  control.cancelled = [] { return g_interrupted.load(); };
  if (options.stats) control.stats = &eval_stats;
  set_eval_control(&control);
  g_interrupted = false;
  g_state = L;
  struct sigaction action {}, previous{};
  action.sa_handler = on_sigint;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previous);
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
    std::ostringstream message;
    status = call_chunk(L, static_cast<int>(args.size()), message);
    if (status != 0 && g_interrupted) {
      err << "wedge: interrupted by Ctrl-C: " << path << " stopped (no output file is left half-written)\n";
      status = 130;
    } else {
      err << message.str();
    }
  }
  sigaction(SIGINT, &previous, nullptr);
  g_state = nullptr;
  set_eval_control(nullptr);
  set_tessellate_progress(nullptr);
  set_tessellate_poll(nullptr);
  if (options.stats) {
    install_stats(L, nullptr);
    report_stats(stats, RunStats::now() - start, path, err);
    report_eval_stats(eval_stats, err);
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
