// The OpenGL 1.x fixed-function pipeline, stage by stage, following the OpenGL 1.5 specification
// (Segal & Akeley), chapters 2-4:
//   vertex stage   object -> eye (modelview), normal by the inverse transpose, lighting (2.14.1:
//                  emission + global ambient + per light attenuation * spot * (ambient + diffuse
//                  + specular), clamped per vertex), texgen and the texture matrix, eye -> clip;
//   assembly       primitives by type, with GL's provoking vertex for flat shading (table 2.12);
//   clipping       in homogeneous clip space before the divide: Sutherland-Hodgman against
//                  -w <= x, y, z <= w and the user planes (in eye space), with edge flags so
//                  that polygon-mode lines skip the edges clipping made;
//   facing/culling by the signed window-space area (2.14.1 / 3.5.1);
//   rasterisation  triangles by edge functions in 24.8 fixed point with a top-left tie rule and
//                  perspective-correct attributes (3.5, a/w and 1/w interpolated linearly);
//                  lines by a diamond-exit DDA, points as squares;
//   fragments      texturing with the env mode, fog (3.10), depth test, blending, colour mask.
// Per-pixel Phong (beyond GL 1.x) evaluates the same lighting equation per fragment on the
// interpolated eye-space normal and position.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#include <immintrin.h>  // AVX2 intrinsics, used only in functions built with target("avx2")
#endif

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "render/context_state.h"

// -Wpsabi notes that 32-byte vectors (__m256, F8, D4) passed by value travel differently with
// and without AVX. Every function here that takes or returns one by value is always inlined (so
// no call crosses that difference: one left out of line would be compiled for the base target
// and misread its AVX2 caller's registers, as happened in the unoptimised build); GCC reports the
// notes where it instantiates templates, at the end of the file, so this holds for all of it.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace wedge::render {

namespace {

// llvmpipe's level-of-detail log2 (gallivm's fast log2): the float's exponent minus one plus its
// mantissa in [1, 2), a piecewise-linear log2 exact at powers of two. Its blend fraction between
// two mipmap levels follows this curve, not the true logarithm.
[[gnu::always_inline]] inline float fast_log2(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, 4);
  const int biased = int(bits >> 23);
  if (biased > 0 && biased < 255) {
    // A positive normal float without a library call: x = m1 2^e, m1 in [1, 2), the same value
    // as frexp's m 2^(e + 1) below.
    const std::uint32_t mb = (bits & 0x7fffffu) | 0x3f800000u;
    float m1;
    std::memcpy(&m1, &mb, 4);
    return float(biased - 128) + m1;
  }
  int e = 0;
  float m = std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1)
  return float(e - 2) + 2 * m;
}

#if defined(__SSE2__)
// Helpers of the 2x2-quad fragment loop (Raster::triangle_t).
struct QPlane {
  __m128 c, dx, dy;  // value at the centre of the first quad's first pixel; steps per pixel in x, y
};
// llround (half away from zero) without a library call, for |x| < 2^52 (window coordinates
// times 256); beyond that x is an integer and is returned as it is.
[[gnu::always_inline]] inline std::int64_t round_half_away(double x) {
  std::int64_t i = std::int64_t(x);
  const double f = x - double(i);
  return i + (f >= 0.5) - (f <= -0.5);
}
[[gnu::always_inline]] inline __m128 sel(__m128 m, __m128 a, __m128 b) {
  return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b));
}
// All ones in the lanes whose bit is set in m.
[[gnu::always_inline]] inline __m128 lane_mask(int m) {
  const __m128i bits = _mm_set_epi32(8, 4, 2, 1);
  return _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(m), bits), bits));
}
// The texture environment (GL 1.x, table 3.22) on lanes: the fragment colours c (r, g, b, a) by
// the texels t (r, g, b, a) of a texture of format fmt, env the environment colour (r, g, b).
// For __m128 and __m256 alike through GCC's vector operators: the same multiplies and adds in the
// same order in the SSE2 and AVX2 loops (no FMA in either build: the same bits).
template <class V>
[[gnu::always_inline]] inline void tex_env(TexEnvMode mode, TexFormat fmt, const V* t, const V* env, V one, V* c) {
  const bool rgba = fmt == TexFormat::RGBA;
  switch (mode) {
    case TexEnvMode::Modulate:
      for (int k = 0; k < 3; ++k) c[k] = c[k] * t[k];
      if (rgba) c[3] = c[3] * t[3];
      break;
    case TexEnvMode::Replace:
      for (int k = 0; k < 3; ++k) c[k] = t[k];
      if (rgba) c[3] = t[3];
      break;
    case TexEnvMode::Decal:
      if (rgba) {
        const V ia = one - t[3];
        for (int k = 0; k < 3; ++k) c[k] = c[k] * ia + t[k] * t[3];
      } else if (fmt == TexFormat::RGB) {
        for (int k = 0; k < 3; ++k) c[k] = t[k];
      }
      break;
    case TexEnvMode::Blend:
      for (int k = 0; k < 3; ++k) c[k] = c[k] * (one - t[k]) + env[k] * t[k];
      if (rgba) c[3] = c[3] * t[3];
      break;
  }
}
// The depth test on four lanes: a bit per passing lane.
[[gnu::always_inline]] inline int depth_cmp4(DepthFunc f, __m128 z, __m128 d) {
  switch (f) {
    case DepthFunc::Never: return 0;
    case DepthFunc::Less: return _mm_movemask_ps(_mm_cmplt_ps(z, d));
    case DepthFunc::Equal: return _mm_movemask_ps(_mm_cmpeq_ps(z, d));
    case DepthFunc::LessEqual: return _mm_movemask_ps(_mm_cmple_ps(z, d));
    case DepthFunc::Greater: return _mm_movemask_ps(_mm_cmpgt_ps(z, d));
    case DepthFunc::NotEqual: return _mm_movemask_ps(_mm_cmpneq_ps(z, d));
    case DepthFunc::GreaterEqual: return _mm_movemask_ps(_mm_cmpge_ps(z, d));
    case DepthFunc::Always: return 15;
  }
  return 0;
}
// Window depth (lanes 0-1 in lo, 2-3 in hi, double) rounded to float, clamped to [0, 1] and
// quantised to 24 bits as Raster::depth_stage_t does (round to nearest even by adding and
// removing 2^52, times 1/(2^24 - 1)).
[[gnu::always_inline]] inline __m128 quantise_depth4(__m128d lo, __m128d hi) {
  __m128 z = _mm_movelh_ps(_mm_cvtpd_ps(lo), _mm_cvtpd_ps(hi));
  z = _mm_min_ps(_mm_max_ps(z, _mm_setzero_ps()), _mm_set1_ps(1.0f));
  const __m128d k = _mm_set1_pd(16777215.0), r = _mm_set1_pd(0x1p52), inv = _mm_set1_pd(1.0 / 16777215.0);
  __m128d a = _mm_mul_pd(_mm_cvtps_pd(z), k), b = _mm_mul_pd(_mm_cvtps_pd(_mm_movehl_ps(z, z)), k);
  a = _mm_sub_pd(_mm_add_pd(a, r), r), b = _mm_sub_pd(_mm_add_pd(b, r), r);
  return _mm_movelh_ps(_mm_cvtpd_ps(_mm_mul_pd(a, inv)), _mm_cvtpd_ps(_mm_mul_pd(b, inv)));
}
#endif

// Attribute layout of a pipeline vertex.
enum : int { kFront = 0, kBack = 4, kTex = 8, kFog = 12, kEye = 13, kNormal = 17, kAttrs = 20 };

struct PVert {
  Vec4 clip;
  float a[kAttrs];
  bool edge = true;  // the edge from this vertex to the next one is an original polygon edge
};

struct WinVert {
  double x, y, z, inv_w;
  const float* a;
};

