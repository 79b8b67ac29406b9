// The hostile mesh files of tests/tessellate/bad_files (made by make.py there): each must be
// refused with a message naming the file, the place and what is wrong (expected.txt), and none
// may need more memory than the file's size suggests: a child process parses them all under a
// 256 MiB address-space limit, where a header believed would need gigabytes.
#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include "csg/solid.h"
#include "tessellate/tessellate.h"

using namespace wedge;
namespace fs = std::filesystem;

namespace {

struct BadFile {
  std::string path, expect;
};

std::vector<BadFile> bad_files() {
  const fs::path dir = fs::path(WEDGE_SOURCE_DIR) / "tests/tessellate/bad_files";
  std::ifstream in(dir / "expected.txt");
  std::vector<BadFile> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    auto tab = line.find('\t');
    out.push_back({(dir / line.substr(0, tab)).string(), line.substr(tab + 1)});
  }
  return out;
}

// What import() does: read the file, make a solid of it.
void import_file(const std::string& path) { Solid::from_mesh(read_mesh(path), path); }

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;  // ASan reserves terabytes of address space: no RLIMIT_AS
#else
constexpr bool kSanitized = false;
#endif

}  // namespace

TEST_CASE("every hostile mesh file is refused with a message naming the file, the place and the fault", "[mesh_io][bad_files]") {
  auto files = bad_files();
  REQUIRE(files.size() >= 30);
  for (const auto& f : files) {
    INFO(f.path);
    try {
      import_file(f.path);
      FAIL("accepted");
    } catch (const Error& e) {
      const std::string msg = e.what();
      CHECK_THAT(msg, Catch::Contains(f.expect));
      CHECK_THAT(msg, Catch::Contains(fs::path(f.path).filename().string()));
    }
  }
}

TEST_CASE("a folder, a missing file and a file that is not a file are refused naming the path and why", "[mesh_io][bad_files]") {
  const fs::path dir = fs::temp_directory_path() / ("wedge-bad-" + std::to_string(::getpid()));
  fs::create_directories(dir / "folder.stl");
  struct Cleanup {
    fs::path p;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(p, ec);
    }
  } cleanup{dir};
  const std::string folder = (dir / "folder.stl").string(), missing = (dir / "missing.obj").string();
  CHECK_THROWS_WITH(import_file(folder), "cannot read '" + folder + "': it is a folder");
  CHECK_THROWS_WITH(import_file(missing), "cannot read '" + missing + "': No such file or directory");
  CHECK_THROWS_WITH(import_file("/dev/null.off"), Catch::Contains("cannot read '/dev/null.off'"));
  CHECK_THROWS_WITH(import_file((dir / "noext").string()), Catch::Contains("unknown mesh format '(no extension)'"));
}

