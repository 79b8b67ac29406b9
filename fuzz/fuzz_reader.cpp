// libFuzzer target for one file reader (issue 14): the bytes go to the same parser that
// import() and textures use, as a file of WEDGE_FUZZ_FORMAT ("stl", "obj", "ply", "off" or
// "png"). A wedge::Error is the reader refusing the file, which is fine; anything else (a crash, a
// sanitizer report, another exception, a leak, more than -rss_limit_mb, more than -timeout
// seconds) is a finding. Built by the `fuzz` preset only (clang; see fuzz/CMakeLists.txt).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "kernel/error.h"
#include "render/png_decode.h"
#include "tessellate/mesh_io.h"

#ifndef WEDGE_FUZZ_FORMAT
#error "WEDGE_FUZZ_FORMAT must name the reader"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::string_view format = WEDGE_FUZZ_FORMAT;
  try {
    if (format == "png") {
      wedge::render::Image im = wedge::render::decode_png(bytes, "fuzz.png");
      (void)im;
    } else {
      wedge::Mesh m = wedge::parse_mesh(bytes, std::string(format), "fuzz." + std::string(format));
      (void)m;
    }
  } catch (const wedge::Error&) {
    // Refused with a message: the reader's job.
  }
  return 0;
}
