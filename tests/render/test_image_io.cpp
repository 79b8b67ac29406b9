// PNG and PFM output that fails, and PNG input that lies: the old file stays whole, no temporary
// is left, the message gives the system's reason; a tiny PNG declaring a huge image is refused
// before anything of that size is allocated.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "kernel/file_io.h"
#include "render/render.h"

using namespace wedge;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("wedge-img-" + std::to_string(::getpid()) + "-" + std::to_string(rand()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::size_t count() const { return std::size_t(std::distance(fs::directory_iterator(path), fs::directory_iterator())); }
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::size_t g_fail_at = 0, g_seen = 0;
ssize_t failing_write(int fd, const void* data, std::size_t size) {
  if (g_seen + size > g_fail_at) {
    if (g_fail_at > g_seen) {
      ssize_t n = ::write(fd, data, g_fail_at - g_seen);
      if (n > 0) g_seen += std::size_t(n);
      return n;
    }
    errno = ENOSPC;
    return -1;
  }
  ssize_t n = ::write(fd, data, size);
  if (n > 0) g_seen += std::size_t(n);
  return n;
}

struct HookGuard {
  FileHooks saved = file_hooks();
  ~HookGuard() { file_hooks() = saved; }
};

// PNG's CRC-32 (ISO 3309), for making chunks by hand.
std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

std::string be32(std::uint32_t x) {
  return {char(x >> 24), char(x >> 16), char(x >> 8), char(x)};
}

std::string chunk(const std::string& type, const std::string& data) {
  return be32(std::uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

}  // namespace

TEST_CASE("a PNG or PFM write that fails keeps the old file and leaves no temporary", "[render][image_io]") {
  TempDir dir;
  render::Image im;
  im.width = 300, im.height = 200;
  im.rgba.resize(std::size_t(im.width) * im.height * 4);
  for (std::size_t i = 0; i < im.rgba.size(); ++i) im.rgba[i] = std::uint8_t(i * 2654435761u >> 24);  // incompressible
  std::vector<float> depth(std::size_t(im.width) * im.height, 0.5f);
  const std::string png = dir.file("out.png"), pfm = dir.file("depth.pfm");
  render::write_png(png, im);
  render::write_pfm(pfm, im.width, im.height, depth);
  const std::string old_png = slurp(png), old_pfm = slurp(pfm);
  for (bool tmpfile : {true, false})
    for (std::size_t at : {std::size_t(0), std::size_t(8), std::size_t(40), old_pfm.size() / 2, old_pfm.size() - 1}) {
      INFO("failing at byte " << at << " tmpfile=" << tmpfile);
      HookGuard guard;
      file_hooks().tmpfile = tmpfile;
      file_hooks().write = failing_write;
      g_fail_at = at, g_seen = 0;
      if (at < old_png.size())
        CHECK_THROWS_WITH(render::write_png(png, im), Catch::Contains("cannot write '" + png + "': No space left on device"));
      g_seen = 0;
      CHECK_THROWS_WITH(render::write_pfm(pfm, im.width, im.height, depth), Catch::Contains("No space left on device"));
      CHECK(slurp(png) == old_png);
      CHECK(slurp(pfm) == old_pfm);
      CHECK(dir.count() == 2);
    }
  CHECK(render::read_png(png).rgba == im.rgba);
}

TEST_CASE("a small PNG that declares a huge image is refused before allocating it", "[render][image_io]") {
  TempDir dir;
  const std::string sig = "\x89PNG\r\n\x1a\n";
  // 16384 x 16384 RGBA: 1 GiB decoded, declared in a 57-byte file.
  std::string ihdr = be32(16384) + be32(16384) + std::string{8, 6, 0, 0, 0};
  std::string file = sig + chunk("IHDR", ihdr) + chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) + chunk("IEND", "");
  std::ofstream(dir.file("huge.png"), std::ios::binary) << file;
  CHECK_THROWS_WITH(render::read_png(dir.file("huge.png")), Catch::Contains("declares 16384 x 16384 pixels"));
  // Truncated files, a folder and a text file are errors naming the path.
  std::ofstream(dir.file("cut.png"), std::ios::binary) << file.substr(0, 20);
  CHECK_THROWS_WITH(render::read_png(dir.file("cut.png")), Catch::Contains("cut.png"));
  fs::create_directory(dir.file("dir.png"));
  CHECK_THROWS_WITH(render::read_png(dir.file("dir.png")), Catch::Contains("it is a folder"));
  std::ofstream(dir.file("text.png")) << "not a png";
  CHECK_THROWS_WITH(render::read_png(dir.file("text.png")), Catch::Contains("is not a readable PNG"));
}

TEST_CASE("a texture larger than 8192 x 8192 texels is refused before it is decoded", "[render][image_io]") {
  // A 1 MB PNG of 16384 x 16384 (one colour compresses 1000:1) took 3.5 GB and 30 s as a texture.
  TempDir dir;
  const std::string sig = "\x89PNG\r\n\x1a\n";
  std::string ihdr = be32(8193) + be32(8192) + std::string{8, 6, 0, 0, 0};
  std::ofstream(dir.file("big.png"), std::ios::binary)
      << sig + chunk("IHDR", ihdr) + chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8)) + chunk("IEND", "");
  CHECK_THROWS_WITH(render::Texture::load_png(dir.file("big.png")),
                    Catch::Contains("is 8193 x 8192 pixels, more than the 67108864 allowed here (8192 x 8192)"));
  CHECK_THROWS_WITH(render::read_png(dir.file("big.png"), 100), Catch::Contains("more than the 100 allowed here (10 x 10)"));
}
