// The hostile mesh files of tests/tessellate/bad_files (made by make.py there): each must be
// refused with a message naming the file, the place and what is wrong (expected.txt), and none
// may need more memory than the file's size suggests: a child process parses them all under a
// 256 MiB address-space limit, where a header believed would need gigabytes.
#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

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
