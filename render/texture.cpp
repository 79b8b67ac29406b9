// Textures as OpenGL 1.x samples them (GL 1.5 spec section 3.8.8): wrap modes repeat, clamp
// (texel coordinates clamped to [0, 1], so linear filtering at the edge blends with the border
// colour) and clamp-to-edge; magnification nearest/linear; minification nearest/linear and the
// four mipmap filters, choosing the level d = lambda (nearest level: round, as the spec's
// ceil(lambda + 1/2) - 1) or blending the two levels around it. The mipmap chain is built by
// 2x2 box filtering (what gluBuild2DMipmaps does for power-of-two images).
//
// Sampling: sample4() runs four fragments at once, one fragment per SIMD lane (structure of
// arrays): the wrapped coordinates, texel indices and bilinear weights of all four in one register
// each, the texels fetched by index, each channel filtered in float on its own register. sample()
// takes one fragment with the four channels in one register, and applies exactly the float
// operations the four-lane path applies to that fragment's lane, in the same order, so the two
// agree bit for bit (tests/render/test_texture.cpp checks it). The base path is SSE2 (part of
// x86-64); trilinear quads take an AVX2 path when the CPU has it (chosen at run time), which puts
// both mip levels in one 256-bit register with the same operations lane for lane (no FMA), so the
// results do not depend on the CPU either. GL_CLAMP (border colour) and images of 32768 texels or
// more a side take a per-fragment general path.
#include <atomic>
#include <cmath>
#include <cstring>

#include <immintrin.h>

#include "render/render.h"

namespace wedge::render {

namespace {

using V4 = __m128;
using I4 = __m128i;

// Loops over the channels of a colour, unrolled (the per-channel registers then stay registers).
#define WEDGE_UNROLL _Pragma("GCC unroll 4")

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

float wrap_coord(float s, TexWrap w) {
  if (w == TexWrap::Repeat) return s - std::floor(s);
  return std::clamp(s, 0.0f, 1.0f);
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
};

Plan make_plan(const Texture& t, float lambda) {
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
        p.l0 = int(std::floor(lambda)), p.l1 = p.l0 + 1;
        p.f = lambda - p.l0;
      }
      break;
  }
  return p;
}

V4 sample_general(const Texture& t, float s, float tt, const Plan& p) {
  const float ws = wrap_coord(s, t.wrap_s), wt = wrap_coord(tt, t.wrap_t);
  const V4 c0 = sample_level(t, p.l0, ws, wt, p.linear);
  if (p.l1 < 0) return c0;
  const V4 c1 = sample_level(t, p.l1, ws, wt, p.linear);
  return _mm_add_ps(_mm_mul_ps(splat(1 - p.f), c0), _mm_mul_ps(splat(p.f), c1));
}

// ---------------------------------------------------------------------------------------------
// Fast path: one fragment per lane. Channels are filtered as texel bytes (0..255) in float and
// scaled by 1/255 at the end, so a nearest sample is exactly byte * (1/255).

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

// The first C channels of four RGBA8 texels as floats 0..255, one register per channel.
template <int C>
[[gnu::always_inline]] inline void channels(I4 x, V4* c) {
  const I4 m = _mm_set1_epi32(0xff);
  c[0] = _mm_cvtepi32_ps(_mm_and_si128(x, m));
  if (C > 1) c[1] = _mm_cvtepi32_ps(_mm_and_si128(_mm_srli_epi32(x, 8), m));
  if (C > 2) c[2] = _mm_cvtepi32_ps(_mm_and_si128(_mm_srli_epi32(x, 16), m));
  if (C > 3) c[3] = _mm_cvtepi32_ps(_mm_srli_epi32(x, 24));
}

// Texel index j * width + i; i, j, width below 2^15 (one multiply-add of 16-bit halves).
[[gnu::always_inline]] inline I4 index(I4 i, I4 j, I4 width) { return _mm_add_epi32(_mm_madd_epi16(j, width), i); }

