// wedge's pipeline against Mesa's OpenGL (OSMesa): the same calls, the same pixels within 2
// levels per channel, with at most 0.1% of the covered pixels as outliers.
#include <catch2/catch.hpp>

#include "scenes.h"

using namespace wedge;
using namespace wedge::render;
using namespace wedge::render::test;

#define CHECK_MATCHES_GL(d)                                                                   \
  do {                                                                                        \
    INFO("covered " << (d).covered << ", outliers " << (d).outliers << ", max diff " << (d).max_diff); \
    CHECK((d).covered > 100);                                                                 \
    CHECK((d).outliers <= (d).covered / 1000);                                                \
    CHECK((d).background_diff == 0);                                                          \
  } while (0)

namespace {

constexpr int W = 128, H = 96;

template <class G>
void lit_setup(G& g) {
  g.clear_color(0.1f, 0.1f, 0.15f, 1);
  g.clear();
  camera(g, W, H);
  g.enable(Cap::DepthTest);
  g.enable(Cap::Lighting);
  g.enable(Cap::Light0);
  g.material_diffuse(Face::FrontAndBack, Vec4f(0.8f, 0.5f, 0.3f, 1));
  g.material_specular(Face::FrontAndBack, Vec4f(0.6f, 0.6f, 0.6f, 1));
  g.material_shininess(Face::FrontAndBack, 20);
}

}  // namespace

TEST_CASE("a directional light on a smooth sphere matches OpenGL", "[render][gl][lighting]") {
  auto scene = [](auto& g) {
    lit_setup(g);
    g.light_position(0, Vec4f(1, 1, 1, 0));
    sphere(g, 1.2, 24, 16);
  };
  Diff d = WEDGE_BOTH("directional", W, H, scene);
  CHECK_MATCHES_GL(d);
}

TEST_CASE("flat shading lights each polygon at its provoking vertex as OpenGL", "[render][gl][lighting]") {
  auto scene = [](auto& g) {
    lit_setup(g);
    g.shade_model(ShadeModel::Flat);
    g.light_position(0, Vec4f(-1, 2, 1, 0));
    sphere(g, 1.2, 12, 8);
  };
  Diff d = WEDGE_BOTH("flat", W, H, scene);
  CHECK_MATCHES_GL(d);
}

TEST_CASE("a point light with attenuation and a local viewer matches OpenGL", "[render][gl][lighting]") {
  auto scene = [](auto& g) {
    lit_setup(g);
    g.light_model_local_viewer(true);
    g.light_position(0, Vec4f(2, 1, 2, 1));
    g.light_attenuation(0, 0.5f, 0.2f, 0.05f);
    g.light_ambient(0, Vec4f(0.1f, 0.1f, 0.2f, 1));
    sphere(g, 1.2, 24, 16);
  };
  Diff d = WEDGE_BOTH("point", W, H, scene);
  CHECK_MATCHES_GL(d);
}

TEST_CASE("a spot light with cutoff and exponent matches OpenGL", "[render][gl][lighting]") {
  auto scene = [](auto& g) {
    lit_setup(g);
    g.light_position(0, Vec4f(0, 0, 4, 1));
    g.light_spot_direction(0, Vec3(0, 0, -1));
    g.light_spot(0, 8, 20);
    g.begin(Primitive::Quads);
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 16; ++j) {
        double x0 = -2 + i * 0.25, y0 = -2 + j * 0.25;
        g.normal(0, 0, 1);
        g.vertex(x0, y0, 0), g.vertex(x0 + 0.25, y0, 0), g.vertex(x0 + 0.25, y0 + 0.25, 0), g.vertex(x0, y0 + 0.25, 0);
      }
    g.end();
  };
  Diff d = WEDGE_BOTH("spot", W, H, scene);
  CHECK_MATCHES_GL(d);
}