// Barycentric planes l_i(x, y) = fa[i] x + fb[i] y + fc[i] from the unsnapped window positions.
// Coverage is decided on the 1/256-pixel grid, but depth and attributes are interpolated from
// the exact positions, as llvmpipe's setup does: weights from snapped vertices put texture
// coordinates up to a few 1/256 texel off on steep, distant triangles. False when the unsnapped
// area is not positive (a sliver that snapping turned over): the caller keeps snapped weights.
inline bool float_barycentrics(const WinVert* const v[3], double fa[3], double fb[3], double fc[3]) {
  const double area = (v[1]->x - v[0]->x) * (v[2]->y - v[0]->y) - (v[2]->x - v[0]->x) * (v[1]->y - v[0]->y);
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

constexpr int kRunMax = 64;  // triangles per run of Raster::triangle_run

// Vectors of doubles (GCC vector extensions): SSE2 pairs, AVX2 quadruples.
typedef double D2 __attribute__((vector_size(16)));
typedef double D4 __attribute__((vector_size(32)));

// --- runs of small triangles: the setup of several triangles at once ---
// Most triangles of a dense mesh cover a pixel or two. Raster::triangle_run sets up the
// triangles of a run a few at a time, one per double lane (four with AVX2, two with SSE2):
// snapping to the 1/256-pixel grid, bounding box, edge functions, the coverage of the pixel
// centres of a bounding box up to 4 x 4, and the barycentric, depth, 1/w and colour planes.
// These are Raster::triangle_q's operations lane by lane in its order (its 64-bit integer
// arithmetic done in doubles, exactly: every value stays below 2^53), so the same bits; no
// branch depends on a triangle's shape, where triangle_q branches per triangle.

struct RunSetup {
  static constexpr int kMax = kRunMax;
  enum : std::uint8_t { kNone, kTiny, kOther };  // draws nothing; small, covered; triangle() draws it
  // In: window x, y, depth (as float, then double), 1/w and the side's colour of each vertex.
  alignas(32) double x[3][kMax], y[3][kMax], z[3][kMax], iw[3][kMax], col[3][4][kMax];
  // Out: what to do, covered centres (bit 4 j + k: pixel (bx0 + k, by0 + j)), the first pixel and
  // quad, depth plane, and the float planes of 1/w and the colours (c, dx, dy each).
  std::uint8_t status[kMax];
  std::uint32_t mask[kMax];
  alignas(32) long long flip[kMax];  // (between the two passes: v1 and v2 swapped; first quad)
  alignas(32) double oxd[kMax], oyd[kMax];
  int bx0[kMax], by0[kMax], ox[kMax], oy[kMax];
  double zc[kMax], zdx[kMax], zdy[kMax];
  float pl[5][3][kMax];
};

// The calling or worker thread's run setup (the one-thread chunk path and the bands use it in
// turn, never at once on one thread).
RunSetup& run_scratch() {
  static thread_local RunSetup scratch;
  return scratch;
}

// (Always inlined into the AVX2 and the default builds of run_setup.)
template <class V, class L>
[[gnu::always_inline]] inline V vsel(L m, V a, V b) { return m ? a : b; }
template <class V>
[[gnu::always_inline]] inline V vmin(V a, V b) { return b < a ? b : a; }  // std::min's choice (equal: a)
template <class V>
[[gnu::always_inline]] inline V vmax(V a, V b) { return a < b ? b : a; }
template <class V>
[[gnu::always_inline]] inline V vabs(V a) { return a < 0.0 ? -a : a; }
// Nearest integer, ties to even, for |a| < 2^51; floor from it.
template <class V>
[[gnu::always_inline]] inline V vnearest(V a) {
  const V m = V{} + 0x1.8p52;
  return (a + m) - m;
}
template <class V>
[[gnu::always_inline]] inline V vfloor(V a) {
  const V t = vnearest(a);
  return vsel(a < t, t - 1.0, t);
}
// round_half_away (llround) for |a| < 2^51: nearest, then ties moved away from zero.
template <class V>
[[gnu::always_inline]] inline V vhalf_away(V a) {
  const V t = vnearest(a), d = a - t, one = V{} + 1.0;
  return t + vsel((d == 0.5) & (a > 0.0), one, V{}) - vsel((d == -0.5) & (a < 0.0), one, V{});
}
template <class V>
[[gnu::always_inline]] inline V vload(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

#if defined(__SSE2__)
template <class V>
[[gnu::always_inline]] inline void run_setup(RunSetup& r, int n, int x0, int y0, int x1, int y1) {
  typedef decltype(V{} < V{}) L;
  constexpr int kW = sizeof(V) / sizeof(double);
  // First the coverage (few values live: the mask stays in a register), then the planes.
  for (int t = 0; t < n; t += kW) {
    V x[3], y[3];
    for (int i = 0; i < 3; ++i) x[i] = vload<V>(r.x[i] + t), y[i] = vload<V>(r.y[i] + t);
    // Snapped coordinates; lanes beyond 2^25 (1/256 pixels) or not finite go to triangle().
    V X[3], Y[3];
    L ok = x[0] == x[0];
    for (int i = 0; i < 3; ++i) {
      const V sx = x[i] * 256.0, sy = y[i] * 256.0;
      ok &= (vabs(sx) < 0x1p25) & (vabs(sy) < 0x1p25);
      X[i] = vhalf_away(vsel(ok, sx, V{})), Y[i] = vhalf_away(vsel(ok, sy, V{}));
    }
    V area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    const L none = area == 0.0;
    const L flip = area < 0.0;
    auto swap12 = [&](V* a) {
      const V a1 = a[1];
      a[1] = vsel(flip, a[2], a[1]), a[2] = vsel(flip, a1, a[2]);
    };
    swap12(X), swap12(Y);
    std::memcpy(r.flip + t, &flip, sizeof flip);
    const V bx0 = vmax(V{} + double(x0), vfloor((vmin(vmin(X[0], X[1]), X[2]) + 127.0) * (1.0 / 256)));
    const V bx1 = vmin(V{} + double(x1 - 1), vfloor((vmax(vmax(X[0], X[1]), X[2]) - 128.0) * (1.0 / 256)));
    const V by0 = vmax(V{} + double(y0), vfloor((vmin(vmin(Y[0], Y[1]), Y[2]) + 127.0) * (1.0 / 256)));
    const V by1 = vmin(V{} + double(y1 - 1), vfloor((vmax(vmax(Y[0], Y[1]), Y[2]) - 128.0) * (1.0 / 256)));
    const L empty = (bx0 > bx1) | (by0 > by1);
    const V ox = vfloor(bx0 * 0.5) * 2.0, oy = vfloor(by0 * 0.5) * 2.0;
    V A[3], B[3], e[3];
    L fits = ok;
    for (int i = 0; i < 3; ++i) {
      const int a = (i + 1) % 3, b = (i + 2) % 3;
      const V dx = X[b] - X[a], dy = Y[b] - Y[a];
      A[i] = -dy, B[i] = dx;
      const L top_left = (dy < 0.0) | ((dy == 0.0) & (dx < 0.0));
      const V K = A[i] * (128.0 - X[a]) + B[i] * (128.0 - Y[a]) + vsel(top_left, V{}, V{} - 1.0);
      const V ci = A[i] * ox + B[i] * oy + vfloor(K * (1.0 / 256));
      fits &= vabs(ci) + vabs(A[i]) * (bx1 + 3.0 - ox) + vabs(B[i]) * (by1 + 3.0 - oy) <= 0x1p30;
      e[i] = ci + B[i] * (by0 - oy) + A[i] * (bx0 - ox);  // at pixel (bx0, by0)
    }
    const L tiny = (bx1 - bx0 < 4.0) & (by1 - by0 < 4.0);
    // Centres (bx0 + k, by0 + j), k, j < 4 (those beyond bx1 or by1 are masked off per triangle
    // below) into bit 4 j + k: covered when no edge function is negative. A step in k adds A, a
    // step in j adds B (exact); the edge functions start at +0 (e + 0: no -0 arises from sums of
    // integers then), so "not negative" is a clear sign bit, and the sign bits of the three
    // ORed are shifted in, from (3, 3) down to (0, 0).
    typedef unsigned long long UL __attribute__((vector_size(sizeof(V))));
    UL mask{};
    V r0 = ((e[0] + 0.0) + B[0] * 3.0) + A[0] * 3.0, r1 = ((e[1] + 0.0) + B[1] * 3.0) + A[1] * 3.0,
      r2 = ((e[2] + 0.0) + B[2] * 3.0) + A[2] * 3.0;
#pragma GCC unroll 4
    for (int j = 3; j >= 0; --j) {
      V t0 = r0, t1 = r1, t2 = r2;
#pragma GCC unroll 4
      for (int k = 3; k >= 0; --k) {
        UL b0, b1, b2;
        std::memcpy(&b0, &t0, sizeof b0), std::memcpy(&b1, &t1, sizeof b1), std::memcpy(&b2, &t2, sizeof b2);
        mask = (mask + mask) | (~(b0 | b1 | b2) >> 63);
        t0 -= A[0], t1 -= A[1], t2 -= A[2];
      }
      r0 -= B[0], r1 -= B[1], r2 -= B[2];
    }
    // As triangle_q decides: nothing when the snapped area is zero or no centre is in the box;
    // triangle() when not small, beyond 32-bit edge functions or a sliver; else the covered
    // centres inside the box (none: nothing).
    alignas(32) unsigned long long mk[kW];
    alignas(32) long long st_none[kW], st_small[kW];
    const L drawn_none = ok & (none | empty);
    const L small = ok & fits & tiny;  // (and a triangle that snapping left the right way round: below)
    std::memcpy(mk, &mask, sizeof mk), std::memcpy(st_none, &drawn_none, sizeof mk), std::memcpy(st_small, &small, sizeof mk);
    alignas(32) double b6[6][kW];
    std::memcpy(r.oxd + t, &ox, sizeof(V)), std::memcpy(r.oyd + t, &oy, sizeof(V));
    std::memcpy(b6[0], &bx0, sizeof(V)), std::memcpy(b6[1], &by0, sizeof(V)), std::memcpy(b6[2], &ox, sizeof(V)),
        std::memcpy(b6[3], &oy, sizeof(V)), std::memcpy(b6[4], &bx1, sizeof(V)), std::memcpy(b6[5], &by1, sizeof(V));
    for (int l = 0; l < kW; ++l) {
      std::uint8_t st = RunSetup::kOther;
      std::uint32_t m = 0;
      if (st_none[l]) {
        st = RunSetup::kNone;
      } else if (st_small[l]) {
        const int w = int(b6[4][l] - b6[0][l]), h = int(b6[5][l] - b6[1][l]);  // 0 .. 3
        m = std::uint32_t(mk[l]) & (0x1111u * ((2u << w) - 1)) & ((2u << (4 * h + 3)) - 1);
        st = m ? RunSetup::kTiny : RunSetup::kNone;
      }
      r.status[t + l] = st;
      r.mask[t + l] = m;
      r.bx0[t + l] = int(b6[0][l]), r.by0[t + l] = int(b6[1][l]), r.ox[t + l] = int(b6[2][l]), r.oy[t + l] = int(b6[3][l]);
    }
  }
  for (int t = 0; t < n; t += kW) {
    V x[3], y[3], z[3], iw[3], c[3][4];
    for (int i = 0; i < 3; ++i) {
      x[i] = vload<V>(r.x[i] + t), y[i] = vload<V>(r.y[i] + t), z[i] = vload<V>(r.z[i] + t), iw[i] = vload<V>(r.iw[i] + t);
      for (int k = 0; k < 4; ++k) c[i][k] = vload<V>(r.col[i][k] + t);
    }
    L flip;
    std::memcpy(&flip, r.flip + t, sizeof flip);
    auto swap12 = [&](V* a) {
      const V a1 = a[1];
      a[1] = vsel(flip, a[2], a[1]), a[2] = vsel(flip, a1, a[2]);
    };
    swap12(x), swap12(y), swap12(z), swap12(iw);
    for (int k = 0; k < 4; ++k) {
      const V c1 = c[1][k];
      c[1][k] = vsel(flip, c[2][k], c[1][k]), c[2][k] = vsel(flip, c1, c[2][k]);
    }
    const V ox = vload<V>(r.oxd + t), oy = vload<V>(r.oyd + t);
    // Barycentric planes from the unsnapped positions (float_barycentrics); a sliver that
    // snapping turned over goes to triangle().
    const V area2 = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    const L bary = (area2 > 0.0) & (area2 < __builtin_inf());
    const V inv = 1.0 / vsel(bary, area2, V{} + 1.0);
    V l0[3], gx[3], gy[3];
    for (int i = 0; i < 3; ++i) {
      const int a = (i + 1) % 3, b = (i + 2) % 3;
      const V fa = (y[a] - y[b]) * inv, fb = (x[b] - x[a]) * inv, fc = -(fa * x[a] + fb * y[a]);
      l0[i] = fa * (ox + 0.5) + fb * (oy + 0.5) + fc, gx[i] = fa, gy[i] = fb;
    }
    // (A loop, not a lambda taking vectors: lambdas do not take the AVX2 target, and an
    // unoptimised build calls them with the vectors where the base target does not look.)
    for (int k = 0; k < 5; ++k) {
      const V f0 = k ? c[0][k - 1] * iw[0] : iw[0], f1 = k ? c[1][k - 1] * iw[1] : iw[1],
              f2 = k ? c[2][k - 1] * iw[2] : iw[2];
      typedef float FV __attribute__((vector_size(sizeof(V) / 2)));
      const FV pc = __builtin_convertvector((l0[0] * f0 + l0[1] * f1) + l0[2] * f2, FV);
      const FV px = __builtin_convertvector((gx[0] * f0 + gx[1] * f1) + gx[2] * f2, FV);
      const FV py = __builtin_convertvector((gy[0] * f0 + gy[1] * f1) + gy[2] * f2, FV);
      std::memcpy(r.pl[k][0] + t, &pc, sizeof(FV)), std::memcpy(r.pl[k][1] + t, &px, sizeof(FV));
      std::memcpy(r.pl[k][2] + t, &py, sizeof(FV));
    }
    V zc = V{}, zdx = V{}, zdy = V{};
    for (int i = 0; i < 3; ++i) zc += l0[i] * z[i], zdx += gx[i] * z[i], zdy += gy[i] * z[i];
    std::memcpy(r.zc + t, &zc, sizeof(V)), std::memcpy(r.zdx + t, &zdx, sizeof(V)), std::memcpy(r.zdy + t, &zdy, sizeof(V));
    alignas(32) long long bok[kW];
    std::memcpy(bok, &bary, sizeof bok);
    for (int l = 0; l < kW; ++l)
      if (!bok[l] && r.status[t + l] == RunSetup::kTiny) r.status[t + l] = RunSetup::kOther;
  }
}

__attribute__((target("avx2"))) void run_setup_avx2(RunSetup& r, int n, int x0, int y0, int x1, int y1) {
  run_setup<D4>(r, n, x0, y0, x1, y1);
}
void run_setup_default(RunSetup& r, int n, int x0, int y0, int x1, int y1) { run_setup<D2>(r, n, x0, y0, x1, y1); }
#endif

// A set-up primitive waiting for rasterisation (binned to bands of rows, then drawn by bands in
// parallel; within a band the primitives keep their submission order, so the image is the same
// as drawing them one by one). Compact: window coordinates and pointers to the attribute sets
// (owned by the queue or by the batch's vertex buffer, alive until the bands are drawn).
struct Job {
  enum Kind : std::uint8_t { Tri, Line, Point } kind = Tri;
  std::uint8_t side = 0;
  int row0 = 0, row1 = 0;  // rows the primitive may touch
  WinVert v[3];
  const float* flat = nullptr;  // the provoking vertex's attributes for flat shading
};
constexpr int kBandRows = 32;

// Attribute sets copied for queued primitives, in blocks that never move (pointers stay valid
// while the store grows); clear() keeps the blocks for the next batch.
class AttrStore {
 public:
  float* add(const float* src) {
    const std::size_t b = used_ / kBlock, o = used_ % kBlock;
    if (b == blocks_.size()) blocks_.push_back(std::make_unique<float[]>(kBlock * kAttrs));
    float* d = blocks_[b].get() + o * kAttrs;
    std::memcpy(d, src, sizeof(float) * kAttrs);
    ++used_;
    return d;
  }
  void clear() { used_ = 0; }

 private:
  static constexpr std::size_t kBlock = 256;
  std::vector<std::unique_ptr<float[]>> blocks_;
  std::size_t used_ = 0;
};

// Queued primitives of one stretch of a batch, in submission order, with their own binning by
// band (a counting sort), so that queues are filled and binned in parallel and the bands read
// them in queue order without a serial merge.
struct Queue {
  std::vector<Job> jobs;
  AttrStore store;
  std::vector<std::uint32_t> band_start, band_jobs;  // jobs of band b: band_jobs[band_start[b] .. band_start[b + 1])
  void clear() { jobs.clear(), store.clear(); }
  void bin(int bands) {
    band_start.assign(std::size_t(bands) + 1, 0);
    auto range = [bands](const Job& j, int& b0, int& b1) {
      if (j.row1 < 0) return false;
      b0 = std::max(0, j.row0 / kBandRows), b1 = std::min(bands - 1, j.row1 / kBandRows);
      return b0 <= b1;
    };
    int b0 = 0, b1 = 0;
    for (const Job& j : jobs)
      if (range(j, b0, b1))
        for (int b = b0; b <= b1; ++b) ++band_start[b + 1];
    for (int b = 0; b < bands; ++b) band_start[b + 1] += band_start[b];
    band_jobs.resize(band_start[bands]);
    std::vector<std::uint32_t>& cursor = cursor_;
    cursor.assign(band_start.begin(), band_start.end() - 1);
    for (std::size_t i = 0; i < jobs.size(); ++i)
      if (range(jobs[i], b0, b1))
        for (int b = b0; b <= b1; ++b) band_jobs[cursor[b]++] = std::uint32_t(i);
  }

 private:
  std::vector<std::uint32_t> cursor_;
};

[[gnu::always_inline]] inline Vec4f clamp01(const Vec4f& c) { return c.cwiseMax(0.0f).cwiseMin(1.0f); }

// Per-draw lighting constants (float, as GL implementations light): the enabled lights with
// their position divided by w or their unit direction, unit spot direction and cosine of the
// cutoff, so that the per-vertex work is the equation itself.
using Vec3f = Eigen::Vector3f;

struct LightSetup {
  struct L {
    Vec3f pos;    // point light: position / w; directional: unit direction
    bool local = false;  // w != 0
    float kc = 1, kl = 0, kq = 0;
    bool spot = false;   // (initialised: unused slots are copied with the setup)
    Vec3f sdir;          // unit spot direction
    float cos_cut = -1, sexp = 0;
    Vec3f amb, dif, spec;
  };
  L l[8];
  int n = 0;
  Vec3f model_ambient;
  bool local_viewer = false;
  bool color_material[2] = {false, false};
  explicit LightSetup(const Context::State& s) {
    model_ambient = s.model_ambient.head<3>();
    local_viewer = s.local_viewer;
    for (int side = 0; side < 2; ++side)
      color_material[side] = s.on(Cap::ColorMaterial) &&
                             (s.cm_face == Face::FrontAndBack || (s.cm_face == Face::Front) == (side == 0));
    for (int i = 0; i < 8; ++i) {
      if (!s.on(light_cap(i))) continue;
      const Light& src = s.lights[i];
      L& d = l[n++];
      d.local = src.position.w() != 0;
      d.pos = d.local ? Vec3f(src.position.head<3>() / src.position.w()) : Vec3f(src.position.head<3>().normalized());
      d.kc = src.constant_attenuation, d.kl = src.linear_attenuation, d.kq = src.quadratic_attenuation;
      d.spot = src.spot_cutoff != 180;
      d.sdir = src.spot_direction.normalized().cast<float>();
      d.cos_cut = float(std::cos(radians(src.spot_cutoff)));
      d.sexp = src.spot_exponent;
      d.amb = src.ambient.head<3>(), d.dif = src.diffuse.head<3>(), d.spec = src.specular.head<3>();
    }
  }
};

// Lighting four or sixteen vertices at once (SoA, GCC vector extensions): F4 (SSE2, the default
// x86-64 build) or F16, two F8 side by side (AVX2, compiled with target("avx2") and chosen at run
// time). Both are written once, as templates on the vector type, with the same operations lane by
// lane as the scalar light_vertex, and no FMA (the AVX2 target does not include it), so every lane
// gives light_vertex's bits.
typedef float F4 __attribute__((vector_size(16)));
typedef int I4 __attribute__((vector_size(16)));
typedef unsigned U4 __attribute__((vector_size(16)));
typedef float F8 __attribute__((vector_size(32)));
typedef int I8 __attribute__((vector_size(32)));
typedef unsigned U8 __attribute__((vector_size(32)));

// The integer (mask) vector of a float vector's lanes, and the register-wide double vector that
// holds half of them (a float vector's doubles are two of these: wider vectors than the target's
// registers compile poorly, selects lane by lane).
template <class V> struct Lanes;
template <> struct Lanes<F4> {
  typedef I4 I;
  typedef U4 U;
  typedef D2 D;
  enum { W = 4 };
};
template <> struct Lanes<F8> {
  typedef I8 I;
  typedef U8 U;
  typedef D4 D;
  enum { W = 8 };
};

// Two vectors as one: the AVX2 lighting's 16 lanes, two independent groups of 8 whose operations
// alternate, so that the lighting's long dependency chains (square root, divide, the pow's divide
// and polynomials) overlap. Operators apply to both halves; vector selects are written sel(m, x, y)
// (the same as m ? x : y on plain vectors, which cannot be overloaded).
template <class T>
struct X2 {
  T a, b;
  // (Always inlined: see the note at the -Wpsabi pragma.)
  X2() = default;
  [[gnu::always_inline]] constexpr X2(T a_, T b_) : a(a_), b(b_) {}
  template <class S>
  [[gnu::always_inline]] explicit X2(const X2<S>& o) : a(T(o.a)), b(T(o.b)) {}  // bits reinterpreted, as T(S) does
};
template <class T> struct IsX2 : std::false_type {};
template <class T> struct IsX2<X2<T>> : std::true_type {};
#define WEDGE_X2_OP(op)                                                                                   \
  template <class T>                                                                                      \
  [[gnu::always_inline]] inline auto operator op(const X2<T>& x, const X2<T>& y) {                        \
    return X2<decltype(x.a op y.a)>{x.a op y.a, x.b op y.b};                                              \
  }                                                                                                       \
  template <class T, class S>                                                                             \
    requires std::is_arithmetic_v<S>                                                                      \
  [[gnu::always_inline]] inline auto operator op(const X2<T>& x, S y) {                                   \
    return X2<decltype(x.a op y)>{x.a op y, x.b op y};                                                    \
  }                                                                                                       \
  template <class T, class S>                                                                             \
    requires std::is_arithmetic_v<S>                                                                      \
  [[gnu::always_inline]] inline auto operator op(S x, const X2<T>& y) {                                   \
    return X2<decltype(x op y.a)>{x op y.a, x op y.b};                                                    \
  }
WEDGE_X2_OP(+)
WEDGE_X2_OP(-)
WEDGE_X2_OP(*)
WEDGE_X2_OP(/)
WEDGE_X2_OP(&)
WEDGE_X2_OP(|)
WEDGE_X2_OP(<<)
WEDGE_X2_OP(>>)
WEDGE_X2_OP(<)
WEDGE_X2_OP(>)
WEDGE_X2_OP(==)
WEDGE_X2_OP(!=)
#undef WEDGE_X2_OP
template <class T>
[[gnu::always_inline]] inline X2<T> operator-(const X2<T>& x) {
  return {-x.a, -x.b};
}
template <class T>
[[gnu::always_inline]] inline X2<T> operator~(const X2<T>& x) {
  return {~x.a, ~x.b};
}
template <> struct Lanes<X2<F8>> {
  typedef X2<I8> I;
  typedef X2<U8> U;
  typedef X2<D4> D;
  enum { W = 16 };
};
// m ? x : y, lane by lane (m: a comparison's mask).
template <class M, class T>
[[gnu::always_inline]] inline T sel(const M& m, const T& x, const T& y) {
  if constexpr (IsX2<T>::value) return T{sel(m.a, x.a, y.a), sel(m.b, x.b, y.b)};
  else return m ? x : y;
}

// x in every lane (an element-wise copy: x - 0 or x + 0 would turn a -0 into +0).
template <class V>
[[gnu::always_inline]] inline V splat(float x) {
  if constexpr (IsX2<V>::value) {
    return V{splat<decltype(V::a)>(x), splat<decltype(V::a)>(x)};
  } else {
    V r;
    for (int l = 0; l < Lanes<V>::W; ++l) r[l] = x;
    return r;
  }
}
[[gnu::always_inline]] inline F4 bcast(float x) { return splat<F4>(x); }

// Halves of an eight-lane vector.
[[gnu::always_inline]] inline F4 lo(F8 x) { return __builtin_shufflevector(x, x, 0, 1, 2, 3); }
[[gnu::always_inline]] inline F4 hi(F8 x) { return __builtin_shufflevector(x, x, 4, 5, 6, 7); }
[[gnu::always_inline]] inline I4 lo(I8 x) { return __builtin_shufflevector(x, x, 0, 1, 2, 3); }
[[gnu::always_inline]] inline I4 hi(I8 x) { return __builtin_shufflevector(x, x, 4, 5, 6, 7); }

[[gnu::always_inline]] inline F4 vsqrt(F4 x) {
#if defined(__SSE2__)
  return _mm_sqrt_ps(x);
#else
  return F4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}
// The eight-lane and four-double ones, used only inside the AVX2 build, as one 256-bit instruction
// (not two halves: a shorter dependency chain), written as inline assembly since an AVX intrinsic
// cannot be called from the lighting templates, which are also compiled for the default target.
[[gnu::always_inline]] inline F8 vsqrt(F8 x) {
  F8 r;
  asm("vsqrtps %1, %0" : "=x"(r) : "x"(x));
  return r;
}
[[gnu::always_inline]] inline D2 vsqrt(D2 x) {
#if defined(__SSE2__)
  return _mm_sqrt_pd(x);
#else
  return D2{std::sqrt(x[0]), std::sqrt(x[1])};
#endif
}
[[gnu::always_inline]] inline D4 vsqrt(D4 x) {
  D4 r;
  asm("vsqrtpd %1, %0" : "=x"(r) : "x"(x));
  return r;
}
template <class T>
[[gnu::always_inline]] inline X2<T> vsqrt(const X2<T>& x) {
  return {vsqrt(x.a), vsqrt(x.b)};
}
// Float (or int) lanes to doubles, in two halves (exact), and doubles back to floats (rounded to
// nearest).
[[gnu::always_inline]] inline void widen(F4 x, D2* d) {
  d[0] = __builtin_convertvector(__builtin_shufflevector(x, x, 0, 1), D2);
  d[1] = __builtin_convertvector(__builtin_shufflevector(x, x, 2, 3), D2);
}
[[gnu::always_inline]] inline void widen(I4 x, D2* d) {
  d[0] = __builtin_convertvector(__builtin_shufflevector(x, x, 0, 1), D2);
  d[1] = __builtin_convertvector(__builtin_shufflevector(x, x, 2, 3), D2);
}
[[gnu::always_inline]] inline void widen(F8 x, D4* d) {
  d[0] = __builtin_convertvector(lo(x), D4), d[1] = __builtin_convertvector(hi(x), D4);
}
[[gnu::always_inline]] inline void widen(I8 x, D4* d) {
  d[0] = __builtin_convertvector(lo(x), D4), d[1] = __builtin_convertvector(hi(x), D4);
}
[[gnu::always_inline]] inline F4 narrow(const D2* d) {
#if defined(__SSE2__)
  return _mm_movelh_ps(_mm_cvtpd_ps(d[0]), _mm_cvtpd_ps(d[1]));
#else
  return F4{float(d[0][0]), float(d[0][1]), float(d[1][0]), float(d[1][1])};
#endif
}
[[gnu::always_inline]] inline F8 narrow(const D4* d) {
  const F4 a = __builtin_convertvector(d[0], F4), b = __builtin_convertvector(d[1], F4);
  return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
}
[[gnu::always_inline]] inline bool any(I4 m) {
#if defined(__SSE2__)
  return _mm_movemask_ps(__m128(m)) != 0;
#else
  return (m[0] | m[1] | m[2] | m[3]) != 0;
#endif
}
[[gnu::always_inline]] inline bool any(I8 m) { return any(I4(lo(m) | hi(m))); }
// The same for two vectors as one: d[0] holds x.a's lanes, d[1] x.b's (in lane order, as the
// halves of a plain vector).
template <class T, class D>
[[gnu::always_inline]] inline void widen(const X2<T>& x, X2<D>* d) {
  D a[2], b[2];
  widen(x.a, a), widen(x.b, b);
  d[0] = {a[0], a[1]}, d[1] = {b[0], b[1]};
}
template <class D>
[[gnu::always_inline]] inline auto narrow(const X2<D>* d) {
  const D a[2] = {d[0].a, d[0].b}, b[2] = {d[1].a, d[1].b};
  return X2<decltype(narrow(a))>{narrow(a), narrow(b)};
}
template <class T>
[[gnu::always_inline]] inline bool any(const X2<T>& m) {
  return any(T(m.a | m.b));
}
// Eigen's order for a 3-vector's dot product and squared norm: a0 b0 + (a1 b1 + a2 b2).
template <class V>
[[gnu::always_inline]] inline V dot3(const V* a, const V* b) {
  return a[0] * b[0] + (a[1] * b[1] + a[2] * b[2]);
}
// Eigen's cwiseMax(0) then cwiseMin(1) (std::max / std::min: NaN stays NaN).
template <class V>
[[gnu::always_inline]] inline V vclamp01(V c) {
  c = sel(c < 0.0f, splat<V>(0.0f), c);
  return sel(1.0f < c, splat<V>(1.0f), c);
}

// x^y for x >= 0 and y > 0 (the callers treat y = 0 as GL's 0^0 = 1), lane by lane: 2^(y log2 x)
// in double (so that y up to 128 does not magnify a rounding), rounded to float once at the end.
// Relative error below 1e-7 where the result is a normal float, within the last (subnormal) place
// below that (tests/render/test_lighting.cpp); 0^y = 0, inf^y = inf, NaN stays NaN; overflow gives
// inf.
template <class V>
[[gnu::always_inline]] inline V vpow(V x, float y) {
  typedef typename Lanes<V>::I I;
  typedef typename Lanes<V>::U U;
  typedef typename Lanes<V>::D D;
  typedef decltype(D{} < D{}) Q;  // 64-bit integer lanes
  // x = m 2^e with m in [sqrt(1/2), sqrt(2)): the bits less those of sqrt(1/2), shifted, give e
  // (subnormal x scaled by 2^24 first). (Unsigned arithmetic: no overflow for other inputs.)
  const I tiny = x < 0x1p-126f;
  const U b = U(sel(tiny, x * 0x1p24f, x));
  const I e = I(b - 0x3f3504f3u) >> 23;
  const V m = V(b - (U(e) << 23));
  // log2 m = 2 atanh(s) / ln 2, s = (m - 1) / (m + 1), |s| <= 0.1716: the odd series to s^11
  // (truncation below 2e-11). Then t = y log2 x (held to [-160, 160]: beyond, the float result
  // over- or underflows anyway), and 2^t = 2^i 2^f, i = t rounded to nearest, |f| <= 1/2: 2^f by
  // its Taylor series to f^7 (remainder below 6e-9), times 2^i (exact), then rounded to float.
  // Both polynomials by Estrin's scheme (pairs, then powers of the square), not Horner's: chains of
  // 7 and 6 operations, not 12 and 14 (the lighting's longest dependency chain runs through here).
  constexpr double k = 2 / 0.693147180559945309417232121458;
  constexpr double c1 = 0.6931471805599453, c2 = 0.2402265069591007, c3 = 0.055504108664821576,
                   c4 = 0.009618129107628477, c5 = 0.0013333558146428441, c6 = 0.00015403530393381606,
                   c7 = 1.5252733804059838e-05;
  D md[2], ed[2], rd[2];
  widen(m, md), widen(I(e - (tiny & 24)), ed);
#pragma GCC unroll 4
  for (int h = 0; h < 2; ++h) {
    const D s = (md[h] - 1.0) / (md[h] + 1.0);
    const D s2 = s * s, s4 = s2 * s2, s8 = s4 * s4;
    const D l = s * (((k + s2 * (k / 3)) + s4 * (k / 5 + s2 * (k / 7))) + s8 * (k / 9 + s2 * (k / 11)));
    D t = double(y) * (ed[h] + l);
    t = sel(t < -160.0, D{} - 160.0, t);
    t = sel(t > 160.0, D{} + 160.0, t);
    // r = 1.5 2^52 + i: its low bits hold i.
    const D r = t + 0x1.8p52;
    const D f = t - (r - 0x1.8p52);
    const D f2 = f * f, f4 = f2 * f2;
    const D p = ((1.0 + f * c1) + f2 * (c2 + f * c3)) + f4 * ((c4 + f * c5) + f2 * (c6 + f * c7));
    rd[h] = p * D((Q(r) + 1023) << 52);
  }
  V res = narrow(rd);
  res = sel(x == 0.0f, splat<V>(0.0f), res);
  res = sel(x == __builtin_huge_valf(), x, res);
  return sel(x != x, x, res);
}

// The scalar pow of the lighting equation: vpow's lane 0, so light_vertex and the vector
// lighting give the same bits.
[[gnu::always_inline]] inline float gl_pow(float x, float y) { return vpow(bcast(x), y)[0]; }


// The lighting equation of GL 1.x section 2.14.1 for one side, in float. P is the eye-space
// position, n the unit (or as given) eye-space normal; `vertex_color` feeds colour material.
// pow only for a positive specular term with non-zero shininess, as GL defines 0^0 = 1.
Vec4f light_vertex(const Context::State& s, const LightSetup& ls, const Vec4& P4, const Vec3& nd,
                   const Vec4f& vertex_color, int side) {
  Material m = s.material[side];  // a copy: colour material may replace parts of it
  if (ls.color_material[side]) {
    switch (s.cm_mode) {
      case ColorMaterialMode::Ambient: m.ambient = vertex_color; break;
      case ColorMaterialMode::Diffuse: m.diffuse = vertex_color; break;
      case ColorMaterialMode::Specular: m.specular = vertex_color; break;
      case ColorMaterialMode::Emission: m.emission = vertex_color; break;
      case ColorMaterialMode::AmbientAndDiffuse: m.ambient = m.diffuse = vertex_color; break;
    }
  }
  const Vec3f P = (P4.head<3>() / P4.w()).cast<float>();
  const Vec3f n = nd.cast<float>();
  const Vec3f ma = m.ambient.head<3>(), md = m.diffuse.head<3>(), ms = m.specular.head<3>();
  Vec3f c = m.emission.head<3>() + ma.cwiseProduct(ls.model_ambient);
  Vec3f eye_dir(0, 0, 1);
  if (ls.local_viewer) eye_dir = -P.normalized();
  for (int i = 0; i < ls.n; ++i) {
    const LightSetup::L& L = ls.l[i];
    Vec3f VP;
    float att = 1;
    if (L.local) {
      VP = L.pos - P;
      float d = VP.norm();
      VP /= d;
      att = 1.0f / (L.kc + L.kl * d + L.kq * d * d);
    } else {
      VP = L.pos;
    }
    float spot = 1;
    if (L.spot) {
      float cosang = -VP.dot(L.sdir);
      if (cosang < L.cos_cut) spot = 0;
      else spot = L.sexp == 0 ? 1.0f : gl_pow(std::max(cosang, 0.0f), L.sexp);
    }
    if (att * spot == 0) continue;
    Vec3f term = ma.cwiseProduct(L.amb);
    float ndl = n.dot(VP);
    if (ndl > 0) {
      term += ndl * md.cwiseProduct(L.dif);
      Vec3f h = VP + eye_dir;
      float hn = h.norm();
      if (hn > 0) {
        float ndh = n.dot(h) / hn;
        if (ndh > 0) {
          float f = m.shininess == 0 ? 1.0f : gl_pow(ndh, m.shininess);
          term += f * ms.cwiseProduct(L.spec);
        }
      }
    }
    c += (att * spot) * term;
  }
  Vec4f out(c.x(), c.y(), c.z(), m.diffuse.w());
  return clamp01(out);
}

// light_vertex's per-draw constants broadcast to the lanes of V, with the products of material
// and light colours it forms per vertex (the same float products) made once. Colour material
// replaces material colours by the vertex colours: those products are then formed per block.
template <class V>
struct LightConsts {
  struct Side {
    V me[4], ma[4], md[4], ms[4];
    V base[3];                          // emission + ambient * model ambient
    V amb[8][3], dif[8][3], spec[8][3];  // material * light colours
    float shin = 0;
    bool cm = false;
  };
  struct L {
    V pos[3], sdir[3], lamb[3], ldif[3], lspec[3];
  };
  Side side[2];
  L l[8];
  V model_ambient[3];
  LightConsts(const Context::State& s, const LightSetup& ls) {
    for (int k = 0; k < 3; ++k) model_ambient[k] = splat<V>(ls.model_ambient[k]);
    for (int i = 0; i < ls.n; ++i)
      for (int k = 0; k < 3; ++k) {
        const LightSetup::L& L = ls.l[i];
        l[i].pos[k] = splat<V>(L.pos[k]), l[i].sdir[k] = splat<V>(L.sdir[k]);
        l[i].lamb[k] = splat<V>(L.amb[k]), l[i].ldif[k] = splat<V>(L.dif[k]), l[i].lspec[k] = splat<V>(L.spec[k]);
      }
    for (int sd = 0; sd < (s.two_side ? 2 : 1); ++sd) {  // (the back side is lit only two-sided)
      const Material& m = s.material[sd];
      Side& d = side[sd];
      d.cm = ls.color_material[sd];
      d.shin = m.shininess;
      for (int k = 0; k < 4; ++k)
        d.me[k] = splat<V>(m.emission[k]), d.ma[k] = splat<V>(m.ambient[k]), d.md[k] = splat<V>(m.diffuse[k]),
        d.ms[k] = splat<V>(m.specular[k]);
      for (int k = 0; k < 3; ++k) d.base[k] = d.me[k] + d.ma[k] * model_ambient[k];
      for (int i = 0; i < ls.n; ++i)
        for (int k = 0; k < 3; ++k)
          d.amb[i][k] = d.ma[k] * l[i].lamb[k], d.dif[i][k] = d.md[k] * l[i].ldif[k], d.spec[i][k] = d.ms[k] * l[i].lspec[k];
    }
  }
};

// Four (F4) or sixteen (F16) vertices lit at once: light_vertex's float operations in the same
// order, lane by lane, so the colours are the same bits. P: eye positions (divided by w);
// n: normals, negated for the back side; vc: vertex colours (read with colour material only).
// (The loops over components are unrolled by pragmas here, in vpow and in light_needed: left as
// loops, -O2 keeps those small arrays of vectors on the stack, each step a store and a reload.)
template <class V, bool CM>
[[gnu::always_inline]] inline void light_t(const Context::State& s, const LightSetup& ls,
                                           const typename LightConsts<V>::Side& m, const LightConsts<V>& lc,
                                           const V* P, const V* n, const V* vc, V* out) {
  typedef typename Lanes<V>::I I;
  const V *me = m.me, *ma = m.ma, *md = m.md, *ms = m.ms;
  V cme[4], cma[4], cmd[4], cms[4];
  if constexpr (CM) {
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k) cme[k] = m.me[k], cma[k] = m.ma[k], cmd[k] = m.md[k], cms[k] = m.ms[k];
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k) {
      switch (s.cm_mode) {
        case ColorMaterialMode::Ambient: cma[k] = vc[k]; break;
        case ColorMaterialMode::Diffuse: cmd[k] = vc[k]; break;
        case ColorMaterialMode::Specular: cms[k] = vc[k]; break;
        case ColorMaterialMode::Emission: cme[k] = vc[k]; break;
        case ColorMaterialMode::AmbientAndDiffuse: cma[k] = cmd[k] = vc[k]; break;
      }
    }
    me = cme, ma = cma, md = cmd, ms = cms;
  }
  V c[3];
#pragma GCC unroll 4
  for (int k = 0; k < 3; ++k) c[k] = CM ? me[k] + ma[k] * lc.model_ambient[k] : m.base[k];
  V ed[3] = {splat<V>(0), splat<V>(0), splat<V>(1)};
  if (ls.local_viewer) {
    const V z = dot3(P, P);
    const I pos = z > 0.0f;
    const V r = vsqrt(z);
#pragma GCC unroll 4
    for (int k = 0; k < 3; ++k) ed[k] = sel(pos, -(P[k] / r), -P[k]);
  }
  const float shin = m.shin;
  for (int i = 0; i < ls.n; ++i) {
    const LightSetup::L& L = ls.l[i];
    const typename LightConsts<V>::L& C = lc.l[i];
    V VP[3];
    V att = splat<V>(1);
    if (L.local) {
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) VP[k] = C.pos[k] - P[k];
      const V d = vsqrt(dot3(VP, VP));
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) VP[k] = VP[k] / d;
      att = 1.0f / ((L.kc + L.kl * d) + (L.kq * d) * d);
    } else {
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) VP[k] = C.pos[k];
    }
    V spot = splat<V>(1);
    if (L.spot) {
      const V cosang = -dot3(VP, C.sdir);
      const I in = ~(cosang < L.cos_cut);
      if (L.sexp == 0) spot = sel(in, splat<V>(1), splat<V>(0));
      else spot = sel(in, vpow(sel(cosang < 0.0f, splat<V>(0.0f), cosang), L.sexp), splat<V>(0));  // (std::max)
    }
    const V k = att * spot;
    const I use = ~(k == 0.0f);
    if (!any(use)) continue;
    V amb[3], dif[3], spec[3];
