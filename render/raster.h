// The rasterizer's private header: the state of one draw (Raster) and the records that flow
// between the stages of the OpenGL 1.x fixed-function pipeline, following the OpenGL 1.5
// specification (Segal & Akeley), chapters 2-4. Private to render/ (not installed). The stages,
// each in a file named for it (the declarations below are grouped by those files):
//   vertex.cpp          object -> eye (modelview), normal by the inverse transpose, lighting (2.14.1:
//                       emission + global ambient + per light attenuation * spot * (ambient +
//                       diffuse + specular), clamped per vertex), texgen and the texture matrix,
//                       eye -> clip; 4 vertices at a time (SSE2) or 16 (AVX2)
//   assembly.cpp        primitives by type, with GL's provoking vertex for flat shading (table 2.12);
//                       facing and culling by the signed window-space area (2.14.1 / 3.5.1)
//   clip.cpp            in homogeneous clip space before the divide: Sutherland-Hodgman against
//                       -w <= x, y, z <= w and the user planes (in eye space), with edge flags so
//                       that polygon-mode lines skip the edges clipping made; lines parametrically
//   fragments.cpp       triangle setup (edge functions in 24.8 fixed point with a top-left tie
//                       rule, perspective-correct attribute planes: a/w and 1/w interpolated
//                       linearly, 3.5), small triangles pixel by pixel, and the fragment loop one
//                       pixel at a time (huge triangles, no SSE2)
//   quad_loop.cpp       the quad fragment loop, written once for 4 lanes (one 2x2 quad; SSE2)
//                       and 8 lanes (two quads side by side; AVX2)
//   triangle_run.cpp    runs of small triangles set up several at once
//   depth_test.h        the depth test (z-buffer): 24-bit quantisation, the depth function
//   lines.cpp           lines (a diamond-exit DDA) and points (squares)
//   bands.cpp           queued primitives drawn by bands of rows on several threads
//   triangles.cpp       the batched path for independent filled triangles from arrays
// and, per fragment (below, in Raster): texturing with the env mode, fog (3.10), blending, colour
// mask. Per-pixel Phong (beyond GL 1.x) evaluates the same lighting equation per fragment on the
// interpolated eye-space normal and position.
//
// Notation.
//   PVert        a vertex after the vertex stage: clip coordinates and kAttrs floats of attributes
//   a[...]       the attribute layout: kFront, kBack (RGBA lit colours of each side), kTex (s t r
//                q), kFog (eye distance), kEye (eye position), kNormal (eye normal)
//   WinVert      a vertex in window coordinates (x, y, z in [0, 1], 1/w_clip) with its attributes
//   grid         coverage is decided on window x, y snapped to 1/256 pixel (24.8 fixed point, as
//                llvmpipe); pixel (px, py) has its centre at (px + 1/2, py + 1/2), window y up
//   E_i, A, B    edge function of the edge opposite vertex i, and its steps per pixel in x and y
//   quad         a 2x2 block of pixels at even (x, y): lane 0 (x, y), 1 (x+1, y), 2 (x, y+1), 3
//                (x+1, y+1); the 8-lane (AVX2) loop takes two quads side by side (lanes 4-7 at
//                x + 2)
//   lanes        F4/F8/D2/D4/X2: see simd.h
//   side         0 front, 1 back (the colour set two-sided lighting uses)
#pragma once
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include <tbb/task_arena.h>

#include "render/context_state.h"
#include "render/depth_test.h"
#include "render/simd.h"

