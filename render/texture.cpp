// Textures as OpenGL 1.x samples them (GL 1.5 spec section 3.8.8): wrap modes repeat, clamp
// (texel coordinates clamped to [0, 1], so linear filtering at the edge blends with the border
// colour) and clamp-to-edge; magnification nearest/linear; minification nearest/linear and the
// four mipmap filters, choosing the level d = lambda (nearest level: round, as the spec's
// ceil(lambda + 1/2) - 1) or blending the two levels around it. The mipmap chain is built by
// 2x2 box filtering (what gluBuild2DMipmaps does for power-of-two images).
//
// Sampling: sample4() runs four fragments at once, one fragment per SIMD lane (structure of
// arrays): the wrapped coordinates, texel indices and bilinear weights of all four in one register
// each, the texels fetched by index, then filtered in fixed point (integer weights, exact integer
// sums; see "Fast path" below). sample() takes one fragment with its two levels' coordinates in
// one register and applies exactly the float operations the four-lane path applies to that
// fragment's lane, so the two agree bit for bit (tests/render/test_texture.cpp checks it). The
// base path is SSE2 (part of x86-64); trilinear quads take an AVX2 path when the CPU has it
// (chosen at run time), which puts both mip levels in one 256-bit register with the same
// operations lane for lane (no FMA), so the results do not depend on the CPU either. GL_CLAMP
// (border colour) and images of 32768 texels or more a side take a per-fragment general path in
// float.
#include <cmath>
#include <cstring>

#include <immintrin.h>

#include "render/render.h"

