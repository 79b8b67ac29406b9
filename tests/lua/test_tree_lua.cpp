// s:contains, s:cells and s:faces from Lua: answers against closed forms, and errors that name
// the argument.
#include <catch2/catch.hpp>

#include <sstream>

#include "lua/wedge_lua.h"

namespace {
struct Run {
  int status;
  std::string err;
};
Run run(const std::string& code) {
  std::ostringstream err;
  int status = wedge::lua::run_string(code, "@tree.lua", err);
  return {status, err.str()};
}
}  // namespace

TEST_CASE("s:contains answers inside, outside and boundary on primitives and booleans", "[lua][tree]") {
  auto r = run(R"(
    local b = box(2, 2, 2)
    assert(b:contains{1, 1, 1} == "inside")
    assert(b:contains{2, 1, 1} == "boundary")
    assert(b:contains{2, 2, 2} == "boundary")
    assert(b:contains{3, 1, 1} == "outside")
    local d = b - box(2, 2, 2):translate(1, 1, 1)
    assert(d:contains{1.5, 1.5, 1.5} == "outside")
    assert(d:contains{1, 1.5, 1.5} == "boundary")
    assert(d:contains{0.5, 1.5, 1.5} == "inside")
    local s = sphere(1)
    assert(s:contains{0, 0, 0.9} == "inside")
    assert(s:contains{0, 0, 1.1} == "outside")
    assert(s:contains{0, 0, 1} == "boundary")
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("s:cells brackets the volume and lists its boxes on request", "[lua][tree]") {
  auto r = run(R"(
    local c = box(1, 2, 3):cells{size = 0.25}
    assert(c.volume_min <= 6 and c.volume_max >= 6, c.volume_min .. " " .. c.volume_max)
    assert(c.inside > 0 and c.boundary > 0 and c.outside >= 0)
    assert(c.boxes == nil)
    local s = sphere(1)
    local coarse, fine = s:cells(0.5), s:cells{size = 0.125, boxes = true}
    local v = 4 / 3 * math.pi
    assert(fine.volume_min <= v and v <= fine.volume_max)
    assert(fine.volume_max - fine.volume_min < coarse.volume_max - coarse.volume_min)
    assert(#fine.boxes == fine.inside + fine.boundary + fine.outside)
    local b = fine.boxes[1]
    assert(#b.min == 3 and #b.max == 3 and (b.state == "inside" or b.state == "outside" or b.state == "boundary"))
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("s:cells' boxes become solids that export and render as a voxel model", "[lua][tree]") {
  // The issue's "the cells can be rendered or exported as boxes": the inside and boundary cells of
  // a box [0,2]^3 at size 0.5 as one scene, written as PLY: 12 triangles a cell (touching cells
  // share faces, so the file is not one solid to import), their total volume between volume_min
  // and volume_max; rendered to a PNG.
  const std::string dir = std::string(WEDGE_BINARY_DIR) + "/cells_export";
  auto r = run("local dir = '" + dir + "'\n" + R"lua(
    os.execute("mkdir -p " .. dir)
    local c = box(2, 2, 2):cells{size = 0.5, boxes = true}
    local g, n, v = group{}, 0, 0
    for _, b in ipairs(c.boxes) do
      if b.state ~= "outside" then
        local w = {b.max[1] - b.min[1], b.max[2] - b.min[2], b.max[3] - b.min[3]}
        g:add(box(w[1], w[2], w[3]):translate(b.min[1], b.min[2], b.min[3]))
        n, v = n + 1, v + w[1] * w[2] * w[3]
      end
    end
    assert(n == c.inside + c.boundary, n)
    assert(v >= c.volume_min - 1e-12 and v <= c.volume_max + 1e-12, v)
    export(g, dir .. "/cells.ply", {ascii = true})
    local ply = assert(io.open(dir .. "/cells.ply")):read("a")
    local faces = tonumber(ply:match("element face (%d+)"))
    assert(faces == 12 * n, faces .. " " .. n)
    render{g, out = dir .. "/cells.png", size = {64, 64}, view = "iso"}
    local f = assert(io.open(dir .. "/cells.png", "rb"))
    assert(f:read(4) == "\x89PNG")
    f:close()
  )lua");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("s:faces lists the faces a boolean kept, with their surfaces", "[lua][tree]") {
  auto r = run(R"(
    local kinds = function(s)
      local k = {}
      for _, f in ipairs(s:faces()) do k[f.surface] = (k[f.surface] or 0) + 1 end
      return k
    end
    local k = kinds(sphere(1) - cube(2))
    assert(k.sphere == 1 and k.plane == 3, "sphere minus cube")
    k = kinds(cylinder(1, 2))
    assert(k.cylinder == 2 and k.plane == 2)
    k = kinds(torus{R = 2, r = 0.5})
    assert(k.torus == 2)
    k = kinds(cone{r1 = 1, r2 = 0.5, h = 1})
    assert(k.cone == 2)
    -- Through a boolean: cones, revolved and extruded surfaces keep their names, and the cuts are
    -- planes.
    k = kinds(cone{r1 = 1, r2 = 0.5, h = 1} - cube(2))
    assert(k.cone and k.plane == 4, "cone minus cube")
    k = kinds(revolve(polygon{{0.5, 0}, {1, 0}, {1, 1}, {0.5, 1}}) - cube(3))
    assert(k.revolved and k.plane == 2, "revolved minus cube")
    k = kinds(extrude(catmull_rom{points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, closed = true}, 1) - cube(0.5))
    assert(k.extruded and k.plane and k.plane >= 5, "extruded minus cube")
    for _, s in ipairs{cone{r1 = 1, h = 1} * sphere(0.8), revolve(polygon{{0.5, 0}, {1, 0}, {1, 1}}) + cube(0.2)} do
      for name in pairs(kinds(s)) do
        assert(({plane = 1, cone = 1, sphere = 1, revolved = 1})[name], "unexpected surface " .. name)
      end
    end
    local f = box(1, 2, 3):faces()
    assert(#f == 6 and f[1].surface == "plane" and f[1].loops == 1)
    local total = 0
    for _, x in ipairs(f) do total = total + x.area end
    assert(math.abs(total - 22) < 1e-12)
    local plate = box(4, 4, 1) - box(2, 2, 3):translate(1, 1, -1)
    local rings = 0
    for _, x in ipairs(plate:faces()) do if x.loops == 2 then rings = rings + 1 end end
    assert(#plate:faces() == 10 and rings == 2)
    local e = plate:euler()
    assert(e.F == 10 and e.R == 2 and e.H == 1 and e.S == 1)
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("a swept tube along a bend goes through booleans at the default tolerance, and s:faces names its faces", "[lua][tree]") {
  // At chordal 0.01 the tube's side had thin triangles along the bend turned over against the
  // surface (each point within the tolerance, the mesh folded onto itself): every boolean with it
  // failed with "the first operand intersects itself". A loft and a sweep keep their names.
  auto r = run(R"(
    local tube = sweep(circle(0.1), bezier{{0, 0, 0}, {1, 0, 1}, {2, 0, 0}})
    for _, t in ipairs{0.01, 0.003} do
      tolerance(t)
      local cut = tube - cube(5):translate(1, -2.5, -2.5)
      assert(cut:is_valid(), "valid at " .. t)
      local v = cut:volume()
      assert(math.abs(v - tube:volume() / 2) < 1e-3 * v, "half the tube at " .. t .. ": " .. v)
      local names = {}
      for _, f in ipairs(cut:faces()) do names[f.surface] = (names[f.surface] or 0) + 1 end
      assert(names.swept == 2 and names.plane == 2, "faces at " .. t)
    end
    local duct = loft{profiles = {circle(1), circle(0.5)}, heights = {0, 2}} - cube(5)
    local k = {}
    for _, f in ipairs(duct:faces()) do k[f.surface] = (k[f.surface] or 0) + 1 end
    assert(k.lofted == 2, "lofted faces")
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("s:faces gives each face its surface as a Surface with its outward side", "[lua][tree]") {
  // sphere(1) minus cube(2): the spherical face's geometry is the unit sphere (points at distance
  // 1 from the origin, outward normal equal to the point); the cut planes x = 0, y = 0, z = 0
  // have outward normals +x, +y, +z.
  auto r = run(R"(
    local d = sphere(1) - cube(2)
    local spheres, planes = 0, 0
    for _, f in ipairs(d:faces()) do
      local S = f.geometry
      assert(S, "face without geometry")
      for _, uv in ipairs{{0.2, 0.3}, {0.5, 0.5}, {0.8, 0.6}} do
        local p, n = S:eval(uv[1], uv[2]), S:normal(uv[1], uv[2])
        if f.reversed then n = {-n[1], -n[2], -n[3]} end
        if f.surface == "sphere" then
          assert(math.abs(math.sqrt(p[1]^2 + p[2]^2 + p[3]^2) - 1) < 1e-12)
          assert(math.abs(n[1] * p[1] + n[2] * p[2] + n[3] * p[3] - 1) < 1e-9)
        else
          local a = math.abs(n[1]) > 0.5 and 1 or math.abs(n[2]) > 0.5 and 2 or 3
          assert(math.abs(p[a]) < 1e-12 and math.abs(n[a] - 1) < 1e-12, "plane " .. a)
        end
      end
      if f.surface == "sphere" then spheres = spheres + 1 else planes = planes + 1 end
    end
    assert(spheres == 1 and planes == 3)
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}

TEST_CASE("s:contains and s:cells name a bad argument", "[lua][tree]") {
  auto bad = [](const std::string& code) { return run(code).err; };
  CHECK_THAT(bad("box(1,1,1):contains(3)"), Catch::Contains("tree.lua:1:") && Catch::Contains("contains"));
  CHECK_THAT(bad("box(1,1,1):contains{0/0, 0, 0}"), Catch::Contains("tree.lua:1:"));
  CHECK_THAT(bad("box(1,1,1):cells{}"), Catch::Contains("tree.lua:1: cells: size is required"));
  CHECK_THAT(bad("box(1,1,1):cells{size = -1}"), Catch::Contains("size"));
  CHECK_THAT(bad("box(1,1,1):cells{size = 1, bogus = 2}"), Catch::Contains("bogus"));
  CHECK_THAT(bad("box(1,1,1):cells(0)"), Catch::Contains("size must be positive"));
}

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

namespace {
struct Interrupted {
  int exit_code = -1;
  double seconds_after_signal = 0;
  std::string err;
};
// Runs `wedge run` on the script, sends SIGINT `delay` after the script has started, and waits
// for the exit. The script's first statement creates a file the test waits for: a signal sent
// before wedge has set its handler (a slow start, as under the sanitizers on a busy machine)
// would kill it instead of testing the handler.
Interrupted interrupt(const std::string& script, std::chrono::milliseconds delay) {
  const std::string dir = std::string(WEDGE_BINARY_DIR) + "/tests";
  const std::string path = dir + "/interrupt-" + std::to_string(::getpid()) + ".lua";
  const std::string errpath = path + ".err";
  const std::string readypath = path + ".ready";
  std::remove(readypath.c_str());
  std::ofstream(path) << "assert(io.open(\"" << readypath << "\", \"w\")):close() " << script;
  Interrupted r;
  pid_t pid = ::fork();
  if (pid == 0) {
    int fd = ::open(errpath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 2);
    ::execl(WEDGE_EXE, WEDGE_EXE, "run", path.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  for (int i = 0; i < 6000 && !std::ifstream(readypath); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::this_thread::sleep_for(delay);
  ::kill(pid, SIGINT);
  auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  ::waitpid(pid, &status, 0);
  r.seconds_after_signal = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(errpath);
  r.err.assign(std::istreambuf_iterator<char>(in), {});
  std::remove(path.c_str());
  std::remove(errpath.c_str());
  std::remove(readypath.c_str());
  return r;
}
}  // namespace

TEST_CASE("Ctrl-C stops a running script and a CSG evaluation cleanly", "[lua][tree][cli]") {
  SECTION("a Lua loop") {
    auto r = interrupt("while true do end\n", std::chrono::milliseconds(300));
    CHECK(r.exit_code == 130);
    CHECK_THAT(r.err, Catch::Contains("interrupted by Ctrl-C"));
  }
  SECTION("a long boolean") {
    // Many fine spheres unioned and subtracted: seconds of work, cancelled between stages.
    auto r = interrupt(R"(
      tolerance(1e-4)
      local s = box(10, 10, 1)
      local holes = {}
      for i = 1, 9 do for j = 1, 9 do holes[#holes + 1] = sphere(0.45):translate(i, j, 0.5) end end
      local d = difference(s, table.unpack(holes))
      print(d:volume())
    )", std::chrono::milliseconds(1500));
    CHECK(r.exit_code == 130);
    CHECK_THAT(r.err, Catch::Contains("interrupted by Ctrl-C"));
    // Generous: the 100 ms target is measured in bench/, not here.
    CHECK(r.seconds_after_signal < 5);
  }
  SECTION("a long tessellation outside any tree") {
    // About 4 s and 3.5 million triangles to the end (release build); the tessellator polls for
    // the interrupt every 1024 points, so it stops within milliseconds (it ran to the end before).
    auto r = interrupt("print(sphere(1):triangles{tolerance = 2e-6})\n", std::chrono::milliseconds(500));
    CHECK(r.exit_code == 130);
    CHECK_THAT(r.err, Catch::Contains("interrupted by Ctrl-C"));
    // Under AddressSanitizer, on a busy 2-core machine, a clean-clone CI run measured 2.3 s from
    // the signal to the exit (the whole tessellation takes many times longer there).
#if defined(__SANITIZE_ADDRESS__)
    CHECK(r.seconds_after_signal < 6);
#else
    CHECK(r.seconds_after_signal < 1.5);
#endif
  }
}

TEST_CASE("wedge run killed (SIGKILL) while exporting a large mesh leaves the old file and no temporary", "[lua][cli][write_failure]") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(WEDGE_BINARY_DIR) / "tests" / ("kill-export-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string part = (dir / "part.stl").string(), ref = (dir / "ref.stl").string(), ready = (dir / "ready").string();
  std::ofstream(part) << "the old file";
  const std::string script = (dir / "export.lua").string();
  // The same mesh to ref.stl (complete), then to part.stl again and again until killed.
  std::ofstream(script) << "tolerance(2e-4)\nlocal s = sphere(1)\nexport(s, '" << ref << "', {ascii = true})\n"
                        << "assert(io.open('" << ready << "', 'w')):close()\n"
                        << "while true do export(s, '" << part << "', {ascii = true}) end\n";
  pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    int fd = ::open("/dev/null", O_WRONLY);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::execl(WEDGE_EXE, WEDGE_EXE, "run", script.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  for (int i = 0; i < 60000 && !fs::exists(ready); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  // Kill it while its temporary file is open: an O_TMPFILE file shows in /proc as "<dir>/#<inode>
  // (deleted)", a named one as "<dir>/.part.stl.wedge-...".
  const fs::path fds = fs::path("/proc") / std::to_string(pid) / "fd";
  bool caught = false;
  for (int i = 0; i < 200000 && !caught; ++i) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fds, ec)) {
      std::error_code ec2;
      const std::string target = fs::read_symlink(e.path(), ec2).string();
      if (!ec2 && (target.rfind((dir / "#").string(), 0) == 0 || target.rfind((dir / ".part.stl.wedge-").string(), 0) == 0)) {
        caught = true;
        break;
      }
    }
    if (!caught) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  CHECK(caught);
  CHECK(WIFSIGNALED(status));
  auto slurp = [](const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  // part.stl is the old file, or (killed in a later round) a complete copy of ref.stl: never part of one.
  const std::string now = slurp(part), whole = slurp(ref);
  CHECK(whole.size() > 1000000);
  CHECK((now == "the old file" || now == whole));
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  // Nothing else, unless the kill fell in the instant between naming the temporary and renaming
  // it; such a leftover (its writer dead) is removed by the next export of the same file.
  if (left.size() == 5) {
    CHECK(left[0].rfind(".part.stl.wedge-" + std::to_string(pid) + "-", 0) == 0);
    std::ostringstream err;
    REQUIRE(wedge::lua::run_string("export(box(1, 1, 1), '" + part + "')", "cleanup.lua", err) == 0);
    left.erase(left.begin());
    std::vector<std::string> after;
    for (const auto& e : fs::directory_iterator(dir)) after.push_back(e.path().filename().string());
    CHECK(after.size() == 4);
  }
  CHECK(left == std::vector<std::string>{"export.lua", "part.stl", "ready", "ref.stl"});
  fs::remove_all(dir);
}

TEST_CASE("a script that applies one shape a thousand times finishes at once with the right volume", "[lua][tree][coincident]") {
  // Issue 14's case: one intersection of 1001 coincident boxes grew past 15 GB in one engine
  // pass. The copies are one operand (A * A = A + A = A, A - B - B = A - B), in chains and mixed.
  // The mixed chain nests two tree levels per step: 499 steps are 998 levels, the tree's limit,
  // in every build. (The evaluator recursed per level, and under AddressSanitizer the 8 MB main
  // stack overflowed at 300 steps; a deep tree is now evaluated from its leaves up.)
  const char* mixed_steps = "499";
  auto r = run(std::string("local mixed_steps = ") + mixed_steps + "\n" + R"(
    local s = box(1000, 1000, 1000)
    for i = 1, 1000 do s = s * box(1000, 1000, 1000) end
    assert(math.abs(s:volume() - 1e9) < 1e-3, s:volume())
    local d = box(1000, 1000, 1000)
    for i = 1, 1000 do d = d - box(1, 1, 1) end
    assert(math.abs(d:volume() - (1e9 - 1)) < 1e-3, d:volume())
    local e = box(10, 10, 10)
    for i = 1, 1000 do e = e - box(10, 10, 10) end
    assert(e:volume() == 0, e:volume())
    local u = box(2, 2, 2)
    for i = 1, 1000 do u = u + box(2, 2, 2) end
    assert(math.abs(u:volume() - 8) < 1e-12, u:volume())
    -- mixed: each step nests (s * B) - b
    local m = box(1000, 1000, 1000)
    for i = 1, mixed_steps do m = (m * box(1000, 1000, 1000)) - box(1, 1, 1) end
    assert(math.abs(m:volume() - (1e9 - 1)) < 1e-3, m:volume())
    assert(m:is_valid())
    -- transforms in the chain: each step nests a difference and a move (998 levels), released
    -- link by link (its destructors recursed through the transforms' children)
    local t = box(10, 10, 10)
    for i = 1, mixed_steps do t = (t - box(1, 1, 1)):translate(0.001, 0, 0) end
    local v = t:volume()
    assert(v > 998 and v < 999.5, v)
    t = nil
    collectgarbage()
  )");
  INFO(r.err);
  CHECK(r.status == 0);
}
