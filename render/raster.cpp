// The state of one draw (Raster) made from the context's state, and the SIMD choice.

#include "render/raster.h"

namespace wedge::render {
bool cpu_has_avx2() {
#if defined(__SSE2__) && defined(__GNUC__)
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
#else
  return false;
#endif
}
}  // namespace wedge::render

namespace wedge::render::raster {

Raster::Raster(Context::State& st, int w, int h, std::uint8_t* c, float* d)
    : s(st), width(w), height(h), color(c), depth(d), lights(st) {
  if (!st.scratch) st.scratch = std::make_shared<Scratch>();
  scratch = st.scratch.get();
  for (int i = 0; i < 6; ++i)
    if (s.on(clip_plane_cap(i))) user_planes.push_back(s.clip_planes[i]);
  x0 = 0, y0 = 0, x1 = w, y1 = h;
  if (s.on(Cap::ScissorTest)) {
    x0 = std::max(x0, s.sc_x), y0 = std::max(y0, s.sc_y);
    x1 = std::min(x1, s.sc_x + s.sc_w), y1 = std::min(y1, s.sc_y + s.sc_h);
  }
  band_y0 = y0, band_y1 = y1;
  lighting = s.on(Cap::Lighting);
  phong = lighting && s.shade == ShadeModel::Phong;
  texturing = s.on(Cap::Texture2D) && s.texture && !s.texture->levels.empty();
  fog = s.on(Cap::Fog);
  blend = s.on(Cap::Blend);
  depth_test = s.on(Cap::DepthTest);
  all_mask = s.color_mask[0] && s.color_mask[1] && s.color_mask[2] && s.color_mask[3];
  avx2 = s.simd == Simd::Auto && cpu_has_avx2();
}

}  // namespace wedge::render::raster