namespace wedge::render {

namespace {

using V4 = __m128;
using I4 = __m128i;

inline V4 splat(float x) { return _mm_set1_ps(x); }
inline V4 load(const Vec4f& v) { return _mm_loadu_ps(v.data()); }

// ---------------------------------------------------------------------------------------------
// General path (one fragment at a time): GL_CLAMP with its border colour, and any texture whose
// levels are too large for the fast path's 16-bit index arithmetic.

// Format expansion of a converted texel (luminance to grey, alpha 1 unless RGBA).
[[gnu::always_inline]] inline V4 expand(V4 c, TexFormat fmt) {
  if (fmt != TexFormat::RGBA) {
    if (fmt == TexFormat::Luminance) c = _mm_shuffle_ps(c, c, 0);
    const V4 rgb = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
    c = _mm_or_ps(_mm_and_ps(c, rgb), _mm_andnot_ps(rgb, splat(1.0f)));
  }
  return c;
}

// Texel (i, j) of a level, already inside the image, as floats in [0, 1] after the format's
// expansion.
[[gnu::always_inline]] inline V4 texel(const std::uint8_t* base, int width, TexFormat fmt, int i, int j) {
  std::int32_t bits;
  std::memcpy(&bits, base + (std::size_t(j) * width + i) * 4, 4);
  const I4 zero = _mm_setzero_si128();
  I4 x = _mm_unpacklo_epi8(_mm_cvtsi32_si128(bits), zero);
  x = _mm_unpacklo_epi16(x, zero);
  return expand(_mm_mul_ps(_mm_cvtepi32_ps(x), splat(1.0f / 255.0f)), fmt);
}

int wrap_repeat(int i, int size) {
  if (unsigned(i) < unsigned(size)) return i;  // already inside: skip the division
  if ((size & (size - 1)) == 0) return i & (size - 1);  // power of two: the mask is the modulo
  i %= size;
  return i < 0 ? i + size : i;
}

// A wrapped coordinate in [0, 1]; NaN (also repeat's inf - inf) becomes 1, as on the fast path.
float wrap_coord(float s, TexWrap w) {
  if (w == TexWrap::Repeat) s -= std::floor(s);
  s = s < 1.0f ? s : 1.0f;
  return s > 0.0f ? s : 0.0f;
}

// One level sampled at wrapped coordinates (ws, wt) in [0, 1] (wrap_coord already applied).
V4 sample_level(const Texture& t, int level, float ws, float wt, bool linear) {
  const Image& im = t.levels[level];
  const int w = im.width, h = im.height;
  const std::uint8_t* base = im.rgba.data();
  const float u = ws * w, v = wt * h;
  if (!linear) {
    int i = std::min(int(std::floor(u)), w - 1), j = std::min(int(std::floor(v)), h - 1);
    if (t.wrap_s == TexWrap::Repeat) i = wrap_repeat(i, w);
    if (t.wrap_t == TexWrap::Repeat) j = wrap_repeat(j, h);
    return texel(base, w, t.format, std::clamp(i, 0, w - 1), std::clamp(j, 0, h - 1));
  }
  const float uf = u - 0.5f, vf = v - 0.5f;
  int i0 = int(std::floor(uf)), j0 = int(std::floor(vf));
  const float a = uf - i0, b = vf - j0;
  int i1 = i0 + 1, j1 = j0 + 1;
  // Wrap the two columns and two rows once; with GL_CLAMP a texel outside the image is the border.
  bool in_i0 = true, in_i1 = true, in_j0 = true, in_j1 = true;
  switch (t.wrap_s) {
    case TexWrap::Repeat: i0 = wrap_repeat(i0, w), i1 = wrap_repeat(i1, w); break;
    case TexWrap::ClampToEdge: i0 = std::clamp(i0, 0, w - 1), i1 = std::clamp(i1, 0, w - 1); break;
    case TexWrap::Clamp: in_i0 = i0 >= 0 && i0 < w, in_i1 = i1 >= 0 && i1 < w; break;
  }
  switch (t.wrap_t) {
    case TexWrap::Repeat: j0 = wrap_repeat(j0, h), j1 = wrap_repeat(j1, h); break;
    case TexWrap::ClampToEdge: j0 = std::clamp(j0, 0, h - 1), j1 = std::clamp(j1, 0, h - 1); break;
    case TexWrap::Clamp: in_j0 = j0 >= 0 && j0 < h, in_j1 = j1 >= 0 && j1 < h; break;
  }
  const V4 border = load(t.border);
  const V4 c00 = in_i0 && in_j0 ? texel(base, w, t.format, i0, j0) : border;
  const V4 c10 = in_i1 && in_j0 ? texel(base, w, t.format, i1, j0) : border;
  const V4 c01 = in_i0 && in_j1 ? texel(base, w, t.format, i0, j1) : border;
  const V4 c11 = in_i1 && in_j1 ? texel(base, w, t.format, i1, j1) : border;
  V4 r = _mm_mul_ps(splat((1 - a) * (1 - b)), c00);
  r = _mm_add_ps(r, _mm_mul_ps(splat(a * (1 - b)), c10));
  r = _mm_add_ps(r, _mm_mul_ps(splat((1 - a) * b), c01));
  return _mm_add_ps(r, _mm_mul_ps(splat(a * b), c11));
}

// Which levels a level of detail reads and how it blends them (shared by both paths).
struct Plan {
  int l0 = 0, l1 = -1;  // l1 < 0: one level
  float f = 0;          // weight of level l1
  bool linear = false;  // bilinear within a level (else nearest)
  int share0 = 16384, share1 = 0;  // fast path: the levels' weights in units of 2^-14, summing to 2^14
};

[[gnu::always_inline]] inline Plan make_plan(const Texture& t, float lambda) {
  const TexFilter min_filter = t.min_filter;
  Plan p;
  if (!(lambda > 0) || t.levels.size() == 1) {  // magnification (also a NaN lambda)
    p.linear = (lambda > 0 ? min_filter : t.mag_filter) == TexFilter::Linear;
    if (lambda > 0) p.linear = min_filter != TexFilter::Nearest && min_filter != TexFilter::NearestMipmapNearest &&
                               min_filter != TexFilter::NearestMipmapLinear;
    return p;
  }
  const int last = int(t.levels.size()) - 1;
  switch (min_filter) {
    case TexFilter::Nearest: break;
    case TexFilter::Linear: p.linear = true; break;
    case TexFilter::NearestMipmapNearest:
    case TexFilter::LinearMipmapNearest:
      p.l0 = lambda <= 0.5f ? 0 : lambda >= last ? last : std::min(last, int(std::ceil(lambda + 0.5f)) - 1);
      p.linear = min_filter == TexFilter::LinearMipmapNearest;
      break;
    case TexFilter::NearestMipmapLinear:
    case TexFilter::LinearMipmapLinear:
      p.linear = min_filter == TexFilter::LinearMipmapLinear;
      if (lambda >= last) {
        p.l0 = last;
      } else {
        p.l0 = int(lambda), p.l1 = p.l0 + 1;  // 0 < lambda < last: truncation is the floor
        p.f = lambda - p.l0;
        p.share1 = _mm_cvtss_si32(_mm_set_ss(p.f * 16384.0f));
        p.share0 = 16384 - p.share1;
      }
      break;
  }
  return p;
}

V4 sample_general(const Texture& t, float s, float tt, const Plan& p) {
  const float ws = wrap_coord(s, t.wrap_s), wt = wrap_coord(tt, t.wrap_t);
  V4 c = sample_level(t, p.l0, ws, wt, p.linear);
  if (p.l1 >= 0) c = _mm_add_ps(_mm_mul_ps(splat(1 - p.f), c), _mm_mul_ps(splat(p.f), sample_level(t, p.l1, ws, wt, p.linear)));
  return _mm_min_ps(_mm_max_ps(c, _mm_setzero_ps()), splat(1.0f));  // weights summing to 1 + ulp
}

[[gnu::noinline]] void sample4_general(const Texture& t, const Plan& p, const float* s, const float* tt, float* out) {
  for (int k = 0; k < 4; ++k) _mm_storeu_ps(out + 4 * k, sample_general(t, s[k], tt[k], p));
}

// ---------------------------------------------------------------------------------------------
// Fast path. A sample is a weighted sum of at most eight texels (a 2x2 footprint, or one texel
// for nearest, in one or two levels) computed in integers. The weights are in units of 2^-14: the
// two levels share 2^14 as S0 = 2^14 - S1 and S1 = round(f 2^14) (one level: S0 = 2^14); within a
// level of share S the bilinear weights (1-a)(1-b), a(1-b), (1-a)b are rounded products
// round(w * S) and ab takes the rest, so the weights add up to 2^14 exactly and a constant texture
// gives its colour exactly. Texel bytes times weights are summed exactly in 32-bit lanes (pmaddwd,
// two texels per multiply-add) and the sum times 1/(255 * 2^14) is the colour. The float steps are
// the same operations in every path and the integer steps are exact, so lane layout and summation
// order do not change a bit. A lone texel of weight 1 comes out as byte * (1/255) exactly (scaling
// by 2^14 is exact); otherwise the weights' rounding (they still add up to 2^14) moves a result by
// at most 1.5 * 2^-14 of full scale per level, under 0.05 of a level of 255 in all.

constexpr float kOutScale = 1.0f / (255.0f * 16384.0f);

// The fast path takes repeat and clamp-to-edge with levels whose indices fit 16 bits (the row
// offset j * width is one _mm_madd_epi16).
bool fast_ok(const Texture& t, const Plan& p) {
  if (t.wrap_s == TexWrap::Clamp || t.wrap_t == TexWrap::Clamp) return false;
  const Image& im = t.levels[p.l0];  // the largest level read
  return im.width < 32768 && im.height < 32768;
}

// floor of four floats in (-2^31, 2^31) with SSE2 alone: truncate, then step down where
// truncation rounded up.
[[gnu::always_inline]] inline V4 floor4(V4 x) {
  const V4 t = _mm_cvtepi32_ps(_mm_cvttps_epi32(x));
  return _mm_sub_ps(t, _mm_and_ps(_mm_cmpgt_ps(t, x), splat(1.0f)));
}

// Wrapped texture coordinates in [0, 1]: repeat takes the fraction (a float of magnitude 2^23 or
// more is already an integer), clamp-to-edge clamps. A NaN or infinite coordinate becomes 1, so
// no index can leave the image.
[[gnu::always_inline]] inline V4 wrap4(V4 s, TexWrap w) {
  if (w == TexWrap::Repeat) {
    const V4 big = _mm_cmpge_ps(_mm_andnot_ps(splat(-0.0f), s), splat(8388608.0f));
    const V4 fl = _mm_or_ps(_mm_and_ps(big, s), _mm_andnot_ps(big, floor4(s)));
    s = _mm_sub_ps(s, fl);
  }
  return _mm_max_ps(_mm_min_ps(s, splat(1.0f)), _mm_setzero_ps());  // NaN -> 1 (MINPS takes the 2nd operand)
}

// Columns (or rows) i0 and i0 + 1 of a bilinear footprint, i0 in [-1, size - 1], wrapped into the
// image: repeat maps -1 to size - 1 and size to 0, clamp-to-edge maps them to 0 and size - 1.
[[gnu::always_inline]] inline void wrap_pair(I4& i0, I4& i1, I4 size, TexWrap w) {
  const I4 lo = _mm_cmplt_epi32(i0, _mm_setzero_si128()), hi = _mm_cmpeq_epi32(i1, size);
  if (w == TexWrap::Repeat) {
    i0 = _mm_add_epi32(i0, _mm_and_si128(lo, size));
    i1 = _mm_sub_epi32(i1, _mm_and_si128(hi, size));
  } else {
    i0 = _mm_sub_epi32(i0, lo);
    i1 = _mm_add_epi32(i1, hi);
  }
}

// Four texels of a level by texel index.
[[gnu::always_inline]] inline I4 gather(const std::uint8_t* base, I4 index) {
  alignas(16) std::int32_t k[4];
  _mm_store_si128(reinterpret_cast<I4*>(k), index);
  auto ld = [&](int n) __attribute__((always_inline)) {
    std::int32_t v;
    std::memcpy(&v, base + std::size_t(k[n]) * 4, 4);
    return _mm_cvtsi32_si128(v);
  };
  return _mm_unpacklo_epi64(_mm_unpacklo_epi32(ld(0), ld(1)), _mm_unpacklo_epi32(ld(2), ld(3)));
}

// Texel index j * width + i; i, j, width below 2^15 (one multiply-add of 16-bit halves).
[[gnu::always_inline]] inline I4 index(I4 i, I4 j, I4 width) { return _mm_add_epi32(_mm_madd_epi16(j, width), i); }

// Adds texels x and y of four fragments, weighted by the low and high 16-bit halves of p's lanes,
// to acc[0..3] (four int32 channel sums per fragment): bytes interleaved x, y per channel, widened
// to 16 bits, one multiply-add per fragment.
[[gnu::always_inline]] inline void add_pair(I4 x, I4 y, I4 p, I4* acc) {
  const I4 zero = _mm_setzero_si128();
  const I4 lo = _mm_unpacklo_epi8(x, y), hi = _mm_unpackhi_epi8(x, y);
  acc[0] = _mm_add_epi32(acc[0], _mm_madd_epi16(_mm_unpacklo_epi8(lo, zero), _mm_shuffle_epi32(p, 0x00)));
  acc[1] = _mm_add_epi32(acc[1], _mm_madd_epi16(_mm_unpackhi_epi8(lo, zero), _mm_shuffle_epi32(p, 0x55)));
  acc[2] = _mm_add_epi32(acc[2], _mm_madd_epi16(_mm_unpacklo_epi8(hi, zero), _mm_shuffle_epi32(p, 0xaa)));
  acc[3] = _mm_add_epi32(acc[3], _mm_madd_epi16(_mm_unpackhi_epi8(hi, zero), _mm_shuffle_epi32(p, 0xff)));
}

// Integer weights: round(w * share).
[[gnu::always_inline]] inline I4 weight(V4 w, V4 share) { return _mm_cvtps_epi32(_mm_mul_ps(w, share)); }

// One level's weighted texels for four fragments, added to acc[0..3].
[[gnu::always_inline]] inline void level4(const Texture& t, const Image& im, bool linear, int share, V4 ws, V4 wt,
                                          I4* acc) {
  const I4 wi = _mm_set1_epi32(im.width), hi = _mm_set1_epi32(im.height);
  const V4 u = _mm_mul_ps(ws, _mm_cvtepi32_ps(wi)), v = _mm_mul_ps(wt, _mm_cvtepi32_ps(hi));
  const std::uint8_t* base = im.rgba.data();
  const I4 si = _mm_set1_epi32(share);
  if (!linear) {
    // u, v in [0, size]: truncation is the floor; size itself is the last texel.
    I4 i = _mm_cvttps_epi32(u), j = _mm_cvttps_epi32(v);
    i = _mm_add_epi32(i, _mm_cmpeq_epi32(i, wi)), j = _mm_add_epi32(j, _mm_cmpeq_epi32(j, hi));
    const I4 x = gather(base, index(i, j, wi));
    add_pair(x, x, si, acc);  // weight in the low halves, 0 in the high ones
    return;
  }
  const V4 uf = _mm_sub_ps(u, splat(0.5f)), vf = _mm_sub_ps(v, splat(0.5f));
  const V4 fu = floor4(uf), fv = floor4(vf);
  const V4 a = _mm_sub_ps(uf, fu), b = _mm_sub_ps(vf, fv);
  I4 i0 = _mm_cvttps_epi32(fu), j0 = _mm_cvttps_epi32(fv);
  const I4 one = _mm_set1_epi32(1);
  I4 i1 = _mm_add_epi32(i0, one), j1 = _mm_add_epi32(j0, one);
  wrap_pair(i0, i1, wi, t.wrap_s);
  wrap_pair(j0, j1, hi, t.wrap_t);
  const V4 na = _mm_sub_ps(splat(1.0f), a), nb = _mm_sub_ps(splat(1.0f), b);
  const V4 g = _mm_cvtepi32_ps(si);
  const I4 w00 = weight(_mm_mul_ps(na, nb), g), w10 = weight(_mm_mul_ps(a, nb), g), w01 = weight(_mm_mul_ps(na, b), g);
  const I4 w11 = _mm_sub_epi32(_mm_sub_epi32(_mm_sub_epi32(si, w00), w10), w01);  // the rest (may be -1)
  const I4 r0 = _mm_madd_epi16(j0, wi), r1 = _mm_madd_epi16(j1, wi);
  const I4 p0 = _mm_or_si128(w00, _mm_slli_epi32(w10, 16)), p1 = _mm_or_si128(w01, _mm_slli_epi32(w11, 16));
  if (_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(i1, _mm_add_epi32(i0, one)))) == 0xf) {
    // Columns i0 and i0 + 1 neighbours in memory in every lane: one 8-byte load per fragment and
    // row (it stays inside the row), channel bytes interleaved with the second texel, widened.
    alignas(16) std::int32_t o[8];
    _mm_store_si128(reinterpret_cast<I4*>(o), _mm_add_epi32(r0, i0));
    _mm_store_si128(reinterpret_cast<I4*>(o + 4), _mm_add_epi32(r1, i0));
    const I4 zero = _mm_setzero_si128();
    const I4 pk[2][4] = {{_mm_shuffle_epi32(p0, 0x00), _mm_shuffle_epi32(p0, 0x55), _mm_shuffle_epi32(p0, 0xaa),
                          _mm_shuffle_epi32(p0, 0xff)},
                         {_mm_shuffle_epi32(p1, 0x00), _mm_shuffle_epi32(p1, 0x55), _mm_shuffle_epi32(p1, 0xaa),
                          _mm_shuffle_epi32(p1, 0xff)}};
#pragma GCC unroll 8
    for (int n = 0; n < 8; ++n) {
      const I4 q = _mm_loadl_epi64(reinterpret_cast<const I4*>(base + std::size_t(o[n]) * 4));
      const I4 x = _mm_unpacklo_epi8(_mm_unpacklo_epi8(q, _mm_srli_si128(q, 4)), zero);
      acc[n & 3] = _mm_add_epi32(acc[n & 3], _mm_madd_epi16(x, pk[n >> 2][n & 3]));
    }
    return;
  }
  const I4 t00 = gather(base, _mm_add_epi32(r0, i0)), t10 = gather(base, _mm_add_epi32(r0, i1));
  const I4 t01 = gather(base, _mm_add_epi32(r1, i0)), t11 = gather(base, _mm_add_epi32(r1, i1));
  add_pair(t00, t10, p0, acc);
  add_pair(t01, t11, p1, acc);
}

