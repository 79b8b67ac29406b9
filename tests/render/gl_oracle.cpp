// Mesa OSMesa backend of the oracle (see gl_oracle.h). Each method is the one GL call it names.
#include "gl_oracle.h"

#include <GL/gl.h>
#include <GL/glu.h>
#include <GL/osmesa.h>

#include <cstring>
#include <stdexcept>

namespace wedge::render::oracle {

namespace {

GLenum cap_enum(Cap c) {
  int i = static_cast<int>(c);
  if (c >= Cap::Light0 && c <= Cap::Light7) return GL_LIGHT0 + (i - static_cast<int>(Cap::Light0));
  if (c >= Cap::ClipPlane0 && c <= Cap::ClipPlane5) return GL_CLIP_PLANE0 + (i - static_cast<int>(Cap::ClipPlane0));
  switch (c) {
    case Cap::DepthTest: return GL_DEPTH_TEST;
    case Cap::CullFace: return GL_CULL_FACE;
    case Cap::Lighting: return GL_LIGHTING;
    case Cap::ColorMaterial: return GL_COLOR_MATERIAL;
    case Cap::Normalize: return GL_NORMALIZE;
    case Cap::Fog: return GL_FOG;
    case Cap::Texture2D: return GL_TEXTURE_2D;
    case Cap::Blend: return GL_BLEND;
    case Cap::ScissorTest: return GL_SCISSOR_TEST;
    case Cap::TextureGenS: return GL_TEXTURE_GEN_S;
    case Cap::TextureGenT: return GL_TEXTURE_GEN_T;
    default: break;
  }
  throw std::logic_error("cap");
}

GLenum face_enum(Face f) { return f == Face::Front ? GL_FRONT : f == Face::Back ? GL_BACK : GL_FRONT_AND_BACK; }

GLenum prim_enum(Primitive p) {
  static const GLenum e[] = {GL_POINTS, GL_LINES, GL_LINE_STRIP, GL_LINE_LOOP, GL_TRIANGLES, GL_TRIANGLE_STRIP,
                             GL_TRIANGLE_FAN, GL_QUADS, GL_QUAD_STRIP, GL_POLYGON};
  return e[static_cast<int>(p)];
}

GLenum blend_enum(BlendFactor f) {
  static const GLenum e[] = {GL_ZERO, GL_ONE, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_DST_ALPHA,
                             GL_ONE_MINUS_DST_ALPHA, GL_SRC_COLOR, GL_ONE_MINUS_SRC_COLOR, GL_DST_COLOR,
                             GL_ONE_MINUS_DST_COLOR};
  return e[static_cast<int>(f)];
}

GLenum filter_enum(TexFilter f) {
  static const GLenum e[] = {GL_NEAREST, GL_LINEAR, GL_NEAREST_MIPMAP_NEAREST, GL_LINEAR_MIPMAP_NEAREST,
                             GL_NEAREST_MIPMAP_LINEAR, GL_LINEAR_MIPMAP_LINEAR};
  return e[static_cast<int>(f)];
}

GLenum wrap_enum(TexWrap w) { return w == TexWrap::Repeat ? GL_REPEAT : w == TexWrap::Clamp ? GL_CLAMP : GL_CLAMP_TO_EDGE; }

}  // namespace

struct GlContext::Impl {
  OSMesaContext ctx = nullptr;
  std::vector<std::uint8_t> buffer;
  int width, height;
  GLuint tex = 0;
  std::shared_ptr<const Texture> bound;
};

GlContext::GlContext(int width, int height) : impl_(std::make_unique<Impl>()) {
  impl_->width = width, impl_->height = height;
  impl_->buffer.assign(std::size_t(width) * height * 4, 0);
  impl_->ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!impl_->ctx) throw std::runtime_error("OSMesaCreateContextExt failed");
  if (!OSMesaMakeCurrent(impl_->ctx, impl_->buffer.data(), GL_UNSIGNED_BYTE, width, height))
    throw std::runtime_error("OSMesaMakeCurrent failed");
  glHint(GL_PERSPECTIVE_CORRECTION_HINT, GL_NICEST);
}