namespace wedge::render::raster {

// Attribute layout of a pipeline vertex.
enum : int { kFront = 0, kBack = 4, kTex = 8, kFog = 12, kEye = 13, kNormal = 17, kAttrs = 20 };

struct PVert {
  Vec4 clip;
  float a[kAttrs];
  bool edge = true;  // the edge from this vertex to the next one is an original polygon edge
};

struct WinVert {
  double x, y, z, inv_w;
  const float* a;
};

// Twice a window triangle's signed area, positive counterclockwise. Two roundings of it are in
// use, and both stay (each decides bits that the tests pin):
//   facing_area  the shoelace sum in vertex order, (x0 y1 - x1 y0) + (x1 y2 - x2 y1) + ..., GL's
//                formula for a polygon's facing (2.14.1, 3.5.1): face culling, on doubles (any
//                polygon) or on lanes of triangles (triangles.cpp's cull rows)
//   setup_area   (x1 - x0)(y2 - y0) - (x2 - x0)(y1 - y0): triangle setup, on the 1/256-pixel
//                grid (int64, exact) or on the unsnapped positions (doubles, lanes)
template <class T>
[[gnu::always_inline]] inline T facing_area(const T* x, const T* y) {
  return ((x[0] * y[1] - x[1] * y[0]) + (x[1] * y[2] - x[2] * y[1])) + (x[2] * y[0] - x[0] * y[2]);
}
inline double facing_area(const WinVert* w, std::size_t n) {
  double area = 0;
  for (std::size_t i = 0; i < n; ++i) area += w[i].x * w[(i + 1) % n].y - w[(i + 1) % n].x * w[i].y;
  return area;
}
template <class T>
[[gnu::always_inline]] inline T setup_area(const T* x, const T* y) {
  return (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
}

constexpr int kRunMax = 64;  // triangles per run of Raster::triangle_run

// --- runs of small triangles: the setup of several triangles at once ---
// Most triangles of a dense mesh cover a pixel or two. Raster::triangle_run sets up the
// triangles of a run a few at a time, one per double lane (four with AVX2, two with SSE2):
// snapping to the 1/256-pixel grid, bounding box, edge functions, the coverage of the pixel
// centres of a bounding box up to 4 x 4, and the barycentric, depth, 1/w and colour planes.
// These are Raster::triangle_q's operations lane by lane in its order (its 64-bit integer
// arithmetic done in doubles, exactly: every value stays below 2^53), so the same bits; no
// branch depends on a triangle's shape, where triangle_q branches per triangle.

struct RunSetup {
  static constexpr int kMax = kRunMax;
  enum : std::uint8_t { kNone, kTiny, kOther };  // draws nothing; small, covered; triangle() draws it
  // In: window x, y, depth (as float, then double), 1/w and the side's colour of each vertex.
  alignas(32) double x[3][kMax], y[3][kMax], z[3][kMax], iw[3][kMax], col[3][4][kMax];
  // Out: what to do, covered centres (bit 4 j + k: pixel (bx0 + k, by0 + j)), the first pixel and
  // quad, depth plane, and the float planes of 1/w and the colours (c, dx, dy each).
  std::uint8_t status[kMax];
  std::uint32_t mask[kMax];
  alignas(32) long long flip[kMax];  // (between the two passes: v1 and v2 swapped; first quad)
  alignas(32) double oxd[kMax], oyd[kMax];
  int bx0[kMax], by0[kMax], ox[kMax], oy[kMax];
  double zc[kMax], zdx[kMax], zdy[kMax];
  float pl[5][3][kMax];
};

// A set-up primitive waiting for rasterisation (binned to bands of rows, then drawn by bands in
// parallel; within a band the primitives keep their submission order, so the image is the same
// as drawing them one by one). Compact (32 bytes: the bands read each of the batch's jobs): a
// pointer to its window vertices and one to the flat attributes (owned by the queue, or by the
// chunk output of the batched triangle path, alive until the bands are drawn).
struct Job {
  enum Kind : std::uint8_t { Tri, Line, Point } kind = Tri;
  std::uint8_t side = 0;
  int row0 = 0, row1 = 0;       // rows the primitive may touch
  const WinVert* v = nullptr;   // its 3, 2 or 1 window vertices, consecutive
  const float* flat = nullptr;  // the provoking vertex's attributes for flat shading
};
// Rows per band. 64 rather than 32: fewer small triangles straddle two bands (each band then
// sets one up again) and a batch's work falls in fewer, larger band tasks; the 1M-triangle
// sphere at 2 threads took 3% less CPU and 1.58x -> 1.63x of its one-thread speed (medians of
// 6 interleaved runs), the other bench scenes within the noise.
constexpr int kBandRows = 64;

// Attribute sets copied for queued primitives, in blocks that never move (pointers stay valid
// while the store grows); clear() keeps the blocks for the next batch.
class AttrStore {
 public:
  float* add(const float* src) {
    const std::size_t b = used_ / kBlock, o = used_ % kBlock;
    if (b == blocks_.size()) blocks_.push_back(std::make_unique<float[]>(kBlock * kAttrs));
    float* d = blocks_[b].get() + o * kAttrs;
    std::memcpy(d, src, sizeof(float) * kAttrs);
    ++used_;
    return d;
  }
  void clear() { used_ = 0; }

 private:
  static constexpr std::size_t kBlock = 256;
  std::vector<std::unique_ptr<float[]>> blocks_;
  std::size_t used_ = 0;
};

// Window vertices copied for queued primitives, n (at most 3) consecutive ones at a time, in
// blocks that never move; clear() keeps the blocks.
class WinStore {
 public:
  WinVert* add(std::size_t n) {
    if (used_ + n > kBlock) ++block_, used_ = 0;
    if (block_ == blocks_.size()) blocks_.push_back(std::make_unique<WinVert[]>(kBlock));
    WinVert* d = blocks_[block_].get() + used_;
    used_ += n;
    return d;
  }
  void clear() { block_ = 0, used_ = 0; }

 private:
  static constexpr std::size_t kBlock = 768;
  std::vector<std::unique_ptr<WinVert[]>> blocks_;
  std::size_t block_ = 0, used_ = 0;
};

// Queued primitives of one stretch of a batch, in submission order, with their own binning by
// band (a counting sort), so that queues are filled and binned in parallel and the bands read
// them in queue order without a serial merge.
struct Queue {
  std::vector<Job> jobs;
  AttrStore store;
  WinStore verts;
  std::vector<std::uint32_t> band_start, band_jobs;  // jobs of band b: band_jobs[band_start[b] .. band_start[b + 1])
  void clear() { jobs.clear(), store.clear(), verts.clear(); }
  void bin(int bands) {
    band_start.assign(std::size_t(bands) + 1, 0);
    auto range = [bands](const Job& j, int& b0, int& b1) {
      if (j.row1 < 0) return false;
      b0 = std::max(0, j.row0 / kBandRows), b1 = std::min(bands - 1, j.row1 / kBandRows);
      return b0 <= b1;
    };
    int b0 = 0, b1 = 0;
    for (const Job& j : jobs)
      if (range(j, b0, b1))
        for (int b = b0; b <= b1; ++b) ++band_start[b + 1];
    for (int b = 0; b < bands; ++b) band_start[b + 1] += band_start[b];
    band_jobs.resize(band_start[bands]);
    std::vector<std::uint32_t>& cursor = cursor_;
    cursor.assign(band_start.begin(), band_start.end() - 1);
    for (std::size_t i = 0; i < jobs.size(); ++i)
      if (range(jobs[i], b0, b1))
        for (int b = b0; b <= b1; ++b) band_jobs[cursor[b]++] = std::uint32_t(i);
  }

 private:
  std::vector<std::uint32_t> cursor_;
};

struct TriChunk;  // triangles.cpp
struct ChunkOut;
// A Context's rasteriser buffers, kept between draws (fresh megabyte-sized buffers for each
// batch cost page faults), and its task arena. The draws of one Context run one at a time; the
// buffers that workers fill at once are one per worker, indexed by its slot in the arena
// (tbb::this_task_arena::current_thread_index(), below the arena's concurrency). Made by the
// Context's first draw (Raster's constructor).
struct Scratch {
  // bands.cpp: the arena of `threads` threads (made again when the count changes).
  tbb::task_arena& arena(int threads);
  // assembly.cpp (run_primitive): vertices after the vertex stage, culled triangles, the
  // queue of primitives and the queues of the parallel triangle chunks.
  std::vector<PVert> verts;
  std::vector<std::uint8_t> culled;
  Queue queue;
  std::vector<std::unique_ptr<Queue>> chunk_queues;
  // triangles.cpp (draw_triangles): each chunk's output, each worker's chunk buffers, and the
  // list of queues handed to the bands.
  std::vector<std::unique_ptr<ChunkOut>> chunk_outs;
  std::vector<std::unique_ptr<TriChunk>> chunks;
  std::vector<Queue*> queue_list;
  Scratch();
  ~Scratch();  // (triangles.cpp, where TriChunk and ChunkOut are complete)

 private:
  std::unique_ptr<tbb::task_arena> arena_;
  int arena_threads_ = 0;
};

[[gnu::always_inline]] inline Vec4f clamp01(const Vec4f& c) { return c.cwiseMax(0.0f).cwiseMin(1.0f); }

// Per-draw lighting constants (float, as GL implementations light): the enabled lights with
// their position divided by w or their unit direction, unit spot direction and cosine of the
// cutoff, so that the per-vertex work is the equation itself.
using Vec3f = Eigen::Vector3f;

struct LightSetup {
  struct L {
    Vec3f pos;    // point light: position / w; directional: unit direction
    bool local = false;  // w != 0
    float kc = 1, kl = 0, kq = 0;
    bool spot = false;   // (initialised: unused slots are copied with the setup)
    Vec3f sdir;          // unit spot direction
    float cos_cut = -1, sexp = 0;
    Vec3f amb, dif, spec;
  };
  L l[8];
  int n = 0;
  Vec3f model_ambient;
  bool local_viewer = false;
  bool color_material[2] = {false, false};
  explicit LightSetup(const Context::State& s) {
    model_ambient = s.model_ambient.head<3>();
    local_viewer = s.local_viewer;
    for (int side = 0; side < 2; ++side)
      color_material[side] = s.on(Cap::ColorMaterial) &&
                             (s.cm_face == Face::FrontAndBack || (s.cm_face == Face::Front) == (side == 0));
    for (int i = 0; i < 8; ++i) {
      if (!s.on(light_cap(i))) continue;
      const Light& src = s.lights[i];
      L& d = l[n++];
      d.local = src.position.w() != 0;
      d.pos = d.local ? Vec3f(src.position.head<3>() / src.position.w()) : Vec3f(src.position.head<3>().normalized());
      d.kc = src.constant_attenuation, d.kl = src.linear_attenuation, d.kq = src.quadratic_attenuation;
      d.spot = src.spot_cutoff != 180;
      d.sdir = src.spot_direction.normalized().cast<float>();
      d.cos_cut = float(std::cos(radians(src.spot_cutoff)));
      d.sexp = src.spot_exponent;
      d.amb = src.ambient.head<3>(), d.dif = src.diffuse.head<3>(), d.spec = src.specular.head<3>();
    }
  }
};

inline bool two_sided_lighting(const Context::State& s) { return s.on(Cap::Lighting) && s.two_side; }

// Whether the vertex stage lights the vertex colours (Phong lights per fragment instead).
inline bool vertex_lighting(const Context::State& s) { return s.on(Cap::Lighting) && s.shade != ShadeModel::Phong; }

// Which attributes the rasteriser will read (the others are left zero): texture coordinates
// when texturing, the fog distance with fog, the eye position and normal for Phong.
struct AttrNeeds {
  bool tex = true, fog = true, eye_normal = true;
  AttrNeeds() = default;
  explicit AttrNeeds(const Context::State& s)
      : tex(s.on(Cap::Texture2D) && s.texture && !s.texture->levels.empty()),
        fog(s.on(Cap::Fog)),
        eye_normal(s.on(Cap::Lighting) && s.shade == ShadeModel::Phong) {}
};

// A chunk's needed vertices as light_needed reads them: indices into the chunk, the eye
// position rows (x, y, z, w), and the chunk's first vertex in the source.
struct NeededVerts {
  const std::uint32_t* need;
  std::size_t n;
  const double* eye[4];
  std::size_t v0;
};

struct InSource {
  const InVertex* v;
  void position(std::size_t i, double& x, double& y, double& z, double& w) const {
    const Vec4& p = v[i].position;
    x = p.x(), y = p.y(), z = p.z(), w = p.w();
  }
  void positions(std::size_t i0, std::size_t n, double* x, double* y, double* z, double* w) const {
    for (std::size_t i = 0; i < n; ++i) position(i0 + i, x[i], y[i], z[i], w[i]);
  }
  const double* packed_xyz(std::size_t) const { return nullptr; }
  const InVertex& vertex(std::size_t i) const { return v[i]; }
  const Vec3& normal(std::size_t i) const { return v[i].normal; }
  const Vec4f& color(std::size_t i) const { return v[i].color; }
};

// A batch's vertices straight from client arrays (element first + i, or indices[first + i]):
// no InVertex for vertices that are never needed. As Context's fetch: missing components
// (0, 0, 0, 1), disabled arrays the current values.
struct ArraySource {
  const Context::State& s;
  const VertexArrays& a;
  const std::uint32_t* indices;
  std::size_t first;
  std::size_t at(std::size_t i) const { return indices ? indices[first + i] : first + i; }
  void position(std::size_t i, double& x, double& y, double& z, double& w) const {
    const double* p = a.positions + at(i) * a.position_size;
    x = p[0], y = p[1], z = a.position_size > 2 ? p[2] : 0.0, w = a.position_size > 3 ? p[3] : 1.0;
  }
  // The x y z of vertex i0 onward, when they lie packed in the client array (no indices, three
  // components): the position stage reads them there. Else null.
  const double* packed_xyz(std::size_t i0) const {
    return !indices && a.position_size == 3 ? a.positions + (first + i0) * 3 : nullptr;
  }
  // Positions i0 .. i0 + n - 1 into rows (those not packed_xyz).
  void positions(std::size_t i0, std::size_t n, double* x, double* y, double* z, double* w) const {
    for (std::size_t i = 0; i < n; ++i) position(i0 + i, x[i], y[i], z[i], w[i]);
  }
  Vec3 normal(std::size_t i) const {
    if (!a.normals) return s.cur_normal;
    const double* n = a.normals + at(i) * 3;
    return Vec3(n[0], n[1], n[2]);
  }
  Vec4f color(std::size_t i) const {
    if (!a.colors) return s.cur_color;
    const float* c = a.colors + at(i) * a.color_size;
    return Vec4f(c[0], c[1], c[2], a.color_size == 4 ? c[3] : 1.0f);
  }
  InVertex vertex(std::size_t i) const { return fetch_vertex(s, a, at(i)); }
};

// vertex.cpp: the vertex stage.
Vec4f light_vertex(const Context::State& s, const LightSetup& ls, const Vec4& P4, const Vec3& nd,
                   const Vec4f& vertex_color, int side);
Vec3 vertex_attrs(const Context::State& s, const InVertex& v, const Vec4& eye, const Mat3& nmat, float* a,
                  const AttrNeeds& need = AttrNeeds());
PVert process_vertex(const Context::State& s, const LightSetup& ls, const InVertex& v, const Vec4& eye,
                     const Vec4& clip, const Mat3& nmat);
template <class V> struct LightConsts;
// A draw's lighting constants for the lanes of the build that lights it (made once per batch of
// the triangle path, not per chunk: the AVX2 set is about 10 KB of broadcasts); nothing when the
// vertex stage does not light.
struct DrawLights {
  std::unique_ptr<LightConsts<F4>> narrow;
  std::unique_ptr<LightConsts<X2<F8>>> wide;
  bool use_wide = false;
  DrawLights(const Context::State& s, const LightSetup& ls, bool avx2);
  ~DrawLights();
};
// The lit colours (and, unless `lean`, vertex_attrs' other attributes) of a chunk's needed
// vertices into attrs (sets of `astride` floats), 4 or 16 at a time. Src: InSource, ArraySource.
template <class Src>
void light_needed_vertices(const DrawLights& dl, const Context::State& s, const LightSetup& ls, const Src& src,
                           const Mat3& nmat, const NeededVerts& nv, bool lean, const AttrNeeds& needs, float* attrs,
                           std::size_t astride);

// bands.cpp: threads.
struct Raster;
void draw_bands(const Raster& r, Queue* const* queues, std::size_t nq);

// triangles.cpp: the batched triangle path.
bool fast_triangles_ok(const Context::State& s);
template <class Src>
void draw_triangles(Raster& r, const Src& src, std::size_t tris);

struct Raster {
  Context::State& s;
  int width, height;
  std::uint8_t* color;
  float* depth;
  // Clip planes: 6 frustum planes then the enabled user planes (as eye-space planes).
  std::vector<Vec4> user_planes;
  int x0, y0, x1, y1;  // pixel bounds (framebuffer ∩ scissor), half open
  // The rows this Raster writes: y0 .. y1, or a band's share of them (bands.cpp). A primitive's
  // setup (its first quad, where its planes are evaluated from, and the choice of path) comes
  // from y0 .. y1 alone, so that the band drawing a row writes the bits one thread writes there.
  int band_y0, band_y1;
  // The AVX2 builds (vertex stage, run setup, fragment loops, texture sampling) for this draw:
  // the Context's Simd choice is Auto and the CPU has AVX2 (one choice for all of them).
  bool avx2 = false;
  bool phong, lighting, texturing, fog, blend, depth_test, all_mask;
  Queue* sink = nullptr;  // when set, primitives are queued instead of drawn
  Scratch* scratch;       // the Context's buffers and arena (Context::State::scratch)
  std::vector<PVert> poly_scratch, clip_scratch;
  std::vector<WinVert> win_scratch;

  LightSetup lights;

  Raster(Context::State& st, int w, int h, std::uint8_t* c, float* d);  // raster.cpp

  // clip.cpp

  // Signed distance of a vertex to clip plane i (>= 0 inside).
  double plane_dist(const PVert& v, int i) const {
    const Vec4& c = v.clip;
    switch (i) {
      case 0: return c.w() + c.x();
      case 1: return c.w() - c.x();
      case 2: return c.w() + c.y();
      case 3: return c.w() - c.y();
      case 4: return c.w() + c.z();
      case 5: return c.w() - c.z();
      default: {
        const Vec4& p = user_planes[i - 6];
        return p[0] * v.a[kEye] + p[1] * v.a[kEye + 1] + p[2] * v.a[kEye + 2] + p[3] * v.a[kEye + 3];
      }
    }
  }
  int plane_count() const { return 6 + int(user_planes.size()); }
  void clip_polygon(std::vector<PVert>& poly);
  void draw_point(const PVert& v);
  void draw_line(const PVert& a0, const PVert& b0, const PVert& provoking);

  WinVert to_window(const PVert& v) const { return to_window(v.clip, v.a); }
  WinVert to_window(const Vec4& clip, const float* a) const {
    double iw = 1.0 / clip.w();
    double nx = clip.x() * iw, ny = clip.y() * iw, nz = clip.z() * iw;
    WinVert w;
    w.x = s.vp_x + (nx + 1) * 0.5 * s.vp_w;
    w.y = s.vp_y + (ny + 1) * 0.5 * s.vp_h;
    w.z = s.depth_near + (nz + 1) * 0.5 * (s.depth_far - s.depth_near);
    w.inv_w = iw;
    w.a = a;
    return w;
  }

  // assembly.cpp
  void draw_inside_triangle(const WinVert* w, const PVert& provoking);
  void draw_triangle(const PVert& a, const PVert& b, const PVert& c, const PVert& provoking);

  // bands.cpp: primitives drawn now, or queued for the bands when `sink` is set.
  void copy_vert(WinVert& d, const WinVert& w);
  Job& new_job(Job::Kind k, int side, const float* flat);
  void emit_triangle(const WinVert& a, const WinVert& b, const WinVert& c, int side, const float* flat);
  void emit_triangle_direct(const WinVert* w, int side, const float* flat);
  void emit_line(const WinVert& a, const WinVert& b, int side, const float* flat);
  void emit_point(const WinVert& p, int side);
  void exec(const Job& j);

  // vertex.cpp: per-pixel (Phong) lighting of interpolated attributes.
  Vec4f phong_color(const float* a, int side) const;

  // The per-fragment operations after the fragment loops (here: inlined into each loop).

  static float factor(BlendFactor f, float src, float dst, float sa, float da) {
    switch (f) {
      case BlendFactor::Zero: return 0;
      case BlendFactor::One: return 1;
      case BlendFactor::SrcAlpha: return sa;
      case BlendFactor::OneMinusSrcAlpha: return 1 - sa;
      case BlendFactor::DstAlpha: return da;
      case BlendFactor::OneMinusDstAlpha: return 1 - da;
      case BlendFactor::SrcColor: return src;
      case BlendFactor::OneMinusSrcColor: return 1 - src;
      case BlendFactor::DstColor: return dst;
      case BlendFactor::OneMinusDstColor: return 1 - dst;
    }
    return 0;
  }

  // The depth test (depth_test.h) for one fragment; false if it fails. Writes the depth buffer
  // when it passes and the depth mask is on.
  [[gnu::always_inline]] bool depth_stage(int x, int y, float z) {
    return depth_test ? depth_stage_t<true>(x, y, z) : true;
  }
  template <bool Depth>
  [[gnu::always_inline]] bool depth_stage_t(int x, int y, float z) {
    return depth_stage_t<Depth>(x, y, z, s.depth_func, s.depth_mask);
  }
  // The function and mask passed in (loop-invariant locals: colour stores may alias the state).
  template <bool Depth>
  [[gnu::always_inline]] bool depth_stage_t(int x, int y, float z, DepthFunc func, bool mask) {
    if constexpr (!Depth) return true;
    float& d = depth[std::size_t(y) * width + x];
    const float zq = quantise_depth(z);
    if (!depth_pass(func, zq, d)) return false;
    if (mask) d = zq;
    return true;
  }

  // Texture environment, fog, blending, colour write (depth already tested).
  [[gnu::always_inline]] void shade_fragment(int x, int y, Vec4f c, const float* tex, float lambda, float fogz) {
    const bool t = texturing && tex;
    if (t && fog) shade_fragment_t<true, true>(x, y, c, tex, lambda, fogz);
    else if (t) shade_fragment_t<true, false>(x, y, c, tex, lambda, fogz);
    else if (fog) shade_fragment_t<false, true>(x, y, c, tex, lambda, fogz);
    else shade_fragment_t<false, false>(x, y, c, tex, lambda, fogz);
  }
  // The same, specialised on texturing and fog (chosen once per primitive, not per fragment).
  template <bool Tex, bool Fog>
  [[gnu::always_inline]] void shade_fragment_t(int x, int y, Vec4f c, const float* tex, float lambda, float fogz) {
    if constexpr (Tex) {
      float q = tex[3] != 0 ? tex[3] : 1.0f;
      Vec4f t = s.texture->sample(tex[0] / q, tex[1] / q, lambda);
      const TexFormat fmt = s.texture->format;
      switch (s.env_mode) {
        case TexEnvMode::Modulate:
          c.head<3>() = c.head<3>().cwiseProduct(t.head<3>());
          if (fmt == TexFormat::RGBA) c.w() *= t.w();
          break;
        case TexEnvMode::Replace:
          c.head<3>() = t.head<3>();
          if (fmt == TexFormat::RGBA) c.w() = t.w();
          break;
        case TexEnvMode::Decal:
          if (fmt == TexFormat::RGBA) c.head<3>() = c.head<3>() * (1 - t.w()) + t.head<3>() * t.w();
          else if (fmt == TexFormat::RGB) c.head<3>() = t.head<3>();
          break;
        case TexEnvMode::Blend:
          for (int k = 0; k < 3; ++k) c[k] = c[k] * (1 - t[k]) + s.env_color[k] * t[k];
          if (fmt == TexFormat::RGBA) c.w() *= t.w();
          break;
      }
    }
    if constexpr (Fog) {
      float f = 1;
      switch (s.fog_mode) {
        case FogMode::Linear: f = s.fog_end == s.fog_start ? 1.0f : (s.fog_end - fogz) / (s.fog_end - s.fog_start); break;
        case FogMode::Exp: f = std::exp(-s.fog_density * fogz); break;
        case FogMode::Exp2: f = std::exp(-(s.fog_density * fogz) * (s.fog_density * fogz)); break;
      }
      f = std::clamp(f, 0.0f, 1.0f);
      c.head<3>() = f * c.head<3>() + (1 - f) * s.fog_color.head<3>();
    }
    write_color(x, y, clamp01(c));
  }

  // Blending and the colour mask, then the colour write of one fragment (c already clamped).
  [[gnu::always_inline]] void write_color(int x, int y, Vec4f c) {
    std::uint8_t* p = &color[(std::size_t(y) * width + x) * 4];
    if (blend) {
      Vec4f d(p[0] / 255.0f, p[1] / 255.0f, p[2] / 255.0f, p[3] / 255.0f);
      Vec4f r;
      for (int k = 0; k < 4; ++k)
        r[k] = c[k] * factor(s.blend_src, c[k], d[k], c.w(), d.w()) + d[k] * factor(s.blend_dst, c[k], d[k], c.w(), d.w());
      c = clamp01(r);
    }
    // c is clamped to [0, 1]: round to nearest without a library call.
    if (all_mask) {
#if defined(__SSE2__)
      // The same float multiply, add and truncation for the four channels at once (SSE2).
      const __m128 f = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(c.data()), _mm_set1_ps(255.0f)), _mm_set1_ps(0.5f));
      const __m128i i32 = _mm_cvttps_epi32(f);
      const __m128i i16 = _mm_packs_epi32(i32, i32);
      const int packed = _mm_cvtsi128_si32(_mm_packus_epi16(i16, i16));
      std::memcpy(p, &packed, 4);
#else
      for (int k = 0; k < 4; ++k) p[k] = std::uint8_t(c[k] * 255.0f + 0.5f);
#endif
    } else {
      for (int k = 0; k < 4; ++k)
        if (s.color_mask[k]) p[k] = std::uint8_t(c[k] * 255.0f + 0.5f);
    }
  }