// A fragment's integer channel sums to its RGBA colour: times 1/(255 * 2^14), clamped to [0, 1]
// (a weight of -1 can take a sum 255 units past either end), then the format's expansion
// (luminance to grey, alpha 1 unless RGBA).
[[gnu::always_inline]] inline V4 to_colour(I4 sum, TexFormat fmt) {
  V4 c = _mm_mul_ps(_mm_cvtepi32_ps(sum), splat(kOutScale));
  c = _mm_min_ps(_mm_max_ps(c, _mm_setzero_ps()), splat(1.0f));
  if (fmt != TexFormat::RGBA) {
    if (fmt == TexFormat::Luminance) c = _mm_shuffle_ps(c, c, 0);
    const V4 rgb = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
    c = _mm_or_ps(_mm_and_ps(c, rgb), _mm_andnot_ps(rgb, splat(1.0f)));
  }
  return c;
}

[[gnu::noinline]] void sample_sse(const Texture& t, const Plan& p, const float* s, const float* tt, float* out) {
  const V4 ws = wrap4(_mm_loadu_ps(s), t.wrap_s), wt = wrap4(_mm_loadu_ps(tt), t.wrap_t);
  I4 acc[4] = {_mm_setzero_si128(), _mm_setzero_si128(), _mm_setzero_si128(), _mm_setzero_si128()};
  level4(t, t.levels[p.l0], p.linear, p.share0, ws, wt, acc);
  if (p.l1 >= 0) level4(t, t.levels[p.l1], p.linear, p.share1, ws, wt, acc);
  const TexFormat fmt = t.format;
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) _mm_storeu_ps(out + 4 * k, to_colour(acc[k], fmt));
}