#pragma GCC unroll 4
    for (int q = 0; q < 3; ++q) {
      amb[q] = CM ? ma[q] * C.lamb[q] : m.amb[i][q];
      dif[q] = CM ? md[q] * C.ldif[q] : m.dif[i][q];
      spec[q] = CM ? ms[q] * C.lspec[q] : m.spec[i][q];
    }
    V term[3];
    const V ndl = dot3(n, VP);
    const I dmask = ndl > 0.0f;
#pragma GCC unroll 4
    for (int q = 0; q < 3; ++q) term[q] = sel(dmask, amb[q] + ndl * dif[q], amb[q]);
    V h[3];
#pragma GCC unroll 4
    for (int q = 0; q < 3; ++q) h[q] = VP[q] + ed[q];
    const V hn = vsqrt(dot3(h, h));
    const V ndh = dot3(n, h) / hn;
    const I smask = dmask & (hn > 0.0f) & (ndh > 0.0f);
    if (any(smask)) {
      // (The lanes outside smask compute a pow that is not used.)
      const V f = shin != 0 ? vpow(ndh, shin) : splat<V>(1);
#pragma GCC unroll 4
      for (int q = 0; q < 3; ++q) term[q] = sel(smask, term[q] + f * spec[q], term[q]);
    }
#pragma GCC unroll 4
    for (int q = 0; q < 3; ++q) c[q] = sel(use, c[q] + k * term[q], c[q]);
  }
#pragma GCC unroll 4
  for (int q = 0; q < 3; ++q) out[q] = vclamp01(c[q]);
  out[3] = vclamp01(md[3]);
}

template <class V>
[[gnu::always_inline]] inline void light(const Context::State& s, const LightSetup& ls, const LightConsts<V>& lc,
                                         const V* P, const V* n, const V* vc, int side, V* out) {
  const typename LightConsts<V>::Side& m = lc.side[side];
  if (m.cm) light_t<V, true>(s, ls, m, lc, P, n, vc, out);
  else light_t<V, false>(s, ls, m, lc, P, n, vc, out);
}

// The two builds, out of line (the equation is inlined once per build and colour-material case).
void light_lanes(const Context::State& s, const LightSetup& ls, const LightConsts<F4>& lc, const F4* P, const F4* n,
                 const F4* vc, int side, F4* out) {
  light<F4>(s, ls, lc, P, n, vc, side, out);
}
#if defined(__x86_64__) && defined(__GNUC__)
typedef X2<F8> F16;  // the AVX2 build's lanes: two groups of eight
__attribute__((target("avx2"))) void light_lanes_avx2(const Context::State& s, const LightSetup& ls,
                                                      const LightConsts<F16>& lc, const F16* P, const F16* n,
                                                      const F16* vc, int side, F16* out) {
  light<F16>(s, ls, lc, P, n, vc, side, out);
}
[[gnu::always_inline]] inline void light_lanes(const Context::State& s, const LightSetup& ls,
                                               const LightConsts<F16>& lc, const F16* P, const F16* n,
                                               const F16* vc, int side, F16* out) {
  light_lanes_avx2(s, ls, lc, P, n, vc, side, out);
}
#endif


bool two_sided_lighting(const Context::State& s) { return s.on(Cap::Lighting) && s.two_side; }

// Whether the vertex stage lights the vertex colours (Phong lights per fragment instead).
bool vertex_lighting(const Context::State& s) { return s.on(Cap::Lighting) && s.shade != ShadeModel::Phong; }

// Which attributes the rasteriser will read (the others are left zero): texture coordinates
// when texturing, the fog distance with fog, the eye position and normal for Phong.
struct AttrNeeds {
  bool tex = true, fog = true, eye_normal = true;
  AttrNeeds() = default;
  explicit AttrNeeds(const Context::State& s)
      : tex(s.on(Cap::Texture2D) && s.texture && !s.texture->levels.empty()),
        fog(s.on(Cap::Fog)),
        eye_normal(s.on(Cap::Lighting) && s.shade == ShadeModel::Phong) {}
};

// The vertex stage but the lit colours: eye-space normal, unlit colours (when not lit),
// texture coordinates (texgen, texture matrix), fog distance, eye position and normal into
// `a` (those in `need`). Returns the eye-space normal (unit if normalised) for lighting.
Vec3 vertex_attrs(const Context::State& s, const InVertex& v, const Vec4& eye, const Mat3& nmat, float* a,
                  const AttrNeeds& need = AttrNeeds()) {
  Vec3 n = nmat * v.normal;
  if (s.on(Cap::Normalize) || s.shade == ShadeModel::Phong) {
    double len = n.norm();
    if (len > 0) n /= len;
  }
  if (!vertex_lighting(s)) {
    Vec4f c = clamp01(v.color);
    for (int k = 0; k < 4; ++k) a[kFront + k] = a[kBack + k] = c[k];
  }
  if (need.tex) {
    Vec4 tex = v.tex;
    for (int k = 0; k < 2; ++k) {
      if (!s.on(k == 0 ? Cap::TextureGenS : Cap::TextureGenT)) continue;
      switch (s.gen_mode[k]) {
        case TexGenMode::ObjectLinear: tex[k] = s.obj_plane[k].dot(v.position); break;
        case TexGenMode::EyeLinear: tex[k] = s.eye_plane[k].dot(eye); break;
        case TexGenMode::SphereMap: {
          Vec3 u = (eye.head<3>() / eye.w()).normalized();
          Vec3 nn = n.normalized();
          Vec3 r = u - 2 * nn.dot(u) * nn;
          double m = 2 * std::sqrt(r.x() * r.x() + r.y() * r.y() + (r.z() + 1) * (r.z() + 1));
          tex[k] = (k == 0 ? r.x() : r.y()) / m + 0.5;
          break;
        }
      }
    }
    if (s.on(Cap::Texture2D)) tex = s.top(MatrixMode::Texture) * tex;
    for (int k = 0; k < 4; ++k) a[kTex + k] = float(tex[k]);
  } else {
    for (int k = 0; k < 4; ++k) a[kTex + k] = 0;
  }
  a[kFog] = need.fog ? float(std::abs(eye.z())) : 0.0f;
  if (need.eye_normal) {
    for (int k = 0; k < 4; ++k) a[kEye + k] = float(eye[k]);
    for (int k = 0; k < 3; ++k) a[kNormal + k] = float(n[k]);
  } else {
    for (int k = kEye; k < kAttrs; ++k) a[k] = 0;
  }
  return n;
}

// Vertex stage: object coordinates to clip coordinates with all per-vertex attributes.
// `eye` and `clip` are the vertex's mv * position and proj * eye, computed by the caller.
PVert process_vertex(const Context::State& s, const LightSetup& ls, const InVertex& v, const Vec4& eye,
                     const Vec4& clip, const Mat3& nmat) {
  PVert out;
  out.clip = clip;
  const Vec3 n = vertex_attrs(s, v, eye, nmat, out.a);
  if (vertex_lighting(s)) {
    Vec4f f = light_vertex(s, ls, eye, n, v.color, 0);
    Vec4f b = s.two_side ? light_vertex(s, ls, eye, -n, v.color, 1) : f;
    for (int k = 0; k < 4; ++k) out.a[kFront + k] = f[k], out.a[kBack + k] = b[k];
  }
  return out;
}

// Lanes to vertices: the RGBA of lane l (c: R, G, B, A rows) to a + l * stride, for l < lanes.
[[gnu::always_inline]] inline void store_rgba(const F4* c, float* a, std::size_t stride, std::size_t lanes) {
  const F4 t0 = __builtin_shufflevector(c[0], c[1], 0, 4, 1, 5), t1 = __builtin_shufflevector(c[0], c[1], 2, 6, 3, 7);
  const F4 t2 = __builtin_shufflevector(c[2], c[3], 0, 4, 1, 5), t3 = __builtin_shufflevector(c[2], c[3], 2, 6, 3, 7);
  const F4 v[4] = {__builtin_shufflevector(t0, t2, 0, 1, 4, 5), __builtin_shufflevector(t0, t2, 2, 3, 6, 7),
                   __builtin_shufflevector(t1, t3, 0, 1, 4, 5), __builtin_shufflevector(t1, t3, 2, 3, 6, 7)};
  for (std::size_t l = 0; l < lanes; ++l) std::memcpy(a + l * stride, &v[l], sizeof(F4));
}
[[gnu::always_inline]] inline void store_rgba(const F8* c, float* a, std::size_t stride, std::size_t lanes) {
  // Within each 128-bit half as the four-lane transpose: u[l] holds vertex l, then vertex l + 4.
  const F8 t0 = __builtin_shufflevector(c[0], c[1], 0, 8, 1, 9, 4, 12, 5, 13);
  const F8 t1 = __builtin_shufflevector(c[0], c[1], 2, 10, 3, 11, 6, 14, 7, 15);
  const F8 t2 = __builtin_shufflevector(c[2], c[3], 0, 8, 1, 9, 4, 12, 5, 13);
  const F8 t3 = __builtin_shufflevector(c[2], c[3], 2, 10, 3, 11, 6, 14, 7, 15);
  const F8 u[4] = {__builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13),
                   __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15),
                   __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13),
                   __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15)};
  if (lanes == 8) {
    for (int l = 0; l < 4; ++l) {
      const F4 a0 = lo(u[l]), a1 = hi(u[l]);
      std::memcpy(a + l * stride, &a0, sizeof(F4)), std::memcpy(a + (l + 4) * stride, &a1, sizeof(F4));
    }
    return;
  }
  for (std::size_t l = 0; l < lanes; ++l) {
    const F4 v = l < 4 ? lo(u[l]) : hi(u[l - 4]);
    std::memcpy(a + l * stride, &v, sizeof(F4));
  }
}

[[gnu::always_inline]] inline void store_rgba(const X2<F8>* c, float* a, std::size_t stride, std::size_t lanes) {
  const F8 ca[4] = {c[0].a, c[1].a, c[2].a, c[3].a}, cb[4] = {c[0].b, c[1].b, c[2].b, c[3].b};
  store_rgba(ca, a, stride, std::min<std::size_t>(lanes, 8));
  if (lanes > 8) store_rgba(cb, a + 8 * stride, stride, lanes - 8);
}

// vertex_attrs' eye normal on all lanes (double, m = nmat column-major): nmat * n in Eigen's order for a
// Matrix3d times a Vector3d (rows 0 and 1 as (m0 n0 + m1 n1) + m2 n2, row 2 as m0 n0 + (m1 n1 +
// m2 n2)), divided by its norm sqrt((x x + y y) + z z) when normalising and the norm is positive.
template <class D>
[[gnu::always_inline]] inline void eye_normals(const double* m, D* n, bool normalize) {
  const D r0 = (m[0] * n[0] + m[3] * n[1]) + m[6] * n[2];
  const D r1 = (m[1] * n[0] + m[4] * n[1]) + m[7] * n[2];
  const D r2 = m[2] * n[0] + (m[5] * n[1] + m[8] * n[2]);
  n[0] = r0, n[1] = r1, n[2] = r2;
  if (normalize) {
    const D len = vsqrt((r0 * r0 + r1 * r1) + r2 * r2);
    for (int k = 0; k < 3; ++k) n[k] = sel(len > 0.0, n[k] / len, n[k]);
  }
}

// A chunk's needed vertices as light_needed reads them: indices into the chunk, the eye
// position rows (x, y, z, w), and the chunk's first vertex in the source.
struct NeededVerts {
  const std::uint32_t* need;
  std::size_t n;
  const double* eye[4];
  std::size_t v0;
};