TEST_CASE("several coloured lights, emission and global ambient match OpenGL", "[render][gl][lighting]") {
  auto scene = [](auto& g) {
    lit_setup(g);
    g.light_model_ambient(Vec4f(0.3f, 0.1f, 0.1f, 1));
    g.material_emission(Face::Front, Vec4f(0.05f, 0.1f, 0.0f, 1));
    g.material_ambient(Face::Front, Vec4f(0.4f, 0.4f, 0.4f, 1));
    g.light_position(0, Vec4f(1, 0, 1, 0));
    g.light_diffuse(0, Vec4f(0.7f, 0.2f, 0.2f, 1));
    g.enable(Cap::Light1);
    g.light_position(1, Vec4f(-2, 1, 1, 1));
    g.light_diffuse(1, Vec4f(0.1f, 0.3f, 0.8f, 1));
    g.light_specular(1, Vec4f(0.5f, 0.5f, 1.0f, 1));
    g.enable(Cap::Light2);
    g.light_position(2, Vec4f(0, -3, 2, 1));
    g.light_diffuse(2, Vec4f(0.2f, 0.7f, 0.2f, 1));
    g.light_spot_direction(2, Vec3(0, 1, -0.5));
    g.light_spot(2, 2, 45);
    sphere(g, 1.2, 24, 16);
  };
  Diff d = WEDGE_BOTH("multi", W, H, scene);
  CHECK_MATCHES_GL(d);
}

TEST_CASE("colour material takes ambient and diffuse from the vertex colour", "[render][gl][lighting]") {
  auto scene = [](auto& g) {
    lit_setup(g);
    g.enable(Cap::ColorMaterial);
    g.color_material(Face::FrontAndBack, ColorMaterialMode::AmbientAndDiffuse);
    g.light_position(0, Vec4f(1, 1, 1, 0));
    g.color(0.2f, 0.9f, 0.4f);
    sphere(g, 1.2, 24, 16);
  };
  Diff d = WEDGE_BOTH("colormaterial", W, H, scene);
  CHECK_MATCHES_GL(d);
}

TEST_CASE("two-sided lighting lights back faces with the back material", "[render][gl][lighting]") {
  auto scene = [](auto& g) {
    lit_setup(g);
    g.light_model_two_side(true);
    g.material_diffuse(Face::Back, Vec4f(0.2f, 0.3f, 0.9f, 1));
    g.light_position(0, Vec4f(0, 0, 1, 0));
    // An open half-cylinder: we see its inside (back faces) and outside.
    g.begin(Primitive::QuadStrip);
    for (int j = 0; j <= 16; ++j) {
      double p = kPi * j / 16;
      g.normal(std::cos(p), 0, std::sin(p));
      g.vertex(1.2 * std::cos(p), 1, 1.2 * std::sin(p) - 0.5);
      g.vertex(1.2 * std::cos(p), -1, 1.2 * std::sin(p) - 0.5);
    }
    g.end();
    g.rotate(200, 0, 1, 0);
  };
  Diff d = WEDGE_BOTH("twoside", W, H, scene);
  CHECK_MATCHES_GL(d);
}

TEST_CASE("back-face culling modes and front-face winding match OpenGL", "[render][gl][culling]") {
  for (int mode = 0; mode < 4; ++mode) {
    auto scene = [&](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      camera(g, W, H);
      g.enable(Cap::CullFace);
      if (mode == 1) g.cull_face(Face::Front);
      if (mode == 2) g.front_face(FrontFace::CW);
      if (mode == 3) g.cull_face(Face::FrontAndBack);
      g.begin(Primitive::Triangles);
      g.color(1, 0, 0), g.vertex(-2, -1, 0), g.vertex(0, -1, 0), g.vertex(-1, 1, 0);    // ccw
      g.color(0, 1, 0), g.vertex(0.2, -1, 0), g.vertex(1.2, 1, 0), g.vertex(2.2, -1, 0);  // cw
      g.end();
      if (mode == 3) {  // nothing drawn: add an unculled point so the comparison sees coverage
        g.disable(Cap::CullFace);
        g.begin(Primitive::Triangles);
        g.color(0, 0, 1), g.vertex(-1, -1, -1), g.vertex(1, -1, -1), g.vertex(0, 1, -1);
        g.end();
      }
    };
    Diff d = WEDGE_BOTH("cull" + std::to_string(mode), W, H, scene);
    CHECK_MATCHES_GL(d);
  }
}

