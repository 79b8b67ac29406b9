// wedge::render — the OpenGL-1.x-style software rasterizer. It knows only kernel/ (the Mesh).
// Its enumerations carry OpenGL's names, so state reads as it would in GL: a Context holds the
// whole GL state machine (matrix stacks, lights, materials, texture, fog, depth, blend, ...) and
// primitives go through it exactly as through glBegin/glEnd or glDrawArrays. No globals: any
// number of contexts may render at once on different threads.
#pragma once
#include <array>
#include <cmath>
#include <functional>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kernel/kernel.h"

namespace wedge::render {

enum class Primitive { Points, Lines, LineStrip, LineLoop, Triangles, TriangleStrip, TriangleFan, Quads, QuadStrip, Polygon };
enum class DepthFunc { Never, Less, Equal, LessEqual, Greater, NotEqual, GreaterEqual, Always };
enum class ShadeModel { Flat, Smooth, Phong };

using Vec4f = Eigen::Vector4f;

enum class MatrixMode { ModelView, Projection, Texture };
enum class Cap {
  DepthTest, CullFace, Lighting, ColorMaterial, Normalize, Fog, Texture2D, Blend, ScissorTest,
  TextureGenS, TextureGenT,
  Light0, Light1, Light2, Light3, Light4, Light5, Light6, Light7,
  ClipPlane0, ClipPlane1, ClipPlane2, ClipPlane3, ClipPlane4, ClipPlane5
};
inline Cap light_cap(int i) { return static_cast<Cap>(static_cast<int>(Cap::Light0) + i); }
inline Cap clip_plane_cap(int i) { return static_cast<Cap>(static_cast<int>(Cap::ClipPlane0) + i); }

enum class Face { Front, Back, FrontAndBack };
enum class FrontFace { CCW, CW };
enum class PolygonMode { Point, Line, Fill };
enum class ColorMaterialMode { Ambient, Diffuse, Specular, Emission, AmbientAndDiffuse };
enum class FogMode { Linear, Exp, Exp2 };
enum class BlendFactor { Zero, One, SrcAlpha, OneMinusSrcAlpha, DstAlpha, OneMinusDstAlpha, SrcColor, OneMinusSrcColor, DstColor, OneMinusDstColor };
enum class TexFilter { Nearest, Linear, NearestMipmapNearest, LinearMipmapNearest, NearestMipmapLinear, LinearMipmapLinear };
enum class TexWrap { Repeat, Clamp, ClampToEdge };
enum class TexEnvMode { Modulate, Replace, Decal, Blend };
enum class TexGenMode { ObjectLinear, EyeLinear, SphereMap };
enum class TexFormat { Luminance, RGB, RGBA };
// The rasteriser's vector code, chosen per Context: Auto takes AVX2 where the CPU has it (else
// SSE2), Sse2 keeps to SSE2. Both draw the same bits (tests/render/test_fragment_paths.cpp);
// Sse2 is there for those tests and for benchmarks.
enum class Simd { Auto, Sse2 };
// Whether this CPU runs AVX2 code (x86-64 with AVX2); what Simd::Auto asks.
bool cpu_has_avx2();

// An 8-bit RGBA image, row 0 at the TOP (as in PNG files).
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // width * height * 4
  std::array<std::uint8_t, 4> pixel(int x, int y) const {
    const std::uint8_t* p = &rgba[(std::size_t(y) * width + x) * 4];
    return {p[0], p[1], p[2], p[3]};
  }
};

// PNG through libspng. Writing goes to a temporary file renamed into place, so a failure never
// leaves a half-written file. Throws wedge::Error naming the path.
void write_png(const std::string& path, const Image& image);
// `max_pixels`: a larger image (by its header) is an error before anything is decoded.
Image read_png(const std::string& path, std::size_t max_pixels = std::size_t(16384) * 16384);
// A float image as PFM ("Pf", one channel, rows bottom to top as PFM stores them), written atomically.
void write_pfm(const std::string& path, int width, int height, const std::vector<float>& values_bottom_up);

// A 2D texture with its mipmap chain (built here by 2x2 box filtering, as gluBuild2DMipmaps).
struct Texture {
  TexFormat format = TexFormat::RGBA;
  std::vector<Image> levels;  // level 0 first; each Image row 0 is texture t = 0 (bottom)
  TexFilter min_filter = TexFilter::NearestMipmapLinear;  // GL's default
  TexFilter mag_filter = TexFilter::Linear;
  TexWrap wrap_s = TexWrap::Repeat, wrap_t = TexWrap::Repeat;
  Vec4f border = Vec4f(0, 0, 0, 0);

