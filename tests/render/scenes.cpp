#include "scenes.h"

#include <cstdlib>

namespace wedge::render::test {

Diff compare(const Image& a, const Image& b, int tolerance) {
  Diff d;
  if (a.width != b.width || a.height != b.height) {
    d.outliers = -1;
    return d;
  }
  // Covered: pixels where either image differs from its own background (its corner pixel, the
  // clear colour in every scene), so the outlier budget is a share of the pixels the geometry
  // really covers. A background that differs between the two images shows up as outliers.
  const std::uint8_t* bga = a.rgba.data();
  const std::uint8_t* bgb = b.rgba.data();
  for (int k = 0; k < 4; ++k) d.background_diff = std::max(d.background_diff, std::abs(int(bga[k]) - int(bgb[k])));
  const std::size_t n = std::size_t(a.width) * a.height;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = &a.rgba[i * 4];
    const std::uint8_t* q = &b.rgba[i * 4];
    bool cov = false;
    int m = 0;
    for (int k = 0; k < 3; ++k) {
      cov = cov || p[k] != bga[k] || q[k] != bgb[k];
      m = std::max(m, std::abs(int(p[k]) - int(q[k])));
    }
    if (cov) ++d.covered;
    d.max_diff = std::max(d.max_diff, m);
    if (m > tolerance) ++d.outliers;
  }
  return d;
}

Diff against_gl(const std::string& name, int w, int h, const std::function<void(Context&)>& ours,
                const std::function<void(oracle::GlContext&)>& theirs) {
  Context c(w, h);
  ours(c);
  Image a = c.image();
  Image b;
  {
    oracle::GlContext g(w, h);
    theirs(g);
    b = g.image();
  }
  Diff d = compare(a, b);
  if (d.outliers > d.covered / 1000 || std::getenv("WEDGE_KEEP_IMAGES")) {
    write_png(std::string(WEDGE_BINARY_DIR) + "/" + name + ".wedge.png", a);
    write_png(std::string(WEDGE_BINARY_DIR) + "/" + name + ".gl.png", b);
  }
  return d;
}

}  // namespace wedge::render::test
