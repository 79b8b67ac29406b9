// render::Context: the state machine side of the OpenGL 1.x pipeline (setters with GL's
// semantics: light positions and clip planes are transformed by the modelview matrix current at
// the time of the call; matrix operations multiply on the right as glMultMatrix).
#include <cmath>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include <tbb/parallel_for.h>

#include "render/context_state.h"
#include "render/raster.h"

namespace wedge::render {

namespace {
constexpr std::array<std::size_t, 3> kStackDepth{32, 2, 2};

// Asks for transparent huge pages on the 2 MiB-aligned part of a buffer not yet touched (Linux,
// where they are given on request: THP "madvise"). A 1920x1080 frame's depth and colour buffers
// are 8 MiB each, and a mesh's triangles reach them in no screen order: with 4 KiB pages nearly
// every triangle's pixels miss the TLB (perf showed the fragment loop waiting on its first depth
// read, prefetches included). A hint only: where it is refused, nothing changes but the speed.
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t(1) << 21;
  const std::uintptr_t b = reinterpret_cast<std::uintptr_t>(v.data()), e = b + n * sizeof(T);
  const std::uintptr_t hb = (b + kHuge - 1) & ~(kHuge - 1), he = e & ~(kHuge - 1);
  if (he > hb) madvise(reinterpret_cast<void*>(hb), he - hb, MADV_HUGEPAGE);
#endif
}

void check_light(int i) {
  if (i < 0 || i >= 8) fail("light index ", i, " out of range 0..7");
}
}  // namespace

Context::Context(int width, int height) : width_(width), height_(height), s_(std::make_unique<State>()) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    fail("render context size ", width, "x", height, " must be within 1..16384");
  reserve_huge(color_, std::size_t(width) * height * 4);
  reserve_huge(depth_, std::size_t(width) * height);
  color_.assign(std::size_t(width) * height * 4, 0);
  depth_.assign(std::size_t(width) * height, 1.0f);
  s_->vp_w = s_->sc_w = width;
  s_->vp_h = s_->sc_h = height;
  for (auto& st : s_->stacks) st.push_back(Mat4::Identity());
  s_->lights[0].diffuse = Vec4f(1, 1, 1, 1);
  s_->lights[0].specular = Vec4f(1, 1, 1, 1);
}

Context::~Context() = default;

void Context::clear_color(float r, float g, float b, float a) { s_->clear_color = Vec4f(r, g, b, a); }
void Context::clear_depth(double d) { s_->clear_depth = std::clamp(d, 0.0, 1.0); }