TEST_CASE("hostile mesh files are refused within a 256 MiB address space", "[mesh_io][bad_files]") {
  if (kSanitized) return;
  auto files = bad_files();
  int fds[2];
  REQUIRE(::pipe(fds) == 0);
  pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    ::close(fds[0]);
    rlimit lim{256u << 20, 256u << 20};
    ::setrlimit(RLIMIT_AS, &lim);
    std::string report;
    for (const auto& f : files) {
      try {
        import_file(f.path);
        report += f.path + ": accepted\n";
      } catch (const Error&) {
      } catch (const std::exception& e) {
        report += f.path + ": " + e.what() + "\n";  // std::bad_alloc: a count was believed
      }
    }
    (void)!::write(fds[1], report.data(), report.size());
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string report;
  char buf[4096];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) report.append(buf, std::size_t(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  CHECK(WIFEXITED(status));
  CHECK(report == "");
}

namespace {
// A temporary folder of the test's own files, removed at the end.
struct Folder {
  fs::path dir;
  explicit Folder(const std::string& name) : dir(fs::temp_directory_path() / (name + std::to_string(::getpid()))) {
    fs::create_directories(dir);
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return (dir / name).string();
  }
};

const std::string kTetV = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
std::string obj_tet() { return "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"; }
std::string off_tet() { return "OFF\n4 4 0\n" + kTetV + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"; }
std::string ply_tet(const std::string& vt = "float", const std::string& it = "int") {
  return "ply\nformat ascii 1.0\nelement vertex 4\nproperty " + vt + " x\nproperty " + vt + " y\nproperty " + vt +
         " z\nelement face 4\nproperty list uchar " + it + " vertex_indices\nend_header\n" + kTetV + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
}
std::string stl_tet() {
  std::string s = "solid t\n";
  for (const char* f : {"0 0 0|0 1 0|1 0 0", "0 0 0|1 0 0|0 0 1", "0 0 0|0 0 1|0 1 0", "1 0 0|0 1 0|0 0 1"}) {
    std::string t = f;
    s += "facet normal 0 0 0\nouter loop\nvertex " + t.substr(0, 5) + "\nvertex " + t.substr(6, 5) + "\nvertex " + t.substr(12, 5) +
         "\nendloop\nendfacet\n";
  }
  return s + "endsolid t\n";
}
std::string replaced(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
  return s;
}
}  // namespace

TEST_CASE("text as editors save it reads as plain text: BOM, CR or CRLF line ends, tabs, relative indices", "[mesh_io][bad_files]") {
  Folder f("wedge-odd-");
  const std::string bom = "\xEF\xBB\xBF";
  std::vector<std::string> files = {
      // A UTF-8 byte order mark made an OBJ's first line unknown (vertex 1 vanished: "index 4 is out
      // of range"), an OFF "not an OFF file", a PLY "not a PLY file", an STL a binary one.
      f.write("bom.obj", bom + obj_tet()), f.write("bom.off", bom + off_tet()), f.write("bom.ply", bom + ply_tet()),
      f.write("bom.stl", bom + stl_tet()),
      // Lines ended by CR alone (classic Mac OS) read as one line: "holds no triangles".
      f.write("cr.obj", replaced(obj_tet(), "\n", "\r")), f.write("cr.off", replaced(off_tet(), "\n", "\r")),
      f.write("cr.stl", replaced(stl_tet(), "\n", "\r")), f.write("cr.ply", replaced(ply_tet(), "\n", "\r")),
      f.write("crlf.obj", replaced(obj_tet(), "\n", "\r\n")), f.write("crlf.ply", replaced(ply_tet(), "\n", "\r\n")),
      f.write("tabs.obj", replaced(obj_tet(), " ", "\t")),
      // OBJ's negative indices count back from the last vertex so far.
      f.write("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf -4 -2 -3\nf -4 -3 -1\nf -3 -2 -1\nf -4 -1 -2\n"),
      f.write("types.ply", ply_tet("int8", "uint32")), f.write("double.ply", ply_tet("float64", "uint16")),
      f.write("header_line.off", replaced(off_tet(), "OFF\n", "OFF ")),
  };
  for (const std::string& path : files) {
    INFO(path);
    const Solid s = Solid::from_mesh(read_mesh(path), path);
    CHECK(s.mass_properties(Tolerance{}).volume == Approx(1.0 / 6).epsilon(1e-15));
    CHECK(s.mesh(Tolerance{}).triangles.size() == 4);
  }
}

TEST_CASE("a FIFO is refused at once, and a file rewritten while it is read is read or refused by name", "[mesh_io][bad_files]") {
  Folder f("wedge-fifo-");
  const std::string fifo = (f.dir / "pipe.obj").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  // No writer: opening it for reading must not wait for one.
  CHECK_THROWS_WITH(import_file(fifo), "cannot read '" + fifo + "': not a regular file");
  // A writer rewrites the file in place (truncate, then write) between a tetrahedron and a longer
  // one while the reader reads it: each read sees some prefix of some version, and must give a
  // solid or an error naming the file, never a crash, a hang or a partial solid.
  const std::string path = f.write("moving.off", off_tet());
  std::atomic<bool> stop{false};
  std::thread writer([&] {
    for (int i = 0; !stop; ++i) std::ofstream(path, std::ios::binary | std::ios::trunc) << (i % 2 ? off_tet() + "# padding\n" : off_tet());
  });
  int read = 0, refused = 0;
  for (int k = 0; k < 300; ++k) {
    try {
      const Solid s = Solid::from_mesh(read_mesh(path), path);
      CHECK(s.mass_properties(Tolerance{}).volume == Approx(1.0 / 6).epsilon(1e-15));
      ++read;
    } catch (const Error& e) {
      CHECK_THAT(e.what(), Catch::Contains("moving.off"));
      ++refused;
    }
  }
  stop = true;
  writer.join();
  INFO(read << " read, " << refused << " refused");
  CHECK(read + refused == 300);  // every one of them read or refused by name, none stuck
}
