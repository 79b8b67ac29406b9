// The triangle fragment loop has three builds: 2x2 quads in SSE2 (the base x86-64), the same
// quads compiled for AVX2 (chosen at run time when the CPU has it), and a pixel-at-a-time
// loop with 64-bit edge functions for triangles too large for 32-bit ones. The two quad builds
// must give the same bits (WEDGE_RENDER_SIMD=sse2 forces the SSE2 one); the large-triangle loop
// is checked against OpenGL.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>

#include "scenes.h"

using namespace wedge;
using namespace wedge::render;
using namespace wedge::render::test;

namespace {

constexpr int W = 131, H = 97;  // odd sizes: partial quads at the right and top edges

struct Frame {
  Image image;
  std::vector<float> depth;
};

template <class Scene>
Frame draw(const Scene& scene, int threads, bool sse2) {
  if (sse2) setenv("WEDGE_RENDER_SIMD", "sse2", 1);
  Context c(W, H);
  c.threads(threads);
  scene(c);
  if (sse2) unsetenv("WEDGE_RENDER_SIMD");
  return {c.image(), c.depth_buffer()};
}

template <class Scene>
void check_same_bits(const char* what, const Scene& scene) {
  for (int threads : {1, 2}) {
    const Frame a = draw(scene, threads, false), b = draw(scene, threads, true);
    INFO(what << ", " << threads << " thread(s)");
    CHECK(a.image.rgba == b.image.rgba);
    CHECK(std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)) == 0);
  }
}

void view(Context& g) {
  camera(g, W, H);
}

}  // namespace

TEST_CASE("the SSE2 and AVX2 builds of the quad fragment loop give the same bits", "[render][simd]") {
  check_same_bits("lit smooth sphere", [](Context& g) {
    g.clear_color(0.1f, 0.1f, 0.15f, 1);
    g.clear();
    view(g);
    g.enable(Cap::DepthTest);
    g.enable(Cap::Lighting);
    g.enable(Cap::Light0);
    g.material_specular(Face::FrontAndBack, Vec4f(0.6f, 0.6f, 0.6f, 1));
    g.material_shininess(Face::FrontAndBack, 20);
    sphere(g, 1.2, 24, 16);
  });
  check_same_bits("flat and Phong spheres, scissor at odd bounds", [](Context& g) {
    g.clear();
    view(g);
    g.enable(Cap::DepthTest);
    g.enable(Cap::Lighting);
    g.enable(Cap::Light0);
    g.enable(Cap::ScissorTest);
    g.scissor(7, 5, 101, 77);
    g.shade_model(ShadeModel::Flat);
    g.translate(-0.8, 0, 0);
    sphere(g, 0.9, 16, 12);
    g.shade_model(ShadeModel::Phong);
    g.translate(1.6, 0, 0);
    sphere(g, 0.9, 16, 12);
  });
  auto tex = Texture::checker(64, 8, Vec4f(0.9f, 0.8f, 0.1f, 0.7f), Vec4f(0.1f, 0.2f, 0.5f, 1));
  tex->min_filter = TexFilter::LinearMipmapLinear;
  for (int env = 0; env < 4; ++env)
    for (int fog = 0; fog < 3; ++fog) {
      check_same_bits("textured quad with fog", [&](Context& g) {
        g.clear_color(0.7f, 0.7f, 0.75f, 1);
        g.clear();
        view(g);
        g.enable(Cap::DepthTest);
        g.enable(Cap::Texture2D);
        g.bind_texture(tex);
        g.tex_env_mode(static_cast<TexEnvMode>(env));
        g.enable(Cap::Fog);
        g.fog_mode(static_cast<FogMode>(fog));
        g.fog_start(1), g.fog_end(12), g.fog_density(0.15f);
        g.rotate(-70, 1, 0, 0);
        g.begin(Primitive::Quads);
        g.color(1, 0.5f, 0.25f), g.tex_coord(0, 0), g.vertex(-3, -3, 0);
        g.color(0.2f, 1, 0.5f), g.tex_coord(6, 0), g.vertex(3, -3, 0);
        g.color(0.5f, 0.2f, 1), g.tex_coord(6, 9, 0, 2), g.vertex(3, 9, 0);
        g.color(1, 1, 1), g.tex_coord(0, 9), g.vertex(-3, 9, 0);
        g.end();
      });
    }
  check_same_bits("blending, colour mask and depth functions", [](Context& g) {
    g.clear_color(0, 0, 0, 1);
    g.clear();
    view(g);
    g.enable(Cap::DepthTest);
    sphere(g, 1, 12, 8);
    g.enable(Cap::Blend);
    g.blend_func(BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha);
    g.depth_func(DepthFunc::GreaterEqual);
    g.color(1, 0, 0, 0.5f);
    g.begin(Primitive::Triangles);
    g.vertex(-2, -2, 0.3), g.vertex(2, -1.5, -0.3), g.vertex(0, 2, 0);
    g.end();
    g.disable(Cap::Blend);
    g.color_mask(true, false, true, false);
    g.depth_mask(false);
    g.depth_func(DepthFunc::NotEqual);
    g.color(0, 1, 1, 1);
    g.begin(Primitive::Triangles);
    g.vertex(-2, 2, 0.5), g.vertex(-1.5, -2, -0.5), g.vertex(2, 0.5, 0);
    g.end();
  });
}

// A viewport much larger than the framebuffer makes window coordinates thousands of pixels
// apart: the quad loop's 32-bit edge functions would overflow, the 64-bit loop draws these.
TEST_CASE("triangles too large for 32-bit edge functions match OpenGL", "[render][gl][simd]") {
  auto tex = Texture::checker(64, 8, Vec4f(0.9f, 0.8f, 0.1f, 1), Vec4f(0.1f, 0.2f, 0.5f, 1));
  tex->min_filter = TexFilter::LinearMipmapLinear;
  auto scene = [&](auto& g) {
    g.clear_color(0, 0, 0, 1);
    g.clear();
    g.viewport(-6000, -6000, 12000, 12000);
    g.enable(Cap::DepthTest);
    g.enable(Cap::Texture2D);
    g.bind_texture(tex);
    g.tex_env_mode(TexEnvMode::Modulate);
    g.begin(Primitive::Triangles);
    g.color(1, 0.2f, 0.2f), g.tex_coord(0, 0), g.vertex(-0.9, -0.8, 0.2);
    g.color(0.2f, 1, 0.2f), g.tex_coord(300, 0), g.vertex(0.95, -0.9, -0.3);
    g.color(0.2f, 0.2f, 1), g.tex_coord(0, 300), g.vertex(0.1, 0.9, 0);
    g.end();
  };
  Diff d = WEDGE_BOTH("huge_triangle", 128, 96, scene);
  INFO("covered " << d.covered << ", outliers " << d.outliers << ", max diff " << d.max_diff);
  CHECK(d.covered > 100);
  CHECK(d.outliers <= d.covered / 1000);
}