  // `image` rows are taken bottom-up (row 0 is t = 0); format says which channels count.
  static std::shared_ptr<Texture> from_image(const Image& image, TexFormat format, bool mipmaps = true);
  // An n x n checkerboard of `size` texels, colours a and b, starting with a at texel (0, 0).
  static std::shared_ptr<Texture> checker(int size, int n, const Vec4f& a, const Vec4f& b, bool mipmaps = true);
  // Loads a PNG (flipped so that the image's bottom row is t = 0).
  // A PNG file as a texture; at most kMaxTextureSide x kMaxTextureSide texels.
  static std::shared_ptr<Texture> load_png(const std::string& path, TexFormat format = TexFormat::RGBA, bool mipmaps = true);
  static constexpr int kMaxTextureSide = 8192;
  void build_mipmaps();
  // Filtered colour at (s, t) for level-of-detail lambda (log2 of the texel-per-pixel scale).
  Vec4f sample(float s, float t, float lambda) const;
  // Four fragments sharing one level of detail (a 2x2 quad, as GPUs take derivatives). s, t: 4 each
  // (already divided by q); out: 4 RGBA colours, 16 floats, bit-identical to four calls of sample().
  // `simd`: the vector code (the rasteriser passes its Context's choice); both give the same bits.
  void sample4(const float* s, const float* t, float lambda, float* out, Simd simd = Simd::Auto) const;
};

struct Light {
  Vec4f ambient{0, 0, 0, 1}, diffuse{0, 0, 0, 1}, specular{0, 0, 0, 1};
  Vec4f position{0, 0, 1, 0};       // eye coordinates
  Vec3 spot_direction{0, 0, -1};    // eye coordinates
  float spot_exponent = 0, spot_cutoff = 180;
  float constant_attenuation = 1, linear_attenuation = 0, quadratic_attenuation = 0;
};

struct Material {
  Vec4f ambient{0.2f, 0.2f, 0.2f, 1}, diffuse{0.8f, 0.8f, 0.8f, 1}, specular{0, 0, 0, 1}, emission{0, 0, 0, 1};
  float shininess = 0;
};

// A client-side vertex array set (glVertexPointer & co.). Empty arrays are disabled.
struct VertexArrays {
  const double* positions = nullptr; int position_size = 3;  // 2, 3 or 4 per vertex
  const double* normals = nullptr;                           // 3 per vertex
  const float* colors = nullptr; int color_size = 4;         // 3 or 4 per vertex
  const double* texcoords = nullptr; int texcoord_size = 2;  // 1..4 per vertex
};

class Context {
 public:
  // A framebuffer of width x height pixels (RGBA8 colour, float depth). The viewport and scissor
  // start as the whole framebuffer, every other state as OpenGL's initial state.
  Context(int width, int height);
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  ~Context();

  int width() const { return width_; }
  int height() const { return height_; }

  // --- framebuffer ---
  void clear_color(float r, float g, float b, float a);
  void clear_depth(double d);
  void clear(bool color = true, bool depth = true);
  void viewport(int x, int y, int w, int h);
  void depth_range(double n, double f);
  void scissor(int x, int y, int w, int h);
  void color_mask(bool r, bool g, bool b, bool a);
  // Pixel (x, y) with y = 0 at the BOTTOM row, as glReadPixels.
  std::array<std::uint8_t, 4> read_pixel(int x, int y) const;
  float read_depth(int x, int y) const;
  Image image() const;                 // the colour buffer, top row first
  const std::vector<float>& depth_buffer() const { return depth_; }  // bottom row first
  void write_png(const std::string& path) const;
  void write_depth_pfm(const std::string& path) const;

  // Rasterisation threads: with n > 1, primitives are binned into bands of rows drawn in
  // parallel (same image as one thread). Default 1.
  void threads(int n);
  int threads() const;
  // The vector code this context draws with (Auto: AVX2 where the CPU has it). Default Auto.
  void simd(Simd s);
  Simd simd() const;

  // --- state switches ---
  void enable(Cap cap);
  void disable(Cap cap);
  bool is_enabled(Cap cap) const;
  void depth_func(DepthFunc f);
  void depth_mask(bool write);
  void cull_face(Face f);
  void front_face(FrontFace f);
  void shade_model(ShadeModel m);
  void polygon_mode(Face face, PolygonMode mode);
  void point_size(float s);
  void line_width(float w);
  void blend_func(BlendFactor src, BlendFactor dst);
  // The plane a x + b y + c z + d w >= 0 in object coordinates, stored in eye coordinates
  // (transformed by the inverse of the current modelview matrix, as glClipPlane).
  void clip_plane(int i, const Vec4& plane);