void Context::clear(bool color, bool depth) {
  int x0 = 0, y0 = 0, x1 = width_, y1 = height_;
  if (s_->on(Cap::ScissorTest)) {
    x0 = std::max(x0, s_->sc_x), y0 = std::max(y0, s_->sc_y);
    x1 = std::min(x1, s_->sc_x + s_->sc_w), y1 = std::min(y1, s_->sc_y + s_->sc_h);
  }
  // Float to 8-bit unorm as Mesa converts a clear colour: the clamped value times 255 in float,
  // rounded to nearest with ties to even (0.3 -> 76.5 -> 76, where lround gives 77). Checked
  // against OSMesa/llvmpipe for 100k values in [0, 1] and the tie points (k + 0.5) / 255.
  std::array<std::uint8_t, 4> c;
  for (int k = 0; k < 4; ++k) {
    const float v = s_->clear_color[k];
    c[k] = !(v > 0.0f) ? 0 : v >= 1.0f ? 255 : std::uint8_t(std::lrint(v * 255.0f));
  }
  const auto& m = s_->color_mask;
  const bool all = m[0] && m[1] && m[2] && m[3];
  if (x1 <= x0 || y1 <= y0) return;
  const bool clear_depth = depth && s_->depth_mask;
  if (all || !color) {
    // Whole pixels and depth words, row by row (or in one run when the rows are contiguous).
    alignas(64) std::uint8_t pattern[512];
    for (std::size_t i = 0; i < sizeof(pattern); i += 4) std::memcpy(pattern + i, c.data(), 4);
    const float dv = float(s_->clear_depth);
    const bool full_rows = x0 == 0 && x1 == width_;
    // Rows ya..yb (one run when the rows are contiguous).
    auto clear_rows = [&](int ya, int yb) {
      const int rows = full_rows ? 1 : yb - ya;
      const std::size_t run = full_rows ? std::size_t(width_) * (yb - ya) : std::size_t(x1 - x0);
      for (int r = 0; r < rows; ++r) {
        const std::size_t at = std::size_t(ya + r) * width_ + x0;
        if (color) {
          // Copies of a small pattern held in L1 (byte copies: no aliasing casts).
          std::uint8_t* p = color_.data() + at * 4;
          const std::size_t bytes = run * 4;
          for (std::size_t done = 0; done < bytes; done += sizeof(pattern))
            std::memcpy(p + done, pattern, std::min(sizeof(pattern), bytes - done));
        }
        if (clear_depth) std::fill_n(depth_.data() + at, run, dv);
      }
    };
    // With threads, a large clear by stretches of rows on the Context's arena: at 1920x1080 it
    // is a millisecond of memory writes, which one thread alone made a serial part of every
    // frame; and it wakes the arena's workers just before the draws that follow need them.
    const int threads = s_->threads;
    if (threads > 1 && std::int64_t(x1 - x0) * (y1 - y0) >= 256 * 256) {
      if (!s_->scratch) s_->scratch = std::make_shared<raster::Scratch>();
      const int pieces = 4 * threads, rows = y1 - y0;
      s_->scratch->arena(threads).execute([&] {
        tbb::parallel_for(0, pieces, [&](int k) { clear_rows(y0 + rows * k / pieces, y0 + rows * (k + 1) / pieces); });
      });
      return;
    }
    clear_rows(y0, y1);
    return;
  }
  for (int y = y0; y < y1; ++y) {
    std::uint8_t* row = &color_[(std::size_t(y) * width_) * 4];
    float* drow = &depth_[std::size_t(y) * width_];
    for (int x = x0; x < x1; ++x) {
      if (color) {
        if (all) std::memcpy(row + x * 4, c.data(), 4);
        else
          for (int k = 0; k < 4; ++k)
            if (m[k]) row[x * 4 + k] = c[k];
      }
      if (depth && s_->depth_mask) drow[x] = float(s_->clear_depth);
    }
  }
}

void Context::viewport(int x, int y, int w, int h) {
  if (w < 0 || h < 0) fail("viewport size ", w, "x", h, " must not be negative");
  s_->vp_x = x, s_->vp_y = y, s_->vp_w = w, s_->vp_h = h;
}
void Context::depth_range(double n, double f) {
  s_->depth_near = std::clamp(n, 0.0, 1.0);
  s_->depth_far = std::clamp(f, 0.0, 1.0);
}
void Context::scissor(int x, int y, int w, int h) {
  if (w < 0 || h < 0) fail("scissor size ", w, "x", h, " must not be negative");
  s_->sc_x = x, s_->sc_y = y, s_->sc_w = w, s_->sc_h = h;
}
void Context::color_mask(bool r, bool g, bool b, bool a) { s_->color_mask = {r, g, b, a}; }

std::array<std::uint8_t, 4> Context::read_pixel(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) fail("read_pixel(", x, ", ", y, ") outside the framebuffer");
  const std::uint8_t* p = &color_[(std::size_t(y) * width_ + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}
float Context::read_depth(int x, int y) const {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) fail("read_depth(", x, ", ", y, ") outside the framebuffer");
  return depth_[std::size_t(y) * width_ + x];
}

Image Context::image() const {
  Image im;
  im.width = width_, im.height = height_;
  im.rgba.resize(color_.size());
  const std::size_t row = std::size_t(width_) * 4;
  for (int y = 0; y < height_; ++y)
    std::memcpy(&im.rgba[(height_ - 1 - y) * row], &color_[y * row], row);
  return im;
}