// Lanes from memory, in registers (no stack array written by lanes and read back whole: that
// stalls on store forwarding). A row's elements i[0], i[1], ... into the lanes of D:
template <class D>
[[gnu::always_inline]] inline D gather(const double* r, const std::uint32_t* i) {
  if constexpr (sizeof(D) == sizeof(D2)) return D{r[i[0]], r[i[1]]};
  else return D{r[i[0]], r[i[1]], r[i[2]], r[i[3]]};
}
template <class D>
[[gnu::always_inline]] inline D load(const double* p) {
  D v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// Packed x y z triples: those at p + 3 i[0], p + 3 i[1], ... by lanes into v[0..2],
[[gnu::always_inline]] inline void gather_xyz(const double* p, const std::uint32_t* i, D2* v) {
  const D2 a = load<D2>(p + 3 * i[0]), b = load<D2>(p + 3 * i[1]);
  v[0] = __builtin_shufflevector(a, b, 0, 2), v[1] = __builtin_shufflevector(a, b, 1, 3);
  v[2] = D2{p[3 * i[0] + 2], p[3 * i[1] + 2]};
}
[[gnu::always_inline]] inline void gather_xyz(const double* p, const std::uint32_t* i, D4* v) {
  D2 lo[3], hi[3];
  gather_xyz(p, i, lo), gather_xyz(p, i + 2, hi);
  for (int k = 0; k < 3; ++k) v[k] = __builtin_shufflevector(lo[k], hi[k], 0, 1, 2, 3);
}
// and those of consecutive vertices from p on (3 lanes' worth of doubles read as three vectors;
// also the position stage's packed positions and the facing test's window rows).
[[gnu::always_inline]] inline void rows_xyz(const double* p, D2* v) {
  const D2 a = load<D2>(p), b = load<D2>(p + 2), c = load<D2>(p + 4);  // x0 y0, z0 x1, y1 z1
  v[0] = __builtin_shufflevector(a, b, 0, 3), v[1] = __builtin_shufflevector(a, c, 1, 2);
  v[2] = __builtin_shufflevector(b, c, 0, 3);
}
[[gnu::always_inline]] inline void rows_xyz(const double* p, D4* v) {
  // a = x0 y0 z0 x1, b = y1 z1 x2 y2, c = z2 x3 y3 z3
  const D4 a = load<D4>(p), b = load<D4>(p + 4), c = load<D4>(p + 8);
  const D4 x = __builtin_shufflevector(a, b, 0, 3, 6, 6), y = __builtin_shufflevector(a, b, 1, 4, 7, 7),
            z = __builtin_shufflevector(a, b, 2, 5, 5, 5);
  v[0] = __builtin_shufflevector(x, c, 0, 1, 2, 5), v[1] = __builtin_shufflevector(y, c, 0, 1, 2, 6);
  v[2] = __builtin_shufflevector(z, c, 0, 1, 4, 7);
}


// The lighting's inputs for needed vertices q .. q + lanes - 1 (lanes <= W), gathered by rows (SoA,
// in registers; a run of consecutive vertices is read straight from the eye rows, and, from packed
// client normals `nrm`, as three vectors per half), the eye position divided by w and the normal
// transformed and normalised in double on all lanes at once with vertex_attrs' operations
// (eye_normals). Unless `lean`, vertex_attrs' other attributes go to attrs.
template <class V, class Src>
[[gnu::always_inline]] inline void light_inputs(const Context::State& s, const Src& src, const Mat3& nmat,
                                                const double* m, const double* nrm, const NeededVerts& nv,
                                                std::size_t q, std::size_t lanes, bool lean, bool want_color,
                                                const AttrNeeds& needs, float* attrs, std::size_t astride, V* P,
                                                V* N, V* C) {
  constexpr int W = Lanes<V>::W, H = W / 2;
  typedef typename Lanes<V>::D D;
  const bool normalize = s.on(Cap::Normalize);
  const std::uint32_t* nd = nv.need + q;
  // The lanes' vertices (the last group's unused lanes repeat lane 0's: computed, not stored).
  std::uint32_t idx[W];
  for (int l = 0; l < W; ++l) idx[l] = nd[std::size_t(l) < lanes ? l : 0];
  const bool run = lanes == W && nd[W - 1] - nd[0] == W - 1;
  // (Doubles in two halves of H lanes, each a register wide.)
  D e[4][2], n[3][2];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
#pragma GCC unroll 4
    for (int h = 0; h < 2; ++h)
      e[k][h] = run ? load<D>(nv.eye[k] + nd[0] + h * H) : gather<D>(nv.eye[k], idx + h * H);
  alignas(32) float pc[4][W];
  if (nrm) {
#pragma GCC unroll 4
    for (int h = 0; h < 2; ++h) {
      D v[3];
      if (run) rows_xyz(nrm + 3 * (nd[0] + h * H), v);
      else gather_xyz(nrm, idx + h * H, v);
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) n[k][h] = v[k];
    }
    if (want_color)
      for (int l = 0; l < W; ++l) {
        const Vec4f c = src.color(nv.v0 + idx[l]);
        for (int k = 0; k < 4; ++k) pc[k][l] = c[k];
      }
  } else {
    alignas(32) double pn[3][W];
    for (std::size_t l = 0; l < lanes; ++l) {
      const std::size_t i = nd[l];
      if (lean) {
        const Vec3 nl = src.normal(nv.v0 + i);
        for (int k = 0; k < 3; ++k) pn[k][l] = nl[k];
        if (want_color) {
          const Vec4f c = src.color(nv.v0 + i);
          for (int k = 0; k < 4; ++k) pc[k][l] = c[k];
        }
      } else {
        // vertex_attrs: every other attribute, and the eye normal (transformed here already).
        auto&& v = src.vertex(nv.v0 + i);
        const Vec4 ev(nv.eye[0][i], nv.eye[1][i], nv.eye[2][i], nv.eye[3][i]);
        const Vec3 nl = vertex_attrs(s, v, ev, nmat, attrs + (q + l) * astride, needs);
        for (int k = 0; k < 3; ++k) pn[k][l] = nl[k];
        for (int k = 0; k < 4; ++k) pc[k][l] = v.color[k];
      }
    }
    for (std::size_t l = lanes; l < W; ++l) {  // the last group's unused lanes copy lane 0
      for (int k = 0; k < 3; ++k) pn[k][l] = pn[k][0];
      for (int k = 0; k < 4; ++k) pc[k][l] = pc[k][0];
    }
    for (int k = 0; k < 3; ++k)
      for (int h = 0; h < 2; ++h) n[k][h] = load<D>(pn[k] + h * H);
  }
  // As light_vertex: P = (eye / w) in double, then float (w = 1 in every lane, the usual affine
  // modelview: x / 1 = x exactly, the divisions are skipped).
  if (any(typename Lanes<V>::I((e[3][0] != 1.0) | (e[3][1] != 1.0))))
#pragma GCC unroll 4
    for (int k = 0; k < 3; ++k)
#pragma GCC unroll 4
      for (int h = 0; h < 2; ++h) e[k][h] = e[k][h] / e[3][h];
#pragma GCC unroll 4
  for (int k = 0; k < 3; ++k) P[k] = narrow(e[k]);
  if (lean)
#pragma GCC unroll 4
    for (int h = 0; h < 2; ++h) {
      D nh[3] = {n[0][h], n[1][h], n[2][h]};
      eye_normals(m, nh, normalize);
#pragma GCC unroll 4
      for (int k = 0; k < 3; ++k) n[k][h] = nh[k];
    }
#pragma GCC unroll 4
  for (int k = 0; k < 3; ++k) N[k] = narrow(n[k]);
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
    if (want_color) std::memcpy(&C[k], pc[k], sizeof(V));
    else C[k] = splat<V>(0);  // (not read)
}

// The lit colours (and, unless `lean`, vertex_attrs' other attributes) of the needed vertices,
// W = 4 or 16 (two groups of 8) at a time, into attrs (sets of `astride` floats): light_inputs,
// then the lighting.
template <class V, class Src>
[[gnu::always_inline]] inline void light_needed(const Context::State& s, const LightSetup& ls, const LightConsts<V>& lc,
                                                const Src& src, const Mat3& nmat, const NeededVerts& nv, bool lean,
                                                const AttrNeeds& needs, float* attrs, std::size_t astride) {
  constexpr int W = Lanes<V>::W;
  const bool two = s.two_side;
  const bool want_color = !lean || lc.side[0].cm || (two && lc.side[1].cm);
  double m[9];
  for (int k = 0; k < 9; ++k) m[k] = nmat(k % 3, k / 3);
  // The client's normals packed x y z, vertex by vertex from the chunk's first (no indices): read
  // there by vectors. Else null (normals come through src.normal).
  const double* nrm = nullptr;
  if constexpr (requires { src.indices, src.a.normals, src.first; })
    if (lean && !src.indices && src.a.normals) nrm = src.a.normals + (src.first + nv.v0) * 3;
  for (std::size_t q = 0; q < nv.n; q += W) {
    const std::size_t lanes = std::min<std::size_t>(W, nv.n - q);
    V P[3], N[3], C[4];
    if constexpr (IsX2<V>::value) {
      // Each group of eight on its own (in registers), then side by side.
      typedef decltype(V::a) T;
      constexpr std::size_t W1 = Lanes<T>::W;
      T p[2][3], n[2][3], c[2][4];
      light_inputs<T>(s, src, nmat, m, nrm, nv, q, std::min(lanes, W1), lean, want_color, needs, attrs, astride,
                      p[0], n[0], c[0]);
      if (lanes > W1)
        light_inputs<T>(s, src, nmat, m, nrm, nv, q + W1, lanes - W1, lean, want_color, needs, attrs, astride, p[1],
                        n[1], c[1]);
      else  // (the last group's second eight: copies, computed, not stored)
        for (int k = 0; k < 4; ++k) {
          if (k < 3) p[1][k] = p[0][k], n[1][k] = n[0][k];
          c[1][k] = c[0][k];
        }
      for (int k = 0; k < 3; ++k) P[k] = {p[0][k], p[1][k]}, N[k] = {n[0][k], n[1][k]};
      for (int k = 0; k < 4; ++k) C[k] = {c[0][k], c[1][k]};
    } else {
      light_inputs<V>(s, src, nmat, m, nrm, nv, q, lanes, lean, want_color, needs, attrs, astride, P, N, C);
    }
    V front[4], back[4];
    light_lanes(s, ls, lc, P, N, C, 0, front);
    float* const a = attrs + q * astride;
    store_rgba(front, a + kFront, astride, lanes);
    if (two) {
      const V nb[3] = {-N[0], -N[1], -N[2]};
      light_lanes(s, ls, lc, P, nb, C, 1, back);
    }
    if (astride > 4) store_rgba(two ? back : front, a + kBack, astride, lanes);
  }
}

template <class Src>
void light_needed_sse2(const Context::State& s, const LightSetup& ls, const LightConsts<F4>& lc, const Src& src,
                       const Mat3& nmat, const NeededVerts& nv, bool lean, const AttrNeeds& needs, float* attrs,
                       std::size_t astride) {
  light_needed<F4>(s, ls, lc, src, nmat, nv, lean, needs, attrs, astride);
}
#if defined(__x86_64__) && defined(__GNUC__)
template <class Src>
__attribute__((target("avx2"))) void light_needed_avx2(const Context::State& s, const LightSetup& ls,
                                                       const LightConsts<F16>& lc, const Src& src, const Mat3& nmat,
                                                       const NeededVerts& nv, bool lean, const AttrNeeds& needs,
                                                       float* attrs, std::size_t astride) {
  light_needed<F16>(s, ls, lc, src, nmat, nv, lean, needs, attrs, astride);
}
#endif

// A draw's lighting constants for the lanes of the build that lights it (made once per batch of
// the triangle path, not per chunk: the AVX2 set is about 10 KB of broadcasts).
struct DrawLights {
  std::unique_ptr<LightConsts<F4>> narrow;
  std::unique_ptr<LightConsts<F16>> wide;
  bool use_wide = false;
};


// m * p in Eigen's order (((c0 x + c1 y) + c2 z) + c3 w), inline.
[[gnu::always_inline]] inline Vec4 xform(const Mat4& m, const Vec4& p) {
  return m.col(0) * p.x() + m.col(1) * p.y() + m.col(2) * p.z() + m.col(3) * p.w();
}

PVert lerp(const PVert& a, const PVert& b, double t) {
  PVert r;
  r.clip = a.clip + t * (b.clip - a.clip);
  for (int k = 0; k < kAttrs; ++k) r.a[k] = float(a.a[k] + t * (b.a[k] - a.a[k]));
  return r;
}

struct Raster {
  Context::State& s;
  int width, height;
  std::uint8_t* color;
  float* depth;
  // Clip planes: 6 frustum planes then the enabled user planes (as eye-space planes).
  std::vector<Vec4> user_planes;
  int x0, y0, x1, y1;  // pixel bounds (framebuffer ∩ scissor), half open
  // The AVX2 builds (vertex stage, run setup, fragment loops) for this draw: the CPU has AVX2,
  // WEDGE_RENDER_SIMD is not "sse2" and simd_fallback is not set (one choice for all of them).
  bool avx2 = false;
  bool phong, lighting, texturing, fog, blend, depth_test, all_mask;
  Queue* sink = nullptr;  // when set, primitives are queued instead of drawn
  std::vector<PVert> poly_scratch, clip_scratch;
  std::vector<WinVert> win_scratch;

  LightSetup lights;

  Raster(Context::State& st, int w, int h, std::uint8_t* c, float* d)
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

  // Signed distance of a vertex to clip plane i (>= 0 inside).
  double plane_dist(const PVert& v, int i) const {
    const Vec4& c = v.clip;
    switch (i) {
      case 0: return c.w() + c.x();
      case 1: return c.w() - c.x();
      case 2: return c.w() + c.y();
      case 3: return c.w() - c.y();
      case 4: return c.w() + c.z();
      case 5: return c.w() - c.z();
      default: {
        const Vec4& p = user_planes[i - 6];
        return p[0] * v.a[kEye] + p[1] * v.a[kEye + 1] + p[2] * v.a[kEye + 2] + p[3] * v.a[kEye + 3];
      }
    }
  }
  int plane_count() const { return 6 + int(user_planes.size()); }

  // Sutherland-Hodgman in homogeneous coordinates, one plane at a time.
  void clip_polygon(std::vector<PVert>& poly) {
    std::vector<PVert>& out = clip_scratch;
    for (int p = 0; p < plane_count() && !poly.empty(); ++p) {
      bool all_in = true;
      for (auto& v : poly)
        if (plane_dist(v, p) < 0) all_in = false;
      if (all_in) continue;
      out.clear();
      const std::size_t n = poly.size();
      for (std::size_t i = 0; i < n; ++i) {
        const PVert& a = poly[i];
        const PVert& b = poly[(i + 1) % n];
        double da = plane_dist(a, p), db = plane_dist(b, p);
        if (da >= 0) out.push_back(a);
        if ((da >= 0) != (db >= 0)) {
          // Always interpolate from the inside vertex, so a shared edge clips identically.
          PVert v = da >= 0 ? lerp(a, b, da / (da - db)) : lerp(b, a, db / (db - da));
          // Leaving: the next edge runs along the plane (made by clipping). Entering: the rest
          // of the original edge a-b.
          v.edge = da >= 0 ? false : a.edge;
          out.push_back(v);
        }
      }
      poly.swap(out);
    }
  }

  WinVert to_window(const PVert& v) const { return to_window(v.clip, v.a); }
  WinVert to_window(const Vec4& clip, const float* a) const {
    double iw = 1.0 / clip.w();
    double nx = clip.x() * iw, ny = clip.y() * iw, nz = clip.z() * iw;
    WinVert w;
    w.x = s.vp_x + (nx + 1) * 0.5 * s.vp_w;
    w.y = s.vp_y + (ny + 1) * 0.5 * s.vp_h;
    w.z = s.depth_near + (nz + 1) * 0.5 * (s.depth_far - s.depth_near);
    w.inv_w = iw;
    w.a = a;
    return w;
  }

  static bool depth_pass(DepthFunc f, float z, float d) {
    switch (f) {
      case DepthFunc::Never: return false;
      case DepthFunc::Less: return z < d;
      case DepthFunc::Equal: return z == d;
      case DepthFunc::LessEqual: return z <= d;
      case DepthFunc::Greater: return z > d;
      case DepthFunc::NotEqual: return z != d;
      case DepthFunc::GreaterEqual: return z >= d;
      case DepthFunc::Always: return true;
    }
    return false;
  }

  static float factor(BlendFactor f, float src, float dst, float sa, float da) {
    switch (f) {
      case BlendFactor::Zero: return 0;
      case BlendFactor::One: return 1;
      case BlendFactor::SrcAlpha: return sa;
      case BlendFactor::OneMinusSrcAlpha: return 1 - sa;
      case BlendFactor::DstAlpha: return da;
      case BlendFactor::OneMinusDstAlpha: return 1 - da;
      case BlendFactor::SrcColor: return src;
      case BlendFactor::OneMinusSrcColor: return 1 - src;
      case BlendFactor::DstColor: return dst;
      case BlendFactor::OneMinusDstColor: return 1 - dst;
    }
    return 0;
  }

  // Depth test for a fragment; returns false if it fails. Writes depth when it passes.
  [[gnu::always_inline]] bool depth_stage(int x, int y, float z) {
    return depth_test ? depth_stage_t<true>(x, y, z) : true;
  }
  template <bool Depth>
  [[gnu::always_inline]] bool depth_stage_t(int x, int y, float z) {
    return depth_stage_t<Depth>(x, y, z, s.depth_func, s.depth_mask);
  }
  // The function and mask passed in (loop-invariant locals: colour stores may alias the state).
  template <bool Depth>
  [[gnu::always_inline]] bool depth_stage_t(int x, int y, float z, DepthFunc func, bool mask) {
    if constexpr (!Depth) return true;
    float& d = depth[std::size_t(y) * width + x];
    // Depth buffers hold fixed-point values in GL; quantise to 24 bits as Mesa's default.
    // Round to nearest even as nearbyint does, without a libm call: adding and removing 2^52
    // leaves no fraction bits for values in [0, 2^52).
    constexpr double kRound = 0x1p52;  // not folded: no -ffast-math (no reassociation)
    double zr = double(std::clamp(z, 0.0f, 1.0f)) * 16777215.0;
    zr = (zr + kRound) - kRound;
    // Times the reciprocal, not a division: the double result is within 2 ulps (2^-52
    // relative) of the quotient, while k / (2^24 - 1) lies at least about 2^-50 (relative) from
    // any float rounding boundary, so the float is the same (checked for all 2^24 values).
    constexpr double kInvMax = 1.0 / 16777215.0;
    float zq = float(zr * kInvMax);
    if (!depth_pass(func, zq, d)) return false;
    if (mask) d = zq;
    return true;
  }

  // Texture environment, fog, blending, colour write (depth already tested).
  [[gnu::always_inline]] void shade_fragment(int x, int y, Vec4f c, const float* tex, float lambda, float fogz) {
    const bool t = texturing && tex;
    if (t && fog) shade_fragment_t<true, true>(x, y, c, tex, lambda, fogz);
    else if (t) shade_fragment_t<true, false>(x, y, c, tex, lambda, fogz);
    else if (fog) shade_fragment_t<false, true>(x, y, c, tex, lambda, fogz);
    else shade_fragment_t<false, false>(x, y, c, tex, lambda, fogz);
  }
  // The same, specialised on texturing and fog (chosen once per primitive, not per fragment).
  template <bool Tex, bool Fog>
  [[gnu::always_inline]] void shade_fragment_t(int x, int y, Vec4f c, const float* tex, float lambda, float fogz) {
    if constexpr (Tex) {
      float q = tex[3] != 0 ? tex[3] : 1.0f;
      Vec4f t = s.texture->sample(tex[0] / q, tex[1] / q, lambda);
      const TexFormat fmt = s.texture->format;
      switch (s.env_mode) {
        case TexEnvMode::Modulate:
          c.head<3>() = c.head<3>().cwiseProduct(t.head<3>());
          if (fmt == TexFormat::RGBA) c.w() *= t.w();
          break;
        case TexEnvMode::Replace:
          c.head<3>() = t.head<3>();
          if (fmt == TexFormat::RGBA) c.w() = t.w();
          break;
        case TexEnvMode::Decal:
          if (fmt == TexFormat::RGBA) c.head<3>() = c.head<3>() * (1 - t.w()) + t.head<3>() * t.w();
          else if (fmt == TexFormat::RGB) c.head<3>() = t.head<3>();
          break;
        case TexEnvMode::Blend:
          for (int k = 0; k < 3; ++k) c[k] = c[k] * (1 - t[k]) + s.env_color[k] * t[k];
          if (fmt == TexFormat::RGBA) c.w() *= t.w();
          break;
      }
    }
    if constexpr (Fog) {
      float f = 1;
      switch (s.fog_mode) {
        case FogMode::Linear: f = s.fog_end == s.fog_start ? 1.0f : (s.fog_end - fogz) / (s.fog_end - s.fog_start); break;
        case FogMode::Exp: f = std::exp(-s.fog_density * fogz); break;
        case FogMode::Exp2: f = std::exp(-(s.fog_density * fogz) * (s.fog_density * fogz)); break;
      }
      f = std::clamp(f, 0.0f, 1.0f);
      c.head<3>() = f * c.head<3>() + (1 - f) * s.fog_color.head<3>();
    }
    write_color(x, y, clamp01(c));
  }

