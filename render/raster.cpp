// The state of one draw (Raster) made from the context's state, and the SIMD choice.

#include <cstdlib>
#include <cstring>

#include "render/raster.h"

namespace wedge::render {
std::atomic<bool> simd_fallback{false};
}  // namespace wedge::render

namespace wedge::render::raster {

Raster::Raster(Context::State& st, int w, int h, std::uint8_t* c, float* d)
    : s(st), width(w), height(h), color(c), depth(d), lights(st) {
  for (int i = 0; i < 6; ++i)
    if (s.on(clip_plane_cap(i))) user_planes.push_back(s.clip_planes[i]);
  x0 = 0, y0 = 0, x1 = w, y1 = h;
  if (s.on(Cap::ScissorTest)) {
    x0 = std::max(x0, s.sc_x), y0 = std::max(y0, s.sc_y);
    x1 = std::min(x1, s.sc_x + s.sc_w), y1 = std::min(y1, s.sc_y + s.sc_h);
  }
  lighting = s.on(Cap::Lighting);
  phong = lighting && s.shade == ShadeModel::Phong;
  texturing = s.on(Cap::Texture2D) && s.texture && !s.texture->levels.empty();
  fog = s.on(Cap::Fog);
  blend = s.on(Cap::Blend);
  depth_test = s.on(Cap::DepthTest);
  all_mask = s.color_mask[0] && s.color_mask[1] && s.color_mask[2] && s.color_mask[3];
#if defined(__SSE2__)
  static const bool cpu_avx2 = __builtin_cpu_supports("avx2");
  const char* simd = std::getenv("WEDGE_RENDER_SIMD");  // read per draw: tests switch it
  avx2 = cpu_avx2 && !(simd && std::strcmp(simd, "sse2") == 0) && !simd_fallback.load(std::memory_order_relaxed);
#endif
}

}  // namespace wedge::render::raster
