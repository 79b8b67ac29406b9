// Textures as OpenGL 1.x samples them (GL 1.5 spec section 3.8.8): wrap modes repeat, clamp
// (texel coordinates clamped to [0, 1], so linear filtering at the edge blends with the border
// colour) and clamp-to-edge; magnification nearest/linear; minification nearest/linear and the
// four mipmap filters, choosing the level d = lambda (nearest level: round, as the spec's
// ceil(lambda + 1/2) - 1) or blending the two levels around it. The mipmap chain is built by
// 2x2 box filtering (what gluBuild2DMipmaps does for power-of-two images).
#include <cmath>

#include "render/render.h"

namespace wedge::render {

namespace {

Vec4f texel(const Image& im, TexFormat fmt, int i, int j) {
  const std::uint8_t* p = &im.rgba[(std::size_t(j) * im.width + i) * 4];
  constexpr float k = 1.0f / 255.0f;
  Vec4f c(p[0] * k, p[1] * k, p[2] * k, p[3] * k);
  if (fmt == TexFormat::Luminance) c = Vec4f(c[0], c[0], c[0], 1);
  else if (fmt == TexFormat::RGB) c.w() = 1;
  return c;
}

int wrap_index(int i, int size, TexWrap w) {
  if (w == TexWrap::Repeat) {
    if (unsigned(i) < unsigned(size)) return i;  // already inside: skip the division
    i %= size;
    return i < 0 ? i + size : i;
  }
  return i;  // clamp modes are handled by the caller (border or edge)
}

Vec4f fetch(const Texture& t, const Image& im, int i, int j) {
  if (t.wrap_s == TexWrap::Repeat) i = wrap_index(i, im.width, TexWrap::Repeat);
  else if (t.wrap_s == TexWrap::ClampToEdge) i = std::clamp(i, 0, im.width - 1);
  if (t.wrap_t == TexWrap::Repeat) j = wrap_index(j, im.height, TexWrap::Repeat);
  else if (t.wrap_t == TexWrap::ClampToEdge) j = std::clamp(j, 0, im.height - 1);
  if (i < 0 || j < 0 || i >= im.width || j >= im.height) return t.border;  // GL_CLAMP beyond the edge
  return texel(im, t.format, i, j);
}

float wrap_coord(float s, TexWrap w) {
  if (w == TexWrap::Repeat) return s - std::floor(s);
  return std::clamp(s, 0.0f, 1.0f);
}

Vec4f sample_level(const Texture& t, int level, float s, float tt, bool linear) {
  const Image& im = t.levels[level];
  float u = wrap_coord(s, t.wrap_s) * im.width, v = wrap_coord(tt, t.wrap_t) * im.height;
  if (!linear) {
    int i = std::min(int(std::floor(u)), im.width - 1), j = std::min(int(std::floor(v)), im.height - 1);
    if (t.wrap_s == TexWrap::Repeat) i = wrap_index(i, im.width, TexWrap::Repeat);
    if (t.wrap_t == TexWrap::Repeat) j = wrap_index(j, im.height, TexWrap::Repeat);
    return texel(im, t.format, std::clamp(i, 0, im.width - 1), std::clamp(j, 0, im.height - 1));
  }
  float uf = u - 0.5f, vf = v - 0.5f;
  int i0 = int(std::floor(uf)), j0 = int(std::floor(vf));
  float a = uf - i0, b = vf - j0;
  return (1 - a) * (1 - b) * fetch(t, im, i0, j0) + a * (1 - b) * fetch(t, im, i0 + 1, j0) +
         (1 - a) * b * fetch(t, im, i0, j0 + 1) + a * b * fetch(t, im, i0 + 1, j0 + 1);
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
  const bool mag = lambda <= 0 || levels.size() == 1;
  if (mag) {
    bool linear = (lambda <= 0 ? mag_filter : min_filter) == TexFilter::Linear;
    if (lambda > 0) linear = min_filter != TexFilter::Nearest && min_filter != TexFilter::NearestMipmapNearest &&
                             min_filter != TexFilter::NearestMipmapLinear;
    return sample_level(*this, 0, s, t, linear);
  }
  const int last = int(levels.size()) - 1;
  switch (min_filter) {
    case TexFilter::Nearest: return sample_level(*this, 0, s, t, false);
    case TexFilter::Linear: return sample_level(*this, 0, s, t, true);
    case TexFilter::NearestMipmapNearest:
    case TexFilter::LinearMipmapNearest: {
      int d = lambda <= 0.5f ? 0 : std::min(last, int(std::ceil(lambda + 0.5f)) - 1);
      return sample_level(*this, d, s, t, min_filter == TexFilter::LinearMipmapNearest);
    }
    case TexFilter::NearestMipmapLinear:
    case TexFilter::LinearMipmapLinear: {
      bool lin = min_filter == TexFilter::LinearMipmapLinear;
      if (lambda >= last) return sample_level(*this, last, s, t, lin);
      int d1 = int(std::floor(lambda));
      float f = lambda - d1;
      return (1 - f) * sample_level(*this, d1, s, t, lin) + f * sample_level(*this, d1 + 1, s, t, lin);
    }
  }
  return Vec4f(0, 0, 0, 0);
}

}  // namespace wedge::render