  // --- triangles ---
  // The attributes whose colour a triangle is filled with: the provoking vertex's (flat, when
  // given), else v0's when the three vertices have the same colour (an unlit or uniformly lit
  // surface: no colour interpolation), else none (smooth).
  static const float* flat_colour(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat) {
    if (flat) return flat;
    const int col = side ? kBack : kFront;
    if (std::memcmp(v0.a + col, v1.a + col, 4 * sizeof(float)) == 0 &&
        std::memcmp(v0.a + col, v2.a + col, 4 * sizeof(float)) == 0)
      return v0.a;
    return nullptr;
  }

  // The fragment loop is specialised on the state that changes its work per fragment (Phong,
  // smooth colour, texturing, fog, depth test), chosen once per triangle: no per-pixel branch

  // fragments.cpp: triangles.
  void triangle(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat);
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  void triangle_scalar(const WinVert& v0, const WinVert& v1in, const WinVert& v2in, int side, const float* flat);
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  void triangle_t(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat);
#if defined(__SSE2__)
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  void triangle_isa(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat);
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  __attribute__((target("avx2"))) void triangle_t_avx2(const WinVert& v0, const WinVert& v1, const WinVert& v2, int side, const float* flat);
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth, bool Avx2>
  void triangle_q(const WinVert& v0, const WinVert& v1in, const WinVert& v2in, int side, const float* flat);