  // Blending and the colour mask, then the colour write of one fragment (c already clamped).
  [[gnu::always_inline]] void write_color(int x, int y, Vec4f c) {
    std::uint8_t* p = &color[(std::size_t(y) * width + x) * 4];
    if (blend) {
      Vec4f d(p[0] / 255.0f, p[1] / 255.0f, p[2] / 255.0f, p[3] / 255.0f);
      Vec4f r;
      for (int k = 0; k < 4; ++k)
        r[k] = c[k] * factor(s.blend_src, c[k], d[k], c.w(), d.w()) + d[k] * factor(s.blend_dst, c[k], d[k], c.w(), d.w());
      c = clamp01(r);
    }
    // c is clamped to [0, 1]: round to nearest without a library call.
    if (all_mask) {
#if defined(__SSE2__)
      // The same float multiply, add and truncation for the four channels at once (SSE2).
      const __m128 f = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(c.data()), _mm_set1_ps(255.0f)), _mm_set1_ps(0.5f));
      const __m128i i32 = _mm_cvttps_epi32(f);
      const __m128i i16 = _mm_packs_epi32(i32, i32);
      const int packed = _mm_cvtsi128_si32(_mm_packus_epi16(i16, i16));
      std::memcpy(p, &packed, 4);
#else
      for (int k = 0; k < 4; ++k) p[k] = std::uint8_t(c[k] * 255.0f + 0.5f);
#endif
    } else {
      for (int k = 0; k < 4; ++k)
        if (s.color_mask[k]) p[k] = std::uint8_t(c[k] * 255.0f + 0.5f);
    }
  }

  Vec4f phong_color(const float* a, int side) const {
    Vec4 eye(a[kEye], a[kEye + 1], a[kEye + 2], a[kEye + 3]);
    Vec3 n(a[kNormal], a[kNormal + 1], a[kNormal + 2]);
    double len = n.norm();
    if (len > 0) n /= len;
    Vec4f vc(a[kFront], a[kFront + 1], a[kFront + 2], a[kFront + 3]);
    return light_vertex(s, lights, eye, side ? Vec3(-n) : n, vc, side);
  }

  // --- triangles ---
  // The attributes whose colour a triangle is filled with: the provoking vertex's (flat, when
  // given), else v0's when the three vertices have the same colour (an unlit or uniformly lit
  // surface: no colour interpolation), else none (smooth).
  static const float* flat_colour(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
    if (flat) return flat;
    const int col = side ? kBack : kFront;
    if (std::memcmp(v0.a + col, v1.a + col, 4 * sizeof(float)) == 0 &&
        std::memcmp(v0.a + col, v2.a + col, 4 * sizeof(float)) == 0)
      return v0.a;
    return nullptr;
  }

  // The fragment loop is specialised on the state that changes its work per fragment (Phong,
  // smooth colour, texturing, fog, depth test), chosen once per triangle: no per-pixel branch
  // on those, the same arithmetic in every specialisation.
  void triangle(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
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
  void triangle_scalar(const WinVert& v0, const WinVert& v1in, const WinVert& v2in, int side, const float* flat) {
    constexpr double kSub = 256.0;
    const WinVert* v[3] = {&v0, &v1in, &v2in};
    std::int64_t X[3], Y[3];
    for (int i = 0; i < 3; ++i) X[i] = std::llround(v[i]->x * kSub), Y[i] = std::llround(v[i]->y * kSub);
    std::int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area == 0) return;
    if (area < 0) {
      std::swap(v[1], v[2]), std::swap(X[1], X[2]), std::swap(Y[1], Y[2]);
      area = -area;
    }
    // Pixels whose centre (p + 1/2) lies within the vertices' bounding box: a covered centre is
    // inside the closed triangle, so no other pixel can be drawn (ceil / floor by shifts).
    int bx0 = std::max<std::int64_t>(x0, (std::min({X[0], X[1], X[2]}) - 128 + 255) >> 8);
    int bx1 = std::min<std::int64_t>(x1 - 1, (std::max({X[0], X[1], X[2]}) - 128) >> 8);
    int by0 = std::max<std::int64_t>(y0, (std::min({Y[0], Y[1], Y[2]}) - 128 + 255) >> 8);
    int by1 = std::min<std::int64_t>(y1 - 1, (std::max({Y[0], Y[1], Y[2]}) - 128) >> 8);
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
            float rx2 = (ux - u0) * (ux - u0) + (vx - v0_) * (vx - v0_);
            float ry2 = (uy - u0) * (uy - u0) + (vy - v0_) * (vy - v0_);
            float rho2 = std::max(rx2, ry2);
            quad_lambda = rho2 > 0 ? 0.5f * fast_log2(rho2) : -100.0f;
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
  // --- the 2x2-quad fragment loop (SSE2) ---
  // Four fragments at once, a 2x2 quad at even (x, y) as GPUs (and llvmpipe) take them: lane 0
  // is (x, y), 1 (x + 1, y), 2 (x, y + 1), 3 (x + 1, y + 1) (window y up). Coverage by exact
  // 32-bit edge functions stepped per quad; depth by a plane in double; the perspective-divided
  // attributes (a/w and 1/w) by planes in float; texture level of detail from the differences
  // of the quad's (u, v) across its top row and left column.
  // The AVX2 build where the CPU has it (Phong excepted: its per-fragment lighting is scalar, the
  // AVX2 copy would only add compile time and code).
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  void triangle_isa(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
    if constexpr (!Phong)
      if (avx2) return triangle_t_avx2<Phong, Smooth, Tex, Fog, Depth>(v0, v1, v2, side, flat);
    triangle_t<Phong, Smooth, Tex, Fog, Depth>(v0, v1, v2, side, flat);
  }
  // Two builds of triangle_q: for the base x86-64 (SSE2: the 4-lane loop), and with AVX2 enabled,
  // chosen at run time (the same setup, then the 8-lane quad_loop8, or the SSE2 build for the
  // states quad_loop8 does not take). FMA is left off so that no multiply-add is contracted:
  // both builds give the same bits.
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  void triangle_t(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
    triangle_q<Phong, Smooth, Tex, Fog, Depth, false>(v0, v1, v2, side, flat);
  }
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  __attribute__((target("avx2"))) void triangle_t_avx2(const WinVert& v0, const WinVert& v1, const WinVert& v2,
                                                           int side, const float* flat) {
    triangle_q<Phong, Smooth, Tex, Fog, Depth, true>(v0, v1, v2, side, flat);
  }
  // One covered pixel of a small triangle in the common state (triangle_q's tiny path and
  // triangle_run): depth from its double plane, colour from the float planes pl (c, dx, dy of 1/w
  // and of r/w, g/w, b/w, a/w) at (X, Y) from the first quad's first pixel, or the flat colour.
  // The quad loops' operations per lane, in the same order (the same bits).
  template <bool Smooth, bool Depth>
  [[gnu::always_inline]] void tiny_pixel(int px, int py, float X, float Y, double zc, double zdx, double zdy,
                                         const float (*pl)[3], const float* flat_rgba, DepthFunc dfunc, bool dmask) {
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
    auto clamp01 = [&](float x) { return _mm_cvtss_f32(_mm_min_ss(_mm_max_ss(_mm_set_ss(x), zero), one)); };
    auto at = [&](int k) { return (pl[k][0] + Y * pl[k][2]) + X * pl[k][1]; };
    const std::size_t idx = std::size_t(py) * width + px;
    if constexpr (Depth) {
      const float zf = clamp01(float((zc + double(Y) * zdy) + double(X) * zdx));
      const double zr = (double(zf) * 16777215.0 + 0x1p52) - 0x1p52;
      const float zq = float(zr * (1.0 / 16777215.0));
      const float d = depth[idx];
      if (!depth_pass(dfunc, zq, d)) return;
      if (dmask) depth[idx] = zq;
    }
    float cr, cg, cb, ca;
    if constexpr (Smooth) {
      const float rw = 1.0f / at(0);
      cr = at(1) * rw, cg = at(2) * rw, cb = at(3) * rw, ca = at(4) * rw;
    } else {
      cr = flat_rgba[0], cg = flat_rgba[1], cb = flat_rgba[2], ca = flat_rgba[3];
    }
    auto q8 = [&](float x) { return std::uint32_t(int(clamp01(x) * 255.0f + 0.5f)); };
    const std::uint32_t pix = q8(cr) | q8(cg) << 8 | q8(cb) << 16 | q8(ca) << 24;
    std::memcpy(color + idx * 4, &pix, 4);
  }

  // A run of independent filled triangles (v: three window vertices each), drawn in order as
  // triangle() draws them one by one: in the common state (no Phong, texture or fog; no blending,
  // all channels written) the run is set up a few triangles at a time (run_setup), the small
  // covered ones are drawn here pixel by pixel, the others by triangle().
  struct RunTri {
    const WinVert* v;
    int side;
    const float* flat;
  };
  void triangle_run(const RunTri* tri, std::size_t n, RunSetup& rs) {
    if (phong || texturing || fog || blend || !all_mask) {
      for (std::size_t k = 0; k < n; ++k) triangle(tri[k].v[0], tri[k].v[1], tri[k].v[2], tri[k].side, tri[k].flat);
      return;
    }
    // Stretches of triangles that may be small (vertices within 5 pixels each way: no more than
    // 4 x 4 centres) go to small_run; larger ones straight to triangle(), in order.
    auto may_be_small = [](const RunTri& t) {
      const WinVert* v = t.v;
      return std::max({v[0].x, v[1].x, v[2].x}) - std::min({v[0].x, v[1].x, v[2].x}) < 5.0 &&
             std::max({v[0].y, v[1].y, v[2].y}) - std::min({v[0].y, v[1].y, v[2].y}) < 5.0;
    };
    for (std::size_t k = 0; k < n;) {
      std::size_t e = k;
      while (e < n && e - k < std::size_t(RunSetup::kMax) && may_be_small(tri[e])) ++e;
      if (e > k) {
        small_run(tri + k, int(e - k), rs);
        k = e;
      } else {
        triangle(tri[k].v[0], tri[k].v[1], tri[k].v[2], tri[k].side, tri[k].flat);
        ++k;
      }
    }
  }
  // Up to RunSetup::kMax triangles of triangle_run, set up together.
  void small_run(const RunTri* tri, int m, RunSetup& rs) {
    const int m4 = (m + 3) & ~3;
    for (int t = 0; t < m4; ++t) {
      const RunTri& rt = tri[std::min(t, m - 1)];  // (the padding lanes repeat the last)
      const int col = rt.side ? kBack : kFront;
      for (int i = 0; i < 3; ++i) {
        const WinVert& w = rt.v[i];
        rs.x[i][t] = w.x, rs.y[i][t] = w.y, rs.z[i][t] = float(w.z), rs.iw[i][t] = w.inv_w;
        for (int c = 0; c < 4; ++c) rs.col[i][c][t] = w.a[col + c];
      }
    }
#if defined(__x86_64__) && defined(__GNUC__)
    if (avx2) run_setup_avx2(rs, m4, x0, y0, x1, y1);
    else run_setup_default(rs, m4, x0, y0, x1, y1);
#else
    run_setup_default(rs, m4, x0, y0, x1, y1);
#endif
    const DepthFunc dfunc = s.depth_func;
    const bool dmask = s.depth_mask;
    // The framebuffer lines of the first and last covered centre of a triangle a few ahead are
    // fetched while this one is drawn (a mesh's triangles come in no screen order: they miss).
    constexpr int kAhead = 8;
    for (int t = -kAhead; t < m; ++t) {
      const int f = t + kAhead;
      if (f < m && rs.status[f] == RunSetup::kTiny) {
        const std::uint32_t mk = rs.mask[f];
        const int b0 = __builtin_ctz(mk), b1 = 31 - __builtin_clz(mk);
        const std::size_t i0 = std::size_t(rs.by0[f] + (b0 >> 2)) * width + std::size_t(rs.bx0[f] + (b0 & 3));
        const std::size_t i1 = std::size_t(rs.by0[f] + (b1 >> 2)) * width + std::size_t(rs.bx0[f] + (b1 & 3));
        __builtin_prefetch(depth + i0, 1), __builtin_prefetch(color + 4 * i0, 1);
        __builtin_prefetch(depth + i1, 1), __builtin_prefetch(color + 4 * i1, 1);
      }
      if (t < 0) continue;
      const RunTri& rt = tri[t];
      if (rs.status[t] == RunSetup::kNone) continue;
      if (rs.status[t] == RunSetup::kOther) {
        triangle(rt.v[0], rt.v[1], rt.v[2], rt.side, rt.flat);
        continue;
      }
      const int col = rt.side ? kBack : kFront;
      const float* flat = flat_colour(rt.v[0], rt.v[1], rt.v[2], rt.side, rt.flat);
      float pl[5][3];
      for (int k = 0; k < 5; ++k)
        for (int q = 0; q < 3; ++q) pl[k][q] = rs.pl[k][q][t];
      const int bx0 = rs.bx0[t], by0 = rs.by0[t], ox = rs.ox[t], oy = rs.oy[t];
      const double zc = rs.zc[t], zdx = rs.zdx[t], zdy = rs.zdy[t];
      for (std::uint32_t mk = rs.mask[t]; mk; mk &= mk - 1) {
        const int b = __builtin_ctz(mk), px = bx0 + (b & 3), py = by0 + (b >> 2);
        const float X = float(px - ox), Y = float(py - oy);
        if (flat) {
          if (depth_test) tiny_pixel<false, true>(px, py, X, Y, zc, zdx, zdy, pl, flat + col, dfunc, dmask);
          else tiny_pixel<false, false>(px, py, X, Y, zc, zdx, zdy, pl, flat + col, dfunc, dmask);
        } else {
          if (depth_test) tiny_pixel<true, true>(px, py, X, Y, zc, zdx, zdy, pl, nullptr, dfunc, dmask);
          else tiny_pixel<true, false>(px, py, X, Y, zc, zdx, zdy, pl, nullptr, dfunc, dmask);
        }
      }
    }
  }
  // --- two quads at once (AVX2) ---
  // The common states (no Phong, no blending, all channels written, linear fog or none) of the
  // quad loop, 8 lanes wide: the quad at x in lanes 0-3 and the one at x + 2 in lanes 4-7, each
  // in the 4-lane order above, with the same operations per lane in the same order (the same
  // bits as the 4-lane loop; tests/render/test_fragment_paths.cpp checks it).
  struct Quad8Setup {
    int ox, oy, bx0, bx1, by0, by1, col;
    std::int64_t c[3], A[3], B[3];
    QPlane pw, pc[4], pt[3], pf;
    bool tex_q, dmask;
    double zc, zdx, zdy;
    const Texture* texture;
    float tex_w, tex_h, fog_end, fog_range;
    TexEnvMode env;
    TexFormat fmt;
    const float* flat;
    DepthFunc dfunc;
  };
  // (Lambdas do not inherit the target: each one in quad_loop8 carries it.)
#define WEDGE_AVX2_LAMBDA __attribute__((target("avx2"), always_inline))
  template <bool Smooth, bool Tex, bool Fog, bool Depth>
  __attribute__((target("avx2"))) void quad_loop8(const Quad8Setup& q) {
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
          __m256 z = _mm256_set_m128(_mm256_cvtpd_ps(zb), _mm256_cvtpd_ps(za));
          z = _mm256_min_ps(_mm256_max_ps(z, zero), one);
          const __m256d k = _mm256_set1_pd(16777215.0), r = _mm256_set1_pd(0x1p52), inv = _mm256_set1_pd(1.0 / 16777215.0);
          __m256d a = _mm256_mul_pd(_mm256_cvtps_pd(_mm256_castps256_ps128(z)), k);
          __m256d b = _mm256_mul_pd(_mm256_cvtps_pd(_mm256_extractf128_ps(z, 1)), k);
          a = _mm256_sub_pd(_mm256_add_pd(a, r), r), b = _mm256_sub_pd(_mm256_add_pd(b, r), r);
          const __m256 zq = _mm256_set_m128(_mm256_cvtpd_ps(_mm256_mul_pd(b, inv)), _mm256_cvtpd_ps(_mm256_mul_pd(a, inv)));
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
          __m256 pass;
          switch (q.dfunc) {
            case DepthFunc::Never: pass = zero; break;
            case DepthFunc::Less: pass = _mm256_cmp_ps(zq, d, _CMP_LT_OQ); break;
            case DepthFunc::Equal: pass = _mm256_cmp_ps(zq, d, _CMP_EQ_OQ); break;
            case DepthFunc::LessEqual: pass = _mm256_cmp_ps(zq, d, _CMP_LE_OQ); break;
            case DepthFunc::Greater: pass = _mm256_cmp_ps(zq, d, _CMP_GT_OQ); break;
            case DepthFunc::NotEqual: pass = _mm256_cmp_ps(zq, d, _CMP_NEQ_UQ); break;
            case DepthFunc::GreaterEqual: pass = _mm256_cmp_ps(zq, d, _CMP_GE_OQ); break;
            default: pass = _mm256_castsi256_ps(_mm256_set1_epi32(-1)); break;
          }
          m &= _mm256_movemask_ps(pass);
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
            const float dux = Uh[3] - Uh[2], dvx = Vh[3] - Vh[2], duy = Uh[0] - Uh[2], dvy = Vh[0] - Vh[2];
            const float rho2 = std::max(dux * dux + dvx * dvx, duy * duy + dvy * dvy);
            float lambda = rho2 > 0 ? 0.5f * fast_log2(rho2) : -100.0f;
            if (!(lambda <= 1000.0f)) lambda = 1000.0f;
            if (mh != 15) {
              const int l0 = __builtin_ctz(unsigned(mh));
              for (int l = 0; l < 4; ++l)
                if (!(mh >> l & 1)) Sh[l] = Sh[l0], Th[l] = Th[l0];
            }
            q.texture->sample4(Sh, Th, lambda, texel + 16 * h);
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
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth, bool Avx2>
  [[gnu::always_inline]] void triangle_q(const WinVert& v0, const WinVert& v1in, const WinVert& v2in, int side,
                                         const float* flat) {
    constexpr double kSub = 256.0;
    const WinVert* v[3] = {&v0, &v1in, &v2in};
    std::int64_t X[3], Y[3];
    for (int i = 0; i < 3; ++i) X[i] = round_half_away(v[i]->x * kSub), Y[i] = round_half_away(v[i]->y * kSub);
    std::int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area == 0) return;
    if (area < 0) {
      std::swap(v[1], v[2]), std::swap(X[1], X[2]), std::swap(Y[1], Y[2]);
      area = -area;
    }
    // Pixels whose centre lies within the vertices' bounding box (as triangle_scalar).
    const int bx0 = int(std::max<std::int64_t>(x0, (std::min({X[0], X[1], X[2]}) - 128 + 255) >> 8));
    const int bx1 = int(std::min<std::int64_t>(x1 - 1, (std::max({X[0], X[1], X[2]}) - 128) >> 8));
    const int by0 = int(std::max<std::int64_t>(y0, (std::min({Y[0], Y[1], Y[2]}) - 128 + 255) >> 8));
    const int by1 = int(std::min<std::int64_t>(y1 - 1, (std::max({Y[0], Y[1], Y[2]}) - 128) >> 8));
    if (bx0 > bx1 || by0 > by1) return;
    const int ox = bx0 & ~1, oy = by0 & ~1;  // the first quad
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
    Quad8Setup qs;  // the setup, as the AVX2 two-quad loop takes it
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
      const std::int64_t w = bx1 + 3 - ox, h = by1 + 3 - oy;
      if (std::abs(c[i]) + std::abs(A[i]) * w + std::abs(B[i]) * h > (std::int64_t(1) << 30)) fits = false;
    }
    if (!fits) return triangle_scalar<Phong, Smooth, Tex, Fog, Depth>(v0, v1in, v2in, side, flat);
    // Tiny triangles (most of a dense mesh's, a pixel or two each): try the few pixel centres of
    // the bounding box first, by the loops' own integer test, and skip the plane setup when none
    // is covered (many cover no centre at all).
    // The covered centres are kept (cov_x, cov_y): the per-pixel path below draws them.
    const bool tiny = bx1 - bx0 < 4 && by1 - by0 < 4;
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
      return QPlane{_mm_shuffle_ps(cdf, cdf, 0), _mm_shuffle_ps(cdf, cdf, 0x55),
                    _mm_set1_ps(float(gly[0] * f0 + gly[1] * f1 + gly[2] * f2))};
    };
    // a/w for attribute k (divided by the 1/w plane per fragment: perspective-correct).
    auto persp = [&](int k) {
      return plane(double(v[0]->a[k]) * v[0]->inv_w, double(v[1]->a[k]) * v[1]->inv_w, double(v[2]->a[k]) * v[2]->inv_w);
    };
    const QPlane pw = qs.pw = plane(v[0]->inv_w, v[1]->inv_w, v[2]->inv_w);
    const int col = side ? kBack : kFront;
    const QPlane none{_mm_setzero_ps(), _mm_setzero_ps(), _mm_setzero_ps()};
    QPlane* const pc = qs.pc;
    QPlane* const pt = qs.pt;
    QPlane& pf = qs.pf;
    for (int k = 0; k < 4; ++k) pc[k] = none;
    for (int k = 0; k < 3; ++k) pt[k] = none;
    pf = none;
    QPlane pa[Phong ? kAttrs : 1];
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
      for (int k = 0; k < kAttrs; ++k) pa[k] = persp(k);
    double zc = 0, zdx = 0, zdy = 0;
    if constexpr (Depth) {
      for (int i = 0; i < 3; ++i) {
        const double zi = float(v[i]->z);
        zc += l0[i] * zi, zdx += glx[i] * zi, zdy += gly[i] * zi;
      }
    }
    const Texture* texture = Tex ? s.texture.get() : nullptr;
    const float tex_w = Tex ? float(texture->levels[0].width) : 0;
    const float tex_h = Tex ? float(texture->levels[0].height) : 0;
    const TexEnvMode env = s.env_mode;
    const TexFormat fmt = Tex ? texture->format : TexFormat::RGBA;
    const FogMode fog_mode = s.fog_mode;
    const float fog_end = s.fog_end, fog_range = s.fog_end - s.fog_start, fog_density = s.fog_density;
    const __m128 fog_r = _mm_set1_ps(s.fog_color[0]), fog_g = _mm_set1_ps(s.fog_color[1]),
                 fog_b = _mm_set1_ps(s.fog_color[2]);
    const __m128 env_r = _mm_set1_ps(s.env_color[0]), env_g = _mm_set1_ps(s.env_color[1]),
                 env_b = _mm_set1_ps(s.env_color[2]);
    const DepthFunc dfunc = s.depth_func;
    const bool dmask = s.depth_mask;
    const bool fast_write = !blend && all_mask;
    if constexpr (!Phong && !Tex && !Fog) {
      // Tiny triangles in the common state: the covered pixels one by one, with the quad loops'
      // operations per lane in the same order (the same bits), without their setup and blocks.
      if (tiny && fast_write) {
        float pl[5][3];
        const QPlane* src[5] = {&pw, &pc[0], &pc[1], &pc[2], &pc[3]};
        for (int k = 0; k < 5; ++k)
          pl[k][0] = _mm_cvtss_f32(src[k]->c), pl[k][1] = _mm_cvtss_f32(src[k]->dx), pl[k][2] = _mm_cvtss_f32(src[k]->dy);
        for (int n = 0; n < cov_n; ++n)
          tiny_pixel<Smooth, Depth>(ox + cov_x[n], oy + cov_y[n], float(cov_x[n]), float(cov_y[n]), zc, zdx, zdy, pl,
                                    Smooth ? nullptr : flat + col, dfunc, dmask);
        return;
      }
    }
    if constexpr (Avx2) {
      static_assert(!Phong, "the AVX2 build takes no Phong triangles (triangle_isa)");
      // The states the two-quad loop takes; the rare others go to the SSE2 build of the 4-lane
      // loop (no AVX2 copy of it: less code and compile time, the same bits).
      if (!(fast_write && (!Fog || fog_mode == FogMode::Linear)))
        return triangle_t<Phong, Smooth, Tex, Fog, Depth>(v0, v1in, v2in, side, flat);
      Quad8Setup& q = qs;
      q.ox = ox, q.oy = oy, q.bx0 = bx0, q.bx1 = bx1, q.by0 = by0, q.by1 = by1, q.col = col;
      q.tex_q = tex_q, q.dmask = dmask, q.zc = zc, q.zdx = zdx, q.zdy = zdy;
      q.texture = texture, q.tex_w = tex_w, q.tex_h = tex_h, q.fog_end = fog_end, q.fog_range = fog_range;
      q.env = env, q.fmt = fmt, q.flat = flat, q.dfunc = dfunc;
      return quad_loop8<Smooth, Tex, Fog, Depth>(q);
    } else {
      const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
      const __m128 lane_dx = _mm_set_ps(1, 0, 1, 0), lane_dy = _mm_set_ps(1, 1, 0, 0);
      __m128i estep[3], erow[3], estepy[3];
      for (int i = 0; i < 3; ++i) {
        estep[i] = _mm_set1_epi32(int(2 * A[i]));
        estepy[i] = _mm_set1_epi32(int(2 * B[i]));
        erow[i] = _mm_add_epi32(_mm_set1_epi32(int(c[i])), _mm_set_epi32(int(A[i] + B[i]), int(B[i]), int(A[i]), 0));
      }
      // A plane's row part c + y dy for the quad row, then + x dx per quad.
      auto row = [](const QPlane& p, __m128 Y4) { return _mm_add_ps(p.c, _mm_mul_ps(Y4, p.dy)); };
      auto at = [](__m128 r, const QPlane& p, __m128 X4) { return _mm_add_ps(r, _mm_mul_ps(X4, p.dx)); };
      __m128 c_row[4] = {zero, zero, zero, zero}, t_row[3] = {zero, zero, zero}, f_row = zero;

      for (int qy = oy; qy <= by1; qy += 2) {
        int rowm = 15;
        if (qy < by0) rowm &= ~3;
        if (qy + 1 > by1) rowm &= ~12;
        __m128i e[3] = {erow[0], erow[1], erow[2]};
        for (int i = 0; i < 3; ++i) erow[i] = _mm_add_epi32(erow[i], estepy[i]);
        const float fy = float(qy - oy);
        const __m128 Y4 = _mm_add_ps(_mm_set1_ps(fy), lane_dy);
        const __m128 rw_row = row(pw, Y4);
        if constexpr (Smooth && !Phong)
          for (int k = 0; k < 4; ++k) c_row[k] = row(pc[k], Y4);
        if constexpr (Tex) {
          t_row[0] = row(pt[0], Y4), t_row[1] = row(pt[1], Y4);
          if (tex_q) t_row[2] = row(pt[2], Y4);
        }
        if constexpr (Fog) f_row = row(pf, Y4);
        const double zrow_lo = zc + double(fy) * zdy, zrow_hi = zc + double(fy + 1) * zdy;
        for (int qx = ox; qx <= bx1;
             qx += 2, e[0] = _mm_add_epi32(e[0], estep[0]), e[1] = _mm_add_epi32(e[1], estep[1]),
                 e[2] = _mm_add_epi32(e[2], estep[2])) {
          // A lane is covered when no edge function is negative (sign bits).
          const __m128i out = _mm_or_si128(_mm_or_si128(e[0], e[1]), e[2]);
          int m = ~_mm_movemask_ps(_mm_castsi128_ps(out)) & rowm;
          if (qx < bx0) m &= ~5;
          if (qx + 1 > bx1) m &= ~10;
          if (!m) continue;
          // Partial quads at the edge of the drawable bounds are read and written lane by lane.
          auto inb = [&] { return qx >= x0 && qx + 1 < x1 && qy >= y0 && qy + 1 < y1; };
          const std::size_t i0 = std::size_t(qy) * width + qx, i1 = i0 + width;
          auto index = [&](int l) { return (l & 2 ? i1 : i0) + (l & 1); };
          const float fx = float(qx - ox);
          const __m128 X4 = _mm_add_ps(_mm_set1_ps(fx), lane_dx);
          if constexpr (Depth) {
            const __m128d xs = _mm_mul_pd(_mm_add_pd(_mm_set1_pd(fx), _mm_set_pd(1, 0)), _mm_set1_pd(zdx));
            const __m128 zq = quantise_depth4(_mm_add_pd(_mm_set1_pd(zrow_lo), xs), _mm_add_pd(_mm_set1_pd(zrow_hi), xs));
            __m128 d;
            if (m == 15 || inb()) {
              d = _mm_movelh_ps(_mm_loadl_pi(zero, reinterpret_cast<const __m64*>(depth + i0)),
                                _mm_loadl_pi(zero, reinterpret_cast<const __m64*>(depth + i1)));
            } else {
              alignas(16) float t[4] = {0, 0, 0, 0};
              for (int l = 0; l < 4; ++l)
                if (m >> l & 1) t[l] = depth[index(l)];
              d = _mm_load_ps(t);
            }
            m &= depth_cmp4(dfunc, zq, d);
            if (!m) continue;
            if (dmask) {
              if (m == 15 || inb()) {
                const __m128 nd = sel(lane_mask(m), zq, d);
                _mm_storel_pi(reinterpret_cast<__m64*>(depth + i0), nd);
                _mm_storeh_pi(reinterpret_cast<__m64*>(depth + i1), nd);
              } else {
                alignas(16) float t[4];
                _mm_store_ps(t, zq);
                for (int l = 0; l < 4; ++l)
                  if (m >> l & 1) depth[index(l)] = t[l];
              }
            }
          }
          const __m128 rw = _mm_div_ps(one, at(rw_row, pw, X4));
          __m128 cr, cg, cb, ca;
          if constexpr (Phong) {
            alignas(16) float pc4[4][4] = {};
            alignas(16) float rw4[4];
            _mm_store_ps(rw4, rw);
            for (int l = 0; l < 4; ++l) {
              if (!(m >> l & 1)) continue;
              const float lx = fx + float(l & 1), ly = fy + float(l >> 1);
              float attrs[kAttrs];
              for (int k = 0; k < kAttrs; ++k)
                attrs[k] = (_mm_cvtss_f32(pa[k].c) + ly * _mm_cvtss_f32(pa[k].dy) + lx * _mm_cvtss_f32(pa[k].dx)) * rw4[l];
              if constexpr (!Smooth)
                for (int k = 0; k < 4; ++k) attrs[kFront + k] = flat[kFront + k];
              const Vec4f pcol = phong_color(attrs, side);
              for (int k = 0; k < 4; ++k) pc4[k][l] = pcol[k];
            }
            cr = _mm_load_ps(pc4[0]), cg = _mm_load_ps(pc4[1]), cb = _mm_load_ps(pc4[2]), ca = _mm_load_ps(pc4[3]);
          } else if constexpr (Smooth) {
            cr = _mm_mul_ps(at(c_row[0], pc[0], X4), rw), cg = _mm_mul_ps(at(c_row[1], pc[1], X4), rw);
            cb = _mm_mul_ps(at(c_row[2], pc[2], X4), rw), ca = _mm_mul_ps(at(c_row[3], pc[3], X4), rw);
          } else {
            cr = _mm_set1_ps(flat[col]), cg = _mm_set1_ps(flat[col + 1]);
            cb = _mm_set1_ps(flat[col + 2]), ca = _mm_set1_ps(flat[col + 3]);
          }
          if constexpr (Tex) {
            __m128 ts = _mm_mul_ps(at(t_row[0], pt[0], X4), rw), tt = _mm_mul_ps(at(t_row[1], pt[1], X4), rw);
            if (tex_q) {
              __m128 tq = _mm_mul_ps(at(t_row[2], pt[2], X4), rw);
              tq = sel(_mm_cmpneq_ps(tq, zero), tq, one);
              ts = _mm_div_ps(ts, tq), tt = _mm_div_ps(tt, tq);
            }
            // Level of detail from the quad's (u, v) = (s W, t H): x differences along its upper
            // row, y differences down its left column (reference: the top-left pixel).
            alignas(16) float S[4], T[4], U[4], V[4];
            _mm_store_ps(U, _mm_mul_ps(ts, _mm_set1_ps(tex_w)));
            _mm_store_ps(V, _mm_mul_ps(tt, _mm_set1_ps(tex_h)));
            const float dux = U[3] - U[2], dvx = V[3] - V[2], duy = U[0] - U[2], dvy = V[0] - V[2];
            const float rho2 = std::max(dux * dux + dvx * dvx, duy * duy + dvy * dvy);
            float lambda = rho2 > 0 ? 0.5f * fast_log2(rho2) : -100.0f;
            if (!(lambda <= 1000.0f)) lambda = 1000.0f;  // extrapolated helper lanes gone astray (inf, NaN)
            _mm_store_ps(S, ts), _mm_store_ps(T, tt);
            if (m != 15) {
              // Lanes outside the triangle may hold extrapolated coordinates (even infinite):
              // sample a covered lane's instead.
              const int l0 = __builtin_ctz(unsigned(m));
              for (int l = 0; l < 4; ++l)
                if (!(m >> l & 1)) S[l] = S[l0], T[l] = T[l0];
            }
            alignas(16) float texel[16];
            texture->sample4(S, T, lambda, texel);
            __m128 tr = _mm_load_ps(texel), tg = _mm_load_ps(texel + 4), tb = _mm_load_ps(texel + 8),
                   ta = _mm_load_ps(texel + 12);
            _MM_TRANSPOSE4_PS(tr, tg, tb, ta);
            const __m128 t[4] = {tr, tg, tb, ta}, env_c[3] = {env_r, env_g, env_b};
            __m128 c[4] = {cr, cg, cb, ca};
            tex_env(env, fmt, t, env_c, one, c);
            cr = c[0], cg = c[1], cb = c[2], ca = c[3];
          }
          if constexpr (Fog) {
            const __m128 fz = _mm_mul_ps(at(f_row, pf, X4), rw);
            __m128 f = one;
            if (fog_mode == FogMode::Linear) {
              if (fog_range != 0) f = _mm_div_ps(_mm_sub_ps(_mm_set1_ps(fog_end), fz), _mm_set1_ps(fog_range));
            } else {
              alignas(16) float z4[4], f4[4];
              _mm_store_ps(z4, fz);
              for (int l = 0; l < 4; ++l) {
                const float dz = fog_density * z4[l];
                f4[l] = std::exp(fog_mode == FogMode::Exp ? -dz : -dz * dz);
              }
              f = _mm_load_ps(f4);
            }
            f = _mm_min_ps(_mm_max_ps(f, zero), one);
            const __m128 g = _mm_sub_ps(one, f);
            cr = _mm_add_ps(_mm_mul_ps(f, cr), _mm_mul_ps(g, fog_r));
            cg = _mm_add_ps(_mm_mul_ps(f, cg), _mm_mul_ps(g, fog_g));
            cb = _mm_add_ps(_mm_mul_ps(f, cb), _mm_mul_ps(g, fog_b));
          }
          cr = _mm_min_ps(_mm_max_ps(cr, zero), one), cg = _mm_min_ps(_mm_max_ps(cg, zero), one);
          cb = _mm_min_ps(_mm_max_ps(cb, zero), one), ca = _mm_min_ps(_mm_max_ps(ca, zero), one);
          if (fast_write) {
            // The colour write's rounding (c 255 + 1/2, truncated) for the four lanes, packed RGBA8.
            const __m128 k255 = _mm_set1_ps(255.0f), half = _mm_set1_ps(0.5f);
            auto q8 = [&](__m128 x) { return _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(x, k255), half)); };
            const __m128i px = _mm_or_si128(_mm_or_si128(q8(cr), _mm_slli_epi32(q8(cg), 8)),
                                            _mm_or_si128(_mm_slli_epi32(q8(cb), 16), _mm_slli_epi32(q8(ca), 24)));
            std::uint8_t* p0 = color + i0 * 4;
            std::uint8_t* p1 = color + i1 * 4;
            if (m == 15) {
              _mm_storel_epi64(reinterpret_cast<__m128i*>(p0), px);
              _mm_storel_epi64(reinterpret_cast<__m128i*>(p1), _mm_srli_si128(px, 8));
            } else if (inb()) {
              const __m128i old = _mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p0)),
                                                     _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p1)));
              const __m128i mk = _mm_castps_si128(lane_mask(m));
              const __m128i nw = _mm_or_si128(_mm_and_si128(mk, px), _mm_andnot_si128(mk, old));
              _mm_storel_epi64(reinterpret_cast<__m128i*>(p0), nw);
              _mm_storel_epi64(reinterpret_cast<__m128i*>(p1), _mm_srli_si128(nw, 8));
            } else {
              alignas(16) std::uint32_t P[4];
              _mm_store_si128(reinterpret_cast<__m128i*>(P), px);
              for (int l = 0; l < 4; ++l)
                if (m >> l & 1) std::memcpy(color + index(l) * 4, &P[l], 4);
            }
          } else {
            alignas(16) float C[4][4];
            _mm_store_ps(C[0], cr), _mm_store_ps(C[1], cg), _mm_store_ps(C[2], cb), _mm_store_ps(C[3], ca);
            for (int l = 0; l < 4; ++l)
              if (m >> l & 1) write_color(qx + (l & 1), qy + (l >> 1), Vec4f(C[0][l], C[1][l], C[2][l], C[3][l]));
          }
        }
      }
    }
  }
