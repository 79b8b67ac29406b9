// PNG through libspng, and PFM for depth. Every file is written through an AtomicFile
// (kernel/file_io.h): whole or not at all, with the system's reason on any error, and no
// temporary file left behind by a killed process.
#include <spng.h>

#include <cmath>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

#include "kernel/file_io.h"
#include "render/png_decode.h"
#include "render/render.h"

namespace wedge::render {

namespace {

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
  write_file_atomically(path, buf, len);
}

Image read_png(const std::string& path, std::size_t max_pixels) { return decode_png(read_file(path), path, max_pixels); }

Image decode_png(std::string_view bytes, const std::string& path, std::size_t max_pixels) {
  std::unique_ptr<spng_ctx, SpngFree> ctx(spng_ctx_new(0));
  if (!ctx) fail("read_png '", path, "': out of memory");
  spng_set_image_limits(ctx.get(), 16384, 16384);
  // Ancillary chunks (text, ICC profiles) are not kept: bound what they may ask for.
  spng_set_chunk_limits(ctx.get(), 1 << 20, 1 << 24);
  spng_set_png_buffer(ctx.get(), bytes.data(), bytes.size());
  spng_ihdr ihdr{};
  int err = spng_get_ihdr(ctx.get(), &ihdr);
  if (err) fail("'", path, "' is not a readable PNG: ", spng_strerror(err));
  if (std::size_t(ihdr.width) * ihdr.height > max_pixels) {
    const auto side = std::size_t(std::llround(std::sqrt(double(max_pixels))));
    fail("'", path, "' is ", ihdr.width, " x ", ihdr.height, " pixels, more than the ", max_pixels, " allowed here",
         side * side == max_pixels ? " (" + std::to_string(side) + " x " + std::to_string(side) + ")" : std::string());
  }
  std::size_t size = 0;
  err = spng_decoded_image_size(ctx.get(), SPNG_FMT_RGBA8, &size);
  if (err) fail("'", path, "': ", spng_strerror(err));
  // Deflate expands at most 1032:1, so an image larger than that much of the file cannot be in it:
  // refuse it before allocating (a 100-byte file may declare 16384 x 16384 pixels).
  const int channels[7] = {1, 0, 3, 1, 2, 0, 4};  // by colour type: grey, -, RGB, palette, grey+alpha, -, RGBA
  const std::size_t bits = std::size_t(ihdr.bit_depth) * channels[ihdr.color_type <= 6 ? ihdr.color_type : 6];
  const std::size_t raw = std::size_t(ihdr.height) * (1 + (std::size_t(ihdr.width) * bits + 7) / 8);
  if (raw > bytes.size() * 1032 + 4096)
    fail("'", path, "': the header declares ", ihdr.width, " x ", ihdr.height, " pixels, more than its ",
         bytes.size(), " bytes can hold (truncated or corrupt PNG)");
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
  write_file_atomically(path, data.data(), data.size());
}

}  // namespace wedge::render
