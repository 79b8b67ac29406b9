// The vertex lighting's own pow (2^(y log2 x), 4 or 8 lanes at once) against std::pow, and
// the lighting's two builds (SSE2, four lanes; AVX2, eight lanes, chosen at run time), which
// must give the same bits as each other and as the scalar lighting of the general path.
#include <catch2/catch.hpp>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "simd_skip.h"
#include "render/context_state.h"  // lighting_pow

using namespace wedge;
using namespace wedge::render;

namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("the lighting's pow is within 1e-7 of std::pow, and its 4- and 8-lane builds agree bit for bit",
          "[render][lighting][simd]") {
  // x: a dense grid of [0, 1] (the lighting's range), every 1024th float of [2^-40, 1], and values
  // beyond 1 up to 2^40; y: GL's shininess and spot exponent range [0, 128] (y = 0 is GL's 1,
  // handled by the callers).
  std::vector<float> xs;
  for (int i = 0; i <= (1 << 19); ++i) xs.push_back(float(i) / float(1 << 19));
  for (std::uint32_t b = 0x2b800000u; b <= 0x3f800000u; b += 1024) {  // 2^-40 .. 1
    float x;
    std::memcpy(&x, &b, sizeof x);
    xs.push_back(x);
  }
  for (float x = 1.0f; x <= 0x1p40f; x *= 1.0003f) xs.push_back(x);
  const float ys[] = {0.001f, 0.1f, 0.5f, 1, 1.5f, 2, 3, 4.75f, 8, 10, 16.5f, 20, 30, 50, 64, 100, 127.25f, 128};
  std::vector<float> p4(xs.size()), p8(xs.size());
  const bool wide = !test::avx2_missing("the lighting pow's 8-lane build");
  double worst = 0;
  for (float y : ys) {
    lighting_pow(xs.data(), xs.size(), y, p4.data(), false);
    lighting_pow(xs.data(), xs.size(), y, p8.data(), true);
    int bad_bits = 0, bad = 0;
    for (std::size_t i = 0; i < xs.size(); ++i) {
      const float x = xs[i], got = p4[i];
      bad_bits += (wide && !same_bits(got, p8[i])) || !same_bits(got, lighting_pow(x, y));
      const double want = std::pow(double(x), double(y));
      if (want > FLT_MAX) {
        bad += got != INFINITY;
      } else if (want >= FLT_MIN) {
        const double rel = std::abs(got - want) / want;
        worst = std::max(worst, rel);
        bad += !(rel < 1e-7);  // (rounded once to float: half a unit in the last place is 6e-8)
      } else {
        bad += !(std::abs(got - want) <= 0x1p-149);  // subnormal or zero: within the last place
      }
    }
    INFO("y = " << y);
    CHECK(bad_bits == 0);
    CHECK(bad == 0);
  }
  WARN("largest relative error against std::pow (normal results): " << worst);
  // GL's special values: 0^y = 0 (y > 0), 1^y = 1, inf^y = inf, NaN stays NaN; subnormal x.
  for (float y : ys) {
    CHECK(lighting_pow(0.0f, y) == 0.0f);
    CHECK(lighting_pow(1.0f, y) == 1.0f);
    CHECK(lighting_pow(INFINITY, y) == INFINITY);
    CHECK(std::isnan(lighting_pow(NAN, y)));
    const double want = std::pow(double(1e-40f), double(y));
    if (want >= FLT_MIN) CHECK(std::abs(lighting_pow(1e-40f, y) - want) / want < 1e-7);
  }
}

