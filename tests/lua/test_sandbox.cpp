// `wedge run --sandbox`: a stranger's script tries every way out (programs, native code, files
// outside its folder and the output folder, bytecode, the debug library) and each is refused with
// a message; what a model script needs (its own folder, the output folder, require of a sibling
// module, export/render into the output folder) still works. Run through the real executable.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace {

struct Result {
  int status;
  std::string output;
};

Result run(const std::string& command) {
  Result r{0, ""};
  std::FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  REQUIRE(p);
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.output.append(buf, n);
  r.status = ::pclose(p);
  return r;
}

// Each escape runs in pcall; the script prints BLOCKED or ESCAPED for each, by name.
const char* kEscapes = R"(
local outside = ...
local function try(name, f)
  local ok, err = pcall(f)
  if ok then print("ESCAPED " .. name) else print("BLOCKED " .. name .. ": " .. tostring(err)) end
end
try("os.execute", function() return os.execute("true") end)
try("io.popen", function() return io.popen("id"):read("a") end)
try("package.loadlib", function() return package.loadlib("libc.so.6", "*") end)
-- The search paths are put back after each try, so that the script's own require below works
-- also without --sandbox (the test runs it both ways and wants it to reach its end).
local function with_paths(path, cpath, f)
  local p, c = package.path, package.cpath
  package.path, package.cpath = path or p, cpath or c
  local ok, r = pcall(f)
  package.path, package.cpath = p, c
  if not ok then error(r, 0) end
  return r
end
try("require of a C module", function() return with_paths(nil, "/usr/lib/x86_64-linux-gnu/lua/5.4/?.so", function() return require("lpeg") end) end)
try("require from another folder", function() return with_paths(outside .. "/?.lua", nil, function() return require("evil") end) end)
try("os.getenv", function() return os.getenv("HOME") end)
try("os.tmpname", function() return os.tmpname() end)
try("io.open outside for reading", function() return assert(io.open("/etc/passwd")):read("a") end)
try("io.open outside for writing", function() return assert(io.open(outside .. "/owned.txt", "w")) end)
try("io.open through ..", function() return assert(io.open(SCRIPT_DIR .. "/../../etc/hostname")) end)
try("io.lines outside", function() for l in io.lines("/etc/passwd") do return l end end)
try("io.output outside", function() return io.output(outside .. "/owned.txt") end)
try("io.input outside", function() return io.input("/etc/passwd") end)
try("os.remove outside", function() return assert(os.remove(outside .. "/keep.txt")) end)
try("os.rename out of the folder", function() return assert(os.rename(SCRIPT_DIR .. "/mine.txt", outside .. "/stolen.txt")) end)
try("dofile outside", function() return dofile(outside .. "/evil.lua") end)
try("loadfile outside", function() return assert(loadfile(outside .. "/evil.lua"))() end)
try("binary chunk", function() return assert(load(string.dump(function() return 1 end), "x", "b"))() end)
try("binary chunk by default mode", function() return assert(load(string.dump(function() return 1 end)))() end)
try("debug.getregistry", function() return debug.getregistry() end)
try("debug.getupvalue", function() return debug.getupvalue(io.open, 1) end)
try("export outside", function() return export(box(1, 1, 1), outside .. "/x.stl") end)
try("import outside", function() return import(outside .. "/tet.off") end)
try("render outside", function() return render{box(1, 1, 1), out = outside .. "/x.png", size = {8, 8}} end)
try("texture outside", function() return box(1, 1, 1):material{texture = outside .. "/t.png"} end)
try("canvas save outside", function() return canvas{width = 2, height = 2}:save(outside .. "/c.png") end)
try("symbolic link out", function() return assert(io.open(SCRIPT_DIR .. "/link/keep.txt")) end)
-- What a model script needs still works.
local f = assert(io.open(SCRIPT_DIR .. "/mine.txt", "w")); f:write("ok"); f:close()
assert(io.open(SCRIPT_DIR .. "/mine.txt"):read("a") == "ok")
assert(require("helper") == 42)
assert(export(box(1, 1, 1), params.out .. "/part.stl") == 12)
render{box(1, 1, 1), out = params.out .. "/part.png", size = {8, 8}}
canvas{width = 2, height = 2}:save(params.out .. "/canvas.png")
assert(import(params.out .. "/part.stl"):volume() > 0.99)
print("WORKS")
)";

}  // namespace

