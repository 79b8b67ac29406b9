// The fragment loop 8 lanes wide (AVX2, compiled with target("avx2") and chosen at run time):
// two 2x2 quads side by side, the quad at x in lanes 0-3 and the one at x + 2 in lanes 4-7, each
// in the 4-lane order of triangle_q's loop, with the same operations per lane in the same order,
// so the same bits (tests/render/test_fragment_paths.cpp checks it). It takes the common states
// (no Phong, no blending, all channels written, linear fog or none) after triangle_q's setup.

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/raster.h"

namespace wedge::render::raster {

#if defined(__SSE2__)
// (Lambdas do not inherit the target: each one in quad_loop8 carries it.)
#define WEDGE_AVX2_LAMBDA __attribute__((target("avx2"), always_inline))
template <bool Smooth, bool Tex, bool Fog, bool Depth>
__attribute__((target("avx2"))) void Raster::quad_loop8(const Quad8Setup& q) {
  struct P8 {
    __m256 c, dx, dy;
  };
  auto p8 = [](const QPlane& p) WEDGE_AVX2_LAMBDA {
    return P8{_mm256_set_m128(p.c, p.c), _mm256_set_m128(p.dx, p.dx), _mm256_set_m128(p.dy, p.dy)};
  };
  auto row = [](const P8& p, __m256 Y) WEDGE_AVX2_LAMBDA { return _mm256_add_ps(p.c, _mm256_mul_ps(Y, p.dy)); };
  auto at = [](__m256 r, const P8& p, __m256 X) WEDGE_AVX2_LAMBDA { return _mm256_add_ps(r, _mm256_mul_ps(X, p.dx)); };
  auto clamp01v = [](__m256 x) WEDGE_AVX2_LAMBDA { return _mm256_min_ps(_mm256_max_ps(x, _mm256_setzero_ps()), _mm256_set1_ps(1.0f)); };
  auto lanes8 = [](int m) WEDGE_AVX2_LAMBDA {
    const __m256i bits = _mm256_set_epi32(128, 64, 32, 16, 8, 4, 2, 1);
    return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(m), bits), bits);
  };
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 lane_dx = _mm256_set_ps(3, 2, 3, 2, 1, 0, 1, 0), lane_dy = _mm256_set_ps(1, 1, 0, 0, 1, 1, 0, 0);
  const P8 pw = p8(q.pw);
  P8 pc[4], pt[3], pf = p8(q.pf);
  for (int k = 0; k < 4; ++k) pc[k] = p8(q.pc[k]);
  for (int k = 0; k < 3; ++k) pt[k] = p8(q.pt[k]);
  __m256 flat_c[4] = {zero, zero, zero, zero};
  if constexpr (!Smooth)
    for (int k = 0; k < 4; ++k) flat_c[k] = _mm256_set1_ps(q.flat[q.col + k]);
  const __m256 fog_c[3] = {_mm256_set1_ps(s.fog_color[0]), _mm256_set1_ps(s.fog_color[1]),
                           _mm256_set1_ps(s.fog_color[2])};
  const __m256 env_c[3] = {_mm256_set1_ps(s.env_color[0]), _mm256_set1_ps(s.env_color[1]),
                           _mm256_set1_ps(s.env_color[2])};
  __m256i estep[3], erow[3], estepy[3];
  for (int i = 0; i < 3; ++i) {
    const int a = int(q.A[i]), b = int(q.B[i]);
    estep[i] = _mm256_set1_epi32(4 * a);
    estepy[i] = _mm256_set1_epi32(2 * b);
    erow[i] = _mm256_add_epi32(_mm256_set1_epi32(int(q.c[i])),
                               _mm256_set_epi32(3 * a + b, 2 * a + b, 3 * a, 2 * a, a + b, b, a, 0));
  }
  const bool wide = q.bx1 - q.ox >= 64;
  for (int qy = q.oy; qy <= q.by1; qy += 2) {
    int rowm = 0xff;
    if (qy < q.by0) rowm &= ~0x33;
    if (qy + 1 > q.by1) rowm &= ~0xcc;
    __m256i e[3] = {erow[0], erow[1], erow[2]};
    for (int i = 0; i < 3; ++i) erow[i] = _mm256_add_epi32(erow[i], estepy[i]);
    // On wide triangles, the columns where this pair of rows can be covered: each edge's
    // e(x) >= 0 solved for x on either row, widened by two pixels (the per-lane edge test
    // still decides coverage; this only skips blocks that cannot pass it).
    int qx_first = q.ox, qx_last = q.bx1;
    if (wide) {
      double lo = 0, hi = q.bx1 - q.ox;
      bool empty = false;
      for (int i = 0; i < 3; ++i) {
        const double e0 = double(q.c[i] + q.B[i] * (qy - q.oy)), e1 = e0 + double(q.B[i]);
        if (q.A[i] > 0) lo = std::max(lo, std::min(-e0, -e1) / double(q.A[i]));
        else if (q.A[i] < 0) hi = std::min(hi, std::max(e0, e1) / double(-q.A[i]));
        else if (e0 < 0 && e1 < 0) empty = true;
      }
      if (empty || lo > hi + 4) continue;
      qx_first = q.ox + (std::max(0, int(lo) - 2) & ~1);
      qx_last = std::min(q.bx1, q.ox + int(hi) + 2);
      if (qx_first > q.ox)
        for (int i = 0; i < 3; ++i)
          e[i] = _mm256_add_epi32(e[i], _mm256_set1_epi32(int(q.A[i]) * (qx_first - q.ox)));
    }
    const float fy = float(qy - q.oy);
    const __m256 Y8 = _mm256_add_ps(_mm256_set1_ps(fy), lane_dy);
    const __m256 rw_row = row(pw, Y8);
    __m256 c_row[4] = {zero, zero, zero, zero}, t_row[3] = {zero, zero, zero}, f_row = zero;
    if constexpr (Smooth)
      for (int k = 0; k < 4; ++k) c_row[k] = row(pc[k], Y8);
    if constexpr (Tex) {
      t_row[0] = row(pt[0], Y8), t_row[1] = row(pt[1], Y8);
      if (q.tex_q) t_row[2] = row(pt[2], Y8);
    }
    if constexpr (Fog) f_row = row(pf, Y8);
    const double zrow_lo = q.zc + double(fy) * q.zdy, zrow_hi = q.zc + double(fy + 1) * q.zdy;
    const __m256d zrow = _mm256_set_pd(zrow_hi, zrow_hi, zrow_lo, zrow_lo);
    for (int qx = qx_first; qx <= qx_last; qx += 4, e[0] = _mm256_add_epi32(e[0], estep[0]),
             e[1] = _mm256_add_epi32(e[1], estep[1]), e[2] = _mm256_add_epi32(e[2], estep[2])) {
      const __m256i out = _mm256_or_si256(_mm256_or_si256(e[0], e[1]), e[2]);
      int m = ~_mm256_movemask_ps(_mm256_castsi256_ps(out)) & rowm;
      if (qx < q.bx0 || qx + 3 > q.bx1) {
        for (int l = 0; l < 8; ++l) {
          const int x = qx + 2 * (l >> 2) + (l & 1);
          if (x < q.bx0 || x > q.bx1) m &= ~(1 << l);
        }
      }
      if (!m) continue;
      const bool inb = qx >= x0 && qx + 3 < x1 && qy >= y0 && qy + 1 < y1;
      const std::size_t i0 = std::size_t(qy) * width + qx, i1 = i0 + width;
      auto index = [&](int l) { return (l & 2 ? i1 : i0) + 2 * (l >> 2) + (l & 1); };
      const float fx = float(qx - q.ox);
      const __m256 X8 = _mm256_add_ps(_mm256_set1_ps(fx), lane_dx);
      if constexpr (Depth) {
        const double dx = fx;
        const __m256d zx = _mm256_set1_pd(q.zdx);
        const __m256d za = _mm256_add_pd(zrow, _mm256_mul_pd(_mm256_set_pd(dx + 1, dx, dx + 1, dx), zx));
        const __m256d zb = _mm256_add_pd(zrow, _mm256_mul_pd(_mm256_set_pd(dx + 3, dx + 2, dx + 3, dx + 2), zx));
        const __m256 zq = quantise_depth8(za, zb);
        __m256 d;
        if (m == 0xff || inb) {
          const __m128 lo = _mm_loadu_ps(depth + i0), hi = _mm_loadu_ps(depth + i1);
          d = _mm256_set_m128(_mm_movehl_ps(hi, lo), _mm_movelh_ps(lo, hi));
        } else {
          alignas(32) float t[8] = {0, 0, 0, 0, 0, 0, 0, 0};
          for (int l = 0; l < 8; ++l)
            if (m >> l & 1) t[l] = depth[index(l)];
          d = _mm256_load_ps(t);
        }
        m &= depth_cmp8(q.dfunc, zq, d);
        if (!m) continue;
        if (q.dmask) {
          if (m == 0xff || inb) {
            const __m256 nd = _mm256_blendv_ps(d, zq, _mm256_castsi256_ps(lanes8(m)));
            const __m128 q0 = _mm256_castps256_ps128(nd), q1 = _mm256_extractf128_ps(nd, 1);
            _mm_storeu_ps(depth + i0, _mm_movelh_ps(q0, q1));
            _mm_storeu_ps(depth + i1, _mm_movehl_ps(q1, q0));
          } else {
            alignas(32) float t[8];
            _mm256_store_ps(t, zq);
            for (int l = 0; l < 8; ++l)
              if (m >> l & 1) depth[index(l)] = t[l];
          }
        }
      }
      const __m256 rw = _mm256_div_ps(one, at(rw_row, pw, X8));
      __m256 cr, cg, cb, ca;
      if constexpr (Smooth) {
        cr = _mm256_mul_ps(at(c_row[0], pc[0], X8), rw), cg = _mm256_mul_ps(at(c_row[1], pc[1], X8), rw);
        cb = _mm256_mul_ps(at(c_row[2], pc[2], X8), rw), ca = _mm256_mul_ps(at(c_row[3], pc[3], X8), rw);
      } else {
        cr = flat_c[0], cg = flat_c[1], cb = flat_c[2], ca = flat_c[3];
      }
      if constexpr (Tex) {
        __m256 ts = _mm256_mul_ps(at(t_row[0], pt[0], X8), rw), tt = _mm256_mul_ps(at(t_row[1], pt[1], X8), rw);
        if (q.tex_q) {
          __m256 tq = _mm256_mul_ps(at(t_row[2], pt[2], X8), rw);
          tq = _mm256_blendv_ps(one, tq, _mm256_cmp_ps(tq, zero, _CMP_NEQ_UQ));
          ts = _mm256_div_ps(ts, tq), tt = _mm256_div_ps(tt, tq);
        }
        alignas(32) float S[8], T[8], U[8], V[8], texel[32];
        _mm256_store_ps(U, _mm256_mul_ps(ts, _mm256_set1_ps(q.tex_w)));
        _mm256_store_ps(V, _mm256_mul_ps(tt, _mm256_set1_ps(q.tex_h)));
        _mm256_store_ps(S, ts), _mm256_store_ps(T, tt);
        for (int h = 0; h < 2; ++h) {
          const int mh = m >> (4 * h) & 15;
          float* const Sh = S + 4 * h;
          float* const Th = T + 4 * h;
          const float* const Uh = U + 4 * h;
          const float* const Vh = V + 4 * h;
          if (!mh) {
            std::memset(texel + 16 * h, 0, 16 * sizeof(float));
            continue;
          }
          // Per quad, as the 4-lane loop: level of detail from its top row and left column.
          const float lambda = quad_lod(Uh[3] - Uh[2], Vh[3] - Vh[2], Uh[0] - Uh[2], Vh[0] - Vh[2]);
          if (mh != 15) {
            const int l0 = __builtin_ctz(unsigned(mh));
            for (int l = 0; l < 4; ++l)
              if (!(mh >> l & 1)) Sh[l] = Sh[l0], Th[l] = Th[l0];
          }
          q.texture->sample4(Sh, Th, lambda, texel + 16 * h, Simd::Auto);
        }
        __m128 a0 = _mm_load_ps(texel), a1 = _mm_load_ps(texel + 4), a2 = _mm_load_ps(texel + 8),
               a3 = _mm_load_ps(texel + 12);
        __m128 b0 = _mm_load_ps(texel + 16), b1 = _mm_load_ps(texel + 20), b2 = _mm_load_ps(texel + 24),
               b3 = _mm_load_ps(texel + 28);
        _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
        _MM_TRANSPOSE4_PS(b0, b1, b2, b3);
        const __m256 tr = _mm256_set_m128(b0, a0), tg = _mm256_set_m128(b1, a1), tb = _mm256_set_m128(b2, a2),
                     ta = _mm256_set_m128(b3, a3);
        const __m256 t[4] = {tr, tg, tb, ta};
        __m256 c[4] = {cr, cg, cb, ca};
        tex_env(q.env, q.fmt, t, env_c, one, c);
        cr = c[0], cg = c[1], cb = c[2], ca = c[3];
      }
      if constexpr (Fog) {
        const __m256 fz = _mm256_mul_ps(at(f_row, pf, X8), rw);
        __m256 f = one;
        if (q.fog_range != 0)
          f = _mm256_div_ps(_mm256_sub_ps(_mm256_set1_ps(q.fog_end), fz), _mm256_set1_ps(q.fog_range));
        f = clamp01v(f);
        const __m256 g = _mm256_sub_ps(one, f);
        cr = _mm256_add_ps(_mm256_mul_ps(f, cr), _mm256_mul_ps(g, fog_c[0]));
        cg = _mm256_add_ps(_mm256_mul_ps(f, cg), _mm256_mul_ps(g, fog_c[1]));
        cb = _mm256_add_ps(_mm256_mul_ps(f, cb), _mm256_mul_ps(g, fog_c[2]));
      }
      cr = clamp01v(cr), cg = clamp01v(cg), cb = clamp01v(cb), ca = clamp01v(ca);
      const __m256 k255 = _mm256_set1_ps(255.0f), half = _mm256_set1_ps(0.5f);
      auto q8 = [&](__m256 x) WEDGE_AVX2_LAMBDA { return _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(x, k255), half)); };
      __m256i px = _mm256_or_si256(_mm256_or_si256(q8(cr), _mm256_slli_epi32(q8(cg), 8)),
                                   _mm256_or_si256(_mm256_slli_epi32(q8(cb), 16), _mm256_slli_epi32(q8(ca), 24)));
      std::uint8_t* p0 = color + i0 * 4;
      std::uint8_t* p1 = color + i1 * 4;
      if (m == 0xff || inb) {
        if (m != 0xff) {
          const __m128i oy = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p0)),
                        oy1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p1));
          const __m256i old = _mm256_set_m128i(_mm_unpackhi_epi64(oy, oy1), _mm_unpacklo_epi64(oy, oy1));
          px = _mm256_blendv_epi8(old, px, lanes8(m));
        }
        const __m128i a = _mm256_castsi256_si128(px), b = _mm256_extracti128_si256(px, 1);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(p0), _mm_unpacklo_epi64(a, b));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(p1), _mm_unpackhi_epi64(a, b));
      } else {
        alignas(32) std::uint32_t P[8];
        _mm256_store_si256(reinterpret_cast<__m256i*>(P), px);
        for (int l = 0; l < 8; ++l)
          if (m >> l & 1) std::memcpy(color + index(l) * 4, &P[l], 4);
      }
    }
  }
}
#undef WEDGE_AVX2_LAMBDA

// The instances triangle_q's AVX2 build calls (Smooth, Tex, Fog, Depth).
#define WEDGE_QUAD8(S, T, F, D) template void Raster::quad_loop8<S, T, F, D>(const Quad8Setup&);
#define WEDGE_QUAD8_D(S, T, F) WEDGE_QUAD8(S, T, F, false) WEDGE_QUAD8(S, T, F, true)
#define WEDGE_QUAD8_F(S, T) WEDGE_QUAD8_D(S, T, false) WEDGE_QUAD8_D(S, T, true)
WEDGE_QUAD8_F(false, false)
WEDGE_QUAD8_F(false, true)
WEDGE_QUAD8_F(true, false)
WEDGE_QUAD8_F(true, true)
#undef WEDGE_QUAD8_F
#undef WEDGE_QUAD8_D
#undef WEDGE_QUAD8
#endif

}  // namespace wedge::render::raster