// ---------------------------------------------------------------------------------------------
// One fragment (sample()): the four channels in one register, both levels' texel coordinates in
// one register (s W0, t H0, s W1, t H1); the float operations are those the four-lane path applies
// to the fragment's lane (IEEE single operations give the same result in any lane or register).

// wrap4 on one coordinate.
[[gnu::always_inline]] inline float wrap1(float s, TexWrap w) {
  if (w == TexWrap::Repeat) {
    float fl = s;
    if (!(std::fabs(s) >= 8388608.0f)) {
      const float tr = float(_mm_cvttss_si32(_mm_set_ss(s)));
      fl = tr > s ? tr - 1.0f : tr;
    }
    s = s - fl;
  }
  s = s < 1.0f ? s : 1.0f;  // as MINPS: NaN -> 1
  return s > 0.0f ? s : 0.0f;
}

// wrap_pair on one column or row.
[[gnu::always_inline]] inline void wrap_pair1(int& i0, int& i1, int size, TexWrap w) {
  if (w == TexWrap::Repeat) {
    if (i0 < 0) i0 += size;
    if (i1 == size) i1 = 0;
  } else {
    if (i0 < 0) i0 = 0;
    if (i1 == size) i1 = size - 1;
  }
}

[[gnu::always_inline]] inline I4 load_texel(const std::uint8_t* base, int width, int i, int j) {
  std::int32_t bits;
  std::memcpy(&bits, base + (std::size_t(j) * width + i) * 4, 4);
  return _mm_cvtsi32_si128(bits);
}