#else
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  void triangle_t(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
    triangle_scalar<Phong, Smooth, Tex, Fog, Depth>(v0, v1, v2, side, flat);
  }
  struct RunTri {
    const WinVert* v;
    int side;
    const float* flat;
  };
  void triangle_run(const RunTri* tri, std::size_t n, RunSetup&) {
    for (std::size_t k = 0; k < n; ++k) triangle(tri[k].v[0], tri[k].v[1], tri[k].v[2], tri[k].side, tri[k].flat);
  }
#endif

  // --- lines: a DDA that samples the line at the pixel centres of its major axis ---
  void line(const WinVert& a_in, const WinVert& b_in, int side, const float* flat) {
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

  void point(const WinVert& p_in, int side) {
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

  // --- queueing for banded rasterisation ---
  // The general path's attributes may live in scratch vectors: the job points at copies.
  void copy_vert(WinVert& d, const WinVert& w) {
    d = w;
    d.a = sink->store.add(w.a);
  }
  Job& new_job(Job::Kind k, int side, const float* flat) {
    Job& j = sink->jobs.emplace_back();
    j.kind = k;
    j.side = std::uint8_t(side);
    j.flat = flat ? sink->store.add(flat) : nullptr;
    return j;
  }
  void emit_triangle(const WinVert& a, const WinVert& b, const WinVert& c, int side, const float* flat) {
    if (!sink) return triangle(a, b, c, side, flat);
    Job& j = new_job(Job::Tri, side, flat);
    copy_vert(j.v[0], a), copy_vert(j.v[1], b), copy_vert(j.v[2], c);
    j.row0 = int(std::floor(std::min({a.y, b.y, c.y}))) - 1;
    j.row1 = int(std::floor(std::max({a.y, b.y, c.y}))) + 1;
  }
  // A triangle whose attribute sets outlive the queue (the triangle path's chunk buffers): the
  // job points at them, no copies.
  void emit_triangle_direct(const WinVert& a, const WinVert& b, const WinVert& c, int side, const float* flat) {
    if (!sink) return triangle(a, b, c, side, flat);
    Job& j = sink->jobs.emplace_back();
    j.kind = Job::Tri;
    j.side = std::uint8_t(side);
    j.flat = flat;
    j.v[0] = a, j.v[1] = b, j.v[2] = c;
    j.row0 = int(std::floor(std::min({a.y, b.y, c.y}))) - 1;
    j.row1 = int(std::floor(std::max({a.y, b.y, c.y}))) + 1;
  }
  void emit_line(const WinVert& a, const WinVert& b, int side, const float* flat) {
    if (!sink) return line(a, b, side, flat);
    Job& j = new_job(Job::Line, side, flat);
    copy_vert(j.v[0], a), copy_vert(j.v[1], b);
    const int pad = int(std::ceil(s.line_width)) + 1;
    j.row0 = int(std::floor(std::min(a.y, b.y))) - pad;
    j.row1 = int(std::floor(std::max(a.y, b.y))) + pad;
  }
  void emit_point(const WinVert& p, int side) {
    if (!sink) return point(p, side);
    Job& j = new_job(Job::Point, side, nullptr);
    copy_vert(j.v[0], p);
    const int pad = int(std::ceil(s.point_size)) + 1;
    j.row0 = int(std::floor(p.y)) - pad;
    j.row1 = int(std::floor(p.y)) + pad;
  }
  void exec(const Job& j) {
    if (j.kind == Job::Tri) triangle(j.v[0], j.v[1], j.v[2], j.side, j.flat);
    else if (j.kind == Job::Line) line(j.v[0], j.v[1], j.side, j.flat);
    else point(j.v[0], j.side);
  }

  // --- primitive-level drivers (after assembly) ---
  void draw_point(const PVert& v) {
    for (int p = 0; p < plane_count(); ++p)
      if (plane_dist(v, p) < 0) return;
    emit_point(to_window(v), 0);
  }

  void draw_line(const PVert& a0, const PVert& b0, const PVert& provoking) {
    // Parametric clipping in homogeneous space (Liang-Barsky's idea applied to the clip volume).
    double t0 = 0, t1 = 1;
    for (int p = 0; p < plane_count(); ++p) {
      double da = plane_dist(a0, p), db = plane_dist(b0, p);
      if (da < 0 && db < 0) return;
      if (da < 0) t0 = std::max(t0, da / (da - db));
      else if (db < 0) t1 = std::min(t1, da / (da - db));
    }
    if (t0 > t1) return;
    PVert a = t0 > 0 ? lerp(a0, b0, t0) : a0;
    PVert b = t1 < 1 ? lerp(a0, b0, t1) : b0;
    const bool flat = s.shade == ShadeModel::Flat;
    emit_line(to_window(a), to_window(b), 0, flat ? provoking.a : nullptr);
  }

  // A filled triangle wholly inside the clip volume, in window coordinates: facing, culling,
  // then the fill (polygon modes both Fill).
  void draw_inside_triangle(const WinVert* w, const PVert& provoking) {
    double area = 0;
    for (int i = 0; i < 3; ++i) area += w[i].x * w[(i + 1) % 3].y - w[(i + 1) % 3].x * w[i].y;
    const bool front = (area > 0) == (s.front_face == FrontFace::CCW);
    if (s.on(Cap::CullFace)) {
      if (s.cull_face == Face::FrontAndBack) return;
      if ((s.cull_face == Face::Front) == front) return;
    }
    const int side = (!front && two_sided_lighting(s)) ? 1 : 0;
    emit_triangle(w[0], w[1], w[2], side, s.shade == ShadeModel::Flat ? provoking.a : nullptr);
  }

  // A polygon with its provoking vertex (for flat shading): clip, find its facing, cull, then
  // fill it as a triangle fan or draw its outline or vertices per the polygon mode.
  void draw_triangle(const PVert& a, const PVert& b, const PVert& c, const PVert& provoking) {
    // Fast path: a filled triangle wholly inside the clip volume needs no polygon copies (the
    // same window coordinates, area and cull decisions as the general path below).
    if (s.poly_front == PolygonMode::Fill && s.poly_back == PolygonMode::Fill) {
      bool inside = true;
      for (int p = 0; p < plane_count() && inside; ++p)
        if (plane_dist(a, p) < 0 || plane_dist(b, p) < 0 || plane_dist(c, p) < 0) inside = false;
      if (inside) {
        const WinVert w[3] = {to_window(a), to_window(b), to_window(c)};
        return draw_inside_triangle(w, provoking);
      }
    }
    std::vector<PVert>& poly = poly_scratch;
    poly.clear();
    poly.push_back(a), poly.push_back(b), poly.push_back(c);
    const PVert& prov = provoking;
    clip_polygon(poly);
    if (poly.size() < 3) return;
    std::vector<WinVert>& w = win_scratch;
    w.resize(poly.size());
    for (std::size_t i = 0; i < poly.size(); ++i) w[i] = to_window(poly[i]);
    double area = 0;
    for (std::size_t i = 0, n = w.size(); i < n; ++i) {
      const WinVert& a = w[i];
      const WinVert& b = w[(i + 1) % n];
      area += a.x * b.y - b.x * a.y;
    }
    bool front = (area > 0) == (s.front_face == FrontFace::CCW);
    if (s.on(Cap::CullFace)) {
      if (s.cull_face == Face::FrontAndBack) return;
      if ((s.cull_face == Face::Front) == front) return;
    }
    const int side = (!front && two_sided_lighting(s)) ? 1 : 0;
    const bool flat = s.shade == ShadeModel::Flat;
    const float* flat_attrs = flat ? prov.a : nullptr;
    PolygonMode mode = front ? s.poly_front : s.poly_back;
    if (mode == PolygonMode::Fill) {
      for (std::size_t i = 1; i + 1 < w.size(); ++i) emit_triangle(w[0], w[i], w[i + 1], side, flat_attrs);
    } else if (mode == PolygonMode::Line) {
      for (std::size_t i = 0, n = w.size(); i < n; ++i)
        if (poly[i].edge) emit_line(w[i], w[(i + 1) % n], side, flat_attrs);
    } else {
      // As Mesa's unfilled stage: a vertex is drawn when the edge leaving it is an original one.
      for (std::size_t i = 0; i < w.size(); ++i)
        if (poly[i].edge) emit_point(w[i], side);
    }
  }
};

// One arena per calling thread and thread count, kept between batches: constructing an arena
// for each stage of each batch (a 1M-triangle draw has hundreds of batches) cost more than
// the second thread gained.
tbb::task_arena& arena_for(int threads) {
  static thread_local std::unique_ptr<tbb::task_arena> arena;
  static thread_local int arena_threads = 0;
  if (!arena || arena_threads != threads) {
    arena = std::make_unique<tbb::task_arena>(threads);
    arena_threads = threads;
  }
  return *arena;
}

// Draws queued primitives by bands of rows in parallel: each band owns its pixels and draws its
// primitives queue by queue, each in submission order (queues already binned).
void draw_bands(const Raster& r, Queue* const* queues, std::size_t nq) {
  const int bands = (r.height + kBandRows - 1) / kBandRows;
  tbb::task_arena& arena = arena_for(r.s.threads);
  arena.execute([&] {
    tbb::parallel_for(0, bands, [&](int b) {
      bool any = false;
      for (std::size_t q = 0; q < nq && !any; ++q) any = queues[q]->band_start[b + 1] > queues[q]->band_start[b];
      if (!any) return;
      Raster band = r;
      band.sink = nullptr;
      band.y0 = std::max(r.y0, b * kBandRows);
      band.y1 = std::min(r.y1, (b + 1) * kBandRows);
      // Consecutive triangles by runs (Raster::triangle_run), lines and points one by one.
      Raster::RunTri run[kRunMax];
      std::size_t n = 0;
      RunSetup& rs = run_scratch();
      for (std::size_t q = 0; q < nq; ++q) {
        const Queue& qu = *queues[q];
        for (std::uint32_t k = qu.band_start[b]; k < qu.band_start[b + 1]; ++k) {
          const Job& j = qu.jobs[qu.band_jobs[k]];
          if (j.kind == Job::Tri) {
            run[n++] = Raster::RunTri{j.v, j.side, j.flat};
            if (n < kRunMax) continue;
          }
          band.triangle_run(run, n, rs);
          n = 0;
          if (j.kind != Job::Tri) band.exec(j);
        }
      }
      band.triangle_run(run, n, rs);
    });
  });
}

// --- independent filled triangles ---
// GL_TRIANGLES with both polygon modes Fill and no user clip planes (the common case) go by
// chunks of triangles: positions transformed; a triangle wholly inside the clip volume gets its
// window coordinates, facing and cull test, and is dropped when it covers no pixel centre;
// only the vertices of the remaining triangles get their attributes (lit 16 at a time with
// AVX2, 4 with SSE2); then the triangles are drawn by runs (Raster::triangle_run), or queued for
// the bands. A triangle crossing the clip volume takes the general path (draw_triangle). The
// same decisions and arithmetic as that general path, but for the zero terms the position stage
// leaves out of the usual matrices (at most the sign of a zero differs).
bool fast_triangles_ok(const Context::State& s) {
  if (s.poly_front != PolygonMode::Fill || s.poly_back != PolygonMode::Fill) return false;
  for (int i = 0; i < 6; ++i)
    if (s.on(clip_plane_cap(i))) return false;
  return true;
}

// A batch's vertices from a begin/end or an InVertex vector.
struct InSource {
  const InVertex* v;
  void position(std::size_t i, double& x, double& y, double& z, double& w) const {
    const Vec4& p = v[i].position;
    x = p.x(), y = p.y(), z = p.z(), w = p.w();
  }
  void positions(std::size_t i0, std::size_t n, double* x, double* y, double* z, double* w) const {
    for (std::size_t i = 0; i < n; ++i) position(i0 + i, x[i], y[i], z[i], w[i]);
  }
  const double* packed_xyz(std::size_t) const { return nullptr; }
  const InVertex& vertex(std::size_t i) const { return v[i]; }
  const Vec3& normal(std::size_t i) const { return v[i].normal; }
  const Vec4f& color(std::size_t i) const { return v[i].color; }
};

// A batch's vertices straight from client arrays (element first + i, or indices[first + i]):
// no InVertex for vertices that are never needed. As Context's fetch: missing components
// (0, 0, 0, 1), disabled arrays the current values.
struct ArraySource {
  const Context::State& s;
  const VertexArrays& a;
  const std::uint32_t* indices;
  std::size_t first;
  std::size_t at(std::size_t i) const { return indices ? indices[first + i] : first + i; }
  void position(std::size_t i, double& x, double& y, double& z, double& w) const {
    const double* p = a.positions + at(i) * a.position_size;
    x = p[0], y = p[1], z = a.position_size > 2 ? p[2] : 0.0, w = a.position_size > 3 ? p[3] : 1.0;
  }
  // The x y z of vertex i0 onward, when they lie packed in the client array (no indices, three
  // components): the position stage reads them there. Else null.
  const double* packed_xyz(std::size_t i0) const {
    return !indices && a.position_size == 3 ? a.positions + (first + i0) * 3 : nullptr;
  }
  // Positions i0 .. i0 + n - 1 into rows (those not packed_xyz).
  void positions(std::size_t i0, std::size_t n, double* x, double* y, double* z, double* w) const {
    for (std::size_t i = 0; i < n; ++i) position(i0 + i, x[i], y[i], z[i], w[i]);
  }
  Vec3 normal(std::size_t i) const {
    if (!a.normals) return s.cur_normal;
    const double* n = a.normals + at(i) * 3;
    return Vec3(n[0], n[1], n[2]);
  }
  Vec4f color(std::size_t i) const {
    if (!a.colors) return s.cur_color;
    const float* c = a.colors + at(i) * a.color_size;
    return Vec4f(c[0], c[1], c[2], a.color_size == 4 ? c[3] : 1.0f);
  }
  InVertex vertex(std::size_t i) const { return fetch_vertex(s, a, at(i)); }
};

constexpr std::size_t kChunk = 256;  // triangles

// One chunk's buffers, kept between batches. Queued triangles point into `win`/`attrs`.
struct TriChunk {
  enum : std::uint8_t { kSkip, kDraw, kClip };
  // Per vertex, by rows (SoA): object position x y z w, eye x y z w, clip x y z w, window
  // x y z and 1 / w_clip; rows of `stride` (the vertex count rounded up to 4).
  enum Row { kPx, kPy, kPz, kPw, kEx, kEy, kEz, kEw, kCx, kCy, kCz, kCw, kWx, kWy, kWz, kIw, kRows };
  std::vector<double> soa;
  std::size_t stride = 0;
  double* row(int r) { return soa.data() + r * stride; }
  std::vector<std::uint8_t> vout;  // per vertex: outside the clip volume
  std::vector<std::uint8_t> status, side, flags;  // per triangle (flags: cull_rows')
  std::vector<std::uint32_t> need;         // vertices whose attributes are needed, in order
  std::vector<WinVert> run_v;              // window vertices of the triangles drawn by runs
  std::vector<Raster::RunTri> run;
};

// What a chunk hands to the bands: the attribute sets of its needed vertices (in `need`
// order) and its queue, whose jobs point into them.
struct ChunkOut {
  std::vector<float> attrs;
  Queue queue;
};

// The calling or worker thread's chunk scratch (the position rows are not needed once the
// chunk's triangles are set up).
TriChunk& chunk_scratch() {
  static thread_local TriChunk scratch;
  return scratch;
}

// The position stage of a chunk, four vertices at a time by rows: eye = mv p, clip = proj eye
// (Eigen's operation order per element: ((c0 x + c1 y) + c2 z) + c3 w), the clip-volume test, and window
// coordinates (to_window's arithmetic) for every vertex. Compiled twice: for AVX2 (4 doubles
// per instruction, chosen at run time) and for the default target (SSE2: pairs).
struct PositionStage {
  double mv[16], proj[16];  // column-major
  double vpx, vpy, vpw, vph, dn, dr;
  // The usual case, taken with fewer operations: an affine modelview (last row 0 0 0 1) and a
  // projection shaped as glFrustum's and gluPerspective's (zeros where theirs are), with w = 1.
  bool frustum = false;
  PositionStage(const Context::State& s) {
    const Mat4& m = s.top(MatrixMode::ModelView);
    const Mat4& p = s.top(MatrixMode::Projection);
    for (int k = 0; k < 16; ++k) mv[k] = m(k % 4, k / 4), proj[k] = p(k % 4, k / 4);
    vpx = s.vp_x, vpy = s.vp_y, vpw = s.vp_w, vph = s.vp_h;
    dn = s.depth_near, dr = s.depth_far - s.depth_near;
    const bool affine = mv[3] == 0 && mv[7] == 0 && mv[11] == 0 && mv[15] == 1;
    bool shape = true;
    for (int k : {1, 2, 3, 4, 6, 7, 12, 13, 15}) shape = shape && proj[k] == 0;
    frustum = affine && shape;
  }
};

// V: a vector of doubles (D2 for the default target, D4 for AVX2); L its comparison mask.
// xyz: the chunk's positions packed x y z (w = 1) in the client array, its `count` vertices read
// there (the padding to the stride from zeros); else null, and the object rows hold them.
// Frustum (ps.frustum, xyz given): the terms whose matrix entries are zero (and w = 1) are left
// out; the others keep their order, so the results differ from the full products at most in
// the sign of a zero (and for infinite input, which the full products turn into NaN).
template <class V, bool Frustum>
[[gnu::always_inline]] inline void position_rows(const PositionStage& ps, TriChunk& ck, const double* xyz,
                                                 std::size_t count) {
  typedef decltype(V{} < V{}) L;
  constexpr int kW = sizeof(V) / sizeof(double);
  const std::size_t n = ck.stride;
  double* const b = ck.soa.data();
  std::uint8_t* const vout = ck.vout.data();
  const double* m = ps.mv;
  const double* p = ps.proj;
  for (std::size_t i = 0; i < n; i += kW) {
    double* const q = b + i;
    V X, Y, Z, W;
    if (xyz) {
      // kW vertices' x y z (3 kW doubles) as three vectors, then by lanes.
      alignas(32) double pad[3 * kW];
      const double* src = xyz + 3 * i;
      if (i + kW > count) {  // (the stride is a multiple of 4: a 2-lane group may lie wholly past the end)
        std::fill(std::begin(pad), std::end(pad), 0.0);
        if (i < count) std::memcpy(pad, src, 3 * (count - i) * sizeof(double));
        src = pad;
      }
      V v[3];
      rows_xyz(src, v);
      X = v[0], Y = v[1], Z = v[2];
      W = V{} + 1.0;
    } else {
      std::memcpy(&X, q, sizeof(V)), std::memcpy(&Y, q + n, sizeof(V));
      std::memcpy(&Z, q + 2 * n, sizeof(V)), std::memcpy(&W, q + 3 * n, sizeof(V));
    }
    V ex, ey, ez, ew, cx, cy, cz, cw;
    if constexpr (Frustum) {
      ex = ((m[0] * X + m[4] * Y) + m[8] * Z) + m[12];
      ey = ((m[1] * X + m[5] * Y) + m[9] * Z) + m[13];
      ez = ((m[2] * X + m[6] * Y) + m[10] * Z) + m[14];
      ew = V{} + 1.0;
      cx = p[0] * ex + p[8] * ez;
      cy = p[5] * ey + p[9] * ez;
      cz = p[10] * ez + p[14];
      cw = p[11] * ez;
    } else {
      ex = ((m[0] * X + m[4] * Y) + m[8] * Z) + m[12] * W;
      ey = ((m[1] * X + m[5] * Y) + m[9] * Z) + m[13] * W;
      ez = ((m[2] * X + m[6] * Y) + m[10] * Z) + m[14] * W;
      ew = ((m[3] * X + m[7] * Y) + m[11] * Z) + m[15] * W;
      cx = ((p[0] * ex + p[4] * ey) + p[8] * ez) + p[12] * ew;
      cy = ((p[1] * ex + p[5] * ey) + p[9] * ez) + p[13] * ew;
      cz = ((p[2] * ex + p[6] * ey) + p[10] * ez) + p[14] * ew;
      cw = ((p[3] * ex + p[7] * ey) + p[11] * ez) + p[15] * ew;
    }
    const L out = ((cw + cx) < 0.0) | ((cw - cx) < 0.0) | ((cw + cy) < 0.0) | ((cw - cy) < 0.0) | ((cw + cz) < 0.0) |
                  ((cw - cz) < 0.0);
    const V iw = 1.0 / cw;
    const V nx = cx * iw, ny = cy * iw, nz = cz * iw;
    const V wx = ps.vpx + (nx + 1.0) * 0.5 * ps.vpw, wy = ps.vpy + (ny + 1.0) * 0.5 * ps.vph;
    const V wz = ps.dn + (nz + 1.0) * 0.5 * ps.dr;
    std::memcpy(q + TriChunk::kEx * n, &ex, sizeof(V)), std::memcpy(q + TriChunk::kEy * n, &ey, sizeof(V));
    std::memcpy(q + TriChunk::kEz * n, &ez, sizeof(V)), std::memcpy(q + TriChunk::kEw * n, &ew, sizeof(V));
    std::memcpy(q + TriChunk::kCx * n, &cx, sizeof(V)), std::memcpy(q + TriChunk::kCy * n, &cy, sizeof(V));
    std::memcpy(q + TriChunk::kCz * n, &cz, sizeof(V)), std::memcpy(q + TriChunk::kCw * n, &cw, sizeof(V));
    std::memcpy(q + TriChunk::kWx * n, &wx, sizeof(V)), std::memcpy(q + TriChunk::kWy * n, &wy, sizeof(V));
    std::memcpy(q + TriChunk::kWz * n, &wz, sizeof(V)), std::memcpy(q + TriChunk::kIw * n, &iw, sizeof(V));
    // (One byte per lane, taken from the register: reading the mask's lanes back from memory
    // stalls on store forwarding.)
    for (int l = 0; l < kW; ++l) vout[i + l] = std::uint8_t(out[l] & 1);
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void position_rows_avx2(const PositionStage& ps, TriChunk& ck, const double* xyz,
                                                         std::size_t count) {
  if (xyz && ps.frustum) position_rows<D4, true>(ps, ck, xyz, count);
  else position_rows<D4, false>(ps, ck, xyz, count);
}
#endif
void position_rows_default(const PositionStage& ps, TriChunk& ck, const double* xyz, std::size_t count) {
  if (xyz && ps.frustum) position_rows<D2, true>(ps, ck, xyz, count);
  else position_rows<D2, false>(ps, ck, xyz, count);
}

// The facing and pixel-centre tests of a chunk's triangles, kW at a time (run_chunk's loop
// takes the bits): bit 0 front facing (draw_inside_triangle's area, lane by lane), bit 1 some
// pixel centre in the vertices' box, 1/256 pixel of slack: the centre columns c with c + 1/2 in
// [xmin - d, xmax + d] and x0 <= c < x1 end at min(floor(xmax - 1/2 + d), x1 - 1), which must
// be at least xmin - 1/2 - d and x0 (rows alike; false for NaN). (Lanes past the chunk's last
// triangle read the rows that follow: their bits are not used.)
struct CullBox {
  bool ccw;
  int x0, y0, x1, y1;
};
template <class V>
[[gnu::always_inline]] inline void cull_rows(const CullBox& cb, TriChunk& ck, std::size_t nt) {
  constexpr int kW = sizeof(V) / sizeof(double);
  const double* wx = ck.row(TriChunk::kWx);
  const double* wy = ck.row(TriChunk::kWy);
  constexpr double d = 1.0 / 256;
  for (std::size_t j = 0; j < nt; j += kW) {
    V x[3], y[3];
    rows_xyz(wx + 3 * j, x), rows_xyz(wy + 3 * j, y);  // (three vertices per triangle, by lanes)
    const V area = ((x[0] * y[1] - x[1] * y[0]) + (x[1] * y[2] - x[2] * y[1])) + (x[2] * y[0] - x[0] * y[2]);
    const auto pos = area > 0.0;
    const auto front = cb.ccw ? pos : ~pos;
    const V xmin = vmin(vmin(x[0], x[1]), x[2]), xmax = vmax(vmax(x[0], x[1]), x[2]);
    const V ymin = vmin(vmin(y[0], y[1]), y[2]), ymax = vmax(vmax(y[0], y[1]), y[2]);
    const V hx = vmin(vfloor(xmax - 0.5 + d), V{} + double(cb.x1 - 1));
    const V hy = vmin(vfloor(ymax - 0.5 + d), V{} + double(cb.y1 - 1));
    const auto box = (hx >= xmin - 0.5 - d) & (hx >= double(cb.x0)) & (hy >= ymin - 0.5 - d) & (hy >= double(cb.y0));
    for (int l = 0; l < kW; ++l) ck.flags[j + l] = std::uint8_t((front[l] & 1) | (box[l] & 2));
  }
}
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void cull_rows_avx2(const CullBox& cb, TriChunk& ck, std::size_t nt) {
  cull_rows<D4>(cb, ck, nt);
}
#endif
void cull_rows_default(const CullBox& cb, TriChunk& ck, std::size_t nt) { cull_rows<D2>(cb, ck, nt); }


template <class Src>
void run_chunk(Raster& rc, const Src& src, const Mat3& nmat, const DrawLights& dl, TriChunk& ck, ChunkOut& co,
               std::size_t t0, std::size_t t1) {
  const Context::State& s = rc.s;
  const std::size_t nt = t1 - t0, nv = 3 * nt, v0 = 3 * t0;
  ck.stride = (nv + 3) & ~std::size_t(3);
  ck.soa.resize(TriChunk::kRows * ck.stride), ck.vout.resize(ck.stride);
  ck.status.resize(nt), ck.side.resize(nt), ck.flags.resize(nt + 4);
  {
    const double* xyz = src.packed_xyz(v0);
    if (!xyz) {
      double* p[4] = {ck.row(TriChunk::kPx), ck.row(TriChunk::kPy), ck.row(TriChunk::kPz), ck.row(TriChunk::kPw)};
      src.positions(v0, nv, p[0], p[1], p[2], p[3]);
      for (std::size_t i = nv; i < ck.stride; ++i) p[0][i] = p[1][i] = p[2][i] = 0, p[3][i] = 1;
    }
    const PositionStage ps(s);
#if defined(__x86_64__) && defined(__GNUC__)
    if (rc.avx2) position_rows_avx2(ps, ck, xyz, nv);
    else position_rows_default(ps, ck, xyz, nv);
#else
    position_rows_default(ps, ck, xyz, nv);
#endif
  }
  const bool cull = s.on(Cap::CullFace);
  const bool two = two_sided_lighting(s);
  {
    // As draw_inside_triangle: signed area ((0 + t0) + t1) + t2 (0 + t0 only differs from t0
    // in the sign of a zero, which `area > 0` does not see), facing; and the centres in the box.
    const CullBox cb{s.front_face == FrontFace::CCW, rc.x0, rc.y0, rc.x1, rc.y1};
#if defined(__x86_64__) && defined(__GNUC__)
    if (rc.avx2) cull_rows_avx2(cb, ck, nt);
    else cull_rows_default(cb, ck, nt);
#else
    cull_rows_default(cb, ck, nt);
#endif
  }
  ck.need.clear();
  for (std::size_t j = 0; j < nt; ++j) {
    const std::size_t i = 3 * j;
    std::uint8_t st = TriChunk::kClip;
    if (!(ck.vout[i] | ck.vout[i + 1] | ck.vout[i + 2])) {
      // Facing, culling, then the pixel-centre test.
      const bool front = ck.flags[j] & 1;
      if (cull && (s.cull_face == Face::FrontAndBack || (s.cull_face == Face::Front) == front)) st = TriChunk::kSkip;
      else if (!(ck.flags[j] & 2)) st = TriChunk::kSkip;
      else st = TriChunk::kDraw, ck.side[j] = (!front && two) ? 1 : 0;
    }
    ck.status[j] = st;
    if (st != TriChunk::kSkip)
      for (int k = 0; k < 3; ++k) ck.need.push_back(std::uint32_t(i + k));
  }
  // Attributes of the needed vertices; lit ones W = 4 or 8 at a time (light_needed).
  const bool lit = vertex_lighting(s);
  const AttrNeeds needs(s);
  // Lit, nothing else read: the normal and colour alone (no InVertex, no texture stage), and
  // attribute sets cut to the colours the fill reads (a[kFront..] and, two-sided, a[kBack..]:
  // kFront = 0, kBack = 4), so queued triangles carry 16 or 32 bytes per vertex, not 80.
  const bool lean = lit && !needs.tex && !needs.fog && !needs.eye_normal;
  static_assert(kFront == 0 && kBack == 4, "lean attribute sets hold the colours first");
  const std::size_t astride = !lean ? kAttrs : s.two_side ? 8 : 4;
  // (Plus one full set of slack: a reader taking kAttrs floats from the last set stays inside.)
  co.attrs.resize(ck.need.size() * astride + kAttrs);
  float* const attrs = co.attrs.data();
  const double* ex = ck.row(TriChunk::kEx);
  const double* ey = ck.row(TriChunk::kEy);
  const double* ez = ck.row(TriChunk::kEz);
  const double* ew = ck.row(TriChunk::kEw);
  const std::size_t nn = ck.need.size();
  if (!lit) {
    for (std::size_t q = 0; q < nn; ++q) {
      const std::size_t i = ck.need[q];
      vertex_attrs(s, src.vertex(v0 + i), Vec4(ex[i], ey[i], ez[i], ew[i]), nmat, attrs + q * astride, needs);
    }
  } else {
    const NeededVerts nv{ck.need.data(), nn, {ex, ey, ez, ew}, v0};
#if defined(__x86_64__) && defined(__GNUC__)
    if (dl.use_wide) light_needed_avx2(s, rc.lights, *dl.wide, src, nmat, nv, lean, needs, attrs, astride);
    else light_needed_sse2(s, rc.lights, *dl.narrow, src, nmat, nv, lean, needs, attrs, astride);
#else
    light_needed_sse2(s, rc.lights, *dl.narrow, src, nmat, nv, lean, needs, attrs, astride);
#endif
  }

  // Draw (or queue) in submission order; a drawn triangle's vertices have consecutive slots.
  const bool flat = s.shade == ShadeModel::Flat;
  std::size_t slot = 0;
  const double* wx = ck.row(TriChunk::kWx);
  const double* wy = ck.row(TriChunk::kWy);
  const double* wz = ck.row(TriChunk::kWz);
  const double* iw = ck.row(TriChunk::kIw);
  const double *cx = ck.row(TriChunk::kCx), *cy = ck.row(TriChunk::kCy), *cz = ck.row(TriChunk::kCz),
               *cw = ck.row(TriChunk::kCw);
  // Drawn now (no bands): by runs (Raster::triangle_run), cut at each clipped triangle.
  std::vector<WinVert>& run_v = ck.run_v;
  std::vector<Raster::RunTri>& run = ck.run;
  run_v.resize(3 * nt), run.clear();
  RunSetup& rs = run_scratch();
  auto flush = [&] {
    rc.triangle_run(run.data(), run.size(), rs);
    run.clear();
  };
  for (std::size_t j = 0; j < nt; ++j) {
    if (ck.status[j] == TriChunk::kSkip) continue;
    const float* a = attrs + slot * astride;
    slot += 3;
    if (ck.status[j] == TriChunk::kDraw) {
      WinVert* w = run_v.data() + 3 * j;
      for (int k = 0; k < 3; ++k) {
        const std::size_t i = 3 * j + k;
        w[k] = WinVert{wx[i], wy[i], wz[i], iw[i], a + k * astride};
      }
      if (rc.sink) rc.emit_triangle_direct(w[0], w[1], w[2], ck.side[j], flat ? w[2].a : nullptr);
      else run.push_back(Raster::RunTri{w, ck.side[j], flat ? w[2].a : nullptr});
      continue;
    }
    flush();
    PVert pv[3];
    for (int k = 0; k < 3; ++k) {
      const std::size_t i = 3 * j + k;
      pv[k].clip = Vec4(cx[i], cy[i], cz[i], cw[i]);
      // (A lean set's missing attributes are zero, as vertex_attrs leaves unread ones.)
      std::fill(std::begin(pv[k].a), std::end(pv[k].a), 0.0f);
      std::memcpy(pv[k].a, a + k * astride, sizeof(float) * astride);
      if (astride == 4) std::memcpy(pv[k].a + kBack, a + k * astride, 4 * sizeof(float));
    }
    rc.draw_triangle(pv[0], pv[1], pv[2], pv[2]);
  }
  flush();
}

// A batch of `tris` independent triangles from `src`, drawn through `r`.
template <class Src>
void draw_triangles(Raster& r, const Src& src, std::size_t tris) {
  if (tris == 0) return;
  const Context::State& s = r.s;
  const Mat3 nmat = s.top(MatrixMode::ModelView).topLeftCorner<3, 3>().inverse().transpose();
  DrawLights dl;
  if (vertex_lighting(s)) {
#if defined(__x86_64__) && defined(__GNUC__)
    dl.use_wide = r.avx2;
#endif
    if (dl.use_wide) dl.wide = std::make_unique<LightConsts<F16>>(s, r.lights);
    else dl.narrow = std::make_unique<LightConsts<F4>>(s, r.lights);
  }
  const std::size_t chunks = (tris + kChunk - 1) / kChunk;
  // Kept between batches (per calling thread): fresh buffers would cost page faults.
  static thread_local std::vector<std::unique_ptr<ChunkOut>> tl_chunks;
  std::vector<std::unique_ptr<ChunkOut>>& ck = tl_chunks;
  const bool banded = s.threads > 1 && (3 * tris >= 64 || std::int64_t(r.width) * r.height >= 512 * 512);
  const std::size_t need = banded ? chunks : 1;
  while (ck.size() < need) ck.push_back(std::make_unique<ChunkOut>());
  if (!banded) {
    r.sink = nullptr;
    for (std::size_t c = 0; c < chunks; ++c)
      run_chunk(r, src, nmat, dl, chunk_scratch(), *ck[0], c * kChunk, std::min(tris, (c + 1) * kChunk));
    return;
  }
  const int bands = (r.height + kBandRows - 1) / kBandRows;
  tbb::task_arena& arena = arena_for(s.threads);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
      Raster rc = r;
      ChunkOut& k = *ck[c];
      k.queue.clear();
      rc.sink = &k.queue;
      run_chunk(rc, src, nmat, dl, chunk_scratch(), k, c * kChunk, std::min(tris, (c + 1) * kChunk));
      k.queue.bin(bands);
    });
  });
  static thread_local std::vector<Queue*> tl_queues;
  std::vector<Queue*>& queues = tl_queues;
  queues.clear();
  for (std::size_t c = 0; c < chunks; ++c) queues.push_back(&ck[c]->queue);
  draw_bands(r, queues.data(), queues.size());
}

}  // namespace

