// The PNG reader's fuzz corpus (tests/data/fuzz/png/: seeds and fuzz/run's minimised corpus)
// replayed through decode_png, which read_png and textures use, in every build: each file is
// decoded or refused with a wedge::Error naming it; no other exception, crash or sanitizer report.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "kernel/error.h"
#include "render/png_decode.h"

using namespace wedge;
namespace fs = std::filesystem;

TEST_CASE("the PNG reader's fuzz corpus replays: every file decoded or refused by name", "[render][fuzz]") {
  const fs::path dir = fs::path(WEDGE_SOURCE_DIR) / "tests/data/fuzz/png";
  std::size_t files = 0, read = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string name = entry.path().filename().string();
    INFO(name);
    ++files;
    try {
      render::Image im = render::decode_png(bytes, name);
      CHECK(im.rgba.size() == std::size_t(im.width) * im.height * 4);
      ++read;
    } catch (const Error& e) {
      CHECK_THAT(e.what(), Catch::Contains(name));
    }
  }
  CHECK(files >= 3);
  CHECK(read >= 3);  // the three seeds: RGBA, grey, palette with transparency
}