// Texels x and y weighted by the low and high halves of p's lane 0: four int32 channel sums.
[[gnu::always_inline]] inline I4 pair1(I4 x, I4 y, I4 p) {
  return _mm_madd_epi16(_mm_unpacklo_epi8(_mm_unpacklo_epi8(x, y), _mm_setzero_si128()), p);
}

// One level's weighted texels; the level's (a, b) are lanes K, K + 1 of ab, its (i0, j0) ij[K],
// ij[K + 1].
template <int K>
[[gnu::always_inline]] inline I4 level1(const Texture& t, const Image& im, const std::int32_t* ij, V4 ab, int share) {
  int i0 = ij[K], j0 = ij[K + 1], i1 = i0 + 1, j1 = j0 + 1;
  wrap_pair1(i0, i1, im.width, t.wrap_s);
  wrap_pair1(j0, j1, im.height, t.wrap_t);
  // Weights in texel order 00, 10, 01, 11: (1-a)(1-b), a(1-b), (1-a)b, ab, as in level4.
  const V4 nab = _mm_sub_ps(splat(1.0f), ab);
  const V4 src = K == 0 ? _mm_unpacklo_ps(nab, ab) : _mm_unpackhi_ps(nab, ab);  // (1-a, a, 1-b, b)
  const V4 w = _mm_mul_ps(_mm_shuffle_ps(src, src, _MM_SHUFFLE(1, 0, 1, 0)), _mm_shuffle_ps(src, src, _MM_SHUFFLE(3, 3, 2, 2)));
  // w11 = share - w00 - w10 - w01 into lane 3 (in registers: a store and reload would stall).
  const I4 wr = weight(w, splat(float(share)));
  const I4 sum3 = _mm_add_epi32(_mm_add_epi32(wr, _mm_srli_si128(wr, 4)), _mm_srli_si128(wr, 8));  // lane 0
  const I4 w11 = _mm_slli_si128(_mm_sub_epi32(_mm_cvtsi32_si128(share), sum3), 12);
  const I4 wi = _mm_or_si128(_mm_and_si128(wr, _mm_set_epi32(0, -1, -1, -1)), w11);
  const I4 p = _mm_packs_epi32(wi, _mm_setzero_si128());  // 16-bit lane 0: 00|10, lane 1: 01|11
  const std::uint8_t* base = im.rgba.data();
  const I4 r0 = pair1(load_texel(base, im.width, i0, j0), load_texel(base, im.width, i1, j0), _mm_shuffle_epi32(p, 0x00));
  const I4 r1 = pair1(load_texel(base, im.width, i0, j1), load_texel(base, im.width, i1, j1), _mm_shuffle_epi32(p, 0x55));
  return _mm_add_epi32(r0, r1);
}

// A level's nearest texel, weighted.
[[gnu::always_inline]] inline I4 nearest1(const Image& im, float ws, float wt, int share) {
  int i = _mm_cvttss_si32(_mm_set_ss(ws * float(im.width))), j = _mm_cvttss_si32(_mm_set_ss(wt * float(im.height)));
  if (i == im.width) --i;
  if (j == im.height) --j;
  const I4 x = load_texel(im.rgba.data(), im.width, i, j);
  return pair1(x, x, _mm_set1_epi32(share));  // weight in the low halves, 0 in the high ones
}

V4 sample_one(const Texture& t, const Plan& p, float s, float tt) {
  const float ws = wrap1(s, t.wrap_s), wt = wrap1(tt, t.wrap_t);
  const Image& l0 = t.levels[p.l0];
  I4 sum;
  if (!p.linear) {
    sum = nearest1(l0, ws, wt, p.share0);
    if (p.l1 >= 0) sum = _mm_add_epi32(sum, nearest1(t.levels[p.l1], ws, wt, p.share1));
  } else {
    const Image& l1 = t.levels[p.l1 >= 0 ? p.l1 : p.l0];
    const V4 dims = _mm_cvtepi32_ps(_mm_set_epi32(l1.height, l1.width, l0.height, l0.width));
    const V4 uvf = _mm_sub_ps(_mm_mul_ps(_mm_set_ps(wt, ws, wt, ws), dims), splat(0.5f));
    const V4 fl = floor4(uvf);
    alignas(16) std::int32_t ij[4];
    _mm_store_si128(reinterpret_cast<I4*>(ij), _mm_cvttps_epi32(fl));
    const V4 ab = _mm_sub_ps(uvf, fl);  // (a0, b0, a1, b1)
    sum = level1<0>(t, l0, ij, ab, p.share0);
    if (p.l1 >= 0) sum = _mm_add_epi32(sum, level1<2>(t, l1, ij, ab, p.share1));
  }
  return to_colour(sum, t.format);
}

