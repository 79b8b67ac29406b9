// Lines and points in window coordinates (GL 1.x sections 3.3, 3.4). A line is sampled at the
// pixel centres of its major axis between its snapped endpoints (a DDA) with the diamond-exit
// rule at the ends (3.4.1), w pixels wide across the minor axis; its depth and attributes are
// interpolated perspective-correctly along it. A point of size s is an s x s square centred on
// the pixel holding it (odd s) or on the nearest pixel corner (even s).

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/raster.h"

namespace wedge::render::raster {

// --- lines: a DDA that samples the line at the pixel centres of its major axis ---
void Raster::line(const WinVert& a_in, const WinVert& b_in, int side, const float* flat) {
  const int col = side ? kBack : kFront;
  // Endpoints snapped to the 1/256-pixel grid the triangle setup uses (and llvmpipe's).
  WinVert a = a_in, b = b_in;
  a.x = std::nearbyint(a.x * 256) / 256, a.y = std::nearbyint(a.y * 256) / 256;
  b.x = std::nearbyint(b.x * 256) / 256, b.y = std::nearbyint(b.y * 256) / 256;
  double dx = b.x - a.x, dy = b.y - a.y;
  if (dx == 0 && dy == 0) return;
  const bool xmajor = std::abs(dx) >= std::abs(dy);
  const double s0 = xmajor ? a.x : a.y, s1 = xmajor ? b.x : b.y;
  const double len = s1 - s0;
  // Centres c with s0 <= c < s1 (or s1 < c <= s0): the diamond-exit rule along the major axis.
  int first, last;
  if (len > 0) first = int(std::ceil(s0 - 0.5)), last = int(std::ceil(s1 - 0.5)) - 1;
  else first = int(std::floor(s1 - 0.5)) + 1, last = int(std::floor(s0 - 0.5));
  const int w = std::max(1, int(std::lround(s.line_width)));
  float attrs[kAttrs] = {};
  // One column (x-major) or row (y-major) of w fragments at parameter t; `major`/`minor0` are
  // the pixel indices along the axes.
  auto column = [&](int major, int minor0, double t) __attribute__((always_inline)) {
    double z = a.z + t * (b.z - a.z);
    double wa = (1 - t) * a.inv_w, wb = t * b.inv_w;
    double sum = wa + wb;
    wa /= sum, wb /= sum;
    // Only the attributes this state reads (each one by the same expression).
    auto interp = [&](int k0, int k1) {
      for (int k = k0; k < k1; ++k) attrs[k] = float(wa * a.a[k] + wb * b.a[k]);
    };
    if (phong) {
      interp(0, kAttrs);
    } else {
      if (!flat) interp(col, col + 4);
      if (texturing) interp(kTex, kTex + 4);
      if (fog) interp(kFog, kFog + 1);
    }
    Vec4f cc;
    if (phong) {
      if (flat)
        for (int k = 0; k < 4; ++k) attrs[kFront + k] = flat[kFront + k];
      cc = phong_color(attrs, side);
    } else if (flat) {
      cc = Vec4f(flat[col], flat[col + 1], flat[col + 2], flat[col + 3]);
    } else {
      cc = Vec4f(attrs[col], attrs[col + 1], attrs[col + 2], attrs[col + 3]);
    }
    for (int j = minor0; j < minor0 + w; ++j) {
      int px = xmajor ? major : j, py = xmajor ? j : major;
      if (px < x0 || px >= x1 || py < y0 || py >= y1) continue;
      if (!depth_stage(px, py, float(z))) continue;
      shade_fragment(px, py, cc, texturing ? attrs + kTex : nullptr, 0, attrs[kFog]);
    }
  };
  // The diamond-exit rule at the ends of a line (GL 1.5, 3.4.1): the pixel whose diamond holds
  // the start point is drawn (the line leaves it), the one holding the end point is not (the
  // line never leaves it). llvmpipe applies it to wide lines too, a whole column of w pixels
  // centred on that pixel.
  auto diamond = [](double x, double y, int& px, int& py) {
    px = int(std::floor(x)), py = int(std::floor(y));
    return std::abs(x - (px + 0.5)) + std::abs(y - (py + 0.5)) <= 0.5;
  };
  int spx = 0, spy = 0, epx = 0, epy = 0;
  const bool start_in = diamond(a.x, a.y, spx, spy);
  const bool end_in = diamond(b.x, b.y, epx, epy);
  auto minor_at = [&](int i) {
    double t = (i + 0.5 - s0) / len;
    return int(std::floor(xmajor ? a.y + t * dy : a.x + t * dx));
  };
  if (start_in) {
    const int si = xmajor ? spx : spy, sm = xmajor ? spy : spx;
    if (si < first || si > last || minor_at(si) != sm) column(si, sm - (w - 1) / 2, 0.0);
  }
  for (int i = first; i <= last; ++i) {
    const double t = (i + 0.5 - s0) / len;
    const int m = minor_at(i);
    if (end_in && i == (xmajor ? epx : epy) && m == (xmajor ? epy : epx)) continue;
    column(i, m - (w - 1) / 2, t);
  }
}

void Raster::point(const WinVert& p_in, int side) {
  const int col = side ? kBack : kFront;
  WinVert p = p_in;  // snapped to the 1/256-pixel grid, as lines and triangles
  p.x = std::nearbyint(p.x * 256) / 256, p.y = std::nearbyint(p.y * 256) / 256;
  const double size = std::max(1.0, double(std::lround(s.point_size)));
  int isz = int(size);
  // GL 3.4: odd sizes centre on the pixel containing the point, even sizes on the nearest corner.
  int xa = (isz % 2) ? int(std::floor(p.x)) - (isz - 1) / 2 : int(std::floor(p.x + 0.5)) - isz / 2;
  int ya = (isz % 2) ? int(std::floor(p.y)) - (isz - 1) / 2 : int(std::floor(p.y + 0.5)) - isz / 2;
  Vec4f c;
  if (phong) c = phong_color(p.a, side);
  else c = Vec4f(p.a[col], p.a[col + 1], p.a[col + 2], p.a[col + 3]);
  for (int y = ya; y < ya + isz; ++y)
    for (int x = xa; x < xa + isz; ++x) {
      if (x < x0 || x >= x1 || y < y0 || y >= y1) continue;
      if (!depth_stage(x, y, float(p.z))) continue;
      shade_fragment(x, y, c, texturing ? p.a + kTex : nullptr, 0, p.a[kFog]);
    }
}

}  // namespace wedge::render::raster
