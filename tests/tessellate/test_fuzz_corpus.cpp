// The fuzz corpus of the mesh readers (tests/data/fuzz/<format>/: the seeds, hostile files and
// whatever fuzz/run's minimised corpora hold) replayed through the parser that import() uses, in
// every build (under the sanitizers too): each file is read or refused with a wedge::Error that
// names the file; no other exception, no crash, no sanitizer report.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "kernel/error.h"
#include "tessellate/mesh_io.h"

using namespace wedge;
namespace fs = std::filesystem;

TEST_CASE("the mesh readers' fuzz corpus replays: every file read or refused by name", "[tessellate][fuzz]") {
  for (const char* format : {"stl", "obj", "ply", "off"}) {
    const fs::path dir = fs::path(WEDGE_SOURCE_DIR) / "tests/data/fuzz" / format;
    std::size_t files = 0, read = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      const std::string name = entry.path().filename().string();
      INFO(format << " file " << name);
      ++files;
      try {
        Mesh m = parse_mesh(bytes, format, name);
        CHECK(m.triangle_count() > 0);
        ++read;
      } catch (const Error& e) {
        CHECK_THAT(e.what(), Catch::Contains(name));
      }
    }
    INFO(format);
    CHECK(files >= 3);
    CHECK(read >= 1);  // the seeds are valid files
  }
}