std::atomic<bool> simd_fallback{false};

namespace {
void pow_lanes4(const float* x, std::size_t n, float y, float* out) {
  for (std::size_t i = 0; i < n; i += 4) {
    F4 v = bcast(1), r;
    std::memcpy(&v, x + i, sizeof(float) * std::min<std::size_t>(4, n - i));
    r = vpow(v, y);
    std::memcpy(out + i, &r, sizeof(float) * std::min<std::size_t>(4, n - i));
  }
}
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2"))) void pow_lanes8(const float* x, std::size_t n, float y, float* out) {
  for (std::size_t i = 0; i < n; i += 8) {
    F8 v = splat<F8>(1), r;
    std::memcpy(&v, x + i, sizeof(float) * std::min<std::size_t>(8, n - i));
    r = vpow(v, y);
    std::memcpy(out + i, &r, sizeof(float) * std::min<std::size_t>(8, n - i));
  }
}
#endif
}  // namespace

void lighting_pow(const float* x, std::size_t n, float y, float* out, bool avx2) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (avx2 && __builtin_cpu_supports("avx2")) return pow_lanes8(x, n, y, out);
#endif
  (void)avx2;
  pow_lanes4(x, n, y, out);
}
float lighting_pow(float x, float y) { return gl_pow(x, y); }

