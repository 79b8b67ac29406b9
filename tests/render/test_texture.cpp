// Texture::sample4 (four fragments sharing one level of detail) against four calls of sample(),
// bit for bit, over random coordinates and every format, wrap mode, filter and texture shape.
#include <catch2/catch.hpp>

#include <cstring>
#include <random>

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
// centre, sometimes far away.
float random_coord(std::mt19937& rng, int size) {
  std::uniform_real_distribution<float> u(-3.0f, 4.0f);
  switch (rng() % 8) {
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
    default: return std::uniform_real_distribution<float>(-2.0f, 11.0f)(rng);
  }
}

// Compares sample4 with four sample() calls for `n` random quads; returns the number of mismatches.
int mismatches(const Texture& t, std::mt19937& rng, int n) {
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
    t.sample4(s, tt, lambda, out);
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

}  // namespace

TEST_CASE("sample4 equals four calls of sample, bit for bit", "[render][texture]") {
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
                CHECK(mismatches(*t, rng, 60) == 0);
              }
      }
}
