// Lines and points in window coordinates (GL 1.x sections 3.3, 3.4). A line is the quad it
// sweeps, w pixels wide across its minor axis, sampled at pixel centres, with the diamond-exit
// rule at its ends (3.4.1), as llvmpipe draws it; its depth and attributes are interpolated
// perspective-correctly along it. A point of size s is an s x s square centred on
// the pixel holding it (odd s) or on the nearest pixel corner (even s).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "render/raster.h"

namespace wedge::render::raster {

// --- lines: a parallelogram w pixels across the minor axis, sampled at pixel centres ---
// llvmpipe's non-smooth lines (our oracle) are the quad swept by the segment, w pixels thick
// across its minor axis, sampled at pixel centres with the triangles' fill rule (left and bottom
// edges included): a line exactly on a pixel boundary takes the pixel left of or below it. Its
// ends follow the diamond-exit rule (GL 1.5, 3.4.1), decided from the unsnapped float ends and
// applied by moving an end of the quad along the line onto the pixel boundary that takes in or
// leaves out the end pixel. llvmpipe makes that decision in its framebuffer's rows, which run
// top-down (y' = height - y); the same here, because the rule's ties (an end on a diamond's
// corner) are not symmetric in y.
namespace {
struct LineEnds {
  double x0, y0, x1, y1;  // the quad's ends on the line (top-down rows, as the input)
};
// The diamond-exit decisions and the ends moved by them, for a line from (ax, ay) to (bx, by)
// in top-down rows (llvmpipe's float arithmetic, so that its ties fall the same way).
LineEnds line_ends(float ax, float ay, float bx, float by) {
  const float ux = bx - ax, uy = by - ay;
  auto off = [](float v) { return v - std::floor(v) - 0.5f; };  // from the pixel centre
  auto frac = [](float v) { return v - std::floor(v); };
  float fx0 = off(ax), fy0 = off(ay), fx1 = off(bx), fy1 = off(by);
  float sx = 0, sy = 0, ex = 0, ey = 0;  // moves of the start and the end
  if (std::fabs(ux) >= std::fabs(uy)) {  // x-major
    const float k = uy / ux;
    if (fy1 == -0.5f && uy > 0) fy1 = 0.5f;
    bool start;  // whether the start pixel is drawn: the line leaves its diamond
    if (std::fabs(fx0) + std::fabs(fy0) < 0.5f) start = true;
    else if ((fx0 >= 0) == (ux >= 0)) start = false;
    else if ((fy0 <= 0) != (uy <= 0)) start = true;
    else {
      const float yi = frac(ay) + fx0 * k;
      start = yi > 0 && yi < 1;
    }
    bool end;  // whether the end pixel is drawn: the line passes its diamond before ending
    if (std::fabs(fx1) + std::fabs(fy1) < 0.5f) end = false;
    else if ((fx1 >= 0) != (ux >= 0)) end = false;
    else if ((fy1 <= 0) == (uy <= 0)) end = true;
    else {
      const float yi = frac(by) + fx1 * k;
      end = yi > 0 && yi < 1;
    }
    // Whether the quad's plain ends already take the end pixels in (left edges included).
    const bool right = ux > 0;
    if ((right ? fx0 <= 0 : fx0 > 0) != start) sx = right ? -fx0 - 0.5f : -fx0 + 0.5f, sy = sx * k;
    if ((right ? fx1 > 0 : fx1 <= 0) != end) ex = right ? -fx1 - 0.5f : -fx1 + 0.5f, ey = ex * k;
  } else {  // y-major
    const float k = ux / uy;
    if (fx1 == -0.5f && ux > 0) fx1 = 0.5f;
    bool start;
    if (std::fabs(fx0) + std::fabs(fy0) < 0.5f) start = true;
    else if ((fy0 <= 0) == (uy <= 0)) start = false;
    else if ((fx0 >= 0) != (ux >= 0)) start = true;
    else {
      const float xi = frac(ax) + fy0 * k;
      start = xi > 0 && xi < 1;
    }
    bool end;
    if (std::fabs(fx1) + std::fabs(fy1) < 0.5f) end = false;
    else if ((fy1 <= 0) != (uy <= 0)) end = false;
    else if ((fx1 >= 0) == (ux >= 0)) end = true;
    else {
      const float xi = frac(bx) + fy1 * k;
      end = xi >= 0 && xi < 1;
    }
    // Top-down rows: the lower edge on screen (larger y') is the one included.
    const bool down = uy < 0;  // towards smaller y' (up on the screen)
    if ((down ? fy0 >= 0 : fy0 < 0) != start) sy = down ? -fy0 + 0.5f : -fy0 - 0.5f, sx = sy * k;
    if ((down ? fy1 < 0 : fy1 >= 0) != end) ey = down ? -fy1 + 0.5f : -fy1 - 0.5f, ex = ey * k;
  }
  return {double(ax + sx), double(ay + sy), double(bx + ex), double(by + ey)};
}
// Floor and ceiling of n / d for d > 0, exactly.
inline std::int64_t floor_div(std::int64_t n, std::int64_t d) { return n >= 0 ? n / d : -((-n + d - 1) / d); }
inline std::int64_t ceil_div(std::int64_t n, std::int64_t d) { return -floor_div(-n, d); }
}  // namespace

void Raster::line(const WinVert& a, const WinVert& b, int side, const float* flat) {
  const int col = side ? kBack : kFront;
  const float ax = float(a.x), ay = float(height - a.y), bx = float(b.x), by = float(height - b.y);
  if (ax == bx && ay == by) return;
  const LineEnds q = line_ends(ax, ay, bx, by);
  // The quad's ends on the 1/256-pixel grid (window y up again).
  const std::int64_t X0 = std::llrint(q.x0 * 256), X1 = std::llrint(q.x1 * 256);
  const std::int64_t Y0 = std::int64_t(height) * 256 - std::llrint(q.y0 * 256);
  const std::int64_t Y1 = std::int64_t(height) * 256 - std::llrint(q.y1 * 256);
  const bool xmajor = std::fabs(bx - ax) >= std::fabs(by - ay);
  // Major axis M, minor axis m (x and y for an x-major line).
  const std::int64_t M0 = xmajor ? X0 : Y0, M1 = xmajor ? X1 : Y1, m0 = xmajor ? Y0 : X0, m1 = xmajor ? Y1 : X1;
  if (M0 == M1) return;
  const std::int64_t dM = M1 - M0, dm = m1 - m0;
  const int w = std::max(1, int(std::lround(s.line_width)));
  // Centres 256 i + 128 in [min M, max M): the left (bottom) end of the quad is included.
  const int first = int(ceil_div(std::min(M0, M1) - 128, 256)), last = int(ceil_div(std::max(M0, M1) - 128, 256)) - 1;
  // A tie (a centre exactly on a long edge) goes as llvmpipe's fill rule for the quad's edges:
  // across an x-major line rising to the right the upper edge is included, the lower one
  // otherwise (and always the left edge of a y-major line).
  const bool rising = xmajor && dm != 0 && (dm > 0) == (dM > 0);
  const double s0 = xmajor ? a.x : a.y, len = (xmajor ? b.x : b.y) - s0;
  float attrs[kAttrs] = {};
  for (int i = first; i <= last; ++i) {
    // The line's minor coordinate at the centre: m0 + (C - M0) dm / dM; the w pixels whose
    // centres lie within w/2 of it.
    const std::int64_t C = std::int64_t(i) * 256 + 128;
    const std::int64_t sgn = dM > 0 ? 1 : -1;
    const std::int64_t num = (m0 - 128 * w - 128) * dM * sgn + (C - M0) * dm * sgn;
    const int j0 = int(rising ? floor_div(num, 256 * dM * sgn) + 1 : ceil_div(num, 256 * dM * sgn));
    const double t = std::clamp((i + 0.5 - s0) / len, 0.0, 1.0);
    double z = a.z + t * (b.z - a.z);
    double wa = (1 - t) * a.inv_w, wb = t * b.inv_w;
    const double sum = wa + wb;
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
    for (int j = j0; j < j0 + w; ++j) {
      const int px = xmajor ? i : j, py = xmajor ? j : i;
      if (px < x0 || px >= x1 || py < band_y0 || py >= band_y1) continue;
      if (!depth_stage(px, py, float(z))) continue;
      shade_fragment(px, py, cc, texturing ? attrs + kTex : nullptr, 0, attrs[kFog]);
    }
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
      if (x < x0 || x >= x1 || y < band_y0 || y >= band_y1) continue;
      if (!depth_stage(x, y, float(p.z))) continue;
      shade_fragment(x, y, c, texturing ? p.a + kTex : nullptr, 0, p.a[kFog]);
    }
}

}  // namespace wedge::render::raster
