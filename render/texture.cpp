// Textures as OpenGL 1.x samples them (GL 1.5 spec section 3.8.8): wrap modes repeat, clamp
// (texel coordinates clamped to [0, 1], so linear filtering at the edge blends with the border
// colour) and clamp-to-edge; magnification nearest/linear; minification nearest/linear and the
// four mipmap filters, choosing the level d = lambda (nearest level: round, as the spec's
// ceil(lambda + 1/2) - 1) or blending the two levels around it. The mipmap chain is built by
// 2x2 box filtering (what gluBuild2DMipmaps does for power-of-two images). Sampling runs on SSE2
// registers (one RGBA colour per register, both mip levels' coordinates in one register for
// trilinear) with the same float operations in the same order as the per-channel formulation, so
// the results are unchanged bit for bit; x86-64 is assumed (SSE2 is part of its base ISA).
#include <cmath>
#include <cstring>

#include <emmintrin.h>

#include "render/render.h"

namespace wedge::render {

namespace {

// Sampling works on one SSE register per colour (x86-64 always has SSE2): a texel's four bytes
// are widened to 32-bit integers and converted together, and the bilinear and mipmap blends run
// on all four channels at once. Every step keeps the scalar formulation's operations and their
// order (byte * (1/255), weights (1-a)(1-b), a(1-b), (1-a)b, ab, sums left to right), so the
// results are bit for bit those of per-channel float code.
using V4 = __m128;

inline V4 splat(float x) { return _mm_set1_ps(x); }

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
  const __m128i zero = _mm_setzero_si128();
  __m128i x = _mm_unpacklo_epi8(_mm_cvtsi32_si128(bits), zero);
  x = _mm_unpacklo_epi16(x, zero);
  return expand(_mm_mul_ps(_mm_cvtepi32_ps(x), splat(1.0f / 255.0f)), fmt);
}

// Texels (i0, j) and (i1, j): one 8-byte load when they are neighbours in memory (the usual case
// of a bilinear footprint that does not wrap), else two texel loads.
[[gnu::always_inline]] inline void texel_pair(const std::uint8_t* base, int width, TexFormat fmt, int i0, int i1,
                                              int j, V4& c0, V4& c1) {
  if (i1 != i0 + 1) {
    c0 = texel(base, width, fmt, i0, j), c1 = texel(base, width, fmt, i1, j);
    return;
  }
  std::int64_t bits;
  std::memcpy(&bits, base + (std::size_t(j) * width + i0) * 4, 8);
  const __m128i zero = _mm_setzero_si128();
  const __m128i x = _mm_unpacklo_epi8(_mm_cvtsi64_si128(bits), zero);
  const V4 k = splat(1.0f / 255.0f);
  c0 = expand(_mm_mul_ps(_mm_cvtepi32_ps(_mm_unpacklo_epi16(x, zero)), k), fmt);
  c1 = expand(_mm_mul_ps(_mm_cvtepi32_ps(_mm_unpackhi_epi16(x, zero)), k), fmt);
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

inline V4 load(const Vec4f& v) { return _mm_loadu_ps(v.data()); }

// One level sampled at wrapped coordinates (ws, wt) in [0, 1] (wrap_coord already applied).
[[gnu::always_inline]] inline V4 sample_level(const Texture& t, int level, float ws, float wt, bool linear) {
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
  V4 c00, c10, c01, c11;
  if (in_i0 && in_i1 && in_j0 && in_j1) {
    c00 = texel(base, w, t.format, i0, j0), c10 = texel(base, w, t.format, i1, j0);
    c01 = texel(base, w, t.format, i0, j1), c11 = texel(base, w, t.format, i1, j1);
  } else {
    const V4 border = load(t.border);
    c00 = in_i0 && in_j0 ? texel(base, w, t.format, i0, j0) : border;
    c10 = in_i1 && in_j0 ? texel(base, w, t.format, i1, j0) : border;
    c01 = in_i0 && in_j1 ? texel(base, w, t.format, i0, j1) : border;
    c11 = in_i1 && in_j1 ? texel(base, w, t.format, i1, j1) : border;
  }
  V4 r = _mm_mul_ps(splat((1 - a) * (1 - b)), c00);
  r = _mm_add_ps(r, _mm_mul_ps(splat(a * (1 - b)), c10));
  r = _mm_add_ps(r, _mm_mul_ps(splat((1 - a) * b), c01));
  return _mm_add_ps(r, _mm_mul_ps(splat(a * b), c11));
}

// floor of four floats with SSE2 alone: truncate, then step down where truncation rounded up.
inline V4 floor4(V4 x) {
  const V4 t = _mm_cvtepi32_ps(_mm_cvttps_epi32(x));
  return _mm_sub_ps(t, _mm_and_ps(_mm_cmpgt_ps(t, x), splat(1.0f)));
}

// A wrapped column or row index: repeat (by mask when the size is a power of two) or clamp to edge.
[[gnu::always_inline]] inline int wrap_fast(int i, int size, TexWrap w) {
  return w == TexWrap::Repeat ? wrap_repeat(i, size) : std::clamp(i, 0, size - 1);
}

// LINEAR_MIPMAP_LINEAR between levels d and d + 1 without GL_CLAMP borders: both levels' texel
// coordinates, floors and fractions in one register (s W0, t H0, s W1, t H1), then the eight
// texels. Same operations as two calls of sample_level and the level blend, in the same order.
[[gnu::always_inline]] inline V4 sample_trilinear(const Texture& t, int d, float ws, float wt, float f) {
  const Image& l0 = t.levels[d];
  const Image& l1 = t.levels[d + 1];
  const V4 dims = _mm_cvtepi32_ps(_mm_set_epi32(l1.height, l1.width, l0.height, l0.width));
  const V4 uv = _mm_mul_ps(_mm_set_ps(wt, ws, wt, ws), dims);
  const V4 uvf = _mm_sub_ps(uv, splat(0.5f));
  const V4 fl = floor4(uvf);
  alignas(16) std::int32_t ij[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(ij), _mm_cvttps_epi32(fl));
  const V4 ab = _mm_sub_ps(uvf, fl);           // (a0, b0, a1, b1)
  const V4 one_ab = _mm_sub_ps(splat(1.0f), ab);  // (1-a0, 1-b0, 1-a1, 1-b1)
  // Weights of level k in texel order 00, 10, 01, 11: (1-a)(1-b), a(1-b), (1-a)b, ab.
  auto weights = [&](int k) {
    const V4 a = _mm_unpacklo_ps(one_ab, ab);  // (1-a0, a0, 1-b0, b0)
    const V4 b = _mm_unpackhi_ps(one_ab, ab);  // (1-a1, a1, 1-b1, b1)
    const V4 src = k == 0 ? a : b;
    const V4 x = _mm_shuffle_ps(src, src, _MM_SHUFFLE(1, 0, 1, 0));
    const V4 y = _mm_shuffle_ps(src, src, _MM_SHUFFLE(3, 3, 2, 2));
    return _mm_mul_ps(x, y);
  };
  auto level = [&](const Image& im, int i0, int j0, V4 w) __attribute__((always_inline)) {
    const int iw = im.width, ih = im.height;
    const int i1 = wrap_fast(i0 + 1, iw, t.wrap_s), j1 = wrap_fast(j0 + 1, ih, t.wrap_t);
    i0 = wrap_fast(i0, iw, t.wrap_s), j0 = wrap_fast(j0, ih, t.wrap_t);
    const std::uint8_t* base = im.rgba.data();
    V4 c00, c10, c01, c11;
    texel_pair(base, iw, t.format, i0, i1, j0, c00, c10);
    texel_pair(base, iw, t.format, i0, i1, j1, c01, c11);
    V4 r = _mm_mul_ps(_mm_shuffle_ps(w, w, 0x00), c00);
    r = _mm_add_ps(r, _mm_mul_ps(_mm_shuffle_ps(w, w, 0x55), c10));
    r = _mm_add_ps(r, _mm_mul_ps(_mm_shuffle_ps(w, w, 0xaa), c01));
    return _mm_add_ps(r, _mm_mul_ps(_mm_shuffle_ps(w, w, 0xff), c11));
  };
  const V4 c0 = level(l0, ij[0], ij[1], weights(0)), c1 = level(l1, ij[2], ij[3], weights(1));
  return _mm_add_ps(_mm_mul_ps(splat(1 - f), c0), _mm_mul_ps(splat(f), c1));
}

[[gnu::always_inline]] inline V4 sample_v(const Texture& t, float s, float tt, float lambda) {
  const float ws = wrap_coord(s, t.wrap_s), wt = wrap_coord(tt, t.wrap_t);
  const TexFilter min_filter = t.min_filter;
  const bool mag = lambda <= 0 || t.levels.size() == 1;
  if (mag) {
    bool linear = (lambda <= 0 ? t.mag_filter : min_filter) == TexFilter::Linear;
    if (lambda > 0) linear = min_filter != TexFilter::Nearest && min_filter != TexFilter::NearestMipmapNearest &&
                             min_filter != TexFilter::NearestMipmapLinear;
    return sample_level(t, 0, ws, wt, linear);
  }
  const int last = int(t.levels.size()) - 1;
  switch (min_filter) {
    case TexFilter::Nearest: return sample_level(t, 0, ws, wt, false);
    case TexFilter::Linear: return sample_level(t, 0, ws, wt, true);
    case TexFilter::NearestMipmapNearest:
    case TexFilter::LinearMipmapNearest: {
      int d = lambda <= 0.5f ? 0 : std::min(last, int(std::ceil(lambda + 0.5f)) - 1);
      return sample_level(t, d, ws, wt, min_filter == TexFilter::LinearMipmapNearest);
    }
    case TexFilter::NearestMipmapLinear:
    case TexFilter::LinearMipmapLinear: {
      bool lin = min_filter == TexFilter::LinearMipmapLinear;
      if (lambda >= last) return sample_level(t, last, ws, wt, lin);
      int d1 = int(std::floor(lambda));
      float f = lambda - d1;
      if (lin && t.wrap_s != TexWrap::Clamp && t.wrap_t != TexWrap::Clamp) return sample_trilinear(t, d1, ws, wt, f);
      // Both levels share the wrapped coordinates computed above.
      V4 c0 = sample_level(t, d1, ws, wt, lin), c1 = sample_level(t, d1 + 1, ws, wt, lin);
      return _mm_add_ps(_mm_mul_ps(splat(1 - f), c0), _mm_mul_ps(splat(f), c1));
    }
  }
  return _mm_setzero_ps();
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
  _mm_storeu_ps(c.data(), sample_v(*this, s, t, lambda));
  return c;
}

void Texture::sample4(const float* s, const float* t, float lambda, float* out) const {
  for (int k = 0; k < 4; ++k) _mm_storeu_ps(out + 4 * k, sample_v(*this, s[k], t[k], lambda));
}

}  // namespace wedge::render