// ---------------------------------------------------------------------------------------------
// AVX2: both levels of a trilinear quad in one 256-bit register (lanes 0-3 level d, 4-7 level
// d + 1), the same float operations lane for lane as level4 (no FMA), the same exact integer sums.
// Quads of one bilinear level take the same code with an empty second level.

using V8 = __m256;
using I8 = __m256i;

#define WEDGE_AVX2 __attribute__((target("avx2"), always_inline)) inline

// wrap4 with SSE4.1's floor (the same value: floor4 is exact below 2^23 and the identity above,
// a NaN or infinity becomes 1 either way, and floor(-0) = -0 against floor4's +0 only changes the
// sign of a zero that MAXPS then replaces by +0).
WEDGE_AVX2 V4 wrap4_avx2(V4 s, TexWrap w) {
  if (w == TexWrap::Repeat) s = _mm_sub_ps(s, _mm_floor_ps(s));
  return _mm_max_ps(_mm_min_ps(s, splat(1.0f)), _mm_setzero_ps());
}

// wrap_pair on eight lanes.
WEDGE_AVX2 void wrap_pair8(I8& i0, I8& i1, I8 size, TexWrap w) {
  const I8 lo = _mm256_cmpgt_epi32(_mm256_setzero_si256(), i0), up = _mm256_cmpeq_epi32(i1, size);
  if (w == TexWrap::Repeat) {
    i0 = _mm256_add_epi32(i0, _mm256_and_si256(lo, size));
    i1 = _mm256_sub_epi32(i1, _mm256_and_si256(up, size));
  } else {
    i0 = _mm256_sub_epi32(i0, lo);
    i1 = _mm256_add_epi32(i1, up);
  }
}

// Texels of lanes 0-3 from level image b0, of lanes 4-7 from b1 (Two) or zero (one level).
template <bool Two>
WEDGE_AVX2 I8 gather8(const int* b0, const int* b1, I8 index) {
  const I4 x0 = _mm_i32gather_epi32(b0, _mm256_castsi256_si128(index), 4);
  if (!Two) return _mm256_zextsi128_si256(x0);
  const I4 x1 = _mm_i32gather_epi32(b1, _mm256_extracti128_si256(index, 1), 4);
  return _mm256_set_m128i(x1, x0);
}

// add_pair on both levels: acc[k] gets fragment k's level-d sums in its low half, level d + 1's
// in its high half.
WEDGE_AVX2 void add_pair8(I8 x, I8 y, I8 p, I8* acc) {
  const I8 zero = _mm256_setzero_si256();
  const I8 lo = _mm256_unpacklo_epi8(x, y), hi = _mm256_unpackhi_epi8(x, y);
  acc[0] = _mm256_add_epi32(acc[0], _mm256_madd_epi16(_mm256_unpacklo_epi8(lo, zero), _mm256_shuffle_epi32(p, 0x00)));
  acc[1] = _mm256_add_epi32(acc[1], _mm256_madd_epi16(_mm256_unpackhi_epi8(lo, zero), _mm256_shuffle_epi32(p, 0x55)));
  acc[2] = _mm256_add_epi32(acc[2], _mm256_madd_epi16(_mm256_unpacklo_epi8(hi, zero), _mm256_shuffle_epi32(p, 0xaa)));
  acc[3] = _mm256_add_epi32(acc[3], _mm256_madd_epi16(_mm256_unpackhi_epi8(hi, zero), _mm256_shuffle_epi32(p, 0xff)));
}

// One row of a level's footprints with adjacent columns: texel pairs by 8-byte gather, bytes
// interleaved per channel (inter), fragments 0 and 2 widened into one register and weighted by
// their pairs of p (lanes 4 level + k), 1 and 3 into the other.
WEDGE_AVX2 void row8(const int* base, I4 index, I8 p, int level, I8 inter, I8& acc02, I8& acc13) {
  const I8 zero = _mm256_setzero_si256();
  const I8 x = _mm256_shuffle_epi8(_mm256_i32gather_epi64(reinterpret_cast<const long long*>(base), index, 4), inter);
  const int k = 4 * level;
  const I8 k02 = _mm256_setr_epi32(k, k, k, k, k + 2, k + 2, k + 2, k + 2);
  const I8 k13 = _mm256_setr_epi32(k + 1, k + 1, k + 1, k + 1, k + 3, k + 3, k + 3, k + 3);
  acc02 = _mm256_add_epi32(acc02, _mm256_madd_epi16(_mm256_unpacklo_epi8(x, zero), _mm256_permutevar8x32_epi32(p, k02)));
  acc13 = _mm256_add_epi32(acc13, _mm256_madd_epi16(_mm256_unpackhi_epi8(x, zero), _mm256_permutevar8x32_epi32(p, k13)));
}

// to_colour for two RGBA fragments.
WEDGE_AVX2 V8 to_colour8(I8 sum) {
  const V8 c = _mm256_mul_ps(_mm256_cvtepi32_ps(sum), _mm256_set1_ps(kOutScale));
  return _mm256_min_ps(_mm256_max_ps(c, _mm256_setzero_ps()), _mm256_set1_ps(1.0f));
}

WEDGE_AVX2 I8 weight8(V8 w, V8 share) { return _mm256_cvtps_epi32(_mm256_mul_ps(w, share)); }