TEST_CASE("all eight depth functions and the depth mask match OpenGL", "[render][gl][depth]") {
  for (int f = 0; f < 8; ++f) {
    auto scene = [&](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      camera(g, W, H);
      g.enable(Cap::DepthTest);
      // A tilted red quad, then a green one crossing it, then a blue copy of the red one.
      g.begin(Primitive::Quads);
      g.color(1, 0, 0), g.vertex(-1.5, -1, -0.5), g.vertex(1.5, -1, 0.5), g.vertex(1.5, 1, 0.5), g.vertex(-1.5, 1, -0.5);
      g.end();
      g.depth_func(static_cast<DepthFunc>(f));
      g.depth_mask(f % 2 == 0);
      g.begin(Primitive::Quads);
      g.color(0, 1, 0), g.vertex(-1, -1.2, 0.3), g.vertex(1, -1.2, -0.3), g.vertex(1, 0.5, -0.3), g.vertex(-1, 0.5, 0.3);
      g.end();
      g.begin(Primitive::Quads);  // blue exactly over the red quad: same vertices, same depths
      g.color(0, 0, 1), g.vertex(-1.5, -1, -0.5), g.vertex(1.5, -1, 0.5), g.vertex(1.5, 1, 0.5), g.vertex(-1.5, 1, -0.5);
      g.end();
    };
    Diff d = WEDGE_BOTH("depth" + std::to_string(f), W, H, scene);
    INFO("depth func " << f);
    CHECK_MATCHES_GL(d);
  }
}

TEST_CASE("every primitive type with smooth vertex colours matches OpenGL", "[render][gl][primitives]") {
  for (int p = 4; p < 10; ++p) {
    auto scene = [&](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      g.viewport(0, 0, W, H);
      g.matrix_mode(MatrixMode::Projection);
      g.load_identity();
      g.ortho(-1, 1, -1, 1, -1, 1);
      g.matrix_mode(MatrixMode::ModelView);
      g.load_identity();
      g.begin(static_cast<Primitive>(p));
      const double pts[8][2] = {{-0.9, -0.8}, {-0.6, 0.7}, {-0.2, -0.7}, {0.1, 0.8}, {0.3, -0.6}, {0.6, 0.6}, {0.8, -0.8}, {0.9, 0.5}};
      for (int i = 0; i < 8; ++i) {
        g.color(float(i % 3 == 0), float(i % 3 == 1), float(i % 3 == 2));
        g.vertex(pts[i][0], pts[i][1]);
      }
      g.end();
    };
    Diff d = WEDGE_BOTH("prim" + std::to_string(p), W, H, scene);
    INFO("primitive " << p);
    CHECK_MATCHES_GL(d);
  }
}

TEST_CASE("homogeneous clipping against the near plane and a user clip plane matches OpenGL", "[render][gl][clip]") {
  auto scene = [](auto& g) {
    lit_setup(g);
    g.light_position(0, Vec4f(1, 1, 1, 0));
    g.clip_plane(0, Vec4(1, 0.3, 0, 0.2));
    g.enable(Cap::ClipPlane0);
    g.matrix_mode(MatrixMode::Projection);
    g.load_identity();
    g.perspective(60, double(W) / H, 4.2, 20);  // the near plane cuts the sphere
    g.matrix_mode(MatrixMode::ModelView);
    g.light_model_two_side(true);
    sphere(g, 1.2, 24, 16);
  };
  Diff d = WEDGE_BOTH("clip", W, H, scene);
  CHECK_MATCHES_GL(d);
}