// One level at the wrapped coordinates of four fragments: C channel sums in texel units.
template <int C>
[[gnu::always_inline]] inline void level4(const Texture& t, const Image& im, bool linear, V4 ws, V4 wt, V4* out) {
  const I4 wi = _mm_set1_epi32(im.width), hi = _mm_set1_epi32(im.height);
  const V4 wf = _mm_cvtepi32_ps(wi), hf = _mm_cvtepi32_ps(hi);
  const std::uint8_t* base = im.rgba.data();
  const V4 u = _mm_mul_ps(ws, wf), v = _mm_mul_ps(wt, hf);
  if (!linear) {
    // u, v in [0, size]: truncation is the floor; size itself is the last texel.
    I4 i = _mm_cvttps_epi32(u), j = _mm_cvttps_epi32(v);
    i = _mm_add_epi32(i, _mm_cmpeq_epi32(i, wi)), j = _mm_add_epi32(j, _mm_cmpeq_epi32(j, hi));
    channels<C>(gather(base, index(i, j, wi)), out);
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
  const V4 w00 = _mm_mul_ps(na, nb), w10 = _mm_mul_ps(a, nb), w01 = _mm_mul_ps(na, b), w11 = _mm_mul_ps(a, b);
  const I4 r0 = _mm_madd_epi16(j0, wi), r1 = _mm_madd_epi16(j1, wi);
  V4 c[C];
  channels<C>(gather(base, _mm_add_epi32(r0, i0)), c);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) out[k] = _mm_mul_ps(w00, c[k]);
  channels<C>(gather(base, _mm_add_epi32(r0, i1)), c);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) out[k] = _mm_add_ps(out[k], _mm_mul_ps(w10, c[k]));
  channels<C>(gather(base, _mm_add_epi32(r1, i0)), c);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) out[k] = _mm_add_ps(out[k], _mm_mul_ps(w01, c[k]));
  channels<C>(gather(base, _mm_add_epi32(r1, i1)), c);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) out[k] = _mm_add_ps(out[k], _mm_mul_ps(w11, c[k]));
}

// Channel sums (C registers, texel units) to four RGBA colours: scale by 1/255, expand the format
// (luminance to grey, alpha 1 unless RGBA), transpose to one colour per fragment.
template <int C>
[[gnu::always_inline]] inline void finish(V4* c, float* out) {
  const V4 k = splat(1.0f / 255.0f);
  V4 r = _mm_mul_ps(c[0], k), g = r, b = r, a = splat(1.0f);
  if (C > 1) g = _mm_mul_ps(c[1], k), b = _mm_mul_ps(c[2], k);
  if (C > 3) a = _mm_mul_ps(c[3], k);
  const V4 rg0 = _mm_unpacklo_ps(r, g), ba0 = _mm_unpacklo_ps(b, a);
  _mm_storeu_ps(out, _mm_movelh_ps(rg0, ba0));
  _mm_storeu_ps(out + 4, _mm_movehl_ps(ba0, rg0));
  const V4 rg1 = _mm_unpackhi_ps(r, g), ba1 = _mm_unpackhi_ps(b, a);
  _mm_storeu_ps(out + 8, _mm_movelh_ps(rg1, ba1));
  _mm_storeu_ps(out + 12, _mm_movehl_ps(ba1, rg1));
}

// The level blend (1 - f) c0 + f c1 of each channel.
template <int C>
[[gnu::always_inline]] inline void blend(V4* c0, const V4* c1, float f) {
  const V4 nf = splat(1 - f), ff = splat(f);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) c0[k] = _mm_add_ps(_mm_mul_ps(nf, c0[k]), _mm_mul_ps(ff, c1[k]));
}

template <int C>
void sample_sse(const Texture& t, const Plan& p, V4 s, V4 tt, float* out) {
  const V4 ws = wrap4(s, t.wrap_s), wt = wrap4(tt, t.wrap_t);
  V4 c0[C];
  level4<C>(t, t.levels[p.l0], p.linear, ws, wt, c0);
  if (p.l1 >= 0) {
    V4 c1[C];
    level4<C>(t, t.levels[p.l1], p.linear, ws, wt, c1);
    blend<C>(c0, c1, p.f);
  }
  finish<C>(c0, out);
}

int channel_count(TexFormat f) { return f == TexFormat::RGBA ? 4 : f == TexFormat::RGB ? 3 : 1; }

// ---------------------------------------------------------------------------------------------
// One fragment (sample()): the four channels of a colour in one register, both levels' texel
// coordinates in one register (s W0, t H0, s W1, t H1). Every float operation is the one the
// four-lane path applies to that fragment's lane, in the same order, so the results are the same
// bits: IEEE single operations give the same result in any lane or register.

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
  s = s < 1.0f ? s : 1.0f;  // MINPS: NaN -> 1
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

