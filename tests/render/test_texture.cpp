// Texture sampling: sample4 (four fragments sharing one level of detail) against four calls of
// sample(), bit for bit, over random coordinates and every format, wrap mode, filter and texture
// shape, on the AVX2 path and with the SSE2 fallback forced; the two paths against each other;
// every filter against the GL formulas in double precision; exact nearest and constant colours.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "simd_skip.h"
#include "render/render.h"

using namespace wedge;
using namespace wedge::render;

namespace {

std::shared_ptr<Texture> random_texture(std::mt19937& rng, int w, int h, TexFormat fmt, bool mipmaps) {
  Image im;
  im.width = w, im.height = h;
  im.rgba.resize(std::size_t(w) * h * 4);
  for (auto& b : im.rgba) b = std::uint8_t(rng() & 0xff);
  auto t = Texture::from_image(im, fmt, mipmaps);
  t->border = Vec4f(0.25f, 0.5f, 0.75f, 1.0f);
  return t;
}

// A coordinate: mostly within a few repeats of [0, 1], sometimes exactly on a texel edge or
// centre, sometimes far away, sometimes special (signed zeros, around 2^23 where floats stop
// having fractions, beyond 2^31, infinities, NaN, tiny).
float random_coord(std::mt19937& rng, int size) {
  std::uniform_real_distribution<float> u(-3.0f, 4.0f);
  const float special[] = {-0.0f, 0.0f, 1.0f, -1.0f, 8388607.5f, -8388607.5f, 8388608.0f, 3e9f, -3e9f, 1e30f,
                           std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                           std::numeric_limits<float>::quiet_NaN(), 0.99999994f, -1e-30f, 1e-30f};
  switch (rng() % 9) {
    case 8: return special[rng() % 16];
    case 0: return float(int(rng() % (4 * size)) - size) / size;                   // texel edge
    case 1: return (float(int(rng() % (4 * size)) - size) + 0.5f) / size;          // texel centre
    case 2: return std::uniform_real_distribution<float>(-300.0f, 300.0f)(rng);    // far
    case 3: return float(int(rng() % 7) - 3);                                      // integer
    default: return u(rng);
  }
}

float random_lambda(std::mt19937& rng) {
  switch (rng() % 6) {
    case 0: return float(int(rng() % 12) - 2);                         // integer
    case 1: return float(int(rng() % 24) - 4) * 0.5f;                  // half-integer
    case 2: return -100.0f;                                            // no derivative
    case 3: return rng() & 1 ? std::numeric_limits<float>::quiet_NaN() : 1e30f;
    default: return std::uniform_real_distribution<float>(-2.0f, 11.0f)(rng);
  }
}

// Compares sample4 with four sample() calls for `n` random quads; returns the number of mismatches.
int mismatches(const Texture& t, std::mt19937& rng, int n, Simd simd) {
  int bad = 0;
  const int size = t.levels[0].width;
  for (int q = 0; q < n; ++q) {
    float s[4], tt[4];
    // Half the quads are tight (as a 2x2 pixel quad is), half spread anywhere.
    const bool tight = rng() & 1;
    const float s0 = random_coord(rng, size), t0 = random_coord(rng, t.levels[0].height);
    std::uniform_real_distribution<float> d(-0.05f, 0.05f);
    for (int k = 0; k < 4; ++k) {
      s[k] = tight ? s0 + d(rng) : random_coord(rng, size);
      tt[k] = tight ? t0 + d(rng) : random_coord(rng, t.levels[0].height);
    }
    const float lambda = random_lambda(rng);
    float out[16];
    t.sample4(s, tt, lambda, out, simd);
    for (int k = 0; k < 16; ++k)
      if (!(out[k] >= 0.0f && out[k] <= 1.0f)) ++bad;  // in [0, 1] (the border colour is too)
    for (int k = 0; k < 4; ++k) {
      const Vec4f c = t.sample(s[k], tt[k], lambda);
      if (std::memcmp(c.data(), out + 4 * k, sizeof(float) * 4) != 0) {
        if (bad < 5)
          UNSCOPED_INFO("s " << s[k] << " t " << tt[k] << " lambda " << lambda << ": sample " << c.transpose()
                             << ", sample4 " << out[4 * k] << " " << out[4 * k + 1] << " " << out[4 * k + 2] << " "
                             << out[4 * k + 3]);
        ++bad;
      }
    }
  }
  return bad;
}


// Every format, wrap pair, filter and shape through sample4 and sample, once on each SIMD path
// (AVX2 when the CPU has it, and the SSE2 fallback forced).
void check_all_paths(bool avx2) {
  const bool on = avx2 && cpu_has_avx2();
  INFO("AVX2 path " << (on ? "on" : "off"));
  std::mt19937 rng(12345);
  const int shapes[][2] = {{256, 256}, {64, 32}, {16, 64}, {17, 9}, {1, 1}, {3, 1}, {8, 8}};
  const TexWrap wraps[] = {TexWrap::Repeat, TexWrap::Clamp, TexWrap::ClampToEdge};
  for (auto& sh : shapes)
    for (int fmt = 0; fmt < 3; ++fmt)
      for (int mip = 0; mip < 2; ++mip) {
        auto t = random_texture(rng, sh[0], sh[1], static_cast<TexFormat>(fmt), mip == 1);
        for (TexWrap ws : wraps)
          for (TexWrap wt : wraps)
            for (int minf = 0; minf < 6; ++minf)
              for (int magf = 0; magf < 2; ++magf) {
                t->wrap_s = ws, t->wrap_t = wt;
                t->min_filter = static_cast<TexFilter>(minf);
                t->mag_filter = static_cast<TexFilter>(magf);
                INFO("texture " << sh[0] << "x" << sh[1] << " format " << fmt << " mipmaps " << mip << " wrap "
                                << int(ws) << "/" << int(wt) << " min " << minf << " mag " << magf);
                CHECK(mismatches(*t, rng, 60, avx2 ? Simd::Auto : Simd::Sse2) == 0);
              }
      }
}

}  // namespace