// Two = false: one level with bilinear filtering, in lanes 0-3 (lanes 4-7 repeat the level with
// share 0 and no texels, so they add nothing).
template <bool Two>
WEDGE_AVX2 void bilinear_avx2(const Texture& t, const Plan& p, const float* s, const float* tt, float* out) {
  const V4 ws4 = wrap4_avx2(_mm_loadu_ps(s), t.wrap_s), wt4 = wrap4_avx2(_mm_loadu_ps(tt), t.wrap_t);
  const V8 ws = _mm256_set_m128(ws4, ws4), wt = _mm256_set_m128(wt4, wt4);
  const Image& l0 = t.levels[p.l0];
  const Image& l1 = t.levels[Two ? p.l1 : p.l0];
  const I8 wi = _mm256_set_m128i(_mm_set1_epi32(l1.width), _mm_set1_epi32(l0.width));
  const I8 hi = _mm256_set_m128i(_mm_set1_epi32(l1.height), _mm_set1_epi32(l0.height));
  const V8 half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f);
  const V8 uf = _mm256_sub_ps(_mm256_mul_ps(ws, _mm256_cvtepi32_ps(wi)), half);
  const V8 vf = _mm256_sub_ps(_mm256_mul_ps(wt, _mm256_cvtepi32_ps(hi)), half);
  const V8 fu = _mm256_floor_ps(uf), fv = _mm256_floor_ps(vf);  // as floor4: exact, uf and vf > -1
  const V8 a = _mm256_sub_ps(uf, fu), b = _mm256_sub_ps(vf, fv);
  const I8 ione = _mm256_set1_epi32(1);
  I8 i0 = _mm256_cvttps_epi32(fu), j0 = _mm256_cvttps_epi32(fv);
  I8 i1 = _mm256_add_epi32(i0, ione), j1 = _mm256_add_epi32(j0, ione);
  wrap_pair8(i0, i1, wi, t.wrap_s);
  wrap_pair8(j0, j1, hi, t.wrap_t);
  const V8 na = _mm256_sub_ps(one, a), nb = _mm256_sub_ps(one, b);
  const I8 si = _mm256_set_m128i(_mm_set1_epi32(p.share1), _mm_set1_epi32(p.share0));
  const V8 g = _mm256_cvtepi32_ps(si);
  const I8 w00 = weight8(_mm256_mul_ps(na, nb), g), w10 = weight8(_mm256_mul_ps(a, nb), g),
           w01 = weight8(_mm256_mul_ps(na, b), g);
  const I8 w11 = _mm256_sub_epi32(_mm256_sub_epi32(_mm256_sub_epi32(si, w00), w10), w01);
  const I8 r0 = _mm256_madd_epi16(j0, wi), r1 = _mm256_madd_epi16(j1, wi);
  const int* b0 = reinterpret_cast<const int*>(l0.rgba.data());
  const int* b1 = reinterpret_cast<const int*>(l1.rgba.data());
  const I8 p0 = _mm256_or_si256(w00, _mm256_slli_epi32(w10, 16)), p1 = _mm256_or_si256(w01, _mm256_slli_epi32(w11, 16));
  I8 s01, s23;
  const I8 adjacent = _mm256_cmpeq_epi32(i1, _mm256_add_epi32(i0, ione));
  if ((_mm256_movemask_ps(_mm256_castsi256_ps(adjacent)) | (Two ? 0 : 0xf0)) == 0xff) {
    // Columns i0 and i0 + 1 are neighbours in memory in every lane (no wrap or edge clamp): each
    // row's two texels come in one 8-byte gather, channel bytes interleaved by one shuffle,
    // widened; fragments 0 and 2 share one register, 1 and 3 another, with their weight pairs
    // picked by vpermd (lane 4L + k is fragment k of level L).
    const I8 inter = _mm256_setr_epi8(0, 4, 1, 5, 2, 6, 3, 7, 8, 12, 9, 13, 10, 14, 11, 15, 0, 4, 1, 5, 2, 6, 3, 7, 8,
                                      12, 9, 13, 10, 14, 11, 15);
    const I8 zero = _mm256_setzero_si256();
    I8 acc02 = zero, acc13 = zero;
    const I8 o0 = _mm256_add_epi32(r0, i0), o1 = _mm256_add_epi32(r1, i0);
    row8(b0, _mm256_castsi256_si128(o0), p0, 0, inter, acc02, acc13);
    row8(b0, _mm256_castsi256_si128(o1), p1, 0, inter, acc02, acc13);
    if (Two) {
      row8(b1, _mm256_extracti128_si256(o0, 1), p0, 1, inter, acc02, acc13);
      row8(b1, _mm256_extracti128_si256(o1, 1), p1, 1, inter, acc02, acc13);
    }
    s01 = _mm256_permute2x128_si256(acc02, acc13, 0x20), s23 = _mm256_permute2x128_si256(acc02, acc13, 0x31);
  } else {
    const I8 t00 = gather8<Two>(b0, b1, _mm256_add_epi32(r0, i0)), t10 = gather8<Two>(b0, b1, _mm256_add_epi32(r0, i1));
    const I8 t01 = gather8<Two>(b0, b1, _mm256_add_epi32(r1, i0)), t11 = gather8<Two>(b0, b1, _mm256_add_epi32(r1, i1));
    I8 acc[4] = {_mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256(), _mm256_setzero_si256()};
    add_pair8(t00, t10, p0, acc);
    add_pair8(t01, t11, p1, acc);
    // Level sums added and two fragments' colours per register.
    s01 = _mm256_add_epi32(_mm256_permute2x128_si256(acc[0], acc[1], 0x20), _mm256_permute2x128_si256(acc[0], acc[1], 0x31));
    s23 = _mm256_add_epi32(_mm256_permute2x128_si256(acc[2], acc[3], 0x20), _mm256_permute2x128_si256(acc[2], acc[3], 0x31));
  }
  if (t.format == TexFormat::RGBA) {
    _mm256_storeu_ps(out, to_colour8(s01));
    _mm256_storeu_ps(out + 8, to_colour8(s23));
  } else {
    _mm_storeu_ps(out, to_colour(_mm256_castsi256_si128(s01), t.format));
    _mm_storeu_ps(out + 4, to_colour(_mm256_extracti128_si256(s01, 1), t.format));
    _mm_storeu_ps(out + 8, to_colour(_mm256_castsi256_si128(s23), t.format));
    _mm_storeu_ps(out + 12, to_colour(_mm256_extracti128_si256(s23, 1), t.format));
  }
}

