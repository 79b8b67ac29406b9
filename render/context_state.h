// The state of a render::Context: OpenGL 1.x's state vector, with GL's initial values.
// Private to render/ (not installed).
#pragma once
#include <bitset>

#include "render/render.h"

namespace wedge::render {

namespace raster {
struct Scratch;  // raster.h
}

struct InVertex {
  Vec4 position;       // object coordinates
  Vec3 normal;
  Vec4f color;
  Vec4 tex;
};

struct Context::State {
  int vp_x = 0, vp_y = 0, vp_w = 0, vp_h = 0;
  double depth_near = 0, depth_far = 1;
  int sc_x = 0, sc_y = 0, sc_w = 0, sc_h = 0;
  Vec4f clear_color{0, 0, 0, 0};
  double clear_depth = 1;
  std::array<bool, 4> color_mask{true, true, true, true};
  std::bitset<32> enabled;
  DepthFunc depth_func = DepthFunc::Less;
  bool depth_mask = true;
  Face cull_face = Face::Back;
  FrontFace front_face = FrontFace::CCW;
  ShadeModel shade = ShadeModel::Smooth;
  PolygonMode poly_front = PolygonMode::Fill, poly_back = PolygonMode::Fill;
  float point_size = 1, line_width = 1;
  BlendFactor blend_src = BlendFactor::One, blend_dst = BlendFactor::Zero;
  std::array<Vec4, 6> clip_planes{};

  MatrixMode mode = MatrixMode::ModelView;
  std::array<std::vector<Mat4>, 3> stacks;

  std::array<Light, 8> lights;
  Vec4f model_ambient{0.2f, 0.2f, 0.2f, 1};
  bool local_viewer = false, two_side = false;
  std::array<Material, 2> material;  // front, back
  ColorMaterialMode cm_mode = ColorMaterialMode::AmbientAndDiffuse;
  Face cm_face = Face::FrontAndBack;

  std::shared_ptr<const Texture> texture;
  TexEnvMode env_mode = TexEnvMode::Modulate;
  Vec4f env_color{0, 0, 0, 0};
  std::array<TexGenMode, 2> gen_mode{TexGenMode::EyeLinear, TexGenMode::EyeLinear};
  std::array<Vec4, 2> obj_plane{Vec4(1, 0, 0, 0), Vec4(0, 1, 0, 0)};
  std::array<Vec4, 2> eye_plane{Vec4(1, 0, 0, 0), Vec4(0, 1, 0, 0)};

  FogMode fog_mode = FogMode::Exp;
  Vec4f fog_color{0, 0, 0, 0};
  float fog_start = 0, fog_end = 1, fog_density = 1;

  int threads = 1;  // rasterisation threads (bands of rows)
  Simd simd = Simd::Auto;  // the vector code (Raster::avx2)
  // The rasteriser's buffers kept between draws and its task arena (made by the first draw),
  // and draw_arrays' and draw_elements' batch of fetched vertices: this Context's alone.
  std::shared_ptr<raster::Scratch> scratch;
  std::vector<InVertex> batch;

  bool in_begin = false;
  Primitive prim = Primitive::Points;
  std::vector<InVertex> verts;
  Vec4f cur_color{1, 1, 1, 1};
  Vec3 cur_normal{0, 0, 1};
  Vec4 cur_tex{0, 0, 0, 1};

  bool on(Cap c) const { return enabled[static_cast<int>(c)]; }
  const Mat4& top(MatrixMode m) const { return stacks[static_cast<int>(m)].back(); }
};

// Element i of client vertex arrays as a pipeline vertex: what the arrays lack comes from the
// current normal, colour and texture coordinate, missing components from (0, 0, 0, 1).
inline InVertex fetch_vertex(const Context::State& s, const VertexArrays& a, std::size_t i) {
  InVertex v{Vec4(0, 0, 0, 1), s.cur_normal, s.cur_color, s.cur_tex};
  for (int k = 0; k < a.position_size; ++k) v.position[k] = a.positions[i * a.position_size + k];
  if (a.normals) v.normal = Vec3(a.normals[i * 3], a.normals[i * 3 + 1], a.normals[i * 3 + 2]);
  if (a.colors) {
    v.color = Vec4f(0, 0, 0, 1);
    for (int k = 0; k < a.color_size; ++k) v.color[k] = a.colors[i * a.color_size + k];
  }
  if (a.texcoords) {
    v.tex = Vec4(0, 0, 0, 1);
    for (int k = 0; k < a.texcoord_size; ++k) v.tex[k] = a.texcoords[i * a.texcoord_size + k];
  }
  return v;
}

// For tests: the lighting equation's x^y (x >= 0, y > 0) on n values, by the vector code the
// lighting runs (8 lanes when `avx2` and the CPU has AVX2, else 4) and the scalar one (gl_pow).
void lighting_pow(const float* x, std::size_t n, float y, float* out, bool avx2);
float lighting_pow(float x, float y);
// For tests: the vertex lighting's eye normals (3 doubles each), as vertex_attrs computes them.
void lighting_normals(const Mat3& nmat, const double* n, std::size_t count, bool normalize, double* out);

// Runs a batch of vertices as one primitive through the pipeline (assembly.cpp).
void run_primitive(Context::State& s, int width, int height, std::uint8_t* color, float* depth, Primitive p,
                   const std::vector<InVertex>& verts);
// Independent triangles (count vertices) straight from client arrays: element first + i, or
// indices[first + i] when indices is not null. Returns false, drawing nothing, when the state
// needs the general path (then the caller fetches InVertex batches for run_primitive).
bool run_triangle_arrays(Context::State& s, int width, int height, std::uint8_t* color, float* depth,
                         const VertexArrays& a, const std::uint32_t* indices, int first, int count);

}  // namespace wedge::render