namespace {

// A textured quad seen in perspective (so minification varies across it), optionally fogged.
template <class G>
void textured_plane(G& g, std::shared_ptr<Texture> tex, TexEnvMode env) {
  g.clear_color(0.2f, 0.2f, 0.3f, 1);
  g.clear();
  camera(g, W, H);
  g.enable(Cap::DepthTest);
  g.enable(Cap::Texture2D);
  g.bind_texture(tex);
  g.tex_env_mode(env);
  g.tex_env_color(Vec4f(0.9f, 0.2f, 0.1f, 1));
  g.begin(Primitive::Quads);
  g.color(0.8f, 0.9f, 0.6f, 0.7f);
  g.tex_coord(0, 0), g.vertex(-3, -1, 2);
  g.tex_coord(4, 0), g.vertex(3, -1, 2);
  g.tex_coord(4, 8), g.vertex(3, -1, -12);
  g.tex_coord(0, 8), g.vertex(-3, -1, -12);
  g.end();
}

}  // namespace

TEST_CASE("wireframe (polygon mode line) and point mode match OpenGL", "[render][gl][wireframe]") {
  for (auto mode : {PolygonMode::Line, PolygonMode::Point}) {
    auto scene = [&](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      camera(g, W, H);
      g.polygon_mode(Face::FrontAndBack, mode);
      g.point_size(3);
      g.color(1, 1, 0.5f);
      sphere(g, 1.2, 12, 8);
    };
    Diff d = WEDGE_BOTH(mode == PolygonMode::Line ? "wire" : "pointmode", W, H, scene);
    CHECK_MATCHES_GL(d);
  }
}

void check_filters(int from, int to) {
  for (int f = from; f < to; ++f) {
    auto tex = Texture::checker(64, 8, Vec4f(1, 1, 1, 1), Vec4f(0.1f, 0.3f, 0.8f, 1));
    tex->min_filter = static_cast<TexFilter>(f);
    auto scene = [&](auto& g) { textured_plane(g, tex, TexEnvMode::Replace); };
    Diff d = WEDGE_BOTH("texfilter" + std::to_string(f), W, H, scene);
    INFO("filter " << f);
    CHECK_MATCHES_GL(d);
  }
}

TEST_CASE("nearest, linear and the two mipmap-nearest filters match OpenGL", "[render][gl][texture]") {
  check_filters(0, 4);
}

// Blending between two levels exposes the level-of-detail fraction, which llvmpipe takes from
// a piecewise-linear log2 (exact only at powers of two).
TEST_CASE("the two mipmap-linear filters match OpenGL", "[render][gl][texture]") {
  check_filters(4, 6);
  // A finer texture on a quad turned about the view axis, so that s and t both vary along x and y.
  for (int f = 4; f < 6; ++f) {
    auto tex = Texture::checker(128, 32, Vec4f(0.9f, 0.8f, 0.1f, 1), Vec4f(0.1f, 0.2f, 0.5f, 1));
    tex->min_filter = static_cast<TexFilter>(f);
    auto scene = [&](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      camera(g, W, H);
      g.enable(Cap::Texture2D);
      g.bind_texture(tex);
      g.tex_env_mode(TexEnvMode::Replace);
      g.rotate(35, 0, 1, 0);
      g.begin(Primitive::Quads);
      g.tex_coord(0, 0), g.vertex(-2, -1, 3);
      g.tex_coord(3, 0), g.vertex(2, -1.5, 3);
      g.tex_coord(3, 5), g.vertex(2.5, -1, -14);
      g.tex_coord(0, 5), g.vertex(-2.5, -0.5, -14);
      g.end();
    };
    Diff d = WEDGE_BOTH("texfilter_rot" + std::to_string(f), W, H, scene);
    INFO("filter " << f << ", turned quad");
    CHECK_MATCHES_GL(d);
  }
}

TEST_CASE("texture environment modes and formats match OpenGL", "[render][gl][texture]") {
  for (int fmt = 0; fmt < 3; ++fmt)
    for (int env = 0; env < 4; ++env) {
      auto tex = Texture::checker(32, 4, Vec4f(1, 0.8f, 0.2f, 0.9f), Vec4f(0.1f, 0.3f, 0.8f, 0.3f));
      tex->format = static_cast<TexFormat>(fmt);
      tex->min_filter = TexFilter::Linear;
      tex->mag_filter = TexFilter::Nearest;
      auto scene = [&](auto& g) { textured_plane(g, tex, static_cast<TexEnvMode>(env)); };
      Diff d = WEDGE_BOTH("texenv" + std::to_string(fmt) + std::to_string(env), W, H, scene);
      INFO("format " << fmt << " env " << env);
      CHECK_MATCHES_GL(d);
    }
}