// Texel (i, j) as four floats 0..255.
[[gnu::always_inline]] inline V4 texel1(const std::uint8_t* base, int width, int i, int j) {
  std::int32_t bits;
  std::memcpy(&bits, base + (std::size_t(j) * width + i) * 4, 4);
  const I4 zero = _mm_setzero_si128();
  return _mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(bits), zero), zero));
}

// Texels (i0, j) and (i1, j): one 8-byte load when they are neighbours in memory.
[[gnu::always_inline]] inline void texel_pair1(const std::uint8_t* base, int width, int i0, int i1, int j, V4& c0,
                                               V4& c1) {
  if (i1 != i0 + 1) {
    c0 = texel1(base, width, i0, j), c1 = texel1(base, width, i1, j);
    return;
  }
  std::int64_t bits;
  std::memcpy(&bits, base + (std::size_t(j) * width + i0) * 4, 8);
  const I4 zero = _mm_setzero_si128();
  const I4 x = _mm_unpacklo_epi8(_mm_cvtsi64_si128(bits), zero);
  c0 = _mm_cvtepi32_ps(_mm_unpacklo_epi16(x, zero));
  c1 = _mm_cvtepi32_ps(_mm_unpackhi_epi16(x, zero));
}

// One level's filtered colour (texel units); uv, fl, ab: this level's two lanes of the shared
// registers are lanes k, k + 1.
template <int K>
[[gnu::always_inline]] inline V4 level1(const Texture& t, const Image& im, const std::int32_t* ij, V4 ab) {
  int i0 = ij[K], j0 = ij[K + 1], i1 = i0 + 1, j1 = j0 + 1;
  wrap_pair1(i0, i1, im.width, t.wrap_s);
  wrap_pair1(j0, j1, im.height, t.wrap_t);
  // Weights in texel order 00, 10, 01, 11: (1-a)(1-b), a(1-b), (1-a)b, ab, as in level4.
  const V4 nab = _mm_sub_ps(splat(1.0f), ab);
  const V4 src = K == 0 ? _mm_unpacklo_ps(nab, ab) : _mm_unpackhi_ps(nab, ab);  // (1-a, a, 1-b, b)
  const V4 w = _mm_mul_ps(_mm_shuffle_ps(src, src, _MM_SHUFFLE(1, 0, 1, 0)), _mm_shuffle_ps(src, src, _MM_SHUFFLE(3, 3, 2, 2)));
  const std::uint8_t* base = im.rgba.data();
  V4 c00, c10, c01, c11;
  texel_pair1(base, im.width, i0, i1, j0, c00, c10);
  texel_pair1(base, im.width, i0, i1, j1, c01, c11);
  V4 r = _mm_mul_ps(_mm_shuffle_ps(w, w, 0x00), c00);
  r = _mm_add_ps(r, _mm_mul_ps(_mm_shuffle_ps(w, w, 0x55), c10));
  r = _mm_add_ps(r, _mm_mul_ps(_mm_shuffle_ps(w, w, 0xaa), c01));
  return _mm_add_ps(r, _mm_mul_ps(_mm_shuffle_ps(w, w, 0xff), c11));
}

// A level's nearest texel (texel units).
[[gnu::always_inline]] inline V4 nearest1(const Image& im, float ws, float wt) {
  int i = _mm_cvttss_si32(_mm_set_ss(ws * float(im.width))), j = _mm_cvttss_si32(_mm_set_ss(wt * float(im.height)));
  if (i == im.width) --i;
  if (j == im.height) --j;
  return texel1(im.rgba.data(), im.width, i, j);
}

