// The same script gives the same bits whatever was asked before: a query of an intermediate solid
// (its volume, its bounds, an export of it, ...) must not change a later result built on it, nor
// may the thread count. Each run is a fresh Lua state that writes the result's exact numbers (%a)
// and its OBJ and STL files; the files of every run are compared byte for byte with the first's.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "lua/wedge_lua.h"

namespace fs = std::filesystem;

namespace {

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
  return s;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The queries a script may ask of the intermediate solid `c` before it builds `r` from it.
const char* const kQueries[] = {
    "",  // none: the reference
    "local _ = c:volume()",
    "local _ = c:area()",
    "local _ = c:bounds()",
    "local _ = c:triangles{}",
    "local _ = c:is_valid()",
    "local _ = c:faces()",
    "local _ = c:euler()",
    "local _ = c:contains{5, 5, 5}",
    "export(c, '$/c.stl')",
    "render{c, out = '$/c.png', size = {16, 16}, view = 'iso'}",
};

// Scripts whose `c` is a boolean of the same kind as the one `r` makes of it (so that r's node can
// take c's operands as its own). `Q` is replaced by the query. The result's numbers go to
// $/numbers.txt; a result that cannot be exported writes the error instead (the same one each time).
struct Case {
  const char* name;
  const char* code;
};
const Case kCases[] = {
    {"a drilled cube minus a sphere, plus a pin",
     "local c = cube(10) - cylinder(3, 10):translate(5, 5, 0)\n"
     "local s = sphere(4):translate(5, 5, 8)\n"
     "Q\n"
     "local r = (c - s) + cylinder(1, 15):translate(1, 1, 0)\n"},
    {"a drilled cube minus itself turned by 90 degrees (slivers)",
     "local c = cube(10) - cylinder(3, 10):translate(5, 5, 0)\n"
     "Q\n"
     "local r = c - c:rotate(90, {0, 0, 1}, {5, 5, 0})\n"},
    {"a union extended", "local c = cube(10) + sphere(4):translate(10, 5, 5)\nQ\nlocal r = c + cylinder(2, 20):translate(5, 5, -5)\n"},
    {"an intersection narrowed",
     "local c = sphere(6):translate(5, 5, 5) * cube(10)\nQ\nlocal r = c * cylinder(5, 20):translate(5, 5, -5)\n"},
    {"at a tolerance of its own (bounds evaluate at the default one)",
     "tolerance(0.05)\n"
     "local c = cube(10) - cylinder(3, 10):translate(5, 5, 0)\n"
     "Q\n"
     "local r = c - sphere(4):translate(5, 5, 8)\n"},
};

const char* const kReport =
    "local f = assert(io.open('$/numbers.txt', 'w'))\n"
    "local ok, e = pcall(function()\n"
    "  f:write(string.format('%a %a %d\\n', r:volume(), r:area(), r:triangles{}))\n"
    "  local b = r:bounds()\n"
    "  f:write(string.format('%a %a %a %a %a %a\\n', b.min[1], b.min[2], b.min[3], b.max[1], b.max[2], b.max[3]))\n"
    "  export(r, '$/r.obj')\n"
    "  export(r, '$/r.stl')\n"
    "end)\n"
    "if not ok then f:write('error: ', tostring(e), '\\n') end\n"
    "f:close()\n";

// The run's files: numbers.txt, r.obj, r.stl (absent ones as empty), removed after reading.
std::vector<std::string> run_case(const std::string& code, const fs::path& dir) {
  std::ostringstream err;
  const int status = wedge::lua::run_string(replace_all(code, "$", dir.string()), "@history.lua", err);
  INFO(err.str());
  CHECK(status == 0);
  std::vector<std::string> out;
  for (const char* name : {"numbers.txt", "r.obj", "r.mtl", "r.stl"}) out.push_back(read_bytes(dir / name));
  for (const auto& e : fs::directory_iterator(dir)) fs::remove(e.path());
  return out;
}

}  // namespace

TEST_CASE("history: a query of an intermediate solid does not change a later result's bits", "[lua][tree][history]") {
  const fs::path dir = fs::temp_directory_path() / ("wedge-history-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const Case& c : kCases) {
    std::vector<std::string> reference;
    for (const char* q : kQueries) {
      INFO(c.name << "; earlier query: " << (*q ? q : "none"));
      const std::vector<std::string> got = run_case(replace_all(c.code, "Q", q) + kReport, dir);
      if (reference.empty()) {
        reference = got;
        CHECK(!reference[0].empty());
        continue;
      }
      CHECK(got[0] == reference[0]);  // the numbers, or the same error
      CHECK(got[1] == reference[1]);  // the OBJ, byte for byte
      CHECK(got[2] == reference[2]);
      CHECK(got[3] == reference[3]);  // the STL
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("history: the same bits at 1 and 2 threads, with and without an earlier query", "[lua][tree][history]") {
  const fs::path dir = fs::temp_directory_path() / ("wedge-history-threads-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Case& c = kCases[0];
  std::vector<std::string> runs[4];
  for (int i = 0; i < 4; ++i) {
    tbb::global_control g(tbb::global_control::max_allowed_parallelism, i % 2 ? 2 : 1);
    runs[i] = run_case(replace_all(c.code, "Q", i < 2 ? "" : kQueries[1]) + kReport, dir);
  }
  for (int i = 1; i < 4; ++i) {
    INFO("run " << i);
    CHECK(runs[i] == runs[0]);
  }
  fs::remove_all(dir);
}