GlContext::~GlContext() {
  if (impl_->tex) glDeleteTextures(1, &impl_->tex);
  OSMesaDestroyContext(impl_->ctx);
}

void GlContext::clear_color(float r, float g, float b, float a) { glClearColor(r, g, b, a); }
void GlContext::clear_depth(double d) { glClearDepth(d); }
void GlContext::clear(bool color, bool depth) { glClear((color ? GL_COLOR_BUFFER_BIT : 0) | (depth ? GL_DEPTH_BUFFER_BIT : 0)); }
void GlContext::viewport(int x, int y, int w, int h) { glViewport(x, y, w, h); }
void GlContext::depth_range(double n, double f) { glDepthRange(n, f); }
void GlContext::scissor(int x, int y, int w, int h) { glScissor(x, y, w, h); }
void GlContext::enable(Cap cap) { glEnable(cap_enum(cap)); }
void GlContext::disable(Cap cap) { glDisable(cap_enum(cap)); }
void GlContext::depth_func(DepthFunc f) { glDepthFunc(GL_NEVER + static_cast<int>(f)); }
void GlContext::depth_mask(bool write) { glDepthMask(write ? GL_TRUE : GL_FALSE); }
void GlContext::cull_face(Face f) { glCullFace(face_enum(f)); }
void GlContext::front_face(FrontFace f) { glFrontFace(f == FrontFace::CCW ? GL_CCW : GL_CW); }
void GlContext::shade_model(ShadeModel m) {
  if (m == ShadeModel::Phong) throw std::logic_error("Phong shading is not OpenGL 1.x");
  glShadeModel(m == ShadeModel::Flat ? GL_FLAT : GL_SMOOTH);
}
void GlContext::polygon_mode(Face face, PolygonMode mode) {
  glPolygonMode(face_enum(face), mode == PolygonMode::Point ? GL_POINT : mode == PolygonMode::Line ? GL_LINE : GL_FILL);
}
void GlContext::point_size(float s) { glPointSize(s); }
void GlContext::line_width(float w) { glLineWidth(w); }
void GlContext::blend_func(BlendFactor src, BlendFactor dst) { glBlendFunc(blend_enum(src), blend_enum(dst)); }
void GlContext::clip_plane(int i, const Vec4& p) {
  GLdouble eq[4] = {p[0], p[1], p[2], p[3]};
  glClipPlane(GL_CLIP_PLANE0 + i, eq);
}

void GlContext::matrix_mode(MatrixMode m) {
  glMatrixMode(m == MatrixMode::ModelView ? GL_MODELVIEW : m == MatrixMode::Projection ? GL_PROJECTION : GL_TEXTURE);
}
void GlContext::load_identity() { glLoadIdentity(); }
void GlContext::push_matrix() { glPushMatrix(); }
void GlContext::pop_matrix() { glPopMatrix(); }
void GlContext::translate(double x, double y, double z) { glTranslated(x, y, z); }
void GlContext::rotate(double deg, double x, double y, double z) { glRotated(deg, x, y, z); }
void GlContext::scale(double x, double y, double z) { glScaled(x, y, z); }
void GlContext::frustum(double l, double r, double b, double t, double n, double f) { glFrustum(l, r, b, t, n, f); }
void GlContext::ortho(double l, double r, double b, double t, double n, double f) { glOrtho(l, r, b, t, n, f); }
void GlContext::perspective(double fovy, double aspect, double n, double f) { gluPerspective(fovy, aspect, n, f); }
void GlContext::look_at(const Point3& e, const Point3& c, const Vec3& u) {
  gluLookAt(e.x(), e.y(), e.z(), c.x(), c.y(), c.z(), u.x(), u.y(), u.z());
}