template <int C>
V4 sample_one(const Texture& t, const Plan& p, float s, float tt) {
  const float ws = wrap1(s, t.wrap_s), wt = wrap1(tt, t.wrap_t);
  const Image& l0 = t.levels[p.l0];
  V4 c;
  if (!p.linear) {
    c = nearest1(l0, ws, wt);
    if (p.l1 >= 0) {
      const V4 c1 = nearest1(t.levels[p.l1], ws, wt);
      c = _mm_add_ps(_mm_mul_ps(splat(1 - p.f), c), _mm_mul_ps(splat(p.f), c1));
    }
  } else {
    const Image& l1 = t.levels[p.l1 >= 0 ? p.l1 : p.l0];
    const V4 dims = _mm_cvtepi32_ps(_mm_set_epi32(l1.height, l1.width, l0.height, l0.width));
    const V4 uvf = _mm_sub_ps(_mm_mul_ps(_mm_set_ps(wt, ws, wt, ws), dims), splat(0.5f));
    const V4 fl = floor4(uvf);
    alignas(16) std::int32_t ij[4];
    _mm_store_si128(reinterpret_cast<I4*>(ij), _mm_cvttps_epi32(fl));
    const V4 ab = _mm_sub_ps(uvf, fl);  // (a0, b0, a1, b1)
    c = level1<0>(t, l0, ij, ab);
    if (p.l1 >= 0) {
      const V4 c1 = level1<2>(t, l1, ij, ab);
      c = _mm_add_ps(_mm_mul_ps(splat(1 - p.f), c), _mm_mul_ps(splat(p.f), c1));
    }
  }
  c = _mm_mul_ps(c, splat(1.0f / 255.0f));
  if (C == 1) c = _mm_shuffle_ps(c, c, 0);
  if (C < 4) {
    const V4 rgb = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));
    c = _mm_or_ps(_mm_and_ps(c, rgb), _mm_andnot_ps(rgb, splat(1.0f)));
  }
  return c;
}

// ---------------------------------------------------------------------------------------------
// AVX2: the bilinear footprints of both levels of a trilinear quad in one 256-bit register (lanes
// 0-3 level d, 4-7 level d + 1), the same operations per lane as level4 and blend above.

using V8 = __m256;
using I8 = __m256i;

#define WEDGE_AVX2 __attribute__((target("avx2"), always_inline)) inline

// floor as floor4: truncate, step down where truncation rounded up.
WEDGE_AVX2 V8 floor8(V8 x) {
  const V8 tr = _mm256_cvtepi32_ps(_mm256_cvttps_epi32(x));
  return _mm256_sub_ps(tr, _mm256_and_ps(_mm256_cmp_ps(tr, x, _CMP_GT_OQ), _mm256_set1_ps(1.0f)));
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

// Texels of lanes 0-3 from level image b0, of lanes 4-7 from b1; channels as in channels().
template <int C>
WEDGE_AVX2 void fetch8(const int* b0, const int* b1, I8 index, V8* c) {
  const I4 x0 = _mm_i32gather_epi32(b0, _mm256_castsi256_si128(index), 4);
  const I4 x1 = _mm_i32gather_epi32(b1, _mm256_extracti128_si256(index, 1), 4);
  const I8 x = _mm256_set_m128i(x1, x0);
  const I8 m = _mm256_set1_epi32(0xff);
  c[0] = _mm256_cvtepi32_ps(_mm256_and_si256(x, m));
  if (C > 1) c[1] = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(x, 8), m));
  if (C > 2) c[2] = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(x, 16), m));
  if (C > 3) c[3] = _mm256_cvtepi32_ps(_mm256_srli_epi32(x, 24));
}

