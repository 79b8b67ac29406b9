// The PNG reader's fuzz corpus (tests/data/fuzz/png/: seeds and fuzz/run's minimised corpus)
// replayed through decode_png, which read_png and textures use, in every build: each file is
// decoded or refused with a wedge::Error naming it; no other exception, crash or sanitizer report.
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
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
  CHECK(read >= 7);  // the seven seeds: RGBA, grey, palette with transparency, 16-bit RGB, grey + alpha,
                     // 1-bit grey, Adam7-interlaced RGBA
}

// Seeds written by Python's zlib (tests/data/fuzz/png/, not by wedge's PNG writer), decoded pixel
// by pixel: the Adam7-interlaced RGBA image holds (50x, 50y, 25(x + y), 255 - 10x) at column x,
// row y from the top; the 1-bit grey one alternates black and white, starting white on row 1.
TEST_CASE("PNG seeds from another writer decode to their pixels: Adam7 interlaced, 1-bit grey", "[render][fuzz]") {
  const fs::path dir = fs::path(WEDGE_SOURCE_DIR) / "tests/data/fuzz/png";
  auto load = [&](const char* name) {
    std::ifstream in(dir / name, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return render::decode_png(bytes, name);
  };
  const render::Image a = load("seed_interlaced.png");
  REQUIRE(a.width == 5);
  REQUIRE(a.height == 5);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x) {
      INFO(x << ", " << y);
      CHECK(a.pixel(x, y) == std::array<std::uint8_t, 4>{std::uint8_t(50 * x), std::uint8_t(50 * y),
                                                          std::uint8_t(25 * (x + y)), std::uint8_t(255 - 10 * x)});
    }
  const render::Image g = load("seed_grey1.png");
  REQUIRE(g.width == 8);
  REQUIRE(g.height == 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 8; ++x) {
      const std::uint8_t v = ((x + y) % 2 == 0) ? 255 : 0;
      INFO(x << ", " << y);
      CHECK(g.pixel(x, y) == std::array<std::uint8_t, 4>{v, v, v, 255});
    }
}
