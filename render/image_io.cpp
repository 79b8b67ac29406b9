// PNG through libspng, and PFM for depth. Every file is written to "<path>.tmp.<random>" in the
// same directory and renamed into place, so a reader never sees a half-written image.
#include <spng.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

#include "render/render.h"

namespace wedge::render {

namespace {

void write_atomically(const std::string& path, const void* data, std::size_t size) {
  std::random_device rd;
  std::string tmp = path + ".tmp." + std::to_string(rd());
  {
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) fail("cannot write '", path, "': ", std::strerror(errno));
    bool ok = std::fwrite(data, 1, size, f) == size;
    ok = (std::fclose(f) == 0) && ok;
    if (!ok) {
      std::remove(tmp.c_str());
      fail("cannot write '", path, "': write failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    fail("cannot write '", path, "': ", ec.message());
  }
}

struct SpngFree {
  void operator()(spng_ctx* c) const { spng_ctx_free(c); }
};

}  // namespace

void write_png(const std::string& path, const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() != std::size_t(image.width) * image.height * 4)
    fail("write_png '", path, "': image is empty or malformed");
  std::unique_ptr<spng_ctx, SpngFree> ctx(spng_ctx_new(SPNG_CTX_ENCODER));
  if (!ctx) fail("write_png '", path, "': out of memory");
  spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  spng_ihdr ihdr{};
  ihdr.width = std::uint32_t(image.width);
  ihdr.height = std::uint32_t(image.height);
  ihdr.bit_depth = 8;
  ihdr.color_type = SPNG_COLOR_TYPE_TRUECOLOR_ALPHA;
  spng_set_ihdr(ctx.get(), &ihdr);
  int err = spng_encode_image(ctx.get(), image.rgba.data(), image.rgba.size(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  if (err) fail("write_png '", path, "': ", spng_strerror(err));
  std::size_t len = 0;
  void* buf = spng_get_png_buffer(ctx.get(), &len, &err);
  if (!buf) fail("write_png '", path, "': ", spng_strerror(err));
  std::unique_ptr<void, void (*)(void*)> owned(buf, std::free);
  write_atomically(path, buf, len);
}

Image read_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("cannot open PNG '", path, "': ", std::strerror(errno));
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::unique_ptr<spng_ctx, SpngFree> ctx(spng_ctx_new(0));
  if (!ctx) fail("read_png '", path, "': out of memory");
  spng_set_image_limits(ctx.get(), 16384, 16384);
  spng_set_png_buffer(ctx.get(), bytes.data(), bytes.size());
  spng_ihdr ihdr{};
  int err = spng_get_ihdr(ctx.get(), &ihdr);
  if (err) fail("'", path, "' is not a readable PNG: ", spng_strerror(err));
  std::size_t size = 0;
  err = spng_decoded_image_size(ctx.get(), SPNG_FMT_RGBA8, &size);
  if (err) fail("'", path, "': ", spng_strerror(err));
  Image im;
  im.width = int(ihdr.width), im.height = int(ihdr.height);
  im.rgba.resize(size);
  err = spng_decode_image(ctx.get(), im.rgba.data(), size, SPNG_FMT_RGBA8, SPNG_DECODE_TRNS);
  if (err) fail("'", path, "': ", spng_strerror(err));
  return im;
}

void write_pfm(const std::string& path, int width, int height, const std::vector<float>& values) {
  if (width <= 0 || height <= 0 || values.size() != std::size_t(width) * height)
    fail("write_pfm '", path, "': ", values.size(), " values do not fill ", width, "x", height);
  std::string header = "Pf\n" + std::to_string(width) + " " + std::to_string(height) + "\n-1.0\n";
  std::vector<char> data(header.begin(), header.end());
  const char* p = reinterpret_cast<const char*>(values.data());
  data.insert(data.end(), p, p + values.size() * sizeof(float));
  write_atomically(path, data.data(), data.size());
}

}  // namespace wedge::render
