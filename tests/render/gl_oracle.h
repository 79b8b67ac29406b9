// The OpenGL oracle: Mesa's OpenGL through OSMesa, behind the same method names as
// render::Context, so one scene function (a template over the backend) draws the same scene in
// both and the tests compare the pixels. Only GL and GLU calls here: nothing of wedge's pipeline.
#pragma once
#include <memory>

#include "render/render.h"

namespace wedge::render::oracle {

class GlContext {
 public:
  GlContext(int width, int height);
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  void clear_color(float r, float g, float b, float a);
  void clear_depth(double d);
  void clear(bool color = true, bool depth = true);
  void viewport(int x, int y, int w, int h);
  void depth_range(double n, double f);
  void scissor(int x, int y, int w, int h);
  void enable(Cap cap);
  void disable(Cap cap);
  void depth_func(DepthFunc f);
  void depth_mask(bool write);
  void cull_face(Face f);
  void front_face(FrontFace f);
  void shade_model(ShadeModel m);  // Phong is not GL: refused
  void polygon_mode(Face face, PolygonMode mode);
  void point_size(float s);
  void line_width(float w);
  void blend_func(BlendFactor src, BlendFactor dst);
  void clip_plane(int i, const Vec4& plane);

  void matrix_mode(MatrixMode m);
  void load_identity();
  void push_matrix();
  void pop_matrix();
  void translate(double x, double y, double z);
  void rotate(double deg, double x, double y, double z);
  void scale(double x, double y, double z);
  void frustum(double l, double r, double b, double t, double n, double f);
  void ortho(double l, double r, double b, double t, double n, double f);
  void perspective(double fovy, double aspect, double n, double f);
  void look_at(const Point3& eye, const Point3& center, const Vec3& up);

  void light_position(int i, const Vec4f& p);
  void light_spot_direction(int i, const Vec3& d);
  void light_ambient(int i, const Vec4f& c);
  void light_diffuse(int i, const Vec4f& c);
  void light_specular(int i, const Vec4f& c);
  void light_spot(int i, float exponent, float cutoff);
  void light_attenuation(int i, float constant, float linear, float quadratic);
  void light_model_ambient(const Vec4f& c);
  void light_model_local_viewer(bool on);
  void light_model_two_side(bool on);
  void material_ambient(Face f, const Vec4f& c);
  void material_diffuse(Face f, const Vec4f& c);
  void material_specular(Face f, const Vec4f& c);
  void material_emission(Face f, const Vec4f& c);
  void material_shininess(Face f, float s);
  void color_material(Face f, ColorMaterialMode mode);

  void bind_texture(std::shared_ptr<const Texture> t);
  void tex_env_mode(TexEnvMode m);
  void tex_env_color(const Vec4f& c);
  void tex_gen(int coord, TexGenMode mode, const Vec4& plane = Vec4(0, 0, 0, 0));

  void fog_mode(FogMode m);
  void fog_color(const Vec4f& c);
  void fog_start(float s);
  void fog_end(float e);
  void fog_density(float d);

  void begin(Primitive p);
  void end();
  void vertex(double x, double y, double z = 0, double w = 1);
  void normal(double x, double y, double z);
  void color(float r, float g, float b, float a = 1);
  void tex_coord(double s, double t, double r = 0, double q = 1);
  void draw_arrays(Primitive p, const VertexArrays& arrays, int first, int count);

  Image image();  // top row first, as render::Context::image()
  void finish();  // glFinish

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace wedge::render::oracle