static void lightv(int i, GLenum pname, const Vec4f& v) {
  GLfloat f[4] = {v[0], v[1], v[2], v[3]};
  glLightfv(GL_LIGHT0 + i, pname, f);
}
void GlContext::light_position(int i, const Vec4f& p) { lightv(i, GL_POSITION, p); }
void GlContext::light_spot_direction(int i, const Vec3& d) {
  GLfloat f[3] = {float(d.x()), float(d.y()), float(d.z())};
  glLightfv(GL_LIGHT0 + i, GL_SPOT_DIRECTION, f);
}
void GlContext::light_ambient(int i, const Vec4f& c) { lightv(i, GL_AMBIENT, c); }
void GlContext::light_diffuse(int i, const Vec4f& c) { lightv(i, GL_DIFFUSE, c); }
void GlContext::light_specular(int i, const Vec4f& c) { lightv(i, GL_SPECULAR, c); }
void GlContext::light_spot(int i, float exponent, float cutoff) {
  glLightf(GL_LIGHT0 + i, GL_SPOT_EXPONENT, exponent);
  glLightf(GL_LIGHT0 + i, GL_SPOT_CUTOFF, cutoff);
}
void GlContext::light_attenuation(int i, float c, float l, float q) {
  glLightf(GL_LIGHT0 + i, GL_CONSTANT_ATTENUATION, c);
  glLightf(GL_LIGHT0 + i, GL_LINEAR_ATTENUATION, l);
  glLightf(GL_LIGHT0 + i, GL_QUADRATIC_ATTENUATION, q);
}
void GlContext::light_model_ambient(const Vec4f& c) {
  GLfloat f[4] = {c[0], c[1], c[2], c[3]};
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, f);
}
void GlContext::light_model_local_viewer(bool on) { glLightModeli(GL_LIGHT_MODEL_LOCAL_VIEWER, on); }
void GlContext::light_model_two_side(bool on) { glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, on); }
static void materialv(Face f, GLenum pname, const Vec4f& v) {
  GLfloat a[4] = {v[0], v[1], v[2], v[3]};
  glMaterialfv(face_enum(f), pname, a);
}
void GlContext::material_ambient(Face f, const Vec4f& c) { materialv(f, GL_AMBIENT, c); }
void GlContext::material_diffuse(Face f, const Vec4f& c) { materialv(f, GL_DIFFUSE, c); }
void GlContext::material_specular(Face f, const Vec4f& c) { materialv(f, GL_SPECULAR, c); }
void GlContext::material_emission(Face f, const Vec4f& c) { materialv(f, GL_EMISSION, c); }
void GlContext::material_shininess(Face f, float s) { glMaterialf(face_enum(f), GL_SHININESS, s); }
void GlContext::color_material(Face f, ColorMaterialMode mode) {
  static const GLenum e[] = {GL_AMBIENT, GL_DIFFUSE, GL_SPECULAR, GL_EMISSION, GL_AMBIENT_AND_DIFFUSE};
  glColorMaterial(face_enum(f), e[static_cast<int>(mode)]);
}