TEST_CASE("sample4 equals four calls of sample, bit for bit, on the AVX2 and the SSE2 path", "[render][texture]") {
  check_all_paths(true);
  check_all_paths(false);
}

TEST_CASE("the AVX2 and SSE2 paths of sample4 give the same bits", "[render][texture]") {
  if (test::avx2_missing("sample4's AVX2 path")) return;
  std::mt19937 rng(777);
  for (int fmt = 0; fmt < 3; ++fmt) {
    auto t = random_texture(rng, 64, 128, static_cast<TexFormat>(fmt), true);
    t->min_filter = TexFilter::LinearMipmapLinear;
    for (TexWrap w : {TexWrap::Repeat, TexWrap::ClampToEdge}) {
      t->wrap_s = t->wrap_t = w;
      int bad = 0;
      for (int q = 0; q < 20000; ++q) {
        float s[4], tt[4], a[16], b[16];
        for (int k = 0; k < 4; ++k) s[k] = random_coord(rng, 64), tt[k] = random_coord(rng, 128);
        const float lambda = random_lambda(rng);
        t->sample4(s, tt, lambda, a, Simd::Auto);
        t->sample4(s, tt, lambda, b, Simd::Sse2);
        bad += std::memcmp(a, b, sizeof a) != 0;
      }
      CHECK(bad == 0);
    }
  }
}

// The GL 1.5 formulas in double precision (section 3.8.8), for one level.
static Vec4f reference_level(const Texture& t, int level, double s, double tc, bool linear) {
  const Image& im = t.levels[level];
  auto wrapc = [](double x, TexWrap w) { return w == TexWrap::Repeat ? x - std::floor(x) : std::clamp(x, 0.0, 1.0); };
  const double u = wrapc(s, t.wrap_s) * im.width, v = wrapc(tc, t.wrap_t) * im.height;
  auto tex = [&](int i, int j) -> Vec4f {
    auto fix = [](int i, int n, TexWrap w, bool& border) {
      if (w == TexWrap::Repeat) return ((i % n) + n) % n;
      if (w == TexWrap::ClampToEdge) return std::clamp(i, 0, n - 1);
      border = border || i < 0 || i >= n;
      return std::clamp(i, 0, n - 1);
    };
    bool border = false;
    i = fix(i, im.width, t.wrap_s, border), j = fix(j, im.height, t.wrap_t, border);
    if (border) return t.border;
    auto p = &im.rgba[(std::size_t(j) * im.width + i) * 4];
    Vec4f c(p[0] / 255.0f, p[1] / 255.0f, p[2] / 255.0f, p[3] / 255.0f);
    if (t.format == TexFormat::Luminance) c = Vec4f(c[0], c[0], c[0], 1);
    if (t.format == TexFormat::RGB) c[3] = 1;
    return c;
  };
  if (!linear) return tex(std::min(int(std::floor(u)), im.width - 1), std::min(int(std::floor(v)), im.height - 1));
  const int i0 = int(std::floor(u - 0.5)), j0 = int(std::floor(v - 0.5));
  const float a = float(u - 0.5 - i0), b = float(v - 0.5 - j0);
  return (1 - a) * (1 - b) * tex(i0, j0) + a * (1 - b) * tex(i0 + 1, j0) + (1 - a) * b * tex(i0, j0 + 1) +
         a * b * tex(i0 + 1, j0 + 1);
}