  // --- the quad fragment loop (quad_loop.cpp) ---
  // A triangle after triangle_q's setup, as the quad loop takes it: the first quad (ox, oy), the
  // pixel bounds (rows by0 .. by1: those of the box in the band), the edge functions e_i = A_i (x - ox) + B_i (y - oy) + c_i, the float planes of
  // 1/w and a/w (colours, texture s t q, fog distance; all kAttrs attributes for Phong), the
  // depth plane in double, and the state the loop reads.
  struct QuadSetup {
    int ox, oy, bx0, bx1, by0, by1, col, side;
    std::int64_t c[3], A[3], B[3];
    QPlane pw, pc[4], pt[3], pf, pa[kAttrs];
    bool tex_q, dmask, fast_write;  // q not 1 at some vertex; depth mask; no blending, all channels
    double zc, zdx, zdy;
    const Texture* texture;
    float tex_w, tex_h, fog_end, fog_range, fog_density;
    FogMode fog_mode;
    TexEnvMode env;
    TexFormat fmt;
    const float* flat;
    DepthFunc dfunc;
  };
  // The loop on lanes V (F4 or F8), and its two builds: 4 lanes (the default target: every
  // state) and 8 lanes (AVX2: every state but Phong, which triangle_isa sends to the 4 lanes).
  template <class V, bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  [[gnu::always_inline]] inline void quad_loop(const QuadSetup& q);
  template <bool Phong, bool Smooth, bool Tex, bool Fog, bool Depth>
  void quad_loop4(const QuadSetup& q);
  template <bool Smooth, bool Tex, bool Fog, bool Depth>
  __attribute__((target("avx2"))) void quad_loop8(const QuadSetup& q);