void GlContext::bind_texture(std::shared_ptr<const Texture> t) {
  if (!impl_->tex) glGenTextures(1, &impl_->tex);
  glBindTexture(GL_TEXTURE_2D, impl_->tex);
  if (impl_->bound == t) return;  // already uploaded (keeps benchmark frames free of uploads)
  impl_->bound = t;
  GLint internal = t->format == TexFormat::Luminance ? GL_LUMINANCE : t->format == TexFormat::RGB ? GL_RGB : GL_RGBA;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  for (std::size_t l = 0; l < t->levels.size(); ++l)
    glTexImage2D(GL_TEXTURE_2D, GLint(l), internal, t->levels[l].width, t->levels[l].height, 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, t->levels[l].rgba.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, GLint(t->levels.size()) - 1);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter_enum(t->min_filter));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter_enum(t->mag_filter));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap_enum(t->wrap_s));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap_enum(t->wrap_t));
  GLfloat b[4] = {t->border[0], t->border[1], t->border[2], t->border[3]};
  glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, b);
}
void GlContext::tex_env_mode(TexEnvMode m) {
  static const GLint e[] = {GL_MODULATE, GL_REPLACE, GL_DECAL, GL_BLEND};
  glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, e[static_cast<int>(m)]);
}
void GlContext::tex_env_color(const Vec4f& c) {
  GLfloat f[4] = {c[0], c[1], c[2], c[3]};
  glTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, f);
}
void GlContext::tex_gen(int coord, TexGenMode mode, const Vec4& p) {
  GLenum c = coord == 0 ? GL_S : GL_T;
  GLint m = mode == TexGenMode::ObjectLinear ? GL_OBJECT_LINEAR : mode == TexGenMode::EyeLinear ? GL_EYE_LINEAR : GL_SPHERE_MAP;
  glTexGeni(c, GL_TEXTURE_GEN_MODE, m);
  GLdouble plane[4] = {p[0], p[1], p[2], p[3]};
  if (mode == TexGenMode::ObjectLinear) glTexGendv(c, GL_OBJECT_PLANE, plane);
  if (mode == TexGenMode::EyeLinear) glTexGendv(c, GL_EYE_PLANE, plane);
}

void GlContext::fog_mode(FogMode m) { glFogi(GL_FOG_MODE, m == FogMode::Linear ? GL_LINEAR : m == FogMode::Exp ? GL_EXP : GL_EXP2); }
void GlContext::fog_color(const Vec4f& c) {
  GLfloat f[4] = {c[0], c[1], c[2], c[3]};
  glFogfv(GL_FOG_COLOR, f);
}
void GlContext::fog_start(float s) { glFogf(GL_FOG_START, s); }
void GlContext::fog_end(float e) { glFogf(GL_FOG_END, e); }
void GlContext::fog_density(float d) { glFogf(GL_FOG_DENSITY, d); }

void GlContext::begin(Primitive p) { glBegin(prim_enum(p)); }
void GlContext::end() { glEnd(); }
void GlContext::vertex(double x, double y, double z, double w) { glVertex4d(x, y, z, w); }
void GlContext::normal(double x, double y, double z) { glNormal3d(x, y, z); }
void GlContext::color(float r, float g, float b, float a) { glColor4f(r, g, b, a); }
void GlContext::tex_coord(double s, double t, double r, double q) { glTexCoord4d(s, t, r, q); }

void GlContext::draw_arrays(Primitive p, const VertexArrays& a, int first, int count) {
  glEnableClientState(GL_VERTEX_ARRAY);
  glVertexPointer(a.position_size, GL_DOUBLE, 0, a.positions);
  if (a.normals) glEnableClientState(GL_NORMAL_ARRAY), glNormalPointer(GL_DOUBLE, 0, a.normals);
  if (a.colors) glEnableClientState(GL_COLOR_ARRAY), glColorPointer(a.color_size, GL_FLOAT, 0, a.colors);
  if (a.texcoords)
    glEnableClientState(GL_TEXTURE_COORD_ARRAY), glTexCoordPointer(a.texcoord_size, GL_DOUBLE, 0, a.texcoords);
  glDrawArrays(prim_enum(p), first, count);
  glDisableClientState(GL_VERTEX_ARRAY);
  glDisableClientState(GL_NORMAL_ARRAY);
  glDisableClientState(GL_COLOR_ARRAY);
  glDisableClientState(GL_TEXTURE_COORD_ARRAY);
}

void GlContext::finish() { glFinish(); }

Image GlContext::image() {
  glFinish();
  Image im;
  im.width = impl_->width, im.height = impl_->height;
  im.rgba.resize(impl_->buffer.size());
  const std::size_t row = std::size_t(im.width) * 4;
  for (int y = 0; y < im.height; ++y)
    std::memcpy(&im.rgba[(im.height - 1 - y) * row], &impl_->buffer[y * row], row);
  return im;
}

}  // namespace wedge::render::oracle