TEST_CASE("sampling follows the GL formulas (every filter and wrap mode)", "[render][texture]") {
  std::mt19937 rng(99);
  for (bool avx2 : {true, false}) {
    for (int fmt = 0; fmt < 3; ++fmt) {
      auto t = random_texture(rng, 32, 16, static_cast<TexFormat>(fmt), true);
      for (TexWrap w : {TexWrap::Repeat, TexWrap::Clamp, TexWrap::ClampToEdge})
        for (int minf = 0; minf < 6; ++minf) {
          t->wrap_s = t->wrap_t = w;
          t->min_filter = static_cast<TexFilter>(minf);
          const bool lin = minf == 1 || minf == 3 || minf == 5;
          double worst = 0;
          for (int q = 0; q < 2000; ++q) {
            // Coordinates away from texel edges by a margin (no float-vs-double floor flip).
            float s[4], tt[4], out[16];
            for (int k = 0; k < 4; ++k) {
              s[k] = float(std::uniform_int_distribution<int>(-64, 95)(rng) + 0.05 + 0.9 * std::uniform_real_distribution<double>()(rng)) / 32;
              tt[k] = float(std::uniform_int_distribution<int>(-32, 47)(rng) + 0.05 + 0.9 * std::uniform_real_distribution<double>()(rng)) / 16;
            }
            // Minified, between levels 1 and 2 (f away from 0 and 1).
            const float lambda = 1.1f + 0.8f * std::uniform_real_distribution<float>()(rng);
            t->sample4(s, tt, lambda, out, avx2 ? Simd::Auto : Simd::Sse2);
            for (int k = 0; k < 4; ++k) {
              Vec4f ref;
              if (minf == 0 || minf == 1) ref = reference_level(*t, 0, s[k], tt[k], lin);
              else if (minf == 2 || minf == 3) ref = reference_level(*t, int(std::ceil(lambda + 0.5f)) - 1, s[k], tt[k], lin);
              else {
                const float f = lambda - 1;
                ref = (1 - f) * reference_level(*t, 1, s[k], tt[k], lin) + f * reference_level(*t, 2, s[k], tt[k], lin);
              }
              for (int c = 0; c < 4; ++c) worst = std::max(worst, double(std::abs(out[4 * k + c] - ref[c])));
            }
          }
          INFO("format " << fmt << " wrap " << int(w) << " min filter " << minf << " AVX2 " << avx2);
          CHECK(worst < 4e-4);  // fixed-point weights: at most 3 units of 2^-14 per level
        }
    }
  }
}

TEST_CASE("nearest samples are exactly texel / 255, constant textures filter to their colour", "[render][texture]") {
  std::mt19937 rng(5);
  auto t = random_texture(rng, 16, 16, TexFormat::RGBA, true);
  t->min_filter = TexFilter::NearestMipmapNearest;
  t->mag_filter = TexFilter::Nearest;
  for (int q = 0; q < 1000; ++q) {
    const int i = rng() % 16, j = rng() % 16;
    const Vec4f c = t->sample((i + 0.5f) / 16, (j + 0.5f) / 16, -1);
    for (int k = 0; k < 4; ++k) CHECK(c[k] == t->levels[0].rgba[(j * 16 + i) * 4 + k] * (1.0f / 255.0f));
  }
  Image im;
  im.width = im.height = 64;
  im.rgba.assign(64 * 64 * 4, 0);
  for (std::size_t k = 0; k < im.rgba.size(); k += 4) im.rgba[k] = 255, im.rgba[k + 1] = 128, im.rgba[k + 3] = 255;
  auto u = Texture::from_image(im, TexFormat::RGBA, true);
  u->min_filter = TexFilter::LinearMipmapLinear;
  for (bool avx2 : {true, false}) {
    for (int q = 0; q < 1000; ++q) {
      float s[4], tt[4], out[16];
      for (int k = 0; k < 4; ++k) s[k] = random_coord(rng, 64), tt[k] = random_coord(rng, 64);
      u->sample4(s, tt, random_lambda(rng), out, avx2 ? Simd::Auto : Simd::Sse2);
      for (int k = 0; k < 4; ++k) {
        CHECK(out[4 * k] == 1.0f);
        CHECK(out[4 * k + 1] == 128 * (1.0f / 255.0f));
        CHECK(out[4 * k + 2] == 0.0f);
        CHECK(out[4 * k + 3] == 1.0f);
      }
    }
  }
}