  // --- matrices ---
  void matrix_mode(MatrixMode m);
  void load_identity();
  void load_matrix(const Mat4& m);
  void mult_matrix(const Mat4& m);
  void push_matrix();  // throws wedge::Error on overflow (depths 32 / 2 / 2)
  void pop_matrix();   // throws wedge::Error on underflow
  void translate(double x, double y, double z);
  void rotate(double deg, double x, double y, double z);
  void scale(double x, double y, double z);
  void frustum(double l, double r, double b, double t, double n, double f);
  void ortho(double l, double r, double b, double t, double n, double f);
  void perspective(double fovy, double aspect, double n, double f);
  void look_at(const Point3& eye, const Point3& center, const Vec3& up);
  const Mat4& matrix(MatrixMode m) const;

  // --- lighting ---
  // The position is transformed by the current modelview matrix, as glLightfv(GL_POSITION).
  void light_position(int i, const Vec4f& p);
  void light_spot_direction(int i, const Vec3& d);
  void light_ambient(int i, const Vec4f& c);
  void light_diffuse(int i, const Vec4f& c);
  void light_specular(int i, const Vec4f& c);
  void light_spot(int i, float exponent, float cutoff);
  void light_attenuation(int i, float constant, float linear, float quadratic);
  const Light& light(int i) const;
  void light_model_ambient(const Vec4f& c);
  void light_model_local_viewer(bool on);
  void light_model_two_side(bool on);
  void material_ambient(Face f, const Vec4f& c);
  void material_diffuse(Face f, const Vec4f& c);
  void material_specular(Face f, const Vec4f& c);
  void material_emission(Face f, const Vec4f& c);
  void material_shininess(Face f, float s);
  void material(Face f, const Material& m);
  void color_material(Face f, ColorMaterialMode mode);

  // --- texturing ---
  void bind_texture(std::shared_ptr<const Texture> t);
  void tex_env_mode(TexEnvMode m);
  void tex_env_color(const Vec4f& c);
  // mode for s and t; the plane applies to object- or eye-linear (eye planes are transformed by
  // the inverse modelview at the time of the call).
  void tex_gen(int coord /*0 = s, 1 = t*/, TexGenMode mode, const Vec4& plane = Vec4(0, 0, 0, 0));

  // --- fog ---
  void fog_mode(FogMode m);
  void fog_color(const Vec4f& c);
  void fog_start(float s);
  void fog_end(float e);
  void fog_density(float d);

  // --- immediate mode ---
  void begin(Primitive p);
  void end();
  void vertex(double x, double y, double z = 0, double w = 1);
  void normal(double x, double y, double z);
  void color(float r, float g, float b, float a = 1);
  void tex_coord(double s, double t, double r = 0, double q = 1);

  // --- vertex arrays ---
  void draw_arrays(Primitive p, const VertexArrays& arrays, int first, int count);
  void draw_elements(Primitive p, const VertexArrays& arrays, const std::uint32_t* indices, int count);

  struct State;  // everything else (defined in context.cpp)

 private:
  int width_, height_;
  std::vector<std::uint8_t> color_;  // RGBA8, bottom row first
  std::vector<float> depth_;
  std::unique_ptr<State> s_;
  friend struct Pipeline;
};

// --- two-step texture mapping (Bier & Sloan 1986): an intermediate surface (cylinder, sphere
// or box) around the object gets the (u, v) parametrisation, then each vertex takes the (u, v)
// of the point where the ray from the centre through it (cylinder/sphere) or its dominant
// normal axis (box) meets that surface. `axis` is the cylinder's axis; the centre is the mesh's
// bounding-box centre. Returns a copy of the mesh with uvs set.
enum class UvMapping { Cylinder, Sphere, Box };
Mesh with_uv_mapping(const Mesh& mesh, UvMapping mapping, const Vec3& axis = Vec3(0, 0, 1));

// --- a mesh drawn with a camera, lights and a material (the path Lua's render{} takes) -------
struct LightSpec {
  enum class Type { Directional, Point, Spot } type = Type::Directional;
  Vec3 position{0, 0, 0};
  Vec3 direction{0, 0, -1};  // the way the light travels
  Vec4f ambient{0, 0, 0, 1}, diffuse{1, 1, 1, 1}, specular{1, 1, 1, 1};
  Vec3 attenuation{1, 0, 0};
  float cutoff = 45, exponent = 0;
  bool eye_space = false;
};