TEST_CASE("texture wrap modes match OpenGL", "[render][gl][texture]") {
  for (int wrap = 0; wrap < 3; ++wrap) {
    auto tex = Texture::checker(16, 4, Vec4f(1, 1, 1, 1), Vec4f(0.8f, 0.1f, 0.1f, 1), false);
    tex->wrap_s = tex->wrap_t = static_cast<TexWrap>(wrap);
    tex->mag_filter = TexFilter::Linear;
    auto scene = [&](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      g.viewport(0, 0, W, H);
      g.enable(Cap::Texture2D);
      g.bind_texture(tex);
      g.tex_env_mode(TexEnvMode::Replace);
      g.begin(Primitive::Quads);
      g.tex_coord(-0.5, -0.5), g.vertex(-0.9, -0.9);
      g.tex_coord(1.5, -0.5), g.vertex(0.9, -0.9);
      g.tex_coord(1.5, 1.5), g.vertex(0.9, 0.9);
      g.tex_coord(-0.5, 1.5), g.vertex(-0.9, 0.9);
      g.end();
    };
    Diff d = WEDGE_BOTH("texwrap" + std::to_string(wrap), W, H, scene);
    INFO("wrap " << wrap);
    CHECK_MATCHES_GL(d);
  }
}

TEST_CASE("linear, exp and exp2 fog match OpenGL", "[render][gl][fog]") {
  for (int m = 0; m < 3; ++m) {
    auto tex = Texture::checker(64, 8, Vec4f(1, 1, 1, 1), Vec4f(0.1f, 0.3f, 0.8f, 1));
    tex->min_filter = TexFilter::Linear;
    auto scene = [&](auto& g) {
      g.enable(Cap::Fog);
      g.fog_mode(static_cast<FogMode>(m));
      g.fog_color(Vec4f(0.7f, 0.7f, 0.75f, 1));
      g.fog_start(3);
      g.fog_end(14);
      g.fog_density(0.15f);
      textured_plane(g, tex, TexEnvMode::Modulate);
    };
    Diff d = WEDGE_BOTH("fog" + std::to_string(m), W, H, scene);
    INFO("fog mode " << m);
    CHECK_MATCHES_GL(d);
  }
}

TEST_CASE("alpha blending and vertex arrays match OpenGL", "[render][gl][blend]") {
  std::vector<double> pos{-1, -1, 0, 1, -1, 0, 0, 1, 0, -0.5, -0.5, 0.5, 1.5, 0, 0.5, 0.2, 1.2, 0.5};
  std::vector<float> col{1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 1, 0.5f, 0, 0.5f, 1, 0.5f, 0, 1, 1, 0.3f};
  auto scene = [&](auto& g) {
    g.clear_color(0.1f, 0.1f, 0.1f, 1);
    g.clear();
    camera(g, W, H);
    g.enable(Cap::Blend);
    g.blend_func(BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha);
    VertexArrays a;
    a.positions = pos.data();
    a.colors = col.data();
    g.draw_arrays(Primitive::Triangles, a, 0, 6);
  };
  Diff d = WEDGE_BOTH("blend", W, H, scene);
  CHECK_MATCHES_GL(d);
}