void lighting_normals(const Mat3& nmat, const double* n, std::size_t count, bool normalize, double* out) {
  double m[9];
  for (int k = 0; k < 9; ++k) m[k] = nmat(k % 3, k / 3);
  for (std::size_t i = 0; i < count; i += 2) {
    Lanes<F4>::D v[3];  // the SSE2 build's (the AVX2 one's: the same operations on four lanes)
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 2; ++l) v[k][l] = i + l < count ? n[3 * (i + l) + k] : 1.0;
    eye_normals(m, v, normalize);
    for (std::size_t l = 0; l < 2 && i + l < count; ++l)
      for (int k = 0; k < 3; ++k) out[3 * (i + l) + k] = v[k][l];
  }
}

bool run_triangle_arrays(Context::State& s, int width, int height, std::uint8_t* color, float* depth,
                         const VertexArrays& a, const std::uint32_t* indices, int first, int count) {
  if (!fast_triangles_ok(s)) return false;
  Raster r(s, width, height, color, depth);
  // Batches bound the queued primitives' memory.
  constexpr std::size_t kBatch = 16384;  // triangles
  const std::size_t tris = std::size_t(count) / 3;
  for (std::size_t t = 0; t < tris; t += kBatch)
    draw_triangles(r, ArraySource{s, a, indices, std::size_t(first) + 3 * t}, std::min(kBatch, tris - t));
  return true;
}

void run_primitive(Context::State& s, int width, int height, std::uint8_t* color, float* depth, Primitive p,
                   const std::vector<InVertex>& in) {
  if (in.empty()) return;
  if (p == Primitive::Triangles && fast_triangles_ok(s)) {
    Raster r(s, width, height, color, depth);
    return draw_triangles(r, InSource{in.data()}, in.size() / 3);
  }
  const Mat4& mv = s.top(MatrixMode::ModelView);
  const Mat3 nmat = mv.topLeftCorner<3, 3>().inverse().transpose();
  const Mat4& proj = s.top(MatrixMode::Projection);
  // Kept between calls (per thread): a fresh megabyte-sized vector per batch costs page faults.
  // (Named through a reference: TBB workers in the lambdas below must see the caller's vector.)
  static thread_local std::vector<PVert> tl_verts;
  std::vector<PVert>& v = tl_verts;
  v.resize(in.size());
  Raster r(s, width, height, color, depth);
  const LightSetup& lights = r.lights;
  // Independent triangles with face culling: a triangle wholly inside the clip volume that the
  // cull test removes (decided exactly as draw_triangle would, on the same window coordinates)
  // is marked here and its vertices are never lit. Every vertex of a non-indexed batch belongs
  // to one triangle, so a closed lit mesh lights about half of its vertices.
  static thread_local std::vector<std::uint8_t> tl_culled;
  std::vector<std::uint8_t>& culled = tl_culled;
  const bool precull = p == Primitive::Triangles && s.on(Cap::CullFace) && r.user_planes.empty();
  const std::size_t units = precull ? in.size() / 3 : in.size();
  if (precull) culled.assign(units, 0);
  static thread_local std::vector<WinVert> tl_win;
  std::vector<WinVert>& win = tl_win;
  const bool fill = s.poly_front == PolygonMode::Fill && s.poly_back == PolygonMode::Fill;
  if (precull && fill) win.resize(in.size());
  auto stage = [&](std::size_t lo, std::size_t hi) {
    for (std::size_t u = lo; u < hi; ++u) {
      if (!precull) {
        const Vec4 eye = mv * in[u].position;
        v[u] = process_vertex(s, lights, in[u], eye, proj * eye, nmat);
        continue;
      }
      PVert c[3];
      Vec4 eye[3];
      bool inside = true;
      for (int k = 0; k < 3; ++k) {
        eye[k] = mv * in[3 * u + k].position;
        c[k].clip = proj * eye[k];
        for (int pl = 0; pl < 6; ++pl)
          if (r.plane_dist(c[k], pl) < 0) inside = false;
      }
      if (inside) {
        const WinVert w[3] = {r.to_window(c[0]), r.to_window(c[1]), r.to_window(c[2])};
        double area = 0;
        for (int i = 0; i < 3; ++i) area += w[i].x * w[(i + 1) % 3].y - w[(i + 1) % 3].x * w[i].y;
        const bool front = (area > 0) == (s.front_face == FrontFace::CCW);
        if (s.cull_face == Face::FrontAndBack || (s.cull_face == Face::Front) == front) {
          culled[u] = 1;
          continue;
        }
        // Visible and inside: its window coordinates are kept for draw_inside_triangle.
        if (fill) {
          for (int k = 0; k < 3; ++k) win[3 * u + k] = w[k], win[3 * u + k].a = v[3 * u + k].a;
          culled[u] = 2;
        }
      }
      for (int k = 0; k < 3; ++k) v[3 * u + k] = process_vertex(s, lights, in[3 * u + k], eye[k], c[k].clip, nmat);
    }
  };
  if (s.threads > 1 && in.size() >= 1024) {
    // The vertex stage is independent per vertex.
    tbb::task_arena& arena = arena_for(s.threads);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, units, 256),
                        [&](const tbb::blocked_range<std::size_t>& br) { stage(br.begin(), br.end()); });
    });
  } else {
    stage(0, units);
  }
  static thread_local Queue tl_queue;
  Queue& jobs = tl_queue;
  jobs.clear();
  std::vector<Queue*> queues;  // queued primitives, in order
  // Bands pay for many primitives, or for few on a large framebuffer (a couple of big textured
  // triangles are all fragment work).
  const bool banded = s.threads > 1 && (in.size() >= 64 || std::int64_t(width) * height >= 512 * 512);
  if (banded) r.sink = &jobs;
  const std::size_t n = v.size();
  // Every polygon is split into triangles before clipping, as Mesa does (quads as (0,1,2),
  // (0,2,3) keeping the last vertex as provoking; polygons as a fan from vertex 0); the edge
  // flags hide the inner diagonals in polygon-mode line.
  auto tri = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t prov, bool e0 = true, bool e1 = true,
                 bool e2 = true) {
    PVert va = v[a], vb = v[b], vc = v[c];
    va.edge = e0, vb.edge = e1, vc.edge = e2;
    r.draw_triangle(va, vb, vc, v[prov]);
  };
  // Which diagonal splits a quad changes how colours interpolate across it. GL leaves it open;
  // Mesa splits (0,1,2),(0,2,3) on its fast path and (0,1,3),(1,2,3) when the batch goes
  // through its clipping/two-side pipeline (some vertex outside the clip volume, or two-sided
  // lighting). We follow Mesa, so that images compare pixel for pixel.
  bool pipeline_split = false;
  if (p == Primitive::Quads || p == Primitive::QuadStrip) {
    pipeline_split = two_sided_lighting(s) || s.poly_front != PolygonMode::Fill || s.poly_back != PolygonMode::Fill;
    for (std::size_t i = 0; i < v.size() && !pipeline_split; ++i)
      for (int k = 0; k < r.plane_count(); ++k)
        if (r.plane_dist(v[i], k) < 0) {
          pipeline_split = true;
          break;
        }
  }
  auto quad = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t d, std::size_t prov) {
    if (pipeline_split) {
      tri(a, b, d, prov, true, false, true);
      tri(b, c, d, prov, true, true, false);
    } else {
      tri(a, b, c, prov, true, true, false);
      tri(a, c, d, prov, false, true, true);
    }
  };
  switch (p) {
    case Primitive::Points:
      for (auto& x : v) r.draw_point(x);
      break;
    case Primitive::Lines:
      for (std::size_t i = 0; i + 1 < n; i += 2) r.draw_line(v[i], v[i + 1], v[i + 1]);
      break;
    case Primitive::LineStrip:
      for (std::size_t i = 0; i + 1 < n; ++i) r.draw_line(v[i], v[i + 1], v[i + 1]);
      break;
    case Primitive::LineLoop:
      for (std::size_t i = 0; i + 1 < n; ++i) r.draw_line(v[i], v[i + 1], v[i + 1]);
      if (n > 1) r.draw_line(v[n - 1], v[0], v[0]);
      break;
    case Primitive::Triangles:
      if (banded && n >= 3 * 512) {
        // Clipping and setup in parallel over chunks of triangles, each into its own queue;
        // the queues are joined in chunk order, so submission order is kept.
        const std::size_t tris = n / 3, chunk = 256, chunks = (tris + chunk - 1) / chunk;
        // Kept between batches (per calling thread): fresh 100 kB queues cost page faults.
        static thread_local std::vector<std::unique_ptr<Queue>> tl_queues;
        std::vector<std::unique_ptr<Queue>>& cq = tl_queues;
        while (cq.size() < chunks) cq.push_back(std::make_unique<Queue>());
        const int bands = (height + kBandRows - 1) / kBandRows;
        tbb::task_arena& arena = arena_for(s.threads);
        arena.execute([&] {
          tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
            Raster rc = r;
            cq[c]->clear();
            rc.sink = cq[c].get();
            for (std::size_t t = c * chunk; t < std::min(tris, (c + 1) * chunk); ++t)
              if (!precull || culled[t] != 1) {
                if (precull && culled[t] == 2) rc.draw_inside_triangle(&win[3 * t], v[3 * t + 2]);
                else rc.draw_triangle(v[3 * t], v[3 * t + 1], v[3 * t + 2], v[3 * t + 2]);
              }
            cq[c]->bin(bands);
          });
        });
        // Drawn straight from the queues, in chunk order (no copy into one list).
        for (std::size_t c = 0; c < chunks; ++c) queues.push_back(cq[c].get());
      } else {
        // Vertices leave the vertex stage with their edge flags set: no copies needed.
        for (std::size_t i = 0; i + 2 < n; i += 3)
          if (!precull || culled[i / 3] != 1) {
            if (precull && culled[i / 3] == 2) r.draw_inside_triangle(&win[i], v[i + 2]);
            else r.draw_triangle(v[i], v[i + 1], v[i + 2], v[i + 2]);
          }
      }
      break;
    case Primitive::TriangleStrip:
      for (std::size_t i = 0; i + 2 < n; ++i) {
        if (i % 2 == 0) tri(i, i + 1, i + 2, i + 2);
        else tri(i + 1, i, i + 2, i + 2);
      }
      break;
    case Primitive::TriangleFan:
      for (std::size_t i = 1; i + 1 < n; ++i) tri(0, i, i + 1, i + 1);
      break;
    case Primitive::Quads:
      for (std::size_t i = 0; i + 3 < n; i += 4) quad(i, i + 1, i + 2, i + 3, i + 3);
      break;
    case Primitive::QuadStrip:
      for (std::size_t i = 0; i + 3 < n; i += 2) {
        if (pipeline_split) quad(i + 2, i, i + 1, i + 3, i + 3);  // Mesa's QUAD(i+2, i, i+1, i+3)
        else quad(i, i + 1, i + 3, i + 2, i + 3);
      }
      break;
    case Primitive::Polygon:
      for (std::size_t i = 1; i + 1 < n; ++i) tri(0, i, i + 1, 0, i == 1, true, i + 2 == n);
      break;
  }
  if (!banded) return;
  if (!jobs.jobs.empty()) {
    jobs.bin((height + kBandRows - 1) / kBandRows);
    queues.push_back(&jobs);
  }
  r.sink = nullptr;
  if (!queues.empty()) draw_bands(r, queues.data(), queues.size());
}

}  // namespace wedge::render