void Context::write_png(const std::string& path) const { render::write_png(path, image()); }
void Context::write_depth_pfm(const std::string& path) const { write_pfm(path, width_, height_, depth_); }

void Context::threads(int n) {
  if (n < 1 || n > 256) fail("threads must be within 1..256, got ", n);
  s_->threads = n;
}
int Context::threads() const { return s_->threads; }
void Context::simd(Simd s) { s_->simd = s; }
Simd Context::simd() const { return s_->simd; }

void Context::enable(Cap cap) { s_->enabled.set(static_cast<int>(cap)); }
void Context::disable(Cap cap) { s_->enabled.reset(static_cast<int>(cap)); }
bool Context::is_enabled(Cap cap) const { return s_->on(cap); }
void Context::depth_func(DepthFunc f) { s_->depth_func = f; }
void Context::depth_mask(bool write) { s_->depth_mask = write; }
void Context::cull_face(Face f) { s_->cull_face = f; }
void Context::front_face(FrontFace f) { s_->front_face = f; }
void Context::shade_model(ShadeModel m) { s_->shade = m; }
void Context::polygon_mode(Face face, PolygonMode mode) {
  if (face != Face::Back) s_->poly_front = mode;
  if (face != Face::Front) s_->poly_back = mode;
}
void Context::point_size(float v) {
  if (!(v > 0)) fail("point size must be positive, got ", v);
  s_->point_size = v;
}
void Context::line_width(float w) {
  if (!(w > 0)) fail("line width must be positive, got ", w);
  s_->line_width = w;
}
void Context::blend_func(BlendFactor src, BlendFactor dst) { s_->blend_src = src, s_->blend_dst = dst; }
void Context::clip_plane(int i, const Vec4& plane) {
  if (i < 0 || i >= 6) fail("clip plane index ", i, " out of range 0..5");
  // A plane p (row vector) in object space is p * M^-1 in eye space.
  s_->clip_planes[i] = (plane.transpose() * inverse(s_->top(MatrixMode::ModelView))).transpose();
}

// --- matrices ---
void Context::matrix_mode(MatrixMode m) { s_->mode = m; }
static Mat4& current(Context::State& s) { return s.stacks[static_cast<int>(s.mode)].back(); }
void Context::load_identity() { current(*s_) = Mat4::Identity(); }
void Context::load_matrix(const Mat4& m) { current(*s_) = m; }
void Context::mult_matrix(const Mat4& m) { current(*s_) = current(*s_) * m; }
void Context::push_matrix() {
  auto& st = s_->stacks[static_cast<int>(s_->mode)];
  if (st.size() >= kStackDepth[static_cast<int>(s_->mode)])
    fail("push_matrix: stack overflow (depth ", kStackDepth[static_cast<int>(s_->mode)], ")");
  st.push_back(st.back());
}
void Context::pop_matrix() {
  auto& st = s_->stacks[static_cast<int>(s_->mode)];
  if (st.size() <= 1) fail("pop_matrix: stack underflow");
  st.pop_back();
}
void Context::translate(double x, double y, double z) { mult_matrix(wedge::translate(Vec3(x, y, z))); }
void Context::rotate(double deg, double x, double y, double z) { mult_matrix(wedge::rotate(deg, Vec3(x, y, z))); }
void Context::scale(double x, double y, double z) { mult_matrix(wedge::scale(Vec3(x, y, z))); }
void Context::frustum(double l, double r, double b, double t, double n, double f) { mult_matrix(wedge::frustum(l, r, b, t, n, f)); }
void Context::ortho(double l, double r, double b, double t, double n, double f) { mult_matrix(wedge::ortho(l, r, b, t, n, f)); }
void Context::perspective(double fovy, double aspect, double n, double f) { mult_matrix(wedge::perspective(fovy, aspect, n, f)); }
void Context::look_at(const Point3& eye, const Point3& center, const Vec3& up) { mult_matrix(wedge::look_at(eye, center, up)); }
const Mat4& Context::matrix(MatrixMode m) const { return s_->top(m); }