TEST_CASE("wedge run with the sandbox flag refuses every escape and keeps what a model script needs", "[lua][sandbox]") {
  const fs::path root = fs::temp_directory_path() / ("wedge-sandbox-" + std::to_string(::getpid()));
  const fs::path dir = root / "model", out = root / "out", outside = root / "outside";
  for (const auto& d : {dir, out, outside}) fs::create_directories(d);
  std::ofstream(dir / "escape.lua") << "SCRIPT_DIR = '" << dir.string() << "'\n" << kEscapes;
  std::ofstream(dir / "helper.lua") << "return 42\n";
  std::ofstream(outside / "evil.lua") << "print('ESCAPED evil.lua ran') return 1\n";
  std::ofstream(outside / "keep.txt") << "keep";
  std::ofstream(outside / "tet.off") << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  fs::create_directory_symlink(outside, dir / "link");

  Result r = run(std::string(WEDGE_EXE) + " run --sandbox " + (dir / "escape.lua").string() + " " + outside.string() +
                 " out=" + out.string());
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(r.output.find("ESCAPED") == std::string::npos);
  std::size_t blocked = 0;
  for (std::size_t at = r.output.find("BLOCKED"); at != std::string::npos; at = r.output.find("BLOCKED", at + 1)) ++blocked;
  CHECK(blocked == 27);
  CHECK_THAT(r.output, Catch::Contains("BLOCKED os.execute: ") && Catch::Contains("os.execute is not available under --sandbox"));
  CHECK_THAT(r.output, Catch::Contains("cannot read '/etc/passwd': under --sandbox a script may use files in '" + dir.string() + "' or '" +
                                       out.string() + "' only"));
  CHECK_THAT(r.output, Catch::Contains("WORKS"));
  CHECK(fs::exists(outside / "keep.txt"));
  CHECK(!fs::exists(outside / "owned.txt"));
  CHECK(!fs::exists(outside / "x.stl"));
  CHECK(!fs::exists(outside / "c.png"));
  CHECK(fs::exists(out / "part.stl"));
  CHECK(fs::exists(out / "canvas.png"));

  // Without --sandbox the same script escapes (the test would notice a sandbox that does nothing).
  // (From the script's folder: without --sandbox, require finds helper.lua through "./?.lua".)
  Result free = run("cd '" + dir.string() + "' && " + std::string(WEDGE_EXE) + " run " + (dir / "escape.lua").string() + " " + outside.string() + " out=" + out.string());
  INFO(free.output);
  CHECK(free.status == 0);  // the script ran to its end, not only far enough to print the line
  CHECK_THAT(free.output, Catch::Contains("ESCAPED io.open outside for reading"));
  fs::remove_all(root);
}

// Without out= the script's own folder is the one allowed (it was none: the params table was
// taken for the list of folders), and a path with a NUL byte is refused, not cut short: the file
// functions would stop at the NUL and write "evil.stl" outside while the check saw a path inside.
TEST_CASE("wedge run --sandbox without out= writes beside the script, a NUL in a path is refused", "[lua][sandbox]") {
  const fs::path root = fs::temp_directory_path() / ("wedge-sandbox-noout-" + std::to_string(::getpid()));
  const fs::path dir = root / "model", outside = root / "outside";
  for (const auto& d : {dir, outside}) fs::create_directories(d);
  std::ofstream(dir / "s.lua") << "assert(export(box(1, 1, 1), '" << (dir / "here.stl").string() << "') == 12)\n"
                               << "local ok, err = pcall(export, box(1, 1, 1), '" << outside.string()
                               << "/evil.stl\\0/../../model/x.stl')\n"
                               << "print(ok, err)\n"
                               << "local ok2, err2 = pcall(export, box(1, 1, 1), '" << outside.string() << "/x.stl')\n"
                               << "print(ok2, err2)\n";
  Result r = run(std::string(WEDGE_EXE) + " run --sandbox " + (dir / "s.lua").string());
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK(fs::exists(dir / "here.stl"));
  CHECK_THAT(r.output, Catch::Contains("false\texport: cannot write '" + outside.string() +
                                       "/evil.stl\\0/../../model/x.stl': a file name cannot hold a NUL byte"));
  CHECK_THAT(r.output, Catch::Contains("under --sandbox a script may use files in '" + dir.string() + "' only"));
  CHECK(fs::is_empty(outside));
  fs::remove_all(root);
}