TEST_CASE("texture coordinate generation (object-linear, eye-linear, sphere map) matches OpenGL", "[render][gl][texture]") {
  for (int mode = 0; mode < 3; ++mode) {
    auto tex = Texture::checker(32, 4, Vec4f(1, 1, 1, 1), Vec4f(0.8f, 0.6f, 0.5f, 1), false);
    tex->min_filter = TexFilter::Linear;
    auto scene = [&](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      camera(g, W, H);
      g.enable(Cap::DepthTest);
      g.enable(Cap::Texture2D);
      g.bind_texture(tex);
      g.tex_env_mode(TexEnvMode::Replace);
      const auto m = static_cast<TexGenMode>(mode);
      g.tex_gen(0, m, Vec4(0.5, 0, 0.2, 0.5));
      g.tex_gen(1, m, Vec4(0, 0.5, 0.1, 0.5));
      g.enable(Cap::TextureGenS);
      g.enable(Cap::TextureGenT);
      g.matrix_mode(MatrixMode::Texture);
      g.scale(1.5, 1.5, 1);
      g.matrix_mode(MatrixMode::ModelView);
      g.rotate(20, 0, 1, 0);
      sphere(g, 1.2, 24, 16);
    };
    Diff d = WEDGE_BOTH("texgen" + std::to_string(mode), W, H, scene);
    INFO("texgen mode " << mode);
    CHECK_MATCHES_GL(d);
  }
}

void check_points_lines(int from, int to) {
  for (int p = from; p < to; ++p) {
    auto scene = [&](auto& g) {
      g.clear_color(0, 0, 0, 1);
      g.clear();
      g.viewport(0, 0, W, H);
      g.point_size(p == 0 ? 1 : 3);
      g.line_width(p == 1 ? 1 : 3);
      g.begin(p == 0 || p == 2 ? Primitive::Points : p == 1 ? Primitive::LineStrip : Primitive::LineLoop);
      const double pts[6][2] = {{-0.83, -0.71}, {-0.52, 0.63}, {-0.13, -0.57}, {0.17, 0.74}, {0.42, -0.33}, {0.71, 0.52}};
      for (int i = 0; i < 6; ++i) {
        g.color(float(i % 3 == 0), float(i % 3 == 1), 0.5f);
        g.vertex(pts[i][0], pts[i][1]);
      }
      g.end();
    };
    Diff d = WEDGE_BOTH("pointline" + std::to_string(p), W, H, scene);
    INFO("case " << p << ": covered " << d.covered << ", outliers " << d.outliers);
    CHECK(d.covered > 5);
    CHECK(d.outliers <= d.covered / 1000);
  }
}

TEST_CASE("points of size 1 and 3 and 1-pixel lines match OpenGL", "[render][gl][primitives]") { check_points_lines(0, 3); }

// The joints of a wide line loop test the diamond-exit rule at each end of a wide line.
TEST_CASE("3-pixel-wide lines match OpenGL", "[render][gl][primitives]") { check_points_lines(3, 4); }

TEST_CASE("clear colours convert to 8 bits exactly as OpenGL (ties to even)", "[render][gl][framebuffer]") {
  // Every 1/2000 step of [0, 1], the tie points (k + 0.5) / 255 and their float neighbours, the
  // clamped ends; each clear compared bit for bit (0.3 -> 76, not lround's 77).
  std::vector<float> values;
  for (int i = 0; i <= 2000; ++i) values.push_back(float(i) / 2000);
  for (int k = 0; k < 255; ++k) {
    float tie = (k + 0.5f) / 255.0f;
    values.insert(values.end(), {tie, std::nextafter(tie, 0.0f), std::nextafter(tie, 1.0f)});
  }
  values.insert(values.end(), {0.3f, 0.7f, -0.25f, 1.5f});
  Context c(2, 2);
  oracle::GlContext g(2, 2);
  int mismatches = 0;
  for (std::size_t i = 0; i + 3 < values.size(); i += 4) {
    const float r = values[i], gr = values[i + 1], b = values[i + 2], a = values[i + 3];
    c.clear_color(r, gr, b, a);
    c.clear();
    g.clear_color(r, gr, b, a);
    g.clear();
    auto p = c.image().pixel(0, 0), q = g.image().pixel(0, 0);
    if (p != q) {
      if (++mismatches <= 5) FAIL_CHECK("clear (" << r << ", " << gr << ", " << b << ", " << a << "): wedge " << int(p[0]) << " " << int(p[1]) << " " << int(p[2]) << " " << int(p[3]) << ", GL " << int(q[0]) << " " << int(q[1]) << " " << int(q[2]) << " " << int(q[3]));
    }
  }
  CHECK(mismatches == 0);
}