template <int C>
__attribute__((target("avx2"))) void trilinear_avx2(const Texture& t, const Plan& p, const float* s,
                                                     const float* tt, float* out) {
  const V4 ws4 = wrap4(_mm_loadu_ps(s), t.wrap_s), wt4 = wrap4(_mm_loadu_ps(tt), t.wrap_t);
  const V8 ws = _mm256_set_m128(ws4, ws4), wt = _mm256_set_m128(wt4, wt4);
  const Image& l0 = t.levels[p.l0];
  const Image& l1 = t.levels[p.l1];
  const I8 wi = _mm256_set_m128i(_mm_set1_epi32(l1.width), _mm_set1_epi32(l0.width));
  const I8 hi = _mm256_set_m128i(_mm_set1_epi32(l1.height), _mm_set1_epi32(l0.height));
  const V8 half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f);
  const V8 uf = _mm256_sub_ps(_mm256_mul_ps(ws, _mm256_cvtepi32_ps(wi)), half);
  const V8 vf = _mm256_sub_ps(_mm256_mul_ps(wt, _mm256_cvtepi32_ps(hi)), half);
  const V8 fu = floor8(uf), fv = floor8(vf);
  const V8 a = _mm256_sub_ps(uf, fu), b = _mm256_sub_ps(vf, fv);
  const I8 ione = _mm256_set1_epi32(1);
  I8 i0 = _mm256_cvttps_epi32(fu), j0 = _mm256_cvttps_epi32(fv);
  I8 i1 = _mm256_add_epi32(i0, ione), j1 = _mm256_add_epi32(j0, ione);
  wrap_pair8(i0, i1, wi, t.wrap_s);
  wrap_pair8(j0, j1, hi, t.wrap_t);
  const V8 na = _mm256_sub_ps(one, a), nb = _mm256_sub_ps(one, b);
  const V8 w00 = _mm256_mul_ps(na, nb), w10 = _mm256_mul_ps(a, nb), w01 = _mm256_mul_ps(na, b),
           w11 = _mm256_mul_ps(a, b);
  const I8 r0 = _mm256_madd_epi16(j0, wi), r1 = _mm256_madd_epi16(j1, wi);
  const int* b0 = reinterpret_cast<const int*>(l0.rgba.data());
  const int* b1 = reinterpret_cast<const int*>(l1.rgba.data());
  V8 acc[C], c[C];
  fetch8<C>(b0, b1, _mm256_add_epi32(r0, i0), c);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) acc[k] = _mm256_mul_ps(w00, c[k]);
  fetch8<C>(b0, b1, _mm256_add_epi32(r0, i1), c);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) acc[k] = _mm256_add_ps(acc[k], _mm256_mul_ps(w10, c[k]));
  fetch8<C>(b0, b1, _mm256_add_epi32(r1, i0), c);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) acc[k] = _mm256_add_ps(acc[k], _mm256_mul_ps(w01, c[k]));
  fetch8<C>(b0, b1, _mm256_add_epi32(r1, i1), c);
  WEDGE_UNROLL for (int k = 0; k < C; ++k) acc[k] = _mm256_add_ps(acc[k], _mm256_mul_ps(w11, c[k]));
  // Level blend: lanes 0-3 times 1 - f plus lanes 4-7 times f (blend's products, in its order).
  const V8 fw = _mm256_set_m128(splat(p.f), splat(1 - p.f));
  V4 r[C];
  WEDGE_UNROLL for (int k = 0; k < C; ++k) {
    const V8 x = _mm256_mul_ps(fw, acc[k]);
    r[k] = _mm_add_ps(_mm256_castps256_ps128(x), _mm256_extractf128_ps(x, 1));
  }
  finish<C>(r, out);
}

bool cpu_has_avx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

std::atomic<bool> g_avx2{cpu_has_avx2()};

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
  Image im = read_png(path);
  // PNG rows run top to bottom; texture rows run from t = 0 upward.
  Image flipped = im;
  const std::size_t row = std::size_t(im.width) * 4;
  for (int y = 0; y < im.height; ++y)
    std::memcpy(&flipped.rgba[y * row], &im.rgba[(im.height - 1 - y) * row], row);
  return from_image(flipped, format, mipmaps);
}

Vec4f Texture::sample(float s, float t, float lambda) const {
  Vec4f c;
  const Plan p = make_plan(*this, lambda);
  V4 r;
  if (!fast_ok(*this, p)) r = sample_general(*this, s, t, p);
  else if (format == TexFormat::RGBA) r = sample_one<4>(*this, p, s, t);
  else if (format == TexFormat::RGB) r = sample_one<3>(*this, p, s, t);
  else r = sample_one<1>(*this, p, s, t);
  _mm_storeu_ps(c.data(), r);
  return c;
}

void Texture::sample4(const float* s, const float* t, float lambda, float* out) const {
  const Plan p = make_plan(*this, lambda);
  if (!fast_ok(*this, p)) {
    for (int k = 0; k < 4; ++k) _mm_storeu_ps(out + 4 * k, sample_general(*this, s[k], t[k], p));
    return;
  }
  if (p.l1 >= 0 && p.linear && g_avx2.load(std::memory_order_relaxed)) {
    switch (channel_count(format)) {
      case 4: return trilinear_avx2<4>(*this, p, s, t, out);
      case 3: return trilinear_avx2<3>(*this, p, s, t, out);
      default: return trilinear_avx2<1>(*this, p, s, t, out);
    }
  }
  const V4 s4 = _mm_loadu_ps(s), t4 = _mm_loadu_ps(t);
  switch (channel_count(format)) {
    case 4: return sample_sse<4>(*this, p, s4, t4, out);
    case 3: return sample_sse<3>(*this, p, s4, t4, out);
    default: return sample_sse<1>(*this, p, s4, t4, out);
  }
}

bool Texture::allow_avx2(bool allow) {
  const bool on = allow && cpu_has_avx2();
  g_avx2.store(on);
  return on;
}

}  // namespace wedge::render
