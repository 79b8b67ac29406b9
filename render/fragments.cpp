// Triangle setup and the fragment loops (GL 1.x section 3.5). Setup snaps the window vertices
// to the 1/256-pixel grid and forms the edge functions E_i (exact integers) with a top-left tie
// rule, and the planes of depth (double) and of the perspective-divided attributes a/w and 1/w
// (float) from the unsnapped positions; the fragment loops then step them: the quad loop
// (quad_loop.cpp: one 2x2 quad per block with SSE2, two with AVX2), the covered pixels of tiny
// triangles one by one (tiny_pixel), or one pixel at a time with 64-bit edge functions
// (triangles too large for 32-bit ones, builds without SSE2: triangle_scalar). Each loop is
// specialised on the state that changes its work per fragment (Phong, smooth colour, texturing,
// fog, depth test), chosen once per triangle.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/raster.h"

namespace wedge::render::raster {

namespace {

// Barycentric planes l_i(x, y) = fa[i] x + fb[i] y + fc[i] from the unsnapped window positions.
// Coverage is decided on the 1/256-pixel grid, but depth and attributes are interpolated from
// the exact positions, as llvmpipe's setup does: weights from snapped vertices put texture
// coordinates up to a few 1/256 texel off on steep, distant triangles. False when the unsnapped
// area is not positive (a sliver that snapping turned over): the caller keeps snapped weights.
inline bool float_barycentrics(const WinVert* const v[3], double fa[3], double fb[3], double fc[3]) {
  const double x[3] = {v[0]->x, v[1]->x, v[2]->x}, y[3] = {v[0]->y, v[1]->y, v[2]->y};
  const double area = setup_area(x, y);
  if (!(area > 0) || !std::isfinite(area)) return false;
  const double inv = 1.0 / area;
  for (int i = 0; i < 3; ++i) {
    const WinVert& a = *v[(i + 1) % 3];
    const WinVert& b = *v[(i + 2) % 3];
    fa[i] = (a.y - b.y) * inv;
    fb[i] = (b.x - a.x) * inv;
    fc[i] = -(fa[i] * a.x + fb[i] * a.y);
  }
  return true;
}
}  // namespace

void Raster::triangle(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
  if (!phong) flat = flat_colour(v0, v1, v2, side, flat);
  const int key = (phong ? 16 : 0) | (flat == nullptr ? 8 : 0) | (texturing ? 4 : 0) | (fog ? 2 : 0) | (depth_test ? 1 : 0);
  switch (key) {
#if defined(__SSE2__)
#define WEDGE_TRI(k) \
case k: return triangle_isa<(k & 16) != 0, (k & 8) != 0, (k & 4) != 0, (k & 2) != 0, (k & 1) != 0>(v0, v1, v2, side, flat);
#else
#define WEDGE_TRI(k) \
case k: return triangle_t<(k & 16) != 0, (k & 8) != 0, (k & 4) != 0, (k & 2) != 0, (k & 1) != 0>(v0, v1, v2, side, flat);
#endif
    WEDGE_TRI(0) WEDGE_TRI(1) WEDGE_TRI(2) WEDGE_TRI(3) WEDGE_TRI(4) WEDGE_TRI(5) WEDGE_TRI(6) WEDGE_TRI(7)
    WEDGE_TRI(8) WEDGE_TRI(9) WEDGE_TRI(10) WEDGE_TRI(11) WEDGE_TRI(12) WEDGE_TRI(13) WEDGE_TRI(14) WEDGE_TRI(15)
    WEDGE_TRI(16) WEDGE_TRI(17) WEDGE_TRI(18) WEDGE_TRI(19) WEDGE_TRI(20) WEDGE_TRI(21) WEDGE_TRI(22) WEDGE_TRI(23)
    WEDGE_TRI(24) WEDGE_TRI(25) WEDGE_TRI(26) WEDGE_TRI(27) WEDGE_TRI(28) WEDGE_TRI(29) WEDGE_TRI(30) WEDGE_TRI(31)
#undef WEDGE_TRI
  }
}
// One pixel at a time with 64-bit edge functions and double barycentrics: triangles whose
// edge functions do not fit in 32 bits over their bounding box (larger than about 2000 x 2000
// pixels), and builds without SSE2.
template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
void Raster::triangle_scalar(const WinVert& v0, const WinVert& v1in, const WinVert& v2in, int side, const float* flat) {
  constexpr double kSub = 256.0;
  const WinVert* v[3] = {&v0, &v1in, &v2in};
  std::int64_t X[3], Y[3];
  for (int i = 0; i < 3; ++i) X[i] = std::llround(v[i]->x * kSub), Y[i] = std::llround(v[i]->y * kSub);
  std::int64_t area = setup_area(X, Y);
  if (area == 0) return;
  if (area < 0) {
    std::swap(v[1], v[2]), std::swap(X[1], X[2]), std::swap(Y[1], Y[2]);
    area = -area;
  }
  // Pixels whose centre (p + 1/2) lies within the vertices' bounding box: a covered centre is
  // inside the closed triangle, so no other pixel can be drawn (ceil / floor by shifts).
  int bx0 = std::max<std::int64_t>(x0, (std::min({X[0], X[1], X[2]}) - 128 + 255) >> 8);
  int bx1 = std::min<std::int64_t>(x1 - 1, (std::max({X[0], X[1], X[2]}) - 128) >> 8);
  // (Each pixel's values come from the planes at its own centre: any band's rows give the same.)
  int by0 = std::max<std::int64_t>(band_y0, (std::min({Y[0], Y[1], Y[2]}) - 128 + 255) >> 8);
  int by1 = std::min<std::int64_t>(band_y1 - 1, (std::max({Y[0], Y[1], Y[2]}) - 128) >> 8);
  if (bx0 > bx1 || by0 > by1) return;

  // Edge i is opposite vertex i: from v[(i+1)%3] to v[(i+2)%3]. E_i > 0 inside (CCW).
  std::int64_t A[3], B[3], bias[3];
  for (int i = 0; i < 3; ++i) {
    int a = (i + 1) % 3, b = (i + 2) % 3;
    std::int64_t dx = X[b] - X[a], dy = Y[b] - Y[a];
    A[i] = -dy;  // dE/dPx
    B[i] = dx;   // dE/dPy
    // Tie rule: a pixel centre on an edge belongs to the triangle if the edge is a "left"
    // edge (going down in y-up window space) or a "top" edge (horizontal, going left).
    bool top_left = dy < 0 || (dy == 0 && dx < 0);
    bias[i] = top_left ? 0 : -1;
  }
  auto edge_at = [&](int i, std::int64_t px, std::int64_t py) {
    int a = (i + 1) % 3;
    return A[i] * (px - X[a]) + B[i] * (py - Y[a]);
  };
  const double inv_area = 1.0 / double(area);
  // Per-vertex values pre-divided by w for perspective correction.
  constexpr bool need_tex = Tex;
  constexpr bool smooth = Smooth;
  const int col = side ? kBack : kFront;
  float zv[3], iw[3];
  for (int i = 0; i < 3; ++i) zv[i] = float(v[i]->z), iw[i] = float(v[i]->inv_w);
  // Barycentric planes from the unsnapped positions, or the snapped ones for a sliver that
  // snapping turned over (then l = E / area per pixel, exactly).
  double dl_dx[3], dl_dy[3], fc[3];
  const bool exact_weights = float_barycentrics(v, dl_dx, dl_dy, fc);
  if (!exact_weights)
    for (int i = 0; i < 3; ++i) dl_dx[i] = A[i] * kSub * inv_area, dl_dy[i] = B[i] * kSub * inv_area;
  const float tex_w = need_tex ? float(s.texture->levels[0].width) : 0;
  const float tex_h = need_tex ? float(s.texture->levels[0].height) : 0;

  const DepthFunc dfunc = s.depth_func;
  const bool dmask = s.depth_mask;
  float attrs[kAttrs];
  int quad_x = -1 << 30, quad_y = -1 << 30;
  float quad_lambda = 0;
  for (int py = by0; py <= by1; ++py) {
    std::int64_t Py = std::int64_t(py) * 256 + 128, Px = std::int64_t(bx0) * 256 + 128;
    std::int64_t E[3];
    for (int i = 0; i < 3; ++i) E[i] = edge_at(i, Px, Py);
    for (int px = bx0; px <= bx1; ++px, E[0] += A[0] * 256, E[1] += A[1] * 256, E[2] += A[2] * 256) {
      if (E[0] + bias[0] < 0 || E[1] + bias[1] < 0 || E[2] + bias[2] < 0) continue;
      double l[3];
      if (exact_weights)
        for (int i = 0; i < 3; ++i) l[i] = dl_dx[i] * (px + 0.5) + dl_dy[i] * (py + 0.5) + fc[i];
      else
        for (int i = 0; i < 3; ++i) l[i] = E[i] * inv_area;
      float z = float(l[0] * zv[0] + l[1] * zv[1] + l[2] * zv[2]);
      if (!depth_stage_t<Depth>(px, py, z, dfunc, dmask)) continue;
      // Perspective-correct weights: l_i / w_i normalised.
      // In float (attributes are floats; the weights need no more precision than they have).
      float pw[3] = {float(l[0]) * iw[0], float(l[1]) * iw[1], float(l[2]) * iw[2]};
      const float inv_sum = 1.0f / (pw[0] + pw[1] + pw[2]);  // one division, not three
      for (float& w : pw) w *= inv_sum;
      auto interp = [&](int k) { return pw[0] * v[0]->a[k] + pw[1] * v[1]->a[k] + pw[2] * v[2]->a[k]; };
      Vec4f c;
      if constexpr (Phong) {
        for (int k = 0; k < kAttrs; ++k) attrs[k] = interp(k);
        if (!smooth)
          for (int k = 0; k < 4; ++k) attrs[kFront + k] = flat[kFront + k];
        c = phong_color(attrs, side);
      } else if constexpr (Smooth) {
        c = Vec4f(interp(col), interp(col + 1), interp(col + 2), interp(col + 3));
      } else {
        c = Vec4f(flat[col], flat[col + 1], flat[col + 2], flat[col + 3]);
      }
      float tex[4] = {0, 0, 0, 1};
      float lambda = 0;
      if constexpr (Tex) {
        for (int k = 0; k < 4; ++k) tex[k] = interp(kTex + k);
        // Level of detail from the screen-space derivatives of (u, v) = (s W, t H).
        auto uv_at = [&](double ox, double oy, float& u, float& vv) {
          double q[3], ssum = 0;
          for (int i = 0; i < 3; ++i) q[i] = (l[i] + ox * dl_dx[i] + oy * dl_dy[i]) * iw[i], ssum += q[i];
          double ss = 0, tt = 0, qq = 0;
          for (int i = 0; i < 3; ++i) {
            ss += q[i] * v[i]->a[kTex];
            tt += q[i] * v[i]->a[kTex + 1];
            qq += q[i] * v[i]->a[kTex + 3];
          }
          if (qq == 0) qq = ssum;
          u = float(ss / qq) * tex_w, vv = float(tt / qq) * tex_h;
        };
        // Derivatives per 2x2 pixel quad, as GPUs (and llvmpipe) take them; the pixels of
        // one quad share the level of detail, so it is computed once per quad.
        const int qkx = px & ~1, qky = py & ~1;
        if (qkx != quad_x || qky != quad_y) {
          // The quad's reference pixel is its top-left one (framebuffers run top-down in
          // llvmpipe): x differences along the upper row, y differences down the left column.
          const double qx = double(qkx - px), qy = double(qky + 1 - py);
          float u0, v0_, ux, vx, uy, vy;
          uv_at(qx, qy, u0, v0_);
          uv_at(qx + 1, qy, ux, vx);
          uv_at(qx, qy - 1, uy, vy);
          quad_lambda = quad_lod(ux - u0, vx - v0_, uy - u0, vy - v0_);
          quad_x = qkx, quad_y = qky;
        }
        lambda = quad_lambda;
      }
      float fogz = 0;
      if constexpr (Fog) fogz = interp(kFog);
      shade_fragment_t<Tex, Fog>(px, py, c, tex, lambda, fogz);
    }
  }
}

#if defined(__SSE2__)
// --- triangle setup for the quad loop ---
// Coverage by exact 32-bit edge functions stepped per block of quads; depth by a plane in
// double; the perspective-divided attributes (a/w and 1/w) by planes in float (quad_loop.cpp).
// The AVX2 build where the CPU has it (Phong excepted: its per-fragment lighting is scalar, the
// AVX2 copy would only add compile time and code).
template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
void Raster::triangle_isa(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
  if constexpr (!Phong)
    if (avx2) return triangle_t_avx2<Phong, Smooth, Tex, Fog, Depth>(v0, v1, v2, side, flat);
  triangle_t<Phong, Smooth, Tex, Fog, Depth>(v0, v1, v2, side, flat);
}
// Two builds of triangle_q: for the base x86-64 (SSE2: then the 4-lane quad loop), and with
// AVX2 enabled, chosen at run time (the same setup, then the 8-lane quad loop). FMA is left off
// so that no multiply-add is contracted: both builds give the same bits.
template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
void Raster::triangle_t(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
  triangle_q<Phong, Smooth, Tex, Fog, Depth, false>(v0, v1, v2, side, flat);
}
template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
__attribute__((target("avx2"))) void Raster::triangle_t_avx2(const WinVert& v0, const WinVert& v1, const WinVert& v2,
                                                         int side, const float* flat) {
  triangle_q<Phong, Smooth, Tex, Fog, Depth, true>(v0, v1, v2, side, flat);
}
template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth, bool Avx2>
[[gnu::always_inline]] inline void Raster::triangle_q(const WinVert& v0, const WinVert& v1in, const WinVert& v2in, int side,
                                       const float* flat) {
  constexpr double kSub = 256.0;
  const WinVert* v[3] = {&v0, &v1in, &v2in};
  std::int64_t X[3], Y[3];
  for (int i = 0; i < 3; ++i) X[i] = round_half_away(v[i]->x * kSub), Y[i] = round_half_away(v[i]->y * kSub);
  std::int64_t area = setup_area(X, Y);
  if (area == 0) return;
  if (area < 0) {
    std::swap(v[1], v[2]), std::swap(X[1], X[2]), std::swap(Y[1], Y[2]);
    area = -area;
  }
  // Pixels whose centre lies within the vertices' bounding box (as triangle_scalar).
  const int bx0 = int(std::max<std::int64_t>(x0, (std::min({X[0], X[1], X[2]}) - 128 + 255) >> 8));
  const int bx1 = int(std::min<std::int64_t>(x1 - 1, (std::max({X[0], X[1], X[2]}) - 128) >> 8));
  const int ty0 = int(std::max<std::int64_t>(y0, (std::min({Y[0], Y[1], Y[2]}) - 128 + 255) >> 8));
  const int ty1 = int(std::min<std::int64_t>(y1 - 1, (std::max({Y[0], Y[1], Y[2]}) - 128) >> 8));
  if (bx0 > bx1 || ty0 > ty1) return;
  const int ox = bx0 & ~1, oy = ty0 & ~1;  // the first quad (of all rows, not the band's)
  // The rows drawn here: the box's rows in the band (all of them without bands).
  const int by0 = std::max(ty0, band_y0), by1 = std::min(ty1, band_y1 - 1);
  if (by0 > by1) return;
  // The framebuffer lines the triangle touches are usually not cached (a mesh's triangles come
  // in no screen order): start fetching them now, to overlap the setup below.
  for (int py : {by0, by1}) {
    const std::size_t i = std::size_t(py) * width + bx0;
    _mm_prefetch(reinterpret_cast<const char*>(depth + i), _MM_HINT_T0);
    _mm_prefetch(reinterpret_cast<const char*>(color + i * 4), _MM_HINT_T0);
  }

  // Edge i (opposite vertex i) at the centre (256 px + 128, 256 py + 128) of pixel (px, py) is
  // E = 256 (A px + B py) + K, K holding the tie-rule bias (see triangle_scalar), and
  // E >= 0  <=>  A px + B py + floor(K / 256) >= 0: the same test on integers 256 times
  // smaller, e(px, py) = A (px - ox) + B (py - oy) + c, which fits in 32 bits unless the
  // triangle is huge.
  QuadSetup qs;  // the setup, as the quad loop takes it
  std::int64_t* const A = qs.A;
  std::int64_t* const B = qs.B;
  std::int64_t* const c = qs.c;
  bool fits = true;
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i) {
    const int a = (i + 1) % 3, b = (i + 2) % 3;
    const std::int64_t dx = X[b] - X[a], dy = Y[b] - Y[a];
    A[i] = -dy, B[i] = dx;
    const bool top_left = dy < 0 || (dy == 0 && dx < 0);
    const std::int64_t K = A[i] * (128 - X[a]) + B[i] * (128 - Y[a]) + (top_left ? 0 : -1);
    c[i] = A[i] * ox + B[i] * oy + (K >> 8);  // >> floors (C++20: arithmetic shift)
    // Bound of |e| over the quads (one step past the last as well).
    const std::int64_t w = bx1 + 3 - ox, h = ty1 + 3 - oy;
    if (std::abs(c[i]) + std::abs(A[i]) * w + std::abs(B[i]) * h > (std::int64_t(1) << 30)) fits = false;
  }
  if (!fits) return triangle_scalar<Phong, Smooth, Tex, Fog, Depth>(v0, v1in, v2in, side, flat);
  // Tiny triangles (most of a dense mesh's, a pixel or two each): try the few pixel centres of
  // the bounding box first, by the loops' own integer test, and skip the plane setup when none
  // is covered (many cover no centre at all).
  // The covered centres are kept (cov_x, cov_y): the per-pixel path below draws them.
  const bool tiny = bx1 - bx0 < 4 && ty1 - ty0 < 4;
  int cov_n = 0;
  std::uint8_t cov_x[16], cov_y[16];  // offsets from (ox, oy)
  if (tiny) {
    for (int py = by0; py <= by1; ++py) {
      const std::int64_t dy = py - oy;
      const std::int64_t r0 = c[0] + B[0] * dy, r1 = c[1] + B[1] * dy, r2 = c[2] + B[2] * dy;
      for (int px = bx0; px <= bx1; ++px) {
        const std::int64_t dx = px - ox;
        if (((r0 + A[0] * dx) | (r1 + A[1] * dx) | (r2 + A[2] * dx)) >= 0)
          cov_x[cov_n] = std::uint8_t(dx), cov_y[cov_n] = std::uint8_t(dy), ++cov_n;
      }
    }
    if (!cov_n) return;
  }