// --- lighting ---
void Context::light_position(int i, const Vec4f& p) {
  check_light(i);
  s_->lights[i].position = (s_->top(MatrixMode::ModelView) * p.cast<double>()).cast<float>();
}
void Context::light_spot_direction(int i, const Vec3& d) {
  check_light(i);
  s_->lights[i].spot_direction = s_->top(MatrixMode::ModelView).topLeftCorner<3, 3>() * d;
}
void Context::light_ambient(int i, const Vec4f& c) { check_light(i), s_->lights[i].ambient = c; }
void Context::light_diffuse(int i, const Vec4f& c) { check_light(i), s_->lights[i].diffuse = c; }
void Context::light_specular(int i, const Vec4f& c) { check_light(i), s_->lights[i].specular = c; }
void Context::light_spot(int i, float exponent, float cutoff) {
  check_light(i);
  if (exponent < 0 || exponent > 128) fail("spot exponent ", exponent, " must be within 0..128");
  if (!((cutoff >= 0 && cutoff <= 90) || cutoff == 180)) fail("spot cutoff ", cutoff, " must be within 0..90 or 180");
  s_->lights[i].spot_exponent = exponent, s_->lights[i].spot_cutoff = cutoff;
}
void Context::light_attenuation(int i, float c, float l, float q) {
  check_light(i);
  if (c < 0 || l < 0 || q < 0) fail("light attenuation factors must not be negative");
  s_->lights[i].constant_attenuation = c, s_->lights[i].linear_attenuation = l, s_->lights[i].quadratic_attenuation = q;
}
const Light& Context::light(int i) const {
  check_light(i);
  return s_->lights[i];
}
void Context::light_model_ambient(const Vec4f& c) { s_->model_ambient = c; }
void Context::light_model_local_viewer(bool on) { s_->local_viewer = on; }
void Context::light_model_two_side(bool on) { s_->two_side = on; }

template <class F>
static void each_face(Context::State& s, Face f, F&& fn) {
  if (f != Face::Back) fn(s.material[0]);
  if (f != Face::Front) fn(s.material[1]);
}
void Context::material_ambient(Face f, const Vec4f& c) { each_face(*s_, f, [&](Material& m) { m.ambient = c; }); }
void Context::material_diffuse(Face f, const Vec4f& c) { each_face(*s_, f, [&](Material& m) { m.diffuse = c; }); }
void Context::material_specular(Face f, const Vec4f& c) { each_face(*s_, f, [&](Material& m) { m.specular = c; }); }
void Context::material_emission(Face f, const Vec4f& c) { each_face(*s_, f, [&](Material& m) { m.emission = c; }); }
void Context::material_shininess(Face f, float v) {
  if (v < 0 || v > 128) fail("shininess ", v, " must be within 0..128");
  each_face(*s_, f, [&](Material& m) { m.shininess = v; });
}
void Context::material(Face f, const Material& mat) {
  if (mat.shininess < 0 || mat.shininess > 128) fail("shininess ", mat.shininess, " must be within 0..128");
  each_face(*s_, f, [&](Material& m) { m = mat; });
}
void Context::color_material(Face f, ColorMaterialMode mode) { s_->cm_face = f, s_->cm_mode = mode; }

// --- texturing and fog ---
void Context::bind_texture(std::shared_ptr<const Texture> t) { s_->texture = std::move(t); }
void Context::tex_env_mode(TexEnvMode m) { s_->env_mode = m; }
void Context::tex_env_color(const Vec4f& c) { s_->env_color = c; }
void Context::tex_gen(int coord, TexGenMode mode, const Vec4& plane) {
  if (coord < 0 || coord > 1) fail("tex_gen coordinate ", coord, " must be 0 (s) or 1 (t)");
  s_->gen_mode[coord] = mode;
  if (mode == TexGenMode::ObjectLinear) s_->obj_plane[coord] = plane;
  if (mode == TexGenMode::EyeLinear)
    s_->eye_plane[coord] = (plane.transpose() * inverse(s_->top(MatrixMode::ModelView))).transpose();
}
void Context::fog_mode(FogMode m) { s_->fog_mode = m; }
void Context::fog_color(const Vec4f& c) { s_->fog_color = c; }
void Context::fog_start(float v) { s_->fog_start = v; }
void Context::fog_end(float v) { s_->fog_end = v; }
void Context::fog_density(float d) {
  if (d < 0) fail("fog density must not be negative, got ", d);
  s_->fog_density = d;
}