// A refused file access names the script's line and the function, as export's refusal does: it
// was "sandbox: cannot read '/etc/passwd': ..." with neither. A removed debug function says it is
// not available, where debug.getregistry() gave "attempt to call a nil value".
TEST_CASE("wedge run --sandbox refusals give the script's file and line and the function", "[lua][sandbox]") {
  const fs::path root = fs::temp_directory_path() / ("wedge-sandbox-where-" + std::to_string(::getpid()));
  const fs::path dir = root / "model";
  fs::create_directories(dir);
  std::ofstream(dir / "loc.lua") << "local function try(f) local ok, err = pcall(f) print(err) end\n"
                                 << "try(function() local f = io.open('/etc/passwd') end)\n"
                                 << "try(function() local f = io.lines('/etc/passwd') end)\n"
                                 << "try(function() local f = dofile('/etc/passwd') end)\n"
                                 << "try(function() local f = loadfile('/etc/passwd') end)\n"
                                 << "try(function() local f = os.remove('/etc/passwd') end)\n"
                                 << "try(function() local f = os.rename('/etc/passwd', '/etc/x') end)\n"
                                 << "try(function() local f = debug.getregistry() end)\n"
                                 << "try(function() local f = debug.getupvalue(print, 1) end)\n"
                                 << "try(function() local f = export(box(1, 1, 1), '/etc/x.stl') end)\n";
  // From the script's folder, so that the chunk name is short enough for Lua to show it whole.
  Result r = run("cd '" + dir.string() + "' && " + std::string(WEDGE_EXE) + " run --sandbox loc.lua");
  INFO(r.output);
  CHECK(r.status == 0);
  const std::string script = "loc.lua";
  CHECK_THAT(r.output, Catch::Contains(script + ":2: io.open: sandbox: cannot read '/etc/passwd': under --sandbox"));
  CHECK_THAT(r.output, Catch::Contains(script + ":3: io.lines: sandbox: cannot read '/etc/passwd'"));
  CHECK_THAT(r.output, Catch::Contains(script + ":4: dofile: sandbox: cannot read '/etc/passwd'"));
  CHECK_THAT(r.output, Catch::Contains(script + ":5: loadfile: sandbox: cannot read '/etc/passwd'"));
  CHECK_THAT(r.output, Catch::Contains(script + ":6: os.remove: sandbox: cannot write '/etc/passwd'"));
  CHECK_THAT(r.output, Catch::Contains(script + ":7: os.rename: sandbox: cannot write '/etc/passwd'"));
  CHECK_THAT(r.output, Catch::Contains(script + ":8: debug.getregistry is not available under --sandbox"));
  CHECK_THAT(r.output, Catch::Contains(script + ":9: debug.getupvalue is not available under --sandbox"));
  CHECK_THAT(r.output, Catch::Contains(script + ":10: export: sandbox: cannot write '/etc/x.stl'"));
  fs::remove_all(root);
}

// The paths an export derives from the one it is given pass the same check: export{split=true}'s
// "stem-K-symbol.ext" per part, and the ".mtl" beside an OBJ with colours. A symbolic link of that
// name shipped beside the script led the write outside (only the base path was checked).
TEST_CASE("wedge run --sandbox checks each path a split export or an OBJ material library derives", "[lua][sandbox]") {
  const fs::path root = fs::temp_directory_path() / ("wedge-sandbox-split-" + std::to_string(::getpid()));
  const fs::path dir = root / "model", outside = root / "outside";
  for (const auto& d : {dir, outside}) fs::create_directories(d);
  for (const char* name : {"victim.stl", "victim.mtl"}) std::ofstream(outside / name) << "SECRET";
  fs::create_symlink("../outside/victim.stl", dir / "out-2-solid.stl");
  fs::create_symlink("../outside/victim.mtl", dir / "red.mtl");
  std::ofstream(dir / "s.lua") << "print(pcall(export, group{box(1, 1, 1), box(2, 2, 2)}, 'out.stl', {split = true}))\n"
                               << "local red = box(1, 1, 1):material{diffuse = {1, 0, 0}}\n"
                               << "print(pcall(export, red, 'red.obj'))\n"
                               << "print(#export(group{box(1, 1, 1)}, 'in.stl', {split = true}))\n";
  Result r = run("cd '" + dir.string() + "' && " + std::string(WEDGE_EXE) + " run --sandbox s.lua");
  INFO(r.output);
  CHECK(r.status == 0);
  CHECK_THAT(r.output, Catch::Contains("false\texport: sandbox: cannot write 'out-2-solid.stl': under --sandbox"));
  CHECK_THAT(r.output, Catch::Contains("false\texport: sandbox: cannot write 'red.mtl': under --sandbox"));
  CHECK(!fs::exists(dir / "out-1-solid.stl"));  // refused before anything is written
  CHECK(!fs::exists(dir / "red.obj"));
  CHECK(fs::exists(dir / "in-1-solid.stl"));  // a split export inside the folder still works
  for (const char* name : {"victim.stl", "victim.mtl"}) {
    std::ifstream in(outside / name);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    CHECK(text == "SECRET");
  }
  fs::remove_all(root);
}
