// PNG decoding from bytes in memory: read_png (render.h) reads a file and calls it; the PNG fuzz
// target (fuzz/) calls it directly. Throws wedge::Error naming `name` and what is wrong.
#pragma once
#include <string>
#include <string_view>

#include "render/render.h"

namespace wedge::render {

Image decode_png(std::string_view bytes, const std::string& name, std::size_t max_pixels = std::size_t(16384) * 16384);

}  // namespace wedge::render
