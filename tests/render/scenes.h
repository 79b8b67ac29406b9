// Scenes drawn through either backend (render::Context or oracle::GlContext): each is a
// template over the backend, so both receive exactly the same sequence of calls.
#pragma once
#include <cmath>
#include <functional>
#include <string>

#include "gl_oracle.h"
#include "render/render.h"

namespace wedge::render::test {

// Pixel comparison per the issue: a pixel is an outlier when a channel differs by more than
// `tolerance` levels; covered pixels are those that differ from their own image's background
// (the corner pixel, the clear colour) in either image, so the 0.1% outlier budget is a share of
// what the geometry covers. background_diff: the largest channel difference of the two
// backgrounds (clears convert exactly as GL's, so 0).
struct Diff {
  int covered = 0, outliers = 0, max_diff = 0, background_diff = 0;
};
Diff compare(const Image& a, const Image& b, int tolerance = 2);

// Renders `scene` with both backends at w x h and compares; on failure writes both images to
// the build directory as <name>.wedge.png / <name>.gl.png.
Diff against_gl(const std::string& name, int w, int h, const std::function<void(Context&)>& ours,
                const std::function<void(oracle::GlContext&)>& theirs);

#define WEDGE_BOTH(name, w, h, scene) \
  ::wedge::render::test::against_gl(name, w, h, [&](::wedge::render::Context& g) { scene(g); }, \
                                    [&](::wedge::render::oracle::GlContext& g) { scene(g); })

// A UV sphere in immediate mode (quad strips), normals = positions / r.
template <class G>
void sphere(G& g, double r, int slices, int stacks) {
  for (int i = 0; i < stacks; ++i) {
    double t0 = kPi * i / stacks - kPi / 2, t1 = kPi * (i + 1) / stacks - kPi / 2;
    g.begin(Primitive::QuadStrip);
    for (int j = 0; j <= slices; ++j) {
      double p = 2 * kPi * j / slices;
      for (double t : {t1, t0}) {
        double x = std::cos(t) * std::cos(p), y = std::cos(t) * std::sin(p), z = std::sin(t);
        g.normal(x, y, z);
        g.tex_coord(double(j) / slices, (t + kPi / 2) / kPi);
        g.vertex(r * x, r * y, r * z);
      }
    }
    g.end();
  }
}

// A standard perspective camera looking at the origin from +z (slightly above).
template <class G>
void camera(G& g, int w, int h) {
  g.viewport(0, 0, w, h);
  g.matrix_mode(MatrixMode::Projection);
  g.load_identity();
  g.perspective(40, double(w) / h, 1, 20);
  g.matrix_mode(MatrixMode::ModelView);
  g.load_identity();
  g.look_at(Point3(0.5, 1.5, 5), Point3(0, 0, 0), Vec3(0, 1, 0));
}

}  // namespace wedge::render::test