struct Camera {
  bool orthographic = false;
  Point3 eye{5, 5, 5}, center{0, 0, 0};
  Vec3 up{0, 0, 1};
  double fovy = 45, near = 0.1, far = 100;
  double left = -1, right = 1, bottom = -1, top = 1;  // orthographic box
  bool fit = true;  // if true, near and far are fitted to the scene's bounds
  // An oblique parallel projection's shear in eye space (see oblique()); the projection matrix is
  // Ortho * shear. Identity for every other camera.
  Mat4 shear = Mat4::Identity();
  // If true, the window (the ortho box, or the frustum's window, then possibly off-axis) is fitted
  // around the scene's bounds as this camera sees them, plus `margin` times the larger extent on
  // each side; left/right/bottom/top and fovy are then unused.
  bool fit_window = false;
  double margin = 0.06;
};

// The course's views (camera.cpp has the frames and formulas):
//   multiview orthographic: "front" (along +Y, Z up), "top" (down -Z, Y up), "side" (along -X);
//   axonometric: "iso" = "isometric", "dimetric" (X and Z whole, Y at half; rx= or ry= choose
//     another), "trimetric" (rx=, ry=: the rotations of axonometric(), default 20 and -30);
//   oblique: "cavalier" (ratio 1), "cabinet" (ratio 1/2), "oblique" (ratio=, default 1/2), the
//     receding axis (world Y) drawn at angle= degrees (default 45) from the picture's x axis;
//   perspective: "one_point", "two_point" (angle=: the view's azimuth, default 30), "three_point";
//     distance= the eye's distance from the centre in bounding radii (default 3).
// NaN means "not given". Options a view does not take are errors.
struct ViewParams {
  double rx = NAN, ry = NAN, angle = NAN, ratio = NAN, distance = NAN;
};
// A named view looking at `bounds`, its window fitted to them. Throws wedge::Error naming the
// view and the bad option.
Camera named_view(const std::string& name, const Box3& bounds, const ViewParams& params);
Camera named_view(const std::string& name, const Box3& bounds);
const std::vector<std::string>& view_names();
// The axonometric rotation Rx(rx) * Ry(ry) (degrees) in the view frame (x right, y up, z towards
// the viewer), to be followed by an orthographic projection along z.
Mat4 axonometric(double rx, double ry);
// The oblique parallel projection's shear in the view frame: the receding axis (-z, into the
// picture) drawn at `angle` degrees from x with lengths times `ratio` (1 cavalier, 1/2 cabinet);
// z is kept for depth. Follow it with an orthographic projection along z.
Mat4 oblique(double angle, double ratio);

// What render_scene loads for camera `c` drawing `bounds` into an image of aspect width/height:
// the modelview (look_at) and projection matrices; also the eye space in which visibility sorting
// is done (the view after any oblique shear, where projectors run along -z) and, for parallel
// projections, the projectors' world direction.
struct CameraMatrices {
  Mat4 view, projection, sort_view;
  Vec3 projector;
};
// A fitted window (fit_window) is fitted around `points` (the scene's vertices in world
// coordinates) if given, else around the corners of `bounds`.
CameraMatrices camera_matrices(const Camera& c, const Box3& bounds, double aspect, const std::vector<Point3>& points = {});

// How hidden surfaces are removed: the z-buffer, or drawing back to front without a depth test
// (painter's algorithm: triangles sorted by their farthest eye-space depth, the order then
// corrected by Newell, Newell & Sancha's overlap tests, no triangle split; or a BSP tree built
// over the world-space triangles, splitting those that straddle a node's plane, traversed back
// to front from the eye). The last two give the z-buffer's image on scenes without cyclic
// overlap or interpenetration, with or without culling (for the BSP tree with flat shading: a
// split triangle's pieces share its face normal); only the BSP tree also handles cyclic overlap.
enum class Visibility { ZBuffer, Painter, Bsp };