  // Barycentrics at the centre of pixel (ox, oy) and their steps per pixel: from the unsnapped
  // positions, or from the snapped ones for a sliver that snapping turned over.
  double l0[3], glx[3], gly[3];
  double fa[3], fb[3], fc[3];
  if (float_barycentrics(v, fa, fb, fc)) {
    for (int i = 0; i < 3; ++i) l0[i] = fa[i] * (ox + 0.5) + fb[i] * (oy + 0.5) + fc[i], glx[i] = fa[i], gly[i] = fb[i];
  } else {
    const double inv_area = 1.0 / double(area);
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      const int a = (i + 1) % 3;
      l0[i] = double(A[i] * (std::int64_t(ox) * 256 + 128 - X[a]) + B[i] * (std::int64_t(oy) * 256 + 128 - Y[a])) * inv_area;
      glx[i] = double(A[i]) * kSub * inv_area, gly[i] = double(B[i]) * kSub * inv_area;
    }
  }
  // (value, x step) of a plane in one register pair, the y step apart: the same products and
  // sums, in the same order, as three scalar dot products.
  const __m128d lg[3] = {_mm_set_pd(glx[0], l0[0]), _mm_set_pd(glx[1], l0[1]), _mm_set_pd(glx[2], l0[2])};
  auto plane = [&](double f0, double f1, double f2) {
    const __m128d cd = _mm_add_pd(_mm_add_pd(_mm_mul_pd(lg[0], _mm_set1_pd(f0)), _mm_mul_pd(lg[1], _mm_set1_pd(f1))),
                                  _mm_mul_pd(lg[2], _mm_set1_pd(f2)));
    const __m128 cdf = _mm_cvtpd_ps(cd);
    return QPlane{_mm_cvtss_f32(cdf), _mm_cvtss_f32(_mm_shuffle_ps(cdf, cdf, 0x55)),
                  float(gly[0] * f0 + gly[1] * f1 + gly[2] * f2)};
  };
  // a/w for attribute k (divided by the 1/w plane per fragment: perspective-correct).
  auto persp = [&](int k) {
    return plane(double(v[0]->a[k]) * v[0]->inv_w, double(v[1]->a[k]) * v[1]->inv_w, double(v[2]->a[k]) * v[2]->inv_w);
  };
  const QPlane pw = qs.pw = plane(v[0]->inv_w, v[1]->inv_w, v[2]->inv_w);
  const int col = side ? kBack : kFront;
  const QPlane none{0, 0, 0};
  QPlane* const pc = qs.pc;
  QPlane* const pt = qs.pt;
  QPlane& pf = qs.pf;
  for (int k = 0; k < 4; ++k) pc[k] = none;
  for (int k = 0; k < 3; ++k) pt[k] = none;
  pf = none;
  bool tex_q = false;
  if constexpr (Smooth && !Phong)
    for (int k = 0; k < 4; ++k) pc[k] = persp(col + k);
  if constexpr (Tex) {
    pt[0] = persp(kTex), pt[1] = persp(kTex + 1);
    // q = 1 at every vertex (no projective texturing): no per-fragment division by q.
    tex_q = v[0]->a[kTex + 3] != 1 || v[1]->a[kTex + 3] != 1 || v[2]->a[kTex + 3] != 1;
    if (tex_q) pt[2] = persp(kTex + 3);
  }
  if constexpr (Fog) pf = persp(kFog);
  if constexpr (Phong)
    for (int k = 0; k < kAttrs; ++k) qs.pa[k] = persp(k);
  double zc = 0, zdx = 0, zdy = 0;
  if constexpr (Depth) {
    for (int i = 0; i < 3; ++i) {
      const double zi = float(v[i]->z);
      zc += l0[i] * zi, zdx += glx[i] * zi, zdy += gly[i] * zi;
    }
  }
  const DepthFunc dfunc = s.depth_func;
  const bool dmask = s.depth_mask;
  const bool fast_write = !blend && all_mask;
  if constexpr (!Phong && !Tex && !Fog) {
    // Tiny triangles in the common state: the covered pixels one by one, with the quad loop's
    // operations per lane in the same order (the same bits), without its setup and blocks.
    if (tiny && fast_write) {
      float pl[5][3];
      const QPlane* src[5] = {&pw, &pc[0], &pc[1], &pc[2], &pc[3]};
      for (int k = 0; k < 5; ++k) pl[k][0] = src[k]->c, pl[k][1] = src[k]->dx, pl[k][2] = src[k]->dy;
      for (int n = 0; n < cov_n; ++n)
        tiny_pixel<Smooth, Depth>(ox + cov_x[n], oy + cov_y[n], float(cov_x[n]), float(cov_y[n]), zc, zdx, zdy, pl,
                                  Smooth ? nullptr : flat + col, dfunc, dmask);
      return;
    }
  }
  QuadSetup& q = qs;
  q.ox = ox, q.oy = oy, q.bx0 = bx0, q.bx1 = bx1, q.by0 = by0, q.by1 = by1, q.col = col, q.side = side;
  q.tex_q = tex_q, q.dmask = dmask, q.fast_write = fast_write, q.zc = zc, q.zdx = zdx, q.zdy = zdy;
  q.texture = Tex ? s.texture.get() : nullptr;
  q.tex_w = Tex ? float(q.texture->levels[0].width) : 0;
  q.tex_h = Tex ? float(q.texture->levels[0].height) : 0;
  q.fog_mode = s.fog_mode, q.fog_end = s.fog_end, q.fog_range = s.fog_end - s.fog_start, q.fog_density = s.fog_density;
  q.env = s.env_mode, q.fmt = Tex ? q.texture->format : TexFormat::RGBA, q.flat = flat, q.dfunc = dfunc;
  if constexpr (Avx2) {
    static_assert(!Phong, "the AVX2 build takes no Phong triangles (triangle_isa)");
    quad_loop8<Smooth, Tex, Fog, Depth>(q);
  } else {
    quad_loop4<Phong, Smooth, Tex, Fog, Depth>(q);
  }
}
#else
template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
void Raster::triangle_t(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
  triangle_scalar<Phong, Smooth, Tex, Fog, Depth>(v0, v1, v2, side, flat);
}
#endif

}  // namespace wedge::render::raster