// --- immediate mode ---
void Context::begin(Primitive p) {
  if (s_->in_begin) fail("begin called inside begin/end");
  s_->in_begin = true;
  s_->prim = p;
  s_->verts.clear();
}
void Context::end() {
  if (!s_->in_begin) fail("end called without begin");
  s_->in_begin = false;
  run_primitive(*s_, width_, height_, color_.data(), depth_.data(), s_->prim, s_->verts);
  s_->verts.clear();
}
void Context::vertex(double x, double y, double z, double w) {
  if (!s_->in_begin) fail("vertex called outside begin/end");
  s_->verts.push_back({Vec4(x, y, z, w), s_->cur_normal, s_->cur_color, s_->cur_tex});
}
void Context::normal(double x, double y, double z) { s_->cur_normal = Vec3(x, y, z); }
void Context::color(float r, float g, float b, float a) { s_->cur_color = Vec4f(r, g, b, a); }
void Context::tex_coord(double s, double t, double r, double q) { s_->cur_tex = Vec4(s, t, r, q); }

// --- vertex arrays ---
static void check_arrays(const VertexArrays& a) {
  if (!a.positions) fail("draw: the position array is required");
  if (a.position_size < 2 || a.position_size > 4) fail("draw: position size ", a.position_size, " must be 2, 3 or 4");
  if (a.colors && (a.color_size < 3 || a.color_size > 4)) fail("draw: colour size ", a.color_size, " must be 3 or 4");
  if (a.texcoords && (a.texcoord_size < 1 || a.texcoord_size > 4)) fail("draw: texcoord size must be 1..4");
}

void Context::draw_arrays(Primitive p, const VertexArrays& a, int first, int count) {
  check_arrays(a);
  if (first < 0 || count < 0) fail("draw_arrays: negative first or count");
  if (p == Primitive::Triangles &&
      run_triangle_arrays(*s_, width_, height_, color_.data(), depth_.data(), a, nullptr, first, count))
    return;
  // Independent primitives go through the pipeline in batches, so memory stays bounded.
  const int group = p == Primitive::Triangles ? 3 : p == Primitive::Lines ? 2 : p == Primitive::Points ? 1
                  : p == Primitive::Quads ? 4 : 0;
  const int batch = group ? group * 4096 : count;
  std::vector<InVertex>& v = s_->batch;  // kept between draws: no page faults per frame
  for (int start = 0; start < count; start += batch) {
    const int n = std::min(batch, count - start);
    v.resize(n);
    for (int i = 0; i < n; ++i) v[i] = fetch_vertex(*s_, a, std::size_t(first + start + i));
    run_primitive(*s_, width_, height_, color_.data(), depth_.data(), p, v);
  }
}

void Context::draw_elements(Primitive p, const VertexArrays& a, const std::uint32_t* indices, int count) {
  check_arrays(a);
  if (count < 0) fail("draw_elements: negative count");
  if (p == Primitive::Triangles &&
      run_triangle_arrays(*s_, width_, height_, color_.data(), depth_.data(), a, indices, 0, count))
    return;
  const int group = p == Primitive::Triangles ? 3 : p == Primitive::Lines ? 2 : p == Primitive::Points ? 1
                  : p == Primitive::Quads ? 4 : 0;
  const int batch = group ? group * 4096 : count;
  std::vector<InVertex>& v = s_->batch;  // kept between draws: no page faults per frame
  for (int start = 0; start < count; start += batch) {
    const int n = std::min(batch, count - start);
    v.resize(n);
    for (int i = 0; i < n; ++i) v[i] = fetch_vertex(*s_, a, indices[start + i]);
    run_primitive(*s_, width_, height_, color_.data(), depth_.data(), p, v);
  }
}

}  // namespace wedge::render
