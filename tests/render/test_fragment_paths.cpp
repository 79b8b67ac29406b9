// The triangle fragment loop has three builds: the quad loop (render/quad_loop.cpp) 4 lanes wide
// in SSE2 (the base x86-64, one 2x2 quad per block) and 8 lanes wide for AVX2 (two quads per
// block, chosen at run time when the CPU has it; every state but Phong), and a pixel-at-a-time
// loop with 64-bit edge functions for triangles too large for 32-bit ones. The two quad builds
// must give the same bits (Context::simd(Simd::Sse2) forces the SSE2 one); the large-triangle loop
// is checked against OpenGL.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <string>

#include "simd_skip.h"
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
  Context c(W, H);
  c.threads(threads);
  if (sse2) c.simd(Simd::Sse2);
  scene(c);
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
  if (test::avx2_missing("the quad fragment loop's AVX2 build")) return;
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

// Each depth function on the loops' common state (no blending, all channels written): the same
// bits in both builds (8 lanes where the CPU has AVX2, else 4), and OpenGL's image.
TEST_CASE("every depth function gives the same bits in both builds and matches OpenGL", "[render][simd][gl]") {
  const DepthFunc funcs[] = {DepthFunc::Never,   DepthFunc::Less,     DepthFunc::Equal,        DepthFunc::LessEqual,
                             DepthFunc::Greater, DepthFunc::NotEqual, DepthFunc::GreaterEqual, DepthFunc::Always};
  for (DepthFunc f : funcs) {
    auto scene = [f](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      camera(g, W, H);
      g.enable(Cap::DepthTest);
      g.color(0.8f, 0.3f, 0.2f);
      sphere(g, 1, 12, 8);
      g.depth_func(f);
      // A slanted triangle through the sphere, and one at the sphere's own depths (its second
      // copy: Equal passes where the depths agree).
      g.color(0.2f, 0.6f, 0.9f);
      g.begin(Primitive::Triangles);
      g.vertex(-2, -2, 0.3), g.vertex(2, -1.5, -0.3), g.vertex(0, 2, 0);
      g.end();
      g.color(0.9f, 0.9f, 0.1f);
      sphere(g, 1, 12, 8);
    };
    INFO("depth function " << int(f));
    if (!test::cpu_has_avx2()) WARN("no AVX2 on this CPU: the SSE2 build is compared with itself");
    check_same_bits("depth function", [&](Context& g) { scene(g); });
    const Diff d = WEDGE_BOTH("depthfunc" + std::to_string(int(f)), W, H, scene);
    INFO("covered " << d.covered << ", outliers " << d.outliers << ", max diff " << d.max_diff);
    CHECK(d.covered > 1000);
    CHECK(d.outliers <= d.covered / 1000);
  }
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

namespace {

// `count` independent triangles from `va` after `setup`: by the triangle path's runs, or
// (general) with a user clip plane that clips nothing, which sends each triangle to
// triangle() alone. Both must give the same bits, at 1 and 2 threads, in both SIMD builds;
// returns the runs' frames for further checks.
template <class Setup>
std::vector<Frame> check_runs(const char* what, const VertexArrays& va, int count, const Setup& setup) {
  std::vector<Frame> frames;
  for (bool sse2 : {false, true})
    for (int threads : {1, 2}) {
      auto draw = [&](bool general) {
        Context c(W, H);
        c.threads(threads);
        if (sse2) c.simd(Simd::Sse2);
        setup(c);
        if (general) {
          c.clip_plane(0, Vec4(0, 0, 1, 100));
          c.enable(Cap::ClipPlane0);
        }
        c.draw_arrays(Primitive::Triangles, va, 0, count);
        return Frame{c.image(), c.depth_buffer()};
      };
      Frame runs = draw(false);
      const Frame one = draw(true);
      INFO(what << (sse2 ? ", SSE2" : ", AVX2 where there is") << ", " << threads << " thread(s)");
      CHECK(runs.image.rgba == one.image.rgba);
      CHECK(std::memcmp(runs.depth.data(), one.depth.data(), runs.depth.size() * sizeof(float)) == 0);
      frames.push_back(std::move(runs));
    }
  return frames;
}

std::size_t drawn_pixels(const Frame& f, float clear_depth) {
  std::size_t n = 0;
  for (float d : f.depth) n += d != clear_depth;
  return n;
}

}  // namespace

// Independent triangles from client arrays are drawn by runs: the small ones set up several at
// a time (run_setup, in double lanes) and filled pixel by pixel, the others one by one. A user
// clip plane that clips nothing takes the same triangles off that path, to triangle() one at a
// time: the images and depth buffers must be the same bits, for a dense mesh of one- and
// two-pixel triangles (some covering no centre, slivers, zero areas) in every state the runs
// take, with a scissor at odd bounds, at 1 and 2 threads (bands), in both SIMD builds.
TEST_CASE("runs of small triangles draw what triangle() draws one by one", "[render][simd][threads]") {
  std::vector<double> pos;
  std::vector<float> col;
  const int stacks = 90, slices = 140;
  auto vert = [&](int i, int j) {
    const double t = kPi * i / stacks - kPi / 2, p = 2 * kPi * j / slices;
    pos.insert(pos.end(), {std::cos(t) * std::cos(p), std::cos(t) * std::sin(p), std::sin(t)});
    col.insert(col.end(), {float(0.5 + 0.5 * std::cos(3 * p)), float(i % 7) / 7.0f, float(j % 5) / 5.0f, 1});
  };
  for (int i = 0; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) vert(i, j), vert(i, j + 1), vert(i + 1, j + 1), vert(i, j), vert(i + 1, j + 1), vert(i + 1, j);
  // A few degenerate ones among them: a repeated vertex, a sliver.
  for (int k = 0; k < 6; ++k) pos.push_back(pos[k % 3]), col.push_back(1);
  pos.insert(pos.end(), {0, 0, 1.2, 0.001, 0.3, 1.2, 0.0005, 0.0, 1.2});
  col.insert(col.end(), 12, 0.5f);
  VertexArrays va;
  va.positions = pos.data(), va.normals = pos.data(), va.colors = col.data();
  const int count = int(pos.size() / 3);
  struct State {
    const char* what;
    void (*set)(Context&);
    bool depth_shows = true;
  };
  const State states[] = {
      {"smooth, colours", [](Context&) {}},
      {"lit, two-sided, no culling", [](Context& c) {
         c.enable(Cap::Lighting), c.enable(Cap::Light0), c.light_model_two_side(true);
         c.material_specular(Face::FrontAndBack, Vec4f(0.5f, 0.5f, 0.5f, 1));
         c.material_shininess(Face::FrontAndBack, 25);
       }},
      {"flat, back faces culled", [](Context& c) {
         c.shade_model(ShadeModel::Flat);
         c.enable(Cap::CullFace);
       }},
      {"depth GreaterEqual from a cleared 0, no depth writes", [](Context& c) {
         c.clear_depth(0);
         c.clear();
         c.depth_func(DepthFunc::GreaterEqual);
         c.depth_mask(false);
       },
       false},
      {"no depth test", [](Context& c) { c.disable(Cap::DepthTest); }, false},
  };
  // A grid of 2 x 2-pixel cells split along a diagonal, its vertices on pixel centres, in
  // window coordinates: many centres lie on shared edges, where the tie rule decides, and the
  // scissor cuts the grid (clamped boxes).
  std::vector<double> gpos;
  std::vector<float> gcol;
  for (int j = 0; j < H / 2; ++j)
    for (int i = 0; i < W / 2; ++i) {
      const double x0 = 2 * i + 0.5, y0 = 2 * j + 0.5, x1 = x0 + 2, y1 = y0 + 2;
      const bool flip = (i + j) % 2;
      const double tri[2][6] = {{x0, y0, x1, y0, flip ? x0 : x1, y1}, {flip ? x1 : x0, y0, x1, y1, x0, y1}};
      for (const auto& t : tri)
        for (int k = 0; k < 3; ++k) {
          gpos.insert(gpos.end(), {t[2 * k], t[2 * k + 1], -0.5 + 0.01 * ((i * 7 + j * 3 + k) % 11)});
          gcol.insert(gcol.end(), {float(i % 9) / 9, float(j % 4) / 4, float(k) / 2, 1});
        }
    }
  VertexArrays grid;
  grid.positions = gpos.data(), grid.colors = gcol.data();
  for (const Frame& f : check_runs("pixel-aligned grid", grid, int(gpos.size() / 3), [](Context& c) {
         c.clear();
         c.matrix_mode(MatrixMode::Projection);
         c.ortho(0, W, 0, H, -1, 1);
         c.matrix_mode(MatrixMode::ModelView);
         c.enable(Cap::DepthTest);
         c.depth_func(DepthFunc::LessEqual);
         c.enable(Cap::ScissorTest);
         c.scissor(5, 4, W - 13, H - 10);
       }))
    CHECK(drawn_pixels(f, 1.0f) == std::size_t(W - 13) * (H - 10));  // every pixel of the scissor box, once
  for (const State& st : states) {
    const std::vector<Frame> frames = check_runs(st.what, va, count, [&](Context& c) {
      c.clear_color(0.1f, 0.1f, 0.15f, 1);
      c.clear();
      camera(c, W, H);
      c.enable(Cap::DepthTest);
      c.enable(Cap::ScissorTest);
      c.scissor(3, 2, W - 8, H - 5);
      st.set(c);
    });
    // Not a blank image: much of the sphere was drawn (where the depth buffer shows it).
    if (st.depth_shows)
      for (const Frame& f : frames) CHECK(drawn_pixels(f, 1.0f) > std::size_t(W * H / 8));
  }
}