struct RenderOptions {
  int width = 800, height = 600;
  Camera camera;
  std::vector<LightSpec> lights;  // empty: one headlight-like directional light from the camera
  Vec4f ambient{0.2f, 0.2f, 0.2f, 1};
  bool local_viewer = false, two_side = false;
  ShadeModel shading = ShadeModel::Smooth;
  bool wireframe = false;
  std::string cull = "back";     // "none" | "back" | "front" | "both"
  DepthFunc depth = DepthFunc::Less;
  bool fog = false;
  FogMode fog_mode = FogMode::Linear;
  float fog_start = 0, fog_end = 1, fog_density = 1;
  Vec4f fog_color{1, 1, 1, 1};
  int antialias = 1;  // supersampling factor per axis
  Vec4f background{1, 1, 1, 1};
  Visibility visibility = Visibility::ZBuffer;
  int threads = 0;  // rasterisation threads; 0 = all cores
  Simd simd = Simd::Auto;  // the vector code (the same image either way)
  // Progress of long work, if set: called on the calling thread with the triangles handed to the
  // pipeline so far and their total, every kProgressTriangles and once at the end.
  std::function<void(std::size_t done, std::size_t total)> progress;
  static constexpr std::size_t kProgressTriangles = 16384;
};

struct DrawItem {
  const Mesh* mesh = nullptr;
  // Polylines drawn as unlit lines in the material's diffuse colour (a wireframe model), placed by
  // `transform` as the mesh is; either may be absent.
  const std::vector<std::vector<Point3>>* lines = nullptr;
  Material material;
  std::shared_ptr<const Texture> texture;
  Mat4 transform = Mat4::Identity();
};

// Every vertex of the items, placed by its item's transform (what a fitted window is fitted to).
std::vector<Point3> world_points(const std::vector<DrawItem>& items);

// Renders the items; smooth normals are computed (area-weighted) only for meshes without them;
// flat shading uses each triangle's geometric normal.
Image render_scene(const std::vector<DrawItem>& items, const RenderOptions& options);
// The same, also handing back the depth buffer (window z in 0..1, bottom row first, at the
// supersampled size: width * antialias by height * antialias).
Image render_scene(const std::vector<DrawItem>& items, const RenderOptions& options, std::vector<float>* depth);
// A multi-view orthographic sheet (drawing{} in API.md): the named views on a grid of
// `columns` (0: ceil(sqrt(views))) cells, each view's orthographic box fitted to the items'
// bounds seen along it, with a one-pixel border and the view's name if asked. `render` gives
// lights, shading, background and antialiasing; its size and camera are set per cell.
struct DrawingOptions {
  std::vector<std::string> views{"front", "top", "side", "iso"};
  std::vector<ViewParams> view_params;  // empty, or one per view
  int width = 800, height = 600;  // the whole sheet
  int columns = 0;
  bool border = true, labels = true;
  // The items' edges as lines over the shaded faces: the edges between different source faces
  // (face ids) that do not meet tangentially, or, without ids, where the faces meet at more than
  // `crease_angle` degrees, plus boundary edges and each view's silhouette. Hidden edges are left
  // out, or drawn dashed.
  bool edges = true;
  bool hidden_dashed = false;
  double crease_angle = 30;
  std::vector<std::string> titles;  // empty, or one per view (default: the view's title)
  RenderOptions render;
  std::function<void()> view_done;  // called after each view is drawn (progress), if set
};
// The edges of a mesh that a drawing or a wireframe shows: those between different source faces
// (face ids), or, without ids, where the faces meet at more than `crease_deg` degrees, and the
// boundary (or non-manifold) edges. Vertices are welded by position first. Without
// `tangent_edges` (a drawing), an edge between two faces that meet tangentially (their shading
// normals, or without those their triangles' normals, agree within half a degree at both ends, as
// on a cylinder's seam) is left out; a wireframe keeps it, as an edge of the solid's faces.
std::vector<std::array<Point3, 2>> feature_edges(const Mesh& mesh, double crease_deg, bool tangent_edges = true);
// Segments joined end to end into polylines (a closed loop repeats its first point at the end).
std::vector<std::vector<Point3>> polylines(const std::vector<std::array<Point3, 2>>& segments);

// The title a drawing gives a view: "FRONT", "ISOMETRIC", "CABINET", "ONE-POINT PERSPECTIVE", ...
std::string view_title(const std::string& name);
Image render_drawing(const std::vector<DrawItem>& items, const DrawingOptions& options);
// Text in the built-in 5x7 bitmap font (6 x 7 pixels a character cell, times `scale`), top-left
// corner at (x, y); characters outside A-Z, 0-9 and "-._:" are left blank. Pixels outside the
// image are skipped.
void draw_text(Image& image, int x, int y, const std::string& text, const std::array<std::uint8_t, 4>& color,
               int scale = 1);
int text_width(const std::string& text, int scale = 1);
// Box-filter downsampling by `factor` per axis (the supersampling resolve).
Image downsample(const Image& image, int factor);

}  // namespace wedge::render