// sample4 on a CPU with AVX2: the plan, then the AVX2 kernel inlined (nearest filters: SSE2).
__attribute__((target("avx2"))) void sample4_avx2(const Texture& t, const float* s, const float* tt, float lambda,
                                                  float* out) {
  // The common case first: trilinear between two levels (make_plan's result, fewer branches).
  const int last = int(t.levels.size()) - 1;
  if (t.min_filter == TexFilter::LinearMipmapLinear && lambda > 0 && lambda < float(last) &&
      t.wrap_s != TexWrap::Clamp && t.wrap_t != TexWrap::Clamp && t.levels[0].width < 32768 &&
      t.levels[0].height < 32768) {
    Plan p;
    p.l0 = int(lambda), p.l1 = p.l0 + 1, p.linear = true;
    p.f = lambda - p.l0;
    p.share1 = _mm_cvtss_si32(_mm_set_ss(p.f * 16384.0f));
    p.share0 = 16384 - p.share1;
    return bilinear_avx2<true>(t, p, s, tt, out);
  }
  const Plan p = make_plan(t, lambda);
  if (!fast_ok(t, p)) return sample4_general(t, p, s, tt, out);
  if (!p.linear) return sample_sse(t, p, s, tt, out);
  if (p.l1 >= 0) bilinear_avx2<true>(t, p, s, tt, out);
  else bilinear_avx2<false>(t, p, s, tt, out);
}

}  // namespace

void Texture::build_mipmaps() {
  if (levels.empty()) fail("texture has no image");
  levels.resize(1);
  while (levels.back().width > 1 || levels.back().height > 1) {
    const Image& a = levels.back();
    Image b;
    b.width = std::max(1, a.width / 2), b.height = std::max(1, a.height / 2);
    b.rgba.resize(std::size_t(b.width) * b.height * 4);
    for (int y = 0; y < b.height; ++y)
      for (int x = 0; x < b.width; ++x)
        for (int k = 0; k < 4; ++k) {
          int sum = 0, cnt = 0;
          for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
              int sx = std::min(2 * x + dx, a.width - 1), sy = std::min(2 * y + dy, a.height - 1);
              sum += a.rgba[(std::size_t(sy) * a.width + sx) * 4 + k], ++cnt;
            }
          b.rgba[(std::size_t(y) * b.width + x) * 4 + k] = std::uint8_t((sum + cnt / 2) / cnt);
        }
    levels.push_back(std::move(b));
  }
}

std::shared_ptr<Texture> Texture::from_image(const Image& image, TexFormat format, bool mipmaps) {
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() != std::size_t(image.width) * image.height * 4)
    fail("texture image is empty or its pixel array does not match ", image.width, "x", image.height);
  auto t = std::make_shared<Texture>();
  t->format = format;
  t->levels.push_back(image);
  if (mipmaps) t->build_mipmaps();
  else t->min_filter = TexFilter::Linear;
  return t;
}

std::shared_ptr<Texture> Texture::checker(int size, int n, const Vec4f& a, const Vec4f& b, bool mipmaps) {
  if (size < 1 || size > 4096) fail("checker texture size ", size, " must be within 1..4096");
  if (n < 1 || n > size) fail("checker squares ", n, " must be within 1..", size);
  Image im;
  im.width = im.height = size;
  im.rgba.resize(std::size_t(size) * size * 4);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      bool odd = ((x * n / size) + (y * n / size)) % 2;
      const Vec4f& c = odd ? b : a;
      for (int k = 0; k < 4; ++k)
        im.rgba[(std::size_t(y) * size + x) * 4 + k] = std::uint8_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255));
    }
  return from_image(im, TexFormat::RGBA, mipmaps);
}

std::shared_ptr<Texture> Texture::load_png(const std::string& path, TexFormat format, bool mipmaps) {
  // At most 8192 x 8192 texels (with its mipmaps, some 350 MB): a 1 MB PNG decoding to 16384 x
  // 16384 took 3.5 GB and 30 s for a 16 x 16 render.
  Image im = read_png(path, std::size_t(kMaxTextureSide) * kMaxTextureSide);
  // PNG rows run top to bottom; texture rows run from t = 0 upward (swapped in place).
  const std::size_t row = std::size_t(im.width) * 4;
  for (int y = 0; y < im.height / 2; ++y)
    std::swap_ranges(im.rgba.begin() + std::ptrdiff_t(y * row), im.rgba.begin() + std::ptrdiff_t((y + 1) * row),
                     im.rgba.begin() + std::ptrdiff_t((im.height - 1 - y) * row));
  return from_image(im, format, mipmaps);
}

Vec4f Texture::sample(float s, float t, float lambda) const {
  Vec4f c;
  const Plan p = make_plan(*this, lambda);
  _mm_storeu_ps(c.data(), fast_ok(*this, p) ? sample_one(*this, p, s, t) : sample_general(*this, s, t, p));
  return c;
}

void Texture::sample4(const float* s, const float* t, float lambda, float* out, Simd simd) const {
  if (simd == Simd::Auto && cpu_has_avx2()) return sample4_avx2(*this, s, t, lambda, out);
  const Plan p = make_plan(*this, lambda);
  if (!fast_ok(*this, p)) return sample4_general(*this, p, s, t, out);
  sample_sse(*this, p, s, t, out);
}

}  // namespace wedge::render