namespace {

// A sphere of independent triangles (positions double as normals), drawn through client arrays.
struct Sphere {
  std::vector<double> pos;
  std::vector<float> col;
  Sphere(int st, int sl) {
    auto vert = [&](int i, int j) {
      const double t = kPi * i / st - kPi / 2, p = 2 * kPi * j / sl;
      pos.insert(pos.end(), {std::cos(t) * std::cos(p), std::cos(t) * std::sin(p), std::sin(t)});
      col.insert(col.end(), {float(0.5 + 0.5 * std::cos(p)), float(i) / float(st), 0.3f, 1});
    };
    for (int i = 0; i < st; ++i)
      for (int j = 0; j < sl; ++j)
        vert(i, j), vert(i, j + 1), vert(i + 1, j + 1), vert(i, j), vert(i + 1, j + 1), vert(i + 1, j);
  }
};

enum class Path { Auto, Sse2, General };

template <class Setup>
Image draw(const Sphere& sp, Path path, Setup setup) {
  Context c(160, 120);
  if (path == Path::Sse2) c.simd(Simd::Sse2);
  c.clear_color(0.1f, 0.1f, 0.1f, 1);
  c.clear();
  c.matrix_mode(MatrixMode::Projection);
  c.perspective(45, 160.0 / 120, 1.1, 10);
  c.matrix_mode(MatrixMode::ModelView);
  c.look_at(Point3(0.3, 0.5, 2.6), Point3(0, 0, 0), Vec3(0, 1, 0));
  c.enable(Cap::DepthTest);
  c.enable(Cap::Lighting);
  c.enable(Cap::Light0);
  c.light_position(0, Vec4f(2, 2, 3, 1));
  c.material_specular(Face::FrontAndBack, Vec4f(0.5f, 0.5f, 0.5f, 1));
  c.material_shininess(Face::FrontAndBack, 30);
  // The general path (process_vertex and light_vertex): a user clip plane that clips nothing
  // takes the triangles off the chunk path.
  if (path == Path::General) {
    c.clip_plane(0, Vec4(0, 0, 1, 100));
    c.enable(Cap::ClipPlane0);
  }
  setup(c);
  VertexArrays va;
  va.positions = sp.pos.data(), va.normals = sp.pos.data(), va.colors = sp.col.data();
  c.draw_arrays(Primitive::Triangles, va, 0, int(sp.pos.size() / 3));
  return c.image();
}

template <class Setup>
void check_paths(const char* what, Setup setup) {
  const Sphere sp(23, 37);  // vertex counts that are not multiples of 8
  const Image ref = draw(sp, Path::Auto, setup);
  INFO(what);
  if (test::cpu_has_avx2())  // (without AVX2 this is the reference's own path)
    CHECK(draw(sp, Path::Sse2, setup).rgba == ref.rgba);
  CHECK(draw(sp, Path::General, setup).rgba == ref.rgba);
}

}  // namespace

TEST_CASE("the vertex lighting's SSE2 and AVX2 builds give the same bits, and the general path's",
          "[render][lighting][simd]") {
  test::avx2_missing("the vertex lighting's AVX2 build (the general path is still compared)");
  check_paths("point light, specular", [](Context&) {});
  check_paths("back faces culled", [](Context& c) { c.enable(Cap::CullFace); });
  check_paths("spot lights, attenuation, local viewer, two-sided, scaled normals", [](Context& c) {
    c.light_model_local_viewer(true);
    c.light_model_two_side(true);
    c.enable(Cap::Normalize);
    c.scale(1.3, 0.8, 1.1);
    c.material_shininess(Face::Back, 7.5f);
    c.light_spot_direction(0, Vec3(-0.5, -0.5, -1));
    c.light_spot(0, 12.5f, 40);
    c.light_attenuation(0, 1, 0.1f, 0.05f);
    c.enable(Cap::Light1);
    c.light_position(1, Vec4f(-1, 0.5, 2, 1));
    c.light_diffuse(1, Vec4f(0.3f, 0.6f, 0.9f, 1));
    c.light_specular(1, Vec4f(1, 1, 1, 1));
    c.light_spot_direction(1, Vec3(0.4, -0.2, -1));
    c.light_spot(1, 0, 60);
    c.enable(Cap::Light2);
    c.light_position(2, Vec4f(0, 1, 1, 0));  // directional
  });
  check_paths("colour material, two-sided, fog (full attribute sets)", [](Context& c) {
    c.enable(Cap::ColorMaterial);
    c.color_material(Face::FrontAndBack, ColorMaterialMode::AmbientAndDiffuse);
    c.light_model_two_side(true);
    c.enable(Cap::Fog);
    c.fog_mode(FogMode::Linear);
    c.fog_start(1), c.fog_end(5);
  });
  check_paths("colour material on the specular term, shininess 128", [](Context& c) {
    c.enable(Cap::ColorMaterial);
    c.color_material(Face::Front, ColorMaterialMode::Specular);
    c.material_shininess(Face::FrontAndBack, 128);
  });
}

TEST_CASE("the vertex lighting's vector normal transform gives Eigen's bits", "[render][lighting][simd]") {
  // nmat * n and its normalisation in double, as vertex_attrs computes them with Eigen.
  std::uint64_t seed = 12345;
  auto rnd = [&] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return double(std::int64_t(seed >> 11) - (std::int64_t(1) << 52)) / double(std::int64_t(1) << 50);  // [-4, 4)
  };
  int bad = 0;
  for (int it = 0; it < 2000; ++it) {
    Mat3 m;
    for (int k = 0; k < 9; ++k) m(k % 3, k / 3) = rnd();
    std::vector<double> n(3 * 37), got(n.size());
    for (double& x : n) x = rnd();
    for (bool normalize : {false, true}) {
      lighting_normals(m, n.data(), 37, normalize, got.data());
      for (int i = 0; i < 37; ++i) {
        Vec3 want = m * Vec3(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
        if (normalize) {
          const double len = want.norm();
          if (len > 0) want /= len;
        }
        for (int k = 0; k < 3; ++k) bad += std::memcmp(&got[3 * i + k], &want[k], sizeof(double)) != 0;
      }
    }
  }
  CHECK(bad == 0);
}