  // One covered pixel of a small triangle in the common state (triangle_q's tiny path and
  // triangle_run): depth from its double plane, colour from the float planes pl (c, dx, dy of 1/w
  // and of r/w, g/w, b/w, a/w) at (X, Y) from the first quad's first pixel, or the flat colour.
  // The quad loops' operations per lane, in the same order (the same bits).
  template <bool Smooth, bool Depth>
  [[gnu::always_inline]] void tiny_pixel(int px, int py, float X, float Y, double zc, double zdx, double zdy,
                                         const float (*pl)[3], const float* flat_rgba, DepthFunc dfunc, bool dmask) {
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
    auto clamp01 = [&](float x) { return _mm_cvtss_f32(_mm_min_ss(_mm_max_ss(_mm_set_ss(x), zero), one)); };
    auto at = [&](int k) { return (pl[k][0] + Y * pl[k][2]) + X * pl[k][1]; };
    const std::size_t idx = std::size_t(py) * width + px;
    if constexpr (Depth) {
      const float zq = quantise_depth(float((zc + double(Y) * zdy) + double(X) * zdx));
      const float d = depth[idx];
      if (!depth_pass(dfunc, zq, d)) return;
      if (dmask) depth[idx] = zq;
    }
    float cr, cg, cb, ca;
    if constexpr (Smooth) {
      const float rw = 1.0f / at(0);
      cr = at(1) * rw, cg = at(2) * rw, cb = at(3) * rw, ca = at(4) * rw;
    } else {
      cr = flat_rgba[0], cg = flat_rgba[1], cb = flat_rgba[2], ca = flat_rgba[3];
    }
    auto q8 = [&](float x) { return std::uint32_t(int(clamp01(x) * 255.0f + 0.5f)); };
    const std::uint32_t pix = q8(cr) | q8(cg) << 8 | q8(cb) << 16 | q8(ca) << 24;
    std::memcpy(color + idx * 4, &pix, 4);
  }
#endif

  // triangle_run.cpp

  // A run of independent filled triangles (v: three window vertices each), drawn in order as
  // triangle() draws them one by one: in the common state (no Phong, texture or fog; no blending,
  // all channels written) the run is set up a few triangles at a time (run_setup), the small
  // covered ones are drawn here pixel by pixel, the others by triangle().
  struct RunTri {
    const WinVert* v;
    int side;
    const float* flat;
  };
  void triangle_run(const RunTri* tri, std::size_t n, RunSetup& rs);
#if defined(__SSE2__)
  void small_run(const RunTri* tri, int m, RunSetup& rs);
#endif

  // lines.cpp
  void line(const WinVert& a_in, const WinVert& b_in, int side, const float* flat);
  void point(const WinVert& p_in, int side);
};

}  // namespace wedge::render::raster
